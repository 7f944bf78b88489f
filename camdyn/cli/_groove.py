"""``sweep`` of a form-closed cam (``[follower] closure = "groove"`` or ``"conjugate"``): its crossover impacts over
cam speed x backlash, or conjugate cams' least cam force and least holding preload over cam speed, in place of the
jump map of a spring-held follower (a form-closed cam cannot jump); ``tolerance``'s is in :mod:`.tolerance`, which
alone loads the tolerance studies."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .._core.errors import InputError
from .._core.outputs import output_dir, output_file, safe_stem, write_new
from ..design.closure import impact_map, preload_map
from ..model.case import Case
from ..plot import save_impact_png, save_preload_png
from ._console import progress_bar


def groove_outputs(args: argparse.Namespace, case: Case, suffix: str, what: str) -> tuple[Path, Path]:
    """DIR/<case>-<suffix>.csv and .png, checked writable (and not there, without --force) before the work."""
    stem = safe_stem(case.name)  # the case's name is data, not a path: the files stay in the folder named
    paths = Path(args.output) / f"{stem}-{suffix}.csv", Path(args.output) / f"{stem}-{suffix}.png"
    output_dir(args.output, what)
    for path in paths:
        output_file(path, args.force, what)
    return paths


def sweep_groove(args: argparse.Namespace, case: Case, speeds: np.ndarray, gaps: np.ndarray | None) -> int:
    """``camdyn sweep`` of a groove cam: DIR/<case>-sweep.csv (the impact map over ``speeds`` x ``gaps``, mm;
    None: the case's backlash) and DIR/<case>-sweep.png."""
    f = case.follower
    assert f is not None and f.form_closed
    what = "a groove cam has" if f.closure == "groove" else "conjugate cams have"
    if args.spring_rates is not None:
        raise InputError("--spring-rates", f"{what} no return spring to vary: sweep its --backlash (mm) instead")
    if f.closure == "conjugate" and f.pair_preload > 0.0 and gaps is not None:
        raise InputError("--backlash", "conjugate cams with a preload have no backlash: sweep them without --backlash")
    if f.closure == "conjugate" and f.backlash == 0.0 and gaps is None:
        return sweep_preload(args, case, speeds)
    if gaps is None:
        gaps = np.array([case.follower.backlash])
    csv_path, png_path = groove_outputs(args, case, "sweep", "impact map")
    with progress_bar(args.quiet) as progress:
        im = impact_map(case, speeds, gaps, progress=progress)
    write_new(csv_path, im.csv, True)
    save_impact_png(im, png_path, speed_rpm=case.speed_rpm, backlash_mm=case.follower.backlash)
    lim = im.max_impact_velocity
    over = im.impact_velocity_m_per_s > lim
    print(
        f"{case.name}: {f.closure} cam, impact map of {im.impact_velocity_m_per_s.size} points ({speeds.size} speeds "
        f"{speeds[0]:g}-{speeds[-1]:g} rpm x {gaps.size} backlashes {gaps[0]:g}-{gaps[-1]:g} mm); a {f.closure} cam "
        "cannot jump: the map is of the impacts where the follower crosses the backlash"
    )
    forces = im.max_impact_force_N
    force = f"; largest impact force {np.nanmax(forces):.4g} N" if np.isfinite(forces).any() else ""
    print(
        f"impact speed above max_impact_velocity {lim:g} m/s at {int(np.count_nonzero(over))} of {over.size} points; "
        f"largest {float(np.max(im.impact_velocity_m_per_s)):.4g} m/s{force}"
    )
    print(f"wrote {csv_path} and {png_path}")
    return 0


def sweep_preload(args: argparse.Namespace, case: Case, speeds: np.ndarray) -> int:
    """``camdyn sweep`` of conjugate cams without backlash: DIR/<case>-sweep.csv (the least cam force and the least
    holding preload at each speed) and DIR/<case>-sweep.png."""
    csv_path, png_path = groove_outputs(args, case, "sweep", "preload sweep")
    with progress_bar(args.quiet) as progress:
        pm = preload_map(case, speeds, progress=progress)
    write_new(csv_path, pm.csv, True)
    save_preload_png(pm, png_path, speed_rpm=case.speed_rpm)
    unit = "N" if pm.translating else "N*m"
    print(
        f"{case.name}: conjugate cams, {speeds.size} speeds {speeds[0]:g}-{speeds[-1]:g} rpm; conjugate cams cannot "
        f"jump: the sweep is of the least force on either cam under the preload {pm.preload:g} {unit}"
    )
    held = pm.held
    if held.all():
        print(
            f"the preload keeps both rollers loaded at every speed (least cam force {pm.least_cam_force_N.min():.4g} N)"
        )
    else:
        first = float(speeds[np.argmin(held)])
        ok = speeds[held & (speeds < first)]
        upto = f"up to {float(ok[-1]):g} rpm" if ok.size else "at no speed of the sweep"
        print(
            f"the preload keeps both rollers loaded {upto}; a roller unloads from {first:g} rpm (the least preload "
            f"that holds there: {float(pm.least_preload[np.argmin(held)]):.4g} {unit})"
        )
    print(f"wrote {csv_path} and {png_path}")
    return 0
