"""The options' own checks, run before JAX loads: argparse's types (a speed, an ``A:B:N`` grid) as the line is parsed,
and each command's rules (:func:`check_options`, from :func:`camdyn.cli._validate`): a bad value, an option that does
not apply, a file name of unknown format is one line at once, not after the seconds it takes to load the models. The
bounds are :mod:`camdyn._core.limits`', the ones the library checks its arguments with."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from .._core.errors import InputError
from .._core.limits import (
    check_chord_tolerance,
    check_ecam_points,
    check_min_force,
    check_samples,
    check_sizing,
    check_table_step,
)
from .._core.outputs import output_file
from .._core.units import MAX_SPEED_RPM


def positive_rpm(text: str) -> float:
    """An argparse type: a cam speed (rpm), positive and at most the schema's."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive number of rpm (got {text!r})") from None
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a positive number of rpm (got {text})")
    if value > MAX_SPEED_RPM:
        raise argparse.ArgumentTypeError(f"at most {MAX_SPEED_RPM:g} rpm (got {text})")
    return value


def grid(most: float = math.inf, unit: str = "") -> Callable[[str], tuple[float, float, int]]:
    """An argparse type: ``A:B:N`` -> (A, B, N) for N equally spaced values from A to B (positive, at most ``most``
    ``unit``, A <= B, N >= 1), so a bad grid is reported before JAX loads."""

    def parse(text: str) -> tuple[float, float, int]:
        parts = text.split(":")
        if len(parts) != 3:
            raise argparse.ArgumentTypeError(f"expected A:B:N (from A to B in N values, e.g. 100:700:61), got {text!r}")
        try:
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected A:B:N with numbers A and B and a whole number N, got {text!r}"
            ) from None
        if not (math.isfinite(a) and math.isfinite(b) and a > 0 and b > 0):
            raise argparse.ArgumentTypeError(f"A and B must be positive numbers, got {text!r}")
        if b > most:
            raise argparse.ArgumentTypeError(f"at most {most:g} {unit} (got {text!r})")
        if a > b:
            raise argparse.ArgumentTypeError(f"A must not exceed B, got {text!r}")
        if n < 1 or (n == 1 and a != b):
            raise argparse.ArgumentTypeError(f"N must be at least 1 (and N = 1 needs A = B), got {text!r}")
        return a, b, n

    return parse


def check_options(args: argparse.Namespace) -> None:
    """:class:`InputError` for the first option of ``args.command`` that is out of its bounds or does not apply."""
    if args.command == "table":
        check_table_step(args.step)
        if args.ecam is not None:
            check_ecam_points(args.ecam)
            if args.speed is not None:
                raise InputError("--speed", "does not apply to an e-cam table (positions per master angle, no forces)")
        if args.output == "-":  # the usual name of standard output, where the table goes without -o
            args.output = None
        if args.output:
            output_file(args.output, args.force, "table")
    elif args.command == "profile":
        from ..export import FORMATS  # the writers' module (and numpy) load for profile only
        from ..export.solid import parse_keyway

        out = Path(args.output)
        if out.is_dir():
            raise InputError(str(out), f"is a folder: give a file name ({', '.join('cam' + f for f in FORMATS)})")
        suffix = out.suffix.lower()
        if not suffix and out.name.lower() in FORMATS:  # ".dxf": a suffix without a name (Python reads a hidden file)
            raise InputError(str(out), f"a format without a file name: give one, as cam{out.name}")
        if suffix not in FORMATS:
            raise InputError(str(out), f"unknown format {suffix or '(no suffix)'!r}: use one of {', '.join(FORMATS)}")
        _profile_options(args, suffix)
        if args.keyway:
            parse_keyway(args.keyway)
    elif args.command == "tolerance" and args.samples is not None:
        check_samples(args.samples)
    elif args.command == "size":
        check_sizing(args.max_speed, args.margin, 0.0 if args.min_rate is None else args.min_rate)
    elif args.command == "optimize":
        if args.min_force is not None:
            check_min_force(args.min_force)
        out = output_file(args.output, args.force, "case file")  # before the work, not after
        if out.resolve() == Path(args.case).resolve():
            raise InputError(str(out), "is the input case; write the optimized case to another file")


def _profile_options(args, suffix: str) -> None:
    """Refuse an option that does not apply to the file asked for: nothing the user gave is silently ignored."""
    grind = args.grinder_wheel_radius is not None
    given = {
        "--cutter-radius": args.cutter_radius is not None,
        "--feed": args.feed is not None,
        "--arcs": args.arcs,
        "--climb/--conventional": args.conventional or args.climb,
        "--grinder-wheel-radius": grind,
        "--follower-lift": args.follower_lift,
        "--step": args.step is not None,
        "--thickness": args.thickness is not None,
        "--bore": args.bore is not None,
        "--keyway": args.keyway is not None,
    }
    takes = {
        ".nc": {"--cutter-radius", "--feed", "--arcs", "--climb/--conventional"},
        ".csv": {"--grinder-wheel-radius", "--follower-lift", "--step"},
        ".step": {"--thickness", "--bore", "--keyway"},
        ".stl": {"--thickness", "--bore", "--keyway"},
    }.get(suffix, set())
    for flag, on in given.items():
        if on and flag not in takes:
            what = {".nc": "a cutter path", ".csv": "an outline or grinder CSV", ".step": "a solid", ".stl": "a solid"}
            raise InputError(flag, f"does not apply to {what.get(suffix, 'an outline')} ({args.output})")
    if suffix == ".nc" and args.cutter_radius is None:
        raise InputError("--cutter-radius", "a cutter path (.nc) needs the cutter radius, mm")
    if suffix in (".step", ".stl") and args.thickness is None:
        raise InputError("--thickness", f"a solid ({suffix}) needs the plate's thickness, mm")
    if grind and args.follower_lift:
        raise InputError("--follower-lift", "write the wheel-centre table and the lift table one at a time")
    if args.step is not None and not (grind or args.follower_lift):
        raise InputError("--step", "is the angle step of a grinder table (--grinder-wheel-radius or --follower-lift)")
    check_chord_tolerance(args.tolerance)
    if args.step is not None:
        check_table_step(args.step)
    for flag, value in (
        ("--cutter-radius", args.cutter_radius),
        ("--grinder-wheel-radius", args.grinder_wheel_radius),
        ("--feed", args.feed),
        ("--thickness", args.thickness),
        ("--bore", args.bore),
    ):
        if value is not None and not (0 < value < 1e6):
            raise InputError(flag, f"must be a positive number below 1e6 (got {value:g})")
