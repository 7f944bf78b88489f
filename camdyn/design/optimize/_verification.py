"""How ``optimize`` checks its answer in the time domain before it writes it (:class:`Verification`): the diffrax
steady state against the frequency domain the optimizer used, or a valvetrain's two-mass model, at the speeds a
claim rests on; and ``--robust``'s claim from the tolerance study (:class:`RobustClaim`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._core.units import RPM
from ...model.case import Case
from ...model.dynamics import linear_least_force, response, valvetrain_response


@dataclass(frozen=True)
class VerifiedSpeed:
    """One speed of the verification: the time-domain least force (N; N*m for an arm) and, where the model has one,
    the frequency domain's (None: no frequency domain through a valvetrain's lash and seat; nan: a rigid
    follower), whether the follower separates (a valve floats) and whether the claim's margin held there.
    ``domain``: where the model of record solved it, "time", or "frequency" where a slow cam's train vibrates past
    the time integration's reach (:mod:`camdyn.model.dynamics`): its least force is then the frequency domain's."""

    speed_rpm: float
    time_domain_least_force: float
    frequency_domain_least_force: float | None
    separated: bool
    margin_held: bool
    domain: str = "time"

    def json(self, suffix: str) -> dict:
        return {
            "speed_rpm": self.speed_rpm,
            f"time_domain_least_force_{suffix}": self.time_domain_least_force,
            f"frequency_domain_least_force_{suffix}": self.frequency_domain_least_force,
            "separated": self.separated,
            "margin_held": self.margin_held,
            "domain": self.domain,
        }


@dataclass(frozen=True)
class Verification:
    """The time-domain model (``model``: "compliant", "rigid" or "two-mass valvetrain") at the speeds a claim
    rests on; ``unit``: the forces' (N or N*m)."""

    model: str
    points: tuple[VerifiedSpeed, ...]
    unit: str

    @property
    def least_force(self) -> float | None:
        return min((p.time_domain_least_force for p in self.points), default=None)

    @property
    def broken_at_rpm(self) -> list[float]:
        """The speeds (rpm) where the margin did not hold."""
        return [p.speed_rpm for p in self.points if not p.margin_held]

    def json(self) -> dict:
        suffix = self.unit.replace("*", "_")
        return {
            "model": self.model,
            "points": [p.json(suffix) for p in self.points],
            "least_force": self.least_force,
            "unit": self.unit,
        }


def unverified(case: Case) -> Verification:
    """No speed checked (an answer refused before it was built)."""
    return Verification("compliant", (), case.kind.force_unit)


def verify(case: Case, speeds_rpm: list[float], margin: float) -> Verification:
    """The diffrax time-domain steady state against the frequency domain the optimizer used, at ``speeds_rpm``:
    least interface force of each (N; N*m for an arm), whether the follower separates and whether it keeps
    ``margin`` (to 0.1 % of the largest force: the two models agree to well within it)."""
    points = []
    for rpm in speeds_rpm:
        w = rpm * RPM
        r = response(case.motion, case.model, w)
        fd = math.nan if case.model.rigid else linear_least_force(case.motion, case.model, w)
        held = bool(r.min_force >= margin - 1e-3 * float(np.abs(r.force).max())) and not r.separations
        points.append(VerifiedSpeed(rpm, float(r.min_force), fd, bool(r.separations), held, r.domain))
    return Verification("rigid" if case.model.rigid else "compliant", tuple(points), case.kind.force_unit)


def verify_valvetrain(case: Case, speeds_rpm: list[float], case_speed_rpm: float) -> Verification:
    """A valvetrain's two-mass model at ``speeds_rpm``: the least cam force over the valve event (N), whether the
    valve floats, and the margin held where it neither floats nor, at the case speed, bounces."""
    assert case.valvetrain is not None  # built from a valvetrain's case
    points = []
    for rpm in speeds_rpm:
        r = valvetrain_response(case.motion, case.valvetrain, rpm * RPM)
        held = not r.floated and not (rpm == case_speed_rpm and r.bounced)
        points.append(VerifiedSpeed(rpm, float(r.least_event_force), None, bool(r.floated), held))
    return Verification("two-mass valvetrain", tuple(points), "N")


@dataclass(frozen=True)
class RobustClaim:
    """``--robust``: the speed (rpm; None: none found) up to which P(separation) stays at or below
    ``separation_probability`` over ``samples`` built cams of the case's ``[tolerances]``."""

    separation_probability: float
    samples: int
    speed_rpm: float | None
    nominal_jump_speed_rpm: float | None

    def json(self) -> dict:
        return {
            "separation_probability": self.separation_probability,
            "samples": self.samples,
            "speed_rpm": self.speed_rpm,
            "nominal_jump_speed_rpm": self.nominal_jump_speed_rpm,
        }
