"""The ``[tolerances]`` table: how far a built cam may differ from its case file, for ``camdyn tolerance``.

Each key is a tolerance: a percentage of the case's value (``"10%"``), an absolute value with a unit
(``"2 N"``, ``"0.2 N/mm"``), or a bare number in the key's case-file unit. ``profile_error`` is absolute only
(mm; rad for an oscillating arm): the RMS of a random smooth lift error made of low harmonics. A key is
either such a value or an inline table ``{value = "10%", distribution = "uniform"}``; the table-wide
``distribution`` is the default of every key: ``normal`` (the tolerance is 3 sigma) or ``uniform`` (the
tolerance is the half-width). For ``profile_error`` the value is the RMS whatever the distribution (the
harmonic amplitudes are normal or uniform with that variance).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Annotated, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from .._core.errors import InputError
from .._core.kinds import FollowerKind
from .._core.units import TOLERANCE_UNITS, VALVETRAIN_TOLERANCE_KEYS, tolerance_to_case_unit
from ._base import Real, Table

TOLERANCE_KEYS = tuple(TOLERANCE_UNITS)
DISTRIBUTIONS = ("normal", "uniform")
_VALUE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(%|[A-Za-z*/^0-9]+)?\s*$")


class ToleranceValue(Table):
    """One tolerance with its own distribution: ``{value = "10%", distribution = "uniform"}``."""

    value: str | Real = Field(description='the tolerance: "10%", "2 N" or a number in the key\'s unit')
    distribution: Literal["normal", "uniform"] | None = Field(
        default=None,
        description="normal (tolerance = 3 sigma) | uniform (tolerance = half-width); default: the table's",
    )


def _kind(raw) -> str:
    return "table" if isinstance(raw, dict | ToleranceValue) else ("text" if isinstance(raw, str) else "number")


# a tolerance: an inline table, a text ("10%", "2 N") or a number; the tag picks which, so an error names the key
Tol = Annotated[
    Annotated[ToleranceValue, Tag("table")] | Annotated[str, Tag("text")] | Annotated[Real, Tag("number")],
    Discriminator(_kind),
]
_HELP = ': "10%", "{u}" or a number ({u0}); or {{value = ..., distribution = "uniform"}}'


class TolerancesSpec(Table):
    """The ``[tolerances]`` table (every key optional; a missing key is no tolerance)."""

    spring_rate: Tol | None = Field(
        default=None, description="spring rate tolerance" + _HELP.format(u="0.2 N/mm", u0="N/mm; N*m/rad for an arm")
    )
    preload: Tol | None = Field(
        default=None, description="preload tolerance" + _HELP.format(u="2 N", u0="N; N*m for an arm")
    )
    mass: Tol | None = Field(
        default=None, description="moving mass tolerance" + _HELP.format(u="0.01 kg", u0="kg; kg*m^2 for an arm")
    )
    train_stiffness: Tol | None = Field(
        default=None,
        description="follower-train stiffness tolerance" + _HELP.format(u="100 N/mm", u0="N/mm; N*m/rad for an arm"),
    )
    speed: Tol | None = Field(default=None, description="cam speed tolerance" + _HELP.format(u="6 rpm", u0="rpm"))
    profile_error: Tol | None = Field(
        default=None,
        description=(
            "RMS of a random smooth lift error (harmonics 1-8), absolute only: mm (rad for an arm), e.g. 0.005 or "
            '"5 um"'
        ),
    )
    lash: Tol | None = Field(
        default=None,
        description="[valvetrain] cases: valve lash tolerance at the valve" + _HELP.format(u="0.05 mm", u0="mm"),
    )
    cam_side_mass: Tol | None = Field(
        default=None,
        description="[valvetrain] cases: cam-side mass tolerance" + _HELP.format(u="5 g", u0="kg"),
    )
    valve_mass: Tol | None = Field(
        default=None,
        description="[valvetrain] cases: valve-side mass tolerance" + _HELP.format(u="5 g", u0="kg"),
    )
    valvetrain_stiffness: Tol | None = Field(
        default=None,
        description=(
            "[valvetrain] cases: tolerance of the train's stiffness between the two masses (valvetrain.stiffness)"
            + _HELP.format(u="500 N/mm", u0="N/mm")
        ),
    )
    backlash: Tol | None = Field(
        default=None,
        description=(
            "a groove cam's (or unpreloaded conjugate cams') backlash tolerance ([follower] closure = \"groove\" or "
            '"conjugate"): "20%", "10 um" or a number (mm); '
            "camdyn tolerance then gives the spread of the crossover impact speed"
        ),
    )
    distribution: Literal["normal", "uniform"] = Field(
        default="normal",
        description=(
            "default distribution of every key: normal (tolerance = 3 sigma) | uniform (tolerance = half-width)"
        ),
    )

    @model_validator(mode="after")
    def _values_parse(self) -> TolerancesSpec:
        for key in TOLERANCE_KEYS:
            raw = getattr(self, key)
            if raw is not None:
                _split(
                    key, raw.value if isinstance(raw, ToleranceValue) else raw
                )  # units are checked with the follower kind
        return self


@dataclass(frozen=True)
class Tolerance:
    """One tolerance resolved: relative (a fraction of the case's value) or absolute (in the case-file unit)."""

    key: str
    value: float  # fraction (relative) or case-file unit (absolute)
    relative: bool
    distribution: str  # "normal" | "uniform"


def _split(key: str, raw) -> tuple[float, str | None]:
    """(number, unit or "%" or None) of a tolerance; ValueError("key: message") for one that cannot be."""
    if isinstance(raw, bool):
        raise ValueError(f'{key}: expected a tolerance such as "10%" or a number, got {raw!r}')
    if isinstance(raw, int | float):
        number, unit = float(raw), None
    else:
        m = _VALUE.match(raw)
        if not m:
            raise ValueError(f'{key}: expected a tolerance such as "10%", "2 N" or a number, got {raw!r}')
        number, unit = float(m.group(1)), m.group(2)
    if not math.isfinite(number) or number < 0:
        raise ValueError(f"{key}: a tolerance must be zero or positive, got {raw!r}")
    if unit == "%" and key == "profile_error":
        raise ValueError(
            f"{key}: a percentage needs a scale and a profile error has none: give an RMS in mm (e.g. 0.005)"
        )
    if unit == "%" and number >= 100:
        raise ValueError(f"{key}: a relative tolerance must be under 100%, got {raw!r}")
    return number, unit


def require_tolerances(spec: TolerancesSpec | None, *, kind: FollowerKind, key: str = "tolerances") -> None:
    """InputError (at ``key``: ``--robust`` for optimize's option) where ``spec`` gives no tolerance: every built cam
    would be the case itself. A question of the file alone, so the command line asks it before JAX loads."""
    if spec is not None and any(getattr(spec, k) is not None for k in TOLERANCE_KEYS):
        return
    raise InputError(
        key,
        "the case gives no tolerances, so every built cam would be the case itself: add a [tolerances] table, "
        f'e.g. spring_rate = "10%" and preload = "{"0.2 N*m" if kind.rotary else "2 N"}" (docs/guide.md, '
        "camdyn tolerance)",
    )


def resolve_tolerances(spec: TolerancesSpec, *, kind: FollowerKind) -> tuple[Tolerance, ...]:
    """The given tolerances resolved, in :data:`TOLERANCE_KEYS` order; ValueError("key: message") for a unit the
    key does not take."""
    out = []
    for key in TOLERANCE_KEYS:
        raw = getattr(spec, key)
        if raw is None:
            continue
        dist = raw.distribution if isinstance(raw, ToleranceValue) and raw.distribution else spec.distribution
        number, unit = _split(key, raw.value if isinstance(raw, ToleranceValue) else raw)
        if unit == "%":
            out.append(Tolerance(key, number / 100.0, True, dist))
        else:
            try:
                value = number if unit is None else tolerance_to_case_unit(key, number, unit, kind.rotary)
            except ValueError as err:
                raise ValueError(f"{key}: {err}") from None
            out.append(Tolerance(key, value, False, dist))
    return tuple(out)


def check_tolerance_keys(
    spec: TolerancesSpec | None,
    *,
    kind: FollowerKind,
    key: str = "tolerances",
    valvetrain: bool = False,
    rigid_train: bool = True,
) -> None:
    """Raise ``ValueError("<key>.<name>: message")`` for a tolerance whose unit its follower kind does not take,
    a valvetrain's tolerance without ``[valvetrain]`` (``valvetrain``: the case has one; ``rigid_train``: its train
    has no stiffness), or a single follower's that a valvetrain replaces or does not model."""
    if spec is not None:
        given = [name for name in TOLERANCE_KEYS if getattr(spec, name) is not None]
        for name in given:
            if name in VALVETRAIN_TOLERANCE_KEYS and not valvetrain:
                raise ValueError(f"{key}.{name}: a valvetrain's tolerance needs [valvetrain]")
            if valvetrain and name == "mass":
                raise ValueError(f"{key}.mass: a valvetrain's masses are cam_side_mass and valve_mass")
            if valvetrain and name == "profile_error":
                raise ValueError(f"{key}.profile_error: not modelled on a valvetrain yet (the two-mass model)")
            if name == "valvetrain_stiffness" and rigid_train:
                raise ValueError(f"{key}.valvetrain_stiffness: the train is rigid: give valvetrain.stiffness")
        try:
            resolve_tolerances(spec, kind=kind)
        except ValueError as err:
            raise ValueError(f"{key}.{err}") from None
