"""Spring sizing (camdyn size): the LP against closed forms and brute force, the dynamic correction, the CLI.

The eccentric cam s = e (1 - cos theta) (two harmonic segments), rigid and undamped, has a closed-form answer.
With R = F_min - F_ext and W the top speed, the constraints for all theta and all w in [0, W] are
``k e (1 - u) + F0 + m w^2 e u >= R`` with u = cos theta in [-1, 1]: for u >= 0 the worst speed is w = 0 and
the worst angle u = 1, so F0 >= R; for u < 0 the worst speed is W and the constraint is linear in u, so its
ends bind: u -> 0 again gives F0 >= R, and u = -1 gives 2 k e + F0 >= R + m W^2 e. The peak spring force is
P = 2 k e + F0 >= R + m W^2 e, reached along the segment F0 = R + m W^2 e - 2 k e for 0 <= k <= m W^2 / 2 (where
F0 >= R still holds). The tie-break (least preload) picks its end: k = m W^2 / 2, F0 = R, P = R + m W^2 e.
With a least rate k_lo above m W^2 / 2 the answer is k = k_lo, F0 = R (P = 2 k_lo e + R); below it, the same tie
end. The kinematic jump speed of the answer is where 2 k e + F0 + F_ext = m w^2 e (at theta = 180 deg).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import pytest

import camdyn.model  # noqa: F401  (float64)
from camdyn._core.units import RPM
from camdyn.cli import main
from camdyn.design.sizing import SpringSizing, size_spring
from camdyn.model import dynamics as dyn
from camdyn.model.case import case_from_dict
from camdyn.model.motion import evaluate
from camdyn.plot import plot_feasible_region

ROOT = Path(__file__).resolve().parents[1]
E, M, FMIN, FEXT, SPEED, MARGIN = 5.0, 0.8, 5.0, 2.0, 400.0, 1.5  # mm, kg, N, N, rpm, -
W = MARGIN * SPEED * RPM


def eccentric(**dynamics) -> dict:
    d = {"speed": SPEED, "mass": M, "spring_rate": 1.0, "preload": 10.0, "external_force": FEXT} | dynamics
    return {
        "name": "eccentric",
        "motion": {
            "segments": [
                {"law": "harmonic", "end": 180, "lift": 2 * E},
                {"law": "harmonic", "end": 360, "lift": -2 * E},
            ]
        },
        "follower": {"type": "translating-flat", "base_radius": 30},
        "dynamics": {k: v for k, v in d.items() if v is not None},
        "limits": {"min_contact_force": FMIN, "speed_margin": MARGIN},
    }


@pytest.fixture(scope="module")
def ecc() -> SpringSizing:
    return size_spring(case_from_dict(eccentric()))


def test_eccentric_closed_form(ecc):
    k_star = M * W**2 / 2  # N/m
    r = FMIN - FEXT
    peak = r + M * W**2 * E * 1e-3
    c = ecc.chosen
    assert ecc.model == "rigid" and ecc.kinematic == ecc.chosen
    assert c.rate == pytest.approx(k_star * 1e-3, rel=1e-6)  # N/mm
    assert c.preload == pytest.approx(r, rel=1e-6)
    assert c.peak_spring == pytest.approx(peak, rel=1e-6)
    assert c.least_force == pytest.approx(FMIN, rel=1e-6)  # binding: at 0 deg (w = 0) and 180 deg (w = W)
    w_jump = math.sqrt((2 * k_star * E * 1e-3 + r + FEXT) / (M * E * 1e-3))
    assert c.kinematic_jump_rpm == pytest.approx(w_jump / RPM, rel=1e-6)
    # the dynamic jump speed against the closed form and against the dynamics model on the spring as reported
    # (user units back to SI through the follower model): rigid, so it is the kinematic one
    case = case_from_dict(eccentric())
    sized = case.model.with_spring(c.rate * 1e3, c.preload)
    assert c.dynamic_jump_rpm == pytest.approx(w_jump / RPM, rel=1e-6)
    assert c.dynamic_jump_rpm == pytest.approx(dyn.dynamic_jump_speed(case.motion, sized, w_max=4 * W) / RPM, rel=1e-9)
    binding = {(round(a, 3), round(w, 3)) for a, _, w in ecc.binding}
    assert binding == {(0.0, 0.0), (180.0, round(W / RPM, 3))}
    doc = ecc.json()
    assert (
        doc["spring_rate_N_per_mm"] == c.rate
        and doc["preload_N"] == c.preload
        and doc["peak_spring_force_N"] == c.peak_spring
    )
    assert doc["jump_speed_rpm"] == pytest.approx(w_jump / RPM, rel=1e-6)
    json.dumps(doc)  # serializable


@pytest.mark.parametrize("frac", [0.25, 0.8])
def test_eccentric_least_rate(frac):
    """Inside the tie segment a least rate changes nothing; beyond its end it binds: k = k_lo, F0 = R."""
    k_lo = frac * M * W**2  # N/m
    sz = size_spring(case_from_dict(eccentric()), min_rate=k_lo * 1e-3)
    k_exp = max(k_lo, M * W**2 / 2)
    assert sz.chosen.rate == pytest.approx(k_exp * 1e-3, rel=1e-6)
    assert sz.chosen.preload == pytest.approx(FMIN - FEXT, rel=1e-6)
    assert sz.chosen.peak_spring == pytest.approx(FMIN - FEXT + 2 * k_exp * E * 1e-3, rel=1e-6)


def brute_force(raw: dict, n: int = 200001):
    """Independent of camdyn's sizing: ``(k, c) -> (least preload, full lift)`` for rate k (N/m) and damping c
    (N*s/m) on ``n`` angles, the least force over speeds in [0, W] in closed form (the vertex or the ends of
    m w^2 s'' + c w s'); N and m."""
    case = case_from_dict(raw)
    theta = np.linspace(0.0, 2 * np.pi, n)
    s, s1, s2 = (v * 1e-3 for v in np.asarray(evaluate(case.motion, jnp.asarray(theta)))[:3])
    m, fmin, w_top = (
        float(case.model.mass),
        case.limits.min_contact_force,
        case.limits.speed_margin * case.speed_rpm * RPM,
    )

    def least_preload(k, c):
        a, b = m * s2, c * s1
        with np.errstate(divide="ignore", invalid="ignore"):
            w_v = np.where((a > 0) & (b < 0), np.clip(-b / (2 * a), 0.0, w_top), 0.0)
        g = np.minimum(np.minimum(0.0, a * w_top**2 + b * w_top), a * w_v**2 + b * w_v)
        return float(np.max(fmin - g - k * s)), float(np.max(s))

    return least_preload


@pytest.mark.slow
@pytest.mark.parametrize("damping", [{"damping": 20.0}, {"damping_ratio": 0.2}])
def test_lp_and_sqrt_k_minimization_vs_brute_force(damping):
    """Lecture cam, rigid: constant damping (the LP) and damping_ratio (exact in sqrt k) against brute force on
    200001 angles: the chosen spring's peak is the brute-force peak at its rate, no rate of a scan does better,
    and its preload holds."""
    raw = tomllib_load(ROOT / "cases" / "lecture.toml")
    raw["dynamics"] = {"speed": 600.0, "mass": 0.5, "spring_rate": 2.0, "preload": 30.0} | damping
    raw["limits"] = {"min_contact_force": 10.0, "speed_margin": 1.25}
    sz = size_spring(case_from_dict(raw))
    least_preload = brute_force(raw)

    def damping_at(k):
        return damping.get("damping", 2 * damping.get("damping_ratio", 0.0) * math.sqrt(k * raw["dynamics"]["mass"]))

    def peak(k):  # N/m -> the least peak spring force (N) at that rate
        f0, s_max = least_preload(k, damping_at(k))
        return k * s_max + f0

    k = sz.chosen.rate * 1e3
    assert sz.chosen.peak_spring == pytest.approx(peak(k), rel=1e-8)
    assert least_preload(k, damping_at(k))[0] <= sz.chosen.preload + 1e-8 * sz.chosen.peak_spring
    assert min(peak(kk) for kk in np.linspace(0.0, 3 * max(k, 100.0), 151)) >= sz.chosen.peak_spring * (1 - 1e-8)
    assert sz.chosen.least_force_kinematic >= 10.0 - 1e-8  # holds between grid points too (cutting planes)


def rigid_boundary(**dynamics) -> dict:
    """Issue 13's case: a rise to full lift, a dwell there, a return and a dwell; rigid follower."""
    return {
        "name": "rigid-boundary",
        "motion": {
            "segments": [
                {"law": "harmonic", "end": 120, "lift": 15},
                {"law": "dwell", "end": 180},
                {"law": "harmonic", "end": 300, "lift": -15},
                {"law": "dwell", "end": 360},
            ]
        },
        "follower": {
            "type": "translating-roller",
            "base_radius": 45,
            "roller_radius": 12,
            "offset": 0,
            "rotation": "cw",
        },
        "dynamics": {
            "speed": 1200,
            "mass": 0.4,
            "spring_rate": 3,
            "preload": 40,
            "damping_ratio": 0.05,
            "restitution": 0.3,
        }
        | dynamics,
        "limits": {},
    }


def test_binding_at_full_lift_with_damping_that_follows_the_rate_is_no_tie():
    """Issue 13, 9: the binding angles (120 and 180 deg) are at full lift, yet with damping_ratio every rate costs
    peak force: c grows like sqrt(k) and moves the binding onto the return flank after 180 deg, where the damper
    pulls the follower off the cam. Brute force (independent) shows the rise; the answer is the least rate, 0,
    exactly, with the warning that says why (it was a rate made by the tie tolerance, 3.7e-6 N/mm). Without damping
    the same binding is a true tie, and the stiffest optimal spring is chosen as the README promises."""
    raw = rigid_boundary()
    sz = size_spring(case_from_dict(raw))
    c = sz.chosen
    assert {round(a, 3) for a, _, _ in sz.binding} == {120.0, 180.0}
    assert c.rate == 0.0 and any("least rate" in w and "no tie" in w for w in sz.warnings)
    least_preload = brute_force(raw)
    zeta, m = raw["dynamics"]["damping_ratio"], raw["dynamics"]["mass"]

    def peak(k):  # N/m -> least peak spring force (N), damping following the rate
        f0, s_max = least_preload(k, 2 * zeta * math.sqrt(k * m))
        return k * s_max + f0

    p0, p1, p10 = peak(0.0), peak(1e3), peak(1e4)
    assert c.peak_spring == pytest.approx(p0, rel=1e-8) and c.preload == pytest.approx(p0, rel=1e-8)
    assert p1 - p0 > 0.02 and p10 - p1 > 0.2  # about 0.04 N per N/mm: no tie
    undamped = size_spring(case_from_dict(rigid_boundary(damping_ratio=0.0)))
    k_end = undamped.chosen.rate * 1e3
    assert k_end > 10e3 and undamped.chosen.peak_spring == pytest.approx(p0, rel=1e-9)
    f0, s_max = least_preload(k_end, 0.0)
    assert k_end * s_max + f0 == pytest.approx(p0, rel=1e-8)  # flat: a true tie, and its stiffest end is chosen
    assert least_preload(1.01 * k_end, 0.0)[0] + 1.01 * k_end * s_max > p0 + 1e-3  # beyond it the peak rises


def tomllib_load(path: Path) -> dict:
    import tomllib

    return tomllib.loads(path.read_text())


# ---------------------------------------------------------------------------------- dynamic correction
@pytest.fixture(scope="module")
def fast(lecture_fast_case):
    return lecture_fast_case, size_spring(lecture_fast_case)


def _least_dynamic(case, sz, design, speeds_rpm):
    model = case.model.with_spring(design.rate * 1e3, design.preload)
    return np.asarray(dyn.linear_min_force(case.motion, model, jnp.asarray(np.asarray(speeds_rpm) * RPM)))


@pytest.mark.slow
def test_dynamic_correction_moves_the_kinematic_answer(fast):
    case, sz = fast
    top = sz.top_speed_rpm
    assert sz.model == "compliant" and top == pytest.approx(750.0)
    kin, cho = sz.kinematic, sz.chosen
    # the kinematic answer holds kinematically up to W (its kinematic jump speed is W) ...
    assert kin.least_force_kinematic >= -1e-6 and kin.kinematic_jump_rpm == pytest.approx(top, rel=1e-6)
    # ... but the compliant train jumps earlier: at W its least dynamic contact force is well below F_min = 0
    speeds = np.linspace(top / 16, top, 16)  # 16 speeds: the shape dynamic_jump_speed compiled already
    f_kin = _least_dynamic(case, sz, kin, speeds)[-1]
    assert f_kin < -5.0 and kin.dynamic_jump_rpm < top - 5.0
    # the corrected spring holds dynamically at W and at every speed below it
    f_cho = _least_dynamic(case, sz, cho, speeds)
    assert f_cho.min() >= -1e-6 and abs(f_cho[-1]) < 1e-3  # binding at W
    assert cho.dynamic_jump_rpm >= top - 0.1
    # the jump speeds against the dynamics model on the springs as reported (user units back to SI)
    for d in (kin, cho):
        model = case.model.with_spring(d.rate * 1e3, d.preload)
        w_dyn = dyn.dynamic_jump_speed(case.motion, model, w_max=4 * max(top, d.kinematic_jump_rpm) * RPM) / RPM
        assert d.dynamic_jump_rpm == pytest.approx(w_dyn, abs=0.1)
    assert cho.peak_spring > kin.peak_spring and cho.preload > kin.preload
    doc = sz.json()
    corr = doc["dynamic_correction"]
    assert corr["preload_N"] == pytest.approx(cho.preload - kin.preload) and corr[
        "spring_rate_N_per_mm"
    ] == pytest.approx(cho.rate - kin.rate)
    for key in (
        "spring_rate_N_per_mm",
        "preload_N",
        "peak_spring_force_N",
        "jump_speed_rpm",
        "kinematic_jump_speed_rpm",
        "dynamic_jump_speed_rpm",
        "peak_contact_force_N",
        "max_speed_rpm",
        "margin",
        "current",
        "tie_break",
        "kinematic_answer",
        "feasible_region",
        "at_current_rate",
    ):
        assert key in doc
    assert doc["current"]["holds"] is False and doc["at_current_rate"]["holds"] is True
    assert doc["at_current_rate"]["spring_rate_N_per_mm"] == 2.0


@pytest.mark.slow
def test_linear_contact_force_matches_linear_min_force(fast):
    case, _ = fast
    w = jnp.linspace(300.0 * RPM, 500.0 * RPM, 16)  # shapes compiled already: 16 (dynamic_jump_speed), 17 (sizing)
    whole = np.asarray(dyn.linear_contact_force(case.motion, case.model, jnp.append(w, 600.0 * RPM)))[:16]
    assert whole.shape == (16, 4096)
    assert np.allclose(
        whole.min(axis=1), np.asarray(dyn.linear_min_force(case.motion, case.model, w)), rtol=0, atol=1e-9
    )


@pytest.mark.slow
def test_plot_feasible_region(fast, ecc):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for sz in (fast[1], ecc):
        fig, ax = plt.subplots()
        plot_feasible_region(ax, sz)
        assert "(N/mm)" in ax.get_xlabel() and "(N)" in ax.get_ylabel()
        plt.close(fig)


# --------------------------------------------------------------------------------------- oscillating
@pytest.mark.slow
def test_oscillating_rigid_in_torsion_units():
    raw = tomllib_load(ROOT / "cases" / "oscillating.toml")
    raw["dynamics"].pop("train_torsion_rate")
    raw["limits"] = {"min_contact_force": 2.0}
    sz = size_spring(case_from_dict(raw))
    doc = sz.json()
    assert doc["follower"] == "oscillating" and doc["spring_rate_N_per_mm"] is None and doc["preload_N"] is None
    assert doc["torsion_rate_N_m_per_rad"] == sz.chosen.rate and doc["preload_torque_N_m"] == sz.chosen.preload
    assert doc["peak_spring_torque_N_m"] == pytest.approx(sz.chosen.rate * sz.s_max + sz.chosen.preload)
    # the contact force through the lever arm is F_min at the binding angle and speed, never below: recomputed
    # here from the torque balance on a finer grid, at speeds up to the top speed
    assert sz.chosen.least_force == pytest.approx(2.0, abs=1e-6)
    case = case_from_dict(raw)
    from camdyn.model.geometry import lever_arm_mm

    theta = np.linspace(0, 2 * np.pi, 20001)
    phi, phi1, phi2 = np.asarray(evaluate(case.motion, jnp.asarray(theta)))[:3]
    arm = np.asarray(lever_arm_mm(case.motion, case.follower, theta)) / 1000.0
    # the arm carries a third of its spring's mass at the spring's lever arm ([spring] model = "lumped")
    assert sz.spring_model == "lumped" and sz.spring_mass_kg > 0.0
    inertia = raw["dynamics"]["inertia"] + sz.spring_mass_kg * (raw["spring"]["lever_arm"] / 1000.0) ** 2 / 3.0
    zeta = raw["dynamics"]["damping_ratio"]
    k, t0 = sz.chosen.rate, sz.chosen.preload
    c = 2 * zeta * math.sqrt(k * inertia)
    least = min(
        np.min((inertia * w**2 * phi2 + c * w * phi1 + k * phi + t0) / arm)
        for w in np.linspace(0, sz.top_speed_rpm * RPM, 41)
    )
    assert least == pytest.approx(2.0, abs=1e-4) and least >= 2.0 - 1e-7


# ---------------------------------------------------------------------------------------------- CLI
def _write(tmp_path: Path, raw: dict) -> Path:
    def val(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + "}"
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)

    lines = [f"name = {json.dumps(raw['name'])}"]
    for table in ("motion", "follower", "dynamics", "limits"):
        lines.append(f"[{table}]")
        lines += [f"{k} = {val(v)}" for k, v in raw[table].items()]
    path = tmp_path / "case.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_cli_size_json_and_table(tmp_path, capsys):
    path = _write(tmp_path, eccentric())
    assert main(["size", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["spring_rate_N_per_mm"] == pytest.approx(M * W**2 / 2e3, rel=1e-6) and doc["margin"] == MARGIN
    assert main(["size", str(path), "--max-speed", "200", "--margin", "2"]) == 0
    out = capsys.readouterr().out
    w2 = 400 * RPM
    assert "holds up to 400 rpm" in out and f"{M * w2**2 / 2e3:.4g}" in out
    assert "tie-break" not in out and max(map(len, out.splitlines())) < 300  # the method only under --verbose
    assert main(["size", str(path), "--max-speed", "200", "--margin", "2", "--verbose"]) == 0
    assert "tie-break:" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("change", "args", "needle"),
    [
        ({"dynamics": {"mass": -1.0}}, [], "dynamics.mass"),
        ({"limits": {"min_contact_force": -1.0}}, [], "min_contact_force"),
        ({"motion": {"segments": [{"law": "dwell", "end": 360}]}}, [], "does not move"),
        ({}, ["--margin", "0"], "--margin"),
        ({}, ["--max-speed", "nan"], "--max-speed"),
        ({}, ["--min-rate", "-1"], "--min-rate"),
        ({}, ["--min-rate", "1e12"], "--min-rate"),  # past any case's spring rate
        ({}, ["--margin", "0.5"], "--margin"),  # as speed_margin: at least 1
        ({}, ["--margin", "1e9"], "--margin"),
        ({}, ["--max-speed", "1e9"], "--max-speed"),  # past any case's speed
        (  # a rigid follower leaves a cam whose velocity drops (here at 180 deg) at any speed: no spring holds it
            {
                "motion": {
                    "segments": [
                        {"law": "constant-velocity", "end": 180, "lift": 10},
                        {"law": "cycloidal", "end": 360, "lift": -10},
                    ]
                }
            },
            [],
            "no spring holds a rigid follower on this cam: its velocity steps at 180 deg",
        ),
    ],
)
def test_cli_size_bad_input(tmp_path, capsys, change, args, needle):
    raw = eccentric()
    for table, vals in change.items():
        raw[table] = (raw[table] | vals) if table != "motion" else vals
    path = _write(tmp_path, raw)
    code = main(["size", str(path), *args])
    err = capsys.readouterr().err
    assert code == 2 and needle in err and err.count("\n") == 1 and err.startswith("camdyn: ")
