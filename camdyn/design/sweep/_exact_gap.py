"""The largest gap of the nonlinear compliant model by exact piecewise-linear stepping.

Both modes of the compliant model are linear: in contact the state is the linear steady state plus a free
vibration of the contact system, in flight a free vibration of spring and damper about their equilibrium. So each
step of the angle grid is exact (2x2 matrix exponentials in closed form); where the contact condition changes sign
within a step, the switch is located on the cubic Hermite interpolant of the step (Illinois iterations) and the
rest of the step is exact in the new mode. The mode is recomputed from the state at every step, exactly as the
vector field decides it (``s > x`` and ``Fi > 0``). Everything here is in the motion's unit (mm or rad) and the
cam angle, per unit ``m w^2``.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ..._core.units import TWO_PI
from ...model.dynamics import steady_state
from ._grid import GAP_LAST, GAP_REVS

_ILLINOIS = 3  # iterations locating a contact switch within a step
_INNER = (0.25, 0.5, 0.75)  # where inside a step the gap is also sampled (0.125 deg apart)


def _expm2(a, b, t):
    """exp(A t) for A = [[0, 1], [-a, -b]] in closed form (under-, critically or over-damped): (e00, e01, e10, e11)."""
    alpha = -0.5 * b
    d = alpha * alpha - a
    y = jnp.sqrt(jnp.abs(d)) * t
    small = y < 1e-8
    under = d < 0
    cc = jnp.where(under, jnp.cos(y), jnp.cosh(y))
    sy = jnp.where(small, 1.0, jnp.where(under, jnp.sin(y), jnp.sinh(y)) / jnp.where(small, 1.0, y))  # sin(y)/y
    ss = sy * t
    e = jnp.exp(alpha * t)
    return e * (cc + 0.5 * b * ss), e * ss, -e * a * ss, e * (cc - 0.5 * b * ss)


def _hermite(f0, d0, f1, d1, u, h):
    """Cubic Hermite interpolation on [0, h] at u = tau / h from values and derivatives at both ends."""
    u2, u3 = u * u, u * u * u
    return (2 * u3 - 3 * u2 + 1) * f0 + (u3 - 2 * u2 + u) * h * d0 + (3 * u2 - 2 * u3) * f1 + (u3 - u2) * h * d1


class _Modes(NamedTuple):
    """The two linear modes per unit m w^2: spring (a_k, b_c), train (a_f, b_f), static load f0 (motion units)."""

    a_k: jax.Array
    b_c: jax.Array
    a_f: jax.Array
    b_f: jax.Array
    f0: jax.Array

    @property
    def x_flight(self):
        """The flight equilibrium."""
        return -self.f0 / self.a_k

    def acc(self, contact, s, s1, x, p):
        """d2x/dtheta2 in contact or in flight."""
        free = -self.a_k * x - self.b_c * p - self.f0
        return jnp.where(contact, free + self.a_f * (s - x) + self.b_f * (s1 - p), free)

    def g(self, s, s1, x, p):
        """> 0 exactly where the vector field has contact: s > x and Fi > 0."""
        return jnp.minimum(self.a_f * (s - x), self.a_f * (s - x) + self.b_f * (s1 - p))


class _Tables(NamedTuple):
    """Per step-grid angle: the motion (s, s', s''), the linear steady state (x, x') and the gap weight."""

    s: jax.Array
    s1: jax.Array
    s2: jax.Array
    xl: jax.Array
    pl: jax.Array
    w: jax.Array

    def at(self, i):
        return tuple(t[i] for t in self)


def _switch_time(md: _Modes, h, ends, x, p, x1, p1, a0, a1, g0, g1):
    """Where in [0, h] the contact condition changes sign: Illinois iterations on the step's Hermite interpolant."""
    (s0, s10, s20), (s1_, s11, s21) = ends

    def g_at(t):
        u = t / h
        return md.g(
            _hermite(s0, s10, s1_, s11, u, h),
            _hermite(s10, s20, s11, s21, u, h),
            _hermite(x, p, x1, p1, u, h),
            _hermite(p, a0, p1, a1, u, h),
        )

    ta, tb, ga, gb = 0.0, h, g0, g1
    for _ in range(_ILLINOIS):
        den = gb - ga
        t = jnp.clip((ta * gb - tb * ga) / jnp.where(den != 0, den, 1.0), 0.0, h)
        gt = g_at(t)
        flip = gt * gb < 0
        ta, ga = jnp.where(flip, tb, ta), jnp.where(flip, gb, 0.5 * ga)
        tb, gb = t, gt
    return tb


def _rest_of_step(md: _Modes, h, tb, contact, row0, row1, xs, ps):
    """The state at the step's end from the switch at tb, exact in the new mode (about the linear steady state
    on entering contact, about the flight equilibrium on leaving it)."""
    s0, s10, _, xl0, pl0, _ = row0
    s1_, s11, _, xl1, pl1, _ = row1
    u = tb / h
    to_contact = ~contact
    er = _expm2(jnp.where(to_contact, md.a_k + md.a_f, md.a_k), jnp.where(to_contact, md.b_c + md.b_f, md.b_c), h - tb)
    al0, al1 = md.acc(True, s0, s10, xl0, pl0), md.acc(True, s1_, s11, xl1, pl1)
    rx = jnp.where(to_contact, _hermite(xl0, pl0, xl1, pl1, u, h), md.x_flight)
    rp = jnp.where(to_contact, _hermite(pl0, al0, pl1, al1, u, h), 0.0)
    dx, dp = xs - rx, ps - rp
    x_ev = jnp.where(to_contact, xl1, md.x_flight) + er[0] * dx + er[1] * dp
    p_ev = jnp.where(to_contact, pl1, 0.0) + er[2] * dx + er[3] * dp
    return x_ev, p_ev


def _step(md: _Modes, tabs: _Tables, h, ec, ef, last, carry, j):
    """One step of the angle grid; the gap is taken from step ``last`` on."""
    x, p, gap = carry
    m_steps = tabs.s.shape[0]
    row0, row1 = tabs.at(j % m_steps), tabs.at((j + 1) % m_steps)
    s0, s10, s20, xl0, pl0, w0 = row0
    s1_, s11, s21, xl1, pl1, w1 = row1
    g0 = md.g(s0, s10, x, p)
    contact = g0 > 0
    dx, dp = x - xl0, p - pl0
    fx = x - md.x_flight
    x1 = jnp.where(contact, xl1 + ec[0] * dx + ec[1] * dp, md.x_flight + ef[0] * fx + ef[1] * p)
    p1 = jnp.where(contact, pl1 + ec[2] * dx + ec[3] * dp, ef[2] * fx + ef[3] * p)
    g1 = md.g(s1_, s11, x1, p1)
    event = (g1 > 0) != contact
    a0, a1 = md.acc(contact, s0, s10, x, p), md.acc(contact, s1_, s11, x1, p1)
    tb = _switch_time(md, h, ((s0, s10, s20), (s1_, s11, s21)), x, p, x1, p1, a0, a1, g0, g1)
    u = tb / h
    xs, ps = _hermite(x, p, x1, p1, u, h), _hermite(p, a0, p1, a1, u, h)
    x_ev, p_ev = _rest_of_step(md, h, tb, contact, row0, row1, xs, ps)
    x_next, p_next = jnp.where(event, x_ev, x1), jnp.where(event, p_ev, p1)
    # the gap at the step end and inside the step (Hermite of this step)
    inner = [(_hermite(x, p, x1, p1, v, h) - _hermite(s0, s10, s1_, s11, v, h)) * (w0 + v * (w1 - w0)) for v in _INNER]
    cand = jnp.maximum(
        jnp.where(event, -jnp.inf, jnp.maximum(jnp.maximum(inner[0], inner[1]), inner[2])), (x_next - s1_) * w1
    )
    gap = jnp.where(j + 1 >= last, jnp.maximum(gap, cand), gap)
    return (x_next, p_next, gap), None


def exact_gap_kernel(const, omega, k, c):
    """Largest gap (weighted: mm) of the nonlinear compliant model over the last ``GAP_LAST`` of ``GAP_REVS``
    revolutions from the linear steady state at theta = 0; NaN where it is not finite.

    ``const = (model, s, s', s'' on the step grid, gap weight on it, rfft of s on the fine grid)`` in the
    motion's unit; ``omega`` (rad/s), ``k`` and ``c`` (SI) are the grid point."""
    base, s_tab, s1_tab, s2_tab, w_tab, spec = const
    n_fft = 2 * (spec.shape[0] - 1)
    m_steps = s_tab.shape[0]
    stride = n_fft // m_steps
    h = TWO_PI / m_steps
    mw2 = base.mass * omega**2
    md = _Modes(
        k / mw2,
        c / (base.mass * omega),
        base.train_stiffness / mw2,
        base.train_damping / (base.mass * omega),
        (base.preload + base.external) / (mw2 * base.scale),
    )
    xl, pl = steady_state(spec, omega, base, k, c, n_fft, unit=base.scale)
    tabs = _Tables(s_tab, s1_tab, s2_tab, xl[::stride], pl[::stride], w_tab)
    ec = _expm2(md.a_k + md.a_f, md.b_c + md.b_f, h)
    ef = _expm2(md.a_k, md.b_c, h)
    last = (GAP_REVS - GAP_LAST) * m_steps

    def step(carry, j):
        return _step(md, tabs, h, ec, ef, last, carry, j)

    (_, _, gap), _ = jax.lax.scan(step, (tabs.xl[0], tabs.pl[0], jnp.asarray(-jnp.inf)), jnp.arange(GAP_REVS * m_steps))
    return jnp.where(jnp.isfinite(gap), gap, jnp.nan)
