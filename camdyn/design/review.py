"""What a design review shows that must be computed, gathered once from a case and its check.

:func:`design_review` takes a :class:`~camdyn.model.case.Case` and its :class:`~camdyn.design.checks.CheckReport`
and adds what the check does not hold: the motion sampled finely with both sides of every break, the steady
state at ``speed_margin`` x speed, the least contact force against cam speed, the spring sizing and a small
jump map. The reports draw a :class:`Review`; a notebook user can draw it with :mod:`camdyn.plot`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import jax.numpy as jnp
import numpy as np

from .._core.errors import CamdynError, InputError
from .._core.progress import Progress, counter
from .._core.results import Unavailable
from .._core.units import FFT_GRID, RPM, THETA_GRID, TWO_PI
from ..model import dynamics as dyn
from ..model.case import Case, load_case
from ..model.geometry import newton_per_torque_at
from ..model.motion import evaluate
from .checks import CheckReport, forces_in_newton, run_check
from .closure import NO_RETURN_SPRING, ImpactMap, impact_map
from .parts import resolve_spring
from .sizing import SpringSizing, size_spring
from .spring import SpringDesign, design_case_spring
from .sweep import JumpMap, jump_map
from .tolerance import ToleranceResult, tolerance_study

SIDE_DEG = 1e-7  # how far either side of a break the one-sided values are taken (deg)
REVIEW_TOLERANCE_SAMPLES = 2000  # built cams of the report's tolerance page (seed 0; `camdyn tolerance` for more)
SPEED_SCAN = 2000  # speeds of the force-against-speed curve: the grid of dynamic_jump_speed's scan
VALVE_SPEED_SCAN = 80  # speeds of a valvetrain's two-mass curve (a revolution of the two-mass model each)
MAP_SPEEDS, MAP_RATES = 48, 24  # the review's jump map: speeds x spring rates
VALVETRAIN_MAP = 24, 6  # a valvetrain's (the two-mass model at each point, about 0.05 s a point)
IMPACT_SPEEDS = 40  # a groove cam's impact speed against cam speed, up to 2 x the check's speed


@dataclass(frozen=True)
class MotionSamples:
    """The motion on a 0.25 deg grid plus both sides (:data:`SIDE_DEG`) of every break.

    ``values`` (4, n) = s, ds/dtheta, d2s/dtheta2, d3s/dtheta3 in the motion's ``unit`` (mm, or rad of arm
    swing) per rad of cam angle to the power of the derivative."""

    theta_deg: np.ndarray
    values: np.ndarray
    breaks_deg: tuple[float, ...]
    unit: str

    def one_sided(self, deg: float) -> tuple[np.ndarray, np.ndarray]:
        """The values (4,) just before and just after cam angle ``deg`` (a break), in the motion's unit."""
        th = self.theta_deg
        i, j = np.searchsorted(th, (deg - SIDE_DEG) % 360.0), np.searchsorted(th, (deg + SIDE_DEG) % 360.0)
        return self.values[:, i], self.values[:, j]


@dataclass(frozen=True)
class ForceVsSpeed:
    """The least contact force (N) over a revolution against cam speed."""

    speeds_rpm: np.ndarray
    kinematic_N: np.ndarray  # rigid follower that never leaves the cam
    dynamic_N: (
        np.ndarray | None
    )  # compliant train: frequency-domain steady state, exact until separation; None if rigid
    # a valvetrain's two-mass model: (speeds rpm, the least cam force over the valve event N at each), up to the
    # first speed where the valve floats (0 there; NaN past it); None for a single follower
    valve_event: tuple[np.ndarray, np.ndarray] | None = None


@dataclass(frozen=True)
class Original:
    """The case an optimized case was reshaped from (``optimized_from``): its motion, check and force against speed."""

    case: Case
    check: CheckReport
    motion: MotionSamples
    force_vs_speed: ForceVsSpeed


@dataclass(frozen=True)
class Review:
    """A design review's data. Where a part cannot be had for this case, it is :class:`Unavailable` with the reason."""

    case: Case
    check: CheckReport
    motion: MotionSamples
    margin_rpm: float  # speed_margin x the check's speed
    margin_response: dyn.Response | Unavailable  # the steady state at margin_rpm, forces in N
    force_vs_speed: ForceVsSpeed | Unavailable  # Unavailable for a form-closed cam: it cannot jump
    sizing: SpringSizing | Unavailable  # size_spring at the case's speed and speed_margin
    jump_map: JumpMap | Unavailable  # at the case's preload, gaps not integrated (least force and the jump boundary)
    spring_part: SpringDesign | Unavailable = Unavailable("not designed")  # the case's own spring (camdyn spring)
    original: Original | Unavailable | None = None  # the case this one was optimized from (None: not optimized)
    tolerance: ToleranceResult | Unavailable | None = None  # the study of [tolerances] (None: the case has none)
    impacts: ImpactMap | None = None  # a groove cam's impacts against cam speed at its backlash (None: spring-held)


def design_review(case: Case, check: CheckReport, *, progress: Progress | None = None) -> Review:
    """Everything a design review of ``case`` draws beyond its ``check`` (run at the speed of the review)."""
    case = resolve_spring(case)  # the spring's own mass ([spring] model), as check weighs it
    tick = counter(progress, f"{case.name}: review", 6)
    motion = sample_motion(case)
    tick()
    if check.closure is not None:  # a groove cam: no jump, no return spring; its crossovers are in the check
        none = Unavailable(NO_RETURN_SPRING)
        assert case.follower is not None  # a groove holds a roller
        top = 2.0 * check.speed_rpm
        speeds = np.linspace(top / IMPACT_SPEEDS, top, IMPACT_SPEEDS)
        impacts = impact_map(case, speeds, np.array([case.follower.backlash]))
        tick(5)
        margin_rpm = case.limits.speed_margin * check.speed_rpm
        return Review(case, check, motion, margin_rpm, none, none, none, none, none, impacts=impacts)
    margin_rpm = case.limits.speed_margin * check.speed_rpm
    margin = _margin_response(case, margin_rpm)
    tick()
    sweep = force_vs_speed(case, check, margin_rpm)
    tick()
    sizing = _or_reason(size_spring, case)
    tick()
    jm = _review_jump_map(case, check, margin_rpm, sizing)
    tick()
    part = _or_reason(design_case_spring, case)
    tick()
    original = _or_reason(_original, case, check, sweep) if case.spec.optimized_from else None
    tol = _or_reason(tolerance_study, case, REVIEW_TOLERANCE_SAMPLES, 0) if case.spec.tolerances is not None else None
    return Review(case, check, motion, margin_rpm, margin, sweep, sizing, jm, part, original, tol)


def _original(case: Case, check: CheckReport, sweep: ForceVsSpeed) -> Original:
    """The case ``case`` was optimized from, checked at the same speed, its force against the same speeds."""
    assert case.spec.optimized_from is not None  # design_review asks for an optimized case's original only
    where = (case.source.parent if case.source else Path.cwd()) / case.spec.optimized_from
    if not where.is_file():
        raise InputError("optimized_from", f"{where} is not a case file: the optimization page compares with it")
    original = load_case(where)
    chk = run_check(original, check.speed_rpm)
    top = float(sweep.speeds_rpm[-1])
    return Original(original, chk, sample_motion(original), force_vs_speed(original, chk, top, top=top))


def _or_reason(fn, *args, **kwargs):
    """``fn(*args, **kwargs)``, or :class:`Unavailable` with the reason it gave up."""
    try:
        return fn(*args, **kwargs)
    except CamdynError as err:
        return Unavailable(str(err))


def sample_motion(case: Case) -> MotionSamples:
    """The motion of ``case`` on a 0.25 deg grid plus both sides of every break."""
    grid = np.linspace(0.0, 360.0, 1441)
    grid[-1] = 360.0 - SIDE_DEG
    b = np.asarray(case.motion.breaks_deg, dtype=float)
    th = np.unique(np.concatenate([grid, (b - SIDE_DEG) % 360.0, (b + SIDE_DEG) % 360.0]))
    return MotionSamples(th, _motion_values(case, th), tuple(case.motion.breaks_deg), case.motion.unit)


def _motion_values(case: Case, theta_deg: np.ndarray) -> np.ndarray:
    """The motion (4, n) at any angles, evaluated in chunks of the dynamics' grid shape, which is compiled
    already (a path motion compiles for seconds per new array shape)."""
    n = THETA_GRID
    flat = np.asarray(theta_deg, dtype=float).ravel()
    parts = []
    for i in range(0, flat.size, n):
        chunk = np.zeros(n)
        part = flat[i : i + n]
        chunk[: part.size] = part
        parts.append(np.asarray(evaluate(case.motion, jnp.deg2rad(jnp.asarray(chunk))))[:, : part.size])
    return np.concatenate(parts, axis=1)


def _margin_response(case: Case, margin_rpm: float) -> dyn.Response | Unavailable:
    try:
        resp = dyn.response(case.motion, case.model, margin_rpm * RPM)
        return forces_in_newton(case, resp)
    except CamdynError as err:
        return Unavailable(str(err))


def _top_speed(check: CheckReport, margin_rpm: float, jump_within: float = np.inf) -> float:
    """The top of a speed axis: 1.6 x the faster of speed and margin, and past the jump speeds below
    ``jump_within`` (rpm)."""
    top = 1.6 * max(margin_rpm, check.speed_rpm)
    for j in (check.dynamic.jump_speed_rpm, check.kinematic.jump_speed_rpm):
        if j is not None and j < jump_within:
            top = max(top, 1.15 * j)
    return top


def force_vs_speed(case: Case, check: CheckReport, margin_rpm: float, *, top: float | None = None) -> ForceVsSpeed:
    """Least contact force against cam speed, up to past the jump speeds (those below 8 x the check's speed), or
    up to ``top`` rpm: kinematic (rigid) and, for a compliant train, the frequency-domain steady state."""
    top = top if top is not None else _top_speed(check, margin_rpm, jump_within=8.0 * check.speed_rpm)
    speeds = np.linspace(top / SPEED_SCAN, top, SPEED_SCAN)
    w = speeds * RPM
    # the kinematic force is a quadratic in the speed at every angle: three evaluations give it all;
    # the very theta array (shape and JAX weak type) of dynamics.response, so its compiled force is reused
    n = THETA_GRID
    theta = jnp.asarray(np.arange(n) * (TWO_PI / n)) if case.model.rigid else jnp.arange(n) * (TWO_PI / n)
    f = [
        np.asarray(dyn.kinematic_force_jit(case.motion, case.model, jnp.asarray(x, dtype=float), theta))
        for x in (0.0, 1.0, -1.0)
    ]
    a, b, c = 0.5 * (f[1] + f[2]) - f[0], 0.5 * (f[1] - f[2]), f[0]
    kin = w[:, None] ** 2 * a + w[:, None] * b + c
    if case.oscillating:
        kin = kin * newton_per_torque_at(case.motion, case.follower, np.asarray(theta))
    linear = None
    if not case.model.rigid:
        weight = None
        if case.oscillating:
            weight = jnp.asarray(
                newton_per_torque_at(case.motion, case.follower, np.arange(FFT_GRID) * (TWO_PI / FFT_GRID))
            )
        linear = np.asarray(dyn.linear_min_force(case.motion, case.model, jnp.asarray(w), FFT_GRID, weight))
    if case.valvetrain is None:
        return ForceVsSpeed(speeds, kin.min(axis=1), linear)
    valve_speeds = np.linspace(top / VALVE_SPEED_SCAN, top, VALVE_SPEED_SCAN)
    return ForceVsSpeed(speeds, kin.min(axis=1), linear, (valve_speeds, _least_event_force(case, valve_speeds)))


def _least_event_force(case: Case, speeds_rpm: np.ndarray) -> np.ndarray:
    """The two-mass model's least cam force over the valve event (N) at each speed, up to the first that floats
    (0 there, NaN past it): what ``check`` judges a valvetrain's contact force and float speed by."""
    assert case.valvetrain is not None  # force_vs_speed asks for a valvetrain's only
    least = np.full(len(speeds_rpm), np.nan)
    for i, rpm in enumerate(speeds_rpm):
        least[i] = dyn.ValvePoint(case.motion, case.valvetrain, float(rpm) * RPM).least_event_force
        if least[i] <= 0.0:
            break
    return least


def _review_jump_map(
    case: Case, check: CheckReport, margin_rpm: float, sizing: SpringSizing | Unavailable
) -> JumpMap | Unavailable:
    """A small jump map at the case's preload: the sizing's rates (twice the case's where sizing does not apply)
    and speeds past the case's jump speeds, however fast; gaps not integrated."""
    top = _top_speed(check, margin_rpm)
    k_top = (
        float(sizing.region_rate[-1])
        if not isinstance(sizing, Unavailable)
        else 2.0 * float(case.kind.rate_from_si(case.model.stiffness))
    )
    n_speeds, n_rates = MAP_SPEEDS, MAP_RATES
    if case.valvetrain is not None:  # the two-mass model point by point: the valve spring's rates, a coarser grid
        k_top, n_speeds, n_rates = 2.0 * float(case.spec.dynamics.spring_rate or 0.0), *VALVETRAIN_MAP
    speeds = np.linspace(top / n_speeds, top, n_speeds)
    rates = np.linspace(k_top / n_rates, k_top, n_rates)
    return _or_reason(jump_map, case, speeds, rates, gaps=False)
