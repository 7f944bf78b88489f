"""The cubic Hermite interpolant of samples with their slopes: its Taylor coefficients per step (the valve fast
path's input between its fine angles), its value and slope inside a step, and its highest point (a diffrax flight's
top between its saved angles)."""

from __future__ import annotations

import numpy as np


def hermite_taylor(
    u: np.ndarray, du: np.ndarray, h: float | np.ndarray, du_end: np.ndarray | None = None
) -> np.ndarray:
    """The cubic through each step's end values ``u`` and slopes ``du`` (steps ``h`` wide: one width, or one per
    step), as its Taylor coefficients at the step's start (value, first, second, third derivative): (steps, 4).
    ``du_end``: the slopes as the steps ending at each sample see them, where the slope jumps there (``du`` the
    slopes past it)."""
    u0, u1, d0, d1 = u[:-1], u[1:], du[:-1], (du if du_end is None else du_end)[1:]
    c2 = (3.0 * (u1 - u0) / h - 2.0 * d0 - d1) / h
    c3 = (d0 + d1 - 2.0 * (u1 - u0) / h) / h**2
    return np.stack([u0, d0, 2.0 * c2, 6.0 * c3], axis=1)


def hermite_at(
    taylor: np.ndarray, u: np.ndarray, du: np.ndarray, steps: np.ndarray, taus: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The value and slope ``taus`` into ``steps`` (arrays of one shape) of the cubic Hermite whose Taylor
    coefficients per step are ``taylor`` (:func:`hermite_taylor` of the samples ``u`` and slopes ``du``): the samples
    themselves on the nodes (``taus`` 0), each step's cubic between them."""
    a0, a1, a2, a3 = taylor[np.minimum(steps, len(taylor) - 1)].T
    value = np.where(taus > 0.0, a0 + a1 * taus + a2 * taus**2 / 2 + a3 * taus**3 / 6, u[steps])
    return value, np.where(taus > 0.0, a1 + a2 * taus + a3 * taus**2 / 2, du[steps])


def hermite_top(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> float:
    """The highest value of the cubic Hermite interpolant through ``x`` and its slopes ``v`` at increasing ``t``
    (a repeated ``t`` counted once): the samples' and each step's interior maxima, where its derivative is 0."""
    keep = np.append(np.diff(t) > 0.0, True)
    t, x, v = t[keep], x[keep], v[keep]
    h = np.diff(t)
    x0, v0, x2, x3 = hermite_taylor(x, v, h).T
    # p'(u) = v0 + x2 u + x3 u^2 / 2 on (0, h): its roots, where a cubic's top within a step can lie
    a, b = 0.5 * x3, x2
    disc = np.maximum(b * b - 4.0 * a * v0, 0.0)
    q = -0.5 * (b + np.copysign(np.sqrt(disc), b))
    with np.errstate(divide="ignore", invalid="ignore"):
        roots = np.stack([np.where(a != 0.0, q / a, -v0 / b), np.where(q != 0.0, v0 / q, np.nan)])
    ok = np.isfinite(roots) & (roots > 0.0) & (roots < h)
    u = np.where(ok, roots, 0.0)
    top = np.where(ok, x0 + v0 * u + x2 * u**2 / 2.0 + x3 * u**3 / 6.0, -np.inf)
    return float(max(np.max(x), np.max(top, initial=-np.inf)))
