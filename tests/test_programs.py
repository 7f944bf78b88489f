"""The traced-program cache: persisted programs give the same answers, and anything static changes the key."""

import dataclasses
import json
import os
import pickle
import subprocess
import sys
import threading
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import camdyn.model  # noqa: F401  (float64)
from camdyn._core import jit as programs
from camdyn._core import jitargs
from camdyn.model.dynamics import _harmonic
from camdyn.model.motion import _base as motion_base

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    """This test's own folder, camdyn's program cache enabled afresh in it."""
    monkeypatch.setattr(programs, "_DIR", None)
    programs.enable(tmp_path)
    return tmp_path


class Poly(eqx.Module):
    coef: jax.Array
    power: int = eqx.field(static=True)

    def __call__(self, x):
        return self.coef * x**self.power


def _value(p, x, shift):
    return p(x) + shift


def test_programs_persist_and_static_fields_are_part_of_the_key(cache_dir):
    x = jnp.linspace(0.0, 2.0, 5)
    square, cube = Poly(jnp.asarray(3.0), 2), Poly(jnp.asarray(3.0), 3)
    first = programs.cached_jit(_value)
    assert np.allclose(first(square, x, 1.0), 3 * x**2 + 1) and np.allclose(first(cube, x, 1.0), 3 * x**3 + 1)
    assert np.allclose(first(cube, x, 2.0), 3 * x**3 + 2)  # a Python number is static: its own program
    assert np.allclose(first(cube, x, shift=jnp.asarray(2.0)), 3 * x**3 + 2)  # keywords too
    assert len(list(cache_dir.rglob("_value-*.jaxprogram"))) == 4
    # a new wrapper (as in a fresh process) reads the programs back instead of tracing
    second = programs.cached_jit(_value)
    assert np.allclose(second(cube, x, 1.0), 3 * x**3 + 1) and np.allclose(
        second(Poly(jnp.asarray(-1.0), 2), x, 1.0), 1 - x**2
    )
    assert len(list(cache_dir.rglob("_value-*.jaxprogram"))) == 4
    # under a transformation the plain jit runs (exported programs have no batching rule)
    assert np.allclose(jax.vmap(lambda c: second(Poly(c, 2), x, 0.0))(jnp.arange(3.0)), np.arange(3.0)[:, None] * x**2)
    (next(cache_dir.rglob("_value-*.jaxprogram"))).write_bytes(b"truncated")  # a damaged file: trace afresh
    assert np.allclose(programs.cached_jit(_value)(square, x, 1.0), 3 * x**2 + 1)


def test_programs_are_kept_per_fingerprint_and_unused_ones_removed(tmp_path, monkeypatch):
    """Each fingerprint (an install's camdyn, JAX stack and machine) has its folder; storing a program removes the
    folders unused for STALE_DAYS and the flat files of the layout before folders, and keeps the rest."""
    monkeypatch.setattr(programs, "_DIR", None)
    stale, recent = tmp_path / "0123456789abcdef", tmp_path / "fedcba9876543210"
    for folder, age_days in ((stale, programs.STALE_DAYS + 1), (recent, programs.STALE_DAYS - 1)):
        folder.mkdir()
        (folder / "f-0.jaxprogram").write_bytes(b"")
        used = folder / programs._USED
        used.touch()
        then = used.stat().st_mtime - age_days * 86400.0
        os.utime(used, (then, then))
    (tmp_path / "g-1.jaxprogram").write_bytes(b"")  # stored before the folders
    programs.enable(tmp_path)
    assert np.allclose(programs.cached_jit(_value)(Poly(jnp.asarray(2.0), 1), jnp.ones(2), 1.0), 3.0)
    ours = tmp_path / programs._fingerprint()[:16]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([ours.name, recent.name])
    assert len(list(ours.glob("_value-*.jaxprogram"))) == 1 and (ours / programs._USED).exists()


def test_prepare_compiles_without_running_and_threads_compile_at_once(cache_dir):
    """``prepare`` stores the program a later call runs (no second trace); two threads compiling two programs at
    once leave JAX's persistent-cache threshold as it was (each compile lifts it while it runs)."""
    import threading

    traced = []

    def double(x):
        traced.append(1)
        return 2.0 * x

    def triple(x):
        traced.append(1)
        return 3.0 * x

    fns = programs.cached_jit(double), programs.cached_jit(triple)
    threshold = jax.config.jax_persistent_cache_min_compile_time_secs
    both = [threading.Thread(target=fn.prepare, args=(np.ones(3),)) for fn in fns]
    for t in both:
        t.start()
    for t in both:
        t.join()
    assert len(traced) == 2 and len(list(cache_dir.rglob("*.jaxprogram"))) == 2
    assert jax.config.jax_persistent_cache_min_compile_time_secs == threshold
    assert np.allclose(fns[0](np.arange(3.0)), [0.0, 2.0, 4.0]) and len(traced) == 2  # prepared: not traced again


def test_caches_turned_on_mid_compile_keep_the_stored_program_out_of_jax_cache(tmp_path):
    """The CLI turns the caches on at each command; in one process (the tests) a program may then still be compiling
    to be stored, on a thread. JAX's threshold comes back only when that compile is done: set at once, the program
    went into JAX's cache, and a second worker compiling it stored the copy that cache deserialized, which ran
    without some of its functions ("negate_bitcast_fusion not found")."""
    before = jax.config.jax_compilation_cache_dir, jax.config.jax_persistent_cache_min_compile_time_secs
    try:
        with programs._outside_jax_cache():
            programs.keep_in_jax_cache(tmp_path, 0.25)
            assert jax.config.jax_persistent_cache_min_compile_time_secs == float("inf")
        assert jax.config.jax_persistent_cache_min_compile_time_secs == 0.25
        assert jax.config.jax_compilation_cache_dir == str(tmp_path)
    finally:
        jax.config.update("jax_compilation_cache_dir", before[0])
        jax.config.update("jax_persistent_cache_min_compile_time_secs", before[1])


def test_store_compiles_a_missing_program_and_leaves_a_stored_one_unloaded(monkeypatch, cache_dir):
    """``store`` compiles and stores a program no process has stored, which the call then runs without a second
    trace; where it is stored, ``store`` neither loads nor traces it (a warm process pays a file's lookup)."""
    traced = []

    def halve(x):
        traced.append(1)
        return 0.5 * x

    fn = programs.cached_jit(halve)
    fn.store(np.ones(3))
    assert len(traced) == 1 and len(list(cache_dir.rglob("halve-*.jaxprogram"))) == 1
    assert np.allclose(fn(np.arange(3.0)), [0.0, 0.5, 1.0]) and len(traced) == 1  # stored and kept: no trace
    again = programs.cached_jit(halve)  # as in a fresh process
    monkeypatch.setattr(programs, "_load", lambda *_: pytest.fail("a stored program was loaded"))
    again.store(np.ones(3))
    assert len(traced) == 1


def test_a_call_waits_for_the_head_start_that_loads_its_program(capsys, cache_dir):
    """A program prepared on another thread (``in_background``) while the caller reaches its first call is traced
    and compiled once: the call waits for it instead of compiling it again. A head start that fails is ignored."""
    import threading

    traced, started = [], threading.Event()

    def slow_double(x):
        started.set()
        traced.append(threading.current_thread().name)
        threading.Event().wait(0.2)  # the trace takes a while: the caller arrives during it
        return 2.0 * x

    fn = programs.cached_jit(slow_double)
    thread = programs.in_background(lambda: fn.prepare(np.ones(3)), "head-start")
    assert started.wait(10.0)
    assert np.allclose(fn(np.arange(3.0)), [0.0, 2.0, 4.0])
    thread.join()
    assert traced == ["head-start"] and len(list(cache_dir.rglob("slow_double-*.jaxprogram"))) == 1

    def broken():
        raise RuntimeError("no head start")

    programs.in_background(broken, "broken").join()
    assert capsys.readouterr().err == ""  # nothing raised, nothing printed


class _Squared(eqx.Module):
    """A stand-in for a motion: its ``jit_form`` (counted) is what compiled programs take."""

    coef: jax.Array
    made = []  # the forms made, counted across instances

    def jit_form(self):
        _Squared.made.append(self)
        return Poly(self.coef, 2)


def _at(p, x):
    return p(x)


def test_a_motions_form_is_made_once_for_all_the_calls_of_a_stored_program(monkeypatch, cache_dir):
    """Issue 23: a speed search calls its stored programs hundreds of times with one motion: its jit form is made
    (and flattened) once, not per call; another object of the same structure makes its own and runs the same
    program, with its own numbers."""
    monkeypatch.setattr(_Squared, "made", [])
    monkeypatch.setattr(jitargs, "_part_memo", {})  # the session's earlier calls leave no eviction due
    x = jnp.linspace(0.0, 2.0, 5)
    fn, one, two = programs.cached_jit(_at), _Squared(jnp.asarray(3.0)), _Squared(jnp.asarray(-2.0))
    for _ in range(5):
        np.testing.assert_allclose(fn(one, x), 3.0 * x**2, rtol=1e-15)
    assert _Squared.made == [one]
    np.testing.assert_allclose(fn(two, x), -2.0 * x**2, rtol=1e-15)
    np.testing.assert_allclose(fn(one, x=x), 3.0 * x**2, rtol=1e-15)  # x as a keyword: a program of its own
    assert _Squared.made == [one, two] and len(list(cache_dir.rglob("_at-*.jaxprogram"))) == 2
    # under a transformation the plain jit runs, on the form as well
    np.testing.assert_allclose(jax.vmap(lambda c: fn(_Squared(c), x))(jnp.arange(2.0)), [0.0 * x, x**2], rtol=1e-15)


class _Scaled(eqx.Module):
    """A stand-in for a follower model: an array field and a static one."""

    gain: jax.Array
    power: int = eqx.field(static=True)


def _scaled(m, x):
    return m.gain * x**m.power


def test_a_module_is_flattened_once_and_keyed_by_its_structure(monkeypatch, cache_dir):
    """A module argument (a follower model) is flattened once per object and its arrays passed on every call: other
    numbers in the same structure run the same stored program, another static field compiles its own."""
    monkeypatch.setattr(jitargs, "_part_memo", {})
    x = np.linspace(0.0, 2.0, 5)
    fn = programs.cached_jit(_scaled)
    one, two, cube = _Scaled(jnp.asarray(2.0), 2), _Scaled(jnp.asarray(-1.5), 2), _Scaled(jnp.asarray(2.0), 3)
    for _ in range(3):
        np.testing.assert_allclose(fn(one, x), 2.0 * x**2, rtol=1e-15)
    np.testing.assert_allclose(fn(two, x), -1.5 * x**2, rtol=1e-15)
    assert len(list(cache_dir.rglob("_scaled-*.jaxprogram"))) == 1
    assert [id(m) for m, _ in jitargs._part_memo.values()] == [id(one), id(two)]
    np.testing.assert_allclose(fn(cube, x), 2.0 * x**3, rtol=1e-15)
    assert len(list(cache_dir.rglob("_scaled-*.jaxprogram"))) == 2
    # past the signatures it remembers, each is numbered afresh and no number is reused: the program a remembered
    # part's number finds is still that part's (a reused number would run the square for the cube)
    monkeypatch.setattr(jitargs, "_MAX_TOKENS", 1)
    monkeypatch.setattr(jitargs, "_part_memo", {})
    for m, power in ((one, 2), (cube, 3), (one, 2), (two, 2), (cube, 3)):
        np.testing.assert_allclose(fn(m, x), float(m.gain) * x**power, rtol=1e-15)


def _wave(x):
    return jnp.exp(-x) * jnp.cos(3.0 * x)


def test_compiler_options_are_part_of_the_key_and_unknown_ones_dropped(tmp_path, monkeypatch):
    """XLA options (camdyn's programs compile with :data:`XLA_OPTIONS` by default) key a program of their own and
    apply whether or not the cache is enabled; an option this XLA does not know is dropped, not an error."""
    monkeypatch.setattr(programs, "_DIR", None)
    opts, unknown = programs.XLA_OPTIONS, (("xla_camdyn_no_such_option", True),)
    x = np.linspace(0.0, 2.0, 7)
    np.testing.assert_allclose(programs.cached_jit(_wave, unknown)(x), np.exp(-x) * np.cos(3.0 * x), rtol=1e-14)
    uncached = np.asarray(programs.cached_jit(_wave, opts)(x))  # no cache: compiled with the options all the same
    programs.enable(tmp_path)
    plain, optioned = programs.cached_jit(_wave, ()), programs.cached_jit(_wave, opts)
    np.testing.assert_allclose(plain(x), np.exp(-x) * np.cos(3.0 * x), rtol=1e-14)
    np.testing.assert_array_equal(optioned(x), uncached)
    np.testing.assert_allclose(optioned(x), plain(x), rtol=1e-14)
    assert len(list(tmp_path.rglob("_wave-*.jaxprogram"))) == 2
    np.testing.assert_array_equal(programs.cached_jit(_wave)(x), uncached)  # the default: XLA_OPTIONS
    assert len(list(tmp_path.rglob("_wave-*.jaxprogram"))) == 2
    inside = jax.jit(jax.vmap(programs.cached_jit(_wave)))  # options go to the outer program only (JAX refuses them
    np.testing.assert_allclose(inside(x[:, None])[:, 0], plain(x), rtol=1e-14)  # on a nested one)
    np.testing.assert_allclose(programs.cached_jit(_wave, unknown)(x), plain(x), rtol=1e-14)  # compiled without it


def test_an_option_xla_refused_is_not_passed_again(tmp_path, monkeypatch):
    """An option this XLA does not know (JAX 0.11's XLA no longer knows ``xla_cpu_use_fusion_emitters``) is refused
    once a process: every later compile leaves it out instead of lowering the program twice, with and without."""
    monkeypatch.setattr(programs, "_REFUSED", set())
    refusals = []
    refused = programs._refused
    monkeypatch.setattr(programs, "_refused", lambda err, passed: refusals.append(str(err)) or refused(err, passed))
    two = (("xla_camdyn_no_such_option", True), ("xla_camdyn_nor_this_one", 1))
    x = np.linspace(0.0, 2.0, 7)
    expected = np.exp(-x) * np.cos(3.0 * x)
    programs.enable(tmp_path)
    np.testing.assert_allclose(programs.cached_jit(_wave, two)(x), expected, rtol=1e-14)  # stored: refused twice
    assert programs._REFUSED == {"xla_camdyn_no_such_option", "xla_camdyn_nor_this_one"} and len(refusals) == 2
    monkeypatch.setattr(programs, "_DIR", None)
    np.testing.assert_allclose(programs.cached_jit(_cube, two)(x), x**3 + 1.0, rtol=1e-14)  # the plain route
    np.testing.assert_allclose(programs.cached_jit(_wave, two)(2 * x), np.exp(-2 * x) * np.cos(6.0 * x), rtol=1e-14)
    assert len(refusals) == 2  # neither compile asked for them again
    # a compile that passed an option another thread had meanwhile found refused retries without it too; an error
    # naming an option this compile did not pass is not this one's to retry
    err = RuntimeError("INVALID_ARGUMENT: No such compile option: 'xla_camdyn_no_such_option'")
    assert refused(err, dict(two)) and not refused(err, {}) and not refused(RuntimeError("other"), dict(two))


def _cube(x):
    return x**3 + 1.0


def test_a_program_another_process_compiles_is_waited_for_and_loaded(cache_dir, monkeypatch):
    """Where another process is compiling a program (it holds the program's lock), a process that needs the same
    program waits for it and loads what it stored, rather than compile it a second time (two test workers, two
    commands at once). Another "process" here is a thread: the lock is per open file, so they exclude each other."""
    x = jnp.linspace(0.0, 1.0, 5)
    programs.cached_jit(_cube)(x)  # the program, compiled and stored
    (file,) = cache_dir.rglob("_cube-*.jaxprogram")
    blob = file.read_bytes()
    file.unlink()
    compiled = []
    monkeypatch.setattr(programs, "_compile", lambda *a: compiled.append(a) or pytest.fail("compiled again"))
    holding, release = threading.Event(), threading.Event()

    def other_process():
        with programs._compiling(file):
            holding.set()
            release.wait(30.0)
            programs._save(file, blob)

    other = threading.Thread(target=other_process)
    other.start()
    assert holding.wait(30.0)
    threading.Timer(0.3, release.set).start()  # the other "compile" ends after this one started to wait
    np.testing.assert_array_equal(programs.cached_jit(_cube)(x), np.asarray(x) ** 3 + 1.0)
    other.join()
    assert compiled == []


def test_a_stored_result_is_read_back_and_a_failure_is_not_stored(tmp_path, monkeypatch):
    """``stored`` computes once a key and reads the result back after (a path case's synthesis); a computation
    that raises stores nothing, and without ``enable`` nothing is written."""
    calls = []

    def compute(value):
        calls.append(value)
        if value is None:
            raise ValueError("no result")
        return {"values": np.arange(3.0) * value, "device": jnp.asarray(value)}

    monkeypatch.setattr(programs, "_DIR", None)
    programs.stored("thing", "a", lambda: compute(1.0))
    assert not list(tmp_path.rglob("*")) and calls == [1.0]
    programs.enable(tmp_path)
    first = programs.stored("thing", "a", lambda: compute(2.0))
    again = programs.stored("thing", "a", lambda: compute(3.0))  # the key, not the function, says which result
    other = programs.stored("thing", "b", lambda: compute(4.0))
    assert calls == [1.0, 2.0, 4.0]
    np.testing.assert_array_equal(again["values"], first["values"])
    assert float(again["device"]) == 2.0 and isinstance(again["device"], jax.Array)
    np.testing.assert_array_equal(other["values"], np.arange(3.0) * 4.0)
    with pytest.raises(ValueError, match="no result"):
        programs.stored("thing", "c", lambda: compute(None))
    assert len(list(tmp_path.rglob("thing-*.result"))) == 2


_PATH_METHOD = """
import sys, numpy as np, camdyn
camdyn.enable_x64()
from camdyn._core import jit
from camdyn.model.linkage import vmap_scalar
from camdyn.model.paths import build_path
jit.enable(sys.argv[1])
u = np.linspace(0.0, 1.0, 7, endpoint=False)
for radius, centre in ((10.0, (0.0, 0.0)), (13.0, (1.0, -2.0))):
    xy = vmap_scalar(build_path({"type": "circle", "center": list(centre), "radius": radius}).point, u)
    want = np.column_stack([np.cos(2 * np.pi * u), np.sin(2 * np.pi * u)]) * radius + centre
    assert np.max(np.abs(xy - want)) < 1e-12
"""


@pytest.mark.slow  # two fresh processes
def test_a_method_of_paths_of_one_type_is_one_stored_program_in_every_process(tmp_path):
    """``vmap_scalar`` of a path's bound method stores one program, named by the method (a function object's text
    holds its address: a new file in every process), that every path of the type shares, whatever its numbers."""
    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"} | {"PYTHONPATH": str(ROOT)}
    for _ in range(2):
        subprocess.run([sys.executable, "-c", _PATH_METHOD, str(tmp_path)], env=env, check=True, timeout=300)
        assert len(list(tmp_path.rglob("_vmap_method-*.jaxprogram"))) == 1


def _solve(a, b):
    return jnp.linalg.solve(a, b)


def test_programs_are_stored_compiled_and_lapack_ones_exported(monkeypatch, cache_dir):
    """A program loads as its compiled executable; one that calls LAPACK (whose kernels JAX registers only while
    lowering) as a ``jax.export`` program. Either gives what the plain jit gives."""
    x = jnp.linspace(0.0, 2.0, 5)
    a, b = jnp.asarray([[4.0, 1.0], [2.0, 3.0]]), jnp.asarray([1.0, 2.0])
    assert np.allclose(programs.cached_jit(_value)(Poly(jnp.asarray(2.0), 2), x, 1.0), 2 * x**2 + 1)
    assert np.allclose(programs.cached_jit(_solve)(a, b), np.linalg.solve(a, b))
    kinds = {f.name.split("-")[0]: pickle.loads(f.read_bytes())[0] for f in cache_dir.rglob("*.jaxprogram")}
    assert kinds == {"_value": "executable", "_solve": "exported"}
    for fn, args, want in ((_value, (Poly(jnp.asarray(2.0), 2), x, 1.0), 2 * x**2 + 1), (_solve, (a, b), None)):
        program = programs.cached_jit(fn)  # a fresh wrapper loads the file: nothing is traced
        monkeypatch.setattr(programs, "_compile", lambda *_: pytest.fail("traced again"))
        got = program(*args)
        assert np.allclose(got, np.linalg.solve(a, b) if want is None else want)


@pytest.mark.slow  # four fresh processes, two of them compiling every program
def test_fresh_check_processes_agree_with_and_without_the_caches(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"} | {"XDG_CACHE_HOME": str(tmp_path)}
    cmd = [sys.executable, "-m", "camdyn", "check", str(ROOT / "cases" / "lecture.toml"), "--json"]
    runs = [subprocess.run(cmd, env=env, capture_output=True, text=True, check=True) for _ in range(2)]
    plain = subprocess.run(cmd, env=env | {"CAMDYN_NO_CACHE": "1"}, capture_output=True, text=True, check=True)
    stored = sorted((tmp_path / "camdyn" / "programs").rglob("*.jaxprogram"))
    # the follower stays on the cam (the smooth orbit's program), and the program of one that leaves it is stored
    # on the side: a failing case after it compiles nothing (issue 23: a new case as fast as a stored one)
    assert {p.name.split("-")[0] for p in stored} >= {"_rev_in_contact", "_rev_with_sensitivity"}
    docs = [json.loads(r.stdout) for r in (*runs, plain)]
    assert docs[0] == docs[1] == docs[2]
    fast = subprocess.run([*cmd[:4], str(ROOT / "cases" / "lecture-fast.toml")], env=env, capture_output=True)
    assert fast.returncode == 1 and sorted((tmp_path / "camdyn" / "programs").rglob("*.jaxprogram")) == stored


@pytest.mark.slow  # two fresh processes, the first compiling every program of a rigid follower
def test_a_rigid_check_stores_the_flight_its_bouncing_neighbour_runs(tmp_path):
    """A rigid follower that stays on its cam stores on the side the programs of one that leaves it (the flight, the
    kinematic force at one angle): the bouncing case's check after it compiles nothing."""

    def rigid(name: str) -> Path:
        text = (ROOT / "cases" / f"{name}.toml").read_text()
        path = tmp_path / f"{name}-rigid.toml"
        path.write_text(
            "".join(x for x in text.splitlines(True) if not x.startswith(("train_stiffness", "train_damp")))
        )
        return path

    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"} | {"XDG_CACHE_HOME": str(tmp_path / "c")}
    check = [sys.executable, "-m", "camdyn", "check"]
    assert subprocess.run([*check, str(rigid("lecture"))], env=env, capture_output=True).returncode == 0
    stored = sorted((tmp_path / "c").rglob("*.jaxprogram"))
    assert {p.name.split("-")[0] for p in stored} >= {"_flight", "kinematic_force"}
    bouncing = subprocess.run([*check, str(rigid("lecture-fast")), "--json"], env=env, capture_output=True, text=True)
    assert bouncing.returncode == 1 and json.loads(bouncing.stdout)["dynamic"]["separations"]
    assert sorted((tmp_path / "c").rglob("*.jaxprogram")) == stored


def _kernel_key(motion):
    """What a compiled program is keyed by: the static part and the array shapes of the motion's jit form."""
    dynamic, static = eqx.partition(motion.jit_form(), eqx.is_array)
    return jax.tree.structure(static), jax.tree.leaves(static), [(x.shape, x.dtype) for x in jax.tree.leaves(dynamic)]


def test_programs_of_other_segments_share_one_compiled_kernel_and_evaluate_alike(monkeypatch, cache_dir):
    from camdyn.model.motion import Program, evaluate

    lecture = Program.from_segments(
        [
            {"law": "dwell", "end": 90},
            {"law": "cycloidal", "end": 180, "lift": 20},
            {"law": "dwell", "end": 240},
            {"law": "harmonic", "end": 360, "lift": -20},
        ]
    )
    other = Program.from_segments(
        [
            {"law": "modified-sine", "end": 70, "lift": 12},
            {"law": "polynomial", "end": 150, "lift": 6, "end_jerk": 0},
            {"law": "dwell", "end": 200},
            {"law": "modified-trapezoid", "end": 330, "lift": -18},
            {"law": "dwell", "end": 360},
        ]
    )
    assert _kernel_key(lecture) == _kernel_key(other)
    # a program of its own: not the one an earlier test of this process holds in memory for these angles' bucket
    monkeypatch.setattr(motion_base, "_evaluate", programs.cached_jit(motion_base._evaluate.__wrapped__))
    theta = jnp.asarray(np.linspace(-1.0, 7.5, 997))
    for prog in (lecture, other):  # the one program on disk; each agrees with the unpadded numpy evaluation
        assert np.allclose(evaluate(prog, theta), prog._eval(np, np.asarray(theta)), rtol=1e-12, atol=1e-9)
    assert len(list(cache_dir.rglob("_evaluate-*.jaxprogram"))) == 1
    # 2 pi is the start (the modified sine's jerk), just below it the closing dwell: padding rows are never read
    ends = np.asarray(evaluate(other, jnp.asarray([2 * np.pi, np.nextafter(2 * np.pi, 0)])))
    assert np.allclose(ends[:, 0], other.host(0.0)) and ends[3, 0] > 100.0 and np.all(ends[:, 1] == 0.0)


@pytest.mark.slow  # evaluate compiled for four shapes (4 s)
def test_angles_of_other_counts_share_one_evaluate_program(monkeypatch, cache_dir):
    """``evaluate`` pads a 1-D array of angles to the next bucket (8, 64, 512, 4096): 300 and 500 angles run the one
    stored program of 512, and 20000 the one of 4096 five times, the values those of the exact shape's program to
    the bit, numpy, as long as the angles."""
    from camdyn.model.motion import Program, evaluate

    prog = Program.from_segments(
        [{"law": "cycloidal", "end": 180, "lift": 20}, {"law": "harmonic", "end": 360, "lift": -20}]
    )
    monkeypatch.setattr(motion_base, "_evaluate", programs.cached_jit(motion_base._evaluate.__wrapped__))
    for n in (300, 500, 20000):
        theta = np.linspace(0.0, 2 * np.pi, n)
        got = evaluate(prog, theta)
        assert isinstance(got, np.ndarray) and got.shape == (4, n)
        assert np.array_equal(got, np.asarray(jax.jit(motion_base._evaluate.__wrapped__)(prog, theta)))
    assert len(list(cache_dir.rglob("_evaluate-*.jaxprogram"))) == 2
    assert evaluate(prog, np.zeros(0)).shape == (4, 0) and evaluate(prog, 1.0).shape == (4,)


@pytest.mark.slow  # the least-force programs of three shapes (4 s)
def test_speeds_of_other_counts_share_the_least_force_programs(monkeypatch, cache_dir, lecture_case):
    """``linear_min_force`` pads a 1-D array of speeds to a bucket (16, 64, 256; longer in pieces of 256):
    the first one, 600 and 2000 of 2000 speeds run two stored programs, each value that of one unpadded program of
    all 2000 to round-off (lax.map batches the speeds by 64 in both, its last partial batch where the lengths
    differ)."""
    monkeypatch.setattr(_harmonic, "_linear_min_force", programs.cached_jit(_harmonic._linear_min_force.__wrapped__))
    motion, model = lecture_case.motion, lecture_case.model
    speeds = np.linspace(10.0, 80.0, 2000)
    exact = jax.jit(_harmonic._linear_min_force.__wrapped__, static_argnums=3)(
        motion, model, speeds, _harmonic._FFT_N, None
    )
    for n in (1, 600, 2000):
        got = _harmonic.linear_min_force(motion, model, speeds[:n])
        assert isinstance(got, np.ndarray) and got.shape == (n,)
        assert np.allclose(got, np.asarray(exact)[:n], rtol=1e-12, atol=1e-9)
    assert len(list(cache_dir.rglob("_linear_min_force-*.jaxprogram"))) == 2


def test_a_thousand_segments_fill_one_bucket():
    from camdyn.model.motion import Program

    prog = Program.from_segments(
        [{"law": "cycloidal", "end": 0.36 * (i + 1), "lift": 1.0 if i % 2 == 0 else -1.0} for i in range(1000)]
    )
    table = prog.jit_form()
    assert table.start.shape == (1024,) and np.isinf(table.start[1000:]).all() and np.isinf(table.jumps[1000:]).all()
    # a cycloid of 1 mm over 0.36 deg peaks at its middle with s' = 2 / beta
    beta = np.deg2rad(0.36)
    s, s1, _, _ = prog.host(np.deg2rad([0.18, 360 - 0.18]))
    assert np.allclose(s, [0.5, 0.5]) and np.allclose(s1, [2 / beta, -2 / beta])


def test_fitted_tables_of_other_lengths_share_one_compiled_kernel():
    from camdyn.model.motion import evaluate, fit_motion

    def fitted(n):
        theta = np.arange(n) * (360.0 / n)
        return fit_motion(theta, 5 * (1 - np.cos(np.deg2rad(theta))), unit="mm", source="table", file="t.csv")[0]

    short, long = fitted(300), fitted(720)
    assert _kernel_key(short) == _kernel_key(long)
    theta = np.array([0.0, 1.0, 3.0, 2 * np.pi, np.nextafter(2 * np.pi, 0), -1e-300])
    for m in (short, long):
        assert np.allclose(m.jit_form().host(theta), m.host(theta), rtol=1e-12, atol=1e-12)
    # the form follows the coefficients (a table's noise study replaces them, under vmap)
    doubled = jax.vmap(lambda c: evaluate(dataclasses.replace(short, coef=c), jnp.asarray(theta)))(2 * short.coef[None])
    assert np.allclose(doubled[0], 2 * short.host(theta), rtol=1e-12, atol=1e-12)


_TWO_DEVICES = """
import sys, jax, numpy as np, camdyn
camdyn.enable_x64()
from camdyn._core import jit
from camdyn.design.sweep import jump_map
from camdyn.model.case import load_case
jit.enable(sys.argv[1])
assert jax.device_count() == 2
jm = jump_map(load_case(sys.argv[2]), [300.0, 650.0], [1.0, 2.0])
print(jm.csv)
"""


@pytest.mark.slow  # two fresh processes mapping on two host devices
def test_a_second_process_on_two_devices_loads_what_the_first_stored(tmp_path):
    """Two host devices: a program stored by one process runs in the next on the default device (a loaded
    executable otherwise spans every device), and a kernel sharded over both is not stored (the plain jit runs)."""
    env = os.environ | {
        "XLA_FLAGS": "--xla_force_host_platform_device_count=2",
        "JAX_PLATFORMS": "cpu",
        "EQX_ON_ERROR": "nan",
        "PYTHONPATH": str(ROOT),
    }
    cmd = [sys.executable, "-c", _TWO_DEVICES, str(tmp_path), str(ROOT / "cases" / "lecture.toml")]
    runs = [subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300) for _ in range(2)]
    assert [r.returncode for r in runs] == [0, 0], runs[-1].stderr[-2000:]
    assert runs[0].stdout == runs[1].stdout
    assert {p.name.split("-")[0] for p in tmp_path.rglob("*.jaxprogram")} == {"_evaluate"}
