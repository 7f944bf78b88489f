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
(``u'`` is known exactly from s' and s''), so the only approximation is that cubic, of order h^4. The steps are
chained as a linear recurrence in the system's modes (a cumulative sum in blocks), contact changes located inside a
step by the same exact propagator on finer angles.

What comes out equals :func:`~camdyn.model.dynamics.valvetrain_response`'s: the valve lifts where the train's
force on the seated valve reaches the preload (algebraic on a rigid cam), the least cam-contact and train forces
over the event on the output grid, the seating (x_v = 0 closing) and its speed, the rebounds off the seat (at
``seat_restitution`` x the landing speed) each a flight on the train or, where the train's force or deflection
falls to zero, off it on the spring alone (a second linear system), to the speed below which the seat holds the
valve, their highest apex (the bounce height) and the gap at the valve, and the rest of the revolution with the
valve seated. The answer is ``None`` (the caller falls back on the diffrax model for that point) wherever the
linear model stops holding before the revolution ends: the train unloads before the seating, the cam contact's
force comes within the sampling's bound of zero without a sure crossing, the valve lifts again after the
seating, the follower leaves the cam on the ramps or the base circle, or the model is not this one (a compliant
cam contact, the spring's surge chain). Where the cam contact's force crosses zero on the exact solution before
anything else opens, the valve floats there for sure: :class:`Floated`, with what happens next left to the diffrax
model. A rigid train needs no integration in the event: the valve moves with the cam from the lash's closing to its
seating, the forces algebraic in the angle (:func:`_rigid_train`); its rebounds fly on the spring alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..._core.units import M_PER_MM, THETA_GRID, TWO_PI
from ..motion import Motion
from ..valvetrain import ValvetrainModel, static_valve_lift
from ._cubic import hermite_taylor
from ._valvefield import GAP_EPS
from ._valvelinear import ORDER, Index, Linear, Unsure, cross, lower_bound, rise, stretch_to
from ._valvetrain import landing_floor, start_angle

REFINE = 2  # fine steps per output angle (0.05 deg): the cubic hold's error is of order h^4
_MAX_REBOUNDS = 200


@dataclass(frozen=True)
class ValveSummary:
    """What the valvetrain's studies read of its revolution at cam speed ``omega`` (rad/s): forces in N, the seating
    velocity in m/s, lifts in mm (the names and meanings of :class:`~camdyn.model.dynamics.ValvetrainResponse`'s).
    ``least_event_force`` is NaN where the valve never lifts."""

    omega: float
    least_event_force: float
    least_event_force_deg: float
    least_train_force: float
    seating_velocity: float
    seating_deg: float
    bounce_height_mm: float
    max_valve_lift_mm: float
    floated: bool = False
    max_gap_mm: float = 0.0  # the valve above where the cam would hold it (off the train on a rebound), mm
    bounce_lift_mm: float = 0.0  # the valve's highest lift on the output grid after its seating, mm


@dataclass(frozen=True)
class Floated:
    """The exact solution's cam-contact force falls below zero before anything else opens: the valve floats.
    ``least_force``: the least force (N, negative) the cam would have to pull with to hold the follower through the
    event, the contact held: the float search's force past the float speed, continuous with the least force below
    it (:func:`~camdyn.model.dynamics.float_speed` refines its zero by interpolation)."""

    least_force: float


_fine_cache: dict[int, tuple[Motion, int, np.ndarray]] = {}


def _fine(motion: Motion, n: int) -> np.ndarray:
    """s, s', s'' (m, m/rad, m/rad^2) on ``n * REFINE`` equal steps of one revolution: the motion evaluated once
    per motion and grid (a speed search asks the same motion many times)."""
    hit = _fine_cache.get(id(motion))
    if hit is not None and hit[0] is motion and hit[1] == n:
        return hit[2]
    theta = np.arange(n * REFINE) * (TWO_PI / (n * REFINE))
    vals = np.asarray(motion.host(theta))[:3] * M_PER_MM
    if len(_fine_cache) > 16:
        _fine_cache.clear()
    _fine_cache[id(motion)] = (motion, n, vals)
    return vals


def fast_valve_summary(
    motion: Motion, vt: ValvetrainModel, omega: float, n: int = THETA_GRID
) -> ValveSummary | Floated | None:
    """The :class:`ValveSummary` at cam speed ``omega`` (rad/s) on the fast path, :class:`Floated` where the valve
    surely floats, or None where the fast path cannot say (the caller runs the diffrax model)."""
    if not vt.rigid_cam or vt.coils is not None:
        return None
    try:
        return (_rigid_train if vt.rigid_train else _rigid_cam)(motion, vt, float(omega), n)
    except Unsure:
        return None


class _Revolution(NamedTuple):
    """One revolution on the fine grid (``h`` rad a step) from the diffrax model's start angle ``th0`` (rad), one
    angle past its end: the cam's lift s, s', s'' (m, m/rad, m/rad^2) and its lift at the valve through the rocker
    g, g', g'' with the ratio r and r' = dr/dx_c at the cam's lift (known functions of the angle: on the fast path
    the follower moves with the cam)."""

    s: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    g: np.ndarray
    g1: np.ndarray
    g2: np.ndarray
    ratio: np.ndarray
    ratio1: np.ndarray
    th0: float
    h: float

    @property
    def out_node(self) -> np.ndarray:
        """Whether each fine angle is one of the output grid's."""
        return (np.arange(self.s.size) % REFINE) == 0

    def deg(self, step: int, tau: float) -> float:
        """The cam angle (deg, in [0, 360)) ``tau`` rad into fine step ``step``."""
        return math.degrees(self.th0 + step * self.h + tau) % 360.0


def _revolution(motion: Motion, vt: ValvetrainModel, n: int) -> _Revolution:
    """The :class:`_Revolution` of ``motion`` through ``vt``'s lever on ``n * REFINE`` fine steps."""
    s_all, s1_all, s2_all = _fine(motion, n)
    nf = s_all.size
    h = TWO_PI / nf
    i0 = start_angle(s_all[::REFINE] / M_PER_MM) * REFINE  # the diffrax model's revolution, from here
    order = (i0 + np.arange(nf + 1)) % nf
    s, s1, s2 = s_all[order], s1_all[order], s2_all[order]
    g, ratio, ratio1 = vt.host_lever(s)
    ratio, ratio1 = np.broadcast_to(ratio, s.shape), np.broadcast_to(ratio1, s.shape)
    return _Revolution(s, s1, s2, g, ratio * s1, ratio1 * s1**2 + ratio * s2, ratio, ratio1, i0 * h, h)


def _constants(vt: ValvetrainModel) -> tuple[float, ...]:
    """The valvetrain's numbers the fast path reads (SI): the lash, the cam side's and the valve's masses, the valve
    spring's rate, damping and preload, the tappet force and the diffrax model's force tolerance on its events."""
    f0 = float(vt.preload)
    tol = 1e-6 * max(1.0, float(vt.ratio) * f0)
    masses = float(vt.cam_side_mass), float(vt.valve_mass)
    return float(vt.lash), *masses, float(vt.spring_rate), float(vt.spring_damping), f0, float(vt.tappet_force), tol


def _flight_reach(
    rev: _Revolution, lash: float, along: np.ndarray, steps: np.ndarray, taus: np.ndarray
) -> tuple[float, float]:
    """A rebound's highest lift on the output grid and its largest gap at the valve above where the cam would hold
    it (m), from its states ``along`` at fine ``steps`` and ``taus`` (rad) into them."""
    grid = (taus == 0.0) & rev.out_node[np.minimum(steps, rev.g.size - 1)]  # the output grid's angles in the flight
    held = np.maximum(rev.g[steps[grid]] - lash, 0.0)
    return float(np.max(along[grid, 0], initial=0.0)), float(np.max(along[grid, 0] - held, initial=0.0))


def _on_spring(vt: ValvetrainModel, w: float, steps: int, h: float) -> Linear:
    """The valve off the train and off its seat at cam speed ``w`` (rad/s): on its spring alone, no input, over
    ``steps`` fine steps of ``h`` rad (a rebound's flight)."""
    m_v, k, c, f0 = float(vt.valve_mass), float(vt.spring_rate), float(vt.spring_damping), float(vt.preload)
    w2 = w * w
    return Linear(
        np.array([[0.0, 1.0], [-k / (m_v * w2), -c / (m_v * w)]]), -f0 / (m_v * w2), np.zeros((steps, ORDER)), h
    )


def _summary(
    w: float, event: tuple[float, float, float, float, float], rebounds: tuple[float, float, float], max_lift: float
) -> ValveSummary:
    """The :class:`ValveSummary` at ``w`` (rad/s) from the event's (least cam force N, its angle deg, least train
    force N, seating velocity m/s, seating angle deg), the rebounds' (highest apex, highest lift on the output grid,
    largest gap at the valve; m) and the event's largest valve lift (m)."""
    bounce, flight_lift, gap = rebounds
    return ValveSummary(
        w,
        *event,
        bounce / M_PER_MM,
        max(max_lift, flight_lift) / M_PER_MM,
        max_gap_mm=gap / M_PER_MM,
        bounce_lift_mm=flight_lift / M_PER_MM,
    )


def _rigid_cam(motion: Motion, vt: ValvetrainModel, w: float, n: int) -> ValveSummary | Floated:
    """:func:`fast_valve_summary` of a rigid cam contact and a compliant train."""
    rev = _revolution(motion, vt, n)
    s, s2, g, g1, g2, ratio = rev.s, rev.s2, rev.g, rev.g1, rev.g2, rev.ratio
    th0, h, out_node = rev.th0, rev.h, rev.out_node
    nf, w2, deg = s.size - 1, w * w, rev.deg
    lash, m_c, m_v, k, c, f0, tappet, tol = _constants(vt)
    kt, ct = float(vt.train.train_stiffness), float(vt.train.train_damping)

    # the valve seated (x_v = 0): the train's force and the cam's, and where the train lifts the valve
    seated_defl = g - lash
    f_seated = np.where(seated_defl > 0.0, np.maximum(0.0, kt * seated_defl + ct * w * g1), 0.0)
    f_cam_bare = m_c * s2 * w2 + tappet  # the cam's force with no train force on the follower
    lifts = np.nonzero(f_seated - f0 - tol > 0.0)[0]
    if not lifts.size:  # the valve never lifts: no event, the follower held on the cam all the way round
        if lower_bound(f_cam_bare + ratio * f_seated) < -tol:
            raise Unsure("the follower leaves the cam")
        nan = math.nan
        return ValveSummary(w, nan, nan, nan, nan, nan, 0.0, 0.0)
    j = int(lifts[0])
    if j == 0 or lower_bound((f_cam_bare + ratio * f_seated)[: j + 1]) < -tol:
        raise Unsure("the follower leaves the cam before the valve lifts")

    def seated_force(theta: np.ndarray) -> np.ndarray:  # the train's on the seated valve, less F0 + tol
        v = np.asarray(motion.host(theta))[:2] * M_PER_MM
        g_v, ratio_v, _ = vt.host_lever(v[0])
        d = g_v - lash
        return np.where(d > 0.0, np.maximum(0.0, kt * d + ct * w * ratio_v * v[1]), 0.0) - f0 - tol

    lift_step = j - 1
    tau_lift = rise(seated_force, th0 + lift_step * h, th0 + j * h) - (th0 + lift_step * h)

    # the valve off its seat, on the train (loaded) or off it (free, on its spring alone): two linear systems
    loaded = Linear(
        np.array([[0.0, 1.0], [-(kt + k) / (m_v * w2), -(ct + c) / (m_v * w)]]),
        (-kt * lash - f0) / (m_v * w2),
        hermite_taylor((kt * g + ct * w * g1) / (m_v * w2), (kt * g1 + ct * w * g2) / (m_v * w2), h),
        h,
    )
    free = _on_spring(vt, w, nf, h)
    cam = hermite_taylor(g, g1, h)  # the cam's lift at the valve between the fine angles, for the guards there

    def train(ys: np.ndarray, steps: Index, taus: Index) -> tuple[np.ndarray, np.ndarray]:
        """The train's deflection (m) and its linear force (N) at states ``ys``, ``taus`` into fine ``steps``."""
        taus = np.broadcast_to(taus, (len(ys),))
        steps = np.broadcast_to(steps, (len(ys),))
        a0, a1, a2, a3 = cam[np.minimum(steps, nf - 1)].T
        at = np.where(taus > 0.0, a0 + a1 * taus + a2 * taus**2 / 2 + a3 * taus**3 / 6, g[steps])
        at1 = np.where(taus > 0.0, a1 + a2 * taus + a3 * taus**2 / 2, g1[steps])
        d = at - lash - ys[:, 0]
        return d, kt * d + ct * w * (at1 - ys[:, 1])

    def on_train(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:  # > 0 while the train pushes the valve (N)
        d, f_t = train(ys, steps, taus)
        return np.minimum(kt * d, f_t)

    def landing(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:  # the valve above its seat (N: as the train)
        return kt * (ys[:, 0] + GAP_EPS)

    def rising(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        return ys[:, 1]

    # the event: lifted by the train, to the seating after rising past half its static lift at the nose (a landing
    # before belongs to the opening: the diffrax model's rule)
    y_first = loaded.advance(lift_step, tau_lift, np.zeros(2), np.array([h - tau_lift]))[0]
    ys = loaded.march(lift_step + 1, y_first)  # to the revolution's end: the seating is late in it
    idx = np.arange(lift_step + 1, nf + 1)
    d, f_t = train(ys, idx, 0.0)
    f_cam = f_cam_bare[idx] + ratio[idx] * f_t
    reach = float(g.max()) - float(g.min()) - lash
    half_lift = 0.5 * static_valve_lift(reach, f0, kt, k)
    risen = np.nonzero(ys[:, 0] > half_lift)[0]
    down = np.nonzero(ys[risen[0] :, 0] < -GAP_EPS)[0] if risen.size else risen
    if not down.size or np.any(ys[: risen[0], 0] < -GAP_EPS):
        raise Unsure("no seating after the valve's rise")
    q = int(risen[0] + down[0])  # the first fine angle below the seat, counted from lift_step + 1
    train_open = np.nonzero((d[:q] <= 0.0) | (f_t[:q] < 0.0))[0]
    cam_open = np.nonzero(f_cam[:q] < -tol)[0]
    if cam_open.size and (not train_open.size or cam_open[0] < train_open[0]):
        # the exact solution's cam force crosses the diffrax model's threshold first: float
        return Floated(float(np.min(f_cam[:q])))
    if train_open.size or lower_bound(f_cam[:q]) <= tol or lower_bound(f_t[:q]) <= 0.0:
        raise Unsure("the cam contact near opening, or the valve off the train, within the event")
    got = cross(loaded, lift_step + q, 0.0, ys[q - 1], h, landing, False)
    if got is None:
        raise Unsure("the seating lost")
    event = out_node[idx[:q]]
    least = int(np.argmin(np.where(event, f_cam[:q], np.inf)))
    least_force, least_deg = float(f_cam[least]), deg(lift_step + 1 + least, 0.0)
    least_train = float(np.min(f_t[:q][event]))
    max_lift = float(np.max(ys[:q, 0][event]))
    step, tau, y = lift_step + q, got[0], got[1]
    seating_velocity, seating_deg = abs(float(y[1])) * w, deg(step, tau)

    # the rebounds at seat_restitution x the landing speed, each a flight on the train or off it, to the speed
    # below which the seat holds the valve; the bounce height is the highest apex
    floor, e_seat = landing_floor(vt, w), float(vt.seat_restitution)
    bounce = gap = flight_lift = 0.0  # the highest apex; above the cam's hold and off the seat on the output grid
    for _ in range(_MAX_REBOUNDS):
        v = -e_seat * float(y[1])
        if v <= floor:
            break
        y = np.array([0.0, v])
        first = True
        while True:  # the flight's stretches, each on one system
            lin, sign = (loaded, 1.0) if on_train(y[None], step, tau)[0] > 0.0 else (free, -1.0)
            guard = lambda ys, st, ta, sign=sign: np.minimum(landing(ys, st, ta), sign * on_train(ys, st, ta))  # noqa: E731
            along, steps, taus, end = stretch_to(lin, step, tau, y, guard, fresh=first)
            if end is None:
                raise Unsure("the valve in the air at the revolution's end")
            if y[1] > 0.0 and end[2][1] <= 0.0:  # the apex in this stretch
                apex = stretch_to(lin, step, tau, y, rising, fresh=first)[3]
                bounce = max(bounce, float(apex[2][0]) if apex is not None else float(np.max(along[:, 0])))
            bounce = max(bounce, float(np.max(along[:, 0])))
            lift_here, gap_here = _flight_reach(rev, lash, along, steps, taus)
            flight_lift, gap = max(flight_lift, lift_here), max(gap, gap_here)
            if np.min(f_cam_bare[np.minimum(steps, nf)]) < -tol:
                raise Unsure("the follower leaves the cam while the valve rebounds")
            step, tau, y = end
            first = False
            if landing(y[None], step, tau)[0] <= kt * GAP_EPS * 1e-3:  # on the seat (not a change of system)
                break
    else:
        raise Unsure("the valve rattles on its seat beyond the rebounds followed")
    # the valve held on its seat to the revolution's end: no re-lift, the follower on the cam
    rest = slice(step + 1, nf + 1)
    if np.any(f_seated[rest] > f0) or lower_bound((f_cam_bare + ratio * f_seated)[rest]) < -tol:
        raise Unsure("the valve re-lifted or the follower off the cam after the seating")
    event = (least_force, least_deg, least_train, seating_velocity, seating_deg)
    return _summary(w, event, (bounce, flight_lift, gap), max_lift)


def _rigid_train(motion: Motion, vt: ValvetrainModel, w: float, n: int) -> ValveSummary | Floated:
    """:func:`fast_valve_summary` of a rigid cam contact and a rigid train: the lash closes as a plastic impact that
    lifts the valve with the cam, which then moves with it (x_v = g - lash) to its seating, the train's and the
    cam's forces algebraic in the angle; each rebound off the seat flies on the valve spring alone (the train open,
    the cam's lift at the valve below the lash on its closing ramp): the same linear system as a compliant train's
    flight off it. The diffrax model's events and tolerances: the lash closes GAP_EPS past the cam's reach, the
    valve seats GAP_EPS below its seat."""
    rev = _revolution(motion, vt, n)
    s1, s2, g, g1, ratio, ratio1, th0, h = rev.s1, rev.s2, rev.g, rev.g1, rev.ratio, rev.ratio1, rev.th0, rev.h
    nf, w2, deg, out_node = g.size - 1, w * w, rev.deg, rev.out_node
    lash, m_c, m_v, k, c, f0, tappet, tol = _constants(vt)
    f_cam_bare = m_c * s2 * w2 + tappet  # the cam's force with the train open

    def cam_at_valve(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # g (m) and g' (m/rad) at angles
        v = np.asarray(motion.host(theta))[:2] * M_PER_MM
        g_v, ratio_v, _ = vt.host_lever(v[0])
        return g_v, ratio_v * v[1]

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
    th_seat = rise(lambda t: -(cam_at_valve(t)[0] - lash + GAP_EPS), th0 + (q - 1) * h, th0 + q * h)
    step, tau = q - 1, th_seat - (th0 + (q - 1) * h)
    closing = float(cam_at_valve(np.array([th_seat]))[1][0])  # the valve's speed as it seats (m/rad, < 0)
    seating_velocity, seating_deg = abs(closing) * w, deg(step, tau)

    # the rebounds at seat_restitution x the landing speed, each a flight on the spring alone to the seat
    free = _on_spring(vt, w, nf, h)
    cam = hermite_taylor(g, g1, h)  # the cam's lift at the valve between the fine angles

    def apart(ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:  # > 0 while the train stays open (m)
        taus = np.broadcast_to(taus, (len(ys),))
        steps = np.broadcast_to(steps, (len(ys),))
        a0, a1, a2, a3 = cam[np.minimum(steps, nf - 1)].T
        at = np.where(taus > 0.0, a0 + a1 * taus + a2 * taus**2 / 2 + a3 * taus**3 / 6, g[steps])
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
    for _ in range(_MAX_REBOUNDS):
        v = -e_seat * speed
        if v <= floor:
            break
        y = np.array([0.0, v])
        along, steps, taus, end = stretch_to(free, step, tau, y, flight, fresh=True)
        if end is None or apart(end[2][None], end[0], end[1])[0] <= landing(end[2][None], end[0], end[1])[0]:
            raise Unsure("the valve in the air at the revolution's end, or meeting the train")
        apex = stretch_to(free, step, tau, y, rising, fresh=True)[3]
        bounce = max(bounce, float(apex[2][0]) if apex is not None else 0.0, float(np.max(along[:, 0])))
        lift_here, gap_here = _flight_reach(rev, lash, along, steps, taus)
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
    return _summary(w, event, (bounce, flight_lift, gap), max_lift)
