"""The tolerance page (cases with ``[tolerances]``): what fraction of the built cams jump, the spread of the jump
speed, and which tolerance matters, from the review's tolerance study."""

from __future__ import annotations

import math

from matplotlib.figure import Figure

from ..._core.results import Unavailable
from ...plot import plot_jump_speed_histogram, plot_tolerance_tornado
from .._data import ReportData
from .._layout import Flow
from .._style import LEFT, C


def draw_tolerances(fig: Figure, data: ReportData) -> None:
    res = data.review.tolerance
    flow = Flow(fig, 0.94)
    if isinstance(res, Unavailable):
        flow.para("The tolerance study failed:", size=9, weight="bold", color=C["fail"])
        flow.para(res.reason, size=8.5, width=110, color=C["ink"])
        return
    assert res is not None  # the page is drawn for a case with [tolerances] only (pages.PAGES)
    lo, hi = res.confidence_interval
    colour = C["ok"] if hi < 0.01 else (C["warn"] if res.probability < 0.05 else C["fail"])
    flow.para(
        f"Probability of separation at {res.speed_rpm:g} rpm: {res.probability:.3g} ({res.confidence:.0%} interval "
        f"{lo:.3g} to {hi:.3g}), {res.samples} built cams (seed {res.seed})",
        size=9,
        weight="bold",
        color=colour,
    )
    q, f = res.percentiles(res.jump_speed_rpm), res.percentiles(res.least_force)
    for line in (  # a line each: as one sentence its last word wrapped alone
        f"Dynamic jump speed P1 {q['p1']:.1f}, P5 {q['p5']:.1f}, P50 {q['p50']:.1f} rpm (nominal "
        f"{res.nominal_jump_speed_rpm:.1f} rpm).",
        f"Least contact force P1 {f['p1']:.4g}, P5 {f['p5']:.4g}, P50 {f['p50']:.4g} N.",
    ):
        flow.para(line, size=8, width=130, color=C["ink"])
    given = ", ".join(f"{k} {t['tolerance']:g} {t['unit']} ({t['distribution']})" for k, t in res.tolerances.items())
    flow.para(
        f"Tolerances: {given or 'none'}. Normal: the tolerance is 3 sigma; uniform: the half-width; profile error: "
        "the RMS of a random lift error of harmonics 1-8 (not in the worst samples' case files).",
        size=7.5,
        width=140,
        color=C["grey"],
    )
    ax = fig.add_axes((LEFT, 0.5, 0.95 - LEFT, 0.3))
    plot_jump_speed_histogram(ax, res)
    ax = fig.add_axes((0.25, 0.1, 0.7, 0.3))
    plot_tolerance_tornado(ax, res)
    if not all(math.isfinite(s["gradient_sigma"]) for s in res.sensitivities.values()):
        ax.text(
            0.5,
            0.5,
            "no jump speed at the nominal design: no gradients",
            transform=ax.transAxes,
            ha="center",
            color=C["grey"],
        )
