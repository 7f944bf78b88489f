"""Jump maps drawn: the least contact force over cam speed and spring rate, with the jump boundary."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import QuadMesh
from matplotlib.figure import Figure

from ..design.sweep import JumpMap


def plot_jump_map(ax: Axes, jm: JumpMap) -> QuadMesh | None:
    """Draw the map on a matplotlib ``ax``: least force over speed x spring rate, the jump boundary (least force
    of the in-contact model = 0) and the operating point. A single spring rate (or speed) gives a line plot.
    Returns the artist a colorbar can use (None for a line plot)."""
    ku = jm.spring_rate_unit
    op_label = f"operating point ({jm.speed_rpm:g} rpm, {jm.spring_rate:g} {ku})"
    title = f"{jm.case}: jump map, {jm.model} follower, preload {jm.preload:g} {jm.preload_unit} fixed"
    ax.set_title(title, fontsize=10)
    if jm.spring_rates.size > 1 and jm.speeds_rpm.size > 1:
        mesh = ax.pcolormesh(jm.speeds_rpm, jm.spring_rates, jm.min_force.T, shading="nearest", cmap="viridis")
        ax.contour(jm.speeds_rpm, jm.spring_rates, jm.contact_force.T, levels=[0.0], colors="red", linewidths=1.5)
        ax.plot([], [], color="red", label="float boundary" if jm.valve is not None else "jump boundary (Fi = 0)")
        if jm.valve is not None:  # where the valve leaves its seat after closing
            bounced = jm.valve.bounced.astype(float).T
            ax.contour(jm.speeds_rpm, jm.spring_rates, bounced, levels=[0.5], colors="orange", linewidths=1.5)
            ax.plot([], [], color="orange", label="bounce boundary")
        ax.plot(
            [jm.speed_rpm],
            [jm.spring_rate],
            marker="*",
            markersize=12,
            color="white",
            markeredgecolor="black",
            linestyle="none",
            label=op_label,
        )
        ax.set_xlabel("cam speed (rpm)")
        ax.set_ylabel(f"spring rate ({ku})")
        ax.legend(loc="upper left", fontsize=8)
        return mesh
    if jm.spring_rates.size == 1:
        x, xlabel, f, op_x = jm.speeds_rpm, "cam speed (rpm)", jm.contact_force[:, 0], jm.speed_rpm
        ax.set_title(title + f", spring rate {jm.spring_rates[0]:g} {ku}", fontsize=10)
    else:
        x, xlabel, f, op_x = jm.spring_rates, f"spring rate ({ku})", jm.contact_force[0, :], jm.spring_rate
        ax.set_title(title + f", {jm.speeds_rpm[0]:g} rpm", fontsize=10)
    ax.plot(x, np.maximum(f, 0.0), color="C0", marker="." if x.size < 50 else None, label="least contact force")
    ax.axhline(0.0, color="grey", linewidth=0.8)
    cross = np.nonzero(np.diff(np.sign(f)) != 0)[0]
    for j, i in enumerate(cross):  # linear interpolation of the sign change
        xb = x[i] - f[i] * (x[i + 1] - x[i]) / (f[i + 1] - f[i])
        ax.axvline(xb, color="red", linewidth=1.2, label="jump boundary (Fi = 0)" if j == 0 else None)
    if jm.valve is not None:  # the points where the valve bounces
        hit = (jm.valve.bounced[:, 0] if jm.spring_rates.size == 1 else jm.valve.bounced[0, :]).astype(bool)
        ax.plot(x[hit], np.maximum(f, 0.0)[hit], "x", color="orange", label="valve bounces")
    ax.axvline(op_x, color="black", linestyle="--", linewidth=1.0, label=op_label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("least contact force (N)")
    ax.legend(loc="best", fontsize=8)
    return None


def save_png(jm: JumpMap, path: str | Path) -> None:
    """Write the heat map (or line plot) of ``jm`` as a PNG (matplotlib, no pyplot state)."""
    fig = Figure(figsize=(8, 5.5), layout="constrained")
    ax = fig.add_subplot()
    art = plot_jump_map(ax, jm)
    if art is not None:
        fig.colorbar(art, ax=ax, label="least contact force (N)")
    fig.savefig(path, dpi=120)
