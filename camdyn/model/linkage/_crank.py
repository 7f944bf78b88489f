"""The crank dyad: the cam-side RRR dyad (path-side point P, crank pin, cam centre) whose assembly mode switches
at the crank's singular positions, and the local expansion that keeps its angle analytic through them.

The crank dyad reaches its extended and folded positions where |OP| is extreme, and there its mode switches
(Ye & Smith's Imin / Imax rule) so that the crank keeps turning the same way. Near a switch the closed form
``acos`` has an infinite derivative on each branch although the crank angle itself is analytic. There the crank
angle is written with the signed square root of f(u) = |d(u) - d*| (a double zero at the switch u*):
sqrt(f) sign(t) = t sqrt(q(t)), t = u - u*, with q = f / t^2 smooth and positive, fitted as a polynomial, so
every derivative stays finite and exact through the switch.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import NumericalError
from ..._core.jit import cached_jit, device_array
from ..paths import Path
from ._batch import padded
from ._dyads import norm
from ._extremes import Extremes

if TYPE_CHECKING:
    from ._chains import LinkChain

WINDOW_RAD = 0.15  # replace acos by the signed-root form within this angle (rad) of a singular position


def _acos(c):
    """arccos written with atan2 (Taylor-mode autodiff has a rule for atan2, not for acos)."""
    return jnp.arctan2(jnp.sqrt(jnp.maximum(1.0 - c * c, 0.0)), c)


def _asin(x):
    return jnp.arctan2(x, jnp.sqrt(jnp.maximum(1.0 - x * x, 0.0)))


class CrankDyad(eqx.Module):
    """The cam-side RRR dyad (P = path-side point, crank pin, cam centre at the origin) with mode switching.

    The crank angle is alpha(u) + Phi(u): alpha the direction of P, Phi the signed angle from OP to the crank.
    ``u_sw`` are the switch parameters (sorted), ``imodes[j]`` the mode on (u_sw[j], u_sw[j+1]). Within the
    window (lo, hi) of switch k, Phi is written with the signed root g(t) = sign(t) sqrt(f) = t sqrt(q(t)) of
    f = |d - d*| (a double zero at the switch, t = u - u_sw): the square root is taken analytically and only
    the smooth, positive q = f / t^2 is a local expansion, a polynomial in t / span fitted by least squares to
    f = t^2 q (``qpoly[k, side]``, ascending powers; side 0 for t < 0, 1 for t > 0, so a curvature break at
    the switch is honoured). The arrays are padded to 2, 4, 8, ... switches (:func:`_padded_dyad`), so that a
    crank with no switch or a few more shares the compiled programs of the others.
    """

    r: jax.Array  # crank, mm
    coupler: jax.Array  # mm
    u_sw: jax.Array
    sgn: jax.Array  # +1 at a minimum of |OP| (f = d - d*), -1 at a maximum (f = d* - d)
    to_pi: jax.Array  # 1: the crank is folded at the switch (Phi -> pi), 0: extended (Phi -> 0)
    m_before: jax.Array
    lo: jax.Array  # window, as offsets t = u - u_sw (lo < 0 < hi)
    hi: jax.Array
    qpoly: jax.Array  # (K, 2, n): q(t) = sum_i qpoly[k, side, i] (t / span[k, side])^i
    span: jax.Array  # (K, 2)
    imodes: jax.Array

    @property
    def n_switch(self) -> int:
        """The number of switches (host only): the arrays are padded past them (:func:`_padded_dyad`)."""
        return int(np.sum(np.isfinite(np.asarray(self.u_sw))))

    def angles(self, pfun: Callable, u: ArrayLike) -> tuple[jax.Array, jax.Array]:
        """(alpha, Phi) at scalar u, rad; Phi is smooth through the switches."""
        p = pfun(u)
        d = norm(p)
        alpha = jnp.arctan2(p[1], p[0])
        r, coupler = self.r, self.coupler
        c = (r * r + d * d - coupler * coupler) / (2.0 * r * d)
        j = jnp.sum(jnp.mod(u, 1.0) >= self.u_sw) - 1
        m = self.imodes[j]  # j = -1 (before the first switch, or no switch): the last interval's, the padding's
        # only the nearest switch can hold u in its window (windows never overlap): evaluate that one
        ts = jnp.mod(u - self.u_sw + 0.5, 1.0) - 0.5
        inside = (ts > self.lo) & (ts < self.hi)
        k = jnp.sum(jnp.where(inside, jnp.arange(self.u_sw.shape[0]), 0))  # (no argmin: jet has no rule for it)
        t = ts[k]
        inw = jnp.sum(inside) > 0
        phi_w = self._window(k, jnp.where(inw, t, 0.0), jnp.where(inw, d, r + coupler))
        phi_c = m * _acos(jnp.clip(jnp.where(inw, 0.0, c), -1.0, 1.0))  # keep acos' finite when unused
        return alpha, jnp.where(inw, phi_w, phi_c)

    def _window(self, k, t, d):
        """Phi near switch k at offset t, d = |OP| there (signed-root form: exact, finite derivatives)."""
        side = jnp.where(t >= 0.0, 1, 0)
        coef, x = self.qpoly[k, side], t / self.span[k, side]
        q_t = jnp.zeros_like(t)
        for i in range(coef.shape[0] - 1, -1, -1):  # Horner
            q_t = q_t * x + coef[i]
        g = t * jnp.sqrt(jnp.maximum(q_t, 0.0))
        r, coupler, sgn = self.r, self.coupler, self.sgn[k]
        fold = self.to_pi[k] > 0.5
        q_fold = (d + r + coupler) / (2.0 * r * d)  # (1 + cos gamma) / f at a folded position
        q_ext = jnp.where(sgn < 0, coupler - r + d, coupler + r - d) / (2.0 * r * d)  # (1 - cos gamma) / f, extended
        q = jnp.where(fold, q_fold, q_ext)
        half = 2.0 * _asin(jnp.clip(g * jnp.sqrt(q / 2.0), -1.0, 1.0))
        mb = self.m_before[k]
        return jnp.where(fold, mb * (jnp.pi + half), -mb * half)


_Q_DEGREE = 12  # degree of the local expansion of q = f / t^2
_Q_NODES = 48
_FIT_RAD = 0.3  # fit q out to where the crank is this far (rad) off collinear


def _break_distance(us: float, breaks: tuple[float, ...], side: int) -> float:
    """Distance in u from the switch to the nearest break on one side (0 excluded), at most 0.5."""
    best = 0.5
    for b in breaks:
        t = side * (((b - us + 0.5) % 1.0) - 0.5)
        if t > 1e-12:
            best = min(best, t)
    return best


def _q_factor(d: np.ndarray, r: float, coupler: float, sgn: float, to_pi: float) -> np.ndarray:
    """(1 -+ cos gamma) / f as in :meth:`CrankDyad._window`, numpy."""
    if to_pi:
        return (d + r + coupler) / (2 * r * d)
    return ((coupler - r + d) if sgn < 0 else (coupler + r - d)) / (2 * r * d)


@cached_jit
def _dvals(chain, u):
    return jax.vmap(lambda v: norm(chain.p_side(v)))(jnp.atleast_1d(u))


def _off_collinear(chain, u, dstar, sgn, to_pi, r, coupler) -> np.ndarray:
    """How far (rad) the crank is from its collinear position at the switch, at parameters u."""
    dv = padded(_dvals, chain, u)
    f = np.clip(sgn * (dv - dstar), 0, None)
    return 2.0 * np.arcsin(np.sqrt(f * _q_factor(dv, r, coupler, sgn, to_pi) / 2.0).clip(0, 1))


def _extent(chain, us, dstar, sgn, to_pi, r, coupler, side, reach) -> tuple[float, float]:
    """(fit span, window) on one side of a switch: the fit reaches to where the crank is _FIT_RAD off collinear,
    the window (where the expansion replaces acos) to WINDOW_RAD; both within ``reach``."""
    tt = np.linspace(reach / 200, reach, 200)
    dev = _off_collinear(chain, us + side * tt, dstar, sgn, to_pi, r, coupler)
    past = np.flatnonzero(dev > _FIT_RAD)
    span = float(tt[past[0]]) if past.size else float(reach)
    inside = np.flatnonzero(dev > WINDOW_RAD)
    return span, min(float(tt[inside[0]]) if inside.size else span, span)


def _fit_q(chain, us, dstar, sgn, t_lo: float, t_hi: float) -> tuple[np.ndarray, float, float]:
    """Local expansion of q = f / t^2 on [t_lo, t_hi] (t_lo <= 0 <= t_hi): (coefficients in t / scale, scale, error).

    f is sampled on Chebyshev nodes and fitted as t^2 q(t) by least squares: f has a uniform absolute rounding
    error, so the fit is governed by the well-resolved outer nodes and q needs no division by a vanishing t^2.
    One polynomial across the switch keeps every derivative continuous there; a curvature break at the
    switch gets one fit per side.
    """
    scale = max(-t_lo, t_hi)
    x = 0.5 * (1.0 - np.cos(np.pi * (np.arange(_Q_NODES) + 0.5) / _Q_NODES))
    t = t_lo + (t_hi - t_lo) * x
    t = t[np.abs(t) > 1e-3 * scale]  # f ~ t^2 is all rounding error there
    f = sgn * (padded(_dvals, chain, us + t) - dstar)
    basis = (t * t)[:, None] * (t / scale)[:, None] ** np.arange(_Q_DEGREE + 1)
    norm = np.linalg.norm(basis, axis=0)
    coef = np.linalg.lstsq(basis / norm, f, rcond=None)[0] / norm
    return coef, scale, float(np.max(np.abs(basis @ coef - f)) / np.max(np.abs(f)))


def build_crank(
    chain: LinkChain, r: float, coupler: float, ext: Extremes, m_start: int, path: Path
) -> tuple[CrankDyad, list[str]]:
    """Crank dyad with switches where |OP| touches r + coupler (extended) or |r - coupler| (folded or extended)."""
    notes: list[str] = []
    sw = []  # (u, d*, sgn, to_pi)
    if abs(ext.d_max - (r + coupler)) <= 1e-6:
        sw += [(u, ext.d_max, -1.0, 0.0) for u in ext.u_max]
    if abs(ext.d_min - abs(r - coupler)) <= 1e-6:
        sw += [(u, ext.d_min, 1.0, 1.0 if coupler > r else 0.0) for u in ext.u_min]
    sw = sorted((0.0 if min(u, 1.0 - u) < 1e-12 else u, *rest) for u, *rest in sw)
    k = len(sw)
    if k % 2:
        raise NumericalError(
            "mechanism.crank",
            f"the crank dyad reaches {k} singular positions per loop; an odd count cannot close the assembly modes",
        )
    if k == 0:
        return _padded_dyad(r, coupler, [], [], [], [], [], [], [], [], [], m_start), notes
    u_sw = np.array([s_[0] for s_ in sw])
    sign0 = 1.0 if u_sw[0] == 0.0 else -1.0
    imodes = np.array([m_start * sign0 * (-1.0) ** j for j in range(k)])
    m_before = np.roll(imodes, 1)
    lo, hi, polys, spans = [], [], [], []
    for j, (us, dstar, sgn, to_pi) in enumerate(sw):
        if any(min(abs(us - b), 1 - abs(us - b)) < 1e-9 for b in path.sharp_u):
            # a sharp corner at the switch: |OP| has a kink, not a double zero; keep the closed form
            lo.append(0.0)
            hi.append(0.0)
            polys.append(np.zeros((2, _Q_DEGREE + 1)))
            spans.append([1.0, 1.0])
            notes.append(
                f"the crank passes a singular position at a sharp corner (u = {us:.4f}): its speed is unbounded there"
            )
            continue
        gap = min(((u_sw[(j + s_) % k] - us) * s_) % 1.0 or 1.0 for s_ in (1, -1))  # to the neighbouring switch
        ext_ = [
            _extent(
                chain,
                us,
                dstar,
                sgn,
                to_pi,
                r,
                coupler,
                side,
                min(_break_distance(us, path.breaks_u, side), 0.45 * gap, 0.1),
            )
            for side in (-1, 1)
        ]
        if min(_break_distance(us, path.breaks_u, 1), _break_distance(us, path.breaks_u, -1)) < 1e-9:
            fl, fr = _fit_q(chain, us, dstar, sgn, -ext_[0][0], 0.0), _fit_q(chain, us, dstar, sgn, 0.0, ext_[1][0])
        else:
            fl = fr = _fit_q(chain, us, dstar, sgn, -ext_[0][0], ext_[1][0])
        fits = [(fl[0], fl[1], ext_[0][1], fl[2]), (fr[0], fr[1], ext_[1][1], fr[2])]
        lo.append(-fits[0][2])
        hi.append(fits[1][2])
        polys.append([fits[0][0], fits[1][0]])
        spans.append([fits[0][1], fits[1][1]])
        edge = _off_collinear(chain, np.array([us - fits[0][2], us + fits[1][2]]), dstar, sgn, to_pi, r, coupler)
        if edge.min() < 0.5 * WINDOW_RAD or max(f[3] for f in fits) > 1e-9:
            notes.append(
                f"the local expansion at the singular position u = {us:.4f} is cramped by a path break (crank "
                f"{np.degrees(edge.min()):.2g} deg off collinear at its edge, fit error "
                f"{max(f[3] for f in fits):.1e}): the follower jerk is less accurate there"
            )
    crank = _padded_dyad(
        r, coupler, u_sw, [s_[2] for s_ in sw], [s_[3] for s_ in sw], m_before, lo, hi, polys, spans, imodes, m_start
    )
    return crank, notes


def _padded_dyad(r, coupler, u_sw, sgn, to_pi, m_before, lo, hi, polys, spans, imodes, m_start) -> CrankDyad:
    """The crank dyad of these switches, padded to 2, 4, 8, ... (one compiled program for every crank of a
    bucket; a crank without switches among them): a padded switch is never reached (u +inf), its window empty,
    and its mode the last interval's (``m_start`` where there is none), which u before the first switch takes."""
    k = len(u_sw)
    size = 2
    while size < k:
        size *= 2
    more = size - k

    def pad(x: ArrayLike, value: float, shape: tuple[int, ...] = ()) -> jax.Array:
        x = np.asarray(x, dtype=float).reshape(k, *shape)
        return device_array(np.concatenate([x, np.full((more, *shape), value, dtype=float)]))

    last = imodes[-1] if k else m_start
    return CrankDyad(
        device_array(r),
        device_array(coupler),
        pad(u_sw, np.inf),
        pad(sgn, 1.0),
        pad(to_pi, 0.0),
        pad(m_before, 1.0),
        pad(lo, 0.0),
        pad(hi, 0.0),
        pad(polys, 0.0, (2, _Q_DEGREE + 1)),
        pad(spans, 1.0, (2,)),
        pad(imodes, last),
    )
