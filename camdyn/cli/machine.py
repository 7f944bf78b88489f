"""``camdyn machine MACHINE.toml [-o DIR] [--json] [--report]``: every cam checked at the machine speed, the summed
shaft torque and the flywheel, the clearances; ``DIR/<machine>-machine.csv`` (exit 0 pass, 1 a cam or a gap fails)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .._core.outputs import output_file, write_new
from ..design.machine import MachineResult, run_machine
from ..schema.machine import machine_stem
from ._console import console, json_text, notes, progress_bar, table


def print_machine(result: MachineResult) -> None:
    con = console()
    con.print(f"[bold]{result.name}[/bold]  {result.description}".rstrip())
    con.print(f"speed {result.speed_rpm:g} rpm, {len(result.cams)} cams on the main shaft")
    t = table(
        ("cam", "left"),
        ("phase", "right"),
        ("least force", "right"),
        ("margin", "right"),
        ("peak torque", "right"),
        ("at", "right"),
        ("result", "left"),
    )
    for cam in result.cams:
        result_text = "[green]pass[/green]" if cam.verdict == "pass" else "[bold red]FAIL[/bold red]"
        t.add_row(
            cam.name,
            f"{cam.phase_deg:g} deg",
            f"{cam.check.dynamic.min_contact_force_N:.4g} N",
            f"n/a: {cam.check.closure.response.type}"
            if cam.check.closure is not None
            else "unbounded"
            if cam.speed_margin is None
            else f"{cam.speed_margin:.3g} x",
            f"{cam.peak_torque:.4g} N*m",
            f"{cam.peak_torque_at_deg:.1f} deg",
            result_text,
        )
    con.print(t)
    fails = [
        f"{cam.name}: {c.name} {c.value_text()} {c.unit}, needs {c.sense} {c.limit:g}"
        for cam in result.cams
        for c in cam.check.checks
        if not c.ok
    ]
    notes(con, "fails", "red", fails)
    d = result.drive
    con.print(
        f"shaft torque: peak {d.peak_torque:.4g} N*m at {d.peak_torque_at_deg:.1f} deg, RMS {d.rms_torque:.4g} N*m, "
        f"mean {d.mean_torque:.4g} N*m"
    )
    con.print(
        f"power: mean {d.mean_power:.4g} W, peak {d.peak_torque * d.omega:.4g} W; energy swing {d.energy_swing:.4g} J, "
        f"flywheel {d.flywheel_inertia:.4g} kg*m^2 for a speed fluctuation of {d.speed_fluctuation:g}"
    )
    for gap in result.clearances:
        ok = "[green]pass[/green]" if gap.check.ok else "[bold red]FAIL[/bold red]"
        con.print(
            f"clearance {' <-> '.join(gap.between)}: least gap {gap.least_gap_mm:.4g} mm "
            f"at {gap.least_gap_at_deg:.1f} deg "
            f"(needs {gap.min_gap_mm:g} mm) {ok}"
        )
    for cam in result.cams:
        notes(con, f"warning ({cam.name})", "yellow", cam.check.warnings)
    colour = "green" if result.verdict == "pass" else "red"
    con.print(f"verdict: [bold {colour}]{result.verdict.upper()}[/bold {colour}]")


def run(args: argparse.Namespace) -> int:
    machine = args.spec
    out = Path(args.output)
    csv_path = output_file(out / f"{machine_stem(machine.name)}.csv", args.force, "machine CSV")
    if args.report:  # refuse before minutes of work, not after
        from ..report.machine import machine_output_names, write_machine_report  # matplotlib only with --report

        pdf, pngs = machine_output_names(machine.name)
        for name in (pdf, *pngs):
            output_file(out / name, args.force, "machine report")
    with progress_bar(args.quiet) as progress:
        result = run_machine(machine, progress=progress)
        written = write_machine_report(result, out, progress=progress) if args.report else None
    write_new(csv_path, result.csv, args.force)
    if args.json:
        print(json_text(result.json()))
    else:
        print_machine(result)
    print(
        f"wrote {csv_path}" + (f", {written.pdf} and {len(written.pngs)} PNG pages" if written else ""), file=sys.stderr
    )
    return 0 if result.verdict == "pass" else 1
