"""Evaluating jitted per-point helpers over arrays of any length, padded so each compiles once."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

N_GRID = 2048  # path points of the synthesis table ("path point i" in messages; Ye & Smith's index I)


def padded(
    fn: Callable[..., Any], obj: Any, u: Sequence[float] | np.ndarray, *more: Sequence[float] | np.ndarray
) -> Any:
    """``fn(obj, u, *more)`` for u of any length, padded to a multiple of N_GRID so each jitted helper compiles
    once per mechanism structure instead of once per array length."""
    u = np.atleast_1d(np.asarray(u, dtype=float))
    n = len(u)
    size = -(-n // N_GRID) * N_GRID
    pad = lambda x: jnp.asarray(np.concatenate([x, np.resize(x, size - n)]) if size > n else x)  # noqa: E731
    out = fn(obj, pad(u), *(pad(np.atleast_1d(np.asarray(m, dtype=float))) for m in more))
    return jax.tree_util.tree_map(lambda x: np.asarray(x)[:n], out)


def where_point(i: int, n: int = N_GRID) -> str:
    """The path point ``i`` of the synthesis table as an error location."""
    return f"path point {i} (u = {i / n:.4f})"


@eqx.filter_jit
def _vmap_jit(fn, u):
    return jax.vmap(fn)(u)


def vmap_scalar(fn: Callable[[jax.Array], jax.Array], u: ArrayLike) -> np.ndarray:
    """numpy values of a scalar-u function (an equinox bound method) over the array u."""
    return np.asarray(_vmap_jit(fn, jnp.asarray(u)))
