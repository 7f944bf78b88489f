"""A revolution of the compliant follower where it may leave the cam, in pieces between the contact's switches.

In each piece the follower's mode is held (on the cam: the train's linear force; flying within the cam's profile
just after leaving it, or clear of it: none), so the field is smooth and affine in the state; a piece ends where its
switch rises through zero (diffrax's event, by bisection on the solver's interpolation). The monodromy is carried
through each piece in closed form and across each switch by its saltation matrix (the flow's Jacobian, for the
shooting's Newton steps in :mod:`._compliant`).
"""

from __future__ import annotations

import functools
from typing import Any

import jax
import jax.numpy as jnp

from ..._core.units import TWO_PI
from ._solver import ATOL, MAX_STEPS, RTOL
from ._train import follower_rates, free_vibration, train_force, vibration_coefficients


def _mode_field(theta, y, args):
    """d/dtheta of (x, p) with the follower's mode held (:data:`_ON` and the flights below): the train's linear force
    on the cam, else none. Smooth across the switches, where :func:`_rev_with_sensitivity` stops each piece of a
    revolution (and the solver's interpolation, on which a switch is found, sees no kink)."""
    motion, model, omega, mode = args
    x, p = y[0], y[1]
    s, s1, _, _ = motion(theta)
    fi = jnp.where(mode == _ON, train_force(model, omega, s, s1, x, p, model.scale), 0.0)
    return follower_rates(model, omega, x, p, fi)


def _mode_flow(model, omega, mode, span):
    """The monodromy of a piece of ``span`` rad in ``mode``: the field is affine in the state there, ``z' = J z +
    g(theta)`` with ``J = [[0, 1], [-a, -b]]``, ``a = (k + k_f) / (m w^2)``, ``b = (c + c_f) / (m w)`` on the cam
    (without the train's terms in flight), so the variational equations' solution is ``exp(J span)``, closed form."""
    on = mode == _ON
    k = model.stiffness + jnp.where(on, model.train_stiffness, 0.0)
    a, b = vibration_coefficients(model.mass, k, model.damping + jnp.where(on, model.train_damping, 0.0), omega)
    e00, e01, e10, e11 = free_vibration(a, b, span)
    return jnp.stack([jnp.stack([e00, e01]), jnp.stack([e10, e11])])


# The follower's modes in a revolution's pieces: clear of the cam (s <= x), flying within its profile (s > x, the
# train's force negative: just after leaving it) and on the cam. The vector field is that of flight in the first two.
_CLEAR, _WITHIN, _ON = 0, 1, 2


def _overlap_and_force(theta, z, motion, model, omega):
    """The follower at ``z`` = (x, dx/dtheta) against the cam at ``theta``: the overlap ``s - x`` and the train's
    force over its stiffness (both motion units), each with its gradient (d/dtheta, d/dz). They touch where both are
    positive (the unilateral :func:`contact_force`)."""
    s, s1, s2, _ = motion(theta)
    lag = model.train_damping * omega / model.train_stiffness  # the damper's share, rad
    overlap, force = s - z[0], s - z[0] + lag * (s1 - z[1])
    return (overlap, s1, jnp.stack([-1.0, 0.0])), (force, s1 + lag * s2, jnp.stack([-1.0, -lag]))


def _mode_of(theta, z, motion, model, omega):
    """The mode of the follower at ``z`` on ``theta`` (:data:`_ON`, :data:`_WITHIN` or :data:`_CLEAR`)."""
    (overlap, _, _), (force, _, _) = _overlap_and_force(theta, z, motion, model, omega)
    return jnp.where(overlap > 0.0, jnp.where(force > 0.0, _ON, _WITHIN), _CLEAR)


def _switch(theta, z, motion, model, omega, mode):
    """The function whose rise through zero ends a piece in ``mode``, with its gradient (d/dtheta, d/dz): clear of
    the cam, the overlap (a landing: the train's force is ``c_f w (s' - x') >= 0`` there); on it, the force's fall
    (it reaches zero before the overlap does, the train's damping pulling back); within its profile, the first of
    the force's rise (the cam catches the follower again) and the overlap's fall (the follower clears it)."""
    overlap, force = _overlap_and_force(theta, z, motion, model, omega)
    clearing = [-a for a in overlap]
    caught = force[0] >= clearing[0]
    return tuple(
        jnp.where(mode == _CLEAR, o, jnp.where(mode == _ON, -f, jnp.where(caught, f, c)))
        for o, f, c in zip(overlap, force, clearing, strict=True)
    )


def _next_mode(theta, z, motion, model, omega, mode):
    """The mode after :func:`_switch` rose through zero at ``theta``."""
    (overlap, _, _), (force, _, _) = _overlap_and_force(theta, z, motion, model, omega)
    leaving = jnp.where(overlap > 0.0, _WITHIN, _CLEAR)
    within = jnp.where(-overlap >= force, _CLEAR, _ON)
    return jnp.where(mode == _CLEAR, _ON, jnp.where(mode == _ON, leaving, within))


def _piece_ends(t, y, args, **_):
    """:func:`_switch` as diffrax's event calls it."""
    motion, model, omega, mode = args
    return _switch(t, y, motion, model, omega, mode)[0]


def _saltation(theta, z, m, motion, model, omega, mode, after):
    """The monodromy ``m`` across a switch at ``theta`` (:func:`_switch` in ``mode``) to mode ``after``:
    ``(I + (f+ - f-) dg/dz^T / (dg/dtheta along f-)) m``, g the switch. A landing with the train's damping changes
    the field (its force jumps from 0 to ``c_f w (s' - x')``); leaving the cam, where the force is zero, does not.
    A grazing switch (no transversal crossing) is left as it is."""
    before = _mode_field(theta, z, (motion, model, omega, mode))
    jump = _mode_field(theta, z, (motion, model, omega, after)) - before
    _, g_theta, g_z = _switch(theta, z, motion, model, omega, mode)
    rate = g_theta + g_z @ before
    scale = jnp.abs(g_theta) + jnp.abs(g_z) @ jnp.abs(before)
    transversal = jnp.abs(rate) > 1e-9 * scale
    return jnp.where(transversal, m + jnp.outer(jump, g_z) @ m / jnp.where(transversal, rate, 1.0), m)


@functools.cache
def _past_the_switch():
    """Bisection for a switch's angle (to :data:`ATOL`, the switch rising from below zero to above it) that returns
    the bracket's upper end, where the switch has risen: the next piece's own switch then starts below zero, as it
    must to be seen rising (from the midpoint, a flight that started with the train's force at +1e-11 mm never saw
    the follower clear the cam, nor land on it again)."""
    import optimistix as optx

    class PastTheSwitch(optx.Bisection):
        def postprocess(  # optimistix calls it so
            self, fn: Any, y: Any, aux: Any, args: Any, options: Any, state: Any, tags: Any, result: Any
        ) -> tuple[Any, Any, dict]:
            return state.upper, aux, {}

    return PastTheSwitch(rtol=0.0, atol=ATOL, flip=False)


# A piece of a revolution (between the contact's switches) runs past this many of the motion's jumps at most (the
# step-size controller is told only these: it sorts them at each start) and past this many angles of the trajectory.
_JUMP_WINDOW, _SAVE_WINDOW = 8, 64
_MAX_PIECES = 50_000  # switches and windows a revolution: a follower that chatters past it fails (NumericalError)


def _rev_with_sensitivity(motion, model, omega, z0, theta, loosen):
    """One revolution from z0 where the follower may leave the cam, as ``_compliant._rev_in_contact`` where it stays
    on: the state on ``theta`` and at 2 pi, the monodromy and whether the solve succeeded; at the step-size
    controller's tolerances times ``loosen`` (1: :data:`RTOL`, :data:`ATOL`). In pieces between the
    contact's switches, each found as the root of the switch on Tsit5's interpolation (diffrax's event, by
    bisection), with the contact held in each piece (a smooth field: stepping through the contact's kink cost
    about 40 rejected steps a switch), the monodromy through each piece in closed form (:func:`_mode_flow`) and
    across each switch by its saltation matrix (so that Newton's steps see the landings)."""
    import diffrax

    n = theta.shape[0]
    jumps = jnp.sort(jnp.asarray(motion.jump_angles(), dtype=float).ravel())
    jumps = jnp.concatenate([jumps, jnp.full(_JUMP_WINDOW, jnp.inf)])
    angles = jnp.concatenate([theta, jnp.full(_SAVE_WINDOW, TWO_PI)])
    pid = diffrax.PIDController(rtol=RTOL * loosen, atol=ATOL * loosen)
    event = diffrax.Event(_piece_ends, _past_the_switch(), direction=True)
    term = diffrax.ODETerm(_mode_field)

    def _piece(carry):
        t, z, m, mode, traj, pieces, steps, ok = carry
        window = jax.lax.dynamic_slice(jumps, (jnp.searchsorted(jumps, t, side="right"),), (_JUMP_WINDOW,))
        first = jnp.searchsorted(theta, t, side="left").astype(int)
        at = jax.lax.dynamic_slice(angles, (first,), (_SAVE_WINDOW,))
        t_end = jnp.minimum(jnp.minimum(window[-1], at[-1]), TWO_PI)
        sol = diffrax.diffeqsolve(
            term,
            diffrax.Tsit5(),
            t0=t,
            t1=t_end,
            dt0=None,
            y0=z,
            args=(motion, model, omega, mode),
            saveat=diffrax.SaveAt(ts=jnp.clip(at, t, t_end), t1=True),
            stepsize_controller=diffrax.ClipStepSizeController(pid, jump_ts=window),
            event=event,
            max_steps=MAX_STEPS,
            throw=False,
        )
        ts, ys = sol.ts, sol.ys
        assert ts is not None and ys is not None  # SaveAt(ts=..., t1=True) saves the states
        # the end is saved after the angles reached (at an event diffrax deletes the rest: +inf), not in the last row
        end = jnp.sum(jnp.isfinite(ts)) - 1
        t1, y1 = ts[end], ys[end]
        switched = sol.result == diffrax.RESULTS.event_occurred
        ok = ok & (switched | (sol.result == diffrax.RESULTS.successful)) & jnp.all(jnp.isfinite(y1))
        saved = (at >= t) & (at <= t1) & (first + jnp.arange(_SAVE_WINDOW) < n)
        corner = (first, jnp.zeros_like(first))
        kept = jax.lax.dynamic_slice(traj, corner, (_SAVE_WINDOW, 2))
        traj = jax.lax.dynamic_update_slice(traj, jnp.where(saved[:, None], ys[:-1], kept), corner)
        m1 = _mode_flow(model, omega, mode, t1 - t) @ m
        after = jnp.where(switched, _next_mode(t1, y1, motion, model, omega, mode), mode)
        m1 = jnp.where(switched, _saltation(t1, y1, m1, motion, model, omega, mode, after), m1)
        stats = sol.stats["num_accepted_steps"] + sol.stats["num_rejected_steps"]
        return t1, y1, m1, after, traj, pieces + 1, steps + stats, ok

    def _more(carry):
        t, _, _, _, _, pieces, steps, ok = carry
        return ok & (t < TWO_PI) & (pieces < _MAX_PIECES) & (steps < MAX_STEPS)

    traj0 = jnp.zeros((n + _SAVE_WINDOW, 2))
    mode0 = _mode_of(jnp.zeros(()), z0, motion, model, omega)
    start = (jnp.zeros(()), z0 + 0.0 * omega, jnp.eye(2), mode0, traj0, 0, 0, jnp.asarray(True))
    t, z, m, _, traj, _, _, ok = jax.lax.while_loop(_more, _piece, start)
    return traj[:n], z, m, ok & (t >= TWO_PI)
