"""The kinematic requirement: at each angle the spring must give ``k s + F0 >= r``, with
``r = F_min arm - F_ext - min over w in [0, W] of (m w^2 s'' + c w s')`` exact for every speed at once; the
least preload for a rate, the angles between grid points where it is least, and where it binds."""

from __future__ import annotations

import math

import numpy as np

from ..._core.units import RPM
from ._problem import STEP, Grid, Problem
from ._quadratic import least_quadratic, refine


def requirement(p: Problem, s1: np.ndarray, s2: np.ndarray, req: np.ndarray, c: float) -> tuple[np.ndarray, np.ndarray]:
    """r at angles with s', s'' (SI) and ``req = F_min arm - F_ext``, damping c; and the speed of the minimum."""
    g, w = least_quadratic(p.m * s2, c * s1, p.W)
    return req - g, w


def required(p: Problem, grid: Grid, c: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`requirement` on the grid's angles."""
    return requirement(p, grid.s1, grid.s2, grid.req, c)


def slack_at(p: Problem, theta: np.ndarray, k: float, f0: float, c: float) -> np.ndarray:
    """``k s + F0 - r`` at angles ``theta`` (rad), off the grid."""
    s, s1, s2 = p.values(theta)
    r, _ = requirement(p, s1, s2, p.fmin * p.arm(theta) - p.ext, c)
    return k * s + f0 - r


def worst_between(p: Problem, grid: Grid, k: float, f0: float, c: float, count: int = 8) -> list[tuple[float, float]]:
    """Angles off the grid where the slack is least, refined from the grid's ``count`` least local minima:
    [(slack, theta)] sorted by slack."""
    r, _ = required(p, grid, c)
    slack = k * grid.s + f0 - r
    local = np.nonzero((slack <= np.roll(slack, 1)) & (slack <= np.roll(slack, -1)))[0]
    local = local[np.argsort(slack[local])][:count]
    ts, vals = refine(lambda t: slack_at(p, t, k, f0, c), grid.theta[local], STEP)
    return sorted(zip(vals.tolist(), (np.mod(ts, 2 * math.pi)).tolist(), strict=True))


def preload_kinematic(p: Problem, grid: Grid, k: float, polish: bool = False) -> float:
    """The least preload that holds with rate k (on the grid; ``polish``: also between grid points), and at
    least ``[limits] min_preload``."""
    c = p.damping(k)
    r, _ = required(p, grid, c)
    f0 = float(np.max(r - k * grid.s))
    if polish:
        worst = worst_between(p, grid, k, f0, c)
        if worst and worst[0][0] < 0.0:
            f0 -= worst[0][0]
    return max(f0, p.f0_lo)


def _runs(on: np.ndarray) -> list[list[int]]:
    """[first, last] index of each run of True in ``on``, a run across the end joined to the first."""
    n = len(on)
    runs, i = [], 0
    while i < n:
        if on[i]:
            j = i
            while j + 1 < n and on[j + 1]:
                j += 1
            runs.append([i, j])
            i = j + 1
        else:
            i += 1
    if len(runs) > 1 and runs[0][0] == 0 and runs[-1][1] == n - 1:  # a run across 0 deg
        runs[0][0] = runs.pop()[0]
    return runs


def binding(p: Problem, grid: Grid, k: float, f0: float) -> tuple[tuple[float, float, float], ...]:
    """Where the kinematic constraint is active (slack within 1e-6 of the force scale), as
    (start_deg, end_deg, speed_rpm): runs of grid angles (a dwell) and single angles refined off the grid."""
    c = p.damping(k)
    tol = 1e-6 * max(1.0, abs(k * p.s_max + f0))
    r, w = required(p, grid, c)
    theta = grid.theta
    span = lambda a, b: (theta[b] - theta[a]) % (2 * math.pi)  # noqa: E731
    out = [
        (math.degrees(theta[a]), math.degrees(theta[b]), float(max(w[a], w[b])) / RPM)
        for a, b in _runs(k * grid.s + f0 - r <= tol)
        if span(a, b) >= 2.5 * STEP
    ]
    for v, t in worst_between(p, grid, k, f0, c):
        if v > tol:
            continue
        deg = math.degrees(t)
        if any((a <= deg <= b) if a <= b else (deg >= a or deg <= b) for a, b, _ in out):
            continue
        if any(abs((deg - a + 180.0) % 360.0 - 180.0) < 1e-4 for a, _, _ in out):
            continue
        _, s1, s2 = p.values(t)
        _, wt = requirement(p, s1, s2, p.fmin * p.arm(t) - p.ext, c)
        out.append((deg, deg, float(wt[0]) / RPM))
    out = [(round(a, 6) % 360.0, round(b, 6) % 360.0, round(wv, 9)) for a, b, wv in sorted(out)]
    return tuple(out[:12])
