"""``camdyn check CASE.toml``: the checks table, warnings, advice and the verdict (exit 0 pass, 1 fail)."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

from .._core.outputs import output_dir
from ..design.advice import corner_radius_advice
from ..design.checks import CheckKind, CheckReport, run_check
from ..model.case import build_case
from ._console import console, json_text, notes, progress_bar, table


def print_check(report: CheckReport) -> None:
    con = console()
    case = report.case
    con.print(f"[bold]{case.name}[/bold]  {case.spec.description}".rstrip())
    dyn, kin = report.dynamic, report.kinematic
    least = (
        f"the follower leaves the cam at {dyn.min_contact_force_deg:.1f} deg"
        if dyn.separations
        else f"least contact force {dyn.min_contact_force_N:.4g} N at {dyn.min_contact_force_deg:.1f} deg"
    )
    if report.closure is not None:  # form-closed: the force is signed, negative on the outer flank
        least = f"form-closed, signed contact force: {least}"
    kinematic = (
        f"kinematic: it leaves the cam at any speed, at {kin.jump_speed_at_deg:.1f} deg, where the cam's velocity steps"
        if kin.thrown_off
        else f"kinematic {kin.min_contact_force_N:.4g} N at {kin.min_contact_force_deg:.1f} deg"
    )
    con.print(f"speed {report.speed_rpm:g} rpm, {dyn.model} follower; {least} ({kinematic})")
    t = table(
        ("check", "left"), ("value", "right"), ("", "center"), ("limit", "right"), ("unit", "left"), ("result", "left")
    )
    for c in report.checks:
        result = "[green]pass[/green]" if c.ok else "[bold red]FAIL[/bold red]"
        limit = f"{c.limit:g}" + (" (no cusp)" if c.kind is CheckKind.CURVATURE and c.unit == "mm" else "")
        t.add_row(c.name, c.value_text(), c.sense, limit, c.unit, result)
    con.print(t)
    notes(con, "warning", "yellow", report.warnings)
    notes(con, "advice", "cyan", report.advice)
    colour = "green" if report.verdict == "pass" else "red"
    con.print(f"verdict: [bold {colour}]{report.verdict.upper()}[/bold {colour}]")


def run(args: argparse.Namespace) -> int:
    case = build_case(args.spec, source=Path(args.case))
    if args.report:
        output_dir(args.report, "report")
    report = run_check(case, args.speed)
    if report.verdict == "fail" and case.synthesis is not None and case.synthesis.sharp_corners:
        with progress_bar(args.quiet) as progress:
            tip = corner_radius_advice(case, report.speed_rpm, progress=progress)
        if tip:
            report = dataclasses.replace(report, advice=report.advice + (tip,))
    if args.json:
        print(json_text(report.json(arrays=args.arrays)))
    else:
        print_check(report)
    if args.report:
        from ..report import write_report  # matplotlib loads only with --report

        with progress_bar(args.quiet) as progress:
            written = write_report(case, args.report, check=report, progress=progress)
        print(f"wrote {written.pdf} and {len(written.pngs)} PNG pages", file=sys.stderr)
    return 0 if report.verdict == "pass" else 1
