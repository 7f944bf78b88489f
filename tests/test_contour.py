"""Measured or drawn contours: the motion by exact contact for the four follower types, the flat face across a
concave stretch, DXF outlines, one-line refusals, and the round trip profile -> contour -> check."""

import io
import json
import math
import re
import tomllib
from contextlib import redirect_stdout
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from ezdxf.math import BSpline

from camdyn import case_from_dict, load_case
from camdyn.cli import main
from camdyn.model.datafiles import Samples, read_contour
from camdyn.model.geometry import analyze, contact_motion
from camdyn.schema import FollowerSpec

ROOT = Path(__file__).resolve().parents[1]
LECTURE = tomllib.loads((ROOT / "cases" / "lecture.toml").read_text())
OSCILLATING = tomllib.loads((ROOT / "cases" / "oscillating.toml").read_text())

FOLLOWERS = {
    "translating-roller cw": (
        LECTURE,
        {"type": "translating-roller", "base_radius": 40, "roller_radius": 10, "offset": 5, "rotation": "cw"},
    ),
    "translating-roller ccw": (
        LECTURE,
        {"type": "translating-roller", "base_radius": 40, "roller_radius": 10, "offset": -5, "rotation": "ccw"},
    ),
    "translating-flat": (LECTURE, {"type": "translating-flat", "base_radius": 50, "offset": 3, "rotation": "ccw"}),
    "oscillating-roller": (
        OSCILLATING,
        {
            "type": "oscillating-roller",
            "base_radius": 40,
            "roller_radius": 8,
            "pivot_distance": 110,
            "arm_length": 90,
            "rotation": "ccw",
            "pivot_angle": 30,
        },
    ),
    "oscillating-flat cw": (
        OSCILLATING,
        {
            "type": "oscillating-flat",
            "base_radius": 60,
            "pivot_distance": 120,
            "offset": 10,
            "rotation": "cw",
            "pivot_angle": -20,
        },
    ),
    "oscillating-flat ccw": (
        OSCILLATING,
        {
            "type": "oscillating-flat",
            "base_radius": 80,
            "pivot_distance": 150,
            "offset": -10,
            "rotation": "ccw",
            "pivot_angle": 100,
        },
    ),
}


def _samples(xy: np.ndarray, name: str = "cam.csv") -> Samples:
    return Samples(name, np.asarray(xy, dtype=float), np.arange(2, len(xy) + 2), "line", 0.0)


def _without_base_radius(follower: dict, contour: str = "cam.csv") -> FollowerSpec:
    return FollowerSpec(**{k: v for k, v in follower.items() if k != "base_radius"}, contour=contour)


@pytest.mark.parametrize("name", FOLLOWERS)
def test_exact_contact_inverts_the_cam_geometry(name):
    """The contour camdyn draws for a motion gives that motion back (and the base radius), for every follower
    type, offset, pivot and rotation: the inverse in closed form against the forward geometry by autodiff."""
    raw, follower = FOLLOWERS[name]
    case = case_from_dict(raw | {"follower": follower})
    xy = analyze(case.motion, case.follower).contour_fn()(np.linspace(0.0, 1.0, 2000, endpoint=False)).T
    derived = contact_motion(_samples(xy), _without_base_radius(follower))
    truth = np.asarray(case.motion.host(np.deg2rad(derived.theta_deg)))[0]
    scale = 1.0 if case.follower.translating else 180.0 / math.pi
    assert derived.follower.base_radius == pytest.approx(follower["base_radius"], abs=1e-5)
    assert np.abs(derived.lift - truth * scale).max() < (2e-5 if case.follower.translating else 1e-6)
    assert derived.warnings == () and len(derived.theta_deg) > 3000


def _dented(n: int = 1440) -> np.ndarray:
    """A star-shaped outline, r = 40 + 4 cos(a) less a 3 mm dent about 90 deg: concave there."""
    a = np.arange(n) * (2 * np.pi / n)
    r = 40 + 4 * np.cos(a) - 3 * np.exp(-(((a - np.pi / 2) / math.radians(8)) ** 2))
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


def test_flat_face_bridges_a_concave_stretch_as_the_support_function_says():
    xy = _dented()
    f = FollowerSpec(type="translating-flat", contour="dent.csv", rotation="cw")
    derived = contact_motion(_samples(xy, "dent.csv"), f)
    (warning,) = derived.warnings
    low, high = (float(v) for v in re.search(r"from polar angle ([\d.]+) to ([\d.]+) deg", warning).groups())
    assert low < 80 < 90 < 100 < high < 120 and "never touches the cam there" in warning
    # independently: the face rests on the highest point of the outline, densely sampled (its support function)
    a = np.linspace(0, 2 * np.pi, 400000, endpoint=False)
    r = 40 + 4 * np.cos(a) - 3 * np.exp(-(((a - np.pi / 2) / math.radians(8)) ** 2))
    dense = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
    th = np.deg2rad(derived.theta_deg[::40])
    n = np.stack([-np.sin(th), np.cos(th)], axis=1)  # the face normal (0, 1) seen in the cam frame, cw cam
    support = np.max(n @ dense.T, axis=1)
    np.testing.assert_allclose(derived.lift[::40], support - derived.follower.base_radius, atol=2e-4)
    assert derived.follower.base_radius == pytest.approx(r.min(), abs=1e-4)


def _write_csv(path: Path, xy) -> None:
    path.write_text("x_mm,y_mm\n" + "".join(f"{x:.6f},{y:.6f}\n" for x, y in xy))


def _contour_case(tmp_path: Path, follower: dict, contour: str) -> Path:
    lines = [f"{k} = {json.dumps(v)}" for k, v in follower.items()] + [f"contour = {json.dumps(contour)}"]
    source = "lecture" if follower["type"].startswith("translating") else "oscillating"
    dyn = (ROOT / "cases" / f"{source}.toml").read_text().split("[dynamics]")[1]
    (tmp_path / "case.toml").write_text("[follower]\n" + "\n".join(lines) + "\n\n[dynamics]" + dyn)
    return tmp_path / "case.toml"


ROLLER = {"type": "translating-roller", "roller_radius": 10, "offset": 5, "rotation": "cw"}
CIRCLE = np.stack([np.cos(np.arange(60) * np.pi / 30), np.sin(np.arange(60) * np.pi / 30)], axis=1) * 40


def _figure_eight():
    t = (np.arange(200) + 0.5) * (2 * np.pi / 200)
    return np.stack([40 * np.sin(t) + 5, 20 * np.sin(2 * t) + 3], axis=1)


def _turning_back():
    """A C-shaped outline around the centre whose tip curls back: rays from the centre cross it three times."""
    a = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    r = 40 + 25 * np.exp(-(((a - np.pi) / 0.15) ** 2))
    xy = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
    hook = (a > np.pi - 0.3) & (a < np.pi + 0.3)
    xy[hook, 1] += 30 * np.sin((a[hook] - np.pi + 0.3) / 0.6 * np.pi) * 0.6
    return xy


@pytest.mark.parametrize(
    "points, follower, where, text",
    [
        (CIRCLE[:20], ROLLER, "cam.csv", "does not go around the cam centre"),
        (CIRCLE[:50], ROLLER, "cam.csv line 51", "the outline is open: no point from polar angle 294 to 360 deg"),
        (CIRCLE + [60, 0], ROLLER, "cam.csv", "does not go around the cam centre"),
        (_figure_eight(), ROLLER, "cam.csv", "self-intersecting"),
        (CIRCLE[:7], ROLLER, "cam.csv", "has 7 data rows: at least 8"),
        (
            _dented(),
            ROLLER,
            "cam.csv",
            "the roller (radius 10 mm) cannot follow the concave stretch around polar angle",
        ),
        (
            _dented(),
            {"type": "oscillating-roller", "roller_radius": 2, "pivot_distance": 30, "arm_length": 12},
            "cam.csv",
            "cannot reach the outline",
        ),
        (None, ROLLER, "cam.csv", "no such file"),
    ],
)
def test_bad_contours_one_line_exit_2(capsys, tmp_path, points, follower, where, text):
    if points is not None:
        _write_csv(tmp_path / "cam.csv", points)
    case = _contour_case(tmp_path, follower, "cam.csv")
    assert main(["check", str(case)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"{case}: {where}" in err and text in err, err


def test_not_star_shaped_names_the_point(tmp_path):
    xy = _turning_back()
    _write_csv(tmp_path / "cam.csv", xy)
    with pytest.raises(Exception) as err:
        contact_motion(read_contour(tmp_path / "cam.csv", "cam.csv"), _without_base_radius(ROLLER | {"base_radius": 1}))
    assert re.search(r"cam.csv line \d+", err.value.where) and (
        "not star-shaped" in err.value.message or "self-intersecting" in err.value.message
    )


def test_contour_and_motion_keys_are_refused_together(capsys, tmp_path):
    _write_csv(tmp_path / "cam.csv", CIRCLE)
    case = _contour_case(tmp_path, ROLLER | {"base_radius": 40}, "cam.csv")
    assert main(["check", str(case)]) == 2
    assert "follower.base_radius: a contour gives the base radius" in capsys.readouterr().err


# ------------------------------------------------------------------------------------------------- DXF
def _eccentric_dxf(path: Path, centre=(3.0, -2.0), radius=40.0, closed=True) -> None:
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    cx, cy = centre
    doc.modelspace().add_circle((0, 0), 5)  # a bore: not an outline
    doc.modelspace().add_lwpolyline(
        [(cx + radius, cy, 0, 0, 1), (cx - radius, cy, 0, 0, 1)], format="xyseb", close=closed
    )
    doc.saveas(path)


def test_dxf_arcs_give_the_eccentric_cams_closed_form(tmp_path):
    """An eccentric circle drawn as two bulged LWPOLYLINE arcs, under a flat face (cw): the face rests at
    R + c . n(theta) from the centre, n = (sin -theta, cos theta)... in the cam frame."""
    _eccentric_dxf(tmp_path / "cam.dxf")
    case = load_case(_contour_case(tmp_path, {"type": "translating-flat", "rotation": "cw"}, "cam.dxf"))
    c, radius = np.array([3.0, -2.0]), 40.0
    assert case.follower.base_radius == pytest.approx(radius - np.hypot(*c), abs=1e-6)
    th = np.linspace(0, 2 * np.pi, 721)
    n = np.stack([-np.sin(th), np.cos(th)], axis=1)
    want = radius + n @ c - case.follower.base_radius
    got = np.asarray(case.motion.host(th))
    np.testing.assert_allclose(got[0], want, atol=2e-6)
    np.testing.assert_allclose(got[2], -(n @ c), atol=1e-4)  # s'' of a sinusoid
    assert case.motion_json()["source"] == "contour" and case.motion_json()["fit"]["max_residual"] < 1e-6


def test_open_dxf_polyline_is_refused(capsys, tmp_path):
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    a = np.linspace(0, 1.9 * np.pi, 50)
    doc.modelspace().add_lwpolyline(np.stack([40 * np.cos(a), 40 * np.sin(a)], axis=1).tolist())
    doc.saveas(tmp_path / "cam.dxf")
    case = _contour_case(tmp_path, ROLLER, "cam.dxf")
    assert main(["check", str(case)]) == 2
    err = capsys.readouterr().err
    assert "cam.dxf: the LWPOLYLINE" in err and "is open: its ends are" in err


def test_closed_dxf_spline_matches_its_points_as_csv(tmp_path):
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    a = np.arange(17) * np.pi / 8  # the first fit point again at the end: the spline closes
    fit = np.stack([(40 + 3 * np.cos(2 * a)) * np.cos(a), (40 + 3 * np.cos(2 * a)) * np.sin(a)], axis=1)
    doc.modelspace().add_spline().apply_construction_tool(BSpline.from_fit_points(fit.tolist(), degree=3))
    doc.saveas(tmp_path / "cam.dxf")
    dxf = read_contour(tmp_path / "cam.dxf", "cam.dxf")
    _write_csv(tmp_path / "cam.csv", dxf.values)
    csv = read_contour(tmp_path / "cam.csv", "cam.csv")
    f = FollowerSpec(type="translating-flat", contour="cam.dxf")
    a_, b_ = contact_motion(dxf, f), contact_motion(csv, f)
    grid = np.arange(0.5, 359.5, 0.25)
    lift = [np.interp(grid, m.theta_deg[np.argsort(m.theta_deg)], m.lift[np.argsort(m.theta_deg)]) for m in (a_, b_)]
    np.testing.assert_allclose(lift[0], lift[1], atol=1e-5)  # the CSV's 6 decimals are all that differ
    assert len(dxf.values) > 100 and dxf.row_word == "point"


# ---------------------------------------------------------------------------------- round trip (slow)
def _check_json(*argv) -> dict:
    buf = io.StringIO()
    with redirect_stdout(buf):
        main(["check", *map(str, argv), "--json"])
    return json.loads(buf.getvalue())


def _case_file(path: Path, raw: dict) -> Path:
    import tomli_w

    path.write_text(tomli_w.dumps(raw))
    return path


def _round_trip(tmp_path: Path, raw: dict, reference: dict) -> dict:
    source = _case_file(tmp_path / "source.toml", raw)
    assert main(["profile", str(source), "-o", str(tmp_path / "cam.csv")]) == 0
    contour = {k: v for k, v in raw.items() if k not in ("motion", "name")}
    contour["follower"] = {k: v for k, v in raw["follower"].items() if k != "base_radius"} | {"contour": "cam.csv"}
    got = _check_json(_case_file(tmp_path / "contour.toml", contour))
    for kind in ("kinematic", "dynamic"):
        assert got[kind]["jump_speed_rpm"] == pytest.approx(reference[kind]["jump_speed_rpm"], rel=0.005), kind
    assert got["geometry"]["max_pressure_angle_deg"] == pytest.approx(
        reference["geometry"]["max_pressure_angle_deg"], abs=0.05
    )
    assert got["geometry"]["min_radius_of_curvature_mm"] == pytest.approx(
        reference["geometry"]["min_radius_of_curvature_mm"], rel=0.01
    )
    assert got["motion"]["source"] == "contour" and got["motion"]["base_radius_mm"] == pytest.approx(
        raw["follower"]["base_radius"], abs=1e-3
    )
    return got


@pytest.mark.slow
def test_round_trip_lecture(tmp_path, lecture_check_json):
    """camdyn profile cases/lecture.toml -o lecture.csv, then the lecture's follower and dynamics on that contour."""
    _round_trip(tmp_path, LECTURE, lecture_check_json)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["flat", "oscillating"])
def test_round_trip_flat_and_oscillating(tmp_path, name):
    raw = OSCILLATING if name == "oscillating" else LECTURE | {"follower": FOLLOWERS["translating-flat"][1]}
    reference = _check_json(_case_file(tmp_path / "reference.toml", raw))
    _round_trip(tmp_path, raw, reference)
