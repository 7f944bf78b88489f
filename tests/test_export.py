"""Contour export: DXF read back by ezdxf, chord tolerance, CSV/SVG, overwrite refusal."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import ezdxf
import numpy as np
import pytest

import camdyn.model  # noqa: F401  (float64)
from camdyn import InputError, Program
from camdyn.export import resample, write_profile
from camdyn.model.geometry import analyze
from camdyn.schema import FollowerSpec


@pytest.fixture(scope="module")
def cam():
    """The lecture's offset-roller cam (base 40 mm, roller 10 mm, offset 5 mm, cw)."""
    motion = Program.from_segments(
        [
            {"law": "dwell", "end": 90},
            {"law": "cycloidal", "end": 180, "lift": 20.0},
            {"law": "dwell", "end": 240},
            {"law": "harmonic", "end": 360, "lift": -20.0},
        ]
    )
    return analyze(motion, FollowerSpec(type="translating-roller", base_radius=40.0, roller_radius=10.0, offset=5.0))


def distance_to_polyline(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of each point (2, m) from the closed polyline (2, k), via the two chords at its nearest vertex."""
    from scipy.spatial import cKDTree

    k = poly.shape[1]
    i = cKDTree(poly.T).query(pts.T)[1]
    best = np.full(pts.shape[1], np.inf)
    for j0 in (i - 1, i):
        a, b = poly[:, j0 % k], poly[:, (j0 + 1) % k]
        d = b - a
        w = np.clip(np.sum((pts - a) * d, 0) / np.sum(d * d, 0), 0.0, 1.0)
        best = np.minimum(best, np.hypot(*(pts - a - w * d)))
    return best


def test_dxf_reads_back_with_the_contour_extents(cam, tmp_path):
    path = tmp_path / "cam.dxf"
    info = write_profile(cam.contour_fn(), path, tolerance=0.01)
    doc = ezdxf.readfile(path)
    assert doc.units == ezdxf.units.MM
    (poly,) = doc.modelspace().query("LWPOLYLINE")
    assert poly.closed
    xy = np.array([(x, y) for x, y, *_ in poly.get_points()]).T
    assert xy.shape[1] == info["points"]
    # extents of the exact contour (dense), which the polyline's vertices lie on: within the chord tolerance
    dense = cam.contour_fn()(np.linspace(0.0, 1.0, 40_001))
    np.testing.assert_allclose(xy.min(axis=1), dense.min(axis=1), atol=0.01)
    np.testing.assert_allclose(xy.max(axis=1), dense.max(axis=1), atol=0.01)
    assert (info["x_min_mm"], info["y_max_mm"]) == pytest.approx((xy[0].min(), xy[1].max()), abs=1e-9)
    # base circle 40 mm; the top of the rise puts the contour about 40 + 20 mm out
    assert np.hypot(*dense).min() == pytest.approx(40.0, abs=1e-6)
    assert 59.0 < np.hypot(*xy).max() < 61.0


def test_polyline_within_chord_tolerance(cam):
    curve = cam.contour_fn()
    ds = 2 * np.pi / cam.contour.shape[1]
    speed = np.hypot(*(np.roll(cam.contour, -1, axis=1) - np.roll(cam.contour, 1, axis=1))) / (2 * ds)
    dense = curve(np.linspace(0.0, 1.0, 40_001))
    for tol in (0.1, 0.01, 0.001):
        poly = resample(curve, tol)
        assert distance_to_polyline(dense, poly).max() <= tol * 1.001
        # adaptive, not wasteful: a chord of sagitta tol spans sqrt(8 tol rho), so the least count is the
        # integral of ds / sqrt(8 tol rho); interval halving may at most double it
        ideal = np.sum(speed / np.sqrt(8 * tol * np.abs(cam.rho_contour_mm))) * ds
        assert ideal < poly.shape[1] < 2 * ideal + 64  # (64: the initial partition)


def test_dense_sample_is_splined(tmp_path):
    """A sampled circle: vertices on the circle, sagitta under the tolerance."""
    r, tol = 25.0, 0.005
    t = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    info = write_profile(np.stack([r * np.cos(t), r * np.sin(t)]), tmp_path / "c.csv", tolerance=tol)
    xy = np.loadtxt(tmp_path / "c.csv", delimiter=",", skiprows=1).T
    assert (tmp_path / "c.csv").read_text().splitlines()[0] == "x_mm,y_mm"
    assert xy.shape[1] == info["points"]
    np.testing.assert_allclose(np.hypot(*xy), r, atol=1e-6)
    gaps = np.hypot(*(np.roll(xy, -1, axis=1) - xy))
    assert (gaps**2 / (8 * r)).max() <= tol * 1.001  # sagitta of each chord
    assert info["x_max_mm"] == pytest.approx(r, abs=tol)


def test_svg_is_well_formed(cam, tmp_path):
    info = write_profile(cam.contour, tmp_path / "cam.svg", tolerance=0.05)
    root = ET.parse(tmp_path / "cam.svg").getroot()
    (poly,) = [e for e in root.iter() if e.tag.endswith("polygon")]
    assert len(poly.get("points").split()) == info["points"]


def test_refuses_to_overwrite_without_force(cam, tmp_path):
    path = tmp_path / "cam.csv"
    path.write_text("keep me")
    with pytest.raises(InputError, match="--force") as err:
        write_profile(cam.contour, path)
    assert str(path) in str(err.value)
    assert path.read_text() == "keep me"
    write_profile(cam.contour, path, force=True)
    assert path.read_text().startswith("x_mm,y_mm")


@pytest.mark.parametrize(
    "name, tol, match",
    [
        ("cam.step", 0.01, "unknown format"),
        ("cam.dxf", 0.0, "between 1e-06 and 10 mm"),
        ("cam.dxf", float("inf"), "between"),
    ],
)
def test_bad_requests(cam, tmp_path, name, tol, match):
    with pytest.raises(InputError, match=match):
        write_profile(cam.contour, tmp_path / name, tolerance=tol)
    assert not (tmp_path / name).exists()
