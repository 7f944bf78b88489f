"""Figures of a machine (many cams on one shaft): the timing diagram, the shaft torque, the energy and the clearances.
Each draws on an ``ax`` from a :class:`camdyn.design.machine.MachineResult`."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes

from ..design.machine import MachineResult
from ._common import C, deg_ticks, mark_mean_and_peak_torque

LANE = 1.5  # height of a follower's lane in the timing diagram (its stroke is 1)
CAM_COLOURS = ("#1f5fa8", "#e07b00", "#2e8540", "#7b4fa0", "#b5651d", "#1b6e75", "#c0392b", "#555555")


def cam_colour(i: int) -> str:
    """The colour of the machine's ``i``-th cam, the same on every figure."""
    return CAM_COLOURS[i % len(CAM_COLOURS)]


def _spans(a: float, b: float) -> list[tuple[float, float]]:
    """A span of machine angles as one or two pieces within [0, 360] (a dwell through 0 deg is two)."""
    return [(a, b)] if b > a else [(a, 360.0), (0.0, b)]


def plot_timing_diagram(ax: Axes, result: MachineResult) -> None:
    """Every follower's lift over its stroke against the machine angle, one lane per cam (the first on top), its
    dwells shaded and a dashed line where its cam angle is 0 (its phase)."""
    n = len(result.cams)
    theta = result.theta_deg
    for i, cam in enumerate(result.cams):
        base = (n - 1 - i) * LANE
        colour = cam_colour(i)
        for a, b in cam.dwells_deg:
            for lo, hi in _spans(a, b):
                ax.fill_between([lo, hi], base - 0.1, base + 1.1, color=colour, alpha=0.10, lw=0)
        ax.plot(theta, base + cam.normalized_lift, color=colour, lw=1.4)
        phase = cam.phase_deg % 360.0
        ax.plot([phase, phase], [base - 0.2, base + 1.2], color=colour, lw=0.9, ls="--")
        ax.annotate(
            f"{phase:g}\u00b0",
            (phase, base + 1.2),
            xytext=(2, -1),
            textcoords="offset points",
            fontsize=6.5,
            color=colour,
            va="top",
        )
        ax.axhline(base, color="0.75", lw=0.5, zorder=0.3)
        stroke = f"{np.ptp(cam.lift):.3g} {cam.lift_unit}"
        ax.text(
            -6, base + 0.5, f"{cam.name}\n{stroke}", ha="right", va="center", fontsize=7.5, color=colour, weight="bold"
        )
    deg_ticks(ax, 30.0)
    ax.set_ylim(-0.35, (n - 1) * LANE + 1.35)
    ax.set_yticks([])
    ax.set_xlabel("machine angle (deg)")
    ax.set_title(
        f"timing diagram at {result.speed_rpm:g} rpm: lift over stroke, dwells shaded, dashed at each cam's 0\u00b0"
    )


def plot_machine_torque(ax: Axes, result: MachineResult) -> None:
    """Each cam's shaft torque (thin) and their sum (thick), the sum's mean and its peak."""
    theta, drive = result.theta_deg, result.drive
    for i, cam in enumerate(result.cams):
        ax.plot(theta, cam.torque, color=cam_colour(i), lw=0.8, alpha=0.9, label=cam.name)
    ax.plot(theta, drive.torque, color=C["ink"], lw=1.6, label="shaft (sum)")
    mark_mean_and_peak_torque(ax, theta, drive, C["grey"])
    deg_ticks(ax, 30.0)
    ax.set_xlabel("machine angle (deg)")
    ax.set_ylabel("shaft torque (N\u00b7m)")
    ax.set_title(
        f"main-shaft torque: RMS {drive.rms_torque:.3g} N\u00b7m, peak power {drive.peak_torque * drive.omega:.3g} W"
    )
    ax.legend(fontsize=6.5, loc="best", ncol=2)


def plot_machine_energy(ax: Axes, result: MachineResult) -> None:
    """The energy the shaft stores and gives back over a revolution, its swing, and the flywheel that holds it."""
    drive = result.drive
    energy = drive.energy
    ax.plot(drive.theta_deg, energy, color=C["dyn"], lw=1.2)
    lo, hi = int(np.argmin(energy)), int(np.argmax(energy))
    for k in (lo, hi):
        ax.axhline(energy[k], color=C["grey"], lw=0.6, ls=":")
    ax.annotate(
        "",
        (drive.theta_deg[hi], energy[hi]),
        (drive.theta_deg[hi], energy[lo]),
        arrowprops={"arrowstyle": "<->", "lw": 0.8, "color": C["limit"]},
    )
    ax.annotate(
        f"\u0394E {drive.energy_swing:.3g} J",
        (drive.theta_deg[hi], 0.5 * (energy[lo] + energy[hi])),
        xytext=(4, 0),
        textcoords="offset points",
        fontsize=7.5,
        color=C["limit"],
    )
    deg_ticks(ax, 30.0)
    ax.set_xlabel("machine angle (deg)")
    ax.set_ylabel("energy \u222b(T \u2212 mean T) d\u03b8 (J)")
    ax.set_title(
        f"flywheel {drive.flywheel_inertia:.3g} kg\u00b7m\u00b2 holds the speed to "
        f"\u00b1{100 * drive.speed_fluctuation / 2:g} % (k_s {drive.speed_fluctuation:g})"
    )


def plot_clearances(ax: Axes, result: MachineResult) -> None:
    """The gap of every ``[[clearance]]`` pair against the machine angle, its least and the gap it needs."""
    for k, gap in enumerate(result.clearances):
        colour = C["ok"] if gap.check.ok else C["fail"]
        ax.plot(
            result.theta_deg,
            gap.gap_mm,
            color=CAM_COLOURS[(k + 3) % len(CAM_COLOURS)],
            lw=1.2,
            label=" \u2194 ".join(gap.between),
        )
        ax.axhline(gap.min_gap_mm, color=C["limit"], lw=0.8, ls="--")
        ax.plot(
            [gap.least_gap_at_deg],
            [gap.least_gap_mm],
            "o",
            color=colour,
            ms=5,
            label=f"least {gap.least_gap_mm:.3g} mm at {gap.least_gap_at_deg:.1f}\u00b0 (needs {gap.min_gap_mm:g})",
        )
    deg_ticks(ax, 30.0)
    ax.set_xlabel("machine angle (deg)")
    ax.set_ylabel("gap (mm)")
    ax.set_title("clearance between followers that share space")
    ax.legend(fontsize=7, loc="best")
