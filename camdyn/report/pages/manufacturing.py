"""The manufacturing page: the title block (case file and its SHA-256, camdyn version), the motion segment by
segment (law, angles, lift, peak velocity, acceleration and jerk and where, continuity at each boundary) and
what a shop needs to make the cam (radii, roller, offset, zero reference, profile tolerance, file formats)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ..._core.units import DEFAULT_PROFILE_TOLERANCE_MM
from ...export import FORMATS
from ...plot import svaj_quantities
from .._data import ReportData
from .._layout import Flow, camdyn_version, fmt
from .._style import C


def title_block(data: ReportData) -> list[tuple[str, str]]:
    """(label, value) of the title block: what was reviewed, exactly."""
    case = data.case
    return [
        ("case", case.name),
        ("case file", case.source.name if case.source is not None else "(built in memory)"),
        ("SHA-256", data.case_sha256 or "(no file)"),
        ("camdyn", camdyn_version()),
        ("verdict", f"{data.check.verdict.upper()} at {data.check.speed_rpm:g} rpm"),
    ]


def segment_rows(data: ReportData) -> list[dict]:
    """One row per motion segment (a table, contour or path motion: one row for the whole revolution): law,
    start and end (deg), lift, the largest |v|, |a|, |j| and where (display units per rad^k of cam angle), and the
    continuity at its end boundary."""
    samples = data.review.motion
    th, vals = samples.theta_deg, samples.values * data.to_display
    segs = getattr(data.case.motion, "segments", ())
    spans = [(seg.law, float(seg.start), float(seg.end), float(seg.lift) * data.to_display) for seg in segs]
    if not spans:  # a table, contour or path: one row per stretch between its breaks (the whole turn without)
        law = data.case.motion_source
        b = list(data.breaks_deg) or [0.0]
        ends = b[1:] + [b[0] + 360.0]
        s_at = lambda deg: float(np.interp(deg % 360.0, th, vals[0]))  # noqa: E731
        spans = [(law, a, e, s_at(e) - s_at(a)) for a, e in zip(b, ends, strict=True)]
    jumps = data.jumps
    rows = []
    for law, a, b, lift in spans:
        # the samples just inside each boundary are the segment's own; a stretch may wrap through 0
        inside = (th > a) & (th < b) if b <= 360.0 else (th > a) | (th < b - 360.0)
        row = {"law": law, "start_deg": a, "end_deg": b, "lift": lift}
        for order, key in ((1, "v"), (2, "a"), (3, "j")):
            i = np.flatnonzero(inside)[int(np.argmax(np.abs(vals[order][inside])))]
            row[key], row[f"{key}_deg"] = float(vals[order][i]), float(th[i])
            if row[key] == 0.0:
                row[f"{key}_deg"] = float("nan")  # a dwell: nowhere
        end = b % 360.0
        at_end = {o for d, o, _ in jumps if abs(d - end) < 1e-6}
        row["continuity"] = "velocity jumps" if 1 in at_end else ("acceleration jumps" if 2 in at_end else "C2")
        rows.append(row)
    return rows


def manufacturing_rows(data: ReportData) -> list[tuple[str, str]]:
    """(label, value) of what a shop needs to make the cam."""
    case, geo = data.case, data.check.geometry
    f = case.follower
    rows = []
    closure = data.check.closure
    conj = closure.conjugate if closure is not None and closure.loads is not None else None
    walls = closure.groove if closure is not None and conj is None else None
    if (
        conj is not None
    ):  # the second cam beside the primary (its contour: its roller + backlash inside its pitch curve)
        r2 = np.hypot(*conj.contour)
        rows.append(
            (
                "conjugate cam",
                f"radius {float(r2.min()):.4f} to {float(r2.max()):.4f} mm from the cam centre; its roller "
                f"{conj.roller_radius_mm:g} mm",
            )
        )
    if walls is not None:  # a groove cam: the slot and its walls, not a contour
        r_in, r_out = np.hypot(*walls.inner), np.hypot(*walls.outer)
        rows += [
            (
                "groove",
                f"slot {2 * walls.wall_offset_mm:.4f} mm wide (roller diameter + backlash {walls.backlash_mm:g} mm), "
                f"each wall {walls.wall_offset_mm:.4f} mm from the pitch curve",
            ),
            ("inner wall", f"radius {float(r_in.min()):.4f} to {float(r_in.max()):.4f} mm from the cam centre"),
            ("outer wall", f"radius {float(r_out.min()):.4f} to {float(r_out.max()):.4f} mm from the cam centre"),
        ]
    if geo is not None:
        radius = np.hypot(*geo.contour)
        roller = float(f.roller_radius or 0.0)
        base = float(radius.min())
        rows += [
            (
                "base radius",
                f"{base:.4f} mm (least contour radius" + (": b/2 outside the inner wall)" if walls else ")"),
            ),
            (
                "prime radius",
                f"{base + roller:.4f} mm" + (" (base + roller)" if roller else " (flat face: the base radius)"),
            ),
            (
                "largest radius",
                f"{float(radius.max()):.4f} mm at cam angle {float(geo.theta_deg[int(np.argmax(radius))]):.1f}\u00b0",
            ),
        ]
        rows.append(
            (
                "follower",
                f"{f.type}"
                + (f", roller radius {roller:g} mm" if roller else "")
                + (f", face width {f.face_width:g} mm" if getattr(f, "face_width", None) else ""),
            )
        )
        if f.translating:
            rows.append(("offset", f"{float(f.offset):g} mm"))
        else:
            rows.append(
                (
                    "pivot",
                    f"{fmt(f.pivot_distance)} mm from the cam centre at {float(f.pivot_angle):g}\u00b0"
                    + (f", arm {fmt(f.arm_length)} mm" if f.arm_length else ""),
                )
            )
        start = (
            "the start of the first segment (lift 0)"
            if getattr(case.motion, "segments", ())
            else f"the {case.motion_source}'s angle 0"
        )
        rows.append(
            (
                "zero reference",
                f"cam angle 0 = {start}; the contour is given in the cam frame at cam angle 0, the cam turning "
                f"{f.rotation}",
            )
        )
    else:
        rows.append(("cam", "no cam follower in this case: nothing to cut"))
    tol = (
        f"camdyn profile writes the contour within a chord tolerance of {DEFAULT_PROFILE_TOLERANCE_MM:g} mm "
        "(--tolerance MM)"
    )
    spec_tol = case.spec.tolerances
    pe = getattr(spec_tol, "profile_error", None) if spec_tol is not None else None
    if pe is not None:
        tol += f"; the tolerance study takes a profile error of {pe} RMS"
    formats = ", ".join(s.lstrip(".").upper() for s in FORMATS) + " (camdyn profile -o cam.<format>)"
    if conj is not None:
        formats = (
            "DXF (layers CAM_PRIMARY, CAM_CONJUGATE), CSV (an outline column), SVG (a polygon per cam): camdyn "
            "profile -o cam.<format>; the conjugate cam's cutter path, grinder table and solid are not built yet"
        )
    if walls is not None:
        formats = (
            "DXF (a layer per wall), CSV (an outline column), SVG (a polygon per wall): camdyn profile -o "
            "cam.<format>; a groove's cutter path, grinder table and solid are not built yet"
        )
    rows += [("profile tolerance", tol), ("file formats", formats)]
    return rows


def draw_manufacturing(fig: Figure, data: ReportData) -> None:
    flow = Flow(fig, 0.93)
    flow.heading("Title block")
    for k, v in title_block(data):
        flow.row(
            [
                (0.0, k, {"color": C["grey"]}),
                (0.16, v, {"family": "DejaVu Sans Mono" if k == "SHA-256" else "DejaVu Sans"}),
            ],
            size=8.2,
        )
    _segments(flow, data)
    flow.heading("Manufacturing")
    for k, v in manufacturing_rows(data):
        flow.row([(0.0, k, {"color": C["grey"]})], size=8.2)
        flow.y += flow.h(8.2)
        flow.para(v, size=8.2, width=100, indent=0.16 * (flow.right - flow.left))


def _segments(flow: Flow, data: ReportData) -> None:
    names = svaj_quantities(data.case.motion.unit)
    u = [names[k][1] for k in range(4)]
    flow.heading("Motion, segment by segment")
    flow.para(
        f"Lift in {u[0]}; peak velocity, acceleration and jerk as |largest| with its sign, per radian of cam angle "
        f"({u[1]}, {u[2]}, {u[3]}), and the cam angle where it is; at the segment's end, C2: velocity and acceleration "
        "continuous, or which of them jumps (infinite acceleration or jerk).",
        size=7.5,
        color=C["grey"],
    )
    cols = [
        (0.0, "law", "left"),
        (0.15, "from\u2013to", "left"),
        (0.32, "lift", "right"),
        (0.5, "peak v (at)", "right"),
        (0.68, "peak a (at)", "right"),
        (0.86, "peak j (at)", "right"),
        (0.88, "at the end", "left"),
    ]
    flow.row([(x, t, {"weight": "bold", "color": C["grey"], "ha": ha}) for x, t, ha in cols], size=7.8)
    rows = segment_rows(data)
    for r in rows[:40]:
        ok = r["continuity"] == "C2"
        at = {k: "0" if r[k] == 0.0 else f"{r[k]:+.4g} ({r[k + '_deg']:.1f}\u00b0)" for k in ("v", "a", "j")}
        flow.row(
            [
                (0.0, r["law"], {}),
                (
                    0.15,
                    f"{r['start_deg']:.4g}\u2013"
                    f"{r['end_deg'] - 360.0 if r['end_deg'] > 360.0 else r['end_deg']:.4g}\u00b0",
                    {},
                ),
                (0.32, f"{r['lift']:+.4g}", {"ha": "right"}),
                (0.5, at["v"], {"ha": "right"}),
                (0.68, at["a"], {"ha": "right"}),
                (0.86, at["j"], {"ha": "right"}),
                (
                    0.88,
                    r["continuity"].replace("acceleration", "a").replace("velocity", "v"),
                    {"color": C["ok"] if ok else C["fail"]},
                ),
            ],
            size=7.6,
        )
    if len(rows) > 40:
        flow.para(f"\u2026 {len(rows) - 40} more segments: camdyn table writes every angle", size=7.5, color=C["grey"])
