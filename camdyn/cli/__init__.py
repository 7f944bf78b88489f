"""The ``camdyn`` command line: parse, call the library, format. No physics here.

Exit codes: 0 every check passes (or the work is written), 1 a check fails, 2 invalid input or a numerical
failure (one line on stderr naming the file, the key or angle, and what is wrong; ``--debug`` shows the
traceback). The parser is built without importing JAX (``camdyn --help`` and ``--version`` answer at once), a
case file is validated before any model is built (a typo is reported before JAX loads), and each command's
module is imported only when that command runs.
"""

from __future__ import annotations

import argparse
import atexit
import os
import sys
import traceback
import warnings
from importlib import import_module
from pathlib import Path
from typing import NoReturn

from .._core.units import DEFAULT_PROFILE_TOLERANCE_MM, MAX_SPEED_RPM
from ._options import check_options, grid, positive_rpm

# The commands whose work is one batch an accelerator speeds up (a jump map, a Monte Carlo study): they run on every
# device JAX finds, but for a valvetrain, whose maps and studies run its two-mass model one point at a time. Every
# other command is one small solve after another, where a GPU's start (CUDA and its memory, 1.3 s on an H100 machine
# before the first program) and its kernel launches cost more than they save: those run on the CPU. JAX_PLATFORMS,
# where the user sets it, decides for every command.
BATCHED_COMMANDS = frozenset({"sweep", "tolerance"})


def _batched(args) -> bool:
    """Whether this run's work is a batch for every device (:data:`BATCHED_COMMANDS`; its case validated)."""
    return args.command in BATCHED_COMMANDS and getattr(getattr(args, "spec", None), "valvetrain", None) is None


def _version() -> str:
    # the installed distributions' metadata loads for --version only (60 ms of every other command's first line)
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("camdyn")
    except PackageNotFoundError:  # a source tree on sys.path
        return "0+unknown"


class _VersionAction(argparse.Action):
    """``--version``: the installed version, looked up only when asked (finding it takes milliseconds)."""

    def __init__(self, option_strings: list[str], dest: str = argparse.SUPPRESS, **kwargs) -> None:
        kwargs.setdefault("help", "show program's version number and exit")
        super().__init__(option_strings, dest=dest, default=argparse.SUPPRESS, nargs=0, **kwargs)

    def __call__(self, parser: argparse.ArgumentParser, *_: object) -> NoReturn:
        print(f"camdyn {_version()}")
        parser.exit()


class _Parser(argparse.ArgumentParser):
    """argparse with camdyn's error format: one line on stderr, exit code 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"camdyn: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    common = _Parser(add_help=False)  # a parent: its arguments only (the subparsers' type is _Parser)
    common.add_argument(
        "--debug", action="store_true", default=argparse.SUPPRESS, help="show the traceback of an error"
    )
    common.add_argument("--quiet", action="store_true", help="no progress on stderr (errors are still reported)")
    parser = _Parser(
        prog="camdyn",
        description="Cam mechanism design and follower dynamics: prove the follower never leaves the cam.",
    )
    parser.add_argument("--version", action=_VersionAction)
    parser.add_argument("--debug", action="store_true", default=False, help="show the traceback of an error")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name: str, help: str) -> argparse.ArgumentParser:
        return sub.add_parser(name, help=help, parents=[common])

    p = command("check", "stability margins and a verdict (exit 0 pass, 1 fail, 2 error)")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--speed", type=positive_rpm, metavar="RPM", help="cam speed, rpm (default: the case's)")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    p.add_argument(
        "--arrays",
        action="store_true",
        help=(
            "with --json: also the synthesis' coordinate arrays of a path case "
            "(pitch curve, contour, path, traced path)"
        ),
    )
    p.add_argument(
        "--report", metavar="DIR", help="also write the design-review report (DIR/<case>.pdf and a PNG per page)"
    )

    p = command("report", "design-review report per case: DIR/<case>.pdf and DIR/<case>-<n>-<page>.png")
    p.add_argument("cases", nargs="+", metavar="CASE", help="case files (TOML)")
    p.add_argument(
        "-o",
        "--output",
        default="reports",
        metavar="DIR",
        help=(
            "output folder (default: reports); the report files camdyn wrote there are rewritten, a file of another "
            "under their names is refused"
        ),
    )
    p.add_argument("--speed", type=positive_rpm, metavar="RPM", help="cam speed, rpm (default: each case's)")

    p = command("table", "CSV per angle: follower motion, contact force (kinematic and dynamic), cam geometry")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--step", type=float, default=1.0, metavar="DEG", help="angle step, deg (default 1)")
    p.add_argument(
        "--speed", type=positive_rpm, metavar="RPM", help="cam speed for the forces, rpm (default: the case's)"
    )
    p.add_argument(
        "-o", "--output", metavar="FILE", help="write to FILE instead of standard output (-: standard output)"
    )
    p.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    p.add_argument(
        "--ecam",
        type=int,
        metavar="N",
        help=(
            "a servo e-cam table instead: N evenly spaced master angles, "
            "master_deg,position,velocity,acceleration (per master degree)"
        ),
    )

    p = command(
        "profile",
        "the cam for manufacturing by the file suffix: outline (DXF, CSV, SVG), cutter path (.nc), grinder table "
        "(.csv), solid (STEP, STL)",
    )
    p.add_argument("case", help="case file (TOML)")
    p.add_argument(
        "-o", "--output", required=True, metavar="FILE", help="cam.dxf, cam.csv, cam.svg, cam.nc, cam.step or cam.stl"
    )
    p.add_argument(
        "--tolerance",
        type=float,
        default=DEFAULT_PROFILE_TOLERANCE_MM,
        metavar="MM",
        help=(
            f"chord tolerance, mm (default {DEFAULT_PROFILE_TOLERANCE_MM:g}, at least 1e-6; "
            "a cutter path at least 0.001)"
        ),
    )
    p.add_argument(
        "--units",
        choices=("mm", "in"),
        default="mm",
        help="the file's length unit (default mm); the options stay in mm",
    )
    p.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    g = p.add_argument_group("CNC cutter path (.nc, ISO G-code)")
    g.add_argument(
        "--cutter-radius",
        type=float,
        metavar="MM",
        help="the end mill's radius, mm: the path is its centre, offset by camdyn",
    )
    g.add_argument("--feed", type=float, metavar="MM_PER_MIN", help="feed rate, mm/min (default 300)")
    sense = g.add_mutually_exclusive_group()
    sense.add_argument("--climb", action="store_true", help="climb milling, clockwise round the cam (the default)")
    sense.add_argument(
        "--conventional", action="store_true", help="conventional milling, counterclockwise round the cam"
    )
    g.add_argument("--arcs", action="store_true", help="G02/G03 arcs fitted within the tolerance instead of lines")
    g = p.add_argument_group("cam grinder table (.csv)")
    g.add_argument(
        "--grinder-wheel-radius",
        type=float,
        metavar="MM",
        help="the wheel's radius, mm: theta_deg,wheel_center_mm per cam angle",
    )
    g.add_argument(
        "--follower-lift",
        action="store_true",
        help="the follower's lift per cam angle instead: theta_deg,lift_mm (lift_deg oscillating)",
    )
    g.add_argument("--step", type=float, metavar="DEG", help="angle step of a grinder table, deg (default 0.5)")
    g = p.add_argument_group("solid (.step, .stl; pip install 'camdyn[cad]')")
    g.add_argument("--thickness", type=float, metavar="MM", help="the cam plate's thickness, mm")
    g.add_argument("--bore", type=float, metavar="MM", help="the shaft bore's diameter, mm")
    g.add_argument(
        "--keyway",
        metavar="WIDTHxDEPTH",
        help="a keyway in the bore, mm: its width and its depth beyond the bore, on the cam frame's +y axis",
    )

    p = command("size", "return spring (rate, preload) with the least peak force that holds up to margin x speed")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--max-speed", type=float, metavar="RPM", help="maximum cam speed, rpm (default: the case's speed)")
    p.add_argument(
        "--margin",
        type=float,
        metavar="X",
        help="hold up to X times the maximum speed (default: the case's speed_margin)",
    )
    p.add_argument(
        "--min-rate",
        type=float,
        metavar="K",
        help="least spring rate, N/mm (N*m/rad oscillating; default 0; a valvetrain's: at the valve, default its own)",
    )
    p.add_argument(
        "--buildable",
        action="store_true",
        help=(
            "the least peak force over springs that can be built within [spring] (surge clear of the cam's strong "
            "harmonics), with the part's own mass; passes check as written"
        ),
    )
    p.add_argument(
        "--verbose", action="store_true", help="also say how ties between springs and the damping are handled"
    )
    p.add_argument("--json", action="store_true", help="print one JSON document")

    p = command("sweep", "jump map over speeds x spring rates: DIR/<case>-sweep.csv and DIR/<case>-sweep.png")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument(
        "--speeds",
        required=True,
        type=grid(MAX_SPEED_RPM, "rpm"),
        metavar="A:B:N",
        help="cam speeds, rpm: N values from A to B",
    )
    p.add_argument(
        "--spring-rates",
        type=grid(),
        metavar="A:B:N",
        help=(
            "spring rates, N/mm (N*m/rad oscillating): N values from A to B (default: the case's); "
            "the preload stays the case's"
        ),
    )
    p.add_argument(
        "--backlash",
        type=grid(),
        metavar="A:B:N",
        help="a groove cam: backlashes, mm: N values from A to B (default: the case's); the map is of the impacts",
    )
    p.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: the current one)")
    p.add_argument("--force", action="store_true", help="overwrite the files if they exist")
    _distributed_options(p)

    p = command(
        "tolerance",
        "Monte Carlo tolerance study of [tolerances]: DIR/<case>-tolerance.csv, .png and the worst samples as case "
        "files",
    )
    p.add_argument("case", help="case file (TOML) with a [tolerances] table")
    p.add_argument(
        "--samples", type=int, metavar="N", help="built cams to draw (default 10000; a valvetrain: 50, two-mass model)"
    )
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: the current one)")
    p.add_argument("--force", action="store_true", help="overwrite the files if they exist")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    _distributed_options(p)

    p = command(
        "synthesize", "choose a CCM's dimensions for a path (differential evolution) and write a complete case file"
    )
    p.add_argument(
        "case",
        metavar="PATH.toml",
        help="path file: [path], [dynamics], optional name, description, [limits], [synthesis]",
    )
    p.add_argument("-o", "--output", required=True, metavar="CASE.toml", help="the case file to write")
    p.add_argument("--force", action="store_true", help="overwrite CASE.toml if it exists")
    p.add_argument("--seed", type=int, metavar="N", help="optimizer seed (default: [synthesis] seed, else 0)")
    p.add_argument(
        "--maxiter", type=int, metavar="N", help="most optimizer generations (default: [synthesis] maxiter, else 200)"
    )
    p.add_argument(
        "--json",
        action="store_true",
        help="print one JSON document (the mechanism, the summary and the four-bar comparison)",
    )

    p = command(
        "optimize",
        "reshape every rise and return (B-splines) for the fastest hold, the least vibration or the least spring force",
    )
    p.add_argument("case", help="case file (TOML) with [motion] segments")
    p.add_argument("-o", "--output", required=True, metavar="OUT.toml", help="the optimized case file to write")
    p.add_argument(
        "--objective",
        choices=("jump-speed", "vibration", "spring-force"),
        default="jump-speed",
        help="what to optimize (default: jump-speed)",
    )
    p.add_argument("--speed", type=positive_rpm, metavar="RPM", help="design speed, rpm (default: the case's)")
    p.add_argument(
        "--min-force",
        type=float,
        metavar="F",
        help="the least contact force to keep at every speed up to "
        "the claimed one, N (N*m for an arm; default: 5 %% of the static preload)",
    )
    p.add_argument(
        "--control-points", type=int, metavar="N", help="B-spline control points per rise and return (default: 16)"
    )
    p.add_argument(
        "--robust",
        action="store_true",
        help="claim the speed up to which P(separation) <= 1e-3 over the case's [tolerances]",
    )
    p.add_argument("--force", action="store_true", help="overwrite OUT.toml if it exists")
    p.add_argument("--json", action="store_true", help="print one JSON document (before, after, verification)")

    p = command(
        "spring",
        "the helical compression spring for the case's rate and preload: wire, coils, lengths, stresses, surge",
    )
    p.add_argument(
        "case",
        help="case file (TOML); an optional [spring] table gives the material, bore, installed length and end type",
    )
    p.add_argument("--json", action="store_true", help="print one JSON document")

    p = command("machine", "many cams on one shaft: each checked at its speed, shaft torque, flywheel, clearances")
    p.add_argument("case", metavar="MACHINE.toml", help="machine file: name, speed, [[cam]] case and phase, [drive]")
    p.add_argument(
        "-o",
        "--output",
        default=".",
        metavar="DIR",
        help="output folder for DIR/<machine>-machine.csv (default: the current one)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON document")
    p.add_argument(
        "--report",
        action="store_true",
        help="also write the machine report: DIR/<machine>-machine.pdf and a PNG per page",
    )
    p.add_argument("--force", action="store_true", help="overwrite the files if they exist")
    return parser


def _distributed_options(p: argparse.ArgumentParser) -> None:
    """JAX's distributed runtime (see camdyn/_core/distributed.py): the options of the batched commands."""
    p.add_argument(
        "--coordinator",
        metavar="HOST:PORT",
        help="several processes: the coordinator's address (or CAMDYN_COORDINATOR)",
    )
    p.add_argument("--num-processes", metavar="N", help="several processes: how many (or CAMDYN_NUM_PROCESSES)")
    p.add_argument(
        "--process-id",
        metavar="I",
        help="several processes: this one's index, 0 writes the outputs (or CAMDYN_PROCESS_ID)",
    )
    p.add_argument(
        "--distributed",
        action="store_true",
        help="start JAX's distributed runtime from what it detects (SLURM, Open MPI)",
    )


def _enable_caches() -> None:
    """Persist compiled XLA programs, traced camdyn programs and data fits between runs (the user's second ``check``
    skips most of JAX's tracing and compilation, and refits nothing). ``CAMDYN_NO_CACHE`` turns them off."""
    if os.environ.get("CAMDYN_NO_CACHE"):
        return
    root = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "camdyn"
    try:
        (root / "jax").mkdir(parents=True, exist_ok=True)
    except OSError:
        return
    from .._core import jit

    jit.keep_in_jax_cache(root / "jax", 0.1)
    jit.enable(root / "programs")  # and the stored data fits (camdyn._core.stored), beside the programs


def _validate(args) -> None:
    """Check the options, then read and validate the input files, before any model is built: a typo is reported
    before JAX loads, and an option's before the case schema loads (pydantic: 0.3 s on a slow machine)."""
    check_options(args)
    from .._core.errors import CamdynError
    from ..schema import load_case_spec, load_path_file, require_tolerances

    if args.command == "synthesize":
        args.spec = load_path_file(args.case)
    elif args.command == "machine":
        from ..schema.machine import load_machine  # a machine's schema loads only for ``machine``

        args.spec = load_machine(args.case)
    elif args.command == "report":
        args.specs = []
        for p in args.cases:
            try:
                args.specs.append(load_case_spec(p))
            except CamdynError as err:  # name the file among several
                raise type(err)(f"{p}: {err.where}" if err.where else str(p), err.message) from None
    else:
        spec = args.spec = load_case_spec(args.case)
        if args.command == "tolerance" or (args.command == "optimize" and args.robust):  # the file's question
            key = "--robust" if args.command == "optimize" else "tolerances"
            require_tolerances(spec.tolerances, kind=spec.kind, key=key)
    if args.command in _SPRING_HELD:
        _refuse_form_closed([args.spec], [""], args.command)


def _refuse_form_closed(specs, paths, command: str) -> None:
    """A command that studies a spring-held follower refuses a form-closed cam (one line)."""
    from .._core.errors import InputError

    for spec, path in zip(specs, paths, strict=True):
        if spec.follower is not None and spec.follower.form_closed:
            raise InputError(
                f"{path}: follower.closure" if path else "follower.closure",
                f"{_FORM_CLOSED_REFUSAL[command]}: a form-closed cam cannot jump and has no return spring "
                "(camdyn check, report, sweep, tolerance and size study a groove cam's crossover impacts)",
            )


# commands that study a spring-held follower: its spring, its jump speed, its design review
_SPRING_HELD = ("spring", "optimize")
_FORM_CLOSED_REFUSAL = {
    "spring": "spring designs the return spring that holds a follower on its cam",
    "optimize": "optimize reshapes the motion so that a spring-held follower holds to a faster jump speed",
}


def _end_process(code: list[int]) -> None:
    """A ``camdyn`` process's last exit handler: once the others (JAX's among them) have run, end the process
    without the interpreter's teardown of every module and JAX's runtime, which takes longer than a warm check's own
    work (about 0.4 s of CPU). Every file camdyn writes is closed by then; the standard streams are flushed here."""
    if not code:  # main did not return: let Python report what happened
        return
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a reader that has gone, a closed stream: nothing more to say
            pass
    os._exit(code[0])


def main(argv: list[str] | None = None) -> int:
    """The command line (``argv`` None: the process's own arguments, and the process ends fast after it) or a
    call from Python with ``argv``; the exit code."""
    code: list[int] = []
    if argv is None:  # registered before JAX loads and registers its own handlers, so it runs after them
        atexit.register(_end_process, code)
    code.append(_command(argv))
    return code[0]


def _command(argv: list[str] | None) -> int:
    if "numpy" not in sys.modules:  # before numpy loads: OpenBLAS reads it then (a caller's numpy keeps its own)
        # camdyn's numpy work is small matrices (a valvetrain's fast path: 37 x 37 propagators, 32 x 16 modes), where
        # BLAS threads only spin: a surge chain's `size` took 123 s of CPU for 77 s of wall on two
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exit_:  # --help, --version, or a usage error already reported in one line
        return int(exit_.code or 0)
    from .._core.errors import CamdynError

    source = getattr(args, "case", "") or ""
    try:
        _validate(args)
        if not _batched(args):
            os.environ.setdefault("JAX_PLATFORMS", "cpu")  # before JAX loads: it reads it then
        from .._core.backends import skip_accelerator_plugins
        from .._core.precision import enable_x64  # loads JAX: only once the input is known to be valid

        enable_x64()  # before any model module loads: camdyn's models compute in float64
        skip_accelerator_plugins()
        # before equinox loads: its runtime checks otherwise embed host callbacks, which keep JAX from caching the
        # compiled diffrax solves on disk (camdyn checks every solver result itself, so NaN-on-error loses nothing)
        os.environ.setdefault("EQX_ON_ERROR", "nan")
        # a case name's characters the plots' font lacks are drawn as boxes; matplotlib's warning of each (two lines
        # of its source per glyph) would be the only text on stderr of a --quiet run
        warnings.filterwarnings("ignore", message=r"Glyph \d+ .*missing from", category=UserWarning)
        run = import_module(f".{args.command}", __name__).run
        _enable_caches()
        return run(args)
    except CamdynError as err:
        if args.debug:
            traceback.print_exc()
        named = source and str(err.where).startswith(source)  # the error names the case file itself: once
        print(f"camdyn: {source + ': ' if source and not named else ''}{err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # the reader (``| head``) has gone: nothing more to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except Exception as err:  # a bug: still one line (exit 2), the traceback on request
        if args.debug:
            traceback.print_exc()
        print(
            f"camdyn: {source + ': ' if source else ''}internal error: {type(err).__name__}: {err} (run with --debug "
            "for the traceback)",
            file=sys.stderr,
        )
        return 2


if __name__ == "__main__":
    sys.exit(main())
