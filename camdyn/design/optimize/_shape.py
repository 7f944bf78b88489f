"""The cam's motion as an affine function of the free control points: every rise and return becomes a clamped
B-spline (:mod:`camdyn.model.motion` law ``bspline``) whose interior control points are free, while the segment
boundaries, their lifts and the dwells stay. The motion and all its derivatives are then
``s^(d)(theta_j) = offset[d] + matrix[d] @ z`` on the grid: the model below is linear in ``z`` in contact.
The control points of a segment are held monotone within [0, 1] (:meth:`ShapeSpace.order`): by the convex-hull
property of a B-spline and of its derivative's, the segment then stays within its lift and never reverses.
A valvetrain's space (:func:`flank_space`) reshapes only the flanks between its lash ramps: their control points
are the null space of the joins' conditions (lift, velocity and acceleration of the ramps and of each other)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import jax
import jax.numpy as jnp
import numpy as np
from scipy.linalg import null_space
from scipy.optimize import isotonic_regression

from ..._core.errors import InputError
from ..._core.linprog import OPTIMAL, LinearProgram
from ..._core.units import FFT_GRID, M_PER_MM, TWO_PI
from ...model.case import Case
from ...model.motion import BSPLINE_CLAMPED as CLAMPED
from ...model.motion import Program, evaluate
from ...model.motion import bspline_basis as basis

MIN_CONTROL, MAX_CONTROL = 2 * CLAMPED + 1, 64  # at least one free point; past 64 the programs only slow down
N_CONTROL = 16  # control points per reshaped segment by default (10 free); docs/guide.md gives the measurements


@dataclass(frozen=True)
class ShapeSpace:
    """The motion of a segment program as ``offset + matrix @ z`` (motion unit per rad^d, d = 0..3) on
    ``theta_j = 2 pi j / n``; ``z0`` reproduces the case's own motion as closely as the splines allow."""

    specs: tuple  # the case's segment specs
    moving: tuple[int, ...]  # the segments reshaped (every one that lifts)
    theta: np.ndarray  # rad
    offset: np.ndarray  # (4, n)
    matrix: np.ndarray  # (4, n, n_free)
    z0: np.ndarray
    to_unit: float  # the case file's lift unit -> the motion's (mm -> mm, deg -> rad)
    n_control: int = N_CONTROL  # control points per reshaped segment, the clamped ends included
    # a valvetrain's flanks (:func:`flank_space`): each reshaped segment's control points are
    # ``control_offset[k] + control_matrix[k] @ z`` and it starts and ends at rest or not; None: clamped at rest
    control_offset: np.ndarray | None = None  # (len(moving), n_control)
    control_matrix: np.ndarray | None = None  # (len(moving), n_control, n_free)
    at_rest: tuple[tuple[bool, bool], ...] | None = None

    @property
    def n_free(self) -> int:
        return self.matrix.shape[-1]

    def values(self, z: np.ndarray | jax.Array) -> jax.Array:
        """(s, s', s'', s''') on the grid for control points ``z``: (4, n), JAX-traceable."""
        return motion_values(self.offset, self.matrix, z)

    def order(self, z: np.ndarray | jax.Array) -> jax.Array:
        """``<= 0`` where each segment's control points (clamped 0s, free, clamped 1s) are monotone in [0, 1]:
        exactly linear in ``z`` (JAX-traceable)."""
        return control_order(z, len(self.moving), self.n_control, self.control_offset, self.control_matrix)

    def control_points(self, z: np.ndarray | jax.Array) -> list[np.ndarray]:
        """The full control points of each reshaped segment (clamped ends included)."""
        free = self.n_control - 2 * CLAMPED
        z = np.asarray(z, dtype=float)
        if self.control_matrix is not None:
            assert self.control_offset is not None and self.at_rest is not None  # flank_space sets all three
            out = []
            for c, (start, end) in zip(self.control_offset + self.control_matrix @ z, self.at_rest, strict=True):
                c[: 3 if start else 1], c[-3 if end else -1 :] = 0.0, 1.0  # exactly what the null space gives to 1e-16
                out.append(c)
            return out
        return [
            np.r_[np.zeros(CLAMPED), z[i * free : (i + 1) * free], np.ones(CLAMPED)] for i in range(len(self.moving))
        ]

    def segments(self, z: np.ndarray | jax.Array) -> list[dict]:
        """The case file's ``[motion] segments`` with the reshaped ones as ``law = "bspline"``."""
        out, cps = [], dict(zip(self.moving, self.control_points(z), strict=True))
        rest = dict(zip(self.moving, self.at_rest or [(True, True)] * len(self.moving), strict=True))
        for i, spec in enumerate(self.specs):
            if i in cps:
                c = [0.0 if abs(v) < 1e-15 else float(v) for v in cps[i]]
                out.append({"law": "bspline", "end": spec.end, "lift": spec.lift, "coefficients": c})
                out[-1] |= {k: False for k, v in zip(("start_at_rest", "end_at_rest"), rest[i], strict=True) if not v}
            else:
                out.append(spec.model_dump(exclude_defaults=True) | {"law": spec.law, "end": spec.end})
        return out

    def program(self, z: np.ndarray | jax.Array, unit: str) -> Program:
        return Program.from_segments(self.segments(z), unit=unit)


def motion_values(offset: np.ndarray, matrix: np.ndarray, z: np.ndarray | jax.Array) -> jax.Array:
    """``offset + matrix @ z``: (s, s', s'', s''') on the grid, (4, n), JAX-traceable."""
    return jnp.asarray(offset) + jnp.einsum("dnk,k->dn", jnp.asarray(matrix), z)


def control_order(
    z: np.ndarray | jax.Array,
    moving: int,
    n_control: int,
    control_offset: np.ndarray | None = None,
    control_matrix: np.ndarray | None = None,
) -> jax.Array:
    """``<= 0`` where the control points of each of ``moving`` segments (clamped 0s, free ones from ``z``, clamped
    1s; or a valvetrain's flanks, ``control_offset + control_matrix @ z``) are monotone in [0, 1]: exactly linear
    in ``z`` (JAX-traceable)."""
    if control_matrix is not None:
        c = jnp.asarray(control_offset) + jnp.einsum("knf,f->kn", jnp.asarray(control_matrix), z)
        return (c[:, :-1] - c[:, 1:]).ravel()
    free = n_control - 2 * CLAMPED
    rows = []
    for k in range(moving):
        c = jnp.concatenate([jnp.zeros(1), z[k * free : (k + 1) * free], jnp.ones(1)])
        rows.append(c[:-1] - c[1:])
    return jnp.concatenate(rows)


def shape_space(case: Case, n: int = FFT_GRID, n_control: int = N_CONTROL) -> ShapeSpace:
    """The shape space of a segment case with ``n_control`` control points per reshaped segment; a path, table or
    contour case has no segments to reshape."""
    _segments_to_reshape(case, n_control)
    assert case.spec.motion is not None  # a segments case
    specs = tuple(case.spec.motion.segments)
    moving = tuple(i for i, s in enumerate(specs) if s.law != "dwell")
    if not moving:
        raise InputError("motion.segments", "no segment lifts: nothing to reshape")
    to_unit = case.kind.motion_per_lift  # the segments' lift unit -> the motion's
    theta = np.arange(n) * (TWO_PI / n)
    now = np.asarray(evaluate(case.motion, theta))  # the case's own motion: the start and what the dwells keep
    offset = np.zeros((4, n))
    free = n_control - 2 * CLAMPED
    matrix = np.zeros((4, n, free * len(moving)))
    z0, start, base = [], 0.0, 0.0
    for i, spec in enumerate(specs):
        a, b = math.radians(start), math.radians(spec.end)
        inside = (theta >= a) & (theta < b) if spec.end < 360.0 else theta >= a
        if i in moving:
            k = moving.index(i)
            beta, lift = b - a, spec.lift * to_unit
            u = (theta[inside] - a) / beta
            for d in range(4):
                B = basis(u, n_control, d) * lift / beta**d
                offset[d, inside] = B[:, -CLAMPED:].sum(axis=1) + (base * to_unit if d == 0 else 0.0)
                matrix[d][np.ix_(inside, np.arange(k * free, (k + 1) * free))] = B[:, CLAMPED:-CLAMPED]
            y = now[0, inside] - offset[0, inside]
            z, *_ = np.linalg.lstsq(matrix[0][np.ix_(inside, np.arange(k * free, (k + 1) * free))], y, rcond=None)
            z0.append(np.clip(isotonic_regression(z).x, 0.0, 1.0))  # the start within :meth:`ShapeSpace.order`
        else:
            offset[0, inside] = base * to_unit
        start, base = spec.end, base + spec.lift
    return ShapeSpace(specs, moving, theta, offset, matrix, np.concatenate(z0), to_unit, n_control)


def _segments_to_reshape(case: Case, n_control: int) -> None:
    """:class:`InputError` where ``case`` has no segments to reshape, or ``n_control`` is out of bounds."""
    if not MIN_CONTROL <= n_control <= MAX_CONTROL:
        raise InputError(
            "--control-points", f"{n_control} control points per segment: give {MIN_CONTROL} to {MAX_CONTROL}"
        )
    if case.motion_source != "segments":
        why = {
            "path": "its motion is fixed by the path the linkage must trace (reshape the path, or synthesize again)",
            "table": "its motion is the lift table's; give the motion as segments to let camdyn reshape it",
            "valve_table": "its motion is the valve-lift table's; give the motion as segments to let camdyn reshape it",
            "contour": "its motion is the measured contour's; give the motion as segments to let camdyn reshape it",
        }[case.motion_source]
        raise InputError("motion", f"a {case.motion_source} case cannot be optimized: {why}")


def flank_space(case: Case, n: int = FFT_GRID, n_control: int = N_CONTROL) -> ShapeSpace:
    """The shape space of a valvetrain's event: only the flanks are reshaped, the segments that start and end with
    the lash taken up (the cam's lift at the valve above the lash); the ramps that take it up and the dwells stay
    as given, and with them the valve's opening and closing. Each flank joins its neighbours with their lift,
    velocity and acceleration (a ramp's constant velocity), two flanks meet with the same velocity and acceleration
    (zero velocity at the nose, whose lift stays). With no lash there is no ramp and every rise and return is a
    flank. ``z`` spans the null space of these joins; ``z0`` is the nearest to the case's own flanks in order."""
    _segments_to_reshape(case, n_control)
    assert case.spec.motion is not None and case.valvetrain is not None  # a valvetrain's segments
    specs = tuple(case.spec.motion.segments)
    to_unit = case.kind.motion_per_lift
    bounds = np.r_[0.0, np.cumsum([s.lift for s in specs])] * to_unit  # lift at each boundary, the motion's unit
    lash_mm = float(case.valvetrain.lash) / M_PER_MM
    over = case.valvetrain.at_valve_mm(bounds)[0] - lash_mm > 1e-9  # the lash taken up at each boundary
    moving = tuple(i for i, s in enumerate(specs) if s.law != "dwell" and (lash_mm == 0.0 or (over[i] and over[i + 1])))
    if not moving:
        raise InputError("motion.segments", "no segment starts and ends with the lash taken up: no flank to reshape")
    if any(specs[i].lift == 0.0 for i in moving):
        i = next(i for i in moving if specs[i].lift == 0.0)
        raise InputError(f"motion.segments[{i}]", "a flank that rises by 0 cannot be reshaped as a B-spline")
    program = case.motion
    assert isinstance(program, Program)  # a segment list's motion
    starts = np.r_[0.0, [s.end for s in specs[:-1]]]
    theta = np.arange(n) * (TWO_PI / n)
    now = case.motion.host(theta)  # numpy: eager jax.numpy compiles a program per operation
    K, m = len(moving), n_control
    ends = [basis(np.array([0.0, 1.0]), m, d) for d in range(3)]  # (2, m): y^(d) at u = 0 and 1
    rows, rhs = [], []

    def condition(pairs: list[tuple[int, np.ndarray]], value: float) -> None:
        row = np.zeros(K * m)
        for k, coef in pairs:
            row[k * m : (k + 1) * m] += coef
        rows.append(row)
        rhs.append(value)

    for k, i in enumerate(moving):
        lift, beta = specs[i].lift * to_unit, math.radians(specs[i].end - starts[i])
        scale = [lift / beta**d for d in range(3)]
        condition([(k, ends[0][0])], 0.0)
        condition([(k, ends[0][1])], 1.0)
        before, after = (i - 1) % len(specs), (i + 1) % len(specs)
        if before not in moving:  # a ramp or a dwell ends here: its velocity and acceleration
            left = program.segment_end(program.segments[before])
            for d in (1, 2):
                condition([(k, scale[d] * ends[d][0])], float(left[d]))
        if after in moving:  # the next flank: the same velocity and acceleration, zero velocity at the nose
            k2 = moving.index(after)
            lift2, beta2 = specs[after].lift * to_unit, math.radians(specs[after].end - starts[after])
            for d in (1, 2):
                condition([(k, scale[d] * ends[d][1]), (k2, -lift2 / beta2**d * ends[d][0])], 0.0)
            if math.copysign(1.0, lift) != math.copysign(1.0, lift2):
                condition([(k, ends[1][1])], 0.0)
        else:
            right = np.asarray(program.host(np.array(math.radians(specs[i].end))))
            for d in (1, 2):
                condition([(k, scale[d] * ends[d][1])], float(right[d]))
    norm = np.linalg.norm(rows, axis=1)  # each join to machine precision, whatever its derivative's scale
    E, e = np.array(rows) / norm[:, None], np.array(rhs) / norm
    particular = np.linalg.lstsq(E, e, rcond=None)[0]
    kernel = null_space(E)
    if kernel.shape[1] == 0:
        raise InputError("--control-points", f"{n_control} control points per flank leave none free: give more")
    offset, matrix = np.zeros((4, n)), np.zeros((4, n, kernel.shape[1]))
    fitted = np.zeros(n, bool)
    for i, spec in enumerate(specs):
        a, b = math.radians(starts[i]), math.radians(spec.end)
        inside = (theta >= a) & (theta < b) if spec.end < 360.0 else theta >= a
        if i not in moving:
            offset[:, inside] = now[:, inside]  # a ramp or a dwell as given
            continue
        k = moving.index(i)
        lift, beta = spec.lift * to_unit, b - a
        u = (theta[inside] - a) / beta
        for d in range(4):
            B = basis(u, m, d) * lift / beta**d
            offset[d, inside] = B @ particular[k * m : (k + 1) * m] + (bounds[i] if d == 0 else 0.0)
            matrix[d, inside] = B @ kernel[k * m : (k + 1) * m]
        fitted |= inside
    z_fit = np.linalg.lstsq(matrix[0, fitted], now[0, fitted] - offset[0, fitted], rcond=None)[0]
    c_off, c_mat = particular.reshape(K, m), kernel.reshape(K, m, -1)
    at_rest = tuple(_at_rest(c_off[k], c_mat[k]) for k in range(K))
    space = ShapeSpace(specs, moving, theta, offset, matrix, z_fit, to_unit, n_control, c_off, c_mat, at_rest)
    return replace(space, z0=_in_order(space, z_fit))


def _at_rest(offset: np.ndarray, matrix: np.ndarray) -> tuple[bool, bool]:
    """Whether a flank's first three control points are 0 (its last three 1) whatever ``z``: it starts (ends) at
    rest, as a clamped B-spline."""
    fixed = np.all(np.abs(matrix) < 1e-12, axis=1)
    return bool(fixed[:3].all() and np.allclose(offset[:3], 0.0, atol=1e-12)), bool(
        fixed[-3:].all() and np.allclose(offset[-3:], 1.0, atol=1e-12)
    )


def _in_order(space: ShapeSpace, z: np.ndarray) -> np.ndarray:
    """The ``z`` nearest to ``z`` (the largest change of a control point least) whose control points are in order
    (:meth:`ShapeSpace.order`): a linear program."""
    if float(np.max(np.asarray(space.order(jnp.asarray(z))))) <= 0.0:
        return z
    assert space.control_matrix is not None and space.control_offset is not None  # a flank space's
    K, m, f = space.control_matrix.shape
    M = space.control_matrix.reshape(K * m, f)
    diff = (np.eye(m)[:-1] - np.eye(m)[1:])[None].repeat(K, 0)  # c_j - c_{j+1} per flank
    D = np.zeros((K * (m - 1), K * m))
    for k in range(K):
        D[k * (m - 1) : (k + 1) * (m - 1), k * m : (k + 1) * m] = diff[k]
    c0 = space.control_offset.reshape(-1)
    one = np.ones((K * m, 1))
    A = np.vstack([np.c_[M, -one], np.c_[-M, -one], np.c_[D @ M, np.zeros((K * (m - 1), 1))]])
    b = np.r_[M @ z, -(M @ z), -(D @ c0)]
    lp = LinearProgram(np.r_[np.zeros(f), 1.0], np.full(f + 1, -np.inf), np.full(f + 1, np.inf))
    lp.add(A, b)
    answer = lp.solve()
    return answer.x[:f] if answer.status == OPTIMAL else z
