"""Design-review reports: pages, titles, non-blank images, byte-identical PDFs, the path-case page, the CLI."""

import json
import re
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from camdyn.case import load_case
from camdyn.checks import run_check
from camdyn.cli import main
from camdyn.report import A4, DPI, PAGES, ReportData, render

ROOT = Path(__file__).resolve().parents[1]
LECTURE = ROOT / "cases" / "lecture.toml"
PATH_CASE = ROOT / "cases" / "racetrack.toml"  # the quickest path case (oscillating linkage, rigid follower)
TRANSLATING = ("Summary", "Follower motion (SVAJ)", "Cam profile", "Dynamics")


@pytest.fixture(scope="module")
def lecture(tmp_path_factory):
    case = load_case(LECTURE)
    data = ReportData(case, run_check(case))
    return data, render(data, tmp_path_factory.mktemp("lecture"))


@pytest.fixture(scope="module")
def path_case(tmp_path_factory):
    case = load_case(PATH_CASE)
    return render(ReportData(case, run_check(case)), tmp_path_factory.mktemp("path"))


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
    assert written.titles == TRANSLATING and written.verdict == "pass"
    assert [p.name for p in written.pngs] == ["lecture-1-summary.png", "lecture-2-svaj.png", "lecture-3-cam.png", "lecture-4-dynamics.png"]
    assert written.pdf.name == "lecture.pdf" and _pdf_pages(written.pdf) == 4
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
    assert path_case.titles == TRANSLATING + ("Mechanism and path",)
    assert path_case.pngs[-1].name == "racetrack-5-mechanism.png" and _pdf_pages(path_case.pdf) == 5
    for png in path_case.pngs:
        _assert_looks_like_a_page(png)


def test_page_list_is_the_extension_point():
    assert [p.slug for p in PAGES][:4] == ["summary", "svaj", "cam", "dynamics"]
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
