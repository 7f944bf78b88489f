"""Each check kind owns its words, its unit and how it judges: the report, the terminal and ``optimize`` read them
from the kind, never from a table of output keys kept beside it (issue 22)."""

import pytest

from camdyn.design.checks import Check, CheckKind


def test_every_check_kind_says_what_it_judges():
    for kind in CheckKind:
        assert kind.label and kind.label != kind.value, kind
        assert kind.sense in (">=", ">", "<="), kind
        assert isinstance(kind.unit, str), kind


@pytest.mark.parametrize("kind", list(CheckKind))
def test_a_kinds_check_carries_its_unit_and_its_margin_is_positive_where_it_passes(kind):
    limit = 2.0
    for value in (1.0, 2.0, 3.0):
        c = kind.check(value, limit)
        assert (c.name, c.unit, c.sense) == (kind.value, kind.unit, kind.sense)
        assert c.kind is kind and c.label == kind.label
        assert abs(c.margin) == abs(value - limit)
        if c.margin != 0.0:
            assert (c.margin > 0.0) == c.ok, (kind, value)
    assert kind.check(None, limit).margin is None  # unbounded


def test_a_flat_faces_curvature_is_a_radius():
    """A flat face's curvature check is in mm (the contour radius above a cusp), and says so."""
    flat = CheckKind.CURVATURE.check(5.0, 1e-6, "mm")
    assert flat.unit == "mm" and "no cusp" in flat.label and flat.json()["unit"] == "mm"
    assert "no cusp" not in CheckKind.CURVATURE.check(5.0, 1.5).label


def test_a_checks_json_is_the_contract():
    assert CheckKind.SPEED_MARGIN.check(1.5, 1.25).json() == {
        "name": "speed_margin",
        "value": 1.5,
        "limit": 1.25,
        "unit": "x",
        "ok": True,
    }
    assert Check("contact_force", 0.0, 0.0, "N", ">").ok is False
