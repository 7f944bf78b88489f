"""The cam of one case: pitch curve, contour, pressure angle, curvature and their extremes over a revolution."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING

import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import InputError, NumericalError
from ..._core.units import CUSP_MM, THETA_GRID, newton_per_torque
from ...schema import FollowerSpec
from ._kernel import MotionSamples, check_assembly, evaluate_geometry, geometry_on, sample_motion, with_breaks

if TYPE_CHECKING:
    from ..motion import Motion


@dataclass(frozen=True)
class GeometryExtremes:
    """The extremes over a revolution that the checks judge (angles deg in [0, 360))."""

    max_pressure_angle_deg: float  # largest |pressure angle|
    max_pressure_angle_at_deg: float
    min_radius_of_curvature_mm: float  # least convex contour radius (roller) or least contour radius (flat), signed
    min_radius_of_curvature_at_deg: float
    cusp: bool  # the contour folds (undercut)
    face_range_mm: tuple[float, float] | None  # flat faces: the contact's travel along the face (t_min, t_max)
    roller_radius_mm: float | None
    lift_range: float  # largest minus least follower displacement, the motion's unit (mm or rad)

    @property
    def curvature(self) -> float:
        """What the curvature check judges: least radius / roller radius for a roller, the least radius (mm)
        for a flat face (which must stay above :data:`camdyn._core.units.CUSP_MM`)."""
        r = self.min_radius_of_curvature_mm
        return r / self.roller_radius_mm if self.roller_radius_mm is not None else r

    @property
    def face_travel_mm(self) -> float | None:
        return None if self.face_range_mm is None else self.face_range_mm[1] - self.face_range_mm[0]

    @property
    def face_centre_mm(self) -> float | None:
        """Where a flat face of the least width (:attr:`face_travel_mm`) is centred, t from the follower's axis
        (or the pivot's foot): the face_width check takes the face there, and the drawings put it there."""
        return None if self.face_range_mm is None else 0.5 * (self.face_range_mm[0] + self.face_range_mm[1])


def _grid(n: int) -> np.ndarray:
    if n < 16:
        raise InputError("n", f"need at least 16 samples per revolution, got {n}")
    return np.deg2rad(np.arange(n) * (360.0 / n))


def _extremes(f: FollowerSpec, theta_rad: np.ndarray, ev: dict[str, np.ndarray]) -> GeometryExtremes:
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
        face = None
    else:
        rho_all = ev["rho_contour"]
        j = int(np.argmin(rho_all))
        rho = float(rho_all[j])
        cusp = rho < CUSP_MM
        face = (float(np.min(ev["face_t"])), float(np.max(ev["face_t"])))
    rr = f.roller_radius if f.roller else None
    return GeometryExtremes(
        float(phi[i]), float(deg[i]), float(rho), float(deg[j]), cusp, face, rr, float(np.ptp(ev["s"]))
    )


def extremes(
    motion: Motion, follower: FollowerSpec, *, base_radius: float | None = None, n: int = THETA_GRID
) -> GeometryExtremes:
    """The geometry's extremes on n equal steps plus both sides of every break, with the follower's own base
    radius or ``base_radius`` (mm; the base-circle search varies it without rebuilding the follower)."""
    return extremes_on(extremes_samples(motion, n), follower, base_radius)


def extremes_on(samples: MotionSamples, follower: FollowerSpec, base_radius: float | None = None) -> GeometryExtremes:
    """:func:`extremes` on the motion already sampled at their angles (:func:`extremes_samples`): once for the many
    base radii of the base-circle search."""
    return _extremes(follower, samples.theta, geometry_on(samples, follower, base_radius))


def extremes_samples(motion: Motion, n: int = THETA_GRID) -> MotionSamples:
    """The motion on the angles :func:`extremes` judges (n equal steps plus both sides of every break)."""
    return sample_motion(motion, with_breaks(motion, _grid(n)))


def geometry_columns(ev: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``table``'s geometry columns of an evaluated cam (:func:`evaluate_geometry`'s dict): pressure angle (deg),
    radii of curvature and the pitch curve and contour in the cam frame (mm)."""
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / ev["kappa_pitch"]
    return {
        "pressure_angle_deg": np.rad2deg(ev["phi"]),
        "rho_pitch_mm": rho_p,
        "rho_contour_mm": ev["rho_contour"],
        "pitch_x_mm": ev["pitch"][..., 0],
        "pitch_y_mm": ev["pitch"][..., 1],
        "contour_x_mm": ev["contour"][..., 0],
        "contour_y_mm": ev["contour"][..., 1],
    }


@dataclass(frozen=True)
class CamGeometry(GeometryExtremes):
    """The cam of one case: its extremes (as :class:`GeometryExtremes`) and, over ``theta_deg`` (n equal steps of
    one revolution), its curves.

    ``pitch`` and ``contour`` (2, n) are in the cam frame, mm (for flat followers ``pitch`` is the face's
    reference point, and ``rho_pitch_mm`` is NaN: a flat face has no pitch curve). Radii are signed, convex
    positive. The extremes are taken on the grid plus both sides of every break.
    """

    follower: FollowerSpec
    theta_deg: np.ndarray
    pitch: np.ndarray
    contour: np.ndarray
    pressure_angle_deg: np.ndarray
    rho_pitch_mm: np.ndarray
    rho_contour_mm: np.ndarray
    face_t_mm: np.ndarray
    _evaluate: Callable[[np.ndarray], dict[str, np.ndarray]] = field(repr=False, compare=False)

    @property
    def undercut(self) -> bool:
        return self.cusp

    @property
    def extremes(self) -> GeometryExtremes:
        return GeometryExtremes(**{f.name: getattr(self, f.name) for f in fields(GeometryExtremes)})

    @property
    def min_face_width_mm(self) -> float | None:
        return self.face_travel_mm

    def json(self) -> dict:
        out = {
            "max_pressure_angle_deg": self.max_pressure_angle_deg,
            "max_pressure_angle_at_deg": self.max_pressure_angle_at_deg,
            "min_radius_of_curvature_mm": self.min_radius_of_curvature_mm,
            "min_radius_of_curvature_at_deg": self.min_radius_of_curvature_at_deg,
            "undercut": self.undercut,
            "cusp": self.cusp,
        }
        if self.face_range_mm is not None:
            out["min_face_width_mm"] = self.min_face_width_mm
            out["face_range_mm"] = list(self.face_range_mm)
            out["face_centre_mm"] = self.face_centre_mm
        return out

    def table(self, theta_deg: ArrayLike) -> dict[str, np.ndarray]:
        """Geometry columns at arbitrary cam angles (deg); see :mod:`camdyn.model.geometry` for signs.

        Flat followers add ``face_t_mm``, the contact's position along the face.
        """
        ev = self._evaluate(np.deg2rad(np.asarray(theta_deg, dtype=float)))
        cols = geometry_columns(ev)
        if not self.follower.roller:
            cols["face_t_mm"] = ev["face_t"]
        return cols

    def contour_fn(self) -> Callable[[np.ndarray], np.ndarray]:
        """The exact contour as a closed curve u in [0, 1] -> (2, m) mm, for :func:`camdyn.export.write_profile`."""
        return lambda u: self._evaluate(2 * np.pi * np.asarray(u, dtype=float))["contour"].T

    def offset_fn(self, distance_mm: float) -> Callable[[np.ndarray], np.ndarray]:
        """The curve ``distance_mm`` outward from the contour along its normal (a cutter's or a grinding wheel's
        centre), as u in [0, 1] -> (2, m) mm like :meth:`contour_fn`; a true offset only where the contour's
        concave radii exceed the distance."""

        def curve(u: ArrayLike) -> np.ndarray:
            ev = self._evaluate(2 * np.pi * np.asarray(u, dtype=float))
            return (ev["contour"] + distance_mm * ev["normal"]).T

        return curve


def analyze(motion: Motion, follower: FollowerSpec, *, n: int = THETA_GRID) -> CamGeometry:
    """Pitch curve, contour, pressure angle and curvature of a cam on n equal steps, and their extremes.

    Raises :class:`InputError` for a follower that cannot be assembled, :class:`NumericalError` for a
    degenerate contour.
    """
    f = follower
    check_assembly(motion, f)
    grid = _grid(n)
    th = with_breaks(motion, grid)
    ev_all = evaluate_geometry(motion, f, th)
    ext = _extremes(f, th, ev_all)
    ev = {k: v[:n] for k, v in ev_all.items()}
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / ev["kappa_pitch"]
    return CamGeometry(
        **vars(ext),
        follower=f,
        theta_deg=np.rad2deg(grid),
        pitch=ev["pitch"].T.copy(),
        contour=ev["contour"].T.copy(),
        pressure_angle_deg=np.rad2deg(ev["phi"]),
        rho_pitch_mm=rho_p,
        rho_contour_mm=ev["rho_contour"],
        face_t_mm=ev["face_t"],
        _evaluate=lambda theta_rad: evaluate_geometry(motion, f, theta_rad),
    )


def lever_arm_mm(motion: Motion, follower: FollowerSpec, theta: ArrayLike) -> np.ndarray:
    """Moment arm (mm) about the pivot of a unit contact force, in the sense of increasing swing.

    theta: cam angle(s), rad. By virtual work the arm is N . dX/dpsi (N the contact normal, X the follower
    point at the contact), so torque [N*m] = force [N] * lever_arm_mm / 1000. For a roller it equals
    arm_length * cos(pressure angle); for a flat face, the contact's distance t along the face.
    """
    if follower.translating:
        raise InputError("follower.type", "a lever arm is defined for oscillating followers only")
    check_assembly(motion, follower)
    return evaluate_geometry(motion, follower, theta)["lever"]


def contact_per_force(motion: Motion, follower: FollowerSpec | None, theta: ArrayLike) -> np.ndarray:
    """The contact force (N) per unit of the force the follower's dynamics carry, at cam angles ``theta`` (rad):
    1 for a translating follower (camdyn reports its axial force), :func:`newton_per_torque_at` for an arm."""
    if not motion.kind.rotary:
        return np.ones(np.shape(theta))
    if follower is None:
        raise InputError("follower", "an arm's contact force needs its geometry (the lever arm)")
    return newton_per_torque_at(motion, follower, theta)


def newton_per_torque_at(motion: Motion, follower: FollowerSpec, theta: ArrayLike) -> np.ndarray:
    """The factor (1/m) turning an arm's torque (N*m) into its contact force (N) at cam angles ``theta`` (rad):
    1 / lever arm. :class:`NumericalError` where the contact normal passes through the pivot (no lever arm)."""
    arm_mm = np.asarray(lever_arm_mm(motion, follower, theta))
    if np.any(arm_mm <= 1e-6):
        at = math.degrees(float(np.atleast_1d(theta)[int(np.argmin(arm_mm))])) % 360.0
        raise NumericalError(
            f"follower at {at:.1f} deg",
            "the contact normal passes through the arm pivot: no lever arm to carry the load",
        )
    return newton_per_torque(arm_mm)
