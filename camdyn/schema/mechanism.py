"""The ``[mechanism]`` table: the cam-linkage that traces a ``[path]`` (the CCM or Ye & Smith's oscillating one)."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import ConfigDict, Field, model_validator

from .._core.kinds import OSCILLATING, TRANSLATING, FollowerKind
from .._core.units import MAX_LENGTH_MM
from ._base import Point, Real, Table, TypeKeys, check_type_keys, keys_by_type

_KINDS = {"ccm": TRANSLATING, "oscillating": OSCILLATING}
# the keys each type needs, and those it may take besides (the keys named for neither, every type takes)
_KEYS: TypeKeys = {
    "ccm": (
        ("link", "slider_angle"),
        ("joint_distance", "joint_angle", "slider_point", "slider_mode", "base_radius", "max_pressure_angle"),
    ),
    "oscillating": (("pivot", "path_link", "follower_link", "pin_distance", "arm"), ("arm_angle", "follower_mode")),
}


class MechanismSpec(Table):
    """The ``[mechanism]`` table (lengths mm, angles deg, points (x, y) mm in the path's frame).

    ``type = "ccm"``: the combined cam mechanism of a profile cutter. The camshaft at ``cam_center`` (A) carries
    the crank pin B; the coupler B-T carries the tracing point T and the joint C; the link C-E drives the slider
    pin E along the slider line; the slider is the cam's translating roller follower.
    ``type = "oscillating"``: Ye & Smith's cam-linkage. Fixed pivots O (``cam_center``) and D (``pivot``); the
    link F-C (F traces the path) carries the pin B; the follower D-C turns with the roller arm D-E; the coupler
    B-A joins B to the crank pin A on the cam. The JSON schema says which keys each type takes.
    """

    model_config = ConfigDict(json_schema_extra=keys_by_type(_KEYS))

    type: Literal["ccm", "oscillating"] = Field(description="ccm | oscillating")
    cam_center: Point = Field(default=(0.0, 0.0), description="camshaft axis (A in the CCM, O in Ye & Smith), mm")
    crank: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "crank length (AB in the CCM, OA in Ye & Smith), mm; default: Ye & Smith eq. 5 from the extremes of "
            "|cam centre to path-side point|"
        ),
    )
    coupler: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "coupler length from the crank pin towards the path (BT in the CCM, BA in Ye & Smith), mm; default: "
            "eq. 5 (give both crank and coupler or neither)"
        ),
    )
    crank_mode: Literal[-1, 1] = Field(
        default=1,
        description=(
            "assembly mode of the crank dyad at the path start: +1 when (path-side point, crank pin, cam centre) "
            "run anticlockwise (Ye & Smith: B0, A0, O)"
        ),
    )
    roller_radius: Real = Field(default=10.0, gt=0, le=MAX_LENGTH_MM, description="follower roller radius, mm")
    width: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="contact width of the roller along the camshaft axis, mm; gives the Hertz contact stress",
    )
    # ccm
    joint_distance: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="ccm: distance from the crank pin B to the joint C on the coupler, mm (default: C = T)",
    )
    joint_angle: Real = Field(default=0.0, description="ccm: angle from B->T to B->C, deg anticlockwise")
    link: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="ccm: length of the link C-E from the coupler joint to the slider pin, mm",
    )
    slider_point: Point | None = Field(
        default=None, description="ccm: a point of the slider line, mm (default: the cam centre)"
    )
    slider_angle: Real | None = Field(
        default=None, description="ccm: direction of the slider line in which the cam lifts the slider, deg"
    )
    slider_mode: Literal[-1, 1] = Field(
        default=1,
        description="ccm: +1 takes the slider pin E ahead of (along slider_angle) the foot of C on the line, -1 behind",
    )
    base_radius: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "ccm: cam base radius, mm (default: the least that keeps the pressure angle within max_pressure_angle "
            "and the contour free of undercut)"
        ),
    )
    max_pressure_angle: Real = Field(
        default=TRANSLATING.default_max_pressure_angle_deg,
        gt=0,
        lt=80,
        description="ccm: pressure angle used to choose the base radius, deg",
    )
    # oscillating
    pivot: Point | None = Field(default=None, description="oscillating: follower pivot D, mm")
    path_link: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="oscillating: link F-C from the path point to the follower joint (LFC), mm",
    )
    follower_link: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="oscillating: follower D-C (LDC), mm"
    )
    pin_distance: Real | None = Field(
        default=None,
        ge=-MAX_LENGTH_MM,
        le=MAX_LENGTH_MM,
        description="oscillating: distance F-B along F->C of the coupler pin B (LFB), mm",
    )
    arm: Real | None = Field(default=None, gt=0, le=MAX_LENGTH_MM, description="oscillating: roller arm D-E (LDE), mm")
    arm_angle: Real = Field(
        default=180.0, description="oscillating: angle from D->C to D->E, deg anticlockwise (180: E on CD produced)"
    )
    follower_mode: Literal[-1, 1] = Field(
        default=1, description="oscillating: assembly mode of F, C, D (+1 anticlockwise)"
    )

    @model_validator(mode="after")
    def _keys_for_type(self) -> MechanismSpec:
        check_type_keys(self, self.type, "mechanism", _KEYS)
        if (self.crank is None) != (self.coupler is None):
            raise ValueError(
                f"{'coupler' if self.coupler is None else 'crank'}: give crank and coupler together, or neither (eq. 5)"
            )
        if self.type == "oscillating":
            assert self.pin_distance is not None and self.path_link is not None  # check_type_keys: needed
            if abs(self.pin_distance - self.path_link) < 1e-9:
                raise ValueError("pin_distance: the pin B cannot coincide with the joint C")
            assert self.pivot is not None and self.arm is not None
            if math.dist(self.pivot, self.cam_center) < 1e-9 * max(self.arm, 1.0):  # before the synthesis compiles
                raise ValueError(
                    "pivot: the follower pivot D lies on the cam centre: move it off cam_center (the arm must swing "
                    "about a point away from the camshaft)"
                )
        return self

    @property
    def kind(self) -> FollowerKind:
        """The kind of the follower the mechanism drives: the CCM's translating cutter, Ye & Smith's arm."""
        return _KINDS[self.type]
