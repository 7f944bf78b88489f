"""The ``[follower]`` table: the follower type and its dimensions (mm, deg)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from .._core.kinds import FOLLOWER_TYPES, FollowerKind, FollowerType
from .._core.units import MAX_LENGTH_MM
from ._base import FileName, Real, Table

# keys each type needs, and those it may take besides ``type``, ``base_radius`` (or ``contour``), ``rotation``
# and ``width``
_NEEDS = {
    "translating-roller": ("roller_radius",),
    "translating-flat": (),
    "oscillating-roller": ("roller_radius", "pivot_distance", "arm_length"),
    "oscillating-flat": ("pivot_distance",),
}
_TAKES = {
    "translating-roller": {"offset"},
    "translating-flat": {"offset", "face_width"},
    "oscillating-roller": {"pivot_angle"},
    "oscillating-flat": {"offset", "pivot_angle", "face_width"},
}


class FollowerSpec(Table):
    """The ``[follower]`` table of a case file (lengths mm, angles deg)."""

    type: Literal["translating-roller", "translating-flat", "oscillating-roller", "oscillating-flat"] = Field(
        default="translating-roller",
        description="translating-roller | translating-flat | oscillating-roller | oscillating-flat",
    )
    base_radius: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="least radius of the cam contour, mm (required unless contour is given)",
    )
    contour: FileName | None = Field(
        default=None,
        description=(
            "the cam's outline instead of [motion] and base_radius: a CSV file (header x_mm,y_mm, as camdyn "
            "profile writes) or a DXF file (a closed LWPOLYLINE, POLYLINE or SPLINE), relative to the case file; "
            "points in the cam frame at cam angle 0, in sequence along the outline; the motion is derived by exact "
            "contact and the base radius is the least contour radius"
        ),
    )
    roller_radius: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="roller radius, mm (roller followers)"
    )
    offset: Real = Field(
        default=0.0,
        ge=-MAX_LENGTH_MM,
        le=MAX_LENGTH_MM,
        description="translating: axis offset e, mm, positive lowers the rise pressure angle; "
        "oscillating-flat: distance of the face line from the pivot, mm, positive toward the cam centre",
    )
    rotation: Literal["cw", "ccw"] = Field(default="cw", description="sense in which the cam turns: cw | ccw")
    pivot_distance: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="oscillating: cam centre to arm pivot, mm"
    )
    pivot_angle: Real = Field(
        default=0.0, ge=-360.0, le=360.0, description="oscillating: direction of the pivot from the cam centre, deg"
    )
    arm_length: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="oscillating roller: pivot to roller centre, mm"
    )
    face_width: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="flat followers: usable face width, mm"
    )
    closure: Literal["spring", "groove", "conjugate"] = Field(
        default="spring",
        description=(
            "what holds the follower on the cam: spring (a return spring, the follower may jump) | groove (a roller "
            "in a slot: form-closed, no spring needed; the contact force is signed, positive on the inner flank) | "
            "conjugate (two cams and two rollers: not built yet, refused)"
        ),
    )
    backlash: Real = Field(
        default=0.0,
        ge=0,
        le=MAX_LENGTH_MM,
        description=(
            "closure = groove: the slot width less the roller diameter, mm; the groove walls lie roller_radius + "
            "backlash/2 either side of the pitch curve, and the follower flies across the backlash where the "
            "contact force changes flank"
        ),
    )
    width: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "contact width along the camshaft axis (the narrower of cam and roller or face), mm; gives the Hertz "
            "contact stress"
        ),
    )

    @model_validator(mode="after")
    def _keys_for_type(self) -> FollowerSpec:
        a = self.kind.article
        for key in _NEEDS[self.type]:
            if getattr(self, key) is None:
                raise ValueError(f"{key}: required for {a} {self.type} follower")
        if self.contour is None and self.base_radius is None:
            raise ValueError('base_radius: required (or give the outline of the cam as contour = "cam.csv")')
        if self.contour is not None and self.base_radius is not None:
            raise ValueError("base_radius: a contour gives the base radius (its least radius): remove base_radius")
        if self.contour is not None and not self.contour.strip():
            raise ValueError("contour: empty file name")
        takes = (
            set(_NEEDS[self.type])
            | _TAKES[self.type]
            | {"type", "base_radius", "contour", "rotation", "width", "closure"}
        )
        if self.closure == "conjugate":
            raise ValueError('closure: "conjugate" cams are not built yet: use "groove" (a roller in a slot)')
        if self.closure == "groove":
            if not self.roller:
                raise ValueError(f"closure: a groove holds a roller, not {a} {self.type} follower")
            if self.contour is not None:
                raise ValueError("closure: a groove cam is drawn from [motion], not from a contour")
            takes = takes | {"backlash"}
        for key in sorted(self.model_fields_set - takes):
            raise ValueError(f"{key}: not used by {a} {self.type} follower (its keys: {', '.join(sorted(takes))})")
        return self

    @property
    def form_closed(self) -> bool:
        """Whether a groove (or conjugate cams) holds the follower both ways: it cannot jump."""
        return self.closure != "spring"

    @property
    def follower_type(self) -> FollowerType:
        """The type as an object: its kind and its contact."""
        return FOLLOWER_TYPES[self.type]

    @property
    def kind(self) -> FollowerKind:
        """Translating or oscillating (:data:`camdyn._core.kinds.TRANSLATING`, ``OSCILLATING``)."""
        return FOLLOWER_TYPES[self.type].kind

    @property
    def translating(self) -> bool:
        return not self.kind.rotary

    @property
    def roller(self) -> bool:
        """A roller follower (else a flat face)."""
        return FOLLOWER_TYPES[self.type].roller

    @property
    def sigma(self) -> float:
        """+1 for a cam turning ccw, -1 for cw."""
        return 1.0 if self.rotation == "ccw" else -1.0
