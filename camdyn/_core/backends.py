"""JAX's backends as the command line starts them: on the CPU alone, without the accelerators' plugins."""

from __future__ import annotations

import jax


def skip_accelerator_plugins() -> None:
    """Where JAX runs on the CPU alone (its ``jax_platforms`` setting ``cpu``, from ``JAX_PLATFORMS=cpu`` as every
    command but a batch sets it before JAX loads), skip JAX's discovery of accelerator plugins before its first
    backend starts: it imports and initializes every plugin installed (JAX's CUDA plugin opens eleven NVIDIA
    libraries) and reads the entry points of every distribution in the environment, for backends this setting never
    starts. JAX has no switch for it: its own record that discovery has run is set, where this JAX keeps one (else
    nothing changes). JAX's setting, not the environment, decides: a caller that loaded JAX before (a notebook calling
    :func:`camdyn.cli.main`) keeps its accelerators."""
    platforms = jax.config.jax_platforms  # pyright: ignore[reportAttributeAccessIssue] - a flag jax adds at run time
    if (platforms or "").strip().lower() != "cpu":
        return
    from jax._src import xla_bridge  # JAX's private module: the only place that record lives

    if getattr(xla_bridge, "_plugins_registered", None) is False:
        xla_bridge._plugins_registered = True  # pyright: ignore[reportPrivateUsage]
