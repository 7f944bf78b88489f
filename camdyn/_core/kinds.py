"""Follower kinds: what differs between a translating follower and an oscillating arm, in one object each.

A :class:`FollowerKind` owns the units of the follower's coordinate (the case file's lift unit and the model's
motion unit), the conversions between them and to SI, the units and JSON/CSV unit suffixes of its rate, force
and mass, and whether its forces are torques about a pivot (turned into contact forces through the lever arm).
A :class:`FollowerType` is a kind and a contact (roller or flat face): the ``[follower] type`` of a case file.
Code reads these attributes instead of testing type-name strings or ``if oscillating``; a new follower is one
new object here. Plain Python: the schema imports this module, and it must not pull in JAX.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .units import DEFAULT_MAX_PRESSURE_ANGLE_DEG, M_PER_MM, N_PER_M_PER_N_PER_MM


@dataclass(frozen=True)
class FollowerKind:
    """A follower's kind of motion and everything that follows from it.

    The model's motion is in ``motion_unit`` per cam angle (mm, or rad of arm swing); the case file and the
    outputs give lift in ``lift_unit`` (mm, or deg of swing). Derivatives per rad of cam angle convert with
    the same factor as the lift.
    """

    name: str  # "translating" | "oscillating"
    article: str  # "a" | "an": "a translating follower", "an oscillating follower"
    rotary: bool  # the coordinate is the arm angle: forces are torques about the pivot, rates torsion rates
    motion_unit: str  # the model's unit of the follower coordinate: "mm" | "rad"
    lift_unit: str  # the case file's and the outputs' unit of lift: "mm" | "deg"
    lift_word: str  # what the lift is called in a figure: "lift" | "swing"
    lift_symbol: str  # its symbol there: "s" | psi
    lift_column: str  # the lift column of a case's lift table: "lift_mm" | "swing_deg"
    lift_per_motion: float  # motion unit -> lift unit (1, or 180/pi)
    motion_per_lift: float  # lift unit -> motion unit (1, or pi/180)
    si_per_motion: float  # motion unit -> SI (mm -> m; rad stays rad)
    rate_unit: str  # a spring or train rate in the case file: "N/mm" | "N*m/rad"
    si_per_rate: float  # that rate -> SI (N/mm -> N/m; N*m/rad stays)
    force_unit: str  # the generalized force: "N" | "N*m"
    force_word: str  # "force" | "torque"
    rate_name: str  # "spring rate" | "torsion rate"
    preload_symbol: str  # "F0" | "T0"
    mass_unit: str  # the generalized mass: "kg" | "kg*m^2"
    damping_unit: str  # a viscous damping coefficient: "N*s/m" | "N*m*s/rad"
    rate_slip_unit: str  # the unit a rate 1000 times too large was likely meant in: "N/m" | "N*mm/rad"
    table_columns: tuple[str, str, str, str]  # camdyn table's motion columns: lift (lift unit), its derivatives
    dynamic_column: str  # camdyn table's column of the dynamic follower position (lift unit)
    rate_suffix: str  # a rate's unit in a JSON key or CSV column: "N_per_mm" | "N_m_per_rad"
    force_suffix: str  # a generalized force's unit there: "N" | "N_m"
    mass_suffix: str  # a generalized mass's unit there: "kg" | "kg_m2"
    default_max_pressure_angle_deg: float  # the pressure-angle limit when [limits] gives none

    def __str__(self) -> str:
        return self.name

    @property
    def a(self) -> str:
        """``"a translating"`` / ``"an oscillating"``: for messages."""
        return f"{self.article} {self.name}"

    def lift_to_motion(self, x):
        """Lift (or a derivative per rad of cam angle) in the lift unit -> the motion unit (floats or arrays)."""
        return x * self.motion_per_lift

    def motion_to_lift(self, x):
        """The inverse of :meth:`lift_to_motion`: motion unit -> lift unit (mm stays mm; rad -> deg)."""
        return x * self.lift_per_motion

    def rate_to_si(self, rate):
        """A spring or train rate as the case file gives it (``rate_unit``) in SI (N/m, or N*m/rad)."""
        return rate * self.si_per_rate

    def rate_from_si(self, rate):
        """The inverse of :meth:`rate_to_si`."""
        return rate / self.si_per_rate


TRANSLATING = FollowerKind(
    name="translating",
    article="a",
    rotary=False,
    motion_unit="mm",
    lift_unit="mm",
    lift_word="lift",
    lift_symbol="s",
    lift_column="lift_mm",
    lift_per_motion=1.0,
    motion_per_lift=1.0,
    si_per_motion=M_PER_MM,
    rate_unit="N/mm",
    si_per_rate=N_PER_M_PER_N_PER_MM,
    force_unit="N",
    force_word="force",
    rate_name="spring rate",
    preload_symbol="F0",
    mass_unit="kg",
    damping_unit="N*s/m",
    rate_slip_unit="N/m",
    table_columns=("s_mm", "v_mm_per_rad", "a_mm_per_rad2", "j_mm_per_rad3"),
    dynamic_column="dynamic_x_mm",
    rate_suffix="N_per_mm",
    force_suffix="N",
    mass_suffix="kg",
    default_max_pressure_angle_deg=DEFAULT_MAX_PRESSURE_ANGLE_DEG["translating"],
)
OSCILLATING = FollowerKind(
    name="oscillating",
    article="an",
    rotary=True,
    motion_unit="rad",
    lift_unit="deg",
    lift_word="swing",
    lift_symbol="\u03c8",
    lift_column="swing_deg",
    lift_per_motion=180.0 / math.pi,
    motion_per_lift=math.pi / 180.0,
    si_per_motion=1.0,
    rate_unit="N*m/rad",
    si_per_rate=1.0,
    force_unit="N*m",
    force_word="torque",
    rate_name="torsion rate",
    preload_symbol="T0",
    mass_unit="kg*m^2",
    damping_unit="N*m*s/rad",
    rate_slip_unit="N*mm/rad",
    table_columns=("phi_deg", "phi1_per_rad", "phi2_per_rad2", "phi3_per_rad3"),  # derivatives in rad/rad
    dynamic_column="dynamic_phi_deg",
    rate_suffix="N_m_per_rad",
    force_suffix="N_m",
    mass_suffix="kg_m2",
    default_max_pressure_angle_deg=DEFAULT_MAX_PRESSURE_ANGLE_DEG["oscillating"],
)
FOLLOWER_KINDS = (TRANSLATING, OSCILLATING)


def kind_of_motion(unit: str) -> FollowerKind:
    """The follower kind whose model motion is in ``unit`` ("mm" or "rad")."""
    for kind in FOLLOWER_KINDS:
        if kind.motion_unit == unit:
            return kind
    raise ValueError(f"no follower moves in {unit!r}: the motion unit is one of mm, rad")


def kind_of_lift(unit: str) -> FollowerKind:
    """The follower kind whose lift is given in ``unit`` ("mm" or "deg")."""
    for kind in FOLLOWER_KINDS:
        if kind.lift_unit == unit:
            return kind
    raise ValueError(f"no follower's lift is in {unit!r}: the lift unit is one of mm, deg")


@dataclass(frozen=True)
class FollowerType:
    """A ``[follower] type``: a kind of motion and the contact (a roller, or a flat face)."""

    name: str  # the case file's value, e.g. "translating-roller"
    kind: FollowerKind
    roller: bool  # False: a flat face

    def __str__(self) -> str:
        return self.name


FOLLOWER_TYPES = {
    t.name: t
    for t in (
        FollowerType("translating-roller", TRANSLATING, roller=True),
        FollowerType("translating-flat", TRANSLATING, roller=False),
        FollowerType("oscillating-roller", OSCILLATING, roller=True),
        FollowerType("oscillating-flat", OSCILLATING, roller=False),
    )
}
