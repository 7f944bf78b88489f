"""Benchmark: ``camdyn optimize`` on cases/lecture.toml (compliant translating roller, 20 free control points).

    python benchmarks/bench_optimize.py [--speed 650] [--full] [--commands]

Prints one aligned table:

(a) the Jacobian of the contact force (32 speeds x 1024 angles, by 20 control points) by JAX forward-mode
    autodiff, compiled once, against central finite differences of the force alone, compiled (40 evaluations):
    time of each and their largest disagreement relative to the Jacobian's largest entry;
(b) the inner problem at one speed (``--speed`` rpm): the largest least contact force at every speed up to it
    within the pressure-angle and curvature limits, by camdyn's sequential linear programs (HiGHS, rows
    generated) and by ``scipy.optimize.minimize(method="SLSQP")`` in epigraph form on the same rows (every
    16th angle, else SLSQP's dense QP is too slow) with the same JAX Jacobians: time and the least force reached;
(c) with ``--full``: the whole ``optimize_case`` (the bisection on the jump speed, both checks and the diffrax
    verification) and its answer;
(d) with ``--commands``: ``camdyn optimize CASE -o OUT --quiet`` of cases/lecture.toml and cases/oscillating.toml as
    fresh processes, first with empty caches (a fresh ``XDG_CACHE_HOME``: a first run, everything traced and
    compiled), then again with the caches that run filled, each as a ratio to issue 23's goal (20 s).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
from scipy.optimize import minimize

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_dynamics import print_table, timed  # noqa: E402

import camdyn  # noqa: E402

camdyn.enable_x64()
from camdyn._core.units import RPM  # noqa: E402
from camdyn.design.optimize import optimize_case  # noqa: E402
from camdyn.design.optimize._objectives import _speed_set, least_slack  # noqa: E402
from camdyn.design.optimize._rows import Rows, speed_slots  # noqa: E402
from camdyn.design.optimize._shape import shape_space  # noqa: E402
from camdyn.design.optimize._slp import maximize_least, with_jacobian  # noqa: E402
from camdyn.model.case import load_case  # noqa: E402

CASE = HERE.parent / "cases" / "lecture.toml"


def gradient_rows(rows: Rows) -> list[tuple[str, str, str]]:
    z = jnp.asarray(rows.space.z0)
    sp = jnp.asarray(speed_slots(_speed_set(500.0 * RPM)))
    rows.slack_jacobian(z, sp)[1].block_until_ready()  # compile (or load the stored program)
    t_ad, (_, J) = timed(lambda: [a.block_until_ready() for a in rows.slack_jacobian(z, sp)], repeat=5)
    f = jax.jit(lambda x: rows.kernel.sampled_slack(x, sp, False))  # the force over its margin alone, compiled
    f(z).block_until_ready()
    h = 1e-6

    def fd():
        cols = []
        for k in range(z.size):
            e = jnp.zeros_like(z).at[k].set(h)
            cols.append((f(z + e) - f(z - e)) / (2 * h))
        return jnp.stack(cols, axis=-1).block_until_ready()

    t_fd, Jfd = timed(fd, repeat=2)
    err = float(np.max(np.abs(np.asarray(J) - np.asarray(Jfd))) / np.max(np.abs(np.asarray(J))))
    return [
        ("Jacobian by autodiff (jvp x 20)", f"{1e3 * t_ad:.1f} ms", f"{J.shape[0]} rows x {J.shape[1]} control points"),
        (
            "Jacobian by central differences",
            f"{1e3 * t_fd:.1f} ms",
            f"{t_fd / t_ad:.1f}x the autodiff time; largest difference {err:.1e} of the largest entry",
        ),
    ]


def inner_rows(rows: Rows, rpm: float) -> list[tuple[str, str, str]]:
    w = rpm * RPM
    sp = jnp.asarray(speed_slots(_speed_set(w)))
    scale = float(rows.case.model.preload)
    values = lambda z: rows.slack_jacobian(z, sp)  # noqa: E731
    values(jnp.asarray(rows.space.z0))
    rows.geometry_jacobian(jnp.asarray(rows.space.z0))
    t_slp, step = timed(lambda: maximize_least(values, rows.geometry_jacobian, rows.space.z0, radius=0.2, scale=scale))
    slp_full = least_slack(rows, step.x, w)[0]

    every = np.arange(0, rows.space.theta.size, 16)
    fz = with_jacobian(lambda z: rows.kernel.slack(z, sp)[:, every].ravel())
    gz = rows.geometry_jacobian
    n = rows.space.n_free
    cache: dict = {}

    def at(x):
        key = x.tobytes()
        if key not in cache:
            z = jnp.asarray(x[:n])
            (v, Jv), (g, Jg) = fz(z), gz(z)
            cache.clear()
            cache[key] = (np.asarray(v), np.asarray(Jv), np.asarray(g), np.asarray(Jg))
        return cache[key]

    cons = [
        {"type": "ineq", "fun": lambda x: at(x)[0] - x[n], "jac": lambda x: np.c_[at(x)[1], -np.ones(at(x)[0].size)]},
        {"type": "ineq", "fun": lambda x: -at(x)[2], "jac": lambda x: np.c_[-at(x)[3], np.zeros(at(x)[2].size)]},
    ]
    x0 = np.r_[rows.space.z0, float(np.min(at(np.r_[rows.space.z0, 0.0])[0]))]
    fz(jnp.asarray(rows.space.z0))
    t_sq, res = timed(
        lambda: minimize(
            lambda x: -x[n],
            x0,
            jac=lambda x: np.r_[np.zeros(n), -1.0],
            constraints=cons,
            method="SLSQP",
            options={"maxiter": 200},
        )
    )
    sq_full = least_slack(rows, res.x[:n], w)[0]
    return [
        (
            f"inner problem at {rpm:g} rpm: SLP + HiGHS",
            f"{t_slp:.2f} s",
            f"least force {slp_full:.3f} N over the fine scan ({step.steps} steps)",
        ),
        (
            f"inner problem at {rpm:g} rpm: SLSQP",
            f"{t_sq:.2f} s",
            f"least force {sq_full:.3f} N over the fine scan ({res.nit} iterations, {res.message})",
        ),
    ]


GOAL_OPTIMIZE_S = 20.0  # issue 23: ``camdyn optimize`` of a shipped case
COMMAND_CASES = ("lecture", "oscillating")


def command_rows() -> list[tuple[str, str, str]]:
    """(d): each case's ``camdyn optimize`` as a fresh process, empty caches then warm, against the goal."""
    rows = []
    root = HERE.parent
    for name in COMMAND_CASES:
        with tempfile.TemporaryDirectory(prefix="camdyn-bench-") as tmp:
            env = os.environ | {"XDG_CACHE_HOME": tmp}
            argv = [sys.executable, "-m", "camdyn", "optimize", str(root / "cases" / f"{name}.toml")]
            argv += ["-o", str(Path(tmp) / "out.toml"), "--force", "--quiet"]
            for caches in ("empty", "warm"):
                t = time.perf_counter()
                done = subprocess.run(argv, env=env, cwd=root, capture_output=True, text=True)
                wall = time.perf_counter() - t
                said = [line for line in done.stdout.splitlines() if line.startswith("claimed:")]
                rows.append(
                    (
                        f"camdyn optimize cases/{name}.toml, caches {caches}",
                        f"{wall:.1f} s",
                        f"{wall / GOAL_OPTIMIZE_S:.2f} x the goal of {GOAL_OPTIMIZE_S:.0f} s; exit {done.returncode}"
                        + (f"; {said[0]}" if said else ""),
                    )
                )
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=650.0, help="speed of the inner-problem comparison, rpm")
    ap.add_argument("--full", action="store_true", help="also the whole optimize_case")
    ap.add_argument(
        "--control-points",
        type=int,
        nargs="+",
        default=[16],
        metavar="N",
        help="of the whole optimize_case (default: 16)",
    )
    ap.add_argument("--commands", action="store_true", help="also camdyn optimize as fresh processes, cold and warm")
    args = ap.parse_args()
    t0 = time.perf_counter()
    case = load_case(CASE)
    rows = Rows(case, shape_space(case))
    table = gradient_rows(rows) + inner_rows(rows, args.speed)
    if args.full:
        for n in args.control_points:
            t, res = timed(lambda n=n: optimize_case(case, control_points=n))
            table.append(
                (
                    f"optimize_case, jump-speed, {n} control points",
                    f"{t:.1f} s",
                    f"margin {res.margin:.3g} N held to {res.before.margin_speed_rpm:.1f} -> "
                    f"{res.claimed_speed_rpm:.1f} rpm; jump speed {res.before.jump_speed_rpm:.1f} -> "
                    f"{res.after.jump_speed_rpm:.1f} rpm, {res.after.verdict}",
                )
            )
    if args.commands:
        table += command_rows()
    load = os.getloadavg()[0]
    print_table(f"camdyn optimize on {CASE.name} ({os.cpu_count()} CPUs, load average {load:.2f})", table, t0)


if __name__ == "__main__":
    main()
