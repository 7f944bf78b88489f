"""The bounds on what a user asks of a command (a table's rows, an e-cam table's points, a study's samples, a profile's
chord tolerance, sizing's speeds) and their one-line refusals. Light (no JAX, no numpy): the command line checks its
options with them before JAX loads, and the library's functions check their arguments with the same ones."""

from __future__ import annotations

import math

from .errors import InputError
from .units import MAX_RATE_N_PER_MM, MAX_SPEED_RPM, SPEED_MARGIN_RANGE

MAX_ROWS = 1_000_000  # a table is read by people and spreadsheets: a million rows is already more than either wants
MAX_ECAM_POINTS = 100_000  # a servo drive's cam table holds a few thousand points at most
MIN_TOLERANCE_MM = 1e-6  # a nanometre: finer is below any machine's resolution (and would need millions of points)
MAX_TOLERANCE_MM = 10.0
MAX_SAMPLES = 10_000_000  # a tolerance study's built cams


def check_table_step(step_deg: float) -> None:
    """A table's angle step (deg): in (0, 360] and at most :data:`MAX_ROWS` rows."""
    if not 0 < step_deg <= 360:
        raise InputError("--step", f"must be in (0, 360] deg (got {step_deg:g})")
    rows = 360.0 / step_deg
    if rows > MAX_ROWS:
        raise InputError(
            "--step",
            f"{step_deg:g} deg makes {rows:.3g} rows; a table has at most {MAX_ROWS:,} (a step of at least "
            f"{360.0 / MAX_ROWS:g} deg)",
        )


def check_ecam_points(n: int) -> None:
    """An e-cam table's master angles: 2 to :data:`MAX_ECAM_POINTS`."""
    if not 2 <= n <= MAX_ECAM_POINTS:
        raise InputError("--ecam", f"must be between 2 and {MAX_ECAM_POINTS:,} master angles (got {n})")


def check_chord_tolerance(tolerance_mm: float) -> None:
    """A profile's chord tolerance (mm): :data:`MIN_TOLERANCE_MM` to :data:`MAX_TOLERANCE_MM`."""
    if not MIN_TOLERANCE_MM <= tolerance_mm <= MAX_TOLERANCE_MM:
        raise InputError(
            "--tolerance",
            f"must be between {MIN_TOLERANCE_MM:g} and {MAX_TOLERANCE_MM:g} mm, got {tolerance_mm:g} mm",
        )


def check_samples(samples: int) -> None:
    """A tolerance study's samples: 1 to :data:`MAX_SAMPLES`."""
    if not 1 <= samples <= MAX_SAMPLES:
        raise InputError("--samples", f"must be from 1 to {MAX_SAMPLES}, got {samples}")


def check_sizing(max_speed_rpm: float | None, margin: float | None, min_rate: float) -> None:
    """``size``'s top speed (rpm, up to a case's largest speed), margin (x, as ``[limits] speed_margin``: 1 to 100)
    and least spring rate (>= 0, up to a case's largest), where given."""
    if max_speed_rpm is not None and not (math.isfinite(max_speed_rpm) and 0 < max_speed_rpm <= MAX_SPEED_RPM):
        raise InputError(
            "--max-speed", f"must be a speed above 0 and at most {MAX_SPEED_RPM:g} rpm (got {max_speed_rpm:g})"
        )
    lo, hi = SPEED_MARGIN_RANGE
    if margin is not None and not (math.isfinite(margin) and lo <= margin <= hi):
        raise InputError(
            "--margin", f"must be a multiple of the speed from {lo:g} to {hi:g}, as speed_margin (got {margin:g})"
        )
    if not (math.isfinite(min_rate) and 0 <= min_rate <= MAX_RATE_N_PER_MM):
        raise InputError("--min-rate", f"must be a number from 0 to {MAX_RATE_N_PER_MM:g} (got {min_rate:g})")


def check_min_force(margin: float) -> None:
    """``optimize``'s force margin (N; N*m for an arm): finite and >= 0."""
    if not math.isfinite(margin) or margin < 0.0:
        raise InputError("--min-force", f"must be a finite force >= 0, got {margin:g}")
