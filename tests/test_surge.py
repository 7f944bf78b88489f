"""The spring as a chain of masses: the lumped limit, the diffrax reference, and surge lowering the jump speed.

The demonstration is a valve-train-like cam (3-4-5 rise and return of 10 mm over 160 deg, a 80 g follower, a
30 N/mm spring with 250 N preload, a compliant train of 20 kN/mm): with an 80 g spring (surge 306 Hz, a real
valve spring's) the lumped model (a third of the spring's mass on the follower) jumps at about 3470 rpm, but the
coils surge on the lift's 6th harmonic and the chain jumps near 2990 rpm.
"""

import math

import equinox as eqx
import numpy as np
import pytest

import camdyn.model  # noqa: F401
from camdyn.model import dynamics as dyn
from camdyn.model.case import case_from_dict
from camdyn.model.follower import with_spring_mass
from camdyn.model.surge import chain_jump_speed, chain_revolution, chain_steady_force

RPM = 2 * math.pi / 60
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
VALVE = {
    "motion": {
        "segments": [
            {"law": "dwell", "end": 100},
            {"law": "polynomial-345", "end": 180, "lift": 10},
            {"law": "polynomial-345", "end": 260, "lift": -10},
            {"law": "dwell", "end": 360},
        ]
    },
    "follower": {"type": "translating-flat", "base_radius": 20},
    "dynamics": {
        "speed": 3000,
        "mass": 0.08,
        "spring_rate": 30,
        "preload": 250,
        "damping_ratio": 0.05,
        "train_stiffness": 20000,
        "train_damping_ratio": 0.05,
    },
}


@pytest.mark.parametrize("train", [False, True])
def test_a_massless_chain_is_the_lumped_spring(train):
    d = {**LECTURE["dynamics"], **({"train_stiffness": 1000, "train_damping_ratio": 0.05} if train else {})}
    case = case_from_dict({**LECTURE, "dynamics": d})
    w, n = 300 * RPM, 4096
    fi, _, _ = chain_steady_force(case.motion, case.model, 1e-12, w, n=n)
    theta = np.arange(n) * (2 * math.pi / n)
    lumped = (
        eqx.filter_jit(lambda motion, model, w: dyn.steady_force_at(motion, model, n)(w))(case.motion, case.model, w)
        if train
        else dyn.kinematic_force_jit(case.motion, case.model, w, theta)
    )
    # what differs is the spring's own inertia (1e-12 kg) and the coils' damper (~ sqrt(m_s): 2e-8 N*s/m)
    np.testing.assert_allclose(fi, np.asarray(lumped), rtol=0, atol=1e-6)


@pytest.mark.slow
def test_diffrax_chain_reproduces_the_frequency_domain_orbit():
    """One revolution of the chain in diffrax from the frequency-domain state at 0 deg comes back to it, with the
    same interface force at every angle."""
    case = case_from_dict(VALVE)
    w, n, ms = 2500 * RPM, 4096, 0.08
    fi, q, dq = chain_steady_force(case.motion, case.model, ms, w, n=n)
    assert fi.min() > 0
    theta = np.arange(n) * (2 * math.pi / n)
    q_t, f_t, end = chain_revolution(case.motion, case.model, ms, w, q[0], w * dq[0], theta)
    segments = q.shape[1]
    assert np.max(np.abs(end[:segments] - q[0])) < 1e-10 * np.max(np.abs(q))
    np.testing.assert_allclose(f_t, fi, rtol=0, atol=1e-7 * np.max(fi))  # (1024 angles alias the jerk jumps: 2e-6)


@pytest.mark.slow
def test_surge_lowers_the_jump_speed_of_a_valve_train():
    case = case_from_dict(VALVE)
    ms = 0.08
    lumped = dyn.dynamic_jump_speed(case.motion, with_spring_mass(case.model, ms), w_max=8000 * RPM)
    chain = chain_jump_speed(case.motion, case.model, ms, w_max=2 * lumped, grid=200)
    assert lumped / RPM == pytest.approx(3475, abs=10)
    assert chain < 0.9 * lumped  # surge costs over 10 % of the speed
    surge_hz = 0.5 * math.sqrt(30e3 / ms)
    assert surge_hz / (chain / RPM / 60) == pytest.approx(6, abs=0.5)  # on the 6th harmonic
    # at that speed the chain's least force is zero, the lumped model's still well positive
    fi, _, _ = chain_steady_force(case.motion, case.model, ms, chain)
    lump = dyn.steady_force_at(case.motion, with_spring_mass(case.model, ms), 4096)(chain)
    assert abs(fi.min()) < 0.01 * fi.max() and float(np.min(lump)) > 0.1 * float(np.max(lump))


@pytest.mark.slow
def test_the_case_chooses_its_spring_model():
    from camdyn.design.parts import spring_jump_speed

    lumped = case_from_dict({**VALVE, "spring": {"model": "lumped"}})
    surge = case_from_dict({**VALVE, "spring": {"model": "surge"}})
    w_l = spring_jump_speed(lumped, 0.08, w_max=8000 * RPM)
    assert w_l == pytest.approx(
        dyn.dynamic_jump_speed(lumped.motion, with_spring_mass(lumped.model, 0.08), w_max=8000 * RPM)
    )
    assert spring_jump_speed(surge, 0.08, w_max=8000 * RPM) < 0.9 * w_l
