"""Cam geometry: follower specification, pitch curve, contour, pressure angle, curvature, undercut.

Conventions (Norton's), in a fixed frame with the cam centre O at the origin; all lengths mm, angles as noted:

* ``base_radius`` Rb is the least radius of the cam contour. For a roller follower of radius Rr the prime
  circle has radius Rp = Rb + Rr.
* ``rotation`` is the sense in which the cam turns in the fixed frame ("cw" or "ccw"); sigma = +1 for ccw,
  -1 for cw. The cam frame coincides with the fixed frame at cam angle 0; a fixed point q is seen in the
  cam frame at R(-sigma theta) q. ``pitch`` and ``contour`` are given in the cam frame.
* translating followers move along +y. A translating roller with offset e has its axis at x = sigma * e, so
  a positive offset always lowers the pressure angle on the rise, whatever the rotation: at lift s the roller
  centre is at (sigma e, sqrt(Rp^2 - e^2) + s) and the pressure angle is Norton's
  phi = atan((s' - e) / (s + sqrt(Rp^2 - e^2))) for both senses. A translating flat face is perpendicular to
  the axis at y = Rb + s (its offset moves only the contact point across the face, not the contour).
* oscillating followers: pivot D at distance ``pivot_distance`` L from O in direction ``pivot_angle`` (deg,
  default 0, i.e. D on +x), u = (O - D)/L. The arm turns clockwise by psi from the direction D->O:
  w(psi) = R(-psi) u. Positive swing phi (the motion, rad) moves the follower away from O; psi = psi0 + phi.

  - oscillating roller: roller centre E = D + ``arm_length`` * w(psi); psi0 puts E on the prime circle,
    cos psi0 = (L^2 + a^2 - Rp^2) / (2 L a).
  - oscillating flat: the face is the line through D + h n(psi) along w(psi), n = J w (J = rotation by +90
    deg), h = ``offset`` (the face's distance from the pivot, positive toward the cam centre; 0: the face
    line passes through the pivot). O lies on the +n side at distance L sin(psi) - h, so psi0 makes the face
    tangent to the base circle: sin psi0 = (Rb + h) / L. ``arm_length`` is not used.

* pressure angle phi (deg, signed): the angle from the follower's velocity direction (the velocity of the
  follower point at the contact for a positive change of s or phi) to the contact normal N (outward from the
  cam), times sigma; so the translating roller gives Norton's formula above and positive phi is the rise.
* radii of curvature (mm) are signed, positive where the curve is convex (seen from outside the cam);
  for a roller, rho_contour = rho_pitch - Rr; for a flat face rho = h + d^2h/dalpha^2 with h the face's
  distance from O and alpha its normal direction (translating: Rb + s + s'').
* the flat face coordinate t (mm) is the contact's position along the face from the follower's axis
  (translating: t = s' - e, the lecture's t = f') or from the foot of the perpendicular from the pivot
  (oscillating; then t is also the lever arm).

The lecture (seed 001) differs: its roller centre at zero lift sits at r_b + r_r along the follower axis, with
the offset delta across it, so its least contour radius is sqrt((r_b + r_r)^2 + delta^2) - r_r (its "r_b = 4 cm"
with r_r = 1, delta = 0.5 cm is camdyn's base_radius = 40.249 mm); its cam frame has the follower along +x at
theta = 0 (camdyn's is that rotated by +90 deg); its cw offset delta > 0 is camdyn's offset e = +delta; and its
ccw flat-face formulas take theta as the polar angle of the contact in the cam frame, i.e. minus the cam angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Literal

import jax
import jax.numpy as jnp
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from .checks import Check
from .errors import InputError, NumericalError
from .motion import evaluate
from .programs import cached_jit

FOLLOWER_TYPES = ("translating-roller", "translating-flat", "oscillating-roller", "oscillating-flat")

CUSP_MM = 1e-6  # a contour radius of curvature under 1 nm is a cusp: flat-faced "curvature" check limit
_BREAK_EPS = 1e-9  # rad: one-sided limits at the motion's breaks, where s'' may jump
_DEFAULT_PRESSURE = {"translating": 30.0, "oscillating": 35.0}


class FollowerSpec(BaseModel):
    """The ``[follower]`` table of a case file (lengths mm, angles deg)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    type: Literal["translating-roller", "translating-flat", "oscillating-roller", "oscillating-flat"] = "translating-roller"
    base_radius: float = Field(gt=0, description="least radius of the cam contour, mm")
    roller_radius: float | None = Field(default=None, gt=0, description="roller radius, mm (roller followers)")
    offset: float = Field(
        default=0.0,
        description="translating: axis offset e, mm, positive lowers the rise pressure angle; "
        "oscillating-flat: distance of the face line from the pivot, mm, positive toward the cam centre",
    )
    rotation: Literal["cw", "ccw"] = "cw"
    pivot_distance: float | None = Field(default=None, gt=0, description="oscillating: cam centre to arm pivot, mm")
    pivot_angle: float = Field(default=0.0, description="oscillating: direction of the pivot from the cam centre, deg")
    arm_length: float | None = Field(default=None, gt=0, description="oscillating: pivot to roller centre, mm")
    face_width: float | None = Field(default=None, gt=0, description="flat followers: usable face width, mm")

    @property
    def translating(self) -> bool:
        return self.type.startswith("translating")

    @property
    def roller(self) -> bool:
        return self.type.endswith("roller")

    @property
    def sigma(self) -> float:
        return 1.0 if self.rotation == "ccw" else -1.0


# ------------------------------------------------------------------------------------- validation
def _validate(motion, f: FollowerSpec) -> None:
    """Raise :class:`InputError` for a follower that cannot carry this motion or cannot be assembled."""
    want = "mm" if f.translating else "rad"
    if motion.unit != want:
        raise InputError("follower.type", f"a {f.type} follower needs a motion in {want}, got {motion.unit}")
    if f.roller and f.roller_radius is None:
        raise InputError("follower.roller_radius", f"required for a {f.type} follower")
    rp = f.base_radius + (f.roller_radius or 0.0)
    if f.type == "translating-roller" and abs(f.offset) >= rp:
        raise InputError("follower.offset", f"|offset| = {abs(f.offset):g} mm must be below the prime radius {rp:g} mm")
    if not f.translating:
        if f.pivot_distance is None:
            raise InputError("follower.pivot_distance", f"required for a {f.type} follower")
        L = f.pivot_distance
        if f.roller:
            if f.arm_length is None:
                raise InputError("follower.arm_length", f"required for a {f.type} follower")
            a = f.arm_length
            if not abs(L - a) < rp < L + a:
                raise InputError(
                    "follower.arm_length",
                    f"the roller cannot reach the prime circle (radius {rp:g} mm): need |L - a| < Rp < L + a "
                    f"with L = {L:g} mm, a = {a:g} mm",
                )
        elif not abs(f.base_radius + f.offset) < L:
            raise InputError(
                "follower.pivot_distance",
                f"the face cannot touch the base circle: need |base_radius + offset| = "
                f"{abs(f.base_radius + f.offset):g} mm < pivot_distance = {L:g} mm",
            )


def _params(f: FollowerSpec, base_radius: float | None = None) -> jnp.ndarray:
    """Numeric follower parameters (dynamic under jit, so base-circle bisection does not recompile)."""
    rb = f.base_radius if base_radius is None else base_radius
    return jnp.array(
        [
            rb,
            f.roller_radius or 0.0,
            f.offset,
            f.pivot_distance or 0.0,
            math.radians(f.pivot_angle),
            f.arm_length or 0.0,
            f.sigma,
        ]
    )


# ------------------------------------------------------------------------------ follower geometry
def _rot(angle, v):
    c, s = jnp.cos(angle), jnp.sin(angle)
    return jnp.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _J(v):  # rotation by +90 deg
    return jnp.stack([-v[1], v[0]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _pivot(p):
    """Pivot D and the unit vector u from D towards O (fixed frame)."""
    d = jnp.stack([jnp.cos(p[4]), jnp.sin(p[4])])
    return p[3] * d, -d


def _roller_centre(kind: str, p, q):
    """Roller centre in the fixed frame at follower coordinate q (mm or rad)."""
    rb, rr, e, L, _, a, sigma = p
    rp = rb + rr
    if kind == "translating-roller":
        return jnp.stack([sigma * e, jnp.sqrt(rp**2 - e**2) + q])
    D, u = _pivot(p)
    psi0 = jnp.arccos((L**2 + a**2 - rp**2) / (2 * L * a))
    return D + a * _rot(-(psi0 + q), u)


def _flat_face(kind: str, p, q):
    """Face of a flat follower in the fixed frame at coordinate q.

    Returns (m, h, foot, along): the cam's outward normal at the contact (unit), the face's distance from O,
    the face's reference point (axis or foot of the pivot's perpendicular) and the unit direction along the
    face in which the face coordinate t is counted.
    """
    rb, _, e, L, _, _, sigma = p
    if kind == "translating-flat":
        m = jnp.array([0.0, 1.0])
        return m, rb + q, jnp.stack([sigma * e, rb + q]), jnp.stack([sigma, 0.0 * sigma])
    D, u = _pivot(p)
    psi = jnp.arcsin((rb + e) / L) + q
    w = _rot(-psi, u)
    n = _J(w)
    return -n, L * jnp.sin(psi) - e, D + e * n, w


def _jet2(F):
    """F(0), F'(0), F''(0) of a function of one scalar by forward-mode autodiff."""
    d1 = jax.jacfwd(F)
    return F(0.0), d1(0.0), jax.jacfwd(d1)(0.0)


def _point(kind: str, p, th0, sv):
    """Everything camdyn judges at one cam angle th0 (rad), given the motion values sv = (s, s', s'', s''').

    The follower coordinate is expanded as the cubic Taylor polynomial of the motion about th0, so autodiff of
    the geometry in t gives exact tangents and curvatures from the motion's closed-form derivatives.
    """
    sigma = p[6]
    q_of = lambda t: sv[0] + t * (sv[1] + t * (sv[2] / 2 + t * sv[3] / 6))  # noqa: E731
    cam = lambda t, v: _rot(-sigma * (th0 + t), v)  # noqa: E731
    nan = jnp.nan
    if kind.endswith("roller"):
        P, P1, P2 = _jet2(lambda t: cam(t, _roller_centre(kind, p, q_of(t))))
        speed = jnp.hypot(P1[0], P1[1])
        N = sigma * _J(P1) / speed  # outward: the pitch curve runs cw for a ccw cam and vice versa
        kappa = -sigma * _cross(P1, P2) / speed**3  # convex positive
        v = cam(0.0, jax.jacfwd(lambda q: _roller_centre(kind, p, q))(sv[0]))
        rr = p[1]
        return dict(
            pitch=P,
            contour=P - rr * N,
            kappa_pitch=kappa,
            rho_contour=(1.0 - rr * kappa) / kappa,
            phi=sigma * jnp.arctan2(_cross(v, N), v @ N),
            lever=v @ N,
            face_t=nan,
        )

    def face(t):  # the face line in the cam frame: unit normal m and distance h from O
        m_fixed, h, _, _ = _flat_face(kind, p, q_of(t))
        return cam(t, m_fixed), h

    (m, h), (m1, h1), (m2, h2) = _jet2(face)
    _, _, foot, along = _flat_face(kind, p, sv[0])
    foot, along = cam(0.0, foot), cam(0.0, along)
    a1, a2 = _cross(m, m1), _cross(m, m2)  # d alpha / d theta and its derivative (|m| = 1)
    C = h * m + (h1 / a1) * _J(m)  # envelope of the lines x . m = h
    if kind == "translating-flat":
        v = m
    else:  # velocity of the follower point at C for d psi = 1: the arm turns clockwise about D
        D = cam(0.0, _pivot(p)[0])
        v = -_J(C - D)
    return dict(
        pitch=foot,
        contour=C,
        kappa_pitch=nan,
        rho_contour=h + (h2 * a1 - h1 * a2) / a1**3,
        phi=sigma * jnp.arctan2(_cross(v, m), v @ m),
        lever=v @ m,
        face_t=(C - foot) @ along,
    )


@cached_jit
def _geometry(p, theta, sv, kind: str):
    """Vectorised :func:`_point`, compiled once per follower type and array bucket whatever the motion (it is
    evaluated apart), the rotation and the lengths: sweeps and base-circle bisection reuse it."""
    return jax.vmap(lambda th, s: _point(kind, p, th, s), in_axes=(0, 1))(theta, sv)


_CHUNK = 4096  # angles per compiled call: a 3600-step revolution plus its breaks fits one


def _eval_np(motion, f: FollowerSpec, theta_rad, base_radius: float | None = None) -> dict[str, np.ndarray]:
    """Evaluate at any number of angles (rad) in fixed-size chunks, so nothing recompiles per query size."""
    theta_rad = np.asarray(theta_rad, dtype=float)
    flat = np.atleast_1d(theta_rad).ravel()
    n = flat.size
    padded = np.zeros(max(1, -(-n // _CHUNK)) * _CHUNK)
    padded[:n] = flat
    p = _params(f, base_radius)
    parts = []
    for chunk in padded.reshape(-1, _CHUNK):
        theta = jnp.asarray(chunk)
        sv = evaluate(motion, theta)
        parts.append(_geometry(p, theta, sv, f.type) | {"s": sv[0]})
    out = {k: np.concatenate([np.asarray(part[k]) for part in parts])[:n] for k in parts[0]}
    return {k: v.reshape(theta_rad.shape + v.shape[1:]) for k, v in out.items()}


def _with_breaks(motion, theta_rad: np.ndarray) -> np.ndarray:
    """theta plus the one-sided limits at every break: extremes of s'' terms may sit exactly there."""
    b = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
    return np.concatenate([theta_rad, np.mod(b - _BREAK_EPS, 2 * np.pi), b + _BREAK_EPS])


# ------------------------------------------------------------------------------------ judgments
@dataclass(frozen=True)
class _Summary:
    max_phi_deg: float
    max_phi_at_deg: float
    min_rho_mm: float  # least convex contour radius (roller) or least contour radius (flat), signed
    min_rho_at_deg: float
    cusp: bool
    t_min: float
    t_max: float


def _summarise(f: FollowerSpec, theta_rad: np.ndarray, ev: dict[str, np.ndarray]) -> _Summary:
    deg = np.rad2deg(theta_rad) % 360.0
    phi = np.abs(np.rad2deg(ev["phi"]))
    if not np.all(np.isfinite(ev["contour"])):
        bad = deg[~np.all(np.isfinite(ev["contour"]), axis=-1)][0]
        raise NumericalError(f"theta = {bad:.4g} deg", "the contour is not finite (degenerate follower geometry)")
    i = int(np.argmax(phi))
    if f.roller:
        kappa = ev["kappa_pitch"]
        j = int(np.argmax(kappa))  # the least convex radius sits at the greatest convex curvature
        rho = 1.0 / kappa[j] - f.roller_radius
        cusp = bool(kappa[j] * f.roller_radius >= 1.0)
        t_min = t_max = math.nan
    else:
        rho_all = ev["rho_contour"]
        j = int(np.argmin(rho_all))
        rho = float(rho_all[j])
        cusp = rho < CUSP_MM
        t_min, t_max = float(np.min(ev["face_t"])), float(np.max(ev["face_t"]))
    return _Summary(float(phi[i]), float(deg[i]), float(rho), float(deg[j]), cusp, t_min, t_max)


def _curvature_value(f: FollowerSpec, s: _Summary) -> float:
    return s.min_rho_mm / f.roller_radius if f.roller else s.min_rho_mm


def _passes(f: FollowerSpec, s: _Summary, max_pa: float, min_ratio: float) -> bool:
    limit = min_ratio if f.roller else CUSP_MM
    return s.max_phi_deg <= max_pa and not s.cusp and _curvature_value(f, s) >= limit


def _limits(f: FollowerSpec, max_pressure_angle: float | None, min_curvature_ratio: float) -> float:
    max_pa = _DEFAULT_PRESSURE["translating" if f.translating else "oscillating"] if max_pressure_angle is None else max_pressure_angle
    if not 0.0 < max_pa < 90.0:
        raise InputError("limits.max_pressure_angle", f"must lie in (0, 90) deg, got {max_pa:g}")
    if not min_curvature_ratio > 0.0:
        raise InputError("limits.min_curvature_ratio", f"must be positive, got {min_curvature_ratio:g}")
    return max_pa


def _grid(n: int) -> np.ndarray:
    if n < 16:
        raise InputError("n", f"need at least 16 samples per revolution, got {n}")
    return np.deg2rad(np.arange(n) * (360.0 / n))


def min_base_radius(
    motion, follower: FollowerSpec, *, max_pressure_angle: float | None = None, min_curvature_ratio: float = 1.5, n: int = 3600
) -> float:
    """The least base radius (mm) meeting the pressure-angle (deg) and curvature limits, to 1e-6 mm.

    The pressure angle falls and the pitch curve flattens as the base circle grows, so the limits hold above
    one threshold; a coarse scan first finds a passing radius (guarding against non-monotone oscillating
    layouts), then bisection. Oscillating layouts bound Rb by the pivot and arm; raises
    :class:`NumericalError` if no admissible base radius passes.
    """
    max_pa = _limits(follower, max_pressure_angle, min_curvature_ratio)
    _validate(motion, follower)
    th = _with_breaks(motion, _grid(n))
    f = follower
    rr = f.roller_radius or 0.0

    def ok(rb: float) -> bool:
        try:
            return _passes(f, _summarise(f, th, _eval_np(motion, f, th, rb)), max_pa, min_curvature_ratio)
        except NumericalError:  # a degenerate layout at this radius: not a solution
            return False

    span = max(float(np.ptp(_eval_np(motion, f, th)["s"])), 1e-3)  # lift (mm): a scale for the search
    if f.type == "translating-roller":
        lo = max(abs(f.offset) - rr, 0.0) * (1 + 1e-9) + 1e-9
        hi = max(f.base_radius, lo, span)
        while not ok(hi):  # the pressure angle -> 0 and the pitch curve flattens as Rb -> infinity
            hi *= 2.0
            if hi > 1e6 * max(span, rr, 1.0):
                raise NumericalError("follower.base_radius", "no base radius meets the limits")
    elif f.type == "translating-flat":
        lo, hi = 1e-9, max(f.base_radius, span)
        while not ok(hi):
            hi *= 2.0
            if hi > 1e6 * span:
                raise NumericalError("follower.base_radius", "no base radius meets the limits")
    else:  # bounded by the assembly conditions of _validate
        L = f.pivot_distance
        if f.roller:
            lo, hi = max(abs(L - f.arm_length) - rr, 0.0), L + f.arm_length - rr
        else:
            lo, hi = max(-L - f.offset, 0.0), L - f.offset
        lo, hi = lo + 1e-6 * (hi - lo), hi - 1e-6 * (hi - lo)
        if hi <= lo:
            raise NumericalError("follower.base_radius", "no admissible base radius for this pivot and arm")
    grid = np.linspace(lo, hi, 33)
    good = [i for i, rb in enumerate(grid) if ok(rb)]
    if not good:
        raise NumericalError(
            "follower.base_radius", f"no base radius in ({lo:.4g}, {hi:.4g}) mm meets the limits; move the pivot or change the arm"
        )
    if good[0] == 0:
        return float(grid[0])
    a, b = grid[good[0] - 1], grid[good[0]]
    while b - a > 1e-6:
        mid = 0.5 * (a + b)
        a, b = (a, mid) if ok(mid) else (mid, b)
    return float(b)


@dataclass(frozen=True)
class GeometryResult:
    """The cam of one case, judged. Arrays are over ``theta_deg`` (n equal steps of one revolution).

    ``pitch`` and ``contour`` (2, n) are in the cam frame, mm (for flat followers ``pitch`` is the face's
    reference point, and ``rho_pitch_mm`` is NaN). Radii are signed, convex positive.
    """

    follower: FollowerSpec
    theta_deg: np.ndarray
    pitch: np.ndarray
    contour: np.ndarray
    pressure_angle_deg: np.ndarray
    rho_pitch_mm: np.ndarray
    rho_contour_mm: np.ndarray
    face_t_mm: np.ndarray
    undercut: bool
    cusp: bool
    max_pressure_angle_deg: float
    max_pressure_angle_at_deg: float
    min_radius_of_curvature_mm: float
    min_radius_of_curvature_at_deg: float
    min_face_width_mm: float | None
    face_range_mm: tuple[float, float] | None
    checks: list[Check]
    warnings: list[str]
    advice: list[str]
    _evaluate: Callable[[np.ndarray], dict[str, np.ndarray]] = field(repr=False, compare=False)

    def json(self) -> dict:
        out = {
            "max_pressure_angle_deg": self.max_pressure_angle_deg,
            "max_pressure_angle_at_deg": self.max_pressure_angle_at_deg,
            "min_radius_of_curvature_mm": self.min_radius_of_curvature_mm,
            "min_radius_of_curvature_at_deg": self.min_radius_of_curvature_at_deg,
            "undercut": self.undercut,
            "cusp": self.cusp,
        }
        if self.min_face_width_mm is not None:
            out["min_face_width_mm"] = self.min_face_width_mm
            out["face_range_mm"] = list(self.face_range_mm)
        return out

    def table(self, theta_deg) -> dict[str, np.ndarray]:
        """Geometry columns at arbitrary cam angles (deg); see the module docstring for signs.

        Flat followers add ``face_t_mm``, the contact's position along the face.
        """
        ev = self._evaluate(np.deg2rad(np.asarray(theta_deg, dtype=float)))
        with np.errstate(divide="ignore"):
            rho_p = 1.0 / ev["kappa_pitch"]
        cols = {
            "pressure_angle_deg": np.rad2deg(ev["phi"]),
            "rho_pitch_mm": rho_p,
            "rho_contour_mm": ev["rho_contour"],
            "pitch_x_mm": ev["pitch"][..., 0],
            "pitch_y_mm": ev["pitch"][..., 1],
            "contour_x_mm": ev["contour"][..., 0],
            "contour_y_mm": ev["contour"][..., 1],
        }
        if not self.follower.roller:
            cols["face_t_mm"] = ev["face_t"]
        return cols

    def contour_fn(self) -> Callable[[np.ndarray], np.ndarray]:
        """The exact contour as a closed curve u in [0, 1] -> (2, m) mm, for :func:`camdyn.export.write_profile`."""
        return lambda u: self._evaluate(2 * np.pi * np.asarray(u, dtype=float))["contour"].T


def analyze(
    motion,
    follower: FollowerSpec,
    *,
    max_pressure_angle: float | None = None,
    min_curvature_ratio: float = 1.5,
    n: int = 3600,
) -> GeometryResult:
    """Pitch curve, contour and the geometry checks of a cam.

    ``max_pressure_angle`` deg (None: 30 translating, 35 oscillating); ``min_curvature_ratio`` is the least
    convex contour radius of curvature over the roller radius (flat followers: the contour radius must stay
    above :data:`CUSP_MM`). Raises :class:`InputError` for an impossible follower, :class:`NumericalError` for
    a degenerate contour.
    """
    f = follower
    max_pa = _limits(f, max_pressure_angle, min_curvature_ratio)
    _validate(motion, f)
    grid = _grid(n)
    th = _with_breaks(motion, grid)
    ev_all = _eval_np(motion, f, th)
    s = _summarise(f, th, ev_all)
    ev = {k: v[:n] for k, v in ev_all.items()}

    checks = [Check("pressure_angle", s.max_phi_deg, max_pa, "deg", "<=")]
    if f.roller:
        checks.append(Check("curvature", _curvature_value(f, s), min_curvature_ratio, "ratio", ">="))
    else:
        checks.append(Check("curvature", s.min_rho_mm, CUSP_MM, "mm", ">="))
    width = None if f.roller else s.t_max - s.t_min
    if width is not None and f.face_width is not None:
        checks.append(Check("face_width", width, f.face_width, "mm", "<="))

    warnings: list[str] = []
    if s.cusp:
        what = "the roller radius reaches the pitch curve's convex radius" if f.roller else "rho = Rb + s + s'' <= 0"
        warnings.append(
            f"undercut: the contour folds ({what}); least radius {s.min_rho_mm:.4g} mm at {s.min_rho_at_deg:.4g} deg"
        )
    if s.max_phi_deg >= 60.0:
        warnings.append(f"pressure angle {s.max_phi_deg:.3g} deg at {s.max_phi_at_deg:.4g} deg: the follower may jam")

    advice: list[str] = []
    if not all(c.ok for c in checks[:2]):
        try:
            rb = min_base_radius(motion, f, max_pressure_angle=max_pa, min_curvature_ratio=min_curvature_ratio, n=n)
            advice.append(
                f"base_radius >= {math.ceil(rb * 100) / 100:.2f} mm would meet the pressure-angle "
                f"({max_pa:g} deg) and curvature limits"
            )
        except NumericalError as err:
            advice.append(f"no base radius alone fixes this: {err.message}")
    if width is not None and f.face_width is not None and width > f.face_width:
        advice.append(
            f"face_width >= {width:.3f} mm: the contact runs from t = {s.t_min:.3f} to {s.t_max:.3f} mm along the face"
        )

    with np.errstate(divide="ignore"):
        rho_p = 1.0 / ev["kappa_pitch"]
    return GeometryResult(
        follower=f,
        theta_deg=np.rad2deg(grid),
        pitch=ev["pitch"].T.copy(),
        contour=ev["contour"].T.copy(),
        pressure_angle_deg=np.rad2deg(ev["phi"]),
        rho_pitch_mm=rho_p,
        rho_contour_mm=ev["rho_contour"],
        face_t_mm=ev["face_t"],
        undercut=s.cusp,
        cusp=s.cusp,
        max_pressure_angle_deg=s.max_phi_deg,
        max_pressure_angle_at_deg=s.max_phi_at_deg,
        min_radius_of_curvature_mm=s.min_rho_mm,
        min_radius_of_curvature_at_deg=s.min_rho_at_deg,
        min_face_width_mm=width,
        face_range_mm=None if f.roller else (s.t_min, s.t_max),
        checks=checks,
        warnings=warnings,
        advice=advice,
        _evaluate=lambda theta_rad: _eval_np(motion, f, theta_rad),
    )


def lever_arm_mm(motion, follower: FollowerSpec, theta) -> np.ndarray:
    """Moment arm (mm) about the pivot of a unit contact force, in the sense of increasing swing.

    theta: cam angle(s), rad. By virtual work the arm is N . dX/dpsi (N the contact normal, X the follower
    point at the contact), so torque [N*m] = force [N] * lever_arm_mm / 1000. For a roller it equals
    arm_length * cos(pressure angle); for a flat face, the contact's distance t along the face.
    """
    if follower.translating:
        raise InputError("follower.type", "a lever arm is defined for oscillating followers only")
    _validate(motion, follower)
    return _eval_np(motion, follower, theta)["lever"]
