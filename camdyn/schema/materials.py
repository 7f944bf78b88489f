"""The ``[materials]`` table: the elastic constants of the cam and the follower (roller or flat face)."""

from __future__ import annotations

from typing import Any

from pydantic import Field, field_validator

from .._core.materials import ELASTIC, unknown_name
from ._base import Real, Table

MATERIAL_NAMES: tuple[str, ...] = tuple(ELASTIC)
_EITHER = f"a name ({', '.join(MATERIAL_NAMES)}; Shigley Table A-5) or {{ elastic_modulus = GPa, poisson_ratio = nu }}"


class ElasticSpec(Table):
    """A material's elastic constants (a named material is turned into these)."""

    elastic_modulus: Real = Field(gt=0, description="Young's modulus E, GPa")
    poisson_ratio: Real = Field(ge=0, lt=0.5, description="Poisson's ratio nu")


class MaterialsSpec(Table):
    """The ``[materials]`` table: each body by name or by its constants."""

    cam: ElasticSpec = Field(
        default=ElasticSpec(elastic_modulus=ELASTIC["steel"][0], poisson_ratio=ELASTIC["steel"][1]),
        description=f"the cam: {_EITHER} (default steel)",
    )
    follower: ElasticSpec = Field(
        default=ElasticSpec(elastic_modulus=ELASTIC["steel"][0], poisson_ratio=ELASTIC["steel"][1]),
        description=f"the roller or flat face: {_EITHER} (default steel)",
    )

    @field_validator("cam", "follower", mode="before")
    @classmethod
    def _by_name(cls, value: Any) -> Any:
        if isinstance(value, str):
            if value not in ELASTIC:
                raise ValueError(unknown_name("material", value, MATERIAL_NAMES))
            e, nu = ELASTIC[value]
            return {"elastic_modulus": e, "poisson_ratio": nu}
        if not isinstance(value, dict | ElasticSpec):
            raise ValueError(f"give {_EITHER}")
        return value
