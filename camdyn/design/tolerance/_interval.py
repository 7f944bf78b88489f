"""The exact (Clopper-Pearson) confidence interval of a probability estimated from samples: beta quantiles by
``scipy.special`` (scipy.stats' ``binomtest(...).proportion_ci(method="exact")`` gives the same interval, root-found,
for 0.5-1 s more of import in every tolerance study)."""

from __future__ import annotations

from scipy.special import betainccinv, betaincinv

CONFIDENCE = 0.95  # of the intervals on the studies' probabilities (of separation, an impact, float, bounce)


def exact_interval(hits: int, samples: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The two-sided Clopper-Pearson interval of a probability seen ``hits`` times in ``samples``: the
    ``(1 - confidence) / 2`` quantile of Beta(hits, samples - hits + 1) and the upper one of Beta(hits + 1, samples -
    hits); 0 and 1 at the ends."""
    tail = 0.5 * (1.0 - confidence)
    low = 0.0 if hits <= 0 else float(betaincinv(hits, samples - hits + 1, tail))
    high = 1.0 if hits >= samples else float(betainccinv(hits + 1, samples - hits, tail))
    return low, high
