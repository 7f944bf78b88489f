"""Checks and verdicts: every judgment camdyn makes is a :class:`Check` with a value, a limit and a unit."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class Check:
    """One pass/fail judgment: the value must be ``sense`` (">=", ">" or "<=") the limit."""

    name: str
    value: float | None  # None: unbounded (e.g. no jump at any speed)
    limit: float
    unit: str
    sense: str = ">="

    @property
    def ok(self) -> bool:
        if self.value is None:  # unbounded: infinitely good for ">=" and ">", infinitely bad for "<="
            return self.sense != "<="
        return {">=": self.value >= self.limit, ">": self.value > self.limit, "<=": self.value <= self.limit}[self.sense]

    def json(self) -> dict:
        d = asdict(self)
        d.pop("sense")
        d["ok"] = self.ok
        return d


# --------------------------------------------------------------------------------------- check
@dataclass(frozen=True)
class CheckReport:
    """Everything ``camdyn check`` concludes about a case at one speed."""

    case: object  # case.Case
    speed_rpm: float
    checks: tuple[Check, ...]
    kinematic: dict
    dynamic: dict
    response: object  # dynamics.Response
    warnings: tuple[str, ...]
    advice: tuple[str, ...] = ()
    geometry: object = None  # geometry.GeometryResult

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
        if self.geometry is not None:
            out["geometry"] = self.geometry.json()
        if self.case.synthesis is not None:
            out["synthesis"] = self.case.synthesis.json()
        return out


def _finite_or_none(x: float) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _forces_in_newton(case, resp):
    """An oscillating follower's torques (N*m) as contact forces (N) through the lever arm of the normal."""
    import dataclasses

    import numpy as np

    from .errors import NumericalError
    from .geometry import lever_arm_mm

    arm_m = np.asarray(lever_arm_mm(case.motion, case.follower, np.deg2rad(resp.theta_deg))) / 1000.0
    if np.any(arm_m <= 1e-9):
        at = float(resp.theta_deg[int(np.argmin(arm_m))])
        raise NumericalError(f"follower at {at:.1f} deg", "the contact normal passes through the arm pivot: no lever arm to carry the load")
    return dataclasses.replace(resp, force=resp.force / arm_m, kinematic_force=resp.kinematic_force / arm_m)


def run_check(case, speed_rpm: float | None = None) -> CheckReport:
    """Kinematic and dynamic interface force, jump speeds, separations and the verdict at ``speed_rpm``."""
    import jax.numpy as jnp

    from . import dynamics as dyn

    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    omega = rpm * dyn.RPM
    motion, model, limits = case.motion, case.model, case.limits
    warnings = list(case.warnings)

    resp = dyn.response(motion, model, omega)
    w_kin, at_kin = dyn.kinematic_jump_speed(motion, model)
    w_max = 4.0 * max(limits.speed_margin * omega, w_kin if math.isfinite(w_kin) else 0.0)
    w_dyn = dyn.dynamic_jump_speed(motion, model, w_max=w_max)
    if not math.isfinite(w_dyn) and not model.rigid:
        warnings.append(f"no jump found up to {w_max / dyn.RPM:.0f} rpm (searched 4x beyond the margin)")
    if not model.rigid and not resp.separations:
        # the frequency-domain steady state is exact without separation: an independent check of the solve
        f_lin = float(dyn.linear_min_force(motion, model, jnp.asarray([omega]))[0])
        if abs(f_lin - resp.min_force) > 5e-3 * max(1.0, float(abs(resp.force).max())):
            warnings.append(f"time-domain and frequency-domain steady states disagree: least force {resp.min_force:.4g} vs {f_lin:.4g} {'N*m' if case.oscillating else 'N'}")
    warnings += list(resp.warnings)
    if case.oscillating:
        resp = _forces_in_newton(case, resp)

    kin_force = resp.kinematic_force
    i_kin = int(kin_force.argmin())
    unit = motion.unit
    checks = (
        Check("contact_force", float(resp.min_force), float(limits.min_contact_force), "N", ">"),
        Check("speed_margin", _finite_or_none(w_dyn / omega), float(limits.speed_margin), "x", ">="),
    )
    kinematic = {
        "min_contact_force_N": float(kin_force[i_kin]),
        "min_contact_force_deg": float(resp.theta_deg[i_kin]),
        "jump_speed_rpm": _finite_or_none(w_kin / dyn.RPM),
        "jump_speed_at_deg": _finite_or_none(at_kin),
    }
    dynamic = {
        "model": resp.model,
        "min_contact_force_N": resp.min_force,
        "min_contact_force_deg": resp.min_force_deg,
        "jump_speed_rpm": _finite_or_none(w_dyn / dyn.RPM),
        "separations": [s.json(unit) for s in resp.separations],
        ("residual_vibration_mm" if unit == "mm" else "residual_vibration_rad"): resp.residual_vibration,
        "periodicity_error": resp.periodicity_error,
    }
    advice: list[str] = []
    geo = None
    if case.follower is not None:
        from .geometry import analyze

        geo = analyze(motion, case.follower, max_pressure_angle=limits.max_pressure_angle, min_curvature_ratio=limits.min_curvature_ratio)
        checks += tuple(geo.checks)
        warnings += list(geo.warnings)
        advice += list(geo.advice)
    for sep in resp.separations:
        warnings.append(f"the follower leaves the cam at {sep.start_deg:.1f} deg and lands at {sep.end_deg:.1f} deg (gap up to {sep.max_gap:.3g} {unit}, impact at {sep.impact_speed:.3g} m/s)")
    return CheckReport(case, rpm, checks, kinematic, dynamic, resp, tuple(warnings), tuple(advice), geo)
