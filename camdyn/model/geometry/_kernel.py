"""The geometry of one contact, exact by autodiff of the motion's Taylor polynomial, vectorised and compiled
once per follower type; and the assembly conditions a follower must meet."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import InputError
from ..._core.jit import cached_jit
from ..._core.kinds import FollowerType
from ...schema import FollowerSpec
from ..motion import evaluate

if TYPE_CHECKING:
    from ..motion import Motion

_BREAK_EPS = 1e-9  # rad: one-sided limits at the motion's breaks, where s'' may jump


def check_assembly(motion: Motion, f: FollowerSpec) -> None:
    """Raise :class:`InputError` for a follower that cannot carry this motion or cannot be assembled (the keys
    each follower type needs are the schema's: :class:`camdyn.schema.FollowerSpec`)."""
    want = f.kind.motion_unit
    if motion.unit != want:
        raise InputError("follower.type", f"a {f.type} follower needs a motion in {want}, got {motion.unit}")
    check_dimensions(f)


def check_dimensions(f: FollowerSpec) -> None:
    """Raise :class:`InputError` for a follower whose dimensions cannot be assembled on its base circle."""
    assert f.base_radius is not None  # a built follower has it (from the contour where one is given)
    rp = f.base_radius + (f.roller_radius or 0.0)
    if f.translating and f.roller and abs(f.offset) >= rp:
        raise InputError("follower.offset", f"|offset| = {abs(f.offset):g} mm must be below the prime radius {rp:g} mm")
    if not f.translating:
        L = f.pivot_distance
        assert L is not None  # the schema: an oscillating follower needs it
        if f.roller:
            a = f.arm_length
            assert a is not None  # the schema: an oscillating roller needs it
            if not abs(L - a) < rp < L + a:
                raise InputError(
                    "follower.arm_length",
                    f"the roller cannot reach the prime circle (radius {rp:g} mm): need |L - a| < Rp < L + a "
                    f"with L = {L:g} mm, a = {a:g} mm",
                )
        elif not abs(f.base_radius + f.offset) < L:
            raise InputError(
                "follower.pivot_distance",
                f"the face cannot touch the base circle: need |base_radius + offset| = "
                f"{abs(f.base_radius + f.offset):g} mm < pivot_distance = {L:g} mm",
            )


def follower_params(f: FollowerSpec, base_radius: float | None = None) -> np.ndarray:
    """The follower's dimensions as the geometry's programs take them (:func:`geometry_of`): an array, data of a
    compiled program, so followers of one type share it and the base circle's bisection does not recompile."""
    rb = f.base_radius if base_radius is None else base_radius
    return np.array(
        [
            rb,
            f.roller_radius or 0.0,
            f.offset,
            f.pivot_distance or 0.0,
            math.radians(f.pivot_angle),
            f.arm_length or 0.0,
            f.sigma,
        ]
    )


# ------------------------------------------------------------------------------ follower geometry
def _rot(angle, v):
    c, s = jnp.cos(angle), jnp.sin(angle)
    return jnp.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _J(v):  # rotation by +90 deg
    return jnp.stack([-v[1], v[0]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _pivot(p):
    """Pivot D and the unit vector u from D towards O (fixed frame)."""
    d = jnp.stack([jnp.cos(p[4]), jnp.sin(p[4])])
    return p[3] * d, -d


def _roller_centre(ftype: FollowerType, p, q):
    """Roller centre in the fixed frame at follower coordinate q (mm or rad)."""
    rb, rr, e, L, _, a, sigma = p
    rp = rb + rr
    if not ftype.kind.rotary:
        return jnp.stack([sigma * e, jnp.sqrt(rp**2 - e**2) + q])
    D, u = _pivot(p)
    psi0 = jnp.arccos((L**2 + a**2 - rp**2) / (2 * L * a))
    return D + a * _rot(-(psi0 + q), u)


def _flat_face(ftype: FollowerType, p, q):
    """Face of a flat follower in the fixed frame at coordinate q.

    Returns (m, h, foot, along): the cam's outward normal at the contact (unit), the face's distance from O,
    the face's reference point (axis or foot of the pivot's perpendicular) and the unit direction along the
    face in which the face coordinate t is counted.
    """
    rb, _, e, L, _, _, sigma = p
    if not ftype.kind.rotary:
        m = jnp.array([0.0, 1.0])
        return m, rb + q, jnp.stack([sigma * e, rb + q]), jnp.stack([sigma, 0.0 * sigma])
    D, u = _pivot(p)
    psi = jnp.arcsin((rb + e) / L) + q
    w = _rot(-psi, u)
    n = _J(w)
    return -n, L * jnp.sin(psi) - e, D + e * n, w


def _jet2(F):
    """F(0), F'(0), F''(0) of a function of one scalar by forward-mode autodiff."""
    d1 = jax.jacfwd(F)
    return F(0.0), d1(0.0), jax.jacfwd(d1)(0.0)


def _taylor(sv):
    """The follower coordinate about a cam angle as the cubic Taylor polynomial of the motion values sv."""
    return lambda t: sv[0] + t * (sv[1] + t * (sv[2] / 2 + t * sv[3] / 6))


def roller_point(
    centre: Callable[[jax.Array], jax.Array],
    sigma: ArrayLike,
    rr: ArrayLike,
    th0: ArrayLike,
    sv: ArrayLike,
    drive: float = 1.0,
) -> dict[str, jax.Array | float]:
    """A roller's contact at cam angle th0 (rad): ``centre`` maps the follower coordinate to the roller centre in
    the fixed frame; ``drive`` +1 where the cam pushes the follower towards increasing coordinate, -1 where it
    pushes it back (a conjugate cam: its pressure angle and lever taken along the direction it drives)."""
    sigma, sv = jnp.asarray(sigma), jnp.asarray(sv)
    q_of = _taylor(sv)
    cam = lambda t, v: _rot(-sigma * (th0 + t), v)  # noqa: E731
    P, P1, P2 = _jet2(lambda t: cam(t, centre(q_of(t))))
    speed = jnp.hypot(P1[0], P1[1])
    N = sigma * _J(P1) / speed  # outward: the pitch curve runs cw for a ccw cam and vice versa
    kappa = -sigma * _cross(P1, P2) / speed**3  # convex positive
    v = drive * cam(0.0, jax.jacfwd(centre)(sv[0]))
    return dict(
        pitch=P,
        contour=P - rr * N,
        normal=N,
        kappa_pitch=kappa,
        rho_contour=(1.0 - rr * kappa) / kappa,
        phi=sigma * jnp.arctan2(_cross(v, N), v @ N),
        lever=v @ N,
        face_t=jnp.nan,
    )


def _point(ftype: FollowerType, p, th0, sv):
    """Everything camdyn judges at one cam angle th0 (rad), given the motion values sv = (s, s', s'', s''').

    The follower coordinate is expanded as the cubic Taylor polynomial of the motion about th0, so autodiff of
    the geometry in t gives exact tangents and curvatures from the motion's closed-form derivatives.
    """
    sigma = p[6]
    cam = lambda t, v: _rot(-sigma * (th0 + t), v)  # noqa: E731
    nan = jnp.nan
    if ftype.roller:
        return roller_point(lambda q: _roller_centre(ftype, p, q), sigma, p[1], th0, sv)
    q_of = _taylor(sv)

    def face(
        t: ArrayLike,
    ) -> tuple[jax.Array, jax.Array]:  # the face line in the cam frame: unit normal m and distance h from O
        m_fixed, h, _, _ = _flat_face(ftype, p, q_of(t))
        return cam(t, m_fixed), h

    (m, h), (m1, h1), (m2, h2) = _jet2(face)
    _, _, foot, along = _flat_face(ftype, p, sv[0])
    foot, along = cam(0.0, foot), cam(0.0, along)
    a1, a2 = _cross(m, m1), _cross(m, m2)  # d alpha / d theta and its derivative (|m| = 1)
    C = h * m + (h1 / a1) * _J(m)  # envelope of the lines x . m = h
    if not ftype.kind.rotary:
        v = m
    else:  # velocity of the follower point at C for d psi = 1: the arm turns clockwise about D
        D = cam(0.0, _pivot(p)[0])
        v = -_J(C - D)
    return dict(
        pitch=foot,
        contour=C,
        normal=m,
        kappa_pitch=nan,
        rho_contour=h + (h2 * a1 - h1 * a2) / a1**3,
        phi=sigma * jnp.arctan2(_cross(v, m), v @ m),
        lever=v @ m,
        face_t=(C - foot) @ along,
    )


def geometry_of(ftype: FollowerType, params: ArrayLike, theta: ArrayLike, sv: jax.Array) -> dict:
    """The geometry at cam angles ``theta`` (rad) from motion values ``sv`` = (s, s', s'', s''') of shape (4, n),
    as a traceable JAX function of ``sv``, for a follower of type ``ftype`` with dimensions ``params``
    (:func:`follower_params`): what the optimizer differentiates (pressure angle ``phi`` rad, ``kappa_pitch``
    1/mm, ``rho_contour`` mm, ``lever`` mm)."""
    return jax.vmap(lambda th, s: _point(ftype, jnp.asarray(params), th, s), in_axes=(0, 1))(theta, sv)


@cached_jit
def _geometry(p, theta, sv, ftype: FollowerType):
    """:func:`geometry_of` as a stored program, compiled once per follower type and array bucket whatever the
    motion (it is evaluated apart), the rotation and the lengths: sweeps and base-circle bisection reuse it."""
    return geometry_of(ftype, p, theta, sv)


_CHUNK = 4096  # angles per compiled call: a 3600-step revolution plus its breaks fits one


def evaluate_geometry(
    motion: Motion, f: FollowerSpec, theta_rad: ArrayLike, base_radius: float | None = None
) -> dict[str, np.ndarray]:
    """Evaluate at any number of angles (rad) in fixed-size chunks, so nothing recompiles per query size."""
    return geometry_on(sample_motion(motion, theta_rad), f, base_radius)


def geometry_on(samples: MotionSamples, f: FollowerSpec, base_radius: float | None = None) -> dict[str, np.ndarray]:
    """:func:`evaluate_geometry` on a motion already sampled (:func:`sample_motion`) at its angles."""
    p = follower_params(f, base_radius)
    return on_samples(samples, lambda theta, sv: _geometry(p, theta, sv, f.follower_type))


@dataclass(frozen=True)
class MotionSamples:
    """A motion's values (s and its first three derivatives) at angles, in the fixed-size chunks of :data:`_CHUNK`
    angles the geometry programs take: sampled once where several geometries of one motion are evaluated (the
    base-circle search evaluates some 70)."""

    theta: np.ndarray  # the angles (rad), any shape
    chunks: tuple[tuple[np.ndarray, np.ndarray], ...]  # (angles, values (4, n)) of each chunk, zero-padded


def sample_motion(motion: Motion, theta_rad: ArrayLike) -> MotionSamples:
    """``motion`` at any number of angles (rad), in :data:`_CHUNK`-angle chunks."""
    theta_rad = np.asarray(theta_rad, dtype=float)
    flat = np.atleast_1d(theta_rad).ravel()
    padded = np.zeros(max(1, -(-flat.size // _CHUNK)) * _CHUNK)
    padded[: flat.size] = flat
    # numpy between the programs: an eager jax op compiles one of its own
    chunks = tuple((theta, np.asarray(evaluate(motion, theta))) for theta in padded.reshape(-1, _CHUNK))
    return MotionSamples(theta_rad, chunks)


def on_samples(samples: MotionSamples, program: Callable[[np.ndarray, np.ndarray], dict]) -> dict[str, np.ndarray]:
    """``program(theta, sv)`` (a compiled geometry of :data:`_CHUNK` angles) over the sampled angles, plus the
    motion ``s``, each shaped as the angles."""
    n, shape = samples.theta.size, samples.theta.shape
    parts = [program(theta, sv) | {"s": sv[0]} for theta, sv in samples.chunks]
    out = {k: np.concatenate([np.asarray(part[k]) for part in parts])[:n] for k in parts[0]}
    return {k: v.reshape(shape + v.shape[1:]) for k, v in out.items()}


def chunked(
    motion: Motion, theta_rad: ArrayLike, program: Callable[[np.ndarray, np.ndarray], dict]
) -> dict[str, np.ndarray]:
    """``program(theta, sv)`` (a compiled geometry of :data:`_CHUNK` angles) over any number of angles (rad), in
    fixed-size chunks, plus the motion ``s``."""
    return on_samples(sample_motion(motion, theta_rad), program)


def with_breaks(motion: Motion, theta_rad: np.ndarray) -> np.ndarray:
    """theta plus the one-sided limits at every break: extremes of s'' terms may sit exactly there."""
    b = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
    return np.concatenate([theta_rad, np.mod(b - _BREAK_EPS, 2 * np.pi), b + _BREAK_EPS])
