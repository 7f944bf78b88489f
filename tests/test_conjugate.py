"""Conjugate cams (issue 25): two cams on the shaft, two rollers on one follower (a yoke, a two-arm rocker). The
conjugate cam is derived exactly; the signed force, its crossovers and the flight across the backlash are the groove's
(:mod:`camdyn.model.dynamics._closure`), with the conjugate cam's own lever; a preload is shared between the cams."""

import copy
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import tomli_w
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
from scipy.optimize import minimize_scalar

from camdyn import InputError
from camdyn.model.case import case_from_dict, load_case
from camdyn.model.dynamics import closure_response, preload_shares
from camdyn.model.geometry import analyze, conjugate

YOKE_TOML = """
name = "yoke"
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
closure = "conjugate"
conjugate_spacing = 150
[dynamics]
speed = 300
mass = 1.0
train_stiffness = 5000
"""
YOKE = tomllib.loads(YOKE_TOML)
EXAMPLE = Path(__file__).resolve().parents[1] / "cases" / "conjugate.toml"


def _yoke(**follower):
    raw = copy.deepcopy(YOKE)
    raw["follower"].update(follower)
    raw["follower"] = {k: v for k, v in raw["follower"].items() if v is not None}
    return case_from_dict(raw)


def _to_cam(theta, sigma, xy):
    """A fixed-frame point seen in the cam frame at cam angle theta: R(-sigma theta) xy."""
    c, s = np.cos(-sigma * theta), np.sin(-sigma * theta)
    return np.array([c * xy[0] - s * xy[1], s * xy[0] + c * xy[1]])


def _distance_to_curve(point, curve, theta):
    """The exact least distance (mm) from ``point`` to the closed curve u -> (2, m) near cam angle ``theta``."""
    u0 = theta / (2 * np.pi)
    res = minimize_scalar(
        lambda u: np.hypot(*(curve(np.array([u]))[:, 0] - point)),
        bounds=(u0 - 0.05, u0 + 0.05),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return res.fun


@pytest.mark.parametrize(
    ("keys", "where", "match"),
    [
        ({"conjugate_spacing": None}, "follower.conjugate_spacing", "required for conjugate cams"),
        ({"conjugate_arm_angle": 30}, "follower.conjugate_arm_angle", "not used"),
        ({"conjugate_preload": 10, "backlash": 0.1}, "follower.backlash", "preloaded conjugate pair"),
        ({"type": "translating-flat", "roller_radius": None}, "follower.closure", "conjugate cams hold a roller"),
        ({"closure": "groove"}, "follower.conjugate_spacing", "not used"),
        ({"closure": "spring"}, "follower.conjugate_spacing", "not used"),
    ],
)
def test_conjugate_keys_refused(keys, where, match):
    with pytest.raises(InputError, match=match) as err:
        _yoke(**keys)
    assert err.value.where == where


def test_a_second_roller_on_the_same_side_is_refused():
    """Spacing 30 mm leaves the second roller above the cam centre: the conjugate cam would push the way the primary
    does; spacing 90 mm puts it across, but at full lift 8 mm from the centre, within its 12 mm radius."""
    for spacing, match in ((30, "cannot drive the follower back"), (90, "reaches the cam centre")):
        case = _yoke(conjugate_spacing=spacing)
        with pytest.raises(InputError, match=match) as err:
            conjugate(case.motion, case.follower, n=720)
        assert err.value.where == "follower.conjugate_spacing"


@pytest.mark.parametrize("rotation", ["cw", "ccw"])
def test_yoke_conjugate_cam_keeps_both_rollers_on_their_cams(rotation):
    """With the first roller on the primary cam (its centre at (sigma e, sqrt(Rp^2 - e^2) + s)), the second roller's
    centre (sigma (e + c), sqrt(Rp^2 - e^2) + s - D) lies exactly Rr2 + b from the conjugate cam's contour at every
    angle (the least distance to the exact curve, 1e-6 mm), the pitch curves stay the yoke's span apart, and on the
    dwells the conjugate contour is a circle of the closed-form radius."""
    e, c, D, rr2, b = 5.0, 8.0, 150.0, 10.0, 0.05
    case = _yoke(offset=e, conjugate_offset=c, conjugate_roller_radius=rr2, backlash=b, rotation=rotation)
    sigma = case.follower.sigma
    g = conjugate(case.motion, case.follower, n=3600)
    p = analyze(case.motion, case.follower, n=3600)
    np.testing.assert_allclose(np.hypot(*(p.pitch - g.pitch)), math.hypot(D, c), rtol=1e-12)
    h0 = math.sqrt(62.0**2 - e**2)
    curve = g.contour_fn()
    for deg in np.arange(0.0, 360.0, 17.3):
        th = np.deg2rad(deg)
        s = host(case, th)[0, 0]
        centre = _to_cam(th, sigma, (sigma * (e + c), h0 + s - D))
        assert _distance_to_curve(centre, curve, th) == pytest.approx(rr2 + b, abs=1e-6)
    i = int(np.argmin(np.abs(g.theta_deg - 150.0)))  # top dwell: s = 20
    assert np.hypot(*g.contour[:, i]) == pytest.approx(math.hypot(e + c, h0 + 20 - D) - rr2 - b, abs=1e-9)


def test_rocker_conjugate_cam_keeps_both_rollers_on_their_cams():
    """The shipped two-arm rocker: the first arm at pi - (psi0 + phi) from the pivot (cos psi0 by the law of cosines),
    the second at conjugate_arm_angle ccw from it; the second roller's centre lies Rr2 from the conjugate contour."""
    case = load_case(EXAMPLE)
    f = case.follower
    L, a, rp = f.pivot_distance, f.arm_length, f.base_radius + f.roller_radius
    psi0 = math.acos((L**2 + a**2 - rp**2) / (2 * L * a))
    g = conjugate(case.motion, f, n=3600)
    curve = g.contour_fn()
    for deg in np.arange(3.0, 360.0, 23.1):
        th = np.deg2rad(deg)
        ang = math.pi - (psi0 + host(case, th)[0, 0]) + math.radians(f.conjugate_arm_angle)
        centre = _to_cam(
            th, f.sigma, (L + f.conjugate_arm_length * math.cos(ang), f.conjugate_arm_length * math.sin(ang))
        )
        assert _distance_to_curve(centre, curve, th) == pytest.approx(f.conjugate_roller_radius, abs=1e-6)


@pytest.mark.parametrize("which", ["yoke", "rocker"])
def test_conjugate_pressure_angle_and_curvature_from_finite_differences(which):
    """The contour's radius of curvature from central differences of the exact contour (convex positive), and the
    pressure angle between the contour's normal (from the differenced tangent) and the direction the conjugate cam
    drives the follower: minus the yoke's axis, or minus the second roller's velocity as the rocker swings."""
    case = _yoke(offset=5.0, conjugate_offset=8.0) if which == "yoke" else load_case(EXAMPLE)
    f = case.follower
    sigma = f.sigma
    g = conjugate(case.motion, f, n=720)
    ev = g._evaluate
    h = 1e-4
    idx = [k for k in range(0, 720, 37)]
    for k in idx:
        th = np.deg2rad(g.theta_deg[k])
        cm, c0, cp = (ev(np.array([th + d]))["contour"][0] for d in (-h, 0.0, h))
        d1, d2 = (cp - cm) / (2 * h), (cp - 2 * c0 + cm) / h**2
        kappa = -sigma * (d1[0] * d2[1] - d1[1] * d2[0]) / np.hypot(*d1) ** 3
        assert 1.0 / kappa == pytest.approx(g.rho_contour_mm[k], rel=2e-5)
        n = sigma * np.array([-d1[1], d1[0]]) / np.hypot(*d1)
        if which == "yoke":
            drive = _to_cam(th, sigma, (0.0, -1.0))
        else:  # the second roller's centre moves with the swing: its back-drive direction by a difference in swing
            q = host(case, th)[0, 0]
            centres = []
            for dq in (-1e-6, 1e-6):
                L = f.pivot_distance
                psi0 = math.acos(
                    (L**2 + f.arm_length**2 - (f.base_radius + f.roller_radius) ** 2) / (2 * L * f.arm_length)
                )
                ang = math.pi - (psi0 + q + dq) + math.radians(f.conjugate_arm_angle)
                centres.append(
                    np.array([L + f.conjugate_arm_length * math.cos(ang), f.conjugate_arm_length * math.sin(ang)])
                )
            drive = _to_cam(th, sigma, centres[0] - centres[1])
            drive = drive / np.hypot(*drive)
        phi = sigma * math.degrees(math.atan2(drive[0] * n[1] - drive[1] * n[0], drive @ n))
        assert phi == pytest.approx(g.pressure_angle_deg[k], abs=2e-5)


def test_crossovers_fall_at_mid_rise_and_the_preload_is_shared():
    """No spring: Fi = m w^2 s'' changes cam at mid-rise (60 deg) and mid-fall (240 deg), primary to conjugate and
    back. A preload P is shared: each cam P +- Fi/2 while |Fi| < 2P, else the one it presses carries Fi alone; the
    check's closure block reports each cam's extremes, and whether the preload held."""
    case = _yoke()
    w = omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    assert [c.deg for c in r.crossovers] == pytest.approx([60.0, 240.0], abs=1e-8)
    assert [(c.from_flank, c.to_flank) for c in r.crossovers] == [("primary", "conjugate"), ("conjugate", "primary")]
    s2 = host(case, np.deg2rad(r.theta_deg))[2]
    np.testing.assert_allclose(r.contact_force, w**2 * s2 * 1e-3, rtol=1e-12, atol=1e-12)
    peak = float(np.max(np.abs(r.contact_force)))  # m w^2 s''max = 2 pi L / beta^2 w^2 m
    assert peak == pytest.approx(2 * np.pi * 20e-3 / (2 * np.pi / 3) ** 2 * w**2, rel=1e-6)
    for preload in (0.6 * peak, 0.4 * peak):
        f1, f2 = preload_shares(r.contact_force, preload)
        np.testing.assert_allclose(f1 - f2, r.contact_force, atol=1e-12)
        held = np.abs(r.contact_force) <= 2 * preload
        np.testing.assert_allclose(f1[held], preload + r.contact_force[held] / 2, rtol=1e-12)
        assert np.all(f1[~held] * f2[~held] == 0.0) and np.all(f1 >= 0) and np.all(f2 >= 0)
        assert held.all() == (preload > peak / 2)


@pytest.mark.slow  # compiles the crossing and the impact (11 s)
def test_flight_across_the_conjugate_backlash_uses_the_conjugate_cams_lever():
    """Backlash b is the clearance at the conjugate cam: across it at constant velocity, the gap along the axis is
    b / cos(phi2) with tan(phi2) = s' / (D - Rp - s) (the second roller below the cam centre), not the primary's
    s' / (Rp + s); the conjugate cam meets the yoke where s'(tc) d - (s(tc + d) - s(tc)) = gap."""
    b, D = 0.05, 150.0
    case = _yoke(backlash=b)
    w = omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    c = r.crossovers[0]
    assert (c.from_flank, c.to_flank) == ("primary", "conjugate")
    tc = np.deg2rad(60.0)
    s0 = host(case, tc)[:, 0]
    gap = b * np.hypot(1.0, s0[1] / (D - 62.0 - s0[0]))
    d = constant_velocity_landing(case, tc, gap)
    assert np.deg2rad(c.land_deg) - tc == pytest.approx(d, rel=1e-6)
    v = (s0[1] - host(case, tc + d)[1, 0]) * w * 1e-3
    assert c.impact_velocity_m_per_s == pytest.approx(v, rel=1e-6)


def test_rocker_cam_forces_through_each_levers():
    """The rocker's torques shared under preload_torque P, each cam's contact force through its own lever arm
    (a cos phi, a2 cos phi2 from the pressure angles): F1 l1 - F2 l2 is the arm's net torque, F1 l1 + F2 l2 = 2P
    while the preload holds (the shipped example's does)."""
    from camdyn.design.closure import closure_study

    case = load_case(EXAMPLE)
    f = case.follower
    study = closure_study(case)
    loads = study.loads
    assert loads.preload_held and loads.preload == f.conjugate_preload_torque == 40.0
    th = study.response.theta_deg
    l1 = f.arm_length * np.cos(np.deg2rad(analyze(case.motion, f).table(th)["pressure_angle_deg"])) * 1e-3
    l2 = f.conjugate_arm_length * np.cos(np.deg2rad(study.walls.pressure_angle_deg)) * 1e-3
    np.testing.assert_allclose(loads.primary_N * l1 - loads.conjugate_N * l2, study.response.contact_force, atol=1e-9)
    np.testing.assert_allclose(loads.primary_N * l1 + loads.conjugate_N * l2, 80.0, rtol=1e-12)


def test_profile_writes_both_cams(tmp_path, capsys):
    """DXF: CAM_PRIMARY and CAM_CONJUGATE layers, each within the tolerance of its exact contour; CSV: the outline
    column; SVG: one polygon each."""
    import ezdxf

    case_file = write_case(tmp_path, "yoke.toml", YOKE_TOML)
    case = case_from_dict(YOKE)
    exact = {
        "CAM_PRIMARY": analyze(case.motion, case.follower, n=40_000).contour,
        "CAM_CONJUGATE": conjugate(case.motion, case.follower, n=40_000).contour,
    }
    assert run(capsys, "profile", case_file, "-o", tmp_path / "y.dxf")[0] == 0
    doc = ezdxf.readfile(tmp_path / "y.dxf")
    layers = {e.dxf.layer: np.array([p[:2] for p in e.get_points()]) for e in doc.modelspace()}
    assert set(layers) == set(exact)
    for name, xy in layers.items():
        assert np.max(distance_to_outline(xy, exact[name].T)) < 0.011
    assert run(capsys, "profile", case_file, "-o", tmp_path / "y.csv")[0] == 0
    rows = np.genfromtxt(tmp_path / "y.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert set(rows["outline"]) == {"cam_primary", "cam_conjugate"}
    assert run(capsys, "profile", case_file, "-o", tmp_path / "y.svg")[0] == 0
    svg = (tmp_path / "y.svg").read_text()
    assert svg.count("<polygon") == 2 and 'id="cam_conjugate"' in svg


def test_check_json_of_the_shipped_conjugate_cam(capsys):
    """The shipped rocker passes: the closure block (type, crossovers at mid-rise and mid-return of its
    modified-sine swings, the conjugate cam, each cam's force, the preload), the conjugate cam judged as the primary,
    no speed_margin."""
    code, out, _ = run(capsys, "check", EXAMPLE, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["verdict"] == "pass"
    cl = doc["closure"]
    assert cl["type"] == "conjugate" and cl["backlash_mm"] == 0.0 and cl["max_impact_force_N"] == 0.0
    assert [round(c["deg"], 6) for c in cl["crossovers"]] == [90.0, 270.0]
    assert {"roller_radius_mm", "max_pressure_angle_deg", "min_radius_of_curvature_mm", "undercut"} <= set(
        cl["conjugate_cam"]
    )
    assert cl["preload_torque_N_m"] == 40.0 and cl["preload_held"] is True
    assert cl["cams"]["primary"]["min_force_N"] > 0 and cl["cams"]["conjugate"]["min_force_N"] > 0
    # the preload holds both rollers: only the net force turns, no cam lets go at the crossovers
    assert any("net contact force changes sign 2 times" in w for w in doc["warnings"])
    assert not any(w.startswith("the contact force changes cam") for w in doc["warnings"])
    names = [c["name"] for c in doc["checks"]]
    assert {"conjugate_pressure_angle", "conjugate_curvature", "crossover_impact"} <= set(names)
    assert "speed_margin" not in names
    held = doc["checks"][names.index("conjugate_preload")]  # the least force on either cam under the preload
    least = min(cl["cams"]["primary"]["min_force_N"], cl["cams"]["conjugate"]["min_force_N"])
    assert held["ok"] and held["value"] == pytest.approx(least, rel=1e-12) and held["limit"] == 0.0
    pa = doc["checks"][names.index("conjugate_pressure_angle")]
    assert pa["value"] == pytest.approx(cl["conjugate_cam"]["max_pressure_angle_deg"]) and pa["limit"] == 35.0


def test_an_undercut_primary_cam_fails_with_no_contact_stress(tmp_path, capsys):
    """The shipped rocker with a swing its primary cam cannot follow (a 7.1 deg cycloidal rise over 40 deg folds
    its contour at 65 deg; the conjugate cam does not fold): a FAIL with the contact stress not computed, as a single
    cam's, not an error on the primary's Hertz strip (it once exited 2)."""
    text = Path(EXAMPLE).read_text()
    head, rest = text.split("segments = [", 1)
    segments = (
        '{ law = "dwell", end = 50 }, { law = "polynomial-4567", end = 70, lift = 4.533 },'
        '{ law = "modified-trapezoid", end = 90, lift = 5.151 }, { law = "cycloidal", end = 130, lift = 7.143 },'
        '{ law = "modified-trapezoid", end = 170, lift = -7.143 }, { law = "harmonic", end = 300, lift = -5.151 },'
        '{ law = "polynomial-345", end = 360, lift = -4.533 }'
    )
    case = write_case(tmp_path, "folded.toml", head + "segments = [" + segments + "]\n" + rest.split("]\n", 1)[1])
    code, out, err = run(capsys, "check", case, "--json")
    doc = json.loads(out)
    assert code == 1 and doc["verdict"] == "fail" and not err
    assert doc["geometry"]["undercut"] and not doc["closure"]["conjugate_cam"]["undercut"]
    assert "contact stress not computed: the cam is undercut" in doc["warnings"]
    assert "contact_stress" not in [c["name"] for c in doc["checks"]]


# slow: compiles the rocker's flight across the backlash alone (seconds); the quick set keeps the yoke's flight
# (test_flight_across_the_conjugate_backlash_uses_the_conjugate_cams_lever) and the rocker's forces
@pytest.mark.slow
def test_rocker_flight_across_the_backlash_lands_and_hits_through_the_conjugate_arm():
    """The shipped rocker without preload, 0.05 mm backlash and a longer second arm (165 mm): the arm keeps its
    angular velocity across the gap b / (a2 cos phi2) (rad, the conjugate cam's lever at the crossover), the landing
    where the closed form puts it; the impact speed at the landing roller's centre (a2 or a times the relative angular
    speed) and the impact force the peak of the arm's torque through the train (a second integrator; near the
    half-sine |T| + w_rel sqrt(k_f I)) over that cam's lever arm."""
    raw = tomllib.loads(EXAMPLE.read_text())
    f = raw["follower"]
    del f["conjugate_preload_torque"]
    f.update(backlash=0.05, conjugate_arm_length=165.0)
    case = case_from_dict(raw)
    w = omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    assert [c.deg for c in r.crossovers] == pytest.approx([90.0, 270.0], abs=1e-8)
    g = conjugate(case.motion, case.follower, n=3600)
    pa1 = lambda deg: analyze(case.motion, case.follower).table([deg])["pressure_angle_deg"][0]  # noqa: E731
    pa2 = lambda deg: g._evaluate(np.deg2rad(np.array([deg])))["phi"][0]  # noqa: E731
    lever = {"primary": lambda d: 150.0 * np.cos(np.deg2rad(pa1(d))), "conjugate": lambda d: 165.0 * np.cos(pa2(d))}
    arm_m = {"primary": 0.150, "conjugate": 0.165}
    md = case.model
    kf, cf, k, c_, t0 = (
        float(x) for x in (md.train_stiffness, md.train_damping, md.stiffness, md.damping, md.preload + md.external)
    )
    for c in r.crossovers:
        tc = np.deg2rad(c.deg)
        p0 = host(case, tc)[:, 0]
        side = 1.0 if c.from_flank == "primary" else -1.0
        gap = 0.05 / lever["conjugate"](c.deg)
        d = constant_velocity_landing(case, tc, gap, side)
        assert c.to_flank != c.from_flank
        assert np.deg2rad(c.land_deg) - tc == pytest.approx(d, rel=1e-6)
        w_rel = abs(p0[1] - host(case, tc + d)[1, 0]) * w
        assert c.impact_velocity_m_per_s == pytest.approx(w_rel * arm_m[c.to_flank], rel=1e-6)
        # the impact through the train: scipy's DOP853 from the closed-form landing, the arm pressed on the flank it
        # lands on through k_f and c_f (N*m/rad), the peak torque over a contact period over that cam's lever arm
        to = -side  # +1: pressed up by the primary cam, -1: back by the conjugate one

        def flank_torque(t, y, to=to, gap=gap):  # t (n,) and y (2, n), or one angle and its state
            sv = host(case, t)
            return to * np.maximum(0.0, kf * (to * (sv[0] - y[0]) - gap / 2) + cf * w * to * (sv[1] - y[1]))

        def field(t, y, flank_torque=flank_torque):
            return [y[1], (flank_torque(t, y)[0] - k * y[0] - c_ * w * y[1] - t0) / (0.05 * w**2)]

        t1, span = tc + d, w * 2 * np.pi / np.sqrt((k + kf) / 0.05)
        ts = np.linspace(t1, t1 + span, 20001)
        y1 = [p0[0] - side * gap / 2 + p0[1] * d, p0[1]]
        sol = solve_ivp(field, (t1, t1 + span), y1, "DOP853", t_eval=ts, rtol=1e-12, atol=1e-14)
        torques = np.abs(flank_torque(ts, sol.y))
        i = int(np.argmax(torques))
        want = torques[i] / (lever[c.to_flank](np.rad2deg(ts[i]) % 360) * 1e-3)
        assert c.impact_force_N == pytest.approx(want, rel=1e-5)
        # near the half-sine of a stiff train on the arm's torque at the landing: |T| + w_rel sqrt(k_f I)
        half_sine = (abs(0.05 * w**2 * host(case, t1)[2, 0]) + w_rel * np.sqrt(kf * 0.05)) / (
            lever[c.to_flank](c.land_deg) * 1e-3
        )
        assert 0.8 * half_sine < c.impact_force_N < 1.25 * half_sine


def test_conjugate_contact_stress_on_each_cam():
    """Each cam's Hertz strip with its own force: where the primary presses, the spring cam's (K = 1/Rr + 1/rho1,
    force over cos phi1); where the conjugate does, its own (K = 1/Rr2 + 1/rho2 of its contour, force over cos phi2);
    under a preload both press and the larger pressure is reported."""
    from camdyn.model.contact import cam_contact, conjugate_contact

    case = _yoke(conjugate_roller_radius=10.0)
    r = closure_response(case.motion, case.follower, case.model, omega(case))
    geo = analyze(case.motion, case.follower)
    second = conjugate(case.motion, case.follower)
    mats = {"width_mm": 10.0, "cam": (206.0, 0.3), "follower": (206.0, 0.3)}
    f1, f2 = preload_shares(r.contact_force, 0.0)
    got = conjugate_contact(geo, second, f1, f2, **mats)
    on1, on2 = r.contact_force > 0, r.contact_force < 0
    spring = cam_contact(geo, f1, **mats)
    np.testing.assert_allclose(got.pressure_MPa[on1], spring.pressure_MPa[on1], rtol=1e-12)
    k2 = 1 / 10.0 + 1 / second.rho_contour_mm[on2]
    np.testing.assert_allclose(got.equivalent_radius_mm[on2], 1 / k2, rtol=1e-12)
    np.testing.assert_allclose(
        got.normal_force_N[on2], f2[on2] / np.cos(np.deg2rad(second.pressure_angle_deg[on2])), rtol=1e-12
    )
    p1, p2 = preload_shares(r.contact_force, 100.0)
    both = conjugate_contact(geo, second, p1, p2, **mats)
    alone = [conjugate_contact(geo, second, p1, 0 * p2, **mats), conjugate_contact(geo, second, 0 * p1, p2, **mats)]
    np.testing.assert_allclose(both.pressure_MPa, np.maximum(*(a.pressure_MPa for a in alone)), rtol=1e-12)


@pytest.mark.slow
def test_report_of_conjugate_cams(tmp_path, capsys):
    """``camdyn report`` of the shipped rocker: both cams and each cam's force in place of the cam, dynamics and
    spring-sizing pages; page 1 gives the preload held, the least cam force and the crossovers as ``check`` does,
    and the forces page draws each cam's force (its share of the preload) under the net force."""
    import re

    from camdyn.design.checks import run_check
    from camdyn.design.review import design_review
    from camdyn.report import ReportData
    from camdyn.report.pages._facts import decision_facts, key_results

    doc = check_json(capsys, EXAMPLE)
    code, _, _ = run(capsys, "report", EXAMPLE, "-o", tmp_path / "r")
    assert code == 0
    pngs = sorted(p.name for p in (tmp_path / "r").glob("*.png"))
    slugs = [re.match(r"conjugate-\d+-([a-z-]+)\.png", p).group(1) for p in pngs]
    assert slugs == ["summary", "svaj", "conjugate", "crossovers", "parts", "manufacturing"]
    assert_pages_inked(tmp_path / "r")
    case = load_case(EXAMPLE)
    data = ReportData(design_review(case, run_check(case)))
    rows = dict(key_results(data))
    cams = doc["closure"]["cams"]
    least = min(cams["primary"]["min_force_N"], cams["conjugate"]["min_force_N"])
    assert doc["closure"]["preload_held"] and rows["preload"] == "40 N\u00b7m: held"
    assert rows["least cam force"].startswith(f"{least:.4g} N (the primary cam's)")
    # each cam carries the preload's share and half the net force: the signed rows say they are the net force, and
    # the largest force on a cam (the one its contact stress takes) is above the least, not a fifth of it
    top = max(cams["primary"]["max_force_N"], cams["conjugate"]["max_force_N"])
    assert rows["largest cam force"].startswith(f"{top:.4g} N at ") and top > least
    assert rows["net force, primary cam"].startswith("up to ") and "force, primary cam" not in rows
    assert rows["crossovers"] == "2, at 90.0, 270.0\u00b0" and rows["jump speed"] == "none: form-closed"
    second = doc["closure"]["conjugate_cam"]
    assert rows["conjugate, max angle"].startswith(f"{second['max_pressure_angle_deg']:.2f}\u00b0")
    facts = decision_facts(data)
    assert "two conjugate cams hold" in facts[0] and f"least cam force is {least:.4g} N" in facts[1]
    # the preload holds while it exceeds half the largest net force (N*m about the pivot): 40 > 4.8
    half = 0.5 * np.max(np.abs(data.check.closure.response.contact_force))
    assert f"({half:.4g} N\u00b7m)" in facts[1] and half < 40.0
    assert all(f"at {c['deg']:.1f}\u00b0" in f for c, f in zip(doc["closure"]["crossovers"], facts[2:], strict=True))
    pages = drawn_pages(data)
    text = {slug: figure_text(fig) for slug, fig in pages.items()}
    lines = {slug: {ln.get_label(): ln for ax in fig.axes for ln in ax.get_lines()} for slug, fig in pages.items()}
    assert "conjugate 26.2\u00b0" in text["conjugate"] and "return spring: none" in text["parts"]
    assert "Crossovers at 200 rpm" in text["crossovers"] and "preload 40 N\u00b7m" in text["crossovers"]
    loads = data.check.closure.loads
    on = lines["crossovers"]
    np.testing.assert_array_equal(on["on the primary cam"].get_ydata(), loads.primary_N)
    np.testing.assert_array_equal(on["on the conjugate cam"].get_ydata(), loads.conjugate_N)
    assert "crossover (the force changes cam)" in on
    # with backlash there is no preload: page 1 gives the impacts and says nothing of a preload
    backlash = _yoke(backlash=0.05)
    data = ReportData(design_review(backlash, run_check(backlash)))
    rows, facts = dict(key_results(data)), decision_facts(data)
    assert "preload" not in rows and not any("preload 0" in f for f in facts)
    assert rows["largest impact"].endswith("m/s at 68.8\u00b0") and "0.05 mm backlash" in facts[1]


def test_size_of_conjugate_cams_gives_the_least_preload(tmp_path, capsys):
    """``size`` of a yoke without backlash: the least preload is half the largest net force (m a of a cycloidal rise,
    closed form: 2 pi h / beta^2 omega^2); preload_shares keeps both rollers loaded just above it and unloads one
    just below; the proposed preload (20 % over, rounded up to 0.1 N) written into the case passes check with both
    rollers held and the least cam force size gives."""
    yoke = write_case(tmp_path, "yoke.toml", YOKE_TOML)
    code, out, _ = run(capsys, "size", yoke, "--json")
    doc = json.loads(out)
    omega, beta = 300 * math.pi / 30, math.radians(120)
    f_max = 1.0 * 2 * math.pi * 0.020 / beta**2 * omega**2
    assert code == 0 and doc["closure"] == "conjugate" and not doc["preload_held"] and doc["least_cam_force_N"] == 0
    assert doc["max_net_force_N"] == pytest.approx(f_max, rel=1e-4) and doc["least_preload_N"] == pytest.approx(
        f_max / 2, rel=1e-4
    )
    p = doc["proposed_preload_N"]
    assert p == math.ceil(1.2 * doc["least_preload_N"] * 10) / 10 == 17.0
    r = closure_response(*(lambda c: (c.motion, c.follower, c.model))(_yoke()), omega)
    for preload, held in ((1.001 * f_max / 2, True), (0.999 * f_max / 2, False)):
        first, second = preload_shares(r.contact_force, preload)
        assert bool(np.all(first > 0) and np.all(second > 0)) is held
    yoke.write_text(YOKE_TOML.replace("conjugate_spacing = 150", f"conjugate_spacing = 150\nconjugate_preload = {p}"))
    code, out, _ = run(capsys, "check", yoke, "--json")
    closure = json.loads(out)["closure"]
    least = min(closure["cams"][c]["min_force_N"] for c in ("primary", "conjugate"))
    assert code == 0 and closure["preload_held"] and least == pytest.approx(doc["least_cam_force_at_proposed_N"])
    assert least == pytest.approx(p - f_max / 2, rel=1e-3)  # each cam carries P -+ F/2: the least is P - max|F|/2
    # the shipped rocker: N*m about the pivot; its 40 N*m holds, 8 times the least
    code, out, _ = run(capsys, "size", EXAMPLE, "--json")
    doc = json.loads(out)
    assert doc["preload_held"] and doc["preload_torque_N_m"] == 40 and 4.0 < doc["least_preload_torque_N_m"] < 6.0
    assert doc["least_preload_torque_N_m"] == pytest.approx(doc["max_net_torque_N_m"] / 2)
    code, _, err = run(capsys, "size", EXAMPLE, "--margin", "1.5")
    assert code == 2 and "conjugate cams have no return spring" in err and "least preload" in err


@pytest.mark.slow  # a whole size search and a check (9 s of a worker)
def test_size_of_conjugate_cams_with_backlash_gives_the_largest_backlash(tmp_path, capsys):
    """With backlash (no preload) ``size`` is the groove's: the largest backlash whose impact at the conjugate cam
    stays 2 % under max_impact_velocity; check of the case written with it passes."""
    yoke = write_case(
        tmp_path, "yoke.toml", YOKE_TOML.replace("conjugate_spacing = 150", "conjugate_spacing = 150\nbacklash = 0.05")
    )
    code, out, _ = run(capsys, "size", yoke, "--json")
    doc = json.loads(out)
    b = doc["max_backlash_mm"]
    assert code == 0 and doc["closure"] == "conjugate" and doc["backlash_mm"] == 0.05 and b > 0.05
    yoke.write_text(YOKE_TOML.replace("conjugate_spacing = 150", f"conjugate_spacing = 150\nbacklash = {b}"))
    code, out, _ = run(capsys, "check", yoke, "--json")
    impact = check_value(json.loads(out), "crossover_impact")
    assert code == 0 and impact == pytest.approx(doc["impact_velocity_at_max_backlash_m_per_s"], rel=1e-9)
    assert impact <= 0.98 * 0.1


@pytest.mark.slow  # compiles the crossing and the impact (13 s)
def test_sweep_of_conjugate_cams(tmp_path, capsys):
    """``sweep`` of the preloaded rocker: the least holding preload over speed, max |F| / 2, grows as the speed
    squared (an inertia force) and is size's at the case's speed; the preload holds (least cam force > 0) exactly
    where it exceeds it. With backlash (a yoke, no preload) the sweep is the groove's impact map, check's impact at
    the case's speed."""
    code, out, _ = run(capsys, "sweep", EXAMPLE, "--speeds", "100:800:8", "-o", tmp_path)
    assert code == 0 and "cannot jump" in out and "unloads from 600 rpm" in out
    rows = np.genfromtxt(tmp_path / "conjugate-sweep.csv", delimiter=",", names=True)
    assert rows.dtype.names == ("speed_rpm", "least_cam_force_N", "least_preload_torque_N_m", "preload_held")
    need = rows["least_preload_torque_N_m"]
    np.testing.assert_allclose(need / need[0], (rows["speed_rpm"] / 100.0) ** 2, rtol=2e-2)
    np.testing.assert_array_equal(rows["preload_held"] == 1, need < 40.0)
    np.testing.assert_array_equal(rows["least_cam_force_N"] > 0, need < 40.0)
    size = json.loads(run(capsys, "size", EXAMPLE, "--json")[1])
    assert need[1] == pytest.approx(size["least_preload_torque_N_m"], rel=1e-9)  # 200 rpm
    assert rows["least_cam_force_N"][1] == pytest.approx(size["least_cam_force_N"], rel=1e-9)
    assert (tmp_path / "conjugate-sweep.png").stat().st_size > 10_000
    code, _, err = run(capsys, "sweep", EXAMPLE, "--speeds", "100:800:8", "--backlash", "0.01:0.02:2", "-o", tmp_path)
    assert code == 2 and "--backlash" in err and "preload" in err
    yoke = write_case(
        tmp_path, "yoke.toml", YOKE_TOML.replace("conjugate_spacing = 150", "conjugate_spacing = 150\nbacklash = 0.05")
    )
    impact = check_value(check_json(capsys, yoke), "crossover_impact")
    code, out, _ = run(capsys, "sweep", yoke, "--speeds", "100:300:3", "-o", tmp_path)
    assert code == 0 and "conjugate cam, impact map" in out
    rows = np.genfromtxt(tmp_path / "yoke-sweep.csv", delimiter=",", names=True)
    assert rows["impact_velocity_m_per_s"][-1] == pytest.approx(impact, rel=1e-9)


def test_tolerance_of_preloaded_conjugate_cams_gives_the_chance_a_roller_unloads(tmp_path, capsys):
    """``tolerance`` of a yoke preloaded 15 N over speed: a built cam's roller unloads where its speed needs more
    than the preload, max |F| / 2 = m 2 pi h / beta^2 omega^2 / 2 (closed form): above 300 sqrt(15 / 14.137) rpm;
    each sample's least cam force is the preload less half its largest net force; the worst is the least loaded."""
    tol = '\n[tolerances]\nspeed = "60 rpm"\nmass = "2%"\n'
    preloaded = YOKE_TOML.replace("conjugate_spacing = 150", "conjugate_spacing = 150\nconjugate_preload = 15")
    yoke = write_case(tmp_path, "yoke.toml", preloaded + tol)
    code, out, _ = run(capsys, "tolerance", yoke, "--samples", "60", "--json", "-o", tmp_path)
    doc = json.loads(out)
    rows = np.genfromtxt(tmp_path / "yoke-tolerance.csv", delimiter=",", names=True)
    assert code == 0 and doc["closure"] == "conjugate" and doc["preload_N"] == 15
    omega, beta = rows["speed_rpm"] * math.pi / 30, math.radians(120)
    half = 0.5 * rows["mass_kg"] * 2 * math.pi * 0.020 / beta**2 * omega**2
    np.testing.assert_allclose(rows["least_cam_force_N"], np.maximum(15 - half, 0.0), atol=0.02 * 15)
    clear = np.abs(half - 15) > 0.02 * 15  # away from the edge, where the compliant train's ripple decides
    np.testing.assert_array_equal(rows["unloaded"][clear] == 1, half[clear] > 15)
    assert 0 < np.sum(rows["unloaded"]) < 60
    assert doc["probability_unloaded"] == pytest.approx(np.mean(rows["unloaded"]))
    assert doc["least_cam_force_N"]["min"] == pytest.approx(rows["least_cam_force_N"].min())
    assert doc["worst"][0]["least_cam_force_N"] == pytest.approx(rows["least_cam_force_N"].min())
    assert (tmp_path / "yoke-tolerance.png").stat().st_size > 10_000


def test_table_adds_the_conjugate_cams_columns(tmp_path, capsys):
    """``table`` of a preloaded yoke: the primary's columns as before, then the conjugate cam's geometry (its pitch
    point 150 mm from the primary's at every angle: the rigid yoke; its pressure angle as the geometry's) and each
    cam's force, whose difference is the signed net force."""
    yoke = write_case(
        tmp_path,
        "yoke.toml",
        YOKE_TOML.replace("conjugate_spacing = 150", "conjugate_spacing = 150\nconjugate_preload = 20"),
    )
    code, out, _ = run(capsys, "table", yoke, "--step", "0.5")
    path = tmp_path / "t.csv"
    path.write_text(out)
    rows = np.genfromtxt(path, delimiter=",", names=True)
    names = rows.dtype.names
    assert code == 0 and names[names.index("drive_torque_N_m") + 1 :] == (
        "conjugate_pressure_angle_deg",
        "conjugate_rho_pitch_mm",
        "conjugate_rho_contour_mm",
        "conjugate_pitch_x_mm",
        "conjugate_pitch_y_mm",
        "conjugate_contour_x_mm",
        "conjugate_contour_y_mm",
        "primary_cam_force_N",
        "conjugate_cam_force_N",
    )
    gap = np.hypot(rows["pitch_x_mm"] - rows["conjugate_pitch_x_mm"], rows["pitch_y_mm"] - rows["conjugate_pitch_y_mm"])
    np.testing.assert_allclose(gap, 150.0, rtol=1e-9)  # the CSV keeps 10 digits
    np.testing.assert_allclose(
        np.hypot(
            rows["conjugate_pitch_x_mm"] - rows["conjugate_contour_x_mm"],
            rows["conjugate_pitch_y_mm"] - rows["conjugate_contour_y_mm"],
        ),
        12.0,
        rtol=1e-9,
    )
    geo = conjugate(*(lambda c: (c.motion, c.follower))(_yoke(conjugate_preload=20)))
    on_grid = np.isin(np.round(rows["theta_deg"], 6), np.round(geo.theta_deg, 6))
    np.testing.assert_allclose(
        rows["conjugate_pressure_angle_deg"][on_grid],
        np.interp(rows["theta_deg"][on_grid], geo.theta_deg, geo.pressure_angle_deg),
        atol=1e-9,
    )
    net = rows["primary_cam_force_N"] - rows["conjugate_cam_force_N"]
    np.testing.assert_allclose(net, rows["dynamic_contact_force_N"], atol=1e-9 * 20)
    assert np.all(rows["primary_cam_force_N"] > 0) and np.all(rows["conjugate_cam_force_N"] > 0)  # 20 N > 14.1


def test_a_preload_too_small_to_hold_fails_the_check(capsys, tmp_path):
    """The shipped rocker needs more than 4.824 N*m of preload at 200 rpm (half its largest net torque): at 4 N*m a
    roller lets go, so ``conjugate_preload`` fails (exit 1) with a least cam force of 0; at 6 N*m it holds."""
    raw = tomllib.loads(EXAMPLE.read_text())
    for preload, ok in ((4.0, False), (6.0, True)):
        raw["follower"]["conjugate_preload_torque"] = preload
        path = tmp_path / f"p{preload:g}.toml"
        path.write_text(tomli_w.dumps(raw))
        code, out, _ = run(capsys, "check", path, "--json")
        doc = json.loads(out)
        check = next(c for c in doc["checks"] if c["name"] == "conjugate_preload")
        assert check["ok"] is ok and doc["closure"]["preload_held"] is ok and code == (0 if ok else 1)
        assert (check["value"] > 0.0) is ok
