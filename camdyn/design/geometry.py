"""The cam's geometry judged: pressure angle, curvature (undercut) and face width against the limits, and the
least base radius that would meet them (:func:`camdyn.model.geometry.min_base_radius`, re-exported here)."""

from __future__ import annotations

import math

from .._core.errors import NumericalError
from .._core.units import DEFAULT_MIN_CURVATURE_RATIO
from ..model.geometry import CamGeometry, curvature_limit, min_base_radius
from ..schema import FollowerSpec
from ._check import Check, CheckKind

JAM_PRESSURE_ANGLE_DEG = 60.0  # beyond this a translating follower may jam in its guide: a warning


def _limits(f: FollowerSpec, max_pressure_angle: float | None) -> float:
    return f.kind.default_max_pressure_angle_deg if max_pressure_angle is None else max_pressure_angle


def judge_geometry(
    geo: CamGeometry,
    motion,
    *,
    max_pressure_angle: float | None = None,
    min_curvature_ratio: float = DEFAULT_MIN_CURVATURE_RATIO,
) -> tuple[list[Check], list[str], list[str]]:
    """The geometry checks of a cam (pressure angle, curvature, face width), its warnings and advice.

    ``max_pressure_angle`` deg (None: 30 translating, 35 oscillating); ``min_curvature_ratio``: the least convex
    contour radius of curvature over the roller radius (flat followers: the contour radius must stay above
    :data:`camdyn._core.units.CUSP_MM`, a cusp). Advice: the least base radius that meets both limits.
    """
    f, ext = geo.follower, geo.extremes
    max_pa = _limits(f, max_pressure_angle)
    checks = [CheckKind.PRESSURE_ANGLE.check(ext.max_pressure_angle_deg, max_pa)]
    checks.append(
        CheckKind.CURVATURE.check(ext.curvature, curvature_limit(f, min_curvature_ratio), None if f.roller else "mm")
    )
    width = ext.face_travel_mm
    if width is not None and f.face_width is not None:
        checks.append(CheckKind.FACE_WIDTH.check(width, f.face_width))

    warnings: list[str] = []
    if ext.cusp:
        what = "the roller radius reaches the pitch curve's convex radius" if f.roller else "rho = Rb + s + s'' <= 0"
        warnings.append(
            f"undercut: the contour folds ({what}); least radius {ext.min_radius_of_curvature_mm:.4g} mm at "
            f"{ext.min_radius_of_curvature_at_deg:.4g} deg"
        )
    if ext.max_pressure_angle_deg >= JAM_PRESSURE_ANGLE_DEG:
        warnings.append(
            f"pressure angle {ext.max_pressure_angle_deg:.3g} deg at {ext.max_pressure_angle_at_deg:.4g} deg: the "
            "follower may jam"
        )

    advice: list[str] = []
    if not all(c.ok for c in checks[:2]):
        try:
            rb = min_base_radius(
                motion, f, max_pressure_angle=max_pa, min_curvature_ratio=min_curvature_ratio, n=len(geo.theta_deg)
            )
            advice.append(
                f"base_radius >= {math.ceil(rb * 100) / 100:.2f} mm would meet the pressure-angle ({max_pa:g} deg) "
                "and curvature limits"
            )
        except NumericalError as err:
            advice.append(f"no base radius alone fixes this: {err.message}")
    if width is not None and f.face_width is not None and width > f.face_width:
        assert ext.face_range_mm is not None  # a flat face's travel is the span of its range
        t_min, t_max = ext.face_range_mm
        advice.append(
            f"face_width >= {width:.3f} mm: the contact runs from t = {t_min:.3f} to {t_max:.3f} mm along the face "
            f"(the face centred at t = {ext.face_centre_mm:.3f} mm)"
        )
    return checks, warnings, advice
