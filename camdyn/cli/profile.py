"""``camdyn profile CASE.toml -o FILE``: the cam for manufacturing, by the file's suffix.

.dxf / .csv / .svg the outline; .nc a CNC cutter-centre path (``--cutter-radius``); .csv with
``--grinder-wheel-radius`` a cam grinder's table, with ``--follower-lift`` the lift per degree; .step / .stl the
plate as a solid (``--thickness``; the optional extra ``camdyn[cad]``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from .._core.errors import InputError
from .._core.outputs import output_file, write_new
from .._core.units import MM_PER_INCH
from ..design.geometry import judge_geometry
from ..design.table import table_angles
from ..export import write_profile
from ..model.case import build_case
from ..model.geometry import WALLS, analyze, conjugate, groove
from . import _version

_DENSE_CURVATURE = 20_000  # angles on which a tool's fit in every concave stretch is judged (0.018 deg)


def run(args: argparse.Namespace) -> int:
    out = Path(args.output)
    suffix = out.suffix.lower()
    # the file name and the options were checked before JAX loaded (camdyn.cli._options)
    if suffix in (".step", ".stl"):
        # the optional extra: say how to get it before any work
        from ..export import solid

        solid.require_cad()
    grind = args.grinder_wheel_radius is not None or args.follower_lift
    if suffix in (".nc", ".step", ".stl") or grind:  # checked before the work (write_profile checks its own)
        output_file(out, args.force, "profile")
    case = build_case(args.spec, source=Path(args.case))
    if case.follower is None:
        raise InputError("follower", "the case has no cam follower geometry")
    if case.follower.form_closed and (suffix not in (".dxf", ".csv", ".svg") or grind):
        raise InputError(
            "follower.closure",
            "a form-closed cam's outlines (groove walls, conjugate cams) are written as an outline (.dxf, .csv or "
            ".svg); its cutter path, grinder table and solid are not built yet",
        )
    geo = analyze(case.motion, case.follower)
    lim = case.limits
    _, warnings, _ = judge_geometry(
        geo, case.motion, max_pressure_angle=lim.max_pressure_angle, min_curvature_ratio=lim.min_curvature_ratio
    )
    if suffix == ".nc":
        line = _cutter_path(args, case, geo, out)
    elif grind:
        line = _grinder(args, case, geo, out)
    elif suffix in (".step", ".stl"):
        line = _solid(args, geo, out)
    else:
        curves = geo.contour_fn()
        if case.follower.closure == "conjugate":  # both cams, the primary the spring cam's contour
            second = conjugate(case.motion, case.follower)
            curves = {"CAM_PRIMARY": curves, "CAM_CONJUGATE": second.contour_fn()}
            warnings += ["the conjugate cam's contour folds (undercut)"] if second.undercut else []
        elif case.follower.form_closed:  # a groove cam: both walls, the inner one where a spring cam's contour is
            walls = groove(case.motion, case.follower)
            curves = {f"GROOVE_{w.upper()}": walls.wall_fn(w) for w in WALLS}
            warnings += [
                f"the groove's {w} wall folds (undercut)" for w in WALLS if getattr(walls, f"{w}_wall").undercut
            ]
        info = write_profile(curves, out, tolerance=args.tolerance, force=args.force, units=args.units)
        line = (
            f"wrote {args.output}: {info['points']} points within {info['tolerance_mm']:g} mm, "
            f"x {info['x_min_mm']:.3f}..{info['x_max_mm']:.3f} mm, y {info['y_min_mm']:.3f}..{info['y_max_mm']:.3f} mm"
            + ("" if args.units == "mm" else " (written in inches)")
        )
    for w in warnings:  # an undercut cam can still be drawn, but the user must know it cannot be followed
        print(f"warning: {w}", file=sys.stderr)
    print(line)
    return 0


def _check_tool(geo, radius_mm: float, tol: float, tool: str) -> None:
    from ..export.machining import check_tool_fits

    theta = np.arange(_DENSE_CURVATURE) * (360.0 / _DENSE_CURVATURE)
    check_tool_fits(theta, geo.table(theta)["rho_contour_mm"], radius_mm, tol, tool)


def _cutter_path(args, case, geo, out: Path) -> str:
    from ..export.machining import (
        DEFAULT_FEED_MM_PER_MIN,
        MIN_MACHINING_TOLERANCE_MM,
        cutter_path,
        gcode_text,
        sha256_of,
    )

    tol, rc = args.tolerance, args.cutter_radius
    if tol < MIN_MACHINING_TOLERANCE_MM:
        least = MIN_MACHINING_TOLERANCE_MM
        raise InputError(
            "--tolerance", f"a cutter path needs at least {least:g} mm (a machine's resolution), got {tol:g} mm"
        )
    _check_tool(geo, rc, tol, "cutter")
    path = cutter_path(geo.contour_fn(), geo.offset_fn, rc, tol, climb=not args.conventional, arcs=args.arcs)
    feed = DEFAULT_FEED_MM_PER_MIN if args.feed is None else args.feed
    sense = "conventional, counterclockwise" if args.conventional else "climb, clockwise"
    header = [
        f"camdyn {_version()} profile: cam {case.name}",
        f"case {Path(args.case).name} sha256 {sha256_of(args.case)}",
        f"cutter radius {rc:g} mm, diameter {2 * rc:g} mm; {sense} round the cam with a right-hand spindle M3",
        "tool-centre path: no cutter compensation G41/G42; XY in the cam frame, the cam axis at X0 Y0",
        f"chord tolerance {tol:g} mm: the path lies {path.min_distance_mm:.4f}..{path.max_distance_mm:.4f} mm from "
        + "the outline, never nearer than the cutter radius",
        f"feed {feed:g} mm/min; Z0 the cutting depth, safe Z above the part; spindle, coolant and work offset are "
        + "the operator's",
        f"units {'mm G21' if args.units == 'mm' else 'inch G20'}",
    ]
    write_new(out, gcode_text(path, header=header, feed_mm_per_min=feed, units=args.units), args.force)
    kind = "arcs and lines" if args.arcs else "lines"
    return (
        f"wrote {args.output}: {len(path.moves)} moves ({kind}), cutter radius {rc:g} mm, the path "
        f"{path.min_distance_mm:.4f}..{path.max_distance_mm:.4f} mm from the outline (tolerance {tol:g} mm)"
    )


def _grinder(args, case, geo, out: Path) -> str:
    from ..export.machining import grinder_table
    from ..model.motion import evaluate

    step = 0.5 if args.step is None else args.step
    theta = table_angles(step)
    scale, u = (1.0, "mm") if args.units == "mm" else (1.0 / MM_PER_INCH, "in")
    if args.follower_lift:
        s = np.asarray(evaluate(case.motion, np.deg2rad(theta)))[0]
        col, val = ("lift_deg", np.degrees(s)) if case.oscillating else (f"lift_{u}", s * scale)
        what = "follower lift"
    else:
        rw = args.grinder_wheel_radius
        _check_tool(geo, rw, args.tolerance, "grinding wheel")
        centre = grinder_table(geo.contour_fn(), theta, rw, case.follower.sigma, args.tolerance)
        col, val = f"wheel_center_{u}", centre * scale
        what = f"wheel centre, wheel radius {rw:g} mm"
    fmt = "%.6f" if u == "mm" or col == "lift_deg" else "%.7f"
    rows = "\n".join(f"{t:.4f},{fmt % v}" for t, v in zip(theta, val, strict=True))
    write_new(out, f"theta_deg,{col}\n{rows}\n", args.force)
    return (
        f"wrote {args.output}: {len(theta)} angles every {step:g} deg, {what}, {col} {val.min():.4f}..{val.max():.4f}"
    )


def _solid(args, geo, out: Path) -> str:
    from ..export import solid

    ext = geo.extremes
    if ext.cusp:  # no plate has a folded outline: its spline would only stray from a contour that crosses itself
        raise InputError(
            f"theta = {ext.min_radius_of_curvature_at_deg:.4g} deg",
            f"the contour folds (undercut; least radius {ext.min_radius_of_curvature_mm:.4g} mm): a plate cut to it "
            "is not this cam, so no solid is written; a larger base radius unfolds it (camdyn check advises one)",
        )
    keyway = solid.parse_keyway(args.keyway) if args.keyway else None
    info = solid.write_solid(
        geo.contour_fn(),
        out,
        thickness_mm=args.thickness,
        bore_mm=args.bore,
        keyway_mm=keyway,
        tolerance_mm=args.tolerance,
        units=args.units,
        force=args.force,
    )
    return (
        f"wrote {args.output}: cam plate {args.thickness:g} mm thick, volume {info['volume_mm3']:.1f} mm^3, "
        f"outline within {info['outline_deviation_mm']:.4f} mm of the contour (tolerance {args.tolerance:g} mm)"
    )
