"""Valvetrains (issue 24): the [valvetrain] table, the two-mass model with lash and a seat, float and bounce.

Checked against independent routes: a stiff, lash-free train is one equivalent follower (its jump speed, rigid and
compliant cam contact); the valve lands at the closing ramp's speed at low cam speed (closed form); scipy's
solve_ivp at tight tolerance integrates the two-mass flight with the seat on its own equations.
"""

import copy
import json
import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from _helpers import run
from scipy.integrate import solve_ivp

from camdyn import InputError
from camdyn._core.units import RPM
from camdyn.design.review import _least_event_force, force_vs_speed
from camdyn.design.valvetrain import ramp_landings
from camdyn.model.case import case_from_dict
from camdyn.model.dynamics import _valvetrain as vtm
from camdyn.model.dynamics import (
    dynamic_jump_speed,
    float_speed,
    kinematic_jump_speed,
    valvetrain_response,
)

CASES = Path(__file__).resolve().parents[1] / "cases"
SHIPPED = tomllib.loads((CASES / "valvetrain.toml").read_text())

# a valve event with continuous jerk (4-5-6-7 rise and return): a stiff train rings only at jerk's jumps
R, M_CAM, M_VALVE, K, F0, C = 1.5, 0.10, 0.05, 30.0, 200.0, 15.0  # -, kg, kg, N/mm, N, N*s/m (at the valve)
EVENT = {
    "motion": {
        "segments": [
            {"law": "dwell", "end": 60},
            {"law": "polynomial-4567", "end": 180, "lift": 8.0},
            {"law": "polynomial-4567", "end": 300, "lift": -8.0},
            {"law": "dwell", "end": 360},
        ]
    },
    "follower": {"type": "translating-flat", "base_radius": 20, "face_width": 30, "rotation": "cw"},
}


def _valvetrain(train_stiffness=None, **valvetrain):
    dyn = {"speed": 3000, "spring_rate": K, "preload": F0, "damping": C, "restitution": 0.0}
    if train_stiffness is not None:
        dyn |= {"train_stiffness": train_stiffness, "train_damping_ratio": 0.05}
    vt = {"ratio": R, "lash": 0.0, "cam_side_mass": M_CAM, "valve_mass": M_VALVE, "stiffness": 1e6} | valvetrain
    return case_from_dict(copy.deepcopy(EVENT) | {"dynamics": dyn, "valvetrain": vt})


def _single(train_stiffness=None):
    """The equivalent follower written out by hand: mass m_cam + m_valve r^2, rate k r^2, preload F0 r, c r^2."""
    dyn = {"speed": 3000, "mass": M_CAM + M_VALVE * R**2, "spring_rate": K * R**2, "preload": F0 * R}
    dyn |= {"damping": C * R**2, "restitution": 0.0}
    if train_stiffness is not None:
        dyn |= {"train_stiffness": train_stiffness, "train_damping_ratio": 0.05}
    return case_from_dict(copy.deepcopy(EVENT) | {"dynamics": dyn})


def test_dynamics_refuses_mass_with_a_valvetrain():
    raw = copy.deepcopy(SHIPPED)
    raw["dynamics"]["mass"] = 0.2
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "dynamics.mass" and "cam_side_mass" in str(err.value) and "\n" not in str(err.value)
    raw = copy.deepcopy(SHIPPED)
    del raw["valvetrain"]["valve_mass"]
    with pytest.raises(InputError, match="required key is missing"):
        case_from_dict(raw)
    raw = copy.deepcopy(SHIPPED)
    raw["valvetrain"]["ratio"] = 0.0
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "valvetrain.ratio"


def test_case_model_is_the_equivalent_follower():
    case, single = _valvetrain(), _single()
    for key in ("mass", "stiffness", "preload", "damping", "external"):
        assert float(getattr(case.model, key)) == pytest.approx(float(getattr(single.model, key)), rel=1e-12)


@pytest.mark.slow
def test_stiff_train_floats_at_the_equivalent_followers_jump_speed_rigid_cam():
    case, single = _valvetrain(), _single()
    w_jump = kinematic_jump_speed(single.motion, single.model)[0]
    w_float = float_speed(case.motion, case.valvetrain, 1.5 * w_jump, width_rpm=0.5)
    assert w_float / RPM == pytest.approx(w_jump / RPM, rel=2e-3)


@pytest.mark.slow
def test_stiff_train_floats_at_the_equivalent_followers_jump_speed_compliant_cam():
    """The single follower's compliant contact carries the preload from the base circle on; the valvetrain's takes
    it up as the valve lifts (r F0 / k_f: 3 um here, 0.15 mm at 2000 N/mm, where the float speed is 0.4 % lower
    for that): the compliant jump speed (4662.5 rpm) is 0.26 % below the rigid one (4674.9), and the float speed
    must find the compliant one."""
    case, single = _valvetrain(train_stiffness=1e5), _single(train_stiffness=1e5)
    w_jump = dynamic_jump_speed(single.motion, single.model, w_max=6000 * RPM)
    w_rigid = kinematic_jump_speed(single.motion, single.model)[0]
    assert w_rigid / w_jump - 1.0 > 2e-3
    w_float = float_speed(case.motion, case.valvetrain, 1.5 * w_jump, width_rpm=0.5)
    assert w_float / RPM == pytest.approx(w_jump / RPM, rel=5e-4)


@pytest.mark.slow
@pytest.mark.parametrize("stiffness", [1e6, None])
def test_seating_velocity_at_low_speed_is_the_closing_ramps(stiffness):
    """The shipped case's closing ramp runs at 0.537148 mm/rad at the tappet: the valve lands at that times the
    ratio and the cam's angular speed (a stiff train, and a rigid one)."""
    raw = copy.deepcopy(SHIPPED)
    raw["valvetrain"].pop("stiffness")
    if stiffness is not None:
        raw["valvetrain"]["stiffness"] = stiffness
    case = case_from_dict(raw)
    omega = 300 * RPM
    resp = valvetrain_response(case.motion, case.valvetrain, omega)
    expected = 0.537148e-3 * raw["valvetrain"]["ratio"] * omega  # m/s
    assert resp.seating_velocity == pytest.approx(expected, rel=1e-3)
    # and where: the ramp reaches the lash (0.125 mm at the tappet) 7.33 deg into it (295 deg)
    assert resp.seating_deg == pytest.approx(295.0 + (0.225 - 0.125) / (0.537148 * math.pi / 180), abs=0.05)


def _solve_ivp_event(case, omega, lever=None):
    """The two-mass valvetrain with a compliant cam contact and train, on scipy's DOP853 from its own equations:
    the first seating (angle, speed) after the valve event and the bounce's height. ``lever``: x_c (m) -> (the
    lift through the rocker at the valve m, the ratio); default the case's constant ratio."""
    motion, vt = case.motion, case.valvetrain
    lash, m_c, m_v = (float(v) for v in (vt.lash, vt.cam_side_mass, vt.valve_mass))
    lever = lever or (lambda x, r=float(vt.ratio): (r * x, r))
    kt, ct, kf, cf = (
        float(v)
        for v in (vt.train.train_stiffness, vt.train.train_damping, vt.cam.train_stiffness, vt.cam.train_damping)
    )
    k, f0, c, e = float(vt.spring_rate), float(vt.preload), float(vt.spring_damping), float(vt.seat_restitution)
    hold = float(vt.tappet_force)

    def cam(theta):
        s, s1 = motion.host(np.asarray([theta]))[:2, 0] * 1e-3
        return s, s1 * omega

    def rhs(t, y, seated):
        xc, vc, xv, vv = y
        s, sd = cam(omega * t)
        f_cam = max(0.0, kf * (s - xc) + cf * (sd - vc)) if s > xc else 0.0
        g, r = lever(xc)
        d = g - lash - xv
        f_t = max(0.0, kt * d + ct * (r * vc - vv)) if d > 0 else 0.0
        a_v = 0.0 if seated else (f_t - (k * xv + f0 + c * vv)) / m_v
        return [vc, (f_cam - r * f_t - hold) / m_c, 0.0 if seated else vv, a_v]

    def lifts(t, y, seated):
        g, r = lever(y[0])
        d = g - lash
        return (kt * d + ct * r * y[1] if d > 0 else d) - f0

    def lands(t, y, seated):
        return y[2]

    lifts.terminal, lifts.direction = True, 1
    lands.terminal, lands.direction = True, -1
    apex = lambda t, y, seated: y[3]  # noqa: E731
    apex.terminal, apex.direction = True, -1
    opts = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-15}
    t0 = math.radians(0.0) / omega
    y0 = [float(motion.host(np.asarray([0.0]))[0, 0]) * 1e-3 - hold / kf, 0.0, 0.0, 0.0]  # at rest on the base circle
    up = solve_ivp(rhs, (t0, 2 * math.pi / omega), y0, events=lifts, args=(True,), **opts)
    down = solve_ivp(rhs, (up.t[-1], 2 * math.pi / omega), up.y[:, -1], events=lands, args=(False,), **opts)
    t_land, y_land = down.t[-1], down.y[:, -1].copy()
    y_land[2], y_land[3] = 0.0, -e * y_land[3]
    bounce = solve_ivp(rhs, (t_land, 2 * math.pi / omega), y_land, events=[apex, lands], args=(False,), **opts)
    return math.degrees(omega * t_land), -down.y[3, -1], float(bounce.y[2, -1])


@pytest.mark.slow
def test_two_mass_flight_and_seat_against_solve_ivp():
    """Past float (the cam contact opens over the nose) the two masses fly on the train and the valve lands and
    bounces: diffrax's event-driven march and scipy's DOP853 on the same physics written apart agree."""
    # a tappet spring keeps the follower on the cam while the lash is open: unloaded, it would flutter on its
    # compliant contact, a motion too sensitive to where it starts to compare two integrators on
    case = _valvetrain(train_stiffness=3000.0, stiffness=3000.0, lash=0.15, seat_restitution=0.4, tappet_force=20.0)
    omega = 4200 * RPM
    resp = valvetrain_response(case.motion, case.valvetrain, omega)
    assert resp.floated  # the case flies: a two-mass flight, not a driven motion
    land_deg, speed, height = _solve_ivp_event(case, omega)
    assert resp.seating_deg == pytest.approx(land_deg, abs=1e-5)  # 273.88088 deg
    assert resp.seating_velocity == pytest.approx(speed, rel=1e-6)  # 1.08377 m/s
    assert resp.bounce_height_mm == pytest.approx(height * 1e3, rel=1e-6)  # 0.033833 mm


@pytest.mark.slow
def test_a_cam_that_lets_go_at_an_acceleration_jump_floats_there():
    """A harmonic return straight after a 3-4-5 one: the cam's acceleration jumps at 210 deg, and with it the force a
    rigid cam contact holds the follower by, from +1243 N to -407 N at 3000 rpm. The float starts there. Diffrax
    steps to the float before the jump and reads the event past it, outside the step's bracket: the stretch once
    ended 0.04 deg short, where nothing had changed, and the march took it for a seating 12 mm up (a 25 m/s seating,
    a 137 mm bounce). Bounds from the valve's energy alone (the train pushes the valve open, never shut): it lands
    no faster than its spring's preload and rate and its speed at the float give, and rebounds at seat_restitution
    x that no higher than its spring's energy allows."""
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {
        "segments": [
            {"law": "modified-trapezoid", "end": 90, "lift": 7.737},
            {"law": "polynomial-345", "end": 130, "lift": 5.395},
            {"law": "polynomial-345", "end": 210, "lift": -5.395},
            {"law": "harmonic", "end": 240, "lift": -7.737},
            {"law": "dwell", "end": 360},
        ]
    }
    case = case_from_dict(raw)
    vt = case.valvetrain
    resp = valvetrain_response(case.motion, vt, 3000 * RPM)
    floats = [e.deg for e in resp.events if e.what == "float"]
    assert any(abs(d - 210.0) < 1e-9 for d in floats), resp.events
    assert resp.settled and not resp.warnings
    m, k, f0, e = (float(v) for v in (vt.valve_mass, vt.spring_rate, vt.preload, vt.seat_restitution))
    at = int(np.searchsorted(resp.theta_deg, 210.0))  # the grid angle at the float (0.1 deg)
    x0, v0 = resp.valve_lift[at] * 1e-3, resp.valve_velocity[at]  # 12.08 mm, 0.12 m/s
    assert resp.seating_velocity <= math.sqrt(v0**2 + (2 * f0 * x0 + k * x0**2) / m)  # 10.09 <= 13.7 m/s
    energy = 0.5 * m * (e * resp.seating_velocity) ** 2
    assert 0.0 < resp.bounce_height_mm * 1e-3 <= (math.sqrt(f0**2 + 2 * k * energy) - f0) / k  # 0.963 <= 1.002 mm


@pytest.mark.slow
@pytest.mark.parametrize(
    "segments",
    [
        # the cam lets go at 130 deg, a grid angle: the solver's root a float past it, the grid angle unsaved (inf)
        [("polynomial-4567", 80, 8.194), ("polynomial-345", 130, 8.141), ("harmonic", 140, -8.141)]
        + [("dwell", 340, None), ("cycloidal", 360, -8.194)],
        # a rebound in the air at the revolution's end, a jump there: its apex's run again a float short of it (inf)
        [("polynomial-4567", 20, 7.932), ("dwell", 100, None), ("harmonic", 120, 5.91), ("modified-sine", 250, 4.57)]
        + [("polynomial-4567", 260, -4.57), ("modified-trapezoid", 320, -5.91), ("modified-trapezoid", 360, -7.932)],
    ],
    ids=["float-on-a-grid-angle", "apex-at-the-end"],
)
def test_a_valve_thrown_about_by_its_cam_has_finite_numbers(segments):
    """Two cams that throw the valve about at 3000 rpm (jumps of acceleration where the solver stops a float short):
    every number of the revolution is finite (a bounce of inf mm and a valve lift of inf once came out)."""
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {
        "segments": [{"law": law, "end": end} | ({} if lift is None else {"lift": lift}) for law, end, lift in segments]
    }
    case = case_from_dict(raw)
    resp = valvetrain_response(case.motion, case.valvetrain, 3000 * RPM)
    arrays = (resp.cam_lift, resp.follower_lift, resp.valve_lift, resp.valve_velocity, resp.cam_force, resp.train_force)
    assert all(np.all(np.isfinite(a)) for a in arrays)
    assert math.isfinite(resp.bounce_height_mm) and math.isfinite(resp.seating_velocity)


@pytest.mark.slow
def test_a_lower_rebound_is_passed_over_and_the_bounce_height_is_the_same(monkeypatch):
    """A flight after the seating is run again on fine angles for its apex (``_apex``) unless the cubic through its
    saved states stays 1 % and 1e-9 m under the highest apex so far. That cubic is within 1e-10 m of every apex of
    the shipped valvetrain (seated, floating, bouncing), and passing the lower rebounds over changes no bounce
    height, bit for bit, while it skips most of the runs again."""
    case = case_from_dict(copy.deepcopy(SHIPPED))
    speeds = [3000.0, 6626.0, 7476.0]  # seated, just bouncing, floating and bouncing
    pairs, calls, last = [], [0], [math.nan]
    flight_top, apex = vtm._flight_top, vtm._apex

    def top(*a):
        last[0] = flight_top(*a)
        return last[0]

    def again(*a):
        calls[0] += 1
        pairs.append((last[0], apex(*a)))
        return pairs[-1][1]

    monkeypatch.setattr(vtm, "_flight_top", top)
    monkeypatch.setattr(vtm, "_apex", again)
    skipped = [valvetrain_response(case.motion, case.valvetrain, w * RPM).bounce_height_mm for w in speeds]
    runs_skipping = calls[0]
    monkeypatch.setattr(vtm, "_below", lambda top, bounce: False)
    calls[0] = 0
    every = [valvetrain_response(case.motion, case.valvetrain, w * RPM).bounce_height_mm for w in speeds]
    assert skipped == every and max(every) > 0.01  # 6626 rpm bounces
    assert runs_skipping < 0.5 * calls[0]
    assert all(abs(t - a) < 1e-10 for t, a in pairs), max(abs(t - a) for t, a in pairs)


@pytest.mark.slow
def test_shipped_case_valve_event():
    """cases/valvetrain.toml at its speed: about 10 mm of valve lift, about 250 cam deg at 0.05 mm, seated at the
    ramp's speed within the dynamics (0.015 mm/deg x 18000 deg/s = 0.27 m/s), settled, no float."""
    case = case_from_dict(copy.deepcopy(SHIPPED))
    resp = valvetrain_response(case.motion, case.valvetrain, 3000 * RPM)
    opening, closing = resp.timing_deg()
    assert 240.0 < closing - opening < 255.0
    assert 9.8 < resp.max_valve_lift_mm < 10.1  # 1.6 x 6.375 - 0.2 = 10 mm less the train's deflection
    assert resp.seating_velocity == pytest.approx(0.015 * 18000e-3, rel=0.05)
    assert resp.settled and not resp.floated and resp.least_event_force > 0.0
    assert not resp.bounced


@pytest.fixture(scope="module")
def shipped_check():
    from camdyn.design.checks import run_check

    return run_check(case_from_dict(copy.deepcopy(SHIPPED)))


VALVETRAIN_KEYS = {
    "ratio",
    "lash_mm",
    "max_valve_lift_mm",
    "opening_deg",
    "closing_deg",
    "seating_velocity_m_per_s",
    "float_speed_rpm",
    "bounce_speed_rpm",
    "bounce_height_mm",
    "ratio_min",
    "ratio_max",
    "coil_bind_lift_mm",
    "coil_bind_clearance_mm",
}


@pytest.mark.slow
def test_check_json_reports_the_valvetrain(shipped_check):
    out = shipped_check.json()
    vt = out["valvetrain"]
    assert set(vt) == VALVETRAIN_KEYS
    assert vt["ratio"] == 1.6 and vt["lash_mm"] == pytest.approx(0.2)
    assert vt["ratio_min"] == vt["ratio_max"] == 1.6  # a constant ratio
    assert vt["coil_bind_lift_mm"] is None and vt["coil_bind_clearance_mm"] is None  # no [spring]: no solid height
    assert out["dynamic"]["jump_speed_rpm"] == vt["float_speed_rpm"]
    # float comes before the equivalent rigid follower's jump (the train's compliance) and after the case speed
    assert 3000 * 1.25 < vt["float_speed_rpm"] < out["kinematic"]["jump_speed_rpm"]
    checks = {c["name"]: c for c in out["checks"]}
    assert checks["seating_velocity"]["limit"] == 0.5 and checks["seating_velocity"]["ok"]
    assert checks["seating_velocity"]["value"] == vt["seating_velocity_m_per_s"]
    assert checks["valve_bounce"]["value"] == vt["bounce_height_mm"] and checks["valve_bounce"]["ok"]
    assert checks["speed_margin"]["value"] == pytest.approx(vt["float_speed_rpm"] / 3000)
    # the contact force is judged over the valve event, not on the base circle where only the tappet force acts
    assert checks["contact_force"]["value"] == out["dynamic"]["min_contact_force_N"] > 0.0
    assert out["verdict"] == "pass"


@pytest.mark.slow
def test_table_has_the_valve_columns(shipped_check):
    from camdyn.design.table import motion_table

    cols = motion_table(shipped_check.case, step_deg=1.0)
    lift, v = cols["valve_lift_mm"], cols["valve_velocity_m_per_s"]
    assert lift.max() == pytest.approx(shipped_check.valvetrain.response.max_valve_lift_mm, abs=0.01)
    assert np.all(lift >= 0.0) and lift[0] == 0.0  # seated on the base circle
    # the velocity is the lift's derivative: w d(lift)/d(theta), by central differences over the event's flanks
    w = 3000 * RPM
    i = np.arange(80, 280)
    assert v[i] == pytest.approx((lift[i + 1] - lift[i - 1]) / (2 * math.radians(1.0)) * w * 1e-3, abs=0.02)


def _valve_table_case(tmp_path, lash, stiffness=None):
    """cases/valve-lift.csv read as the lift at the valve, through a 1.5 rocker, rigid cam contact."""
    (tmp_path / "valve.csv").write_text((CASES / "valve-lift.csv").read_text())
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {"valve_table": "valve.csv"}
    raw["valvetrain"] |= {"ratio": 1.5, "lash": lash}
    raw["valvetrain"].pop("stiffness")
    if stiffness is not None:
        raw["valvetrain"]["stiffness"] = stiffness
    path = tmp_path / "vt.toml"
    import tomli_w

    path.write_text(tomli_w.dumps(raw))
    from camdyn.model.case import load_case

    return load_case(path)


@pytest.mark.slow  # compiles a valve table's fit and its table
@pytest.mark.parametrize("lash", [0.0, 0.2])
def test_valve_table_reproduced_at_the_valve(tmp_path, lash):
    """A valve-lift table, rigid train: the valve's lift reproduces the table within the fit's stated residual,
    and the follower's lift is the table's (its ramps added) over the ratio."""
    from camdyn.design.table import motion_table

    case = _valve_table_case(tmp_path, lash)
    assert case.motion_source == "valve_table" and case.fit.follower_per_data == pytest.approx(1 / 1.5)
    data = np.loadtxt(CASES / "valve-lift.csv", delimiter=",", skiprows=1)
    cols = motion_table(case, step_deg=1.0, speed_rpm=1000)
    assert np.allclose(cols["theta_deg"], data[:, 0])
    stated = case.fit.spline.max_residual
    assert np.max(np.abs(cols["valve_lift_mm"] - data[:, 1])) <= stated + 1e-9
    ramps = np.where(data[:, 1] > 0, data[:, 1] + lash, cols["s_mm"] * 1.5)
    assert np.max(np.abs(cols["s_mm"] * 1.5 - ramps)) <= stated + 1e-9
    if lash:  # the ramps: the lash taken up at 0.015 mm/deg, 13.3 deg each side of the valve's event
        base = cols["s_mm"][(data[:, 1] == 0) & (cols["s_mm"] * 1.5 < 0.5 * lash)]
        assert base.size and np.max(np.abs(base[:20])) < 0.01


def test_a_valve_table_that_misses_its_ramps_speed_is_told(tmp_path):
    """A valve table that leaves its seat at rest (10 sin^3 over 250 deg) meets 0.015 mm/deg ramps with a jump of
    the cam's velocity at both ends: one warning each; the same with 3.75 x (1 - x) added (it leaves and meets its
    seat at 0.015 mm/deg) meets them."""
    theta = np.arange(360.0)
    x = np.clip((theta - 55.0) / 250.0, 0.0, 1.0)

    def told(lift: np.ndarray) -> list[str]:
        rows = "".join(f"{t:g},{v:.4f}\n" for t, v in zip(theta, lift, strict=True))
        (tmp_path / "valve.csv").write_text("theta_deg,lift_mm\n" + rows)
        raw = copy.deepcopy(SHIPPED)
        raw["motion"] = {"valve_table": str(tmp_path / "valve.csv")}
        raw["valvetrain"] |= {"ratio": 1.5, "lash": 0.15}
        return [w.split(" at ")[0] for w in case_from_dict(raw).warnings if "lash ramp at 0.015" in w]

    at_rest = 10.0 * np.sin(np.pi * x) ** 3
    assert told(at_rest) == ["the valve table opens", "the valve table closes"]
    assert told(at_rest + 3.75 * x * (1.0 - x)) == []


def test_valve_table_needs_a_valvetrain(tmp_path):
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {"valve_table": "valve.csv"}
    del raw["valvetrain"]
    raw["dynamics"]["mass"] = 0.2
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "motion.valve_table"


@pytest.mark.slow
def test_valvetrain_figures_and_search_curve(shipped_check):
    """The report's valvetrain figures draw from check's result; the seating velocity the searches marched grows
    with speed below float as the closing ramp's does (0.015 mm/deg x the cam's deg/s, within the dynamics)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from camdyn.plot import plot_seating_velocity, plot_valve_lift, plot_valve_velocity

    vt = shipped_check.valvetrain
    fig, axes = plt.subplots(3)
    plot_valve_lift(axes[0], vt)
    plot_valve_velocity(axes[1], vt)
    plot_seating_velocity(axes[2], vt, 0.5)
    plt.close(fig)
    rpm, v = np.asarray(vt.speeds_rpm), np.asarray(vt.seating_velocities)
    below = rpm < 0.9 * vt.float_speed_rpm
    assert below.sum() >= 5
    assert v[below] == pytest.approx(0.015e-3 * rpm[below] * 6.0, rel=0.1)


def test_train_that_gives_way_to_the_spring_is_refused():
    """A train that lifts the valve, but less than half the cam's stroke at the valve, turned slowly: (k_t (L - lash)
    - F0) / (k_t + k) at full lift, the train and the spring in series (here 1.25 of 10 mm)."""
    raw = copy.deepcopy(SHIPPED)
    raw["valvetrain"]["stiffness"] = 40  # N/mm: 400 N at full compression, more than the 300 N preload
    stroke = 6.375 * 1.6 - 0.2
    lifted = (40 * stroke - 300) / (40 + 40)
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "valvetrain.stiffness" and f"lifts only {lifted:.3g} mm" in str(err.value)
    raw["valvetrain"]["stiffness"] = 120  # 5.6 of 10 mm: a soft train, not a unit slip
    case_from_dict(raw)


def test_lash_the_cam_cannot_take_up_is_refused():
    raw = copy.deepcopy(SHIPPED)
    raw["valvetrain"]["lash"] = 4.0  # more than 0.5 x 6.375 mm
    raw["valvetrain"]["ratio"] = 0.5
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "valvetrain.lash" and "never lifts" in str(err.value)


def test_train_too_soft_to_lift_the_valve_is_refused():
    """The issue's sketch gives stiffness = 25 N/mm: a train that soft, compressed by the whole 10 mm, carries less
    than the spring's 300 N preload; camdyn says so (a unit slip: 25 kN/mm was likely meant)."""
    raw = copy.deepcopy(SHIPPED)
    raw["valvetrain"]["stiffness"] = 25
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "valvetrain.stiffness" and "N/mm" in str(err.value)


@pytest.mark.slow
def test_report_has_a_valvetrain_page(tmp_path, shipped_check):
    from camdyn.design.review import design_review
    from camdyn.report import render

    written = render(design_review(shipped_check.case, shipped_check), tmp_path)
    pages = sorted(p.name for p in tmp_path.glob("*.png"))
    assert "valvetrain-5-valvetrain.png" in pages and written.pdf.exists()


@pytest.mark.slow
def test_summary_gives_the_two_mass_models_numbers(shipped_check):
    """Page 1's key results are the two-mass model's, as check --json gives them (float, bounce, seating, the
    least cam force over the valve event); the one equivalent-follower figure says it is one."""
    from types import SimpleNamespace

    from camdyn.report.pages._facts import key_results

    vt = shipped_check.json()["valvetrain"]
    rows = dict(key_results(SimpleNamespace(check=shipped_check, case=shipped_check.case)))
    assert rows["float speed"] == f"{vt['float_speed_rpm']:.4g} rpm"
    assert rows["bounce speed"] == f"{vt['bounce_speed_rpm']:.4g} rpm"
    assert rows["seating velocity"] == f"{vt['seating_velocity_m_per_s']:.3g} m/s"
    least = shipped_check.valvetrain.response
    assert rows["least cam force, event"].startswith(f"{least.least_event_force:.4g} N")
    assert shipped_check.json()["dynamic"]["min_contact_force_N"] == pytest.approx(least.least_event_force)
    assert rows["equivalent follower"].startswith("rigid jump") and "coil-bind clearance" not in rows
    assert not any(k.startswith(("least force", "jump speed", "flights")) for k in rows)  # the single follower's


def test_optimize_of_a_valvetrain_reshapes_for_its_float_speed_only(capsys, tmp_path):
    """A valvetrain is optimized for its float speed: another objective is refused in one line, exit 2 (the
    reshaped valvetrain itself is tests/test_optimize_valvetrain.py's)."""
    code, out, err = run(
        capsys, "optimize", CASES / "valvetrain.toml", "-o", tmp_path / "o.toml", "--objective", "vibration"
    )
    assert code == 2 and len(err.strip().splitlines()) == 1 and "float speed (jump-speed) only" in err
    assert not (tmp_path / "o.toml").exists()


@pytest.mark.slow
def test_rigid_train_takes_up_the_lash_at_the_ramps_speed():
    """A rigid train closes the lash on the opening ramp with a plastic impact: the cam holds the follower, so the
    valve leaves its seat at once at the ramp's speed times the ratio (0.537148 mm/rad x 1.6 x w), and the lash is
    taken up where the ramp reaches lash / ratio = 0.125 mm (42 + 0.06875 / 0.537148 rad, in deg)."""
    raw = copy.deepcopy(SHIPPED)
    raw["valvetrain"].pop("stiffness")
    case = case_from_dict(raw)
    omega = 300 * RPM
    resp = valvetrain_response(case.motion, case.valvetrain, omega)
    lash = [e for e in resp.events if e.what == "lash"]
    assert len(lash) == 1
    assert lash[0].deg == pytest.approx(42.0 + math.degrees((0.125 - 0.05625) / 0.537148), abs=1e-3)
    after = (resp.theta_deg > lash[0].deg) & (resp.theta_deg < 59.0)  # still on the constant-velocity ramp
    assert resp.valve_velocity[after] == pytest.approx(0.537148e-3 * 1.6 * omega, rel=1e-6)


@pytest.mark.slow
def test_size_of_a_stiff_lash_free_train_is_the_equivalent_followers_closed_form():
    """A stiff train (1e6 N/mm) without lash is the equivalent follower: the closed form (its kinematic LP, carried
    to the valve as k_eq / r^2 and P_eq / r) already floats at the sizing speed in the two-mass model, so the search
    keeps it; the two-mass float speed is the equivalent's jump speed."""
    from camdyn.design.sizing import size_valve_spring

    vs = size_valve_spring(_valvetrain())
    target = 1.25 * 3000 * 1.002
    assert vs.closed_form_jump_rpm == pytest.approx(target, rel=2e-4)  # the LP binds at the top speed
    assert vs.chosen == vs.closed_form and vs.chosen.rate == K  # the rate: the case's own, by default
    assert vs.chosen.float_speed_rpm == pytest.approx(vs.closed_form_jump_rpm, rel=1e-3)
    assert vs.chosen.holds(vs.top_speed_rpm) and vs.verdict == "pass"
    # the closed form by hand: the preload that brings the equivalent's least kinematic force to 0 at the target
    case = _valvetrain()
    th = np.linspace(0.0, 2 * np.pi, 36001)
    s, s1, s2 = (v * 1e-3 for v in case.motion.host(th)[:3])
    w = target * RPM
    m_eq, k_eq, c_eq = M_CAM + M_VALVE * R**2, K * 1e3 * R**2, C * R**2
    p_eq = float(np.max(-m_eq * s2 * w**2 - c_eq * s1 * w - k_eq * s))  # the top speed binds: at W, not below
    assert vs.chosen.preload == pytest.approx(p_eq / R, rel=2e-3)


@pytest.mark.slow
def test_size_valve_spring_passes_check_as_written(capsys, tmp_path):
    """size on the shipped valvetrain: float and bounce both above margin x speed and the valve on the train there;
    the proposal written into the case file passes check, and 2 % less preload does not hold (the least preload)."""
    from camdyn.design.valvetrain import analyze_valvetrain
    from camdyn.model.case import load_case, with_valvetrain_keys

    code, out, err = run(capsys, "size", CASES / "valvetrain.toml", "--json")
    assert code == 0, err
    doc = json.loads(out)
    top = doc["sized_to_rpm"]
    assert doc["model"] == "valvetrain" and top == 3750.0 and doc["holds"]
    assert doc["spring_rate_N_per_mm"] == 40.0  # the case's own rate: the least preload for it
    assert min(doc["float_speed_rpm"], doc["bounce_speed_rpm"]) >= top * 1.001
    assert doc["valvetrain"]["check"]["verdict"] == "pass"
    assert doc["peak_spring_force_N"] == pytest.approx(40.0 * doc["valvetrain"]["valve_lift_mm"] + doc["preload_N"])
    text = (CASES / "valvetrain.toml").read_text()
    text = re.sub(r"^spring_rate = .*$", f"spring_rate = {doc['spring_rate_N_per_mm']!r}", text, flags=re.M)
    text = re.sub(r"^preload = .*$", f"preload = {doc['preload_N']!r}", text, flags=re.M)
    (tmp_path / "proposed.toml").write_text(text)
    code, out, err = run(capsys, "check", tmp_path / "proposed.toml", "--json")
    chk = json.loads(out)
    assert code == 0 and chk["verdict"] == "pass", err
    vt = chk["valvetrain"]
    assert vt["float_speed_rpm"] >= top and vt["bounce_speed_rpm"] >= top
    assert chk["dynamic"]["jump_speed_rpm"] == pytest.approx(doc["jump_speed_rpm"])
    assert doc["least_train_force_N"] > 1e-3 * doc["peak_spring_force_N"]  # the valve on the train at 3750 rpm
    # the least preload: 2 % less and the valve is tossed off the train as the lash closes at 3750 rpm, or floats
    # or bounces below it
    less = with_valvetrain_keys(load_case(CASES / "valvetrain.toml"), dynamics={"preload": 0.98 * doc["preload_N"]})
    resp = valvetrain_response(less.motion, less.valvetrain, top * RPM)
    tossed = resp.train_force[resp.in_event].min() <= 1e-3 * doc["peak_spring_force_N"]
    res = analyze_valvetrain(less, 3000 * RPM, 1.25)
    assert tossed or min(res.float_speed_rpm, res.bounce_speed_rpm) < top
    # the closed form (the equivalent follower: no preload needed at the follower, k lash = 8 N at the valve) is
    # tossed off and bounces early in the two-mass model
    closed = doc["valvetrain"]["closed_form"]
    assert closed["preload_N"] == pytest.approx(40.0 * 0.2) and not closed["holds"]


@pytest.mark.slow
def test_size_of_a_valve_cam_no_spring_holds_stays_within_what_the_train_lifts(capsys, tmp_path):
    """A 23 mm lift in 120 deg at 3000 rpm through the 1.6 rocker: no valve spring keeps the valve on this cam to
    3750 rpm. The search once ran the preload up to 3.9e8 N, where the 8000 N/mm train no longer lifts the valve (a
    case with it is refused), and size --json stopped on the NaN of a valve that never lifts; now it stops at the
    most the train lifts the valve half its stroke under, says none holds, and proposes the nearest, which comes
    nearer than the case's own spring."""
    text = (CASES / "valvetrain.toml").read_text()
    head, rest = text.split("segments = [", 1)
    segments = (
        '{ law = "harmonic", end = 20, lift = 7.118 }, { law = "dwell", end = 40 },'
        '{ law = "polynomial-345", end = 50, lift = 7.599 }, { law = "polynomial-4567", end = 120, lift = 8.428 },'
        '{ law = "modified-trapezoid", end = 150, lift = -8.428 },'
        '{ law = "polynomial-4567", end = 220, lift = -7.599 }, { law = "dwell", end = 310 },'
        '{ law = "polynomial-4567", end = 360, lift = -7.118 }'
    )
    case = tmp_path / "steep.toml"
    case.write_text(head + "segments = [" + segments + "]\n" + rest.split("]\n", 1)[1])
    code, out, err = run(capsys, "size", case, "--json", "--quiet")
    assert code == 0, err
    doc = json.loads(out)
    assert not doc["holds"] and doc["valvetrain"]["check"]["verdict"] == "fail"
    stroke, kt = doc["valvetrain"]["valve_lift_mm"], 8000.0
    ceiling = (kt - 0.5 * (kt + 40.0)) * stroke  # N: the valve lifts half its stroke under it
    assert max(s["preload_N"] for s in doc["valvetrain"]["search"]) <= ceiling
    assert any("no preload found up to" in w for w in doc["warnings"])
    least = min(doc["float_speed_rpm"], doc["bounce_speed_rpm"])
    assert least > min(doc["current"]["float_speed_rpm"], doc["current"]["bounce_speed_rpm"])
    # the proposal is a case check accepts
    text = re.sub(r"^preload = .*$", f"preload = {doc['preload_N']!r}", case.read_text(), flags=re.M)
    case.write_text(text)
    code, out, err = run(capsys, "check", case, "--json")
    assert code == 1 and json.loads(out)["verdict"] == "fail", err


def test_size_buildable_is_refused_for_a_valvetrain(capsys):
    code, out, err = run(capsys, "size", CASES / "valvetrain.toml", "--buildable")
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--buildable" in err


@pytest.mark.slow
def test_sweep_of_a_valvetrain_shows_float_and_bounce_and_a_gap_the_seat_bounds(capsys, tmp_path):
    """The map runs the two-mass model at each point: at 3000 rpm the valve is held (check's seating velocity), at
    7000 rpm with the case's 40 N/mm spring it floats and bounces; the gap at the valve never exceeds the valve's
    travel (the seat catches it: lift >= 0), unlike a single follower's flight that falls through the base circle."""
    import csv

    from camdyn.design.sweep import CSV_COLUMNS

    code, out, err = run(
        capsys, "sweep", CASES / "valvetrain.toml", "--speeds", "3000:7000:2", "-o", tmp_path, "--quiet"
    )
    assert code == 0, err
    rows = list(csv.DictReader((tmp_path / "valvetrain-sweep.csv").read_text().splitlines()))
    assert tuple(rows[0]) == CSV_COLUMNS and len(rows) == 2
    slow, fast = rows
    assert slow["separated"] == "0" and slow["bounced"] == "0" and float(slow["max_gap_mm"]) < 0.01
    assert float(slow["seating_velocity_m_per_s"]) == pytest.approx(0.26864, rel=1e-3)  # check's, at 3000 rpm
    assert float(slow["min_contact_force_N"]) == pytest.approx(241.57, rel=1e-3)
    assert fast["separated"] == "1" and fast["bounced"] == "1"
    assert 0.1 < float(fast["max_gap_mm"]) < 10.2  # the valve's travel: 10 mm (ratio x lift - lash)
    assert "valve spring 40 N/mm: floats at 7000 rpm, bounces at 7000 rpm (both at once)" in out


def _with_tolerances(tmp_path, **tolerances):
    raw = copy.deepcopy(SHIPPED) | {"tolerances": tolerances}
    from camdyn.export.toml import dumps_case

    path = tmp_path / "vt-tol.toml"
    path.write_text(dumps_case(raw, []))
    return path


@pytest.mark.slow
def test_tolerance_of_a_valvetrain_float_and_bounce_speeds_agree_with_check(capsys, tmp_path):
    """Monte Carlo over the valve spring, the lash, the valve mass and the train's stiffness with the two-mass
    model per sample: the worst sample's float speed (a local search about the nominal's) agrees with check's
    global search on that sample written as a case file, within the searches' 1 % width; its bounce speed is
    not below check's first one."""
    path = _with_tolerances(
        tmp_path, spring_rate="5%", preload="10 N", lash="0.05 mm", valve_mass="5%", valvetrain_stiffness="10%"
    )
    code, out, err = run(capsys, "tolerance", path, "--samples", "4", "-o", tmp_path / "out", "--json", "--quiet")
    assert code == 0, err
    doc = json.loads(out)
    vt = doc["valvetrain"]
    assert doc["samples"] == 4 and vt["probability_of_float"] == 0.0 and vt["probability_of_bounce"] == 0.0
    assert vt["nominal_float_speed_rpm"] == pytest.approx(5920.15, abs=1.0)  # check's, on the nominal case
    assert 0.25 < vt["seating_velocity_m_per_s"]["p50"] < 0.29  # about the nominal's 0.269 m/s at 3000 rpm
    assert set(doc["tolerances"]) == {"spring_rate", "preload", "lash", "valve_mass", "valvetrain_stiffness"}
    rows = (tmp_path / "out" / "valvetrain-tolerance.csv").read_text().splitlines()
    assert rows[0].startswith("sample,spring_rate_N_per_mm,preload_N") and len(rows) == 5
    worst = doc["worst"][0]
    code, out, err = run(capsys, "check", worst["file"], "--json")
    chk = json.loads(out)["valvetrain"]
    assert chk["float_speed_rpm"] == pytest.approx(worst["jump_speed_rpm"], rel=0.011)
    # bounce is a threshold on a re-lift that comes and goes with speed near its onset: the local search finds a
    # crossing about the nominal's, check's global search the first (here a window 3 % below)
    assert chk["bounce_speed_rpm"] <= worst["bounce_speed_rpm"] * 1.011


@pytest.mark.parametrize(
    ("valvetrain", "key", "words"),
    [(False, "lash", "needs [valvetrain]"), (True, "mass", "cam_side_mass"), (True, "profile_error", "not modelled")],
)
def test_valvetrain_tolerance_keys_are_checked(valvetrain, key, words):
    raw = copy.deepcopy(SHIPPED if valvetrain else EVENT | {"dynamics": {"speed": 300, "mass": 1.0}})
    raw["tolerances"] = {key: "0.01" if key != "mass" else "5%"}
    if not valvetrain:
        raw["dynamics"] |= {"spring_rate": 10.0, "preload": 50.0}
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == f"tolerances.{key}" and words in str(err.value)


def test_single_follower_sizing_and_tolerance_name_the_valvetrain_studies():
    """From Python the single follower's studies refuse a valvetrain in one line naming the two-mass ones."""
    from camdyn.design.sizing import size_spring
    from camdyn.design.tolerance import tolerance_study

    case = case_from_dict(copy.deepcopy(SHIPPED))
    with pytest.raises(InputError) as err:
        size_spring(case)
    assert err.value.where == "valvetrain" and "size_valve_spring" in str(err.value)
    with pytest.raises(InputError) as err:
        tolerance_study(case, 10)
    assert err.value.where == "valvetrain" and "valvetrain_tolerance_study" in str(err.value)


@pytest.mark.slow
def test_force_against_speed_is_the_two_mass_models(shipped_check):
    """The review's force against speed (the dynamics and optimization pages) carries the two-mass model's least
    cam force over the valve event: at the case speed check's contact force, positive up to the float speed, 0 at
    the first speed past it and not computed beyond (the equivalent follower's curve said 480 N at 3000 rpm, where
    page 1 and the operating point say 241.6 N)."""
    case, float_rpm = shipped_check.case, shipped_check.valvetrain.float_speed_rpm
    assert _least_event_force(case, np.array([3000.0]))[0] == pytest.approx(
        shipped_check.dynamic.min_contact_force_N, rel=1e-6
    )
    fvs = force_vs_speed(case, shipped_check, 1.25 * 3000.0)
    assert fvs.valve_event is not None
    speeds, least = fvs.valve_event
    i = int(np.searchsorted(speeds, float_rpm))
    assert np.all(least[:i] > 0.0) and least[i] == 0.0 and np.isnan(least[i + 1 :]).all()


@pytest.mark.slow
def test_a_valve_far_past_float_never_goes_through_its_seat():
    """A rigid train without lash on cases/valve-lift.csv (at the valve, ratio 1.5), 15540 rpm, 2.6 x its float
    speed: the valve is tossed and lands where it may, but never below its seat and the follower never inside the
    cam (a grazing change the root finder missed left every event function below zero, and the valve fell to -27.8
    mm through a revolution without an event)."""
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {"valve_table": str(CASES / "valve-lift.csv")}
    raw["valvetrain"] |= {"ratio": 1.5, "lash": 0.0}
    raw["valvetrain"].pop("stiffness")
    case = case_from_dict(raw)
    assert case.valvetrain is not None
    r = valvetrain_response(case.motion, case.valvetrain, 15540 * RPM)
    assert r.valve_lift.min() >= -1e-6 and r.events
    assert np.min(r.follower_lift - r.cam_lift) >= -1e-6


def test_cams_of_other_segment_counts_share_the_stretch_program():
    """The stretches' jump times (every break over the revolutions marched) are padded with +inf to 512, 2048, ...:
    cams of four, five, eight (the shipped valvetrain's) and 28 segments (its optimized B-spline's breaks) give the
    stretch's stored program arguments of one shape (a valve cam of five segments compiled its own: 3 s)."""
    from camdyn.model.dynamics._valvetrain import _jump_angles
    from camdyn.model.motion import Program

    def cam(n):  # a rise, a return and n - 2 dwells
        lifts = [1.0, -1.0] + [0.0] * (n - 2)
        laws = ["cycloidal", "cycloidal"] + ["dwell"] * (n - 2)
        return Program.from_segments(
            [
                {"law": law, "end": 360.0 * (i + 1) / n} | ({"lift": lift} if lift else {})
                for i, (law, lift) in enumerate(zip(laws, lifts, strict=True))
            ]
        )

    four, five, eight, many = (_jump_angles(cam(n)) for n in (4, 5, 8, 28))
    assert four.shape == five.shape == eight.shape == many.shape == (512,)
    assert np.isfinite(four).sum() == 24 and np.isfinite(five).sum() == 30 and np.all(np.diff(five[:30]) > 0)
    assert np.isfinite(many).sum() == 168 and np.all(np.diff(many[:168]) > 0)
    assert np.isinf(five[30:]).all() and np.isinf(four[24:]).all() and np.isinf(many[168:]).all()
    assert _jump_angles(cam(90)).shape == (2048,)  # past 85 segments, the next bucket


def _decelerating_ramp(tappet_force: float):
    """The shipped valvetrain with an opening ramp that overshoots its end speed (0.15 mm in 15 deg ending at 0.5
    mm/rad: it decelerates over its last 6 deg, s'' down to -5.3 mm/rad^2) while the lash is still open."""
    raw = copy.deepcopy(SHIPPED)
    raw["motion"]["segments"] = [
        {"law": "dwell", "end": 40},
        {"law": "polynomial", "end": 55, "lift": 0.15, "end_velocity": 0.5},
        {"law": "polynomial", "end": 175, "lift": 7.0, "start_velocity": 0.5, "end_acceleration": -9.0},
        {"law": "polynomial", "end": 300, "lift": -7.0, "start_acceleration": -9.0, "end_velocity": -0.5},
        {"law": "polynomial", "end": 315, "lift": -0.15, "start_velocity": -0.5},
        {"law": "dwell", "end": 360},
    ]
    raw["dynamics"]["speed"] = 2800
    raw["valvetrain"]["tappet_force"] = tappet_force
    return case_from_dict(raw)


@pytest.mark.slow
def test_a_follower_thrown_off_a_decelerating_ramp_is_a_warning():
    """With the lash open only the tappet force holds the follower: it leaves a ramp that decelerates faster than
    F_tappet / (m_c w^2) allows and lands back on the cam before the lash closes, which ``check`` says (angle and
    impact speed). The threshold is the closed form's: no landing with a tappet force above m_c |s''|max w^2
    (about 55 N here), landings with one below; none on the shipped ramps."""
    w = 2800 * RPM
    case = _decelerating_ramp(0.0)
    theta = np.radians(np.arange(40.0, 55.0, 0.01))
    s2 = np.asarray(case.motion.host(theta))[2] * 1e-3  # m/rad^2
    hold = float(case.valvetrain.cam_side_mass) * float(-s2.min()) * w**2  # N: the least tappet force that holds it
    assert 50.0 < hold < 60.0
    for force, lands in ((0.0, True), (0.5 * hold, True), (1.2 * hold, False)):
        case = _decelerating_ramp(force)
        resp = valvetrain_response(case.motion, case.valvetrain, w)
        line = ramp_landings(resp, force)
        assert (line is not None) == lands, (force, line)
        if lands:
            leaves = math.degrees(theta[np.argmax(float(case.valvetrain.cam_side_mass) * s2 * w**2 + force < 0.0)])
            lift = next(e.deg for e in resp.events if e.what == "valve-lift")
            first = next(e for e in resp.events if e.what == "cam-landing")
            assert leaves < first.deg < lift and first.speed > 0.0  # thrown off the ramp, back before the lash closes
            assert f"{first.deg:.1f} deg ({first.speed:.3g} m/s)" in line and f"({force:.4g} N)" in line
    shipped = case_from_dict(copy.deepcopy(SHIPPED))
    assert ramp_landings(valvetrain_response(shipped.motion, shipped.valvetrain, 3000 * RPM), 0.0) is None
