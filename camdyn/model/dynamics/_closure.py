"""A form-closed follower (a roller in a groove): it cannot jump, the contact force changes flank instead.

The follower, held on the cam by both walls, follows the motion, so the force the cam exerts on it is the
kinematic force ``Fi = m w^2 s'' + c w s' + k s + F0 + F_ext`` (:mod:`._kinematic`), signed: positive on the
inner flank (the one a spring would hold it on), negative on the outer. A crossover is where Fi changes sign.

With backlash b the roller, where the force leaves its flank, flies free (under its spring and damper, if any:
:func:`._compliant.vector_field`; at constant velocity without them) across the gap until the other flank meets
it: diffrax with a landing event, as the rigid follower's flights (:mod:`._rigid`). The gap along the follower's
coordinate is b / lever, the lever (mm per motion unit, :func:`camdyn.model.geometry.geometry_of`) taken at the
crossover and held for the flight (cos of the pressure angle for a translating roller, arm length times it for an
oscillating one; a flight across a fraction of a mm lasts a few degrees). The flank meets the roller at the
relative speed ``v``. A follower train of stiffness k_f (and damping c_f) carries the impact: from the landing the
follower is integrated on that flank through the train (:func:`._train.contact_force`, unilateral, mirrored for
the outer flank; the spring and damper as in flight, :func:`._compliant.vector_field`) over one period of the
contact mode sqrt((k + k_f) / m), and the impact force is the contact force's peak there (about ``|Fi| + v
sqrt(k_f m)``, the half-sine on the flank's steady force, for a stiff undamped train); a rigid train has no finite
impact force.
The crossovers are the zeros of the force with the roller on the pitch curve: a spring's share of the b/2 it
actually sits off it (k b / 2) moves them by that over the force's slope. For the march the landing is plastic
(the rebound after the impact's peak is not followed); the follower's own motion across the gap (at most b /
lever) is not carried into the response's displacement.

Conjugate cams (two cams, two rollers on one follower) are the same with the primary cam for the inner flank and the
conjugate cam for the outer (the flanks named "primary" and "conjugate"); their backlash is the clearance at the
conjugate cam, so the gap along the follower's coordinate is b over the conjugate cam's own lever
(:func:`camdyn.model.geometry.conjugate_lever_mm`), and an arm's impact torque becomes a force through the lever of
the cam it lands on. A preload between the rollers is shared between the cams (:func:`preload_shares`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.errors import NumericalError
from ..._core.jit import cached_jit
from ..._core.units import THETA_GRID, TWO_PI, newton_per_torque
from ...schema import FollowerSpec
from ..follower import FollowerModel
from ..geometry import conjugate_lever_mm, evaluate_geometry
from ..motion import Motion, evaluate
from ._compliant import vector_field
from ._kinematic import kinematic_force_jit
from ._rigid import _lift_off
from ._solver import ATOL, MAX_STEPS, RTOL
from ._train import contact_force

# the flank that pushes the follower up (a spring's) and the one that pulls it back, by closure
_FLANK_NAMES = {"groove": ("inner", "outer"), "conjugate": ("primary", "conjugate")}
_GAP_EPS = 1e-9  # motion units: a return onto the flank left is detected this far into it
_ZERO_FORCE = 1e-9  # of the largest |Fi|: below it the force is zero (a dwell without spring), on neither flank


@dataclass(frozen=True)
class Crossover:
    """Where the contact force leaves a flank (deg in [0, 360)), the flank it leaves and the one the roller lands
    on (the other, or with backlash the same one where the force turns back during the flight), and with backlash
    the landing: angle (deg), relative speed (m/s, at the roller centre) and impact force (N; None for a rigid
    train)."""

    deg: float
    from_flank: str  # "inner" | "outer" (a groove), "primary" | "conjugate" (conjugate cams)
    to_flank: str
    land_deg: float
    impact_velocity_m_per_s: float
    impact_force_N: float | None

    def json(self) -> dict:
        return {
            "deg": self.deg,
            "from_flank": self.from_flank,
            "to_flank": self.to_flank,
            "land_deg": self.land_deg,
            "impact_velocity_m_per_s": self.impact_velocity_m_per_s,
            "impact_force_N": self.impact_force_N,
        }


@dataclass(frozen=True)
class ClosureResponse:
    """A form-closed follower over a revolution at ``omega`` (rad/s): the signed contact force (N, positive on the
    inner flank, 0 in flight; N*m for an oscillating arm as the other models' forces) on ``theta_deg``, and its
    crossovers."""

    type: str
    backlash_mm: float
    omega: float
    theta_deg: np.ndarray
    contact_force: np.ndarray
    crossovers: tuple[Crossover, ...]

    @property
    def max_impact_velocity_m_per_s(self) -> float:
        return max((c.impact_velocity_m_per_s for c in self.crossovers), default=0.0)

    @property
    def max_impact_force_N(self) -> float | None:
        forces = [c.impact_force_N for c in self.crossovers]
        if any(f is None for f in forces):
            return None
        return max((f for f in forces if f is not None), default=0.0)

    def json(self) -> dict:
        return {
            "type": self.type,
            "backlash_mm": self.backlash_mm,
            "crossovers": [c.json() for c in self.crossovers],
            "max_impact_velocity_m_per_s": self.max_impact_velocity_m_per_s,
            "max_impact_force_N": self.max_impact_force_N,
        }


def _other_flank(t, y, args, **kwargs):
    """Zero where the roller, flying towards the flank on ``side`` (+1 outer, -1 inner), meets it."""
    motion, _, _, _, side, gap = args
    return side * (y[0] - motion(t)[0]) - 0.5 * gap


def _same_flank(t, y, args, **kwargs):
    """Zero where the roller comes back onto the flank it left (``_GAP_EPS`` into it, so not at the start)."""
    motion, _, _, _, side, gap = args
    return -side * (y[0] - motion(t)[0]) - 0.5 * gap - _GAP_EPS


def _flank_met(t, y, args, **kwargs):
    """Zero where either flank meets the roller (each condition rises to 0): one continuous condition, so that a
    bracketing root finder takes it (the same flank's condition barely moves while the roller drifts)."""
    return jnp.maximum(_other_flank(t, y, args), _same_flank(t, y, args))


def _flight_field(t, y, args):
    motion, model, omega, contact, _, _ = args
    return vector_field(t, y, (motion, model, omega, contact))


@cached_jit
def _cross(motion, model, omega, theta0, y0, side, gap):
    """Free flight from theta0 until a flank meets the roller: the other one across the gap (motion units) on
    ``side``, or the one it left. Returns the angle (rad) and state where it ended and whether a flank was met,
    each read inside the program (an indexing or a comparison of its result outside compiles one of its own)."""
    import diffrax  # diffrax loads where a program is traced, not where a stored one runs

    sol = _cross_solve(motion, model, omega, theta0, y0, side, gap)
    assert sol.ts is not None and sol.ys is not None
    return sol.ts[-1], sol.ys[-1], sol.result == diffrax.RESULTS.event_occurred


def _cross_solve(motion, model, omega, theta0, y0, side, gap):
    import diffrax
    import optimistix as optx

    return diffrax.diffeqsolve(
        diffrax.ODETerm(_flight_field),
        diffrax.Tsit5(),
        t0=theta0,
        t1=theta0 + TWO_PI,
        dt0=None,
        y0=y0,
        args=(motion, model, omega, False, side, gap),
        saveat=diffrax.SaveAt(t1=True),
        stepsize_controller=diffrax.PIDController(rtol=RTOL, atol=ATOL),
        event=diffrax.Event(_flank_met, root_finder=optx.Bisection(1e-12, 1e-12), direction=True),
        max_steps=MAX_STEPS,
        throw=False,
    )


IMPACT_SAMPLES = 2001  # angles over the contact period at which the impact's contact force is taken


def flank_force(motion, model, omega, theta, y, side, gap):
    """The contact force (N, or N*m for an arm; signed as the flank pushes) of the follower at (x, dx/dtheta)
    ``y`` (motion units, rows) on the flank on ``side`` at ``theta`` (rad), the flank ``gap`` / 2 off the pitch
    curve: the train's unilateral force (:func:`._train.contact_force`), mirrored for the outer flank."""
    s, s1, _, _ = motion(theta)
    return side * contact_force(
        model, omega, side * s - 0.5 * gap, side * s1, side * y[..., 0], side * y[..., 1], model.scale
    )


def _flank_field(t, y, args):
    """d/dtheta of (x, p) of the follower pressed on the flank on ``side`` (+1 inner: pushes it up; -1 outer)
    through the train: the free flight's field plus the flank's force (:func:`flank_force`)."""
    motion, model, omega, side, gap = args
    fi = flank_force(motion, model, omega, t, y, side, gap)
    return vector_field(t, y, (motion, model, omega, False)) + jnp.stack(
        [0.0, fi / (model.mass * omega**2 * model.scale)]
    )


@cached_jit
def _impact(motion, model, omega, theta0, y0, side, gap, span):
    """The follower from its landing (theta0, y0) on the flank on ``side`` over ``span`` rad of cam angle: its
    contact force there on :data:`IMPACT_SAMPLES` angles."""
    import diffrax

    ts = theta0 + span * jnp.linspace(0.0, 1.0, IMPACT_SAMPLES)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_flank_field),
        diffrax.Tsit5(),
        t0=theta0,
        t1=theta0 + span,
        dt0=None,
        y0=y0,
        args=(motion, model, omega, side, gap),
        saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=diffrax.PIDController(rtol=RTOL, atol=ATOL),
        max_steps=MAX_STEPS,
        throw=False,
    )
    return flank_force(motion, model, omega, ts, sol.ys, side, gap), sol.result == diffrax.RESULTS.successful


def _host(x: ArrayLike) -> np.ndarray:
    """A compiled program's argument as a float64 numpy array: ``jnp.asarray`` outside a program compiles one of
    its own."""
    return np.asarray(x, dtype=float)


def impact_force(motion: Motion, model: FollowerModel, omega: float, theta: float, y, side: float, gap: float):
    """The peak contact force (N, or N*m for an arm) of the impact of the follower landing at ``theta`` (rad) in
    state ``y`` (x, dx/dtheta; motion units) on the flank on ``side`` (+1 inner, -1 outer) of the groove ``gap``
    wide (motion units): the train's contact over one period of its contact mode, and the angle (rad) of the peak."""
    span = omega * TWO_PI / math.sqrt((float(model.stiffness) + float(model.train_stiffness)) / float(model.mass))
    f, ok = _impact(motion, model, _host(omega), _host(theta), _host(y), _host(side), _host(gap), _host(span))
    f = np.abs(np.asarray(f))
    if not bool(ok) or not np.all(np.isfinite(f)):
        raise NumericalError(f"impact at {math.degrees(theta) % 360:.2f} deg", "the train's contact did not integrate")
    i = int(np.argmax(f))
    if 0 < i < f.size - 1:  # the parabola through the peak sample and its neighbours: its vertex
        a, b, c = f[i - 1], f[i], f[i + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            u = 0.5 * (a - c) / den
            return float(b - 0.25 * (a - c) * u), theta + span * (i + u) / (IMPACT_SAMPLES - 1)
    return float(f[i]), theta + span * i / (IMPACT_SAMPLES - 1)


def flank_lever(motion: Motion, follower: FollowerSpec, theta: float, inner: bool = True) -> float:
    """The lever (mm per motion unit) of the flank at cam angle ``theta`` (rad): the inner (primary) one, or the
    outer; a groove's walls share the pitch curve's normal, conjugate cams have each their own."""
    if not inner and follower.closure == "conjugate":
        return float(conjugate_lever_mm(motion, follower, np.array([theta]))[0])
    return float(evaluate_geometry(motion, follower, np.array([theta]))["lever"][0])


def _roller_arm_m(follower: FollowerSpec, inner: bool) -> float:
    """m at the centre of the roller on the inner (primary) or the outer flank per unit of the follower's velocity:
    1 for a translating follower, the arm's length for an oscillating one (a conjugate rocker's second arm)."""
    if follower.translating:
        return 1.0
    second = not inner and follower.closure == "conjugate"
    return 1e-3 * ((follower.conjugate_arm_length if second else None) or follower.arm_length or 0.0)


def flight_gap(motion: Motion, follower: FollowerSpec, theta: float) -> float:
    """The backlash along the follower's coordinate at cam angle ``theta`` (rad): b / lever, mm or rad (the
    conjugate cam's lever: the backlash is its clearance)."""
    return follower.backlash / flank_lever(motion, follower, theta, inner=follower.closure != "conjugate")


def cross_gap(motion: Motion, model: FollowerModel, omega: float, theta0: float, gap: float, side: float):
    """The flight from the flank opposite ``side`` at ``theta0`` (rad) towards the one across ``gap`` (motion
    units): the landing angle (rad, unwrapped), the relative speed there (motion units per rad, positive closing),
    whether the roller met the other flank (False: it came back onto the one it left) and its state there (x,
    dx/dtheta)."""
    s0 = np.asarray(evaluate(motion, _host(theta0)))
    y0 = np.array([s0[0] - side * 0.5 * gap, s0[1]])
    t1, y1, met = _cross(motion, model, _host(omega), _host(theta0), y0, _host(side), _host(gap))
    if not bool(met):
        raise NumericalError(
            f"crossover at {math.degrees(theta0) % 360:.2f} deg", "the follower never met the other flank"
        )
    t1, y1 = float(t1), np.asarray(y1)
    s1 = np.asarray(evaluate(motion, _host(t1)))
    across = side * float(y1[0] - s1[0]) > 0.0  # on the far side of the pitch curve: the other flank
    return t1, abs(float(y1[1] - s1[1])), across, y1


def _sign_changes(signs: np.ndarray) -> list[tuple[int, int]]:
    """(i, j) for each change of sign between the non-zero entries i and j (j the next non-zero after i,
    cyclically; j may wrap past the end), starting at the first non-zero entry."""
    nz = np.flatnonzero(signs)
    n = signs.size
    return [
        (int(i), int(j) if j > i else int(j) + n)
        for i, j in zip(nz, np.roll(nz, -1), strict=True)
        if signs[i] != signs[j]
    ]


def _crossing_angles(fk, signs: np.ndarray, h: float, breaks: np.ndarray) -> list[tuple[float, bool]]:
    """(angle in rad, leaving the inner flank) of every sign change of the force on the grid, in order: its root in
    a step (:func:`._rigid._lift_off`), or a jump through zero at a break; where the force was zero between (a dwell
    without spring), the last break there, else the step before it leaves zero."""
    out = []
    for i, j in _sign_changes(signs):
        down = bool(signs[i] > 0)
        if j == i + 1:
            t_c = _lift_off(fk if down else (lambda t: -fk(t)), i * h, h, breaks)
        else:
            t_a, t_b = (i + 1) * h, (j - 1) * h
            inside = [b + TWO_PI * k for b in breaks for k in (0, 1) if t_a - 1e-12 <= b + TWO_PI * k <= t_b + h]
            t_c = max(inside) if inside else t_b
        out.append((t_c, down))
    return sorted(out)


def closure_response(
    motion: Motion,
    follower: FollowerSpec,
    model: FollowerModel,
    omega: float,
    n: int = THETA_GRID,
    max_flights: int = 64,
) -> ClosureResponse:
    """The signed contact force of a groove cam's follower at cam speed ``omega`` (rad/s), its crossovers, and with
    ``follower.backlash`` the flights across the gap and the impacts on the other flank.

    With backlash the revolution is marched from the first crossover: a flight from each angle where the force
    leaves the flank the roller is on, landing (plastic) on the other flank or back on the same one; where the
    force at a landing already pulls the roller off that flank, the next flight starts there.
    """
    h = TWO_PI / n
    theta = np.arange(n) * h
    w = np.asarray(omega, dtype=float)  # numpy arguments: jnp.asarray would compile a program of its own
    force = np.asarray(kinematic_force_jit(motion, model, w, theta))
    signs = np.where(np.abs(force) <= _ZERO_FORCE * float(np.max(np.abs(force))), 0, np.sign(force)).astype(int)

    def fk(t):
        return float(kinematic_force_jit(motion, model, w, np.asarray(t, dtype=float)))

    breaks = np.deg2rad(np.asarray(motion.breaks_deg, dtype=float))
    cands = _crossing_angles(fk, signs, h, breaks)
    deg = lambda t: math.degrees(t) % 360.0  # noqa: E731
    names = _FLANK_NAMES[follower.closure]
    out = force.copy()
    if follower.backlash == 0.0 or not cands:
        flip = (names[1], names[0])
        crossovers = [Crossover(deg(t), *(names if down else flip), deg(t), 0.0, 0.0) for t, down in cands]
        return ClosureResponse(
            follower.closure, follower.backlash, float(omega), np.degrees(theta), out, tuple(crossovers)
        )
    cands += [(t + TWO_PI, down) for t, down in cands]  # a flight may carry past the revolution's end
    kf = float(model.train_stiffness)
    t_end = cands[0][0] + TWO_PI
    inner = cands[0][1]  # the flank the roller is on before the first crossover (leaving inner: it was on it)
    t_c = cands[0][0]
    crossovers = []
    for _ in range(max_flights):
        left = names[0] if inner else names[1]
        side = 1.0 if inner else -1.0  # towards the outer flank from the inner one
        gap = flight_gap(motion, follower, t_c)
        t_land, v_rel, across, y_land = cross_gap(motion, model, omega, t_c, gap, side)
        inner = inner != across
        v_rel_si = v_rel * omega * model.scale  # m/s, or rad/s of the arm
        f_land = fk(t_land)
        f_imp = None
        if not math.isinf(kf):
            peak, t_peak = impact_force(motion, model, omega, t_land, y_land, 1.0 if inner else -1.0, gap)
            if not follower.translating:  # the arm's torque as the force at the roller
                peak *= float(newton_per_torque(flank_lever(motion, follower, t_peak, inner)))
            f_imp = float(peak)
        landed = names[0] if inner else names[1]
        crossovers.append(
            Crossover(deg(t_c), left, landed, deg(t_land), v_rel_si * _roller_arm_m(follower, inner), f_imp)
        )
        out[np.arange(math.ceil(t_c / h), math.floor(t_land / h) + 1) % n] = 0.0  # in flight: on neither flank
        if (f_land <= 0.0) == inner:  # the force pulls the roller off the flank it landed on: off again
            t_c = t_land
        else:
            nxt = [t for t, down in cands if t > t_land and down == inner]
            if not nxt:
                break
            t_c = nxt[0]
        if t_c >= t_end - 1e-12:
            break
    else:
        raise NumericalError(
            f"crossover at {deg(t_c):.2f} deg", f"still crossing the backlash after {max_flights} flights"
        )
    crossovers.sort(key=lambda c: c.deg)
    return ClosureResponse(follower.closure, follower.backlash, float(omega), np.degrees(theta), out, tuple(crossovers))


def preload_shares(force: np.ndarray, preload: float) -> tuple[np.ndarray, np.ndarray]:
    """Each conjugate cam's share of the follower's signed force ``force`` (N, or N*m) with the rollers pressed on
    their cams by ``preload`` (same unit) at rest: equally stiff contacts share a change of force half each, so the
    primary cam carries P + F/2 and the conjugate P - F/2, until one unloads and the other carries it all
    (F1 = max(F, P + F/2, 0), F2 = F1 - F; with no preload the force on the cam it presses)."""
    primary = np.maximum(np.maximum(force, preload + 0.5 * force), 0.0)
    return primary, primary - force
