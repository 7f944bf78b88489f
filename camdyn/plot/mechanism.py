"""A path case's cam-linkage drawn: the mechanism at a cam angle, the target and traced path, the path error."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle, Polygon
from numpy.typing import ArrayLike

from .._core.units import DEFAULT_MAX_PATH_ERROR_MM
from ..model.linkage import Synthesis
from ._common import C, rotate

LINKS = {
    "ccm": [("A", "B"), ("B", "T"), ("B", "C"), ("C", "E")],
    "oscillating": [("O", "A"), ("A", "B"), ("F", "C"), ("C", "D"), ("D", "E")],
}
GROUND = {"ccm": ("A",), "oscillating": ("O", "D")}  # the fixed pivots
TRACER = {"ccm": "T", "oscillating": "F"}  # the joint that traces the path
JOINTS = {
    "ccm": "A cam centre and crank, B crank pin, T tracing point, C coupler joint, E slider pin",
    "oscillating": "O cam centre, A crank pin, B coupler pin, F tracing point, C follower joint, D arm pivot, E roller",
}


def mechanism_frames(synthesis: Synthesis, theta_deg: ArrayLike) -> dict:
    """The mechanism at cam angles ``theta_deg`` (case frame, mm): ``points`` (joint name -> (n, 2)), the
    ``roller`` centres (n, 2) and the turned ``cams`` (a list of (m, 2) outlines)."""
    syn = synthesis
    angles = np.atleast_1d(np.asarray(theta_deg, dtype=float))
    pts = syn.linkage_at(angles)
    sense = 1.0 if syn.summary["rotation"] == "ccw" else -1.0
    c0 = np.asarray(syn.mechanism.cam_center, dtype=float)
    idx = np.round(angles).astype(int) % 360
    roller = np.stack([rotate(sense * math.radians(a), syn.pitch[i]) for a, i in zip(angles, idx, strict=True)]) + c0
    cams = [(rotate(sense * math.radians(a), syn.contour.T)).T + c0 for a in angles]
    return {"points": pts, "roller": roller, "cams": cams}


def mechanism_bounds(synthesis: Synthesis, theta_deg: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) x-y corners (mm) that hold every joint over a revolution, the target path, and the cams and
    rollers at ``theta_deg``, with a margin: common limits for drawings of the mechanism at those angles."""
    syn = synthesis
    fr = mechanism_frames(syn, theta_deg)
    rr = syn.mechanism.roller_radius
    every = syn.linkage_at(np.arange(0.0, 360.0, 5.0))
    allxy = np.vstack([v for v in every.values()] + [syn.path_xy] + fr["cams"] + [fr["roller"] + rr, fr["roller"] - rr])
    lo, hi = allxy.min(axis=0), allxy.max(axis=0)
    pad = 0.06 * (hi - lo).max()
    return lo - pad, hi + pad


def plot_mechanism(
    ax: Axes,
    synthesis: Synthesis,
    theta_deg: float,
    *,
    bounds: tuple[np.ndarray, np.ndarray] | None = None,
    label_joints: bool = False,
) -> None:
    """The cam-linkage at cam angle ``theta_deg``: the target path, the turned cam and its roller, the links, the
    fixed pivots and the tracing point. ``bounds``: :func:`mechanism_bounds` (default: this angle's);
    ``label_joints``: name the joints."""
    syn = synthesis
    kind = syn.mechanism.type
    lo, hi = bounds if bounds is not None else mechanism_bounds(syn, [theta_deg])
    fr = mechanism_frames(syn, [theta_deg])
    pts = {name: xy[0] for name, xy in fr["points"].items()}
    roller = fr["roller"][0]
    ax.set_aspect("equal")
    ax.grid(False)
    ax.plot(*syn.path_xy.T, color=C["path"], lw=2.5, zorder=1)
    ax.add_patch(Polygon(fr["cams"][0], closed=True, fc=C["cam"], ec=C["ink"], lw=0.8, zorder=2))
    if kind == "ccm":
        m = syn.mechanism
        assert m.slider_angle is not None  # the schema: a ccm needs slider_angle
        e_dir = np.array([math.cos(math.radians(m.slider_angle)), math.sin(math.radians(m.slider_angle))])
        sp = np.asarray(m.slider_point if m.slider_point is not None else m.cam_center, dtype=float)
        span = (hi - lo).max() * 1.5
        ax.plot(*np.c_[sp - e_dir * span, sp + e_dir * span], color=C["grey"], lw=0.7, ls="-.", zorder=1)
        e = pts["E"]
        ax.plot(
            [roller[0], e[0]], [roller[1], e[1]], color=C["ink"], lw=3.0, alpha=0.6, zorder=3, solid_capstyle="butt"
        )
    ax.add_patch(Circle(roller, syn.mechanism.roller_radius, fc="white", ec=C["ink"], lw=1.0, zorder=4))
    for p, q in LINKS[kind]:
        if p in pts and q in pts and np.linalg.norm(pts[p] - pts[q]) > 1e-9:
            ax.plot(
                [pts[p][0], pts[q][0]], [pts[p][1], pts[q][1]], color=C["dyn"], lw=1.8, zorder=5, solid_capstyle="round"
            )
    for xy in pts.values():
        ax.plot(*xy, "o", ms=3.2, mfc="white", mec=C["dyn"], mew=1.0, zorder=6)
    for g in GROUND[kind]:
        ax.plot(*pts[g], marker="^", ms=8, color=C["ink"], zorder=6, ls="none")
    ax.plot(*pts[TRACER[kind]], "o", ms=5, color=C["traced"], zorder=7)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_title(f"\u03b8 = {theta_deg:g}\u00b0", fontsize=8.5)
    if label_joints:
        _label_joints(ax, pts, (hi - lo).max())


def _label_joints(ax, pts: dict, size: float) -> None:
    """Joint names beside the joints, away from their centroid; joints that coincide share a label."""
    centre = np.mean(list(pts.values()), axis=0)
    labels: list[tuple[str, np.ndarray]] = []
    for name, xy in pts.items():
        same = next((i for i, (_, q) in enumerate(labels) if np.linalg.norm(q - xy) < 1e-6 * size), None)
        if same is None:
            labels.append((name, xy))
        else:
            labels[same] = (f"{labels[same][0]}={name}", labels[same][1])
    for name, xy in labels:
        d = xy - centre
        d = d / np.linalg.norm(d) if np.linalg.norm(d) > 1e-9 else np.array([1.0, 0.0])
        ax.annotate(
            name,
            xy,
            xytext=tuple(9 * d),
            textcoords="offset points",
            size=7,
            weight="bold",
            color=C["ink"],
            ha="center",
            va="center",
            zorder=8,
        )


def plot_path(ax: Axes, synthesis: Synthesis) -> None:
    """The target path and the path the linkage traces, with cam angles marked every 45 deg."""
    target, traced = synthesis.path_xy, synthesis.traced_xy
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.08)  # room for the angle labels at the path's extremes
    ax.plot(*np.c_[target.T, target[:1].T], color=C["path"], lw=4.0, label="target path")
    ax.plot(*np.c_[traced.T, traced[:1].T], color=C["traced"], lw=1.0, ls="--", label="traced by the linkage")
    for a in range(0, 360, 45):
        ax.plot(*target[a], "o", ms=3, color=C["ink"])
        first = a < 180  # out and back along the same points (a line): first half above, second below
        ax.annotate(
            f"{a}\u00b0",
            target[a],
            xytext=(3, 3) if first else (3, -3),
            textcoords="offset points",
            size=6.5,
            color=C["grey"],
            va="bottom" if first else "top",
        )
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title("path: target and traced (cam angles marked)", fontsize=9)
    ax.legend(loc="best", fontsize=7)


def plot_path_error(ax: Axes, synthesis: Synthesis, limit_mm: float = DEFAULT_MAX_PATH_ERROR_MM) -> None:
    """|traced - target| (mm, log scale) along the target path, with ``check``'s limit (``[limits] max_path_error``,
    mm) marked."""
    target, traced = synthesis.path_xy, synthesis.traced_xy
    seg = np.linalg.norm(np.diff(np.vstack([target, target[:1]]), axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    err = np.linalg.norm(traced - target, axis=1)
    ax.semilogy(arc, np.maximum(err, 1e-16), color=C["traced"], lw=1.0)
    ax.axhline(limit_mm, color=C["limit"], ls="--", lw=0.8)
    ax.text(arc[-1], limit_mm, f"limit {limit_mm:g} mm ", color=C["limit"], size=7, ha="right", va="bottom")
    ax.set_ylim(1e-16, max(1e-1, 10.0 * limit_mm, 3.0 * float(err.max())))  # a miss of millimetres in view
    ax.set_xlim(0.0, arc[-1])
    ax.set_xlabel("distance along the target path (mm)")
    ax.set_ylabel("|traced \u2212 target| (mm)")
    ax.set_title(f"path error (largest {err.max():.2g} mm)", fontsize=9)
