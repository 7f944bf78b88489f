"""The sizing problem: the follower in SI generalized units (N, m or N*m, rad), the speed range and the limits
(:class:`Problem`), and the angles its constraints are written on (:class:`Grid`). Both are immutable: cutting
planes give a new grid."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..._core.errors import InputError
from ..._core.kinds import FollowerKind
from ..._core.units import RPM, THETA_GRID, TWO_PI, damping_from_ratio
from ...model.follower import FollowerModel
from ...model.geometry import contact_per_force
from ...model.motion import Motion
from ...schema import FollowerSpec
from ..spring import min_preload
from ._quadratic import refine

STEP = TWO_PI / THETA_GRID  # rad: the kinematic grid's spacing
_BREAK_EPS = 1e-9  # rad: both sides of a segment boundary


@dataclass(frozen=True)
class Problem:
    """The case to size, in SI: the motion, the follower and its spring's damping law, the top speed W, the least
    contact force and the least rate, the full lift."""

    motion: Motion
    follower: FollowerSpec  # the lever arm of an oscillating follower
    model: FollowerModel
    kind: FollowerKind
    rigid: bool
    scale: float  # motion unit -> SI
    m: float  # kg (kg*m^2)
    ext: float  # N (N*m)
    kf: float  # train stiffness; inf: rigid
    c_fixed: float | None  # N*s/m (N*m*s/rad) where the damping is a constant, else None
    zeta: float  # damping ratio where c = 2 zeta sqrt(k m) follows the rate
    speed_rpm: float
    margin: float
    W: float  # rad/s: the constraints hold for every speed in [0, W]
    fmin: float  # N
    k_lo: float  # SI: the least rate
    f0_lo: float  # N (N*m): the least preload, ``[limits] min_preload`` (-inf: free)
    s_max: float = math.nan  # SI: full lift, polished between grid angles
    s_min: float = math.nan

    def damping(self, k) -> float:
        """The spring's damping at rate k (SI): constant, or 2 zeta sqrt(k m)."""
        if self.c_fixed is not None:
            return self.c_fixed
        return damping_from_ratio(self.zeta, max(k, 0.0), self.m)

    def values(self, theta):
        """s, s', s'' (SI, per rad) at angles ``theta`` (rad)."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        v = self.motion.host(theta)
        return v[0] * self.scale, v[1] * self.scale, v[2] * self.scale

    def arm(self, theta):
        """Lever arm (m) turning a contact force (N) into the generalized force; 1 for translating followers."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        return 1.0 / contact_per_force(self.motion, self.follower, theta)

    def with_spring(self, k, f0) -> FollowerModel:
        """The follower model with rate k and preload f0 (SI), its damping following the rate where it does."""
        return self.model.with_spring(float(k), float(f0))


@dataclass(frozen=True)
class Grid:
    """The constraint angles (rad, sorted) with the motion there (SI), the lever arm (m) and the part of the
    requirement that does not depend on the speed: ``F_min * arm - F_ext``."""

    theta: np.ndarray
    s: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    arm: np.ndarray
    req: np.ndarray

    @property
    def i_min(self) -> int:
        """Index of the least lift."""
        return int(np.argmin(self.s))

    def with_angles(self, p: Problem, ts) -> Grid:
        """The grid with angles ``ts`` added (cutting planes), kept sorted."""
        ts = np.mod(np.asarray(ts, dtype=float), 2 * math.pi)
        s, s1, s2 = p.values(ts)
        theta = np.concatenate([self.theta, ts])
        order = np.argsort(theta, kind="stable")
        s, s1, s2 = (np.concatenate([a, b])[order] for a, b in ((self.s, s), (self.s1, s1), (self.s2, s2)))
        arm = np.concatenate([self.arm, p.arm(ts)])[order]
        return Grid(theta[order], s, s1, s2, arm, p.fmin * arm - p.ext)


def _polish_extreme(p: Problem, t0: float, v0: float, sign: int) -> float:
    _, v = refine(lambda t: -sign * p.values(t)[0], np.array([t0]), STEP)
    v = -sign * float(v[0])
    return max(v0, v) if sign > 0 else min(v0, v)


def _damping_law(model: FollowerModel) -> tuple[float | None, float]:
    """(c_fixed, zeta) from the model: its damping ratio is NaN where the damping was given as a constant."""
    ratio = float(model.damping_ratio)
    return (float(model.damping), 0.0) if math.isnan(ratio) else (None, ratio)


def build_problem(case, max_speed_rpm, margin, min_rate) -> tuple[Problem, Grid]:
    """The problem and its first grid: 3600 angles and both sides of every segment boundary."""
    kind, model = case.kind, case.model
    if kind.rotary and case.follower is None:
        raise InputError("follower", f"{kind.a} follower needs its geometry (lever arm) for sizing")
    c_fixed, zeta = _damping_law(model)
    speed_rpm = float(case.speed_rpm if max_speed_rpm is None else max_speed_rpm)
    margin = float(case.limits.speed_margin if margin is None else margin)
    p = Problem(
        motion=case.motion,
        follower=case.follower,
        model=model,
        kind=kind,
        rigid=model.rigid,
        scale=model.scale,
        m=float(model.mass),
        ext=float(model.external),
        kf=float(model.train_stiffness),
        c_fixed=c_fixed,
        zeta=zeta,
        speed_rpm=speed_rpm,
        margin=margin,
        W=margin * speed_rpm * RPM,
        fmin=float(case.limits.min_contact_force),
        k_lo=kind.rate_to_si(float(min_rate)),
        f0_lo=min_preload(case),
    )
    if p.fmin < 0.0:
        raise InputError(
            "limits.min_contact_force",
            f"sizing needs a least contact force >= 0 N (got {p.fmin:g}): below 0 the follower has left the cam",
        )
    theta = np.arange(THETA_GRID) * (TWO_PI / THETA_GRID)
    breaks = np.deg2rad(np.asarray(p.motion.breaks_deg, dtype=float))
    theta = np.unique(np.mod(np.concatenate([theta, breaks - _BREAK_EPS, breaks + _BREAK_EPS]), TWO_PI))
    arm = p.arm(theta)
    grid = Grid(theta, *p.values(theta), arm, p.fmin * arm - p.ext)
    i_max, i_min = int(np.argmax(grid.s)), grid.i_min
    s_max = _polish_extreme(p, theta[i_max], float(grid.s[i_max]), +1)
    s_min = _polish_extreme(p, theta[i_min], float(grid.s[i_min]), -1)
    if not s_max - s_min > 1e-12 * max(1.0, abs(s_max)):
        raise InputError("motion", "the follower does not move: there is no spring to size")
    return replace(p, s_max=s_max, s_min=s_min), grid
