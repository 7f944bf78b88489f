"""The CCM's objective for the optimizer: whole populations of designs scored at once with vectorized numpy on a
few hundred path samples, and the ``[mechanism]`` table of a design.

A design is x = (ax, ay, slider_angle_deg, slider_offset, link): the cam centre A, the slider line (its
direction, and its offset from A along the direction's clockwise normal) and the link C-E (mm). The tracing
point is the coupler joint (C = T); crank and coupler follow from Ye & Smith eq. 5.

The cam of each design is sized from its sampled motion with closed forms: the translating roller at (e, d0 + s)
in the slider's frame (x across the slider line, y along it) on a cam turning with ``sense`` (+1 anticlockwise),
d0 = sqrt(rp^2 - e^2) for the prime radius rp, and s, s', s'' per radian of cam angle from differences. This is
the population-wide stand-in for :func:`camdyn.model.geometry.min_base_radius`, which sizes the chosen design
exactly (0.3 s a design against a generation of thousands here); the tests check the two against each other.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ..._core.units import (
    DEFAULT_MAX_PATH_ERROR_MM,
    DEFAULT_MIN_CURVATURE_RATIO,
    DEFAULT_MIN_TRANSMISSION_ANGLE_DEG,
    TWO_PI,
)

FIT_MARGIN_DEG = 1.0  # the optimizer asks for 31 deg: the exact synthesis samples finer and rounds the table
DIMENSION_OBJECTIVE = (
    "stroke + 0.5 x the cam's prime radius (the least that meets the pressure-angle and curvature limits)"
)
_BISECTIONS = 16  # halvings of log rp over [rp0, 1.05^100 rp0] in the curvature search (7e-5 relative)


def pitch_convexity(
    rp: npt.ArrayLike, s: np.ndarray, s1: np.ndarray, s2: np.ndarray, e: npt.ArrayLike, sense: npt.ArrayLike
) -> np.ndarray:
    """Largest convex curvature (1/mm) of the pitch curve over the samples (last axis of s, s1, s2), for prime
    radii ``rp``, offsets ``e`` (mm) and senses that are scalars or arrays of the designs' shape (...); <= 0
    where the pitch curve is nowhere convex."""
    rp, e, sense = (np.asarray(v)[..., None] for v in (rp, e, sense))
    y = np.sqrt(np.maximum(rp * rp - e * e, 1e-12)) + s
    v1x, v1y = sense * y, s1 - sense * e  # P' - sense J P, P = (e, y)
    v2x, v2y = 2.0 * sense * s1 - e, s2 - y  # P'' - 2 sense J P' - P
    kappa = (v1x * v2y - v1y * v2x) / (np.hypot(v1x, v1y) ** 3 + 1e-300)
    return (-sense * kappa).max(-1)  # traversal opposite to the cam's turn: convex where this is > 0


def prime_radius_for_pressure_angle(
    s: np.ndarray, s1: np.ndarray, e: npt.ArrayLike, sense: npt.ArrayLike, rr: float, max_pa_deg: float
) -> np.ndarray:
    """Least prime radius (mm) keeping the pressure angle tan phi = (s' - sense e) / (d0 + s) within
    ``max_pa_deg`` at every sample (last axis of s, s1), and at least |e| + rr and 1.5 rr (the roller clears the
    cam centre); e, sense scalars or of the designs' shape (...)."""
    e, sense = np.asarray(e), np.asarray(sense)
    tan_max = math.tan(math.radians(max_pa_deg))
    d0 = np.maximum(np.max(np.abs(s1 - sense[..., None] * e[..., None]) / tan_max - s, axis=-1), 1e-3)
    return np.maximum(np.hypot(d0, e), np.maximum(np.abs(e) + rr, 1.5 * rr))


def prime_radius_for_curvature(
    s: np.ndarray,
    s1: np.ndarray,
    s2: np.ndarray,
    e: npt.ArrayLike,
    sense: npt.ArrayLike,
    rp0: npt.ArrayLike,
    rho_min: float,
) -> np.ndarray:
    """Least prime radius >= ``rp0`` (S,) whose pitch curve keeps a convex radius of curvature >= ``rho_min``
    (mm), by bisection in log rp up to 1.05^100 rp0 (a continuous function of the design, as an optimizer
    wants; at most 16 halvings); s, s1, s2 (S, n), e, sense (S,)."""

    def ok(rp: npt.ArrayLike) -> np.ndarray:
        return pitch_convexity(rp, s, s1, s2, e, sense) <= 1.0 / rho_min

    lo, hi = np.log(rp0), np.log(rp0) + 100 * math.log(1.05)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        good = ok(np.exp(mid))
        lo, hi = np.where(good, lo, mid), np.where(good, mid, hi)
    return np.where(ok(rp0), rp0, np.exp(hi))


def _unwrap_turn(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unwrapped closed sequences of angles (along the last axis) and their net turns (rad)."""
    un = np.unwrap(np.concatenate([theta, theta[..., :1]], axis=-1), axis=-1)
    return un, un[..., -1] - un[..., 0]


def _crank(px: np.ndarray, py: np.ndarray) -> dict[str, np.ndarray]:
    """Crank and coupler from eq. 5 for tracing points (px, py) relative to A (S, n), and the crank angles with
    the modes switched at the extremes of |AT|: both start modes are tried, and the one whose crank turns
    monotonically once is kept (``rev`` measures how far it is from that)."""
    d = np.hypot(px, py)
    n = d.shape[1]
    dmax, dmin = d.max(1), d.min(1)
    r, coupler = (dmax - dmin) / 2.0, (dmax + dmin) / 2.0
    degenerate = r <= 1e-9 * np.maximum(coupler, 1.0)
    rs, ls = np.where(degenerate, 1.0, r)[:, None], coupler[:, None]
    gam = np.arccos(np.clip((rs * rs + d * d - ls * ls) / (2.0 * rs * d), -1.0, 1.0))
    imax, imin = d.argmax(1)[:, None], d.argmin(1)[:, None]
    idx = np.arange(n)[None]
    m = np.where((idx > np.minimum(imin, imax)) & (idx <= np.maximum(imin, imax)), -1.0, 1.0)
    alpha = np.arctan2(py, px)
    runs = []
    for start in (1.0, -1.0):
        th = alpha + start * m * gam
        un, turn = _unwrap_turn(th)
        step = np.diff(un, axis=-1) * np.sign(turn)[:, None]
        rev = np.clip(-step, 0.0, None).sum(1) + np.abs(np.abs(turn) - TWO_PI)
        runs.append((rev, th, un, np.sign(turn)))
    use = runs[0][0] <= runs[1][0]
    pick = lambda a, b: np.where(use.reshape(-1, *([1] * (a.ndim - 1))), a, b)  # noqa: E731
    rev, th, un, sense = (pick(a, b) for a, b in zip(runs[0], runs[1], strict=True))
    return dict(
        r=r, l=coupler, rs=rs, degenerate=degenerate, rev=rev, th=th, un=un, sense=sense, start=np.where(use, 1.0, -1.0)
    )


def _prime_radius(s, un, e, sense, rr: float, max_pa: float, sharp: bool, min_ratio: float) -> np.ndarray:
    """Least prime radius (S,) for the pressure-angle limit (slopes per radian of cam angle, at the sample
    midpoints) and, unless ``sharp``, the curvature limit (differences in the cam angle, which is not uniform)."""
    s_next = np.roll(s, -1, axis=1)
    h = np.abs(np.diff(un, axis=-1)) + 1e-12  # cam angle from sample i to i + 1
    s1m = (s_next - s) / h
    rp = prime_radius_for_pressure_angle(0.5 * (s + s_next), s1m, e, sense, rr, max_pa)
    if sharp:
        return rp
    h_prev = np.roll(h, 1, axis=1)
    s1 = (s1m * h_prev + np.roll(s1m, 1, axis=1) * h) / (h + h_prev)
    s2 = 2.0 * (s1m - np.roll(s1m, 1, axis=1)) / (h + h_prev)
    return prime_radius_for_curvature(s, s1, s2, e, sense, rp, (1.0 + min_ratio) * rr)


def ccm_objective(
    x: np.ndarray,
    t: np.ndarray,
    max_pa: float,
    rr: float,
    sharp: bool = False,
    min_ratio: float = DEFAULT_MIN_CURVATURE_RATIO,
) -> dict[str, np.ndarray]:
    """Objective terms of CCM designs x (5, S) on path samples t (n, 2), every array (S,).

    ``cost``: the stroke plus half the prime radius (:data:`DIMENSION_OBJECTIVE`), plus penalties for a dyad
    that cannot close (``miss``, mm), a crank that reverses or does not turn exactly once (``reversal``, rad)
    and transmission angles under 31 deg (``min_transmission`` at C, ``min_slider`` between the link and the
    slider's normal, deg). The prime radius is the least that keeps the translating-roller pressure angle
    tan phi = (s' - sense e) / (d0 + s) within ``max_pa`` (deg) and, unless the path has ``sharp`` corners, the
    contour's convex radius of curvature at least ``min_ratio`` roller radii ``rr`` (mm), from differences of
    the samples (:func:`prime_radius_for_pressure_angle`, :func:`prime_radius_for_curvature`). Also ``crank``,
    ``coupler`` (eq. 5), ``start`` (the crank mode at the start), ``stroke``, ``prime_radius``, ``sense``.
    """
    x = np.asarray(x, dtype=float).reshape(5, -1)
    ax, ay, ang, off, link = (v[:, None] for v in x)
    px, py = t[None, :, 0] - ax, t[None, :, 1] - ay  # (S, n): tracing point relative to A
    k = _crank(px, py)
    # slider E on the line through off * normal along e_dir, ahead of the foot of C (slider_mode +1)
    a = np.radians(ang)
    ex, ey = np.cos(a), np.sin(a)
    nx, ny = ey, -ex
    wx, wy = px - off * nx, py - off * ny
    along, across = wx * ex + wy * ey, wx * nx + wy * ny
    miss = np.clip(np.abs(across) - link, 0.0, None).max(1)
    pe = along + np.sqrt(np.clip(link * link - across * across, 0.0, None))
    s = pe - pe.min(1, keepdims=True)
    # transmission angles: at C between C->B and C->E; link to the slider line (90 deg: along the line)
    cbx, cby = k["rs"] * np.cos(k["th"]) - px, k["rs"] * np.sin(k["th"]) - py
    cex, cey = off * nx + pe * ex - px, off * ny + pe * ey - py
    ce = np.hypot(cex, cey) + 1e-300
    tr = np.degrees(np.arccos(np.clip((cbx * cex + cby * cey) / (np.hypot(cbx, cby) * ce + 1e-300), -1.0, 1.0)))
    tr = np.minimum(tr, 180.0 - tr).min(1)
    sl = (90.0 - np.degrees(np.arccos(np.clip(np.abs(cex * ex + cey * ey) / ce, 0.0, 1.0)))).min(1)
    rp = _prime_radius(s, k["un"], off[:, 0], k["sense"], rr, max_pa, sharp, min_ratio)
    stroke = s.max(1)
    need = DEFAULT_MIN_TRANSMISSION_ANGLE_DEG + FIT_MARGIN_DEG
    penalty = 1e3 * miss + 1e3 * k["rev"] + 10.0 * (np.clip(need - tr, 0.0, None) + np.clip(need - sl, 0.0, None))
    cost = np.where(k["degenerate"], 1e6, stroke + 0.5 * rp + penalty)
    return dict(
        cost=cost,
        crank=k["r"],
        coupler=k["l"],
        start=k["start"],
        stroke=stroke,
        prime_radius=rp,
        min_transmission=tr,
        min_slider=sl,
        sense=k["sense"],
        reversal=k["rev"],
        miss=miss,
    )


def ccm_score(
    x: np.ndarray,
    t: np.ndarray,
    max_pa: float,
    rr: float = 10.0,
    sharp: bool = False,
    min_ratio: float = DEFAULT_MIN_CURVATURE_RATIO,
) -> tuple[float, dict]:
    """:func:`ccm_objective` of one design x (5,): its cost and its other terms as floats."""
    out = ccm_objective(np.asarray(x, dtype=float)[:, None], t, max_pa, rr, sharp, min_ratio)
    return float(out["cost"][0]), {k: float(v[0]) for k, v in out.items() if k != "cost"}


def ccm_table(x: np.ndarray, start: float, rr: float, max_pa: float) -> dict:
    """The ``[mechanism]`` table of design x (rounded to 0.001 mm / deg) with crank mode ``start``."""
    ang = float(x[2])
    normal = np.array([math.sin(math.radians(ang)), -math.cos(math.radians(ang))])
    table = {
        "type": "ccm",
        "cam_center": [round(float(x[0]), 3), round(float(x[1]), 3)],
        "crank_mode": 1 if start >= 0 else -1,
        "link": round(float(x[4]), 3),
        "slider_point": [round(float(x[0] + x[3] * normal[0]), 3), round(float(x[1] + x[3] * normal[1]), 3)],
        "slider_angle": round(ang, 3),
        "roller_radius": float(rr),
    }
    if max_pa != 30.0:
        table["max_pressure_angle"] = float(max_pa)
    return table


def meets_constraints(summary: dict) -> list[str]:
    """What an exactly synthesized CCM misses of the synthesis constraints (empty: it meets them all)."""
    out = []
    if not summary["max_path_error_mm"] < DEFAULT_MAX_PATH_ERROR_MM:
        out.append(f"forward check misses the path by {summary['max_path_error_mm']:.3g} mm")
    for key, name in (("min_transmission_angle_deg", "coupler-link"), ("min_slider_angle_deg", "link-slider")):
        if summary[key] < DEFAULT_MIN_TRANSMISSION_ANGLE_DEG:
            out.append(f"{name} transmission angle {summary[key]:.1f} deg < {DEFAULT_MIN_TRANSMISSION_ANGLE_DEG:g} deg")
    return out
