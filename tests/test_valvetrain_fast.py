"""The valvetrain's fast path (issue 24): the exact linear solution of the valve event where every contact stays
closed, checked against the event-driven diffrax model (an independent integrator of the same equations at
tight tolerance), and the points it must hand to that model: float, a compliant cam contact."""

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from camdyn._core.units import RPM, THETA_GRID
from camdyn.design.parts import resolve_spring
from camdyn.model.case import case_from_dict, load_case
from camdyn.model.dynamics import (
    ValvePoint,
    ValveSummary,
    bounce_speed,
    fast_valve_summary,
    float_speed,
    jump_search_limit,
    kinematic_jump_speed,
    valvetrain_response,
)
from camdyn.model.dynamics._valveevent import revolution
from camdyn.model.dynamics._valvefast import Floated
from camdyn.model.dynamics._valvefield import CAM, SEAT, TRAIN
from camdyn.model.dynamics._valvelinear import batched_expm
from camdyn.model.dynamics._valvetrain import _Impacts, _transition

CASES = Path(__file__).resolve().parents[1] / "cases"
SHIPPED = tomllib.loads((CASES / "valvetrain.toml").read_text())


def _variant(dynamics=None, valvetrain=None):
    raw = copy.deepcopy(SHIPPED)
    raw["dynamics"] |= dynamics or {}
    raw["valvetrain"] |= valvetrain or {}
    return case_from_dict(raw)


@pytest.fixture(scope="module")
def shipped():
    return load_case(CASES / "valvetrain.toml")


def _same(fast: ValveSummary, resp, lift_rel: float = 1e-9) -> None:
    """The fast path's numbers against the diffrax model's: forces to 1e-6 of the preload's push at the cam,
    the seating speed and the bounce to 1e-6 and 1e-5 relative, the largest lift to ``lift_rel`` (both solve the same
    equations; the diffrax model at rtol 1e-10)."""
    scale = 1e-6 * 1.6 * 300.0  # N
    assert fast.least_event_force == pytest.approx(resp.least_event_force, abs=scale)
    assert fast.least_event_force_deg == pytest.approx(resp.least_event_force_deg, abs=1e-9)
    assert fast.least_train_force == pytest.approx(resp.least_train_force, abs=scale)
    assert fast.seating_velocity == pytest.approx(resp.seating_velocity, rel=1e-6)
    assert fast.seating_deg == pytest.approx(resp.seating_deg, abs=1e-6)
    assert fast.bounce_height_mm == pytest.approx(resp.bounce_height_mm, rel=1e-5, abs=1e-9)
    assert fast.max_valve_lift_mm == pytest.approx(resp.max_valve_lift_mm, rel=lift_rel)


def _agrees(case, rpm: float):
    """The fast path's summary of ``case`` at ``rpm`` and the diffrax model's revolution there, checked equal
    (:func:`_same`, and the gap at the valve to 1e-8 mm), the valve not floating."""
    vt, w = case.valvetrain, rpm * RPM
    fast = fast_valve_summary(case.motion, vt, w)
    assert isinstance(fast, ValveSummary)
    resp = valvetrain_response(case.motion, vt, w)
    assert not resp.floated and resp.settled
    _same(fast, resp)
    assert fast.max_gap_mm == pytest.approx(resp.max_gap_mm(vt), abs=1e-8)
    return fast, resp


ROCKER = {"cam_arm": 25.0, "valve_arm": 40.0, "cam_arm_angle": -7.3, "valve_arm_angle": -2.0}


def _scaled_lifts(factor: float, dynamics=None, rocker=None):
    """The shipped case with every lift times ``factor``: its ramps' constant velocities no longer fit their lifts.
    ``rocker``: a ``[valvetrain.rocker]`` in place of the ratio."""
    raw = copy.deepcopy(SHIPPED)
    raw["motion"]["segments"] = [
        s | {"lift": s["lift"] * factor} if "lift" in s else s for s in raw["motion"]["segments"]
    ]
    raw["dynamics"] |= dynamics or {}
    if rocker is not None:
        del raw["valvetrain"]["ratio"]
        raw["valvetrain"]["rocker"] = rocker
    return case_from_dict(raw)


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [1500.0, 3000.0, 5000.0, 5900.0])
def test_fast_path_equals_the_diffrax_model_on_the_shipped_case(shipped, rpm):
    """Below the float speed (5920 rpm) every contact of the shipped case stays closed over the event; the rebounds
    off the seat run on the train and, from about 3500 rpm, off it (the gap at the valve): all on the fast path."""
    _, resp = _agrees(shipped, rpm)
    point = ValvePoint(shipped.motion, shipped.valvetrain, rpm * RPM)
    assert point.fast and not point.floated and point.bounced == resp.bounced


@pytest.mark.slow
@pytest.mark.parametrize(
    ("valvetrain", "rpm"),
    [
        ({"stiffness": 3000.0, "lash": 0.15, "seat_restitution": 0.4}, 3000.0),  # a soft train: long rebounds
        ({"stiffness": 1e6, "lash": 0.0, "tappet_force": 20.0}, 4500.0),  # a stiff train, no lash, a tappet spring
    ],
)
def test_fast_path_equals_the_diffrax_model_on_other_trains(valvetrain, rpm):
    case = _variant(valvetrain=valvetrain)
    fast = fast_valve_summary(case.motion, case.valvetrain, rpm * RPM)
    assert isinstance(fast, ValveSummary)
    _same(fast, valvetrain_response(case.motion, case.valvetrain, rpm * RPM))


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [3000.0, 5500.0])
def test_fast_path_follows_rebounds_where_the_closing_ramp_decelerates(rpm):
    """Every lift 1 % higher: the ramps' constant velocities no longer fit their lifts, so the closing ramp
    decelerates (s'' down to -0.03 mm/rad^2) while the lash is still closed and the valve rebounds off its seat. With
    no tappet force the follower's own force on the cam is negative there, but the train still presses it on: the
    cam force the fast path judges a rebound by carries the train's share, and it answers as the diffrax model."""
    fast, _ = _agrees(_scaled_lifts(1.01), rpm)
    assert fast.bounce_height_mm > 1e-3  # it rebounds


@pytest.mark.slow
@pytest.mark.parametrize(("restitution", "rpm"), [(0.0, 1500.0), (0.0, 3000.0), (0.3, 1500.0)])
def test_fast_path_follows_the_follower_off_the_cam_while_the_valve_is_seated(restitution, rpm):
    """Every lift 2 % lower: the opening ramp decelerates (s'' down to -0.2 mm/rad^2) with the lash open and no
    tappet force, so the follower leaves the cam at 42 deg, the lash closes under it in the air and the train
    presses it back; it leaves the closing ramp again after the valve has seated. Each flight lands (rebounding at
    the cam's restitution) before the valve lifts or the revolution ends: the valve's event is the one the diffrax
    model gives, on the fast path."""
    case = _scaled_lifts(0.98, {"restitution": restitution})
    fast, resp = _agrees(case, rpm)
    landings = [e for e in resp.events if e.what == "cam-landing"]
    assert len(landings) >= (2 if restitution == 0.0 else 6)
    assert min(e.deg for e in landings) < 60.0 < 300.0 < max(e.deg for e in landings)  # before and after the event


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [1500.0, 4500.0])
def test_fast_path_on_a_valve_table_whose_follower_flies_over_the_revolutions_start(tmp_path, rpm):
    """cases/valve-lift.csv as the lift at the valve through a 1.5 rocker: the fitted table's base circle and ramps
    wave by a few um, and with no tappet force the follower hops along them, one flight over the revolution's
    start, so the diffrax model never comes back to rest (its last revolution reported, with the flight carried into
    it). The fast path carries that flight into the revolution's start, where it lands before the valve lifts: the
    valve's event is the diffrax model's."""
    (tmp_path / "valve.csv").write_text((CASES / "valve-lift.csv").read_text())
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {"valve_table": str(tmp_path / "valve.csv")}
    raw["valvetrain"] |= {"ratio": 1.5}
    case = case_from_dict(raw)
    vt, w = case.valvetrain, rpm * RPM
    fast = fast_valve_summary(case.motion, vt, w)
    assert isinstance(fast, ValveSummary)
    resp = valvetrain_response(case.motion, vt, w)
    assert not resp.settled and not resp.floated
    assert sum(e.what == "cam-landing" for e in resp.events) >= 2
    _same(fast, resp)
    assert fast.max_gap_mm == pytest.approx(resp.max_gap_mm(vt), abs=1e-8)


@pytest.mark.slow
def test_a_follower_off_the_cam_while_the_valve_rebounds_falls_back():
    """At 4500 rpm the same follower leaves the closing ramp while the valve still rebounds off its seat (the two
    flights meet through the train): the diffrax model's point."""
    case = _scaled_lifts(0.98)
    assert fast_valve_summary(case.motion, case.valvetrain, 4500.0 * RPM) is None


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [1500.0, 3000.0])
def test_fast_path_follows_a_flying_follower_that_the_train_holds_through_a_rocker(rpm):
    """The 2 % lower lifts through a rocker: the train takes hold of the flying follower where the lash closes under
    it, its push (a rocker's ratio moves with the follower's lift) not linear: Runge-Kutta on the fine steps' substeps
    to the landing, the valve's event then the diffrax model's."""
    case = _scaled_lifts(0.98, rocker=ROCKER)
    _, resp = _agrees(case, rpm)
    assert sum(e.what == "cam-landing" for e in resp.events) >= 2


@pytest.mark.slow
def test_a_point_that_floats_falls_back(shipped):
    """At 6500 rpm the cam contact opens in the event: the exact solution says so (float, least force 0), and the
    rest (seating, bounce: a flight) is the diffrax model's, run for that point only."""
    vt, w = shipped.valvetrain, 6500.0 * RPM
    floated = fast_valve_summary(shipped.motion, vt, w)
    assert isinstance(floated, Floated) and floated.least_force < 0.0
    point = ValvePoint(shipped.motion, vt, w)
    assert point.floated and point.least_event_force == 0.0 and not point.fast
    resp = valvetrain_response(shipped.motion, vt, w)
    assert resp.floated
    assert point.seating_velocity == resp.seating_velocity and point.bounce_height_mm == resp.bounce_height_mm
    assert point.max_gap_mm() == resp.max_gap_mm(vt)


# a never-seen valve cam (the latency benchmark's seed 900): the lash closes on a 4.37 mm modified-sine rise in 20 deg
THROWN = [
    {"law": "dwell", "end": 90},
    {"law": "modified-sine", "end": 110, "lift": 4.37},
    {"law": "dwell", "end": 120},
    {"law": "harmonic", "end": 140, "lift": 7.545},
    {"law": "modified-trapezoid", "end": 150, "lift": 6.964},
    {"law": "cycloidal", "end": 180, "lift": -6.964},
    {"law": "dwell", "end": 190},
    {"law": "polynomial-4567", "end": 300, "lift": -7.545},
    {"law": "modified-trapezoid", "end": 360, "lift": -4.37},
]


def _with_segments(segments):
    """The shipped case with another segment list."""
    raw = copy.deepcopy(SHIPPED)
    raw["motion"]["segments"] = segments
    return case_from_dict(raw)


@pytest.fixture(scope="module")
def thrown():
    return _with_segments(THROWN)


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [575.0, 700.0])
def test_fast_path_follows_the_valve_thrown_off_its_train(thrown, rpm):
    """Just after the lift the valve outruns its train (the diffrax model's train force is 0 at 94.5 deg and on,
    for 0.1-0.3 deg), flies on its spring and is caught again: the fast path follows it off the train and back (its
    answer was the diffrax model's, 23 revolutions a check) and gives the diffrax model's event, seating, bounce and
    gap."""
    fast, resp = _agrees(thrown, rpm)
    assert fast.least_train_force == resp.least_train_force == 0.0
    off = (resp.train_force <= 0.0) & resp.in_event
    assert 94.0 < float(resp.theta_deg[off].min()) < float(resp.theta_deg[off].max()) < 96.0  # off it at the opening


def test_the_trains_push_is_held_to_each_side_of_an_acceleration_jump(thrown):
    """The train's push on the valve is held between the fine angles as the cubic through its values and slopes
    (kt g + ct w g', and kt g' + ct w g''): where g'' jumps at a segment's end (the dwell into the harmonic rise at 120
    deg) the step that ends there takes the slope from before the jump, the dwell's 0, and the next one the
    harmonic's, L pi^2 / (2 beta^2) at the valve (once read on both sides: the valve's lift 3e-6 mm off the
    diffrax model's near the thrown cam's breaks)."""
    rev = revolution(thrown.motion, thrown.valvetrain, THETA_GRID)
    i = int(np.argmin([abs(rev.deg(k, 0.0) - 120.0) for k in range(rev.g.size)]))
    ratio, lift, beta = 1.6, 7.545e-3, np.radians(20.0)
    assert rev.g2_before[i] == 0.0 and rev.s2_before[i] == 0.0
    assert rev.g2[i] == pytest.approx(ratio * lift * np.pi**2 / (2 * beta**2), rel=1e-9)
    jumps = np.abs(rev.g2_before - rev.g2) > 0.0
    assert np.count_nonzero(jumps) <= 2 * len(THROWN)  # only at segments' ends


@pytest.mark.slow
def test_a_valve_thrown_off_its_train_that_floats_later(thrown):
    """At 750 rpm the valve leaves its train at the opening and the cam lets go of the follower at 145.6 deg: the
    float search's answer is :class:`Floated` (the force the cam would pull with, the follower held on it: the diffrax
    model's float force near the float speed, where the search looks), and followed through the float (``floats``)
    the diffrax model's event; the float speed is the diffrax model's within the search's 1 rpm."""
    vt, w = thrown.valvetrain, 750.0 * RPM
    resp = valvetrain_response(thrown.motion, vt, w)
    assert resp.floated and resp.least_train_force == 0.0
    floated = fast_valve_summary(thrown.motion, vt, w)
    assert isinstance(floated, Floated) and floated.least_force < -600.0
    fast = fast_valve_summary(thrown.motion, vt, w, floats=True)
    assert isinstance(fast, ValveSummary) and fast.floated
    # the flight's contact changes (the train taking hold and letting go, the landing: force and speed jumps) are
    # where the fast path interpolates its roots (to the square of its last cut): the flight's lifts 5e-7 mm apart,
    # and its hold, which rides on the stiff train's deflection, 7e-6 of itself
    _same(fast, resp, lift_rel=1e-7)
    assert fast.max_gap_mm == pytest.approx(resp.max_gap_mm(vt), abs=1e-6)
    assert fast.hold_force == pytest.approx(resp.float_force, rel=2e-5)
    w_max = 1000.0 * RPM
    on_fast = float_speed(thrown.motion, vt, w_max) / RPM
    alone = float_speed(thrown.motion, vt, w_max, respond=lambda w: _Diffrax(valvetrain_response(thrown.motion, vt, w)))
    assert on_fast == pytest.approx(alone / RPM, abs=1.0)
    assert not valvetrain_response(thrown.motion, vt, (on_fast - 0.5) * RPM).floated


# another (seed 925): the lash closes on a 3.25 mm modified trapezoid in 10 deg, with no ramp
SLAMMED = [
    {"law": "dwell", "end": 70},
    {"law": "modified-trapezoid", "end": 80, "lift": 3.249},
    {"law": "dwell", "end": 110},
    {"law": "polynomial-4567", "end": 210, "lift": -3.249},
    {"law": "dwell", "end": 360},
]


@pytest.mark.slow
def test_a_lash_closed_fast_lifts_the_valve_off_its_seat_in_the_diffrax_model():
    """At 2450 rpm the train's damping alone pushes past the preload as the lash closes (71.7 deg): the seat's force
    jumps through zero. The diffrax model took the least of its contacts' conditions there for the contact that
    changed: a compliant train's, a constant 1 N, under the seat's 300 N read before the jump, so it closed the lash
    of a rigid train and locked the train rigid through the event (the valve to 19.3 mm, where the fast path's
    exact solution lifts it to 24.9). Now the seat lets the valve go, and the two agree through the floats that
    follow (three landings with the cam's restitution: the seating's speed to 4e-4 of itself)."""
    case = _with_segments(SLAMMED)
    vt, w = case.valvetrain, 2450.0 * RPM
    resp = valvetrain_response(case.motion, vt, w)
    whats = [e.what for e in resp.events]
    assert whats[:2] == ["valve-lift", "float"] and "lash" not in whats  # a compliant train has no lash event
    fast = fast_valve_summary(case.motion, vt, w, floats=True)
    assert isinstance(fast, ValveSummary) and fast.floated and resp.floated
    assert fast.max_valve_lift_mm == pytest.approx(resp.max_valve_lift_mm, rel=1e-7)  # 24.9 mm
    assert fast.hold_force == pytest.approx(resp.float_force, rel=1e-9)
    assert fast.seating_deg == pytest.approx(resp.seating_deg, abs=2e-3)
    assert fast.seating_velocity == pytest.approx(resp.seating_velocity, rel=1e-3)
    assert fast.bounce_height_mm == pytest.approx(resp.bounce_height_mm, rel=1e-3)


def test_a_contact_whose_condition_jumps_through_zero_is_the_one_that_changed(shipped):
    """Where a stretch ends, the diffrax model reads each contact's event function there and a hair past it: a seat
    force that jumps through zero (300 N before, -500 N after: a compliant train's damping as it closes the lash
    fast) is the change, though the locked cam's force (100 N) reads less before it; the valve lifts, the cam
    holds."""

    modes = np.array([True, False, True])  # the cam locked, the train compliant, the valve seated
    state = np.array([1e-3, 0.01, 1e-3, 0.01, 0.0, 0.0, 0.0])  # s, s', x_c, x_c', x_v, x_v' (m, m/rad), spare
    before, after = np.array([100.0, np.inf, 300.0]), np.array([100.0, np.inf, -500.0])
    impacts = _Impacts(0.0, 0.3, 300.0, 1e-6)
    y = np.zeros(4)
    event, changed, _ = _transition(shipped.valvetrain, impacts, modes, np.concatenate([state, before]), y, 1.2, after)
    assert event is not None and event.what == "valve-lift"
    assert changed[CAM] and not changed[TRAIN] and not changed[SEAT]


class _Diffrax:
    """A :class:`ValvePoint` stand-in that is the diffrax model's response only (the float search reads its
    ``float_force``)."""

    def __init__(self, resp) -> None:
        self.float_force = resp.float_force


def _same_through_float(fast, resp, vt) -> None:
    """:func:`_same`, for a valve that floated: the float search's force (the least the cam would have to pull
    with) to 1e-5 N of the forces' 1e3, the gap at the valve to 1e-8 mm."""
    assert isinstance(fast, ValveSummary) and fast.floated and resp.floated
    _same(fast, resp)
    assert fast.hold_force == pytest.approx(resp.float_force, abs=1e-5)
    assert fast.max_gap_mm == pytest.approx(resp.max_gap_mm(vt), abs=1e-8)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("dynamics", "valvetrain", "rpm", "floats"),
    [
        ({}, {}, 6000.0, 1),  # one float near the nose, the follower landing on the flank
        ({}, {}, 6625.0, 2),  # two, the second 75 deg long; back on the cam the train lets the valve go
        ({"restitution": 0.3}, {}, 6400.0, 1),  # the follower rebounds off the cam
        ({}, {"tappet_force": 20.0}, 6800.0, 1),  # a tappet spring pulls the follower back in its flight
    ],
)
def test_fast_path_follows_the_valve_through_its_float(dynamics, valvetrain, rpm, floats):
    """Past the float speed the two masses fly on the train (or off it) and the follower lands on the cam again
    before the valve seats: the fast path follows them (``floats``) and gives the diffrax model's event, seating,
    bounce, gap and float force."""
    case = _variant(dynamics, valvetrain)
    vt, w = case.valvetrain, rpm * RPM
    resp = valvetrain_response(case.motion, vt, w)
    assert sum(e.what == "float" for e in resp.events) == floats
    _same_through_float(fast_valve_summary(case.motion, vt, w, floats=True), resp, vt)
    assert isinstance(fast_valve_summary(case.motion, vt, w), Floated)  # the float search's answer stays the same
    point = ValvePoint(case.motion, vt, w, floats=True)
    assert point.fast and point.floated and point.float_force == pytest.approx(resp.float_force, abs=1e-5)


@pytest.mark.slow
def test_fast_path_follows_a_float_before_the_valve_has_risen(tmp_path):
    """cases/valve-lift.csv as the valve's lift through a 1.5 ratio at 4800 rpm: the cam lets go of the follower 13
    deg into the valve's lift, before the valve has risen past half its lift, while the follower also hops along
    the table's base circle: the event, followed through the float, is the diffrax model's."""
    (tmp_path / "valve.csv").write_text((CASES / "valve-lift.csv").read_text())
    raw = copy.deepcopy(SHIPPED)
    raw["motion"] = {"valve_table": str(tmp_path / "valve.csv")}
    raw["valvetrain"] |= {"ratio": 1.5}
    case = case_from_dict(raw)
    vt, w = case.valvetrain, 4800.0 * RPM
    resp = valvetrain_response(case.motion, vt, w)
    lift, float_at = (next(e.deg for e in resp.events if e.what == what) for what in ("valve-lift", "float"))
    assert float_at - lift < 20.0
    _same_through_float(fast_valve_summary(case.motion, vt, w, floats=True), resp, vt)


@pytest.mark.slow
def test_a_valve_that_seats_while_the_follower_flies_falls_back(shipped):
    """At 6850 rpm the valve seats while the follower is still in the air: the diffrax model's point; a rocker's
    float (its ratio moves with the flying follower) is the diffrax model's at once."""
    vt, w = shipped.valvetrain, 6850.0 * RPM
    assert fast_valve_summary(shipped.motion, vt, w, floats=True) is None
    case = _scaled_lifts(1.0, rocker=ROCKER)
    point = ValvePoint(case.motion, case.valvetrain, w, floats=True)
    assert point.floated and not point.fast


@pytest.mark.slow
def test_check_follows_the_float_on_the_fast_path_past_the_float_speed(shipped):
    """The bounce search's speeds past the float speed follow the float on the fast path (those below, and the float
    search's, stop at it: its force is the search's); where that cannot say, the diffrax model's."""
    from camdyn.design.valvetrain import analyze_valvetrain

    result = analyze_valvetrain(shipped, shipped.speed_rpm * RPM, 1.25)
    through = [p for p in result.marched if p._floats]  # the bounce search's past the float speed
    assert len(through) >= 8 and all(p.omega / RPM > result.float_speed_rpm for p in through)
    assert sum(p.fast for p in through) >= 4  # answered through the float
    assert all(p._response is not None for p in through if not p.fast)
    assert result.bounce_speed_rpm == pytest.approx(6625.9, abs=0.5)


@pytest.mark.slow
def test_float_and_bounce_speeds_equal_the_diffrax_models(shipped):
    """The searches on the fast path (the diffrax model where the valve floats) give the speeds the diffrax model
    alone gives: the bounce search to 0.1 rpm (the same bisection: every speed's verdict agrees); the float search's
    interpolation, on the fast path's force continued past the float speed (the diffrax model's is 0 there), within
    the search's 1 rpm, and the diffrax model floats 0.5 rpm above its answer and holds 0.5 rpm below."""
    vt = shipped.valvetrain
    w_max = jump_search_limit(1.25 * shipped.speed_rpm * RPM, kinematic_jump_speed(shipped.motion, shipped.model)[0])
    slow: dict[float, object] = {}

    def diffrax_only(w):
        if w not in slow:
            slow[w] = valvetrain_response(shipped.motion, vt, w)
        return slow[w]

    fast: dict[float, ValvePoint] = {}

    def points(w):
        if w not in fast:
            fast[w] = ValvePoint(shipped.motion, vt, w)
        return fast[w]

    for search, within in ((float_speed, 1.0), (bounce_speed, 0.1)):
        ref = search(shipped.motion, vt, w_max, respond=diffrax_only)
        assert search(shipped.motion, vt, w_max, respond=points) / RPM == pytest.approx(ref / RPM, abs=within)
    w_float = float_speed(shipped.motion, vt, w_max, respond=points)
    # the bounce search as check runs it: past the float speed through the floats on the fast path
    through = {w: p for w, p in fast.items() if w <= w_float}

    def as_check(w):
        if w not in through:
            through[w] = ValvePoint(shipped.motion, vt, w, floats=w > w_float)
        return through[w]

    ref = bounce_speed(shipped.motion, vt, w_max, respond=diffrax_only)
    assert bounce_speed(shipped.motion, vt, w_max, respond=as_check) / RPM == pytest.approx(ref / RPM, abs=0.1)
    assert sum(p.fast for w, p in through.items() if w > w_float) >= 4
    assert w_float / RPM == pytest.approx(5920.06, abs=0.5)
    assert not diffrax_only(w_float - 0.5 * RPM).floated and diffrax_only(w_float + 0.5 * RPM).floated
    assert sum(p.fast for p in fast.values()) >= 8  # the speeds below float, on the fast path


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [1500.0, 4500.0, 5900.0])
def test_fast_path_equals_the_diffrax_model_through_a_rocker(rpm):
    """Through a rocker whose ratio varies with lift (1.61 on the base circle, 1.58 at 6 mm of follower lift) the
    valve's equation is still linear where the follower moves with the cam: the cam's lift at the valve is a known
    function of the angle. The fast path's numbers are the diffrax model's (it floats at 5916 rpm); from 4500 rpm the
    valve rebounds off the train (a gap at the valve)."""
    case = _scaled_lifts(1.0, rocker=ROCKER)
    ratios = case.valvetrain.at_valve_mm(np.array([0.0, 6.0]))[1]
    assert ratios[0] > ratios[1] + 0.03  # not a constant ratio
    fast, _ = _agrees(case, rpm)
    assert (fast.max_gap_mm > 1e-3) == (rpm > 3000.0)


@pytest.fixture(scope="module")
def rigid_train():
    """The shipped valvetrain with a rigid train (no ``valvetrain.stiffness``): its ramps take up the lash."""
    raw = copy.deepcopy(SHIPPED)
    del raw["valvetrain"]["stiffness"]
    return case_from_dict(raw)


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [1500.0, 5000.0, 6190.0])
def test_fast_path_equals_the_diffrax_model_with_a_rigid_train(rigid_train, rpm):
    """A rigid train moves the valve with the cam from the lash's closing (a plastic impact) to its seating at the
    ramp's speed, the forces algebraic in the angle; each rebound flies on the spring alone. The fast path's numbers
    are the diffrax model's up to its float at 6194 rpm (the least cam force 1.7 N at 6190 rpm)."""
    fast, _ = _agrees(rigid_train, rpm)
    assert fast.seating_velocity == pytest.approx(0.135 * rpm / 1500.0, rel=1e-6)  # the ramp's 0.135 m/s at 1500 rpm


@pytest.mark.slow
def test_a_rigid_train_that_floats_falls_back(rigid_train):
    """At 6300 rpm the cam force falls below zero in the event: the fast path says so, with the force the cam would
    have to pull with (near the diffrax model's), and the diffrax model runs the flight."""
    vt, w = rigid_train.valvetrain, 6300.0 * RPM
    floated = fast_valve_summary(rigid_train.motion, vt, w)
    assert isinstance(floated, Floated)
    resp = valvetrain_response(rigid_train.motion, vt, w)
    assert resp.floated and floated.least_force == pytest.approx(resp.float_force, rel=1e-3)


def _with_surge(rigid_train: bool = False):
    """The shipped valvetrain with its spring designed as a part whose coils surge (``[spring] model = "surge"``: a
    chain of 16 segments on the valve); ``rigid_train``: without the train's stiffness."""
    raw = copy.deepcopy(SHIPPED)
    raw["spring"] = {"material": "chrome-silicon", "model": "surge"}
    raw["valvetrain"]["valve_mass"] = 0.055  # the valve, retainer and keepers: the chain's half lump joins them
    if rigid_train:
        del raw["valvetrain"]["stiffness"]
    return resolve_spring(case_from_dict(raw))


@pytest.fixture(scope="module")
def surge():
    return _with_surge()


@pytest.mark.slow
@pytest.mark.parametrize("rpm", [1500.0, 4500.0, 5020.0])
def test_fast_path_equals_the_diffrax_model_with_the_springs_surge_chain(surge, rpm):
    """With the surge chain the valve's systems carry its 15 inner lumps and the chain rings on over the seated
    valve, so the valve lifts where the train's force passes the chain's; the diffrax model reports the second
    revolution from rest, and so does the fast path (from the first one's ringing: without it the least cam force is
    1.4 N off at 1500 rpm, 21 N at 4500 rpm). Equal up to 5020 rpm (float at 5027 rpm, the least cam force 7.2 N);
    from 4500 rpm the valve rebounds off the train."""
    assert surge.valvetrain.coils.count == 16
    fast, _ = _agrees(surge, rpm)
    assert (fast.max_gap_mm > 1e-5) == (rpm > 3000.0)


@pytest.mark.slow
def test_a_surge_chain_that_floats_from_rest_falls_back(surge):
    """At 5300 rpm the valve floats in the revolution from rest: what the chain carries into the next one is the
    flight's, so the point is the diffrax model's whole; so is a rigid train's with the chain."""
    w = 5300.0 * RPM
    assert fast_valve_summary(surge.motion, surge.valvetrain, w) is None
    point = ValvePoint(surge.motion, surge.valvetrain, w)
    assert point.floated and not point.fast
    rigid = _with_surge(rigid_train=True)
    assert rigid.valvetrain.rigid_train and fast_valve_summary(rigid.motion, rigid.valvetrain, 3000.0 * RPM) is None


def test_a_compliant_cam_falls_back(shipped):
    """What the fast path does not model yet goes to the diffrax model whole: a compliant cam contact (a 2-DOF
    event)."""
    w = 3000.0 * RPM
    compliant = _variant(dynamics={"train_stiffness": 2e4, "train_damping_ratio": 0.05})
    assert fast_valve_summary(compliant.motion, compliant.valvetrain, w) is None
    assert isinstance(fast_valve_summary(shipped.motion, shipped.valvetrain, w), ValveSummary)


def test_batched_matrix_exponential_against_scipy():
    """The augmented propagators' exponential (batched Taylor with scaling and squaring) against scipy's Pade:
    a valve on its train (1.7 kHz, 5 % damping) at 1000 to 8000 rpm over steps of 1e-7 to 0.05 deg."""
    rng = np.random.default_rng(1)
    for rpm in (1000.0, 8000.0):
        w = rpm * RPM
        z = np.zeros((7, 7))
        z[:2, :2] = [[0.0, 1.0], [-(8e6 + 4e4) / (0.07 * w**2), -(75.0 + 10.0) / (0.07 * w)]]
        z[1, 2], z[1, 6] = 1.0, -rng.uniform(1.0, 100.0)
        z[2, 3] = z[3, 4] = z[4, 5] = 1.0
        deltas = np.deg2rad(np.geomspace(1e-7, 0.05, 12))
        ours = batched_expm(z[None] * deltas[:, None, None])
        for d, e in zip(deltas, ours, strict=True):
            ref = expm(z * d)
            assert np.max(np.abs(e - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_modal_recurrence_against_the_loop():
    """The blocked cumulative sum that chains the steps against the recurrence stepped one at a time, every mode at
    once: a slowly and a quickly decaying mode (a stiff train: blocks of a few dozen steps, which the slow one shares),
    an undamped one, one gone within a step."""
    from camdyn.model.dynamics._valvelinear import recur

    lam = np.array([0.999 * np.exp(0.03j), 0.85 * np.exp(0.9j), 1.0 + 0.0j, 1e-14 + 0.0j])
    rng = np.random.default_rng(2)
    g = rng.normal(size=(4, 3000)) + 1j * rng.normal(size=(4, 3000))
    want = np.empty((4, 3001), complex)
    want[:, 0] = 0.3 - 0.2j
    for k in range(3000):
        want[:, k + 1] = lam * want[:, k] + g[:, k]
    got = recur(lam, g, want[:, 0])
    for i in range(4):
        assert np.max(np.abs(got[i] - want[i])) <= 1e-11 * np.max(np.abs(want[i]))
