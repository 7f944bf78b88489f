"""The golden snapshot of every shipped case's numbers: ``check --json``, ``size --json`` and ``table`` CSV.

Run ``python tests/golden_regen.py`` (from the repository root, ``PYTHONPATH=.``) to rewrite
``tests/data/golden/<case>.json.gz`` with the current code; ``tests/test_golden.py`` compares against them. Regenerate
only when a change of numbers is intended, and say why in the commit.
"""

from __future__ import annotations

import contextlib
import csv
import gzip
import io
import json
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "cases"
GOLDEN = Path(__file__).resolve().parent / "data" / "golden"


def shipped_cases() -> list[Path]:
    """Every shipped case file: ``cases/*.toml`` and the cams of ``cases/machines`` (not the machine files, which
    list ``[[cam]]``); ``cases/paths`` holds the inputs of ``synthesize``, whose cases ship as ``cases/<name>.toml``."""
    cams = [p for p in sorted((CASES / "machines").glob("*.toml")) if "cam" not in tomllib.loads(p.read_text())]
    return sorted(CASES.glob("*.toml")) + cams


def golden_name(case: Path) -> str:
    """The snapshot's name: the case file's path under ``cases/``, ``/`` as ``-``."""
    return case.relative_to(CASES).with_suffix("").as_posix().replace("/", "-")


def _cli(*argv: str) -> tuple[int, str]:
    """``camdyn ARGV`` in this process: (exit code, stdout)."""
    from camdyn.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(list(argv))
    return code, out.getvalue()


def _table_rows(text: str) -> list[list]:
    """The CSV's rows, numbers as floats (so they compare at a tolerance), other cells as strings."""
    rows = []
    for row in csv.reader(io.StringIO(text)):
        cells = []
        for cell in row:
            try:
                cells.append(float(cell))
            except ValueError:
                cells.append(cell)
        rows.append(cells)
    return rows


def _untimed(doc):
    """``doc`` with every timing (a key ending in ``time_s``) replaced by a marker: the key stays, its value varies."""
    if isinstance(doc, dict):
        return {k: "<time>" if k.endswith("time_s") else _untimed(v) for k, v in doc.items()}
    if isinstance(doc, list):
        return [_untimed(v) for v in doc]
    return doc


def snapshot(case: Path) -> dict:
    """Everything the golden test compares for one case: each command's exit code and output."""
    out = {}
    code, text = _cli("check", "--json", str(case))
    out["check"] = {"exit": code, "json": _untimed(json.loads(text)) if code in (0, 1) else None}
    code, text = _cli("size", "--json", "--quiet", str(case))
    out["size"] = {"exit": code, "json": _untimed(json.loads(text)) if code in (0, 1) else None}
    code, text = _cli("table", "--quiet", str(case))
    out["table"] = {"exit": code, "rows": _table_rows(text) if code == 0 else None}
    return out


def golden_file(case: Path) -> Path:
    return GOLDEN / f"{golden_name(case)}.json.gz"


def main(names: list[str]) -> None:
    """Rewrite the snapshots of every shipped case, or of those named (``golden_name``)."""
    GOLDEN.mkdir(parents=True, exist_ok=True)
    for case in shipped_cases():
        if names and golden_name(case) not in names:
            continue
        snap = snapshot(case)
        golden_file(case).write_bytes(gzip.compress(json.dumps(snap, sort_keys=False).encode(), mtime=0))
        print(case.name, {k: v["exit"] for k, v in snap.items()}, file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
