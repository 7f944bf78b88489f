"""Path-generation synthesis of combined cam-linkage mechanisms (Ye & Smith 2005; the CCM of a profile cutter).

A point of a linkage must run once round a closed path (:mod:`camdyn.paths`) while the cam turns once. For every
path parameter u the linkage is solved backwards from the path with Assur dyads: the follower side gives the
follower coordinate (slider position or arm angle), the crank dyad gives the cam (crank) angle. The follower
motion as a function of cam angle is then :class:`CamLinkMotion`, which inverts the crank angle Theta(u) by
Newton's method on the exact representation and gets s', s'', s''' by the implicit-function chain rule.

Frames and signs. All lengths mm, angles deg in the tables and rad inside. The cam centre is moved to the
origin. An RRR dyad with outer joints P, Q and middle joint M has assembly mode +1 when P, M, Q run
anticlockwise (Ye & Smith, Appendix 2, the "solid" mode: theta_PM = theta_PQ - angle MPQ), -1 otherwise.
The crank dyad is (P = the path-side point, M = the crank pin, Q = the cam centre); it reaches its extended
and folded positions where |QP| is extreme, and there its mode switches (Ye & Smith's Imin / Imax rule) so
that the crank keeps turning the same way.

Singular positions. Near a switch the closed form ``acos`` has an infinite derivative on each branch although
the crank angle itself is analytic. There the crank angle is written with the signed square root of
f(u) = |d(u) - d*| (a double zero at the switch u*): sqrt(f) sign(t) = t sqrt(h(t)), t = u - u*, with
h(t) = integral_0^1 (1 - s) f''(u* + s t) ds (Taylor's remainder, evaluated by Gauss-Legendre quadrature
split at path curvature breaks), so every derivative stays finite and exact through the switch.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._core.errors import InputError, NumericalError
from .._core.units import TWO_PI
from ..schema import FollowerSpec, MechanismSpec, PathSpec, parse
from .motion import HermiteMotion, Motion
from .paths import Path, build_path, parse_path, taylor

N_GRID = 2048  # path points of the synthesis table ("path point i" in messages; Ye & Smith's index I)
_WINDOW_RAD = 0.15  # replace acos by the signed-root form within this angle (rad) of a singular position


# ============================================================================================ dyads
def cross2(a, b):
    """z component of a x b for 2-vectors (..., 2)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _cw(v):
    """v turned clockwise by 90 degrees."""
    return jnp.stack([v[..., 1], -v[..., 0]], axis=-1)


def _unit(angle):
    return jnp.stack([jnp.cos(angle), jnp.sin(angle)], axis=-1)


def _turn(v, angle):
    """v turned anticlockwise by ``angle`` (rad)."""
    c, s = jnp.cos(angle), jnp.sin(angle)
    return jnp.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def rrr_reach_miss(p, q, lp, lq):
    """How far (mm) the RRR dyad P-M-Q is from closing: 0 when |lp - lq| <= |PQ| <= lp + lq."""
    d = jnp.linalg.norm(jnp.asarray(q) - jnp.asarray(p), axis=-1)
    return jnp.maximum(jnp.maximum(d - (lp + lq), abs(lp - lq) - d), 0.0)


def rrr(p, q, lp, lq, mode):
    """Middle joint M of an RRR dyad with |M - P| = lp, |M - Q| = lq (mm).

    ``mode`` +1: P, M, Q anticlockwise (Ye & Smith's solid lines), -1: clockwise. Works on (..., 2) arrays;
    a dyad that cannot close gives NaN (check :func:`rrr_reach_miss` first for a message).
    """
    p, q = jnp.asarray(p, dtype=float), jnp.asarray(q, dtype=float)
    v = q - p
    d2 = jnp.sum(v * v, axis=-1)
    x = (lp * lp - lq * lq + d2) / (2.0 * d2)  # foot of M on PQ, as a fraction of PQ
    h = jnp.sqrt(lp * lp / d2 - x * x)  # distance of M from PQ, as a fraction of |PQ|
    return p + x[..., None] * v + (mode * h)[..., None] * _cw(v)


def rrp(c, origin, direction, length, mode):
    """Slider point E on the line ``origin + p * direction`` with |E - C| = ``length``: returns p (mm).

    ``mode`` +1 takes E ahead of the foot of C on the line (along ``direction``, a unit vector), -1 behind.
    """
    w = jnp.asarray(c, dtype=float) - origin
    along = jnp.sum(w * direction, axis=-1)
    off = cross2(direction, w)
    return along + mode * jnp.sqrt(length * length - off * off)


def _kinematics(fn, *xs):
    """Position, velocity and acceleration of ``fn`` of points moving as x(tau) = x0 + v tau + a tau^2 / 2."""

    def at(tau):
        return fn(*[x[0] + x[1] * tau + 0.5 * x[2] * tau * tau for x in xs])

    vals = taylor(lambda tau: jnp.concatenate([jnp.atleast_1d(y) for y in at(tau)]), jnp.zeros(()), 2)
    return vals


def rrr_kinematics(p, q, lp: float, lq: float, mode: int) -> dict:
    """RRR dyad kinematics (Ye & Smith Appendix 2) by forward-mode autodiff.

    ``p``, ``q``: (3, 2) arrays of position (mm), velocity (mm/s) and acceleration (mm/s^2) of the outer joints.
    Returns ``M`` (3, 2) for the middle joint and ``theta_pm``, ``theta_qm`` (3,): the link angles (rad),
    angular velocities (rad/s) and accelerations (rad/s^2) of P->M and Q->M.
    """

    def fn(p_, q_):
        m = rrr(p_, q_, lp, lq, mode)
        dp, dq = m - p_, m - q_
        return m, jnp.arctan2(dp[1], dp[0]), jnp.arctan2(dq[1], dq[0])

    vals = _kinematics(fn, jnp.asarray(p, dtype=float), jnp.asarray(q, dtype=float))
    out = jnp.stack(vals)  # (3, 4)
    return {"M": out[:, :2], "theta_pm": out[:, 2], "theta_qm": out[:, 3]}


def rrp_kinematics(c, origin, direction, length: float, mode: int) -> dict:
    """RRP dyad kinematics: ``c`` (3, 2) position, velocity, acceleration of the pin C; the line is fixed.

    Returns ``p`` (3,): slider coordinate (mm), velocity and acceleration, and ``theta_ce`` (3,) for link C->E.
    """
    origin, direction = jnp.asarray(origin, dtype=float), jnp.asarray(direction, dtype=float)

    def fn(c_):
        p = rrp(c_, origin, direction, length, mode)
        e = origin + p * direction - c_
        return p, jnp.arctan2(e[1], e[0])

    out = jnp.stack(_kinematics(fn, jnp.asarray(c, dtype=float)))
    return {"p": out[:, 0], "theta_ce": out[:, 1]}


# ============================================================================================ crank dyad
def _acos(c):
    """arccos written with atan2 (Taylor-mode autodiff has a rule for atan2, not for acos)."""
    return jnp.arctan2(jnp.sqrt(jnp.maximum(1.0 - c * c, 0.0)), c)


def _asin(x):
    return jnp.arctan2(x, jnp.sqrt(jnp.maximum(1.0 - x * x, 0.0)))


def _norm(v):
    return jnp.sqrt(jnp.sum(v * v, axis=-1))


class CrankDyad(eqx.Module):
    """The cam-side RRR dyad (P = path-side point, crank pin, cam centre at the origin) with mode switching.

    The crank angle is alpha(u) + Phi(u): alpha the direction of P, Phi the signed angle from OP to the crank.
    ``u_sw`` are the switch parameters (sorted), ``imodes[j]`` the mode on (u_sw[j], u_sw[j+1]). Within the
    window (lo, hi) of switch k, Phi is written with the signed root g(t) = sign(t) sqrt(f) = t sqrt(q(t)) of
    f = |d - d*| (a double zero at the switch, t = u - u_sw): the square root is taken analytically and only
    the smooth, positive q = f / t^2 is a local expansion, a polynomial in t / span fitted by least squares to
    f = t^2 q (``qpoly[k, side]``, ascending powers; side 0 for t < 0, 1 for t > 0, so a curvature break at
    the switch is honoured).
    """

    r: jax.Array  # crank, mm
    l: jax.Array  # coupler, mm
    u_sw: jax.Array
    sgn: jax.Array  # +1 at a minimum of |OP| (f = d - d*), -1 at a maximum (f = d* - d)
    to_pi: jax.Array  # 1: the crank is folded at the switch (Phi -> pi), 0: extended (Phi -> 0)
    m_before: jax.Array
    lo: jax.Array  # window, as offsets t = u - u_sw (lo < 0 < hi)
    hi: jax.Array
    qpoly: jax.Array  # (K, 2, n): q(t) = sum_i qpoly[k, side, i] (t / span[k, side])^i
    span: jax.Array  # (K, 2)
    imodes: jax.Array
    m_start: float = eqx.field(static=True)

    @property
    def n_switch(self) -> int:
        return int(self.u_sw.shape[0])

    def angles(self, pfun: Callable, u):
        """(alpha, Phi) at scalar u, rad; Phi is smooth through the switches."""
        p = pfun(u)
        d = _norm(p)
        alpha = jnp.arctan2(p[1], p[0])
        r, l = self.r, self.l
        c = (r * r + d * d - l * l) / (2.0 * r * d)
        if self.n_switch == 0:
            return alpha, self.m_start * _acos(jnp.clip(c, -1.0, 1.0))
        j = jnp.sum(jnp.mod(u, 1.0) >= self.u_sw) - 1
        m = self.imodes[j]  # j = -1 (before the first switch) is the last interval
        # only the nearest switch can hold u in its window (windows never overlap): evaluate that one
        ts = jnp.mod(u - self.u_sw + 0.5, 1.0) - 0.5
        inside = (ts > self.lo) & (ts < self.hi)
        k = jnp.sum(jnp.where(inside, jnp.arange(self.n_switch), 0))  # (no argmin: jet has no rule for it)
        t = ts[k]
        inw = jnp.sum(inside) > 0
        phi_w = self._window(k, jnp.where(inw, t, 0.0), jnp.where(inw, d, r + l))
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
        r, l, sgn = self.r, self.l, self.sgn[k]
        fold = self.to_pi[k] > 0.5
        q_fold = (d + r + l) / (2.0 * r * d)  # (1 + cos gamma) / f at a folded position
        q_ext = jnp.where(sgn < 0, l - r + d, l + r - d) / (2.0 * r * d)  # (1 - cos gamma) / f, extended
        q = jnp.where(fold, q_fold, q_ext)
        half = 2.0 * _asin(jnp.clip(g * jnp.sqrt(q / 2.0), -1.0, 1.0))
        mb = self.m_before[k]
        return jnp.where(fold, mb * (jnp.pi + half), -mb * half)


# ============================================================================================ mechanisms
class CCMChain(eqx.Module):
    """CCM (seed 003): crank A-B on the camshaft, coupler B-T carrying joint C, link C-E, slider E on a line.

    Coordinates relative to the cam centre A. Output: slider coordinate p of E along ``direction`` (mm).
    """

    path: Path
    center: jax.Array  # A in the case frame
    crank: jax.Array
    coupler: jax.Array
    joint: jax.Array  # C in the coupler frame (x along B->T, y to its left), mm
    link: jax.Array
    origin: jax.Array  # a point of the slider line (relative to A)
    direction: jax.Array  # unit lift direction
    slider_mode: float = eqx.field(static=True)

    def p_side(self, u):
        return self.path.point(u) - self.center

    def points(self, u, theta):
        """Joint positions relative to A at path parameter u and crank angle theta (rad)."""
        t = self.p_side(u)
        b = self.crank * _unit(theta)
        ex = (t - b) / self.coupler
        c = b + self.joint[0] * ex + self.joint[1] * jnp.stack([-ex[1], ex[0]])
        p = rrp(c, self.origin, self.direction, self.link, self.slider_mode)
        return {"B": b, "T": t, "C": c, "E": self.origin + p * self.direction, "p": p}

    def output(self, u, theta):
        return self.points(u, theta)["p"]


class OscillatingChain(eqx.Module):
    """Ye & Smith (seed 000): path point F, link F-C through the pin B, follower D-C with roller arm D-E.

    Coordinates relative to the cam centre O. Output: psi, the arm angle turned clockwise from D->O to D->E.
    """

    path: Path
    center: jax.Array  # O in the case frame
    pivot: jax.Array  # D relative to O
    path_link: jax.Array  # FC
    follower_link: jax.Array  # DC
    pin: jax.Array  # FB along F->C
    arm: jax.Array  # DE
    arm_angle: jax.Array  # angle D->C to D->E, rad anticlockwise
    follower_mode: float = eqx.field(static=True)

    def _fc(self, u):
        f = self.path.point(u) - self.center
        return f, rrr(f, self.pivot, self.path_link, self.follower_link, self.follower_mode)

    def p_side(self, u):
        f, c = self._fc(u)
        return f + self.pin * (c - f) / self.path_link

    def points(self, u, theta=None):
        f, c = self._fc(u)
        b = f + self.pin * (c - f) / self.path_link
        e = self.pivot + self.arm * _turn((c - self.pivot) / self.follower_link, self.arm_angle)
        a, dn = e - self.pivot, -self.pivot
        psi = jnp.arctan2(cross2(a, dn), jnp.sum(a * dn))
        return {"F": f, "C": c, "B": b, "E": e, "psi": psi}

    def output(self, u, theta):
        return self.points(u)["psi"]


def _wrap(x):
    return jnp.mod(x + jnp.pi, TWO_PI) - jnp.pi


class CamLinkMotion(Motion):
    """Follower motion of a cam-linkage synthesis: s(theta) (mm) or phi(theta) (rad), exact derivatives.

    theta is the cam angle turned from the path start in the cam's sense of rotation. Evaluation: find u with
    Theta(u) = theta by safeguarded Newton from the table bracket, then with Theta^(k)(u), s^(k)(u) (nested
    forward autodiff) s' = s_u / Theta_u, s'' = (s_uu Theta_u - s_u Theta_uu) / Theta_u^3 and
    s''' = (s_uuu Theta_u^2 - 3 s_uu Theta_u Theta_uu + s_u (3 Theta_uu^2 - Theta_u Theta_uuu)) / Theta_u^5.
    """

    chain: eqx.Module
    crank_dyad: CrankDyad
    theta0: jax.Array  # crank angle at u = 0, rad
    out0: jax.Array  # follower coordinate at zero lift
    tab_u: jax.Array  # (N + 1,) table of u and cam angle, Theta increasing from 0 to 2 pi
    tab_theta: jax.Array
    sense: jax.Array  # +1: crank turns anticlockwise, -1 clockwise
    unit: str = eqx.field(static=True)
    breaks_deg: tuple[float, ...] = eqx.field(static=True)

    def crank_angle(self, u):
        """Crank angle at u (rad, not unwrapped)."""
        alpha, phi = self.crank_dyad.angles(self.chain.p_side, u)
        return alpha + phi

    def _theta_raw(self, u):
        return self.sense * (self.crank_angle(u) - self.theta0)

    def _pair(self, u):
        th = self.crank_angle(u)
        return jnp.stack([self.sense * (th - self.theta0), self.chain.output(u, th) - self.out0])

    def u_of(self, theta):
        """Path parameter u (scalar) at cam angle theta (rad): Newton with a bisection safeguard in the table cell.

        Theta(u) is increasing; the bracket [a, b] shrinks with every residual sign, and a Newton step that
        leaves it is replaced by bisection (robust where Theta' is unbounded, at a sharp corner).
        """
        theta = jnp.mod(theta, TWO_PI)
        i = jnp.clip(jnp.searchsorted(self.tab_theta, theta, side="right") - 1, 0, self.tab_u.shape[0] - 2)
        a, b = self.tab_u[i], self.tab_u[i + 1]
        ta, tb = self.tab_theta[i], self.tab_theta[i + 1]
        u = a + (b - a) * (theta - ta) / (tb - ta)

        def step(state, _):
            u, a, b = state
            val, der = jax.jvp(self._theta_raw, (u,), (jnp.ones_like(u),))
            res = _wrap(val - theta)
            a, b = jnp.where(res < 0.0, u, a), jnp.where(res > 0.0, u, b)
            nxt = u - res / jnp.where(der > 0.0, der, 1.0)
            # closed bracket: a converged iterate sits on the end its own residual set, and a Newton step of
            # zero length must not be mistaken for one that left the bracket (it would bisect away from the root)
            ok = (nxt >= a) & (nxt <= b) & (der > 0.0)
            return (jnp.where(res == 0.0, u, jnp.where(ok, nxt, 0.5 * (a + b))), a, b), None

        (u, _, _), _ = jax.lax.scan(step, (u, a, b), None, length=8)
        return jax.lax.stop_gradient(u)

    def at_u(self, u):
        """(Theta, s) and their first three u-derivatives at scalar u: (4, 2)."""
        return jnp.stack(taylor(self._pair, u, 3))

    def _one(self, theta):
        tv = self.at_u(self.u_of(theta))
        t1, t2, t3 = tv[1, 0], tv[2, 0], tv[3, 0]
        s0, s1, s2, s3 = tv[0, 1], tv[1, 1], tv[2, 1], tv[3, 1]
        d1 = s1 / t1
        d2 = (s2 * t1 - s1 * t2) / t1**3
        d3 = (s3 * t1**2 - 3.0 * s2 * t1 * t2 + s1 * (3.0 * t2**2 - t1 * t3)) / t1**5
        return jnp.stack([s0, d1, d2, d3])

    def __call__(self, theta):
        theta = jnp.asarray(theta, dtype=float)
        out = jax.vmap(self._one)(theta.ravel())  # (n, 4)
        return out.T.reshape(4, *theta.shape)


def parse_mechanism(mech: dict | MechanismSpec) -> MechanismSpec:
    """A validated ``[mechanism]`` table (a :class:`camdyn.schema.MechanismSpec`); errors name ``mechanism.<key>``."""
    return mech if isinstance(mech, MechanismSpec) else parse(MechanismSpec, mech, "mechanism")


# ============================================================================================ synthesis
def _padded(fn, obj, u, *more):
    """``fn(obj, u, *more)`` for u of any length, padded to a multiple of N_GRID so each jitted helper compiles
    once per mechanism structure instead of once per array length."""
    u = np.atleast_1d(np.asarray(u, dtype=float))
    n = len(u)
    size = -(-n // N_GRID) * N_GRID
    pad = lambda x: jnp.asarray(np.concatenate([x, np.resize(x, size - n)]) if size > n else x)  # noqa: E731
    out = fn(obj, pad(u), *(pad(np.atleast_1d(np.asarray(m, dtype=float))) for m in more))
    return jax.tree_util.tree_map(lambda x: np.asarray(x)[:n], out)


def _where_point(i: int, n: int = N_GRID) -> str:
    return f"path point {i} (u = {i / n:.4f})"


@eqx.filter_jit
def _vmap_jit(fn, u):
    return jax.vmap(fn)(u)


def vmap_scalar(fn, u):
    """numpy values of a scalar-u function (an equinox bound method) over the array u."""
    return np.asarray(_vmap_jit(fn, jnp.asarray(u)))


@eqx.filter_jit
def _d_and_slope(chain, u):
    def one(v):
        d, dd = jax.jvp(lambda w: _norm(chain.p_side(w)), (v,), (jnp.ones_like(v),))
        return jnp.stack([d, dd])

    return jax.vmap(one)(u)


def _refine_extremum(chain, u0: float, h: float) -> float:
    """u of the extremum of d(u) = |p_side(u)| near u0 (bisection on d', robust at curvature breaks)."""
    lo, hi = u0 - h, u0 + h
    slope = lambda v: float(_padded(_d_and_slope, chain, [v])[0, 1])  # noqa: E731
    s_lo, s_hi = slope(lo), slope(hi)
    if s_lo * s_hi > 0.0:  # no sign change: a kink (sharp corner) or flat; keep the grid extremum
        return u0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        s_mid = slope(mid)
        if s_mid == 0.0:
            return mid
        if (s_mid > 0.0) == (s_lo > 0.0):
            lo, s_lo = mid, s_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class _Extremes:
    u_max: list[float]
    u_min: list[float]
    d_max: float
    d_min: float
    i_max: int
    i_min: int


def _extremes(chain, u_grid: np.ndarray) -> _Extremes:
    """Global extremes of |cam centre - path-side point| (all local extremes within 1e-9 relative)."""
    dd = _padded(_d_and_slope, chain, u_grid)
    d = dd[:, 0]
    n, h = len(d), 1.0 / len(d)
    cands = {"max": [], "min": []}
    for i in range(n):
        a, b = d[i - 1], d[(i + 1) % n]
        if d[i] >= a and d[i] > b:
            cands["max"].append(i)
        if d[i] <= a and d[i] < b:
            cands["min"].append(i)
    out = {}
    for kind in ("max", "min"):
        refined = []
        for i in cands[kind]:
            u = _refine_extremum(chain, u_grid[i], h) % 1.0
            refined.append((float(_padded(_d_and_slope, chain, [u])[0, 0]), u, i))
        best = max(refined)[0] if kind == "max" else min(refined)[0]
        keep = [(dv, u, i) for dv, u, i in refined if abs(dv - best) <= 1e-9 * max(best, 1.0)]
        out[kind] = (best, keep)
    (dmax, kmax), (dmin, kmin) = out["max"], out["min"]
    return _Extremes([u for _, u, _ in kmax], [u for _, u, _ in kmin], dmax, dmin, kmax[0][2], kmin[0][2])


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


def _q_factor(d: np.ndarray, r: float, l: float, sgn: float, to_pi: float) -> np.ndarray:
    """(1 -+ cos gamma) / f as in :meth:`CrankDyad._window`, numpy."""
    if to_pi:
        return (d + r + l) / (2 * r * d)
    return ((l - r + d) if sgn < 0 else (l + r - d)) / (2 * r * d)


@eqx.filter_jit
def _dvals(chain, u):
    return jax.vmap(lambda v: _norm(chain.p_side(v)))(jnp.atleast_1d(u))


def _off_collinear(chain, u, dstar, sgn, to_pi, r, l) -> np.ndarray:
    """How far (rad) the crank is from its collinear position at the switch, at parameters u."""
    dv = _padded(_dvals, chain, u)
    f = np.clip(sgn * (dv - dstar), 0, None)
    return 2.0 * np.arcsin(np.sqrt(f * _q_factor(dv, r, l, sgn, to_pi) / 2.0).clip(0, 1))


def _extent(chain, us, dstar, sgn, to_pi, r, l, side, reach) -> tuple[float, float]:
    """(fit span, window) on one side of a switch: the fit reaches to where the crank is _FIT_RAD off collinear,
    the window (where the expansion replaces acos) to _WINDOW_RAD; both within ``reach``."""
    tt = np.linspace(reach / 200, reach, 200)
    dev = _off_collinear(chain, us + side * tt, dstar, sgn, to_pi, r, l)
    past = np.flatnonzero(dev > _FIT_RAD)
    span = float(tt[past[0]]) if past.size else float(reach)
    inside = np.flatnonzero(dev > _WINDOW_RAD)
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
    f = sgn * (_padded(_dvals, chain, us + t) - dstar)
    basis = (t * t)[:, None] * (t / scale)[:, None] ** np.arange(_Q_DEGREE + 1)
    norm = np.linalg.norm(basis, axis=0)
    coef = np.linalg.lstsq(basis / norm, f, rcond=None)[0] / norm
    return coef, scale, float(np.max(np.abs(basis @ coef - f)) / np.max(np.abs(f)))


def _build_crank(chain, r: float, l: float, ext: _Extremes, m_start: int, path: Path) -> tuple[CrankDyad, list[str]]:
    """Crank dyad with switches where |OP| touches r + l (extended) or |r - l| (folded or extended)."""
    notes: list[str] = []
    sw = []  # (u, d*, sgn, to_pi)
    if abs(ext.d_max - (r + l)) <= 1e-6:
        sw += [(u, ext.d_max, -1.0, 0.0) for u in ext.u_max]
    if abs(ext.d_min - abs(r - l)) <= 1e-6:
        sw += [(u, ext.d_min, 1.0, 1.0 if l > r else 0.0) for u in ext.u_min]
    sw = sorted((0.0 if min(u, 1.0 - u) < 1e-12 else u, *rest) for u, *rest in sw)
    k = len(sw)
    a = lambda x: jnp.asarray(np.array(x, dtype=float))  # noqa: E731
    if k % 2:
        raise NumericalError("mechanism.crank", f"the crank dyad reaches {k} singular positions per loop; an odd count cannot close the assembly modes")
    if k == 0:
        z = jnp.zeros(0)
        return CrankDyad(a(r), a(l), z, z, z, z, z, z, jnp.zeros((0, 2, _Q_DEGREE + 1)), jnp.zeros((0, 2)), z, m_start=float(m_start)), notes
    u_sw = np.array([s_[0] for s_ in sw])
    sign0 = 1.0 if u_sw[0] == 0.0 else -1.0
    imodes = np.array([m_start * sign0 * (-1.0) ** j for j in range(k)])
    m_before = np.roll(imodes, 1)
    lo, hi, polys, spans = [], [], [], []
    for j, (us, dstar, sgn, to_pi) in enumerate(sw):
        if any(min(abs(us - b), 1 - abs(us - b)) < 1e-9 for b in path.sharp_u):
            # a sharp corner at the switch: |OP| has a kink, not a double zero; keep the closed form
            lo.append(0.0), hi.append(0.0), polys.append(np.zeros((2, _Q_DEGREE + 1))), spans.append([1.0, 1.0])
            notes.append(f"the crank passes a singular position at a sharp corner (u = {us:.4f}): its speed is unbounded there")
            continue
        gap = min(((u_sw[(j + s_) % k] - us) * s_) % 1.0 or 1.0 for s_ in (1, -1))  # to the neighbouring switch
        ext_ = [_extent(chain, us, dstar, sgn, to_pi, r, l, side, min(_break_distance(us, path.breaks_u, side), 0.45 * gap, 0.1)) for side in (-1, 1)]
        if min(_break_distance(us, path.breaks_u, 1), _break_distance(us, path.breaks_u, -1)) < 1e-9:
            fl, fr = _fit_q(chain, us, dstar, sgn, -ext_[0][0], 0.0), _fit_q(chain, us, dstar, sgn, 0.0, ext_[1][0])
        else:
            fl = fr = _fit_q(chain, us, dstar, sgn, -ext_[0][0], ext_[1][0])
        fits = [(fl[0], fl[1], ext_[0][1], fl[2]), (fr[0], fr[1], ext_[1][1], fr[2])]
        lo.append(-fits[0][2]), hi.append(fits[1][2])
        polys.append([fits[0][0], fits[1][0]]), spans.append([fits[0][1], fits[1][1]])
        edge = _off_collinear(chain, np.array([us - fits[0][2], us + fits[1][2]]), dstar, sgn, to_pi, r, l)
        if edge.min() < 0.5 * _WINDOW_RAD or max(f[3] for f in fits) > 1e-9:
            notes.append(
                f"the local expansion at the singular position u = {us:.4f} is cramped by a path break (crank "
                f"{np.degrees(edge.min()):.2g} deg off collinear at its edge, fit error {max(f[3] for f in fits):.1e}): "
                "the follower jerk is less accurate there"
            )
    crank = CrankDyad(
        a(r), a(l), a(u_sw), a([s_[2] for s_ in sw]), a([s_[3] for s_ in sw]), a(m_before), a(lo), a(hi),
        a(np.array(polys)), a(np.array(spans)), a(imodes), m_start=float(m_start),
    )
    return crank, notes


@eqx.filter_jit
def _tabulate(motion: CamLinkMotion, u):
    """Theta_raw, follower coordinate and their u-derivative on a grid."""

    def one(v):
        val, der = jax.jvp(motion._pair, (v,), (jnp.ones_like(v),))
        return jnp.concatenate([val, der])

    return jax.vmap(one)(u)


def _with_breaks(m: CamLinkMotion, breaks: tuple[float, ...]) -> CamLinkMotion:
    """The same motion with other ``breaks_deg`` (internal jitted helpers use ``()`` so they compile once)."""
    return CamLinkMotion(
        chain=m.chain, crank_dyad=m.crank_dyad, theta0=m.theta0, out0=m.out0, tab_u=m.tab_u, tab_theta=m.tab_theta,
        sense=m.sense, unit=m.unit, breaks_deg=breaks,
    )


@eqx.filter_jit
def _sample(motion: CamLinkMotion, theta):
    """Path parameters u (n,) and follower value and first derivative per radian of cam angle (n, 2) at theta.

    First order only (one jvp): the synthesis does not need the third-order Taylor program that the full
    ``motion(theta)`` compiles, so it stays fast; s'' for sizing the cam comes from differences of s'.
    """

    def one(th):
        u = motion.u_of(th)
        val, der = jax.jvp(motion._pair, (u,), (jnp.ones_like(u),))
        return u, jnp.stack([val[1], der[1] / der[0]])

    return jax.vmap(one)(theta)


@eqx.filter_jit
def _points(chain, u, theta):
    return jax.vmap(chain.points)(u, theta)


@dataclass(frozen=True)
class Synthesis:
    """Result of :func:`synthesize_motion`.

    ``motion``: the follower motion (:class:`CamLinkMotion`); ``tabulated``: its quintic Hermite table, which
    the case hands to the dynamics (exact at the knots, error in ``summary["motion_table_error"]``); ``follower``: the cam-follower geometry in the
    shared conventions of :mod:`camdyn.geometry` (cam centre at the origin). ``json()`` gives the summary for
    ``check --json``; :meth:`linkage_at` the joint positions for drawings.
    """

    motion: CamLinkMotion
    tabulated: HermiteMotion
    follower: FollowerSpec
    path_spec: PathSpec
    mechanism: MechanismSpec
    summary: dict
    theta_deg: np.ndarray  # cam angles of the arrays below
    pitch: np.ndarray  # (n, 2) roller centre in the cam frame, mm (Ye & Smith eq. 6)
    contour: np.ndarray  # (n, 2) cam contour in the cam frame, mm (eqs. 7-8)
    path_xy: np.ndarray  # (n, 2) target points at the same cam angles, case frame
    traced_xy: np.ndarray  # (n, 2) forward check: points traced by the linkage driven by the cam
    sharp_corners: bool = False
    warnings: list[str] = field(default_factory=list)

    def json(self) -> dict:
        out = dict(self.summary)
        out.update(
            sharp_corners=self.sharp_corners, warnings=list(self.warnings),
            theta_deg=self.theta_deg.tolist(), pitch=self.pitch.tolist(), contour=self.contour.tolist(),
            path_xy=self.path_xy.tolist(), traced_xy=self.traced_xy.tolist(),
        )
        return out

    def linkage_at(self, theta_deg) -> dict[str, np.ndarray]:
        """Joint positions (case frame, mm) at cam angles ``theta_deg``: name -> (n, 2).

        CCM: A (cam centre), B (crank pin), T (tracing point), C (coupler joint), E (slider pin).
        Oscillating: O (cam centre), A (crank pin), B, F (tracing point), C, D (pivot), E (roller centre).
        """
        m = _with_breaks(self.motion, ())
        th = jnp.deg2rad(jnp.atleast_1d(jnp.asarray(theta_deg, dtype=float)))
        u = _padded(_sample, m, np.asarray(th))[0]
        crank = np.asarray(m.theta0) + float(m.sense) * np.asarray(th)
        pts = {k: v for k, v in _padded(_points, m.chain, u, crank).items() if np.ndim(v) == 2}
        c0 = np.asarray(m.chain.center)
        out = {k: v + c0 for k, v in pts.items()}
        r = float(m.crank_dyad.r)
        pin = r * np.column_stack([np.cos(crank), np.sin(crank)]) + c0
        centre = np.broadcast_to(c0, pin.shape).copy()
        if isinstance(m.chain, CCMChain):
            out.update(A=centre, B=pin)
        else:
            out.update(O=centre, A=pin, D=np.broadcast_to(np.asarray(m.chain.pivot) + c0, pin.shape).copy())
        return out


def _make_chain(path: Path, ms: MechanismSpec, r: float, l: float):
    c0 = jnp.asarray(ms.cam_center, dtype=float)
    if ms.type == "ccm":
        jd = ms.joint_distance if ms.joint_distance is not None else l
        ja = math.radians(ms.joint_angle)
        sp = np.asarray(ms.slider_point if ms.slider_point is not None else ms.cam_center, dtype=float) - np.asarray(ms.cam_center)
        a = math.radians(ms.slider_angle)
        return CCMChain(
            path=path, center=c0, crank=jnp.asarray(r), coupler=jnp.asarray(l),
            joint=jnp.asarray([jd * math.cos(ja), jd * math.sin(ja)]), link=jnp.asarray(ms.link),
            origin=jnp.asarray(sp), direction=jnp.asarray([math.cos(a), math.sin(a)]), slider_mode=float(ms.slider_mode),
        )
    return OscillatingChain(
        path=path, center=c0, pivot=jnp.asarray(ms.pivot, dtype=float) - c0, path_link=jnp.asarray(ms.path_link),
        follower_link=jnp.asarray(ms.follower_link), pin=jnp.asarray(float(ms.pin_distance)), arm=jnp.asarray(ms.arm),
        arm_angle=jnp.asarray(math.radians(ms.arm_angle)), follower_mode=float(ms.follower_mode),
    )


def _check_follower_side(chain, ms: MechanismSpec, u_grid: np.ndarray) -> None:
    """The path-driven follower dyad must close at every path point (else: where and by how much)."""
    if ms.type != "oscillating":
        return
    f = vmap_scalar(chain.path.point, u_grid) - np.asarray(chain.center)
    miss = np.asarray(rrr_reach_miss(f, np.asarray(chain.pivot), ms.path_link, ms.follower_link))
    i = int(np.argmax(miss))
    if miss[i] > 0.0:
        raise NumericalError(_where_point(i), f"dyad F-C-D cannot close: reach missed by {miss[i]:.4g} mm (|DF| = {np.linalg.norm(f[i] - np.asarray(chain.pivot)):.4g} mm, FC + DC = {ms.path_link + ms.follower_link:g} mm, |FC - DC| = {abs(ms.path_link - ms.follower_link):g} mm)")


def _check_ccm_slider(chain: CCMChain, motion_pts: dict, ms: MechanismSpec) -> None:
    c = np.asarray(motion_pts["C"])
    off = np.abs(np.asarray(cross2(jnp.asarray(chain.direction), jnp.asarray(c - np.asarray(chain.origin)))))
    miss = off - ms.link
    i = int(np.argmax(miss))
    if miss[i] > 0.0:
        raise NumericalError(_where_point(i), f"dyad C-E-slider cannot close: the link C-E ({ms.link:g} mm) misses the slider line by {miss[i]:.4g} mm")


def _pitch_contour(pos: np.ndarray, vel: np.ndarray, theta: np.ndarray, sense: float, rr: float):
    """Pitch curve and contour in the cam frame (Ye & Smith eqs. 6-8) from the roller centre in the fixed frame.

    ``pos``, ``vel``: roller centre and its derivative per radian of cam angle (n, 2), relative to the cam centre.
    """
    a = -sense * theta  # cam frame = fixed frame turned back by the cam angle
    c, s = np.cos(a), np.sin(a)
    rot = lambda v: np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])  # noqa: E731
    pitch = rot(pos)
    rel = vel - sense * np.column_stack([-pos[:, 1], pos[:, 0]])  # d/dtheta seen from the cam
    tan = rot(rel)
    speed = np.linalg.norm(tan, axis=1)
    unit = tan / np.where(speed > 0, speed, 1.0)[:, None]
    contour = pitch + sense * rr * np.column_stack([unit[:, 1], -unit[:, 0]])  # eq. 8: towards the cam
    return pitch, contour, rel


def _choose_base_radius(s: np.ndarray, s1: np.ndarray, s2: np.ndarray, e: float, sense: float, rr: float, max_pa_deg: float, sharp: bool = False) -> float:
    """Least base radius (0.5 mm steps) keeping the translating-roller pressure angle within the limit and
    the pitch curve's convex radius of curvature at least 2.5 roller radii: the contour's is then at least 1.5,
    the default limit of ``check``'s curvature judgment.

    Pressure angle of a roller at (e, d0 + s) on a cam turning with ``sense``: tan phi = (s' - sense e)/(d0 + s).
    """
    tan_max = math.tan(math.radians(max_pa_deg))
    d0 = max(float(np.max(np.abs(s1 - sense * e) / tan_max - s)), 1e-3)
    rp = max(math.hypot(d0, e), abs(e) + rr, 1.5 * rr)
    for _ in range(200):
        if sharp or pitch_convexity(rp, s, s1, s2, e, sense) <= 1.0 / (2.5 * rr):  # at sharp corners no base
            break  # radius can save the curvature
        rp *= 1.05
    return math.ceil((rp - rr) * 2.0) / 2.0


def pitch_convexity(rp, s, s1, s2, e, sense):
    """Largest convex curvature (1/mm) of the pitch curve of a translating roller at (e, d0 + s), d0 =
    sqrt(rp^2 - e^2), on a cam turning with ``sense``, over the last axis (s, s1, s2 (..., n); rp, e, sense
    broadcast against (..., 1)); <= 0 where the pitch curve is nowhere convex."""
    y = np.sqrt(np.maximum(rp * rp - e * e, 1e-12)) + s
    v1x, v1y = sense * y, s1 - sense * e  # P' - sense J P, P = (e, y)
    v2x, v2y = 2.0 * sense * s1 - e, s2 - y  # P'' - 2 sense J P' - P
    kappa = (v1x * v2y - v1y * v2x) / (np.hypot(v1x, v1y) ** 3 + 1e-300)
    return (-sense * kappa).max(-1)  # traversal opposite to the cam's turn: convex where this is > 0


def synthesize_motion(path: dict, mechanism: dict) -> Synthesis:
    """Synthesize the cam of a combined cam-linkage so that the tracing point follows ``path`` exactly.

    ``path``, ``mechanism``: the ``[path]`` and ``[mechanism]`` tables (see :class:`PathSpec`,
    :class:`MechanismSpec`). Raises :class:`InputError` for invalid tables and :class:`NumericalError` for a
    dyad that cannot close or a crank that would reverse (naming the path point).
    """
    t_start = time.perf_counter()
    ps, ms = parse_path(path), parse_mechanism(mechanism)
    pth = build_path(ps)
    warnings: list[str] = []
    sharp = bool(pth.sharp_u)
    n = N_GRID
    u_grid = np.arange(n) / n
    chain = _make_chain(pth, ms, 1.0, 1.0)
    _check_follower_side(chain, ms, u_grid)
    ext = _extremes(chain, u_grid)
    if ms.crank is None:  # Ye & Smith eq. 5
        r, l = (ext.d_max - ext.d_min) / 2.0, (ext.d_max + ext.d_min) / 2.0
        if r <= 0.0:
            raise NumericalError("mechanism.crank", "the path-side point keeps a constant distance from the cam centre: eq. 5 gives no crank")
    else:
        r, l = ms.crank, ms.coupler
        if ext.d_max > r + l + 1e-6:
            raise NumericalError(_where_point(ext.i_max), f"crank dyad cannot close: reach missed by {ext.d_max - r - l:.4g} mm (|cam centre to path-side point| = {ext.d_max:.6g} mm > crank + coupler = {r + l:g} mm)")
        if ext.d_min < abs(r - l) - 1e-6:
            raise NumericalError(_where_point(ext.i_min), f"crank dyad cannot close: reach missed by {abs(r - l) - ext.d_min:.4g} mm (|cam centre to path-side point| = {ext.d_min:.6g} mm < |crank - coupler| = {abs(r - l):g} mm)")
    chain = _make_chain(pth, ms, r, l)
    dyad, notes = _build_crank(chain, r, l, ext, ms.crank_mode, pth)
    warnings += notes
    unit = "mm" if ms.type == "ccm" else "rad"
    proto = CamLinkMotion(chain=chain, crank_dyad=dyad, theta0=jnp.asarray(0.0), out0=jnp.asarray(0.0), tab_u=jnp.zeros(N_GRID + 1), tab_theta=jnp.zeros(N_GRID + 1), sense=jnp.asarray(1.0), unit=unit, breaks_deg=())
    th0 = float(_padded(_tabulate, proto, [0.0])[0, 0])
    proto = eqx.tree_at(lambda m: m.theta0, proto, jnp.asarray(th0))
    if ms.type == "ccm":
        pts0 = _padded(_points, chain, u_grid, _padded(_tabulate, proto, u_grid)[:, 0] + th0)
        _check_ccm_slider(chain, pts0, ms)
    # --- crank monotonicity, sense, unwrapped cam-angle table
    tab = _padded(_tabulate, proto, u_grid)
    if not np.all(np.isfinite(tab[:, :2])):
        i = int(np.argmax(~np.isfinite(tab[:, :2]).all(axis=1)))
        raise NumericalError(_where_point(i), "the linkage cannot be assembled here (NaN position)")
    raw = np.unwrap(np.append(tab[:, 0], tab[0, 0]))
    turn = raw[-1] - raw[0]
    slope = tab[:, 2]
    sense = 1.0 if turn > 0 else -1.0
    bad = np.flatnonzero(sense * slope <= 0.0)
    if bad.size:
        i = int(bad[0])
        hint = f"; try crank_mode = {-ms.crank_mode}" if dyad.n_switch else "; with crank and coupler from eq. 5 it passes its collinear positions instead"
        raise NumericalError(
            _where_point(i),
            f"the crank would reverse here (dtheta/du changes sign: {math.degrees(slope[i]):.4g} deg per unit u against a net turn of {math.degrees(turn):.1f} deg){hint}",
        )
    if abs(abs(turn) - TWO_PI) > 1e-6:
        raise NumericalError("mechanism.cam_center", f"the crank turns {math.degrees(turn):.1f} deg while the point runs once round the path; it must turn exactly once (360 deg)")
    tab_theta = np.append(sense * (raw[:-1] - raw[0]), TWO_PI)
    tab_u = np.append(u_grid, 1.0)
    out = tab[:, 1]
    out0 = float(out.min())
    # breaks: path curvature breaks and switches with a tangent break
    brk_u = sorted(set(pth.breaks_u) | set(pth.sharp_u))
    core = CamLinkMotion(
        chain=chain, crank_dyad=dyad, theta0=jnp.asarray(th0), out0=jnp.asarray(out0), tab_u=jnp.asarray(tab_u),
        tab_theta=jnp.asarray(tab_theta), sense=jnp.asarray(sense), unit=unit, breaks_deg=(),
    )
    # exact cam angles of the breaks (the table's linear interpolation would miss them by up to ~1e-5 rad,
    # enough to put a jump of s'' inside an interval of the dynamics' step controller or the Hermite table)
    brk_theta = vmap_scalar(core._theta_raw, np.asarray(brk_u, dtype=float)) if brk_u else np.zeros(0)
    breaks = tuple(sorted({round(float(b) % TWO_PI * 180 / math.pi, 9) % 360.0 for b in brk_theta}))
    motion = _with_breaks(core, breaks)
    # --- samples at 1-degree steps: motion, forward check, pitch and contour
    theta = np.deg2rad(np.arange(360.0))
    u_s, sv = _padded(_sample, core, theta)
    step = theta[1] - theta[0]
    s2 = (np.roll(sv[:, 1], -1) - np.roll(sv[:, 1], 1)) / (2 * step)  # sizing only; exact s'' is motion(theta)[2]
    vals = np.vstack([sv.T, s2])
    crank_s = th0 + sense * theta
    target = vmap_scalar(pth.point, u_s)
    follower, traced, pos, vel, extra = _follower_and_forward(motion, ms, vals, crank_s, u_s, r, l, sense, warnings)
    err = float(np.max(np.linalg.norm(traced - target, axis=1)))
    if not err < 1e-3:
        warnings.append(f"forward check: the linkage driven by the cam misses the path by {err:.3g} mm")
    rr = ms.roller_radius
    pitch, contour, _ = _pitch_contour(pos, vel, theta, sense, rr)
    if sharp:
        warnings.append(
            "the path has sharp corners (corner_radius = 0): the follower velocity jumps there, so its acceleration is unbounded; give the corners a radius"
        )
    summary = {
        "mechanism": ms.type,
        "crank_mm": r,
        "coupler_mm": l,
        "start_angle_deg": (math.degrees(th0) + 180.0) % 360.0 - 180.0,
        "rotation": "ccw" if sense > 0 else "cw",
        "lob_min_mm": ext.d_min,
        "lob_max_mm": ext.d_max,
        "u_lob_min": ext.u_min[0],
        "u_lob_max": ext.u_max[0],
        "switches": [{"u": float(us), "cam_angle_deg": float(np.interp(us, tab_u, tab_theta)) * 180 / math.pi} for us in np.asarray(dyad.u_sw)],
        "max_path_error_mm": err,
        "base_radius_mm": follower.base_radius,
        "roller_radius_mm": rr,
        "synthesis_time_s": time.perf_counter() - t_start,
        **extra,
    }
    # the consumers that evaluate the motion millions of times (ODE right-hand side, sweeps) read a table
    tabulated = HermiteMotion.from_motion(motion)
    tab_err = tabulated.max_error(motion)
    summary["motion_table_error"] = dict(zip(("s", "s1", "s2", "s3"), map(float, tab_err)))
    if tab_err[2] > 1e-4 * max(float(np.ptp(vals[2])), 1e-12):
        warnings.append(f"the tabulated follower motion misses the exact s'' by up to {tab_err[2]:.3g} per rad^2; the dynamics use the table")
    if unit == "mm":
        summary["stroke_mm"] = float(vals[0].max() - vals[0].min())
    else:
        summary["swing_deg"] = math.degrees(float(vals[0].max() - vals[0].min()))
    return Synthesis(
        motion=motion, tabulated=tabulated, follower=follower, path_spec=ps, mechanism=ms, summary=summary, theta_deg=np.arange(360.0),
        pitch=pitch, contour=contour, path_xy=target, traced_xy=traced, sharp_corners=sharp, warnings=warnings,
    )


def _transmission_warning(name: str, ang: np.ndarray, warnings: list[str]) -> float:
    """Least transmission angle (deg, folded into [0, 90]) of a driven dyad; warns below 30 deg."""
    fold = np.degrees(np.minimum(ang, np.pi - ang))
    worst = float(fold.min())
    if worst < 30.0:
        warnings.append(f"transmission angle of dyad {name} falls to {worst:.1f} deg (below 30 deg)")
    return worst


def _angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.arccos(np.clip(np.sum(a * b, 1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)), -1, 1))


def _follower_and_forward(motion, ms, vals, crank, u, r, l, sense, warnings):
    """FollowerSpec, forward-checked traced points, roller centre (and d/dtheta) relative to the cam centre."""
    chain = motion.chain
    pts = _padded(_points, chain, u, crank)
    c0 = np.asarray(chain.center)
    a_pin = r * np.column_stack([np.cos(crank), np.sin(crank)])
    if ms.type == "ccm":
        e_dir, origin = np.asarray(chain.direction), np.asarray(chain.origin)
        xhat = np.array([e_dir[1], -e_dir[0]])
        e = float(origin @ xhat)  # offset of the slider line from the cam centre (follower frame x)
        s, s1, s2 = vals[0], vals[1], vals[2]
        base = ms.base_radius if ms.base_radius is not None else _choose_base_radius(s, s1, s2, e, sense, ms.roller_radius, ms.max_pressure_angle, bool(chain.path.sharp_u))
        rp = base + ms.roller_radius
        if rp <= abs(e):
            raise InputError("mechanism.base_radius", f"base + roller radius ({rp:g} mm) must exceed the slider line's offset from the cam centre ({abs(e):.4g} mm)")
        d0 = math.sqrt(rp * rp - e * e)
        follower = FollowerSpec(type="translating-roller", base_radius=base, roller_radius=ms.roller_radius, offset=e, rotation="ccw" if sense > 0 else "cw")
        pos = e * xhat + (d0 + s)[:, None] * e_dir
        vel = s1[:, None] * e_dir
        # forward: crank at the cam angle, slider where the cam puts it, then the RRR dyad B-C-E closes the coupler
        e_pin = origin + (float(motion.out0) + s)[:, None] * e_dir
        mode_c = float(np.sign(cross2(pts["C"][0] - pts["B"][0], e_pin[0] - pts["B"][0])))
        c_fwd = np.asarray(rrr(a_pin, e_pin, float(np.linalg.norm(chain.joint)), ms.link, mode_c))
        jx, jy = np.asarray(chain.joint)
        bc = c_fwd - a_pin
        jn2 = jx * jx + jy * jy
        ex = (jx * bc + jy * np.column_stack([bc[:, 1], -bc[:, 0]])) / jn2  # rotate B->C back into B->T
        traced = a_pin + l * ex + c0
        modes = np.sign(cross2(pts["C"] - pts["B"], pts["E"] - pts["B"]))
        if np.any(modes != mode_c):
            warnings.append("the forward dyad B-C-E changes assembly mode along the path: the linkage cannot run through it")
        tmin = _transmission_warning("B-C-E (angle at C)", _angle_between(pts["B"] - pts["C"], pts["E"] - pts["C"]), warnings)
        # RRP transmission angle: 90 deg minus the link's angle to the slider line (singular when perpendicular)
        phi = _angle_between(pts["C"] - pts["E"], np.broadcast_to(e_dir, pts["E"].shape))
        slider_ang = _transmission_warning("C-E-slider (link to the slider's normal)", np.pi / 2 - np.minimum(phi, np.pi - phi), warnings)
        extra = {"offset_mm": e, "min_transmission_angle_deg": tmin, "min_slider_angle_deg": slider_ang, "slider_zero_mm": float(motion.out0)}
        return follower, traced, pos, vel, extra
    # oscillating
    d = np.asarray(chain.pivot)
    psi = np.asarray(pts["psi"])
    if np.any(psi <= 0.0) or np.any(psi >= np.pi):
        raise InputError(
            "mechanism.arm_angle",
            "the roller arm must lie clockwise of D->O (0 < psi < 180 deg) for the shared geometry convention; "
            "this mechanism needs an 'arm side' field in FollowerSpec (or mirror the case)",
        )
    psi0 = float(motion.out0)
    dn = -d / np.linalg.norm(d)
    e0 = d + ms.arm * np.asarray(_turn(jnp.asarray(dn), -psi0))
    rp = float(np.linalg.norm(e0))
    base = rp - ms.roller_radius
    if base <= 0.0:
        raise InputError("mechanism.roller_radius", f"roller radius {ms.roller_radius:g} mm exceeds the least distance {rp:.4g} mm from the cam centre to the roller centre")
    follower = FollowerSpec(
        type="oscillating-roller", base_radius=base, roller_radius=ms.roller_radius, pivot_distance=float(np.linalg.norm(d)),
        pivot_angle=math.degrees(math.atan2(d[1], d[0])), arm_length=ms.arm, rotation="ccw" if sense > 0 else "cw",
    )
    psi_t = psi0 + vals[0]
    arm_dir = np.asarray(_turn(jnp.asarray(np.broadcast_to(dn, (len(psi_t), 2))), -jnp.asarray(psi_t)))
    pos = d + ms.arm * arm_dir
    vel = -ms.arm * vals[1][:, None] * np.column_stack([-arm_dir[:, 1], arm_dir[:, 0]])  # dE/dpsi = arm * (cw normal)
    # forward: arm at phi(theta) -> C; crank at the cam angle -> A; dyad A-B-C closes; F on C->B produced
    c_fwd = d + ms.follower_link * np.asarray(_turn(jnp.asarray(arm_dir), -math.radians(ms.arm_angle)))
    lbc = abs(ms.path_link - ms.pin_distance)
    mode_b = float(np.sign(cross2(pts["B"][0] - a_pin[0], pts["C"][0] - a_pin[0])))
    b_fwd = np.asarray(rrr(a_pin, c_fwd, l, lbc, mode_b))
    e_fc = (b_fwd - c_fwd) / (ms.pin_distance - ms.path_link)
    traced = c_fwd - ms.path_link * e_fc + c0
    modes = np.sign(cross2(pts["B"] - a_pin, pts["C"] - a_pin))
    if np.any(modes != mode_b):
        warnings.append("the forward dyad A-B-C changes assembly mode along the path: the linkage cannot run through it")
    tmin = _transmission_warning("A-B-C (angle at B)", _angle_between(a_pin - pts["B"], pts["C"] - pts["B"]), warnings)
    extra = {"min_transmission_angle_deg": tmin, "psi0_deg": math.degrees(psi0)}
    return follower, traced, pos, vel, extra
