"""A valvetrain's valve spring as a part (``[spring]`` with ``[valvetrain]``, issue 24): designed for the valve's
stroke, a third of its mass on the valve, and coil bind, a stop the valve's flight must stay short of.

Checked against independent routes: the spring's travel to solid from its solid force and rate; a stiff, lash-free
train with the spring's third on the valve floats at the hand-written equivalent follower's jump speed (mass
m_cam + (m_valve + m_s / 3) r^2); a flight past float that reaches solid fails ``coil_bind`` by what it overshoots.
"""

import copy
import math

import numpy as np
import pytest
from test_valvetrain import EVENT, F0, M_CAM, M_VALVE, SHIPPED, C, K, R

from camdyn._core.units import RPM
from camdyn.design.parts import resolve_spring
from camdyn.design.spring import design_case_spring
from camdyn.design.valvetrain import ValvetrainResult
from camdyn.model.case import case_from_dict
from camdyn.model.dynamics import float_speed, kinematic_jump_speed, valvetrain_response
from camdyn.model.surge import chain_steady_force

SPRING = {"material": "chrome-silicon"}


def _shipped_with_spring(**spring):
    raw = copy.deepcopy(SHIPPED)
    raw["spring"] = SPRING | spring
    raw["valvetrain"]["valve_mass"] = 0.055  # the valve, retainer and keepers: camdyn adds the spring's third
    return case_from_dict(raw)


def test_the_valve_spring_is_designed_for_the_valves_stroke():
    """At the valve: the case's 40 N/mm and 300 N with the valve closed, over the valve's stroke on a rigid train
    (1.6 x 6.375 mm - 0.2 mm lash = 10 mm); its travel from installed to solid is (solid force - preload) / rate."""
    case = _shipped_with_spring()
    part = design_case_spring(case)
    assert part.spring.rate == pytest.approx(40.0, rel=1e-9) and part.preload == pytest.approx(300.0)
    assert part.lift == pytest.approx(1.6 * 6.375 - 0.2, rel=1e-9)
    resolved = resolve_spring(case)
    travel = (part.spring.solid_force - 300.0) / 40.0
    assert resolved.spring.travel_to_solid_mm == pytest.approx(travel, rel=1e-9)
    assert travel >= 1.15 * part.lift  # Shigley's clash allowance, at least


def test_a_third_of_the_spring_moves_with_the_valve():
    case = _shipped_with_spring()
    resolved = resolve_spring(case)
    m_s = resolved.spring.mass_kg
    assert 0.0 < m_s and resolved.spring.model == "lumped"
    assert float(resolved.valvetrain.valve_mass) == pytest.approx(0.055 + m_s / 3.0, rel=1e-12)
    # the equivalent follower: m_cam + m_valve r^2 with the spring's third on the valve; its damping keeps its ratio
    assert float(resolved.model.mass) == pytest.approx(0.12 + (0.055 + m_s / 3.0) * 1.6**2, rel=1e-12)
    assert float(resolved.model.mass) == pytest.approx(float(resolved.spring.follower().mass), rel=1e-12)
    assert float(resolved.model.damping) == pytest.approx(float(resolved.spring.follower().damping), rel=1e-12)


@pytest.mark.slow
def test_surge_on_the_valve_side_is_the_chain_of_the_equivalent_follower():
    """[spring] model = "surge": the coils a chain of masses on the valve. A rigid cam contact and train without lash
    carry the valve with the cam, so the cam's force is that of the single follower m_cam + m_valve r^2 with the
    chain of mass m_s r^2 and rate k r^2 at the follower, whose periodic orbit the frequency domain solves exactly
    (camdyn.model.surge, written apart): they agree to the transient the march from rest leaves (3 revolutions,
    0.18 N of 853 N at 1500 rpm), where the lumped third is 7 N off."""
    dyn = {"speed": 3000, "spring_rate": K, "preload": F0, "damping": C, "restitution": 0.0}
    vt = {"ratio": R, "lash": 0.0, "cam_side_mass": M_CAM, "valve_mass": M_VALVE, "tappet_force": 10.0}
    raw = copy.deepcopy(EVENT) | {"dynamics": dyn, "valvetrain": vt, "spring": SPRING | {"model": "surge"}}
    case = resolve_spring(case_from_dict(raw))
    m_s = case.spring.mass_kg
    coils = case.valvetrain.coils
    assert coils.count == 16 and float(coils.lump_mass) == pytest.approx(m_s / 16, rel=1e-12)
    assert float(case.valvetrain.valve_mass) == pytest.approx(M_VALVE + m_s / 32, rel=1e-12)
    single_dyn = {"speed": 3000, "mass": M_CAM + M_VALVE * R**2, "spring_rate": K * R**2, "preload": F0 * R}
    single_dyn |= {"damping": C * R**2, "restitution": 0.0, "external_force": 10.0}
    single = case_from_dict(copy.deepcopy(EVENT) | {"dynamics": single_dyn})
    omega = 1500 * RPM
    resp = valvetrain_response(case.motion, case.valvetrain, omega)
    chain, _, _ = chain_steady_force(single.motion, single.model, m_s * R**2, omega, n=len(resp.theta_deg))
    lifted = resp.valve_lift > 0.1
    assert not resp.floated and chain.min() > 0.0
    assert resp.cam_force[lifted] == pytest.approx(chain[lifted], abs=0.5)
    lumped = resolve_spring(case_from_dict(raw | {"spring": SPRING}))
    off = valvetrain_response(lumped.motion, lumped.valvetrain, omega).cam_force - chain
    assert np.max(np.abs(off[lifted])) > 10 * 0.5  # 7 N


@pytest.mark.slow
def test_stiff_train_with_its_springs_third_floats_at_the_equivalent_followers_jump_speed():
    """A stiff, lash-free train with a [spring] part on a rigid cam contact floats where the single follower of mass
    m_cam + (m_valve + m_s / 3) r^2, rate k r^2 and preload F0 r, written out by hand, jumps (closed form)."""
    dyn = {"speed": 3000, "spring_rate": K, "preload": F0, "damping": C, "restitution": 0.0}
    vt = {"ratio": R, "lash": 0.0, "cam_side_mass": M_CAM, "valve_mass": M_VALVE, "stiffness": 1e6}
    case = resolve_spring(case_from_dict(copy.deepcopy(EVENT) | {"dynamics": dyn, "valvetrain": vt, "spring": SPRING}))
    m_s = case.spring.mass_kg
    single_dyn = {"speed": 3000, "mass": M_CAM + (M_VALVE + m_s / 3.0) * R**2, "spring_rate": K * R**2}
    single_dyn |= {"preload": F0 * R, "damping": C * R**2, "restitution": 0.0}
    single = case_from_dict(copy.deepcopy(EVENT) | {"dynamics": single_dyn})
    w_jump = kinematic_jump_speed(single.motion, single.model)[0]
    w_bare = kinematic_jump_speed(single.motion, case.spring.bare)[0]
    assert w_bare / w_jump - 1.0 > 0.02  # the spring's third matters here
    w_float = float_speed(case.motion, case.valvetrain, 1.5 * w_jump, width_rpm=0.5)
    assert w_float / RPM == pytest.approx(w_jump / RPM, rel=2e-3)


@pytest.mark.slow
def test_check_reports_coil_bind_and_fails_a_flight_to_solid():
    """At the case speed the valve stops 2.7 mm short of solid (check --json, coil_bind passes); at 10000 rpm, far
    past float, it flies 18.3 mm and would compress the spring to solid: coil_bind fails by the overshoot."""
    from camdyn.design.checks import run_check

    case = resolve_spring(_shipped_with_spring())
    travel = case.spring.travel_to_solid_mm
    report = run_check(case)
    vt = report.json()["valvetrain"]
    assert vt["coil_bind_lift_mm"] == pytest.approx(travel, rel=1e-12)
    assert vt["coil_bind_clearance_mm"] == pytest.approx(travel - vt["max_valve_lift_mm"], rel=1e-12)
    assert 2.0 < vt["coil_bind_clearance_mm"] < travel - 9.5
    checks = {c["name"]: c for c in report.json()["checks"]}
    assert checks["coil_bind"]["ok"] and checks["coil_bind"]["value"] == vt["coil_bind_clearance_mm"]
    from types import SimpleNamespace

    from camdyn.report.pages._facts import key_results

    rows = dict(key_results(SimpleNamespace(check=report, case=case)))
    assert rows["coil-bind clearance"] == f"{vt['coil_bind_clearance_mm']:.3g} mm"  # page 1 gives it
    fast = valvetrain_response(case.motion, case.valvetrain, 10000 * RPM)
    assert fast.floated and fast.max_valve_lift_mm > travel + 3.0
    flight = ValvetrainResult(1.6, 0.2, fast, math.inf, math.inf, 10000.0 * 4, coil_bind_lift_mm=travel)
    coil = {c.name: c for c in flight.checks(0.5)}["coil_bind"]
    assert not coil.ok and coil.value == pytest.approx(travel - fast.max_valve_lift_mm, rel=1e-12) and coil.value < 0


@pytest.mark.slow  # a whole check of the two-mass model
def test_a_valvetrains_check_judges_its_float_speed_without_its_equivalent_followers_jump(monkeypatch):
    """``check`` judges a valvetrain's speed margin on its float speed; the equivalent follower's dynamic jump speed,
    which no verdict reads, is not searched (with the spring's surge chain it was 5 s of an 8 s check)."""
    from camdyn.design.checks import run_check
    from camdyn.model.surge import SpringInDynamics

    def refuse(*args, **kwargs):
        raise AssertionError("the equivalent follower's jump speed was searched")

    monkeypatch.setattr(SpringInDynamics, "jump_speed", refuse)
    report = run_check(_shipped_with_spring())
    assert report.valvetrain is not None and math.isfinite(report.valvetrain.float_speed_rpm)
    assert report.dynamic.jump_speed_rpm == report.valvetrain.float_speed_rpm
    margin = {c.name: c for c in report.checks}["speed_margin"]
    assert margin.value == pytest.approx(report.valvetrain.float_speed_rpm / 3000.0, rel=1e-12)


def test_a_rebuilt_valvetrain_keeps_its_springs_mass():
    """Sweep and tolerance rebuild the two-mass model per point (with_valvetrain_keys): a resolved case keeps the
    case's spring on the valve there, its lumped third (and its surge chain), as check carries it."""
    from camdyn.model.case import with_valvetrain_keys

    case = resolve_spring(_shipped_with_spring())
    m_s = case.spring.mass_kg
    again = with_valvetrain_keys(case, dynamics={"spring_rate": 40.0})
    assert float(again.valvetrain.valve_mass) == pytest.approx(0.055 + m_s / 3.0, rel=1e-12)
    assert float(again.model.mass) == pytest.approx(float(case.model.mass), rel=1e-12)
    stiffer = with_valvetrain_keys(case, dynamics={"spring_rate": 50.0})
    assert float(stiffer.valvetrain.spring_rate) == pytest.approx(50e3, rel=1e-12)
    assert float(stiffer.valvetrain.valve_mass) == pytest.approx(0.055 + m_s / 3.0, rel=1e-12)
    surge = resolve_spring(_shipped_with_spring(model="surge"))
    rebuilt = with_valvetrain_keys(surge, valvetrain={"lash": 0.2}).valvetrain
    assert rebuilt.coils is not None and rebuilt.coils.count == surge.valvetrain.coils.count
    assert float(rebuilt.valve_mass) == pytest.approx(float(surge.valvetrain.valve_mass), rel=1e-12)


@pytest.mark.slow
def test_size_with_a_spring_part_proposes_the_part_check_designs(capsys, tmp_path):
    """size on the shipped valvetrain with a [spring] part: the preload is sized with the mass of the part designed
    for it (a fixed point, from the case's own part's mass), the part is reported, and the proposal written into
    the case file passes check with that very part; 2 % less preload, the part's mass on the valve, does not hold
    at margin x speed."""
    import json
    import re

    import tomli_w
    from _helpers import run

    from camdyn.design.valvetrain import analyze_valvetrain
    from camdyn.model.case import load_case, with_valvetrain_keys

    raw = copy.deepcopy(SHIPPED) | {"spring": SPRING}
    raw["valvetrain"]["valve_mass"] = 0.055
    path = tmp_path / "vs.toml"
    path.write_text(tomli_w.dumps(raw))
    code, out, err = run(capsys, "size", path, "--json")
    assert code == 0, err
    doc = json.loads(out)
    top = doc["sized_to_rpm"]
    assert doc["holds"] and doc["valvetrain"]["check"]["verdict"] == "pass" and doc["spring_model"] == "lumped"
    part, rounds = doc["part"], doc["part_rounds"]
    assert part["rate_N_per_mm"] == pytest.approx(40.0) and part["preload_N"] == pytest.approx(doc["preload_N"])
    assert doc["spring_mass_kg"] == pytest.approx(part["mass_kg"], rel=1e-12)
    # the first round's mass is the case's own part's (300 N); the last round's preload is the proposal, sized with
    # a mass whose part moves it by less than 0.1 %
    assert rounds[0]["spring_mass_kg"] == pytest.approx(design_case_spring(load_case(path)).spring.mass, rel=1e-12)
    assert rounds[-1]["preload_N"] == doc["preload_N"] and len(rounds) >= 2
    exact = rounds[-1]["spring_mass_kg"] == pytest.approx(part["mass_kg"], rel=1e-12)
    assert exact or abs(rounds[-1]["preload_N"] - rounds[-2]["preload_N"]) <= 1e-3 * doc["preload_N"]
    # the part's mass matters: the case's own (heavier, 300 N) part's third on the valve asked for more preload
    assert rounds[0]["spring_mass_kg"] > 1.1 * part["mass_kg"] and rounds[0]["preload_N"] > doc["preload_N"]
    text = re.sub(r"^preload = .*$", f"preload = {doc['preload_N']!r}", path.read_text(), flags=re.M)
    (tmp_path / "proposed.toml").write_text(text)
    code, out, err = run(capsys, "check", tmp_path / "proposed.toml", "--json")
    chk = json.loads(out)
    assert code == 0 and chk["verdict"] == "pass", err
    assert chk["dynamic"]["spring_mass_kg"] == pytest.approx(part["mass_kg"], rel=1e-12)  # check's part is size's
    vt = chk["valvetrain"]
    assert vt["float_speed_rpm"] >= top and vt["bounce_speed_rpm"] >= top and vt["coil_bind_clearance_mm"] > 0
    # the least preload: 2 % less, with the proposed part's mass, is tossed off the train at the top speed, or
    # floats or bounces below it
    written = resolve_spring(load_case(tmp_path / "proposed.toml"))
    assert written.spring.mass_kg == pytest.approx(part["mass_kg"], rel=1e-12)
    less = with_valvetrain_keys(written, dynamics={"preload": 0.98 * doc["preload_N"]})
    resp = valvetrain_response(less.motion, less.valvetrain, top * RPM)
    tossed = resp.train_force[resp.in_event].min() <= 1e-3 * doc["peak_spring_force_N"]
    res = analyze_valvetrain(less, 3000 * RPM, 1.25)
    assert tossed or min(res.float_speed_rpm, res.bounce_speed_rpm) < top


@pytest.mark.slow
def test_sweep_carries_the_spring_and_bounds_the_gap_by_coil_bind():
    """At 3000 rpm the map's point is check's (the spring's third on the valve): its seating velocity and its
    coil-bind clearance (travel to solid less the valve's largest lift); at 10000 rpm the flight would pass solid
    (clearance negative by the overshoot) and the gap is counted to solid, not beyond."""
    from camdyn.design.sweep import jump_map

    case = resolve_spring(_shipped_with_spring())
    travel = case.spring.travel_to_solid_mm
    jm = jump_map(_shipped_with_spring(), [3000.0, 10000.0])
    slow = valvetrain_response(case.motion, case.valvetrain, 3000 * RPM)
    fast = valvetrain_response(case.motion, case.valvetrain, 10000 * RPM)
    clearance = jm.valve.coil_bind_clearance[:, 0]
    assert clearance[0] == pytest.approx(travel - slow.max_valve_lift_mm, rel=1e-9) and clearance[0] > 2.0
    # the map's point on the valvetrain's fast path (every contact closed at 3000 rpm): the same to 1e-9
    assert jm.valve.seating_velocity[0, 0] == pytest.approx(slow.seating_velocity, rel=1e-9)
    assert clearance[1] == pytest.approx(travel - fast.max_valve_lift_mm, rel=1e-9) and clearance[1] < -3.0
    free = fast.max_gap_mm(case.valvetrain)
    assert free > travel and jm.max_gap[1, 0] <= travel and jm.max_gap[1, 0] > 0.8 * travel
    assert any("valve spring" in n and "lumped third" in n for n in jm.notes)
    assert any(n.startswith("coil bind") for n in jm.notes)
    rows = jm.csv.splitlines()
    assert rows[0].endswith(",coil_bind_clearance_mm")
    assert float(rows[1].split(",")[-1]) == pytest.approx(clearance[0], rel=1e-9)


@pytest.mark.slow
def test_tolerance_carries_the_springs_third_as_a_hand_written_valve_mass_would():
    """The study's nominal float speed is that of the case without [spring] and a third of the spring's mass
    written into valvetrain.valve_mass (the route the refusal used to ask for): the same model, the same search."""
    from camdyn.design.tolerance import valvetrain_tolerance_study
    from camdyn.design.valvetrain import analyze_valvetrain

    raw = copy.deepcopy(SHIPPED) | {"spring": SPRING, "tolerances": {"preload": "1 N"}}
    raw["valvetrain"]["valve_mass"] = 0.055
    case = case_from_dict(raw)
    m_s = resolve_spring(case).spring.mass_kg
    by_hand = copy.deepcopy(SHIPPED)
    by_hand["valvetrain"]["valve_mass"] = 0.055 + m_s / 3.0
    hand = analyze_valvetrain(case_from_dict(by_hand), 3000 * RPM, 1.25)
    study = valvetrain_tolerance_study(case, 1)
    assert study.nominal_float_speed_rpm == pytest.approx(hand.float_speed_rpm, rel=1e-9)
    assert study.nominal_bounce_speed_rpm == pytest.approx(hand.bounce_speed_rpm, rel=1e-9)
    assert study.float_speed_rpm[0] == pytest.approx(hand.float_speed_rpm, rel=0.02)
    assert any("lumped third in every sample" in n for n in study.notes)


def _sizing(preload: float):
    """A stand-in for a preload search's answer proposing ``preload`` (N) at 40 N/mm."""
    from camdyn.design.sizing._valvetrain import ValveSpringDesign, ValveSpringSizing

    design = ValveSpringDesign(40.0, preload, 400.0 + preload, 5000.0, 6000.0, 9000.0, 0.3, 0.002, 300.0, 100.0)
    numbers = ("v", 3000.0, 1.25, 3750.0, 40.0, 1.6, 0.2, 0.27, 10.0)
    return ValveSpringSizing(*numbers, design, 4000.0, design, design, (), ())


def test_a_part_mass_that_cycles_ends_on_a_search_that_carried_its_parts_mass(monkeypatch):
    """The parts come in wire sizes and coil counts, so the fixed point on a [spring] part's mass may not exist: a
    search with 96.05 g asks for 110.8 N, whose part weighs 97.34 g; a search with 97.34 g asks for 108.1 N, whose
    part weighs 96.05 g (a surge chain's valvetrain did so). The loop stops at the cycle (no rounds to its budget),
    proposes the search that carried at least its own part's mass (a lighter part floats and bounces later), and
    reports the part designed for that proposal, its preload the proposal's. (The heaviest search of a cycle always
    carried at least its part's mass: its part's mass is another of the cycle's.)"""
    import types

    import camdyn.design.sizing._valvetrain as vs

    part_mass = {100.1: 0.09605, 110.8: 0.09734, 108.1: 0.09605}  # kg, of the part designed for each preload
    preload_for = {0.1252: 100.1, 0.09605: 110.8, 0.09734: 108.1}  # N, of the search with each mass
    searched: list[float] = []

    def design(case, *, rate, preload):
        return types.SimpleNamespace(spring=types.SimpleNamespace(mass=part_mass[preload]), preload=preload)

    def size(case, min_rate):
        mass = case.spring.mass_kg if isinstance(case, types.SimpleNamespace) else case[1]
        searched.append(mass)
        return _sizing(preload_for[mass])

    own = types.SimpleNamespace(spring=types.SimpleNamespace(mass_kg=0.1252))
    spec = types.SimpleNamespace(spring=types.SimpleNamespace(model="surge"))
    monkeypatch.setattr(vs, "resolve_spring", lambda case: own)
    monkeypatch.setattr(vs, "design_case_spring", design)
    monkeypatch.setattr(vs, "with_spring_part", lambda case, part: ("sized with", part.spring.mass))
    monkeypatch.setattr(vs, "_size", size)
    sizing = vs._size_with_part(types.SimpleNamespace(spec=spec), 40.0)
    assert searched == [0.1252, 0.09605, 0.09734]  # the cycle closed: 96.05 g is not searched again
    assert sizing.chosen.preload == 108.1 and sizing.part.preload == 108.1 and sizing.spring_mass_kg == 0.09605
    assert sizing.part_rounds[-1] == (0.09734, 108.1)
    assert any("cycles between 96.05 g and 97.34 g" in w and "sized with 97.34 g" in w for w in sizing.warnings)
