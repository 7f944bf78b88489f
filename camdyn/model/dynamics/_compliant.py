"""The compliant follower in the time domain (diffrax): the periodic steady state by shooting.

``m x'' = Fi - (k x + F0) - c x' - F_ext`` with ``Fi = max(0, k_f (s - x) + c_f (w s' - x'))`` while s > x,
integrated in the cam angle (state: x and dx/dtheta in the motion's unit), so segment boundaries are fixed
angles that the step-size controller is told about (``jump_ts``). Where the follower leaves the cam a revolution is
integrated in pieces between the contact's switches (:mod:`._pieces`).
"""

from __future__ import annotations

import math
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike
from jaxtyping import PyTree

from ..._core.errors import NumericalError
from ..._core.jit import cached_jit
from ..._core.units import RPM, THETA_GRID, TWO_PI
from ..follower import FollowerModel
from ..motion import Motion
from ._harmonic import linear_least_force, steady_state
from ._kinematic import kinematic_force, kinematic_force_of
from ._pieces import _ON, _mode_flow, _rev_with_sensitivity
from ._result import Response, residual_vibration, separations_from_mask
from ._solver import MAX_STEPS, SMOOTH_ATOL, SMOOTH_RTOL
from ._train import contact_force, follower_rates, static_position


def vector_field(theta: ArrayLike, y: jax.Array, args: Any) -> jax.Array:
    """d/dtheta of (x, p = dx/dtheta) for the compliant model (``contact`` True) or free flight."""
    motion, model, omega, contact = args
    x, p = y
    s, s1, _, _ = motion(theta)
    fi = jnp.where(contact, contact_force(model, omega, s, s1, x, p, model.scale), 0.0)
    return follower_rates(model, omega, x, p, fi)


def _controller(motion: Motion, rtol: float, atol: float):
    """The step-size controller of a revolution from theta = 0, told the motion's breaks (and their images a
    revolution either side)."""
    import diffrax  # diffrax loads where a program is traced, not where a stored one runs

    breaks = motion.jump_angles()  # data padded with +inf for a program: the controller skips those
    pid = diffrax.PIDController(rtol=rtol, atol=atol)
    if np.size(breaks) == 0:
        return pid
    jumps = jnp.sort((jnp.asarray(breaks)[None, :] + TWO_PI * np.arange(-1, 3)[:, None]).ravel())
    return diffrax.ClipStepSizeController(pid, jump_ts=jumps)


def _contact_force(motion, model, omega, theta, x, p):
    """The interface force (N or N*m) on ``theta`` of the follower at (x, dx/dtheta), motion units."""
    s, s1, _, _ = motion(theta)
    return contact_force(model, omega, s, s1, x, p, model.scale)


_contact_force_jit = cached_jit(_contact_force)


@cached_jit
def _response_arrays(motion, model, omega, theta, x, p):
    """The steady state's interface force, the motion's values (4, n) and the kinematic force on ``theta``: one
    compiled program (each program a fresh process loads costs a cache look-up)."""
    fi = _contact_force(motion, model, omega, theta, x, p)
    return fi, motion(theta), kinematic_force(motion, model, omega, theta)


def _quasi_static(model, omega, sv):
    """The shooting's start (x, dx/dtheta) from the motion's values ``sv`` = (s, s', s'', ...) at theta = 0: the
    follower where the train's compression carries the kinematic force. jax.numpy or numpy alike."""
    fi = kinematic_force_of(model, omega, *(sv[:3] * model.scale))
    return sv[0] - fi / (model.train_stiffness * model.scale), sv[1]


_NEWTON_ITERS = 8
# The condition number of the Newton system (monodromy less identity) past which a step where the follower leaves the
# cam is not taken (a multiplier at 1: the step's length is noise); a plain revolution instead.
_ILL_POSED = 1e8


def _rev_in_contact(motion, model, omega, z0, theta):
    """One revolution from z0 where the orbit is smooth (the follower on the cam all round): Dopri8 at
    :data:`SMOOTH_RTOL` (see :mod:`._solver`). Returns the state on ``theta`` and at 2 pi, the monodromy of the flow on
    the cam, ``exp(J 2 pi)`` in closed form (:func:`_mode_flow`: that flow is affine, so from anywhere one Newton step
    lands on its orbit, even where a revolution from the start leaves the cam), and whether the solve succeeded."""
    import diffrax

    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(vector_field),
        diffrax.Dopri8(),
        t0=0.0,
        t1=TWO_PI,
        dt0=None,
        y0=z0,
        args=(motion, model, omega, True),
        saveat=diffrax.SaveAt(ts=theta, t1=True),
        stepsize_controller=_controller(motion, SMOOTH_RTOL, SMOOTH_ATOL),
        max_steps=MAX_STEPS,
        throw=False,
    )
    ys = sol.ys
    assert ys is not None  # SaveAt(ts=..., t1=True) saves the states
    mono = _mode_flow(model, omega, _ON, TWO_PI)
    return ys[:-1], ys[-1], mono, sol.result == diffrax.RESULTS.successful


_rev_jit = cached_jit(_rev_with_sensitivity)
_rev_smooth_jit = cached_jit(_rev_in_contact)


def store_shooting(motion: Motion, model: FollowerModel, n: int = THETA_GRID) -> None:
    """Compile and store both shooting programs for ``motion``'s and ``model``'s kinds on ``n`` angles where either
    is missing, without loading a stored one: the shooting runs one of them (:func:`_shoot`), and a later case of the
    other kind (a follower that leaves its cam after one that stays on it, or the reverse) then finds its own
    program stored instead of compiling it (about 1.5 s on a CPU). Nothing where the program cache is off."""
    w, z, theta = np.asarray(1.0), np.zeros(2), np.zeros(n)
    _rev_smooth_jit.store(motion, model, w, z, theta)  # pyright: ignore[reportFunctionMemberAccess]
    _rev_jit.store(motion, model, w, z, theta, np.asarray(1.0))  # pyright: ignore[reportFunctionMemberAccess]


_PLAIN_REVS = 60  # after Newton stalls (non-smooth bouncing): revolutions of plain iteration at most
# Revolutions without a better residual after which an orbit already periodic to within PERIODIC_TOL stops while
# Newton may still step (past Newton's iterations, the first revolution within it ends the run): a follower that
# taps the cam many times a revolution has a mismatch floor set by the solver's tolerances (1e-8 to 1e-6 mm for a
# thousand 0.36 deg cycloids), far above the Newton tolerance, and revolutions more only add noise.
_FLOOR_REVS = 2
# Revolutions without a better residual after which a bouncing that is not periodic (a period-2 orbit, chatter)
# stops: its best revolution is then the answer, and each revolution of a dense program costs seconds.
_STALL_REVS = 10
# Plain revolutions whose mismatch shrinks by at least this factor each, this many in a row, settle towards a stable
# orbit (a bouncing transient that dies out by 0.8 a revolution took 66 revolutions of 47 ms): the iteration jumps
# to where that geometric series ends (Aitken's extrapolation along the last step; Newton's monodromy is no guide
# across the contact's switches); a jump that does not halve the mismatch goes back to where it left.
_SETTLING, _SETTLING_REVS = 0.9, 3
# Where the follower leaves the cam, revolutions run at the step-size controller's tolerances times _LOOSE until one
# misses the orbit by no more than _TIGHTEN periodic tolerances (periodic_tol; from then on all at the full ones): they
# only steer the iteration (the lecture at 600 rpm: 5e-5 mm off the full tolerances' trajectory, its end 2.5e-4 off,
# where the mismatch is above 2e-2 mm), in under half the steps (the thousand cycloids: 14,500 -> 6,000 a revolution,
# 0.13 -> 0.075 s). Only revolutions at the full tolerances are judged periodic and returned.
_LOOSE, _TIGHTEN = 1e3, 1e3
_LANDED = 0.5  # a jump that lands cuts the mismatch by this factor at least (the series' dominant term gone)
_ALIGNED = 0.999  # the cosine between the last two steps above which they are one direction shrinking
# Revolutions more at most after which a bouncing is not of period two, and the revolutions in which its
# two-revolution mismatch must halve (a bouncing that settles into period two: the lecture cam at 600 rpm takes 0.72 a
# revolution; where it does not halve, the bouncing is not settling into it and the search ends)
_PERIOD2_REVS, _PERIOD2_CHECK = 24, 4
PERIODIC_TOL = 1e-6  # mismatch, times the largest lift (or 1, motion units), above which the orbit is not periodic


# The train's vibrations a revolution (its contact mode over the cam speed) above which the time integration is not
# run where the frequency domain's steady state stays on the cam and the ringing it leaves out (:func:`_ringing`) is
# within the periodic tolerance: Dopri8 takes about 60 steps a vibration, so 2000 (the lecture below 6.8 rpm,
# ringing 5.6e-6 mm against 2e-5 mm) is 1.7 s of shooting on a CPU; a check at 1 rpm took 7.8 s, at 0.001 rpm 12.5 s
# (the integration ran out of steps first). The shipped cases run at 23 to 503.
_SLOW_RATIO = 2000.0


def _contact_mode(model: FollowerModel) -> float:
    """The angular frequency (rad/s) of the follower's vibration on the cam: sqrt((k + k_f) / m)."""
    return math.sqrt((float(model.stiffness) + float(model.train_stiffness)) / float(model.mass))


def _integration_failure(model: FollowerModel, omega: float) -> str:
    """Why the time integration of the compliant model can fail, in the case file's terms."""
    ratio = _contact_mode(model) / omega  # contact-mode vibration periods per revolution
    what = "the compliant-model integration failed (solver out of steps or NaN)"
    if ratio > 1e3:
        hz = _contact_mode(model) / TWO_PI
        return (
            f"{what}: the follower train vibrates at {hz:.4g} Hz, {ratio:.3g} times per cam revolution; "
            "a slower time integration cannot resolve it: check dynamics.train_stiffness, dynamics.mass and the speed"
        )
    return (
        f"{what}: check that dynamics.mass, the spring and the train stiffness are in the units the case file uses "
        "(kg, N/mm)"
    )


def periodic_orbit(motion: Motion, model: FollowerModel, omega: float, theta: ArrayLike) -> tuple[PyTree, float]:
    """Periodic steady state of the compliant model at cam speed ``omega`` (rad/s) by shooting.

    Newton on ``Phi(z0) - z0 = 0``, the one-revolution flow Phi by one diffrax solve and its Jacobian (the
    monodromy matrix) in closed form within each of the follower's modes (:func:`_mode_flow`). While the follower
    stays in contact the flow is affine and Newton converges in one step. Where the follower leaves the cam the
    monodromy takes each switch's saltation (:mod:`._pieces`), and Newton steps only where the flow
    contracts (no Floquet multiplier outside the unit circle: it would home in on a repelling orbit as readily,
    :func:`_unstable`) and the system is not near-singular (:data:`_ILL_POSED`); a step that does not reduce the
    residual goes back to where it left (the next one half as long), and an orbit reached that repels all the same
    is set aside for plain revolutions from the first one's end. Elsewhere the iteration takes plain revolutions
    (the transient dies out revolution by revolution; where it dies out
    by a steady ratio, the iteration jumps to the end of that series, :func:`_rest_of_series`). The iteration
    stops at a residual of 1e-10 (relative), at the first revolution within :func:`periodic_tol` where the
    frequency domain's steady state leaves the cam or past Newton's ``_NEWTON_ITERS``, or once the best residual is
    within it and ``_FLOOR_REVS`` revolutions more have not lowered it (the solver's noise floor).
    Where the follower leaves the cam, revolutions far from the orbit (the last mismatch above ``_TIGHTEN`` periodic
    tolerances) run at loosened tolerances (``_LOOSE``): they only steer; none is judged periodic or returned (the
    least-mismatch start of a run that ends loose is run again at the full tolerances).
    Either way, ``_STALL_REVS`` revolutions without a lower residual end it; a bouncing that is not periodic may
    still repeat every other revolution (:func:`_period_two`: the trajectory is then the one of the two with the
    higher peak contact force, the residual the two revolutions' |Phi(Phi(z0)) - z0|).
    Returns the trajectory (x, dx/dtheta; motion units) on ``theta`` (n, 2) of the best iterate and its residual
    |Phi(z0) - z0|; NumericalError if a revolution does not integrate.
    """
    traj, residual, _, _, _ = _shoot(motion, model, omega, theta)
    return traj, residual


def _shoot(motion: Motion, model: FollowerModel, omega: float, theta):
    """:func:`periodic_orbit`, which revolution (1-based) it returns of how many it integrated, and the steady
    state's period in revolutions (2: a bouncing that repeats every other revolution, :func:`_period_two`; None where
    no revolution came back within :func:`periodic_tol`)."""
    # the start and the Newton bookkeeping are numpy: eager jax ops would each compile a tiny program on first use
    w = np.asarray(omega, dtype=float)
    z = np.array(_quasi_static(jax.device_get(model), omega, motion.host(np.zeros(()))))
    tol = 1e-10 * (1.0 + float(np.max(np.abs(z))))
    floor = periodic_tol(motion.host(theta)[0])
    # where the frequency domain's steady state stays on the cam it is a periodic orbit of the model, and a smooth
    # one: the higher-order solver's (either integrates any orbit: the choice is one of speed)
    smooth = linear_least_force(motion, model, omega) > 0.0
    program = _rev_smooth_jit if smooth else _rev_jit

    def revolution(z: np.ndarray, loose: bool = False) -> tuple[Any, np.ndarray, np.ndarray]:
        """One revolution from ``z``: its trajectory, its end and the monodromy matrix (numpy); ``loose``: at the
        tolerances times :data:`_LOOSE` (where the follower leaves the cam)."""
        loosen = () if smooth else (np.asarray(_LOOSE if loose else 1.0),)
        traj, phi, mono, ok = program(motion, model, w, z, theta, *loosen)
        phi, mono = np.asarray(phi), np.asarray(mono)
        if not bool(ok) or not np.all(np.isfinite(phi)):
            raise NumericalError(f"dynamics at {omega / RPM:.4g} rpm", _integration_failure(model, omega))
        return traj, phi, mono

    best_traj, best_r, best_i, best_mono, r_prev = None, math.inf, 0, None, math.inf
    newton_ok, first_end = True, None  # Newton's steps allowed; the first revolution's end (a restart's start)
    steps: list[np.ndarray] = []  # each revolution's phi - z since the last Newton step or jump
    left = None  # (where a settling jump or a Newton step left from: the plain iteration's next start, its mismatch,
    # the factor by which the step must cut it)
    damping = 1.0  # the share of a Newton step taken where the follower leaves the cam: halved by each that missed
    starts: list[np.ndarray] = []  # the plain revolutions' run: each one's start, and the last one's end
    trajs: list[Any] = []  # and each one's trajectory
    # far from the orbit a revolution only steers the iteration: at looser tolerances, in under half the steps
    last_r, run_loose, best_loose, best_start = math.inf, not smooth, False, z
    for i in range(_NEWTON_ITERS + _PLAIN_REVS):
        loose = run_loose and last_r > _TIGHTEN * floor  # tightened once, for good: no steering back and forth
        traj, phi, mono = revolution(z, loose)
        if not (starts and starts[-1] is z) or loose != run_loose:
            # a Newton step, a jump or the way back, or the tolerances tightened: a new run of plain revolutions
            starts, trajs = [z], []
        run_loose = loose
        starts.append(phi)
        trajs.append(traj)
        r = last_r = float(np.linalg.norm(phi - z))
        first_end = phi if first_end is None else first_end
        if r < best_r or (best_loose and not loose):  # a revolution at the tolerances before one that steered
            best_traj, best_r, best_i, best_mono, best_loose, best_start = traj, r, i, mono, loose, z
        # a revolution within the periodic tolerance is periodic by camdyn's own measure where the follower leaves the
        # cam (the switches' located angles set a noise floor far above Newton's tolerance) and past Newton's
        # iterations; on a smooth orbit Newton, converging quadratically, steps on to its own tolerance
        at_floor = best_r <= floor and (not smooth or i >= _NEWTON_ITERS or i - best_i >= _FLOOR_REVS)
        settled = not best_loose and (best_r <= tol or at_floor)  # a loose revolution's mismatch is not judged
        unstable = not smooth and newton_ok and best_mono is not None and _unstable(best_mono)
        if settled and unstable and i + 1 < _NEWTON_ITERS + _PLAIN_REVS:
            # Newton's steps found a periodic orbit the follower does not settle into (its bouncing grows away from
            # it): plain revolutions from the first one's end instead, which settle only where it does
            newton_ok, z, r_prev, left, steps = False, first_end, math.inf, None, []
            best_traj, best_r, best_i, best_loose = None, math.inf, i, False
            continue
        if settled or i - best_i >= _STALL_REVS:
            break
        if left is not None and r > left[2] * left[1]:  # the jump or Newton step missed: on from where it left
            z, r_prev, left = left[0], left[1], None
            damping *= 0.5
            continue
        if left is not None and left[2] == 1.0:  # a Newton step that cut the mismatch: the next one whole again
            damping = min(1.0, 2.0 * damping)
        steps.append(phi - z)
        rest = _rest_of_series(steps) if i >= _NEWTON_ITERS or not newton_ok else None
        # where the follower leaves the cam, Newton only where the flow contracts: it would home in on a repelling orbit
        # as readily as on an attracting one (where the bouncing settles, which plain revolutions reach anyway)
        newton = newton_ok and i < _NEWTON_ITERS and r <= r_prev
        newton = newton and (smooth or (np.linalg.cond(mono - np.eye(2)) < _ILL_POSED and not _unstable(mono)))
        left = None if rest is None else (phi, r, _LANDED)
        if newton or rest is not None:
            steps = []
        if newton:
            step = np.linalg.solve(mono - np.eye(2), phi - z)
            if not smooth:  # the map is not affine: a step that does not cut the mismatch is not kept
                step, left = damping * step, (phi, r, 1.0)
            z = z - step
        else:
            z = phi if rest is None else phi + rest
        r_prev = r
    assert best_traj is not None  # every revolution is finite (else NumericalError), so the first one is kept
    revs = i + 1
    if best_loose:  # the best revolution steered at loose tolerances: it again at those that judge it
        best_traj, phi, _ = revolution(best_start)
        best_r, best_i, revs = float(np.linalg.norm(phi - best_start)), revs, revs + 1
    if best_r > floor and not smooth:  # not periodic: perhaps every other revolution

        def peak_force(traj: Any) -> float:  # the response's program: a failing case's check compiles nothing more
            return float(np.max(np.asarray(_response_arrays(motion, model, w, theta, *np.asarray(traj).T)[0])))

        two, more = _period_two(revolution, starts, trajs, floor, peak_force)
        if two is not None:
            traj, r2, which = two
            return traj, r2, revs + which, revs + more, 2
        revs += more
    return best_traj, best_r, best_i + 1, revs, 1 if best_r <= floor else None


def _unstable(mono: np.ndarray) -> bool:
    """Whether the periodic orbit of monodromy ``mono`` repels a follower (a Floquet multiplier outside the unit
    circle): Newton converges to such an orbit as readily as to a stable one, but no bouncing settles into it."""
    return bool(np.max(np.abs(np.linalg.eigvals(mono))) > 1.0)


def _period_two(revolution, starts, trajs, floor: float, peak_force):
    """A bouncing that repeats every other revolution, from the plain revolutions ``starts`` (each the one before
    run one revolution, ``trajs`` their trajectories) and on by ``revolution``: the state two revolutions on returns to
    within ``floor``, directly or once the two-revolution steps settle by a steady ratio and
    :func:`_rest_of_series` sums them. Returns the trajectory of the one of the two revolutions with the higher
    ``peak_force`` (of a trajectory: the contact force's peak, a landing's where the follower bounces), the
    two-revolution mismatch and that revolution's count among those run here (0: the last of ``trajs``), or None
    where the mismatch does not halve in :data:`_PERIOD2_CHECK` revolutions or :data:`_PERIOD2_REVS` run out; and
    how many revolutions ran here."""
    xs, ts = list(starts), list(trajs)
    mark = math.inf  # the two-revolution mismatch (the larger of the last two) at the last checkpoint
    for k in range(_PERIOD2_REVS + 1):
        if len(xs) >= 3:
            r2 = float(np.linalg.norm(xs[-1] - xs[-3]))
            if r2 <= floor:
                higher = int(peak_force(ts[-1]) >= peak_force(ts[-2]))
                return (ts[-2 + higher], r2, k - 1 + higher), k
        if k % _PERIOD2_CHECK == 0 and len(xs) >= 4:  # settling into period two halves the mismatch in that time
            now = max(float(np.linalg.norm(xs[-1] - xs[-3])), float(np.linalg.norm(xs[-2] - xs[-4])))
            if now > 0.5 * mark:
                return None, k
            mark = now
        if k == _PERIOD2_REVS:
            return None, k
        twos = [xs[j] - xs[j - 2] for j in range(len(xs) - 1, 1, -2)][::-1]  # of the last one's parity
        rest = _rest_of_series(twos) if len(twos) > _SETTLING_REVS else None
        if rest is not None:
            xs, ts = [xs[-1] + rest], []
        traj, phi, _ = revolution(xs[-1])
        xs.append(phi)
        ts.append(traj)
    return None, _PERIOD2_REVS


def _rest_of_series(steps: list[np.ndarray]) -> np.ndarray | None:
    """How far past the last revolution's end plain revolutions settle, from their steps ``phi - z``, where the
    last :data:`_SETTLING_REVS` each shrank by :data:`_SETTLING` or more along one line (:data:`_ALIGNED`): the rest
    of the geometric series of the last step's ratio to the one before; None where they do not settle so."""
    last = [float(np.linalg.norm(d)) for d in steps[-_SETTLING_REVS - 1 :]]
    if len(last) <= _SETTLING_REVS or any(b > _SETTLING * a for a, b in zip(last[:-1], last[1:], strict=True)):
        return None
    before, step = steps[-2], steps[-1]
    ratio = float(np.dot(step, before) / np.dot(before, before))  # negative: a period-2 bouncing that dies out
    if abs(ratio) * last[-2] < _ALIGNED * last[-1]:  # the steps turn (a spiral): no one ratio to sum
        return None
    return step * (ratio / (1.0 - ratio))


def periodic_tol(lift: float) -> float:
    """The revolution-to-revolution mismatch (motion units) up to which a steady state counts as periodic:
    ``PERIODIC_TOL`` times the largest ``lift`` (the cam's, motion units), at least 1 unit."""
    return PERIODIC_TOL * max(1.0, float(np.max(np.abs(lift))))


def min_contact_force(motion: Motion, model: FollowerModel, omega: float, n: int = THETA_GRID) -> float:
    """Least steady-state interface force (N, or N*m for an arm) of the compliant model at ``omega`` (rad/s) by
    time-domain shooting (:func:`periodic_orbit`) on ``n`` angles; NaN where the integration fails. The
    reference for :func:`camdyn.model.dynamics.linear_min_force`."""
    theta = jnp.arange(n) * (TWO_PI / n)
    try:
        traj, _ = periodic_orbit(motion, model, float(omega), theta)
    except NumericalError:
        return math.nan
    w = jnp.asarray(omega, dtype=float)
    return float(jnp.min(_contact_force_jit(motion, model, w, theta, traj[:, 0], traj[:, 1])))


@cached_jit
def _in_contact(motion: Motion, model: FollowerModel, omega, n: int):
    """The frequency domain's steady state in contact on the response grid: (x, dx/dtheta), motion units."""
    s = motion(jnp.arange(n) * (TWO_PI / n))[0]
    return steady_state(jnp.fft.rfft(s), omega, model, model.stiffness, model.damping, n, unit=model.scale)


def _ringing(motion: Motion, ratio: float) -> float:
    """The largest free vibration (motion units) the cam's jumps leave in a follower train that vibrates ``ratio``
    times a revolution: a step of the cam's velocity rings with ``|ds'| / ratio``, of its acceleration with
    ``|ds''| / ratio**2`` (the quasi-static lag of the train, m a / (k + k_f), jumps). The frequency domain on
    ``THETA_GRID`` angles leaves it out where the mode is past the grid's harmonics."""
    jumps = np.asarray(motion.jump_angles(), dtype=float)
    jumps = jumps[np.isfinite(jumps)]
    if not jumps.size:
        return 0.0
    step = np.abs(motion.host((jumps + 1e-9) % TWO_PI) - motion.host((jumps - 1e-9) % TWO_PI))
    return float(max(np.max(step[1]) / ratio, np.max(step[2]) / (ratio * ratio)))  # a float's ** overflows, * gives inf


def _on_cam(
    motion: Motion, model: FollowerModel, w: np.ndarray, theta: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """The frequency domain's steady state (x, dx/dtheta on ``theta``, numpy) where its interface force stays
    positive all round: then it is the compliant model's periodic orbit but for the ringing of the train's mode past
    the grid's harmonics (:func:`_ringing`); else None."""
    x, p = (np.asarray(a) for a in _in_contact(motion, model, w, theta.size))
    return (x, p) if float(np.min(_contact_force_jit(motion, model, w, theta, x, p))) > 0.0 else None


def compliant_response(motion: Motion, model: FollowerModel, omega: float, n: int = THETA_GRID) -> Response:
    """Periodic steady state of the compliant follower at cam speed omega (rad/s)."""
    # numpy between the compiled programs: an eager jax op compiles a program of its own
    theta = np.arange(n) * (TWO_PI / n)
    w = np.asarray(omega, dtype=float)
    notes = []
    # Far below resonance (a slow cam) the time integration must step through every vibration of the train, thousands
    # to millions a revolution; the frequency domain's steady state is the answer where it stays on the cam and the
    # ringing it misses is within the periodic tolerance (and, past the integration's reach, wherever it stays on).
    ratio = _contact_mode(model) / omega
    ring = _ringing(motion, ratio) if ratio > _SLOW_RATIO else None
    slow = ring is not None and ring <= periodic_tol(motion.host(theta)[0])
    on_cam = _on_cam(motion, model, w, theta) if slow else None
    if on_cam is None:
        try:
            traj, residual, best_rev, revs, period = _shoot(motion, model, float(omega), theta)
            x, p = np.asarray(traj).T
        except NumericalError as err:
            on_cam = _on_cam(motion, model, w, theta)
            if on_cam is None:
                raise err from None
    if on_cam is not None:
        (x, p), residual, best_rev, revs, period = on_cam, 0.0, 0, 0, 1
        ring = _ringing(motion, ratio) if ring is None else ring  # past the integration's reach: not yet known
        notes.append(
            f"at {omega / RPM:.4g} rpm the steady state comes from the frequency domain (in contact): the follower "
            f"train vibrates {ratio:.3g} times a revolution, more than the time integration resolves; the ringing of "
            f"that mode where the cam's velocity or acceleration jumps, at most {ring:.2g} {motion.unit}, is left out"
        )
    fi, vals, kin = (np.asarray(a) for a in _response_arrays(motion, model, w, theta, x, p))
    theta_deg = np.degrees(theta)
    flying = fi <= 0.0
    # contact-mode period, in cam degrees: bounces closer than this belong to one separation
    merge_deg = math.degrees(omega * TWO_PI / _contact_mode(model))
    rel = omega * model.scale * (p - vals[1])
    seps = separations_from_mask(theta_deg, flying, x - vals[0], rel, merge_deg)
    # in numpy on the host, like the rest of the response (XLA's division differs from numpy's in the last bit)
    x_static = static_position(jax.device_get(model), vals[0], model.scale)
    resid, resid_deg = residual_vibration(motion, theta_deg, np.asarray(x - x_static))
    warnings = notes
    if period == 2:
        warnings.append(
            f"at {omega / RPM:.1f} rpm the follower's bouncing repeats every other revolution (after two it is back "
            f"within the periodic tolerance, {periodic_tol(vals[0]):.2g} {motion.unit}), not every one: results are "
            f"for revolution {best_rev} of the {revs} integrated from the quasi-static start, the one of the two with "
            "the higher peak contact force"
        )
    elif period is None:
        warnings.append(
            f"no exactly periodic steady state at {omega / RPM:.1f} rpm (revolution-to-revolution mismatch "
            f"{float(residual):.2g} {motion.unit}): the follower's bouncing is not periodic; results are for "
            f"revolution {best_rev} of the {revs} integrated from the quasi-static start (the least mismatch)"
        )
    return Response(
        "compliant",
        float(omega),
        theta_deg,
        vals[0],
        x,
        p,
        fi,
        kin,
        tuple(seps),
        resid,
        float(residual),
        tuple(warnings),
        resid_deg,
        merge_deg,
        "time" if on_cam is None else "frequency",
        period,
    )
