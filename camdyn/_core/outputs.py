"""Output files: names made from user data, the files and folders a command writes, and the overwrite guard.

A case's ``name`` is data, not a path: :func:`safe_stem` turns it into a file-name stem that cannot leave the
folder the user named (no separators, no ``..``, no leading dot). Commands check where their output goes
(:func:`output_file`, :func:`output_dir`) before they work, not after minutes of it.
"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Iterable
from pathlib import Path

from .errors import InputError

# the longest stem made from user data: with the suffixes a command adds ("-machine-1-summary.png") far below the 255
# bytes a file name may have on common file systems
MAX_STEM = 96


def safe_stem(name: str) -> str:
    """A file-name stem from user data (a case name): letters, digits, ``._-``; never empty, never hidden, at most
    :data:`MAX_STEM` characters (a longer one cut, with a digest of the whole name, so that two names that differ
    only past the cut still name two files)."""
    s = re.sub(r"[^A-Za-z0-9._-]+", "-", name).strip("-.")
    if len(s) > MAX_STEM:
        digest = hashlib.sha256(name.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        s = f"{s[: MAX_STEM - 9].rstrip('-.')}-{digest}"
    return s or "case"


def _writable_dir(path: Path, what: str) -> Path:
    """``path`` as an existing folder that can be written into (created, with its parents, if missing)."""
    if path.exists() and not path.is_dir():
        raise InputError(str(path), f"exists and is not a folder: give a folder for the {what}")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise InputError(
            str(path), f"a part of this path is a file, not a folder: give a folder for the {what}"
        ) from None
    except OSError as err:
        raise InputError(str(path), f"cannot create the {what} folder: {err.strerror or err}") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError(
            str(path), f"cannot write into this folder (permission denied): give another folder for the {what}"
        )
    return path


def output_dir(path: str | Path, what: str = "output") -> Path:
    """``path`` as a folder to write into, created if missing; :class:`InputError` if it cannot be one."""
    return _writable_dir(Path(path), what)


def output_file(path: str | Path, force: bool, what: str = "output") -> Path:
    """``path`` as a file to write: not a folder, not an existing file unless ``force``, its folder created and
    writable. Call it before the work that makes the file."""
    path = Path(path)
    if path.is_dir():
        raise InputError(str(path), f"is a folder: give a file name for the {what}")
    refuse_overwrite(path, force)
    _writable_dir(path.parent if str(path.parent) else Path("."), what)
    return path


def refuse_overwrite(path: Path, force: bool) -> None:
    """:class:`InputError` if ``path`` exists and ``force`` is not given."""
    if path.exists() and not force:
        raise InputError(str(path), "exists; pass --force to overwrite it")


# what marks a file camdyn wrote: a report's PDF (its Creator) and PNG pages (their Software text chunk)
CAMDYN_MARKS = (b"/Creator (camdyn)", b"tEXtSoftware\x00camdyn")
_MARKED_BYTES = 64 * 2**20  # a file larger than this is no page of camdyn's


def refuse_foreign(paths: Iterable[Path]) -> None:
    """:class:`InputError` for the first of ``paths`` that exists and is not a file camdyn wrote (no
    :data:`CAMDYN_MARKS` in it): a report rewrites its own files of an earlier run, never a user's of the same name."""
    for path in paths:
        if not path.exists():
            continue
        try:
            ours = (
                path.is_file()
                and path.stat().st_size <= _MARKED_BYTES
                and any(mark in path.read_bytes() for mark in CAMDYN_MARKS)
            )
        except OSError:
            ours = False
        if not ours:
            raise InputError(
                str(path),
                "exists and is not a file camdyn wrote: move it, or give another folder (a report rewrites "
                "only its own files)",
            )


def write_new(path: Path, text: str, force: bool) -> None:
    """Write ``text`` to ``path`` (see :func:`output_file`), refusing to replace a file without ``force``."""
    path = output_file(path, force)
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as err:
        raise InputError(str(path), f"cannot write the file: {err.strerror or err}") from None
