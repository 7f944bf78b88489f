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
from _helpers import distance_to_outline, run
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

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


def _omega(case) -> float:
    return case.speed_rpm * 2 * np.pi / 60


def _host(case, theta):
    return np.asarray(case.motion.host(np.atleast_1d(theta)))


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
        s = _host(case, th)[0, 0]
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
        ang = math.pi - (psi0 + _host(case, th)[0, 0]) + math.radians(f.conjugate_arm_angle)
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
            q = _host(case, th)[0, 0]
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
    w = _omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    assert [c.deg for c in r.crossovers] == pytest.approx([60.0, 240.0], abs=1e-8)
    assert [(c.from_flank, c.to_flank) for c in r.crossovers] == [("primary", "conjugate"), ("conjugate", "primary")]
    s2 = _host(case, np.deg2rad(r.theta_deg))[2]
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


def test_flight_across_the_conjugate_backlash_uses_the_conjugate_cams_lever():
    """Backlash b is the clearance at the conjugate cam: across it at constant velocity, the gap along the axis is
    b / cos(phi2) with tan(phi2) = s' / (D - Rp - s) (the second roller below the cam centre), not the primary's
    s' / (Rp + s); the conjugate cam meets the yoke where s'(tc) d - (s(tc + d) - s(tc)) = gap."""
    b, D = 0.05, 150.0
    case = _yoke(backlash=b)
    w = _omega(case)
    r = closure_response(case.motion, case.follower, case.model, w)
    c = r.crossovers[0]
    assert (c.from_flank, c.to_flank) == ("primary", "conjugate")
    tc = np.deg2rad(60.0)
    s0 = _host(case, tc)[:, 0]
    gap = b * np.hypot(1.0, s0[1] / (D - 62.0 - s0[0]))
    d = brentq(lambda d: s0[1] * d - (_host(case, tc + d)[0, 0] - s0[0]) - gap, 1e-6, 1.0, xtol=1e-15)
    assert np.deg2rad(c.land_deg) - tc == pytest.approx(d, rel=1e-6)
    v = (s0[1] - _host(case, tc + d)[1, 0]) * w * 1e-3
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

    case_file = tmp_path / "yoke.toml"
    case_file.write_text(YOKE_TOML)
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
    pa = doc["checks"][names.index("conjugate_pressure_angle")]
    assert pa["value"] == pytest.approx(cl["conjugate_cam"]["max_pressure_angle_deg"]) and pa["limit"] == 35.0


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
    w = _omega(case)
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
        p0 = _host(case, tc)[:, 0]
        side = 1.0 if c.from_flank == "primary" else -1.0
        gap = 0.05 / lever["conjugate"](c.deg)

        def rel(d, tc=tc, p0=p0, side=side, gap=gap):
            return side * (p0[1] * d - (_host(case, tc + d)[0, 0] - p0[0])) - gap

        d = brentq(rel, 1e-6, 1.0, xtol=1e-15)
        assert c.to_flank != c.from_flank
        assert np.deg2rad(c.land_deg) - tc == pytest.approx(d, rel=1e-6)
        w_rel = abs(p0[1] - _host(case, tc + d)[1, 0]) * w
        assert c.impact_velocity_m_per_s == pytest.approx(w_rel * arm_m[c.to_flank], rel=1e-6)
        # the impact through the train: scipy's DOP853 from the closed-form landing, the arm pressed on the flank it
        # lands on through k_f and c_f (N*m/rad), the peak torque over a contact period over that cam's lever arm
        to = -side  # +1: pressed up by the primary cam, -1: back by the conjugate one

        def flank_torque(t, y, to=to, gap=gap):  # t (n,) and y (2, n), or one angle and its state
            sv = _host(case, t)
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
        half_sine = (abs(0.05 * w**2 * _host(case, t1)[2, 0]) + w_rel * np.sqrt(kf * 0.05)) / (
            lever[c.to_flank](c.land_deg) * 1e-3
        )
        assert 0.8 * half_sine < c.impact_force_N < 1.25 * half_sine


def test_conjugate_contact_stress_on_each_cam():
    """Each cam's Hertz strip with its own force: where the primary presses, the spring cam's (K = 1/Rr + 1/rho1,
    force over cos phi1); where the conjugate does, its own (K = 1/Rr2 + 1/rho2 of its contour, force over cos phi2);
    under a preload both press and the larger pressure is reported."""
    from camdyn.model.contact import cam_contact, conjugate_contact

    case = _yoke(conjugate_roller_radius=10.0)
    r = closure_response(case.motion, case.follower, case.model, _omega(case))
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
