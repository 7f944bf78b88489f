"""Traced-program cache: a fresh ``camdyn`` process skips JAX tracing and compiling of the programs it ran before.

JAX's persistent compilation cache skips XLA compilation but not Python tracing and lowering, which for a
diffrax solve takes longer (about 1 s) than the solve itself. :func:`cached_jit` wraps a function like
``equinox.filter_jit``; once :func:`enable` names a directory, it stores each program it compiles, keyed by the
function, the static part of its arguments (everything that is not an array: an equinox module's static fields,
Python numbers), the shapes and dtypes of the arrays, camdyn's own source, the versions of the JAX stack and the
machine (:func:`_fingerprint`). A later process loads the program instead of tracing it. Without :func:`enable`
(the library) it is ``equinox.filter_jit`` and nothing is written; the tests enable it in a session folder.

A program is stored as its compiled executable (``jax.experimental.serialize_executable``): loading one is a read
and a deserialization, about 5 ms. A ``jax.export`` program, the portable form, must be lowered and looked up in
JAX's compilation cache on every load, and on a CPU every such call first loads ``scipy.linalg`` (jaxlib takes its
LAPACK kernels from it: about 0.25 s a process). That form is kept for the programs that call out of XLA
(LAPACK, whose kernels JAX registers only while lowering). A program sharded over several devices is not stored.
The files are pickles the user's own processes wrote: like JAX's own cache, the directory is trusted. They are kept
in a folder per :func:`_fingerprint` (a camdyn release, a JAX stack, a machine): the first program a process stores
removes the folders no process has used for :data:`STALE_DAYS` days (an install upgraded long ago), so the cache
holds what the installs in use need, not every version's programs.

Either way an argument with a ``jit_form`` method (a motion) is replaced by what it returns (:func:`jit_forms`):
a form whose static structure does not depend on the case, so a case never seen before reuses the programs of
the others.

:func:`stored` keeps a deterministic result of those programs that takes longer to compute than to read (a path's
synthesis: its programs alone take 0.3 s to load), keyed like the programs.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import math
import os
import pickle
import platform
import re
import shutil
import sys
import threading
import time
from collections.abc import Callable
from importlib import metadata
from pathlib import Path
from typing import Any, TypeVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax import export
from jax.core import Tracer
from jax.experimental import serialize_executable

from .jitargs import flat_once, jit_forms, part, unflatten_parts

try:
    import fcntl
except ImportError:  # not POSIX: processes that need one program at once each compile it
    fcntl = None

T = TypeVar("T")
_DIR: Path | None = None
SUFFIX = "jaxprogram"  # the stored programs' file names end so
STALE_DAYS = 14  # a fingerprint's folder no process has used for this long is removed
_USED = "used"  # the file in a fingerprint's folder whose time says when a process last used it


def enable(directory: str | Path) -> None:
    """Cache traced programs under ``directory`` (created if needed; silently off if it cannot be)."""
    global _DIR
    try:
        Path(directory).mkdir(parents=True, exist_ok=True)
    except OSError:
        return
    _DIR = Path(directory)


@functools.cache
def _fingerprint() -> str:
    """camdyn's source, the JAX stack's versions and the machine a compiled program runs on (the backend's device,
    the CPU's instruction set, ``XLA_FLAGS``): a change to any invalidates every program."""
    h = hashlib.sha256()
    for path in sorted(Path(__file__).parents[1].rglob("*.py")):
        h.update(path.read_bytes())
    for dist in ("jax", "jaxlib", "equinox", "diffrax", "optimistix", "lineax"):
        try:  # a loaded package's own __version__ is at hand; its metadata takes milliseconds to find
            known = getattr(sys.modules.get(dist), "__version__", None)
            h.update(f"{dist}={known or metadata.version(dist)};".encode())
        except metadata.PackageNotFoundError:
            pass
    x64 = jax.config.jax_enable_x64  # pyright: ignore[reportAttributeAccessIssue] - a flag jax adds at run time
    h.update(f"{jax.default_backend()};{jax.devices()[0].device_kind};x64={x64};".encode())
    h.update(f"{platform.machine()};{_cpu_flags()};{os.environ.get('XLA_FLAGS', '')}".encode())
    return h.hexdigest()


def _cpu_flags() -> str:
    """The CPU's feature flags where the system says them (Linux): XLA compiles for the host's instruction set."""
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as f:
            return next((line for line in f if line.startswith(("flags", "Features"))), "")
    except OSError:
        return platform.processor()


@functools.cache
def _programs(root: Path) -> Path:
    """This fingerprint's folder under ``root``, marked as used now (once a process)."""
    folder = root / _fingerprint()[:16]
    try:
        folder.mkdir(exist_ok=True)
        (folder / _USED).touch()
    except OSError:
        pass
    return folder


@functools.cache
def _prune(root: Path) -> None:
    """Remove the folders under ``root`` of other fingerprints unused for :data:`STALE_DAYS` days, and the programs
    stored before they had folders (once a process, when it stores its first program: a slow moment anyway)."""
    keep, cutoff = _programs(root), time.time() - STALE_DAYS * 86400.0
    for entry in root.iterdir():
        try:
            if entry.is_dir() and entry != keep and (entry / _USED).stat().st_mtime < cutoff:
                shutil.rmtree(entry, ignore_errors=True)
            elif entry.is_file() and entry.suffix == f".{SUFFIX}":
                entry.unlink()
        except OSError:  # another process removed it first, or no stamp: a folder being made
            pass


_OUTSIDE = threading.Lock()
_outside: list = [0, None]  # compilations under way outside JAX's cache, and the threshold they replaced


def keep_in_jax_cache(directory: str | Path, min_compile_secs: float) -> None:
    """JAX's persistent compilation cache in ``directory``, keeping compiles of ``min_compile_secs`` or longer. While
    a thread compiles a program to store (:func:`_outside_jax_cache`) the threshold takes effect when the last such
    compile is done: set at once it let that program into JAX's cache, and a process that compiled it again (a second
    test worker) stored the copy JAX's cache deserialized, which runs without some of its functions."""
    jax.config.update("jax_compilation_cache_dir", str(directory))
    with _OUTSIDE:
        if _outside[0]:
            _outside[1] = min_compile_secs
        else:
            jax.config.update("jax_persistent_cache_min_compile_time_secs", min_compile_secs)


@contextlib.contextmanager
def _outside_jax_cache():
    """JAX's persistent cache keeps nothing compiled inside (its threshold infinite), while any thread compiles
    inside: threads may compile at once, and the threshold comes back when the last one is done."""
    with _OUTSIDE:
        if not _outside[0]:
            _outside[1] = jax.config.jax_persistent_cache_min_compile_time_secs  # pyright: ignore[reportAttributeAccessIssue]
            jax.config.update("jax_persistent_cache_min_compile_time_secs", math.inf)
        _outside[0] += 1
    try:
        yield
    finally:
        with _OUTSIDE:
            _outside[0] -= 1
            if not _outside[0]:
                jax.config.update("jax_persistent_cache_min_compile_time_secs", _outside[1])


def _compile(flat: Callable, avals: tuple, name: str, options: dict) -> tuple[Callable, bytes]:
    """``flat`` traced and compiled for arrays of ``avals`` ((shape, dtype) each): the program, and what a later
    process loads it from (:func:`_load`). Raises where it cannot be stored (a host callback, say).

    The executable must come from XLA, not from JAX's compilation cache: one that cache deserialized serializes
    without some of its functions ("Function ... not found" when the stored copy runs). So the program's module
    is named for its file (``name``: JAX's cache keys start with it) and JAX's cache does not keep it."""
    specs = [jax.ShapeDtypeStruct(s, d) for s, d in avals]
    flat.__name__ = flat.__qualname__ = f"camdyn_{name}"
    with _outside_jax_cache():
        compiled = _jit_compile(flat, options, *specs)
    if len({d for s in jax.tree.leaves(compiled.input_shardings) for d in s.device_set}) > 1:
        # a kernel sharded over several devices: neither a loaded executable nor a loaded jax.export program
        # places one-device inputs on its mesh; the caller runs the plain jit
        raise ValueError("a program over several devices is not stored")
    if "custom_call_target=" not in (compiled.as_text() or ""):
        return compiled, pickle.dumps(("executable", *serialize_executable.serialize(compiled)))
    # a call out of XLA: LAPACK, whose kernels JAX registers as it lowers the program, or a host callback, which
    # jax.export refuses (and the caller then runs the plain jit)
    exported = export.export(jax.jit(flat))(*specs)
    return exported.call, pickle.dumps(("exported", exported.serialize()))


def _load(file: Path) -> Callable | None:
    """The program :func:`_compile` stored in ``file``; None where there is none to load."""
    try:
        kind, *data = pickle.loads(file.read_bytes())
        if kind == "executable":
            # on the default device, as jax.jit compiled it (by default a loaded executable spans every device)
            return serialize_executable.deserialize_and_load(*data, execution_devices=jax.devices()[:1])
        return export.deserialize(bytearray(data[0])).call
    except Exception:  # missing, truncated, or from another JAX or machine: trace afresh
        return None


def _save(file: Path, blob: bytes) -> None:
    tmp = file.with_suffix(f".{os.getpid()}.tmp")
    try:
        tmp.write_bytes(blob)
        os.replace(tmp, file)  # atomic: parallel processes never read half a file
    except OSError:
        tmp.unlink(missing_ok=True)


_WAIT_S = 120.0  # the longest a process waits for another's compile of a program before compiling it itself


@contextlib.contextmanager
def _compiling(file: Path):
    """Held while this process compiles the program of ``file``: another process that needs the same program (a
    second test worker, two ``camdyn`` commands at once) waits for it and loads it, instead of compiling it a second
    time (each 1-10 s). An advisory lock on a file beside it; after :data:`_WAIT_S` (a lock never released) or where
    files cannot be locked, each compiles its own."""
    try:
        fd = os.open(file.with_suffix(".lock"), os.O_RDWR | os.O_CREAT, 0o644) if fcntl else None
    except OSError:
        fd = None
    if fd is None or fcntl is None:
        yield
        return
    try:
        deadline = time.monotonic() + _WAIT_S
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except OSError:
                if time.monotonic() > deadline:
                    break
                time.sleep(0.02)
        yield
    finally:
        os.close(fd)  # and with it the lock


def stored(name: str, key: str, compute: Callable[[], T]) -> T:
    """``compute()``, or what an earlier process stored for the same ``key`` (the text of every input) under the
    same camdyn source, JAX stack and machine (:func:`_fingerprint`: the same programs, so the same numbers);
    nothing stored without :func:`enable`, nor where ``compute`` raises."""
    if (root := _DIR) is None:
        return compute()
    file = _programs(root) / f"{name}-{hashlib.sha256(key.encode()).hexdigest()[:32]}.result"
    try:
        return pickle.loads(file.read_bytes())
    except Exception:  # missing, truncated, or of classes that changed: compute afresh
        pass
    value = compute()
    _save(file, pickle.dumps(value))
    return value


def padded_length(n: int, least: int, factor: int = 4) -> int:
    """The bucket ``n`` rows are padded to: ``least``, or ``least * factor**k``, the first that holds them (a
    program compiled for the bucket serves every length in it)."""
    size = least
    while size < n:
        size *= factor
    return size


def on_buckets(program: Callable[[Any], Any], x: Any, *, least: int, factor: int, largest: int) -> Any:
    """``program(x)`` of a program that is elementwise in ``x`` (its output's last axis), compiled for a few lengths
    only: a 1-D array of numbers is padded (with its last value) to ``least * factor**k`` (at most ``largest``, itself
    such a bucket) and a longer one runs in pieces of ``largest``, so one compiled program per bucket serves every
    length, and the output comes back as numpy cut to ``x``'s length (a traced output stays traced). Inside a
    trace, or for other shapes, ``program(x)`` as it is. The values are the program's on each element: to the bit
    where it computes each alone (the motion's evaluation), to round-off where it batches them (the least steady
    force's ``lax.map``)."""
    if isinstance(x, Tracer) or np.ndim(x) != 1:
        return program(x)
    t = np.asarray(x, dtype=float)
    n = t.size
    if n <= largest:
        size = padded_length(n, least, factor)
        out = program(np.pad(t, (0, size - n), mode="edge") if n else np.zeros(size))
        return out[..., :n] if isinstance(out, Tracer) else np.asarray(out)[..., :n]
    pieces = [
        on_buckets(program, t[i : i + largest], least=least, factor=factor, largest=largest)
        for i in range(0, n, largest)
    ]
    traced = any(isinstance(piece, Tracer) for piece in pieces)
    return jnp.concatenate(pieces, axis=-1) if traced else np.concatenate(pieces, axis=-1)


# 8, 64, 512, 4096 angles: four programs per motion form, a revolution of 3600 and its breaks (the geometry's chunk)
# in one
_ANGLE_BUCKETS = {"least": 8, "factor": 8, "largest": 4096}


def on_angle_buckets(program: Callable[[Any], Any], theta: Any) -> Any:
    """:func:`on_buckets` for a program elementwise in the angles ``theta`` (rad): one of four programs serves every
    number of angles."""
    return on_buckets(program, theta, **_ANGLE_BUCKETS)


def device_array(x: Any) -> jax.Array:
    """``x`` as a float64 JAX array, placed without a program: ``jnp.asarray`` of a host value compiles one per
    shape (JAX 0.10), some 10 ms each in every process."""
    return jax.device_put(np.asarray(x, dtype=float))


# XLA compiles camdyn's programs with its CPU loop emitters, not its newer fusion emitters: about 40 % less compile
# (the oscillating case's shooting 2.2 -> 1.2 s of XLA, its sensitivity shooting 6.3 -> 3.9 s, the jump map's gap
# stepping 1.06 -> 0.63 s of CPU), the same numbers to rounding. The price, where a program runs long: the map's gap
# stepping about 15 % slower over 10^4 designs; a warm `check`, `optimize` or `tolerance` within the machine's noise
# (docs/benchmarks.md, session 36). A CPU option (the jump map compiled with it on an H100 in sessions 17 and 22);
# dropped where an XLA no longer knows it.
XLA_OPTIONS: tuple[tuple[str, Any], ...] = (("xla_cpu_use_fusion_emitters", False),)
_UNKNOWN_OPTION = re.compile(r"No such compile option: '([^']+)'")  # XLA's error for an option it does not know
_NESTED = "can only be passed to top-level"  # JAX's error for options on a program called inside another's trace
# the options this process's XLA refused (JAX 0.11's no longer knows xla_cpu_use_fusion_emitters): not passed again,
# so that each program is lowered once, not once with them and once without
_REFUSED: set[str] = set()


def _known(options: dict) -> dict:
    """``options`` without those this XLA refused."""
    return {k: v for k, v in options.items() if k not in _REFUSED}


def _refused(err: Exception, passed: dict) -> bool:
    """Whether ``err`` is XLA refusing one of the options ``passed`` (one a later XLA dropped); that option is then
    left out of every later compile of this process, whichever thread compiles it."""
    found = _UNKNOWN_OPTION.search(str(err))
    if found is None or found.group(1) not in passed:
        return False
    _REFUSED.add(found.group(1))
    return True


def _jit_compile(flat: Callable, options: dict, *specs: Any) -> Any:
    """``jax.jit(flat)`` lowered for ``specs`` and compiled with the XLA ``options`` this XLA knows."""
    known = _known(options)
    try:
        return jax.jit(flat, compiler_options=known or None).lower(*specs).compile()
    except Exception as err:
        if not _refused(err, known):
            raise
        return _jit_compile(flat, options, *specs)


def jit_with(fn: Callable, options: dict | None = None) -> Callable:
    """``equinox.filter_jit(fn)``, compiled with the XLA compiler ``options`` (equinox takes none; default
    :data:`XLA_OPTIONS`)."""
    options = dict(XLA_OPTIONS) if options is None else options
    plain = eqx.filter_jit(fn)
    if not options:
        return plain
    traced: dict = {}

    def call(*args: Any, **kwargs: Any) -> Any:
        dynamic, static = eqx.partition((args, kwargs), eqx.is_array)
        leaves, treedef = jax.tree.flatten(dynamic)
        try:
            key = (treedef, tuple(jax.tree.leaves(static)))
            hash(key)
        except TypeError:
            key = repr((treedef, static))
        if key not in traced:

            def flat(*xs: Any) -> Any:
                a, kw = eqx.combine(jax.tree.unflatten(treedef, xs), static)
                return fn(*a, **kw)

            traced[key] = jax.jit(flat, compiler_options=_known(options) or None)
        try:
            return traced[key](*leaves)
        except Exception as err:
            if _NESTED in str(err):  # called inside another program's trace: XLA compiles that one, with its options
                return plain(*args, **kwargs)
            if not _refused(err, options):
                raise
            traced[key] = jax.jit(traced[key].__wrapped__, compiler_options=_known(options) or None)
            return call(*args, **kwargs)

    return call


def _program_name(fn: Callable, options: dict, treedef, forms, is_array, static, avals) -> str:
    """The name of :func:`cached_jit`'s program for ``fn`` and these arguments (its file's, after ``fn``'s)."""
    # the static part as the treedefs (structure, static fields) and the static leaves say it: an equinox
    # module's own repr pretty-prints, a millisecond or more a program
    text = repr((fn.__module__, fn.__qualname__, _fingerprint(), treedef, forms, is_array, static, avals))
    text += repr(sorted(options.items())) if options else ""  # no options: the keys of before
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def _program_file(root: Path, fn: Callable, name: str) -> Path:
    """The file of :func:`cached_jit`'s program ``name`` for ``fn`` under ``root``."""
    return _programs(root) / f"{fn.__name__}-{name}.{SUFFIX}"


def _load_or_compile(
    root: Path, name: str, fn: Callable, jitted: Callable, options: dict, treedef, forms, is_array, static, avals
) -> Callable:
    """:func:`cached_jit`'s program ``name`` for ``fn`` and these arguments: loaded from ``root``, or traced,
    compiled and stored there (the plain ``jitted`` where it cannot be stored)."""
    file = _program_file(root, fn, name)
    program = _load(file)
    if program is not None:
        return program

    def flat(*xs: Any) -> Any:
        it, fixed = iter(xs), iter(static)
        a, kw = unflatten_parts(treedef, forms, [next(it) if b else next(fixed) for b in is_array])
        return fn(*a, **kw)

    with _compiling(file):
        program = _load(file)  # stored by another process while this one waited
        if program is not None:
            return program
        try:
            program, blob = _compile(flat, avals, name, options)
        except Exception:  # e.g. a host callback, which cannot be serialized: plain jit
            return jitted
        _prune(root)
        _save(file, blob)
    return program


def in_background(prepare: Callable[[], object], name: str) -> threading.Thread:
    """``prepare()`` (a :func:`cached_jit` program's ``prepare``: its load or compile, which on a CPU releases the
    interpreter) on a thread named ``name`` while the caller computes what comes before the program's first
    call; that call waits for it. A failure there is ignored: the first call loads or compiles as ever."""

    def run() -> None:
        try:
            prepare()
        except Exception:  # noqa: BLE001, S110  (only a head start)
            pass

    # not a daemon: a caller that ends first (an error) waits for it at exit rather than tear XLA down under it
    thread = threading.Thread(target=run, name=name)
    thread.start()
    return thread


def cached_jit(fn: Callable[..., T], compiler_options: tuple[tuple[str, Any], ...] = XLA_OPTIONS) -> Callable[..., T]:
    """``equinox.filter_jit(fn)`` on the arguments' :func:`jit_forms` (compiled once per follower kind and bucket, not
    once per case), whose traced programs persist across processes once :func:`enable` is called.
    ``compiler_options``: XLA options as (name, value) pairs, for every compile of ``fn``, cached or not (and
    part of the key); dropped where this XLA does not know them."""
    options = dict(compiler_options)
    jitted = jit_with(fn, options)
    programs: dict = {}
    # one load or compile at a time: a caller that arrives while another thread loads the program (a head start,
    # :func:`in_background`) waits for it instead of loading it a second time
    loading = threading.RLock()

    def program_for(tree: tuple, load: bool = True) -> tuple[Callable, list] | None:
        """The program for these (args, kwargs), compiled or loaded, and their array leaves; None where the plain
        ``jitted`` runs them (inside another trace, or with the cache not enabled), and with ``load`` False where
        the program is stored (it is not loaded). A motion is keyed and traced as its :func:`jit_forms`."""
        if (root := _DIR) is None:
            return None
        outer, treedef = jax.tree.flatten(tree, is_leaf=flat_once)
        parts = [part(x) for x in outer]
        if any(p.traced for p in parts):  # inside jit/vmap/grad: an exported program has
            return None  # no batching or differentiation rules; the outer trace is cached anyway
        key = (treedef, tuple(p.token for p in parts))
        program = programs.get(key)
        if program is None:
            forms = tuple(None if p.treedef is None else (p.treedef, len(p.leaves)) for p in parts)
            is_array = [a for p in parts for a in p.is_array]
            static = [x for p in parts for x in p.static]
            avals = tuple(v for p in parts for v in p.avals)
            with loading:
                program = programs.get(key)
                if program is None:
                    name = _program_name(fn, options, treedef, forms, is_array, static, avals)
                    if not load and _program_file(root, fn, name).exists():
                        return None
                    program = _load_or_compile(root, name, fn, jitted, options, treedef, forms, is_array, static, avals)
                    programs[key] = program
        arrays = [x for p in parts for x in p.arrays]
        return program, arrays

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> Any:
        found = program_for((args, kwargs))
        if found is None or found[0] is jitted:
            return jitted(*jit_forms(args), **jit_forms(kwargs))
        program, arrays = found
        return program(*arrays)

    def prepare(*args: Any, **kwargs: Any) -> None:
        """Compile (or load) the program for arguments like these without running it (nothing where the cache is
        not enabled)."""
        program_for((args, kwargs))

    def store(*args: Any, **kwargs: Any) -> None:
        """Compile and store the program for arguments like these where none is stored, without loading a stored
        one (nothing where the cache is not enabled): for a later process's first call."""
        program_for((args, kwargs), load=False)

    call.prepare = prepare  # pyright: ignore[reportAttributeAccessIssue]
    call.store = store  # pyright: ignore[reportAttributeAccessIssue]
    return call
