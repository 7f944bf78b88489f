"""``camdyn optimize``: reshape every rise and return of a segment case, keeping its timing, lifts, dwells,
follower, spring and limits, for the objective the designer names (:mod:`._objectives`). The margins are
differentiated through the frequency-domain steady state by JAX (never by finite differences) and each step is
a linear program (:mod:`._slp`); the answer is then checked by ``check``'s own models, the time-domain
diffrax model included."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..._core.errors import InputError
from ..._core.progress import Progress
from ..._core.units import RPM, rate_from_si
from ...export import camdyn_version, dumps_case
from ...model.case import Case, build_case
from ...model.dynamics import linear_min_force, response
from ...schema import CaseSpec
from ...schema.dynamics import LINEAR_KEYS, ROTARY_KEYS
from ..checks import CheckReport, run_check
from ._objectives import CLEAR, jump_speed, least_force, spring_force, vibration
from ._rows import Rows
from ._shape import N_CONTROL, ShapeSpace, shape_space

OBJECTIVES = ("jump-speed", "vibration", "spring-force")


def _shown(label: str, fmt: str = ".4g"):
    """A field of :class:`Metrics` with how the before/after table shows it ({u}: mm or deg, {f}: N or N*m)."""
    return field(metadata={"label": label, "format": fmt})


@dataclass(frozen=True)
class Metrics:
    """What the before/after table compares."""

    jump_speed_rpm: float = _shown("dynamic jump speed (rpm)", ".1f")  # check's
    least_force_N: float = _shown("least contact force at the case speed (N)")
    peak_acceleration: float = _shown("peak acceleration ({u}/rad^2)")  # |s''| max
    max_pressure_angle_deg: float = _shown("max pressure angle (deg)", ".2f")
    min_radius_of_curvature_mm: float = _shown("least radius of curvature (mm)")
    peak_spring_force: float = _shown("peak spring force ({f})")  # N (N*m for an arm)
    residual_vibration: float = _shown("residual vibration ({u})", ".3g")  # at the case speed
    verdict: str = _shown("verdict", "")

    def json(self, unit: str) -> dict:
        return {
            "jump_speed_rpm": self.jump_speed_rpm, "least_contact_force_N": self.least_force_N,
            f"peak_acceleration_{unit}_per_rad2": self.peak_acceleration, "max_pressure_angle_deg": self.max_pressure_angle_deg,
            "min_radius_of_curvature_mm": self.min_radius_of_curvature_mm,
            "peak_spring_force_N_m" if unit == "deg" else "peak_spring_force_N": self.peak_spring_force,
            f"residual_vibration_{unit}": self.residual_vibration, "verdict": self.verdict,
        }


@dataclass(frozen=True)
class Optimization:
    """The optimized case (as a case-file dict and as a :class:`Case`), what changed, and how it was verified."""

    objective: str
    before: Metrics
    after: Metrics
    case: Case
    document: dict  # the case file to write
    claimed_speed_rpm: float  # what the optimizer's own scan promised (jump-speed: up to where it holds)
    verification: dict  # the time-domain model against the frequency domain at the claimed speeds
    control_points: int
    time_s: float

    @property
    def unit(self) -> str:
        return "deg" if self.case.oscillating else "mm"

    def text(self, source: str) -> str:
        """The case file, with a header saying how it was made from ``source``."""
        b, a = self.before, self.after
        ver = f" {camdyn_version()}".rstrip()
        aim = {
            "jump-speed": f"the largest speed up to which the least contact force stays >= {self.case.limits.min_contact_force:g} N at every speed",
            "vibration": "the least residual vibration in the dwells over 0.9-1.1 x the case speed, holding there",
            "spring-force": "the least peak spring force (preload and rate free) holding to speed_margin x speed",
        }[self.objective]
        header = [
            f"Written by `camdyn optimize {source} --objective {self.objective}` (camdyn{ver}): every rise and return is a "
            f'clamped B-spline of degree 5 with {self.control_points} control points (law = "bspline"); the segment boundaries, '
            "lifts and dwells, the follower, the limits and (but for spring-force) the spring are the original's.",
            f"Objective: {aim}. Linear programs (HiGHS) on the frequency-domain steady state, its Jacobian by JAX autodiff.",
            f"Dynamic jump speed {b.jump_speed_rpm:.1f} -> {a.jump_speed_rpm:.1f} rpm; least contact force at the case speed "
            f"{b.least_force_N:.3g} -> {a.least_force_N:.3g} N; max pressure angle {b.max_pressure_angle_deg:.2f} -> "
            f"{a.max_pressure_angle_deg:.2f} deg; verdict {b.verdict} -> {a.verdict}.",
            "Checked by the time-domain (diffrax) model at " + ", ".join(f"{p['speed_rpm']:.0f}" for p in self.verification["points"]) + " rpm.",
        ]
        return dumps_case(self.document, header)

    def json(self) -> dict:
        return {
            "case": self.case.name, "objective": self.objective, "control_points_per_segment": self.control_points,
            "claimed_speed_rpm": self.claimed_speed_rpm if math.isfinite(self.claimed_speed_rpm) else None, "before": self.before.json(self.unit), "after": self.after.json(self.unit),
            "verification": self.verification, "time_s": self.time_s,
        }


def metrics(case: Case, check: CheckReport | None = None) -> Metrics:
    chk = check or run_check(case)
    theta = np.linspace(0.0, 2 * math.pi, 7200, endpoint=False)
    sv = np.asarray(case.motion(theta))
    to_user = 1.0 if case.motion.unit == "mm" else 180.0 / math.pi
    m = case.model
    geo = chk.geometry
    return Metrics(
        jump_speed_rpm=float(chk.dynamic["jump_speed_rpm"]),
        least_force_N=float(chk.dynamic["min_contact_force_N"]),
        peak_acceleration=float(np.abs(sv[2]).max() * to_user),
        max_pressure_angle_deg=float(geo.max_pressure_angle_deg) if geo else math.nan,
        min_radius_of_curvature_mm=float(geo.min_radius_of_curvature_mm) if geo else math.nan,
        peak_spring_force=float(m.preload + m.stiffness * sv[0].max() * m.scale),
        residual_vibration=float(chk.dynamic.get("residual_vibration_mm", chk.dynamic.get("residual_vibration_deg", math.nan))),
        verdict=chk.verdict,
    )


def _document(case: Case, space: ShapeSpace, z, objective: str, name: str | None, source: str | None, dynamics: dict | None = None) -> dict:
    """The case file of the optimized motion: the original with its segments (and spring, if freed) replaced;
    ``source``: the original's path relative to where the new file goes."""
    doc = case.spec.model_dump(exclude_unset=True, exclude_none=True)
    if source:
        doc["optimized_from"] = source
    doc["name"] = name or f"{case.name}-optimized"
    said = case.spec.description.strip().rstrip(".")
    doc["description"] = (f"{said}. " if said else "") + f"Rises and returns reshaped by camdyn optimize ({objective})."
    doc["motion"] = {"segments": space.segments(z)}
    if dynamics:
        doc["dynamics"] = doc["dynamics"] | dynamics
    return doc


def _verify(case: Case, speeds_rpm: list[float]) -> dict:
    """The diffrax time-domain steady state against the frequency domain the optimizer used, at ``speeds_rpm``:
    least interface force of each (N; N*m for an arm) and whether the follower separates."""
    unit = "N_m" if case.oscillating else "N"
    points = []
    for rpm in speeds_rpm:
        w = rpm * RPM
        r = response(case.motion, case.model, w)
        fd = float(np.asarray(linear_min_force(case.motion, case.model, np.array([w])))[0]) if not case.model.rigid else math.nan
        points.append({"speed_rpm": rpm, f"time_domain_least_force_{unit}": r.min_force, f"frequency_domain_least_force_{unit}": fd, "separated": bool(r.separations)})
    return {"model": "rigid" if case.model.rigid else "compliant", "points": points}


def optimize_case(
    case: Case, objective: str = "jump-speed", *, speed_rpm: float | None = None, progress: Progress | None = None, name: str | None = None,
    source: str | None = None,
) -> Optimization:
    """Reshape ``case``'s rises and returns for ``objective`` (one of :data:`OBJECTIVES`) at ``speed_rpm`` (default:
    the case's); ``name``: the optimized case's (default: the case's with "-optimized"); ``source``: the original
    case file as the new one will find it (its ``optimized_from``)."""
    if objective not in OBJECTIVES:
        raise InputError("--objective", f"unknown objective {objective!r}; choose one of {', '.join(OBJECTIVES)}")
    t0 = time.perf_counter()
    space = shape_space(case)
    rows = Rows(case, space)
    before_check = run_check(case, speed_rpm)
    before = metrics(case, before_check)
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    dynamics: dict = {}
    claimed = math.nan
    if objective == "jump-speed":
        w0 = before.jump_speed_rpm * RPM
        if not math.isfinite(w0):
            raise InputError("case", "the case does not jump within the check's search: there is no jump speed to raise")
        z, w = jump_speed(rows, w0, progress)
        claimed = w / RPM
    elif objective == "vibration":
        z = vibration(rows, rpm * RPM)
    else:
        w = case.limits.speed_margin * rpm * RPM * CLEAR
        rates = float(case.model.stiffness) * np.array([0.25, 0.5, 1.0, 2.0])
        z, k, f0 = spring_force(rows, w, rates)
        keys = ROTARY_KEYS if case.oscillating else LINEAR_KEYS
        dynamics = {keys[1]: float(np.round(rate_from_si(k, case.oscillating), 6)), keys[2]: float(math.ceil(f0 * 100.0) / 100.0)}
    doc = _document(case, space, z, objective, name, source, dynamics)
    new = build_case(CaseSpec.model_validate(doc), case.source)
    after_check = run_check(new, speed_rpm)
    after = metrics(new, after_check)
    checked = [rpm] if not math.isfinite(claimed) else [0.5 * claimed, 0.9 * claimed, 0.99 * claimed]
    verification = _verify(new, checked)
    return Optimization(objective, before, after, new, doc, claimed, verification, N_CONTROL, time.perf_counter() - t0)


__all__ = ["OBJECTIVES", "Metrics", "Optimization", "least_force", "metrics", "optimize_case"]
