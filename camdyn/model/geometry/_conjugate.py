"""The conjugate cam of a form-closed pair: a second cam on the shaft and a second roller on the same follower (a
yoke for a translating follower, a two-arm rocker for an oscillating one) that hold it the other way.

The primary cam is the spring cam of ``[motion]`` and ``[follower]``. The second roller is rigidly tied to the
first: on a yoke its centre is E2 = E1 + (sigma c, -D) (D ``conjugate_spacing`` along the axis, c
``conjugate_offset`` across, signed as ``offset``), on a rocker E2 = P + (a2 / a) R(beta) (E1 - P) (P the pivot, a2
``conjugate_arm_length``, beta ``conjugate_arm_angle`` ccw). The conjugate cam's pitch curve is E2 seen in the cam
frame as the follower runs its motion: exact, by the same autodiff of the motion's Taylor polynomial as the primary
(:func:`._kernel.roller_point`), so both rollers touch their cams at every angle with the follower rigid. Its
contour lies ``conjugate_roller_radius`` + ``backlash`` inside the pitch curve (the backlash a clearance along the
normal while the first roller sits on the primary cam).

The conjugate cam drives the follower back (towards decreasing lift or swing): its pressure angle is taken from
that direction to its contact normal, and its ``lever`` (mm per motion unit: the roller centre's speed along the
normal, cos of the pressure angle on a yoke, a2 times it on a rocker) is positive where it can. Radii of curvature
are signed as the primary's (convex positive).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import InputError
from ..._core.jit import cached_jit
from ..._core.kinds import FollowerType
from ..._core.units import THETA_GRID
from ...schema import FollowerSpec
from ._analyze import _grid, geometry_columns
from ._groove import Wall, _wall
from ._kernel import _pivot, _roller_centre, _rot, check_assembly, chunked, follower_params, roller_point, with_breaks

if TYPE_CHECKING:
    from ..motion import Motion


def _second_centre(ftype: FollowerType, p, q):
    """The second roller's centre in the fixed frame at follower coordinate q; p = the primary's parameters and
    (contour offset, spacing, offset across, second arm length, arm angle rad)."""
    e1 = _roller_centre(ftype, p[:7], q)
    if not ftype.kind.rotary:
        return e1 + jnp.stack([p[6] * p[9], -p[8]])
    pivot, _ = _pivot(p[:7])
    return pivot + (p[10] / p[5]) * _rot(p[11], e1 - pivot)


@cached_jit
def _conjugate_geometry(p, theta, sv, ftype: FollowerType):
    return jax.vmap(
        lambda th, s: roller_point(lambda q: _second_centre(ftype, p, q), p[6], p[7], th, s, -1.0), in_axes=(0, 1)
    )(theta, sv)


def _conjugate_params(f: FollowerSpec) -> np.ndarray:
    rr2 = f.conjugate_roller_radius or f.roller_radius or 0.0
    second = [
        rr2 + f.backlash,
        f.conjugate_spacing or 0.0,
        f.conjugate_offset,
        f.conjugate_arm_length or f.arm_length or 0.0,
        math.radians(f.conjugate_arm_angle or 0.0),
    ]
    return np.concatenate([follower_params(f), second])


def evaluate_conjugate(motion: Motion, f: FollowerSpec, theta_rad: ArrayLike) -> dict[str, np.ndarray]:
    """The conjugate cam at cam angles ``theta_rad`` (rad): as :func:`evaluate_geometry` (``pitch``, ``contour``,
    ``normal``, ``kappa_pitch`` 1/mm, ``rho_contour`` mm, ``phi`` rad, ``lever`` mm per motion unit, ``s``)."""
    p = _conjugate_params(f)
    return chunked(motion, theta_rad, lambda theta, sv: _conjugate_geometry(p, theta, sv, f.follower_type))


@dataclass(frozen=True)
class ConjugateGeometry:
    """The conjugate cam over ``theta_deg`` (n equal steps): pitch curve and contour (2, n) in the cam frame (mm),
    pressure angle (deg, from the direction it drives the follower), signed radii of curvature (mm, convex
    positive), and its extremes taken on the grid and both sides of every break."""

    roller_radius_mm: float  # the second roller's
    backlash_mm: float
    preload: float  # between the rollers, the motion's force unit (N, or N*m about the pivot)
    theta_deg: np.ndarray
    pitch: np.ndarray
    contour: np.ndarray
    pressure_angle_deg: np.ndarray
    rho_pitch_mm: np.ndarray
    rho_contour_mm: np.ndarray
    max_pressure_angle_deg: float
    max_pressure_angle_at_deg: float
    convex: Wall  # the least convex contour radius, where, and whether the contour folds
    min_contour_radius_mm: float  # the contour's least distance from the cam centre (room for the hub)
    _evaluate: Callable[[np.ndarray], dict[str, np.ndarray]]

    @property
    def undercut(self) -> bool:
        return self.convex.undercut

    @property
    def curvature(self) -> float | None:
        """Least convex contour radius over the second roller's radius (None: nowhere convex)."""
        r = self.convex.min_convex_radius_mm
        return None if math.isinf(r) else r / self.roller_radius_mm

    def table(self, theta_deg: ArrayLike) -> dict[str, np.ndarray]:
        """``table``'s columns of the conjugate cam at cam angles (deg): the primary's geometry columns
        (:meth:`CamGeometry.table`) prefixed ``conjugate_``."""
        ev = self._evaluate(np.deg2rad(np.asarray(theta_deg, dtype=float)))
        return {f"conjugate_{k}": v for k, v in geometry_columns(ev).items()}

    def contour_fn(self) -> Callable[[np.ndarray], np.ndarray]:
        """The exact contour as a closed curve u in [0, 1] -> (2, m) mm (as :meth:`CamGeometry.contour_fn`)."""
        return lambda u: self._evaluate(2 * np.pi * np.asarray(u, dtype=float))["contour"].T

    def json(self) -> dict:
        return {
            "roller_radius_mm": self.roller_radius_mm,
            "max_pressure_angle_deg": self.max_pressure_angle_deg,
            "max_pressure_angle_at_deg": self.max_pressure_angle_at_deg,
            **self.convex.json(),
            "min_contour_radius_mm": self.min_contour_radius_mm,
        }


def _position_key(f: FollowerSpec) -> str:
    return "follower.conjugate_spacing" if f.translating else "follower.conjugate_arm_angle"


def conjugate(motion: Motion, follower: FollowerSpec, *, n: int = THETA_GRID) -> ConjugateGeometry:
    """The conjugate cam that keeps ``follower``'s second roller in contact while the first follows the primary.

    Raises :class:`camdyn.InputError` for a follower that cannot be assembled, a second roller the conjugate cam
    cannot drive back (on the same side of the camshaft as the first), or a contour that reaches the cam centre.
    """
    f = follower
    assert f.closure == "conjugate" and f.roller_radius is not None  # the schema: two rollers
    check_assembly(motion, f)
    rr2 = f.conjugate_roller_radius or f.roller_radius
    grid = _grid(n)
    th = with_breaks(motion, grid)
    ev = evaluate_conjugate(motion, f, th)
    deg = np.rad2deg(th) % 360.0
    if not np.all(np.isfinite(ev["contour"])) or np.min(ev["lever"]) <= 0.0:
        bad = ~np.isfinite(ev["lever"]) | (ev["lever"] <= 0.0) | ~np.all(np.isfinite(ev["contour"]), axis=-1)
        raise InputError(
            _position_key(f),
            f"the conjugate cam cannot drive the follower back at {deg[np.argmax(bad)]:.1f} deg: put the second "
            "roller across the camshaft from the first",
        )
    radius = np.hypot(*ev["pitch"].T)
    if np.min(radius) <= rr2 + f.backlash:
        raise InputError(
            _position_key(f),
            f"the conjugate cam's contour reaches the cam centre at {deg[np.argmin(radius)]:.1f} deg (pitch radius "
            f"{np.min(radius):.4g} mm, second roller {rr2:g} mm): move the second roller further out",
        )
    phi = np.abs(np.rad2deg(ev["phi"]))
    i = int(np.argmax(phi))
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / ev["kappa_pitch"][:n]
    return ConjugateGeometry(
        roller_radius_mm=float(rr2),
        backlash_mm=f.backlash,
        preload=f.pair_preload,
        theta_deg=np.rad2deg(grid),
        pitch=ev["pitch"][:n].T.copy(),
        contour=ev["contour"][:n].T.copy(),
        pressure_angle_deg=np.rad2deg(ev["phi"][:n]),
        rho_pitch_mm=rho_p,
        rho_contour_mm=ev["rho_contour"][:n],
        max_pressure_angle_deg=float(phi[i]),
        max_pressure_angle_at_deg=float(deg[i]),
        convex=_wall(ev["kappa_pitch"], deg, rr2 + f.backlash, 1.0),
        min_contour_radius_mm=float(np.min(np.hypot(*ev["contour"].T))),
        _evaluate=lambda theta_rad: evaluate_conjugate(motion, f, theta_rad),
    )


def conjugate_lever_mm(motion: Motion, follower: FollowerSpec, theta_rad: ArrayLike) -> np.ndarray:
    """The conjugate cam's lever at cam angles ``theta_rad`` (rad): mm of its normal per motion unit (positive)."""
    return evaluate_conjugate(motion, follower, theta_rad)["lever"]
