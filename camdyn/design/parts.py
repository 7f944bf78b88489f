"""From forces to parts for a whole case: the drive and the contact stress of ``camdyn check``'s response, the
contact-stress verdict, and the jump speed with the spring's own mass. (The spring is :mod:`camdyn.design.spring`.)"""

from __future__ import annotations

import numpy as np

from .._core.units import M_PER_MM
from ..model.case import Case
from ..model.contact import ContactStress, cam_contact
from ..model.drive import DriveTorque, drive_torque, follower_velocity
from ..model.dynamics import Response, dynamic_jump_speed
from ..model.follower import FollowerModel, with_spring_mass
from ..model.geometry import CamGeometry, newton_per_torque_at
from ..model.surge import chain_jump_speed
from ._check import Check, CheckKind


def case_drive(case: Case, resp: Response) -> DriveTorque:
    """The camshaft drive of ``camdyn check``'s response (``CheckReport.response``: forces in N, an oscillating
    arm's as contact forces through its lever arm), with the case's ``[drive] speed_fluctuation``."""
    force = resp.force
    if case.oscillating:  # back to the arm torque (N*m): the generalized force that works on the swing
        force = force / newton_per_torque_at(case.motion, case.follower, np.deg2rad(resp.theta_deg))
    velocity = follower_velocity(case.motion, resp.theta_deg, case.model.scale)
    return drive_torque(resp.theta_deg, force, velocity, resp.omega, speed_fluctuation=case.spec.drive.speed_fluctuation)


def case_contact(case: Case, geometry: CamGeometry, resp: Response) -> ContactStress | None:
    """The Hertz contact stress of ``camdyn check``'s response on the case's cam, with its ``[materials]``;
    None where the case gives no contact width (``[follower] width`` or ``[mechanism] width``)."""
    width = case.spec.contact_width_mm
    if width is None:
        return None
    m = case.spec.materials
    cam = (m.cam.elastic_modulus, m.cam.poisson_ratio)
    follower = (m.follower.elastic_modulus, m.follower.poisson_ratio)
    return cam_contact(geometry, resp.force, width_mm=width, cam=cam, follower=follower)


def contact_check(contact: ContactStress, max_contact_stress_MPa: float) -> Check:
    """``[limits] max_contact_stress``: the largest Hertz pressure over the revolution must not exceed it."""
    return Check(CheckKind.CONTACT_STRESS.value, contact.peak_pressure_MPa, float(max_contact_stress_MPa), "MPa", "<=")


def with_spring(case: Case, spring_mass_kg: float) -> FollowerModel:
    """The case's follower model with a third of its spring's mass moving with it (the lumped correction; an
    arm's spring acts at ``[spring] lever_arm``)."""
    arm = case.spec.spring.lever_arm if case.oscillating else None
    return with_spring_mass(case.model, spring_mass_kg, lever_arm_mm=arm)


def spring_jump_speed(case: Case, spring_mass_kg: float, *, w_max: float) -> float:
    """The dynamic jump speed (rad/s; inf if none up to ``w_max``) with the spring's own mass, as ``[spring]
    model`` asks: "lumped" (a third of it on the follower) or "surge" (the spring as a chain of masses)."""
    spec = case.spec.spring
    if spec is None or spec.model == "lumped":
        return dynamic_jump_speed(case.motion, with_spring(case, spring_mass_kg), w_max=w_max)
    mass = spring_mass_kg * (spec.lever_arm * M_PER_MM) ** 2 if case.oscillating else spring_mass_kg  # an arm's: m_s r^2
    return chain_jump_speed(case.motion, case.model, mass, w_max=w_max)
