"""`size --buildable`: the least peak force over springs that can be built, and the part (issue 16)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from camdyn.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["lecture", "oscillating", "circle"])
def test_buildable_spring_is_a_part_that_holds(capsys, name):
    code = main(["size", str(ROOT / "cases" / f"{name}.toml"), "--buildable", "--json"])
    doc = json.loads(capsys.readouterr().out)
    part = doc["part"]
    assert code == 0 and doc["buildable"] and doc["holds"]
    assert part["rate_N_per_mm"] >= 0.05  # a real spring, not 1e-6 N/mm
    assert all(c["ok"] for c in part["checks"])
    # the part is the sized spring: its rate at the spring is the sizer's rate (through the lever arm for an arm)
    if doc["follower"] == "translating":
        assert part["rate_N_per_mm"] == pytest.approx(doc["spring_rate_N_per_mm"], rel=1e-9)
    # the unconstrained optimum is a lower bound on the buildable peak force
    unconstrained = main(["size", str(ROOT / "cases" / f"{name}.toml"), "--json"])
    free = json.loads(capsys.readouterr().out)
    key = "peak_spring_force_N" if doc["follower"] == "translating" else "peak_spring_torque_N_m"
    assert unconstrained == 0 and doc[key] >= free[key] * (1 - 1e-6)


def test_nothing_buildable_is_one_line(capsys, tmp_path):
    text = (ROOT / "cases" / "lecture.toml").read_text() + "\n[spring]\noutside_diameter_max = 2\n"
    case = tmp_path / "tiny.toml"
    case.write_text(text)
    code = main(["size", str(case), "--buildable"])
    *phases, error = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and "spring" in error and "Traceback" not in error
    assert all(line.startswith("camdyn: buildable springs") and line.endswith(" ...") for line in phases)  # a pipe
