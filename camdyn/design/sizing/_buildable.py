"""``size --buildable``: the least peak spring force over springs that can be built within ``[spring]``.

For every rate the sizer knows the least preload that holds (kinematic, or the dynamic model's for a compliant
train), and the spring designer knows the largest preload a buildable spring of that rate can give
(:func:`camdyn.design.spring.case_max_preload`; every lower preload is buildable too). A rate is feasible where
the first does not exceed the second; the answer is the feasible rate with the least peak spring force
``k s_max + F0``: a scan over rates a spring can have (log-spaced), refined by golden section between the best
scanned rate's neighbours.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from ..._core.errors import InputError
from ..._core.units import rate_from_si, rate_to_si
from ..spring import case_max_preload
from ._dynamic import Dynamic
from ._kinematic import preload_kinematic
from ._problem import Grid, Problem

LINEAR_RATES_N_PER_MM = (0.05, 2000.0)  # the rates a helical compression spring of camdyn's wire sizes can have
_N_SCAN = 41


def _rate_range(case, p: Problem) -> tuple[float, float]:
    """The scan's rates in the case's units (N/mm; N*m/rad for an arm: k_lin r^2, the spring at ``lever_arm``)."""
    lo, hi = LINEAR_RATES_N_PER_MM
    if p.osc:
        r = case.spec.spring.lever_arm if case.spec.spring is not None and case.spec.spring.lever_arm else None
        if r is None:
            raise InputError("spring.lever_arm", "an oscillating follower's spring needs [spring] lever_arm to be sized as a part: the distance from the arm pivot to the spring, mm")
        lo, hi = lo * r * r / 1000.0, hi * r * r / 1000.0
    return max(lo, rate_from_si(p.k_lo, p.osc)), hi


def buildable_answer(case, p: Problem, grid: Grid, dynamic: Dynamic | None) -> tuple[float, float]:
    """(k SI, F0) of the buildable spring with the least peak force; :class:`InputError` naming ``[spring]``
    where no rate gives a spring that holds."""

    def least(k_si: float) -> float:
        f0 = preload_kinematic(p, grid, k_si, polish=True) if dynamic is None else dynamic.raised(k_si, dynamic.preload(k_si)[0])
        return max(f0, 0.0)  # a compression spring at zero lift pushes, or touches

    def peak(rate: float) -> float:  # user units in, the peak spring force out; inf where it cannot be built
        k_si = rate_to_si(rate, p.osc)
        top = case_max_preload(case, rate)
        f0 = least(k_si)
        return math.inf if top is None or f0 > top else k_si * p.s_max + f0

    lo, hi = _rate_range(case, p)
    if not lo < hi:
        raise InputError("--min-rate", f"no buildable spring is as stiff as {rate_from_si(p.k_lo, p.osc):g}: camdyn's springs reach {hi:g}")
    rates = np.geomspace(lo, hi, _N_SCAN)
    peaks = np.array([peak(r) for r in rates])
    if not np.isfinite(peaks).any():
        raise InputError("spring", f"no buildable spring holds the follower: at every rate from {lo:.3g} to {hi:.3g} {'N*m/rad' if p.osc else 'N/mm'} the preload it needs exceeds what a spring of that rate within [spring] can give (a larger outside_diameter_max or installed_length, or another material, widens the choice)")
    i = int(np.nanargmin(peaks))
    a, b = math.log(rates[max(i - 1, 0)]), math.log(rates[min(i + 1, len(rates) - 1)])
    res = minimize_scalar(lambda u: peak(math.exp(u)), bounds=(a, b), method="bounded", options={"xatol": 1e-4})
    rate = math.exp(res.x) if res.fun < peaks[i] else rates[i]
    k_si = rate_to_si(rate, p.osc)
    return k_si, least(k_si)
