"""The largest gap of the nonlinear compliant model by exact piecewise-linear stepping.

Both modes of the compliant model are linear: in contact the state is the linear steady state plus a free
vibration of the contact system, in flight a free vibration of spring and damper about their equilibrium. So each
step of the angle grid is exact (2x2 matrix exponentials in closed form); where the contact condition changes sign
within a step, the switch is located on the cubic Hermite interpolant of the step (Illinois iterations) and the
rest of the step is exact in the new mode. The mode is recomputed from the state at every step, exactly as the
vector field decides it (``s > x`` and ``Fi > 0``). Everything here is in the motion's unit (mm or rad) and the
cam angle, per unit ``m w^2``.

A chunk of points is stepped together; at each step the points whose contact switches (one or two in a hundred) are
gathered, ``_EVENTS`` at a time, for the switch and the rest of their step, which cost as much as a whole step of
every point. The linear steady state is needed only on the step grid: it comes from the aliased spectrum by
inverse FFTs of the step grid's size.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ..._core.units import TWO_PI
from ...model.dynamics import free_vibration, steady_spectrum, vibration_coefficients
from ._grid import GAP_LAST, GAP_REVS

_ILLINOIS = 3  # iterations locating a contact switch within a step
_INNER = (0.25, 0.5, 0.75)  # where inside a step the gap is also sampled (0.125 deg apart)
_EVENTS = 32  # switching points handled together (a step with more repeats)


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


def _on_steps(x_spec, n, m_steps):
    """x and dx/dtheta on every ``n / m_steps``-th point of the fine grid from the rfft ``x_spec`` of x on it
    (last axis), as ``irfft(x_spec, n)`` and ``irfft(i k x_spec, n)`` give them there: inverse FFTs of ``m_steps``
    points of the aliased spectra (each bin the sum of the fine bins it aliases with), a tenth of the work on the
    fine grid. Needs ``n / m_steps`` odd and ``m_steps`` even (3600 / 720 = 5)."""
    half, m_half, q = n // 2, m_steps // 2, n // m_steps
    d_spec = 1j * jnp.arange(half + 1) * x_spec
    nyquist = jnp.arange(half + 1) == half  # irfft reads only the Nyquist bin's real part

    def aliased(spec):
        spec = jnp.where(nyquist, spec.real, spec)
        # bin r (0..m/2) of the coarse grid: the fine bins r + j m (j = 0..(q-1)/2), and the conjugates of the
        # fine bins j m - r (j = 1..(q-1)/2), which stand for the negative frequencies r - j m
        pos = sum(spec[..., j * m_steps : j * m_steps + m_half + 1] for j in range((q + 1) // 2))
        neg = sum(spec[..., j * m_steps - m_half : j * m_steps + 1] for j in range(1, (q + 1) // 2))
        return pos + jnp.flip(jnp.conj(neg), axis=-1)

    return jnp.fft.irfft(aliased(x_spec), m_steps) / q, jnp.fft.irfft(aliased(d_spec), m_steps) / q


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
    a = jnp.where(to_contact, md.a_k + md.a_f, md.a_k)
    er = free_vibration(a, jnp.where(to_contact, md.b_c + md.b_f, md.b_c), h - tb)
    al0, al1 = md.acc(True, s0, s10, xl0, pl0), md.acc(True, s1_, s11, xl1, pl1)
    rx = jnp.where(to_contact, _hermite(xl0, pl0, xl1, pl1, u, h), md.x_flight)
    rp = jnp.where(to_contact, _hermite(pl0, al0, pl1, al1, u, h), 0.0)
    dx, dp = xs - rx, ps - rp
    x_ev = jnp.where(to_contact, xl1, md.x_flight) + er[0] * dx + er[1] * dp
    p_ev = jnp.where(to_contact, pl1, 0.0) + er[2] * dx + er[3] * dp
    return x_ev, p_ev


def _switched(md: _Modes, h, ends, rows, x, p, x1, p1, contact, g0, g1):
    """The state at the step's end of points whose contact changes within the step: the switch time on the
    step's Hermite cubic, then the rest of the step exact in the new mode."""
    (s0, s10, s20), (s1_, s11, s21) = ends
    xl0, pl0, xl1, pl1 = rows
    a0, a1 = md.acc(contact, s0, s10, x, p), md.acc(contact, s1_, s11, x1, p1)
    tb = _switch_time(md, h, ends, x, p, x1, p1, a0, a1, g0, g1)
    u = tb / h
    xs, ps = _hermite(x, p, x1, p1, u, h), _hermite(p, a0, p1, a1, u, h)
    row0, row1 = (s0, s10, s20, xl0, pl0, None), (s1_, s11, s21, xl1, pl1, None)
    return _rest_of_step(md, h, tb, contact, row0, row1, xs, ps)


def _events(md: _Modes, h, ends, rows, x, p, x1, p1, contact, g0, g1, todo, gather: bool):
    """The state at the step's end, :func:`_switched` for the points ``todo`` whose contact changes within the step.
    ``gather`` (a CPU): they are gathered ``_EVENTS`` at a time: the switch costs about as much as a whole step of
    every point, and a step has few switching points. Else (an accelerator) the switch of every point is computed
    in parallel and the ``todo`` ones kept: its sequential gathers would cost more than the arithmetic (0.10 s
    against 0.77 s a map of 10^4 designs on an H200)."""
    if not gather:
        x_ev, p_ev = _switched(md, h, ends, rows, x, p, x1, p1, contact, g0, g1)
        return jnp.where(todo, x_ev, x1), jnp.where(todo, p_ev, p1)
    n = x.shape[0]
    n_lanes = math.gcd(n, _EVENTS)
    # every per-point input as the rows of one array, the state as another: one gather and one scatter a round
    # (a gather or a scatter per array is a kernel each: more program to compile)
    data = jnp.stack([*md, *rows, x, p, x1, p1, contact.astype(x.dtype), g0, g1])

    def body(state):
        end, left = state
        # point i is in lane i % n_lanes: each lane gives its first point left (one reduction, no sort or cumsum)
        lanes = left.reshape(n // n_lanes, n_lanes)
        idx = jnp.where(lanes.any(axis=0), jnp.argmax(lanes, axis=0) * n_lanes + jnp.arange(n_lanes), n)
        got = data.at[:, idx].get(mode="clip")  # the fill columns read a real point; their results are dropped
        xk, pk, x1k, p1k, ck, g0k, g1k = got[9:]
        ev = _switched(_Modes(*got[:5]), h, ends, tuple(got[5:9]), xk, pk, x1k, p1k, ck > 0.5, g0k, g1k)
        return end.at[:, idx].set(jnp.stack(ev), mode="drop"), left.at[idx].set(False, mode="drop")

    end, _ = jax.lax.while_loop(lambda state: jnp.any(state[1]), body, (jnp.stack([x1, p1]), todo))
    return end[0], end[1]


def _gap(const, omega, k, gather: bool):
    """Largest gap (weighted: mm) of the nonlinear compliant model over the last ``GAP_LAST`` of ``GAP_REVS``
    revolutions from the linear steady state at theta = 0; NaN where it is not finite. A batch kernel: ``omega``
    (rad/s) and ``k`` (SI; the damping follows from it) are arrays of grid points, stepped together.

    ``const = (model, s, s', s'' on the step grid, gap weight on it, rfft of s on the fine grid)`` in the
    motion's unit."""
    base, s_tab, s1_tab, s2_tab, w_tab, spec = const
    n_fft = 2 * (spec.shape[0] - 1)
    m_steps = s_tab.shape[0]
    h = TWO_PI / m_steps
    c = base.damping_at(k)
    md = _Modes(
        *vibration_coefficients(base.mass, k, c, omega),
        *vibration_coefficients(base.mass, base.train_stiffness, base.train_damping, omega),
        (base.preload + base.external) / (base.mass * omega**2 * base.scale),
    )
    x_spec = steady_spectrum(spec, omega[:, None], base, k[:, None], c[:, None], n_fft, base.scale, conjugate=True)
    xl, pl = _on_steps(x_spec, n_fft, m_steps)
    xl, pl = xl.T, pl.T  # (steps, points): a step reads a row
    ec = free_vibration(md.a_k + md.a_f, md.b_c + md.b_f, h)
    ef = free_vibration(md.a_k, md.b_c, h)
    last = (GAP_REVS - GAP_LAST) * m_steps

    def step(carry, j):
        x, p, gap = carry
        i0, i1 = j % m_steps, (j + 1) % m_steps
        s0, s10, s20, w0 = s_tab[i0], s1_tab[i0], s2_tab[i0], w_tab[i0]
        s1_, s11, s21, w1 = s_tab[i1], s1_tab[i1], s2_tab[i1], w_tab[i1]
        xl0, pl0, xl1, pl1 = xl[i0], pl[i0], xl[i1], pl[i1]
        g0 = md.g(s0, s10, x, p)
        contact = g0 > 0
        dx, dp = x - xl0, p - pl0
        fx = x - md.x_flight
        x1 = jnp.where(contact, xl1 + ec[0] * dx + ec[1] * dp, md.x_flight + ef[0] * fx + ef[1] * p)
        p1 = jnp.where(contact, pl1 + ec[2] * dx + ec[3] * dp, ef[2] * fx + ef[3] * p)
        g1 = md.g(s1_, s11, x1, p1)
        event = (g1 > 0) != contact
        ends = ((s0, s10, s20), (s1_, s11, s21))
        x_next, p_next = _events(md, h, ends, (xl0, pl0, xl1, pl1), x, p, x1, p1, contact, g0, g1, event, gather)

        def tracked(gap):  # the gap at the step end and inside the step (Hermite of this step)
            inner = [
                (_hermite(x, p, x1, p1, v, h) - _hermite(s0, s10, s1_, s11, v, h)) * (w0 + v * (w1 - w0))
                for v in _INNER
            ]
            cand = jnp.maximum(
                jnp.where(event, -jnp.inf, jnp.maximum(jnp.maximum(inner[0], inner[1]), inner[2])),
                (x_next - s1_) * w1,
            )
            return jnp.maximum(gap, cand)

        # the gap is taken from the step that ends where revolution GAP_REVS - GAP_LAST + 1 begins; one loop with
        # the tracking in a branch, not a loop before and a loop after: half the program to trace and compile
        return (x_next, p_next, jax.lax.cond(j >= last - 1, tracked, lambda g: g, gap)), None

    carry = (xl[0], pl[0], jnp.full(omega.shape, -jnp.inf))
    carry, _ = jax.lax.scan(step, carry, jnp.arange(GAP_REVS * m_steps))
    gap = carry[2]
    return jnp.where(jnp.isfinite(gap), gap, jnp.nan)


def exact_gap_kernel(const, omega, k):
    """The largest gap of :func:`_gap` with the switching points gathered: a CPU's kernel."""
    return _gap(const, omega, k, gather=True)


def exact_gap_kernel_every(const, omega, k):
    """The largest gap of :func:`_gap` with every point's switch computed: an accelerator's kernel."""
    return _gap(const, omega, k, gather=False)


def gap_kernel(accelerator: bool):
    """The gap kernel for CPUs or for accelerators (:func:`camdyn._core.sharding.accelerated` of the devices)."""
    return exact_gap_kernel_every if accelerator else exact_gap_kernel
