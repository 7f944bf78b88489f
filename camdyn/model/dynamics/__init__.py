"""Single-DOF follower dynamics on diffrax: interface force, separation, flight, impact, jump speed.

The follower (mass m, return spring k with preload F0, damper c, constant external force F_ext pushing it onto
the cam) is driven by a cam turning at constant speed w, theta = w t. Two time-domain models:

* compliant (a follower train of stiffness k_f and damping c_f between cam and mass):
  ``m x'' = Fi - (k x + F0) - c x' - F_ext`` with ``Fi = max(0, k_f (s - x) + c_f (w s' - x'))`` while s > x
  (:mod:`._compliant`, shooting on diffrax; in contact also exact in the frequency domain, :mod:`._harmonic`);
* rigid: contact (x = s) until the kinematic force falls to zero; flight under spring and damper until the
  follower meets the cam again; impact ``x'+ = w s' - e (x'- - w s')``; contact again when the bounces die
  (:mod:`._rigid`).

Both are integrated in the cam angle (state: x and dx/dtheta, in the motion's unit: mm or rad), so segment
boundaries are fixed angles that the step-size controller is told about (``jump_ts``). Everything is in SI
inside; ``scale`` converts the motion's unit to m (1e-3) or keeps rad (1.0), and the same equations then
hold for the rotational equivalent of an oscillating follower (inertia, torsion spring, torques). The train's
force on the cam and the follower's rest on it are written once (:mod:`._train`), for these models, the spring's
surge chain (:mod:`camdyn.model.surge`) and the design studies.
"""

from ._closure import ClosureResponse, Crossover, closure_response, preload_shares
from ._compliant import compliant_response, min_contact_force, periodic_orbit, vector_field
from ._harmonic import (
    linear_contact_force,
    linear_least_force,
    linear_min_force,
    steady_force_at,
    steady_spectrum,
    steady_state,
    steady_train_force,
)
from ._kinematic import (
    kinematic_force,
    kinematic_force_jit,
    kinematic_force_of,
    kinematic_jump_speed,
    least_static_force,
    velocity_steps,
)
from ._response import dynamic_jump_speed, first_zero_speed, jump_search_limit, response, store_response
from ._result import Flight, Impact, Response, Separation
from ._rigid import rigid_response
from ._train import (
    contact_force,
    free_vibration,
    preload_share,
    static_position,
    train_force,
    vibration_coefficients,
)
from ._valvefast import ValveSummary, fast_valve_summary
from ._valvepoint import ValvePoint, bounce_speed, float_speed, valve_scan_speeds
from ._valveresponse import ValveEvent, ValvetrainResponse
from ._valvetrain import prepare_valvetrain, valvetrain_response

__all__ = [
    "ClosureResponse",
    "Crossover",
    "Flight",
    "Impact",
    "Response",
    "Separation",
    "closure_response",
    "preload_shares",
    "prepare_valvetrain",
    "compliant_response",
    "contact_force",
    "dynamic_jump_speed",
    "first_zero_speed",
    "free_vibration",
    "jump_search_limit",
    "kinematic_force",
    "kinematic_force_jit",
    "kinematic_force_of",
    "kinematic_jump_speed",
    "linear_contact_force",
    "linear_least_force",
    "linear_min_force",
    "min_contact_force",
    "periodic_orbit",
    "least_static_force",
    "preload_share",
    "response",
    "rigid_response",
    "steady_force_at",
    "vector_field",
    "static_position",
    "steady_spectrum",
    "steady_state",
    "steady_train_force",
    "store_response",
    "train_force",
    "vibration_coefficients",
    "ValveEvent",
    "ValvetrainResponse",
    "ValvePoint",
    "ValveSummary",
    "fast_valve_summary",
    "bounce_speed",
    "float_speed",
    "valve_scan_speeds",
    "valvetrain_response",
    "velocity_steps",
]
