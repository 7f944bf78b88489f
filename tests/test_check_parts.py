"""`check` and `table` carry the parts: the camshaft drive, the Hertz contact stress and its limit."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _helpers import run

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"


@pytest.mark.slow
def test_check_reports_drive_and_contact_stress(capsys, tmp_path):
    text = (
        LECTURE.read_text()
        .replace("rotation = ", "width = 10\nrotation = ", 1)
        .replace("[limits]", "[limits]\nmax_contact_stress = 400")
    )
    case = tmp_path / "wide.toml"
    case.write_text(text)
    code, out, err = run(capsys, "check", case, "--json")
    doc = json.loads(out)
    drive, contact = doc["drive"], doc["contact"]
    assert {"peak_torque_N_m", "rms_torque_N_m", "mean_power_W", "flywheel_inertia_kg_m2"} <= set(drive)
    assert drive["rms_torque_N_m"] <= drive["peak_torque_N_m"]
    stress = {c["name"]: c for c in doc["checks"]}["contact_stress"]
    assert stress["value"] == pytest.approx(contact["max_contact_stress_MPa"]) and stress["limit"] == 400.0
    # steel on steel, 10 mm wide, a few tens of newtons on radii of tens of mm: hundreds of MPa
    assert 100.0 < contact["max_contact_stress_MPa"] < 1000.0
    assert code == (0 if stress["ok"] else 1)


@pytest.mark.slow
def test_table_torque_is_force_times_follower_velocity(capsys):
    code, out, _ = run(capsys, "table", LECTURE)  # the default 1 deg step: the programs test_cli's tables compile
    header = out.splitlines()[0].split(",")
    data = np.loadtxt(out.splitlines()[1:], delimiter=",")
    col = {name: data[:, i] for i, name in enumerate(header)}
    np.testing.assert_allclose(
        col["drive_torque_N_m"], col["contact_force_N"] * col["v_mm_per_rad"] / 1000.0, rtol=1e-8, atol=1e-12
    )
