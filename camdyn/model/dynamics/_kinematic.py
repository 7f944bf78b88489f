"""The kinematic interface force of a follower that never leaves the cam, and its closed-form jump speed."""

from __future__ import annotations

import math

import jax
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import cached_jit, on_angle_buckets
from ..._core.minimize import minimize_bounded
from ..._core.units import THETA_GRID, TWO_PI
from ..follower import FollowerModel
from ..motion import Motion


def kinematic_force(motion: Motion, model: FollowerModel, omega: ArrayLike, theta: ArrayLike) -> jax.Array:
    """Interface force of a follower that never leaves the cam (CCM paper eq. 7), N.

    ``Fi = m w^2 s'' + c w s' + k s + F0 + F_ext`` with s in SI (scale applied), w in rad/s.
    """
    s, s1, s2, _ = motion(theta) * model.scale
    return kinematic_force_of(model, omega, s, s1, s2)


def kinematic_force_of(
    model: FollowerModel,
    omega: ArrayLike,
    s: ArrayLike,
    s1: ArrayLike,
    s2: ArrayLike,
    stiffness: ArrayLike | None = None,
    damping: ArrayLike | None = None,
) -> jax.Array:
    """:func:`kinematic_force` from the motion's values in SI (s, ds/dtheta, d2s/dtheta2); ``stiffness`` and
    ``damping`` (SI) replace the model's spring where given (arrays: a grid of spring rates is one ``vmap``)."""
    k = model.stiffness if stiffness is None else stiffness
    c = model.damping if damping is None else damping
    return model.mass * omega**2 * s2 + c * omega * s1 + k * s + model.preload + model.external


_kinematic_force_program = cached_jit(kinematic_force)


def least_static_force(motion: Motion, model: FollowerModel) -> tuple[float, float]:
    """The least kinematic force at rest round the cam, ``k s + F0 + F_ext`` (N, or N*m), on ``THETA_GRID`` angles,
    and its angle (deg): the interface force of a cam turned slowly where it is lowest (at the lowest lift for a
    positive spring rate), whatever the train. numpy on the host: no program to compile."""
    theta_deg = np.arange(THETA_GRID) * (360.0 / THETA_GRID)
    host = jax.device_get(model)
    at_rest = np.asarray(kinematic_force_of(host, 0.0, motion.host(np.deg2rad(theta_deg))[0] * host.scale, 0.0, 0.0))
    i = int(at_rest.argmin())
    return float(at_rest[i]), float(theta_deg[i])


def kinematic_force_jit(
    motion: Motion, model: FollowerModel, omega: ArrayLike, theta: ArrayLike
) -> jax.Array | np.ndarray:
    """:func:`kinematic_force` compiled once per motion form and bucket of angles
    (:func:`camdyn._core.jit.on_angle_buckets`), for every speed: ``omega`` goes in as data (a Python float would be a
    static argument of the stored program, one program per speed)."""
    w = np.asarray(omega, dtype=float)
    return on_angle_buckets(lambda t: _kinematic_force_program(motion, model, w, t), theta)


def store_kinematic_force(motion: Motion, model: FollowerModel) -> None:
    """Compile and store :func:`kinematic_force_jit`'s program at one angle (a lift-off's root search) where it is
    missing, without loading a stored one (nothing where the program cache is off)."""
    _kinematic_force_program.store(motion, model, np.asarray(1.0), np.zeros(()))  # pyright: ignore[reportFunctionMemberAccess]


def velocity_steps(motion: Motion, restitution: float) -> list[tuple[float, float]]:
    """(cam angle rad, how much faster than the cam the follower leaves it, motion units per rad) at each step of
    the cam's velocity (:meth:`camdyn.model.motion.Motion.velocity_jumps`) that throws a rigid follower off: a drop
    leaves it moving at the cam's speed before; a rise strikes it, and it rebounds by the restitution."""
    out = []
    for deg, jump in motion.velocity_jumps():
        dv = -jump if jump < 0.0 else restitution * jump
        if dv > 0.0:
            out.append((math.radians(deg), dv))
    return out


def _quadratic_jump_speed(a, b, c):
    """Least w > 0 with a w^2 + b w + c <= 0 given c > 0 (inf where none); vectorized numpy."""
    a, b, c = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float), np.asarray(c, float))
    w = np.full(a.shape, np.inf)
    with np.errstate(invalid="ignore", divide="ignore"):
        lin = np.abs(a) <= 1e-300
        w = np.where(lin & (b < 0), -c / np.where(b < 0, b, -1.0), w)
        disc = b * b - 4 * a * c
        sq = np.sqrt(np.maximum(disc, 0.0))
        # a < 0: exactly one positive root; a > 0: the smaller root, positive only if b < 0 and disc >= 0
        neg = (~lin) & (a < 0)
        w = np.where(neg, (-b - sq) / (2 * np.where(neg, a, 1.0)), w)
        pos = (~lin) & (a > 0) & (b < 0) & (disc >= 0)
        q = -0.5 * (b - sq)  # stable form of the smaller root: c / q
        w = np.where(pos, c / np.where(pos, q, 1.0), w)
    return w


def kinematic_jump_speed(motion: Motion, model: FollowerModel, n: int = 7200) -> tuple[float, float]:
    """Least cam speed (rad/s) at which the kinematic interface force reaches zero, and the angle (deg).

    At each angle Fi is the quadratic ``(m s'') w^2 + (c s') w + (k s + F0 + F_ext)`` in w, whose least
    positive root is closed form; the minimum over angles is taken on an n-point grid and polished with a
    bounded scalar minimization of the same closed form. ``(inf, nan)`` when no speed makes it jump; ``(0, the
    angle)`` where a step in the cam's velocity throws the follower off at any speed (:func:`velocity_steps`).
    """
    if steps := velocity_steps(motion, float(model.restitution)):
        return 0.0, math.degrees(steps[0][0])
    m, c, k = (float(model.mass), float(model.damping), float(model.stiffness))
    f0 = float(model.preload) + float(model.external)

    def w_at(theta: ArrayLike) -> np.ndarray:
        s, s1, s2, _ = motion.host(np.asarray(theta, dtype=float)) * model.scale  # numpy where it can: no program
        return _quadratic_jump_speed(m * s2, c * s1, k * s + f0)

    theta = np.arange(n) * (TWO_PI / n)
    w = w_at(theta)
    i = int(np.argmin(w))
    if not np.isfinite(w[i]):
        return math.inf, math.nan
    h = TWO_PI / n
    cap = 1e6 * w[i]  # a finite stand-in for "no jump here": Brent's parabola steps turn inf into NaN

    def objective(t: float) -> float:
        return min(float(w_at(np.array([t]))[0]), cap)

    x, fx, _ = minimize_bounded(objective, theta[i] - h, theta[i] + h, xatol=1e-10)
    if fx < w[i]:
        return float(fx), math.degrees(x) % 360.0
    return float(w[i]), math.degrees(theta[i])
