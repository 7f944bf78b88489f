"""`size --buildable`: the least peak force over springs that can be built, and the part (issue 16)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from camdyn._core.errors import InputError
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


def _lecture_sizing():
    """The lecture resolved and its sizing problem at its speed margin: (case, problem, grid, dynamic, surge top)."""
    from camdyn.design.parts import resolve_spring
    from camdyn.design.sizing._dynamic import Dynamic
    from camdyn.design.sizing._problem import build_problem
    from camdyn.model.case import build_case
    from camdyn.schema import load_case_spec

    path = ROOT / "cases" / "lecture.toml"
    case = resolve_spring(build_case(load_case_spec(path), source=path))
    margin = float(case.limits.speed_margin)
    p, grid = build_problem(case, case.speed_rpm, margin, 0.0)
    return case, p, grid, Dynamic.of(p), margin * case.speed_rpm


@pytest.mark.slow  # three sizings of the lecture, one verifying every scanned rate
def test_a_verified_preload_past_its_springs_reach_gives_way_to_the_next_rate(monkeypatch):
    """The scan compares the preloads the search finds; the answer's is verified on more speeds. Where that raises
    it past what a spring of the rate can give, the best scanned rate whose verified preload still fits is the answer,
    never an unbuildable one; where none fits, one line naming [spring]."""
    from camdyn.design.sizing._buildable import buildable_answer
    from camdyn.design.sizing._dynamic import Dynamic
    from camdyn.design.spring import case_max_preload

    case, p, grid, dynamic, top_rpm = _lecture_sizing()
    k0, f0 = buildable_answer(case, p, grid, dynamic, top_rpm)
    assert f0 <= case_max_preload(case, p.kind.rate_from_si(k0), top_rpm)
    verify = Dynamic.raised

    def raised_past_reach(self, k, f, rtol=0.0):  # every rate as soft as the answer verified far above its reach
        return verify(self, k, f, rtol) + (1e6 if k <= k0 * (1.0 + 1e-9) else 0.0)

    monkeypatch.setattr(Dynamic, "raised", raised_past_reach)
    k1, f1 = buildable_answer(case, p, grid, dynamic, top_rpm)
    assert k1 > k0 and f1 <= case_max_preload(case, p.kind.rate_from_si(k1), top_rpm)
    monkeypatch.setattr(Dynamic, "raised", lambda self, k, f, rtol=0.0: verify(self, k, f, rtol) + 1e6)
    with pytest.raises(InputError, match="no buildable spring holds"):
        buildable_answer(case, p, grid, dynamic, top_rpm)
