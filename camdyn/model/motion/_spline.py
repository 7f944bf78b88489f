"""Periodic quintic penalized splines: a smooth curve with exact derivatives through noisy periodic data.

The curve is s(x) = sum_j c_j B_j(x) over one period [0, 2 pi) (rad), the B_j periodic quintic B-splines on m
uniform knots; it minimizes ``sum_i (y_i - s(x_i))^2 + lam * integral s'''(x)^2 dx``. The penalty is the
integrated squared third derivative (exact, not a difference approximation), whose minimizer among all
functions is a quintic spline (Reinsch): with about as many knots as data this is the smoothing spline, so
s, s', s'' and s''' are continuous (C4) and the fitted jerk is as small as the data allow. The knots are
uniform whatever the data spacing; between sparse data the penalty makes the curve the least-jerk one.

The smoothing ``lam`` is chosen by restricted maximum likelihood (REML; Wood 2011, J. R. Stat. Soc. B 73,
3-36), with the noise variance profiled out. REML needs only the log-determinant of the normal matrix, which
its banded Cholesky factor gives at O(m) per trial (the periodic band becomes an ordinary band of width 11
once the unknowns are interleaved from both ends), whereas generalized cross-validation needs the trace of
an inverse; REML also undersmooths less often than GCV. Data given to a few decimals carry rounding noise of
at least a twelfth of the last digit squared; where REML sees less noise than that (the data are smoother
than their own rounding), the smoothing is chosen by REML with the noise fixed at that floor instead.

scipy's smoothing splines do not fit: ``make_smoothing_spline`` is cubic (s''' piecewise constant, so the jerk
and the forcing of the follower jump at every data point) and not periodic; FITPACK's periodic splines pick
their knots for a residual given in advance, not a smoothing chosen from the data.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from ..._core.minimize import minimize_bounded
from ..._core.stored import stored_by_arguments
from ._hermite import quintic_eval

_BAND = 5  # a quintic B-spline overlaps 5 neighbours on each side
_LOG_LAM = (-12.0, 10.0)  # log10 of the smoothing relative to trace(G) / trace(P): the search range
_GRID = 12  # REML grid points over that range (two decades apart), then Brent around the best
# Least ratio of the smallest to the largest Cholesky pivot. Below it the data leave some coefficients to a
# penalty too weak to hold them, and round-off leaks into s'': on exact samples of known curves (random and
# gapped spacing, as many knots as points) s'' is good to 1e-5 relative at 1e-4, to 1e-2 at 1e-8.
_MIN_PIVOT = 1e-4
_MC = 24  # seeded noise samples for the acceleration's uncertainty
_SEED = 20240601


@cache
def _pieces() -> np.ndarray:
    """Q[k, p]: the coefficient of u^p of the cardinal quintic B-spline on [k, k + 1], at k + u."""
    q = np.zeros((6, 6))
    for k in range(6):
        for j in range(k + 1):  # N5(x) = sum_j (-1)^j C(6, j) (x - j)_+^5 / 5!
            a = k - j  # (u + a)^5 = sum_p C(5, p) a^(5 - p) u^p
            for p in range(6):
                q[k, p] += (-1) ** j * math.comb(6, j) * math.comb(5, p) * a ** (5 - p) / 120.0
    return q


def _gram2() -> np.ndarray:
    """The Gram stencil (offsets -2 .. 2) of the cardinal quadratic B-splines: N5(3 + l) = 1, 26, 66, 26, 1 over 120."""
    return np.array([1.0, 26.0, 66.0, 26.0, 1.0]) / 120.0


@cache
def penalty_stencil() -> np.ndarray:
    """The circulant stencil (offsets -5 .. 5) of integral (s''')^2 dx in units of h^-5 (h the knot spacing):
    nabla^3' G2 nabla^3, with G2 the Gram matrix of the cardinal quadratic B-splines, N5(3 + l) = 66, 26, 1
    over 120 (the derivative of a B-spline series is the difference series one degree lower)."""
    d3 = np.array([1.0, -3.0, 3.0, -1.0])
    return np.convolve(np.convolve(d3, d3[::-1]), _gram2())


def design(x: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """The periodic B-spline design at x (rad): columns (n, 6) and values (n, 6), B_{i-k}(x) for x in interval i."""
    t = np.mod(x, 2 * math.pi) * (m / (2 * math.pi))
    i = np.minimum(np.floor(t).astype(int), m - 1)
    u = t - i
    vals = (u[:, None] ** np.arange(6)) @ _pieces().T
    return (i[:, None] - np.arange(6)) % m, vals


def piecewise(c: np.ndarray) -> np.ndarray:
    """Per-interval polynomial coefficients (m, 6[, k]) in tau = x - knot_i (rad) of the spline with B-spline
    coefficients c (m[, k]): s(knot_i + tau) = sum_p coef[i, p] tau^p."""
    m = c.shape[0]
    h = 2 * math.pi / m
    shifted = np.stack([np.roll(c, k, axis=0) for k in range(6)], axis=1)  # c_{i-k}
    scale = (1.0 / h ** np.arange(6)).reshape((6,) + (1,) * (c.ndim - 1))
    return np.einsum("ik...,kp->ip...", shifted, _pieces()) * scale


class Residuals:
    """The largest and the RMS of a fit's ``residual`` (data - fit), the data's unit."""

    residual: np.ndarray

    @property
    def max_residual(self) -> float:
        return float(np.max(np.abs(self.residual)))

    @property
    def rms_residual(self) -> float:
        return float(np.sqrt(np.mean(self.residual**2)))


@dataclass(frozen=True)
class SplineFit(Residuals):
    """A fitted periodic quintic spline and how it departs from its data (values in the data's unit)."""

    coef: np.ndarray  # (m, 6): s(knots[i] + tau) = sum_p coef[i, p] tau^p, tau rad, knots uniform over 2 pi
    x: np.ndarray  # the data's angles, rad in [0, 2 pi)
    y: np.ndarray  # the data
    fitted: np.ndarray  # the spline at x
    lam: float  # weight of integral s'''^2 dx against the squared residuals (rad^5)
    sigma: float  # the data's noise: REML's estimate, or the rounding floor where that is larger
    criterion: str  # how the smoothing was chosen: "REML", "REML, rounding floor" or "tolerance"
    # the fit's response to seeded white noise of size sigma, (m, 6, _MC) per-interval coefficients like ``coef``:
    # what the data's noise may have put into the fit (a parametric bootstrap of anything linear in the motion)
    noise_coef: np.ndarray

    @property
    def accel_std(self) -> float:
        """Largest pointwise standard deviation of the fitted s'' (unit/rad^2) under the data's noise."""
        return float(np.max(np.sqrt(np.mean((2.0 * self.noise_coef[:, 2]) ** 2, axis=-1))))

    @property
    def knots(self) -> np.ndarray:
        return np.linspace(0.0, 2 * math.pi, self.coef.shape[0] + 1)

    def __call__(self, x) -> np.ndarray:
        """(s, s', s'', s''') at x (rad), derivatives per rad: shape (4, *x.shape)."""
        return quintic_eval(np, self.knots, self.coef, x)

    @property
    def residual(self) -> np.ndarray:
        return self.y - self.fitted

    @property
    def worst(self) -> int:
        """The index of the largest residual."""
        return int(np.argmax(np.abs(self.residual)))

    def method(self, of: str = "") -> str:
        """How the fit was made, in words; ``of`` says what was fitted against what (" of the radius over the polar
        angle")."""
        return f"periodic quintic smoothing spline{of}, {self.coef.shape[0]} knots, smoothing by {self.criterion}"


class FitResiduals(Residuals):
    """What a fit to a user's data (a lift table's, an outline's) says of itself, for the reports and the JSON: its
    residuals and its data's noise, in the data's unit. Mixed into a result with a ``spline`` (its
    :class:`SplineFit`), ``residual`` (data - fit), the ``unit``, the ``point_count`` and the ``method`` in words."""

    spline: SplineFit
    unit: str
    point_count: int
    method: str

    @property
    def noise(self) -> float:
        """The data's noise: REML's estimate, or the data's rounding where that is larger."""
        return self.spline.sigma

    def residuals_json(self) -> dict:
        """The keys a fit's JSON starts with: how it was made, its points, residuals, noise and their unit."""
        return {
            "method": self.method,
            "points": self.point_count,
            "max_residual": self.max_residual,
            "rms_residual": self.rms_residual,
            "noise": self.noise,
            "unit": self.unit,
        }


class _Problem:
    """The normal equations (G + lam P) c = B'y of one data set, solved for any smoothing.

    G and P are cyclic banded (offsets -5..5 mod m). Interleaving the unknowns from both ends (0, m-1, 1, m-2,
    ...) makes them banded of half-width 11 without fill, so LAPACK's banded Cholesky factors them in O(m)."""

    def __init__(self, x: np.ndarray, y: np.ndarray, m: int) -> None:
        import scipy.sparse as sp  # scipy loads only to fit: a case given by segments never does (0.2 s saved)

        self.y, self.m, self.n = y, m, len(x)
        self.cols, self.vals = design(x, m)
        self.B = sp.csr_matrix(
            (self.vals.ravel(), (np.repeat(np.arange(self.n), 6), self.cols.ravel())), shape=(self.n, m)
        )
        self.rhs = self.B.T @ y
        g = np.zeros((_BAND + 1, m))  # g[d, j] = G[j, j + d mod m]
        for d in range(_BAND + 1):
            for k1 in range(d, 6):
                g[d] += np.bincount(self.cols[:, k1], weights=self.vals[:, k1] * self.vals[:, k1 - d], minlength=m)
        self.p = penalty_stencil()[_BAND:]  # p[d] = P[j, j + d]
        self.scale = g[0].sum() / (m * self.p[0])
        self.order = np.empty(m, dtype=int)
        self.order[0::2], self.order[1::2] = np.arange((m + 1) // 2), np.arange(m - 1, (m + 1) // 2 - 1, -1)
        pos = np.empty(m, dtype=int)
        pos[self.order] = np.arange(m)
        j = np.arange(m)
        self.u = 2 * _BAND + 1
        self.ab_g, self.ab_p = np.zeros((self.u + 1, m)), np.zeros((self.u + 1, m))  # upper banded storage
        for d in range(_BAND + 1):
            a, b = pos[j], pos[(j + d) % m]
            r, c = np.minimum(a, b), np.maximum(a, b)
            self.ab_g[self.u + r - c, c] += g[d]
            self.ab_p[self.u + r - c, c] += self.p[d]

    def roughness(self, c: np.ndarray) -> float:
        """c'Pc (units of h^-5, P the penalty matrix) as (D c)' G2 (D c), D the third difference: a sum of small
        terms, where c'(P c) is a sum of products of coefficients the size of the data with residues of
        cancellation, and carries the data's magnitude times the round-off (1e-3 of the penalty on a cam's 50 mm
        radius, enough to move REML's choice by 0.02 decades and the smoothing's result from one CPU to another)."""
        d3 = c - 3.0 * np.roll(c, -1) + 3.0 * np.roll(c, -2) - np.roll(c, -3)
        g2 = _gram2()
        g2d = g2[2] * d3 + g2[3] * (np.roll(d3, -1) + np.roll(d3, 1)) + g2[4] * (np.roll(d3, -2) + np.roll(d3, 2))
        return float(d3 @ g2d)

    def factor(self, lam: float) -> np.ndarray:
        from scipy.linalg import cholesky_banded

        return cholesky_banded(self.ab_g + lam * self.ab_p, lower=False, check_finite=False)

    def solve_with(self, cb: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        from scipy.linalg import cho_solve_banded

        out = np.empty_like(rhs)
        out[self.order] = cho_solve_banded((cb, False), rhs[self.order], check_finite=False)
        return out

    def solve(self, log_lam: float) -> tuple[np.ndarray, np.ndarray, float, float]:
        """(c, factor, D, log det) at lam = scale * 10^log_lam (units of h^-5); D = RSS + lam c'Pc."""
        lam = self.scale * 10.0**log_lam
        cb = self.factor(lam)
        c = self.solve_with(cb, self.rhs)
        r = self.y - self.B @ c
        d = float(r @ r + lam * self.roughness(c))
        return c, cb, d, 2.0 * float(np.sum(np.log(cb[self.u])))

    def score(self, log_lam: float, sigma: float | None) -> float:
        """-2 log restricted likelihood (up to a constant): sigma^2 profiled out, or fixed at sigma. The
        penalty's null space is the constants (M_p = 1); its pseudo-determinant is a constant."""
        from scipy.linalg import LinAlgError

        try:
            _, _, d, logdet = self.solve(log_lam)
        except LinAlgError:  # not positive definite in floating point: no fit at this smoothing
            return math.inf
        log_lam_e = math.log(self.scale) + log_lam * math.log(10.0)
        if sigma is None:
            return (self.n - 1) * math.log(max(d, 1e-300)) + logdet - (self.m - 1) * log_lam_e
        return d / sigma**2 + logdet - (self.m - 1) * log_lam_e

    def lowest(self) -> float:
        """The least smoothing (log10, relative) whose pivots stay within :data:`_MIN_PIVOT`: exact data ask for
        none, but where they are sparse the curve would then rest on round-off."""
        from scipy.linalg import LinAlgError

        grid = np.linspace(*_LOG_LAM, _GRID)
        for g in grid:
            try:
                pivots = self.factor(self.scale * 10.0**g)[self.u] ** 2
            except LinAlgError:
                continue
            if pivots.min() >= _MIN_PIVOT * pivots.max():
                return float(g)
        return float(grid[-1])

    def choose(self, sigma: float | None, lowest: float) -> float:
        grid = np.linspace(lowest, _LOG_LAM[1], _GRID)
        scores = np.array([self.score(g, sigma) for g in grid])
        i = int(np.argmin(scores))
        step = grid[1] - grid[0]
        lo, hi = max(grid[0], grid[i] - step), min(grid[-1], grid[i] + step)
        # scipy's bounded minimize_scalar, ported (bit-identical): scipy.optimize takes 0.25 s to import
        x, fun, _ = minimize_bounded(lambda g: self.score(g, sigma), float(lo), float(hi), xatol=1e-4)
        return float(x) if fun <= scores[i] else float(grid[i])

    def max_residual(self, log_lam: float) -> float:
        """The largest |residual| at this smoothing."""
        return float(np.max(np.abs(self.y - self.B @ self.solve(log_lam)[0])))


def knot_count(n: int) -> int:
    """Uniform knots about as many as the data, from 1 deg to 0.1 deg apart: a quintic spline on them resolves
    what the data resolve; where the data are uneven, the penalty (kept from vanishing by :data:`_MIN_PIVOT`)
    holds the knots they leave free."""
    return int(np.clip(n, 360, 3600))


@stored_by_arguments  # a check of unchanged data reads the fit an earlier one stored: no scipy, no REML search
def fit_periodic(
    x: np.ndarray, y: np.ndarray, *, tolerance: float | None = None, sigma_floor: float = 0.0, m: int | None = None
) -> SplineFit:
    """The periodic quintic smoothing spline through (x rad, y), its smoothing chosen by REML.

    ``sigma_floor``: the least noise the data can have (their rounding); ``tolerance`` (the data's unit):
    the smoothing is lowered until no residual exceeds it (if none can, the least-smoothed fit is returned:
    compare its ``max_residual``)."""
    x = np.mod(np.asarray(x, dtype=float), 2 * math.pi)
    y = np.asarray(y, dtype=float)
    prob = _Problem(x, y, m or knot_count(len(x)))
    lowest = prob.lowest()
    g = prob.choose(None, lowest)
    c, cb, d, _ = prob.solve(g)
    sigma, criterion = math.sqrt(d / max(prob.n - 1, 1)), "REML"
    if sigma < sigma_floor:
        g = prob.choose(sigma_floor, lowest=g)  # a larger noise only ever asks for more smoothing
        c, cb, d, _ = prob.solve(g)
        sigma, criterion = sigma_floor, "REML, rounding floor"
    if tolerance is not None and prob.max_residual(g) > tolerance:
        lo, hi = lowest, g  # less smoothing follows the data closer: the largest smoothing that meets it
        while hi - lo > 0.01:
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if prob.max_residual(mid) > tolerance else (mid, hi)
        g, criterion = lo, "tolerance"
        c, cb, d, _ = prob.solve(g)
    h = 2 * math.pi / prob.m
    return SplineFit(
        coef=piecewise(c),
        x=x,
        y=y,
        fitted=prob.B @ c,
        lam=prob.scale * 10.0**g * h**5,
        sigma=sigma,
        criterion=criterion,
        noise_coef=piecewise(_noise_fits(prob, cb, sigma)),
    )


def _noise_fits(prob: _Problem, cb, sigma: float) -> np.ndarray:
    """B-spline coefficients (m, _MC) of the same linear smoother applied to seeded white-noise samples of size
    sigma (Monte Carlo: the exact covariance needs the inverse)."""
    eps = np.random.default_rng(_SEED).standard_normal((prob.n, _MC)) * sigma
    return prob.solve_with(cb, np.asarray(prob.B.T @ eps))
