"""The valvetrain fast path through a float: the follower off the cam while the valve is off its seat.

Past the float speed the cam lets go of the follower during the valve's event; with a rigid cam contact, a
compliant train and a constant ratio r the two masses then fly together (SI, the cam angle, ' = d/dtheta)::

    m_c w^2 x_c'' = -F_tappet - r F_t,   m_v w^2 x_v'' = F_t - (k x_v + F0 + c w x_v'),
    F_t = k_t d + c_t w d',   d = r x_c - lash - x_v   (0 where d <= 0 or the sum would pull)

a linear system in (x_c, x_c', x_v, x_v') while the train pushes, and two uncoupled ones (the follower on its tappet
force, the valve on its spring) while it does not. So a float runs on the fast path's exact propagators, each
stretch to the first of its guards (the follower landing on the cam, the train taking hold or letting go), and the
landing follows the diffrax model's rule (the cam's restitution, or held where the rebound is below the landing
floor); back on the cam the valve rides its train, or flies off it on its spring (the fast path's own systems), to
the next float or to its seating. What the diffrax model's revolution gives of the event (its least forces on the
output grid, the valve's largest lift and gap, the seating) is gathered on the way. Anything else (the valve seating
or the train lifting it while the follower flies, a rocker, whose ratio moves with the flying follower, the spring's
surge chain, a chatter of the train about zero force) is :class:`~._valvelinear.Unsure`: the diffrax model's."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..motion import Motion
from ..valvetrain import ValvetrainModel
from ._cubic import hermite_at, hermite_taylor
from ._valvefield import GAP_EPS
from ._valvelinear import ORDER, Index, Linear, Unsure, cross, step_bounds, stretch_to
from ._valvetrain import landing_floor

# the stretches of one event's floats (flights, landings, the train taking hold and letting go): the shipped
# valvetrain's take 2-10 up to 6900 rpm; a stiff train's dither about zero force takes hundreds (the diffrax model's)
_MAX_STRETCHES = 16
_X_C, _P_C, _X_V, _P_V = 0, 1, 2, 3  # the flight's state, as the diffrax model's


@dataclass
class EventRows:
    """The valve event's numbers on the output grid, as the diffrax model's revolution gives them, gathered in angle
    order: the cam contact's force (0 in a flight), the force that would hold the follower on the cam, the train's
    force (N), the valve's lift and its gap above where the cam would hold it (m), and each row's angle (deg)."""

    cam: list[np.ndarray] = field(default_factory=list)
    hold: list[np.ndarray] = field(default_factory=list)
    train: list[np.ndarray] = field(default_factory=list)
    lift: list[np.ndarray] = field(default_factory=list)
    gap: list[np.ndarray] = field(default_factory=list)
    deg: list[np.ndarray] = field(default_factory=list)

    def add(
        self, cam: np.ndarray, hold: np.ndarray, train: np.ndarray, lift: np.ndarray, gap: np.ndarray, deg: np.ndarray
    ) -> None:
        """Rows of each, in angle order after those already added."""
        rows = (cam, hold, train, lift, gap, deg)
        for name, value in zip(("cam", "hold", "train", "lift", "gap", "deg"), rows, strict=True):
            getattr(self, name).append(np.asarray(value, dtype=float))

    def joined(self, name: str) -> np.ndarray:
        return np.concatenate(getattr(self, name)) if getattr(self, name) else np.zeros(0)


def follows_floats(vt: ValvetrainModel) -> bool:
    """Whether the fast path can follow ``vt``'s valve through a float: a rigid cam contact, a compliant train of
    constant ratio, no surge chain."""
    return vt.rigid_cam and not vt.rigid_train and vt.rocker is None and vt.coils is None


class ValveFloats:
    """The two masses of a rigid cam contact, a compliant train of constant ratio and a valve without the surge
    chain at cam speed ``w`` (rad/s), through the floats of the valve's event. ``rev``: the fast path's revolution;
    ``systems``: the valve's on its train with the follower on the cam and on its spring alone (the fast path's);
    ``numbers``: the valvetrain's (:func:`~._valveevent.constants`)."""

    def __init__(
        self, motion: Motion, vt: ValvetrainModel, w: float, rev, systems: tuple[Linear, Linear], numbers
    ) -> None:
        if not follows_floats(vt):
            raise Unsure("a float through a rocker, with the spring's surge chain or a rigid train")
        self.motion, self.w, self.rev = motion, w, rev
        self.loaded, self.free = systems
        self.lash, self.m_c, m_v, k, c, self.f0, self.tappet, self.tol = numbers
        self.kt, self.ct = kt, ct = float(vt.train.train_stiffness), float(vt.train.train_damping)
        self.r = r = float(vt.ratio)
        self.e_cam, self.floor = float(vt.cam_restitution), landing_floor(vt, w)
        mc, mv = self.m_c * w * w, m_v * w * w
        still = np.zeros((rev.g.size - 1, ORDER))
        # (x_c, x_c', x_v, x_v'): the train pushing (coupled), and not (the follower on its tappet force alone)
        pushed = np.array(
            [
                [0.0, 1.0, 0.0, 0.0],
                [-r * r * kt / mc, -r * r * ct * w / mc, r * kt / mc, r * ct * w / mc],
                [0.0, 0.0, 0.0, 1.0],
                [r * kt / mv, r * ct * w / mv, -(kt + k) / mv, -(ct + c) * w / mv],
            ]
        )
        apart = np.array([[0.0, 1.0, 0.0, 0.0], [0.0] * 4, [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, -k / mv, -c * w / mv]])
        b_pushed = np.array([0.0, (r * kt * self.lash - self.tappet) / mc, 0.0, (-kt * self.lash - self.f0) / mv])
        b_apart = np.array([0.0, -self.tappet / mc, 0.0, -self.f0 / mv])
        self.systems = {True: Linear(pushed, b_pushed, still, rev.h), False: Linear(apart, b_apart, still, rev.h)}
        self.stretches = 0  # :meth:`_stretch`'s count
        self.slope = hermite_taylor(rev.s1, rev.s2, rev.h, rev.s2_before)  # the cam's slope between the fine angles

    def _stretch(self, lin: Linear, step: int, tau: float, y: np.ndarray, guard, fresh: bool = False):
        """:func:`~._valvelinear.stretch_to`, counted against the event's :data:`_MAX_STRETCHES`."""
        self.stretches += 1
        if self.stretches > _MAX_STRETCHES:
            raise Unsure("the follower or the train chatters within the float")
        return stretch_to(lin, step, tau, y, guard, fresh=fresh)

    # -- what the contacts see ------------------------------------------------------------------------------------

    def _motion(self, steps: Index, taus: Index, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The cam's s, s', s'' (m, m/rad, m/rad^2) ``taus`` rad into fine ``steps``: on the fine angles, and between
        them on each step's cubic Hermite of s and of s' (the motion's own program costs half a millisecond a call,
        the guards' thousands of calls a speed)."""
        steps, taus = np.broadcast_to(steps, (size,)), np.broadcast_to(taus, (size,))
        rev = self.rev
        if not taus.any():  # the fine angles themselves (a stretch's march)
            return rev.s[steps], rev.s1[steps], rev.s2[steps]
        s, s1 = rev.at_cam(steps, taus)
        _, s2 = hermite_at(self.slope, rev.s1, rev.s2, steps, taus)
        return s, s1, s2

    def _train(self, xc, pc, xv, pv) -> tuple[np.ndarray, np.ndarray]:
        """The train's hold (its least of the spring's and the whole force: > 0 while it pushes) and its force on
        the valve (0 where it does not push), N."""
        d = self.r * xc - self.lash - xv
        f = self.kt * d + self.ct * self.w * (self.r * pc - pv)
        return np.minimum(self.kt * d, f), np.where(d > 0.0, np.maximum(f, 0.0), 0.0)

    def _on_cam(self, ys: np.ndarray, steps: Index, taus: Index) -> tuple[np.ndarray, ...]:
        """The valve's states ``ys`` (x_v, x_v') on its train with the follower on the cam: (the cam's force + the
        diffrax model's tolerance, the train's hold, the valve above its seat, the cam's force, the train's), N."""
        s, s1, s2 = self._motion(steps, taus, len(ys))
        hold, f_t = self._train(s, s1, ys[:, 0], ys[:, 1])
        f_cam = self._cam_force(s2, f_t)
        return f_cam + self.tol, hold, self.kt * (ys[:, 0] + GAP_EPS), f_cam, f_t

    def _cam_force(self, s2: np.ndarray, f_t: np.ndarray) -> np.ndarray:
        """The cam contact's force (N) with the follower on the cam (its acceleration ``s2``, m/rad^2) and the train
        pushing the valve with ``f_t`` (N)."""
        return self.m_c * s2 * self.w**2 + self.tappet + self.r * f_t

    def _gap(self, steps: np.ndarray, x_v: np.ndarray) -> np.ndarray:
        """The valve's lift ``x_v`` above where the cam would hold it at fine ``steps`` (m)."""
        return x_v - np.maximum(self.rev.g[steps] - self.lash, 0.0)

    def _flying(self, ys: np.ndarray, steps: Index, taus: Index) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The flight's states ``ys``: (the follower above the cam, the train's hold, the valve above its seat), N."""
        s, _, _ = self._motion(steps, taus, len(ys))
        hold, _ = self._train(ys[:, _X_C], ys[:, _P_C], ys[:, _X_V], ys[:, _P_V])
        return self.kt * (ys[:, _X_C] - s + GAP_EPS), hold, self.kt * (ys[:, _X_V] + GAP_EPS)

    # -- the output grid's rows -----------------------------------------------------------------------------------

    def _grid(self, steps: np.ndarray, taus: np.ndarray) -> np.ndarray:
        """Which of the states at fine ``steps`` and ``taus`` lie on the output grid's angles."""
        return (taus == 0.0) & self.rev.out_node[np.minimum(steps, self.rev.g.size - 1)]

    def rows_on_cam(self, rows: EventRows, ys: np.ndarray, steps: np.ndarray, taus: np.ndarray) -> None:
        """The output grid's rows of valve states ``ys`` on the train, the follower on the cam."""
        on = self._grid(steps, taus)
        if not on.any():
            return
        _, _, _, f_cam, f_t = self._on_cam(ys[on], steps[on], 0.0)
        at = steps[on]
        rows.add(f_cam, f_cam, f_t, ys[on, 0], self._gap(at, ys[on, 0]), self._deg(at))

    def _rows_flying(self, rows: EventRows, ys: np.ndarray, steps: np.ndarray, taus: np.ndarray) -> None:
        on = self._grid(steps, taus)
        if not on.any():
            return
        at, y = steps[on], ys[on]
        _, f_t = self._train(y[:, _X_C], y[:, _P_C], y[:, _X_V], y[:, _P_V])
        # the hold: the cam's force were the follower on it (at the cam's lift and speed), the valve as it moves
        _, held = self._train(self.rev.s[at], self.rev.s1[at], y[:, _X_V], y[:, _P_V])
        rows.add(
            np.zeros(at.size),
            self._cam_force(self.rev.s2[at], held),
            f_t,
            y[:, _X_V],
            self._gap(at, y[:, _X_V]),
            self._deg(at),
        )

    def _deg(self, steps: np.ndarray) -> np.ndarray:
        return np.degrees(self.rev.th0 + steps * self.rev.h) % 360.0

    # -- the event --------------------------------------------------------------------------------------------------

    def start(self, step: int, y: np.ndarray) -> tuple[float, np.ndarray]:
        """Where in fine ``step`` (from the valve's state ``y`` at its start, on its train) the cam's force falls
        below the diffrax model's threshold: (rad into the step, the valve's state there)."""
        got = cross(self.loaded, step, 0.0, y, self.rev.h, lambda ys, st, ta: self._on_cam(ys, st, ta)[0], False)
        if got is None:
            raise Unsure("the float's start lost")
        return got

    def event(
        self, step: int, tau: float, y: np.ndarray, rows: EventRows, half_lift: float
    ) -> tuple[int, float, np.ndarray]:
        """From the cam letting go ``tau`` rad into fine ``step`` (the valve's state ``y`` there, on its train) to
        the valve's seating: each flight to its landing, each stretch back on the cam (the valve on its train or off
        it, on its spring) to the next float, the rows of the output grid added to ``rows``. Returns where the valve
        seats (fine step, rad into it) and its state there (x_v, x_v'): a seating once it has risen past
        ``half_lift`` (m) on the output grid, as the diffrax model's event ends."""
        for _ in range(_MAX_STRETCHES):
            step, tau, y = self._flight(step, tau, y, rows)
            pushing = bool(self._on_cam(y[None], step, tau)[1][0] > 0.0)
            step, tau, y, let_go, _ = self.ride(step, tau, y, rows, half_lift, pushing)
            if not let_go:  # seated: the rebounds are the fast path's
                return step, tau, y
        raise Unsure("the follower chatters on the cam within the event")

    def ride(
        self, step: int, tau: float, y: np.ndarray, rows: EventRows, half_lift: float, pushing: bool, held: bool = False
    ) -> tuple[int, float, np.ndarray, bool, float]:
        """The follower on the cam from ``tau`` rad into fine ``step``, the valve (state ``y``) on its train where
        ``pushing``, else off it on its spring, each stretch to the train taking hold or letting go, to the valve's
        seating (once it has risen past ``half_lift``, m) or the cam letting go; the output grid's rows added to
        ``rows``. Returns (fine step, rad into it, the valve's state there, whether the cam let go, the least cam
        force on the fine angles passed, N). ``held``: the follower held on the cam to the seating whatever the cam's
        force (the force it would then pull with: :class:`~._valveevent.Floated`'s), whose lower bound between the
        fine angles must stay clear of the threshold (else :class:`~._valvelinear.Unsure`) unless the force falls
        below it on them."""
        least = bound = np.inf
        for _ in range(_MAX_STRETCHES):
            sign = 1.0 if pushing else -1.0

            def guard(ys: np.ndarray, st: Index, ta: Index, sign: float = sign) -> np.ndarray:
                cam, hold, seat, _, _ = self._on_cam(ys, st, ta)
                return np.minimum(np.minimum(np.inf if held else cam, sign * hold), seat)

            along, steps, taus, end = self._stretch(self.loaded if pushing else self.free, step, tau, y, guard)
            if end is None:
                raise Unsure("the valve in the air at the revolution's end")
            on = taus == 0.0
            cam_tol = self._on_cam(along[on], steps[on], 0.0)[0]  # the cam's force + the diffrax model's threshold
            least = min(least, float(np.min(cam_tol, initial=np.inf)) - self.tol)
            bound = min(bound, float(np.min(step_bounds(cam_tol), initial=np.inf)))
            if bound < 0.0 and not (held and least < -self.tol):
                raise Unsure("the cam contact's force near its threshold between the fine angles")
            self.rows_on_cam(rows, along, steps, taus)
            step, tau, y = end
            cam, hold, seat, _, _ = (float(v[0]) for v in self._on_cam(y[None], step, tau))
            which = int(np.argmin([np.inf if held else cam, sign * hold, seat]))
            if which == 2:
                if not float(np.max(rows.joined("lift"), initial=0.0)) > half_lift:
                    raise Unsure("the valve back on its seat before it rose past half its lift")
                return step, tau, y, False, least
            if which == 0:
                return step, tau, y, True, least
            pushing = not pushing  # the train's hold crossed zero: read at the root it is zero, not its sign
        raise Unsure("the train takes hold of the valve and lets it go beyond count")

    def _flight(self, step: int, tau: float, y: np.ndarray, rows: EventRows) -> tuple[int, float, np.ndarray]:
        """A flight from the cam letting go ``tau`` rad into fine ``step`` (the valve's state ``y``) to where the
        follower stays on the cam again: (fine step, rad into it, the valve's state)."""
        (s,), (s1,), _ = self._motion(step, tau, 1)
        z = np.array([s, s1, y[0], y[1]])
        fresh = True
        pushing = bool(self._train(z[_X_C], z[_P_C], z[_X_V], z[_P_V])[0] > 0.0)
        for _ in range(_MAX_STRETCHES):
            sign = 1.0 if pushing else -1.0

            def guard(zs: np.ndarray, st: Index, ta: Index, sign: float = sign) -> np.ndarray:
                cam, hold, seat = self._flying(zs, st, ta)
                return np.minimum(np.minimum(cam, sign * hold), seat)

            along, steps, taus, end = self._stretch(self.systems[pushing], step, tau, z, guard, fresh)
            if end is None:
                raise Unsure("the follower in the air at the revolution's end")
            self._rows_flying(rows, along, steps, taus)
            step, tau, z = end
            cam, hold, seat = (float(v[0]) for v in self._flying(z[None], step, tau))
            which = int(np.argmin([cam, sign * hold, seat]))
            fresh = which == 0
            if which == 2:
                raise Unsure("the valve seats while the follower flies")
            if which == 1:
                pushing = not pushing  # the train takes hold or lets go
                continue
            (s,), (s1,), _ = self._motion(step, tau, 1)
            rel = float(z[_P_C]) - s1  # the landing: the diffrax model's rule
            if self.e_cam > 0.0 and abs(rel) > self.floor:
                z = np.array([s, s1 - self.e_cam * rel, z[_X_V], z[_P_V]])
            elif self._on_cam(z[None, _X_V:], step, tau)[0][0] <= 0.0:  # the cam pulls away at once: flying on
                z = np.array([s, s1, z[_X_V], z[_P_V]])
            else:
                return step, tau, z[_X_V:]
            pushing = bool(self._train(z[_X_C], z[_P_C], z[_X_V], z[_P_V])[0] > 0.0)
        raise Unsure("the follower rattles on the cam")


def least_rows(rows: EventRows, floated: bool) -> tuple[float, float, float, float, float]:
    """(the least cam force over the event: 0 where it ``floated``, its angle, the least train force, the least force
    that would hold the follower on the cam (at most 0; NaN where it did not float), the valve's largest lift m) of an
    event's rows."""
    cam = rows.joined("cam")
    i = int(np.argmin(cam))
    return (
        0.0 if floated else float(cam[i]),
        float(rows.joined("deg")[i]),
        float(np.min(rows.joined("train"))),
        min(float(np.min(rows.joined("hold"))), 0.0) if floated else math.nan,
        float(np.max(rows.joined("lift"))),
    )
