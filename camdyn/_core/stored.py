"""Results stored by their arguments: a fresh process reads what an earlier one computed from the same data.

For host-side (numpy) work a check repeats on unchanged data and that costs more than reading its result: a lift
table's or a contour's smoothing-spline fit (scipy's LAPACK and a REML search) or a B-spline law's piecewise table
(scipy.interpolate, 0.3 s to import). :func:`stored_by_arguments` wraps such a function in
:func:`camdyn._core.jit.stored` (beside the programs of this camdyn source, JAX stack and machine, removed with
them when stale; nothing stored while the program cache is off), keyed by the function, its arguments (arrays by
their bytes, other values by their repr) and the numpy and scipy versions.
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Callable
from importlib import metadata
from typing import Any, TypeVar

import numpy as np

from . import jit

T = TypeVar("T")


@functools.cache
def _versions() -> str:
    """The libraries the stored functions compute with (numpy, scipy's LAPACK and splines)."""
    try:
        scipy = metadata.version("scipy")
    except metadata.PackageNotFoundError:
        scipy = ""
    return f"numpy={np.__version__};scipy={scipy}"


def _text(x: Any) -> str:
    """An argument as key text: an array by its dtype, shape and bytes' hash, anything else by its repr."""
    if isinstance(x, np.ndarray):
        return f"array({x.dtype.str},{x.shape},{hashlib.sha256(np.ascontiguousarray(x).tobytes()).hexdigest()})"
    if isinstance(x, list | tuple):
        return f"{type(x).__name__}({','.join(_text(v) for v in x)})"
    return repr(x)


def stored_by_arguments(fn: Callable[..., T]) -> Callable[..., T]:
    """``fn``, its results stored by its arguments while the program cache is on. ``fn`` must be pure: its result a
    function of its arguments (numpy arrays, numbers, strings, tuples of them) and of camdyn's source, picklable."""

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> T:
        if jit._DIR is None:  # the library: nothing stored, no key to make
            return fn(*args, **kwargs)
        key = repr((fn.__module__, fn.__qualname__, _versions())) + _text(args) + _text(sorted(kwargs.items()))
        return jit.stored(fn.__name__, key, lambda: fn(*args, **kwargs))

    return call
