"""Sequential linear programming: each step maximizes a linear model of the objective (the least contact force
over sampled speeds and angles, or a residual vibration, or a preload) under the linearized geometry limits
within a trust region, with HiGHS (``highspy``: its rows generated in rounds, each round re-solved from the last
round's basis). The Jacobians are JAX autodiff (forward mode:
a few dozen control points); in contact the force is exactly linear in the control points, so for a
translating follower only the geometry is linearized."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from ..._core.jit import jit_with
from ..._core.linprog import FAILED, INFEASIBLE, OPTIMAL, Answer, LinearProgram

_MAX_STEPS = 30
_FIRST_ROWS = 200  # rows of a linear program's first round
_FIRST_TROUGHS = 100  # and of the force's troughs over each speed's angles, the lowest (where an optimum binds)
_ADDED_ROWS = 100  # rows joining it per round at most, the most broken first
_TIE = 1e-7  # the least move's weight (of the objective's scale) per half-width of the trust region moved
_PENALTY = 1e3  # merit per unit of scaled geometry violation, relative to the objective's own scale


Bound = tuple[np.ndarray, np.ndarray]  # the value rows and the limit rows that bound a linear program's answer


@dataclass(frozen=True)
class Step:
    x: np.ndarray  # the variables: control points (and a preload where it is free)
    value: float  # the objective reached (to maximize)
    violation: float  # largest scaled geometry violation (<= 0: feasible)
    steps: int
    bound: Bound | None = None  # the rows that bound its last linear program (a later one's first rows)


def value_and_jacobian(fn: Callable, x: jax.Array, *args: Any) -> tuple[jax.Array, jax.Array]:
    """``(fn(x, *args), dfn/dx)`` by forward-mode autodiff, one tangent per variable (JAX-traceable)."""
    v, jvp_fn = jax.linearize(lambda y: fn(y, *args), x)
    return v, jax.vmap(jvp_fn, out_axes=-1)(jnp.eye(x.size))


def with_jacobian(fn: Callable) -> Callable:
    """``x -> (fn(x), dfn/dx)`` compiled once (:func:`value_and_jacobian`)."""
    return jit_with(lambda x, *args: value_and_jacobian(fn, x, *args))


def _value_and_jacobian(fn: Callable, x: np.ndarray):
    v, J = fn(jnp.asarray(x))
    return np.asarray(v), np.asarray(J)


def _matvec(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``a @ x`` without BLAS: thousands of rows by a few dozen columns, where a threaded BLAS spends more time
    waking its threads than multiplying (10x on a loaded 2-core machine)."""
    return np.einsum("ij,j->i", a, x)


def _split_bounds(lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of ``(p, q)`` with ``dx = p - q``, ``p, q >= 0``, for ``lower <= dx <= upper``."""
    return np.r_[np.maximum(lower, 0.0), np.maximum(-upper, 0.0)], np.r_[
        np.maximum(upper, 0.0), np.maximum(-lower, 0.0)
    ]


def _least_violation(Jg: np.ndarray, g: np.ndarray, lower: np.ndarray, upper: np.ndarray, tie: np.ndarray) -> Answer:
    """The step ``dx`` within the bounds that breaks the linearized limits ``g + Jg dx <= 0`` least, the least
    move (``tie`` per unit of ``|dx|``) among them: variables (p, q, s), dx = p - q, minimize s with
    g + Jg dx <= s, s >= 0. Its ``x`` is (dx, s)."""
    n = Jg.shape[1]
    lo, hi = _split_bounds(lower, upper)
    lp = LinearProgram(np.r_[tie, tie, 1.0], np.r_[lo, 0.0], np.r_[hi, np.inf])
    lp.add(np.c_[Jg, -Jg, -np.ones(g.size)], -g)
    answer = lp.solve()
    return Answer(answer.status, np.r_[answer.x[:n] - answer.x[n : 2 * n], answer.x[-1]])


def _troughs(v: np.ndarray, block: int) -> np.ndarray:
    """The rows of ``v`` (``block`` angles a speed, around the cam) each at most its neighbours at its speed."""
    vb = v.reshape(-1, block)
    return np.nonzero(((vb <= np.roll(vb, 1, axis=1)) & (vb <= np.roll(vb, -1, axis=1))).ravel())[0]


def _linear_step(
    v, Jv, g, Jg, bounds, seed: Bound | None = None, tie=0.0, block: int | None = None
) -> tuple[Answer, Bound | None]:
    """The linear program of one step, variables (dx, t): maximize t with v + Jv dx >= t, g + Jg dx <= 0 within
    ``bounds``; where the linearized limits cannot be met there, the least violation instead. Of the steps that
    reach the best t, the least move: ``tie`` (units of t) per half-width of the box moved in a variable, so the
    answer does not depend on which of a degenerate program's optimal vertices the simplex ends at. Rows are
    generated: HiGHS sees the lowest rows (and ``seed``'s, the rows that bound the previous step) first, and the
    rows the answer breaks most join, re-solved from the last basis, until none is broken (the answer is that of
    the whole program). ``block``: the value rows come ``block`` angles a speed, and the first round holds the
    lowest of the force's troughs over the angles too (a trough at a lower speed binds the optimum as well: on the
    oscillating case 126 solves where 196 were). Returns the program's answer, its ``x`` (dx, t), and the rows
    that bound it (the next step's ``seed``)."""
    n = Jv.shape[1]
    lo_dx = np.array([b[0] for b in bounds])
    hi_dx = np.array([b[1] for b in bounds])
    # a row that stays above the best bound (or a limit that stays met) whatever dx in the box cannot bind
    half = np.maximum(-lo_dx, hi_dx)
    reach_v, reach_g = _matvec(np.abs(Jv), half), _matvec(np.abs(Jg), half)
    kv_all = np.nonzero(v - reach_v <= np.min(v + reach_v))[0]
    kg_all = np.nonzero(g + reach_g >= 0.0)[0]
    v_all, Jv_all, g_all, Jg_all = v[kv_all], Jv[kv_all], g[kg_all], Jg[kg_all]  # the candidate rows, copied once
    # positions within the candidates: the lowest, and the seed's that are still candidates
    kv = np.argsort(v_all)[:_FIRST_ROWS]
    if block:
        troughs = _troughs(v, block)
        kv = np.union1d(kv, np.nonzero(np.isin(kv_all, troughs[np.argsort(v[troughs])][:_FIRST_TROUGHS]))[0])
    kg = np.argsort(-g_all)[:_FIRST_ROWS]
    if seed is not None:
        kv = np.union1d(kv, np.nonzero(np.isin(kv_all, seed[0]))[0])
        kg = np.union1d(kg, np.nonzero(np.isin(kg_all, seed[1]))[0])
    move = np.divide(tie, half, out=np.zeros(n), where=half > 0)
    lo, hi = _split_bounds(lo_dx, hi_dx)
    lp = LinearProgram(np.r_[move, move, -1.0], np.r_[lo, -np.inf], np.r_[hi, np.inf])
    new_v, new_g = kv, kg
    answer = Answer(FAILED, np.full(n + 1, np.nan))
    for _ in range(50):
        lp.add(np.c_[-Jv_all[new_v], Jv_all[new_v], np.ones(new_v.size)], v_all[new_v])
        lp.add(np.c_[Jg_all[new_g], -Jg_all[new_g], np.zeros(new_g.size)], -g_all[new_g])
        answer = lp.solve()
        if answer.status == INFEASIBLE:  # the linearized geometry cannot be met in this region: least violation
            return _least_violation(Jg_all, g_all, lo_dx, hi_dx, move), None
        dx, t = answer.x[:n] - answer.x[n : 2 * n], answer.x[-1]
        answer = Answer(answer.status, np.r_[dx, t])
        if answer.status != OPTIMAL:
            return answer, None
        over_v = (v_all + _matvec(Jv_all, dx)) - t  # < 0: broken
        over_g = g_all + _matvec(Jg_all, dx)  # > 0: broken
        broken_v = np.nonzero(over_v < -1e-9 * max(1.0, abs(t)))[0]
        broken_g = np.nonzero(over_g > 1e-12)[0]
        new_v = broken_v[~np.isin(broken_v, kv)]
        new_g = broken_g[~np.isin(broken_g, kg)]
        if new_v.size == 0 and new_g.size == 0:
            bind_v = kv[over_v[kv] <= 1e-9 * max(1.0, abs(t))]
            bind_g = kg[over_g[kg] >= -1e-12]
            return answer, (kv_all[bind_v], kg_all[bind_g])
        # the most broken first: fewer rounds of smaller programs
        new_v = new_v[np.argsort(over_v[new_v])][:_ADDED_ROWS]
        new_g = new_g[np.argsort(-over_g[new_g])][:_ADDED_ROWS]
        kv, kg = np.union1d(kv, new_v), np.union1d(kg, new_g)
    return answer, None


def maximize_least(
    values: Callable,
    geometry: Callable,
    x0: np.ndarray,
    *,
    radius: npt.ArrayLike,
    scale: float,
    lower: np.ndarray | None = None,
    upper: np.ndarray | None = None,
    seed: Bound | None = None,
    block: int | None = None,
) -> Step:
    """Maximize ``min(values(x))`` subject to ``geometry(x) <= 0``, from ``x0``; both callables return the value and
    its Jacobian (:func:`with_jacobian`). ``radius``: the first trust region (one, or one per variable); ``scale``: the
    objective's size (N), for the merit that trades it against the geometry; ``lower``/``upper``: bounds on the
    variables (None: free); ``seed``: the rows an earlier answer's program bound (:attr:`Step.bound`), its first
    program's first rows; ``block``: the values come ``block`` angles a speed (:func:`_linear_step`)."""
    x = np.asarray(x0, dtype=float)
    n = x.size
    lo = np.full(n, -np.inf) if lower is None else np.asarray(lower, dtype=float)
    hi = np.full(n, np.inf) if upper is None else np.asarray(upper, dtype=float)

    def merit(v: np.ndarray, g: np.ndarray) -> float:
        return float(np.min(v)) - _PENALTY * scale * max(0.0, float(np.max(g)))

    v, Jv = _value_and_jacobian(values, x)
    g, Jg = _value_and_jacobian(geometry, x)
    radius = np.broadcast_to(np.asarray(radius, dtype=float), x.shape)
    bound = seed  # the rows that bound the last program: the next one starts with them
    best, delta, steps = merit(v, g), radius.copy(), 0  # a writable trust region (the broadcast is a read-only view)
    for _ in range(_MAX_STEPS):
        steps += 1  # the steps taken, read after the loop
        bounds = [(max(-delta[i], lo[i] - x[i]), min(delta[i], hi[i] - x[i])) for i in range(n)]
        lp, found = _linear_step(v, Jv, g, Jg, bounds, bound, _TIE * scale, block)
        bound = found or bound
        if lp.status != OPTIMAL:  # HiGHS gave up on this region (numerical trouble): the point reached stands
            break
        dx = lp.x[:n]
        if lp.x[-1] - np.min(v) <= 1e-9 * scale and np.max(g) <= 0.0:
            break  # the linear model promises nothing more: a vertex of the (linear in contact) problem
        trial = x + dx
        v2, Jv2 = _value_and_jacobian(values, trial)
        g2, Jg2 = _value_and_jacobian(geometry, trial)
        m2 = merit(v2, g2)
        if m2 > best + 1e-9 * max(1.0, abs(best)):
            x, v, Jv, g, Jg, best = trial, v2, Jv2, g2, Jg2, m2
            delta = np.minimum(2.0 * delta, 4.0 * radius) if np.any(np.abs(dx) > 0.9 * delta) else delta
        else:
            delta = 0.5 * delta
        if np.all(delta < 1e-5 * radius):
            break
    return Step(x, float(np.min(v)), float(np.max(g)), steps, bound)
