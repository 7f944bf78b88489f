"""The valvetrain in the time domain: two masses, the train and its lash, the cam contact and the valve's seat,
event-driven on diffrax (float64), over one revolution at a constant cam speed.

Equations (SI, time derivatives; x_c the follower's lift at the cam, x_v the valve's lift, g(x_c) the cam's lift
at the valve through the rocker and r = dg/dx_c its ratio, constant or varying with lift)::

    m_c x_c'' = F_cam - r F_t - F_hold
    m_v x_v'' = F_t - (k x_v + F0 + c x_v') + F_seat

* F_t, the train: ``train_force`` (the compliant contact's formula) on the deflection ``g(x_c) - lash - x_v``, in
  compression only; a rigid train locks the two masses together once the lash closes (a plastic impact) and lets
  go where its force would pull. Locked, x_v'' = r x_c'' + r' x_c'^2 (r' = dr/dx_c: 0 for a constant ratio).
* The valve spring: ``k x_v + F0 + c x_v'``; with its coils as a chain of masses (``[spring] model = "surge"``,
  :class:`~camdyn.model.valvetrain.Coils`) the last segment's spring and damper on the valve, the inner lumps in
  the state after the four above, each between its neighbours (the head fixed).
* F_cam, the cam contact: compliant (``train_force`` on ``s - x_c``) or rigid (x_c = s while F_cam > 0, a flight
  when it falls to zero, a landing with the cam's restitution).
* F_seat, the seat at zero valve lift: rigid, with ``seat_restitution``. A seat is one to two orders stiffer than
  the train (a few 1e8 N/m against 1e7), so a compliant seat would set the integrator's step for no more
  information than the restitution gives: the rebound speed. The valve rests on it while the spring's force
  exceeds the train's.

Between events every active contact's state is smooth, so each stretch is one diffrax solve (Tsit5, tight
tolerances) with a terminating event for each contact that can open or close; the transitions (impacts, locks,
releases) are applied on the host. The state is integrated in the cam angle (x and dx/dtheta, m and m/rad).
The revolution starts on the base circle with the valve seated and at rest, so once the valve has seated and
the follower is back on the cam before the revolution ends, that revolution is the periodic steady state.
"""

from __future__ import annotations

import math
from typing import Any

import diffrax
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from jax.typing import ArrayLike

from ..._core.errors import NumericalError
from ..._core.jit import cached_jit, padded_length
from ..._core.units import M_PER_MM, RPM, THETA_GRID, TWO_PI
from ..motion import Motion
from ..valvetrain import ValvetrainModel, static_valve_lift
from ._cubic import hermite_top
from ._train import contact_force
from ._valveresponse import ValveEvent, ValvetrainResponse

_RTOL, _ATOL = 1e-10, 1e-14  # the state is in m and m/rad: lifts of 1e-2 m
GAP_EPS = 1e-12  # m: a landing is detected this far below contact
_MAX_STEPS = 1_000_000
_MAX_EVENTS = 2000  # per revolution: bounces beyond it leave the valve or the follower not settled
_REVS = 3  # revolutions at most to reach the periodic steady state
_JUMP_ROWS = 32  # the stretches' jump times are padded to 32, 128, 512, ... (+inf)
NO_EVENT = 1e300  # N: the float search's least force at a speed where the valve does not lift (it wants finite)
CAM, TRAIN, SEAT = 0, 1, 2  # the contacts, in the mode vector and the event list


def _state(theta, y, args):
    """The positions and speeds the contacts see, with the locked ones taken from what locks them."""
    motion, vt, omega, modes, _ = args
    cam_locked, train_locked, seat_locked = modes[CAM], modes[TRAIN], modes[SEAT]
    s, s1, s2, _ = motion(theta) * M_PER_MM
    xc = jnp.where(cam_locked, s, y[0])
    pc = jnp.where(cam_locked, s1, y[1])
    g, r, _ = vt.lever(xc)
    xv = jnp.where(train_locked, g - vt.lash, jnp.where(seat_locked, 0.0, y[2]))
    pv = jnp.where(train_locked, r * pc, jnp.where(seat_locked, 0.0, y[3]))
    return s, s1, s2, xc, pc, xv, pv


def _dynamics(theta, y, args):
    """(accelerations per rad^2 of the follower and the valve, F_cam, F_t, the seat's reaction) in this mode."""
    motion, vt, omega, modes, _ = args
    cam_locked, train_locked, seat_locked = modes[CAM], modes[TRAIN], modes[SEAT]
    s, s1, s2, xc, pc, xv, pv = _state(theta, y, args)
    w2 = omega**2
    m_c, m_v = vt.cam_side_mass, vt.valve_mass
    g, r, r1 = vt.lever(xc)
    spring = _spring_force(vt, omega, xv, pv, y)
    # the compliant contacts (0 for a rigid one, whose force is its constraint's): the cam's, and the train's on
    # its deflection g(x_c) - lash - x_v
    f_cam_c = jnp.where(jnp.isinf(vt.cam.train_stiffness), 0.0, contact_force(vt.cam, omega, s, s1, xc, pc))
    f_t_c = jnp.where(
        jnp.isinf(vt.train.train_stiffness), 0.0, contact_force(vt.train, omega, g - vt.lash, r * pc, xv, pv)
    )
    # the train locked: one body at the follower (mass m_c + m_v r^2), driven by the cam or flying on its contact;
    # a varying ratio adds the valve's r' x_c'^2
    turn = m_v * r * r1 * pc**2
    a_body = (f_cam_c - r * spring - vt.tappet_force - turn * w2) / ((m_c + m_v * r**2) * w2)
    a_c_locked_train = jnp.where(cam_locked, s2, a_body)
    f_t_locked = m_v * r * a_c_locked_train * w2 + m_v * r1 * pc**2 * w2 + spring
    f_t = jnp.where(train_locked, f_t_locked, f_t_c)
    a_c_free = (f_cam_c - r * f_t - vt.tappet_force) / (m_c * w2)
    a_c = jnp.where(cam_locked, s2, jnp.where(train_locked, a_body, a_c_free))
    f_cam = jnp.where(cam_locked, m_c * s2 * w2 + r * f_t + vt.tappet_force, f_cam_c)
    a_v = jnp.where(train_locked, r * a_c + r1 * pc**2, jnp.where(seat_locked, 0.0, (f_t - spring) / (m_v * w2)))
    f_seat = jnp.where(seat_locked, spring - f_t, 0.0)
    return a_c, a_v, f_cam, f_t, f_seat, (xc, pc, xv, pv, s, s1)


def _spring_force(vt, omega, xv, pv, y):
    """The valve spring's force on the valve (N): ``k x_v + F0 + c x_v'``, or with its coils as a chain the last
    segment's (spring and damper) with the preload and the valve's damper."""
    if vt.coils is None:
        return vt.spring_rate * xv + vt.preload + vt.spring_damping * omega * pv
    m = vt.coils.count - 1
    u, p = y[4 + m - 1], y[4 + 2 * m - 1]  # the lump next to the valve
    end = vt.coils.segment_rate * (xv - u) + vt.coils.segment_damping * omega * (pv - p)
    return end + vt.preload + vt.spring_damping * omega * pv


def _coils_accel(vt, omega, xv, pv, y):
    """The inner lumps' accelerations per rad^2, each between its neighbours (the fixed head at 0, the valve)."""
    c, m = vt.coils, vt.coils.count - 1
    u, p = y[4 : 4 + m], y[4 + m :]
    zero = jnp.zeros(1)
    u_l, u_r = jnp.concatenate([zero, u[:-1]]), jnp.concatenate([u[1:], jnp.atleast_1d(xv)])
    p_l, p_r = jnp.concatenate([zero, p[:-1]]), jnp.concatenate([p[1:], jnp.atleast_1d(pv)])
    force = c.segment_rate * (u_l - 2 * u + u_r) + c.segment_damping * omega * (p_l - 2 * p + p_r)
    return force / (c.lump_mass * omega**2)


def _vector_field(theta, y, args):
    a_c, a_v, *_, (xc, pc, xv, pv, s, s1) = _dynamics(theta, y, args)
    vt, omega = args[1], args[2]
    if vt.coils is None:
        return jnp.stack([pc, a_c, pv, a_v])
    m = vt.coils.count - 1
    return jnp.concatenate([jnp.stack([pc, a_c, pv, a_v]), y[4 + m :], _coils_accel(vt, omega, xv, pv, y)])


def _conditions(theta, y, args):
    """Each contact's event function, positive while its mode holds: a locked contact's force, a free one's gap."""
    _, vt, _, modes, force_tol = args
    _, _, f_cam, f_t, f_seat, (xc, pc, xv, pv, s, s1) = _dynamics(theta, y, args)
    cam = jnp.where(modes[CAM], f_cam + force_tol, jnp.where(jnp.isinf(vt.cam.train_stiffness), xc - s + GAP_EPS, 1.0))
    lash_gap = vt.lash + xv - vt.lever(xc)[0]
    train = jnp.where(
        jnp.isinf(vt.train.train_stiffness), jnp.where(modes[TRAIN], f_t + force_tol, lash_gap + GAP_EPS), 1.0
    )
    seat = jnp.where(modes[SEAT], f_seat + force_tol, xv + GAP_EPS)
    return cam, train, seat


def _first_change(t, y, args, **kwargs):
    """Positive while every contact keeps its mode: the least of the contacts' event functions (continuous, so a
    bracketing root finder pins where the first one changes)."""
    return jnp.min(jnp.stack(_conditions(t, y, args)))


class _Bracket(optx.Bisection):
    """Bisection that stops on the bracket's width alone: the event functions mix forces (N) and gaps (m), and
    a force through a kink or a segment boundary need not come near zero at its crossing."""

    def terminate(
        self, fn: Any, y: Any, args: Any, options: Any, state: Any, tags: Any
    ) -> tuple[jax.Array, optx.RESULTS]:
        return jnp.abs(state.lower - state.upper) < self.atol + self.rtol * jnp.abs(y), optx.RESULTS.successful


_EVENT = diffrax.Event(_first_change, root_finder=_Bracket(rtol=1e-14, atol=1e-12), direction=False)


@cached_jit
def _stretch(motion, vt, omega, modes, force_tol, t0, t1, y0, jumps, ts):
    """One stretch in a fixed mode from t0 until a contact opens or closes (an event) or t1, saved at ``ts``
    (clipped into [t0, t1]; those past an event come back as inf) and at its end, with (F_cam, F_t) at each,
    whether it ended at an event and whether the solver succeeded, and :func:`_state_and_conditions` at its end
    (what the transition there reads: one program call a stretch, not two)."""
    pid = diffrax.PIDController(rtol=_RTOL, atol=_ATOL)
    args = (motion, vt, omega, modes, force_tol)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_vector_field),
        diffrax.Tsit5(),
        t0=t0,
        t1=t1,
        dt0=None,
        y0=y0,
        args=args,
        saveat=diffrax.SaveAt(subs=(diffrax.SubSaveAt(ts=ts), diffrax.SubSaveAt(t1=True))),
        stepsize_controller=diffrax.ClipStepSizeController(pid, jump_ts=jumps),
        event=_EVENT,
        max_steps=_MAX_STEPS,
        throw=False,
    )

    def one(t: ArrayLike, y: jax.Array) -> jax.Array:
        _, _, f_cam, f_t, _, (xc, pc, xv, pv, _, _) = _dynamics(t, y, args)
        return jnp.stack([xc, pc, xv, pv, f_cam, f_t])

    assert sol.ts is not None and sol.ys is not None  # saved at ts and at the end
    (t_saved, t_end), (y_saved, y_end) = sol.ts, sol.ys
    # the solver's result as two flags: a stored program (cached_jit) returns arrays, not equinox's enumeration
    hit, ok = sol.result == diffrax.RESULTS.event_occurred, sol.result == diffrax.RESULTS.successful
    end = _state_and_conditions(t_end[0], y_end[0], args)
    return t_end[0], y_end[0], (hit, ok), jax.vmap(one)(t_saved, y_saved), end


def _state_and_conditions(theta, y, args):
    """:func:`_state`'s seven numbers and :func:`_conditions`' three in one array: where a stretch ends, one call."""
    return jnp.concatenate([jnp.stack(_state(theta, y, args)), jnp.stack(_conditions(theta, y, args))])


_conditions_jit = cached_jit(_conditions)
_state_and_conditions_jit = cached_jit(_state_and_conditions)


def _jump_angles(motion: Motion) -> np.ndarray:
    """The motion's segment boundaries (rad) over every revolution a response marches: the stretches' jump times,
    padded with +inf to a bucket of lengths (32, 128, ...), so that cams with other numbers of segments share the
    stretch's stored program (a compile of about 3 s)."""
    breaks = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
    jumps = np.sort((breaks[None, :] + TWO_PI * np.arange(-1, _REVS + 2)[:, None]).ravel())
    return np.pad(jumps, (0, padded_length(jumps.size, _JUMP_ROWS) - jumps.size), constant_values=np.inf)


def _state_size(vt: ValvetrainModel) -> int:
    """The two-mass state's length: follower and valve (position and velocity), and the spring's inner lumps."""
    return 4 + (0 if vt.coils is None else 2 * (vt.coils.count - 1))


def _first_modes(vt: ValvetrainModel) -> np.ndarray:
    """The contacts' modes at rest (cam contact locked where it is rigid, the train free, the valve seated)."""
    return np.array([vt.rigid_cam, False, True])


def prepare_valvetrain(motion: Motion, vt: ValvetrainModel, n: int = THETA_GRID) -> None:
    """Load (or compile) the stored programs :func:`valvetrain_response` starts with, for ``motion`` and ``vt`` on
    ``n`` angles, without running them: the stretch's (a 1.6 MB executable: 0.16 s of a warm valvetrain ``check``
    on a CPU) and the contacts' conditions. For a head start on another thread
    (:func:`camdyn._core.jit.in_background`)."""
    one, y = np.asarray(1.0), np.zeros(_state_size(vt))
    args = (motion, vt, one, _first_modes(vt), one)
    _stretch.prepare(*args, one, one, y, _jump_angles(motion), np.zeros(n))  # pyright: ignore[reportFunctionMemberAccess]
    _conditions_jit.prepare(one, y, args)  # pyright: ignore[reportFunctionMemberAccess]


def landing_floor(vt: ValvetrainModel, omega: float) -> float:
    """The valve's rebound speed (m/rad) at or below which the seat holds it: its bounces below are the landing
    tolerance's own (the Zeno tail)."""
    a_seat = float(vt.preload) / float(vt.valve_mass) / omega**2
    return 10.0 * math.sqrt(2.0 * a_seat * GAP_EPS)


def start_angle(s: np.ndarray) -> int:
    """The grid index in the middle of the longest stretch of base circle (the least lift, periodic): where the
    follower rests furthest from the event on either side (a start closer to the rise would begin with the
    compliant contact's vibration that the rise's first acceleration sets off, not at rest)."""
    n = len(s)
    low = s <= s.min() + 1e-6 * max(1e-12, float(s.max() - s.min()))
    if low.all():
        return 0
    shift = int(np.argmin(low))  # a lifted angle: no run of base circle wraps the scan
    edges = np.diff(np.concatenate([[0], low[(np.arange(n) + shift) % n].astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # each run of base circle: [start, end)
    k = int(np.argmax(ends - starts))  # the longest (the first of equals)
    return int((shift + ends[k] - 1 - (ends[k] - starts[k]) // 2) % n)


def valvetrain_response(motion: Motion, vt: ValvetrainModel, omega: float, n: int = THETA_GRID) -> ValvetrainResponse:
    """The periodic steady state of the valvetrain at cam speed ``omega`` (rad/s), on ``n`` angles.

    From rest on the base circle (the valve seated, the follower on the cam) the revolution is marched stretch by
    stretch; where the valve or the follower is still moving when it ends, up to :data:`_REVS` revolutions are
    marched and the last one is the answer (``settled`` says whether it came back to rest); a spring's coils, which
    ring on over the base circle, at least two.
    """
    theta = np.arange(n) * (TWO_PI / n)
    vals = motion.host(theta)
    s_si = vals[0] * M_PER_MM
    i0 = start_angle(vals[0])
    t_start = float(theta[i0])
    # the stored programs' inputs as numpy arrays: jnp.asarray dispatches a conversion (tens of microseconds) per call
    w = np.asarray(float(omega))
    r = float(vt.ratio)
    rigid_cam, rigid_train = vt.rigid_cam, vt.rigid_train
    force_tol = np.asarray(1e-6 * max(1.0, r * float(vt.preload)))
    jumps = _jump_angles(motion)
    # the rest state: the valve seated, the follower on the cam, pressed into a compliant contact by the tappet force
    deflect = 0.0 if rigid_cam else float(vt.tappet_force) / float(vt.cam.train_stiffness)
    y = np.zeros(_state_size(vt))  # the spring's inner lumps at rest
    y[:2] = s_si[i0] - deflect, vals[1][i0] * M_PER_MM
    modes = _first_modes(vt)
    out = np.zeros((6, n))
    seated = np.ones(n, bool)
    v_floor = landing_floor(vt, float(omega))
    e_seat, e_cam = float(vt.seat_restitution), float(vt.cam_restitution)
    # the valve's event ends where it lands after rising past half its static lift at the nose (the train and the
    # spring in balance): a landing before (the valve kicked off its seat as the lash closes) belongs to the opening

    def lever(x_c: float) -> tuple[float, float]:  # the cam's lift at the valve (m) and the ratio at x_c (m)
        g, ratio, _ = vt.host_lever(x_c)
        return float(g), float(ratio)

    reach = lever(float(s_si.max()))[0] - lever(float(s_si.min()))[0] - float(vt.lash)
    half_lift = 0.5 * static_valve_lift(
        reach, float(vt.preload), float(vt.train.train_stiffness), float(vt.spring_rate)
    )
    warnings: list[str] = []
    settled = False
    for rev in range(_REVS):
        t0, t_end = t_start + rev * TWO_PI, t_start + (rev + 1) * TWO_PI
        events: list[ValveEvent] = []
        first_seating, bounce, peak = None, 0.0, 0.0
        k_next = rev * n  # the next grid angle to fill, counted from t_start
        in_event = np.zeros(n, bool)  # the valve off its seat between its lift and its first seating
        count = 0
        start = None  # the contacts' event functions where the next stretch starts
        while True:
            m = modes.copy()  # this stretch's: modes changes at its end

            def run(
                ts: np.ndarray, m: Any = m, t0: float = t0, t_end: float = t_end, y: Any = y
            ) -> np.ndarray:  # this stretch again, saved at ts: (6, len(ts))
                t1, _, _, out, _ = _stretch(
                    motion, vt, w, m, force_tol, np.asarray(t0), np.asarray(t_end), np.asarray(y), jumps, ts
                )
                return np.asarray(out).T

            if start is None:  # a revolution's first stretch (after a transition _consistent gave them)
                start = np.asarray(_conditions_jit(np.asarray(t0), np.asarray(y), (motion, vt, w, m, force_tol)))
            if start.min() < 0.0:
                # a contact already past its change where the stretch would start (a grazing crossing the last
                # one's root finder did not see): every event function would start below zero and the stretch
                # would see none of them, so the change is made here, before marching on
                t1, y1, hit, end = t0, y, True, None
            else:
                tt = np.clip(t_start + np.arange(k_next, k_next + n) * (TWO_PI / n), t0, t_end)  # fixed shape
                t1, y1, (hit, ok), samples, end = _stretch(
                    motion,
                    vt,
                    w,
                    m,
                    force_tol,
                    np.asarray(t0),
                    np.asarray(t_end),
                    np.asarray(y),
                    jumps,
                    tt,
                )
                t1, samples = float(t1), np.asarray(samples).T
                hit = bool(hit)
                if not (hit or bool(ok)):
                    raise NumericalError(
                        f"valvetrain at {omega / RPM:.4g} rpm",
                        "the two-mass integration failed (solver out of steps or NaN): check the masses and "
                        "stiffnesses",
                    )
                k1 = min(math.floor((t1 - t_start) / (TWO_PI / n) + 1e-9), (rev + 1) * n - 1)
                if k1 >= k_next:
                    ii = (i0 + np.arange(k_next, k1 + 1)) % n
                    out[:, ii] = samples[:, : k1 - k_next + 1]
                    seated[ii] = bool(modes[SEAT])
                    in_event[ii] = first_seating is None and not modes[SEAT]
                    peak = max(peak, float(samples[2, : k1 - k_next + 1].max()))
                    k_next = k1 + 1
                # a flight after the seating: its apex (the stretch run again on n angles), unless the cubic
                # through its saved states stays well below the highest apex so far (a later, lower rebound)
                if first_seating is not None and not modes[SEAT]:
                    if modes[TRAIN] or not _below(_flight_top(t0, y, t1, np.asarray(y1), tt, samples), bounce):
                        bounce = max(bounce, _apex(run, t0, t1, n))
                if not hit:  # the revolution's end: the next one, if any, goes on from here
                    y = np.asarray(y1)
                    break
            count += 1
            if count > _MAX_EVENTS:
                warnings.append(f"more than {_MAX_EVENTS} contact changes in a revolution at {omega / RPM:.1f} rpm")
                break
            y1 = np.asarray(y1)
            if end is None:  # no stretch ran: the state and the conditions where it would have started
                end = _state_and_conditions_jit(np.asarray(t1), y1, (motion, vt, w, modes.copy(), force_tol))
            st = np.asarray(end)
            s, s1, _, xc, pc, xv, pv = (float(v) for v in st[:7])
            conds = st[7:]
            which = int(np.argmin(conds))  # the contact whose event function reached zero
            deg = math.degrees(t1) % 360.0
            y = np.concatenate([[xc, pc, xv, pv], y1[4:]])
            if which == CAM and modes[CAM]:  # the cam lets go of the follower
                modes[CAM] = False
                if not modes[SEAT] and first_seating is None:
                    events.append(ValveEvent("float", deg))
            elif which == CAM:  # the follower lands on the cam
                rel = pc - s1
                events.append(ValveEvent("cam-landing", deg, abs(rel) * float(omega)))
                y[1] = s1 - e_cam * rel
                y[0] = s
                if modes[TRAIN]:
                    y[3] = lever(y[0])[1] * y[1]
                if not (e_cam > 0.0 and abs(rel) > v_floor):
                    y[1] = s1
                    modes[CAM] = True
            elif which == TRAIN and modes[TRAIN]:  # the rigid train lets go: the lash opens
                modes[TRAIN] = False
            elif which == TRAIN:  # the lash closes: the two masses meet (plastic), at the rocker's ratio there
                g, r_here = lever(xc)
                if modes[CAM]:
                    y[3] = r_here * pc
                else:
                    m_c, m_v = float(vt.cam_side_mass), float(vt.valve_mass)
                    y[1] = (m_c * pc + r_here * m_v * pv) / (m_c + m_v * r_here**2)
                    y[3] = r_here * y[1]
                y[2] = g - float(vt.lash)
                modes[TRAIN], modes[SEAT] = True, False
                events.append(ValveEvent("lash", deg))
            elif which == SEAT and modes[SEAT]:  # the train lifts the valve
                modes[SEAT] = False
                y[2], y[3] = 0.0, 0.0
                events.append(ValveEvent("valve-lift", deg))
            else:  # the valve lands on its seat
                events.append(ValveEvent("seating", deg, abs(pv) * float(omega)))
                if first_seating is None and peak > half_lift:  # the landing that ends the event, not a rattle
                    first_seating = t1
                modes[TRAIN] = False
                y[2], y[3] = 0.0, -e_seat * pv
                if y[3] <= v_floor:
                    modes[SEAT], y[3] = True, 0.0
            modes, start = _consistent(modes, t1, y, motion, vt, w, force_tol, rigid_cam, rigid_train)
            t0 = t1
        settled = (
            modes[SEAT]
            and (modes[CAM] or not rigid_cam)
            and not modes[TRAIN]
            and abs(y[3]) == 0.0
            and count <= _MAX_EVENTS
        )
        if settled and (vt.coils is None or rev > 0):  # a spring's coils ring on: a revolution that starts with it
            break
    if not settled:
        warnings.append(
            f"the valvetrain is not back at rest on the base circle after {_REVS} revolutions at "
            f"{omega / RPM:.1f} rpm: the last one is reported"
        )
    xc, pc, xv, pv, f_cam, f_t = out
    return ValvetrainResponse(
        float(omega),
        np.degrees(theta),
        vals[0],
        xc / M_PER_MM,
        np.where(seated, 0.0, xv) / M_PER_MM,
        np.where(seated, 0.0, pv) * float(omega),
        f_cam,
        f_t,
        seated,
        in_event,
        tuple(events),
        bounce / M_PER_MM,
        bool(settled),
        tuple(warnings),
    )


def _consistent(modes, t, y, motion, vt, w, force_tol, rigid_cam, rigid_train) -> tuple[np.ndarray, np.ndarray]:
    """The modes after a transition, with every locked contact whose force already pulls released (its event
    would not see a crossing that starts below zero), and the contacts' event functions in those modes."""
    modes = modes.copy()

    def conditions() -> np.ndarray:
        return np.asarray(_conditions_jit(np.asarray(t), np.asarray(y), (motion, vt, w, modes.copy(), force_tol)))

    for _ in range(4):
        conds = conditions()
        changed = False
        if modes[CAM] and rigid_cam and conds[CAM] <= 0.0:
            modes[CAM], changed = False, True
        if modes[TRAIN] and rigid_train and conds[TRAIN] <= 0.0:
            modes[TRAIN], changed = False, True
        if modes[SEAT] and conds[SEAT] <= 0.0:
            modes[SEAT], changed = False, True
        if not changed:
            return modes, conds
    return modes, conditions()


def _flight_top(t0: float, y0: np.ndarray, t1: float, y1: np.ndarray, ts: np.ndarray, samples: np.ndarray) -> float:
    """The highest lift (m) of the cubic Hermite interpolant through the valve's lift and speed at a free stretch's
    start ``y0`` (``t0``), its samples (``samples`` rows 2 and 3 at ``ts``, those inside (t0, t1)) and its end
    ``y1`` (``t1``): an error of order a grid step's h^4 (within 3e-11 m of every apex on the shipped valvetrains)."""
    inside = (ts > t0) & (ts < t1)
    t = np.concatenate([[t0], ts[inside], [t1]])
    x = np.concatenate([[y0[2]], samples[2, inside], [y1[2]]])
    v = np.concatenate([[y0[3]], samples[3, inside], [y1[3]]])
    return hermite_top(t, x, v)


def _below(top: float, bounce: float) -> bool:
    """Whether a flight whose interpolated top is ``top`` (m) surely stays under the highest apex so far: by 1 % and
    1e-9 m, 30 times the interpolation's largest error measured (:func:`_flight_top`)."""
    return top * 1.01 + 1e-9 < bounce


def _apex(run, t0: float, t1: float, n: int) -> float:
    """The valve's highest lift within a stretch of free flight (m): the stretch again on ``n`` angles, the top
    refined by the parabola through the highest sample and its neighbours."""
    ts = np.linspace(t0, t1, n)
    xv = run(ts)[2]
    j = int(np.argmax(xv))
    if 0 < j < n - 1:
        a, b, c = xv[j - 1], xv[j], xv[j + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            return float(b - 0.125 * (a - c) ** 2 / den)
    return float(xv[j])
