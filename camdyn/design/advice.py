"""Advice that takes more than one check to find: the corner radius that makes a sharp-cornered path pass."""

from __future__ import annotations

from .._core.errors import CamdynError
from .._core.progress import Progress, counter
from ..model.case import Case, case_from_dict
from ._check import CheckKind, find
from .checks import CheckReport, run_check

CORNER_EVALUATIONS = 6  # full checks of the corner-radius bisection


def corner_radius_advice(
    case: Case,
    speed_rpm: float | None = None,
    *,
    evaluations: int = CORNER_EVALUATIONS,
    progress: Progress | None = None,
) -> str | None:
    """For a failing path case with sharp corners: the corner radius (mm) with which it passes, or why none does.

    The sharp corner is the cause (the follower's velocity jumps there), so the remedy is a fillet: bisect
    ``[path] corner_radius`` between 0 (fails) and half the shorter side on the full check's verdict, with
    ``evaluations`` checks in all (each re-synthesizes the mechanism). None if the case has no sharp corners.
    """
    syn = case.synthesis
    path = case.spec.path
    if syn is None or not syn.sharp_corners or path is None or path.type != "rectangle":
        return None
    raw = case.spec.model_dump(exclude_unset=True)
    r_max = 0.5 * min(float(raw["path"]["width"]), float(raw["path"]["height"]))
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    seen: dict[float, CheckReport | None] = {}
    tick = counter(progress, "corner radius", evaluations)

    def verdict(r: float) -> bool:
        trial = {**raw, "path": {**raw["path"], "corner_radius": r}}
        try:
            seen[r] = run_check(case_from_dict(trial, source=case.source), rpm)
        except CamdynError:  # a radius the mechanism cannot trace counts as failing
            seen[r] = None
        tick()
        return (rep := seen[r]) is not None and rep.verdict == "pass"

    tidy = lambda r: max(round(r, 1), 0.1)  # noqa: E731 - a radius to 0.1 mm is what a drawing gives
    lo, hi = 0.0, None
    first = tidy(r_max / 8.0)
    if verdict(first):
        hi = first
    else:
        lo, top = first, tidy(0.98 * r_max)
        if not verdict(top):
            return (
                f"no corner radius up to {top:g} mm passes at {rpm:g} rpm: the sharp corners are not the only problem"
            )
        hi = top
    for _ in range(evaluations - len(seen)):
        mid = tidy(0.5 * (lo + hi))
        if mid in (lo, hi):
            break
        lo, hi = (lo, mid) if verdict(mid) else (mid, hi)
    rep = seen[hi]
    assert rep is not None  # hi passed
    force = find(rep.checks, CheckKind.CONTACT_FORCE)
    margin = find(rep.checks, CheckKind.SPEED_MARGIN)
    assert force is not None and margin is not None  # every check report has both
    margin_txt = "no jump" if margin.value is None else f"speed margin {margin.value:.3g}"
    return (
        f"sharp corners: [path] corner_radius = {hi:g} mm passes at {rpm:g} rpm (least contact force "
        f"{force.value:.3g} N, {margin_txt}){f'; {lo:g} mm fails' if lo > 0 else ''}"
    )
