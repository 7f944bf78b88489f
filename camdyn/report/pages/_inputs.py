"""The key inputs of a case for page 1 of its report: the motion and follower (or the path and mechanism), the
dynamics and the limits, as (title, rows) columns of label and value with units."""

from __future__ import annotations

from ...design.checks import CheckKind
from .._data import ReportData
from .._layout import fmt

UNITS = {
    "base_radius": "mm",
    "roller_radius": "mm",
    "offset": "mm",
    "pivot_distance": "mm",
    "pivot_angle": "deg",
    "arm_length": "mm",
    "face_width": "mm",
    "speed": "rpm",
    "mass": "kg",
    "spring_rate": "N/mm",
    "preload": "N",
    "train_stiffness": "N/mm",
    "external_force": "N",
    "inertia": "kg\u00b7m\u00b2",
    "torsion_rate": "N\u00b7m/rad",
    "preload_torque": "N\u00b7m",
    "train_torsion_rate": "N\u00b7m/rad",
    "external_torque": "N\u00b7m",
    "speed_margin": "\u00d7",
    "min_contact_force": "N",
    "max_pressure_angle": "deg",
    "max_contact_stress": "MPa",
    "max_seating_velocity": "m/s",
    "max_impact_velocity": "m/s",
    "max_path_error": "mm",  # path cases
    "min_transmission_angle": "deg",
    "backlash": "mm",
    "width": "mm",
    "conjugate_spacing": "mm",  # closure = "conjugate"
    "conjugate_offset": "mm",
    "conjugate_arm_angle": "deg",
    "conjugate_arm_length": "mm",
    "conjugate_roller_radius": "mm",
    "conjugate_preload": "N",
    "conjugate_preload_torque": "N\u00b7m",
    "min_preload": "N",
    "lash": "mm",  # [valvetrain]
    "cam_side_mass": "kg",
    "valve_mass": "kg",
    "stiffness": "N/mm",
    "ramp_velocity": "mm/deg",
    "tappet_force": "N",
    "outside_diameter_max": "mm",  # [spring]
    "installed_length": "mm",
    "lever_arm": "mm",
    "cam_arm": "mm",  # [valvetrain.rocker]
    "valve_arm": "mm",
    "cam_arm_angle": "deg",
    "valve_arm_angle": "deg",
}
# keys whose values are pure numbers (ratios, fractions) or words: no unit on page 1
DIMENSIONLESS = frozenset(
    {"damping_ratio", "train_damping_ratio", "restitution", "seat_restitution", "ratio", "min_curvature_ratio"}
    | {"max_train_deflection", "type", "rotation", "closure", "contour"}
    | {"material", "end_type", "model", "max_active_coils"}  # [spring]
)
# limits of checks only some cases have: listed where the case has the check or the user set the limit
_LIMIT_OF_CHECK = {
    "max_seating_velocity": CheckKind.SEATING_VELOCITY,
    "max_impact_velocity": CheckKind.CROSSOVER_IMPACT,
    "max_path_error": CheckKind.PATH_ERROR,
    "min_transmission_angle": CheckKind.TRANSMISSION_ANGLE,
    "max_train_deflection": CheckKind.TRAIN_DEFLECTION,  # a compliant train's
}

# limits that judge a follower held on by a spring (it may jump): a groove cam has none of their checks
_SPRING_HELD_LIMITS = ("speed_margin", "min_contact_force", "min_preload", "max_train_deflection")


def _kv_lines(d: dict, oscillating: bool = False) -> list[tuple[str, str]]:
    out = []
    for k, v in d.items():
        unit = UNITS.get(k, "")
        if k == "damping":
            unit = "N\u00b7m\u00b7s/rad" if oscillating else "N\u00b7s/m"
        elif k == "min_preload" and oscillating:
            unit = "N\u00b7m"
        out.append((k, f"{fmt(v)} {unit if v is not None else ''}".strip()))  # "unbounded" takes no unit
    return out


def _geom_unit(key: str, value) -> str:
    """Unit of a [path] or [mechanism] value (lengths mm, angles deg)."""
    if isinstance(value, bool | str) or "mode" in key or key in ("phase", "reverse"):
        return ""
    if isinstance(value, list | tuple) and len(value) > 4:
        return ""
    return "deg" if ("angle" in key or key == "rotation") else "mm"


def input_columns(data: ReportData) -> list[tuple[str, list[tuple[str, str]]]]:
    """(title, rows) per column of the key inputs: the motion and follower, or the path and mechanism (with
    what the synthesis chose); the dynamics and the limits."""
    case = data.case
    spec = case.spec
    columns: list[tuple[str, list[tuple[str, str]]]] = []
    if case.motion_source in ("table", "valve_table", "contour"):
        columns.append((case.motion_source, _fit_rows(case)))
        columns.append(("follower", _kv_lines(case.follower.model_dump(exclude_unset=True))))
    elif spec.motion is not None:
        rows, start = [], 0.0
        lu = data.case.kind.lift_unit
        for seg in spec.motion.segments:
            lift = "" if seg.law == "dwell" else f"  {seg.lift:+g} {lu}"
            rows.append((f"{start:g}\u2013{seg.end:g}\u00b0", f"{seg.law}{lift}"))
            start = seg.end
        columns.append(("motion", rows))
        columns.append(("follower", _kv_lines(case.follower.model_dump(exclude_unset=True))))
    else:
        assert spec.path is not None  # CaseSpec: a case without [motion] or a contour has [path]
        path = spec.path.model_dump(exclude_unset=True)
        columns.append(("path", [(k, f"{fmt(v)} {_geom_unit(k, v)}".strip()) for k, v in path.items()]))
        columns.append(("mechanism (\u2192 synthesized)", _mechanism_rows(data)))
    if spec.valvetrain is not None:  # the train between the cam and the valve: under the follower
        title, rows = columns[-1]
        given = spec.valvetrain.model_dump(exclude_unset=True)
        rocker = given.pop("rocker", None)
        vt = _kv_lines(given) + ([] if rocker is None else [("\x00rocker", ""), *_kv_lines(rocker)])
        columns[-1] = (title, [*rows, ("", ""), ("\x00valvetrain", ""), *vt])
    dyn_rows = _kv_lines(spec.dynamics.model_dump(exclude_unset=True), data.oscillating)
    if spec.spring is not None:  # the spring as a part: its keys the user gave, under the dynamics they change
        part = spec.spring.model_dump(exclude_unset=True)
        dyn_rows += [(f"spring.{k}", v) for k, v in _kv_lines(part)]
    lim = spec.limits.model_dump()
    pa_check = data.check.find(CheckKind.PRESSURE_ANGLE)
    pa = None if pa_check is None else pa_check.limit
    if lim.get("max_pressure_angle") is None and pa is not None:
        lim["max_pressure_angle"] = pa
    for key, kind in _LIMIT_OF_CHECK.items():
        if data.check.find(kind) is None and key not in spec.limits.model_fields_set:
            lim.pop(key, None)
    curvature = data.check.find(CheckKind.CURVATURE)
    if curvature is not None and curvature.unit == "mm" and "min_curvature_ratio" not in spec.limits.model_fields_set:
        lim.pop("min_curvature_ratio", None)  # a flat face's contour is held above a cusp, not to a roller's ratio
    if data.check.closure is not None:
        for key in _SPRING_HELD_LIMITS:
            lim.pop(key, None)
    dyn_rows += [("", ""), ("\x00limits", "")] + _kv_lines(lim, data.oscillating)
    columns.append(("dynamics", dyn_rows))
    return columns


def _fit_rows(case) -> list[tuple[str, str]]:
    """The data file a table or contour case was fitted to, and how closely the fit follows it."""
    fit = case.contour or case.fit
    motion = case.spec.motion
    file = {"table": motion and motion.table, "valve_table": motion and motion.valve_table}.get(
        case.motion_source, case.spec.follower.contour
    )
    unit = fit.unit
    return [
        ("file", str(file)),
        ("points", f"{fit.point_count}"),
        ("max residual", f"{fmt(fit.max_residual)} {unit}"),
        ("rms residual", f"{fmt(fit.rms_residual)} {unit}"),
        ("noise", f"{fmt(fit.noise)} {unit}"),
    ] + ([("repeats dropped", f"{fit.repeats}")] if fit.repeats else [])


def _mechanism_rows(data: ReportData) -> list[tuple[str, str]]:
    case = data.case
    assert case.spec.mechanism is not None  # a synthesized case's [mechanism]
    mech = [
        (k, f"{fmt(v)} {_geom_unit(k, v)}".strip())
        for k, v in case.spec.mechanism.model_dump(exclude_unset=True).items()
    ]
    sm = case.synthesis.summary
    mech += [
        ("\u2192 crank", f"{sm['crank_mm']:.4g} mm"),
        ("\u2192 coupler", f"{sm['coupler_mm']:.4g} mm"),
        ("\u2192 base radius", f"{sm['base_radius_mm']:.4g} mm"),
    ]
    if "stroke_mm" in sm:
        mech.append(("\u2192 stroke", f"{sm['stroke_mm']:.4g} mm"))
    if "swing_deg" in sm:
        mech.append(("\u2192 swing", f"{sm['swing_deg']:.4g} deg"))
    mech.append(("\u2192 rotation", sm["rotation"]))
    return mech
