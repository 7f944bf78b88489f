"""Benchmark: the latency a user feels, as ratios to a bare ``import jax, diffrax`` measured in the same run.

    python benchmarks/bench_latency.py [--repeat 5] [--cases lecture oscillating] [--against DIR]

Fresh processes, round-robin (one of each per round, so a change in the machine's load moves them alike), best of
``--repeat`` walls each:

* ``python -c "import jax, diffrax"``: the floor every command that computes stands on;
* ``camdyn check cases/<case>.toml`` with warm caches (a private cache directory, filled by one run first);
  goal (issue 23): at most 1.5 x the bare import;
* a bad option (``check cases/lecture.toml --bogus``) and a case whose ``[motion] table`` names a missing file:
  goal, reported (exit 2) before JAX loads, under 0.5 s.

``--against DIR`` also times ``check`` from another camdyn source tree (say a worktree of the commit before a
change) in the same rounds, with its own private cache. The CPU time (user + system) of each best run is beside
its wall: on a loaded machine it moves less. The load average is printed.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_dynamics import print_table  # noqa: E402  (the shared table printer)

ROOT = HERE.parent
BARE = "import jax, diffrax"
GOAL_CHECK = 1.5  # x the bare import (issue 23)
GOAL_ERROR_S = 0.5


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
    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"}
    return env | {"PYTHONPATH": os.pathsep.join([str(source), env.get("PYTHONPATH", "")]), "XDG_CACHE_HOME": str(cache)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="rounds; the best of each is shown (default 5)")
    ap.add_argument(
        "--cases", nargs="+", default=["lecture", "oscillating"], metavar="NAME", help="shipped cases/NAME.toml"
    )
    ap.add_argument("--against", type=Path, metavar="DIR", help="another camdyn source tree to time check from")
    opts = ap.parse_args()
    t_all = time.perf_counter()
    tmp = Path(tempfile.mkdtemp(prefix="camdyn-bench-latency-"))
    try:
        missing = tmp / "missing-table.toml"
        missing.write_text((ROOT / "cases" / "valve-lift.toml").read_text().replace("valve-lift.csv", "nope.csv"))
        py = [sys.executable]
        trees = [("", ROOT)] + ([(f" [{opts.against}]", opts.against.resolve())] if opts.against else [])
        jobs: dict[str, tuple[list[str], dict]] = {"bare": ([*py, "-c", BARE], _env(ROOT, tmp / "cache"))}
        for tag, tree in trees:
            env = _env(tree, tmp / f"cache{len(jobs)}")
            for case in opts.cases:
                argv = [*py, "-m", "camdyn", "check", str(ROOT / "cases" / f"{case}.toml"), "--quiet"]
                jobs[f"camdyn check cases/{case}.toml, warm caches{tag}"] = (argv, env)
        env = _env(ROOT, tmp / "cache")
        jobs["camdyn check cases/lecture.toml --bogus"] = (
            [*py, "-m", "camdyn", "check", str(ROOT / "cases" / "lecture.toml"), "--bogus"],
            env,
        )
        jobs["camdyn check, [motion] table missing"] = ([*py, "-m", "camdyn", "check", str(missing)], env)
        for name, (argv, env) in jobs.items():  # warm-up: fills each tree's caches, loads the files into memory
            if _run(argv, env, tmp)[2] not in (0, 1, 2):
                raise RuntimeError(f"{name} failed")
        best: dict[str, tuple[float, float, int, str]] = {}
        for _ in range(opts.repeat):
            for name, (argv, env) in jobs.items():
                r = _run(argv, env, tmp)
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
        else:
            goal = f"goal < {GOAL_ERROR_S:g} s; exit {code}: {err[:70]}"
        rows.append((name, f"{wall:.2f} s", f"{wall / bare:.2f} x the bare import, cpu {cpu:.2f} s; {goal}"))
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    title = f"latency, fresh processes, best of {opts.repeat} (load average {load:.2f}, {os.cpu_count()} CPUs)"
    print_table(title, rows, t_all)
    return 0


if __name__ == "__main__":
    sys.exit(main())
