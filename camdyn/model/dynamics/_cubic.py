"""The cubic Hermite interpolant of samples with their slopes, as Taylor coefficients per step: the valve fast
path's input between its fine angles, and the diffrax model's flights between their saved angles."""

from __future__ import annotations

import numpy as np


def hermite_taylor(u: np.ndarray, du: np.ndarray, h: float | np.ndarray) -> np.ndarray:
    """The cubic through each step's end values ``u`` and slopes ``du`` (steps ``h`` wide: one width, or one per
    step), as its Taylor coefficients at the step's start (value, first, second, third derivative): (steps, 4)."""
    u0, u1, d0, d1 = u[:-1], u[1:], du[:-1], du[1:]
    c2 = (3.0 * (u1 - u0) / h - 2.0 * d0 - d1) / h
    c3 = (d0 + d1 - 2.0 * (u1 - u0) / h) / h**2
    return np.stack([u0, d0, 2.0 * c2, 6.0 * c3], axis=1)
