"""``sweep`` and ``tolerance`` of a groove cam (``[follower] closure = "groove"``): its crossover impacts over
cam speed x backlash, and their distribution over the built cams, in place of the jump map and the probability of
separation of a spring-held follower (a groove cam cannot jump)."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .._core.errors import InputError
from .._core.outputs import output_dir, output_file, safe_stem, write_new
from ..design.closure import impact_map
from ..design.tolerance import impact_tolerance_study
from ..model.case import Case
from ..plot import save_impact_histogram_png, save_impact_png
from ._console import console, json_text, progress_bar, table


def _outputs(args: argparse.Namespace, case: Case, suffix: str, what: str) -> tuple[Path, Path]:
    """DIR/<case>-<suffix>.csv and .png, checked writable (and not there, without --force) before the work."""
    stem = safe_stem(case.name)  # the case's name is data, not a path: the files stay in the folder named
    paths = Path(args.output) / f"{stem}-{suffix}.csv", Path(args.output) / f"{stem}-{suffix}.png"
    output_dir(args.output, what)
    for path in paths:
        output_file(path, args.force, what)
    return paths


def sweep_groove(args: argparse.Namespace, case: Case, speeds: np.ndarray, gaps: np.ndarray | None) -> int:
    """``camdyn sweep`` of a groove cam: DIR/<case>-sweep.csv (the impact map over ``speeds`` x ``gaps``, mm;
    None: the case's backlash) and DIR/<case>-sweep.png."""
    assert case.follower is not None and case.follower.form_closed
    if args.spring_rates is not None:
        raise InputError(
            "--spring-rates", "a groove cam has no return spring to vary: sweep its --backlash (mm) instead"
        )
    if gaps is None:
        gaps = np.array([case.follower.backlash])
    csv_path, png_path = _outputs(args, case, "sweep", "impact map")
    with progress_bar(args.quiet) as progress:
        im = impact_map(case, speeds, gaps, progress=progress)
    write_new(csv_path, im.csv, True)
    save_impact_png(im, png_path, speed_rpm=case.speed_rpm, backlash_mm=case.follower.backlash)
    lim = im.max_impact_velocity
    over = im.impact_velocity_m_per_s > lim
    print(
        f"{case.name}: groove cam, impact map of {im.impact_velocity_m_per_s.size} points ({speeds.size} speeds "
        f"{speeds[0]:g}-{speeds[-1]:g} rpm x {gaps.size} backlashes {gaps[0]:g}-{gaps[-1]:g} mm); a groove cam "
        "cannot jump: the map is of the impacts where the follower crosses the backlash"
    )
    forces = im.max_impact_force_N
    force = f"; largest impact force {np.nanmax(forces):.4g} N" if np.isfinite(forces).any() else ""
    print(
        f"impact speed above max_impact_velocity {lim:g} m/s at {int(np.count_nonzero(over))} of {over.size} points; "
        f"largest {float(np.max(im.impact_velocity_m_per_s)):.4g} m/s{force}"
    )
    print(f"wrote {csv_path} and {png_path}")
    return 0


def tolerance_groove(args: argparse.Namespace, case: Case) -> int:
    """``camdyn tolerance`` of a groove cam: DIR/<case>-tolerance.csv and .png of the built cams' crossover impacts
    and a summary (``--json``: the document of docs/contracts.md); no worst samples as case files."""
    csv_path, png_path = _outputs(args, case, "tolerance", "tolerance study")
    with progress_bar(args.quiet) as progress:
        samples = 10000 if args.samples is None else args.samples
        result = impact_tolerance_study(case, samples, args.seed, progress=progress)
    write_new(csv_path, result.csv, True)
    save_impact_histogram_png(result, png_path)
    if args.json:
        print(json_text(result.json()))
        return 0
    con = console()
    lo, hi = result.confidence_interval
    con.print(
        f"{case.name}: {result.samples} built groove cams (seed {result.seed}) at {result.speed_rpm:g} rpm; a groove "
        "cam cannot jump: the study is of the impacts where the follower crosses the backlash"
    )
    con.print(
        f"probability of an impact speed above max_impact_velocity {result.max_impact_velocity:g} m/s: "
        f"{result.probability:.4g} (95% interval {lo:.4g} to {hi:.4g})"
    )
    t = table(
        ("quantity", "left"), ("P50", "right"), ("P95", "right"), ("P99", "right"), ("max", "right"), ("unit", "left")
    )
    for name, vals, unit in (
        ("impact speed", result.impact_velocity_m_per_s, "m/s"),
        ("impact force", result.max_impact_force_N, "N"),
    ):
        q = result.percentiles(vals)
        if q is not None:
            t.add_row(name, *(f"{q[k]:.4g}" for k in ("p50", "p95", "p99", "max")), unit)
    con.print(t)
    con.print(f"wrote {csv_path} and {png_path}")
    return 0
