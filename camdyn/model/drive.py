"""The camshaft drive: torque from the power balance, its peak, RMS and mean, the mean power and the flywheel.

With a frictionless contact the cam does work on the follower only through the interface force along the
follower's own coordinate, so the power balance at constant cam speed w gives the camshaft torque
``T(theta) = F(theta) * ds/dtheta``: F in N and s' in m/rad for a translating follower, or the arm torque in
N*m and dphi/dtheta (rad/rad) for an oscillating one (the generalized force times the generalized velocity per
radian of cam angle). The cam-side contact point follows the kinematic s even when the follower train is
compliant, so the same formula holds for the dynamic interface force. Its mean over a revolution is the power
the followers dissipate, divided by w.

Flywheel: the energy ``E(theta) = integral (T - mean T) dtheta`` swings by dE over a revolution; the inertia that
holds the coefficient of speed fluctuation ``k_s = (w_max - w_min) / w`` is ``I = dE / (k_s w^2)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.units import DEFAULT_SPEED_FLUCTUATION, THETA_GRID, TWO_PI
from .dynamics import Response, kinematic_force_jit
from .follower import FollowerModel
from .motion import Motion


def camshaft_torque(force, velocity):
    """Camshaft torque (N*m) from the interface force and the follower's velocity per radian of cam angle:
    ``T = F * ds/dtheta`` (N and m/rad, or an arm's N*m and rad/rad). Arrays broadcast."""
    return np.asarray(force) * np.asarray(velocity)


@dataclass(frozen=True)
class DriveTorque:
    """The camshaft torque over one revolution at cam speed ``omega`` (rad/s), on equal steps ``theta_deg``."""

    omega: float
    theta_deg: np.ndarray
    torque: np.ndarray  # N*m; positive where the drive does work on the follower
    speed_fluctuation: float = DEFAULT_SPEED_FLUCTUATION

    @property
    def peak_torque(self) -> float:
        """Largest |T| over the revolution, N*m (what the drive must deliver or hold back)."""
        return float(np.max(np.abs(self.torque)))

    @property
    def peak_torque_at_deg(self) -> float:
        return float(self.theta_deg[int(np.argmax(np.abs(self.torque)))])

    @property
    def rms_torque(self) -> float:
        return float(np.sqrt(np.mean(self.torque**2)))

    @property
    def mean_torque(self) -> float:
        """Mean over the revolution, N*m (the rectangle rule, exact to high order for a periodic integrand)."""
        return float(np.mean(self.torque))

    @property
    def mean_power(self) -> float:
        """Mean power the drive delivers, W: mean T times w."""
        return self.mean_torque * self.omega

    @property
    def energy(self) -> np.ndarray:
        """``E(theta) = integral from 0 to theta of (T - mean T) dtheta``, J (trapezoids; E returns to 0 at 360)."""
        t = self.torque - self.mean_torque
        h = TWO_PI / t.size
        return np.concatenate([[0.0], np.cumsum(0.5 * h * (t[:-1] + t[1:]))])

    @property
    def energy_swing(self) -> float:
        """dE: the largest minus the least of :attr:`energy` over the revolution, J."""
        return float(np.ptp(self.energy))

    @property
    def flywheel_inertia(self) -> float:
        """``I = dE / (k_s w^2)``, kg*m^2: the camshaft inertia that holds the speed fluctuation to k_s."""
        return self.energy_swing / (self.speed_fluctuation * self.omega**2)

    def json(self) -> dict:
        return {
            "peak_torque_N_m": self.peak_torque,
            "peak_torque_at_deg": self.peak_torque_at_deg,
            "max_torque_N_m": float(np.max(self.torque)),
            "min_torque_N_m": float(np.min(self.torque)),
            "rms_torque_N_m": self.rms_torque,
            "mean_torque_N_m": self.mean_torque,
            "mean_power_W": self.mean_power,
            "peak_power_W": self.peak_torque * self.omega,
            "energy_swing_J": self.energy_swing,
            "speed_fluctuation": self.speed_fluctuation,
            "flywheel_inertia_kg_m2": self.flywheel_inertia,
        }


def drive_torque(
    theta_deg, force, velocity, omega: float, *, speed_fluctuation: float = DEFAULT_SPEED_FLUCTUATION
) -> DriveTorque:
    """The drive of a force F (N, or an arm's N*m) and velocity s' (m/rad, or rad/rad) given on equal steps
    ``theta_deg`` of one revolution, at cam speed ``omega`` (rad/s)."""
    theta_deg = np.asarray(theta_deg, dtype=float)
    steps = np.diff(theta_deg)
    if (
        theta_deg.ndim != 1
        or theta_deg.size < 16
        or not np.allclose(steps, 360.0 / theta_deg.size, rtol=1e-9, atol=1e-9)
    ):
        raise InputError("theta_deg", "the drive needs equal steps over one revolution [0, 360)")
    if not (omega > 0 and np.isfinite(omega)):
        raise InputError("omega", f"the cam speed must be positive (got {omega})")
    if not 0.0 < speed_fluctuation < 1.0:
        raise InputError("drive.speed_fluctuation", f"must be between 0 and 1 (got {speed_fluctuation})")
    torque = camshaft_torque(force, velocity)
    return DriveTorque(float(omega), theta_deg, np.asarray(torque, dtype=float), float(speed_fluctuation))


def follower_velocity(motion: Motion, theta_deg, scale: float) -> np.ndarray:
    """ds/dtheta in SI (m/rad, or rad/rad for an arm) at cam angles ``theta_deg``."""
    return motion.host(np.deg2rad(np.asarray(theta_deg, dtype=float)))[1] * scale


def response_drive(
    motion: Motion, resp: Response, *, scale: float, speed_fluctuation: float = DEFAULT_SPEED_FLUCTUATION
) -> DriveTorque:
    """The drive of a steady-state response, from its dynamic interface force.

    ``resp`` is in the model's own units, as :func:`camdyn.model.dynamics.response` returns it: N for a
    translating follower, the arm torque N*m for an oscillating one (not the contact force in N that
    ``camdyn check`` reports). ``scale`` is the follower model's motion unit in SI (``FollowerModel.scale``).
    """
    velocity = follower_velocity(motion, resp.theta_deg, scale)
    return drive_torque(resp.theta_deg, resp.force, velocity, resp.omega, speed_fluctuation=speed_fluctuation)


def kinematic_drive(
    motion: Motion,
    model: FollowerModel,
    omega: float,
    *,
    n: int = THETA_GRID,
    speed_fluctuation: float = DEFAULT_SPEED_FLUCTUATION,
) -> DriveTorque:
    """The drive of a follower that never leaves the cam (its kinematic interface force), n equal steps."""
    theta_deg = np.arange(n) * (360.0 / n)
    force = np.asarray(kinematic_force_jit(motion, model, float(omega), np.deg2rad(theta_deg)))
    velocity = follower_velocity(motion, theta_deg, model.scale)
    return drive_torque(theta_deg, force, velocity, omega, speed_fluctuation=speed_fluctuation)
