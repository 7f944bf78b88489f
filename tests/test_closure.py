"""Form-closed cams (issue 25): the groove's schema, its two walls, the signed contact force and its crossovers,
and the flight across the backlash."""

import copy

import numpy as np
import pytest
from _helpers import distance_to_outline

from camdyn import InputError
from camdyn.model.case import case_from_dict
from camdyn.model.geometry import analyze, groove

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


def case_geometry_pitch(case, n: int) -> np.ndarray:
    """The pitch curve (2, n), mm, on n equal steps."""
    return analyze(case.motion, case.follower, n=n).pitch


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


def test_groove_walls_lie_at_roller_radius_plus_half_backlash():
    """Each wall lies Rr + b/2 from the pitch curve (its distance from a dense pitch polyline), and on a dwell at
    the closed-form radii Rb + s - b/2 and Rb + 2 Rr + s + b/2 with radii of curvature -+(Rp + s) - d."""
    case = case_from_dict(GROOVE)
    g = groove(case.motion, case.follower, n=3600)
    rb, rr, b = 50.0, 12.0, 0.05
    d = rr + b / 2
    assert g.wall_offset_mm == pytest.approx(d)
    pitch = np.asarray(case_geometry_pitch(case, 40_000))
    for wall in (g.inner, g.outer):
        dist = distance_to_outline(wall[:, ::7].T, pitch.T)
        assert np.max(np.abs(dist - d)) < 2e-4  # the polyline's chord error at 40 000 points is ~1e-5 mm
    i = int(np.argmin(np.abs(g.theta_deg - 150.0)))  # on the top dwell: lift 20
    assert np.hypot(*g.inner[:, i]) == pytest.approx(rb + 20 - b / 2, abs=1e-9)
    assert np.hypot(*g.outer[:, i]) == pytest.approx(rb + 2 * rr + 20 + b / 2, abs=1e-9)
    assert g.rho_inner_mm[i] == pytest.approx(rb + rr + 20 - d, rel=1e-9)
    assert g.rho_outer_mm[i] == pytest.approx(-(rb + rr + 20 + d), rel=1e-9)
    # one wall concave where the other is convex
    assert np.all(np.sign(g.rho_inner_mm + d) == -np.sign(g.rho_outer_mm + d))
    assert not g.undercut and g.outer_wall.min_convex_radius_mm > 0


def test_groove_wall_undercut_where_the_pitch_curve_turns_tighter_than_the_wall():
    """A concave stretch of the pitch curve tighter than Rr + b/2 folds the outer wall, not the inner."""
    raw = _with("follower", base_radius=25, roller_radius=10)
    raw["motion"]["segments"][0] = {"law": "cycloidal", "end": 40, "lift": 20}
    raw["motion"]["segments"][1] = {"law": "dwell", "end": 180}
    case = case_from_dict(raw)
    g = groove(case.motion, case.follower, n=3600)
    assert g.outer_wall.undercut and not g.inner_wall.undercut
    assert g.outer_wall.min_convex_radius_mm < 0 < g.inner_wall.min_convex_radius_mm
    rho_p = analyze(case.motion, case.follower, n=3600).rho_pitch_mm  # the spring cam's pitch curve
    assert g.outer_wall.min_convex_radius_mm == pytest.approx(np.max(rho_p[rho_p < 0]) * -1 - 10.025, abs=1e-3)
