"""A valvetrain judged: the valve's event at the case speed (lift, timing, seating speed, bounce), and the float
and bounce speeds, from the two-mass model (:mod:`camdyn.model.dynamics._valvetrain`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._core.errors import InputError
from .._core.units import M_PER_MM, RPM, VALVE_BOUNCE_TOLERANCE_MM, VALVE_TIMING_LIFT_MM
from ..model import dynamics as dyn
from ..model.case import Case
from ._check import Check, CheckKind


def _finite_or_none(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


@dataclass(frozen=True)
class ValvetrainResult:
    """The valvetrain at one cam speed: its steady revolution and the speeds where it floats and bounces."""

    ratio: float
    lash_mm: float
    response: dyn.ValvetrainResponse
    float_speed_rpm: float  # inf: no float up to the search's top
    bounce_speed_rpm: float  # inf: no bounce up to the search's top
    search_top_rpm: float
    speeds_rpm: tuple[float, ...] = ()  # the speeds the searches marched, increasing
    seating_velocities: tuple[float, ...] = ()  # m/s at each (NaN: the valve never lifts)
    bounce_heights_mm: tuple[float, ...] = ()  # at each

    @property
    def timing_deg(self) -> tuple[float, float]:
        """Opening and closing angles at :data:`VALVE_TIMING_LIFT_MM` of valve lift, deg."""
        return self.response.timing_deg(VALVE_TIMING_LIFT_MM)

    @property
    def seating_velocity(self) -> float:
        """m/s; NaN where the valve never lifts."""
        return self.response.seating_velocity

    def json(self) -> dict:
        """``check --json``'s ``valvetrain``."""
        opening, closing = self.timing_deg
        return {
            "ratio": self.ratio,
            "lash_mm": self.lash_mm,
            "max_valve_lift_mm": self.response.max_valve_lift_mm,
            "opening_deg": _finite_or_none(opening),
            "closing_deg": _finite_or_none(closing),
            "seating_velocity_m_per_s": _finite_or_none(self.seating_velocity),
            "float_speed_rpm": _finite_or_none(self.float_speed_rpm),
            "bounce_speed_rpm": _finite_or_none(self.bounce_speed_rpm),
            "bounce_height_mm": self.response.bounce_height_mm,
        }

    def checks(self, max_seating_velocity: float) -> tuple[Check, ...]:
        """``seating_velocity`` against ``[limits] max_seating_velocity`` and ``valve_bounce`` (none beyond the seat's
        micro-bounce tolerance) at the case speed."""
        v = self.seating_velocity
        return (
            CheckKind.SEATING_VELOCITY.check(_finite_or_none(v), float(max_seating_velocity)),
            CheckKind.VALVE_BOUNCE.check(self.response.bounce_height_mm, VALVE_BOUNCE_TOLERANCE_MM),
        )

    def note(self) -> str:
        """What the contact-force check means on a valvetrain, for ``check``'s warnings."""
        return (
            "valvetrain: the cam contact force is judged over the valve event (from the valve's lift to its seating); "
            "on the base circle the lash is open and only valvetrain.tappet_force holds the follower"
        )


def refuse_valvetrain(case: Case, what: str, why: str = "") -> None:
    """:class:`InputError` where a study that knows one follower (``what``: a tolerance study, the optimizer) is
    asked about a valvetrain: it would judge the equivalent single follower, without the lash, the seat or float,
    and propose what ``check`` may then fail; ``why``: what else it would get wrong."""
    if case.valvetrain is not None:
        raise InputError(
            "valvetrain",
            f"{what} does not model a valvetrain yet (it would judge the equivalent single follower, without the lash, "
            f"the seat or float{why}): camdyn check gives its float and bounce speeds; size, sweep and tolerance "
            "model it",
        )


def analyze_valvetrain(case: Case, omega: float, margin: float) -> ValvetrainResult:
    """The valvetrain of ``case`` at cam speed ``omega`` (rad/s), with its float and bounce speeds searched up to
    the dynamic jump search's top for ``margin`` x the speed (both searches share the revolutions they march)."""
    vt = case.valvetrain
    assert vt is not None  # the caller's: a [valvetrain] case
    w_kin = dyn.kinematic_jump_speed(case.motion, case.model)[0]  # the equivalent follower's: where float begins
    w_max = dyn.jump_search_limit(margin * omega, w_kin)
    marched: dict[float, dyn.ValvetrainResponse] = {}

    def at(w: float) -> dyn.ValvetrainResponse:
        if w not in marched:
            marched[w] = dyn.valvetrain_response(case.motion, vt, w)
        return marched[w]

    w_float = dyn.float_speed(case.motion, vt, w_max, respond=at)
    w_bounce = dyn.bounce_speed(case.motion, vt, w_max, respond=at)
    here = at(float(omega))
    speeds = sorted(marched)
    return ValvetrainResult(
        float(vt.ratio),
        float(vt.lash) / M_PER_MM,
        here,
        w_float / RPM,
        w_bounce / RPM,
        w_max / RPM,
        tuple(w / RPM for w in speeds),
        tuple(marched[w].seating_velocity for w in speeds),
        tuple(marched[w].bounce_height_mm for w in speeds),
    )
