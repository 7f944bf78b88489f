"""A machine file: many cams on one main shaft, each a case file of its own, phased by a timing diagram.

```toml
name = "cartoner"
speed = 100                 # main-shaft rpm
[[cam]]
case = "infeed.toml"        # a case file, relative to this file
phase = 0                   # deg: the machine angle at which this cam's angle is 0
[[clearance]]               # optional: two followers that share space
between = ["infeed", "gripper"]
gap = 60                    # mm between them with both at lift 0
closes = [1.0, 1.0]         # mm the gap closes per unit of each follower's lift (mm, or deg of an arm)
min_gap = 5                 # mm
[drive]
speed_fluctuation = 0.05
```

:func:`load_machine` reads the machine file and every case file it names, and validates all of them before any
model is built; every problem is one :class:`InputError` naming the key (and, in a case file, that file).
"""

from __future__ import annotations

from dataclasses import dataclass
from difflib import get_close_matches
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from .._core.errors import CamdynError, InputError
from .._core.outputs import safe_stem
from .._core.units import MAX_LENGTH_MM, MAX_SPEED_RPM
from . import load_case_spec, read_toml
from ._base import Name, Real, Table, Text, parse
from .case import CaseSpec
from .drive import DriveSpec

MACHINE_SCHEMA_VERSION = 1


class MachineCamSpec(Table):
    """One ``[[cam]]``: a case file on the main shaft and its phase."""

    case: Name = Field(min_length=1, description="the cam's case file, relative to the machine file")
    phase: Real = Field(
        default=0.0,
        ge=-360,
        le=360,
        description="machine angle (deg) at which this cam's angle is 0: the cam angle is the machine angle less "
        "the phase",
    )
    name: Name | None = Field(
        default=None,
        min_length=1,
        description="the cam's name in the machine (default: its case's name); unique in the machine, it names "
        "the CSV column",
    )


class ClearanceSpec(Table):
    """One ``[[clearance]]``: two followers that share space and the gap they need, along a line they share.

    The gap is ``gap - closes[0] * s_a - closes[1] * s_b`` at every machine angle, with ``s`` each follower's lift
    from its cam's angle 0 (mm; an arm's swing in deg)."""

    between: tuple[Name, Name] = Field(description="the two cams' names (as the machine names them)")
    gap: Real = Field(
        ge=-MAX_LENGTH_MM, le=MAX_LENGTH_MM, description="gap between the two followers (mm) with both at lift 0"
    )
    closes: tuple[Real, Real] = Field(
        default=(1.0, 1.0),
        description="mm the gap closes per mm of each follower's lift (per deg of an arm's swing); negative where "
        "the lift opens it",
    )
    min_gap: Real = Field(ge=0, le=MAX_LENGTH_MM, description="the least gap the two need over a revolution, mm")

    @model_validator(mode="after")
    def _two_cams(self) -> ClearanceSpec:
        if self.between[0] == self.between[1]:
            raise ValueError(f"between: name two different cams (got {self.between[0]!r} twice)")
        return self


class MachineSpec(Table):
    """A machine file: the main-shaft speed, the ``[[cam]]`` list, optional ``[[clearance]]`` and ``[drive]``."""

    version: Literal[1] = Field(default=MACHINE_SCHEMA_VERSION, description="machine-file schema version (1)")
    name: Name | None = Field(
        default=None, description="machine name, used in reports and output file names (default: the file name)"
    )
    description: Text = Field(default="", description="one line on what the machine is")
    speed: Real = Field(gt=0, le=MAX_SPEED_RPM, description="main-shaft speed, rpm: every cam is checked at it")
    cam: list[MachineCamSpec] = Field(min_length=1, description="the cams on the main shaft")
    clearance: list[ClearanceSpec] = Field(
        default=[], description="pairs of followers that share space and the gap they need"
    )
    drive: DriveSpec = Field(
        default=DriveSpec(), description="the main-shaft drive: speed fluctuation for the flywheel"
    )


@dataclass(frozen=True)
class MachineCamFile:
    """A ``[[cam]]`` with its case file read: the cam's name, the path and the validated case."""

    name: str
    path: Path
    phase_deg: float
    spec: CaseSpec


@dataclass(frozen=True)
class MachineFile:
    """A validated machine file and the validated case of every cam on it."""

    source: Path
    spec: MachineSpec
    cams: tuple[MachineCamFile, ...]

    @property
    def name(self) -> str:
        return self.spec.name or self.source.stem


def machine_stem(name: str) -> str:
    """The stem of a machine's output files, ``<machine>-machine``: the name is data, never a path."""
    return f"{safe_stem(name)}-machine"


def _case_spec(i: int, cam: MachineCamSpec, folder: Path) -> tuple[Path, CaseSpec]:
    """The ``i``-th cam's case file, read and validated; an error names the cam, its file and the key."""
    path = folder / cam.case
    try:
        return path, load_case_spec(path)
    except CamdynError as err:
        where = f"cam[{i}].case {cam.case}" + (f": {err.where}" if err.where else "")
        raise InputError(where, err.message) from None


def load_machine(path: str | Path) -> MachineFile:
    """Read and validate a machine file and every case file it names (relative to it): one :class:`InputError`
    naming the key for any problem, before any model is built."""
    path = Path(path)
    spec = parse(MachineSpec, read_toml(path))
    cams = []
    seen: dict[str, int] = {}
    for i, cam in enumerate(spec.cam):
        case_path, case = _case_spec(i, cam, path.parent)
        name = cam.name or case.name or case_path.stem
        stem = safe_stem(name)
        if stem in seen:
            raise InputError(
                f"cam[{i}].name", f"{name!r} is also the name of cam[{seen[stem]}]: give each cam its own name"
            )
        seen[stem] = i
        cams.append(MachineCamFile(name, case_path, float(cam.phase), case))
    names = {c.name for c in cams}
    for i, gap in enumerate(spec.clearance):
        for who in gap.between:
            if who not in names:
                hint = get_close_matches(who, sorted(names), n=1)
                also = f" (did you mean {hint[0]!r}?)" if hint else f" (cams: {', '.join(sorted(names))})"
                raise InputError(f"clearance[{i}].between", f"no cam named {who!r}{also}")
    return MachineFile(path, spec, tuple(cams))
