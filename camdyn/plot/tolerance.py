"""Tolerance studies drawn: the spread of the jump speed against the case speed, and the sensitivities."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ._common import PALETTE, sample_histogram

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.tolerance import ToleranceResult, ValveToleranceResult


def plot_jump_speed_histogram(ax: Axes, result: ToleranceResult) -> None:
    """Histogram of the samples' dynamic jump speed (rpm), the case speed and the P1/P50 marked."""
    q = result.percentiles(result.jump_speed_rpm)
    lo, hi = result.confidence_interval
    sample_histogram(
        ax,
        result.jump_speed_rpm,
        (result.speed_rpm, f"case speed {result.speed_rpm:g} rpm"),
        [
            (q[n], style, f"{n.upper()} {q[n]:.1f} rpm")
            for n, style in (("p1", ":"), ("p50", "--"))
            if math.isfinite(q[n])
        ],
        f"{result.case}: dynamic jump speed of {result.samples} built cams; P(separation) = {result.probability:.3g} "
        f"[{lo:.3g}, {hi:.3g}]",
        "dynamic jump speed (rpm)",
    )


def plot_tolerance_tornado(ax: Axes, result: ToleranceResult) -> None:
    """Tornado chart: each tolerance's effect on the jump-speed margin (d margin / d p x sigma, from gradients),
    largest on top, its Monte Carlo variance share written beside it."""
    items = sorted(result.sensitivities.items(), key=lambda kv: abs(np.nan_to_num(kv[1]["gradient_sigma"])))
    names = [k for k, _ in items]
    vals = np.array([np.nan_to_num(v["gradient_sigma"]) for _, v in items])
    y = np.arange(len(names))
    ax.barh(y, vals, color=[PALETTE["ok"] if v >= 0 else PALETTE["fail"] for v in vals])
    ax.set_yticks(y, [n.replace("_", " ") for n in names])
    ax.axvline(0.0, color=PALETTE["grey"], linewidth=0.8)
    for yi, (_, v), x in zip(y, items, vals, strict=True):
        share = v["share_monte_carlo"]
        # on the other side of zero from the bar: never over it, never past the axes
        ax.annotate(
            f"MC share {share:.0%}" if math.isfinite(share) else "",
            (0.0, yi),
            xytext=(-4 if x >= 0 else 4, 0),
            textcoords="offset points",
            ha="right" if x >= 0 else "left",
            va="center",
            fontsize=7,
        )
    # two lines: as one it was wider than the axes and ran off the side-by-side PNG
    ax.set_xlabel("change of the jump-speed margin per sigma (x)\nprofile error: per RMS over its harmonics")
    ax.set_title("sensitivities at the nominal design (JAX gradients), Monte Carlo shares", fontsize=9)


def _save_side_by_side(left: Callable, right: Callable, result: object, path: str | Path) -> None:
    """Two plots of ``result`` side by side, as a PNG."""
    fig = Figure(figsize=(12, 4.8), layout="constrained")
    a, b = fig.subplots(1, 2)
    left(a, result)
    right(b, result)
    fig.savefig(path, dpi=110)


def save_tolerance_png(result: ToleranceResult, path: str | Path) -> None:
    """The histogram and the tornado chart side by side, as a PNG."""
    _save_side_by_side(plot_jump_speed_histogram, plot_tolerance_tornado, result, path)


def plot_valve_speed_histogram(ax: Axes, result: ValveToleranceResult) -> None:
    """Histograms of the built valvetrains' float and bounce speeds (rpm), the case speed and the nominal ones."""
    for values, name, color, nominal in (
        (result.float_speed_rpm, "float", PALETTE["dyn"], result.nominal_float_speed_rpm),
        (result.bounce_speed_rpm, "bounce", PALETTE["fail"], result.nominal_bounce_speed_rpm),
    ):
        ok = values[np.isfinite(values)]
        if ok.size:
            ax.hist(ok, bins=min(40, max(8, int(np.sqrt(ok.size)))), color=color, alpha=0.6, label=f"{name} speed")
        if math.isfinite(nominal):
            ax.axvline(nominal, color=color, linestyle="--", linewidth=1, label=f"nominal {name} {nominal:.0f} rpm")
    ax.axvline(result.speed_rpm, color=PALETTE["limit"], linewidth=1.5, label=f"case speed {result.speed_rpm:g} rpm")
    p_float, _ = result.probability(result.floated)
    p_bounce, _ = result.probability(result.bounced)
    ax.set_title(
        f"{result.case}: {result.samples} built valvetrains; P(float) = {p_float:.3g}, P(bounce) = {p_bounce:.3g} "
        "at their speed",
        fontsize=9,
    )
    ax.set_xlabel("speed (rpm)")
    ax.set_ylabel("samples")
    ax.legend(fontsize=8)


def plot_seating_velocity_histogram(ax: Axes, result: ValveToleranceResult) -> None:
    """Histogram of the built valvetrains' seating velocity at their speed (m/s)."""
    v = result.seating_velocity[np.isfinite(result.seating_velocity)]
    if v.size:
        ax.hist(v, bins=min(40, max(8, int(np.sqrt(v.size)))), color=PALETTE["ok"], alpha=0.8)
    ax.set_xlabel("seating velocity at the sample's speed (m/s)")
    ax.set_ylabel("samples")
    ax.set_title("the valve landing on its seat", fontsize=9)


def save_valve_tolerance_png(result: ValveToleranceResult, path: str | Path) -> None:
    """A valvetrain's float and bounce speeds and its seating velocity side by side, as a PNG."""
    _save_side_by_side(plot_valve_speed_histogram, plot_seating_velocity_histogram, result, path)
