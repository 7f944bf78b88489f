"""``camdyn size CASE.toml``: the return spring with the least peak force that holds up to margin x speed."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from rich.markup import escape
from rich.table import Table

from .._core.errors import InputError
from ..design.closure import BACKLASH_STEP_MM, PRELOAD_MARGIN, PRELOAD_STEP, largest_backlash, least_preload
from ..design.sizing import TIE_BREAK, SpringSizing, ValveSpringSizing, size_spring, size_valve_spring
from ..model.case import Case, build_case
from . import _console
from .spring import print_spring


def print_size(sz: SpringSizing, verbose: bool = False) -> None:
    console = _console.console()
    u = sz.units
    console.print(f"[bold]{sz.case_name}[/bold]  spring sizing")
    console.print(
        f"contact force >= {sz.min_contact_force:g} N at every angle and every speed up to {sz.top_speed_rpm:.4g} rpm "
        f"({sz.margin:g} x {sz.speed_rpm:g} rpm); {sz.model} follower; least peak spring force"
    )
    jump = lambda w: "none" if w == float("inf") else f"{w:.1f}"  # noqa: E731
    fmt = lambda x, scale: f"{0.0 if abs(x) < 1e-9 * max(1.0, abs(scale)) else x:.4g}"  # noqa: E731
    designs = [
        ("chosen" if sz.part is not None else "bound", sz.chosen)
    ]  # plain size: a bound on the force, not a part
    designs += [("kinematic LP", sz.kinematic)] if sz.model == "compliant" else []
    designs += [("current", sz.current), ("current rate", sz.at_current_rate)]
    table = Table(show_edge=False, pad_edge=False, box=None, header_style="bold")
    table.add_column("")
    for name, _ in designs:
        table.add_column(name, justify="right", no_wrap=True)
    ds = [d for _, d in designs]
    spring = sz.kind.force_word
    table.add_row(f"rate ({u['rate']})", *(f"{d.rate:.4g}" for d in ds))
    table.add_row(f"preload ({u['preload']})", *(fmt(d.preload, d.peak_spring) for d in ds))
    table.add_row(f"peak spring {spring} ({u['spring']})", *(f"{d.peak_spring:.4g}" for d in ds))
    table.add_row("peak contact force (N)", *(f"{d.peak_contact:.4g}" for d in ds))
    table.add_row("least contact force (N)", *(fmt(d.least_force, d.peak_contact) for d in ds))
    table.add_row("kinematic jump speed (rpm)", *(jump(d.kinematic_jump_rpm) for d in ds))
    table.add_row("dynamic jump speed (rpm)", *(jump(d.dynamic_jump_rpm) for d in ds))
    holds = (d.holds(sz.min_contact_force) for d in ds)
    table.add_row(
        f"holds up to {sz.top_speed_rpm:.4g} rpm",
        *("[green]yes[/green]" if h else "[bold red]no[/bold red]" for h in holds),
    )
    console.print(table)
    console.print(
        "[dim]contact forces: over every angle and every speed up to the top speed; current rate: the least preload "
        "that holds with the case's own rate[/dim]"
    )
    if sz.model == "compliant":
        c, k = sz.chosen, sz.kinematic
        console.print(
            f"dynamic correction (compliant train): rate {c.rate - k.rate:+.4g} {u['rate']}, preload "
            f"{c.preload - k.preload:+.4g} {u['preload']}, peak spring {c.peak_spring - k.peak_spring:+.4g} "
            f"{u['spring']}; dynamic jump speed {jump(k.dynamic_jump_rpm)} -> {jump(c.dynamic_jump_rpm)} rpm (the "
            f"kinematic answer's least dynamic contact force is {k.least_force:.4g} N)"
        )
    where = ", ".join(f"{a:.1f} deg" if a == b else f"{a:.1f}-{b:.1f} deg" for a, b, _ in sz.binding[:4])
    line = f"binding (kinematic): {where}" if where else "binding (kinematic): -"
    if sz.dynamic_binding is not None:
        line += f"; dynamic: {sz.dynamic_binding[0]:.1f} deg at {sz.dynamic_binding[1]:.4g} rpm"
    console.print(line)
    region = Table(
        show_edge=False,
        pad_edge=False,
        box=None,
        header_style="bold",
        title="feasible region: preload >= least preload(rate)",
        title_justify="left",
    )
    for col in (
        f"rate ({u['rate']})",
        f"least preload ({u['preload']}): kinematic",
        "dynamic",
        f"peak spring ({u['spring']})",
    ):
        region.add_column(col, justify="right", no_wrap=True)
    n = len(sz.region_rate)
    for i in np.unique(np.linspace(0, n - 1, 6).round().astype(int)):
        dyn_pre = (
            sz.region_preload_dynamic[i] if sz.region_preload_dynamic is not None else sz.region_preload_kinematic[i]
        )
        peak = sz.region_rate[i] * sz.s_max + dyn_pre
        region.add_row(
            f"{sz.region_rate[i]:.4g}",
            fmt(sz.region_preload_kinematic[i], peak),
            "-" if sz.region_preload_dynamic is None else fmt(dyn_pre, peak),
            f"{peak:.4g}",
        )
    console.print(region)
    if verbose:  # how ties are broken and how damping follows the rate: the method, not the answer
        console.print(f"[dim]tie-break:[/dim] {TIE_BREAK}")
        console.print(f"[dim]damping:[/dim] {sz.damping}")
    else:
        console.print("[dim]ties go to the least preload; --verbose says how ties and damping are handled[/dim]")
    for w in sz.warnings:
        console.print(f"[yellow]warning:[/yellow] {escape(w)}")
    c = sz.chosen
    spring = f"rate {c.rate:.4g} {u['rate']}, preload {c.preload:.4g} {u['preload']}"
    if sz.part is None:
        console.print(
            f"size: [bold]a lower bound, not a spring[/bold]: no spring holds to {sz.top_speed_rpm:.4g} rpm with a "
            f"peak force below {c.peak_spring:.4g} {u['spring']} ({spring}{_preload_deflection(sz)}); such a spring "
            "may not exist as a part: [bold]camdyn size --buildable[/bold] proposes one that can be built and passes "
            "check with its own mass"
        )
        return
    chk = sz.check
    assert chk is not None  # size --buildable gives the part and its check together
    console.print(
        f"size: [bold]{spring}[/bold] (peak spring {c.peak_spring:.4g} {u['spring']}), the part below; check with its "
        f"own mass ({sz.spring_model}, {1e3 * sz.spring_mass_kg:.3g} g): speed_margin {chk.value:.5g} {chk.sense} "
        f"{chk.limit:g} " + ("[green]pass[/green]" if chk.ok else "[bold red]FAIL[/bold red]")
    )


def size_preload(args: argparse.Namespace, case: Case) -> int:
    """``camdyn size`` of conjugate cams without backlash: the least preload between the rollers (N, or N*m about
    the pivot) that keeps both loaded at the speed, and the one proposed with its margin."""
    sz = least_preload(case, args.max_speed)
    if args.json:
        print(_console.json_text(sz.json()))
        return 0
    con = _console.console()
    unit, key = ("N", "conjugate_preload") if sz.translating else ("N*m", "conjugate_preload_torque")
    con.print(
        f"[bold]{case.name}[/bold]  conjugate cams: no return spring to size (the two cams hold the follower both "
        f"ways); the preload between the rollers that keeps both loaded at {sz.speed_rpm:g} rpm"
    )
    con.print(
        f"case: {key} = {sz.current_preload:g} {unit}, least force on either cam {sz.current_least_cam_force_N:.4g} N "
        + ("[green]held[/green]" if sz.holds else "[bold red]a roller unloads[/bold red]")
        + (f" ({sz.current_preload / sz.least_preload:.3g} x the least)" if sz.least_preload > 0.0 else "")
    )
    con.print(
        f"least preload: {sz.least_preload:.4g} {unit} (half the largest net force {sz.max_net_force:.4g} {unit}: "
        "equally stiff contacts share a change of force half each)"
    )
    con.print(
        f"size: [bold]{key} = {sz.proposed_preload:g} {unit}[/bold] ({PRELOAD_MARGIN:g} x the least, rounded up to "
        f"{PRELOAD_STEP:g} {unit}); least force on either cam {sz.proposed_least_cam_force_N:.4g} N there"
    )
    return 0


def _preload_deflection(sz: SpringSizing) -> str:
    """The spring's deflection at its preload (mm; translating followers), which says whether it can be a part."""
    c = sz.chosen
    if sz.kind.rotary or not c.rate > 0.0 or c.preload <= 0.0:
        return ""
    return f"; {c.preload / c.rate:.4g} mm of preload deflection"


def print_valve_size(vs: ValveSpringSizing) -> None:
    """``size`` on a valvetrain: the closed-form start, the proposal and the case's spring, by the two-mass model."""
    console = _console.console()
    console.print(f"[bold]{vs.case_name}[/bold]  valve spring sizing (at the valve)")
    console.print(
        f"float and bounce speeds >= {vs.top_speed_rpm:.5g} rpm ({vs.margin:g} x {vs.speed_rpm:g} rpm), two-mass "
        f"model; ratio {vs.ratio:g}, lash {vs.lash_mm:g} mm, equivalent mass {vs.equivalent_mass_kg:.4g} kg at the "
        f"follower, {vs.valve_lift_mm:.4g} mm of spring travel; the least preload with rate >= {vs.min_rate:g} N/mm"
    )
    speed = lambda w: "none" if w == float("inf") else f"{w:.1f}"  # noqa: E731
    designs = (("proposed", vs.chosen), ("closed form", vs.closed_form), ("current", vs.current))
    table = Table(show_edge=False, pad_edge=False, box=None, header_style="bold")
    table.add_column("")
    for name, _ in designs:
        table.add_column(name, justify="right", no_wrap=True)
    ds = [d for _, d in designs]
    table.add_row("rate (N/mm)", *(f"{d.rate:.4g}" for d in ds))
    table.add_row("preload (N)", *(f"{d.preload:.4g}" for d in ds))
    table.add_row("peak spring force (N)", *(f"{d.peak_spring:.4g}" for d in ds))
    table.add_row("float speed (rpm)", *(speed(d.float_speed_rpm) for d in ds))
    table.add_row("bounce speed (rpm)", *(speed(d.bounce_speed_rpm) for d in ds))
    table.add_row(f"seating velocity at {vs.speed_rpm:g} rpm (m/s)", *(f"{d.seating_velocity:.3g}" for d in ds))
    table.add_row(f"bounce height at {vs.speed_rpm:g} rpm (mm)", *(f"{d.bounce_height_mm:.3g}" for d in ds))
    table.add_row(f"least train force at {vs.top_speed_rpm:.5g} rpm (N)", *(f"{d.least_train_force:.4g}" for d in ds))
    holds = (d.holds(vs.top_speed_rpm) for d in ds)
    table.add_row(
        f"holds up to {vs.top_speed_rpm:.5g} rpm",
        *("[green]yes[/green]" if h else "[bold red]no[/bold red]" for h in holds),
    )
    console.print(table)
    console.print(
        f"[dim]closed form: the equivalent follower's least peak force (its kinematic jump speed "
        f"{speed(vs.closed_form_jump_rpm)} rpm), judged by the two-mass model; the preload then searched in "
        f"{len(vs.rounds)} two-mass runs[/dim]"
    )
    for w in vs.warnings:
        console.print(f"[yellow]warning:[/yellow] {escape(w)}")
    c = vs.chosen
    verdict = "[green]pass[/green]" if vs.verdict == "pass" else "[bold red]FAIL[/bold red]"
    part = ""
    if vs.part is not None:
        settled = ", ".join(f"{1e3 * m:.4g} g: {f0:.4g} N" for m, f0 in vs.part_rounds)
        console.print(
            f"[dim]the \\[spring] part: its mass on the valve ({vs.spring_model}) sized with, round by round, "
            f"and the preload it asked: {settled}; the part below is the one check designs for the proposal[/dim]"
        )
        part = f", the \\[spring] part below ({1e3 * vs.spring_mass_kg:.4g} g)"
    console.print(
        f"size: [bold]spring_rate = {c.rate:.4g}, preload = {c.preload:.4g}[/bold] in \\[dynamics] (at the valve)"
        f"{part}; check as written: {verdict}"
    )


def run(args: argparse.Namespace) -> int:
    case = build_case(args.spec, source=Path(args.case))
    if case.valvetrain is not None:
        if args.buildable:
            raise InputError(
                "--buildable",
                "size --buildable does not apply to a valvetrain: size proposes the valve spring's rate and "
                "preload, and with a [spring] part designs the part for them",
            )
        with _console.progress_bar(args.quiet) as progress:  # seconds: the two-mass model at each preload tried
            vs = size_valve_spring(case, args.max_speed, args.margin, args.min_rate, progress)
        if args.json:
            print(_console.json_text(vs.json()))
        else:
            print_valve_size(vs)
            if vs.part is not None:
                print_spring(vs.case_name, vs.part, None)
        return 0
    if case.follower is not None and case.follower.form_closed:  # no return spring: its largest backlash instead
        return size_groove(args, case)
    min_rate = 0.0 if args.min_rate is None else args.min_rate
    with _console.progress_bar(args.quiet or not args.buildable) as progress:  # --buildable: seconds a round
        sz = size_spring(case, args.max_speed, args.margin, min_rate, buildable=args.buildable, progress=progress)
    if args.json:
        print(_console.json_text(sz.json()))
    else:
        print_size(sz, args.verbose)
        if sz.part is not None:
            spring_spec = case.spec.spring
            lever_arm = spring_spec.lever_arm if spring_spec is not None else None  # an arm's only
            print_spring(sz.case_name, sz.part, lever_arm)
    return 0


def size_groove(args: argparse.Namespace, case: Case) -> int:
    """``camdyn size`` of a groove cam (or conjugate cams with backlash): there is no return spring; the largest
    backlash (mm) that keeps the impact speed within max_impact_velocity at the speed (``--max-speed``, default the
    case's). Conjugate cams without backlash: the least preload between the rollers (:func:`size_preload`)."""
    f = case.follower
    assert f is not None
    conj = f.closure == "conjugate"
    answer = "the least preload between its rollers" if conj and f.backlash == 0.0 else "its largest backlash"
    what = "conjugate cams have" if conj else "a groove cam has"
    for flag, given in (("--margin", args.margin), ("--min-rate", args.min_rate), ("--buildable", args.buildable)):
        if given:
            raise InputError(flag, f"{what} no return spring to size: size gives {answer}")
    if conj and f.backlash == 0.0:
        return size_preload(args, case)
    sz = largest_backlash(case, args.max_speed)
    if args.json:
        print(_console.json_text(sz.json()))
        return 0
    con = _console.console()
    holder = "the conjugate cams hold" if conj else "the groove holds"
    con.print(
        f"[bold]{case.name}[/bold]  {f.closure} cam: no return spring to size ({holder} the follower both ways); "
        f"the largest backlash with impact speed <= max_impact_velocity {sz.max_impact_velocity:g} m/s at "
        f"{sz.speed_rpm:g} rpm"
    )
    con.print(
        f"case: backlash {sz.current_backlash_mm:g} mm, impact speed {sz.current_impact_velocity_m_per_s:.4g} m/s "
        + ("[green]pass[/green]" if sz.passes else "[bold red]FAIL[/bold red]")
    )
    if np.isinf(sz.max_backlash_mm):
        con.print("size: any backlash up to the roller radius keeps the impact speed within the limit")
    elif sz.max_backlash_mm <= 0.0:
        con.print(f"size: [bold red]no backlash of {BACKLASH_STEP_MM:g} mm or more[/bold red] keeps the limit")
    else:
        con.print(
            f"size: [bold]backlash <= {sz.max_backlash_mm:.4g} mm[/bold] (rounded down to {BACKLASH_STEP_MM:g} mm; "
            f"impact speed {sz.impact_velocity_at_max_m_per_s:.4g} m/s there)"
        )
    return 0
