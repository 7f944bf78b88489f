"""No crash without a verdict, no hang, no NaN (issue 13): each finding's reproducer, and a fuzz run over the
shipped cases. Every command ends with exit 0 (pass / written), 1 (a valid design that fails, with its reason) or 2
(one line naming the file, the key and what is wrong)."""

from __future__ import annotations

import json
import math
import os
import random
import tomllib
import warnings
from pathlib import Path

import pytest
from _helpers import RIGID_BOUNDARY, run

from camdyn import InputError, load_case, response
from camdyn._core.units import RPM
from camdyn.cli import main
from camdyn.schema import load_case_spec

ROOT = Path(__file__).resolve().parents[1]
CASES = sorted(p for p in (ROOT / "cases").glob("*.toml"))
LECTURE = ROOT / "cases" / "lecture.toml"


def one_line_error(code: int, err: str) -> bool:
    return (
        code == 2 and len(err.strip().splitlines()) == 1 and err.startswith("camdyn: ") and "internal error" not in err
    )


@pytest.fixture
def rigid_case(tmp_path):
    path = tmp_path / "rigid.toml"
    path.write_text(RIGID_BOUNDARY)
    return path


# ------------------------------------------------------------------------------------------- verdicts
@pytest.mark.slow
def test_rigid_lift_off_on_a_segment_boundary_gives_a_verdict_at_every_speed(capsys, rigid_case):
    for rpm in range(1000, 1901, 100):
        code, out, err = run(capsys, "check", rigid_case, "--speed", rpm, "--json")
        assert code in (0, 1), f"{rpm} rpm: {err}"
        doc = json.loads(out)
        dyn = doc["dynamic"]
        assert dyn["min_contact_force_N"] >= 0.0  # a rigid follower is pushed, never pulled
        assert all(s["max_gap_mm"] > 0 for s in dyn["separations"])
        assert (code == 1) == any(not c["ok"] for c in doc["checks"])
    # at 1200 rpm the follower leaves the cam exactly at the boundary where the return's acceleration starts
    code, out, _ = run(capsys, "check", rigid_case, "--speed", 1200, "--json")
    starts = [s["start_deg"] for s in json.loads(out)["dynamic"]["separations"]]
    assert any(abs(s - 180.0) < 1e-6 for s in starts)


@pytest.mark.slow
def test_bouncing_that_never_settles_is_a_fail_with_its_reason(capsys, tmp_path):
    path = tmp_path / "elastic.toml"
    path.write_text(RIGID_BOUNDARY.replace("restitution = 0.3", "restitution = 1.0"))
    code, out, err = run(capsys, "check", path, "--speed", 1500)
    assert code == 1, err
    assert "does not settle back" in out and "FAIL" in out


@pytest.mark.slow
def test_far_beyond_the_jump_speed_is_a_fail_not_an_error(capsys):
    code, out, err = run(capsys, "check", LECTURE, "--speed", 10000, "--json")
    assert code == 1, err
    doc = json.loads(out)
    assert doc["verdict"] == "fail" and any("far beyond its jump speed" in w for w in doc["warnings"])


@pytest.mark.slow
def test_a_train_compressed_by_more_than_the_lift_fails(capsys, tmp_path):
    """At 1e5 rpm with a 1.5 MN preload (what sizing asks for at that speed) the compliant train stays in
    contact: the follower mass cannot move at 1667 Hz, so the train is squeezed by the whole lift and more, and
    the contact force never falls. The kinematic force is -1.3 MN. The cam no longer drives the follower: FAIL."""
    text = LECTURE.read_text().replace("speed = 300", "speed = 100000").replace("preload = 30 ", "preload = 1.5e6 ")
    path = tmp_path / "fast.toml"
    path.write_text(text)
    code, out, err = run(capsys, "check", path, "--json")
    doc = json.loads(out)
    checks = {c["name"]: c for c in doc["checks"]}
    assert code == 1 and checks["contact_force"]["ok"] and not checks["train_deflection"]["ok"], err
    assert doc["kinematic"]["min_contact_force_N"] < -1e6 and checks["train_deflection"]["value"] > 1.0


@pytest.mark.slow
def test_a_very_slow_cam_is_checked_in_the_frequency_domain(capsys):
    """At 1e-3 rpm the train vibrates 13.5 million times a revolution: no time integration resolves that, but the
    steady state in contact is exact in the frequency domain: quasi-static, k_f / (k + k_f) of the spring force."""
    code, out, err = run(capsys, "check", LECTURE, "--speed", 0.001, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["dynamic"]["min_contact_force_N"] == pytest.approx(30.0 * 1000.0 / 1002.0, rel=1e-6)
    assert any("frequency domain" in w for w in doc["warnings"])


@pytest.mark.slow  # a whole check of a follower that leaves its cam
def test_the_lecture_fast_description_says_where_it_jumps(capsys):
    """The shipped failing case says where the follower leaves the cam, and check agrees (the cycloidal rise)."""
    code, out, _ = run(capsys, "check", ROOT / "cases" / "lecture-fast.toml", "--json")
    doc = json.loads(out)
    first = min(doc["dynamic"]["separations"], key=lambda s: abs(s["start_deg"] - 145.0))
    assert code == 1 and 140.0 < first["start_deg"] < 150.0
    assert "cycloidal rise" in tomllib.loads((ROOT / "cases" / "lecture-fast.toml").read_text())["description"]
    assert 140.0 < doc["dynamic"]["min_contact_force_deg"] < 150.0  # where it leaves, not "0 N at 0.0 deg"


# ------------------------------------------------------------------------------------------- contracts
@pytest.mark.slow  # a whole check of an arm that leaves its cam: the oscillating shooting and flight compile
def test_oscillating_separations_carry_mm_and_rad(capsys, tmp_path):
    text = (ROOT / "cases" / "oscillating.toml").read_text()
    path = tmp_path / "osc.toml"
    path.write_text(text)
    code, out, _ = run(capsys, "check", path, "--speed", 2000, "--json")
    dyn = json.loads(out)["dynamic"]
    assert {"residual_vibration_mm", "residual_vibration_rad"} <= set(dyn)
    assert dyn["separations"], "the arm should leave the cam at 2000 rpm"
    for s in dyn["separations"]:
        assert {"max_gap_mm", "impact_speed_m_s", "max_gap_rad", "impact_speed_rad_s", "settled"} <= set(s)
        # at the contact, through the lever arm: a gap of radians times tens of millimetres
        assert 1.0 < s["max_gap_mm"] / s["max_gap_rad"] < 1000.0
    assert "m/s" not in "".join(w for w in json.loads(out)["warnings"] if "rad/s" in w)


@pytest.mark.slow  # the session's racetrack check: a synthesis and a whole check
def test_json_is_strict_and_path_arrays_are_optional(capsys, monkeypatch, racetrack_check):
    # the CLI formats the session's racetrack check (the same run_check of the same case) rather than solving it twice
    monkeypatch.setattr("camdyn.cli.check.run_check", lambda case, speed=None: racetrack_check)
    code, out, _ = run(capsys, "check", ROOT / "cases" / "racetrack.toml", "--json")
    assert code == 0 and "NaN" not in out and "Infinity" not in out
    doc = json.loads(out)
    assert "contour" not in doc["synthesis"] and "crank_mm" in doc["synthesis"]
    assert len(out) < 20_000
    code, out, _ = run(capsys, "check", ROOT / "cases" / "racetrack.toml", "--json", "--arrays")
    assert len(json.loads(out)["synthesis"]["contour"]) == 360


@pytest.mark.slow  # the steady state's programs at a speed of the table's own: 6 s of compiling no quick test shares
def test_table_speed_and_dynamic_columns(capsys):
    code, out, _ = run(capsys, "table", LECTURE, "--step", 30, "--speed", 200)
    header = out.splitlines()[0].split(",")
    assert code == 0 and {"dynamic_x_mm", "dynamic_contact_force_N", "contact_force_N"} <= set(header)
    rows = [dict(zip(header, map(float, line.split(",")), strict=True)) for line in out.splitlines()[1:]]
    # every 30 deg lies on the dynamics' 0.1 deg grid: the columns are the steady state itself there
    case = load_case(LECTURE)
    resp = response(case.motion, case.model, 200 * RPM)
    for r in rows:
        i = int(round(r["theta_deg"] * 10))
        assert r["dynamic_contact_force_N"] == pytest.approx(resp.force[i], rel=1e-9, abs=1e-9)
        assert r["dynamic_x_mm"] == pytest.approx(resp.x[i], rel=1e-9, abs=1e-12)
        assert abs(r["dynamic_x_mm"] - r["s_mm"]) < 0.2  # a stiff train: the follower stays with the cam


# --------------------------------------------------------------------------------- bad input, one line
@pytest.mark.parametrize(
    "content, needle",
    [
        (b"\x00\x01\x02binary", "NUL"),
        ("name = 'caf\u00e9'\n".encode("latin-1"), "UTF-8"),
        (b"[motion\n", "TOML"),
    ],
)
def test_unreadable_case_files(capsys, tmp_path, content, needle):
    path = tmp_path / "bad.toml"
    path.write_bytes(content)
    code, _, err = run(capsys, "check", path)
    assert one_line_error(code, err) and needle in err


def test_a_folder_is_not_a_case_file_and_a_bom_is_fine(capsys, tmp_path):
    code, _, err = run(capsys, "check", tmp_path)
    assert one_line_error(code, err) and "folder" in err
    bom = tmp_path / "bom.toml"
    bom.write_bytes(b"\xef\xbb\xbf" + LECTURE.read_bytes())
    code, _, err = run(capsys, "profile", bom, "-o", tmp_path / "cam.csv")  # the contour: no dynamics to compile
    assert code == 0 and (tmp_path / "cam.csv").read_text().startswith("x_mm"), err


@pytest.mark.parametrize(
    "old, new, key",
    [
        ('name = "lecture"', 'name = "a\\u0000b"', "name"),
        ("speed = 300", "speed = true", "dynamics.speed"),
        ("roller_radius = 10", "roller_radius = 1e12", "follower.roller_radius"),
        ("lift = 20 }", "lift = 1e12 }", "motion.segments[1].lift"),
        ("mass = 0.5", "mass = 1e-12", "dynamics.mass"),
        ("spring_rate = 2.0", "spring_rate = 1e12", "dynamics.spring_rate"),
        ("offset = 5", "offset = nan", "follower.offset"),
        ("base_radius = 40", "base_radius = inf", "follower.base_radius"),
        ("end = 180, lift = 20", "end = 90.000001, lift = 20", "motion.segments[1].end"),
    ],
)
def test_values_out_of_physical_range_are_refused(capsys, tmp_path, old, new, key):
    text = LECTURE.read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    code, _, err = run(capsys, "check", path)
    assert one_line_error(code, err) and f": {key}: " in err


@pytest.mark.parametrize(
    "case, old, new, key",
    [
        ("circle", "link = ", "link = 1e12 #", "mechanism.link"),
        ("circle", "slider_point = [-24.839", "slider_point = [nan", "mechanism.slider_point[0]"),
        ("circle", "slider_angle = ", "slider_angle = inf #", "mechanism.slider_angle"),
        ("racetrack", "pivot = [-100.0", "pivot = [-inf", "mechanism.pivot[0]"),
        ("racetrack", "arm = ", "arm = nan #", "mechanism.arm"),
        ("racetrack", "pivot = [-100.0, -80.0]", "pivot = [0.0, 0.0]", "mechanism.pivot"),
        ("ellipse", "x = [28.0, ", "x = [nan, ", "path.x[0]"),
        ("ellipse", "y = [11.0, ", "y = [inf, ", "path.y[0]"),
        ("eight", "center = [0.0", "center = [1e12", "path.center[0]"),
    ],
)
def test_path_and_mechanism_values_are_checked_before_the_linkage(capsys, tmp_path, case, old, new, key):
    """NaN, inf, 1e12 and a pivot on the cam centre in [path] / [mechanism]: one line naming the key (issue 13: 3,
    14, 15), never a FollowerSpec field or a precision-loss verdict."""
    text = (ROOT / "cases" / f"{case}.toml").read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    code, _, err = run(capsys, "check", path)
    assert one_line_error(code, err) and f": {key}: " in err and "Spec" not in err


@pytest.mark.parametrize(
    "old, new, key",
    [
        ("roller_radius = 10.0", "roller_radius = 1e12 #", "synthesis.roller_radius"),
        ("x = [28, ", "x = [inf, ", "path.x[0]"),
        ("y = [11, ", "y = [nan, ", "path.y[0]"),
    ],
)
def test_bad_path_files_are_refused_before_the_optimizer(capsys, tmp_path, old, new, key):
    text = (ROOT / "cases" / "paths" / "ellipse.toml").read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    code, _, err = run(capsys, "synthesize", path, "-o", tmp_path / "out.toml")
    assert one_line_error(code, err) and f": {key}: " in err and not (tmp_path / "out.toml").exists()


def test_a_long_point_list_is_bounded(capsys, tmp_path):
    text = (ROOT / "cases" / "paths" / "ellipse.toml").read_text()
    many = ", ".join(["1.0"] * 10_001)
    path = tmp_path / "long.toml"
    path.write_text(text.replace("x = [28, ", f"x = [{many}, ", 1))
    code, _, err = run(capsys, "synthesize", path, "-o", tmp_path / "out.toml")
    assert one_line_error(code, err) and "path.x" in err and "10000" in err


def test_keys_that_do_not_apply_are_refused(capsys, tmp_path):
    text = LECTURE.read_text().replace('type = "translating-roller"', 'type = "translating-flat"')
    path = tmp_path / "flat.toml"
    path.write_text(text)
    code, _, err = run(capsys, "check", path)
    assert one_line_error(code, err) and "follower.roller_radius: not used by a translating-flat follower" in err


def test_command_line_details(capsys):
    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.startswith("camdyn ")
    assert main(["check", "missing.toml", "--debug"]) == 2  # --debug after the subcommand: the traceback, still exit 2
    err = capsys.readouterr().err
    assert "Traceback" in err and "InputError" in err and "no such file" in err.splitlines()[-1]
    code, _, err = run(capsys, "table", LECTURE, "--step", 1e-7)
    assert one_line_error(code, err) and "--step" in err and "1,000,000" in err
    code, _, err = run(capsys, "check", LECTURE, "--speed", "inf")
    assert one_line_error(code, err) and "--speed" in err


def test_outputs_where_the_user_said(capsys, tmp_path):
    # a missing folder is made; a file where a folder should be, or a folder where a file should be, is refused
    code, _, err = run(capsys, "profile", LECTURE, "-o", tmp_path / "new" / "sub" / "cam.csv")
    assert code == 0 and (tmp_path / "new" / "sub" / "cam.csv").exists(), err
    (tmp_path / "afile").write_text("")
    code, _, err = run(capsys, "profile", LECTURE, "-o", tmp_path / "afile" / "cam.csv")
    assert one_line_error(code, err)
    code, _, err = run(capsys, "profile", LECTURE, "-o", tmp_path / "new", "--force")
    assert one_line_error(code, err) and "is a folder" in err
    code, _, err = run(capsys, "profile", LECTURE, "-o", tmp_path / "x.dxf", "--tolerance", "inf")
    assert one_line_error(code, err) and "--tolerance" in err


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root writes anywhere")
def test_an_unwritable_folder_is_refused_before_the_work(capsys, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    code, _, err = run(capsys, "sweep", LECTURE, "--speeds", "300:300:1", "-o", locked)
    assert one_line_error(code, err) and "permission" in err


@pytest.mark.slow
@pytest.mark.parametrize("name", ["../escaped", "/tmp/camdyn-absolute", "a/b\\c", ".."])
def test_a_case_name_is_data_not_a_path(capsys, tmp_path, name):
    text = LECTURE.read_text().replace('name = "lecture"', f"name = {json.dumps(name)}")
    (tmp_path / "in").mkdir()
    case = tmp_path / "in" / "c.toml"
    case.write_text(text)
    out = tmp_path / "in" / "out"
    before = set(tmp_path.rglob("*")) | set(Path("/tmp").glob("camdyn-absolute*"))
    code, _, err = run(capsys, "sweep", case, "--speeds", "300:300:1", "-o", out)
    assert code == 0, err
    written = (set(tmp_path.rglob("*")) | set(Path("/tmp").glob("camdyn-absolute*"))) - before
    assert written and all(out in p.parents or p == out for p in written), written


@pytest.mark.parametrize("law", ["3", "inf", None])
def test_a_segment_whose_law_is_not_a_name_is_told_so(capsys, tmp_path, law):
    """A polynomial segment's law mistyped or missing: the law is named, not the boundary conditions it decides."""
    text = (ROOT / "cases" / "polynomial.toml").read_text()
    old = '{ law = "polynomial", end = 80,'
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, "{ end = 80," if law is None else f"{{ law = {law}, end = 80,", 1))
    code, _, err = run(capsys, "check", path)
    assert one_line_error(code, err) and "motion.segments[0]" in err
    assert "only a law" not in err  # not "start_jerk: only a law = polynomial segment takes ... (this one is 3)"
    assert ("law: Input should be a valid string" in err) if law else ("valid keys: law, end, lift" in err)


# ----------------------------------------------------------------------------------------------- fuzz
_MUTATIONS = ("drop", math.nan, math.inf, -math.inf, 1e12, -1e12, 0, -1, True, "x", [1, 2], {"a": 1})


def _mutants(seed: int, count: int):
    """Mutated case files: one key of a shipped case dropped or replaced by something wrong."""
    rng = random.Random(seed)
    docs = [(p.name, tomllib.loads(p.read_text())) for p in CASES]
    for _ in range(count):
        name, doc = rng.choice(docs)
        doc = json.loads(json.dumps(doc))  # a deep copy
        tables = [k for k, v in doc.items() if isinstance(v, dict)]
        table = rng.choice(tables)
        key = rng.choice(list(doc[table]))
        value = rng.choice(_MUTATIONS)
        if value == "drop":
            del doc[table][key]
        elif isinstance(doc[table][key], list) and doc[table][key] and isinstance(doc[table][key][0], dict):
            seg = rng.choice(doc[table][key])  # a motion segment: mutate one of its keys
            seg[rng.choice(list(seg))] = value
        else:
            doc[table][key] = value
        yield name, table, key, doc


def _toml(doc: dict) -> str:
    """TOML text of a mutated case; non-finite floats as TOML's nan/inf (tomli-w refuses them)."""
    import tomli_w

    def fix(v):
        if isinstance(v, float) and not math.isfinite(v):
            return f"__{v}__"
        if isinstance(v, dict):
            return {k: fix(x) for k, x in v.items()}
        if isinstance(v, list):
            return [fix(x) for x in v]
        return v

    text = tomli_w.dumps(fix(doc))
    return text.replace('"__nan__"', "nan").replace('"__inf__"', "inf").replace('"__-inf__"', "-inf")


@pytest.mark.slow
def test_fuzz_every_mutant_ends_in_a_verdict_or_one_line(capsys, tmp_path):
    """Mutants the schema refuses are checked through `camdyn check` in full (the error comes before any
    physics); of those it accepts, a sample of the motion cases runs the whole check (a path case's synthesis
    alone takes seconds). Exit 0, 1 or 2, at most 3 lines on stderr,
    never an internal error."""
    full_checks = 0
    for i, (name, table, key, doc) in enumerate(_mutants(seed=13, count=300)):
        path = tmp_path / f"m{i}.toml"
        path.write_text(_toml(doc))
        try:
            load_case_spec(path)
        except InputError:
            accepted = False
        else:
            accepted = True
        if accepted and (full_checks >= 6 or "path" in doc):  # a sample of full checks, of quick cases
            continue
        full_checks += accepted
        code, out, err = run(capsys, "check", path)
        where = f"mutant {i} of {name}: {table}.{key} ({err.strip()[:200]})"
        assert code in (0, 1, 2), where
        assert len(err.strip().splitlines()) <= 3, where
        assert "internal error" not in err and "Traceback" not in err, where


def test_profile_of_an_undercut_flat_cam_warns(capsys, tmp_path):
    """Issue 13, 15: `profile` draws an undercut cam (it can be made) but says, as `check` does, that it folds."""
    text = (
        LECTURE.read_text()
        .replace('type = "translating-roller"', 'type = "translating-flat"')
        .replace("base_radius = 40", "base_radius = 5")
    )
    text = "\n".join(line for line in text.splitlines() if not line.startswith("roller_radius"))
    case = tmp_path / "flat.toml"
    case.write_text(text)
    code, out, err = run(capsys, "profile", case, "-o", tmp_path / "cam.csv")
    assert code == 0 and out.startswith("wrote ") and "warning: undercut: the contour folds" in err


@pytest.mark.slow
def test_many_landings_of_a_rigid_follower_are_one_warning(tmp_path, capsys):
    """Forty 1 mm cycloids at 300 rpm: a rigid follower leaves the cam ten times; check says so in one line with
    the worst gap and impact (the JSON keeps each flight), not ten lines (1000 segments gave 400)."""
    segments = ",\n".join(f'{{ law = "cycloidal", end = {9 * (i + 1)}, lift = {1 - 2 * (i % 2)} }}' for i in range(40))
    case = tmp_path / "ripple.toml"
    case.write_text(
        f"[motion]\nsegments = [\n{segments}\n]\n"
        '[follower]\ntype = "translating-roller"\nbase_radius = 60\nroller_radius = 10\n'
        "[dynamics]\nspeed = 300\nmass = 1\nspring_rate = 10\npreload = 50\n"
    )
    code, out, _ = run(capsys, "check", case, "--json")
    doc = json.loads(out)
    seps = doc["dynamic"]["separations"]
    notes = [w for w in doc["warnings"] if w.startswith("the follower leaves the cam")]
    assert code == 1 and len(seps) > 4 and len(notes) == 1
    assert notes[0].startswith(f"the follower leaves the cam {len(seps)} times a revolution at 300 rpm")
    assert f"gap up to {max(s['max_gap_mm'] for s in seps):.3g} mm" in notes[0]
    assert f"impacts up to {max(s['impact_speed_m_s'] for s in seps):.3g} m/s" in notes[0]


@pytest.mark.parametrize(
    ("extra", "key"),
    [
        (["--coordinator", "foo"], "--coordinator: expected the coordinator's address as host:port"),
        (["--coordinator", "localhost:9999"], "--num-processes: several processes need it"),
        (["--coordinator", "localhost:9999", "--num-processes", "2"], "--process-id: several processes need it"),
    ],
)
def test_a_coordinator_without_its_processes_is_one_line(capsys, tmp_path, extra, key):
    """Several processes need the coordinator as host:port and each process's count and id: said before JAX's
    runtime is asked (it failed with 'Number of processes must be defined', an internal error)."""
    code, _, err = run(capsys, "sweep", LECTURE, "--speeds", "100:200:2", "-o", tmp_path, *extra)
    assert code == 2 and key in err and len(err.strip().splitlines()) == 1, err


def test_the_ringing_of_a_train_at_a_vanishing_speed_is_no_overflow():
    """At 1e-300 rpm the train vibrates 1e304 times a revolution: its ringing vanishes, not an OverflowError of a
    float's square (an internal error of ``check --speed 1e-300``)."""
    from camdyn.model.dynamics._compliant import _ringing

    motion = load_case(LECTURE).motion
    assert _ringing(motion, 1e304) < 1e-300 and 0.0 < _ringing(motion, 10.0) < 1.0


def test_a_long_name_makes_a_stem_a_file_system_takes():
    """A case name of 300 characters made a file name past the 255 bytes a file system takes (an internal error of
    ``sweep``): a stem is cut at MAX_STEM with a digest of the whole name, so two names that differ past the cut still
    name two files; a short one is as it was."""
    from camdyn._core.outputs import MAX_STEM, safe_stem

    a, b = safe_stem("a" * 300), safe_stem("a" * 299 + "b")
    assert len(a) <= MAX_STEM and len(b) <= MAX_STEM and a != b and a.startswith("a" * 80)
    assert safe_stem("../lecture cam") == "lecture-cam" and safe_stem("x" * MAX_STEM) == "x" * MAX_STEM


def test_a_case_written_elsewhere_names_its_data_files_from_there(tmp_path):
    """``tolerance`` writes its worst samples as case files in its output folder: a data file the case names by a
    relative path is named from there (``check`` of a worst sample said 'valve-lift.csv: no such file'); an absolute
    one as it is; the case's own document is not changed."""
    from camdyn.schema import moved_data_files

    doc = {"motion": {"table": "lift.csv"}, "follower": {"contour": "/abs/cam.csv", "type": "flat"}, "dynamics": {}}
    out = moved_data_files(doc, tmp_path / "in", tmp_path / "in" / "out" / "deep")
    assert out["motion"]["table"] == "../../lift.csv" and out["follower"]["contour"] == "/abs/cam.csv"
    assert doc["motion"]["table"] == "lift.csv" and out["dynamics"] is doc["dynamics"]


@pytest.mark.slow  # a map of one point still compiles the map's gap stepping (3 s)
def test_a_name_the_plot_font_cannot_draw_leaves_a_quiet_run_quiet(capsys, tmp_path):
    """A case named in characters DejaVu Sans lacks (CJK, an emoji): its plots draw boxes, and ``--quiet`` prints
    nothing on stderr (matplotlib warned of each glyph in two lines of its own source)."""
    case = tmp_path / "c.toml"
    case.write_text(
        LECTURE.read_text().replace('name = "lecture"', 'name = "Nocke \u00fc \u2014 \u51f8\u8f6e \U0001f680"')
    )
    with warnings.catch_warnings(record=True) as caught:  # as a process shows them, not as pytest collects them
        warnings.simplefilter("always")
        code, _, err = run(capsys, "sweep", case, "--speeds", "300:300:1", "-o", tmp_path / "out", "--quiet")
    assert code == 0 and err == "", err
    assert not [w for w in caught if "missing from" in str(w.message)]


def test_a_lift_below_zero_names_the_segment_not_the_spring(capsys, tmp_path):
    """A polynomial whose boundary conditions send it 69 mm below the base circle leaves the spring pulling the
    follower off the cam at rest: the segment is named (it was blamed on ``dynamics.preload``); a spring too weak for
    a motion that stays above zero is still the preload's."""
    text = (ROOT / "cases" / "polynomial.toml").read_text()
    old = "end_acceleration = -40 }"
    assert old in text
    (tmp_path / "under.toml").write_text(text.replace(old, "end_acceleration = -4000 }", 1))
    code, _, err = run(capsys, "check", tmp_path / "under.toml")
    assert one_line_error(code, err) and "motion.segments[0]: the lift goes below zero, to -69.12 mm" in err, err
    (tmp_path / "weak.toml").write_text(LECTURE.read_text().replace("preload = 30", "preload = -10"))
    code, _, err = run(capsys, "check", tmp_path / "weak.toml")
    assert one_line_error(code, err) and "dynamics.preload: the spring cannot hold" in err, err
