"""The least base radius that meets the pressure-angle and curvature limits: ``camdyn check``'s advice, the cam
size ``camdyn synthesize`` writes, and the base radius of a path case that states none."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..._core.errors import NumericalError
from ..._core.units import CUSP_MM, DEFAULT_MIN_CURVATURE_RATIO, THETA_GRID
from ...schema import FollowerSpec
from ._analyze import GeometryExtremes, extremes_on, extremes_samples
from ._kernel import check_assembly

if TYPE_CHECKING:
    from ..motion import Motion

BASE_RADIUS_STEP_MM = 0.5  # a base radius chosen for a cam that is to be made is rounded up to this


def curvature_limit(f: FollowerSpec, min_curvature_ratio: float) -> float:
    """What the curvature check compares with: ``min_curvature_ratio`` roller radii for a roller, a contour radius
    above :data:`camdyn._core.units.CUSP_MM` (no cusp) for a flat face."""
    return min_curvature_ratio if f.roller else CUSP_MM


def passes(
    f: FollowerSpec, ext: GeometryExtremes, max_pressure_angle: float, min_curvature_ratio: float | None
) -> bool:
    """Whether the pressure-angle and curvature checks pass on these extremes (``min_curvature_ratio`` None: the
    pressure angle alone, for a contour with sharp corners, which no base radius can smooth)."""
    if ext.max_pressure_angle_deg > max_pressure_angle:
        return False
    return min_curvature_ratio is None or (not ext.cusp and ext.curvature >= curvature_limit(f, min_curvature_ratio))


def rounded_base_radius(rb: float) -> float:
    """A base radius (mm) rounded up to :data:`BASE_RADIUS_STEP_MM` and kept clear of the limit it was bisected to."""
    step = BASE_RADIUS_STEP_MM
    return max(math.ceil((rb + 1e-6) / step) * step, step)


def min_base_radius(
    motion: Motion,
    follower: FollowerSpec,
    *,
    max_pressure_angle: float | None = None,
    min_curvature_ratio: float | None = DEFAULT_MIN_CURVATURE_RATIO,
    n: int = THETA_GRID,
) -> float:
    """The least base radius (mm) meeting the pressure-angle (deg) and curvature limits, to 1e-6 mm.

    The pressure angle falls and the pitch curve flattens as the base circle grows, so the limits hold above
    one threshold: bisection between a radius that fails and one that holds (for an oscillating layout, which need
    not be monotone, the first that holds in a coarse scan of the admissible radii and the one before it).
    ``min_curvature_ratio`` None judges the pressure angle alone (:func:`passes`). Oscillating layouts bound Rb by
    the pivot and arm; raises :class:`NumericalError` if no admissible base radius passes.
    """
    f = follower
    max_pa = f.kind.default_max_pressure_angle_deg if max_pressure_angle is None else max_pressure_angle
    check_assembly(motion, f)
    assert f.base_radius is not None  # a built follower has it (from the contour where one is given)
    rr = f.roller_radius or 0.0
    samples = extremes_samples(motion, n)  # the motion once: the search evaluates some 70 base radii on it

    def ok(rb: float) -> bool:
        try:
            return passes(f, extremes_on(samples, f, rb), max_pa, min_curvature_ratio)
        except NumericalError:  # a degenerate layout at this radius: not a solution
            return False

    span = max(extremes_on(samples, f).lift_range, 1e-3)  # lift (mm): a scale for the search
    if f.translating and f.roller:
        lo = max(abs(f.offset) - rr, 0.0) * (1 + 1e-9) + 1e-9
        hi = max(f.base_radius, lo, span)
        while not ok(hi):  # the pressure angle -> 0 and the pitch curve flattens as Rb -> infinity
            hi *= 2.0
            if hi > 1e6 * max(span, rr, 1.0):
                raise NumericalError("follower.base_radius", "no base radius meets the limits")
    elif f.translating:
        lo, hi = 1e-9, max(f.base_radius, span)
        while not ok(hi):
            hi *= 2.0
            if hi > 1e6 * span:
                raise NumericalError("follower.base_radius", "no base radius meets the limits")
    else:  # bounded by the assembly conditions of check_assembly
        L = f.pivot_distance
        assert L is not None  # the schema: an oscillating follower needs it
        if f.roller:
            assert f.arm_length is not None  # the schema: an oscillating roller needs it
            lo, hi = max(abs(L - f.arm_length) - rr, 0.0), L + f.arm_length - rr
        else:
            lo, hi = max(-L - f.offset, 0.0), L - f.offset
        lo, hi = lo + 1e-6 * (hi - lo), hi - 1e-6 * (hi - lo)
        if hi <= lo:
            raise NumericalError("follower.base_radius", "no admissible base radius for this pivot and arm")
    if f.translating:  # the limits hold above one radius (hi holds): bisect between lo and hi
        if ok(lo):
            return float(lo)
        a, b = lo, hi
    else:  # the first of a coarse scan that holds (an oscillating layout need not be monotone), then bisect
        grid = np.linspace(lo, hi, 33)
        first = next((i for i, rb in enumerate(grid) if ok(rb)), None)
        if first is None:
            raise NumericalError(
                "follower.base_radius",
                f"no base radius in ({lo:.4g}, {hi:.4g}) mm meets the limits; move the pivot or change the arm",
            )
        if first == 0:
            return float(grid[0])
        a, b = grid[first - 1], grid[first]
    for _ in range(200):  # halves down to 1e-6 mm from any bracket a float can hold
        if b - a <= 1e-6:
            break
        mid = 0.5 * (a + b)
        a, b = (a, mid) if ok(mid) else (mid, b)
    return float(b)
