"""The jump map as a result: arrays over (speed, spring rate), and its CSV (the public column contract: columns are
only ever added, at the end).

CSV columns: ``speed_rpm``; ``spring_rate_N_per_mm`` (for an oscillating follower it holds the torsion rate in
N*m/rad: deprecated there, kept for the scripts that read it; use ``spring_rate_N_m_per_rad``);
``min_contact_force_N``; ``separated`` (0/1: the interface force of the in-contact model reaches 0);
``max_gap_mm`` (the largest overshoot of the follower beyond the cam profile; 0 where it stays on the cam, and
also where contact is lost in the follower train alone, the follower never passing the profile);
``spring_rate_N_m_per_rad`` (the torsion rate of an oscillating follower; empty for a translating one);
``status`` (``ok``, or ``failed: <reason>`` for a point whose computation failed: its ``min_contact_force_N``,
``separated`` and ``max_gap_mm`` are ``nan``); ``bounced``, ``seating_velocity_m_per_s``, ``bounce_height_mm``
(a valvetrain's map: the valve leaves its seat after closing, 0/1, its landing speed and re-lift; empty for a
single follower). On a valvetrain's map ``spring_rate_N_per_mm`` is the valve spring's at the valve,
``min_contact_force_N`` the cam contact's over the valve event, ``separated`` float and ``max_gap_mm`` the valve's
largest lift above where the cam would hold it (at the valve; the seat bounds it, and with a ``[spring]`` part its
coil bind); ``coil_bind_clearance_mm`` (a valvetrain's map with a ``[spring]`` part: the valve's lift to spare
before the case's spring goes solid, negative where the flight would reach solid; empty otherwise).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field

import numpy as np

from ..._core.kinds import FollowerKind

CSV_COLUMNS = (
    "speed_rpm",
    "spring_rate_N_per_mm",
    "min_contact_force_N",
    "separated",
    "max_gap_mm",
    "spring_rate_N_m_per_rad",
    "status",
    "bounced",
    "seating_velocity_m_per_s",
    "bounce_height_mm",
    "coil_bind_clearance_mm",
)
STATUS_OK = "ok"


def failed(reason: str) -> str:
    """The status of a point whose computation failed, on one line."""
    return "failed: " + " ".join(str(reason).split())


def _quoted(text: str) -> str:
    """``text`` as one CSV field (quoted where it holds a comma or a quote)."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="").writerow([text])
    return buf.getvalue()


@dataclass(frozen=True)
class ValveMap:
    """A valvetrain's map beyond float (``JumpMap.separated``): arrays of shape (speeds, spring rates)."""

    bounced: np.ndarray  # bool: the valve leaves its seat after closing by more than the micro-bounce tolerance
    seating_velocity: np.ndarray  # m/s; NaN where the valve never lifts or the point failed
    bounce_height: np.ndarray  # mm
    coil_bind_clearance: np.ndarray | None = None  # mm to spare before the spring is solid; None: no [spring] part


def first_speeds(speeds_rpm: np.ndarray, hit: np.ndarray) -> np.ndarray:
    """The first speed of each spring rate's column where ``hit`` (rpm; NaN where none on the grid)."""
    any_ = hit.any(axis=0)
    return np.where(any_, speeds_rpm[np.argmax(hit, axis=0)], np.nan)


@dataclass(frozen=True)
class JumpMap:
    """A jump map: arrays of shape (len(speeds_rpm), len(spring_rates)), forces in N and gaps in mm."""

    case: str
    model: str  # "compliant" | "rigid"
    kind: FollowerKind
    speeds_rpm: np.ndarray  # (ns,)
    spring_rates: np.ndarray  # (nk,) N/mm; N*m/rad for an oscillating follower
    min_force: np.ndarray  # least interface force, N; 0 where the follower separates; NaN where the point failed
    separated: np.ndarray  # bool: the in-contact model's least force <= 0
    max_gap: np.ndarray  # largest gap, mm; 0 where it stays on the cam; NaN where the point failed (or gaps=False)
    contact_force: (
        np.ndarray
    )  # signed least force of the in-contact model (linear steady state / kinematic), N: <= 0 beyond the jump boundary
    speed_rpm: float  # the case's operating point
    spring_rate: float
    preload: float  # kept fixed over the map: N (N*m for an oscillating follower)
    devices: int = 1
    notes: tuple[str, ...] = field(default=())
    status: np.ndarray | None = None  # str per point: "ok" or "failed: <reason>"; None: every point ok
    valve: ValveMap | None = None  # a valvetrain's map: bounce and seating beside float

    @property
    def oscillating(self) -> bool:
        return self.kind.rotary

    @property
    def spring_rate_unit(self) -> str:
        return self.kind.rate_unit

    @property
    def preload_unit(self) -> str:
        return self.kind.force_unit

    @property
    def statuses(self) -> np.ndarray:
        """The status of every point (ns, nk): ``ok`` or ``failed: <reason>``."""
        return np.full(self.separated.shape, STATUS_OK, dtype=object) if self.status is None else self.status

    @property
    def failed(self) -> np.ndarray:
        """Where the computation failed (bool, (ns, nk))."""
        return self.statuses != STATUS_OK

    @property
    def csv(self) -> str:
        """CSV text: one row per grid point (speed-major), columns :data:`CSV_COLUMNS`."""
        sp, kr = np.meshgrid(self.speeds_rpm, self.spring_rates, indexing="ij")
        status = self.statuses.ravel()
        quoted = {s: _quoted(s) for s in set(status.tolist())}
        rows = zip(
            sp.ravel().tolist(),
            kr.ravel().tolist(),
            self.min_force.ravel().tolist(),
            self.separated.ravel().tolist(),
            self.max_gap.ravel().tolist(),
            status.tolist(),
            *(
                (np.zeros(sp.size, int).tolist(),) * 3 + ([None] * sp.size,)
                if self.valve is None
                else (
                    self.valve.bounced.ravel().tolist(),
                    self.valve.seating_velocity.ravel().tolist(),
                    self.valve.bounce_height.ravel().tolist(),
                    [None] * sp.size
                    if self.valve.coil_bind_clearance is None
                    else self.valve.coil_bind_clearance.ravel().tolist(),
                )
            ),
            strict=True,
        )
        buf = io.StringIO()
        buf.write(",".join(CSV_COLUMNS) + "\n")
        for speed, rate, force, sep, gap, st, bounce, seat_v, height, coil in rows:
            ok = st == STATUS_OK
            sep_text = f"{sep:d}" if ok else "nan"
            torsion = f"{rate:.10g}" if self.kind.rotary else ""
            if self.valve is None:
                valve = ",,,"
            else:
                valve = f"{bounce:d}," if ok else "nan,"
                valve += f"{seat_v:.10g},{height:.10g}," + ("" if coil is None else f"{coil:.10g}")
            buf.write(f"{speed:.10g},{rate:.10g},{force:.10g},{sep_text},{gap:.10g},{torsion},{quoted[st]},{valve}\n")
        return buf.getvalue()
