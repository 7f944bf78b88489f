"""``camdyn table CASE.toml``: a CSV row per angle (motion, kinematic and dynamic contact force, geometry); with
``--ecam N`` a servo drive's e-cam table (position, velocity, acceleration per master degree)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .._core.errors import InputError
from .._core.outputs import output_file, write_new
from ..design.table import csv_text, ecam_table, motion_table, table_angles
from ..model.case import build_case


def run(args: argparse.Namespace) -> int:
    table_angles(args.step)  # a bad step is refused before any model is built
    if args.output:
        output_file(args.output, args.force, "table")
    if args.ecam is not None:
        if args.speed is not None:
            raise InputError("--speed", "does not apply to an e-cam table (positions per master angle, no forces)")
        case = build_case(args.spec, source=Path(args.case))
        cols, units = ecam_table(case, args.ecam)
        text = f"# camdyn e-cam table of {case.name}: {units}\n" + csv_text(cols)
    else:
        text = csv_text(motion_table(build_case(args.spec, source=Path(args.case)), args.step, args.speed))
    if args.output:
        write_new(Path(args.output), text, args.force)
    else:
        sys.stdout.write(text)
    return 0
