"""``camdyn table``: the follower motion, the kinematic contact force and the cam geometry per angle."""

from __future__ import annotations

import io

import jax.numpy as jnp
import numpy as np

from .._core.units import RPM
from ..model.case import Case
from ..model.dynamics import kinematic_force
from ..model.geometry import analyze, newton_per_torque_at
from ..model.motion import evaluate


def motion_table(case: Case, step_deg: float = 1.0) -> dict[str, np.ndarray]:
    """Columns of ``camdyn table`` (one row per angle), kinematic, at the case speed."""
    theta_deg = np.arange(0.0, 360.0 - 1e-9, step_deg)
    theta = jnp.deg2rad(theta_deg)
    vals = np.asarray(evaluate(case.motion, theta))
    force = np.asarray(kinematic_force(case.motion, case.model, case.speed_rpm * RPM, theta))
    cols = {"theta_deg": theta_deg}
    if case.oscillating:
        cols |= {"phi_deg": np.degrees(vals[0]), "phi1_per_rad": vals[1], "phi2_per_rad2": vals[2], "phi3_per_rad3": vals[3]}
        force = force * newton_per_torque_at(case.motion, case.follower, np.asarray(theta))
    else:
        cols |= {"s_mm": vals[0], "v_mm_per_rad": vals[1], "a_mm_per_rad2": vals[2], "j_mm_per_rad3": vals[3]}
    cols["contact_force_N"] = force
    if case.follower is not None:
        cols |= analyze(case.motion, case.follower).table(theta_deg)
    return cols


def csv_text(cols: dict[str, np.ndarray]) -> str:
    """The columns as CSV text with a header row."""
    buf = io.StringIO()
    buf.write(",".join(cols) + "\n")
    np.savetxt(buf, np.column_stack(list(cols.values())), delimiter=",", fmt="%.10g")
    return buf.getvalue()
