"""Pages to files: the PDF and a PNG per page of a review, deterministic and under names camdyn makes."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure
from PIL import Image, PngImagePlugin

from .._core.errors import CamdynError, InputError
from .._core.outputs import output_dir, refuse_foreign, safe_stem
from .._core.progress import Progress, counter, phase
from ..design.checks import run_check
from ..design.review import Review, design_review
from ..model.case import build_case, load_case
from ._data import ReportData
from ._layout import camdyn_version, header
from ._style import A4, DPI, plain_ticks, style
from .pages import PAGES, Page

if TYPE_CHECKING:
    from ..design.checks import CheckReport
    from ..model.case import Case
    from ..schema import CaseSpec


@dataclass(frozen=True)
class Written:
    """A written report: the PDF, the PNG per page, and the page titles (in order)."""

    pdf: Path
    pngs: tuple[Path, ...]
    titles: tuple[str, ...]
    verdict: str


def output_names(case_name: str, pages: list[Page]) -> tuple[str, list[str]]:
    """The PDF's name and the PNGs' names, ``<case>.pdf`` and ``<case>-<n>-<slug>.png``."""
    stem = safe_stem(case_name)
    return f"{stem}.pdf", [f"{stem}-{i}-{p.slug}.png" for i, p in enumerate(pages, start=1)]


def _own_pngs(out_dir: Path, stem: str) -> list[Path]:
    pat = re.compile(rf"^{re.escape(stem)}-\d+-[a-z][a-z-]*\.png$")  # not another case's: "lecture-1-1-summary.png"
    return sorted(p for p in out_dir.glob(f"{stem}-*.png") if pat.match(p.name))


def _refuse_foreign_pages(out_dir: Path, stem: str) -> None:
    """:func:`refuse_foreign` of what a report of ``stem`` writes or removes in ``out_dir``: its PDF and every page
    PNG under its names (a page that no longer applies is removed)."""
    if out_dir.is_dir():
        refuse_foreign([out_dir / f"{stem}.pdf", *_own_pngs(out_dir, stem)])


def render(review: Review, out_dir: Path, *, progress: Progress | None = None) -> Written:
    """Draw every page that applies to the review's case into ``out_dir``: the PDF and one PNG per page. Stale
    ``<case>-<n>-<page>.png`` pages of an earlier run are removed; nothing else is touched."""
    data = ReportData(review)
    out_dir = output_dir(out_dir, "report")
    pages = [p for p in PAGES if p.applies(data)]
    pdf_name, png_names = output_names(data.case.name, pages)
    stem = pdf_name[:-4]
    _refuse_foreign_pages(out_dir, stem)
    tick = counter(progress, f"{data.case.name}: report pages", len(pages))
    tick(0)  # said before the first page, which waits on the figure machinery
    version = camdyn_version()
    meta = {
        "Title": f"camdyn design review: {data.case.name}",
        "Subject": " | ".join(p.title for p in pages),
        "Creator": "camdyn",
        "Producer": f"camdyn {version} (matplotlib {matplotlib.__version__})",
        "CreationDate": None,
        "ModDate": None,
    }
    pngs = []
    with style(), PdfPages(out_dir / pdf_name, metadata=meta) as pdf:
        for i, page in enumerate(pages, start=1):
            fig = Figure(figsize=A4)
            header(fig, data, page.title, i, len(pages))
            page.draw(fig, data)
            png = out_dir / png_names[i - 1]
            write_page(pdf, fig, png, version)
            pngs.append(png)
            tick()
    for old in _own_pngs(out_dir, stem):
        if old.name not in png_names:
            old.unlink()
    return Written(out_dir / pdf_name, tuple(pngs), tuple(p.title for p in pages), data.check.verdict)


def write_page(pdf: PdfPages, fig: Figure, png: Path, version: str) -> None:
    """A drawn page into ``pdf`` and as the PNG ``png``, its tick labels as plain text (:func:`plain_ticks`)."""
    plain_ticks(fig)
    pdf.savefig(fig)
    _save_png(fig, png, version)


def _save_png(fig: Figure, path: Path, version: str) -> None:
    """The page as a full-colour RGB PNG (the PDF's colours exactly: no palette), without the alpha channel: drawn
    at :data:`DPI` into Agg's buffer and written once by PIL at zlib's default level (matplotlib's own PNG, read
    back, and PIL's ``optimize`` took half of a report's writing for files 2-5 % smaller)."""
    dpi = fig.dpi
    fig.dpi = DPI
    try:
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        rgb = Image.fromarray(np.asarray(canvas.buffer_rgba())).convert("RGB")
    finally:
        fig.dpi = dpi
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"camdyn {version}")
    rgb.save(path, format="PNG", pnginfo=info)


def write_report(
    case: Case,
    out_dir: str | Path,
    *,
    check: CheckReport | None = None,
    speed_rpm: float | None = None,
    progress: Progress | None = None,
) -> Written:
    """Check ``case`` (unless ``check``, a :class:`camdyn.design.checks.CheckReport`, is given), review it and
    write its report."""
    if check is None:
        with phase(progress, f"{case.name}: check"):  # cold, the programs compile: the longest silence of a report
            check = run_check(case, speed_rpm)
    return render(design_review(case, check, progress=progress), Path(out_dir), progress=progress)


def _named(path, err: CamdynError) -> CamdynError:
    """The error with the case file's name in front of where it happened."""
    return type(err)(f"{path}: {err.where}" if err.where else str(path), err.message)


def report_cases(
    paths: list[str | Path],
    out_dir: str | Path,
    *,
    speed_rpm: float | None = None,
    specs: list[CaseSpec] | None = None,
    progress: Progress | None = None,
) -> list[Written]:
    """Load, check and report every case file in ``paths`` (bad input stops before any work, naming the file).
    ``specs``: the files' validated :class:`camdyn.schema.CaseSpec`, where the caller has read them already."""
    output_dir(out_dir, "report")
    cases = []
    for i, p in enumerate(paths):
        try:
            cases.append(load_case(p) if specs is None else build_case(specs[i], source=Path(p)))
        except CamdynError as err:
            raise _named(p, err) from None
    stems: dict[str, str] = {}
    for p, c in zip(paths, cases, strict=True):
        stem = safe_stem(c.name)
        if stem in stems:
            raise InputError(
                str(p),
                f"case name {c.name!r} is also the name of {stems[stem]}: their reports would overwrite each other",
            )
        stems[stem] = str(p)
        try:  # before any case is checked: not after minutes of work
            _refuse_foreign_pages(Path(out_dir), stem)
        except CamdynError as err:
            raise _named(p, err) from None
    out = []
    # several cases: a phase over them, said started before the first (one case: its own phases say it all)
    tick = counter(progress if len(cases) > 1 else None, "cases", len(cases))
    tick(0)
    for p, case in zip(paths, cases, strict=True):
        try:
            out.append(write_report(case, out_dir, speed_rpm=speed_rpm, progress=progress))
        except CamdynError as err:
            raise _named(p, err) from None
        tick()
    return out
