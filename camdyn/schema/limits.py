"""The ``[limits]`` table: what a passing design must meet."""

from __future__ import annotations

from pydantic import Field

from .._core.units import DEFAULT_MIN_CONTACT_FORCE_N, DEFAULT_MIN_CURVATURE_RATIO, DEFAULT_SPEED_MARGIN
from ._base import Real, Table


class LimitsSpec(Table):
    """The ``[limits]`` table."""

    speed_margin: Real = Field(default=DEFAULT_SPEED_MARGIN, gt=0, description="the dynamic jump speed must be at least this times the speed")
    min_contact_force: Real = Field(default=DEFAULT_MIN_CONTACT_FORCE_N, description="the least interface force over a revolution must exceed this, N")
    max_pressure_angle: Real | None = Field(default=None, gt=0, lt=90, description="deg; default 30 for translating, 35 for oscillating followers")
    min_curvature_ratio: Real = Field(default=DEFAULT_MIN_CURVATURE_RATIO, gt=0, description="least convex contour radius of curvature / roller radius")
    max_contact_stress: Real | None = Field(default=None, gt=0, description="largest Hertz contact pressure between cam and follower over a revolution, MPa (needs [follower] width)")
