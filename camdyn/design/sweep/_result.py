"""The jump map as a result: arrays over (speed, spring rate), and its CSV (the public column contract)."""

from __future__ import annotations

import io
from dataclasses import dataclass, field

import numpy as np

CSV_COLUMNS = ("speed_rpm", "spring_rate_N_per_mm", "min_contact_force_N", "separated", "max_gap_mm")


@dataclass(frozen=True)
class JumpMap:
    """A jump map: arrays of shape (len(speeds_rpm), len(spring_rates)), forces in N and gaps in mm."""

    case: str
    model: str  # "compliant" | "rigid"
    oscillating: bool
    speeds_rpm: np.ndarray  # (ns,)
    spring_rates: np.ndarray  # (nk,) N/mm; N*m/rad for an oscillating follower
    min_force: np.ndarray  # least interface force, N; 0 where the follower separates
    separated: np.ndarray  # bool
    max_gap: np.ndarray  # largest gap, mm; 0 where it stays on the cam, NaN where the integration failed
    contact_force: np.ndarray  # signed least force of the in-contact model (linear steady state / kinematic), N: <= 0 beyond the jump boundary
    speed_rpm: float  # the case's operating point
    spring_rate: float
    preload: float  # kept fixed over the map: N (N*m for an oscillating follower)
    devices: int = 1
    notes: tuple[str, ...] = field(default=())

    @property
    def spring_rate_unit(self) -> str:
        return "N*m/rad" if self.oscillating else "N/mm"

    @property
    def preload_unit(self) -> str:
        return "N*m" if self.oscillating else "N"

    @property
    def csv(self) -> str:
        """CSV text: one row per grid point (speed-major), columns :data:`CSV_COLUMNS`."""
        sp, kr = np.meshgrid(self.speeds_rpm, self.spring_rates, indexing="ij")
        data = np.column_stack([sp.ravel(), kr.ravel(), self.min_force.ravel(), self.separated.ravel().astype(float), self.max_gap.ravel()])
        buf = io.StringIO()
        buf.write(",".join(CSV_COLUMNS) + "\n")
        np.savetxt(buf, data, delimiter=",", fmt=["%.10g", "%.10g", "%.10g", "%d", "%.10g"])
        return buf.getvalue()
