"""The command line: verdicts, exit codes, the JSON and CSV contracts, and one-line errors for bad input."""

import json
import re
import subprocess
import sys
from contextlib import chdir
from pathlib import Path

import numpy as np
import pytest
from _helpers import run

from camdyn.cli import main

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"


@pytest.fixture(scope="module")
def lecture_json():
    import io
    from contextlib import redirect_stdout

    buf = io.StringIO()
    with redirect_stdout(buf):
        code = main(["check", str(LECTURE), "--json"])
    return code, json.loads(buf.getvalue())


@pytest.mark.slow  # a whole check: it compiles its shooting and stores the other (25 s of compile)
def test_check_lecture_passes_with_contract_keys(lecture_json):
    code, doc = lecture_json
    assert code == 0 and doc["verdict"] == "pass" and doc["case"] == "lecture" and doc["speed_rpm"] == 300
    assert {c["name"] for c in doc["checks"]} >= {"contact_force", "speed_margin"}
    for c in doc["checks"]:
        assert set(c) >= {"name", "value", "limit", "unit", "ok"}
    assert set(doc["kinematic"]) >= {"min_contact_force_N", "min_contact_force_deg", "jump_speed_rpm"}
    dyn = doc["dynamic"]
    assert dyn["model"] == "compliant" and dyn["separations"] == []
    assert set(dyn) >= {
        "min_contact_force_N",
        "min_contact_force_deg",
        "jump_speed_rpm",
        "separations",
        "residual_vibration_mm",
    }
    # a compliant train jumps a little below the rigid (kinematic) jump speed
    assert 0.9 * doc["kinematic"]["jump_speed_rpm"] < dyn["jump_speed_rpm"] < doc["kinematic"]["jump_speed_rpm"]
    assert any("240 deg" in w for w in doc["warnings"])


@pytest.mark.slow  # a separating check: the shooting with sensitivities (12 s of compile)
def test_check_fast_case_fails_with_separation(capsys):
    code, out, _ = run(capsys, "check", ROOT / "cases" / "lecture-fast.toml", "--json")
    doc = json.loads(out)
    assert code == 1 and doc["verdict"] == "fail"
    seps = doc["dynamic"]["separations"]
    assert seps and all(set(s) >= {"start_deg", "end_deg", "max_gap_mm", "impact_speed_m_s"} for s in seps)
    assert max(s["max_gap_mm"] for s in seps) > 0.1


@pytest.mark.slow  # a whole check
def test_check_speed_override_and_text_output(capsys):
    code, out, _ = run(capsys, "check", LECTURE, "--speed", "200")
    assert code == 0 and "contact_force" in out and "PASS" in out


@pytest.mark.slow  # its contact force is the dynamic response's: compiles the shooting (9 s)
def test_table_columns_and_values(capsys, tmp_path):
    code, out, _ = run(capsys, "table", LECTURE, "--step", "10")
    assert code == 0
    lines = out.strip().splitlines()
    assert lines[0] == "theta_deg,s_mm,v_mm_per_rad,a_mm_per_rad2,j_mm_per_rad3,contact_force_N" or lines[0].startswith(
        "theta_deg,s_mm,v_mm_per_rad,a_mm_per_rad2,j_mm_per_rad3,contact_force_N"
    )
    data = np.loadtxt(lines[1:], delimiter=",")
    assert data.shape[0] == 36
    row = data[data[:, 0] == 120][0]
    assert row[1] == pytest.approx(3.910, abs=1e-3)  # lecture table: f(120) = 0.391 cm
    # kinematic force at a dwell: k s + F0 = 2 N/mm * 20 mm + 30 N
    assert data[data[:, 0] == 200][0][5] == pytest.approx(70.0, abs=1e-9)
    target = tmp_path / "t.csv"
    assert run(capsys, "table", LECTURE, "-o", target)[0] == 0
    code, _, err = run(capsys, "table", LECTURE, "-o", target)
    assert code == 2 and "--force" in err
    assert run(capsys, "table", LECTURE, "-o", target, "--force")[0] == 0
    with chdir(tmp_path):  # "-o -": standard output, as without -o (it wrote a file named "-")
        code, dash, _ = run(capsys, "table", LECTURE, "--step", "10", "-o", "-")
    assert code == 0 and dash == out and not (tmp_path / "-").exists()


def test_an_error_naming_the_case_file_names_it_once(capsys, tmp_path):
    """``-o`` the input case itself: one line that names the file once (it was printed twice)."""
    case = tmp_path / "lecture.toml"
    case.write_text(LECTURE.read_text())
    for extra in ((), ("--force",)):
        code, _, err = run(capsys, "optimize", case, "-o", case, *extra)
        assert code == 2 and err.count(str(case)) == 1 and len(err.strip().splitlines()) == 1, err


BAD = [
    ("[motion\nsegments = [", "TOML"),
    ("[dynamics]\nspeed = 300\nmas = 0.5\n", "did you mean 'mass'"),
    ("[dynamics]\nspeed = -300\n", "dynamics.speed"),
    ('[dynamics]\nspeed = "fast"\n', "dynamics.speed"),
    ("[dynamics]\nspeed = nan\n", "dynamics.speed"),
    ("[dynamics]\nspeed = 300\nmass = 0\n", "dynamics.mass"),
]

LECTURE_TEXT = LECTURE.read_text()


@pytest.mark.parametrize("text, expected", BAD)
def test_bad_input_one_line_exit_2(capsys, tmp_path, text, expected):
    case = tmp_path / "bad.toml"
    if text.startswith("[dynamics]"):
        head = LECTURE_TEXT.split("[dynamics]")[0]
        text = head + text
    case.write_text(text)
    code, out, err = run(capsys, "check", case)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and str(case) in err and expected in err and "Traceback" not in err


@pytest.mark.parametrize(
    "replace, expected",
    [
        (('{ law = "dwell",     end = 240 }', '{ law = "dwell",     end = 170 }'), "motion.segments[2].end"),
        (("preload = 30", "preload = -10"), "dynamics.preload"),
        (("end = 360, lift = -20", "end = 350, lift = -20"), "not 360"),
        (("damping_ratio = 0.05\ntrain", "damping_ratio = 0.05\ndamping = 3\ntrain"), "not both"),
        (("spring_rate = 2.0", "spring_rate = 2.0\ntorsion_rate = 3"), "dynamics.torsion_rate"),
        # limits that would pass a follower that leaves its cam: a least force below 0, a jump speed below the speed
        (("min_contact_force = 0", "min_contact_force = -50"), "limits.min_contact_force"),
        (("speed_margin = 1.25", "speed_margin = 0.5"), "limits.speed_margin"),
    ],
)
def test_bad_case_values(capsys, tmp_path, replace, expected):
    case = tmp_path / "bad.toml"
    assert replace[0] in LECTURE_TEXT
    case.write_text(LECTURE_TEXT.replace(*replace))
    code, _, err = run(capsys, "check", case)
    assert code == 2 and expected in err and len(err.strip().splitlines()) == 1


def test_missing_file_and_bad_speed(capsys):
    code, _, err = run(capsys, "check", "nope.toml")
    assert code == 2 and "nope.toml" in err
    code, _, err = run(capsys, "check", LECTURE, "--speed", "-5")
    assert code == 2 and "--speed" in err


@pytest.mark.slow  # a whole check in a fresh process
def test_console_script_fresh_process():
    proc = subprocess.run(
        [sys.executable, "-m", "camdyn", "check", str(LECTURE)], capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    assert "verdict: PASS" in proc.stdout


def test_profile_writes_dxf_and_refuses_overwrite(capsys, tmp_path):
    import ezdxf

    target = tmp_path / "cam.dxf"
    code, out, _ = run(capsys, "profile", LECTURE, "-o", target)
    assert code == 0 and target.exists() and "points" in out
    doc = ezdxf.readfile(target)
    poly = list(doc.modelspace().query("LWPOLYLINE"))[0]
    pts = np.array([p[:2] for p in poly.get_points()])
    radius = np.hypot(pts[:, 0], pts[:, 1])
    assert radius.min() == pytest.approx(40.0, abs=0.02)  # the base circle
    # in the top dwell the roller centre is at (e, sqrt(Rp^2 - e^2) + h): the contour is Rr inside that radius
    top = np.hypot(5.0, np.sqrt(50.0**2 - 5.0**2) + 20.0) - 10.0
    assert radius.max() == pytest.approx(top, abs=0.01)
    code, _, err = run(capsys, "profile", LECTURE, "-o", target)
    assert code == 2 and "--force" in err


@pytest.mark.slow
def test_oscillating_case_forces_in_newton(capsys):
    from camdyn.model.case import load_case
    from camdyn.model.geometry import lever_arm_mm

    case_path = ROOT / "cases" / "oscillating.toml"
    code, out, _ = run(capsys, "table", case_path, "--step", "30")
    assert code == 0
    header = out.splitlines()[0].split(",")
    assert header[:6] == ["theta_deg", "phi_deg", "phi1_per_rad", "phi2_per_rad2", "phi3_per_rad3", "contact_force_N"]
    data = np.loadtxt(out.splitlines()[1:], delimiter=",")
    case = load_case(case_path)
    d = case.spec.dynamics
    w = d.speed * 2 * np.pi / 60
    th = np.deg2rad(data[:, 0])
    phi, phi1, phi2, _ = case.motion.host(th)
    c = 2 * d.damping_ratio * np.sqrt(d.torsion_rate * d.inertia)
    torque = d.inertia * w**2 * phi2 + c * w * phi1 + d.torsion_rate * phi + d.preload_torque
    force = torque / (np.asarray(lever_arm_mm(case.motion, case.follower, th)) / 1000.0)
    np.testing.assert_allclose(data[:, 5], force, rtol=1e-9)
    np.testing.assert_allclose(data[:, 1], np.degrees(phi), atol=1e-9)


@pytest.mark.slow  # a whole check; test_robustness' oscillating check at 2000 rpm keeps the quick set's
def test_oscillating_case_check_passes_with_its_residual_vibration_in_rad(capsys):
    code, out, _ = run(capsys, "check", ROOT / "cases" / "oscillating.toml", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["dynamic"]["min_contact_force_N"] > 10.0 and "residual_vibration_rad" in doc["dynamic"]


@pytest.mark.slow  # four checks of a path case, each radius a new synthesis (11 s CPU of the not-slow set's 96)
def test_sharp_square_gets_the_corner_radius_that_passes(capsys, tmp_path, monkeypatch):
    import functools

    from camdyn.cli import check
    from camdyn.design.advice import corner_radius_advice

    # three checks instead of six: a bracket of a failing and a passing radius around the shipped 5 mm
    monkeypatch.setattr(check, "corner_radius_advice", functools.partial(corner_radius_advice, evaluations=3))
    text = (ROOT / "cases" / "square.toml").read_text().replace("corner_radius = 5.0", "corner_radius = 0.0")
    (tmp_path / "sharp.toml").write_text(text)
    code, out, _ = run(capsys, "check", tmp_path / "sharp.toml", "--json")
    doc = json.loads(out)
    assert code == 1 and doc["verdict"] == "fail"
    assert any("sharp corners" in w and "unbounded" in w for w in doc["warnings"])
    (tip,) = doc["advice"]
    m = re.fullmatch(
        r"sharp corners: \[path\] corner_radius = ([\d.]+) mm passes at 60 rpm \(least contact force ([\d.]+) N, "
        r".*\); ([\d.]+) mm fails",
        tip,
    )
    assert m, tip
    passes, force, fails = map(float, m.groups())
    assert fails < 5.0 < passes <= 20.0 and force >= 2.0  # the shipped 5 mm fillets pass; min_contact_force 2 N


@pytest.mark.slow  # a sweep's kernels and two profiles (4 s)
def test_only_batched_commands_reach_for_an_accelerator(capsys, tmp_path, monkeypatch):
    """``sweep`` and ``tolerance`` run on every device JAX finds (but for a valvetrain, a point at a time); every
    other command on the CPU (JAX_PLATFORMS=cpu before JAX loads: a GPU's start alone is longer than a check),
    unless the user set JAX_PLATFORMS."""
    import os

    from camdyn.cli import BATCHED_COMMANDS

    assert BATCHED_COMMANDS == {"sweep", "tolerance"}
    monkeypatch.delenv("JAX_PLATFORMS", raising=False)
    sweep = ["sweep", LECTURE, "--speeds", "200:300:2", "--spring-rates", "1:2:2", "-o", tmp_path, "--quiet"]
    assert run(capsys, *sweep)[0] == 0 and "JAX_PLATFORMS" not in os.environ
    profile = ["profile", LECTURE, "-o", tmp_path / "cam.csv", "--force"]  # the cam's contour: no dynamics to compile
    assert run(capsys, *profile)[0] == 0 and os.environ["JAX_PLATFORMS"] == "cpu"
    monkeypatch.setenv("JAX_PLATFORMS", "cuda,cpu")
    assert run(capsys, *profile)[0] == 0 and os.environ["JAX_PLATFORMS"] == "cuda,cpu"


def test_blas_runs_on_one_thread_unless_the_user_says():
    """camdyn's numpy work is small matrices, where BLAS threads only spin: a command line sets OpenBLAS to one
    thread before numpy loads (it reads the setting then), unless the user set it; a caller that loaded numpy keeps
    its own. Fresh processes (a bad option: nothing computed)."""
    import os

    code = (
        "import os, sys\nfrom camdyn.cli import main\n"
        "main(['check', 'case.toml', '--bogus']); print(os.environ.get('OPENBLAS_NUM_THREADS'), 'numpy' in sys.modules)"
    )

    def run_with(*env: tuple[str, str], before: str = "") -> list[str]:
        base = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"} | dict(env)
        out = subprocess.run([sys.executable, "-c", before + code], env=base, capture_output=True, text=True)
        return out.stdout.split()

    assert run_with() == ["1", "False"]
    assert run_with(("OPENBLAS_NUM_THREADS", "4")) == ["4", "False"]
    assert run_with(before="import numpy\n") == ["None", "True"]


@pytest.mark.slow  # two fresh Pythons loading JAX (4 s)
def test_a_cpu_run_skips_the_discovery_of_accelerator_plugins():
    """Where JAX is set to the CPU alone (JAX_PLATFORMS=cpu before it loads), the command line tells JAX its plugins
    are registered before a backend starts (it would import and initialize every one installed, for backends it never
    starts), and JAX still computes on the CPU. JAX's own setting decides, not the environment a caller changes after
    JAX loaded (a notebook calling main keeps its accelerators). Fresh processes: JAX's backends start once."""
    import os

    code = (
        "import os, jax; from jax._src import xla_bridge as xb\n"
        "from camdyn._core.backends import skip_accelerator_plugins\n"
        "os.environ['JAX_PLATFORMS'] = 'cpu'; skip_accelerator_plugins(); skipped = xb._plugins_registered\n"
        "print(skipped, jax.devices()[0].platform, float(jax.numpy.arange(4.0).sum()))"
    )

    def run_with(platforms: str) -> list[str]:
        env = os.environ | {"JAX_PLATFORMS": platforms}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        return out.stdout.split()

    assert run_with("cpu") == ["True", "cpu", "6.0"]
    assert run_with("")[0] == "False"  # JAX loaded with its default: the caller's later setting changes nothing


@pytest.mark.slow  # the two-mass model's programs
def test_a_valvetrains_map_runs_on_the_cpu(capsys, tmp_path, monkeypatch):
    """A valvetrain's ``sweep`` runs its two-mass model one point at a time: on the CPU, as every unbatched command."""
    import os

    monkeypatch.delenv("JAX_PLATFORMS", raising=False)
    valve = ["sweep", ROOT / "cases" / "valvetrain.toml", "--speeds", "2000:2500:2", "-o", tmp_path, "--quiet"]
    assert run(capsys, *valve)[0] == 0 and os.environ["JAX_PLATFORMS"] == "cpu"


@pytest.mark.slow  # a sweep's kernels (2-4 s)
def test_long_runs_say_each_phase_on_a_pipe_unless_quiet(capsys, tmp_path):
    """Where stderr is no terminal (a pipe, a log, CI), a long command still says what it is doing, one line per
    phase; --quiet silences it (issue 23)."""
    args = [
        "sweep",
        str(ROOT / "cases" / "lecture.toml"),
        "--speeds",
        "200:600:5",
        "--spring-rates",
        "1:2:2",
        "-o",
        str(tmp_path),
    ]
    code, _, err = run(capsys, *args)
    assert code == 0, err
    phases = [line for line in err.splitlines() if line.startswith("camdyn: ")]
    assert phases and all(" done in " in p or p.endswith(" ...") for p in phases), err
    assert any("steady state" in p for p in phases)
    code, _, err = run(capsys, *args, "--force", "--quiet")
    assert code == 0 and "camdyn: " not in err, err
