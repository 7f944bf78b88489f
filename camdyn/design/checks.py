"""``camdyn check``: the interface force, the jump speeds, the separations and the geometry of a case, judged."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np

from .._core.units import RPM
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.geometry import CamGeometry, analyze, newton_per_torque_at
from ._check import Check, CheckKind
from .geometry import judge_geometry


@dataclass(frozen=True)
class CheckReport:
    """Everything ``camdyn check`` concludes about a case at one speed."""

    case: Case
    speed_rpm: float
    checks: tuple[Check, ...]
    kinematic: dict
    dynamic: dict
    response: dyn.Response  # forces in N (an oscillating arm's torques through its lever arm)
    warnings: tuple[str, ...]
    advice: tuple[str, ...] = ()
    geometry: CamGeometry | None = None

    @property
    def verdict(self) -> str:
        return "pass" if all(c.ok for c in self.checks) else "fail"

    def json(self) -> dict:
        out = {
            "case": self.case.name,
            "verdict": self.verdict,
            "speed_rpm": self.speed_rpm,
            "checks": [c.json() for c in self.checks],
            "kinematic": self.kinematic,
            "dynamic": self.dynamic,
            "warnings": list(self.warnings),
            "advice": list(self.advice),
        }
        out["motion"] = self.case.motion_json()
        if self.geometry is not None:
            out["geometry"] = self.geometry.json()
        if self.case.synthesis is not None:
            out["synthesis"] = self.case.synthesis.json()
        return out


def _finite_or_none(x: float) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def forces_in_newton(case: Case, resp: dyn.Response) -> dyn.Response:
    """A response with an oscillating follower's torques (N*m) as contact forces (N) through the lever arm of
    the contact normal; a translating follower's as it is."""
    if not case.oscillating:
        return resp
    per_torque = newton_per_torque_at(case.motion, case.follower, np.deg2rad(resp.theta_deg))
    return dataclasses.replace(resp, force=resp.force * per_torque, kinematic_force=resp.kinematic_force * per_torque)


def run_check(case: Case, speed_rpm: float | None = None) -> CheckReport:
    """Kinematic and dynamic interface force, jump speeds, separations and the verdict at ``speed_rpm``."""
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    omega = rpm * RPM
    motion, model, limits = case.motion, case.model, case.limits
    warnings = list(case.warnings)

    resp = dyn.response(motion, model, omega)
    w_kin, at_kin = dyn.kinematic_jump_speed(motion, model)
    w_max = 4.0 * max(limits.speed_margin * omega, w_kin if math.isfinite(w_kin) else 0.0)
    w_dyn = dyn.dynamic_jump_speed(motion, model, w_max=w_max)
    if not math.isfinite(w_dyn) and not model.rigid:
        warnings.append(f"no jump found up to {w_max / RPM:.0f} rpm (searched 4x beyond the margin)")
    if not model.rigid and not resp.separations:
        # the frequency-domain steady state is exact without separation: an independent check of the solve
        f_lin = float(dyn.linear_min_force(motion, model, jnp.asarray([omega]))[0])
        if abs(f_lin - resp.min_force) > 5e-3 * max(1.0, float(abs(resp.force).max())):
            warnings.append(f"time-domain and frequency-domain steady states disagree: least force {resp.min_force:.4g} vs {f_lin:.4g} {'N*m' if case.oscillating else 'N'}")
    warnings += list(resp.warnings)
    resp = forces_in_newton(case, resp)

    kin_force = resp.kinematic_force
    i_kin = int(kin_force.argmin())
    unit = motion.unit
    checks = (
        Check(CheckKind.CONTACT_FORCE.value, float(resp.min_force), float(limits.min_contact_force), "N", ">"),
        Check(CheckKind.SPEED_MARGIN.value, _finite_or_none(w_dyn / omega), float(limits.speed_margin), "x", ">="),
    )
    kinematic = {
        "min_contact_force_N": float(kin_force[i_kin]),
        "min_contact_force_deg": float(resp.theta_deg[i_kin]),
        "jump_speed_rpm": _finite_or_none(w_kin / RPM),
        "jump_speed_at_deg": _finite_or_none(at_kin),
    }
    dynamic = {
        "model": resp.model,
        "min_contact_force_N": resp.min_force,
        "min_contact_force_deg": resp.min_force_deg,
        "jump_speed_rpm": _finite_or_none(w_dyn / RPM),
        "separations": [s.json(unit) for s in resp.separations],
        ("residual_vibration_mm" if unit == "mm" else "residual_vibration_rad"): resp.residual_vibration,
        "periodicity_error": resp.periodicity_error,
    }
    advice: list[str] = []
    geo = None
    if case.follower is not None:
        geo = analyze(motion, case.follower)
        geo_checks, geo_warnings, geo_advice = judge_geometry(geo, motion, max_pressure_angle=limits.max_pressure_angle, min_curvature_ratio=limits.min_curvature_ratio)
        checks += tuple(geo_checks)
        warnings += geo_warnings
        advice += geo_advice
    for sep in resp.separations:
        warnings.append(f"the follower leaves the cam at {sep.start_deg:.1f} deg and lands at {sep.end_deg:.1f} deg (gap up to {sep.max_gap:.3g} {unit}, impact at {sep.impact_speed:.3g} m/s)")
    return CheckReport(case, rpm, checks, kinematic, dynamic, resp, tuple(warnings), tuple(advice), geo)
