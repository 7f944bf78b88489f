"""``camdyn tolerance CASE.toml``: the Monte Carlo tolerance study of the case's ``[tolerances]``: CSV of samples,
PNG, the worst samples as case files, and a summary (``--json``: the contract of docs/contracts.md)."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from .._core.distributed import initialize, is_writer
from .._core.outputs import output_dir, output_file, safe_stem, write_new
from .._core.results import finite_or_none
from ..design.tolerance import (
    DEFAULT_VALVETRAIN_SAMPLES,
    case_tolerances,
    impact_tolerance_study,
    tolerance_study,
    valvetrain_tolerance_study,
    worst_case_docs,
    worst_valvetrain_docs,
)
from ..export.toml import dumps_case
from ..model.case import Case, build_case
from ..plot import save_impact_histogram_png, save_tolerance_png, save_valve_tolerance_png
from ..schema import moved_data_files
from ._console import console, json_text, progress_bar, table
from ._groove import groove_outputs

if TYPE_CHECKING:
    from ..design.tolerance import ToleranceResult, ValveToleranceResult

R = TypeVar("R", "ToleranceResult", "ValveToleranceResult")


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
        "sensitivities": {  # null: a share or gradient not computed (no spread to share, no jump speed)
            k: {name: finite_or_none(v) for name, v in s.items()} for k, s in result.sensitivities.items()
        },
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
    initialize(args.coordinator, args.num_processes, args.process_id, auto=args.distributed)
    case = build_case(args.spec, source=Path(args.case))
    case_tolerances(case)  # a case that gives none is refused before anything is written
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
    if case.valvetrain is not None:  # the two-mass model per sample: float, bounce, seating velocity
        samples = DEFAULT_VALVETRAIN_SAMPLES if args.samples is None else args.samples
        with progress_bar(args.quiet) as progress:
            vt = valvetrain_tolerance_study(case, samples, args.seed, progress=progress if writer else None)
        if writer:
            outputs = (save_valve_tolerance_png, worst_valvetrain_docs, valvetrain_json_doc, _print_valvetrain)
            _write(args, case, vt, time.perf_counter() - t0, paths, *outputs)
        return 0
    samples = 10000 if args.samples is None else args.samples
    with progress_bar(args.quiet) as progress:
        result = tolerance_study(case, samples, args.seed, progress=progress if writer else None)
    if writer:
        outputs = (save_tolerance_png, worst_case_docs, json_doc, _print)
        _write(args, case, result, time.perf_counter() - t0, paths, *outputs)
    return 0


def _write(args, case, result: R, elapsed: float, paths, save, docs, as_json, show) -> None:
    """Write a study's CSV, PNG and worst samples, then its summary or ``--json`` (``save``, ``docs``, ``as_json``,
    ``show``: the study's own writers of ``result``)."""
    worst_files = paths["worst"][: len(result.worst)]
    write_new(paths["csv"], result.csv, True)
    save(result, paths["png"])
    for (doc, header), path in zip(docs(case, result), worst_files, strict=True):
        if case.source is not None:  # the data files it names, as the written case finds them
            doc = moved_data_files(doc, case.source.parent, path.parent)
        write_new(path, dumps_case(doc, header), True)
    if args.json:
        print(json_text(as_json(result, worst_files, elapsed)))
    else:
        show(case, result, elapsed, paths, worst_files)


def _print(case, result, elapsed, paths, worst_files) -> None:
    con = console()
    lo, hi = result.confidence_interval
    con.print(
        f"{case.name}: {result.samples} built cams (seed {result.seed}) at {result.speed_rpm:g} rpm, {elapsed:.1f} s "
        f"on {result.devices} device(s), {result.processes} process(es)"
    )
    con.print(
        f"probability of separation {result.probability:.4g} ({result.confidence:.0%} interval {lo:.4g} to {hi:.4g}); "
        f"nominal jump speed {result.nominal_jump_speed_rpm:.1f} rpm"
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


def valvetrain_json_doc(result: ValveToleranceResult, worst_files: list[Path], elapsed: float) -> dict:
    """A valvetrain's ``--json`` document: the single follower's keys where they mean the same (separation is
    float, the jump speed the float speed), and ``valvetrain``."""
    p_float, ci = result.probability(result.floated)
    return {
        "case": result.case,
        "samples": result.samples,
        "seed": result.seed,
        "probability_of_separation": p_float,
        "confidence_interval": list(ci),
        "jump_speed_rpm": result.low(result.float_speed_rpm),
        "least_contact_force_N": result.low(result.least_force),
        "sensitivities": {},
        "worst": [
            {
                "sample": i,
                "file": str(f),
                "least_contact_force_N": float(result.least_force[i]),
                "jump_speed_rpm": float(result.float_speed_rpm[i]),
                "bounce_speed_rpm": float(result.bounce_speed_rpm[i]),
                "separated": bool(result.floated[i]),
            }
            for i, f in zip(result.worst, worst_files, strict=True)
        ],
        "time_s": elapsed,
        "nominal_jump_speed_rpm": result.nominal_float_speed_rpm,
        "speed_rpm": result.speed_rpm,
        "tolerances": result.tolerances,
        "confidence": 0.95,
        "devices": 1,
        "processes": 1,
        "valvetrain": result.json(),
    }


def _print_valvetrain(case, result: ValveToleranceResult, elapsed, paths, worst_files) -> None:
    con = console()
    con.print(
        f"{case.name}: {result.samples} built valvetrains (seed {result.seed}) at {result.speed_rpm:g} rpm, two-mass "
        f"model, {elapsed:.1f} s"
    )
    for what, hit, nominal in (
        ("float", result.floated, result.nominal_float_speed_rpm),
        ("bounce", result.bounced, result.nominal_bounce_speed_rpm),
    ):
        p, (lo, hi) = result.probability(hit)
        con.print(
            f"probability of {what} at the sample's speed {p:.4g} ({result.confidence:.0%} interval {lo:.4g} "
            f"to {hi:.4g}); nominal {what} speed {nominal:.1f} rpm"
        )
    t = table(("quantity", "left"), ("P1", "right"), ("P5", "right"), ("P50", "right"), ("unit", "left"))
    for name, speeds in (("float speed", result.float_speed_rpm), ("bounce speed", result.bounce_speed_rpm)):
        q = result.low(speeds)
        t.add_row(name, *(f"{q[k]:.5g}" for k in ("p1", "p5", "p50")), "rpm")
    con.print(t)
    t = table(("quantity", "left"), ("P50", "right"), ("P95", "right"), ("P99", "right"), ("unit", "left"))
    for name, values, unit in (
        ("seating velocity", result.seating_velocity, "m/s"),
        ("bounce height", result.bounce_height, "mm"),
    ):
        q = result.high(values)
        t.add_row(name, *(f"{q[k]:.4g}" for k in ("p50", "p95", "p99")), unit)
    con.print(t)
    shares = ", ".join(f"{k} {v:.0%}" for k, v in result.shares.items() if math.isfinite(v))
    if shares:
        con.print(f"share of the float/bounce margin's variance (linear fit over the samples): {shares}")
    for note in result.notes:
        con.print(f"note: {note}")
    con.print(f"wrote {paths['csv']}, {paths['png']} and the worst samples {', '.join(str(p) for p in worst_files)}")


def tolerance_groove(args: argparse.Namespace, case: Case) -> int:
    """``camdyn tolerance`` of a form-closed cam: DIR/<case>-tolerance.csv and .png of the built cams' crossover
    impacts (conjugate cams under a preload: their least cam force) and a summary (``--json``: the document of
    docs/contracts.md); no worst samples as case files."""
    csv_path, png_path = groove_outputs(args, case, "tolerance", "tolerance study")
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
    q = result.least_cam_force_low
    if q is not None:  # conjugate cams under a preload: no impacts, whether a roller unloads
        lo, hi = result.unloaded_interval
        con.print(
            f"{case.name}: {result.samples} built conjugate cams (seed {result.seed}) at {result.speed_rpm:g} rpm "
            f"under the preload {result.preload:g} {'N*m' if case.kind.rotary else 'N'}; they cannot jump: the study "
            "is of the least force on either cam"
        )
        con.print(
            f"probability that a roller unloads: {result.unloaded_probability:.4g} ({result.confidence:.0%} interval "
            f"{lo:.4g} to {hi:.4g}); least cam force P1 {q['p1']:.4g} N, P50 {q['p50']:.4g} N, least {q['min']:.4g} N"
        )
        con.print(f"wrote {csv_path} and {png_path}")
        return 0
    con.print(
        f"{case.name}: {result.samples} built {result.closure} cams (seed {result.seed}) at {result.speed_rpm:g} rpm; "
        f"a {result.closure} cam cannot jump: the study is of the impacts where the follower crosses the backlash"
    )
    con.print(
        f"probability of an impact speed above max_impact_velocity {result.max_impact_velocity:g} m/s: "
        f"{result.probability:.4g} ({result.confidence:.0%} interval {lo:.4g} to {hi:.4g})"
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
