"""Polynomial segments from boundary conditions (Norton's method, as DYNACAM builds them).

On the normalized segment x = (theta - start) / beta in [0, 1] the polynomial y(x) = sum_k b_k x^k meets every
condition exactly: y(0) = 0 and y(1) = lift; y'(0), y'(1), y''(0), y''(1) (given per rad^n of cam angle, so
y^(n) = beta^n * value), the jerks where given, and y(x_p) = lift_p at the interior points. Those are
Hermite conditions (each end's derivatives consecutive from order 0, points distinct), so the square system
is never singular; its degree is the number of conditions less one. Without options it is the 3-4-5
polynomial, with zero end jerks the 4-5-6-7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...schema.motion import PolynomialSegmentSpec

# Condition number of the system (monomials on [0, 1]) beyond which fewer than 6 of float64's 16 digits remain
# in the coefficients, and so in s'' (a sum of large, cancelling terms): 3-4-5 has 8e2, 4-5-6-7 5e4, a degree 10
# (three points and the jerks) 2e8, a degree 12 6e16.
ILL_CONDITIONED = 1e10


@dataclass(frozen=True)
class BoundaryPolynomial:
    """The solved polynomial of one segment, in the unit its lifts were given in (mm, or deg of swing)."""

    coef: tuple[float, ...]  # b_k of y(x) = sum b_k x^k, x in [0, 1]
    low: float  # the range the conditions span: least and greatest of 0, lift and the points' lifts
    high: float
    condition: float  # 2-norm condition number of the system


def _row(x: float, order: int, n: int) -> np.ndarray:
    """d^order/dx^order of (1, x, ..., x^(n-1)) at x."""
    k = np.arange(n)
    fall = np.array([math.perm(int(i), order) for i in k], dtype=float)  # k! / (k - order)!
    with np.errstate(divide="ignore", invalid="ignore"):
        powers = np.where(k >= order, float(x) ** np.maximum(k - order, 0), 0.0)
    return fall * powers


def solve_polynomial(seg: PolynomialSegmentSpec, start_deg: float) -> BoundaryPolynomial:
    """The polynomial of least degree that meets the segment's conditions (lift units of the case file)."""
    beta = math.radians(seg.end - start_deg)
    n = seg.condition_count
    rows, rhs = [], []

    def cond(x: float, order: int, value: float) -> None:
        rows.append(_row(x, order, n))
        rhs.append(value)

    cond(0.0, 0, 0.0)
    cond(0.0, 1, seg.start_velocity * beta)
    cond(0.0, 2, seg.start_acceleration * beta**2)
    if seg.start_jerk is not None:
        cond(0.0, 3, seg.start_jerk * beta**3)
    cond(1.0, 0, seg.lift)
    cond(1.0, 1, seg.end_velocity * beta)
    cond(1.0, 2, seg.end_acceleration * beta**2)
    if seg.end_jerk is not None:
        cond(1.0, 3, seg.end_jerk * beta**3)
    for theta, lift in seg.points:
        cond((theta - start_deg) / (seg.end - start_deg), 0, lift)
    a = np.array(rows)
    b = np.linalg.solve(a, np.array(rhs))
    targets = [0.0, seg.lift] + [lift for _, lift in seg.points]
    return BoundaryPolynomial(tuple(float(v) for v in b), min(targets), max(targets), float(np.linalg.cond(a)))


def polynomial_warnings(
    poly: BoundaryPolynomial, where: str, start_deg: float, end_deg: float, lift_unit: str
) -> list[str]:
    """An overshoot (the lift leaves the range its conditions span) and an ill-conditioned system, as warnings
    that say by how much and where (angles deg, lifts from the segment's start in ``lift_unit``)."""
    out = []
    p = np.polynomial.Polynomial(poly.coef)
    crit = p.deriv().roots()
    x = np.concatenate([[0.0, 1.0], crit.real[(np.abs(crit.imag) < 1e-9) & (crit.real > 0.0) & (crit.real < 1.0)]])
    y = p(x)
    span = max(poly.high - poly.low, 1e-12)
    over, under = y.max() - poly.high, poly.low - y.min()
    if max(over, under) > 1e-6 * span:
        i = int(np.argmax(y)) if over >= under else int(np.argmin(y))
        at = start_deg + x[i] * (end_deg - start_deg)
        by, side = (over, "above") if over >= under else (under, "below")
        out.append(
            f"{where}: the polynomial (degree {len(poly.coef) - 1}) overshoots its range {poly.low:g} to "
            f"{poly.high:g} {lift_unit}: {by:.4g} {lift_unit} {side} it at {at:.4g} deg (lift {y[i]:.4g} {lift_unit} "
            "from the segment's start)"
        )
    if poly.condition > ILL_CONDITIONED:
        out.append(
            f"{where}: the polynomial (degree {len(poly.coef) - 1}) is ill-conditioned (condition number "
            f"{poly.condition:.2g}): its coefficients keep fewer than 6 digits; use fewer points or conditions, or "
            "split the segment"
        )
    return out
