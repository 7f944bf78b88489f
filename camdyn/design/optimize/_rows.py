"""What the optimizer holds the cam to, as JAX functions of the control points (their Jacobians by autodiff):
the steady-state contact force at a set of speeds (the frequency-domain model of ``check``, exact in contact)
over the force margin to keep, the pressure angle and the curvature against the check's limits, and the
control points' order (monotone within [0, 1]: the segment within its lift, never reversing)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import TypeVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import cached_jit
from ..._core.kinds import FollowerType
from ..._core.units import newton_per_torque
from ...model.case import Case
from ...model.dynamics import (
    free_vibration,
    kinematic_force_of,
    steady_state,
    steady_train_force,
    train_force,
    vibration_coefficients,
)
from ...model.follower import FollowerModel
from ...model.geometry import analyze, curvature_limit, follower_params, geometry_of
from ...model.valvetrain import Rocker
from ._shape import ShapeSpace, control_order, motion_values
from ._slp import value_and_jacobian

EVERY = 4  # the linear programs see every 4th grid angle; a fine scan of each answer checks them all
_SAFETY = 1e-4  # the limits are met with this much to spare: the check reads them on another grid
FINE = 400  # speeds of the scan that checks each answer between the programs' speeds
SPEED_SLOTS = 32  # speeds per linear program (a fixed count: one compiled Jacobian per case)
Variables = TypeVar("Variables", np.ndarray, jax.Array)  # an optimizer's: control points (and a preload)


class RowsKernel(eqx.Module):
    """What the rows compute from: the model, the shape space's arrays, the grid, the follower's dimensions and the
    limits (array leaves, arguments of the compiled programs), and the case's structure (static: the follower
    type, the model's kind, the shape space's sizes; part of the programs' keys). A module-level pytree, so the
    programs of :class:`Rows` are stored by :func:`camdyn._core.jit.cached_jit`: a later ``optimize`` of the
    case, or of another case of the same structure (another margin, spring, limit, lash or preload), loads them
    instead of tracing them (seconds each)."""

    model: FollowerModel
    offset: np.ndarray  # (4, n) the shape space's
    matrix: np.ndarray  # (4, n, n_free)
    theta: np.ndarray  # (n,) rad
    follower: np.ndarray  # the follower's dimensions, :func:`camdyn.model.geometry.follower_params`
    margin: np.ndarray  # () the least interface force to keep (N; N*m for an arm)
    min_contact_force: np.ndarray  # () N at the contact
    max_pressure_angle: np.ndarray  # () rad
    # () the curvature the check holds a roller's pitch curve to (1/mm, the largest), a flat face's contour to (mm,
    # the least radius)
    curvature_bound: np.ndarray
    # a flat face of a given width: (the centre the contact's travel along it is held about, half its width), mm;
    # None for a roller or a face of no given width
    face: np.ndarray | None
    follower_type: FollowerType = eqx.field(static=True)
    roller: bool = eqx.field(static=True)
    rotary: bool = eqx.field(static=True)
    rigid: bool = eqx.field(static=True)  # the model's, which its (traced) train stiffness says
    moving: int = eqx.field(static=True)  # segments reshaped
    n_control: int = eqx.field(static=True)
    control_offset: np.ndarray | None = None  # a valvetrain's flanks (:class:`ShapeSpace`)
    control_matrix: np.ndarray | None = None
    # a valvetrain's event: the cam side's inertia (kg) and the tappet force (N) on the cam's force
    event: bool = eqx.field(static=True, default=False)
    cam_mass: np.ndarray | float = 0.0
    cam_load: np.ndarray | float = 0.0
    # and its valve's closing speed held: the grid angles around its seating, and (cam speed rad/s, ratio, the most
    # m/s)
    seating_idx: np.ndarray | None = None
    seating: np.ndarray | None = None
    # and where its valve lifts off: the follower's position with the valve seated (m) and the train's force that
    # lifts it (N), :func:`camdyn.model.valvetrain.lift_off`
    lift_off: np.ndarray | None = None
    # and a rocker's geometry: the event follower's drive is the lift the rocker gives the valve over its constant
    # ratio ``rocker_ratio`` (the ratio :func:`camdyn.model.valvetrain.event_follower` reduces the valve with)
    rocker: Rocker | None = None
    rocker_ratio: np.ndarray | float = 1.0

    def values(self, z: np.ndarray | jax.Array) -> jax.Array:
        return motion_values(self.offset, self.matrix, z)

    def forces(self, z: np.ndarray | jax.Array, omegas: jax.Array, preload: ArrayLike | None = None) -> jax.Array:
        """Interface force (N; N*m for an arm) at each speed (rad/s) and grid angle: (len(omegas), n). ``preload``
        (SI) overrides the case's, traceably (the spring-force objective frees it)."""
        model = self.model if preload is None else eqx.tree_at(lambda m: m.preload, self.model, preload)
        sv = self.values(z)
        s, s1, s2 = sv[0] * model.scale, sv[1] * model.scale, sv[2] * model.scale
        omegas = jnp.asarray(omegas, dtype=float)
        if self.rigid:
            force = kinematic_force_of(model, omegas[:, None], s, s1, s2)
        else:
            d, d1, factor = self.drive(s, s1)
            if self.lift_off is None:  # the force's own spectrum, one inverse FFT a speed: a fine scan 54 -> 16 ms
                spec = jnp.fft.rfft(d)
                one = lambda w: steady_train_force(spec, w, model, model.stiffness, model.damping, d, d1)  # noqa: E731
            else:
                one = lambda w: train_force(model, w, d, d1, *self.in_contact(model, w, d, d1))  # noqa: E731
            force = factor * jax.vmap(one)(omegas)
        if self.event:
            force = force + self.cam_mass * omegas[:, None] ** 2 * s2 + self.cam_load
        return force

    def drive(self, s: jax.Array, s1: jax.Array) -> tuple[jax.Array, jax.Array, jax.Array | float]:
        """What drives the follower of the rows, from the cam's lift ``s`` and ``s1`` (m): the lift itself, or through a
        rocker's geometry ``g(s)`` its lift at the valve over the constant ratio r the event follower is reduced with
        (so the valve's equation is the event follower's exactly: x = (x_v + lash) / r), with the factor ``g'(s) / r``
        that turns the event follower's train force into the cam's (the rocker's ratio at the cam's lift). Not affine
        in the control points then: the rows differentiate again at every step (:meth:`Rows.force_values`)."""
        if self.rocker is None:
            return s, s1, 1.0
        g, ratio, _ = self.rocker.lever(s)
        r = self.rocker_ratio
        return g / r, ratio * s1 / r, ratio / r

    def in_contact(
        self, model: FollowerModel, w: float | jax.Array, s: jax.Array, s1: jax.Array
    ) -> tuple[jax.Array, jax.Array]:
        """The follower's x and dx/dtheta (m) on the grid at cam speed ``w`` (rad/s) for the lift ``s``, ``s1`` (m): the
        periodic steady state in contact (frequency domain), and for a valvetrain's event the valve's lift from rest
        on its seat (:meth:`_from_lift_off`)."""
        x, x1 = steady_state(jnp.fft.rfft(s), w, model, model.stiffness, model.damping, s.shape[0])
        if self.lift_off is None:
            return x, x1
        h, h1 = self._from_lift_off(model, w, s, s1, x, x1)
        return x + h, x1 + h1

    def _from_lift_off(
        self, model: FollowerModel, w: float | jax.Array, s: jax.Array, s1: jax.Array, x: jax.Array, x1: jax.Array
    ) -> tuple[jax.Array, jax.Array]:
        """What a valvetrain's event adds to the periodic steady state ``x``, ``x1``: the valve leaves its seat at rest
        where the train's force on it reaches the preload (on the opening ramp), while the steady state has it
        moving there, so the free vibration of the difference rings on through the event (the train's mode: at
        engine speeds a hundred newtons and more on the cam). Exact in contact: the steady state plus the free motion
        from the state the seat imposes at lift-off. Linear in the lift, as the rows need it. Zero before lift-off
        (the base circle and the lash ramp, where the steady state stands as before), and for an event that runs
        through theta = 0 (the grid must start on the base circle)."""
        assert self.lift_off is not None  # a valvetrain's rows (in_contact asks)
        x_seat, f_lift = self.lift_off
        seated = model.train_stiffness * (s - x_seat) + model.train_damping * w * s1  # the train on the seated valve
        up = seated >= f_lift
        i = jnp.maximum(jnp.argmax(up), 1)  # the first grid angle past lift-off (the grid starts on the base circle)
        u = jnp.clip((f_lift - seated[i - 1]) / (seated[i] - seated[i - 1]), 0.0, 1.0)  # where between, linearly
        theta = jnp.asarray(self.theta)
        at = theta[i - 1] + u * (theta[i] - theta[i - 1])
        h0 = x_seat - (x[i - 1] + u * (x[i] - x[i - 1]))
        h1 = -(x1[i - 1] + u * (x1[i] - x1[i - 1]))
        k, c = model.train_stiffness + model.stiffness, model.train_damping + model.damping
        a, b = vibration_coefficients(model.mass, k, c, w)
        # an event that runs through theta = 0 (its valve up where the grid starts) keeps the steady state alone
        after = (theta >= at) & jnp.any(up) & ~up[0]
        e00, e01, e10, e11 = free_vibration(a, b, jnp.where(after, theta - at, 0.0))
        return jnp.where(after, e00 * h0 + e01 * h1, 0.0), jnp.where(after, e10 * h0 + e11 * h1, 0.0)

    def need(self, z: np.ndarray | jax.Array, at: np.ndarray | None = None) -> jax.Array:
        """The least interface force to keep (N; N*m for an arm): the margin, or the check's ``min_contact_force``
        (N at the contact) where it is more; for an arm through its lever arm, which moves with s (then one per grid
        angle, or per grid index of ``at``; else a scalar)."""
        fmin = self.min_contact_force
        if self.rotary:
            lever = self._geometry(z, at)["lever"]
            return jnp.maximum(self.margin, fmin / newton_per_torque(lever))
        return jnp.maximum(self.margin, fmin)

    def slack(self, z: np.ndarray | jax.Array, omegas: jax.Array, preload: ArrayLike | None = None) -> jax.Array:
        """:meth:`forces` over the least to keep (:meth:`need`): >= 0 where both the margin and the check's
        ``min_contact_force`` hold."""
        return self.forces(z, omegas, preload) - self.need(z)

    def geometry(self, z: np.ndarray | jax.Array) -> jax.Array:
        """The geometry constraints as ``g <= 0``, each scaled to its limit: :meth:`shape_limits`, and a
        valvetrain's :meth:`seating_limits`."""
        if self.seating is None:
            return self.shape_limits(z)
        return jnp.concatenate([self.shape_limits(z), self.seating_limits(z)])

    def shape_limits(self, z: np.ndarray | jax.Array) -> jax.Array:
        """|phi| / phi_max - 1 and, for a roller, kappa / kappa_max - 1 (the check's least contour radius over the
        roller radius), for a flat face 1 - rho / rho_min and, where its width is given, the contact's distance t
        along it from the centre of the case's own travel within half that width (the check's face_width: the travel
        at most the width); and the control points' order."""
        geo = self._geometry(z)
        rows = [jnp.abs(geo["phi"]) / self.max_pressure_angle - 1.0 + _SAFETY]
        if self.roller:  # the pitch curve's curvature at most kappa_max
            rows.append(geo["kappa_pitch"] / self.curvature_bound - 1.0 + _SAFETY)
        else:  # the contour's radius at least rho_min
            rows.append(1.0 - geo["rho_contour"] / self.curvature_bound + _SAFETY)
        if self.face is not None:  # the contact within the face: a row for each side, each affine where t is
            centre, half = self.face[0], self.face[1]
            rows += [(geo["face_t"] - centre) / half - 1.0 + _SAFETY, (centre - geo["face_t"]) / half - 1.0 + _SAFETY]
        rows.append(control_order(z, self.moving, self.n_control, self.control_offset, self.control_matrix))
        return jnp.concatenate(rows)

    def seating_limits(self, z: np.ndarray | jax.Array) -> jax.Array:
        """A valvetrain's valve closing speed over the most it may have, less 1, at its seating's grid angles."""
        assert self.seating is not None  # a valvetrain's rows
        return self.closing_speed(z) / self.seating[2] - 1.0

    @property
    def affine_shape(self) -> bool:
        """Whether :meth:`shape_limits` are affine in the control points: a translating flat face's (its pressure
        angle 0, its contour's radius R_b + s + s'' linear in the lift; the order is linear for every follower)."""
        return not self.roller and not self.rotary

    def _geometry(self, z: np.ndarray | jax.Array, at: np.ndarray | None = None) -> dict:
        """The cam's geometry (:func:`~camdyn.model.geometry.geometry_of`) on the grid, or at its indices ``at`` (each
        angle's is its own)."""
        theta, values = jnp.asarray(self.theta), self.values(z)
        if at is not None:
            theta, values = theta[at], values[:, at]
        return geometry_of(self.follower_type, self.follower, theta, values)

    def closing_speed(self, z: np.ndarray | jax.Array) -> jax.Array:
        """A valvetrain's valve speed toward its seat (m/s, the surrogate's steady state at ``seating``'s speed) at
        ``seating``'s grid angles: where the valve lands on its seat, what its seating velocity follows."""
        assert self.seating is not None  # a valvetrain's rows
        omega, ratio, _ = self.seating
        model = self.model
        sv = self.values(z)
        d, d1, _ = self.drive(sv[0] * model.scale, sv[1] * model.scale)
        _, x1 = self.in_contact(model, omega, d, d1)
        return -ratio * omega * x1[self.seating_idx]

    @property
    def sampled(self) -> np.ndarray:
        """The grid angles the linear programs see (indices)."""
        return np.arange(0, self.theta.size, EVERY)

    def sampled_forces(self, x: jax.Array, speeds: jax.Array, preload_free: bool) -> jax.Array:
        """:meth:`forces` at the angles the linear programs see, flat; ``x`` the control points, and the preload (SI)
        after them where ``preload_free``."""
        z, preload = split_preload(x, preload_free)
        return self.forces(z, speeds, preload)[:, self.sampled].ravel()

    def sampled_need(self, x: jax.Array, preload_free: bool) -> jax.Array:
        """:meth:`need` at the angles the linear programs see (``x`` as :meth:`sampled_forces`')."""
        at = self.sampled
        return jnp.broadcast_to(self.need(split_preload(x, preload_free)[0], at), at.shape)

    def sampled_slack(self, x: jax.Array, speeds: jax.Array, preload_free: bool) -> jax.Array:
        """:meth:`slack` at the angles the linear programs see, flat (``x`` as :meth:`sampled_forces`')."""
        z, preload = split_preload(x, preload_free)
        return self.slack(z, speeds, preload)[:, self.sampled].ravel()


def split_preload(x: Variables, preload_free: bool) -> tuple[Variables, Variables | None]:
    """The control points and the preload (SI; None: the case's) of an optimizer's variables ``x``."""
    return (x[:-1], x[-1]) if preload_free else (x, None)


def _jacobian_of(method: str, name: str) -> Callable:
    """The stored program ``name``: ``(kernel, x, *args) -> (kernel.<method>(x, *args), d/dx)``
    (:func:`value_and_jacobian`)."""

    def program(kernel: RowsKernel, x: jax.Array, *args: object) -> tuple[jax.Array, jax.Array]:
        return value_and_jacobian(getattr(kernel, method), x, *args)

    program.__name__ = program.__qualname__ = name  # the stored program's key and file name
    return cached_jit(program)


_forces_jacobian = _jacobian_of("sampled_forces", "_forces_jacobian")  # (kernel, x, speeds, preload_free)
_need_jacobian = _jacobian_of("sampled_need", "_need_jacobian")  # (kernel, x, preload_free)
_slack_jacobian = _jacobian_of("sampled_slack", "_slack_jacobian")  # (kernel, x, speeds, preload_free)
_geometry_jacobian = _jacobian_of("geometry", "_geometry_jacobian")  # (kernel, z)
_shape_jacobian = _jacobian_of("shape_limits", "_shape_jacobian")  # (kernel, z)
_seating_jacobian = _jacobian_of("seating_limits", "_seating_jacobian")  # (kernel, z)


@cached_jit
def _closing_speed(kernel: RowsKernel, z: jax.Array) -> jax.Array:
    return kernel.closing_speed(z)


@cached_jit
def _least_on_scan(kernel: RowsKernel, z: jax.Array, w: jax.Array, preload: ArrayLike | None) -> jax.Array:
    return kernel.slack(z, w * jnp.arange(1, FINE + 1) / FINE, preload).min(axis=1)


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
    lift_off: tuple[float, float] | None = None  # and where its valve lifts off (RowsKernel.lift_off)
    rocker: Rocker | None = None  # and its rocker's geometry, with the event follower's ratio (RowsKernel.rocker)
    rocker_ratio: float = 1.0

    @property
    def scale(self) -> float:
        """The size of the forces (N; N*m for an arm): the static preload."""
        return max(abs(float(self.case.model.preload)), abs(self.margin), 1e-3)

    @cached_property
    def kernel(self) -> RowsKernel:
        case, space, lim, f = self.case, self.space, self.case.limits, self.case.follower
        data = lambda x: np.asarray(x, dtype=float)  # noqa: E731  (data of the programs, not a constant in them)
        ratio = float(lim.min_curvature_ratio)
        if f.roller_radius is not None:  # the least contour radius the check allows, as the pitch curvature
            bound = 1.0 / (f.roller_radius * (1.0 + curvature_limit(f, ratio)))
        else:
            assert f.base_radius is not None  # a built case's follower has it
            bound = max(curvature_limit(f, ratio), 1e-3 * f.base_radius)
        return RowsKernel(
            model=case.model,
            offset=space.offset,
            matrix=space.matrix,
            theta=space.theta,
            follower=follower_params(f),
            margin=data(self.margin),
            min_contact_force=data(lim.min_contact_force),
            max_pressure_angle=data(
                math.radians(float(lim.max_pressure_angle or f.kind.default_max_pressure_angle_deg))
            ),
            curvature_bound=data(bound),
            face=self._face,
            follower_type=f.follower_type,
            roller=f.roller_radius is not None,
            rotary=case.kind.rotary,
            rigid=case.model.rigid,
            moving=len(space.moving),
            n_control=space.n_control,
            control_offset=space.control_offset,
            control_matrix=space.control_matrix,
            event=bool(self.cam_mass or self.cam_load),
            cam_mass=data(self.cam_mass),
            cam_load=data(self.cam_load),
            seating_idx=None if self.seating is None else np.asarray(self.seating[2]),
            seating=None if self.seating is None else data([self.seating[0], self.seating[1], self.seating[3]]),
            lift_off=None if self.lift_off is None else data(self.lift_off),
            rocker=self.rocker,
            rocker_ratio=data(self.rocker_ratio),
        )

    @property
    def _face(self) -> np.ndarray | None:
        """:attr:`RowsKernel.face`: a flat face's travel held about the centre of the case's own (where its check
        centres the face), within half its width (mm)."""
        f = self.case.follower
        if f.roller_radius is not None or f.face_width is None:
            return None
        centre = analyze(self.case.motion, f).extremes.face_centre_mm
        assert centre is not None  # a flat face's travel
        return np.array([centre, 0.5 * float(f.face_width)])

    def forces(self, z: np.ndarray | jax.Array, omegas: jax.Array, preload: ArrayLike | None = None) -> jax.Array:
        return self.kernel.forces(z, omegas, preload)

    def geometry(self, z: np.ndarray | jax.Array) -> jax.Array:
        return self.kernel.geometry(z)

    def closing_speed(self, z: np.ndarray | jax.Array) -> jax.Array:
        """:meth:`RowsKernel.closing_speed`, a stored program."""
        return _closing_speed(self.kernel, jnp.asarray(z))

    @property
    def sampled(self) -> np.ndarray:
        """The grid angles the linear programs see (:attr:`RowsKernel.sampled`)."""
        return self.kernel.sampled

    def slack_jacobian(
        self, x: ArrayLike, speeds: jax.Array, preload_free: bool = False
    ) -> tuple[jax.Array, jax.Array]:
        """``(x, speeds[SPEED_SLOTS]) -> (slack at the sampled angles, d/dx)`` differentiated at ``x`` (the control
        points, and the preload after them where ``preload_free``), a stored program."""
        return _slack_jacobian(self.kernel, jnp.asarray(x), speeds, preload_free)

    def force_values(
        self, speeds: jax.Array, x_ref: ArrayLike | None = None, preload_free: bool = False
    ) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """``x -> (slack at the sampled angles, d/dx)`` at the fixed ``speeds`` (:data:`SPEED_SLOTS`) for the linear
        programs; ``x`` the control points, and the preload (SI) after them where ``preload_free`` (``x_ref``: where
        the Jacobian is taken, default the shape space's own). The force is exactly affine in ``x`` (the steady
        state in contact is linear in the motion and the preload, the motion in the control points), so its
        Jacobian is computed once and every later value is one product; what an arm must keep moves with its lever
        arm, so there each call differentiates that alone (the geometry, not the force's speeds); a rocker's ratio
        moves the force itself, so there each call differentiates again."""
        if self.rocker is not None:
            return lambda x: _numpy(self.slack_jacobian(x, speeds, preload_free))
        x_ref = np.asarray(self.space.z0 if x_ref is None else x_ref, dtype=float)
        f_ref, jac_f = _numpy(_forces_jacobian(self.kernel, jnp.asarray(x_ref), speeds, preload_free))
        m = int(np.shape(speeds)[0])
        if not self.kernel.rotary:  # the need is a constant: the slack itself is affine
            v_ref = f_ref - np.tile(_numpy(_need_jacobian(self.kernel, jnp.asarray(x_ref), preload_free))[0], m)
            return lambda x: (v_ref + np.einsum("ij,j->i", jac_f, np.asarray(x, dtype=float) - x_ref), jac_f)

        def slack(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            need, jac_need = _numpy(_need_jacobian(self.kernel, jnp.asarray(x), preload_free))
            dx = np.asarray(x, dtype=float) - x_ref
            return f_ref + np.einsum("ij,j->i", jac_f, dx) - np.tile(need, m), jac_f - np.tile(jac_need, (m, 1))

        return slack

    def prepare(self, preload_free: bool = False) -> None:
        """Compile (or load) the stored programs the linear programs call, for arguments shaped as theirs (numpy: a
        program is keyed by the shapes, and no transfer is compiled), without running them: ``optimize`` does it on
        the side while it checks the case (seconds of compiling in a first run). ``preload_free``: with the preload
        among the variables (the spring-force objective)."""
        kernel, z = self.kernel, np.asarray(self.space.z0, dtype=float)
        x, speeds = (np.r_[z, 0.0] if preload_free else z), np.zeros(SPEED_SLOTS)
        if self.rocker is None:  # as force_values calls them
            _forces_jacobian.prepare(kernel, x, speeds, preload_free)  # pyright: ignore[reportFunctionMemberAccess]
            _need_jacobian.prepare(kernel, x, preload_free)  # pyright: ignore[reportFunctionMemberAccess]
        else:
            _slack_jacobian.prepare(kernel, x, speeds, preload_free)  # pyright: ignore[reportFunctionMemberAccess]
        if not kernel.affine_shape:  # as geometry_values calls them
            _geometry_jacobian.prepare(kernel, z)  # pyright: ignore[reportFunctionMemberAccess]
        else:
            _shape_jacobian.prepare(kernel, z)  # pyright: ignore[reportFunctionMemberAccess]
            if kernel.seating is not None:
                _seating_jacobian.prepare(kernel, z)  # pyright: ignore[reportFunctionMemberAccess]
        preload = np.zeros(()) if preload_free else None  # as least_on_scan calls it
        _least_on_scan.prepare(kernel, z, np.ones(()), preload)  # pyright: ignore[reportFunctionMemberAccess]

    def least_on_scan(self, z: jax.Array, w_max: float, preload: ArrayLike | None = None) -> jax.Array:
        """The least slack at each of FINE speeds up to ``w_max`` (rad/s), a stored program; the speed and a preload
        go in as data (a Python float would be a static argument: a program for every value)."""
        f0 = None if preload is None else np.asarray(preload, dtype=float)
        return _least_on_scan(self.kernel, z, np.asarray(w_max, dtype=float), f0)

    def geometry_jacobian(self, z: jax.Array) -> tuple[jax.Array, jax.Array]:
        """``z -> (geometry constraints, d/dz)`` (:meth:`geometry`), a stored program."""
        return _geometry_jacobian(self.kernel, z)

    @cached_property
    def geometry_values(self) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """``z -> (geometry constraints, d/dz)`` (:meth:`geometry`) for the linear programs: differentiated at each
        call, but where the shape's limits are affine (:attr:`RowsKernel.affine_shape`) from one Jacobian, with only
        a valvetrain's seating rows differentiated at each call."""
        kernel = self.kernel
        if not kernel.affine_shape:
            return lambda z: _numpy(self.geometry_jacobian(jnp.asarray(z)))
        z_ref = np.asarray(self.space.z0, dtype=float)
        g_ref, jac = _numpy(_shape_jacobian(kernel, jnp.asarray(z_ref)))

        def values(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            g = g_ref + np.einsum("ij,j->i", jac, np.asarray(z, dtype=float) - z_ref)
            if kernel.seating is None:
                return g, jac
            seat, jac_seat = _numpy(_seating_jacobian(kernel, jnp.asarray(z)))
            return np.r_[g, seat], np.r_[jac, jac_seat]

        return values


def _numpy(pair: tuple[jax.Array, jax.Array]) -> tuple[np.ndarray, np.ndarray]:
    return np.asarray(pair[0]), np.asarray(pair[1])


def speed_slots(speeds: ArrayLike) -> np.ndarray:
    """``speeds`` padded to :data:`SPEED_SLOTS` by repeating the last (a repeated row changes no linear program)."""
    speeds = np.asarray(speeds, dtype=float)[-SPEED_SLOTS:]
    return np.r_[speeds, np.full(SPEED_SLOTS - speeds.size, speeds[-1])]
