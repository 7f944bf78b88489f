"""What a check cannot see in the numbers alone: how far a lift table's noise moves the least contact force, and
magnitudes that are almost surely a unit slip.

A lift table's fit (:mod:`camdyn.model.motion._spline`) keeps some of the data's noise, and the force goes with the
fitted acceleration: in a dwell the exact s'' is 0, the fitted one is noise, and the least force over a flat
stretch is the deepest of that noise. The interface force is affine in the motion while the follower stays on
the cam, so the error the noise leaves is ``e(theta) = F[fit] - F[true]``, and ``|min F[fit] - min F[true]| <=
max |e|``. The spline's response to seeded noise of the data's size (a parametric bootstrap, ``noise_coef``)
samples ``e``; the 95th percentile of ``max |e|`` over those samples is the uncertainty stated.

A unit slip is a warning, not an error (the value may be meant): the thresholds sit far from every shipped case
(jump speed over speed at most 26, spring force over the lift at most 2.6 times the preload or inertia force) and
far below what the slip gives (60 x a margin, 1000 x a ratio).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import numpy as np

from .._core.jit import cached_jit
from .._core.units import FFT_GRID, RPM
from ..model import dynamics as dyn
from ..model.case import Case
from ..model.geometry import contact_per_force
from ..model.motion import FittedMotion
from ..schema import dynamics_keys

# A table's least force is called uncertain when its noise moves it by more than this share (95 %): a finer
# distinction than a design's force margin is then left to the noise, not to the data.
FORCE_NOISE_SHARE = 0.02
# a speed this many times below the jump speed is likely rev/s (Hz) given as rpm (a slip gives 60 x the margin)
HZ_SLIP_RATIO = 40.0
# a spring whose force over the lift is this many times the preload and the peak inertia force is likely given
# per m (N/m, N*mm/rad) instead of per mm (N/mm, N*m/rad): a slip gives 1000 x the ratio
RATE_SLIP_RATIO = 30.0


@cached_jit
def _noise_forces(motion, model, omega, theta, noise, rigid: bool):
    """The interface force (N or N*m) of the follower in contact on ``theta`` (rad, 2 pi k / n), and its change
    (samples, n) with each of ``noise``'s coefficients (samples, rows, 6) added to the motion's (its jit form, whose
    rows they match): one compiled program, stored, where eager ops and a vmap would trace in every process."""

    def _force(m):  # m: the motion's jit form (a QuinticTable), evaluated like a Motion
        if rigid:
            return dyn.kinematic_force(m, model, omega, theta)
        return dyn.linear_contact_force(m, model, omega[None], n=theta.size)[0]

    base = _force(motion)
    return base, jax.vmap(lambda c: _force(eqx.tree_at(lambda t: t.coef, motion, motion.coef + c)) - base)(noise)


def least_force_uncertainty(case: Case, omega: float) -> float | None:
    """The 95 % uncertainty (N) that a lift table's noise leaves in the least contact force at ``omega`` (rad/s)
    of a follower that stays on the cam; None for a motion not fitted to a table."""
    if case.fit is None or case.fit.source != "table" or case.fit.spline.sigma == 0.0:
        return None
    motion = case.motion
    assert isinstance(motion, FittedMotion)  # a table's motion is fitted to it
    noise = case.kind.lift_to_motion(np.moveaxis(case.fit.spline.noise_coef, -1, 0))  # (samples, m, 6)
    rows = motion.jit_form().coef.shape[0]  # the padded rows the compiled program takes: one program per bucket
    noise = np.pad(noise, [(0, 0), (0, rows - noise.shape[1]), (0, 0)])  # the padding rows are never evaluated
    theta = np.arange(FFT_GRID) * (2 * math.pi / FFT_GRID)
    base, err = (
        np.asarray(a)
        for a in _noise_forces(motion, case.model, np.asarray(omega, dtype=float), theta, noise, case.model.rigid)
    )
    if case.kind.rotary:  # torques to contact forces through the lever arm
        per_torque = contact_per_force(motion, case.follower, theta)
        base, err = base * per_torque, err * per_torque
    bound = float(np.percentile(np.max(np.abs(err), axis=1), 95.0))
    # the true least force lies where the fitted force is within twice that bound of its least: only there
    # does the error matter
    near = base <= base.min() + 2.0 * bound
    return float(np.percentile(np.max(np.abs(err[:, near]), axis=1), 95.0))


def least_force_warning(case: Case, least_force_N: float, uncertainty_N: float | None) -> list[str]:
    """A warning where the table's noise moves the least force by more than :data:`FORCE_NOISE_SHARE` of it."""
    fit = case.fit
    if fit is None or uncertainty_N is None or uncertainty_N <= FORCE_NOISE_SHARE * abs(least_force_N):
        return []
    share = 100 * uncertainty_N / abs(least_force_N)
    return [
        (
            f"{fit.file}: the data's noise (about {fit.spline.sigma:.2g} {fit.unit}) leaves the least contact force "
            f"{least_force_N:.4g} N uncertain by up to +-{uncertainty_N:.2g} N ({share:.2g} %; a 95 % bound): the "
            "fitted acceleration carries that noise into the force (in a dwell the least of a noisy force falls low); "
            "tabulate the lift finer or to less noise, or give the motion as segments"
        )
    ]


STILL_NOISE_MULTIPLE = 10.0  # a data case's lift within this many times its noise: the follower barely moves


def lift_within_noise(case: Case, lift: float) -> str | None:
    """A warning where the follower's lift (``lift``, the motion's unit) is within :data:`STILL_NOISE_MULTIPLE`
    times its table's or contour's noise (a round contour): the follower barely moves, and the train's compression
    over that lift says nothing; None otherwise (and for a motion not fitted to data)."""
    fit = case.fit
    if fit is None:
        return None
    if case.contour is not None:  # the outline's radial noise (mm) against the lift at the contact
        noise, unit = case.contour.noise, case.contour.unit
        f = case.follower
        assert f is not None  # a contour is a follower's cam
        arm_mm = 1.0
        if case.kind.rotary:  # an arm's swing (rad) at its roller
            assert f.arm_length is not None  # the schema requires an arm's length
            arm_mm = float(f.arm_length)
        lift_data = lift * arm_mm
    else:
        noise, unit = fit.noise, fit.unit
        lift_data = lift * case.kind.lift_per_motion / fit.follower_per_data
    if noise <= 0.0 or lift_data > STILL_NOISE_MULTIPLE * noise:
        return None
    return (
        f"{fit.file}: the follower's lift, {lift_data:.2g} {unit}, is within {STILL_NOISE_MULTIPLE:g} times the "
        f"data's noise ({noise:.2g} {unit}): it barely moves, so train_deflection (the train's compression over the "
        "lift) is not judged"
    )


def unit_slip_warnings(case: Case, rpm: float, jump_rpm: float | None, jump_name: str = "the jump speed") -> list[str]:
    """Warnings for the case's speed and spring rate where their magnitude is almost surely a unit slip:
    ``speed`` in rev/s for rpm (checked at the case's own speed against ``jump_rpm``, which ``jump_name`` names),
    ``spring_rate`` in N/m for N/mm (``torsion_rate`` in N*mm/rad for N*m/rad)."""
    out = []
    if jump_rpm is not None and rpm == case.speed_rpm and jump_rpm > HZ_SLIP_RATIO * rpm:
        out.append(
            f"dynamics.speed = {rpm:g} rpm is 1/{jump_rpm / rpm:.0f} of {jump_name} ({jump_rpm:.4g} rpm): "
            f"was it given in rev/s (Hz)? {rpm:g} rev/s is {60.0 * rpm:g} rpm"
        )
    model = case.model
    s = case.motion.host(np.linspace(0.0, 2 * math.pi, 3600, endpoint=False))[:3] * model.scale
    spring = float(model.stiffness) * float(np.ptp(s[0]))
    other = max(
        abs(float(model.preload)),
        abs(float(model.external)),
        float(model.mass) * (rpm * RPM) ** 2 * float(np.abs(s[2]).max()),
    )
    if other > 0.0 and spring > RATE_SLIP_RATIO * other:
        kind = case.kind
        key, unit, slip, force = (
            dynamics_keys(kind)[1],
            kind.rate_unit,
            kind.rate_slip_unit,
            kind.force_unit,
        )
        rate = getattr(case.spec.dynamics, key)
        out.append(
            f"dynamics.{key} = {rate:g} {unit}: over the lift its force changes by {spring:.4g} {force}, "
            f"{spring / other:.0f} times the preload and the peak inertia force: was it given in {slip}? "
            f"{rate:g} {slip} is {rate / 1000.0:g} {unit}"
        )
    return out
