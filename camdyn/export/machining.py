"""Paths for the machines that make a cam plate: a CNC cutter-centre path (ISO G-code) and a cam grinder's table.

Both take the exact contour as curves u in [0, 1] -> (2, m) mm in the cam frame (see :mod:`camdyn.export.profile`)
and never cut into it:

* the cutter path is the contour's offset at the cutter radius plus half the chord tolerance, written as lines
  (or arcs) that deviate from that offset by at most 0.45 of the tolerance, so every point of the path lies
  between the cutter radius and the cutter radius plus the tolerance from the outline: the cam is never cut under
  size. A concave stretch tighter than the cutter is refused (:func:`check_tool_fits`), and the written path is
  measured against the outline before it is written.
* the grinder table gives, per cam angle, the distance from the cam axis to the wheel centre when the wheel,
  on a line through the cam axis, touches the turned cam: the largest distance at which the wheel circle meets
  the outline.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._core.errors import InputError, NumericalError
from .._core.units import MM_PER_INCH
from .profile import resample, resample_u

Curve = Callable[[np.ndarray], np.ndarray]

MIN_MACHINING_TOLERANCE_MM = 1e-3  # a micrometre: below a machine tool's resolution (and the G-code's rounding)
_PATH_SHARE = 0.45  # of the tolerance: the path's own deviation from the offset curve (the rest absorbs rounding)
_DECIMALS = {"mm": 5, "in": 6}  # G-code coordinates: 10 nm, 25 nm
SAFE_Z_MM = 5.0  # rapid height above the part's top (Z0 is the cutting depth; the operator sets the work offset)
DEFAULT_FEED_MM_PER_MIN = 300.0
MAX_ARC_SWEEP_DEG = 180.0  # one G02/G03 turns at most a half circle: a controller's I, J stay well conditioned


def reference_tolerance(tolerance_mm: float) -> float:
    """Chord tolerance (mm) of the dense outline a path is measured against: a hundredth of the user's, at least
    10 nm (finer would need more points than a polyline may have)."""
    return max(tolerance_mm / 100, 1e-5)


def sha256_of(path: str | Path) -> str:
    """The file's SHA-256 (hex): a G-code header names the case it was made from."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def check_tool_fits(
    theta_deg: np.ndarray, rho_contour_mm: np.ndarray, radius_mm: float, tolerance_mm: float, tool: str
) -> None:
    """:class:`InputError` if a concave stretch of the contour is tighter than a tool of ``radius_mm`` standing off
    by half the tolerance: the message names the stretch's angles, its least radius and the largest tool that fits.

    ``rho_contour_mm``: the contour's signed radius of curvature (concave negative) at cam angles ``theta_deg``,
    sampled densely enough to catch its extremes (camdyn's geometry grid plus both sides of every break).
    """
    need = radius_mm + 0.5 * tolerance_mm
    tight = (rho_contour_mm < 0) & (-rho_contour_mm <= need)
    if not tight.any():
        return
    concave = rho_contour_mm < 0
    least = float(np.min(-rho_contour_mm[concave]))
    at = np.sort(np.asarray(theta_deg)[tight] % 360.0)
    fits = max(least - 0.5 * tolerance_mm, 0.0)
    raise InputError(
        f"theta = {at[0]:.1f}..{at[-1]:.1f} deg",
        f"a concave stretch of the contour (least radius {least:.3f} mm) is tighter than the {tool} of radius "
        f"{radius_mm:g} mm: it would cut into the cam; the largest {tool} that fits has radius "
        f"{math.floor(fits * 1000) / 1000:.3f} mm",
    )


def segment_distance(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of points (m, 2) from the closed polyline (k, 2), exact over the chords next to the nearest
    ``_NEAR`` vertices (a KD-tree finds them)."""
    from scipy.spatial import KDTree

    k = len(poly)
    _, near = KDTree(poly).query(pts, k=min(_NEAR, k))
    near = np.asarray(near).reshape(len(pts), -1)  # (m, neighbours)
    best = np.full(len(pts), np.inf)
    for col in near.T:
        for j in (col - 1, col):
            a, b = poly[j % k], poly[(j + 1) % k]
            d = b - a
            w = np.clip(np.sum((pts - a) * d, 1) / np.maximum(np.sum(d * d, 1), 1e-300), 0.0, 1.0)
            best = np.minimum(best, np.hypot(*(pts - a - w[:, None] * d).T))
    return best


_NEAR = 4


@dataclass(frozen=True)
class Move:
    """One cutting move to ``end`` (mm): a line, or an arc about ``centre`` (mm), ``ccw`` its sense."""

    end: np.ndarray
    centre: np.ndarray | None = None
    ccw: bool = False


def _arc_through(p: np.ndarray, m: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, float] | None:
    """Centre and radius of the circle through three points; None when they are (nearly) collinear."""
    ax, ay = m - p
    bx, by = q - p
    det = 2.0 * (ax * by - ay * bx)
    scale = max(ax * ax + ay * ay, bx * bx + by * by)
    if abs(det) < 1e-12 * scale:
        return None
    a2, b2 = ax * ax + ay * ay, bx * bx + by * by
    c = p + np.array([by * a2 - ay * b2, ax * b2 - bx * a2]) / det
    return c, float(np.hypot(*(p - c)))


def _arc_fits(P: np.ndarray, i: int, j: int, tol: float) -> Move | None:
    """The arc (or line) from P[i] to P[j] through P[(i + j) // 2] if every sample between lies within ``tol``
    of it and the samples run along it in one sense (at most :data:`MAX_ARC_SWEEP_DEG`); else None."""
    seg = P[i : j + 1]
    fit = _arc_through(P[i], P[(i + j) // 2], P[j])
    if fit is None or fit[1] > 1e4 * np.ptp(seg, axis=0).max():  # a line
        d = P[j] - P[i]
        L = np.hypot(*d)
        if L == 0:
            return None
        off = np.abs((seg[:, 0] - P[i, 0]) * d[1] - (seg[:, 1] - P[i, 1]) * d[0]) / L
        along = ((seg - P[i]) @ d) / L**2
        if off.max() <= tol and np.all(np.diff(along) > 0):
            return Move(P[j].copy())
        return None
    c, R = fit
    if np.max(np.abs(np.hypot(*(seg - c).T) - R)) > tol:
        return None
    v = seg - c
    turn = np.arctan2(v[:-1, 0] * v[1:, 1] - v[:-1, 1] * v[1:, 0], np.sum(v[:-1] * v[1:], 1))
    if not (np.all(turn > 0) or np.all(turn < 0)) or abs(np.sum(turn)) > math.radians(MAX_ARC_SWEEP_DEG):
        return None
    return Move(P[j].copy(), c, bool(turn[0] > 0))


def fit_arcs(P: np.ndarray, tol: float) -> list[Move]:
    """Arcs and lines through a dense closed sample P (k, 2) from P[0] round to P[0], each within ``tol`` of the
    samples it replaces; greedy, each as long as it fits (doubling, then bisection on its end)."""
    k = len(P)
    Q = np.concatenate([P, P[:1]])
    moves: list[Move] = []
    i = 0
    while i < k:
        lo, hi, best = i + 1, None, Move(Q[i + 1].copy())  # one chord of the dense sample always fits
        step = 2
        while hi is None:
            j = min(i + step, k)
            fit = _arc_fits(Q, i, j, tol)
            if fit is None:
                hi = j
            else:
                lo, best = j, fit
                if j == k:
                    break
                step *= 2
        if hi is not None:
            while hi - lo > 1:
                mid = (lo + hi) // 2
                fit = _arc_fits(Q, i, mid, tol)
                if fit is None:
                    hi = mid
                else:
                    lo, best = mid, fit
        moves.append(best)
        i = lo
    return moves


def _arc_points(start: np.ndarray, move: Move, n: int = 16) -> np.ndarray:
    """Points (n, 2) along a move after its start, its end included."""
    t = np.arange(1, n + 1)[:, None] / n
    if move.centre is None:
        return start + t * (move.end - start)
    a0 = math.atan2(*(start - move.centre)[::-1])
    a1 = math.atan2(*(move.end - move.centre)[::-1])
    sweep = (a1 - a0) % (2 * math.pi) if move.ccw else -((a0 - a1) % (2 * math.pi))
    ang = a0 + t[:, 0] * sweep
    R = float(np.hypot(*(start - move.centre)))
    return move.centre + R * np.column_stack([np.cos(ang), np.sin(ang)])


@dataclass(frozen=True)
class CutterPath:
    """The cutter-centre path (mm, cam frame) and its measured distance from the outline."""

    start: np.ndarray  # (2,)
    moves: tuple[Move, ...]
    min_distance_mm: float
    max_distance_mm: float

    def points(self, per_move: int = 16) -> np.ndarray:
        """The path sampled (n, 2): the start and ``per_move`` points along each move."""
        out, at = [self.start[None]], self.start
        for mv in self.moves:
            out.append(_arc_points(at, mv, per_move))
            at = mv.end
        return np.concatenate(out)


def cutter_path(
    contour: Curve,
    offset: Callable[[float], Curve],
    cutter_radius_mm: float,
    tolerance_mm: float,
    *,
    climb: bool = True,
    arcs: bool = False,
) -> CutterPath:
    """The cutter-centre path round the cam (mm): lines (or arcs) within the tolerance, climb milling (clockwise
    round the cam, a right-hand spindle) or conventional; it starts at its farthest point from the axis.

    ``contour``: the outline u -> (2, m); ``offset(d)``: the curve at distance d outward
    (:meth:`CamGeometry.offset_fn`).
    :class:`NumericalError` if the path, measured against a dense outline, comes nearer than the cutter radius or
    farther than the radius plus the tolerance (a self-intersecting offset the curvature check did not see).
    """
    dev = _PATH_SHARE * tolerance_mm
    centre = offset(cutter_radius_mm + 0.5 * tolerance_mm)
    P = resample(centre, dev / 25 if arcs else dev).T  # (k, 2)
    ccw = np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]) > 0  # the shoelace's sign
    if ccw == climb:  # climb milling runs clockwise round an outside contour
        P = P[::-1]
    P = np.roll(P, -int(np.argmax(np.hypot(*P.T))), axis=0)
    moves = fit_arcs(P, dev) if arcs else [Move(p.copy()) for p in np.concatenate([P[1:], P[:1]])]
    path = CutterPath(P[0].copy(), tuple(moves), math.nan, math.nan)
    ref = reference_tolerance(tolerance_mm)
    outline = resample(contour, ref).T
    d = segment_distance(path.points(), outline)
    lo, hi = float(d.min()), float(d.max())
    slack = ref + 1e-9  # the dense outline's own chords
    if lo < cutter_radius_mm - slack or hi > cutter_radius_mm + tolerance_mm + slack:
        raise NumericalError(
            "cutter path",
            f"the path comes {lo:.4f}..{hi:.4f} mm from the outline, not within {cutter_radius_mm:g}.."
            f"{cutter_radius_mm + tolerance_mm:g} mm: "
            "the cutter would cut into the cam (a narrow neck or groove); use a smaller cutter",
        )
    return CutterPath(path.start, path.moves, lo, hi)


def gcode_text(path: CutterPath, *, header: list[str], feed_mm_per_min: float, units: str = "mm") -> str:
    """ISO G-code (RS-274 / ISO 6983) of the cutter-centre path: G17 G21|G20 G90, the tool-centre path without
    G41/G42, a radial lead-in and lead-out in the air outside the cam, ``header`` as comment lines."""
    scale = 1.0 if units == "mm" else 1.0 / MM_PER_INCH
    nd = _DECIMALS[units]

    def f(v: float) -> str:
        return f"{v * scale:.{nd}f}"

    start = path.start
    r = float(np.hypot(*start))
    lead = start * (1.0 + max(0.5 * r, 5.0) / r)  # outward along the radius: nothing of the cam lies beyond the start
    feed = f"{feed_mm_per_min * scale:.{max(nd - 3, 1)}f}"
    lines = ["%"] + [f"({_comment(h)})" for h in header]
    lines += [
        f"G17 {'G21' if units == 'mm' else 'G20'} G90 G40 G49 G94",
        f"G0 Z{f(SAFE_Z_MM)}",
        f"G0 X{f(lead[0])} Y{f(lead[1])}",
        f"G1 Z{f(0.0)} F{feed}",
        f"G1 X{f(start[0])} Y{f(start[1])}",
    ]
    at = start
    for mv in path.moves:
        if mv.centre is None:
            lines.append(f"G1 X{f(mv.end[0])} Y{f(mv.end[1])}")
        else:
            ij = mv.centre - at
            lines.append(f"{'G3' if mv.ccw else 'G2'} X{f(mv.end[0])} Y{f(mv.end[1])} I{f(ij[0])} J{f(ij[1])}")
        at = mv.end
    lines += [f"G1 X{f(lead[0])} Y{f(lead[1])}", f"G0 Z{f(SAFE_Z_MM)}", "M30", "%"]
    return "\n".join(lines) + "\n"


def _comment(text: str) -> str:
    """A G-code comment's text: no parentheses (they would end it), plain ASCII."""
    return text.replace("(", "[").replace(")", "]").encode("ascii", "replace").decode()


def grinder_table(
    contour: Curve, theta_deg: np.ndarray, wheel_radius_mm: float, sigma: float, tolerance_mm: float
) -> np.ndarray:
    """Distance (mm) from the cam axis to the wheel centre at each cam angle (deg), the wheel on the fixed +y axis
    (the follower's side), the cam turned by theta in its sense ``sigma`` (+1 ccw, -1 cw).

    In the cam frame the wheel's line has direction e = R(-sigma theta) (0, 1); the centre sits at the largest d
    for which the wheel circle about d e meets the outline: d = max over contour points p with |p . e_perp| <=
    Rw of p . e + sqrt(Rw^2 - (p . e_perp)^2). Found on a polyline within tolerance / 100 of the outline and
    refined on the exact contour about each maximum.
    """
    th = np.deg2rad(np.asarray(theta_deg, dtype=float))
    e = np.stack([np.sin(sigma * th), np.cos(sigma * th)], axis=1)  # R(-sigma theta) (0, 1)
    ep = np.stack([e[:, 1], -e[:, 0]], axis=1)
    u, pts = resample_u(contour, reference_tolerance(tolerance_mm))
    pts = pts.T  # (k, 2)

    def reach(
        P: np.ndarray, rows: np.ndarray
    ) -> np.ndarray:  # P (..., 2) against rows of e: the wheel centre distance that touches each point
        a = np.einsum("r...i,ri->r...", P, e[rows])
        b = np.einsum("r...i,ri->r...", P, ep[rows])
        return np.where(np.abs(b) <= wheel_radius_mm, a + np.sqrt(np.maximum(wheel_radius_mm**2 - b * b, 0.0)), -np.inf)

    best_u = np.empty(len(th))
    for rows in np.array_split(np.arange(len(th)), max(1, len(th) * len(pts) // 4_000_000)):
        r = reach(np.broadcast_to(pts, (len(rows),) + pts.shape), rows)
        best_u[rows] = u[np.argmax(r, axis=1)]
    du = float(np.diff(np.concatenate([u, [u[0] + 1.0]])).max())
    local = best_u[:, None] + du * np.linspace(-1.0, 1.0, 41)[None]
    for _ in range(3):  # zoom in on the exact contour: each pass shrinks the bracket twentyfold
        P = contour(local.ravel()).T.reshape(local.shape + (2,))
        r = reach(P, np.arange(len(th)))
        k = np.argmax(r, axis=1)
        best_u = local[np.arange(len(th)), k]
        du /= 20.0
        local = best_u[:, None] + du * np.linspace(-1.0, 1.0, 41)[None]
    d = reach(contour(best_u).T[:, None], np.arange(len(th)))[:, 0]
    if not np.all(np.isfinite(d)):
        raise NumericalError("grinder table", "the wheel's line misses the cam at some angle")
    return d
