"""The valvetrain at one cam speed as its studies read it (:class:`ValvePoint`: the fast path where it answers, the
diffrax model where it cannot), and the float and bounce speeds searched on it."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np

from ..._core.units import VALVE_BOUNCE_TOLERANCE_MM
from ..motion import Motion
from ..valvetrain import ValvetrainModel
from ._response import first_zero_speed, scan_speeds
from ._valvefast import Floated, ValveSummary, fast_valve_summary
from ._valvefloat import follows_floats
from ._valveresponse import ValvetrainResponse
from ._valvetrain import NO_EVENT, valvetrain_response

# the speed searches' scan, one speed at a time from the slowest: each speed is a solve of its own (no batch to fill),
# and above the first crossing the valve floats and every speed is the diffrax model's, the slow one
_SCAN_CHUNK = 1
SCAN_GRID = 40  # the float and bounce searches' scan: speeds up to the search's top


def valve_scan_speeds(w_max: float) -> np.ndarray:
    """The speeds (rad/s) the float and bounce searches scan up to ``w_max``, from the slowest."""
    return scan_speeds(w_max, SCAN_GRID)


def _read(name: str) -> property:
    """A number the fast path's summary and the diffrax model's response both give, from whichever answers."""
    return property(lambda self: float(getattr(self._answer, name)), doc=f"The response's ``{name}``.")


class ValvePoint:
    """The valvetrain at one cam speed as its studies read it: :func:`fast_valve_summary` where it answers, the
    diffrax model's :func:`~camdyn.model.dynamics.valvetrain_response` (run once, when first asked) for what it
    does not: everything where the fast path cannot say, all but the float verdict and the least force (0) where
    the valve surely floats. The same names as the response's. Nothing is computed until a number is asked for.
    ``floats``: a speed past the float speed, where the fast path follows the float through
    (:func:`fast_valve_summary`'s ``floats``) instead of saying only that the valve floats."""

    def __init__(self, motion: Motion, vt: ValvetrainModel, omega: float, *, floats: bool = False) -> None:
        self.omega = float(omega)
        # past the float speed a valvetrain whose floats the fast path cannot follow goes to the diffrax model at
        # once: the fast path would say only that the valve floats
        floats = bool(floats)
        self._try_fast, self._floats = follows_floats(vt) or not floats, floats
        self._motion, self._vt = motion, vt
        self._response: ValvetrainResponse | None = None

    @functools.cached_property
    def _fast(self) -> ValveSummary | Floated | None:
        """The fast path's answer (:func:`fast_valve_summary`), on first use."""
        if not self._try_fast:
            return None
        return fast_valve_summary(self._motion, self._vt, self.omega, floats=self._floats)

    @property
    def fast(self) -> bool:
        """Whether the fast path answered everything (the diffrax model not run)."""
        return isinstance(self._fast, ValveSummary)

    @property
    def response(self) -> ValvetrainResponse:
        """The diffrax model's revolution at this speed (run on first use)."""
        if self._response is None:
            self._response = valvetrain_response(self._motion, self._vt, self.omega)
        return self._response

    @property
    def _answer(self) -> ValveSummary | ValvetrainResponse:
        return self._fast if isinstance(self._fast, ValveSummary) else self.response

    @property
    def floated(self) -> bool:
        return True if isinstance(self._fast, Floated) else bool(self._answer.floated)

    @property
    def least_event_force(self) -> float:
        return 0.0 if isinstance(self._fast, Floated) else float(self._answer.least_event_force)

    @property
    def float_force(self) -> float:
        """The float search's force (N): :attr:`least_event_force`, but where the valve floats the least force the
        cam would have to pull with to hold the follower (negative: the fast path's, or the diffrax model's
        :attr:`ValvetrainResponse.float_force` on a rigid cam contact), continuous through the float speed; NaN
        where the valve never lifts."""
        fast = self._fast
        if isinstance(fast, Floated):
            return fast.least_force
        if isinstance(fast, ValveSummary):
            return float(fast.hold_force if fast.floated else fast.least_event_force)
        return float(self.response.float_force)

    least_event_force_deg = _read("least_event_force_deg")
    least_train_force = _read("least_train_force")
    seating_velocity = _read("seating_velocity")
    seating_deg = _read("seating_deg")
    bounce_height_mm = _read("bounce_height_mm")
    max_valve_lift_mm = _read("max_valve_lift_mm")

    @property
    def bounced(self) -> bool:
        """Whether the valve leaves its seat after closing by more than the seat's micro-bounce tolerance."""
        return self.bounce_height_mm > VALVE_BOUNCE_TOLERANCE_MM

    def max_gap_mm(self, solid_mm: float = math.inf) -> float:
        """:meth:`ValvetrainResponse.max_gap_mm` (mm)."""
        fast = self._fast
        if isinstance(fast, ValveSummary) and fast.bounce_lift_mm <= solid_mm:  # the rebounds short of coil bind
            return fast.max_gap_mm
        return self.response.max_gap_mm(self._vt, solid_mm)


def float_speed(
    motion: Motion,
    vt: ValvetrainModel,
    w_max: float,
    *,
    grid: int = SCAN_GRID,
    width_rpm: float = 1.0,
    respond: Callable[[float], ValvePoint] | None = None,
    margin: float = 0.0,
) -> float:
    """The first cam speed (rad/s) at which the cam contact opens while the valve is off its seat (inf: none up
    to ``w_max``): the shared jump search on the least cam-contact force over the valve event. ``respond``: the
    valvetrain at a speed, where a caller shares them between searches (default a fresh :class:`ValvePoint`);
    ``margin`` (N): the first speed at which that force falls to it instead (``optimize``'s force margin)."""
    respond = respond or (lambda w: ValvePoint(motion, vt, w))

    def least(ws: np.ndarray) -> np.ndarray:  # a speed at which the valve does not lift has no event to float in
        forces = [respond(float(w)).float_force - margin for w in np.atleast_1d(ws)]
        return np.nan_to_num(forces, nan=NO_EVENT)

    return first_zero_speed(
        least,
        w_max,
        grid=grid,
        width_rpm=width_rpm,
        points=1,
        where="valvetrain float search",
        chunk=_SCAN_CHUNK,
        signed=True,
    )


def bounce_speed(
    motion: Motion,
    vt: ValvetrainModel,
    w_max: float,
    *,
    grid: int = SCAN_GRID,
    width_rpm: float = 1.0,
    respond: Callable[[float], ValvePoint] | None = None,
) -> float:
    """The first cam speed (rad/s) at which the valve leaves its seat after closing by more than the seat's
    micro-bounce tolerance :data:`VALVE_BOUNCE_TOLERANCE_MM` (inf: none up to ``w_max``)."""
    respond = respond or (lambda w: ValvePoint(motion, vt, w))

    def margin(ws: np.ndarray) -> np.ndarray:
        return np.array([VALVE_BOUNCE_TOLERANCE_MM - respond(float(w)).bounce_height_mm for w in np.atleast_1d(ws)])

    return first_zero_speed(
        margin, w_max, grid=grid, width_rpm=width_rpm, points=1, where="valvetrain bounce search", chunk=_SCAN_CHUNK
    )
