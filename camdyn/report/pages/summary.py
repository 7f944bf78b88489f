"""Page 1, the summary: the verdict, the checks, key results, warnings and advice, key inputs, two thumbnails."""

from __future__ import annotations

import math
import textwrap
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from ...design.checks import CheckKind
from ...plot import (
    deg_ticks,
    flank_names,
    legend_above_data,
    plot_flank_force,
    plot_follower,
    plot_groove_cam,
    shade_separations,
)
from .._data import ReportData
from .._layout import Flow, verdict_block
from .._style import C
from ._facts import IN_FACTS, at_limit, conjugate, decision_facts, holder, key_results
from ._inputs import input_columns

if TYPE_CHECKING:
    pass

NOTE_LINES = 14  # lines of warnings and advice before the rest is referred to `camdyn check`
INPUT_ROWS = 26  # rows per column of key inputs


def draw_summary(fig: Figure, data: ReportData) -> None:
    flow = Flow(fig, 0.93)
    if data.case.spec.description:
        flow.para(data.case.spec.description, size=8.5, width=105, color=C["grey"])
    _verdict(fig, data, flow)
    _checks_table(data, flow)
    _key_results(data, flow)
    _facts(fig, data, flow)
    _notes(fig, data, flow)
    flow.heading("Key inputs")
    _draw_inputs(data, flow)
    _glance(fig, data, flow.y - 0.02)


def _verdict(fig, data: ReportData, flow: Flow) -> None:
    """PASS or FAIL, large, and how many checks fail at which speed."""
    chk = data.check
    passed = chk.verdict == "pass"
    n_fail = sum(not c.ok for c in chk.checks)
    what = "every check passes" if passed else f"{n_fail} of {len(chk.checks)} checks fail"
    if chk.valvetrain is not None:
        verdict_block(fig, flow, passed, f"at {chk.speed_rpm:g} rpm: {what}", _valvetrain_model(data))
        return
    model = f"{chk.dynamic.model} follower" + (
        " (oscillating arm; torques as contact forces through the lever arm)" if data.oscillating else ""
    )
    verdict_block(fig, flow, passed, f"at {chk.speed_rpm:g} rpm: {what}", model)


def _valvetrain_model(data: ReportData) -> str:
    """What judges a valvetrain: the two-mass model, its cam contact and its spring's mass."""
    sd = data.case.spring
    spring = "" if sd is None or sd.model == "none" else f"; the valve spring's mass on the valve ({sd.model})"
    return f"two-mass valvetrain, {data.check.dynamic.model} cam contact{spring}"


def _margin(c) -> str:
    """The distance from the check's value to its limit, positive where it passes; "at limit" within 2 %."""
    if c.value is None:
        return "\u221e" if c.ok else "-\u221e"
    d = c.margin
    if d == 0.0:
        return "0 (at the limit)"
    if at_limit(c):
        return f"{d:+.3g}: at limit"
    pct = 100.0 * d / abs(c.limit) if abs(c.limit) > 1e-9 and abs(c.limit) < 1e9 else math.inf
    rel = (
        f" ({pct:+.0f}%)" if abs(pct) < 1000.0 else ""
    )  # against a limit near 0 (no cusp: 1e-6 mm) a ratio says nothing
    return f"{d:+.3g}{rel}"


def _checks_table(data: ReportData, flow: Flow) -> None:
    flow.heading("Checks")
    cols = [
        (0.0, "check"),
        (0.165, "what"),
        (0.6, "value"),
        (0.625, ""),
        (0.74, "limit"),
        (0.78, "margin"),
        (1.0, "result"),
    ]
    flow.row(
        [
            (
                x,
                t,
                {"weight": "bold", "ha": "right" if t in ("value", "limit", "result") else "left", "color": C["grey"]},
            )
            for x, t in cols
        ]
    )
    for c in data.check.checks:
        ok_kw = {"color": C["ok"] if c.ok else C["fail"], "weight": "bold", "ha": "right"}
        flow.row(
            [
                (0.0, c.name, {"family": "DejaVu Sans Mono", "size": min(7.8, 132.0 / len(c.name))}),  # fits its column
                (0.165, c.label, {"color": C["grey"]}),
                (0.6, c.value_text(), {"ha": "right"}),
                (0.625, {">=": "\u2265", "<=": "\u2264", ">": ">"}.get(c.sense, c.sense), {"ha": "center"}),
                (0.74, f"{c.limit:g} {c.unit}", {"ha": "right"}),
                (0.78, _margin(c), {"color": C["ok"] if c.ok else C["fail"]}),
                (1.0, "pass" if c.ok else "FAIL", ok_kw),
            ],
            size=8.5,
        )
    mono = {"family": "DejaVu Sans Mono", "size": 7.8}
    if data.check.closure is not None:  # what a spring-held cam is judged by first, and why a groove cam is not
        flow.row(
            [
                (0.0, "speed_margin", mono),
                (
                    0.165,
                    f"does not apply: form-closed, {holder(data)} the follower both ways (it cannot jump)",
                    {"color": C["grey"]},
                ),
            ],
            size=8.5,
        )
    contact = data.check.contact
    if contact is None:
        what = "not evaluated: the case gives no contact width ([follower] width)"
    elif data.check.find(CheckKind.CONTACT_STRESS) is None:
        what = f"largest Hertz pressure {contact.peak_pressure_MPa:.4g} MPa: not judged, no [limits] max_contact_stress"
    else:
        return
    flow.row([(0.0, "contact_stress", mono), (0.165, what, {"color": C["grey"]})], size=8.5)


def _key_results(data: ReportData, flow: Flow) -> None:
    """The key results in two columns."""
    flow.heading("Key results")
    rows = key_results(data)
    half = (len(rows) + 1) // 2
    for i in range(half):
        cells = []
        for j, off in ((i, 0.0), (i + half, 0.5)):
            if j < len(rows):
                cells += [(off, rows[j][0], {"color": C["grey"]}), (off + 0.2, rows[j][1], {})]
        flow.row(cells, size=8.2)


def _facts(fig, data: ReportData, flow: Flow) -> None:
    """The decision-changing facts of the later pages, each a line (or two)."""
    facts = decision_facts(data)
    flow.heading("Decision-changing facts" if facts else "Decision-changing facts: none beyond the checks")
    for text in facts:
        fig.text(flow.left, flow.y, "\u25b8", size=7.8, va="top", color=C["fail"])
        flow.para(text, size=7.8, width=118, indent=0.02, color=C["ink"])


def _notes(fig, data: ReportData, flow: Flow) -> None:
    """The check's warnings and advice, as many as fit in :data:`NOTE_LINES` lines."""
    chk, case = data.check, data.case
    # the motion's jumps and the follower's flights are in the decision-changing facts, counted from the plots
    shown = [w for w in chk.warnings if not w.startswith(IN_FACTS)]
    notes = [(w, "warning", C["warn"]) for w in shown] + [(a, "advice", C["advice"]) for a in chk.advice]
    told = len(chk.warnings) - len(shown)
    if notes:
        flow.heading("Warnings and advice" + (f" ({told} more among the facts above)" if told else ""))
    else:
        flow.heading("Warnings and advice: none" + (" beyond the facts above" if told else ""))
    budget = NOTE_LINES
    for k, (text, kind, colour) in enumerate(notes):
        lines = textwrap.wrap(text, 112)
        if budget - len(lines) < 1 and k < len(notes) - 1:
            flow.para(
                (
                    f"\u2026 and {len(notes) - k} more: run camdyn check {case.source.name if case.source else ''}"
                ).rstrip(),
                size=7.8,
                color=C["grey"],
            )
            break
        fig.text(flow.left, flow.y, kind, size=7.8, va="top", color=colour, weight="bold")
        flow.para(text, size=7.8, width=112, indent=0.075, color=C["ink"])
        budget -= len(lines)


def _draw_inputs(data: ReportData, flow: Flow) -> None:
    columns = input_columns(data)
    width = 1.0 / len(columns)
    y0 = flow.y
    ys = []
    for i, (title, rows) in enumerate(columns):
        flow.y = y0
        x = i * width
        flow.row([(x, title, {"weight": "bold", "color": C["grey"]})], size=8.2)
        key_w = max([len(k) for k, _ in rows if not k.startswith("\x00")] + [8]) * 0.0083 + 0.012  # flow units
        for k, v in rows[:INPUT_ROWS]:
            if k.startswith("\x00"):  # a sub-heading
                flow.row([(x, k[1:], {"weight": "bold", "color": C["grey"]})], size=8.2)
                continue
            flow.row([(x, k, {"color": C["grey"]}), (x + key_w, v, {})], size=7.6)
        if len(rows) > INPUT_ROWS:
            flow.row([(x, f"\u2026 {len(rows) - INPUT_ROWS} more", {"color": C["grey"]})], size=7.6)
        ys.append(flow.y)
    flow.y = min(ys)


def _glance(fig, data: ReportData, top: float) -> None:
    """Thumbnails in the space left at the bottom of the summary: the cam and the interface force."""
    bottom = 0.065
    if top - bottom < 0.11:  # thumbnails under 0.08 of the page say nothing
        return
    h = min(top - bottom - 0.03, 0.26)
    y0 = top - 0.03 - h
    geo = data.check.geometry
    if data.check.closure is not None:
        ax = fig.add_axes((0.06, y0, 0.3, h))
        plot_groove_cam(ax, data.check, angles=(0.0,), marks=False)
        ax.set_title(f"cam at \u03b8 = 0: both {'cams' if conjugate(data) else 'walls'}", fontsize=8.5)
        _small(ax)
        ax = fig.add_axes((0.42, y0, 0.52, h))
        plot_flank_force(ax, data.check, legend=False, marks=False)
        plus, minus = flank_names(data.check)
        ax.set_title(f"contact force at {data.check.speed_rpm:g} rpm (+ {plus}, \u2212 {minus})", fontsize=8.5)
        _small(ax)
        return
    if geo is not None:
        ax = fig.add_axes((0.1, y0, 0.24, h))
        ax.set_aspect("equal", adjustable="datalim")
        ax.add_patch(Polygon(geo.contour.T, closed=True, fc=C["cam"], ec=C["ink"], lw=1.0))
        ax.plot(0, 0, "+", color=C["ink"], ms=7)
        plot_follower(ax, geo, 0.0, colour=C["dyn"], lw=1.0)
        ax.autoscale_view()
        ax.set_title("cam at \u03b8 = 0", fontsize=8.5)
        ax.set_xlabel("x (mm)", fontsize=7)
        ax.set_ylabel("y (mm)", fontsize=7)
        ax.tick_params(labelsize=6.5)
        ax.grid(False)
    _force_thumbnail(fig.add_axes((0.42, y0, 0.52, h)), data)


def _small(ax) -> None:
    """A thumbnail's axis labels and ticks, small."""
    ax.xaxis.label.set_fontsize(7)
    ax.yaxis.label.set_fontsize(7)
    ax.tick_params(labelsize=6.5)


def _force_thumbnail(ax, data: ReportData) -> None:
    resp = data.check.response
    kin_label = "kinematic" if data.check.valvetrain is None else "kinematic, one equivalent mass"
    ax.plot(resp.theta_deg, resp.kinematic_force, color=C["kin"], ls="--", lw=0.9, label=kin_label)
    valve = data.check.valvetrain
    dyn_label = "dynamic" if valve is None else "dynamic, one equivalent mass"
    ax.plot(resp.theta_deg, resp.force, color=C["dyn"], lw=1.2, label=dyn_label)
    if valve is not None:  # what contact_force judges: the two-mass model's cam force over the valve event
        v = valve.response
        event = np.where(v.in_event, v.cam_force, np.nan)
        ax.plot(v.theta_deg, event, color=C["margin"], lw=1.2, label="two masses, valve event")
    ax.axhline(0.0, color=C["ink"], lw=0.7)
    mf = data.case.limits.min_contact_force
    if mf:
        ax.axhline(mf, color=C["limit"], ls="--", lw=0.8, label="min_contact_force")
    shade_separations(ax, resp, label=True)
    deg_ticks(ax, 60.0)
    ax.set_title(f"interface force at {data.check.speed_rpm:g} rpm", fontsize=8.5)
    ax.set_xlabel("cam angle \u03b8 (deg)", fontsize=7)
    ax.set_ylabel("force (N)", fontsize=7)
    ax.tick_params(labelsize=6.5)
    legend_above_data(ax, fontsize=6.5, ncol=4 if valve is None else 2)
