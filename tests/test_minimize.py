"""camdyn._core.minimize is scipy's bounded Brent, bit for bit: the same minimum, value and evaluation count."""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from camdyn._core.minimize import minimize_bounded

FUNCTIONS = {
    "quadratic": (lambda x: (x - 0.3) ** 2, -1.0, 2.0),
    "quartic, flat bottom": (lambda x: (x - 1.234567) ** 4 + 2.0, 0.0, 3.0),
    "cosine": (lambda x: math.cos(3.0 * x), 0.1, 1.9),
    "kink": (lambda x: abs(x - 0.7) + 0.1 * x, 0.0, 1.0),
    "minimum on the bound": (lambda x: x**3, 0.5, 1.5),
    "capped plateau": (lambda x: min(1.0 / max(abs(x - 0.25), 1e-300), 1e6), 0.2, 0.3),
    "a jump speed's cusp": (lambda x: min(math.sqrt(abs(math.sin(x))) + 5.0, 7.0), -1e-3, 1.2e-3),
}


@pytest.mark.parametrize("name", FUNCTIONS)
@pytest.mark.parametrize("xatol", [1e-5, 1e-10])
def test_same_as_scipy(name, xatol):
    fun, lo, hi = FUNCTIONS[name]
    want = minimize_scalar(fun, bounds=(np.float64(lo), np.float64(hi)), method="bounded", options={"xatol": xatol})
    x, fx, nfev = minimize_bounded(fun, lo, hi, xatol=xatol)
    assert (x, fx, nfev) == (float(want.x), float(want.fun), want.nfev)


def test_maxiter_stops_it_as_scipy_does():
    fun = lambda x: (x - 0.3) ** 2  # noqa: E731
    want = minimize_scalar(fun, bounds=(-1.0, 2.0), method="bounded", options={"xatol": 1e-12, "maxiter": 4})
    assert minimize_bounded(fun, -1.0, 2.0, xatol=1e-12, maxiter=4) == (float(want.x), float(want.fun), 4)


def test_bad_bounds():
    with pytest.raises(ValueError, match="lower bound"):
        minimize_bounded(abs, 1.0, 0.0)
    with pytest.raises(ValueError, match="finite"):
        minimize_bounded(abs, 0.0, math.inf)
