"""Design-review reports: pages, titles, non-blank images, byte-identical PDFs, the path-case page, the spring-sizing
page, the CLI."""

import json
import re
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from camdyn.model.case import load_case
from camdyn.design.checks import run_check
from camdyn.cli import main
from camdyn.report import A4, DPI, PAGES, ReportData, draw_springs, render
from camdyn.design.sizing import SpringSizing

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"
PATH_CASE = ROOT / "cases" / "racetrack.toml"  # the quickest path case (oscillating linkage, rigid follower)
TRANSLATING = ("Summary", "Follower motion (SVAJ)", "Cam profile", "Dynamics")
SPRINGS = "Spring sizing"  # the last page of every case


@pytest.fixture(scope="module")
def lecture(tmp_path_factory):
    case = load_case(LECTURE)
    data = ReportData(case, run_check(case))
    return data, render(data, tmp_path_factory.mktemp("lecture"))


@pytest.fixture(scope="module")
def path_case(tmp_path_factory):
    case = load_case(PATH_CASE)
    data = ReportData(case, run_check(case))
    return data, render(data, tmp_path_factory.mktemp("path"))


def _pdf_pages(pdf: Path) -> int:
    return len(re.findall(rb"/Type\s*/Page\b(?!s)", pdf.read_bytes()))


def _assert_looks_like_a_page(png: Path) -> None:
    img = imread(png)[..., :3]
    assert img.shape[:2] == (round(A4[1] * DPI), round(A4[0] * DPI))
    ink = np.any(img < 0.9, axis=-1).mean()  # fraction of pixels that are not (near) white
    assert 0.02 < ink < 0.6, f"{png.name}: {ink:.3f} of the page inked"
    assert img.std() > 0.05
    assert png.stat().st_size < 200_000


def test_pages_titles_and_names(lecture):
    data, written = lecture
    assert written.titles == TRANSLATING + (SPRINGS,) and written.verdict == "pass"
    assert [p.name for p in written.pngs] == ["lecture-1-summary.png", "lecture-2-svaj.png", "lecture-3-cam.png", "lecture-4-dynamics.png", "lecture-5-springs.png"]
    assert written.pdf.name == "lecture.pdf" and _pdf_pages(written.pdf) == 5
    raw = written.pdf.read_bytes()
    assert b"CreationDate" not in raw and b"ModDate" not in raw and b"camdyn design review: lecture" in raw
    assert written.pdf.stat().st_size < 1_000_000
    # the force-against-speed curve meets the check: the operating point and the jump speed
    sweep, dyn = data.speed_sweep, data.check.dynamic
    assert np.interp(300.0, sweep["rpm"], sweep["linear"]) == pytest.approx(dyn["min_contact_force_N"], rel=1e-3)
    assert sweep["rpm"][np.argmax(sweep["linear"] <= 0.0)] == pytest.approx(dyn["jump_speed_rpm"], rel=2e-3)
    # the lecture's acceleration jumps (dwell -> harmonic at 240 deg, harmonic -> dwell at 0 deg) are flagged
    assert sorted((deg, order) for deg, order, _ in data.jumps) == [(0.0, 2), (240.0, 2)]


def test_pages_are_not_blank(lecture):
    for png in lecture[1].pngs:
        _assert_looks_like_a_page(png)


def test_path_case_gets_the_mechanism_page(path_case):
    data, written = path_case
    assert written.titles == TRANSLATING + ("Mechanism and path", SPRINGS)
    assert [p.name for p in written.pngs[-2:]] == ["racetrack-5-mechanism.png", "racetrack-6-springs.png"] and _pdf_pages(written.pdf) == 6
    for png in written.pngs:
        _assert_looks_like_a_page(png)
    # an oscillating (path) follower is sized in torsion units; its rigid follower has no dynamic correction
    sz = data.sizing
    assert isinstance(sz, SpringSizing) and sz.oscillating and sz.model == "rigid" and sz.units["rate"] == "N*m/rad"
    assert data.jump_map.oscillating and data.jump_map.spring_rate_unit == "N*m/rad"


def test_spring_page_agrees_with_the_check(lecture):
    """The sizing page's current design is the case's own spring: its jump speeds are the check's; the chosen
    spring holds up to speed_margin x speed; the jump map sits on the page's rates at the case's preload."""
    data, _ = lecture
    sz, chk = data.sizing, data.check
    assert isinstance(sz, SpringSizing) and sz.model == "compliant" and not sz.oscillating
    assert sz.top_speed_rpm == pytest.approx(1.25 * 300.0)
    assert (sz.current.rate, sz.current.preload) == (2.0, 30.0)
    assert sz.current.kinematic_jump_rpm == pytest.approx(chk.kinematic["jump_speed_rpm"], rel=1e-3)
    assert sz.current.dynamic_jump_rpm == pytest.approx(chk.dynamic["jump_speed_rpm"], rel=1e-3)
    assert sz.chosen.least_force >= sz.min_contact_force - 1e-6 and sz.chosen.dynamic_jump_rpm >= sz.top_speed_rpm * (1 - 1e-3)
    assert sz.chosen.peak_spring < sz.current.peak_spring
    jm = data.jump_map
    assert jm.preload == 30.0 and jm.spring_rates[-1] == pytest.approx(sz.region_rate[-1]) and jm.speeds_rpm[-1] > chk.dynamic["jump_speed_rpm"]
    assert jm.separated.any() and not jm.separated[:, -1][jm.speeds_rpm < 300.0].any()


def test_spring_page_says_why_sizing_does_not_apply(lecture):
    from matplotlib.figure import Figure

    data, _ = lecture
    bad = ReportData(data.case, data.check)
    bad.__dict__["sizing"] = "motion: the follower does not move: there is no spring to size"  # what size_spring raised
    bad.__dict__["jump_map"] = data.jump_map
    fig = Figure(figsize=A4)
    draw_springs(fig, bad)
    texts = " ".join(t.get_text() for t in fig.texts)
    assert "Spring sizing does not apply to this case" in texts and "no spring to size" in texts
    assert len(fig.axes) == 2  # the jump map and its colour bar still drawn


def test_page_list_is_the_extension_point():
    assert [p.slug for p in PAGES] == ["summary", "svaj", "cam", "dynamics", "mechanism", "springs"]
    assert len({p.slug for p in PAGES}) == len(PAGES)


def test_cli_report_is_deterministic_and_keeps_foreign_files(lecture, tmp_path, capsys):
    out = tmp_path / "reports"
    out.mkdir()
    (out / "lecture-9-old.png").write_bytes(b"stale page of an earlier run")
    (out / "notes.txt").write_text("not ours")
    (out / "lecture-summary.png").write_bytes(b"not named like a camdyn page")
    code = main(["report", str(LECTURE), "-o", str(out)])
    stdout = capsys.readouterr().out
    assert code == 0 and "lecture.pdf" in stdout
    # a second, independent run (fresh check) gives the same bytes
    assert (out / "lecture.pdf").read_bytes() == lecture[1].pdf.read_bytes()
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(["lecture.pdf", "notes.txt", "lecture-summary.png"] + [p.name for p in lecture[1].pngs])


def test_cli_check_report_keeps_json_on_stdout(tmp_path, capsys):
    code = main(["check", str(LECTURE), "--json", "--report", str(tmp_path / "r")])
    out, err = capsys.readouterr()
    assert code == 0 and json.loads(out)["verdict"] == "pass"
    assert "lecture.pdf" in err
    assert sorted(p.name for p in (tmp_path / "r").iterdir())[-1] == "lecture.pdf"


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
