"""Benchmark: camdyn jump maps against a solve_ivp loop, the dynamic jump speed, and ``camdyn check`` latency.

    python benchmarks/bench_sweep.py [--grid 100] [--sample 30] [--seed 0] [--with-diffrax] [--no-check]
        [--warm-case cases/polynomial.toml]

Runs unchanged on CPU or on a GPU machine (it prints ``jax.devices()``; the map is sharded over all of them).
Prints one aligned table:

(a) the jump map of cases/lecture.toml (compliant follower) over ``grid`` speeds 100-700 rpm x ``grid`` spring
    rates 0.5-5 N/mm (preload fixed at the case's 30 N): camdyn's batched map (``camdyn.design.sweep.jump_map``:
    frequency-domain steady state for every point, exact piecewise-linear stepping of the nonlinear model for
    the separated ones), timed three ways, each against the solve_ivp loop of this same run:

    * **cold, compile included**: this process with empty caches of its own (a fresh temporary directory for
      JAX's persistent compilation cache and camdyn's traced-program cache, enabled as the CLI enables them): the
      first map traces, compiles and writes both caches; the time is the whole first ``jump_map`` call (not the
      import of JAX and camdyn);
    * **warm install cache, loading included**: a fresh process whose caches were filled by an earlier process
      that mapped a DIFFERENT case (``--warm-case``: another segment list of the same follower kind), as a user's
      install is after any earlier map: the lecture's map then traces and compiles nothing (it loads the traced
      programs and their compiled executables; the row counts what was traced or compiled in that process); the
      time is the whole first ``jump_map`` call of that process, loading included (not the import);
    * **run alone**: the map again in this process, everything compiled (best of 2).

    The ``scipy.integrate.solve_ivp`` loop is the same model, one point at a time: RK45 at rtol 1e-6 (the loosest
    tolerance whose least force agrees with camdyn's to 0.01 N, as bench_dynamics.py found; checked again here
    on every sampled point), revolution after revolution from the quasi-static start until the state repeats
    to 1e-6 mm; where the follower separates it stops after as many revolutions as camdyn integrates a
    separated point (``GAP_REVS``), least force 0 and the largest gap over the last ``GAP_LAST`` revolutions,
    as camdyn reports it. The motion is the lecture's closed form in scalar ``math`` (the fastest right-hand
    side a scipy user would write). The loop over all grid points would take far too long, so it runs on a
    random sample of points and its time is extrapolated per class (points that stay on the cam and points
    that separate have different costs) to the whole grid's mix.
(b) the dynamic jump speed of lecture.toml (``dynamics.dynamic_jump_speed``) after compilation;
(c) ``camdyn check cases/lecture.toml`` as fresh processes, cold (CAMDYN_NO_CACHE=1) and warm (persistent XLA
    cache), with the import / compile / run split (see bench_dynamics.py).

The machine may be shared: the load average is printed, and every ratio is taken within this one run.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_dynamics import CASE, ROOT, check_latency_rows, print_table, scipy_point, timed  # noqa: E402  (the shared loop and timer)

GOAL = 3000  # issue 23: the map of 10^4 designs at least this many times the solve_ivp loop


def _enable_caches(directory: Path) -> None:
    """JAX's persistent compilation cache and camdyn's traced-program cache under ``directory``, as the CLI enables
    them (camdyn.cli._enable_caches), but in a directory of the benchmark's own."""
    import jax

    from camdyn._core import jit

    jax.config.update("jax_compilation_cache_dir", str(directory / "jax"))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.1)
    jit.enable(directory / "programs")


class _Compiles(logging.Handler):
    """Counts, from JAX's compile log, the programs it compiled and those it loaded from the persistent cache."""

    def __init__(self):
        super().__init__(logging.DEBUG)
        self.started = self.hits = 0

    def emit(self, record):
        msg = record.getMessage()
        self.started += msg.startswith("Compiling ")
        self.hits += msg.startswith("Persistent compilation cache hit")


def _map_process(case_file: str, cache: str, grid: int) -> int:
    """``--map-only``: one jump map in this fresh process with the caches in ``cache``; prints JSON: its time (s),
    the programs it traced (new files in the traced-program cache) and the XLA compilations it ran."""
    import jax
    import numpy as np

    from camdyn import enable_x64
    from camdyn.design import sweep
    from camdyn.model.case import load_case

    enable_x64()
    _enable_caches(Path(cache))
    case = load_case(case_file)
    speeds, rates = np.linspace(100.0, 700.0, grid), np.linspace(0.5, 5.0, grid)
    compiles = _Compiles()
    jax.config.update("jax_log_compiles", True)
    for name in ("jax._src.dispatch", "jax._src.compiler", "jax._src.interpreters.pxla"):
        log = logging.getLogger(name)
        log.addHandler(compiles)
        log.propagate = False  # counted, not printed
    from camdyn._core.jit import SUFFIX

    programs = Path(cache) / "programs"
    before = set(programs.rglob(f"*.{SUFFIX}"))
    t = time.perf_counter()
    jm = sweep.jump_map(case, speeds, rates)
    t_map = time.perf_counter() - t
    traced = len(set(programs.rglob(f"*.{SUFFIX}")) - before)
    counts = {"traced": traced, "loaded": compiles.hits, "compiled": compiles.started - compiles.hits}
    print(json.dumps({"t_map": t_map, "separated": int(jm.separated.sum())} | counts))
    return 0


def _warm_install_map(warm_case: Path, grid: int) -> dict:
    """The lecture's map in a fresh process whose caches a process mapping ``warm_case`` filled."""
    cache = tempfile.mkdtemp(prefix="camdyn-bench-map-")
    try:
        run = lambda case: subprocess.run(  # noqa: E731
            [sys.executable, __file__, "--map-only", str(case), "--cache", cache, "--grid", str(grid)],
            capture_output=True,
            text=True,
            check=True,
            env=os.environ | {"PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])},
        )
        json.loads(run(warm_case).stdout.splitlines()[-1])
        return json.loads(run(CASE).stdout.splitlines()[-1])
    finally:
        shutil.rmtree(cache, ignore_errors=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grid", type=int, default=100, help="speeds and spring rates per axis (default 100)")
    ap.add_argument("--sample", type=int, default=30, help="grid points timed with the solve_ivp loop (default 30)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--with-diffrax",
        action="store_true",
        help="also time the map with diffrax (adaptive Tsit5) for the separated points",
    )
    ap.add_argument("--no-check", action="store_true", help="skip (c), the camdyn check subprocesses")
    ap.add_argument(
        "--warm-case",
        type=Path,
        default=ROOT / "cases" / "polynomial.toml",
        help="the other case whose map warms the install's caches (default cases/polynomial.toml)",
    )
    ap.add_argument("--map-only", help=argparse.SUPPRESS)  # internal: one map in a fresh process
    ap.add_argument("--cache", help=argparse.SUPPRESS)
    opts = ap.parse_args()
    if opts.map_only:
        return _map_process(opts.map_only, opts.cache, opts.grid)
    t_all = time.perf_counter()
    os.environ.setdefault("EQX_ON_ERROR", "nan")  # as the command line runs

    import jax
    import numpy as np

    from camdyn import enable_x64
    from camdyn._core.units import RPM
    from camdyn.design import sweep
    from camdyn.model import dynamics as dyn

    enable_x64()
    from camdyn.model.case import load_case

    cold_cache = Path(tempfile.mkdtemp(prefix="camdyn-bench-cold-"))
    _enable_caches(cold_cache)  # empty: the first map below traces and compiles everything

    case = load_case(CASE)
    speeds = np.linspace(100.0, 700.0, opts.grid)
    rates = np.linspace(0.5, 5.0, opts.grid)
    npts = speeds.size * rates.size
    rows: list[tuple[str, str, str]] = []

    # (a) camdyn's batched map
    t_first, jm = timed(lambda: sweep.jump_map(case, speeds, rates))
    t_run, jm = timed(lambda: sweep.jump_map(case, speeds, rates), repeat=2)
    warm = _warm_install_map(opts.warm_case, opts.grid)
    n_sep = int(jm.separated.sum())
    rows.append(
        (
            f"camdyn jump map {speeds.size}x{rates.size}: cold, compile included",
            f"{t_first:.2f} s",
            f"empty caches: trace + compile + run; compile ~{t_first - t_run:.2f} s",
        )
    )
    rows.append(
        (
            f"camdyn jump map {speeds.size}x{rates.size}: warm install cache",
            f"{warm['t_map']:.2f} s",
            f"fresh process, caches filled by {opts.warm_case.name}'s map: loading + run; traced {warm['traced']}, "
            f"loaded {warm['loaded']}, compiled {warm['compiled']} program(s) (JAX caches only those over 0.1 s)",
        )
    )
    rows.append(
        (
            f"camdyn jump map {speeds.size}x{rates.size}: run",
            f"{t_run:.2f} s",
            f"{npts} points, {n_sep} separated; {t_run / npts * 1e6:.0f} us/point on {jm.devices} device(s)",
        )
    )
    if opts.with_diffrax:
        t_dx1, jm_dx = timed(lambda: sweep.jump_map(case, speeds, rates, gap_method="diffrax"))
        t_dx, jm_dx = timed(lambda: sweep.jump_map(case, speeds, rates, gap_method="diffrax"))
        sel = jm.separated
        dg = np.abs(jm_dx.max_gap[sel] - jm.max_gap[sel])
        rows.append(
            (
                "camdyn jump map, diffrax for separated pts: run",
                f"{t_dx:.2f} s",
                f"compile ~{t_dx1 - t_dx:.2f} s; gap vs exact stepping: median |diff| {np.median(dg):.1e} mm (chaotic "
                "bounces differ)",
            )
        )

    # the solve_ivp loop on a random sample of grid points
    rng = np.random.default_rng(opts.seed)
    picks = rng.choice(npts, size=min(opts.sample, npts), replace=False)
    base = case.model
    t_by_class: dict[bool, list[float]] = {False: [], True: []}
    dev_f, sep_ok, dgap = [], 0, []
    for flat in picks:
        i, j = divmod(int(flat), rates.size)
        k_si = rates[j] * 1e3
        p = {
            "m": float(base.mass),
            "k": k_si,
            "f0": float(base.preload),
            "c": float(base.damping_at(k_si)),
            "fe": float(base.external),
            "kf": float(base.train_stiffness),
            "cf": float(base.train_damping),
        }
        t = time.perf_counter()
        f_sp, sep_sp, gap_sp, _ = scipy_point(p, speeds[i] * RPM, sep_revs=sweep.GAP_REVS, last=sweep.GAP_LAST)
        t_by_class[bool(jm.separated[i, j])].append(time.perf_counter() - t)
        sep_ok += sep_sp == bool(jm.separated[i, j])
        dev_f.append(abs(f_sp - jm.min_force[i, j]))
        if sep_sp and jm.separated[i, j]:
            dgap.append(abs(gap_sp - jm.max_gap[i, j]))
    n_s = len(picks)
    matched = sum(d < 0.01 for d in dev_f)
    mean = {cls: (float(np.mean(ts)) if ts else float(np.mean(t_by_class[not cls]))) for cls, ts in t_by_class.items()}
    t_scipy = mean[False] * (npts - n_sep) + mean[True] * n_sep
    rows.append(
        (
            f"solve_ivp loop RK45 rtol 1e-6, {n_s} sampled points",
            f"{sum(map(sum, t_by_class.values())):.2f} s",
            f"{mean[False] * 1e3:.0f} ms/point in contact ({len(t_by_class[False])}), {mean[True] * 1e3:.0f} ms/point "
            f"separated ({len(t_by_class[True])})",
        )
    )
    rows.append(
        (
            "  accuracy against camdyn on the sample",
            f"{max(dev_f):.1e} N",
            f"largest |least force diff|; {matched}/{n_s} within 0.01 N, separation agrees at {sep_ok}/{n_s}"
            + (
                f"; gap median |diff| {np.median(dgap):.1e} mm over {len(dgap)} (chaotic bounces differ)"
                if dgap
                else ""
            ),
        )
    )
    rows.append(
        (
            f"solve_ivp loop extrapolated to {npts} points",
            f"{t_scipy:.0f} s",
            f"per-class means x the map's {npts - n_sep} contact + {n_sep} separated points (not run)",
        )
    )
    rows.append(("ratio solve_ivp / camdyn map (run)", f"{t_scipy / t_run:.0f}x", "the map after compilation"))
    for label, t in (("cold, compile included", t_first), ("warm install cache", warm["t_map"])):
        r = t_scipy / t
        rows.append(
            (
                f"ratio solve_ivp / camdyn map, {label}",
                f"{r:.0f}x",
                f"issue 23's goal for 10^4 designs: >= {GOAL}x ({'met' if r >= GOAL else 'not met'})",
            )
        )

    # (b) dynamic jump speed
    omega = case.speed_rpm * RPM
    w_kin, _ = dyn.kinematic_jump_speed(case.motion, base)
    w_max = 4.0 * max(case.limits.speed_margin * omega, w_kin)
    t_j1, _ = timed(lambda: dyn.dynamic_jump_speed(case.motion, base, w_max=w_max))
    t_j, w_dyn = timed(lambda: dyn.dynamic_jump_speed(case.motion, base, w_max=w_max), repeat=5)
    rows.append(("dynamic jump speed: compile + run", f"{t_j1:.2f} s", ""))
    rows.append(("dynamic jump speed: run", f"{t_j * 1e3:.0f} ms", f"{w_dyn / RPM:.2f} rpm; goal < 200 ms"))

    # (c) camdyn check as fresh processes
    if not opts.no_check:
        rows += check_latency_rows()

    shutil.rmtree(cold_cache, ignore_errors=True)
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg()) if hasattr(os, "getloadavg") else "n/a"
    print_table(
        f"camdyn sweep benchmark: {CASE.name}, compliant model; devices {jax.devices()}; {os.cpu_count()} cores, load "
        f"average {load}",
        rows,
        t_all,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
