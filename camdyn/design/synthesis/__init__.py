"""Dimensional synthesis: choose a CCM's dimensions for a closed path and write a complete case file.

* ``_ccm``: the CCM's objective, scoring whole populations of designs at once (the cam sized by closed forms
  on sampled motion), and a design's ``[mechanism]``;
* ``_fourbar``: the CCM paper's comparison, the best plain four-bar for the same path;
* ``_optimize``: :func:`synthesize_dimensions`, differential evolution, the exact synthesis of the best designs
  and the cam size ``camdyn check`` accepts;
* ``_case``: :func:`synthesize_case`, a path file in, a case file's text out (``camdyn synthesize``).
"""

from ._case import PRELOAD_STEP, SynthesizedCase, synthesize_case, validate_path_file
from ._ccm import (
    DIMENSION_OBJECTIVE,
    ccm_objective,
    ccm_score,
    ccm_table,
    pitch_convexity,
    prime_radius_for_curvature,
    prime_radius_for_pressure_angle,
)
from ._fourbar import curve_error, fourbar_curve, fourbar_objective
from ._optimize import synthesize_dimensions

__all__ = [
    "DIMENSION_OBJECTIVE",
    "PRELOAD_STEP",
    "SynthesizedCase",
    "ccm_objective",
    "ccm_score",
    "ccm_table",
    "curve_error",
    "fourbar_curve",
    "fourbar_objective",
    "pitch_convexity",
    "prime_radius_for_curvature",
    "prime_radius_for_pressure_angle",
    "synthesize_case",
    "synthesize_dimensions",
    "validate_path_file",
]
