"""The schema's base: strict tables (no unknown keys, no NaN or inf, frozen) and one-line validation errors."""

from __future__ import annotations

import re
from collections.abc import Callable
from difflib import get_close_matches
from typing import Annotated, Any, TypeVar, get_args, get_origin

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, Tag, ValidationError

from .._core.errors import InputError
from .._core.units import MAX_LENGTH_MM


class Table(BaseModel):
    """A table of a case file: unknown keys, NaN and inf are refused; validated values are frozen."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)


# a number: an int or a float, never a bool or a string (TOML's ``true`` is not 1 rpm)
Real = Annotated[float, Field(strict=True)]
Pair = tuple[Real, Real]
# a coordinate in the case's frame, mm: within the physical bound on lengths
Coordinate = Annotated[float, Field(strict=True, ge=-MAX_LENGTH_MM, le=MAX_LENGTH_MM)]
Point = tuple[Coordinate, Coordinate]

# a validator names the key it refuses as "key: message" (the key may be dotted or indexed: "segments[2].end")
_KEYED = re.compile(r"^([A-Za-z_][\w]*(?:\[\d+\])?(?:\.[A-Za-z_][\w]*(?:\[\d+\])?)*): (.*)$", re.S)


# keys of a table with a ``type``: type -> (the keys it needs, the keys it may take besides); a key named for no
# type is one every type takes
TypeKeys = dict[str, tuple[tuple[str, ...], tuple[str, ...]]]


def _specific(keys: TypeKeys) -> set[str]:
    return {k for needs, optional in keys.values() for k in (*needs, *optional)}


def check_type_keys(table: BaseModel, t: str, kind: str, keys: TypeKeys) -> None:
    """Raise ``ValueError("key: message")`` for a key the table's ``type`` needs and lacks, or one given that
    belongs to other types only; ``t`` is the table's ``type``, ``kind`` names the table in the message ("path",
    "mechanism")."""
    a = "an" if t[0] in "aeiou" else "a"
    needs, optional = keys[t]
    for key in needs:
        if getattr(table, key) is None:
            raise ValueError(f"{key}: required for {a} {t} {kind}")
    specific, takes = _specific(keys), {*needs, *optional}
    for key in type(table).model_fields:
        if key in specific and key not in takes and key in table.model_fields_set and getattr(table, key) is not None:
            allowed = sorted(k for k in type(table).model_fields if k in takes or k not in specific)
            raise ValueError(f"{key}: not used by {a} {t} {kind} (keys: {', '.join(allowed)})")


def keys_by_type(keys: TypeKeys) -> Callable[[dict, type[BaseModel]], None]:
    """A ``json_schema_extra`` that declares, per ``type``, the keys it needs and the only keys it takes (JSON
    Schema ``if``/``then``), from the same table :func:`check_type_keys` validates with."""

    def extra(schema: dict, cls: type[BaseModel]) -> None:
        specific = _specific(keys)
        schema["allOf"] = [
            {
                "if": {"properties": {"type": {"const": t}}},
                "then": {
                    "required": list(needs),
                    "propertyNames": {
                        "enum": [k for k in cls.model_fields if k not in specific or k in {*needs, *optional}]
                    },
                },
            }
            for t, (needs, optional) in keys.items()
        ]

    return extra


def _models_in(annotation) -> list[tuple[str | None, type[BaseModel]]]:
    """The models an annotation holds (a model, a list or optional of models, a tagged union), with their tags."""
    if get_origin(annotation) is Annotated:
        inner, *meta = get_args(annotation)
        tag = next((m.tag for m in meta if isinstance(m, Tag)), None)
        return [(tag or t, model) for t, model in _models_in(inner)]
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [(None, annotation)]
    return [pair for arg in get_args(annotation) for pair in _models_in(arg)]


def _resolve(cls: type[BaseModel], loc: tuple) -> tuple[tuple, type[BaseModel] | None]:
    """The key path of an error location without the tags of discriminated unions (pydantic puts the chosen
    member's tag in the path: ``segments.0.polynomial.end``), and the model that owns its last key."""
    model: type[BaseModel] | None = cls
    tagged: dict[str, type[BaseModel]] = {}
    out: list = []
    owner = None
    for part in loc:
        if isinstance(part, str) and part in tagged:
            model, tagged = tagged[part], {}
            continue
        out.append(part)
        owner = model
        if isinstance(part, int) or model is None:
            continue
        field = model.model_fields.get(part)
        found = _models_in(field.annotation) if field is not None else []
        tagged = {t: m for t, m in found if t is not None}
        model = found[0][1] if len(found) == 1 and not tagged else None
    return tuple(out), owner


def _where(loc: tuple) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def validation_error(err: ValidationError, cls: type[BaseModel], table: str = "") -> InputError:
    """The first problem of a pydantic validation as one :class:`InputError` naming the key (prefixed with
    ``table``, e.g. ``path.width``), with the nearest valid key for an unknown one."""
    errors = err.errors()
    e = errors[0]
    if e["type"] == "missing":  # beside an unknown key at the same level: that one is the missing key misspelt
        e = next((x for x in errors if x["type"] == "extra_forbidden" and x["loc"][:-1] == e["loc"][:-1]), e)
    loc, owner = _resolve(
        cls, tuple(p for p in e["loc"] if not (isinstance(p, str) and ("[" in p or p.startswith("function-"))))
    )
    msg = e["msg"].removeprefix("Value error, ")
    keyed = _KEYED.match(msg) if e["type"] == "value_error" else None
    if keyed:  # a table-level validator names its key: "key: message"
        key, msg = keyed.groups()
        loc = loc + (key,)
    where = ".".join(filter(None, (table, _where(loc)))) or "case"
    if e["type"] == "extra_forbidden":
        hint = get_close_matches(str(loc[-1]), list(owner.model_fields), n=1) if owner else []
        got = e.get("input")
        tabular = isinstance(got, dict) or (isinstance(got, list) and got and all(isinstance(t, dict) for t in got))
        if len(loc) == 1 and not table and tabular:
            # a [table] (or an array of [[tables]]) of the file
            tables = [k for k, f in owner.model_fields.items() if _models_in(f.annotation)] if owner else []
            hint = get_close_matches(str(loc[-1]), tables, n=1)
            valid = f"; tables: {', '.join(f'[{t}]' for t in tables)}" if not hint else ""
            mean = f" (did you mean [{hint[0]}]?)" if hint else ""
            return InputError(where, f"unknown table [{loc[-1]}]{mean}{valid}")
        valid = f"; valid keys: {', '.join(owner.model_fields)}" if owner and not hint else ""
        return InputError(where, "unknown key" + (f" (did you mean {hint[0]!r}?)" if hint else "") + valid)
    if e["type"] == "missing" and loc and isinstance(loc[-1], int) and isinstance(e.get("input"), list):
        # a position of a fixed-length list (a pair of names or numbers): name the list and what it holds
        where = ".".join(filter(None, (table, _where(loc[:-1])))) or "case"
        same = [int(x["loc"][-1]) for x in errors if x["type"] == "missing" and x["loc"][:-1] == e["loc"][:-1]]
        return InputError(where, f"expected {max(same) + 1} values, got {len(e['input'])} ({e['input']!r})")
    if e["type"] == "missing":
        return InputError(where, "required key is missing")
    if "input" in e and not isinstance(e["input"], dict | list) and not keyed:
        got = e["input"]
        msg += f" (got {got:g})" if isinstance(got, float) else f" (got {got!r})"
    return InputError(where, msg)


_Model = TypeVar("_Model", bound=BaseModel)


def parse(cls: type[_Model], raw: Any, table: str = "") -> _Model:
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
# a data file's name, relative to the case file: plain text too (a NUL or a tab in a path is a slip, not a file)
FileName = Name
Text = Annotated[str, AfterValidator(lambda s: _plain(s, "\n\t"))]
