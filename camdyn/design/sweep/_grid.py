"""The jump map's grids and batch sizes: the angle grid of the least force, the revolutions and steps of the
gap integration, and how many grid points go to a device at once."""

from __future__ import annotations

from ..._core.errors import InputError
from ..._core.units import THETA_GRID

GRID_N = THETA_GRID  # angle grid of the least force: 0.1 deg, the grid of ``camdyn check``
GAP_REVS = 6  # revolutions of the nonlinear model from the linear steady state
GAP_LAST = 2  # the largest gap is taken over the last GAP_LAST of them
GAP_SAMPLES = 1440  # diffrax: samples per revolution for the largest gap (0.25 deg)
GAP_STRIDE = 5  # exact stepping: a step of GAP_STRIDE points of the GRID_N grid (0.5 deg)
GAP_RTOL, GAP_ATOL = 1e-8, 1e-9  # diffrax tolerances of the gap integration (motion units)
GAP_MAX_STEPS = 400_000
LINEAR_CHUNK = 256  # grid points per device per chunk (frequency-domain steady state)
GAP_CHUNK = 1024  # separated points per device per chunk (nonlinear integration; a scan step costs per call: wide)

# The budget of one map: its arrays, its CSV (about 70 bytes a row) and its time grow with the number of points,
# and a compliant point costs about 15 us (in contact) to 0.15 ms (separated) of CPU, a rigid separated point 10 ms
# or more. 1e6 points is a few hundred MB and minutes to hours on a CPU: beyond it a grid is refused.
MAX_GRID_POINTS = 1_000_000


def check_grid_size(n_speeds: int, n_rates: int, where: str = "sweep") -> None:
    """Refuse a grid of more than :data:`MAX_GRID_POINTS` points, naming the budget (one line, before any work)."""
    n = int(n_speeds) * int(n_rates)
    if n > MAX_GRID_POINTS:
        raise InputError(
            where,
            f"a grid of {n_speeds:,} speeds x {n_rates:,} spring rates = {n:,} points is beyond the sweep's budget "
            f"of {MAX_GRID_POINTS:,} points (memory and time: a few hundred MB and up to hours of CPU at the "
            "budget); use fewer points",
        )
