"""The valvetrain fast path's follower off the cam while the valve sits on its seat: where the cam decelerates faster
than the tappet force (and the train, once the lash has closed) can pull the follower after it, on a ramp whose
velocity is not constant, the follower flies and lands again before the valve lifts, or after it has seated.

With the valve seated the follower's flight is linear (SI, the cam angle, ' = d/dtheta): on the tappet force alone
while the lash is open, pressed back by the train too once it closes under a constant rocker ratio r::

    m_c w^2 x_c'' = -F_tappet - r F_t,   F_t = k_t (r x_c - lash) + c_t w r x_c'   (0 while the lash is open)

(a rocker's ratio moves with the follower's lift: its train's push on a flying follower is not linear and runs by
Runge-Kutta, :meth:`FollowerFlights._pushed`). So a flight runs on the fast path's exact propagators, each stretch
to the first of its guards (the landing on the cam, the train taking hold or letting go, the seat letting the valve
go). A landing follows the diffrax model's rule: the follower rebounds at the cam's restitution, or stays where that
rebound is below the seat's landing floor. The valve's event is not touched, so the fast path's summary holds as
long as every flight lands before the valve lifts (one over the revolution's end carried into its start) and the
train never lifts the valve in one; anything else is :class:`~._valvelinear.Unsure`."""

from __future__ import annotations

import functools
import math

import numpy as np

from ..._core.units import M_PER_MM
from ..motion import Motion
from ..valvetrain import ValvetrainModel
from ._valvefield import GAP_EPS
from ._valvelinear import ORDER, Index, Linear, Unsure, rise, step_bounds, stretch_to
from ._valvetrain import landing_floor

_RK_PHASE = 0.01  # rad of the train's vibration per Runge-Kutta substep (a rocker's push on a flying follower)
_CHUNK = 16  # fine steps a Runge-Kutta stretch takes before reading its guard
_BISECT = 40  # halvings of a substep locating a guard's zero (to 1e-12 of it)
_MAX_FLIGHTS = 64  # flights (and rebounds off the cam) in one stretch on the cam: beyond, a chatter for diffrax
_MIN_TRAIN, _OFF_CAM, _SEAT = 0, 1, 2  # the guards, in :meth:`FollowerFlights._guards`' order


class FollowerFlights:
    """The follower of a rigid cam contact and a compliant train at cam speed ``w`` (rad/s), the valve seated: its
    flights off the cam followed to their landings (:meth:`hold`). ``rev``: the fast path's revolution
    (:class:`~._valveevent.Revolution`); ``on_cam``: the cam's force on the follower at its fine angles with the valve
    seated and the follower on the cam (N); ``numbers``: the valvetrain's (:func:`~._valveevent.constants`)."""

    def __init__(self, motion: Motion, vt: ValvetrainModel, w: float, rev, on_cam: np.ndarray, numbers) -> None:
        self.motion, self.vt, self.w, self.rev, self.on_cam = motion, vt, w, rev, on_cam
        self.lash, self.m_c, _, _, _, self.f0, self.tappet, self.tol = numbers
        self.kt, self.ct = float(vt.train.train_stiffness), float(vt.train.train_damping)
        self.e_cam, self.floor = float(vt.cam_restitution), landing_floor(vt, w)
        # a rocker's ratio varies with the follower's lift, which off the cam is no longer the cam's: the train's
        # push on a flying follower is not linear there (:meth:`_pushed`)
        self.r = None if vt.rocker is not None else float(vt.ratio)
        ratio = float(vt.ratio)
        self.lever = vt.rocker.bound_lever() if vt.rocker is not None else (lambda x: (ratio * x, ratio, 0.0))

    @functools.cached_property
    def _systems(self) -> tuple[Linear, Linear]:
        """The follower's (x_c, x_c') off the cam: on the tappet force alone, and pressed back by the train too."""
        r, kt, ct, w, h = float(self.r or 0.0), self.kt, self.ct, self.w, self.rev.h
        mw2, still = self.m_c * w * w, np.zeros((self.rev.g.size - 1, ORDER))
        alone = Linear(np.array([[0.0, 1.0], [0.0, 0.0]]), -self.tappet / mw2, still, h)
        train = np.array([[0.0, 1.0], [-r * r * kt / mw2, -r * r * ct / (self.m_c * w)]])
        return alone, Linear(train, (r * kt * self.lash - self.tappet) / mw2, still, h)

    def _cam(self, steps: Index, taus: Index, size: int) -> tuple[np.ndarray, np.ndarray]:
        """The cam's lift s (m) and slope s' (m/rad) ``taus`` rad into fine ``steps``: on the fine angles, on each
        step's cubic Hermite between them."""
        steps, taus = np.broadcast_to(steps, (size,)), np.broadcast_to(taus, (size,))
        return self.rev.at_cam(steps, taus)

    def _guards(self, ys: np.ndarray, steps: Index, taus: Index) -> np.ndarray:
        """(3, len(ys)), each > 0 while its mode holds (N): the train's hold on the follower (its least of the
        spring's and the whole force, > 0 while it pushes), the follower above the cam, the seat holding the valve."""
        s, _ = self._cam(steps, taus, len(ys))
        g, ratio, _ = self.lever(ys[:, 0])
        d = g - self.lash
        f_t = self.kt * d + self.ct * self.w * ratio * ys[:, 1]
        pushed = np.where(d > 0.0, np.maximum(0.0, f_t), 0.0)
        return np.stack([np.minimum(self.kt * d, f_t), self.kt * (ys[:, 0] - s + GAP_EPS), self.f0 - pushed + self.tol])

    def _cam_force(self, theta: np.ndarray) -> np.ndarray:
        """The cam's force on the follower (N) at angles ``theta`` (rad), on the cam with the valve seated, from the
        motion itself (where a flight begins between the fine angles)."""
        s, s1, s2 = np.asarray(self.motion.host(theta))[:3] * M_PER_MM
        g, ratio, _ = self.lever(s)
        d = g - self.lash
        seated = np.where(d > 0.0, np.maximum(0.0, self.kt * d + self.ct * self.w * ratio * s1), 0.0)
        return self.m_c * s2 * self.w**2 + self.tappet + ratio * seated

    def hold(
        self, step: int, stop: int, *, tau: float = 0.0, flying: np.ndarray | None = None, carry: bool = False
    ) -> np.ndarray | None:
        """The follower from ``tau`` rad into fine ``step`` (on the cam, or in the air with the state ``flying``: m,
        m/rad) to fine angle ``stop``, the valve seated: each flight where the cam's force falls below the diffrax
        model's threshold followed to its landing. :class:`Unsure` where one has not landed a fine step before
        ``stop`` (the valve lifts in the step before it: a landing there could move the lift; with ``carry``, one in
        the air at the revolution's end gives its state there), the train lifts the valve in one, or they do not
        end."""
        tol, h, th0 = self.tol, self.rev.h, self.rev.th0
        land_by = stop - 1
        if flying is not None:
            got = self._fly(step, tau, land_by, flying, carry=False)
            assert not isinstance(got, np.ndarray)  # landed, or Unsure
            step, tau = got
        lo = th0 + step * h + tau
        for _ in range(_MAX_FLIGHTS):
            bounds = step_bounds(self.on_cam[step : stop + 1])
            below = np.nonzero(bounds < -tol)[0]
            if not below.size:
                return None
            i = step + int(below[0])
            start, end = max(lo, th0 + i * h), th0 + (i + 1) * h
            force = self._cam_force(np.linspace(start, end, 65))
            if np.all(force >= -tol):  # the bound's reach, not a crossing
                step, lo = i + 1, end
                if step >= stop:
                    return None
                continue
            # where it leaves: at once (a landing where the cam still pulls away), or where its force crosses
            theta = start if force[0] < -tol else rise(lambda t: -(self._cam_force(t) + tol), start, end)
            got = self._fly(i, theta - (th0 + i * h), land_by, None, carry)
            if isinstance(got, np.ndarray):
                return got
            step, tau = got
            lo = th0 + step * h + tau
        raise Unsure("the follower chatters on the cam")

    def _fly(
        self, step: int, tau: float, stop: int, flying: np.ndarray | None, carry: bool
    ) -> tuple[int, float] | np.ndarray:
        """A flight from ``tau`` rad into fine ``step`` with the state ``flying`` (None: leaving the cam, with its
        speed): where it stays on the cam again (fine step, rad into it), or with ``carry`` its state at the
        revolution's end where it is still in the air there."""
        fresh = flying is None
        (s,), (s1,) = self._cam(step, tau, 1)
        y = np.array([s, s1]) if flying is None else flying
        sign = 1.0 if self._guards(y[None], step, tau)[_MIN_TRAIN, 0] > 0.0 else -1.0  # the train's hold, or not
        for _ in range(_MAX_FLIGHTS):

            def guard(ys: np.ndarray, st: Index, ta: Index, sign: float = sign) -> np.ndarray:
                g = self._guards(ys, st, ta)
                return np.minimum(np.minimum(sign * g[_MIN_TRAIN], g[_OFF_CAM]), g[_SEAT])

            if sign > 0.0 and self.r is None:
                along, end = self._pushed(step, tau, y, guard)
            else:
                along, _, _, end = stretch_to(self._systems[1 if sign > 0.0 else 0], step, tau, y, guard, fresh=fresh)
            if end is None and carry:
                return along[-1]
            if end is None or end[0] >= stop:
                raise Unsure("the follower in the air where the valve lifts or the revolution ends")
            step, tau, y = end
            fresh = False
            at = self._guards(y[None], step, tau)[:, 0] * np.array([sign, 1.0, 1.0])
            which = int(np.argmin(at))
            if which == _SEAT:
                raise Unsure("the train lifts the valve while the follower flies")
            if which == _MIN_TRAIN:  # the train takes hold of the follower or lets it go
                sign = -sign
                continue
            (s,), (s1,) = self._cam(step, tau, 1)  # the landing
            rel = float(y[1]) - s1
            if not (self.e_cam > 0.0 and abs(rel) > self.floor):
                return step, tau
            y, fresh = np.array([s, s1 - self.e_cam * rel]), True
        raise Unsure("the follower rattles on the cam")

    def _pushed(self, step: int, tau: float, y: np.ndarray, guard) -> tuple[np.ndarray, tuple | None]:
        """A stretch of the follower pushed back by the train through a rocker, whose push is not linear in the
        follower's lift: classical Runge-Kutta on equal substeps of each fine step, each at most :data:`_RK_PHASE`
        rad of the train's vibration (a local error of order its fifth power), from ``tau`` rad into fine ``step``
        with the state ``y`` to where ``guard`` first falls below zero on them, located by bisection on a shortened
        last substep: (the state at the revolution's end, None) or (the state there, (step, tau, state))."""
        assert self.vt.rocker is not None  # a constant ratio's push is linear: :attr:`_systems`
        lever = self.vt.rocker.bound_lever(scalar=True)
        kt, ct, w, lash, tappet = self.kt, self.ct, self.w, self.lash, self.tappet
        mw2, h, nf = self.m_c * w * w, self.rev.h, len(self.rev.lift)

        def acc(x: float, p: float) -> float:
            g, r, _ = lever(x)
            return -(tappet + r * (kt * (g - lash) + ct * w * r * p)) / mw2

        def rk(x: float, p: float, d: float) -> tuple[float, float]:
            a1 = acc(x, p)
            p2 = p + 0.5 * d * a1
            a2 = acc(x + 0.5 * d * p, p2)
            p3 = p + 0.5 * d * a2
            a3 = acc(x + 0.5 * d * p2, p3)
            p4 = p + d * a3
            a4 = acc(x + d * p3, p4)
            return x + d * (p + 2.0 * p2 + 2.0 * p3 + p4) / 6.0, p + d * (a1 + 2.0 * a2 + 2.0 * a3 + a4) / 6.0

        vibration = math.sqrt(kt * float(np.max(self.rev.ratio)) ** 2 / self.m_c) / w  # rad per cam rad
        per_step = max(1, math.ceil(h * vibration / _RK_PHASE))
        x, p = float(y[0]), float(y[1])
        while step < nf:  # a chunk of fine steps at a time, the guard read once on all its substeps
            starts: list[tuple[float, float, int, float]] = []  # each substep's start: state, fine step, angle
            ends: list[tuple[float, float, int, float]] = []
            for st in range(step, min(step + _CHUNK, nf)):
                t0 = tau if st == step else 0.0
                cuts = np.linspace(t0, h, max(1, math.ceil(per_step * (h - t0) / h)) + 1)
                for a, b in zip(cuts[:-1], cuts[1:], strict=True):
                    starts.append((x, p, st, float(a)))
                    x, p = rk(x, p, float(b - a))
                    ends.append((x, p, st, float(b)))
            table = np.array(ends)
            below = np.nonzero(guard(table[:, :2], table[:, 2].astype(int), table[:, 3]) < 0.0)[0]
            if below.size:
                x0, p0, st, lo = starts[int(below[0])]
                t0, hi = lo, ends[int(below[0])][3]
                for _ in range(_BISECT):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if guard(np.array([rk(x0, p0, mid - t0)]), st, mid)[0] >= 0.0 else (lo, mid)
                end = np.array(rk(x0, p0, hi - t0))
                return end[None], ((st, hi, end) if hi < h else (st + 1, 0.0, end))
            step, tau = ends[-1][2] + 1, 0.0
        return np.array([[x, p]]), None
