"""The case-file schema: the only place that knows a case file's keys, their units and the rules between them.

One pydantic model per table (:class:`MotionSpec`, :class:`FollowerSpec`, :class:`DynamicsSpec`,
:class:`LimitsSpec`, :class:`PathSpec`, :class:`MechanismSpec`, :class:`SpringSpec`, :class:`MaterialsSpec`,
:class:`DriveSpec`), assembled into :class:`CaseSpec` (a case
file) and :class:`PathFileSpec` (the input of ``camdyn synthesize``). Validation happens once, here, and every
problem is one :class:`camdyn.InputError` naming the key. Nothing in this package imports JAX: a typo in a
case file is reported before any physics is loaded.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from .._core.errors import InputError
from .._core.files import check_file, data_file_path, read_text_file
from ._base import Table, parse, validation_error
from .case import DATA_FILE_KEYS, SCHEMA_VERSION, CaseSpec, moved_data_files
from .drive import DriveSpec
from .dynamics import LINEAR_KEYS, ROTARY_KEYS, DynamicsSpec, dynamics_keys
from .follower import FOLLOWER_TYPES, FollowerSpec
from .limits import LimitsSpec
from .materials import MATERIAL_NAMES, ElasticSpec, MaterialsSpec
from .mechanism import MechanismSpec
from .motion import LAW_NAMES, MotionSpec, SegmentSpec, check_segments
from .path import PATH_TYPES, PathSpec
from .pathfile import PathFileSpec, SynthesisSpec
from .spring import END_TYPES, SPRING_MODELS, SpringSpec
from .tolerances import (
    DISTRIBUTIONS,
    TOLERANCE_KEYS,
    Tolerance,
    TolerancesSpec,
    ToleranceValue,
    require_tolerances,
    resolve_tolerances,
)
from .valvetrain import RockerSpec, ValvetrainSpec

__all__ = [
    "CaseSpec",
    "DATA_FILE_KEYS",
    "DriveSpec",
    "DynamicsSpec",
    "END_TYPES",
    "ElasticSpec",
    "MATERIAL_NAMES",
    "MaterialsSpec",
    "SPRING_MODELS",
    "SpringSpec",
    "FOLLOWER_TYPES",
    "FollowerSpec",
    "LAW_NAMES",
    "LINEAR_KEYS",
    "LimitsSpec",
    "MechanismSpec",
    "MotionSpec",
    "PATH_TYPES",
    "PathFileSpec",
    "PathSpec",
    "ROTARY_KEYS",
    "SCHEMA_VERSION",
    "SegmentSpec",
    "SynthesisSpec",
    "Table",
    "check_segments",
    "dynamics_keys",
    "load_case_spec",
    "load_path_file",
    "moved_data_files",
    "parse",
    "read_toml",
    "validation_error",
    "DISTRIBUTIONS",
    "TOLERANCE_KEYS",
    "Tolerance",
    "TolerancesSpec",
    "ToleranceValue",
    "require_tolerances",
    "resolve_tolerances",
    "RockerSpec",
    "ValvetrainSpec",
]


def read_toml(path: str | Path) -> dict:
    """The parsed TOML of a case (or path) file; :class:`InputError` for a file that is missing, not a regular
    file, too large, not UTF-8 text, or not TOML (:func:`~camdyn._core.files.read_text_file`). A UTF-8 byte-order
    mark is accepted."""
    text = read_text_file(Path(path), "", "case file")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError("TOML", str(err)) from None


def load_case_spec(path: str | Path) -> CaseSpec:
    """Read and validate a case file; every problem is one :class:`InputError` naming the key, and a data file it
    names that is missing (or cannot be one) is refused here too, before any model is built."""
    spec = parse(CaseSpec, read_toml(path))
    for name in spec.data_files:
        check_file(data_file_path(name, Path(path)), name, "data file")
    return spec


def load_path_file(path: str | Path) -> PathFileSpec:
    """Read and validate a path file (the input of ``camdyn synthesize``)."""
    return parse(PathFileSpec, read_toml(path))
