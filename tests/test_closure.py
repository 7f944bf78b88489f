"""Form-closed cams (issue 25): the groove's schema, its two walls, the signed contact force and its crossovers,
and the flight across the backlash."""

import copy
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from _helpers import (
    assert_pages_inked,
    check_json,
    check_value,
    constant_velocity_landing,
    distance_to_outline,
    drawn_pages,
    figure_text,
    host,
    omega,
    run,
    write_case,
)
from scipy.integrate import solve_ivp

from camdyn import InputError
from camdyn.model.case import case_from_dict
from camdyn.model.dynamics import closure_response
from camdyn.model.geometry import analyze, groove

ROOT = Path(__file__).resolve().parents[1]

GROOVE_TOML = """
name = "groove"
[motion]
segments = [
  { law = "cycloidal", end = 120, lift = 20 },
  { law = "dwell", end = 180 },
  { law = "cycloidal", end = 300, lift = -20 },
  { law = "dwell", end = 360 },
]
[follower]
type = "translating-roller"
base_radius = 50
roller_radius = 12
closure = "groove"
backlash = 0.05
[dynamics]
speed = 300
mass = 1.0
train_stiffness = 5000
"""
GROOVE = tomllib.loads(GROOVE_TOML)


def case_geometry_pitch(case, n: int) -> np.ndarray:
    """The pitch curve (2, n), mm, on n equal steps."""
    return analyze(case.motion, case.follower, n=n).pitch


def _with(table: str, **keys) -> dict:
    raw = copy.deepcopy(GROOVE)
    raw[table].update(keys)
    return raw


def test_groove_needs_no_spring():
    case = case_from_dict(GROOVE)
    assert case.follower.form_closed and case.follower.backlash == 0.05
    assert float(case.model.stiffness) == 0.0 and float(case.model.preload) == 0.0
    assert case.limits.max_impact_velocity == 0.1


@pytest.mark.parametrize(
    ("table", "keys", "where", "match"),
    [
        ("follower", {"closure": "spring"}, "follower.backlash", "not used"),
        ("follower", {"type": "translating-flat", "roller_radius": None}, "follower.closure", "holds a roller"),
        ("follower", {"backlash": -1}, "follower.backlash", "greater than or equal"),
        ("limits", {"max_impact_velocity": 0}, "limits.max_impact_velocity", "greater than"),
    ],
)
def test_groove_keys_refused(table, keys, where, match):
    raw = _with(table, **keys) if table in GROOVE else dict(copy.deepcopy(GROOVE), **{table: keys})
    raw[table] = {k: v for k, v in raw[table].items() if v is not None}
    with pytest.raises(InputError, match=match) as err:
        case_from_dict(raw)
    assert err.value.where == where


def test_spring_closure_still_needs_the_spring():
    raw = _with("follower", closure="spring")
    del raw["follower"]["backlash"]
    with pytest.raises(InputError, match="required key is missing") as err:
        case_from_dict(raw)
    assert err.value.where == "dynamics.spring_rate"


def test_groove_walls_lie_at_roller_radius_plus_half_backlash():
    """Each wall lies Rr + b/2 from the pitch curve (its distance from a dense pitch polyline), and on a dwell at
    the closed-form radii Rb + s - b/2 and Rb + 2 Rr + s + b/2 with radii of curvature -+(Rp + s) - d."""
    case = case_from_dict(GROOVE)
    g = groove(case.motion, case.follower, n=3600)
    rb, rr, b = 50.0, 12.0, 0.05
    d = rr + b / 2
    assert g.wall_offset_mm == pytest.approx(d)
    pitch = np.asarray(case_geometry_pitch(case, 40_000))
    for wall in (g.inner, g.outer):
        dist = distance_to_outline(wall[:, ::7].T, pitch.T)
        assert np.max(np.abs(dist - d)) < 2e-4  # the polyline's chord error at 40 000 points is ~1e-5 mm
    i = int(np.argmin(np.abs(g.theta_deg - 150.0)))  # on the top dwell: lift 20
    assert np.hypot(*g.inner[:, i]) == pytest.approx(rb + 20 - b / 2, abs=1e-9)
    assert np.hypot(*g.outer[:, i]) == pytest.approx(rb + 2 * rr + 20 + b / 2, abs=1e-9)
    assert g.rho_inner_mm[i] == pytest.approx(rb + rr + 20 - d, rel=1e-9)
    assert g.rho_outer_mm[i] == pytest.approx(-(rb + rr + 20 + d), rel=1e-9)
    # one wall concave where the other is convex
    assert np.all(np.sign(g.rho_inner_mm + d) == -np.sign(g.rho_outer_mm + d))
    assert not g.undercut and g.outer_wall.min_convex_radius_mm > 0


def test_groove_wall_undercut_where_the_pitch_curve_turns_tighter_than_the_wall():
    """A concave stretch of the pitch curve tighter than Rr + b/2 folds the outer wall, not the inner."""
    raw = _with("follower", base_radius=25, roller_radius=10)
    raw["motion"]["segments"][0] = {"law": "cycloidal", "end": 40, "lift": 20}
    raw["motion"]["segments"][1] = {"law": "dwell", "end": 180}
    case = case_from_dict(raw)
    g = groove(case.motion, case.follower, n=3600)
    assert g.outer_wall.undercut and not g.inner_wall.undercut
    assert g.outer_wall.min_convex_radius_mm < 0 < g.inner_wall.min_convex_radius_mm
    rho_p = analyze(case.motion, case.follower, n=3600).rho_pitch_mm  # the spring cam's pitch curve
    assert g.outer_wall.min_convex_radius_mm == pytest.approx(np.max(rho_p[rho_p < 0]) * -1 - 10.025, abs=1e-3)


@pytest.mark.slow  # compiles the groove's model
def test_a_grooves_curvature_check_judges_both_walls():
    """The groove whose outer wall folds (above): ``check``'s curvature is the least convex radius of either wall
    over the roller radius, the outer wall's (negative: folded), not the spring cam's contour's."""
    from camdyn.design.checks import run_check

    raw = _with("follower", base_radius=25, roller_radius=10)
    raw["motion"]["segments"][0] = {"law": "cycloidal", "end": 40, "lift": 20}
    raw["motion"]["segments"][1] = {"law": "dwell", "end": 180}
    report = run_check(case_from_dict(raw))
    curvature = next(c for c in report.checks if c.name == "curvature")
    assert report.closure is not None and report.geometry is not None and curvature.value is not None
    walls = report.closure.groove
    assert curvature.value == pytest.approx(walls.outer_wall.min_convex_radius_mm / 10.0, rel=1e-12)
    assert curvature.value < 0 < report.geometry.extremes.curvature and not curvature.ok


def _groove_case(backlash: float, fall: str = "polynomial-345", **dynamics):
    raw = _with("follower", backlash=backlash)
    raw["motion"]["segments"][2]["law"] = fall
    raw["dynamics"].update(dynamics)
    if backlash == 0.0:
        del raw["follower"]["backlash"]
    return case_from_dict(raw)


def test_crossovers_fall_where_the_acceleration_changes_sign():
    """No spring, no external force: Fi = m w^2 s'', so the force changes flank at mid-rise of the cycloidal rise
    (60 deg) and mid-fall of the 3-4-5 fall (240 deg), and nowhere on the dwells (where it is zero)."""
    case = _groove_case(0.0)
    r = closure_response(case.motion, case.follower, case.model, omega(case))
    assert [(c.from_flank, c.to_flank) for c in r.crossovers] == [("inner", "outer"), ("outer", "inner")]
    assert [c.deg for c in r.crossovers] == pytest.approx([60.0, 240.0], abs=1e-8)
    assert all(c.impact_velocity_m_per_s == 0.0 and c.land_deg == c.deg for c in r.crossovers)
    # signed: positive (inner flank) in the first half of the rise, negative (outer) in the second
    i, j = int(np.argmin(np.abs(r.theta_deg - 30))), int(np.argmin(np.abs(r.theta_deg - 90)))
    assert r.contact_force[i] > 0 > r.contact_force[j]
    vals = host(case, np.deg2rad(r.theta_deg))
    np.testing.assert_allclose(r.contact_force, 1.0 * omega(case) ** 2 * vals[2] * 1e-3, rtol=1e-12, atol=1e-12)


@pytest.mark.slow  # compiles the groove's diffrax model
def test_flight_across_the_backlash_lands_where_the_closed_form_says():
    """No spring: the roller leaves the inner flank at mid-rise with the cam's velocity and keeps it; the outer
    flank meets it where s'(tc) d - (s(tc + d) - s(tc)) = G, G = b / cos(phi) the gap along the follower's axis
    (tan phi = s' / (Rp + s), zero offset), at the relative speed (s'(tc) - s'(tc + d)) w."""
    b = 0.05
    case = _groove_case(b, train_stiffness=5000)
    w = omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    c = r.crossovers[0]
    tc = np.deg2rad(60.0)
    s = lambda t: host(case, t)[:, 0]  # noqa: E731
    s0 = s(tc)
    gap = b * np.hypot(1.0, s0[1] / (62.0 + s0[0]))
    d = constant_velocity_landing(case, tc, gap)
    v = (s0[1] - s(tc + d)[1]) * w * 1e-3
    assert np.deg2rad(c.land_deg) - tc == pytest.approx(d, rel=1e-6)
    assert c.impact_velocity_m_per_s == pytest.approx(v, rel=1e-6)
    # the impact through the train: scipy's DOP853 at tight tolerance from the closed-form landing, the roller
    # pressed on the outer flank (at s + G/2) by k_f (x - s - G/2) + c_f w (x' - s'), the peak over a contact period
    kf, cf = float(case.model.train_stiffness), float(case.model.train_damping)
    t1 = tc + d
    x1 = s0[0] - gap / 2 + s0[1] * d  # mm: the roller at constant velocity since it left the inner flank

    def flank(t, y):
        sv = s(t)
        f = max(0.0, kf * (y[0] - sv[0] - gap / 2) * 1e-3 + cf * w * (y[1] - sv[1]) * 1e-3)
        return [y[1], -f / (1.0 * w**2 * 1e-3)]

    span = w * 2 * np.pi / np.sqrt(kf / 1.0)
    ts = np.linspace(t1, t1 + span, 20001)
    sol = solve_ivp(flank, (t1, t1 + span), [x1, s0[1]], "DOP853", t_eval=ts, rtol=1e-12, atol=1e-14)
    sv = host(case, ts)
    peak = np.max(kf * (sol.y[0] - sv[0] - gap / 2) * 1e-3 + cf * w * (sol.y[1] - sv[1]) * 1e-3)
    assert c.impact_force_N == pytest.approx(peak, rel=1e-5)
    # under the half-sine on the flank's steady force (the closed form of a stiff undamped train), and near it
    half_sine = abs(w**2 * s(t1)[2] * 1e-3) + v * np.sqrt(kf * 1.0)
    assert 0.9 * half_sine < c.impact_force_N < half_sine
    assert r.max_impact_velocity_m_per_s == max(x.impact_velocity_m_per_s for x in r.crossovers)
    k0 = int(np.ceil(np.rad2deg(tc) * 10 + 1e-9))
    assert r.contact_force[k0] == 0.0  # in flight: on neither flank


@pytest.mark.slow  # compiles the groove cam's flight model (4-5 s)
@pytest.mark.parametrize("rpm", [300, 3000])
def test_flight_under_a_spring_matches_a_second_integrator(rpm):
    """With a spring and damper in the groove the flight is no longer at constant velocity: scipy's DOP853 at
    tight tolerance, from each crossover, meets the same flank at the same angle and speed (at 3000 rpm the roller
    drifts across the top dwell and the falling outer flank catches it: a flight back onto the flank it left)."""
    case = _groove_case(0.2, spring_rate=1.0, preload=5.0, damping_ratio=0.1, speed=rpm)
    w = omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    assert len(r.crossovers) >= 2
    m, k, c, f0 = (float(x) for x in (case.model.mass, case.model.stiffness, case.model.damping, case.model.preload))
    motion = lambda t: host(case, t)[:, 0]  # noqa: E731

    def field(t, y):  # x in mm, p = dx/dtheta: m w^2 x'' = -(k x + F0 + c w x'), SI inside
        return [y[1], -(k * y[0] * 1e-3 + f0 + c * w * y[1] * 1e-3) / (m * w**2 * 1e-3)]

    for x in r.crossovers:
        side = 1.0 if x.from_flank == "inner" else -1.0
        tc = np.deg2rad(x.deg)
        s0 = motion(tc)
        gap = 0.2 * np.hypot(1.0, s0[1] / (62.0 + s0[0]))
        other = lambda t, y, side=side, gap=gap: side * (y[0] - motion(t)[0]) - gap / 2  # noqa: E731
        same = lambda t, y, side=side, gap=gap: -side * (y[0] - motion(t)[0]) - gap / 2 - 1e-9  # noqa: E731
        for ev in (other, same):
            ev.terminal, ev.direction = True, 1.0
        sol = solve_ivp(
            field,
            (tc, tc + 2 * np.pi),
            [s0[0] - side * gap / 2, s0[1]],
            "DOP853",
            events=(other, same),
            rtol=1e-12,
            atol=1e-13,
        )
        hit = 0 if sol.t_events[0].size else 1
        assert (x.to_flank != x.from_flank) == (hit == 0)
        t1, y1 = sol.t_events[hit][0], sol.y_events[hit][0]
        assert np.deg2rad(x.land_deg) == pytest.approx(t1 % (2 * np.pi), abs=1e-7)
        v = abs(y1[1] - motion(t1)[1]) * w * 1e-3
        assert x.impact_velocity_m_per_s == pytest.approx(v, rel=1e-5, abs=1e-9)


def test_profile_writes_both_walls(tmp_path, capsys):
    """DXF: one layer per wall; CSV: an ``outline`` column; each wall within the tolerance of Rr + b/2 from the
    pitch curve. A cutter path of a groove is refused (not built)."""
    import ezdxf

    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    assert run(capsys, "profile", case_file, "-o", tmp_path / "g.dxf")[0] == 0
    doc = ezdxf.readfile(tmp_path / "g.dxf")
    layers = {e.dxf.layer: np.array([p[:2] for p in e.get_points()]) for e in doc.modelspace()}
    assert set(layers) == {"GROOVE_INNER", "GROOVE_OUTER"}
    pitch = case_geometry_pitch(case_from_dict(GROOVE), 40_000)
    for xy in layers.values():
        assert np.max(np.abs(distance_to_outline(xy, pitch.T) - 12.025)) < 0.011
    assert run(capsys, "profile", case_file, "-o", tmp_path / "g.csv")[0] == 0
    rows = np.genfromtxt(tmp_path / "g.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert set(rows["outline"]) == {"groove_inner", "groove_outer"}
    code, _, err = run(capsys, "profile", case_file, "-o", tmp_path / "g.nc", "--cutter-radius", 5)
    assert code == 2 and "follower.closure" in err


@pytest.mark.slow
def test_check_json_of_a_groove_cam(tmp_path, capsys):
    """``check --json``: the closure block (the contract's keys), crossover_impact judged against
    max_impact_velocity, no speed_margin and no least contact force (said, not an infinite margin); a tighter limit
    than the impact fails (exit 1)."""
    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    code, out, _ = run(capsys, "check", case_file, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["verdict"] == "pass"
    cl = doc["closure"]
    assert cl["type"] == "groove" and cl["backlash_mm"] == 0.05
    assert [round(c["deg"], 6) for c in cl["crossovers"]] == [60.0, 240.0]
    assert {"deg", "impact_velocity_m_per_s", "impact_force_N"} <= set(cl["crossovers"][0])
    top = max(c["impact_force_N"] for c in cl["crossovers"])
    assert cl["max_impact_force_N"] == top and doc["dynamic"]["max_impact_force_N"] == top
    names = [c["name"] for c in doc["checks"]]
    assert "crossover_impact" in names and "speed_margin" not in names and "contact_force" not in names
    impact = doc["checks"][names.index("crossover_impact")]
    assert impact["value"] == pytest.approx(0.031439, rel=1e-4) and impact["limit"] == 0.1
    assert doc["kinematic"]["jump_speed_rpm"] is None
    assert any("speed_margin" in w and "do not apply" in w for w in doc["warnings"])
    case_file.write_text(GROOVE_TOML + "[limits]\nmax_impact_velocity = 0.02\n")
    assert run(capsys, "check", case_file)[0] == 1


@pytest.mark.slow
def test_table_contact_force_is_signed(tmp_path, capsys):
    """``table``: contact_force_N positive on the inner flank, negative on the outer; the dynamic column is zero
    while the follower crosses the backlash (60 to 68.8 deg)."""
    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    code, out, _ = run(capsys, "table", case_file, "--step", 1)
    assert code == 0
    rows = np.genfromtxt(out.splitlines(), delimiter=",", names=True)
    by = {int(t): r for t, r in zip(rows["theta_deg"], rows, strict=True)}
    assert by[30]["contact_force_N"] > 0 > by[90]["contact_force_N"]
    assert by[65]["dynamic_contact_force_N"] == 0.0 and by[75]["dynamic_contact_force_N"] < 0


@pytest.mark.parametrize(
    "argv",
    [
        ["spring"],
        ["optimize", "-o", "r"],
        ["size", "--buildable"],
    ],
)
def test_spring_held_studies_refuse_a_groove_cam(tmp_path, capsys, argv):
    """They design a return spring or a motion for a follower that may jump: one line naming follower.closure (or the
    spring's flag), exit 2, nothing written."""
    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    argv = [a if a != "r" else tmp_path / "r" for a in argv]
    code, out, err = run(capsys, argv[0], case_file, *argv[1:])
    assert code == 2 and len(err.strip().splitlines()) == 1 and "no return spring" in err
    assert "follower.closure" in err or "--buildable" in err
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize(
    "case, old, new, argv",
    [
        ("machines/infeed.toml", "arm_length = 150", "arm_length = 75", ["check"]),
        ("machines/infeed.toml", "arm_length = 150", "arm_length = 75", ["table", "-o", "t.csv"]),
        ("oscillating.toml", "arm_length = 90", "arm_length = 50", ["spring"]),
    ],
)
def test_an_arm_that_cannot_reach_its_cam_is_refused_by_every_command(tmp_path, capsys, case, old, new, argv):
    """The infeed's groove cam with its arm shortened to 75 mm on a 180 mm pivot: the roller's centre comes no
    nearer the cam's than 105 mm, its prime circle is 90 mm. One line naming follower.arm_length, as `profile`
    gave; `check` and `table` ran the groove's dynamics first and stopped on "crossover at 90.00 deg: the follower
    never met the other flank", and `spring` designed a return spring for such an arm."""
    text = (ROOT / "cases" / case).read_text()
    assert old in text
    case_file = tmp_path / "short-arm.toml"
    case_file.write_text(text.replace(old, new, 1))
    argv = [tmp_path / a if a == "t.csv" else a for a in argv]
    code, _, err = run(capsys, argv[0], case_file, *argv[1:])
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert ": follower.arm_length: the roller cannot reach the prime circle" in err
    assert not (tmp_path / "t.csv").exists()


# slow: the oscillating groove's flight compiles alone (seconds); the quick set keeps the translating groove's
# (test_flight_across_the_backlash_lands_where_the_closed_form_says)
@pytest.mark.slow
def test_oscillating_groove_cam_crosses_at_mid_rise_and_lands_as_the_closed_form_says():
    """The cartoner's infeed arm in its groove (no spring): the force changes flank at mid-rise and mid-return of its
    modified-sine swings (90 and 260 deg); the arm keeps its angular velocity across the gap b / (a cos phi) (rad) and
    the flank meets the roller at a (phi'(tc) - phi'(tc + d)) w; the impact force at the roller is the arm's torque
    plus w_rel sqrt(k_f I) (less a few percent of train damping), over the lever arm a cos phi at the landing."""
    from pathlib import Path

    from camdyn.model.case import load_case

    case = load_case(Path(__file__).resolve().parents[1] / "cases" / "machines" / "infeed.toml")
    w = omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    assert [c.deg for c in r.crossovers] == pytest.approx([90.0, 260.0], abs=1e-8)
    geo = analyze(case.motion, case.follower)
    a_m, b = 0.150, 0.05
    phi = lambda t: host(case, t)[:, 0]  # noqa: E731
    for c in r.crossovers:
        tc = np.deg2rad(c.deg)
        p0 = phi(tc)
        side = 1.0 if c.from_flank == "inner" else -1.0
        gap = b / (150.0 * np.cos(np.deg2rad(geo.table([c.deg])["pressure_angle_deg"][0])))
        d = constant_velocity_landing(case, tc, gap, side)  # the gap closed at constant arm velocity
        assert np.deg2rad(c.land_deg) - tc == pytest.approx(d, rel=1e-6)
        w_rel = abs(p0[1] - phi(tc + d)[1]) * w
        assert c.impact_velocity_m_per_s == pytest.approx(w_rel * a_m, rel=1e-6)
        lever_m = a_m * np.cos(np.deg2rad(geo.table([c.land_deg])["pressure_angle_deg"][0]))
        torque = abs(0.06 * w**2 * phi(tc + d)[2])
        # the train's contact (damping ratio 0.05) peaks a few percent under the undamped half-sine's closed form
        half_sine = (torque + w_rel * np.sqrt(20000 * 0.06)) / lever_m
        assert 0.94 * half_sine < c.impact_force_N < half_sine


def test_groove_contact_stress_on_the_wall_the_force_presses():
    """Without backlash the inner wall is the spring cam's contour: where the force is positive the Hertz strip is
    the spring cam's (1/K = 1/(1/Rr + 1/(rho_p - Rr))); where negative the roller presses the concave-for-convex outer
    wall, 1/K = 1/(1/Rr - 1/(rho_p + Rr)), with the force's magnitude."""
    from camdyn.model.contact import cam_contact, groove_contact

    case = _groove_case(0.0)
    r = closure_response(case.motion, case.follower, case.model, omega(case))
    geo = analyze(case.motion, case.follower)
    walls = groove(case.motion, case.follower)
    mats = {"width_mm": 10.0, "cam": (206.0, 0.3), "follower": (206.0, 0.3)}
    got = groove_contact(geo, walls, r.contact_force, **mats)
    spring = cam_contact(geo, np.abs(r.contact_force), **mats)
    inner, outer = r.contact_force > 0, r.contact_force < 0
    np.testing.assert_allclose(got.pressure_MPa[inner], spring.pressure_MPa[inner], rtol=1e-12)
    rho_p, rr = geo.rho_pitch_mm[outer], 12.0
    np.testing.assert_allclose(got.equivalent_radius_mm[outer], 1 / (1 / rr - 1 / (rho_p + rr)), rtol=1e-12)
    assert np.all(got.pressure_MPa[outer] < spring.pressure_MPa[outer])  # conformal: gentler than convex


@pytest.mark.slow
def test_report_of_a_groove_cam(tmp_path, capsys):
    """``camdyn report``: the walls and crossovers pages in place of the cam, dynamics and spring-sizing pages; page 1
    says why there is no jump speed and gives each crossover's impact against the limit, as ``check`` does."""
    import re

    from camdyn.report import ReportData
    from camdyn.report.pages._facts import decision_facts, key_results

    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    doc = check_json(capsys, case_file)
    code, out, _ = run(capsys, "report", case_file, "-o", tmp_path / "r")
    assert code == 0
    pngs = sorted(p.name for p in (tmp_path / "r").glob("*.png"))
    slugs = [re.match(r"groove-\d+-([a-z-]+)\.png", p).group(1) for p in pngs]
    assert slugs == ["summary", "svaj", "groove", "crossovers", "parts", "manufacturing"]
    assert_pages_inked(tmp_path / "r")
    from camdyn.design.checks import run_check
    from camdyn.design.review import design_review

    case = case_from_dict(GROOVE)
    data = ReportData(design_review(case, run_check(case)))
    rows = dict(key_results(data))
    assert rows["jump speed"] == "none: form-closed" and "jump speed, dynamic" not in rows
    walls = doc["closure"]["walls"]  # the inner wall lies b/2 inside the cam's contour: page 1 gives the wall's
    inner, outer = (walls[w]["min_radius_of_curvature_mm"] for w in ("inner", "outer"))
    assert rows["inner wall, least radius"].startswith(f"{inner:.4g} mm at")
    curvature = next(c for c in doc["checks"] if c["name"] == "curvature")
    assert curvature["value"] == pytest.approx(min(inner, outer or math.inf) / 12.0, rel=1e-12)
    top = doc["closure"]["max_impact_velocity_m_per_s"]
    assert rows["largest impact"].startswith(f"{top:.3g} m/s")
    facts = decision_facts(data)
    assert "no jump speed and no speed_margin" in facts[0]
    for c, fact in zip(doc["closure"]["crossovers"], facts[1:], strict=True):
        assert f"{c['impact_velocity_m_per_s']:.3g} m/s (limit 0.1 m/s)" in fact and f"{c['deg']:.1f}" in fact
    assert not any("return spring cannot be built" in f or "leaves the cam" in f for f in facts)
    with_tol = case_from_dict(GROOVE | {"tolerances": {"backlash": "20%"}})
    assert any(
        f.startswith("[tolerances]") and "camdyn tolerance" in f
        for f in decision_facts(ReportData(design_review(with_tol, run_check(with_tol))))
    )
    # the impact speed against cam speed meets the check at the case's speed
    imp = data.review.impacts
    assert np.interp(300.0, imp.speeds_rpm, imp.impact_velocity_m_per_s[0]) == pytest.approx(top, rel=2e-3)
    text = {slug: figure_text(fig) for slug, fig in drawn_pages(data).items()}
    assert "does not apply: form-closed" in text["summary"] and "inner wall" in text["groove"]
    assert "Crossovers at 300 rpm" in text["crossovers"] and "return spring: none" in text["parts"]


@pytest.mark.slow  # a whole check, a sweep and its plot
def test_sweep_of_a_groove_cam_maps_the_impacts(tmp_path, capsys):
    """``sweep`` of a groove cam: the largest impact speed over speed x backlash. No spring: the flight across the
    gap takes the same cam angle at any speed, so the impact speed is proportional to the speed; at the case's
    speed and backlash it is check's crossover_impact; the gap closes against the cubic lead the cam gains from a
    crossover where s'' = 0 changes sign, so v grows as b^(2/3) for a small backlash."""
    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    doc = check_json(capsys, case_file)
    code, out, _ = run(capsys, "sweep", case_file, "--speeds", "100:300:3", "--backlash", "0.01:0.05:5", "-o", tmp_path)
    assert code == 0 and "cannot jump" in out
    rows = np.genfromtxt(tmp_path / "groove-sweep.csv", delimiter=",", names=True)
    assert rows.dtype.names == ("speed_rpm", "backlash_mm", "impact_velocity_m_per_s", "max_impact_force_N")
    v = rows["impact_velocity_m_per_s"].reshape(5, 3)  # backlash x speed
    np.testing.assert_allclose(v[:, 2] / v[:, 0], 3.0, rtol=1e-6)
    impact = check_value(doc, "crossover_impact")
    assert v[4, 2] == pytest.approx(impact, rel=1e-9)
    assert v[1, 0] / v[0, 0] == pytest.approx(2.0 ** (2 / 3), rel=0.02)
    assert (tmp_path / "groove-sweep.png").stat().st_size > 10_000
    code, _, err = run(capsys, "sweep", case_file, "--speeds", "100:300:3", "--spring-rates", "1:2:2", "-o", tmp_path)
    assert code == 2 and "--spring-rates" in err and "no return spring" in err


def test_sweep_backlash_of_a_spring_held_cam_is_refused(tmp_path, capsys):
    spring = GROOVE_TOML.replace('closure = "groove"\nbacklash = 0.05\n', "")
    case_file = write_case(
        tmp_path,
        "spring.toml",
        spring.replace("train_stiffness = 5000", "train_stiffness = 5000\nspring_rate = 5\npreload = 100"),
    )
    code, _, err = run(capsys, "sweep", case_file, "--speeds", "100:300:3", "--backlash", "0.01:0.05:2")
    assert code == 2 and "--backlash" in err and "groove" in err


@pytest.mark.slow  # compiles the groove's tolerance programs
def test_tolerance_of_a_groove_cam_gives_the_impact_spread(tmp_path, capsys):
    """``tolerance`` of a groove cam over backlash, mass and speed: each built cam's impact is the one
    closure_response gives a case of its backlash, mass and speed; the probability is the share over the limit."""
    tol = '\n[limits]\nmax_impact_velocity = 0.031\n[tolerances]\nbacklash = "20%"\nmass = "5%"\nspeed = "10 rpm"\n'
    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML + tol)
    code, out, _ = run(capsys, "tolerance", case_file, "--samples", "12", "--json", "-o", tmp_path)
    assert code == 0
    doc = json.loads(out)
    rows = np.genfromtxt(tmp_path / "groove-tolerance.csv", delimiter=",", names=True)
    assert doc["samples"] == 12 and doc["closure"] == "groove" and doc["max_impact_velocity"] == 0.031
    v = rows["impact_velocity_m_per_s"]
    assert doc["probability_over_limit"] == pytest.approx(np.mean(v > 0.031)) and 0 < np.sum(rows["over_limit"]) < 12
    assert doc["impact_velocity_m_per_s"]["max"] == pytest.approx(v.max()) and doc["worst"][0]["sample"] == v.argmax()
    assert np.ptp(rows["backlash_mm"]) > 0 and np.ptp(rows["speed_rpm"]) > 0 and np.ptp(rows["mass_kg"]) > 0
    for i in (int(v.argmax()), int(v.argmin())):
        case = case_from_dict(
            _with("follower", backlash=float(rows["backlash_mm"][i]))
            | {"dynamics": GROOVE["dynamics"] | {"mass": float(rows["mass_kg"][i])}}
        )
        r = closure_response(case.motion, case.follower, case.model, rows["speed_rpm"][i] * np.pi / 30)
        assert v[i] == pytest.approx(r.max_impact_velocity_m_per_s, rel=1e-9)
        # the force is k_f times a penetration of microns on positions of mm: the CSV's 10 digits move the adaptive
        # steps, and the solver's tolerance on the positions is 1e-6 of the penetration
        assert rows["max_impact_force_N"][i] == pytest.approx(r.max_impact_force_N, rel=1e-5)
    case_file.write_text(GROOVE_TOML + "[tolerances]\nprofile_error = 0.005\n")
    code, _, err = run(capsys, "tolerance", case_file, "--samples", "4", "-o", tmp_path, "--force")
    assert code == 2 and "tolerances.profile_error" in err


def test_a_backlash_tolerance_needs_a_groove():
    raw = _with("follower", closure="spring")
    del raw["follower"]["backlash"]
    raw["dynamics"] |= {"spring_rate": 5.0, "preload": 100.0}
    raw["tolerances"] = {"backlash": "10%"}
    with pytest.raises(InputError, match="tolerances.backlash.*only a groove cam"):
        case_from_dict(raw)


@pytest.mark.slow  # a groove's crossing and impact programs and three checks (11 s of compile)
def test_size_of_a_groove_cam_gives_the_largest_backlash(tmp_path, capsys):
    """``size``: no spring to size; the largest backlash (to 0.001 mm) whose impact speed stays 2 % under the limit:
    check passes at it (away from the at-limit band), and 0.002 mm more would not keep that margin."""
    case_file = write_case(tmp_path, "groove.toml", GROOVE_TOML)
    code, out, _ = run(capsys, "size", case_file, "--json")
    doc = json.loads(out)
    b = doc["max_backlash_mm"]
    assert code == 0 and doc["backlash_mm"] == 0.05 and b > 0.05 and round(b, 3) == b
    impacts = []
    for gap in (b, b + 0.002):
        case_file.write_text(GROOVE_TOML.replace("backlash = 0.05", f"backlash = {gap}"))
        code, out, _ = run(capsys, "check", case_file, "--json")
        assert code == 0
        impacts.append(check_value(json.loads(out), "crossover_impact"))
    assert impacts[0] <= 0.98 * 0.1 < impacts[1]
    assert doc["impact_velocity_at_max_backlash_m_per_s"] == pytest.approx(impacts[0], rel=1e-12)


def test_each_groove_walls_least_circle_osculates_it():
    """The groove whose outer wall folds (above): each wall's least convex radius is drawn as a circle at its point
    on the exact wall, centred on the pitch curve's centre of curvature (|rho| + d from the pitch curve: the walls
    are its parallel curves), and the wall near it lies on that circle."""
    from camdyn.model.geometry import WALLS

    raw = _with("follower", base_radius=25, roller_radius=10)
    raw["motion"]["segments"][0] = {"law": "cycloidal", "end": 40, "lift": 20}
    raw["motion"]["segments"][1] = {"law": "dwell", "end": 180}
    case = case_from_dict(raw)
    g = groove(case.motion, case.follower, n=3600)
    for name in WALLS:
        point, centre, rho = g.least_circle(name)
        assert rho == getattr(g, f"{name}_wall").min_convex_radius_mm
        u = getattr(g, f"{name}_wall").min_convex_radius_at_deg / 360.0
        on = g.wall_fn(name)(np.array([u - 1e-4, u, u + 1e-4]))
        np.testing.assert_allclose(point, on[:, 1], atol=1e-9)
        pitch = 0.5 * (g.wall_fn("inner")(np.array([u])) + g.wall_fn("outer")(np.array([u])))[:, 0]
        assert np.hypot(*(centre - pitch)) == pytest.approx(abs(rho + g.wall_offset_mm), rel=1e-9)
        assert np.hypot(*(centre - point)) == pytest.approx(abs(rho), rel=1e-9)
        assert np.max(np.abs(np.hypot(*(on.T - centre).T) - abs(rho))) < 1e-4 * abs(rho)  # osculates: O(s^3)
    assert g.least_circle("outer")[2] < 0 < g.least_circle("inner")[2]  # the outer wall folds
