"""The valvetrain in the time domain: two masses, the train and its lash, the cam contact and the valve's seat,
event-driven on diffrax (float64), over one revolution at a constant cam speed (the equations and the stretch between
two contact changes: :mod:`._valvefield`).

The revolution is marched stretch by stretch; at each stretch's end the contact that changed is changed on the host
(:func:`_transition`: a landing with its restitution, the lash closing as a plastic impact, the valve lifted off or
landing on its seat). The revolution starts on the base circle with the valve seated and at rest, so once the valve
has seated and the follower is back on the cam before the revolution ends, that revolution is the periodic steady
state.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from ..._core.errors import NumericalError
from ..._core.jit import padded_length
from ..._core.units import M_PER_MM, RPM, THETA_GRID, TWO_PI
from ..motion import Motion
from ..valvetrain import ValvetrainModel, static_valve_lift
from ._cubic import hermite_top
from ._valvefield import CAM, GAP_EPS, SEAT, TRAIN, conditions_at, rows_at, state_and_conditions_at, stretch
from ._valveresponse import ValveEvent, ValvetrainResponse

_MAX_EVENTS = 2000  # per revolution: bounces beyond it leave the valve or the follower not settled
_REVS = 3  # revolutions at most to reach the periodic steady state
# How far past a stretch's end (rad) the contacts' event functions are read again: past the root finder's 1e-12 rad
# (an event function that jumps through zero reads its value after the jump there), within a hair of it for the rest
_PAST = 1e-9
_JUMP_ROWS = 512  # the stretches' jump times are padded to 512, 2048, ... (+inf): any cam of up to 85 segments
NO_EVENT = 1e300  # N: the float search's least force at a speed where the valve does not lift (it wants finite)


def _jump_angles(motion: Motion) -> np.ndarray:
    """The motion's segment boundaries (rad) over every revolution a response marches: the stretches' jump times,
    padded with +inf to a bucket of lengths (512, 2048, ...), so that cams with other numbers of segments share the
    stretch's stored program (a compile of about 3 s). One bucket up to 85 segments, so that a new valve cam finds
    the program the shipped ones stored (smaller buckets split cams of 5 and 8 segments); the controller finds its
    next jump from the last (diffrax's hint), so the padding costs nothing a step."""
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
    on a CPU), the contacts' conditions and the revolution's rows. For a head start on another thread
    (:func:`camdyn._core.jit.in_background`)."""
    one, y = np.asarray(1.0), np.zeros(_state_size(vt))
    args = (motion, vt, one, _first_modes(vt), one)
    stretch.prepare(*args, one, one, y, _jump_angles(motion), np.zeros(n))  # pyright: ignore[reportFunctionMemberAccess]
    conditions_at.prepare(one, y, args)  # pyright: ignore[reportFunctionMemberAccess]
    modes = np.broadcast_to(_first_modes(vt), (n, 3))
    rows_at.prepare(motion, vt, one, modes, one, np.zeros(n), np.zeros((n, y.size)))  # pyright: ignore[reportFunctionMemberAccess]


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
    # each grid angle's solver state, angle and contacts' modes as last marched: what the contacts see there is
    # evaluated once, after the last revolution (:func:`._valvefield.rows_at`)
    t_at, y_at, mode_at = np.zeros(n), np.zeros((n, y.size)), np.zeros((n, 3), bool)
    filled = np.zeros(n, bool)
    seated = np.ones(n, bool)
    impacts = _Impacts(
        float(vt.cam_restitution), float(vt.seat_restitution), float(omega), landing_floor(vt, float(omega))
    )
    # the valve's event ends where it lands after rising past half its static lift at the nose (the train and the
    # spring in balance): a landing before (the valve kicked off its seat as the lash closes) belongs to the opening
    reach = float(vt.host_lever(float(s_si.max()))[0]) - float(vt.host_lever(float(s_si.min()))[0]) - float(vt.lash)
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
            ) -> np.ndarray:  # this stretch again, saved at ts: rows_at's (7, len(ts))
                _, _, _, ys, _ = stretch(
                    motion, vt, w, m, force_tol, np.asarray(t0), np.asarray(t_end), np.asarray(y), jumps, ts
                )
                return np.asarray(rows_at(motion, vt, w, np.broadcast_to(m, (len(ts), 3)), force_tol, ts, ys))

            if start is None:  # a revolution's first stretch (after a transition _consistent gave them)
                start = np.asarray(conditions_at(np.asarray(t0), np.asarray(y), (motion, vt, w, m, force_tol)))
            if start.min() < 0.0:
                # a contact already past its change where the stretch would start (a grazing crossing the last
                # one's root finder did not see): every event function would start below zero and the stretch
                # would see none of them, so the change is made here, before marching on
                t1, y1, hit, end = t0, y, True, None
            else:
                tt = np.clip(t_start + np.arange(k_next, k_next + n) * (TWO_PI / n), t0, t_end)  # fixed shape
                t1, y1, (hit, ok), samples, end = stretch(
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
                t1, samples = float(t1), np.asarray(samples)  # the solver's states at tt: (n, state)
                hit = bool(hit)
                if not (hit or bool(ok)):
                    raise NumericalError(
                        f"valvetrain at {omega / RPM:.4g} rpm",
                        "the two-mass integration failed (solver out of steps or NaN): check the masses and "
                        "stiffnesses",
                    )
                k1 = min(math.floor((t1 - t_start) / (TWO_PI / n) + 1e-9), (rev + 1) * n - 1)
                # an angle the solver did not save (inf: a hair past its root at an event on a grid angle, or at a
                # jump on the revolution's end) is the next stretch's to fill
                k1 = min(k1, k_next + int(np.isfinite(samples[:, 0]).sum()) - 1)
                if k1 >= k_next:
                    ii, count_ii = (i0 + np.arange(k_next, k1 + 1)) % n, k1 - k_next + 1
                    t_at[ii], y_at[ii], mode_at[ii], filled[ii] = tt[:count_ii], samples[:count_ii], m, True
                    seated[ii] = bool(modes[SEAT])
                    in_event[ii] = first_seating is None and not modes[SEAT]
                    # the valve's lift as integrated (what the locks give within the solver's tolerance)
                    peak = max(peak, float(samples[:count_ii, 2].max()))
                    k_next = k1 + 1
                # a flight after the seating: its apex (the stretch run again on n angles), unless the cubic
                # through its saved states stays well below the highest apex so far (a later, lower rebound)
                if first_seating is not None and not modes[SEAT]:
                    if modes[TRAIN] or not _below(_flight_top(t0, y, t1, np.asarray(y1), tt, samples.T), bounce):
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
                end = state_and_conditions_at(np.asarray(t1), y1, (motion, vt, w, modes.copy(), force_tol))
            after = conditions_at(np.asarray(t1 + _PAST), y1, (motion, vt, w, modes.copy(), force_tol))
            event, modes, y = _transition(vt, impacts, modes, np.asarray(end), y1, t1, np.asarray(after))
            if event is not None and not (event.what == "float" and first_seating is not None):
                events.append(event)  # a float counts until the valve has first seated
            if event is not None and event.what == "seating" and first_seating is None and peak > half_lift:
                first_seating = t1  # the landing that ends the event, not a rattle
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
    xc, pc, xv, pv, f_cam, f_t, f_hold = np.where(
        filled, np.asarray(rows_at(motion, vt, w, mode_at, force_tol, t_at, y_at)), 0.0
    )
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
        f_hold if rigid_cam else None,  # a compliant contact's force is its spring's: no lock to hold it by
    )


class _Impacts(NamedTuple):
    """What a contact change needs at one cam speed: the cam's and the seat's restitution, the speed (rad/s) and the
    rebound speed (m/rad) at or below which a landing holds (:func:`landing_floor`)."""

    e_cam: float
    e_seat: float
    omega: float
    v_floor: float


def _transition(
    vt: ValvetrainModel,
    impacts: _Impacts,
    modes: np.ndarray,
    st: np.ndarray,
    y1: np.ndarray,
    t1: float,
    after: np.ndarray,
) -> tuple[ValveEvent | None, np.ndarray, np.ndarray]:
    """The contact change at a stretch's end ``t1`` (rad): ``st`` the state and the contacts' event functions there
    (:func:`._valvefield.state_and_conditions_at`), ``after`` the event functions :data:`_PAST` later (the same state),
    ``y1`` the solver's state (its spring lumps go on), ``modes`` the contacts' modes in the stretch. The change is the
    contact whose event function reached zero (the least of each one's two values: one that jumps through zero there, a
    seat force as a compliant train closes its lash fast, reads its value before the jump at ``t1``, after it past it):
    a locked one lets go, a free one closes (an impact: the cam's restitution, the lash's plastic meeting at the
    rocker's ratio, the seat's restitution). Returns the event it makes (None: the cam or the train letting go makes
    none here) and the modes and the state after it."""
    modes = modes.copy()
    s, s1, _, xc, pc, xv, pv = (float(v) for v in st[:7])
    which = int(np.argmin(np.minimum(st[7:], after)))
    deg = math.degrees(t1) % 360.0
    y = np.concatenate([[xc, pc, xv, pv], y1[4:]])
    event = None
    if which == CAM and modes[CAM]:  # the cam lets go of the follower: a float if the valve is off its seat
        modes[CAM] = False
        event = None if modes[SEAT] else ValveEvent("float", deg)
    elif which == CAM:  # the follower lands on the cam
        rel = pc - s1
        event = ValveEvent("cam-landing", deg, abs(rel) * impacts.omega)
        y[1] = s1 - impacts.e_cam * rel
        y[0] = s
        if modes[TRAIN]:
            y[3] = float(vt.host_lever(y[0])[1]) * y[1]
        if not (impacts.e_cam > 0.0 and abs(rel) > impacts.v_floor):
            y[1] = s1
            modes[CAM] = True
    elif which == TRAIN and modes[TRAIN]:  # the rigid train lets go: the lash opens
        modes[TRAIN] = False
    elif which == TRAIN:  # the lash closes: the two masses meet (plastic), at the rocker's ratio there
        g, r_here, _ = (float(v) for v in vt.host_lever(xc))
        if modes[CAM]:
            y[3] = r_here * pc
        else:
            m_c, m_v = float(vt.cam_side_mass), float(vt.valve_mass)
            y[1] = (m_c * pc + r_here * m_v * pv) / (m_c + m_v * r_here**2)
            y[3] = r_here * y[1]
        y[2] = g - float(vt.lash)
        modes[TRAIN], modes[SEAT] = True, False
        event = ValveEvent("lash", deg)
    elif which == SEAT and modes[SEAT]:  # the train lifts the valve
        modes[SEAT] = False
        y[2], y[3] = 0.0, 0.0
        event = ValveEvent("valve-lift", deg)
    else:  # the valve lands on its seat
        event = ValveEvent("seating", deg, abs(pv) * impacts.omega)
        modes[TRAIN] = False
        y[2], y[3] = 0.0, -impacts.e_seat * pv
        if y[3] <= impacts.v_floor:
            modes[SEAT], y[3] = True, 0.0
    return event, modes, y


def _consistent(modes, t, y, motion, vt, w, force_tol, rigid_cam, rigid_train) -> tuple[np.ndarray, np.ndarray]:
    """The modes after a transition, with every locked contact whose force already pulls released (its event
    would not see a crossing that starts below zero), and the contacts' event functions in those modes."""
    modes = modes.copy()

    def conditions() -> np.ndarray:
        return np.asarray(conditions_at(np.asarray(t), np.asarray(y), (motion, vt, w, modes.copy(), force_tol)))

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
    xv = np.where(np.isfinite(xv), xv, -np.inf)  # the end, where a jump there kept the solver a float short of it
    j = int(np.argmax(xv))
    if 0 < j < n - 1 and np.isfinite(xv[j + 1]):
        a, b, c = xv[j - 1], xv[j], xv[j + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            return float(b - 0.125 * (a - c) ** 2 / den)
    return float(xv[j])
