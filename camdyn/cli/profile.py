"""``camdyn profile CASE.toml -o cam.dxf|cam.csv|cam.svg``: the cam contour for manufacturing."""

from __future__ import annotations

import sys
from pathlib import Path

from .._core.errors import InputError
from ..design.geometry import judge_geometry
from ..export import write_profile
from ..model.case import build_case
from ..model.geometry import analyze


def run(args) -> int:
    case = build_case(args.spec, source=Path(args.case))
    if case.follower is None:
        raise InputError("follower", "the case has no cam follower geometry")
    geo = analyze(case.motion, case.follower)
    _, warnings, _ = judge_geometry(geo, case.motion, max_pressure_angle=case.limits.max_pressure_angle, min_curvature_ratio=case.limits.min_curvature_ratio)
    info = write_profile(geo.contour_fn(), Path(args.output), tolerance=args.tolerance, force=args.force)
    for w in warnings:  # an undercut cam can still be drawn, but the user must know it cannot be followed
        print(f"warning: {w}", file=sys.stderr)
    print(
        f"wrote {args.output}: {info['points']} points within {info['tolerance_mm']:g} mm, "
        f"x {info['x_min_mm']:.3f}..{info['x_max_mm']:.3f} mm, y {info['y_min_mm']:.3f}..{info['y_max_mm']:.3f} mm"
    )
    return 0
