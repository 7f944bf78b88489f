"""The ``[valvetrain]`` table: the follower drives a valve through a rocker (or directly), with lash, two masses,
the train between them and the valve's seat.

With it, ``[dynamics]`` keeps the speed, the valve spring (``spring_rate``, ``preload``, at the valve, and its
damping) and the cam contact (``train_stiffness``, ``train_damping_ratio``, ``restitution``), and refuses ``mass``:
``cam_side_mass`` and ``valve_mass`` replace it.
"""

from __future__ import annotations

from pydantic import Field

from .._core.units import (
    DEFAULT_RAMP_VELOCITY_MM_PER_DEG,
    DEFAULT_SEAT_RESTITUTION,
    DEFAULT_TRAIN_DAMPING_RATIO,
    MASS_RANGE_KG,
    MAX_DAMPING_RATIO,
    MAX_FORCE_N,
    MAX_RATE_N_PER_MM,
    MAX_ROCKER_RATIO,
)
from ._base import Real, Table
from .dynamics import LINEAR_KEYS, ROTARY_KEYS, DynamicsSpec


class RockerSpec(Table):
    """The ``[valvetrain.rocker]`` table: a rocker (or a finger follower) turning about a fixed pivot, whose ratio
    follows from its geometry and varies with lift. Each contact is a point of the rocker (the centre of a pushrod's
    ball, a roller's axle, a radiused pad's centre of curvature) pressing on a flat face square to its line of motion
    (the tappet's cup, the valve's tip): its lift is the point's travel along that line, whatever the pad's radius."""

    cam_arm: Real = Field(
        gt=0,
        le=1000.0,
        description=(
            "pivot to the cam side's contact point (the pushrod's ball centre, a finger follower's roller axle or "
            "pad centre), mm"
        ),
    )
    valve_arm: Real = Field(
        gt=0,
        le=1000.0,
        description="pivot to the valve side's contact point (the centre of curvature of the pad on the valve tip), mm",
    )
    cam_arm_angle: Real = Field(
        default=0.0,
        gt=-80.0,
        lt=80.0,
        description=(
            "the cam arm's angle at zero lift, deg, from the square to the follower's line of motion, positive "
            "towards the follower's lift (0: square at zero lift; -a/2: square at half of a lift of a)"
        ),
    )
    valve_arm_angle: Real = Field(
        default=0.0,
        gt=-80.0,
        lt=80.0,
        description=(
            "the valve arm's angle at zero lift, deg, from the square to the valve's axis, positive towards the "
            "valve's opening; equal to cam_arm_angle for a straight rocker (a constant ratio valve_arm / cam_arm)"
        ),
    )


class ValvetrainSpec(Table):
    """The ``[valvetrain]`` table: a rocker of constant ratio (1: direct acting) or of given geometry
    (``[valvetrain.rocker]``), lash at the valve, the cam side and the valve as two masses joined by the train, the
    valve on a rigid seat."""

    ratio: Real = Field(
        default=1.0,
        gt=0,
        le=MAX_ROCKER_RATIO,
        description=(
            "valve lift per unit of follower lift (rocker ratio), constant; 1: direct acting (at most 5); omit with "
            "[valvetrain.rocker], whose geometry gives the ratio"
        ),
    )
    rocker: RockerSpec | None = Field(
        default=None,
        description="the rocker's geometry (its arms and their angles): a ratio varying with lift, instead of ratio",
    )
    lash: Real = Field(
        default=0.0,
        ge=0,
        le=5.0,
        description="valve clearance at the valve, mm: the follower's ramps take it up before the valve moves",
    )
    cam_side_mass: Real = Field(
        ge=MASS_RANGE_KG[0],
        le=MASS_RANGE_KG[1],
        description="mass moving with the follower: tappet, pushrod, the rocker reduced to the cam side, kg",
    )
    valve_mass: Real = Field(
        ge=MASS_RANGE_KG[0],
        le=MASS_RANGE_KG[1],
        description=(
            "mass moving with the valve: valve, retainer, keepers, and a third of the valve spring's mass unless a "
            "[spring] part is given (camdyn then adds its designed spring's third), kg"
        ),
    )
    stiffness: Real | None = Field(
        default=None,
        gt=0,
        le=10 * MAX_RATE_N_PER_MM,
        description=(
            "the train between the two masses (pushrod, rocker, valve stem) at the valve, N/mm; omit for a rigid "
            "train (the lash then closes with a plastic impact)"
        ),
    )
    damping_ratio: Real = Field(
        default=DEFAULT_TRAIN_DAMPING_RATIO,
        ge=0,
        le=MAX_DAMPING_RATIO,
        description="of the train: c = 2 zeta sqrt(stiffness * valve_mass)",
    )
    seat_restitution: Real = Field(
        default=DEFAULT_SEAT_RESTITUTION,
        ge=0,
        le=1,
        description="coefficient of restitution of the valve on its seat (a rigid seat), 0..1",
    )
    ramp_velocity: Real = Field(
        default=DEFAULT_RAMP_VELOCITY_MM_PER_DEG,
        gt=0,
        le=1.0,
        description=(
            "velocity of the opening and closing ramps that take up the lash, mm per cam degree at the valve "
            "(for a motion given at the valve)"
        ),
    )
    tappet_force: Real = Field(
        default=0.0,
        ge=0,
        le=MAX_FORCE_N,
        description=(
            "constant force holding the follower on the cam while the lash is open (a tappet spring, a hydraulic "
            "lifter's plunger spring), N; 0: nothing holds it there"
        ),
    )


def check_valvetrain_keys(v: ValvetrainSpec, d: DynamicsSpec, *, translating: bool) -> None:
    """Raise ``ValueError("<key>: message")`` unless ``[dynamics]`` fits a valvetrain: a translating follower,
    the valve spring's rate and preload given, no ``mass`` (the two masses replace it), no rotational keys and no
    external force (``tappet_force`` holds the follower on the cam)."""
    if v.rocker is not None and "ratio" in v.model_fields_set:
        raise ValueError("valvetrain.ratio: give either ratio or [valvetrain.rocker] (its geometry gives it), not both")
    if not translating:
        raise ValueError("valvetrain: the follower must be translating (a tappet or a lifter); the rocker is the ratio")
    if d.mass is not None:
        raise ValueError(
            "dynamics.mass: a [valvetrain] case gives valvetrain.cam_side_mass and valvetrain.valve_mass instead"
        )
    if d.external_force != 0.0:
        raise ValueError("dynamics.external_force: with [valvetrain], valvetrain.tappet_force holds the follower")
    for key in ROTARY_KEYS:
        if getattr(d, key) not in (None, 0.0):
            raise ValueError(f"dynamics.{key}: a valvetrain uses the linear keys ({', '.join(LINEAR_KEYS[1:3])})")
    for key in ("spring_rate", "preload"):
        if getattr(d, key) is None:
            raise ValueError(f"dynamics.{key}: required key is missing (the valve spring, at the valve)")
