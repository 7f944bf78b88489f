"""The cam for the shop: the CNC cutter path (G-code), the grinder table, inch files, the servo e-cam table.

Every path is measured against a dense sample of the exact contour, independently of camdyn's own offsetting:
the cutter's centre stays between the cutter radius and the radius plus the tolerance from the outline (it never
gouges), the grinding wheel touches the turned cam and enters it nowhere.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
from _helpers import distance_to_outline, run

import camdyn.model  # noqa: F401  (float64)
from camdyn.model.case import build_case
from camdyn.model.geometry import analyze
from camdyn.model.motion import evaluate
from camdyn.schema import load_case_spec

CASES = Path(__file__).parent.parent / "cases"

OSC_FLAT = """
name = "osc-flat"
[motion]
segments = [
  { law = "cycloidal", end = 120, lift = 8 },
  { law = "dwell", end = 180 },
  { law = "cycloidal", end = 300, lift = -8 },
  { law = "dwell", end = 360 },
]
[follower]
type = "oscillating-flat"
base_radius = 50
pivot_distance = 150
offset = 0
face_width = 120
rotation = "ccw"
[dynamics]
speed = 200
inertia = 0.002
torsion_rate = 5
preload_torque = 2
damping_ratio = 0.05
"""

# a quick rise on a small base circle: its pitch curve turns concave (least concave contour radius about 8 mm)
CONCAVE = """
name = "concave"
[motion]
segments = [
  { law = "cycloidal", end = 60, lift = 25 },
  { law = "dwell", end = 120 },
  { law = "cycloidal", end = 180, lift = -25 },
  { law = "dwell", end = 360 },
]
[follower]
type = "translating-roller"
base_radius = 25
roller_radius = 5
offset = 0
rotation = "cw"
[dynamics]
speed = 100
mass = 0.4
spring_rate = 3
preload = 40
damping_ratio = 0.05
"""


def _case_file(tmp_path, name: str) -> Path:
    if name.endswith(".toml"):
        return CASES / name
    path = tmp_path / f"{name}.toml"
    path.write_text({"osc-flat": OSC_FLAT, "concave": CONCAVE}[name])
    return path


def _geometry(path: Path):
    case = build_case(load_case_spec(path), source=path)
    return case, analyze(case.motion, case.follower)


def _dense_outline(geo, n: int = 40_000) -> np.ndarray:
    return geo.contour_fn()(np.arange(n) / n).T


def _gcode_points(text: str, scale: float = 1.0) -> tuple[np.ndarray, int]:
    """The contour's points (mm): the cutting moves but the radial lead-in and lead-out in the air, arcs sampled every
    0.5 deg of their sweep, lines every 0.05 mm; and the number of arcs."""
    pts, at, arcs, cutting = [], None, 0, False
    for line in text.splitlines():
        words = dict(re.findall(r"([GXYZIJF])(-?[\d.]+)", line))
        if "Z" in words:
            cutting = float(words["Z"]) <= 0
        if "X" not in words:
            continue
        end = np.array([float(words["X"]), float(words["Y"])]) * scale
        g = words.get("G")
        if g in ("2", "3") and cutting:
            arcs += 1
            c = at + np.array([float(words["I"]), float(words["J"])]) * scale
            a0, a1 = math.atan2(*(at - c)[::-1]), math.atan2(*(end - c)[::-1])
            sweep = (a1 - a0) % (2 * math.pi) if g == "3" else -((a0 - a1) % (2 * math.pi))
            t = np.linspace(0, 1, max(2, int(abs(math.degrees(sweep)) * 2)))[1:]
            r = np.hypot(*(at - c))
            pts.append(c + r * np.column_stack([np.cos(a0 + t * sweep), np.sin(a0 + t * sweep)]))
        elif g == "1" and cutting:
            n = max(2, int(np.hypot(*(end - at)) / 0.05))
            pts.append(at + np.linspace(0, 1, n)[1:, None] * (end - at))
        at = end
    return np.concatenate(pts[1:-1]), arcs


@pytest.mark.slow  # each follower type's geometry compiles once
@pytest.mark.parametrize("name", ["lecture.toml", "oscillating.toml", "valve-lift.toml", "osc-flat"])
@pytest.mark.parametrize("arcs", [False, True])
def test_cutter_centre_stays_at_the_cutter_radius_and_never_gouges(capsys, tmp_path, name, arcs):
    src = _case_file(tmp_path, name)
    _, geo = _geometry(src)
    rc, tol = 4.0, 0.01
    out = tmp_path / "cam.nc"
    code, _, err = run(capsys, "profile", src, "-o", out, "--cutter-radius", rc, *(["--arcs"] if arcs else []))
    assert code == 0, err
    text = out.read_text()
    pts, n_arcs = _gcode_points(text)
    d = distance_to_outline(pts, _dense_outline(geo))
    sag = 1e-5  # the dense outline's own chords (40 000 of them) lie inside the convex contour by at most this
    assert d.min() >= rc - sag, f"gouge: {rc - d.min():.2e} mm"
    assert d.max() <= rc + tol + sag
    # all round: every point of the outline has the path within the cutter radius (and the tolerance) of it
    assert distance_to_outline(_dense_outline(geo, 2000), pts).max() <= rc + tol + sag
    assert (n_arcs > 0) == arcs
    head = text.splitlines()[:12]
    assert re.search(r"sha256 [0-9a-f]{64}", "\n".join(head))
    assert any("G17" in h and "G21" in h and "G90" in h for h in head)
    assert not re.search(r"G4[12]\b", text.split("\n", 9)[-1])  # no controller compensation in the program


def test_gcode_header_names_case_hash_cutter_tolerance_and_inches(capsys, tmp_path):
    import hashlib

    src = CASES / "lecture.toml"
    code, _, err = run(capsys, "profile", src, "-o", tmp_path / "mm.nc", "--cutter-radius", 5, "--feed", 254)
    assert code == 0, err
    code, _, err = run(
        capsys, "profile", src, "-o", tmp_path / "in.nc", "--cutter-radius", 5, "--feed", 254, "--units", "in"
    )
    assert code == 0, err
    mm, inch = (tmp_path / "mm.nc").read_text(), (tmp_path / "in.nc").read_text()
    assert hashlib.sha256(src.read_bytes()).hexdigest() in mm and "lecture" in mm
    assert "cutter radius 5 mm" in mm and "chord tolerance 0.01 mm" in mm
    assert "G21" in mm and "G20" in inch and "G21" not in inch
    assert "F254.00" in mm and "F10.000" in inch  # 254 mm/min is 10 in/min
    a, _ = _gcode_points(mm)
    b, _ = _gcode_points(inch, scale=25.4)
    np.testing.assert_allclose(a, b, atol=2e-5)


def test_climb_runs_clockwise_conventional_counterclockwise(capsys, tmp_path):
    src = CASES / "lecture.toml"
    area = {}
    for sense in ("--climb", "--conventional"):
        out = tmp_path / f"{sense[2:]}.nc"
        assert run(capsys, "profile", src, "-o", out, "--cutter-radius", 3, sense)[0] == 0
        p, _ = _gcode_points(out.read_text())
        area[sense] = 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
    assert area["--climb"] < 0 < area["--conventional"]


@pytest.mark.slow
def test_a_concave_stretch_tighter_than_the_cutter_is_refused(capsys, tmp_path):
    src = _case_file(tmp_path, "concave")
    _, geo = _geometry(src)
    rho = geo.table(np.arange(36000) * 0.01)["rho_contour_mm"]
    least = float(np.min(-rho[rho < 0]))
    assert 3.0 < least < 30.0  # the case is what it says
    code, _, err = run(capsys, "profile", src, "-o", tmp_path / "big.nc", "--cutter-radius", least + 1.0)
    assert code == 2 and not (tmp_path / "big.nc").exists()
    assert "concave" in err and "deg" in err and err.count("\n") == 1
    fits = float(re.search(r"largest cutter that fits has radius ([\d.]+) mm", err).group(1))
    assert fits == pytest.approx(least - 0.005, abs=2e-3)
    out = tmp_path / "fits.nc"
    code, _, err = run(capsys, "profile", src, "-o", out, "--cutter-radius", fits * 0.98)
    assert code == 0, err
    d = distance_to_outline(_gcode_points(out.read_text())[0], _dense_outline(geo))
    assert d.min() >= fits * 0.98 - 1e-5


def test_wrong_options_are_refused_in_one_line(capsys, tmp_path):
    src = CASES / "lecture.toml"
    for argv, where in [
        (["-o", tmp_path / "a.nc"], "--cutter-radius"),
        (["-o", tmp_path / "a.dxf", "--cutter-radius", 3], "--cutter-radius"),
        (["-o", tmp_path / "a.csv", "--arcs"], "--arcs"),
        (["-o", tmp_path / "a.nc", "--cutter-radius", -1], "--cutter-radius"),
        (["-o", tmp_path / "a.csv", "--grinder-wheel-radius", 100, "--follower-lift"], "--follower-lift"),
        (["-o", tmp_path / "a.nc", "--cutter-radius", 3, "--tolerance", 1e-5], "--tolerance"),
        (["-o", tmp_path / "a.csv", "--grinder-wheel-radius", 100, "--tolerance", "inf"], "--tolerance"),
        (["-o", tmp_path / "a.csv", "--follower-lift", "--step", 0], "--step"),
    ]:
        code, _, err = run(capsys, "profile", src, *argv)
        assert code == 2 and where in err and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []


def _wheel_reach(outline: np.ndarray, theta_deg: np.ndarray, rw: float, sigma: float) -> np.ndarray:
    """Independently: the cam turned to each angle, the farthest wheel centre on the +y axis that touches it."""
    out = np.empty(len(theta_deg))
    for i, th in enumerate(np.deg2rad(theta_deg)):
        c, s = math.cos(sigma * th), math.sin(sigma * th)
        turned = outline @ np.array([[c, s], [-s, c]])  # R(sigma theta) p: the cam frame seen in the fixed frame
        x, y = turned.T
        ok = np.abs(x) <= rw
        out[i] = np.max(y[ok] + np.sqrt(rw * rw - x[ok] ** 2))
    return out


@pytest.mark.parametrize(
    "name, rw",
    [
        ("lecture.toml", 150.0),
        pytest.param("oscillating.toml", 10.0, marks=pytest.mark.slow),  # its geometry's own programs: 2 s
        ("valve-lift.toml", 200.0),
    ],
)
def test_grinder_wheel_touches_the_turned_cam_and_cuts_nowhere(capsys, tmp_path, name, rw):
    src = _case_file(tmp_path, name)
    case, geo = _geometry(src)
    out = tmp_path / "grind.csv"
    code, _, err = run(capsys, "profile", src, "-o", out, "--grinder-wheel-radius", rw, "--step", 2)
    assert code == 0, err
    rows = list(csv.DictReader(out.open()))
    theta = np.array([float(r["theta_deg"]) for r in rows])
    d = np.array([float(r["wheel_center_mm"]) for r in rows])
    np.testing.assert_allclose(theta, np.arange(0, 360, 2.0))
    outline = _dense_outline(geo, 100_000)
    sigma = case.follower.sigma
    np.testing.assert_allclose(d, _wheel_reach(outline, theta, rw, sigma), atol=1e-5)
    # the wheel centre, in the cam frame: Rw from the outline
    for th, di in zip(np.deg2rad(theta[::5]), d[::5], strict=True):
        centre = di * np.array([math.sin(sigma * th), math.cos(sigma * th)])
        gap = np.min(np.hypot(*(outline - centre).T))
        assert rw - 1e-6 <= gap <= rw + 1e-4  # touches, never enters (the dense sample's spacing is ~0.005 mm)


def test_grinder_table_of_a_centred_roller_is_its_pitch_radius(capsys, tmp_path):
    """A wheel the size of a centred follower's roller grinds exactly the roller centre's path: Rb + Rr + s."""
    text = (CASES / "lecture.toml").read_text().replace("offset = 5", "offset = 0")
    src = tmp_path / "centred.toml"
    src.write_text(text)
    case, _ = _geometry(src)
    out = tmp_path / "grind.csv"
    assert run(capsys, "profile", src, "-o", out, "--grinder-wheel-radius", 10)[0] == 0
    t, d = np.loadtxt(out, delimiter=",", skiprows=1).T
    s = np.asarray(evaluate(case.motion, np.deg2rad(t)))[0]
    np.testing.assert_allclose(d, 40.0 + 10.0 + s, atol=1e-6)
    assert len(t) == 720  # the default step is 0.5 deg


def test_follower_lift_table_and_inches(capsys, tmp_path):
    src = CASES / "lecture.toml"
    case, _ = _geometry(src)
    assert run(capsys, "profile", src, "-o", tmp_path / "lift.csv", "--follower-lift", "--step", 1)[0] == 0
    assert (
        run(capsys, "profile", src, "-o", tmp_path / "lift-in.csv", "--follower-lift", "--step", 1, "--units", "in")[0]
        == 0
    )
    head = (tmp_path / "lift.csv").read_text().splitlines()[0]
    assert head == "theta_deg,lift_mm" and (tmp_path / "lift-in.csv").read_text().startswith("theta_deg,lift_in\n")
    t, s = np.loadtxt(tmp_path / "lift.csv", delimiter=",", skiprows=1).T
    np.testing.assert_allclose(s, np.asarray(evaluate(case.motion, np.deg2rad(t)))[0], atol=1e-6)
    _, s_in = np.loadtxt(tmp_path / "lift-in.csv", delimiter=",", skiprows=1).T
    np.testing.assert_allclose(s_in * 25.4, s, atol=1e-5)
    osc = CASES / "oscillating.toml"
    assert run(capsys, "profile", osc, "-o", tmp_path / "osc.csv", "--follower-lift")[0] == 0
    assert (tmp_path / "osc.csv").read_text().startswith("theta_deg,lift_deg\n")


@pytest.mark.parametrize("suffix", [".csv", ".dxf", ".svg"])
def test_outline_in_inches_is_the_mm_outline_over_25_4(capsys, tmp_path, suffix):
    import ezdxf

    src = CASES / "lecture.toml"
    mm, inch = tmp_path / f"mm{suffix}", tmp_path / f"in{suffix}"
    assert run(capsys, "profile", src, "-o", mm)[0] == 0
    assert run(capsys, "profile", src, "-o", inch, "--units", "in")[0] == 0
    if suffix == ".csv":
        assert inch.read_text().startswith("x_in,y_in\n")
        a, b = (np.loadtxt(p, delimiter=",", skiprows=1) for p in (mm, inch))
    elif suffix == ".dxf":
        docs = [ezdxf.readfile(p) for p in (mm, inch)]
        assert (docs[0].units, docs[1].units) == (ezdxf.units.MM, ezdxf.units.IN)
        a, b = (np.array([p[:2] for p in d.modelspace().query("LWPOLYLINE")[0].get_points()]) for d in docs)
    else:
        assert 'width="' in inch.read_text() and 'in" height' in inch.read_text()
        a, b = (
            np.array(re.search(r'points="([^"]+)"', p.read_text()).group(1).replace(",", " ").split(), float)
            for p in (mm, inch)
        )
    np.testing.assert_allclose(b * 25.4, a, atol=2e-4)


def _ecam(capsys, tmp_path, src: Path, n: int):
    out = tmp_path / f"ecam-{n}.csv"
    code, _, err = run(capsys, "table", src, "--ecam", n, "-o", out)
    assert code == 0, err
    lines = out.read_text().splitlines()
    assert lines[0].startswith("# ") and "per master degree" in lines[0]
    assert lines[1] == "master_deg,position,velocity,acceleration"
    return lines[0], np.loadtxt(out, delimiter=",", skiprows=2).T


@pytest.mark.parametrize("name, unit", [("lecture.toml", "mm"), ("oscillating.toml", "deg")])
def test_ecam_velocity_and_acceleration_are_the_derivatives_of_position(capsys, tmp_path, name, unit):
    header, (m, s, v, a) = _ecam(capsys, tmp_path, CASES / name, 7200)
    assert f"position {unit}; velocity {unit}/deg; acceleration {unit}/deg^2" in header.split(": ", 1)[1]
    np.testing.assert_allclose(m, np.arange(7200) * 0.05)
    h = 0.05  # deg: periodic central differences, error h^2 / 6 times the next derivative
    dv = (np.roll(s, -1) - np.roll(s, 1)) / (2 * h)
    da = (np.roll(v, -1) - np.roll(v, 1)) / (2 * h)
    case, _ = _geometry(CASES / name)  # a difference across a segment's end sees the jump in the law's next derivative
    breaks = np.asarray(case.motion.breaks_deg, float)
    smooth = np.min(np.abs((m[:, None] - breaks[None] + 180.0) % 360.0 - 180.0), axis=1) > 1.5 * h
    assert smooth.sum() > 7000
    assert np.max(np.abs(dv - v)[smooth]) <= 1e-5 * np.max(np.abs(v))
    assert np.max(np.abs(da - a)[smooth]) <= 1e-4 * np.max(np.abs(a))
    assert np.max(np.abs(dv - v)) <= 5e-4 * np.max(np.abs(v))  # at a break too: velocity is continuous


@pytest.mark.slow  # the table's dynamic columns compile the shooting
@pytest.mark.parametrize("name", ["lecture.toml", "oscillating.toml"])
def test_ecam_equals_the_tables_columns_per_master_degree(capsys, tmp_path, name):
    _, (m, s, v, a) = _ecam(capsys, tmp_path, CASES / name, 360)
    code, out, err = run(capsys, "table", CASES / name, "--step", 1)
    assert code == 0, err
    rows = list(csv.DictReader(out.splitlines()))

    def col(k):
        return np.array([float(r[k]) for r in rows])

    np.testing.assert_allclose(col("theta_deg"), m)
    per_deg = math.pi / 180
    if "s_mm" in rows[0]:
        ts, tv, ta = col("s_mm"), col("v_mm_per_rad") * per_deg, col("a_mm_per_rad2") * per_deg**2
    else:  # oscillating: deg, rad/rad = deg/deg, rad/rad^2 -> deg/deg^2
        ts, tv, ta = col("phi_deg"), col("phi1_per_rad"), col("phi2_per_rad2") * per_deg
    np.testing.assert_allclose(s, ts, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(v, tv, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(a, ta, rtol=1e-8, atol=1e-12)


def test_ecam_bad_count_is_one_line(capsys, tmp_path):
    code, _, err = run(capsys, "table", CASES / "lecture.toml", "--ecam", 1)
    assert code == 2 and "--ecam" in err and err.count("\n") == 1
