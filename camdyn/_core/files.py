"""Reading a file the user named: bounded, and refused in one line before the read where it is not a text file.

A case or data file is read whole, so it is checked first: a device (``/dev/zero``), a FIFO (a read that never
ends) or a file larger than :data:`MAX_FILE_BYTES` (a sparse or runaway export) is refused by its ``stat``
before a byte is read, and the read itself stops at the limit should the file grow meanwhile.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from .errors import InputError

MAX_FILE_BYTES = 16 * 2**20  # 16 MiB: a 200 000-row lift table or contour at full precision is about 8 MiB


def _kind(mode: int) -> str:
    for test, what in (
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a FIFO (named pipe)"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return what
    return "not a regular file"


def data_file_path(name: str, case_file: Path | None) -> Path:
    """Where a data file a case names lies: relative to the case file's folder (to the working folder for a case
    built from a dict)."""
    return (case_file.parent if case_file is not None else Path.cwd()) / name


def check_file(path: Path, where: str, what: str) -> None:
    """One :class:`InputError` at ``where`` for a file that is missing, a folder, a device or FIFO, or larger than
    :data:`MAX_FILE_BYTES`, by its ``stat`` alone: a data file is refused with its case, before any model loads.
    ``what`` names the file's role in the messages ("case file", "data file")."""
    at = f" ({path})" if where else ""  # a data file is named as the case gives it: say where that led
    if "\x00" in str(path):
        raise InputError(where, "the file name contains a NUL byte: name a file without control characters")
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise InputError(where, f"no such file{at}") from None
    except OSError as err:
        raise InputError(where, f"cannot read the file: {err.strerror or err}") from None
    if stat.S_ISDIR(info.st_mode):
        raise InputError(where, f"is a folder, not a {what}")
    if not stat.S_ISREG(info.st_mode):
        raise InputError(where, f"is {_kind(info.st_mode)}, not a {what}: name a regular file{at}")
    if info.st_size > MAX_FILE_BYTES:
        raise InputError(
            where, f"is {info.st_size / 2**20:.1f} MiB, over the {MAX_FILE_BYTES // 2**20} MiB a {what} may have{at}"
        )


def read_text_file(path: Path, where: str, what: str) -> str:
    """The UTF-8 text (a byte-order mark dropped) of ``path``; one :class:`InputError` at ``where`` for a file
    :func:`check_file` refuses, or one unreadable, not UTF-8 or holding a NUL byte."""
    check_file(path, where, what)
    at = f" ({path})" if where else ""
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_FILE_BYTES + 1)
    except OSError as err:
        raise InputError(where, f"cannot read the file: {err.strerror or err}") from None
    if len(data) > MAX_FILE_BYTES:
        raise InputError(where, f"grew over the {MAX_FILE_BYTES // 2**20} MiB a {what} may have while it was read{at}")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(where, f"not UTF-8 text (byte {err.start})") from None
    if "\x00" in text:
        raise InputError(where, f"contains a NUL byte (at character {text.index(chr(0))}): not a text file")
    return text
