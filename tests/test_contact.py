"""Hertz line contact against textbook worked examples, an independent concave-contact formula, and the cam.

Worked examples (the numbers as printed there):

* Shigley's Mechanical Engineering Design, 10th ed., Problem 3-142 and its solutions manual: a cast-iron wheel,
  d = 3 in, w = 1.25 in, F = 250 lbf, on a flat cast-iron rail (E = 14.5 Mpsi, nu = 0.211, Table A-5), with
  Eq. (3-73): b = 0.007095 in; Eq. (3-74) p_max = 2F / (pi b l) then gives 17.9 kpsi.
* T. H. Brown, Marks' Calculations for Machine Design (McGraw-Hill, 2005), chapter 3, contact stresses,
  Example 2 (SI): a steel railroad wheel d = 1 m on a flat steel rail, L = 0.1 m, F = 147,500 N (1,180 kN on
  eight wheels), E = 210 GPa, nu = 0.3: b^2 = 8.14e-6 m^2, b = 0.0028 m.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camdyn.model  # noqa: F401  (float64)
from camdyn import InputError, NumericalError
from camdyn.model.contact import cam_contact, cylinders, effective_modulus, equivalent_curvature_per_mm, line_contact
from camdyn.model.geometry import analyze
from camdyn.model.motion import Program
from camdyn.schema import FollowerSpec

IN, LBF, PSI = 0.0254, 4.4482216152605, 6894.757293168


def test_shigley_problem_3_142_cast_iron_wheel_on_rail():
    e_star = effective_modulus(14.5e6 * PSI, 0.211, 14.5e6 * PSI, 0.211)
    b, p = cylinders(250 * LBF, 1.5 * IN, math.inf, 1.25 * IN, e_star)
    assert float(b) / IN == pytest.approx(0.007095, rel=2e-4)
    assert float(p) / PSI / 1e3 == pytest.approx(17.9, abs=0.05)
    assert float(p) == pytest.approx(2 * 250 * LBF / (math.pi * float(b) * 1.25 * IN), rel=1e-12)  # Eq. (3-74)


def test_marks_example_2_railroad_wheel():
    e_star = effective_modulus(210e9, 0.3, 210e9, 0.3)
    b, p = cylinders(147_500.0, 0.5, math.inf, 0.1, e_star)
    assert float(b) ** 2 == pytest.approx(8.14e-6, rel=1e-3)
    assert float(b) == pytest.approx(0.0028, rel=0.02)  # printed to two figures
    assert float(p) == pytest.approx(2 * 147_500.0 / (math.pi * float(b) * 0.1), rel=1e-12)


def test_concave_contact_against_the_roller_in_a_hollow_formula():
    """A roller in a concave cylinder of the same material: Mechanical Engineer's Data Handbook (J. Carvill,
    1993), 'roller on concave surface': w = sqrt(32 F (1 - nu^2) / (pi L E (1/r1 - 1/r2))), p = 4 F / (pi w L)
    (w the full width 2b), written out here without camdyn's effective modulus."""
    E, nu, F, L, r1, r2 = 200e9, 0.3, 2000.0, 0.012, 0.010, 0.045
    w = math.sqrt(32 * F * (1 - nu**2) / (math.pi * L * E * (1 / r1 - 1 / r2)))
    b, p = cylinders(F, r1, -r2, L, effective_modulus(E, nu, E, nu))
    assert 2 * float(b) == pytest.approx(w, rel=1e-12)
    assert float(p) == pytest.approx(4 * F / (math.pi * w * L), rel=1e-12)


def test_no_force_no_contact_and_a_roller_too_large_for_its_hollow():
    b, p = line_contact(np.array([-5.0, 0.0, 10.0]), np.array([-1.0, 50.0, 50.0]), 0.01, 1e11)
    assert b[0] == p[0] == b[1] == p[1] == 0.0 and p[2] > 0
    with pytest.raises(NumericalError, match="not positive"):
        cylinders(10.0, 0.02, -0.01, 0.01, 1e11)


STEEL = (207.0, 0.292)
E_MM, RB_MM = 5.0, 30.0


def eccentric():
    return Program.from_segments(
        [{"law": "harmonic", "end": 180, "lift": 2 * E_MM}, {"law": "harmonic", "end": 360, "lift": -2 * E_MM}]
    )


def test_eccentric_cam_flat_face_is_a_cylinder_on_a_plane():
    """s = e (1 - cos): the contour is a circle of radius Rb + e, so p = sqrt(F E* / (pi L (Rb + e)))."""
    geo = analyze(eccentric(), FollowerSpec(type="translating-flat", base_radius=RB_MM))
    theta = np.deg2rad(geo.theta_deg)
    force = 30.0 + 400.0 * (1 - np.cos(theta)) + 80.0 * np.cos(theta)  # any positive force
    cs = cam_contact(geo, force, width_mm=12.0, cam=STEEL, follower=STEEL)
    e_star = 207e9 / (2 * (1 - 0.292**2))
    expect = np.sqrt(force * e_star / (math.pi * 0.012 * (RB_MM + E_MM) * 1e-3)) / 1e6
    np.testing.assert_allclose(cs.pressure_MPa, expect, rtol=1e-9)
    np.testing.assert_allclose(cs.equivalent_radius_mm, RB_MM + E_MM, rtol=1e-9)
    i = int(np.argmax(expect))
    assert cs.peak_pressure_MPa == pytest.approx(expect[i], rel=1e-12) and cs.peak_at_deg == geo.theta_deg[i]
    assert cs.json()["max_contact_stress_MPa"] == cs.peak_pressure_MPa


STEEP = Program.from_segments(
    [
        {"law": "dwell", "end": 90},
        {"law": "cycloidal", "end": 150, "lift": 30},
        {"law": "dwell", "end": 210},
        {"law": "cycloidal", "end": 270, "lift": -30},
        {"law": "dwell", "end": 360},
    ]
)


def test_roller_on_concave_flanks():
    """A steep cam has concave flanks (negative contour radius): there the roller touches like a cylinder of
    radius R = Rr rho / (rho + Rr) > Rr, from the contour radius camdyn reports (the other route to K)."""
    rr = 10.0
    geo = analyze(STEEP, FollowerSpec(type="translating-roller", base_radius=40.0, roller_radius=rr))
    rho = geo.rho_contour_mm
    concave = rho < 0
    assert concave.sum() > 100
    k = equivalent_curvature_per_mm(geo)
    straight = ~np.isfinite(rho)
    np.testing.assert_allclose(1.0 / k[~straight], rr * rho[~straight] / (rho[~straight] + rr), rtol=1e-9)
    assert np.all(1.0 / k[concave] > rr)
    cs = cam_contact(geo, np.full(geo.theta_deg.shape, 500.0), width_mm=10.0, cam=STEEL, follower=STEEL)
    # a translating roller's normal force is the axial force over cos(pressure angle)
    np.testing.assert_allclose(cs.normal_force_N, 500.0 / np.cos(np.deg2rad(geo.pressure_angle_deg)), rtol=1e-12)
    assert np.all(np.isfinite(cs.pressure_MPa)) and cs.peak_pressure_MPa > 0


def test_undercut_and_bad_width_refused():
    geo = analyze(STEEP, FollowerSpec(type="translating-roller", base_radius=10.0, roller_radius=30.0))
    assert geo.undercut
    with pytest.raises(NumericalError, match="undercut"):
        cam_contact(geo, np.ones(geo.theta_deg.shape), width_mm=10.0, cam=STEEL, follower=STEEL)
    flat = analyze(STEEP, FollowerSpec(type="translating-flat", base_radius=40.0))
    with pytest.raises(NumericalError, match="undercut"):
        cam_contact(flat, np.ones(flat.theta_deg.shape), width_mm=10.0, cam=STEEL, follower=STEEL)
    ok = analyze(eccentric(), FollowerSpec(type="translating-flat", base_radius=RB_MM))
    with pytest.raises(InputError, match="width"):
        cam_contact(ok, np.ones(ok.theta_deg.shape), width_mm=-1.0, cam=STEEL, follower=STEEL)
