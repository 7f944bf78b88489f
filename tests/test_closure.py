"""Form-closed cams (issue 25): the groove's schema, its two walls, the signed contact force and its crossovers,
and the flight across the backlash."""

import copy

import pytest

from camdyn import InputError
from camdyn.model.case import case_from_dict

GROOVE = {
    "name": "groove",
    "motion": {
        "segments": [
            {"law": "cycloidal", "end": 120, "lift": 20},
            {"law": "dwell", "end": 180},
            {"law": "cycloidal", "end": 300, "lift": -20},
            {"law": "dwell", "end": 360},
        ]
    },
    "follower": {
        "type": "translating-roller",
        "base_radius": 50,
        "roller_radius": 12,
        "closure": "groove",
        "backlash": 0.05,
    },
    "dynamics": {"speed": 300, "mass": 1.0, "train_stiffness": 5000},
}


def _with(table: str, **keys) -> dict:
    raw = copy.deepcopy(GROOVE)
    raw[table].update(keys)
    return raw


def test_groove_needs_no_spring():
    case = case_from_dict(GROOVE)
    assert case.follower.form_closed and case.follower.backlash == 0.05
    assert float(case.model.stiffness) == 0.0 and float(case.model.preload) == 0.0
    assert case.limits.max_impact_velocity == 0.1


@pytest.mark.parametrize(
    ("table", "keys", "where", "match"),
    [
        ("follower", {"closure": "spring"}, "follower.backlash", "not used"),
        ("follower", {"closure": "conjugate"}, "follower.closure", "not built yet"),
        ("follower", {"type": "translating-flat", "roller_radius": None}, "follower.closure", "holds a roller"),
        ("follower", {"backlash": -1}, "follower.backlash", "greater than or equal"),
        ("limits", {"max_impact_velocity": 0}, "limits.max_impact_velocity", "greater than"),
    ],
)
def test_groove_keys_refused(table, keys, where, match):
    raw = _with(table, **keys) if table in GROOVE else dict(copy.deepcopy(GROOVE), **{table: keys})
    raw[table] = {k: v for k, v in raw[table].items() if v is not None}
    with pytest.raises(InputError, match=match) as err:
        case_from_dict(raw)
    assert err.value.where == where


def test_spring_closure_still_needs_the_spring():
    raw = _with("follower", closure="spring")
    del raw["follower"]["backlash"]
    with pytest.raises(InputError, match="required key is missing") as err:
        case_from_dict(raw)
    assert err.value.where == "dynamics.spring_rate"
