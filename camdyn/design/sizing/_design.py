"""What one spring (k, F0) does: its least and largest interface force over angles and speeds in [0, W]
(kinematic on the constraint grid; dynamic from the frequency-domain steady state for a compliant follower) and
its kinematic and dynamic jump speeds."""

from __future__ import annotations

import math

import numpy as np

from ..._core.units import RPM
from ...model import dynamics as dyn
from ._dynamic import Dynamic
from ._problem import Grid, Problem
from ._quadratic import least_quadratic, most_quadratic
from ._results import SpringDesign


def _kinematic_extremes(p: Problem, grid: Grid, k, f0):
    """Least and largest kinematic interface force (N) over the grid and [0, W], each (value, theta_deg,
    speed_rpm), and whether the spring alone keeps the force >= 0 at rest."""
    c = p.damping(k)
    base = k * grid.s + f0 + p.ext
    g_lo, w_lo = least_quadratic(p.m * grid.s2, c * grid.s1, p.W)
    g_hi, w_hi = most_quadratic(p.m * grid.s2, c * grid.s1, p.W)
    f_lo, f_hi = (base + g_lo) / grid.arm, (base + g_hi) / grid.arm
    i, j = int(np.argmin(f_lo)), int(np.argmax(f_hi))
    lo = (float(f_lo[i]), math.degrees(grid.theta[i]), float(w_lo[i]) / RPM)
    hi = (float(f_hi[j]), math.degrees(grid.theta[j]), float(w_hi[j]) / RPM)
    return lo, hi, bool(np.min(base) >= 0.0)


def design(p: Problem, grid: Grid, dynamic: Dynamic | None, k, f0) -> SpringDesign:
    """The spring (k, F0) (SI) evaluated; ``dynamic`` None for a rigid follower (dynamic = kinematic)."""
    kin_lo, kin_hi, holds_at_rest = _kinematic_extremes(p, grid, k, f0)
    model = p.with_spring(k, f0)
    w_kin = dyn.kinematic_jump_speed(p.motion, model)[0] if holds_at_rest else 0.0
    if dynamic is None:
        lo, hi, w_dyn = kin_lo, kin_hi, w_kin
    else:
        lo, hi, _ = dynamic.verify(k, f0)
        w_max = dyn.jump_search_limit(p.W, w_kin)
        w_dyn = dyn.dynamic_jump_speed(p.motion, model, w_max=w_max) if holds_at_rest else 0.0
    return SpringDesign(
        rate=p.kind.rate_from_si(k),
        preload=f0,
        peak_spring=k * p.s_max + f0,
        least_force_kinematic=kin_lo[0],
        least_force=lo[0],
        least_force_deg=lo[1],
        least_force_rpm=lo[2],
        peak_contact=hi[0],
        peak_contact_deg=hi[1],
        peak_contact_rpm=hi[2],
        kinematic_jump_rpm=w_kin / RPM,
        dynamic_jump_rpm=w_dyn / RPM,
    )
