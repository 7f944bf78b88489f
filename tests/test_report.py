"""Design-review reports: the review data against the check and the motion laws, the pages a case gets and what
each shows, non-blank images, deterministic PDFs, the figures as a notebook calls them, the CLI."""

import dataclasses
import json
import re
import tomllib
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.image import imread
from PIL import Image

from camdyn._core.results import Unavailable
from camdyn.cli import main
from camdyn.design.checks import run_check
from camdyn.design.review import design_review
from camdyn.design.sizing import SpringSizing
from camdyn.model.case import case_from_dict
from camdyn.model.dynamics import Separation
from camdyn.plot import (
    face_extremes,
    plot_cam_profile,
    plot_contact_force,
    plot_curvature,
    plot_displacement,
    plot_feasible_region,
    plot_force_vs_speed,
    plot_jump_map,
    plot_mechanism,
    plot_path,
    plot_path_error,
    plot_pressure_angle,
    plot_svaj,
    plot_vibration,
    square_face,
)
from camdyn.report import A4, DPI, PAGES, STYLE, ReportData, render
from camdyn.report.pages import draw_parts, draw_springs
from camdyn.report.pages._facts import key_results

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"
# slow: a test that takes a reviewed case (JAX compiles the dynamics, the sizing and the jump map) or runs the CLI to
# the end


# ------------------------------------------------------------------------------------------------ fixtures
@pytest.fixture(scope="session")
def lecture_review(lecture_case, lecture_check):
    return design_review(lecture_case, lecture_check)


@pytest.fixture(scope="session")
def lecture(lecture_review, tmp_path_factory):
    return lecture_review, render(lecture_review, tmp_path_factory.mktemp("lecture"))


@pytest.fixture(scope="session")
def path_case(racetrack_case, racetrack_check, tmp_path_factory):
    review = design_review(racetrack_case, racetrack_check)
    return review, render(review, tmp_path_factory.mktemp("path"))


# ------------------------------------------------------------------------------------------------- helpers
def expected_slugs(case) -> list[str]:
    """The pages a case has, from what the case is: a cam page where there is a cam follower, a mechanism page
    where a linkage was synthesized; the parts (drive, contact, spring) on every case."""
    return [
        "summary",
        "svaj",
        *(["cam"] if case.follower is not None else []),
        "dynamics",
        *(["valvetrain"] if case.valvetrain is not None else []),
        *(["mechanism"] if case.synthesis is not None else []),
        *(["optimization"] if case.spec.optimized_from else []),
        "parts",
        "springs",
        "manufacturing",
    ]


def page_text(fig) -> str:
    """Every text on a drawn page: figure texts, axes titles, labels, texts, legends (secondary axes too)."""
    out = [t.get_text() for t in fig.texts]
    axes = list(fig.axes)
    axes += [child for ax in fig.axes for child in ax.child_axes]
    for ax in axes:
        out += [ax.xaxis.label.get_text(), ax.yaxis.label.get_text()] + [t.get_text() for t in ax.texts]
        out += [ax.get_title(loc=loc) for loc in ("left", "center")] if hasattr(ax, "get_title") else []
        if ax.get_legend() is not None:
            out += [t.get_text() for t in ax.get_legend().get_texts()]
    return "\n".join(out)


def drawn_pages(review) -> dict[str, str]:
    """slug -> the text of that page, drawn as the report draws it."""
    data = ReportData(review)
    out = {}
    with matplotlib.rc_context(STYLE):
        for page in PAGES:
            if page.applies(data):
                fig = Figure(figsize=A4)
                page.draw(fig, data)
                out[page.slug] = page_text(fig)
    return out


def pdf_pages(pdf: Path) -> int:
    return len(re.findall(rb"/Type\s*/Page\b(?!s)", pdf.read_bytes()))


def assert_looks_like_a_page(png: Path) -> None:
    img = imread(png)[..., :3]
    assert DPI >= 150 and img.shape[:2] == (int(A4[1] * DPI), int(A4[0] * DPI))  # legible on a projector; Agg truncates
    ink = np.any(img < 0.9, axis=-1).mean()  # fraction of pixels that are not (near) white
    assert 0.02 < ink < 0.6, f"{png.name}: {ink:.3f} of the page inked"
    assert img.std() > 0.05
    assert png.stat().st_size < 450_000  # full RGB (the PDF's colours) at 1240 x 1753 px: 100-300 kB a page
    with Image.open(png) as im:
        assert im.mode == "RGB"


# --------------------------------------------------------------------------------------------- review data
@pytest.mark.slow
def test_review_motion_jumps_are_the_laws(lecture_review):
    """The one-sided values at the lecture's breaks are its laws' own: the harmonic return (-20 mm over 120 deg)
    starts and ends with s'' = -/+ h/2 (pi/beta)^2 = -/+ 22.5 mm/rad^2 against the dwells' 0; the cycloidal rise's
    acceleration is 0 at its ends, so its breaks (90, 180 deg) have no jump."""
    motion = lecture_review.motion
    assert motion.unit == "mm" and motion.breaks_deg == (0.0, 90.0, 180.0, 240.0)
    beta = np.deg2rad(120.0)
    a0 = -20.0 / 2.0 * (np.pi / beta) ** 2
    left, right = motion.one_sided(240.0)
    assert left[2] == pytest.approx(0.0, abs=1e-9) and right[2] == pytest.approx(a0, rel=1e-9)
    left, right = motion.one_sided(0.0)
    assert left[2] == pytest.approx(-a0, rel=1e-9) and right[2] == pytest.approx(0.0, abs=1e-9)
    jumps = ReportData(lecture_review).jumps
    assert [(deg, order) for deg, order, _ in jumps] == [(0.0, 2), (240.0, 2)]
    assert [j for _, _, j in jumps] == pytest.approx([a0, a0], rel=1e-9)


@pytest.mark.slow
def test_review_force_against_speed_meets_the_check(lecture_review):
    """The frequency-domain curve passes through the check's time-domain least force at the case speed and
    crosses zero at the check's jump speed; the kinematic curve is the check's kinematic least force there."""
    sweep, chk = lecture_review.force_vs_speed, lecture_review.check
    dyn, kin = chk.dynamic, chk.kinematic
    assert np.interp(300.0, sweep.speeds_rpm, sweep.dynamic_N) == pytest.approx(dyn.min_contact_force_N, rel=1e-3)
    assert sweep.speeds_rpm[np.argmax(sweep.dynamic_N <= 0.0)] == pytest.approx(dyn.jump_speed_rpm, rel=2e-3)
    assert np.interp(300.0, sweep.speeds_rpm, sweep.kinematic_N) == pytest.approx(kin.min_contact_force_N, rel=1e-3)
    assert sweep.speeds_rpm[np.argmax(sweep.kinematic_N <= 0.0)] == pytest.approx(kin.jump_speed_rpm, rel=2e-3)
    assert lecture_review.margin_rpm == pytest.approx(375.0)
    assert lecture_review.margin_response.omega == pytest.approx(375.0 * 2 * np.pi / 60)


@pytest.mark.slow
def test_spring_page_agrees_with_the_check(lecture_review):
    """The sizing's current design is the case's own spring: its jump speeds are the check's; the chosen spring
    holds up to speed_margin x speed; the jump map sits on the sizing's rates at the case's preload."""
    sz, chk = lecture_review.sizing, lecture_review.check
    assert isinstance(sz, SpringSizing) and sz.model == "compliant" and not sz.oscillating
    assert sz.top_speed_rpm == pytest.approx(1.25 * 300.0)
    assert (sz.current.rate, sz.current.preload) == (2.0, 30.0)
    assert sz.current.kinematic_jump_rpm == pytest.approx(chk.kinematic.jump_speed_rpm, rel=1e-3)
    assert sz.current.dynamic_jump_rpm == pytest.approx(chk.dynamic.jump_speed_rpm, rel=1e-3)
    assert sz.chosen.least_force >= sz.min_contact_force - 1e-6 and sz.chosen.dynamic_jump_rpm >= sz.top_speed_rpm * (
        1 - 1e-3
    )
    assert sz.chosen.peak_spring < sz.current.peak_spring
    jm = lecture_review.jump_map
    assert (
        jm.preload == 30.0
        and jm.spring_rates[-1] == pytest.approx(sz.region_rate[-1])
        and jm.speeds_rpm[-1] > chk.dynamic.jump_speed_rpm
    )
    assert jm.separated.any() and not jm.separated[:, -1][jm.speeds_rpm < 300.0].any()


# ---------------------------------------------------------------------------------------------------- pages
@pytest.mark.slow
def test_pages_titles_and_names(lecture):
    review, written = lecture
    slugs = expected_slugs(review.case)
    assert slugs == ["summary", "svaj", "cam", "dynamics", "parts", "springs", "manufacturing"]
    assert [p.name for p in written.pngs] == [f"lecture-{i}-{s}.png" for i, s in enumerate(slugs, start=1)]
    assert (
        written.titles[0] == "Summary"
        and written.titles[-1] == "Segments and manufacturing"
        and written.verdict == "pass"
    )
    assert written.pdf.name == "lecture.pdf" and pdf_pages(written.pdf) == len(slugs)
    raw = written.pdf.read_bytes()
    assert b"CreationDate" not in raw and b"ModDate" not in raw and b"camdyn design review: lecture" in raw
    assert written.pdf.stat().st_size < 1_000_000


@pytest.mark.slow
def test_each_page_shows_its_content(lecture_review):
    """Each page, drawn as the report draws it, shows what it is for, with the check's numbers."""
    chk = lecture_review.check
    text = drawn_pages(lecture_review)
    assert list(text) == expected_slugs(lecture_review.case)
    assert "PASS" in text["summary"] and all(c.name in text["summary"] for c in chk.checks)
    assert (
        f"{chk.dynamic.min_contact_force_N:.4g} N at {chk.dynamic.min_contact_force_deg:.1f}\u00b0" in text["summary"]
    )
    for quantity in (
        "lift s",
        "velocity ds/d\u03b8",
        "acceleration d\u00b2s/d\u03b8\u00b2",
        "jerk d\u00b3s/d\u03b8\u00b3",
        "time at 300 rpm (ms)",
    ):
        assert quantity in text["svaj"]
    assert "acceleration jumps -22.5 mm/rad\u00b2" in text["svaj"] and "infinite jerk" in text["svaj"]
    geo = chk.geometry
    assert (
        f"max pressure angle {geo.max_pressure_angle_deg:.1f}\u00b0" in text["cam"]
        and "radius of curvature" in text["cam"]
    )
    assert (
        "interface force at 300 rpm" in text["dynamics"]
        and "speed_margin 1.25 \u00d7 speed = 375 rpm" in text["dynamics"]
    )
    assert f"dynamic jump speed {chk.dynamic.jump_speed_rpm:.0f} rpm" in text["dynamics"]
    assert "Springs compared" in text["springs"] and "jump map" in text["springs"]


@pytest.mark.slow
def test_pages_are_not_blank(lecture):
    for png in lecture[1].pngs:
        assert_looks_like_a_page(png)


@pytest.mark.slow
def test_path_case_gets_the_mechanism_page(path_case):
    review, written = path_case
    slugs = expected_slugs(review.case)
    assert slugs == ["summary", "svaj", "cam", "dynamics", "mechanism", "parts", "springs", "manufacturing"]
    assert [p.name for p in written.pngs] == [
        f"racetrack-{i}-{s}.png" for i, s in enumerate(slugs, start=1)
    ] and pdf_pages(written.pdf) == 8
    for png in written.pngs:
        assert_looks_like_a_page(png)
    text = drawn_pages(review)
    assert (
        all(f"\u03b8 = {a}\u00b0" in text["mechanism"] for a in range(0, 360, 60))
        and "path: target and traced" in text["mechanism"]
    )
    assert "swing \u03c8" in text["svaj"] and "torque / lever arm" in text["dynamics"]
    # the drawings and the path plots fill the page: no band of it is left empty
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        next(p for p in PAGES if p.slug == "mechanism").draw(fig, ReportData(review))
    spans = sorted((ax.get_position().y0, ax.get_position().y1) for ax in fig.axes)
    reach, gaps = spans[0][1], []
    for y0, y1 in spans[1:]:
        gaps.append(y0 - reach)
        reach = max(reach, y1)
    assert spans[0][0] < 0.08 and reach > 0.85 and max(gaps) < 0.09  # titles and tick labels between the axes
    # an oscillating (path) follower is sized in torsion units; its rigid follower has no dynamic correction
    sz = review.sizing
    assert isinstance(sz, SpringSizing) and sz.oscillating and sz.model == "rigid" and sz.units["rate"] == "N*m/rad"
    assert review.jump_map.oscillating and review.jump_map.spring_rate_unit == "N*m/rad"
    assert review.force_vs_speed.dynamic_N is None  # a rigid follower: the kinematic curve is its dynamics


@pytest.mark.slow
def test_spring_page_says_why_sizing_does_not_apply(lecture_review):
    reason = "motion: the follower does not move: there is no spring to size"
    bad = dataclasses.replace(lecture_review, sizing=Unavailable(reason))
    fig = Figure(figsize=A4)
    draw_springs(fig, ReportData(bad))
    texts = " ".join(t.get_text() for t in fig.texts)
    assert "Spring sizing does not apply to this case" in texts and "no spring to size" in texts
    assert len(fig.axes) == 2  # the jump map and its colour bar still drawn


@pytest.fixture(scope="session")
def flat_review(lecture_review):
    """The lecture's motion on a translating flat face (offset 5 mm, face 60 mm wide); the dynamics and sizing
    parts of the review are the lecture's (the pages tested here do not draw them)."""
    raw = tomllib.loads(LECTURE.read_text())
    raw["name"] = "flat"
    raw["follower"] = {
        "type": "translating-flat",
        "base_radius": 40.0,
        "offset": 5.0,
        "face_width": 60.0,
        "rotation": "cw",
    }
    case = case_from_dict(raw)
    return dataclasses.replace(lecture_review, case=case, check=run_check(case))


@pytest.mark.slow
def test_flat_face_shows_the_contact_travel_not_a_zero_pressure_angle(flat_review):
    """A translating flat face has pressure angle 0 by construction; the report shows instead where the contact
    runs along the face: t = s' - e, so from the laws t_max = 2h/beta - e at mid-rise (cycloidal, 20 mm over
    90 deg: +20.46 mm at 135 deg) and t_min = -(h/2)(pi/beta) - e at mid-return (harmonic, 20 mm over 120 deg:
    -20 mm at 300 deg); travel 40.46 mm of the 60 mm face."""
    geo = flat_review.check.geometry
    assert square_face(geo) and geo.max_pressure_angle_deg < 1e-9
    (t_lo, th_lo), (t_hi, th_hi) = face_extremes(geo)
    assert t_hi == pytest.approx(2 * 20.0 / (np.pi / 2) - 5.0, rel=1e-9) and th_hi == pytest.approx(135.0)
    assert t_lo == pytest.approx(-10.0 * 1.5 - 5.0, rel=1e-9) and th_lo == pytest.approx(300.0)
    text = drawn_pages(flat_review)
    assert (
        "contact on the face from t = -20.0 mm (\u03b8 = 300.0\u00b0) to +20.5 mm (\u03b8 = 135.0\u00b0): travel "
        "40.46 of face_width 60 mm" in text["cam"]
    )
    assert "pressure angle 0 all round" in text["cam"] and "t from the axis (mm)" in text["cam"]
    assert "max pressure angle" not in text["cam"] + text["summary"] and "follower motion" not in text["cam"]
    rows = dict(key_results(ReportData(flat_review)))
    assert rows["pressure angle"] == "0 all round (face square to its motion)"
    assert rows["contact on the face"] == "t = -20.00 to +20.46 mm (face centred at +0.23)"
    assert "(above 0: no cusp)" in text["summary"] and not re.search(
        r"\(\+\d{4,}%\)", text["summary"]
    )  # no margin in % of 1e-6 mm


@pytest.mark.slow
def test_roller_cam_page_labels_do_not_overlap(lecture_review):
    data = ReportData(lecture_review)
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        next(p for p in PAGES if p.slug == "cam").draw(fig, data)
        fig.canvas.draw()
    (ax,) = [ax for ax in fig.axes if ax.get_aspect() == 1.0]
    boxes = {
        t.get_text(): t.get_window_extent() for t in ax.texts if t.get_text() in ("contact normal", "follower motion")
    }
    assert len(boxes) == 2 and not boxes["contact normal"].overlaps(boxes["follower motion"])


def test_segment_laws_are_named_only_between_their_boundaries():
    """Along the lift panel's top: a law's whole name where it fits between its segment's boundaries, else its
    short name, else none (the valvetrain's 18 deg ramps had "polynomial" struck through by their boundaries)."""
    from types import SimpleNamespace

    from camdyn.report.pages.svaj import _segment_laws

    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=A4)
        ax = fig.add_axes((0.1, 0.5, 0.8, 0.3))
        ax.set_xlim(0.0, 360.0)
        ends = [0.0, 12.0, 30.0, 90.0, 360.0]
        segs = [SimpleNamespace(start=a, end=b, law="polynomial") for a, b in zip(ends[:-1], ends[1:], strict=True)]
        _segment_laws(ax, segs)
        fig.canvas.draw()
    named = {(t.get_position()[0], t.get_text()): t.get_window_extent() for t in ax.texts}
    assert [text for _, text in named] == ["poly", "polynomial", "polynomial"]  # none in 0-12 deg
    for (mid, _), box in named.items():
        seg = next(s for s in segs if s.start < mid < s.end)
        (x0, _), (x1, _) = ax.transData.transform([[seg.start, 0.0], [seg.end, 0.0]])
        assert x0 < box.x0 and box.x1 < x1


def test_jumps_closer_than_a_label_are_marked_by_their_values_alone():
    """A label in words ("velocity jumps +12.7 mm/rad") takes about 100 deg of the page: jumps 90 deg apart (a
    constant-velocity rise's two steps) ran into each other; the lecture's, 120 deg apart, keep their words."""
    from camdyn.report.pages.svaj import _is_compact

    assert _is_compact([(90.0, 1, 12.7), (180.0, 1, -12.7), (240.0, 2, -22.5), (0.0, 2, -22.5)])
    assert not _is_compact([(240.0, 2, -22.5), (0.0, 2, -22.5)])


def test_a_legend_keeps_clear_of_the_curves_of_a_twin_axis():
    """A legend over an axes and its ``twinx``: both axes' curves end below the legend's lower edge (the valvetrain
    page's velocity and cam force panel had its force curve under the legend)."""
    from camdyn.plot._common import legend_above_data

    fig = Figure(figsize=(6, 3))
    ax = fig.add_subplot()
    x = np.linspace(0.0, 1.0, 50)
    ax.plot(x, np.sin(3 * x), label="low")
    twin = ax.twinx()
    twin.plot(x, np.full_like(x, 5.0), color="C1", label="high on the twin")
    twin.set_ylim(0.0, 5.2)
    legend_above_data(ax, twins=(twin,), handles=ax.lines + twin.lines, labels=["low", "high on the twin"])
    fig.canvas.draw()
    bottom = ax.get_legend().get_window_extent().y0
    for a in (ax, twin):
        top = max(a.transData.transform(np.column_stack([x, ln.get_ydata()]))[:, 1].max() for ln in a.lines)
        assert top < bottom, (a, top, bottom)


# ------------------------------------------------------------------------------------ figures in a notebook
@pytest.mark.slow
def test_plot_functions_draw_public_results(lecture_review):
    """Each figure drawn on its own axes from the public results, as a notebook would; the marked least force
    is the check's."""
    chk, rv = lecture_review.check, lecture_review
    fig = Figure(figsize=(8, 16))
    axes = fig.subplots(13, 1).ravel()
    plot_svaj(axes[:4], rv.motion, speed_rpm=chk.speed_rpm)
    plot_cam_profile(axes[4], chk.geometry, chk)
    plot_pressure_angle(axes[5], chk.geometry, chk)
    plot_curvature(axes[6], chk.geometry, chk)
    plot_contact_force(axes[7], chk.response)
    plot_displacement(axes[8], chk.response)
    plot_vibration(axes[9], [(chk.response, "C0", "case speed"), (rv.margin_response, "C1", "margin")])
    plot_force_vs_speed(axes[10], rv)
    plot_feasible_region(axes[11], rv.sizing)
    assert plot_jump_map(axes[12], rv.jump_map) is not None
    assert all(ax.lines or ax.collections or ax.patches for ax in axes)
    least = f"least {chk.dynamic.min_contact_force_N:.3g} N at {chk.dynamic.min_contact_force_deg:.1f}\u00b0"
    assert not axes[7].texts and least in [
        t.get_text() for t in axes[7].get_legend().get_texts()
    ]  # named in the legend
    assert axes[7].get_title() == "interface force at 300 rpm"


def separated(response):
    """``response`` as if the follower flew twice: 145.3 -> 15.8 deg (the larger gap) and 24.8 -> 89.2 deg."""
    flights = (Separation(24.8, 89.2, 0.21, 0.09), Separation(145.3, 15.8, 2.23, 0.2))
    return dataclasses.replace(response, force=np.maximum(response.force - 25.0, 0.0), separations=flights)


@pytest.mark.slow
def test_force_panel_says_where_the_follower_leaves(lecture_review):
    """A separated response marks where the follower leaves the cam on each flight (the spans of zero force), its
    impacts and their largest force, named in the legend, nothing written over the curve; page 1 names where it
    leaves on its largest separation, not its least force of 0 N at 0 deg."""
    chk = lecture_review.check
    fig = Figure(figsize=A4)
    ax1, ax2 = fig.subplots(2, 1)
    plot_contact_force(ax1, chk.response)
    resp = separated(chk.response)
    plot_contact_force(ax2, resp)
    flights = resp.flights
    assert flights and not ax1.texts and not ax2.texts
    assert [tuple(line.get_xdata()) for line in ax2.lines if line.get_marker() == "v"] == [
        tuple(f.leave_deg for f in flights)
    ]
    labels = [t.get_text() for t in ax2.get_legend().get_texts()]
    assert f"leaves the cam ({len(flights)} flight{'s' if len(flights) > 1 else ''})" in labels
    assert any(t.startswith(f"impact ({len(resp.impacts)}), largest {resp.max_impact_force:.4g} N") for t in labels)
    data = ReportData(dataclasses.replace(lecture_review, check=dataclasses.replace(chk, response=resp)))
    least = dict(key_results(data))["least force, dynamic"]
    assert least == f"{chk.dynamic.min_contact_force_N:.4g} N: leaves the cam at 145.3\u00b0"


@pytest.mark.slow
def test_plot_mechanism_draws_a_path_case(path_case):
    syn = path_case[0].case.synthesis
    fig = Figure()
    ax1, ax2, ax3 = fig.subplots(1, 3)
    plot_mechanism(ax1, syn, 30.0, label_joints=True)
    plot_path(ax2, syn)
    plot_path_error(ax3, syn)
    assert ax1.get_title() == "\u03b8 = 30\u00b0" and {t.get_text() for t in ax1.texts} >= {"O", "A", "D"}
    assert len(ax2.lines) >= 2 and ax3.get_yscale() == "log"


# ----------------------------------------------------------------------------------------------------- CLI
@pytest.mark.slow
def test_cli_report_is_deterministic_and_keeps_foreign_files(lecture, tmp_path, capsys):
    out = tmp_path / "reports"
    out.mkdir()
    (out / "lecture-9-old.png").write_bytes(b"tEXtSoftware\x00camdyn 0.1.0: a stale page of an earlier run")
    (out / "notes.txt").write_text("not ours")
    (out / "lecture-summary.png").write_bytes(b"not named like a camdyn page")
    code = main(["report", str(LECTURE), "-o", str(out)])
    stdout = capsys.readouterr().out
    assert code == 0 and "lecture.pdf" in stdout
    # a second, independent run (fresh check and review) gives the same bytes
    assert (out / "lecture.pdf").read_bytes() == lecture[1].pdf.read_bytes()
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(["lecture.pdf", "notes.txt", "lecture-summary.png"] + [p.name for p in lecture[1].pngs])


@pytest.mark.slow
def test_cli_check_report_keeps_json_on_stdout(tmp_path, capsys):
    code = main(["check", str(LECTURE), "--json", "--report", str(tmp_path / "r")])
    out, err = capsys.readouterr()
    assert code == 0 and json.loads(out)["verdict"] == "pass"
    assert "lecture.pdf" in err
    assert sorted(p.name for p in (tmp_path / "r").iterdir())[-1] == "lecture.pdf"


@pytest.mark.parametrize("name", ["lecture.pdf", "lecture-1-summary.png", "lecture-9-old.png"])
def test_cli_report_never_overwrites_a_file_camdyn_did_not_write(tmp_path, capsys, name):
    """A report rewrites its own PDF and pages of an earlier run (camdyn's mark in them) and removes its stale pages;
    a user's file under one of those names is refused before the case is checked, one line, and left as it was."""
    mine = tmp_path / name
    mine.write_text("mine")
    code = main(["report", str(LECTURE), "-o", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and name in err and "not a file camdyn wrote" in err and len(err.strip().splitlines()) == 1
    assert mine.read_text() == "mine" and [p.name for p in tmp_path.iterdir()] == [name]


def test_cli_report_bad_input(tmp_path, capsys):
    code = main(["report", str(tmp_path / "missing.toml"), "-o", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and "missing.toml" in err and "no such file" in err and len(err.strip().splitlines()) == 1
    target = tmp_path / "file.pdf"
    target.write_text("x")
    code = main(["report", str(LECTURE), "-o", str(target)])
    err = capsys.readouterr().err
    assert code == 2 and "not a folder" in err
    code = main(["report", str(LECTURE), str(LECTURE), "-o", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and "overwrite each other" in err


@pytest.mark.slow
def test_parts_page_draws_the_drive_and_the_spring(lecture):
    """The parts page: the camshaft torque (its peak is the check's), and the case's own spring as a part."""
    review, written = lecture
    fig = Figure(figsize=A4)
    draw_parts(fig, ReportData(review))
    text = page_text(fig)
    assert f"{review.check.drive.peak_torque:.3g}" in text and "free length" in text and "Contact stress: give" in text


@pytest.mark.slow
def test_a_contour_case_shows_its_data_file_and_fit(shipped_check):
    """A measured contour has no segments and no path: the summary lists the file and how the fit follows it."""
    case, check = shipped_check("measured-cam")
    text = drawn_pages(design_review(case, check))
    fit = case.contour.json()
    assert "measured-cam.csv" in text["summary"] and f"{fit['points']}" in text["summary"]
    assert "max residual" in text["summary"] and "rms residual" in text["summary"]


@pytest.mark.slow
def test_an_optimized_case_is_compared_with_its_original(shipped_check):
    """cases/lecture-optimized.toml names lecture.toml in optimized_from: its report gets the optimization page,
    the motion and the force against speed of both, with both jump speeds."""
    case, check = shipped_check("lecture-optimized")
    review = design_review(case, check)
    assert review.original.case.name == "lecture" and review.original.check.dynamic.jump_speed_rpm == pytest.approx(
        484.818, abs=0.01
    )
    text = drawn_pages(review)
    assert list(text) == expected_slugs(case)
    assert (
        "before: jump speed 485 rpm" in text["optimization"]
        and f"after: jump speed {review.check.dynamic.jump_speed_rpm:.0f} rpm" in text["optimization"]
    )


@pytest.mark.slow  # 137 pages to decode
def test_no_shipped_page_draws_past_its_margins():
    """Nothing on a page of the shipped reports reaches the paper's edge: no ink within 1 % of it on the left or 3 %
    on the right (the flow's margin is 6 %; a legend four columns wide, a long key result and three plot titles ran
    off the page)."""
    pages = sorted((ROOT / "reports").glob("*.png"))
    assert len(pages) > 100
    off = []
    for page in pages:
        with Image.open(page) as image:
            width, ink = image.size[0], np.flatnonzero((np.asarray(image.convert("L")) < 200).any(axis=0))
        if ink[0] < 0.01 * width or ink[-1] > 0.97 * width:
            off.append(f"{page.name}: ink from {ink[0] / width:.3f} to {ink[-1] / width:.3f} of the width")
    assert off == []
