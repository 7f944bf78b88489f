"""The kinematic answer at constant damping: a linear program in (k, F0) with cutting planes, checked against
its closed form, and the tie-break in closed form."""

from __future__ import annotations

import numpy as np

from ..._core.errors import NumericalError
from ..._core.linprog import INFEASIBLE, OPTIMAL, LinearProgram
from ._kinematic import preload_kinematic, required, worst_between
from ._problem import Grid, Problem

_LP_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
_CUT_ROUNDS = 8


def cut(p: Problem, grid: Grid, k: float, f0: float, c: float) -> Grid | None:
    """The grid with the off-grid angles where (k, f0) violates the kinematic constraint by more than 1e-9 of
    the peak added (cutting planes); None where there is none."""
    tol = 1e-9 * max(1.0, abs(k * p.s_max + f0))
    new = [t for v, t in worst_between(p, grid, k, f0, c) if v < -tol]
    return grid.with_angles(p, new) if new else None


def _solve(p: Problem, grid: Grid, c) -> tuple[float, float]:
    """(k, F0) of the LP on the grid: the least peak force, ties broken to the least preload."""
    s = grid.s
    r, _ = required(p, grid, c)
    a_ub = -np.column_stack([s / p.s_max, np.ones_like(s)])  # variables: k s_max (N), F0 (N)
    program = LinearProgram(np.ones(2), np.array([p.k_lo * p.s_max, p.f0_lo]), np.full(2, np.inf), _LP_OPTIONS)
    program.add(a_ub, -r)
    answer = program.solve()
    if answer.status != OPTIMAL:
        what = "infeasible" if answer.status == INFEASIBLE else "not solvable (numerical trouble)"
        raise NumericalError("sizing", f"the linear program failed: HiGHS found it {what}")
    fun = float(np.sum(answer.x))
    gap = p.s_max - s
    peak_req = float(np.max(r + p.k_lo * gap))
    peak = max(peak_req, p.k_lo * p.s_max + p.f0_lo)  # min_preload: the peak k s_max + F0 grows with k at F0 = f0_lo
    if abs(fun - peak) > 1e-7 * max(1.0, abs(peak)):
        raise NumericalError(
            "sizing", f"the linear program's least peak force {fun:.10g} disagrees with the closed form {peak:.10g}"
        )
    tie = gap > 1e-12 * p.s_max
    k = max(p.k_lo, float(np.min((peak - r[tie]) / gap[tie]))) if tie.any() else p.k_lo
    k = max(p.k_lo, min(k, (peak - p.f0_lo) / p.s_max))  # no tie beyond the rate where F0 would fall below f0_lo
    return k, peak - k * p.s_max


def lp(p: Problem, grid: Grid, c: float) -> tuple[float, float, Grid]:
    """The kinematic LP at constant damping c, with cutting planes and the tie-break: (k, F0, the refined grid).

    HiGHS solves ``min k s_max + F0 s.t. s_i k + F0 >= r_i, k >= k_lo``. Its value is also closed form: the
    peak ``P(k) = max_i (r_i + k (s_max - s_i))`` never decreases with k, so P* = P(k_lo), and the springs
    reaching it are k in [k_lo, k_end], ``k_end = min over s_i < s_max of (P* - r_i) / (s_max - s_i)``. The
    tie-break takes k_end, the least preload F0 = P* - k_end s_max: what a second, lexicographic LP minimizing
    F0 at the optimal peak returns, without its tolerance. The LP value is checked against P* (1e-7).
    """
    for _ in range(_CUT_ROUNDS):
        k, f0 = _solve(p, grid, c)
        refined = cut(p, grid, k, f0, c)
        if refined is None:
            return k, f0, grid
        grid = refined
    return k, preload_kinematic(p, grid, k, polish=True), grid
