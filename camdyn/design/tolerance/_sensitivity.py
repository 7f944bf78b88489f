"""The jump-speed margin's sensitivity to each tolerance: linearised from JAX gradients at the nominal design,
and the Monte Carlo variance shares it is set against.

The margin is ``jump speed / cam speed``. At the nominal jump speed w* the least force F(w, p) is 0, so
``dw*/dp = -(dF/dp) / (dF/dw)`` (implicit function; gradients of the kernel's own least force on the scan
grid). A key's sensitivity is ``d margin / d p x sigma`` (signed; for the profile error, whose coefficients
are independent, the root sum of squares over them). The Monte Carlo shares come from a least-squares fit of
the samples' margin on their deviations: the variance of each key's linear part over the margin's variance.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
import numpy as np

from ..._core.jit import cached_jit, device_array
from ._kernel import Grid, Sample, jump_speed, min_force

if TYPE_CHECKING:
    from ...model.follower import FollowerModel


@cached_jit
def nominal_derivatives(
    base: FollowerModel, scan: Grid, nominal: Sample, w_max: jax.Array, rigid: bool
) -> tuple[jax.Array, jax.Array, Sample]:
    """The nominal design's jump speed w* (rad/s, inf if none up to ``w_max``) on the scan grid, and the
    derivatives of its least force F there: dF/dw and dF/dp (a :class:`Sample` of them). One compiled program,
    stored: evaluated op by op, each operation compiled alone (about 4 s a ``tolerance`` run)."""
    w_star = jump_speed(base, scan, nominal, w_max, rigid)
    w = jnp.where(jnp.isfinite(w_star), w_star, w_max)  # a finite speed to differentiate at; unread where inf
    f_w = jax.grad(lambda w_: min_force(base, scan, nominal, w_, rigid))(w)
    return w_star, f_w, jax.grad(lambda p: min_force(base, scan, p, w, rigid))(nominal)


def gradient_sensitivities(
    base: FollowerModel, scan: Grid, nominal: Sample, w_max: float, sigma_si: dict[str, float], rigid: bool
) -> tuple[dict[str, float], float]:
    """``d margin / d p x sigma`` per key of ``sigma_si`` (SI sigmas; the profile error's per coefficient), NaN
    for every key where the nominal design has no jump speed up to ``w_max`` (rad/s); and that jump speed w*
    (rad/s, inf if none)."""
    w_star, f_w, g = nominal_derivatives(base, scan, nominal, device_array(w_max), rigid)
    w_star = float(w_star)
    if not math.isfinite(w_star):
        return {key: math.nan for key in sigma_si}, w_star
    f_w = float(f_w)
    omega = float(nominal.omega)
    dm = {"spring_rate": float(g.k), "preload": float(g.f0), "mass": float(g.m), "train_stiffness": float(g.kf)}
    out = {}
    for key, sig in sigma_si.items():
        if key == "speed":
            out[key] = -w_star / omega**2 * sig  # the jump speed does not move with the cam speed
        elif key == "profile_error":
            out[key] = float(np.sqrt(np.sum((np.asarray(g.coeffs) / -f_w / omega * sig) ** 2)))
        else:
            out[key] = -dm[key] / f_w / omega * sig
    return out, w_star


def variance_shares(margin: np.ndarray, deviations: dict[str, np.ndarray]) -> dict[str, float]:
    """Each key's first-order share of the margin's variance from a linear least-squares fit over the samples
    with a finite margin (``deviations``: (n,) or (n, j) per key); NaN where the margin does not vary."""
    ok = np.isfinite(margin)
    y = margin[ok]
    if y.size < 3 or np.var(y) == 0.0:
        return {key: math.nan for key in deviations}
    cols = {key: np.atleast_2d(d.T).T[ok] for key, d in deviations.items()}
    x = np.concatenate([np.ones((y.size, 1)), *cols.values()], axis=1)
    beta = np.linalg.lstsq(x, y, rcond=None)[0]
    out, at = {}, 1
    for key, c in cols.items():
        out[key] = float(np.var(c @ beta[at : at + c.shape[1]]) / np.var(y))
        at += c.shape[1]
    return out
