"""``camdyn report CASE.toml ... -o DIR``: a design-review PDF and a PNG per page for each case."""

from __future__ import annotations

import argparse

from ..report import report_cases
from ._console import progress_bar


def run(args: argparse.Namespace) -> int:
    with progress_bar(args.quiet) as progress:
        written = report_cases(args.cases, args.output, speed_rpm=args.speed, specs=args.specs, progress=progress)
    for w in written:
        print(f"wrote {w.pdf} ({len(w.pngs)} pages, {w.verdict}) and {', '.join(p.name for p in w.pngs)}")
    return 0
