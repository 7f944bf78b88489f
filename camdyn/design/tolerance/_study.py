"""The Monte Carlo tolerance study: draw the built cams, run the kernel over them (sharded over every device of
every process), and summarise: the probability of separation at the case speed with its confidence interval,
percentiles, the worst samples and the sensitivities."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import jax
import numpy as np

from ..._core.errors import InputError
from ..._core.jit import device_array
from ..._core.limits import check_samples
from ..._core.progress import Progress, counter, phase
from ..._core.sharding import run_batched
from ..._core.units import FFT_GRID, PROFILE_ERROR_HARMONICS, RPM, THETA_GRID, tolerance_unit
from ...model import dynamics as dyn
from ...model.geometry import contact_per_force
from ...schema import Tolerance
from ..parts import resolve_spring
from ._interval import exact_interval
from ._kernel import Sample, make_grid, rigid_tolerance_kernel, tolerance_kernel
from ._result import ToleranceResult
from ._sampling import SCALAR_KEYS, Spread, case_tolerances, draw_samples, spreads
from ._sensitivity import gradient_sensitivities, variance_shares

if TYPE_CHECKING:
    from ...model.case import Case

SCAN_GRID = 512  # angles of the jump-speed search (the least force at the case speed uses THETA_GRID)
CHUNK_SAMPLES = 256  # samples per device per compiled call
WORST = 3  # samples written out as case files


def _nominal(case) -> dict[str, float]:
    m, kind = case.model, case.kind
    return {
        "spring_rate": float(kind.rate_from_si(m.stiffness)),
        "preload": float(m.preload),
        "mass": float(m.mass),
        "train_stiffness": float(kind.rate_from_si(m.train_stiffness)),
        "speed": float(case.speed_rpm),
        "profile_error": 0.0,
    }


def scan_grid(case: Case) -> int:
    """The angles of the jump-speed search: :data:`SCAN_GRID`, or the check's :data:`FFT_GRID` where the cam's
    velocity steps under a compliant train (a rigid follower it throws off at any speed: the study says so without
    a search). A train's steady response to a step is a spike that a coarser grid misses or overshoots: a
    constant-velocity rise between dwells (the lecture's tolerances at 30 rpm) jumps at 55.0 rpm on 512 angles, 29.9
    on 1024, 37.0 on 2048, 40.3 on 3600 and 4096 (the check's 40.33; the time domain holds at 40 rpm and leaves the
    cam at 45)."""
    return FFT_GRID if not case.model.rigid and case.motion.velocity_jumps() else SCAN_GRID


def _search_limit(case) -> float:
    """The jump-speed search limit, rad/s: ``camdyn check``'s, 4x beyond the margin (or the kinematic jump)."""
    omega = case.speed_rpm * RPM
    w_kin, _ = dyn.kinematic_jump_speed(case.motion, case.model)
    return dyn.jump_search_limit(case.limits.speed_margin * omega, w_kin)


def _to_si(case, vals: dict[str, np.ndarray]) -> list[np.ndarray]:
    kind = case.kind
    return [
        kind.rate_to_si(vals["spring_rate"]),
        vals["preload"],
        vals["mass"],
        kind.rate_to_si(vals["train_stiffness"]),
        vals["speed"] * RPM,
        vals["profile_coeffs"],
    ]


def tolerance_study(
    case: Case,
    samples: int,
    seed: int = 0,
    *,
    progress: Progress | None = None,
    devices: tuple | None = None,
) -> ToleranceResult:
    """Monte Carlo study of ``case``'s ``[tolerances]`` over ``samples`` built cams drawn from ``seed``.

    ``devices``: the JAX devices to shard the samples over (default: every device of every process, the global
    mesh after :func:`camdyn._core.distributed.initialize`); the result does not depend on them."""
    check_samples(samples)
    if case.valvetrain is not None:  # the equivalent single follower has no lash, seat or float
        raise InputError(
            "valvetrain",
            "the single follower's tolerance study does not apply: camdyn tolerance studies a valvetrain with the "
            "two-mass model (valvetrain_tolerance_study)",
        )
    devices = tuple(jax.devices() if devices is None else devices)
    case = resolve_spring(case)  # [spring] model: the spring's own mass (its lumped third) in the nominal mass
    kind, base = case.kind, case.model
    tols = case_tolerances(case)
    if base.rigid and any(t.key == "train_stiffness" for t in tols):
        raise InputError(
            "tolerances.train_stiffness",
            "a rigid follower has no train stiffness: remove the key or give [dynamics] train_stiffness",
        )
    nominal = _nominal(case)
    spread = spreads(tols, nominal)
    vals = draw_samples(spread, nominal, samples, seed)
    for key in ("spring_rate", "mass", "train_stiffness", "speed"):
        if np.any(vals[key] <= 0.0):
            raise InputError(
                f"tolerances.{key}",
                f"the tolerance reaches a value <= 0 {tolerance_unit(key, kind.rotary)} in some samples: give a "
                "smaller one",
            )
    with phase(progress, "the nominal cam (grids, the search's speed limit)"):
        weight = lambda t: contact_per_force(case.motion, case.follower, t)  # noqa: E731
        fine = make_grid(case, THETA_GRID, PROFILE_ERROR_HARMONICS, weight)
        scan = make_grid(case, scan_grid(case), PROFILE_ERROR_HARMONICS, lambda t: np.ones_like(t))
        w_max = _search_limit(case)
    kernel = rigid_tolerance_kernel if base.rigid else tolerance_kernel
    tick = counter(progress, "built cams (steady state, jump speed)", samples)
    tick(0)  # said before the first chunk, which waits on the kernel's compile
    force, jump = run_batched(
        kernel, (base, fine, scan, device_array(w_max)), _to_si(case, vals), CHUNK_SAMPLES, tick, devices
    )
    thrown = base.rigid and bool(dyn.velocity_steps(case.motion, float(base.restitution)))
    if thrown:  # a step in the cam's velocity throws a rigid follower off at any speed; the samples keep the step
        force, jump = np.minimum(np.asarray(force), 0.0), np.zeros_like(np.asarray(jump))
    sep = int(np.count_nonzero(force <= 0.0))
    ci = exact_interval(sep, samples)
    jump_rpm = np.asarray(jump) / RPM
    params = {k: vals[k] for k in SCALAR_KEYS} | {
        "profile_error": np.sqrt(0.5 * np.sum(vals["profile_coeffs"] ** 2, axis=1))
    }
    if thrown:  # the margin is 0 whatever the tolerances: none of them moves it
        sens = {k: {"gradient_sigma": 0.0, "share_linear": math.nan, "share_monte_carlo": math.nan} for k in spread}
        w_star = 0.0
    else:
        with phase(progress, "sensitivities"):
            sens, w_star = _sensitivities(case, base, scan, w_max, nominal, spread, vals, jump_rpm)
    return ToleranceResult(
        case=case.name,
        kind=kind,
        seed=seed,
        speed_rpm=float(case.speed_rpm),
        params=params,
        least_force=np.asarray(force),
        jump_speed_rpm=jump_rpm,
        tolerances={t.key: describe(t, spread[t.key], kind.rotary) for t in tols},
        probability=sep / samples,
        confidence_interval=ci,
        sensitivities=sens,
        nominal_jump_speed_rpm=w_star / RPM,
        worst=tuple(int(i) for i in np.argsort(force, kind="stable")[:WORST]),
        devices=len(devices),
        processes=jax.process_count(),
    )


def describe(t: Tolerance, sp: Spread, rotary: bool) -> dict:
    return {
        "tolerance": t.value * 100.0 if t.relative else t.value,
        "unit": "%" if t.relative else tolerance_unit(t.key, rotary),
        "distribution": t.distribution,
        "sigma": sp.sigma,
        "sigma_unit": tolerance_unit(t.key, rotary),
    }


def _sensitivities(case, base, scan, w_max, nominal, spread, vals, jump_rpm):
    """Per key: the gradient sensitivity, its share of the linearised variance and the Monte Carlo share."""
    kind = case.kind
    si = dict(
        zip(
            ("spring_rate", "preload", "mass", "train_stiffness", "speed"),
            (kind.rate_to_si(1.0), 1.0, 1.0, kind.rate_to_si(1.0), RPM),
            strict=True,
        )
    )
    nom = Sample(
        base.stiffness,
        base.preload,
        base.mass,
        base.train_stiffness,
        device_array(case.speed_rpm * RPM),  # placed: jax.numpy here would compile a program per operation
        device_array(np.zeros(2 * PROFILE_ERROR_HARMONICS)),
    )
    sigma_si = {k: sp.sigma * si.get(k, 1.0) for k, sp in spread.items()}
    grad, w_star = gradient_sensitivities(base, scan, nom, w_max, sigma_si, base.rigid)
    margin = jump_rpm / vals["speed"]
    devs = {k: (vals["profile_coeffs"] if k == "profile_error" else vals[k] - nominal[k]) for k in spread}
    shares = variance_shares(margin, devs)
    total = sum(g * g for g in grad.values() if math.isfinite(g))
    return {
        k: {
            "gradient_sigma": grad[k],
            "share_linear": grad[k] ** 2 / total if total > 0 and math.isfinite(grad[k]) else math.nan,
            "share_monte_carlo": shares[k],
        }
        for k in spread
    }, w_star
