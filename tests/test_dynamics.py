"""Follower dynamics against closed forms and independent integrators.

Two motion structures are used, so that every jitted diffrax solve compiles at most twice:

* the eccentric cam (two harmonic segments, s = e (1 - cos theta)): closed-form kinematic jump speed, and the
  stiff-train limit (its acceleration is continuous, so the compliant force can converge to the kinematic one);
* the lecture cam (cases/lecture.toml): everything else, with its motion re-derived here in numpy (cycloidal
  rise 20 mm over 90-180 deg, harmonic return over 240-360 deg) so the references share no code with camdyn.

Units: the motion in mm and mm/rad, the model in SI (N/m, N*s/m), like camdyn.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import camdyn.model  # noqa: F401  (float64)
from camdyn._core.errors import NumericalError
from camdyn._core.units import THETA_GRID
from camdyn.design.checks import run_check
from camdyn.model import dynamics as dyn
from camdyn.model.case import case_from_dict
from camdyn.model.dynamics import _compliant, _rigid
from camdyn.model.dynamics._root import itp_zero
from camdyn.model.follower import FollowerModel
from camdyn.model.motion import Motion, Program

RPM = 2 * math.pi / 60
N = THETA_GRID  # the grid check runs the dynamics on: the programs the rest of the suite compiles serve these tests
ONE = np.asarray(1.0)  # a revolution at the shooting's full tolerances (not loosened)

LECTURE = {
    "name": "lecture",
    "motion": {
        "segments": [
            {"law": "dwell", "end": 90},
            {"law": "cycloidal", "end": 180, "lift": 20},
            {"law": "dwell", "end": 240},
            {"law": "harmonic", "end": 360, "lift": -20},
        ]
    },
    "follower": {"type": "translating-roller", "base_radius": 40, "roller_radius": 10, "offset": 5, "rotation": "cw"},
    "dynamics": {
        "speed": 300,
        "mass": 0.5,
        "spring_rate": 2.0,
        "preload": 30,
        "damping_ratio": 0.05,
        "train_stiffness": 1000,
        "train_damping_ratio": 0.05,
        "restitution": 0.0,
        "external_force": 0,
    },
}
BREAKS = (0.0, 0.5 * math.pi, math.pi, 4 * math.pi / 3, 2 * math.pi)  # lecture segment boundaries, rad


def model_of(m, k, f0, c, fext=0.0, kf=math.inf, cf=0.0, e=0.0):
    """FollowerModel from SI numbers (k, kf in N/m)."""
    return FollowerModel(*(jnp.asarray(float(v)) for v in (m, k, f0, c, fext, kf, cf, e)), scale=1e-3)


def with_(model, **kw):
    """A copy of ``model`` with some SI fields replaced (same pytree structure: no recompilation)."""
    fields = dict(
        mass=model.mass,
        stiffness=model.stiffness,
        preload=model.preload,
        damping=model.damping,
        external=model.external,
        train_stiffness=model.train_stiffness,
        train_damping=model.train_damping,
        restitution=model.restitution,
    )
    fields.update({k: jnp.asarray(float(v)) for k, v in kw.items()})
    return FollowerModel(**fields, scale=model.scale)


def params(model):
    names = ("mass", "stiffness", "preload", "damping", "external", "train_stiffness", "train_damping", "restitution")
    return {n: float(getattr(model, n)) for n in names}


# ------------------------------------------------------------------ independent lecture motion (numpy)
def lecture_motion(theta):
    """(s, s', s'') of the lecture cam in mm and per rad, written from the textbook laws."""
    th = np.mod(np.asarray(theta, float), 2 * math.pi)
    s, s1, s2 = np.zeros_like(th), np.zeros_like(th), np.zeros_like(th)
    rise = (th >= BREAKS[1]) & (th < BREAKS[2])
    b = BREAKS[2] - BREAKS[1]
    x = (th[rise] - BREAKS[1]) / b  # cycloidal: s = h (x - sin(2 pi x) / (2 pi))
    s[rise] = 20 * (x - np.sin(2 * math.pi * x) / (2 * math.pi))
    s1[rise] = 20 / b * (1 - np.cos(2 * math.pi * x))
    s2[rise] = 20 / b**2 * 2 * math.pi * np.sin(2 * math.pi * x)
    dwell = (th >= BREAKS[2]) & (th < BREAKS[3])
    s[dwell] = 20.0
    ret = th >= BREAKS[3]
    b = BREAKS[4] - BREAKS[3]
    x = (th[ret] - BREAKS[3]) / b  # harmonic return: s = 20 - 10 (1 - cos(pi x))
    s[ret] = 20 - 10 * (1 - np.cos(math.pi * x))
    s1[ret] = -10 * math.pi / b * np.sin(math.pi * x)
    s2[ret] = -10 * (math.pi / b) ** 2 * np.cos(math.pi * x)
    return s, s1, s2


def lecture_s_s1(th):
    """Scalar (s, s') of the lecture cam for the scipy right-hand sides (math, not numpy: speed)."""
    th = th % (2 * math.pi)
    if th < BREAKS[1]:
        return 0.0, 0.0
    if th < BREAKS[2]:
        b = BREAKS[2] - BREAKS[1]
        x = (th - BREAKS[1]) / b
        return 20 * (x - math.sin(2 * math.pi * x) / (2 * math.pi)), 20 / b * (1 - math.cos(2 * math.pi * x))
    if th < BREAKS[3]:
        return 20.0, 0.0
    b = BREAKS[4] - BREAKS[3]
    x = (th - BREAKS[3]) / b
    return 20 - 10 * (1 - math.cos(math.pi * x)), -10 * math.pi / b * math.sin(math.pi * x)


def kin_force_np(model, omega, theta):
    """Fi = m w^2 s'' + c w s' + k s + F0 + F_ext with s in m (eq. 7 of the CCM paper), N."""
    p = params(model)
    s, s1, s2 = (v * 1e-3 for v in lecture_motion(theta))
    return p["mass"] * omega**2 * s2 + p["damping"] * omega * s1 + p["stiffness"] * s + p["preload"] + p["external"]


# --------------------------------------------------- independent compliant model in time, SI (scipy)
def scipy_revolutions(model, omega, z0, revs=1, n=N, rtol=1e-11, atol=1e-12):
    """Integrate the compliant follower with solve_ivp (DOP853) in time, SI state (x m, v m/s).

    ``m x'' = Fi - (k x + F0) - c x' - F_ext``, ``Fi = max(0, k_f (s - x) + c_f (w s' - x'))`` while s > x.
    Restarted at every segment boundary (where s'' jumps). ``z0`` is (x mm, dx/dtheta mm/rad) at theta = 0;
    returns x (mm) and dx/dtheta (mm/rad) on the grid of every revolution, shape (revs, n), and the end state.
    """
    p = params(model)
    m, k, f0, c, fe, kf, cf = (
        p[n_] for n_ in ("mass", "stiffness", "preload", "damping", "external", "train_stiffness", "train_damping")
    )

    def rhs(t, y):
        x, v = y
        s, s1 = lecture_s_s1(omega * t)
        s, sdot = s * 1e-3, s1 * 1e-3 * omega
        fi = max(0.0, kf * (s - x) + cf * (sdot - v)) if s > x else 0.0
        return [v, (fi - (k * x + f0) - c * v - fe) / m]

    theta = np.arange(n) * (2 * math.pi / n)
    y = np.array([z0[0] * 1e-3, z0[1] * 1e-3 * omega])
    xs, ps = np.empty((revs, n)), np.empty((revs, n))
    for r in range(revs):
        for a, b in zip(BREAKS[:-1], BREAKS[1:], strict=True):
            sel = (theta >= a) & (theta < b)
            t_a, t_b = (a + 2 * math.pi * r) / omega, (b + 2 * math.pi * r) / omega
            sol = solve_ivp(rhs, (t_a, t_b), y, method="DOP853", rtol=rtol, atol=atol, dense_output=True)
            assert sol.success, sol.message
            yy = sol.sol((theta[sel] + 2 * math.pi * r) / omega)
            xs[r, sel], ps[r, sel] = yy[0] * 1e3, yy[1] * 1e3 / omega
            y = sol.y[:, -1]
    return xs, ps, np.array([y[0] * 1e3, y[1] * 1e3 / omega])


def contact_force_np(model, omega, theta, x, p):
    """Interface force of the compliant model from (x mm, dx/dtheta mm/rad), N."""
    q = params(model)
    s, s1, _ = lecture_motion(theta)
    f = q["train_stiffness"] * 1e-3 * (s - x) + q["train_damping"] * omega * 1e-3 * (s1 - p)
    return np.where(s > x, np.maximum(0.0, f), 0.0)


# -------------------------------------------------------------------------------------- fixtures
@pytest.fixture(scope="module")
def lecture():
    case = case_from_dict(LECTURE)
    return case.motion, case.model


@pytest.fixture(scope="module")
def lecture_300(lecture):
    """diffrax periodic steady state of the lecture case at 300 rpm (compiles the shooting once)."""
    motion, model = lecture
    return dyn.compliant_response(motion, model, 300 * RPM, n=N)


@pytest.fixture(scope="module")
def scipy_300(lecture, lecture_300):
    """solve_ivp over one revolution from camdyn's periodic initial state."""
    _, model = lecture
    r = lecture_300
    return scipy_revolutions(model, 300 * RPM, (r.x[0], r.dx[0]))


E_MM = 10.0


def eccentric(e):
    return Program.from_segments(
        [{"law": "harmonic", "end": 180, "lift": 2 * e}, {"law": "harmonic", "end": 360, "lift": -2 * e}]
    )


# ================================================================================== 1. kinematic
def test_lecture_model_from_case(lecture):
    """The case loader's SI conversion (N/mm -> N/m, damping ratios -> c) that every test below relies on."""
    _, model = lecture
    p = params(model)
    assert p["stiffness"] == 2000.0 and p["train_stiffness"] == 1e6 and p["preload"] == 30.0
    assert p["damping"] == pytest.approx(2 * 0.05 * math.sqrt(2000 * 0.5), rel=1e-14)
    assert p["train_damping"] == pytest.approx(2 * 0.05 * math.sqrt(1e6 * 0.5), rel=1e-14)


@pytest.mark.parametrize("m, k, f0", [(0.5, 2000.0, 30.0), (1.2, 15000.0, 5.0), (0.2, 500.0, 80.0)])
def test_kinematic_jump_speed_eccentric_closed_form(m, k, f0):
    # s = e (1 - cos t), s'' = e cos t, c = 0:
    #   Fi = m w^2 e cos t + k e (1 - cos t) + F0 = (m e w^2 - k e) cos t + k e + F0.
    # If m e w^2 > k e the least value is at t = 180 deg: Fi_min = 2 k e + F0 - m e w^2, which is 0 at
    #   w_jump^2 = (2 k e + F0) / (m e).   (If m e w^2 <= k e, Fi >= F0 > 0 everywhere: no jump.)
    e_mm = E_MM  # one motion structure for all (the segments, lift included, are static: new lift = recompile)
    e = e_mm * 1e-3
    w_ref = math.sqrt((2 * k * e + f0) / (m * e))
    assert m * e * w_ref**2 > k * e  # the closed form's own condition holds at its root
    w, at = dyn.kinematic_jump_speed(eccentric(e_mm), model_of(m, k, f0, 0.0))
    assert w == pytest.approx(w_ref, rel=1e-6)
    assert at == pytest.approx(180.0, abs=1e-3)


def test_kinematic_jump_speed_eccentric_damped():
    # With damping, Fi = A cos t + B sin t + k e + F0, A = (m w^2 - k) e, B = c w e, so
    #   min Fi = k e + F0 - e sqrt((m w^2 - k)^2 + c^2 w^2)  at  t = pi + atan2(B, A).
    # min Fi = 0 is a quadratic in u = w^2: m^2 u^2 + (c^2 - 2 m k) u + k^2 - ((k e + F0) / e)^2 = 0.
    e_mm, m, k, f0, c = E_MM, 0.5, 2000.0, 30.0, 40.0
    e = e_mm * 1e-3
    motion, model = eccentric(e_mm), model_of(m, k, f0, c)
    a2, a1, a0 = m**2, c**2 - 2 * m * k, k**2 - ((k * e + f0) / e) ** 2
    u = (-a1 + math.sqrt(a1 * a1 - 4 * a2 * a0)) / (2 * a2)
    w_ref = math.sqrt(u)
    at_ref = math.degrees(math.pi + math.atan2(c * w_ref * e, (m * w_ref**2 - k) * e))
    w, at = dyn.kinematic_jump_speed(motion, model)
    assert w == pytest.approx(w_ref, rel=1e-6)
    assert at == pytest.approx(at_ref, abs=1e-3)
    assert 180.0 < at < 270.0  # damping moves the minimum into the return, where c w s' < 0

    # brute force: least Fi over a fine angle grid, for speeds on a 0.01 rad/s grid around the answer
    theta = jnp.asarray(np.arange(7200) * (2 * math.pi / 7200))
    speeds = np.arange(w_ref - 0.303, w_ref + 0.3, 0.01)  # off the answer (here w_ref = 100 rad/s exactly)
    fmin = np.array([float(jnp.min(dyn.kinematic_force_jit(motion, model, jnp.asarray(ws), theta))) for ws in speeds])
    first = speeds[np.nonzero(fmin <= 0.0)[0][0]]
    assert fmin[0] > 0.0
    assert first - 0.01 < w < first
    # and the undamped closed form is not the answer here (damping matters by far more than the tolerance)
    assert abs(w - math.sqrt((2 * k * e + f0) / (m * e))) > 0.1


def test_kinematic_jump_speed_none():
    """No acceleration, no jump: a pure dwell has Fi = k s + F0 > 0 at every speed."""
    w, at = dyn.kinematic_jump_speed(
        Program.from_segments([{"law": "dwell", "end": 360}]), model_of(0.5, 2000.0, 30.0, 10.0)
    )
    assert math.isinf(w) and math.isnan(at)


def test_kinematic_force_by_hand(lecture):
    motion, model = lecture
    model = with_(model, external=7.5, damping=55.0)  # make the c and F_ext terms matter
    omega = 437 * RPM
    theta = np.arange(N) * (2 * math.pi / N) + 1e-4
    got = np.asarray(dyn.kinematic_force_jit(motion, model, jnp.asarray(omega, dtype=float), jnp.asarray(theta)))
    ref = kin_force_np(model, omega, theta)
    assert np.max(np.abs(got - ref)) < 1e-9 * np.max(np.abs(ref))
    # each term is really there: the damping and external terms are each far above the tolerance
    s1 = lecture_motion(theta)[1]
    assert np.max(np.abs(55.0 * omega * s1 * 1e-3)) > 1e6 * 1e-9 * np.max(np.abs(ref))


def test_train_force_by_hand():
    """The one interface law: k_f (s - x) + c_f w (s' - x') in SI, the same from mm with unit=1e-3, 0 off the cam."""
    model = model_of(0.5, 2000.0, 30.0, 10.0, kf=1e6, cf=40.0)
    omega = 300 * RPM
    s, s1, x, x1 = np.array([5.0, 5.0, 5.0]), np.array([2.0, 2.0, -1.0]), np.array([4.99, 5.01, 4.999]), 0.5
    by_hand = 1e6 * (s - x) * 1e-3 + 40.0 * omega * (s1 - x1) * 1e-3  # N
    got = np.asarray(dyn.train_force(model, omega, s * 1e-3, s1 * 1e-3, x * 1e-3, x1 * 1e-3))
    assert got == pytest.approx(by_hand, rel=1e-12)
    in_mm = np.asarray(dyn.train_force(model, omega, s, s1, x, x1, unit=1e-3))
    assert in_mm == pytest.approx(by_hand, rel=1e-12)
    # unilateral: pushes while the cam is ahead (10 N + damping), 0 behind it (s < x), 0 where the pull would be < 0
    assert by_hand[2] < 0.0 < by_hand[0]
    contact = np.asarray(dyn.contact_force(model, omega, s, s1, x, x1, unit=1e-3))
    assert contact[0] == pytest.approx(by_hand[0], rel=1e-12) and contact[1] == contact[2] == 0.0


# ============================================================================ 2. compliant model
@pytest.mark.slow
def test_stiff_train_tends_to_kinematic_force():
    """Eccentric cam (continuous acceleration) at 900 rpm: the compliant force converges to the kinematic one as
    1/k_f, with the first-order correction Fi_dyn ~ Fi_kin - (m w^2 Fi'' + c w Fi' + k Fi) / k_f
    (from x = s - Fi/k_f + O(c_f w / k_f^2) substituted into the follower's equation of motion)."""
    e_mm, m, k, f0, zeta = E_MM, 0.5, 2000.0, 30.0, 0.05
    c = 2 * zeta * math.sqrt(k * m)
    motion = eccentric(e_mm)
    omega = 900 * RPM
    theta = np.arange(N) * (2 * math.pi / N)
    e = e_mm * 1e-3
    # kinematic force and its theta derivatives in closed form
    a, b, d = (m * omega**2 - k) * e, c * omega * e, k * e + f0
    fk = a * np.cos(theta) + b * np.sin(theta) + d
    fk1 = -a * np.sin(theta) + b * np.cos(theta)
    fk2 = -a * np.cos(theta) - b * np.sin(theta)
    span = fk.max() - fk.min()
    assert span > 40.0
    errs, first_order = [], []
    for kf in (1e6, 1e7, 1e8):  # 1e3, 1e4, 1e5 N/mm
        model = model_of(m, k, f0, c, kf=kf, cf=2 * 0.05 * math.sqrt(kf * m))
        r = dyn.compliant_response(motion, model, omega, n=N)
        assert not r.separations and r.periodicity_error < 1e-8
        errs.append(np.max(np.abs(r.force - fk)))
        corr = fk - (m * omega**2 * fk2 + c * omega * fk1 + k * fk) / kf
        first_order.append(np.max(np.abs(r.force - corr)))
    errs = np.array(errs)
    assert errs[-1] < 1e-4 * span  # 1e5 N/mm: within 0.01 % of the force range
    assert np.all(errs[1:] < 0.15 * errs[:-1])  # ~1/k_f: ten times smaller per decade
    assert np.all(np.array(first_order) < 0.1 * errs)  # and it is the predicted O(1/k_f) term


@pytest.mark.slow  # compiles the shooting
def test_diffrax_vs_solve_ivp_periodic(lecture, lecture_300, scipy_300):
    motion, model = lecture
    r = lecture_300
    omega = 300 * RPM
    assert not r.separations
    assert r.periodicity_error < 1e-9
    xs, ps, z_end = scipy_300
    x_err = np.max(np.abs(xs[0] - r.x))
    p_err = np.max(np.abs(ps[0] - r.dx))
    theta = np.arange(N) * (2 * math.pi / N)
    f_ref = contact_force_np(model, omega, theta, xs[0], ps[0])
    f_err = np.max(np.abs(f_ref - r.force))
    assert x_err < 1e-7, x_err  # mm (measured ~2e-9)
    assert p_err < 1e-6, p_err  # mm/rad (~5e-8)
    assert f_err < 1e-4, f_err  # N (~2e-6)
    # the scipy orbit from camdyn's initial state is periodic too
    assert np.max(np.abs(z_end - np.array([r.x[0], r.dx[0]]))) < 1e-7
    # camdyn's grid and kinematic force are what they say
    assert np.max(np.abs(r.s - lecture_motion(theta)[0])) < 1e-12
    assert np.max(np.abs(r.kinematic_force - kin_force_np(model, omega, theta))) < 1e-9


@pytest.mark.slow  # compiles the shooting with sensitivities (11 s)
def test_diffrax_vs_solve_ivp_with_separation(lecture):
    """Lecture cam at 600 rpm (above the jump speed): three plain revolutions from the quasi-static start, with
    lift-offs and landings, by diffrax (camdyn's one-revolution solve, chained) and by solve_ivp."""
    motion, model = lecture
    omega = 600 * RPM
    theta = np.arange(N) * (2 * math.pi / N)
    z0 = np.array([-30.0 / 1e3, 0.0])  # x = s - Fi/k_f = -F0/k_f at theta = 0 (dwell), mm
    xs, ps, _ = scipy_revolutions(model, omega, z0, revs=3, rtol=1e-10, atol=1e-12)
    z = jnp.asarray(z0)
    for rev in range(3):
        traj, z, _, ok = _compliant._rev_jit(motion, model, jnp.asarray(omega), z, jnp.asarray(theta), ONE)
        traj = np.asarray(traj)
        assert bool(ok)
        f = contact_force_np(model, omega, theta, traj[:, 0], traj[:, 1])
        assert np.mean(f <= 0.0) > 0.05  # it does fly
        x_err = np.max(np.abs(traj[:, 0] - xs[rev]))
        f_err = np.max(np.abs(f - contact_force_np(model, omega, theta, xs[rev], ps[rev])))
        assert x_err < 1e-6, (rev, x_err)  # mm (measured 1e-8 .. 4e-8: contact damps the difference out)
        assert f_err < 1e-3, (rev, f_err)  # N (1e-5 .. 4e-5)


@pytest.mark.slow  # compiles the shooting with sensitivities (11 s)
def test_bouncing_monodromy_is_the_flows_jacobian(lecture):
    """Where the follower leaves the cam, one revolution's monodromy matrix (each piece's in closed form, with each
    switch's saltation matrix) is the flow's Jacobian by central differences of the same revolution: the lecture cam
    at 600 rpm, three revolutions from the quasi-static start, where it lands several times a revolution. Without
    the landings' saltation the matrix differed from the differences even in sign."""
    motion, model = lecture
    omega, theta = jnp.asarray(600 * RPM), jnp.asarray(np.arange(N) * (2 * math.pi / N))
    z = jnp.asarray([-30.0 / 1e3, 0.0])
    for _ in range(3):
        traj, z, mono, ok = _compliant._rev_jit(motion, model, omega, z, theta, ONE)
        assert bool(ok)
    f = contact_force_np(model, float(omega), np.asarray(theta), *np.asarray(traj).T)
    landings = int(np.sum((f[1:] > 0.0) & (f[:-1] <= 0.0)))
    assert landings >= 5  # it does bounce
    _, _, mono, _ = _compliant._rev_jit(motion, model, omega, z, theta, ONE)
    h = 1e-5
    columns = []
    for e in np.eye(2):
        ends = [
            np.asarray(_compliant._rev_jit(motion, model, omega, z + sign * h * e, theta, ONE)[1]) for sign in (1, -1)
        ]
        columns.append((ends[0] - ends[1]) / (2 * h))
    fd = np.stack(columns, axis=1)
    assert np.max(np.abs(np.asarray(mono) - fd)) <= 1e-4 * np.max(np.abs(fd)), (np.asarray(mono), fd)  # 2.9e-6


# =============================================================================== 3. free flight
def flight_closed_form(model, omega, theta0, x0_mm, p0_mm):
    """x(theta) (mm) of m x'' + c x' + k x = -(F0 + F_ext) (underdamped) from (x0, dx/dtheta0) at theta0."""
    q = params(model)
    m, k, c = q["mass"], q["stiffness"], q["damping"]
    xeq = -(q["preload"] + q["external"]) / k
    wn = math.sqrt(k / m)
    zeta = c / (2 * math.sqrt(k * m))
    assert zeta < 1.0
    wd = wn * math.sqrt(1 - zeta**2)
    u0, v0 = x0_mm * 1e-3 - xeq, p0_mm * 1e-3 * omega
    a, b = u0, (v0 + zeta * wn * u0) / wd

    def x(theta):
        t = (np.asarray(theta) - theta0) / omega
        return 1e3 * (xeq + np.exp(-zeta * wn * t) * (a * np.cos(wd * t) + b * np.sin(wd * t)))

    def v(theta):  # m/s
        t = (np.asarray(theta) - theta0) / omega
        env = np.exp(-zeta * wn * t)
        return env * (
            -zeta * wn * (a * np.cos(wd * t) + b * np.sin(wd * t)) + wd * (-a * np.sin(wd * t) + b * np.cos(wd * t))
        )

    return x, v


def lift_off(model, omega, lo_deg, hi_deg):
    return brentq(
        lambda t: float(kin_force_np(model, omega, np.array([t]))[0]),
        math.radians(lo_deg),
        math.radians(hi_deg),
        xtol=1e-14,
    )


@pytest.mark.slow  # compiles the rigid follower's flight
def test_free_flight_closed_form(lecture):
    motion, model = lecture
    model = with_(model, external=5.0, damping=20.0, train_stiffness=math.inf, train_damping=0.0)
    omega = 600 * RPM
    t_lo = lift_off(model, omega, 130, 155)
    s0, s10, _ = lecture_motion(np.array([t_lo]))
    # the argument types of rigid_response's march (a flight leaving the cam at its speed): one program shared
    t1, y1, s1, landed, tt, yy, apex, apex_at = (
        np.asarray(a)
        for a in _rigid._flight(
            motion, model, np.asarray(omega), np.asarray(t_lo), np.asarray(0.0), np.asarray(t_lo + 7.0), THETA_GRID
        )
    )
    t1 = float(t1)
    x_cf, _ = flight_closed_form(model, omega, t_lo, s0[0], s10[0])
    # landing where the closed-form x meets the cam again
    th = np.linspace(t_lo + 1e-3, t_lo + math.pi, 20001)
    gap = x_cf(th) - lecture_motion(th)[0]
    j = int(np.nonzero(gap < 0)[0][0])
    t_land = brentq(lambda t: float(x_cf(t) - lecture_motion(np.array([t]))[0][0]), th[j - 1], th[j], xtol=1e-15)
    assert math.degrees(t_land - t_lo) > 20.0  # a real flight
    assert bool(landed) and abs(t1 - t_land) < 1e-8, (t1, t_land)
    assert abs(y1[0] - lecture_motion(np.array([t1]))[0][0]) < 1e-8  # the event: x = s at the landing
    assert np.allclose(s1, [a[0] for a in lecture_motion(np.array([t1]))[:2]], rtol=0, atol=1e-12)  # the cam there
    # the dense solution on the grid's angles within the flight against the closed form (the rest clipped to t1)
    inside = tt < t1
    assert inside.sum() > 200 and np.all(tt[inside] >= t_lo) and np.all(tt[~inside] == t1)
    assert np.allclose(np.diff(tt[inside]), 2 * math.pi / THETA_GRID, rtol=0, atol=1e-12)
    got = yy[inside, 0]
    assert np.max(np.abs(got - x_cf(tt[inside]))) < 5e-8, np.max(np.abs(got - x_cf(tt[inside])))  # mm
    assert np.all(got[1:] > lecture_motion(tt[inside][1:])[0])  # airborne
    fine = np.linspace(t_lo, t1, 20001)  # the largest gap at 65 angles across the flight: the closed form's apex
    top = x_cf(fine) - lecture_motion(fine)[0]  # within the sampling's (1/64)^2 / 8 of the flight's curvature
    assert apex == pytest.approx(top.max(), rel=1e-3) and abs(float(apex_at) - fine[np.argmax(top)]) < (t1 - t_lo) / 64


def test_itp_zero_brackets_the_zero_within_bisections_count():
    """The bracketing root finder of the speed searches and the rigid lift-off: the zero of cos within half the width,
    in a few evaluations (smooth: the regula falsi's pace); a step with no slope (a jump) never costs more than
    bisection's count plus one; a non-finite value raises what the caller names."""
    calls = []

    def cos(x):
        calls.append(x)
        return math.cos(x)

    z = itp_zero(cos, 0.0, 3.0, 1.0, math.cos(3.0), 1e-12, ValueError)
    assert abs(z - math.pi / 2) <= 0.5e-12 and len(calls) <= 10
    calls.clear()
    z = itp_zero(lambda x: cos(0.0 if x < 0.3 else math.pi), 0.0, 1.0, 1.0, -1.0, 1e-9, ValueError)
    assert abs(z - 0.3) <= 0.5e-9 and len(calls) <= math.ceil(math.log2(1.0 / 1e-9)) + 1
    with pytest.raises(ValueError, match="0.5"):
        itp_zero(lambda x: math.nan, 0.0, 1.0, 1.0, -1.0, 1e-6, lambda x: ValueError(f"not finite at {x}"))


# ================================================================================= 4. rigid model
@pytest.fixture(scope="module")
def rigid_600(lecture):
    motion, model = lecture
    rigid = with_(model, train_stiffness=math.inf, train_damping=0.0)
    omega = 600 * RPM
    return rigid, omega, dyn.rigid_response(motion, rigid, omega, n=N)


@pytest.mark.slow  # rigid_600 compiles the rigid follower's flight
def test_rigid_lift_off_and_landing(lecture, rigid_600):
    motion, _ = lecture
    rigid, omega, r = rigid_600
    assert len(r.separations) == 1
    sep = r.separations[0]
    t_lo = lift_off(rigid, omega, 130, 155)
    # lift-off: the zero of camdyn's own kinematic force too
    t_lo2 = brentq(
        lambda t: float(dyn.kinematic_force_jit(motion, rigid, omega, np.asarray(t))),
        math.radians(130),
        math.radians(155),
        xtol=1e-14,
    )
    assert abs(t_lo - t_lo2) < 1e-10
    assert sep.start_deg == pytest.approx(math.degrees(t_lo), abs=1e-7)
    # landing: where the closed-form flight from the lift-off meets the cam
    s0, s10, _ = lecture_motion(np.array([t_lo]))
    x_cf, v_cf = flight_closed_form(rigid, omega, t_lo, s0[0], s10[0])
    th = np.linspace(t_lo + 1e-3, t_lo + math.pi, 20001)
    j = int(np.nonzero(x_cf(th) - lecture_motion(th)[0] < 0)[0][0])
    t_land = brentq(lambda t: float(x_cf(t) - lecture_motion(np.array([t]))[0][0]), th[j - 1], th[j], xtol=1e-15)
    assert sep.end_deg == pytest.approx(math.degrees(t_land) % 360, abs=1e-6)
    assert sep.bounces == 0
    # impact speed |x' - w s'| at the landing, and the largest gap on the grid
    _, s1_land, _ = lecture_motion(np.array([t_land]))
    assert sep.impact_speed == pytest.approx(abs(v_cf(t_land) - omega * s1_land[0] * 1e-3), rel=1e-6)
    theta = np.arange(N) * (2 * math.pi / N)
    fly = (theta > t_lo) & (theta < t_land)
    assert np.max(np.abs(r.x[fly] - x_cf(theta[fly]))) < 1e-7
    fine = np.linspace(t_lo, t_land, 20001)  # the apex between the grid's angles: within (span / 64)^2 of its top
    assert sep.max_gap == pytest.approx(np.max(x_cf(fine) - lecture_motion(fine)[0]), rel=1e-4)
    assert np.all(r.force[fly] == 0.0) and np.all(r.x[~fly] == r.s[~fly])


@pytest.mark.slow  # rigid_600 compiles the rigid follower's flight
def test_rigid_restitution_bounces(lecture, rigid_600):
    motion, _ = lecture
    rigid, omega, r0 = rigid_600
    r5 = dyn.rigid_response(motion, with_(rigid, restitution=0.5), omega, n=N)
    assert len(r5.separations) == 1
    s0, s5 = r0.separations[0], r5.separations[0]
    assert s5.start_deg == s0.start_deg  # same lift-off (a property of the kinematic force only)
    assert s5.impact_speed == pytest.approx(s0.impact_speed, rel=1e-9)  # same first flight
    assert s5.bounces > s0.bounces and s5.bounces >= 3
    assert s5.end_deg > s0.end_deg  # bouncing lasts beyond the first touchdown


@pytest.mark.slow  # rigid_600 compiles the rigid follower's flight
def test_rigid_bouncing_dies_out(lecture, rigid_600):
    """e = 0.5: impact speeds halve per bounce, 0.65 m/s -> 1e-6 m/s in ~20 bounces (Zeno: finite total time).
    The bounce count and the end of the separation must not depend on the safety cap ``max_bounces``."""
    motion, _ = lecture
    rigid, omega, _ = rigid_600
    model = with_(rigid, restitution=0.5)
    capped = dyn.rigid_response(motion, model, omega, n=N, max_bounces=60).separations[0]
    assert capped.bounces < 60, capped
    free = dyn.rigid_response(motion, model, omega, n=N).separations[0]
    assert free.bounces == capped.bounces and free.end_deg == pytest.approx(capped.end_deg, abs=1e-9)


@pytest.mark.slow  # compiles the rigid follower's flight
def test_rigid_jump_speed(lecture):
    motion, model = lecture
    rigid = with_(model, train_stiffness=math.inf, train_damping=0.0)
    w_kin, at = dyn.kinematic_jump_speed(motion, rigid)
    assert dyn.dynamic_jump_speed(motion, rigid, w_max=10 * w_kin) == w_kin
    below = dyn.rigid_response(motion, rigid, 0.999 * w_kin, n=N)
    above = dyn.rigid_response(motion, rigid, 1.001 * w_kin, n=N)
    assert not below.separations and below.min_force > 0.0
    assert len(above.separations) == 1
    assert above.separations[0].start_deg < at < above.separations[0].end_deg


_STEPPED = [  # a constant-velocity rise between dwells: its velocity steps up at 90 deg and down at 180 deg
    {"law": "dwell", "end": 90},
    {"law": "constant-velocity", "end": 180, "lift": 20},
    {"law": "dwell", "end": 240},
    {"law": "cycloidal", "end": 360, "lift": -20},
]


def test_a_step_in_the_cams_velocity_is_a_jump_at_any_speed(lecture):
    """The constant-velocity rise's steps, v = 20 mm / (pi / 2) either way, read exactly from its segments and again
    from either side of its breaks; a rigid follower's kinematic jump speed is 0 at the drop (180 deg), whatever its
    restitution; the rise (90 deg) strikes it and throws it off only with a restitution."""
    _, model = lecture
    motion = Program.from_segments(_STEPPED)
    v = 20.0 / (math.pi / 2)
    assert np.allclose(motion.velocity_jumps(), [(90.0, v), (180.0, -v)], rtol=1e-12, atol=0)
    generic = Motion.derivative_jumps(motion)  # one-sided values at the breaks
    assert [(d, o) for d, o, _ in generic] == [(d, o) for d, o, _ in motion.derivative_jumps()]
    assert np.allclose([j for *_, j in generic], [j for *_, j in motion.derivative_jumps()], rtol=1e-6)
    rigid = with_(model, train_stiffness=math.inf, train_damping=0.0)
    assert dyn.kinematic_jump_speed(motion, rigid) == (0.0, pytest.approx(180.0))
    assert np.allclose(dyn.velocity_steps(motion, 0.0), [(math.pi, v)], rtol=1e-12, atol=0)
    assert np.allclose(dyn.velocity_steps(motion, 0.5), [(math.pi / 2, 0.5 * v), (math.pi, v)], rtol=1e-12, atol=0)
    assert dyn.kinematic_jump_speed(Program.from_segments(LECTURE["motion"]["segments"]), rigid)[0] > 0.0


@pytest.mark.slow  # compiles the rigid follower's flight
def test_a_rigid_follower_leaves_a_cam_whose_velocity_drops_and_flies_in_closed_form(lecture):
    """At 30 rpm, far below any acceleration's jump speed, the rigid follower leaves the constant-velocity rise's end
    at the cam's speed before the step, v w, and flies under its undamped spring from the dwell's lift h:
    X'' = -w_n^2 X - a0 (a0 = (k h + F0) / m) lands after t = 2 atan(v w w_n / a0) / w_n, at the speed it left at;
    the largest gap on the grid is below the closed form's (sqrt(a0^2 + (v w w_n)^2) - a0) / w_n^2. ``check``
    fails it (force and margin), and the rise, where the cam strikes it, is no flight."""
    _, model = lecture
    motion = Program.from_segments(_STEPPED)
    rigid = with_(model, train_stiffness=math.inf, train_damping=0.0, damping=0.0)
    omega = 30 * RPM
    r = dyn.rigid_response(motion, rigid, omega, n=N)
    assert len(r.separations) == 1
    sep = r.separations[0]
    v = 20.0 / (math.pi / 2) * 1e-3 * omega  # m/s
    m, k, f0 = float(rigid.mass), float(rigid.stiffness), float(rigid.preload)
    a0, wn = (k * 0.020 + f0) / m, math.sqrt(k / m)
    t_land = 2.0 * math.atan(v * wn / a0) / wn
    assert sep.start_deg == pytest.approx(180.0, abs=1e-8) and sep.bounces == 0
    assert sep.end_deg == pytest.approx(180.0 + math.degrees(omega * t_land), abs=1e-7)
    assert sep.impact_speed == pytest.approx(v, rel=1e-6)
    assert sep.max_gap * 1e-3 == pytest.approx((math.hypot(a0, v * wn) - a0) / wn**2, rel=1e-3)  # its apex
    fly = (r.theta_deg > 180.0) & (r.theta_deg < sep.end_deg)
    assert fly.any() and np.all(r.force[fly] == 0.0) and np.all(r.x[~fly] == r.s[~fly])
    assert r.flights[0].leave_deg == 180.0  # the grid angle on the step is the flight's first, as the separation's
    dynamics = {key: x for key, x in LECTURE["dynamics"].items() if not key.startswith("train_")} | {"speed": 30}
    case = case_from_dict(LECTURE | {"motion": {"segments": _STEPPED}, "dynamics": dynamics})
    report = run_check(case)
    failed = {c.name for c in report.checks if not c.ok}
    assert report.verdict == "fail" and failed == {"contact_force", "speed_margin"}, failed


# ============================================================== 5. frequency domain and jump speed
@pytest.mark.slow  # compiles the diffrax response at four speeds (6 s)
def test_linear_min_force_vs_diffrax(lecture):
    motion, model = lecture
    rpms = np.array([120.0, 250.0, 380.0, 470.0])
    lin = np.asarray(dyn.linear_min_force(motion, model, jnp.asarray(rpms * RPM), n=N))
    td = np.array([dyn.compliant_response(motion, model, w * RPM, n=N).min_force for w in rpms])
    assert np.all(td > 0.0)
    assert np.max(np.abs(lin - td)) < 1e-4, np.abs(lin - td)  # N (measured <= 6e-6)


@pytest.mark.slow  # bisects on the shooting with sensitivities (11 s of compile)
def test_dynamic_jump_speed_vs_bisection(lecture):
    motion, model = lecture
    w_kin, _ = dyn.kinematic_jump_speed(motion, model)
    w_dyn = dyn.dynamic_jump_speed(motion, model, w_max=4 * w_kin)
    assert 0.8 * w_kin < w_dyn < 1.1 * w_kin

    def fmin(w):
        return float(dyn.min_contact_force(motion, model, jnp.asarray(w), n=N))

    # the least contact force changes sign within 0.05 rpm of w_dyn (a bisection of it measured 0.004 rpm): two
    # solves bracket it as tightly as the nine of a bisection to 0.05 rpm would
    assert fmin(w_dyn - 0.05 * RPM) > 0.0, w_dyn / RPM
    assert fmin(w_dyn + 0.05 * RPM) <= 0.0, w_dyn / RPM


def test_the_chunked_scan_finds_what_the_whole_scan_finds():
    """first_zero_speed in chunks (the jump speed's scan, issue 23) stops at the chunk of the first sign change: the
    same speed as the whole scan, fewer speeds computed; the padded last chunk and no zero at all too."""
    calls = []

    def least(ws, zero):
        calls.append(ws.size)
        return np.where(ws < zero, 1.0 - ws / zero, -1.0)

    for zero, chunk in ((100.0, 256), (790.0, 256), (100.0, 300), (5e3, 256)):
        whole = dyn.first_zero_speed(
            functools.partial(least, zero=zero), 800.0, grid=2000, width_rpm=1e-3, points=16, where="t"
        )
        calls.clear()
        got = dyn.first_zero_speed(
            functools.partial(least, zero=zero), 800.0, grid=2000, width_rpm=1e-3, points=16, where="t", chunk=chunk
        )
        assert got == whole and (math.isinf(got) if zero > 800.0 else got == pytest.approx(zero, abs=1e-3 * RPM))
        scanned = sum(c for c in calls if c == chunk)
        assert set(calls) <= {chunk, 16} and scanned == chunk * math.ceil(min(zero / 0.4 + 1, 2000) / chunk)
    with pytest.raises(NumericalError, match="not finite"):
        dyn.first_zero_speed(lambda w: w * np.nan, 800.0, grid=2000, width_rpm=1e-3, points=16, where="t", chunk=256)


def test_a_signed_force_is_refined_in_a_few_speeds_and_never_more_than_bisection_and_one():
    """first_zero_speed(signed=True) refines the scan's first sign change by ITP: a smooth force's zero in four speeds
    where bisection takes ten (a 623 rpm cell to 1 rpm), the bracket's midpoint within half the width of the zero; a
    force that jumps through zero (nothing to interpolate) in at most bisection's count and one; a force of exactly
    0 counts as reached, as in the scan."""
    zero = 5920.06 * RPM
    w_max = 40 * 623.0 * RPM
    grid = 40

    def run(force, signed):
        seen = []

        def least(ws):
            seen.extend(np.atleast_1d(ws))
            return force(np.atleast_1d(ws))

        got = dyn.first_zero_speed(least, w_max, grid=grid, width_rpm=1.0, points=1, where="t", chunk=1, signed=signed)
        return got, len(seen) - math.ceil(zero / (w_max / grid))  # the speeds after the scan's

    smooth = lambda ws: 300.0 * (1.0 - (ws / zero) ** 2)  # noqa: E731  (a least force falls about as w^2)
    got, n = run(smooth, True)
    assert abs(got - zero) <= 0.5 * RPM and n <= 4
    got_bisect, n_bisect = run(smooth, False)
    assert abs(got_bisect - zero) <= 0.5 * RPM and n_bisect == 10
    step = lambda ws: np.where(ws < zero, 1.0, -1e-9)  # noqa: E731
    got, n = run(step, True)
    assert abs(got - zero) <= 0.5 * RPM and n <= n_bisect + 1
    plateau = lambda ws: np.maximum(0.0, 1.0 - ws / zero)  # noqa: E731  (0 past the zero: reached)
    got, n = run(plateau, True)
    assert abs(got - zero) <= 0.5 * RPM and n <= n_bisect + 1


# ============================================================================ 6. residual vibration
@pytest.mark.slow  # lecture_300 compiles the shooting
def test_residual_vibration(lecture, lecture_300, scipy_300):
    """Residual vibration in the dwells of the lecture case at 300 rpm.

    camdyn reports max |x - x_static| over the dwells, x_static = (k_f s - F0 - F_ext)/(k + k_f). The harmonic return
    ends at 360 deg with an acceleration step of 22.5 mm/rad^2 into the 0-90 deg dwell, a step of m w^2 da in the
    kinematic force: x_qs jumps by that / k_f while x cannot, so the follower starts the dwell that far from
    equilibrium and rings down from there. The largest deviation is that initial one, whatever the damping; more
    train damping makes the ringing die out faster, which is what the deviation later in the dwell shows.
    """
    motion, model = lecture
    omega = 300 * RPM
    r = lecture_300
    theta = np.arange(N) * (2 * math.pi / N)
    # independent: |x - x_static| in the dwells of the scipy orbit (k = 2, k_f = 1000 N/mm, F0 = 30 N)
    xs = scipy_300[0][0]
    s = lecture_motion(theta)[0]
    dwell = (theta < BREAKS[1]) | ((theta >= BREAKS[2]) & (theta < BREAKS[3]))
    ref = np.max(np.abs(xs - (1000.0 * s - 30.0) / (2.0 + 1000.0))[dwell])
    assert r.residual_vibration == pytest.approx(ref, abs=1e-6)
    step_mm = 0.5 * omega**2 * 22.5e-3 / 1e6 * 1e3  # m w^2 da / k_f, mm
    assert r.residual_vibration == pytest.approx(step_mm, rel=0.02)

    def late_ringing(resp):
        """Largest |x - x_static| over 45-90 deg (second half of the first dwell), exact static equilibrium
        x = (k_f s - F0) / (k + k_f) of the spring-train pair (s = 0 there)."""
        sel = (theta >= math.pi / 4) & (theta < BREAKS[1])
        return np.max(np.abs(resp.x[sel] - (-30.0 / (2000.0 + 1e6) * 1e3)))

    resid, ring = [r.residual_vibration], [late_ringing(r)]
    for zf in (0.2, 0.5):
        rz = dyn.compliant_response(motion, with_(model, train_damping=2 * zf * math.sqrt(1e6 * 0.5)), omega, n=N)
        resid.append(rz.residual_vibration)
        ring.append(late_ringing(rz))
    assert resid[0] > 0 and np.all(np.diff(resid) <= 0.0)  # positive, never grows with damping
    assert ring[0] > 1e-3 and ring[1] < 0.1 * ring[0] and ring[2] < 0.1 * ring[1], ring  # dies out much faster


class Revolution(NamedTuple):
    mismatch: float  # |Phi(z) - z|, motion units
    loose: bool  # at the tolerances loosened (a revolution that steers the shooting)
    start: np.ndarray  # z


def _counting_revolutions(monkeypatch) -> list[Revolution]:
    """Counts the shooting's one-revolution solves (``_compliant._rev_jit`` calls) into the returned list."""
    calls: list[Revolution] = []
    solve = _compliant._rev_jit

    def counted(motion, model, omega, z, theta, loosen):
        out = solve(motion, model, omega, z, theta, loosen)
        calls.append(Revolution(float(np.linalg.norm(np.asarray(out[1]) - np.asarray(z))), loosen > 1, np.asarray(z)))
        return out

    monkeypatch.setattr(_compliant, "_rev_jit", counted)
    return calls


# a never-seen lecture-like cam (the latency benchmark's random segments, seed 500) whose follower bounces without
# settling at the lecture's 300 rpm
UNSETTLED_SEGMENTS = [
    {"law": "polynomial-345", "end": 30, "lift": 8.697},
    {"law": "dwell", "end": 70},
    {"law": "harmonic", "end": 80, "lift": 6.47},
    {"law": "polynomial-4567", "end": 140, "lift": -6.47},
    {"law": "dwell", "end": 230},
    {"law": "polynomial-345", "end": 360, "lift": -8.697},
]


@pytest.mark.slow
def test_shooting_that_does_not_converge_reports_its_best_revolution(monkeypatch):
    """A cam whose follower bounces without settling, not even every other revolution: ten revolutions without a
    lower mismatch end the run, which steers at loose tolerances while its mismatch is large; the revolution reported
    is the start of least mismatch run again at the full ones; and the search for a bouncing that repeats every other
    revolution gives up at a checkpoint (the two-revolution mismatch did not halve)."""
    revs = _counting_revolutions(monkeypatch)
    case = case_from_dict(LECTURE | {"motion": {"segments": UNSETTLED_SEGMENTS}})
    r = dyn.compliant_response(case.motion, case.model, case.speed_rpm * RPM)
    said = next(w for w in r.warnings if "no exactly periodic steady state" in w)
    which = said.split("results are for revolution ")[1].split(" integrated")[0]
    best, total = (int(x) for x in which.split(" of the "))
    assert total == len(revs)
    run, again = revs[: best - 1], revs[best - 1]  # the shooting's own, and its best start at the full tolerances
    least = min(range(len(run)), key=lambda i: run[i].mismatch)
    assert all(rev.loose for rev in run) and len(run) == least + 1 + _compliant._STALL_REVS
    assert not again.loose and np.array_equal(again.start, run[least].start)
    assert r.separations and r.periodicity_error == again.mismatch > _compliant.periodic_tol(r.s)
    searched = total - best  # the period-two search's, at the full tolerances
    assert searched > 0 and searched % _compliant._PERIOD2_CHECK == 0 and not any(x.loose for x in revs[best:])
    assert r.period_revolutions is None  # check --json: "period_revolutions": null


@pytest.mark.slow
def test_lecture_fast_bounces_the_same_every_other_revolution(lecture_fast_case):
    """The lecture cam at 600 rpm: from the quasi-static start the follower's bouncing settles into one that repeats
    every other revolution (the state at a revolution's start 2.1 mm and mm/rad from the one before, back within the
    periodic tolerance after two). solve_ivp (DOP853) from the returned revolution's start: two revolutions come
    back to it, one does not, and the first follows the returned trajectory."""
    case = lecture_fast_case
    w, theta = case.speed_rpm * RPM, np.arange(N) * (2 * math.pi / N)
    traj, residual, best, total, period = _compliant._shoot(case.motion, case.model, w, theta)
    traj = np.asarray(traj)
    floor = _compliant.periodic_tol(case.motion.host(theta)[0])
    assert period == 2 and residual <= floor and best in (total - 1, total)
    # DOP853 at rtol 1e-13: at 1e-11 it is 4.3e-6 mm off itself at 1e-13 (camdyn stepped through the switches agreed
    # with that one to 1.8e-8 mm)
    xs, ps, end = scipy_revolutions(case.model, w, traj[0], revs=2, rtol=1e-13, atol=1e-15)
    assert np.max(np.abs(xs[0] - traj[:, 0])) < 1e-7  # mm: the returned revolution (1.2e-8)
    assert np.hypot(xs[1, 0] - traj[0, 0], ps[1, 0] - traj[0, 1]) > 2.0  # the next one starts elsewhere
    assert np.hypot(*(end - traj[0])) < floor  # two come back (3e-6 of the 2e-5 tolerance)
    s = case.motion.host(theta)[0]
    assert np.max(traj[:, 0] - s) > np.max(xs[1] - s)  # of the two, the one in which the follower flies the higher
    r = dyn.compliant_response(case.motion, case.model, w, n=N)
    assert any("repeats every other revolution" in x for x in r.warnings)
    assert not any("no exactly periodic" in x for x in r.warnings)
    assert r.period_revolutions == 2 and r.periodicity_error == pytest.approx(residual, rel=1e-12)


# a never-seen lecture-like cam whose bouncing dies out slowly: the start of a revolution swings to either side of
# the periodic orbit's, 0.8 of the swing before (its monodromy matrix, blind to the contact's switches, says 1.45)
SETTLING_SEGMENTS = [
    {"law": "modified-sine", "end": 100, "lift": 5.348},
    {"law": "modified-sine", "end": 150, "lift": 7.232},
    {"law": "modified-sine", "end": 160, "lift": 4.654},
    {"law": "polynomial-345", "end": 170, "lift": -4.654},
    {"law": "cycloidal", "end": 200, "lift": -7.232},
    {"law": "polynomial-345", "end": 280, "lift": -5.348},
    {"law": "dwell", "end": 360},
]


@pytest.mark.slow
def test_a_bouncing_that_dies_out_slowly_is_summed_to_its_orbit(monkeypatch):
    """Plain revolutions that settle by a steady ratio are summed to where they end (Aitken's extrapolation): the
    same periodic orbit as 66 plain revolutions reach (the gap to 1e-6 of itself, the forces within what the
    reference's mismatch moves them; closer to periodic), in a third of the revolutions."""
    case = case_from_dict(LECTURE | {"motion": {"segments": SETTLING_SEGMENTS}})
    w, theta = case.speed_rpm * RPM, np.arange(THETA_GRID) * (2 * math.pi / THETA_GRID)
    revs = _counting_revolutions(monkeypatch)
    traj, residual, best, total, _ = _compliant._shoot(case.motion, case.model, w, theta)
    summed = len(revs)
    monkeypatch.setattr(_compliant, "_SETTLING_REVS", 10**6)  # plain revolutions only: the reference
    ref, ref_residual, _, ref_total, _ = _compliant._shoot(case.motion, case.model, w, theta)
    assert (best, total, summed) == (total, total, total) and total <= ref_total // 3
    floor = _compliant.periodic_tol(case.motion.host(theta)[0])
    assert residual <= floor and ref_residual <= floor and residual < ref_residual
    s = case.motion.host(theta)[0]
    gap, ref_gap = (float(np.max(np.asarray(t)[:, 0] - s)) for t in (traj, ref))
    assert gap > 20.0 and gap == pytest.approx(ref_gap, rel=1e-6)
    force = [
        np.asarray(_compliant._contact_force_jit(case.motion, case.model, np.asarray(w), theta, *np.asarray(t).T))
        for t in (traj, ref)
    ]
    # within what the reference's own mismatch moves the train's force (1000 N/mm x 1.7e-5 mm)
    assert np.max(np.abs(force[0] - force[1])) <= float(case.model.train_stiffness) * case.model.scale * ref_residual


@pytest.mark.slow
def test_thousand_segment_program_gets_a_verdict(monkeypatch):
    """500 pairs of +-1 mm cycloids of 0.36 deg each on the lecture's follower: the follower is hit by every tooth
    and flies between them (a thousand switches a revolution, each a piece of its own). The shooting stops at the
    first revolution within the periodic tolerance instead of running all 8 + 60 (where it spent minutes): a FAIL
    verdict with one flight and one impact per tooth."""
    segments = [{"law": "cycloidal", "end": 0.36 * (i + 1), "lift": 1.0 - 2.0 * (i % 2)} for i in range(1000)]
    case = case_from_dict(LECTURE | {"motion": {"segments": segments}})
    revs = _counting_revolutions(monkeypatch)
    report = run_check(case)
    assert report.verdict == "fail" and report.response.min_force == 0.0
    # plain revolutions while the flow expands, then Newton's steps with the switches' saltation: the 5th within the
    # periodic tolerance (8 when the monodromy missed the saltation, 10 when a first Newton step threw the start 25 mm
    # off, 15 when 2 more had to see the floor, 68 before it)
    assert len(revs) <= 6
    # all but the last steer at loosened tolerances (under half the steps each); the last, at the full ones, is judged
    assert [rev.loose for rev in revs] == [True] * (len(revs) - 1) + [False]
    assert report.response.periodicity_error <= _compliant.periodic_tol(report.response.s)
    assert report.dynamic.json()["period_revolutions"] == 1
    assert len(report.response.flights) == 500 and len(report.response.impacts) == 500
    assert any("leaves the cam 500 times a revolution" in w for w in report.warnings)


@pytest.mark.slow
def test_a_slow_cam_takes_the_frequency_domain_within_the_ringing_it_leaves_out(lecture):
    """Past ``_SLOW_RATIO`` train vibrations a revolution (the lecture below 6.8 rpm), where the frequency domain stays
    on the cam, the response is its steady state with a note, not 10^4 vibrations stepped through (a check at 1 rpm:
    7.8 -> 1.1 s). What that leaves out is the ringing of the train's mode where the cam's acceleration jumps, past
    the grid's harmonics: just under the switch the shooting's orbit differs from the frequency domain's by that
    bound (|ds''| / ratio^2, 4.0e-6 against 4.6e-6 mm), within the periodic tolerance."""
    motion, model = lecture
    mode = _compliant._contact_mode(model)
    w_shot, w_fd = mode / (0.95 * _compliant._SLOW_RATIO), mode / (1.05 * _compliant._SLOW_RATIO)
    shot, fd = (dyn.compliant_response(motion, model, w) for w in (w_shot, w_fd))
    assert not any("frequency domain" in w for w in shot.warnings) and shot.domain == "time"
    assert any("frequency domain (in contact)" in w and "is left out" in w for w in fd.warnings)
    assert fd.domain == "frequency"  # the report's operating point says so
    theta = np.arange(THETA_GRID) * (2 * math.pi / THETA_GRID)
    on_cam = _compliant._on_cam(motion, model, np.asarray(w_shot), theta)
    assert on_cam is not None
    bound = _compliant._ringing(motion, mode / w_shot)
    gap = float(np.max(np.abs(on_cam[0] - shot.x)))
    assert 0.5 * bound < gap < 1.2 * bound < _compliant.periodic_tol(20.0)
