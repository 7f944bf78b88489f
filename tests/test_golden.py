"""Every shipped case's numbers as the golden snapshot has them (``tests/golden_regen.py`` writes it): ``check --json``,
``size --json`` and ``table`` CSV, key for key in the same order, floats at 1e-9 relative, the rest exactly."""

import gzip
import json
import math

import pytest
from golden_regen import golden_file, golden_name, shipped_cases, snapshot

RTOL = 1e-9


def assert_same(got, want, where: str = "") -> None:
    """``got`` is ``want``: dicts with the same keys in the same order, lists as long, floats within :data:`RTOL`."""
    if isinstance(want, dict):
        assert isinstance(got, dict), f"{where}: {type(got).__name__}, want an object"
        assert list(got) == list(want), f"{where}: keys {list(got)}, want {list(want)}"
        for k in want:
            assert_same(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), f"{where}: {got!r:.200}, want {want!r:.200}"
        for i, (g, w) in enumerate(zip(got, want, strict=True)):
            assert_same(g, w, f"{where}[{i}]")
    elif isinstance(want, float) and not isinstance(want, bool):
        assert isinstance(got, int | float) and not isinstance(got, bool), f"{where}: {got!r}, want {want!r}"
        if math.isnan(want):
            assert math.isnan(got), f"{where}: {got!r}, want nan"
        else:
            assert got == pytest.approx(want, rel=RTOL, abs=0.0), f"{where}: {got!r}, want {want!r}"
    else:
        assert type(got) is type(want) and got == want, f"{where}: {got!r}, want {want!r}"


@pytest.mark.slow
@pytest.mark.parametrize("case", shipped_cases(), ids=golden_name)
def test_golden(case):
    want = json.loads(gzip.decompress(golden_file(case).read_bytes()))
    assert_same(snapshot(case), want, golden_name(case))


def test_assert_same_fails_on_a_change():
    """The comparison can fail: a float off by 1e-8, a key out of order, a string changed."""
    want = {"a": 1.0, "b": "x", "c": [1, True]}
    assert_same({"a": 1.0 + 1e-12, "b": "x", "c": [1, True]}, want)
    for got in (
        {"a": 1.0 + 1e-8, "b": "x", "c": [1, True]},
        {"b": "x", "a": 1.0, "c": [1, True]},
        {"a": 1.0, "b": "y", "c": [1, True]},
        {"a": 1.0, "b": "x", "c": [1, 1]},
    ):
        with pytest.raises(AssertionError):
            assert_same(got, want)
