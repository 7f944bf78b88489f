"""The report never contradicts itself (issue 21, section 3): flights and impacts counted from the force, the
shading exactly where the force is zero, page 1's decision-changing facts, jumps only above rounding, the
title block's hash, the flat face where its check puts it, legends clear of the curves."""

import hashlib
import math
import tomllib
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.path import Path as MplPath
from matplotlib.textpath import TextPath

from camdyn._core.results import Unavailable
from camdyn.design.checks import run_check
from camdyn.design.review import Review, _margin_response, _or_reason, sample_motion
from camdyn.design.spring import design_case_spring
from camdyn.design.tolerance import tolerance_study
from camdyn.export import FORMATS
from camdyn.model.case import case_from_dict, load_case
from camdyn.model.dynamics import Response
from camdyn.plot import flight_spans, plot_contact_force, plot_follower
from camdyn.report import A4, DPI, PAGES, STYLE, ReportData
from camdyn.report._layout import Flow, header, ink_width, text_width
from camdyn.report.pages._facts import decision_facts, key_results
from camdyn.report.pages._inputs import DIMENSIONLESS, UNITS, _kv_lines
from camdyn.report.pages.dynamics import _force_panels
from camdyn.report.pages.manufacturing import manufacturing_rows, segment_rows, title_block
from camdyn.report.pages.summary import draw_summary
from camdyn.schema import DynamicsSpec, FollowerSpec, LimitsSpec, RockerSpec, ValvetrainSpec

CASES = Path(__file__).resolve().parents[1] / "cases"


# ------------------------------------------------------------------------------ flights and impacts, synthetic
def synthetic(force, model="compliant", period_deg=10.0) -> Response:
    """A response on a 1 deg grid with the given interface force (N) and a flat cam."""
    n = force.size
    th = np.arange(n) * 360.0 / n
    z = np.zeros(n)
    return Response(
        model, 1.0, th, z, z + 0.1 * (force <= 0), z, force, force, (), 0.0, 0.0, contact_period_deg=period_deg
    )


def test_flights_are_the_runs_of_zero_force_and_impacts_their_landings():
    """Three spans of zero force (one wrapping through 0 deg) are three flights; each landing is an impact whose
    peak is the largest force within half a contact period after it, not the cam's later force."""
    f = np.full(360, 50.0)
    f[100:120] = 0.0  # flight 1: 100..119 deg
    f[120:125] = [300.0, 700.0, 400.0, 100.0, 60.0]  # its impact pulse, then the cam's force
    f[130:140] = 900.0  # later than half a contact period (5 deg) after landing: not the impact
    f[200:210] = 0.0  # flight 2, landing at 210 with a pulse of 250 N
    f[210:213] = [120.0, 250.0, 80.0]
    f[213:220] = 0.0  # flight 3 right after: the pulse between two flights is a whole impact
    f[350:] = 0.0  # flight 4 wraps: 350..4 deg
    f[:5] = 0.0
    r = synthetic(f)
    assert [(fl.leave_deg, fl.land_deg) for fl in r.flights] == [
        (100.0, 119.0),
        (200.0, 209.0),
        (213.0, 219.0),
        (350.0, 4.0),
    ]
    assert r.flights[-1].span_deg == pytest.approx(14.0)
    assert [(i.deg, i.peak_force, i.peak_deg) for i in r.impacts] == [
        (120.0, 700.0, 121.0),
        (210.0, 250.0, 211.0),
        (220.0, 50.0, 220.0),
        (5.0, 50.0, 5.0),
    ]
    assert r.max_impact_force == 700.0
    spans = flight_spans(r)
    assert spans == [(100.0, 119.0), (200.0, 209.0), (213.0, 219.0), (350.0, 360.0), (0.0, 4.0)]
    assert_shading_is_the_zero_force(r)


def test_no_flight_no_impact_and_a_rigid_landing_is_an_impulse():
    r = synthetic(np.full(360, 5.0))
    assert r.flights == () and r.impacts == () and r.max_impact_force == 0.0
    f = np.full(360, 5.0)
    f[10:20] = 0.0
    rigid = synthetic(f, model="rigid", period_deg=math.nan)
    (imp,) = rigid.impacts
    assert imp.deg == 20.0 and math.isnan(imp.peak_force) and math.isnan(rigid.max_impact_force)
    never = synthetic(np.zeros(360))
    assert len(never.flights) == 1 and never.impacts == ()


def assert_shading_is_the_zero_force(resp) -> None:
    """Every grid angle in a shaded span has zero force, and every angle of zero force is in a shaded span."""
    th = resp.theta_deg
    shaded = np.zeros(th.size, bool)
    for a, b in flight_spans(resp):
        shaded |= (th >= a - 1e-9) & (th <= b + 1e-9)
    assert np.array_equal(shaded, resp.force <= 0.0)


# ------------------------------------------------------------------------------------------ reviews, light
def light_review(case, check, *, margin=False, tolerance_samples=0) -> Review:
    """A review with what the tested facts need (the sizing and jump map left out: they are not facts here)."""
    margin_rpm = case.limits.speed_margin * check.speed_rpm
    resp = _margin_response(case, margin_rpm) if margin else Unavailable("not computed")
    tol = None
    if case.spec.tolerances is not None:
        tol = _or_reason(tolerance_study, case, tolerance_samples, 0)
    return Review(
        case,
        check,
        sample_motion(case),
        margin_rpm,
        resp,
        None,
        Unavailable("not sized"),
        Unavailable("no map"),
        _or_reason(design_case_spring, case),
        None,
        tol,
    )


@pytest.fixture(scope="module")
def fast_review(lecture_fast_case):
    return light_review(lecture_fast_case, run_check(lecture_fast_case), margin=True)


@pytest.mark.slow
def test_lecture_fast_page_one_counts_the_flights_and_impacts_of_the_plot(fast_review):
    """lecture-fast at 600 rpm leaves the cam 8 times (the 2 bouncing separations hold 6 impacts between flights)
    and lands 8 times, hardest at about 606 N; page 1, the JSON and the plots all say so; the shading is exactly
    where the force is zero, at 600 and at 750 rpm (3 flights, 3 impacts up to about 1530 N). At both speeds the
    bouncing repeats every other revolution: the revolution shown is the one of the two with the higher peak
    contact force."""
    chk = fast_review.check
    resp, doc = chk.response, chk.json()["dynamic"]
    assert len(resp.separations) == 2 and len(doc["separations"]) == 2  # the contract's separations stay
    assert len(resp.flights) == len(doc["flights"]) == 8 and len(resp.impacts) == len(doc["impacts"]) == 8
    assert doc["max_impact_force_N"] == pytest.approx(resp.max_impact_force) == pytest.approx(606.0, rel=0.02)
    for fl, js in zip(resp.flights, doc["flights"], strict=True):
        assert (js["leave_deg"], js["land_deg"]) == (fl.leave_deg, fl.land_deg)
        inside = np.isin(
            np.round(resp.theta_deg, 6),
            np.round(np.arange(fl.leave_deg, fl.leave_deg + fl.span_deg + 0.05, 0.1) % 360.0, 6),
        )
        assert np.all(resp.force[inside] == 0.0)
    assert_shading_is_the_zero_force(resp)
    assert_shading_is_the_zero_force(fast_review.margin_response)
    m = fast_review.margin_response
    assert len(m.flights) == 3 and len(m.impacts) == 3 and m.max_impact_force == pytest.approx(1533.0, rel=0.03)
    rows = dict(key_results(ReportData(fast_review)))
    assert rows["flights (force 0)"].startswith("8, first at 21.0\u00b0")
    assert (
        rows["impacts"] == f"8, largest {resp.max_impact_force:.4g} N at "
        f"{max(resp.impacts, key=lambda i: i.peak_force).peak_deg:.1f}\u00b0"
    )
    facts = decision_facts(ReportData(fast_review))
    assert any(
        f.startswith("the follower leaves the cam: 8 flights") and f"up to {resp.max_impact_force:.4g} N" in f
        for f in facts
    )
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        ax = fig.add_subplot()
        plot_contact_force(ax, m)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert f"leaves the cam ({len(m.flights)} flights)" in labels and any(
        t.startswith(f"impact ({len(m.impacts)}), largest {m.max_impact_force:.4g} N") for t in labels
    )
    assert not ax.texts  # nothing written over the curve
    assert_legend_clear(ax)
    # check's own warnings say the same: one note of the 8 flights and the largest impact, no "leaves ... lands"
    notes = [w for w in chk.warnings if "leaves the cam" in w]
    assert len(notes) == 1 and notes[0].startswith("the follower leaves the cam 8 times a revolution at 600 rpm")
    assert f"8 impacts, the largest {resp.max_impact_force:.4g} N" in notes[0]


def assert_legend_clear(ax) -> None:
    """No point of a data curve lies under the axes' legend."""
    fig = ax.figure
    renderer = fig._get_renderer()
    box = ax.get_legend().get_window_extent(renderer)
    for line in ax.lines:
        if line.get_transform() != ax.transData:
            continue
        xy = ax.transData.transform(
            np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)])
        )
        inside = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)
        assert not inside.any(), f"{line.get_label()} under the legend of {ax.get_title()!r}"


@pytest.mark.slow
def test_square_page_one_says_its_spring_cannot_be_built(shipped_check):
    """square passes its checks, but its own spring cannot be built (page 6): page 1 says so."""
    review = light_review(*shipped_check("square"))
    assert isinstance(review.spring_part, Unavailable)
    facts = decision_facts(ReportData(review))
    assert any(f.startswith("the return spring cannot be built") and review.spring_part.reason in f for f in facts)
    data = ReportData(review)
    rows = segment_rows(data)  # a path: a row per stretch between breaks, its jumps the facts' jumps
    assert len(rows) == len(data.breaks_deg) and {
        round(r["end_deg"] % 360.0, 6) for r in rows if r["continuity"] != "C2"
    } == {round(d, 6) for d, _, _ in data.jumps}
    assert data.jumps and any(
        f.startswith(f"acceleration jumps at {len({d for d, o, _ in data.jumps if o == 2})} boundar") for f in facts
    )
    assert any("at limit" in f for f in facts) == any(
        c.name == "curvature" and abs(c.value / c.limit - 1) <= 0.02 for c in review.check.checks
    )


@pytest.mark.slow
def test_lecture_tolerances_page_one_carries_p_separation():
    case = load_case(CASES / "lecture-tolerances.toml")
    review = light_review(case, run_check(case), tolerance_samples=64)
    tol = review.tolerance
    facts = decision_facts(ReportData(review))
    assert any(
        f.startswith(f"tolerances: P(separation) at {tol.speed_rpm:g} rpm = {tol.probability:.3g}") for f in facts
    )


@pytest.mark.slow
def test_rounding_is_not_a_jump_and_knots_are_not_boundaries(shipped_check):
    """lecture-optimized's B-splines end with accelerations of about 1e-6 mm/rad^2: not a jump, on page 1 or 2
    or in the check's warnings; its dotted boundaries are the segments' (not the knots'). The lecture's real
    jumps (22.5 mm/rad^2) stay flagged."""
    opt, opt_check = shipped_check("lecture-optimized")
    assert len(opt.motion.breaks_deg) > 4  # the knots are breaks for the integrators
    assert not [w for w in opt.motion.continuity_warnings() if "jumps" in w]
    data = ReportData(light_review(opt, opt_check))
    assert data.breaks_deg == (0.0, 90.0, 180.0, 240.0) and data.jumps == []
    assert not [f for f in decision_facts(data) if "jumps" in f]
    lecture = load_case(CASES / "lecture.toml")
    assert len([w for w in lecture.motion.continuity_warnings() if "acceleration jumps by -22.5" in w]) == 2


@pytest.mark.slow
def test_title_block_manufacturing_and_segments(lecture_case, lecture_check):
    """The title block's SHA-256 is hashlib's of the file; the segment table has the laws' peaks (cycloidal rise
    of 20 mm over 90 deg: v = 2h/beta at its middle, a = 2 pi h / beta^2 at a quarter; harmonic return over
    120 deg: a = h/2 (pi/beta)^2 at its ends, a jump there); the file formats are camdyn profile's."""
    data = ReportData(light_review(lecture_case, lecture_check))
    block = dict(title_block(data))
    assert block["SHA-256"] == hashlib.sha256((CASES / "lecture.toml").read_bytes()).hexdigest() == data.case_sha256
    assert block["case file"] == "lecture.toml" and block["verdict"] == "PASS at 300 rpm"
    rows = segment_rows(data)
    assert [r["law"] for r in rows] == ["dwell", "cycloidal", "dwell", "harmonic"]
    rise, ret = rows[1], rows[3]
    beta = math.pi / 2
    assert rise["v"] == pytest.approx(2 * 20 / beta, rel=1e-6) and rise["v_deg"] == pytest.approx(135.0, abs=0.25)
    assert rise["a"] == pytest.approx(2 * math.pi * 20 / beta**2, rel=1e-6) and rise["a_deg"] == pytest.approx(
        112.5, abs=0.25
    )
    assert abs(ret["a"]) == pytest.approx(10 * (math.pi / (2 * math.pi / 3)) ** 2, rel=1e-6)
    assert [r["continuity"] for r in rows] == ["C2", "C2", "acceleration jumps", "acceleration jumps"]
    assert math.isnan(rows[0]["v_deg"])  # a dwell has no peak anywhere
    made = dict(manufacturing_rows(data))
    assert made["file formats"].startswith(", ".join(s.lstrip(".").upper() for s in FORMATS))
    assert made["prime radius"].startswith("50.0000 mm") and made["base radius"].startswith("40.0000 mm")
    assert "manufacturing" in [p.slug for p in PAGES]


@pytest.mark.slow
def test_flat_face_drawn_where_the_face_width_check_puts_it(lecture_case):
    """The face is drawn face_width long, centred on the middle of the contact's travel: both extreme contacts
    lie on it, at the distances from its ends that the check's margin gives."""
    raw = tomllib.loads((CASES / "lecture.toml").read_text())
    raw["follower"] = {
        "type": "translating-flat",
        "base_radius": 40.0,
        "offset": 5.0,
        "face_width": 44.0,
        "rotation": "cw",
    }
    geo = run_check(case_from_dict(raw)).geometry
    lo, hi = geo.face_range_mm
    c = geo.face_centre_mm
    assert c == pytest.approx(0.5 * (lo + hi)) and hi - lo <= 44.0
    fig = Figure()
    ax = fig.add_subplot()
    for t, th in ((lo, 300.0), (hi, 135.0)):
        ax.clear()
        at = plot_follower(ax, geo, th, colour="k", stem=False)
        (line,) = ax.lines
        a, b = np.column_stack([line.get_xdata(), line.get_ydata()])
        assert np.linalg.norm(b - a) == pytest.approx(44.0, rel=1e-9)
        d = sorted([np.linalg.norm(at["contact"] - a), np.linalg.norm(at["contact"] - b)])
        assert d == pytest.approx(sorted([t - (c - 22.0), (c + 22.0) - t]), abs=1e-6)


@pytest.mark.slow
def test_dynamics_page_force_panels_legends_cover_no_curve(fast_review):
    """Page 4 of lecture-fast: both force panels on one scale, each legend clear of every curve (the marks'
    labels are in the legends, nothing is written over the curves)."""
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        ax_f, ax_m = fig.subplots(2, 1)
        _force_panels(ax_f, ax_m, ReportData(fast_review))
    assert ax_f.get_ylim() == ax_m.get_ylim()
    for ax in (ax_f, ax_m):
        assert_legend_clear(ax)
        assert not ax.texts


@pytest.mark.slow  # a valvetrain's check
def test_a_valvetrains_dynamics_page_marks_the_two_mass_least_force(shipped_check):
    """Page 4 of the valvetrain: the force judged (page 1's, the valvetrain page's) is the two-mass model's over the
    valve event, and its least is the one marked; the equivalent single follower's curves are drawn, named so, and
    their least (480 N, where the two masses give 242 N) is not marked as if it were the verdict's."""
    case, check = shipped_check("valvetrain")
    least = check.valvetrain.response.least_event_force
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        ax_f, ax_m = fig.subplots(2, 1)
        _force_panels(ax_f, ax_m, ReportData(light_review(case, check, margin=True)))
        top = [t.get_text() for t in ax_f.get_legend().get_texts()]
        margin = [t.get_text() for t in ax_m.get_legend().get_texts()]
    marked = [t for t in top + margin if t.startswith("least ")]
    assert marked == [f"least {least:.3g} N at {marked[0].split(' at ')[1]}"] and 200.0 < least < 300.0, top
    assert "two masses, valve event" in top and "one equivalent mass (rigid)" in top
    assert "one equivalent mass (rigid)" in margin and "two masses" in ax_f.get_title(loc="left")
    assert_legend_clear(ax_f)


@pytest.mark.slow
def test_verdict_on_every_page_and_page_one_says_what_it_did_not_evaluate(fast_review):
    """The header of every page carries the verdict and the case file's hash; page 1 says the contact stress is
    not evaluated (no width) and lists the decision-changing facts."""
    data = ReportData(fast_review)
    with matplotlib.rc_context(STYLE):
        for k, page in enumerate(PAGES[:3], start=1):
            fig = Figure(figsize=A4)
            header(fig, data, page.title, k, 3)
            texts = [t.get_text() for t in fig.texts]
            assert "FAIL" in texts and any(f"sha256 {data.case_sha256[:12]}" in t for t in texts)
        fig = Figure(figsize=A4)
        draw_summary(fig, data)
    for ax in fig.axes:  # the force at a glance: its legend clear of the impacts' spikes
        if ax.get_legend() is not None:
            assert_legend_clear(ax)
    text = "\n".join(t.get_text() for t in fig.texts)
    assert "not evaluated: the case gives no contact width" in text and "Decision-changing facts" in text
    assert "the follower leaves the cam: 8 flights" in text


def test_every_key_input_on_page_one_has_its_unit():
    """Page 1's key inputs print a number with its unit: every numeric key of the sections it lists is in UNITS
    or declared dimensionless (a new key without either would print a bare number)."""
    missing = [
        f"{spec.__name__}.{key}"
        for spec in (FollowerSpec, DynamicsSpec, LimitsSpec, ValvetrainSpec, RockerSpec)
        for key in spec.model_fields
        if key not in UNITS and key not in DIMENSIONLESS and key not in ("damping", "rocker")
    ]
    assert missing == []
    # an arm's preload is a torque; a limit left unbounded takes no unit
    assert _kv_lines({"min_preload": 2.0, "max_contact_stress": None}, oscillating=True) == [
        ("min_preload", "2 N\u00b7m"),
        ("max_contact_stress", "unbounded"),
    ]


def _extent(fig, t) -> tuple[float, float]:
    """Where a figure text starts and ends across the page as the PNG draws it (fractions of its width)."""
    fig.set_dpi(DPI)
    box = t.get_window_extent(FigureCanvasAgg(fig).get_renderer())
    w = DPI * fig.get_figwidth()
    return box.x0 / w, box.x1 / w


def test_a_cell_too_long_for_its_column_wraps_within_it():
    """A flow row's left-aligned cell wraps where it would run into the next cell or past the flow's right edge
    (the shipped flat-face cases' "contact on the face" ran off the page); a cell that fits is one line as before."""
    long = "t = -8.60 to +10.78 mm (face centred at +1.09 mm)"
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        flow = Flow(fig, 0.9)
        y0 = flow.y
        flow.row([(0.0, "a label", {}), (0.2, long, {}), (0.5, "next", {}), (0.7, long, {})], size=8.2)
        texts = {t.get_text(): _extent(fig, t) for t in fig.texts}
    lines = [t for t in fig.texts if t.get_text() not in ("a label", "next")]
    assert len(lines) == 4 and " ".join(t.get_text() for t in lines[:2]) == long  # two lines in each column
    x_next = texts["next"][0]
    assert all(_extent(fig, t)[1] < x_next for t in lines[:2])
    assert all(_extent(fig, t)[1] <= flow.right for t in lines[2:])
    assert y0 - flow.y == pytest.approx(flow.h(8.2) * (1 + 1.3 / 1.45))  # as tall as two lines
    lo, hi = texts["a label"]
    assert text_width(fig, "a label", {"size": 8.2}) == pytest.approx(hi - lo, rel=1e-6)  # measured as the PNG draws


def test_ink_width_is_matplotlibs_extents():
    """The text's outline width the flow wraps by is :meth:`Path.get_extents`' (computed segment by segment in
    Python, a third of a report's time): for lines of text in the pages' fonts (TrueType: quadratic curves), and for
    paths of cubic curves, lines and a closed figure."""
    texts = ["a label", "Oo Qg %", "least contact force 12.5 N at 143.2 deg", "âéç ß∞√ −12.5 N·mm²", "(j)"]
    fonts = [FontProperties(size=8.0), FontProperties(size=10.5, weight="bold"), FontProperties(size=9, style="italic")]
    paths = [TextPath((0.0, 0.0), text, prop=font) for text in texts for font in fonts]
    rng = np.random.default_rng(3)
    codes = [MplPath.MOVETO, *[MplPath.CURVE4] * 3, MplPath.CURVE3, MplPath.CURVE3, MplPath.LINETO, MplPath.CLOSEPOLY]
    paths += [MplPath(rng.normal(size=(8, 2)), codes) for _ in range(50)]
    paths.append(MplPath(rng.normal(size=(5, 2))))  # no codes: a polyline
    for path in paths:
        assert ink_width(path) == pytest.approx(path.get_extents().width, rel=1e-13, abs=1e-13)


@pytest.mark.slow
def test_page_one_stays_on_the_page_and_says_where_there_is_no_dwell(shipped_check, racetrack_case, racetrack_check):
    """Page 1 of a flat-faced valve-lift table (its longest key result) keeps every text within the page's margins;
    its table's base circle is a dwell, so it has a residual vibration; a path's mechanism has no dwell, and page 1
    says so instead of a residual vibration of 0."""
    case, check = shipped_check("valve-lift")
    data = ReportData(light_review(case, check))
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        header(fig, data, PAGES[0].title, 1, 7)
        draw_summary(fig, data)
        spans = [_extent(fig, t) for t in fig.texts if t.get_text().strip()]
    assert all(0.05 <= lo and hi <= 0.945 for lo, hi in spans), max(hi for _, hi in spans)
    rows = dict(key_results(data))
    assert rows["residual vibration"] == f"{check.response.residual_vibration:.3g} mm" and case.motion.dwells_deg
    assert check.response.residual_vibration > 0.0
    path = dict(key_results(ReportData(light_review(racetrack_case, racetrack_check))))
    assert path["residual vibration"] == "none: no dwell to judge it in"


@pytest.mark.slow  # the session's racetrack check: a synthesis and a whole check
def test_key_inputs_give_the_spring_part_the_user_gave(racetrack_case, racetrack_check):
    """``[spring]``'s keys the user gave are page 1's key inputs, under the dynamics they change (the racetrack's
    lever_arm: where the spring acts on the arm, which sets its rate and its mass at the arm)."""
    from types import SimpleNamespace

    from camdyn.report.pages._inputs import input_columns

    data = SimpleNamespace(case=racetrack_case, check=racetrack_check, oscillating=True)
    rows = dict(input_columns(data)[-1][1])  # type: ignore[arg-type]  (the fields it reads)
    assert rows["spring.lever_arm"] == "50 mm" and not any(
        k.startswith("spring.") and k != "spring.lever_arm" for k in rows
    )


@pytest.mark.slow  # a valvetrain's check
def test_key_inputs_list_only_the_limits_a_check_judges(shipped_check):
    """Page 1's key inputs leave out a default limit no check of the case judges: a valvetrain on a rigid cam contact
    has no train deflection, and its flat face is held above a cusp, not to a roller's curvature ratio (the page
    listed both beside a curvature check 'above 1e-06 mm'); the lecture's compliant roller has both."""
    from types import SimpleNamespace

    from camdyn.report.pages._inputs import input_columns

    both = {"max_train_deflection", "min_curvature_ratio"}
    for name, listed in (("valvetrain", set()), ("lecture", both)):
        case, check = shipped_check(name)
        data = SimpleNamespace(case=case, check=check, oscillating=case.kind.rotary)
        rows = {key for key, _ in input_columns(data)[-1][1]}  # type: ignore[arg-type]  (the fields it reads)
        assert rows & both == listed, (name, rows)
