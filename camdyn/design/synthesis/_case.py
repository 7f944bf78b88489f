"""``camdyn synthesize``: choose a CCM's dimensions for a path and write a complete case file.

The input (a *path file*, TOML) is a case file without ``[mechanism]``: ``name``, ``description``, ``[path]``
(required), ``[dynamics]`` (required: ``speed``, ``mass`` and ``spring_rate``; ``preload`` is sized when it is
left out), ``[limits]``, and an optional ``[synthesis]`` table of optimizer options (:class:`SynthesisSpec`).
:func:`synthesize_case` runs :func:`synthesize_dimensions` on it and returns the case file's
text with a header comment saying how it was made; the text is loaded back (:func:`camdyn.model.case.case_from_dict`)
before it is returned, so what is written is a case that ``camdyn check`` accepts.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..._core.errors import InputError
from ..._core.progress import Progress
from ...export.toml import camdyn_version, dumps_case
from ...model.case import Case, case_from_dict
from ...schema import PathFileSpec, parse
from ..sizing import size_spring
from ._ccm import DIMENSION_OBJECTIVE
from ._optimize import synthesize_dimensions

PRELOAD_STEP = 0.1  # N: a sized preload is rounded up to this (and at least one step above the least that holds)


@dataclass
class SynthesizedCase:
    """What :func:`synthesize_case` made: the case file ``text``, the loaded ``case``, the ``[mechanism]`` table
    and the optimizer's ``summary`` (see :func:`synthesize_dimensions`)."""

    text: str
    case: Case
    mechanism: dict
    summary: dict
    dynamics: dict
    preload_sized: bool = False
    notes: list[str] = field(default_factory=list)

    @property
    def constraints_met(self) -> bool:
        return bool(self.summary["constraints_met"])


def validate_path_file(raw: dict) -> PathFileSpec:
    """Validate a path file; every problem is one :class:`InputError` naming the key."""
    return parse(PathFileSpec, raw)


# ------------------------------------------------------------------------------------------ writing
def _fmt(x: float) -> str:
    return f"{x:.3g}" if abs(x) >= 1e-3 or x == 0.0 else f"{x:.1e}"


def _header(source: Path | None, summary: dict, sized: str | None) -> list[str]:
    ver = f" {camdyn_version()}".rstrip()
    src = f" {source}" if source is not None else ""
    lines = [
        f"Written by `camdyn synthesize{src}` (camdyn{ver}): the [mechanism] dimensions were chosen by scipy's "
        f"differential_evolution (seed {summary['seed']}, maxiter {summary['maxiter']}, popsize {summary['popsize']}; "
        f"{summary['generations']} generations, {'converged' if summary['optimizer_converged'] else 'not converged'}).",
        f"Objective: {DIMENSION_OBJECTIVE}; pressure angle <= {summary['max_pressure_angle_deg']:g} deg, "
        f"contour curvature radius >= {summary['min_curvature_ratio']:g} roller radii.",
        "Constraints: every dyad closes, the crank turns monotonically once per loop, transmission angles >= 30 deg.",
        f"CCM: crank {summary['crank_mm']:.3f} mm, coupler {summary['coupler_mm']:.3f} mm (eq. 5), stroke "
        f"{summary['stroke_mm']:.3f} mm, base radius {summary['base_radius_mm']:g} mm, least transmission angles "
        f"{summary['min_transmission_angle_deg']:.1f} deg (coupler-link) and {summary['min_slider_angle_deg']:.1f} "
        "deg (link-slider).",
        f"Path error: CCM {_fmt(summary['max_path_error_mm'])} mm (forward check of the exact synthesis)"
        + (
            "; the best plain four-bar found (Grashof crank-rocker, transmission >= 30 deg) "
            f"{_fmt(summary['fourbar_path_error_mm'])} mm."
            if "fourbar_path_error_mm" in summary
            else "."
        ),
    ]
    if not summary["constraints_met"]:
        lines.append("NOT MET: " + "; ".join(summary["violations"]) + " (try a larger maxiter or another seed)")
    if sized:
        lines.append(sized)
    lines.append("Units: lengths mm, angles deg, speed rpm, mass kg, force N, stiffness N/mm.")
    return lines


def _size_preload(doc: dict, source: Path | None, progress) -> tuple[float, str]:
    """The least preload (N) that holds at the case's spring rate up to speed_margin x speed, rounded up."""
    trial = dict(doc, dynamics=dict(doc["dynamics"], preload=1e6))  # holds at rest whatever the motion
    case = case_from_dict(trial, source=source)
    progress("spring sizing", 0, 1)
    sz = size_spring(case)
    progress("spring sizing", 1, 1)
    least = float(sz.at_current_rate.preload)
    preload = (math.floor(least / PRELOAD_STEP) + 1) * PRELOAD_STEP
    preload = round(max(preload, PRELOAD_STEP), 3)
    note = (
        "preload sized by camdyn's spring sizing: the least that keeps the contact force >= "
        f"{sz.min_contact_force:g} N up to {sz.top_speed_rpm:.4g} rpm at spring_rate "
        f"{doc['dynamics']['spring_rate']:g} N/mm is {least:.4g} N, rounded up to {preload:g} N."
    )
    return preload, note


def synthesize_case(
    raw: dict | PathFileSpec,
    *,
    source: Path | None = None,
    name: str | None = None,
    seed: int | None = None,
    maxiter: int | None = None,
    progress: Progress | None = None,
) -> SynthesizedCase:
    """Synthesize a CCM for the parsed path file ``raw`` and build the complete case file.

    ``seed`` and ``maxiter`` override ``[synthesis]``; ``name`` is the case name when the file gives none.
    ``progress(phase, done, total)`` follows the optimizer. Raises :class:`InputError` for a bad path file and
    :class:`NumericalError` when no design can be synthesized.
    """
    spec = raw if isinstance(raw, PathFileSpec) else validate_path_file(raw)
    raw = spec.model_dump(mode="json", exclude_unset=True)
    assert spec.path is not None and spec.dynamics is not None  # PathFileSpec requires both
    opts = spec.synthesis
    for flag, v in (("--seed", seed), ("--maxiter", maxiter)):
        if v is not None and v < (0 if flag == "--seed" else 1):
            raise InputError(flag, f"must be {'>= 0' if flag == '--seed' else '>= 1'} (got {v})")
    seed = opts.seed if seed is None else seed
    maxiter = opts.maxiter if maxiter is None else maxiter
    max_pa = opts.max_pressure_angle or spec.limits.max_pressure_angle or 30.0
    tick = progress or (lambda phase, done, total: None)
    result = synthesize_dimensions(
        spec.path,
        seed=seed,
        maxiter=maxiter,
        popsize=opts.popsize,
        max_pressure_angle=max_pa,
        min_curvature_ratio=spec.limits.min_curvature_ratio,
        roller_radius=opts.roller_radius,
        fourbar=opts.fourbar,
        progress=tick,
    )
    summary, mechanism = result["summary"], result["mechanism"]
    dynamics = dict(raw["dynamics"])
    doc: dict[str, Any] = {"name": spec.name or name or "case"}
    doc["description"] = spec.description or (
        f"CCM synthesized by camdyn synthesize for the {spec.path.type} path{f' of {source.name}' if source else ''}."
    )
    doc |= {"path": dict(raw["path"]), "mechanism": mechanism, "dynamics": dynamics}
    if "limits" in raw:
        doc["limits"] = dict(raw["limits"])
    sized_note = None
    if spec.dynamics.preload is None:
        preload, sized_note = _size_preload(doc, source, tick)
        keys = list(dynamics)
        at = keys.index("spring_rate") + 1
        dynamics = dict([*list(dynamics.items())[:at], ("preload", preload), *list(dynamics.items())[at:]])
        doc["dynamics"] = dynamics
    text = dumps_case(doc, _header(source, summary, sized_note))
    case = case_from_dict(tomllib.loads(text), source=source)
    notes = [sized_note] if sized_note else []
    return SynthesizedCase(
        text=text,
        case=case,
        mechanism=mechanism,
        summary=summary,
        dynamics=dynamics,
        preload_sized=sized_note is not None,
        notes=notes,
    )
