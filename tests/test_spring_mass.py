"""Sizing and springs with the spring's own mass (issue 21, section 2): what ``size --buildable`` proposes passes
``check`` as written; ``[spring] model`` changes check's jump speed by what an independent model of the spring
as a distributed mass gives; ``[limits] min_preload``; surge as a constraint; plain size's answer is a bound."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from camdyn import InputError
from camdyn.design.checks import run_check
from camdyn.design.sizing import size_spring
from camdyn.design.spring import design_spring
from camdyn.design.surge import CamHarmonics, judge_surge, surge_floor_hz
from camdyn.model.case import case_from_dict
from camdyn.model.motion import evaluate
from tests._helpers import run
from tests.conftest import load_toml

ROOT = Path(__file__).resolve().parents[1]
RPM = 2 * math.pi / 60


def _case(name: str, dynamics: dict | None = None, spring: dict | None = None, limits: dict | None = None):
    raw = load_toml(name)
    raw["dynamics"] = raw["dynamics"] | (dynamics or {})
    raw["limits"] = raw.get("limits", {}) | (limits or {})
    if spring is not None:
        raw["spring"] = spring
    return case_from_dict(raw)


# ---- an independent model of the spring: a uniform distributed mass (the wave equation), solved exactly ----


def _continuum_min_force(s, m, k, c, kf, cf, f0, ms, zeta_s, w):
    """Least interface force (N) of a compliant follower whose spring is a uniform rod of rate k and mass ms
    fixed at its far end: per harmonic its dynamic stiffness at the follower is k* beta cot(beta), k* = k + i w c_s,
    beta = w sqrt(ms / k*) (no chain, no segments); the coils' Kelvin-Voigt damping c_s gives the first
    fixed-fixed mode the damping ratio zeta_s; the follower's damper c and the train (kf, cf) as in the case."""
    n = s.size
    S = np.fft.rfft(s)
    h = np.arange(S.size)
    wh = h * w
    cs = 2 * zeta_s * k / (math.pi * math.sqrt(k / ms))
    kstar = k + 1j * wh * cs
    beta = wh * np.sqrt(ms / kstar)
    with np.errstate(invalid="ignore", divide="ignore"):
        z = np.where(h == 0, k, kstar * beta / np.tan(beta))
    X = (kf + 1j * wh * cf) * S / (z + kf - m * wh**2 + 1j * wh * (c + cf))
    X[0] = (kf * S[0] - n * f0) / (k + kf)
    x, x1, s1 = np.fft.irfft(X, n), np.fft.irfft(1j * h * X, n), np.fft.irfft(1j * h * S, n)
    return float(np.min(kf * (s - x) + cf * w * (s1 - x1)))


def _continuum_jump_rpm(case, spring_mass_kg: float, lo_rpm: float, hi_rpm: float) -> float:
    m, n = case.model, 4096
    s = np.asarray(evaluate(case.motion, np.arange(n) * (2 * math.pi / n)))[0] * m.scale
    args = [float(v) for v in (m.mass, m.stiffness, m.damping, m.train_stiffness, m.train_damping, m.preload)]

    def f(w):
        return _continuum_min_force(s, *args, spring_mass_kg, 0.02, w)

    ws = np.linspace(lo_rpm, hi_rpm, 201) * RPM
    i = int(np.nonzero(np.array([f(w) for w in ws]) <= 0.0)[0][0])
    return brentq(f, ws[i - 1], ws[i], xtol=1e-9) / RPM


@pytest.mark.slow
def test_spring_model_changes_checks_jump_speed_as_an_independent_model_does():
    """lecture-fast with the spring size --buildable proposed before this issue (1.361 N/mm, 148.2 N): massless it
    jumps at 750 rpm; with the spring's mass check's jump speed is the lumped model's (a case whose follower
    carries a third of the spring's mass: the closed form) and the surge model's (a distributed mass solved
    exactly, no chain), and the JSON names the model."""
    sized = {"spring_rate": 1.361, "preload": 148.2}
    out = {
        m: run_check(_case("lecture-fast", sized, None if m == "none" else {"model": m}))
        for m in ("none", "lumped", "surge")
    }
    jump = {m: r.json()["dynamic"]["jump_speed_rpm"] for m, r in out.items()}
    assert {m: r.json()["dynamic"]["spring_model"] for m, r in out.items()} == {
        "none": "none",
        "lumped": "lumped",
        "surge": "surge",
    }
    ms = out["lumped"].json()["dynamic"]["spring_mass_kg"]
    assert (
        out["none"].json()["dynamic"]["spring_mass_kg"] is None
        and out["surge"].json()["dynamic"]["spring_mass_kg"] == ms > 0.0
    )
    # lumped: the follower 0.5 kg plus a third of the spring, no [spring] table
    third = run_check(_case("lecture-fast", sized | {"mass": 0.5 + ms / 3}))
    assert jump["lumped"] == pytest.approx(third.json()["dynamic"]["jump_speed_rpm"], abs=0.02)
    # surge: the wave equation's jump speed, and the shift from the massless spring it gives
    bare = _case("lecture-fast", sized)
    continuum = _continuum_jump_rpm(bare, ms, 600, 900)
    massless = _continuum_jump_rpm(bare, 1e-9, 600, 900)
    assert massless == pytest.approx(jump["none"], abs=0.02)
    assert jump["surge"] == pytest.approx(continuum, abs=0.2)
    assert jump["surge"] - jump["none"] == pytest.approx(continuum - massless, rel=0.02, abs=0.2)
    assert jump["lumped"] != pytest.approx(jump["none"], abs=1.0)
    # the numbers: the 142 g spring (3.35 mm wire, 14.25 coils) it proposed then jumps at 716.8 (lumped)
    # and 706.9 rpm (surge)
    spring = out["surge"].case.spring.with_mass(0.14215889, "lumped")
    w_max = 4 * 750 * RPM
    assert spring.jump_speed(bare.motion, w_max=w_max) / RPM == pytest.approx(716.84, abs=0.05)
    surge = spring.with_mass(0.14215889, "surge").jump_speed(bare.motion, w_max=w_max) / RPM
    assert surge == pytest.approx(_continuum_jump_rpm(bare, 0.14215889, 600, 800), abs=0.2)
    assert surge == pytest.approx(706.9, abs=0.2)


@pytest.mark.slow
def test_lecture_fast_buildable_passes_check_with_its_own_mass():
    """size --buildable on lecture-fast, then check of the case with that spring as written (4 digits) and its
    own mass: passes, with margin; also with the mass put on the follower by hand and with the surge model."""
    case = _case("lecture-fast")
    sz = size_spring(case, buildable=True)
    doc = sz.json()
    rate, preload = doc["spring_rate_N_per_mm"], doc["preload_N"]
    assert float(f"{rate:.4g}") == rate and float(f"{preload:.4g}") == preload  # as written
    assert doc["check"]["ok"] and doc["check"]["value"] >= 1.25 * 1.001 and doc["spring_model"] == "lumped"
    part = doc["part"]
    assert doc["spring_mass_kg"] == pytest.approx(part["mass_kg"], rel=1e-12)
    written = {"spring_rate": rate, "preload": preload}
    for spring in ({"model": "lumped"}, {"model": "surge"}):
        rep = run_check(_case("lecture-fast", written, spring))
        margin = next(c for c in rep.checks if c.name == "speed_margin")
        assert rep.verdict == "pass" and margin.value >= 1.25 * 1.001
        assert rep.json()["dynamic"]["spring_mass_kg"] == pytest.approx(
            part["mass_kg"], rel=1e-12
        )  # check weighs the same part
    by_hand = run_check(_case("lecture-fast", written | {"mass": 0.5 + part["mass_kg"] / 3}))
    assert next(c for c in by_hand.checks if c.name == "speed_margin").value >= 1.25 * 1.001
    # surge is a constraint: clear of every strong harmonic up to 750 rpm
    assert part["surge"]["surge_frequency_Hz"] >= surge_floor_hz(_harmonics(case), 750.0)
    assert not any("sits on cam harmonic" in w for w in part["warnings"])


def _harmonics(case):
    from camdyn.design.surge import cam_harmonics

    return cam_harmonics(case.motion, case.speed_rpm)


def test_surge_floor_clears_every_strong_harmonic_at_every_speed(lecture_fast_case):
    h = _harmonics(lecture_fast_case)
    floor = surge_floor_hz(h, 750.0)
    assert floor == pytest.approx(6.25 * 12.5)  # harmonic 6 is the last over 1 % of the largest on this cam
    for rpm in np.linspace(50.0, 750.0, 57):
        at = CamHarmonics(float(rpm), h.amplitudes)
        assert not any("sits on" in w for w in judge_surge(floor * 1.0001, at).warnings)
    assert any("sits on cam harmonic 6" in w for w in judge_surge(6 * 12.5, h.__class__(750.0, h.amplitudes)).warnings)


def test_surge_is_a_constraint_of_the_design():
    """With a surge floor the designer keeps only parts whose surge frequency reaches it, and says so by name
    when none does (the lightest part of a rate has the highest surge frequency, so the floor mostly moves the
    rate size --buildable chooses: lecture-fast's 52 Hz spring on harmonic 5 became a 78 Hz one)."""
    h = CamHarmonics(3000.0, np.array([0.0, 1.0, 0.5, 0.1, 0.02, 0.005]))
    floor = surge_floor_hz(h, 3000.0)
    assert floor == pytest.approx(4.25 * 50.0)  # harmonic 4 is the last over 1 % of the largest
    free = design_spring(4.28, 100.0, 8.0, harmonics=h)
    assert design_spring(4.28, 100.0, 8.0, harmonics=h, min_surge_hz=floor).spring == free.spring  # 241 Hz: clear
    assert design_spring(4.28, 200.0, 10.0, harmonics=h).spring.surge_frequency < floor
    with pytest.raises(InputError, match="surge frequency clear of the cam's strong harmonics"):
        design_spring(4.28, 200.0, 10.0, harmonics=h, min_surge_hz=floor)


@pytest.mark.parametrize("floor", [80.0, 150.0])
def test_min_preload_is_honoured(lecture_rigid_case, floor):
    """[limits] min_preload: a seat load. Above the free answer's preload the answer is the least peak force with
    F0 >= min_preload: at the least rate (a rate only adds peak force there), F0 = min_preload exactly."""
    free = size_spring(lecture_rigid_case)
    assert free.chosen.preload < floor
    case = dataclasses.replace(
        lecture_rigid_case,
        spec=lecture_rigid_case.spec.model_copy(
            update={"limits": lecture_rigid_case.spec.limits.model_copy(update={"min_preload": floor})}
        ),
    )
    sz = size_spring(case)
    assert sz.chosen.preload == pytest.approx(floor, abs=1e-9) and sz.chosen.rate == pytest.approx(0.0, abs=1e-12)
    assert sz.chosen.holds(sz.min_contact_force)
    with_rate = size_spring(case, min_rate=3.0)  # a valve spring with its rate: still the seat load
    assert with_rate.chosen.preload >= floor - 1e-9 and with_rate.chosen.rate == pytest.approx(3.0)


def test_min_preload_below_the_answer_changes_nothing(lecture_rigid_case):
    free = size_spring(lecture_rigid_case)
    limits = lecture_rigid_case.spec.limits.model_copy(update={"min_preload": 0.5 * free.chosen.preload})
    sz = size_spring(
        dataclasses.replace(lecture_rigid_case, spec=lecture_rigid_case.spec.model_copy(update={"limits": limits}))
    )
    assert (sz.chosen.rate, sz.chosen.preload) == pytest.approx(
        (free.chosen.rate, free.chosen.preload), rel=1e-9, abs=1e-9
    )


def test_min_preload_is_a_case_key(tmp_path, capsys):
    text = (ROOT / "cases" / "lecture.toml").read_text().replace("[limits]", "[limits]\nmin_preload = -3")
    case = tmp_path / "neg.toml"
    case.write_text(text)
    code, _, err = run(capsys, "size", case)
    assert code == 2 and "limits.min_preload" in err


@pytest.mark.slow  # sizes twice with the dynamic model (4-5 s)
def test_plain_size_is_a_bound_not_a_spring(capsys):
    """The lecture's least peak force is a 0.086 N/mm spring with 437 mm of preload deflection: never drawn or
    printed as the chosen spring."""
    code, out, _ = run(capsys, "size", ROOT / "cases" / "lecture.toml")
    assert code == 0
    last = " ".join(out.split())
    assert "a lower bound, not a spring" in last and "--buildable" in last and "437.6 mm of preload deflection" in last
    assert "chosen" not in out.splitlines()[2]  # the table's header says "bound"
    code, out, _ = run(capsys, "size", ROOT / "cases" / "lecture.toml", "--json")
    doc = json.loads(out)
    assert doc["bound"] is True and doc["buildable"] is False


@pytest.mark.slow
def test_plain_size_plot_draws_a_bound(lecture_case):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from camdyn.plot.springs import plot_feasible_region

    sz = size_spring(lecture_case)
    fig, ax = plt.subplots()
    plot_feasible_region(ax, sz)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(fig)
    assert not any(lab.startswith("chosen") for lab in labels) and any(lab.startswith("bound") for lab in labels)
