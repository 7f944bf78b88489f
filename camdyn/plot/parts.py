"""Figures of the parts: the spring as a drawing with its dimensions, the camshaft torque, the contact stress."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle

from ..model.contact import ContactStress
from ..model.drive import DriveTorque
from ._common import C, deg_ticks, mark_mean_and_peak_torque

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.spring import SpringDesign


def _coil_positions(design: SpringDesign) -> np.ndarray:
    """Axial position (mm, 0 at one end) of each half turn of the wire's centre, at the free length: the end
    coils closed (pitch d), the active coils at the spring's pitch; ground ends cut to the free length."""
    s = design.spring
    ends = (s.total_coils - s.active_coils) / 2.0
    halves = np.arange(0, 2 * s.total_coils + 1) / 2.0
    pitch = np.where((halves < ends) | (halves > s.total_coils - ends), s.wire_diameter, s.pitch)
    x = np.concatenate([[0.0], np.cumsum(0.5 * pitch[1:])])
    return s.wire_diameter / 2 + (x - x[0]) * (s.free_length - s.wire_diameter) / max(x[-1] - x[0], 1e-12)


def _dimension(ax, a, b, y, text, vertical=False):
    """A dimension line with arrows both ends and its text beside its middle."""
    (x0, y0), (x1, y1) = ((y, a), (y, b)) if vertical else ((a, y), (b, y))
    ax.annotate("", (x0, y0), (x1, y1), arrowprops=dict(arrowstyle="<->", lw=0.8, color="0.2"))
    ax.annotate(
        text,
        ((x0 + x1) / 2, (y0 + y1) / 2),
        xytext=(-3, 0) if vertical else (0, 2),
        textcoords="offset points",
        fontsize=7,
        ha="right" if vertical else "center",
        va="center" if vertical else "bottom",
        rotation=90 if vertical else 0,
    )


def plot_spring(ax: Axes, design: SpringDesign) -> None:
    """The spring at its free length, in section (the wire cut on both sides of the coil), with its free,
    installed, full-lift and solid lengths, its outside diameter and what it is made of."""
    s = design.spring
    r, d = s.mean_diameter / 2, s.wire_diameter
    x = _coil_positions(design)
    y = np.where(np.arange(x.size) % 2 == 0, r, -r)
    ax.plot(x, y, color="0.55", lw=0.6)  # the wire's centre line, front half turns
    for xi, yi in zip(x, y, strict=True):
        ax.add_patch(Circle((xi, yi), d / 2, fc="0.35", ec="k", lw=0.4))
    L0, top, gap = s.free_length, r + d / 2, 0.28 * s.outside_diameter  # gap: between dimension lines
    ax.plot([0, 0], [-top - 0.2 * gap, top + 0.2 * gap], color="k", lw=1.5)  # the fixed seat
    _dimension(ax, 0, L0, top + 0.8 * gap, f"free length {L0:.1f}")
    lengths = (
        (design.installed_length, "installed (preload)"),
        (design.full_lift_length, "full lift"),
        (s.solid_length, "solid"),
    )
    for n, (length, name) in enumerate(lengths):
        _dimension(ax, 0, length, -top - (0.8 + n) * gap, f"{name} {length:.1f}")
    _dimension(
        ax,
        -s.outside_diameter / 2,
        s.outside_diameter / 2,
        L0 + 0.8 * gap,
        f"OD {s.outside_diameter:.2f}",
        vertical=True,
    )
    bottom = -top - (len(lengths) + 0.5) * gap
    ax.text(
        0,
        bottom,
        f"{s.material} (ASTM {s.wire.astm}), wire d {d:g}, mean D {s.mean_diameter:.2f}, {s.active_coils:g} active / "
        f"{s.total_coils:g} total coils, {s.end_type} ends\nrate {s.rate:.4g} N/mm, preload {design.preload:.4g} N, "
        f"mass {1e3 * s.mass:.3g} g, surge {s.surge_frequency:.4g} Hz",
        fontsize=7,
        ha="left",
        va="top",
    )
    ax.set_aspect("equal")
    ax.set_xlim(-0.05 * L0 - gap, L0 + 1.6 * gap)
    ax.set_ylim(bottom - 1.4 * gap, top + 1.4 * gap)
    ax.axis("off")
    ax.set_title("return spring (lengths in mm)")


def plot_drive(ax: Axes, drive: DriveTorque) -> None:
    """Camshaft torque over a revolution, its mean and its peak."""
    ax.plot(drive.theta_deg, drive.torque, color=C["dyn"], lw=1.2, label="camshaft torque")
    mark_mean_and_peak_torque(ax, drive.theta_deg, drive, C["margin"])
    deg_ticks(ax, 45.0)
    ax.set_xlabel("cam angle \u03b8 (deg)")
    ax.set_ylabel("camshaft torque (N\u00b7m)")
    ax.set_title(
        f"drive: flywheel {drive.flywheel_inertia:.3g} kg\u00b7m\u00b2 for a speed fluctuation of "
        f"{drive.speed_fluctuation:g}"
    )
    ax.legend(fontsize=7, loc="best")


def plot_contact(ax: Axes, contact: ContactStress, limit_MPa: float | None = None) -> None:
    """Hertz contact pressure over a revolution, its peak and the limit."""
    ax.plot(contact.theta_deg, contact.pressure_MPa, color=C["dyn"], lw=1.2, label="peak contact pressure")
    ax.plot(
        [contact.peak_at_deg],
        [contact.peak_pressure_MPa],
        "o",
        color=C["limit"],
        ms=5,
        label=f"max {contact.peak_pressure_MPa:.4g} MPa at {contact.peak_at_deg:.1f}\u00b0",
    )
    if limit_MPa is not None:
        ax.axhline(limit_MPa, color="k", lw=0.8, ls="--", label=f"limit {limit_MPa:g} MPa")
    deg_ticks(ax, 45.0)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("cam angle \u03b8 (deg)")
    ax.set_ylabel("contact pressure (MPa)")
    ax.set_title(f"Hertz contact, width {contact.width_mm:g} mm")
    ax.legend(fontsize=7, loc="best")
