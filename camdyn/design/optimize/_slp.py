"""Sequential linear programming: each step maximizes a linear model of the objective (the least contact force
over sampled speeds and angles, or a residual vibration, or a preload) under the linearized geometry limits
within a trust region, with HiGHS (``scipy.optimize.linprog``). The Jacobians are JAX autodiff (forward mode:
a few dozen control points); in contact the force is exactly linear in the control points, so for a
translating follower only the geometry is linearized."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
from scipy.optimize import linprog

_MAX_STEPS = 30
_FIRST_ROWS = 400  # rows of a linear program's first round
_PENALTY = 1e3  # merit per unit of scaled geometry violation, relative to the objective's own scale


@dataclass(frozen=True)
class Step:
    x: np.ndarray  # the variables: control points (and a preload where it is free)
    value: float  # the objective reached (to maximize)
    violation: float  # largest scaled geometry violation (<= 0: feasible)
    steps: int


def with_jacobian(fn: Callable) -> Callable:
    """``x -> (fn(x), dfn/dx)`` compiled once: forward-mode autodiff, one tangent per variable."""

    def both(x, *args):
        v, jvp_fn = jax.linearize(lambda y: fn(y, *args), x)
        return v, jax.vmap(jvp_fn, out_axes=-1)(jnp.eye(x.size))

    return jax.jit(both)


def _value_and_jacobian(fn: Callable, x: np.ndarray):
    v, J = fn(jnp.asarray(x))
    return np.asarray(v), np.asarray(J)


def _linear_step(v, Jv, g, Jg, bounds):
    """The linear program of one step, variables (dx, t): maximize t with v + Jv dx >= t, g + Jg dx <= 0 within
    ``bounds``; where the linearized limits cannot be met there, the least violation instead. Rows are
    generated: HiGHS sees the lowest rows first, and any row the answer breaks joins until none does (the
    answer is that of the whole program)."""
    n = Jv.shape[1]
    lo_dx = np.array([b[0] for b in bounds])
    hi_dx = np.array([b[1] for b in bounds])
    # a row that stays above the best bound (or a limit that stays met) whatever dx in the box cannot bind
    half = np.maximum(-lo_dx, hi_dx)
    reach_v, reach_g = np.abs(Jv) @ half, np.abs(Jg) @ half
    kv_all = np.nonzero(v - reach_v <= np.min(v + reach_v))[0]
    kg_all = np.nonzero(g + reach_g >= 0.0)[0]
    kv = kv_all[np.argsort(v[kv_all])[:_FIRST_ROWS]]
    kg = kg_all[np.argsort(-g[kg_all])[:_FIRST_ROWS]]
    for _ in range(50):
        A = np.vstack([np.c_[-Jv[kv], np.ones(kv.size)], np.c_[Jg[kg], np.zeros(kg.size)]])
        lp = linprog(
            np.r_[np.zeros(n), -1.0], A_ub=A, b_ub=np.r_[v[kv], -g[kg]], bounds=bounds + [(None, None)], method="highs"
        )
        if lp.status == 2:  # the linearized geometry cannot be met in this region: least violation instead
            A2 = np.c_[Jg[kg_all], -np.ones(kg_all.size)]
            return linprog(
                np.r_[np.zeros(n), 1.0], A_ub=A2, b_ub=-g[kg_all], bounds=bounds + [(0, None)], method="highs"
            )
        if lp.status != 0:
            return lp
        dx, t = lp.x[:n], lp.x[-1]
        broken_v = kv_all[(v[kv_all] + Jv[kv_all] @ dx) < t - 1e-9 * max(1.0, abs(t))]
        broken_g = kg_all[(g[kg_all] + Jg[kg_all] @ dx) > 1e-12]
        new_v, new_g = np.setdiff1d(broken_v, kv), np.setdiff1d(broken_g, kg)
        if new_v.size == 0 and new_g.size == 0:
            return lp
        kv, kg = np.union1d(kv, new_v[:_FIRST_ROWS]), np.union1d(kg, new_g[:_FIRST_ROWS])
    return lp


def maximize_least(
    values: Callable, geometry: Callable, x0: np.ndarray, *, radius, scale: float, lower=None, upper=None
) -> Step:
    """Maximize ``min(values(x))`` subject to ``geometry(x) <= 0``, from ``x0``; both callables return the value and
    its Jacobian (:func:`with_jacobian`). ``radius``: the first trust region (one, or one per variable); ``scale``: the
    objective's size (N), for the merit that trades it against the geometry; ``lower``/``upper``: bounds on the
    variables (None: free)."""
    x = np.asarray(x0, dtype=float)
    n = x.size
    lo = np.full(n, -np.inf) if lower is None else np.asarray(lower, dtype=float)
    hi = np.full(n, np.inf) if upper is None else np.asarray(upper, dtype=float)

    def merit(v, g):
        return float(np.min(v)) - _PENALTY * scale * max(0.0, float(np.max(g)))

    v, Jv = _value_and_jacobian(values, x)
    g, Jg = _value_and_jacobian(geometry, x)
    radius = np.broadcast_to(np.asarray(radius, dtype=float), x.shape)
    best, delta, steps = merit(v, g), radius.copy(), 0  # a writable trust region (the broadcast is a read-only view)
    for _ in range(_MAX_STEPS):
        steps += 1  # the steps taken, read after the loop
        bounds = [(max(-delta[i], lo[i] - x[i]), min(delta[i], hi[i] - x[i])) for i in range(n)]
        lp = _linear_step(v, Jv, g, Jg, bounds)
        if (
            lp.status != 0
        ):  # HiGHS gave up on this region (numerical trouble): the point reached stands, judged as it is
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
    return Step(x, float(np.min(v)), float(np.max(g)), steps)
