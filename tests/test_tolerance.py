"""camdyn tolerance: the Monte Carlo tolerance study, its schema, its distributed run."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from _helpers import run
from scipy.stats import norm

from camdyn._core.units import FFT_GRID
from camdyn.cli import main
from camdyn.design.checks import run_check
from camdyn.design.sweep import jump_map
from camdyn.design.tolerance import SCAN_GRID, tolerance_study
from camdyn.design.tolerance._study import scan_grid
from camdyn.model.case import case_from_dict

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "cases"


def _lecture(tolerances: dict | None, speed: float | None = None) -> dict:
    raw = tomllib.loads((CASES / "lecture.toml").read_text())
    if tolerances is not None:
        raw["tolerances"] = tolerances
    if speed is not None:
        raw["dynamics"]["speed"] = speed
    return raw


def _write(tmp_path: Path, raw: dict, name: str = "case.toml") -> Path:
    import tomli_w

    path = tmp_path / name
    path.write_text(tomli_w.dumps(raw))
    return path


@pytest.mark.parametrize(
    ("tolerances", "argv", "message"),
    [
        ({"sprng_rate": "5%"}, [], "tolerances.sprng_rate: unknown key"),
        ({"spring_rate": "-5%"}, [], "tolerances.spring_rate: a tolerance must be zero or positive"),
        ({"preload": -1.0}, [], "tolerances.preload: a tolerance must be zero or positive"),
        ({"profile_error": "5%"}, [], "tolerances.profile_error: a percentage needs a scale"),
        ({"preload": "2 kg"}, [], "tolerances.preload: unit 'kg' not known here"),
        ({"mass": {"value": "3%", "distribution": "triangular"}}, [], "tolerances.mass.distribution"),
        ({"spring_rate": "5%"}, ["--samples", "0"], "--samples: must be from 1"),
        ({}, [], "tolerances: the case gives no tolerances"),
        ({"distribution": "uniform"}, [], "tolerances: the case gives no tolerances"),
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, capsys, tolerances, argv, message):
    path = _write(tmp_path, _lecture(tolerances))
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and message in err, err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_units_and_distributions_resolve():
    from camdyn._core.kinds import TRANSLATING
    from camdyn.schema import CaseSpec, parse, resolve_tolerances

    spec = parse(
        CaseSpec,
        _lecture(
            {
                "preload": "0.002 kN",
                "train_stiffness": {"value": "20%", "distribution": "uniform"},
                "profile_error": "5 um",
                "distribution": "normal",
            }
        ),
    )
    tol = {t.key: t for t in resolve_tolerances(spec.tolerances, kind=TRANSLATING)}
    assert tol["preload"].value == pytest.approx(2.0) and not tol["preload"].relative
    assert (
        tol["train_stiffness"].distribution == "uniform"
        and tol["train_stiffness"].relative
        and tol["train_stiffness"].value == pytest.approx(0.2)
    )
    assert tol["profile_error"].value == pytest.approx(0.005) and tol["profile_error"].distribution == "normal"


def test_samples_do_not_depend_on_chunks():
    from camdyn.design.tolerance._sampling import Spread, draw_samples

    nominal = {
        "spring_rate": 2.0,
        "preload": 30.0,
        "mass": 0.5,
        "train_stiffness": 1000.0,
        "speed": 300.0,
        "profile_error": 0.0,
    }
    spread = {
        "spring_rate": Spread("spring_rate", 2.0, 0.2, "normal"),
        "profile_error": Spread("profile_error", 0.0, 0.005, "uniform"),
    }
    a, b = draw_samples(spread, nominal, 1000, 7), draw_samples(spread, nominal, 1000, 7)
    assert all(np.array_equal(a[k], b[k]) for k in a)
    assert np.std(a["spring_rate"]) == pytest.approx(0.2 / 3, rel=0.1)  # tolerance = 3 sigma
    rms = np.sqrt(np.mean(0.5 * np.sum(a["profile_coeffs"] ** 2, axis=1)))
    assert rms == pytest.approx(0.005, rel=0.05)  # the profile error's RMS, on average
    assert np.all(np.abs(a["profile_coeffs"]) <= np.sqrt(3) * 0.005 / np.sqrt(8) + 1e-15)  # uniform


@pytest.mark.slow
@pytest.mark.parametrize("speed", [300.0, 560.0])
def test_zero_tolerances_agree_with_check(speed):
    zeros = {k: "0%" for k in ("spring_rate", "preload", "mass", "train_stiffness", "speed")} | {"profile_error": 0.0}
    case = case_from_dict(_lecture(zeros, speed))
    result = tolerance_study(case, 16, seed=3)
    report = run_check(case)
    fails = bool(report.json()["dynamic"]["separations"])
    assert result.probability in (0.0, 1.0)
    assert result.probability == (1.0 if fails else 0.0)
    assert (speed > 500) == fails
    # the nominal jump speed agrees with check's (a 512-angle scan grid against check's 4096)
    assert result.nominal_jump_speed_rpm == pytest.approx(report.json()["dynamic"]["jump_speed_rpm"], rel=2e-4)


@pytest.mark.slow
def test_a_rigid_follower_thrown_off_by_a_velocity_step_separates_in_every_built_cam(tmp_path, capsys):
    """A constant-velocity rise between dwells on a rigid follower: the step at its end throws it off at any speed,
    in every built cam (the tolerances keep the step): P(separation) 1, jump speeds 0, and no tolerance moves the
    margin (gradients 0, shares null in --json: it failed on their NaN after writing its files)."""
    raw = _lecture({"spring_rate": "10%", "preload": "2 N"})
    raw["motion"]["segments"][1]["law"] = "constant-velocity"
    raw["dynamics"] = {k: v for k, v in raw["dynamics"].items() if not k.startswith("train_")}
    path = _write(tmp_path, raw)
    code, out, err = run(capsys, "tolerance", path, "--samples", "64", "-o", tmp_path / "out", "--json", "--quiet")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["probability_of_separation"] == 1.0 and doc["nominal_jump_speed_rpm"] == 0.0
    assert doc["jump_speed_rpm"]["p50"] == 0.0 and doc["least_contact_force_N"]["p50"] <= 0.0
    for s in doc["sensitivities"].values():
        assert s == {"gradient_sigma": 0.0, "share_linear": None, "share_monte_carlo": None}


@pytest.mark.slow
def test_a_compliant_train_struck_by_a_velocity_step_has_the_checks_jump_speed():
    """A constant-velocity rise between dwells on a compliant train: the jump speed is the train's response to the
    steps, a spike the 512-angle scan grid missed (the nominal 55.0 rpm against check's 40.33; the time domain leaves
    the cam at 45 rpm): the study searches on check's own grid there, and agrees with it."""
    zeros = {k: "0%" for k in ("spring_rate", "preload", "mass", "train_stiffness", "speed")} | {"profile_error": 0.0}
    raw = _lecture(zeros, 30.0)
    raw["motion"]["segments"][1]["law"] = "constant-velocity"
    case = case_from_dict(raw)
    assert scan_grid(case) == FFT_GRID and scan_grid(case_from_dict(_lecture(zeros, 30.0))) == SCAN_GRID
    rigid = {**raw, "dynamics": {k: v for k, v in raw["dynamics"].items() if not k.startswith("train_")}}
    assert scan_grid(case_from_dict(rigid)) == SCAN_GRID  # thrown off at the step: no search to resolve it
    want = run_check(case).json()["dynamic"]["jump_speed_rpm"]
    assert want == pytest.approx(40.33, abs=0.05)
    assert tolerance_study(case, 16, seed=3).nominal_jump_speed_rpm == pytest.approx(want, rel=2e-4)


@pytest.mark.slow
def test_spring_rate_tolerance_matches_closed_form():
    """One tolerance (spring rate, normal): the probability of separation is Phi((k_crit - k0) / sigma), k_crit
    from the jump map of ``sweep`` over spring rates at the case speed."""
    speed, k0, sigma = 481.0, 2.0, 0.2 / 3
    case = case_from_dict(_lecture({"spring_rate": "10%"}, speed))
    rates = np.linspace(k0 - 4 * sigma, k0 + 4 * sigma, 161)
    f = jump_map(case, [speed], rates, gaps=False).contact_force[0]
    i = int(np.nonzero(np.diff(np.sign(f)) != 0)[0][0])
    k_crit = rates[i] - f[i] * (rates[i + 1] - rates[i]) / (f[i + 1] - f[i])
    p_closed = norm.cdf((k_crit - k0) / sigma)
    result = tolerance_study(case, 2000, seed=1)
    lo, hi = result.confidence_interval
    assert 0.05 < p_closed < 0.95  # a test that means something
    print("closed form", p_closed, "Monte Carlo", result.probability, (lo, hi))
    assert lo <= p_closed <= hi, (p_closed, result.probability, lo, hi)
    assert set(result.sensitivities) == {"spring_rate"}
    assert result.sensitivities["spring_rate"]["share_monte_carlo"] == pytest.approx(1.0, abs=0.05)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# the one process loads the session's stored programs; the two trace their own (a stored program runs on the first of
# the devices, and with two processes the first may be the other's)
ENV_ONE = {**os.environ, "JAX_PLATFORMS": "cpu", "XLA_FLAGS": ""}
ENV = ENV_ONE | {"CAMDYN_NO_CACHE": "1"}


def _one_and_two(args: list[str], tmp_path: Path):
    """Run ``args`` as 1 process into tmp/one and as 2 processes (localhost coordinator) into tmp/two: (the one's
    stdout, the two's (stdout, stderr) per process)."""
    one = subprocess.run([*args, "-o", str(tmp_path / "one")], env=ENV_ONE, capture_output=True, text=True, timeout=300)
    assert one.returncode == 0, one.stderr
    port = _free_port()
    procs = [
        subprocess.Popen(
            [
                *args,
                "-o",
                str(tmp_path / "two"),
                "--coordinator",
                f"127.0.0.1:{port}",
                "--num-processes",
                "2",
                "--process-id",
                str(i),
            ],
            env=ENV,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for i in range(2)
    ]
    outs = [p.communicate(timeout=300) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [o[1][-2000:] for o in outs]
    return one, outs


@pytest.mark.slow
def test_two_processes_sweep_the_same_map(tmp_path):
    args = [
        sys.executable,
        "-m",
        "camdyn",
        "sweep",
        str(CASES / "lecture.toml"),
        "--speeds",
        "200:700:8",
        "--spring-rates",
        "1:3:3",
    ]
    _one_and_two(args, tmp_path)
    assert (tmp_path / "two" / "lecture-sweep.csv").read_bytes() == (
        tmp_path / "one" / "lecture-sweep.csv"
    ).read_bytes()


@pytest.mark.slow
def test_two_processes_write_the_same_csv(tmp_path):
    case = CASES / "lecture-tolerances.toml"
    args = [sys.executable, "-m", "camdyn", "tolerance", str(case), "--samples", "300", "--seed", "5", "--json"]
    one, outs = _one_and_two(args, tmp_path)
    doc = json.loads(outs[0][0])
    assert doc["processes"] == 2 and doc["devices"] == 2 and outs[1][0] == ""  # process 0 writes
    name = "lecture-tolerances-tolerance.csv"
    assert (tmp_path / "two" / name).read_bytes() == (tmp_path / "one" / name).read_bytes()
    assert json.loads(one.stdout)["probability_of_separation"] == doc["probability_of_separation"]


@pytest.mark.parametrize(
    "hits, samples", [(0, 300), (1, 300), (7, 300), (299, 300), (300, 300), (3, 10**6), (1, 100000)]
)
def test_the_exact_interval_is_scipys_clopper_pearson(hits, samples):
    """The studies' interval on a probability, beta quantiles by scipy.special (scipy.stats loads 0.5-1 s later), is
    binomtest's exact interval, which root-finds the same equations: equal to 1e-5 (its root finding's tolerance
    near zero), and each end solves its binomial tail equation to 1e-11 (binomtest's own ends: to 4e-8 at 1 in 1e5)."""
    from scipy.stats import binom, binomtest

    from camdyn.design.tolerance._interval import exact_interval

    lo, hi = exact_interval(hits, samples)
    ci = binomtest(hits, samples).proportion_ci(0.95, method="exact")
    assert lo == pytest.approx(ci.low, rel=1e-5, abs=1e-300) and hi == pytest.approx(ci.high, rel=1e-5)
    assert (lo == 0.0) == (hits == 0) and (hi == 1.0) == (hits == samples)
    if hits:
        assert abs(binom.sf(hits - 1, samples, lo) - 0.025) < 1e-11
    if hits < samples:
        assert abs(binom.cdf(hits, samples, hi) - 0.025) < 1e-11
