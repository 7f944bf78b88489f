"""The two walls of a groove cam: a roller of radius Rr runs in a slot of width 2 Rr + b (b the backlash) cut
along the pitch curve, so each wall lies Rr + b/2 from the pitch curve, on either side along its normal.

The inner wall (towards the cam centre) is the flank a return spring would hold the roller on: the spring cam's
contour moved b/2 inward. The walls are parallel curves of the pitch curve, so they share its normal: at one cam
angle the contact force has one line of action on either flank, and the pressure angle is the pitch curve's (the
roller's centre sits b/2 off the pitch curve when it touches a wall, a difference of order b / Rp). Radii of
curvature are signed as seen by the roller, positive where the wall is convex towards it: the inner wall's is
rho_p - d, the outer wall's -(rho_p + d), with d = Rr + b/2 and rho_p the pitch curve's (convex positive), so one
wall is concave where the other is convex. A wall folds (undercut) where the roller's side of the pitch curve is
convex with a radius below d: kappa_p d >= 1 for the inner wall, -kappa_p d >= 1 for the outer.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..._core.units import THETA_GRID
from ...schema import FollowerSpec
from ._analyze import _grid
from ._kernel import check_assembly, evaluate_geometry, with_breaks

WALLS = ("inner", "outer")
_SIDE = {"inner": -1.0, "outer": 1.0}  # each wall's side of the pitch curve, along its normal


@dataclass(frozen=True)
class Wall:
    """One groove wall's extremes: the least radius of curvature where it is convex towards the roller (mm; inf
    where it never is), where (deg), and whether it folds."""

    min_convex_radius_mm: float
    min_convex_radius_at_deg: float
    undercut: bool

    def json(self) -> dict:
        r = self.min_convex_radius_mm
        return {
            "min_radius_of_curvature_mm": None if np.isinf(r) else r,
            "min_radius_of_curvature_at_deg": None if np.isinf(r) else self.min_convex_radius_at_deg,
            "undercut": self.undercut,
        }


@dataclass(frozen=True)
class GrooveGeometry:
    """Both walls of a groove cam over ``theta_deg`` (n equal steps): outlines (2, n) in the cam frame (mm), their
    signed radii of curvature (mm, convex towards the roller positive), the shared pressure angle (deg) and each
    wall's extremes (taken on the grid and both sides of every break)."""

    backlash_mm: float
    wall_offset_mm: float  # Rr + b/2: each wall's distance from the pitch curve
    theta_deg: np.ndarray
    inner: np.ndarray
    outer: np.ndarray
    rho_inner_mm: np.ndarray
    rho_outer_mm: np.ndarray
    pressure_angle_deg: np.ndarray
    inner_wall: Wall
    outer_wall: Wall
    _evaluate: Callable[[np.ndarray], dict[str, np.ndarray]]

    @property
    def undercut(self) -> bool:
        return self.inner_wall.undercut or self.outer_wall.undercut

    def wall_fn(self, wall: str) -> Callable[[np.ndarray], np.ndarray]:
        """The exact wall ``"inner"`` or ``"outer"`` as a closed curve u in [0, 1] -> (2, m) mm (as
        :meth:`CamGeometry.contour_fn`)."""
        side = _SIDE[wall] * self.wall_offset_mm

        def curve(u):
            ev = self._evaluate(2 * np.pi * np.asarray(u, dtype=float))
            return (ev["pitch"] + side * ev["normal"]).T

        return curve

    def least_circle(self, wall: str) -> tuple[np.ndarray, np.ndarray, float] | None:
        """Where ``wall`` (``"inner"`` or ``"outer"``) is most sharply convex towards the roller: the point on it and
        the centre of its osculating circle there (mm, cam frame), and the signed radius (mm, negative where the wall
        folds); None where it never is. The walls are parallel curves of the pitch curve, so the centre is the pitch
        curve's centre of curvature: inward of the inner wall, outward of the outer (across a fold, the other way)."""
        w = getattr(self, f"{wall}_wall")
        if not np.isfinite(w.min_convex_radius_mm):
            return None
        side = _SIDE[wall]
        ev = self._evaluate(np.deg2rad(np.array([w.min_convex_radius_at_deg])))
        point = ev["pitch"][0] + side * self.wall_offset_mm * ev["normal"][0]
        return point, point + side * w.min_convex_radius_mm * ev["normal"][0], w.min_convex_radius_mm

    def json(self) -> dict:
        return {
            "backlash_mm": self.backlash_mm,
            "wall_offset_mm": self.wall_offset_mm,
            "inner": self.inner_wall.json(),
            "outer": self.outer_wall.json(),
            "undercut": self.undercut,
        }


def _wall(kappa: np.ndarray, deg: np.ndarray, d: float, side: float) -> Wall:
    """``side`` +1 for the inner wall (convex where the pitch curve is), -1 for the outer."""
    k = side * kappa  # the pitch curve's curvature seen from this wall's side
    j = int(np.argmax(k))
    if k[j] <= 0.0:
        return Wall(np.inf, np.nan, False)
    return Wall(float(1.0 / k[j] - d), float(deg[j]), bool(k[j] * d >= 1.0))


def groove(motion, follower: FollowerSpec, *, n: int = THETA_GRID) -> GrooveGeometry:
    """Both walls of the groove that carries ``follower``'s roller (``[follower] backlash``) along the pitch curve.

    Raises :class:`camdyn.InputError` for a follower that cannot be assembled.
    """
    f = follower
    assert f.roller and f.roller_radius is not None  # the schema: a groove holds a roller
    check_assembly(motion, f)
    d = f.roller_radius + 0.5 * f.backlash
    grid = _grid(n)
    th = with_breaks(motion, grid)
    ev = evaluate_geometry(motion, f, th)
    deg = np.rad2deg(th) % 360.0
    kappa = ev["kappa_pitch"]
    pitch, normal = ev["pitch"][:n], ev["normal"][:n]
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / kappa[:n]
    return GrooveGeometry(
        backlash_mm=f.backlash,
        wall_offset_mm=d,
        theta_deg=np.rad2deg(grid),
        inner=(pitch - d * normal).T.copy(),
        outer=(pitch + d * normal).T.copy(),
        rho_inner_mm=rho_p - d,
        rho_outer_mm=-(rho_p + d),
        pressure_angle_deg=np.rad2deg(ev["phi"][:n]),
        inner_wall=_wall(kappa, deg, d, 1.0),
        outer_wall=_wall(kappa, deg, d, -1.0),
        _evaluate=lambda theta_rad: evaluate_geometry(motion, f, theta_rad),
    )
