"""The valvetrain's fast path: the valve event solved exactly where every contact stays closed.

From the valve's lift off its seat to its seating, with the cam contact rigid and closed (x_c = s), the lash
closed and the train in compression, the valve's equation (SI, in the cam angle, ' = d/dtheta, omega the cam
speed) is linear with constant coefficients::

    m_v w^2 x'' + (c_t + c) w x' + (k_t + k) x = u(theta) - k_t lash - F0,   u = k_t g + c_t w g'

(the train's force ``k_t d + c_t w d'`` on its deflection ``d = g - lash - x``, the valve spring ``k x + F0 + c w
x'``), where ``g(theta) = g(s(theta))`` is the cam's lift at the valve through the rocker: ``r s`` for a constant
ratio, the rocker's lever of the cam's own lift otherwise (the follower moves with the cam, so a rocker's varying
ratio is a known function of the angle, and the equation stays linear). Its exact solution over a step of a
fixed angle grid (:data:`REFINE` steps per angle of the output grid) is a matrix exponential of the system
augmented with the input's Taylor chain, the input held as the cubic through its values and slopes at both ends
(``u'`` is known exactly from s' and s'', each step's from its own side of a segment's end where s'' jumps), so the
only approximation is that cubic, of order h^4. The steps are chained as a linear recurrence in the system's modes (a
cumulative sum in blocks), contact changes located inside a step by the same exact propagator on finer angles.

What comes out equals :func:`~camdyn.model.dynamics.valvetrain_response`'s: the valve lifts where the train's force on
the seated valve reaches the preload (algebraic on a rigid cam), the least cam-contact and train forces over the event
on the output grid, the seating (x_v = 0 closing) and its speed, the rebounds off the seat (at ``seat_restitution`` x
the landing speed) each a flight on the train or, where the train's force or deflection falls to zero, off it on the
spring alone (a second linear system), to the speed below which the seat holds the valve, their highest apex (the bounce
height) and the gap at the valve, and the rest of the revolution with the valve seated. A valve that outruns its train
within the event (a steep opening flank throws it off, or its spring cannot follow the closing one) flies on its spring
alone until the train takes hold of it again, each stretch on its linear system (:meth:`~._valvefloat.ValveFloats.ride`;
a constant ratio and no surge chain, else the diffrax model's). The answer is ``None`` (the caller falls back on the
diffrax model for that point) wherever the linear model stops holding before the revolution ends: the train unloads
before the seating (through a rocker or with the surge chain), the cam contact's force comes within the sampling's bound
of zero without a sure crossing, the valve lifts again after the seating, the follower leaves the cam while the valve
rebounds (or at all, with the spring's surge chain), or the model is not this one (a compliant cam contact; a rigid
train with the spring's surge chain). A flight of the follower off the cam while the valve sits on its seat (a ramp that
decelerates faster than the tappet force pulls) is followed to its landing (:mod:`._valveflight`): the valve's event is
unchanged. Where the cam contact's force crosses zero on the exact solution before anything else opens, the valve floats
there for sure: :class:`Floated`, with what happens next left to the diffrax model, or with ``floats`` (the bounce
search past the float speed) followed through its flights and landings (:mod:`._valvefloat`). A rigid train needs no
integration in the event: the valve moves with the cam from the lash's closing to its seating, the forces algebraic in
the angle (:func:`_rigid_train`); its rebounds fly on the spring alone.

With the spring's surge chain (``[spring] model = "surge"``) the valve's system carries the chain's inner lumps
(:func:`._valveevent.valve_matrix`: still linear, one mode a lump more) and the chain rings on while the valve is
seated (a third system, the valve held): the valve lifts where the train's force passes the chain's on the seat,
no longer algebraic. The diffrax model reports the second revolution from rest (the first leaves the chain ringing),
so the fast path solves two: the first for the chain's state at its end, the second from it; a valve that floats in
the first goes to the diffrax model whole.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..._core.units import M_PER_MM, THETA_GRID
from ..motion import Motion
from ..valvetrain import ValvetrainModel, static_valve_lift
from ._cubic import hermite_taylor
from ._valveevent import (
    MAX_REBOUNDS,
    MAX_SWITCHES,
    Floated,
    ValveSummary,
    constants,
    exact_at_valve,
    flight_reach,
    layout,
    on_spring,
    revolution,
    seated,
    summary,
    valve_matrix,
)
from ._valvefield import GAP_EPS
from ._valveflight import FollowerFlights
from ._valvefloat import EventRows, ValveFloats, follows_floats, least_rows
from ._valvelinear import Index, Linear, Unsure, cross, lower_bound, rise, step_bounds, stretch_to
from ._valvetrain import landing_floor

__all__ = ["Floated", "ValveSummary", "fast_valve_summary"]


def fast_valve_summary(
    motion: Motion, vt: ValvetrainModel, omega: float, n: int = THETA_GRID, *, floats: bool = False
) -> ValveSummary | Floated | None:
    """The :class:`ValveSummary` at cam speed ``omega`` (rad/s) on the fast path, :class:`Floated` where the valve
    surely floats, or None where the fast path cannot say (the caller runs the diffrax model). ``floats``: a float
    is followed through (:mod:`._valvefloat`, a compliant train of constant ratio) to a summary, not cut short at
    :class:`Floated` (whose force is the float search's)."""
    if not vt.rigid_cam or (vt.coils is not None and vt.rigid_train):
        return None
    try:
        if vt.rigid_train:
            return _rigid_train(motion, vt, float(omega), n)
        return _rigid_cam(motion, vt, float(omega), n, floats)
    except Unsure:
        return None


def _rigid_cam(motion: Motion, vt: ValvetrainModel, w: float, n: int, floats: bool) -> ValveSummary | Floated:
    """:func:`fast_valve_summary` of a rigid cam contact and a compliant train: one revolution from rest, or with the
    spring's surge chain the second (the first for the chain's ringing at its end)."""
    train = _CompliantTrain(motion, vt, w, n, floats)
    rest = np.zeros(2 * train.layout.lumps)
    if not rest.size:
        return train.revolution(rest)[0]
    first, ringing = train.revolution(rest)
    if isinstance(first, Floated):
        raise Unsure("the valve floats in the revolution from rest: the next starts from the diffrax model's flight")
    return train.revolution(ringing)[0]


class _CompliantTrain:
    """A rigid cam contact and a compliant train at cam speed ``w`` (rad/s): the valve's linear systems on ``n`` x
    :data:`REFINE` fine steps, the forces the seated valve sees, and the contacts' guards."""

    def __init__(self, motion: Motion, vt: ValvetrainModel, w: float, n: int, floats: bool = False) -> None:
        self.motion, self.vt, self.w, self.follow_floats = motion, vt, w, floats
        self.rev = rev = revolution(motion, vt, n)
        s, s2, g, g1, g2, ratio, h = rev.s, rev.s2, rev.g, rev.g1, rev.g2, rev.ratio, rev.h
        self.nf, w2 = s.size - 1, w * w
        self.lash, m_c, m_v, self.k, _, self.f0, tappet, self.tol = constants(vt)
        self.kt, self.ct = kt, ct = float(vt.train.train_stiffness), float(vt.train.train_damping)
        self.layout = layout(vt)
        # the valve seated (x_v = 0): the train's force and the cam's with no train force on the follower
        seated_defl = g - self.lash
        self.f_seated = np.where(seated_defl > 0.0, np.maximum(0.0, kt * seated_defl + ct * w * g1), 0.0)
        self.f_cam_bare = m_c * s2 * w2 + tappet
        self.on_cam = self.f_cam_bare + ratio * self.f_seated  # the cam's force with the valve seated
        # the valve off its seat, on the train (loaded) or off it (free, on its spring alone), and the chain ringing
        # on the seated valve: linear systems
        self.loaded = Linear(
            valve_matrix(vt, w, kt, ct),
            (-kt * self.lash - self.f0) / (m_v * w2),
            hermite_taylor(
                (kt * g + ct * w * g1) / (m_v * w2),
                (kt * g1 + ct * w * g2) / (m_v * w2),
                h,
                (kt * g1 + ct * w * rev.g2_before) / (m_v * w2),
            ),
            h,
        )
        self.free = on_spring(vt, w, self.nf, h)
        self.seated = seated(vt, w, self.nf, h) if self.layout.lumps else None
        self.flights = FollowerFlights(motion, vt, w, rev, self.on_cam, constants(vt))

    def _hold_follower(self, step: int, stop: int, why: str) -> None:
        """The follower from fine angle ``step`` to ``stop`` with the valve seated: its flights off the cam followed
        to their landings (:meth:`FollowerFlights.hold`); with the spring's surge chain, whose ringing the seat's
        hold would carry, :class:`Unsure` (``why``) where it may leave the cam at all."""
        if not self.layout.lumps:
            self.flights.hold(step, stop)
        elif lower_bound(self.on_cam[step : stop + 1]) < -self.tol:
            raise Unsure(why)

    def train(self, x: np.ndarray, p: np.ndarray, steps: Index, taus: Index) -> tuple[np.ndarray, np.ndarray]:
        """The train's deflection (m) and its linear force (N) at valve lifts ``x`` and speeds ``p``, ``taus`` into
        fine ``steps``."""
        at, at1 = self.rev.at_valve(np.broadcast_to(steps, x.shape), np.broadcast_to(taus, x.shape))
        d = at - self.lash - x
        return d, self.kt * d + self.ct * self.w * (at1 - p)

    def on_train(self, ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        """> 0 while the train pushes the valve (N)."""
        d, f_t = self.train(ys[:, self.layout.x], ys[:, self.layout.v], steps, taus)
        return np.minimum(self.kt * d, f_t)

    def landing(self, ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        """The valve above its seat (N: as the train)."""
        return self.kt * (ys[:, self.layout.x] + GAP_EPS)

    def rising(self, ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        return ys[:, self.layout.v]

    def holds(self, chains: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        """> 0 while the seat holds the valve (N): the spring's force on it (the chain's last segment and the
        preload) less the train's, with the diffrax model's tolerance. ``chains``: the seated system's states."""
        m = self.layout.lumps
        zero = np.zeros(len(chains))
        d, f_t = self.train(zero, zero, steps, taus)
        pushed = np.where(d > 0.0, np.maximum(0.0, f_t), 0.0)
        coils = self.vt.coils
        assert coils is not None  # the seated system is the chain's
        k_s, c_s = float(coils.segment_rate), float(coils.segment_damping)
        spring = self.f0 - k_s * chains[:, m - 1] - c_s * self.w * chains[:, 2 * m - 1]
        return spring - pushed + self.tol

    def _lift(self, chain0: np.ndarray) -> tuple[int, float, np.ndarray]:
        """Where the train lifts the valve off its seat in a revolution that starts with the chain's state
        ``chain0``: (fine step, rad into it, the chain's state there); the revolution's end (step ``nf``) where the
        valve never lifts."""
        rev, h, tol = self.rev, self.rev.h, self.tol
        if not chain0.any():  # no chain, or one at rest (it stays so on the seated valve): algebraic
            lifts = np.nonzero(self.f_seated - self.f0 - tol > 0.0)[0]
            if not lifts.size:
                return self.nf, 0.0, chain0
            j = int(lifts[0])
            if j == 0:
                raise Unsure("the valve lifts as the revolution starts")
            if self.layout.lumps:  # without the chain, the flights before the lift are followed last (:meth:`_held`)
                self._hold_follower(0, j, "the follower leaves the cam before the valve lifts")
            motion, vt, lash, kt, ct, w, f0 = self.motion, self.vt, self.lash, self.kt, self.ct, self.w, self.f0

            def seated_force(theta: np.ndarray) -> np.ndarray:  # the train's on the seated valve, less F0 + tol
                g_v, g1_v = exact_at_valve(motion, vt, theta)
                d = g_v - lash
                return np.where(d > 0.0, np.maximum(0.0, kt * d + ct * w * g1_v), 0.0) - f0 - tol

            step = j - 1
            tau = rise(seated_force, rev.th0 + step * h, rev.th0 + j * h) - (rev.th0 + step * h)
            return step, tau, chain0
        assert self.seated is not None  # a chain to ring
        if self.holds(chain0[None], 0, 0.0)[0] <= 0.0:
            raise Unsure("the valve off its seat as the revolution starts")
        along, _, _, end = stretch_to(self.seated, 0, 0.0, chain0, self.holds)
        if end is None:
            return self.nf, 0.0, along[-1]
        step, tau, chain = end
        if step == 0 or lower_bound(self.on_cam[: step + 2]) < -tol:
            raise Unsure("the follower leaves the cam before the valve lifts")
        return step, tau, chain

    def _held(self, step: int, tau: float, chain: np.ndarray, lift_step: int) -> np.ndarray:
        """The valve held on its seat from ``tau`` rad into fine ``step`` to the revolution's end, the follower on the
        cam or flying off it (a flight over the revolution's end goes on at its start, where it must land before the
        valve lifts in fine step ``lift_step``): the chain's state at the end (empty without one)."""
        rest = slice(step + 1, self.nf + 1)
        if self.seated is None:
            if np.any(self.f_seated[rest] > self.f0):
                raise Unsure("the valve re-lifted after the seating")
            # the follower's flights, followed once the valve's event is known (where that fails they are not
            # needed): after the seating, and before the lift, from the revolution's start or from a flight over
            # its end (the periodic revolution then starts with the follower in the air)
            carried = self.flights.hold(step + 1, self.nf, carry=True)
            self.flights.hold(0, lift_step + 1, flying=carried)
            return chain
        if lower_bound(self.on_cam[rest]) < -self.tol:
            raise Unsure("the follower off the cam after the seating")
        along, _, _, end = stretch_to(self.seated, step, tau, chain, self.holds)
        if end is not None:
            raise Unsure("the valve re-lifted after the seating")
        return along[-1]

    def revolution(self, chain0: np.ndarray) -> tuple[ValveSummary | Floated, np.ndarray]:
        """One revolution from rest on the base circle but for the surge chain's state ``chain0`` (its inner lumps'
        lifts and speeds; empty without one): its summary, and the chain's state at its end (NaN where the valve
        floats: what follows is the diffrax model's)."""
        rev, lay, nf, h, w, tol, kt = self.rev, self.layout, self.nf, self.rev.h, self.w, self.tol, self.kt
        loaded, deg, out_node = self.loaded, rev.deg, rev.out_node
        lift_step, tau_lift, chain = self._lift(chain0)
        if lift_step >= nf:  # the valve never lifts: no event, the follower held on the cam all the way round
            self._hold_follower(0, nf, "the follower leaves the cam")
            nan = math.nan
            return ValveSummary(w, nan, nan, nan, nan, nan, 0.0, 0.0), chain

        # the event: lifted by the train, to the seating after rising past half its static lift at the nose (a landing
        # before belongs to the opening: the diffrax model's rule)
        y_first = loaded.advance(lift_step, tau_lift, lay.lifted(chain), np.array([h - tau_lift]))[0]
        ys = loaded.march(lift_step + 1, y_first)  # to the revolution's end: the seating is late in it
        idx = np.arange(lift_step + 1, nf + 1)
        xv = ys[:, lay.x]
        d, f_t = self.train(xv, ys[:, lay.v], idx, 0.0)
        f_cam = self.f_cam_bare[idx] + rev.ratio[idx] * f_t
        reach = float(rev.g.max()) - float(rev.g.min()) - self.lash
        half_lift = 0.5 * static_valve_lift(reach, self.f0, kt, self.k)
        risen = np.nonzero(xv > half_lift)[0]
        down = np.nonzero(xv[risen[0] :] < -GAP_EPS)[0] if risen.size else risen
        if not down.size or np.any(xv[: risen[0]] < -GAP_EPS):
            raise Unsure("no seating after the valve's rise")
        q = int(risen[0] + down[0])  # the first fine angle below the seat, counted from lift_step + 1
        train_open = np.nonzero((d[:q] <= 0.0) | (f_t[:q] < 0.0))[0]
        cam_open = np.nonzero(f_cam[:q] < -tol)[0]
        if cam_open.size and (not train_open.size or cam_open[0] < train_open[0]):
            # the exact solution's cam force crosses the diffrax model's threshold first: float
            if not self.follow_floats:
                return Floated(float(np.min(f_cam[:q]))), np.full_like(chain0, np.nan)
            return self._through_float(lift_step, ys, (idx, xv, f_t, f_cam), half_lift, int(cam_open[0]))
        if (train_open.size or lower_bound(f_t[:q]) <= 0.0) and follows_floats(self.vt):
            return self._off_the_train(lift_step, tau_lift, chain, half_lift)
        if train_open.size or lower_bound(f_cam[:q]) <= tol or lower_bound(f_t[:q]) <= 0.0:
            raise Unsure("the cam contact near opening, or the valve off the train, within the event")
        got = cross(loaded, lift_step + q, 0.0, ys[q - 1], h, self.landing, False)
        if got is None:
            raise Unsure("the seating lost")
        event = out_node[idx[:q]]
        least = int(np.argmin(np.where(event, f_cam[:q], np.inf)))
        least_force, least_deg = float(f_cam[least]), deg(lift_step + 1 + least, 0.0)
        least_train = float(np.min(f_t[:q][event]))
        max_lift = float(np.max(xv[:q][event]))
        step, tau, y = lift_step + q, got[0], got[1]
        seating_velocity, seating_deg = abs(float(y[lay.v])) * w, deg(step, tau)
        step, tau, y, rebounds = self._rebounds(step, tau, y)
        event_numbers = (least_force, least_deg, least_train, seating_velocity, seating_deg)
        return summary(w, event_numbers, rebounds, max_lift), self._held(step, tau, lay.chain(y), lift_step)

    def _through_float(
        self, lift_step: int, ys: np.ndarray, marched: tuple[np.ndarray, ...], half_lift: float, opens: int
    ) -> tuple[ValveSummary, np.ndarray]:
        """The revolution of a valve that floats: its event followed through its floats (:mod:`._valvefloat`) from
        the lift at fine ``lift_step`` (``ys``: the valve's states on its train from the next fine angle, with
        ``marched``: their fine angles, lifts, train and cam forces), the cam letting go before fine angle
        ``opens`` of them, to its seating past ``half_lift`` (m); then its rebounds and the rest of the revolution
        as the fast path's."""
        idx, xv, f_t, f_cam = marched
        if opens == 0:
            raise Unsure("the cam lets go as the valve lifts")
        if np.min(step_bounds(f_cam[:opens] + self.tol), initial=np.inf) < 0.0 or lower_bound(f_t[:opens]) <= 0.0:
            raise Unsure("the cam contact or the train near opening before the float")
        floats = self._floats()
        rows = EventRows()
        floats.rows_on_cam(rows, ys[:opens], idx[:opens], np.zeros(opens))
        tau, y = floats.start(int(idx[opens]) - 1, ys[opens - 1])
        seated_at = floats.event(int(idx[opens]) - 1, tau, y, rows, half_lift)
        return self._event_summary(rows, seated_at, lift_step, floated=True)

    def _off_the_train(
        self, lift_step: int, tau_lift: float, chain: np.ndarray, half_lift: float
    ) -> tuple[ValveSummary | Floated, np.ndarray]:
        """The revolution of a valve that leaves its train within its event (a steep ramp throws it past the train's
        reach, or its spring cannot follow the closing flank) from its lift ``tau_lift`` rad into fine ``lift_step``
        (the chain's state ``chain``): each stretch on the train or off it on the spring alone, the follower on the
        cam, to the seating past ``half_lift`` (m) (:meth:`ValveFloats.ride`). Where the cam lets go on the way the
        valve floats: :class:`Floated` (the force the cam would pull with, the follower held to the seating), or the
        float followed through (``floats``). Then the rebounds and the rest of the revolution as the fast path's."""
        floats, rows, y = self._floats(), EventRows(), self.layout.lifted(chain)
        step, tau, y, let_go, least = floats.ride(lift_step, tau_lift, y, rows, half_lift, True, not self.follow_floats)
        if not self.follow_floats and least < -self.tol:
            return Floated(least), np.full_like(chain, np.nan)
        if let_go:
            seated_at = floats.event(step, tau, y, rows, half_lift)
            return self._event_summary(rows, seated_at, lift_step, floated=True)
        return self._event_summary(rows, (step, tau, y), lift_step, floated=False)

    def _floats(self) -> ValveFloats:
        """The valve's and the follower's systems through the contacts' changes (:mod:`._valvefloat`)."""
        return ValveFloats(self.motion, self.vt, self.w, self.rev, (self.loaded, self.free), constants(self.vt))

    def _event_summary(
        self, rows: EventRows, seated_at: tuple[int, float, np.ndarray], lift_step: int, floated: bool
    ) -> tuple[ValveSummary, np.ndarray]:
        """The summary of an event followed stretch by stretch (its output grid's ``rows``, the valve seated at
        ``seated_at``: fine step, rad into it, state), ``floated`` or not; then its rebounds and the rest of the
        revolution as the fast path's."""
        step, tau, y = seated_at
        least_force, least_deg, least_train, hold, max_lift = least_rows(rows, floated)
        seating = (abs(float(y[self.layout.v])) * self.w, self.rev.deg(step, tau))
        step, tau, y, (bounce, flight_lift, gap) = self._rebounds(step, tau, y)
        # the valve above where the cam would hold it in the event, as on the rebounds
        gap = max(gap, float(np.max(rows.joined("gap"), initial=0.0)))
        got = summary(self.w, (least_force, least_deg, least_train, *seating), (bounce, flight_lift, gap), max_lift)
        if floated:  # the float's lifts bound the gap as the rebounds' do (a coil bind below them: the diffrax model's)
            bounce_lift = max(got.bounce_lift_mm, max_lift / M_PER_MM)
            got = replace(got, floated=True, hold_force=hold, bounce_lift_mm=bounce_lift)
        return got, self._held(step, tau, self.layout.chain(y), lift_step)

    def _cam_force(self, ys: np.ndarray, steps: np.ndarray, taus: np.ndarray, loaded: bool) -> float:
        """The least cam-contact force (N) at a rebound's states ``ys``: the follower's own (its mass on the cam, the
        tappet force) and, while the valve flies on the train (``loaded``), the train's at the rocker's ratio (a
        cam that decelerates on its closing ramp with the lash still closed is held there by the train)."""
        at = np.minimum(steps, self.nf)
        force = self.f_cam_bare[at]
        if loaded:
            force = force + self.rev.ratio[at] * self.train(ys[:, self.layout.x], ys[:, self.layout.v], steps, taus)[1]
        return float(np.min(force, initial=math.inf))

    def _rebounds(
        self, step: int, tau: float, y: np.ndarray
    ) -> tuple[int, float, np.ndarray, tuple[float, float, float]]:
        """The rebounds off the seat from the seating at ``tau`` rad into fine ``step`` (state ``y``), at
        seat_restitution x the landing speed, each a flight on the train or off it, to the speed below which the seat
        holds the valve: where it is held, the state there, and the highest apex (the bounce height), the highest
        lift on the output grid and the largest gap at the valve above the cam's hold (m)."""
        rev, lay, tol = self.rev, self.layout, self.tol
        floor, e_seat = landing_floor(self.vt, self.w), float(self.vt.seat_restitution)
        bounce = gap = flight_lift = 0.0
        for _ in range(MAX_REBOUNDS):
            v = -e_seat * float(y[lay.v])
            if v <= floor:
                return step, tau, y, (bounce, flight_lift, gap)
            y = lay.lifted(lay.chain(y), 0.0, v)
            first = True
            for _ in range(MAX_SWITCHES):  # the flight's stretches, each on one system
                lin, sign = (self.loaded, 1.0) if self.on_train(y[None], step, tau)[0] > 0.0 else (self.free, -1.0)

                def guard(ys: np.ndarray, st: Index, ta: Index, sign: float = sign) -> np.ndarray:
                    return np.minimum(self.landing(ys, st, ta), sign * self.on_train(ys, st, ta))

                along, steps, taus, end = stretch_to(lin, step, tau, y, guard, fresh=first)
                if end is None:
                    raise Unsure("the valve in the air at the revolution's end")
                if y[lay.v] > 0.0 and end[2][lay.v] <= 0.0:  # the apex in this stretch
                    apex = stretch_to(lin, step, tau, y, self.rising, fresh=first)[3]
                    top = float(apex[2][lay.x]) if apex is not None else float(np.max(along[:, lay.x]))
                    bounce = max(bounce, top)
                bounce = max(bounce, float(np.max(along[:, lay.x])))
                lift_here, gap_here = flight_reach(rev, self.lash, along[:, lay.x], steps, taus)
                flight_lift, gap = max(flight_lift, lift_here), max(gap, gap_here)
                if self._cam_force(along, steps, taus, sign > 0.0) < -tol:
                    raise Unsure("the follower leaves the cam while the valve rebounds")
                step, tau, y = end
                first = False
                if (
                    self.landing(y[None], step, tau)[0] <= self.kt * GAP_EPS * 1e-3
                ):  # on the seat: not a change of system
                    break
            else:  # the train's force dithering about zero (a stiff train): the diffrax model's
                raise Unsure("the train takes hold of the rebounding valve and lets it go beyond count")
        raise Unsure("the valve rattles on its seat beyond the rebounds followed")


def _rigid_train(motion: Motion, vt: ValvetrainModel, w: float, n: int) -> ValveSummary | Floated:
    """:func:`fast_valve_summary` of a rigid cam contact and a rigid train: the lash closes as a plastic impact that
    lifts the valve with the cam, which then moves with it (x_v = g - lash) to its seating, the train's and the
    cam's forces algebraic in the angle; each rebound off the seat flies on the valve spring alone (the train open,
    the cam's lift at the valve below the lash on its closing ramp): the same linear system as a compliant train's
    flight off it. The diffrax model's events and tolerances: the lash closes GAP_EPS past the cam's reach, the
    valve seats GAP_EPS below its seat."""
    rev = revolution(motion, vt, n)
    s1, s2, g, ratio, ratio1, th0, h = rev.s1, rev.s2, rev.g, rev.ratio, rev.ratio1, rev.th0, rev.h
    nf, w2, deg, out_node = g.size - 1, w * w, rev.deg, rev.out_node
    lash, m_c, m_v, k, c, f0, tappet, tol = constants(vt)
    f_cam_bare = m_c * s2 * w2 + tappet  # the cam's force with the train open

    # the lash closes where the cam's lift at the valve passes it (the valve seated): the valve lifts with the cam
    closed = np.nonzero(g - lash - GAP_EPS > 0.0)[0]
    if not closed.size:  # the valve never lifts
        if lower_bound(f_cam_bare) < -tol:
            raise Unsure("the follower leaves the cam")
        nan = math.nan
        return ValveSummary(w, nan, nan, nan, nan, nan, 0.0, 0.0)
    j = int(closed[0])
    if j == 0 or lower_bound(f_cam_bare[: j + 1]) < -tol:
        raise Unsure("the follower leaves the cam before the lash closes")

    # the valve on the train, moving with the cam: its lift, the train's force and the cam's, to the seating after
    # rising past half its lift (the diffrax model's rule)
    x_v = g - lash
    f_t = m_v * (ratio * s2 + ratio1 * s1**2) * w2 + k * x_v + f0 + c * w * ratio * s1
    f_cam = f_cam_bare + ratio * f_t
    half_lift = 0.5 * (float(g.max()) - float(g.min()) - lash)
    risen = j + np.nonzero(x_v[j:] > half_lift)[0]
    down = risen[0] + np.nonzero(x_v[risen[0] :] + GAP_EPS < 0.0)[0] if risen.size else risen
    if not down.size:
        raise Unsure("no seating after the valve's rise")
    q = int(down[0])  # the first fine angle below the seat
    event = slice(j, q)
    train_open = np.nonzero(f_t[event] < -tol)[0]
    cam_open = np.nonzero(f_cam[event] < -tol)[0]
    if cam_open.size and (not train_open.size or cam_open[0] < train_open[0]):
        return Floated(float(np.min(f_cam[event])))
    if train_open.size or lower_bound(f_cam[event]) <= tol or lower_bound(f_t[event]) <= tol:
        raise Unsure("the cam contact or the train near opening within the event")
    grid = np.flatnonzero(out_node[event]) + j
    least = int(grid[np.argmin(f_cam[grid])])
    least_force, least_deg = float(f_cam[least]), deg(least, 0.0)
    least_train = float(np.min(f_t[grid]))
    max_lift = float(np.max(x_v[grid]))
    th_seat = rise(lambda t: -(exact_at_valve(motion, vt, t)[0] - lash + GAP_EPS), th0 + (q - 1) * h, th0 + q * h)
    step, tau = q - 1, th_seat - (th0 + (q - 1) * h)
    closing = float(exact_at_valve(motion, vt, np.array([th_seat]))[1][0])  # the valve's speed as it seats (m/rad, < 0)
    seating_velocity, seating_deg = abs(closing) * w, deg(step, tau)

    # the rebounds at seat_restitution x the landing speed, each a flight on the spring alone to the seat
    free = on_spring(vt, w, nf, h)

    def apart(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:  # > 0 while the train stays open (m)
        at, _ = rev.at_valve(np.broadcast_to(steps, (len(ys),)), np.broadcast_to(taus, (len(ys),)))
        return lash + ys[:, 0] - at + GAP_EPS

    def landing(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:  # the valve above its seat (m)
        return ys[:, 0] + GAP_EPS

    def rising(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        return ys[:, 1]

    def flight(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        return np.minimum(landing(ys, steps, taus), apart(ys, steps, taus))

    floor, e_seat = landing_floor(vt, w), float(vt.seat_restitution)
    bounce = gap = flight_lift = 0.0
    speed = closing
    for _ in range(MAX_REBOUNDS):
        v = -e_seat * speed
        if v <= floor:
            break
        y = np.array([0.0, v])
        along, steps, taus, end = stretch_to(free, step, tau, y, flight, fresh=True)
        if end is None or apart(end[2][None], end[0], end[1])[0] <= landing(end[2][None], end[0], end[1])[0]:
            raise Unsure("the valve in the air at the revolution's end, or meeting the train")
        apex = stretch_to(free, step, tau, y, rising, fresh=True)[3]
        bounce = max(bounce, float(apex[2][0]) if apex is not None else 0.0, float(np.max(along[:, 0])))
        lift_here, gap_here = flight_reach(rev, lash, along[:, 0], steps, taus)
        flight_lift, gap = max(flight_lift, lift_here), max(gap, gap_here)
        if np.min(f_cam_bare[np.minimum(steps, nf)]) < -tol:
            raise Unsure("the follower leaves the cam while the valve rebounds")
        step, tau, y = end
        speed = float(y[1])
    else:
        raise Unsure("the valve rattles on its seat beyond the rebounds followed")
    # the valve held on its seat to the revolution's end: the lash open, the follower on the cam
    rest = slice(step + 1, nf + 1)
    if np.any(g[rest] - lash - GAP_EPS > 0.0) or lower_bound(f_cam_bare[rest]) < -tol:
        raise Unsure("the lash closed again or the follower off the cam after the seating")
    event = (least_force, least_deg, least_train, seating_velocity, seating_deg)
    return summary(w, event, (bounce, flight_lift, gap), max_lift)
