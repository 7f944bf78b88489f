"""Dimensional synthesis of a CCM for a path by differential evolution, the exact synthesis of the best designs,
the cam size that ``camdyn check`` accepts, and the four-bar comparison."""

from __future__ import annotations

import inspect
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.optimize import differential_evolution

from ..._core.errors import InputError, NumericalError
from ...model.geometry import min_base_radius, rounded_base_radius
from ...model.linkage import synthesize_motion, vmap_scalar
from ...model.paths import build_path, parse_path
from ...schema import PathSpec
from ._ccm import DIMENSION_OBJECTIVE, ccm_objective, ccm_score, ccm_table, meets_constraints
from ._fourbar import fourbar_bounds, fourbar_objective, fourbar_summary

_N_FIT = 256  # path samples used by the optimizer (the chosen design is then synthesized exactly)
_N_CANDIDATES = 12  # designs of the final population tried in order when the best one fails the exact synthesis
_SUMMARY_KEYS = (
    "crank_mm",
    "coupler_mm",
    "start_angle_deg",
    "rotation",
    "stroke_mm",
    "max_path_error_mm",
    "min_transmission_angle_deg",
    "min_slider_angle_deg",
    "base_radius_mm",
    "offset_mm",
)


def _de_seed(seed: int) -> dict:
    """``rng=`` where scipy has it (>= 1.15; ``seed=`` is deprecated there), ``seed=`` before."""
    return {"rng": seed} if "rng" in inspect.signature(differential_evolution).parameters else {"seed": seed}


def _quantized(energies) -> np.ndarray:
    """Scores rounded to 10 significant digits. Differential evolution's path turns on comparisons of scores; a
    last-bit difference between machines (another CPU's vector code in XLA) would otherwise send it elsewhere,
    and the same seed must give the same mechanism everywhere."""
    e = np.asarray(energies, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = 10.0 ** (np.floor(np.log10(np.abs(e))) - 9)
    return np.where(np.isfinite(scale) & (scale > 0), np.round(e / scale) * scale, e)


def _run_de(phase: str, fn, bounds, *, seed: int, maxiter: int, popsize: int, tick):
    """One differential evolution over ``bounds``, its population scored at once by ``fn`` (vectorized, scores
    rounded by ``_quantized``), reporting each generation as ``tick(phase, done, maxiter)``."""
    gen = [0]
    tick(phase, 0, maxiter)

    def callback(xk: np.ndarray, convergence: float | None = None) -> None:
        gen[0] += 1
        tick(phase, gen[0], maxiter)

    res = differential_evolution(
        lambda x: _quantized(fn(x)),
        bounds,
        maxiter=maxiter,
        popsize=popsize,
        tol=1e-3,
        polish=False,
        vectorized=True,
        updating="deferred",
        callback=callback,
        **_de_seed(seed),
    )
    tick(phase, maxiter, maxiter)
    return res


def _ccm_bounds(mid: np.ndarray, size: float) -> list[tuple[float, float]]:
    """The box of CCM designs for a path of extent ``size`` (mm) about ``mid``: the cam centre within 4 sizes,
    any slider direction, its offset within 2 sizes, the link from half a size to 6."""
    return [
        (mid[0] - 4 * size, mid[0] + 4 * size),
        (mid[1] - 4 * size, mid[1] + 4 * size),
        (-180.0, 180.0),
        (-2 * size, 2 * size),
        (0.5 * size, 6 * size),
    ]


def _exact_best(res, path, t, max_pa: float, rr: float, sharp: bool, min_ratio: float):
    """The first of the final population's best designs (in order of their score) whose exact synthesis meets
    every constraint, else the best that synthesizes at all: (table, synthesis, violations, score)."""
    order = np.argsort(res.population_energies)
    cands = [res.x] + [res.population[i] for i in order if not np.allclose(res.population[i], res.x)]
    best, errors = None, []
    for x in cands[:_N_CANDIDATES]:
        score, info = ccm_score(x, t, max_pa, rr, sharp, min_ratio)
        table = ccm_table(x, info["start"], rr, max_pa)
        try:
            syn = synthesize_motion(path, table)
        except (NumericalError, InputError) as exc:
            errors.append(str(exc))
            continue
        violations = meets_constraints(syn.summary)
        if best is None or (best[2] and not violations):
            best = (table, syn, violations, score)
        if not violations:
            break
    if best is None:
        raise NumericalError(
            "synthesis",
            f"none of the {min(len(cands), _N_CANDIDATES)} best designs could be synthesized exactly (first: "
            f"{errors[0]}); try a larger maxiter or another seed",
        )
    return best


def _size_cam(table: dict, syn, max_pa: float, min_ratio: float) -> None:
    """Set ``table["base_radius"]`` to the least that meets ``camdyn check``'s pressure-angle and curvature limits
    on its own grid, rounded up to 0.5 mm (else keep the synthesis' own choice, with a warning)."""
    try:
        rb = min_base_radius(syn.tabulated, syn.follower, max_pressure_angle=max_pa, min_curvature_ratio=min_ratio)
        table["base_radius"] = rounded_base_radius(rb)
    except NumericalError as exc:  # e.g. sharp corners: no base radius makes the contour smooth
        table["base_radius"] = float(syn.summary["base_radius_mm"])
        syn.warnings.append(f"base radius: {exc.message}; kept {table['base_radius']:g} mm")
    table.pop("max_pressure_angle", None)  # used only to choose a base radius, which the table now gives


def synthesize_dimensions(
    path: dict | PathSpec,
    *,
    seed: int = 0,
    maxiter: int = 200,
    max_pressure_angle: float = 30.0,
    min_curvature_ratio: float = 1.5,
    roller_radius: float = 10.0,
    popsize: int = 15,
    fourbar: bool = True,
    progress: Callable[[str, int, int], None] | None = None,
) -> dict:
    """Choose CCM dimensions for ``path`` with ``differential_evolution`` (the CCM paper's GA family).

    Free: cam centre A, slider line (angle and offset from A), link C-E; the tracing point is the coupler
    joint (C = T); crank and coupler from Ye & Smith eq. 5. Minimizes the stroke plus half the prime radius
    that keeps the pressure angle within ``max_pressure_angle`` and the contour's radius of curvature at least
    ``min_curvature_ratio`` roller radii (:data:`DIMENSION_OBJECTIVE`: a short stroke on a small cam), subject
    to: every dyad closes, the crank turns monotonically exactly once per loop, transmission angles
    (coupler-link and link-slider) >= 30 deg. (Grashof's condition does not apply to the CCM: with the slider
    driven by the cam its linkage is not a four-bar loop.) Constraints enter as penalties; the optimizer
    scores 256 path samples of each of ``popsize`` x 5 designs per generation (vectorized) and stops after
    ``maxiter`` generations or when the population's scores agree to 0.1 %. The best designs of its final
    population are then synthesized exactly (:func:`synthesize_motion`, rounded to 0.001 mm / deg) in order
    until one meets every constraint there, and its base radius is the least that passes ``camdyn check``'s
    pressure-angle and curvature limits (:func:`camdyn.model.geometry.min_base_radius`, rounded up to 0.5 mm).
    Also fits the best plain four-bar to the path: a Grashof crank-rocker (the crank the shortest link) with
    transmission angle >= 30 deg, 10 free values including the assembly mode; its path error is the
    Hausdorff distance between its coupler curve and the path (the CCM paper's comparison; ``fourbar=False``
    skips it).

    ``progress(phase, done, total)`` is called once per optimizer generation and phase. Returns
    ``{"mechanism": <[mechanism] table>, "summary": {...}}``: the summary has ``crank_mm``, ``coupler_mm``,
    ``stroke_mm``, ``base_radius_mm``, ``min_transmission_angle_deg``, ``min_slider_angle_deg``,
    ``max_path_error_mm`` (forward check of the exact synthesis), ``constraints_met`` and ``violations``,
    ``optimizer_converged``, ``generations``, ``warnings``, ``fourbar_path_error_mm`` with the four-bar's
    dimensions and checks in ``fourbar``, and ``time_s``. Raises :class:`NumericalError` when no design of
    the final population can be synthesized.
    """
    t_start = time.perf_counter()
    pth = build_path(parse_path(path))
    t = vmap_scalar(pth.point, np.arange(_N_FIT) / _N_FIT)
    lo_xy, hi_xy = t.min(0), t.max(0)
    size = float(np.max(hi_xy - lo_xy))
    mid = (lo_xy + hi_xy) / 2
    tick = progress or (lambda phase, done, total: None)
    de: dict[str, Any] = dict(seed=seed, maxiter=maxiter, popsize=popsize, tick=tick)
    sharp = bool(pth.sharp_u)
    fit = (max_pressure_angle, roller_radius, sharp, min_curvature_ratio)
    res = _run_de("CCM dimensions", lambda x: ccm_objective(x, t, *fit)["cost"], _ccm_bounds(mid, size), **de)
    tick("exact synthesis", 0, 1)
    table, syn, violations, score = _exact_best(res, path, t, *fit)
    tick("exact synthesis", 1, 1)
    tick("cam size", 0, 1)
    _size_cam(table, syn, max_pressure_angle, min_curvature_ratio)
    tick("cam size", 1, 1)
    summary: dict = {k: syn.summary[k] for k in _SUMMARY_KEYS}
    summary["base_radius_mm"] = table["base_radius"]
    summary.update(
        objective=DIMENSION_OBJECTIVE,
        objective_value=float(score),
        optimizer_converged=bool(res.success),
        generations=int(res.nit),
        seed=seed,
        maxiter=maxiter,
        popsize=popsize,
        max_pressure_angle_deg=max_pressure_angle,
        min_curvature_ratio=min_curvature_ratio,
        constraints_met=not violations,
        violations=violations,
        warnings=list(syn.warnings),
    )
    if fourbar:  # the CCM paper's comparison: the best plain four-bar coupler curve
        fb = _run_de("four-bar comparison", lambda x: fourbar_objective(x, t), fourbar_bounds(mid, size), **de)
        summary["fourbar_path_error_mm"], info = fourbar_summary(fb.x, t)
        summary["fourbar"] = info | {"optimizer_converged": bool(fb.success), "generations": int(fb.nit)}
    summary["time_s"] = time.perf_counter() - t_start
    return {"mechanism": table, "summary": summary}
