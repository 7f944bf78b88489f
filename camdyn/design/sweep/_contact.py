"""The least interface force of a follower that stays on the cam, per grid point (speed, spring rate, damping).

Compliant: the frequency-domain steady state (harmonic balance, :func:`camdyn.model.dynamics.contact_transfer`),
exact while the follower stays on the cam, batched in numpy (:func:`linear_least_force`: nothing to compile, one
inverse FFT a point); rigid: the kinematic force, closed form per angle, a kernel ``kernel(const, omega, k, c)``
for :func:`camdyn._core.sharding.run_batched`. Forces are weighted per angle (1 for a translating follower,
1 / lever arm for an oscillating one: N).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from scipy import fft

from ...model.dynamics import contact_transfer, kinematic_force_of
from ...model.follower import FollowerModel


def with_spring_damping(base: FollowerModel, k, c) -> FollowerModel:
    """``base`` with the spring rate ``k`` and the damping ``c`` (SI) of a grid point, ``c`` from
    :meth:`FollowerModel.damping_at` (it follows the rate where the damping was given as a ratio)."""
    return eqx.tree_at(lambda m: (m.stiffness, m.damping), base, (k, c))


def linear_least_force(base: FollowerModel, s, s1, weight, omega, k, c, chunk: int = 256, tick=None):
    """Least interface force (N, weighted) of the frequency-domain steady state at each point (``omega`` rad/s,
    spring ``k`` and damping ``c`` SI, arrays of one length), and its state (x, dx/dtheta) at theta = 0 in the
    motion's unit (the start of the diffrax gap integration): numpy, ``chunk`` points at a time, ``tick(points)``
    after each.

    ``s``, ``s1`` (SI) on ``theta_j = 2 pi j / n``. The force ``k_f (s - x) + c_f w (s' - x')`` is
    ``k_f s + c_f w s'`` less the inverse FFT of ``(k_f + i k w c_f) X_k``: one inverse FFT a point, with
    ``X_k = contact_transfer * S_k`` and ``X_0`` carrying the static load (as :func:`steady_state`)."""
    s, s1, weight = (np.asarray(a, dtype=float) for a in (s, s1, weight))
    n = s.size
    spec = np.fft.rfft(s)
    harmonic = np.arange(spec.size)
    m, kf, cf = (float(v) for v in (base.mass, base.train_stiffness, base.train_damping))
    static = n * (float(base.preload) + float(base.external))
    least, z0 = np.empty(omega.size), np.empty((omega.size, 2))
    twice = np.full(spec.size, 2.0 / n)  # x and x' at theta = 0: the inverse FFT's first sample, summed directly
    twice[0] = 1.0 / n
    if n % 2 == 0:
        twice[-1] = 1.0 / n  # the Nyquist bin counts once
    for a in range(0, omega.size, chunk):
        w, kk, cc = (np.asarray(v[a : a + chunk], dtype=float)[:, None] for v in (omega, k, c))
        wk = harmonic * w
        x_spec = spec * contact_transfer(wk, m, kk, cc, kf, cf)
        x_spec[:, 0] = (kf * spec[0] - static) / (kk[:, 0] + kf)
        train_x = fft.irfft((kf + 1j * wk * cf) * x_spec, n, axis=1)  # k_f x + c_f w x'
        least[a : a + chunk] = np.min((kf * s + cf * w * s1 - train_x) * weight, axis=1)
        z0[a : a + chunk, 0] = x_spec.real @ twice
        z0[a : a + chunk, 1] = -(x_spec.imag * harmonic) @ twice
        if tick is not None:
            tick(w.shape[0])
    return least, z0 / base.scale


def kinematic_kernel(const, omega, k, c):
    """Least kinematic (rigid follower) interface force, N (weighted)."""
    base, s, s1, s2, weight = const
    return jnp.min(kinematic_force_of(base, omega, s, s1, s2, k, c) * weight)
