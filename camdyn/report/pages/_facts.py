"""Page 1's facts as text: the key results (:func:`key_results`) and every fact of the later pages that changes a
decision about the design (:func:`decision_facts`), a line each, for the summary page to set."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..._core.results import Unavailable
from ..._core.units import AT_LIMIT_RTOL
from ...model.geometry import GrooveGeometry
from ...plot import flank_names, flight_summary, flights_by_gap, square_face, svaj_quantities
from .._data import ReportData
from .._layout import fmt

if TYPE_CHECKING:
    from ...design.checks import Check
    from ...model.geometry import CamGeometry

IN_FACTS = (
    "velocity jumps by",
    "acceleration jumps by",
    "the follower leaves the cam ",  # at ..., or N times a revolution: the flights fact says it
    "speed_margin and contact_force do not apply",  # a groove cam: the no-jump fact says it
    "the contact force changes flank",  # a groove cam: the crossover facts say it
)  # warnings page 1 lists as facts


def at_limit(c: Check) -> bool:
    """Whether a check's value is within :data:`~camdyn._core.units.AT_LIMIT_RTOL` of its (nonzero) limit."""
    return c.value is not None and c.limit != 0.0 and abs(c.value - c.limit) <= AT_LIMIT_RTOL * abs(c.limit)


def key_results(data: ReportData) -> list[tuple[str, str]]:
    """(label, value) of the summary's key results."""
    chk = data.check
    if chk.closure is not None:
        return _groove_results(data) + _geometry_results(data)
    if chk.valvetrain is not None:
        return valvetrain_results(data) + _geometry_results(data)
    dyn, kin = chk.dynamic, chk.kinematic
    resp = chk.response
    seps = resp.separations
    if seps:  # the least force is 0 over the flights: where the follower leaves (the largest flight) says more
        least = f"{dyn.min_contact_force_N:.4g} N: leaves the cam at {flights_by_gap(resp)[0].start_deg:.1f}\u00b0"
    else:
        least = f"{dyn.min_contact_force_N:.4g} N at {dyn.min_contact_force_deg:.1f}\u00b0"
    rows = [
        ("least force, dynamic", least),
        (
            "least force, kinematic",
            f"none: the cam's velocity steps at {kin.jump_speed_at_deg:.1f}\u00b0 (an infinite pull)"
            if kin.thrown_off
            else f"{kin.min_contact_force_N:.4g} N at {kin.min_contact_force_deg:.1f}\u00b0",
        ),
        ("jump speed, dynamic", f"{fmt(dyn.jump_speed_rpm)} rpm"),
        (
            "jump speed, rigid",
            f"{fmt(kin.jump_speed_rpm)} rpm"
            + (f" (at {kin.jump_speed_at_deg:.1f}\u00b0)" if kin.jump_speed_at_deg is not None else ""),
        ),
    ]
    flights, impacts = resp.flights, resp.impacts
    if flights:  # what the shading on the force plots is: spans of zero force, and the landings between them
        gap = max(f.max_gap for f in flights) * data.to_display
        rows.append(
            (
                "flights (force 0)",
                f"{len(flights)}, first at {min(f.leave_deg for f in flights):.1f}\u00b0; gap up to {gap:.3g} "
                f"{data.unit}",
            )
        )
        top = [i for i in impacts if math.isfinite(i.peak_force)]
        if top:
            big = max(top, key=lambda i: i.peak_force)
            rows.append(("impacts", f"{len(impacts)}, largest {big.peak_force:.4g} N at {big.peak_deg:.1f}\u00b0"))
        else:
            rows.append(
                ("impacts", f"{len(impacts)}" + (" (rigid: impulsive)" if impacts else ", never back on the cam"))
            )
    else:
        rows.append(("flights", "none: in contact all round"))
    if data.case.motion.dwells_deg:
        rv = chk.response.residual_vibration * data.to_display
        rows.append(("residual vibration", f"{rv:.3g} {data.unit}"))
    else:  # it is judged in the dwells: 0 would read as a measurement
        rows.append(("residual vibration", "none: no dwell to judge it in"))
    return rows + _geometry_results(data)


def _speed(rpm: float, top_rpm: float) -> str:
    return f"{rpm:.4g} rpm" if math.isfinite(rpm) else f"none up to {top_rpm:.4g} rpm"


def valvetrain_results(data: ReportData) -> list[tuple[str, str]]:
    """A valvetrain's key results, the two-mass model's (what its checks judge): the least cam-contact force over
    the valve event, the float and bounce speeds, the seating velocity and bounce height at the case speed, the
    coil-bind clearance with a designed spring; the equivalent single follower's rigid jump speed, labelled so."""
    chk = data.check
    vt = chk.valvetrain
    assert vt is not None
    r = vt.response
    opening, closing = vt.timing_deg
    least = r.least_event_force
    if r.floated:
        force = f"0 N: floats at {r.least_event_force_deg:.1f}\u00b0"
    elif math.isfinite(least):
        force = f"{least:.4g} N at {r.least_event_force_deg:.1f}\u00b0"
    else:
        force = "no valve event"
    seat = vt.seating_velocity
    rows = [
        ("least cam force, event", force),
        ("float speed", _speed(vt.float_speed_rpm, vt.search_top_rpm)),
        ("bounce speed", _speed(vt.bounce_speed_rpm, vt.search_top_rpm)),
        ("seating velocity", f"{seat:.3g} m/s" if math.isfinite(seat) else "the valve never lifts"),
        ("bounce height", f"{r.bounce_height_mm:.3g} mm"),
        (
            "valve lift",
            f"{r.max_valve_lift_mm:.4g} mm, open {opening:.1f} to {closing:.1f}\u00b0"
            if math.isfinite(opening) and math.isfinite(closing)
            else f"{r.max_valve_lift_mm:.4g} mm",
        ),
    ]
    clearance = vt.coil_bind_clearance_mm
    if clearance is not None:
        rows.append(("coil-bind clearance", f"{clearance:.3g} mm" + (" (goes solid)" if clearance < 0.0 else "")))
    rows.append(("equivalent follower", f"rigid jump {fmt(chk.kinematic.jump_speed_rpm)} rpm (one mass, no lash)"))
    return rows


def _groove_results(data: ReportData) -> list[tuple[str, str]]:
    """A groove cam's key results: the signed force on each flank, the crossovers and their impacts; no jump."""
    chk = data.check
    assert chk.closure is not None
    r, force, th = chk.closure.response, chk.response.force, chk.response.theta_deg
    i, j = int(np.argmax(force)), int(np.argmin(force))
    plus, minus = flank_names(chk)
    loads = chk.closure.loads
    preloaded = loads is not None and r.backlash_mm == 0.0  # a preload and a backlash exclude each other
    # preloaded cams each carry the preload plus or minus half the signed force: that one is the net force
    signed = "net force" if preloaded else "force"
    rows = [
        (f"{signed}, {plus}", f"up to {force[i]:.4g} N at {th[i]:.1f}\u00b0"),
        (f"{signed}, {minus}", f"up to {-force[j]:.4g} N at {th[j]:.1f}\u00b0" if force[j] < 0.0 else "never"),
        ("jump speed", "none: form-closed"),
        (
            "crossovers",
            f"{len(r.crossovers)}"
            + (f", at {', '.join(f'{c.deg:.1f}' for c in r.crossovers[:4])}\u00b0" if r.crossovers else ""),
        ),
    ]
    if r.crossovers and r.backlash_mm > 0.0:
        top = max(r.crossovers, key=lambda c: c.impact_velocity_m_per_s)
        rows.append(("largest impact", f"{top.impact_velocity_m_per_s:.3g} m/s at {top.land_deg:.1f}\u00b0"))
        f = r.max_impact_force_N
        rows.append(("impact force", "impulse (rigid train)" if f is None else f"up to {f:.4g} N"))
    if preloaded:
        assert loads is not None  # preloaded says so
        unit = "N" if loads.translating else "N\u00b7m"
        cams = (("primary", loads.primary_N), ("conjugate", loads.conjugate_N))
        k, cam = min((float(np.min(v)), n) for n, v in cams)
        top, at, top_cam = max((float(np.max(v)), float(loads.theta_deg[np.argmax(v)]), n) for n, v in cams)
        rows.append(("preload", f"{loads.preload:g} {unit}: " + ("held" if loads.preload_held else "NOT held")))
        rows.append(("largest cam force", f"{top:.4g} N at {at:.1f}\u00b0 (the {top_cam} cam's)"))
        rows.append(("least cam force", f"{k:.4g} N (the {cam} cam's)"))
    return rows


def _geometry_results(data: ReportData) -> list[tuple[str, str]]:
    """The key results of the cam's geometry: pressure angle, face contact, radius of curvature, path error."""
    chk, case = data.check, data.case
    rows: list[tuple[str, str]] = []
    geo = chk.geometry
    if geo is not None:
        if square_face(geo):
            rows.append(("pressure angle", "0 all round (face square to its motion)"))
        else:
            rows.append(
                (
                    "max pressure angle",
                    f"{geo.max_pressure_angle_deg:.2f}\u00b0 at {geo.max_pressure_angle_at_deg:.1f}\u00b0",
                )
            )
        if geo.extremes.face_range_mm is not None:
            t_lo, t_hi = geo.extremes.face_range_mm
            rows.append(
                (
                    "contact on the face",
                    f"t = {t_lo:+.2f} to {t_hi:+.2f} mm (face centred at {geo.extremes.face_centre_mm:+.2f})",
                )
            )
        least, at, folded = geo.min_radius_of_curvature_mm, geo.min_radius_of_curvature_at_deg, geo.undercut
        if chk.closure is not None and isinstance(chk.closure.walls, GrooveGeometry):  # b/2 inside the cam contour
            inner = chk.closure.groove.inner_wall
            least, at, folded = inner.min_convex_radius_mm, inner.min_convex_radius_at_deg, inner.undercut
        rows.append(
            (
                "least radius of curvature" if chk.closure is None else f"{_flanks(data)[0]}, least radius",
                f"{least:.4g} mm at {at:.1f}\u00b0" + ("  (undercut)" if folded else ""),
            )
        )
    if chk.closure is not None:  # the outer wall (convex where the pitch curve is concave), or the conjugate cam
        second = chk.closure.conjugate if chk.closure.loads is not None else None
        w = second.convex if second is not None else chk.closure.groove.outer_wall
        if second is not None:
            rows.append(
                (
                    "conjugate, max angle",
                    f"{second.max_pressure_angle_deg:.2f}\u00b0 at {second.max_pressure_angle_at_deg:.1f}\u00b0",
                )
            )
        rows.append(
            (
                f"{_flanks(data)[1]}, least convex",
                "concave all round"
                if math.isinf(w.min_convex_radius_mm)
                else f"{w.min_convex_radius_mm:.4g} mm at {w.min_convex_radius_at_deg:.1f}\u00b0",
            )
        )
    if case.synthesis is not None:
        rows.append(("path error", f"{case.synthesis.summary['max_path_error_mm']:.3g} mm"))
    return rows


def decision_facts(data: ReportData) -> list[str]:
    """Every fact on the later pages that changes a decision about the design, in a line each: checks at their
    limit, flights and impacts, a return spring that cannot be built, the tolerance study's result, velocity and
    acceleration jumps, concave flanks."""
    chk, rv = data.check, data.review
    out = []
    if chk.closure is not None:
        out += groove_facts(data)
    for c in chk.checks:
        if at_limit(c):
            out.append(
                f"{c.name} at limit: {c.value:.6g} against {c.limit:g} {c.unit} (within {100 * AT_LIMIT_RTOL:g} %: "
                f"{'passes' if c.ok else 'fails'} by a rounding)"
            )
    resp = chk.response
    if resp.flights and chk.closure is None:
        out.append(f"the follower leaves the cam: {flight_summary(resp)}")
    part = rv.spring_part
    if chk.closure is not None:
        pass  # no return spring: groove_facts says so
    elif isinstance(part, Unavailable):
        out.append(f"the return spring cannot be built within [spring]: {part}")
    else:
        bad = [c.name for c in part.checks if not c.ok]
        if bad:
            out.append(f"the return spring fails its own checks: {', '.join(bad)}")
    tol = rv.tolerance
    if isinstance(tol, Unavailable):
        out.append(f"tolerance study failed: {tol}")
    elif tol is not None:
        lo, hi = tol.confidence_interval
        p1 = tol.percentiles(tol.jump_speed_rpm)["p1"]
        out.append(
            f"tolerances: P(separation) at {tol.speed_rpm:g} rpm = {tol.probability:.3g} ({100 * tol.confidence:g} % "
            f"interval {lo:.3g} to {hi:.3g}, {tol.samples} built cams); 1 % of the cams jump below {p1:.1f} rpm"
        )
    names = svaj_quantities(data.case.motion.unit)
    for order, what, cause in ((1, "velocity", "acceleration"), (2, "acceleration", "jerk")):
        js = [(d, j) for d, o, j in data.jumps if o == order]
        if js:
            listed = ", ".join(f"{j:+.3g} at {d:.1f}\u00b0" for d, j in js[:4]) + (", \u2026" if len(js) > 4 else "")
            out.append(
                f"{what} jumps at {len(js)} boundar{'ies' if len(js) > 1 else 'y'} ({names[order][1]}): {listed}: "
                f"infinite {cause}"
            )
    geo = chk.geometry
    if geo is not None and not geo.undercut and chk.closure is None:  # a groove: one wall is concave by design
        spans = concave_spans(geo)
        if spans:
            where = ", ".join(f"{a:.0f}\u2013{b:.0f}\u00b0" for a, b, _ in spans[:3])
            least = min(r for _, _, r in spans)
            out.append(
                f"concave flank{'s' if len(spans) > 1 else ''} at cam angles {where}: least concave radius "
                f"{least:.4g} mm (the grinding wheel or cutter must be smaller)"
            )
    return out


def conjugate(data: ReportData) -> bool:
    return data.check.closure is not None and data.check.closure.loads is not None


def holder(data: ReportData) -> str:
    """What holds a form-closed follower both ways."""
    return "the two conjugate cams hold" if conjugate(data) else "the groove holds"


def _flanks(data: ReportData) -> tuple[str, str]:
    """A form-closed cam's two contours: a groove's walls, or the conjugate cams."""
    return ("primary", "conjugate") if conjugate(data) else ("inner wall", "outer wall")


def groove_facts(data: ReportData) -> list[str]:
    """A form-closed cam's decision-changing facts: that it cannot jump (no jump speed, no speed margin, no return
    spring: why the spring pages are left out), whether conjugate cams' preload holds both rollers on their cams
    (and the least cam force), and each crossover's flight and impact against the limit."""
    study = data.check.closure
    assert study is not None
    r = study.response
    out = [
        f"no jump speed and no speed_margin: {holder(data)} the follower both ways, so it cannot jump; there is no "
        "return spring to size (no spring sizing or jump map pages); what limits the speed is "
        + (
            "the preload that keeps both rollers loaded, or with backlash the impact where the follower crosses it"
            if conjugate(data)
            else "the impact where the follower crosses the backlash"
        )
        + " (crossover_impact)"
    ]
    loads = study.loads
    if loads is not None and r.backlash_mm == 0.0:  # a preload and a backlash exclude each other
        unit = "N" if loads.translating else "N\u00b7m"
        k, cam = min((float(np.min(v)), n) for n, v in (("primary", loads.primary_N), ("conjugate", loads.conjugate_N)))
        net = float(np.max(np.abs(r.contact_force)))
        if loads.preload_held:
            out.append(
                f"the preload {loads.preload:g} {unit} holds both rollers on their cams all round: the least cam force "
                f"is {k:.4g} N (the {cam} cam's); it holds while the preload exceeds half the largest net force "
                f"({0.5 * net:.4g} {unit})"
            )
        else:
            out.append(
                f"the preload {loads.preload:g} {unit} does not hold both rollers: the {cam} cam unloads (force "
                f"{k:.4g} N); holding needs more than half the largest net force ({0.5 * net:.4g} {unit}; camdyn size)"
            )
    lim = data.case.limits.max_impact_velocity
    for c in r.crossovers[:4]:
        if r.backlash_mm == 0.0:
            what = "flank" if loads is None else "cam"
            out.append(f"the net force changes from the {c.from_flank} to the {c.to_flank} {what} at {c.deg:.1f}\u00b0")
            continue
        force = "an impulse (rigid train)" if c.impact_force_N is None else f"a peak of {c.impact_force_N:.4g} N"
        out.append(
            f"at {c.deg:.1f}\u00b0 the force leaves the {c.from_flank} flank: the follower crosses the "
            f"{r.backlash_mm:g} mm backlash and the {c.to_flank} flank meets it at {c.land_deg:.1f}\u00b0 at "
            f"{c.impact_velocity_m_per_s:.3g} m/s (limit {lim:g} m/s), {force}"
        )
    if len(r.crossovers) > 4:
        out.append(f"\u2026 and {len(r.crossovers) - 4} more crossovers (page 'Dynamics: crossovers and impacts')")
    if data.case.spec.tolerances is not None:
        out.append(
            "[tolerances]: the report does not draw a form-closed cam's tolerance study: camdyn tolerance gives the "
            "spread of its impact speed over the built cams (of preloaded conjugate cams: their least cam force)"
        )
    return out


def concave_spans(geo: CamGeometry) -> list[tuple[float, float, float]]:
    """(first deg, last deg, least |radius| mm) of each run of cam angles where the contour is concave."""
    concave = np.asarray(geo.rho_contour_mm) < 0.0
    if not concave.any() or concave.all():
        return []
    th, rho = np.asarray(geo.theta_deg), np.abs(np.asarray(geo.rho_contour_mm))
    n = th.size
    shift = int(np.argmin(concave))
    idx = (np.arange(n) + shift) % n
    c = concave[idx].astype(np.int8)
    starts = np.flatnonzero(np.diff(np.concatenate([[0], c])) == 1)
    ends = np.flatnonzero(np.diff(np.concatenate([c, [0]])) == -1)
    return sorted(
        (float(th[idx[a]]), float(th[idx[b]]), float(rho[idx[a : b + 1]].min()))
        for a, b in zip(starts, ends, strict=True)
    )
