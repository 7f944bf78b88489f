"""The arguments of a :func:`camdyn._core.jit.cached_jit` call, flattened to key its program and to call it: an
object with a ``jit_form`` (a motion) as that form, an equinox module flattened once per object, and a number per
signature (its structure, static values and array shapes), so that a call's key is hashed from a few numbers, not
from the arguments (about 0.1 ms a call less: a valvetrain revolution makes dozens)."""

from __future__ import annotations

import itertools
import threading
from typing import Any, NamedTuple, TypeVar

import equinox as eqx
import jax
from jax.core import Tracer

T = TypeVar("T")


def has_form(x: Any) -> bool:
    """Whether ``x`` has a ``jit_form`` method (a motion): programs take what it returns."""
    return hasattr(type(x), "jit_form")


def jit_forms(tree: T) -> T:
    """``tree`` with every object that has a ``jit_form`` method (a motion) replaced by ``x.jit_form()``."""
    return jax.tree.map(lambda x: x.jit_form() if has_form(x) else x, tree, is_leaf=has_form)


def flat_once(x: Any) -> bool:
    """Whether ``x`` is flattened once and remembered (:func:`part`): a motion (as its ``jit_form``) or another
    equinox module. Both are immutable, and a search calls its programs hundreds of times with the same ones."""
    return has_form(x) or isinstance(x, eqx.Module)


class Part(NamedTuple):
    """One leaf of a call's arguments flattened with :func:`flat_once` as leaves: its own leaves (a motion's form's,
    a module's; itself for a plain leaf), the treedef that rebuilds it (None: a plain leaf), which leaves are
    arrays, the others (static: part of the program's key), the arrays' (shape, dtype), and a token of all that
    (equal tokens, equal keys: a dict lookup hashes it, not the part)."""

    leaves: list
    treedef: Any
    is_array: tuple
    static: tuple
    avals: tuple
    arrays: list
    traced: bool
    token: Any


_tokens: dict = {}
_token_numbers = itertools.count()  # never reused: a program found by a number is that signature's
_tokens_lock = threading.Lock()  # the chunks of a batch call programs from a thread each
_MAX_TOKENS = 4096  # signatures remembered; past it they are numbered afresh (a program looked up again, not wrong)
_part_memo: dict[int, tuple[Any, Part]] = {}


def _token(sig: tuple) -> int:
    """A number standing for ``sig`` (hashed once, not at every call): the same for equal signatures while it is
    remembered, and never for another."""
    try:
        hash(sig)
    except TypeError:  # an unhashable static value: keyed by its text (a millisecond, but once per object)
        sig = ("text", repr(sig))
    with _tokens_lock:
        if len(_tokens) >= _MAX_TOKENS:
            _tokens.clear()
        number = _tokens.get(sig)
        if number is None:
            number = _tokens[sig] = next(_token_numbers)
        return number


def _flat_part(leaves: list, treedef: Any) -> Part:
    is_array = tuple(eqx.is_array(x) for x in leaves)
    arrays = [x for x, a in zip(leaves, is_array, strict=True) if a]
    static = tuple(x for x, a in zip(leaves, is_array, strict=True) if not a)
    avals = tuple((x.shape, x.dtype.str) for x in arrays)
    traced = any(isinstance(x, Tracer) for x in arrays)
    return Part(leaves, treedef, is_array, static, avals, arrays, traced, _token((treedef, is_array, static, avals)))


def part(x: Any) -> Part:
    """:class:`Part` of ``x``: a motion's (as its form) or a module's (a motion in it as its form: its
    :func:`jit_forms`) once per object; a plain leaf's at each call (an array: its shape and dtype; else its value)."""
    if not flat_once(x):
        if eqx.is_array(x):
            sig = (x.shape, x.dtype.str)
            return Part([x], None, (True,), (), (sig,), [x], isinstance(x, Tracer), sig)
        try:
            token = ("static", x, type(x))
            hash(token)
        except TypeError:
            token = ("static", repr(x))
        return Part([x], None, (False,), (x,), (), [], False, token)
    hit = _part_memo.get(id(x))
    if hit is None or hit[0] is not x:  # the memo holds x: its id is not reused while it is here
        if len(_part_memo) > 64:
            _part_memo.clear()
        hit = _part_memo[id(x)] = (x, _flat_part(*jax.tree.flatten(x.jit_form() if has_form(x) else jit_forms(x))))
    return hit[1]


def unflatten_parts(treedef: Any, forms: tuple, leaves: list) -> Any:
    """The arguments :func:`camdyn._core.jit.cached_jit` flattened into :class:`Part` s (``forms``: each part's
    treedef and number of leaves, None for a plain leaf), each object that has a ``jit_form`` as its form."""
    if not forms:
        return jax.tree.unflatten(treedef, leaves)
    outer, i = [], 0
    for form in forms:
        if form is None:
            outer.append(leaves[i])
            i += 1
        else:
            inner_def, count = form
            outer.append(jax.tree.unflatten(inner_def, leaves[i : i + count]))
            i += count
    return jax.tree.unflatten(treedef, outer)
