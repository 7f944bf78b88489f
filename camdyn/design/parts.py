"""From forces to parts for a whole case: the drive and the contact stress of ``camdyn check``'s response, the
contact-stress verdict, and the spring's own mass in the dynamics. (The spring is :mod:`camdyn.design.spring`.)"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .._core.errors import InputError
from ..model.case import Case, valvetrain_with_spring_mass
from ..model.contact import ContactStress, cam_contact, conjugate_contact, groove_contact
from ..model.drive import DriveTorque, drive_torque, follower_velocity
from ..model.dynamics import Response
from ..model.follower import FollowerModel
from ..model.geometry import CamGeometry, ConjugateGeometry, GrooveGeometry, contact_per_force
from ..model.surge import SpringInDynamics
from ..model.valvetrain import equivalent_follower
from ._check import Check, CheckKind
from .spring import SpringDesign, design_case_spring


def case_drive(case: Case, resp: Response) -> DriveTorque:
    """The camshaft drive of ``camdyn check``'s response (``CheckReport.response``: forces in N, an oscillating
    arm's as contact forces through its lever arm), with the case's ``[drive] speed_fluctuation``."""
    # an arm's back to its torque (N*m): the generalized force that works on the swing
    force = resp.force / contact_per_force(case.motion, case.follower, np.deg2rad(resp.theta_deg))
    velocity = follower_velocity(case.motion, resp.theta_deg, case.model.scale)
    return drive_torque(
        resp.theta_deg, force, velocity, resp.omega, speed_fluctuation=case.spec.drive.speed_fluctuation
    )


def case_contact(
    case: Case,
    geometry: CamGeometry,
    resp: Response,
    walls: GrooveGeometry | ConjugateGeometry | None = None,
    cam_forces_N: tuple[np.ndarray, np.ndarray] | None = None,
) -> ContactStress | None:
    """The Hertz contact stress of ``camdyn check``'s response on the case's cam, with its ``[materials]``;
    None where the case gives no contact width (``[follower] width`` or ``[mechanism] width``). A groove cam's
    (``walls``): on the wall its signed force presses; conjugate cams' (``walls`` the conjugate cam): each cam with
    its own force, ``cam_forces_N`` (primary, conjugate)."""
    width = case.spec.contact_width_mm
    if width is None:
        return None
    m = case.spec.materials
    cam = (m.cam.elastic_modulus, m.cam.poisson_ratio)
    follower = (m.follower.elastic_modulus, m.follower.poisson_ratio)
    if isinstance(walls, ConjugateGeometry):
        assert cam_forces_N is not None  # the caller gives each cam's force
        return conjugate_contact(geometry, walls, *cam_forces_N, width_mm=width, cam=cam, follower=follower)
    if walls is not None:
        return groove_contact(geometry, walls, resp.force, width_mm=width, cam=cam, follower=follower)
    return cam_contact(geometry, resp.force, width_mm=width, cam=cam, follower=follower)


def contact_check(contact: ContactStress, max_contact_stress_MPa: float) -> Check:
    """``[limits] max_contact_stress``: the largest Hertz pressure over the revolution must not exceed it."""
    return CheckKind.CONTACT_STRESS.check(contact.peak_pressure_MPa, float(max_contact_stress_MPa))


def with_spring(case: Case, spring_mass_kg: float) -> FollowerModel:
    """The case's follower model with a third of its spring's mass moving with it (the lumped correction; an
    arm's spring acts at ``[spring] lever_arm``)."""
    return _bare(case).with_mass(spring_mass_kg, "lumped").follower()


def _bare(case: Case) -> SpringInDynamics:
    """The case's follower with a massless spring: what :func:`resolve_spring` adds the spring's mass to."""
    spec = case.spec.spring
    arm = spec.lever_arm if spec is not None and case.kind.rotary else None
    ratio = None if case.valvetrain is None else float(case.valvetrain.ratio)
    bare = case.model if case.spring is None else case.spring.bare
    return SpringInDynamics("none", 0.0, arm, bare, valve_ratio=ratio)


def resolve_spring(case: Case) -> Case:
    """The case with its spring's own mass in the dynamics, as ``[spring] model`` asks: the spring is the part
    ``camdyn spring`` designs for the case's rate and preload (:func:`camdyn.design.spring.design_case_spring`),
    and its mass enters ``case.model`` as a third on the follower ("lumped", and "surge", whose jump speed is the
    chain's: :class:`camdyn.model.surge.SpringInDynamics`); a valvetrain's valve spring as a third on the valve
    (and so through the ratio squared in its equivalent follower), in the two-mass model a chain of masses for
    "surge". Without a ``[spring]`` table the spring is massless (its part is not known); where no spring can be
    built the mass stays out and ``case.spring.note`` says why.
    Idempotent: a resolved case comes back as it is."""
    if case.spring is not None:
        return case
    bare = _bare(case)
    if case.spec.spring is None:
        return replace(case, spring=bare)
    try:
        part = design_case_spring(case)
    except InputError as e:
        note = (
            "the spring's own mass is left out of the dynamics: no spring of the case's rate and preload can be built "
            f"within [spring] ({e})"
        )
        return replace(case, spring=replace(bare, note=note))
    return with_spring_part(case, part)


def with_spring_part(case: Case, part: SpringDesign) -> Case:
    """The case with ``part``'s own mass (and its travel to solid) in the dynamics, as ``[spring] model`` asks
    (:func:`resolve_spring`, which gives it the part designed for the case's rate and preload)."""
    assert case.spec.spring is not None  # the caller's: a case with a [spring] table
    sd = replace(
        _bare(case).with_mass(part.spring.mass, case.spec.spring.model),
        travel_to_solid_mm=part.installed_length - part.spring.solid_length,
    )
    if case.valvetrain is not None:  # the valve spring's third moves with the valve, in the two-mass model too
        lumped = valvetrain_with_spring_mass(case, part.spring.mass)
        valvetrain = valvetrain_with_spring_mass(case, part.spring.mass, surge=sd.model == "surge")
        return replace(case, model=equivalent_follower(lumped), spring=sd, valvetrain=valvetrain)
    return replace(case, model=sd.follower(), spring=sd)


def spring_mass_notes(case: Case) -> tuple[str, ...]:
    """What a vmapped study (sweep, tolerance) says of the spring's mass in a resolved case: held at every rate,
    and, for the surge model, carried as its lumped third (the chain is in ``check`` and ``size``)."""
    sd = case.spring
    if sd is None or sd.model == "none":
        return () if sd is None or sd.note is None else (sd.note,)
    out = (
        f"the spring's own mass ({1e3 * sd.mass_kg:.3g} g, the case's spring) is on the follower as its lumped "
        "third at every "
    )
    out += "rate"
    if sd.model == "surge":
        out += '; [spring] model = "surge": the chain\'s surge is judged by check and size, not here'
    return (out,)


def spring_jump_speed(case: Case, spring_mass_kg: float, *, w_max: float) -> float:
    """The dynamic jump speed (rad/s; inf if none up to ``w_max``) with a spring of that mass, as ``[spring]
    model`` asks: "lumped" (a third of it on the follower) or "surge" (the spring as a chain of masses)."""
    spec = case.spec.spring
    model = "lumped" if spec is None else spec.model
    return _bare(case).with_mass(spring_mass_kg, model).jump_speed(case.motion, w_max=w_max)
