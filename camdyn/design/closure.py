"""Form-closed cams judged (``[follower] closure = "groove"`` or ``"conjugate"``): the signed contact force, its
crossovers, the flights across the backlash and their impacts (``check --json`` ``closure``, the
``crossover_impact`` check); of conjugate cams also the conjugate cam's geometry and each cam's force under the
preload between the rollers.

A groove (or a conjugate pair) holds the follower both ways: it cannot jump, so ``speed_margin`` (and the least
contact force, which is negative on the outer flank by design) do not apply; ``check`` says so instead of printing an
infinite margin.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._core.units import RPM, newton_per_torque
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.geometry import (
    WALLS,
    ConjugateGeometry,
    GrooveGeometry,
    conjugate,
    conjugate_lever_mm,
    groove,
    newton_per_torque_at,
)
from ..model.motion import evaluate
from ._check import Check, CheckKind

NOT_APPLICABLE = (
    "speed_margin and contact_force do not apply to a form-closed cam: the groove holds the follower both ways, so "
    "it cannot jump; the contact force is signed (positive on the inner flank) and changes flank at the crossovers"
)
NOT_APPLICABLE_CONJUGATE = (
    "speed_margin and contact_force do not apply to conjugate cams: the two cams hold the follower both ways, so it "
    "cannot jump; the contact force is signed (positive on the primary cam) and changes cam at the crossovers"
)


@dataclass(frozen=True)
class CamLoads:
    """Conjugate cams: each cam's force over ``theta_deg`` with the preload between the rollers, N (axial for a
    yoke, at the contact for a rocker; :func:`camdyn.model.dynamics.preload_shares`)."""

    theta_deg: np.ndarray
    primary_N: np.ndarray
    conjugate_N: np.ndarray
    preload: float  # the motion's force unit: N, or N*m about the pivot
    translating: bool

    @property
    def preload_held(self) -> bool:
        """Both rollers stay loaded all round (with no preload: never)."""
        return bool(np.all(self.primary_N > 0.0) and np.all(self.conjugate_N > 0.0))

    def json(self) -> dict:
        def cam(f: np.ndarray) -> dict:
            i, j = int(np.argmax(f)), int(np.argmin(f))
            return {
                "max_force_N": float(f[i]),
                "max_force_at_deg": float(self.theta_deg[i]),
                "min_force_N": float(f[j]),
                "min_force_at_deg": float(self.theta_deg[j]),
            }

        return {
            "preload_N" if self.translating else "preload_torque_N_m": self.preload,
            "preload_held": self.preload_held,
            "cams": {"primary": cam(self.primary_N), "conjugate": cam(self.conjugate_N)},
        }


@dataclass(frozen=True)
class ClosureStudy:
    """A form-closed cam at one speed: its follower's signed contact force and crossovers
    (:class:`dyn.ClosureResponse`) and both walls (:class:`GrooveGeometry`), or the conjugate cam
    (:class:`ConjugateGeometry`) and each cam's force (:class:`CamLoads`)."""

    response: dyn.ClosureResponse
    walls: GrooveGeometry | ConjugateGeometry
    loads: CamLoads | None = None  # conjugate cams

    def json(self) -> dict:
        out = self.response.json() | {"speed_margin": "not applicable: form-closed"}
        if self.loads is None:
            return out | {"walls": self.walls.json()}
        return out | {"conjugate_cam": self.walls.json()} | self.loads.json()

    @property
    def not_applicable(self) -> str:
        """Why speed_margin and the least contact force are not judged."""
        return NOT_APPLICABLE if self.loads is None else NOT_APPLICABLE_CONJUGATE

    @property
    def fold_warnings(self) -> list[str]:
        """A warning per groove wall, or for the conjugate cam, whose contour folds (undercut)."""
        w = self.walls
        if isinstance(w, ConjugateGeometry):
            return ["the conjugate cam's contour folds (undercut)"] if w.undercut else []
        return [f"the groove's {n} wall folds (undercut)" for n in WALLS if getattr(w, f"{n}_wall").undercut]

    def geometry_checks(self, max_pressure_angle: float, min_curvature_ratio: float) -> tuple[Check, ...]:
        """The conjugate cam's pressure angle and curvature against the primary's limits (deg, ratio to its
        roller); none for a groove (its walls share the pitch curve's pressure angle, judged as the cam's)."""
        w = self.walls
        if not isinstance(w, ConjugateGeometry):
            return ()
        return (
            CheckKind.CONJUGATE_PRESSURE_ANGLE.check(w.max_pressure_angle_deg, float(max_pressure_angle)),
            CheckKind.CONJUGATE_CURVATURE.check(w.curvature, float(min_curvature_ratio)),
        )

    def on_its_cam(self, case: Case, resp: dyn.Response) -> dyn.Response:
        """A response in N (:func:`camdyn.design.checks.forces_in_newton`, through the primary's lever) with a
        conjugate rocker's negative forces through the conjugate cam's lever instead: each force on its cam."""
        if self.loads is None or not case.oscillating:
            return resp
        on = lambda f: self.force_on_its_cam(case, resp.theta_deg, f)  # noqa: E731
        return replace(resp, force=on(resp.force), kinematic_force=on(resp.kinematic_force))

    def force_on_its_cam(self, case: Case, theta_deg: np.ndarray, force_N: np.ndarray) -> np.ndarray:
        """Signed forces (N) taken through the primary's lever at ``theta_deg``, the negative ones of a conjugate
        rocker through the conjugate cam's lever instead (a groove's, or a yoke's, as they are)."""
        if self.loads is None or not case.oscillating:
            return force_N
        th = np.deg2rad(theta_deg)
        ratio = np.asarray(newton_per_torque(conjugate_lever_mm(case.motion, case.follower, th))) / np.asarray(
            newton_per_torque_at(case.motion, case.follower, th)
        )
        return np.where(force_N < 0.0, force_N * ratio, force_N)

    def as_response(self, case: Case) -> dyn.Response:
        """The follower as the other models give it (forces in N, or N*m for an arm; the follower on the cam's
        motion, which the backlash leaves within b/2), for the drive torque, the tables and the plots."""
        r = self.response
        vals = np.asarray(evaluate(case.motion, np.deg2rad(r.theta_deg)))
        kin = np.asarray(dyn.kinematic_force(case.motion, case.model, r.omega, np.deg2rad(r.theta_deg)))
        return dyn.Response(
            case.follower.closure,
            r.omega,
            r.theta_deg,
            vals[0],
            vals[0].copy(),
            vals[1].copy(),
            r.contact_force,
            kin,
            (),
            0.0,
            0.0,
        )

    def check(self, max_impact_velocity: float) -> Check:
        """``[limits] max_impact_velocity``: the largest speed at which a flank meets the follower crossing the
        backlash, m/s (0 without backlash)."""
        return CheckKind.CROSSOVER_IMPACT.check(self.response.max_impact_velocity_m_per_s, float(max_impact_velocity))


def closure_study(case: Case, speed_rpm: float | None = None) -> ClosureStudy:
    """The form-closed cam of ``case`` at ``speed_rpm`` (default: the case's)."""
    f = case.follower
    assert f is not None and f.form_closed  # the caller asks only of a form-closed cam
    omega = float(case.speed_rpm if speed_rpm is None else speed_rpm) * RPM
    if f.closure != "conjugate":
        return ClosureStudy(dyn.closure_response(case.motion, f, case.model, omega), groove(case.motion, f))
    second = conjugate(case.motion, f)  # first: a pair that cannot be assembled is refused before the dynamics
    r = dyn.closure_response(case.motion, f, case.model, omega)
    primary, other = dyn.preload_shares(r.contact_force, f.pair_preload)
    if case.oscillating:  # torques about the pivot -> each cam's contact force through its own lever
        th = np.deg2rad(r.theta_deg)
        primary = primary * newton_per_torque_at(case.motion, f, th)
        other = other * newton_per_torque(conjugate_lever_mm(case.motion, f, th))
    return ClosureStudy(r, second, CamLoads(r.theta_deg, primary, other, f.pair_preload, f.translating))
