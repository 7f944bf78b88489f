"""What a steady-state response is: the follower over one revolution, its contact force and its separations."""

from __future__ import annotations

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
    periodicity_error: float  # |Phi(y0) - y0| of the shooting, motion units
    warnings: tuple[str, ...] = field(default=())
    residual_vibration_deg: float = float("nan")  # where the residual vibration peaks

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
    segs = getattr(motion, "segments", ())
    mask = np.zeros(theta_deg.shape, bool)
    for seg in segs:
        if seg.law == "dwell":
            mask |= (theta_deg >= seg.start) & (theta_deg < seg.end)
    return mask


def _separations_from_mask(theta_deg, flying, gap, rel_speed, merge_deg) -> list[Separation]:
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
