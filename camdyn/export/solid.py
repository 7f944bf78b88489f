"""The cam plate as a solid: STEP (a smooth B-spline outline) or STL, through build123d (the optional extra
``pip install 'camdyn[cad]'``).

build123d, not CadQuery: both drive the same OpenCascade kernel (OCP), but build123d takes the kernel without VTK
(``cadquery-ocp-novtk``) and nothing else heavy, where CadQuery 2.8 also pulls VTK, casadi, numba and trame;
a fresh environment installs build123d in under half a minute.

The outline is the periodic cubic B-spline interpolating the contour at the vertices of a polyline within the
chord tolerance; it is sampled and measured against the exact contour, and the points are refined until it lies
within the tolerance. The plate lies on z = 0..thickness, the cam frame's x, y; the bore (a diameter) is centred
on the cam axis, the keyway centred on the +y axis, its depth measured beyond the bore.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .._core.errors import InputError, NumericalError
from .._core.outputs import output_file
from .._core.units import MM_PER_INCH
from .machining import reference_tolerance, segment_distance
from .profile import resample

CAD_HINT = "a solid (.step, .stl) needs the optional extra: pip install 'camdyn[cad]' (build123d)"
_REFINE = 4  # tries, each with a four times finer polyline, before the spline is given up


def require_cad() -> None:
    """:class:`InputError` (one line, how to get it) when build123d is not installed."""
    try:
        import build123d  # noqa: F401
    except ImportError:
        raise InputError("--output", CAD_HINT) from None


def parse_keyway(text: str) -> tuple[float, float]:
    """``"WIDTHxDEPTH"`` (mm) as (width, depth)."""
    m = re.fullmatch(r"\s*([0-9.]+(?:[eE][-+]?\d+)?)\s*[xX*]\s*([0-9.]+(?:[eE][-+]?\d+)?)\s*", text)
    try:
        w, d = (float(m.group(1)), float(m.group(2))) if m else (math.nan, math.nan)
    except ValueError:
        w = d = math.nan
    if not (w > 0 and d > 0 and math.isfinite(w + d)):
        raise InputError("--keyway", f"give WIDTHxDEPTH in mm, both positive, e.g. 6x2.8 (got {text!r})")
    return w, d


def removed_area_mm2(bore_mm: float | None, keyway_mm: tuple[float, float] | None) -> float:
    """Area (mm^2) the bore and the keyway take from the plate: the disc, and the slot's part outside it."""
    if bore_mm is None:
        return 0.0
    r = bore_mm / 2
    area = math.pi * r * r
    if keyway_mm is not None:
        w, d = keyway_mm
        a = w / 2  # the slot |x| <= a, 0 <= y <= r + d, less the disc's cap under it
        area += w * (r + d) - (a * math.sqrt(r * r - a * a) + r * r * math.asin(a / r))
    return area


def _check_hole(contour: np.ndarray, bore_mm: float | None, keyway_mm) -> None:
    if bore_mm is None:
        if keyway_mm is not None:
            raise InputError("--keyway", "a keyway is cut in the bore: give --bore too")
        return
    r = bore_mm / 2
    reach = r
    if keyway_mm is not None:
        w, d = keyway_mm
        if w >= bore_mm:
            raise InputError("--keyway", f"the keyway ({w:g} mm) must be narrower than the bore ({bore_mm:g} mm)")
        reach = math.hypot(w / 2, r + d)
    least = float(np.min(np.hypot(*contour)))
    if reach >= least:
        what = "bore and keyway reach" if keyway_mm else "bore reaches"
        raise InputError("--bore", f"the {what} {reach:.3f} mm from the axis; the outline comes within {least:.3f} mm")


def _spline_outline(contour: Callable[[np.ndarray], np.ndarray], tolerance_mm: float, exact: np.ndarray):
    """The edges of a periodic cubic B-spline within the tolerance of the contour, and its measured deviation (mm)."""
    from build123d import Edge, Vector

    tol = tolerance_mm
    for _ in range(_REFINE):
        pts = resample(contour, tol).T
        edge = Edge.make_spline([Vector(x, y, 0.0) for x, y in pts], periodic=True)
        t = np.linspace(0.0, 1.0, 8 * len(pts), endpoint=False)
        on = np.array([tuple(edge.position_at(ti))[:2] for ti in t])
        dev = float(segment_distance(on, exact).max())
        if dev <= tolerance_mm:
            # the same curve in pieces: OpenCascade's default mass properties integrate each edge with a fixed
            # number of Gauss points, which one long periodic spline starves (0.2 % off a small cam's volume)
            n = int(np.clip(len(pts) // 8, 16, 64))
            return [edge.trim(i / n, (i + 1) / n) for i in range(n)], dev
        tol /= 4
    raise NumericalError(
        "solid", f"the B-spline outline strays {dev:.4f} mm from the contour: over {tolerance_mm:g} mm"
    )


def _export_step(part, path: Path, units: str) -> None:
    """STEP in mm, or in inches (its coordinates in inches, its length unit INCH): OpenCascade's writer setting."""
    from build123d import Unit, export_step
    from OCP.Interface import Interface_Static  # pyright: ignore[reportAttributeAccessIssue] - OCP's stubs lack it
    from OCP.STEPControl import STEPControl_Controller  # pyright: ignore[reportAttributeAccessIssue] - as above

    STEPControl_Controller.Init_s()
    Interface_Static.SetCVal_s("write.step.unit", "MM" if units == "mm" else "INCH")
    try:
        export_step(part, str(path), unit=Unit.MM)
    finally:
        Interface_Static.SetCVal_s("write.step.unit", "MM")


def write_solid(
    contour: Callable[[np.ndarray], np.ndarray],
    path: str | Path,
    *,
    thickness_mm: float,
    bore_mm: float | None = None,
    keyway_mm: tuple[float, float] | None = None,
    tolerance_mm: float = 0.01,
    units: str = "mm",
    force: bool = False,
) -> dict:
    """Write the cam plate (STEP or STL by the suffix); returns ``{path, format, volume_mm3, area_mm2,
    outline_deviation_mm}``: the solid's volume (OpenCascade's), its outline's area and deviation from the contour."""
    require_cad()
    from build123d import Face, Pos, Solid, Wire, export_stl, extrude

    path = output_file(Path(path), force, "solid")
    suffix = path.suffix.lower()
    exact = resample(contour, reference_tolerance(tolerance_mm)).T
    _check_hole(exact.T, bore_mm, keyway_mm)
    edges, dev = _spline_outline(contour, tolerance_mm, exact)
    face = Face(Wire(edges))
    area = float(face.area)
    part = extrude(face, amount=thickness_mm)
    if bore_mm is not None:
        part = part - Solid.make_cylinder(bore_mm / 2, thickness_mm)
        if keyway_mm is not None:
            w, d = keyway_mm
            part = part - Pos(-w / 2, 0.0, 0.0) * Solid.make_box(w, bore_mm / 2 + d, thickness_mm)
    volume = float(part.volume)
    try:
        if suffix == ".step":
            _export_step(part, path, units)
        else:
            shape = part if units == "mm" else part.scale(1.0 / MM_PER_INCH)
            export_stl(shape, str(path), tolerance=tolerance_mm / (1.0 if units == "mm" else MM_PER_INCH))
    except OSError as err:
        raise InputError(str(path), f"cannot write the file: {err.strerror or err}") from None
    if not path.exists():
        raise NumericalError(str(path), "the CAD kernel wrote no file")
    return {
        "path": str(path),
        "format": suffix[1:],
        "volume_mm3": volume,
        "area_mm2": area,
        "outline_deviation_mm": dev,
    }
