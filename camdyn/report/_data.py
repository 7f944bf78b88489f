"""What the pages draw: a :class:`~camdyn.design.review.Review` and the derivations that are for display only
(units, the motion's jumps in display units). Nothing here computes physics: it gathers."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

from .._core.units import RPM
from ..design.review import Review
from ..plot.motion import display_scale, display_unit

if TYPE_CHECKING:
    from ..design.checks import CheckReport
    from ..model.case import Case


def file_sha256(path: Path | None) -> str | None:
    """The SHA-256 (hex) of a file the user gave (a case or machine file), for the pages' feet: which file they
    review; None where there is none (built in memory)."""
    if path is None or not Path(path).is_file():
        return None
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@dataclass(frozen=True)
class ReportData:
    """A review as the pages see it."""

    review: Review

    @property
    def case(self) -> Case:
        return self.review.case

    @property
    def check(self) -> CheckReport:
        return self.review.check

    @cached_property
    def case_sha256(self) -> str | None:
        """The SHA-256 (hex) of the case file as it was read; None for a case built in memory."""
        return file_sha256(self.case.source)

    @property
    def oscillating(self) -> bool:
        return self.case.oscillating

    @property
    def omega(self) -> float:
        """The cam speed of the review, rad/s."""
        return self.check.speed_rpm * RPM

    @property
    def to_display(self) -> float:
        """Motion unit -> display unit: mm stays mm, an arm swing in rad is shown in degrees."""
        return display_scale(self.case.motion.unit)

    @property
    def unit(self) -> str:
        return display_unit(self.case.motion.unit)

    @property
    def breaks_deg(self) -> tuple[float, ...]:
        """The segment boundaries (deg) of a segment motion (not the pieces a B-spline or polynomial is made of
        inside a segment); a table's or path's breaks as the motion has them."""
        segs = getattr(self.case.motion, "segments", ())
        if segs:
            return tuple(sorted({float(seg.end) % 360.0 for seg in segs}))
        return tuple(self.case.motion.breaks_deg)

    @cached_property
    def jumps(self) -> list[tuple[float, int, float]]:
        """(angle deg, order 1 or 2, jump in display units) of the velocity and acceleration jumps at the
        boundaries, by angle (:meth:`camdyn.model.motion.Motion.derivative_jumps`)."""
        k = self.to_display
        return sorted((deg, order, jump * k) for deg, order, jump in self.case.motion.derivative_jumps())
