"""The valvetrain's equations in one mode of its contacts, and the stretch: one diffrax solve (Tsit5, tight
tolerances) until a contact opens or closes.

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

Between events every active contact's state is smooth, so a stretch is one solve with a terminating event for each
contact that can open or close. The state is integrated in the cam angle (x and dx/dtheta, m and m/rad).
"""

from __future__ import annotations

import functools
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
from jax.typing import ArrayLike

from ..._core.jit import cached_jit
from ..._core.units import M_PER_MM
from ..motion import Motion
from ..valvetrain import ValvetrainModel
from ._train import contact_force

_RTOL, _ATOL = 1e-10, 1e-14  # the state is in m and m/rad: lifts of 1e-2 m
GAP_EPS = 1e-12  # m: a landing is detected this far below contact
_MAX_STEPS = 1_000_000
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
    """Each contact's event function, positive while its mode holds: a locked contact's force, a free one's gap; +inf
    for a compliant contact, which has no modes. (Not a finite constant: the transition takes the least of the three
    where a stretch ends as the contact that changed, and a seat force that jumps through zero there, the damping of a
    compliant train closing its lash fast, still reads its value before the jump: 1.0 N was once taken for the lash,
    locking the compliant train rigid.)"""
    _, vt, _, modes, force_tol = args
    _, _, f_cam, f_t, f_seat, (xc, pc, xv, pv, s, s1) = _dynamics(theta, y, args)
    cam = jnp.where(
        modes[CAM], f_cam + force_tol, jnp.where(jnp.isinf(vt.cam.train_stiffness), xc - s + GAP_EPS, jnp.inf)
    )
    lash_gap = vt.lash + xv - vt.lever(xc)[0]
    train = jnp.where(
        jnp.isinf(vt.train.train_stiffness), jnp.where(modes[TRAIN], f_t + force_tol, lash_gap + GAP_EPS), jnp.inf
    )
    seat = jnp.where(modes[SEAT], f_seat + force_tol, xv + GAP_EPS)
    return cam, train, seat


def _first_change(t, y, args, **kwargs):
    """Positive while every contact keeps its mode: the least of the contacts' event functions (continuous, so a
    bracketing root finder pins where the first one changes)."""
    return jnp.min(jnp.stack(_conditions(t, y, args)))


@functools.cache
def _event() -> Any:
    """The stretch's event: the first contact change, its root bracketed by bisection that stops on the bracket's
    width alone (the event functions mix forces (N) and gaps (m), and a force through a kink or a segment boundary
    need not come near zero at its crossing). Built at the first trace: diffrax and optimistix load only where a
    program is traced, not where a stored one runs (0.4 s of a warm ``check``).

    A change that the step does not bracket is at the angle the step ends on: where the cam's acceleration jumps
    (a segment boundary, one of the controller's ``jump_ts``) a locked cam contact's force jumps with it; the
    step ends on the float before the jump, and diffrax reads the event function where the next step starts, the
    float after it, past the step's bracket (optimistix's bisection would stop with an error, or under
    ``EQX_ON_ERROR=nan`` return a time inside the step, where no contact changes). The root is then that angle."""
    import diffrax
    import optimistix as optx

    class Bracket(optx.Bisection):
        def init(self, fn: Any, y: Any, args: Any, options: Any, f_struct: Any, aux_struct: Any, tags: Any) -> Any:
            state = super().init(fn, y, args, options, f_struct, aux_struct, tags)  # flip given: no evaluation
            lower_val, upper_val = fn(state.lower, args)[0], fn(state.upper, args)[0]
            inside = (lower_val < 0) != (upper_val < 0)  # else the change is past the step's end: collapse there
            lower = jnp.where(inside, state.lower, state.upper)
            return eqx.tree_at(lambda s: (s.lower, s.flip), state, (lower, lower_val > upper_val))

        def step(self, fn: Any, y: Any, args: Any, options: Any, state: Any, tags: Any) -> tuple[Any, Any, Any]:
            collapsed = state.lower == state.upper
            new_y, new_state, aux = super().step(fn, y, args, options, state, tags)
            past = jnp.nextafter(jnp.nextafter(state.upper, jnp.inf), jnp.inf)  # where diffrax read the change
            return jnp.where(collapsed, past, new_y), new_state, aux

        def terminate(
            self, fn: Any, y: Any, args: Any, options: Any, state: Any, tags: Any
        ) -> tuple[jax.Array, optx.RESULTS]:
            # after one step at least (the initial error is inf): the first guess is the step's end, not the root
            narrow = jnp.abs(state.lower - state.upper) < self.atol + self.rtol * jnp.abs(y)
            return narrow & jnp.isfinite(state.error), optx.RESULTS.successful

    return diffrax.Event(_first_change, root_finder=Bracket(rtol=1e-14, atol=1e-12, flip=False), direction=False)


@cached_jit
def stretch(
    motion: Motion,
    vt: ValvetrainModel,
    omega: ArrayLike,
    modes: ArrayLike,
    force_tol: ArrayLike,
    t0: jax.Array,
    t1: jax.Array,
    y0: ArrayLike,
    jumps: jax.Array,
    ts: jax.Array,
) -> tuple[jax.Array, jax.Array, tuple[jax.Array, jax.Array], jax.Array, jax.Array]:
    """One stretch in a fixed mode (``modes``: the contacts' locks, :data:`CAM`, :data:`TRAIN`, :data:`SEAT`) at cam
    speed ``omega`` (rad/s) from t0 (rad) until a contact opens or closes (an event) or t1: the solver's state at
    ``ts`` (clipped into [t0, t1]; those past an event come back as inf; :func:`rows_at` turns them into what the
    contacts see) and at its end, whether it ended at an event and whether the solver succeeded, and
    :func:`_state_and_conditions` at its end (what the transition there reads: one program call a stretch, not
    two)."""
    import diffrax  # at the trace only (:func:`_event`)

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
        event=_event(),
        max_steps=_MAX_STEPS,
        throw=False,
    )
    assert sol.ts is not None and sol.ys is not None  # saved at ts and at the end
    (_, t_end), (y_saved, y_end) = sol.ts, sol.ys
    # the solver's result as two flags: a stored program (cached_jit) returns arrays, not equinox's enumeration
    hit, ok = sol.result == diffrax.RESULTS.event_occurred, sol.result == diffrax.RESULTS.successful
    end = _state_and_conditions(t_end[0], y_end[0], args)
    return t_end[0], y_end[0], (hit, ok), y_saved, end


@cached_jit
def rows_at(
    motion: Motion,
    vt: ValvetrainModel,
    omega: ArrayLike,
    modes: ArrayLike,
    force_tol: ArrayLike,
    ts: jax.Array,
    ys: jax.Array,
) -> jax.Array:
    """What the contacts see at the angles ``ts`` (rad) from the solver's states ``ys`` there (one row each), each
    in its own contacts' ``modes`` (one row each): (x_c, x_c', x_v, x_v', F_cam, F_t, F_hold), shape (7, len(ts))
    (m, m/rad, N). ``F_hold``: the cam contact's force were it locked there, the valve as it moves: the force the
    cam would have to give to keep the follower on it (F_cam where a rigid contact holds, negative in a float). A
    revolution's angles in one call at its end: in each stretch, every saved angle's forces took a fifth of the
    revolution's time."""

    def one(t: ArrayLike, y: jax.Array, m: jax.Array) -> jax.Array:
        _, _, f_cam, f_t, _, (xc, pc, xv, pv, _, _) = _dynamics(t, y, (motion, vt, omega, m, force_tol))
        f_hold = _dynamics(t, y, (motion, vt, omega, m.at[CAM].set(True), force_tol))[2]
        return jnp.stack([xc, pc, xv, pv, f_cam, f_t, f_hold])

    return jax.vmap(one, out_axes=1)(ts, ys, jnp.asarray(modes))


def _state_and_conditions(theta, y, args):
    """:func:`_state`'s seven numbers and :func:`_conditions`' three in one array: where a stretch ends, one call."""
    return jnp.concatenate([jnp.stack(_state(theta, y, args)), jnp.stack(_conditions(theta, y, args))])


conditions_at = cached_jit(_conditions)  # the contacts' event functions at one state
state_and_conditions_at = cached_jit(_state_and_conditions)
