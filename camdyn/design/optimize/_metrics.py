"""What ``optimize`` compares before and after (:class:`Metrics`), and the force margin's speed: the least speed
at which the least contact force falls to the margin, by ``check``'s own searches."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import equinox as eqx
import numpy as np

from ..._core.results import finite_or_none
from ..._core.units import RPM
from ...model.case import Case
from ...model.dynamics import dynamic_jump_speed, float_speed, preload_share
from ...model.follower import FollowerModel
from ...model.motion import evaluate
from ..checks import CheckReport, run_check

MARGIN_OF_PRELOAD = 0.05  # the default force margin: this share of the static preload


def _shown(label: str, fmt: str = ".4g", claim: bool = False):
    """A field of :class:`Metrics` with how the before/after table shows it ({u}: mm or deg, {f}: N or N*m);
    ``claim``: a speed camdyn claims holds, shown rounded down as the written case's header says it
    (:func:`floor_rpm`)."""
    return field(metadata={"label": label, "format": fmt, "claim": claim})


@dataclass(frozen=True)
class Metrics:
    """What the before/after table compares."""

    jump_speed_rpm: float = _shown("dynamic jump speed (rpm)", ".1f")  # check's
    margin_speed_rpm: float = _shown("speed holding the force margin (rpm)", ".1f", claim=True)  # :func:`margin_speed`
    least_force_N: float = _shown("least contact force at the case speed (N)")
    peak_acceleration: float = _shown("peak acceleration ({u}/rad^2)")  # |s''| max
    max_pressure_angle_deg: float = _shown("max pressure angle (deg)", ".2f")
    min_radius_of_curvature_mm: float = _shown("least radius of curvature (mm)")
    peak_spring_force: float = _shown("peak spring force ({f})")  # N (N*m for an arm)
    residual_vibration: float = _shown(
        "residual vibration ({u})", ".3g"
    )  # at the case speed: mm (deg of swing for an arm)
    verdict: str = _shown("verdict", "")

    def json(self, unit: str) -> dict:
        return {
            "jump_speed_rpm": finite_or_none(self.jump_speed_rpm),
            "least_contact_force_N": self.least_force_N,
            f"peak_acceleration_{unit}_per_rad2": self.peak_acceleration,
            "max_pressure_angle_deg": self.max_pressure_angle_deg,
            "min_radius_of_curvature_mm": self.min_radius_of_curvature_mm,
            "peak_spring_force_N_m" if unit == "deg" else "peak_spring_force_N": self.peak_spring_force,
            f"residual_vibration_{unit}": self.residual_vibration,
            "verdict": self.verdict,
            "margin_speed_rpm": finite_or_none(self.margin_speed_rpm),
        }


def floor_rpm(rpm: float) -> float:
    """A claimed speed as printed (to 0.1 rpm): rounded down, never past what holds."""
    return math.floor(rpm * 10.0) / 10.0 if math.isfinite(rpm) else rpm


def default_margin(case: Case) -> float:
    """The force margin to keep when none is given: :data:`MARGIN_OF_PRELOAD` of the static preload (N; N*m)."""
    return MARGIN_OF_PRELOAD * abs(float(case.model.preload))


def _less_preload(model: FollowerModel, margin: float) -> FollowerModel:
    """The model whose interface force is ``model``'s less ``margin`` at every angle and speed in contact: the
    steady state is affine in the preload, a change dF0 moving the force by k_f / (k + k_f) dF0."""
    share = 1.0 if model.rigid else float(preload_share(model.stiffness, model.train_stiffness))
    return eqx.tree_at(lambda m: m.preload, model, model.preload - margin / share)


def margin_speed(case: Case, margin: float, w_max: float) -> float:
    """The least speed (rad/s) at which the least interface force falls to ``margin`` (N; N*m for an arm), by
    ``check``'s own jump-speed search on the model less the margin (a valvetrain's: its float search, the two-mass
    model's least cam force over the valve event); inf if none up to ``w_max``."""
    if case.valvetrain is not None:
        return float_speed(case.motion, case.valvetrain, w_max, margin=margin)
    return follower_margin_speed(case, margin, w_max)


def follower_margin_speed(case: Case, margin: float, w_max: float) -> float:
    """:func:`margin_speed` of the case's single follower (a valvetrain's equivalent follower), rad/s."""
    return dynamic_jump_speed(case.motion, _less_preload(case.model, margin), w_max=w_max)


def search_top(case: Case, chk: CheckReport) -> float:
    """How far (rad/s) the margin-speed searches look: 4 x the larger of the margin speed and the jump speed."""
    jump = chk.dynamic.jump_speed_rpm
    return 4.0 * max(case.limits.speed_margin * chk.speed_rpm, jump if jump is not None else 0.0) * RPM


def metrics(case: Case, check: CheckReport | None = None, margin: float = 0.0) -> Metrics:
    chk = check or run_check(case)
    theta = np.linspace(0.0, 2 * math.pi, 7200, endpoint=False)
    sv = np.asarray(evaluate(case.motion, theta))  # one program: eagerly each operation compiles alone
    to_user = 1.0 if case.motion.unit == "mm" else 180.0 / math.pi
    m = case.model
    geo = chk.geometry
    jump = chk.dynamic.jump_speed_rpm
    w_max = search_top(case, chk)
    residual = chk.dynamic.residual_vibration_as_lift  # mm, or deg of arm swing, as the motion's unit
    return Metrics(
        jump_speed_rpm=float(jump if jump is not None else math.inf),
        margin_speed_rpm=float(margin_speed(case, margin, w_max) / RPM),
        least_force_N=float(chk.dynamic.min_contact_force_N),
        peak_acceleration=float(np.abs(sv[2]).max() * to_user),
        max_pressure_angle_deg=float(geo.max_pressure_angle_deg) if geo else math.nan,
        min_radius_of_curvature_mm=float(geo.min_radius_of_curvature_mm) if geo else math.nan,
        peak_spring_force=float(m.preload + m.stiffness * sv[0].max() * m.scale),
        residual_vibration=float(residual),
        verdict=chk.verdict,
    )
