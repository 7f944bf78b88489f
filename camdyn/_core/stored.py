"""Stored results: a fresh process reads what an earlier one computed from the same data instead of computing it.

For host-side (numpy) work a check repeats on unchanged data and that costs more than reading its result: a lift
table's or a contour's smoothing-spline fit (scipy's LAPACK and a REML search) or a B-spline law's piecewise table
(scipy.interpolate, 0.3 s to import). :func:`stored` wraps such a function; while the traced-program cache is on
(:func:`camdyn._core.jit.enable`: the CLI, the tests), each result is pickled beside the programs of this
fingerprint (camdyn's source, the JAX stack, the machine), which go with them when stale, under a key of the
function, its arguments (arrays by their bytes, other values by their repr) and the numpy and scipy versions.
Without it (the library) it only computes. Like JAX's own cache, the folder is trusted: the files are pickles
the user's own processes wrote.
"""

from __future__ import annotations

import functools
import hashlib
import os
import pickle
from collections.abc import Callable
from importlib import metadata
from typing import Any, TypeVar

import numpy as np

from . import jit

T = TypeVar("T")
SUFFIX = "result"  # the stored results' file names end so


@functools.cache
def _versions() -> str:
    """camdyn's source and the libraries the stored functions compute with (numpy, scipy's LAPACK and splines)."""
    try:
        scipy = metadata.version("scipy")
    except metadata.PackageNotFoundError:
        scipy = ""
    return f"{jit._fingerprint()};numpy={np.__version__};scipy={scipy}"


def _text(x: Any) -> str:
    """An argument as key text: an array by its dtype, shape and bytes' hash, anything else by its repr."""
    if isinstance(x, np.ndarray):
        return f"array({x.dtype.str},{x.shape},{hashlib.sha256(np.ascontiguousarray(x).tobytes()).hexdigest()})"
    if isinstance(x, list | tuple):
        return f"{type(x).__name__}({','.join(_text(v) for v in x)})"
    return repr(x)


def stored(fn: Callable[..., T]) -> Callable[..., T]:
    """``fn``, its results stored while the program cache is on. ``fn`` must be pure: its result a function of its
    arguments (numpy arrays, numbers, strings, tuples of them) and of camdyn's source alone, and picklable."""

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> T:
        if (root := jit._DIR) is None:
            return fn(*args, **kwargs)
        text = repr((fn.__module__, fn.__qualname__, _versions()))
        text += _text(args) + _text(sorted(kwargs.items()))
        # this fingerprint's folder of programs: camdyn's source is in its name, and stale ones are removed
        file = jit._programs(root) / f"{fn.__name__}-{hashlib.sha256(text.encode()).hexdigest()[:32]}.{SUFFIX}"
        try:
            return pickle.loads(file.read_bytes())
        except Exception:  # missing, truncated or unreadable: compute afresh
            pass
        result = fn(*args, **kwargs)
        tmp = file.with_suffix(f".{os.getpid()}.tmp")
        try:
            tmp.write_bytes(pickle.dumps(result))
            os.replace(tmp, file)  # atomic: parallel processes never read half a file
        except OSError:
            tmp.unlink(missing_ok=True)
        return result

    return call
