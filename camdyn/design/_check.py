"""The verdict primitive: every judgment camdyn makes is a :class:`Check` with a value, a limit and a unit."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from enum import Enum


class CheckKind(str, Enum):  # noqa: UP042 (StrEnum would change str() and format() of a member)
    """What a check judges (its ``name`` in the JSON contract)."""

    CONTACT_FORCE = "contact_force"
    SPEED_MARGIN = "speed_margin"
    PRESSURE_ANGLE = "pressure_angle"
    CURVATURE = "curvature"
    FACE_WIDTH = "face_width"
    TRAIN_DEFLECTION = "train_deflection"
    CONTACT_STRESS = "contact_stress"  # Hertz pressure between cam and follower, MPa
    CLEARANCE = "clearance"  # camdyn machine: the least gap between two followers that share space, mm
    CROSSOVER_IMPACT = "crossover_impact"  # a groove cam: the speed at which a flank meets the follower, m/s
    # the return spring as a part (camdyn spring)
    SPRING_INDEX_MIN = "spring_index_min"
    SPRING_INDEX_MAX = "spring_index_max"
    SPRING_LIFT_SAFETY = "spring_lift_safety"  # Ssy / stress at full lift
    SPRING_SOLID_SAFETY = "spring_solid_safety"  # Ssy / stress at solid
    SPRING_FATIGUE_SAFETY = "spring_fatigue_safety"
    SPRING_BUCKLING = "spring_buckling"  # free length against the critical free length
    SPRING_CLASH_ALLOWANCE = "spring_clash_allowance"  # (solid deflection / full-lift deflection) - 1
    SPRING_OUTSIDE_DIAMETER = "spring_outside_diameter"

    @property
    def label(self) -> str:
        """What the check's value is, in words (the report's and the terminal's "what" column)."""
        return _LABELS[self]


_LABELS = {
    CheckKind.CONTACT_FORCE: "least interface force, dynamic",
    CheckKind.SPEED_MARGIN: "dynamic jump speed / cam speed",
    CheckKind.PRESSURE_ANGLE: "largest pressure angle",
    CheckKind.CURVATURE: "least contour radius / roller radius",
    CheckKind.FACE_WIDTH: "contact travel along the face",
    CheckKind.TRAIN_DEFLECTION: "largest train compression / lift",
    CheckKind.CONTACT_STRESS: "largest Hertz contact pressure",
    CheckKind.CLEARANCE: "least gap between two followers",
    CheckKind.CROSSOVER_IMPACT: "largest impact speed across the backlash",
    CheckKind.SPRING_INDEX_MIN: "spring index D/d, at least",
    CheckKind.SPRING_INDEX_MAX: "spring index D/d, at most",
    CheckKind.SPRING_LIFT_SAFETY: "shear yield strength / stress at full lift",
    CheckKind.SPRING_SOLID_SAFETY: "shear yield strength / stress at solid",
    CheckKind.SPRING_FATIGUE_SAFETY: "fatigue safety factor",
    CheckKind.SPRING_BUCKLING: "free length, against the buckling limit",
    CheckKind.SPRING_CLASH_ALLOWANCE: "solid deflection / full-lift deflection - 1",
    CheckKind.SPRING_OUTSIDE_DIAMETER: "outside diameter",
}


@dataclass(frozen=True)
class Check:
    """One pass/fail judgment: the value must be ``sense`` (">=", ">" or "<=") the limit."""

    name: str
    value: float | None  # None: unbounded (e.g. no jump at any speed)
    limit: float
    unit: str
    sense: str = ">="

    @property
    def ok(self) -> bool:
        if self.value is None:  # unbounded: infinitely good for ">=" and ">", infinitely bad for "<="
            return self.sense != "<="
        return {">=": self.value >= self.limit, ">": self.value > self.limit, "<=": self.value <= self.limit}[
            self.sense
        ]

    @property
    def kind(self) -> CheckKind:
        return CheckKind(self.name)

    def json(self) -> dict:
        d = asdict(self)
        d.pop("sense")
        d["ok"] = self.ok
        return d


def find(checks, kind: CheckKind) -> Check | None:
    """The check of ``kind`` among ``checks``, or None."""
    return next((c for c in checks if c.name == kind.value), None)
