"""Benchmark: bringing your own cam, the time from data to a Motion (not a test; prints one table).

    python benchmarks/bench_imports.py [--repeat 5]

(a) a lift table of 3600 points (cases/lecture.toml's lift every 0.1 deg, 4 decimals), read from CSV and fitted
    by the periodic quintic smoothing spline (3600 knots; REML, then REML at the rounding floor): the whole of
    what ``[motion] table`` adds to ``build_case``; also the same table with 1 um of noise (REML alone);
(b) a contour of 2000 points (the lecture cam's exact outline, evenly in the curve parameter), read from CSV,
    its radius fitted over the polar angle, the motion derived by exact contact at 16384 outline points and
    fitted as a 3600-point table: what ``[follower] contour`` adds to ``build_case``;
(c) the same contour as a DXF LWPOLYLINE (ezdxf's import included).

Best of ``--repeat`` runs each, after one warm-up (numpy/scipy only: nothing here compiles). The machine may be
shared: the load average is printed.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_dynamics import print_table, timed  # noqa: E402  (the shared table printer and timer)

ROOT = HERE.parent


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs per row, the best is shown (default 5)")
    opts = ap.parse_args()
    t_all = time.perf_counter()

    import ezdxf
    import numpy as np

    from camdyn import enable_x64

    enable_x64()
    from camdyn.model.case import load_case
    from camdyn.model.datafiles import read_contour, read_lift_table
    from camdyn.model.geometry import analyze, contact_motion
    from camdyn.model.motion import fit_motion
    from camdyn.schema import FollowerSpec

    lecture = load_case(ROOT / "cases" / "lecture.toml")
    tmp = Path(tempfile.mkdtemp(prefix="camdyn-bench-"))
    theta = np.arange(3600) * 0.1
    lift = np.asarray(lecture.motion._eval(np, np.deg2rad(theta)))[0]
    noisy = lift + 1e-3 * np.random.default_rng(0).standard_normal(theta.size)
    for name, values, fmt in (("table.csv", lift, ".4f"), ("noisy.csv", noisy, ".6f")):
        (tmp / name).write_text(
            "theta_deg,lift_mm\n" + "".join(f"{t:g},{v:{fmt}}\n" for t, v in zip(theta, values, strict=True))
        )

    xy = analyze(lecture.motion, lecture.follower).contour_fn()(np.linspace(0.0, 1.0, 2000, endpoint=False))
    (tmp / "cam.csv").write_text("x_mm,y_mm\n" + "".join(f"{x:.6f},{y:.6f}\n" for x, y in xy.T))
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    doc.modelspace().add_lwpolyline(xy.T.tolist(), close=True)
    doc.saveas(tmp / "cam.dxf")
    follower = FollowerSpec(type="translating-roller", contour="cam.csv", roller_radius=10, offset=5, rotation="cw")

    def table(name):
        t = read_lift_table(tmp / name, name, oscillating=False)
        return fit_motion(t.values[:, 0], t.values[:, 1], unit="mm", source="table", file=name, rounding=t.rounding)[1]

    def contour(name):
        derived = contact_motion(read_contour(tmp / name, name), follower)
        fit_motion(derived.theta_deg, derived.lift, unit="mm", source="contour", file=name)
        return derived

    rows = []
    for label, fn in (
        ("(a) 3600-point table, 4 decimals", lambda: table("table.csv")),
        ("(a) 3600-point table, 1 um noise", lambda: table("noisy.csv")),
        ("(b) 2000-point contour, CSV", lambda: contour("cam.csv")),
        ("(c) 2000-point contour, DXF", lambda: contour("cam.dxf")),
    ):
        fn()  # warm-up: imports, caches
        best, out = timed(fn, opts.repeat)
        if hasattr(out, "spline"):
            note = (
                f"{out.spline.coef.shape[0]} knots, {out.spline.criterion}, max residual "
                f"{out.spline.max_residual:.2g} mm"
            )
        else:
            note = f"base radius {out.follower.base_radius:.6f} mm, {len(out.theta_deg)} contact samples"
        rows.append((label, f"{best * 1000:.0f} ms", note))
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print_table(f"data -> Motion, best of {opts.repeat} (load average {load:.2f}, {os.cpu_count()} CPUs)", rows, t_all)
    return 0


if __name__ == "__main__":
    sys.exit(main())
