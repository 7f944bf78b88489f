"""One built cam: its least contact force at the case speed and its dynamic jump speed, as a kernel for
:func:`camdyn._core.sharding.run_batched` (vmapped over samples, sharded over devices).

A sample is the follower's parameters (spring rate, preload, mass, train stiffness: SI), its cam speed (rad/s)
and the coefficients of its profile error (motion unit: mm or rad; cos and sin of harmonics 1..K). The force is
the sweep's: the frequency-domain steady state of the compliant model (:func:`camdyn.model.dynamics.steady_state`,
:func:`train_force`) or the kinematic force of a rigid follower, on a grid of angles with the profile error's
exact derivatives added to the motion. Damping given as a ratio follows the sample's rate and mass (as
:meth:`FollowerModel.damping_at`); the train keeps its damping ratio.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.units import TWO_PI, damping_from_ratio
from ...model.dynamics import kinematic_force_of, steady_state, train_force
from ...model.follower import FollowerModel
from ...model.motion import evaluate

if TYPE_CHECKING:
    from ...model.case import Case

SCAN_SPEEDS = 16  # speeds scanned in (0, w_max] for the first one that separates
ROOT_STEPS = 7  # then Illinois steps on that bracket (superlinear: well under 0.01 rpm)


class Grid(NamedTuple):
    """A grid of angles: the nominal motion (s, s', s'', SI), the profile-error basis and its derivatives (per
    unit coefficient, SI) and the force weight (1, or N per N*m of an arm)."""

    s: jax.Array  # (3, n)
    basis: jax.Array  # (3, 2K, n)
    weight: jax.Array  # (n,)
    spec: jax.Array  # rfft of the nominal s
    unit: jax.Array  # the motion's unit in SI (m per mm, or 1 for rad): the profile coefficients' scale


def make_grid(case: Case, n: int, harmonics: int, weight: Callable[[np.ndarray], np.ndarray]) -> Grid:
    """The :class:`Grid` of ``n`` angles for ``case``; ``weight(theta)`` is the force weight."""
    theta = np.arange(n) * (TWO_PI / n)
    s = np.asarray(evaluate(case.motion, jnp.asarray(theta)))[:3] * case.model.scale
    h = np.arange(1, harmonics + 1)[:, None]
    c, si = np.cos(h * theta), np.sin(h * theta)
    # a cos(h t) + b sin(h t) and its first two derivatives in theta, per unit a and b
    basis = (
        np.stack([np.concatenate([c, si]), np.concatenate([-h * si, h * c]), np.concatenate([-h * h * c, -h * h * si])])
        * case.model.scale
    )
    return Grid(
        jnp.asarray(s),
        jnp.asarray(basis),
        jnp.asarray(weight(theta)),
        jnp.fft.rfft(jnp.asarray(s[0])),
        jnp.asarray(case.model.scale),
    )


class Sample(NamedTuple):
    """One built cam's parameters: SI, speed in rad/s, profile coefficients in the motion's unit."""

    k: jax.Array
    f0: jax.Array
    m: jax.Array
    kf: jax.Array
    omega: jax.Array
    coeffs: jax.Array  # (2K,)


def sample_model(base: FollowerModel, p: Sample) -> FollowerModel:
    """``base`` with the sample's spring, preload, mass and train; damping ratios kept."""
    c = jnp.where(
        jnp.isnan(base.damping_ratio), base.damping, damping_from_ratio(jnp.nan_to_num(base.damping_ratio), p.k, p.m)
    )
    zeta_f = base.train_damping / damping_from_ratio(1.0, base.train_stiffness, base.mass)
    cf = jnp.where(jnp.isinf(base.train_stiffness), 0.0, damping_from_ratio(jnp.nan_to_num(zeta_f), p.kf, p.m))
    return eqx.tree_at(
        lambda m: (m.stiffness, m.preload, m.mass, m.damping, m.train_stiffness, m.train_damping),
        base,
        (p.k, p.f0, p.m, c, p.kf, cf),
    )


def _tables(grid: Grid, p: Sample):
    """The sample's motion on the grid (s, s', s'': SI, the profile error added) and the rfft of s: the nominal
    spectrum plus the error's harmonics (rfft of a cos(h t) + b sin(h t) on n angles: n (a - i b) / 2 at h)."""
    s, s1, s2 = grid.s + jnp.einsum("dkn,k->dn", grid.basis, p.coeffs)
    k2, n = p.coeffs.shape[0] // 2, s.shape[0]
    spec = grid.spec.at[1 : k2 + 1].add(0.5 * n * grid.unit * (p.coeffs[:k2] - 1j * p.coeffs[k2:]))
    return s, s1, s2, spec


def _min_force(md: FollowerModel, tabs, weight, omega, rigid: bool):
    s, s1, s2, spec = tabs
    if rigid:
        force = kinematic_force_of(md, omega, s, s1, s2)
    else:
        x, x1 = steady_state(spec, omega, md, md.stiffness, md.damping, s.shape[0])
        force = train_force(md, omega, s, s1, x, x1)
    return jnp.min(force * weight)


def min_force(base: FollowerModel, grid: Grid, p: Sample, omega: ArrayLike, rigid: bool) -> jax.Array:
    """Least interface force (N, weighted) of the in-contact model of sample ``p`` at ``omega`` (rad/s)."""
    return _min_force(sample_model(base, p), _tables(grid, p), grid.weight, omega, rigid)


def jump_speed(base: FollowerModel, grid: Grid, p: Sample, w_max: ArrayLike, rigid: bool) -> jax.Array:
    """Least speed (rad/s) whose least force is <= 0: the first of ``SCAN_SPEEDS`` in (0, w_max], then the
    Illinois method (regula falsi) on that bracket; inf where none is."""
    md, tabs = sample_model(base, p), _tables(grid, p)
    f_at = lambda w: _min_force(md, tabs, grid.weight, w, rigid)  # noqa: E731
    speeds = w_max * jnp.arange(1, SCAN_SPEEDS + 1) / SCAN_SPEEDS
    f = jax.vmap(f_at)(speeds)
    hit = f <= 0.0
    i = jnp.argmax(hit)
    prev = jnp.maximum(i - 1, 0)
    lo, hi = jnp.where(i > 0, speeds[prev], 0.0), speeds[i]
    f_lo = jnp.where(i > 0, f[prev], _min_force(md, tabs, grid.weight, 0.0, rigid))
    f_hi = f[i]

    def illinois(
        _: Any, b: tuple[jax.Array, jax.Array, jax.Array, jax.Array, jax.Array]
    ) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array, jax.Array]:
        lo, hi, f_lo, f_hi, side = b
        w = jnp.clip(hi - f_hi * (hi - lo) / jnp.where(f_hi != f_lo, f_hi - f_lo, 1.0), lo, hi)
        w = jnp.where((w <= lo) | (w >= hi), 0.5 * (lo + hi), w)
        fw = f_at(w)
        below = fw <= 0.0
        # Illinois: halve the stale end's value when the same end moves twice
        f_lo2 = jnp.where(below & (side < 0), 0.5 * f_lo, f_lo)
        f_hi2 = jnp.where(~below & (side > 0), 0.5 * f_hi, f_hi)
        return (
            jnp.where(below, lo, w),
            jnp.where(below, w, hi),
            jnp.where(below, f_lo2, fw),
            jnp.where(below, fw, f_hi2),
            jnp.where(below, -1, 1),
        )

    lo, hi, *_ = jax.lax.fori_loop(0, ROOT_STEPS, illinois, (lo, hi, f_lo, f_hi, 0))
    return jnp.where(jnp.any(hit), hi, jnp.inf)


def _both(const, p: Sample, rigid: bool):
    base, fine, scan, w_max = const
    return min_force(base, fine, p, p.omega, rigid), jump_speed(base, scan, p, w_max, rigid)


def tolerance_kernel(
    const: tuple[FollowerModel, Grid, Grid, jax.Array],
    k: jax.Array,
    f0: jax.Array,
    m: jax.Array,
    kf: jax.Array,
    omega: jax.Array,
    coeffs: jax.Array,
) -> tuple[jax.Array, jax.Array]:
    """Per sample of a compliant follower: (least force at its speed on the fine grid, N; jump speed on the scan
    grid, rad/s). ``const = (nominal model, fine Grid, scan Grid, w_max)``."""
    return _both(const, Sample(k, f0, m, kf, omega, coeffs), False)


def rigid_tolerance_kernel(
    const: tuple[FollowerModel, Grid, Grid, jax.Array],
    k: jax.Array,
    f0: jax.Array,
    m: jax.Array,
    kf: jax.Array,
    omega: jax.Array,
    coeffs: jax.Array,
) -> tuple[jax.Array, jax.Array]:
    """:func:`tolerance_kernel` of a rigid follower (the kinematic force)."""
    return _both(const, Sample(k, f0, m, kf, omega, coeffs), True)
