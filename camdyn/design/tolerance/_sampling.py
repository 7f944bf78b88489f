"""Random built cams: every sample drawn up front from ``numpy.random.default_rng(seed)``, in one fixed order, so
the samples do not depend on how they are later cut into chunks or shared between devices and processes.

Per key, the nominal value (case-file unit) and its spread: ``normal``: sigma = tolerance / 3;
``uniform``: +- tolerance. A relative tolerance is a fraction of the nominal value. A profile error of RMS r is
sum over h = 1..K of a_h cos(h theta) + b_h sin(h theta) with a_h, b_h of variance r^2 / K (normal, or uniform
with that variance), so its mean square over a revolution is r^2 on average.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._core.units import NORMAL_TOLERANCE_SIGMAS, PROFILE_ERROR_HARMONICS
from ...model.case import Case
from ...schema import Tolerance, require_tolerances, resolve_tolerances

SCALAR_KEYS = ("spring_rate", "preload", "mass", "train_stiffness", "speed")


@dataclass(frozen=True)
class Spread:
    """One tolerance as a distribution about the nominal value (case-file unit)."""

    key: str
    nominal: float
    half_width: float  # tolerance in the case-file unit (the RMS for profile_error)
    distribution: str

    @property
    def sigma(self) -> float:
        """Standard deviation of one coordinate (a scalar key; a harmonic coefficient of profile_error)."""
        if self.key == "profile_error":
            return self.half_width / math.sqrt(PROFILE_ERROR_HARMONICS)
        return self.half_width / (NORMAL_TOLERANCE_SIGMAS if self.distribution == "normal" else math.sqrt(3.0))

    def draw(self, rng: np.random.Generator, shape: int | tuple[int, ...]) -> np.ndarray:
        """Deviations from the nominal value."""
        if self.distribution == "normal":
            return self.sigma * rng.standard_normal(shape)
        return rng.uniform(-math.sqrt(3.0) * self.sigma, math.sqrt(3.0) * self.sigma, shape)


def case_tolerances(case: Case) -> tuple[Tolerance, ...]:
    """The case's ``[tolerances]``, resolved; an InputError where it gives none: every built cam would be the case
    itself."""
    require_tolerances(case.spec.tolerances, kind=case.kind)
    assert case.spec.tolerances is not None  # required above
    return resolve_tolerances(case.spec.tolerances, kind=case.kind)


def spreads(tolerances: tuple[Tolerance, ...], nominal: dict[str, float]) -> dict[str, Spread]:
    """The :class:`Spread` of each given tolerance; ``nominal`` per key in the case-file unit (0 for profile_error)."""
    return {
        t.key: Spread(t.key, nominal[t.key], t.value * abs(nominal[t.key]) if t.relative else t.value, t.distribution)
        for t in tolerances
    }


def draw_samples(spread: dict[str, Spread], nominal: dict[str, float], n: int, seed: int) -> dict[str, np.ndarray]:
    """``n`` samples of every key (case-file units) and ``profile_coeffs`` (n, 2K: cos then sin, motion unit).

    The generator draws key by key in :data:`SCALAR_KEYS` order, then the profile coefficients, whatever is given;
    a key without a tolerance stays at its nominal value."""
    rng = np.random.default_rng(seed)
    out = {}
    for key in SCALAR_KEYS:
        out[key] = nominal[key] + (spread[key].draw(rng, n) if key in spread else np.zeros(n))
    k2 = 2 * PROFILE_ERROR_HARMONICS
    out["profile_coeffs"] = (
        spread["profile_error"].draw(rng, (n, k2)) if "profile_error" in spread else np.zeros((n, k2))
    )
    if "backlash" in nominal:  # a groove cam's, drawn last: the other keys' samples are a spring cam's
        out["backlash"] = nominal["backlash"] + (spread["backlash"].draw(rng, n) if "backlash" in spread else 0.0)
    return out
