"""``camdyn check`` of a form-closed cam (a groove or conjugate cams): the crossovers and their impacts across the
backlash judged, the geometry as any cam's."""

from __future__ import annotations

from ..model.case import Case
from ..model.geometry import analyze
from ._check import CheckKind
from ._check_report import CheckReport, Dynamics, Kinematics, forces_in_newton
from .closure import ClosureStudy, closure_study
from .geometry import judge_geometry
from .parts import case_contact, case_drive, contact_check


def closure_check(case: Case, rpm: float) -> CheckReport:
    """:func:`camdyn.design.checks.run_check` of a form-closed cam: the crossovers and their impacts judged, the
    geometry as any cam's; no jump speed (it cannot jump) and no least contact force (signed by design)."""
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
    geo_checks = [study.judged_curvature(c) if c.kind is CheckKind.CURVATURE else c for c in geo_checks]
    checks = (study.check(lim.max_impact_velocity), *geo_checks)
    checks += study.geometry_checks(geo_checks[0].limit, lim.min_curvature_ratio)
    checks += study.preload_check(lim.min_contact_force)
    warnings += geo_warnings
    warnings += study.fold_warnings
    contact = None
    if case.spec.contact_width_mm is not None:
        # a folded wall or cam: no radius of curvature to press on (a groove's walls are its contact; conjugate cams
        # press on both, the case's own contour too)
        if study.loads is None:
            folded = ["a groove wall"] if study.walls.undercut else []
        else:
            folded = [
                what for what, bad in (("the cam", geo.undercut), ("the conjugate cam", study.walls.undercut)) if bad
            ]
        if folded:
            warnings.append(
                f"contact stress not computed: {' and '.join(folded)} {'are' if len(folded) > 1 else 'is'} undercut"
            )
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
