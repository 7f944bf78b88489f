"""``camdyn tolerance CASE.toml``: the Monte Carlo tolerance study of the case's ``[tolerances]``: CSV of samples,
PNG, the worst samples as case files, and a summary (``--json``: the contract of docs/contracts.md)."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import TYPE_CHECKING

from .._core.distributed import initialize, is_writer
from .._core.errors import InputError
from .._core.outputs import output_dir, output_file, safe_stem, write_new
from ..design.tolerance import MAX_SAMPLES, tolerance_study, worst_case_docs
from ..export.toml import dumps_case
from ..model.case import build_case
from ..plot import save_tolerance_png
from ._console import console, json_text, progress_bar, table
from ._groove import tolerance_groove

if TYPE_CHECKING:
    from ..design.tolerance import ToleranceResult


def _paths(out: Path, stem: str, worst: int) -> dict:
    return {
        "csv": out / f"{stem}-tolerance.csv",
        "png": out / f"{stem}-tolerance.png",
        "worst": [out / f"{stem}-worst-{r}.toml" for r in range(1, worst + 1)],
    }


def json_doc(result: ToleranceResult, worst_files: list[Path], elapsed: float) -> dict:
    """The ``--json`` document (keys only ever added)."""
    return {
        "case": result.case,
        "samples": result.samples,
        "seed": result.seed,
        "probability_of_separation": result.probability,
        "confidence_interval": list(result.confidence_interval),
        "jump_speed_rpm": result.percentiles(result.jump_speed_rpm),
        "least_contact_force_N": result.percentiles(result.least_force),
        "sensitivities": result.sensitivities,
        "worst": [
            {
                "sample": i,
                "file": str(f),
                "least_contact_force_N": float(result.least_force[i]),
                "jump_speed_rpm": float(result.jump_speed_rpm[i]),
                "separated": bool(result.least_force[i] <= 0.0),
            }
            for i, f in zip(result.worst, worst_files, strict=True)
        ],
        "time_s": elapsed,
        "nominal_jump_speed_rpm": result.nominal_jump_speed_rpm,
        "speed_rpm": result.speed_rpm,
        "tolerances": result.tolerances,
        "confidence": 0.95,
        "devices": result.devices,
        "processes": result.processes,
    }


def run(args: argparse.Namespace) -> int:
    if not 1 <= args.samples <= MAX_SAMPLES:  # before any work or any folder is made
        raise InputError("--samples", f"must be from 1 to {MAX_SAMPLES}, got {args.samples}")
    initialize(args.coordinator, args.num_processes, args.process_id, auto=args.distributed)
    case = build_case(args.spec, source=Path(args.case))
    if case.follower is not None and case.follower.form_closed:  # a groove cam: its impacts, not its jumps
        return tolerance_groove(args, case) if is_writer() else 0  # not sharded: process 0 does the work
    writer = is_writer()
    stem = safe_stem(case.name)  # the case's name is data, not a path
    paths = _paths(Path(args.output), stem, 3)
    if writer:
        output_dir(args.output, "tolerance study")
        for p in (paths["csv"], paths["png"], *paths["worst"]):
            output_file(p, args.force, "tolerance study")
    t0 = time.perf_counter()
    with progress_bar(args.quiet) as progress:
        result = tolerance_study(case, args.samples, args.seed, progress=progress if writer else None)
    elapsed = time.perf_counter() - t0
    worst_files = paths["worst"][: len(result.worst)]
    if not writer:
        return 0
    write_new(paths["csv"], result.csv, True)
    save_tolerance_png(result, paths["png"])
    for (doc, header), path in zip(worst_case_docs(case, result), worst_files, strict=True):
        write_new(path, dumps_case(doc, header), True)
    if args.json:
        print(json_text(json_doc(result, worst_files, elapsed)))
        return 0
    _print(case, result, elapsed, paths, worst_files)
    return 0


def _print(case, result, elapsed, paths, worst_files) -> None:
    con = console()
    lo, hi = result.confidence_interval
    con.print(
        f"{case.name}: {result.samples} built cams (seed {result.seed}) at {result.speed_rpm:g} rpm, {elapsed:.1f} s "
        f"on {result.devices} device(s), {result.processes} process(es)"
    )
    con.print(
        f"probability of separation {result.probability:.4g} (95% interval {lo:.4g} to {hi:.4g}); nominal jump speed "
        f"{result.nominal_jump_speed_rpm:.1f} rpm"
    )
    t = table(("quantity", "left"), ("P1", "right"), ("P5", "right"), ("P50", "right"), ("unit", "left"))
    for name, vals, unit in (
        ("jump speed", result.jump_speed_rpm, "rpm"),
        ("least contact force", result.least_force, "N"),
    ):
        q = result.percentiles(vals)
        t.add_row(name, *(f"{q[k]:.4g}" for k in ("p1", "p5", "p50")), unit)
    con.print(t)
    t = table(
        ("tolerance", "left"),
        ("given", "right"),
        ("dist", "left"),
        ("margin/sigma", "right"),
        ("lin share", "right"),
        ("MC share", "right"),
    )
    for key, s in result.sensitivities.items():
        tol = result.tolerances[key]
        pct = lambda v: "-" if not math.isfinite(v) else f"{v:.0%}"  # noqa: E731
        t.add_row(
            key,
            f"{tol['tolerance']:.4g} {tol['unit']}",
            tol["distribution"],
            f"{s['gradient_sigma']:+.4f}",
            pct(s["share_linear"]),
            pct(s["share_monte_carlo"]),
        )
    for col in t.columns:  # never an ellipsis in a key's name
        col.no_wrap = True
    if result.sensitivities:
        con.print(t)
    con.print(f"wrote {paths['csv']}, {paths['png']} and the worst samples {', '.join(str(p) for p in worst_files)}")
