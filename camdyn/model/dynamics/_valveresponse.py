"""What the valvetrain's time-domain model gives for one revolution (:class:`ValvetrainResponse`) and the contact
changes in it (:class:`ValveEvent`): the arrays, and the facts its checks and searches read from them (float,
the least cam force over the valve event, seating, bounce, timing)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..._core.units import M_PER_MM, VALVE_BOUNCE_TOLERANCE_MM, VALVE_TIMING_LIFT_MM
from ..valvetrain import ValvetrainModel


@dataclass(frozen=True)
class ValveEvent:
    """A contact's change: ``what`` ("float", "cam-landing", "valve-lift", "seating", "lash") at ``deg``, with
    the relative speed at an impact (m/s; NaN otherwise)."""

    what: str
    deg: float
    speed: float = math.nan


@dataclass(frozen=True)
class ValvetrainResponse:
    """The valvetrain over one revolution at cam speed ``omega`` (rad/s), on ``theta_deg`` (n,).

    Lifts in mm, the valve's velocity in m/s, forces in N. ``seated``: the valve on its seat at each angle.
    """

    omega: float
    theta_deg: np.ndarray
    cam_lift: np.ndarray  # the cam's lift at the follower, mm
    follower_lift: np.ndarray  # mm
    valve_lift: np.ndarray  # mm
    valve_velocity: np.ndarray  # m/s
    cam_force: np.ndarray  # N, the cam contact
    train_force: np.ndarray  # N, at the valve
    seated: np.ndarray  # bool
    in_event: np.ndarray  # bool: the valve off its seat between its lift and its first seating (the valve event)
    events: tuple[ValveEvent, ...]
    bounce_height_mm: float  # the valve's highest lift off its seat after it first seats, mm (0: never lifts again)
    settled: bool  # back at rest on the base circle within the revolutions simulated
    warnings: tuple[str, ...] = field(default=())
    # N: the force a rigid cam contact would have to give at each angle to keep the follower on it, the valve as it
    # moves (cam_force where the contact holds, negative in a float); None for a compliant contact
    hold_force: np.ndarray | None = None

    @property
    def max_valve_lift_mm(self) -> float:
        return float(np.max(self.valve_lift))

    @property
    def floated(self) -> bool:
        """Whether the cam contact opened while the valve was off its seat (valve float)."""
        return any(e.what == "float" for e in self.events) or bool(np.any((self.cam_force <= 0.0) & self.in_event))

    @property
    def least_event_force(self) -> float:
        """The least cam-contact force over the valve event (from the valve's lift to its first seating), N (0 where
        the contact opens there); NaN for a valve that never lifts."""
        if not self.in_event.any():
            return math.nan
        return 0.0 if self.floated else float(np.min(self.cam_force[self.in_event]))

    @property
    def float_force(self) -> float:
        """The float search's force (N): :attr:`least_event_force`, but where a rigid cam contact opens, the least
        force over the valve event that the cam would have to pull with to keep the follower on it
        (:attr:`hold_force`, at most 0): continuous through the float speed, as the fast path's
        :class:`~camdyn.model.dynamics.Floated` force, so the search refines it by interpolation."""
        least = self.least_event_force
        if self.hold_force is None or not self.floated or math.isnan(least):
            return least
        return min(float(np.min(self.hold_force[self.in_event])), 0.0)

    @property
    def least_event_force_deg(self) -> float:
        """Where the cam-contact force is least over the valve event, deg (NaN for a valve that never lifts)."""
        if not self.in_event.any():
            return math.nan
        return float(self.theta_deg[self.in_event][int(np.argmin(self.cam_force[self.in_event]))])

    @property
    def seating_velocity(self) -> float:
        """The valve's speed as it first lands on its seat after the event, m/s (NaN: it never lifts)."""
        landings = [e for e in self.events if e.what == "seating"]
        return landings[0].speed if landings else math.nan

    @property
    def seating_deg(self) -> float:
        landings = [e for e in self.events if e.what == "seating"]
        return landings[0].deg if landings else math.nan

    @property
    def least_train_force(self) -> float:
        """The train's least force on the valve over the valve event, N (0 where the valve leaves the train); NaN for
        a valve that never lifts."""
        return float(np.min(self.train_force[self.in_event])) if self.in_event.any() else math.nan

    def max_gap_mm(self, vt: ValvetrainModel, solid_mm: float = math.inf) -> float:
        """The valve's largest lift above where the cam would hold it (mm, at the valve; through the rocker's lever
        where it has one), float and bounce both; the valve's lift bounded by ``solid_mm``, its coil bind."""
        at_valve = vt.host_lever(self.cam_lift * M_PER_MM)[0] / M_PER_MM
        held = np.maximum(at_valve - float(vt.lash) / M_PER_MM, 0.0)
        return max(0.0, float(np.max(np.minimum(self.valve_lift, solid_mm) - held)))

    @property
    def bounced(self) -> bool:
        """Whether the valve leaves its seat after closing by more than the seat's micro-bounce tolerance."""
        return self.bounce_height_mm > VALVE_BOUNCE_TOLERANCE_MM

    def timing_deg(self, lift_mm: float = VALVE_TIMING_LIFT_MM) -> tuple[float, float]:
        """The opening and closing angles (deg in [0, 360)): where the valve's lift first rises above ``lift_mm``
        and where it last falls below it, on the grid, interpolated linearly; (NaN, NaN) if it never does."""
        n = len(self.theta_deg)
        above = self.valve_lift > lift_mm
        if not above.any() or above.all():
            return math.nan, math.nan
        shift = int(np.argmin(above))  # start below: the open span does not wrap the scan
        idx = (np.arange(n) + shift) % n
        a = self.valve_lift[idx] - lift_mm
        up = int(np.argmax(a > 0.0))
        down = n - 1 - int(np.argmax(a[::-1] > 0.0))  # the last open grid point
        step = 360.0 / n

        def cross(j0: int) -> float:  # a[j0] <= 0 < a[j0 + 1] or the reverse
            f = a[j0] / (a[j0] - a[(j0 + 1) % n])
            return (self.theta_deg[idx[j0]] + f * step) % 360.0

        return float(cross(up - 1)), float(cross(down))
