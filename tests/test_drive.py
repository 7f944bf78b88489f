"""Camshaft drive torque against closed forms and the energy balance.

* The eccentric cam (two harmonic segments: s = e (1 - cos theta) exactly) at constant speed: the torque, its
  mean, RMS, peak, the energy swing and the flywheel inertia in closed form, written out here from
  F = m w^2 s'' + c w s' + k s + F0 and T = F s' (no camdyn code in the reference).
* The energy balance: over a revolution the drive's mean power equals what the dampers dissipate. For a rigid
  follower with viscous damping c that is c w^2 mean(s'^2); for a compliant train (the diffrax steady state)
  it is w^2 [c mean(x'^2) + c_f mean((s' - x')^2)], from the solved x alone.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camdyn.model  # noqa: F401  (float64)
from camdyn import InputError
from camdyn.model import dynamics as dyn
from camdyn.model.case import case_from_dict
from camdyn.model.drive import drive_torque, kinematic_drive, response_drive
from camdyn.model.follower import FollowerModel
from camdyn.model.motion import Program

RPM = 2 * math.pi / 60
E_M = 5e-3  # eccentricity, m
M, K, F0, C = 0.5, 2000.0, 30.0, 3.0  # kg, N/m, N, N*s/m


def eccentric_cam():
    e_mm = E_M * 1e3
    return Program.from_segments(
        [{"law": "harmonic", "end": 180, "lift": 2 * e_mm}, {"law": "harmonic", "end": 360, "lift": -2 * e_mm}]
    )


def rigid(c=C):
    vals = dict(
        mass=M,
        stiffness=K,
        preload=F0,
        damping=c,
        external=0.0,
        train_stiffness=math.inf,
        train_damping=0.0,
        restitution=0.0,
    )
    return FollowerModel(**{k: np.asarray(float(v)) for k, v in vals.items()})


def closed_form(theta, w, c):
    """T(theta) = A sin(theta) + B sin(2 theta) + Cc sin^2(theta) and its energy integral for s = e (1 - cos)."""
    A = E_M * (F0 + K * E_M)
    B = 0.5 * E_M**2 * (M * w**2 - K)
    Cc = c * w * E_M**2
    torque = A * np.sin(theta) + B * np.sin(2 * theta) + Cc * np.sin(theta) ** 2
    energy = A * (1 - np.cos(theta)) + 0.5 * B * (1 - np.cos(2 * theta)) - 0.25 * Cc * np.sin(2 * theta)
    return torque, energy, (A, B, Cc)


@pytest.mark.parametrize("rpm, c", [(300.0, C), (300.0, 0.0), (900.0, C)])
def test_eccentric_cam_against_closed_form(rpm, c):
    w = rpm * RPM
    d = kinematic_drive(eccentric_cam(), rigid(c), w, speed_fluctuation=0.04)
    theta = np.deg2rad(d.theta_deg)
    torque, _, (A, B, Cc) = closed_form(theta, w, c)
    scale = np.max(np.abs(torque))
    np.testing.assert_allclose(d.torque, torque, rtol=0, atol=1e-12 * scale)
    assert d.mean_torque == pytest.approx(Cc / 2, abs=1e-12 * scale)  # only the damper takes energy
    assert d.mean_power == pytest.approx(Cc / 2 * w, abs=1e-12 * scale * w)
    assert d.rms_torque == pytest.approx(math.sqrt(A**2 / 2 + B**2 / 2 + 3 * Cc**2 / 8), rel=1e-12)
    # the peak and the energy swing from the closed form on a grid 300x finer
    fine = np.linspace(0, 2 * math.pi, 1_080_001)
    t_fine, e_fine, _ = closed_form(fine, w, c)
    i = int(np.argmax(np.abs(t_fine)))
    assert d.peak_torque == pytest.approx(abs(t_fine[i]), rel=1e-6)
    assert d.peak_torque_at_deg == pytest.approx(math.degrees(fine[i]), abs=0.1)
    swing = np.ptp(e_fine)
    assert d.energy_swing == pytest.approx(swing, rel=1e-6)
    assert d.flywheel_inertia == pytest.approx(swing / (0.04 * w**2), rel=1e-6)
    if c == 0.0:  # without damping the swing has a closed form: E = A (1 - u) + B (1 - u^2), u = cos(theta)
        cand = [0.0, 2 * A] + ([A + B + A**2 / (4 * B)] if B != 0 and abs(A / (2 * B)) <= 1 else [])
        assert d.energy_swing == pytest.approx(max(cand) - min(cand), rel=1e-6)


def test_json_keys_and_units():
    d = kinematic_drive(eccentric_cam(), rigid(), 300 * RPM)
    out = d.json()
    for key in (
        "peak_torque_N_m",
        "rms_torque_N_m",
        "mean_power_W",
        "flywheel_inertia_kg_m2",
        "energy_swing_J",
        "speed_fluctuation",
    ):
        assert math.isfinite(out[key])
    assert out["speed_fluctuation"] == 0.05
    assert out["max_torque_N_m"] >= out["mean_torque_N_m"] >= out["min_torque_N_m"]


def test_bad_grid_and_speed_refused():
    theta = np.arange(360.0)
    with pytest.raises(InputError, match="equal steps"):
        drive_torque(theta[::-1], np.ones(360), np.ones(360), 1.0)
    with pytest.raises(InputError, match="positive"):
        drive_torque(theta, np.ones(360), np.ones(360), 0.0)
    with pytest.raises(InputError, match="speed_fluctuation"):
        drive_torque(theta, np.ones(360), np.ones(360), 1.0, speed_fluctuation=0.0)


LECTURE = {
    "motion": {
        "segments": [
            {"law": "dwell", "end": 90},
            {"law": "cycloidal", "end": 180, "lift": 20},
            {"law": "dwell", "end": 240},
            {"law": "harmonic", "end": 360, "lift": -20},
        ]
    },
    "follower": {"type": "translating-roller", "base_radius": 40, "roller_radius": 10, "offset": 5},
    "dynamics": {"speed": 300, "mass": 0.5, "spring_rate": 2.0, "preload": 30, "damping_ratio": 0.05},
}


def test_energy_balance_rigid_follower():
    """Mean drive power = c w^2 mean(s'^2): the inertia, spring and preload terms return what they take.

    On a grid the conservative terms cancel only to the rectangle rule's error, O(h^2) where s'' jumps (the
    harmonic return): the balance holds to 1e-5 on 3600 steps, and doubling the steps divides the gap by 4.
    """
    case = case_from_dict(LECTURE)
    w = 300 * RPM
    gaps = []
    for n in (3600, 7200):
        resp = dyn.response(case.motion, case.model, w, n)
        assert resp.model == "rigid" and not resp.separations
        d = response_drive(case.motion, resp, scale=case.model.scale)
        _, vals = case.motion.sample(n)
        loss = float(case.model.damping) * w**2 * np.mean((vals[1] * 1e-3) ** 2)
        gaps.append(d.mean_power / loss - 1.0)
        # the test means something: the power that flows in and back out is far larger than the loss
        assert np.max(np.abs(d.torque)) * w > 50 * loss
    assert abs(gaps[0]) < 2e-5
    assert gaps[0] / gaps[1] == pytest.approx(4.0, rel=0.02)


@pytest.mark.slow
def test_energy_balance_compliant_train():
    """With a compliant train the loss is w^2 [c mean(x'^2) + c_f mean((s' - x')^2)], from the diffrax orbit."""
    case = case_from_dict(
        {**LECTURE, "dynamics": {**LECTURE["dynamics"], "train_stiffness": 1000, "train_damping_ratio": 0.05}}
    )
    w = 300 * RPM
    resp = dyn.response(case.motion, case.model, w)
    assert resp.model == "compliant" and not resp.separations
    d = response_drive(case.motion, resp, scale=case.model.scale)
    _, vals = case.motion.sample(resp.theta_deg.size)
    s1, x1 = vals[1] * 1e-3, resp.dx * 1e-3
    loss = w**2 * (
        float(case.model.damping) * np.mean(x1**2) + float(case.model.train_damping) * np.mean((s1 - x1) ** 2)
    )
    assert d.mean_power == pytest.approx(loss, rel=2e-5)  # the rectangle rule's O(h^2), as for the rigid follower
    assert np.max(np.abs(d.torque)) * w > 50 * loss


def test_one_stored_program_serves_every_speed(tmp_path, monkeypatch):
    """The speed is data, not part of the program: a drive at a second speed traces and stores nothing new (a Python
    float would be a static argument, a program for every speed)."""
    from camdyn._core import jit as programs
    from camdyn.model.dynamics import _kinematic

    monkeypatch.setattr(programs, "_DIR", None)
    programs.enable(tmp_path)
    # a program of its own: not the one an earlier test of this process holds in memory
    monkeypatch.setattr(_kinematic, "_kinematic_force_program", programs.cached_jit(_kinematic.kinematic_force))
    stored = lambda: set(tmp_path.rglob(f"*.{programs.SUFFIX}"))  # noqa: E731
    kinematic_drive(eccentric_cam(), rigid(), 300.0 * RPM)
    first = stored()
    assert any(p.name.startswith("kinematic_force") for p in first)
    kinematic_drive(eccentric_cam(), rigid(), 450.0 * RPM)
    assert stored() == first
