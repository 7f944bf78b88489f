"""``camdyn machine``: many cams on one shaft. Each cam's torque column is its own ``check``'s drive moved by its
phase, the shaft carries their sum, the flywheel is I = dE / (k_s w^2) of the sum, a clearance is the gap its keys
define; the machine file is validated like a case file (one line naming the file and the key)."""

from __future__ import annotations

import contextlib
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest
from _helpers import run
from scipy.integrate import cumulative_simpson

from camdyn import InputError
from camdyn._core.units import RPM
from camdyn.cli import main
from camdyn.design.checks import run_check
from camdyn.design.machine import at_machine_angles, dwell_spans, machine_angles
from camdyn.model.case import load_case
from camdyn.schema.machine import load_machine, machine_stem

CASES = Path(__file__).resolve().parents[1] / "cases"
LECTURE, OSCILLATING = CASES / "lecture.toml", CASES / "oscillating.toml"
SPEED = 420.0  # rpm: the lecture cam's speed margin falls under 1.25 here (its dynamic jump speed is about 485 rpm)
PHASES = {"a": 0.0, "b": 180.0, "oscillating": 37.25}  # 37.25: between the 0.1 deg steps (interpolated)


def write_machine(folder, body: str = "", name: str = "test machine") -> str:
    """A machine of the lecture cam twice (0 and 180 deg) and the oscillating cam, in ``folder``."""
    text = f"""name = "{name}"
speed = {SPEED}
[[cam]]
case = "{LECTURE}"
name = "a"
[[cam]]
case = "{LECTURE}"
name = "b"
phase = 180
[[cam]]
case = "{OSCILLATING}"
phase = 37.25
[[clearance]]
between = ["a", "b"]
gap = 50
closes = [1.0, 0.5]
min_gap = 3
[drive]
speed_fluctuation = 0.04
{body}"""
    path = folder / "machine.toml"
    path.write_text(text)
    return str(path)


# ---- the machine file: validated before any model is built ----


@pytest.mark.parametrize(
    ("change", "where", "message"),
    [
        (("phase = 180", "phse = 180"), "cam[1].phse", "unknown key (did you mean 'phase'?)"),
        (("speed = 420.0", "speed = -1"), "speed", "greater than 0"),
        (('name = "b"', 'name = "a"'), "cam[1].name", "is also the name of cam[0]"),
        (
            ('between = ["a", "b"]', 'between = ["a", "bb"]'),
            "clearance[0].between",
            "no cam named 'bb' (did you mean 'b'?)",
        ),
        (('between = ["a", "b"]', 'between = ["a", "a"]'), "clearance[0].between", "two different cams"),
        (("speed_fluctuation = 0.04", "speed_fluctuation = 1.5"), "drive.speed_fluctuation", "less than 1"),
        (("phase = 37.25", 'phase = "late"'), "cam[2].phase", "valid number"),
        (('between = ["a", "b"]', 'between = ["a"]'), "clearance[0].between", "expected 2 values, got 1 (['a'])"),
        (('between = ["a", "b"]', "between = []"), "clearance[0].between", "expected 2 values, got 0 ([])"),
    ],
)
def test_machine_file_errors_name_the_key(tmp_path, change, where, message):
    path = tmp_path / "m.toml"
    path.write_text(Path(write_machine(tmp_path)).read_text().replace(*change))
    with pytest.raises(InputError) as err:
        load_machine(path)
    assert err.value.where == where and message in err.value.message


def test_an_error_in_a_case_file_names_the_cam_the_file_and_the_key(tmp_path):
    (tmp_path / "bad.toml").write_text(LECTURE.read_text().replace("mass = 0.5", "mas = 0.5"))
    (tmp_path / "m.toml").write_text('speed = 100\n[[cam]]\ncase = "bad.toml"\n')
    with pytest.raises(InputError) as err:
        load_machine(tmp_path / "m.toml")
    assert str(err.value) == "cam[0].case bad.toml: dynamics.mas: unknown key (did you mean 'mass'?)"
    (tmp_path / "m.toml").write_text('speed = 100\n[[cam]]\ncase = "missing.toml"\n')
    with pytest.raises(InputError, match=r"^cam\[0\].case missing.toml: no such file$"):
        load_machine(tmp_path / "m.toml")


def test_cli_bad_input_is_one_line_and_exit_2(capsys, tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(Path(write_machine(tmp_path)).read_text().replace("phase = 180", "phse = 180"))
    code, out, err = run(capsys, "machine", path, "-o", tmp_path)
    assert code == 2 and out == ""
    assert err.strip() == f"camdyn: {path}: cam[1].phse: unknown key (did you mean 'phase'?)"
    assert not list(tmp_path.glob("*.csv"))


def test_the_name_is_data_not_a_path():
    assert machine_stem("../../etc/cartoner") == "etc-cartoner-machine"
    assert machine_stem("..") == "case-machine"


# ---- moving to machine angles, dwells ----


def test_at_machine_angles_moves_by_the_phase():
    theta = machine_angles()
    values = np.exp(-0.5 * ((theta - 140.0) / 5.0) ** 2)  # a bump at cam angle 140
    for phase, peak in ((0.0, 140.0), (250.0, 30.0), (-30.0, 110.0), (37.25, 177.25)):
        moved = at_machine_angles(theta, values, phase)
        assert abs(theta[int(np.argmax(moved))] - peak) <= 0.05 + 1e-9
        assert math.isclose(moved.sum(), values.sum(), rel_tol=1e-6)  # a shift, nothing gained or lost


def test_dwell_spans_find_dwells_and_one_through_zero():
    theta = machine_angles()
    v = np.where((theta > 30) & (theta < 150), np.sin(np.pi * (theta - 30) / 120), 0.0)
    v = v - np.where((theta > 200) & (theta < 330), np.sin(np.pi * (theta - 200) / 130), 0.0)
    assert dwell_spans(theta, v) == ((150.0, 200.0), (330.0, 30.0))
    assert dwell_spans(theta, np.zeros_like(theta)) == ((0.0, 360.0),)


# ---- the machine against each cam's own check ----


@pytest.fixture(scope="module")
def machine_run(tmp_path_factory):
    """``camdyn machine --json --report`` of the test machine: (exit code, JSON, CSV columns, output folder)."""
    folder = tmp_path_factory.mktemp("machine")
    path = write_machine(folder)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["machine", path, "-o", str(folder / "out"), "--json", "--report"])
    csv = folder / "out" / "test-machine-machine.csv"
    header = csv.read_text().splitlines()[0].split(",")
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    return code, json.loads(buf.getvalue()), {k: data[:, i] for i, k in enumerate(header)}, folder


@pytest.fixture(scope="module")
def own_checks():
    """Each cam's own ``check --speed SPEED``."""
    return {"lecture": run_check(load_case(LECTURE), SPEED), "oscillating": run_check(load_case(OSCILLATING), SPEED)}


@pytest.mark.slow
def test_each_column_peaks_where_its_check_puts_its_drive_peak_moved_by_the_phase(machine_run, own_checks):
    _, doc, cols, _ = machine_run
    assert list(cols) == ["theta_deg", "torque_a_N_m", "torque_b_N_m", "torque_oscillating_N_m", "torque_total_N_m"]
    np.testing.assert_allclose(cols["theta_deg"], np.arange(3600) * 0.1, atol=1e-9)
    for name, check in (("a", "lecture"), ("b", "lecture"), ("oscillating", "oscillating")):
        drive = own_checks[check].json()["drive"]
        col = cols[f"torque_{name}_N_m"]
        i = int(np.argmax(np.abs(col)))
        expected = (drive["peak_torque_at_deg"] + PHASES[name]) % 360.0
        assert abs(cols["theta_deg"][i] - expected) <= 0.05 + 1e-9, name
        assert math.isclose(abs(col[i]), drive["peak_torque_N_m"], rel_tol=2e-3), name
        cam = next(c for c in doc["cams"] if c["name"] == name)
        assert cam["phase_deg"] == PHASES[name] and cam["verdict"] == own_checks[check].verdict
        assert math.isclose(cam["peak_torque_N_m"], abs(col[i]), rel_tol=1e-9)
    # the lecture cam twice, half a turn apart: the shaft sees it every 180 deg
    np.testing.assert_allclose(cols["torque_a_N_m"], np.roll(cols["torque_b_N_m"], 1800), atol=1e-12)


@pytest.mark.slow
def test_the_total_is_the_sum_and_the_flywheel_the_closed_form(machine_run):
    _, doc, cols, _ = machine_run
    total = cols["torque_total_N_m"]
    np.testing.assert_allclose(
        total, cols["torque_a_N_m"] + cols["torque_b_N_m"] + cols["torque_oscillating_N_m"], atol=1e-8
    )
    drive = doc["drive"]
    i = int(np.argmax(np.abs(total)))
    assert math.isclose(drive["peak_torque_N_m"], abs(total[i]), rel_tol=1e-8) and drive[
        "peak_torque_at_deg"
    ] == pytest.approx(cols["theta_deg"][i])
    assert math.isclose(drive["rms_torque_N_m"], float(np.sqrt(np.mean(total**2))), rel_tol=1e-8)
    omega = SPEED * RPM
    assert math.isclose(drive["mean_power_W"], float(np.mean(total)) * omega, rel_tol=1e-6, abs_tol=1e-9)
    # the energy swing by Simpson's rule on the periodic torque (a second route to the trapezoids),
    # then I = dE / (k_s w^2)
    t = np.append(total, total[0]) - np.mean(total)
    energy = cumulative_simpson(t, dx=2 * np.pi / total.size, initial=0.0)
    swing = float(np.ptp(energy))
    assert math.isclose(drive["energy_swing_J"], swing, rel_tol=1e-4)
    assert math.isclose(drive["flywheel_inertia_kg_m2"], swing / (0.04 * omega**2), rel_tol=1e-4)
    assert drive["speed_fluctuation"] == 0.04


@pytest.mark.slow
def test_the_clearance_is_the_gap_its_keys_define(machine_run):
    _, doc, _, _ = machine_run
    theta_deg, values = load_case(LECTURE).motion.sample(3600)
    s = values[0]  # mm: a's lift at machine angle theta, b's half a turn later
    gap = 50.0 - 1.0 * s - 0.5 * np.roll(s, 1800)
    (found,) = doc["clearances"]
    assert found["between"] == ["a", "b"] and found["min_gap_mm"] == 3.0
    assert math.isclose(found["least_gap_mm"], float(gap.min()), rel_tol=1e-9)
    assert found["least_gap_at_deg"] == pytest.approx(theta_deg[int(np.argmin(gap))])
    assert found["ok"] is True and gap.min() > 3.0


@pytest.mark.slow
def test_a_failing_cam_fails_the_machine_exit_1(machine_run, own_checks):
    code, doc, _, _ = machine_run
    assert own_checks["lecture"].verdict == "fail"  # speed margin under 1.25 at SPEED
    assert code == 1 and doc["verdict"] == "fail" and doc["speed_rpm"] == SPEED
    assert {c["name"]: c["failed_checks"] for c in doc["cams"]}["a"] == ["speed_margin"]
    assert set(doc["drive"]) >= {
        "peak_torque_N_m",
        "peak_torque_at_deg",
        "rms_torque_N_m",
        "mean_torque_N_m",
        "mean_power_W",
        "peak_power_W",
        "energy_swing_J",
        "speed_fluctuation",
        "flywheel_inertia_kg_m2",
    }


@pytest.mark.slow
def test_nothing_is_overwritten_without_force_and_the_report_is_deterministic(machine_run, capsys):
    _, _, _, folder = machine_run
    path, out = folder / "machine.toml", folder / "out"
    names = [
        "test-machine-machine-1-summary.png",
        "test-machine-machine-2-drive.png",
        "test-machine-machine.csv",
        "test-machine-machine.pdf",
    ]
    assert sorted(p.name for p in out.iterdir()) == names
    before = {name: (out / name).read_bytes() for name in names}
    code, _, err = run(capsys, "machine", path, "-o", out)
    assert code == 2 and "exists; pass --force to overwrite it" in err
    code, text, err = run(capsys, "machine", path, "-o", out, "--force", "--report")
    assert code == 1 and "verdict: FAIL" in text and "fails: a: speed_margin" in text
    assert {
        name: (out / name).read_bytes() for name in sorted(p.name for p in out.iterdir())
    } == before  # the same bytes


def test_a_cams_line_names_the_check_nearest_its_limit():
    """Page 1 of the machine report gives each cam the passing check nearest its limit, relative to the limit (a
    groove's crossover impact or a contact stress that page would otherwise leave out); a failing check is said as
    failing, and a limit of 0 (the least contact force, said anyway) has no relative margin."""
    from camdyn.design.checks import Check
    from camdyn.report.machine import _nearest_its_limit

    angle = Check("pressure_angle", 27.5, 35.0, "deg", "<=")  # 21 % to spare
    impact = Check("crossover_impact", 0.0117, 0.1, "m/s", "<=")  # 88 %
    curvature = Check("curvature", 3.5, 1.5, "ratio", ">=")  # 133 %
    force = Check("contact_force", 0.5, 0.0, "N", ">")
    failing = Check("contact_stress", 1300.0, 1200.0, "MPa", "<=")
    assert _nearest_its_limit((impact, curvature, angle, force, failing)) is angle
    assert _nearest_its_limit((impact, curvature)) is impact
    assert _nearest_its_limit((force, failing, Check("speed_margin", None, 1.25, "x"))) is None


def test_the_sha256_a_report_names_its_files_by(tmp_path):
    """``file_sha256``: what a case report's feet, the machine report's feet and each of its cam lines print of the
    file they review (the five files behind the cartoner's pages could not be traced before); none for a case or
    machine built in memory, or a file gone."""
    import hashlib

    from camdyn.report._data import file_sha256

    path = tmp_path / "m.toml"
    path.write_bytes(b"name = 'm'\n")
    assert file_sha256(path) == hashlib.sha256(b"name = 'm'\n").hexdigest()
    assert file_sha256(None) is None and file_sha256(tmp_path / "gone.toml") is None and file_sha256(tmp_path) is None
