"""``camdyn optimize``: reshape every rise and return of a segment case, keeping its timing, lifts, dwells,
follower, spring and limits, for the objective the designer names (:mod:`._objectives`). The margins are
differentiated through the frequency-domain steady state by JAX (never by finite differences) and each step is
a linear program (:mod:`._slp`); the answer is then checked by ``check``'s own models, the time-domain
diffrax model included. A valvetrain keeps its ramps and its valve's timing: only the flanks between the ramps
are reshaped (:func:`._shape.flank_space`), on the valve event's single follower (the valve on the compliant
train, :func:`camdyn.model.valvetrain.event_follower`, from rest on its seat where it lifts off:
:meth:`._rows.RowsKernel.in_contact`), and the answer is judged by the
two-mass model's float and bounce speeds and seating velocity (``check``'s), none of which may come out worse."""

from __future__ import annotations

import functools
import math
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

import numpy as np

from ..._core import sharding
from ..._core.errors import InputError, NumericalError
from ..._core.jit import in_background
from ..._core.limits import check_min_force
from ..._core.progress import Progress, phase
from ..._core.results import finite_or_none
from ..._core.units import RPM
from ...model.case import Case, build_case
from ...model.dynamics import least_static_force, linear_min_force
from ...model.motion import evaluate
from ...model.valvetrain import event_follower, lift_off
from ...schema import CaseSpec, require_tolerances
from ...schema.dynamics import dynamics_keys
from .._check import Check
from ..checks import CheckReport, run_check
from ..parts import resolve_spring
from ._metrics import (
    MARGIN_OF_PRELOAD,
    Metrics,
    default_margin,
    floor_rpm,
    follower_margin_speed,
    margin_speed,
    metrics,
    search_top,
)
from ._objectives import (
    BETTER,
    CLEAR,
    jump_speed,
    least_slack,
    margin_speed_of_fit,
    peak_spring_force_floor,
    spring_force,
    vibration,
)
from ._result import Optimization
from ._rows import Rows
from ._shape import N_CONTROL, ShapeSpace, flank_space, shape_space
from ._valvetrain import ValveFacts, seating_rows, valve_refusals
from ._verification import (
    RobustClaim,
    Verification,
    VerifiedSpeed,
    unverified,
    verify,
    verify_valvetrain,
)

OBJECTIVES = ("jump-speed", "vibration", "spring-force")
ROBUST_SEPARATION = 1e-3  # --robust: the claim is the speed up to which P(separation) stays at or below this
ROBUST_SAMPLES = 4000  # built cams drawn for it (4 below the 1e-3 quantile)
_VERIFIED = 3  # the time-domain model checks this many of the force's dips below the claim, and the claim


def _document(
    case: Case, space: ShapeSpace, z, objective: str, name: str | None, source: str | None, dynamics: dict | None = None
) -> dict:
    """The case file of the optimized motion: the original with its segments (and spring, if freed) replaced;
    ``source``: the original's path relative to where the new file goes."""
    doc = case.spec.model_dump(exclude_unset=True, exclude_none=True)
    if source:
        doc["optimized_from"] = source
    doc["name"] = name or f"{case.name}-optimized"
    said = case.spec.description.strip().rstrip(".")
    what = "Rises and returns" if space.control_matrix is None else "Flanks between the ramps"
    doc["description"] = (f"{said}. " if said else "") + f"{what} reshaped by camdyn optimize ({objective})."
    doc["motion"] = {"segments": space.segments(z)}
    if dynamics:
        doc["dynamics"] = doc["dynamics"] | dynamics
    return doc


def _dips(case: Case, w_claim: float, count: int) -> list[float]:
    """The speeds (rad/s) of the ``count`` lowest local minima of the frequency-domain least force over speed
    below ``w_claim``: where a margin is thinnest, which a few evenly spread speeds would miss."""
    speeds = np.linspace(w_claim / 1000.0, w_claim, 1000)
    f = np.asarray(linear_min_force(case.motion, case.model, speeds))
    inner = np.nonzero((f[1:-1] <= f[:-2]) & (f[1:-1] <= f[2:]))[0] + 1
    return sorted(float(speeds[i]) for i in inner[np.argsort(f[inner])][:count])


def _motion_kept(new: Case, space: ShapeSpace) -> list[str]:
    """Where a reshaped segment leaves its lift's range or reverses, on a 0.01 deg grid (the control points'
    order rules it out; this is the written file's own proof)."""
    theta = np.radians(np.arange(0.0, 360.0, 0.01))
    sv = np.asarray(evaluate(new.motion, theta))
    out, start, base = [], 0.0, 0.0
    for i, spec in enumerate(space.specs):
        inside = (theta >= math.radians(start)) & (theta < math.radians(spec.end))
        if i in space.moving and inside.any():
            lift = spec.lift * space.to_unit
            lo, hi = sorted((base, base + lift))
            s, v = sv[0, inside], sv[1, inside] * math.copysign(1.0, lift)
            tol = 1e-9 * abs(lift)
            if s.min() < lo - tol or s.max() > hi + tol:
                out.append(
                    f"segment {i + 1} leaves its range ({s.min() / space.to_unit:.6g} to {s.max() / space.to_unit:.6g})"
                )
            if v.min() < -tol:
                out.append(f"segment {i + 1} reverses (velocity {v.min() / space.to_unit:.3g} against its lift)")
        start, base = spec.end, base + spec.lift * space.to_unit
    return out


def _refusals(
    objective: str,
    before: CheckReport,
    after: CheckReport,
    b: Metrics,
    a: Metrics,
    kept: list[str],
    verification: Verification,
) -> list[str]:
    """Why the answer must not be written: no better than the input on the objective, a check the input passed
    failing, the motion leaving its range, or the time-domain model finding the margin broken."""
    out = []
    worse = {
        "jump-speed": a.margin_speed_rpm <= b.margin_speed_rpm * (1.0 + BETTER),
        "vibration": a.residual_vibration >= b.residual_vibration * (1.0 - BETTER),
        "spring-force": a.peak_spring_force >= b.peak_spring_force * (1.0 - BETTER),
    }[objective]
    if worse:
        what = {
            "jump-speed": "the speed holding the force margin",
            "vibration": "the residual vibration",
            "spring-force": "the peak spring force",
        }
        out.append(f"no better on {objective}: {what[objective]} would go {_pair(objective, b, a)}")
    elif objective == "jump-speed" and a.jump_speed_rpm < b.jump_speed_rpm:  # the margin held faster, the jump not
        out.append(
            f"worse on jump-speed: the dynamic jump speed would fall {b.jump_speed_rpm:.4g} -> "
            f"{a.jump_speed_rpm:.4g} rpm (the speed holding the force margin would go {_pair(objective, b, a)})"
        )
    out += _broken_checks(before, after)
    out += kept
    out += [f"the time-domain model finds the margin broken at {rpm:.1f} rpm" for rpm in verification.broken_at_rpm]
    return out


def _broken_checks(before: CheckReport, after: CheckReport) -> list[str]:
    """The checks the input passed that the answer would fail, and those it failed that the answer would fail by
    more (never worse than what the user gave)."""
    was = {c.name: c for c in before.checks}
    out = []
    for c in after.checks:
        b = was.get(c.name)
        if b is None or c.ok:
            continue
        if b.ok:
            out.append(
                f"check {c.name} passed before and would fail ({c.value_text(6)} against {c.limit:.6g} {c.unit})"
            )
        elif _further(b, c):
            out.append(
                f"check {c.name} failed before and would fail by more ({b.value_text(6)} -> {c.value_text(6)} against "
                f"{c.limit:.6g} {c.unit})"
            )
    return out


def _further(before: Check, after: Check) -> bool:
    """Whether the failing ``after`` is further from its limit than the failing ``before`` (None: unbounded, worst
    for an upper limit)."""
    if after.sense == "<=":
        return before.value is not None and (after.value is None or after.value > before.value)
    return after.value is not None and before.value is not None and after.value < before.value


def _pair(objective: str, b: Metrics, a: Metrics) -> str:
    name = {"jump-speed": "margin_speed_rpm", "vibration": "residual_vibration", "spring-force": "peak_spring_force"}[
        objective
    ]
    return f"{getattr(b, name):.4g} -> {getattr(a, name):.4g}"


def _robust_claim(case: Case, progress: Progress | None) -> RobustClaim:
    """The speed up to which P(separation) <= :data:`ROBUST_SEPARATION` over the case's ``[tolerances]``: that
    quantile of the built cams' jump speeds (the tolerance study's kernel)."""
    from ..tolerance import tolerance_study  # the sampling kernels load only with --robust

    study = tolerance_study(case, ROBUST_SAMPLES, progress=progress)
    jumps = np.asarray(study.jump_speed_rpm, dtype=float)
    return RobustClaim(
        ROBUST_SEPARATION,
        study.samples,
        finite_or_none(float(np.quantile(jumps, ROBUST_SEPARATION))),
        finite_or_none(study.nominal_jump_speed_rpm),
    )


def optimize_case(
    case: Case,
    objective: str = "jump-speed",
    *,
    speed_rpm: float | None = None,
    progress: Progress | None = None,
    name: str | None = None,
    source: str | None = None,
    min_force: float | None = None,
    control_points: int | None = None,
    robust: bool = False,
) -> Optimization:
    """Reshape ``case``'s rises and returns for ``objective`` (one of :data:`OBJECTIVES`) at ``speed_rpm`` (default:
    the case's); ``name``: the optimized case's (default: the case's with "-optimized"); ``source``: the original
    case file as the new one will find it (its ``optimized_from``); ``min_force``: the force margin to keep at
    every speed held (N; N*m for an arm; default :func:`default_margin`); ``control_points``: per reshaped
    segment (default :data:`N_CONTROL`); ``robust``: claim the speed up to which P(separation) <= 1e-3 over the
    case's ``[tolerances]``.
    The answer's ``refusals`` say why it is not to be written (no better, or a check it would break)."""
    if objective not in OBJECTIVES:
        raise InputError("--objective", f"unknown objective {objective!r}; choose one of {', '.join(OBJECTIVES)}")
    if case.valvetrain is not None and objective != "jump-speed":
        raise InputError(
            "--objective",
            f"{objective}: a valvetrain is optimized for its float speed (jump-speed) only; camdyn size sizes its "
            "valve spring",
        )
    if robust:
        require_tolerances(case.spec.tolerances, kind=case.kind, key="--robust")
    margin = default_margin(case) if min_force is None else float(min_force)
    check_min_force(margin)
    if case.valvetrain is None and objective != "spring-force":  # spring-force may raise the preload
        # the least force at rest: reshaping the rises and returns between the dwells does not change it
        at_rest, f = least_static_force(case.motion, case.model)[0], case.kind.force_unit
        if margin >= at_rest:
            given = "" if min_force is not None else f" (the default, {MARGIN_OF_PRELOAD:.0%} of the preload)"
            raise InputError(
                "--min-force",
                f"a force margin of {margin:.4g} {f}{given} is not held even with the cam turned slowly: the least "
                f"contact force at rest is {at_rest:.4g} {f} (the spring and the external load at the lowest lift), "
                "which reshaping the rises and returns does not change; give a smaller margin, or optimize for "
                "spring-force",
            )
    t0 = time.perf_counter()
    case = resolve_spring(case)  # the model check judges: with the spring's own mass where [spring] gives the part
    control_points = N_CONTROL if control_points is None else control_points
    space = (flank_space if case.valvetrain is not None else shape_space)(case, n_control=control_points)
    rows = Rows(case, space, margin)
    with phase(progress, "the input's check"):  # cold, most of the run: the check's programs compile
        search, searched, stop = None, None, threading.Event()
        if case.valvetrain is None and objective == "jump-speed":
            # the search starts from the margin speed of the input's fit, and runs beside the check: its programs and
            # linear programs (mostly outside the interpreter's lock) beside the check's tracing (a first oscillating
            # optimize 23.5 -> 21.2 s); after it, with its programs compiled beside it, where JAX's CPU client
            # cannot run programs from two threads at once
            w_first = 2.0 * case.limits.speed_margin * float(speed_rpm or case.speed_rpm) * RPM
            search = functools.partial(_search_from_fit, rows, w_first, _until(stop, progress))
            if sharding.CPU_THREADS:
                beside = ThreadPoolExecutor(1, thread_name_prefix="camdyn-search")
                searched = beside.submit(search)
                beside.shutdown(wait=False)  # its one thread ends with the search; the answer waits in ``searched``
            else:
                in_background(rows.prepare, "camdyn-rows")
        elif case.valvetrain is None:  # the linear programs' programs compile on the side
            in_background(functools.partial(rows.prepare, objective == "spring-force"), "camdyn-rows")
        try:
            before_check = run_check(case, speed_rpm, store_programs=False)
            before = metrics(case, before_check, margin)
        except BaseException:
            stop.set()  # the error is reported at once, not after the search
            raise
    if case.valvetrain is not None:  # the event's single follower: the train's compliance, the lash taken up
        vt = case.valvetrain
        surrogate, cam_mass = event_follower(vt)
        seat = None if vt.rigid_train else lift_off(vt)  # a rigid train has no ringing
        rows = Rows(
            replace(case, model=surrogate),
            space,
            margin,
            cam_mass=cam_mass,
            cam_load=float(vt.tappet_force),
            lift_off=seat,
            rocker=vt.rocker if seat is not None else None,  # its geometry on the valve's drive (Rows.rocker)
            rocker_ratio=float(vt.ratio),
        )
        rows = replace(rows, seating=seating_rows(rows, before_check, speed_rpm))
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    dynamics: dict = {}
    try:
        found = None if search is None else search() if searched is None else searched.result()
        if found is not None:
            z = found
        elif objective == "jump-speed":
            w0 = before.margin_speed_rpm * RPM
            if case.valvetrain is not None:  # the programs start where the equivalent follower's margin gives out
                w0 = follower_margin_speed(case, margin, search_top(case, before_check))
            if not math.isfinite(w0):
                raise InputError(
                    "case", "the case does not jump within the check's search: there is no jump speed to raise"
                )
            z, _ = jump_speed(rows, w0, progress)
        elif objective == "vibration":
            with phase(progress, "optimize"):
                z = vibration(rows, rpm * RPM)
        else:
            w = case.limits.speed_margin * rpm * RPM * CLEAR
            rates = float(case.model.stiffness) * np.array([0.25, 0.5, 1.0, 2.0])
            floors = peak_spring_force_floor(rows, rates)
            hopeful = floors < before.peak_spring_force * (1.0 - BETTER)
            if not hopeful.any():  # closed form: no program of these rates can come out lighter than the input
                f = case.kind.force_unit
                return _refused(
                    objective,
                    before,
                    case,
                    margin,
                    control_points,
                    t0,
                    f"no spring of the rates tried (0.25 to 2 x the input's) can hold the {margin:.4g} {f} margin "
                    f"with a peak force under the input's {before.peak_spring_force:.4g} {f}: the least is "
                    f"{float(np.min(floors)):.4g} {f} (the least interface force is at most its mean over a "
                    "revolution, k <s> + preload + external force)",
                )
            with phase(progress, "optimize"):
                z, k, f0 = spring_force(rows, w, rates[hopeful])
            keys = dynamics_keys(case.kind)
            dynamics = {
                keys[1]: float(np.round(case.kind.rate_from_si(k), 6)),
                keys[2]: float(math.ceil(f0 * 100.0) / 100.0),
            }
    except NumericalError as err:  # the programs found nothing to write: the input stands
        return _refused(
            objective, before, case, margin, control_points, t0, f"the optimizer found no answer: {err.message}"
        )
    with phase(progress, "the answer's check and time-domain verification"):
        doc = _document(case, space, z, objective, name, source, dynamics)
        new = resolve_spring(build_case(CaseSpec.model_validate(doc), case.source))
        after_check = run_check(new, speed_rpm, store_programs=False)
        after = metrics(new, after_check, margin)
        facts = None
        if case.valvetrain is not None:
            claimed, verification, refusals, facts = _valvetrain_verdict(new, space, before_check, after_check)
        else:
            claimed = after.margin_speed_rpm if objective == "jump-speed" else case.limits.speed_margin * rpm
            checked = [w / RPM for w in _dips(new, claimed * RPM, _VERIFIED)] if not new.model.rigid else []
            candidates = checked + [0.99 * claimed] + ([] if objective == "jump-speed" else [rpm])
            checked = sorted(set(round(v, 1) for v in candidates if round(v, 1) > 0.0))  # a cam at rest: no dynamics
            verification = verify(new, checked, margin)
            refusals = _refusals(
                objective, before_check, after_check, before, after, _motion_kept(new, space), verification
            )
    robust_claim = None
    if robust and not refusals:
        robust_claim = _robust_claim(new, progress)
        claimed = robust_claim.speed_rpm if robust_claim.speed_rpm is not None else math.nan
    return Optimization(
        objective,
        before,
        after,
        new,
        doc,
        claimed,
        verification,
        control_points,
        time.perf_counter() - t0,
        margin,
        tuple(refusals),
        robust_claim,
        facts,
    )


class _Stopped(Exception):
    """The search beside the input's check stopped: the check failed (no one reads its answer)."""


def _until(stop: threading.Event, progress: Progress | None) -> Progress:
    """``progress``, raising :class:`_Stopped` at the search's next trial once ``stop`` is set."""

    def report(phase: str, done: int, total: int) -> None:  # the protocol names its first argument so
        if stop.is_set():
            raise _Stopped
        if progress is not None:
            progress(phase, done, total)

    return report


def _search_from_fit(rows: Rows, w_first: float, progress: Progress | None) -> np.ndarray | None:
    """:func:`._objectives.jump_speed` from the margin speed of the input's fit (:func:`margin_speed_of_fit`), its
    programs compiled first; None where the fit holds at every speed scanned (the check's own margin speed
    decides then)."""
    rows.prepare()
    w0 = margin_speed_of_fit(rows, w_first)
    return None if math.isnan(w0) else jump_speed(rows, w0, progress)[0]


def _valvetrain_verdict(
    new: Case, space: ShapeSpace, before_check: CheckReport, after_check: CheckReport
) -> tuple[float, Verification, list[str], tuple[ValveFacts, ValveFacts]]:
    """A valvetrain's answer judged by the two-mass model: the claim (its float speed, rpm), the verification (the
    model again at 0.99 x the claim and at the case speed: the least cam force over the valve event, and whether it
    floats), the refusals and the facts before and after."""
    facts = ValveFacts.of(before_check), ValveFacts.of(after_check)
    claimed = facts[1].float_speed_rpm
    claimed = math.inf if claimed is None else floor_rpm(claimed)
    speeds = sorted({after_check.speed_rpm} | ({0.99 * claimed} if math.isfinite(claimed) else set()))
    verification = verify_valvetrain(new, speeds, after_check.speed_rpm)
    refusals = valve_refusals(*facts)
    refusals += _broken_checks(before_check, after_check)
    refusals += _motion_kept(new, space)
    refusals += [f"the two-mass model floats or bounces at {rpm:.1f} rpm" for rpm in verification.broken_at_rpm]
    return claimed, verification, refusals, facts


def _refused(
    objective: str, before: Metrics, case: Case, margin: float, control_points: int, t0: float, why: str
) -> Optimization:
    """The input itself, with why nothing better was found."""
    doc = case.spec.model_dump(exclude_unset=True, exclude_none=True)
    return Optimization(
        objective,
        before,
        before,
        case,
        doc,
        math.nan,
        unverified(case),
        control_points,
        time.perf_counter() - t0,
        margin,
        (why,),
    )


__all__ = [
    "MARGIN_OF_PRELOAD",
    "OBJECTIVES",
    "Metrics",
    "Optimization",
    "RobustClaim",
    "Verification",
    "VerifiedSpeed",
    "default_margin",
    "floor_rpm",
    "least_slack",
    "margin_speed",
    "metrics",
    "optimize_case",
    "ValveFacts",
]
