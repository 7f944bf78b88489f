"""The results of spring sizing: one spring and what it does (:class:`SpringDesign`), the whole answer
(:class:`SpringSizing`), their JSON (the ``size --json`` contract: keys are only ever added) and the tie-break rule
as the JSON states it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..._core.kinds import FOLLOWER_KINDS, FollowerKind
from ...schema import dynamics_keys
from .._check import Check
from ..spring import SpringDesign as SpringPart  # the part (wire, coils), not this module's (rate, preload)

TIE_BREAK = (
    "the least peak spring force is reached by more than one spring only where the peak force stays flat as the "
    "rate grows: the binding angle at full lift, with no damping force there that grows with the rate (with "
    "damping_ratio the damping grows like sqrt(k), and next to a binding angle where the follower leaves full lift "
    "it costs peak force: no tie, although the binding angle is at full lift); then the one with the least preload "
    "is chosen (the stiffest, which also has the least mean spring force): exactly, as a second lexicographic LP "
    "minimizing the preload at the least peak force would, for constant damping; with damping_ratio the largest "
    "rate whose peak force is within 1e-11 (kinematic) or 1e-6 (dynamic) of the least. Where the least rate "
    "reaches the least peak force and the peak force rises from it, the answer is the least rate (min_rate; 0 is a "
    "constant-force spring)"
)


def _inf_none(x: float) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


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

    def json(self, kind: FollowerKind, fmin: float) -> dict:
        keys = dict(zip(spring_keys(kind), (self.rate, self.preload, self.peak_spring), strict=True))
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


def spring_keys(kind: FollowerKind) -> tuple[str, str, str]:
    """The JSON keys of a spring's rate, preload and peak force for ``kind`` (``spring_rate_N_per_mm``, ...)."""
    _, rate, preload, _, _ = dynamics_keys(kind)
    force = f"{kind.force_word}_{kind.force_suffix}"
    return f"{rate}_{kind.rate_suffix}", f"{preload}_{kind.force_suffix}", f"peak_spring_{force}"


@dataclass(frozen=True)
class SpringSizing:
    """The result of :func:`size_spring`: the chosen spring, the kinematic LP answer it was corrected from,
    the case's current spring, the least preload at the current rate, and the feasible region."""

    case_name: str
    kind: FollowerKind
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
    part: SpringPart | None = None  # size --buildable: the spring as a part
    check: Check | None = None  # size --buildable: check's speed-margin verdict on the spring as written, with its mass
    spring_model: str = "none"  # how the spring's own mass is in the dynamics: none | lumped | surge
    spring_mass_kg: float = 0.0  # the spring whose mass is in the dynamics (buildable: the proposed part's)

    @property
    def oscillating(self) -> bool:
        return self.kind.rotary

    @property
    def units(self) -> dict:
        k = self.kind
        return {"rate": k.rate_unit, "preload": k.force_unit, "spring": k.force_unit, "lift": k.motion_unit}

    def json(self) -> dict:
        kind, fmin = self.kind, self.min_contact_force
        chosen = self.chosen.json(kind, fmin)
        out = {
            "case": self.case_name,
            "follower": kind.name,
            "model": self.model,
            "max_speed_rpm": self.speed_rpm,
            "margin": self.margin,
            "sized_to_rpm": self.top_speed_rpm,
            "min_contact_force_N": fmin,
            "min_rate": self.min_rate,
            "units": self.units,
        } | {key: None for each in FOLLOWER_KINDS for key in spring_keys(each)}
        out |= chosen
        out["jump_speed_rpm"] = chosen["dynamic_jump_speed_rpm"]  # what `check` judges the margin on
        kin = self.kinematic.json(kind, fmin)
        out["kinematic_answer"] = kin
        rate_key, pre_key, peak_key = list(chosen)[:3]
        out["dynamic_correction"] = {
            rate_key: chosen[rate_key] - kin[rate_key],
            pre_key: chosen[pre_key] - kin[pre_key],
            peak_key: chosen[peak_key] - kin[peak_key],
            "dynamic_jump_speed_rpm": None
            if None in (chosen["dynamic_jump_speed_rpm"], kin["dynamic_jump_speed_rpm"])
            else chosen["dynamic_jump_speed_rpm"] - kin["dynamic_jump_speed_rpm"],
        }
        out["current"] = self.current.json(kind, fmin)
        out["at_current_rate"] = self.at_current_rate.json(kind, fmin)
        out["binding"] = [{"start_deg": a, "end_deg": b, "speed_rpm": w} for a, b, w in self.binding]
        out["dynamic_binding"] = (
            None
            if self.dynamic_binding is None
            else {"theta_deg": self.dynamic_binding[0], "speed_rpm": self.dynamic_binding[1]}
        )
        out["tie_break"] = TIE_BREAK
        out["damping"] = self.damping
        out["method"] = self.method
        step = max(1, len(self.region_rate) // 20)
        out["feasible_region"] = {
            "description": f"feasible: preload >= least preload(rate); rate >= {self.min_rate:g} {self.units['rate']}",
            "rate": self.region_rate[::step].tolist(),
            "least_preload_kinematic": self.region_preload_kinematic[::step].tolist(),
            "least_preload_dynamic": None
            if self.region_preload_dynamic is None
            else self.region_preload_dynamic[::step].tolist(),
        }
        out["warnings"] = list(self.warnings)
        out["buildable"] = self.part is not None
        out["spring_model"] = self.spring_model
        out["spring_mass_kg"] = self.spring_mass_kg if self.spring_model != "none" else None
        out["bound"] = self.part is None  # plain size: the least peak force any spring needs, not a part
        if self.part is not None:
            assert self.check is not None  # size --buildable gives both
            out["part"] = self.part.json()
            out["check"] = self.check.json()
        return out
