"""The follower train's force on the cam and the follower's rest on it: the one place each is written.

Every model with a compliant train (the lumped follower in the time and frequency domains, the spring's surge
chain, the sweeps, the tolerance study, the optimizer) reads it from here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from ..follower import FollowerModel

if TYPE_CHECKING:
    import numpy as np

    from ..._core.units import Num

    Values = float | np.ndarray | jax.Array  # floats, numpy or JAX arrays alike: the same arithmetic


def train_force(
    model: FollowerModel, omega: Values, s: Values, s1: Values, x: Values, x1: Values, unit: Values = 1.0
) -> jax.Array:
    """The train's force on the cam while they touch, ``k_f (s - x) + c_f w (s' - x')``: N, or N*m for an arm.

    ``omega``: the cam speed (rad/s); ``s``, ``s1``: the cam's lift and its d/dtheta; ``x``, ``x1``: the
    follower's; all four in the length unit whose SI value is ``unit`` (1.0: m or rad already; the model's
    ``scale`` for the motion's unit, mm -> m). Linear (the in-contact models); pure arithmetic on numpy or
    JAX arrays, so it traces under ``jit`` and ``vmap``.
    """
    return model.train_stiffness * unit * (s - x) + model.train_damping * omega * unit * (s1 - x1)


def contact_force(
    model: FollowerModel, omega: Values, s: Values, s1: Values, x: Values, x1: Values, unit: Values = 1.0
) -> jax.Array:
    """The interface force with unilateral contact: :func:`train_force` while the cam is ahead of the follower
    (s > x) and pushes it, else 0 (the follower flies); same units and arguments. JAX (returns a JAX array)."""
    return jnp.where(s > x, jnp.maximum(0.0, train_force(model, omega, s, s1, x, x1, unit)), 0.0)


def follower_rates(model: FollowerModel, omega: Values, x: Values, p: Values, fi: Values) -> jax.Array:
    """d/dtheta of the follower's (x, p = dx/dtheta), motion units, under the interface force ``fi`` (N, or N*m for
    an arm): ``m w^2 x'' = fi - (k x + F0) - c w x' - F_ext`` in the cam angle (``omega`` rad/s), the follower's
    equation of motion wherever it flies or rides the cam."""
    sc = model.scale
    f_net = fi - (model.stiffness * sc * x + model.preload) - model.damping * omega * sc * p - model.external
    return jnp.stack([p, f_net / (model.mass * omega**2 * sc)])


def static_position(model: FollowerModel, s: Values, unit: Values = 1.0) -> jax.Array:
    """Where the compliant follower rests on a cam standing at lift ``s``: ``k_f (s - x) = k x + F0 + F_ext``, so
    ``x = (k_f s - F0 - F_ext) / (k + k_f)``, in the unit of ``s`` whose SI value is ``unit`` (as
    :func:`train_force`). The reference the residual vibration in a dwell is measured from."""
    kf, k = model.train_stiffness * unit, model.stiffness * unit
    return (kf * s - model.preload - model.external) / (k + kf)


def preload_share(stiffness: Num, train_stiffness: Num) -> Num:
    """How much of a preload change reaches the cam in contact, ``dF_i / dF0 = k_f / (k + k_f)`` (1): the
    in-contact steady state is affine in the preload, which moves the follower by ``-dF0 / (k + k_f)`` at every
    angle and speed (:func:`static_position`). Spring rate and train stiffness in one unit (SI); compliant trains."""
    return train_stiffness / (stiffness + train_stiffness)


def vibration_coefficients(
    mass: Values, stiffness: Values, damping: Values, omega: Values
) -> tuple[jax.Array, jax.Array]:
    """A linear follower's ``a = k / (m w^2)`` and ``b = c / (m w)`` (SI), its stiffness and damping per unit mass in
    cam-angle time: :func:`free_vibration`'s coefficients, as JAX arrays (for compiled programs)."""
    return jnp.asarray(stiffness / (mass * omega**2)), jnp.asarray(damping / (mass * omega))


def free_vibration(a: Values, b: Values, t: Values) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array]:
    """exp(A t) for A = [[0, 1], [-a, -b]] in closed form (under-, critically or over-damped): (e00, e01, e10,
    e11). The free motion of a linear follower, ``y'' = -a y - b y'``, over ``t`` (any consistent units: the cam
    angle with ``a = k / (m w^2)``, ``b = c / (m w)``): ``y(t) = e00 y0 + e01 y0'``, ``y'(t) = e10 y0 + e11 y0'``."""
    alpha = -0.5 * b
    d = alpha * alpha - a
    y = jnp.sqrt(jnp.abs(d)) * t
    small = y < 1e-8
    under = d < 0
    cc = jnp.where(under, jnp.cos(y), jnp.cosh(y))
    sy = jnp.where(small, 1.0, jnp.where(under, jnp.sin(y), jnp.sinh(y)) / jnp.where(small, 1.0, y))  # sin(y)/y
    ss = sy * t
    e = jnp.exp(alpha * t)
    return e * (cc + 0.5 * b * ss), e * ss, -e * a * ss, e * (cc - 0.5 * b * ss)
