"""A tolerance study's result and its CSV (the public column contract: columns are only ever added, at the end).

CSV columns (translating follower; an oscillating arm's rate, preload, inertia and profile columns are named in
its units: ``spring_rate_N_m_per_rad``, ``preload_N_m``, ``mass_kg_m2``, ``train_stiffness_N_m_per_rad``,
``profile_error_rms_rad``): ``sample`` (index, 0-based); ``spring_rate_N_per_mm``; ``preload_N``; ``mass_kg``;
``train_stiffness_N_per_mm`` (inf for a rigid follower); ``speed_rpm``; ``profile_error_rms_mm`` (the sample's
lift error RMS); ``least_contact_force_N`` (signed least force of the in-contact model at the sample's speed:
<= 0 where it separates); ``jump_speed_rpm`` (inf where none up to the search limit); ``separated`` (0/1).
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..._core.kinds import TRANSLATING, FollowerKind
from ._interval import CONFIDENCE

PARAM_KEYS = ("spring_rate", "preload", "mass", "train_stiffness", "speed", "profile_error")


def csv_columns(kind: FollowerKind) -> tuple[str, ...]:
    """The CSV's columns for a translating follower or an oscillating arm."""
    names = [f"{k}_rms" if k == "profile_error" else k for k in PARAM_KEYS]
    units = (kind.rate_suffix, kind.force_suffix, kind.mass_suffix, kind.rate_suffix, "rpm", kind.motion_unit)
    return (
        "sample",
        *(f"{n}_{u}" for n, u in zip(names, units, strict=True)),
        "least_contact_force_N",
        "jump_speed_rpm",
        "separated",
    )


CSV_COLUMNS = csv_columns(TRANSLATING)


@dataclass(frozen=True)
class ToleranceResult:
    """A Monte Carlo tolerance study: per sample its parameters (case-file units), least force and jump speed."""

    case: str
    kind: FollowerKind
    seed: int
    speed_rpm: float  # the case's
    params: dict[str, np.ndarray]  # PARAM_KEYS -> (n,) (profile_error: the RMS of each sample's lift error)
    least_force: np.ndarray  # (n,) N, signed
    jump_speed_rpm: np.ndarray  # (n,) inf where none
    tolerances: dict[str, dict]  # key -> {"tolerance", "unit", "relative", "distribution", "sigma"}
    probability: float
    confidence_interval: tuple[float, float]
    confidence: ClassVar[float] = CONFIDENCE  # of the interval
    sensitivities: dict[str, dict] = field(
        default_factory=dict
    )  # key -> {"gradient_sigma", "share_linear", "share_monte_carlo"}
    nominal_jump_speed_rpm: float = float("nan")
    worst: tuple[int, ...] = ()
    devices: int = 1
    processes: int = 1

    @property
    def samples(self) -> int:
        return self.least_force.size

    @property
    def separated(self) -> np.ndarray:
        return self.least_force <= 0.0

    def percentiles(self, values: np.ndarray) -> dict[str, float]:
        """P1, P5, P50 (the sample values, no interpolation: an infinite jump speed stays infinite)."""
        q = np.percentile(values, [1, 5, 50], method="inverted_cdf")
        return {"p1": float(q[0]), "p5": float(q[1]), "p50": float(q[2])}

    @property
    def csv(self) -> str:
        """CSV text, one row per sample, columns :func:`csv_columns`."""
        buf = io.StringIO()
        buf.write(",".join(csv_columns(self.kind)) + "\n")
        cols = [self.params[k].tolist() for k in PARAM_KEYS]
        for i, row in enumerate(zip(*cols, self.least_force.tolist(), self.jump_speed_rpm.tolist(), strict=True)):
            buf.write(f"{i:d}," + ",".join(f"{v:.10g}" for v in row) + f",{row[-2] <= 0.0:d}\n")
        return buf.getvalue()
