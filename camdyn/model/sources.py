"""Motions from a case's own data: a lift table (``[motion] table``) or a cam outline (``[follower] contour``).

File names are relative to the case file (to the working folder for a case built from a dict). Each builder
returns the fitted motion, its :class:`~camdyn.model.motion.MotionFit` and the warnings a designer must read.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import equinox as eqx
import numpy as np

from .._core.errors import InputError
from .._core.files import data_file_path
from .._core.units import M_PER_MM
from ..schema import CaseSpec, FollowerSpec
from .datafiles import Samples, read_contour, read_lift_table
from .geometry import ContourFit, contact_motion
from .motion import FittedMotion, MotionFit, fit_motion, fit_warnings
from .valvetrain import (
    Rocker,
    lift_with_ramps,
    ramp_join_warnings,
    rocker_follower_lift,
    rocker_model,
    rocker_valve_reach,
)

ZERO_SHARE = 0.01  # a table may dip below zero lift by this share of its range (noise in a dwell), no more
# a table whose lift spans less than this (mm; deg of swing) is likely in metres (radians): no cam lifts less
SLIP_RANGE = {"mm": (0.1, "metres", 1000.0), "deg": (1.0, "radians", 180.0 / np.pi)}


def _lift_level(table: Samples, lift: np.ndarray, unit: str, column: str) -> list[str]:
    """Lift is measured from the base circle: a dip below zero beyond noise is an error, a table whose least
    lift is well above zero gets a warning."""
    span = float(np.ptp(lift))
    i = int(np.argmin(lift))
    if lift[i] < -ZERO_SHARE * span:
        raise InputError(
            table.where(i),
            f"{column} = {lift[i]:g} is below zero by more than {100 * ZERO_SHARE:g} % of the table's {span:g} {unit} "
            "range: lift is measured from the base circle (a slight dip in a dwell is taken as noise)",
        )
    if lift[i] > ZERO_SHARE * span:
        return [
            f"{table.shown}: the least {column} is {lift[i]:g} {unit}, not 0: camdyn measures lift from the base "
            "circle (base_radius is the least contour radius)"
        ]
    return []


def _unit_slip(table: Samples, lift: np.ndarray, unit: str, column: str) -> list[str]:
    """A warning where the table's lift is so small that its column's unit is almost surely not the one used."""
    least, other, factor = SLIP_RANGE[unit]
    span = float(np.ptp(lift))
    if span >= least:
        return []
    return [
        f"{table.shown}: {column} spans only {span:.3g} {unit}: was it given in {other}? "
        f"{span:.3g} {other} is {span * factor:.4g} {unit}"
    ]


def _within_tolerance(fit: MotionFit, table: Samples, tolerance: float | None) -> None:
    if tolerance is None or fit.max_residual <= tolerance * (1.0 + 1e-9):
        return
    i = int(np.argmax(np.abs(fit.residual)))
    raise InputError(
        "motion.tolerance",
        f"no smooth fit comes within {tolerance:g} {fit.unit} of {table.shown}: the closest departs by "
        f"{fit.max_residual:.3g} {fit.unit} at {table.row_word} {int(table.rows[i])} ({fit.theta_deg[i]:g} "
        "deg): is the data periodic, without a step?",
    )


def table_motion(spec: CaseSpec, source: Path | None) -> tuple[FittedMotion, MotionFit, list[str]]:
    """The motion fitted to the case's lift table. A valve's lift table (``valve_table``) gets its lash ramps
    (:func:`~camdyn.model.valvetrain.lift_with_ramps`); through a constant ratio it is fitted at the valve and divided
    by the ratio, through a rocker's geometry it is carried to the follower by the inverse of the rocker's lift and
    fitted there, its residual measured back at the valve."""
    if spec.motion is None or (spec.motion.table is None and spec.motion.valve_table is None):
        raise ValueError("table_motion: the case's [motion] has no table")
    vt = spec.valvetrain if spec.motion.valve_table is not None else None
    if spec.motion.valve_table is not None and vt is None:
        raise ValueError("table_motion: a valve_table needs [valvetrain]")
    name = spec.motion.valve_table or spec.motion.table or ""
    tolerance = spec.motion.tolerance
    table = read_lift_table(data_file_path(name, source), name, spec.kind)
    theta, lift = table.values.T
    unit, column = spec.kind.lift_unit, spec.kind.lift_column
    warnings = _unit_slip(table, lift, unit, column) + _lift_level(table, lift, unit, column)
    if vt is not None:
        try:
            lift = lift_with_ramps(theta, lift, vt.lash, vt.ramp_velocity)
        except ValueError as err:
            raise InputError(f"motion.valve_table ({name})", str(err)) from None
        warnings += ramp_join_warnings(theta, table.values[:, 1], vt.ramp_velocity)
    rocker = None if vt is None or vt.rocker is None else rocker_model(vt.rocker)
    data = lift if rocker is None else _through_rocker(rocker, lift, table)
    # through a rocker the data's rounding and the tolerance at the follower are the valve's over the largest ratio
    per_data = 1.0 if rocker is None else 1.0 / _largest_ratio(rocker, data, tolerance)
    motion, fit = fit_motion(
        theta,
        data,
        unit=unit,
        source="table" if vt is None else "valve_table",
        file=name,
        tolerance=None if tolerance is None else tolerance * per_data,
        rounding=table.rounding * per_data,
        repeats=table.repeats,
    )
    if rocker is not None:
        at_valve = rocker.host_lever(fit.fitted * M_PER_MM)[0] / M_PER_MM
        fit = dataclasses.replace(fit, data=lift, tolerance=tolerance, follower_data=data, data_fitted=at_valve)
    _within_tolerance(fit, table, tolerance)
    if vt is not None and rocker is None:  # the follower's lift: the cam's lift at the valve over the ratio
        motion = eqx.tree_at(lambda m: m.coef, motion, motion.coef / vt.ratio)
        fit = dataclasses.replace(fit, follower_per_data=1.0 / vt.ratio)
    return motion, fit, warnings + fit_warnings(fit)


def _through_rocker(rocker: Rocker, at_valve: np.ndarray, table: Samples) -> np.ndarray:
    """The follower's lift (mm) that gives the cam's lift at the valve ``at_valve`` (mm, ramps added) through the
    rocker; InputError at the first row asking for more (or less) than the rocker can give."""
    follower = rocker_follower_lift(rocker, at_valve)
    bad = np.flatnonzero(np.isnan(follower))
    if bad.size:
        i = int(bad[0])
        (least, least_arm), (most, most_arm) = rocker_valve_reach(rocker)
        word, reach, arm = ("more", most, most_arm) if at_valve[i] > 0 else ("less", least, least_arm)
        raise InputError(
            table.where(i),
            f"at {table.values[i, 0]:g} deg the cam's lift at the valve ({at_valve[i]:.4g} mm, the lash taken up) "
            f"is {word} than the rocker can give ({reach:.4g} mm, where its {arm} arm turns square to its contact's "
            "line): lengthen the valve arm or change the arms' angles",
        )
    return follower


def _largest_ratio(rocker: Rocker, follower_mm: np.ndarray, tolerance: float | None) -> float:
    """The rocker's largest ratio over the follower's lifts (mm) and a tolerance's (mm at the valve) span around
    them: a residual at the follower within ``tolerance`` over it is within ``tolerance`` at the valve. The ratio
    is monotone in lift (its slope's sign is that of sin(cam_angle - valve_angle)): its ends bound it."""
    ends = np.array([follower_mm.min(), follower_mm.max()]) * M_PER_MM
    span = 0.0 if tolerance is None else tolerance * M_PER_MM / float(np.min(rocker.host_lever(ends)[1]))
    return float(np.nanmax(rocker.host_lever(ends + np.array([-span, span]))[1]))


def contour_motion(
    spec: CaseSpec, source: Path | None
) -> tuple[FittedMotion, FollowerSpec, MotionFit, ContourFit, list[str]]:
    """The motion of the case's cam outline by exact contact, the follower with the outline's base radius."""
    if spec.follower is None or spec.follower.contour is None:
        raise ValueError("contour_motion: the case's [follower] has no contour")
    name = spec.follower.contour
    derived = contact_motion(read_contour(data_file_path(name, source), name), spec.follower)
    unit = spec.kind.lift_unit
    motion, fit = fit_motion(
        derived.theta_deg, derived.lift, unit=unit, source="contour", file=name, rounding=derived.rounding
    )
    return motion, derived.follower, fit, derived.contour, list(derived.warnings) + fit_warnings(fit)
