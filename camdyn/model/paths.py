"""Closed target paths for path-generation synthesis: the ``[path]`` table.

A :class:`Path` maps the path parameter u (any real; period 1, one loop per unit) to a point (x, y) in mm.
Every path is a JAX pytree (an equinox module) written with smooth closed-form pieces, so autodiff gives
exact derivatives d^k P / du^k wherever the curve is smooth. ``breaks_u`` lists the parameters where a
derivative of order two or more jumps (curvature jumps between a straight and an arc, the knots of a cubic
spline); ``sharp_u`` those where the tangent direction itself jumps (a rectangle with ``corner_radius = 0``).

The parametrizations are chosen to be smooth where the curve is: straights and arcs by arc length, the
ellipse, circle and figure eight by their angle, the line ``start -> end -> start`` harmonically (the point
comes to rest at the two ends, so the tangent never jumps), the precision points by chord length.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.experimental import jet
from jax.typing import ArrayLike

from .._core.errors import InputError
from .._core.jit import device_array
from .._core.units import TWO_PI
from ..schema import PathSpec, parse

_CHAIN_PIECES = 12
_SPLINE_PIECES = 64  # precision points padded to a multiple of this: splines of up to 64 points share one program


def parse_path(path: dict | PathSpec) -> PathSpec:
    """A validated ``[path]`` table (a :class:`camdyn.schema.PathSpec`); errors name ``path.<key>``."""
    return path if isinstance(path, PathSpec) else parse(PathSpec, path, "path")


# ------------------------------------------------------------------------------------------------ paths
def _pad_nan(v, block: int = 64) -> np.ndarray:
    v = np.asarray(v, dtype=float).reshape(-1)
    return np.concatenate([v, np.full(-(-max(len(v), 1) // block) * block - len(v), np.nan)])


def _rot(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s], [s, c]])


class Path(eqx.Module):
    """A closed curve P(u), period 1 in u, in mm (abstract).

    Subclasses implement ``_local(v)`` for a scalar v in [0, 1); ``point(u)`` applies the start shift and the
    direction (``phase``, ``reverse``). ``__call__`` takes any shape of u and returns ``(*u.shape, 2)``.
    """

    phase: float = eqx.field(static=True)
    sign: float = eqx.field(static=True)  # +1 as defined, -1 reversed
    # NaN-padded arrays, not static fields: paths that differ only in their breaks (a corner radius, sharp or
    # not) share compiled code
    local_breaks: np.ndarray = eqx.field(converter=lambda v: _pad_nan(v))
    local_sharp: np.ndarray = eqx.field(converter=lambda v: _pad_nan(v))

    def _local(self, v):  # pragma: no cover - abstract
        raise NotImplementedError

    def point(self, u: ArrayLike) -> jax.Array:
        """P(u) for a scalar u, mm (differentiable)."""
        return self._local(jnp.mod(self.phase + self.sign * u, 1.0))

    def __call__(self, u: ArrayLike) -> jax.Array:
        u = jnp.asarray(u, dtype=float)
        return jax.vmap(self.point)(u.ravel()).reshape(*u.shape, 2)

    def _to_u(self, v) -> tuple[float, ...]:
        v = np.asarray(v)
        return tuple(sorted({round(((float(b) - self.phase) * self.sign) % 1.0, 15) % 1.0 for b in v[~np.isnan(v)]}))

    @property
    def breaks_u(self) -> tuple[float, ...]:
        """Parameters where the curvature (or a higher derivative) jumps."""
        return self._to_u(self.local_breaks)

    @property
    def sharp_u(self) -> tuple[float, ...]:
        """Parameters where the tangent direction jumps (sharp corners)."""
        return self._to_u(self.local_sharp)

    def derivatives(self, u: ArrayLike, order: int = 3) -> jax.Array:
        """(P, P', ..., P^(order)) at scalar u by nested forward-mode autodiff: shape (order + 1, 2)."""
        return jnp.stack(taylor(self.point, u, order))


def taylor(f: Callable[[jax.Array], jax.Array], x: ArrayLike, order: int) -> list[jax.Array]:
    """[f(x), f'(x), ..., f^(order)(x)] of a scalar-argument function (Taylor-mode autodiff, ``jax.experimental.jet``).

    One propagation of the truncated series instead of ``order`` nested ``jvp`` passes: the traced program
    grows linearly, not exponentially, with the order (it keeps compile times short).
    """
    x = jnp.asarray(x, dtype=float)
    if order == 0:
        return [f(x)]
    seed = (jnp.ones_like(x),) + (jnp.zeros_like(x),) * (order - 1)
    y, ys = jet.jet(f, (x,), (seed,))
    return [y] + list(ys)


def _piece(knots, v):
    """Index of the piece of sorted ``knots`` that holds v (a comparison count: Taylor-mode friendly)."""
    return jnp.sum(v >= knots) - 1  # knots[0] = 0 <= v < 1: always a valid index (no clip: jet has no int max rule)


class Trig(Path):
    """P(v) = c + sum_{k=1,2} (A_k cos(2 pi k v) + B_k sin(2 pi k v)): ellipse, circle, figure eight, line.

    One class for the four smooth closed curves, so they share one compiled program.
    """

    center: jax.Array  # (2,)
    a: jax.Array  # (2, 2): A_1, A_2
    b: jax.Array  # (2, 2): B_1, B_2

    def _local(self, v):
        w = TWO_PI * v
        cos = jnp.stack([jnp.cos(w), jnp.cos(2.0 * w)])
        sin = jnp.stack([jnp.sin(w), jnp.sin(2.0 * w)])
        return self.center + cos @ self.a + sin @ self.b


class Chain(Path):
    """Closed chain of straights and circular arcs (tangent-continuous unless sharp), by arc length.

    Piece i starts at ``v0[i]`` at point ``p0[i]`` heading ``head[i]`` (rad) with curvature ``kappa[i]``
    (1/mm, 0 for a straight; arcs turn anticlockwise); ``total`` is the perimeter, mm.
    """

    v0: jax.Array
    p0: jax.Array
    head: jax.Array
    kappa: jax.Array
    total: jax.Array

    def _local(self, v):
        i = _piece(self.v0, v)
        sigma = (v - self.v0[i]) * self.total
        k, h = self.kappa[i], self.head[i]
        straight = k == 0.0
        k_safe = jnp.where(straight, 1.0, k)  # keep the unused branch finite for autodiff
        along = jnp.where(straight, sigma, jnp.sin(k_safe * sigma) / k_safe)
        across = jnp.where(straight, 0.0, (1.0 - jnp.cos(k_safe * sigma)) / k_safe)
        c, s = jnp.cos(h), jnp.sin(h)
        return self.p0[i] + jnp.stack([c * along - s * across, s * along + c * across])


class Spline(Path):
    """Periodic cubic spline through precision points, chord-length parametrized (C2; jerk jumps at knots)."""

    knots: jax.Array  # (n + 1,) in [0, 1], then 2 (never reached) up to a multiple of _SPLINE_PIECES
    coef: jax.Array  # (n, 4, 2): P = sum_k coef[i, k] (v - knot_i)^(3 - k); zeros past them

    def _local(self, v):
        i = _piece(self.knots, v)  # v < 1 = knots[n]: never the last knot nor the padding
        x = v - self.knots[i]
        c = self.coef[i]
        return ((c[0] * x + c[1]) * x + c[2]) * x + c[3]


def _chain(pieces: list, start: np.ndarray, head0: float, joints_sharp: bool, first_is_break: bool, **kw) -> Chain:
    """Chain of ("line", length) / ("arc", (radius, turn_rad)) pieces from ``start`` heading ``head0`` (rad).

    Every joint between pieces is a curvature break; with ``joints_sharp`` (zero-radius arcs) also a
    tangent break. ``first_is_break``: the start point itself is a joint (the chain starts at a piece end).
    """
    v0, p0, head, kappa, lengths = [], [], [], [], []
    p, h = np.asarray(start, dtype=float), head0
    for kind, val in pieces:
        if kind == "line":
            length, k, end = val, 0.0, p + val * np.array([math.cos(h), math.sin(h)])
            turn = 0.0
        else:
            radius, turn = val
            if radius == 0.0:  # sharp corner: no arc, only the heading turns
                h += turn
                continue
            length, k = radius * turn, 1.0 / radius
            along, across = radius * math.sin(turn), radius * (1.0 - math.cos(turn))
            end = p + along * np.array([math.cos(h), math.sin(h)]) + across * np.array([-math.sin(h), math.cos(h)])
        p0.append(p.copy())
        head.append(h)
        kappa.append(k)
        lengths.append(length)
        p, h = end, h + turn
    total = float(sum(lengths))
    v0 = np.concatenate([[0.0], np.cumsum(lengths)[:-1]]) / total
    joints = ((0.0,) if first_is_break else ()) + tuple(float(v) for v in v0[1:])
    pad = _CHAIN_PIECES - len(v0)  # a fixed piece count: every chain shares one compiled program
    p0, head, kappa = np.array(p0), np.array(head), np.array(kappa)
    v0 = np.concatenate([v0, np.full(pad, 2.0)])  # v < 1 never reaches the padding
    p0, head, kappa = (
        np.vstack([p0, np.zeros((pad, 2))]),
        np.append(head, np.zeros(pad)),
        np.append(kappa, np.zeros(pad)),
    )
    return Chain(
        v0=device_array(v0),
        p0=device_array(p0),
        head=device_array(head),
        kappa=device_array(kappa),
        total=device_array(total),
        local_breaks=joints,
        local_sharp=joints if joints_sharp else (),
        **kw,
    )


def build_path(spec: PathSpec | dict) -> Path:
    """The :class:`Path` of a validated ``[path]`` table."""
    if isinstance(spec, dict):
        spec = parse_path(spec)
    common = dict(phase=spec.phase, sign=-1.0 if spec.reverse else 1.0)
    rot = _rot(spec.rotation)
    c = np.asarray(spec.center if spec.center is not None else (0.0, 0.0), dtype=float)
    t = spec.type
    if t in ("ellipse", "circle", "eight", "line"):
        a, b = np.zeros((2, 2)), np.zeros((2, 2))
        if t in ("ellipse", "circle"):  # x = a cos w, y = b sin w: starts at the end of the first axis
            ax, by = (spec.semi_major, spec.semi_minor) if t == "ellipse" else (spec.radius, spec.radius)
            a[0], b[0] = rot @ [ax, 0.0], rot @ [0.0, by]
        elif t == "eight":  # x = W/2 sin w, y = H/2 sin 2w: starts at the crossing
            assert spec.width is not None and spec.height is not None  # the schema: an eight needs them
            b[0], b[1] = rot @ [spec.width / 2, 0.0], rot @ [0.0, spec.height / 2]
        else:  # start + (end - start)(1 - cos w)/2: at rest at both ends, no tangent jump
            p0, p1 = np.asarray(spec.start, dtype=float), np.asarray(spec.end, dtype=float)
            c, a[0] = (p0 + p1) / 2.0, -(p1 - p0) / 2.0
        return Trig(
            center=device_array(c), a=device_array(a), b=device_array(b), local_breaks=(), local_sharp=(), **common
        )
    if t == "rectangle":
        w, h, r = spec.width, spec.height, spec.corner_radius or 0.0
        assert w is not None and h is not None  # the schema: a rectangle needs them
        quarter = ("arc", (r, math.pi / 2))
        pieces = [
            ("line", h / 2 - r),
            quarter,
            ("line", w - 2 * r),
            quarter,
            ("line", h - 2 * r),
            quarter,
            ("line", w - 2 * r),
            quarter,
            ("line", h / 2 - r),
        ]
        pieces = [p for p in pieces if p[0] == "arc" or p[1] > 0.0]
        head0 = math.radians(spec.rotation) + math.pi / 2
        return _chain(pieces, c + rot @ np.array([w / 2, 0.0]), head0, r == 0.0, False, **common)
    if t == "racetrack":
        r, length = spec.radius, spec.straight
        assert r is not None and length is not None  # the schema: a racetrack needs them
        half = ("arc", (r, math.pi))
        g = c + rot @ np.array([length / 2, -r])  # lower end of the right semicircle: Ye & Smith's F0
        return _chain(
            [half, ("line", length), half, ("line", length)], g, math.radians(spec.rotation), False, True, **common
        )
    # points: periodic cubic spline, chord-length knots (scipy.interpolate loads here only: 0.3 s)
    from scipy.interpolate import CubicSpline

    assert spec.x is not None and spec.y is not None  # the schema: points need them
    pts = np.column_stack([spec.x, spec.y]).astype(float)
    if np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    closed = np.vstack([pts, pts[:1]])
    chord = np.linalg.norm(np.diff(closed, axis=0), axis=1)
    if np.any(chord == 0.0):
        i = int(np.argmin(chord))
        raise InputError(f"path.x[{i + 1}]", f"precision point {i + 1} repeats point {i}")
    knots = np.concatenate([[0.0], np.cumsum(chord)]) / chord.sum()
    cs = CubicSpline(knots, closed, bc_type="periodic")
    coef = np.transpose(cs.c, (1, 0, 2))  # (n, 4, 2)
    pad = -(-len(coef) // _SPLINE_PIECES) * _SPLINE_PIECES - len(coef)
    return Spline(
        knots=device_array(np.concatenate([knots, np.full(pad, 2.0)])),
        coef=device_array(np.concatenate([coef, np.zeros((pad, 4, 2))])),
        local_breaks=tuple(float(k) for k in knots[:-1]),
        local_sharp=(),
        **common,
    )
