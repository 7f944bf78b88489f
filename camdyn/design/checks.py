"""``camdyn check``: the interface force, the jump speeds, the separations and the geometry of a case, judged."""

from __future__ import annotations

import functools
import math

import numpy as np

from .._core import jit
from .._core.results import finite_or_none
from .._core.units import JUMP_SEARCH_FACTOR, RPM
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.geometry import analyze
from ._check import Check, CheckKind
from ._check_report import (
    CheckReport,
    ContactFlight,
    ContactImpact,
    ContactSeparation,
    Dynamics,
    Kinematics,
    at_contact,
    contact_flight,
    contact_impact,
    contact_separation,
    forces_in_newton,
)
from ._closure_check import closure_check
from .geometry import judge_geometry
from .parts import case_contact, case_drive, contact_check, resolve_spring
from .userdata import least_force_uncertainty, least_force_warning, lift_within_noise, unit_slip_warnings
from .valvetrain import ValvetrainResult, analyze_valvetrain

__all__ = [
    "Check",
    "CheckKind",
    "CheckReport",
    "forces_in_newton",
    "jump_speeds",
    "run_check",
    "speed_margin_check",
]

MAX_SEPARATION_NOTES = 4  # landed separations listed one per line; more are summed up in one


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


def jump_speeds(
    case: Case, omega: float, margin: float, valve: ValvetrainResult | None = None
) -> tuple[float, float, float, float]:
    """(kinematic jump speed rad/s, where deg, dynamic jump speed rad/s, the top of its search rad/s) of a case
    whose spring is resolved (:func:`camdyn.design.parts.resolve_spring`): the dynamic one with its spring model,
    or a valvetrain's float speed (``valve``: its analysis, searched to the same top): a valvetrain jumps where it
    floats, and its equivalent follower's jump speed, which no verdict reads, is not searched."""
    w_kin, at_kin = dyn.kinematic_jump_speed(case.motion, case.model)
    w_max = dyn.jump_search_limit(margin * omega, w_kin)
    if valve is not None:
        return w_kin, at_kin, valve.float_speed_rpm * RPM, w_max
    assert case.spring is not None  # resolved, as the docstring asks
    return w_kin, at_kin, case.spring.jump_speed(case.motion, w_max=w_max), w_max


def speed_margin_check(w_dyn: float, omega: float, margin: float) -> Check:
    """``[limits] speed_margin``: the dynamic jump speed over the speed, at least ``margin``. The one comparison
    ``check`` judges and ``size`` proposes a spring by."""
    return CheckKind.SPEED_MARGIN.check(finite_or_none(w_dyn / omega), float(margin))


def run_check(case: Case, speed_rpm: float | None = None, *, store_programs: bool = True) -> CheckReport:
    """Kinematic and dynamic interface force, jump speeds, separations and the verdict at ``speed_rpm``, with the
    spring's own mass as ``[spring] model`` asks (:func:`camdyn.design.parts.resolve_spring`). ``store_programs``:
    compile on the side, for later processes, the programs of a follower of this kind that leaves its cam where this
    one stays on it, and the reverse (``optimize`` keeps that core for its own programs)."""
    case = resolve_spring(case)
    assert case.spring is not None  # resolve_spring resolved it
    if (vt := case.valvetrain) is not None:  # its two-mass programs load while the equivalent follower is judged
        jit.in_background(functools.partial(dyn.prepare_valvetrain, case.motion, vt), "camdyn-valvetrain")
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    if case.follower is not None and case.follower.form_closed:
        return closure_check(case, rpm)
    omega = rpm * RPM
    motion, model, limits = case.motion, case.model, case.limits
    if store_programs:  # the programs of a follower of this kind that stays on its cam and of one that leaves it
        jit.in_background(functools.partial(dyn.store_response, motion, model), "camdyn-store")
    warnings = list(case.warnings) + ([case.spring.note] if case.spring.note else [])

    resp = dyn.response(motion, model, omega)
    valve = None if case.valvetrain is None else analyze_valvetrain(case, omega, limits.speed_margin)
    w_kin, at_kin, w_dyn, w_max = jump_speeds(case, omega, limits.speed_margin, valve)
    if not math.isfinite(w_dyn) and (valve is not None or not model.rigid):
        searched = f"searched {JUMP_SEARCH_FACTOR:g}x beyond the margin"
        what = "jump" if valve is None else "valve float"
        warnings.append(f"no {what} found up to {w_max / RPM:.0f} rpm ({searched})")
    if math.isfinite(w_dyn):
        warnings += unit_slip_warnings(case, rpm, finite_or_none(w_dyn / RPM))
    else:  # none found up to the search's top: the rigid follower's says how far it is
        warnings += unit_slip_warnings(case, rpm, finite_or_none(w_kin / RPM), "the kinematic jump speed")
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

    checks_train = ()
    if not model.rigid:  # a train compressed by much of the lift no longer drives the follower: a verdict
        lift = float(np.ptp(resp.s))
        if (still := lift_within_noise(case, lift)) is not None:  # a lift of noise: the ratio says nothing
            warnings.append(still)
        else:
            # compression only: where the follower flies above the cam (x > s) the train is unloaded, not stretched
            deflection = float(np.max(np.clip(resp.s - resp.x, 0.0, None))) / lift if lift > 0.0 else 0.0
            checks_train = (CheckKind.TRAIN_DEFLECTION.check(deflection, float(limits.max_train_deflection)),)
    kin_force = resp.kinematic_force
    i_kin = int(kin_force.argmin())
    least = resp.min_force if valve is None else valve.response.least_event_force  # a valve: over its event
    if valve is not None:
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
            at_contact(case, resp.residual_vibration, resp.residual_vibration_deg) if osc else resp.residual_vibration
        ),
        periodicity_error=resp.periodicity_error,
        spring=case.spring,
        residual_vibration_rad=resp.residual_vibration if osc else None,
        period_revolutions=resp.period_revolutions,
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
