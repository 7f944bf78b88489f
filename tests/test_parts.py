"""The parts of a whole case from ``camdyn check``'s response: drive and contact stress, both follower kinds."""

import math
from pathlib import Path

import numpy as np
import pytest

import camdyn.model  # noqa: F401
from camdyn.design.checks import run_check
from camdyn.design.parts import case_contact, case_drive, contact_check
from camdyn.model import dynamics as dyn
from camdyn.model.case import case_from_dict
from camdyn.model.drive import response_drive
from camdyn.schema import read_toml

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module", params=["lecture", "oscillating"])
def checked(request):
    raw = read_toml(ROOT / "cases" / f"{request.param}.toml")
    raw["follower"]["width"] = 8.0
    raw["materials"] = {"cam": "steel", "follower": {"elastic_modulus": 200.0, "poisson_ratio": 0.3}}
    raw["drive"] = {"speed_fluctuation": 0.02}
    case = case_from_dict(raw)
    return case, run_check(case)


@pytest.mark.slow
def test_drive_of_the_check_response_is_the_generalized_one(checked):
    """check reports an arm's torque as a contact force in N; the drive undoes that through the lever arm and
    equals the drive of the response in the model's own units."""
    _, report = checked
    case = report.case  # with the spring's own mass ([spring] model), as check weighed it
    drive = case_drive(case, report.response)
    own = dyn.response(case.motion, case.model, report.speed_rpm * 2 * math.pi / 60)
    ref = response_drive(case.motion, own, scale=case.model.scale, speed_fluctuation=0.02)
    # two shootings at speeds a rounding apart (rpm * RPM against rpm * 2 pi / 60): their adaptive steps may part,
    # which moves a value by the integrator's error, far below 1e-10 of the largest torque
    np.testing.assert_allclose(drive.torque, ref.torque, rtol=1e-9, atol=1e-10 * np.max(np.abs(ref.torque)))
    assert drive.flywheel_inertia == pytest.approx(ref.energy_swing / (0.02 * drive.omega**2), rel=1e-12)
    assert drive.mean_power > 0  # the dampers take power


@pytest.mark.slow
def test_contact_of_the_check_response(checked):
    case, report = checked
    cs = case_contact(case, report.geometry, report.response)
    assert cs is not None and cs.width_mm == 8.0
    assert cs.e_star_GPa == pytest.approx(1 / ((1 - 0.292**2) / 207 + (1 - 0.3**2) / 200))
    i = int(np.argmax(cs.pressure_MPa))
    # the peak against the formula at that angle, from the reported normal force and equivalent radius
    p = (
        math.sqrt(cs.normal_force_N[i] * cs.e_star_GPa * 1e9 / (math.pi * 8e-3 * cs.equivalent_radius_mm[i] * 1e-3))
        / 1e6
    )
    assert cs.peak_pressure_MPa == pytest.approx(p, rel=1e-12)
    assert contact_check(cs, 2 * p).ok and not contact_check(cs, 0.5 * p).ok
    if case.oscillating:  # the contact force is the normal force
        np.testing.assert_array_equal(cs.normal_force_N, report.response.force)
