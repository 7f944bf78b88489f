"""The return spring as a chain of masses (``[spring] model = "surge"``): spring surge in the follower dynamics.

The lumped model puts a third of the spring's mass on the follower (:func:`camdyn.model.follower.with_spring_mass`),
which holds while the lift's harmonics stay well below the spring's surge frequency. Here the spring of rate k
and mass m_s is ``segments`` = N equal lumps joined by springs of rate N k, fixed at the far end; the lump at
each end is half a lump, and the one at the follower moves with it. The case's damper c stays on the follower
(so a slow stroke sees exactly the lumped model); the coils' own damping is a damper N c_s across each segment,
with c_s set so the spring's first surge mode (fixed at both ends, f_s = (1/2) sqrt(k / m_s)) has the damping
ratio ``surge_damping`` (stiffness-proportional: higher surge modes are damped more). Its surge modes make the
spring force at the follower swing more than k x + F0 when a harmonic of the lift drives them, and the
follower can leave the cam at a lower speed.

Nodes q = (u_1, ..., u_{N-1}, x): coil positions and the follower, SI (m, or rad for an arm, with the spring's
mass as the rotational equivalent m_s r^2). While the follower touches the cam the chain is linear with a
periodic input, so its steady state is exact per harmonic h of the cam speed w (as for the lumped model,
:mod:`camdyn.model.dynamics._harmonic`):

    (K - (h w)^2 M + i h w C) Q_h = e_x (k_f + i h w c_f) S_h,   F_i = k_f (s - x) + c_f (s' - x') w

for a compliant train; a rigid follower moves with the cam (x = s) and F_i is the force that takes. The diffrax
time-domain model (:func:`chain_revolution`) integrates the same chain with the contact law max(0, F_i), the
reference for the frequency-domain orbit.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from .._core.errors import InputError, NumericalError
from .._core.units import FFT_GRID, RPM, TWO_PI
from .dynamics import contact_force, dynamic_jump_speed, first_zero_speed, train_force
from .follower import FollowerModel, with_spring_mass
from .motion import Motion, evaluate
from .spring import DEFAULT_SEGMENTS, DEFAULT_SURGE_DAMPING, chain_segments


def _matrices(model: FollowerModel, spring_mass: float, segments: int, surge_damping: float):
    """Node masses (N,), stiffness and damping (N, N) of the chain with the follower as the last node (no train)."""
    if segments < 1 or not spring_mass > 0:
        raise InputError(
            "spring", f"a chain needs at least one segment and a positive spring mass (got {segments}, {spring_mass})"
        )
    n = segments
    lump, k_seg, c_seg = chain_segments(float(model.stiffness), spring_mass, n, surge_damping)
    mass = np.full(n, lump)
    mass[-1] = float(model.mass) + lump / 2
    band = np.diag(np.full(n, 2.0)) - np.diag(np.ones(n - 1), 1) - np.diag(np.ones(n - 1), -1)
    band[-1, -1] = 1.0
    K, C = k_seg * band, c_seg * band
    C[-1, -1] += float(model.damping)
    return mass, K, C


def _spectrum(motion: Motion, model: FollowerModel, n: int):
    """The motion (SI) on ``theta_j = 2 pi j / n`` and the lift's spectrum."""
    vals = np.asarray(evaluate(motion, jnp.arange(n) * (TWO_PI / n))) * model.scale
    return vals, np.fft.rfft(vals[0])


def chain_steady_force(
    motion: Motion,
    model: FollowerModel,
    spring_mass: float,
    omega: float,
    *,
    segments: int = DEFAULT_SEGMENTS,
    surge_damping: float = DEFAULT_SURGE_DAMPING,
    n: int = FFT_GRID,
    _spec: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Interface force (N, or N*m) on ``theta_j = 2 pi j / n`` of the chain's periodic orbit while the follower
    stays on the cam, and the nodes' orbit q (n, N) with its dq/dtheta (SI). Exact wherever the force stays
    positive."""
    mass, K, C = _matrices(model, spring_mass, segments, surge_damping)
    vals, S = _spec if _spec is not None else _spectrum(motion, model, n)
    h = np.arange(S.size)
    wh = h * omega
    ext = float(model.preload) + float(model.external)
    if model.rigid:  # the follower moves with the cam: solve the coils, driven through the last segment
        Kc, Cc, mc = K[:-1, :-1], C[:-1, :-1], mass[:-1]
        kn, cn = -K[-2, -1] if segments > 1 else 0.0, -C[-2, -1] if segments > 1 else 0.0
        Q = np.zeros((S.size, segments), complex)
        Q[:, -1] = S
        if segments > 1:
            A = Kc[None] - (wh**2)[:, None, None] * np.diag(mc)[None] + 1j * wh[:, None, None] * Cc[None]
            b = np.zeros((S.size, segments - 1), complex)
            b[:, -1] = (kn + 1j * wh * cn) * S
            Q[:, :-1] = np.linalg.solve(A, b[..., None])[..., 0]
    else:
        kf, cf = float(model.train_stiffness), float(model.train_damping)
        K, C = K.copy(), C.copy()
        K[-1, -1] += kf
        C[-1, -1] += cf
        A = K[None] - (wh**2)[:, None, None] * np.diag(mass)[None] + 1j * wh[:, None, None] * C[None]
        b = np.zeros((S.size, segments), complex)
        b[:, -1] = (kf + 1j * wh * cf) * S
        b[0, -1] = kf * S[0] - n * ext
        Q = np.linalg.solve(A, b[..., None])[..., 0]
    q = np.fft.irfft(Q, n, axis=0)
    dq = np.fft.irfft(1j * h[:, None] * Q, n, axis=0)
    s, s1, s2 = vals[0], vals[1], vals[2]
    if model.rigid:  # what the cam must push: the follower's inertia, the last segment, the damper, the preload
        u, du = (q[:, -2], dq[:, -2]) if segments > 1 else (0.0, 0.0)
        c = float(model.damping)
        fi = mass[-1] * omega**2 * s2 + K[-1, -1] * (s - u) + (C[-1, -1] - c) * omega * (s1 - du) + c * omega * s1 + ext
    else:
        fi = np.asarray(train_force(model, omega, s, s1, q[:, -1], dq[:, -1]))
    return fi, q, dq


def chain_min_force(
    motion: Motion, model: FollowerModel, spring_mass: float, omegas: ArrayLike, *, n: int = FFT_GRID, **kw: Any
) -> np.ndarray:
    """Least steady-state interface force per speed (contact assumed, as for the jump speed)."""
    spec = _spectrum(motion, model, n)
    return np.array(
        [
            np.min(chain_steady_force(motion, model, spring_mass, float(w), n=n, _spec=spec, **kw)[0])
            for w in np.atleast_1d(omegas)
        ]
    )


def chain_jump_speed(
    motion: Motion,
    model: FollowerModel,
    spring_mass: float,
    *,
    w_max: float,
    grid: int = 400,
    tol_rpm: float = 0.1,
    **kw: Any,
) -> float:
    """Least cam speed (rad/s) at which the chain's steady-state least interface force reaches 0 (inf if none
    up to ``w_max``): a scan over ``grid`` speeds, then the first sign change refined by interpolation (the force
    is the steady state's with the contact held: signed and smooth through the jump)."""
    least = lambda ws: chain_min_force(motion, model, spring_mass, ws, **kw)  # noqa: E731
    return first_zero_speed(least, w_max, grid=grid, width_rpm=tol_rpm, points=1, where="surge model", signed=True)


def _field(t, y, args):
    motion, model, mass, K, C, ext, omega = args
    n = mass.shape[0]
    q, v = y[:n], y[n:]
    s, s1, _, _ = motion(omega * t) * model.scale
    fi = contact_force(model, omega, s, s1, q[-1], v[-1] / omega)
    force = -(K @ q) - (C @ v)
    force = force.at[-1].add(fi - ext)
    return jnp.concatenate([v, force / mass])


def chain_revolution(
    motion: Motion,
    model: FollowerModel,
    spring_mass: float,
    omega: float,
    q0: jax.Array,
    v0: jax.Array,
    theta: jax.Array,
    *,
    segments: int = DEFAULT_SEGMENTS,
    surge_damping: float = DEFAULT_SURGE_DAMPING,
    rtol: float = 1e-10,
    atol: float = 1e-13,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """diffrax: one revolution of a compliant follower with the chain, from nodes q0 and velocities v0 (SI, per
    second) at theta = 0; returns the nodes (len(theta), N), the interface force on ``theta`` (rad) and the
    state at 2 pi. Contact is unilateral: the follower may leave the cam."""
    import diffrax  # a reference model's: loaded where it runs, not by every command that imports the surge model

    if model.rigid:
        raise InputError("dynamics.train_stiffness", "the time-domain chain needs a compliant follower train")
    mass, K, C = _matrices(model, spring_mass, segments, surge_damping)
    kernel = motion.jit_form()  # the solve compiles once per follower kind, not once per segment list
    args = (
        kernel,
        model,
        jnp.asarray(mass),
        jnp.asarray(K),
        jnp.asarray(C),
        float(model.preload) + float(model.external),
        float(omega),
    )
    breaks = np.asarray(kernel.jump_angles()) / omega  # +inf past a program's breaks: the controller skips those
    period = TWO_PI / omega
    ts = jnp.asarray(np.asarray(theta) / omega)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_field),
        diffrax.Tsit5(),
        t0=0.0,
        t1=period,
        dt0=None,
        y0=jnp.concatenate([jnp.asarray(q0), jnp.asarray(v0)]),
        args=args,
        saveat=diffrax.SaveAt(ts=ts, t1=True),
        stepsize_controller=diffrax.ClipStepSizeController(
            diffrax.PIDController(rtol=rtol, atol=atol), jump_ts=jnp.asarray(np.sort(breaks))
        ),
        max_steps=400_000,
        throw=False,
    )
    if sol.result != diffrax.RESULTS.successful:
        raise NumericalError(
            f"surge model at {omega / RPM:.1f} rpm", "the chain integration failed (solver out of steps or NaN)"
        )
    ys = np.asarray(sol.ys)
    nn = segments
    q, v = ys[:-1, :nn], ys[:-1, nn:]
    vals = np.asarray(evaluate(motion, jnp.asarray(theta))) * model.scale
    fi = np.asarray(contact_force(model, omega, vals[0], vals[1], q[:, -1], v[:, -1] / omega))
    return q, fi, ys[-1]


SPRING_MODELS = ("none", "lumped", "surge")  # how the spring's own mass enters the dynamics


@dataclass(frozen=True)
class SpringInDynamics:
    """How the return spring's own mass enters the follower dynamics (``[spring] model``).

    ``"none"``: a massless spring (no ``[spring]`` table, so no part whose mass is known, or no spring of the
    case's rate and preload can be built within it: ``note`` says which). ``"lumped"``: a third of its mass moves
    with the follower (:func:`camdyn.model.follower.with_spring_mass`). ``"surge"``: the spring as a chain of
    masses (this module); the time-domain response keeps the lumped third, the jump speed is the chain's."""

    model: str
    mass_kg: float  # the whole spring, end coils included (0 for "none")
    lever_arm_mm: float | None  # an oscillating arm's spring acts here; None: translating
    bare: FollowerModel  # the follower without the spring's mass
    note: str | None = None
    valve_ratio: float | None = None  # a valve spring's: it acts at the valve, through the rocker's (nominal) ratio
    travel_to_solid_mm: float | None = None  # the designed part's, from its installed length to solid

    @property
    def generalized_mass(self) -> float:
        """The spring's mass in the follower's coordinate: kg, or kg*m^2 for an arm (m_s r^2); a valve spring's
        through the rocker (m_s ratio^2)."""
        r = 1.0 if self.lever_arm_mm is None else (self.lever_arm_mm * 1e-3) ** 2
        return self.mass_kg * r * (1.0 if self.valve_ratio is None else self.valve_ratio**2)

    def follower(self, bare: FollowerModel | None = None) -> FollowerModel:
        """The follower model the dynamics integrate: ``bare`` (default the case's) with the lumped third of the
        spring's mass, for both spring models ("none": as it is)."""
        bare = self.bare if bare is None else bare
        if self.model == "none":
            return bare
        at_valve = 1.0 if self.valve_ratio is None else self.valve_ratio**2
        return with_spring_mass(bare, self.mass_kg * at_valve, lever_arm_mm=self.lever_arm_mm)

    def jump_speed(self, motion: Motion, bare: FollowerModel | None = None, *, w_max: float) -> float:
        """The dynamic jump speed (rad/s; inf if none up to ``w_max``) of the follower ``bare`` (default the
        case's) with this spring: the lumped model's (:func:`camdyn.model.dynamics.dynamic_jump_speed`), or
        the chain's for "surge" (:func:`chain_jump_speed`)."""
        bare = self.bare if bare is None else bare
        if self.model == "surge":
            return chain_jump_speed(motion, bare, self.generalized_mass, w_max=w_max, tol_rpm=0.01)
        return dynamic_jump_speed(motion, self.follower(bare), w_max=w_max)

    def with_mass(self, mass_kg: float, model: str | None = None) -> SpringInDynamics:
        """The same follower with another spring (kg), and spring model if given (its travel to solid unknown)."""
        model = self.model if model is None else model
        return replace(self, mass_kg=float(mass_kg), model=model, note=None, travel_to_solid_mm=None)

    def json(self) -> dict:
        return {"spring_model": self.model, "spring_mass_kg": self.mass_kg if self.model != "none" else None}
