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
# the second roller's keys (closure = conjugate), by translating
_CONJUGATE = {
    True: {"conjugate_spacing", "conjugate_offset", "conjugate_roller_radius", "conjugate_preload"},
    False: {"conjugate_arm_angle", "conjugate_arm_length", "conjugate_roller_radius", "conjugate_preload_torque"},
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
            "conjugate (two cams on the shaft, two rollers on one follower: a yoke for a translating follower, a "
            "two-arm rocker for an oscillating one; the primary cam is drawn from [motion] as a spring cam's, the "
            "conjugate cam is derived so that the second roller stays on it; the contact force is signed, positive "
            "on the primary cam)"
        ),
    )
    backlash: Real = Field(
        default=0.0,
        ge=0,
        le=MAX_LENGTH_MM,
        description=(
            "closure = groove: the slot width less the roller diameter, mm; the groove walls lie roller_radius + "
            "backlash/2 either side of the pitch curve, and the follower flies across the backlash where the "
            "contact force changes flank. closure = conjugate (with no preload): the clearance between the second "
            "roller and the conjugate cam, along its normal, while the first roller sits on the primary cam, mm"
        ),
    )
    conjugate_spacing: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "closure = conjugate, translating (required): the yoke's span, mm: the second roller's centre lies this "
            "far from the first's along the follower's axis, towards the cam centre and past it (the two rollers "
            "sit either side of the camshaft)"
        ),
    )
    conjugate_offset: Real = Field(
        default=0.0,
        ge=-MAX_LENGTH_MM,
        le=MAX_LENGTH_MM,
        description=(
            "closure = conjugate, translating: the second roller's centre across the follower's axis from the "
            "first's, mm, positive as offset"
        ),
    )
    conjugate_arm_angle: Real | None = Field(
        default=None,
        ge=-360.0,
        le=360.0,
        description=(
            "closure = conjugate, oscillating (required): the angle at the pivot from the first arm (pivot to first "
            "roller) to the second, deg, counter-clockwise positive as drawn with the cam's frame (the two arms are "
            "one rigid rocker)"
        ),
    )
    conjugate_arm_length: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="closure = conjugate, oscillating: pivot to the second roller's centre, mm (default arm_length)",
    )
    conjugate_roller_radius: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="closure = conjugate: the second roller's radius, mm (default roller_radius)",
    )
    conjugate_preload: Real = Field(
        default=0.0,
        ge=0,
        le=1e9,
        description=(
            "closure = conjugate, translating: the force with which the yoke, assembled with interference, presses "
            "each roller on its cam at rest, N; the follower's force is shared between the cams (each carries the "
            "preload plus or minus half the force, equally stiff contacts) until one unloads"
        ),
    )
    conjugate_preload_torque: Real = Field(
        default=0.0,
        ge=0,
        le=1e9,
        description=(
            "closure = conjugate, oscillating: the torque about the pivot with which each arm's roller is pressed "
            "on its cam at rest, N*m (shared as conjugate_preload)"
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
        if self.form_closed:
            holds, drawn = {
                "groove": ("a groove holds", "a groove cam is"),
                "conjugate": ("conjugate cams hold", "conjugate cams are"),
            }[self.closure]
            if not self.roller:
                raise ValueError(f"closure: {holds} a roller, not {a} {self.type} follower")
            if self.contour is not None:
                raise ValueError(f"closure: {drawn} drawn from [motion], not from a contour")
            takes = takes | {"backlash"}
        if self.closure == "conjugate":
            takes = takes | _CONJUGATE[self.translating]
            need = "conjugate_spacing" if self.translating else "conjugate_arm_angle"
            if getattr(self, need) is None:
                raise ValueError(f"{need}: required for conjugate cams on {a} {self.type} follower")
            if self.backlash > 0.0 and self.pair_preload > 0.0:
                raise ValueError("backlash: a preloaded conjugate pair has no backlash (give one or the other)")
        for key in sorted(self.model_fields_set - takes):
            raise ValueError(f"{key}: not used by {a} {self.type} follower (its keys: {', '.join(sorted(takes))})")
        return self

    @property
    def form_closed(self) -> bool:
        """Whether a groove (or conjugate cams) holds the follower both ways: it cannot jump."""
        return self.closure != "spring"

    @property
    def pair_preload(self) -> float:
        """closure = conjugate: the preload between the rollers in the motion's force unit (N, or N*m)."""
        return self.conjugate_preload if self.translating else self.conjugate_preload_torque

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
