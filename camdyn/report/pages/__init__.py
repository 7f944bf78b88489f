"""The report's pages, in order: :data:`PAGES` is the one list of them (adding a page is adding an entry)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from matplotlib.figure import Figure

from ..._core.results import Unavailable
from .._data import ReportData
from .cam import draw_cam
from .dynamics import draw_dynamics
from .groove import draw_conjugate, draw_crossovers, draw_groove
from .manufacturing import draw_manufacturing
from .mechanism import draw_mechanism
from .optimization import draw_optimization
from .parts import draw_parts
from .springs import draw_springs
from .summary import draw_summary
from .svaj import draw_svaj
from .tolerances import draw_tolerances
from .valvetrain import draw_valvetrain


def _groove(data: ReportData) -> bool:
    """A groove cam: its walls and crossovers in place of the cam, dynamics and spring sizing pages."""
    return data.check.closure is not None and data.case.follower.closure == "groove"


def _conjugate(data: ReportData) -> bool:
    """Conjugate cams: both cams and each cam's force in place of the cam, dynamics and spring sizing pages."""
    return data.check.closure is not None and data.case.follower.closure == "conjugate"


def _form_closed(data: ReportData) -> bool:
    return data.check.closure is not None


@dataclass(frozen=True)
class Page:
    """One report page: ``draw(fig, data)`` fills an A4 figure; ``applies(data)`` says whether the case has it."""

    slug: str  # file name part: <case>-<n>-<slug>.png
    title: str
    draw: Callable[[Figure, ReportData], None]
    applies: Callable[[ReportData], bool] = field(default=lambda data: True)


PAGES: list[Page] = [
    Page("summary", "Summary", draw_summary),
    Page("svaj", "Follower motion (SVAJ)", draw_svaj),
    Page("cam", "Cam profile", draw_cam, lambda data: data.check.geometry is not None and not _form_closed(data)),
    Page("groove", "Groove cam: both walls", draw_groove, _groove),
    Page("conjugate", "Conjugate cams: both cams", draw_conjugate, _conjugate),
    Page("dynamics", "Dynamics", draw_dynamics, lambda data: not _form_closed(data)),
    Page("crossovers", "Dynamics: crossovers and impacts", draw_crossovers, _form_closed),
    Page(
        "valvetrain",
        "Valvetrain: valve lift, seating, float and bounce",
        draw_valvetrain,
        lambda data: data.check.valvetrain is not None,
    ),
    Page("mechanism", "Mechanism and path", draw_mechanism, lambda data: data.case.synthesis is not None),
    Page(
        "optimization",
        "Optimization",
        draw_optimization,
        lambda data: data.review.original is not None and not isinstance(data.review.original, Unavailable),
    ),
    Page("parts", "Drive, contact and spring", draw_parts),
    Page("springs", "Spring sizing", draw_springs, lambda data: not _form_closed(data)),
    Page("manufacturing", "Segments and manufacturing", draw_manufacturing),
    Page("tolerances", "Tolerances", draw_tolerances, lambda data: data.review.tolerance is not None),
]

__all__ = [
    "PAGES",
    "Page",
    "draw_cam",
    "draw_conjugate",
    "draw_crossovers",
    "draw_groove",
    "draw_dynamics",
    "draw_manufacturing",
    "draw_mechanism",
    "draw_optimization",
    "draw_parts",
    "draw_springs",
    "draw_summary",
    "draw_svaj",
    "draw_tolerances",
    "draw_valvetrain",
]
