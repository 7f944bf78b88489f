"""Benchmark: the test suite a contributor waits for, against issue 23's goals, in one run.

    python benchmarks/bench_suite.py [--full]

Runs the README's second command's tests as fresh ``python -m pytest`` processes from the repository root (the
options of ``pyproject.toml``: ``-n auto --dist worksteal``), each with the session's program cache starting empty
(the suite's own: ``tests/conftest.py`` makes a fresh folder unless ``CAMDYN_TEST_CACHE`` names one, and this
benchmark removes that variable), and prints one aligned table:

* ``pytest -m "not slow"`` (the quick set): wall and CPU time (user + sys of the processes), and the wall as a ratio
  to its goal, 60 s;
* with ``--full``, the whole suite (``pytest``): the same, against its goal of 3 minutes on a quiet machine.

The machine may be shared: the load average and the CPU count are printed (the suite's workers are one per CPU).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_dynamics import print_table  # noqa: E402  (the shared table printer)

ROOT = HERE.parent
GOAL_QUICK_S = 60.0  # issue 23: -m "not slow"
GOAL_FULL_S = 180.0  # issue 23: the whole suite, quiet


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_pytest(args: list[str]) -> tuple[float, float, int, str]:
    """(wall s, CPU s, exit code, pytest's last line) of ``python -m pytest ARGS`` from the repository root, with
    the session's program cache starting empty."""
    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_TEST_CACHE"}
    cpu0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *args],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
    )
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    last = (proc.stdout.strip().splitlines() or [""])[-1].strip("= ")
    return wall, cpu, proc.returncode, last


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    ap.add_argument("--full", action="store_true", help="also the whole suite (minutes)")
    opts = ap.parse_args()
    t_start = time.perf_counter()
    runs = [('pytest -m "not slow"', ["-m", "not slow"], GOAL_QUICK_S)]
    if opts.full:
        runs.append(("pytest (the whole suite)", [], GOAL_FULL_S))
    rows = []
    for what, args, goal in runs:
        wall, cpu, rc, last = run_pytest(args)
        note = f"{wall / goal:.2f} x its goal of {goal:.0f} s, cpu {cpu:.0f} s; exit {rc}: {last}"
        rows.append((what, f"{wall:.1f} s", note))
    print_table(
        f"the test suite, fresh processes, the program cache starting empty (load average "
        f"{os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs)",
        rows,
        t_start,
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
