"""The schema's base: strict tables (no unknown keys, no NaN or inf, frozen) and one-line validation errors."""

from __future__ import annotations

import re
from difflib import get_close_matches

from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, ValidationError

from .._core.errors import InputError


class Table(BaseModel):
    """A table of a case file: unknown keys, NaN and inf are refused; validated values are frozen."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)


# a number: an int or a float, never a bool or a string (TOML's ``true`` is not 1 rpm)
Real = Annotated[float, Field(strict=True)]
Pair = tuple[Real, Real]

# a validator names the key it refuses as "key: message" (the key may be dotted or indexed: "segments[2].end")
_KEYED = re.compile(r"^([A-Za-z_][\w]*(?:\[\d+\])?(?:\.[A-Za-z_][\w]*(?:\[\d+\])?)*): (.*)$", re.S)


def _model_at(model: type[BaseModel] | None, loc: tuple) -> type[BaseModel] | None:
    """The pydantic model that owns the key at ``loc`` (to suggest the nearest valid key)."""
    for part in loc[:-1]:
        if isinstance(part, int) or model is None:
            continue
        field = model.model_fields.get(part)
        if field is None:
            return None
        cand = [t for t in getattr(field.annotation, "__args__", (field.annotation,)) if isinstance(t, type) and issubclass(t, BaseModel)]
        if not cand:
            args = getattr(field.annotation, "__args__", ())
            cand = [a for t in args for a in getattr(t, "__args__", ()) if isinstance(a, type) and issubclass(a, BaseModel)]
        model = cand[0] if cand else None
    return model


def _where(loc: tuple) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def validation_error(err: ValidationError, cls: type[BaseModel], table: str = "") -> InputError:
    """The first problem of a pydantic validation as one :class:`InputError` naming the key (prefixed with
    ``table``, e.g. ``path.width``), with the nearest valid key for an unknown one."""
    e = err.errors()[0]
    loc = tuple(p for p in e["loc"] if not (isinstance(p, str) and ("[" in p or p.startswith("function-"))))
    msg = e["msg"].removeprefix("Value error, ")
    keyed = _KEYED.match(msg) if e["type"] == "value_error" else None
    if keyed:  # a table-level validator names its key: "key: message"
        key, msg = keyed.groups()
        loc = loc + (key,)
    where = ".".join(filter(None, (table, _where(loc)))) or "case"
    if e["type"] == "extra_forbidden":
        owner = _model_at(cls, loc)
        hint = get_close_matches(str(loc[-1]), list(owner.model_fields), n=1) if owner else []
        valid = f"; valid keys: {', '.join(owner.model_fields)}" if owner and not hint else ""
        return InputError(where, "unknown key" + (f" (did you mean {hint[0]!r}?)" if hint else "") + valid)
    if e["type"] == "missing":
        return InputError(where, "required key is missing")
    if "input" in e and not isinstance(e["input"], dict | list) and not keyed:
        got = e["input"]
        msg += f" (got {got:g})" if isinstance(got, float) else f" (got {got!r})"
    return InputError(where, msg)


def parse(cls: type[BaseModel], raw, table: str = ""):
    """Validate ``raw`` as ``cls``; every problem is one :class:`InputError` naming ``table.key``."""
    try:
        return cls.model_validate(raw)
    except ValidationError as err:
        raise validation_error(err, cls, table) from None


def _plain(text: str | None, allowed: str) -> str | None:
    """``text`` unless it holds control characters other than ``allowed`` (a NUL byte in a name...)."""
    if text is not None:
        bad = sorted({repr(c) for c in text if (ord(c) < 32 or ord(c) == 127) and c not in allowed})
        if bad:
            raise ValueError(f"contains a control character ({', '.join(bad)}): use plain text")
    return text


# a name (also a file-name stem) and a description: plain text, a description may run over lines
Name = Annotated[str, AfterValidator(lambda s: _plain(s, ""))]
Text = Annotated[str, AfterValidator(lambda s: _plain(s, "\n\t"))]
