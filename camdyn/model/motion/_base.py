"""The one motion interface every synthesis produces and every consumer reads.

A :class:`Motion` maps cam angle theta (rad) to the follower displacement and its first three derivatives
per radian of cam angle, ``motion(theta) -> (4, *theta.shape)`` = (s, s', s'', s'''). Translating followers
use mm (``unit == "mm"``), oscillating followers the arm angle in rad (``unit == "rad"``). Every motion is a
JAX pytree (an equinox module), so dynamics, geometry and sweeps can ``jit`` and ``vmap`` over it.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import cached_jit, on_angle_buckets
from ..._core.kinds import FollowerKind, kind_of_motion
from ..._core.units import JUMP_RTOL, THETA_GRID, TWO_PI

_SIDE = 1e-9  # rad: a break's one-sided values are taken this far either side of it


class Motion(eqx.Module):
    """Follower motion over one cam revolution (abstract).

    Subclasses implement ``__call__(theta)`` returning ``jnp.stack([s, s1, s2, s3])`` for theta in rad
    (any shape; periodic with period 2 pi), and provide ``unit`` ("mm" or "rad") and ``breaks_deg``: the cam
    angles (deg, in [0, 360)) where s'' or s''' may jump, which the ODE step-size controller is told about.
    """

    unit: eqx.AbstractVar[str]
    breaks_deg: eqx.AbstractVar[tuple[float, ...]]

    def __call__(self, theta: ArrayLike) -> jax.Array:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def dwells_deg(self) -> tuple[tuple[float, float], ...]:
        """Where the follower dwells: (start, end) cam angles (deg, end > start, within 0-360), in which its
        residual vibration is judged; none unless the motion says so."""
        return ()

    @property
    def kind(self) -> FollowerKind:
        """The kind of follower this motion drives (its ``unit``: mm translating, rad oscillating)."""
        return kind_of_motion(self.unit)

    def jit_form(self) -> Motion:
        """What compiled programs take in place of this motion (:func:`camdyn._core.jit.cached_jit`): a form
        whose static structure does not depend on the case (a program's segments become padded arrays), so one
        compiled program serves every case. The motion itself where it has no other."""
        return self

    def jump_angles(self) -> np.ndarray | jax.Array:
        """The breaks (rad) as the ODE step-size controller takes them: numpy, or a padded array (+inf beyond
        the breaks) where they are data."""
        return np.deg2rad(np.asarray(self.breaks_deg, dtype=float))

    def derivative_jumps(self) -> tuple[tuple[float, int, float], ...]:
        """(cam angle deg, order 1 or 2, jump) where the velocity (order 1, the motion's unit per rad) or the
        acceleration (order 2, per rad^2) jumps at a break: by more than ``JUMP_RTOL`` of its largest magnitude
        round the cam or of either side (the fundamental law of cam design). From the values either side of each
        break; a motion that knows its pieces' ends may give them exactly."""
        breaks = np.deg2rad(np.asarray(self.breaks_deg, dtype=float))
        left, right = self.host(breaks - _SIDE), self.host(breaks + _SIDE)
        peak = np.max(np.abs(self.host(np.linspace(0.0, TWO_PI, 3601))), axis=1)
        return tuple(
            (float(deg) % 360.0, order, float(right[order, i] - left[order, i]))
            for i, deg in enumerate(self.breaks_deg)
            for order in (1, 2)
            if derivative_jumps_at(right[order, i] - left[order, i], peak[order], left[order, i], right[order, i])
        )

    def velocity_jumps(self) -> tuple[tuple[float, float], ...]:
        """(cam angle deg, jump of ds/dtheta in the motion's unit per rad) where the velocity jumps
        (:meth:`derivative_jumps`): a follower held on by a spring leaves a cam whose velocity drops there, at any
        speed, and the cam strikes one where it rises."""
        return tuple((deg, jump) for deg, order, jump in self.derivative_jumps() if order == 1)

    def host(self, theta: ArrayLike) -> np.ndarray:
        """s and its first three derivatives at ``theta`` (rad) as a numpy array of shape (4, *theta.shape): the
        compiled evaluation here; motions with a numpy form override it (no dispatch or compile cost)."""
        return np.asarray(evaluate(self, jnp.asarray(theta, dtype=float)))

    def sample(self, n: int = THETA_GRID) -> tuple[np.ndarray, np.ndarray]:
        """(theta_deg, values) on ``n`` equal steps of [0, 360); values has shape (4, n)."""
        theta_deg = np.arange(n) * (360.0 / n)
        return theta_deg, self.host(np.deg2rad(theta_deg))


def derivative_jumps_at(jump: float, peak: float, left: float, right: float) -> bool:
    """Whether a derivative's ``jump`` at a break (from ``left`` to ``right``) is one: more than ``JUMP_RTOL`` of
    the derivative's largest magnitude round the cam (``peak``) or either side."""
    return abs(jump) > JUMP_RTOL * max(float(peak), abs(left), abs(right))


@cached_jit
def _evaluate(motion: Motion, theta: ArrayLike) -> jax.Array:
    """``motion(theta)`` compiled once per motion form and shape of ``theta`` (eagerly each operation dispatches and
    compiles alone)."""
    return motion(theta)


def evaluate(motion: Motion, theta: ArrayLike) -> jax.Array | np.ndarray:
    """s and its first three derivatives at ``theta`` (rad), shape (4, *theta.shape), by a program compiled once per
    motion form and bucket of lengths (:func:`camdyn._core.jit.on_angle_buckets`: a new number of angles, a table's
    step or another case's breaks, runs a stored program; the values are the same to the bit)."""
    return on_angle_buckets(lambda t: _evaluate(motion, t), theta)
