"""Page 5 of a path case, the mechanism: the cam-linkage at six cam angles, the target and traced path, the
path error."""

from __future__ import annotations

import textwrap

import numpy as np
from matplotlib.figure import Figure

from ...plot import mechanism_bounds, plot_mechanism, plot_path, plot_path_error
from ...plot.mechanism import JOINTS
from .._data import ReportData
from .._style import A4, C

NCOLS = 3


def draw_mechanism(fig: Figure, data: ReportData) -> None:
    syn = data.case.synthesis
    kind = syn.mechanism.type
    angles = np.arange(0.0, 360.0, 60.0)
    lo, hi = mechanism_bounds(syn, angles)
    nrows = len(angles) // NCOLS
    # rows as tall as the drawings (equal aspect), the rest of the page to the path plots
    width_in = (0.89 * A4[0] - 2 * 0.6) / NCOLS
    height_in = min(width_in * (hi - lo)[1] / (hi - lo)[0], 2.7)
    grid_bottom = 0.895 - (nrows * height_in + (nrows - 1) * 0.45) / A4[1]
    gs = fig.add_gridspec(
        nrows, NCOLS, left=0.08, right=0.97, top=0.895, bottom=grid_bottom, hspace=0.45 / height_in, wspace=0.22
    )
    caption = (
        f"The linkage at six cam angles. {JOINTS[kind]}; \u25b2 fixed pivots; red: the tracing point on the target "
        "path (light blue)" + ("; grey bar: the slider, from its roller to E." if kind == "ccm" else ".")
    )
    fig.text(0.06, 0.94, "\n".join(textwrap.wrap(caption, 140)), size=7.5, color=C["grey"], va="top", linespacing=1.3)
    for k, a in enumerate(angles):
        ax = fig.add_subplot(gs[k // NCOLS, k % NCOLS])
        plot_mechanism(ax, syn, a, bounds=(lo, hi), label_joints=k == 0)
        ax.tick_params(labelsize=6.5)
        if k % NCOLS == 0:
            ax.set_ylabel("y (mm)", fontsize=7.5)
        if k >= len(angles) - NCOLS:
            ax.set_xlabel("x (mm)", fontsize=7.5)
    path_box, error_box = _path_boxes(syn.path_xy, grid_bottom - 0.075)
    plot_path(fig.add_axes(path_box), syn)
    plot_path_error(fig.add_axes(error_box), syn, float(data.case.limits.max_path_error))


_Box = tuple[float, float, float, float]  # an axes' rectangle: left, bottom, width, height (figure fractions)


def _path_boxes(path_xy: np.ndarray, top: float, bottom: float = 0.065) -> tuple[_Box, _Box]:
    """Axes (figure fractions) for the path and its error below the linkage drawings, filling the page down to
    ``bottom``: side by side, or for a path much wider than tall the path across the page (as tall as it needs)
    and the error under it, whichever draws the path larger."""
    span = np.ptp(path_xy, axis=0)
    dx, dy = span + 0.12 * span.max()  # room for the angle labels
    height_in = (top - bottom) * A4[1]
    side_in, width_in = 0.38 * A4[0], 0.88 * A4[0]
    gap_in, error_in = 0.75, 1.5  # the path's x label and the error's title; the least error plot
    stacked_in = min(height_in - gap_in - error_in, width_in * dy / dx)  # the path box, at the path's aspect
    if min(width_in / dx, stacked_in / dy) <= 1.2 * min(side_in / dx, height_in / dy):
        return (0.08, bottom, 0.38, top - bottom), (0.58, bottom, 0.38, top - bottom)
    path_h = stacked_in / A4[1]
    return (0.08, top - path_h, 0.88, path_h), (0.08, bottom, 0.88, top - path_h - gap_in / A4[1] - bottom)
