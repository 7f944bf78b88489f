"""What ``optimize`` returns (:class:`Optimization`): the optimized case, what changed and how it was verified,
with its case file's text and its JSON."""

from __future__ import annotations

from dataclasses import dataclass

from ..._core.results import finite_or_none
from ...export import camdyn_version, dumps_case
from ...model.case import Case
from ._metrics import Metrics, floor_rpm
from ._valvetrain import ValveFacts, valve_sentence
from ._verification import RobustClaim, Verification


@dataclass(frozen=True)
class Optimization:
    """The optimized case (as a case-file dict and as a :class:`Case`), what changed, how it was verified, and
    why it is not to be written (``refusals``: empty when it is)."""

    objective: str
    before: Metrics
    after: Metrics
    case: Case
    document: dict  # the case file to write
    claimed_speed_rpm: float  # the speed up to which the written design keeps the force margin (robust: P(sep) <= 1e-3)
    verification: Verification  # the time-domain model at the speeds the claim rests on
    control_points: int
    time_s: float
    margin: float = 0.0  # the force margin held (N; N*m for an arm)
    refusals: tuple[str, ...] = ()  # why the answer is no better than the input, or invalid
    robust: RobustClaim | None = None  # --robust: the tolerance study's claim
    valvetrain: tuple[ValveFacts, ValveFacts] | None = None  # a valvetrain's two-mass facts, before and after

    @property
    def unit(self) -> str:
        return self.case.kind.lift_unit

    @property
    def force_unit(self) -> str:
        return self.case.kind.force_unit

    @property
    def written(self) -> bool:
        return not self.refusals

    def text(self, source: str) -> str:
        """The case file, with a header saying how it was made from ``source``."""
        b, a = self.before, self.after
        ver = f" {camdyn_version()}".rstrip()
        f = self.force_unit
        aim = {
            "jump-speed": f"the largest speed up to which the least contact force stays >= {self.margin:.4g} {f} "
            "at every speed",
            "vibration": "the least residual vibration in the dwells over 0.9-1.1 x the case speed, holding there",
            "spring-force": "the least peak spring force (preload and rate free) holding to speed_margin x speed",
        }[self.objective]
        checked = "the time-domain (diffrax) model"
        if self.valvetrain is not None:
            aim += (
                " on the valve event's single follower (the valve on the compliant train from rest on its seat, the "
                "cam side moving with the cam), the valve closing no faster where it seats"
            )
            checked = "the two-mass (diffrax) valvetrain model, least cam force over the valve event,"
        made = (
            f"Written by `camdyn optimize {source} --objective {self.objective} --control-points {self.control_points}`"
        )
        what = (
            f"every rise and return is a clamped B-spline of degree 5 with {self.control_points} control points "
            '(law = "bspline"), monotone within [0, 1]; the segment boundaries, lifts and dwells, the follower, the '
            "limits and (but for spring-force) the spring are the original's."
        )
        if self.valvetrain is not None:
            what = (
                f"only the flanks between the lash ramps are reshaped, each a B-spline of degree 5 with "
                f'{self.control_points} control points (law = "bspline"), monotone within [0, 1], meeting the ramps '
                "with their lift, velocity and acceleration; the ramps, the dwells, the nose's angle and lift, the "
                "valvetrain, the spring and the limits are the original's."
            )
        header = [
            f"{made} (camdyn{ver}): {what}",
            f"Objective: {aim}. Linear programs (HiGHS) on the frequency-domain steady state, its Jacobian by JAX "
            "autodiff.",
            f"Dynamic jump speed {b.jump_speed_rpm:.1f} -> {a.jump_speed_rpm:.1f} rpm; the force margin of "
            f"{self.margin:.4g} {f} holds to {floor_rpm(b.margin_speed_rpm):.1f} -> "
            f"{floor_rpm(a.margin_speed_rpm):.1f} rpm; least contact force at the case speed "
            f"{b.least_force_N:.3g} -> {a.least_force_N:.3g} N; max pressure angle {b.max_pressure_angle_deg:.2f} -> "
            f"{a.max_pressure_angle_deg:.2f} deg; verdict {b.verdict} -> {a.verdict}.",
            *([] if self.valvetrain is None else [valve_sentence(*self.valvetrain)]),
            f"Checked by {checked} at "
            + ", ".join(f"{p.speed_rpm:.0f}" for p in self.verification.points)
            + f" rpm (least force {self.verification.least_force:.4g} {f}).",
        ]
        return dumps_case(self.document, header)

    def json(self) -> dict:
        margin_key = f"force_margin_{self.case.kind.force_suffix}"
        return {
            "case": self.case.name,
            "objective": self.objective,
            "control_points_per_segment": self.control_points,
            "claimed_speed_rpm": finite_or_none(self.claimed_speed_rpm),
            "before": self.before.json(self.unit),
            "after": self.after.json(self.unit),
            "verification": self.verification.json(),
            "time_s": self.time_s,
            margin_key: self.margin,
            "written": self.written,
            "refusals": list(self.refusals),
            "robust": None if self.robust is None else self.robust.json(),
            "valvetrain": None
            if self.valvetrain is None
            else {"before": self.valvetrain[0].json(), "after": self.valvetrain[1].json()},
        }
