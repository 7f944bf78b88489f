"""Page 3, the cam: its profile with the follower, the pressure angle and the radius of curvature."""

from __future__ import annotations

import math

from ...design.checks import CheckKind
from ...plot import (
    check_colour,
    face_extremes,
    plot_cam_profile,
    plot_curvature,
    plot_face_contact,
    plot_pressure_angle,
    square_face,
)
from .._data import ReportData
from .._style import LEFT, C


def draw_cam(fig, data: ReportData) -> None:
    geo, f, chk = data.check.geometry, data.case.follower, data.check
    assert geo is not None  # the page is drawn for a case with a cam geometry only (pages.PAGES)
    plot_cam_profile(fig.add_axes([0.08, 0.43, 0.84, 0.455]), geo, chk)
    _captions(fig, data)
    fig.text(
        0.08,
        0.94,
        f"cam and {f.type.replace('-', ' ')} follower; grey: the follower as the cam sees it at 0, 90, 180, 270\u00b0",
        size=9,
        weight="bold",
        va="top",
    )
    gs = fig.add_gridspec(2, 1, left=LEFT, right=0.95, top=0.37, bottom=0.06, hspace=0.35)
    ax1 = fig.add_subplot(gs[0])
    ax2 = fig.add_subplot(gs[1], sharex=ax1)
    if square_face(geo):  # its pressure angle is 0 all round: where the contact runs on the face matters
        plot_face_contact(ax1, geo, chk, breaks_deg=data.breaks_deg)
    else:
        plot_pressure_angle(ax1, geo, chk, breaks_deg=data.breaks_deg)
    ax1.tick_params(labelbottom=False)
    plot_curvature(ax2, geo, chk, min_curvature_ratio=data.case.limits.min_curvature_ratio, breaks_deg=data.breaks_deg)


def _captions(fig, data: ReportData) -> None:
    """What the coloured marks on the profile are: the largest pressure angle (on a face square to its motion:
    the ends of the contact's travel along it) and the least radius of curvature."""
    geo, chk = data.check.geometry, data.check
    assert geo is not None  # the page is drawn for a case with a cam geometry only (pages.PAGES)
    if square_face(geo):
        (t_lo, th_lo), (t_hi, th_hi) = face_extremes(geo)
        w = geo.follower.face_width
        fig.text(
            0.08,
            0.922,
            f"\u25cf contact on the face from t = {t_lo:+.1f} mm (\u03b8 = {th_lo:.1f}\u00b0) to {t_hi:+.1f} mm "
            f"(\u03b8 = {th_hi:.1f}\u00b0): "
            f"travel {t_hi - t_lo:.4g}" + (f" of face_width {w:g} mm" if w is not None else " mm"),
            size=7.8,
            color=check_colour(chk, CheckKind.FACE_WIDTH, C["margin"]),
            va="top",
        )
    else:
        fig.text(
            0.08,
            0.922,
            f"\u25cf max pressure angle {geo.max_pressure_angle_deg:.1f}\u00b0 at \u03b8 = "
            f"{geo.max_pressure_angle_at_deg:.1f}\u00b0: the follower there, "
            "its motion and the contact normal",
            size=7.8,
            color=check_colour(chk, CheckKind.PRESSURE_ANGLE, C["margin"]),
            va="top",
        )
    rho, th_r = geo.min_radius_of_curvature_mm, geo.min_radius_of_curvature_at_deg
    if math.isfinite(rho):
        fig.text(
            0.08,
            0.906,
            f"\u25cf least radius of curvature {rho:.3g} mm at \u03b8 = {th_r:.1f}\u00b0: the point on the contour "
            "and its osculating circle (dashed)",
            size=7.8,
            color=check_colour(chk, CheckKind.CURVATURE, C["advice"]),
            va="top",
        )
