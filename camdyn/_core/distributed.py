"""JAX's own distributed runtime for the batched commands (``sweep``, ``tolerance``): one place that starts it.

``initialize(coordinator, num_processes, process_id, auto=...)`` calls :func:`jax.distributed.initialize` when
the command line or the environment (``CAMDYN_COORDINATOR``, ``CAMDYN_NUM_PROCESSES``, ``CAMDYN_PROCESS_ID``)
asks for several processes, or with ``auto`` (``--distributed``) on a cluster JAX detects by itself (SLURM,
Open MPI), which then supplies the three values.
Afterwards ``jax.devices()`` is the global list of every process's devices, the batched kernels are sharded over
that global mesh (:func:`camdyn._core.sharding.run_batched`), every process computes the same inputs
and receives every result, and only process 0 writes (:func:`is_writer`). On CPU the collectives go through gloo.
"""

from __future__ import annotations

import os
import sys

import jax

from .errors import InputError

_ENV = {"coordinator": "CAMDYN_COORDINATOR", "num_processes": "CAMDYN_NUM_PROCESSES", "process_id": "CAMDYN_PROCESS_ID"}
_CLUSTER_ENV = ("SLURM_JOB_ID", "OMPI_COMM_WORLD_SIZE")  # what jax.distributed detects by itself
_started = False


def _from_env(name: str) -> str | None:
    """The environment variable of option ``name``; None where unset or empty."""
    return os.environ.get(_ENV[name]) or None


def _option(value: int | None, name: str, flag: str) -> int | None:
    """``value`` from the command line, else the environment variable of ``name``; a whole number checked."""
    raw = value if value is not None else _from_env(name)
    if raw is None:
        return None
    try:
        number = int(raw)
    except (TypeError, ValueError):
        raise InputError(flag, f"expected a whole number, got {raw!r}") from None
    if number < (1 if name == "num_processes" else 0):
        raise InputError(flag, f"out of range: {number}")
    return number


def initialize(
    coordinator: str | None = None,
    num_processes: int | None = None,
    process_id: int | None = None,
    *,
    auto: bool = False,
) -> int:
    """Start JAX's distributed runtime if asked (options, environment, or ``auto`` on a cluster JAX detects);
    returns the number of processes. A no-op (1) for a single process."""
    global _started
    coordinator = coordinator if coordinator is not None else _from_env("coordinator")
    num_processes = _option(num_processes, "num_processes", "--num-processes")
    process_id = _option(process_id, "process_id", "--process-id")
    detected = auto and any(v in os.environ for v in _CLUSTER_ENV)
    if _started or (coordinator is None and num_processes in (None, 1) and not detected):
        return jax.process_count()
    if coordinator is None and not detected:
        raise InputError("--coordinator", "several processes need the coordinator's address, host:port")
    if not detected:  # a cluster JAX detects supplies what is not given; elsewhere the command line must
        assert coordinator is not None  # refused above
        host, colon, port = coordinator.rpartition(":")
        if not (colon and host and port.isdigit() and 0 < int(port) < 65536):
            raise InputError("--coordinator", f"expected the coordinator's address as host:port, got {coordinator!r}")
        for flag, value in (("--num-processes", num_processes), ("--process-id", process_id)):
            if value is None:
                raise InputError(flag, "several processes need it beside --coordinator (each process its own id)")
    if num_processes is not None and process_id is not None and process_id >= num_processes:
        raise InputError("--process-id", f"must be below --num-processes ({num_processes}), got {process_id}")
    # before initialize, without asking for a backend (that would start it); only CPU devices use it
    jax.config.update("jax_cpu_collectives_implementation", "gloo")
    jax.distributed.initialize(coordinator_address=coordinator, num_processes=num_processes, process_id=process_id)
    _started = True
    _native_chatter_to_stderr()
    return jax.process_count()


def _native_chatter_to_stderr() -> None:
    """Native libraries (gloo: "[Gloo] Rank 0 is connected ...") print on file descriptor 1, which would spoil
    ``--json``: point descriptor 1 at stderr and keep Python's ``sys.stdout`` on the real standard output."""
    sys.stdout.flush()
    real = os.dup(1)
    os.dup2(2, 1)
    sys.stdout = open(real, "w", encoding=sys.stdout.encoding or "utf-8", buffering=1)  # noqa: SIM115  (lives as long as the process)


def is_writer() -> bool:
    """Whether this process writes the outputs (process 0)."""
    return jax.process_index() == 0
