"""A path file: the input of ``camdyn synthesize`` (a case file without ``[mechanism]``, with ``[synthesis]``)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from .._core.units import MAX_LENGTH_MM
from ._base import Name, Real, Table, Text
from .case import SCHEMA_VERSION
from .dynamics import ROTARY_KEYS, DynamicsSpec
from .limits import LimitsSpec
from .path import PathSpec


class SynthesisSpec(Table):
    """The ``[synthesis]`` table of a path file: options of the dimensional synthesis."""

    seed: int = Field(default=0, ge=0, description="random seed of the optimizer (the same seed gives the same design)")
    maxiter: int = Field(
        default=200,
        ge=1,
        le=100000,
        description="most generations of differential evolution (each: the CCM and the four-bar comparison)",
    )
    popsize: int = Field(default=15, ge=5, le=1000, description="population per free dimension")
    max_pressure_angle: Real | None = Field(
        default=None,
        gt=0,
        lt=80,
        description="deg, the cam is sized for it; default: [limits] max_pressure_angle, else 30",
    )
    roller_radius: Real = Field(default=10.0, gt=0, le=MAX_LENGTH_MM, description="follower roller radius, mm")
    fourbar: bool = Field(
        default=True, description="also fit the best plain four-bar to the path (the CCM paper's comparison)"
    )


class PathFileSpec(Table):
    """A whole path file (the input of ``camdyn synthesize``)."""

    version: Literal[1] = Field(default=SCHEMA_VERSION, description="path-file schema version (1)")
    name: Name | None = Field(default=None, description="case name (default: the output file name)")
    description: Text = Field(default="", description="one line on what the case is")
    path: PathSpec | None = Field(default=None, description="the closed curve to trace (required)")
    dynamics: DynamicsSpec | None = Field(
        default=None, description="speed, mass, spring_rate (required); preload is sized when left out"
    )
    limits: LimitsSpec = Field(default=LimitsSpec(), description="what a passing design must meet")
    synthesis: SynthesisSpec = Field(default=SynthesisSpec(), description="optimizer options")

    @model_validator(mode="before")
    @classmethod
    def _no_mechanism(cls, raw: Any) -> Any:
        if isinstance(raw, dict) and "mechanism" in raw:
            raise ValueError(
                "mechanism: a path file has no [mechanism] table: camdyn synthesize chooses it (remove it, or run "
                "camdyn check on a case file)"
            )
        return raw

    @model_validator(mode="after")
    def _complete(self) -> PathFileSpec:
        if self.path is None:
            raise ValueError(
                "path: the [path] table is required: the closed curve the tracing point must follow (type = "
                "ellipse, circle, rectangle, eight, line, racetrack or points)"
            )
        if self.dynamics is None:
            raise ValueError(
                "dynamics: the [dynamics] table is required: give at least speed (rpm), mass (kg) and spring_rate "
                "(N/mm); preload (N) is sized when left out"
            )
        d = self.dynamics
        for key in ROTARY_KEYS:
            if getattr(d, key) not in (None, 0.0):
                raise ValueError(
                    f"dynamics.{key}: the synthesized CCM has a translating follower: use mass, spring_rate, "
                    "preload, train_stiffness"
                )
        for key, what in (
            ("mass", "the slider's moving mass, kg"),
            ("spring_rate", "the return spring's rate, N/mm (the preload may be left out: it is then sized)"),
        ):
            if getattr(d, key) is None:
                raise ValueError(f"dynamics.{key}: required key is missing: {what}")
        s = self.synthesis
        if (
            s.max_pressure_angle is not None
            and self.limits.max_pressure_angle is not None
            and s.max_pressure_angle > self.limits.max_pressure_angle
        ):
            raise ValueError(
                f"synthesis.max_pressure_angle: {s.max_pressure_angle:g} deg exceeds [limits] max_pressure_angle = "
                f"{self.limits.max_pressure_angle:g} deg: the case would fail its own check"
            )
        return self
