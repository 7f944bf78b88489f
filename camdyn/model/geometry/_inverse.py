"""The follower motion of a given cam outline, by exact contact: the inverse of the cam's geometry.

The outline's points (cam frame at cam angle 0, in sequence along it) must be star-shaped about the cam centre,
so the outline is a radius r(alpha) of the polar angle; r is fitted as a periodic quintic smoothing spline
(exact for points written by ``camdyn profile``, smoothing for measured ones). Each point P of that smooth
outline, with its outward normal N, is then the contact at exactly one cam angle, in closed form with the
conventions of :mod:`camdyn.model.geometry`:

* translating roller: the roller centre C = P + Rr N lies on the follower axis x = sigma e, so
  theta = sigma (acos(sigma e / |C|) - angle(C)) and s = sqrt(|C|^2 - e^2) - sqrt(Rp^2 - e^2);
* oscillating roller: C lies on the circle of radius ``arm_length`` about the pivot, which fixes the arm angle
  psi by |C| (cos psi = (L^2 + a^2 - |C|^2) / (2 L a)) and then theta by the angle of C;
* translating flat face: N points along +y, theta = sigma (90 deg - angle(N)), s = P.N - Rb (the support
  function of the cam);
* oscillating flat face: the face's distance from the centre is L sin psi - h = P.N, and N is the face's normal.

A flat face touches only the outline's convex hull: where it bridges a concave stretch it never touches the
cam there. A roller cannot follow a concave stretch of smaller radius than its own, nor a contour whose contact
would run backwards (a pressure angle of 90 deg): such outlines are refused. The base radius is the least
radius of the fitted outline.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..._core.errors import InputError
from ...schema import FollowerSpec
from ..datafiles import MAX_GAP_DEG, Samples
from ..motion import FitResiduals, SplineFit, acceleration_noise, fit_periodic
from ._kernel import check_dimensions

_DENSE = 16384  # samples of the fitted outline, evenly in polar angle
_TARGET = 3600  # contact samples kept for the motion's fit, about evenly in cam angle
_BRIDGE_MM = 1e-3  # a bridged stretch shallower than this (and than 3 sigma of the outline's noise) is not reported


@dataclass(frozen=True)
class ContourFit(FitResiduals):
    """An outline and its fitted radius r(polar angle) (mm, cam frame; the points in counterclockwise order)."""

    file: str
    points: np.ndarray  # (n, 2) mm
    spline: SplineFit  # r(alpha), mm
    base_radius: float  # least radius of the fitted outline, mm
    repeats: int = 0  # points dropped from the file for exactly repeating the one before them
    unit: ClassVar[str] = "mm"  # of the residuals and the noise

    @property
    def angle_deg(self) -> np.ndarray:
        return np.rad2deg(self.spline.x)

    @property
    def residual(self) -> np.ndarray:
        """Radial departure of the points from the fitted outline, mm (outward positive)."""
        return self.spline.residual

    @property
    def max_residual_at_polar_deg(self) -> float:
        return float(self.angle_deg[self.spline.worst])

    @property
    def point_count(self) -> int:
        return int(len(self.points))

    @property
    def method(self) -> str:
        """How the outline was fitted, in words."""
        return self.spline.method(" of the radius over the polar angle")

    def json(self) -> dict:
        """``check --json``'s ``motion.contour``: the outline's fit, its residuals and noise (mm)."""
        return self.residuals_json() | {
            "max_residual_at_polar_deg": self.max_residual_at_polar_deg,
            "repeats_dropped": self.repeats,
        }


@dataclass(frozen=True)
class ContactMotion:
    """The follower motion derived from an outline: samples (cam angle deg, lift mm or swing deg) at exact
    contact, the follower with the outline's base radius, the outline's fit and what a designer must know."""

    follower: FollowerSpec
    theta_deg: np.ndarray
    lift: np.ndarray
    contour: ContourFit
    warnings: tuple[str, ...]

    # The samples' noise floor for their fit (mm, or deg of swing): closed-form contact is exact to round-off
    # (about 1e-13 of the unit), below which REML would choose the smoothing by the CPU's rounding (the least
    # contact force then differed by 1e-3 between two machines); a picometre (a nano-degree) floor is far below
    # anything a cam's motion can show and gives every machine the same smoothing.
    rounding: float = 1e-9


def _first_crossing(xy: np.ndarray) -> tuple[int, int] | None:
    """The first pair of non-adjacent edges (i, i+1), (j, j+1) of a closed polygon that cross, if any."""
    a, b = xy, np.roll(xy, -1, axis=0)
    n = len(xy)

    def orient(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
        return np.sign(
            (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
        )

    for i in range(n):
        j = np.arange(i + 2, n if i else n - 1)
        if not j.size:
            continue
        cross = (orient(a[i], b[i], a[j]) * orient(a[i], b[i], b[j]) < 0) & (
            orient(a[j], b[j], a[i]) * orient(a[j], b[j], b[i]) < 0
        )
        if cross.any():
            return i, int(j[np.argmax(cross)])
    return None


def _star_order(s: Samples) -> tuple[np.ndarray, np.ndarray]:
    """The points in counterclockwise order about the cam centre and their row numbers; :class:`InputError` for
    an outline that is open, not around the centre, self-intersecting or not star-shaped about it."""
    xy, rows = s.values, s.rows
    r = np.hypot(xy[:, 0], xy[:, 1])
    if np.any(r <= 1e-9 * r.max()):
        raise InputError(
            s.where(int(np.argmin(r))), "lies on the cam centre (0, 0): the outline must surround the centre"
        )
    ang = np.arctan2(xy[:, 1], xy[:, 0])
    step = np.angle(np.exp(1j * (np.roll(ang, -1) - ang)))  # point i to i + 1, the closing edge last
    turns = int(round(step.sum() / (2 * math.pi)))
    if turns == 0:
        raise InputError(
            s.shown,
            "does not go around the cam centre (0, 0): give the outline in the cam frame, centred on the camshaft, "
            "and closed",
        )
    if abs(turns) > 1:
        raise InputError(s.shown, f"winds {abs(turns)} times around the cam centre: the outline is self-intersecting")
    if turns < 0:
        xy, rows, ang = xy[::-1], rows[::-1], ang[::-1]
        step = np.angle(np.exp(1j * (np.roll(ang, -1) - ang)))
    shown = Samples(s.shown, xy, rows, s.row_word, s.rounding)
    back = np.flatnonzero(step <= 0.0)
    if back.size:
        hit = _first_crossing(xy)
        if hit is not None:
            i, j = hit
            raise InputError(
                shown.where(i),
                f"the outline is self-intersecting: its edge from here crosses the edge from {s.row_word} "
                f"{int(rows[j])}",
            )
        i = (int(back[0]) + 1) % len(xy)
        raise InputError(
            shown.where(i),
            "the outline is not star-shaped about the cam centre: it turns back here (polar angle "
            f"{math.degrees(ang[i]):.4g} deg after {math.degrees(ang[i - 1]):.4g} deg); every ray from the centre "
            "must cross it once",
        )
    k = int(np.argmax(step))
    if math.degrees(step[k]) > MAX_GAP_DEG:
        a0 = math.degrees(ang[k]) % 360.0
        raise InputError(
            shown.where(k),
            f"the outline is open: no point from polar angle {a0:.4g} to {a0 + math.degrees(step[k]):.4g} deg (at "
            f"most {MAX_GAP_DEG:g} deg between points)",
        )
    return xy, rows


def _outline(alpha: np.ndarray, spline: SplineFit) -> dict[str, np.ndarray]:
    """Point P, outward unit normal N and curvature kappa (convex positive) of r(alpha), counterclockwise."""
    r, r1, r2, _ = spline(alpha)
    c, s = np.cos(alpha), np.sin(alpha)
    P = np.stack([r * c, r * s], axis=-1)
    d1 = np.stack([r1 * c - r * s, r1 * s + r * c], axis=-1)
    d2 = np.stack([(r2 - r) * c - 2 * r1 * s, (r2 - r) * s + 2 * r1 * c], axis=-1)
    speed = np.hypot(d1[:, 0], d1[:, 1])
    N = np.stack([d1[:, 1], -d1[:, 0]], axis=-1) / speed[:, None]
    kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3
    return {"P": P, "N": N, "kappa": kappa}


def _rot(angle, v):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _contacts(f: FollowerSpec, rb: float, P: np.ndarray, N: np.ndarray, shown: str) -> tuple[np.ndarray, np.ndarray]:
    """Cam angle (rad, unwrapped) and follower coordinate (mm or rad) at which each outline point is the contact."""
    sigma, e = f.sigma, f.offset
    ang = lambda v: np.arctan2(v[..., 1], v[..., 0])  # noqa: E731
    if not f.translating:
        L, pa = f.pivot_distance, math.radians(f.pivot_angle)
        assert L is not None  # the schema: an oscillating follower needs it
        D = L * np.array([math.cos(pa), math.sin(pa)])
        u = -D / L
    if f.roller_radius is not None:
        rr = f.roller_radius
        C = P + rr * N
        rc, gamma = np.hypot(C[:, 0], C[:, 1]), ang(C)
        rp = rb + rr
        if f.translating:
            return sigma * (np.arccos(sigma * e / rc) - gamma), np.sqrt(rc**2 - e**2) - math.sqrt(rp**2 - e**2)
        a = f.arm_length
        assert a is not None  # the schema: an oscillating roller needs it
        cos_psi = (L**2 + a**2 - rc**2) / (2 * L * a)
        if np.any(np.abs(cos_psi) >= 1.0):
            i = int(np.argmax(np.abs(cos_psi)))
            raise InputError(
                shown,
                f"the arm (arm_length {a:g} mm, pivot_distance {L:g} mm) cannot reach the outline at polar angle "
                f"{math.degrees(ang(P[i])) % 360:.4g} deg",
            )
        psi = np.arccos(cos_psi)
        E = D + a * _rot(-psi, u)
        return sigma * (ang(E) - gamma), psi - math.acos((L**2 + a**2 - rp**2) / (2 * L * a))
    support = np.sum(P * N, axis=1)
    if f.translating:
        return sigma * (math.pi / 2 - ang(N)), support - rb
    h = e
    sin_psi = (support + h) / L
    if np.any(np.abs(sin_psi) >= 1.0):
        i = int(np.argmax(np.abs(sin_psi)))
        raise InputError(
            shown,
            f"the face (pivot_distance {L:g} mm, offset {h:g} mm) cannot reach the outline at polar angle "
            f"{math.degrees(ang(P[i])) % 360:.4g} deg",
        )
    psi = np.arcsin(sin_psi)
    w = _rot(-psi, u)
    m = -np.stack([-w[:, 1], w[:, 0]], axis=-1)
    return sigma * (ang(m) - ang(N)), psi - math.asin((rb + h) / L)


def _stretch(alpha: np.ndarray, mask: np.ndarray) -> list[tuple[int, int]]:
    """Runs (first, last) of True in a periodic mask, as sample indices (last may wrap past the end)."""
    if mask.all() or not mask.any():
        return [(0, len(mask) - 1)] if mask.all() else []
    start = int(np.argmin(mask))  # begin the scan where the mask is False
    m = np.roll(mask, -start)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], m.astype(int), [0]])))
    return [(int(a + start), int(b - 1 + start)) for a, b in zip(edges[0::2], edges[1::2], strict=True)]


def _bridges(f: FollowerSpec, alpha, geo, on_hull, theta, min_depth: float) -> list[str]:
    """Warnings for concave stretches a flat face bridges: the polar angles it never touches, and the cam angle
    at which it lies across them."""
    out = []
    n = len(alpha)
    for a, b in _stretch(alpha, ~on_hull):
        i0, i1 = (a - 1) % n, (b + 1) % n  # the hull vertices on either side
        P = geo["P"]
        chord = P[i1] - P[i0]
        idx = np.arange(a, b + 1) % n
        normal = np.array([chord[1], -chord[0]]) / max(np.hypot(*chord), 1e-300)
        depth = float(np.max((P[i0] - P[idx]) @ normal))
        if depth <= min_depth:
            continue
        at = math.degrees(theta[i0]) % 360.0
        out.append(
            f"the flat face bridges a concave stretch of the outline from polar angle {math.degrees(alpha[a]):.4g} to "
            f"{math.degrees(alpha[b % n] + (2 * math.pi if b >= n else 0.0)):.4g} deg (up to {depth:.3g} mm deep): "
            f"the follower never touches the cam there; the contact jumps across it at cam angle {at:.4g} deg"
        )
    return out


def contact_motion(samples: Samples, f: FollowerSpec) -> ContactMotion:
    """The follower motion of the outline ``samples`` for follower ``f`` (its base radius is the outline's
    least radius), by exact contact; see the module docstring."""
    xy, rows = _star_order(samples)
    alpha_pts = np.mod(np.arctan2(xy[:, 1], xy[:, 0]), 2 * math.pi)
    spline = fit_periodic(alpha_pts, np.hypot(xy[:, 0], xy[:, 1]), sigma_floor=samples.rounding)
    alpha = np.arange(_DENSE) * (2 * math.pi / _DENSE)
    r_dense = spline(alpha)[0]
    rb = float(r_dense.min())
    contour = ContourFit(samples.shown, xy, spline, rb, samples.repeats)
    f = f.model_copy(update={"base_radius": rb})
    check_dimensions(f)
    geo = _outline(alpha, spline)
    warnings: list[str] = []
    keep = np.ones(_DENSE, dtype=bool)
    if f.roller:
        bad = 1.0 + f.roller_radius * geo["kappa"] <= 0.0
        if bad.any():
            i = int(np.argmin(geo["kappa"]))
            raise InputError(
                samples.shown,
                f"the roller (radius {f.roller_radius:g} mm) cannot follow the concave stretch around polar angle "
                f"{math.degrees(alpha[i]):.4g} deg: its radius of curvature (down to {-1.0 / geo['kappa'][i]:.4g} mm) "
                "is smaller than the roller's",
            )
    else:
        from scipy.spatial import ConvexHull  # a flat face's contour only: scipy.spatial takes 0.2 s to load

        keep[:] = False
        keep[ConvexHull(geo["P"]).vertices] = True
    theta, q = _contacts(f, rb, geo["P"][keep], geo["N"][keep], samples.shown)
    theta = np.unwrap(theta)
    index = np.flatnonzero(keep)
    # the contact runs against the cam's rotation; across a bridge (not adjacent samples) the two ends of the
    # discrete hull's edge may straddle its normal by a sample's turn, which is no reversal
    ahead = np.where(np.diff(index) == 1, -f.sigma * np.diff(theta), np.inf)
    if np.any(ahead <= 0.0):
        i = int(index[int(np.argmin(ahead))])
        raise InputError(
            samples.shown,
            f"the follower cannot follow the outline near polar angle {math.degrees(alpha[i]):.4g} deg: the contact "
            "would run backwards (a pressure angle of 90 deg); change the follower or its offset, pivot or arm",
        )
    if not f.roller:
        th_all = np.full(_DENSE, np.nan)
        th_all[keep] = theta
        warnings += _bridges(f, alpha, geo, keep, th_all, max(_BRIDGE_MM, 3.0 * spline.sigma))
    warnings += _noise_warning(contour)
    theta_deg = np.rad2deg(theta) % 360.0
    order = np.argsort(theta_deg)
    pick = order[
        np.unique(np.searchsorted(theta_deg[order], np.linspace(0.0, 360.0, _TARGET, endpoint=False)) % len(order))
    ]
    return ContactMotion(f, theta_deg[pick], f.kind.motion_to_lift(q[pick]), contour, tuple(warnings))


def _noise_warning(contour: ContourFit) -> list[str]:
    """The outline's measurement noise, where it leaves its curvature (and so the follower's acceleration)
    uncertain by more than :data:`camdyn.model.motion.ACCEL_NOISE_SHARE` of the largest."""
    sp = contour.spline
    if (noisy := acceleration_noise(sp)) is None:
        return []
    band, share, _ = noisy
    return [
        f"{contour.file}: the outline's noise (about {sp.sigma:.2g} mm) leaves its radius's second derivative "
        f"uncertain by +-{band:.3g} mm/rad^2 (95 %), {share}: the follower's acceleration, jump speeds and forces "
        "rest on the smoothing, not on the measurement"
    ]
