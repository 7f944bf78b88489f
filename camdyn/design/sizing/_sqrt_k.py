"""Damping that follows the rate (c = 2 zeta sqrt(k m)): the peak spring force is then minimized in u = sqrt(k),
where it is convex, with the tie-break towards the largest rate; the same one-dimensional search serves the
dynamic correction."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ..._core.minimize import minimize_bounded
from ._kinematic import preload_kinematic
from ._lp import cut
from ._problem import Grid, Problem

TIE_KIN = 1e-11  # one-dimensional (damping_ratio) ties; the LP's are exact
_CUT_ROUNDS = 6
_BISECTIONS = 40


def _bracket(f: Callable[[float], float], u_lo, u_hi, scan, seeds) -> tuple[float, float]:
    """The interval Brent searches: all of [u_lo, u_hi], or (``scan`` > 0) the neighbours of the best of an even
    scan plus ``seeds``."""
    if not scan:
        return u_lo, u_hi
    grid = np.unique(np.concatenate([np.linspace(u_lo, u_hi, scan), np.clip(np.asarray(seeds, float), u_lo, u_hi)]))
    vals = np.array([f(u) for u in grid])
    i = int(np.argmin(vals))
    return grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]


def _tie_end(f: Callable[[float], float], cache: dict[float, float], u_best: float, cap: float, u_hi: float) -> float:
    """The largest u right of ``u_best`` whose value is still <= ``cap``: over the known points, then bisection."""
    lo, hi = u_best, None
    for u in sorted(u for u in cache if u > u_best):
        if cache[u] <= cap:
            lo = u
        else:
            hi = u
            break
    if hi is not None:
        for _ in range(_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if hi - lo <= 1e-12 * max(1.0, u_hi):
                break
            lo, hi = (mid, hi) if f(mid) <= cap else (lo, mid)
    return lo


def _rises(f: Callable[[float], float], u_a: float, u_b: float, tol: float) -> bool:
    """Whether the peak force rises through [u_a, u_b] rather than staying flat: its value at the midpoint in k
    is above its value at u_a by more than tol / 8 (a rise linear in k gives tol / 2 there, a flat tie rounding)."""
    u_mid = math.sqrt(0.5 * (u_a * u_a + u_b * u_b))
    return f(u_mid) - f(u_a) > 0.125 * tol


def minimize_in_sqrt_k(
    peak_of: Callable[[float], float],
    u_lo: float,
    u_hi: float,
    rtol: float,
    scan: int = 0,
    seeds: Sequence[float] = (),
    flat_of: Callable[[float], float] | None = None,
) -> float:
    """argmin of ``peak_of(u)`` on [u_lo, u_hi] (bounded Brent, after a scan of ``scan`` points where given), ties
    broken towards the largest u whose value is within ``rtol`` of the least.

    Where the least rate u_lo itself reaches the least value (within rtol) and the peak force rises from there
    (judged by ``flat_of``, default ``peak_of``: :func:`_rises`), there is no tie and the answer is u_lo: the
    rtol walk alone would stop wherever the rise reaches rtol, a rate made by the tolerance."""
    cache: dict[float, float] = {}

    def f(u: float) -> float:
        u = float(min(max(u, u_lo), u_hi))
        if u not in cache:
            cache[u] = float(peak_of(u))
        return cache[u]

    a, b = _bracket(f, u_lo, u_hi, scan, seeds)
    if b > a:
        f(minimize_bounded(f, a, b, xatol=1e-10 * max(1.0, u_hi))[0])
    for u in (u_lo, u_hi, *seeds):
        f(u)
    u_best = min(cache, key=lambda u: (cache[u], -u))
    best = cache[u_best]
    tol = rtol * max(1.0, abs(best))
    end = _tie_end(f, cache, u_best, best + tol, u_hi)
    if end > u_lo and cache[u_lo] <= best + tol and _rises(flat_of or f, u_lo, end, tol):
        return u_lo
    return end


def ratio_answer(p: Problem, grid: Grid) -> tuple[float, float, Grid]:
    """(k, F0, the refined grid) of the kinematic problem with c = 2 zeta sqrt(k m): for each k the least preload
    is closed form, and the peak force, convex in sqrt(k), is minimized exactly in sqrt(k); cutting planes refine
    the angles where the answer is violated between grid points."""
    k_lo = p.k_lo
    peak_lo = k_lo * p.s_max + preload_kinematic(p, grid, k_lo)
    k_hi = max(k_lo, (peak_lo - grid.req[grid.i_min]) / (p.s_max - grid.s[grid.i_min]))
    k_hi = max(k_hi, 2.0 * k_lo, 1e-12)
    for _ in range(_CUT_ROUNDS):
        u = minimize_in_sqrt_k(
            lambda u, g=grid: u * u * p.s_max + preload_kinematic(p, g, u * u),
            math.sqrt(k_lo),
            math.sqrt(k_hi),
            TIE_KIN,
            flat_of=lambda u, g=grid: (
                u * u * p.s_max + preload_kinematic(p, g, u * u, polish=True)
            ),  # between grid angles too
        )
        k = u * u
        f0 = preload_kinematic(p, grid, k)
        refined = cut(p, grid, k, f0, p.damping(k))
        if refined is None:
            break
        grid = refined
    return k, preload_kinematic(p, grid, k, polish=True), grid
