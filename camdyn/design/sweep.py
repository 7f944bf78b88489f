"""Jump maps: least interface force, separation and largest gap over a grid of cam speeds and spring rates.

The map is computed batched: every kernel is one ``jax.vmap`` over grid points, compiled once
(``jax.jit``) and sharded over all local JAX devices (``jax.shard_map`` on a one-axis mesh; the grid is cut
into chunks padded to a multiple of the device count, so a progress bar can follow the chunks).

* Compliant follower: while the follower stays on the cam the model is linear, so the steady state is exact
  in the frequency domain (harmonic balance by FFT, as :func:`camdyn.dynamics.linear_min_force`) on the same
  0.1 degree grid ``camdyn check`` uses. Where that least force is <= 0 no steady state stays in contact: the
  follower separates, its least force is 0, and the largest gap comes from the nonlinear model integrated
  ``GAP_REVS`` revolutions in the cam angle from the linear steady state; the gap is the largest ``x - s`` over
  the last ``GAP_LAST`` revolutions (a period-2 bounce alternates between two gaps). The integration is exact
  piecewise-linear stepping (:func:`_exact_gap_kernel`: both contact modes are linear), vmapped; diffrax on
  the vector field of :mod:`camdyn.dynamics` (``gap_method="diffrax"``) is the reference, about 20x slower.
* Rigid follower: the least force is the kinematic one (closed form per angle, vectorized); where it is
  <= 0 the follower separates, and the largest gap comes from the event-driven flight model
  (:func:`camdyn.dynamics.rigid_response`), one separated point at a time (a Python loop, not batched).
* Oscillating follower: the model is rotational; forces are converted to N through the lever arm of the
  contact normal (as ``check`` does) and gaps to mm along the normal (lever arm x arm-swing gap, first order).
  Its spring rates are torsion rates, N*m/rad (the column keeps its name ``spring_rate_N_per_mm``).

The case's preload F0 is kept fixed while the spring rate varies; damping given as ``damping_ratio`` scales
with sqrt(k m), damping given as ``damping`` stays fixed.
"""

from __future__ import annotations

import functools
import io
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, PartitionSpec

from .._core.errors import InputError, NumericalError
from .._core.progress import Progress, counter
from .._core.units import RPM, THETA_GRID, TWO_PI, rate_from_si, rate_to_si
from ..model import dynamics as dyn
from ..model.dynamics._compliant import _vector_field
from ..model.follower import FollowerModel
from ..model.geometry import newton_per_torque_at
from ..model.motion import evaluate

GRID_N = THETA_GRID  # angle grid of the least force: 0.1 deg, the grid of ``camdyn check``
GAP_REVS = 6  # revolutions of the nonlinear model from the linear steady state
GAP_LAST = 2  # the largest gap is taken over the last GAP_LAST of them
GAP_SAMPLES = 1440  # diffrax: samples per revolution for the largest gap (0.25 deg)
GAP_STRIDE = 5  # exact stepping: a step of GAP_STRIDE points of the GRID_N grid (0.5 deg)
GAP_RTOL, GAP_ATOL = 1e-8, 1e-9  # diffrax tolerances of the gap integration (motion units)
_GAP_MAX_STEPS = 400_000
LINEAR_CHUNK = 256  # grid points per device per chunk (frequency-domain steady state)
GAP_CHUNK = 64  # separated points per device per chunk (nonlinear integration)
CSV_COLUMNS = ("speed_rpm", "spring_rate_N_per_mm", "min_contact_force_N", "separated", "max_gap_mm")


@dataclass(frozen=True)
class JumpMap:
    """A jump map: arrays of shape (len(speeds_rpm), len(spring_rates)), forces in N and gaps in mm."""

    case: str
    model: str  # "compliant" | "rigid"
    oscillating: bool
    speeds_rpm: np.ndarray  # (ns,)
    spring_rates: np.ndarray  # (nk,) N/mm; N*m/rad for an oscillating follower
    min_force: np.ndarray  # least interface force, N; 0 where the follower separates
    separated: np.ndarray  # bool
    max_gap: np.ndarray  # largest gap, mm; 0 where it stays on the cam, NaN where the integration failed
    contact_force: np.ndarray  # signed least force of the in-contact model (linear steady state / kinematic), N: <= 0 beyond the jump boundary
    speed_rpm: float  # the case's operating point
    spring_rate: float
    preload: float  # kept fixed over the map: N (N*m for an oscillating follower)
    devices: int = 1
    notes: tuple[str, ...] = field(default=())

    @property
    def spring_rate_unit(self) -> str:
        return "N*m/rad" if self.oscillating else "N/mm"

    @property
    def preload_unit(self) -> str:
        return "N*m" if self.oscillating else "N"

    @property
    def csv(self) -> str:
        """CSV text: one row per grid point (speed-major), columns :data:`CSV_COLUMNS`."""
        sp, kr = np.meshgrid(self.speeds_rpm, self.spring_rates, indexing="ij")
        data = np.column_stack([sp.ravel(), kr.ravel(), self.min_force.ravel(), self.separated.ravel().astype(float), self.max_gap.ravel()])
        buf = io.StringIO()
        buf.write(",".join(CSV_COLUMNS) + "\n")
        np.savetxt(buf, data, delimiter=",", fmt=["%.10g", "%.10g", "%.10g", "%d", "%.10g"])
        return buf.getvalue()


# ---------------------------------------------------------------------------------- sharding
def _shard_map(f, mesh, in_specs, out_specs):
    if hasattr(jax, "shard_map"):
        return jax.shard_map(f, mesh=mesh, in_specs=in_specs, out_specs=out_specs, check_vma=False)
    from jax.experimental.shard_map import shard_map  # older JAX

    return shard_map(f, mesh=mesh, in_specs=in_specs, out_specs=out_specs, check_rep=False)


@functools.lru_cache(maxsize=None)
def _sharded(kernel: Callable, devices: tuple):
    """``kernel(const, *point)`` vmapped over grid points and sharded over ``devices``, compiled."""
    mesh = Mesh(np.asarray(devices), ("grid",))

    def run(const, *batched):
        body = lambda c, *b: jax.vmap(lambda *p: kernel(c, *p))(*b)  # noqa: E731
        spec = PartitionSpec("grid")
        return _shard_map(body, mesh, (PartitionSpec(), *([spec] * len(batched))), spec)(const, *batched)

    return eqx.filter_jit(run)


def _batched(kernel: Callable, const, batched: list[np.ndarray], chunk: int, progress: Callable[[int], None] | None, devices: tuple):
    """Run ``kernel`` over the rows of ``batched`` in chunks of ``chunk`` points per device (padded)."""
    n_dev = len(devices)
    size = chunk * n_dev * (1 if devices[0].platform == "cpu" else 16)  # accelerators want wide batches
    n = batched[0].shape[0]
    fn = _sharded(kernel, devices)
    outs = []
    for start in range(0, n, size):
        part = [b[start : start + size] for b in batched]
        m = part[0].shape[0]
        if m < size:  # pad with copies of the first point: one compiled shape for every chunk
            part = [np.concatenate([p, np.repeat(p[:1], size - m, axis=0)]) for p in part]
        res = fn(const, *(jnp.asarray(p) for p in part))
        res = jax.tree_util.tree_map(lambda r: np.asarray(r)[:m], res)
        outs.append(res)
        if progress is not None:
            progress(m)
    return jax.tree_util.tree_map(lambda *r: np.concatenate(r), *outs)


# ----------------------------------------------------------------------------------- kernels
def _with_spring(base: FollowerModel, k, c) -> FollowerModel:
    return eqx.tree_at(lambda m: (m.stiffness, m.damping), base, (k, c))


def _linear_kernel(const, omega, k, c):
    """Least force (N, weighted) of the frequency-domain steady state, and its state (x, dx/dtheta) at 0."""
    base, s, s1, spec, weight = const
    n = s.shape[0]
    md = _with_spring(base, k, c)
    kk = jnp.arange(spec.shape[0])
    m, kf, cf = md.mass, md.train_stiffness, md.train_damping
    wk = kk * omega
    x_spec = spec * (kf + 1j * wk * cf) / (k + kf - m * wk**2 + 1j * wk * (c + cf))
    x_spec = x_spec.at[0].set((kf * spec[0] - n * (md.preload + md.external)) / (k + kf))
    x = jnp.fft.irfft(x_spec, n)
    x1 = jnp.fft.irfft(1j * kk * x_spec, n)
    force = (kf * (s - x) + cf * omega * (s1 - x1)) * weight
    return jnp.min(force), jnp.stack([x[0], x1[0]]) / md.scale


def _kinematic_kernel(const, omega, k, c):
    """Least kinematic (rigid follower) interface force, N (weighted)."""
    base, s, s1, s2, weight = const
    f = base.mass * omega**2 * s2 + c * omega * s1 + k * s + base.preload + base.external
    return jnp.min(f * weight)


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


def _exact_gap_kernel(const, omega, k, c, z0):
    """Largest gap (weighted: mm) of the nonlinear compliant model by exact piecewise-linear stepping.

    Both modes of the compliant model are linear: in contact the state is the linear steady state plus a
    free vibration of the contact system, in flight a free vibration of spring and damper about their
    equilibrium. So each step of the angle grid is exact (2x2 matrix exponentials in closed form); where the
    contact condition changes sign within a step, the switch is located on the cubic Hermite interpolant of
    the step (Illinois iterations) and the rest of the step is exact in the new mode. The mode is recomputed
    from the state at every step, exactly as the vector field decides it (``s > x`` and ``Fi > 0``).
    """
    base, s_tab, s1_tab, s2_tab, w_tab, spec = const
    n_fft = 2 * (spec.shape[0] - 1)
    m_steps = s_tab.shape[0]
    stride = n_fft // m_steps
    h = TWO_PI / m_steps
    sc = base.scale
    md = _with_spring(base, k, c)
    mw2 = md.mass * omega**2
    a_k, b_c = k / mw2, c / (md.mass * omega)
    a_f, b_f = md.train_stiffness / mw2, md.train_damping / (md.mass * omega)
    f0 = (md.preload + md.external) / (mw2 * sc)
    xf = -f0 / a_k  # flight equilibrium
    # linear (contact) steady state on the FFT grid, in motion units, sampled on the step grid
    kk = jnp.arange(spec.shape[0])
    wk = kk * omega
    x_spec = spec * (md.train_stiffness + 1j * wk * md.train_damping) / (k + md.train_stiffness - md.mass * wk**2 + 1j * wk * (c + md.train_damping))
    x_spec = x_spec.at[0].set((md.train_stiffness * spec[0] - n_fft * (md.preload + md.external) / sc) / (k + md.train_stiffness))
    xl_tab = jnp.fft.irfft(x_spec, n_fft)[::stride]
    pl_tab = jnp.fft.irfft(1j * kk * x_spec, n_fft)[::stride]
    ec = _expm2(a_k + a_f, b_c + b_f, h)
    ef = _expm2(a_k, b_c, h)

    def acc(contact, s, s1, x, p):
        free = -a_k * x - b_c * p - f0
        return jnp.where(contact, free + a_f * (s - x) + b_f * (s1 - p), free)

    def g(s, s1, x, p):  # > 0 exactly where the vector field has contact: s > x and Fi > 0
        return jnp.minimum(a_f * (s - x), a_f * (s - x) + b_f * (s1 - p))

    last = (GAP_REVS - GAP_LAST) * m_steps
    uu = (0.25, 0.5, 0.75)

    def step(carry, j):
        x, p, gap = carry
        i0, i1 = j % m_steps, (j + 1) % m_steps
        s0, s10, s20, s1_, s11, s21 = s_tab[i0], s1_tab[i0], s2_tab[i0], s_tab[i1], s1_tab[i1], s2_tab[i1]
        xl0, pl0, xl1, pl1 = xl_tab[i0], pl_tab[i0], xl_tab[i1], pl_tab[i1]
        g0 = g(s0, s10, x, p)
        contact = g0 > 0
        dx, dp = x - xl0, p - pl0
        fx = x - xf
        x1 = jnp.where(contact, xl1 + ec[0] * dx + ec[1] * dp, xf + ef[0] * fx + ef[1] * p)
        p1 = jnp.where(contact, pl1 + ec[2] * dx + ec[3] * dp, ef[2] * fx + ef[3] * p)
        g1 = g(s1_, s11, x1, p1)
        event = (g1 > 0) != contact
        a0, a1 = acc(contact, s0, s10, x, p), acc(contact, s1_, s11, x1, p1)

        def g_at(t):
            u = t / h
            return g(_hermite(s0, s10, s1_, s11, u, h), _hermite(s10, s20, s11, s21, u, h), _hermite(x, p, x1, p1, u, h), _hermite(p, a0, p1, a1, u, h))

        # the switch: Illinois iterations on the Hermite interpolant of this step in the current mode
        ta, tb, ga, gb = 0.0, h, g0, g1
        for _ in range(3):
            den = gb - ga
            t = jnp.clip((ta * gb - tb * ga) / jnp.where(den != 0, den, 1.0), 0.0, h)
            gt = g_at(t)
            flip = gt * gb < 0
            ta, ga = jnp.where(flip, tb, ta), jnp.where(flip, gb, 0.5 * ga)
            tb, gb = t, gt
        u = tb / h
        xs, ps = _hermite(x, p, x1, p1, u, h), _hermite(p, a0, p1, a1, u, h)
        # the rest of the step, exact in the new mode (about the linear steady state or the flight equilibrium)
        to_contact = ~contact
        er = _expm2(jnp.where(to_contact, a_k + a_f, a_k), jnp.where(to_contact, b_c + b_f, b_c), h - tb)
        al0, al1 = acc(True, s0, s10, xl0, pl0), acc(True, s1_, s11, xl1, pl1)
        rx = jnp.where(to_contact, _hermite(xl0, pl0, xl1, pl1, u, h), xf)
        rp = jnp.where(to_contact, _hermite(pl0, al0, pl1, al1, u, h), 0.0)
        dx, dp = xs - rx, ps - rp
        x_ev = jnp.where(to_contact, xl1, xf) + er[0] * dx + er[1] * dp
        p_ev = jnp.where(to_contact, pl1, 0.0) + er[2] * dx + er[3] * dp
        x_next, p_next = jnp.where(event, x_ev, x1), jnp.where(event, p_ev, p1)
        # the gap at the step end and inside the step (Hermite of this step): 0.125 deg apart
        w0, w1 = w_tab[i0], w_tab[i1]
        inner = [(_hermite(x, p, x1, p1, v, h) - _hermite(s0, s10, s1_, s11, v, h)) * (w0 + v * (w1 - w0)) for v in uu]
        cand = jnp.maximum(jnp.where(event, -jnp.inf, jnp.maximum(jnp.maximum(inner[0], inner[1]), inner[2])), (x_next - s1_) * w1)
        gap = jnp.where(j + 1 >= last, jnp.maximum(gap, cand), gap)
        return (x_next, p_next, gap), None

    (_, _, gap), _ = jax.lax.scan(step, (xl_tab[0], pl_tab[0], jnp.asarray(-jnp.inf)), jnp.arange(GAP_REVS * m_steps))
    del z0  # the start is the linear steady state at theta = 0, recomputed here
    return jnp.where(jnp.isfinite(gap), gap, jnp.nan)


def _gap_kernel(const, omega, k, c, z0):
    """Largest gap (weighted: mm) of the nonlinear compliant model over the last revolutions; NaN on failure."""
    motion, base, jumps, ts, s_ts, weight_ts = const
    md = _with_spring(base, k, c)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_vector_field),
        diffrax.Tsit5(),
        t0=0.0,
        t1=TWO_PI * GAP_REVS,
        dt0=None,
        y0=z0,
        args=(motion, md, omega, True),
        saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=diffrax.ClipStepSizeController(diffrax.PIDController(rtol=GAP_RTOL, atol=GAP_ATOL), jump_ts=jumps),
        max_steps=_GAP_MAX_STEPS,
        throw=False,
    )
    gap = jnp.max((sol.ys[:, 0] - s_ts) * weight_ts)
    ok = (sol.result == diffrax.RESULTS.successful) & jnp.isfinite(gap)
    return jnp.where(ok, gap, jnp.nan)


# -------------------------------------------------------------------------------------- map
def _lever_arm_mm(case, theta) -> np.ndarray:
    return 1000.0 / newton_per_torque_at(case.motion, case.follower, np.asarray(theta))


def jump_map(
    case,
    speeds_rpm,
    spring_rates=None,
    *,
    progress: Progress | None = None,
    gap_method: str = "exact",
    devices=None,
    gaps: bool = True,
) -> JumpMap:
    """Jump map of ``case`` over ``speeds_rpm`` x ``spring_rates`` (N/mm; N*m/rad for an oscillating follower).

    ``spring_rates`` defaults to the case's own. ``progress(phase, done, total)`` is called after every chunk.
    ``gap_method``: how the compliant model's separated points are integrated: ``"exact"`` (piecewise-linear
    stepping, :func:`_exact_gap_kernel`) or ``"diffrax"`` (adaptive Tsit5 on the vector field of
    :mod:`camdyn.dynamics`, the reference; about 20x slower). ``devices``: the JAX devices to shard the grid
    over (default: all local devices); the result does not depend on them. ``gaps=False`` skips the largest gap
    of the separated points (the nonlinear integration, most of the cost of a rigid follower's map): their
    ``max_gap`` is NaN; the least force, the separation and the jump boundary are the same.
    """
    devices = tuple(jax.devices() if devices is None else devices)
    if gap_method not in ("exact", "diffrax"):
        raise ValueError(f"gap_method must be 'exact' or 'diffrax', not {gap_method!r}")
    motion, base = case.motion, case.model
    rate0 = float(rate_from_si(base.stiffness, case.oscillating))
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    rates = np.atleast_1d(np.asarray(spring_rates if spring_rates is not None else [rate0], dtype=float))
    if speeds.size == 0 or rates.size == 0 or not (np.all(speeds > 0) and np.all(rates > 0) and np.all(np.isfinite(speeds)) and np.all(np.isfinite(rates))):
        raise InputError("sweep", "speeds and spring rates must be positive and finite")
    ns, nk = speeds.size, rates.size
    sp, kr = np.meshgrid(speeds, rates, indexing="ij")
    omega = sp.ravel() * RPM
    k_si = rate_to_si(kr.ravel(), case.oscillating)
    c_si = np.asarray(base.damping_at(jnp.asarray(k_si)))
    npts = omega.size

    theta = np.arange(GRID_N) * (TWO_PI / GRID_N)
    vals = np.asarray(evaluate(motion, jnp.asarray(theta))) * base.scale
    weight = newton_per_torque_at(motion, case.follower, theta) if case.oscillating else np.ones(GRID_N)

    def tick(phase, total):
        return counter(progress, phase, total)

    notes: list[str] = []
    if base.rigid:
        const = (base, *(jnp.asarray(v) for v in vals[:3]), jnp.asarray(weight))
        signed = _batched(_kinematic_kernel, const, [omega, k_si, c_si], LINEAR_CHUNK, tick("kinematic force", npts), devices)
        separated = signed <= 0.0
        gap = np.zeros(npts)
        idx = np.nonzero(separated)[0] if gaps else np.zeros(0, dtype=int)
        step = tick("flights (rigid model, one point at a time)", idx.size)
        for i in idx:
            # Python floats, as case.follower_model builds them: the compiled flight solve is reused
            md = _with_spring(base, jnp.asarray(float(k_si[i])), jnp.asarray(float(c_si[i])))
            try:
                r = dyn.rigid_response(motion, md, float(omega[i]))
            except NumericalError:
                gap[i] = np.nan
            else:
                w = _lever_arm_mm(case, np.deg2rad(r.theta_deg)) if case.oscillating else 1.0
                gap[i] = max(0.0, float(np.max((r.x - r.s) * w)))
            step(1)
        model = "rigid"
    else:
        spec = jnp.fft.rfft(jnp.asarray(vals[0]))
        const = (base, jnp.asarray(vals[0]), jnp.asarray(vals[1]), spec, jnp.asarray(weight))
        signed, z0 = _batched(_linear_kernel, const, [omega, k_si, c_si], LINEAR_CHUNK, tick("steady state (frequency domain)", npts), devices)
        separated = signed <= 0.0
        gap = np.zeros(npts)
        idx = np.nonzero(separated)[0] if gaps else np.zeros(0, dtype=int)
        if idx.size and gap_method == "exact":
            tab = np.asarray(evaluate(motion, jnp.asarray(theta[::GAP_STRIDE])))[:3]
            w_tab = _lever_arm_mm(case, theta[::GAP_STRIDE]) if case.oscillating else np.ones(tab.shape[1])
            gconst = (base, *(jnp.asarray(t) for t in tab), jnp.asarray(w_tab), jnp.fft.rfft(jnp.asarray(vals[0] / base.scale)))
            g = _batched(_exact_gap_kernel, gconst, [omega[idx], k_si[idx], c_si[idx], z0[idx]], GAP_CHUNK, tick("separated points (nonlinear model)", idx.size), devices)
            gap[idx] = np.maximum(g, 0.0)
        elif idx.size:
            breaks = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
            jumps = np.sort((breaks[None, :] + TWO_PI * np.arange(GAP_REVS + 1)[:, None]).ravel())
            ts = TWO_PI * (GAP_REVS - GAP_LAST) + np.arange(GAP_LAST * GAP_SAMPLES) * (TWO_PI / GAP_SAMPLES)
            s_ts = np.asarray(evaluate(motion, jnp.asarray(ts)))[0]
            w_ts = _lever_arm_mm(case, ts % TWO_PI) if case.oscillating else np.ones_like(ts)
            gconst = (motion, base, jnp.asarray(jumps), jnp.asarray(ts), jnp.asarray(s_ts), jnp.asarray(w_ts))
            g = _batched(_gap_kernel, gconst, [omega[idx], k_si[idx], c_si[idx], z0[idx]], GAP_CHUNK, tick("separated points (nonlinear model)", idx.size), devices)
            gap[idx] = np.maximum(g, 0.0)
        model = "compliant"
    if not gaps:
        gap[separated] = np.nan
        if separated.any():
            notes.append("gaps not computed (gaps=False): max_gap_mm is NaN where the follower separates")
    failed = int(np.count_nonzero(~np.isfinite(gap))) if gaps else 0
    if failed:
        notes.append(f"the flight integration failed at {failed} separated point(s): their max_gap_mm is NaN")
    if not np.all(np.isfinite(signed)):
        raise NumericalError("sweep", "the steady-state force is not finite at some grid points")
    shape = (ns, nk)
    return JumpMap(
        case=case.name,
        model=model,
        oscillating=case.oscillating,
        speeds_rpm=speeds,
        spring_rates=rates,
        min_force=np.where(separated, 0.0, signed).reshape(shape),
        separated=separated.reshape(shape),
        max_gap=gap.reshape(shape),
        contact_force=np.asarray(signed).reshape(shape),
        speed_rpm=float(case.speed_rpm),
        spring_rate=rate0,
        preload=float(base.preload),
        devices=len(devices),
        notes=tuple(notes),
    )
