"""``camdyn check``: the interface force, the jump speeds, the separations and the geometry of a case, judged."""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np

from .._core import jit
from .._core.results import finite_or_none
from .._core.units import JUMP_SEARCH_FACTOR, RPM
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.contact import ContactStress
from ..model.drive import DriveTorque
from ..model.geometry import CamGeometry, analyze, lever_arm_mm, newton_per_torque_at
from ..model.surge import SpringInDynamics
from ._check import Check, CheckKind, find
from .closure import ClosureStudy, closure_study
from .geometry import judge_geometry
from .parts import case_contact, case_drive, contact_check, resolve_spring
from .userdata import least_force_uncertainty, least_force_warning, unit_slip_warnings
from .valvetrain import ValvetrainResult, analyze_valvetrain

SYNTHESIS_ARRAYS = ("theta_deg", "pitch", "contour", "path_xy", "traced_xy")  # check --json --arrays only
MAX_SEPARATION_NOTES = 4  # landed separations listed one per line; more are summed up in one


@dataclass(frozen=True)
class Kinematics:
    """The rigid follower that never leaves the cam (``check --json`` ``kinematic``): its least contact force (N)
    and where (cam deg), and its jump speed (rpm; None: none) and where (deg)."""

    min_contact_force_N: float
    min_contact_force_deg: float
    jump_speed_rpm: float | None
    jump_speed_at_deg: float | None

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


def _at_contact(case: Case, value_rad: float, deg: float) -> float:
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
            _at_contact(case, sep.max_gap, sep.max_gap_deg),
            _at_contact(case, sep.impact_speed, sep.impact_deg) / 1000.0,
            sep.bounces,
            sep.settled,
            sep.max_gap,
            sep.impact_speed,
        )
    return ContactSeparation(sep.start_deg, sep.end_deg, sep.max_gap, sep.impact_speed, sep.bounces, sep.settled)


def contact_flight(case: Case, fl: dyn.Flight) -> ContactFlight:
    """One flight at the contact: an arm's angular gap carried out to the contact point (mm), the arm's beside it."""
    if case.oscillating:
        return ContactFlight(fl.leave_deg, fl.land_deg, _at_contact(case, fl.max_gap, fl.max_gap_deg), fl.max_gap)
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


def _separation_note(sep: ContactSeparation, rpm: float, restitution: float) -> str:
    gap = f"gap up to {sep.max_gap_mm:.3g} mm"
    if not sep.settled:
        why = "it keeps bouncing" if sep.bounces else "it is not back on the cam within a revolution"
        if sep.start_deg == sep.end_deg == 0.0:
            return f"the follower does not stay on the cam anywhere at {rpm:g} rpm ({gap}): far beyond its jump speed"
        return (
            f"the follower leaves the cam at {sep.start_deg:.1f} deg and does not settle back ({why}; "
            f"restitution {restitution:g}; {gap})"
        )
    return (
        f"the follower leaves the cam at {sep.start_deg:.1f} deg and lands at {sep.end_deg:.1f} deg ({gap}, "
        f"impact at {sep.impact_speed_m_s:.3g} m/s)"
    )


def _spans(spans: list[tuple[float, float]]) -> str:
    """The first four (leave, land) spans of a list of flights, deg, as a note gives them."""
    return ", ".join(f"{a:.1f}-{b:.1f}" for a, b in spans[:4]) + (", ..." if len(spans) > 4 else "")


def _separations_note(seps: list[ContactSeparation], rpm: float) -> str:
    """Many landed separations of a rigid follower in one line: how many, the first few, the worst gap and impact."""
    spans = _spans([(sep.start_deg, sep.end_deg) for sep in seps])
    gap = max(sep.max_gap_mm for sep in seps)
    impact = max(sep.impact_speed_m_s for sep in seps)
    return (
        f"the follower leaves the cam {len(seps)} times a revolution at {rpm:g} rpm (flights {spans} deg; "
        f"gap up to {gap:.3g} mm, impacts up to {impact:.3g} m/s; check --json lists each)"
    )


def _flights_note(flights: tuple[ContactFlight, ...], impacts: tuple[ContactImpact, ...], rpm: float) -> str:
    """Every flight (where the interface force is zero) and the largest impact: what the report's page 1 says."""
    spans = _spans([(f.leave_deg, f.land_deg) for f in flights])
    gap = max(f.max_gap_mm for f in flights)
    times = {1: "once", 2: "twice"}.get(len(flights), f"{len(flights)} times")
    note = (
        f"the follower leaves the cam {times} a revolution at {rpm:g} rpm (flights {spans} deg; gap up to {gap:.3g} mm)"
    )
    peaks = [(i.peak_force_N, i.peak_deg) for i in impacts if i.peak_force_N is not None]  # a rigid impulse has none
    if peaks:
        force, deg = max(peaks, key=lambda p: p[0])
        many = f"{len(impacts)} impacts, the largest" if len(impacts) > 1 else "an impact of"
        note += f"; {many} {force:.4g} N at {deg:.1f} deg"
    return note


def jump_speeds(case: Case, omega: float, margin: float) -> tuple[float, float, float, float]:
    """(kinematic jump speed rad/s, where deg, dynamic jump speed rad/s, the top of its search rad/s) of a case
    whose spring is resolved (:func:`camdyn.design.parts.resolve_spring`): the dynamic one with its spring model."""
    w_kin, at_kin = dyn.kinematic_jump_speed(case.motion, case.model)
    w_max = dyn.jump_search_limit(margin * omega, w_kin)
    assert case.spring is not None  # resolved, as the docstring asks
    return w_kin, at_kin, case.spring.jump_speed(case.motion, w_max=w_max), w_max


def speed_margin_check(w_dyn: float, omega: float, margin: float) -> Check:
    """``[limits] speed_margin``: the dynamic jump speed over the speed, at least ``margin``. The one comparison
    ``check`` judges and ``size`` proposes a spring by."""
    return CheckKind.SPEED_MARGIN.check(finite_or_none(w_dyn / omega), float(margin))


def run_check(case: Case, speed_rpm: float | None = None) -> CheckReport:
    """Kinematic and dynamic interface force, jump speeds, separations and the verdict at ``speed_rpm``, with the
    spring's own mass as ``[spring] model`` asks (:func:`camdyn.design.parts.resolve_spring`)."""
    case = resolve_spring(case)
    assert case.spring is not None  # resolve_spring resolved it
    if (vt := case.valvetrain) is not None:  # its two-mass programs load while the equivalent follower is judged
        jit.in_background(functools.partial(dyn.prepare_valvetrain, case.motion, vt), "camdyn-valvetrain")
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    if case.follower is not None and case.follower.form_closed:
        return _closure_check(case, rpm)
    omega = rpm * RPM
    motion, model, limits = case.motion, case.model, case.limits
    # the programs of a follower of this kind that stays on its cam and of one that leaves it, stored on the side
    jit.in_background(functools.partial(dyn.store_response, motion, model), "camdyn-store")
    warnings = list(case.warnings) + ([case.spring.note] if case.spring.note else [])

    resp = dyn.response(motion, model, omega)
    w_kin, at_kin, w_dyn, w_max = jump_speeds(case, omega, limits.speed_margin)
    if not math.isfinite(w_dyn) and not model.rigid:
        searched = f"searched {JUMP_SEARCH_FACTOR:g}x beyond the margin"
        warnings.append(f"no jump found up to {w_max / RPM:.0f} rpm ({searched})")
    warnings += unit_slip_warnings(case, rpm, finite_or_none((w_dyn if math.isfinite(w_dyn) else w_kin) / RPM))
    if not model.rigid and not resp.separations:
        # the frequency-domain steady state is exact without separation: an independent check of the solve
        f_lin = dyn.linear_least_force(motion, model, omega)
        if abs(f_lin - resp.min_force) > 5e-3 * max(1.0, float(abs(resp.force).max())):
            warnings.append(
                f"time-domain and frequency-domain steady states disagree: least force {resp.min_force:.4g} vs "
                f"{f_lin:.4g} {case.kind.force_unit}"
            )
    warnings += list(resp.warnings)
    resp = forces_in_newton(case, resp)
    noise_N = None if resp.separations else least_force_uncertainty(case, omega)  # a table's noise, in contact only
    warnings += least_force_warning(case, resp.min_force, noise_N)

    if not model.rigid:  # a train compressed by much of the lift no longer drives the follower: a verdict
        lift = float(np.ptp(resp.s))
        # compression only: where the follower flies above the cam (x > s) the train is unloaded, not stretched
        deflection = float(np.max(np.clip(resp.s - resp.x, 0.0, None))) / lift if lift > 0.0 else 0.0
        checks_train = (CheckKind.TRAIN_DEFLECTION.check(deflection, float(limits.max_train_deflection)),)
    else:
        checks_train = ()
    kin_force = resp.kinematic_force
    i_kin = int(kin_force.argmin())
    valve = None if case.valvetrain is None else analyze_valvetrain(case, omega, limits.speed_margin)
    least = resp.min_force if valve is None else valve.response.least_event_force  # a valve: over its event
    if valve is not None:
        w_dyn = valve.float_speed_rpm * RPM  # a valvetrain jumps where it floats
        warnings += valve.warnings()
    checks = (
        CheckKind.CONTACT_FORCE.check(float(least), float(limits.min_contact_force)),
        speed_margin_check(w_dyn, omega, limits.speed_margin),
    ) + checks_train
    if valve is not None:
        checks += valve.checks(limits.max_seating_velocity)
    kinematic = Kinematics(
        float(kin_force[i_kin]), float(resp.theta_deg[i_kin]), finite_or_none(w_kin / RPM), finite_or_none(at_kin)
    )
    osc = case.oscillating  # the contract's values at the contact, the arm's angle beside them
    dynamic = Dynamics(
        model=resp.model,
        min_contact_force_N=float(least),  # a valve: the cam contact over the valve event, where it is judged
        min_contact_force_deg=resp.min_force_deg if valve is None else float(valve.response.least_event_force_deg),
        min_contact_force_uncertainty_N=noise_N,
        jump_speed_rpm=finite_or_none(w_dyn / RPM),
        separations=tuple(contact_separation(case, s) for s in resp.separations),
        flights=tuple(contact_flight(case, f) for f in resp.flights),
        impacts=tuple(contact_impact(i) for i in resp.impacts),
        max_impact_force_N=finite_or_none(resp.max_impact_force),
        residual_vibration_mm=(
            _at_contact(case, resp.residual_vibration, resp.residual_vibration_deg) if osc else resp.residual_vibration
        ),
        periodicity_error=resp.periodicity_error,
        spring=case.spring,
        residual_vibration_rad=resp.residual_vibration if osc else None,
    )
    advice: list[str] = []
    geo = None
    if case.follower is not None:
        geo = analyze(motion, case.follower)
        geo_checks, geo_warnings, geo_advice = judge_geometry(
            geo, motion, max_pressure_angle=limits.max_pressure_angle, min_curvature_ratio=limits.min_curvature_ratio
        )
        checks += tuple(geo_checks)
        warnings += geo_warnings
        advice += geo_advice
    if case.synthesis is not None:  # a path case: the linkage the cam drives must trace the path, and run
        checks += (
            CheckKind.PATH_ERROR.check(case.synthesis.path_error_mm, float(limits.max_path_error)),
            CheckKind.TRANSMISSION_ANGLE.check(
                case.synthesis.least_transmission_deg, float(limits.min_transmission_angle)
            ),
        )
    drive = case_drive(case, resp)
    contact = None
    if geo is not None and case.spec.contact_width_mm is not None:
        if geo.undercut:  # the contour folds: no radius of curvature to press on
            warnings.append("contact stress not computed: the contour is undercut")
        else:
            contact = case_contact(case, geo, resp)
            if contact is not None and limits.max_contact_stress is not None:
                checks += (contact_check(contact, limits.max_contact_stress),)
    by_flights = bool(resp.flights) and not model.rigid  # a compliant train's flights and impacts
    told = [sep for sep in dynamic.separations if not (by_flights and sep.settled)]  # flights: one note says it
    landed = [sep for sep in told if sep.settled]
    if len(landed) > MAX_SEPARATION_NOTES:  # hundreds of short flights: one line, the JSON lists each
        warnings.append(_separations_note(landed, rpm))
        told = [sep for sep in told if not sep.settled]
    warnings += [_separation_note(sep, rpm, float(case.model.restitution)) for sep in told]
    if by_flights:
        warnings.append(_flights_note(dynamic.flights, dynamic.impacts, rpm))
    return CheckReport(
        case, rpm, checks, kinematic, dynamic, resp, tuple(warnings), tuple(advice), geo, drive, contact, valve
    )


def _closure_check(case: Case, rpm: float) -> CheckReport:
    """:func:`run_check` of a form-closed cam: the crossovers and their impacts judged, the geometry as any cam's;
    no jump speed (it cannot jump) and no least contact force (signed by design)."""
    assert case.follower is not None and case.spring is not None  # run_check: a groove cam, its spring resolved
    study = closure_study(case, rpm)
    resp = forces_in_newton(case, study.as_response(case))
    drive = case_drive(case, resp)
    resp = study.on_its_cam(case, resp)
    warnings = list(case.warnings) + [study.not_applicable]
    kin = resp.kinematic_force
    i = int(kin.argmin())
    kinematic = Kinematics(float(kin[i]), float(resp.theta_deg[i]), None, None)
    dynamic = Dynamics(
        resp.model,
        resp.min_force,
        resp.min_force_deg,
        None,
        None,
        (),
        (),
        (),
        study.response.max_impact_force_N,
        0.0,
        0.0,
        case.spring,
    )
    geo = analyze(case.motion, case.follower)
    lim = case.limits
    geo_checks, geo_warnings, advice = judge_geometry(
        geo, case.motion, max_pressure_angle=lim.max_pressure_angle, min_curvature_ratio=lim.min_curvature_ratio
    )
    checks = (study.check(lim.max_impact_velocity), *geo_checks)
    checks += study.geometry_checks(geo_checks[0].limit, lim.min_curvature_ratio)
    checks += study.preload_check(lim.min_contact_force)
    warnings += geo_warnings
    warnings += study.fold_warnings
    contact = None
    if case.spec.contact_width_mm is not None:
        if study.walls.undercut:  # a folded wall: no radius of curvature to press on
            what = "a groove wall" if study.loads is None else "the conjugate cam"
            warnings.append(f"contact stress not computed: {what} is undercut")
        else:
            loads = None if study.loads is None else (study.loads.primary_N, study.loads.conjugate_N)
            contact = case_contact(case, geo, resp, study.walls, cam_forces_N=loads)
            if contact is not None and lim.max_contact_stress is not None:
                checks += (contact_check(contact, lim.max_contact_stress),)
    if study.response.crossovers:
        warnings.append(_crossovers_note(study, case.follower.backlash))
    return CheckReport(
        case, rpm, checks, kinematic, dynamic, resp, tuple(warnings), tuple(advice), geo, drive, contact, closure=study
    )


def _crossovers_note(study: ClosureStudy, backlash_mm: float) -> str:
    """Where the contact force changes flank, and with backlash where and how fast the other flank meets it."""
    xs = study.response.crossovers
    flank = "flank" if study.loads is None else "cam"
    where = ", ".join(f"{c.deg:.1f}" for c in xs[:6]) + (", ..." if len(xs) > 6 else "")
    if study.loads is not None and study.loads.preload_held:  # both rollers stay loaded: only the net force turns
        note = (
            f"the net contact force changes sign {len(xs)} times a revolution (at {where} deg); the preload keeps "
            "both cams loaded all round"
        )
    else:
        note = f"the contact force changes {flank} {len(xs)} times a revolution (at {where} deg)"
    if backlash_mm > 0.0:
        top = max(xs, key=lambda c: c.impact_velocity_m_per_s)
        note += (
            f"; across the {backlash_mm:g} mm backlash the {top.to_flank} {flank} meets the follower hardest at "
            f"{top.land_deg:.1f} deg, {top.impact_velocity_m_per_s:.3g} m/s"
        )
    return note
