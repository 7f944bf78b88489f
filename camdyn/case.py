"""Case files (TOML): schema, validation with one-line errors, and the :class:`Case` every command reads.

Units in case files: lengths mm, angles deg, speed rpm, mass kg, force N, stiffness N/mm; oscillating
followers use the rotational equivalent (inertia kg*m^2, torsion rate N*m/rad, torque N*m).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from difflib import get_close_matches
from pathlib import Path
from typing import Any

import jax.numpy as jnp
import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from .errors import InputError
from .geometry import FollowerSpec
from .motion import Motion, Program

_STRICT = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)


class SegmentSpec(BaseModel):
    """One motion segment: ``law`` up to ``end`` (deg), rising by ``lift`` (mm; deg of arm swing for an
    oscillating follower; negative for a return)."""

    model_config = _STRICT
    law: str
    end: float
    lift: float = 0.0


class MotionSpec(BaseModel):
    """The ``[motion]`` table."""

    model_config = _STRICT
    segments: list[SegmentSpec] = Field(min_length=1)


class DynamicsSpec(BaseModel):
    """The ``[dynamics]`` table. Translating followers use the linear keys, oscillating the rotational ones."""

    model_config = _STRICT
    speed: float = Field(gt=0, description="cam speed, rpm")
    # translating follower
    mass: float | None = Field(default=None, gt=0, description="equivalent moving mass, kg")
    spring_rate: float | None = Field(default=None, gt=0, description="return spring rate k, N/mm")
    preload: float | None = Field(default=None, description="spring force at zero lift F0, N")
    train_stiffness: float | None = Field(default=None, gt=0, description="follower-train stiffness k_f, N/mm; omit: rigid")
    external_force: float = Field(default=0.0, description="constant force pushing the follower onto the cam, N")
    # oscillating follower (rotational equivalent)
    inertia: float | None = Field(default=None, gt=0, description="arm inertia about its pivot, kg*m^2")
    torsion_rate: float | None = Field(default=None, gt=0, description="return torsion spring rate, N*m/rad")
    preload_torque: float | None = Field(default=None, description="spring torque at zero swing, N*m")
    train_torsion_rate: float | None = Field(default=None, gt=0, description="follower-train stiffness, N*m/rad; omit: rigid")
    external_torque: float = Field(default=0.0, description="constant torque pushing the arm onto the cam, N*m")
    # both
    damping_ratio: float | None = Field(default=None, ge=0, description="zeta: c = 2 zeta sqrt(k m)")
    damping: float | None = Field(default=None, ge=0, description="c, N*s/m (N*m*s/rad for an oscillating arm)")
    train_damping_ratio: float = Field(default=0.05, ge=0, description="zeta_f: c_f = 2 zeta_f sqrt(k_f m)")
    restitution: float = Field(default=0.0, ge=0, le=1, description="coefficient of restitution at re-contact")

    @model_validator(mode="after")
    def _one_damping(self):
        if self.damping_ratio is not None and self.damping is not None:
            raise ValueError("give damping_ratio or damping, not both")
        return self


class LimitsSpec(BaseModel):
    """The ``[limits]`` table."""

    model_config = _STRICT
    speed_margin: float = Field(default=1.25, gt=0, description="jump speed / speed must be at least this")
    min_contact_force: float = Field(default=0.0, description="least interface force must exceed this, N")
    max_pressure_angle: float | None = Field(default=None, gt=0, lt=90, description="deg; default 30 translating, 35 oscillating")
    min_curvature_ratio: float = Field(default=1.5, gt=0, description="least contour radius of curvature / roller radius")


class CaseSpec(BaseModel):
    """A whole case file."""

    model_config = _STRICT
    name: str | None = None
    description: str = ""
    motion: MotionSpec | None = None
    follower: FollowerSpec | None = None
    path: dict[str, Any] | None = None
    mechanism: dict[str, Any] | None = None
    dynamics: DynamicsSpec
    limits: LimitsSpec = LimitsSpec()


@dataclass(frozen=True)
class Case:
    """A validated case: the motion, the follower, the dynamic model and the limits."""

    name: str
    source: Path | None
    spec: CaseSpec
    motion: Motion
    follower: FollowerSpec | None
    model: Any  # dynamics.FollowerModel
    synthesis: Any = None  # linkage.Synthesis for path cases
    warnings: tuple[str, ...] = field(default=())

    @property
    def speed_rpm(self) -> float:
        return self.spec.dynamics.speed

    @property
    def limits(self) -> LimitsSpec:
        return self.spec.limits

    @property
    def oscillating(self) -> bool:
        return self.motion.unit == "rad"


# ------------------------------------------------------------------------------------- errors
def _model_at(model: type[BaseModel], loc: tuple) -> type[BaseModel] | None:
    """The pydantic model that owns the key at ``loc`` (to suggest the nearest valid key)."""
    for part in loc[:-1]:
        if isinstance(part, int) or model is None:
            continue
        ann = model.model_fields.get(part)
        if ann is None:
            return None
        cand = [t for t in getattr(ann.annotation, "__args__", (ann.annotation,)) if isinstance(t, type) and issubclass(t, BaseModel)]
        if not cand:
            args = getattr(ann.annotation, "__args__", ())
            cand = [a for t in args for a in getattr(t, "__args__", ()) if isinstance(a, type) and issubclass(a, BaseModel)]
        model = cand[0] if cand else None
    return model


def _where(loc: tuple) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def validation_error(err: ValidationError, cls: type[BaseModel] = CaseSpec, table: str = "") -> InputError:
    """The first problem of a pydantic validation as one :class:`InputError` naming the key (prefixed with
    ``table``, e.g. ``path.width``), with the nearest valid key for an unknown one."""
    e = err.errors()[0]
    loc = tuple(p for p in e["loc"] if not (isinstance(p, str) and ("[" in p or p.startswith("function-"))))
    msg = e["msg"].removeprefix("Value error, ")
    if table and not loc and ":" in msg:  # a table-level validator names its key: "key: message"
        key, msg = msg.split(":", 1)
        loc, msg = (key.strip(),), msg.strip()
    where = ".".join(filter(None, (table, _where(loc)))) or "case"
    if e["type"] == "extra_forbidden":
        owner = _model_at(cls, loc)
        hint = get_close_matches(str(loc[-1]), list(owner.model_fields), n=1) if owner else []
        valid = f"; valid keys: {', '.join(owner.model_fields)}" if owner and not hint else ""
        return InputError(where, "unknown key" + (f" (did you mean {hint[0]!r}?)" if hint else "") + valid)
    if e["type"] == "missing":
        return InputError(where, "required key is missing")
    if "input" in e and not isinstance(e["input"], dict | list):
        msg += f" (got {e['input']!r})"
    return InputError(where, msg)


# ------------------------------------------------------------------------------------ loading
def read_toml(path: str | Path) -> dict:
    """The parsed TOML of a case (or path) file; :class:`InputError` for a missing file or bad TOML."""
    try:
        return tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError("", "no such file") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError("TOML", str(err)) from None


def load_case(path: str | Path) -> Case:
    """Read, validate and build a case file. Raises :class:`InputError` (one line) on any problem."""
    return case_from_dict(read_toml(path), source=Path(path))


def case_from_dict(raw: dict, source: Path | None = None) -> Case:
    """Validate a parsed case (the TOML as a dict) and build the :class:`Case`."""
    try:
        spec = CaseSpec.model_validate(raw)
    except ValidationError as err:
        raise validation_error(err) from None
    name = spec.name or (source.stem if source else "case")
    warnings: list[str] = []
    synthesis = None
    if spec.motion is not None and (spec.path is not None or spec.mechanism is not None):
        raise InputError("motion", "give either [motion] segments or [path] and [mechanism], not both")
    if spec.motion is not None:
        if spec.follower is None:
            raise InputError("follower", "the [follower] table is required with [motion]")
        motion = Program.from_segments([s.model_dump() for s in spec.motion.segments], unit="rad" if spec.follower.type.startswith("oscillating") else "mm")
        follower = spec.follower
        warnings += motion.continuity_warnings()
    elif spec.path is not None or spec.mechanism is not None:
        if spec.path is None or spec.mechanism is None:
            raise InputError("path" if spec.path is None else "mechanism", "a path case needs both [path] and [mechanism]")
        if spec.follower is not None:
            raise InputError("follower", "a path case gets its follower from the synthesis: remove [follower]")
        from .linkage import synthesize_motion

        synthesis = synthesize_motion(spec.path, spec.mechanism)
        motion, follower = synthesis.tabulated, synthesis.follower
        warnings += list(synthesis.warnings)
    else:
        raise InputError("motion", "the case needs [motion] segments, or [path] and [mechanism]")
    model = follower_model(spec.dynamics, oscillating=motion.unit == "rad")
    _check_holds_at_rest(motion, model, spec.dynamics, motion.unit == "rad")
    return Case(name, source, spec, motion, follower, model, synthesis, tuple(warnings))


_LINEAR = ("mass", "spring_rate", "preload", "train_stiffness")
_ROTARY = ("inertia", "torsion_rate", "preload_torque", "train_torsion_rate")


def follower_model(d: DynamicsSpec, *, oscillating: bool):
    """SI follower parameters from the ``[dynamics]`` table (N/mm -> N/m for translating followers)."""
    from .dynamics import FollowerModel

    use, other = (_ROTARY, _LINEAR) if oscillating else (_LINEAR, _ROTARY)
    kind = "an oscillating" if oscillating else "a translating"
    for k_use, k_other in zip(use, other, strict=True):
        if getattr(d, k_other) is not None:
            raise InputError(f"dynamics.{k_other}", f"{kind} follower uses {k_use}, not {k_other}")
    if oscillating and d.external_force:
        raise InputError("dynamics.external_force", "an oscillating follower uses external_torque (N*m)")
    if not oscillating and d.external_torque:
        raise InputError("dynamics.external_torque", "a translating follower uses external_force (N)")
    for k in use[:3]:
        if getattr(d, k) is None:
            raise InputError(f"dynamics.{k}", "required key is missing")
    to_si = 1.0 if oscillating else 1e3  # N/mm -> N/m
    m = d.inertia if oscillating else d.mass
    k = (d.torsion_rate if oscillating else d.spring_rate) * to_si
    f0 = d.preload_torque if oscillating else d.preload
    kf_in = d.train_torsion_rate if oscillating else d.train_stiffness
    kf = math.inf if kf_in is None else kf_in * to_si
    c = d.damping if d.damping is not None else 2.0 * (d.damping_ratio or 0.0) * math.sqrt(k * m)
    cf = 0.0 if math.isinf(kf) else 2.0 * d.train_damping_ratio * math.sqrt(kf * m)
    ext = d.external_torque if oscillating else d.external_force
    vals = (m, k, f0, c, ext, kf, cf, d.restitution)
    return FollowerModel(*(jnp.asarray(float(v)) for v in vals), scale=1.0 if oscillating else 1e-3)


def _check_holds_at_rest(motion: Motion, model, d: DynamicsSpec, oscillating: bool) -> None:
    theta_deg = np.arange(3600) * 0.1
    vals = motion._eval(np, np.deg2rad(theta_deg)) if hasattr(motion, "_eval") else motion.sample(3600)[1]
    at_rest = float(model.stiffness) * vals[0] * model.scale + float(model.preload) + float(model.external)
    i = int(at_rest.argmin())
    if at_rest[i] <= 0.0:
        key, unit = ("dynamics.preload_torque", "N*m") if oscillating else ("dynamics.preload", "N")
        raise InputError(key, f"the spring cannot hold the follower on the cam even at rest: spring + external load is {at_rest[i]:.4g} {unit} at {theta_deg[i]:g} deg")
