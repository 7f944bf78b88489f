"""The cam plate as a solid (STEP, STL) through the optional extra camdyn[cad]: its volume is the outline's area
times the thickness less the bore and keyway, its outline a B-spline within the chord tolerance of the outline."""

from __future__ import annotations

import math
import struct
from pathlib import Path

import numpy as np
import pytest
from _helpers import distance_to_outline, run
from scipy.spatial import cKDTree

import camdyn.model  # noqa: F401  (float64)
from camdyn.export.solid import parse_keyway, removed_area_mm2

CASES = Path(__file__).parent.parent / "cases"


def _polygon_area(xy: np.ndarray) -> float:
    return 0.5 * abs(float(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1])))


def _stl_volume(path: Path) -> float:
    """Signed volume of a binary STL by the divergence theorem (the sum of the tetrahedra on its triangles)."""
    raw = path.read_bytes()
    (n,) = struct.unpack("<I", raw[80:84])
    tri = np.frombuffer(raw[84 : 84 + 50 * n], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))[
        "v"
    ]
    tri = tri.astype(float)
    return float(np.sum(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])))) / 6.0


def test_keyway_text_and_the_removed_area():
    assert parse_keyway("6x2.8") == (6.0, 2.8) and parse_keyway(" 8 X 3 ") == (8.0, 3.0)
    # a keyway 2a wide on a bore of radius r: the slot's area outside the disc, by Monte Carlo as a second route
    rng = np.random.default_rng(0)
    p = rng.uniform([-13, -13], [13, 13], size=(2_000_000, 2))
    inside = (np.hypot(*p.T) <= 10) | ((np.abs(p[:, 0]) <= 3) & (p[:, 1] >= 0) & (p[:, 1] <= 10 + 2.8 - 1e-12))
    assert removed_area_mm2(20.0, (6.0, 2.8)) == pytest.approx(inside.mean() * 26.0**2, rel=2e-3)
    assert removed_area_mm2(20.0, None) == pytest.approx(math.pi * 100)


@pytest.mark.parametrize("bad", ["6", "6x", "x2", "-6x2", "6x0", "axb"])
def test_bad_keyway_is_one_line(capsys, tmp_path, bad):
    code, _, err = run(
        capsys,
        "profile",
        CASES / "lecture.toml",
        "-o",
        tmp_path / "c.step",
        "--thickness",
        10,
        "--bore",
        20,
        "--keyway",
        bad,
    )
    assert code == 2 and err.count("\n") == 1 and ("--keyway" in err or "camdyn[cad]" in err)


def test_without_the_extra_one_line_says_how_to_get_it(capsys, tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "build123d", None)  # as if not installed
    code, _, err = run(capsys, "profile", CASES / "lecture.toml", "-o", tmp_path / "c.step", "--thickness", 10)
    assert code == 2 and "pip install 'camdyn[cad]'" in err and err.count("\n") == 1
    assert not (tmp_path / "c.step").exists()


# OpenCascade builds each solid for seconds (6 s the valve lift's on 2 cores): every STEP is a slow test
@pytest.mark.slow
@pytest.mark.parametrize("name", ["lecture.toml", "valve-lift.toml"])
def test_step_volume_and_outline(capsys, tmp_path, name):
    bd = pytest.importorskip("build123d")
    src, tol, t = CASES / name, 0.01, 12.0
    bore, key = (20.0, (6.0, 2.8)) if name == "lecture.toml" else (10.0, None)
    assert run(capsys, "profile", src, "-o", tmp_path / "cam.csv")[0] == 0
    argv = ["-o", tmp_path / "cam.step", "--thickness", t, "--bore", bore] + (["--keyway", "6x2.8"] if key else [])
    code, _, err = run(capsys, "profile", src, *argv)
    assert code == 0, err
    outline = np.loadtxt(tmp_path / "cam.csv", delimiter=",", skiprows=1)
    solid = bd.import_step(str(tmp_path / "cam.step"))
    expect = _polygon_area(outline) * t - removed_area_mm2(bore, key) * t
    assert solid.volume == pytest.approx(expect, rel=1e-3)
    splines = [e for e in solid.edges() if e.geom_type == bd.GeomType.BSPLINE]
    assert splines, "the outline is a B-spline, not a faceted polygon"
    at = {z: [e for e in splines if all(abs(e.position_at(u).Z - z) < 1e-6 for u in (0.0, 0.5, 1.0))] for z in (0, t)}
    assert len(at[0]) == len(at[t]) >= len(splines) // 3  # the outline at z = 0 and again at z = t
    # (sampled in Python, a point a call: the bottom's edges only, half of the 3 s that both faces took)
    on = np.concatenate([[tuple(e.position_at(u)) for u in np.linspace(0, 1, 1000)] for e in at[0]])
    bottom = on[:, :2]
    assert np.abs(on[:, 2]).max() < 1e-6
    # the spline lies on the exact contour (on which the CSV's vertices lie) within the tolerance: its distance from
    # the CSV polyline is at most the polyline's own chord sagitta plus that; every vertex is near the spline
    assert distance_to_outline(bottom, outline).max() <= 2 * tol
    assert cKDTree(bottom).query(outline)[0].max() <= tol


@pytest.mark.slow  # three solids
def test_stl_volume_and_inch_step(capsys, tmp_path):
    bd = pytest.importorskip("build123d")
    src, t = CASES / "lecture.toml", 8.0
    assert run(capsys, "profile", src, "-o", tmp_path / "cam.csv")[0] == 0
    for out, units in (("cam.stl", "mm"), ("cam-in.stl", "in"), ("cam-in.step", "in")):
        code, _, err = run(
            capsys, "profile", src, "-o", tmp_path / out, "--thickness", t, "--bore", 16, "--units", units
        )
        assert code == 0, err
    outline = np.loadtxt(tmp_path / "cam.csv", delimiter=",", skiprows=1)
    expect = (_polygon_area(outline) - removed_area_mm2(16.0, None)) * t
    assert abs(_stl_volume(tmp_path / "cam.stl")) == pytest.approx(expect, rel=1e-3)
    assert abs(_stl_volume(tmp_path / "cam-in.stl")) * 25.4**3 == pytest.approx(expect, rel=1e-3)
    assert "INCH" in (tmp_path / "cam-in.step").read_text().upper()
    assert bd.import_step(str(tmp_path / "cam-in.step")).volume == pytest.approx(expect, rel=1e-3)  # read back in mm


@pytest.mark.slow  # the CAD kernel's import and the outline, as the solids above
def test_a_bore_through_the_outline_is_refused(capsys, tmp_path):
    pytest.importorskip("build123d")
    code, _, err = run(
        capsys, "profile", CASES / "lecture.toml", "-o", tmp_path / "c.step", "--thickness", 10, "--bore", 85
    )
    assert code == 2 and "--bore" in err and err.count("\n") == 1 and not (tmp_path / "c.step").exists()


@pytest.mark.slow  # the CAD kernel's import, as the solids above
def test_a_folded_contour_is_refused_where_it_folds(capsys, tmp_path):
    """The lecture's rise in 20 deg where it takes 90 folds the contour (undercut, least radius -4.24 mm at 106.7
    deg): no plate has that outline, and the spline's stray from it was all the error said; now the angle, the fold
    and the way out."""
    pytest.importorskip("build123d")
    text = (CASES / "lecture.toml").read_text()
    assert '{ law = "cycloidal", end = 180, lift = 20 }' in text
    text = text.replace('{ law = "cycloidal", end = 180,', '{ law = "cycloidal", end = 110,')
    case = tmp_path / "folded.toml"
    case.write_text(text)
    code, _, err = run(capsys, "profile", case, "-o", tmp_path / "c.step", "--thickness", 10)
    assert code == 2 and err.count("\n") == 1 and not (tmp_path / "c.step").exists()
    assert "theta = " in err and "the contour folds (undercut" in err and "larger base radius" in err
