"""The cam's motion as an affine function of the free control points: every rise and return becomes a clamped
B-spline (:mod:`camdyn.model.motion` law ``bspline``) whose interior control points are free, while the segment
boundaries, their lifts and the dwells stay. The motion and all its derivatives are then
``s^(d)(theta_j) = offset[d] + matrix[d] @ z`` on the grid: the model below is linear in ``z`` in contact.
The control points of a segment are held monotone within [0, 1] (:meth:`ShapeSpace.order`): by the convex-hull
property of a B-spline and of its derivative's, the segment then stays within its lift and never reverses."""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
from scipy.optimize import isotonic_regression

from ..._core.errors import InputError
from ..._core.units import FFT_GRID, TWO_PI
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

    @property
    def n_free(self) -> int:
        return self.matrix.shape[-1]

    def values(self, z: np.ndarray | jax.Array) -> jax.Array:
        """(s, s', s'', s''') on the grid for control points ``z``: (4, n), JAX-traceable."""
        return jnp.asarray(self.offset) + jnp.einsum("dnk,k->dn", jnp.asarray(self.matrix), z)

    def order(self, z: np.ndarray | jax.Array) -> jax.Array:
        """``<= 0`` where each segment's control points (clamped 0s, free, clamped 1s) are monotone in [0, 1]:
        exactly linear in ``z`` (JAX-traceable)."""
        free = self.n_control - 2 * CLAMPED
        rows = []
        for k in range(len(self.moving)):
            c = jnp.concatenate([jnp.zeros(1), z[k * free : (k + 1) * free], jnp.ones(1)])
            rows.append(c[:-1] - c[1:])
        return jnp.concatenate(rows)

    def control_points(self, z: np.ndarray | jax.Array) -> list[np.ndarray]:
        """The full control points of each reshaped segment (clamped ends included)."""
        free = self.n_control - 2 * CLAMPED
        z = np.asarray(z, dtype=float)
        return [
            np.r_[np.zeros(CLAMPED), z[i * free : (i + 1) * free], np.ones(CLAMPED)] for i in range(len(self.moving))
        ]

    def segments(self, z: np.ndarray | jax.Array) -> list[dict]:
        """The case file's ``[motion] segments`` with the reshaped ones as ``law = "bspline"``."""
        out, cps = [], dict(zip(self.moving, self.control_points(z), strict=True))
        for i, spec in enumerate(self.specs):
            if i in cps:
                c = [0.0 if abs(v) < 1e-15 else float(v) for v in cps[i]]
                out.append({"law": "bspline", "end": spec.end, "lift": spec.lift, "coefficients": c})
            else:
                out.append(spec.model_dump(exclude_defaults=True) | {"law": spec.law, "end": spec.end})
        return out

    def program(self, z: np.ndarray | jax.Array, unit: str) -> Program:
        return Program.from_segments(self.segments(z), unit=unit)


def shape_space(case: Case, n: int = FFT_GRID, n_control: int = N_CONTROL) -> ShapeSpace:
    """The shape space of a segment case with ``n_control`` control points per reshaped segment; a path, table or
    contour case has no segments to reshape."""
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
