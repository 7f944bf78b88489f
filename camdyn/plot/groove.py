"""A form-closed cam drawn (``[follower] closure = "groove"`` or ``"conjugate"``): the cam with both walls (or
both conjugate cams, each roller on its cam), the signed contact force with its crossovers and impacts (and each
conjugate cam's own force under the preload), and each flank's radius of curvature. Each takes a
:class:`~camdyn.design.checks.CheckReport` of a form-closed cam (``check.closure`` set)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import QuadMesh
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

from .._core.units import DEFAULT_MIN_CURVATURE_RATIO
from ..design.checks import CheckKind, CheckReport
from ..model.geometry import WALLS, ConjugateGeometry, GrooveGeometry
from ._common import C, deg_ticks, legend_above_data, mark_breaks, sample_histogram
from .cam import (
    _curvature_mark,
    _osculating_mark,
    _pressure_angle_mark,
    _rotation_arrow,
    check_colour,
    curvature_limit_line,
    plot_follower,
    plot_pressure_angle,
)

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.closure import ClosureStudy, ImpactMap, PreloadMap
    from ..design.tolerance import ImpactToleranceResult

WALL_COLOURS = {"inner": C["dyn"], "outer": C["advice"]}
CAM_COLOURS = {"primary": C["dyn"], "conjugate": C["iso"]}


def _study(check: CheckReport) -> ClosureStudy:
    assert check.closure is not None, "a form-closed cam's check (check.closure set)"
    return check.closure


def flank_names(check: CheckReport) -> tuple[str, str]:
    """The flank a positive force presses and the other: a groove's walls, or the conjugate cams."""
    return ("inner flank", "outer flank") if _study(check).loads is None else ("primary cam", "conjugate cam")


def conjugate_centre(study: ClosureStudy, theta_deg: float) -> np.ndarray:
    """The second roller's centre in the cam frame at cam angle ``theta_deg`` (mm; the nearest grid angle)."""
    w = study.walls
    assert isinstance(w, ConjugateGeometry)
    n = w.theta_deg.size
    return w.pitch[:, int(round(theta_deg / 360.0 * n)) % n]


def flight_spans_deg(check: CheckReport) -> list[tuple[float, float]]:
    """The cam-angle spans (deg, within [0, 360]) of the flights across the backlash: two where one wraps 0."""
    out = []
    for c in _study(check).response.crossovers:
        a, b = c.deg, c.land_deg
        if b > a:
            out.append((a, b))
        elif b < a:
            out += [(a, 360.0), (0.0, b)]
    return out


def _second_roller(ax: Axes, study: ClosureStudy, at: dict, theta_deg: float, *, colour: str, **kw) -> np.ndarray:
    """The conjugate cam's roller at ``theta_deg`` (cam frame) tied to the first (``at``: its
    :func:`follower_pose`): the rocker's second arm from the pivot, or the yoke between the rollers."""
    centre = conjugate_centre(study, theta_deg)
    rr2 = study.conjugate.roller_radius_mm
    lw, alpha, z = kw.get("lw", 1.0), kw.get("alpha", 1.0), kw.get("z", 3)
    ax.add_patch(Circle((float(centre[0]), float(centre[1])), rr2, fill=False, ec=colour, lw=lw, alpha=alpha, zorder=z))
    ax.plot(*centre, marker=".", ms=2.5, color=colour, alpha=alpha, zorder=z)
    tie = at["centre"] if at["pivot"] is None else at["pivot"]
    ax.plot(*np.c_[tie, centre], color=colour, lw=lw * 1.6, alpha=alpha, zorder=z, solid_capstyle="butt")
    return centre


def plot_groove_cam(
    ax: Axes, check: CheckReport, *, angles: Sequence[float] = (0.0, 90.0, 180.0, 270.0), marks: bool = True
) -> None:
    """The form-closed cam in its frame: a groove's slot between the inner and the outer wall (the cam's face
    shaded, the slot white), or both conjugate cams (the primary shaded, the conjugate outlined over it), the pitch
    curve(s), the roller(s) at ``angles`` (grey); with ``marks`` the roller where each crossover's flight lands (on
    the flank it lands on), the largest pressure angle and the least radius of curvature (a groove's on each wall
    convex towards its roller, conjugate cams' on the primary), and the legend."""
    study, geo = _study(check), check.geometry
    assert geo is not None  # check computes a form-closed cam's geometry
    walls, f = study.walls, geo.follower
    conj = isinstance(walls, ConjugateGeometry)
    ax.set_aspect("equal")
    ax.grid(False)
    if conj:
        r_out = float(max(np.hypot(*geo.pitch).max(), np.hypot(*walls.pitch).max()))
        disc = r_out + max(f.roller_radius or 0.0, walls.roller_radius_mm)
        ax.add_patch(Polygon(geo.contour.T, closed=True, fc=C["cam"], ec="none", zorder=0.8))
        ax.add_patch(Polygon(walls.contour.T, closed=True, fc=C["iso"], alpha=0.1, ec="none", zorder=0.9))
        curves = (("primary", geo.contour, geo.pitch), ("conjugate", walls.contour, walls.pitch))
        for name, contour, pitch in curves:
            colour = CAM_COLOURS[name]
            ax.plot(*np.c_[contour, contour[:, :1]], color=colour, lw=1.3, zorder=2, label=f"{name} cam")
            ax.plot(*np.c_[pitch, pitch[:, :1]], color=colour, lw=0.7, ls="--", alpha=0.8, zorder=2)
        ax.plot([], [], color=C["grey"], lw=0.7, ls="--", label="pitch curves")
    else:
        r_out = float(np.hypot(*walls.outer).max())
        disc = 1.12 * r_out
        ax.add_patch(Circle((0, 0), disc, fc=C["cam"], ec=C["ink"], lw=1.0, zorder=0.5, label="cam face"))
        ax.add_patch(Polygon(walls.outer.T, closed=True, fc="white", ec="none", zorder=0.8))
        ax.add_patch(Polygon(walls.inner.T, closed=True, fc=C["cam"], ec="none", zorder=0.9))
        for name in ("inner", "outer"):
            xy = getattr(walls, name)
            ax.plot(*np.c_[xy, xy[:, :1]], color=WALL_COLOURS[name], lw=1.3, zorder=2, label=f"{name} wall")
        ax.plot(*np.c_[geo.pitch, geo.pitch[:, :1]], color=C["grey"], lw=0.8, ls="--", zorder=2, label="pitch curve")
    ax.plot(0, 0, marker="+", color=C["ink"], ms=9, mew=1.2, zorder=4)
    for th in angles:
        at = plot_follower(ax, geo, th, colour=C["grey"], lw=0.9, alpha=0.85, z=3)
        if conj:
            _second_roller(ax, study, at, th, colour=C["grey"], lw=0.9, alpha=0.85, z=3)
        if marks:
            ax.annotate(
                f"{th:g}\u00b0",
                at["centre"],
                xytext=(0, 0),
                textcoords="offset points",
                size=6.5,
                color=C["grey"],
                ha="center",
                va="center",
                zorder=5,
            )
    lim = disc * 1.04
    if conj and not f.translating:  # the rocker's pivot lies beyond the cams
        lim = max(lim, 1.08 * (f.pivot_distance or 0.0))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel("x, cam frame = fixed frame at \u03b8 = 0 (mm)" if marks else "x (mm)")
    ax.set_ylabel("y (mm)")
    if not marks:
        return
    colour = check_colour(check, CheckKind.CROSSOVER_IMPACT, C["margin"])
    landings = study.response.crossovers if not conj or study.response.backlash_mm > 0.0 else ()  # none at b = 0
    for k, c in enumerate(landings):
        at = plot_follower(ax, geo, c.land_deg, colour=colour, lw=1.4, z=6, stem=False)
        where = at["centre"]
        if conj and c.to_flank == "conjugate":
            where = _second_roller(ax, study, at, c.land_deg, colour=colour, lw=1.4, z=6)
        out = where / max(float(np.linalg.norm(where)), 1e-9)
        ax.annotate(
            f"lands {c.land_deg:.0f}\u00b0\n({c.to_flank})",
            (float(where[0]), float(where[1])),
            xytext=tuple(26 * out),
            textcoords="offset points",
            size=7,
            color=colour,
            ha="center",
            va="center",
            zorder=7,
            bbox=dict(fc="white", ec="none", alpha=0.8, pad=0.6),
        )
        if k == 0:
            ax.plot([], [], "o", mfc="none", color=colour, label="roller where a flight\nacross the backlash lands")
    r_all = float(np.hypot(*geo.pitch).max()) + (f.roller_radius or 0.0)
    _pressure_angle_mark(ax, geo, check_colour(check, CheckKind.PRESSURE_ANGLE, C["margin"]), r_all)
    colour = check_colour(check, CheckKind.CURVATURE, C["advice"])
    if conj:
        _curvature_mark(ax, geo, colour, r_all)
    else:
        _wall_curvature_marks(ax, walls, colour, r_all)
    _rotation_arrow(ax, f)
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=7, framealpha=0.9)


def _wall_curvature_marks(ax: Axes, walls: GrooveGeometry, colour: str, r_all: float) -> None:
    """Each groove wall's point of least convex radius of curvature and its osculating circle there (dashed), where
    the wall is convex towards the roller anywhere."""
    for name in WALLS:
        if (least := walls.least_circle(name)) is None:
            continue
        _osculating_mark(ax, *least, colour, r_all)  # a folded wall's radius is negative: its loop's circle


def plot_flank_force(
    ax: Axes, check: CheckReport, *, breaks_deg: Sequence[float] = (), legend: bool = True, marks: bool = True
) -> None:
    """The signed contact force (N at the roller) over a revolution: positive on the inner flank (the primary cam),
    negative on the outer (the conjugate cam), 0 in flight across the backlash (shaded); the kinematic force (the
    roller on the pitch curve) dashed; of conjugate cams each cam's own force under the preload (its share); each
    crossover (where the force leaves its flank) and each impact (on the flank it lands on: its peak force where
    the train is compliant, else its speed) marked, labelled with ``marks``."""
    study, resp = _study(check), check.response
    th = resp.theta_deg
    plus, minus = flank_names(check)
    loads = study.loads if study.response.backlash_mm == 0.0 else None  # with backlash there is no preload
    conj = study.loads is not None
    if loads is not None:
        for name, share in (("primary", loads.primary_N), ("conjugate", loads.conjugate_N)):
            ax.plot(loads.theta_deg, share, color=CAM_COLOURS[name], lw=1.0, alpha=0.9, label=f"on the {name} cam")
    ax.plot(th, resp.kinematic_force, color=C["kin"], lw=1.0, ls="--", label="kinematic (on the pitch curve)")
    net = "contact force" if loads is None else "net force"
    colour = C["dyn" if loads is None else "ink"]
    ax.plot(th, resp.force, color=colour, lw=1.3, label=f"{net} at {check.speed_rpm:g} rpm")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    for k, (a, b) in enumerate(flight_spans_deg(check)):
        ax.axvspan(
            a, b, color=C["limit"], alpha=0.13, lw=0, zorder=0.4, label="flight across the backlash" if k == 0 else None
        )
    mark_breaks(ax, breaks_deg)
    colour = check_colour(check, CheckKind.CROSSOVER_IMPACT, C["margin"])
    for k, c in enumerate(study.response.crossovers):
        ax.axvline(
            c.deg,
            color=C["ink"],
            lw=0.8,
            ls="-.",
            zorder=1,
            label=f"crossover (the force changes {'cam' if conj else 'flank'})" if k == 0 else None,
        )
        if loads is not None:
            continue  # held on both cams: no flight, no impact to mark
        sign = 1.0 if c.to_flank in ("inner", "primary") else -1.0
        if c.impact_force_N is not None:
            y = sign * c.impact_force_N
            text = f"{c.impact_velocity_m_per_s:.3g} m/s, {c.impact_force_N:.3g} N"
        else:  # a rigid train: the impact is an impulse, its force is not finite
            y = float(np.interp(c.land_deg, th, resp.kinematic_force, period=360.0))
            text = f"{c.impact_velocity_m_per_s:.3g} m/s (rigid: impulse)"
        ax.plot(
            c.land_deg,
            y,
            "v" if sign < 0 else "^",
            color=colour,
            ms=6,
            zorder=6,
            label=f"impact on the other flank ({'peak force' if c.impact_force_N is not None else 'speed'})"
            if k == 0
            else None,
        )
        if marks:
            ax.annotate(
                text,
                (c.land_deg, y),
                xytext=(6, -2 * sign),
                textcoords="offset points",
                size=6.8,
                color=colour,
                ha="left",
                va="top" if sign < 0 else "bottom",
                zorder=7,
            )
    deg_ticks(ax, 30.0 if marks else 60.0)
    ax.set_ylabel("contact force (N)")
    if not marks:
        return
    lo, hi = ax.get_ylim()
    ax.text(2, hi * 0.96, f"{plus} (+)", size=7, color=C["grey"], va="top")
    ax.text(2, lo * 0.96, f"{minus} (\u2212)", size=7, color=C["grey"], va="bottom")
    ax.set_xlabel("cam angle \u03b8 (deg)")
    if loads is None:
        what = "on the cam that carries it" if conj else "on the flank that carries it"
    else:
        unit = "N" if loads.translating else "N\u00b7m"
        what = f"net (signed) and on each cam under the preload {loads.preload:g} {unit}"
    # preloaded conjugate cams have no backlash (they exclude each other): a title without it fits the page
    backlash = "" if loads is not None else f" (backlash {study.response.backlash_mm:g} mm)"
    ax.set_title(f"contact force {what} at {check.speed_rpm:g} rpm{backlash}", fontsize=9)
    if legend:
        legend_above_data(ax, fontsize=7, ncol=2)


def plot_wall_curvature(
    ax: Axes,
    check: CheckReport,
    *,
    min_curvature_ratio: float = DEFAULT_MIN_CURVATURE_RATIO,
    breaks_deg: Sequence[float] = (),
) -> None:
    """Both walls' (or both conjugate cams') radii of curvature against the cam angle, as the roller sees each
    (convex towards it > 0: a groove's one wall is concave where the other is convex), the limit
    (``min_curvature_ratio`` x roller radius) and each one's least convex radius marked."""
    study, geo = _study(check), check.geometry
    assert geo is not None and geo.follower.roller_radius is not None  # a form-closed cam holds a roller
    walls = study.walls
    rr = geo.follower.roller_radius
    cap = 3.0 * float(geo.follower.base_radius or rr)
    if isinstance(walls, ConjugateGeometry):
        least = walls.convex.min_convex_radius_mm, walls.convex.min_convex_radius_at_deg
        curves = [
            (
                "primary cam",
                CAM_COLOURS["primary"],
                geo.theta_deg,
                geo.rho_contour_mm,
                CheckKind.CURVATURE,
                (geo.min_radius_of_curvature_mm, geo.min_radius_of_curvature_at_deg),
            ),
            (
                "conjugate cam",
                CAM_COLOURS["conjugate"],
                walls.theta_deg,
                walls.rho_contour_mm,
                CheckKind.CONJUGATE_CURVATURE,
                least,
            ),
        ]
        what = "each cam"
    else:
        curves = [
            (
                f"{n} wall",
                WALL_COLOURS[n],
                walls.theta_deg,
                getattr(walls, f"rho_{n}_mm"),
                CheckKind.CURVATURE,
                (
                    getattr(walls, f"{n}_wall").min_convex_radius_mm,
                    getattr(walls, f"{n}_wall").min_convex_radius_at_deg,
                ),
            )
            for n in ("inner", "outer")
        ]
        what = "each wall"
    for label, colour, th, rho, kind, (r_least, at_deg) in curves:
        rho = np.asarray(rho)
        shown = np.where(np.isfinite(rho) & (np.abs(rho) <= cap * 1.05), rho, np.nan)
        ax.plot(th, shown, color=colour, lw=1.3, label=label)
        if np.isfinite(r_least):
            ax.plot(at_deg, r_least, "o", ms=4.5, color=check_colour(check, kind, colour))
    curvature_limit_line(ax, min_curvature_ratio, rr)
    ax.axhline(0, color="#888888", lw=0.6)
    ax.set_ylim(-cap, cap)
    mark_breaks(ax, breaks_deg)
    deg_ticks(ax, 30.0)
    ax.set_ylabel("radius of curvature (mm)")
    ax.set_xlabel("cam angle \u03b8 (deg)")
    ax.set_title(
        f"radius of curvature of {what}, as its roller sees it (convex > 0; |\u03c1| > {cap:.0f} mm not drawn)",
        fontsize=9,
    )
    ax.legend(loc="best", fontsize=7, ncol=2)  # the curves run off the top and bottom: the emptiest corner


def plot_cam_pressure_angles(ax: Axes, check: CheckReport, *, breaks_deg: Sequence[float] = ()) -> None:
    """Conjugate cams: each cam's pressure angle against the cam angle (the conjugate's from the direction it
    drives the follower back), the limit and each one's largest marked."""
    study, geo = _study(check), check.geometry
    walls = study.walls
    assert geo is not None and isinstance(walls, ConjugateGeometry)
    plot_pressure_angle(ax, geo, check, breaks_deg=breaks_deg)
    ax.lines[0].set_label("primary cam")
    ax.plot(walls.theta_deg, walls.pressure_angle_deg, color=CAM_COLOURS["conjugate"], lw=1.3, label="conjugate cam")
    i = int(np.argmax(np.abs(walls.pressure_angle_deg)))
    colour = check_colour(check, CheckKind.CONJUGATE_PRESSURE_ANGLE, CAM_COLOURS["conjugate"])
    ax.plot(walls.theta_deg[i], walls.pressure_angle_deg[i], "o", color=colour, ms=4.5)
    ax.set_title("pressure angle of each cam (the conjugate's from the way it drives the follower back)", fontsize=9)
    ax.legend(loc="upper right", fontsize=7, ncol=2)


def plot_impact_speed(ax: Axes, impacts: ImpactMap, *, speed_rpm: float | None = None) -> None:
    """The largest crossover impact speed against cam speed, a line per backlash, the limit
    (``[limits] max_impact_velocity``) and the case's speed marked."""
    for i, b in enumerate(impacts.backlash_mm):
        ax.plot(
            impacts.speeds_rpm,
            impacts.impact_velocity_m_per_s[i],
            lw=1.3,
            color=C["dyn"] if i == 0 else None,
            label=f"backlash {b:g} mm",
        )
    lim = impacts.max_impact_velocity
    ax.axhline(lim, color=C["limit"], ls="--", lw=0.9, label=f"max_impact_velocity {lim:g} m/s")
    if speed_rpm is not None:
        ax.axvline(speed_rpm, color=C["ink"], ls=":", lw=0.9, label=f"{speed_rpm:g} rpm")
    ax.set_xlim(0.0, float(impacts.speeds_rpm[-1]))
    ax.set_ylim(0.0, max(lim, float(np.nanmax(impacts.impact_velocity_m_per_s))) * 1.1)
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel("impact speed (m/s)")
    # that a form-closed cam has no jump speed is in the report page's caption (a title as long ran past the page)
    ax.set_title("largest impact speed across the backlash against cam speed", fontsize=9)
    legend_above_data(ax, also=(lim,), fontsize=7, ncol=3, loc="upper left")


def plot_impact_map(
    ax: Axes, impacts: ImpactMap, *, speed_rpm: float | None = None, backlash_mm: float | None = None
) -> QuadMesh | None:
    """The largest impact speed over cam speed x backlash, the limit's contour and the operating point; a single
    backlash gives :func:`plot_impact_speed`. Returns the artist a colorbar can use (None for a line plot)."""
    if impacts.backlash_mm.size == 1 or impacts.speeds_rpm.size == 1:
        plot_impact_speed(ax, impacts, speed_rpm=speed_rpm)
        return None
    v = impacts.impact_velocity_m_per_s
    mesh = ax.pcolormesh(impacts.speeds_rpm, impacts.backlash_mm, v, shading="nearest", cmap="viridis")
    lim = impacts.max_impact_velocity
    if np.nanmin(v) < lim < np.nanmax(v):
        ax.contour(impacts.speeds_rpm, impacts.backlash_mm, v, levels=[lim], colors="red", linewidths=1.5)
        ax.plot([], [], color="red", label=f"max_impact_velocity {lim:g} m/s")
    if speed_rpm is not None and backlash_mm is not None:
        ax.plot(
            [speed_rpm],
            [backlash_mm],
            marker="*",
            ms=12,
            color="white",
            mec="black",
            ls="none",
            label=f"operating point ({speed_rpm:g} rpm, {backlash_mm:g} mm)",
        )
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel("backlash (mm)")
    ax.set_title("largest impact speed across the backlash (m/s)", fontsize=10)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", fontsize=8)
    return mesh


def save_impact_png(
    impacts: ImpactMap, path: str | Path, *, speed_rpm: float | None = None, backlash_mm: float | None = None
) -> None:
    """Write :func:`plot_impact_map` of ``impacts`` as a PNG (matplotlib, no pyplot state)."""
    fig = Figure(figsize=(8, 5.5), layout="constrained")
    art = plot_impact_map(fig.add_subplot(), impacts, speed_rpm=speed_rpm, backlash_mm=backlash_mm)
    if art is not None:
        fig.colorbar(art, ax=fig.axes[0], label="largest impact speed (m/s)")
    fig.savefig(path, dpi=120)


def plot_preload_map(ax: Axes, pm: PreloadMap, *, speed_rpm: float | None = None) -> None:
    """Conjugate cams over cam speed: the least preload that keeps both rollers loaded (half the largest |net
    force|) against the case's preload, and the case's speed marked; the preload holds where its line is above."""
    unit = "N" if pm.translating else "N\u00b7m"
    ax.plot(pm.speeds_rpm, pm.least_preload, color=C["dyn"], lw=1.3, label="least preload that holds (max |F| / 2)")
    ax.axhline(pm.preload, color=C["limit"], ls="--", lw=0.9, label=f"the case's preload {pm.preload:g} {unit}")
    if speed_rpm is not None:
        ax.axvline(speed_rpm, color=C["ink"], ls=":", lw=0.9, label=f"{speed_rpm:g} rpm")
    ax.set_xlim(0.0, float(pm.speeds_rpm[-1]))
    ax.set_ylim(0.0, 1.1 * max(pm.preload, float(np.max(pm.least_preload))))
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel(f"preload ({unit})")
    ax.set_title("least preload between the rollers against cam speed (conjugate cams have no jump speed)", fontsize=9)
    legend_above_data(ax, also=(pm.preload,), fontsize=7, loc="upper left")


def plot_least_cam_force(ax: Axes, pm: PreloadMap, *, speed_rpm: float | None = None) -> None:
    """Conjugate cams over cam speed: the least force on either cam under the case's preload (0: a roller
    unloads), the case's speed marked."""
    ax.plot(pm.speeds_rpm, pm.least_cam_force_N, color=C["dyn"], lw=1.3, label="least force on either cam")
    ax.axhline(0.0, color=C["limit"], ls="--", lw=0.9, label="0: a roller unloads")
    if speed_rpm is not None:
        ax.axvline(speed_rpm, color=C["ink"], ls=":", lw=0.9, label=f"{speed_rpm:g} rpm")
    ax.set_xlim(0.0, float(pm.speeds_rpm[-1]))
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel("least cam force (N)")
    ax.set_title("least force on either cam under the preload", fontsize=9)
    legend_above_data(ax, fontsize=7, loc="upper right")


def save_preload_png(pm: PreloadMap, path: str | Path, *, speed_rpm: float | None = None) -> None:
    """Write :func:`plot_preload_map` and :func:`plot_least_cam_force` of ``pm`` as a PNG (no pyplot state)."""
    fig = Figure(figsize=(8, 7), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    plot_preload_map(top, pm, speed_rpm=speed_rpm)
    plot_least_cam_force(bottom, pm, speed_rpm=speed_rpm)
    top.set_xlabel("")
    fig.savefig(path, dpi=120)


def plot_least_cam_force_histogram(ax: Axes, result: ImpactToleranceResult) -> None:
    """Conjugate cams under a preload: histogram of the built cams' least force on either cam (N), 0 (a roller
    unloads) and the P1/P50 marked."""
    held = result.least_cam_force_N
    assert held is not None  # a preloaded pair's study
    q = {p: float(np.percentile(held, p, method="inverted_cdf")) for p in (1, 50)}
    lo, hi = result.unloaded_interval
    sample_histogram(
        ax,
        held,
        (0.0, "0: a roller unloads"),
        [(q[1], ":", f"P1 {q[1]:.4g} N"), (q[50], "--", f"P50 {q[50]:.4g} N")],
        f"{result.case}: least force on either cam of {result.samples} built conjugate cams; P(a roller unloads) = "
        f"{result.unloaded_probability:.3g} [{lo:.3g}, {hi:.3g}]",
        "least force on either cam (N)",
    )


def plot_impact_histogram(ax: Axes, result: ImpactToleranceResult) -> None:
    """Histogram of the built cams' largest impact speed (m/s), the limit and the P50/P99 marked (conjugate cams
    under a preload: :func:`plot_least_cam_force_histogram`)."""
    if result.least_cam_force_N is not None:
        plot_least_cam_force_histogram(ax, result)
        return
    v = result.impact_velocity_m_per_s
    lim = result.max_impact_velocity
    q = result.percentiles(v)
    assert q is not None  # impact speeds are finite
    lo, hi = result.confidence_interval
    sample_histogram(
        ax,
        v,
        (lim, f"max_impact_velocity {lim:g} m/s"),
        [(q[n], style, f"{n.upper()} {q[n]:.3g} m/s") for n, style in (("p50", "--"), ("p99", ":"))],
        f"{result.case}: largest impact speed of {result.samples} built {result.closure} cams; P(over the limit) = "
        f"{result.probability:.3g} [{lo:.3g}, {hi:.3g}]",
        "largest impact speed across the backlash (m/s)",
    )


def save_impact_histogram_png(result: ImpactToleranceResult, path: str | Path) -> None:
    """Write :func:`plot_impact_histogram` of ``result`` as a PNG (matplotlib, no pyplot state)."""
    fig = Figure(figsize=(8, 5), layout="constrained")
    plot_impact_histogram(fig.add_subplot(), result)
    fig.savefig(path, dpi=120)
