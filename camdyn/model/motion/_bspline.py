"""The ``bspline`` segment law: the normalized lift y(u), u in [0, 1], as a clamped B-spline of degree 5 on
uniform knots. Its control points enter y and every derivative linearly, which is what the optimizer of
:mod:`camdyn.design.optimize` works with (:func:`basis`); evaluation goes through the same acceleration-piece
tables as the named laws (:func:`bspline_table`), so a bspline program jits, vmaps and differentiates alike."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from jax.typing import ArrayLike

from ..._core.stored import stored_by_arguments
from ...schema.motion import BSPLINE_DEGREE
from ._laws import _LawTable, law_host

CLAMPED = 3  # control points held at each end: y, y', y'' meet a dwell (0 at the start, 1 at the end)


def knots(n: int) -> np.ndarray:
    """The clamped knot vector of ``n`` control points: degree + 1 repeated ends, uniform inside."""
    p = BSPLINE_DEGREE
    inner = np.linspace(0.0, 1.0, n - p + 1)
    return np.r_[np.zeros(p), inner, np.ones(p)]


def basis(u: ArrayLike, n: int, order: int = 0) -> np.ndarray:
    """The ``order``-th derivative (per unit u) of each of the ``n`` basis functions at ``u``: (len(u), n)."""
    from scipy.interpolate import BSpline  # only a bspline segment needs it: a check without one saves 0.3 s

    u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
    eye = np.eye(n)
    spl = BSpline(knots(n), eye, BSPLINE_DEGREE, extrapolate=False)
    out = spl.derivative(order)(u) if order else spl(u)
    return np.nan_to_num(out)


@stored_by_arguments  # an unchanged case reads the table an earlier check stored: scipy.interpolate takes 0.3 s
def bspline_table(coefficients: Sequence[float] | np.ndarray) -> _LawTable:
    """The acceleration-piece table of y(u) (``_piece_eval``'s form): one cubic acceleration per knot span, with
    y and y' at the span's start."""
    from scipy.interpolate import BSpline, PPoly

    c = np.asarray(coefficients, dtype=float)
    spl = BSpline(knots(len(c)), c, BSPLINE_DEGREE)
    acc = PPoly.from_spline(spl.derivative(2))
    starts = acc.x[:-1]
    keep = np.nonzero(np.diff(acc.x) > 0)[0]
    x0 = starts[keep]
    coef = acc.c[::-1, keep].T  # ascending powers of the local coordinate u - x0
    one = np.ones(len(x0))
    return _LawTable(x0=x0, c=coef, w=one, p1=0 * one, p2=0 * one, y0=spl(x0), v0=spl.derivative(1)(x0))


def fit_law(name: str, n: int) -> np.ndarray:
    """The ``n`` control points of the clamped spline nearest (least squares on 400 points) to the named law's
    normalized lift; the first and last three are exactly 0 and 1."""
    u = np.linspace(0.0, 1.0, 401)
    y = law_host(name, u)[0]
    B = basis(u, n)
    fixed = np.r_[np.zeros(CLAMPED), np.ones(CLAMPED)]
    free = slice(CLAMPED, n - CLAMPED)
    rhs = y - B[:, -CLAMPED:] @ fixed[CLAMPED:]
    z, *_ = np.linalg.lstsq(B[:, free], rhs, rcond=None)
    return np.r_[fixed[:CLAMPED], z, fixed[CLAMPED:]]
