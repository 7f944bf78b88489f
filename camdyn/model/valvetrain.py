"""A valvetrain's lumped parameters in SI, from ``[valvetrain]`` and ``[dynamics]``: the cam side and the valve as
two masses, the train between them, the lash, the valve spring and seat; and the single follower it reduces to.

Coordinates: the follower's lift x_c at the cam and the valve's lift x_v at the valve (m). The rocker carries the
follower's lift to the valve as ``g(x_c)`` (``r x_c`` for a constant ratio r; a rocker's geometry otherwise,
:class:`Rocker`), whose derivative ``r(x_c) = dg/dx_c`` is the instantaneous ratio. The train's deflection at the
valve is ``g(x_c) - lash - x_v`` (the lash is closed where it is positive); its force F_t at the valve acts as
``r(x_c) F_t`` on the follower (virtual work).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from .._core.jit import device_array
from .._core.kinds import TRANSLATING
from .._core.units import M_PER_MM, MIN_STATIC_VALVE_LIFT, damping_from_ratio
from ..schema import DynamicsSpec, RockerSpec, ValvetrainSpec
from .follower import FollowerModel
from .spring import DEFAULT_SEGMENTS, DEFAULT_SURGE_DAMPING, chain_segments


class Link(eqx.Module):
    """A spring and damper in compression only (a contact): what ``dynamics.contact_force`` reads."""

    train_stiffness: jax.Array  # N/m; inf: rigid
    train_damping: jax.Array  # N*s/m


class Rocker(eqx.Module):
    """A rocker's geometry in SI: each contact a point of the rocker at ``arm`` (m) from the pivot and ``angle``
    (rad) from the square to its line of motion at zero lift, pressing on a flat face square to that line. Turned
    by phi, a point lifts its face by ``arm (sin(angle + phi) - sin(angle))``: the follower's lift fixes phi, phi
    the valve's."""

    cam_arm: jax.Array  # m
    valve_arm: jax.Array  # m
    cam_angle: jax.Array  # rad
    valve_angle: jax.Array  # rad

    def lever(self, x_c: ArrayLike) -> tuple[jax.Array, jax.Array, jax.Array]:
        """At follower lift ``x_c`` (m): the cam's lift at the valve g (m), the ratio dg/dx_c and d2g/dx_c2 (1/m).
        NaN where the cam arm would turn past square to the follower's line (the caller's check refuses it)."""
        return _rocker_lever(jnp, x_c, self.cam_arm, self.valve_arm, self.cam_angle, self.valve_angle)

    def host_lever(self, x_c: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`lever` on the host, in numpy: outside a trace each jax operation is a program of its own, compiled
        in every process."""
        return self.bound_lever()(x_c)

    def bound_lever(self, scalar: bool = False) -> Callable[[Any], tuple[Any, Any, Any]]:
        """:meth:`host_lever` with the geometry read once (a call through the module reads each field again: tens of
        microseconds), in numpy, or with ``scalar`` of one lift in plain floats (``math``: a numpy scalar's operation
        costs a microsecond): for the thousands of calls of a sequential integration."""
        fields = tuple(float(v) for v in (self.cam_arm, self.valve_arm, self.cam_angle, self.valve_angle))
        if scalar:
            return lambda x_c: _rocker_lever(_SCALAR, x_c, *fields)
        return lambda x_c: _rocker_lever(np, np.asarray(x_c, dtype=float), *fields)


# the array module's functions :func:`_rocker_lever` calls, for plain floats
_SCALAR = SimpleNamespace(sin=math.sin, cos=math.cos, sqrt=math.sqrt, arcsin=math.asin)


def _rocker_lever(xp, x_c, a, b, al, be):
    """:meth:`Rocker.lever` in the array module ``xp`` (jax.numpy or numpy): arms ``a``, ``b`` (m), angles ``al``,
    ``be`` (rad)."""
    u = x_c / a + xp.sin(al)  # sin(al + phi)
    cos_a = xp.sqrt(1.0 - u**2)
    phi = xp.arcsin(u) - al
    g = b * (xp.sin(be + phi) - xp.sin(be))
    ratio = b * xp.cos(be + phi) / (a * cos_a)
    return g, ratio, b * xp.sin(al - be) / (a**2 * cos_a**3)


def rocker_model(spec: RockerSpec) -> Rocker:
    """The SI :class:`Rocker` of a ``[valvetrain.rocker]`` table (mm, deg)."""
    a = device_array
    return Rocker(
        a(spec.cam_arm * M_PER_MM),
        a(spec.valve_arm * M_PER_MM),
        a(math.radians(spec.cam_arm_angle)),
        a(math.radians(spec.valve_arm_angle)),
    )


def rocker_reach(rocker: Rocker, lift_mm: float) -> str | None:
    """Why the rocker cannot carry the follower to ``lift_mm`` (mm from zero lift), or None where it can: an arm
    turned to square with its contact's line would stall the train there, and past it reverse it."""
    al, be = float(rocker.cam_angle), float(rocker.valve_angle)
    u = lift_mm * M_PER_MM / float(rocker.cam_arm) + math.sin(al)
    if abs(u) >= 1.0:
        return f"the cam arm turns square to the follower's line before the follower's lift of {lift_mm:.4g} mm"
    turned = math.asin(u) - al + be
    if abs(turned) >= math.pi / 2:
        return f"the valve arm turns square to the valve's axis before the follower's lift of {lift_mm:.4g} mm"
    return None


def rocker_follower_lift(rocker: Rocker, valve_mm: np.ndarray) -> np.ndarray:
    """The follower's lift (mm) whose lift through the rocker at the valve is ``valve_mm`` (mm, the lash not taken
    off): the inverse of :meth:`Rocker.lever`'s g, in closed form (g fixes the turn phi by sin(be + phi) = g / b +
    sin(be), phi the follower's lift a (sin(al + phi) - sin(al))). NaN where only an arm turned to or past square
    with its contact's line would give it (:func:`rocker_valve_reach`)."""
    a, b = float(rocker.cam_arm), float(rocker.valve_arm)
    al, be = float(rocker.cam_angle), float(rocker.valve_angle)
    low, high = rocker_valve_reach(rocker)
    g = np.asarray(valve_mm, dtype=float)
    inside = (g > low[0]) & (g < high[0])
    phi = np.arcsin(np.clip(g * M_PER_MM / b + math.sin(be), -1.0, 1.0)) - be
    return np.where(inside, a * (np.sin(al + phi) - math.sin(al)) / M_PER_MM, np.nan)


def rocker_valve_reach(rocker: Rocker) -> tuple[tuple[float, str], tuple[float, str]]:
    """The least and the most lift (mm from zero lift, at the valve) the rocker can give, each with the arm that
    turns square to its contact's line there ("cam" or "valve"): the follower's lift through g is monotone between
    them (:func:`rocker_reach`)."""
    b, al, be = float(rocker.valve_arm), float(rocker.cam_angle), float(rocker.valve_angle)

    def at(sign: float) -> tuple[float, str]:
        turns = {"cam": sign * math.pi / 2 - al, "valve": sign * math.pi / 2 - be}  # the turn that squares each arm
        arm = min(turns, key=lambda k: abs(turns[k]))
        return b * (math.sin(be + turns[arm]) - math.sin(be)) / M_PER_MM, arm

    return at(-1.0), at(1.0)


class Coils(eqx.Module):
    """The valve spring as a chain of masses on the valve's side (``[spring] model = "surge"``): ``count`` segments
    fixed at the head, their inner lumps (``count - 1`` of them) free, the last half lump on the valve
    (:func:`camdyn.model.spring.chain_segments`)."""

    count: int = eqx.field(static=True)
    lump_mass: jax.Array  # kg, each inner lump
    segment_rate: jax.Array  # N/m, each segment: count x the spring's rate
    segment_damping: jax.Array  # N*s/m, each segment's damper


def coils_model(rate: float, spring_mass_kg: float) -> Coils:
    """The chain of a valve spring of ``rate`` (N/m) and mass ``spring_mass_kg`` (kg), at the default segments and
    surge damping."""
    lump, k_seg, c_seg = chain_segments(rate, spring_mass_kg, DEFAULT_SEGMENTS, DEFAULT_SURGE_DAMPING)
    return Coils(DEFAULT_SEGMENTS, jnp.asarray(lump), jnp.asarray(k_seg), jnp.asarray(c_seg))


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
    rocker: Rocker | None = None  # a rocker's geometry; None: the constant ``ratio``. With it ``ratio`` is the ratio
    # at the cam's peak lift (the nominal: where float begins), which the equivalent follower uses
    spring_damping_ratio: jax.Array = eqx.field(default_factory=lambda: jnp.asarray(math.nan))  # NaN: c was given
    coils: Coils | None = None  # the valve spring's surge ([spring] model = "surge"); None: its mass lumped, or none

    def lever(self, x_c: ArrayLike) -> tuple[jax.Array, jax.Array, jax.Array | float]:
        """At follower lift ``x_c`` (m): the cam's lift at the valve g (m), the ratio dg/dx_c and d2g/dx_c2 (1/m)."""
        if self.rocker is None:
            return self.ratio * x_c, self.ratio, 0.0
        return self.rocker.lever(x_c)

    def host_lever(self, x_c: ArrayLike) -> tuple[np.ndarray, np.ndarray | float, np.ndarray | float]:
        """:meth:`lever` on the host, in numpy (no compiled program)."""
        if self.rocker is None:
            ratio = float(self.ratio)
            return ratio * np.asarray(x_c, dtype=float), ratio, 0.0
        return self.rocker.host_lever(x_c)

    def at_valve_mm(self, lift_mm: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """At follower lifts ``lift_mm`` (mm), on the host: the lift through the rocker at the valve (mm, the lash
        not taken off) and the instantaneous ratio."""
        g, ratio, _ = self.host_lever(np.asarray(lift_mm, dtype=float) * M_PER_MM)
        shape = np.shape(lift_mm)
        return np.broadcast_to(np.asarray(g) / M_PER_MM, shape), np.broadcast_to(np.asarray(ratio), shape)

    @property
    def rigid_cam(self) -> bool:
        return bool(math.isinf(float(self.cam.train_stiffness)))

    @property
    def rigid_train(self) -> bool:
        return bool(math.isinf(float(self.train.train_stiffness)))

    @property
    def equivalent_mass(self) -> float:
        """The whole train's mass at the follower, kg: ``m_cam + m_valve r^2`` (on the host: a jax.numpy operation
        outside a compiled program compiles one of its own)."""
        return float(self.cam_side_mass) + float(self.valve_mass) * float(self.ratio) ** 2


def valvetrain_model(v: ValvetrainSpec, d: DynamicsSpec, peak_lift_mm: float = 0.0) -> ValvetrainModel:
    """SI valvetrain parameters from validated ``[valvetrain]`` and ``[dynamics]`` tables.

    Damping ratios become dampers on the mass each one moves: the valve spring's ``c = 2 zeta sqrt(k m)`` with the
    whole train's mass reduced to the valve (``m_valve + m_cam / r^2``), so that the equivalent follower's ratio is
    the same zeta; the train's on the valve (``c = 2 zeta sqrt(k_t m_valve)``); the cam contact's on the whole
    train at the follower (``m_cam + m_valve r^2``), as a single follower's would be. With a rocker, r is its
    ratio at the follower's ``peak_lift_mm`` (mm).
    """
    rocker = None if v.rocker is None else rocker_model(v.rocker)
    r = float(v.ratio) if rocker is None else float(rocker.host_lever(peak_lift_mm * M_PER_MM)[1])
    m_c, m_v = float(v.cam_side_mass), float(v.valve_mass)
    assert d.spring_rate is not None  # the valvetrain's check: [dynamics] gives the valve spring's rate
    k = TRANSLATING.rate_to_si(d.spring_rate)
    m_at_valve = m_v + m_c / r**2
    c = d.damping if d.damping is not None else damping_from_ratio(d.damping_ratio or 0.0, k, m_at_valve)
    kt = math.inf if v.stiffness is None else TRANSLATING.rate_to_si(v.stiffness)
    ct = 0.0 if math.isinf(kt) else damping_from_ratio(v.damping_ratio, kt, m_v)
    kf = math.inf if d.train_stiffness is None else TRANSLATING.rate_to_si(d.train_stiffness)
    cf = 0.0 if math.isinf(kf) else damping_from_ratio(d.train_damping_ratio, kf, m_c + m_v * r**2)
    a = device_array
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
        rocker,
        a(math.nan if d.damping is not None else (d.damping_ratio or 0.0)),
    )


def equivalent_follower(vt: ValvetrainModel) -> FollowerModel:
    """The single follower a rigid, lash-free valvetrain is, at the cam: mass ``m_cam + m_valve r^2``, spring rate
    ``k r^2``, preload ``F0 r``, damping ``c r^2`` (the same damping ratio), the tappet force as the external load,
    the same cam contact.
    The checks that know one follower read this; the valvetrain's own results come from the two-mass model."""
    r = float(vt.ratio)  # the products on the host, placed as the case's own model is (no program per operation)
    host = (vt.equivalent_mass, float(vt.spring_rate) * r**2, float(vt.preload) * r, float(vt.spring_damping) * r**2)
    mass, rate, preload, damping = (device_array(x) for x in host)
    return FollowerModel(
        mass,
        rate,
        preload,
        damping,
        vt.tappet_force,
        vt.cam.train_stiffness,
        vt.cam.train_damping,
        vt.cam_restitution,
        scale=M_PER_MM,
        damping_ratio=vt.spring_damping_ratio,
    )


def static_valve_lift(stroke: float, preload: float, train_rate: float, spring_rate: float) -> float:
    """The valve's lift with the cam turned slowly to ``stroke`` past the lash (at the valve): the train
    (``train_rate``; inf: rigid) and the valve spring (``spring_rate``, ``preload``) in series share it,
    ``(k_t stroke - F0) / (k_t + k)``. Any consistent units (mm, N and N/mm, or SI)."""
    if math.isinf(train_rate):
        return stroke
    return (train_rate * stroke - preload) / (train_rate + spring_rate)


def max_lifting_preload(stroke: float, train_rate: float, spring_rate: float) -> float:
    """The largest preload with which the valve still lifts :data:`MIN_STATIC_VALVE_LIFT` of ``stroke`` with the cam
    turned slowly (:func:`static_valve_lift`): what a case accepts; inf for a rigid train (``train_rate`` inf). Any
    consistent units."""
    if math.isinf(train_rate):
        return math.inf
    return (train_rate - MIN_STATIC_VALVE_LIFT * (train_rate + spring_rate)) * stroke


def lift_with_ramps(theta_deg: np.ndarray, lift: np.ndarray, lash: float, ramp_velocity: float) -> np.ndarray:
    """The cam's lift at the valve (mm, ``r`` times the follower's) that gives the valve ``lift`` (mm) at
    ``theta_deg`` (one revolution, increasing) with ``lash`` (mm) taken up by constant-velocity ramps of
    ``ramp_velocity`` (mm per cam degree): ``lift + lash`` while the valve is open; before it opens and after it
    closes a ramp from the base circle to ``lash`` over ``lash / ramp_velocity`` degrees; 0 elsewhere.
    ValueError for a valve that never opens or opens more than once a revolution."""
    n = len(lift)
    rise, fall = _event_rows(lift)
    seat_open = theta_deg[(rise - 1) % n]  # the last row on the seat before the event, and the first after
    seat_close = theta_deg[(fall + 1) % n]
    to_open = (seat_open - theta_deg) % 360.0
    from_close = (theta_deg - seat_close) % 360.0
    ramp = np.maximum(0.0, lash - ramp_velocity * np.minimum(to_open, from_close))
    return np.where(lift > 0.0, lift + lash, ramp)


def _event_rows(lift: np.ndarray) -> tuple[int, int]:
    """The first and the last open row (lift > 0) of a valve's one event a revolution. ValueError for a valve that
    never opens, never closes or opens more than once a revolution."""
    open_ = lift > 0.0
    if not open_.any():
        raise ValueError("the valve never lifts: no lift_mm above 0")
    if open_.all():
        raise ValueError("the valve never closes: no lift_mm of 0")
    rises = np.flatnonzero(open_ & ~np.roll(open_, 1))  # the first open row of each event
    if len(rises) > 1:
        raise ValueError(f"the valve opens {len(rises)} times a revolution: camdyn models one event")
    return int(rises[0]), int(np.flatnonzero(open_ & ~np.roll(open_, -1))[0])


def ramp_join_warnings(theta_deg: np.ndarray, lift: np.ndarray, ramp_velocity: float) -> list[str]:
    """Where a valve's lift table opens or closes at a speed far from the lash ramp's (mm per cam degree), the cam's
    velocity jumps as the ramp joins it: the fit smooths the jump into a spike of acceleration that a follower held
    by ``tappet_force`` alone cannot follow. One line per such end (none for a table that meets its ramps).
    ``lift``: a table :func:`lift_with_ramps` takes (ValueError otherwise, as there)."""
    n = len(lift)
    rise, fall = _event_rows(lift)
    out = []
    for name, seat, inner in (("opens", rise - 1, rise + 1), ("closes", fall + 1, fall - 1)):
        # the mean slope over the two table steps from the seat: the valve's speed as it leaves or meets it
        span = abs(theta_deg[inner % n] - theta_deg[seat % n]) % 360.0
        speed = float(lift[inner % n]) / span if span > 0.0 else math.inf
        if not 0.5 <= speed / ramp_velocity <= 2.0:
            out.append(
                f"the valve table {name} at {speed:.3g} mm/deg near {theta_deg[seat % n]:g} deg and the "
                f"lash ramp at {ramp_velocity:g} (valvetrain.ramp_velocity): the cam's velocity jumps where they "
                "join and the follower leaves the cam there unless valvetrain.tappet_force holds it; a table from a "
                "cam card starts and ends at its ramp's speed"
            )
    return out


def lift_off(vt: ValvetrainModel) -> tuple[float, float]:
    """Where :func:`event_follower`'s follower sits while the valve is seated (m: the lash at the cam, ``lash / r``)
    and the train's force on it that lifts the valve off its seat (N: the preload at the cam, ``F0 r``)."""
    r = float(vt.ratio)
    return float(vt.lash) / r, float(vt.preload) * r


def event_follower(vt: ValvetrainModel) -> tuple[FollowerModel, float]:
    """The single follower that stands for a valvetrain over its event (the lash taken up, a constant ratio r), and
    the mass (kg) that moves with the cam beside it. The valve spring is ``k r^2`` with the preload it has at the
    valve's lift, ``(F0 - k lash) r``; the tappet force is left to the caller (it loads the cam, not the valve).
    A rigid train is the equivalent follower; a compliant train on a rigid cam contact is the valve on the train
    reduced to the cam (mass m_v r^2, train k_t r^2 and c_t r^2), the cam side's m_c moving with the cam beside it
    (the cam's force is the train's plus m_c s'' w^2: exact in contact, with the valve's start from rest on its seat
    where it lifts off, :func:`lift_off`); a compliant train on a compliant cam
    contact, the whole mass on the two contacts in series."""
    r = vt.ratio
    eq = equivalent_follower(vt)
    eq = eqx.tree_at(
        lambda m: (m.preload, m.external), eq, ((vt.preload - vt.spring_rate * vt.lash) * r, jnp.zeros(()))
    )
    if vt.rigid_train:
        return eq, 0.0
    kt, ct = vt.train.train_stiffness * r**2, vt.train.train_damping * r**2
    if vt.rigid_cam:
        return eqx.tree_at(
            lambda m: (m.mass, m.train_stiffness, m.train_damping), eq, (vt.valve_mass * r**2, kt, ct)
        ), (float(vt.cam_side_mass))
    kc, cc = vt.cam.train_stiffness, vt.cam.train_damping
    series = kc * kt / (kc + kt)
    return eqx.tree_at(lambda m: (m.train_stiffness, m.train_damping), eq, (series, cc * series / kc)), 0.0
