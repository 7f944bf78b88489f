"""``camdyn synthesize PATH.toml -o CASE.toml``: a CCM's dimensions for a path, written as a complete case."""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import TYPE_CHECKING

from rich.markup import escape
from rich.table import Table

from .._core.errors import InputError
from .._core.outputs import output_file, write_new
from ..design.synthesis import synthesize_case
from . import _console

if TYPE_CHECKING:
    from ..design.synthesis import SynthesizedCase


def print_synthesize(res: SynthesizedCase, output: Path, elapsed: float) -> None:
    console = _console.console()
    s, m = res.summary, res.mechanism
    fb = s.get("fourbar")
    path = res.case.spec.path
    assert path is not None  # synthesize_case refuses a case without [path]
    console.print(
        f"[bold]{res.case.name}[/bold]  CCM for the {path.type} path, dimensions by differential "
        f"evolution (seed {s['seed']})"
    )
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
    table.add_row(
        "least transmission angle (deg)",
        f"{min(s['min_transmission_angle_deg'], s['min_slider_angle_deg']):.1f}",
        f"{fb['min_transmission_angle_deg']:.1f}" if fb else "",
    )
    table.add_row("base radius (mm)", f"{s['base_radius_mm']:g}", "-" if fb else "")
    err = lambda x: f"{x:.2g}" if x < 1e-3 else f"{x:.4g}"  # noqa: E731
    table.add_row("max path error (mm)", err(s["max_path_error_mm"]), err(s["fourbar_path_error_mm"]) if fb else "")
    table.add_row(
        "optimizer converged",
        conv(s["optimizer_converged"], s["generations"]),
        conv(fb["optimizer_converged"], fb["generations"]) if fb else "",
    )
    console.print(table)
    console.print(
        f"[dim]cam centre ({m['cam_center'][0]:g}, {m['cam_center'][1]:g}) mm, slider line through "
        f"({m['slider_point'][0]:g}, {m['slider_point'][1]:g}) mm at {m['slider_angle']:g} deg, crank turns "
        f"{s['rotation']}; objective {s['objective']}[/dim]"
    )
    for note in res.notes:
        console.print(f"[cyan]note:[/cyan] {escape(note)}")
    for w in s["warnings"]:
        console.print(f"[yellow]warning:[/yellow] {escape(w)}")
    if not res.constraints_met:
        console.print(
            f"[bold red]constraints not met:[/bold red] {escape('; '.join(s['violations']))} (try a larger --maxiter "
            "or another --seed)"
        )
    console.print(f"wrote {output} in {elapsed:.1f} s; next: camdyn check {output}")


def run(args: argparse.Namespace) -> int:
    out = output_file(args.output, args.force, "case file")  # before minutes of work, not after
    if out.resolve() == Path(args.case).resolve():
        raise InputError(str(out), "is the input path file; write the case to another file")
    t0 = time.perf_counter()
    with _console.progress_bar(args.quiet) as progress:
        res = synthesize_case(
            args.spec, source=Path(args.case), name=out.stem, seed=args.seed, maxiter=args.maxiter, progress=progress
        )
    elapsed = time.perf_counter() - t0
    write_new(out, res.text, args.force)
    if args.json:
        doc = {
            "output": str(out),
            "constraints_met": res.constraints_met,
            "time_s": elapsed,
            "mechanism": res.mechanism,
            "dynamics": res.dynamics,
            "summary": res.summary,
            "notes": res.notes,
        }
        print(_console.json_text(doc))
    else:
        print_synthesize(res, out, elapsed)
    return 0 if res.constraints_met else 1
