"""camdyn computes in float64. JAX's 64-bit mode is a process-wide setting, so camdyn leaves it to its caller
(as diffrax and equinox do): the command line and the tests switch it on; the library's entry points check it."""

from __future__ import annotations

import jax

from .errors import CamdynError

X64_HINT = "camdyn computes in float64: call jax.config.update('jax_enable_x64', True) (or set JAX_ENABLE_X64=1) first"


def enable_x64() -> None:
    """Switch JAX to 64-bit floats for this process (the command line's and the tests' choice)."""
    jax.config.update("jax_enable_x64", True)


def require_x64() -> None:
    """Raise :class:`CamdynError` unless JAX computes in float64: a float32 cam would be silently wrong."""
    if not jax.config.jax_enable_x64:  # pyright: ignore[reportAttributeAccessIssue] - a flag jax adds at run time
        raise CamdynError("", X64_HINT)
