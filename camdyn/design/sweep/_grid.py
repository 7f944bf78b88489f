"""The jump map's grids and batch sizes: the angle grid of the least force, the revolutions and steps of the
gap integration, and how many grid points go to a device at once."""

from __future__ import annotations

from ..._core.units import THETA_GRID

GRID_N = THETA_GRID  # angle grid of the least force: 0.1 deg, the grid of ``camdyn check``
GAP_REVS = 6  # revolutions of the nonlinear model from the linear steady state
GAP_LAST = 2  # the largest gap is taken over the last GAP_LAST of them
GAP_SAMPLES = 1440  # diffrax: samples per revolution for the largest gap (0.25 deg)
GAP_STRIDE = 5  # exact stepping: a step of GAP_STRIDE points of the GRID_N grid (0.5 deg)
GAP_RTOL, GAP_ATOL = 1e-8, 1e-9  # diffrax tolerances of the gap integration (motion units)
GAP_MAX_STEPS = 400_000
LINEAR_CHUNK = 256  # grid points per device per chunk (frequency-domain steady state)
GAP_CHUNK = 64  # separated points per device per chunk (nonlinear integration)
