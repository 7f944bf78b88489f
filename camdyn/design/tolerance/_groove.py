"""A form-closed cam's tolerance study: the spread of its crossover impact over the built cams (a groove cam, or
conjugate cams with backlash), or of the least force on either conjugate cam under their preload.

A groove cam cannot jump, so what its tolerances change is how hard the flanks meet the follower where it crosses
the backlash. The samples are drawn as a spring cam's (:mod:`._sampling`: the same keys, seed and order, the
``backlash`` drawn last); each built cam's follower (:func:`._kernel.sample_model`) and backlash go through
:func:`camdyn.model.dynamics.closure_response` at the sample's speed, one after another (a flight is an
event-driven solve: tens of ms a sample). The result: the probability that the impact speed exceeds
``[limits] max_impact_velocity`` (Clopper-Pearson interval), the percentiles of the impact speed and force, and
the worst samples. Conjugate cams under a preload (no backlash) have no impacts: each built cam's least force on
either cam (:func:`camdyn.design.closure.cam_loads`) and the probability that a roller unloads (force 0) instead.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import jax.numpy as jnp
import numpy as np

from ..._core.errors import InputError
from ..._core.kinds import FollowerKind
from ..._core.limits import check_samples
from ..._core.progress import Progress, counter
from ..._core.units import PROFILE_ERROR_HARMONICS, tolerance_unit
from ...model import dynamics as dyn
from ..closure import cam_loads
from ._interval import CONFIDENCE, exact_interval
from ._kernel import Sample, sample_model
from ._result import csv_columns
from ._sampling import SCALAR_KEYS, case_tolerances, draw_samples, spreads
from ._study import WORST, _nominal, _to_si, describe

if TYPE_CHECKING:
    from ...model.case import Case

IMPACT_PERCENTILES = (50, 95, 99)  # of the impact speed and force: the upper tail is what fails


@dataclass(frozen=True)
class ImpactToleranceResult:
    """A groove cam's Monte Carlo tolerance study: per sample its parameters (case-file units, the backlash in mm)
    and its largest impact speed (m/s) and force (N; NaN for a rigid train)."""

    case: str
    kind: FollowerKind
    seed: int
    speed_rpm: float  # the case's
    params: dict[str, np.ndarray]  # SCALAR_KEYS and "backlash" -> (n,)
    impact_velocity_m_per_s: np.ndarray
    max_impact_force_N: np.ndarray
    max_impact_velocity: float  # the limit, m/s
    tolerances: dict[str, dict]
    probability: float  # of an impact speed above the limit
    confidence_interval: tuple[float, float]
    confidence: ClassVar[float] = CONFIDENCE  # of the intervals
    worst: tuple[int, ...]  # the samples of the fastest impacts, fastest first (the least cam force, least first)
    closure: str = "groove"  # or "conjugate"
    preload: float | None = None  # conjugate cams under a preload: N, or N*m about the pivot
    least_cam_force_N: np.ndarray | None = None  # with a preload: each sample's least force on either cam
    unloaded_probability: float = 0.0  # with a preload: of a roller unloading somewhere
    unloaded_interval: tuple[float, float] = (0.0, 0.0)

    @property
    def samples(self) -> int:
        return self.impact_velocity_m_per_s.size

    @staticmethod
    def percentiles(values: np.ndarray) -> dict[str, float] | None:
        """P50, P95, P99 and the largest (sample values); None where every value is NaN (a rigid train's force)."""
        if np.all(np.isnan(values)):
            return None
        q = np.percentile(values, IMPACT_PERCENTILES, method="inverted_cdf")
        return {f"p{p}": float(v) for p, v in zip(IMPACT_PERCENTILES, q, strict=True)} | {"max": float(np.max(values))}

    @property
    def csv(self) -> str:
        """One row per sample: ``sample``, the spring cam's parameter columns (:func:`csv_columns`) but the
        profile error, ``backlash_mm``, ``impact_velocity_m_per_s``, ``max_impact_force_N`` (empty for a rigid
        train), ``over_limit`` (0/1)."""
        buf = io.StringIO()
        names = csv_columns(self.kind)[1 : 1 + len(SCALAR_KEYS)]
        held = self.least_cam_force_N
        extra = ("least_cam_force_N", "unloaded") if held is not None else ()
        buf.write(
            ",".join(
                ("sample", *names, "backlash_mm", "impact_velocity_m_per_s", "max_impact_force_N", "over_limit", *extra)
            )
            + "\n"
        )
        cols = [self.params[k] for k in (*SCALAR_KEYS, "backlash")]
        for i in range(self.samples):
            v, f = self.impact_velocity_m_per_s[i], self.max_impact_force_N[i]
            force = "" if np.isnan(f) else f"{f:.10g}"
            more = "" if held is None else f",{held[i]:.10g},{held[i] <= 0.0:d}"
            buf.write(
                f"{i:d},"
                + ",".join(f"{c[i]:.10g}" for c in cols)
                + f",{v:.10g},{force},{v > self.max_impact_velocity:d}{more}\n"
            )
        return buf.getvalue()

    def json(self) -> dict:
        """The ``tolerance --json`` document of a form-closed cam (keys only ever added)."""
        return {
            "case": self.case,
            "closure": self.closure,
            "samples": self.samples,
            "seed": self.seed,
            "speed_rpm": self.speed_rpm,
            "max_impact_velocity": self.max_impact_velocity,
            "probability_over_limit": self.probability,
            "confidence_interval": list(self.confidence_interval),
            "confidence": self.confidence,
            "impact_velocity_m_per_s": self.percentiles(self.impact_velocity_m_per_s),
            "max_impact_force_N": self.percentiles(self.max_impact_force_N),
            "tolerances": self.tolerances,
            "worst": [
                {
                    "sample": i,
                    "backlash_mm": float(self.params["backlash"][i]),
                    "speed_rpm": float(self.params["speed"][i]),
                    "impact_velocity_m_per_s": float(self.impact_velocity_m_per_s[i]),
                    "max_impact_force_N": None
                    if np.isnan(self.max_impact_force_N[i])
                    else float(self.max_impact_force_N[i]),
                }
                | ({} if self.least_cam_force_N is None else {"least_cam_force_N": float(self.least_cam_force_N[i])})
                for i in self.worst
            ],
        } | self._preload_json()

    def _preload_json(self) -> dict:
        """Conjugate cams under a preload: the preload, the least cam force's low tail and P(a roller unloads)."""
        low = self.least_cam_force_low
        if low is None:
            return {}
        return {
            "preload_N" if not self.kind.rotary else "preload_torque_N_m": self.preload,
            "probability_unloaded": self.unloaded_probability,
            "unloaded_confidence_interval": list(self.unloaded_interval),
            "least_cam_force_N": low,
        }

    @property
    def least_cam_force_low(self) -> dict[str, float] | None:
        """Conjugate cams under a preload: the low tail of the least force on either cam (N: P1, P5, P50, least)."""
        held = self.least_cam_force_N
        if held is None:
            return None
        q = np.percentile(held, (1, 5, 50), method="inverted_cdf")
        return {"p1": float(q[0]), "p5": float(q[1]), "p50": float(q[2]), "min": float(held.min())}


def impact_tolerance_study(
    case: Case, samples: int, seed: int = 0, *, progress: Progress | None = None
) -> ImpactToleranceResult:
    """Monte Carlo study of the form-closed cam ``case``'s ``[tolerances]`` (``backlash`` among them) over ``samples``
    built cams drawn from ``seed``: their largest crossover impact at their speed, and conjugate cams' least cam
    force under their preload."""
    check_samples(samples)
    f = case.follower
    assert f is not None and f.form_closed  # the caller asks only of a form-closed cam
    kind, base = case.kind, case.model
    tols = case_tolerances(case)
    keys = {t.key for t in tols}
    if "profile_error" in keys:
        raise InputError(
            "tolerances.profile_error",
            f"a {f.closure} cam's tolerance study does not take a profile error yet: its crossovers are studied on the "
            "drawn motion (remove the key; backlash, mass, train_stiffness and speed are studied)",
        )
    if base.rigid and "train_stiffness" in keys:
        raise InputError(
            "tolerances.train_stiffness",
            "a rigid follower has no train stiffness: remove the key or give [dynamics] train_stiffness",
        )
    nominal = _nominal(case) | {"backlash": float(f.backlash)}
    spread = spreads(tols, nominal)
    vals = draw_samples(spread, nominal, samples, seed)
    vals["backlash"] = np.broadcast_to(np.asarray(vals["backlash"], dtype=float), (samples,))  # a scalar if not drawn
    for key in ("mass", "train_stiffness", "speed"):
        if np.any(vals[key] <= 0.0):
            raise InputError(
                f"tolerances.{key}",
                f"the tolerance reaches a value <= 0 {tolerance_unit(key, kind.rotary)} in some samples: give a "
                "smaller one",
            )
    for key in ("spring_rate", "preload", "backlash"):
        if np.any(vals[key] < 0.0) and key in keys:
            raise InputError(
                f"tolerances.{key}",
                f"the tolerance reaches a value < 0 {tolerance_unit(key, kind.rotary)} in some samples: give a "
                "smaller one",
            )
    k, f0, m, kf, omega, _ = _to_si(case, vals)
    zero = jnp.zeros(2 * PROFILE_ERROR_HARMONICS)
    v = np.zeros(samples)
    force = np.full(samples, np.nan)
    preloaded = f.closure == "conjugate" and f.backlash == 0.0 and "backlash" not in keys
    held = np.zeros(samples) if preloaded else None
    tick = counter(progress, "built cams (crossover impacts)", samples)
    for i in range(samples):
        k_i, f0_i, m_i, kf_i, omega_i = (jnp.asarray(float(x[i])) for x in (k, f0, m, kf, omega))
        p = Sample(k_i, f0_i, m_i, kf_i, omega_i, zero)
        r = dyn.closure_response(
            case.motion, f.model_copy(update={"backlash": float(vals["backlash"][i])}), sample_model(base, p), omega[i]
        )
        v[i] = r.max_impact_velocity_m_per_s
        if r.max_impact_force_N is not None and vals["backlash"][i] > 0.0 and r.crossovers:
            force[i] = r.max_impact_force_N
        if held is not None:
            loads = cam_loads(case, r, f.pair_preload)
            held[i] = min(np.min(loads.primary_N), np.min(loads.conjugate_N))
        tick()
    lim = float(case.limits.max_impact_velocity)
    over = int(np.count_nonzero(v > lim))
    ci = exact_interval(over, samples)
    more = {}
    if held is not None:
        unloaded = int(np.count_nonzero(held <= 0.0))
        u_ci = exact_interval(unloaded, samples)
        more = {
            "preload": float(f.pair_preload),
            "least_cam_force_N": held,
            "unloaded_probability": unloaded / samples,
            "unloaded_interval": u_ci,
        }
    worst = np.argsort(held, kind="stable") if held is not None else np.argsort(-v, kind="stable")
    return ImpactToleranceResult(
        case=case.name,
        kind=kind,
        seed=seed,
        speed_rpm=float(case.speed_rpm),
        params={key: vals[key] for key in (*SCALAR_KEYS, "backlash")},
        impact_velocity_m_per_s=v,
        max_impact_force_N=force,
        max_impact_velocity=lim,
        tolerances={t.key: describe(t, spread[t.key], kind.rotary) for t in tols},
        probability=over / samples,
        confidence_interval=ci,
        worst=tuple(int(i) for i in worst[:WORST]),
        closure=f.closure,
        **more,
    )
