"""Evaluating compiled per-point helpers over arrays of any length, padded so each compiles once.

The helpers are :func:`camdyn._core.jit.cached_jit` programs whose arguments carry the case's numbers as arrays:
one stored program serves every path and mechanism of a kind, and a later process loads it instead of tracing.
Their inputs stay numpy (``jnp.asarray`` of a numpy array is itself a small compiled program in every process).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import equinox as eqx
import jax
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import cached_jit

N_GRID = 2048  # path points of the synthesis table ("path point i" in messages; Ye & Smith's index I)


def padded(
    fn: Callable[..., Any], obj: Any, u: Sequence[float] | np.ndarray, *more: Sequence[float] | np.ndarray
) -> Any:
    """``fn(obj, u, *more)`` for u of any length, padded to a multiple of N_GRID so each compiled helper serves
    every array length."""
    u = np.atleast_1d(np.asarray(u, dtype=float))
    n = len(u)
    size = -(-n // N_GRID) * N_GRID
    pad = lambda x: np.concatenate([x, np.resize(x, size - n)]) if size > n else x  # noqa: E731
    out = fn(obj, pad(u), *(pad(np.atleast_1d(np.asarray(m, dtype=float))) for m in more))
    return jax.tree_util.tree_map(lambda x: np.asarray(x)[:n], out)


def where_point(i: int, n: int = N_GRID) -> str:
    """The path point ``i`` of the synthesis table as an error location."""
    return f"path point {i} (u = {i / n:.4f})"


@cached_jit
def _vmap_method(obj: eqx.Module, name: str, u: jax.Array) -> jax.Array:
    """``obj.<name>`` of scalar u, mapped over u: the method by its name, so the stored program's key is the
    same in every process (a function object's text holds its address)."""
    return jax.vmap(getattr(obj, name))(u)


_vmap_jit = eqx.filter_jit(lambda fn, u: jax.vmap(fn)(u))  # any other function: traced in each process


def vmap_scalar(fn: Callable[[jax.Array], jax.Array], u: ArrayLike) -> np.ndarray:
    """numpy values of a scalar-u function (an equinox module's bound method: a stored program) over the array u,
    padded to a multiple of N_GRID."""
    obj, func = getattr(fn, "__self__", None), getattr(fn, "__func__", None)
    if isinstance(obj, eqx.Module) and func is not None and getattr(type(obj), func.__name__, None) is not None:
        return padded(lambda o, v: _vmap_method(o, func.__name__, v), obj, np.asarray(u, dtype=float))
    return np.asarray(_vmap_jit(fn, np.asarray(u)))
