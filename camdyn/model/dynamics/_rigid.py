"""The rigid follower, event-driven: contact until the kinematic force falls to zero, flight under spring and
damper (diffrax, with a landing event) until it meets the cam, impact ``x'+ = w s' - e (x'- - w s')``."""

from __future__ import annotations

import math

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from scipy.optimize import brentq

from ..._core.errors import NumericalError
from ..._core.units import RPM, THETA_GRID, TWO_PI
from ..follower import FollowerModel
from ..motion import Motion, evaluate
from ._compliant import _ATOL, _MAX_STEPS, _RTOL, _vector_field
from ._kinematic import kinematic_force_jit
from ._result import Response, Separation, _dwell_mask


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


def rigid_response(motion: Motion, model: FollowerModel, omega: float, n: int = THETA_GRID, max_bounces: int = 200) -> Response:
    """Event-driven steady state of the rigid follower at cam speed omega (rad/s).

    In contact the follower has no state of its own, so the steady state is reached at the first touchdown:
    start in contact at the angle of the largest kinematic force and march one revolution through lift-offs
    (zeros of the kinematic force), flights (diffrax, landing event) and impacts.
    """
    theta = np.arange(n) * (TWO_PI / n)
    theta_deg = np.degrees(theta)
    vals = np.asarray(evaluate(motion, jnp.asarray(theta)))
    kin = np.asarray(kinematic_force_jit(motion, model, jnp.asarray(omega, dtype=float), jnp.asarray(theta)))
    if kin.min() > 0.0:
        return Response("rigid", float(omega), theta_deg, vals[0], vals[0].copy(), vals[1].copy(), kin, kin, (), 0.0, 0.0)

    fk = lambda t: float(kinematic_force_jit(motion, model, jnp.asarray(omega, dtype=float), jnp.asarray(t, dtype=float)))  # noqa: E731
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
