"""The ``[limits]`` table: what a passing design must meet."""

from __future__ import annotations

from pydantic import Field

from .._core.units import (
    DEFAULT_MAX_IMPACT_VELOCITY_M_PER_S,
    DEFAULT_MAX_PATH_ERROR_MM,
    DEFAULT_MAX_SEATING_VELOCITY,
    DEFAULT_MAX_TRAIN_DEFLECTION,
    DEFAULT_MIN_CONTACT_FORCE_N,
    DEFAULT_MIN_CURVATURE_RATIO,
    DEFAULT_MIN_TRANSMISSION_ANGLE_DEG,
    DEFAULT_SPEED_MARGIN,
    MAX_FORCE_N,
    SPEED_MARGIN_RANGE,
)
from ._base import Real, Table


class LimitsSpec(Table):
    """The ``[limits]`` table."""

    speed_margin: Real = Field(
        default=DEFAULT_SPEED_MARGIN,
        ge=SPEED_MARGIN_RANGE[0],
        le=SPEED_MARGIN_RANGE[1],
        description=(
            "the dynamic jump speed must be at least this times the speed (at least 1: below it the follower jumps at "
            "its own speed)"
        ),
    )
    min_contact_force: Real = Field(
        default=DEFAULT_MIN_CONTACT_FORCE_N,
        ge=0,
        le=MAX_FORCE_N,
        description=(
            "the least interface force over a revolution must exceed this, N (at least 0: a follower that leaves the "
            "cam has none, so a negative limit would pass it)"
        ),
    )
    max_pressure_angle: Real | None = Field(
        default=None, gt=0, lt=90, description="deg; default 30 for translating, 35 for oscillating followers"
    )
    min_curvature_ratio: Real = Field(
        default=DEFAULT_MIN_CURVATURE_RATIO,
        gt=0,
        description="least convex contour radius of curvature / roller radius",
    )
    max_train_deflection: Real = Field(
        default=DEFAULT_MAX_TRAIN_DEFLECTION,
        gt=0,
        le=1,
        description=(
            "compliant trains: the largest train deflection (cam lift minus follower motion) as a fraction of the "
            "lift; beyond it the cam no longer drives the follower"
        ),
    )
    max_path_error: Real = Field(
        default=DEFAULT_MAX_PATH_ERROR_MM,
        gt=0,
        description=(
            "path cases ([path] and [mechanism]): how far the linkage driven by the synthesized cam may miss the path, "
            f"mm (the forward check); default {DEFAULT_MAX_PATH_ERROR_MM:g}"
        ),
    )
    min_transmission_angle: Real = Field(
        default=DEFAULT_MIN_TRANSMISSION_ANGLE_DEG,
        gt=0,
        lt=90,
        description=(
            "path cases: the least transmission angle of the mechanism's driven dyads over the path, deg (under it the "
            f"linkage binds; 0 is a dead centre); default {DEFAULT_MIN_TRANSMISSION_ANGLE_DEG:g}"
        ),
    )
    min_preload: Real | None = Field(
        default=None,
        ge=0,
        le=MAX_FORCE_N,
        description=(
            "the least preload a proposed spring may give at zero lift (a seat load), N (N*m for an oscillating arm): "
            "honoured by size and optimize --objective spring-force"
        ),
    )
    max_contact_stress: Real | None = Field(
        default=None,
        gt=0,
        description=(
            "largest Hertz contact pressure between cam and follower over a revolution, MPa (needs [follower] width)"
        ),
    )
    max_impact_velocity: Real = Field(
        default=DEFAULT_MAX_IMPACT_VELOCITY_M_PER_S,
        gt=0,
        le=100,
        description=(
            "form-closed cams ([follower] closure = groove or conjugate): the largest relative speed at which the "
            "follower, crossing its backlash, may meet the other flank (or cam), m/s (at the roller centre for an "
            "oscillating arm); "
            f"default {DEFAULT_MAX_IMPACT_VELOCITY_M_PER_S:g}"
        ),
    )
    max_seating_velocity: Real = Field(
        default=DEFAULT_MAX_SEATING_VELOCITY,
        gt=0,
        le=100,
        description="[valvetrain] cases: the valve's speed on landing on its seat at the case speed, m/s (default 0.5)",
    )
