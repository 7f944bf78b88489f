"""Benchmark: ``camdyn tolerance`` samples per second, on 1 and 2 local devices and on 2 processes.

    python benchmarks/bench_tolerance.py [--samples 20000] [--case cases/lecture-tolerances.toml]

Each configuration is a fresh Python process (the device count is fixed when JAX starts):
1 local device, 2 local CPU devices (``XLA_FLAGS=--xla_force_host_platform_device_count=2``) and 2 processes of
1 device each on JAX's distributed runtime (localhost coordinator, gloo collectives). Each first runs a small
study (compilation), then times ``tolerance_study`` over ``--samples`` samples. On a GPU machine the first
configuration is the GPU. Prints one aligned table; the machine may be shared (the load average is printed).
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def inner(opts) -> int:
    """One configuration: compile, then time the study; process 0 prints JSON."""
    from camdyn import enable_x64
    from camdyn._core.distributed import initialize, is_writer
    from camdyn.design.tolerance import CHUNK_SAMPLES, tolerance_study

    enable_x64()
    from camdyn.model.case import load_case

    initialize(opts.coordinator, opts.num_processes, opts.process_id)
    import jax

    case = load_case(opts.case)
    t0 = time.perf_counter()
    tolerance_study(case, CHUNK_SAMPLES * len(jax.devices()), seed=1)
    compile_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    res = tolerance_study(case, opts.samples, seed=0)
    run_s = time.perf_counter() - t0
    if is_writer():
        print(
            json.dumps(
                {
                    "devices": res.devices,
                    "processes": res.processes,
                    "platform": jax.devices()[0].platform,
                    "compile_s": compile_s,
                    "run_s": run_s,
                    "samples_per_s": opts.samples / run_s,
                    "probability": res.probability,
                }
            )
        )
    return 0


def _run(extra_env: dict, args: list[str], processes: int = 1) -> dict:
    env = {**os.environ, **extra_env}
    base = [sys.executable, __file__, "--inner", *args]
    if processes == 1:
        out = subprocess.run(base, env=env, capture_output=True, text=True, check=True)
        return json.loads(out.stdout.strip().splitlines()[-1])
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    procs = [
        subprocess.Popen(
            [*base, "--coordinator", f"127.0.0.1:{port}", "--num-processes", str(processes), "--process-id", str(i)],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for i in range(processes)
    ]
    outs = [p.communicate() for p in procs]
    if any(p.returncode for p in procs):
        raise RuntimeError("\n".join(o[1][-2000:] for o in outs))
    return json.loads(outs[0][0].strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=20000)
    ap.add_argument("--case", default=str(ROOT / "cases" / "lecture-tolerances.toml"))
    ap.add_argument("--inner", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--coordinator")
    ap.add_argument("--num-processes")
    ap.add_argument("--process-id")
    ap.add_argument("--configs", default="1dev,2dev,2proc", help="comma-separated: 1dev, 2dev, 2proc")
    opts = ap.parse_args()
    if opts.inner:
        return inner(opts)
    args = ["--samples", str(opts.samples), "--case", opts.case]
    flags = os.environ.get("XLA_FLAGS", "")
    configs = {
        "1dev": ("1 local device", {"XLA_FLAGS": f"{flags} --xla_force_host_platform_device_count=1"}, 1),
        "2dev": (
            "2 local CPU devices",
            {"XLA_FLAGS": f"{flags} --xla_force_host_platform_device_count=2", "JAX_PLATFORMS": "cpu"},
            1,
        ),
        "2proc": (
            "2 processes x 1 CPU device",
            {"XLA_FLAGS": f"{flags} --xla_force_host_platform_device_count=1", "JAX_PLATFORMS": "cpu"},
            2,
        ),
    }
    print(
        f"camdyn tolerance benchmark: {opts.samples} samples of {Path(opts.case).name}; {os.cpu_count()} CPUs, load "
        f"average {os.getloadavg()[0]:.2f}"
    )
    print(
        f"{'configuration':<28} {'platform':>8} {'compile s':>10} {'run s':>8} {'samples/s':>10} {'P(separation)':>14}"
    )
    for key in opts.configs.split(","):
        name, env, procs = configs[key]
        r = _run(env, args, procs)
        print(
            f"{name:<28} {r['platform']:>8} {r['compile_s']:>10.1f} {r['run_s']:>8.1f} {r['samples_per_s']:>10.0f} "
            f"{r['probability']:>14.4g}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
