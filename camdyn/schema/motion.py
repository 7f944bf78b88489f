"""The ``[motion]`` table: contiguous segments of named laws covering one cam revolution."""

from __future__ import annotations

from difflib import get_close_matches

from pydantic import Field

from .._core.units import MAX_LENGTH_MM
from ._base import Real, Table

MIN_SEGMENT_DEG = 0.01  # a move over less cam angle than this cannot be cut, nor followed

# the named motion laws (camdyn.model.motion implements each)
LAW_NAMES: tuple[str, ...] = (
    "dwell",
    "constant-velocity",
    "constant-acceleration",
    "harmonic",
    "cycloidal",
    "polynomial-345",
    "polynomial-4567",
    "modified-trapezoid",
    "modified-sine",
)


class SegmentSpec(Table):
    """One motion segment: ``law`` up to ``end`` (deg), rising by ``lift`` (mm; deg of arm swing for an
    oscillating follower; negative for a return)."""

    law: str = Field(description=f"motion law: {', '.join(LAW_NAMES)}")
    end: Real = Field(description="cam angle where the segment ends, deg (the next starts there; the last ends at 360)")
    lift: Real = Field(default=0.0, ge=-MAX_LENGTH_MM, le=MAX_LENGTH_MM, description="rise of the segment, mm (deg of arm swing for an oscillating follower); negative for a return, 0 for a dwell")


class MotionSpec(Table):
    """The ``[motion]`` table."""

    segments: list[SegmentSpec] = Field(min_length=1, description="the segments in order, from 0 deg")


def check_segments(segments: list[SegmentSpec], lift_unit: str = "mm", key: str = "segments") -> None:
    """Raise ``ValueError("<key>[i].<field>: message")`` unless the segments form a motion program: known laws,
    increasing ends up to exactly 360 deg, dwells that do not lift and moves that do, never below zero lift,
    net lift 0. ``lift_unit`` ("mm" or "deg") is the unit the lifts were given in, for the messages."""
    start, base = 0.0, 0.0
    lu = lift_unit
    for i, seg in enumerate(segments):
        where = f"{key}[{i}]"
        if seg.law not in LAW_NAMES:
            hint = get_close_matches(seg.law, LAW_NAMES, n=1)
            raise ValueError(
                f"{where}.law: unknown law {seg.law!r}" + (f" (did you mean {hint[0]!r}?)" if hint else "") + f"; valid laws: {', '.join(LAW_NAMES)}"
            )
        end, lift = seg.end, seg.lift
        if not end > start:
            what = "overlaps the previous segment" if end < start else "has zero length"
            raise ValueError(f"{where}.end: segment ends at {end:g} deg, {what} (starts at {start:g} deg)")
        if seg.law != "dwell" and end - start < MIN_SEGMENT_DEG:
            raise ValueError(f"{where}.end: a {seg.law} segment over {end - start:.3g} deg is shorter than {MIN_SEGMENT_DEG:g} deg: no cam can be cut to it")
        if end > 360.0 + 1e-9:
            raise ValueError(f"{where}.end: segment ends at {end:g} deg, past 360 deg")
        if seg.law == "dwell" and lift != 0.0:
            raise ValueError(f"{where}.lift: a dwell cannot lift (got lift = {lift:g} {lu})")
        if seg.law != "dwell" and lift == 0.0:
            raise ValueError(f"{where}.lift: a {seg.law} segment needs a non-zero lift, {lu}")
        if base + lift < -1e-9:
            raise ValueError(f"{where}.lift: the follower goes below zero lift at {end:g} deg (lift {base + lift:g} {lu})")
        start, base = end, base + lift
    if abs(start - 360.0) > 1e-9:
        raise ValueError(f"{key}[{len(segments) - 1}].end: the last segment ends at {start:g} deg, not 360")
    if abs(base) > 1e-9:
        raise ValueError(f"{key}: the program does not close: net lift is {base:g} {lu}, must be 0")
