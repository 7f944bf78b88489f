"""Follower motion: the one interface every synthesis produces and every consumer reads.

A :class:`Motion` maps cam angle theta (rad) to the follower displacement and its first three derivatives
per radian of cam angle, ``motion(theta) -> (4, *theta.shape)`` = (s, s', s'', s'''). Translating followers
use mm (``unit == "mm"``), oscillating followers the arm angle in rad (``unit == "rad"``). Every motion is a
JAX pytree (an equinox module), so dynamics, geometry and sweeps can ``jit`` and ``vmap`` over it.

:class:`Program` is the motion-program synthesis (dwell / rise / return segments). Every law is written as
acceleration pieces of the form ``a(u) = sum_k c_k u^k + p1 cos(w u) + p2 sin(w u)`` on the normalized
rise ``x in [0, 1]``; velocity and displacement are their exact integrals, so s, s', s'', s''' are closed form
for all nine laws (and the tests check them against autodiff).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .errors import InputError
from .programs import cached_jit

TWO_PI = 2.0 * math.pi


class Motion(eqx.Module):
    """Follower motion over one cam revolution (abstract).

    Subclasses implement ``__call__(theta)`` returning ``jnp.stack([s, s1, s2, s3])`` for theta in rad
    (any shape; periodic with period 2 pi), and provide ``unit`` ("mm" or "rad") and ``breaks_deg``: the cam
    angles (deg, in [0, 360)) where s'' or s''' may jump, which the ODE step-size controller is told about.
    """

    unit: eqx.AbstractVar[str]
    breaks_deg: eqx.AbstractVar[tuple[float, ...]]

    def __call__(self, theta):  # pragma: no cover - abstract
        raise NotImplementedError

    def sample(self, n: int = 3600) -> tuple[np.ndarray, np.ndarray]:
        """(theta_deg, values) on ``n`` equal steps of [0, 360); values has shape (4, n)."""
        theta_deg = np.arange(n) * (360.0 / n)
        return theta_deg, np.asarray(evaluate(self, jnp.deg2rad(theta_deg)))


@cached_jit
def evaluate(motion: Motion, theta):
    """``motion(theta)`` compiled once per motion structure (eager evaluation dispatches op by op)."""
    return motion(theta)


# ----------------------------------------------------------------------------------------------- laws
@dataclass(frozen=True)
class _Piece:
    """Acceleration piece on x in [x0, x1]: a(u) = sum c_k u^k + p1 cos(w u) + p2 sin(w u), u = x - x0."""

    x0: float
    x1: float
    c: tuple[float, ...] = ()
    w: float = 0.0
    p1: float = 0.0
    p2: float = 0.0


_NC = 6  # polynomial coefficients per piece (4567 acceleration is quintic)
_PI = math.pi

# Unit-amplitude acceleration shapes; amplitudes are rescaled below so that y(1) = 1.
_LAW_PIECES: dict[str, tuple[list[_Piece], float]] = {
    # law: (pieces, initial normalized velocity)
    "dwell": ([_Piece(0.0, 1.0)], 0.0),
    "constant-velocity": ([_Piece(0.0, 1.0)], 1.0),
    "constant-acceleration": ([_Piece(0.0, 0.5, (1.0,)), _Piece(0.5, 1.0, (-1.0,))], 0.0),
    "harmonic": ([_Piece(0.0, 1.0, w=_PI, p1=1.0)], 0.0),
    "cycloidal": ([_Piece(0.0, 1.0, w=2 * _PI, p2=1.0)], 0.0),
    "polynomial-345": ([_Piece(0.0, 1.0, (0.0, 60.0, -180.0, 120.0))], 0.0),
    "polynomial-4567": ([_Piece(0.0, 1.0, (0.0, 0.0, 420.0, -1680.0, 2100.0, -840.0))], 0.0),
    # Norton: sine ramps of period 1/2 joined by constant acceleration (peak Ca = 4.8881)
    "modified-trapezoid": (
        [
            _Piece(0.0, 0.125, w=4 * _PI, p2=1.0),
            _Piece(0.125, 0.375, (1.0,)),
            _Piece(0.375, 0.625, w=4 * _PI, p1=1.0),
            _Piece(0.625, 0.875, (-1.0,)),
            _Piece(0.875, 1.0, w=4 * _PI, p1=-1.0),
        ],
        0.0,
    ),
    # Norton: sine of period 1/2 for the first and last eighths, period 3/2 between (peak Ca = 5.5280)
    "modified-sine": (
        [
            _Piece(0.0, 0.125, w=4 * _PI, p2=1.0),
            _Piece(0.125, 0.875, w=4 * _PI / 3, p1=1.0),
            _Piece(0.875, 1.0, w=4 * _PI, p1=-1.0),
        ],
        0.0,
    ),
}

LAWS: tuple[str, ...] = tuple(_LAW_PIECES)


def _piece_eval(xp, u, c, w, p1, p2, y0, v0):
    """Normalized y, y', y'', y''' of one piece at local coordinate u (works for numpy and jax arrays)."""
    k = np.arange(_NC)

    def horner(coef):  # sum_i coef[..., i] u^i, without powers (autodiff-safe at u = 0)
        acc = coef[..., -1]
        for i in range(coef.shape[-1] - 2, -1, -1):
            acc = acc * u + coef[..., i]
        return acc

    a = horner(c)
    j = horner((c * k)[..., 1:])
    v = u * horner(c / (k + 1))
    y = u * u * horner(c / ((k + 1) * (k + 2)))
    wu = w * u
    s, co = xp.sin(wu), xp.cos(wu)
    a = a + p1 * co + p2 * s
    j = j - p1 * w * s + p2 * w * co
    v = v0 + v + (p1 / w) * s + (p2 / w) * (1.0 - co)
    y = y0 + v0 * u + y + (p1 / w**2) * (1.0 - co) + (p2 / w**2) * (wu - s)
    return y, v, a, j


@dataclass(frozen=True)
class _LawTable:
    """Numeric piece table of one law, normalized so that y(0) = 0 and y(1) = 1 (0 for dwell)."""

    x0: np.ndarray
    c: np.ndarray  # (n, _NC)
    w: np.ndarray
    p1: np.ndarray
    p2: np.ndarray
    y0: np.ndarray
    v0: np.ndarray


def _build_law(name: str) -> _LawTable:
    pieces, v_start = _LAW_PIECES[name]
    n = len(pieces)
    c = np.zeros((n, _NC))
    for i, p in enumerate(pieces):
        c[i, : len(p.c)] = p.c
    w = np.array([p.w if p.w else 1.0 for p in pieces])
    p1 = np.array([p.p1 for p in pieces])
    p2 = np.array([p.p2 for p in pieces])
    x0 = np.array([p.x0 for p in pieces])
    y0, v0 = np.zeros(n), np.zeros(n)
    y, v = 0.0, v_start
    for i, p in enumerate(pieces):  # integrate piece by piece so that y and y' are continuous
        y0[i], v0[i] = y, v
        yy, vv, _, _ = _piece_eval(np, np.array(p.x1 - p.x0), c[i], w[i], p1[i], p2[i], y, v)
        y, v = float(yy), float(vv)
    if name != "dwell":
        scale = 1.0 / y
        c, p1, p2, y0, v0 = c * scale, p1 * scale, p2 * scale, y0 * scale, v0 * scale
    return _LawTable(x0, c, w, p1, p2, y0, v0)


_LAW_TABLES = {name: _build_law(name) for name in LAWS}


def law(name: str, x):
    """Normalized law ``name`` at x in [0, 1]: (y, y', y'', y''') with y(0) = 0, y(1) = 1."""
    t = _LAW_TABLES[name]
    x = jnp.asarray(x, dtype=float)
    i = jnp.clip(jnp.searchsorted(jnp.asarray(t.x0), x, side="right") - 1, 0, len(t.x0) - 1)
    g = lambda a: jnp.asarray(a)[i]  # noqa: E731
    return jnp.stack(_piece_eval(jnp, x - g(t.x0), g(t.c), g(t.w), g(t.p1), g(t.p2), g(t.y0), g(t.v0)))


# ------------------------------------------------------------------------------------------- program
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
    def from_segments(cls, segments: list[dict], key: str = "motion.segments", unit: str = "mm") -> Program:
        """Validate ``[{law, end, lift}, ...]`` (deg; lift in mm, or in deg of arm swing when unit is "rad").

        Raises :class:`InputError` naming the segment for an unknown law, a non-increasing end, a program
        that does not end at 360 degrees, does not close (net lift 0) or dips below zero lift.
        """
        if not segments:
            raise InputError(key, "at least one segment is required")
        segs: list[Segment] = []
        start, base = 0.0, 0.0
        lu = "mm" if unit == "mm" else "deg"
        to_unit = 1.0 if unit == "mm" else math.pi / 180.0
        for i, raw in enumerate(segments):
            where = f"{key}[{i}]"
            name, end, lift = raw["law"], float(raw["end"]), float(raw.get("lift", 0.0))  # lift in lu
            if name not in _LAW_TABLES:
                from difflib import get_close_matches

                hint = get_close_matches(name, LAWS, n=1)
                raise InputError(
                    f"{where}.law",
                    f"unknown law {name!r}" + (f" (did you mean {hint[0]!r}?)" if hint else "")
                    + f"; valid laws: {', '.join(LAWS)}",
                )
            if not end > start:
                what = "overlaps the previous segment" if end < start else "has zero length"
                raise InputError(f"{where}.end", f"segment ends at {end:g} deg, {what} (starts at {start:g} deg)")
            if end > 360.0 + 1e-9:
                raise InputError(f"{where}.end", f"segment ends at {end:g} deg, past 360 deg")
            if name == "dwell" and lift != 0.0:
                raise InputError(f"{where}.lift", f"a dwell cannot lift (got lift = {lift:g} {lu})")
            if name != "dwell" and lift == 0.0:
                raise InputError(f"{where}.lift", f"a {name} segment needs a non-zero lift, {lu}")
            segs.append(Segment(name, start, end, lift * to_unit, base * to_unit))
            if base + lift < -1e-9:
                raise InputError(
                    f"{where}.lift", f"the follower goes below zero lift at {end:g} deg (lift {base + lift:g} {lu})"
                )
            start, base = end, base + lift
        if abs(start - 360.0) > 1e-9:
            raise InputError(f"{key}[{len(segs) - 1}].end", f"the last segment ends at {start:g} deg, not 360")
        if abs(base) > 1e-9:
            raise InputError(key, f"the program does not close: net lift is {base:g} {lu}, must be 0")
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


# ------------------------------------------------------------------------------------ tabulated motion
class HermiteMotion(Motion):
    """Piecewise quintic Hermite interpolant of another motion: exact s, s', s'' at every knot.

    Motions whose every evaluation is expensive (a cam-linkage synthesis solves its dyads and a Newton
    iteration per angle) are tabulated once for the consumers that evaluate them millions of times (the ODE
    right-hand side, sweeps). The interpolant is C2 between knots and takes one-sided values at the source's
    ``breaks_deg``, where s'' may jump; its error is O(h^6) in s (measured by :meth:`max_error`).
    """

    knots: jax.Array  # (m + 1,) rad, 0 .. 2 pi, the source's breaks among them
    coef: jax.Array  # (m, 6) s = sum coef[i, k] t^k, t = theta - knots[i] (rad)
    unit: str = eqx.field(static=True)
    breaks_deg: tuple[float, ...] = eqx.field(static=True)

    @classmethod
    def from_motion(cls, source: Motion, n: int = 2048) -> HermiteMotion:
        """Tabulate ``source`` on ``n`` equal steps of the revolution plus its breaks."""
        grid = np.linspace(0.0, TWO_PI, n + 1)
        brk = np.deg2rad(np.asarray(source.breaks_deg, dtype=float))
        brk = brk[(brk > 1e-9) & (brk < TWO_PI - 1e-9)]
        # a grid knot within a tenth of a step of a break would leave a sliver interval: the break replaces it
        keep = np.array([np.all(np.abs(g - brk) > 0.1 * TWO_PI / n) for g in grid])
        keep[[0, -1]] = True
        knots = np.unique(np.concatenate([grid[keep], brk]))
        h = np.diff(knots)
        # one-sided values: evaluate just inside each interval and step back by Taylor to the knot
        d = 1e-7 * h
        left = np.asarray(evaluate(source, jnp.asarray(knots[:-1] + d)))  # at the start of interval i, from the right
        right = np.asarray(evaluate(source, jnp.asarray(knots[1:] - d)))  # at its end, from the left
        y0 = np.stack([left[0] - d * left[1] + d**2 / 2 * left[2] - d**3 / 6 * left[3],
                       left[1] - d * left[2] + d**2 / 2 * left[3], left[2] - d * left[3]])
        y1 = np.stack([right[0] + d * right[1] + d**2 / 2 * right[2] + d**3 / 6 * right[3],
                       right[1] + d * right[2] + d**2 / 2 * right[3], right[2] + d * right[3]])
        # c3..c5 from the end conditions: s(h), s'(h), s''(h) less the part of c0..c2
        r0 = y1[0] - (y0[0] + y0[1] * h + y0[2] / 2 * h**2)
        r1 = y1[1] - (y0[1] + y0[2] * h)
        r2 = y1[2] - y0[2]
        c3 = (10 * r0 - 4 * h * r1 + h**2 / 2 * r2) / h**3
        c4 = (-15 * r0 + 7 * h * r1 - h**2 * r2) / h**4
        c5 = (6 * r0 - 3 * h * r1 + h**2 / 2 * r2) / h**5
        coef = np.column_stack([y0[0], y0[1], y0[2] / 2, c3, c4, c5])
        return cls(knots=jnp.asarray(knots), coef=jnp.asarray(coef), unit=source.unit, breaks_deg=tuple(source.breaks_deg))

    def __call__(self, theta):
        theta = jnp.asarray(theta, dtype=float)
        th = jnp.mod(theta, TWO_PI)
        i = jnp.clip(jnp.searchsorted(self.knots, th, side="right") - 1, 0, self.coef.shape[0] - 1)
        t = th - self.knots[i]
        c = self.coef[i]  # (..., 6)
        c0, c1, c2, c3, c4, c5 = (c[..., k] for k in range(6))
        s = c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * c5))))
        s1 = c1 + t * (2 * c2 + t * (3 * c3 + t * (4 * c4 + t * 5 * c5)))
        s2 = 2 * c2 + t * (6 * c3 + t * (12 * c4 + t * 20 * c5))
        s3 = 6 * c3 + t * (24 * c4 + t * 60 * c5)
        return jnp.stack([s, s1, s2, s3])

    def max_error(self, source: Motion) -> np.ndarray:
        """Largest |self - source| of (s, s', s'', s''') at the interval midpoints, where the error peaks."""
        mid = jnp.asarray(0.5 * (np.asarray(self.knots[:-1]) + np.asarray(self.knots[1:])))
        return np.max(np.abs(np.asarray(evaluate(self, mid)) - np.asarray(evaluate(source, mid))), axis=1)
