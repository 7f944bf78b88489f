"""Tolerance studies: the probability that a built cam, differing from its drawing within ``[tolerances]``,
separates at the case speed; the spread of its jump speed and least contact force; which tolerance matters.

Every sample is drawn up front (:mod:`._sampling`, ``numpy.random.default_rng(seed)``), so the result does not
depend on how the samples are chunked or sharded. One compiled, vmapped kernel (:mod:`._kernel`) computes per
sample the least force at its cam speed (the sweep's frequency-domain steady state on the 0.1 deg grid; the
kinematic force for a rigid follower) and its dynamic jump speed (a scan of 16 speeds up to ``check``'s search
limit on a 512-angle grid, the check's 4096 where the cam's velocity steps, then Illinois steps), run in chunks by
:func:`camdyn._core.sharding.run_batched` over every device of every process. A groove cam (it cannot jump) is
studied for its crossover impacts instead (:mod:`._groove`). :mod:`._sensitivity` linearises the jump-speed margin
with JAX gradients and sets it against the Monte Carlo variance shares; :mod:`._result` holds the result and its CSV.
A valvetrain's study (:mod:`._valvetrain`) runs the two-mass model per sample instead: float and bounce at the
sample's speed, its float and bounce speeds and seating velocity.
"""

from ._groove import ImpactToleranceResult, impact_tolerance_study
from ._interval import CONFIDENCE
from ._result import CSV_COLUMNS, PARAM_KEYS, ToleranceResult, csv_columns
from ._sampling import case_tolerances
from ._study import CHUNK_SAMPLES, SCAN_GRID, WORST, tolerance_study
from ._valvetrain import (
    DEFAULT_VALVETRAIN_SAMPLES,
    MAX_VALVETRAIN_SAMPLES,
    ValveToleranceResult,
    valvetrain_tolerance_study,
)
from ._worst import worst_case_docs, worst_valvetrain_docs

__all__ = [
    "CHUNK_SAMPLES",
    "CONFIDENCE",
    "CSV_COLUMNS",
    "DEFAULT_VALVETRAIN_SAMPLES",
    "MAX_VALVETRAIN_SAMPLES",
    "ImpactToleranceResult",
    "impact_tolerance_study",
    "PARAM_KEYS",
    "SCAN_GRID",
    "ToleranceResult",
    "ValveToleranceResult",
    "WORST",
    "case_tolerances",
    "csv_columns",
    "tolerance_study",
    "valvetrain_tolerance_study",
    "worst_case_docs",
    "worst_valvetrain_docs",
]
