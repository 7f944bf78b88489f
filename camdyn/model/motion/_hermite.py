"""Quintic Hermite tables of expensive motions: exact s, s', s'' at every knot."""

from __future__ import annotations

import threading
from collections.abc import Sequence
from types import ModuleType
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.core import Tracer
from jax.typing import ArrayLike

from ..._core.errors import NumericalError
from ..._core.jit import padded_length
from ..._core.units import TWO_PI
from ._base import Motion, evaluate
from ._lookup import WINDOW, bin_table, interval


def quintic_eval(
    xp: ModuleType,
    knots: np.ndarray | jax.Array,
    coef: np.ndarray | jax.Array,
    theta: ArrayLike,
    last: ArrayLike | None = None,
    bins: ArrayLike | None = None,
) -> Any:
    """(s, s', s'', s''') of the piecewise quintic ``coef`` (m, 6) on ``knots`` (m + 1,) rad from 0 to 2 pi, at
    theta (rad, any shape, periodic): one lookup of the interval and one gather, whatever the number of
    knots. ``xp`` is jax.numpy (traceable) or numpy (no dispatch or compile cost). ``last``: the last
    interval's index where the tables are padded past it (knots +inf there). ``bins``: the knots' bin table
    (:func:`._lookup.bin_table`: a compiled program then finds the interval without a search loop)."""
    theta = xp.asarray(theta, dtype=float)
    th = xp.mod(theta, TWO_PI)
    i = xp.minimum(interval(xp, knots, bins, th), coef.shape[0] - 1 if last is None else last)
    t = th - knots[i]
    c = coef[i]  # (..., 6)
    c0, c1, c2, c3, c4, c5 = (c[..., k] for k in range(6))
    s = c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * c5))))
    s1 = c1 + t * (2 * c2 + t * (3 * c3 + t * (4 * c4 + t * 5 * c5)))
    s2 = 2 * c2 + t * (6 * c3 + t * (12 * c4 + t * 20 * c5))
    s3 = 6 * c3 + t * (24 * c4 + t * 60 * c5)
    return xp.stack([s, s1, s2, s3])


# Compiled programs take a quintic table padded to 4096 intervals (16384, ... beyond) and its breaks padded to 1024
# (+inf past them): lift tables of any length up to that, linkages of any breaks, share one compiled program.
_INTERVAL_ROWS, _BREAK_ROWS = 4096, 1024
# The padded tables last made (:meth:`QuinticTable.padded`), by the identity of the arrays they pad
_MADE: dict[tuple, tuple[jax.Array, jax.Array, QuinticTable]] = {}
_MADE_MOST = 8
_MADE_LOCK = threading.Lock()


class QuinticTable(eqx.Module):
    """A piecewise quintic motion as compiled programs take it (:meth:`Motion.jit_form`): knots, coefficients and
    breaks as data padded to a bucketed length, so that one compiled program serves every table of a bucket."""

    knots: jax.Array  # (P + 1,) rad; +inf past the last knot
    coef: jax.Array  # (P, 6); the last interval repeated past it
    last: jax.Array  # the last interval's index
    jumps: jax.Array  # breaks (rad), +inf past the last; empty where there are none
    bins: jax.Array  # (B,) int32: the interval at each bin's start angle (:func:`._lookup.bin_table`)
    unit: str = eqx.field(static=True)

    @classmethod
    def padded(
        cls, knots: np.ndarray | jax.Array, coef: np.ndarray | jax.Array, breaks_deg: Sequence[float], unit: str
    ) -> QuinticTable:
        """The table of ``knots`` (m + 1,) and ``coef`` (m, 6), padded; traceable (a vmap over noisy coefficients).
        Made once for the same (immutable) JAX arrays: every compiled call on a motion asks for its form."""
        key = (id(knots), id(coef), tuple(breaks_deg), unit)
        with _MADE_LOCK:  # a sweep prepares programs in a thread of its own
            made = _MADE.get(key)
        if made is not None and made[0] is knots and made[1] is coef:
            return made[2]
        table = cls._padded(knots, coef, breaks_deg, unit)
        if isinstance(knots, jax.Array) and isinstance(coef, jax.Array) and not isinstance(coef, Tracer):
            with _MADE_LOCK:
                if len(_MADE) >= _MADE_MOST:
                    del _MADE[next(iter(_MADE))]
                _MADE[key] = (knots, coef, table)  # holding the arrays: their ids stay theirs while the entry lives
        return table

    @classmethod
    def _padded(
        cls, knots: np.ndarray | jax.Array, coef: np.ndarray | jax.Array, breaks_deg: Sequence[float], unit: str
    ) -> QuinticTable:
        xp = jnp if isinstance(coef, Tracer) else np  # numpy where it can: no eager dispatch
        knots, coef = xp.asarray(knots), xp.asarray(coef)
        more = padded_length(coef.shape[0] + WINDOW, _INTERVAL_ROWS) - coef.shape[0]  # the lookup's +inf knots too
        breaks = np.deg2rad(np.asarray(breaks_deg, dtype=float))
        if breaks.size:
            breaks = np.pad(breaks, (0, padded_length(breaks.size, _BREAK_ROWS) - breaks.size), constant_values=np.inf)
        # host values are placed, not staged: jnp.asarray compiles a program a shape (JAX 0.10), in every process
        put = jnp.asarray if xp is jnp else jax.device_put
        padded_knots = xp.pad(knots, (0, more), constant_values=np.inf)
        try:
            bins = bin_table(np.asarray(padded_knots))  # the knots are data, never traced
        except ValueError as err:  # uniform knots and a path's breaks among them: never seen
            raise NumericalError("the motion's quintic table", f"{err}: its knots cannot be looked up") from None
        return cls(
            knots=put(padded_knots),
            coef=put(xp.pad(coef, [(0, more), (0, 0)], mode="edge")),
            last=put(np.asarray(coef.shape[0] - 1)),
            jumps=put(breaks),
            bins=jax.device_put(bins),
            unit=unit,
        )

    def jump_angles(self) -> jax.Array:
        return self.jumps

    def __call__(self, theta: ArrayLike) -> jax.Array:
        return quintic_eval(jnp, self.knots, self.coef, theta, self.last, self.bins)

    def host(self, theta: ArrayLike) -> np.ndarray:
        return quintic_eval(np, np.asarray(self.knots), np.asarray(self.coef), theta, int(self.last))


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
        left = evaluate(source, knots[:-1] + d)  # at the start of interval i, from the right
        right = evaluate(source, knots[1:] - d)  # at its end, from the left
        y0 = np.stack(
            [
                left[0] - d * left[1] + d**2 / 2 * left[2] - d**3 / 6 * left[3],
                left[1] - d * left[2] + d**2 / 2 * left[3],
                left[2] - d * left[3],
            ]
        )
        y1 = np.stack(
            [
                right[0] + d * right[1] + d**2 / 2 * right[2] + d**3 / 6 * right[3],
                right[1] + d * right[2] + d**2 / 2 * right[3],
                right[2] + d * right[3],
            ]
        )
        # c3..c5 from the end conditions: s(h), s'(h), s''(h) less the part of c0..c2
        r0 = y1[0] - (y0[0] + y0[1] * h + y0[2] / 2 * h**2)
        r1 = y1[1] - (y0[1] + y0[2] * h)
        r2 = y1[2] - y0[2]
        c3 = (10 * r0 - 4 * h * r1 + h**2 / 2 * r2) / h**3
        c4 = (-15 * r0 + 7 * h * r1 - h**2 * r2) / h**4
        c5 = (6 * r0 - 3 * h * r1 + h**2 / 2 * r2) / h**5
        coef = np.column_stack([y0[0], y0[1], y0[2] / 2, c3, c4, c5])
        return cls(
            knots=jax.device_put(knots),
            coef=jax.device_put(coef),
            unit=source.unit,
            breaks_deg=tuple(source.breaks_deg),
        )

    def jit_form(self) -> QuinticTable:
        return QuinticTable.padded(self.knots, self.coef, self.breaks_deg, self.unit)

    def __call__(self, theta: ArrayLike) -> jax.Array:
        return quintic_eval(jnp, self.knots, self.coef, theta)

    def max_error(self, source: Motion) -> np.ndarray:
        """Largest |self - source| of (s, s', s'', s''') at the interval midpoints, where the error peaks."""
        knots = np.asarray(self.knots)
        mid = 0.5 * (knots[:-1] + knots[1:])
        return np.max(np.abs(evaluate(self, mid) - evaluate(source, mid)), axis=1)
