"""Polynomial segments from boundary conditions (Norton's method): the named polynomials recovered, every
condition met, overshoot and conditioning warnings, and the schema's refusals."""

import math
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _helpers import up_to_third_derivative

from camdyn import InputError, Program
from camdyn.cli import main
from camdyn.model.motion import evaluate

ROOT = Path(__file__).resolve().parents[1]

NAMED = [
    {"law": "dwell", "end": 60},
    {"law": "polynomial-345", "end": 150, "lift": 20},
    {"law": "dwell", "end": 200},
    {"law": "polynomial-4567", "end": 330, "lift": -20},
    {"law": "dwell", "end": 360},
]
FROM_CONDITIONS = [
    {"law": "dwell", "end": 60},
    {"law": "polynomial", "end": 150, "lift": 20},
    {"law": "dwell", "end": 200},
    {"law": "polynomial", "end": 330, "lift": -20, "start_jerk": 0, "end_jerk": 0},
    {"law": "dwell", "end": 360},
]


def _toml(segments) -> str:
    rows = ",\n".join(
        "  { "
        + ", ".join(f"{k} = {v!r}" if isinstance(v, str) else f"{k} = {v}" for k, v in s.items()).replace("'", '"')
        + " }"
        for s in segments
    )
    lecture = (ROOT / "cases" / "lecture.toml").read_text()
    return "[motion]\nsegments = [\n" + rows + "\n]\n\n[follower]" + lecture.split("[follower]")[1]


def _table(capsys, tmp_path, name, segments) -> np.ndarray:
    case = tmp_path / f"{name}.toml"
    case.write_text(_toml(segments))
    assert main(["table", str(case), "--step", "0.5"]) == 0
    out = capsys.readouterr().out.splitlines()
    return out[0].split(","), np.loadtxt(out[1:], delimiter=",")


@pytest.mark.slow  # two tables' dynamic columns compile the shooting (5-7 s)
def test_no_options_is_345_and_zero_end_jerks_is_4567(capsys, tmp_path):
    """`camdyn table` of the polynomial segments equals the named laws' column by column, to 1e-9; the dynamic
    force to the integrator's accuracy (1e-7): two shootings of motions equal to a rounding, whose adaptive steps may
    part (the lecture's least force is within 1.4e-6 N of a reference at rtol 1e-13, docs/benchmarks.md)."""
    head_a, a = _table(capsys, tmp_path, "named", NAMED)
    head_b, b = _table(capsys, tmp_path, "conditions", FROM_CONDITIONS)
    assert head_a == head_b and a.shape == b.shape
    for k, name in enumerate(head_a):
        tol = 1e-7 if name.startswith("dynamic") else 1e-9
        np.testing.assert_allclose(b[:, k], a[:, k], rtol=tol, atol=tol * max(1.0, np.abs(a[:, k]).max()), err_msg=name)


def test_degrees_follow_the_conditions():
    prog = Program.from_segments(FROM_CONDITIONS)
    polys = [s.polynomial for s in prog.segments if s.polynomial is not None]
    assert [len(p.coef) - 1 for p in polys] == [5, 7]
    np.testing.assert_allclose(polys[0].coef, [0, 0, 0, 200, -300, 120], atol=1e-10)  # 20 (10x^3 - 15x^4 + 6x^5)
    np.testing.assert_allclose(polys[1].coef, -20 * np.array([0, 0, 0, 0, 35, -84, 70, -20]), atol=1e-9)


def test_norton_single_dwell_3456():
    """Norton's single-dwell rise-fall (h = 25 mm at mid-span, one segment): y = h (64x^3 - 192x^4 + 192x^5 - 64x^6)."""
    prog = Program.from_segments(
        [{"law": "polynomial", "end": 180, "lift": 0, "points": [[90, 25]]}, {"law": "dwell", "end": 360}]
    )
    np.testing.assert_allclose(
        prog.segments[0].polynomial.coef, 25 * np.array([0, 0, 0, 64, -192, 192, -64]), atol=1e-9
    )
    assert prog.polynomial_warnings() == [] and prog.continuity_warnings() == []


SEGMENTS = [
    {"law": "dwell", "end": 30},
    {
        "law": "polynomial",
        "end": 110,
        "lift": 12,
        "start_jerk": 0,
        "end_velocity": 9,
        "end_acceleration": -3,
        "points": [[60, 3.5]],
    },
    {"law": "polynomial", "end": 190, "lift": 8, "start_velocity": 9, "start_acceleration": -3, "end_jerk": 5},
    {"law": "polynomial", "end": 330, "lift": -20, "start_jerk": 5, "points": [[250, -9], [300, -18]]},
    {"law": "dwell", "end": 360},
]


def test_every_condition_is_met_by_autodiff_of_the_program():
    """Values at the ends and points, velocities, accelerations and given jerks, per rad of cam angle, through
    the program's own evaluation differentiated by JAX (not the solve's matrix)."""
    prog = Program.from_segments(SEGMENTS)
    derivatives = jax.jit(lambda t: jnp.stack(up_to_third_derivative(lambda t: prog(t)[0])(t)))
    d = [lambda t, k=k: np.asarray(derivatives(t))[k] for k in range(4)]  # one compiled program for the four
    base, start = 0.0, 0.0
    eps = 1e-9
    for seg in SEGMENTS:
        if seg["law"] == "polynomial":
            at0, at1 = math.radians(start) + eps, math.radians(seg["end"]) - eps
            want0 = [base, seg.get("start_velocity", 0), seg.get("start_acceleration", 0), seg.get("start_jerk")]
            want1 = [
                base + seg["lift"],
                seg.get("end_velocity", 0),
                seg.get("end_acceleration", 0),
                seg.get("end_jerk"),
            ]
            for k in range(4):
                for at, want in ((at0, want0[k]), (at1, want1[k])):
                    if want is not None:
                        assert float(d[k](jnp.asarray(at))) == pytest.approx(want, abs=1e-6 * 10**k), (seg, k)
            for theta, lift in seg.get("points", []):
                assert float(d[0](math.radians(theta))) == pytest.approx(base + lift, abs=1e-9)
        base += seg.get("lift", 0.0)
        start = seg["end"]
    assert prog.continuity_warnings() == []  # matched velocities and accelerations at 110 and 190 deg


def test_oscillating_conditions_are_in_degrees_of_swing():
    deg = Program.from_segments(
        [
            {"law": "polynomial", "end": 180, "lift": 15, "end_velocity": 2},
            {"law": "polynomial", "end": 360, "lift": -15, "start_velocity": 2},
        ],
        unit="rad",
    )
    before, at = np.asarray(evaluate(deg, np.deg2rad(np.array([180.0 - 1e-7, 180.0])))).T
    assert math.degrees(float(before[1])) == pytest.approx(2.0, rel=1e-5)
    assert math.degrees(float(at[0])) == pytest.approx(15.0, rel=1e-9)


def test_overshoot_warning_says_by_how_much_and_where():
    prog = Program.from_segments(
        [
            {"law": "polynomial", "end": 180, "lift": 20, "points": [[100, 2], [170, 19]]},
            {"law": "polynomial", "end": 360, "lift": -20},
        ]
    )
    (warning,) = prog.polynomial_warnings()
    th = np.linspace(0.0, 180.0, 180001)
    s = np.asarray(prog.host(np.deg2rad(th)))[0]
    over = s.max() - 20.0
    assert over > 1.0 and "motion.segments[0]" in warning and "overshoots its range 0 to 20 mm" in warning
    assert f"{over:.4g} mm above it at {th[s.argmax()]:.4g} deg" in warning


def test_ill_conditioned_polynomial_is_warned():
    points = [[10 + 160 * (i + 1) / 8, 20 * ((i + 1) / 8) ** 2] for i in range(7)]
    prog = Program.from_segments(
        [
            {"law": "polynomial", "end": 180, "lift": 20, "start_jerk": 0, "end_jerk": 0, "points": points},
            {"law": "polynomial", "end": 360, "lift": -20},
        ]
    )
    assert any("ill-conditioned (condition number" in w and "degree 14" in w for w in prog.polynomial_warnings())


@pytest.mark.parametrize(
    "segment, where, text",
    [
        (
            {"law": "cycloidal", "end": 180, "lift": 20, "start_velocity": 1},
            "[1].start_velocity",
            'only a law = "polynomial" segment',
        ),
        ({"law": "polynomial", "end": 180, "lift": 20, "end_jrek": 0}, "[1].end_jrek", "did you mean 'end_jerk'"),
        ({"law": "polynomal", "end": 180, "lift": 20}, "[1].law", "did you mean 'polynomial'"),
        (
            {"law": "polynomial", "end": 180, "lift": 20, "points": [[60, 3]]},
            "[1].points[0]",
            "outside the segment (90 to 180 deg)",
        ),
        (
            {"law": "polynomial", "end": 180, "lift": 20, "points": [[120, 3], [110, 2]]},
            "[1].points[1]",
            "not after the previous point",
        ),
        ({"law": "polynomial", "end": 180}, "[1].lift", 'use law = "dwell"'),
    ],
)
def test_schema_refusals(segment, where, text):
    with pytest.raises(InputError) as err:
        Program.from_segments([{"law": "dwell", "end": 90}, segment, {"law": "cycloidal", "end": 360, "lift": -20}])
    assert where in err.value.where and text in err.value.message


def test_case_file_errors_name_the_key(capsys, tmp_path):
    case = tmp_path / "bad.toml"
    case.write_text(
        _toml(
            [
                {"law": "dwell", "end": 90},
                {"law": "harmonic", "end": 180, "lift": 20, "end_jerk": 0},
                {"law": "cycloidal", "end": 360, "lift": -20},
            ]
        )
    )
    assert main(["check", str(case)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "motion.segments[1].end_jerk" in err and "polynomial" in err
