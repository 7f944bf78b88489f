"""The ``camdyn`` command line: check, table (and the commands the other modules add).

Exit codes: 0 every check passes, 1 a check fails, 2 invalid input or a numerical failure (one line on
stderr naming the file, the key or angle, and what is wrong; ``--debug`` shows the traceback).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

# Before equinox loads: its runtime checks otherwise embed host callbacks, which keep JAX from caching the
# compiled diffrax solves on disk (camdyn checks every solver result itself, so NaN-on-error loses nothing).
os.environ.setdefault("EQX_ON_ERROR", "nan")


def _enable_compilation_cache() -> None:
    """Persist compiled XLA programs between runs (the user's second ``check`` skips most compile time)."""
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


def _write_new(path: Path, text: str, force: bool) -> None:
    from .errors import InputError

    if path.exists() and not force:
        raise InputError(str(path), "exists; pass --force to overwrite it")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


# -------------------------------------------------------------------------------------- check
def _print_check(report) -> None:
    from rich.console import Console
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
        console.print(f"[yellow]warning:[/yellow] {w}")
    for a in report.advice:
        console.print(f"[cyan]advice:[/cyan] {a}")
    colour = "green" if report.verdict == "pass" else "red"
    console.print(f"verdict: [bold {colour}]{report.verdict.upper()}[/bold {colour}]")


def cmd_check(args) -> int:
    from .case import load_case
    from .checks import run_check

    report = run_check(load_case(args.case), args.speed)
    if args.json:
        print(json.dumps(report.json(), indent=2))
    else:
        _print_check(report)
    return 0 if report.verdict == "pass" else 1


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


# ---------------------------------------------------------------------------------- plumbing
def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="camdyn", description="Cam mechanism design and follower dynamics: prove the follower never leaves the cam.")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an error")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("check", help="stability margins and a verdict (exit 0 pass, 1 fail, 2 error)")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--speed", type=float, metavar="RPM", help="cam speed, rpm (default: the case's)")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    p.set_defaults(func=cmd_check)

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
