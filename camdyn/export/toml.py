"""Case files written by camdyn (``synthesize``, ``optimize``): TOML with a header saying how they were made."""

from __future__ import annotations

import re
import textwrap
import tomllib
from importlib.metadata import PackageNotFoundError, version

import tomli_w


def camdyn_version() -> str:
    """camdyn's installed version, for a written file's header ("" in a source tree on sys.path)."""
    try:
        return version("camdyn")
    except PackageNotFoundError:
        return ""


def dumps_case(doc: dict, header: list[str]) -> str:
    """TOML text of ``doc`` (tomli-w) with arrays of numbers on one line and ``header`` as comment lines."""
    body = tomli_w.dumps(doc, multiline_strings=True)

    def inline(m: re.Match) -> str:
        items = [line.strip().removesuffix(",") for line in m.group(2).splitlines()]
        return f"{m.group(1)}[{', '.join(items)}]\n"

    short = re.sub(r"^([A-Za-z0-9_]+ = )\[\n((?:    [^\n\[\]{}]*,\n)+)\]\n", inline, body, flags=re.M)
    if tomllib.loads(short) == tomllib.loads(body):  # only ever a change of layout
        body = short
    lines = [w for line in header for w in textwrap.wrap(line, 112, break_long_words=False, break_on_hyphens=False)]
    return "".join(f"# {line}\n" for line in lines) + "\n" + body
