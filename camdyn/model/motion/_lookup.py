"""Which interval of an ascending table of angles an angle lies in, inside a compiled program without a search.

A search (``jnp.searchsorted``) is a loop of ten rounds or more, run in every evaluation of an ODE's right-hand side;
on a CPU each round is kernels of its own. Instead, the revolution is cut in bins and :func:`bin_table` keeps the
interval at each bin's start: an angle's interval is that of the bin before its own plus how many of the next
:data:`WINDOW` interval starts it has passed, one comparison of a few numbers. The tables keep :data:`WINDOW` +inf
starts past their last. Exact wherever at most :data:`WINDOW` starts lie within four bins in a row
(an angle rounded into the bin beside its own still finds its interval); :func:`bin_table` takes as many bins as
that needs.
"""

from __future__ import annotations

import math
from types import ModuleType

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.units import TWO_PI

BINS, WINDOW = 4096, 8
MOST_BINS = BINS * 4**5  # 4.2 million: 8 starts within 0.00034 deg


def bin_table(starts: np.ndarray) -> np.ndarray:
    """The interval at each bin's start (int32) for the ascending starts ``starts`` (rad in [0, 2 pi), +inf padded),
    in the fewest bins (:data:`BINS` x 4^k) that hold at most :data:`WINDOW` starts within any four in a row.
    ValueError, saying where, where even :data:`MOST_BINS` do not."""
    starts = np.asarray(starts, dtype=float)
    finite = starts[np.isfinite(starts)]
    n = BINS
    while n <= MOST_BINS:
        edges = np.arange(n) * (TWO_PI / n)
        first = np.clip(np.searchsorted(starts, edges, side="right") - 1, 0, len(starts) - 1)
        per_bin = np.bincount(np.minimum((finite * (n / TWO_PI)).astype(int), n - 1), minlength=n)
        crowded = np.convolve(np.r_[per_bin[-3:], per_bin], np.ones(4, int), "valid")
        if np.max(crowded) <= WINDOW:
            return first.astype(np.int32)
        n *= 4
    at = math.degrees(float(np.argmax(crowded)) * TWO_PI / (n // 4))
    raise ValueError(f"more than {WINDOW} pieces start within {4 * 360.0 / (n // 4):.2g} deg near {at:.4g} deg")


def interval(xp: ModuleType, starts: ArrayLike, bins: ArrayLike | None, theta: ArrayLike) -> np.ndarray | jax.Array:
    """The interval of ``starts`` (ascending, +inf padded, at least :data:`WINDOW` of them past the last) that each
    angle ``theta`` (rad, in [0, 2 pi)) lies in, 0 before the first: a search (numpy's, or where there are no
    ``bins`` JAX's), or in a compiled program the same from ``bins`` (:func:`bin_table`)."""
    if xp is np or bins is None:
        return xp.maximum(xp.searchsorted(xp.asarray(starts), theta, side="right") - 1, 0)
    starts, bins, theta = jnp.asarray(starts), jnp.asarray(bins), jnp.asarray(theta)
    n_bins = bins.shape[0]
    b = jnp.clip(jnp.floor(theta * (n_bins / TWO_PI)).astype(jnp.int32) - 1, 0, n_bins - 1)
    lo = bins[b]
    return lo + jnp.sum(starts[lo[..., None] + 1 + jnp.arange(WINDOW)] <= theta[..., None], axis=-1)
