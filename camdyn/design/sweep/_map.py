"""The jump map: the grid of (speed, spring rate) points, the in-contact least force at each, the largest gap of
the separated ones, and the :class:`JumpMap` they make."""

from __future__ import annotations

import threading
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from ..._core.errors import InputError, NumericalError
from ..._core.jit import in_background
from ..._core.progress import Progress, counter
from ..._core.sharding import accelerated, prepare_batched, run_batched
from ..._core.units import RPM, TWO_PI
from ...model import dynamics as dyn
from ...model.geometry import contact_per_force, newton_per_torque_at
from ...model.motion import evaluate
from ..parts import resolve_spring, spring_mass_notes
from ._contact import damping_kernel, kinematic_kernel, linear_kernel, with_spring_damping
from ._diffrax_gap import diffrax_gap_const, diffrax_gap_kernel
from ._exact_gap import gap_kernel
from ._grid import GAP_CHUNK, GAP_STRIDE, GRID_N, LINEAR_CHUNK, check_grid_size
from ._result import STATUS_OK, JumpMap, failed
from ._valvetrain import valvetrain_map


@dataclass(frozen=True)
class _Points:
    """The grid flattened speed-major: cam speed (rad/s), spring rate and damping (SI) per point (the damping only
    for a rigid follower: the compliant kernels derive it from the rate themselves, one program fewer to load)."""

    speeds_rpm: np.ndarray  # (ns,)
    rates: np.ndarray  # (nk,) user units
    omega: np.ndarray  # (ns * nk,)
    k: np.ndarray
    c: np.ndarray | None

    @property
    def damping(self) -> np.ndarray:
        """The damping per point (SI), computed for a rigid follower's map only."""
        if self.c is None:
            raise ValueError("the damping per point is computed for a rigid follower's map only")
        return self.c

    @property
    def shape(self) -> tuple[int, int]:
        return self.speeds_rpm.size, self.rates.size


def _points(case, speeds_rpm, spring_rates, devices) -> _Points:
    base = case.model
    rate0 = case.kind.rate_from_si(float(base.stiffness))
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    rates = np.atleast_1d(np.asarray(spring_rates if spring_rates is not None else [rate0], dtype=float))
    check_grid_size(speeds.size, rates.size)
    if (
        speeds.size == 0
        or rates.size == 0
        or not (np.all(speeds > 0) and np.all(rates > 0) and np.all(np.isfinite(speeds)) and np.all(np.isfinite(rates)))
    ):
        raise InputError("sweep", "speeds and spring rates must be positive and finite")
    sp, kr = np.meshgrid(speeds, rates, indexing="ij")
    k_si = case.kind.rate_to_si(kr.ravel())
    c = run_batched(damping_kernel, base, [k_si], LINEAR_CHUNK, None, devices) if base.rigid else None
    return _Points(speeds, rates, sp.ravel() * RPM, k_si, c)


def _gap_weight_mm(case, theta) -> np.ndarray:
    """The contact's gap (mm) per unit of the follower's gap (mm, or rad of swing: the lever arm, mm)."""
    if not case.kind.rotary:
        return np.ones(np.shape(theta))
    return 1000.0 / newton_per_torque_at(case.motion, case.follower, np.asarray(theta))


def _rigid_gaps(case, pts: _Points, idx, progress) -> tuple[np.ndarray, dict[int, str]]:
    """Largest gap (mm) of the event-driven flight model at the separated points ``idx``, one at a time, and the
    reason per point where the flight computation failed (its gap NaN): a point that fails never stops the map."""
    base, gap, why = case.model, np.zeros(pts.omega.size), {}
    step = counter(progress, "flights (rigid model, one point at a time)", idx.size)
    for i in idx:
        # Python floats, as case.follower_model builds them: the compiled flight solve is reused
        md = with_spring_damping(base, jnp.asarray(float(pts.k[i])), jnp.asarray(float(pts.damping[i])))
        try:
            r = dyn.rigid_response(case.motion, md, float(pts.omega[i]))
        except NumericalError as err:
            gap[i], why[int(i)] = np.nan, str(err)
        except Exception as err:  # noqa: BLE001  (a bug at one point: flagged in its row, the map goes on)
            gap[i], why[int(i)] = np.nan, f"internal error in the flight model: {type(err).__name__}: {err}"
        else:
            w = _gap_weight_mm(case, np.deg2rad(r.theta_deg))
            # the grid's, and each flight's apex between the grid's angles (a short flight has none on it)
            apex = 0.0
            if r.separations:
                at = np.deg2rad([sep.max_gap_deg for sep in r.separations])
                apex = float(np.max(np.array([sep.max_gap for sep in r.separations]) * _gap_weight_mm(case, at)))
            gap[i] = max(0.0, float(np.max((r.x - r.s) * w)), apex)
        step(1)
    return gap, why


def _rigid_map(case, pts: _Points, angles, gaps: bool, progress, devices):
    theta, vals, weight = angles
    const = (case.model, *vals[:3], weight)  # numpy: no transfer programs to compile
    signed = run_batched(
        kinematic_kernel,
        const,
        [pts.omega, pts.k, pts.damping],
        LINEAR_CHUNK,
        counter(progress, "kinematic force", pts.omega.size),
        devices,
    )
    why = {int(i): "the kinematic force is not finite" for i in np.nonzero(~np.isfinite(signed))[0]}
    if dyn.velocity_steps(case.motion, float(case.model.restitution)):  # thrown off at any speed: no force holds
        signed = np.minimum(signed, 0.0)
    separated = signed <= 0.0
    idx = np.nonzero(separated)[0] if gaps else np.zeros(0, dtype=int)
    gap, why_gap = _rigid_gaps(case, pts, idx, progress)
    return signed, separated, gap, why | why_gap


def _compliant_map(case, pts: _Points, angles, gaps: bool, gap_method: str, progress, devices, head_start=None):
    base = case.model
    theta, vals, weight = angles
    const = (base, vals[0], vals[1], np.fft.rfft(vals[0]), weight)  # numpy: no transfer or FFT program to compile
    tick = counter(progress, "steady state (frequency domain)", pts.omega.size)
    signed = run_batched(linear_kernel, const, [pts.omega, pts.k], LINEAR_CHUNK, tick, devices)
    why = {int(i): "the frequency-domain steady state is not finite" for i in np.nonzero(~np.isfinite(signed))[0]}
    separated = signed <= 0.0
    gap = np.zeros(pts.omega.size)
    idx = np.nonzero(separated)[0] if gaps else np.zeros(0, dtype=int)
    if not idx.size:
        return signed, separated, gap, why
    tick = counter(progress, "separated points (nonlinear model)", idx.size)
    point = [pts.omega[idx], pts.k[idx]]
    spec_unit = np.fft.rfft(vals[0] / base.scale)  # the lift's spectrum in the motion's unit
    if gap_method == "exact":
        tab = vals[:3, ::GAP_STRIDE] / base.scale  # the same angles: no second evaluation of the motion (its compile)
        w_tab = _gap_weight_mm(case, theta[::GAP_STRIDE])
        gconst = (base, *tab, w_tab, spec_unit)
        kernel = gap_kernel(accelerated(devices))
        if head_start is not None:
            head_start.join()  # its program, not a second compile of it here
        g = run_batched(kernel, gconst, point, GAP_CHUNK, tick, devices, per_point=False)
    else:
        gconst = diffrax_gap_const(case, lambda t: _gap_weight_mm(case, t), spec_unit)
        g = run_batched(diffrax_gap_kernel, gconst, point, GAP_CHUNK, tick, devices)
    gap[idx] = np.maximum(g, 0.0)
    how = "exact piecewise-linear stepping" if gap_method == "exact" else "diffrax"
    why |= {int(i): f"the gap integration of the nonlinear model ({how}) did not finish" for i in idx[~np.isfinite(g)]}
    return signed, separated, gap, why


def _gap_const_like(base) -> tuple:
    """Zeros shaped as the exact gap stepping's constants (``_compliant_map``'s ``gconst``): its program's key."""
    steps = np.zeros(GRID_N // GAP_STRIDE)
    return (base, steps, steps, steps, steps, np.zeros(GRID_N // 2 + 1, dtype=complex))


def _prepare_gaps(base, devices) -> threading.Thread:
    """A thread that compiles (or loads) the exact gap stepping's program while this one evaluates the motion and
    the steady state (a compile of about a second on a CPU, most of a first map's time). Its key depends on the
    follower kind and the shapes only, so it is known before anything is computed."""
    kernel = gap_kernel(accelerated(devices))
    point = [np.ones(1), np.ones(1)]
    return in_background(
        lambda: prepare_batched(kernel, _gap_const_like(base), point, GAP_CHUNK, devices, False),
        "camdyn-prepare-gaps",
    )


def _notes(gaps: bool, separated, gap, why: dict[int, str]) -> tuple[str, ...]:
    notes = []
    if not gaps and separated.any():
        notes.append("gaps not computed (gaps=False): max_gap_mm is NaN where the follower separates")
    if why:
        first = min(why)
        notes.append(f"{len(why)} grid point(s) failed (status column, their numbers NaN); the first: {why[first]}")
    train_only = separated & (gap == 0.0)
    if gaps and train_only.any():
        notes.append(
            f"at {int(train_only.sum())} separated point(s) max_gap_mm is 0: the interface force reaches 0 in the "
            "follower train alone (its damper would have to pull) while the follower never passes the cam profile "
            "(as where the spring rate dwarfs the train stiffness, or just past the jump boundary)"
        )
    return tuple(notes)


def jump_map(
    case,
    speeds_rpm,
    spring_rates=None,
    *,
    progress: Progress | None = None,
    gap_method: str = "exact",
    devices=None,
    gaps: bool = True,
) -> JumpMap:
    """Jump map of ``case`` over ``speeds_rpm`` x ``spring_rates`` (N/mm; N*m/rad for an oscillating follower).
    A ``[valvetrain]`` case's is the two-mass model's (:mod:`._valvetrain`: float, bounce, the valve spring's
    rate at the valve).

    ``spring_rates`` defaults to the case's own. ``progress(phase, done, total)`` is called after every chunk.
    ``gap_method``: how the compliant model's separated points are integrated: ``"exact"`` (piecewise-linear
    stepping, :mod:`._exact_gap`) or ``"diffrax"`` (adaptive Tsit5 on the vector field of
    :mod:`camdyn.model.dynamics`, the reference; tens of times slower). ``devices``: the JAX devices to shard the
    grid over (default: all local devices); the result does not depend on them. ``gaps=False`` skips the largest
    gap of the separated points (the nonlinear integration, most of the cost of a rigid follower's map): their
    ``max_gap`` is NaN; the least force, the separation and the jump boundary are the same.
    """
    if case.valvetrain is not None:  # the two-mass model, one point at a time: lash, seat, float and bounce
        return valvetrain_map(case, speeds_rpm, spring_rates, progress=progress)
    devices = tuple(jax.devices() if devices is None else devices)
    if gap_method not in ("exact", "diffrax"):
        raise ValueError(f"gap_method must be 'exact' or 'diffrax', not {gap_method!r}")
    case = resolve_spring(case)  # [spring] model: the spring's own mass (its lumped third) on the follower
    pts = _points(case, speeds_rpm, spring_rates, devices)
    base = case.model
    head_start = _prepare_gaps(base, devices) if gaps and gap_method == "exact" and not base.rigid else None
    try:
        theta = np.arange(GRID_N) * (TWO_PI / GRID_N)
        vals = np.asarray(evaluate(case.motion, theta)) * base.scale
        weight = contact_per_force(case.motion, case.follower, theta)
        angles = (theta, vals, weight)
        if base.rigid:
            signed, separated, gap, why = _rigid_map(case, pts, angles, gaps, progress, devices)
        else:
            signed, separated, gap, why = _compliant_map(
                case, pts, angles, gaps, gap_method, progress, devices, head_start
            )
    finally:
        if head_start is not None:
            head_start.join()
    if not gaps:
        gap[separated] = np.nan
    status = np.full(signed.shape, STATUS_OK, dtype=object)
    bad = np.zeros(signed.shape, dtype=bool)
    for i, reason in why.items():
        status[i], bad[i] = failed(reason), True
    notes = _notes(gaps, separated, gap, why) + spring_mass_notes(case)
    return JumpMap(
        case=case.name,
        model="rigid" if base.rigid else "compliant",
        kind=case.kind,
        speeds_rpm=pts.speeds_rpm,
        spring_rates=pts.rates,
        min_force=np.where(bad, np.nan, np.where(separated, 0.0, signed)).reshape(pts.shape),
        separated=separated.reshape(pts.shape),
        max_gap=np.where(bad, np.nan, gap).reshape(pts.shape),
        contact_force=np.asarray(signed).reshape(pts.shape),
        speed_rpm=float(case.speed_rpm),
        spring_rate=case.kind.rate_from_si(float(base.stiffness)),
        preload=float(base.preload),
        devices=len(devices),
        notes=notes,
        status=status.reshape(pts.shape),
    )
