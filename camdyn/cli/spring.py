"""``camdyn spring CASE.toml``: the helical compression spring for the case's own rate and preload, as a part."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..design.spring import SpringDesign, design_case_spring, spring_loads
from ..model.case import build_case
from ._console import console, json_text, notes, table


def _rows(d: SpringDesign):
    s = d.spring
    lengths_mm = {
        "wire diameter": s.wire_diameter,
        "mean coil diameter": s.mean_diameter,
        "free length": s.free_length,
        "installed length (preload)": d.installed_length,
        "length at full lift": d.full_lift_length,
        "solid length": s.solid_length,
        "pitch": s.pitch,
    }
    for name, mm in lengths_mm.items():
        yield name, f"{mm:.4g}", "mm"
    yield "outside / inside diameter", f"{s.outside_diameter:.2f} / {s.inside_diameter:.2f}", "mm"
    yield "spring index", f"{s.index:.3g}", ""
    yield "active / total coils", f"{s.active_coils:g} / {s.total_coils:g}", ""
    yield "rate", f"{s.rate:.4g}", "N/mm"
    yield "mass (active coils)", f"{1e3 * s.mass:.3g} ({1e3 * s.active_mass:.3g})", "g"
    surge = f" ({d.surge.ratio:.3g} x the cam's)" if d.surge else ""
    yield "surge frequency", f"{s.surge_frequency:.4g}{surge}", "Hz"


def print_spring(case_name: str, d: SpringDesign, lever_arm: float | None) -> None:
    con = console()
    s = d.spring
    con.print(f"[bold]{case_name}[/bold]  return spring: {s.material} (ASTM {s.wire.astm}), {s.end_type} ends")
    at = f" at {lever_arm:g} mm from the arm pivot" if lever_arm is not None else ""
    con.print(f"rate {s.rate:.4g} N/mm{at}, preload {d.preload:.4g} N at the installed length, lift {d.lift:.4g} mm")
    t = table(("part", "left"), ("value", "right"), ("unit", "left"))
    for row in _rows(d):
        t.add_row(*row)
    con.print(t)
    w = table(("working point", "left"), ("length mm", "right"), ("force N", "right"), ("stress MPa", "right"))
    for name, length, force in (
        ("installed", d.installed_length, d.preload),
        ("full lift", d.full_lift_length, d.full_lift_force),
        ("solid", s.solid_length, s.solid_force),
    ):
        w.add_row(name, f"{length:.1f}", f"{force:.4g}", f"{float(s.stress(force)):.4g}")
    con.print(w)
    sut, ssy = s.strengths
    con.print(
        f"[dim]wire: Sut {sut:.4g} MPa, torsional yield {ssy:.4g} MPa (Shigley Tables 10-4, 10-6); stresses with the "
        "Bergstrasser factor[/dim]"
    )
    c = table(
        ("check", "left"), ("value", "right"), ("", "center"), ("limit", "right"), ("unit", "left"), ("result", "left")
    )
    for chk in d.checks:
        c.add_row(
            chk.name,
            chk.value_text(),
            chk.sense,
            f"{chk.limit:.4g}",
            chk.unit,
            "[green]pass[/green]" if chk.ok else "[bold red]FAIL[/bold red]",
        )
    con.print(c)
    notes(con, "warning", "yellow", d.warnings)
    con.print(
        f"spring: [bold]{s.material} d {s.wire_diameter:g} mm, D {s.mean_diameter:.2f} mm, {s.active_coils:g} active "
        f"/ {s.total_coils:g} total coils, free length {s.free_length:.1f} mm[/bold]"
    )


def run(args: argparse.Namespace) -> int:
    case = build_case(args.spec, source=Path(args.case))
    loads = spring_loads(case)
    design = design_case_spring(case)
    spring_spec = case.spec.spring
    lever_arm = spring_spec.lever_arm if spring_spec is not None else None  # an arm's only (the schema's rule)
    if args.json:
        doc = {
            "case": case.name,
            "rate_N_per_mm": loads.rate,
            "preload_N": loads.preload,
            "lift_mm": loads.lift,
            "spring": design.json(),
        }
        if lever_arm is not None:
            doc["lever_arm_mm"] = lever_arm
        print(json_text(doc))
    else:
        print_spring(case.name, design, lever_arm)
    return 0
