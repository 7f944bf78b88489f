"""The cam's geometry judged: pressure angle, curvature (undercut) and face width against the limits, and the
least base radius that would meet them."""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import NumericalError
from .._core.units import CUSP_MM, DEFAULT_MIN_CURVATURE_RATIO, THETA_GRID, default_max_pressure_angle
from ..model.geometry import CamGeometry, GeometryExtremes, check_assembly, extremes
from ..schema import FollowerSpec
from ._check import Check, CheckKind

JAM_PRESSURE_ANGLE_DEG = 60.0  # beyond this a translating follower may jam in its guide: a warning


def _limits(f: FollowerSpec, max_pressure_angle: float | None) -> float:
    return default_max_pressure_angle(f.translating) if max_pressure_angle is None else max_pressure_angle


def _curvature_limit(f: FollowerSpec, min_curvature_ratio: float) -> float:
    return min_curvature_ratio if f.roller else CUSP_MM


def passes(f: FollowerSpec, ext: GeometryExtremes, max_pressure_angle: float, min_curvature_ratio: float) -> bool:
    """Whether the pressure-angle and curvature checks pass on these extremes."""
    return ext.max_pressure_angle_deg <= max_pressure_angle and not ext.cusp and ext.curvature >= _curvature_limit(f, min_curvature_ratio)


def judge_geometry(
    geo: CamGeometry, motion, *, max_pressure_angle: float | None = None, min_curvature_ratio: float = DEFAULT_MIN_CURVATURE_RATIO
) -> tuple[list[Check], list[str], list[str]]:
    """The geometry checks of a cam (pressure angle, curvature, face width), its warnings and advice.

    ``max_pressure_angle`` deg (None: 30 translating, 35 oscillating); ``min_curvature_ratio``: the least convex
    contour radius of curvature over the roller radius (flat followers: the contour radius must stay above
    :data:`camdyn._core.units.CUSP_MM`, a cusp). Advice: the least base radius that meets both limits.
    """
    f, ext = geo.follower, geo.extremes
    max_pa = _limits(f, max_pressure_angle)
    checks = [Check(CheckKind.PRESSURE_ANGLE.value, ext.max_pressure_angle_deg, max_pa, "deg", "<=")]
    checks.append(Check(CheckKind.CURVATURE.value, ext.curvature, _curvature_limit(f, min_curvature_ratio), "ratio" if f.roller else "mm", ">="))
    width = ext.face_travel_mm
    if width is not None and f.face_width is not None:
        checks.append(Check(CheckKind.FACE_WIDTH.value, width, f.face_width, "mm", "<="))

    warnings: list[str] = []
    if ext.cusp:
        what = "the roller radius reaches the pitch curve's convex radius" if f.roller else "rho = Rb + s + s'' <= 0"
        warnings.append(f"undercut: the contour folds ({what}); least radius {ext.min_radius_of_curvature_mm:.4g} mm at {ext.min_radius_of_curvature_at_deg:.4g} deg")
    if ext.max_pressure_angle_deg >= JAM_PRESSURE_ANGLE_DEG:
        warnings.append(f"pressure angle {ext.max_pressure_angle_deg:.3g} deg at {ext.max_pressure_angle_at_deg:.4g} deg: the follower may jam")

    advice: list[str] = []
    if not all(c.ok for c in checks[:2]):
        try:
            rb = min_base_radius(motion, f, max_pressure_angle=max_pa, min_curvature_ratio=min_curvature_ratio, n=len(geo.theta_deg))
            advice.append(f"base_radius >= {math.ceil(rb * 100) / 100:.2f} mm would meet the pressure-angle ({max_pa:g} deg) and curvature limits")
        except NumericalError as err:
            advice.append(f"no base radius alone fixes this: {err.message}")
    if width is not None and f.face_width is not None and width > f.face_width:
        t_min, t_max = ext.face_range_mm
        advice.append(f"face_width >= {width:.3f} mm: the contact runs from t = {t_min:.3f} to {t_max:.3f} mm along the face")
    return checks, warnings, advice


def min_base_radius(
    motion, follower: FollowerSpec, *, max_pressure_angle: float | None = None, min_curvature_ratio: float = DEFAULT_MIN_CURVATURE_RATIO, n: int = THETA_GRID
) -> float:
    """The least base radius (mm) meeting the pressure-angle (deg) and curvature limits, to 1e-6 mm.

    The pressure angle falls and the pitch curve flattens as the base circle grows, so the limits hold above
    one threshold; a coarse scan first finds a passing radius (guarding against non-monotone oscillating
    layouts), then bisection. Oscillating layouts bound Rb by the pivot and arm; raises
    :class:`NumericalError` if no admissible base radius passes.
    """
    f = follower
    max_pa = _limits(f, max_pressure_angle)
    check_assembly(motion, f)
    rr = f.roller_radius or 0.0

    def ok(rb: float) -> bool:
        try:
            return passes(f, extremes(motion, f, base_radius=rb, n=n), max_pa, min_curvature_ratio)
        except NumericalError:  # a degenerate layout at this radius: not a solution
            return False

    span = max(extremes(motion, f, n=n).lift_range, 1e-3)  # lift (mm): a scale for the search
    if f.type == "translating-roller":
        lo = max(abs(f.offset) - rr, 0.0) * (1 + 1e-9) + 1e-9
        hi = max(f.base_radius, lo, span)
        while not ok(hi):  # the pressure angle -> 0 and the pitch curve flattens as Rb -> infinity
            hi *= 2.0
            if hi > 1e6 * max(span, rr, 1.0):
                raise NumericalError("follower.base_radius", "no base radius meets the limits")
    elif f.type == "translating-flat":
        lo, hi = 1e-9, max(f.base_radius, span)
        while not ok(hi):
            hi *= 2.0
            if hi > 1e6 * span:
                raise NumericalError("follower.base_radius", "no base radius meets the limits")
    else:  # bounded by the assembly conditions of check_assembly
        L = f.pivot_distance
        if f.roller:
            lo, hi = max(abs(L - f.arm_length) - rr, 0.0), L + f.arm_length - rr
        else:
            lo, hi = max(-L - f.offset, 0.0), L - f.offset
        lo, hi = lo + 1e-6 * (hi - lo), hi - 1e-6 * (hi - lo)
        if hi <= lo:
            raise NumericalError("follower.base_radius", "no admissible base radius for this pivot and arm")
    grid = np.linspace(lo, hi, 33)
    good = [i for i, rb in enumerate(grid) if ok(rb)]
    if not good:
        raise NumericalError("follower.base_radius", f"no base radius in ({lo:.4g}, {hi:.4g}) mm meets the limits; move the pivot or change the arm")
    if good[0] == 0:
        return float(grid[0])
    a, b = grid[good[0] - 1], grid[good[0]]
    for _ in range(200):  # halves down to 1e-6 mm from any bracket a float can hold
        if b - a <= 1e-6:
            break
        mid = 0.5 * (a + b)
        a, b = (a, mid) if ok(mid) else (mid, b)
    return float(b)
