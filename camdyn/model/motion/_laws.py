"""The named motion laws, each written as acceleration pieces with closed-form integrals.

Every law is a sum of pieces ``a(u) = sum_k c_k u^k + p1 cos(w u) + p2 sin(w u)`` on the normalized rise
``x in [0, 1]``; velocity and displacement are their exact integrals, so s, s', s'', s''' are closed form for
all nine laws (the tests check them against autodiff).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike


@dataclass(frozen=True)
class _Piece:
    """Acceleration piece on x in [x0, x1]: a(u) = sum c_k u^k + p1 cos(w u) + p2 sin(w u), u = x - x0."""

    x0: float
    x1: float
    c: tuple[float, ...] = ()
    w: float = 0.0
    p1: float = 0.0
    p2: float = 0.0


_NC = 6  # polynomial coefficients per piece (4567 acceleration is quintic)
_PI = math.pi

# Unit-amplitude acceleration shapes; amplitudes are rescaled below so that y(1) = 1.
_LAW_PIECES: dict[str, tuple[list[_Piece], float]] = {
    # law: (pieces, initial normalized velocity)
    "dwell": ([_Piece(0.0, 1.0)], 0.0),
    "constant-velocity": ([_Piece(0.0, 1.0)], 1.0),
    "constant-acceleration": ([_Piece(0.0, 0.5, (1.0,)), _Piece(0.5, 1.0, (-1.0,))], 0.0),
    "harmonic": ([_Piece(0.0, 1.0, w=_PI, p1=1.0)], 0.0),
    "cycloidal": ([_Piece(0.0, 1.0, w=2 * _PI, p2=1.0)], 0.0),
    "polynomial-345": ([_Piece(0.0, 1.0, (0.0, 60.0, -180.0, 120.0))], 0.0),
    "polynomial-4567": ([_Piece(0.0, 1.0, (0.0, 0.0, 420.0, -1680.0, 2100.0, -840.0))], 0.0),
    # Norton: sine ramps of period 1/2 joined by constant acceleration (peak Ca = 4.8881)
    "modified-trapezoid": (
        [
            _Piece(0.0, 0.125, w=4 * _PI, p2=1.0),
            _Piece(0.125, 0.375, (1.0,)),
            _Piece(0.375, 0.625, w=4 * _PI, p1=1.0),
            _Piece(0.625, 0.875, (-1.0,)),
            _Piece(0.875, 1.0, w=4 * _PI, p1=-1.0),
        ],
        0.0,
    ),
    # Norton: sine of period 1/2 for the first and last eighths, period 3/2 between (peak Ca = 5.5280)
    "modified-sine": (
        [
            _Piece(0.0, 0.125, w=4 * _PI, p2=1.0),
            _Piece(0.125, 0.875, w=4 * _PI / 3, p1=1.0),
            _Piece(0.875, 1.0, w=4 * _PI, p1=-1.0),
        ],
        0.0,
    ),
}

LAWS: tuple[str, ...] = tuple(_LAW_PIECES)


def _piece_eval(xp, u, c, w, p1, p2, y0, v0):
    """Normalized y, y', y'', y''' of one piece at local coordinate u (works for numpy and jax arrays); c holds
    the acceleration's polynomial coefficients (_NC for the named laws, more for a polynomial of high degree)."""
    k = np.arange(c.shape[-1])

    def horner(
        coef: np.ndarray | jax.Array,
    ) -> np.ndarray | jax.Array:  # sum_i coef[..., i] u^i, without powers (autodiff-safe at u = 0)
        acc = coef[..., -1]
        for i in range(coef.shape[-1] - 2, -1, -1):
            acc = acc * u + coef[..., i]
        return acc

    a = horner(c)
    j = horner((c * k)[..., 1:])
    v = u * horner(c / (k + 1))
    y = u * u * horner(c / ((k + 1) * (k + 2)))
    wu = w * u
    s, co = xp.sin(wu), xp.cos(wu)
    a = a + p1 * co + p2 * s
    j = j - p1 * w * s + p2 * w * co
    v = v0 + v + (p1 / w) * s + (p2 / w) * (1.0 - co)
    y = y0 + v0 * u + y + (p1 / w**2) * (1.0 - co) + (p2 / w**2) * (wu - s)
    return y, v, a, j


@dataclass(frozen=True)
class _LawTable:
    """Numeric piece table of one law, normalized so that y(0) = 0 and y(1) = 1 (0 for dwell)."""

    x0: np.ndarray
    c: np.ndarray  # (n, _NC)
    w: np.ndarray
    p1: np.ndarray
    p2: np.ndarray
    y0: np.ndarray
    v0: np.ndarray


def _build_law(name: str) -> _LawTable:
    pieces, v_start = _LAW_PIECES[name]
    n = len(pieces)
    c = np.zeros((n, _NC))
    for i, p in enumerate(pieces):
        c[i, : len(p.c)] = p.c
    w = np.array([p.w if p.w else 1.0 for p in pieces])
    p1 = np.array([p.p1 for p in pieces])
    p2 = np.array([p.p2 for p in pieces])
    x0 = np.array([p.x0 for p in pieces])
    y0, v0 = np.zeros(n), np.zeros(n)
    y, v = 0.0, v_start
    for i, p in enumerate(pieces):  # integrate piece by piece so that y and y' are continuous
        y0[i], v0[i] = y, v
        yy, vv, _, _ = _piece_eval(np, np.array(p.x1 - p.x0), c[i], w[i], p1[i], p2[i], y, v)
        y, v = float(yy), float(vv)
    if name != "dwell":
        scale = 1.0 / y
        c, p1, p2, y0, v0 = c * scale, p1 * scale, p2 * scale, y0 * scale, v0 * scale
    return _LawTable(x0, c, w, p1, p2, y0, v0)


_LAW_TABLES = {name: _build_law(name) for name in LAWS}


def law(name: str, x: ArrayLike) -> jax.Array:
    """Normalized law ``name`` at x in [0, 1]: (y, y', y'', y''') with y(0) = 0, y(1) = 1."""
    return _law(jnp, name, x)


def law_host(name: str, x: ArrayLike) -> np.ndarray:
    """:func:`law` in numpy (no dispatch or compile cost outside compiled programs)."""
    return _law(np, name, x)


def _law(xp, name: str, x: ArrayLike):
    t = _LAW_TABLES[name]
    x = xp.asarray(x, dtype=float)
    i = xp.clip(xp.searchsorted(xp.asarray(t.x0), x, side="right") - 1, 0, len(t.x0) - 1)
    g = lambda a: xp.asarray(a)[i]  # noqa: E731
    return xp.stack(_piece_eval(xp, x - g(t.x0), g(t.c), g(t.w), g(t.p1), g(t.p2), g(t.y0), g(t.v0)))
