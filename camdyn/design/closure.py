"""Form-closed cams judged (``[follower] closure = "groove"`` or ``"conjugate"``): the signed contact force, its
crossovers, the flights across the backlash and their impacts (``check --json`` ``closure``, the
``crossover_impact`` check); of conjugate cams also the conjugate cam's geometry and each cam's force under the
preload between the rollers.

A groove (or a conjugate pair) holds the follower both ways: it cannot jump, so ``speed_margin`` (and the least
contact force, which is negative on the outer flank by design) do not apply; ``check`` says so instead of printing an
infinite margin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .._core.errors import InputError
from .._core.progress import Progress, counter
from .._core.units import AT_LIMIT_RTOL, RPM, newton_per_torque
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


NO_RETURN_SPRING = (
    "a form-closed cam has no return spring to size or build and no jump speed: the groove (or the conjugate cams) "
    "holds the follower both ways, so what limits its speed is the impact where the follower crosses the backlash "
    "(crossover_impact), or conjugate cams' preload that keeps both rollers loaded"
)


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
    def groove(self) -> GrooveGeometry:
        """The groove's walls (a groove cam only)."""
        if not isinstance(self.walls, GrooveGeometry):
            raise TypeError("conjugate cams have no groove walls")
        return self.walls

    @property
    def conjugate(self) -> ConjugateGeometry:
        """The conjugate cam (conjugate cams only)."""
        if not isinstance(self.walls, ConjugateGeometry):
            raise TypeError("a groove cam has no conjugate cam")
        return self.walls

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

    def preload_check(self, min_contact_force: float) -> tuple[Check, ...]:
        """Preloaded conjugate cams: the least force on either cam (N, at the contact) against ``[limits]
        min_contact_force``: the preload must keep both rollers loaded all round, or one lets go and the follower is
        held by one cam at a time. None without a preload (a groove, or conjugate cams with backlash)."""
        if self.loads is None or self.loads.preload <= 0.0:
            return ()
        least = float(min(np.min(self.loads.primary_N), np.min(self.loads.conjugate_N)))
        return (CheckKind.CONJUGATE_PRELOAD.check(least, float(min_contact_force)),)

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

    def judged_curvature(self, cam: Check) -> Check:
        """The ``curvature`` check of the cam (``cam``: its contour's), or for a groove of the walls the roller
        presses on: the least radius where either wall is convex towards the roller over the roller radius (the
        inner wall is the cam's contour moved b/2 in; the outer wall is convex where the pitch curve is concave)."""
        w = self.walls
        if not isinstance(w, GrooveGeometry):
            return cam
        least = min(w.inner_wall.min_convex_radius_mm, w.outer_wall.min_convex_radius_mm)
        roller = w.wall_offset_mm - 0.5 * w.backlash_mm
        return CheckKind.CURVATURE.check(least / roller, cam.limit)

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
        kin = np.asarray(dyn.kinematic_force_jit(case.motion, case.model, r.omega, np.deg2rad(r.theta_deg)))
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
    return ClosureStudy(r, second, cam_loads(case, r, f.pair_preload))


def cam_loads(case: Case, response: dyn.ClosureResponse, preload: float) -> CamLoads:
    """Each conjugate cam's force (N) under ``preload`` (N, or N*m about the pivot) for the net force of
    ``response``."""
    f = case.follower
    primary, other = dyn.preload_shares(response.contact_force, preload)
    if case.oscillating:  # torques about the pivot -> each cam's contact force through its own lever
        th = np.deg2rad(response.theta_deg)
        primary = primary * newton_per_torque_at(case.motion, f, th)
        other = other * newton_per_torque(conjugate_lever_mm(case.motion, f, th))
    return CamLoads(response.theta_deg, primary, other, preload, f.translating)


MAX_IMPACT_POINTS = 10_000  # speeds x backlashes of a sweep: about 20 ms a point, a few minutes at the budget
IMPACT_MAP_COLUMNS = ("speed_rpm", "backlash_mm", "impact_velocity_m_per_s", "max_impact_force_N")


@dataclass(frozen=True)
class ImpactMap:
    """A groove cam's crossover impacts over cam speed x backlash: the largest impact speed (m/s at the roller)
    and impact force (N; NaN for a rigid train, whose impact is an impulse) a revolution, (n_backlash, n_speed)."""

    speeds_rpm: np.ndarray
    backlash_mm: np.ndarray
    impact_velocity_m_per_s: np.ndarray
    max_impact_force_N: np.ndarray
    max_impact_velocity: float  # [limits] max_impact_velocity, m/s

    def json(self) -> dict:
        return {
            "speeds_rpm": self.speeds_rpm.tolist(),
            "backlash_mm": self.backlash_mm.tolist(),
            "impact_velocity_m_per_s": self.impact_velocity_m_per_s.tolist(),
            "max_impact_force_N": [[None if np.isnan(f) else float(f) for f in row] for row in self.max_impact_force_N],
            "max_impact_velocity": self.max_impact_velocity,
        }

    @property
    def csv(self) -> str:
        """One row per speed and backlash (speed fastest): :data:`IMPACT_MAP_COLUMNS`; the force empty for a rigid
        train."""
        rows = [",".join(IMPACT_MAP_COLUMNS)]
        for i, b in enumerate(self.backlash_mm):
            for j, rpm in enumerate(self.speeds_rpm):
                f = self.max_impact_force_N[i, j]
                force = "" if np.isnan(f) else f"{f:.10g}"
                rows.append(f"{rpm:.10g},{b:.10g},{self.impact_velocity_m_per_s[i, j]:.10g},{force}")
        return "\n".join(rows) + "\n"


def impact_map(
    case: Case, speeds_rpm: np.ndarray, backlash_mm: np.ndarray, *, progress: Progress | None = None
) -> ImpactMap:
    """The largest crossover impact of the groove cam of ``case`` at every speed (rpm) and backlash (mm)."""
    assert case.follower is not None and case.follower.form_closed  # the caller asks only of a groove cam
    speeds, gaps = np.asarray(speeds_rpm, dtype=float), np.asarray(backlash_mm, dtype=float)
    if speeds.size * gaps.size > MAX_IMPACT_POINTS:
        raise InputError(
            "--speeds x --backlash",
            f"a grid of {speeds.size:,} speeds x {gaps.size:,} backlashes = {speeds.size * gaps.size:,} points is "
            f"beyond the groove sweep's budget of {MAX_IMPACT_POINTS:,} points (about 20 ms each): use fewer points",
        )
    v = np.zeros((gaps.size, speeds.size))
    f = np.full_like(v, np.nan)
    tick = counter(progress, f"{case.name}: impact map", v.size)
    for i, b in enumerate(gaps):
        follower = case.follower.model_copy(update={"backlash": float(b)})
        for j, rpm in enumerate(speeds):
            r = dyn.closure_response(case.motion, follower, case.model, float(rpm) * RPM)
            v[i, j] = r.max_impact_velocity_m_per_s
            if r.max_impact_force_N is not None and r.crossovers and b > 0.0:
                f[i, j] = r.max_impact_force_N
            tick()
    return ImpactMap(speeds, gaps, v, f, float(case.limits.max_impact_velocity))


BACKLASH_STEP_MM = 0.001  # a proposed backlash is rounded down to this: a slot width the shop can hold to
_BISECT_RTOL = 1e-6  # of the backlash, where the bisection stops


@dataclass(frozen=True)
class BacklashSizing:
    """The largest backlash (mm, rounded down to :data:`BACKLASH_STEP_MM`) at which the groove cam's impact speed
    stays within ``[limits] max_impact_velocity`` at ``speed_rpm``, with the margin of
    :data:`~camdyn._core.units.AT_LIMIT_RTOL` (the report calls a check closer to its limit "at limit"): 0 where
    no backlash of a step keeps it, ``inf`` where every backlash up to the roller radius does (the force never
    changes flank, or the impacts stay slow)."""

    case: str
    speed_rpm: float
    max_impact_velocity: float  # the limit, m/s
    current_backlash_mm: float
    current_impact_velocity_m_per_s: float
    max_backlash_mm: float
    impact_velocity_at_max_m_per_s: float  # at max_backlash_mm (0 where inf)
    closure: str = "groove"  # or "conjugate": the clearance at the conjugate cam

    @property
    def passes(self) -> bool:
        """Whether the case's own backlash keeps the limit."""
        return self.current_impact_velocity_m_per_s <= self.max_impact_velocity

    def json(self) -> dict:
        inf = np.isinf(self.max_backlash_mm)
        return {
            "case": self.case,
            "closure": self.closure,
            "speed_rpm": self.speed_rpm,
            "max_impact_velocity": self.max_impact_velocity,
            "backlash_mm": self.current_backlash_mm,
            "impact_velocity_m_per_s": self.current_impact_velocity_m_per_s,
            "max_backlash_mm": None if inf else self.max_backlash_mm,
            "impact_velocity_at_max_backlash_m_per_s": None if inf else self.impact_velocity_at_max_m_per_s,
        }


def largest_backlash(case: Case, speed_rpm: float | None = None) -> BacklashSizing:
    """The largest backlash that keeps the groove (or conjugate) cam of ``case`` within ``max_impact_velocity`` at
    ``speed_rpm``
    (default: the case's): doubled from the case's (or 0.01 mm) until the impact exceeds the limit less
    :data:`~camdyn._core.units.AT_LIMIT_RTOL`, then bisected,
    then rounded down to :data:`BACKLASH_STEP_MM` and its impact computed again (what ``check`` then gives)."""
    f = case.follower
    assert f is not None and f.form_closed and f.roller_radius is not None  # a groove holds a roller
    rpm = float(case.speed_rpm if speed_rpm is None else speed_rpm)
    lim = float(case.limits.max_impact_velocity)
    target = (1.0 - AT_LIMIT_RTOL) * lim  # passes check with margin, not at the limit

    def impact(b: float) -> float:
        follower = f.model_copy(update={"backlash": float(b)})
        return dyn.closure_response(case.motion, follower, case.model, rpm * RPM).max_impact_velocity_m_per_s

    v_now = impact(f.backlash)
    out = lambda b, v: BacklashSizing(case.name, rpm, lim, float(f.backlash), v_now, b, v, f.closure)  # noqa: E731
    lo, hi = 0.0, max(f.backlash, 10 * BACKLASH_STEP_MM)
    while impact(hi) <= target:
        lo, hi = hi, 2.0 * hi
        if lo >= f.roller_radius:
            return out(np.inf, 0.0)
    while hi - lo > _BISECT_RTOL * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if impact(mid) <= target else (lo, mid)
    b = round(math.floor(lo / BACKLASH_STEP_MM) * BACKLASH_STEP_MM, 9)  # 1.257, not 1.2570000000000001
    return out(b, impact(b) if b > 0.0 else 0.0)


PRELOAD_MARGIN = 1.2  # a proposed preload between conjugate rollers: 20 % over the least that keeps both loaded
PRELOAD_STEP = 0.1  # N (a yoke) or N*m (a rocker): a proposed preload is rounded up to this


@dataclass(frozen=True)
class PreloadSizing:
    """The least preload between conjugate cams' rollers (N for a yoke, N*m about the pivot for a rocker) that keeps
    both rollers loaded all round at ``speed_rpm``, and the one proposed: :data:`PRELOAD_MARGIN` x the least, rounded
    up to :data:`PRELOAD_STEP`. With equally stiff contacts each cam carries P +- F/2 of the net force F
    (:func:`camdyn.model.dynamics.preload_shares`), so both stay loaded while P > max |F| / 2."""

    case: str
    speed_rpm: float
    translating: bool
    max_net_force: float  # the largest |F| a revolution, N or N*m
    current_preload: float
    current_least_cam_force_N: float  # the least force on either cam with the case's preload (0: a roller unloads)
    proposed_preload: float
    proposed_least_cam_force_N: float  # the same with the proposed preload

    @property
    def least_preload(self) -> float:
        """max |F| / 2: the preload at which the more loaded angle just unloads a roller."""
        return 0.5 * self.max_net_force

    @property
    def holds(self) -> bool:
        """Whether the case's own preload keeps both rollers loaded all round."""
        return self.current_least_cam_force_N > 0.0

    def json(self) -> dict:
        unit = "_N" if self.translating else "_torque_N_m"
        return {
            "case": self.case,
            "closure": "conjugate",
            "speed_rpm": self.speed_rpm,
            f"preload{unit}": self.current_preload,
            "preload_held": self.holds,
            "least_cam_force_N": self.current_least_cam_force_N,
            "max_net_force_N" if self.translating else "max_net_torque_N_m": self.max_net_force,
            f"least_preload{unit}": self.least_preload,
            "margin": PRELOAD_MARGIN,
            f"proposed_preload{unit}": self.proposed_preload,
            "least_cam_force_at_proposed_N": self.proposed_least_cam_force_N,
        }


def least_preload(case: Case, speed_rpm: float | None = None) -> PreloadSizing:
    """The preload that keeps both rollers of the conjugate cams of ``case`` loaded at ``speed_rpm`` (default: the
    case's), with each cam's least force under the case's preload and the proposed one (:class:`CamLoads`)."""
    f = case.follower
    assert f is not None and f.closure == "conjugate" and f.backlash == 0.0  # a preload and a backlash exclude
    rpm = float(case.speed_rpm if speed_rpm is None else speed_rpm)
    r = dyn.closure_response(case.motion, f, case.model, rpm * RPM)
    f_max = float(np.max(np.abs(r.contact_force)))
    proposed = round(math.ceil(PRELOAD_MARGIN * 0.5 * f_max / PRELOAD_STEP) * PRELOAD_STEP, 9)

    def least_cam_force(preload: float) -> float:
        loads = cam_loads(case, r, preload)
        return float(min(np.min(loads.primary_N), np.min(loads.conjugate_N)))

    return PreloadSizing(
        case.name,
        rpm,
        f.translating,
        f_max,
        float(f.pair_preload),
        least_cam_force(f.pair_preload),
        proposed,
        least_cam_force(proposed),
    )


PRELOAD_MAP_COLUMNS = ("speed_rpm", "least_cam_force_N", "least_preload", "preload_held")


@dataclass(frozen=True)
class PreloadMap:
    """Conjugate cams under their preload over cam speed: the least force on either cam (N; 0 where a roller
    unloads) and the least preload that holds (half the largest |net force|: N, or N*m about the pivot) a
    revolution at each speed."""

    speeds_rpm: np.ndarray
    least_cam_force_N: np.ndarray
    least_preload: np.ndarray
    preload: float  # the case's, N or N*m
    translating: bool

    @property
    def columns(self) -> tuple[str, ...]:
        """:data:`PRELOAD_MAP_COLUMNS` with the preload's unit: ``least_preload_N`` or ``least_preload_torque_N_m``."""
        unit = "_N" if self.translating else "_torque_N_m"
        return tuple(c + unit if c == "least_preload" else c for c in PRELOAD_MAP_COLUMNS)

    @property
    def held(self) -> np.ndarray:
        """Whether the preload keeps both rollers loaded at each speed."""
        return self.least_cam_force_N > 0.0

    @property
    def csv(self) -> str:
        rows = [",".join(self.columns)]
        for rpm, f, p, h in zip(self.speeds_rpm, self.least_cam_force_N, self.least_preload, self.held, strict=True):
            rows.append(f"{rpm:.10g},{f:.10g},{p:.10g},{int(h)}")
        return "\n".join(rows) + "\n"


def preload_map(case: Case, speeds_rpm: np.ndarray, *, progress: Progress | None = None) -> PreloadMap:
    """The least cam force and the least holding preload of the conjugate cams of ``case`` at every speed (rpm)."""
    f = case.follower
    assert f is not None and f.closure == "conjugate"  # the caller asks only of conjugate cams
    speeds = np.asarray(speeds_rpm, dtype=float)
    if speeds.size > MAX_IMPACT_POINTS:
        raise InputError("--speeds", f"{speeds.size:,} speeds is beyond the sweep's budget of {MAX_IMPACT_POINTS:,}")
    least, need = np.zeros(speeds.size), np.zeros(speeds.size)
    tick = counter(progress, f"{case.name}: preload over speed", speeds.size)
    for j, rpm in enumerate(speeds):
        r = dyn.closure_response(case.motion, f, case.model, float(rpm) * RPM)
        loads = cam_loads(case, r, f.pair_preload)
        least[j] = min(np.min(loads.primary_N), np.min(loads.conjugate_N))
        need[j] = 0.5 * np.max(np.abs(r.contact_force))
        tick()
    return PreloadMap(speeds, least, need, float(f.pair_preload), f.translating)
