"""A zero of a function that falls through it, bracketed to a width: the ITP method."""

from __future__ import annotations

import math
from collections.abc import Callable


def itp_zero(
    f: Callable[[float], float],
    lo: float,
    hi: float,
    f_lo: float,
    f_hi: float,
    width: float,
    not_finite: Callable[[float], Exception],
) -> float:
    """The midpoint of a bracket of ``f``'s zero at most ``width`` wide, from ``f(lo) = f_lo > 0 >= f_hi = f(hi)``:
    the ITP method (interpolate, truncate, project; Oliveira & Takahashi, ACM TOMS 47, 2021) with its usual constants
    (kappa1 = 0.2 / (hi - lo), kappa2 = 2, n0 = 1). Each point is the regula falsi's, moved towards the midpoint (by at
    least 0.45 ``width``) and kept within the bisection's worst case, so it takes at most one point more than
    bisection and, where ``f`` is smooth, a few. A value of 0 counts as reached; where ``f(x)`` is not finite,
    ``not_finite(x)`` is raised. (A speed search's least force, a rigid follower's lift-off: a dozen lines rather
    than scipy.optimize, whose import costs a ``check`` 0.2-0.4 s.)"""
    n_max = max(0, math.ceil(math.log2((hi - lo) / width))) + 1
    kappa1 = 0.2 / (hi - lo)
    j = 0
    while hi - lo > width * (1.0 + 1e-12):
        mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        radius = max(0.0, 0.5 * width * 2.0 ** (n_max - j) - half)  # how far from the midpoint keeps the worst case
        falsi = (f_hi * lo - f_lo * hi) / (f_hi - f_lo)
        toward = math.copysign(1.0, mid - falsi)
        # kappa1's truncation, and at least 0.45 of the width: the next points fall either side of the zero, not
        # on it, so two of them close a bracket narrower than the width (the regula falsi converges from one side)
        delta = max(kappa1 * (hi - lo) ** 2, 0.45 * width)
        x = falsi + toward * delta if delta <= abs(mid - falsi) else mid
        if abs(x - mid) > radius:
            x = mid - toward * radius
        fx = f(x)
        if not math.isfinite(fx):
            raise not_finite(x)
        if fx <= 0.0:
            hi, f_hi = x, fx
        else:
            lo, f_lo = x, fx
        j += 1
    return 0.5 * (lo + hi)
