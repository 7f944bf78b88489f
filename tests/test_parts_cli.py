"""``camdyn spring``: the part for a case, its JSON document, and one line with exit code 2 for bad input."""

import json
from pathlib import Path

import pytest
from _helpers import run

ROOT = Path(__file__).resolve().parents[1]
LECTURE = (ROOT / "cases" / "lecture.toml").read_text()
OSCILLATING = (
    (ROOT / "cases" / "oscillating.toml").read_text().split("\n[spring]")[0]
)  # without its own [spring]: each test gives one


def case_file(tmp_path, text, extra=""):
    p = tmp_path / "case.toml"
    p.write_text(text + "\n" + extra)
    return p


def test_spring_for_the_lecture_case(capsys):
    code, out, err = run(capsys, "spring", ROOT / "cases" / "lecture.toml", "--json")
    assert code == 0 and not err
    doc = json.loads(out)
    assert (
        doc["case"] == "lecture"
        and doc["rate_N_per_mm"] == 2.0
        and doc["preload_N"] == 30.0
        and doc["lift_mm"] == pytest.approx(20.0)
    )
    s = doc["spring"]
    assert s["rate_N_per_mm"] == pytest.approx(2.0, rel=1e-9) and all(c["ok"] for c in s["checks"])
    assert {
        "wire_diameter_mm",
        "mean_diameter_mm",
        "active_coils",
        "total_coils",
        "free_length_mm",
        "solid_length_mm",
        "mass_kg",
        "surge",
    } <= set(s)
    assert s["surge"]["cam_frequency_Hz"] == 5.0
    code, out, _ = run(capsys, "spring", ROOT / "cases" / "lecture.toml")
    assert code == 0 and "wire diameter" in out and "spring_fatigue_safety" in out and "surge frequency" in out


def test_spring_within_a_table(capsys, tmp_path):
    extra = (
        '[spring]\nmaterial = "chrome-silicon"\noutside_diameter_max = 25\ninstalled_length = 60\n'
        'end_type = "squared"\n'
    )
    code, out, _ = run(capsys, "spring", case_file(tmp_path, LECTURE, extra), "--json")
    s = json.loads(out)["spring"]
    assert code == 0 and s["material"] == "chrome-silicon" and s["end_type"] == "squared"
    assert s["outside_diameter_mm"] <= 25 and s["installed_length_mm"] == pytest.approx(60.0)


def test_spring_on_an_arm(capsys, tmp_path):
    code, out, _ = run(capsys, "spring", case_file(tmp_path, OSCILLATING, "[spring]\nlever_arm = 40\n"), "--json")
    doc = json.loads(out)
    assert code == 0 and doc["lever_arm_mm"] == 40
    # torsion_rate 5 N*m/rad, preload_torque 2 N*m, swing 15 deg, at 40 mm from the pivot
    assert doc["rate_N_per_mm"] == pytest.approx(5.0 / 0.04**2 / 1e3) and doc["preload_N"] == pytest.approx(2.0 / 0.04)
    assert doc["lift_mm"] == pytest.approx(40 * 15 * 3.141592653589793 / 180)


@pytest.mark.parametrize(
    "text, extra, expected",
    [
        (
            LECTURE,
            '[spring]\nmaterial = "music wire"\n',
            "spring.material: unknown spring material (did you mean 'music-wire'?)",
        ),
        (
            LECTURE,
            "[spring]\noutside_diameter_max = 6\n",
            "spring.outside_diameter_max: no music-wire spring of 2 N/mm fits in 6 mm",
        ),
        (
            LECTURE.replace('rotation = "cw"', 'rotation = "cw"\nwidth = -4'),
            "",
            "follower.width: Input should be greater than 0",
        ),
        (LECTURE, '[materials]\ncam = "stel"\n', "materials.cam: unknown material (did you mean 'steel'?)"),
        (LECTURE, "[spring]\nlever_arm = 30\n", "spring.lever_arm: not used by a translating follower"),
        (OSCILLATING, "", "spring.lever_arm: an oscillating follower's spring needs [spring] lever_arm"),
        (
            LECTURE.replace("spring_rate = 2.0", "spring_rate = 5.8e-6"),
            "",
            "dynamics.spring_rate: no music-wire spring of 5.8e-06 N/mm",
        ),
    ],
)
def test_bad_input_is_one_line_exit_2(capsys, tmp_path, text, extra, expected):
    code, out, err = run(capsys, "spring", case_file(tmp_path, text, extra))
    assert code == 2 and not out
    assert err.count("\n") == 1 and expected in err, err


def test_a_contact_stress_limit_needs_a_width(tmp_path):
    from camdyn import InputError
    from camdyn.schema import load_case_spec

    with pytest.raises(InputError, match=r"limits.max_contact_stress: .*\[follower\] width"):
        load_case_spec(
            case_file(
                tmp_path, LECTURE.replace("min_contact_force = 0", "min_contact_force = 0\nmax_contact_stress = 900")
            )
        )
    spec = load_case_spec(
        case_file(
            tmp_path,
            LECTURE.replace("min_contact_force = 0", "min_contact_force = 0\nmax_contact_stress = 900").replace(
                'rotation = "cw"', 'rotation = "cw"\nwidth = 8'
            ),
        )
    )
    assert spec.limits.max_contact_stress == 900 and spec.contact_width_mm == 8


def test_surge_on_a_cam_harmonic_is_named(capsys, tmp_path):
    """At 1770 rpm (29.5 Hz) the lecture spring's 176.6 Hz surge sits on the lift's 6th harmonic (1.65 % of the
    fundamental): a warning names it, and Shigley's 15x rule draws another."""
    code, out, _ = run(
        capsys, "spring", case_file(tmp_path, LECTURE.replace("speed = 300 ", "speed = 1770 ")), "--json"
    )
    s = json.loads(out)["spring"]
    assert code == 0 and s["surge"]["surge_to_cam_frequency_ratio"] == pytest.approx(5.99, abs=0.01)
    assert any("harmonic 6 " in w for w in s["warnings"]) and any("15 to 20" in w for w in s["warnings"])
    assert [h["harmonic"] for h in s["surge"]["harmonics_near"]] == [5, 6]


def test_the_spring_drawing_carries_its_dimensions():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from camdyn.design.spring import design_spring
    from camdyn.plot import plot_spring

    d = design_spring(2.0, 30.0, 20.0)
    fig, ax = plt.subplots()
    plot_spring(ax, d)
    texts = " ".join(t.get_text() for t in ax.texts)
    plt.close(fig)
    for label in (
        f"free length {d.spring.free_length:.1f}",
        f"installed (preload) {d.installed_length:.1f}",
        f"solid {d.spring.solid_length:.1f}",
        f"OD {d.spring.outside_diameter:.2f}",
        "wire d 1.9",
        "13.5 active / 15.5 total coils",
    ):
        assert label in texts
    assert len(ax.patches) == 2 * d.spring.total_coils + 1  # the wire cut twice per turn
