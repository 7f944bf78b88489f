"""The tolerance study of a valvetrain: Monte Carlo over ``[tolerances]`` with the two-mass model per sample.

Keys: the valve spring (``spring_rate``, ``preload``, at the valve), the cam contact's ``train_stiffness``, the
``speed``, and the valvetrain's own: ``lash``, ``cam_side_mass``, ``valve_mass``, ``valvetrain_stiffness``
(the train between the two masses). The ground cam is the nominal one (its ramps included): a lash off nominal
is what the assembly sets, and the ramps take it up where they reach it.

Per sample (:class:`camdyn.model.dynamics.ValvePoint`: the exact linear solution where every contact stays closed,
else :func:`camdyn.model.dynamics.valvetrain_response`, event driven on diffrax; one sample at a time):
at the sample's speed whether the valve floats and bounces, its seating velocity, bounce height and the least
cam-contact force over the valve event; and its float and bounce speeds, searched locally about the nominal
design's (which ``check``'s global searches give): from the nominal speed in steps of 10 % until the valve floats
(bounces) on one side and not on the other, then bisected to 1 %. A sample whose float window lies far below the
nominal one would be missed by that local search, and bounce, a threshold on a re-lift that can come and go
with speed near its onset, may start in a window below the crossing found (``check``'s global search finds the
first); the per-sample verdict at its speed is exact. With a ``[spring]`` part the case's valve spring is in every
sample as ``check`` carries it: its own mass on the valve (its lumped third, or its surge chain; a sample's
``valve_mass`` is the case file's, without it) and its coil bind in the nominal ``check``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..._core.errors import InputError
from ..._core.progress import Progress, counter
from ..._core.units import RPM, tolerance_unit
from ...model import dynamics as dyn
from ...model.case import Case, with_valvetrain_keys
from ...model.valvetrain import ValvetrainModel
from ..parts import resolve_spring
from ..valvetrain import analyze_valvetrain, spring_notes
from ._interval import CONFIDENCE, exact_interval
from ._sampling import case_tolerances, spreads
from ._sensitivity import variance_shares
from ._study import describe

VALVE_KEYS = (
    "spring_rate",
    "preload",
    "train_stiffness",
    "speed",
    "lash",
    "cam_side_mass",
    "valve_mass",
    "valvetrain_stiffness",
)
_UNITS = ("N_per_mm", "N", "N_per_mm", "rpm", "mm", "kg", "kg", "N_per_mm")
CSV_COLUMNS = (
    "sample",
    *(f"{k}_{u}" for k, u in zip(VALVE_KEYS, _UNITS, strict=True)),
    "least_contact_force_N",
    "float_speed_rpm",
    "bounce_speed_rpm",
    "seating_velocity_m_per_s",
    "bounce_height_mm",
    "floated",
    "bounced",
)
MAX_VALVETRAIN_SAMPLES = 5000  # the two-mass model runs per sample, about a second each with the searches
DEFAULT_VALVETRAIN_SAMPLES = 50
_STEP, _WIDTH = 1.1, 0.01  # the local speed searches: bracketing factor, relative width
_WORST = 3


@dataclass(frozen=True)
class ValveToleranceResult:
    """A valvetrain's Monte Carlo tolerance study: per sample its parameters (case-file units) and what the
    two-mass model does."""

    case: str
    seed: int
    speed_rpm: float
    params: dict[str, np.ndarray]  # VALVE_KEYS -> (n,)
    least_force: np.ndarray  # (n,) N: the cam contact over the valve event at the sample's speed (0: floats)
    floated: np.ndarray  # (n,) bool, at the sample's speed
    bounced: np.ndarray
    seating_velocity: np.ndarray  # (n,) m/s
    bounce_height: np.ndarray  # (n,) mm
    float_speed_rpm: np.ndarray  # (n,) inf: none within the local search
    bounce_speed_rpm: np.ndarray
    tolerances: dict[str, dict]
    nominal_float_speed_rpm: float
    nominal_bounce_speed_rpm: float
    shares: dict[str, float] = field(default_factory=dict)  # first-order share of the least speed's variance
    notes: tuple[str, ...] = ()  # what the study carries beyond the keys (a [spring] part's mass)
    confidence: ClassVar[float] = CONFIDENCE  # of the intervals

    @property
    def samples(self) -> int:
        return self.least_force.size

    def probability(self, hit: np.ndarray) -> tuple[float, tuple[float, float]]:
        """The fraction of samples where ``hit`` and its Clopper-Pearson interval at :attr:`confidence`."""
        return float(hit.mean()), exact_interval(int(hit.sum()), hit.size)

    @property
    def least_speed_rpm(self) -> np.ndarray:
        return np.minimum(self.float_speed_rpm, self.bounce_speed_rpm)

    @property
    def worst(self) -> tuple[int, ...]:
        """The samples with the lowest of their float and bounce speeds, lowest first."""
        return tuple(int(i) for i in np.argsort(self.least_speed_rpm, kind="stable")[:_WORST])

    @staticmethod
    def low(values: np.ndarray) -> dict[str, float]:
        q = np.percentile(values, [1, 5, 50], method="inverted_cdf")
        return {"p1": float(q[0]), "p5": float(q[1]), "p50": float(q[2])}

    @staticmethod
    def high(values: np.ndarray) -> dict[str, float]:
        ok = values[np.isfinite(values)]
        if not ok.size:
            return {"p50": math.nan, "p95": math.nan, "p99": math.nan}
        q = np.percentile(ok, [50, 95, 99], method="inverted_cdf")
        return {"p50": float(q[0]), "p95": float(q[1]), "p99": float(q[2])}

    def json(self) -> dict:
        """``tolerance --json``'s ``valvetrain``."""
        p_float, ci_float = self.probability(self.floated)
        p_bounce, ci_bounce = self.probability(self.bounced)
        return {
            "probability_of_float": p_float,
            "float_confidence_interval": list(ci_float),
            "probability_of_bounce": p_bounce,
            "bounce_confidence_interval": list(ci_bounce),
            "float_speed_rpm": self.low(self.float_speed_rpm),
            "bounce_speed_rpm": self.low(self.bounce_speed_rpm),
            "seating_velocity_m_per_s": self.high(self.seating_velocity),
            "bounce_height_mm": self.high(self.bounce_height),
            "nominal_float_speed_rpm": self.nominal_float_speed_rpm,
            "nominal_bounce_speed_rpm": self.nominal_bounce_speed_rpm,
            "shares": self.shares,
            "notes": list(self.notes),
        }

    @property
    def csv(self) -> str:
        """CSV text, one row per sample, columns :data:`CSV_COLUMNS`."""
        lines = [",".join(CSV_COLUMNS)]
        cols = [self.params[k] for k in VALVE_KEYS]
        cols += [self.least_force, self.float_speed_rpm, self.bounce_speed_rpm]
        cols += [self.seating_velocity, self.bounce_height]
        for i in range(self.samples):
            row = ",".join(f"{float(c[i]):.10g}" for c in cols)
            lines.append(f"{i:d},{row},{int(self.floated[i]):d},{int(self.bounced[i]):d}")
        return "\n".join(lines) + "\n"


def _nominal(case: Case) -> dict[str, float]:
    d, v = case.spec.dynamics, case.spec.valvetrain
    assert v is not None and d.spring_rate is not None and d.preload is not None  # a valvetrain case's
    inf = math.inf
    return {
        "spring_rate": float(d.spring_rate),
        "preload": float(d.preload),
        "train_stiffness": inf if d.train_stiffness is None else float(d.train_stiffness),
        "speed": float(d.speed),
        "lash": float(v.lash),
        "cam_side_mass": float(v.cam_side_mass),
        "valve_mass": float(v.valve_mass),
        "valvetrain_stiffness": inf if v.stiffness is None else float(v.stiffness),
    }


def _sample_case(case: Case, vals: dict[str, np.ndarray], i: int) -> Case:
    """The case with sample ``i``'s values (a rigid contact or train stays rigid)."""
    dyn_keys = {"spring_rate": float(vals["spring_rate"][i]), "preload": float(vals["preload"][i])}
    dyn_keys["speed"] = float(vals["speed"][i])
    if math.isfinite(vals["train_stiffness"][i]):
        dyn_keys["train_stiffness"] = float(vals["train_stiffness"][i])
    vt_keys = {k: float(vals[k][i]) for k in ("lash", "cam_side_mass", "valve_mass")}
    if math.isfinite(vals["valvetrain_stiffness"][i]):
        vt_keys["stiffness"] = float(vals["valvetrain_stiffness"][i])
    return with_valvetrain_keys(case, dynamics=dyn_keys, valvetrain=vt_keys)


def _first_speed(hit: Callable[[float], bool], w0: float, w_top: float) -> float:
    """The least speed (rad/s) near ``w0`` where ``hit``: bracketed in steps of :data:`_STEP`, bisected to
    :data:`_WIDTH`; inf where none up to ``w_top``."""
    if hit(w0):
        hi, lo = w0, w0 / _STEP
        while hit(lo):
            hi, lo = lo, lo / _STEP
            if lo < 1e-3 * w0:
                return lo
    else:
        lo, hi = w0, w0 * _STEP
        while not hit(hi):
            lo, hi = hi, hi * _STEP
            if hi > w_top:
                return math.inf
    while hi - lo > _WIDTH * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if hit(mid) else (mid, hi)
    return 0.5 * (lo + hi)


def valvetrain_tolerance_study(
    case: Case, samples: int, seed: int = 0, *, progress: Progress | None = None
) -> ValveToleranceResult:
    """Monte Carlo study of a ``[valvetrain]`` case's ``[tolerances]`` over ``samples`` built valvetrains drawn
    from ``seed`` (see the module's docstring)."""
    if not 1 <= samples <= MAX_VALVETRAIN_SAMPLES:
        raise InputError(
            "--samples",
            f"a valvetrain runs the two-mass model per sample: from 1 to {MAX_VALVETRAIN_SAMPLES}, got {samples}",
        )
    case = resolve_spring(case)  # [spring]: the valve spring's own mass on the valve and its coil bind, as check
    tols = case_tolerances(case)
    nominal = _nominal(case)
    if any(t.key == "train_stiffness" for t in tols) and math.isinf(nominal["train_stiffness"]):
        raise InputError(
            "tolerances.train_stiffness",
            "the cam contact is rigid: remove the key or give [dynamics] train_stiffness",
        )
    spread = spreads(tols, nominal)
    rng = np.random.default_rng(seed)
    vals = {k: nominal[k] + (spread[k].draw(rng, samples) if k in spread else np.zeros(samples)) for k in VALVE_KEYS}
    for key in VALVE_KEYS:
        floor = 0.0 if key in ("lash", "preload") else 1e-300
        if np.any(vals[key] < floor):
            raise InputError(
                f"tolerances.{key}",
                f"the tolerance reaches a value below {floor:g} {tolerance_unit(key, False)} in some samples: give a "
                "smaller one",
            )
    omega = case.speed_rpm * RPM
    nominal_res = analyze_valvetrain(case, omega, case.limits.speed_margin)
    w_top = nominal_res.search_top_rpm * RPM
    w_float0 = min(nominal_res.float_speed_rpm, nominal_res.search_top_rpm) * RPM
    w_bounce0 = min(nominal_res.bounce_speed_rpm, nominal_res.search_top_rpm) * RPM
    n = samples
    least, seat_v, height = np.zeros(n), np.zeros(n), np.zeros(n)
    floated, bounced = np.zeros(n, bool), np.zeros(n, bool)
    w_float, w_bounce = np.zeros(n), np.zeros(n)
    tick = counter(progress, "built valvetrains (two-mass model, float and bounce searches)", n)
    for i in range(n):
        sample = _sample_case(case, vals, i)
        vt = sample.valvetrain
        assert vt is not None  # with_valvetrain_keys rebuilds it
        memo: dict[float, dyn.ValvePoint] = {}

        def at(w: float, vt: ValvetrainModel = vt, memo: dict = memo, floats: bool = False) -> dyn.ValvePoint:
            if w not in memo:
                memo[w] = dyn.ValvePoint(case.motion, vt, w, floats=floats)
            return memo[w]

        here = at(float(vals["speed"][i]) * RPM)
        least[i] = 0.0 if here.floated else here.least_event_force
        floated[i], bounced[i] = here.floated, here.bounced
        seat_v[i], height[i] = here.seating_velocity, here.bounce_height_mm
        w_float[i] = _first_speed(lambda w, at=at: at(w).floated, w_float0, w_top) / RPM
        # past the sample's float speed the fast path follows the float through (as in check)
        past = w_float[i] * RPM
        w_bounce[i] = _first_speed(lambda w, at=at, past=past: at(w, floats=w > past).bounced, w_bounce0, w_top) / RPM
        tick(1)
    margin = np.minimum(w_float, w_bounce) / case.speed_rpm
    given = [t.key for t in tols]
    shares = variance_shares(margin, {k: vals[k] - nominal[k] for k in given}) if given else {}
    return ValveToleranceResult(
        case=case.name,
        seed=seed,
        speed_rpm=float(case.speed_rpm),
        params=vals,
        least_force=least,
        floated=floated,
        bounced=bounced,
        seating_velocity=seat_v,
        bounce_height=height,
        float_speed_rpm=w_float,
        bounce_speed_rpm=w_bounce,
        tolerances={t.key: describe(t, spread[t.key], False) for t in tols},
        nominal_float_speed_rpm=nominal_res.float_speed_rpm,
        nominal_bounce_speed_rpm=nominal_res.bounce_speed_rpm,
        shares=shares,
        notes=spring_notes(case, "in every sample"),
    )
