"""What ``optimize`` judges a valvetrain's answer by: the two-mass model's facts of ``check`` before and after
(:class:`ValveFacts`), why an answer is worse on any of them, and the seating rows that hold its closing speed."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from ..._core.results import finite_or_none
from ..._core.units import RPM
from ...model.motion import evaluate
from ..checks import CheckReport
from ._objectives import BETTER
from ._rows import Rows

TIMING_DEG = 0.5  # a valvetrain's opening or closing (at 0.05 mm of valve lift) may move this much at the case speed
SEAT_WINDOW_DEG = 3.0  # the surrogate holds the valve's closing speed this close to where it seats
SEATING_RTOL = 1e-3  # its seating velocity may differ by this share: the ramp sets it, the integrator's noise moves it


def _shown(label: str, fmt: str):
    """A field of :class:`ValveFacts` with how ``optimize``'s before/after table shows it."""
    return field(metadata={"label": label, "format": fmt})


@dataclass(frozen=True)
class ValveFacts:
    """A valvetrain as ``check``'s two-mass model judges it: None where a speed is not found up to the search's top
    or an angle is never reached."""

    peak_cam_lift_mm: float  # the cam's peak lift at the follower, mm (not shown)
    float_speed_rpm: float | None = _shown("valve float speed, two-mass (rpm)", ".1f")
    bounce_speed_rpm: float | None = _shown("valve bounce speed, two-mass (rpm)", ".1f")
    seating_velocity_m_per_s: float | None = _shown("seating velocity (m/s)", ".4g")
    opening_deg: float | None = _shown("opening at 0.05 mm (deg)", ".2f")  # at the case speed
    closing_deg: float | None = _shown("closing at 0.05 mm (deg)", ".2f")
    max_valve_lift_mm: float = _shown("max valve lift (mm)", ".4g")

    @classmethod
    def of(cls, check: CheckReport) -> ValveFacts:
        vt = check.valvetrain
        assert vt is not None  # a valvetrain's check
        opening, closing = vt.timing_deg
        return cls(
            float(np.max(vt.response.cam_lift)),
            finite_or_none(vt.float_speed_rpm),
            finite_or_none(vt.bounce_speed_rpm),
            finite_or_none(vt.seating_velocity),
            finite_or_none(opening),
            finite_or_none(closing),
            vt.response.max_valve_lift_mm,
        )

    def json(self) -> dict:
        return asdict(self)


def shown_or_none(x: float | None, fmt: str) -> str:
    """``x`` as ``fmt``; "none" for a speed none was found up to the search's top (or an angle never reached)."""
    return "none" if x is None else format(x, fmt)


def valve_sentence(b: ValveFacts, a: ValveFacts) -> str:
    """The written case's header line of a valvetrain's two-mass facts, before -> after."""
    rows = (
        ("float speed", "float_speed_rpm", ".1f", " rpm"),
        ("bounce speed", "bounce_speed_rpm", ".1f", " rpm"),
        ("seating velocity", "seating_velocity_m_per_s", ".4g", " m/s"),
        ("opening", "opening_deg", ".2f", " deg"),
        ("closing", "closing_deg", ".2f", " deg"),
    )
    said = (
        f"{label} {shown_or_none(getattr(b, key), fmt)} -> {shown_or_none(getattr(a, key), fmt)}{unit}"
        for label, key, fmt, unit in rows
    )
    return "Two-mass valvetrain: " + ", ".join(said) + "."


def valve_refusals(b: ValveFacts, a: ValveFacts) -> list[str]:
    """Why a valvetrain's answer must not be written: its float speed no higher, its bounce speed lower, its
    seating velocity higher, its timing moved or its peak lift changed."""
    inf = lambda x: math.inf if x is None else x  # noqa: E731  (None: no float or bounce up to the search's top)
    out = []
    fb, fa = inf(b.float_speed_rpm), inf(a.float_speed_rpm)
    if not fa > fb * (1.0 + BETTER):
        out.append(f"no better on jump-speed: the float speed would go {fb:.1f} -> {fa:.1f} rpm")
    if inf(a.bounce_speed_rpm) < inf(b.bounce_speed_rpm):
        out.append(f"the bounce speed would fall {inf(b.bounce_speed_rpm):.1f} -> {a.bounce_speed_rpm:.1f} rpm")
    vb, va = b.seating_velocity_m_per_s, a.seating_velocity_m_per_s
    if vb is not None and (va is None or va > vb * (1.0 + SEATING_RTOL)):
        out.append(f"the seating velocity would rise {vb:.4g} -> {shown_or_none(va, '.4g')} m/s")
    for key in ("opening_deg", "closing_deg"):
        was, now = getattr(b, key), getattr(a, key)
        if was is None or now is None or abs(now - was) > TIMING_DEG:
            shown = (shown_or_none(v, ".2f") for v in (was, now))
            out.append(f"the valve's {key[:-4]} at 0.05 mm would move {' -> '.join(shown)} deg")
    if abs(a.peak_cam_lift_mm - b.peak_cam_lift_mm) > 1e-9 * b.peak_cam_lift_mm:
        out.append(f"the peak lift would change {b.peak_cam_lift_mm:.6g} -> {a.peak_cam_lift_mm:.6g} mm")
    return out


def seating_rows(rows: Rows, check: CheckReport, speed_rpm: float | None) -> tuple | None:
    """What holds a valvetrain's seating velocity at the case speed (:attr:`Rows.seating`): its valve's speed
    toward the seat in the surrogate, at every grid angle within :data:`SEAT_WINDOW_DEG` of where the two-mass
    model seats it, at most what the case's own flanks give there; None for a rigid train (the ramp sets it)."""
    vt = rows.case.valvetrain
    assert vt is not None and check.valvetrain is not None  # a valvetrain's rows and check
    if rows.case.model.rigid or not math.isfinite(check.valvetrain.response.seating_deg):
        return None
    omega = float(speed_rpm if speed_rpm is not None else rows.case.speed_rpm) * RPM
    deg = np.degrees(rows.space.theta)
    near = np.abs((deg - check.valvetrain.response.seating_deg + 180.0) % 360.0 - 180.0) <= SEAT_WINDOW_DEG
    # as many angles for every case (a seat between two grid angles has one fewer within the window): the stored
    # programs of the rows are shared by the valvetrains of one structure; a repeated angle repeats a row
    width = math.floor(2.0 * SEAT_WINDOW_DEG / (deg[1] - deg[0])) + 1  # the most a window of the grid holds
    idx = np.nonzero(near)[0]
    idx = np.pad(idx, (0, width - idx.size), mode="edge")
    s = np.asarray(evaluate(rows.case.motion, rows.space.theta))[:, None]  # the case's own flanks, not their fit
    own = replace(rows.space, offset=s[:, 0], matrix=np.zeros((4, s.shape[-1], 1)), z0=np.zeros(1))
    probe = replace(rows, space=own, seating=(omega, float(vt.ratio), idx, 1.0))
    return omega, float(vt.ratio), idx, float(np.max(np.asarray(probe.closing_speed(np.zeros(1)))))
