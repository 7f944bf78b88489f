"""Results stored by their arguments (``camdyn._core.stored``): a second process reads what the first computed from
the same data, the same to the bit; other data are computed afresh; nothing is stored while the program cache is
off."""

import dataclasses

import numpy as np
import pytest

from camdyn._core import jit
from camdyn._core.stored import stored_by_arguments
from camdyn.model.motion import fit_periodic


@pytest.fixture
def cache(monkeypatch, tmp_path):
    """The program cache, and so the stored results, in a fresh folder for one test: this fingerprint's folder."""
    monkeypatch.setattr(jit, "_DIR", None)
    jit.enable(tmp_path)
    return jit._programs(tmp_path)


def test_a_result_is_computed_once_per_distinct_arguments(cache):
    calls = []

    @stored_by_arguments
    def scaled(x, factor=1.0):
        calls.append(1)
        return x * factor

    x = np.arange(5.0)
    first = scaled(x, factor=2.0)
    again = scaled(x.copy(), factor=2.0)  # equal bytes, another array: read back, not computed
    assert len(calls) == 1 and np.array_equal(first, again)
    scaled(x, factor=3.0)  # another keyword value
    scaled(x + 1e-15 * x, factor=2.0)  # other bytes, however close
    scaled(x.astype(np.float32), factor=2.0)  # another dtype
    assert len(calls) == 4 and len(list(cache.glob("*.result"))) == 4


def test_a_truncated_file_is_computed_afresh(cache):
    @stored_by_arguments
    def double(x):
        return 2 * x

    assert double(np.ones(3)).sum() == 6.0
    (file,) = cache.glob("*.result")
    file.write_bytes(file.read_bytes()[:10])
    assert double(np.ones(3)).sum() == 6.0


def test_nothing_is_stored_while_the_cache_is_off(monkeypatch, tmp_path):
    monkeypatch.setattr(jit, "_DIR", None)
    calls = []

    @stored_by_arguments
    def one(x):
        calls.append(1)
        return x

    one(1.0)
    one(1.0)
    assert len(calls) == 2 and not list(tmp_path.iterdir())


def test_a_stored_fit_is_the_fit(cache):
    """The smoothing-spline fit read back equals the one computed, array for array, to the bit."""
    rng = np.random.default_rng(3)
    x = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    y = np.round(np.sin(x) + 0.3 * np.cos(3 * x) + 1e-3 * rng.standard_normal(x.size), 3)
    computed = fit_periodic(x, y, sigma_floor=1e-3 / np.sqrt(12.0))
    read = fit_periodic(x, y, sigma_floor=1e-3 / np.sqrt(12.0))
    assert len(list(cache.glob("fit_periodic-*.result"))) == 1
    for field in dataclasses.fields(computed):
        a, b = getattr(computed, field.name), getattr(read, field.name)
        assert np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b, field.name
