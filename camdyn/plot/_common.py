"""What every figure shares: the palette (one meaning per colour), angle axes, breaks and separations."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.ticker import MultipleLocator

# Colours with one meaning each, on every figure.
PALETTE = {
    "kin": "#7f7f7f",  # kinematic (rigid follower, never leaves the cam)
    "dyn": "#1f5fa8",  # dynamic at the case speed
    "margin": "#e07b00",  # dynamic at speed_margin x speed
    "limit": "#c0392b",  # limits, failures, separations
    "ok": "#2e8540",
    "fail": "#c0392b",
    "break": "#999999",  # segment boundaries
    "cam": "#dfe4ea",
    "ink": "#222222",
    "grey": "#666666",
    "warn": "#a86800",
    "advice": "#1b6e75",
    "path": "#9ecae1",
    "traced": "#d62728",
    "constraint": "#b3b3b3",  # one cam angle's constraint on the spring
    "iso": "#7b4fa0",  # iso-lines of the peak spring force
}
C = PALETTE


def deg_ticks(ax, every: float = 45.0) -> None:
    """A cam-angle x axis: one revolution, a tick every ``every`` degrees."""
    ax.set_xlim(0.0, 360.0)
    ax.xaxis.set_major_locator(MultipleLocator(every))


def mark_breaks(ax, breaks_deg) -> None:
    """Dotted lines at the motion's breaks (segment boundaries), behind the curves."""
    for b in breaks_deg:
        ax.axvline(b, color=C["break"], lw=0.7, ls=":", zorder=0.5)


def shade_separations(ax, response, label: bool = False) -> None:
    """Shade the cam angles where the follower is off the cam (a flight may wrap through 0 deg)."""
    first = True
    for s in response.separations:
        spans = [(s.start_deg, s.end_deg)] if s.end_deg >= s.start_deg else [(s.start_deg, 360.0), (0.0, s.end_deg)]
        for a, b in spans:
            ax.axvspan(a, b, color=C["limit"], alpha=0.13, lw=0, zorder=0.4, label="separated" if (label and first) else None)
            first = False


def rotate(angle_rad: float, xy: np.ndarray) -> np.ndarray:
    """Points (2, ...) turned by ``angle_rad`` about the origin."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s], [s, c]]) @ xy
