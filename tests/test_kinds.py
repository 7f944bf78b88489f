"""The follower kinds: each owns its units, its conversions and its output names (camdyn._core.kinds)."""

from __future__ import annotations

import math
import typing
from pathlib import Path

import numpy as np
import pytest

from camdyn._core.kinds import (
    FOLLOWER_KINDS,
    FOLLOWER_TYPES,
    OSCILLATING,
    TRANSLATING,
    kind_of_lift,
    kind_of_motion,
)
from camdyn._core.units import tolerance_unit
from camdyn.design.sizing._results import spring_keys
from camdyn.design.tolerance import csv_columns
from camdyn.schema import FollowerSpec, dynamics_keys, load_case_spec


def test_the_two_kinds_units():
    assert (TRANSLATING.lift_unit, TRANSLATING.motion_unit, TRANSLATING.rate_unit, TRANSLATING.force_unit) == (
        "mm",
        "mm",
        "N/mm",
        "N",
    )
    assert (OSCILLATING.lift_unit, OSCILLATING.motion_unit, OSCILLATING.rate_unit, OSCILLATING.force_unit) == (
        "deg",
        "rad",
        "N*m/rad",
        "N*m",
    )
    assert not TRANSLATING.rotary and OSCILLATING.rotary
    assert (TRANSLATING.default_max_pressure_angle_deg, OSCILLATING.default_max_pressure_angle_deg) == (30.0, 35.0)
    assert TRANSLATING.a == "a translating" and OSCILLATING.a == "an oscillating"


def test_lift_and_rate_conversions():
    # an arm's 180 deg of swing is pi rad; its dynamics are in rad already, a translating follower's in m
    assert OSCILLATING.lift_to_motion(180.0) == pytest.approx(math.pi, rel=1e-15)
    assert OSCILLATING.motion_to_lift(math.pi / 6) == pytest.approx(30.0, rel=1e-15)
    assert TRANSLATING.lift_to_motion(12.5) == 12.5
    assert TRANSLATING.si_per_motion == 1e-3 and OSCILLATING.si_per_motion == 1.0
    assert TRANSLATING.rate_to_si(2.5) == pytest.approx(2500.0, rel=1e-15)  # N/mm -> N/m
    assert OSCILLATING.rate_to_si(2.5) == 2.5  # N*m/rad stays
    x = np.random.default_rng(0).normal(size=(3, 7)) * 40.0
    for kind in FOLLOWER_KINDS:
        np.testing.assert_allclose(kind.motion_to_lift(kind.lift_to_motion(x)), x, rtol=1e-15)
        np.testing.assert_allclose(kind.rate_from_si(kind.rate_to_si(x)), x, rtol=1e-15)


def test_kinds_are_found_by_their_units():
    assert kind_of_motion("mm") is TRANSLATING and kind_of_motion("rad") is OSCILLATING
    assert kind_of_lift("mm") is TRANSLATING and kind_of_lift("deg") is OSCILLATING
    with pytest.raises(ValueError, match="mm, rad"):
        kind_of_motion("in")


def test_the_follower_types_are_the_schemas():
    assert tuple(FOLLOWER_TYPES) == typing.get_args(FollowerSpec.model_fields["type"].annotation)
    assert {(t.kind, t.roller) for t in FOLLOWER_TYPES.values()} == {
        (k, roller) for k in FOLLOWER_KINDS for roller in (True, False)
    }


@pytest.mark.parametrize(
    ("case", "kind", "roller"),
    [("lecture", TRANSLATING, True), ("oscillating", OSCILLATING, True), ("valve-lift", TRANSLATING, False)],
)
def test_a_case_reads_its_kind(case, kind, roller):
    spec = load_case_spec(Path(__file__).resolve().parents[1] / "cases" / f"{case}.toml")
    assert spec.kind is kind and spec.follower.kind is kind and spec.follower.roller is roller
    assert spec.oscillating is kind.rotary


def test_output_names_per_kind():
    assert dynamics_keys(TRANSLATING)[:3] == ("mass", "spring_rate", "preload")
    assert dynamics_keys(OSCILLATING)[:3] == ("inertia", "torsion_rate", "preload_torque")
    assert spring_keys(TRANSLATING) == ("spring_rate_N_per_mm", "preload_N", "peak_spring_force_N")
    assert spring_keys(OSCILLATING) == ("torsion_rate_N_m_per_rad", "preload_torque_N_m", "peak_spring_torque_N_m")
    assert csv_columns(OSCILLATING)[1:7] == (
        "spring_rate_N_m_per_rad",
        "preload_N_m",
        "mass_kg_m2",
        "train_stiffness_N_m_per_rad",
        "speed_rpm",
        "profile_error_rms_rad",
    )
    assert csv_columns(TRANSLATING)[6] == "profile_error_rms_mm"
    assert tolerance_unit("profile_error", OSCILLATING.rotary) == OSCILLATING.motion_unit
    assert TRANSLATING.table_columns[0] == "s_mm" and OSCILLATING.table_columns[0] == "phi_deg"
