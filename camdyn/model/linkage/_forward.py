"""The follower of a synthesized cam in the shared geometry conventions, and the forward check: the linkage driven
by the cam (crank at the cam angle, follower where the cam puts it) must trace the path again.

Each function returns the :class:`camdyn.schema.FollowerSpec`, the traced points (n, 2) in the case frame, the
roller centre and its derivative per radian of cam angle (n, 2) relative to the cam centre, and the summary
entries it adds; warnings are appended to ``warnings``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from pydantic import ValidationError

from ..._core.errors import InputError
from ..._core.units import DEFAULT_MIN_CURVATURE_RATIO
from ...schema import FollowerSpec, MechanismSpec
from ..geometry import min_base_radius, rounded_base_radius
from ._chains import CCMChain, OscillatingChain
from ._dyads import cross2, rrr, turn

if TYPE_CHECKING:
    from ..motion import Motion
    from ._motion import CamLinkMotion


def least_transmission_deg(ang: np.ndarray) -> float:
    """Least transmission angle (deg, folded into [0, 90]) of a driven dyad over the path (``check`` judges it:
    ``[limits] min_transmission_angle``)."""
    return float(np.degrees(np.minimum(ang, np.pi - ang)).min())


def pitch_contour(
    pos: np.ndarray, vel: np.ndarray, theta: np.ndarray, sense: float, rr: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pitch curve and contour in the cam frame (Ye & Smith eqs. 6-8) from the roller centre in the fixed frame.

    ``pos``, ``vel``: roller centre and its derivative per radian of cam angle (n, 2), relative to the cam centre.
    Returns (pitch, contour, velocity seen from the cam), each (n, 2) mm.
    """
    a = -sense * theta  # cam frame = fixed frame turned back by the cam angle
    c, s = np.cos(a), np.sin(a)
    rot = lambda v: np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])  # noqa: E731
    pitch = rot(pos)
    rel = vel - sense * np.column_stack([-pos[:, 1], pos[:, 0]])  # d/dtheta seen from the cam
    tan = rot(rel)
    speed = np.linalg.norm(tan, axis=1)
    unit = tan / np.where(speed > 0, speed, 1.0)[:, None]
    contour = pitch + sense * rr * np.column_stack([unit[:, 1], -unit[:, 0]])  # eq. 8: towards the cam
    return pitch, contour, rel


def _angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.arccos(np.clip(np.sum(a * b, 1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)), -1, 1))


def _derived_follower(**fields) -> FollowerSpec:
    """The follower a mechanism implies; a dimension beyond the schema's physical bounds is a fault of the
    mechanism (an :class:`InputError` on ``mechanism``), not of a follower table the user never wrote."""
    try:
        return FollowerSpec(**fields)
    except ValidationError as err:
        bad = "; ".join(f"{'.'.join(map(str, e['loc']))} = {e['input']:.6g}: {e['msg'].lower()}" for e in err.errors())
        raise InputError("mechanism", f"the cam follower this mechanism implies is out of range ({bad})") from None


def _ccm_follower(ms: MechanismSpec, e: float, sense: float, base: float) -> FollowerSpec:
    return _derived_follower(
        type="translating-roller",
        base_radius=base,
        roller_radius=ms.roller_radius,
        offset=e,
        rotation="ccw" if sense > 0 else "cw",
    )


def _choose_base_radius(tabulated, ms: MechanismSpec, e: float, sense: float, sharp: bool) -> float:
    """The least base radius (mm) with which ``camdyn check`` passes the cam at the mechanism's pressure-angle
    limit and the default curvature limit (the pressure angle alone where sharp corners leave the contour no
    curvature to meet), rounded up to 0.5 mm: :func:`camdyn.model.geometry.min_base_radius`."""
    trial = _ccm_follower(ms, e, sense, abs(e) + ms.roller_radius)  # any base radius that assembles: a search start
    ratio = None if sharp else DEFAULT_MIN_CURVATURE_RATIO
    return rounded_base_radius(
        min_base_radius(tabulated, trial, max_pressure_angle=ms.max_pressure_angle, min_curvature_ratio=ratio)
    )


def ccm_forward(
    motion: CamLinkMotion,
    tabulated: Motion,
    ms: MechanismSpec,
    vals: np.ndarray,
    pts: dict,
    a_pin: np.ndarray,
    coupler: float,
    sense: float,
    warnings: list[str],
) -> tuple[FollowerSpec, np.ndarray, np.ndarray, np.ndarray, dict]:
    """The CCM's translating roller (base radius chosen on the ``tabulated`` motion unless given) and its forward
    check.

    ``vals``: s, s' per radian at the sample angles (2, n); ``pts``: the joints solved from the path there;
    ``a_pin``: the crank pin at those angles (n, 2), relative to the cam centre; ``coupler``: the coupler, mm.
    """
    chain = motion.chain
    assert isinstance(chain, CCMChain)  # a ccm mechanism's chain
    e_dir, origin = np.asarray(chain.direction), np.asarray(chain.origin)
    xhat = np.array([e_dir[1], -e_dir[0]])
    e = float(origin @ xhat)  # offset of the slider line from the cam centre (follower frame x)
    s, s1 = vals[0], vals[1]
    base = (
        ms.base_radius
        if ms.base_radius is not None
        else _choose_base_radius(tabulated, ms, e, sense, bool(chain.path.sharp_u))
    )
    rp = base + ms.roller_radius
    if rp <= abs(e):
        raise InputError(
            "mechanism.base_radius",
            f"base + roller radius ({rp:g} mm) must exceed the slider line's offset from the cam centre ({abs(e):.4g} "
            "mm)",
        )
    d0 = math.sqrt(rp * rp - e * e)
    follower = _ccm_follower(ms, e, sense, base)
    pos = e * xhat + (d0 + s)[:, None] * e_dir
    vel = s1[:, None] * e_dir
    # forward: crank at the cam angle, slider where the cam puts it, then the RRR dyad B-C-E closes the coupler
    e_pin = origin + (float(motion.out0) + s)[:, None] * e_dir
    mode_c = float(np.sign(cross2(pts["C"][0] - pts["B"][0], e_pin[0] - pts["B"][0])))
    assert ms.link is not None  # the schema: a ccm mechanism needs its link
    c_fwd = np.asarray(rrr(a_pin, e_pin, float(np.linalg.norm(chain.joint)), ms.link, mode_c))
    jx, jy = np.asarray(chain.joint)
    bc = c_fwd - a_pin
    jn2 = jx * jx + jy * jy
    ex = (jx * bc + jy * np.column_stack([bc[:, 1], -bc[:, 0]])) / jn2  # rotate B->C back into B->T
    traced = a_pin + coupler * ex + np.asarray(chain.center)
    modes = np.sign(cross2(pts["C"] - pts["B"], pts["E"] - pts["B"]))
    if np.any(modes != mode_c):
        warnings.append(
            "the forward dyad B-C-E changes assembly mode along the path: the linkage cannot run through it"
        )
    tmin = least_transmission_deg(_angle_between(pts["B"] - pts["C"], pts["E"] - pts["C"]))  # B-C-E, at C
    # RRP transmission angle: 90 deg minus the link's angle to the slider line (singular when perpendicular)
    phi = _angle_between(pts["C"] - pts["E"], np.broadcast_to(e_dir, pts["E"].shape))
    slider_ang = least_transmission_deg(np.pi / 2 - np.minimum(phi, np.pi - phi))  # the link to the slider's normal
    extra = {
        "offset_mm": e,
        "min_transmission_angle_deg": tmin,
        "min_slider_angle_deg": slider_ang,
        "slider_zero_mm": float(motion.out0),
    }
    return follower, traced, pos, vel, extra


def oscillating_forward(
    motion: CamLinkMotion,
    tabulated: Motion,
    ms: MechanismSpec,
    vals: np.ndarray,
    pts: dict,
    a_pin: np.ndarray,
    coupler: float,
    sense: float,
    warnings: list[str],
) -> tuple[FollowerSpec, np.ndarray, np.ndarray, np.ndarray, dict]:
    """Ye & Smith's oscillating roller (base radius from the arm's least reach) and its forward check; arguments
    as :func:`ccm_forward`."""
    chain = motion.chain
    assert isinstance(chain, OscillatingChain)  # an oscillating mechanism's chain
    # the schema: an oscillating mechanism needs these; the roller radius is the one the synthesis chose
    assert ms.arm is not None and ms.path_link is not None and ms.follower_link is not None
    assert ms.pin_distance is not None and ms.roller_radius is not None
    d = np.asarray(chain.pivot)  # the schema refused a pivot on the cam centre
    psi = np.asarray(pts["psi"])
    if np.any(psi <= 0.0) or np.any(psi >= np.pi):
        raise InputError(
            "mechanism.arm_angle",
            "the roller arm must lie clockwise of the line from the pivot D to the cam centre O (0 < psi < 180 deg "
            "all the way round); camdyn cannot model an arm on the other side: mirror the mechanism (negate every y)",
        )
    psi0 = float(motion.out0)
    dn = -d / np.linalg.norm(d)
    e0 = d + ms.arm * turn(dn, -psi0)
    rp = float(np.linalg.norm(e0))
    base = rp - ms.roller_radius
    if base <= 0.0:
        raise InputError(
            "mechanism.roller_radius",
            f"roller radius {ms.roller_radius:g} mm exceeds the least distance {rp:.4g} mm from the cam centre to the "
            "roller centre",
        )
    follower = _derived_follower(
        type="oscillating-roller",
        base_radius=base,
        roller_radius=ms.roller_radius,
        pivot_distance=float(np.linalg.norm(d)),
        pivot_angle=math.degrees(math.atan2(d[1], d[0])),
        arm_length=ms.arm,
        rotation="ccw" if sense > 0 else "cw",
    )
    psi_t = psi0 + vals[0]
    arm_dir = turn(np.broadcast_to(dn, (len(psi_t), 2)), -psi_t)
    pos = d + ms.arm * arm_dir
    vel = -ms.arm * vals[1][:, None] * np.column_stack([-arm_dir[:, 1], arm_dir[:, 0]])  # dE/dpsi = arm * (cw normal)
    # forward: arm at phi(theta) -> C; crank at the cam angle -> A; dyad A-B-C closes; F on C->B produced
    c_fwd = d + ms.follower_link * turn(arm_dir, -math.radians(ms.arm_angle))
    lbc = abs(ms.path_link - ms.pin_distance)
    mode_b = float(np.sign(cross2(pts["B"][0] - a_pin[0], pts["C"][0] - a_pin[0])))
    b_fwd = np.asarray(rrr(a_pin, c_fwd, coupler, lbc, mode_b))
    e_fc = (b_fwd - c_fwd) / (ms.pin_distance - ms.path_link)
    traced = c_fwd - ms.path_link * e_fc + np.asarray(chain.center)
    modes = np.sign(cross2(pts["B"] - a_pin, pts["C"] - a_pin))
    if np.any(modes != mode_b):
        warnings.append(
            "the forward dyad A-B-C changes assembly mode along the path: the linkage cannot run through it"
        )
    tmin = least_transmission_deg(_angle_between(a_pin - pts["B"], pts["C"] - pts["B"]))  # A-B-C, at B
    extra = {"min_transmission_angle_deg": tmin, "psi0_deg": math.degrees(psi0)}
    return follower, traced, pos, vel, extra
