"""The least interface force of a follower that stays on the cam, per grid point (speed, spring rate, damping).

Compliant: the frequency-domain steady state (:func:`camdyn.model.dynamics.steady_state`, harmonic balance), exact
while the follower stays on the cam; rigid: the kinematic force, closed form per angle. Both are kernels
``kernel(const, omega, k[, c])`` for :func:`camdyn._core.sharding.run_batched`; forces are weighted per angle (1 for a
translating follower, 1 / lever arm for an oscillating one: N).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp

from ...model.dynamics import kinematic_force_of, steady_train_force
from ...model.follower import FollowerModel


def with_spring_damping(base: FollowerModel, k, c) -> FollowerModel:
    """``base`` with the spring rate ``k`` and the damping ``c`` (SI) of a grid point, ``c`` from
    :meth:`FollowerModel.damping_at` (it follows the rate where the damping was given as a ratio)."""
    return eqx.tree_at(lambda m: (m.stiffness, m.damping), base, (k, c))


def damping_kernel(base: FollowerModel, k):
    """:meth:`FollowerModel.damping_at` a grid point's spring rate ``k`` (SI): batched in chunks, one cached program
    for any grid (eagerly, each of its operations would be a program compiled in every process)."""
    return base.damping_at(k)


def linear_kernel(const, omega, k):
    """Least force (N, weighted) of the frequency-domain steady state (the damping follows from ``k``)."""
    base, s, s1, spec, weight = const
    return jnp.min(steady_train_force(spec, omega, base, k, base.damping_at(k), s, s1) * weight)


def kinematic_kernel(const, omega, k, c):
    """Least kinematic (rigid follower) interface force, N (weighted)."""
    base, s, s1, s2, weight = const
    return jnp.min(kinematic_force_of(base, omega, s, s1, s2, k, c) * weight)
