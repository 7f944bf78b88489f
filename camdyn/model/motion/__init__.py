"""Follower motion: the :class:`Motion` interface, the named laws, motion programs (named laws and polynomials
from boundary conditions), tabulated motions and motions fitted to data."""

from ._base import Motion, evaluate
from ._bspline import CLAMPED as BSPLINE_CLAMPED
from ._bspline import basis as bspline_basis
from ._fitted import ACCEL_NOISE_SHARE, FittedMotion, MotionFit, acceleration_noise, fit_motion, fit_warnings
from ._hermite import HermiteMotion
from ._laws import LAWS, law
from ._program import Program, Segment
from ._spline import FitResiduals, SplineFit, fit_periodic

__all__ = [
    "ACCEL_NOISE_SHARE",
    "acceleration_noise",
    "BSPLINE_CLAMPED",
    "FitResiduals",
    "FittedMotion",
    "HermiteMotion",
    "LAWS",
    "Motion",
    "MotionFit",
    "Program",
    "Segment",
    "SplineFit",
    "bspline_basis",
    "evaluate",
    "fit_motion",
    "fit_periodic",
    "fit_warnings",
    "law",
]
