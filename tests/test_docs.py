"""The documentation cannot drift: the generated key reference equals the schema's, every key of the shipped
case files is in it, its per-type key tables agree with the validators, and the links between the docs resolve.
No JAX: these tests read the schema and the Markdown only."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path
from typing import Literal

import pytest

from camdyn import CaseSpec, InputError
from camdyn.schema import LINEAR_KEYS, ROTARY_KEYS, Table, parse, reference

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "docs" / "reference"


def test_committed_reference_is_what_the_schema_gives():
    for name, text in reference.generated().items():
        committed = (REFERENCE / name).read_text(encoding="utf-8")
        assert committed == text, f"docs/reference/{name} is stale: run python -m camdyn.schema.reference"


def test_main_writes_and_checks(tmp_path, capsys):
    assert reference.main(["--check", str(tmp_path)]) == 1
    assert reference.main([str(tmp_path)]) == 0
    assert reference.main(["--check", str(tmp_path)]) == 0
    (tmp_path / reference.MARKDOWN).write_text("stale\n", encoding="utf-8")
    assert reference.main(["--check", str(tmp_path)]) == 1
    assert "differs from the schema" in capsys.readouterr().err


# -- every shipped key is documented ----------------------------------------------------------------------------


def _documented() -> dict[str, set[str]]:
    """Heading of each section of the reference -> the keys in its first column."""
    out: dict[str, set[str]] = {}
    heading = ""
    for line in (REFERENCE / reference.MARKDOWN).read_text(encoding="utf-8").splitlines():
        if line.startswith("#"):
            heading = line.lstrip("#").strip()
            out[heading] = set()
        elif line.startswith("| ") and (key := re.match(r"\|\s*\[?`([^`]+)`", line)):
            out[heading].add(key.group(1))
    return out


def _keys(table: dict, where: str):
    """(section heading, key) for every key of a TOML table, depth first."""
    for key, value in table.items():
        if isinstance(value, dict):
            yield where, f"[{key}]" if where in ("Case file", "Path file") else key
            yield from _keys(value, f"`[{key}]`")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            yield where, key
            for item in value:
                yield from _keys(item, f"`[[{where.strip('`[]')}.{key}]]`")
        else:
            yield where, key


SHIPPED = sorted((ROOT / "cases").glob("*.toml")) + sorted((ROOT / "cases" / "paths").glob("*.toml"))


@pytest.mark.parametrize("case", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_key_of_a_shipped_case_is_documented(case):
    documented = _documented()
    top = "Path file" if case.parent.name == "paths" else "Case file"
    keys = list(_keys(tomllib.loads(case.read_text(encoding="utf-8")), top))
    assert keys
    missing = [f"{where}: {key}" for where, key in keys if key not in documented.get(where, set())]
    assert not missing, f"keys of {case.name} not in the reference: {missing}"


# -- the per-type tables agree with the validators ------------------------------------------------------------

SEGMENTS = [
    {"law": "dwell", "end": 90},
    {"law": "cycloidal", "end": 180, "lift": 20},
    {"law": "dwell", "end": 240},
    {"law": "harmonic", "end": 360, "lift": -20},
]
TRANSLATING = {"speed": 300.0, "mass": 0.5, "spring_rate": 2.0, "preload": 30.0}
OSCILLATING = {"speed": 200.0, "inertia": 0.002, "torsion_rate": 5.0, "preload_torque": 2.0}

# a valid value of every type-specific key (a case needs only its own type's)
SAMPLE = {
    "follower": {
        "roller_radius": 8.0,
        "pivot_distance": 110.0,
        "arm_length": 90.0,
        "offset": 2.0,
        "pivot_angle": 10.0,
        "face_width": 30.0,
    },
    "path": {
        "center": [0.0, 0.0],
        "semi_major": 20.0,
        "semi_minor": 10.0,
        "radius": 10.0,
        "width": 40.0,
        "height": 20.0,
        "corner_radius": 2.0,
        "straight": 50.0,
        "start": [0.0, 0.0],
        "end": [10.0, 0.0],
        "x": [0.0, 10.0, 10.0, 0.0],
        "y": [0.0, 0.0, 10.0, 10.0],
    },
    "mechanism": {
        "link": 60.0,
        "slider_angle": 90.0,
        "pivot": [-100.0, -80.0],
        "path_link": 260.0,
        "follower_link": 205.0,
        "pin_distance": 150.0,
        "arm": 115.0,
        "joint_distance": 5.0,
        "joint_angle": 10.0,
        "slider_point": [1.0, 2.0],
        "slider_mode": -1,
        "base_radius": 30.0,
        "max_pressure_angle": 25.0,
        "arm_angle": 170.0,
        "follower_mode": -1,
    },
}

# keys of another type a validator accepts (none: every table refuses them)
ACCEPTED_NOT_USED: set[tuple[str, str, str]] = set()


def _case(table: str, kind: str, keys: dict) -> dict:
    """A case whose ``table`` has ``type = kind`` and ``keys``; the other tables minimal and valid."""
    body = {"type": kind, **keys}
    if table == "follower":
        return {
            "motion": {"segments": SEGMENTS},
            "follower": {"base_radius": 40.0, **body},
            "dynamics": OSCILLATING if kind.startswith("oscillating") else TRANSLATING,
        }
    if table == "path":
        return {"path": body, "mechanism": {"type": "ccm", "link": 60.0, "slider_angle": 90.0}, "dynamics": TRANSLATING}
    return {
        "path": {"type": "circle", "center": [0.0, 0.0], "radius": 20.0},
        "mechanism": body,
        "dynamics": OSCILLATING if kind == "oscillating" else TRANSLATING,
    }


def _refused(raw: dict) -> str:
    with pytest.raises(InputError) as err:
        parse(CaseSpec, raw)
    return err.value.where


TYPED = {t: reference.type_keys(CaseSpec.model_fields[t].annotation) for t in ("follower", "path", "mechanism")}


@pytest.mark.parametrize(("table", "kind"), [(t, k) for t, tk in TYPED.items() for k in tk.by_type])
def test_needed_and_optional_keys_are_what_the_validator_takes(table, kind):
    needs, optional = TYPED[table].by_type[kind]
    sample = SAMPLE[table]
    parse(CaseSpec, _case(table, kind, {k: sample[k] for k in needs}))
    for key in needs:
        assert _refused(_case(table, kind, {k: sample[k] for k in needs if k != key})) == f"{table}.{key}"
    for key in optional:
        parse(CaseSpec, _case(table, kind, {**{k: sample[k] for k in needs}, key: sample[key]}))


def _other_keys():
    for table, tk in TYPED.items():
        named = {k for n, o in tk.by_type.values() for k in (*n, *o)}
        for kind, (needs, optional) in tk.by_type.items():
            for key in sorted(named - set(needs) - set(optional)):
                mark = (
                    pytest.mark.xfail(strict=True, reason="validator ignores it")
                    if (table, kind, key) in ACCEPTED_NOT_USED
                    else ()
                )
                yield pytest.param(table, kind, key, marks=mark, id=f"{table}-{kind}-{key}")


@pytest.mark.parametrize(("table", "kind", "key"), list(_other_keys()))
def test_a_key_of_another_type_is_refused(table, kind, key):
    needs, _ = TYPED[table].by_type[kind]
    sample = SAMPLE[table]
    assert _refused(_case(table, kind, {**{k: sample[k] for k in needs}, key: sample[key]})) == f"{table}.{key}"


@pytest.mark.parametrize(
    ("kind", "dynamics", "keys"),
    [("translating-roller", TRANSLATING, LINEAR_KEYS), ("oscillating-roller", OSCILLATING, ROTARY_KEYS)],
)
def test_dynamics_needs_the_first_three_keys_of_its_kind(kind, dynamics, keys):
    case = _case("follower", kind, {k: SAMPLE["follower"][k] for k in TYPED["follower"].by_type[kind][0]})
    for key in keys[:3]:
        assert _refused({**case, "dynamics": {k: v for k, v in dynamics.items() if k != key}}) == f"dynamics.{key}"


def test_type_keys_of_a_discriminated_union():
    """The shape PathSpec or MechanismSpec may take: one model per type."""

    class A(Table):
        type: Literal["a"]
        x: float
        shared: float = 0.0

    class B(Table):
        type: Literal["b"]
        y: float = 1.0
        shared: float = 0.0

    class Doc(Table):
        """A toy file."""

        thing: A | B | None = None

    tk = reference.type_keys(Doc.model_fields["thing"].annotation)
    assert tk.common == ("shared",)
    assert tk.by_type == {"a": (("x",), ()), "b": ((), ("y",))}
    md = reference.reference_markdown([("Toy file", Doc)])
    assert (
        '| `type`   | string | `"a"`, `"b"` | required |' in md
        and "| `x`      | number |              | by type  |" in md
    )
    assert "| `a`    | `x`   | —" in md and "| `b`    | —     | `y`" in md


# -- the README and the docs ----------------------------------------------------------------------------------


def test_readme_quick_start_is_the_two_commands():
    """CI (.ci/run) runs the second; the first is what a newcomer types."""
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    test_command = "pip install -e '.[test]' -c constraints.txt && python -m pytest"
    assert "pip install . && camdyn check cases/lecture.toml" in lines
    assert test_command in lines
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    install, tests = test_command.split(" && ")
    style, types = "ruff check . && ruff format --check .", "pyright"
    assert ci.index(install) < ci.index(style) < ci.index(types) < ci.index(tests)  # style and types first
    assert f"`{style}` and `{types}` between them" in " ".join(lines)


def _anchors(md: Path) -> set[str]:
    """GitHub's anchors of a Markdown file's headings."""
    out = set()
    for line in md.read_text(encoding="utf-8").splitlines():
        if re.match(r"#{1,6} ", line):
            slug = re.sub(r"[^\w\- ]", "", line.lstrip("#").strip().lower()).replace(" ", "-")
            out.add(slug if slug not in out else next(f"{slug}-{i}" for i in range(1, 99) if f"{slug}-{i}" not in out))
    return out


DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


@pytest.mark.parametrize("md", DOCS, ids=lambda p: str(p.relative_to(ROOT)))
def test_links_between_the_docs_resolve(md):
    text = re.sub(r"```.*?```", "", md.read_text(encoding="utf-8"), flags=re.S)
    broken = []
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue
        name, _, anchor = target.partition("#")
        path = (md.parent / name).resolve() if name else md
        if not path.exists():
            broken.append(target)
        elif anchor and path.suffix == ".md" and anchor not in _anchors(path):
            broken.append(target)
    assert not broken, f"{md.name}: broken links {broken}"


@pytest.mark.slow
def test_readme_example_is_what_check_prints(capsys):
    """The README's worked example is the real output of ``camdyn check cases/lecture.toml``."""
    from camdyn.cli import main

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    shown = re.search(r"```console\n\$ camdyn check cases/lecture.toml\n(.*?)```", readme, re.S).group(1)
    assert main(["check", str(ROOT / "cases" / "lecture.toml")]) == 0
    assert [line.rstrip() for line in capsys.readouterr().out.splitlines()] == shown.splitlines()


def test_whiteboard_names_only_paths_that_exist():
    """docs/whiteboard.json moves with the folders it names."""
    board = json.loads((ROOT / "docs" / "whiteboard.json").read_text())
    paths = [p for part in board["parts"].values() for p in part["is"]]
    assert paths and all((ROOT / p).exists() for p in paths), [p for p in paths if not (ROOT / p).exists()]
    covered = {p.rstrip("/") for p in paths}
    packages = {str(d.relative_to(ROOT)) for d in (ROOT / "camdyn").iterdir() if (d / "__init__.py").exists()}
    assert packages <= covered, packages - covered
