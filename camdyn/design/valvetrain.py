"""A valvetrain judged: the valve's event at the case speed (lift, timing, seating speed, bounce), and the float
and bounce speeds, from the two-mass model (:mod:`camdyn.model.dynamics._valvetrain`; the searches on its fast
path where every contact stays closed, :mod:`camdyn.model.dynamics._valvefast`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._core.results import finite_or_none
from .._core.units import M_PER_MM, RPM, VALVE_BOUNCE_TOLERANCE_MM, VALVE_TIMING_LIFT_MM
from ..model import dynamics as dyn
from ..model.case import Case
from ._check import Check, CheckKind

# the seating velocity against speed reaches half again the float speed (or the case speed): beyond float the train
# flies and its landings scatter
SEATING_CURVE_REACH = 1.5


def _seating_curve_top(case_speed: float, float_speed: float) -> float:
    """Where the seating velocity against speed ends (the units of the speeds given)."""
    return SEATING_CURVE_REACH * max(case_speed, float_speed if math.isfinite(float_speed) else 0.0)


@dataclass(frozen=True)
class ValvetrainResult:
    """The valvetrain at one cam speed: its steady revolution and the speeds where it floats and bounces."""

    ratio: float  # constant, or a rocker's at the cam's peak lift
    lash_mm: float
    response: dyn.ValvetrainResponse
    float_speed_rpm: float  # inf: no float up to the search's top
    bounce_speed_rpm: float  # inf: no bounce up to the search's top
    search_top_rpm: float
    # the valvetrain at each speed the searches marched and at the scan's speeds to the seating curve's top,
    # increasing: what the searches did not read of one (the seating of a floating valve: its diffrax run) is
    # computed when first asked (a report's figure, not check)
    marched: tuple[dyn.ValvePoint, ...] = ()
    # a rocker's: the cam's and the follower's lifts through it (mm, the lash not taken off) and its instantaneous
    # ratio at the cam's lift, on response.theta_deg; None: the constant ratio's
    rocker_curves: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    coil_bind_lift_mm: float | None = None  # the valve's lift at which its designed spring ([spring]) is solid
    tappet_force: float = 0.0  # N, valvetrain.tappet_force: what holds the follower on the cam while the lash is open

    @property
    def speeds_rpm(self) -> tuple[float, ...]:
        """The speeds the float and bounce searches marched, increasing, rpm."""
        return tuple(p.omega / RPM for p in self.marched)

    @property
    def seating_curve_top_rpm(self) -> float:
        """How far the seating velocity against speed is drawn: :data:`SEATING_CURVE_REACH` x the float speed (or
        the case speed), rpm."""
        return _seating_curve_top(self.response.omega / RPM, self.float_speed_rpm)

    @property
    def seating_velocities(self) -> tuple[float, ...]:
        """m/s at each of :attr:`speeds_rpm` (NaN: the valve never lifts)."""
        return tuple(p.seating_velocity for p in self.marched)

    @property
    def bounce_heights_mm(self) -> tuple[float, ...]:
        """The bounce height at each of :attr:`speeds_rpm`, mm."""
        return tuple(p.bounce_height_mm for p in self.marched)

    @property
    def coil_bind_clearance_mm(self) -> float | None:
        """The valve's lift to spare before its spring goes solid, at its largest lift at the case speed (a flight's
        overshoot included), mm; None without a designed spring."""
        if self.coil_bind_lift_mm is None:
            return None
        return self.coil_bind_lift_mm - self.response.max_valve_lift_mm

    @property
    def ratios(self) -> np.ndarray:
        """The instantaneous ratio (valve lift per follower lift) at the cam's lift, on ``response.theta_deg``."""
        curves = self.rocker_curves
        return np.full_like(self.response.theta_deg, self.ratio) if curves is None else curves[2]

    @property
    def cam_at_valve(self) -> np.ndarray:
        """Where a rigid train would hold the valve: the cam's lift through the rocker less the lash, mm."""
        curves = self.rocker_curves
        return (self.ratio * self.response.cam_lift if curves is None else curves[0]) - self.lash_mm

    @property
    def follower_at_valve(self) -> np.ndarray:
        """The follower's lift through the rocker less the lash, mm."""
        curves = self.rocker_curves
        return (self.ratio * self.response.follower_lift if curves is None else curves[1]) - self.lash_mm

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
            "opening_deg": finite_or_none(opening),
            "closing_deg": finite_or_none(closing),
            "seating_velocity_m_per_s": finite_or_none(self.seating_velocity),
            "float_speed_rpm": finite_or_none(self.float_speed_rpm),
            "bounce_speed_rpm": finite_or_none(self.bounce_speed_rpm),
            "bounce_height_mm": self.response.bounce_height_mm,
            "ratio_min": float(self.ratios.min()),
            "ratio_max": float(self.ratios.max()),
            "coil_bind_lift_mm": self.coil_bind_lift_mm,
            "coil_bind_clearance_mm": self.coil_bind_clearance_mm,
        }

    def checks(self, max_seating_velocity: float) -> tuple[Check, ...]:
        """``seating_velocity`` against ``[limits] max_seating_velocity`` and ``valve_bounce`` (none beyond the seat's
        micro-bounce tolerance) at the case speed; with a designed spring, ``coil_bind``: the valve's largest lift
        (a flight's overshoot included) short of where the spring goes solid."""
        v = self.seating_velocity
        checks = (
            CheckKind.SEATING_VELOCITY.check(finite_or_none(v), float(max_seating_velocity)),
            CheckKind.VALVE_BOUNCE.check(self.response.bounce_height_mm, VALVE_BOUNCE_TOLERANCE_MM),
        )
        clearance = self.coil_bind_clearance_mm
        return checks if clearance is None else (*checks, CheckKind.COIL_BIND.check(clearance, 0.0))

    def note(self) -> str:
        """What the contact-force check means on a valvetrain, for ``check``'s warnings."""
        return (
            "valvetrain: the cam contact force is judged over the valve event (from the valve's lift to its seating); "
            "on the base circle the lash is open and only valvetrain.tappet_force holds the follower"
        )

    def warnings(self) -> tuple[str, ...]:
        """``check``'s lines on the valvetrain at the case speed: :meth:`note`, the follower's landings on the cam
        outside the valve event (:func:`ramp_landings`) and the two-mass model's own."""
        landings = ramp_landings(self.response, self.tappet_force)
        return (self.note(), *(() if landings is None else (landings,)), *self.response.warnings)


def ramp_landings(response: dyn.ValvetrainResponse, tappet_force: float) -> str | None:
    """One line for the follower's landings back on the cam while the valve is seated (the lash open: only the
    tappet force holds it there, and a ramp that decelerates throws it off), with their angles and impact speeds;
    None where it never leaves the cam outside the valve event (a landing after a float is the float's)."""
    n = len(response.theta_deg)
    landings = [e for e in response.events if e.what == "cam-landing" and response.seated[round(e.deg / 360.0 * n) % n]]
    if not landings:
        return None
    where = " and ".join(f"{e.deg:.1f} deg ({e.speed:.3g} m/s)" for e in landings)
    rpm = response.omega / RPM
    return (
        f"valvetrain: at {rpm:.6g} rpm the follower leaves the cam with the lash open and lands back on it at {where}: "
        f"valvetrain.tappet_force ({tappet_force:.4g} N) does not hold it where the ramp decelerates"
    )


def spring_notes(case: Case, study: str) -> tuple[str, ...]:
    """What a valvetrain study (``study``: "at every rate", "in every sample") carries of a resolved ``[spring]``
    part: the case's spring, its mass on the valve and its coil bind."""
    sd = case.spring
    if sd is None or sd.model == "none":
        return () if sd is None or sd.note is None else (sd.note,)
    how = "its surge chain" if sd.model == "surge" else "its lumped third"
    out = f"the case's valve spring ({1e3 * sd.mass_kg:.3g} g) is on the valve as {how} {study}"
    if sd.travel_to_solid_mm is not None:
        out += f"; it goes solid at {sd.travel_to_solid_mm:.4g} mm of valve lift (coil bind)"
    return (out,)


def analyze_valvetrain(case: Case, omega: float, margin: float) -> ValvetrainResult:
    """The valvetrain of ``case`` at cam speed ``omega`` (rad/s), with its float and bounce speeds searched up to
    the dynamic jump search's top for ``margin`` x the speed (both searches share the revolutions they march). A
    case resolved with its designed spring (:func:`camdyn.design.parts.resolve_spring`) carries its coil bind."""
    vt = case.valvetrain
    assert vt is not None  # the caller's: a [valvetrain] case
    w_kin = dyn.kinematic_jump_speed(case.motion, case.model)[0]  # the equivalent follower's: where float begins
    w_max = dyn.jump_search_limit(margin * omega, w_kin)
    marched: dict[float, dyn.ValvePoint] = {}

    def at(w: float, floats: bool = False) -> dyn.ValvePoint:  # the fast path where it can say
        if w not in marched:
            marched[w] = dyn.ValvePoint(case.motion, vt, w, floats=floats)
        return marched[w]

    w_float = dyn.float_speed(case.motion, vt, w_max, respond=at)
    # past the float speed the bounce search's fast path follows the float through (the float search's stops at it)
    w_bounce = dyn.bounce_speed(case.motion, vt, w_max, respond=lambda w: at(w, floats=w > w_float))
    here = at(float(omega)).response  # the whole revolution at the case speed: the diffrax model's
    top = _seating_curve_top(float(omega), w_float)
    for w in dyn.valve_scan_speeds(w_max):  # the seating curve's scan beyond the searches', to its first past the top
        at(float(w))
        if w >= top:
            break
    curves = None
    if vt.rocker is not None:
        cam_at_valve, ratios = vt.at_valve_mm(here.cam_lift)
        curves = (cam_at_valve, vt.at_valve_mm(here.follower_lift)[0], ratios)
    return ValvetrainResult(
        float(vt.ratio),
        float(vt.lash) / M_PER_MM,
        here,
        w_float / RPM,
        w_bounce / RPM,
        w_max / RPM,
        tuple(marched[w] for w in sorted(marched)),
        curves,
        None if case.spring is None else case.spring.travel_to_solid_mm,
        float(vt.tappet_force),
    )
