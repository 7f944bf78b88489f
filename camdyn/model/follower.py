"""The follower's lumped dynamic parameters in SI, built from the ``[dynamics]`` table: the one place where the
case file's units become the models' (N/mm -> N/m, damping ratios -> damping)."""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.core import Tracer
from jax.typing import ArrayLike

from .._core.jit import device_array
from .._core.kinds import FollowerKind
from .._core.units import M_PER_MM, damping_from_ratio
from ..schema import DynamicsSpec


class FollowerModel(eqx.Module):
    """Lumped follower parameters in SI (generalized: N and m, or N*m and rad for an oscillating arm).

    Every field is an array leaf, so a batch of models (e.g. a sweep over spring rates) is one ``vmap``.
    ``train_stiffness = inf`` marks a rigid follower; ``damping_ratio`` is NaN where the damping was given
    as a constant (it then stays when the spring is re-rated).
    """

    mass: jax.Array  # kg (or kg*m^2)
    stiffness: jax.Array  # N/m (or N*m/rad)
    preload: jax.Array  # N (or N*m)
    damping: jax.Array  # N*s/m (or N*m*s/rad)
    external: jax.Array  # N (or N*m), pushing the follower onto the cam
    train_stiffness: jax.Array  # N/m (or N*m/rad); inf for a rigid follower
    train_damping: jax.Array  # N*s/m
    restitution: jax.Array  # 0..1
    scale: float = eqx.field(static=True, default=1e-3)  # motion unit -> SI length (mm -> m)
    damping_ratio: jax.Array = eqx.field(
        default=math.nan, converter=jnp.asarray
    )  # zeta of c = 2 zeta sqrt(k m); NaN: c fixed

    @property
    def rigid(self) -> bool:
        return bool(np.all(np.isinf(np.asarray(self.train_stiffness))))

    def damping_at(self, stiffness: ArrayLike) -> jax.Array:
        """The spring damping at another rate: it follows sqrt(k m) when given as a ratio, else it stays."""
        xp, (ratio, damping, mass, k) = _host_or_traced(self.damping_ratio, self.damping, self.mass, stiffness)
        c = xp.where(xp.isnan(ratio), damping, damping_from_ratio(xp.nan_to_num(ratio), k, mass))
        return c if xp is jnp else jax.device_put(c)

    def with_spring(self, stiffness: ArrayLike, preload: ArrayLike | None = None) -> FollowerModel:
        """The same follower with another spring rate (SI; and preload, if given), its damping re-derived."""
        stiffness = _placed(stiffness)
        new = (stiffness, self.preload if preload is None else _placed(preload), self.damping_at(stiffness))
        return eqx.tree_at(lambda m: (m.stiffness, m.preload, m.damping), self, new)


def _placed(x: ArrayLike) -> jax.Array:
    """``x`` as a float64 JAX array: placed on the device where it is concrete (:func:`device_array`, no program
    compiled), ``jnp.asarray`` inside a trace."""
    return jnp.asarray(x, dtype=float) if isinstance(x, Tracer) else device_array(x)


def _host_or_traced(*values: ArrayLike) -> tuple:
    """(jax.numpy, the values) where any is traced (inside a compiled program), else (numpy, the values as numpy
    arrays): the same IEEE operations, but an eager jax.numpy operation compiles a program of its own on first use
    and costs tens of microseconds a call (a spring search re-rates a follower a thousand times)."""
    if any(isinstance(x, Tracer) for x in values):
        return jnp, values
    return np, tuple(np.asarray(x, dtype=float) for x in values)


def follower_model(d: DynamicsSpec, *, kind: FollowerKind) -> FollowerModel:
    """SI follower parameters from a validated ``[dynamics]`` table (translating: mm -> m, N/mm -> N/m)."""
    m, k_in, f0, kf_in, ext = d.generalized(kind)
    assert m is not None  # check_dynamics_keys: the kind's mass (and rate and preload, unless form-closed)
    k = kind.rate_to_si(k_in or 0.0)  # a groove cam needs no return spring
    f0 = f0 or 0.0
    kf = math.inf if kf_in is None else kind.rate_to_si(kf_in)
    c = d.damping if d.damping is not None else damping_from_ratio(d.damping_ratio or 0.0, k, m)
    cf = 0.0 if math.isinf(kf) else damping_from_ratio(d.train_damping_ratio, kf, m)
    ratio = math.nan if d.damping is not None else (d.damping_ratio or 0.0)
    vals = (m, k, f0, c, ext, kf, cf, d.restitution)
    # device_put, not jnp.asarray: the latter compiles a program per shape on first use (JAX 0.10), 10 ms each
    return FollowerModel(
        *(jax.device_put(float(v)) for v in vals), scale=kind.si_per_motion, damping_ratio=jax.device_put(ratio)
    )


def with_spring_mass(model: FollowerModel, spring_mass: float, *, lever_arm_mm: float | None = None) -> FollowerModel:
    """The follower with a third of its spring's mass (kg) added to the moving mass, the classic correction for
    a spring whose far end is fixed (the coils' kinetic energy with a linear velocity profile). For an
    oscillating arm the spring acts at ``lever_arm_mm`` from the pivot and adds m_s r^2 / 3 to the inertia.
    Damping given as a ratio follows the new mass; the train damping keeps its ratio too."""
    added = spring_mass / 3.0
    if lever_arm_mm is not None:
        added = added * (lever_arm_mm * M_PER_MM) ** 2
    # numpy where the model is concrete: six eager jax ops would cost 40 ms of every check of a case with a spring
    xp, (m0, c0, cf0, ratio) = _host_or_traced(model.mass, model.damping, model.train_damping, model.damping_ratio)
    mass = m0 + added
    grow = xp.sqrt(mass / m0)
    new = (mass, xp.where(xp.isnan(ratio), c0, c0 * grow), cf0 * grow)
    if xp is np:  # back to JAX arrays, scalars weakly typed as jax.numpy's results are
        new = tuple(jax.device_put(float(x) if np.ndim(x) == 0 else x) for x in new)
    return eqx.tree_at(lambda m: (m.mass, m.damping, m.train_damping), model, new)
