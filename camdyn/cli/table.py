"""``camdyn table CASE.toml``: a CSV row per angle (motion, kinematic contact force, geometry)."""

from __future__ import annotations

import sys
from pathlib import Path

from .._core.errors import InputError
from .._core.outputs import write_new
from ..design.table import csv_text, motion_table
from ..model.case import build_case


def run(args) -> int:
    if not 0 < args.step <= 360:
        raise InputError("--step", f"must be in (0, 360] deg (got {args.step:g})")
    text = csv_text(motion_table(build_case(args.spec, source=Path(args.case)), args.step))
    if args.output:
        write_new(Path(args.output), text, args.force)
    else:
        sys.stdout.write(text)
    return 0
