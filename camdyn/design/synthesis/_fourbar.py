"""The CCM paper's comparison: the best plain four-bar whose coupler curve follows the path, and how far it misses.

A four-bar is x = (ax, ay, dx, dy, crank, coupler, rocker, px, py, mode): the ground pivots A and D, the crank
A-B, the coupler B-C carrying the tracing point (px along B->C, py across it), the rocker D-C and the assembly
mode sign(mode); lengths mm.
"""

from __future__ import annotations

import numpy as np

from ..._core.units import DEFAULT_MIN_TRANSMISSION_ANGLE_DEG, TWO_PI
from ._ccm import FIT_MARGIN_DEG


def fourbar_curve(x: np.ndarray, n: int = 360) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coupler curves of four-bars x = (ax, ay, dx, dy, crank, coupler, rocker, px, py, mode), (10,) or (10, S).

    Crank A-B, coupler B-C (coupler point B + px along BC + py across), rocker D-C, assembly mode sign(mode).
    Returns the curves (n, 2) or (S, n, 2), how far the loop misses closing (mm) and the least transmission
    angle at C (deg, folded into [0, 90]), each () or (S,).
    """
    x = np.asarray(x, dtype=float)
    single = x.ndim == 1
    ax, ay, dx, dy, r2, r3, r4, px, py, mode = (v[:, None] for v in x.reshape(10, -1))
    th = np.linspace(0.0, TWO_PI, n, endpoint=False)[None]
    bx, by = ax + r2 * np.cos(th), ay + r2 * np.sin(th)
    vx, vy = dx - bx, dy - by
    dist2 = vx * vx + vy * vy
    dist = np.sqrt(dist2)
    miss = np.clip(np.maximum(dist - (r3 + r4), np.abs(r3 - r4) - dist), 0.0, None).max(1)
    f = (r3 * r3 - r4 * r4 + dist2) / (2.0 * dist2)
    h = np.where(mode >= 0.0, 1.0, -1.0) * np.sqrt(np.clip(r3 * r3 / dist2 - f * f, 0.0, None))
    cx, cy = bx + f * vx + h * vy, by + f * vy - h * vx
    ux, uy = (cx - bx) / r3, (cy - by) / r3
    curve = np.stack([bx + px * ux - py * uy, by + px * uy + py * ux], axis=-1)
    cos_mu = ((bx - cx) * (dx - cx) + (by - cy) * (dy - cy)) / (r3 * r4)
    mu = np.degrees(np.arccos(np.clip(cos_mu, -1.0, 1.0)))
    tmin = np.minimum(mu, 180.0 - mu).min(1)
    return (curve[0], miss[0], tmin[0]) if single else (curve, miss, tmin)


def _polyline_distance(pts, poly):
    """Distance (mm) from each point (..., a, 2) to the closed polyline (..., b, 2): (..., a)."""
    ab = np.roll(poly, -1, axis=-2) - poly
    ap = pts[..., :, None, :] - poly[..., None, :, :]
    tt = np.clip(np.sum(ap * ab[..., None, :, :], -1) / np.maximum(np.sum(ab * ab, -1), 1e-300)[..., None, :], 0.0, 1.0)
    return np.sqrt(np.min(np.sum((ap - tt[..., None] * ab[..., None, :, :]) ** 2, -1), axis=-1))


def curve_error(curve: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Largest distance (mm) between the target samples t (n, 2) and a closed curve (m, 2) or curves (S, m, 2),
    either way (the Hausdorff distance of the two closed polylines)."""
    tt = np.broadcast_to(t, curve.shape[:-2] + t.shape)
    return np.maximum(_polyline_distance(tt, curve).max(-1), _polyline_distance(curve, tt).max(-1))


def _near_distance(pts, poly):
    """Distance (mm) from points (S, a, 2) to closed polylines (S, b, 2) through the two segments at the nearest
    vertex: exact unless a farther segment comes nearer (a proxy for the optimizer; :func:`curve_error` is exact)."""
    b = poly.shape[-2]
    d2 = np.sum(poly * poly, -1)[..., None, :] - 2.0 * (pts @ np.swapaxes(poly, -1, -2))  # + |pts|^2: same argmin
    j = np.argmin(d2, axis=-1)[..., None]
    best = None
    for k0 in ((j - 1) % b, j):
        p0 = np.take_along_axis(poly, k0, axis=-2)
        ab = np.take_along_axis(poly, (k0 + 1) % b, axis=-2) - p0
        ap = pts - p0
        tt = np.clip(np.sum(ap * ab, -1) / np.maximum(np.sum(ab * ab, -1), 1e-300), 0.0, 1.0)
        dd = np.sum((ap - tt[..., None] * ab) ** 2, -1)
        best = dd if best is None else np.minimum(best, dd)
    return np.sqrt(best)


def grashof_excess(x: np.ndarray) -> np.ndarray:
    """How far (mm) four-bars (10, S) are from a Grashof crank-rocker: s + l - p - q where positive (not
    Grashof) plus how much the crank exceeds the shortest link. 0: Grashof with the crank (next to the ground)
    the shortest link, so the crank turns fully."""
    x = np.asarray(x, dtype=float).reshape(10, -1)
    r2 = x[4]
    links = np.sort(np.stack([r2, x[5], x[6], np.hypot(x[2] - x[0], x[3] - x[1])]), axis=0)
    return np.clip(links[0] + links[3] - links[1] - links[2], 0.0, None) + np.clip(r2 - links[0], 0.0, None)


def fourbar_objective(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Path error of four-bar candidates (10, S) on every 4th path sample plus penalties: the loop must close,
    be a Grashof crank-rocker (the crank the shortest link, s + l <= p + q) and keep its transmission angle at
    or above 30 deg."""
    x = np.asarray(x, dtype=float).reshape(10, -1)
    curve, miss, tmin = fourbar_curve(x, 180)
    need = DEFAULT_MIN_TRANSMISSION_ANGLE_DEG + FIT_MARGIN_DEG
    pen = 1e3 * miss + 1e2 * grashof_excess(x) + np.clip(need - tmin, 0.0, None)
    tt = np.broadcast_to(t[::4], curve.shape[:-2] + t[::4].shape)
    return np.maximum(_near_distance(tt, curve).max(-1), _near_distance(curve, tt).max(-1)) + pen


FOURBAR_NAMES = ("ax", "ay", "dx", "dy", "crank", "coupler", "rocker", "point_along", "point_across")


def fourbar_bounds(mid: np.ndarray, size: float) -> list[tuple[float, float]]:
    """The optimizer's box for a path of extent ``size`` (mm) about ``mid``: pivots within 3 sizes, links
    from a tenth of a size (the crank from a twentieth) to a few sizes, and the assembly mode."""
    return [
        (mid[0] - 3 * size, mid[0] + 3 * size),
        (mid[1] - 3 * size, mid[1] + 3 * size),
        (mid[0] - 3 * size, mid[0] + 3 * size),
        (mid[1] - 3 * size, mid[1] + 3 * size),
        (0.05 * size, 2 * size),
        (0.1 * size, 5 * size),
        (0.1 * size, 5 * size),
        (-3 * size, 3 * size),
        (-3 * size, 3 * size),
        (-1.0, 1.0),
    ]


def fourbar_summary(x: np.ndarray, t: np.ndarray) -> tuple[float, dict]:
    """The path error (mm, the Hausdorff distance of coupler curve and path samples t) of the four-bar x and its
    dimensions and checks."""
    curve, miss, tmin = fourbar_curve(x)
    info = dict(zip(FOURBAR_NAMES, map(float, x[:9]), strict=True)) | {
        "mode": 1 if x[9] >= 0 else -1,
        "min_transmission_angle_deg": float(tmin),
        "closes": bool(miss == 0.0),
        "grashof_crank_rocker": bool(grashof_excess(x[:, None])[0] <= 1e-9),
    }
    return float(curve_error(curve, t)), info
