"""The ``camdyn`` command line: check, table (and the commands the other modules add).

Exit codes: 0 every check passes, 1 a check fails, 2 invalid input or a numerical failure (one line on
stderr naming the file, the key or angle, and what is wrong; ``--debug`` shows the traceback).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from contextlib import contextmanager
from pathlib import Path

# Before equinox loads: its runtime checks otherwise embed host callbacks, which keep JAX from caching the
# compiled diffrax solves on disk (camdyn checks every solver result itself, so NaN-on-error loses nothing).
os.environ.setdefault("EQX_ON_ERROR", "nan")


def _enable_compilation_cache() -> None:
    """Persist compiled XLA programs and traced camdyn programs between runs (the user's second ``check`` skips
    most of JAX's tracing and compilation)."""
    if os.environ.get("CAMDYN_NO_CACHE"):
        return
    import jax

    root = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "camdyn" / "jax"
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError:
        return
    jax.config.update("jax_compilation_cache_dir", str(root))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.1)
    from . import programs

    programs.enable(root.parent / "programs")


def _refuse_overwrite(path: Path, force: bool) -> None:
    from .errors import InputError

    if path.exists() and not force:
        raise InputError(str(path), "exists; pass --force to overwrite it")


@contextmanager
def _phase_progress():
    """A rich progress bar on stderr (silent when stderr is not a terminal), one task per phase; yields the
    ``progress(phase, done, total)`` callback that camdyn's long computations take."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    columns = (SpinnerColumn(), TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=Console(stderr=True), disable=not sys.stderr.isatty()) as bar:
        tasks: dict = {}

        def progress(phase, done, total):
            if phase not in tasks:
                tasks[phase] = bar.add_task(phase, total=total)
            bar.update(tasks[phase], completed=done, total=total)

        yield progress


def _write_new(path: Path, text: str, force: bool) -> None:
    _refuse_overwrite(path, force)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


# -------------------------------------------------------------------------------------- check
def _print_check(report) -> None:
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    console = Console(highlight=False, soft_wrap=True)
    case = report.case
    console.print(f"[bold]{case.name}[/bold]  {case.spec.description}".rstrip())
    dyn, kin = report.dynamic, report.kinematic
    console.print(
        f"speed {report.speed_rpm:g} rpm, {dyn['model']} follower; least contact force {dyn['min_contact_force_N']:.4g} N "
        f"at {dyn['min_contact_force_deg']:.1f} deg (kinematic {kin['min_contact_force_N']:.4g} N at {kin['min_contact_force_deg']:.1f} deg)"
    )
    table = Table(show_edge=False, pad_edge=False, box=None, header_style="bold")
    for col, just in (("check", "left"), ("value", "right"), ("", "center"), ("limit", "right"), ("unit", "left"), ("result", "left")):
        table.add_column(col, justify=just)
    for c in report.checks:
        value = "unbounded" if c.value is None else f"{c.value:.4g}"
        result = "[green]pass[/green]" if c.ok else "[bold red]FAIL[/bold red]"
        table.add_row(c.name, value, c.sense, f"{c.limit:g}", c.unit, result)
    console.print(table)
    for w in report.warnings:
        console.print(f"[yellow]warning:[/yellow] {escape(w)}")
    for a in report.advice:
        console.print(f"[cyan]advice:[/cyan] {escape(a)}")
    colour = "green" if report.verdict == "pass" else "red"
    console.print(f"verdict: [bold {colour}]{report.verdict.upper()}[/bold {colour}]")


def cmd_check(args) -> int:
    from .case import load_case
    from .checks import run_check

    case = load_case(args.case)
    if args.report:
        from .report import output_dir

        output_dir(args.report)
    report = run_check(case, args.speed)
    if report.verdict == "fail" and case.synthesis is not None and case.synthesis.sharp_corners:
        import dataclasses

        from .checks import corner_radius_advice
        from .report import progress

        with progress() as task:
            advance, done = task(6)
            tip = corner_radius_advice(case, report.speed_rpm, advance=advance)
            done("corner radius found")
        if tip:
            report = dataclasses.replace(report, advice=report.advice + (tip,))
    if args.json:
        print(json.dumps(report.json(), indent=2))
    else:
        _print_check(report)
    if args.report:
        from .report import progress, write_report

        with progress() as task:
            advance, done = task(5)
            written = write_report(case, args.report, check=report, advance=advance)
            done(f"{case.name}: {len(written.pngs)} pages")
        print(f"wrote {written.pdf} and {len(written.pngs)} PNG pages", file=sys.stderr)
    return 0 if report.verdict == "pass" else 1


# ------------------------------------------------------------------------------------- report
def cmd_report(args) -> int:
    from .report import report_cases

    for written in report_cases(args.cases, args.output, speed_rpm=args.speed):
        print(f"wrote {written.pdf} ({len(written.pngs)} pages, {written.verdict}) and {', '.join(p.name for p in written.pngs)}")
    return 0


# -------------------------------------------------------------------------------------- table
def motion_table(case, step_deg: float = 1.0) -> dict:
    """Columns of ``camdyn table`` (one row per angle), kinematic, at the case speed."""
    import jax.numpy as jnp
    import numpy as np

    from . import dynamics as dyn
    from .motion import evaluate

    theta_deg = np.arange(0.0, 360.0 - 1e-9, step_deg)
    theta = jnp.deg2rad(theta_deg)
    vals = np.asarray(evaluate(case.motion, theta))
    force = np.asarray(dyn.kinematic_force(case.motion, case.model, case.speed_rpm * dyn.RPM, theta))
    cols = {"theta_deg": theta_deg}
    if case.oscillating:
        cols |= {"phi_deg": np.degrees(vals[0]), "phi1_per_rad": vals[1], "phi2_per_rad2": vals[2], "phi3_per_rad3": vals[3]}
    else:
        cols |= {"s_mm": vals[0], "v_mm_per_rad": vals[1], "a_mm_per_rad2": vals[2], "j_mm_per_rad3": vals[3]}
    if case.oscillating:
        from .geometry import lever_arm_mm

        force = force / (np.asarray(lever_arm_mm(case.motion, case.follower, np.asarray(theta))) / 1000.0)
    cols["contact_force_N"] = force
    if case.follower is not None:
        from .geometry import analyze

        cols |= analyze(case.motion, case.follower).table(theta_deg)
    return cols


def cmd_table(args) -> int:
    import io

    import numpy as np

    from .case import load_case
    from .errors import InputError

    if not 0 < args.step <= 360:
        raise InputError("--step", f"must be in (0, 360] deg (got {args.step:g})")
    cols = motion_table(load_case(args.case), args.step)
    buf = io.StringIO()
    buf.write(",".join(cols) + "\n")
    np.savetxt(buf, np.column_stack(list(cols.values())), delimiter=",", fmt="%.10g")
    if args.output:
        _write_new(Path(args.output), buf.getvalue(), args.force)
    else:
        sys.stdout.write(buf.getvalue())
    return 0


# ------------------------------------------------------------------------------------ profile
def cmd_profile(args) -> int:
    from .case import load_case
    from .export import write_profile
    from .geometry import analyze

    case = load_case(args.case)
    if case.follower is None:
        from .errors import InputError

        raise InputError("follower", "the case has no cam follower geometry")
    geo = analyze(case.motion, case.follower)
    info = write_profile(geo.contour_fn(), Path(args.output), tolerance=args.tolerance, force=args.force)
    print(
        f"wrote {args.output}: {info['points']} points within {info['tolerance_mm']:g} mm, "
        f"x {info['x_min_mm']:.3f}..{info['x_max_mm']:.3f} mm, y {info['y_min_mm']:.3f}..{info['y_max_mm']:.3f} mm"
    )
    return 0


# --------------------------------------------------------------------------------------- size
def _print_size(sz) -> None:
    import numpy as np
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    from .sizing import TIE_BREAK

    console = Console(highlight=False, soft_wrap=True)
    u = sz.units
    console.print(f"[bold]{sz.case_name}[/bold]  spring sizing")
    console.print(
        f"contact force >= {sz.min_contact_force:g} N at every angle and every speed up to {sz.top_speed_rpm:.4g} rpm "
        f"({sz.margin:g} x {sz.speed_rpm:g} rpm); {sz.model} follower; least peak spring force"
    )
    jump = lambda w: "none" if w == float("inf") else f"{w:.1f}"  # noqa: E731
    fmt = lambda x, scale: f"{0.0 if abs(x) < 1e-9 * max(1.0, abs(scale)) else x:.4g}"  # noqa: E731
    designs = [("chosen", sz.chosen)] + ([("kinematic LP", sz.kinematic)] if sz.model == "compliant" else [])
    designs += [("current", sz.current), ("current rate", sz.at_current_rate)]
    table = Table(show_edge=False, pad_edge=False, box=None, header_style="bold")
    table.add_column("")
    for name, _ in designs:
        table.add_column(name, justify="right", no_wrap=True)
    ds = [d for _, d in designs]
    spring = "torque" if sz.oscillating else "force"
    table.add_row(f"rate ({u['rate']})", *(f"{d.rate:.4g}" for d in ds))
    table.add_row(f"preload ({u['preload']})", *(fmt(d.preload, d.peak_spring) for d in ds))
    table.add_row(f"peak spring {spring} ({u['spring']})", *(f"{d.peak_spring:.4g}" for d in ds))
    table.add_row("peak contact force (N)", *(f"{d.peak_contact:.4g}" for d in ds))
    table.add_row("least contact force (N)", *(fmt(d.least_force, d.peak_contact) for d in ds))
    table.add_row("kinematic jump speed (rpm)", *(jump(d.kinematic_jump_rpm) for d in ds))
    table.add_row("dynamic jump speed (rpm)", *(jump(d.dynamic_jump_rpm) for d in ds))
    holds = (d.least_force >= sz.min_contact_force - 1e-6 * max(1.0, abs(d.peak_contact)) for d in ds)
    table.add_row(f"holds up to {sz.top_speed_rpm:.4g} rpm", *("[green]yes[/green]" if h else "[bold red]no[/bold red]" for h in holds))
    console.print(table)
    console.print("[dim]contact forces: over every angle and every speed up to the top speed; current rate: the least preload that holds with the case's own rate[/dim]")
    if sz.model == "compliant":
        c, k = sz.chosen, sz.kinematic
        console.print(
            f"dynamic correction (compliant train): rate {c.rate - k.rate:+.4g} {u['rate']}, preload {c.preload - k.preload:+.4g} {u['preload']}, "
            f"peak spring {c.peak_spring - k.peak_spring:+.4g} {u['spring']}; dynamic jump speed {jump(k.dynamic_jump_rpm)} -> {jump(c.dynamic_jump_rpm)} rpm "
            f"(the kinematic answer's least dynamic contact force is {k.least_force:.4g} N)"
        )
    where = ", ".join(f"{a:.1f} deg" if a == b else f"{a:.1f}-{b:.1f} deg" for a, b, _ in sz.binding[:4])
    line = f"binding (kinematic): {where}" if where else "binding (kinematic): -"
    if sz.dynamic_binding is not None:
        line += f"; dynamic: {sz.dynamic_binding[0]:.1f} deg at {sz.dynamic_binding[1]:.4g} rpm"
    console.print(line)
    region = Table(show_edge=False, pad_edge=False, box=None, header_style="bold", title="feasible region: preload >= least preload(rate)", title_justify="left")
    for col in (f"rate ({u['rate']})", f"least preload ({u['preload']}): kinematic", "dynamic", f"peak spring ({u['spring']})"):
        region.add_column(col, justify="right", no_wrap=True)
    n = len(sz.region_rate)
    for i in np.unique(np.linspace(0, n - 1, 6).round().astype(int)):
        dyn_pre = sz.region_preload_dynamic[i] if sz.region_preload_dynamic is not None else sz.region_preload_kinematic[i]
        peak = sz.region_rate[i] * sz.s_max + dyn_pre
        region.add_row(f"{sz.region_rate[i]:.4g}", fmt(sz.region_preload_kinematic[i], peak), "-" if sz.region_preload_dynamic is None else fmt(dyn_pre, peak), f"{peak:.4g}")
    console.print(region)
    console.print(f"[dim]tie-break:[/dim] {TIE_BREAK}")
    console.print(f"[dim]damping:[/dim] {sz.damping}")
    for w in sz.warnings:
        console.print(f"[yellow]warning:[/yellow] {escape(w)}")
    c = sz.chosen
    console.print(f"size: [bold]rate {c.rate:.4g} {u['rate']}, preload {c.preload:.4g} {u['preload']}[/bold] (peak spring {c.peak_spring:.4g} {u['spring']})")


def cmd_size(args) -> int:
    from .case import load_case
    from .sizing import size_spring

    sz = size_spring(load_case(args.case), args.max_speed, args.margin, args.min_rate)
    if args.json:
        print(json.dumps(sz.json(), indent=2))
    else:
        _print_size(sz)
    return 0


# -------------------------------------------------------------------------------------- sweep
def _parse_grid(flag: str, text: str):
    """``A:B:N`` -> N equally spaced values from A to B (positive, A <= B, N >= 1); InputError naming the flag."""
    import math

    import numpy as np

    from .errors import InputError

    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(flag, f"expected A:B:N (from A to B in N values, e.g. 100:700:61), got {text!r}")
    try:
        a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise InputError(flag, f"expected A:B:N with numbers A and B and a whole number N, got {text!r}") from None
    if not (math.isfinite(a) and math.isfinite(b) and a > 0 and b > 0):
        raise InputError(flag, f"A and B must be positive numbers, got {text!r}")
    if a > b:
        raise InputError(flag, f"A must not exceed B, got {text!r}")
    if n < 1 or (n == 1 and a != b):
        raise InputError(flag, f"N must be at least 1 (and N = 1 needs A = B), got {text!r}")
    return np.linspace(a, b, n)


def cmd_sweep(args) -> int:
    import time

    import numpy as np

    from .case import load_case
    from .sweep import jump_map, save_png

    speeds = _parse_grid("--speeds", args.speeds)
    rates = _parse_grid("--spring-rates", args.spring_rates) if args.spring_rates is not None else None
    case = load_case(args.case)
    out = Path(args.output)
    csv_path, png_path = out / f"{case.name}-sweep.csv", out / f"{case.name}-sweep.png"
    for path in (csv_path, png_path):
        _refuse_overwrite(path, args.force)
    t0 = time.perf_counter()
    with _phase_progress() as progress:
        jm = jump_map(case, speeds, rates, progress=progress)
    elapsed = time.perf_counter() - t0
    _write_new(csv_path, jm.csv, True)
    save_png(jm, png_path)
    ku = jm.spring_rate_unit
    n_sep = int(np.count_nonzero(jm.separated))
    print(
        f"{case.name}: jump map of {jm.separated.size} points ({speeds.size} speeds {speeds[0]:g}-{speeds[-1]:g} rpm x "
        f"{jm.spring_rates.size} spring rates {jm.spring_rates[0]:g}-{jm.spring_rates[-1]:g} {ku}), {jm.model} follower, "
        f"{elapsed:.1f} s on {jm.devices} device(s)"
    )
    print(f"preload kept at the case's {jm.preload:g} {jm.preload_unit} while the spring rate varies" + ("; spring rates are torsion rates, N*m/rad (column spring_rate_N_per_mm)" if jm.oscillating else ""))
    gap = np.nanmax(jm.max_gap) if n_sep else 0.0
    print(f"separated at {n_sep} of {jm.separated.size} points" + (f" (largest gap {gap:.4g} mm)" if n_sep else "") + f"; least contact force on the map {float(np.min(jm.min_force)):.4g} N")
    for note in jm.notes:
        print(f"warning: {note}", file=sys.stderr)
    print(f"wrote {csv_path} and {png_path}")
    return 0


# --------------------------------------------------------------------------------- synthesize
def _print_synthesize(res, output: Path, elapsed: float) -> None:
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    console = Console(highlight=False, soft_wrap=True)
    s, m = res.summary, res.mechanism
    fb = s.get("fourbar")
    console.print(f"[bold]{res.case.name}[/bold]  CCM for the {res.case.spec.path['type']} path, dimensions by differential evolution (seed {s['seed']})")
    table = Table(show_edge=False, pad_edge=False, box=None, header_style="bold")
    table.add_column("")
    table.add_column("CCM", justify="right", no_wrap=True)
    table.add_column("best four-bar" if fb else "", justify="right", no_wrap=True)
    f = lambda x: f"{x:.4g}"  # noqa: E731
    conv = lambda ok, n: f"{'yes' if ok else 'no'} ({n} gen)"  # noqa: E731
    table.add_row("crank (mm)", f(s["crank_mm"]), f(fb["crank"]) if fb else "")
    table.add_row("coupler (mm)", f(s["coupler_mm"]), f(fb["coupler"]) if fb else "")
    table.add_row("link C-E / rocker (mm)", f(m["link"]), f(fb["rocker"]) if fb else "")
    table.add_row("stroke (mm)", f(s["stroke_mm"]), "-" if fb else "")
    table.add_row("least transmission angle (deg)", f"{min(s['min_transmission_angle_deg'], s['min_slider_angle_deg']):.1f}", f"{fb['min_transmission_angle_deg']:.1f}" if fb else "")
    table.add_row("base radius (mm)", f"{s['base_radius_mm']:g}", "-" if fb else "")
    err = lambda x: f"{x:.2g}" if x < 1e-3 else f"{x:.4g}"  # noqa: E731
    table.add_row("max path error (mm)", err(s["max_path_error_mm"]), err(s["fourbar_path_error_mm"]) if fb else "")
    table.add_row("optimizer converged", conv(s["optimizer_converged"], s["generations"]), conv(fb["optimizer_converged"], fb["generations"]) if fb else "")
    console.print(table)
    console.print(f"[dim]cam centre ({m['cam_center'][0]:g}, {m['cam_center'][1]:g}) mm, slider line through ({m['slider_point'][0]:g}, {m['slider_point'][1]:g}) mm at {m['slider_angle']:g} deg, crank turns {s['rotation']}; objective {s['objective']}[/dim]")
    for note in res.notes:
        console.print(f"[cyan]note:[/cyan] {escape(note)}")
    for w in s["warnings"]:
        console.print(f"[yellow]warning:[/yellow] {escape(w)}")
    if not res.constraints_met:
        console.print(f"[bold red]constraints not met:[/bold red] {escape('; '.join(s['violations']))} (try a larger --maxiter or another --seed)")
    console.print(f"wrote {output} in {elapsed:.1f} s; next: camdyn check {output}")


def cmd_synthesize(args) -> int:
    import time

    from .case import read_toml
    from .errors import InputError
    from .synthesize import synthesize_case

    out = Path(args.output)
    _refuse_overwrite(out, args.force)  # before minutes of work, not after
    if out.resolve() == Path(args.case).resolve():
        raise InputError(str(out), "is the input path file; write the case to another file")
    raw = read_toml(args.case)
    t0 = time.perf_counter()
    with _phase_progress() as progress:
        res = synthesize_case(raw, source=Path(args.case), name=out.stem, seed=args.seed, maxiter=args.maxiter, progress=progress)
    elapsed = time.perf_counter() - t0
    _write_new(out, res.text, args.force)
    if args.json:
        doc = {"output": str(out), "constraints_met": res.constraints_met, "time_s": elapsed, "mechanism": res.mechanism, "dynamics": res.dynamics, "summary": res.summary, "notes": res.notes}
        print(json.dumps(doc, indent=2, default=lambda o: o.item() if hasattr(o, "item") else str(o)))
    else:
        _print_synthesize(res, out, elapsed)
    return 0 if res.constraints_met else 1


# ---------------------------------------------------------------------------------- plumbing
def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="camdyn", description="Cam mechanism design and follower dynamics: prove the follower never leaves the cam.")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an error")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("check", help="stability margins and a verdict (exit 0 pass, 1 fail, 2 error)")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--speed", type=float, metavar="RPM", help="cam speed, rpm (default: the case's)")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    p.add_argument("--report", metavar="DIR", help="also write the design-review report (DIR/<case>.pdf and a PNG per page)")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("report", help="design-review report per case: DIR/<case>.pdf and DIR/<case>-<n>-<page>.png")
    p.add_argument("cases", nargs="+", metavar="CASE", help="case files (TOML)")
    p.add_argument("-o", "--output", default="reports", metavar="DIR", help="output folder (default: reports); camdyn's own report files there are overwritten")
    p.add_argument("--speed", type=float, metavar="RPM", help="cam speed, rpm (default: each case's)")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("table", help="CSV of the follower motion and kinematic contact force per angle")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--step", type=float, default=1.0, metavar="DEG", help="angle step, deg (default 1)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of standard output")
    p.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    p.set_defaults(func=cmd_table)

    p = sub.add_parser("profile", help="the cam contour for manufacturing: DXF, CSV or SVG by the file suffix")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="cam.dxf, cam.csv or cam.svg")
    p.add_argument("--tolerance", type=float, default=0.01, metavar="MM", help="chord tolerance, mm (default 0.01)")
    p.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    p.set_defaults(func=cmd_profile)

    p = sub.add_parser("size", help="return spring (rate, preload) with the least peak force that holds up to margin x speed")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--max-speed", type=float, metavar="RPM", help="maximum cam speed, rpm (default: the case's speed)")
    p.add_argument("--margin", type=float, metavar="X", help="hold up to X times the maximum speed (default: the case's speed_margin)")
    p.add_argument("--min-rate", type=float, default=0.0, metavar="K", help="least spring rate, N/mm (N*m/rad oscillating; default 0)")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    p.set_defaults(func=cmd_size)

    p = sub.add_parser("sweep", help="jump map over speeds x spring rates: DIR/<case>-sweep.csv and DIR/<case>-sweep.png")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--speeds", required=True, metavar="A:B:N", help="cam speeds, rpm: N values from A to B")
    p.add_argument("--spring-rates", metavar="A:B:N", help="spring rates, N/mm (N*m/rad oscillating): N values from A to B (default: the case's); the preload stays the case's")
    p.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: the current one)")
    p.add_argument("--force", action="store_true", help="overwrite the files if they exist")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("synthesize", help="choose a CCM's dimensions for a path (differential evolution) and write a complete case file")
    p.add_argument("case", metavar="PATH.toml", help="path file: [path], [dynamics], optional name, description, [limits], [synthesis]")
    p.add_argument("-o", "--output", required=True, metavar="CASE.toml", help="the case file to write")
    p.add_argument("--force", action="store_true", help="overwrite CASE.toml if it exists")
    p.add_argument("--seed", type=int, metavar="N", help="optimizer seed (default: [synthesis] seed, else 0)")
    p.add_argument("--maxiter", type=int, metavar="N", help="most optimizer generations (default: [synthesis] maxiter, else 200)")
    p.add_argument("--json", action="store_true", help="print one JSON document (the mechanism, the summary and the four-bar comparison)")
    p.set_defaults(func=cmd_synthesize)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "speed", None) is not None and not (args.speed > 0 and args.speed < float("inf")):
        print(f"camdyn: --speed: must be a positive number of rpm (got {args.speed:g})", file=sys.stderr)
        return 2
    _enable_compilation_cache()
    from .errors import CamdynError

    source = getattr(args, "case", "") or ""
    try:
        return args.func(args)
    except CamdynError as err:
        if args.debug:
            raise
        print(f"camdyn: {source + ': ' if source else ''}{err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except Exception as err:  # a bug: still one line, the traceback on request
        if args.debug:
            raise
        print(f"camdyn: {source + ': ' if source else ''}internal error: {type(err).__name__}: {err} (run with --debug for the traceback)", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
