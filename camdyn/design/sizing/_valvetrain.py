"""``size`` on a valvetrain: the valve spring (rate and preload at the valve) with which the two-mass model's float
and bounce speeds both reach margin x the speed.

**Closed-form start.** A rigid, lash-free train is one follower at the cam (:func:`~camdyn.model.valvetrain.
equivalent_follower`): mass ``m_cam + m_valve r^2``, rate ``k r^2``, preload ``F0 r``. Its spring is sized by the
kinematic linear program (:mod:`._lp`, exact at every speed up to the top one) with the rate at least ``min_rate
r^2``; back at the valve ``k = k_eq / r^2`` and ``F0 = P_eq / r + k lash``: with the valve open the spring is
compressed by ``r s - lash``, so its force at the follower is ``k r^2 s + r (F0 - k lash)``.

**The two-mass model decides.** The train's compliance, the lash and the seat move the float speed off the
equivalent's jump speed, and bounce is the two-mass model's alone. A light preload also lets the valve leave the
train as the lash closes (tossed off the rocker on the opening ramp, the cam contact then unloaded on the
constant-velocity ramp, a knife-edge the float search need not see): so the least preload that keeps the train's
force on the valve above 0.1 % of the peak spring force over the event at the top speed is found first (bisected
to 0.5 %), and bounds the search below; above, the largest preload with which the train still lifts the valve
half its stroke turned slowly (what a case accepts, :func:`~camdyn.model.valvetrain.max_lifting_preload`): a
preload past it keeps the valve shut, a float and a bounce never seen. The rate is kept and the preload is searched:
the float and bounce speeds (:func:`~camdyn.design.valvetrain.analyze_valvetrain`, the searches ``check`` runs)
of the spring as written (4 significant digits, the preload rounded up) are driven to (1 + HEADROOM) x the top
speed by secant steps on the least of the two speeds squared (the equivalent's jump speed squared is affine in the
preload), bracketed, with bisection where a secant step leaves the bracket. The answer is the least preload whose
float and bounce speeds are at least (1 + HEADROOM / 2) x the top speed, and ``check`` judges it as written.

**A ``[spring]`` part** moves with the valve (its lumped third, or its surge chain), and its mass depends on the
rate and preload sized: a fixed point (:func:`_size_with_part`) sizes with the case's own part's mass, then with
the mass of the part designed for each proposal, until the part is the one sized with or its mass moves the
preload by less than 0.1 %; ``check`` judges the proposal with the part it designs for it, the one reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..._core.limits import check_sizing
from ..._core.progress import Progress, phase
from ..._core.results import finite_or_none
from ..._core.units import M_PER_MM, RPM
from ...model import dynamics as dyn
from ...model.case import Case, valve_stroke_mm, with_valvetrain_keys
from ...model.valvetrain import max_lifting_preload
from .._check import Check
from ..checks import run_check
from ..parts import resolve_spring, with_spring_part
from ..spring import SpringDesign, design_case_spring
from ..valvetrain import ValvetrainResult, analyze_valvetrain
from ._buildable import HEADROOM, WRITTEN_DIGITS, written
from ._lp import lp
from ._problem import build_problem

_ROUNDS = 10
_CLOSE = 0.01  # the search stops once the least speed is within 1 % above (1 + HEADROOM) x the top speed
_ON_TRAIN = 1e-3  # of the peak spring force: the least train force over the valve event that keeps it on the train
_SEARCH = "valve spring: preload search (two-mass model)"
_TRAIN_WIDTH = 0.005  # relative width of the bisection for the least preload that keeps the valve on the train
_TRAIN_ROUNDS = 30
_PART_ROUNDS = 6
_PART_CLOSE = 1e-3  # a [spring] part's fixed point ends where the part's new mass moves the preload by less

METHOD = (
    "closed form: the equivalent single follower (mass m_cam + m_valve r^2, rate k r^2, preload F0 r) sized by the "
    "kinematic linear program, the rate at least min_rate; then the preload searched (secant on the least of the "
    "float and bounce speeds squared, bracketed) until the two-mass model's float and bounce speeds, as check "
    f"searches them, reach (1 + {HEADROOM:g}) x the top speed; written to {WRITTEN_DIGITS} digits, the preload "
    "rounded up, and judged by check as written"
)


@dataclass(frozen=True)
class ValveSpringDesign:
    """One valve spring (N/mm and N at the valve) and what the two-mass model does with it."""

    rate: float  # N/mm
    preload: float  # N
    peak_spring: float  # N: rate x the valve's full lift + preload
    float_speed_rpm: float  # inf: none up to the search's top
    bounce_speed_rpm: float
    search_top_rpm: float
    seating_velocity: float  # m/s at the case speed
    bounce_height_mm: float  # at the case speed
    least_event_force: float  # N: the cam contact over the valve event at the case speed
    least_train_force: float  # N: the train on the valve over the valve event at the top speed (0: the valve left it)

    @property
    def on_train(self) -> bool:
        """Whether the valve stays on the train over its event at the top speed (its force above
        :data:`_ON_TRAIN` of the peak spring force: not a knife-edge)."""
        return bool(self.least_train_force > _ON_TRAIN * self.peak_spring)

    @property
    def least_speed_rpm(self) -> float:
        """The lower of the float and bounce speeds (the search's top where neither happens below it)."""
        return min(self.float_speed_rpm, self.bounce_speed_rpm, self.search_top_rpm)

    def holds(self, top_rpm: float) -> bool:
        return bool(self.float_speed_rpm >= top_rpm and self.bounce_speed_rpm >= top_rpm and self.on_train)

    def json(self, top_rpm: float) -> dict:
        return {
            "spring_rate_N_per_mm": self.rate,
            "preload_N": self.preload,
            "peak_spring_force_N": self.peak_spring,
            "float_speed_rpm": finite_or_none(self.float_speed_rpm),
            "bounce_speed_rpm": finite_or_none(self.bounce_speed_rpm),
            "seating_velocity_m_per_s": finite_or_none(self.seating_velocity),
            "bounce_height_mm": self.bounce_height_mm,
            "least_event_contact_force_N": finite_or_none(self.least_event_force),
            "least_train_force_N": finite_or_none(self.least_train_force),
            "holds": self.holds(top_rpm),
        }


@dataclass(frozen=True)
class ValveSpringSizing:
    """:func:`size_valve_spring`'s answer: the proposed valve spring, the closed-form start it was searched from,
    the case's own spring, and ``check``'s verdict on the proposal as written."""

    case_name: str
    speed_rpm: float
    margin: float
    top_speed_rpm: float  # margin x speed: float and bounce must not come below it
    min_rate: float  # N/mm at the valve
    ratio: float
    lash_mm: float
    equivalent_mass_kg: float
    valve_lift_mm: float  # the cam's full lift at the valve less the lash: the spring's travel
    closed_form: ValveSpringDesign
    closed_form_jump_rpm: float  # the equivalent follower's kinematic jump speed with the closed-form spring
    chosen: ValveSpringDesign
    current: ValveSpringDesign
    checks: tuple[Check, ...]  # check's on the proposal as written
    rounds: tuple[tuple[float, float], ...]  # (preload N, least of float and bounce rpm) the search judged
    warnings: tuple[str, ...] = ()
    part: SpringDesign | None = None  # with a [spring] part: the part check designs for the proposal
    spring_model: str = "none"  # the spring whose mass is in the sizing's dynamics ([spring] model)
    spring_mass_kg: float = 0.0  # its mass: the proposed part's (the case's own spring's before the first round)
    part_rounds: tuple[tuple[float, float], ...] = ()  # (spring mass kg, preload N) of the fixed point on the part

    @property
    def verdict(self) -> str:
        return "pass" if all(c.ok for c in self.checks) else "fail"

    def json(self) -> dict:
        top = self.top_speed_rpm
        chosen = self.chosen.json(top)
        return {
            "case": self.case_name,
            "follower": "translating",
            "model": "valvetrain",
            "max_speed_rpm": self.speed_rpm,
            "margin": self.margin,
            "sized_to_rpm": top,
            "min_rate": self.min_rate,
            "units": {"rate": "N/mm", "preload": "N", "spring": "N", "lift": "mm"},
            **chosen,
            "jump_speed_rpm": chosen["float_speed_rpm"],  # what check judges the margin on: the float speed
            "current": self.current.json(top),
            "method": METHOD,
            "warnings": list(self.warnings),
            "buildable": False,
            "bound": False,
            **({} if self.part is None else self._part_json()),
            "valvetrain": {
                "ratio": self.ratio,
                "lash_mm": self.lash_mm,
                "equivalent_mass_kg": self.equivalent_mass_kg,
                "valve_lift_mm": self.valve_lift_mm,
                "closed_form": self.closed_form.json(top)
                | {"equivalent_jump_speed_rpm": finite_or_none(self.closed_form_jump_rpm)},
                "search": [{"preload_N": f0, "least_speed_rpm": w} for f0, w in self.rounds],
                "check": {"verdict": self.verdict, "checks": [c.json() for c in self.checks]},
            },
        }

    def _part_json(self) -> dict:
        """With a ``[spring]`` part: the spring whose mass is in the sizing, the part, and the fixed point's rounds."""
        assert self.part is not None  # the caller's
        rounds = [{"spring_mass_kg": m, "preload_N": f0} for m, f0 in self.part_rounds]
        return {
            "spring_model": self.spring_model,
            "spring_mass_kg": self.spring_mass_kg,
            "part": self.part.json(),
            "part_rounds": rounds,
        }


def _least_train_force(case: Case, omega: float) -> float:
    """The train's least force on the valve over its event at ``omega`` (rad/s), N (0 where the valve leaves the
    train: tossed off it as the lash closes, or running ahead of it); NaN where the valve never lifts."""
    assert case.valvetrain is not None  # the caller's
    return dyn.ValvePoint(case.motion, case.valvetrain, omega).least_train_force


def _judge(case: Case, rate: float, preload: float, valve_lift_mm: float) -> ValveSpringDesign:
    """The case with this valve spring and what the two-mass model does with it: at the case speed, the float and
    bounce searches ``check`` runs, and whether the valve stays on the train at the top speed."""
    sized = with_valvetrain_keys(case, dynamics={"spring_rate": rate, "preload": preload})
    res: ValvetrainResult = analyze_valvetrain(sized, case.speed_rpm * RPM, case.limits.speed_margin)
    top = case.limits.speed_margin * case.speed_rpm * RPM
    return ValveSpringDesign(
        rate,
        preload,
        rate * valve_lift_mm + preload,
        res.float_speed_rpm,
        res.bounce_speed_rpm,
        res.search_top_rpm,
        res.seating_velocity,
        res.response.bounce_height_mm,
        res.response.least_event_force,
        _least_train_force(sized, top),
    )


def _least_preload_on_train(case: Case, rate: float, start: float, valve_lift_mm: float, ceiling: float) -> float:
    """The least preload (N, to :data:`_TRAIN_WIDTH`) at or above ``start`` with which the valve stays on the train
    over its event at the top speed (:attr:`ValveSpringDesign.on_train`): doubled from ``start`` until it holds,
    then bisected (the train's least force grows with the preload); ``ceiling`` where none up to it holds."""
    top = case.limits.speed_margin * case.speed_rpm * RPM

    def holds(f0: float) -> bool:
        sized = with_valvetrain_keys(case, dynamics={"spring_rate": rate, "preload": f0})
        return _least_train_force(sized, top) > _ON_TRAIN * (rate * valve_lift_mm + f0)

    lo, hi = math.nan, min(start, ceiling)
    for _ in range(_TRAIN_ROUNDS):
        if holds(hi):
            break
        if hi >= ceiling:
            return ceiling
        lo, hi = hi, min(2.0 * hi + rate * valve_lift_mm, ceiling)
    if math.isnan(lo):
        return hi
    for _ in range(_TRAIN_ROUNDS):
        if hi - lo <= _TRAIN_WIDTH * hi:
            break
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if holds(mid) else (mid, hi)
    return hi


def size_valve_spring(
    case: Case,
    max_speed_rpm: float | None = None,
    margin: float | None = None,
    min_rate: float | None = None,
    progress: Progress | None = None,
) -> ValveSpringSizing:
    """The valve spring of a ``[valvetrain]`` case (rate and preload at the valve) with the least preload for its
    rate whose float and bounce speeds are at least ``margin`` x ``max_speed_rpm`` (defaults: the case's speed and
    speed_margin); ``min_rate`` (N/mm at the valve) bounds the rate from below (default: the case's own rate; 0
    lets the closed form choose, a constant-force spring where the rate only costs peak force). With a ``[spring]``
    part, the part designed for the proposal and its mass on the valve (:func:`_size_with_part`). The proposal is
    judged by ``check`` as written (the part designed afresh for it). See the module's docstring for the method.
    ``progress``: a phase per search (one per part round) and one for the check."""
    assert case.valvetrain is not None  # the caller's: a [valvetrain] case
    speed = float(case.speed_rpm if max_speed_rpm is None else max_speed_rpm)
    margin = float(case.limits.speed_margin if margin is None else margin)
    own_rate = float(case.spec.dynamics.spring_rate or 0.0)
    min_rate = own_rate if min_rate is None else float(min_rate)
    check_sizing(max_speed_rpm, margin, min_rate)
    # the case is judged at its speed with the sizing's top: check at max_speed_rpm with the margin asked
    spec = case.spec.model_copy(
        update={
            "dynamics": case.spec.dynamics.model_copy(update={"speed": speed}),
            "limits": case.spec.limits.model_copy(update={"speed_margin": margin}),
        }
    )
    case = replace(case, spec=spec)
    if case.spec.spring is None:
        with phase(progress, _SEARCH):
            sizing = _size(case, min_rate)
    else:
        sizing = _size_with_part(case, min_rate, progress)
    chosen = sizing.chosen
    unresolved = replace(case, spring=None)  # check designs the [spring] part for the proposal, as for the file
    as_written = with_valvetrain_keys(unresolved, dynamics={"spring_rate": chosen.rate, "preload": chosen.preload})
    with phase(progress, "the proposal's check"):
        report = run_check(as_written)
    failing = [
        f"check {c.name} fails on the proposal as written ({c.value_text()} {c.unit}, not {c.sense} {c.limit:g}): "
        "the spring does not set it"
        for c in report.checks
        if not c.ok and c.name != "speed_margin"
    ]
    current = sizing.current
    if current.holds(sizing.top_speed_rpm) and current.peak_spring < chosen.peak_spring:
        failing.insert(0, f"the case's own spring holds with a lower peak force ({current.peak_spring:.4g} N): keep it")
    return replace(sizing, checks=report.checks, warnings=sizing.warnings + tuple(failing))


def _search_round(i: int, mass_kg: float) -> str:
    """The progress phase of the ``i``-th preload search, sized with the spring part's mass ``mass_kg``."""
    return f"{_SEARCH}, round {i} (spring mass {1000.0 * mass_kg:.4g} g)"


def _size_with_part(case: Case, min_rate: float, progress: Progress | None = None) -> ValveSpringSizing:
    """:func:`_size` with a ``[spring]`` part: its mass (a third on the valve, or its surge chain) depends on the
    rate and preload sized. A fixed point: sized with the case's own part's mass first, then with the mass of the
    part designed for the last proposal (:func:`camdyn.design.spring.design_case_spring`, as ``check`` designs it),
    until that part's mass is the one sized with, or its change moves the preload by less than
    :data:`_PART_CLOSE`. The parts come in wire sizes and coil counts, so the masses may cycle instead (a part sized
    with one mass asks for another, whose sizing asks for the first): then the proposal is one of the cycle sized
    with at least its own part's mass (:func:`_cycle_proposal`). The part reported is always the one designed for
    the proposal, as ``check`` designs it. The case's own spring is judged with its own part."""
    own = resolve_spring(case)  # the case's own part: the first round's mass, and its spring's judge
    assert own.spring is not None and case.spec.spring is not None  # resolved, of a case with a [spring] table
    mass, model = own.spring.mass_kg, case.spec.spring.model
    with phase(progress, _search_round(1, mass)):
        sizing = first = _size(own, min_rate)
    searched = {mass: sizing}  # each search by the spring mass it was sized with, in order
    designed: dict[float, SpringDesign] = {}  # the part designed for each search's proposal, by the same mass
    rounds: list[tuple[float, float]] = []
    warnings: list[str] = []
    for _ in range(_PART_ROUNDS):
        rate, preload = sizing.chosen.rate, sizing.chosen.preload
        part = designed[mass] = design_case_spring(case, rate=rate, preload=preload)
        rounds.append((mass, preload))
        moved = abs(preload - rounds[-2][1]) if len(rounds) > 1 else math.inf
        if part.spring.mass == mass or moved <= _PART_CLOSE * preload:
            break
        if part.spring.mass in searched:  # a cycle: its searches are done already
            mass, note = _cycle_proposal(searched, designed, part.spring.mass)
            sizing, part = searched[mass], designed[mass]
            if rounds[-1] != (mass, sizing.chosen.preload):
                rounds.append((mass, sizing.chosen.preload))
            warnings.append(note)
            break
        mass = part.spring.mass
        with phase(progress, _search_round(len(rounds) + 1, mass)):
            sizing = searched[mass] = _size(with_spring_part(case, part), min_rate)
    else:
        part = design_case_spring(case, rate=sizing.chosen.rate, preload=sizing.chosen.preload)  # the proposal's
        rounds.append((mass, sizing.chosen.preload))
        warnings.append(
            f"the spring part's mass did not settle in {_PART_ROUNDS} rounds (last: {1e3 * mass:.4g} g, preload "
            f"{sizing.chosen.preload:g} N, its part {1e3 * part.spring.mass:.4g} g): check judges the proposal with "
            "its own part"
        )
    return replace(
        sizing,
        current=first.current,
        warnings=sizing.warnings + tuple(warnings),
        part=part,
        spring_model=model,
        spring_mass_kg=part.spring.mass,
        part_rounds=tuple(rounds),
    )


def _cycle_proposal(
    searched: dict[float, ValveSpringSizing], designed: dict[float, SpringDesign], start: float
) -> tuple[float, str]:
    """The proposal of a cycle of the part's masses: the searches from the one sized with ``start`` (kg) on, each
    sized with a mass whose proposal's part (``designed``) has another of the cycle. Of those sized with at least
    their own part's mass (the part lighter than what the search carried: it floats and bounces later, not sooner;
    the heaviest search is one), the least peak spring force. Returns the mass it was sized with and the note that
    says so."""
    masses = list(searched)
    cycle = masses[masses.index(start) :]
    safe = (m for m in cycle if designed[m].spring.mass <= m)
    pick = min(safe, key=lambda m: searched[m].chosen.peak_spring)
    grams = [f"{1e3 * m:.4g} g" for m in sorted(cycle)]
    note = (
        f"the spring part's mass cycles between {', '.join(grams[:-1])} and {grams[-1]} (the parts come in wire "
        f"sizes and coil counts: no fixed point): the proposal is the one sized with {1e3 * pick:.4g} g, its own "
        f"part lighter ({1e3 * designed[pick].spring.mass:.4g} g)"
    )
    return pick, note


def _size(case: Case, min_rate: float) -> ValveSpringSizing:
    """The sizing's search on ``case`` (its speed and margin the sizing's; a ``[spring]`` part's mass, if any,
    held as the case carries it), not yet judged by ``check`` (``checks`` empty)."""
    vt = case.valvetrain
    assert vt is not None  # the caller's: a [valvetrain] case
    speed, margin = case.speed_rpm, case.limits.speed_margin
    own_rate = float(case.spec.dynamics.spring_rate or 0.0)
    r, lash_mm = float(vt.ratio), float(vt.lash) / M_PER_MM
    top = margin * speed
    target, need = top * (1.0 + HEADROOM), top * (1.0 + 0.5 * HEADROOM)

    # the closed form: the equivalent follower's least peak force at every speed up to the target
    p, grid = build_problem(case, speed, margin * (1.0 + HEADROOM), min_rate * r * r)
    p = replace(p, f0_lo=-math.inf)  # [limits] min_preload is the valve's seat load: applied at the valve below
    k_eq, p_eq, _ = lp(p, grid, p.damping(0.0))
    valve_lift_mm = (r * p.s_max - float(vt.lash)) / M_PER_MM
    rate = written(max(p.kind.rate_from_si(k_eq) / r**2, min_rate))
    seat_load = case.limits.min_preload if case.limits.min_preload is not None else 0.0
    f0_closed = max(p_eq / r + rate * lash_mm, seat_load, 0.0)
    # the most the train lifts the valve under (a case refuses more): the search's top, as written
    train_rate = float(vt.train.train_stiffness) * M_PER_MM  # N/mm at the valve; inf: a rigid train
    ceiling = written(max_lifting_preload(valve_stroke_mm(case.motion, vt), train_rate, rate), down=True)
    closed = _judge(case, rate, written(f0_closed, up=True), valve_lift_mm)
    w_eq = _equivalent_jump(case, rate, closed.preload)

    # the two-mass search on the preload: (least speed)^2 is near affine in it
    judged: dict[float, ValveSpringDesign] = {closed.preload: closed}

    def judge(f0: float) -> ValveSpringDesign:
        if f0 not in judged:
            judged[f0] = _judge(case, rate, f0, valve_lift_mm)
        return judged[f0]

    current = _judge(case, own_rate, float(case.spec.dynamics.preload or 0.0), valve_lift_mm)
    same_rate = rate == own_rate  # the case's own spring is then a point of the search: a secant seed
    if same_rate:
        judged.setdefault(current.preload, current)
    # the valve on the train at the top speed: below this preload it is tossed off as the lash closes
    floor = max(
        written(_least_preload_on_train(case, rate, closed.preload, valve_lift_mm, ceiling), up=True), seat_load
    )
    floor = min(floor, ceiling)
    lo: ValveSpringDesign | None = None  # the highest preload that fails
    hi = current if same_rate and current.least_speed_rpm >= need and current.on_train else None  # least that holds
    prev, d = (current if same_rate else None), (closed if floor <= closed.preload else judge(floor))
    for _ in range(_ROUNDS):
        w = d.least_speed_rpm
        if w >= need and d.on_train:
            hi = d if hi is None or d.preload < hi.preload else hi
            if w <= target * (1.0 + _CLOSE):
                break
        else:
            lo = d if lo is None or d.preload > lo.preload else lo
        f0 = min(written(_next_preload(d, prev, lo, hi, target, floor), up=True), ceiling)
        if f0 in judged:  # the written digits cannot get closer
            if hi is not None or f0 >= ceiling:  # or no preload the train lifts the valve under holds
                break
            f0 = min(written(f0 * 1.001, up=True), ceiling)
        prev, d = d, judge(f0)
    rounds = tuple((f0, dd.least_speed_rpm) for f0, dd in judged.items() if dd.rate == rate)
    warnings: list[str] = []
    if hi is None:  # none holds: the nearest judged, never one the case's own spring comes nearer than
        how = (
            f"up to {ceiling:g} N (the most under which the train lifts the valve half its stroke)"
            if d.preload >= ceiling
            else f"in {_ROUNDS} rounds"
        )
        near = max((dd for dd in judged.values() if dd.rate == rate), key=lambda dd: dd.least_speed_rpm)
        hi = current if current.least_speed_rpm >= near.least_speed_rpm else near
        what = "the case's own spring comes nearest: keep it" if hi is current else "the proposal does not hold"
        warnings.append(
            f"no preload found {how} whose float and bounce speeds reach {need:.5g} rpm with the valve on the train "
            f"(the nearest: {hi.preload:g} N, {hi.least_speed_rpm:.5g} rpm): {what}"
        )
    chosen = hi
    if min_rate > 0.0 and min_rate == own_rate:
        warnings.append(
            f"the rate is the case's own ({own_rate:g} N/mm): pass --min-rate for another least rate (0: the closed "
            "form's choice)"
        )
    return ValveSpringSizing(
        case.name,
        speed,
        margin,
        top,
        min_rate,
        r,
        lash_mm,
        float(vt.equivalent_mass),
        valve_lift_mm,
        closed,
        w_eq,
        chosen,
        current,
        (),
        rounds,
        tuple(warnings),
    )


def _equivalent_jump(case: Case, rate: float, preload: float) -> float:
    """The equivalent follower's kinematic jump speed (rpm) with this valve spring (the closed form's own check)."""
    sized = with_valvetrain_keys(case, dynamics={"spring_rate": rate, "preload": preload})
    return dyn.kinematic_jump_speed(sized.motion, sized.model)[0] / RPM


def _next_preload(
    d: ValveSpringDesign,
    prev: ValveSpringDesign | None,
    lo: ValveSpringDesign | None,
    hi: ValveSpringDesign | None,
    target: float,
    floor: float,
) -> float:
    """The next preload to judge: the secant on (least speed)^2 through the last two judged (the first step: the
    force at the nose, rate x lift + preload, growing as speed^2, at most doubled), bisection of the bracket where
    the step leaves it."""
    w = d.least_speed_rpm
    if prev is not None and prev.least_speed_rpm != w:
        f0 = d.preload + (target**2 - w**2) * (d.preload - prev.preload) / (w**2 - prev.least_speed_rpm**2)
    else:
        f0 = d.preload + d.peak_spring * min((target / w) ** 2 - 1.0, 1.0)
    if lo is not None and hi is not None and not lo.preload < f0 < hi.preload:
        f0 = 0.5 * (lo.preload + hi.preload)
    elif lo is not None and f0 <= lo.preload:
        f0 = lo.preload + min(lo.peak_spring, 2.0 * (lo.preload - f0) + 1e-3 * lo.peak_spring)
    elif hi is not None and f0 >= hi.preload:
        f0 = 0.5 * (max(floor, 0.0) + hi.preload)
    return max(f0, floor, 0.0)
