"""The machine report: ``camdyn machine MACHINE.toml --report`` writes ``DIR/<machine>-machine.pdf`` and
``DIR/<machine>-machine-<n>-<page>.png`` (deterministic, like a case's report): page 1 the verdict, each cam's
summary line and the timing diagram; page 2 the shaft torque, the energy and flywheel, and the clearances."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

from .._core.outputs import output_dir
from .._core.progress import Progress, counter
from ..design.machine import MachineCam, MachineResult
from ..plot.machine import (
    cam_colour,
    plot_clearances,
    plot_machine_energy,
    plot_machine_torque,
    plot_timing_diagram,
)
from ..schema.machine import machine_stem
from ._data import file_sha256
from ._layout import Flow, camdyn_version, fmt, page_frame, verdict_block
from ._render import Written, write_page
from ._style import A4, LEFT, C, style

if TYPE_CHECKING:
    from ..design.checks import Check

PAGES = (("summary", "Machine and timing"), ("drive", "Shaft torque and flywheel"))


def machine_output_names(machine_name: str) -> tuple[str, list[str]]:
    """The PDF's and the PNGs' names: ``<machine>-machine.pdf`` and ``<machine>-machine-<n>-<slug>.png``."""
    stem = machine_stem(machine_name)
    return f"{stem}.pdf", [f"{stem}-{i}-{slug}.png" for i, (slug, _) in enumerate(PAGES, start=1)]


def _header(fig, result: MachineResult, title: str, number: int) -> None:
    src = result.source.name if result.source is not None else result.name
    sha = file_sha256(result.source)
    src += f"  \u00b7  sha256 {sha[:12]}" if sha else ""
    page_frame(
        fig, result.name, title, number, len(PAGES), f"machine review  \u00b7  {src}  \u00b7  {result.speed_rpm:g} rpm"
    )


_SENSE = {">=": "\u2265", "<=": "\u2264", ">": ">"}


def _nearest_its_limit(checks: tuple[Check, ...]) -> Check | None:
    """The passing check with the least margin relative to its limit (a limit of 0, the least contact force's, has
    no relative margin: that force is said anyway)."""
    near = [c for c in checks if c.ok and c.margin is not None and c.limit != 0.0]
    return min(near, key=lambda c: (c.margin or 0.0) / abs(c.limit), default=None)


def cam_line(cam: MachineCam) -> str:
    """One cam's summary: its least contact force (a form-closed cam's: its crossovers, as its force is signed),
    speed margin, peak torque, the check nearest its limit and what fails."""
    chk = cam.check
    dyn = chk.dynamic
    if chk.closure is not None:
        n = len(chk.closure.response.crossovers)
        text = f"form-closed (cannot jump), the force changes flank {n} time{'s' if n != 1 else ''} a turn, "
    else:
        text = (
            f"least contact force {dyn.min_contact_force_N:.3g} N at cam {dyn.min_contact_force_deg:.1f}\u00b0, "
            f"speed margin {fmt(cam.speed_margin, 3)}\u00d7, "
        )
    text += f"peak torque {cam.peak_torque:.3g} N\u00b7m at {cam.peak_torque_at_deg:.1f}\u00b0"
    if dyn.separations:
        text += f", leaves the cam ({len(dyn.separations)} flights)"
    near = _nearest_its_limit(chk.checks)
    if near is not None:
        text += (
            f"; nearest its limit: {near.name} {near.value_text(3)} {_SENSE.get(near.sense, near.sense)} "
            f"{near.limit:g} {near.unit}"
        )
    return text + (f"; fails {', '.join(cam.failed)}" if cam.failed else "")


def _sha(cam: MachineCam) -> str:
    """`` (sha256 <12 hex>)`` of the cam's case file as it was read: which file its line reviews."""
    sha = file_sha256(cam.check.case.source)
    return f" (sha256 {sha[:12]})" if sha else ""


def _summary(fig, result: MachineResult) -> None:
    flow = Flow(fig, 0.93)
    if result.description:
        flow.para(result.description, size=8.5, width=105, color=C["grey"])
    n_fail = sum(c.verdict != "pass" for c in result.cams)
    what = f"all {len(result.cams)} cams pass" if n_fail == 0 else f"{n_fail} of {len(result.cams)} cams fail"
    gaps_fail = sum(not g.check.ok for g in result.clearances)
    if result.clearances:
        what += (
            "; clearances hold"
            if gaps_fail == 0
            else f"; {gaps_fail} clearance{'s' if gaps_fail > 1 else ''} too small"
        )
    subline = "each cam checked at the machine speed, as camdyn check --speed checks it"
    verdict_block(fig, flow, result.verdict == "pass", f"at {result.speed_rpm:g} rpm: {what}", subline)
    flow.heading("Cams")
    for i, cam in enumerate(result.cams):
        ok = cam.verdict == "pass"
        flow.row(
            [
                (0.0, cam.name, {"weight": "bold", "color": cam_colour(i)}),
                (0.16, f"{cam.case_file}{_sha(cam)}, phase {cam.phase_deg:g}\u00b0", {"color": C["grey"]}),
                (
                    1.0,
                    "pass" if ok else "FAIL",
                    {"ha": "right", "weight": "bold", "color": C["ok"] if ok else C["fail"]},
                ),
            ],
            size=8.5,
        )
        flow.para(cam_line(cam), size=7.8, width=120, indent=0.02, color=C["ink"])
        flow.y -= flow.h(7.8) * 0.35
    if result.clearances:
        flow.heading("Clearances")
        for gap in result.clearances:
            ok = gap.check.ok
            at = f"{gap.least_gap_at_deg:.1f}\u00b0"
            least = f"least gap {gap.least_gap_mm:.3g} mm at {at}, needs {gap.min_gap_mm:g} mm"
            flow.row(
                [
                    (0.0, " \u2194 ".join(gap.between), {"weight": "bold"}),
                    (0.3, least, {}),
                    (
                        1.0,
                        "pass" if ok else "FAIL",
                        {"ha": "right", "weight": "bold", "color": C["ok"] if ok else C["fail"]},
                    ),
                ],
                size=8.2,
            )
    d = result.drive
    flow.heading("Main-shaft drive")
    rows = [
        ("peak torque", f"{d.peak_torque:.4g} N\u00b7m at {d.peak_torque_at_deg:.1f}\u00b0"),
        ("RMS torque", f"{d.rms_torque:.4g} N\u00b7m"),
        ("mean torque", f"{d.mean_torque:.4g} N\u00b7m"),
        ("mean power", f"{d.mean_power:.4g} W"),
        ("peak power", f"{d.peak_torque * d.omega:.4g} W"),
        ("energy swing", f"{d.energy_swing:.4g} J"),
        ("speed fluctuation", f"{d.speed_fluctuation:g}"),
        ("flywheel", f"{d.flywheel_inertia:.4g} kg\u00b7m\u00b2"),
    ]
    for k in range(0, len(rows), 2):
        cells = []
        for off, (label, value) in zip((0.0, 0.5), rows[k : k + 2], strict=False):
            cells += [(off, label, {"color": C["grey"]}), (off + 0.18, value, {})]
        flow.row(cells, size=8.2)
    top = flow.y - 0.04
    height = min(top - 0.085, 0.09 * len(result.cams) + 0.08)
    ax = fig.add_axes((LEFT + 0.06, top - height, 0.94 - LEFT - 0.08, height))
    plot_timing_diagram(ax, result)


def _drive(fig, result: MachineResult) -> None:
    rows = 3 if result.clearances else 2
    height, gap, top = (0.215, 0.08, 0.9) if rows == 3 else (0.34, 0.09, 0.9)
    axes = [fig.add_axes((LEFT, top - (k + 1) * height - k * gap, 0.94 - LEFT - 0.02, height)) for k in range(rows)]
    plot_machine_torque(axes[0], result)
    plot_machine_energy(axes[1], result)
    if result.clearances:
        plot_clearances(axes[2], result)


DRAW = {"summary": _summary, "drive": _drive}


def write_machine_report(result: MachineResult, out_dir: str | Path, *, progress: Progress | None = None) -> Written:
    """The machine report into ``out_dir``: the PDF and one PNG per page (only under :func:`machine_output_names`)."""
    out_dir = output_dir(Path(out_dir), "report")
    pdf_name, png_names = machine_output_names(result.name)
    version = camdyn_version()
    meta = {
        "Title": f"camdyn machine review: {result.name}",
        "Subject": " | ".join(t for _, t in PAGES),
        "Creator": "camdyn",
        "Producer": f"camdyn {version} (matplotlib {matplotlib.__version__})",
        "CreationDate": None,
        "ModDate": None,
    }
    tick = counter(progress, f"{result.name}: report pages", len(PAGES))
    pngs = []
    with style(), PdfPages(out_dir / pdf_name, metadata=meta) as pdf:
        for i, ((slug, title), png) in enumerate(zip(PAGES, png_names, strict=True), start=1):
            fig = Figure(figsize=A4)
            _header(fig, result, title, i)
            DRAW[slug](fig, result)
            write_page(pdf, fig, out_dir / png, version)
            pngs.append(out_dir / png)
            tick()
    return Written(out_dir / pdf_name, tuple(pngs), tuple(t for _, t in PAGES), result.verdict)
