"""What a steady-state response is: the follower over one revolution, its contact force and its separations."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..motion import Motion


@dataclass(frozen=True)
class Separation:
    """One flight from lift-off to the touchdown that ends the bouncing (angles deg in [0, 360)).

    Gaps and speeds are in the motion's units: mm and m/s for a translating follower, rad and rad/s of arm
    swing for an oscillating one (camdyn.design.checks turns those into mm and m/s at the contact).
    ``settled`` is False where the follower never returns to steady contact (it keeps bouncing, or is not back
    on the cam two revolutions after lift-off): the flight then runs to ``end_deg`` and no further.
    """

    start_deg: float
    end_deg: float
    max_gap: float  # motion units (mm or rad)
    impact_speed: float  # relative speed at the first touchdown, m/s (or rad/s)
    bounces: int = 0
    max_gap_deg: float = float("nan")  # where the largest gap is
    impact_deg: float = float("nan")  # where the first touchdown is
    settled: bool = True


@dataclass(frozen=True)
class Flight:
    """One span of cam angle where the interface force is zero: from where the follower leaves the cam
    (``leave_deg``, the first grid angle with zero force) to where it is last off it (``land_deg``, the last one;
    deg in [0, 360), a flight may wrap through 0). ``max_gap`` in the motion's units (mm or rad)."""

    leave_deg: float
    land_deg: float
    max_gap: float
    max_gap_deg: float

    @property
    def span_deg(self) -> float:
        """The flight's length in cam degrees."""
        return (self.land_deg - self.leave_deg) % 360.0


@dataclass(frozen=True)
class Impact:
    """A landing: the contact that begins at ``deg`` after a flight, and its largest force (``peak_force``, N or
    N*m as the response holds its forces, at ``peak_deg``) within half a contact-mode period of the landing (the
    length of a bounce's force pulse; later, the cam drives the force).

    A rigid follower lands with an impulse: its ``peak_force`` is NaN (the impact speed is its separation's)."""

    deg: float
    peak_force: float
    peak_deg: float


@dataclass(frozen=True)
class Response:
    """Periodic steady-state response over one revolution at cam speed ``omega`` (rad/s)."""

    model: str  # "rigid" | "compliant"
    omega: float
    theta_deg: np.ndarray
    s: np.ndarray  # kinematic displacement, motion units
    x: np.ndarray  # follower displacement, motion units
    dx: np.ndarray  # dx/dtheta, motion units per rad
    force: np.ndarray  # interface force, N (or N*m)
    kinematic_force: np.ndarray
    separations: tuple[Separation, ...]
    residual_vibration: float  # largest |x - x_static| in the dwells (static equilibrium), motion units
    periodicity_error: float  # |Phi(y0) - y0| of the shooting over its period (1 or 2 revolutions), motion units
    warnings: tuple[str, ...] = field(default=())
    residual_vibration_deg: float = float("nan")  # where the residual vibration peaks
    contact_period_deg: float = float("nan")  # the contact mode's period in cam degrees (compliant; an impact's span)
    domain: str = "time"  # where the steady state was solved: "time", or "frequency" (a slow compliant cam)
    # the revolutions after which the steady state repeats within the periodic tolerance: 1, 2 (a bouncing of period
    # two), None (a compliant bouncing that is not periodic: this is its least-mismatch revolution)
    period_revolutions: int | None = 1

    @property
    def flights(self) -> tuple[Flight, ...]:
        """The spans where the interface force is zero, each one flight (a separation with bounces holds several)."""
        return tuple(Flight(*f) for f in _zero_runs(self.theta_deg, self.force, self.x - self.s))

    @property
    def impacts(self) -> tuple[Impact, ...]:
        """Every landing after a flight, with its peak force (a compliant follower; NaN for a rigid one)."""
        out = []
        n = len(self.theta_deg)
        step = 360.0 / n
        window = max(1, round(0.5 * self.contact_period_deg / step)) if math.isfinite(self.contact_period_deg) else 0
        flights = self.flights
        if len(flights) == 1 and flights[0].span_deg >= 360.0 - 1.5 * step:
            return ()  # never back on the cam
        for fl in flights:
            first = (int(round(fl.land_deg / step)) + 1) % n  # the first grid angle in contact again
            if self.model == "rigid" or window == 0:
                out.append(Impact(float(self.theta_deg[first]), math.nan, math.nan))
                continue
            idx = (first + np.arange(window)) % n
            idx = idx[: int(np.argmin(self.force[idx] > 0.0)) or window]  # up to the next flight, if sooner
            top = idx[int(np.argmax(self.force[idx]))]
            out.append(Impact(float(self.theta_deg[first]), float(self.force[top]), float(self.theta_deg[top])))
        return tuple(out)

    @property
    def max_impact_force(self) -> float:
        """The largest impact force (N or N*m); 0 without impacts, NaN for a rigid follower's impulses."""
        peaks = [i.peak_force for i in self.impacts]
        return max(peaks) if peaks else 0.0

    @property
    def settled(self) -> bool:
        """Whether the follower is back in steady contact after every separation."""
        return all(s.settled for s in self.separations)

    @property
    def min_force(self) -> float:
        return float(np.min(self.force))

    @property
    def min_force_deg(self) -> float:
        """Where the force is least; where the follower separates (the force is 0 over whole flights), where it
        leaves the cam on its highest flight."""
        if self.separations:
            return max(self.separations, key=lambda s: s.max_gap).start_deg
        return float(self.theta_deg[int(np.argmin(self.force))])


def residual_vibration(motion: Motion, theta_deg: np.ndarray, deviation: np.ndarray) -> tuple[float, float]:
    """The largest |deviation from static equilibrium| in the dwells (motion units) and its angle (deg);
    (0, NaN) for a motion without dwells."""
    dwell = _dwell_mask(motion, theta_deg)
    if not dwell.any():
        return 0.0, float("nan")
    dev = np.where(dwell, np.abs(deviation), -1.0)
    i = int(np.argmax(dev))
    return float(dev[i]), float(theta_deg[i])


def _dwell_mask(motion: Motion, theta_deg: np.ndarray) -> np.ndarray:
    mask = np.zeros(theta_deg.shape, bool)
    for start, end in motion.dwells_deg:
        mask |= (theta_deg >= start) & (theta_deg < end)
    return mask


def _zero_runs(theta_deg, force, gap) -> list[tuple[float, float, float, float]]:
    """(first angle, last angle, largest gap, its angle) of every periodic run of grid angles where force <= 0."""
    flying = np.asarray(force) <= 0.0
    n = len(theta_deg)
    if not flying.any():
        return []
    if flying.all():
        i = int(np.argmax(gap))
        return [(float(theta_deg[0]), float(theta_deg[-1]), float(gap[i]), float(theta_deg[i]))]
    shift = int(np.argmin(flying))  # a contact angle: no run wraps the scan's end
    idx = (np.arange(n) + shift) % n
    f = flying[idx].astype(np.int8)
    starts = np.flatnonzero(np.diff(np.concatenate([[0], f])) == 1)
    ends = np.flatnonzero(np.diff(np.concatenate([f, [0]])) == -1)
    out = []
    for a, b in zip(starts, ends, strict=True):
        sel = idx[a : b + 1]
        top = sel[int(np.argmax(gap[sel]))]
        out.append((float(theta_deg[sel[0]]), float(theta_deg[sel[-1]]), float(gap[top]), float(theta_deg[top])))
    return sorted(out)


def separations_from_mask(
    theta_deg: np.ndarray, flying: np.ndarray, gap: np.ndarray, rel_speed: np.ndarray, merge_deg: float
) -> list[Separation]:
    """Flights from a boolean mask on a periodic grid; flights split by contact shorter than merge_deg merge."""
    n = len(theta_deg)
    if not flying.any():
        return []
    if flying.all():  # far beyond the jump speed: no steady contact at all
        i = int(np.argmax(gap))
        return [Separation(0.0, 0.0, float(gap[i]), 0.0, 0, float(theta_deg[i]), float("nan"), settled=False)]
    step = 360.0 / n
    shift = int(np.argmin(flying))  # start the scan in contact so no flight wraps the grid end
    idx = (np.arange(n) + shift) % n
    runs, start = [], None
    for j, i in enumerate(idx):
        if flying[i] and start is None:
            start = j
        if not flying[i] and start is not None:
            runs.append([start, j])
            start = None
    if start is not None:
        runs.append([start, n])
    merged = [runs[0] + [0]]
    for r in runs[1:]:
        if (r[0] - merged[-1][1]) * step < merge_deg:
            merged[-1][1] = r[1]
            merged[-1][2] += 1
        else:
            merged.append(r + [0])
    out = []
    for a, b, bounces in merged:
        sel = idx[a:b]
        first_touch = idx[min(b, n - 1)] if b < n else idx[0]
        top = sel[int(np.argmax(gap[sel]))]
        out.append(
            Separation(
                start_deg=float(theta_deg[idx[a]]),
                end_deg=float(theta_deg[idx[b % n]]) if b < n else float(theta_deg[idx[0]]),
                max_gap=float(gap[top]),
                impact_speed=float(abs(rel_speed[first_touch])),
                bounces=bounces,
                max_gap_deg=float(theta_deg[top]),
                impact_deg=float(theta_deg[first_touch]),
            )
        )
    return out
