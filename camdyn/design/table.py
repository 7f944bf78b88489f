"""``camdyn table``: the follower motion, the contact force (kinematic and dynamic) and the cam geometry per angle."""

from __future__ import annotations

import io

import jax.numpy as jnp
import numpy as np

from .._core.limits import check_ecam_points, check_table_step
from .._core.units import RPM
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.drive import camshaft_torque
from ..model.geometry import analyze, contact_per_force
from ..model.motion import evaluate
from .checks import forces_in_newton
from .closure import closure_study


def table_angles(step_deg: float) -> np.ndarray:
    """Cam angles (deg) from 0 in steps of ``step_deg`` below 360; :class:`InputError` for a step that is not in
    (0, 360] or makes more than :data:`~camdyn._core.limits.MAX_ROWS` rows."""
    check_table_step(step_deg)
    return np.arange(0.0, 360.0 - 1e-9, step_deg)


def motion_table(case: Case, step_deg: float = 1.0, speed_rpm: float | None = None) -> dict[str, np.ndarray]:
    """Columns of ``camdyn table`` (one row per angle) at ``speed_rpm`` (default: the case's): the motion, the
    kinematic contact force, the follower's steady-state displacement and contact force from the dynamic model
    (interpolated from its 0.1 deg grid), and the cam geometry; a valvetrain's valve lift and velocity."""
    theta_deg = table_angles(step_deg)
    rpm = float(case.speed_rpm if speed_rpm is None else speed_rpm)
    theta = jnp.asarray(np.deg2rad(theta_deg))
    vals = np.asarray(evaluate(case.motion, theta))
    force = np.asarray(dyn.kinematic_force_jit(case.motion, case.model, rpm * RPM, theta))  # one program
    study = None
    if case.follower is not None and case.follower.form_closed:  # signed: positive on the inner flank, 0 in flight
        study = closure_study(case, rpm)
        resp = study.on_its_cam(case, forces_in_newton(case, study.as_response(case)))
    else:
        resp = forces_in_newton(case, dyn.response(case.motion, case.model, rpm * RPM))
    at = lambda y: np.interp(theta_deg, resp.theta_deg, y, period=360.0)  # noqa: E731
    kind = case.kind
    cols = {"theta_deg": theta_deg}
    cols |= dict(zip(kind.table_columns, (kind.motion_to_lift(vals[0]), *vals[1:]), strict=True))
    per_force = contact_per_force(case.motion, case.follower, np.asarray(theta))  # an arm's torque -> N
    force = force * per_force
    torque = camshaft_torque(force / per_force, vals[1] * case.model.scale)
    cols["contact_force_N"] = force if study is None else study.force_on_its_cam(case, theta_deg, force)
    if case.follower is not None:
        cols |= analyze(case.motion, case.follower).table(theta_deg)
    cols[kind.dynamic_column] = kind.motion_to_lift(at(resp.x))
    cols["dynamic_contact_force_N"] = at(resp.force)
    if case.valvetrain is not None:  # the valve at the valve, from the two-mass model's steady revolution
        valve = dyn.valvetrain_response(case.motion, case.valvetrain, rpm * RPM)
        cols["valve_lift_mm"] = np.interp(theta_deg, valve.theta_deg, valve.valve_lift, period=360.0)
        cols["valve_velocity_m_per_s"] = np.interp(theta_deg, valve.theta_deg, valve.valve_velocity, period=360.0)
    cols["drive_torque_N_m"] = torque  # the camshaft torque of the kinematic force, from the power balance
    if study is not None and study.loads is not None:  # conjugate cams: the second cam and each cam's force
        cols |= study.conjugate.table(theta_deg)
        cols["primary_cam_force_N"] = np.interp(theta_deg, study.loads.theta_deg, study.loads.primary_N, period=360.0)
        cols["conjugate_cam_force_N"] = np.interp(
            theta_deg, study.loads.theta_deg, study.loads.conjugate_N, period=360.0
        )
    return cols


def ecam_table(case: Case, n: int) -> tuple[dict[str, np.ndarray], str]:
    """A servo e-cam table: ``n`` evenly spaced master angles (deg, from 0 below 360) and the follower's position,
    velocity and acceleration per master degree (mm, mm/deg, mm/deg^2; oscillating deg, deg/deg, deg/deg^2), the
    units a drive's cam table takes (slave units per master unit). Returns the columns and a line naming the units."""
    check_ecam_points(n)
    master = np.arange(n) * (360.0 / n)
    s, v, a, _ = np.asarray(evaluate(case.motion, jnp.asarray(np.deg2rad(master))))
    rad = np.pi / 180.0  # per master degree: d/d(deg) = (pi / 180) d/d(rad)
    kind = case.kind
    s, v, a, unit = (
        kind.motion_to_lift(s),
        kind.motion_to_lift(v) * rad,
        kind.motion_to_lift(a) * rad**2,
        kind.lift_unit,
    )
    cols = {"master_deg": master, "position": s, "velocity": v, "acceleration": a}
    units = (
        f"master: cam angle, deg; position {unit}; velocity {unit}/deg; acceleration {unit}/deg^2 (per master degree)"
    )
    return cols, units


def csv_text(cols: dict[str, np.ndarray]) -> str:
    """The columns as CSV text with a header row."""
    buf = io.StringIO()
    buf.write(",".join(cols) + "\n")
    np.savetxt(buf, np.column_stack(list(cols.values())), delimiter=",", fmt="%.10g")
    return buf.getvalue()
