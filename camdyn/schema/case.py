"""A whole case file: its tables and the rules between them."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from .._core.kinds import TRANSLATING, FollowerKind
from ._base import Name, Table, Text
from .drive import DriveSpec
from .dynamics import DynamicsSpec, check_dynamics_keys
from .follower import FollowerSpec
from .limits import LimitsSpec
from .materials import MaterialsSpec
from .mechanism import MechanismSpec
from .motion import MotionSpec, check_segments
from .path import PathSpec
from .spring import SpringSpec, check_spring_keys
from .tolerances import TolerancesSpec, check_tolerance_keys
from .valvetrain import ValvetrainSpec, check_valvetrain_keys

SCHEMA_VERSION = 1


class CaseSpec(Table):
    """A case file: ``[motion]`` and ``[follower]``, or ``[path]`` and ``[mechanism]``; then ``[dynamics]`` and
    ``[limits]``; optionally ``[spring]``, ``[materials]`` and ``[drive]``."""

    version: Literal[1] = Field(default=SCHEMA_VERSION, description="case-file schema version (1)")
    name: Name | None = Field(
        default=None, description="case name, used in reports and output file names (default: the file name)"
    )
    description: Text = Field(default="", description="one line on what the case is")
    optimized_from: Text | None = Field(
        default=None,
        description=(
            "the case file this one was reshaped from, relative to this file (camdyn optimize writes it; the "
            "report's optimization page compares the two)"
        ),
    )
    motion: MotionSpec | None = Field(
        default=None, description="the follower motion as segments or a lift table (with [follower])"
    )
    follower: FollowerSpec | None = Field(
        default=None,
        description="the follower and cam dimensions (with [motion]), or the follower and the cam's contour (alone)",
    )
    path: PathSpec | None = Field(
        default=None, description="a closed path to trace (with [mechanism]): the motion and follower are synthesized"
    )
    mechanism: MechanismSpec | None = Field(default=None, description="the cam-linkage that traces [path]")
    dynamics: DynamicsSpec = Field(description="speed, mass, spring, damping")
    limits: LimitsSpec = Field(default=LimitsSpec(), description="what a passing design must meet")
    spring: SpringSpec | None = Field(
        default=None, description="the return spring as a part: wire material, bore, installed length, end type"
    )
    materials: MaterialsSpec = Field(
        default=MaterialsSpec(), description="elastic constants of the cam and the follower, for the contact stress"
    )
    drive: DriveSpec = Field(default=DriveSpec(), description="the camshaft drive: speed fluctuation for the flywheel")
    tolerances: TolerancesSpec | None = Field(
        default=None, description="how far a built cam may differ from the case (camdyn tolerance)"
    )
    valvetrain: ValvetrainSpec | None = Field(
        default=None,
        description="the follower drives a valve: rocker ratio, lash, the cam-side and valve masses, the seat",
    )

    @model_validator(mode="after")
    def _tables_fit_together(self) -> CaseSpec:
        if self.motion is not None and (self.path is not None or self.mechanism is not None):
            raise ValueError("motion: give either [motion] segments or [path] and [mechanism], not both")
        if self.motion is not None:
            if self.follower is None:
                raise ValueError("follower: the [follower] table is required with [motion]")
            if self.follower.contour is not None:
                raise ValueError("motion: a contour case derives its motion from [follower] contour: remove [motion]")
            if self.motion.segments:
                check_segments(self.motion.segments, self.follower.kind.lift_unit, key="motion.segments")
        elif self.follower is not None and self.follower.contour is not None:
            if self.path is not None or self.mechanism is not None:
                raise ValueError("follower.contour: give either a contour or [path] and [mechanism], not both")
        elif self.path is not None or self.mechanism is not None:
            if self.path is None or self.mechanism is None:
                raise ValueError(
                    f"{'path' if self.path is None else 'mechanism'}: a path case needs both [path] and [mechanism]"
                )
            if self.follower is not None:
                raise ValueError("follower: a path case gets its follower from the synthesis: remove [follower]")
        else:
            raise ValueError(
                "motion: the case needs [motion] segments or a table, a [follower] contour, or [path] and [mechanism]"
            )
        if self.motion is not None and self.motion.valve_table is not None and self.valvetrain is None:
            raise ValueError("motion.valve_table: a lift at the valve needs [valvetrain] (its ratio and lash)")
        if self.valvetrain is not None and self.follower is not None and self.follower.form_closed:
            raise ValueError("follower.closure: a valvetrain is spring-closed: remove closure (or [valvetrain])")
        if self.valvetrain is not None:
            check_valvetrain_keys(self.valvetrain, self.dynamics, translating=not self.oscillating)
        else:
            form_closed = self.follower is not None and self.follower.form_closed
            check_dynamics_keys(self.dynamics, kind=self.kind, form_closed=form_closed)
        check_spring_keys(self.spring, kind=self.kind)
        vt = self.valvetrain
        check_tolerance_keys(
            self.tolerances, kind=self.kind, valvetrain=vt is not None, rigid_train=vt is None or vt.stiffness is None
        )
        if self.tolerances is not None and self.tolerances.backlash is not None:
            f = self.follower
            if f is None or not f.form_closed or f.pair_preload > 0.0:
                raise ValueError(
                    'tolerances.backlash: only a groove cam ([follower] closure = "groove") or conjugate cams without '
                    "a preload have a backlash"
                )
        if self.limits.max_contact_stress is not None and self.contact_width_mm is None:
            where = "follower" if self.follower is not None else "mechanism"
            raise ValueError(
                f"limits.max_contact_stress: the contact stress needs the contact width: give [{where}] width, mm"
            )
        return self

    @property
    def kind(self) -> FollowerKind:
        """The follower's kind: the ``[follower]``'s, or that of the follower the ``[mechanism]`` drives."""
        if self.follower is not None:
            return self.follower.kind
        return self.mechanism.kind if self.mechanism is not None else TRANSLATING

    @property
    def oscillating(self) -> bool:
        """Whether the follower is an oscillating arm (its motion in rad, its dynamics rotational)."""
        return self.kind.rotary

    @property
    def contact_width_mm(self) -> float | None:
        """The contact width along the camshaft axis, mm (``[follower] width`` or ``[mechanism] width``); None
        where the case gives none (no contact stress then)."""
        table = self.follower if self.follower is not None else self.mechanism
        return None if table is None else table.width

    @property
    def data_files(self) -> tuple[str, ...]:
        """The data files the case names (``[motion] table`` or ``valve_table``, ``[follower] contour``), relative to
        the case file."""
        names = (getattr(getattr(self, table), key, None) for table, key in DATA_FILE_KEYS)
        return tuple(name for name in names if name is not None)


# the keys whose values name a data file, relative to the case file's folder: (table, key)
DATA_FILE_KEYS = (("motion", "table"), ("motion", "valve_table"), ("follower", "contour"))


def moved_data_files(doc: dict, source: Path, destination: Path) -> dict:
    """A case file's document ``doc``, read from folder ``source``, as a case file written into folder
    ``destination`` needs it: each data file it names by a relative path named relative to ``destination``."""
    out = dict(doc)
    for table, key in DATA_FILE_KEYS:
        name = out.get(table, {}).get(key)
        if isinstance(name, str) and not Path(name).is_absolute():
            where = os.path.relpath((source / name).resolve(), destination.resolve())
            out[table] = {**out[table], key: Path(where).as_posix()}
    return out
