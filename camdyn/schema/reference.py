"""The case-file key reference, generated from the schema so that it cannot drift from it.

    python -m camdyn.schema.reference [--check] [DIR]

writes ``DIR/case-file.md`` (every table's keys with type, range, default and description, and the keys of
each follower, path and mechanism type) and ``DIR/case-file.schema.json`` (``CaseSpec.model_json_schema()``);
DIR defaults to ``docs/reference`` of the source tree. ``--check`` writes nothing and exits 1 when a file
differs from what the schema gives.

What it assumes of the schema (adapt :data:`FLAT_RULES` or :func:`type_keys` when the schema changes shape):

* Every table is a pydantic model reached from :class:`CaseSpec` or :class:`PathFileSpec` through their
  fields; a key's type, range (``gt``, ``ge``, ``lt``, ``le``, ``min_length``, ``max_length``), default and
  ``description`` come from its field, and a model's docstring introduces its table.
* A table whose keys depend on ``type`` is either one flat model whose rules sit in tables registered in
  :data:`FLAT_RULES` (type -> the keys it needs, type -> the keys it may take besides them), or a
  discriminated union of one model per type (``Annotated[A | B, Field(discriminator="type")]``): each member's
  required fields are the keys it needs, its other fields the keys it may take. In both, the keys every type
  takes are those no rule names (flat) or every member has alike (union).
* ``PathSpec`` and ``MechanismSpec`` keep their rules in a ``_KEYS`` table (type -> (needs, may take)) that their
  validators and their JSON Schema read too; ``tests/test_docs.py`` holds every rule table to its validator.
* In ``[dynamics]``, :data:`~camdyn.schema.dynamics.LINEAR_KEYS` and ``ROTARY_KEYS`` pair a translating key
  with its oscillating counterpart, and the first three of each kind are required in a case file.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import types
import typing
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import annotated_types as at
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from . import follower, mechanism, path
from .case import CaseSpec
from .dynamics import LINEAR_KEYS, ROTARY_KEYS, DynamicsSpec
from .follower import FollowerSpec
from .mechanism import MechanismSpec
from .path import PathSpec
from .pathfile import PathFileSpec

OUT_DIR = Path(__file__).resolve().parents[2] / "docs" / "reference"
MARKDOWN, JSON_SCHEMA = "case-file.md", "case-file.schema.json"


@dataclass(frozen=True)
class FlatRules:
    """The per-type keys of one flat model: type -> keys it needs, type -> keys it may take besides them."""

    needs: dict[str, tuple[str, ...]]
    takes: typing.Mapping[str, typing.Collection[str]]


def _rules(keys) -> FlatRules:
    """A ``TypeKeys`` table of the schema (type -> (needs, may take besides)) as :class:`FlatRules`."""
    return FlatRules({k: needs for k, (needs, _) in keys.items()}, {k: optional for k, (_, optional) in keys.items()})


FLAT_RULES: dict[type[BaseModel], FlatRules] = {
    FollowerSpec: FlatRules(follower._NEEDS, follower._TAKES),
    PathSpec: _rules(path._KEYS),
    MechanismSpec: _rules(mechanism._KEYS),
}


@dataclass(frozen=True)
class TypeKeys:
    """The keys of a table that depends on ``type``: those every type takes, and per type (needed, optional)."""

    common: tuple[str, ...]
    by_type: dict[str, tuple[tuple[str, ...], tuple[str, ...]]]


# -- reading the models --------------------------------------------------------------------------------------


def _strip(annotation):
    """``annotation`` without ``Annotated`` metadata and without ``None`` in a union."""
    if typing.get_origin(annotation) is typing.Annotated:
        return _strip(typing.get_args(annotation)[0])
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(annotation) if a is not type(None)]
        return _strip(args[0]) if len(args) == 1 else typing.Union[tuple(_strip(a) for a in args)]  # noqa: UP007 (built at run time from a tuple)
    return annotation


def models_in(annotation: Any) -> list[type[BaseModel]]:
    """The pydantic models a field holds (one table, a union of tables, or a list of tables), in order."""
    annotation = _strip(annotation)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    if typing.get_origin(annotation) is typing.Literal:
        return []
    return [m for arg in typing.get_args(annotation) for m in models_in(arg)]


def _is_list(annotation) -> bool:
    return typing.get_origin(_strip(annotation)) is list


def _type_name(annotation) -> str:
    a = _strip(annotation)
    origin = typing.get_origin(a)
    if models_in(a):
        return "array of tables" if origin is list else "table"
    if origin is typing.Literal:
        kinds = {type(v) for v in typing.get_args(a)}
        return (
            {str: "string", int: "integer", bool: "boolean"}.get(kinds.pop(), "value") if len(kinds) == 1 else "value"
        )
    if origin is list:
        return f"array of {_type_name(typing.get_args(a)[0])}s"
    if origin is tuple:
        return "[" + ", ".join(_type_name(t) for t in typing.get_args(a)) + "]"
    if origin in (typing.Union, types.UnionType):
        return " or ".join(_type_name(t) for t in typing.get_args(a))
    return {float: "number", int: "integer", str: "string", bool: "boolean"}.get(a, getattr(a, "__name__", str(a)))


def _toml(value) -> str:
    """A value as it is written in a case file."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):  # the shortest form that reads back the same: 30, 0.05, 1e7 (not 1e+07)
        text = f"{value:g}" if float(f"{value:g}") == value else repr(value)
        return re.sub(r"e\+?(-?)0*(\d)", r"e\1\2", text)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, tuple | list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return str(value)


_BOUNDS = (
    (at.Gt, "gt", "> {}"),
    (at.Ge, "ge", ">= {}"),
    (at.Lt, "lt", "< {}"),
    (at.Le, "le", "<= {}"),
    (at.MinLen, "min_length", "at least {} item"),
    (at.MaxLen, "max_length", "at most {} item"),
)


def _range(field: FieldInfo) -> str:
    a = _strip(field.annotation)
    if typing.get_origin(a) is typing.Literal:
        return ", ".join(f"`{_toml(v)}`" for v in typing.get_args(a))
    out = []
    for m in field.metadata:
        for cls, attr, fmt in _BOUNDS:
            if isinstance(m, cls):
                n = getattr(m, attr)
                out.append(fmt.format(_toml(n)) + ("s" if fmt.endswith("item") and n != 1 else ""))
    return ", ".join(out)


def _default(field: FieldInfo) -> str:
    if field.is_required():
        return "required"
    value = field.get_default(call_default_factory=True)
    if value is None:
        return "—"
    if isinstance(value, BaseModel):
        return "its defaults"
    return f"`{_toml(value)}`"


def _cell(text: str) -> str:
    """Plain text for a table cell: ``|`` and ``*`` escaped outside code spans, one line."""
    parts = re.split(r"(`[^`]*`)", " ".join(text.split()))
    return "".join(p if p.startswith("`") else p.replace("|", "\\|").replace("*", "\\*") for p in parts)


def type_keys(annotation: Any) -> TypeKeys | None:
    """The per-type keys of a table field (a flat model in :data:`FLAT_RULES` or a discriminated union of one
    model per ``type``); ``None`` for a table whose keys do not depend on ``type``."""
    members = models_in(annotation)
    if len(members) == 1 and members[0] in FLAT_RULES:
        model, rules = members[0], FLAT_RULES[members[0]]
        named = {k for keys in (*rules.needs.values(), *rules.takes.values()) for k in keys}
        order = list(model.model_fields)
        common = tuple(k for k in order if k not in named and k != "type")
        return TypeKeys(
            common,
            {
                t: (
                    tuple(rules.needs[t]),
                    tuple(k for k in order if k in set(rules.takes.get(t, ())) - set(rules.needs[t])),
                )
                for t in typing.get_args(_strip(model.model_fields["type"].annotation))
            },
        )
    if len(members) > 1 and all("type" in m.model_fields for m in members):

        def sig(m: type[BaseModel], k: str) -> tuple[bool, str, str | None]:
            f = m.model_fields[k]
            return (f.is_required(), _default(f), f.description)

        shared = [k for k in members[0].model_fields if k != "type" and all(k in m.model_fields for m in members)]
        common = tuple(k for k in shared if len({sig(m, k) for m in members}) == 1)
        by_type = {}
        for m in members:
            for t in typing.get_args(_strip(m.model_fields["type"].annotation)):
                rest = [k for k in m.model_fields if k != "type" and k not in common]
                by_type[t] = (
                    tuple(k for k in rest if m.model_fields[k].is_required()),
                    tuple(k for k in rest if not m.model_fields[k].is_required()),
                )
        return TypeKeys(common, by_type)
    return None


def _header(key: str, field: FieldInfo) -> str:
    """The TOML header of the table a field holds: ``[motion]``, ``[[motion.segments]]`` for an array."""
    return f"[[{key}]]" if _is_list(field.annotation) else f"[{key}]"


def _fields(annotation) -> dict[str, list[FieldInfo]]:
    """The keys of a table field, each with its field in every model that has it (one, unless a union)."""
    out: dict[str, list[FieldInfo]] = {}
    for m in models_in(annotation):
        for k, f in m.model_fields.items():
            out.setdefault(k, []).append(f)
    return out


def _row(fields: list[FieldInfo], members: int = 1) -> tuple[str, str, str, str]:
    """Type, range, default and description of a key held by ``len(fields)`` of a union's ``members``; where
    they differ: the values of all (a literal such as ``type``, the descriptions), else "by type" (see the table
    of each type), as is "required" by only some types."""

    def distinct(values: Iterable[str]) -> list[str]:
        return list(dict.fromkeys(values))

    literal = all(typing.get_origin(_strip(f.annotation)) is typing.Literal for f in fields)
    ranges, defaults = distinct(_range(f) for f in fields), distinct(_default(f) for f in fields)
    rng = ", ".join(ranges) if literal else ranges[0] if len(ranges) == 1 else "by type"
    desc = "; ".join(distinct(f.description or "" for f in fields))
    if any(f.deprecated for f in fields):
        why = next(f.deprecated for f in fields if f.deprecated)
        desc = f"deprecated{': ' + why if isinstance(why, str) else ''}. {desc}"
    default = defaults[0] if len(defaults) == 1 and (len(fields) == members or defaults != ["required"]) else "by type"
    return _type_name(fields[0].annotation), rng, default, _cell(desc)


# -- writing the reference ------------------------------------------------------------------------------------


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading."""
    return re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-")


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.anchor: dict[type[BaseModel], str] = {}

    def section(self, heading: str, level: int, doc: str | None) -> None:
        """A heading and the docstring of its model as plain paragraphs (one that only names its table left out)."""
        self.lines += ["", "#" * level + " " + heading, ""]
        doc = (doc or "").replace("``", "`").strip()
        if doc and not re.fullmatch(r"The `\[\w+\]` table\.", doc):
            self.lines += [line for p in doc.split("\n\n") for line in (" ".join(p.split()), "")]

    def keys(self, fields: dict[str, list[FieldInfo]], prefix: str) -> None:
        """The key table of one table; a key that holds a table links to its section."""
        rows = [("key", "type", "range", "default", "description")]
        n_models = max(map(len, fields.values()))
        for name, fs in fields.items():
            key = f"`{name}`"
            if members := models_in(fs[0].annotation):  # a table: its header at the top level, its key inside one
                # a table not written yet gets its section under the first key that holds it (see tables)
                first = next(n for n, g in fields.items() if models_in(g[0].annotation)[:1] == members[:1])
                anchor = self.anchor.get(members[0]) or _slug(f"`{_header(prefix + first, fields[first][0])}`")
                key = f"[`{_header(name, fs[0]) if not prefix else name}`](#{anchor})"
            rows.append((key, *_row(fs, n_models)))
        self.table(rows)

    def table(self, rows: list[tuple[str, ...]]) -> None:
        """An aligned Markdown table (the last column is left ragged)."""
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]

        def line(cells: Sequence[str]) -> str:
            return "| " + " | ".join([*(c.ljust(w) for c, w in zip(cells, widths, strict=False)), cells[-1]]) + " |"

        self.lines += [line(rows[0]), line(["-" * w for w in widths] + ["---"]), *(line(r) for r in rows[1:])]

    def by_type(self, table: str, tk: TypeKeys, level: int) -> None:
        self.section(f"Keys of each `[{table}]` type", level, None)
        common = ", ".join(f"`{k}`" for k in tk.common)
        self.lines += [
            f"Every type takes {common}. Besides, each type needs some keys and may take others; a key "
            "of another type is refused.",
            "",
        ]

        def code(keys: Iterable[str]) -> str:
            return ", ".join(f"`{k}`" for k in keys) or "—"

        self.table(
            [("`type`", "needs", "may take"), *((f"`{t}`", code(n), code(o)) for t, (n, o) in tk.by_type.items())]
        )

    def document(self, heading: str, model: type[BaseModel]) -> None:
        """A whole file (case file, path file): its keys, then each of its tables not yet written."""
        self.section(heading, 2, model.__doc__)
        self.anchor[model] = _slug(heading)
        self.keys(_fields(model), "")
        self.tables(_fields(model), "")

    def tables(self, fields: dict[str, list[FieldInfo]], prefix: str) -> None:
        """A section per table among ``fields`` (depth first): its keys and, where they depend on ``type``, the
        keys of each type."""
        level = 2 + prefix.count(".")
        for name, (f, *_) in fields.items():
            members = models_in(f.annotation)
            if not members or all(m in self.anchor for m in members):
                continue
            heading = f"`{_header(prefix + name, f)}`"
            self.section(heading, level, members[0].__doc__ if len(members) == 1 else f.description)
            self.anchor.update({m: _slug(heading) for m in members})
            inner = _fields(f.annotation)
            self.keys(inner, f"{prefix}{name}.")
            if (tk := type_keys(f.annotation)) is not None:
                self.by_type(prefix + name, tk, level + 1)
            if members == [DynamicsSpec]:
                self._dynamics_kinds(level + 1)
            self.tables(inner, f"{prefix}{name}.")

    def _dynamics_kinds(self, level: int) -> None:
        self.section("Keys of each follower kind in `[dynamics]`", level, None)
        need_lin, need_rot = ", ".join(f"`{k}`" for k in LINEAR_KEYS[:3]), ", ".join(f"`{k}`" for k in ROTARY_KEYS[:3])
        self.lines += [
            "A translating follower (and a `ccm` mechanism) takes the translating keys, an oscillating follower (and "
            "an `oscillating` mechanism) their rotational counterparts; a key of the other kind is refused (a zero "
            f"external force or torque excepted). A case file needs {need_lin}, or {need_rot}; the other keys of "
            "`[dynamics]` are the same for both kinds.",
            "",
        ]
        self.table(
            [
                ("translating", "oscillating"),
                *((f"`{a}`", f"`{b}`") for a, b in zip(LINEAR_KEYS, ROTARY_KEYS, strict=True)),
            ]
        )


_HEAD = """\
# Case-file reference

<!-- Generated from camdyn/schema/ by `python -m camdyn.schema.reference`: edit the schema, not this file. -->

A case file is TOML. Each table below lists its keys: the type, the range a number must lie in (or the values a
key takes), the default, and what it means with its unit. Default "required": the key must be given; "—": the
key is unset unless given, and its description says what applies then. A key not listed, NaN and inf are
refused with one line naming the key. [case-file.schema.json](case-file.schema.json) is the JSON Schema of a case
file (key types and ranges; the rules between keys, such as the keys of each type, are checked by camdyn). The
[guide](../guide.md) shows how the tables are used."""


DOCUMENTS = (("Case file", CaseSpec), ("Path file", PathFileSpec))


def reference_markdown(documents: Sequence[tuple[str, type[BaseModel]]] = DOCUMENTS) -> str:
    """The Markdown key reference of ``documents`` ((heading, model) pairs: case files and path files)."""
    w = _Writer()
    w.lines = [*_HEAD.splitlines()]
    for heading, model in documents:
        w.document(heading, model)
    return "\n".join(w.lines) + "\n"


def case_file_schema() -> str:
    """The JSON Schema of a case file (pydantic writes draft 2020-12)."""
    schema = {"$schema": "https://json-schema.org/draft/2020-12/schema", **CaseSpec.model_json_schema()}
    return json.dumps(schema, indent=2, ensure_ascii=False) + "\n"


def generated() -> dict[str, str]:
    """File name -> the text the schema gives it."""
    return {MARKDOWN: reference_markdown(), JSON_SCHEMA: case_file_schema()}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m camdyn.schema.reference", description=(__doc__ or "").partition("\n")[0]
    )
    ap.add_argument("dir", nargs="?", type=Path, default=OUT_DIR, help=f"output folder (default: {OUT_DIR})")
    ap.add_argument("--check", action="store_true", help="write nothing; exit 1 when a file differs from the schema's")
    args = ap.parse_args(argv)
    stale = []
    for name, text in generated().items():
        target = args.dir / name
        current = target.read_text(encoding="utf-8") if target.is_file() else None
        if current == text:
            continue
        stale.append(str(target))
        if not args.check:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text, encoding="utf-8")
    verb = "differs from the schema" if args.check else "written"
    for name in stale:
        print(f"{name}: {verb}", file=sys.stderr if args.check else sys.stdout)
    return 1 if stale and args.check else 0


if __name__ == "__main__":
    sys.exit(main())
