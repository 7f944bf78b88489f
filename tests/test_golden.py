"""Every shipped case's numbers as the golden snapshot has them (``tests/golden_regen.py`` writes it): ``check --json``,
``size --json`` and ``table`` CSV, key for key in the same order, floats within what another CPU's rounding moves
them, the rest exactly.

The tolerances were measured: the snapshot written on one machine (AVX-512) against the same code on another (AVX
without AVX2), and on this one with XLA held to SSE4.2 and OpenBLAS to its Nehalem kernels
(``XLA_FLAGS=--xla_cpu_max_isa=SSE4_2 OPENBLAS_CORETYPE=Nehalem``). Through the adaptive steps and the searches a
value moved by up to 6e-6 of itself (most by under 1e-7); a number that is round-off by nature (a force sized to
zero, a table cell beside a zero crossing) by up to 4e-11 in its unit, a small difference of two values (a
sized preload's dynamic correction) by up to 6e-9; a measure of numerical error (how far a path
case's table is from its mechanism, a revolution from the one before) by up to 40 % of itself, being a difference of
nearly equal numbers; where an extreme lies, on a plateau (a dwell's force, an arc's curvature), by whatever point
rounding picks; a table's jerk column (a path's mechanism or a fit differentiated three times) by up to 1.2e-5 of
its largest value, the other columns by up to 1.3e-8; and the lecture cam past its jump speed, which bounces
without settling, by 5e-4 of a value and 7e-6 of a column. A change of model moves them by far more."""

import gzip
import json
import math
import re

import pytest
from golden_regen import golden_file, golden_name, shipped_cases, snapshot

RTOL = 1e-5  # of a value
ATOL = 1e-7  # in the value's unit (N, mm, rad, rpm, ...): a round-off-sized number, or a small difference of two values
TABLE_ATOL = 1e-7  # of the column's largest magnitude: a cell beside a zero crossing
JERK_ATOL = 1e-4  # of the column's largest magnitude, in a jerk column
JERK_COLUMN = re.compile(r"^(j|phi3)_")
ERROR_MEASURES = {"motion_table_error", "periodicity_error"}  # within a factor of 2 (or both round-off)
EXTREME_AT = re.compile(r"(_at_deg|^(min|least|peak)_contact_force_deg)$")  # an angle, wherever on a plateau


def _close(got: float, want: float, atol: float, rtol: float) -> bool:
    """Within ``rtol`` of ``want`` and ``atol`` (NaN is NaN)."""
    return math.isnan(got) if math.isnan(want) else abs(got - want) <= rtol * abs(want) + atol


def assert_same(got, want, where: str = "", atol: float = ATOL, rtol: float = RTOL) -> None:
    """``got`` is ``want``: dicts with the same keys in the same order, lists as long, floats within ``rtol`` of
    themselves and ``atol``; a table (a list of rows under ``rows``) within :data:`TABLE_ATOL` of each column."""
    if isinstance(want, dict):
        assert isinstance(got, dict), f"{where}: {type(got).__name__}, want an object"
        assert list(got) == list(want), f"{where}: keys {list(got)}, want {list(want)}"
        for k in want:
            here = f"{where}.{k}"
            if EXTREME_AT.search(k) and isinstance(want[k], float):
                assert isinstance(got[k], float) and -360.0 <= got[k] <= 720.0, f"{here}: {got[k]!r}, want an angle"
            elif k in ERROR_MEASURES:
                _assert_error_measure(got[k], want[k], here)
            elif k == "rows" and isinstance(want[k], list):
                _assert_table(got[k], want[k], here, rtol)
            else:
                assert_same(got[k], want[k], here, atol, rtol)
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), f"{where}: {got!r:.200}, want {want!r:.200}"
        for i, (g, w) in enumerate(zip(got, want, strict=True)):
            assert_same(g, w, f"{where}[{i}]", atol, rtol)
    elif isinstance(want, float) and not isinstance(want, bool):
        assert isinstance(got, int | float) and not isinstance(got, bool), f"{where}: {got!r}, want {want!r}"
        assert _close(got, want, atol, rtol), f"{where}: {got!r}, want {want!r}"
    else:
        assert type(got) is type(want) and got == want, f"{where}: {got!r}, want {want!r}"


def _assert_error_measure(got, want, where: str) -> None:
    """A measure of numerical error (a float or an object of them): within a factor of 2, or both round-off."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and list(got) == list(want), f"{where}: {got!r:.200}, want {want!r:.200}"
        for k in want:
            _assert_error_measure(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, float):
        assert isinstance(got, float), f"{where}: {got!r}, want {want!r}"
        assert max(abs(got), abs(want)) <= ATOL or 0.5 <= got / want <= 2.0, f"{where}: {got!r}, want {want!r}"
    else:
        assert_same(got, want, where)


def _assert_table(got: list, want: list, where: str, rtol: float) -> None:
    """A CSV's rows (numbers as floats; the first row its header): each number within ``rtol`` of itself and
    :data:`TABLE_ATOL` of its column's largest (:data:`JERK_ATOL` in a jerk column), as loose as ``rtol`` is."""
    assert isinstance(got, list) and len(got) == len(want), f"{where}: {len(got)} rows, want {len(want)}"
    if not want:
        return
    header, loose = want[0], rtol / RTOL
    scale = [max((abs(r[j]) for r in want if isinstance(r[j], float)), default=0.0) for j in range(len(header))]
    share = [JERK_ATOL if JERK_COLUMN.match(str(h)) else TABLE_ATOL for h in header]
    for i, (g, w) in enumerate(zip(got, want, strict=True)):
        assert isinstance(g, list) and len(g) == len(w), f"{where}[{i}]: {g!r:.200}, want {w!r:.200}"
        for j, (a, b) in enumerate(zip(g, w, strict=True)):
            assert_same(a, b, f"{where}[{i}][{j}]", ATOL + loose * share[j] * scale[j], rtol)


@pytest.mark.slow
@pytest.mark.parametrize("case", shipped_cases(), ids=golden_name)
def test_golden(case):
    want = json.loads(gzip.decompress(golden_file(case).read_bytes()))
    name = golden_name(case)
    assert_same(snapshot(case), want, name)


def test_assert_same_fails_on_a_change():
    """The comparison can fail: a float off by 1e-4, a key out of order, a string changed, a table's cell off by
    3e-5 of itself or of its column, a round-off-sized number off by more than round-off, an error measure 3 times
    as large, an extreme's place not an angle."""
    want = {
        "a": 1.0, "b": "x", "c": [1, True], "rows": [["s_mm", "v"], [0.0, 2.0], [1e-9, -3.0]], "e": 1e-12,
        "periodicity_error": 1e-6, "motion_table_error": {"s1": 2e-3}, "least_contact_force_deg": 30.0,
    }  # fmt: skip
    near = {
        "a": 1.0 + 1e-6, "e": 3e-11, "rows": [["s_mm", "v"], [1e-8, 2.0], [0.0, -3.0]], "periodicity_error": 1.5e-6,
        "motion_table_error": {"s1": 1.2e-3}, "least_contact_force_deg": 250.0,
    }  # fmt: skip
    assert_same({**want, **near}, want)
    for got in (
        {**want, "periodicity_error": 3e-6},
        {**want, "motion_table_error": {"s1": 6e-3}},
        {**want, "least_contact_force_deg": None},
        {**want, "a": 1.0 + 1e-4},
        {**want, "rows": [["s_mm", "v"], [0.0, 2.0], [1e-9, -3.0 + 1e-4]]},
        {**want, "rows": [["s_mm", "v"], [3e-5, 2.0], [1e-9, -3.0]]},
        {**want, "e": 1e-6},
        {"b": "x", "a": 1.0, "c": [1, True], "rows": want["rows"], "e": 1e-12},
        {**want, "b": "y"},
        {**want, "c": [1, 1]},
    ):
        with pytest.raises(AssertionError):
            assert_same(got, want)
