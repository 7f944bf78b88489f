"""The ``[path]`` table: the closed curve a point of the linkage must trace, once per cam revolution."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import ConfigDict, Field, model_validator

from .._core.units import MAX_LENGTH_MM, MAX_PATH_POINTS
from ._base import Coordinate, Point, Real, Table, TypeKeys, check_type_keys, keys_by_type

PATH_TYPES = ("ellipse", "circle", "rectangle", "eight", "line", "racetrack", "points")

# the keys each type needs, and those it may take besides (every type takes type, rotation, reverse, phase)
_KEYS: TypeKeys = {
    "ellipse": (("center", "semi_major", "semi_minor"), ()),
    "circle": (("center", "radius"), ()),
    "rectangle": (("center", "width", "height"), ("corner_radius",)),
    "eight": (("center", "width", "height"), ()),
    "line": (("start", "end"), ()),
    "racetrack": (("center", "straight", "radius"), ()),
    "points": (("x", "y"), ()),
}


class PathSpec(Table):
    """The ``[path]`` table: the closed curve the tracing point must follow (lengths mm, angles deg); the
    tracing point goes round it once per cam revolution.

    Where each type starts and how it runs: ``ellipse`` at the end of ``semi_major``, anticlockwise;
    ``circle`` at angle ``rotation``, anticlockwise; ``rectangle`` at the middle of its right side,
    anticlockwise; ``eight`` at the crossing, x = W/2 sin w, y = H/2 sin 2w; ``line`` from ``start`` to ``end``
    and back, at rest at both ends (harmonic); ``racetrack`` at the lower end of the right semicircle,
    anticlockwise (Ye & Smith eq. 9); ``points`` at the first point, through every point on a periodic cubic
    spline (chord-length knots). ``reverse`` runs the curve the other way round, ``phase`` shifts the start.
    The JSON schema says which keys each type takes.
    """

    model_config = ConfigDict(json_schema_extra=keys_by_type(_KEYS))

    type: Literal["ellipse", "circle", "rectangle", "eight", "line", "racetrack", "points"] = Field(
        description="ellipse | circle | rectangle | eight | line | racetrack | points"
    )
    center: Point | None = Field(default=None, description="centre of the curve (x, y), mm (all but line, points)")
    semi_major: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="ellipse: semi-axis along `rotation`, mm; starts at its end, runs anticlockwise",
    )
    semi_minor: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="ellipse: the other semi-axis, mm"
    )
    radius: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description="circle: radius (starts at angle `rotation`); racetrack: radius of the two semicircles, mm",
    )
    width: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="rectangle, eight: extent along `rotation`, mm"
    )
    height: Real | None = Field(
        default=None, gt=0, le=MAX_LENGTH_MM, description="rectangle, eight: extent across it, mm"
    )
    corner_radius: Real | None = Field(
        default=None,
        ge=0,
        le=MAX_LENGTH_MM,
        description=(
            "rectangle: corner fillet radius, mm (0: sharp corners; the follower acceleration is then unbounded); "
            "the rectangle starts at the middle of its right side"
        ),
    )
    straight: Real | None = Field(
        default=None,
        gt=0,
        le=MAX_LENGTH_MM,
        description=(
            "racetrack: length of each straight, mm (Ye & Smith eq. 9: starts at the lower end of the right semicircle)"
        ),
    )
    start: Point | None = Field(
        default=None, description="line: first end (x, y), mm; the point runs start -> end -> start"
    )
    end: Point | None = Field(default=None, description="line: second end (x, y), mm")
    x: list[Coordinate] | None = Field(
        default=None,
        max_length=MAX_PATH_POINTS,
        description="points: x of the precision points in order, mm (a last point equal to the first is dropped)",
    )
    y: list[Coordinate] | None = Field(
        default=None, max_length=MAX_PATH_POINTS, description="points: y of the precision points, mm"
    )
    rotation: Real = Field(default=0.0, description="turn of the curve about its centre, deg anticlockwise")
    reverse: bool = Field(default=False, description="run the curve the other way round (clockwise)")
    phase: Real = Field(default=0.0, ge=0.0, lt=1.0, description="shift the start point by this fraction of a loop")

    @model_validator(mode="after")
    def _keys_for_type(self) -> PathSpec:
        check_type_keys(self, self.type, "path", _KEYS)
        if self.type == "line":
            assert self.start is not None and self.end is not None  # check_type_keys: a line needs both
            if math.dist(self.start, self.end) == 0.0:
                raise ValueError("end: the line has zero length")
        if self.type == "points":
            assert self.x is not None and self.y is not None  # check_type_keys: points need both
            if len(self.x) != len(self.y):
                raise ValueError(f"y: {len(self.y)} values for {len(self.x)} x values")
            if len(self.x) < 4:
                raise ValueError("x: at least 4 precision points are needed")
        if self.type == "rectangle":
            assert self.width is not None and self.height is not None  # check_type_keys: a rectangle needs both
            if 2.0 * (self.corner_radius or 0.0) > min(self.width, self.height):
                raise ValueError(f"corner_radius: {self.corner_radius:g} mm is more than half the shorter side")
        return self
