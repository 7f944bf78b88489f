"""The valvetrain fast path's shared parts (:mod:`._valvefast` solves the trains with them): what it answers
(:class:`ValveSummary`, :class:`Floated`), one revolution of the cam's lift on the fine grid and through the rocker
(:class:`Revolution`), the valvetrain's numbers, and the valve's linear systems in the state's :class:`Layout`: the
valve alone, or with the spring's surge chain (``[spring] model = "surge"``: its inner lumps, each between its
neighbours, the head fixed), on its train, on its spring alone, or seated (the chain ringing on a held valve)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..._core.units import M_PER_MM, TWO_PI
from ..motion import Motion
from ..valvetrain import ValvetrainModel
from ._cubic import hermite_at, hermite_taylor
from ._valvelinear import ORDER, Linear
from ._valvetrain import start_angle

REFINE = 2  # fine steps per output angle (0.05 deg): the cubic hold's error is of order h^4
MAX_REBOUNDS = 200
MAX_SWITCHES = 16  # the train taking hold and letting go in one rebound: beyond, a chatter for the diffrax model


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
    # the least force over the event that would hold the follower on the cam (N, at most 0) where the valve floated:
    # the float search's force (:attr:`~camdyn.model.dynamics.ValvetrainResponse.float_force`)
    hold_force: float = math.nan


@dataclass(frozen=True)
class Floated:
    """The exact solution's cam-contact force falls below zero before anything else opens: the valve floats.
    ``least_force``: the least force (N, negative) the cam would have to pull with to hold the follower through the
    event, the contact held: the float search's force past the float speed, continuous with the least force below
    it (:func:`~camdyn.model.dynamics.float_speed` refines its zero by interpolation)."""

    least_force: float


_fine_cache: dict[int, tuple[Motion, int, np.ndarray]] = {}


def _fine(motion: Motion, n: int) -> np.ndarray:
    """s, s', s'' (m, m/rad, m/rad^2) on ``n * REFINE`` equal steps of one revolution, and s'' as the step ending
    at each angle sees it (where it jumps there, at a segment's end; else s''): the motion evaluated once per motion
    and grid (a speed search asks the same motion many times)."""
    hit = _fine_cache.get(id(motion))
    if hit is not None and hit[0] is motion and hit[1] == n:
        return hit[2]
    theta = np.arange(n * REFINE) * (TWO_PI / (n * REFINE))
    vals = np.asarray(motion.host(theta))[:3] * M_PER_MM
    # an angle on a break is its next segment's: the limit from below, 1e-7 of a step before it, where it differs by
    # more than the jerk moves it there (a smooth s'' moves 1e-7 x h x s''', far below 1e-6 of its largest)
    before = np.asarray(motion.host(theta - 1e-7 * (theta[1] - theta[0])))[2] * M_PER_MM
    jumps = np.abs(before - vals[2]) > 1e-6 * float(np.max(np.abs(vals[2])))
    vals = np.concatenate([vals, np.where(jumps, before, vals[2])[None]])
    if len(_fine_cache) > 16:
        _fine_cache.clear()
    _fine_cache[id(motion)] = (motion, n, vals)
    return vals


class Revolution(NamedTuple):
    """One revolution on the fine grid (``h`` rad a step) from the diffrax model's start angle ``th0`` (rad), one
    angle past its end: the cam's lift s, s', s'' (m, m/rad, m/rad^2) and its lift at the valve through the rocker
    g, g', g'' with the ratio r and r' = dr/dx_c at the cam's lift (known functions of the angle: on the fast path
    the follower moves with the cam), and the cubic Hermites of g and of s on each fine step (Taylor coefficients)."""

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
    cam: np.ndarray
    lift: np.ndarray
    s2_before: np.ndarray  # s'' and g'' as the step ending at each fine angle sees them (they jump at a segment's end)
    g2_before: np.ndarray

    def at_valve(self, steps: np.ndarray, taus: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The cam's lift at the valve g (m) and its slope g' (m/rad) ``taus`` rad into fine ``steps`` (arrays of one
        shape): sampled on the fine angles, on each step's cubic Hermite between them (where a guard is cut)."""
        return hermite_at(self.cam, self.g, self.g1, steps, taus)

    def at_cam(self, steps: np.ndarray, taus: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The cam's own lift s (m) and slope s' (m/rad) ``taus`` rad into fine ``steps``, as :meth:`at_valve`
        (where a flying follower's landing is cut)."""
        return hermite_at(self.lift, self.s, self.s1, steps, taus)

    @property
    def out_node(self) -> np.ndarray:
        """Whether each fine angle is one of the output grid's."""
        return (np.arange(self.s.size) % REFINE) == 0

    def deg(self, step: int, tau: float) -> float:
        """The cam angle (deg, in [0, 360)) ``tau`` rad into fine step ``step``."""
        return math.degrees(self.th0 + step * self.h + tau) % 360.0


def revolution(motion: Motion, vt: ValvetrainModel, n: int) -> Revolution:
    """The :class:`Revolution` of ``motion`` through ``vt``'s lever on ``n * REFINE`` fine steps."""
    s_all, s1_all, s2_all, s2_before_all = _fine(motion, n)
    nf = s_all.size
    h = TWO_PI / nf
    i0 = start_angle(s_all[::REFINE] / M_PER_MM) * REFINE  # the diffrax model's revolution, from here
    order = (i0 + np.arange(nf + 1)) % nf
    s, s1, s2, s2_before = s_all[order], s1_all[order], s2_all[order], s2_before_all[order]
    g, ratio, ratio1 = vt.host_lever(s)
    ratio, ratio1 = np.broadcast_to(ratio, s.shape), np.broadcast_to(ratio1, s.shape)
    g1 = ratio * s1
    g2 = ratio1 * s1**2 + ratio * s2
    g2_before = ratio1 * s1**2 + ratio * s2_before
    cam, lift = hermite_taylor(g, g1, h), hermite_taylor(s, s1, h)
    return Revolution(s, s1, s2, g, g1, g2, ratio, ratio1, i0 * h, h, cam, lift, s2_before, g2_before)


def exact_at_valve(motion: Motion, vt: ValvetrainModel, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cam's lift at the valve g (m) and its slope g' (m/rad) at angles ``theta`` (rad), from the motion itself
    (where an event is pinned between fine angles: the valve's lift, its seating on a rigid train)."""
    v = np.asarray(motion.host(theta))[:2] * M_PER_MM
    g, ratio, _ = vt.host_lever(v[0])
    return g, ratio * v[1]


def constants(vt: ValvetrainModel) -> tuple[float, ...]:
    """The valvetrain's numbers the fast path reads (SI): the lash, the cam side's and the valve's masses, the valve
    spring's rate, damping and preload, the tappet force and the diffrax model's force tolerance on its events."""
    f0 = float(vt.preload)
    tol = 1e-6 * max(1.0, float(vt.ratio) * f0)
    masses = float(vt.cam_side_mass), float(vt.valve_mass)
    return float(vt.lash), *masses, float(vt.spring_rate), float(vt.spring_damping), f0, float(vt.tappet_force), tol


def flight_reach(
    rev: Revolution, lash: float, lift: np.ndarray, steps: np.ndarray, taus: np.ndarray
) -> tuple[float, float]:
    """A rebound's highest lift on the output grid and its largest gap at the valve above where the cam would hold
    it (m), from the valve's lifts ``lift`` (m) at fine ``steps`` and ``taus`` (rad) into them."""
    grid = (taus == 0.0) & rev.out_node[np.minimum(steps, rev.g.size - 1)]  # the output grid's angles in the flight
    held = np.maximum(rev.g[steps[grid]] - lash, 0.0)
    return float(np.max(lift[grid], initial=0.0)), float(np.max(lift[grid] - held, initial=0.0))


class Layout(NamedTuple):
    """The fast path's state: the spring's inner lumps' lifts and the valve's, then their speeds (m, m/rad): the
    valve's speed last, where a :class:`~._valvelinear.Linear` system's input drives it. Without the surge chain
    (``lumps`` 0) the state is the valve's (x, x')."""

    lumps: int

    @property
    def x(self) -> int:
        """The valve's lift's index."""
        return self.lumps

    @property
    def v(self) -> int:
        """The valve's speed's index."""
        return 2 * self.lumps + 1

    def chain(self, y: np.ndarray) -> np.ndarray:
        """The inner lumps' part of state ``y`` (lifts, then speeds): the seated system's state."""
        return np.concatenate([y[: self.x], y[self.x + 1 : self.v]])

    def lifted(self, chain: np.ndarray, x: float = 0.0, v: float = 0.0) -> np.ndarray:
        """The whole state from the lumps' part ``chain`` and the valve's lift ``x`` and speed ``v``."""
        m = self.lumps
        return np.concatenate([chain[:m], [x], chain[m:], [v]])


def layout(vt: ValvetrainModel) -> Layout:
    """The state's :class:`Layout` for ``vt``: the surge chain's inner lumps, if it has one."""
    return Layout(0 if vt.coils is None else vt.coils.count - 1)


def valve_matrix(vt: ValvetrainModel, w: float, kt: float = 0.0, ct: float = 0.0) -> np.ndarray:
    """The valve's (and the surge chain's) linear system off its seat at cam speed ``w`` (rad/s), in the cam angle:
    on its spring and a train of stiffness ``kt`` and damping ``ct`` (0: off the train), the train's input and the
    preload left out (:class:`Layout`'s order). The spring's force on the valve is ``k x + F0 + c x'``, or with the
    chain its last segment's ``k_s (x - u_m) + c_s w (x' - u_m')`` with the preload and the valve's damper."""
    m, m_v, c = layout(vt).lumps, float(vt.valve_mass), float(vt.spring_damping)
    w2, n = w * w, 2 * (m + 1)
    a = np.zeros((n, n))
    a[: m + 1, m + 1 :] = np.eye(m + 1)
    if vt.coils is None:
        k_end, c_end = float(vt.spring_rate), 0.0
    else:
        k_end, c_end = float(vt.coils.segment_rate), float(vt.coils.segment_damping)
        lump = float(vt.coils.lump_mass)
        # each inner lump between its neighbours: the head (0) and, after the last, the valve
        lap = np.zeros((m, m + 1))
        i = np.arange(m)
        lap[i, i] = -2.0
        lap[i[1:], i[:-1]] = 1.0
        lap[i, i + 1] = 1.0
        a[m + 1 : 2 * m + 1, : m + 1] = k_end / (lump * w2) * lap
        a[m + 1 : 2 * m + 1, m + 1 :] = c_end / (lump * w) * lap
        a[2 * m + 1, m - 1] = k_end / (m_v * w2)
        a[2 * m + 1, 2 * m] = c_end / (m_v * w)
    a[2 * m + 1, m] = -(kt + k_end) / (m_v * w2)
    a[2 * m + 1, 2 * m + 1] = -(ct + c_end + c) / (m_v * w)
    return a


def on_spring(vt: ValvetrainModel, w: float, steps: int, h: float) -> Linear:
    """The valve off the train and off its seat at cam speed ``w`` (rad/s): on its spring alone, no input, over
    ``steps`` fine steps of ``h`` rad (a rebound's flight)."""
    b = -float(vt.preload) / (float(vt.valve_mass) * w * w)
    return Linear(valve_matrix(vt, w), b, np.zeros((steps, ORDER)), h)


def seated(vt: ValvetrainModel, w: float, steps: int, h: float) -> Linear:
    """The surge chain ringing on the seated valve (held at 0) at cam speed ``w`` (rad/s), over ``steps`` fine steps
    of ``h`` rad: :meth:`Layout.chain`'s state."""
    m = layout(vt).lumps
    keep = np.r_[0:m, m + 1 : 2 * m + 1]
    return Linear(valve_matrix(vt, w)[np.ix_(keep, keep)], 0.0, np.zeros((steps, ORDER)), h)


def summary(
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
