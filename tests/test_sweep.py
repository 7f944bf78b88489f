"""Jump maps (camdyn sweep): the CSV contract, agreement with the dynamics models, sharding, the command line."""

import csv
import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _helpers import RIGID_BOUNDARY

from camdyn._core.errors import InputError, NumericalError
from camdyn._core.units import RPM
from camdyn.cli import main
from camdyn.design.sweep import CSV_COLUMNS, MAX_GRID_POINTS, jump_map
from camdyn.model import dynamics as dyn
from camdyn.model.case import load_case
from camdyn.model.dynamics import _compliant
from camdyn.model.motion import evaluate

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"


@pytest.fixture(scope="module")
def lecture(lecture_case):
    return lecture_case


@pytest.fixture(scope="module")
def small_map(lecture):
    # 300 rpm stays on the cam at every rate; 520 rpm at 2 N/mm separates with a periodic bounce
    return jump_map(lecture, [300.0, 520.0, 650.0], [1.0, 2.0])


def _model_with_rate(case, rate_n_per_mm):
    """The case's follower with another spring rate (preload fixed; damping from the damping ratio, written out
    here: an independent route to what the map does)."""
    k = rate_n_per_mm * 1e3
    c = 2.0 * case.spec.dynamics.damping_ratio * np.sqrt(k * float(case.model.mass))
    return eqx.tree_at(lambda m: (m.stiffness, m.damping), case.model, (jnp.asarray(float(k)), jnp.asarray(float(c))))


def _rows(csv_text: str) -> tuple[list[str], list[dict[str, str]]]:
    reader = csv.DictReader(io.StringIO(csv_text))
    return list(reader.fieldnames), list(reader)


@pytest.mark.slow  # the map's gap stepping compiles for 3 s
def test_csv_columns_and_rows(small_map):
    header, rows = _rows(small_map.csv)
    assert tuple(header) == CSV_COLUMNS
    # the contract only ever grows, at the end: the first five columns are those of every earlier release
    assert ",".join(header).startswith("speed_rpm,spring_rate_N_per_mm,min_contact_force_N,separated,max_gap_mm,")
    assert len(rows) == 6
    assert [float(r["speed_rpm"]) for r in rows] == [300, 300, 520, 520, 650, 650]
    assert [float(r["spring_rate_N_per_mm"]) for r in rows] == [1, 2] * 3
    assert all(r["spring_rate_N_m_per_rad"] == "" for r in rows)  # a translating follower has no torsion rate
    assert all(r["status"] == "ok" for r in rows)
    sep = np.array([r["separated"] for r in rows]) == "1"
    assert {r["separated"] for r in rows} <= {"0", "1"}
    force, gap = (np.array([float(r[c]) for r in rows]) for c in ("min_contact_force_N", "max_gap_mm"))
    assert np.all(force[sep] == 0.0) and np.all(force[~sep] > 0.0)  # least force 0 where it separates
    assert np.all(gap[sep] > 0.0) and np.all(gap[~sep] == 0.0)


@pytest.mark.slow
def test_map_without_gaps(lecture, small_map, lecture_rigid_case):
    """gaps=False (the report's jump map): the same least force and separation, no gap integration (NaN)."""
    jm = jump_map(lecture, small_map.speeds_rpm, small_map.spring_rates, gaps=False)
    np.testing.assert_array_equal(jm.separated, small_map.separated)
    np.testing.assert_allclose(jm.min_force, small_map.min_force, rtol=0, atol=1e-12)
    np.testing.assert_allclose(jm.contact_force, small_map.contact_force, rtol=0, atol=1e-12)
    assert (
        small_map.separated.any()
        and np.all(np.isnan(jm.max_gap[jm.separated]))
        and np.all(jm.max_gap[~jm.separated] == 0.0)
    )
    assert any("gaps not computed" in n for n in jm.notes)
    # a rigid follower: no flights are integrated either
    jr = jump_map(lecture_rigid_case, [100.0, 700.0], [1.0], gaps=False)
    assert jr.model == "rigid" and list(jr.separated[:, 0]) == [False, True] and np.isnan(jr.max_gap[1, 0])


@pytest.mark.slow
def test_separation_agrees_with_dynamics(lecture, lecture_fast_case):
    fast = lecture_fast_case
    jm_fast = jump_map(fast, [600.0])  # the case's own spring rate
    jm_slow = jump_map(lecture, [300.0])
    assert jm_fast.separated[0, 0] and jm_fast.min_force[0, 0] == 0.0 and jm_fast.max_gap[0, 0] > 0.1
    assert not jm_slow.separated[0, 0] and jm_slow.max_gap[0, 0] == 0.0
    # the boundary at the case's spring rate is the dynamic jump speed
    w_jump = dyn.dynamic_jump_speed(lecture.motion, lecture.model, w_max=2000 * RPM) / RPM
    jm = jump_map(lecture, [w_jump - 1.0, w_jump + 1.0])
    assert list(jm.separated[:, 0]) == [False, True]


@pytest.mark.slow
def test_steady_state_vs_diffrax(lecture, small_map):
    """The map's frequency-domain steady state against the diffrax time-domain shooting (compliant_response)."""
    for i, j in ((0, 0), (0, 1)):
        rpm, rate = small_map.speeds_rpm[i], small_map.spring_rates[j]
        resp = dyn.compliant_response(lecture.motion, _model_with_rate(lecture, rate), rpm * RPM)
        assert not resp.separations and not small_map.separated[i, j]
        assert small_map.min_force[i, j] == pytest.approx(resp.min_force, abs=0.01)
    # a third point, near the jump boundary
    jm = jump_map(lecture, [480.0])
    resp = dyn.compliant_response(lecture.motion, lecture.model, 480.0 * RPM)
    assert 0.0 < resp.min_force < 2.0 and jm.min_force[0, 0] == pytest.approx(resp.min_force, abs=0.01)


@pytest.mark.slow  # compiles the shooting with sensitivities
def test_gap_vs_diffrax_shooting(lecture, small_map):
    """A periodic bounce (520 rpm, 2 N/mm): the map's largest gap against the diffrax periodic orbit."""
    resp = dyn.compliant_response(lecture.motion, lecture.model, 520.0 * RPM)
    # periodic by camdyn's own measure (1e-6 of the 20 mm lift): the shooting stops at the first revolution within it
    assert resp.separations and resp.periodicity_error <= _compliant.periodic_tol(resp.s)
    gap = max(s.max_gap for s in resp.separations)
    assert small_map.separated[1, 1] and small_map.max_gap[1, 1] == pytest.approx(gap, abs=1e-3)


@pytest.mark.slow
def test_rigid_map_agrees_with_kinematics_and_flight(lecture_rigid_case):
    rigid = lecture_rigid_case
    w_kin = dyn.kinematic_jump_speed(rigid.motion, rigid.model)[0] / RPM
    jm = jump_map(rigid, [w_kin - 1.0, 600.0])
    assert jm.model == "rigid" and list(jm.separated[:, 0]) == [False, True]
    resp = dyn.rigid_response(rigid.motion, rigid.model, 600.0 * RPM)
    assert jm.max_gap[1, 0] == pytest.approx(max(s.max_gap for s in resp.separations), rel=1e-6)


@pytest.mark.slow
def test_oscillating_forces_in_newton():
    from camdyn.design.checks import forces_in_newton as _forces_in_newton

    case = load_case(ROOT / "cases" / "oscillating.toml")
    jm = jump_map(case, [case.speed_rpm])
    resp = _forces_in_newton(case, dyn.compliant_response(case.motion, case.model, case.speed_rpm * RPM))
    assert jm.oscillating and jm.spring_rate_unit == "N*m/rad"
    assert jm.min_force[0, 0] == pytest.approx(resp.min_force, abs=0.01)
    # issue 13, 5: the torsion rate in a column named for it; the old column keeps the same numbers (deprecated)
    (row,) = _rows(jm.csv)[1]
    rate = float(case.spec.dynamics.torsion_rate)
    assert float(row["spring_rate_N_m_per_rad"]) == rate and float(row["spring_rate_N_per_mm"]) == rate


@pytest.mark.slow
def test_sharded_over_two_devices_equals_one(small_map):
    """Two host devices (a subprocess): the grid sharded over both equals the grid on one of them."""
    code = (
        "import sys, jax, numpy as np, camdyn\n"
        "camdyn.enable_x64()\n"
        "from camdyn.model.case import load_case\n"
        "from camdyn.design.sweep import jump_map\n"
        "assert jax.device_count() == 2, jax.devices()\n"
        f"case = load_case({str(LECTURE)!r})\n"
        "grid = ([300.0, 520.0, 650.0], [1.0, 2.0])\n"
        "two, one = jump_map(case, *grid), jump_map(case, *grid, devices=jax.devices()[:1])\n"
        "assert two.devices == 2 and one.devices == 1\n"
        "assert two.csv == one.csv, (two.csv, one.csv)\n"
        "sys.stdout.write(two.csv)\n"
    )
    env = os.environ | {
        "XLA_FLAGS": "--xla_force_host_platform_device_count=2",
        "JAX_PLATFORMS": "cpu",
        "EQX_ON_ERROR": "nan",
    }
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    two = np.loadtxt(out.stdout.strip().splitlines()[1:], delimiter=",", usecols=range(5))
    one = np.loadtxt(small_map.csv.strip().splitlines()[1:], delimiter=",", usecols=range(5))
    assert two.shape == one.shape == (6, 5)
    np.testing.assert_allclose(two[:, :4], one[:, :4], rtol=1e-9, atol=1e-9)  # this process: maybe another platform


@pytest.mark.slow
def test_cli_writes_csv_and_png(capsys, tmp_path):
    argv = ["sweep", str(LECTURE), "--speeds", "300:520:2", "--spring-rates", "1:2:2", "-o", str(tmp_path)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    csv, png = tmp_path / "lecture-sweep.csv", tmp_path / "lecture-sweep.png"
    assert "preload kept" in out and csv.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(csv.read_text().strip().splitlines()) == 1 + 4
    assert main(argv) == 2 and "--force" in capsys.readouterr().err  # nothing overwritten without --force
    assert main([*argv, "--force"]) == 0


@pytest.mark.parametrize(
    "flag, value",
    [
        ("--speeds", "100-700-3"),
        ("--speeds", "100:700"),
        ("--speeds", "a:700:3"),
        ("--speeds", "100:700:2.5"),
        ("--speeds", "700:100:3"),
        ("--speeds", "0:100:3"),
        ("--speeds", "100:700:0"),
        ("--speeds", "100:700:1"),
        ("--speeds", "100:inf:3"),
        ("--spring-rates", "1:2:x"),
    ],
)
def test_cli_bad_grid_is_one_line_exit_2(capsys, flag, value):
    grids = {"--speeds": "100:700:3", flag: value}
    argv = ["sweep", str(LECTURE), *(a for kv in grids.items() for a in kv), "-o", "/nonexistent-camdyn-dir"]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and flag in err and err.startswith("camdyn: ")


# ------------------------------------------------------------------------------- issue 13: robustness


@pytest.mark.slow
def test_failed_points_are_flagged_and_the_map_goes_on(lecture_rigid_case, monkeypatch):
    """Issue 13, 1: a point whose flight model fails (a NumericalError, or even an unexpected error) is flagged in
    its row with NaN numbers; the other points are computed as ever."""
    real = dyn.rigid_response

    def flaky(motion, model, omega, *args, **kwargs):
        if abs(omega - 650.0 * RPM) < 1e-9:
            raise NumericalError("rigid model", "the flight does not end")
        if abs(omega - 700.0 * RPM) < 1e-9:
            raise ValueError("f(a) and f(b) must have different signs")
        return real(motion, model, omega, *args, **kwargs)

    monkeypatch.setattr(dyn, "rigid_response", flaky)
    jm = jump_map(lecture_rigid_case, [300.0, 600.0, 650.0, 700.0])
    header, rows = _rows(jm.csv)
    status = [r["status"] for r in rows]
    assert status[:2] == ["ok", "ok"]
    assert status[2] == "failed: rigid model: the flight does not end"
    assert (
        status[3].startswith("failed: internal error")
        and "ValueError: f(a) and f(b) must have different signs" in status[3]
    )
    for r in rows[2:]:
        assert r["min_contact_force_N"] == r["separated"] == r["max_gap_mm"] == "nan"
    assert rows[0]["separated"] == "0" and rows[1]["separated"] == "1" and float(rows[1]["max_gap_mm"]) > 0.0
    assert list(jm.failed[:, 0]) == [False, False, True, True] and np.isnan(jm.max_gap[2:, 0]).all()
    assert any("2 grid point(s) failed" in n for n in jm.notes)


@pytest.mark.slow
def test_issue_case_sweep_writes_its_csv(tmp_path, capsys):
    """Issue 13, 1: the rigid follower whose lift-off falls on a segment boundary: the sweep writes its CSV, every
    row with a status, whatever the flight model does at 1200 rpm."""
    case = tmp_path / "rigid-boundary.toml"
    case.write_text(RIGID_BOUNDARY)
    assert main(["sweep", str(case), "--speeds", "800:1200:5", "-o", str(tmp_path)]) == 0
    capsys.readouterr()
    _, rows = _rows((tmp_path / "rigid-boundary-sweep.csv").read_text())
    assert [float(r["speed_rpm"]) for r in rows] == [800, 900, 1000, 1100, 1200]
    for r in rows:
        assert r["status"] == "ok" or r["status"].startswith("failed: ")
        if r["status"] != "ok":
            assert r["min_contact_force_N"] == r["max_gap_mm"] == "nan"
    assert rows[0]["status"] == "ok" and rows[0]["separated"] == "0"


def test_grid_beyond_the_budget_is_refused(lecture, capsys):
    """Issue 13, 2: an absurd grid is refused at once, in one line naming the budget (exit 2), by the command line
    before it allocates the grid, and by the library before any work."""
    argv = [
        "sweep",
        str(LECTURE),
        "--speeds",
        "1:1e5:1000000000",
        "--spring-rates",
        "1:2:1000000",
        "-o",
        "/nonexistent-camdyn-dir",
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and f"budget of {MAX_GRID_POINTS:,} points" in err
    with pytest.raises(InputError, match="budget"):
        jump_map(lecture, np.linspace(100.0, 200.0, 1001), np.linspace(1.0, 2.0, MAX_GRID_POINTS // 1000))


@pytest.mark.slow  # the map's gap stepping compiles for 3 s
def test_absurd_spring_rates_separate_in_the_train(lecture):
    """Issue 13, 14: with a spring rate 1e8 times the train's the spring, not the cam, holds the follower: the cam
    sees only the train, ``k_f s + c_f w s'``, which reaches zero near the end of the return (the train's damper
    would have to pull). So the point separates while the follower never passes the cam: gap 0, and a note says so.
    The in-contact least force is checked against that locked-follower limit, an independent closed form."""
    jm = jump_map(lecture, [300.0, 500.0], [1e11, 1e12])
    assert jm.separated.all() and np.all(jm.max_gap == 0.0) and not jm.failed.any()
    theta = np.arange(3600) * (2 * np.pi / 3600)
    s, s1 = np.asarray(evaluate(lecture.motion, jnp.asarray(theta)))[:2] * 1e-3
    kf, cf = float(lecture.model.train_stiffness), float(lecture.model.train_damping)
    for i, rpm in enumerate(jm.speeds_rpm):
        locked = np.min(kf * s + cf * rpm * RPM * s1)
        assert locked < 0.0 and np.allclose(jm.contact_force[i], locked, rtol=0, atol=1e-3)
    assert any("follower train alone" in n for n in jm.notes)


_TWO_MAPS = """
import json, sys
from pathlib import Path
from camdyn import enable_x64
from camdyn._core import jit
from camdyn.design.sweep import jump_map
from camdyn.model.case import load_case
enable_x64()
jit.enable(sys.argv[1])
files = lambda: sorted(p.name for p in Path(sys.argv[1]).rglob("*.jaxprogram"))
out = {}
for name in ("polynomial", "lecture"):
    jm = jump_map(load_case(Path(sys.argv[2]) / "cases" / f"{name}.toml"), [300.0, 700.0], [0.5, 3.0])
    out[name] = {"files": files(), "separated": jm.separated.tolist(), "gap": jm.max_gap.tolist(),
                 "force": jm.min_force.tolist()}
print(json.dumps(out))
"""


@pytest.mark.slow
def test_a_new_case_reuses_the_traced_map_programs(lecture, tmp_path):
    """Issue 23: every program of a compliant map is in the traced-program cache, keyed by the follower kind and not
    the case: in a fresh process whose cache another case's map filled, the lecture's (another segment list) traces
    nothing new, and the loaded programs give what the programs traced here give."""
    env = os.environ | {"PYTHONPATH": str(ROOT), "EQX_ON_ERROR": "nan"}
    run = subprocess.run(
        [sys.executable, "-c", _TWO_MAPS, str(tmp_path), str(ROOT)], env=env, capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr[-2000:]
    out = json.loads(run.stdout.splitlines()[-1])
    first = out["polynomial"]["files"]
    assert {p.split("-")[0] for p in first} >= {"_evaluate", "linear_kernel", "exact_gap_kernel"}
    assert out["lecture"]["files"] == first
    assert any(map(any, out["polynomial"]["separated"])) and any(map(any, out["lecture"]["separated"]))
    plain = jump_map(lecture, [300.0, 700.0], [0.5, 3.0])
    np.testing.assert_allclose(out["lecture"]["force"], plain.min_force, rtol=1e-12)
    np.testing.assert_allclose(out["lecture"]["gap"], plain.max_gap, rtol=1e-12)


def test_one_test_of_the_platform_decides_batch_width_and_gap_kernel():
    """The jump map's batch width and its gap stepping's path follow one function of the devices it runs on
    (:func:`camdyn._core.sharding.accelerated`), not the default backend."""
    from types import SimpleNamespace

    import jax

    from camdyn._core.sharding import _chunk_size, accelerated
    from camdyn.design.sweep import _exact_gap

    cpu, gpu = tuple(jax.devices("cpu")[:1]), (SimpleNamespace(platform="gpu"),)
    assert not accelerated(cpu) and accelerated(gpu)
    assert _chunk_size(1024, cpu) == 1024 and _chunk_size(1024, gpu) == 16 * 1024
    assert _exact_gap.gap_kernel(accelerated(cpu)) is _exact_gap.exact_gap_kernel
    assert _exact_gap.gap_kernel(accelerated(gpu)) is _exact_gap.exact_gap_kernel_every


def test_cpu_threads_only_where_jax_runs_programs_from_several(monkeypatch):
    """A thread per core the process may use, on a JAX whose CPU client runs programs from several threads at once;
    one where it does not (JAX 0.11's never finished the jump map's so) and on accelerators."""
    import os

    from camdyn._core import sharding

    cpu = tuple(jax.devices("cpu")[:1])
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    assert sharding.CPU_THREADS == (jax.__version_info__ < (0, 11))
    monkeypatch.setattr(sharding, "CPU_THREADS", True)
    assert sharding._workers(cpu) == cores and sharding._workers(cpu * 2) == max(1, cores // 2)
    monkeypatch.setattr(sharding, "CPU_THREADS", False)
    assert sharding._workers(cpu) == 1


def test_cpu_chunks_on_threads_equal_one_thread(monkeypatch):
    """On CPUs the chunks run on a thread per core (XLA runs one program at a time per CPU device): the rows come
    back in order, each chunk's padding dropped, progress told in order, the same numbers as on one thread."""
    from camdyn._core import sharding

    cpu = tuple(jax.devices("cpu")[:1])
    rows = np.arange(1, 11, dtype=float)

    def kernel(const, x):
        return const * x**2

    def run(workers):
        monkeypatch.setattr(sharding, "_workers", lambda devices: workers)
        told = []
        return sharding.run_batched(kernel, 3.0, [rows], 4, told.append, cpu), told

    (one, told1), (three, told3) = run(1), run(3)
    np.testing.assert_array_equal(three, 3.0 * rows**2)
    np.testing.assert_array_equal(three, one)
    assert told1 == told3 == [4, 4, 2]


def test_on_cores_keeps_the_order_and_raises_the_first_error(monkeypatch):
    """``on_cores`` (``size --buildable``'s rate scan) is ``[fn(x) for x in items]`` on threads: in order, the same
    values as on one thread, and an error raised as such."""
    import threading

    from camdyn._core import sharding

    seen = set()

    def fn(x):
        seen.add(threading.current_thread().name)
        if x == 7:
            raise ValueError("seven")
        return float(np.sqrt(x))

    monkeypatch.setattr(sharding, "_workers", lambda devices: 3)
    items = [0, 1, 4, 9, 16, 25]
    assert sharding.on_cores(fn, items) == [float(np.sqrt(x)) for x in items]
    assert any(name.startswith("camdyn-core") for name in seen)
    with pytest.raises(ValueError, match="seven"):
        sharding.on_cores(fn, [1, 7, 2])
    done = []

    def slow(x):
        done.append(x)
        if x == 7:
            raise ValueError("seven")
        time.sleep(0.01)

    with pytest.raises(ValueError, match="seven"):  # after an error the items not started are dropped
        sharding.on_cores(slow, [7] + [1] * 200)
    assert len(done) < 100
    monkeypatch.setattr(sharding, "_workers", lambda devices: 1)
    seen.clear()
    assert sharding.on_cores(fn, items) == [float(np.sqrt(x)) for x in items]
    assert seen == {threading.current_thread().name}


def test_steady_state_on_the_step_grid_from_the_aliased_spectrum():
    """The gap stepping's steady state on every 5th angle (720 steps of 3600) from inverse FFTs of 720 points of the
    aliased spectrum equals the full inverse FFTs there, x and dx/dtheta, Nyquist bin included (numpy's irfft)."""
    from camdyn.design.sweep._exact_gap import _on_steps

    rng = np.random.default_rng(3)
    x_spec = np.fft.rfft(rng.standard_normal((2, 3600)), axis=-1) * np.exp(-np.arange(1801) / 300.0)
    x_spec[:, -1] += 0.25j  # irfft reads only the Nyquist bin's real part
    x, x1 = jax.jit(_on_steps, static_argnums=(1, 2))(x_spec, 3600, 720)  # compiled, as the map runs it
    k = np.arange(1801)
    np.testing.assert_allclose(x, np.fft.irfft(x_spec, 3600)[:, ::5], rtol=0, atol=1e-14)
    np.testing.assert_allclose(x1, np.fft.irfft(1j * k * x_spec, 3600)[:, ::5], rtol=0, atol=1e-12)


def test_steady_train_force_is_the_train_force_of_the_steady_state(lecture):
    """The map's least force from one inverse FFT of the force spectrum (and the conjugate division) against
    train_force of steady_state's x and dx/dtheta (two inverse FFTs, XLA's complex division)."""
    base = lecture.model
    theta = np.arange(3600) * (2 * np.pi / 3600)
    s, s1 = (v * base.scale for v in np.asarray(evaluate(lecture.motion, theta))[:2])
    spec = jnp.asarray(np.fft.rfft(s))

    @eqx.filter_jit  # one compiled program for both routes (eager jax.numpy compiles one per operation)
    def want_and_got(spec, omega, base, k, c, s, s1):
        x, x1 = dyn.steady_state(spec, omega, base, k, c, 3600)
        return dyn.train_force(base, omega, s, s1, x, x1), dyn.steady_train_force(spec, omega, base, k, c, s, s1)

    for rpm, rate in ((300.0, 2.0), (650.0, 0.5)):
        omega, k = rpm * RPM, rate * 1e3
        c = base.damping_at(k)
        omega, k, c = (np.asarray(v, dtype=float) for v in (omega, k, c))  # traced, not static: one compile
        want, got = (np.asarray(a) for a in want_and_got(spec, omega, base, k, c, jnp.asarray(s), jnp.asarray(s1)))
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * np.max(np.abs(want)))


@pytest.mark.slow
def test_the_accelerators_every_point_stepping_equals_the_gathered_one(lecture):
    """The exact stepping computes a switching point's step gathered with the others that switch (a CPU) or at
    every point, keeping the switching ones (an accelerator, where gathers cost more than arithmetic): the same
    largest gaps at 8 speeds of the lecture, most of them separating."""
    from camdyn._core.units import TWO_PI
    from camdyn.design.sweep import _exact_gap
    from camdyn.design.sweep._grid import GAP_STRIDE, GRID_N
    from camdyn.design.sweep._map import _gap_weight_mm

    theta = np.arange(GRID_N) * (TWO_PI / GRID_N)
    vals = np.asarray(evaluate(lecture.motion, theta))  # the motion's unit, as the map hands the kernel
    tab = vals[:3, ::GAP_STRIDE]
    const = (lecture.model, *tab, _gap_weight_mm(lecture, theta[::GAP_STRIDE]), np.fft.rfft(vals[0]))
    omega, k = np.linspace(480.0, 700.0, 8) * RPM, np.full(8, 2e3)
    gaps = {
        gathered: np.asarray(eqx.filter_jit(_exact_gap.gap_kernel(accelerator=not gathered))(const, omega, k))
        for gathered in (True, False)
    }
    assert np.all(np.isfinite(gaps[True])) and np.sum(gaps[True] > 1e-3) >= 4
    np.testing.assert_allclose(gaps[False], gaps[True], rtol=1e-9, atol=1e-12)
