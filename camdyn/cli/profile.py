"""``camdyn profile CASE.toml -o cam.dxf|cam.csv|cam.svg``: the cam contour for manufacturing."""

from __future__ import annotations

from pathlib import Path

from .._core.errors import InputError
from ..export import write_profile
from ..model.case import build_case
from ..model.geometry import analyze


def run(args) -> int:
    case = build_case(args.spec, source=Path(args.case))
    if case.follower is None:
        raise InputError("follower", "the case has no cam follower geometry")
    geo = analyze(case.motion, case.follower)
    info = write_profile(geo.contour_fn(), Path(args.output), tolerance=args.tolerance, force=args.force)
    print(
        f"wrote {args.output}: {info['points']} points within {info['tolerance_mm']:g} mm, "
        f"x {info['x_min_mm']:.3f}..{info['x_max_mm']:.3f} mm, y {info['y_min_mm']:.3f}..{info['y_max_mm']:.3f} mm"
    )
    return 0
