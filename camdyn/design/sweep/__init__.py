"""Jump maps: least interface force, separation and largest gap over a grid of cam speeds and spring rates.

The map is computed batched: every kernel is one ``jax.vmap`` over grid points (the exact gap stepping takes a
chunk of points as arrays itself), compiled once and sharded over all local JAX devices
(:mod:`camdyn._core.sharding`: ``jax.shard_map`` on a one-axis mesh; the grid is cut into chunks padded to a
multiple of the device count, so a progress bar can follow the chunks).

* Compliant follower (:mod:`._contact`): while the follower stays on the cam the model is linear, so the steady
  state is exact in the frequency domain (harmonic balance by FFT, :func:`camdyn.model.dynamics.steady_state`;
  its interface force by one inverse FFT, :func:`camdyn.model.dynamics.steady_train_force`) on the same 0.1 degree
  grid ``camdyn check`` uses. Where that least force is <= 0 no steady state stays in
  contact: the follower separates, its least force is 0, and the largest gap comes from the nonlinear model
  integrated ``GAP_REVS`` revolutions in the cam angle from the linear steady state; the gap is the largest
  ``x - s`` over the last ``GAP_LAST`` revolutions (a period-2 bounce alternates between two gaps). The
  integration is exact piecewise-linear stepping (:mod:`._exact_gap`: both contact modes are linear), a chunk
  of points stepped together and the few whose contact switches within a step gathered for the switch;
  diffrax on the vector field of :mod:`camdyn.model.dynamics` (``gap_method="diffrax"``, :mod:`._diffrax_gap`)
  is the reference, tens of times slower; on the benchmark's map both agree to a median 3e-5 mm. Its program
  depends on the follower kind and the shapes only, so a map compiles (or loads) it in another thread from the
  start, beside the motion's evaluation and the steady state (most of a first map's time on a CPU). A CPU gathers
  the switching points; an accelerator computes every point's switch (:func:`._exact_gap.gap_kernel`, chosen by
  :func:`camdyn._core.sharding.accelerated`, the test that also sets the batch width).
* Rigid follower: the least force is the kinematic one (closed form per angle, vectorized); where it is
  <= 0 the follower separates, and the largest gap comes from the event-driven flight model
  (:func:`camdyn.model.dynamics.rigid_response`), one separated point at a time (a Python loop, not batched).
* Oscillating follower: the model is rotational; forces are converted to N through the lever arm of the
  contact normal (as ``check`` does) and gaps to mm along the normal (lever arm x arm-swing gap, first order).
  Its spring rates are torsion rates, N*m/rad: the CSV column ``spring_rate_N_m_per_rad`` (the old column
  ``spring_rate_N_per_mm`` holds the same numbers for those scripts that read it: deprecated for an arm).

Every point ends with a status: a point whose computation fails (a :class:`NumericalError` of the flight model,
a steady state or gap that is not finite, even an unexpected error at one point) is flagged ``failed: <reason>``
with NaN numbers, and the map goes on. A grid beyond :data:`MAX_GRID_POINTS` is refused before any work.

The case's preload F0 is kept fixed while the spring rate varies; damping given as ``damping_ratio`` scales
with sqrt(k m) (:meth:`camdyn.model.follower.FollowerModel.damping_at`), damping given as ``damping`` stays fixed.
The map and its CSV are :mod:`._result`; :mod:`._map` assembles them. A valvetrain's map is the two-mass model's,
one point at a time (:mod:`._valvetrain`): float, bounce, the seating velocity and the gap at the valve.
"""

from ._grid import (
    GAP_CHUNK,
    GAP_LAST,
    GAP_REVS,
    GAP_SAMPLES,
    GAP_STRIDE,
    GRID_N,
    LINEAR_CHUNK,
    MAX_GRID_POINTS,
    check_grid_size,
)
from ._map import jump_map
from ._result import CSV_COLUMNS, STATUS_OK, JumpMap, ValveMap, first_speeds

__all__ = [
    "CSV_COLUMNS",
    "GAP_CHUNK",
    "GAP_LAST",
    "GAP_REVS",
    "GAP_SAMPLES",
    "GAP_STRIDE",
    "GRID_N",
    "JumpMap",
    "LINEAR_CHUNK",
    "MAX_GRID_POINTS",
    "STATUS_OK",
    "ValveMap",
    "check_grid_size",
    "first_speeds",
    "jump_map",
]
