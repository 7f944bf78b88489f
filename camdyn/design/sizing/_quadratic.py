"""Small numerical pieces of sizing: the extremes of ``a w^2 + b w`` over a speed range in closed form, and a
vectorized local minimization in the angle."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from jax.typing import ArrayLike


def least_quadratic(a: np.ndarray, b: np.ndarray, w_top: float) -> tuple[np.ndarray, np.ndarray]:
    """min over w in [0, w_top] of a w^2 + b w, and the speed where it is reached (vectorized)."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    g_top = a * w_top * w_top + b * w_top
    with np.errstate(invalid="ignore", divide="ignore"):
        wv = np.where((a > 0) & (b < 0), -b / np.where(a > 0, 2 * a, 1.0), np.inf)
        gv = np.where(wv < w_top, -b * b / np.where(a > 0, 4 * a, 1.0), np.inf)
    cand = np.stack([np.zeros_like(a), g_top, gv])
    i = np.argmin(cand, axis=0)
    w = np.choose(i, [np.zeros_like(a), np.full_like(a, w_top), np.where(np.isfinite(wv), wv, 0.0)])
    return np.min(cand, axis=0), w


def most_quadratic(a: np.ndarray, b: np.ndarray, w_top: float) -> tuple[np.ndarray, np.ndarray]:
    """max over w in [0, w_top] of a w^2 + b w, and the speed where it is reached."""
    g, w = least_quadratic(-np.asarray(a, float), -np.asarray(b, float), w_top)
    return -g, w


def refine(
    fn: Callable[[np.ndarray], np.ndarray], t0: ArrayLike, h: float, rounds: int = 3, points: int = 41
) -> tuple[np.ndarray, np.ndarray]:
    """Vectorized local minimization of fn (array -> array) in [t0 - h, t0 + h] for each start in t0: a grid
    of ``points`` angles, then again around the best, ``rounds`` times (resolution 2 h / 20^rounds)."""
    ts = np.asarray(t0, dtype=float)
    if ts.size == 0:
        return ts, ts
    offsets = np.linspace(-1.0, 1.0, points)
    best_v = np.asarray(fn(ts), dtype=float)
    for _ in range(rounds):
        cand = ts[:, None] + h * offsets[None, :]
        v = np.asarray(fn(cand.ravel()), dtype=float).reshape(cand.shape)
        j = np.argmin(v, axis=1)
        vj = v[np.arange(len(ts)), j]
        better = vj < best_v
        ts = np.where(better, cand[np.arange(len(ts)), j], ts)
        best_v = np.minimum(vj, best_v)
        h *= 2.0 / (points - 1)
    return ts, best_v
