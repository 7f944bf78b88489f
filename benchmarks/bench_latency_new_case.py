"""Benchmark: the first ``check`` of a case never seen before, against the warm ``check`` of a shipped case.

    python benchmarks/bench_latency_new_case.py [--repeat 2]

All in one run, as fresh ``python -m camdyn check`` processes sharing the install's caches (``~/.cache/camdyn``,
or ``$XDG_CACHE_HOME/camdyn``), which are NOT cleared: the point is a cache warm from other cases.
(a) ``cases/lecture.toml``, warm (run once to fill the caches, then best of ``--repeat``);
(b) a never-seen case: the lecture's follower and dynamics with a random segment list (a seed taken from the clock,
    so the structure is new to the caches: 3-9 segments of random named laws, lifts and angles), its first ``check``;
(c) the 1000-segment program: alternating cycloids of 0.36 deg each, +-1 mm give or take a random half millimetre
    (so its numbers are new to the caches too), its first ``check``;
(d) the same for a rigid follower (the lecture without its train's stiffness and damping): the rigid lecture warm,
    then a never-seen rigid case (another random segment list), its first ``check``;
(e) a new user's valve cam: ``cases/valvetrain.toml`` warm, then its train under a random segment list;
(f) and indexer: ``cases/oscillating.toml`` warm, then its arm under a random segment list.
Prints each wall time and its ratio to its shipped case's warm check ((a), the rigid lecture's, the valvetrain's, the
oscillating case's), and for the never-seen cases their ratio to a second ``check`` of the same case (its own warm
check: what the caches leave of a first one, the case's own work apart). The machine may be shared: the load average
is printed.
"""

from __future__ import annotations

import argparse
import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAWS = ("cycloidal", "harmonic", "polynomial-345", "polynomial-4567", "modified-trapezoid", "modified-sine")


def check_time(case: Path) -> tuple[float, int]:
    """Wall time (s) and exit code of one ``python -m camdyn check`` process."""
    t = time.perf_counter()
    rc = subprocess.run(
        [sys.executable, "-m", "camdyn", "check", str(case)], cwd=ROOT, capture_output=True, text=True
    ).returncode
    return time.perf_counter() - t, rc


def rigid(text: str) -> str:
    """A case's text without its train's stiffness and damping: a rigid follower."""
    return "".join(line for line in text.splitlines(True) if not line.startswith(("train_stiffness", "train_damping")))


def lecture_with(segments: str, name: str, shipped: str = "lecture") -> str:
    """cases/<shipped>.toml with its segment list replaced."""
    text = (ROOT / "cases" / f"{shipped}.toml").read_text()
    head, rest = text.split("segments = [", 1)
    tail = rest.split("]\n", 1)[1]
    return head.replace(f'name = "{shipped}"', f'name = "{name}"') + "segments = [\n" + segments + "]\n" + tail


def random_segments(rng: random.Random) -> str:
    """A closed program with random laws and angles: 1-3 rises, then as many returns (each undoing a rise, so the
    lift never goes below zero), 1-3 dwells among them; segments at least 10 deg long."""
    n_rise = rng.randint(1, 3)
    lifts = [round(rng.uniform(3.0, 9.0), 3) for _ in range(n_rise)]
    kinds = [("rise", x) for x in lifts] + [("return", -x) for x in reversed(lifts)]
    for _ in range(rng.randint(1, 3)):
        kinds.insert(rng.randint(0, len(kinds)), ("dwell", 0.0))
    ends = sorted(rng.sample(range(20, 350, 10), len(kinds) - 1)) + [360]
    lines = []
    for end, (kind, lift) in zip(ends, kinds, strict=True):
        if kind == "dwell":
            lines.append(f'  {{ law = "dwell", end = {end} }},\n')
        else:
            lines.append(f'  {{ law = "{rng.choice(LAWS)}", end = {end}, lift = {lift} }},\n')
    return "".join(lines)


def thousand_segments(rng: random.Random) -> str:
    base = round(rng.uniform(0.5, 1.5), 6)
    lines = [
        f'  {{ law = "cycloidal", end = {0.36 * (i + 1):.2f}, lift = {base if i % 2 == 0 else -base} }},\n'
        for i in range(1000)
    ]
    return "".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=2, help="warm runs of the shipped case, the best is shown")
    opts = ap.parse_args()
    rng = random.Random(time.time_ns())
    tmp = Path(tempfile.mkdtemp(prefix="camdyn-newcase-"))
    new, thousand = tmp / "new.toml", tmp / "thousand.toml"
    new.write_text(lecture_with(random_segments(rng), "never-seen"))
    thousand.write_text(lecture_with(thousand_segments(rng), "thousand"))
    rigid_lecture, rigid_new = tmp / "lecture-rigid.toml", tmp / "new-rigid.toml"
    rigid_lecture.write_text(rigid((ROOT / "cases" / "lecture.toml").read_text()))
    rigid_new.write_text(rigid(lecture_with(random_segments(rng), "never-seen-rigid")))
    valve, indexer = tmp / "new-valve.toml", tmp / "new-indexer.toml"
    valve.write_text(lecture_with(random_segments(rng), "never-seen-valve", "valvetrain"))
    indexer.write_text(lecture_with(random_segments(rng), "never-seen-indexer", "oscillating"))

    def warm_check(case: Path) -> float:
        check_time(case)  # fills the caches if they are empty
        return min(check_time(case)[0] for _ in range(opts.repeat))

    def first_check(case: Path) -> tuple[float, int, float]:
        """A never-seen case's first check (wall, exit code) and its second (its own warm check)."""
        first, rc = check_time(case)
        return first, rc, check_time(case)[0]

    # (label of the shipped case's warm check, its wall, [(never-seen case, first, exit, its own warm)])
    groups = []
    for label, shipped, news in (
        (
            "check cases/lecture.toml, warm caches",
            ROOT / "cases" / "lecture.toml",
            [("a never-seen case", new), ("1000 cycloids", thousand)],
        ),
        ("check of the lecture, rigid follower, warm caches", rigid_lecture, [("a never-seen rigid case", rigid_new)]),
        (
            "check cases/valvetrain.toml, warm caches",
            ROOT / "cases" / "valvetrain.toml",
            [("a never-seen valve", valve)],
        ),
        (
            "check cases/oscillating.toml, warm caches",
            ROOT / "cases" / "oscillating.toml",
            [("a never-seen indexer", indexer)],
        ),
    ):
        # each case's own warm check: a failing case (the follower bouncing for dozens of revolutions of the
        # shooting) costs more than its shipped case however warm the caches, and this ratio is the caches' share
        unit = warm_check(shipped)
        groups.append((label, unit, [(name, *first_check(case)) for name, case in news]))
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs; cases in {tmp}")
    print(f"{'what':<52} {'wall':>8} {'/ warm':>8} {'/ its own warm':>15}")
    for label, unit, news in groups:
        print(f"{label:<52} {unit:7.2f}s {1.0:8.2f}")
        for name, first, rc, again in news:
            print(f"{f'first check of {name} (exit {rc})':<52} {first:7.2f}s {first / unit:8.2f} {first / again:15.2f}")
            print(f"{'  its second check':<52} {again:7.2f}s {again / unit:8.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
