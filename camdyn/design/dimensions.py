"""Dimensional synthesis of a CCM for a path (differential evolution), beside the best plain four-bar.

The free values are the cam centre A, the slider line (direction and offset from A) and the link C-E; the
tracing point is the coupler joint (C = T), crank and coupler follow from Ye & Smith eq. 5. The optimizer scores
whole populations with vectorized numpy on a few hundred path samples; the best designs are then synthesized
exactly (:func:`camdyn.model.linkage.synthesize_motion`).
"""

from __future__ import annotations

import math
import time
from typing import Callable

import numpy as np

from .._core.errors import InputError, NumericalError
from .._core.units import TWO_PI
from ..model.linkage import pitch_convexity, synthesize_motion, vmap_scalar
from ..model.paths import build_path, parse_path
from .geometry import min_base_radius

_N_FIT = 256  # path samples used by the optimizer (the chosen design is then synthesized exactly)
_MIN_TRANSMISSION_DEG = 30.0  # every transmission angle must stay at or above this
_FIT_MARGIN_DEG = 1.0  # the optimizer asks for 31 deg: the exact synthesis samples finer and rounds the table
_N_CANDIDATES = 12  # designs of the final population tried in order when the best one fails the exact synthesis
DIMENSION_OBJECTIVE = "stroke + 0.5 x the cam's prime radius (the least that meets the pressure-angle and curvature limits)"


def _unwrap_turn(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unwrapped closed sequences of angles (along the last axis) and their net turns (rad)."""
    un = np.unwrap(np.concatenate([theta, theta[..., :1]], axis=-1), axis=-1)
    return un, un[..., -1] - un[..., 0]


def _de_seed(seed: int) -> dict:
    """``rng=`` where scipy has it (>= 1.15; ``seed=`` is deprecated there), ``seed=`` before."""
    import inspect

    from scipy.optimize import differential_evolution

    return {"rng": seed} if "rng" in inspect.signature(differential_evolution).parameters else {"seed": seed}


def _prime_radius_for_curvature(s, s1, s2, e, sense, rp0, rho_min):
    """Least prime radius >= rp0 (S,) whose pitch curve keeps a convex radius of curvature >= ``rho_min`` (mm),
    with the pitch curve of :func:`_choose_base_radius` (bisection in log rp, up to 1.05^100 rp0); s, s1, s2
    (S, n), e, sense (S,)."""
    e, sense = e[:, None], sense[:, None]

    def ok(rp):
        return pitch_convexity(rp[:, None], s, s1, s2, e, sense) <= 1.0 / rho_min

    lo, hi = np.log(rp0), np.log(rp0) + 100 * math.log(1.05)
    for _ in range(16):
        mid = 0.5 * (lo + hi)
        good = ok(np.exp(mid))
        lo, hi = np.where(good, lo, mid), np.where(good, mid, hi)
    return np.where(ok(rp0), rp0, np.exp(hi))


def _ccm_eval(x: np.ndarray, t: np.ndarray, max_pa: float, rr: float, sharp: bool = False, min_ratio: float = 1.5) -> dict[str, np.ndarray]:
    """Objective terms of CCM candidates x = (ax, ay, slider_angle_deg, slider_offset, link), shape (5, S).

    The tracing point is the coupler joint (C = T). Crank and coupler from eq. 5, modes switched at the
    extremes of |AT| (both start modes tried; the one whose crank turns monotonically once is kept). The prime
    radius is the least that keeps the translating-roller pressure angle tan phi = (s' - sense e) / (d0 + s)
    within ``max_pa`` and, unless the path has ``sharp`` corners, the contour's convex radius of curvature at
    least ``min_ratio`` roller radii (the pitch curve's at least 1 + min_ratio, from differences of the samples;
    ``camdyn check``'s curvature limit). Every array (S,).
    """
    x = np.asarray(x, dtype=float).reshape(5, -1)
    ax, ay, ang, off, link = (v[:, None] for v in x)
    px, py = t[None, :, 0] - ax, t[None, :, 1] - ay  # (S, n): tracing point relative to A
    d = np.hypot(px, py)
    n = d.shape[1]
    dmax, dmin = d.max(1), d.min(1)
    r, l = (dmax - dmin) / 2.0, (dmax + dmin) / 2.0
    degenerate = r <= 1e-9 * np.maximum(l, 1.0)
    rs, ls = np.where(degenerate, 1.0, r)[:, None], l[:, None]
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
    start = np.where(use, 1.0, -1.0)
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
    cbx, cby = rs * np.cos(th) - px, rs * np.sin(th) - py
    cex, cey = off * nx + pe * ex - px, off * ny + pe * ey - py
    ce = np.hypot(cex, cey) + 1e-300
    tr = np.degrees(np.arccos(np.clip((cbx * cex + cby * cey) / (np.hypot(cbx, cby) * ce + 1e-300), -1.0, 1.0)))
    tr = np.minimum(tr, 180.0 - tr).min(1)
    sl = (90.0 - np.degrees(np.arccos(np.clip(np.abs(cex * ex + cey * ey) / ce, 0.0, 1.0)))).min(1)
    # pressure angle -> least prime radius (slopes per radian of cam angle, at the sample midpoints), then the
    # pitch-curve curvature as _choose_base_radius has it (differences in the cam angle, which is not uniform)
    s_next = np.roll(s, -1, axis=1)
    h = np.abs(np.diff(un, axis=-1)) + 1e-12  # cam angle from sample i to i + 1
    s1m = (s_next - s) / h
    e = off[:, 0]
    tan_max = math.tan(math.radians(max_pa))
    d0 = np.maximum(np.max(np.abs(s1m - sense[:, None] * e[:, None]) / tan_max - 0.5 * (s + s_next), axis=1), 1e-3)
    rp = np.maximum(np.hypot(d0, e), np.maximum(np.abs(e) + rr, 1.5 * rr))
    if not sharp:
        h_prev = np.roll(h, 1, axis=1)
        s1 = (s1m * h_prev + np.roll(s1m, 1, axis=1) * h) / (h + h_prev)
        s2 = 2.0 * (s1m - np.roll(s1m, 1, axis=1)) / (h + h_prev)
        rp = _prime_radius_for_curvature(s, s1, s2, e, sense, rp, (1.0 + min_ratio) * rr)
    stroke = s.max(1)
    need = _MIN_TRANSMISSION_DEG + _FIT_MARGIN_DEG
    penalty = 1e3 * miss + 1e3 * rev + 10.0 * (np.clip(need - tr, 0.0, None) + np.clip(need - sl, 0.0, None))
    cost = np.where(degenerate, 1e6, stroke + 0.5 * rp + penalty)
    return dict(cost=cost, crank=r, coupler=l, start=start, stroke=stroke, prime_radius=rp, min_transmission=tr, min_slider=sl, sense=sense, reversal=rev, miss=miss)


def _ccm_score(x: np.ndarray, t: np.ndarray, max_pa: float, rr: float = 10.0, sharp: bool = False, min_ratio: float = 1.5) -> tuple[float, dict]:
    """Objective of one CCM candidate x = (ax, ay, slider_angle_deg, slider_offset, link) on path samples t:
    stroke + half the prime radius that the pressure-angle limit needs (a small cam), plus penalties for a dyad
    that cannot close, a crank that reverses or does not turn exactly once, and transmission angles under
    30 deg (see :func:`_ccm_eval`, which scores a whole population at once)."""
    out = _ccm_eval(np.asarray(x, dtype=float)[:, None], t, max_pa, rr, sharp, min_ratio)
    return float(out["cost"][0]), {k: float(v[0]) for k, v in out.items() if k != "cost"}


def _fourbar_curve(x, n: int = 360):
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


def _curve_error(curve, t):
    """Largest distance (mm) between the target samples t (n, 2) and a closed curve (m, 2) or curves (S, m, 2),
    either way (the Hausdorff distance of the two closed polylines)."""
    tt = np.broadcast_to(t, curve.shape[:-2] + t.shape)
    return np.maximum(_polyline_distance(tt, curve).max(-1), _polyline_distance(curve, tt).max(-1))


def _near_distance(pts, poly):
    """Distance (mm) from points (S, a, 2) to closed polylines (S, b, 2) through the two segments at the nearest
    vertex: exact unless a farther segment comes nearer (a proxy for the optimizer; :func:`_curve_error` is exact)."""
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


def _fourbar_grashof(x: np.ndarray) -> np.ndarray:
    """How far (mm) four-bars (10, S) are from a Grashof crank-rocker: s + l - p - q where positive (not
    Grashof) plus how much the crank exceeds the shortest link. 0: Grashof with the crank (next to the ground)
    the shortest link, so the crank turns fully."""
    x = np.asarray(x, dtype=float).reshape(10, -1)
    r2 = x[4]
    links = np.sort(np.stack([r2, x[5], x[6], np.hypot(x[2] - x[0], x[3] - x[1])]), axis=0)
    return np.clip(links[0] + links[3] - links[1] - links[2], 0.0, None) + np.clip(r2 - links[0], 0.0, None)


def _fourbar_score(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Path error of four-bar candidates (10, S) on every 4th path sample plus penalties: the loop must close,
    be a Grashof crank-rocker (the crank the shortest link, s + l <= p + q) and keep its transmission angle at
    or above 30 deg."""
    x = np.asarray(x, dtype=float).reshape(10, -1)
    curve, miss, tmin = _fourbar_curve(x, 180)
    need = _MIN_TRANSMISSION_DEG + _FIT_MARGIN_DEG
    pen = 1e3 * miss + 1e2 * _fourbar_grashof(x) + np.clip(need - tmin, 0.0, None)
    tt = np.broadcast_to(t[::4], curve.shape[:-2] + t[::4].shape)
    return np.maximum(_near_distance(tt, curve).max(-1), _near_distance(curve, tt).max(-1)) + pen


def _ccm_table(x: np.ndarray, start: float, rr: float, max_pa: float) -> dict:
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


def _meets_constraints(summary: dict) -> list[str]:
    """What an exactly synthesized CCM misses of the synthesis constraints (empty: it meets them all)."""
    out = []
    if not summary["max_path_error_mm"] < 1e-3:
        out.append(f"forward check misses the path by {summary['max_path_error_mm']:.3g} mm")
    for key, name in (("min_transmission_angle_deg", "coupler-link"), ("min_slider_angle_deg", "link-slider")):
        if summary[key] < _MIN_TRANSMISSION_DEG:
            out.append(f"{name} transmission angle {summary[key]:.1f} deg < {_MIN_TRANSMISSION_DEG:g} deg")
    return out


def synthesize_dimensions(
    path: dict,
    *,
    seed: int = 0,
    maxiter: int = 200,
    max_pressure_angle: float = 30.0,
    min_curvature_ratio: float = 1.5,
    roller_radius: float = 10.0,
    popsize: int = 15,
    fourbar: bool = True,
    progress: Callable[[str, int, int], None] | None = None,
) -> dict:
    """Choose CCM dimensions for ``path`` with ``differential_evolution`` (the CCM paper's GA family).

    Free: cam centre A, slider line (angle and offset from A), link C-E; the tracing point is the coupler
    joint (C = T); crank and coupler from Ye & Smith eq. 5. Minimizes the stroke plus half the prime radius
    that keeps the pressure angle within ``max_pressure_angle`` and the contour's radius of curvature at least
    ``min_curvature_ratio`` roller radii (:data:`DIMENSION_OBJECTIVE`: a short stroke on a small cam), subject
    to: every dyad closes, the crank turns monotonically exactly once per loop, transmission angles
    (coupler-link and link-slider) >= 30 deg. (Grashof's condition does not apply to the CCM: with the slider
    driven by the cam its linkage is not a four-bar loop.) Constraints enter as penalties; the optimizer
    scores 256 path samples of each of ``popsize`` x 5 designs per generation (vectorized) and stops after
    ``maxiter`` generations or when the population's scores agree to 0.1 %. The best designs of its final
    population are then synthesized exactly (:func:`synthesize_motion`, rounded to 0.001 mm / deg) in order
    until one meets every constraint there, and its base radius is the least that passes ``camdyn check``'s
    pressure-angle and curvature limits (:func:`camdyn.geometry.min_base_radius`, rounded up to 0.5 mm).
    Also fits the best plain four-bar to the path: a Grashof crank-rocker (the crank the shortest link) with
    transmission angle >= 30 deg, 10 free values including the assembly mode; its path error is the
    Hausdorff distance between its coupler curve and the path (the CCM paper's comparison; ``fourbar=False``
    skips it).

    ``progress(phase, done, total)`` is called once per optimizer generation and phase. Returns
    ``{"mechanism": <[mechanism] table>, "summary": {...}}``: the summary has ``crank_mm``, ``coupler_mm``,
    ``stroke_mm``, ``base_radius_mm``, ``min_transmission_angle_deg``, ``min_slider_angle_deg``,
    ``max_path_error_mm`` (forward check of the exact synthesis), ``constraints_met`` and ``violations``,
    ``optimizer_converged``, ``generations``, ``warnings``, ``fourbar_path_error_mm`` with the four-bar's
    dimensions and checks in ``fourbar``, and ``time_s``. Raises :class:`NumericalError` when no design of
    the final population can be synthesized.
    """
    from scipy.optimize import differential_evolution

    t_start = time.perf_counter()
    ps = parse_path(path)
    pth = build_path(ps)
    t = vmap_scalar(pth.point, np.arange(_N_FIT) / _N_FIT)
    lo_xy, hi_xy = t.min(0), t.max(0)
    size = float(np.max(hi_xy - lo_xy))
    mid = (lo_xy + hi_xy) / 2
    tick = progress or (lambda phase, done, total: None)
    sharp = bool(pth.sharp_u)

    def run_de(phase, fn, bounds):
        gen = [0]
        tick(phase, 0, maxiter)

        def callback(xk, convergence=None):
            gen[0] += 1
            tick(phase, gen[0], maxiter)

        res = differential_evolution(
            fn, bounds, maxiter=maxiter, popsize=popsize, tol=1e-3, polish=False, vectorized=True, updating="deferred",
            callback=callback, **_de_seed(seed),
        )
        tick(phase, maxiter, maxiter)
        return res

    bounds = [
        (mid[0] - 4 * size, mid[0] + 4 * size), (mid[1] - 4 * size, mid[1] + 4 * size),
        (-180.0, 180.0), (-2 * size, 2 * size), (0.5 * size, 6 * size),
    ]
    res = run_de("CCM dimensions", lambda x: _ccm_eval(x, t, max_pressure_angle, roller_radius, sharp, min_curvature_ratio)["cost"], bounds)
    # exact synthesis of the best designs, in order of their score, until one meets every constraint
    tick("exact synthesis", 0, 1)
    order = np.argsort(res.population_energies)
    cands = [res.x] + [res.population[i] for i in order if not np.allclose(res.population[i], res.x)]
    best, errors = None, []
    for x in cands[:_N_CANDIDATES]:
        score, info = _ccm_score(x, t, max_pressure_angle, roller_radius, sharp, min_curvature_ratio)
        table = _ccm_table(x, info["start"], roller_radius, max_pressure_angle)
        try:
            syn = synthesize_motion(path, table)
        except (NumericalError, InputError) as exc:
            errors.append(str(exc))
            continue
        violations = _meets_constraints(syn.summary)
        if best is None or (best[2] and not violations):
            best = (table, syn, violations, score)
        if not violations:
            break
    tick("exact synthesis", 1, 1)
    if best is None:
        raise NumericalError("synthesis", f"none of the {min(len(cands), _N_CANDIDATES)} best designs could be synthesized exactly (first: {errors[0]}); try a larger maxiter or another seed")
    table, syn, violations, score = best
    # the least base radius that meets `camdyn check`'s pressure-angle and curvature limits on its own grid
    tick("cam size", 0, 1)
    try:
        rb = min_base_radius(syn.tabulated, syn.follower, max_pressure_angle=max_pressure_angle, min_curvature_ratio=min_curvature_ratio)
        table["base_radius"] = max(math.ceil((rb + 1e-6) * 2.0) / 2.0, 0.5)
    except NumericalError as exc:  # e.g. sharp corners: no base radius makes the contour smooth
        table["base_radius"] = float(syn.summary["base_radius_mm"])
        syn.warnings.append(f"base radius: {exc.message}; kept {table['base_radius']:g} mm")
    table.pop("max_pressure_angle", None)  # used only to choose a base radius, which the table now gives
    tick("cam size", 1, 1)
    keys = ("crank_mm", "coupler_mm", "start_angle_deg", "rotation", "stroke_mm", "max_path_error_mm", "min_transmission_angle_deg", "min_slider_angle_deg", "base_radius_mm", "offset_mm")
    summary: dict = {k: syn.summary[k] for k in keys}
    summary["base_radius_mm"] = table["base_radius"]
    summary.update(
        objective=DIMENSION_OBJECTIVE, objective_value=float(score), optimizer_converged=bool(res.success), generations=int(res.nit),
        seed=seed, maxiter=maxiter, popsize=popsize, max_pressure_angle_deg=max_pressure_angle, min_curvature_ratio=min_curvature_ratio,
        constraints_met=not violations, violations=violations, warnings=list(syn.warnings),
    )
    if fourbar:  # the CCM paper's comparison: the best plain four-bar coupler curve
        fb_bounds = [
            (mid[0] - 3 * size, mid[0] + 3 * size), (mid[1] - 3 * size, mid[1] + 3 * size),
            (mid[0] - 3 * size, mid[0] + 3 * size), (mid[1] - 3 * size, mid[1] + 3 * size),
            (0.05 * size, 2 * size), (0.1 * size, 5 * size), (0.1 * size, 5 * size), (-3 * size, 3 * size), (-3 * size, 3 * size),
            (-1.0, 1.0),
        ]
        fb = run_de("four-bar comparison", lambda x: _fourbar_score(x, t), fb_bounds)
        curve, miss, tmin = _fourbar_curve(fb.x)
        names = ("ax", "ay", "dx", "dy", "crank", "coupler", "rocker", "point_along", "point_across")
        summary["fourbar_path_error_mm"] = float(_curve_error(curve, t))
        summary["fourbar"] = dict(zip(names, map(float, fb.x[:9]), strict=True)) | {
            "mode": 1 if fb.x[9] >= 0 else -1, "min_transmission_angle_deg": float(tmin), "closes": bool(miss == 0.0),
            "grashof_crank_rocker": bool(_fourbar_grashof(fb.x[:, None])[0] <= 1e-9),
            "optimizer_converged": bool(fb.success), "generations": int(fb.nit),
        }
    summary["time_s"] = time.perf_counter() - t_start
    return {"mechanism": table, "summary": summary}
