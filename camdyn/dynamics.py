"""Single-DOF follower dynamics on diffrax: interface force, separation, flight, impact, jump speed.

The follower (mass m, return spring k with preload F0, damper c, constant external force F_ext pushing it onto
the cam) is driven by a cam turning at constant speed w, theta = w t. Two time-domain models:

* compliant (a follower train of stiffness k_f and damping c_f between cam and mass):
  ``m x'' = Fi - (k x + F0) - c x' - F_ext`` with ``Fi = max(0, k_f (s - x) + c_f (w s' - x'))`` while s > x;
* rigid: contact (x = s) until the kinematic force falls to zero; flight under spring and damper until the
  follower meets the cam again; impact ``x'+ = w s' - e (x'- - w s')``; contact again when the bounces die.

Both are integrated in the cam angle (state: x and dx/dtheta, in the motion's unit: mm or rad), so segment
boundaries are fixed angles that the step-size controller is told about (``jump_ts``). Everything is in SI
inside; ``scale`` converts the motion's unit to m (1e-3) or keeps rad (1.0), and the same equations then
hold for the rotational equivalent of an oscillating follower (inertia, torsion spring, torques).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from scipy.optimize import brentq, minimize_scalar

from .errors import NumericalError
from .programs import cached_jit
from .motion import TWO_PI, Motion, evaluate

RPM = TWO_PI / 60.0  # rad/s per rpm


class FollowerModel(eqx.Module):
    """Lumped follower parameters in SI (generalized: N and m, or N*m and rad for an oscillating arm).

    Every field is an array leaf, so a batch of models (e.g. a sweep over spring rates) is one ``vmap``.
    ``train_stiffness = inf`` marks a rigid follower.
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

    @property
    def rigid(self) -> bool:
        return bool(np.all(np.isinf(np.asarray(self.train_stiffness))))


# ------------------------------------------------------------------------------------- kinematics
def kinematic_force(motion: Motion, model: FollowerModel, omega, theta):
    """Interface force of a follower that never leaves the cam (CCM paper eq. 7), N.

    ``Fi = m w^2 s'' + c w s' + k s + F0 + F_ext`` with s in SI (scale applied), w in rad/s.
    """
    s, s1, s2, _ = motion(theta) * model.scale
    return model.mass * omega**2 * s2 + model.damping * omega * s1 + model.stiffness * s + model.preload + model.external


_kinematic_force_jit = cached_jit(kinematic_force)


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
    bounded scalar minimization of the same closed form. ``(inf, nan)`` when no speed makes it jump.
    """
    m, c, k = (float(model.mass), float(model.damping), float(model.stiffness))
    f0 = float(model.preload) + float(model.external)

    def w_at(theta):
        s, s1, s2, _ = np.asarray(evaluate(motion, jnp.asarray(theta, dtype=float))) * model.scale
        return _quadratic_jump_speed(m * s2, c * s1, k * s + f0)

    theta = np.arange(n) * (TWO_PI / n)
    w = w_at(theta)
    i = int(np.argmin(w))
    if not np.isfinite(w[i]):
        return math.inf, math.nan
    h = TWO_PI / n
    cap = 1e6 * w[i]  # a finite stand-in for "no jump here": Brent's parabola steps turn inf into NaN

    def objective(t):
        return min(float(w_at(np.array([t]))[0]), cap)

    res = minimize_scalar(objective, bounds=(theta[i] - h, theta[i] + h), method="bounded", options={"xatol": 1e-10})
    if res.fun < w[i]:
        return float(res.fun), math.degrees(res.x) % 360.0
    return float(w[i]), math.degrees(theta[i])


# --------------------------------------------------------------------------------- time domain
_RTOL, _ATOL = 1e-9, 1e-10


def _vector_field(theta, y, args):
    """d/dtheta of (x, p = dx/dtheta) for the compliant model (``contact`` True) or free flight."""
    motion, model, omega, contact = args
    x, p = y
    s, s1, _, _ = motion(theta)
    sc = model.scale
    fi = jnp.where(
        contact & (s > x),
        jnp.maximum(0.0, model.train_stiffness * sc * (s - x) + model.train_damping * omega * sc * (s1 - p)),
        0.0,
    )
    f_net = fi - (model.stiffness * sc * x + model.preload) - model.damping * omega * sc * p - model.external
    return jnp.stack([p, f_net / (model.mass * omega**2 * sc)])


def _controller(motion: Motion, theta0, revs: float):
    breaks = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
    jumps = (breaks[None, :] + TWO_PI * np.arange(-1, math.ceil(revs) + 2)[:, None]).ravel()
    jumps = jnp.asarray(np.sort(jumps)) + 0.0 * theta0
    pid = diffrax.PIDController(rtol=_RTOL, atol=_ATOL)
    if jumps.size == 0:
        return pid
    return diffrax.ClipStepSizeController(pid, jump_ts=jumps)


def _contact_force(motion, model, omega, theta, x, p):
    s, s1, _, _ = motion(theta)
    sc = model.scale
    return jnp.where(s > x, jnp.maximum(0.0, model.train_stiffness * sc * (s - x) + model.train_damping * omega * sc * (s1 - p)), 0.0)


_contact_force_jit = cached_jit(_contact_force)
_MAX_STEPS = 200_000


def _quasi_static_start(motion, model, omega):
    s, s1, _, _ = motion(jnp.asarray(0.0))
    fi = kinematic_force(motion, model, omega, jnp.asarray(0.0))
    return jnp.stack([s - fi / (model.train_stiffness * model.scale), s1])


_NEWTON_ITERS = 8
_quasi_static_jit = cached_jit(_quasi_static_start)


def _variational_field(theta, y, args):
    """State and monodromy sensitivities: d/dtheta (z, M) = (f(z), J_f(z) M), J_f by JAX autodiff."""
    z, m = y[:2], y[2:].reshape(2, 2)
    f = lambda z_: _vector_field(theta, z_, args)  # noqa: E731
    return jnp.concatenate([f(z), (jax.jacfwd(f)(z) @ m).ravel()])


def _rev_with_sensitivity(motion, model, omega, z0, theta):
    """One revolution from z0: the state on ``theta`` and at 2 pi, and d z(2 pi) / d z0."""
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_variational_field),
        diffrax.Tsit5(),
        t0=0.0,
        t1=TWO_PI,
        dt0=None,
        y0=jnp.concatenate([z0, jnp.eye(2).ravel()]),
        args=(motion, model, omega, True),
        saveat=diffrax.SaveAt(ts=theta, t1=True),
        stepsize_controller=_controller(motion, 0.0, 1),
        max_steps=_MAX_STEPS,
        throw=False,
    )
    ys = sol.ys
    return ys[:-1, :2], ys[-1, :2], ys[-1, 2:].reshape(2, 2), sol.result == diffrax.RESULTS.successful


_rev_jit = cached_jit(_rev_with_sensitivity)
_PLAIN_REVS = 60  # after Newton stalls (non-smooth bouncing): revolutions of plain iteration at most


def periodic_orbit(motion: Motion, model: FollowerModel, omega: float, theta):
    """Periodic steady state of the compliant model by shooting.

    Newton on ``Phi(z0) - z0 = 0``, where the one-revolution flow Phi and its Jacobian (the monodromy matrix)
    come from one diffrax solve of the state with its variational equations (the vector field's Jacobian by
    JAX autodiff). While the follower stays in contact the flow is affine and Newton converges in one step.
    Where a separation makes the flow non-smooth and a Newton step does not reduce the residual, the
    iteration falls back to plain revolutions (the transient dies out revolution by revolution).
    Returns the trajectory on ``theta`` (n, 2) of the best iterate and its residual |Phi(z0) - z0|.
    """
    # the Newton bookkeeping is 2x2 numpy: eager jax ops would each compile a tiny program on first use
    z = np.asarray(_quasi_static_jit(motion, model, jnp.asarray(omega, dtype=float)))
    tol = 1e-10 * (1.0 + float(np.max(np.abs(z))))
    w = jnp.asarray(omega, dtype=float)
    best_traj, best_r, r_prev = None, math.inf, math.inf
    for i in range(_NEWTON_ITERS + _PLAIN_REVS):
        traj, phi, mono, ok = _rev_jit(motion, model, w, jnp.asarray(z), theta)
        phi, mono = np.asarray(phi), np.asarray(mono)
        if not bool(ok) or not np.all(np.isfinite(phi)):
            raise NumericalError(f"dynamics at {omega / RPM:.1f} rpm", "the compliant-model integration failed (solver out of steps or NaN)")
        r = float(np.linalg.norm(phi - z))
        if r < best_r:
            best_traj, best_r = traj, r
        if best_r <= tol:
            break
        newton = i < _NEWTON_ITERS and r <= r_prev
        z = z - np.linalg.solve(mono - np.eye(2), phi - z) if newton else phi
        r_prev = r
    return best_traj, best_r


def _steady_jax(motion, model, omega, theta):
    """Jittable periodic orbit for batched use (vmap over speeds or models): Newton then plain revolutions."""

    def body(carry):
        i, z, r_prev, best_traj, best_r = carry
        traj, phi, mono, _ = _rev_with_sensitivity(motion, model, omega, z, theta)
        r = phi - z
        rn = jnp.where(jnp.all(jnp.isfinite(traj)), jnp.linalg.norm(r), jnp.nan)
        better = rn < best_r
        best_traj = jnp.where(better, traj, best_traj)
        best_r = jnp.where(better, rn, best_r)
        z_newton = z - jnp.linalg.solve(mono - jnp.eye(2), r)
        use_newton = (i < _NEWTON_ITERS) & (rn <= r_prev) & jnp.all(jnp.isfinite(z_newton))
        return i + 1, jnp.where(use_newton, z_newton, phi), rn, best_traj, best_r

    def cond(carry):
        i, z, _, _, best_r = carry
        return (i < _NEWTON_ITERS + _PLAIN_REVS) & (best_r > 1e-10 * (1.0 + jnp.max(jnp.abs(z))))

    z0 = _quasi_static_start(motion, model, omega)
    init = (0, z0, jnp.inf, jnp.full((theta.shape[0], 2), jnp.nan), jnp.asarray(jnp.inf))
    _, _, _, traj, residual = jax.lax.while_loop(cond, body, init)
    return traj, residual


@eqx.filter_jit
def min_contact_force(motion, model, omega, n: int = 3600):
    """Least steady-state interface force of the compliant model by time-domain shooting (N; NaN on failure).

    Jittable and vmappable over speeds and models; the reference for :func:`linear_min_force`.
    """
    theta = jnp.arange(n) * (TWO_PI / n)
    traj, _ = _steady_jax(motion, model, omega, theta)
    return jnp.min(_contact_force(motion, model, omega, theta, traj[:, 0], traj[:, 1]))


# ------------------------------------------------------------------------------------ rigid model
_GAP_EPS = 1e-9  # motion units; a landing is detected this far below contact, so a flight starts above it


def _flight_event(t, y, args, **kwargs):
    motion = args[0]
    return y[0] - motion(t)[0] + _GAP_EPS


@eqx.filter_jit
def _flight(motion, model, omega, theta0, y0):
    """Free flight from theta0 until the follower lands on the cam (event) or 4 pi later."""
    return diffrax.diffeqsolve(
        diffrax.ODETerm(_vector_field),
        diffrax.Tsit5(),
        t0=theta0,
        t1=theta0 + 2 * TWO_PI,
        dt0=None,
        y0=y0,
        args=(motion, model, omega, False),
        saveat=diffrax.SaveAt(t1=True, dense=True),
        stepsize_controller=diffrax.PIDController(rtol=_RTOL, atol=_ATOL),
        event=diffrax.Event(_flight_event, root_finder=optx.Newton(1e-12, 1e-12), direction=False),
        max_steps=_MAX_STEPS,
        throw=False,
    )


@eqx.filter_jit
def _sample_dense(sol, ts):
    return jax.vmap(sol.evaluate)(ts)


# ------------------------------------------------------------------------------------- response
@dataclass(frozen=True)
class Separation:
    """One flight from lift-off to the touchdown that ends the bouncing."""

    start_deg: float
    end_deg: float
    max_gap: float  # motion units (mm or rad)
    impact_speed: float  # relative speed at the first touchdown, m/s (or rad/s)
    bounces: int = 0

    def json(self, unit: str) -> dict:
        gap_key = "max_gap_mm" if unit == "mm" else "max_gap_rad"
        speed_key = "impact_speed_m_s" if unit == "mm" else "impact_speed_rad_s"
        return {"start_deg": self.start_deg, "end_deg": self.end_deg, gap_key: self.max_gap, speed_key: self.impact_speed, "bounces": self.bounces}


@dataclass(frozen=True)
class Response:
    """Periodic steady-state response over one revolution at cam speed ``omega`` (rad/s)."""

    model: str  # "rigid" | "compliant"
    omega: float
    theta_deg: np.ndarray
    s: np.ndarray  # kinematic displacement, motion units
    x: np.ndarray  # follower displacement, motion units
    dx: np.ndarray  # dx/dtheta, motion units per rad
    force: np.ndarray  # interface force, N (or N*m)
    kinematic_force: np.ndarray
    separations: tuple[Separation, ...]
    residual_vibration: float  # largest |x - x_static| in the dwells (static equilibrium), motion units
    periodicity_error: float  # |Phi(y0) - y0| of the shooting, motion units
    warnings: tuple[str, ...] = field(default=())

    @property
    def min_force(self) -> float:
        return float(np.min(self.force))

    @property
    def min_force_deg(self) -> float:
        return float(self.theta_deg[int(np.argmin(self.force))])


def _dwell_mask(motion: Motion, theta_deg: np.ndarray) -> np.ndarray:
    segs = getattr(motion, "segments", ())
    mask = np.zeros(theta_deg.shape, bool)
    for seg in segs:
        if seg.law == "dwell":
            mask |= (theta_deg >= seg.start) & (theta_deg < seg.end)
    return mask


def _separations_from_mask(theta_deg, flying, gap, rel_speed, merge_deg) -> list[Separation]:
    """Flights from a boolean mask on a periodic grid; flights split by contact shorter than merge_deg merge."""
    n = len(theta_deg)
    if not flying.any():
        return []
    if flying.all():
        raise NumericalError("dynamics", "the follower never touches the cam in steady state")
    step = 360.0 / n
    shift = int(np.argmin(flying))  # start the scan in contact so no flight wraps the grid end
    idx = (np.arange(n) + shift) % n
    runs, start = [], None
    for j, i in enumerate(idx):
        if flying[i] and start is None:
            start = j
        if not flying[i] and start is not None:
            runs.append([start, j])
            start = None
    if start is not None:
        runs.append([start, n])
    merged = [runs[0] + [0]]
    for r in runs[1:]:
        if (r[0] - merged[-1][1]) * step < merge_deg:
            merged[-1][1] = r[1]
            merged[-1][2] += 1
        else:
            merged.append(r + [0])
    out = []
    for a, b, bounces in merged:
        sel = idx[a:b]
        first_touch = idx[min(b, n - 1)] if b < n else idx[0]
        out.append(
            Separation(
                start_deg=float(theta_deg[idx[a]]),
                end_deg=float(theta_deg[idx[b % n]]) if b < n else float(theta_deg[idx[0]]),
                max_gap=float(np.max(gap[sel])),
                impact_speed=float(abs(rel_speed[first_touch])),
                bounces=bounces,
            )
        )
    return out


def compliant_response(motion: Motion, model: FollowerModel, omega: float, n: int = 3600) -> Response:
    """Periodic steady state of the compliant follower at cam speed omega (rad/s)."""
    theta = jnp.arange(n) * (TWO_PI / n)
    traj, residual = periodic_orbit(motion, model, float(omega), theta)
    x, p = np.asarray(traj[:, 0]), np.asarray(traj[:, 1])
    fi = np.asarray(_contact_force_jit(motion, model, jnp.asarray(omega, dtype=float), theta, traj[:, 0], traj[:, 1]))
    theta_deg = np.degrees(np.asarray(theta))
    vals = np.asarray(evaluate(motion, theta))
    kin = np.asarray(_kinematic_force_jit(motion, model, jnp.asarray(omega, dtype=float), theta))
    flying = fi <= 0.0
    # contact-mode period, in cam degrees: bounces closer than this belong to one separation
    k_total = float(model.stiffness) + float(model.train_stiffness)
    merge_deg = math.degrees(omega * TWO_PI / math.sqrt(k_total / float(model.mass)))
    rel = omega * model.scale * (p - vals[1])
    seps = _separations_from_mask(theta_deg, flying, x - vals[0], rel, merge_deg)
    # static equilibrium in a dwell: k_f (s - x) = k x + F0 + F_ext
    kf, kk = float(model.train_stiffness) * model.scale, float(model.stiffness) * model.scale
    x_static = (kf * vals[0] - float(model.preload) - float(model.external)) / (kk + kf)
    dwell = _dwell_mask(motion, theta_deg)
    resid = float(np.max(np.abs(x - x_static)[dwell])) if dwell.any() else 0.0
    warnings = []
    tol = 1e-6 * max(1.0, float(np.max(np.abs(vals[0]))))
    if float(residual) > tol:
        warnings.append(f"no exactly periodic steady state at {omega / RPM:.1f} rpm (revolution-to-revolution mismatch {float(residual):.2g} {motion.unit}): the follower's bouncing is not periodic; results are for the best of {_NEWTON_ITERS} shooting iterations and {_PLAIN_REVS} revolutions")
    return Response("compliant", float(omega), theta_deg, vals[0], x, p, fi, kin, tuple(seps), resid, float(residual), tuple(warnings))


def rigid_response(motion: Motion, model: FollowerModel, omega: float, n: int = 3600, max_bounces: int = 200) -> Response:
    """Event-driven steady state of the rigid follower at cam speed omega (rad/s).

    In contact the follower has no state of its own, so the steady state is reached at the first touchdown:
    start in contact at the angle of the largest kinematic force and march one revolution through lift-offs
    (zeros of the kinematic force), flights (diffrax, landing event) and impacts.
    """
    theta = np.arange(n) * (TWO_PI / n)
    theta_deg = np.degrees(theta)
    vals = np.asarray(evaluate(motion, jnp.asarray(theta)))
    kin = np.asarray(_kinematic_force_jit(motion, model, jnp.asarray(omega, dtype=float), jnp.asarray(theta)))
    if kin.min() > 0.0:
        return Response("rigid", float(omega), theta_deg, vals[0], vals[0].copy(), vals[1].copy(), kin, kin, (), 0.0, 0.0)

    fk = lambda t: float(_kinematic_force_jit(motion, model, jnp.asarray(omega, dtype=float), jnp.asarray(t, dtype=float)))  # noqa: E731
    x, p, force = vals[0].copy(), vals[1].copy(), kin.copy()
    theta_start = theta[int(np.argmax(kin))]
    # lift-offs: downward zero crossings of the kinematic force, in [theta_start, theta_start + 2 pi)
    order = (np.arange(n) + int(np.argmax(kin))) % n
    ks = kin[order]
    crossings = [j for j in range(1, n) if ks[j - 1] > 0.0 >= ks[j]]
    seps: list[Separation] = []
    t_end_prev = theta_start
    w_sc = omega * model.scale
    for j in crossings:
        t_a = theta_start + (j - 1) * TWO_PI / n
        if t_a < t_end_prev:
            continue  # this zero lies inside the previous flight
        t_lo = brentq(fk, t_a, t_a + TWO_PI / n, xtol=1e-13)
        s_lo = np.asarray(evaluate(motion, jnp.asarray(t_lo)))
        y = jnp.asarray([s_lo[0], s_lo[1]])
        t0, bounces, max_gap, impact = t_lo, 0, 0.0, None
        while True:
            sol = _flight(motion, model, jnp.asarray(omega, dtype=float), jnp.asarray(t0, dtype=float), y)
            if sol.result != diffrax.RESULTS.event_occurred:
                raise NumericalError(f"dynamics at {omega / RPM:.1f} rpm, lift-off at {math.degrees(t_lo) % 360:.2f} deg", "the follower does not return to the cam within two revolutions")
            t1 = float(sol.ts[-1])
            # sample the flight on the grid for the output arrays and the largest gap
            k0, k1 = math.ceil(t0 / (TWO_PI / n)), math.floor(t1 / (TWO_PI / n))
            if k1 >= k0:
                count = k1 - k0 + 1
                tt = np.clip(np.arange(k0, k0 + 2 * n) * (TWO_PI / n), t0, t1)  # fixed shape: one compile
                yy = np.asarray(_sample_dense(sol, jnp.asarray(tt)))[:count]
                ii = np.arange(k0, k1 + 1) % n
                x[ii], p[ii], force[ii] = yy[:, 0], yy[:, 1], 0.0
                max_gap = max(max_gap, float(np.max(yy[:, 0] - vals[0][ii])))
            y1 = np.asarray(sol.ys[-1])
            s1 = np.asarray(evaluate(motion, jnp.asarray(t1)))
            rel = y1[1] - s1[1]  # per rad, negative: closing
            if impact is None:
                impact = abs(rel) * w_sc
            e = float(model.restitution)
            t0 = t1
            # A landing is detected _GAP_EPS below the cam, so every relaunch gains the speed of that fall:
            # bounces slower than it are numerical, not physical (the Zeno sequence has accumulated).
            a_rel = abs(fk(t1)) / (float(model.mass) * omega**2 * model.scale)  # relative accel, unit/rad^2
            v_floor = 10.0 * math.sqrt(2.0 * a_rel * _GAP_EPS)
            if e > 0.0 and abs(rel) > v_floor and bounces < max_bounces:
                bounces += 1
                y = jnp.asarray([s1[0], s1[1] - e * rel])
                continue
            if fk(t1) <= 0.0:  # the cam is still pulling away: another flight right away
                bounces += 1
                y = jnp.asarray([s1[0], s1[1]])
                continue
            break
        t_end_prev = t0
        seps.append(Separation(math.degrees(t_lo) % 360.0, math.degrees(t0) % 360.0, max_gap, float(impact), bounces))
    dwell = _dwell_mask(motion, theta_deg)
    resid = float(np.max(np.abs(x - vals[0])[dwell])) if dwell.any() else 0.0
    return Response("rigid", float(omega), theta_deg, vals[0], x, p, force, kin, tuple(seps), resid, 0.0)


def response(motion: Motion, model: FollowerModel, omega: float, n: int = 3600) -> Response:
    """Steady-state response with the model the parameters call for (rigid if train_stiffness is inf)."""
    return rigid_response(motion, model, omega, n) if model.rigid else compliant_response(motion, model, omega, n)


_FFT_N = 4096


def _steady_force_at(motion: Motion, model: FollowerModel, n: int):
    """``omega -> interface force`` on the grid ``theta_k = 2 pi k / n`` of the compliant model's periodic orbit
    while it stays on the cam (harmonic balance by FFT)."""
    theta = jnp.arange(n) * (TWO_PI / n)
    s, s1, _, _ = motion(theta) * model.scale
    spec = jnp.fft.rfft(s)
    k = jnp.arange(spec.shape[0])
    m, kk, c, kf, cf = model.mass, model.stiffness, model.damping, model.train_stiffness, model.train_damping

    def force(omega):
        wk = k * omega
        x_spec = spec * (kf + 1j * wk * cf) / (kk + kf - m * wk**2 + 1j * wk * (c + cf))
        x_spec = x_spec.at[0].set((kf * spec[0] - n * (model.preload + model.external)) / (kk + kf))
        x = jnp.fft.irfft(x_spec, n)
        x1 = jnp.fft.irfft(1j * k * x_spec, n)
        return kf * (s - x) + cf * omega * (s1 - x1)

    return force


@cached_jit
def linear_min_force(motion: Motion, model: FollowerModel, omegas, n: int = _FFT_N, weight=None):
    """Least interface force (N) of the compliant model's periodic orbit if it never separates, per speed.

    While the follower stays on the cam the model is linear and time-invariant with a periodic input, so its
    steady state is exact in the frequency domain (harmonic balance by FFT):
    ``X_k = (k_f + i k w c_f) S_k / (k + k_f - m (k w)^2 + i k w (c + c_f))``. The result is the true
    steady state for every speed whose least force is positive, which is all the jump speed needs. Vectorized
    over ``omegas`` (any shape). ``weight``: optional (n,) factor per angle theta_k = 2 pi k / n applied before
    the minimum (``1000 / lever_arm_mm`` turns an oscillating follower's torque into its contact force in N).
    """
    force = _steady_force_at(motion, model, n)

    def one(omega):
        f = force(omega)
        return jnp.min(f if weight is None else f * weight)

    omegas = jnp.asarray(omegas, dtype=float)
    return jax.lax.map(one, omegas.ravel(), batch_size=64).reshape(omegas.shape)


@eqx.filter_jit
def linear_contact_force(motion: Motion, model: FollowerModel, omegas, n: int = _FFT_N):
    """The whole interface force (N or N*m) of :func:`linear_min_force`'s steady state: shape (*omegas.shape, n).

    Angles ``theta_j = 2 pi j / n``. Exact wherever it stays positive; affine in the preload (raising F0 adds
    ``k_f / (k + k_f) * dF0`` at every angle and speed), which is what spring sizing (``sizing.py``) uses.
    """
    omegas = jnp.asarray(omegas, dtype=float)
    return jax.lax.map(_steady_force_at(motion, model, n), omegas.ravel(), batch_size=64).reshape(omegas.shape + (n,))


def dynamic_jump_speed(motion: Motion, model: FollowerModel, *, w_max: float, tol_rpm: float = 0.1, grid: int = 2000) -> float:
    """Least cam speed (rad/s) at which the steady-state least interface force reaches 0; inf if none up to w_max.

    Rigid followers: the kinematic jump speed (closed form). Compliant: below the jump speed the follower
    stays in contact, where the model is linear, so the scan over ``grid`` speeds in (0, w_max] and the
    bisection of the first sign change use the exact frequency-domain steady state (:func:`linear_min_force`);
    the diffrax time-domain model is its reference (tests, and ``check`` compares both at the case speed).
    """
    if model.rigid:
        return kinematic_jump_speed(motion, model)[0]
    speeds = np.linspace(w_max / grid, w_max, grid)
    fmin = np.asarray(linear_min_force(motion, model, speeds))
    if not np.all(np.isfinite(fmin)):
        bad = speeds[~np.isfinite(fmin)][0]
        raise NumericalError(f"jump-speed search at {bad / RPM:.1f} rpm", "the steady-state force is not finite")
    hit = np.nonzero(fmin <= 0.0)[0]
    if hit.size == 0:
        return math.inf
    i = int(hit[0])
    lo, hi = (speeds[i - 1] if i > 0 else 0.0), speeds[i]
    while (hi - lo) / RPM > tol_rpm / 10:
        ws = np.linspace(lo, hi, 18)[1:-1]
        f = np.asarray(linear_min_force(motion, model, ws))
        below = np.nonzero(f <= 0.0)[0]
        j = int(below[0]) if below.size else len(ws)
        lo, hi = (ws[j - 1] if j > 0 else lo), (ws[j] if j < len(ws) else hi)
    return float(0.5 * (lo + hi))
