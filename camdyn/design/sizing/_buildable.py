"""``size --buildable``: the least peak spring force over springs that can be built within ``[spring]``.

For every rate the sizer knows the least preload that holds (kinematic, or the dynamic model's for a compliant
train), and the spring designer knows the largest preload a buildable spring of that rate can give
(:func:`camdyn.design.spring.case_max_preload`; every lower preload is buildable too). A rate is feasible where
the first does not exceed the second; the answer is the feasible rate with the least peak spring force
``k s_max + F0``: a scan over rates a spring can have (log-spaced), refined by golden section between the best
scanned rate's neighbours (a compliant train's preloads as its search finds them; the answer's verified on more
speeds, :func:`buildable_answer`). Only springs whose surge frequency is clear of the cam's strong harmonics at every
speed up to the top one are buildable (:func:`camdyn.design.surge.surge_floor_hz`).

**The spring's own mass** (:func:`buildable_fixed_point`): the part proposed has a mass, and a third of it moves
with the follower (``[spring] model``), which lowers the jump speed. So the sizing is repeated with the mass of
the spring it proposes until the mass no longer grows (it only ever grows, so the rounds end: the set of parts
is finite). The answer is written to 4 significant digits (the preload rounded up), sized to (1 + HEADROOM) x the
top speed, and judged as ``check`` judges it (:func:`camdyn.design.checks.speed_margin_check`, with the spring
``check`` designs for it and its mass); where the check's margin falls short (the surge model's jump speed is
below the lumped one the sizing uses), the sizing speed is raised by the shortfall and the rounds go on.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..._core.errors import InputError
from ..._core.minimize import minimize_bounded
from ..._core.progress import Progress, phase
from ..._core.sharding import on_cores
from ..._core.units import RPM
from ...model.case import Case
from ...model.follower import follower_model
from ...schema import SpringSpec, dynamics_keys
from .._check import Check
from ..checks import jump_speeds, speed_margin_check
from ..parts import resolve_spring
from ..spring import SpringDesign, case_max_preload, design_case_spring, surge_floor
from ._dynamic import Dynamic
from ._kinematic import preload_kinematic
from ._problem import Grid, Problem, build_problem

LINEAR_RATES_N_PER_MM = (0.05, 2000.0)  # the rates a helical compression spring of camdyn's wire sizes can have
_N_SCAN = 41
_UNBUILDABLE = 1e300  # the peak force of a rate no spring has (finite: Brent's parabolas must not meet inf - inf)


def _rate_range(case, p: Problem) -> tuple[float, float]:
    """The scan's rates in the case's units (N/mm; N*m/rad for an arm: k_lin r^2, the spring at ``lever_arm``)."""
    lo, hi = LINEAR_RATES_N_PER_MM
    if p.kind.rotary:  # the spring acts at [spring] lever_arm from the pivot
        r = case.spec.spring.lever_arm if case.spec.spring is not None and case.spec.spring.lever_arm else None
        if r is None:
            raise InputError(
                "spring.lever_arm",
                f"{p.kind.a} follower's spring needs [spring] lever_arm to be sized as a part: the distance "
                "from the arm pivot to the spring, mm",
            )
        lo, hi = lo * r * r / 1000.0, hi * r * r / 1000.0
    return max(lo, p.kind.rate_from_si(p.k_lo)), hi


HEADROOM = 2e-3  # the spring is sized to (1 + HEADROOM) x the top speed: it passes check as written, with margin
WRITTEN_DIGITS = 4  # significant digits the proposal is written (and judged) with
_ROUNDS = 8


def written(x: float, up: bool = False, down: bool = False) -> float:
    """``x`` to :data:`WRITTEN_DIGITS` significant digits (``up``: rounded up; ``down``: rounded down), as ``size``
    writes it."""
    if x == 0.0 or not math.isfinite(x):
        return x
    q = 10.0 ** (math.floor(math.log10(abs(x))) - WRITTEN_DIGITS + 1)
    n = math.ceil(x / q - 1e-9) if up else math.floor(x / q + 1e-9) if down else round(x / q)
    return float(f"{n * q:.{WRITTEN_DIGITS + 2}g}")


def buildable_answer(
    case: Case, p: Problem, grid: Grid, dynamic: Dynamic | None, surge_top_rpm: float
) -> tuple[float, float]:
    """(k SI, F0) of the buildable spring with the least peak force, its surge clear of the cam's strong
    harmonics up to ``surge_top_rpm``; :class:`InputError` naming ``[spring]`` where no rate gives a spring that
    holds.

    A compliant train's scan and refinement compare the least preloads its search finds (161 speeds, the worst
    refined); the answer's is verified on 1127 (:meth:`Dynamic.raised`, which moves it by rounding: 1e-7 of itself
    at most on the shipped cases) and must still fit a spring of its rate, else the next best scanned rate's."""

    def least(k_si: float, verified: bool = False) -> float:
        if dynamic is None:
            f0 = preload_kinematic(p, grid, k_si, polish=True)
        else:
            f0 = dynamic.preload(k_si)[0]
            f0 = dynamic.raised(k_si, f0) if verified else f0
        return max(f0, 0.0)  # a compression spring at zero lift pushes, or touches

    def peak(rate: float) -> float:  # user units in, the peak spring force out; inf where it cannot be built
        k_si = p.kind.rate_to_si(rate)
        top = case_max_preload(case, rate, surge_top_rpm)
        if top is None:  # no spring of this rate fits: the least preload (10 dynamic solves) is not needed
            return _UNBUILDABLE
        f0 = least(k_si)
        return _UNBUILDABLE if f0 > top else k_si * p.s_max + f0

    lo, hi = _rate_range(case, p)
    if not lo < hi:
        raise InputError(
            "--min-rate",
            f"no buildable spring is as stiff as {p.kind.rate_from_si(p.k_lo):g}: camdyn's springs reach {hi:g}",
        )
    rates = np.geomspace(lo, hi, _N_SCAN)
    peaks = np.array(on_cores(peak, rates))  # each rate a few steady-state programs: on a thread per core
    if (peaks < _UNBUILDABLE).any():
        i = int(np.nanargmin(peaks))
        a, b = math.log(rates[max(i - 1, 0)]), math.log(rates[min(i + 1, len(rates) - 1)])
        u, peak_u, _ = minimize_bounded(lambda u: peak(math.exp(u)), a, b, xatol=1e-4)
        best = math.exp(u) if peak_u < peaks[i] else rates[i]
        fits = [rates[j] for j in np.argsort(peaks) if peaks[j] < _UNBUILDABLE]  # the scan's, best first
        for rate in [best, *fits]:
            k_si = p.kind.rate_to_si(rate)
            f0, top = least(k_si, verified=True), case_max_preload(case, rate, surge_top_rpm)
            if top is not None and f0 <= top:
                return k_si, f0
    raise InputError(
        "spring",
        f"no buildable spring holds the follower: at every rate from {lo:.3g} to {hi:.3g} "
        f"{p.kind.rate_unit} the preload it needs exceeds what a spring of that rate within "
        f"[spring], its surge at least {surge_floor(case, surge_top_rpm):.4g} Hz (clear of the cam's strong "
        f"harmonics up to {surge_top_rpm:.4g} rpm), can give (a larger outside_diameter_max or "
        "installed_length, or another material, widens the choice)",
    )


def as_written(case: Case, rate: float, preload: float) -> Case:
    """The case with the proposed spring in ``[dynamics]`` (the case's units) and its ``[spring]`` table (the
    default one where it has none: the part ``size --buildable`` designs), its spring not yet resolved."""
    _, rate_key, preload_key, _, _ = dynamics_keys(case.kind)
    keys = (rate_key, preload_key)
    dyn_spec = case.spec.dynamics.model_copy(update=dict(zip(keys, (rate, preload), strict=True)))
    spec = case.spec.model_copy(update={"dynamics": dyn_spec, "spring": case.spec.spring or SpringSpec()})
    return replace(case, spec=spec, model=follower_model(dyn_spec, kind=case.kind), spring=None)


def judged_as_written(case: Case, rate: float, preload: float, speed_rpm: float, margin: float) -> tuple[Check, Case]:
    """``check``'s speed-margin verdict on the case with the spring as written, its own mass in the dynamics
    (``[spring] model``), and that case resolved."""
    resolved = resolve_spring(as_written(case, rate, preload))
    omega = speed_rpm * RPM
    return speed_margin_check(jump_speeds(resolved, omega, margin)[2], omega, margin), resolved


def buildable_fixed_point(
    case: Case, speed_rpm: float, margin: float, min_rate: float, progress: Progress | None = None
) -> tuple[Case, float, float, SpringDesign, Check]:
    """``size --buildable`` with the proposed spring's own mass: (the case, its own spring, with the proposed
    spring's mass in its model; rate and preload as written, the case's units; the part; check's speed-margin
    verdict on the case with that spring). ``case`` is resolved (:func:`camdyn.design.parts.resolve_spring`).
    ``progress``: a phase per round (a scan of the rates a spring can have, seconds each)."""
    model = case.spec.spring.model if case.spec.spring is not None else "lumped"
    spring = case.spring
    assert spring is not None  # the case is resolved (resolve_spring)
    target = margin * (1.0 + HEADROOM)
    size_margin, mass, check, rate, preload = target, 0.0, None, math.nan, math.nan
    for i in range(_ROUNDS):
        sd = spring.with_mass(mass, model)
        sized = replace(case, model=sd.follower(), spring=sd)
        p, grid = build_problem(sized, speed_rpm, size_margin, min_rate)
        with phase(progress, f"buildable springs, round {i + 1} (spring mass {1000.0 * mass:.4g} g)"):
            k, f0 = buildable_answer(sized, p, grid, None if p.rigid else Dynamic.of(p), margin * speed_rpm)
        rate, preload = written(p.kind.rate_from_si(k)), written(f0, up=True)
        part = design_case_spring(sized, rate=rate, preload=preload, surge="require", top_speed_rpm=margin * speed_rpm)
        if part.spring.mass > mass * (1.0 + 1e-9):
            mass = part.spring.mass
            continue
        check, resolved = judged_as_written(case, rate, preload, speed_rpm, margin)
        if check.value is None or check.value >= margin * (1.0 + 0.5 * HEADROOM):
            assert resolved.spring is not None  # judged_as_written resolves it
            sd = spring.with_mass(resolved.spring.mass_kg, resolved.spring.model)  # the mass check weighs
            return replace(case, model=sd.follower(), spring=sd), rate, preload, part, check
        size_margin *= target / check.value
    last = f"last: {rate:g}, {preload:g}; check's speed margin {None if check is None else check.value}"
    raise InputError(
        "spring",
        f"size --buildable did not settle on a spring that holds with its own mass in {_ROUNDS} rounds ({last})",
    )
