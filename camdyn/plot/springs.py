"""The rate-preload plane of a spring sizing: which springs hold, and the one chosen."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.sizing import SpringSizing


# colours of plot_feasible_region by role
PLOT_COLORS = {
    "kinematic": "tab:green",  # feasible region (kinematic) and the kinematic LP answer
    "dynamic": "tab:blue",  # feasible region (dynamic, compliant train)
    "lines": "0.55",  # constraint lines
    "iso": "tab:orange",  # iso-lines of the peak spring force
    "chosen": "tab:red",
    "current": "k",
}


def plot_feasible_region(ax: Axes, sizing: SpringSizing, colors: dict | None = None) -> None:
    """The rate-preload plane: constraint lines (the binding ones and those forming the envelope), the feasible
    region shaded (kinematic; dynamic too for a compliant follower), iso-lines of the peak spring force, the
    chosen spring, the kinematic LP answer and the case's current spring. ``colors`` overrides any of the
    colours by role (keys of :data:`PLOT_COLORS`), as the design-review report does with its own palette."""
    col = PLOT_COLORS | (colors or {})
    u = sizing.units
    k = np.asarray(sizing.region_rate)
    f_kin = np.asarray(sizing.region_preload_kinematic)
    f_dyn = None if sizing.region_preload_dynamic is None else np.asarray(sizing.region_preload_dynamic)
    pts = [sizing.chosen, sizing.kinematic, sizing.current]
    lows = [f_kin.min(), *(d.preload for d in pts)] + ([] if f_dyn is None else [f_dyn.min()])
    highs = [f_kin.max(), *(d.preload for d in pts)] + ([] if f_dyn is None else [f_dyn.max()])
    span = max(highs) - min(lows) or max(1.0, abs(max(highs)))
    y0, y1 = min(lows) - 0.15 * span, max(highs) + 0.25 * span
    kin_label = "feasible (kinematic)"
    ax.fill_between(k, f_kin, y1, color=col["kinematic"], alpha=0.15, label=kin_label, linewidth=0)
    ax.plot(k, f_kin, color=col["kinematic"], lw=1.5)
    if f_dyn is not None:
        ax.fill_between(
            k, f_dyn, y1, color=col["dynamic"], alpha=0.15, label="feasible (dynamic, compliant train)", linewidth=0
        )
        ax.plot(k, f_dyn, color=col["dynamic"], lw=1.5)
    for n, (_theta_deg, s, r) in enumerate(sizing.lines):
        ax.plot(
            k,
            r - k * s,
            color=col["lines"],
            lw=0.6,
            ls="-",
            label="constraint lines (envelope, binding)" if n == 0 else None,
        )
    s_max = sizing.s_max
    peaks = sorted({round(d.peak_spring, 9) for d in pts})
    labelled: list[float] = []
    for n, peak in enumerate(peaks):
        label = f"iso peak spring {sizing.kind.force_word}" if n == 0 else None  # an arm's spring: a torque
        ax.plot(k, peak - k * s_max, color=col["iso"], lw=0.8, ls=":", label=label)
        if any(abs(peak - q) <= 0.03 * max(abs(peak), abs(q), 1e-300) for q in labelled):
            continue  # one label for iso-lines that nearly coincide
        # the label on the part of the line inside the plot, staggered along it from one line to the next
        seen = np.nonzero((peak - k * s_max > y0 + 0.08 * (y1 - y0)) & (peak - k * s_max < y1 - 0.12 * (y1 - y0)))[0]
        if seen.size == 0:
            continue
        kx = k[seen[min(len(seen) - 1, (len(seen) * (1 + len(labelled))) // 4)]]
        ax.annotate(
            f"P = {peak:.4g} {u['spring']}",
            (kx, peak - kx * s_max),
            xytext=(3, 2),
            textcoords="offset points",
            fontsize=7,
            color=col["iso"],
            bbox=dict(fc="white", ec="none", alpha=0.75, pad=0.6),
        )
        labelled.append(peak)
    if sizing.model == "compliant":
        ax.plot(
            [sizing.kinematic.rate],
            [sizing.kinematic.preload],
            "o",
            mfc="none",
            mec=col["kinematic"],
            ms=8,
            label="kinematic LP answer",
        )
    if sizing.part is not None:  # a part that can be built: the answer
        ax.plot(
            [sizing.chosen.rate], [sizing.chosen.preload], "*", color=col["chosen"], ms=12, label="chosen (buildable)"
        )
    else:  # the least peak force any spring needs: a bound, maybe no spring at all
        label = f"bound: least peak {sizing.kind.force_word} (not a part; size --buildable)"
        ax.plot([sizing.chosen.rate], [sizing.chosen.preload], "D", mfc="none", mec=col["chosen"], ms=8, label=label)
    ax.plot(
        [sizing.current.rate],
        [sizing.current.preload],
        "s",
        mfc="none",
        mec=col["current"],
        ms=7,
        label="current design",
    )
    ax.set_xlim(k[0], k[-1])
    ax.set_ylim(y0, y1)
    if sizing.kind.rotary:
        ax.set_xlabel(f"torsion rate k ({u['rate']})")
        ax.set_ylabel(f"preload torque T0 ({u['preload']})")
    else:
        ax.set_xlabel(f"spring rate k ({u['rate']})")
        ax.set_ylabel(f"preload F0 ({u['preload']})")
    ax.set_title(f"{sizing.case_name}: springs that hold up to {sizing.top_speed_rpm:.4g} rpm")
    ax.legend(fontsize=7, loc="best")
