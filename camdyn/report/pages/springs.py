"""The last page, spring sizing: the feasible springs, the springs compared, and the jump map."""

from __future__ import annotations

import math
import textwrap

from matplotlib import patheffects
from matplotlib.figure import Figure

from ..._core.results import Unavailable
from ...design.sizing import SpringSizing
from ...plot import plot_feasible_region, plot_jump_map
from .._data import ReportData
from .._layout import Flow, fit_lines, fmt, pretty_unit
from .._style import LEFT, C

MAP_TOP = 0.25  # the top of the jump map's axes (figure fraction)
DASH = "\u2013"


def _small(x: float, scale: float) -> str:
    """``x`` to 4 digits, and 0 where it is round-off against ``scale`` (a zero rate from the LP: 1e-17)."""
    return fmt(0.0 if abs(x) <= 1e-9 * max(1.0, abs(scale)) else x)


def _missed(x: float, limit: float) -> str:
    """A force ``x`` that misses ``limit``, to 4 digits or as many more (up to 7) as show it below the limit."""
    for digits in range(4, 8):
        text = f"{x:.{digits}g}"
        if float(text) < limit:
            return text
    return text


def _jump(rpm: float) -> str:
    return "unbounded" if not math.isfinite(rpm) else f"{rpm:.1f} rpm"


def _nb(text: str) -> str:
    """Text not to be broken across lines (a formula)."""
    return text.replace(" ", "\u00a0")


def draw_springs(fig: Figure, data: ReportData) -> None:
    sz = data.review.sizing
    if isinstance(sz, Unavailable):
        flow = Flow(fig, 0.94)
        flow.para("Spring sizing does not apply to this case:", size=9, weight="bold", color=C["fail"])
        flow.para(sz.reason, size=8.5, width=110, color=C["ink"])
        _spring_jump_map(fig, data)
        return
    _caption(fig, sz)
    _feasible_region(fig, sz)
    flow = Flow(fig, 0.545)
    _springs_compared(flow, sz)
    _notes(flow, sz)
    _spring_jump_map(fig, data)


def _symbols(sz: SpringSizing) -> tuple[str, str, str]:
    """(force, rate symbol, preload symbol): torque and T0 for an oscillating arm."""
    return sz.kind.force_word, "k", sz.kind.preload_symbol


def _caption(fig, sz: SpringSizing) -> None:
    force, k_sym, f_sym = _symbols(sz)
    constraint = _nb(f"{f_sym} \u2265 r \u2212 {k_sym} s")
    caption = (
        f"The return spring with the least peak spring {force} {_nb(f'P = {k_sym} s_max + {f_sym}')} that keeps the "
        f"contact force \u2265 min_contact_force = {sz.min_contact_force:g} N at every cam angle and every speed up "
        f"to {sz.top_speed_rpm:.4g} rpm (speed_margin {sz.margin:g} \u00d7 {sz.speed_rpm:g} rpm), {sz.model} "
        f"follower. Each grey line is one cam angle's constraint {constraint} (shown: the envelope and the binding "
        "angles); the springs above all of them hold."
    )
    lines = fit_lines(fig, caption, 0.88, {"size": 7.5}, 140)  # 140 characters, or fewer where they pass the margin
    fig.text(0.06, 0.94, "\n".join(lines), size=7.5, color=C["grey"], va="top", linespacing=1.3)


def _feasible_region(fig, sz: SpringSizing) -> None:
    ax = fig.add_axes((LEFT, 0.615, 0.95 - LEFT, 0.26))
    plot_feasible_region(
        ax,
        sz,
        colors={
            "kinematic": C["kin"],
            "dynamic": C["dyn"],
            "lines": C["constraint"],
            "iso": C["iso"],
            "chosen": C["ok"],
            "current": C["ink"],
        },
    )
    ax.set_xlabel(pretty_unit(ax.get_xlabel()))
    ax.set_ylabel(pretty_unit(ax.get_ylabel()))
    ax.set_title(f"feasible springs: preload against rate (holding up to {sz.top_speed_rpm:.4g} rpm)", fontsize=9)
    for t in ax.texts:  # the iso-line labels, in this report's way of writing units
        t.set_text(pretty_unit(t.get_text()))
    for line in ax.lines:  # a spring at the least rate (often 0) sits on the left edge: draw it whole
        if line.get_marker() not in (None, "None", ""):
            line.set_clip_on(False)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, fontsize=7)


def _holds(sz: SpringSizing, d) -> bool:
    return d.least_force >= sz.min_contact_force - 1e-6 * max(1.0, abs(d.peak_contact))


def _springs_compared(flow: Flow, sz: SpringSizing) -> None:
    """A table: the chosen spring (or plain size's bound), the kinematic LP answer (compliant train), the current
    design and the current rate with its least preload; their forces and jump speeds, and whether each holds."""
    u = {k: pretty_unit(v) for k, v in sz.units.items()}
    force, k_sym, f_sym = _symbols(sz)
    flow.heading("Springs compared")
    answer = "chosen" if sz.part is not None else "bound\n(not a part)"  # plain size: the least peak force, no spring
    designs = [(answer, sz.chosen)] + ([("kinematic LP\nanswer", sz.kinematic)] if sz.model == "compliant" else [])
    designs += [("current\ndesign", sz.current), ("current rate,\nleast preload", sz.at_current_rate)]
    xs = [0.52, 0.67, 0.82, 0.97] if len(designs) == 4 else [0.57, 0.77, 0.97]
    head = [
        (
            0.0,
            f"forces over every angle and\nevery speed up to {sz.top_speed_rpm:.4g} rpm",
            {"color": C["grey"], "linespacing": 1.3},
        )
    ]
    head += [
        (
            x,
            name,
            {"weight": "bold", "ha": "right", "linespacing": 1.3, "color": C["ok"] if name == answer else C["grey"]},
        )
        for x, (name, _) in zip(xs, designs, strict=True)
    ]
    flow.row(head, size=8.2)
    flow.y -= flow.h(8.2) * 1.05
    holds = [_holds(sz, d) for _, d in designs]
    rows = [
        (
            f"{sz.kind.rate_name} {k_sym} ({u['rate']})",
            [_small(d.rate, d.peak_spring / max(sz.s_max, 1e-300)) for _, d in designs],
        ),
        (f"preload {f_sym} ({u['preload']})", [_small(d.preload, d.peak_spring) for _, d in designs]),
        (f"peak spring {force} P ({u['spring']})", [fmt(d.peak_spring) for _, d in designs]),
        # a design that misses the limit by less than 4 digits shows the digits it misses by
        (
            "least contact force (N)",
            [
                _small(d.least_force, d.peak_contact) if h else _missed(d.least_force, sz.min_contact_force)
                for (_, d), h in zip(designs, holds, strict=True)
            ],
        ),
        ("peak contact force (N)", [fmt(d.peak_contact) for _, d in designs]),
        ("jump speed, kinematic (rigid)", [_jump(d.kinematic_jump_rpm) for _, d in designs]),
        ("jump speed, dynamic", [_jump(d.dynamic_jump_rpm) for _, d in designs]),
    ]
    for label, vals in rows:
        flow.row(
            [(0.0, label, {"color": C["grey"]})] + [(x, v, {"ha": "right"}) for x, v in zip(xs, vals, strict=True)],
            size=8.2,
        )
    flow.row(
        [(0.0, f"holds up to {sz.top_speed_rpm:.4g} rpm", {"color": C["grey"]})]
        + [
            (x, "yes" if h else "NO", {"ha": "right", "weight": "bold", "color": C["ok"] if h else C["fail"]})
            for x, h in zip(xs, holds, strict=True)
        ],
        size=8.2,
    )
    flow.y -= flow.h(8) * 0.4


def _binding_line(sz: SpringSizing) -> str:
    where = ", ".join(f"{a:.1f}\u00b0" if a == b else f"{a:.1f}\u2013{b:.1f}\u00b0" for a, b, _ in sz.binding[:4])
    speeds = sorted({round(w) for _, _, w in sz.binding[:4]})
    line = f"Binding (kinematic): {where or DASH}" + (
        f" at {', '.join(f'{w:g}' for w in speeds)} rpm" if speeds else ""
    )
    if sz.dynamic_binding is not None:
        line += f"; dynamic: {sz.dynamic_binding[0]:.1f}\u00b0 at {sz.dynamic_binding[1]:.4g} rpm"
    lift = f"{math.degrees(sz.s_max):.4g}\u00b0 of swing" if sz.kind.rotary else f"{sz.s_max:.4g} mm"
    return line + f". Full lift s_max = {lift}: the spring's deflection beyond its preload."


def _notes(flow: Flow, sz: SpringSizing) -> None:
    """Where the spring binds, how the choice was made, the dynamic correction and warnings: what fits above
    the jump map, the least important left out first (`camdyn size` prints them all)."""
    u = {k: pretty_unit(v) for k, v in sz.units.items()}
    force = _symbols(sz)[0]
    damping = _nb(sz.damping.split(":")[0])  # how c was treated; the method's detail is in `camdyn size`
    notes = [(_binding_line(sz), C["ink"], 0)]
    notes.append(
        (
            f"Chosen: the least peak spring {force}; ties (a binding angle at full lift) go to the least preload. "
            f"Damping: {damping}.",
            C["grey"],
            3,
        )
    )
    if sz.model == "compliant":
        c, k = sz.chosen, sz.kinematic
        correction = (
            "Dynamic correction for the compliant train, over the kinematic LP answer: preload "
            f"{_nb(f'{c.preload - k.preload:+.4g} ' + u['preload'])}, "
            f"peak spring {force} {_nb(f'{c.peak_spring - k.peak_spring:+.4g} ' + u['spring'])}."
        )
        notes.append((correction, C["grey"], 2))
    notes += [(f"Warning: {w}.", C["warn"], 1) for w in sz.warnings]
    size, width = 7.6, 124
    height = lambda text: flow.para_height(text, size=size, width=width) + flow.h(size) * 0.25  # noqa: E731
    room = flow.y - (MAP_TOP + 0.03)
    for prio in sorted({p for _, _, p in notes}, reverse=True):
        if sum(height(t) for t, _, _ in notes) <= room:
            break
        notes = [n for n in notes if n[2] != prio or prio == 0]
    for text, colour, _ in notes:
        text = text.replace("N*m", pretty_unit("N*m"))
        flow.para(text, size=size, width=width, color=colour)
        flow.y -= flow.h(size) * 0.25


def _spring_jump_map(fig, data: ReportData) -> None:
    """The jump map at the case's preload: least contact force over cam speed and spring rate."""
    top, bottom = MAP_TOP, 0.095  # room for the legend under the axes
    jm = data.review.jump_map
    ax = fig.add_axes((LEFT, bottom, 0.79 - LEFT, top - bottom))
    kind = data.case.kind
    preload = float(data.case.model.preload) if isinstance(jm, Unavailable) else jm.preload  # a valve's: at the valve
    pre = f"{preload:g} {pretty_unit(kind.force_unit)}"
    title = f"jump map: least contact force at the case's preload {kind.preload_symbol} = {pre}"
    if isinstance(jm, Unavailable):
        ax.text(
            0.5,
            0.5,
            "\n".join(textwrap.wrap(f"no jump map: {jm}", 90)),
            transform=ax.transAxes,
            ha="center",
            va="center",
            color=C["fail"],
            size=8,
        )
        ax.set_axis_off()
        ax.set_title(title, fontsize=9)
        return
    mesh = plot_jump_map(ax, jm)
    if mesh is not None:
        mesh.set_rasterized(True)  # 1152 cells: an image in the PDF is a tenth of the bytes of as many paths
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel(f"{kind.rate_name} ({pretty_unit(jm.spring_rate_unit)})")
    outline = [patheffects.withStroke(linewidth=2.2, foreground=C["ink"])]  # legible on light and dark colours
    ax.axvline(
        data.review.margin_rpm,
        color=C["margin"],
        lw=1.0,
        ls="-.",
        path_effects=outline,
        label=f"{data.case.limits.speed_margin:g} \u00d7 speed",
    )
    ax.grid(False)
    leg = ax.legend(
        loc="upper center",
        bbox_to_anchor=(0.5 * (LEFT + 0.79), bottom - 0.036),
        bbox_transform=fig.transFigure,
        ncol=3,
        fontsize=7,
    )
    for t in leg.get_texts():
        t.set_text(pretty_unit(t.get_text()))
    if mesh is not None:
        cax = fig.add_axes((0.81, bottom, 0.015, top - bottom))
        cb = fig.colorbar(mesh, cax=cax)
        cb.set_label("least contact force (N)", fontsize=7.5)
        cb.ax.tick_params(labelsize=7)
