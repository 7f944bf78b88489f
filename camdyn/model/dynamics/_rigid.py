"""The rigid follower, event-driven: contact until the kinematic force falls to zero, flight under spring and
damper (diffrax, with a landing event) until it meets the cam, impact ``x'+ = w s' - e (x'- - w s')``."""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from ..._core.errors import NumericalError
from ..._core.jit import cached_jit
from ..._core.units import THETA_GRID, TWO_PI
from ..follower import FollowerModel
from ..motion import Motion, evaluate
from ._compliant import vector_field
from ._kinematic import kinematic_force_jit, store_kinematic_force, velocity_steps
from ._result import Response, Separation, residual_vibration
from ._root import itp_zero
from ._solver import ATOL, MAX_STEPS, RTOL

_GAP_EPS = 1e-9  # motion units; a landing is detected this far below contact, so a flight starts above it
_BREAK_EPS = 1e-10  # rad: just past a segment boundary, on its far side
_APEX_SAMPLES = 65  # angles spread over a flight for its largest gap, beside the grid's


def _flight_event(t, y, args, **kwargs):
    motion = args[0]
    return y[0] - motion(t)[0] + _GAP_EPS


@cached_jit
def _flight(motion, model, omega, theta0, dv, t_cap, n: int):
    """Free flight from the cam at ``theta0`` (rad), leaving it ``dv`` (motion units per rad) faster than the cam,
    until the follower lands on the cam (an event) or 4 pi later, and the flight on the grid of ``n`` angles a
    revolution: the end ``t1`` (the landing, else the solve's end capped at ``t_cap``), the state and the cam's
    (s, s') there, whether it landed, and the state at the ``2 n`` grid angles from the first at or after ``theta0``,
    clipped into [theta0, t1], and the largest gap over the cam at ``_APEX_SAMPLES`` angles spread over the
    flight and its angle (a flight shorter than the grid's step has no grid angle in it) (one stored program: the
    flight's start on the cam, its solve and its samples)."""
    import diffrax  # diffrax loads where a program is traced, not where a stored one runs
    import optimistix as optx

    s0 = motion(theta0)
    y0 = jnp.stack([s0[0], s0[1] + dv])
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(vector_field),
        diffrax.Tsit5(),
        t0=theta0,
        t1=theta0 + 2 * TWO_PI,
        dt0=None,
        y0=y0,
        args=(motion, model, omega, False),
        saveat=diffrax.SaveAt(t1=True, dense=True),
        stepsize_controller=diffrax.PIDController(rtol=RTOL, atol=ATOL),
        event=diffrax.Event(_flight_event, root_finder=optx.Newton(1e-12, 1e-12), direction=False),
        max_steps=MAX_STEPS,
        throw=False,
    )
    assert sol.ts is not None and sol.ys is not None  # saved at the end
    landed = sol.result == diffrax.RESULTS.event_occurred
    t1 = jnp.where(landed, sol.ts[-1], jnp.minimum(sol.ts[-1], t_cap))
    h = TWO_PI / n
    tt = jnp.clip((jnp.ceil(theta0 / h) + jnp.arange(2 * n)) * h, theta0, t1)
    ta = theta0 + (t1 - theta0) * jnp.linspace(0.0, 1.0, _APEX_SAMPLES)
    gaps = jax.vmap(sol.evaluate)(ta)[:, 0] - motion(ta)[0]
    i = jnp.argmax(gaps)
    return t1, sol.ys[-1], motion(t1)[:2], landed, tt, jax.vmap(sol.evaluate)(tt), gaps[i], ta[i]


_LIFT_OFF_WIDTH = 2e-13  # rad: the lift-off's bracket (its midpoint within 1e-13 rad of the zero)


def _lift_off(fk, t_a: float, h: float, breaks_rad: np.ndarray) -> float:
    """The lift-off angle (rad) in the grid step [t_a, t_a + h] where the kinematic force ``fk`` falls to zero.

    Where the force is continuous, its zero (:func:`itp_zero`, to 1e-13 rad). Where the step holds a segment
    boundary at which the force jumps from positive to non-positive (an acceleration jump), the follower leaves
    exactly there: the boundary, just past it. The grid's own sign change may sit on either side of a boundary on
    the grid, so the step is widened by a step each way before giving up.
    """
    where = f"lift-off near {math.degrees(t_a) % 360:.2f} deg"

    def zero(lo: float, hi: float, f_lo: float, f_hi: float) -> float:
        return itp_zero(
            fk,
            lo,
            hi,
            f_lo,
            f_hi,
            _LIFT_OFF_WIDTH,
            lambda t: NumericalError(where, "the kinematic force is not finite"),
        )

    a, b = t_a, t_a + h
    f_a, f_b = fk(a), fk(b)
    if f_a > 0.0 >= f_b:
        return zero(a, b, f_a, f_b)
    for brk in breaks_rad:  # a jump at a segment boundary in or next to this step
        t_b = brk + TWO_PI * math.floor((t_a - brk) / TWO_PI + 0.5)
        if a - h - 1e-12 <= t_b <= b + h + 1e-12 and fk(t_b - _BREAK_EPS) > 0.0 >= fk(t_b + _BREAK_EPS):
            return t_b + _BREAK_EPS
    ts = np.linspace(a - h, b + h, 33)
    fs = [fk(t) for t in ts]
    for k in range(32):
        if fs[k] > 0.0 >= fs[k + 1]:
            return zero(float(ts[k]), float(ts[k + 1]), fs[k], fs[k + 1])
    raise NumericalError(where, "no sign change of the kinematic force found in the step the grid flagged")


@dataclass
class _Flight:
    """What a march from one lift-off found: where the bouncing ended, how high, how hard, how often."""

    end: float  # rad, unwrapped
    max_gap: float = 0.0
    max_gap_at: float = math.nan
    impact: float | None = None  # relative speed at the first touchdown, SI
    impact_at: float = math.nan
    bounces: int = 0
    settled: bool = True


def _march(motion, model, omega, fk, t_lo, out, vals, n, max_bounces, dv0: float = 0.0) -> _Flight:
    """Flights from lift-off ``t_lo`` (rad), the first leaving the cam ``dv0`` faster than it (motion units per
    rad: a step in the cam's velocity), until the follower is back in contact for good, writing the flying grid
    points into ``out = (x, p, force)``. Bounces end when the relative speed falls below what the landing
    tolerance itself adds; the rest of the geometric bounce sequence then adds its accumulation time."""
    x, p, force = out
    h = TWO_PI / n
    w_sc = omega * model.scale
    e = float(model.restitution)
    fl = _Flight(end=t_lo)
    t0, dv = t_lo, dv0  # each flight leaves the cam, dv faster than it
    w, t_cap = np.asarray(omega, dtype=float), np.asarray(t_lo + TWO_PI - h)
    for _ in range(max_bounces + 2):
        flight = _flight(motion, model, w, np.asarray(t0), np.asarray(dv), t_cap, n)
        t1, y1, s1, landed, tt, yy, apex, apex_at = (np.asarray(a) for a in flight)
        if apex > fl.max_gap:  # between the grid's angles (all of a flight shorter than their step)
            fl.max_gap, fl.max_gap_at = float(apex), float(apex_at)
        t1, landed = float(t1), bool(landed)
        k0, k1 = math.ceil(t0 / h), math.floor(t1 / h)
        if k1 >= k0:  # the flight on the grid: the output arrays and the largest gap
            count = k1 - k0 + 1
            yy = yy[:count]
            ii = np.arange(k0, k1 + 1) % n
            x[ii], p[ii], force[ii] = yy[:, 0], yy[:, 1], 0.0
            gaps = yy[:, 0] - vals[0][ii]
            if gaps.max() > fl.max_gap:
                fl.max_gap, fl.max_gap_at = float(gaps.max()), float(tt[int(np.argmax(gaps))])
        if not landed or t1 - t_lo > TWO_PI - h:  # not back on the cam within a revolution of lift-off
            fl.end, fl.settled = t1, False
            return fl
        rel = y1[1] - s1[1]  # per rad, negative: closing
        if fl.impact is None:
            fl.impact, fl.impact_at = abs(rel) * w_sc, t1
        t0 = t1
        # A landing is detected _GAP_EPS below the cam, so every relaunch gains the speed of that fall:
        # bounces slower than it are numerical, not physical (the Zeno sequence has accumulated).
        a_rel = abs(fk(t1)) / (float(model.mass) * omega**2 * model.scale)  # relative accel, unit/rad^2
        v_floor = 10.0 * math.sqrt(2.0 * a_rel * _GAP_EPS)
        if e > 0.0 and abs(rel) > v_floor:
            fl.bounces += 1
            dv = -e * rel
            continue
        if fk(t1) <= 0.0:  # the cam is still pulling away: another flight right away
            fl.bounces += 1
            dv = 0.0
            continue
        # the bounces left below the floor form a geometric sequence: flight times 2 e^k v / a, summed
        fl.end = t1 + (2.0 * e * abs(rel) / (a_rel * (1.0 - e)) if 0.0 < e < 1.0 and a_rel > 0.0 else 0.0)
        return fl
    fl.end, fl.settled = t0, False  # still bouncing after max_bounces
    return fl


def store_flight(motion: Motion, model: FollowerModel, n: int = THETA_GRID) -> None:
    """Compile and store the programs of a rigid follower that leaves its cam (the flight on ``n`` angles, the
    kinematic force at one angle) where either is missing, without loading a stored one: a case whose follower
    stays on the cam then stores them for a later one whose follower leaves it (about 2 s of compiles on a CPU).
    Nothing where the program cache is off."""
    w, t = np.asarray(1.0), np.asarray(0.0)
    _flight.store(motion, model, w, t, t, t, n)  # pyright: ignore[reportFunctionMemberAccess]
    store_kinematic_force(motion, model)


def rigid_response(
    motion: Motion, model: FollowerModel, omega: float, n: int = THETA_GRID, max_bounces: int = 200
) -> Response:
    """Event-driven steady state of the rigid follower at cam speed omega (rad/s).

    In contact the follower has no state of its own, so the steady state is reached at the first touchdown:
    start in contact at the angle of the largest kinematic force and march one revolution through lift-offs
    (zeros of the kinematic force, or jumps through zero at segment boundaries), flights (diffrax, landing
    event) and impacts. A follower that does not settle back on the cam (it keeps bouncing, e.g. with
    restitution 1, or stays off it for a revolution) is a result, not an error: its separation says
    ``settled=False`` and the rest of the revolution counts as flight.
    """
    theta = np.arange(n) * (TWO_PI / n)
    theta_deg = np.degrees(theta)
    # numpy arguments: jnp.asarray outside a compiled program compiles one of its own
    vals = np.asarray(evaluate(motion, theta))
    kin = np.asarray(kinematic_force_jit(motion, model, np.asarray(omega, dtype=float), theta))
    steps = velocity_steps(motion, float(model.restitution))
    if kin.min() > 0.0 and not steps:
        return Response(
            "rigid", float(omega), theta_deg, vals[0], vals[0].copy(), vals[1].copy(), kin, kin, (), 0.0, 0.0
        )

    w = np.asarray(omega, dtype=float)

    def fk(t: float) -> float:
        return float(kinematic_force_jit(motion, model, w, np.asarray(t, dtype=float)))

    x, p, force = vals[0].copy(), vals[1].copy(), kin.copy()
    i_start = int(np.argmax(kin))
    theta_start = theta[i_start]
    # lift-offs: downward zero crossings of the kinematic force, in [theta_start, theta_start + 2 pi)
    ks = kin[(np.arange(n) + i_start) % n]
    crossings = [j for j in range(1, n) if ks[j - 1] > 0.0 >= ks[j]]
    breaks = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
    # where the force falls through zero (the grid's step before it), and where the cam's velocity steps, in turn
    unwrap = lambda t: theta_start + (t - theta_start) % TWO_PI  # noqa: E731
    starts = sorted(
        [(theta_start + (j - 1) * TWO_PI / n, None) for j in crossings]
        + [(unwrap(t) + _BREAK_EPS, dv) for t, dv in steps],
        key=lambda start: start[0],
    )
    seps: list[Separation] = []
    t_end_prev = theta_start
    for t_a, dv0 in starts:
        if t_a < t_end_prev:
            continue  # this zero lies inside the previous flight
        t_lo = _lift_off(fk, t_a, TWO_PI / n, breaks) if dv0 is None else t_a
        fl = _march(motion, model, omega, fk, t_lo, (x, p, force), vals, n, max_bounces, dv0 or 0.0)
        on_grid = (t_lo - _BREAK_EPS) * n / TWO_PI
        if dv0 is not None and abs(on_grid - round(on_grid)) < 1e-6:  # a step on a grid angle: its flight's first
            force[round(on_grid) % n] = 0.0
        deg = lambda t: math.degrees(t) % 360.0  # noqa: E731
        seps.append(
            Separation(
                deg(t_lo),
                deg(fl.end),
                fl.max_gap,
                float(fl.impact or 0.0),
                fl.bounces,
                deg(fl.max_gap_at),
                deg(fl.impact_at),
                fl.settled,
            )
        )
        t_end_prev = fl.end
        if not fl.settled:
            break
    # a grid point exactly on a boundary where the force jumps through zero takes the far side's (negative)
    # kinematic value; the follower leaves there: a rigid follower's contact force is never below zero
    force = np.maximum(force, 0.0)
    resid, resid_deg = residual_vibration(motion, theta_deg, x - vals[0])
    return Response("rigid", float(omega), theta_deg, vals[0], x, p, force, kin, tuple(seps), resid, 0.0, (), resid_deg)
