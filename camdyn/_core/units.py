"""Units, grids, defaults and the few conversions every layer shares: each lives here and nowhere else.

Case files speak the designer's units (mm, deg, rpm, N/mm); the models work in SI (m, rad, rad/s, N/m), or in
the rotational equivalent for an oscillating arm (rad, N*m/rad, N*m). What differs between the two follower kinds
(their units, their conversions, their output names) is :mod:`camdyn._core.kinds`, built on the factors here.
Plain Python and numpy only: the schema imports this module, and it must not pull in JAX.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, TypeVar, overload

if TYPE_CHECKING:  # annotations only: importing units (the CLI's --help does) must not load JAX
    import jax
    import numpy as np
    from jax.typing import ArrayLike

# a float, a numpy or a JAX array in: the same kind out (unit conversions work elementwise on any of them)
Num = TypeVar("Num", "float", "np.ndarray", "jax.Array")

TWO_PI = 2.0 * math.pi
RPM = TWO_PI / 60.0  # rad/s per rpm
M_PER_MM = 1e-3  # a translating follower's motion is in mm, its dynamics in m
MM_PER_INCH = 25.4  # profile --units in: files for shops that work in inches (the inch is defined as 25.4 mm)
N_PER_M_PER_N_PER_MM = 1e3  # spring rates: N/mm -> N/m

# angle grids
THETA_GRID = 3600  # angles per revolution of the dynamics, the checks and the tables (0.1 deg)
FFT_GRID = 4096  # angles per revolution of the frequency-domain steady state

# A velocity or acceleration jump at a segment boundary smaller than this fraction of the derivative's largest
# magnitude over the revolution is rounding (an optimizer's spline ends at 1e-6 mm/rad^2), not a jump to flag.
JUMP_RTOL = 1e-4
# A check whose value is within this fraction of its limit is "at limit": one rounding from the other verdict.
AT_LIMIT_RTOL = 0.02

DEFAULT_PROFILE_TOLERANCE_MM = 0.01  # chord tolerance of `camdyn profile`

# defaults of the [limits] table
DEFAULT_SPEED_MARGIN = 1.25
SPEED_MARGIN_RANGE = (1, 100)  # [limits] speed_margin and size --margin: below 1 the follower jumps at its speed
JUMP_SEARCH_FACTOR = 4.0  # every dynamic jump-speed search reaches this many times the top speed a verdict needs
DEFAULT_MIN_CONTACT_FORCE_N = 0.0
DEFAULT_MAX_PRESSURE_ANGLE_DEG = {"translating": 30.0, "oscillating": 35.0}
DEFAULT_MIN_CURVATURE_RATIO = 1.5
DEFAULT_MAX_TRAIN_DEFLECTION = 0.1  # of the lift: a compliant train compressed by more no longer drives the follower
DEFAULT_MAX_PATH_ERROR_MM = 1e-3  # a path case: the linkage driven by the cam may miss its path by this (mm)
DEFAULT_MIN_TRANSMISSION_ANGLE_DEG = 30.0  # a path case's driven dyads: under this the linkage binds
DEFAULT_TRAIN_DAMPING_RATIO = 0.05
# form-closed cams: the largest speed at which a follower crossing its backlash may meet the other flank, m/s (a
# soft landing; the noise and the flank wear of a groove cam grow with it)
DEFAULT_MAX_IMPACT_VELOCITY_M_PER_S = 0.1
# [valvetrain] defaults
# A steel valve on a hardened seat keeps some rebound; 0.3 is the middle of the 0.2-0.4 usually assumed.
DEFAULT_SEAT_RESTITUTION = 0.3
# Lash take-up ramps run at 0.01-0.02 mm per cam degree at the valve: at 3000 cam rpm 0.015 mm/deg seats the valve
# at 0.27 m/s, inside the seating-velocity limit below.
DEFAULT_RAMP_VELOCITY_MM_PER_DEG = 0.015
MAX_ROCKER_RATIO = 5.0
# A train that lets the valve lift less than this fraction of the cam's stroke at the valve, at rest, is a unit slip
# (a real pushrod and rocker lose tenths of a millimetre of ten to their compliance), not a valvetrain.
MIN_STATIC_VALVE_LIFT = 0.5
# [limits] max_seating_velocity default, m/s: the valve's speed on landing; 0.5 m/s is the usual ceiling at rated
# speed for a steel valve on a hardened seat (0.3 m/s where seat wear matters most).
DEFAULT_MAX_SEATING_VELOCITY = 0.5
# A re-lift of the valve after it seats below this (mm) is the rigid seat's restitution micro-bounce, not a bounce.
VALVE_BOUNCE_TOLERANCE_MM = 0.01
# The valve is open where its lift exceeds this (mm): the opening and closing angles of a cam card.
VALVE_TIMING_LIFT_MM = 0.05
# Physical bounds: a number beyond them is a typo or a unit slip, not a cam camdyn can judge (a 10 m cam, a
# follower lighter than a milligram), and it would only send the solvers into the weeds.
MAX_LENGTH_MM = 1e4  # 10 m
MAX_PATH_POINTS = 10_000  # precision points of a [path]: the synthesis fits a spline through every one
MAX_SPEED_RPM = 1e5
MASS_RANGE_KG = (1e-6, 1e4)
INERTIA_RANGE_KG_M2 = (1e-12, 1e4)
MAX_RATE_N_PER_MM = 1e7  # a spring rate; a follower train may be 10x stiffer
MAX_TORSION_RATE_N_M_PER_RAD = 1e7
MAX_FORCE_N = 1e7
MAX_TORQUE_N_M = 1e6
MAX_DAMPING = 1e7  # N*s/m or N*m*s/rad
MAX_DAMPING_RATIO = 100.0

DEFAULT_SPEED_FLUCTUATION = 0.05  # [drive]: coefficient of speed fluctuation the flywheel is sized for

CUSP_MM = 1e-6  # a flat-faced contour radius of curvature under 1 nm is a cusp: that check's limit


@overload
def damping_from_ratio(ratio: float, stiffness: float, mass: float) -> float: ...
@overload
def damping_from_ratio(ratio: ArrayLike, stiffness: ArrayLike, mass: ArrayLike) -> ArrayLike: ...
def damping_from_ratio(ratio: ArrayLike, stiffness: ArrayLike, mass: ArrayLike) -> ArrayLike:
    """Viscous damping c = 2 zeta sqrt(k m) (N*s/m, or N*m*s/rad): floats, numpy or JAX arrays."""
    return 2.0 * ratio * (stiffness * mass) ** 0.5


def newton_per_torque(lever_arm_mm: Num) -> Num:
    """The factor that turns an arm's torque (N*m) into its contact force (N) through the lever arm (mm)."""
    return 1000.0 / lever_arm_mm


def torsion_rate_at_arm(torsion_rate: Num, lever_arm_mm: Num) -> Num:
    """The rate (N/mm) of a linear spring acting at ``lever_arm_mm`` from the pivot that gives an arm the
    torsion rate (N*m/rad): k = k_t / r^2, small swings."""
    return torsion_rate * newton_per_torque(lever_arm_mm) ** 2 * M_PER_MM


# [tolerances]: the units an absolute tolerance may carry, per key, as factors to the key's case-file unit
# (translating follower, oscillating arm); a bare number is in the case-file unit (the first one listed)
_RATE_UNITS = ({"N/mm": 1.0, "N/m": 1e-3, "kN/m": 1.0}, {"N*m/rad": 1.0})
TOLERANCE_UNITS: dict[str, tuple[dict[str, float], dict[str, float]]] = {
    "spring_rate": _RATE_UNITS,
    "preload": ({"N": 1.0, "kN": 1e3}, {"N*m": 1.0}),
    "mass": ({"kg": 1.0, "g": 1e-3}, {"kg*m^2": 1.0}),
    "train_stiffness": _RATE_UNITS,
    "speed": ({"rpm": 1.0}, {"rpm": 1.0}),
    "profile_error": ({"mm": 1.0, "um": 1e-3}, {"rad": 1.0, "deg": math.pi / 180.0}),
    # [valvetrain] cases only (a valvetrain's follower translates: its second entry is never read)
    "lash": ({"mm": 1.0, "um": 1e-3}, {"mm": 1.0}),
    "cam_side_mass": ({"kg": 1.0, "g": 1e-3}, {"kg": 1.0}),
    "valve_mass": ({"kg": 1.0, "g": 1e-3}, {"kg": 1.0}),
    "valvetrain_stiffness": _RATE_UNITS,
    "backlash": ({"mm": 1.0, "um": 1e-3}, {"mm": 1.0, "um": 1e-3}),  # a groove's, at the roller either way
}
VALVETRAIN_TOLERANCE_KEYS = ("lash", "cam_side_mass", "valve_mass", "valvetrain_stiffness")
NORMAL_TOLERANCE_SIGMAS = 3.0  # a normal tolerance is this many standard deviations
PROFILE_ERROR_HARMONICS = 8  # a profile error is a random sum of harmonics 1..this of the revolution


def tolerance_unit(key: str, rotary: bool) -> str:
    """The case-file unit of tolerance ``key`` (a bare number is in it)."""
    return next(iter(TOLERANCE_UNITS[key][int(rotary)]))


def tolerance_to_case_unit(key: str, value: float, unit: str, rotary: bool) -> float:
    """An absolute tolerance ``value unit`` in the key's case-file unit; ValueError naming the units it takes."""
    units = TOLERANCE_UNITS[key][int(rotary)]
    if unit not in units:
        raise ValueError(f"unit {unit!r} not known here: use a percentage or one of {', '.join(units)}")
    return value * units[unit]
