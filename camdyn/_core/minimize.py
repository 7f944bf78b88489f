"""Bounded scalar minimization: a faithful port of scipy's ``minimize_scalar(method="bounded")``.

Why a port: ``scipy.optimize`` takes about 0.25 s to import (it pulls in scipy.linalg, scipy.sparse and
scipy.fft), and the kinematic jump speed polishes its grid minimum with this method on every ``check``.
Same arithmetic, step by step, as scipy 1.17's ``_minimize_scalar_bounded`` (Brent's method with golden-section
steps, Forsythe, Malcolm & Moler's ``fmin``): the same points are evaluated in the same order, so the results are
bit-identical to scipy's (``tests/test_minimize.py`` holds them against it).
"""

from __future__ import annotations

import math
from collections.abc import Callable

_SQRT_EPS = math.sqrt(2.2e-16)
_GOLDEN_MEAN = 0.5 * (3.0 - math.sqrt(5.0))


def _sign_or_one(d: float) -> float:
    """``np.sign(d) + (d == 0)``: 1 for d >= 0, -1 for d < 0, NaN for NaN."""
    return 1.0 if d >= 0.0 else -1.0 if d < 0.0 else math.nan


def minimize_bounded(
    fun: Callable[[float], float], lo: float, hi: float, xatol: float = 1e-5, maxiter: int = 500
) -> tuple[float, float, int]:
    """(x, fun(x), evaluations) at a local minimum of ``fun`` on [``lo``, ``hi``], within ``xatol`` in x:
    scipy's ``minimize_scalar(fun, bounds=(lo, hi), method="bounded", options={"xatol": xatol})``."""
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError("minimize_bounded: the bounds must be finite")
    if lo > hi:
        raise ValueError("minimize_bounded: the lower bound exceeds the upper bound")
    a, b = float(lo), float(hi)
    fulc = a + _GOLDEN_MEAN * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = fun(x)
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1

    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:  # try a parabolic fit
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (b - xf):  # the parabola is acceptable
                rat = (p + 0.0) / q
                x = xf + rat
                if (x - a) < tol2 or (b - x) < tol2:
                    rat = tol1 * _sign_or_one(xm - xf)
            else:
                golden = True
        if golden:
            e = (a - xf) if xf >= xm else (b - xf)
            rat = _GOLDEN_MEAN * e

        x = xf + _sign_or_one(rat) * _nan_max(abs(rat), tol1)
        fu = fun(x)
        num += 1

        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if (fu <= fnfc) or (nfc == xf):
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif (fu <= ffulc) or (fulc == xf) or (fulc == nfc):
                fulc, ffulc = x, fu

        xm = 0.5 * (a + b)
        tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxiter:
            break
    return xf, fx, num


def _nan_max(u: float, v: float) -> float:
    """``np.maximum(u, v)``: NaN if either is."""
    return u if (u >= v or math.isnan(u)) else v
