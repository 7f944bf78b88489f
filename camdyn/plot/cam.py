"""The cam drawn: its profile with the follower, the pressure angle and the radius of curvature."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle, FancyArrowPatch, Polygon

from .._core.units import DEFAULT_MIN_CURVATURE_RATIO
from ..design.checks import CheckKind, CheckReport
from ..model.geometry import CamGeometry
from ._common import C, deg_ticks, legend_above_data, mark_breaks, rotate


def check_colour(check: CheckReport | None, kind: CheckKind, ok_colour: str) -> str:
    """``ok_colour`` where the check of ``kind`` passes (or is absent), the failure colour where it fails."""
    c = None if check is None else check.find(kind)
    return ok_colour if (c is None or c.ok) else C["fail"]


def check_limit(check: CheckReport | None, kind: CheckKind) -> float | None:
    c = None if check is None else check.find(kind)
    return None if c is None else c.limit


def square_face(geometry: CamGeometry) -> bool:
    """A flat face square to its motion (translating; or oscillating with the face line through the pivot): its
    pressure angle is 0 all round, and what matters instead is where the contact runs along the face."""
    return not geometry.follower.roller and geometry.max_pressure_angle_deg < 1e-6


def follower_pose(geometry: CamGeometry, theta_deg: float) -> dict:
    """The follower as the cam sees it at cam angle theta (cam frame, mm): roller centre (or face reference
    point) ``centre``, ``contact`` point, outward unit ``normal`` at the contact, the unit direction ``move`` in
    which the follower point at the contact moves for a positive lift, the arm ``pivot`` (None if translating)."""
    geo, f = geometry, geometry.follower
    row = geo.table(np.array([theta_deg]))
    centre = np.array([row["pitch_x_mm"][0], row["pitch_y_mm"][0]])
    contact = np.array([row["contour_x_mm"][0], row["contour_y_mm"][0]])
    back = -f.sigma * math.radians(theta_deg)  # fixed frame -> cam frame
    d = 0.01
    tt = geo.table(np.array([theta_deg - d, theta_deg + d]))
    tan = np.array([tt["contour_x_mm"][1] - tt["contour_x_mm"][0], tt["contour_y_mm"][1] - tt["contour_y_mm"][0]])
    normal = np.array([tan[1], -tan[0]]) / max(np.linalg.norm(tan), 1e-300)
    if normal @ contact < 0:  # outward
        normal = -normal
    if f.translating:
        move = rotate(back, np.array([0.0, 1.0]))
        pivot = None
    else:
        pa = math.radians(f.pivot_angle)
        pivot = rotate(back, f.pivot_distance * np.array([math.cos(pa), math.sin(pa)]))
        arm = contact - pivot
        move = np.array([-arm[1], arm[0]]) / np.linalg.norm(arm)
    if move @ normal < 0:
        move = -move
    return {"centre": centre, "contact": contact, "normal": normal, "move": move, "pivot": pivot, "back": back}


def _face_sense(geometry: CamGeometry) -> float:
    """+1 where t along a flat face counts the way of the contact normal turned anticlockwise, -1 the other
    way (taken where the contact is furthest from t = 0)."""
    i = int(np.argmax(np.abs(geometry.face_t_mm)))
    at = follower_pose(geometry, float(geometry.theta_deg[i]))
    along = np.array([-at["normal"][1], at["normal"][0]])
    return 1.0 if float((at["contact"] - at["centre"]) @ along) * float(geometry.face_t_mm[i]) >= 0.0 else -1.0


def plot_follower(
    ax: Axes,
    geometry: CamGeometry,
    theta_deg: float,
    *,
    colour: str,
    lw: float = 1.0,
    alpha: float = 1.0,
    stem: bool = True,
    z: float = 3,
) -> dict:
    """Draw the follower as the cam sees it at cam angle theta (cam frame); returns :func:`follower_pose`
    with the end of its stem, ``tip``."""
    f = geometry.follower
    assert f.base_radius is not None  # a built geometry has its base radius (from the contour where one is given)
    at = follower_pose(geometry, theta_deg)
    centre, contact = at["centre"], at["contact"]
    stem_len = 1.6 * (f.roller_radius or 0.15 * f.base_radius)
    if f.roller_radius is not None:
        ax.add_patch(Circle(centre, f.roller_radius, fill=False, ec=colour, lw=lw, alpha=alpha, zorder=z))
        ax.plot(*centre, marker=".", ms=2.5, color=colour, alpha=alpha, zorder=z)
        base = centre
    else:
        # the face as the face_width check takes it: face_width long (the contact's travel where none is
        # given), centred on the middle of the travel (t from the axis or the pivot's foot)
        along = _face_sense(geometry) * np.array([-at["normal"][1], at["normal"][0]])  # the way t counts
        t_along = float((contact - centre) @ along)
        mid = contact - along * t_along  # t = 0 on the face
        travel, c = geometry.face_travel_mm, geometry.face_centre_mm
        assert travel is not None and c is not None  # a flat face has its contact's travel
        half = 0.5 * (f.face_width or travel)
        a, b = mid + along * (c - half), mid + along * (c + half)
        ax.plot([a[0], b[0]], [a[1], b[1]], color=colour, lw=lw * 2.0, alpha=alpha, zorder=z, solid_capstyle="butt")
        base = mid
    tip = base
    if stem:
        if at["pivot"] is None:
            tip = base + at["move"] * stem_len
        else:
            d = at["pivot"] - base
            tip = base + d / np.linalg.norm(d) * min(np.linalg.norm(d), stem_len)
        ax.plot(
            [base[0], tip[0]],
            [base[1], tip[1]],
            color=colour,
            lw=lw * 1.6,
            alpha=alpha,
            zorder=z,
            solid_capstyle="butt",
        )
    at["tip"] = tip
    return at


def plot_cam_profile(
    ax: Axes,
    geometry: CamGeometry,
    check: CheckReport | None = None,
    *,
    angles: Sequence[float] = (0.0, 90.0, 180.0, 270.0),
) -> None:
    """The cam in its frame: contour, pitch curve, base circle, the follower at ``angles`` (grey), the follower at
    the largest pressure angle with its motion and the contact normal, the osculating circle at the least radius
    of curvature and the sense of rotation. The marks turn red where ``check`` fails that check."""
    geo, f = geometry, geometry.follower
    assert f.base_radius is not None  # a built geometry has its base radius (from the contour where one is given)
    ax.set_aspect("equal")
    ax.grid(False)
    contour, pitch = geo.contour, geo.pitch
    ax.add_patch(Polygon(contour.T, closed=True, fc=C["cam"], ec=C["ink"], lw=1.3, zorder=1, label="cam contour"))
    if f.roller:
        ax.plot(
            *np.c_[pitch, pitch[:, :1]], color=C["dyn"], lw=0.9, ls="--", zorder=2, label="pitch curve (roller centre)"
        )
    ax.add_patch(
        Circle(
            (0, 0),
            f.base_radius,
            fill=False,
            ec=C["grey"],
            lw=0.8,
            ls=":",
            zorder=2,
            label=f"base circle, radius {f.base_radius:.4g} mm",
        )
    )
    ax.plot(0, 0, marker="+", color=C["ink"], ms=9, mew=1.2, zorder=4)
    r_all = np.hypot(pitch[0], pitch[1]).max() + (f.roller_radius or 0.0)
    reach = r_all
    for th in angles:
        at = plot_follower(ax, geo, th, colour=C["grey"], lw=0.9, alpha=0.85, z=3)
        reach = max(reach, float(np.max(np.abs(at["tip"]))) + 0.1 * r_all)
        out = at["tip"] - at["centre"]
        out = (
            out / np.linalg.norm(out)
            if np.linalg.norm(out) > 1e-9
            else at["centre"] / max(np.linalg.norm(at["centre"]), 1e-9)
        )
        ax.annotate(
            f"{th:g}\u00b0",
            at["tip"],
            xytext=tuple(9 * out),
            textcoords="offset points",
            size=7.5,
            color=C["grey"],
            ha="center",
            va="center",
            zorder=5,
        )
    if square_face(geo):
        reach = max(reach, _face_travel_mark(ax, geo, check_colour(check, CheckKind.FACE_WIDTH, C["margin"])))
    else:
        pa_colour = check_colour(check, CheckKind.PRESSURE_ANGLE, C["margin"])
        reach = max(reach, _pressure_angle_mark(ax, geo, pa_colour, r_all))
    _curvature_mark(ax, geo, check_colour(check, CheckKind.CURVATURE, C["advice"]), r_all)
    _rotation_arrow(ax, f)
    lim_r = reach * 1.06
    ax.set_xlim(-lim_r, lim_r)
    ax.set_ylim(-lim_r, lim_r)
    ax.set_xlabel("x, cam frame = fixed frame at \u03b8 = 0 (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(loc="lower left", fontsize=7, framealpha=0.9)


def _pressure_angle_mark(ax, geo: CamGeometry, colour: str, r_all: float) -> float:
    """The follower at the largest pressure angle, its direction of motion and the contact normal; returns the
    reach of the drawing from the cam centre."""
    f = geo.follower
    at = plot_follower(ax, geo, geo.max_pressure_angle_at_deg, colour=colour, lw=1.6, z=6, stem=False)
    L = 0.32 * r_all
    origin = at["centre"] if f.roller else at["contact"]
    arrows = ((at["normal"], at["move"], "contact normal"), (at["move"], at["normal"], "follower motion"))
    sides = []
    for vec, other, text in arrows:
        ax.add_patch(
            FancyArrowPatch(
                origin, origin + vec * L, arrowstyle="-|>", mutation_scale=9, color=colour, lw=1.2, zorder=6
            )
        )
        side = np.array([-vec[1], vec[0]])
        if side @ other > 0:
            side = -side
        if sides and abs(vec[0] * other[1] - vec[1] * other[0]) < math.sin(math.radians(15.0)):
            side = -sides[0]  # nearly parallel arrows: their labels either side, not on top of each other
        sides.append(side)
        ax.annotate(
            text,
            origin + vec * L,
            xytext=tuple(8 * side),
            textcoords="offset points",
            size=7,
            color=colour,
            ha="left" if side[0] > 0 else "right",
            va="center",
            zorder=6,
        )
    return float(np.max(np.abs(origin))) + L * 1.25


def face_extremes(geometry: CamGeometry) -> tuple[tuple[float, float], tuple[float, float]]:
    """((t_min mm, at deg), (t_max mm, at deg)): where the contact runs along a flat face, from the follower's
    axis (translating) or the foot of the perpendicular from the pivot (oscillating); the angles on the grid."""
    t, th = geometry.face_t_mm, geometry.theta_deg
    face_range = geometry.extremes.face_range_mm
    assert face_range is not None  # drawn for flat faces only
    lo, hi = face_range  # on the grid and both sides of every break: what face_width judges
    return (lo, float(th[int(np.argmin(t))])), (hi, float(th[int(np.argmax(t))]))


def _face_travel_mark(ax, geo: CamGeometry, colour: str) -> float:
    """The face at the two ends of the contact's travel along it, the contact points marked with their t;
    returns the reach of the drawing from the cam centre."""
    reach = 0.0
    for t, th in face_extremes(geo):
        at = plot_follower(ax, geo, th, colour=colour, lw=1.6, z=6, stem=False)
        p, n = at["contact"], at["normal"]
        ax.plot(*p, marker="o", ms=5, color=colour, zorder=7)
        ax.annotate(
            f"t = {t:+.1f} mm\nat {th:.1f}\u00b0",
            p,
            xytext=tuple(16 * n),
            textcoords="offset points",
            size=7,
            color=colour,
            zorder=7,
            ha="left" if n[0] > 0.3 else ("right" if n[0] < -0.3 else "center"),
            va="bottom" if n[1] > 0.3 else ("top" if n[1] < -0.3 else "center"),
            bbox=dict(fc="white", ec="none", alpha=0.85, pad=0.8),
        )
        reach = max(reach, float(np.max(np.abs(p))) * 1.25)
    return reach


def plot_face_contact(
    ax: Axes, geometry: CamGeometry, check: CheckReport | None = None, *, breaks_deg: Sequence[float] = ()
) -> None:
    """Where the contact runs along a flat face against the cam angle: t (mm), its travel shaded and its ends
    marked (red where ``check``'s face_width fails). For a face square to its motion, what the pressure angle
    says of a roller."""
    geo = geometry
    colour = check_colour(check, CheckKind.FACE_WIDTH, C["margin"])
    (t_lo, th_lo), (t_hi, th_hi) = face_extremes(geo)
    ax.plot(geo.theta_deg, geo.face_t_mm, color=C["dyn"], lw=1.3)
    ax.axhspan(t_lo, t_hi, color=colour, alpha=0.1, lw=0)
    ax.plot([th_lo, th_hi], [t_lo, t_hi], "o", color=colour, ms=4.5)
    if t_lo < 0.0 < t_hi:
        ax.axhline(0, color="#888888", lw=0.6)
    width = geo.follower.face_width
    c = geo.face_centre_mm
    if width and c is not None:  # the face's ends where the face_width check and the cam drawing put them
        for end in (c - 0.5 * width, c + 0.5 * width):
            ax.axhline(
                end,
                color=C["limit"],
                lw=0.9,
                ls="--",
                label=f"face ends: face_width {width:g} mm centred at t = {c:+.2f} mm" if end < c else None,
            )
        legend_above_data(ax, also=(c + 0.5 * width,), fontsize=7)
    mark_breaks(ax, breaks_deg)
    ax.set_ylabel(f"t from the {'axis' if geo.follower.translating else 'pivot foot'} (mm)")
    ax.set_title(
        "contact position t along the face (pressure angle 0 all round: the face is square to its motion)", fontsize=9
    )


def _curvature_mark(ax, geo: CamGeometry, colour: str, r_all: float) -> None:
    """The point of least radius of curvature on the contour and its osculating circle (dashed)."""
    rho = geo.min_radius_of_curvature_mm
    at_r = follower_pose(geo, geo.min_radius_of_curvature_at_deg)
    p = at_r["contact"]
    if math.isfinite(rho):
        _osculating_mark(ax, p, p - at_r["normal"] * rho, rho, colour, r_all)


def _osculating_mark(ax, point, centre, rho: float, colour: str, r_all: float) -> None:
    """A point of least radius of curvature ``rho`` (mm, signed) and its osculating circle about ``centre``, dashed
    (left out where it is over three times ``r_all``, the drawing's reach: it would leave the axes)."""
    if abs(rho) < 3 * r_all:
        ax.add_patch(Circle(tuple(centre), abs(rho), fill=False, ec=colour, lw=0.9, ls="--", zorder=5))
    ax.plot(*point, marker="o", ms=5, color=colour, zorder=7)


def _rotation_arrow(ax, f) -> None:
    arc_r = 0.22 * f.base_radius
    sign = f.sigma
    a0, a1 = (math.radians(200), math.radians(340)) if sign > 0 else (math.radians(340), math.radians(200))
    ax.add_patch(
        FancyArrowPatch(
            (arc_r * math.cos(a0), arc_r * math.sin(a0)),
            (arc_r * math.cos(a1), arc_r * math.sin(a1)),
            connectionstyle=f"arc3,rad={0.5 * sign}",
            arrowstyle="-|>",
            mutation_scale=8,
            color=C["ink"],
            lw=0.9,
            zorder=4,
        )
    )
    ax.text(0, -arc_r * 1.9, f"turns {f.rotation}", size=7.5, ha="center", va="center", color=C["ink"])


def plot_pressure_angle(
    ax: Axes, geometry: CamGeometry, check: CheckReport | None = None, *, breaks_deg: Sequence[float] = ()
) -> None:
    """The pressure angle against the cam angle, the check's limit (both signs) and its largest value marked."""
    geo = geometry
    th = geo.theta_deg
    pa = geo.pressure_angle_deg
    pa_lim = check_limit(check, CheckKind.PRESSURE_ANGLE)
    ax.plot(th, pa, color=C["dyn"], lw=1.3, label="pressure angle")
    if pa_lim is not None:
        for sgn in (1, -1):
            ax.axhline(sgn * pa_lim, color=C["limit"], ls="--", lw=0.9)
        top = max(pa_lim, np.abs(pa).max()) * 1.18
        ax.axhspan(pa_lim, top, color=C["limit"], alpha=0.08, lw=0)
        ax.axhspan(-top, -pa_lim, color=C["limit"], alpha=0.08, lw=0)
        ax.set_ylim(-top, top)
        ax.text(2, pa_lim, f" limit \u00b1{pa_lim:g}\u00b0", color=C["limit"], size=7, va="bottom")
    i = int(np.argmax(np.abs(pa)))
    ax.plot(th[i], pa[i], "o", color=check_colour(check, CheckKind.PRESSURE_ANGLE, C["margin"]), ms=4.5)
    ax.axhline(0, color="#888888", lw=0.6)
    mark_breaks(ax, breaks_deg)
    ax.set_ylabel("pressure angle (deg)")
    ax.set_title("pressure angle", fontsize=9)


def curvature_limit_line(ax: Axes, min_curvature_ratio: float, roller_radius: float) -> None:
    """The curvature check's limit on a radius-of-curvature axis: ``min_curvature_ratio`` x roller radius (mm)."""
    r_lim = min_curvature_ratio * roller_radius
    ax.axhline(r_lim, color=C["limit"], ls="--", lw=0.9)
    ax.text(
        2,
        r_lim,
        f" limit {min_curvature_ratio:g} \u00d7 roller radius = {r_lim:.3g} mm (convex)",
        color=C["limit"],
        size=7,
        va="bottom",
    )


def plot_curvature(
    ax: Axes,
    geometry: CamGeometry,
    check: CheckReport | None = None,
    *,
    min_curvature_ratio: float = DEFAULT_MIN_CURVATURE_RATIO,
    breaks_deg: Sequence[float] = (),
) -> None:
    """The contour's (and a roller's pitch curve's) radius of curvature against the cam angle, convex > 0, with
    the limit (``min_curvature_ratio`` x roller radius; no cusp for a flat face) and the least value marked."""
    geo, f = geometry, geometry.follower
    th = geo.theta_deg
    rho_c = geo.rho_contour_mm.copy()
    assert f.base_radius is not None  # a built geometry has its base radius (from the contour where one is given)
    cap = max(3.0 * f.base_radius, 2.5 * ((f.roller_radius or 0.0) * min_curvature_ratio))
    finite = np.isfinite(rho_c)
    low = float(np.min(rho_c[finite])) if finite.any() else -cap
    floor = max(low, -cap)
    shown = np.where(finite & (np.abs(rho_c) <= cap * 1.05), rho_c, np.nan)
    ax.plot(th, shown, color=C["dyn"], lw=1.3, label="contour")
    if f.roller_radius is not None:
        rho_p = np.where(np.abs(geo.rho_pitch_mm) <= cap * 1.05, geo.rho_pitch_mm, np.nan)
        ax.plot(th, rho_p, color=C["dyn"], lw=0.8, ls="--", alpha=0.7, label="pitch curve")
        curvature_limit_line(ax, min_curvature_ratio, f.roller_radius)
    else:
        ax.axhline(0.0, color=C["limit"], ls="--", lw=0.9)
        ax.text(2, 0.0, " limit: no cusp (\u03c1 > 0)", color=C["limit"], size=7, va="bottom")
    ax.axhline(0, color="#888888", lw=0.6)
    ax.plot(
        geo.min_radius_of_curvature_at_deg,
        geo.min_radius_of_curvature_mm,
        "o",
        color=check_colour(check, CheckKind.CURVATURE, C["advice"]),
        ms=4.5,
    )
    ax.set_ylim(min(floor * 1.1, -0.05 * cap), cap)
    mark_breaks(ax, breaks_deg)
    ax.set_ylabel("radius of curvature (mm)")
    ax.set_title(f"radius of curvature (convex > 0; |\u03c1| above {cap:.0f} mm not drawn)", fontsize=9)
    ax.legend(loc="upper right", fontsize=7, ncol=2)
    deg_ticks(ax, 30.0)
    ax.set_xlabel("cam angle \u03b8 (deg)")
