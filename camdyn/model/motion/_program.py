"""Motion programs: contiguous segments of named laws, or of polynomials from boundary conditions, covering
one cam revolution."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import ModuleType

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import InputError
from ..._core.jit import padded_length
from ..._core.kinds import kind_of_motion
from ..._core.units import TWO_PI
from ...schema import SegmentSpec, check_segments, parse
from ...schema.motion import BSPLINE, POLYNOMIAL, BSplineSegmentSpec, PolynomialSegmentSpec
from ._base import Motion, derivative_jumps_at
from ._bspline import bspline_table
from ._laws import _LAW_TABLES, _NC, _LawTable, _piece_eval
from ._lookup import WINDOW, bin_table, interval
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


# Compiled programs take a program's pieces as arrays padded to 1024 rows (4096, ... beyond) and its acceleration
# polynomials padded to 8 coefficients (16, 32, ... for a polynomial of high degree): one compiled program serves
# every program of a follower kind, whatever its segments, laws and angles. A longer search costs nothing measurable
# against a trace and compile (about 10 s), which a new bucket would cost a new case.
_PIECE_ROWS, _COEF_WIDTH = 1024, 8


class PieceTable(eqx.Module):
    """A motion program as compiled programs take it: its pieces as data, padded to a bucketed length.

    Row i is piece i (start angle, its segment's start, span, base lift and lift scale, and the normalized law's
    acceleration coefficients, trigonometric term and initial values); rows past the last piece repeat it, with
    start angles of +inf so that the segment search never lands on them. ``jumps`` holds the breaks (rad), padded
    with +inf, for the ODE step-size controller. Nothing about the segment list is static, so every program of a
    bucket shares one compiled program; it has no ``breaks_deg`` (the :class:`Program` has). Evaluation: one
    lookup of the piece and one closed-form law (named laws, polynomials and B-spline pieces alike), so it jits,
    vmaps and differentiates.
    """

    unit: str = eqx.field(static=True)
    start: jax.Array  # (P,) piece start, rad; +inf past the last piece
    theta0: jax.Array  # (P,) segment start, rad
    beta: jax.Array  # (P,) segment span, rad
    base: jax.Array  # (P,) lift at the segment start, the motion's unit
    lift: jax.Array  # (P,) the factor of the normalized law
    x0: jax.Array  # (P,) piece start on the normalized segment
    c: jax.Array  # (P, W) acceleration polynomial, ascending powers
    w: jax.Array  # (P,)
    p1: jax.Array  # (P,)
    p2: jax.Array  # (P,)
    y0: jax.Array  # (P,)
    v0: jax.Array  # (P,)
    jumps: jax.Array  # (P,) breaks, rad, ascending; +inf past the last
    bins: jax.Array  # (B,) int32: the piece at each bin's start angle (:func:`._lookup.bin_table`)

    def jump_angles(self) -> jax.Array:
        return self.jumps

    def __call__(self, theta: ArrayLike) -> jax.Array:
        return self._eval(jnp, theta)

    def host(self, theta: ArrayLike) -> np.ndarray:
        return self._eval(np, theta)

    def piece_index(self, xp: ModuleType, theta: ArrayLike) -> np.ndarray | jax.Array:
        """The row of the piece each angle ``theta`` (rad, in [0, 2 pi)) lies in: numpy's search, or in a compiled
        program the same row from the bins (:func:`._lookup.interval`), without a search loop."""
        return xp.minimum(interval(xp, self.start, self.bins, theta), self.start.shape[0] - 1)

    def _eval(self, xp, theta):
        """Evaluate with jax.numpy (traceable) or numpy (no dispatch or compile cost, for validation)."""
        theta = xp.mod(xp.asarray(theta, dtype=float), TWO_PI)
        i = self.piece_index(xp, theta)
        g = lambda a: xp.asarray(a)[i]  # noqa: E731
        beta, lift = g(self.beta), g(self.lift)
        x = (theta - g(self.theta0)) / beta
        y, v, a, j = _piece_eval(
            xp, x - g(self.x0), g(self.c), g(self.w), g(self.p1), g(self.p2), g(self.y0), g(self.v0)
        )
        return xp.stack([g(self.base) + lift * y, lift * v / beta, lift * a / beta**2, lift * j / beta**3])


class Program(Motion):
    """A motion program: contiguous segments covering 0-360 degrees of cam angle.

    Build it with :meth:`Program.from_segments`. Its segments are what the warnings and reports read; compiled
    programs take its :class:`PieceTable` (:meth:`jit_form`), so a new segment list compiles nothing new.
    """

    segments: tuple[Segment, ...] = eqx.field(static=True)
    unit: str = eqx.field(static=True)
    breaks_deg: tuple[float, ...] = eqx.field(static=True)
    table: PieceTable

    @property
    def dwells_deg(self) -> tuple[tuple[float, float], ...]:
        """The dwell segments' (start, end) (deg)."""
        return tuple((seg.start, seg.end) for seg in self.segments if seg.law == "dwell")

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
        breaks = tuple(sorted({round(math.degrees(a), 12) % 360.0 for a in cols["start"]}))
        rows = padded_length(len(cols["start"]) + WINDOW, _PIECE_ROWS)  # the lookup's +inf starts past the last
        width = padded_length(max(len(c) for c in cols["c"]), _COEF_WIDTH, 2)  # the named laws' _NC, or a polynomial's
        cols["c"] = [np.pad(c, (0, width - len(c))) for c in cols["c"]]  # zero terms leave Horner's sums exact
        arrays = {k: np.array(v, dtype=float) for k, v in cols.items()}
        arrays = {k: _pad_rows(v, rows, np.inf if k == "start" else None) for k, v in arrays.items()}
        arrays["jumps"] = _pad_rows(np.deg2rad(np.asarray(breaks, dtype=float)), rows, np.inf)
        try:
            arrays["bins"] = bin_table(arrays["start"])
        except ValueError as err:
            raise InputError(
                "motion.segments", f"{err}: segments (dwells among them) that short stand for one; merge them"
            ) from None
        table = PieceTable(unit=unit, **{k: jax.device_put(v) for k, v in arrays.items()})  # jnp.asarray compiles
        return cls(segments=segs, unit=unit, breaks_deg=breaks, table=table)

    def jit_form(self) -> PieceTable:
        return self.table

    def __call__(self, theta: ArrayLike) -> jax.Array:
        return self.table(theta)

    def host(self, theta: ArrayLike) -> np.ndarray:
        return self.table.host(theta)

    def _eval(self, xp, theta):
        return self.table._eval(xp, theta)

    def derivative_jumps(self) -> tuple[tuple[float, int, float], ...]:
        """:meth:`Motion.derivative_jumps` at the segment boundaries, exactly: each segment's end by its own law
        against the next one's start."""
        return tuple((self.segments[i].end % 360.0, order, jump) for i, order, jump in self._boundary_jumps())

    def continuity_warnings(self) -> list[str]:
        """Velocity and acceleration jumps at segment boundaries (the fundamental law of cam design)."""
        # the jump in the units the segments' lift was given in: mm, or deg of arm swing (an oscillating
        # follower's motion is in rad); per radian of cam angle, as the SVAJ page plots it
        lu, to_user = self.kind.lift_unit, self.kind.lift_per_motion
        out = []
        for i, order, jump in self._boundary_jumps():
            seg, nxt = self.segments[i], self.segments[(i + 1) % len(self.segments)]
            name, unit = ("velocity", f"{lu}/rad") if order == 1 else ("acceleration", f"{lu}/rad^2")
            out.append(
                f"{name} jumps by {jump * to_user:+.4g} {unit} at {seg.end % 360.0:g} deg "
                f"({seg.law} -> {nxt.law}): infinite {'acceleration' if order == 1 else 'jerk'}"
            )
        return out

    def _boundary_jumps(self) -> list[tuple[int, int, float]]:
        """(index of the segment whose end it is, order 1 or 2, jump per rad^order) of every jump at a boundary."""
        peak = np.max(np.abs(self._eval(np, np.linspace(0.0, TWO_PI, 3601))), axis=1)
        # the right side of every boundary in one evaluation (one angle at a time: 0.3 ms each, 1000 segments)
        rights = self._eval(np, np.deg2rad(np.array([seg.end % 360.0 for seg in self.segments])))
        lefts = self.segment_ends()
        jumps = rights - lefts
        return [
            (i, order, float(jumps[order, i]))
            for i in range(len(self.segments))
            for order in (1, 2)
            if derivative_jumps_at(jumps[order, i], peak[order], lefts[order, i], rights[order, i])
        ]

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

    def segment_end(self, seg: Segment) -> np.ndarray:
        """s and its first three derivatives at ``seg``'s end by its own law (the motion's unit per rad^d): the
        left side of the boundary, where the program evaluated there gives the next segment's start."""
        return self._ends((seg,))[:, 0]

    def segment_ends(self) -> np.ndarray:
        """:meth:`segment_end` of every segment, (4, segments), in one evaluation (1000 segments: 0.1 s one by
        one)."""
        return self._ends(self.segments)

    def _ends(self, segments: tuple[Segment, ...]) -> np.ndarray:
        tables = [seg.table(self.kind.motion_per_lift) for seg in segments]
        width = max(t.c.shape[-1] for t, _ in tables)
        c = np.stack([np.pad(t.c[-1], (0, width - t.c.shape[-1])) for t, _ in tables])
        last = {k: np.array([getattr(t, k)[-1] for t, _ in tables]) for k in ("x0", "w", "p1", "p2", "y0", "v0")}
        y, v, a, j = _piece_eval(np, 1.0 - last["x0"], c, last["w"], last["p1"], last["p2"], last["y0"], last["v0"])
        lift = np.array([lift for _, lift in tables])
        base = np.array([seg.base for seg in segments])
        beta = np.radians(np.array([seg.end - seg.start for seg in segments]))
        return np.stack([base + lift * y, lift * v / beta, lift * a / beta**2, lift * j / beta**3])


def _pad_rows(a: np.ndarray, rows: int, fill: float | None = None) -> np.ndarray:
    """``a`` with ``rows`` rows: the last row repeated, or ``fill``."""
    widths = [(0, rows - len(a))] + [(0, 0)] * (a.ndim - 1)
    return np.pad(a, widths, mode="edge") if fill is None else np.pad(a, widths, constant_values=fill)


def _segment_spec(raw, where: str):
    """A segment given as a dict (or already a spec), validated as the schema's member for its law."""
    if not isinstance(raw, dict):
        return raw
    members: dict[str | None, type[SegmentSpec | PolynomialSegmentSpec | BSplineSegmentSpec]]
    members = {POLYNOMIAL: PolynomialSegmentSpec, BSPLINE: BSplineSegmentSpec}
    model = members.get(raw.get("law"), SegmentSpec)
    return parse(model, raw, where)
