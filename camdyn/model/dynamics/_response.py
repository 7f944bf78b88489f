"""The steady state with the model a follower calls for, and the dynamic jump speed."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..._core.errors import NumericalError
from ..._core.units import JUMP_SEARCH_FACTOR, RPM, THETA_GRID
from ..follower import FollowerModel
from ..motion import Motion
from ._compliant import compliant_response, store_shooting
from ._harmonic import BISECT_POINTS, SPEED_PIECE, linear_min_force
from ._kinematic import kinematic_jump_speed
from ._result import Response
from ._rigid import rigid_response, store_flight
from ._root import itp_zero


def response(motion: Motion, model: FollowerModel, omega: float, n: int = THETA_GRID) -> Response:
    """Steady-state response with the model the parameters call for (rigid if train_stiffness is inf)."""
    return rigid_response(motion, model, omega, n) if model.rigid else compliant_response(motion, model, omega, n)


def store_response(motion: Motion, model: FollowerModel, n: int = THETA_GRID) -> None:
    """Compile and store every program :func:`response` may run for this follower kind, where one is missing,
    without loading the stored ones: whether the follower stays on its cam or leaves it, a later case of the same
    kind finds its programs stored (issue 23: a new case as fast as a stored one). ``check`` runs it on the side."""
    (store_flight if model.rigid else store_shooting)(motion, model, n)


def dynamic_jump_speed(
    motion: Motion, model: FollowerModel, *, w_max: float, tol_rpm: float = 0.1, grid: int = 2000
) -> float:
    """Least cam speed (rad/s) at which the steady-state least interface force reaches 0; inf if none up to w_max.

    Rigid followers: the kinematic jump speed (closed form). Compliant: below the jump speed the follower
    stays in contact, where the model is linear, so the scan over ``grid`` speeds in (0, w_max] and the
    bisection of the first sign change use the exact frequency-domain steady state (:func:`linear_min_force`);
    the diffrax time-domain model is its reference (tests, and ``check`` compares both at the case speed).
    """
    if model.rigid:
        return kinematic_jump_speed(motion, model)[0]
    least = lambda ws: np.asarray(linear_min_force(motion, model, ws))  # noqa: E731
    return first_zero_speed(
        least,
        w_max,
        grid=grid,
        width_rpm=tol_rpm / 10,
        points=BISECT_POINTS,
        where="jump-speed search",
        chunk=SPEED_PIECE,  # a program's most speeds: four of its lax.map batches of 64
    )


def scan_speeds(w_max: float, grid: int) -> np.ndarray:
    """The jump-speed search's scan (:func:`first_zero_speed`): ``grid`` equal steps up to ``w_max`` (rad/s)."""
    return np.linspace(w_max / grid, w_max, grid)


def first_zero_speed(
    least_force: Callable[[np.ndarray], np.ndarray],
    w_max: float,
    *,
    grid: int,
    width_rpm: float,
    points: int,
    where: str,
    chunk: int | None = None,
    signed: bool = False,
) -> float:
    """The jump-speed search, for every steady-state model: the least speed (rad/s) in (0, ``w_max``] at which
    ``least_force(omegas)`` (the least interface force at each speed, an array) reaches 0, inf if none. A scan
    of ``grid`` speeds, then ``points`` speeds at a time (1: bisection) into the first sign change until it is
    ``width_rpm`` wide; ``where`` names the model in a numerical error.

    ``chunk``: the scan runs ``chunk`` speeds at a time from the slowest (the last chunk padded with its top speed:
    one array shape) and stops at the first chunk that reaches 0; the same answer as the whole scan, which
    computes every speed above the jump too (the jump is usually in the first quarter of the grid).

    ``signed``: the force is continuous through its zero (a force the model would need, negative past the jump,
    not one clipped at 0), so one speed at a time refines it by interpolation (:func:`_itp`): a few speeds where
    the force is smooth, never more than one more than bisection's."""
    speeds = scan_speeds(w_max, grid)
    step = chunk or grid
    before = math.nan  # the force at the scan's speed below the chunk
    for start in range(0, grid, step):
        part = speeds[start : start + step]
        fmin = np.asarray(least_force(np.pad(part, (0, step - part.size), mode="edge")))[: part.size]
        if not np.all(np.isfinite(fmin)):
            bad = part[~np.isfinite(fmin)][0]
            raise NumericalError(f"{where} at {bad / RPM:.1f} rpm", "the steady-state force is not finite")
        hit = np.nonzero(fmin <= 0.0)[0]
        if hit.size:
            break
        before = float(fmin[-1])
    else:
        return math.inf
    i = start + int(hit[0])
    lo, hi = (speeds[i - 1] if i > 0 else 0.0), speeds[i]
    if signed and points == 1 and i > 0:
        f_lo = float(fmin[hit[0] - 1]) if hit[0] > 0 else before
        one = lambda w: float(np.asarray(least_force(np.array([w])))[0])  # noqa: E731
        return _itp(one, lo, hi, f_lo, float(fmin[hit[0]]), width_rpm * RPM, where)
    while (hi - lo) / RPM > width_rpm:
        ws = np.linspace(lo, hi, points + 2)[1:-1]
        below = np.nonzero(least_force(ws) <= 0.0)[0]
        j = int(below[0]) if below.size else len(ws)
        lo, hi = (ws[j - 1] if j > 0 else lo), (ws[j] if j < len(ws) else hi)
    return float(0.5 * (lo + hi))


def _itp(
    force: Callable[[float], float], lo: float, hi: float, f_lo: float, f_hi: float, width: float, where: str
) -> float:
    """:func:`itp_zero` of the least force over speed (rad/s); ``where`` names the model in a numerical error."""

    def not_finite(w: float) -> NumericalError:
        return NumericalError(f"{where} at {w / RPM:.1f} rpm", "the steady-state force is not finite")

    return itp_zero(force, lo, hi, f_lo, f_hi, width, not_finite)


def jump_search_limit(top_omega: float, kinematic_jump: float) -> float:
    """The top of every dynamic jump-speed search (rad/s): ``JUMP_SEARCH_FACTOR`` times the higher of the
    fastest speed a verdict needs (margin x speed) and the kinematic jump speed, so the first crossing lies inside."""
    return JUMP_SEARCH_FACTOR * max(top_omega, kinematic_jump if math.isfinite(kinematic_jump) else 0.0)
