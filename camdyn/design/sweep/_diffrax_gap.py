"""The reference for the largest gap: diffrax (adaptive Tsit5) on the compliant model's own vector field, from the
linear steady state, tens of times slower than the exact stepping of :mod:`._exact_gap`."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..._core.units import TWO_PI
from ...model.dynamics import steady_state, vector_field
from ...model.motion import evaluate
from ._contact import with_spring_damping
from ._grid import GAP_ATOL, GAP_LAST, GAP_MAX_STEPS, GAP_REVS, GAP_RTOL, GAP_SAMPLES


def diffrax_gap_const(case, gap_weight_mm, spec):
    """The kernel's constants: segment boundaries over the revolutions, the sampled angles of the last
    revolutions, the cam there, the gap weight ``gap_weight_mm(theta)`` (1, or an arm's lever arm) and ``spec``,
    the rfft of the lift (the motion's unit) on the fine grid (the linear steady state the integration starts
    from)."""
    motion = case.motion.jit_form()  # compiled once per follower kind, not once per case
    breaks = np.asarray(motion.jump_angles())  # +inf past a program's breaks: the controller skips those
    jumps = np.sort((breaks[None, :] + TWO_PI * np.arange(GAP_REVS + 1)[:, None]).ravel())
    ts = TWO_PI * (GAP_REVS - GAP_LAST) + np.arange(GAP_LAST * GAP_SAMPLES) * (TWO_PI / GAP_SAMPLES)
    s_ts = np.asarray(evaluate(motion, jnp.asarray(ts)))[0]
    w_ts = gap_weight_mm(ts % TWO_PI)
    return (motion, case.model, jnp.asarray(jumps), jnp.asarray(ts), jnp.asarray(s_ts), jnp.asarray(w_ts), spec)


def diffrax_gap_kernel(const, omega, k):
    """Largest gap (weighted: mm) of the nonlinear compliant model over the last revolutions from the linear
    steady state at theta = 0; NaN on failure."""
    import diffrax  # diffrax loads where a program is traced, not where a stored one runs

    motion, base, jumps, ts, s_ts, weight_ts, spec = const
    c = base.damping_at(k)
    md = with_spring_damping(base, k, c)
    x, x1 = steady_state(spec, omega, base, k, c, 2 * (spec.shape[0] - 1), unit=base.scale)
    z0 = jnp.stack([x[0], x1[0]])
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(vector_field),
        diffrax.Tsit5(),
        t0=0.0,
        t1=TWO_PI * GAP_REVS,
        dt0=None,
        y0=z0,
        args=(motion, md, omega, True),
        saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=diffrax.ClipStepSizeController(
            diffrax.PIDController(rtol=GAP_RTOL, atol=GAP_ATOL), jump_ts=jumps
        ),
        max_steps=GAP_MAX_STEPS,
        throw=False,
    )
    assert sol.ys is not None  # SaveAt(ts=...) saves the states
    gap = jnp.max((sol.ys[:, 0] - s_ts) * weight_ts)
    ok = (sol.result == diffrax.RESULTS.successful) & jnp.isfinite(gap)
    return jnp.where(ok, gap, jnp.nan)
