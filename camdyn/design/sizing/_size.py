"""``size_spring``: the kinematic answer (LP or sqrt-k search), the dynamic correction of a compliant follower,
the chosen, kinematic and current springs evaluated, the warnings and the feasible region."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..._core.errors import InputError
from ..._core.limits import check_sizing
from ..._core.progress import Progress
from ..._core.units import RPM
from ...model.dynamics import velocity_steps
from ..parts import resolve_spring
from ._buildable import HEADROOM, WRITTEN_DIGITS, buildable_fixed_point
from ._design import design
from ._dynamic import Dynamic, dynamic_answer
from ._kinematic import binding, preload_kinematic, required
from ._lp import lp
from ._problem import Grid, Problem, build_problem
from ._results import SpringSizing
from ._sqrt_k import ratio_answer

if TYPE_CHECKING:
    from ...model.case import Case

_LP_METHOD = "linear program (HiGHS) with cutting planes, checked against its closed form; tie-break in closed form"
_SQRT_K_METHOD = "exact minimization of the peak force in sqrt(k) (bounded Brent; ties to the largest k)"
_SMOOTH_THE_STEP = {  # how to remove a step in the cam's velocity, by where the motion comes from
    "segments": "join the segments with a continuous velocity",
    "path": "give the path's corners a radius ([path] corner_radius)",
    "table": "tabulate a lift whose velocity is continuous there",
    "valve_table": "tabulate a lift whose velocity is continuous there",
    "contour": "measure or smooth the contour there",
}
_DYNAMIC_METHOD = (
    "; dynamic correction: exact least preload per rate (frequency-domain steady state, affine in F0) minimized "
    "over sqrt(k)"
)


def _kinematic_answer(p: Problem, grid: Grid) -> tuple[float, float, str, str, Grid]:
    """(k, F0) of the kinematic problem, how damping was treated, the method, and the refined grid."""
    if p.c_fixed is not None or p.zeta == 0.0:
        k, f0, grid = lp(p, grid, p.damping(0.0))
        what = "no damping" if p.damping(0.0) == 0.0 else f"constant damping c = {p.c_fixed:g} {p.kind.damping_unit}"
        return k, f0, f"{what}: the linear program is exact", _LP_METHOD, grid
    k, f0, grid = ratio_answer(p, grid)
    note = (
        f"c = 2 zeta sqrt(k m) with zeta = {p.zeta:g} follows the rate: for each k the least preload is closed form "
        "and the peak force, convex in sqrt(k), is minimized exactly in sqrt(k) (not a frozen-c LP)"
    )
    return k, f0, note, _SQRT_K_METHOD, grid


def _at_full_lift(p: Problem, bind) -> bool:
    """Whether a binding angle is at full lift (to 1e-9 of it)."""
    s = p.values(np.deg2rad([a for a, _, _ in bind]))[0] if bind else np.zeros(0)
    return bool(np.any(np.abs(p.s_max - s) <= 1e-9 * abs(p.s_max)))


def _warnings(p: Problem, k: float, min_rate: float, bind) -> tuple[str, ...]:
    out = []
    if k <= p.k_lo * (1 + 1e-9) + 1e-12:
        why = ""
        if p.c_fixed is None and p.zeta > 0.0 and _at_full_lift(p, bind):
            why = (
                "; the binding angle is at full lift, but the damping (damping_ratio) grows with the rate and, "
                "where the follower leaves full lift, moves the binding onto that flank: no tie"
            )
        out.append(
            f"the least peak force is reached at the least rate ({min_rate:g} {p.kind.rate_unit}): "
            f"any rate adds k times (full lift - lift at the binding angle) to the peak{why}; pass --min-rate for "
            "the least preload with the rate you have"
        )
    if p.fmin == 0.0 and any(w == 0.0 for _, _, w in bind):
        at = next(a for a, _, w in bind if w == 0.0)
        out.append(
            f"with min_contact_force = 0 the sized spring leaves zero contact force at rest at {at:.1f} deg, and "
            "check requires a force strictly above the limit: give [limits] min_contact_force > 0 for a margin"
        )
    return tuple(out)


def _region(p: Problem, grid: Grid, dynamic: Dynamic | None, k_top: float):
    """The least preload per rate on 41 rates in [min_rate, k_top]: kinematic, and dynamic (on every 4th rate,
    interpolated) for a compliant follower."""
    rates = np.linspace(p.k_lo, k_top, 41)
    pre_kin = np.array([preload_kinematic(p, grid, kk) for kk in rates])
    pre_dyn = None
    if dynamic is not None:
        rates_d = rates[::4]
        pre_d = np.array([dynamic.preload(kk, refine=False)[0] for kk in rates_d])
        pre_dyn = np.interp(rates, rates_d, pre_d)
    return rates, pre_kin, pre_dyn


def _lines(p: Problem, grid: Grid, k_kin: float, f0_kin: float, rates) -> tuple[tuple[float, float, float], ...]:
    """The constraint lines F0 >= r - k s worth drawing: those binding somewhere on ``rates`` and the 3 tightest
    at the kinematic answer, as (theta_deg, s, r)."""
    r, _ = required(p, grid, p.damping(k_kin))
    idx = {int(np.argmax(r - kk * grid.s)) for kk in rates}
    slack = k_kin * grid.s + f0_kin - r
    idx |= set(np.argsort(slack)[:3].tolist())
    return tuple((math.degrees(grid.theta[i]), float(grid.s[i] / p.scale), float(r[i])) for i in sorted(idx))


def size_spring(
    case: Case,
    max_speed_rpm: float | None = None,
    margin: float | None = None,
    min_rate: float = 0.0,
    buildable: bool = False,
    progress: Progress | None = None,
) -> SpringSizing:
    """Size the return spring of ``case``: the (rate, preload) with the least peak spring force that keeps the
    interface force >= ``[limits] min_contact_force`` at every angle and every speed up to ``margin`` times
    ``max_speed_rpm`` (defaults: the case's speed and speed_margin); ``min_rate`` (N/mm, or N*m/rad for an
    oscillating follower) bounds the rate from below. ``buildable``: the least peak force over springs that can
    be built within the case's ``[spring]`` table, and the part (:mod:`._buildable`; ``progress``: its rounds). See
    :mod:`camdyn.design.sizing` for the method, the tie-break rule and the dynamic correction. Raises
    :class:`InputError` on bad input."""
    check_sizing(max_speed_rpm, margin, min_rate)
    if case.valvetrain is not None:  # the equivalent single follower has no lash, seat or float
        raise InputError(
            "valvetrain",
            "the single follower's sizing does not apply: camdyn size sizes the valve spring with the two-mass "
            "model (size_valve_spring)",
        )
    case = resolve_spring(case)
    if case.model.rigid and (steps := velocity_steps(case.motion, float(case.model.restitution))):
        raise InputError(
            "motion",
            f"no spring holds a rigid follower on this cam: its velocity steps at {math.degrees(steps[0][0]):g} deg, "
            f"which throws the follower off at any speed; {_SMOOTH_THE_STEP[case.motion_source]} (or give "
            "[dynamics] train_stiffness: a compliant train takes up the step)",
        )
    part = check = None
    if buildable:
        speed = float(case.speed_rpm if max_speed_rpm is None else max_speed_rpm)
        top_margin = float(case.limits.speed_margin if margin is None else margin)
        case, rate_w, f0_w, part, check = buildable_fixed_point(case, speed, top_margin, min_rate, progress)
    spring = case.spring
    assert spring is not None  # resolve_spring resolved it; buildable_fixed_point keeps it resolved
    p, grid = build_problem(case, max_speed_rpm, margin, min_rate)
    k_kin, f0_kin, damping_note, method, grid = _kinematic_answer(p, grid)
    dynamic = None if p.rigid else Dynamic.of(p)
    k, f0, dyn_bind = k_kin, f0_kin, None
    if dynamic is not None:
        k, f0, dyn_bind = dynamic_answer(dynamic, grid, k_kin)
        method += _DYNAMIC_METHOD
    if buildable:
        k, f0 = p.kind.rate_to_si(rate_w), f0_w
        method += (
            "; buildable: the least peak force over the springs [spring] allows, their surge clear of the cam's "
            "strong harmonics (a scan of rates, the designer's largest preload per rate), with the proposed "
            f"spring's own mass ({spring.model}), sized to {1 + HEADROOM:g} x the top speed and written to "
            f"{WRITTEN_DIGITS} digits"
        )
    kin_design = design(p, grid, dynamic, k_kin, f0_kin)
    chosen = kin_design if dynamic is None and not buildable else design(p, grid, dynamic, k, f0)
    k_cur, f0_cur = float(p.model.stiffness), float(p.model.preload)
    current = design(p, grid, dynamic, k_cur, f0_cur)
    if dynamic is None:
        f0_at = preload_kinematic(p, grid, k_cur, polish=True)
    else:
        f0_at = dynamic.raised(k_cur, dynamic.preload(k_cur)[0])
    at_current = design(p, grid, dynamic, k_cur, f0_at)
    bind = binding(p, grid, k_kin, f0_kin)
    rates, pre_kin, pre_dyn = _region(p, grid, dynamic, 1.5 * max(k, k_kin, k_cur, p.k_lo, 1e-12))
    return SpringSizing(
        case_name=case.name,
        kind=p.kind,
        model="rigid" if p.rigid else "compliant",
        speed_rpm=p.speed_rpm,
        margin=p.margin,
        top_speed_rpm=p.W / RPM,
        min_contact_force=p.fmin,
        min_rate=float(min_rate),
        s_max=p.s_max / p.scale,
        chosen=chosen,
        kinematic=kin_design,
        current=current,
        at_current_rate=at_current,
        binding=bind,
        dynamic_binding=dyn_bind,
        damping=damping_note,
        method=method,
        region_rate=p.kind.rate_from_si(rates),
        region_preload_kinematic=pre_kin,
        region_preload_dynamic=pre_dyn,
        lines=_lines(p, grid, k_kin, f0_kin, rates),
        warnings=() if buildable else _warnings(p, k, min_rate, bind),
        part=part,
        check=check,
        spring_model=spring.model,
        spring_mass_kg=spring.mass_kg,
    )
