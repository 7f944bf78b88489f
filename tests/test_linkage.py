"""Assur dyads, cam-linkage synthesis (Ye & Smith 2005 section 8, the CCM), derivatives and errors."""

import math
import tomllib
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _helpers import assert_keys_by_type

import camdyn.model  # noqa: F401  (float64)
from camdyn import InputError, NumericalError
from camdyn.model.geometry import analyze, extremes, passes
from camdyn.model.linkage import (
    cross2,
    parse_mechanism,
    rrp_kinematics,
    rrr,
    rrr_kinematics,
    rrr_reach_miss,
    synthesize_motion,
)
from camdyn.model.motion import evaluate as evaluate_motion
from camdyn.schema import MechanismSpec

CASES = Path(__file__).resolve().parents[1] / "cases"
SHIPPED = ("racetrack", "ellipse", "square", "circle", "eight", "line")


def evaluate(syn, theta, motion=None):
    """``motion(theta)`` (default: the synthesis' exact motion) at as many angles as its Hermite table has
    intervals, padded: the program the table's construction compiled is reused, not compiled again."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    n = len(syn.tabulated.knots) - 1
    assert len(theta) <= n
    return np.asarray(evaluate_motion(motion or syn.motion, jnp.asarray(np.resize(theta, n))))[:, : len(theta)]


def load(name):
    return tomllib.loads((CASES / f"{name}.toml").read_text())


@pytest.fixture
def racetrack(path_synthesis):
    return path_synthesis("racetrack")


# ------------------------------------------------------------------------------------------------ dyads
# the dyads compiled: eager jax.numpy compiles one small program per operation
rrr_ = jax.jit(rrr, static_argnums=4)
reach_miss_ = jax.jit(rrr_reach_miss)
rrr_kinematics_ = jax.jit(rrr_kinematics, static_argnums=4)
rrp_kinematics_ = jax.jit(rrp_kinematics, static_argnums=4)


def test_rrr_closes_with_the_paper_mode_convention():
    p, q = np.array([0.0, 0.0]), np.array([10.0, 0.0])
    for mode in (1, -1):
        m = np.asarray(rrr_(p, q, 6.0, 7.0, mode))
        assert np.linalg.norm(m - p) == pytest.approx(6.0) and np.linalg.norm(m - q) == pytest.approx(7.0)
        # mode +1: P, M, Q anticlockwise (Ye & Smith, Appendix 2: theta_PM = theta_PQ - angle MPQ)
        assert np.sign(cross2(m - p, q - p)) == mode
    assert float(reach_miss_(p, q, 3.0, 4.0)) == pytest.approx(3.0)
    assert float(reach_miss_(p, q, 30.0, 4.0)) == pytest.approx(16.0)
    assert float(reach_miss_(p, q, 6.0, 7.0)) == 0.0


def test_rrr_velocity_matches_ye_smith_explicit_formulas_and_acceleration_fd():
    rng = np.random.default_rng(3)
    p = np.vstack([[0.0, 0.0], rng.normal(size=2), rng.normal(size=2)])
    q = np.vstack([[9.0, 2.0], rng.normal(size=2), rng.normal(size=2)])
    lp, lq = 6.0, 5.0
    k = {key: np.asarray(v) for key, v in rrr_kinematics_(p, q, lp, lq, 1).items()}
    t_ab, t_cb = float(k["theta_pm"][0]), float(k["theta_qm"][0])
    dv = p[1] - q[1]  # Appendix 2 with A -> P, C -> Q: omega_AB and omega_CB
    w_ab = (dv[0] * math.cos(t_cb) + dv[1] * math.sin(t_cb)) / (lp * math.sin(t_ab - t_cb))
    w_cb = (dv[0] * math.cos(t_ab) + dv[1] * math.sin(t_ab)) / (lq * math.sin(t_ab - t_cb))
    assert float(k["theta_pm"][1]) == pytest.approx(w_ab, rel=1e-12)
    assert float(k["theta_qm"][1]) == pytest.approx(w_cb, rel=1e-12)
    h = 1e-5

    def at(tau):
        return np.asarray(rrr_(p[0] + p[1] * tau + p[2] * tau**2 / 2, q[0] + q[1] * tau + q[2] * tau**2 / 2, lp, lq, 1))

    fd2 = (at(h) - 2 * at(0.0) + at(-h)) / h**2
    assert np.allclose(np.asarray(k["M"][2]), fd2, atol=1e-5)


def test_rrp_kinematics_against_finite_differences():
    c = np.array([[3.0, 4.0], [0.5, -0.2], [0.1, 0.3]])
    origin, direction = np.array([0.0, 0.0]), np.array([1.0, 0.0])
    k = {key: np.asarray(v) for key, v in rrp_kinematics_(c, origin, direction, 6.0, 1).items()}
    assert float(k["p"][0]) == pytest.approx(3.0 + math.sqrt(36 - 16))
    h = 1e-5

    def pos(tau):
        moved = np.array([c[0] + c[1] * tau + c[2] * tau**2 / 2, c[1], c[2]])
        return float(np.asarray(rrp_kinematics_(moved, origin, direction, 6.0, 1)["p"])[0])

    assert float(k["p"][1]) == pytest.approx((pos(h) - pos(-h)) / (2 * h), rel=1e-8)
    assert float(k["p"][2]) == pytest.approx((pos(h) - 2 * pos(0) + pos(-h)) / h**2, rel=1e-4)


# ------------------------------------------------------------------------------------------------ Ye & Smith
@pytest.mark.slow
def test_ye_smith_section_8(racetrack):
    j = racetrack.json()
    # first phase (section 4): extremes of |OB| and eq. 5
    assert j["lob_min_mm"] == pytest.approx(272.383, abs=5e-4)
    assert j["lob_max_mm"] == pytest.approx(341.069, abs=5e-4)
    assert round(j["u_lob_min"] * 4000) == 416 and round(j["u_lob_max"] * 4000) == 2442
    assert j["crank_mm"] == pytest.approx(34.3428, abs=5e-5)  # LOA
    assert j["coupler_mm"] == pytest.approx(306.726, abs=5e-4)  # LBA
    assert (j["start_angle_deg"] + 180) % 360 - 180 == pytest.approx(-51.9412, abs=5e-5)  # theta_OA0
    assert j["rotation"] == "ccw"
    # intermediate printed values at I = 0 and I = 800
    m = racetrack.motion
    chain = m.chain
    points = eqx.filter_jit(lambda c, u: c.points(u))
    p0, p800 = points(chain, jnp.asarray(0.0)), points(chain, jnp.asarray(0.2))
    ang = lambda v: math.degrees(math.atan2(float(v[1]), float(v[0])))  # noqa: E731
    assert ang(p0["C"] - p0["F"]) == pytest.approx(-102.193, abs=1e-3)  # theta_F0C0
    assert ang(p0["C"] - chain.pivot) == pytest.approx(-178.332, abs=1e-3)  # theta_DC0
    assert np.allclose(np.asarray(p0["B"]), [-281.681, 21.5527], atol=1e-3)
    assert ang(p800["C"] - p800["F"]) == pytest.approx(-104.789, abs=1e-3)
    assert ang(p800["C"] - chain.pivot) == pytest.approx(164.621, abs=1e-3)
    assert np.allclose(np.asarray(p800["B"]), [-269.58, 80.7212], atol=5e-3)
    assert np.allclose(np.asarray(p800["E"]), [10.8823, -110.498], atol=1e-3)
    crank, cam = eqx.filter_jit(lambda mm, u: (mm.crank_angle(u), mm.cam_angle(u)))(m, jnp.asarray(0.2))
    assert math.degrees(float(crank)) == pytest.approx(28.1442, abs=1e-4)  # theta_OA
    theta = float(cam) % (2 * math.pi)  # cam angle, not unwrapped
    assert math.degrees(theta) == pytest.approx(80.0853, abs=1e-4)
    # eqs. 6-8 at I = 800: the pitch point and the contour point in the cam frame
    c, s = math.cos(theta), math.sin(theta)
    xe, ye = (float(v) for v in p800["E"])
    xe1, ye1 = xe * c + ye * s, -xe * s + ye * c
    assert (xe1, ye1) == pytest.approx((-106.974, -29.745), abs=1e-3)

    def e1(u):  # E in the cam frame
        th, e = m.cam_angle(u), chain.points(u)["E"]
        return jnp.stack([e[0] * jnp.cos(th) + e[1] * jnp.sin(th), -e[0] * jnp.sin(th) + e[1] * jnp.cos(th)])

    v = np.asarray(jax.jit(lambda u: jax.jvp(e1, (u,), (jnp.ones_like(u),))[1])(jnp.asarray(0.2)))
    v = v / np.linalg.norm(v)
    xt1, yt1 = xe1 + 20 * v[1], ye1 - 20 * v[0]
    assert yt1 == pytest.approx(-22.5475, abs=1e-3)
    assert xt1 == pytest.approx(-88.3139, abs=1e-3)  # the paper prints -88.3199: an arithmetic slip
    assert abs(xt1 - -88.3199) > 5e-3
    # camdyn's cam geometry from the synthesized follower (an independent route: the envelope of the roller
    # about the arm pivot, not eqs. 6-8) gives the same pitch and contour points, of the exact and tabulated motion
    for motion in (racetrack.motion, racetrack.tabulated):
        cols = analyze(motion, racetrack.follower, n=16).table([math.degrees(theta)])
        assert np.allclose([cols["pitch_x_mm"][0], cols["pitch_y_mm"][0]], [xe1, ye1], atol=1e-6)
        assert np.allclose([cols["contour_x_mm"][0], cols["contour_y_mm"][0]], [xt1, yt1], atol=1e-6)


@pytest.mark.slow
def test_follower_spec_reproduces_the_pitch_curve(racetrack):
    """The FollowerSpec and phi(theta) in the shared geometry convention give back the roller centre E."""
    f = racetrack.follower
    th = np.deg2rad(np.arange(0.0, 360.0, 7.0))
    phi = evaluate(racetrack, th)[0]
    assert (
        phi.min() >= -1e-12 and evaluate(racetrack, np.linspace(0.0, 2 * math.pi, 1024, endpoint=False))[0].min() < 1e-5
    )
    d = f.pivot_distance * np.array([math.cos(math.radians(f.pivot_angle)), math.sin(math.radians(f.pivot_angle))])
    dn = -d / np.linalg.norm(d)
    psi0 = racetrack.summary["psi0_deg"] * math.pi / 180
    dist0 = np.linalg.norm(
        d
        + f.arm_length
        * np.array(
            [math.cos(-psi0) * dn[0] - math.sin(-psi0) * dn[1], math.sin(-psi0) * dn[0] + math.cos(-psi0) * dn[1]]
        )
    )
    assert dist0 == pytest.approx(f.base_radius + f.roller_radius, rel=1e-12)
    psi = psi0 + phi
    e = d + f.arm_length * np.column_stack(
        [np.cos(-psi) * dn[0] - np.sin(-psi) * dn[1], np.sin(-psi) * dn[0] + np.cos(-psi) * dn[1]]
    )
    a = -th  # ccw cam: cam frame = fixed frame turned back by theta
    pitch = np.column_stack([np.cos(a) * e[:, 0] - np.sin(a) * e[:, 1], np.sin(a) * e[:, 0] + np.cos(a) * e[:, 1]])
    assert np.max(np.abs(pitch - racetrack.pitch[::7])) < 1e-9


@pytest.mark.slow
def test_motion_derivatives_match_finite_differences_through_the_singular_positions(racetrack):
    m = racetrack.motion
    sw = [s["cam_angle_deg"] for s in racetrack.summary["switches"]]
    dyad = m.crank_dyad
    # points: the switches themselves, just inside and outside their series windows, and ordinary angles
    pts = list(np.deg2rad(sw))
    for k, s in enumerate(racetrack.summary["switches"]):
        for t in (float(dyad.lo[k]), float(dyad.hi[k])):
            for e in (-1e-7, 1e-7):
                u = s["u"] + t + e
                pts.append(u)
    raw = eqx.filter_jit(lambda mm, u: jax.vmap(mm.cam_angle)(u))
    pts[len(sw) :] = list(np.asarray(raw(m, jnp.asarray(pts[len(sw) :]))) % (2 * math.pi))
    pts += [0.3, 1.7, 4.0]
    th = np.asarray(pts)
    h = 1e-5
    v, vp, vm = (evaluate(racetrack, x) for x in (th, th + h, th - h))
    assert np.all(np.isfinite(v))
    for k in (1, 2, 3):
        fd = (vp[k - 1] - vm[k - 1]) / (2 * h)
        scale = np.abs(v[k]).max()
        # 1e-11 at the switches; the series meets acos at the window edges within 2e-7 relative (third derivative)
        assert np.max(np.abs(fd - v[k])) < 1e-6 * scale, (k, np.abs(fd - v[k]).max(), scale)
        assert np.max(np.abs(fd - v[k])[: len(sw)]) < 1e-9 * scale
    # no jump across a window edge: the series and the closed form agree in value and derivatives
    u_edge = racetrack.summary["switches"][0]["u"] + float(dyad.hi[0])
    at_u = eqx.filter_jit(lambda mm, u: jax.vmap(mm.at_u)(u))
    a, b, c = np.asarray(at_u(m, jnp.asarray([u_edge - 1e-10, u_edge + 1e-10, racetrack.summary["switches"][0]["u"]])))
    assert abs((a[0, 0] - b[0, 0] + math.pi) % (2 * math.pi) - math.pi) < 1e-8  # angle: equal modulo 2 pi
    assert np.allclose(a[0, 1], b[0, 1], atol=1e-8) and np.allclose(a[1:], b[1:], rtol=1e-6, atol=1e-9)
    # the crank passes the singular position with finite, non-zero speed: dTheta/du at the switch
    assert 0 < float(c[1, 0]) < 1e3


@pytest.mark.slow
def test_motion_breaks(racetrack):
    m = racetrack.motion
    assert m.unit == "rad" and m.breaks_deg == tuple(sorted(m.breaks_deg)) and len(m.breaks_deg) == 4
    assert m.breaks_deg[0] == 0.0  # the path starts at a straight-arc joint


# ------------------------------------------------------------------------------------------------ shipped cases
@pytest.mark.slow
@pytest.mark.parametrize("name", SHIPPED)
def test_forward_check_of_every_shipped_case(name, path_synthesis):
    case = load(name)
    assert "motion" not in case and "follower" not in case and {"path", "mechanism", "dynamics", "limits"} <= set(case)
    syn = path_synthesis(name)
    j = syn.json()
    assert j["max_path_error_mm"] < 1e-3
    assert np.max(np.linalg.norm(syn.traced_xy - syn.path_xy, axis=1)) == pytest.approx(j["max_path_error_mm"])
    # the dynamics read the quintic table: it must follow the exact motion (s to a micron, s'' to 2e-5 of its range)
    tab, th = syn.tabulated, jnp.asarray(np.random.default_rng(1).uniform(0.0, 2 * np.pi, 400))
    exact, table = evaluate(syn, th), evaluate(syn, th, tab)
    assert np.max(np.abs(table[0] - exact[0])) < 1e-6 and syn.summary["motion_table_error"]["s"] < 1e-6
    assert np.max(np.abs(table[2] - exact[2])) < 2e-5 * np.ptp(exact[2])
    assert {
        "crank_mm",
        "coupler_mm",
        "start_angle_deg",
        "pitch",
        "contour",
        "path_xy",
        "traced_xy",
        "sharp_corners",
        "warnings",
    } <= set(j)
    assert ("stroke_mm" in j) == (syn.motion.unit == "mm") and ("swing_deg" in j) == (syn.motion.unit == "rad")
    assert not syn.sharp_corners
    # the contour lies one roller radius inside the pitch curve
    gap = np.linalg.norm(syn.pitch - syn.contour, axis=1)
    assert np.allclose(gap, syn.follower.roller_radius)
    links = syn.linkage_at([0.0, 90.0])
    tracer = "T" if case["mechanism"]["type"] == "ccm" else "F"
    assert np.allclose(links[tracer], syn.path_xy[[0, 90]], atol=1e-6)


@pytest.mark.slow
def test_square_corners(path_synthesis):
    case = load("square")
    syn = path_synthesis("square")  # corner_radius = 5: four straights and four arcs
    assert syn.summary["max_path_error_mm"] < 1e-3 and len(syn.motion.breaks_deg) == 8
    sharp = synthesize_motion(dict(case["path"], corner_radius=0.0), case["mechanism"])
    assert sharp.sharp_corners and any("sharp corners" in w for w in sharp.warnings)
    assert np.all(np.isfinite(sharp.pitch)) and np.all(np.isfinite(sharp.traced_xy))


# ------------------------------------------------------------------------------------------------ errors
def test_unreachable_path_names_the_point_and_the_miss():
    case = load("racetrack")
    with pytest.raises(NumericalError) as err:
        synthesize_motion(case["path"], dict(case["mechanism"], follower_link=100.0))
    assert err.value.where.startswith("path point ") and "(u = " in err.value.where
    assert "cannot close: reach missed by" in err.value.message
    miss = float(err.value.message.split("reach missed by ")[1].split()[0])
    assert 0 < miss < 200
    with pytest.raises(NumericalError, match="crank dyad cannot close: reach missed by 1"):
        synthesize_motion(case["path"], dict(case["mechanism"], crank=34.3428, coupler=305.0))


@pytest.mark.slow
def test_reversing_crank_is_refused():
    case = load("circle")
    # crank and coupler that close everywhere but never reach collinear: the crank rocks instead of turning
    with pytest.raises(NumericalError) as err:
        synthesize_motion(case["path"], dict(case["mechanism"], crank=25.0, coupler=65.0))
    assert "the crank would reverse" in err.value.message and err.value.where.startswith("path point ")
    # cam centre inside the path: the crank turns twice per loop
    with pytest.raises(NumericalError, match="turns 720.0 deg"):
        synthesize_motion(case["path"], dict(case["mechanism"], cam_center=[0.0, 5.0]))


@pytest.mark.parametrize(
    "mech, key",
    [
        (dict(type="ccm", slider_angle=0.0), "mechanism.link"),
        (dict(type="ccm", link=10.0, slider_angle=0.0, pivot=[1, 1]), "mechanism.pivot"),
        (dict(type="ccm", link=10.0, slider_angle=0.0, crank=3.0), "mechanism.coupler"),
        (dict(type="ccm", link=10.0, slider_angle=0.0, crank_mode=2), "mechanism.crank_mode"),
        (dict(type="slider-crank"), "mechanism.type"),
    ],
)
def test_invalid_mechanism_tables_name_the_key(mech, key):
    with pytest.raises(InputError) as err:
        synthesize_motion(dict(type="circle", center=[0, 0], radius=10), mech)
    assert err.value.where == key


def test_json_schema_declares_the_mechanism_keys_each_type_needs_and_takes():
    rules = {r["if"]["properties"]["type"]["const"]: r["then"] for r in MechanismSpec.model_json_schema()["allOf"]}
    tables = {"ccm": load("circle")["mechanism"], "oscillating": load("racetrack")["mechanism"]}
    assert set(rules) == set(tables)
    values = {k: v for t in tables.values() for k, v in t.items() if k != "type"} | dict(
        joint_distance=10.0, joint_angle=5.0, slider_mode=-1, base_radius=50.0, max_pressure_angle=25.0, arm_angle=170.0
    )
    for kind, table in tables.items():
        assert_keys_by_type(table, rules[kind], parse_mechanism, values, kind, "mechanism")


@pytest.mark.slow
def test_chosen_base_radius_is_the_least_half_millimetre_check_accepts(path_synthesis):
    """A path case without base_radius gets the least on a 0.5 mm grid that passes check's default limits."""
    syn = path_synthesis("circle")
    f, tab = syn.follower, syn.tabulated
    assert f.base_radius % 0.5 == 0.0 and "base_radius" not in load("circle")["mechanism"]
    assert passes(f, extremes(tab, f), 30.0, 1.5)
    assert not passes(f, extremes(tab, f, base_radius=f.base_radius - 0.5), 30.0, 1.5)


@pytest.mark.slow  # compiles the padded crank's programs and their gradient
def test_a_crank_without_switches_is_padded_and_is_the_closed_form():
    """A crank with slack (no singular position) is padded to the two switches of the usual crank, so it shares
    their compiled programs, and its angle is still the closed form: the padding is never reached."""
    from camdyn.model.linkage._crank import _padded_dyad

    r, coupler, m_start = 12.0, 20.0, -1.0
    dyad = _padded_dyad(r, coupler, [], [], [], [], [], [], [], [], [], m_start)
    assert dyad.n_switch == 0 and dyad.u_sw.shape == (2,) and dyad.qpoly.shape[0] == 2

    def p_side(u):
        return jnp.stack([20.0 * jnp.cos(2 * jnp.pi * u) - 2.0, 20.0 * jnp.sin(2 * jnp.pi * u) - 3.0])

    u = np.linspace(0.0, 1.0, 9)
    alpha, phi = jax.vmap(lambda v: dyad.angles(p_side, v))(jnp.asarray(u))
    p = np.asarray(jax.vmap(p_side)(jnp.asarray(u)))
    d = np.linalg.norm(p, axis=1)
    np.testing.assert_allclose(alpha, np.arctan2(p[:, 1], p[:, 0]), rtol=0, atol=1e-14)
    np.testing.assert_allclose(phi, m_start * np.arccos((r * r + d * d - coupler**2) / (2 * r * d)), rtol=0, atol=1e-13)
    slope = jax.vmap(jax.grad(lambda v: dyad.angles(p_side, v)[1]))(jnp.asarray(u))
    assert np.all(np.isfinite(slope))


@pytest.mark.slow  # three whole checks of path cases, each a synthesis
def test_a_linkage_that_cannot_trace_its_path_fails_check():
    """The shipped circle with its cam centre moved and a crank and coupler given: the forward dyad changes assembly
    mode along the path, so the linkage the cam drives misses the circle by its diameter and passes through a dead
    centre. check judges both (it passed with three warnings before); the shipped circle passes them with margin."""
    from camdyn.design.checks import run_check
    from camdyn.model.case import case_from_dict

    doc = load("circle")
    shipped = {c.name: c for c in run_check(case_from_dict(doc)).checks}
    assert shipped["path_error"].ok and shipped["path_error"].value < 1e-9
    assert shipped["transmission_angle"].ok and shipped["transmission_angle"].value == pytest.approx(47.67, abs=0.01)
    doc["mechanism"] |= {"cam_center": [2.0, 3.0], "crank": 12.0, "coupler": 20.0}
    report = run_check(case_from_dict(doc))
    checks = {c.name: c for c in report.checks}
    assert report.verdict == "fail"
    assert not checks["path_error"].ok and checks["path_error"].value == pytest.approx(40.0, abs=0.01)  # the diameter
    assert not checks["transmission_angle"].ok and checks["transmission_angle"].value < 1.0
    assert any("changes assembly mode" in w for w in report.warnings)
    doc["limits"] |= {"max_path_error": 50.0, "min_transmission_angle": 0.1}  # the limits are the user's
    assert all(c.ok for c in run_check(case_from_dict(doc)).checks if c.name in ("path_error", "transmission_angle"))
