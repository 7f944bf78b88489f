"""``camdyn sweep CASE.toml --speeds A:B:N``: the jump map over speeds x spring rates, as CSV and PNG."""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from .._core.distributed import initialize, is_writer
from .._core.errors import InputError
from .._core.outputs import output_dir, output_file, safe_stem, write_new
from ..design.sweep import JumpMap, check_grid_size, first_speeds, jump_map
from ..model.case import build_case
from ..plot import save_png
from ._console import progress_bar
from ._groove import sweep_groove


def run(args: argparse.Namespace) -> int:
    if args.spec.follower is not None and args.spec.follower.form_closed:  # a groove cam: its impacts, not jumps
        speeds = np.linspace(*args.speeds)  # (A, B, N), parsed and checked with the options
        gaps = None if args.backlash is None else np.linspace(*args.backlash)
        initialize(args.coordinator, args.num_processes, args.process_id, auto=args.distributed)
        if not is_writer():  # not sharded: process 0 does the work
            return 0
        return sweep_groove(args, build_case(args.spec, source=Path(args.case)), speeds, gaps)
    if args.backlash is not None:
        raise InputError("--backlash", 'only a groove cam ([follower] closure = "groove") has a backlash')
    speed_grid, rate_grid = args.speeds, args.spring_rates
    check_grid_size(
        speed_grid[2], 1 if rate_grid is None else rate_grid[2], "--speeds x --spring-rates"
    )  # before allocating it
    speeds = np.linspace(*speed_grid)
    rates = None if rate_grid is None else np.linspace(*rate_grid)
    initialize(args.coordinator, args.num_processes, args.process_id, auto=args.distributed)
    writer = is_writer()  # with several processes, process 0 writes
    case = build_case(args.spec, source=Path(args.case))
    stem = safe_stem(case.name)  # the case's name is data, not a path: the files stay in the folder named
    csv_path, png_path = Path(args.output) / f"{stem}-sweep.csv", Path(args.output) / f"{stem}-sweep.png"
    if writer:
        output_dir(args.output, "jump map")
        for path in (csv_path, png_path):
            output_file(path, args.force, "jump map")
    t0 = time.perf_counter()
    with progress_bar(args.quiet) as progress:
        jm = jump_map(case, speeds, rates, progress=progress if writer else None)
    elapsed = time.perf_counter() - t0
    if not writer:
        return 0
    write_new(csv_path, jm.csv, True)
    save_png(jm, png_path)
    ku = jm.spring_rate_unit
    n_sep = int(np.count_nonzero(jm.separated))
    print(
        f"{case.name}: jump map of {jm.separated.size} points ({speeds.size} speeds {speeds[0]:g}-{speeds[-1]:g} rpm "
        f"x {jm.spring_rates.size} spring rates {jm.spring_rates[0]:g}-{jm.spring_rates[-1]:g} {ku}), {jm.model} "
        f"follower, {elapsed:.1f} s on {jm.devices} device(s)"
    )
    print(
        f"preload kept at the case's {jm.preload:g} {jm.preload_unit} while the spring rate varies"
        + (
            f"; spring rates are torsion rates, {jm.kind.rate_unit} (column spring_rate_{jm.kind.rate_suffix})"
            if jm.kind.rotary
            else ""
        )
    )
    if jm.valve is not None:
        _print_valvetrain(jm)
    gap = np.nanmax(jm.max_gap) if n_sep and np.isfinite(jm.max_gap).any() else 0.0
    least = float(np.nanmin(jm.min_force)) if np.isfinite(jm.min_force).any() else math.nan
    n_failed = int(np.count_nonzero(jm.failed))
    print(
        f"{'floats' if jm.valve is not None else 'separated'} at {n_sep} of {jm.separated.size} points"
        + (f" (largest gap {gap:.4g} mm{' at the valve' if jm.valve is not None else ''})" if n_sep else "")
        + f"; least contact force on the map {least:.4g} N"
        + (f"; {n_failed} point(s) failed (status column)" if n_failed else "")
    )
    for note in jm.notes:
        print(f"warning: {note}", file=sys.stderr)
    print(f"wrote {csv_path} and {png_path}")
    return 0


def _print_valvetrain(jm: JumpMap) -> None:
    """A valvetrain's map: per valve spring rate, the first speed on the grid where it floats and where it
    bounces, which comes first, and the seating velocity there."""
    assert jm.valve is not None  # the caller's: a valvetrain's map
    floats, bounces = first_speeds(jm.speeds_rpm, jm.separated), first_speeds(jm.speeds_rpm, jm.valve.bounced)
    at = lambda w: "none on the grid" if math.isnan(w) else f"{w:g} rpm"  # noqa: E731
    for j, rate in enumerate(jm.spring_rates):
        f, b = floats[j], bounces[j]
        first = (
            "neither"
            if math.isnan(f) and math.isnan(b)
            else "float first"
            if math.isnan(b) or (not math.isnan(f) and f < b)
            else "bounce first"
            if math.isnan(f) or b < f
            else "both at once"
        )
        v = jm.valve.seating_velocity[:, j]
        seat = f"{np.nanmin(v):.3g}-{np.nanmax(v):.3g} m/s" if np.isfinite(v).any() else "-"
        print(f"valve spring {rate:g} N/mm: floats at {at(f)}, bounces at {at(b)} ({first}); seating {seat}")
