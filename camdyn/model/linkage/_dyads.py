"""Assur dyads: RRR (three revolute joints) and RRP (a slider on a fixed line), with their kinematics.

An RRR dyad with outer joints P, Q and middle joint M has assembly mode +1 when P, M, Q run anticlockwise
(Ye & Smith, Appendix 2, the "solid" mode: theta_PM = theta_PQ - angle MPQ), -1 otherwise. Lengths mm.
"""

from __future__ import annotations

from typing import Any, TypeVar

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..paths import taylor

Vec = TypeVar("Vec", jax.Array, np.ndarray)  # a host (numpy) array or a device or traced one: computed in its library


def _xp(*xs) -> Any:  # numpy or jax.numpy
    """numpy for host values (the synthesis' checks on its samples: no program to compile, and the same numbers as
    JAX's operations one by one), jax.numpy for device arrays and traced ones."""
    return jnp if any(isinstance(x, jax.Array) for x in xs) else np


def cross2(a: Vec, b: Vec) -> Vec:
    """z component of a x b for 2-vectors (..., 2)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def cw(v: Vec) -> Vec:
    """v turned clockwise by 90 degrees."""
    return _xp(v).stack([v[..., 1], -v[..., 0]], axis=-1)


def unit(angle: ArrayLike) -> Any:
    """Unit vector at ``angle`` (rad)."""
    xp = _xp(angle)
    return xp.stack([xp.cos(angle), xp.sin(angle)], axis=-1)


def turn(v: Vec, angle: ArrayLike) -> Vec:
    """v turned anticlockwise by ``angle`` (rad)."""
    xp = _xp(v, angle)
    c, s = xp.cos(angle), xp.sin(angle)
    return xp.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def rrr_reach_miss(p: ArrayLike, q: ArrayLike, lp: float | Vec, lq: float | Vec) -> Vec:
    """How far (mm) the RRR dyad P-M-Q is from closing: 0 when |lp - lq| <= |PQ| <= lp + lq."""
    xp = _xp(p, q, lp, lq)
    d = xp.linalg.norm(xp.asarray(q) - xp.asarray(p), axis=-1)
    return xp.maximum(xp.maximum(d - (lp + lq), abs(lp - lq) - d), 0.0)


def rrr(p: ArrayLike, q: ArrayLike, lp: float | Vec, lq: float | Vec, mode: ArrayLike) -> Vec:
    """Middle joint M of an RRR dyad with |M - P| = lp, |M - Q| = lq (mm).

    ``mode`` +1: P, M, Q anticlockwise (Ye & Smith's solid lines), -1: clockwise. Works on (..., 2) arrays;
    a dyad that cannot close gives NaN (check :func:`rrr_reach_miss` first for a message).
    """
    xp = _xp(p, q, lp, lq, mode)
    pa, qa = xp.asarray(p, dtype=float), xp.asarray(q, dtype=float)
    v = qa - pa
    d2 = xp.sum(v * v, axis=-1)
    x = (lp * lp - lq * lq + d2) / (2.0 * d2)  # foot of M on PQ, as a fraction of PQ
    with np.errstate(invalid="ignore"):  # NaN where the dyad cannot close, as in JAX
        h = xp.sqrt(lp * lp / d2 - x * x)  # distance of M from PQ, as a fraction of |PQ|
    return pa + x[..., None] * v + (mode * h)[..., None] * cw(v)


def rrp(c: jax.Array, origin: jax.Array, direction: jax.Array, length: ArrayLike, mode: ArrayLike) -> jax.Array:
    """Slider point E on the line ``origin + p * direction`` with |E - C| = ``length``: returns p (mm).

    ``mode`` +1 takes E ahead of the foot of C on the line (along ``direction``, a unit vector), -1 behind.
    """
    w = jnp.asarray(c, dtype=float) - origin
    along = jnp.sum(w * direction, axis=-1)
    off = cross2(direction, w)
    return along + mode * jnp.sqrt(length * length - off * off)


def _kinematics(fn, *xs):
    """Position, velocity and acceleration of ``fn`` of points moving as x(tau) = x0 + v tau + a tau^2 / 2."""

    def at(tau: ArrayLike) -> jax.Array:
        return fn(*[x[0] + x[1] * tau + 0.5 * x[2] * tau * tau for x in xs])

    vals = taylor(lambda tau: jnp.concatenate([jnp.atleast_1d(y) for y in at(tau)]), jnp.zeros(()), 2)
    return vals


def rrr_kinematics(p: jax.Array, q: jax.Array, lp: float, lq: float, mode: int) -> dict:
    """RRR dyad kinematics (Ye & Smith Appendix 2) by forward-mode autodiff.

    ``p``, ``q``: (3, 2) arrays of position (mm), velocity (mm/s) and acceleration (mm/s^2) of the outer joints.
    Returns ``M`` (3, 2) for the middle joint and ``theta_pm``, ``theta_qm`` (3,): the link angles (rad),
    angular velocities (rad/s) and accelerations (rad/s^2) of P->M and Q->M.
    """

    def fn(p_: jax.Array, q_: jax.Array) -> tuple[jax.Array, jax.Array, jax.Array]:
        m = rrr(p_, q_, lp, lq, mode)
        dp, dq = m - p_, m - q_
        return m, jnp.arctan2(dp[1], dp[0]), jnp.arctan2(dq[1], dq[0])

    vals = _kinematics(fn, jnp.asarray(p, dtype=float), jnp.asarray(q, dtype=float))
    out = jnp.stack(vals)  # (3, 4)
    return {"M": out[:, :2], "theta_pm": out[:, 2], "theta_qm": out[:, 3]}


def rrp_kinematics(c: jax.Array, origin: jax.Array, direction: jax.Array, length: float, mode: int) -> dict:
    """RRP dyad kinematics: ``c`` (3, 2) position, velocity, acceleration of the pin C; the line is fixed.

    Returns ``p`` (3,): slider coordinate (mm), velocity and acceleration, and ``theta_ce`` (3,) for link C->E.
    """
    origin, direction = jnp.asarray(origin, dtype=float), jnp.asarray(direction, dtype=float)

    def fn(c_: jax.Array) -> tuple[jax.Array, jax.Array]:
        p = rrp(c_, origin, direction, length, mode)
        e = origin + p * direction - c_
        return p, jnp.arctan2(e[1], e[0])

    out = jnp.stack(_kinematics(fn, jnp.asarray(c, dtype=float)))
    return {"p": out[:, 0], "theta_ce": out[:, 1]}


def norm(v: jax.Array) -> jax.Array:
    """Length of 2-vectors (..., 2)."""
    return jnp.sqrt(jnp.sum(v * v, axis=-1))
