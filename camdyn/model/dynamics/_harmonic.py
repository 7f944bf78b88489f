"""The compliant follower's steady state in contact, exact in the frequency domain (harmonic balance by FFT).

While the follower stays on the cam the compliant model is linear and time-invariant with a periodic input, so
its periodic steady state is exact in the frequency domain:
``X_k = (k_f + i k w c_f) S_k / (k + k_f - m (k w)^2 + i k w (c + c_f))``. This is the one place that formula is
written (:func:`steady_state`); the jump speed, spring sizing, jump maps and the optimizer all read it from here.
"""

from __future__ import annotations

from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import cached_jit, on_buckets
from ..._core.units import FFT_GRID, TWO_PI
from ..follower import FollowerModel
from ..motion import Motion
from ._train import train_force

_FFT_N = FFT_GRID


def steady_spectrum(
    spec: jax.Array,
    omega: ArrayLike,
    model: FollowerModel,
    stiffness: ArrayLike,
    damping: ArrayLike,
    n: int,
    unit: ArrayLike | None = None,
    *,
    conjugate: bool = False,
) -> jax.Array:
    """The rfft (on ``theta_j = 2 pi j / n``) of the compliant model's periodic steady state in contact, x.

    ``spec = rfft(s)`` of the cam motion on that grid; ``omega`` (rad/s), ``stiffness`` and ``damping`` (the
    spring's, SI) are arrays, so a grid of speeds and spring rates is one ``vmap`` (or a broadcast: shape (..., 1)
    each gives (..., len(spec))); the mass, the train and the static load come from ``model``. ``unit``: the SI
    value of the unit ``spec`` is in (None: SI already; the model's ``scale`` for a spectrum in the motion's unit,
    mm or rad), which the static load is divided by.
    ``X_k = (k_f + i k w c_f) S_k / (k + k_f - m (k w)^2 + i k w (c + c_f))``; ``X_0`` carries the static load.
    ``conjugate``: divide as a product with the conjugate over the squared modulus, 5-10x faster than XLA's
    (overflow-guarded) complex division and the same to rounding (the jump maps and sizing's
    :func:`linear_contact_force`, the optimizer's rows; ``check``'s jump speed keeps the division).
    """
    k = jnp.arange(spec.shape[0])
    m, kf, cf = model.mass, model.train_stiffness, model.train_damping
    wk = k * omega
    den_re, den_im = stiffness + kf - m * wk**2, wk * (damping + cf)
    if conjugate:
        x_spec = spec * (kf + 1j * wk * cf) * jax.lax.complex(den_re, -den_im) * (1.0 / (den_re**2 + den_im**2))
    else:
        x_spec = spec * (kf + 1j * wk * cf) / (stiffness + kf - m * wk**2 + 1j * wk * (damping + cf))
    static = n * (model.preload + model.external)
    if unit is not None:
        static = static / unit
    return jnp.where(k == 0, (kf * spec[0] - static) / (stiffness + kf), x_spec)


def steady_state(
    spec: jax.Array,
    omega: ArrayLike,
    model: FollowerModel,
    stiffness: ArrayLike,
    damping: ArrayLike,
    n: int,
    unit: ArrayLike | None = None,
) -> tuple[jax.Array, jax.Array]:
    """The compliant model's periodic steady state in contact on ``theta_j = 2 pi j / n``: (x, dx/dtheta), from
    :func:`steady_spectrum` (same arguments)."""
    x_spec = steady_spectrum(spec, omega, model, stiffness, damping, n, unit)
    return jnp.fft.irfft(x_spec, n), jnp.fft.irfft(1j * jnp.arange(spec.shape[0]) * x_spec, n)


def steady_train_force(
    spec: jax.Array,
    omega: jax.Array | float,
    model: FollowerModel,
    stiffness: ArrayLike,
    damping: ArrayLike,
    s: jax.Array,
    s1: jax.Array,
) -> jax.Array:
    """The interface force (N, or N*m) of :func:`steady_state` on its grid (``s``, ``s1``: the cam's lift and
    d/dtheta there, SI; ``spec = rfft(s)``): :func:`train_force` is linear, so the follower's part is one inverse
    FFT of its spectrum, half the work of transforming x and dx/dtheta (the ``conjugate`` division: the same to
    rounding)."""
    n = s.shape[0]
    x_spec = steady_spectrum(spec, omega, model, stiffness, damping, n, conjugate=True)
    follower = train_force(model, omega, 0.0, 0.0, x_spec, 1j * jnp.arange(spec.shape[0]) * x_spec)
    return train_force(model, omega, s, s1, 0.0, 0.0) + jnp.fft.irfft(follower, n)


def _on_grid(motion: Motion, model: FollowerModel, n: int) -> tuple[jax.Array, jax.Array, jax.Array]:
    """The cam's lift and its d/dtheta (SI) on ``theta_k = 2 pi k / n``, and the lift's rfft."""
    s, s1, _, _ = motion(jnp.arange(n) * (TWO_PI / n)) * model.scale
    return s, s1, jnp.fft.rfft(s)


def steady_force_at(motion: Motion, model: FollowerModel, n: int) -> Callable[[float | jax.Array], jax.Array]:
    """``omega -> interface force`` on the grid ``theta_k = 2 pi k / n`` of the compliant model's periodic orbit
    while it stays on the cam (harmonic balance by FFT, :func:`steady_state`)."""
    s, s1, spec = _on_grid(motion, model, n)

    def force(omega: float | jax.Array) -> jax.Array:
        x, x1 = steady_state(spec, omega, model, model.stiffness, model.damping, n)
        return train_force(model, omega, s, s1, x, x1)

    return force


BISECT_POINTS = 16  # speeds per step of the jump-speed search's bisection (:func:`linear_min_force` calls)
# the most speeds a program of linear_min_force takes (longer arrays in pieces), and the jump-speed scan's chunk: a
# first ``optimize``, whose verification looks for dips among 1000 speeds, compiled a fourth program for them (1.3 s)
SPEED_PIECE = 256
# 16, 64, 256 speeds: three programs at most
_SPEED_BUCKETS = {"least": BISECT_POINTS, "factor": 4, "largest": SPEED_PIECE}


def linear_min_force(
    motion: Motion, model: FollowerModel, omegas: ArrayLike, n: int = _FFT_N, weight: ArrayLike | None = None
) -> jax.Array | np.ndarray:
    """Least interface force (N) of the compliant model's periodic orbit if it never separates, per speed.

    While the follower stays on the cam the model is linear and time-invariant with a periodic input, so its
    steady state is exact in the frequency domain (harmonic balance by FFT, :func:`steady_state`). The result is the
    true steady state for every speed whose least force is positive, which is all the jump speed needs. Vectorized
    over ``omegas`` (any shape). ``weight``: optional (n,) factor per angle theta_k = 2 pi k / n applied before
    the minimum (``1000 / lever_arm_mm`` turns an oscillating follower's torque into its contact force in N).
    A 1-D array of speeds on the host runs a program compiled for a bucket of lengths (:func:`on_buckets`) and
    comes back as numpy.
    """
    return on_buckets(lambda w: _linear_min_force(motion, model, w, n, weight), omegas, **_SPEED_BUCKETS)


@cached_jit
def _linear_min_force(
    motion: Motion, model: FollowerModel, omegas: jax.Array, n: int, weight: ArrayLike | None
) -> jax.Array:
    """:func:`linear_min_force`'s program, for any shape of ``omegas``."""
    force = steady_force_at(motion, model, n)

    def one(omega: float | jax.Array) -> jax.Array:
        f = force(omega)
        return jnp.min(f if weight is None else f * weight)

    omegas = jnp.asarray(omegas, dtype=float)
    return jax.lax.map(one, omegas.ravel(), batch_size=64).reshape(omegas.shape)


def linear_least_force(motion: Motion, model: FollowerModel, omega: float) -> float:
    """:func:`linear_min_force` at one speed (rad/s), N: padded to the least bucket of speeds, the jump-speed
    bisection's, a program a ``check`` has loaded already (each program a fresh process loads costs milliseconds)."""
    return float(np.asarray(linear_min_force(motion, model, np.array([float(omega)])))[0])


@cached_jit
def linear_contact_force(motion: Motion, model: FollowerModel, omegas: jax.Array, n: int = _FFT_N) -> jax.Array:
    """The whole interface force (N or N*m) of :func:`linear_min_force`'s steady state: shape (*omegas.shape, n).

    Angles ``theta_j = 2 pi j / n``. Exact wherever it stays positive; affine in the preload (raising F0 adds
    ``k_f / (k + k_f) * dF0`` at every angle and speed), which is what spring sizing (:mod:`camdyn.design.sizing`) uses.
    By :func:`steady_train_force` (one inverse FFT a speed, the conjugate division): 1.9 x as fast as
    :func:`steady_force_at`'s, the same to 1.2e-13 of the largest force (the lecture on 161 speeds).
    """
    s, s1, spec = _on_grid(motion, model, n)

    def force(omega: jax.Array) -> jax.Array:
        return steady_train_force(spec, omega, model, model.stiffness, model.damping, s, s1)

    omegas = jnp.asarray(omegas, dtype=float)
    return jax.lax.map(force, omegas.ravel(), batch_size=64).reshape(omegas.shape + (n,))
