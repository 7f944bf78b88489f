"""The ``[drive]`` table: what the camshaft drive must allow."""

from __future__ import annotations

from pydantic import Field

from .._core.units import DEFAULT_SPEED_FLUCTUATION
from ._base import Real, Table


class DriveSpec(Table):
    """The ``[drive]`` table."""

    speed_fluctuation: Real = Field(
        default=DEFAULT_SPEED_FLUCTUATION,
        gt=0,
        lt=1,
        description="coefficient of speed fluctuation k_s = (w_max - w_min) / w_mean the flywheel is sized for",
    )
