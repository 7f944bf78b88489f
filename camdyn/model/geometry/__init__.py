"""Cam geometry: pitch curve, contour, pressure angle, curvature, undercut (the follower is a
:class:`camdyn.schema.FollowerSpec`).

Conventions (Norton's), in a fixed frame with the cam centre O at the origin; all lengths mm, angles as noted:

* ``base_radius`` Rb is the least radius of the cam contour. For a roller follower of radius Rr the prime
  circle has radius Rp = Rb + Rr.
* ``rotation`` is the sense in which the cam turns in the fixed frame ("cw" or "ccw"); sigma = +1 for ccw,
  -1 for cw. The cam frame coincides with the fixed frame at cam angle 0; a fixed point q is seen in the
  cam frame at R(-sigma theta) q. ``pitch`` and ``contour`` are given in the cam frame.
* translating followers move along +y. A translating roller with offset e has its axis at x = sigma * e, so
  a positive offset always lowers the pressure angle on the rise, whatever the rotation: at lift s the roller
  centre is at (sigma e, sqrt(Rp^2 - e^2) + s) and the pressure angle is Norton's
  phi = atan((s' - e) / (s + sqrt(Rp^2 - e^2))) for both senses. A translating flat face is perpendicular to
  the axis at y = Rb + s (its offset moves only the contact point across the face, not the contour).
* oscillating followers: pivot D at distance ``pivot_distance`` L from O in direction ``pivot_angle`` (deg,
  default 0, i.e. D on +x), u = (O - D)/L. The arm turns clockwise by psi from the direction D->O:
  w(psi) = R(-psi) u. Positive swing phi (the motion, rad) moves the follower away from O; psi = psi0 + phi.

  - oscillating roller: roller centre E = D + ``arm_length`` * w(psi); psi0 puts E on the prime circle,
    cos psi0 = (L^2 + a^2 - Rp^2) / (2 L a).
  - oscillating flat: the face is the line through D + h n(psi) along w(psi), n = J w (J = rotation by +90
    deg), h = ``offset`` (the face's distance from the pivot, positive toward the cam centre; 0: the face
    line passes through the pivot). O lies on the +n side at distance L sin(psi) - h, so psi0 makes the face
    tangent to the base circle: sin psi0 = (Rb + h) / L. ``arm_length`` is not used.

* pressure angle phi (deg, signed): the angle from the follower's velocity direction (the velocity of the
  follower point at the contact for a positive change of s or phi) to the contact normal N (outward from the
  cam), times sigma; so the translating roller gives Norton's formula above and positive phi is the rise.
* radii of curvature (mm) are signed, positive where the curve is convex (seen from outside the cam);
  for a roller, rho_contour = rho_pitch - Rr; for a flat face rho = h + d^2h/dalpha^2 with h the face's
  distance from O and alpha its normal direction (translating: Rb + s + s'').
* the flat face coordinate t (mm) is the contact's position along the face from the follower's axis
  (translating: t = s' - e, the lecture's t = f') or from the foot of the perpendicular from the pivot
  (oscillating; then t is also the lever arm).

The lecture (seed 001) differs: its roller centre at zero lift sits at r_b + r_r along the follower axis, with
the offset delta across it, so its least contour radius is sqrt((r_b + r_r)^2 + delta^2) - r_r (its "r_b = 4 cm"
with r_r = 1, delta = 0.5 cm is camdyn's base_radius = 40.249 mm); its cam frame has the follower along +x at
theta = 0 (camdyn's is that rotated by +90 deg); its cw offset delta > 0 is camdyn's offset e = +delta; and its
ccw flat-face formulas take theta as the polar angle of the contact in the cam frame, i.e. minus the cam angle.
"""

from ._analyze import (
    CamGeometry,
    GeometryExtremes,
    analyze,
    contact_per_force,
    extremes,
    lever_arm_mm,
    newton_per_torque_at,
)
from ._conjugate import ConjugateGeometry, conjugate, conjugate_lever_mm, evaluate_conjugate
from ._groove import WALLS, GrooveGeometry, Wall, groove
from ._inverse import ContactMotion, ContourFit, contact_motion
from ._kernel import check_assembly, check_dimensions, evaluate_geometry, follower_params, geometry_of
from ._size import BASE_RADIUS_STEP_MM, curvature_limit, min_base_radius, passes, rounded_base_radius

__all__ = [
    "BASE_RADIUS_STEP_MM",
    "CamGeometry",
    "ConjugateGeometry",
    "ContactMotion",
    "ContourFit",
    "GeometryExtremes",
    "GrooveGeometry",
    "WALLS",
    "Wall",
    "analyze",
    "check_assembly",
    "check_dimensions",
    "conjugate",
    "conjugate_lever_mm",
    "contact_motion",
    "curvature_limit",
    "evaluate_conjugate",
    "evaluate_geometry",
    "extremes",
    "follower_params",
    "geometry_of",
    "contact_per_force",
    "groove",
    "lever_arm_mm",
    "min_base_radius",
    "newton_per_torque_at",
    "passes",
    "rounded_base_radius",
]
