"""Grid points over devices: a kernel ``kernel(const, *point)`` vmapped over points, compiled once and sharded
over the JAX devices (``jax.shard_map`` on a one-axis mesh), run chunk by chunk so progress can follow.

On CPUs the chunks run on a thread per core: XLA runs one program at a time per CPU device, each on one core, so
chunks dispatched from one thread wait for each other (a 100 x 100 jump map's gap stepping: 0.28 s on one of two
cores, 0.15 s on both). Accelerators take them from one thread: their dispatch does not wait. So does JAX 0.11's CPU
client (:data:`CPU_THREADS`).

With several processes (:func:`camdyn._core.distributed.initialize`) the devices are every process's: each
process holds the same inputs, gives the mesh its own devices' shards of them (``jax.make_array_from_callback``)
and gathers every result (``multihost_utils.process_allgather``), so every process returns the whole output."""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import equinox as eqx
import jax
import numpy as np
from jax.experimental import multihost_utils
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from .jit import cached_jit, jit_with


def accelerated(devices: Sequence[Any]) -> bool:  # jax.Device, which pyright cannot take as a type
    """Whether ``devices`` are accelerators (GPUs, TPUs) rather than CPUs: the one test of the platform a batched
    kernel runs on, for its batch width here and for the path a kernel takes (see the jump map's gap stepping)."""
    return devices[0].platform != "cpu"


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
        return jit_with(run), mesh
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


def _chunk_size(chunk: int, devices: tuple) -> int:
    """Grid points a call takes: ``chunk`` per device, 16 times as many on accelerators (they want wide batches)."""
    return chunk * len(devices) * (16 if accelerated(devices) else 1)


# Whether programs may run on a CPU device from several threads at once. JAX 0.11's CPU client never finished two of
# the jump map's programs started together from two threads (JAX 0.11.2 on a 16-core machine, pinned to 2 cores or
# not, session 39: its steady state or its gap stepping waited for 40 s and more, where one thread took 0.8 s), when a
# plain loop's program ran so; JAX 0.10 runs them side by side, a core each.
CPU_THREADS = jax.__version_info__ < (0, 11)


def _workers(devices: tuple) -> int:
    """Threads that run chunks at once: the cores this process may use per CPU device (1 on accelerators, and where
    JAX's CPU client cannot take programs from several threads: :data:`CPU_THREADS`)."""
    if accelerated(devices) or not CPU_THREADS:
        return 1
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, cores // len(devices))


def on_cores(fn: Callable[[Any], Any], items: Iterable[Any]) -> list[Any]:
    """``[fn(x) for x in items]`` on a thread per core the process may use, where JAX computes on CPUs (XLA runs one
    program at a time per CPU device, on one core, and a running program releases the interpreter): for independent
    evaluations that are mostly compiled work. In order; the first exception is raised."""
    items = list(items)
    workers = min(_workers(tuple(jax.local_devices())[:1]), len(items))
    if workers <= 1:
        return [fn(x) for x in items]
    with ThreadPoolExecutor(workers, thread_name_prefix="camdyn-core") as pool:
        return list(pool.map(fn, items))


def _padded(batched: list[np.ndarray], size: int) -> list[np.ndarray]:
    """``batched`` padded to ``size`` rows with copies of the first: one compiled shape for every chunk."""
    m = batched[0].shape[0]
    return [np.concatenate([b, np.repeat(b[:1], size - m, axis=0)]) for b in batched] if m < size else batched


def prepare_batched(
    kernel: Callable,
    const: Any,
    point: list[np.ndarray],
    chunk: int,
    devices: tuple,
    per_point: bool = True,
) -> None:
    """Trace and compile (or load) the program :func:`run_batched` will run ``kernel`` with, for grid points like
    ``point`` (one row of each batched input is enough), without running it: another thread can do this while
    the caller computes what decides the points. Nothing where the program is not one of the traced-program
    cache's (several processes, or the cache not enabled: then the first call compiles)."""
    if jax.process_count() > 1:
        return
    fn, _ = _sharded(kernel, devices, per_point)
    prepare = getattr(fn, "prepare", None)
    if prepare is not None:
        prepare(const, *_padded([np.asarray(p)[:1] for p in point], _chunk_size(chunk, devices)))


def _ready(out: tuple[Any, int]) -> tuple[Any, int]:
    """A chunk's result, computed: its worker thread waits for it, not the thread that gathers them."""
    return jax.block_until_ready(out[0]), out[1]


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
    size = _chunk_size(chunk, devices)
    n = batched[0].shape[0]
    fn, mesh = _sharded(kernel, devices, per_point)
    multi = jax.process_count() > 1

    def one(start: int) -> tuple[Any, int]:
        part = [b[start : start + size] for b in batched]
        m = part[0].shape[0]
        part = _padded(part, size)
        if multi:
            c, pts = _to_mesh(const, part, mesh)
            return multihost_utils.process_allgather(fn(c, *pts), tiled=True), m
        return fn(const, *part), m  # numpy: no transfer program to compile

    starts = range(0, n, size)
    workers = 1 if multi else min(_workers(devices), len(starts))
    if workers > 1:
        pool = ThreadPoolExecutor(workers, thread_name_prefix="camdyn-chunk")
        pending = pool.map(lambda start: _ready(one(start)), starts)
    else:  # dispatched, not waited for: an accelerator queues the next chunk while this one runs
        pool, pending = None, [one(start) for start in starts]
    outs = []
    try:
        for res, m in pending:
            outs.append(jax.tree_util.tree_map(lambda r, m=m: np.asarray(r)[:m], res))  # m bound now
            if progress is not None:
                progress(m)
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
    return jax.tree_util.tree_map(lambda *r: np.concatenate(r), *outs)
