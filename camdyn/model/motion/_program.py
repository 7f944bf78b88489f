"""Motion programs: contiguous segments of named laws, or of polynomials from boundary conditions, covering
one cam revolution."""

from __future__ import annotations

import math
from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..._core.errors import InputError
from ..._core.kinds import kind_of_motion
from ..._core.units import JUMP_RTOL, TWO_PI
from ...schema import SegmentSpec, check_segments, parse
from ...schema.motion import BSPLINE, POLYNOMIAL, BSplineSegmentSpec, PolynomialSegmentSpec
from ._base import Motion
from ._bspline import bspline_table
from ._laws import _LAW_TABLES, _NC, _LawTable, _piece_eval
from ._polynomial import BoundaryPolynomial, polynomial_warnings, solve_polynomial


@dataclass(frozen=True)
class Segment:
    """One segment of a motion program: ``law`` from ``start`` to ``end`` (deg), rising by ``lift`` (mm, or rad
    of swing); a polynomial segment carries its solved polynomial (in the case file's lift unit)."""

    law: str
    start: float
    end: float
    lift: float = 0.0
    base: float = 0.0  # lift at the segment start, mm
    polynomial: BoundaryPolynomial | None = None
    coefficients: tuple[float, ...] | None = None

    def table(self, to_unit: float) -> tuple[_LawTable, float]:
        """The segment's piece table and the factor that scales its normalized y to the motion's unit: a law's
        y runs from 0 to 1 (times the lift), a polynomial's is its own (times mm or rad per lift unit)."""
        if self.coefficients is not None:
            return bspline_table(self.coefficients), self.lift
        if self.polynomial is None:
            return _LAW_TABLES[self.law], self.lift
        b = np.asarray(self.polynomial.coef)
        k = np.arange(max(len(b) - 2, 1))
        acc = np.zeros(max(_NC, len(k)))
        acc[: len(b) - 2] = (k[: len(b) - 2] + 1) * (k[: len(b) - 2] + 2) * b[2:]
        one = np.ones(1)
        return _LawTable(x0=np.zeros(1), c=acc[None, :], w=one, p1=0 * one, p2=0 * one, y0=b[:1], v0=b[1:2]), to_unit


class Program(Motion):
    """A motion program: contiguous segments covering 0-360 degrees of cam angle.

    Build it with :meth:`Program.from_segments`; evaluation is a table look-up of the segment piece and the
    closed-form law, so it jits, vmaps and differentiates.
    """

    segments: tuple[Segment, ...] = eqx.field(static=True)
    unit: str = eqx.field(static=True)
    breaks_deg: tuple[float, ...] = eqx.field(static=True)
    _start: jax.Array  # piece start, rad
    _theta0: jax.Array  # segment start, rad
    _beta: jax.Array  # segment span, rad
    _base: jax.Array
    _lift: jax.Array
    _x0: jax.Array
    _c: jax.Array
    _w: jax.Array
    _p1: jax.Array
    _p2: jax.Array
    _y0: jax.Array
    _v0: jax.Array

    @classmethod
    def from_segments(cls, segments: list, key: str = "motion.segments", unit: str = "mm") -> Program:
        """A program from ``[{law, end, lift}, ...]`` (or :class:`camdyn.schema.SegmentSpec`): ends in deg, lifts in
        mm, or in deg of arm swing when ``unit`` is "rad".

        Raises :class:`InputError` naming the segment for an unknown law, a non-increasing end, a program
        that does not end at 360 degrees, does not close (net lift 0) or dips below zero lift
        (:func:`camdyn.schema.check_segments`, the schema's rule).
        """
        if not segments:
            raise InputError(key, "at least one segment is required")
        specs = [_segment_spec(s, f"{key}[{i}]") for i, s in enumerate(segments)]
        try:
            check_segments(specs, kind_of_motion(unit).lift_unit, key=key)
        except ValueError as err:
            where, message = str(err).split(": ", 1)
            raise InputError(where, message) from None
        return cls.from_specs(specs, unit)

    @classmethod
    def from_specs(cls, specs: list, unit: str = "mm") -> Program:
        """A program from segments the schema has checked (:func:`camdyn.schema.check_segments`)."""
        to_unit = kind_of_motion(unit).motion_per_lift
        segs: list[Segment] = []
        start, base = 0.0, 0.0
        for s in specs:
            poly = solve_polynomial(s, start) if isinstance(s, PolynomialSegmentSpec) else None
            coefs = tuple(s.coefficients) if isinstance(s, BSplineSegmentSpec) else None
            segs.append(Segment(s.law, start, s.end, s.lift * to_unit, base * to_unit, poly, coefs))
            start, base = s.end, base + s.lift
        return cls._from_checked(tuple(segs), unit)

    @classmethod
    def _from_checked(cls, segs: tuple[Segment, ...], unit: str) -> Program:
        cols: dict[str, list] = {
            k: [] for k in ("start", "theta0", "beta", "base", "lift", "x0", "c", "w", "p1", "p2", "y0", "v0")
        }
        for seg in segs:
            t, scale = seg.table(kind_of_motion(unit).motion_per_lift)
            th0, beta = math.radians(seg.start), math.radians(seg.end - seg.start)
            for i in range(len(t.x0)):
                cols["start"].append(th0 + beta * t.x0[i])
                cols["theta0"].append(th0)
                cols["beta"].append(beta)
                cols["base"].append(seg.base)
                cols["lift"].append(scale)
                for k in ("x0", "c", "w", "p1", "p2", "y0", "v0"):
                    cols[k].append(getattr(t, k)[i])
        width = max(len(c) for c in cols["c"])  # the named laws' _NC, or a high-degree polynomial's
        cols["c"] = [np.pad(c, (0, width - len(c))) for c in cols["c"]]
        breaks = tuple(sorted({round(math.degrees(a), 12) % 360.0 for a in cols["start"]}))
        arrays = {f"_{k}": jnp.asarray(np.array(v, dtype=float)) for k, v in cols.items()}
        return cls(segments=segs, unit=unit, breaks_deg=breaks, **arrays)

    def __call__(self, theta):
        return self._eval(jnp, theta)

    def host(self, theta) -> np.ndarray:
        return self._eval(np, theta)

    def _eval(self, xp, theta):
        """Evaluate with jax.numpy (traceable) or numpy (no dispatch or compile cost, for validation)."""
        start = xp.asarray(self._start)
        theta = xp.mod(xp.asarray(theta, dtype=float), TWO_PI)
        i = xp.clip(xp.searchsorted(start, theta, side="right") - 1, 0, start.shape[0] - 1)
        g = lambda a: xp.asarray(a)[i]  # noqa: E731
        beta, lift = g(self._beta), g(self._lift)
        x = (theta - g(self._theta0)) / beta
        y, v, a, j = _piece_eval(
            xp, x - g(self._x0), g(self._c), g(self._w), g(self._p1), g(self._p2), g(self._y0), g(self._v0)
        )
        return xp.stack([g(self._base) + lift * y, lift * v / beta, lift * a / beta**2, lift * j / beta**3])

    def continuity_warnings(self) -> list[str]:
        """Velocity and acceleration jumps at segment boundaries (the fundamental law of cam design)."""
        out = []
        n = len(self.segments)
        # the jump in the units the segments' lift was given in: mm, or deg of arm swing (an oscillating
        # follower's motion is in rad); per radian of cam angle, as the SVAJ page plots it
        lu, to_user = self.kind.lift_unit, self.kind.lift_per_motion
        # a jump is measured against the derivative's largest magnitude over the revolution (JUMP_RTOL)
        peak = np.max(np.abs(self._eval(np, np.linspace(0.0, TWO_PI, 3601))), axis=1)
        for i, seg in enumerate(self.segments):
            nxt = self.segments[(i + 1) % n]
            left = self._segment_end(seg)
            right = self._eval(np, np.deg2rad(seg.end % 360.0))
            for order, name, unit in ((1, "velocity", f"{lu}/rad"), (2, "acceleration", f"{lu}/rad^2")):
                jump = right[order] - left[order]
                if abs(jump) > JUMP_RTOL * max(float(peak[order]), abs(left[order]), abs(right[order])):
                    out.append(
                        f"{name} jumps by {jump * to_user:+.4g} {unit} at {seg.end % 360.0:g} deg "
                        f"({seg.law} -> {nxt.law}): infinite {'acceleration' if order == 1 else 'jerk'}"
                    )
        return out

    def polynomial_warnings(self) -> list[str]:
        """Polynomial segments that overshoot the range their conditions span, or whose system is
        ill-conditioned (:func:`camdyn.model.motion._polynomial.polynomial_warnings`)."""
        lu = self.kind.lift_unit
        return [
            w
            for i, seg in enumerate(self.segments)
            if seg.polynomial is not None
            for w in polynomial_warnings(seg.polynomial, f"motion.segments[{i}]", seg.start, seg.end, lu)
        ]

    def _segment_end(self, seg: Segment):
        t, lift = seg.table(self.kind.motion_per_lift)
        u = np.array(1.0 - t.x0[-1])
        vals = _piece_eval(np, u, t.c[-1], t.w[-1], t.p1[-1], t.p2[-1], t.y0[-1], t.v0[-1])
        beta = math.radians(seg.end - seg.start)
        return np.array(
            [seg.base + lift * vals[0], lift * vals[1] / beta, lift * vals[2] / beta**2, lift * vals[3] / beta**3]
        )


def _segment_spec(raw, where: str):
    """A segment given as a dict (or already a spec), validated as the schema's member for its law."""
    if not isinstance(raw, dict):
        return raw
    model = {POLYNOMIAL: PolynomialSegmentSpec, BSPLINE: BSplineSegmentSpec}.get(raw.get("law"), SegmentSpec)
    return parse(model, raw, where)
