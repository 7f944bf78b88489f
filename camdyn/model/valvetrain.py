"""A valvetrain's lumped parameters in SI, from ``[valvetrain]`` and ``[dynamics]``: the cam side and the valve as
two masses, the train between them, the lash, the valve spring and seat; and the single follower it reduces to.

Coordinates: the follower's lift x_c at the cam and the valve's lift x_v at the valve (m). The train's
deflection at the valve is ``r x_c - lash - x_v`` (the lash is closed where it is positive); its force F_t at the
valve acts as ``r F_t`` on the follower (a rocker of ratio r, virtual work).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._core.kinds import TRANSLATING
from .._core.units import M_PER_MM, damping_from_ratio
from ..schema import DynamicsSpec, ValvetrainSpec
from .follower import FollowerModel


class Link(eqx.Module):
    """A spring and damper in compression only (a contact): what ``dynamics.contact_force`` reads."""

    train_stiffness: jax.Array  # N/m; inf: rigid
    train_damping: jax.Array  # N*s/m


class ValvetrainModel(eqx.Module):
    """Valvetrain parameters in SI; every field an array leaf (``vmap``-able). ``inf`` stiffness: rigid."""

    ratio: jax.Array  # valve lift per follower lift
    lash: jax.Array  # m, at the valve
    cam_side_mass: jax.Array  # kg
    valve_mass: jax.Array  # kg
    train: Link  # between the two masses, at the valve
    cam: Link  # the cam contact, at the follower
    cam_restitution: jax.Array  # a rigid cam contact's, 0..1
    seat_restitution: jax.Array  # 0..1
    spring_rate: jax.Array  # N/m, the valve spring
    preload: jax.Array  # N, the valve spring's force on the closed valve
    spring_damping: jax.Array  # N*s/m, at the valve
    tappet_force: jax.Array  # N, holding the follower on the cam

    @property
    def rigid_cam(self) -> bool:
        return bool(math.isinf(float(self.cam.train_stiffness)))

    @property
    def rigid_train(self) -> bool:
        return bool(math.isinf(float(self.train.train_stiffness)))

    @property
    def equivalent_mass(self):
        """The whole train's mass at the follower, kg: ``m_cam + m_valve r^2``."""
        return self.cam_side_mass + self.valve_mass * self.ratio**2


def valvetrain_model(v: ValvetrainSpec, d: DynamicsSpec) -> ValvetrainModel:
    """SI valvetrain parameters from validated ``[valvetrain]`` and ``[dynamics]`` tables.

    Damping ratios become dampers on the mass each one moves: the valve spring's ``c = 2 zeta sqrt(k m)`` with the
    whole train's mass reduced to the valve (``m_valve + m_cam / r^2``), so that the equivalent follower's ratio is
    the same zeta; the train's on the valve (``c = 2 zeta sqrt(k_t m_valve)``); the cam contact's on the whole
    train at the follower (``m_cam + m_valve r^2``), as a single follower's would be.
    """
    r = float(v.ratio)
    m_c, m_v = float(v.cam_side_mass), float(v.valve_mass)
    k = TRANSLATING.rate_to_si(d.spring_rate)
    m_at_valve = m_v + m_c / r**2
    c = d.damping if d.damping is not None else damping_from_ratio(d.damping_ratio or 0.0, k, m_at_valve)
    kt = math.inf if v.stiffness is None else TRANSLATING.rate_to_si(v.stiffness)
    ct = 0.0 if math.isinf(kt) else damping_from_ratio(v.damping_ratio, kt, m_v)
    kf = math.inf if d.train_stiffness is None else TRANSLATING.rate_to_si(d.train_stiffness)
    cf = 0.0 if math.isinf(kf) else damping_from_ratio(d.train_damping_ratio, kf, m_c + m_v * r**2)
    a = lambda x: jnp.asarray(float(x))  # noqa: E731
    return ValvetrainModel(
        a(r),
        a(v.lash * M_PER_MM),
        a(m_c),
        a(m_v),
        Link(a(kt), a(ct)),
        Link(a(kf), a(cf)),
        a(d.restitution),
        a(v.seat_restitution),
        a(k),
        a(d.preload),
        a(c),
        a(v.tappet_force),
    )


def equivalent_follower(vt: ValvetrainModel) -> FollowerModel:
    """The single follower a rigid, lash-free valvetrain is, at the cam: mass ``m_cam + m_valve r^2``, spring rate
    ``k r^2``, preload ``F0 r``, damping ``c r^2``, the tappet force as the external load, the same cam contact.
    The checks that know one follower read this; the valvetrain's own results come from the two-mass model."""
    r = vt.ratio
    return FollowerModel(
        vt.equivalent_mass,
        vt.spring_rate * r**2,
        vt.preload * r,
        vt.spring_damping * r**2,
        vt.tappet_force,
        vt.cam.train_stiffness,
        vt.cam.train_damping,
        vt.cam_restitution,
        scale=M_PER_MM,
    )


def lift_with_ramps(theta_deg: np.ndarray, lift: np.ndarray, lash: float, ramp_velocity: float) -> np.ndarray:
    """The cam's lift at the valve (mm, ``r`` times the follower's) that gives the valve ``lift`` (mm) at
    ``theta_deg`` (one revolution, increasing) with ``lash`` (mm) taken up by constant-velocity ramps of
    ``ramp_velocity`` (mm per cam degree): ``lift + lash`` while the valve is open; before it opens and after it
    closes a ramp from the base circle to ``lash`` over ``lash / ramp_velocity`` degrees; 0 elsewhere.
    ValueError for a valve that never opens or opens more than once a revolution."""
    open_ = lift > 0.0
    n = len(lift)
    if not open_.any():
        raise ValueError("the valve never lifts: no lift_mm above 0")
    if open_.all():
        raise ValueError("the valve never closes: no lift_mm of 0")
    rises = np.flatnonzero(open_ & ~np.roll(open_, 1))  # the first open row of each event
    if len(rises) > 1:
        raise ValueError(f"the valve opens {len(rises)} times a revolution: camdyn models one event")
    falls = np.flatnonzero(open_ & ~np.roll(open_, -1))
    seat_open = theta_deg[(rises[0] - 1) % n]  # the last row on the seat before the event, and the first after
    seat_close = theta_deg[(falls[0] + 1) % n]
    to_open = (seat_open - theta_deg) % 360.0
    from_close = (theta_deg - seat_close) % 360.0
    ramp = np.maximum(0.0, lash - ramp_velocity * np.minimum(to_open, from_close))
    return np.where(open_, lift + lash, ramp)
