"""Benchmark: the compliant steady state of cases/lecture.toml by camdyn (diffrax) and by a solve_ivp loop.

    python benchmarks/bench_dynamics.py

Prints one aligned table:

* camdyn ``compliant_response`` (shooting on diffrax: Newton on the one-revolution flow with its variational
  equations): compile + first run, then the run alone (best of 5);
* a scipy loop: ``solve_ivp`` revolution after revolution from the quasi-static start until the state repeats,
  same equations in the cam angle, restarted at the segment boundaries: RK45 at rtol 1e-6 (its least interface
  force agrees with camdyn's to 0.01 N) and DOP853 at camdyn's own rtol 1e-9; the motion is the lecture's closed form
  written out as scalar ``math`` (the fastest right-hand side a scipy user would write, which favours scipy);
* the dynamic jump speed (frequency-domain scan + bisection) after compilation;
* ``camdyn check cases/lecture.toml`` as fresh processes: cold (CAMDYN_NO_CACHE=1) and warm (persistent XLA cache
  in a private temporary directory, filled by one earlier run), each as the plain command and as an instrumented
  process that splits import / first check (compile + run) / second check (run) so compile = first - second.

Runs in about 1-2 minutes on 2 cores.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "lecture.toml"
N = 3600  # the grid compliant_response uses by default (and camdyn check)

_INSTRUMENTED = r"""
import json, sys, time, os, io, contextlib
t0 = time.perf_counter()
import camdyn.cli as cli
cli._enable_caches()
import jax, diffrax, camdyn.cli.check  # what check imports
t1 = time.perf_counter()
out = {"import": t1 - t0}
for key in ("first", "second"):
    buf = io.StringIO()
    t = time.perf_counter()
    with contextlib.redirect_stdout(buf):
        rc = cli.main(["check", sys.argv[1]])
    out[key] = time.perf_counter() - t
    out["rc"] = rc
print(json.dumps(out))
"""


def lecture_s_s1(th: float) -> tuple[float, float]:
    """(s mm, s' mm/rad) of the lecture cam: dwell, cycloidal rise 20 mm 90-180, dwell, harmonic return 240-360."""
    th = th % (2 * math.pi)
    if th < 0.5 * math.pi:
        return 0.0, 0.0
    if th < math.pi:
        b = 0.5 * math.pi
        x = (th - 0.5 * math.pi) / b
        return 20 * (x - math.sin(2 * math.pi * x) / (2 * math.pi)), 20 / b * (1 - math.cos(2 * math.pi * x))
    if th < 4 * math.pi / 3:
        return 20.0, 0.0
    b = 2 * math.pi / 3
    x = (th - 4 * math.pi / 3) / b
    return 20 - 10 * (1 - math.cos(math.pi * x)), -10 * math.pi / b * math.sin(math.pi * x)


def scipy_point(p: dict, omega: float, rtol=1e-6, atol=1e-8, method="RK45", tol=1e-6, max_revs=60, sep_revs=6, last=2):
    """One grid point by a solve_ivp loop: (least force N, separated, largest gap mm, revolutions)."""
    import numpy as np
    from scipy.integrate import solve_ivp

    m, k, f0, c, fe, kf, cf = (p[n] for n in ("m", "k", "f0", "c", "fe", "kf", "cf"))
    sc = 1e-3
    den = m * omega**2 * sc

    def rhs(th, y):
        x, v = y
        s, s1 = lecture_s_s1(th)
        fi = max(0.0, kf * sc * (s - x) + cf * omega * sc * (s1 - v)) if s > x else 0.0
        return [v, (fi - (k * sc * x + f0) - c * omega * sc * v - fe) / den]

    breaks = (0.0, 0.5 * math.pi, math.pi, 4 * math.pi / 3, 2 * math.pi)
    theta = np.arange(N) * (2 * math.pi / N)
    ss = np.array([lecture_s_s1(t) for t in theta])
    z = np.array([-(f0 + fe) / (kf * sc), 0.0])  # quasi-static start at theta = 0 (dwell, s = 0)
    gaps, first_sep, fmin = [], None, math.nan
    for rev in range(1, max_revs + 1):
        z_start, xs, vs, y = z, np.empty(N), np.empty(N), z
        for a, b in zip(breaks[:-1], breaks[1:], strict=True):
            sol = solve_ivp(rhs, (a, b), y, method=method, rtol=rtol, atol=atol, dense_output=True)
            sel = (theta >= a) & (theta < b)
            xs[sel], vs[sel] = sol.sol(theta[sel])
            y = sol.y[:, -1]
        z = y
        f = kf * sc * (ss[:, 0] - xs) + cf * omega * sc * (ss[:, 1] - vs)
        fmin = float(np.where(ss[:, 0] > xs, np.maximum(f, 0.0), 0.0).min())
        gaps.append(max(0.0, float(np.max(xs - ss[:, 0]))))
        if fmin <= 0.0 and first_sep is None:
            first_sep = rev
        if np.max(np.abs(z - z_start)) < tol or (first_sep is not None and rev >= sep_revs):
            break
    separated = first_sep is not None
    return (0.0 if separated else fmin), separated, (max(gaps[-last:]) if separated else 0.0), rev


def scipy_steady(model, omega, rtol, atol, method="DOP853", tol=1e-6, max_revs=200):
    """Revolution-to-revolution solve_ivp loop until |z(2 pi) - z(0)| < tol (mm, mm/rad): (least force N,
    revolutions)."""
    names = {
        "m": "mass",
        "k": "stiffness",
        "f0": "preload",
        "c": "damping",
        "fe": "external",
        "kf": "train_stiffness",
        "cf": "train_damping",
    }
    p = {key: float(getattr(model, name)) for key, name in names.items()}
    fmin, _, _, revs = scipy_point(p, omega, rtol, atol, method, tol=tol, max_revs=max_revs, sep_revs=max_revs)
    return fmin, revs


def timed(fn, repeat=1):
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def camdyn_cmd() -> list[str]:
    exe = Path(sys.executable).with_name("camdyn")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "camdyn"]


def check_process(env: dict) -> tuple[float, dict]:
    """Wall time of the plain ``camdyn check`` command, and the instrumented breakdown, in ``env``."""
    t = time.perf_counter()
    plain = subprocess.run([*camdyn_cmd(), "check", str(CASE)], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if plain.returncode not in (0, 1):
        raise RuntimeError(f"camdyn check failed: {plain.stderr.strip()}")
    inst = subprocess.run([sys.executable, "-c", _INSTRUMENTED, str(CASE)], env=env, capture_output=True, text=True)
    if inst.returncode != 0:
        raise RuntimeError(f"instrumented check failed: {inst.stderr.strip()[-500:]}")
    return wall, json.loads(inst.stdout.strip().splitlines()[-1])


def print_table(title: str, rows: list[tuple[str, str, str]], t_start: float) -> None:
    """The benchmark's aligned table (what, time, note) under ``title``, and its total time."""
    w1 = max(len(a) for a, _, _ in rows)
    w2 = max(len(b) for _, b, _ in rows)
    print(title)
    print(f"{'what':<{w1}}  {'time':>{w2}}  note")
    print(f"{'-' * w1}  {'-' * w2}  ----")
    for a, b, c in rows:
        print(f"{a:<{w1}}  {b:>{w2}}  {c}")
    print(f"(benchmark total {time.perf_counter() - t_start:.0f} s)")


def with_bytecode(env: dict, folder: str | Path) -> dict:
    """``env`` with Python's bytecode written to and read from ``folder`` (``PYTHONPYCACHEPREFIX``), even where
    ``PYTHONDONTWRITEBYTECODE`` is set: a user's ``pip install .`` byte-compiles camdyn, so a benchmark of what a
    user waits for keeps the bytecode as it keeps the programs (without it an editable checkout compiles camdyn's
    sources in every process: 0.2 s of a ``check`` on a 2-core machine)."""
    return {k: v for k, v in env.items() if k != "PYTHONDONTWRITEBYTECODE"} | {"PYTHONPYCACHEPREFIX": str(folder)}


def check_latency_rows(repeat: int = 3) -> list[tuple[str, str, str]]:
    """``camdyn check`` of the lecture case as fresh processes: with no caches, and with the caches a previous
    run left (JAX's compiled programs and camdyn's traced ones); best of ``repeat`` walls, with the breakdown."""
    rows = []
    cache = tempfile.mkdtemp(prefix="camdyn-bench-cache-")
    try:
        # the bytecode as an install has it, with or without the program caches
        base = with_bytecode({k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"}, Path(cache) / "bytecode")
        warm_env = base | {"XDG_CACHE_HOME": cache}
        subprocess.run([*camdyn_cmd(), "check", str(CASE)], env=warm_env, capture_output=True)  # fill the caches
        for label, env in (("no cache", base | {"CAMDYN_NO_CACHE": "1"}), ("warm cache", warm_env)):
            wall, br = min((check_process(env) for _ in range(repeat)), key=lambda r: r[0])
            comp = br["first"] - br["second"]
            rows.append(
                (
                    f"camdyn check ({label}), fresh process",
                    f"{wall:.2f} s",
                    f"import {br['import']:.2f} s + trace/compile {comp:.2f} s + run {br['second']:.2f} s (exit "
                    f"{br['rc']}); best of {repeat}",
                )
            )
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    return rows


def main() -> int:
    t_all = time.perf_counter()
    t = time.perf_counter()
    import jax.numpy as jnp

    from camdyn import enable_x64
    from camdyn._core.units import RPM
    from camdyn.model import dynamics as dyn

    enable_x64()
    from camdyn.model.case import load_case

    t_import = time.perf_counter() - t
    case = load_case(CASE)
    motion, model = case.motion, case.model
    omega = case.speed_rpm * RPM
    rows: list[tuple[str, str, str]] = []  # (what, time, note)

    # (a) camdyn / diffrax
    t_first, r = timed(lambda: dyn.compliant_response(motion, model, omega, n=N))
    t_run, r = timed(lambda: dyn.compliant_response(motion, model, omega, n=N), repeat=5)
    f_dx = r.min_force
    rows.append(("import jax + camdyn (this process)", f"{t_import:.2f} s", ""))
    rows.append(("camdyn steady state: compile + run", f"{t_first:.2f} s", f"compile ~{t_first - t_run:.2f} s"))
    rows.append(
        (
            "camdyn steady state: run",
            f"{t_run * 1e3:.0f} ms",
            f"least force {f_dx:.4f} N, periodicity {r.periodicity_error:.1e} mm",
        )
    )

    # (b) scipy loop: the loosest tolerance whose least force agrees to 0.01 N, and camdyn's own tolerance
    matched = None
    for method, rtol, atol in (("RK45", 1e-6, 1e-8), ("DOP853", 1e-9, 1e-10)):
        t_sp, (f_sp, revs) = timed(
            lambda method=method, rtol=rtol, atol=atol: scipy_steady(model, omega, rtol, atol, method), repeat=2
        )
        ok = abs(f_sp - f_dx) < 0.01
        rows.append(
            (
                f"solve_ivp loop {method} rtol {rtol:.0e}",
                f"{t_sp:.2f} s",
                f"least force {f_sp:.4f} N ({f_sp - f_dx:+.1e}), {revs} revs, ratio "
                f"{t_sp / t_run:.1f}x{'' if ok else '  (not matched)'}",
            )
        )
        if ok and matched is None:
            matched = t_sp
    if matched is not None:
        rows.append(
            (
                "ratio solve_ivp / camdyn (run)",
                f"{matched / t_run:.1f}x",
                "loosest scipy tolerance with least force within 0.01 N",
            )
        )

    # dynamic jump speed
    w_kin, _ = dyn.kinematic_jump_speed(motion, model)
    w_max = 4.0 * max(case.limits.speed_margin * omega, w_kin)
    t_j1, _ = timed(lambda: dyn.dynamic_jump_speed(motion, model, w_max=w_max))
    t_j2, w_dyn = timed(lambda: dyn.dynamic_jump_speed(motion, model, w_max=w_max), repeat=3)
    rows.append(("dynamic jump speed: compile + run", f"{t_j1:.2f} s", ""))
    rows.append(
        ("dynamic jump speed: run", f"{t_j2 * 1e3:.0f} ms", f"{w_dyn / RPM:.2f} rpm (kinematic {w_kin / RPM:.2f} rpm)")
    )
    _ = jnp  # keep the import explicit: jax is part of the import time above

    rows += check_latency_rows()

    print_table(
        f"camdyn dynamics benchmark: {CASE.name} at {case.speed_rpm:g} rpm, compliant model, {N}-point grid, "
        f"{os.cpu_count()} cores",
        rows,
        t_all,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
