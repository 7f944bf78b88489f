"""The ``[spring]`` table: the return spring as a part (a helical compression spring), for ``camdyn spring``."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator

from .._core.kinds import FollowerKind
from .._core.materials import WIRE_NAMES, unknown_name
from ._base import Real, Table

END_TYPES = ("plain", "plain-ground", "squared", "squared-ground")
SPRING_MODELS = ("lumped", "surge")


class SpringSpec(Table):
    """The ``[spring]`` table (lengths mm). Every key is optional: without it the spring is designed freely."""

    material: str = Field(
        default="music-wire", description=f"spring wire: {', '.join(WIRE_NAMES)} (Shigley Table 10-4)"
    )
    outside_diameter_max: Real | None = Field(
        default=None, gt=0, description="largest outside coil diameter (the bore it works in), mm"
    )
    installed_length: Real | None = Field(
        default=None,
        gt=0,
        description=(
            "spring length at zero lift (where it gives the preload), mm; default: the shortest spring that meets "
            "the clash allowance"
        ),
    )
    end_type: Literal["plain", "plain-ground", "squared", "squared-ground"] = Field(
        default="squared-ground", description="coil ends: plain | plain-ground | squared | squared-ground"
    )
    lever_arm: Real | None = Field(
        default=None,
        gt=0,
        description=(
            "oscillating followers: distance from the arm pivot to the spring's line of action, mm (the spring's "
            "rate is torsion_rate / lever_arm^2)"
        ),
    )
    max_active_coils: Real | None = Field(
        default=None,
        ge=3,
        le=200,
        description="most active coils the design may use (default 15, Shigley's 3 <= N_a <= 15)",
    )
    model: Literal["lumped", "surge"] = Field(
        default="lumped",
        description=(
            "the spring in the dynamics: lumped (a third of its mass moves with the follower, or the valve of a "
            "[valvetrain]) | surge (a chain of masses)"
        ),
    )

    @field_validator("material")
    @classmethod
    def _known_material(cls, name: str) -> str:
        if name not in WIRE_NAMES:
            raise ValueError(unknown_name("spring material", name, WIRE_NAMES))
        return name


def check_spring_keys(spring: SpringSpec | None, *, kind: FollowerKind, key: str = "spring") -> None:
    """Raise ``ValueError("<key>.lever_arm: ...")`` unless ``lever_arm`` is given exactly for a rotary kind (an arm)."""
    if spring is None:
        return
    if kind.rotary and spring.lever_arm is None:
        raise ValueError(
            f"{key}.lever_arm: required for {kind.a} follower: the distance from the arm pivot to the spring, mm"
        )
    if not kind.rotary and spring.lever_arm is not None:
        raise ValueError(f"{key}.lever_arm: not used by a translating follower (the spring acts along its axis)")
