"""Motions fitted to data: a lift table, or the exact-contact motion of a measured contour.

The fit is a periodic quintic smoothing spline (:mod:`._spline`), stored as per-interval polynomial
coefficients in HermiteMotion's layout and evaluated by one search and one gather however many knots it has.
"""

from __future__ import annotations

from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from ..._core.jit import device_array
from ..._core.kinds import kind_of_lift
from ..._core.units import TWO_PI
from ._base import Motion
from ._hermite import QuinticTable, quintic_eval
from ._spline import FitResiduals, SplineFit, fit_periodic

# The fitted s'' is called meaningless when the noise alone moves it by more than a tenth of its peak (two
# standard deviations, 95 %): the jump speed goes as |s''|^(-1/2), so it would be uncertain by over 5 %, more
# than a design's speed margin can tell apart.
ACCEL_NOISE_SHARE = 0.10


class FittedMotion(Motion):
    """A smooth periodic motion fitted to data: a quintic spline (C4: s''' continuous, so no breaks) as
    per-interval polynomial coefficients on uniform knots."""

    knots: jax.Array  # (m + 1,) rad, 0 .. 2 pi
    coef: jax.Array  # (m, 6): s = sum coef[i, k] t^k, t = theta - knots[i] (rad), the motion's unit
    unit: str = eqx.field(static=True)
    breaks_deg: tuple[float, ...] = eqx.field(static=True)  # none: a quintic spline is C4
    flat_deg: tuple[tuple[float, float], ...] = eqx.field(static=True, default=())  # the data's equal runs

    @property
    def dwells_deg(self) -> tuple[tuple[float, float], ...]:
        """Where the data dwell: runs of rows of one value as written (:func:`flat_runs`: a lift table's base
        circle of 0.000 mm); a noisy measurement has none."""
        return self.flat_deg

    def jit_form(self) -> QuinticTable:
        return QuinticTable.padded(self.knots, self.coef, self.breaks_deg, self.unit)

    def __call__(self, theta: ArrayLike) -> jax.Array:
        return quintic_eval(jnp, self.knots, self.coef, theta)

    def host(self, theta: ArrayLike) -> np.ndarray:
        return quintic_eval(np, np.asarray(self.knots), np.asarray(self.coef), theta)


@dataclass(frozen=True)
class MotionFit(FitResiduals):
    """A fitted motion's data and how far the fit departs from it, in the data's unit (mm, or deg of swing).

    ``theta_deg`` and ``data`` are the samples the spline was fitted to (a lift table's rows, or the exact-contact
    motion of a contour), ``fitted`` the spline there; ``spline`` holds the smoothing and the noise estimate."""

    source: str  # "table" or "contour"
    file: str  # as the case file names it
    unit: str  # "mm" or "deg"
    theta_deg: np.ndarray
    data: np.ndarray
    spline: SplineFit
    tolerance: float | None = None
    repeats: int = 0  # rows dropped from the file for exactly repeating the one before them
    follower_per_data: float = 1.0  # the data times this is the follower's lift (1 / ratio for a valve's table)
    # a valve's table through a rocker: the spline is fitted to the data carried to the follower (``follower_data``,
    # through the inverse of the rocker's lift), and ``data_fitted`` is that fit carried back to the valve
    follower_data: np.ndarray | None = None
    data_fitted: np.ndarray | None = None

    @property
    def fitted(self) -> np.ndarray:
        """The fit at the data's angles, the data's unit."""
        return self.spline.fitted if self.data_fitted is None else self.data_fitted

    @property
    def residual(self) -> np.ndarray:
        """data - fit, the data's unit."""
        return self.data - self.fitted

    @property
    def max_residual_at_deg(self) -> float:
        """The cam angle of the largest residual, deg in [0, 360)."""
        return float(self.theta_deg[int(np.argmax(np.abs(self.residual)))] % 360.0)

    @property
    def point_count(self) -> int:
        return int(len(self.data))

    @property
    def method(self) -> str:
        """How the fit was made, in words."""
        return self.spline.method(
            "" if self.follower_data is None else " to the follower's lift (the table's through the rocker)"
        )

    @property
    def data_at_follower(self) -> np.ndarray:
        """The data as the follower's lift (a valve's table: its ramps added, through the rocker)."""
        return self.data * self.follower_per_data if self.follower_data is None else self.follower_data

    def json(self) -> dict:
        """``check --json``'s ``motion.fit``: the method, the residuals and the noise (the data's unit)."""
        return self.residuals_json() | {
            "max_residual_at_deg": self.max_residual_at_deg,
            "tolerance": self.tolerance,
            "smoothing": self.spline.lam,
            "acceleration_std": self.spline.accel_std,
            "repeats_dropped": self.repeats,
        }


DWELL_ROWS, DWELL_DEG = 3, 5.0  # a table's dwell: at least 3 rows of one value over at least 5 deg


def flat_runs(theta_deg: ArrayLike, data: ArrayLike) -> tuple[tuple[float, float], ...]:
    """(first, last) cam angle (deg, 0-360) of every run of at least :data:`DWELL_ROWS` consecutive rows (by angle,
    round the revolution) over at least :data:`DWELL_DEG` whose values are equal as written (a few equal rows of
    noisy data are chance); a run through 360 deg is split there."""
    theta = np.mod(np.asarray(theta_deg, dtype=float), 360.0)
    order = np.argsort(theta, kind="stable")
    theta, values = theta[order], np.asarray(data, dtype=float)[order]
    n = theta.size
    same = values == np.roll(values, -1)  # row i equals row i + 1 (the last: the first, round the revolution)
    if n < DWELL_ROWS or same.all():
        return ((0.0, 360.0),) if n >= DWELL_ROWS else ()
    ends = np.flatnonzero(~same)  # the last row of each run
    runs: list[tuple[float, float]] = []
    for before, last in zip(np.roll(ends, 1), ends, strict=True):
        first = (before + 1) % n
        a, b = float(theta[first]), float(theta[last])
        if (last - first) % n + 1 >= DWELL_ROWS and (b - a) % 360.0 >= DWELL_DEG:
            runs += [(a, b)] if b > a else [(a, 360.0), (0.0, b)]
    return tuple(sorted(runs))


def fit_motion(
    theta_deg: ArrayLike,
    data: ArrayLike,
    *,
    unit: str,
    source: str,
    file: str,
    tolerance: float | None = None,
    rounding: float = 0.0,
    repeats: int = 0,
) -> tuple[FittedMotion, MotionFit]:
    """Fit ``data`` (mm, or deg of swing when ``unit`` is "deg") at cam angles ``theta_deg``: the
    :class:`FittedMotion` (mm, or rad) and its :class:`MotionFit`. ``rounding`` is the data's least noise
    (their written digits); ``tolerance`` bounds the largest residual where the caller checks the result;
    ``repeats`` counts the rows the reader dropped as exact repeats."""
    theta_deg = np.asarray(theta_deg, dtype=float)
    data = np.asarray(data, dtype=float)
    spline = fit_periodic(np.deg2rad(theta_deg), data, tolerance=tolerance, sigma_floor=rounding)
    kind = kind_of_lift(unit)
    m = spline.coef.shape[0]
    motion = FittedMotion(
        knots=device_array(np.linspace(0.0, TWO_PI, m + 1)),
        coef=device_array(kind.lift_to_motion(spline.coef)),
        unit=kind.motion_unit,
        breaks_deg=(),
        flat_deg=flat_runs(theta_deg, data),
    )
    return motion, MotionFit(source, file, unit, theta_deg, data, spline, tolerance, repeats)


def acceleration_noise(spline: SplineFit) -> tuple[float, str, float] | None:
    """Where a fit's noise leaves its second derivative meaningless (a 95 % band over :data:`ACCEL_NOISE_SHARE` of
    its peak): the band (the data's unit per rad^2), how it compares with the peak in words, and the peak; None
    where it does not."""
    peak = float(np.max(np.abs(2.0 * spline.coef[:, 2])))
    band = 2.0 * spline.accel_std
    if band <= ACCEL_NOISE_SHARE * peak:
        return None
    share = f"{100 * band / peak:.0f} % of its peak" if band < 1e3 * peak else "over 1000 times its peak"
    return band, share, peak


def fit_warnings(fit: MotionFit) -> list[str]:
    """What a designer must know about a fit: noise that makes the acceleration meaningless
    (:data:`ACCEL_NOISE_SHARE`), and a tolerance that made the fit follow the noise."""
    sp, u = fit.spline, fit.unit
    out = []
    if (noisy := acceleration_noise(sp)) is not None:
        band, share, peak = noisy
        out.append(
            f"{fit.file}: the data's noise (about {sp.sigma:.2g} {u}) leaves the fitted acceleration uncertain by "
            f"+-{band:.3g} {u}/rad^2 (95 %), {share} {peak:.4g} {u}/rad^2: "
            "jump speeds and forces rest on the smoothing, not on the data; measure the lift finer or with less noise"
        )
    if sp.criterion == "tolerance":
        out.append(
            f"{fit.file}: tolerance = {fit.tolerance:g} {u} asks for less smoothing than the data's noise (about "
            f"{sp.sigma:.2g} {u}) does: the fit follows that noise and its acceleration is wavier than the motion"
        )
    return out
