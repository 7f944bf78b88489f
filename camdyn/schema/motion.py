"""The ``[motion]`` table: contiguous segments covering one cam revolution (named laws, polynomials from
boundary conditions, or B-splines), or a lift table read from a CSV file."""

from __future__ import annotations

from difflib import get_close_matches
from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from .._core.units import MAX_LENGTH_MM
from ._base import FileName, Pair, Real, Table

MIN_SEGMENT_DEG = 0.01  # a move over less cam angle than this cannot be cut, nor followed

# the named motion laws (camdyn.model.motion implements each)
LAW_NAMES: tuple[str, ...] = (
    "dwell",
    "constant-velocity",
    "constant-acceleration",
    "harmonic",
    "cycloidal",
    "polynomial-345",
    "polynomial-4567",
    "modified-trapezoid",
    "modified-sine",
)
POLYNOMIAL = "polynomial"  # a polynomial from boundary conditions (Norton's method)
BSPLINE = "bspline"  # a clamped B-spline of the normalized lift (what camdyn optimize writes)
BSPLINE_DEGREE = 5
SEGMENT_LAWS: tuple[str, ...] = LAW_NAMES + (POLYNOMIAL, BSPLINE)

# the boundary conditions only a polynomial segment takes
BOUNDARY_KEYS: tuple[str, ...] = (
    "start_velocity",
    "start_acceleration",
    "start_jerk",
    "end_velocity",
    "end_acceleration",
    "end_jerk",
    "points",
)


class SegmentSpec(Table):
    """One segment of a named law: ``law`` up to ``end`` (deg), rising by ``lift`` (mm; deg of arm swing for an
    oscillating follower; negative for a return)."""

    law: str = Field(description=f"motion law: {', '.join(SEGMENT_LAWS)}")
    end: Real = Field(description="cam angle where the segment ends, deg (the next starts there; the last ends at 360)")
    lift: Real = Field(
        default=0.0,
        ge=-MAX_LENGTH_MM,
        le=MAX_LENGTH_MM,
        description=(
            "rise of the segment, mm (deg of arm swing for an oscillating follower); negative for a return, 0 for "
            "a dwell"
        ),
    )

    @model_validator(mode="before")
    @classmethod
    def _no_boundary_conditions(cls, raw: Any) -> Any:
        if isinstance(raw, dict):
            if not isinstance(raw.get("law"), str):  # the law first: it decides the keys
                return raw  # missing or not a string: the field says so
            if raw["law"] not in SEGMENT_LAWS:
                raise _unknown_law("law", raw["law"])
            if "coefficients" in raw:
                raise ValueError(
                    'coefficients: only a law = "bspline" segment takes control points (this one is '
                    f"{raw.get('law')!r})"
                )
            for key in BOUNDARY_KEYS:
                if key in raw:
                    raise ValueError(
                        f'{key}: only a law = "polynomial" segment takes boundary conditions (this one is '
                        f"{raw.get('law')!r})"
                    )
        return raw


_PER = "per rad^{n} of cam angle: mm/rad^{n} (deg/rad^{n} of arm swing for an oscillating follower)"


class PolynomialSegmentSpec(Table):
    """A polynomial segment from boundary conditions (Norton's method): the polynomial of least degree through
    lift 0 at the start and ``lift`` at ``end``, with the given end derivatives and interior ``points``.
    Velocity and acceleration default to 0 at both ends, jerks are free unless given; the degree is the number
    of conditions less one (none given: 3-4-5; zero end jerks: 4-5-6-7)."""

    law: Literal["polynomial"] = Field(description='"polynomial"')
    end: Real = Field(description="cam angle where the segment ends, deg")
    lift: Real = Field(
        default=0.0,
        ge=-MAX_LENGTH_MM,
        le=MAX_LENGTH_MM,
        description="rise of the segment, mm (deg of arm swing for an oscillating follower); negative for a return",
    )
    start_velocity: Real = Field(default=0.0, description="velocity at the start, " + _PER.format(n=1))
    start_acceleration: Real = Field(default=0.0, description="acceleration at the start, " + _PER.format(n=2))
    start_jerk: Real | None = Field(
        default=None, description="jerk at the start (free if not given), " + _PER.format(n=3)
    )
    end_velocity: Real = Field(default=0.0, description="velocity at the end, " + _PER.format(n=1))
    end_acceleration: Real = Field(default=0.0, description="acceleration at the end, " + _PER.format(n=2))
    end_jerk: Real | None = Field(default=None, description="jerk at the end (free if not given), " + _PER.format(n=3))
    points: list[Pair] = Field(
        default_factory=list,
        description=(
            "interior positions [[theta_deg, lift], ...]: cam angle (deg, inside the segment) and lift from the "
            "segment's start (mm; deg of swing)"
        ),
    )

    @property
    def condition_count(self) -> int:
        """Conditions on the polynomial: the two end lifts, four end slopes and curvatures, given jerks, points."""
        return 6 + (self.start_jerk is not None) + (self.end_jerk is not None) + len(self.points)


class BSplineSegmentSpec(Table):
    """A rise or return whose normalized lift y(u) (u from 0 to 1 over the segment, y from 0 to 1) is a clamped
    B-spline of degree 5 on uniform knots with the control points ``coefficients``: the first three 0 and the last
    three 1, so that lift, velocity and acceleration meet a dwell on either side smoothly; an end not at rest
    (``start_at_rest``/``end_at_rest`` false) keeps only its first 0 (last 1), its next two setting the velocity and
    acceleration there (a valvetrain's flank meeting its lash ramp). ``camdyn optimize`` writes these."""

    law: Literal["bspline"] = Field(description='"bspline"')
    end: Real = Field(description="cam angle where the segment ends, deg")
    lift: Real = Field(
        default=0.0,
        ge=-MAX_LENGTH_MM,
        le=MAX_LENGTH_MM,
        description="rise of the segment, mm (deg of arm swing for an oscillating follower); negative for a return",
    )
    coefficients: list[Annotated[float, Field(strict=True, ge=-100.0, le=100.0)]] = Field(
        min_length=BSPLINE_DEGREE + 1,
        max_length=1000,
        description=(
            f"control points of y(u), dimensionless: at least {BSPLINE_DEGREE + 1}, the first three 0 and the last "
            f"three 1 (degree {BSPLINE_DEGREE}, uniform knots); at an end not at rest only the first 0 (the last 1)"
        ),
    )
    start_at_rest: bool = Field(
        default=True,
        description=(
            "the segment starts at rest (the first three coefficients 0); false: only the first is 0 and the second "
            "and third set its starting velocity and acceleration (camdyn optimize's flank meeting a valvetrain's "
            "opening ramp)"
        ),
    )
    end_at_rest: bool = Field(
        default=True,
        description=(
            "the segment ends at rest (the last three coefficients 1); false: only the last is 1 and the two before "
            "set its ending velocity and acceleration"
        ),
    )

    @model_validator(mode="after")
    def _clamped_ends(self) -> BSplineSegmentSpec:
        c = self.coefficients
        head, tail = c[: 3 if self.start_at_rest else 1], c[-3 if self.end_at_rest else -1 :]
        if any(abs(v) > 1e-12 for v in head) or any(abs(v - 1.0) > 1e-12 for v in tail):
            if self.start_at_rest and self.end_at_rest:
                raise ValueError(
                    f"coefficients: the first three must be 0 and the last three 1 (got {c[:3]} ... {c[-3:]}): lift, "
                    "velocity and acceleration start at 0 and end at the full lift, at rest"
                )
            first = "three" if self.start_at_rest else "one"
            last = "three" if self.end_at_rest else "one"
            raise ValueError(
                f"coefficients: the first {first} must be 0 and the last {last} 1 (got {c[:3]} ... {c[-3:]}): the "
                "lift starts at 0 and ends at the full lift"
            )
        return self


def _segment_kind(raw: Any) -> str:
    law = raw.get("law") if isinstance(raw, dict) else getattr(raw, "law", None)
    return law if law in (POLYNOMIAL, BSPLINE) else "law"


AnySegment = Annotated[
    Annotated[SegmentSpec, Tag("law")]
    | Annotated[PolynomialSegmentSpec, Tag(POLYNOMIAL)]
    | Annotated[BSplineSegmentSpec, Tag(BSPLINE)],
    Discriminator(_segment_kind),
]


class MotionSpec(Table):
    """The ``[motion]`` table: ``segments``, or a ``table`` of measured or tabulated lift."""

    segments: list[AnySegment] = Field(
        default_factory=list, description="the segments in order, from 0 deg (or give table)"
    )
    table: FileName | None = Field(
        default=None,
        description=(
            "CSV file of the lift, relative to the case file: header theta_deg,lift_mm (theta_deg,swing_deg for an "
            "oscillating follower), one revolution, angles increasing, any spacing; fitted by a periodic quintic "
            "smoothing spline"
        ),
    )
    valve_table: FileName | None = Field(
        default=None,
        description=(
            "with [valvetrain]: CSV file of the valve's lift at the valve, header theta_deg,lift_mm (cam degrees); "
            "camdyn adds constant-velocity ramps (valvetrain.ramp_velocity) that take up the lash, divides by the "
            "ratio (or carries it through the inverse of [valvetrain.rocker]'s lift) and fits the follower's lift as "
            "a table's"
        ),
    )
    tolerance: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "table: the largest departure of the fit from the data, mm (deg oscillating; default: the smoothing "
            "the data's noise asks for); valve_table: at the valve"
        ),
    )

    @model_validator(mode="after")
    def _one_source(self) -> MotionSpec:
        if self.table is not None and self.valve_table is not None:
            raise ValueError("valve_table: give either a table at the follower or a valve_table, not both")
        table, key = (self.table, "table") if self.valve_table is None else (self.valve_table, "valve_table")
        if table is not None and self.segments:
            raise ValueError(f"{key}: give either segments or a {key}, not both")
        if table is None and not self.segments:
            raise ValueError('segments: give the motion as segments = [...] or as table = "lift.csv"')
        if self.tolerance is not None and table is None:
            raise ValueError("tolerance: bounds the fit of a table: only with table = ... or valve_table = ...")
        if table is not None and not table.strip():
            raise ValueError(f"{key}: empty file name")
        return self


def _unknown_law(key: str, law: str) -> ValueError:
    hint = get_close_matches(law, SEGMENT_LAWS, n=1)
    mean = f" (did you mean {hint[0]!r}?)" if hint else ""
    return ValueError(f"{key}: unknown law {law!r}{mean}; valid laws: {', '.join(SEGMENT_LAWS)}")


def _check_polynomial(seg: PolynomialSegmentSpec, where: str, start: float, lu: str) -> None:
    prev = start
    for j, (theta, _) in enumerate(seg.points):
        if not start < theta < seg.end:
            raise ValueError(
                f"{where}.points[{j}]: at {theta:g} deg, outside the segment ({start:g} to {seg.end:g} deg)"
            )
        if not theta > prev:
            raise ValueError(
                f"{where}.points[{j}]: at {theta:g} deg, not after the previous point ({prev:g} deg): give the "
                "points in increasing angle, each once"
            )
        prev = theta
    given = [
        seg.lift,
        seg.start_velocity,
        seg.start_acceleration,
        seg.end_velocity,
        seg.end_acceleration,
        seg.start_jerk or 0.0,
        seg.end_jerk or 0.0,
    ]
    if not any(given) and not any(lift for _, lift in seg.points):
        raise ValueError(
            f"{where}.lift: a polynomial segment with no lift and no non-zero condition is a dwell: use law = "
            f'"dwell" (lift in {lu})'
        )


def check_segments(segments: list, lift_unit: str = "mm", key: str = "segments") -> None:
    """Raise ``ValueError("<key>[i].<field>: message")`` unless the segments form a motion program: known laws,
    increasing ends up to exactly 360 deg, dwells that do not lift and moves that do, polynomial points inside
    their segment, never below zero lift at a segment's end, net lift 0. ``lift_unit`` ("mm" or "deg") is the
    unit the lifts were given in, for the messages."""
    start, base = 0.0, 0.0
    lu = lift_unit
    for i, seg in enumerate(segments):
        where = f"{key}[{i}]"
        if seg.law not in SEGMENT_LAWS:
            raise _unknown_law(f"{where}.law", seg.law)
        end, lift = seg.end, seg.lift
        if not end > start:
            what = "overlaps the previous segment" if end < start else "has zero length"
            raise ValueError(f"{where}.end: segment ends at {end:g} deg, {what} (starts at {start:g} deg)")
        if seg.law != "dwell" and end - start < MIN_SEGMENT_DEG:
            raise ValueError(
                f"{where}.end: a {seg.law} segment over {end - start:.3g} deg is shorter than {MIN_SEGMENT_DEG:g} "
                "deg: no cam can be cut to it"
            )
        if end > 360.0 + 1e-9:
            raise ValueError(f"{where}.end: segment ends at {end:g} deg, past 360 deg")
        if seg.law == POLYNOMIAL:
            _check_polynomial(seg, where, start, lu)
        elif seg.law == "dwell" and lift != 0.0:
            raise ValueError(f"{where}.lift: a dwell cannot lift (got lift = {lift:g} {lu})")
        elif seg.law != "dwell" and lift == 0.0:
            raise ValueError(f"{where}.lift: a {seg.law} segment needs a non-zero lift, {lu}")
        if base + lift < -1e-9:
            raise ValueError(
                f"{where}.lift: the follower goes below zero lift at {end:g} deg (lift {base + lift:g} {lu})"
            )
        start, base = end, base + lift
    if abs(start - 360.0) > 1e-9:
        raise ValueError(f"{key}[{len(segments) - 1}].end: the last segment ends at {start:g} deg, not 360")
    if abs(base) > 1e-9:
        raise ValueError(f"{key}: the program does not close: net lift is {base:g} {lu}, must be 0")
