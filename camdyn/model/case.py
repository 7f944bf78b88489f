"""A case built: the validated spec turned into its models, once (motion, follower geometry, dynamics)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._core.errors import InputError
from .._core.kinds import FollowerKind
from .._core.precision import require_x64
from .._core.units import M_PER_MM, MAX_ROCKER_RATIO, THETA_GRID
from ..schema import CaseSpec, FollowerSpec, LimitsSpec, ValvetrainSpec, dynamics_keys, load_case_spec, parse
from .dynamics import least_static_force
from .follower import FollowerModel, follower_model
from .geometry import ContourFit, check_assembly
from .motion import Motion, MotionFit, Program
from .sources import contour_motion, table_motion
from .surge import SpringInDynamics
from .valvetrain import (
    ValvetrainModel,
    coils_model,
    equivalent_follower,
    max_lifting_preload,
    rocker_model,
    rocker_reach,
    static_valve_lift,
    valvetrain_model,
)


@dataclass(frozen=True)
class Case:
    """A validated case and its models: the motion, the follower geometry, the dynamic model and the limits."""

    name: str
    source: Path | None
    spec: CaseSpec
    motion: Motion
    follower: FollowerSpec  # the case's, or the one a contour or a cam-linkage gives
    model: FollowerModel
    synthesis: Any = None  # linkage.Synthesis for path cases
    warnings: tuple[str, ...] = field(default=())
    fit: MotionFit | None = None  # a lift table's or a contour's fitted motion: its data and residuals
    contour: ContourFit | None = None  # a contour case's outline: its points, fit and radial residuals
    spring: SpringInDynamics | None = (
        None  # the spring's mass in ``model``, once resolved (design.parts.resolve_spring)
    )
    valvetrain: ValvetrainModel | None = None  # [valvetrain]: the two-mass model; ``model`` is its equivalent follower

    @property
    def speed_rpm(self) -> float:
        return self.spec.dynamics.speed

    @property
    def limits(self) -> LimitsSpec:
        return self.spec.limits

    @property
    def kind(self) -> FollowerKind:
        """Translating or oscillating: the units, conversions and force semantics of this case's follower."""
        return self.motion.kind

    @property
    def oscillating(self) -> bool:
        return self.kind.rotary

    @property
    def motion_source(self) -> str:
        """Where the motion comes from: "segments", "table", "valve_table", "contour" or "path"."""
        if self.contour is not None:
            return "contour"
        if self.fit is not None:
            return self.fit.source
        return "segments" if self.spec.motion is not None else "path"

    def motion_json(self) -> dict:
        """``check --json``'s ``motion``: the source and, for fitted motions, how far the fit departs from the data
        (a contour's ``fit`` is the outline's, radial in mm; ``motion_fit`` the contact motion's)."""
        out: dict = {"source": self.motion_source, "fit": None}
        if self.contour is not None:
            assert self.fit is not None  # a contour case's motion is fitted to its contact motion
            out |= {
                "fit": self.contour.json(),
                "motion_fit": self.fit.json(),
                "base_radius_mm": self.contour.base_radius,
            }
        elif self.fit is not None:
            out["fit"] = self.fit.json()
        return out


def with_valvetrain_keys(case: Case, dynamics: dict | None = None, valvetrain: dict | None = None) -> Case:
    """A ``[valvetrain]`` case with ``[dynamics]`` and ``[valvetrain]`` keys replaced (the case file's names and
    units: the valve spring's ``spring_rate`` N/mm and ``preload`` N at the valve, the masses, the stiffness, the
    lash), its two-mass model and equivalent follower rebuilt; the motion (ramps included) is kept. A case whose
    spring is resolved keeps that spring (its mass on the valve, lumped or its surge chain, and its coil bind), as
    :func:`valvetrain_with_spring_mass` puts it there."""
    assert case.spec.valvetrain is not None  # the caller's: a [valvetrain] case
    d = case.spec.dynamics.model_copy(update=dynamics or {})
    v = case.spec.valvetrain.model_copy(update=valvetrain or {})
    vt = valvetrain_model(v, d, float(_lifts(case.motion).max()))
    spec = case.spec.model_copy(update={"dynamics": d, "valvetrain": v})
    sd = case.spring
    if sd is None or sd.model == "none":
        return replace(case, spec=spec, model=equivalent_follower(vt), valvetrain=vt)
    rebuilt = replace(case, spec=spec, spring=replace(sd, bare=equivalent_follower(vt)))
    lumped = valvetrain_with_spring_mass(rebuilt, sd.mass_kg)
    train = valvetrain_with_spring_mass(rebuilt, sd.mass_kg, surge=True) if sd.model == "surge" else lumped
    return replace(rebuilt, model=equivalent_follower(lumped), valvetrain=train)


def load_case(path: str | Path) -> Case:
    """Read, validate and build a case file. Raises :class:`InputError` (one line) on any problem."""
    return build_case(load_case_spec(path), source=Path(path))


def case_from_dict(raw: dict, source: Path | None = None) -> Case:
    """Validate a parsed case (the TOML as a dict) and build the :class:`Case`."""
    return build_case(parse(CaseSpec, raw), source)


def build_case(spec: CaseSpec, source: Path | None = None) -> Case:
    """The models of a validated case: a motion program, a lift table's fit or a contour's contact motion with
    its follower, or a path synthesized by its cam-linkage; then the follower's dynamic model in SI. Data files
    are read relative to ``source`` (the case file)."""
    require_x64()
    name = spec.name or (source.stem if source else "case")
    warnings: list[str] = []
    synthesis = fit = contour = None
    if spec.motion is not None:
        assert spec.follower is not None  # CaseSpec: [motion] comes with [follower]
        follower = spec.follower
        if spec.motion.table is not None or spec.motion.valve_table is not None:
            motion, fit, warnings = table_motion(spec, source)
        else:
            motion = Program.from_specs(spec.motion.segments, unit=spec.kind.motion_unit)
            warnings += motion.continuity_warnings() + motion.polynomial_warnings()
    elif spec.follower is not None:
        motion, follower, fit, contour, warnings = contour_motion(spec, source)
    else:
        assert spec.path is not None and spec.mechanism is not None  # CaseSpec: a case without [motion] has both
        from .linkage import synthesize_motion  # only a path case loads the cam-linkage models (17 ms a check)

        synthesis = synthesize_motion(spec.path, spec.mechanism, reuse=True)
        motion, follower = synthesis.tabulated, synthesis.follower
        warnings += list(synthesis.warnings)
    # a follower that cannot be assembled on its cam is the case's error whatever the command (a groove cam's check
    # reaches its dynamics before its geometry, and `spring` none at all)
    check_assembly(motion, follower)
    valvetrain = None
    if spec.valvetrain is not None:
        lifts = _lifts(motion)
        _check_rocker(spec.valvetrain, lifts)
        valvetrain = valvetrain_model(spec.valvetrain, spec.dynamics, float(lifts.max()))
    if valvetrain is None:
        model = follower_model(spec.dynamics, kind=spec.kind)
    else:
        model = equivalent_follower(valvetrain)
    if not follower.form_closed:  # a groove holds the follower both ways: it needs no spring to stay on
        _check_holds_at_rest(motion, model, spec)
    if valvetrain is not None:
        _check_valve_lifts(motion, spec, valvetrain)
    return Case(
        name, source, spec, motion, follower, model, synthesis, tuple(warnings), fit, contour, valvetrain=valvetrain
    )


def _lifts(motion: Motion) -> np.ndarray:
    """The follower's lift on the revolution's grid (mm)."""
    return motion.host(np.arange(THETA_GRID) * (2 * np.pi / THETA_GRID))[0]


def valvetrain_with_spring_mass(case: Case, spring_mass_kg: float, surge: bool = False) -> ValvetrainModel:
    """The case's two-mass valvetrain with a third of its valve spring's mass (kg) moving with the valve (the
    lumped correction: the coils' kinetic energy with a linear velocity profile), its dampers kept at their ratios;
    ``surge``: the spring a chain of masses instead (:class:`Coils`), half a lump on the valve, the dampers the
    lumped model's (so a slow stroke sees it)."""
    vt = case.spec.valvetrain
    assert vt is not None  # the caller's: a [valvetrain] case
    heavier = vt.model_copy(update={"valve_mass": vt.valve_mass + spring_mass_kg / 3.0})
    lumped = valvetrain_model(heavier, case.spec.dynamics, float(_lifts(case.motion).max()))
    if not surge:
        return lumped
    coils = coils_model(float(lumped.spring_rate), spring_mass_kg)
    valve = jnp.asarray(float(vt.valve_mass)) + coils.lump_mass / 2
    return eqx.tree_at(lambda v: (v.valve_mass, v.coils), lumped, (valve, coils), is_leaf=lambda x: x is None)


def _check_rocker(vt: ValvetrainSpec, lifts: np.ndarray) -> None:
    """A rocker's geometry must carry the follower over all its lifts (mm) without an arm turning square to its
    contact's line (where the ratio would fall to zero or grow without bound)."""
    if vt.rocker is None:
        return
    rocker = rocker_model(vt.rocker)
    for lift in (float(lifts.min()), float(lifts.max())):
        why = rocker_reach(rocker, lift)
        if why is not None:
            raise InputError("valvetrain.rocker", f"{why}: lengthen the arm or change its angle")
    ratios = rocker.host_lever(lifts * M_PER_MM)[1]
    if ratios.max() > MAX_ROCKER_RATIO:
        raise InputError(
            "valvetrain.rocker",
            f"the rocker's ratio reaches {ratios.max():.3g} over the lift (at most {MAX_ROCKER_RATIO:g}): "
            "check the arms",
        )


def valve_stroke_mm(motion: Motion, vt_model: ValvetrainModel) -> float:
    """The cam's whole lift at the valve (through the rocker) less the lash (mm): how far a rigid train would move
    the valve (0 or less: it never lifts)."""
    lifts = _lifts(motion)
    at_valve = vt_model.at_valve_mm(np.array([lifts.min(), lifts.max()]))[0]
    return float(at_valve[1] - at_valve[0]) - float(vt_model.lash) / M_PER_MM


def _check_valve_lifts(motion: Motion, spec: CaseSpec, vt_model: ValvetrainModel) -> None:
    """The cam's lift at the valve (its lift through the rocker) must take up the lash, and a compliant train
    compressed by the rest must carry more than the spring's preload, or the valve never moves (statically)."""
    vt, preload = spec.valvetrain, spec.dynamics.preload
    assert vt is not None and preload is not None  # the caller's; CaseSpec: a valvetrain's spring has a preload
    stroke = valve_stroke_mm(motion, vt_model)  # mm the cam would move the valve through a rigid train
    reach = stroke + vt.lash
    if stroke <= 0.0:
        raise InputError(
            "valvetrain.lash",
            f"the valve never lifts: the cam's lift at the valve (through the rocker: {reach:.4g} mm) does not take up "
            f"the lash ({vt.lash:g} mm)",
        )
    if vt.stiffness is None:
        return
    if vt.stiffness * stroke <= preload:
        raise InputError(
            "valvetrain.stiffness",
            f"the valve never lifts: the train ({vt.stiffness:g} N/mm) compressed by the cam's whole lift at the "
            f"valve less the lash ({stroke:.4g} mm) carries {vt.stiffness * stroke:.4g} N, not "
            f"the spring's preload ({preload:g} N): is the stiffness in N/mm, at the valve?",
        )
    rate = spec.dynamics.spring_rate or 0.0
    if preload > max_lifting_preload(stroke, vt.stiffness, rate):
        lifted = static_valve_lift(stroke, preload, vt.stiffness, rate)  # at full lift
        raise InputError(
            "valvetrain.stiffness",
            f"the valve lifts only {lifted:.3g} mm of the cam's {stroke:.4g} mm at the valve, turned slowly: the train "
            f"({vt.stiffness:g} N/mm) gives way under the spring's load: is the stiffness in N/mm, at the valve?",
        )


_BELOW_ZERO = 0.01  # a lift below zero by more than this share of the largest is the motion's, not a fit's ripple


def _check_holds_at_rest(motion: Motion, model: FollowerModel, spec: CaseSpec) -> None:
    """The spring and the external load keep the follower on its cam turned slowly; where they do not because the
    lift goes below zero (a polynomial's boundary conditions that overshoot), the motion is named, not the spring."""
    least, at = least_static_force(motion, model)
    if least > 0.0:
        return
    kind, unit = spec.kind, spec.kind.force_unit
    held = f"spring + external load is {least:.4g} {unit} at {at:g} deg"
    lift = kind.motion_to_lift(np.asarray(_lifts(motion)))
    i = int(np.argmin(lift))
    deg = i * (360.0 / THETA_GRID)  # _lifts' grid
    if lift[i] < -_BELOW_ZERO * float(np.max(np.abs(lift))):
        where = "motion"
        if spec.motion is not None and spec.motion.segments:
            k = next((k for k, seg in enumerate(spec.motion.segments) if seg.end > deg), 0)
            where = f"motion.segments[{k}]"
        raise InputError(
            where,
            f"the lift goes below zero, to {lift[i]:.4g} {kind.lift_unit} at {deg:.1f} deg, so the spring "
            f"pulls the follower off the cam even at rest ({held}): check its lift and boundary conditions",
        )
    raise InputError(
        f"dynamics.{dynamics_keys(kind)[2]}", f"the spring cannot hold the follower on the cam even at rest: {held}"
    )
