"""A rocker's geometry (``[valvetrain.rocker]``): the ratio varies with lift (issue 24).

Checked against independent routes: the rocker turned as a rigid body in the plane (the turn found by root finding,
the valve's point rotated), its ratio and the ratio's derivative by finite differences; closed forms (a straight
rocker's constant arm ratio, a bent one's ratio 1 where its arms lean equally); a straight rocker's two-mass response
is the constant ratio's; a rigid train's cam force from Lagrange's equation with the ratio's derivative; scipy's
solve_ivp on the two masses through the rocker, past float, with the seat.
"""

import copy
import math

import numpy as np
import pytest
from scipy.optimize import brentq
from test_valvetrain import CASES, EVENT, SHIPPED, _solve_ivp_event, _valvetrain

from camdyn import InputError
from camdyn._core.units import RPM
from camdyn.model.case import case_from_dict
from camdyn.model.dynamics import valvetrain_response
from camdyn.model.valvetrain import Rocker

# a bent rocker for the shipped case's 6.375 mm tappet lift: 25 mm and 40 mm arms, the cam arm square at half lift
ROCKER = {"cam_arm": 25.0, "valve_arm": 40.0, "cam_arm_angle": -7.3, "valve_arm_angle": -2.0}


def _rocker(cam_arm, valve_arm, cam_arm_angle=0.0, valve_arm_angle=0.0) -> Rocker:
    a = lambda x: np.asarray(float(x))  # noqa: E731
    angles = a(math.radians(cam_arm_angle)), a(math.radians(valve_arm_angle))
    return Rocker(a(cam_arm * 1e-3), a(valve_arm * 1e-3), *angles)


def _planar(cam_arm, valve_arm, cam_arm_angle=0.0, valve_arm_angle=0.0):
    """x_c (m) -> the valve's lift through the rocker (m): the rocker turned as a rigid body until its cam-side
    point has lifted x_c along the follower's line (root finding), its valve-side point rotated by the same turn."""
    a, b = cam_arm * 1e-3, valve_arm * 1e-3
    al, be = math.radians(cam_arm_angle), math.radians(valve_arm_angle)
    cam0 = a * np.array([math.cos(al), math.sin(al)])
    valve0 = b * np.array([math.cos(be), math.sin(be)])

    def turned(p, phi):
        c, s = math.cos(phi), math.sin(phi)
        return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])

    def lift(x):
        phi = brentq(lambda f: turned(cam0, f)[1] - cam0[1] - x, -al - 1.5, 1.5 - al, xtol=1e-15, rtol=1e-15)
        return turned(valve0, phi)[1] - valve0[1]

    return lift


def _fd(f, x, h=1e-6):
    return (f(x + h) - f(x - h)) / (2 * h)


def _with_rocker(raw, rocker=ROCKER):
    raw = copy.deepcopy(raw)
    raw["valvetrain"].pop("ratio", None)
    raw["valvetrain"]["rocker"] = dict(rocker)
    return raw


def test_straight_rocker_is_its_arms_ratio():
    """Arms in line through the pivot (equal angles): the ratio is valve_arm / cam_arm at every lift; equal arms,
    valve lift = follower lift."""
    x = np.linspace(0.0, 8e-3, 9)
    for a, b, angle, ratio in ((25.0, 40.0, -7.0, 1.6), (30.0, 30.0, 12.0, 1.0)):
        g, r, r1 = _rocker(a, b, angle, angle).lever(x)
        assert np.asarray(g) == pytest.approx(ratio * x, rel=1e-12, abs=1e-18)
        assert np.asarray(r) == pytest.approx(ratio, rel=1e-12) and np.asarray(r1) == pytest.approx(0.0, abs=1e-12)


def test_bent_rocker_ratio_is_one_where_equal_arms_lean_equally():
    """Equal arms, the cam arm 20 deg below square and the valve arm square at zero lift: turned 10 deg both lean
    10 deg, the symmetric point, where the ratio is 1; elsewhere cos(valve arm) / cos(cam arm) (closed form)."""
    rocker = _rocker(30.0, 30.0, -20.0, 0.0)
    x_sym = 30e-3 * (math.sin(math.radians(-10.0)) - math.sin(math.radians(-20.0)))
    assert float(rocker.lever(x_sym)[1]) == pytest.approx(1.0, abs=1e-12)
    for turn_deg in (0.0, 5.0, 15.0, 25.0):
        phi = math.radians(turn_deg)
        x = 30e-3 * (math.sin(phi - math.radians(20.0)) - math.sin(math.radians(-20.0)))
        expected = math.cos(phi) / math.cos(phi - math.radians(20.0))
        assert float(rocker.lever(x)[1]) == pytest.approx(expected, rel=1e-12)
    assert float(rocker.lever(0.0)[1]) > 1.0 > float(rocker.lever(2 * x_sym)[1])


@pytest.mark.parametrize("geometry", [(25.0, 40.0, -7.3, -2.0), (20.0, 38.0, 10.0, -15.0), (45.0, 30.0, -3.0, 8.0)])
def test_rocker_lift_ratio_and_its_slope_against_the_plane(geometry):
    """The valve's lift through the rocker against the rocker turned in the plane (root finding), the ratio against
    finite differences of that lift, and the ratio's slope against finite differences of the ratio."""
    rocker, planar = _rocker(*geometry), _planar(*geometry)
    for x in np.linspace(0.0, 7e-3, 8):
        g, r, r1 = (float(v) for v in rocker.lever(x))
        assert g == pytest.approx(planar(x), abs=1e-13)
        assert r == pytest.approx(_fd(planar, x), rel=1e-7)
        assert r1 == pytest.approx(_fd(lambda u: float(rocker.lever(u)[1]), x), rel=1e-6, abs=1e-9)


def test_ratio_and_a_rocker_are_refused_together():
    raw = _with_rocker(SHIPPED)
    raw["valvetrain"]["ratio"] = 1.6
    with pytest.raises(InputError) as err:
        case_from_dict(raw)
    assert err.value.where == "valvetrain.ratio" and "not both" in str(err.value)


def test_a_rocker_that_turns_square_is_refused():
    """A 5 mm cam arm cannot carry the shipped case's 6.375 mm of tappet lift: one line naming the rocker."""
    with pytest.raises(InputError) as err:
        case_from_dict(_with_rocker(SHIPPED, ROCKER | {"cam_arm": 5.0}))
    assert err.value.where == "valvetrain.rocker" and "square" in str(err.value)


# a bent rocker whose ratio varies by 5 % over cases/valve-lift.csv's 10 mm of valve lift (6.25 mm at the tappet)
TABLE_ROCKER = {"cam_arm": 25.0, "valve_arm": 40.0, "cam_arm_angle": -12.0, "valve_arm_angle": -2.0}


def _valve_table_rocker_case(tmp_path, rocker=TABLE_ROCKER, lash=0.2, **motion):
    """cases/valve-lift.csv read as the lift at the valve, through ``rocker``, rigid train and cam contact."""
    import tomli_w

    from camdyn.model.case import load_case

    (tmp_path / "valve.csv").write_text((CASES / "valve-lift.csv").read_text())
    raw = _with_rocker(SHIPPED, rocker)
    raw["motion"] = {"valve_table": "valve.csv"} | motion
    raw["valvetrain"]["lash"] = lash
    raw["valvetrain"].pop("stiffness")
    path = tmp_path / "vt.toml"
    path.write_text(tomli_w.dumps(raw))
    return load_case(path)


@pytest.mark.slow  # compiles a valve table's fit through a rocker
def test_valve_table_through_a_rocker_is_reproduced_at_the_valve(tmp_path):
    """A valve-lift table through a bent rocker, rigid train: the valve's lift (``table``'s valve_lift_mm) reproduces
    the table within the fit's stated residual, and the follower's lift carried back through the rocker turned in
    the plane is the table with its lash ramps, to that residual (which is measured there, at the valve)."""
    from camdyn.design.table import motion_table

    case = _valve_table_rocker_case(tmp_path)
    fit = case.fit
    assert case.motion_source == "valve_table" and fit.follower_data is not None
    data = np.loadtxt(CASES / "valve-lift.csv", delimiter=",", skiprows=1)
    cols = motion_table(case, step_deg=1.0, speed_rpm=1000)
    assert np.allclose(cols["theta_deg"], data[:, 0])
    stated = fit.json()["max_residual"]
    assert 1e-4 < stated < 0.01  # mm: the fit's own, not a bound made loose
    assert np.max(np.abs(cols["valve_lift_mm"] - data[:, 1])) <= stated + 1e-9
    planar = _planar(**TABLE_ROCKER)
    through = np.array([planar(x * 1e-3) for x in cols["s_mm"]]) * 1e3  # the cam's lift at the valve, mm
    assert fit.data[data[:, 1] > 0] == pytest.approx(data[data[:, 1] > 0, 1] + 0.2, abs=1e-12)
    assert np.max(np.abs(through - fit.data)) == pytest.approx(stated, rel=1e-6)  # the stated residual is this
    # the lash ramps at 0.015 mm/deg at the valve: 13.3 deg each side of the event, from the base circle
    ramp = fit.data[(data[:, 1] == 0) & (fit.data > 0)]
    assert ramp.size and np.all(ramp <= 0.2) and np.max(np.abs(np.diff(np.sort(ramp)))) == pytest.approx(0.015)
    # the data points at the follower: their lift through the plane's rocker is the table with its ramps
    assert np.array([planar(x * 1e-3) for x in fit.data_at_follower]) * 1e3 == pytest.approx(fit.data, abs=1e-12)
    ratios = np.array([_fd(planar, x * 1e-3) for x in cols["s_mm"]])
    assert ratios.max() - ratios.min() > 0.05  # the rocker's ratio varies over the lift: not a constant ratio


def test_valve_table_through_a_rocker_meets_a_tolerance_at_the_valve(tmp_path):
    """``tolerance`` bounds the residual at the valve, where the table is given, though the fit is made at the
    follower: 2 um, below the 3 um the smoothing would leave."""
    case = _valve_table_rocker_case(tmp_path, tolerance=0.002)
    fit = case.fit.json()
    assert "tolerance" in fit["method"] and fit["tolerance"] == 0.002
    assert 0.0015 < fit["max_residual"] <= 0.002 * (1 + 1e-9)
    planar = _planar(**TABLE_ROCKER)
    theta = np.deg2rad(case.fit.theta_deg)
    through = np.array([planar(x * 1e-3) for x in case.motion.host(theta)[0]]) * 1e3
    assert np.max(np.abs(through - case.fit.data)) <= 0.002 * (1 + 1e-9)


def test_valve_table_beyond_the_rockers_reach_is_refused(tmp_path):
    """A valve arm 60 deg past square at zero lift gives at most 40 (1 - sin 60 deg) = 5.36 mm at the valve: the
    table's 10 mm is refused at its first row asking for more, by angle and line."""
    with pytest.raises(InputError) as err:
        _valve_table_rocker_case(tmp_path, TABLE_ROCKER | {"valve_arm_angle": 60.0})
    data = np.loadtxt(CASES / "valve-lift.csv", delimiter=",", skiprows=1)
    first = int(np.flatnonzero(data[:, 1] + 0.2 > 40.0 * (1.0 - math.sin(math.radians(60.0))))[0])
    assert err.value.where == f"valve.csv line {first + 2}"
    assert (
        f"at {data[first, 0]:g} deg" in str(err.value)
        and "5.359 mm" in str(err.value)
        and "valve arm" in str(err.value)
    )


def test_case_model_ratio_is_the_rockers_at_peak_lift():
    case = case_from_dict(_with_rocker(SHIPPED))
    peak = 6.375e-3
    assert float(case.valvetrain.ratio) == pytest.approx(_fd(_planar(**ROCKER), peak), rel=1e-7)
    assert float(case.model.mass) == pytest.approx(0.12 + 0.07 * float(case.valvetrain.ratio) ** 2, rel=1e-12)


@pytest.mark.slow
def test_straight_rocker_moves_the_valve_as_the_constant_ratio():
    """A straight rocker of arms 25 and 40 mm is the shipped case's 1.6 ratio: the same valve event, to rounding."""
    const = case_from_dict(copy.deepcopy(SHIPPED))
    straight = case_from_dict(_with_rocker(SHIPPED, ROCKER | {"valve_arm_angle": ROCKER["cam_arm_angle"]}))
    omega = 3000 * RPM
    a = valvetrain_response(const.motion, const.valvetrain, omega)
    b = valvetrain_response(straight.motion, straight.valvetrain, omega)
    assert np.max(np.abs(a.valve_lift - b.valve_lift)) < 1e-7  # mm
    assert b.seating_velocity == pytest.approx(a.seating_velocity, rel=1e-7)
    assert b.seating_deg == pytest.approx(a.seating_deg, abs=1e-6)


@pytest.mark.slow
def test_rigid_rocker_train_cam_force_is_lagranges():
    """Rigid cam contact and train, no lash, no float at 2500 rpm: the valve lift is g(s), and the cam force over
    the event is Lagrange's for one body through the rocker, m_c s'' + r m_v (r s'' + r' s'^2) w^2 + r (spring)
    + the tappet force, with g, r and r' from the plane (finite differences). The r' s'^2 term alone is many times
    the tolerance."""
    raw = _with_rocker(SHIPPED)
    raw["valvetrain"] |= {"lash": 0.0, "tappet_force": 15.0}
    raw["valvetrain"].pop("stiffness")
    case = case_from_dict(raw)
    omega = 2500 * RPM
    resp = valvetrain_response(case.motion, case.valvetrain, omega)
    assert not resp.floated
    planar = _planar(**ROCKER)
    s, s1, s2 = case.motion.host(np.deg2rad(resp.theta_deg))[:3] * 1e-3
    g = np.array([planar(x) for x in s])
    r = np.array([_fd(planar, x) for x in s])
    r1 = np.array([_fd(lambda u: _fd(planar, u), x, 1e-5) for x in s])
    ev = resp.in_event & (resp.valve_lift > 0.05)
    assert resp.valve_lift[ev] == pytest.approx(g[ev] * 1e3, abs=1e-9)
    m_c, m_v, k, f0, c = 0.12, 0.07, 40e3, 300.0, float(case.valvetrain.spring_damping)
    spring = k * g + f0 + c * r * s1 * omega
    turn = m_v * r * r1 * s1**2 * omega**2
    f_cam = m_c * s2 * omega**2 + r * (m_v * r * s2 * omega**2 + spring) + turn + 15.0
    assert resp.cam_force[ev] == pytest.approx(f_cam[ev], abs=2e-3)
    assert np.max(np.abs(turn[ev])) > 100 * 2e-3


@pytest.mark.slow
def test_two_masses_through_a_rocker_against_solve_ivp():
    """Past float the two masses fly on a compliant train through a bent rocker and the valve lands and bounces:
    diffrax's event-driven march and scipy's DOP853 on the same physics, the rocker turned in the plane, agree."""
    geometry = {"cam_arm": 30.0, "valve_arm": 45.0, "cam_arm_angle": -8.0, "valve_arm_angle": -3.0}
    base = _valvetrain(train_stiffness=3000.0, stiffness=3000.0, lash=0.15, seat_restitution=0.4, tappet_force=20.0)
    tables = {"dynamics": base.spec.dynamics.model_dump(exclude_none=True)}
    tables["valvetrain"] = base.spec.valvetrain.model_dump(exclude_none=True)
    raw = _with_rocker(copy.deepcopy(EVENT) | tables, geometry)
    case = case_from_dict(raw)
    omega = 4200 * RPM
    resp = valvetrain_response(case.motion, case.valvetrain, omega)
    assert resp.floated
    planar = _planar(**geometry)
    # an integrator's trial stage may try lifts far off (metres) that no rocker reaches: held within 20 mm there
    lever = lambda x: (planar(np.clip(x, -0.02, 0.02)), _fd(planar, np.clip(x, -0.02, 0.02)))  # noqa: E731
    land_deg, speed, height = _solve_ivp_event(case, omega, lever=lever)
    assert resp.seating_deg == pytest.approx(land_deg, abs=1e-5)
    assert resp.seating_velocity == pytest.approx(speed, rel=1e-6)
    assert resp.bounce_height_mm == pytest.approx(height * 1e3, rel=1e-5)


@pytest.mark.slow
def test_check_json_and_figure_show_the_rockers_ratio():
    """``check --json``'s valvetrain: ``ratio`` the rocker's at the cam's peak lift, ``ratio_min`` and ``ratio_max``
    over the cam's lift (the plane's, by finite differences); the report's figure draws that ratio against angle."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from camdyn.design.checks import run_check
    from camdyn.plot import plot_rocker_ratio, plot_valve_lift

    report = run_check(case_from_dict(_with_rocker(SHIPPED)))
    vt = report.json()["valvetrain"]
    planar = _planar(**ROCKER)
    ratios = np.array([_fd(planar, x) for x in np.linspace(0.0, 6.375e-3, 256)])
    assert vt["ratio"] == pytest.approx(ratios[-1], rel=1e-7)
    assert vt["ratio_min"] == pytest.approx(ratios.min(), rel=1e-6)
    assert vt["ratio_max"] == pytest.approx(ratios.max(), rel=1e-6)
    assert vt["ratio_max"] - vt["ratio_min"] > 0.03  # 1.574 to 1.612: the bent rocker's ratio varies
    result = report.valvetrain
    ax = Figure().add_subplot()
    plot_rocker_ratio(ax, result)
    assert np.allclose(ax.lines[0].get_ydata(), result.ratios)
    ax = Figure().add_subplot()
    plot_valve_lift(ax, result)
    cam = np.array([planar(x * 1e-3) for x in result.response.cam_lift]) * 1e3 - 0.2
    assert np.allclose(ax.lines[0].get_ydata(), cam, atol=1e-9)


@pytest.mark.slow  # the float search on the two-mass model (no fast path through a rocker)
def test_through_a_rocker_the_float_search_interpolates_the_force_the_cam_would_pull_with():
    """Past the float speed the diffrax model's float force is the least force a rigid cam contact would have to pull
    with to keep the follower on it (the valve as it moves), not 0: continuous through the float speed, so the
    search interpolates it (14 speeds through this rocker, where the clipped force took 21, halving like bisection),
    and the valve floats 1 rpm above the answer and not 1 rpm below it, the force there a fraction of a newton."""
    from camdyn.model.dynamics import ValvePoint, float_speed, jump_search_limit, kinematic_jump_speed

    case = case_from_dict(_with_rocker(SHIPPED))
    vt = case.valvetrain
    w_max = jump_search_limit(1.25 * 3000.0 * RPM, kinematic_jump_speed(case.motion, case.model)[0])
    asked = []

    def at(w):
        asked.append(w)
        return ValvePoint(case.motion, vt, w)

    w_float = float_speed(case.motion, vt, w_max, respond=at)
    assert len(asked) <= 15
    below, above = ValvePoint(case.motion, vt, w_float - RPM), ValvePoint(case.motion, vt, w_float + RPM)
    assert not below.response.floated and above.response.floated
    assert 0.0 < below.float_force < 2.0 and -2.0 < above.float_force < 0.0
    assert below.float_force == below.least_event_force  # below the float speed: the contact's own least force
