"""What the optimizer holds the cam to, as JAX functions of the control points (their Jacobians by autodiff):
the steady-state contact force at a set of speeds (the frequency-domain model of ``check``, exact in contact)
over the force margin to keep, the pressure angle and the curvature against the check's limits, and the
control points' order (monotone within [0, 1]: the segment within its lift, never reversing)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.units import newton_per_torque
from ...model.case import Case
from ...model.dynamics import kinematic_force_of, steady_state, train_force
from ...model.geometry import curvature_limit, geometry_of
from ._shape import ShapeSpace
from ._slp import with_jacobian

EVERY = 4  # the linear programs see every 4th grid angle; a fine scan of each answer checks them all
_SAFETY = 1e-4  # the limits are met with this much to spare: the check reads them on another grid
FINE = 400  # speeds of the scan that checks each answer between the programs' speeds
SPEED_SLOTS = 32  # speeds per linear program (a fixed count: one compiled Jacobian per case)


@dataclass(frozen=True)
class Rows:
    """The case's model and limits, bound to a shape space."""

    case: Case
    space: ShapeSpace
    margin: float = 0.0  # the least interface force to keep at every speed held (N; N*m for an arm)
    # a valvetrain's event (:func:`camdyn.model.valvetrain.event_follower`): the case's model is the valve side, and
    # the cam's force adds the cam side's inertia (kg, moving with the cam) and the tappet force (N)
    cam_mass: float = 0.0
    cam_load: float = 0.0
    # and the valve's closing speed held: (cam speed rad/s, ratio, grid angles around its seating, the most m/s)
    seating: tuple[float, float, np.ndarray, float] | None = None

    @property
    def scale(self) -> float:
        """The size of the forces (N; N*m for an arm): the static preload."""
        return max(abs(float(self.case.model.preload)), abs(self.margin), 1e-3)

    def forces(self, z: np.ndarray | jax.Array, omegas: jax.Array, preload: ArrayLike | None = None) -> jax.Array:
        """Interface force (N; N*m for an arm) at each speed (rad/s) and grid angle: (len(omegas), n). ``preload``
        (SI) overrides the case's, traceably (the spring-force objective frees it)."""
        case, space = self.case, self.space
        model = case.model if preload is None else eqx.tree_at(lambda m: m.preload, case.model, preload)
        sv = space.values(z)
        s, s1, s2 = sv[0] * model.scale, sv[1] * model.scale, sv[2] * model.scale
        omegas = jnp.asarray(omegas, dtype=float)
        if model.rigid:
            force = kinematic_force_of(model, omegas[:, None], s, s1, s2)
        else:
            spec = jnp.fft.rfft(s)
            n = s.shape[0]

            def one(w: float | jax.Array) -> jax.Array:
                x, x1 = steady_state(spec, w, model, model.stiffness, model.damping, n)
                return train_force(model, w, s, s1, x, x1)

            force = jax.vmap(one)(omegas)
        if self.cam_mass or self.cam_load:
            force = force + self.cam_mass * omegas[:, None] ** 2 * s2 + self.cam_load
        return force

    def slack(self, z: np.ndarray | jax.Array, omegas: jax.Array, preload: ArrayLike | None = None) -> jax.Array:
        """:meth:`forces` over the least to keep (N; N*m for an arm): >= 0 where both the margin and the check's
        ``min_contact_force`` (N at the contact; through the lever arm, which moves with s, for an arm) hold."""
        fmin = float(self.case.limits.min_contact_force)
        need = max(self.margin, fmin)
        if self.case.kind.rotary:  # the least contact force through the lever arm, which moves with s
            lever = geometry_of(self.case.follower, jnp.asarray(self.space.theta), self.space.values(z))["lever"]
            need = jnp.maximum(self.margin, fmin / newton_per_torque(lever))
        return self.forces(z, omegas, preload) - need

    def geometry(self, z: np.ndarray | jax.Array) -> jax.Array:
        """The geometry constraints as ``g <= 0``, each scaled to its limit: |phi| / phi_max - 1 and, for a roller,
        kappa / kappa_max - 1 (the check's least contour radius over the roller radius), for a flat face
        1 - rho / rho_min."""
        f, lim = self.case.follower, self.case.limits
        geo = geometry_of(f, jnp.asarray(self.space.theta), self.space.values(z))
        phi_max = math.radians(lim.max_pressure_angle or f.kind.default_max_pressure_angle_deg)
        rows = [jnp.abs(geo["phi"]) / phi_max - 1.0 + _SAFETY]
        if f.roller_radius is not None:  # a roller follower
            kappa_max = 1.0 / (f.roller_radius * (1.0 + curvature_limit(f, lim.min_curvature_ratio)))
            rows.append(geo["kappa_pitch"] / kappa_max - 1.0 + _SAFETY)
        else:
            assert f.base_radius is not None  # a built case's follower has it
            rho_min = max(curvature_limit(f, lim.min_curvature_ratio), 1e-3 * f.base_radius)
            rows.append(1.0 - geo["rho_contour"] / rho_min + _SAFETY)
        rows.append(self.space.order(z))
        if self.seating is not None:
            rows.append(self.closing_speed(z) / self.seating[3] - 1.0)
        return jnp.concatenate(rows)

    def closing_speed(self, z: np.ndarray | jax.Array) -> jax.Array:
        """A valvetrain's valve speed toward its seat (m/s, the surrogate's steady state at ``seating``'s speed) at
        ``seating``'s grid angles: where the valve lands on its seat, what its seating velocity follows."""
        assert self.seating is not None  # a valvetrain's rows
        omega, ratio, idx, _ = self.seating
        model = self.case.model
        s = self.space.values(z)[0] * model.scale
        _, x1 = steady_state(jnp.fft.rfft(s), omega, model, model.stiffness, model.damping, s.shape[0])
        return -ratio * omega * x1[idx]

    @cached_property
    def sampled(self) -> np.ndarray:
        """The grid angles the linear programs see."""
        return np.arange(0, self.space.theta.size, EVERY)

    @cached_property
    def force_jacobian(self) -> Callable[..., tuple[jax.Array, jax.Array]]:
        """``(z, speeds[SPEED_SLOTS], preload) -> (slack at the sampled angles, d/dz)``, compiled once."""
        return with_jacobian(lambda z, speeds, preload: self.slack(z, speeds, preload)[:, self.sampled].ravel())

    def force_values(
        self, speeds: jax.Array
    ) -> Callable[[np.ndarray], tuple[np.ndarray | jax.Array, np.ndarray | jax.Array]]:
        """``z -> (slack at the sampled angles, d/dz)`` at the fixed ``speeds`` (:data:`SPEED_SLOTS`) for the linear
        programs. Where the follower translates the slack is exactly affine in ``z`` (the steady state in contact is
        linear in the motion, the motion in the control points), so the Jacobian is computed once and every later
        value is one product; an arm's lever arm moves with ``z``, so there each call differentiates again."""
        if self.case.oscillating:
            return lambda z: self.force_jacobian(z, speeds, None)
        z_ref = np.asarray(self.space.z0, dtype=float)
        v_ref, jac = (np.asarray(a) for a in self.force_jacobian(jnp.asarray(z_ref), speeds, None))
        return lambda z: (v_ref + np.einsum("ij,j->i", jac, np.asarray(z, dtype=float) - z_ref), jac)

    @cached_property
    def least_on_scan(self) -> Callable[..., jax.Array]:
        """``(z, w_max, preload) -> the least slack at each of FINE speeds up to w_max``, compiled once."""
        return jax.jit(
            lambda z, w, preload=None: self.slack(z, w * jnp.arange(1, FINE + 1) / FINE, preload).min(axis=1)
        )

    @cached_property
    def geometry_jacobian(self) -> Callable[..., tuple[jax.Array, jax.Array]]:
        return with_jacobian(self.geometry)


def speed_slots(speeds: ArrayLike) -> np.ndarray:
    """``speeds`` padded to :data:`SPEED_SLOTS` by repeating the last (a repeated row changes no linear program)."""
    speeds = np.asarray(speeds, dtype=float)[-SPEED_SLOTS:]
    return np.r_[speeds, np.full(SPEED_SLOTS - speeds.size, speeds[-1])]
