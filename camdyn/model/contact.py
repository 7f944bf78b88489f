"""Hertz line contact between the cam and its follower: the contact half-width and the peak pressure per angle.

Two elastic cylinders with parallel axes (or a cylinder on a plane) pressed together by a force F over a width
L touch on a strip of half-width b with a semi-elliptical pressure (Hertz; Shigley eqs. 3-73, 3-74; Johnson,
Contact Mechanics, section 4.3):

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,      K = 1/R1 + 1/R2 (signed curvatures, convex positive)
    b = sqrt(4 F / (pi L E* K)),                  p_max = 2 F / (pi b L) = sqrt(F E* K / (pi L))

A concave surface has a negative radius; a plane has none (curvature 0). K must be positive where the bodies
touch: K <= 0 means a roller that does not fit the hollow, i.e. an undercut contour, which is refused.

On the cam: a roller of radius Rr against a contour whose pitch curve has signed curvature kappa (convex
positive) touches with ``1/K = Rr (1 - Rr kappa)``, the same as 1/Rr + 1/rho_contour with
rho_contour = 1/kappa - Rr but finite where the contour is straight; a flat face is a plane against the contour
radius rho. The normal force is the interface force over cos(pressure angle) for a translating follower
(camdyn's force acts along the follower's axis) and the contact force itself for an oscillating arm (camdyn
check reports the arm torque through the lever arm of the contact normal).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from jax.typing import ArrayLike

from .._core.errors import InputError, NumericalError
from .._core.materials import GPA, MPA
from .._core.units import CUSP_MM, M_PER_MM
from .geometry import CamGeometry, ConjugateGeometry, GrooveGeometry


def effective_modulus(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """The contact modulus E* (same unit as E1, E2): ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``."""
    return 1.0 / ((1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2)


def line_contact(force: ArrayLike, curvature: ArrayLike, width: float, e_star: float) -> tuple[np.ndarray, np.ndarray]:
    """Half-width b (m) and peak pressure p_max (Pa) of a Hertz line contact (SI in, SI out; arrays broadcast).

    ``force`` N (no contact where <= 0: b = p = 0), ``curvature`` K = 1/R1 + 1/R2 in 1/m (must be > 0 where
    the force is), ``width`` L in m, ``e_star`` Pa (:func:`effective_modulus`).
    """
    force, curvature = np.broadcast_arrays(np.asarray(force, dtype=float), np.asarray(curvature, dtype=float))
    touching = force > 0.0
    if np.any(touching & ~(curvature > 0.0)):
        raise NumericalError(
            "contact",
            "the curvature sum 1/R1 + 1/R2 is not positive where the bodies touch (a roller larger than the hollow "
            "it runs in)",
        )
    f = np.where(touching, force, 0.0)
    k = np.where(touching, curvature, 1.0)
    b = np.sqrt(4.0 * f / (math.pi * width * e_star * k))
    p = np.sqrt(f * e_star * k / (math.pi * width))
    return b, p


def cylinders(
    force: ArrayLike, radius1: ArrayLike, radius2: ArrayLike, width: float, e_star: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`line_contact` of two cylinders of signed radii (m; negative: concave; ``math.inf``: a plane)."""
    return line_contact(
        force, 1.0 / np.asarray(radius1, dtype=float) + 1.0 / np.asarray(radius2, dtype=float), width, e_star
    )


@dataclass(frozen=True)
class ContactStress:
    """The Hertz contact between cam and follower over a revolution (arrays over ``theta_deg``)."""

    theta_deg: np.ndarray
    normal_force_N: np.ndarray
    equivalent_radius_mm: np.ndarray  # 1/K: the cylinder on a plane that touches like the two bodies
    half_width_mm: np.ndarray
    pressure_MPa: np.ndarray  # peak (centre) pressure of the strip at each angle
    width_mm: float
    e_star_GPa: float

    @property
    def peak_pressure_MPa(self) -> float:
        return float(np.max(self.pressure_MPa))

    @property
    def peak_at_deg(self) -> float:
        return float(self.theta_deg[int(np.argmax(self.pressure_MPa))])

    def json(self) -> dict:
        i = int(np.argmax(self.pressure_MPa))
        return {
            "max_contact_stress_MPa": self.peak_pressure_MPa,
            "max_contact_stress_at_deg": self.peak_at_deg,
            "half_width_at_max_mm": float(self.half_width_mm[i]),
            "normal_force_at_max_N": float(self.normal_force_N[i]),
            "equivalent_radius_at_max_mm": float(self.equivalent_radius_mm[i]),
            "contact_width_mm": self.width_mm,
            "effective_modulus_GPa": self.e_star_GPa,
        }


def _undercut(theta_deg, bad) -> NumericalError:
    at = float(np.asarray(theta_deg)[np.argmax(bad)])
    return NumericalError(
        f"theta = {at:.4g} deg",
        "the contour is undercut (a cusp): the follower cannot touch it there, so no Hertz contact stress",
    )


def equivalent_curvature_per_mm(geometry: CamGeometry) -> np.ndarray:
    """K = 1/R1 + 1/R2 of cam and follower per angle, 1/mm; :class:`NumericalError` where the contour is undercut."""
    f = geometry.follower
    if f.roller_radius is not None:  # a roller follower (the schema: roller_radius is a roller's only)
        rr = f.roller_radius
        kappa = 1.0 / geometry.rho_pitch_mm  # 0 where the pitch curve is straight (rho = inf)
        bad = rr * kappa >= 1.0
        if bad.any():
            raise _undercut(geometry.theta_deg, bad)
        return 1.0 / (rr * (1.0 - rr * kappa))
    rho = geometry.rho_contour_mm
    bad = rho < CUSP_MM
    if bad.any():
        raise _undercut(geometry.theta_deg, bad)
    return 1.0 / rho


def normal_force(geometry: CamGeometry, force: ArrayLike) -> np.ndarray:
    """The normal contact force (N) from the force camdyn check reports per angle of ``geometry``: a translating
    follower's axial force over cos(pressure angle); an oscillating arm's contact force as it is."""
    force = np.asarray(force, dtype=float)
    if geometry.follower.kind.rotary:  # the response's force is already the contact force
        return force
    return force / np.cos(np.deg2rad(geometry.pressure_angle_deg))


def cam_contact(
    geometry: CamGeometry, force: ArrayLike, *, width_mm: float, cam: tuple[float, float], follower: tuple[float, float]
) -> ContactStress:
    """Hertz contact stress over a revolution.

    ``force``: the interface force (N) on ``geometry.theta_deg``, as ``camdyn check`` reports it (the
    response's force: axial for a translating follower, the contact force for an oscillating arm);
    ``width_mm`` the contact width along the camshaft; ``cam`` and ``follower`` their (E GPa, nu).
    """
    force = _forces(geometry, force, width_mm)
    return _strip(
        geometry.theta_deg,
        normal_force(geometry, force),
        equivalent_curvature_per_mm(geometry),
        width_mm,
        cam,
        follower,
    )


def groove_contact(
    geometry: CamGeometry,
    walls: GrooveGeometry,
    force: ArrayLike,
    *,
    width_mm: float,
    cam: tuple[float, float],
    follower: tuple[float, float],
) -> ContactStress:
    """:func:`cam_contact` of a groove cam: the roller on the inner wall where the signed ``force`` is positive, on
    the outer where negative, K = 1/Rr + 1/rho_wall with the wall's radius seen from the roller (the outer wall is
    concave where the inner one is convex: a conformal, gentler contact). ``geometry`` and ``walls`` on one grid."""
    force = _forces(geometry, force, width_mm)
    rr = geometry.follower.roller_radius
    assert rr is not None  # the schema: a groove holds a roller
    inner = force >= 0.0
    with np.errstate(divide="ignore"):
        k_mm = 1.0 / rr + 1.0 / np.where(inner, walls.rho_inner_mm, walls.rho_outer_mm)
    folded = (walls.inner_wall.undercut and np.any(inner)) or (walls.outer_wall.undercut and not np.all(inner))
    if folded or np.any(k_mm <= 0.0):
        raise _undercut(geometry.theta_deg, k_mm <= 0.0)
    return _strip(geometry.theta_deg, np.abs(normal_force(geometry, force)), k_mm, width_mm, cam, follower)


def conjugate_contact(
    geometry: CamGeometry,
    second: ConjugateGeometry,
    primary_N: ArrayLike,
    conjugate_N: ArrayLike,
    *,
    width_mm: float,
    cam: tuple[float, float],
    follower: tuple[float, float],
) -> ContactStress:
    """:func:`cam_contact` of conjugate cams: each roller on its own cam with its own force (N, as ``camdyn check``
    reports them: axial for a yoke, at the contact for a rocker; both loaded under a preload), and at each angle
    the more stressed contact. The conjugate contact: K = 1/Rr2 + 1/rho (rho its contour's signed radius), the
    force over cos of its pressure angle on a yoke. ``geometry`` and ``second`` on one grid."""
    primary = cam_contact(
        geometry, np.abs(_forces(geometry, primary_N, width_mm)), width_mm=width_mm, cam=cam, follower=follower
    )
    f2 = np.abs(_forces(geometry, conjugate_N, width_mm))
    if not geometry.follower.kind.rotary:
        f2 = f2 / np.cos(np.deg2rad(second.pressure_angle_deg))
    with np.errstate(divide="ignore"):
        k_mm = 1.0 / second.roller_radius_mm + 1.0 / second.rho_contour_mm
    if second.undercut or np.any(k_mm <= 0.0):
        raise _undercut(geometry.theta_deg, k_mm <= 0.0)
    other = _strip(geometry.theta_deg, f2, k_mm, width_mm, cam, follower)
    on_second = other.pressure_MPa > primary.pressure_MPa
    pick = lambda a, b: np.where(on_second, b, a)  # noqa: E731
    return ContactStress(
        geometry.theta_deg,
        pick(primary.normal_force_N, other.normal_force_N),
        pick(primary.equivalent_radius_mm, other.equivalent_radius_mm),
        pick(primary.half_width_mm, other.half_width_mm),
        pick(primary.pressure_MPa, other.pressure_MPa),
        primary.width_mm,
        primary.e_star_GPa,
    )


def _forces(geometry: CamGeometry, force, width_mm: float) -> np.ndarray:
    if not (width_mm > 0 and math.isfinite(width_mm)):
        raise InputError("follower.width", f"the contact width must be positive, mm (got {width_mm})")
    force = np.asarray(force, dtype=float)
    if force.shape != geometry.theta_deg.shape:
        raise InputError("force", f"{force.size} forces for {geometry.theta_deg.size} cam angles")
    return force


def _strip(theta_deg, fn, k_mm, width_mm: float, cam, follower) -> ContactStress:
    """The Hertz strip of normal force ``fn`` (N) at equivalent curvature ``k_mm`` (1/mm) per angle."""
    e_star = effective_modulus(cam[0] * GPA, cam[1], follower[0] * GPA, follower[1])
    b, p = line_contact(fn, k_mm / M_PER_MM, width_mm * M_PER_MM, e_star)
    return ContactStress(theta_deg, fn, 1.0 / k_mm, b / M_PER_MM, p / MPA, float(width_mm), e_star / GPA)
