"""Path-generation synthesis of combined cam-linkage mechanisms (Ye & Smith 2005; the CCM of a profile cutter).

A point of a linkage must run once round a closed path (:mod:`camdyn.model.paths`) while the cam turns once.
For every path parameter u the linkage is solved backwards from the path with Assur dyads: the follower side
gives the follower coordinate (slider position or arm angle), the crank dyad gives the cam (crank) angle. The
follower motion as a function of cam angle is then :class:`CamLinkMotion`, which inverts the crank angle
Theta(u) by Newton's method on the exact representation and gets s', s'', s''' by the implicit-function chain
rule.

Frames and signs. All lengths mm, angles deg in the tables and rad inside. The cam centre is moved to the
origin. The crank dyad is (P = the path-side point, M = the crank pin, Q = the cam centre); its assembly mode
switches at its singular positions so that the crank keeps turning the same way (:class:`CrankDyad`).

The package, one concept per module:

* ``_dyads``: vector helpers, the RRR and RRP dyads and their kinematics;
* ``_extremes``: where the path-side point is nearest to and farthest from the cam centre;
* ``_crank``: :class:`CrankDyad` and its expansion through the singular positions;
* ``_chains``: :class:`CCMChain` and :class:`OscillatingChain`, built from a ``[mechanism]`` table;
* ``_motion``: :class:`CamLinkMotion`, the follower motion of a synthesized cam;
* ``_forward``: the follower in the shared geometry conventions (a CCM's base radius, unless given, is the
  least ``camdyn check`` accepts: :func:`camdyn.model.geometry.min_base_radius`), Ye & Smith's pitch curve and
  contour, and the forward check;
* ``_synthesis``: :func:`synthesize_motion` and its result :class:`Synthesis`;
* ``_batch``: padded evaluation of the jitted helpers (each compiles once).
"""

from ._batch import N_GRID, vmap_scalar
from ._chains import CCMChain, OscillatingChain
from ._crank import CrankDyad
from ._dyads import cross2, rrp, rrp_kinematics, rrr, rrr_kinematics, rrr_reach_miss
from ._forward import pitch_contour
from ._motion import CamLinkMotion
from ._synthesis import Synthesis, parse_mechanism, synthesize_motion

__all__ = [
    "CCMChain",
    "CamLinkMotion",
    "CrankDyad",
    "N_GRID",
    "OscillatingChain",
    "Synthesis",
    "cross2",
    "parse_mechanism",
    "pitch_contour",
    "rrp",
    "rrp_kinematics",
    "rrr",
    "rrr_kinematics",
    "rrr_reach_miss",
    "synthesize_motion",
    "vmap_scalar",
]
