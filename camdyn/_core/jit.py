"""Traced-program cache: a fresh ``camdyn`` process skips JAX tracing of the programs it ran before.

JAX's persistent compilation cache skips XLA compilation but not Python tracing and lowering, which for a
diffrax solve takes longer (about 1 s) than the solve itself. :func:`cached_jit` wraps a function like
``equinox.filter_jit``; once :func:`enable` names a directory, it serializes each traced program with
``jax.export``, keyed by the function, the static part of its arguments (everything that is not an array:
an equinox module's static fields, Python numbers), the shapes and dtypes of the arrays, camdyn's own source
and the versions of the JAX stack. A later process deserializes the program instead of tracing it. Without
:func:`enable` (the library, the tests) it is ``equinox.filter_jit`` and nothing is written.

Either way an argument with a ``jit_form`` method (a motion) is replaced by what it returns (:func:`jit_forms`):
a form whose static structure does not depend on the case, so a case never seen before reuses the programs of
the others.
"""

from __future__ import annotations

import functools
import hashlib
import os
from collections.abc import Callable
from importlib import metadata
from pathlib import Path
from typing import Any, TypeVar

import equinox as eqx
import jax
import numpy as np
from jax import export
from jax.core import Tracer

T = TypeVar("T")
_DIR: Path | None = None


def enable(directory: str | Path) -> None:
    """Cache traced programs under ``directory`` (created if needed; silently off if it cannot be)."""
    global _DIR
    try:
        Path(directory).mkdir(parents=True, exist_ok=True)
    except OSError:
        return
    _DIR = Path(directory)


@functools.cache
def _fingerprint() -> str:
    """camdyn's source and the JAX stack's versions: a change to either invalidates every program."""
    h = hashlib.sha256()
    for path in sorted(Path(__file__).parents[1].rglob("*.py")):
        h.update(path.read_bytes())
    for dist in ("jax", "jaxlib", "equinox", "diffrax", "optimistix", "lineax"):
        try:
            h.update(f"{dist}={metadata.version(dist)};".encode())
        except metadata.PackageNotFoundError:
            pass
    x64 = jax.config.jax_enable_x64  # pyright: ignore[reportAttributeAccessIssue] - a flag jax adds at run time
    h.update(f"{jax.default_backend()};x64={x64}".encode())
    return h.hexdigest()


def _load(file: Path):
    try:
        return export.deserialize(bytearray(file.read_bytes()))
    except Exception:  # missing, truncated or from an incompatible JAX: trace afresh
        return None


def _save(file: Path, exported) -> None:
    tmp = file.with_suffix(f".{os.getpid()}.tmp")
    try:
        tmp.write_bytes(exported.serialize())
        os.replace(tmp, file)  # atomic: parallel processes never read half a file
    except OSError:
        tmp.unlink(missing_ok=True)


def _has_form(x) -> bool:
    return hasattr(type(x), "jit_form")


def jit_forms(tree: T) -> T:
    """``tree`` with every object that has a ``jit_form`` method (a motion) replaced by ``x.jit_form()``."""
    return jax.tree.map(lambda x: x.jit_form() if _has_form(x) else x, tree, is_leaf=_has_form)


def filter_jit(fn: Callable[..., T]) -> Callable[..., T]:
    """``equinox.filter_jit(fn)`` on the arguments' :func:`jit_forms`: compiled once per follower kind and bucket,
    not once per case (in-process only; :func:`cached_jit` also persists)."""
    jitted = eqx.filter_jit(fn)

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> T:
        args, kwargs = jit_forms((args, kwargs))
        return jitted(*args, **kwargs)

    return call


def cached_jit(fn: Callable[..., T]) -> Callable[..., T]:
    """:func:`filter_jit` whose traced programs persist across processes once :func:`enable` is called."""
    jitted = eqx.filter_jit(fn)
    programs: dict = {}

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> Any:
        args, kwargs = jit_forms((args, kwargs))
        if _DIR is None:
            return jitted(*args, **kwargs)
        dynamic, static = eqx.partition((args, kwargs), eqx.is_array)
        leaves, treedef = jax.tree.flatten(dynamic)
        if any(isinstance(x, Tracer) for x in leaves):  # inside jit/vmap/grad: an exported program has
            return jitted(*args, **kwargs)  # no batching or differentiation rules; the outer trace is cached anyway
        avals = tuple((np.shape(x), np.dtype(x.dtype).str) for x in leaves)
        try:  # hashing the static part is cheap; its repr (the disk key) is not, for a motion of 1000 segments
            key = (treedef, tuple(jax.tree.leaves(static)), avals)
            exported = programs.get(key)
        except TypeError:  # an unhashable static value: key by its text
            key = repr((treedef, static, avals))
            exported = programs.get(key)
        if exported is None:
            name = hashlib.sha256(
                repr((fn.__module__, fn.__qualname__, _fingerprint(), treedef, static, avals)).encode()
            ).hexdigest()[:32]
            file = _DIR / f"{fn.__name__}-{name}.jaxexport"
            exported = _load(file)
            if exported is None:

                def flat(*xs: Any) -> Any:
                    a, kw = eqx.combine(jax.tree.unflatten(treedef, xs), static)
                    return fn(*a, **kw)

                try:
                    exported = export.export(jax.jit(flat))(*(jax.ShapeDtypeStruct(s, d) for s, d in avals))
                except Exception:  # e.g. a host callback, which jax.export cannot serialize: plain jit
                    programs[key] = jitted
                    return jitted(*args, **kwargs)
                _save(file, exported)
            programs[key] = exported
        if exported is jitted:
            return jitted(*args, **kwargs)
        return exported.call(*leaves)

    return call
