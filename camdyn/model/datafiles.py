"""The data files a case may name: a lift table (CSV) and a cam contour (CSV or DXF).

Each reader checks what it reads and refuses bad input with one :class:`InputError` naming the file as the
case file gives it, the line (CSV) or point (DXF), and what is wrong. Numbers only; no fitting here. A file is
read bounded: a regular file of at most :data:`~camdyn._core.files.MAX_FILE_BYTES` and :data:`MAX_ROWS` rows.
"""

from __future__ import annotations

import io
import itertools
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .._core.errors import InputError
from .._core.files import read_text_file
from .._core.kinds import FOLLOWER_KINDS, FollowerKind

MIN_POINTS = 8  # fewer cannot describe a revolution, let alone its acceleration
MAX_GAP_DEG = 45.0  # a revolution's table leaves no gap wider than an eighth of a turn
# Most rows (CSV) or points (DXF, arcs and splines sampled) a data file may give: 500 per degree, far finer than
# any measurement resolves, and still fitted in seconds. Files are also bounded in bytes (MAX_FILE_BYTES).
MAX_ROWS = 200_000


@dataclass(frozen=True)
class Samples:
    """Numbers read from a data file: ``values`` (n, k) in the file's columns, the line (CSV) or point number
    (DXF, from 1) of each row, and the rounding noise the written digits imply (0 where unknown)."""

    shown: str  # the file as the case file names it, for messages
    values: np.ndarray
    rows: np.ndarray
    row_word: str  # "line" or "point"
    rounding: float  # standard deviation of rounding to the finest digit written: step / sqrt(12)
    repeats: int = 0  # rows dropped for exactly repeating the row before them (exports rounded to few digits)

    def where(self, i: int) -> str:
        return f"{self.shown} {self.row_word} {int(self.rows[i])}"

    def without_repeats(self, same: np.ndarray) -> Samples:
        """These samples less the rows ``same`` marks (each a repeat of the row before it), counted in ``repeats``."""
        keep = ~same
        return replace(self, values=self.values[keep], rows=self.rows[keep], repeats=self.repeats + int(same.sum()))


def _bounded(shown: str, count: int, what: str) -> None:
    if count > MAX_ROWS:
        most = "the most a data file may give: thin it (every k-th row)"
        raise InputError(shown, f"has more than {MAX_ROWS} {what}, {most}")


def _decimals(text: str) -> int:
    """Digits a written number carries below the unit: 12.345 -> 3, 1.5e-3 -> 4, 120 -> 0."""
    mant, _, exp = text.lower().partition("e")
    frac = mant.partition(".")[2]
    try:
        return len(frac) - (int(exp) if exp else 0)
    except ValueError:
        return 0


def read_csv(path: Path, shown: str, columns: tuple[str, ...], hints: dict[str, str] | None = None) -> Samples:
    """The named columns of a CSV file with a header row (any order; other columns ignored; blank lines and
    lines starting with # skipped). ``hints``: a column name that may stand in the header instead, and what
    to say about it."""
    body = []  # (line number, text) of the header and the data rows; read line by line, so a file of blank lines
    for n, line in enumerate(io.StringIO(read_text_file(path, shown, "data file"), newline=None), start=1):
        if line.strip() and not line.lstrip().startswith("#"):  # or of millions of rows holds no list of them
            body.append((n, line))
            _bounded(shown, len(body) - 1, "data rows")
    if not body:
        raise InputError(shown, f"is empty: expected the header {','.join(columns)} and a row per point")
    n0, header = body[0]
    names = [h.strip().strip('"').strip() for h in header.split(",")]
    missing = [c for c in columns if c not in names]
    if missing:
        hint = "".join(f" ({text})" for name, text in (hints or {}).items() if name in names)
        raise InputError(f"{shown} line {n0}", f"expected the header {','.join(columns)}, got {header.strip()!r}{hint}")
    index = [names.index(c) for c in columns]
    values, rows, decimals = [], [], 0
    for n, line in body[1:]:
        cells = [c.strip() for c in line.split(",")]
        if any(cells[len(names) :]):  # a row past its header: a shifted or pasted row, whose columns are not named
            raise InputError(f"{shown} line {n}", f"{len(cells)} fields where the header names {len(names)}")
        row = []
        for col, i in zip(columns, index, strict=True):
            cell = cells[i] if i < len(cells) else ""
            if not cell:
                raise InputError(f"{shown} line {n}", f"{col} is missing")
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{shown} line {n}", f"{col} = {cell!r} is not a number") from None
            if not math.isfinite(v):
                raise InputError(f"{shown} line {n}", f"{col} = {cell} is not a finite number")
            decimals = max(decimals, _decimals(cell))
            row.append(v)
        values.append(row)
        rows.append(n)
    if len(values) < MIN_POINTS:
        raise InputError(shown, f"has {len(values)} data rows: at least {MIN_POINTS} are needed")
    return Samples(shown, np.array(values), np.array(rows), "line", 10.0**-decimals / math.sqrt(12.0))


def read_lift_table(path: Path, shown: str, kind: FollowerKind) -> Samples:
    """A lift table: theta_deg and the kind's lift column (lift_mm, swing_deg), one revolution, angles increasing and
    distinct, any spacing, no gap over :data:`MAX_GAP_DEG`. A last row at the first angle plus 360 closes the
    revolution (it counts as a second sample of the first angle). A row exactly repeating the one before it
    (angle and lift) is dropped and counted in ``repeats``; the same angle with another lift is refused."""
    column = kind.lift_column
    refused = {
        k.lift_column: f"{kind.a} follower's table gives {column}, not {k.lift_column}"
        for k in FOLLOWER_KINDS
        if k is not kind
    }
    table = read_csv(path, shown, ("theta_deg", column), refused)
    table = table.without_repeats(np.r_[False, np.all(np.diff(table.values, axis=0) == 0.0, axis=1)])
    theta = table.values[:, 0]
    step = np.diff(theta)
    bad = np.flatnonzero(step <= 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        what = (
            "repeats the previous row's angle"
            if step[i - 1] == 0.0
            else f"is below the previous row's {theta[i - 1]:g} deg: angles must increase"
        )
        raise InputError(table.where(i), f"theta_deg = {theta[i]:g} {what}")
    beyond = np.flatnonzero(theta - theta[0] > 360.0 + 1e-9)
    if beyond.size:
        i = int(beyond[0])
        raise InputError(
            table.where(i),
            f"theta_deg = {theta[i]:g} is more than one revolution after the first row's {theta[0]:g} deg",
        )
    gaps = np.append(step, theta[0] + 360.0 - theta[-1])
    j = int(np.argmax(gaps))
    if gaps[j] > MAX_GAP_DEG:
        a = theta[j]
        raise InputError(
            shown,
            f"does not span one revolution: no data from {a:g} to {a + gaps[j]:g} deg (a {gaps[j]:g} deg gap; at most "
            f"{MAX_GAP_DEG:g}); give the whole revolution, the dwells included",
        )
    return table


def read_contour(path: Path, shown: str) -> Samples:
    """A cam contour: points (x_mm, y_mm) in the cam frame, from a CSV (as ``camdyn profile -o cam.csv``
    writes it) or a DXF (a closed LWPOLYLINE, POLYLINE or SPLINE). A last point repeating the first closes the
    outline and is dropped; so is a point exactly repeating the one before it (counted in ``repeats``)."""
    if path.suffix.lower() == ".dxf":
        pts = _read_dxf(path, shown)
    elif path.suffix.lower() == ".csv":
        pts = read_csv(path, shown, ("x_mm", "y_mm"))
    else:
        raise InputError(
            shown, f"unknown contour format {path.suffix or '(no suffix)'!r}: use .csv (x_mm,y_mm) or .dxf"
        )
    size = float(np.ptp(pts.values, axis=0).max())
    # CMM and CAD exports repeat points once rounded to their digits: a point equal to the one before it adds nothing
    pts = pts.without_repeats(np.r_[False, np.hypot(*np.diff(pts.values, axis=0).T) <= 1e-12 * size])
    xy = pts.values
    if len(xy) > 1 and np.hypot(*(xy[-1] - xy[0])) <= 1e-9 * size:  # the closing point: the outline's convention
        pts = replace(pts, values=xy[:-1], rows=pts.rows[:-1])
        xy = pts.values
    if len(xy) < MIN_POINTS:
        raise InputError(shown, f"has {len(xy)} points: at least {MIN_POINTS} are needed for an outline")
    return pts


_SAGITTA_MM = 1e-4  # the chord of a drawn arc or spline lies this close to it: points on the curve itself


def _arc(p1: np.ndarray, p2: np.ndarray, bulge: float) -> np.ndarray:
    """Points strictly inside the arc from p1 to p2 of a polyline's bulge (tan of a quarter of its signed
    included angle), on the circle itself."""
    d = float(np.hypot(*(p2 - p1)))
    centre = 0.5 * (p1 + p2) + d * (1 - bulge**2) / (4 * bulge) * np.array([p1[1] - p2[1], p2[0] - p1[0]]) / d
    radius = d * (1 + bulge**2) / (4 * abs(bulge))
    sweep = 4 * math.atan(bulge)
    step = 2 * math.acos(max(1 - _SAGITTA_MM / radius, -1.0))
    # an arc flatter than the sagitta is its chord; no arc gives more points than a file may (the caller refuses)
    n = min(math.ceil(abs(sweep) / step), MAX_ROWS + 1) if step > 0.0 else 1
    t = np.arange(1, max(n, 1)) / max(n, 1)
    a = math.atan2(p1[1] - centre[1], p1[0] - centre[0]) + sweep * t
    return centre + radius * np.stack([np.cos(a), np.sin(a)], axis=1)


def _entity_points(e, shown: str) -> tuple[np.ndarray, bool]:
    """The points of a LWPOLYLINE, POLYLINE or SPLINE (arcs and splines sampled on the curve) and whether the
    polyline is flagged closed (its closing edge then joins the last point to the first); refused as soon as
    they exceed :data:`MAX_ROWS`."""
    if e.dxftype() == "SPLINE":
        pts = [(v.x, v.y) for v in itertools.islice(e.construction_tool().flattening(_SAGITTA_MM), MAX_ROWS + 1)]
        _bounded(shown, len(pts), "points (arcs and splines sampled)")
        return np.array(pts), False
    if e.dxftype() == "LWPOLYLINE":
        verts, closed = [(x, y, b) for x, y, b in e.get_points("xyb")], bool(e.closed)
    else:
        verts, closed = [(v.dxf.location.x, v.dxf.location.y, v.dxf.bulge) for v in e.vertices], bool(e.is_closed)
    out, count = [], 0
    for i in range(len(verts) if closed else len(verts) - 1):
        p1, p2, bulge = np.array(verts[i][:2]), np.array(verts[(i + 1) % len(verts)][:2]), verts[i][2]
        out.append(p1[None, :])
        if bulge and np.hypot(*(p2 - p1)) > 0:
            out.append(_arc(p1, p2, bulge))
        count += len(out[-1])
        _bounded(shown, count, "points (arcs and splines sampled)")
    if not closed:
        out.append(np.array([verts[-1][:2]]))
    return np.concatenate(out), closed


def _read_dxf(path: Path, shown: str) -> Samples:
    from ezdxf.enums import InsertUnits
    from ezdxf.filemanagement import readfile
    from ezdxf.lldxf.const import DXFError
    from ezdxf.units import conversion_factor

    read_text_file(path, shown, "data file")  # the file's own errors first: missing, a folder, unreadable
    try:
        doc = readfile(path)
    except (OSError, DXFError) as err:
        raise InputError(shown, f"not a readable DXF file: {err}") from None
    # coordinates are mm unless the drawing declares another length unit ($INSUNITS)
    scale = conversion_factor(InsertUnits(doc.units), InsertUnits.Millimeters) if doc.units else 1.0
    found = [e for e in doc.modelspace() if e.dxftype() in ("LWPOLYLINE", "POLYLINE", "SPLINE")]
    if not found:
        raise InputError(shown, "has no LWPOLYLINE, POLYLINE or SPLINE: draw the cam's outline as one closed curve")
    outlines = []
    for e in found:
        pts, flagged = _entity_points(e, shown)
        pts = pts * scale
        if len(pts) < 3 or not (flagged or np.hypot(*(pts[-1] - pts[0])) <= 1e-6 * float(np.ptp(pts, axis=0).max())):
            outlines.append((0.0, e, pts))
            continue
        x, y = pts.T
        outlines.append((abs(0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))), e, pts))
    area, e, pts = max(outlines, key=lambda t: t[0])  # the largest closed curve is the outline (not a bore)
    if area == 0.0:
        gap = float(np.hypot(*(pts[-1] - pts[0])))
        raise InputError(
            shown,
            f"the {e.dxftype()} (handle {e.dxf.handle}) is open: its ends are {gap:.4g} mm apart; the outline must be "
            "closed",
        )
    _bounded(shown, len(pts), "points (arcs and splines sampled)")
    return Samples(shown, pts, np.arange(1, len(pts) + 1), "point", 0.0)
