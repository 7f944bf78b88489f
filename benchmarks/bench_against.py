"""Benchmark: ``camdyn check`` and ``camdyn optimize`` from this tree against another camdyn source tree, in one run.

    python benchmarks/bench_against.py --against DIR [--repeat 5] [--what check optimize] [--cases lecture ...]

Fresh processes with the caches warm (one warm-up run of each first; the user's cache directory, where each
tree's stored programs have keys of their own), interleaved round by round (the bare import, then each command
from DIR and from this tree back to back), so that the load of a shared machine moves them alike. Prints the
medians over ``--repeat`` rounds of the wall time and the CPU time (user + sys, which moves less with the load),
and for ``check`` the median of each round's ratio to that round's bare ``python -c "import jax, diffrax"``
(issue 23's goal: at most 1.5 x); the load average over the rounds. ``optimize`` writes into a temporary folder.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
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
CASES = ("lecture", "oscillating")


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _run(argv: list[str], tree: Path, cwd: Path) -> tuple[float, float]:
    """(wall s, CPU s) of one fresh process importing camdyn from ``tree``."""
    env = os.environ | {"PYTHONPATH": os.pathsep.join([str(tree), os.environ.get("PYTHONPATH", "")])}
    cpu0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    if proc.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(argv)} from {tree}: exit {proc.returncode}: {proc.stderr.strip()[-300:]}")
    return wall, cpu


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--against", type=Path, required=True, metavar="DIR", help="the other camdyn source tree")
    ap.add_argument("--repeat", type=int, default=5, help="rounds; medians are shown (default 5)")
    ap.add_argument("--what", nargs="+", default=["check", "optimize"], choices=["check", "optimize"])
    ap.add_argument(
        "--cases", nargs="+", default=list(CASES), metavar="CASE", help="shipped cases under cases/, without .toml"
    )
    opts = ap.parse_args()
    t_all = time.perf_counter()
    py = sys.executable
    trees = {"DIR": opts.against.resolve(), "this tree": ROOT}
    tmp = Path(tempfile.mkdtemp(prefix="camdyn-bench-against-"))
    jobs: list[tuple[str, str, list[str]]] = [("bare", "", [py, "-c", BARE])]
    for what in opts.what:
        for case in opts.cases:
            for tag in trees:
                argv = [py, "-m", "camdyn", what, str(ROOT / "cases" / f"{case}.toml"), "--quiet"]
                if what == "optimize":
                    argv += ["-o", str(tmp / f"{case}-{len(jobs)}.toml"), "--force"]
                jobs.append((f"camdyn {what} cases/{case}.toml", tag, argv))
    runs: dict[tuple[str, str], list[tuple[float, float]]] = {}
    loads = []
    try:
        for _, tag, argv in jobs:  # warm-up: fills each tree's caches
            _run(argv, trees.get(tag, ROOT), tmp)
        for _ in range(opts.repeat):
            for name, tag, argv in jobs:
                runs.setdefault((name, tag), []).append(_run(argv, trees.get(tag, ROOT), tmp))
            loads.append(os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan"))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    bare = runs[("bare", "")]
    rows = [
        (
            f'python -c "{BARE}"',
            f"{statistics.median(w for w, _ in bare):.2f} s",
            f"cpu {statistics.median(c for _, c in bare):.2f} s; the unit of the ratios",
        )
    ]
    for (name, tag), got in runs.items():
        if name == "bare":
            continue
        note = f"cpu {statistics.median(c for _, c in got):.2f} s"
        if "check" in name:
            wall_x = statistics.median(w / b for (w, _), (b, _) in zip(got, bare, strict=True))
            cpu_x = statistics.median(c / b for (_, c), (_, b) in zip(got, bare, strict=True))
            note += f"; {wall_x:.2f} x the bare import (cpu {cpu_x:.2f} x), goal <= 1.5 x"
        where = f" [{opts.against}]" if tag == "DIR" else ""
        rows.append((name + where, f"{statistics.median(w for w, _ in got):.2f} s", note))
    title = (
        f"this tree against {opts.against}, fresh processes, medians of {opts.repeat} rounds "
        f"(load average {min(loads):.1f}-{max(loads):.1f}, {os.cpu_count()} CPUs)"
    )
    print_table(title, rows, t_all)
    return 0


if __name__ == "__main__":
    sys.exit(main())
