"""Where the path-side point is nearest to and farthest from the cam centre: Ye & Smith eq. 5 and the crank's
singular positions (its extended and folded positions) both come from these extremes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import cached_jit
from ._batch import padded
from ._dyads import norm

if TYPE_CHECKING:
    from ._chains import LinkChain


@cached_jit
def _d_and_slope(chain, u):
    def one(v: ArrayLike) -> jax.Array:
        d, dd = jax.jvp(lambda w: norm(chain.p_side(w)), (v,), (jnp.ones_like(v),))
        return jnp.stack([d, dd])

    return jax.vmap(one)(u)


def _refine_extrema(chain, u0: np.ndarray, h: float) -> np.ndarray:
    """u of the extremum of d(u) = |p_side(u)| near each u0 (bisection on d', robust at curvature breaks); all
    candidates in one evaluation a step."""
    lo, hi = u0 - h, u0 + h
    slope = lambda v: padded(_d_and_slope, chain, v)[:, 1]  # noqa: E731
    s_lo, s_hi = slope(lo), slope(hi)
    done = s_lo * s_hi > 0.0  # no sign change: a kink (sharp corner) or flat; keep the grid extremum
    out = u0.copy()
    for _ in range(60):
        if done.all():
            return out
        mid = 0.5 * (lo + hi)
        s_mid = slope(mid)
        hit = ~done & (s_mid == 0.0)
        out[hit], done = mid[hit], done | hit
        up = (s_mid > 0.0) == (s_lo > 0.0)
        lo, s_lo = np.where(up, mid, lo), np.where(up, s_mid, s_lo)
        hi = np.where(up, hi, mid)
    out[~done] = 0.5 * (lo + hi)[~done]
    return out


@dataclass(frozen=True)
class Extremes:
    """Global extremes of d(u) = |cam centre - path-side point| (mm): every u where each is reached, and the
    table points ``i_max``, ``i_min`` nearest the first (for messages)."""

    u_max: list[float]
    u_min: list[float]
    d_max: float
    d_min: float
    i_max: int
    i_min: int


def find_extremes(chain: LinkChain, u_grid: np.ndarray) -> Extremes:
    """Global extremes of |cam centre - path-side point| (all local extremes within 1e-9 relative)."""
    dd = padded(_d_and_slope, chain, u_grid)
    d = dd[:, 0]
    n, h = len(d), 1.0 / len(d)
    cands = {"max": [], "min": []}
    for i in range(n):
        a, b = d[i - 1], d[(i + 1) % n]
        if d[i] >= a and d[i] > b:
            cands["max"].append(i)
        if d[i] <= a and d[i] < b:
            cands["min"].append(i)
    index = np.array(cands["max"] + cands["min"], dtype=int)
    u = _refine_extrema(chain, u_grid[index], h) % 1.0
    dv = padded(_d_and_slope, chain, u)[:, 0]
    out = {}
    for kind, part in (("max", slice(0, len(cands["max"]))), ("min", slice(len(cands["max"]), None))):
        refined = [(float(a), float(b), int(i)) for a, b, i in zip(dv[part], u[part], index[part], strict=True)]
        best = max(refined)[0] if kind == "max" else min(refined)[0]
        keep = [(dv, u, i) for dv, u, i in refined if abs(dv - best) <= 1e-9 * max(best, 1.0)]
        out[kind] = (best, keep)
    (dmax, kmax), (dmin, kmin) = out["max"], out["min"]
    return Extremes([u for _, u, _ in kmax], [u for _, u, _ in kmin], dmax, dmin, kmax[0][2], kmin[0][2])
