"""What ``camdyn check`` concludes (:class:`CheckReport` and its parts), forces and gaps at the contact: an
oscillating follower's torques and arm swings carried out to the contact through its lever arm."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .._core.results import finite_or_none
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.contact import ContactStress
from ..model.drive import DriveTorque
from ..model.geometry import CamGeometry, lever_arm_mm, newton_per_torque_at
from ..model.surge import SpringInDynamics
from ._check import Check, CheckKind, find
from .closure import ClosureStudy
from .valvetrain import ValvetrainResult

SYNTHESIS_ARRAYS = ("theta_deg", "pitch", "contour", "path_xy", "traced_xy")  # check --json --arrays only


@dataclass(frozen=True)
class Kinematics:
    """The rigid follower that never leaves the cam (``check --json`` ``kinematic``): its least contact force (N)
    and where (cam deg), and its jump speed (rpm; None: none) and where (deg)."""

    min_contact_force_N: float
    min_contact_force_deg: float
    jump_speed_rpm: float | None
    jump_speed_at_deg: float | None

    @property
    def thrown_off(self) -> bool:
        """Whether a step in the cam's velocity throws the follower off at any speed (its jump speed 0, where the
        step is): its least force is then the smooth motion's, without the step's infinite pull."""
        return self.jump_speed_rpm == 0.0 and self.jump_speed_at_deg is not None

    def json(self) -> dict:
        return {
            "min_contact_force_N": self.min_contact_force_N,
            "min_contact_force_deg": self.min_contact_force_deg,
            "jump_speed_rpm": self.jump_speed_rpm,
            "jump_speed_at_deg": self.jump_speed_at_deg,
        }


@dataclass(frozen=True)
class ContactSeparation:
    """One separation at the contact: gap (mm) and impact speed (m/s) along the contact normal; an oscillating
    follower's arm gap (rad) and speed (rad/s) beside them (None for a translating one)."""

    start_deg: float
    end_deg: float
    max_gap_mm: float
    impact_speed_m_s: float
    bounces: int
    settled: bool
    max_gap_rad: float | None = None
    impact_speed_rad_s: float | None = None

    def json(self) -> dict:
        out = {
            "start_deg": self.start_deg,
            "end_deg": self.end_deg,
            "max_gap_mm": self.max_gap_mm,
            "impact_speed_m_s": self.impact_speed_m_s,
        }
        if self.max_gap_rad is not None:
            out |= {"max_gap_rad": self.max_gap_rad, "impact_speed_rad_s": self.impact_speed_rad_s}
        return out | {"bounces": self.bounces, "settled": self.settled}


@dataclass(frozen=True)
class ContactFlight:
    """One flight (a span of zero interface force): its largest gap at the contact (mm), and an oscillating
    follower's arm gap (rad; None for a translating one)."""

    leave_deg: float
    land_deg: float
    max_gap_mm: float
    max_gap_rad: float | None = None

    def json(self) -> dict:
        out = {"leave_deg": self.leave_deg, "land_deg": self.land_deg, "max_gap_mm": self.max_gap_mm}
        return out | ({"max_gap_rad": self.max_gap_rad} if self.max_gap_rad is not None else {})


@dataclass(frozen=True)
class ContactImpact:
    """One landing: where (deg), and its peak contact force (N) and where (deg); None for a rigid impulse."""

    deg: float
    peak_force_N: float | None
    peak_deg: float | None

    def json(self) -> dict:
        return {"deg": self.deg, "peak_force_N": self.peak_force_N, "peak_deg": self.peak_deg}


@dataclass(frozen=True)
class Dynamics:
    """The follower as its model moves it (``check --json`` ``dynamic``), forces in N at the contact.

    ``residual_vibration_mm`` is at the contact; an oscillating follower's arm swing (rad) is beside it in
    ``residual_vibration_rad`` (None for a translating one). ``spring`` is the return spring's own mass as the
    model weighs it."""

    model: str
    min_contact_force_N: float
    min_contact_force_deg: float
    min_contact_force_uncertainty_N: float | None
    jump_speed_rpm: float | None
    separations: tuple[ContactSeparation, ...]
    flights: tuple[ContactFlight, ...]
    impacts: tuple[ContactImpact, ...]
    max_impact_force_N: float | None
    residual_vibration_mm: float
    periodicity_error: float
    spring: SpringInDynamics
    residual_vibration_rad: float | None = None
    period_revolutions: int | None = 1  # the steady state's period (2: period two); None: not periodic

    @property
    def residual_vibration_deg(self) -> float | None:
        """An oscillating follower's residual arm swing, deg (None for a translating one)."""
        return None if self.residual_vibration_rad is None else math.degrees(self.residual_vibration_rad)

    @property
    def residual_vibration_as_lift(self) -> float:
        """The residual vibration in the unit the lift is given in: an arm's swing in deg, else mm at the contact."""
        deg = self.residual_vibration_deg
        return self.residual_vibration_mm if deg is None else deg

    def json(self) -> dict:
        out = {
            "model": self.model,
            "min_contact_force_N": self.min_contact_force_N,
            "min_contact_force_deg": finite_or_none(self.min_contact_force_deg),  # NaN: a valve that never opens
            "min_contact_force_uncertainty_N": self.min_contact_force_uncertainty_N,
            "jump_speed_rpm": self.jump_speed_rpm,
            "separations": [s.json() for s in self.separations],
            "flights": [f.json() for f in self.flights],
            "impacts": [i.json() for i in self.impacts],
            "max_impact_force_N": self.max_impact_force_N,
            "residual_vibration_mm": self.residual_vibration_mm,
            "periodicity_error": self.periodicity_error,
            "period_revolutions": self.period_revolutions,
        } | self.spring.json()
        if self.residual_vibration_rad is not None:
            out["residual_vibration_rad"] = self.residual_vibration_rad
        return out


@dataclass(frozen=True)
class CheckReport:
    """Everything ``camdyn check`` concludes about a case at one speed."""

    case: Case
    speed_rpm: float
    checks: tuple[Check, ...]
    kinematic: Kinematics
    dynamic: Dynamics
    response: dyn.Response  # forces in N (an oscillating arm's torques through its lever arm)
    warnings: tuple[str, ...]
    advice: tuple[str, ...] = ()
    geometry: CamGeometry | None = None
    drive: DriveTorque | None = None  # the camshaft torque of the dynamic forces
    contact: ContactStress | None = None  # Hertz stress, where the case gives a contact width
    valvetrain: ValvetrainResult | None = None  # a [valvetrain] case's two-mass model
    closure: ClosureStudy | None = None  # a form-closed cam's crossovers and walls

    @property
    def verdict(self) -> str:
        return "pass" if all(c.ok for c in self.checks) else "fail"

    def find(self, kind: CheckKind) -> Check | None:
        """The check of ``kind``, or None where this case has none."""
        return find(self.checks, kind)

    def json(self, arrays: bool = False) -> dict:
        """The ``check --json`` document; a path case's synthesis carries its coordinate arrays only with ``arrays``."""
        out = {
            "case": self.case.name,
            "verdict": self.verdict,
            "speed_rpm": self.speed_rpm,
            "checks": [c.json() for c in self.checks],
            "kinematic": self.kinematic.json(),
            "dynamic": self.dynamic.json(),
            "warnings": list(self.warnings),
            "advice": list(self.advice),
        }
        out["motion"] = self.case.motion_json()
        if self.geometry is not None:
            out["geometry"] = self.geometry.json()
        if self.drive is not None:
            out["drive"] = self.drive.json()
        if self.contact is not None:
            out["contact"] = self.contact.json()
        if self.closure is not None:
            out["closure"] = self.closure.json()
        if self.valvetrain is not None:
            out["valvetrain"] = self.valvetrain.json()
        if self.case.synthesis is not None:
            syn = self.case.synthesis.json()
            out["synthesis"] = syn if arrays else {k: v for k, v in syn.items() if k not in SYNTHESIS_ARRAYS}
        return out


def at_contact(case: Case, value_rad: float, deg: float) -> float:
    """An arm-swing quantity (rad, rad/s) at the contact along its normal (mm, mm/s): times the lever arm there."""
    if not math.isfinite(deg):
        return 0.0 if value_rad == 0.0 else math.nan
    return value_rad * float(lever_arm_mm(case.motion, case.follower, np.deg2rad([deg]))[0])


def contact_separation(case: Case, sep: dyn.Separation) -> ContactSeparation:
    """One separation at the contact: an oscillating follower's arm gap (rad) and speed (rad/s) carried out to the
    contact (mm, m/s), the arm's own beside them."""
    if case.oscillating:
        return ContactSeparation(
            sep.start_deg,
            sep.end_deg,
            at_contact(case, sep.max_gap, sep.max_gap_deg),
            at_contact(case, sep.impact_speed, sep.impact_deg) / 1000.0,
            sep.bounces,
            sep.settled,
            sep.max_gap,
            sep.impact_speed,
        )
    return ContactSeparation(sep.start_deg, sep.end_deg, sep.max_gap, sep.impact_speed, sep.bounces, sep.settled)


def contact_flight(case: Case, fl: dyn.Flight) -> ContactFlight:
    """One flight at the contact: an arm's angular gap carried out to the contact point (mm), the arm's beside it."""
    if case.oscillating:
        return ContactFlight(fl.leave_deg, fl.land_deg, at_contact(case, fl.max_gap, fl.max_gap_deg), fl.max_gap)
    return ContactFlight(fl.leave_deg, fl.land_deg, fl.max_gap)


def contact_impact(imp: dyn.Impact) -> ContactImpact:
    """One landing: where, and its peak contact force (N; None for a rigid follower's impulse)."""
    return ContactImpact(imp.deg, finite_or_none(imp.peak_force), finite_or_none(imp.peak_deg))


def forces_in_newton(case: Case, resp: dyn.Response) -> dyn.Response:
    """A response with an oscillating follower's torques (N*m) as contact forces (N) through the lever arm of
    the contact normal; a translating follower's as it is."""
    if not case.oscillating:
        return resp
    per_torque = newton_per_torque_at(case.motion, case.follower, np.deg2rad(resp.theta_deg))
    return dataclasses.replace(resp, force=resp.force * per_torque, kinematic_force=resp.kinematic_force * per_torque)
