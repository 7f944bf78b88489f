"""Spring sizing: the return spring with the least peak force that keeps the follower on the cam.

**Problem.** Choose the spring rate k and preload F0 so that the interface force stays at or above
``[limits] min_contact_force`` (F_min) at every cam angle and every cam speed w in [0, W], W = margin * the
maximum speed, with the least peak spring force ``P = max_theta (k s + F0) = k s_max + F0`` (it drives the cam
stress, the wear and the drive torque). k >= ``min_rate`` (default 0); F0 is free.

**Kinematic answer (linear program).** The interface force of a follower that stays on the cam,
``Fi(theta, w) = m w^2 s'' + c w s' + k s + F0 + F_ext``, is linear in (k, F0) at every angle and speed. At each
angle it is a quadratic in w, so its least value over [0, W] is closed form: at w = 0, at w = W, or at the vertex
w = -c s' / (2 m s'') where m s'' > 0 > c s'. So every angle gives one constraint, exact for all speeds at once:
``s_i k + F0 >= r_i``, ``r_i = F_min - F_ext - min_w (m w^2 s''_i + c w s'_i)``. On 3600 angles (and both sides
of every segment boundary) this is a linear program in (k, F0), solved by ``scipy.optimize.linprog`` (HiGHS);
the angles between grid points where the answer would be violated are found by local minimization and added as
cutting planes until none is violated by more than 1e-9 of the force scale.

**Ties.** With c constant the peak force ``P(k) = max_i (r_i + k (s_max - s_i))`` never decreases with k
(F0 >= r_i - k s_i and s_i <= s_max), so the least rate attains the least peak force P* = P(k_lo); with
k_lo = 0 that is a constant-force spring. A rate only costs peak force, by k (s_max - s_bind), unless the binding
angle is at full lift; then the optimum is the segment k in [k_lo, k_end] of the line k s_max + F0 = P*,
``k_end = min over s_i < s_max of (P* - r_i) / (s_max - s_i)`` (the eccentric cam is the example). Ties are
broken towards the least preload: k_end, the stiffest optimal spring, which also has the least mean spring force
over the revolution (``k mean(s) + F0 = P - k (s_max - mean(s))``); it is what a second, lexicographic LP
minimizing F0 at P* returns, computed in closed form (no LP tolerance), and the LP's P* is checked against the
closed form. ``min_rate`` bounds k from below: a real spring has a rate, and with the rate you have the answer
is the least preload for it.

**Damping.** ``damping`` (N*s/m) is a constant c and the LP above is exact. With ``damping_ratio``,
c = 2 zeta sqrt(k m) depends on k; then for each k the least preload is still closed form,
``F0(k) = max_i (r_i(sqrt k) - k s_i)``, and the peak force ``P = k s_max + F0(k)`` is convex in u = sqrt(k)
(r_i is the maximum over w of functions affine in u, and (s_max - s_i) u^2 is convex), so it is minimized exactly
in u (bounded Brent), with the same tie-break (the largest k whose peak force is within 1e-11 of the least).
(Freezing c at one value and iterating the LP to a fixed point does not find this optimum: with c frozen the LP
puts k at 0, where c = 0, although a little damping on a rising binding angle lowers the requirement like sqrt k.)

**Dynamic correction.** A compliant follower train (``train_stiffness``) jumps below its kinematic jump speed,
so the kinematic answer can fail at W. In contact the model is linear, and its steady state is exact in the
frequency domain (:func:`camdyn.dynamics.linear_contact_force`); the preload only shifts its mean:
``Fc(theta, w; k, F0) = alpha F0 + G(theta, w; k)``, alpha = k_f / (k + k_f). So for each k the least preload is
exact, ``F0_dyn(k) = max over theta and w of (F_min - G) / alpha``, with w on 0 and 160 speeds up to W refined
twice around the worst. The dynamic peak force ``k s_max + F0_dyn(k)`` is minimized over k (scan in sqrt k from
min_rate to the rate beyond which even the static requirement at least lift costs more than the kinematic
answer does dynamically, then bounded Brent around the best), ties within 1e-6 broken the same way (largest k).
The answer is then verified on 1127 speeds in [0, W] and F0 raised by any remaining deficit / alpha. Rigid
followers: the dynamic interface force is the kinematic one, and the kinematic answer is the answer.

**Oscillating followers** are sized in their rotational units: torsion rate (N*m/rad), preload torque (N*m),
peak spring torque (N*m); the contact force limit F_min (N) becomes the torque ``F_min * lever_arm(theta)`` at
each angle (the same conversion ``check`` uses), which keeps every constraint linear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import jax.numpy as jnp
import numpy as np
from scipy.optimize import linprog, minimize_scalar

from .._core.errors import InputError, NumericalError
from .._core.units import FFT_GRID, RPM, THETA_GRID, TWO_PI, damping_from_ratio, rate_from_si, rate_to_si
from ..model import dynamics as dyn
from ..model.geometry import newton_per_torque_at
from ..model.motion import evaluate
_N_THETA = THETA_GRID  # kinematic LP grid
_N_FFT = FFT_GRID  # frequency-domain steady state
_N_SPEEDS = 160  # dynamic requirement: 0 and 160 speeds up to W
_N_REFINE = 17
_N_VERIFY_CHUNKS = 7  # verification: 7 * 161 speeds in [0, W]
_N_SCAN = 24
_TIE_KIN = 1e-11  # one-dimensional (damping_ratio) ties; the LP's are exact
_TIE_DYN = 1e-6
_BREAK_EPS = 1e-9  # rad: both sides of a segment boundary

TIE_BREAK = (
    "the least peak spring force is reached by more than one spring only where the binding angle is at full lift; "
    "then the one with the least preload is chosen (the stiffest, which also has the least mean spring force): "
    "exactly, as a second lexicographic LP minimizing the preload at the least peak force would, for constant "
    "damping; else the largest rate whose peak force is within 1e-11 (kinematic) or 1e-6 (dynamic) of the least. "
    "Otherwise the least peak force needs the least rate (min_rate; 0 is a constant-force spring)"
)


def _least_quadratic(a, b, w_top):
    """min over w in [0, w_top] of a w^2 + b w, and the speed where it is reached (vectorized)."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    g_top = a * w_top * w_top + b * w_top
    with np.errstate(invalid="ignore", divide="ignore"):
        wv = np.where((a > 0) & (b < 0), -b / np.where(a > 0, 2 * a, 1.0), np.inf)
        gv = np.where(wv < w_top, -b * b / np.where(a > 0, 4 * a, 1.0), np.inf)
    cand = np.stack([np.zeros_like(a), g_top, gv])
    i = np.argmin(cand, axis=0)
    w = np.choose(i, [np.zeros_like(a), np.full_like(a, w_top), np.where(np.isfinite(wv), wv, 0.0)])
    return np.min(cand, axis=0), w


def _most_quadratic(a, b, w_top):
    """max over w in [0, w_top] of a w^2 + b w, and the speed where it is reached."""
    g, w = _least_quadratic(-np.asarray(a, float), -np.asarray(b, float), w_top)
    return -g, w


def _refine(fn, t0, h, rounds=3, points=41):
    """Vectorized local minimization of fn (array -> array) in [t0 - h, t0 + h] for each start in t0: a grid
    of ``points`` angles, then again around the best, ``rounds`` times (resolution 2 h / 20^rounds)."""
    ts = np.asarray(t0, dtype=float)
    if ts.size == 0:
        return ts, ts
    offsets = np.linspace(-1.0, 1.0, points)
    best_v = np.asarray(fn(ts), dtype=float)
    for _ in range(rounds):
        cand = ts[:, None] + h * offsets[None, :]
        v = np.asarray(fn(cand.ravel()), dtype=float).reshape(cand.shape)
        j = np.argmin(v, axis=1)
        vj = v[np.arange(len(ts)), j]
        better = vj < best_v
        ts = np.where(better, cand[np.arange(len(ts)), j], ts)
        best_v = np.minimum(vj, best_v)
        h *= 2.0 / (points - 1)
    return ts, best_v


def _inf_none(x: float) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


# ------------------------------------------------------------------------------------------ results
@dataclass(frozen=True)
class SpringDesign:
    """One spring (rate, preload) and what it does; user units (N/mm and N, or N*m/rad and N*m)."""

    rate: float  # N/mm (translating) or N*m/rad (oscillating)
    preload: float  # N or N*m
    peak_spring: float  # k s_max + F0: N or N*m
    least_force_kinematic: float  # N: least kinematic interface force over angles and speeds in [0, W]
    least_force: float  # N: least dynamic interface force over angles and speeds in [0, W] (rigid: kinematic)
    least_force_deg: float
    least_force_rpm: float
    peak_contact: float  # N: largest interface force over angles and speeds in [0, W]
    peak_contact_deg: float
    peak_contact_rpm: float
    kinematic_jump_rpm: float  # inf: none
    dynamic_jump_rpm: float

    def holds(self, fmin: float) -> bool:
        """Whether the least contact force meets ``fmin`` (N), to 1e-6 of the peak contact force."""
        return bool(self.least_force >= fmin - 1e-6 * max(1.0, abs(self.peak_contact)))

    def json(self, oscillating: bool, fmin: float) -> dict:
        if oscillating:
            keys = {"torsion_rate_N_m_per_rad": self.rate, "preload_torque_N_m": self.preload, "peak_spring_torque_N_m": self.peak_spring}
        else:
            keys = {"spring_rate_N_per_mm": self.rate, "preload_N": self.preload, "peak_spring_force_N": self.peak_spring}
        return keys | {
            "least_contact_force_N": self.least_force,
            "least_contact_force_deg": self.least_force_deg,
            "least_contact_force_rpm": self.least_force_rpm,
            "kinematic_least_contact_force_N": self.least_force_kinematic,
            "peak_contact_force_N": self.peak_contact,
            "peak_contact_force_deg": self.peak_contact_deg,
            "peak_contact_force_rpm": self.peak_contact_rpm,
            "kinematic_jump_speed_rpm": _inf_none(self.kinematic_jump_rpm),
            "dynamic_jump_speed_rpm": _inf_none(self.dynamic_jump_rpm),
            "holds": self.holds(fmin),
        }


@dataclass(frozen=True)
class SpringSizing:
    """The result of :func:`size_spring`: the chosen spring, the kinematic LP answer it was corrected from,
    the case's current spring, the least preload at the current rate, and the feasible region."""

    case_name: str
    oscillating: bool
    model: str  # "rigid" | "compliant"
    speed_rpm: float  # the maximum operating speed
    margin: float
    top_speed_rpm: float  # margin * speed_rpm: the constraints hold for every speed up to this
    min_contact_force: float  # N
    min_rate: float  # user units
    s_max: float  # mm or rad: the full lift (the spring's peak deflection beyond its preload)
    chosen: SpringDesign
    kinematic: SpringDesign  # the LP answer before the dynamic correction (== chosen for rigid followers)
    current: SpringDesign
    at_current_rate: SpringDesign  # the least preload that holds with the case's own rate
    binding: tuple[tuple[float, float, float], ...]  # kinematic answer: (start_deg, end_deg, speed_rpm)
    dynamic_binding: tuple[float, float] | None  # chosen, compliant: (theta_deg, speed_rpm) of the least force
    damping: str  # how c was treated
    method: str
    region_rate: np.ndarray = field(repr=False)  # user units
    region_preload_kinematic: np.ndarray = field(repr=False)  # least preload per rate (kinematic)
    region_preload_dynamic: np.ndarray | None = field(repr=False)  # least preload per rate (dynamic), compliant
    lines: tuple[tuple[float, float, float], ...] = field(repr=False, default=())  # (theta_deg, s, r): F0 >= r - k s
    warnings: tuple[str, ...] = ()

    @property
    def units(self) -> dict:
        if self.oscillating:
            return {"rate": "N*m/rad", "preload": "N*m", "spring": "N*m", "lift": "rad"}
        return {"rate": "N/mm", "preload": "N", "spring": "N", "lift": "mm"}

    def json(self) -> dict:
        osc, fmin = self.oscillating, self.min_contact_force
        chosen = self.chosen.json(osc, fmin)
        out = {
            "case": self.case_name,
            "follower": "oscillating" if osc else "translating",
            "model": self.model,
            "max_speed_rpm": self.speed_rpm,
            "margin": self.margin,
            "sized_to_rpm": self.top_speed_rpm,
            "min_contact_force_N": fmin,
            "min_rate": self.min_rate,
            "units": self.units,
            "spring_rate_N_per_mm": None,
            "preload_N": None,
            "peak_spring_force_N": None,
            "torsion_rate_N_m_per_rad": None,
            "preload_torque_N_m": None,
            "peak_spring_torque_N_m": None,
        }
        out |= chosen
        out["jump_speed_rpm"] = chosen["dynamic_jump_speed_rpm"]  # what `check` judges the margin on
        kin = self.kinematic.json(osc, fmin)
        out["kinematic_answer"] = kin
        rate_key, pre_key, peak_key = list(chosen)[:3]
        out["dynamic_correction"] = {
            rate_key: chosen[rate_key] - kin[rate_key],
            pre_key: chosen[pre_key] - kin[pre_key],
            peak_key: chosen[peak_key] - kin[peak_key],
            "dynamic_jump_speed_rpm": None if None in (chosen["dynamic_jump_speed_rpm"], kin["dynamic_jump_speed_rpm"]) else chosen["dynamic_jump_speed_rpm"] - kin["dynamic_jump_speed_rpm"],
        }
        out["current"] = self.current.json(osc, fmin)
        out["at_current_rate"] = self.at_current_rate.json(osc, fmin)
        out["binding"] = [{"start_deg": a, "end_deg": b, "speed_rpm": w} for a, b, w in self.binding]
        out["dynamic_binding"] = None if self.dynamic_binding is None else {"theta_deg": self.dynamic_binding[0], "speed_rpm": self.dynamic_binding[1]}
        out["tie_break"] = TIE_BREAK
        out["damping"] = self.damping
        out["method"] = self.method
        step = max(1, len(self.region_rate) // 20)
        out["feasible_region"] = {
            "description": f"feasible: preload >= least preload(rate); rate >= {self.min_rate:g} {self.units['rate']}",
            "rate": self.region_rate[::step].tolist(),
            "least_preload_kinematic": self.region_preload_kinematic[::step].tolist(),
            "least_preload_dynamic": None if self.region_preload_dynamic is None else self.region_preload_dynamic[::step].tolist(),
        }
        out["warnings"] = list(self.warnings)
        return out


# ------------------------------------------------------------------------------------------ problem
class _Problem:
    """The case in SI generalized units (N, m or N*m, rad) on the LP angle grid."""

    def __init__(self, case, max_speed_rpm, margin, min_rate):
        self.case, self.motion, self.model = case, case.motion, case.model
        self.osc = case.oscillating
        if self.osc and case.follower is None:
            raise InputError("follower", "an oscillating follower needs its geometry (lever arm) for sizing")
        m = self.model
        d = case.spec.dynamics
        self.rigid = m.rigid
        self.scale = m.scale
        self.m, self.ext, self.kf = float(m.mass), float(m.external), float(m.train_stiffness)
        self.c_fixed = float(d.damping) if d.damping is not None else None
        self.zeta = float(d.damping_ratio or 0.0)
        self.speed_rpm = float(case.speed_rpm if max_speed_rpm is None else max_speed_rpm)
        self.margin = float(case.limits.speed_margin if margin is None else margin)
        self.W = self.margin * self.speed_rpm * RPM
        self.fmin = float(case.limits.min_contact_force)
        self.k_lo = rate_to_si(float(min_rate), self.osc)
        if self.fmin < 0.0:
            raise InputError("limits.min_contact_force", f"sizing needs a least contact force >= 0 N (got {self.fmin:g}): below 0 the follower has left the cam")

        theta = np.arange(_N_THETA) * (TWO_PI / _N_THETA)
        breaks = np.deg2rad(np.asarray(self.motion.breaks_deg, dtype=float))
        theta = np.unique(np.mod(np.concatenate([theta, breaks - _BREAK_EPS, breaks + _BREAK_EPS]), TWO_PI))
        self.theta = theta
        self.step = TWO_PI / _N_THETA
        self.s, self.s1, self.s2 = self._vals(theta)
        self.arm = self._arm(theta)
        self.req = self.fmin * self.arm - self.ext  # required spring force + inertia, before the speed terms
        i_max, i_min = int(np.argmax(self.s)), int(np.argmin(self.s))
        self.s_max = self._polish_extreme(theta[i_max], float(self.s[i_max]), +1)
        self.s_min = self._polish_extreme(theta[i_min], float(self.s[i_min]), -1)
        self.i_min = i_min
        if not self.s_max - self.s_min > 1e-12 * max(1.0, abs(self.s_max)):
            raise InputError("motion", "the follower does not move: there is no spring to size")

    def add_angles(self, ts) -> None:
        """Add angles (cutting planes) to the constraint set, keeping it sorted."""
        ts = np.mod(np.asarray(ts, dtype=float), 2 * math.pi)
        s, s1, s2 = self._vals(ts)
        theta = np.concatenate([self.theta, ts])
        order = np.argsort(theta, kind="stable")
        self.theta = theta[order]
        self.s, self.s1, self.s2 = (np.concatenate([a, b])[order] for a, b in ((self.s, s), (self.s1, s1), (self.s2, s2)))
        self.arm = np.concatenate([self.arm, self._arm(ts)])[order]
        self.req = self.fmin * self.arm - self.ext
        self.i_min = int(np.argmin(self.s))

    # ---- motion values
    def _vals(self, theta):
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        if hasattr(self.motion, "_eval"):
            v = np.asarray(self.motion._eval(np, theta))
        else:
            v = np.asarray(evaluate(self.motion, jnp.asarray(theta)))
        return v[0] * self.scale, v[1] * self.scale, v[2] * self.scale

    def _arm(self, theta):
        """Lever arm (m) turning a contact force (N) into the generalized force; 1 for translating followers."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        if not self.osc:
            return np.ones_like(theta)
        return 1.0 / newton_per_torque_at(self.motion, self.case.follower, theta)

    def _polish_extreme(self, t0, v0, sign):
        _, v = _refine(lambda t: -sign * self._vals(t)[0], np.array([t0]), self.step)
        v = -sign * float(v[0])
        return max(v0, v) if sign > 0 else min(v0, v)

    def damping(self, k):
        if self.c_fixed is not None:
            return self.c_fixed
        return damping_from_ratio(self.zeta, max(k, 0.0), self.m)

    # ---- kinematic requirement
    def required(self, c, s1=None, s2=None, req=None):
        """r_i = F_min arm - F_ext - min over w in [0, W] of (m w^2 s'' + c w s'), and the speed of that minimum."""
        s1 = self.s1 if s1 is None else s1
        s2 = self.s2 if s2 is None else s2
        req = self.req if req is None else req
        g, w = _least_quadratic(self.m * s2, c * s1, self.W)
        return req - g, w

    def slack_at(self, theta, k, f0, c):
        s, s1, s2 = self._vals(theta)
        r, _ = self.required(c, s1, s2, self.fmin * self._arm(theta) - self.ext)
        return k * s + f0 - r

    def worst_between(self, k, f0, c, count=8):
        """Angles off the grid where the slack is least: refined from the grid's least local minima.

        Returns [(slack, theta)] sorted by slack."""
        r, _ = self.required(c)
        slack = k * self.s + f0 - r
        local = np.nonzero((slack <= np.roll(slack, 1)) & (slack <= np.roll(slack, -1)))[0]
        local = local[np.argsort(slack[local])][:count]
        ts, vals = _refine(lambda t: self.slack_at(t, k, f0, c), self.theta[local], self.step)
        return sorted(zip(vals.tolist(), (np.mod(ts, 2 * math.pi)).tolist(), strict=True))

    def preload_kinematic(self, k, polish=False):
        """The least preload that holds with rate k (grid; ``polish``: also between grid points)."""
        c = self.damping(k)
        r, _ = self.required(c)
        f0 = float(np.max(r - k * self.s))
        if polish:
            worst = self.worst_between(k, f0, c)
            if worst and worst[0][0] < 0.0:
                f0 -= worst[0][0]
        return f0

    def binding(self, k, f0):
        """Where the kinematic constraint is active (slack within 1e-6 of the force scale), as
        (start_deg, end_deg, speed_rpm): runs of grid angles (a dwell) and single angles refined off the grid."""
        c = self.damping(k)
        tol = 1e-6 * max(1.0, abs(k * self.s_max + f0))
        r, w = self.required(c)
        on = k * self.s + f0 - r <= tol
        n = len(on)
        runs, i = [], 0
        while i < n:
            if on[i]:
                j = i
                while j + 1 < n and on[j + 1]:
                    j += 1
                runs.append([i, j])
                i = j + 1
            else:
                i += 1
        if len(runs) > 1 and runs[0][0] == 0 and runs[-1][1] == n - 1:  # a run across 0 deg
            runs[0][0] = runs.pop()[0]
        span = lambda a, b: (self.theta[b] - self.theta[a]) % (2 * math.pi)  # noqa: E731
        out = [(math.degrees(self.theta[a]), math.degrees(self.theta[b]), float(max(w[a], w[b])) / RPM) for a, b in runs if span(a, b) >= 2.5 * self.step]
        for v, t in self.worst_between(k, f0, c):
            if v > tol:
                continue
            deg = math.degrees(t)
            if any((a <= deg <= b) if a <= b else (deg >= a or deg <= b) for a, b, _ in out):
                continue
            if any(abs((deg - a + 180.0) % 360.0 - 180.0) < 1e-4 for a, _, _ in out):
                continue
            s, s1, s2 = self._vals(t)
            _, wt = self.required(c, s1, s2, self.fmin * self._arm(t) - self.ext)
            out.append((deg, deg, float(wt[0]) / RPM))
        out = [(round(a, 6) % 360.0, round(b, 6) % 360.0, round(wv, 9)) for a, b, wv in sorted(out)]
        return tuple(out[:12])

    # ---- linear program (constant damping)
    def lp(self, c):
        """The kinematic LP at constant damping c, with cutting planes and the tie-break. Returns (k, F0).

        HiGHS solves ``min k s_max + F0 s.t. s_i k + F0 >= r_i, k >= k_lo``. Its value is also closed form: the
        peak ``P(k) = max_i (r_i + k (s_max - s_i))`` never decreases with k, so P* = P(k_lo), and the springs
        reaching it are k in [k_lo, k_end], ``k_end = min over s_i < s_max of (P* - r_i) / (s_max - s_i)``. The
        tie-break takes k_end, the least preload F0 = P* - k_end s_max: what a second, lexicographic LP minimizing
        F0 at the optimal peak returns, without its tolerance. The LP value is checked against P* (1e-7).
        """
        opts = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
        for _ in range(8):
            s = self.s
            r, _ = self.required(c)
            a_ub = -np.column_stack([s / self.s_max, np.ones_like(s)])  # variables: k s_max (N), F0 (N)
            bounds = [(self.k_lo * self.s_max, None), (None, None)]
            res = linprog([1.0, 1.0], A_ub=a_ub, b_ub=-r, bounds=bounds, method="highs", options=opts)
            if res.status != 0:
                raise NumericalError("sizing", f"the linear program failed: {res.message}")
            gap = self.s_max - s
            peak = float(np.max(r + self.k_lo * gap))
            if abs(float(res.fun) - peak) > 1e-7 * max(1.0, abs(peak)):
                raise NumericalError("sizing", f"the linear program's least peak force {res.fun:.10g} disagrees with the closed form {peak:.10g}")
            tie = gap > 1e-12 * self.s_max
            k = max(self.k_lo, float(np.min((peak - r[tie]) / gap[tie]))) if tie.any() else self.k_lo
            f0 = peak - k * self.s_max
            if not self.cut(k, f0, c):
                return k, f0
        return k, self.preload_kinematic(k, polish=True)

    def cut(self, k, f0, c) -> bool:
        """Add the off-grid angles where (k, f0) violates the kinematic constraint by > 1e-9 of the peak."""
        tol = 1e-9 * max(1.0, abs(k * self.s_max + f0))
        new = [t for v, t in self.worst_between(k, f0, c) if v < -tol]
        if new:
            self.add_angles(new)
        return bool(new)

    # ---- one-dimensional minimization in u = sqrt(k)
    def minimize_in_sqrt_k(self, peak_of, u_lo, u_hi, rtol, scan=0, seeds=()):
        """argmin of peak_of(u) on [u_lo, u_hi], ties broken towards the largest u within rtol of the least."""
        cache: dict[float, float] = {}

        def f(u):
            u = float(min(max(u, u_lo), u_hi))
            if u not in cache:
                cache[u] = float(peak_of(u))
            return cache[u]

        if scan:
            grid = np.unique(np.concatenate([np.linspace(u_lo, u_hi, scan), np.clip(np.asarray(seeds, float), u_lo, u_hi)]))
            vals = np.array([f(u) for u in grid])
            i = int(np.argmin(vals))
            a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
        else:
            a, b = u_lo, u_hi
        if b > a:
            res = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-10 * max(1.0, u_hi)})
            f(res.x)
        for u in (u_lo, u_hi, *seeds):
            f(u)
        u_best = min(cache, key=lambda u: (cache[u], -u))
        best = cache[u_best]
        cap = best + rtol * max(1.0, abs(best))
        right = sorted(u for u in cache if u > u_best)
        lo, hi = u_best, None
        for u in right:  # walk right over known points still within the tie tolerance
            if cache[u] <= cap:
                lo = u
            else:
                hi = u
                break
        if hi is not None:
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                if hi - lo <= 1e-12 * max(1.0, u_hi):
                    break
                lo, hi = (mid, hi) if f(mid) <= cap else (lo, mid)
        return lo

    # ---- dynamics
    def fft_setup(self):
        if not hasattr(self, "req_f"):
            theta_f = np.arange(_N_FFT) * (TWO_PI / _N_FFT)
            self.arm_f = self._arm(theta_f)
            self.req_f = self.fmin * self.arm_f
            self.speeds = np.linspace(0.0, self.W, _N_SPEEDS + 1)

    def with_spring(self, k, f0):
        return self.model.with_spring(float(k), float(f0))

    def contact_force(self, k, f0, speeds):
        """Frequency-domain steady-state interface force (N or N*m), shape (len(speeds), _N_FFT)."""
        out = np.asarray(dyn.linear_contact_force(self.motion, self.with_spring(k, f0), jnp.asarray(speeds, dtype=float), _N_FFT))
        if not np.all(np.isfinite(out)):
            raise NumericalError(f"sizing, rate {rate_from_si(k, self.osc):.4g}", "the steady-state contact force is not finite")
        return out

    def preload_dynamic(self, k, refine=True):
        """The least preload for rate k from the dynamic model: (F0, theta_deg, speed_rpm) of the binding point."""
        self.fft_setup()
        alpha = self.kf / (k + self.kf)

        def worst(speeds):
            d = self.req_f[None, :] - self.contact_force(k, 0.0, speeds)
            j = np.argmax(d, axis=1)
            dm = d[np.arange(len(speeds)), j]
            i = int(np.argmax(dm))
            return float(dm[i]), float(speeds[i]), int(j[i])

        best, w, j = worst(self.speeds)
        if refine:
            h = self.speeds[1] - self.speeds[0]
            for _ in range(2):
                ws = np.linspace(max(w - h, 0.0), min(w + h, self.W), _N_REFINE)
                b2, w2, j2 = worst(ws)
                if b2 > best:
                    best, w, j = b2, w2, j2
                h = ws[1] - ws[0]
        return best / alpha, 360.0 * j / _N_FFT, w / RPM

    def verify(self, k, f0):
        """Least and largest dynamic interface force (N) on 1127 speeds in [0, W] (values and where), and the
        least slack of the requirement (N or N*m)."""
        key = (float(k), float(f0))
        cache = self.__dict__.setdefault("_verified", {})
        if key not in cache:
            cache[key] = self._verify(k, f0)
        return cache[key]

    def _verify(self, k, f0):
        self.fft_setup()
        speeds = np.linspace(0.0, self.W, _N_VERIFY_CHUNKS * (_N_SPEEDS + 1))
        lo = (math.inf, 0, 0.0)
        hi = (-math.inf, 0, 0.0)
        slack_min = math.inf
        for chunk in speeds.reshape(_N_VERIFY_CHUNKS, -1):
            fc = self.contact_force(k, f0, chunk)
            slack_min = min(slack_min, float(np.min(fc - self.req_f[None, :])))
            fn = fc / self.arm_f[None, :]
            i, j = np.unravel_index(int(np.argmin(fn)), fn.shape)
            if fn[i, j] < lo[0]:
                lo = (float(fn[i, j]), 360.0 * j / _N_FFT, float(chunk[i]) / RPM)
            i, j = np.unravel_index(int(np.argmax(fn)), fn.shape)
            if fn[i, j] > hi[0]:
                hi = (float(fn[i, j]), 360.0 * j / _N_FFT, float(chunk[i]) / RPM)
        return lo, hi, slack_min

    # ---- evaluation of one spring
    def design(self, k, f0) -> SpringDesign:
        c = self.damping(k)
        base = k * self.s + f0 + self.ext
        g_lo, w_lo = _least_quadratic(self.m * self.s2, c * self.s1, self.W)
        g_hi, w_hi = _most_quadratic(self.m * self.s2, c * self.s1, self.W)
        f_lo, f_hi = (base + g_lo) / self.arm, (base + g_hi) / self.arm
        i, j = int(np.argmin(f_lo)), int(np.argmax(f_hi))
        kin_lo = (float(f_lo[i]), math.degrees(self.theta[i]), float(w_lo[i]) / RPM)
        kin_hi = (float(f_hi[j]), math.degrees(self.theta[j]), float(w_hi[j]) / RPM)
        model = self.with_spring(k, f0)
        w_kin = dyn.kinematic_jump_speed(self.motion, model)[0] if np.min(base) >= 0.0 else 0.0
        if self.rigid:
            lo, hi, w_dyn = kin_lo, kin_hi, w_kin
        else:
            lo, hi, _ = self.verify(k, f0)
            w_max = 4.0 * max(self.W, w_kin if math.isfinite(w_kin) else 0.0)
            w_dyn = dyn.dynamic_jump_speed(self.motion, model, w_max=w_max) if np.min(base) >= 0.0 else 0.0
        return SpringDesign(
            rate=rate_from_si(k, self.osc),
            preload=f0,
            peak_spring=k * self.s_max + f0,
            least_force_kinematic=kin_lo[0],
            least_force=lo[0],
            least_force_deg=lo[1],
            least_force_rpm=lo[2],
            peak_contact=hi[0],
            peak_contact_deg=hi[1],
            peak_contact_rpm=hi[2],
            kinematic_jump_rpm=w_kin / RPM,
            dynamic_jump_rpm=w_dyn / RPM,
        )


# ------------------------------------------------------------------------------------------ sizing
def _kinematic_answer(p: _Problem) -> tuple[float, float, str, str]:
    """(k, F0) of the kinematic problem, how damping was treated, and the method."""
    if p.c_fixed is not None or p.zeta == 0.0:
        k, f0 = p.lp(p.damping(0.0))
        what = "no damping" if p.damping(0.0) == 0.0 else f"constant damping c = {p.c_fixed:g} {'N*m*s/rad' if p.osc else 'N*s/m'}"
        return k, f0, f"{what}: the linear program is exact", "linear program (scipy linprog, HiGHS) with cutting planes, checked against its closed form; tie-break in closed form"
    # c = 2 zeta sqrt(k m): exact minimization of the peak force, convex in u = sqrt(k)
    k_lo = p.k_lo
    peak_lo = k_lo * p.s_max + p.preload_kinematic(k_lo)
    k_hi = max(k_lo, (peak_lo - p.req[p.i_min]) / (p.s_max - p.s[p.i_min]))
    k_hi = max(k_hi, 2.0 * k_lo, 1e-12)
    for _ in range(6):  # cutting planes: refine the angle set where the answer is violated between grid points
        u = p.minimize_in_sqrt_k(lambda u: u * u * p.s_max + p.preload_kinematic(u * u), math.sqrt(k_lo), math.sqrt(k_hi), _TIE_KIN)
        k = u * u
        f0 = p.preload_kinematic(k)
        if not p.cut(k, f0, p.damping(k)):
            break
    f0 = p.preload_kinematic(k, polish=True)
    note = (
        f"c = 2 zeta sqrt(k m) with zeta = {p.zeta:g} follows the rate: for each k the least preload is closed form and the "
        "peak force, convex in sqrt(k), is minimized exactly in sqrt(k) (not a frozen-c LP)"
    )
    return k, f0, note, "exact minimization of the peak force in sqrt(k) (bounded Brent; ties to the largest k)"


def size_spring(case, max_speed_rpm: float | None = None, margin: float | None = None, min_rate: float = 0.0) -> SpringSizing:
    """Size the return spring of ``case``: the (rate, preload) with the least peak spring force that keeps the
    interface force >= ``[limits] min_contact_force`` at every angle and every speed up to ``margin`` times
    ``max_speed_rpm`` (defaults: the case's speed and speed_margin); ``min_rate`` (N/mm, or N*m/rad for an
    oscillating follower) bounds the rate from below. See the module docstring for the method, the tie-break
    rule and the dynamic correction. Raises :class:`InputError` on bad input."""
    for name, v in (("--max-speed", max_speed_rpm), ("--margin", margin)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise InputError(name, f"must be a positive number (got {v:g})")
    if not (math.isfinite(min_rate) and min_rate >= 0):
        raise InputError("--min-rate", f"must be a number >= 0 (got {min_rate:g})")
    p = _Problem(case, max_speed_rpm, margin, min_rate)
    warnings: list[str] = []
    k_kin, f0_kin, damping_note, method = _kinematic_answer(p)

    k, f0, dyn_bind = k_kin, f0_kin, None
    if not p.rigid:
        # dynamic correction: exact least preload per rate from the frequency-domain steady state
        peak_dyn = lambda u: u * u * p.s_max + p.preload_dynamic(u * u)[0]  # noqa: E731
        p_ref = peak_dyn(math.sqrt(k_kin))
        k_hi = max(p.k_lo, (p_ref - p.req[p.i_min]) / (p.s_max - p.s[p.i_min]), 2.0 * k_kin, 1e-12)
        u = p.minimize_in_sqrt_k(peak_dyn, math.sqrt(p.k_lo), math.sqrt(k_hi), _TIE_DYN, scan=_N_SCAN, seeds=(math.sqrt(k_kin),))
        k = u * u
        f0, th, w = p.preload_dynamic(k)
        for _ in range(3):  # verify on the fine speed grid; the force is affine in F0, so a deficit is exact to fix
            _, _, slack = p.verify(k, f0)
            if slack >= -1e-9 * max(1.0, abs(f0)):
                break
            f0 -= slack * (k + p.kf) / p.kf
        dyn_bind = (th, w)
        method += "; dynamic correction: exact least preload per rate (frequency-domain steady state, affine in F0) minimized over sqrt(k)"
    kin_design = p.design(k_kin, f0_kin)
    chosen = kin_design if p.rigid else p.design(k, f0)
    k_cur, f0_cur = float(p.model.stiffness), float(p.model.preload)
    current = p.design(k_cur, f0_cur)
    f0_at = p.preload_kinematic(k_cur, polish=True) if p.rigid else p.preload_dynamic(k_cur)[0]
    if not p.rigid:
        _, _, slack = p.verify(k_cur, f0_at)
        f0_at -= min(0.0, slack) * (k_cur + p.kf) / p.kf
    at_current = p.design(k_cur, f0_at)
    if k <= p.k_lo * (1 + 1e-9) + 1e-12:
        warnings.append(
            f"the least peak force is reached at the least rate ({min_rate:g} {'N*m/rad' if p.osc else 'N/mm'}): any rate adds k times "
            f"(full lift - lift at the binding angle) to the peak; pass --min-rate for the least preload with the rate you have"
        )

    binding = p.binding(k_kin, f0_kin)
    if p.fmin == 0.0 and any(w == 0.0 for _, _, w in binding):
        at = next(a for a, _, w in binding if w == 0.0)
        warnings.append(
            f"with min_contact_force = 0 the sized spring leaves zero contact force at rest at {at:.1f} deg, and check requires a "
            "force strictly above the limit: give [limits] min_contact_force > 0 for a margin"
        )

    # feasible region (for the table and the plot)
    k_top = 1.5 * max(k, k_kin, k_cur, p.k_lo, 1e-12)
    rates = np.linspace(p.k_lo, k_top, 41)
    pre_kin = np.array([p.preload_kinematic(kk) for kk in rates])
    pre_dyn = None
    if not p.rigid:
        rates_d = rates[::4]
        pre_d = np.array([p.preload_dynamic(kk, refine=False)[0] for kk in rates_d])
        pre_dyn = np.interp(rates, rates_d, pre_d)
    c_lines = p.damping(k_kin)
    r, _ = p.required(c_lines)
    idx = {int(np.argmax(r - kk * p.s)) for kk in rates}
    slack = k_kin * p.s + f0_kin - r
    idx |= set(np.argsort(slack)[:3].tolist())
    lines = tuple((math.degrees(p.theta[i]), float(p.s[i] / p.scale), float(r[i])) for i in sorted(idx))

    return SpringSizing(
        case_name=case.name,
        oscillating=p.osc,
        model="rigid" if p.rigid else "compliant",
        speed_rpm=p.speed_rpm,
        margin=p.margin,
        top_speed_rpm=p.W / RPM,
        min_contact_force=p.fmin,
        min_rate=float(min_rate),
        s_max=p.s_max / p.scale,
        chosen=chosen,
        kinematic=kin_design,
        current=current,
        at_current_rate=at_current,
        binding=binding,
        dynamic_binding=dyn_bind,
        damping=damping_note,
        method=method,
        region_rate=rate_from_si(rates, p.osc),
        region_preload_kinematic=pre_kin,
        region_preload_dynamic=pre_dyn,
        lines=lines,
        warnings=tuple(warnings),
    )
