"""Grid points over devices: a kernel ``kernel(const, *point)`` vmapped over points, compiled once and sharded
over the JAX devices (``jax.shard_map`` on a one-axis mesh), run chunk by chunk so progress can follow.

With several processes (:func:`camdyn._core.distributed.initialize`) the devices are every process's: each
process holds the same inputs, gives the mesh its own devices' shards of them (``jax.make_array_from_callback``)
and gathers every result (``multihost_utils.process_allgather``), so every process returns the whole output."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import equinox as eqx
import jax
import numpy as np
from jax.experimental import multihost_utils
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from .jit import cached_jit


def _shard_map(f, mesh, in_specs, out_specs):
    if hasattr(jax, "shard_map"):
        return jax.shard_map(f, mesh=mesh, in_specs=in_specs, out_specs=out_specs, check_vma=False)
    from jax.experimental.shard_map import shard_map  # older JAX

    return shard_map(f, mesh=mesh, in_specs=in_specs, out_specs=out_specs, check_rep=False)


@functools.cache
def _sharded(kernel: Callable, devices: tuple, per_point: bool):
    """``kernel(const, *point)`` vmapped over grid points (``per_point``; else the kernel takes a device's points
    as arrays itself) and sharded over ``devices``, compiled; in one process
    through :func:`camdyn._core.jit.cached_jit`, so a later process loads the traced program instead of tracing it."""
    mesh = Mesh(np.asarray(devices), ("grid",))

    def run(const: Any, *batched: Any) -> Any:
        body = (lambda c, *b: jax.vmap(lambda *p: kernel(c, *p))(*b)) if per_point else kernel
        spec = PartitionSpec("grid")
        return _shard_map(body, mesh, (PartitionSpec(), *([spec] * len(batched))), spec)(const, *batched)

    if jax.process_count() > 1:  # global arrays over several processes: traced in each
        return eqx.filter_jit(run), mesh
    # the disk key names the kernel and the devices (cached_jit keys by the wrapped function's name)
    run.__module__ = kernel.__module__
    run.__qualname__ = run.__name__ = f"{kernel.__qualname__}-on-{len(devices)}-{devices[0].platform}"
    return cached_jit(run), mesh


def _global(x, mesh, spec):
    """``x`` (the same on every process) as a global array over ``mesh``, each process giving its own shards."""
    x = np.asarray(x)
    return jax.make_array_from_callback(x.shape, NamedSharding(mesh, spec), lambda idx: x[idx])


def _to_mesh(const, part, mesh):
    """The kernel's inputs on the global mesh of several processes: constants replicated, points sharded."""
    const = jax.tree_util.tree_map(lambda c: _global(c, mesh, PartitionSpec()) if eqx.is_array(c) else c, const)
    return const, [_global(p, mesh, PartitionSpec("grid")) for p in part]


def run_batched(
    kernel: Callable,
    const: Any,
    batched: list[np.ndarray],
    chunk: int,
    progress: Callable[[int], None] | None,
    devices: tuple,
    per_point: bool = True,
) -> Any:
    """Run ``kernel`` over the rows of ``batched`` in chunks of ``chunk`` points per device (padded); ``per_point``:
    the kernel computes one point (vmapped here), else a device's chunk of points at once."""
    n_dev = len(devices)
    size = chunk * n_dev * (1 if devices[0].platform == "cpu" else 16)  # accelerators want wide batches
    n = batched[0].shape[0]
    fn, mesh = _sharded(kernel, devices, per_point)
    multi = jax.process_count() > 1
    pending = []
    for start in range(0, n, size):
        part = [b[start : start + size] for b in batched]
        m = part[0].shape[0]
        if m < size:  # pad with copies of the first point: one compiled shape for every chunk
            part = [np.concatenate([p, np.repeat(p[:1], size - m, axis=0)]) for p in part]
        if multi:
            c, pts = _to_mesh(const, part, mesh)
            pending.append((multihost_utils.process_allgather(fn(c, *pts), tiled=True), m))
        else:  # dispatched, not waited for: the next chunk may run beside it on another core
            pending.append((fn(const, *part), m))  # numpy: no transfer program to compile
    outs = []
    for res, m in pending:
        outs.append(jax.tree_util.tree_map(lambda r, m=m: np.asarray(r)[:m], res))  # m bound now
        if progress is not None:
            progress(m)
    return jax.tree_util.tree_map(lambda *r: np.concatenate(r), *outs)
