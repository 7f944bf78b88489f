"""``camdyn table CASE.toml``: a CSV row per angle (motion, kinematic and dynamic contact force, geometry); with
``--ecam N`` a servo drive's e-cam table (position, velocity, acceleration per master degree)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .._core.outputs import write_new
from ..design.table import csv_text, ecam_table, motion_table
from ..model.case import build_case


def run(args: argparse.Namespace) -> int:
    # the step, the e-cam's angles and the output file were checked before JAX loaded (camdyn.cli._options)
    if args.ecam is not None:
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
