"""A form-closed cam's pages (``[follower] closure = "groove"`` or ``"conjugate"``), in place of the spring-held
cam's cam and dynamics pages: the cam with both walls (or both conjugate cams, each roller on its cam), their
pressure angle and curvature; the contact force on the flank (or cam) that carries it, each conjugate cam's own
force under the preload, the crossovers, the flights across the backlash and the impacts on the other flank."""

from __future__ import annotations

from matplotlib.figure import Figure

from ...design.checks import CheckKind
from ...plot import (
    check_colour,
    plot_cam_pressure_angles,
    plot_flank_force,
    plot_groove_cam,
    plot_impact_speed,
    plot_pressure_angle,
    plot_wall_curvature,
)
from .._data import ReportData
from .._layout import Flow
from .._style import LEFT, C


def draw_groove(fig: Figure, data: ReportData) -> None:
    chk = data.check
    assert chk.closure is not None and chk.geometry is not None  # drawn for a groove cam only (pages.PAGES)
    walls = chk.closure.groove
    plot_groove_cam(fig.add_axes((0.1, 0.43, 0.56, 0.455)), chk)
    fig.text(
        0.08,
        0.94,
        f"groove cam: a slot {2 * walls.wall_offset_mm:.4g} mm wide (backlash {walls.backlash_mm:g} mm); grey: the "
        "roller at 0, 90, 180, 270\u00b0",
        size=9,
        weight="bold",
        va="top",
    )
    geo = chk.geometry
    fig.text(
        0.08,
        0.922,
        f"\u25cf max pressure angle {geo.max_pressure_angle_deg:.1f}\u00b0 at \u03b8 = "
        f"{geo.max_pressure_angle_at_deg:.1f}\u00b0 (both walls'): the roller there, its motion and the contact "
        "normal",
        size=7.8,
        color=check_colour(chk, CheckKind.PRESSURE_ANGLE, C["margin"]),
        va="top",
    )
    least = [
        f"{w} wall {getattr(walls, f'{w}_wall').min_convex_radius_mm:.4g} mm at "
        f"{getattr(walls, f'{w}_wall').min_convex_radius_at_deg:.1f}\u00b0"
        for w in ("inner", "outer")
        if getattr(walls, f"{w}_wall").min_convex_radius_mm != float("inf")
    ]
    fig.text(
        0.08,
        0.906,
        "\u25cf least convex radius of curvature: "
        + ("; ".join(least) or "neither wall is convex anywhere")
        + " (osculating circles dashed)",
        size=7.8,
        color=check_colour(chk, CheckKind.CURVATURE, C["advice"]),
        va="top",
    )
    gs = fig.add_gridspec(2, 1, left=LEFT, right=0.95, top=0.37, bottom=0.06, hspace=0.35)
    ax1 = fig.add_subplot(gs[0])
    ax2 = fig.add_subplot(gs[1], sharex=ax1)
    plot_pressure_angle(ax1, geo, chk, breaks_deg=data.breaks_deg)
    ax1.set_title("pressure angle, both walls (the pitch curve's)", fontsize=9)
    ax1.tick_params(labelbottom=False)
    plot_wall_curvature(ax2, chk, min_curvature_ratio=data.case.limits.min_curvature_ratio, breaks_deg=data.breaks_deg)


def draw_conjugate(fig: Figure, data: ReportData) -> None:
    """Both conjugate cams, each roller on its cam; each cam's pressure angle and radius of curvature."""
    chk = data.check
    assert chk.closure is not None and chk.geometry is not None  # drawn for conjugate cams only (pages.PAGES)
    second, geo = chk.closure.conjugate, chk.geometry
    plot_groove_cam(fig.add_axes((0.1, 0.43, 0.56, 0.455)), chk)
    f = data.case.follower
    tie = "yoke" if f.translating else "two-arm rocker"
    fig.text(
        0.08,
        0.94,
        f"conjugate cams: a {tie}, a roller on each cam; grey: the rollers at 0, 90, 180, 270\u00b0",
        size=9,
        weight="bold",
        va="top",
    )
    lines = [
        (
            f"\u25cf max pressure angle: primary {geo.max_pressure_angle_deg:.1f}\u00b0 at "
            f"{geo.max_pressure_angle_at_deg:.1f}\u00b0, conjugate {second.max_pressure_angle_deg:.1f}\u00b0 at "
            f"{second.max_pressure_angle_at_deg:.1f}\u00b0",
            (CheckKind.PRESSURE_ANGLE, CheckKind.CONJUGATE_PRESSURE_ANGLE),
        ),
        (
            f"\u25cf least convex radius: primary {geo.min_radius_of_curvature_mm:.4g} mm at "
            f"{geo.min_radius_of_curvature_at_deg:.1f}\u00b0 (its osculating circle dashed), conjugate "
            + (
                "concave all round"
                if second.curvature is None
                else f"{second.convex.min_convex_radius_mm:.4g} mm at {second.convex.min_convex_radius_at_deg:.1f}"
                "\u00b0"
            ),
            (CheckKind.CURVATURE, CheckKind.CONJUGATE_CURVATURE),
        ),
    ]
    for k, (text, kinds) in enumerate(lines):
        colour = C["fail"] if any(check_colour(chk, kd, C["margin"]) == C["fail"] for kd in kinds) else C["margin"]
        fig.text(0.08, 0.922 - 0.016 * k, text, size=7.8, color=colour, va="top")
    gs = fig.add_gridspec(2, 1, left=LEFT, right=0.95, top=0.37, bottom=0.06, hspace=0.35)
    ax1 = fig.add_subplot(gs[0])
    ax2 = fig.add_subplot(gs[1], sharex=ax1)
    plot_cam_pressure_angles(ax1, chk, breaks_deg=data.breaks_deg)
    ax1.tick_params(labelbottom=False)
    plot_wall_curvature(ax2, chk, min_curvature_ratio=data.case.limits.min_curvature_ratio, breaks_deg=data.breaks_deg)


def draw_crossovers(fig: Figure, data: ReportData) -> None:
    chk = data.check
    assert chk.closure is not None  # drawn for a groove cam only (pages.PAGES)
    held = chk.closure.loads is not None and chk.closure.response.backlash_mm == 0.0  # no flights, no impacts
    rows = [2.4, 1] if held else [1.5, 1, 1]
    gs = fig.add_gridspec(len(rows), 1, left=LEFT, right=0.95, top=0.925, bottom=0.06, hspace=0.4, height_ratios=rows)
    plot_flank_force(fig.add_subplot(gs[0]), chk, breaks_deg=data.breaks_deg)
    if not held:
        assert data.review.impacts is not None  # the review of a form-closed cam has its impacts against speed
        plot_impact_speed(fig.add_subplot(gs[1]), data.review.impacts, speed_rpm=chk.speed_rpm)
    ax = fig.add_subplot(gs[-1])
    ax.axis("off")
    flow = Flow(fig, ax.get_position().y1)
    crossover_table(flow, data)


def crossover_table(flow: Flow, data: ReportData) -> None:
    """One row per crossover: where the force leaves its flank, the flank it lands on, where, how fast, how hard."""
    chk = data.check
    study = chk.closure
    assert study is not None
    lim = data.case.limits.max_impact_velocity
    flow.heading(f"Crossovers at {chk.speed_rpm:g} rpm (limit max_impact_velocity {lim:g} m/s)")
    cols = [
        (0.0, "leaves at"),
        (0.14, "from"),
        (0.24, "lands on"),
        (0.36, "lands at"),
        (0.5, "impact speed"),
        (0.66, "impact force"),
        (0.82, "result"),
    ]
    flow.row([(x, t, {"weight": "bold", "color": C["grey"]}) for x, t in cols], size=8.2)
    for c in study.response.crossovers:
        ok = c.impact_velocity_m_per_s <= lim
        force = "impulse (rigid train)" if c.impact_force_N is None else f"{c.impact_force_N:.4g} N"
        if study.response.backlash_mm == 0.0:
            force = "none (no backlash)"
        flow.row(
            [
                (0.0, f"{c.deg:.2f}\u00b0", {}),
                (0.14, c.from_flank, {}),
                (0.24, c.to_flank, {}),
                (0.36, f"{c.land_deg:.2f}\u00b0", {}),
                (0.5, f"{c.impact_velocity_m_per_s:.4g} m/s", {}),
                (0.66, force, {}),
                (0.82, "pass" if ok else "FAIL", {"color": C["ok"] if ok else C["fail"], "weight": "bold"}),
            ],
            size=8.2,
        )
    if not study.response.crossovers:
        flow.para("none: the contact force stays on one flank all round", size=8.2, color=C["grey"])
    if study.loads is not None:
        flow.para(
            "Two conjugate cams hold the follower both ways: it cannot jump. Where the net force changes sign it "
            "changes cam; with the rollers preloaded against each other both stay loaded (each cam's force = the "
            "preload \u00b1 half the net force, equally stiff contacts) as long as the preload exceeds half the "
            "largest net force; without preload the force crosses any clearance (backlash) and the other cam meets "
            "the roller.",
            size=7.8,
            width=118,
            color=C["grey"],
        )
        return
    flow.para(
        "A groove holds the follower both ways: it cannot jump, so there is no jump speed and no speed margin; where "
        "the force changes sign the roller crosses the backlash and the other flank meets it. The impact speed is "
        "the relative speed at the roller centre; the impact force is the peak of the contact on the flank it lands "
        "on, through the follower train's stiffness; a rigid train's impact is an impulse.",
        size=7.8,
        width=118,
        color=C["grey"],
    )
