"""The return spring as a part you can buy: a helical compression spring for a rate, a preload and a lift.

:func:`design_spring` searches the preferred wire sizes of the ``[spring]`` material and the active coils in
quarter turns; for each pair the mean diameter that gives the rate exactly follows from k = d^4 G / (8 D^3 N_a),
and the free length from the installed length (or, without one, the shortest spring that meets the clash
allowance). It keeps the candidates that meet Shigley's design conditions (Mechanical Engineering Design, 10th
ed., section 10-8: spring index 4..12, 3..15 active coils, clash allowance xi >= 0.15, solid-safe with
n_s >= 1.2; fatigue n_f >= 1.5 with Zimmerli's data; absolutely stable against buckling) and the bore, and
chooses the lightest (the cheapest wire, and the highest surge frequency for the rate). The spring it returns is
judged again from its own dimensions (:attr:`SpringDesign.checks`); when none fits, one :class:`InputError`
names the key that rules it out (the bore, the installed length, or the rate itself).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from .._core.errors import InputError
from .._core.materials import PREFERRED_WIRE_MM
from .._core.units import M_PER_MM, THETA_GRID, newton_per_torque, torsion_rate_at_arm
from ..model import spring as sp
from ..schema import SpringSpec
from ._check import Check, CheckKind
from .surge import CamHarmonics, SurgeReport, cam_harmonics, judge_surge, surge_floor_hz

if TYPE_CHECKING:
    from ..model.case import Case


@dataclass(frozen=True)
class SpringRules:
    """The design conditions a spring must meet (Shigley section 10-8, eqs. 10-18..10-21)."""

    index_min: float = 4.0
    index_max: float = 12.0
    active_coils_min: float = 3.0
    active_coils_max: float = 15.0
    coil_step: float = 0.25  # active coils are chosen in quarter turns
    clash_allowance: float = 0.15  # xi: the solid deflection is at least (1 + xi) times the full-lift deflection
    static_safety: float = 1.2  # n_s at solid (and so at full lift)
    fatigue_safety: float = 1.5  # n_f for infinite life
    criterion: str = "gerber"  # gerber | goodman | sines
    peened: bool = False
    alpha: float = sp.ALPHA_FLAT_PLATES  # end-condition constant for buckling


_MARGIN = 1e-9  # the search keeps a hair inside each limit, so the spring's own checks (recomputed) pass


@dataclass(frozen=True)
class SpringDesign:
    """A designed spring at its working points: installed (preload) and at full lift (mm, N, MPa)."""

    spring: sp.HelicalSpring
    preload: float  # N at the installed length
    lift: float  # mm of working stroke
    installed_length: float  # mm
    rules: SpringRules
    outside_diameter_max: float | None = None
    surge: SurgeReport | None = None

    @property
    def full_lift_length(self) -> float:
        return self.installed_length - self.lift

    @property
    def full_lift_force(self) -> float:
        return self.preload + self.spring.rate * self.lift

    @property
    def clash_allowance(self) -> float:
        """(solid deflection / full-lift deflection) - 1: xi of Shigley eq. (10-17)."""
        s = self.spring
        return (s.free_length - s.solid_length) / (s.free_length - self.full_lift_length) - 1.0

    @property
    def fatigue_safety(self) -> float:
        r = self.rules
        return self.spring.fatigue_safety(self.preload, self.full_lift_force, r.criterion, r.peened)

    @property
    def checks(self) -> tuple[Check, ...]:
        """The spring's own verdict, recomputed from its dimensions."""
        s, r = self.spring, self.rules
        ssy = s.strengths[1]
        fatigue = self.fatigue_safety
        out = [
            CheckKind.SPRING_INDEX_MIN.check(s.index, r.index_min),
            CheckKind.SPRING_INDEX_MAX.check(s.index, r.index_max),
            CheckKind.SPRING_LIFT_SAFETY.check(ssy / float(s.stress(self.full_lift_force)), r.static_safety),
            CheckKind.SPRING_SOLID_SAFETY.check(ssy / float(s.stress(s.solid_force)), r.static_safety),
            # inf: nothing alternates (unbounded); NaN: a wire over Zimmerli's 10 mm has no fatigue data (fails)
            CheckKind.SPRING_FATIGUE_SAFETY.check(
                None if fatigue == math.inf else (0.0 if math.isnan(fatigue) else fatigue), r.fatigue_safety
            ),
            CheckKind.SPRING_BUCKLING.check(s.free_length, s.critical_free_length),
            CheckKind.SPRING_CLASH_ALLOWANCE.check(self.clash_allowance, r.clash_allowance),
        ]
        if self.outside_diameter_max is not None:
            out.append(CheckKind.SPRING_OUTSIDE_DIAMETER.check(s.outside_diameter, self.outside_diameter_max))
        return tuple(out)

    def with_surge(self, harmonics: CamHarmonics) -> SpringDesign:
        """The same design with its surge judged against the cam's harmonics."""
        return replace(self, surge=judge_surge(self.spring.surge_frequency, harmonics))

    @property
    def ok(self) -> bool:
        return all(c.ok for c in self.checks)

    @property
    def warnings(self) -> tuple[str, ...]:
        return () if self.surge is None else self.surge.warnings

    def json(self) -> dict:
        s = self.spring
        out = {
            **s.json(),
            "installed_length_mm": self.installed_length,
            "full_lift_length_mm": self.full_lift_length,
            "lift_mm": self.lift,
            "preload_N": self.preload,
            "full_lift_force_N": self.full_lift_force,
            "solid_force_N": s.solid_force,
            "stress_installed_MPa": float(s.stress(self.preload)),
            "stress_full_lift_MPa": float(s.stress(self.full_lift_force)),
            "stress_solid_MPa": float(s.stress(s.solid_force)),
            "fatigue_safety": self.fatigue_safety if math.isfinite(self.fatigue_safety) else None,
            "fatigue_criterion": self.rules.criterion,
            "clash_allowance": self.clash_allowance,
            "checks": [c.json() for c in self.checks],
            "warnings": list(self.warnings),
        }
        if self.surge is not None:
            out["surge"] = self.surge.json()
        return out


def _wire_sizes(material) -> np.ndarray:
    lo, hi = material.d_range_mm
    return np.array([d for d in PREFERRED_WIRE_MM if lo <= d <= hi])


def _candidates(
    rate: float, preload: float, lift: float, spec: SpringSpec, rules: SpringRules, min_surge_hz: float | None = None
) -> dict:
    """Every (wire size, active coils) pair with the mean diameter that gives the rate, and what each is judged on."""
    wire = sp.wire(spec.material)
    d1 = _wire_sizes(wire)
    na_max = rules.active_coils_max if spec.max_active_coils is None else spec.max_active_coils
    na1 = np.arange(rules.active_coils_min, na_max + 0.5 * rules.coil_step, rules.coil_step)
    d, na = (a.ravel() for a in np.meshgrid(d1, na1, indexing="ij"))
    G = sp.shear_modulus(wire, d)
    D = (G * d**4 / (8.0 * rate * na)) ** (1.0 / 3.0)
    Ls = sp.solid_length(d, na, spec.end_type)
    y0, y1 = preload / rate, preload / rate + lift
    if spec.installed_length is not None:
        L0 = np.full(d.shape, spec.installed_length + y0)
    else:
        L0 = Ls + (1.0 + rules.clash_allowance) * y1 * (1.0 + 2 * _MARGIN)
    ssy = sp.torsional_yield(wire, d)
    f1 = preload + rate * lift
    # a pair whose coil is hardly wider than its wire (index near 1: the stress factors' poles) is refused by the
    # index's limits, and a spring shorter than solid at its free length has no stress to judge: no warnings
    with np.errstate(divide="ignore", invalid="ignore"):
        tau_a, tau_m = sp.shear_stress(0.5 * rate * lift, D, d), sp.shear_stress(preload + 0.5 * rate * lift, D, d)
        fatigue = sp.fatigue_safety(tau_a, tau_m, sp.tensile_strength(wire, d), rules.criterion, rules.peened)
        solid = ssy / sp.shear_stress(rate * (L0 - Ls), D, d)
        full_lift = ssy / sp.shear_stress(f1, D, d)
    fatigue = np.where(d <= sp.ZIMMERLI_MAX_WIRE_MM, fatigue, np.nan)
    Lcr = sp.critical_free_length(D, sp.elastic_modulus(wire, d), G, rules.alpha)
    return {
        "d": d,
        "D": D,
        "na": na,
        "L0": L0,
        "Ls": Ls,
        "min_surge_hz": min_surge_hz,
        "surge": sp.surge_frequency(rate, sp.coil_mass(d, D, na, wire.density_kg_m3)),
        "mass": sp.coil_mass(d, D, sp.total_coils(na, spec.end_type), wire.density_kg_m3),
        "index": D / d,
        "od": D + d,
        "clash": (L0 - Ls) / y1 - 1.0,
        "solid": np.where(L0 > Ls, solid, -np.inf),
        "full_lift": full_lift,
        "fatigue": fatigue,
        "buckling": Lcr - L0,
    }


def _constraints(c: dict, spec: SpringSpec, rules: SpringRules):
    """(name, key the user can change, value, limit, sense) in the order the search reports a dead end."""
    m = 1.0 + _MARGIN
    out = [
        (f"spring index at least {rules.index_min:g}", "index", c["index"], rules.index_min * m, ">="),
        (f"spring index at most {rules.index_max:g}", "index", c["index"], rules.index_max / m, "<="),
        ("outside diameter", "outside_diameter_max", c["od"], (spec.outside_diameter_max or math.inf) / m, "<="),
        ("clash allowance at the installed length", "installed_length", c["clash"], rules.clash_allowance * m, ">="),
        ("stress at full lift (n_s)", "", c["full_lift"], rules.static_safety * m, ">="),
        ("stress at solid (n_s)", "", c["solid"], rules.static_safety * m, ">="),
        (f"fatigue ({rules.criterion}, Zimmerli; n_f)", "", c["fatigue"], rules.fatigue_safety * m, ">="),
        ("buckling (critical minus free length, mm)", "", c["buckling"], 0.0, ">="),
    ]
    if c["min_surge_hz"] is not None:  # clear of the cam's strong harmonics (design.surge.surge_floor_hz)
        name = "surge frequency clear of the cam's strong harmonics (Hz)"
        out.append((name, "", c["surge"], c["min_surge_hz"] * m, ">="))
    return [(name, key, v, lim, sense, (v >= lim) if sense == ">=" else (v <= lim)) for name, key, v, lim, sense in out]


def _feasible(
    rate: float, preload: float, lift: float, spec: SpringSpec, rules: SpringRules, min_surge_hz: float | None = None
):
    """The candidates and which of them meet every condition."""
    c = _candidates(rate, preload, lift, spec, rules, min_surge_hz)
    return c, np.logical_and.reduce([con[5] for con in _constraints(c, spec, rules)])


def _first_failure(cons) -> tuple[str, float, float]:
    """The first condition (in order) that rules out the last candidates: its name, the best value any
    candidate still in the running reached, and its limit."""
    alive = np.ones(cons[0][2].shape, bool)
    for name, _, v, lim, sense, ok in cons:
        if not (alive & ok).any():
            vals = v[alive & np.isfinite(v)]
            return name, ((vals.max() if sense == ">=" else vals.min()) if vals.size else math.nan), lim
        alive &= ok
    raise AssertionError("unreachable: some candidate passes")


def _dead_end(
    c, cons, rate: float, preload: float, lift: float, spec: SpringSpec, rules: SpringRules, rate_key: str
) -> InputError:
    """Why no candidate passes: the bore, or the installed length, where freeing it would let one through; else
    the first condition that rules out the last candidates, with the best value any candidate reached."""
    what = f"no {spec.material} spring of {rate:.4g} N/mm"
    if spec.outside_diameter_max is not None:
        rest = np.logical_and.reduce([ok for _, key, _, _, _, ok in cons if key != "outside_diameter_max"])
        if rest.any():
            least = float(c["od"][rest].min())
            return InputError(
                "spring.outside_diameter_max",
                f"{what} fits in {spec.outside_diameter_max:g} mm: the least outside diameter that meets the other "
                f"checks is {least:.3g} mm",
            )
    if spec.installed_length is not None:
        cf, fits = _feasible(
            rate, preload, lift, spec.model_copy(update={"installed_length": None}), rules, c["min_surge_hz"]
        )
        if fits.any():
            need = float(np.min(cf["L0"][fits] - preload / rate))
            why = (
                f"it needs at least {need:.4g} mm"
                if spec.installed_length < need
                else (
                    f"there every candidate fails the {_first_failure(cons)[0]} (the shortest that fits is "
                    f"installed at {need:.4g} mm)"
                )
            )
            return InputError(
                "spring.installed_length",
                f"{what} fits at {spec.installed_length:g} mm with {preload:.4g} N preload over a {lift:.4g} mm "
                f"lift: {why}",
            )
    if spec.outside_diameter_max is not None and spec.installed_length is not None:
        cf, fits = _feasible(
            rate,
            preload,
            lift,
            spec.model_copy(update={"installed_length": None, "outside_diameter_max": None}),
            rules,
            c["min_surge_hz"],
        )
        if fits.any():
            i = np.flatnonzero(fits)[np.argmin(cf["mass"][fits])]
            return InputError(
                "spring.outside_diameter_max",
                f"{what} fits in {spec.outside_diameter_max:g} mm installed at {spec.installed_length:g} mm: "
                f"without those two limits the lightest is {float(cf['od'][i]):.3g} mm across and installed at "
                f"{float(cf['L0'][i]) - preload / rate:.4g} mm",
            )
    name, best, lim = _first_failure(cons)
    na_max = rules.active_coils_max if spec.max_active_coils is None else spec.max_active_coils
    return InputError(
        rate_key,
        f"{what} with {preload:.4g} N preload over a {lift:.4g} mm lift meets Shigley's design conditions "
        f"({rules.active_coils_min:g}-{na_max:g} active coils, preferred wire sizes): every candidate fails the "
        f"{name}: best {best:.3g} against {lim:.3g}"
        + _more_coils_hint(rate, preload, lift, spec, rules, na_max, c["min_surge_hz"]),
    )


def _more_coils_hint(
    rate, preload, lift, spec: SpringSpec, rules: SpringRules, na_max: float, min_surge_hz=None
) -> str:
    """Where more active coils than allowed would make a spring: say how many."""
    c, ok = _feasible(
        rate, preload, lift, spec.model_copy(update={"max_active_coils": 4 * na_max}), rules, min_surge_hz
    )
    if not ok.any():
        return ""
    return f" (one with {float(c['na'][ok].min()):g} active coils fits: allow it with [spring] max_active_coils)"


def design_spring(
    rate: float,
    preload: float,
    lift: float,
    spec: SpringSpec | None = None,
    *,
    rules: SpringRules = SpringRules(),
    rate_key: str = "dynamics.spring_rate",
    harmonics: CamHarmonics | None = None,
    min_surge_hz: float | None = None,
) -> SpringDesign:
    """The lightest helical compression spring of ``rate`` (N/mm) giving ``preload`` (N) at its installed length
    and compressed a further ``lift`` (mm), within ``spec`` (``[spring]``: material, bore, installed length,
    end type) and Shigley's design conditions. :class:`InputError` (naming the binding key, ``rate_key`` for
    the rate itself) when none fits. ``harmonics``: the cam's, to judge the chosen spring's surge against;
    ``min_surge_hz``: the least surge frequency a candidate may have (:func:`camdyn.design.surge.surge_floor_hz`)."""
    spec = spec or SpringSpec()
    if not (math.isfinite(rate) and rate > 0):
        raise InputError(rate_key, f"a spring needs a positive rate (got {rate:g} N/mm)")
    if not (math.isfinite(preload) and preload >= 0):
        raise InputError(
            "preload",
            f"a compression spring cannot pull: the preload at the installed length must be >= 0 (got {preload:g} N)",
        )
    if not (math.isfinite(lift) and lift > 0):
        raise InputError("lift", f"the working stroke must be positive (got {lift:g} mm)")
    c = _candidates(rate, preload, lift, spec, rules, min_surge_hz)
    cons = _constraints(c, spec, rules)
    ok = np.logical_and.reduce([con[5] for con in cons])
    if not ok.any():
        raise _dead_end(c, cons, rate, preload, lift, spec, rules, rate_key)
    i = np.flatnonzero(ok)[np.lexsort((c["od"][ok], c["mass"][ok]))[0]]
    spring = sp.HelicalSpring(
        spec.material,
        float(c["d"][i]),
        float(c["D"][i]),
        float(c["na"][i]),
        spec.end_type,
        float(c["L0"][i]),
        rules.alpha,
    )
    installed = spring.free_length - preload / rate
    design = SpringDesign(spring, float(preload), float(lift), installed, rules, spec.outside_diameter_max)
    return design if harmonics is None else design.with_surge(harmonics)


def max_buildable_preload(
    rate: float,
    lift: float,
    spec: SpringSpec | None = None,
    *,
    rules: SpringRules = SpringRules(),
    tol: float = 1e-3,
    min_surge_hz: float | None = None,
) -> float | None:
    """The largest preload (N) for which a spring of ``rate`` (N/mm) and ``lift`` (mm) can be built within
    ``spec``; None when none can, even without preload. Every lower preload is buildable too (a smaller preload
    lowers every stress and shortens the spring), so ``size --buildable`` may use it as a bound on F0."""
    spec = spec or SpringSpec()

    def fits(f0: float) -> bool:
        return bool(_feasible(rate, f0, lift, spec, rules, min_surge_hz)[1].any())

    if not fits(0.0):
        return None
    lo, hi = 0.0, max(1.0, rate * lift)
    while fits(hi):
        lo, hi = hi, 2.0 * hi
        if hi > 1e9:
            return math.inf
    while hi - lo > tol * max(1.0, lo):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fits(mid) else (lo, mid)
    return lo


@dataclass(frozen=True)
class SpringLoads:
    """What a case asks of its spring, as a linear spring sees it: rate N/mm, the force at the least lift N
    (the installed point), the stroke mm, and where the installed point sits below zero lift (mm)."""

    rate: float
    preload: float
    lift: float
    installed_shift: float  # the spring's length at the least lift is [spring] installed_length minus this
    rate_key: str


def spring_loads(case: Case, *, rate: float | None = None, preload: float | None = None) -> SpringLoads:
    """The loads of a case's spring (its own ``[dynamics]`` rate and preload, or ``rate`` and ``preload`` in the
    case's units: N/mm and N, or N*m/rad and N*m for an oscillating arm, whose spring acts at ``[spring]
    lever_arm``; a valvetrain's valve spring at the valve, over the valve's lift on a rigid train)."""
    d = case.spec.dynamics
    s = case.motion.sample(THETA_GRID)[1][0]
    if case.kind.rotary:  # the spring acts at [spring] lever_arm from the pivot
        spec = case.spec.spring
        if spec is None or spec.lever_arm is None:
            raise InputError(
                "spring.lever_arm",
                f"{case.kind.a} follower's spring needs [spring] lever_arm: the distance from the arm pivot to the "
                "spring, mm",
            )
        r = spec.lever_arm
        rate_t = d.torsion_rate if rate is None else rate
        torque = d.preload_torque if preload is None else preload
        assert rate_t is not None and torque is not None  # check_dynamics_keys: an arm's rate and preload
        k = torsion_rate_at_arm(rate_t, r)
        f0 = torque * newton_per_torque(r)
        s_mm, key = s * r, "dynamics.torsion_rate"  # small swings: the arc at the spring
    else:
        k = d.spring_rate if rate is None else rate
        f0 = d.preload if preload is None else preload
        assert k is not None and f0 is not None  # check_dynamics_keys: the spring's rate and preload
        s_mm, key = s, "dynamics.spring_rate"
        if case.valvetrain is not None:  # the valve spring: installed with the valve closed, its stroke the valve's
            reach = case.valvetrain.at_valve_mm(np.array([s.min(), s.max()]))[0]
            stroke = float(reach[1] - reach[0]) - float(case.valvetrain.lash) / M_PER_MM  # positive: build_case
            return SpringLoads(float(k), float(f0), stroke, 0.0, key)
    lo, hi = float(np.min(s_mm)), float(np.max(s_mm))
    return SpringLoads(float(k), float(f0 + k * lo), hi - lo, lo, key)


def _case_spec(case, loads: SpringLoads) -> SpringSpec:
    """The case's ``[spring]`` with its installed length moved to the least lift (where the design installs it)."""
    spec = case.spec.spring or SpringSpec()
    if spec.installed_length is not None and loads.installed_shift != 0.0:
        spec = spec.model_copy(update={"installed_length": spec.installed_length - loads.installed_shift})
    return spec


def surge_floor(case: Case, top_speed_rpm: float | None) -> float:
    """The least surge frequency (Hz) clear of the cam's strong harmonics up to ``top_speed_rpm`` (default: the
    case's speed_margin times its speed)."""
    top = case.limits.speed_margin * case.speed_rpm if top_speed_rpm is None else top_speed_rpm
    return surge_floor_hz(cam_harmonics(case.motion, case.speed_rpm), top)


def design_case_spring(
    case: Case,
    *,
    rate: float | None = None,
    preload: float | None = None,
    rules: SpringRules = SpringRules(),
    surge: str = "prefer",
    top_speed_rpm: float | None = None,
) -> SpringDesign:
    """The spring for a case (its ``[spring]`` table; its rate and preload unless given, in the case's units),
    with its surge judged against the cam's harmonics at the case speed. ``surge``: "prefer" the lightest spring
    whose surge frequency is clear of the cam's strong harmonics at every speed up to ``top_speed_rpm`` (default
    speed_margin x speed; :func:`camdyn.design.surge.surge_floor_hz`), else the lightest (its warnings say where
    it surges); "require" only such a spring (``size --buildable``); "ignore" the lightest."""
    loads = spring_loads(case, rate=rate, preload=preload)
    spec = _case_spec(case, loads)
    if loads.preload < 0:
        raise InputError(
            "dynamics.preload",
            f"a compression spring cannot pull: its force at the least lift would be {loads.preload:.4g} N",
        )
    harmonics = cam_harmonics(case.motion, case.speed_rpm)
    args = (loads.rate, loads.preload, loads.lift, spec)
    if surge != "ignore":
        try:
            floor = surge_floor(case, top_speed_rpm)
            return design_spring(*args, rules=rules, rate_key=loads.rate_key, harmonics=harmonics, min_surge_hz=floor)
        except InputError:
            if surge == "require":
                raise
    return design_spring(*args, rules=rules, rate_key=loads.rate_key, harmonics=harmonics)


def case_max_preload(case: Case, rate: float, top_speed_rpm: float | None = None) -> float | None:
    """The largest preload (the case's units: N, or N*m for an arm) a buildable spring of ``rate`` (N/mm, or
    N*m/rad) can give this case within its ``[spring]`` table, its surge frequency clear of the cam's strong
    harmonics up to ``top_speed_rpm``; None where no spring of that rate can be built. Every lower preload down
    to the least the spring can hold is buildable too: with the sizer's least preload per rate this bounds
    ``size --buildable``'s feasible region."""
    loads = spring_loads(case, rate=rate, preload=0.0)
    spec = _case_spec(case, loads)
    top = max_buildable_preload(loads.rate, loads.lift, spec, min_surge_hz=surge_floor(case, top_speed_rpm))
    if top is None:
        return None
    linear = top - loads.rate * loads.installed_shift  # the spring force at zero lift
    if not case.kind.rotary:
        return linear
    assert spec.lever_arm is not None  # the schema: an arm's spring needs its lever arm
    return linear / newton_per_torque(spec.lever_arm)


def min_preload(case: Case) -> float:
    """``[limits] min_preload``: the least preload (seat load) a spring proposed for the case may have, in the
    case's units (N, or N*m for an arm, as ``[dynamics] preload`` / ``preload_torque``: SI); -inf where none is
    given. ``size`` honours it; an optimizer that frees the preload bounds it below by this."""
    f0 = case.limits.min_preload
    return -math.inf if f0 is None else float(f0)
