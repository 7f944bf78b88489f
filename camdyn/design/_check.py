"""The verdict primitive: every judgment camdyn makes is a :class:`Check` with a value, a limit and a unit."""

from __future__ import annotations

from collections.abc import Iterable
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
    PATH_ERROR = "path_error"  # a path case: how far the linkage driven by the cam misses the path, mm
    TRANSMISSION_ANGLE = "transmission_angle"  # a path case: the driven dyads' least transmission angle, deg
    CLEARANCE = "clearance"  # camdyn machine: the least gap between two followers that share space, mm
    SEATING_VELOCITY = "seating_velocity"  # [valvetrain]: the valve's speed landing on its seat, m/s
    VALVE_BOUNCE = "valve_bounce"  # [valvetrain]: the valve's re-lift after it seats, mm
    COIL_BIND = "coil_bind"  # [valvetrain] with [spring]: the valve's lift to spare before its spring goes solid, mm
    CROSSOVER_IMPACT = "crossover_impact"  # a groove cam: the speed at which a flank meets the follower, m/s
    CONJUGATE_PRESSURE_ANGLE = "conjugate_pressure_angle"  # conjugate cams: the second cam's, deg
    CONJUGATE_CURVATURE = "conjugate_curvature"  # conjugate cams: the second cam's least convex radius / its roller
    CONJUGATE_PRELOAD = "conjugate_preload"  # preloaded conjugate cams: the least force on either cam, N
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
        return _WORDS[self][0]

    @property
    def unit(self) -> str:
        """The unit of the check's value and limit (``curvature``: "ratio" for a roller; a flat face's is "mm")."""
        return _WORDS[self][1]

    @property
    def sense(self) -> str:
        """How the value must compare with the limit: ">=", ">" or "<="."""
        return _WORDS[self][2]

    def check(self, value: float | None, limit: float, unit: str | None = None) -> Check:
        """The judgment of ``value`` against ``limit``, in this kind's unit unless ``unit`` is given."""
        return Check(self.value, value, limit, self.unit if unit is None else unit, self.sense)


# label, unit, sense
_WORDS = {
    CheckKind.CONTACT_FORCE: ("least interface force, dynamic", "N", ">"),
    CheckKind.SPEED_MARGIN: ("dynamic jump speed / cam speed", "x", ">="),
    CheckKind.PRESSURE_ANGLE: ("largest pressure angle", "deg", "<="),
    CheckKind.CURVATURE: ("least contour radius / roller radius", "ratio", ">="),
    CheckKind.FACE_WIDTH: ("contact travel along the face", "mm", "<="),
    CheckKind.TRAIN_DEFLECTION: ("largest train compression / lift", "ratio", "<="),
    CheckKind.CONTACT_STRESS: ("largest Hertz contact pressure", "MPa", "<="),
    CheckKind.PATH_ERROR: ("largest distance from the path", "mm", "<="),
    CheckKind.TRANSMISSION_ANGLE: ("least transmission angle of the linkage", "deg", ">="),
    CheckKind.CLEARANCE: ("least gap between two followers", "mm", ">="),
    CheckKind.SEATING_VELOCITY: ("valve speed landing on its seat", "m/s", "<="),
    CheckKind.VALVE_BOUNCE: ("valve re-lift after seating", "mm", "<="),
    CheckKind.COIL_BIND: ("valve lift to spare before the spring is solid", "mm", ">"),
    CheckKind.CROSSOVER_IMPACT: ("largest impact speed across the backlash", "m/s", "<="),
    CheckKind.CONJUGATE_PRESSURE_ANGLE: ("largest pressure angle, conjugate cam", "deg", "<="),
    CheckKind.CONJUGATE_CURVATURE: ("conjugate cam: least radius / its roller", "ratio", ">="),
    CheckKind.CONJUGATE_PRELOAD: ("least force on either cam, preloaded", "N", ">"),
    CheckKind.SPRING_INDEX_MIN: ("spring index D/d, at least", "", ">="),
    CheckKind.SPRING_INDEX_MAX: ("spring index D/d, at most", "", "<="),
    CheckKind.SPRING_LIFT_SAFETY: ("shear yield strength / stress at full lift", "x", ">="),
    CheckKind.SPRING_SOLID_SAFETY: ("shear yield strength / stress at solid", "x", ">="),
    CheckKind.SPRING_FATIGUE_SAFETY: ("fatigue safety factor", "x", ">="),
    CheckKind.SPRING_BUCKLING: ("free length, against the buckling limit", "mm", "<="),
    CheckKind.SPRING_CLASH_ALLOWANCE: ("solid deflection / full-lift deflection - 1", "x", ">="),
    CheckKind.SPRING_OUTSIDE_DIAMETER: ("outside diameter", "mm", "<="),
}
FLAT_CURVATURE_LABEL = "least contour radius (above 0: no cusp)"  # a flat face's curvature check, in mm


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

    @property
    def label(self) -> str:
        """What the value is, in words: its kind's label (a flat face's curvature is a radius, mm)."""
        return FLAT_CURVATURE_LABEL if self.kind is CheckKind.CURVATURE and self.unit == "mm" else self.kind.label

    def value_text(self, digits: int = 4) -> str:
        """The value in a table or a sentence: ``digits`` significant digits ("unbounded" for None)."""
        return "unbounded" if self.value is None else f"{self.value:.{digits}g}"

    @property
    def margin(self) -> float | None:
        """How far the value is from the limit, in the check's unit, positive where it passes; None: unbounded."""
        if self.value is None:
            return None
        return self.value - self.limit if self.sense in (">=", ">") else self.limit - self.value

    def json(self) -> dict:
        d = asdict(self)
        d.pop("sense")
        d["ok"] = self.ok
        return d


def find(checks: Iterable[Check], kind: CheckKind) -> Check | None:
    """The check of ``kind`` among ``checks``, or None."""
    return next((c for c in checks if c.name == kind.value), None)
