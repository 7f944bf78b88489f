"""Motion programs: contiguous segments of named laws covering one cam revolution."""

from __future__ import annotations

import math
from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..._core.errors import InputError
from ..._core.units import TWO_PI
from ...schema import SegmentSpec, check_segments, parse
from ._base import Motion
from ._laws import _LAW_TABLES, _piece_eval


@dataclass(frozen=True)
class Segment:
    """One segment of a motion program: ``law`` from ``start`` to ``end`` (deg), rising by ``lift`` (mm)."""

    law: str
    start: float
    end: float
    lift: float = 0.0
    base: float = 0.0  # lift at the segment start, mm


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
        specs = [s if isinstance(s, SegmentSpec) else parse(SegmentSpec, s, f"{key}[{i}]") for i, s in enumerate(segments)]
        try:
            check_segments(specs, "mm" if unit == "mm" else "deg", key=key)
        except ValueError as err:
            where, message = str(err).split(": ", 1)
            raise InputError(where, message) from None
        return cls.from_specs(specs, unit)

    @classmethod
    def from_specs(cls, specs: list[SegmentSpec], unit: str = "mm") -> Program:
        """A program from segments the schema has checked (:func:`camdyn.schema.check_segments`)."""
        to_unit = 1.0 if unit == "mm" else math.pi / 180.0
        segs: list[Segment] = []
        start, base = 0.0, 0.0
        for s in specs:
            segs.append(Segment(s.law, start, s.end, s.lift * to_unit, base * to_unit))
            start, base = s.end, base + s.lift
        return cls._from_checked(tuple(segs), unit)

    @classmethod
    def _from_checked(cls, segs: tuple[Segment, ...], unit: str) -> Program:
        cols: dict[str, list] = {k: [] for k in ("start", "theta0", "beta", "base", "lift", "x0", "c", "w", "p1", "p2", "y0", "v0")}
        for seg in segs:
            t = _LAW_TABLES[seg.law]
            th0, beta = math.radians(seg.start), math.radians(seg.end - seg.start)
            for i in range(len(t.x0)):
                cols["start"].append(th0 + beta * t.x0[i])
                cols["theta0"].append(th0)
                cols["beta"].append(beta)
                cols["base"].append(seg.base)
                cols["lift"].append(seg.lift)
                for k in ("x0", "c", "w", "p1", "p2", "y0", "v0"):
                    cols[k].append(getattr(t, k)[i])
        breaks = tuple(sorted({round(math.degrees(a), 12) % 360.0 for a in cols["start"]}))
        arrays = {f"_{k}": jnp.asarray(np.array(v, dtype=float)) for k, v in cols.items()}
        return cls(segments=segs, unit=unit, breaks_deg=breaks, **arrays)

    def __call__(self, theta):
        return self._eval(jnp, theta)

    def _eval(self, xp, theta):
        """Evaluate with jax.numpy (traceable) or numpy (no dispatch or compile cost, for validation)."""
        start = xp.asarray(self._start)
        theta = xp.mod(xp.asarray(theta, dtype=float), TWO_PI)
        i = xp.clip(xp.searchsorted(start, theta, side="right") - 1, 0, start.shape[0] - 1)
        g = lambda a: xp.asarray(a)[i]  # noqa: E731
        beta, lift = g(self._beta), g(self._lift)
        x = (theta - g(self._theta0)) / beta
        y, v, a, j = _piece_eval(xp, x - g(self._x0), g(self._c), g(self._w), g(self._p1), g(self._p2), g(self._y0), g(self._v0))
        return xp.stack([g(self._base) + lift * y, lift * v / beta, lift * a / beta**2, lift * j / beta**3])

    def continuity_warnings(self) -> list[str]:
        """Velocity and acceleration jumps at segment boundaries (the fundamental law of cam design)."""
        out = []
        n = len(self.segments)
        # the jump in the units the segments' lift was given in: mm, or deg of arm swing (an oscillating
        # follower's motion is in rad); per radian of cam angle, as the SVAJ page plots it
        lu, to_user = ("mm", 1.0) if self.unit == "mm" else ("deg", 180.0 / math.pi)
        for i, seg in enumerate(self.segments):
            nxt = self.segments[(i + 1) % n]
            left = self._segment_end(seg)
            right = self._eval(np, np.deg2rad(seg.end % 360.0))
            for order, name, unit in ((1, "velocity", f"{lu}/rad"), (2, "acceleration", f"{lu}/rad^2")):
                jump = right[order] - left[order]
                if abs(jump) > 1e-9 * max(1.0, abs(left[order]), abs(right[order])):
                    out.append(
                        f"{name} jumps by {jump * to_user:+.4g} {unit} at {seg.end % 360.0:g} deg "
                        f"({seg.law} -> {nxt.law}): infinite {'acceleration' if order == 1 else 'jerk'}"
                    )
        return out

    def _segment_end(self, seg: Segment):
        t = _LAW_TABLES[seg.law]
        u = np.array(1.0 - t.x0[-1])
        vals = _piece_eval(np, u, t.c[-1], t.w[-1], t.p1[-1], t.p2[-1], t.y0[-1], t.v0[-1])
        beta = math.radians(seg.end - seg.start)
        return np.array([seg.base + seg.lift * vals[0], seg.lift * vals[1] / beta, seg.lift * vals[2] / beta**2, seg.lift * vals[3] / beta**3])
