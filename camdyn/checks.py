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


# ------------------------------------------------------------------------------ corner advice
def corner_radius_advice(case, speed_rpm: float | None = None, *, evaluations: int = 6, advance=None) -> str | None:
    """For a failing path case with sharp corners: the corner radius (mm) with which it passes, or why none does.

    The sharp corner is the cause (the follower's velocity jumps there), so the remedy is a fillet: bisect
    ``[path] corner_radius`` between 0 (fails) and half the shorter side on the full check's verdict, with
    ``evaluations`` checks in all (each re-synthesizes the mechanism). ``advance(description)`` is called before
    each. None if the case has no sharp corners.
    """
    from .case import case_from_dict
    from .errors import CamdynError

    syn = case.synthesis
    if syn is None or not syn.sharp_corners or case.spec.path.get("type") != "rectangle":
        return None
    raw = case.spec.model_dump(exclude_none=True)
    r_max = 0.5 * min(float(raw["path"]["width"]), float(raw["path"]["height"]))
    rpm = float(speed_rpm if speed_rpm is not None else case.speed_rpm)
    seen: dict[float, CheckReport | None] = {}

    def verdict(r: float) -> bool:
        if advance is not None:
            advance(f"corner_radius {r:g} mm")
        trial = {**raw, "path": {**raw["path"], "corner_radius": r}}
        try:
            seen[r] = run_check(case_from_dict(trial, source=case.source), rpm)
        except CamdynError:  # a radius the mechanism cannot trace counts as failing
            seen[r] = None
        return seen[r] is not None and seen[r].verdict == "pass"

    tidy = lambda r: max(round(r, 1), 0.1)  # noqa: E731 - a radius to 0.1 mm is what a drawing gives
    lo, hi = 0.0, None
    first = tidy(r_max / 8.0)
    if verdict(first):
        hi = first
    else:
        lo, top = first, tidy(0.98 * r_max)
        if not verdict(top):
            return f"no corner radius up to {top:g} mm passes at {rpm:g} rpm: the sharp corners are not the only problem"
        hi = top
    for _ in range(evaluations - len(seen)):
        mid = tidy(0.5 * (lo + hi))
        if mid in (lo, hi):
            break
        lo, hi = (lo, mid) if verdict(mid) else (mid, hi)
    rep = seen[hi]
    force = next(c for c in rep.checks if c.name == "contact_force")
    margin = next(c for c in rep.checks if c.name == "speed_margin")
    margin_txt = "no jump" if margin.value is None else f"speed margin {margin.value:.3g}"
    return (
        f"sharp corners: [path] corner_radius = {hi:g} mm passes at {rpm:g} rpm (least contact force {force.value:.3g} N, "
        f"{margin_txt}){f'; {lo:g} mm fails' if lo > 0 else ''}"
    )
