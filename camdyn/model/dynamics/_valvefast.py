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
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..._core.units import M_PER_MM, THETA_GRID, TWO_PI
from ..motion import Motion
from ..valvetrain import ValvetrainModel, static_valve_lift
from ._cubic import hermite_taylor
from ._valvefield import GAP_EPS
from ._valvetrain import landing_floor, start_angle

REFINE = 2  # fine steps per output angle (0.05 deg): the cubic hold's error is of order h^4
_SPLIT = 64  # a contact change inside a step: the step cut in 64, twice over
_MAX_REBOUNDS = 200
_MARCH = 64  # a stretch's first chunk of fine steps (then four times what it has, to the revolution's end)
_ORDER = 4  # the input's Taylor chain: value, slope, curvature, third derivative (a cubic)


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


Index = int | float | np.ndarray  # fine steps, or angles into them (rad): one, or one per state
Guard = Callable[[np.ndarray, Index, Index], np.ndarray]  # states, their steps and angles -> > 0 while a mode holds

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


def _expm(z: np.ndarray) -> np.ndarray:
    """``exp`` of a stack of small matrices (..., m, m), batched: scaled to a norm below 1/4, a Taylor series to
    the 12th power (a remainder below 3e-18), squared back. scipy's ``expm`` goes matrix by matrix (its Pade
    step costs milliseconds for each of the thousands a speed asks for)."""
    norm = np.max(np.sum(np.abs(z), axis=-1), axis=-1)
    squarings = np.maximum(0, np.ceil(np.log2(np.maximum(norm, 1e-300)) + 2)).astype(int)
    top = int(squarings.max()) if squarings.size else 0
    a = z / (2.0**squarings)[..., None, None]
    # the series to a^12 by Paterson-Stockmeyer: a^2, a^3, a^4, then Horner in a^4 over blocks of four terms
    # (5 products, not 12: each is a numpy call on a stack of small matrices)
    eye = np.broadcast_to(np.eye(z.shape[-1]), z.shape)
    a2 = a @ a
    a3 = a2 @ a
    a4 = a3 @ a
    c = [1.0 / math.factorial(k) for k in range(13)]
    out = c[12] * a4 + (c[8] * eye + c[9] * a + c[10] * a2 + c[11] * a3)
    for k in (4, 0):
        out = out @ a4 + (c[k] * eye + c[k + 1] * a + c[k + 2] * a2 + c[k + 3] * a3)
    for i in range(top):
        more = squarings > i
        if more.all():
            out = out @ out
        else:
            out[more] = out[more] @ out[more]
    return out


def _shift(taylor: np.ndarray, tau: float) -> np.ndarray:
    """A cubic's Taylor coefficients moved ``tau`` along its step."""
    a0, a1, a2, a3 = taylor
    return np.array(
        [a0 + a1 * tau + a2 * tau**2 / 2 + a3 * tau**3 / 6, a1 + a2 * tau + a3 * tau**2 / 2, a2 + a3 * tau, a3]
    )


def _recur(lam: complex, g: np.ndarray, z0: complex) -> np.ndarray:
    """``z[k + 1] = lam z[k] + g[k]`` from ``z[0] = z0``: (len(g) + 1,). In blocks short enough that ``lam``'s powers
    within one stay within 1e3 of each other (a decaying mode), each block a cumulative sum:
    ``z[k + i] = lam^i (z[k] + sum_{j < i} g[k + j] lam^-(j + 1))``."""
    count = len(g)
    out = np.empty(count + 1, complex)
    out[0] = z0
    size = abs(lam)
    if size < 1e-12:  # a mode gone within a step
        out[1:] = g
        return out
    block = count if size >= 1.0 else max(1, min(count, int(math.log(1e3) / -math.log(size))))
    k = 0
    while k < count:
        m = min(block, count - k)
        powers = np.exp(np.arange(1, m + 1) * np.log(lam))  # lam ** k: numpy's complex ** is 7x slower, no closer
        out[k + 1 : k + m + 1] = powers * (out[k] + np.cumsum(g[k : k + m] / powers))
        k += m
    return out


class _Linear:
    """The valve's linear system ``y' = A y + e (w0 + b)`` (y = (x, x'), w0 the cubic input) and its exact
    propagators: ``expm`` of the system augmented with the input's Taylor chain and the constant."""

    def __init__(self, a: np.ndarray, b: float, taylor: np.ndarray, h: float) -> None:
        n = a.shape[0]
        z = np.zeros((n + _ORDER + 1, n + _ORDER + 1))
        z[:n, :n] = a
        z[n - 1, n] = 1.0  # the input drives the last state's derivative
        z[n - 1, n + _ORDER] = b
        for i in range(_ORDER - 1):
            z[n + i, n + i + 1] = 1.0
        self.z, self.n, self.taylor, self.h = z, n, taylor, h
        self._step: tuple | None = None  # the full step's propagator and its modes, once
        self._steps: dict[bytes, np.ndarray] = {}  # propagators by their angles

    def steps(self, deltas: np.ndarray) -> np.ndarray:
        """The augmented propagators over angles ``deltas`` (rad): (len, n, n + 5)."""
        deltas = np.asarray(deltas, dtype=float)
        key = deltas.tobytes()
        if key not in self._steps:  # a step's cuts from its start recur: kept
            if len(self._steps) > 64:
                self._steps.clear()
            self._steps[key] = _expm(self.z[None] * deltas[:, None, None])[:, : self.n, :]
        return self._steps[key]

    def advance(self, step: int, tau: float, y: np.ndarray, deltas: np.ndarray) -> np.ndarray:
        """The states at ``deltas`` past angle ``tau`` into fine step ``step`` from ``y`` there: (len, n)."""
        e = self.steps(deltas)
        src = np.concatenate([y, _shift(self.taylor[step], tau), [1.0]])
        return e @ src

    def march(self, step: int, y: np.ndarray, count: int | None = None) -> np.ndarray:
        """The states at the nodes from ``step`` (where the state is ``y``) to the last, or the next ``count`` steps
        of them: (steps + 1, n)."""
        if self._step is None:
            e = self.steps(np.array([self.h]))[0]
            phi = e[:, : self.n]
            lam, vec = np.linalg.eig(phi)
            self._step = (phi, e[:, self.n :], lam, vec, np.linalg.cond(vec) > 1e8)
        phi, gam, lam, vec, repeated = self._step
        taylor = self.taylor[step:] if count is None else self.taylor[step : step + count]
        if not taylor.shape[0]:
            return y[None]
        forcing = np.concatenate([taylor, np.ones((taylor.shape[0], 1))], axis=1) @ gam.T  # (steps, n)
        if repeated:  # (nearly) repeated modes: step by step
            out = [y]
            for g in forcing:
                out.append(phi @ out[-1] + g)
            return np.array(out)
        modal = np.linalg.solve(vec, forcing.T.astype(complex))  # (n, steps)
        z0 = np.linalg.solve(vec, y.astype(complex))
        z = np.empty((self.n, taylor.shape[0] + 1), complex)
        z[:, 0] = z0
        for i in range(self.n):
            z[i] = _recur(lam[i], modal[i], z0[i])
        return np.real(vec @ z).T


class _Unsure(Exception):
    """The fast path cannot say: the caller runs the diffrax model."""


def _cross(
    lin: _Linear, step: int, tau: float, y: np.ndarray, span: float, guard: Guard, fresh: bool
) -> tuple[float, np.ndarray] | None:
    """The first angle past ``tau`` in fine step ``step`` (from state ``y``), within ``span`` (rad), where
    ``guard(states, steps, taus)`` falls below zero: (delta, state) or None. The span cut in :data:`_SPLIT` finds
    the first sign change (``fresh``: the guard starts at zero, a rebound off the seat: the cuts spaced
    geometrically), that cut in :data:`_SPLIT` again, the guard interpolated linearly across the last (a width of
    1/4096 of a fine step: an error of its square), and the state there from the exact propagator."""
    lo, width, g_lo, g_hi = 0.0, span, 0.0, 0.0
    for r in range(2):
        if r == 0 and fresh:
            ds = span * np.geomspace(1e-7, 1.0, _SPLIT)
        else:
            ds = lo + np.linspace(0.0, width, _SPLIT + 1)
        ys = lin.advance(step, tau, y, ds)
        g = guard(ys, step, tau + ds)
        below = np.nonzero(g < 0.0)[0]
        if r == 0 and not fresh:
            below = below[below > 0]
        if not below.size:
            return None
        j = int(below[0])
        if j == 0:  # fresh: below at the first cut already
            lo, g_lo, width = 0.0, 0.0, ds[0]
        else:
            lo, g_lo, width = ds[j - 1], float(g[j - 1]), ds[j] - ds[j - 1]
        g_hi = float(g[j])
    f = min(max(g_lo / (g_lo - g_hi), 0.0), 1.0) if g_lo != g_hi else 1.0
    root = lo + f * width
    return root, lin.advance(step, tau, y, np.array([root]))[0]


def _stretch(
    lin: _Linear, step: int, tau: float, y: np.ndarray, guard: Guard, fresh: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple | None]:
    """From angle ``tau`` into fine step ``step`` with state ``y`` on ``lin`` to where ``guard`` first falls below
    zero: the states passed (at their fine steps and angles into them) and the event (step, tau, state), None where
    the revolution ends first."""
    h = lin.h
    got = _cross(lin, step, tau, y, h - tau, guard, fresh)
    if got is not None:
        ds = np.linspace(0.0, got[0], 9)[1:]
        return lin.advance(step, tau, y, ds), np.full(ds.size, step), tau + ds, (step, tau + got[0], got[1])
    nodes = lin.march(step + 1, lin.advance(step, tau, y, np.array([h - tau]))[0], _MARCH)
    last = len(lin.taylor)  # the last node: the revolution's end
    while True:  # a chunk at a time: most stretches end within a few steps
        idx = step + 1 + np.arange(len(nodes))
        below = np.nonzero(guard(nodes, idx, np.zeros(len(nodes))) < 0.0)[0]
        if below.size or idx[-1] >= last:
            break
        nodes = np.concatenate([nodes, lin.march(int(idx[-1]), nodes[-1], 4 * len(nodes))[1:]])
    if not below.size:
        return nodes, idx, np.zeros(len(nodes)), None
    q = int(below[0])
    got = _cross(lin, step + q, 0.0, nodes[q - 1], h, guard, False) if q > 0 else None
    if got is None:
        raise _Unsure("a contact change the bracketing lost")
    return nodes[:q], idx[:q], np.zeros(q), (step + q, got[0], got[1])


def _rise(fn: Callable[[np.ndarray], np.ndarray], lo: float, hi: float) -> float:
    """The angle (rad) in [lo, hi] where ``fn`` (of angles, on the host), below zero at ``lo``, first rises above
    it: as :func:`_cross`, the span cut in 64 twice over, the root interpolated across the last cut."""
    for _ in range(2):
        ts = np.linspace(lo, hi, _SPLIT + 1)
        vals = fn(ts)
        i = int(np.argmax(vals > 0.0))
        lo, hi = ts[i - 1], ts[i]
    f = min(max(vals[i - 1] / (vals[i - 1] - vals[i]), 0.0), 1.0)
    return lo + f * (hi - lo)


def _lower_bound(f: np.ndarray) -> float:
    """A bound below a force sampled on the fine nodes, between them too: each step's lower end less twice the
    reach of its convexity (a second difference over 8), the least of the four second differences about the step
    (a jump at a segment's boundary is not a curvature)."""
    if f.size < 4:
        return float(np.min(f)) if f.size else math.inf
    d2 = np.diff(f, 2)
    curv = np.concatenate([d2[:1], d2, d2[-1:]])  # per node
    pad = np.concatenate([curv[:1], curv, curv[-1:]])  # per node, one more each side
    convex = np.maximum(0.0, np.min(np.stack([pad[:-3], pad[1:-2], pad[2:-1], pad[3:]]), axis=0))  # per step
    return float(np.min(np.minimum(f[:-1], f[1:]) - 0.25 * convex))


def fast_valve_summary(
    motion: Motion, vt: ValvetrainModel, omega: float, n: int = THETA_GRID
) -> ValveSummary | Floated | None:
    """The :class:`ValveSummary` at cam speed ``omega`` (rad/s) on the fast path, :class:`Floated` where the valve
    surely floats, or None where the fast path cannot say (the caller runs the diffrax model)."""
    if not vt.rigid_cam or vt.coils is not None:
        return None
    try:
        return (_rigid_train if vt.rigid_train else _rigid_cam)(motion, vt, float(omega), n)
    except _Unsure:
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
        if _lower_bound(f_cam_bare + ratio * f_seated) < -tol:
            raise _Unsure("the follower leaves the cam")
        nan = math.nan
        return ValveSummary(w, nan, nan, nan, nan, nan, 0.0, 0.0)
    j = int(lifts[0])
    if j == 0 or _lower_bound((f_cam_bare + ratio * f_seated)[: j + 1]) < -tol:
        raise _Unsure("the follower leaves the cam before the valve lifts")

    def seated_force(theta: np.ndarray) -> np.ndarray:  # the train's on the seated valve, less F0 + tol
        v = np.asarray(motion.host(theta))[:2] * M_PER_MM
        g_v, ratio_v, _ = vt.host_lever(v[0])
        d = g_v - lash
        return np.where(d > 0.0, np.maximum(0.0, kt * d + ct * w * ratio_v * v[1]), 0.0) - f0 - tol

    lift_step = j - 1
    tau_lift = _rise(seated_force, th0 + lift_step * h, th0 + j * h) - (th0 + lift_step * h)

    # the valve off its seat, on the train (loaded) or off it (free, on its spring alone): two linear systems
    loaded = _Linear(
        np.array([[0.0, 1.0], [-(kt + k) / (m_v * w2), -(ct + c) / (m_v * w)]]),
        (-kt * lash - f0) / (m_v * w2),
        hermite_taylor((kt * g + ct * w * g1) / (m_v * w2), (kt * g1 + ct * w * g2) / (m_v * w2), h),
        h,
    )
    free = _Linear(
        np.array([[0.0, 1.0], [-k / (m_v * w2), -c / (m_v * w)]]), -f0 / (m_v * w2), np.zeros((nf, _ORDER)), h
    )
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
        raise _Unsure("no seating after the valve's rise")
    q = int(risen[0] + down[0])  # the first fine angle below the seat, counted from lift_step + 1
    train_open = np.nonzero((d[:q] <= 0.0) | (f_t[:q] < 0.0))[0]
    cam_open = np.nonzero(f_cam[:q] < -tol)[0]
    if cam_open.size and (not train_open.size or cam_open[0] < train_open[0]):
        # the exact solution's cam force crosses the diffrax model's threshold first: float
        return Floated(float(np.min(f_cam[:q])))
    if train_open.size or _lower_bound(f_cam[:q]) <= tol or _lower_bound(f_t[:q]) <= 0.0:
        raise _Unsure("the cam contact near opening, or the valve off the train, within the event")
    got = _cross(loaded, lift_step + q, 0.0, ys[q - 1], h, landing, False)
    if got is None:
        raise _Unsure("the seating lost")
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
            along, steps, taus, end = _stretch(lin, step, tau, y, guard, fresh=first)
            if end is None:
                raise _Unsure("the valve in the air at the revolution's end")
            if y[1] > 0.0 and end[2][1] <= 0.0:  # the apex in this stretch
                apex = _stretch(lin, step, tau, y, rising, fresh=first)[3]
                bounce = max(bounce, float(apex[2][0]) if apex is not None else float(np.max(along[:, 0])))
            bounce = max(bounce, float(np.max(along[:, 0])))
            lift_here, gap_here = _flight_reach(rev, lash, along, steps, taus)
            flight_lift, gap = max(flight_lift, lift_here), max(gap, gap_here)
            if np.min(f_cam_bare[np.minimum(steps, nf)]) < -tol:
                raise _Unsure("the follower leaves the cam while the valve rebounds")
            step, tau, y = end
            first = False
            if landing(y[None], step, tau)[0] <= kt * GAP_EPS * 1e-3:  # on the seat (not a change of system)
                break
    else:
        raise _Unsure("the valve rattles on its seat beyond the rebounds followed")
    # the valve held on its seat to the revolution's end: no re-lift, the follower on the cam
    rest = slice(step + 1, nf + 1)
    if np.any(f_seated[rest] > f0) or _lower_bound((f_cam_bare + ratio * f_seated)[rest]) < -tol:
        raise _Unsure("the valve re-lifted or the follower off the cam after the seating")
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
        if _lower_bound(f_cam_bare) < -tol:
            raise _Unsure("the follower leaves the cam")
        nan = math.nan
        return ValveSummary(w, nan, nan, nan, nan, nan, 0.0, 0.0)
    j = int(closed[0])
    if j == 0 or _lower_bound(f_cam_bare[: j + 1]) < -tol:
        raise _Unsure("the follower leaves the cam before the lash closes")

    # the valve on the train, moving with the cam: its lift, the train's force and the cam's, to the seating after
    # rising past half its lift (the diffrax model's rule)
    x_v = g - lash
    f_t = m_v * (ratio * s2 + ratio1 * s1**2) * w2 + k * x_v + f0 + c * w * ratio * s1
    f_cam = f_cam_bare + ratio * f_t
    half_lift = 0.5 * (float(g.max()) - float(g.min()) - lash)
    risen = j + np.nonzero(x_v[j:] > half_lift)[0]
    down = risen[0] + np.nonzero(x_v[risen[0] :] + GAP_EPS < 0.0)[0] if risen.size else risen
    if not down.size:
        raise _Unsure("no seating after the valve's rise")
    q = int(down[0])  # the first fine angle below the seat
    event = slice(j, q)
    train_open = np.nonzero(f_t[event] < -tol)[0]
    cam_open = np.nonzero(f_cam[event] < -tol)[0]
    if cam_open.size and (not train_open.size or cam_open[0] < train_open[0]):
        return Floated(float(np.min(f_cam[event])))
    if train_open.size or _lower_bound(f_cam[event]) <= tol or _lower_bound(f_t[event]) <= tol:
        raise _Unsure("the cam contact or the train near opening within the event")
    grid = np.flatnonzero(out_node[event]) + j
    least = int(grid[np.argmin(f_cam[grid])])
    least_force, least_deg = float(f_cam[least]), deg(least, 0.0)
    least_train = float(np.min(f_t[grid]))
    max_lift = float(np.max(x_v[grid]))
    th_seat = _rise(lambda t: -(cam_at_valve(t)[0] - lash + GAP_EPS), th0 + (q - 1) * h, th0 + q * h)
    step, tau = q - 1, th_seat - (th0 + (q - 1) * h)
    closing = float(cam_at_valve(np.array([th_seat]))[1][0])  # the valve's speed as it seats (m/rad, < 0)
    seating_velocity, seating_deg = abs(closing) * w, deg(step, tau)

    # the rebounds at seat_restitution x the landing speed, each a flight on the spring alone to the seat
    free = _Linear(
        np.array([[0.0, 1.0], [-k / (m_v * w2), -c / (m_v * w)]]), -f0 / (m_v * w2), np.zeros((nf, _ORDER)), h
    )
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
        along, steps, taus, end = _stretch(free, step, tau, y, flight, fresh=True)
        if end is None or apart(end[2][None], end[0], end[1])[0] <= landing(end[2][None], end[0], end[1])[0]:
            raise _Unsure("the valve in the air at the revolution's end, or meeting the train")
        apex = _stretch(free, step, tau, y, rising, fresh=True)[3]
        bounce = max(bounce, float(apex[2][0]) if apex is not None else 0.0, float(np.max(along[:, 0])))
        lift_here, gap_here = _flight_reach(rev, lash, along, steps, taus)
        flight_lift, gap = max(flight_lift, lift_here), max(gap, gap_here)
        if np.min(f_cam_bare[np.minimum(steps, nf)]) < -tol:
            raise _Unsure("the follower leaves the cam while the valve rebounds")
        step, tau, y = end
        speed = float(y[1])
    else:
        raise _Unsure("the valve rattles on its seat beyond the rebounds followed")
    # the valve held on its seat to the revolution's end: the lash open, the follower on the cam
    rest = slice(step + 1, nf + 1)
    if np.any(g[rest] - lash - GAP_EPS > 0.0) or _lower_bound(f_cam_bare[rest]) < -tol:
        raise _Unsure("the lash closed again or the follower off the cam after the seating")
    event = (least_force, least_deg, least_train, seating_velocity, seating_deg)
    return _summary(w, event, (bounce, flight_lift, gap), max_lift)
