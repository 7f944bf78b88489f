"""Output files: names made from user data, folders to write into, and the overwrite guard.

A case's ``name`` is data, not a path: :func:`safe_stem` turns it into a file-name stem that cannot leave the
folder the user named (no separators, no ``..``, no leading dot).
"""

from __future__ import annotations

import re
from pathlib import Path

from .errors import InputError


def safe_stem(name: str) -> str:
    """A file-name stem from user data (a case name): letters, digits, ``._-``; never empty, never hidden."""
    s = re.sub(r"[^A-Za-z0-9._-]+", "-", name).strip("-.")
    return s or "case"


def output_dir(path, what: str = "output") -> Path:
    """``path`` as a folder to write into, created if missing; :class:`InputError` if it cannot be one."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InputError(str(path), f"exists and is not a folder: give -o a folder for the {what}")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise InputError(str(path), f"cannot create the {what} folder: {err.strerror or err}") from None
    return path


def refuse_overwrite(path: Path, force: bool) -> None:
    """:class:`InputError` if ``path`` exists and ``force`` is not given."""
    if path.exists() and not force:
        raise InputError(str(path), "exists; pass --force to overwrite it")


def write_new(path: Path, text: str, force: bool) -> None:
    """Write ``text`` to ``path`` (its folder created), refusing to replace a file without ``force``."""
    refuse_overwrite(path, force)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
