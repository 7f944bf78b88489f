"""Motions fitted to data: the periodic quintic smoothing spline, lift tables and their refusals, and the
jump speeds a sampled table gives back."""

import json
import math
import tomllib
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from camdyn import case_from_dict, load_case, run_check
from camdyn.cli import main
from camdyn.model.motion import FittedMotion, evaluate, fit_motion, fit_periodic
from camdyn.model.motion._fitted import flat_runs
from camdyn.model.motion._spline import _Problem, penalty_stencil, piecewise

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"


def smooth(x):
    """A periodic test signal and its first three derivatives."""
    return np.stack(
        [
            3 * np.sin(x) + np.cos(3 * x) + 0.5 * np.sin(5 * x + 1),
            3 * np.cos(x) - 3 * np.sin(3 * x) + 2.5 * np.cos(5 * x + 1),
            -3 * np.sin(x) - 9 * np.cos(3 * x) - 12.5 * np.sin(5 * x + 1),
            -3 * np.cos(x) + 27 * np.sin(3 * x) - 62.5 * np.cos(5 * x + 1),
        ]
    )


# ------------------------------------------------------------------------------------------- the spline
def test_penalty_is_the_integral_of_the_squared_jerk():
    """c'Pc h^-5 equals integral s'''^2 by Gauss quadrature of the fitted pieces (exact for their degree)."""
    x = np.sort(np.random.default_rng(0).uniform(0, 2 * np.pi, 300))
    prob = _Problem(x, smooth(x)[0] + 0.01 * np.random.default_rng(1).standard_normal(300), 360)
    c = prob.solve(-2.0)[0]
    coef = piecewise(c)
    h = 2 * np.pi / 360
    g, w = np.polynomial.legendre.leggauss(4)
    tau = (g + 1) / 2 * h
    jerk = sum(k * (k - 1) * (k - 2) * coef[:, k, None] * tau ** (k - 3) for k in range(3, 6))
    assert prob.roughness(c) / h**5 == pytest.approx(float(np.sum(jerk**2 * w * h / 2)), rel=1e-8)
    assert penalty_stencil().sum() == pytest.approx(0.0, abs=1e-12)  # constants cost nothing


def test_the_penalty_of_a_curve_far_from_zero_is_its_jerk_not_round_off():
    """A constant (a cam's 50 mm radius) costs nothing: c'Pc from the third differences stays what it was, where
    c'(Pc) carried the constant times the round-off (1e-3 of the penalty on a cam), enough to move REML's choice of
    the smoothing from one CPU to another. So a change of the data at the last bit leaves that choice where it was."""
    x = np.sort(np.random.default_rng(0).uniform(0, 2 * np.pi, 1500))
    y = 50.0 + smooth(x)[0] + 0.002 * np.random.default_rng(1).standard_normal(1500)
    prob = _Problem(x, y, 1500)
    c = prob.solve(5.0)[0]
    h = 2 * np.pi / 1500
    g, w = np.polynomial.legendre.leggauss(4)
    tau = (g + 1) / 2 * h
    coef = piecewise(c)
    jerk = sum(k * (k - 1) * (k - 2) * coef[:, k, None] * tau ** (k - 3) for k in range(3, 6))
    assert prob.roughness(c) / h**5 == pytest.approx(float(np.sum(jerk**2 * w * h / 2)), rel=1e-6)
    assert prob.roughness(c - 50.0) == pytest.approx(prob.roughness(c), rel=1e-9)
    bumped = fit_periodic(x, y * (1.0 + 2e-16 * np.random.default_rng(2).standard_normal(1500)))
    assert bumped.lam == pytest.approx(fit_periodic(x, y).lam, rel=1e-6)


def test_banded_solve_and_log_determinant_match_dense_algebra():
    x = np.sort(np.random.default_rng(2).uniform(0, 2 * np.pi, 500))
    prob = _Problem(x, smooth(x)[0], 400)
    dense_p = np.zeros((400, 400))
    for d, v in zip(range(-5, 6), penalty_stencil(), strict=True):
        dense_p[np.arange(400), (np.arange(400) + d) % 400] = v
    a = (prob.B.T @ prob.B).toarray() + prob.scale * 10.0 * dense_p
    c, _, _, logdet = prob.solve(1.0)
    np.testing.assert_allclose(c, np.linalg.solve(a, prob.rhs), rtol=1e-10, atol=1e-12)
    assert logdet == pytest.approx(np.linalg.slogdet(a)[1], rel=1e-12)


def test_exact_uneven_data_give_exact_derivatives():
    x = np.sort(np.random.default_rng(3).uniform(0, 2 * np.pi, 900))
    fit = fit_periodic(x, smooth(x)[0])
    grid = np.linspace(0, 2 * np.pi, 2001)
    got, want = fit(grid), smooth(grid)
    for k, tol in enumerate((1e-6, 1e-5, 1e-3, 5e-2)):
        assert np.abs(got[k] - want[k]).max() < tol * np.abs(want[k]).max(), k


def test_noise_is_estimated_and_its_effect_on_the_acceleration_is_bounded():
    """REML finds the noise it was given; the Monte Carlo acceleration spread agrees with refits of fresh noise."""
    x = np.arange(720) * (2 * np.pi / 720)
    sigma = 0.01
    fits = [
        fit_periodic(x, smooth(x)[0] + sigma * np.random.default_rng(10 + k).standard_normal(720)) for k in range(6)
    ]
    for f in fits:
        assert f.sigma == pytest.approx(sigma, rel=0.12) and f.criterion == "REML"
        assert f.rms_residual == pytest.approx(sigma, rel=0.2)
    knots = fits[0].knots[:-1]
    spread = np.std([2 * f.coef[:, 2] for f in fits], axis=0).max()
    assert fits[0].accel_std == pytest.approx(spread, rel=0.5)
    assert np.abs(fits[0](knots)[2] - smooth(knots)[2]).max() < 6 * fits[0].accel_std


def test_rounding_floor_and_tolerance():
    x = np.arange(360) * (2 * np.pi / 360)
    y = np.round(smooth(x)[0], 4)
    floor = fit_periodic(x, y, sigma_floor=1e-4 / math.sqrt(12))
    assert floor.criterion == "REML, rounding floor" and floor.sigma == pytest.approx(1e-4 / math.sqrt(12))
    tight = fit_periodic(x, y, sigma_floor=1e-4 / math.sqrt(12), tolerance=2e-5)
    assert tight.criterion == "tolerance" and tight.max_residual <= 2e-5 < floor.max_residual


def test_fitted_motion_evaluates_like_its_spline_jitted_vmapped_and_in_numpy():
    x = np.arange(400) * (2 * np.pi / 400)
    motion, fit = fit_motion(np.rad2deg(x), smooth(x)[0], unit="deg", source="table", file="t.csv")
    assert isinstance(motion, FittedMotion) and motion.unit == "rad" and motion.breaks_deg == ()
    th = np.linspace(-1.0, 8.0, 77)
    want = fit.spline(th) * math.pi / 180
    np.testing.assert_allclose(np.asarray(evaluate(motion, jnp.asarray(th))), want, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(np.asarray(motion.host(th)), want, rtol=1e-12, atol=1e-14)
    slope = jax.jit(jax.vmap(jax.grad(lambda t: motion(t)[0])))  # compiled: eager autodiff compiles op by op
    np.testing.assert_allclose(np.asarray(slope(th)), want[1], rtol=1e-9, atol=1e-12)


# --------------------------------------------------------------------------------------------- tables
def _table_case(tmp_path, rows: list[str] | None, extra: str = "") -> Path:
    text = LECTURE.read_text()
    motion = text[text.index("[motion]") : text.index("[follower]")]
    (tmp_path / "case.toml").write_text(text.replace(motion, f'[motion]\ntable = "lift.csv"\n{extra}\n'))
    if rows is not None:
        (tmp_path / "lift.csv").write_text("\n".join(rows) + "\n")
    return tmp_path / "case.toml"


GOOD = ["theta_deg,lift_mm"] + [f"{a},{5 * (1 - math.cos(math.radians(a))):.4f}" for a in range(0, 360, 10)]


@pytest.mark.parametrize(
    "rows, where, text",
    [
        (GOOD[:5] + [GOOD[6], GOOD[5]] + GOOD[7:], "lift.csv line 7", "is below the previous row's 50 deg"),
        # another lift at the same angle (an exact repeat of a row is dropped)
        (GOOD[:6] + [GOOD[5] + "1"] + GOOD[6:], "lift.csv line 7", "repeats the previous row's angle"),
        (GOOD[:19], "lift.csv", "does not span one revolution: no data from 170 to 360 deg"),
        (GOOD + ["400,0"], "lift.csv line 38", "more than one revolution"),
        (GOOD[:4] + ["30,nan"] + GOOD[5:], "lift.csv line 5", "lift_mm = nan is not a finite number"),
        (GOOD[:4] + ["30,"] + GOOD[5:], "lift.csv line 5", "lift_mm is missing"),
        # a row with fields past its header (a shifted or pasted row); trailing empty ones are a spreadsheet's
        (GOOD[:4] + ["30,0.6699,oops,!!"] + GOOD[5:], "lift.csv line 5", "4 fields where the header names 2"),
        (GOOD[:8], "lift.csv", "has 7 data rows: at least 8"),
        (["theta_deg,swing_deg"] + GOOD[1:], "lift.csv line 1", "gives lift_mm, not swing_deg"),
        (GOOD[:4] + ["30,-2"] + GOOD[5:], "lift.csv line 5", "below zero by more than 1 %"),
        (None, "lift.csv", "no such file"),
    ],
)
def test_bad_tables_one_line_exit_2(capsys, tmp_path, rows, where, text):
    case = _table_case(tmp_path, rows)
    assert main(["check", str(case)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"{case}: {where}: " in err and text in err, err


def test_tolerance_that_cannot_be_met_is_refused(capsys, tmp_path):
    rows = GOOD + ["360,0.5"]  # the closing row disagrees with the first (0 mm at 0 deg) by 0.5 mm
    case = _table_case(tmp_path, rows, "tolerance = 0.001")
    assert main(["check", str(case)]) == 2
    err = capsys.readouterr().err
    assert (
        "motion.tolerance: no smooth fit comes within 0.001 mm of lift.csv: the closest departs by 0.25 mm at line"
        in err
    )


def test_noise_that_swamps_the_acceleration_is_warned(tmp_path):
    theta = np.arange(0.0, 360.0, 2.0)
    clean = 5 * (1 - np.cos(np.deg2rad(theta)))
    noisy = clean + 0.05 * np.random.default_rng(0).standard_normal(theta.size)
    for lift, warned in ((clean, False), (noisy + 0.2, True)):
        rows = ["theta_deg,lift_mm"] + [f"{t:g},{v:.5f}" for t, v in zip(theta, lift, strict=True)]
        case = load_case(_table_case(tmp_path, rows))
        text = " ".join(case.warnings)
        assert ("leaves the fitted acceleration uncertain" in text) is warned, text
        assert case.fit.spline.sigma == pytest.approx(0.05 if warned else 1e-5 / math.sqrt(12), rel=0.25)


def test_table_motion_json_exposes_the_fit(tmp_path):
    case = load_case(_table_case(tmp_path, GOOD))
    m = case.motion_json()
    assert m["source"] == "table" and set(m["fit"]) >= {"max_residual", "rms_residual", "method", "points"}
    assert m["fit"]["points"] == 36 and m["fit"]["max_residual"] < 1e-4 and m["fit"]["unit"] == "mm"
    assert load_case(LECTURE).motion_json() == {"source": "segments", "fit": None}
    np.testing.assert_allclose(case.fit.theta_deg, np.arange(0, 360, 10))
    np.testing.assert_allclose(case.fit.data - case.fit.fitted, case.fit.residual)


def test_a_tables_dwells_are_its_runs_of_one_value():
    """A table dwells where at least 3 rows over at least 5 deg have one value as written (a run through 360 deg is
    split there); a few equal rows of noise do not dwell; a program dwells in its dwell segments."""
    theta = np.arange(360.0)
    lift = np.zeros(360)
    lift[60:250] = 5.0 * np.sin(np.linspace(0.01, np.pi - 0.01, 190))
    lift[150:160] = 6.0  # a 9 deg dwell at the top
    lift[170:173] = 6.0  # 3 equal rows over 2 deg: chance
    assert flat_runs(theta, lift) == ((0.0, 59.0), (150.0, 159.0), (250.0, 360.0))
    assert flat_runs(theta[::-1], np.roll(lift, -30)[::-1]) == ((0.0, 29.0), (120.0, 129.0), (220.0, 360.0))
    assert flat_runs(theta, np.random.default_rng(0).standard_normal(360)) == ()
    motion, _ = fit_motion(theta, lift, unit="mm", source="table", file="t.csv")
    assert motion.dwells_deg == flat_runs(theta, lift)
    assert load_case(LECTURE).motion.dwells_deg == ((0.0, 90.0), (180.0, 240.0))


# ------------------------------------------------------------------ jump speeds of a sampled shipped case
def _sampled(tmp_path, step: float, noise: float) -> dict:
    case = load_case(LECTURE)
    theta = np.arange(0.0, 360.0, step)
    lift = np.asarray(case.motion.host(np.deg2rad(theta)))[0]
    lift = lift + noise * np.random.default_rng(7).standard_normal(theta.size)
    rows = ["theta_deg,lift_mm"] + [f"{t:g},{v:.4f}" for t, v in zip(theta, lift, strict=True)]
    return run_check(load_case(_table_case(tmp_path, rows))).json()


@pytest.mark.slow
@pytest.mark.parametrize("step, noise, within", [(1.0, 0.0, 0.01), (0.5, 1e-3, 0.02)])
def test_sampled_table_gives_the_jump_speeds_back(tmp_path, lecture_check_json, step, noise, within):
    """The lecture tabulated gives its jump speeds back; tabulated exactly, its dwells (rows of 0.0000 and 20.0000)
    and the residual vibration in them too (0.01127 against the segments' 0.01115 mm); with noise it has no dwell."""
    got = _sampled(tmp_path, step, noise)
    for kind in ("kinematic", "dynamic"):
        assert got[kind]["jump_speed_rpm"] == pytest.approx(lecture_check_json[kind]["jump_speed_rpm"], rel=within), (
            kind
        )
    residual, want = got["dynamic"]["residual_vibration_mm"], lecture_check_json["dynamic"]["residual_vibration_mm"]
    assert residual == (pytest.approx(want, rel=0.03) if noise == 0.0 else 0.0)
    assert got["motion"]["source"] == "table" and got["motion"]["fit"]["points"] == int(360 / step)
    json.dumps(got)  # the contract stays plain JSON


@pytest.mark.slow
@pytest.mark.parametrize("name", ["valve-lift", "measured-cam", "polynomial"])
def test_shipped_cases_pass_and_match_the_designs_they_were_made_from(shipped_check, name):
    """The data files were made from designs (the scripts beside them): the fitted cases come within a few per
    cent of those designs' jump speeds."""
    report = shipped_check(name)[1].json()
    # the valve-lift table's 0.001 mm rounding at 3000 rpm on a stiff train leaves its least force uncertain (below)
    assert report["verdict"] == "pass" and [w for w in report["warnings"] if "uncertain by up to" not in w] == []
    if name == "polynomial":
        return
    import importlib.util

    spec = importlib.util.spec_from_file_location("maker", ROOT / "cases" / f"make_{name.replace('-', '_')}.py")
    maker = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(maker)
    raw = tomllib.loads((ROOT / "cases" / f"{name}.toml").read_text())
    raw["motion"] = {"segments": maker.SEGMENTS}
    if name == "measured-cam":
        raw["follower"] = maker.FOLLOWER.model_dump(exclude_unset=True)
    design = run_check(case_from_dict(raw)).json()
    for kind in ("kinematic", "dynamic"):
        assert report[kind]["jump_speed_rpm"] == pytest.approx(design[kind]["jump_speed_rpm"], rel=0.01), kind
    noise_N = report["dynamic"]["min_contact_force_uncertainty_N"]
    if noise_N is not None:  # the stated uncertainty covers the least force of the design the data were made from
        assert abs(report["dynamic"]["min_contact_force_N"] - design["dynamic"]["min_contact_force_N"]) <= noise_N


def test_trailing_empty_fields_of_a_spreadsheet_are_no_data(tmp_path):
    """``30,0.6699,,`` (a spreadsheet's export of a wider sheet) reads as its two named fields."""
    from camdyn.model.datafiles import read_csv

    (tmp_path / "lift.csv").write_text("\n".join(GOOD[:1] + [f"{row},," for row in GOOD[1:]]) + "\n")
    got = read_csv(tmp_path / "lift.csv", "lift.csv", ("theta_deg", "lift_mm"))
    assert got.values.shape == (36, 2) and got.values[3, 0] == 30.0


def test_the_noise_on_a_fits_acceleration_is_put_against_its_peak_in_words():
    """A fit's 95 % band on s'' against its peak: none below a tenth of it; else its share, and for a lift that does
    not move (peak 0) words, not a 300-digit percentage."""
    from types import SimpleNamespace

    from camdyn.model.motion import acceleration_noise

    def fit(peak: float, std: float) -> SimpleNamespace:
        return SimpleNamespace(coef=np.array([[0.0, 0.0, peak / 2.0]]), accel_std=std)

    assert acceleration_noise(fit(1.0, 0.04)) is None  # band 0.08 < 0.1
    assert acceleration_noise(fit(1.0, 0.25)) == (0.5, "50 % of its peak", 1.0)
    assert acceleration_noise(fit(0.0, 1e-4)) == (2e-4, "over 1000 times its peak", 0.0)
