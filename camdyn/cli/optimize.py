"""``camdyn optimize CASE.toml -o OUT.toml``: reshape the rises and returns for an objective, write the case
only where it is better than the input on the objective and breaks nothing the input passed (else exit 1)."""

from __future__ import annotations

import argparse
import os
from dataclasses import fields
from pathlib import Path
from typing import TYPE_CHECKING

from .._core.outputs import write_new
from ..design.optimize import floor_rpm, optimize_case
from ..model.case import build_case
from . import _console

if TYPE_CHECKING:
    from ..design.optimize import Optimization


def print_optimization(res: Optimization, output: Path, original: str) -> None:
    """The before/after table, the time-domain verification and the claim, or why nothing was written;
    ``original``: the input case's name (the answer takes the output file's)."""
    con = _console.console()
    u, f = res.unit, res.force_unit
    con.print(
        f"[bold]{res.case.name}[/bold]  optimized for {res.objective}: "
        f"{len(res.document['motion']['segments'])} segments, "
        f"{'rises and returns' if res.valvetrain is None else 'the flanks between the ramps'} as B-splines of "
        f"{res.control_points} control points"
    )
    con.print(f"force margin {res.margin:.4g} {f}")
    t = _console.table(("", "left"), ("before", "right"), ("after", "right"))
    for fld in fields(res.before):
        fmt, shown = fld.metadata["format"], floor_rpm if fld.metadata["claim"] else (lambda x: x)
        t.add_row(
            fld.metadata["label"].format(u=u, f=f),
            format(shown(getattr(res.before, fld.name)), fmt),
            format(shown(getattr(res.after, fld.name)), fmt),
        )
    if res.valvetrain is not None:  # the two-mass facts its table shows (ValveFacts' labelled fields)
        for fld in (f for f in fields(res.valvetrain[0]) if "label" in f.metadata):
            pair = (getattr(facts, fld.name) for facts in res.valvetrain)
            shown = ("none found" if x is None else format(x, fld.metadata["format"]) for x in pair)
            t.add_row(fld.metadata["label"], *shown)
    con.print(t)
    for p in res.verification.points:
        td, fd = p.time_domain_least_force, p.frequency_domain_least_force
        if res.valvetrain is not None:
            said = ", floats" if p.separated else ("" if p.margin_held else ", bounces")
            con.print(
                f"[dim]two-mass model at {p.speed_rpm:.1f} rpm: least cam force over the valve event {td:.4g} N"
                f"{said}[/dim]"
            )
            continue
        said = ", separates" if p.separated else ("" if p.margin_held else f", under the {res.margin:.4g} {f} margin")
        beside = f" (frequency domain {fd:.4g} {f})" if p.domain == "time" else ""  # else it is the frequency domain's
        con.print(f"[dim]{p.domain} domain at {p.speed_rpm:.1f} rpm: least force {td:.4g} {f}{beside}{said}[/dim]")
    if (rob := res.robust) is not None:  # no speed: none of the built cams jumps within the search
        up_to = "at every speed searched" if rob.speed_rpm is None else f"up to {floor_rpm(rob.speed_rpm):.1f} rpm"
        con.print(
            f"robust: P(separation) <= {rob.separation_probability:g} {up_to} "
            f"({rob.samples} built cams of [tolerances])"
        )
    if res.written and res.valvetrain is not None:
        con.print(
            f"claimed: the valve does not float up to {floor_rpm(res.claimed_speed_rpm):.1f} rpm (two-mass model)"
        )
        con.print(f"wrote {output} in {res.time_s:.1f} s; next: camdyn check {output}")
    elif res.written:
        con.print(f"claimed: the margin holds at every speed up to {floor_rpm(res.claimed_speed_rpm):.1f} rpm")
        con.print(f"wrote {output} in {res.time_s:.1f} s; next: camdyn check {output}")
    else:
        con.print(f"[bold]cannot improve[/bold] {original} for {res.objective}; wrote nothing ({res.time_s:.1f} s):")
        for why in res.refusals:
            con.print(f"  - {why}")


def run(args: argparse.Namespace) -> int:
    out = Path(args.output)  # checked before JAX loaded (camdyn.cli._options): a new file, not the input
    case = build_case(args.spec, source=Path(args.case))
    with _console.progress_bar(args.quiet) as progress:
        source = Path(os.path.relpath(Path(args.case).resolve(), out.resolve().parent)).as_posix()
        res = optimize_case(
            case,
            args.objective,
            speed_rpm=args.speed,
            progress=progress,
            name=out.stem,
            source=source,
            min_force=args.min_force,
            control_points=args.control_points,
            robust=args.robust,
        )
    if res.written:
        write_new(out, res.text(args.case), args.force)
    if args.json:
        print(_console.json_text(res.json() | {"output": str(out) if res.written else None}))
    else:
        print_optimization(res, out, case.name)
    return 0 if res.written and res.after.verdict == "pass" else 1
