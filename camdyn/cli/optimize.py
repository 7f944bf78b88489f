"""``camdyn optimize CASE.toml -o OUT.toml``: reshape the rises and returns for an objective, write the case."""

from __future__ import annotations

import os
from pathlib import Path

from .._core.errors import InputError
from .._core.outputs import output_file, write_new
from ..design.optimize import optimize_case
from ..model.case import build_case
from . import _console

_ROWS = (  # (label, Metrics field, format)
    ("dynamic jump speed (rpm)", "jump_speed_rpm", ".1f"),
    ("least contact force at the case speed (N)", "least_force_N", ".4g"),
    ("peak acceleration ({u}/rad^2)", "peak_acceleration", ".4g"),
    ("max pressure angle (deg)", "max_pressure_angle_deg", ".2f"),
    ("least radius of curvature (mm)", "min_radius_of_curvature_mm", ".4g"),
    ("peak spring force ({f})", "peak_spring_force", ".4g"),
    ("residual vibration ({u})", "residual_vibration", ".3g"),
    ("verdict", "verdict", ""),
)


def print_optimization(res, output: Path) -> None:
    con = _console.console()
    u, f = ("deg", "N*m") if res.case.oscillating else ("mm", "N")
    con.print(f"[bold]{res.case.name}[/bold]  optimized for {res.objective}: {len(res.document['motion']['segments'])} segments, rises and returns as B-splines")
    t = _console.table(("", "left"), ("before", "right"), ("after", "right"))
    for label, key, fmt in _ROWS:
        before, after = getattr(res.before, key), getattr(res.after, key)
        t.add_row(label.format(u=u, f=f), format(before, fmt), format(after, fmt))
    con.print(t)
    for p in res.verification["points"]:
        td = next(v for k, v in p.items() if k.startswith("time_domain"))
        fd = next(v for k, v in p.items() if k.startswith("frequency_domain"))
        con.print(f"[dim]time domain at {p['speed_rpm']:.0f} rpm: least force {td:.4g} (frequency domain {fd:.4g}){', separates' if p['separated'] else ''}[/dim]")
    con.print(f"wrote {output} in {res.time_s:.1f} s; next: camdyn check {output}")


def run(args) -> int:
    out = output_file(args.output, args.force, "case file")  # before the work, not after
    if out.resolve() == Path(args.case).resolve():
        raise InputError(str(out), "is the input case; write the optimized case to another file")
    case = build_case(args.spec, source=Path(args.case))
    with _console.progress_bar() as progress:
        source = Path(os.path.relpath(Path(args.case).resolve(), out.resolve().parent)).as_posix()
        res = optimize_case(case, args.objective, speed_rpm=args.speed, progress=progress, name=out.stem, source=source)
    write_new(out, res.text(args.case), args.force)
    if args.json:
        print(_console.json_text(res.json() | {"output": str(out)}))
    else:
        print_optimization(res, out)
    return 0 if res.after.verdict == "pass" else 1
