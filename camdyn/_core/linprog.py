"""Linear programs by HiGHS (``highspy``): ``min cost @ x`` subject to rows ``a @ x <= b`` added in rounds, within
bounds on ``x``, each solve starting from the last basis. optimize's sequential linear programs and the spring
sizing's check of its closed form both solve through it (scipy's ``linprog`` calls the same HiGHS, after a 0.5 s
import of scipy.optimize)."""

from __future__ import annotations

from typing import NamedTuple

import highspy
import numpy as np
from highspy._core import _Highs  # highspy.__all__ exports it; its stub names it here only

OPTIMAL, INFEASIBLE, FAILED = 0, 2, 4  # an answer's status (scipy's ``linprog`` codes)


class Answer(NamedTuple):
    """A linear program's answer: its status (:data:`OPTIMAL`, :data:`INFEASIBLE` or :data:`FAILED`) and the
    variables (NaN unless optimal)."""

    status: int
    x: np.ndarray


class LinearProgram:
    """``min cost @ x`` subject to rows ``a @ x <= b`` added in rounds, within bounds on ``x`` (``-inf``, ``inf``:
    none); each :meth:`solve` starts from the basis of the last (HiGHS' dual simplex: the rows a round adds cost a
    few pivots, where a new program would start over: a fifth of the time of ``scipy.optimize.linprog`` on
    ``optimize``'s programs). ``options``: HiGHS options by name (tolerances, say)."""

    def __init__(
        self, cost: np.ndarray, lower: np.ndarray, upper: np.ndarray, options: dict[str, float] | None = None
    ) -> None:
        # the binding's class: highspy.Highs adds Python callbacks and prints HiGHS' banner on stdout (where a
        # --json document goes)
        self._h = _Highs()
        self._h.setOptionValue("output_flag", False)
        for name, value in (options or {}).items():
            self._h.setOptionValue(name, value)
        cost = np.asarray(cost, dtype=float)
        self._n = cost.size
        self._h.addVars(self._n, np.asarray(lower, dtype=float), np.asarray(upper, dtype=float))
        self._h.changeColsCost(self._n, np.arange(self._n, dtype=np.int32), cost)

    def add(self, a: np.ndarray, b: np.ndarray) -> None:
        """The rows ``a @ x <= b`` (dense)."""
        m = a.shape[0]
        if m:
            starts = np.arange(m, dtype=np.int32) * self._n
            index = np.tile(np.arange(self._n, dtype=np.int32), m)
            self._h.addRows(m, np.full(m, -np.inf), b, m * self._n, starts, index, np.ravel(a))

    def solve(self) -> Answer:
        self._h.run()
        status = self._h.getModelStatus()
        if status == highspy.HighsModelStatus.kOptimal:
            return Answer(OPTIMAL, np.asarray(self._h.getSolution().col_value))
        code = INFEASIBLE if status == highspy.HighsModelStatus.kInfeasible else FAILED
        return Answer(code, np.full(self._n, np.nan))
