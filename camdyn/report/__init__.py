"""Design-review reports: one A4 PDF per case and one PNG per page, made to be looked at.

``camdyn report CASE.toml ... -o DIR`` and ``camdyn check CASE.toml --report DIR`` write ``DIR/<case>.pdf`` and
``DIR/<case>-<n>-<page>.png``. The pages are the entries of :data:`PAGES`, in order; a page is a :class:`Page`
(file-name slug, title, a function drawing it on an A4 figure from a :class:`ReportData`, and a predicate saying
whether it applies to a case), so adding a page is adding one entry. What the pages draw is a
:class:`camdyn.design.review.Review` (:func:`camdyn.design.review.design_review`: the check and what must be
computed beyond it); the figures on them are :mod:`camdyn.plot`'s.

Files are written deterministically (no timestamps in the PDF; the same case gives the same bytes) and only
under names camdyn itself produces: a report overwrites ``<case>.pdf`` and ``<case>-<n>-<page>.png`` and removes
stale ``<case>-<n>-<page>.png`` pages from an earlier run, and touches nothing else.

Modules: :mod:`._style` (page size, resolution, style, palette), :mod:`._layout` (header, text flow, number
formats), :mod:`._data` (the review as pages see it), :mod:`.pages` (one module per page), :mod:`._render`
(files).
"""

from ._data import ReportData
from ._render import Written, output_names, render, report_cases, write_report
from ._style import A4, DPI, STYLE
from .pages import PAGES, Page

__all__ = [
    "A4",
    "DPI",
    "PAGES",
    "STYLE",
    "Page",
    "ReportData",
    "Written",
    "output_names",
    "render",
    "report_cases",
    "write_report",
]
