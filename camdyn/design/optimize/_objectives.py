"""The three objectives of ``camdyn optimize``, each a sequence of linear programs (:mod:`._slp`):

* ``jump-speed``: the largest speed W up to which the least contact force keeps its margin (``Rows.margin``
  and ``min_contact_force``) at every speed, by bisection on W (a speed set up to W, refined where a finer
  scan finds a lower force);
* ``vibration``: the least residual vibration in the dwells over a speed band, while holding there;
* ``spring-force``: the least peak spring force (preload and rate free) that holds to ``speed_margin`` x speed.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import InputError, NumericalError
from ..._core.progress import Progress, counter
from ..._core.units import RPM
from ...model.dynamics import static_position, steady_state
from ..spring import min_preload
from ._rows import FINE, Rows, speed_slots, split_preload
from ._slp import Bound, Step, maximize_least, with_jacobian

RADIUS = 0.2  # first trust region of a control point (normalized lift)
BETTER = 1e-3  # an answer must beat the input on its objective by this share to be written
CLEAR = 1.002  # hold a little past the margin the check asks for: it reads the jump speed on its own grid
_TOL_RPM = 1.0  # the search stops when the jump speed is known to 1 rpm
_CARRIED = 4  # an earlier trial's dips held from the start: the set's 23 speeds, these and 5 found fill SPEED_SLOTS


def _speed_set(w: float) -> np.ndarray:
    return w * np.r_[np.linspace(0.05, 0.9, 18), np.linspace(0.92, 1.0, 5)]


def least_slack(rows: Rows, z: ArrayLike, w_max: float, preload: ArrayLike | None = None) -> tuple[float, float]:
    """Least contact force over its margin (N; N*m for an arm, :meth:`Rows.slack`) over a fine scan of speeds up
    to ``w_max`` (rad/s) and every grid angle, and the speed where it occurs (rad/s); ``preload`` (SI) overrides
    the case's."""
    f = np.asarray(rows.least_on_scan(jnp.asarray(z), w_max, preload))
    i = int(np.argmin(f))
    return float(f[i]), float(w_max * (i + 1) / FINE)


def hold_to(
    rows: Rows, w: float, z0: np.ndarray, dips: tuple[float, ...] = (), seed: Bound | None = None
) -> tuple[Step, float, tuple[float, ...]]:
    """Control points that maximize the least slack (:meth:`Rows.slack`) at every speed up to ``w`` (rad/s) within
    the geometry limits, that least slack over the fine scan, and the dips: the speeds (fractions of ``w``) the
    programs held beyond their own set. The programs hold a set of speeds; a speed of the scan where the slack dips
    below both zero and the programs' answer joins the set. ``dips``: an earlier call's, held from the start (a
    search's speeds near its end differ by a fraction of a percent, and so do the dips: each found again cost a
    round of programs). ``seed``: the rows that bound an earlier call's last program (:attr:`Step.bound`; the
    oscillating case's search 6.8 -> 5.7 s with the troughs' rows of :func:`maximize_least`)."""
    dipped = tuple(dips[-_CARRIED:])
    speeds = np.r_[_speed_set(w), w * np.asarray(dipped, dtype=float)]
    scale = rows.scale
    step, radius = Step(z0, -math.inf, math.inf, 0, seed), RADIUS
    for _ in range(6):
        step = maximize_least(
            rows.force_values(jnp.asarray(speed_slots(speeds))),
            rows.geometry_values,
            step.x,
            radius=radius,
            scale=scale,
            seed=step.bound,
            block=rows.sampled.size,  # the slack comes a speed at a time
        )
        full, at = least_slack(rows, step.x, w)
        if full >= min(0.0, step.value - 1e-3 * scale) or step.value < 0.0:
            break  # held (or cannot be: the programs' own speeds already fail)
        speeds, dipped = np.r_[speeds, at], (*dipped, at / w)
        radius = 0.25 * RADIUS
    return step, full, dipped


def margin_speed_of_fit(rows: Rows, w_first: float) -> float:
    """The last speed (rad/s) of the rows' fine scan (:data:`FINE` speeds) at which the shape space's fit of the
    input still holds its margin, looking up to ``w_first``, then 2, 4 and 8 times it; NaN where it holds at every
    speed scanned or at none. The search's start while the input's own check (whose margin speed it approximates to
    a scan step) is still running."""
    z, w_top = jnp.asarray(rows.space.z0), float(w_first)
    for _ in range(4):
        below = np.nonzero(np.asarray(rows.least_on_scan(z, w_top)) < 0.0)[0]
        if below.size:
            return w_top * below[0] / FINE if below[0] > 0 else math.nan
        w_top *= 2.0
    return math.nan


def jump_speed(rows: Rows, w0: float, progress: Progress | None = None) -> tuple[np.ndarray, float]:
    """The reshaped control points and the largest speed (rad/s) up to which they hold, from ``w0``, where the input's
    force first falls to the limit (:func:`margin_speed_of_fit`, or its check's): trial speeds 1.3 x up from it
    until one fails, then bisection to :data:`_TOL_RPM`. Each trial holds from the start the speeds where the last
    ones' answers dipped (:func:`hold_to`): the lecture's search 6.4 -> 5.5 s, the oscillating case's 10.1 -> 7.1 s.
    Trial speeds up along the line of the last two held speeds' slacks (6.2 s on the oscillating case, 9.4 s on the
    lecture) and regula falsi in the bracket (more trials) were tried and dropped."""
    z = rows.space.z0
    tick = counter(progress, "optimize", 12)
    tick(0)  # the phase starts with the first trial, not the first of the twelve
    lo, hi = 0.95 * w0, None
    step, full, dips = hold_to(rows, lo, z)
    if full < 0.0 or step.violation > 1e-6:
        lo = 0.5 * w0  # the fitted start may sit just off the case's own margin: start lower
        step, full, dips = hold_to(rows, lo, z, dips, step.bound)
    z = step.x
    w = 1.3 * lo
    for _ in range(12):
        tick()
        step, full, dips = hold_to(rows, w, z, dips, step.bound)
        if full >= 0.0 and step.violation <= 1e-6:
            lo, z = w, step.x
        else:
            hi = w
        if hi is not None and (hi - lo) / RPM < _TOL_RPM:
            break
        w = 1.3 * lo if hi is None else 0.5 * (lo + hi)
    tick.finish()
    return z, lo


def _band(speed: float) -> np.ndarray:
    return speed * np.linspace(0.9, 1.1, 9)


def _held(
    rows: Rows, objective, x0: np.ndarray, w: float, *, preload_free: bool = False, lower=None, radius=RADIUS
) -> Step:
    """Maximize the least of ``objective(x)`` within the geometry limits, holding the contact force at the limit at
    every speed up to ``w`` (rad/s): the programs' speed set grows where a fine scan finds the force below it.
    ``x`` is the control points, and the preload (SI) after them where ``preload_free``."""
    scale = rows.scale
    objective_jac = with_jacobian(objective)

    def limits(x: np.ndarray, slack: Callable, cushion: float) -> tuple[np.ndarray, np.ndarray]:
        x = np.asarray(x, dtype=float)
        g, jac_g = rows.geometry_values(split_preload(x, preload_free)[0])
        if preload_free:  # the geometry does not move with the preload
            jac_g = np.c_[jac_g, np.zeros(g.size)]
        v, jac_v = slack(x)
        return np.r_[g, (cushion - v) / scale], np.r_[jac_g, -jac_v / scale]

    # a cushion over the limit: an optimum holds many speeds at once right at it, where the check's own grid
    # would read a last-digit dip as the jump
    speeds, step, cushion = _speed_set(w), Step(x0, -math.inf, math.inf, 0), 1e-2 * scale
    for _ in range(8):
        slack = rows.force_values(jnp.asarray(speed_slots(speeds)), x0, preload_free)
        step = maximize_least(
            objective_jac,
            lambda x, slack=slack, cushion=cushion: limits(x, slack, cushion),
            step.x,
            radius=radius,
            scale=scale,
            lower=lower,
        )
        z, preload = split_preload(step.x, preload_free)
        full, at = least_slack(rows, z, w, preload)
        if full >= 0.0:
            break
        if np.min(np.abs(speeds - at)) > 1e-9 * w:
            speeds = np.r_[speeds, at]  # a dip between the programs' speeds: hold that speed too
        else:  # a dip between the programs' angles: hold the sampled ones higher by what it missed
            cushion += 1.5 * (-full)
    return step


def vibration(rows: Rows, omega: float, band: bool = True) -> np.ndarray:
    """Control points with the least residual vibration (|x - x_static| in the dwells, motion unit) over the speeds
    ``0.9..1.1 x omega`` (``band`` False: at ``omega`` alone, Dudley's polydyne aim), holding the contact force
    at the limit up to ``speed_margin`` x ``omega``."""
    case, space = rows.case, rows.space
    if case.model.rigid:
        raise InputError(
            "--objective", "vibration: a rigid follower does not vibrate in contact (give [dynamics] train_stiffness)"
        )
    dwell = np.asarray(np.abs(space.matrix[0]).sum(axis=1) == 0.0)
    idx = np.nonzero(dwell)[0][::4]
    speeds = _band(omega) if band else np.array([omega])
    m = case.model

    def deviation(z: jax.Array) -> jax.Array:
        s = space.values(z)[0] * m.scale
        spec = jnp.fft.rfft(s)
        static = static_position(m, s)
        x = jnp.stack([steady_state(spec, w, m, m.stiffness, m.damping, s.shape[0])[0] for w in speeds])
        dev = (x - static)[:, idx].ravel() / m.scale
        return jnp.concatenate([-dev, dev])  # its least is -max |x - x_static|

    return _held(rows, deviation, space.z0, case.limits.speed_margin * omega * CLEAR).x


def peak_spring_force_floor(rows: Rows, rates: np.ndarray) -> np.ndarray:
    """The least peak spring force (N; N*m for an arm) that any motion of the shape space can have at each rate
    (SI) while it keeps the margin in a steady state. Over a revolution inertia and damping average out, through a
    compliant train too, so the least interface force is at most its mean, ``k <s> + F0 + F_ext`` (less in a
    compliant train); the peak is ``F0 + k s_max``. Hence ``peak >= margin - F_ext + k (s_max - <s>_max)``, with
    ``<s>_max`` the mean lift when every reshaped angle sits at ``s_max`` (a reshaped segment stays within its
    lifts), and ``peak >= k s_max + seat`` (the least preload the spring may have)."""
    case, space = rows.case, rows.space
    s0 = space.offset[0] + space.matrix[0] @ space.z0
    s_max = float(np.max(s0)) * case.model.scale
    moving = np.any(space.matrix[0] != 0.0, axis=-1)
    mean_max = float(np.mean(np.where(moving, np.max(s0), space.offset[0]))) * case.model.scale
    seat = max(0.0, min_preload(case))
    by_mean = rows.margin - float(case.model.external) + rates * (s_max - mean_max)
    return np.maximum(by_mean, rates * s_max + seat)


def spring_force(rows: Rows, w: float, rates: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Control points, spring rate (SI) and preload (SI) of the least peak spring force that holds at every speed
    up to ``w`` (rad/s): linear programs in the control points and the preload, per trial rate."""
    case, space = rows.case, rows.space
    lift = float(np.max(space.offset[0] + space.matrix[0] @ space.z0)) * case.model.scale
    seat = max(0.0, min_preload(case))  # [limits] min_preload: the seat load a valve or machine spring must keep
    lower = np.r_[np.full(space.n_free, -np.inf), seat]
    best = None
    for k in rates:
        r = dataclasses.replace(rows, case=dataclasses.replace(case, model=case.model.with_spring(k)))
        f0 = max(float(case.model.preload), seat)
        radius = np.r_[np.full(space.n_free, RADIUS), max(0.5 * f0, 1.0)]  # the preload moves in newtons
        step = _held(r, lambda x: -x[-1:], np.r_[space.z0, f0], w, preload_free=True, lower=lower, radius=radius)
        peak = k * lift + step.x[-1]
        held = least_slack(r, step.x[:-1], w, step.x[-1])[0] >= 0.0
        if step.violation <= 1e-6 and held and (best is None or peak < best[0]):
            best = (peak, step.x[:-1], float(k), float(step.x[-1]))
    if best is None:
        raise NumericalError("spring-force", "no spring rate tried holds within the geometry limits")
    return best[1], best[2], best[3]
