"""Export of a cam contour for manufacturing: DXF (ezdxf), CSV or SVG, within a chord tolerance.

The curve is given either as a callable ``u -> (2, m)`` mm on u in [0, 1] (closed: u = 0 and u = 1 are the same
point), e.g. :meth:`camdyn.model.geometry.CamGeometry.contour_fn`, which evaluates the exact contour; or as a dense
closed sample ``(2, n)`` mm (first point not repeated), which is taken to be the periodic cubic spline through
the samples (chord-length parametrised), so its points must be dense enough for that spline to be the curve.
The curve is then resampled adaptively: an interval is halved until the curve deviates from its chord by at
most ``tolerance`` mm, so the written polyline is within the tolerance of the curve everywhere.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from .._core.errors import InputError, NumericalError
from .._core.limits import check_chord_tolerance
from .._core.outputs import output_file
from .._core.units import MM_PER_INCH

# what ``camdyn profile`` writes, by suffix (.csv also a grinder's table; .step and .stl need camdyn[cad])
FORMATS = (".dxf", ".csv", ".svg", ".nc", ".step", ".stl")
OUTLINE_FORMATS = (".dxf", ".csv", ".svg")  # the outline itself (write_profile)
_PROBES = 15  # interior samples per interval for its chord deviation; odd, so the midpoint is one
_START = 64  # initial equal intervals in u
_MAX_POINTS = 200_000


def _spline(xy: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """The closed periodic cubic spline through a dense sample (2, n), as u in [0, 1] -> (2, m)."""
    from scipy.interpolate import CubicSpline

    closed = np.concatenate([xy, xy[:, :1]], axis=1)
    chord = np.hypot(*np.diff(closed, axis=1))
    if np.any(chord == 0.0):
        raise InputError("contour", "repeated consecutive points: give each point once, without closing the loop")
    knots = np.concatenate([[0.0], np.cumsum(chord)])
    sp = CubicSpline(knots / knots[-1], closed, axis=1, bc_type="periodic")
    return lambda u: sp(np.mod(u, 1.0))


def _chord_deviation(a: np.ndarray, b: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Largest distance of pts (k, m, 2) from the segments a-b (k, 2), per segment."""
    d = b - a
    L2 = np.maximum(np.sum(d * d, axis=-1), 1e-300)[:, None]
    w = np.clip(np.sum((pts - a[:, None]) * d[:, None], axis=-1) / L2, 0.0, 1.0)
    return np.max(np.linalg.norm(pts - (a[:, None] + w[..., None] * d[:, None]), axis=-1), axis=1)


def resample_u(curve: Callable[[np.ndarray], np.ndarray], tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """Parameters u (k,) and vertices (2, k) of a closed polyline within ``tolerance`` mm of the closed curve
    u -> (2, m)."""
    u = np.linspace(0.0, 1.0, _START + 1)
    frac = np.arange(1, _PROBES + 1) / (_PROBES + 1)
    while True:
        ends = np.asarray(curve(u)).T  # (k+1, 2)
        probe_u = u[:-1, None] + np.diff(u)[:, None] * frac
        probes = np.asarray(curve(probe_u.ravel())).T.reshape(len(u) - 1, _PROBES, 2)
        bad = _chord_deviation(ends[:-1], ends[1:], probes) > tolerance
        if not bad.any():
            return u[:-1], ends[:-1].T
        if len(u) > _MAX_POINTS:
            raise NumericalError("contour", f"more than {_MAX_POINTS} points needed for a {tolerance:g} mm tolerance")
        u = np.sort(np.concatenate([u, 0.5 * (u[:-1] + u[1:])[bad]]))


def resample(curve: Callable[[np.ndarray], np.ndarray], tolerance: float) -> np.ndarray:
    """Vertices (2, k) of a closed polyline within ``tolerance`` mm of the closed curve u -> (2, m)."""
    return resample_u(curve, tolerance)[1]


def _write_dxf(outlines: dict[str, np.ndarray], path: Path, unit: str) -> None:
    from ezdxf import units
    from ezdxf.filemanagement import new

    doc = new("R2010")
    doc.units = units.MM if unit == "mm" else units.IN
    for layer, xy in outlines.items():
        doc.modelspace().add_lwpolyline(xy.T.tolist(), format="xy", close=True, dxfattribs={"layer": layer})
    doc.saveas(path)


def _write_csv(outlines: dict[str, np.ndarray], path: Path, unit: str) -> None:
    fmt = "%.6f" if unit == "mm" else "%.7f"
    if len(outlines) == 1:
        np.savetxt(
            path, next(iter(outlines.values())).T, delimiter=",", header=f"x_{unit},y_{unit}", comments="", fmt=fmt
        )
        return
    with path.open("w") as fh:  # several outlines: a third column names each row's outline, one after the other
        fh.write(f"x_{unit},y_{unit},outline\n")
        for name, xy in outlines.items():
            for x, y in xy.T:
                fh.write(f"{fmt % x},{fmt % y},{name.lower()}\n")


def _write_svg(outlines: dict[str, np.ndarray], path: Path, unit: str) -> None:
    allxy = np.concatenate(list(outlines.values()), axis=1)
    lo, hi = allxy.min(axis=1), allxy.max(axis=1)
    pad = 0.05 * float(np.max(hi - lo))
    x0, y0, w, h = lo[0] - pad, -hi[1] - pad, hi[0] - lo[0] + 2 * pad, hi[1] - lo[1] + 2 * pad
    nd = 4 if unit == "mm" else 6  # 0.1 um either way
    stroke = 0.004 * max(w, h)
    polygons = ""
    for name, xy in outlines.items():
        pts = " ".join(f"{x:.{nd}f},{-y:.{nd}f}" for x, y in xy.T)  # SVG's y axis points down
        ident = "" if len(outlines) == 1 else f'id="{name.lower()}" '
        polygons += f'  <polygon {ident}points="{pts}" fill="none" stroke="black" stroke-width="{stroke:.{nd}f}"/>\n'
    path.write_text(
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.4f}{unit}" height="{h:.4f}{unit}" '
        f'viewBox="{x0:.{nd}f} {y0:.{nd}f} {w:.{nd}f} {h:.{nd}f}">\n'
        + polygons
        + f'  <circle cx="0" cy="0" r="{2 * stroke:.{nd}f}" fill="black"/>\n</svg>\n'
    )


_WRITERS = {".dxf": _write_dxf, ".csv": _write_csv, ".svg": _write_svg}


def write_profile(
    contour_xy: np.ndarray | Callable[[np.ndarray], np.ndarray] | dict[str, Callable[[np.ndarray], np.ndarray]],
    path: str | Path,
    *,
    tolerance: float = 0.01,
    force: bool = False,
    units: str = "mm",
) -> dict:
    """Write a closed cam contour (mm, cam frame) to ``path``; the format follows the suffix.

    ``contour_xy``: a dense closed sample (2, n) or a callable u -> (2, m) on u in [0, 1] (see the module
    docstring). ``tolerance``: the largest chord deviation, mm. ``units``: the file's, ``"mm"`` or ``"in"`` (the
    DXF's $INSUNITS, the CSV's ``x_in,y_in`` columns, the SVG's size). Refuses to overwrite an existing file unless
    ``force``. Returns ``{path, format, points, tolerance_mm, units, x_min_mm, x_max_mm, y_min_mm, y_max_mm}``.

    Several outlines (a groove cam's walls) come as a dict of callables by name: the DXF puts each on a layer of
    that name, the CSV adds a column ``outline`` (the name in lower case) and lists them one after the other, the
    SVG draws a polygon per outline with the name as its ``id``; ``points`` counts them all.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if path.is_dir():
        raise InputError(str(path), "is a folder: give a file name (cam.dxf, cam.csv or cam.svg)")
    if suffix not in _WRITERS:
        known = ", ".join(OUTLINE_FORMATS)
        raise InputError(str(path), f"unknown format {suffix or '(no suffix)'!r}: use one of {known}")
    if units not in ("mm", "in"):
        raise InputError("--units", f"must be mm or in, got {units!r}")
    check_chord_tolerance(tolerance)
    path = output_file(path, force, "contour")
    if isinstance(contour_xy, dict):
        curves = contour_xy
    elif callable(contour_xy):
        curves = {"CAM": contour_xy}
    else:
        xy = np.asarray(contour_xy, dtype=float)
        if xy.ndim != 2 or xy.shape[0] != 2 or xy.shape[1] < 4:
            raise InputError("contour", f"expected a (2, n >= 4) array of x, y in mm, got shape {xy.shape}")
        if not np.all(np.isfinite(xy)):
            raise InputError("contour", "the contour has non-finite points")
        curves = {"CAM": _spline(xy)}
    outlines = {name: resample(curve, tolerance) for name, curve in curves.items()}
    pts = np.concatenate(list(outlines.values()), axis=1)
    try:
        _WRITERS[suffix]({k: v if units == "mm" else v / MM_PER_INCH for k, v in outlines.items()}, path, units)
    except OSError as err:
        raise InputError(str(path), f"cannot write the file: {err.strerror or err}") from None
    lo, hi = pts.min(axis=1), pts.max(axis=1)
    return {
        "path": str(path),
        "format": suffix[1:],
        "points": int(pts.shape[1]),
        "tolerance_mm": tolerance,
        "units": units,
        "x_min_mm": float(lo[0]),
        "x_max_mm": float(hi[0]),
        "y_min_mm": float(lo[1]),
        "y_max_mm": float(hi[1]),
    }
