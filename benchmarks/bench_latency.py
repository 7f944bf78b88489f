"""Benchmark: the latency a user feels, as ratios to a bare ``import jax, diffrax`` measured in the same run.

    python benchmarks/bench_latency.py [--repeat 5] [--cases lecture oscillating | all] [--new] [--against DIR]

Fresh processes, round-robin (one of each per round, so a change in the machine's load moves them alike), best of
``--repeat`` walls each:

* ``python -c "import jax, diffrax"``: the floor every command that computes stands on;
* ``camdyn check cases/<case>.toml`` with warm caches (a private cache directory, filled by one run first: JAX's
  and camdyn's programs and Python's bytecode, as a user's install has them);
  goal (issue 23): at most 1.5 x the bare import;
* a bad option (``check cases/lecture.toml --bogus``), a case whose ``[motion] table`` names a missing file and
  options whose values are out of bounds or do not apply (:data:`BAD_VALUES`): goal, reported (exit 2) before JAX
  loads, under 0.5 s;
* with ``--new``, the first ``check`` of a never-seen variant of each case, in the cache the shipped cases filled:
  a copy with one set of numbers changed, new every round, so that its structure is the case's and its values
  new (:func:`variant`: a program's lifts and B-spline control points, a lift table's or a contour's values, a
  path's size); goal (issue 23): at most 2 x the warm ``check`` of its case.

``--cases all`` is every shipped case (``cases/*.toml``; ``cases/paths`` holds path files, ``cases/machines`` the
inputs of ``camdyn machine``).

``--against DIR`` also times ``check`` from another camdyn source tree (say a worktree of the commit before a
change) in the same rounds, with its own private cache. The CPU time (user + system) of each best run is beside
its wall: on a loaded machine it moves less. The load average is printed.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_dynamics import print_table, with_bytecode  # noqa: E402  (the shared table printer, the bytecode)

ROOT = HERE.parent
BARE = "import jax, diffrax"
GOAL_CHECK = 1.5  # x the bare import (issue 23)
GOAL_NEW = 2.0  # x the warm check of the case (issue 23)
GOAL_ERROR_S = 0.5
# options whose values a user mistypes, each refused in one line before JAX loads ({tmp}: the run's own folder)
BAD_VALUES = {
    "camdyn table cases/lecture.toml --step 0": ["table", "--step", "0"],
    "camdyn sweep cases/lecture.toml --speeds 700:100:3": ["sweep", "--speeds", "700:100:3"],
    "camdyn profile cases/lecture.toml -o cam.nc (no --cutter-radius)": ["profile", "-o", "{tmp}/cam.nc"],
    "camdyn size cases/lecture.toml --margin -1": ["size", "--margin", "-1"],
}
PATH_SIZES = ("radius", "width", "height", "straight", "corner_radius")  # a path's size keys, scaled by a variant


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _run(argv: list[str], env: dict, cwd: Path) -> tuple[float, float, int, str]:
    """(wall s, CPU s, exit code, last line of stderr) of one fresh process."""
    cpu0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    return wall, cpu, proc.returncode, (proc.stderr.strip().splitlines() or [""])[-1]


def _env(source: Path, cache: Path) -> dict:
    """A fresh process's environment with its caches in ``cache``: JAX's and camdyn's programs (``XDG_CACHE_HOME``)
    and Python's bytecode (:func:`bench_dynamics.with_bytecode`; the bare import's too)."""
    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"}
    env |= {"PYTHONPATH": os.pathsep.join([str(source), env.get("PYTHONPATH", "")]), "XDG_CACHE_HOME": str(cache)}
    return with_bytecode(env, cache / "bytecode")


def _scaled(value: float, f: float, plus: float = 0.0) -> str:
    """``plus + value * f`` as TOML, to 9 decimals."""
    return repr(round(plus + value * f, 9))


def _scale_csv(source: Path, target: Path, columns: slice, f: float) -> None:
    """``source``'s rows with the numbers of ``columns`` scaled by ``f``, written to ``target`` to as many decimals."""
    out = []
    for line in source.read_text().splitlines():
        cells = line.split(",")
        try:
            for i in range(len(cells))[columns]:
                decimals = len(cells[i].strip().partition(".")[2])
                cells[i] = f"{float(cells[i]) * f:.{decimals}f}"
        except ValueError:  # the header
            pass
        out.append(",".join(cells))
    target.write_text("\n".join(out) + "\n")


def _key(text: str, key: str, new) -> str:
    """``text`` with every number (or list of numbers) given to ``key`` replaced by ``new(value)``."""
    number = r"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
    pattern = rf"(?<![\w.]){key}(\s*=\s*)(\[[^\]]*\]|{number})"

    def sub(m: re.Match) -> str:
        value = tomllib.loads(f"v = {m.group(2)}")["v"]
        return f"{key}{m.group(1)}{new(value)}"

    return re.sub(pattern, sub, text)


def variant(case: Path, f: float, into: Path) -> Path:
    """A never-seen variant of the shipped ``case``, written into ``into``: the same structure, values scaled by ``f``
    (near 1): a segment program's lifts (every one, so that it still closes) and B-spline control points (|c| ** f
    with c's sign: still monotone from 0 to 1), a lift table's lifts, a contour's points, a path's size (about its own
    centre)."""
    text = case.read_text()
    doc = tomllib.loads(text)
    motion, follower, path = doc.get("motion", {}), doc.get("follower", {}), doc.get("path", {})
    name = f"{case.stem}-{f:.6f}"
    if "table" in motion or "valve_table" in motion or "contour" in follower:
        data = motion.get("table") or motion.get("valve_table") or follower["contour"]
        csv = f"{name}.csv"
        _scale_csv(case.parent / data, into / csv, slice(1, 2) if "contour" not in follower else slice(0, 2), f)
        text = text.replace(f'"{data}"', f'"{csv}"')
    elif "segments" in motion:
        text = _key(text, "lift", lambda v: _scaled(v, f))
        text = _key(
            text, "coefficients", lambda c: "[" + ", ".join(repr(math.copysign(abs(x) ** f, x)) for x in c) + "]"
        )
    elif path.get("type") == "points":
        for key in ("x", "y"):
            mid = sum(path[key]) / len(path[key])
            text = _key(text, key, lambda v, mid=mid: "[" + ", ".join(_scaled(x - mid, f, mid) for x in v) + "]")
    elif path.get("type") == "line":
        (x0, y0), (x1, y1) = path["start"], path["end"]
        text = _key(text, "end", lambda _: f"[{_scaled(x1 - x0, f, x0)}, {_scaled(y1 - y0, f, y0)}]")
    elif path:
        for key in PATH_SIZES:
            text = _key(text, key, lambda v: _scaled(v, f))
    else:
        raise ValueError(f"{case}: no variant for this kind of case")
    target = into / f"{name}.toml"
    target.write_text(text.replace(f'name = "{case.stem}"', f'name = "{name}"', 1))
    return target


def shipped(names: list[str]) -> list[str]:
    """The case names ``--cases`` gives: ``all`` is every ``cases/*.toml``."""
    return sorted(p.stem for p in (ROOT / "cases").glob("*.toml")) if names == ["all"] else names


def case_file(case: str) -> Path:
    """A ``--cases`` name's file: ``cases/NAME.toml``, or a case file of the user's (a path ending in .toml)."""
    return Path(case).resolve() if case.endswith(".toml") else ROOT / "cases" / f"{case}.toml"


def case_label(case: str) -> str:
    """How a ``--cases`` name's file is named in the table."""
    return case if case.endswith(".toml") else f"cases/{case}.toml"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="rounds; the best of each is shown (default 5)")
    ap.add_argument(
        "--cases",
        nargs="+",
        default=["lecture", "oscillating"],
        metavar="NAME",
        help="shipped cases/NAME.toml, all (every one), or a case file's path (ending in .toml)",
    )
    ap.add_argument(
        "--new", action="store_true", help="also the first check of a never-seen variant of each case, every round"
    )
    ap.add_argument("--against", type=Path, metavar="DIR", help="another camdyn source tree to time check from")
    opts = ap.parse_args()
    cases = shipped(opts.cases)
    t_all = time.perf_counter()
    tmp = Path(tempfile.mkdtemp(prefix="camdyn-bench-latency-"))
    try:
        missing = tmp / "missing-table.toml"
        missing.write_text((ROOT / "cases" / "valve-lift.toml").read_text().replace("valve-lift.csv", "nope.csv"))
        py = [sys.executable]
        trees = [("", ROOT)] + ([(f" [{opts.against}]", opts.against.resolve())] if opts.against else [])
        # name: (argv of each round, environment, whether a warm-up run comes first)
        jobs: dict[str, tuple[list[list[str]], dict, bool]] = {
            "bare": ([[*py, "-c", BARE]] * opts.repeat, _env(ROOT, tmp / "cache"), True)
        }
        new_cases = tmp / "new"
        new_cases.mkdir()
        for tag, tree in trees:
            env = _env(tree, tmp / f"cache{len(jobs)}")
            for case in cases:
                argv = [*py, "-m", "camdyn", "check", str(case_file(case)), "--quiet"]
                jobs[f"camdyn check {case_label(case)}, warm caches{tag}"] = ([argv] * opts.repeat, env, True)
            if opts.new and not tag:  # this tree's: in the cache its shipped cases filled, a new variant each round
                for case in cases:
                    argvs = [
                        [*py, "-m", "camdyn", "check", str(variant(case_file(case), f, new_cases))] + ["--quiet"]
                        for f in [1.0 + 0.002 * (i + 1) for i in range(opts.repeat)]
                    ]
                    jobs[f"camdyn check, new {case} variant, first{tag}"] = (argvs, env, False)
        env = _env(ROOT, tmp / "cache")
        bogus = [*py, "-m", "camdyn", "check", str(ROOT / "cases" / "lecture.toml"), "--bogus"]
        jobs["camdyn check cases/lecture.toml --bogus"] = ([bogus] * opts.repeat, env, True)
        jobs["camdyn check, [motion] table missing"] = (
            [[*py, "-m", "camdyn", "check", str(missing)]] * opts.repeat,
            env,
            True,
        )
        lecture = str(ROOT / "cases" / "lecture.toml")
        for label, argv in BAD_VALUES.items():  # an option's value out of bounds, or an option that does not apply
            args = [a.format(tmp=tmp) for a in argv]
            jobs[label] = ([[*py, "-m", "camdyn", args[0], lecture, *args[1:]]] * opts.repeat, env, True)

        def run(name: str, argv: list[str], env: dict) -> tuple[float, float, int, str]:
            """One timed run: a check gives a verdict (exit 0 or 1), a refused input exit 2."""
            r = _run(argv, env, tmp)
            if r[2] not in ((0, 1) if "warm caches" in name or ", new " in name else (2,)) and name != "bare":
                raise RuntimeError(f"{name}: exit {r[2]}: {r[3]}")
            return r

        for name, (argvs, env, warm_up) in jobs.items():  # warm-up: fills each tree's caches, loads the files
            if warm_up:
                run(name, argvs[0], env)
        best: dict[str, tuple[float, float, int, str]] = {}
        for i in range(opts.repeat):
            for name, (argvs, env, _) in jobs.items():
                r = run(name, argvs[i], env)
                if name not in best or r[0] < best[name][0]:
                    best[name] = r
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    bare = best["bare"][0]
    rows = [(f'python -c "{BARE}"', f"{bare:.2f} s", f"cpu {best['bare'][1]:.2f} s; the unit of the ratios")]
    for name, (wall, cpu, code, err) in best.items():
        if name == "bare":
            continue
        if "warm" in name:
            goal = f"goal <= {GOAL_CHECK:g} x"
        elif ", new " in name:
            case = name.split(", new ")[1].split(" variant")[0]
            warm = best[f"camdyn check {case_label(case)}, warm caches"][0]
            goal = f"{wall / warm:.2f} x the shipped case's warm check, goal <= {GOAL_NEW:g} x"
        else:
            goal = f"goal < {GOAL_ERROR_S:g} s; exit {code}: {err.replace(f'{tmp}/', '')[:70]}"
        rows.append((name, f"{wall:.2f} s", f"{wall / bare:.2f} x the bare import, cpu {cpu:.2f} s; {goal}"))
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    title = f"latency, fresh processes, best of {opts.repeat} (load average {load:.2f}, {os.cpu_count()} CPUs)"
    print_table(title, rows, t_all)
    return 0


if __name__ == "__main__":
    sys.exit(main())
