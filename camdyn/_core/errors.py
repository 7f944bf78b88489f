"""The two ways camdyn refuses: bad input and numerical failure (both exit code 2)."""

from __future__ import annotations


class CamdynError(Exception):
    """An error reported to the user as one line: ``<file>: <where>: <message>``.

    ``where`` names the key (``dynamics.mass``), the segment, the angle or the path point.
    """

    def __init__(self, where: str, message: str) -> None:
        super().__init__(f"{where}: {message}" if where else message)
        self.where = where
        self.message = message


class InputError(CamdynError):
    """The case file (or a command-line value) is invalid."""


class NumericalError(CamdynError):
    """A computation failed: solver out of steps, a dyad that cannot close, NaN, ..."""
