"""Motion laws and programs: closed forms against autodiff, published coefficients, the lecture's table."""

import functools
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _helpers import up_to_third_derivative

from camdyn import LAWS, HermiteMotion, InputError, Program, law
from camdyn.model.case import load_case
from camdyn.model.motion import evaluate
from camdyn.model.motion._laws import law_host
from camdyn.model.motion._lookup import interval
from camdyn.model.motion._program import PieceTable
from camdyn.schema import LAW_NAMES

X = np.linspace(0.0, 1.0, 2001)


@functools.cache
def every_law(n: int = X.size) -> dict[str, np.ndarray]:
    """Each law's (y, y', y'', y'''), shape (4, n), at n points spread over [0, 1], by :func:`law_host` (the closed
    forms in numpy: nothing to compile; :func:`test_law_in_jax_is_law_host` holds JAX's route to them)."""
    x = np.linspace(0.0, 1.0, n)
    return {name: law_host(name, x) for name in LAWS}


def _autodiff(name, x):
    """The first three derivatives of law ``name``'s y at each x, by forward-mode autodiff: shape (3, *x.shape)."""
    return jnp.stack(up_to_third_derivative(lambda t: law(name, t)[0])(x)[1:])


@functools.cache
def every_law_autodiff() -> dict[str, np.ndarray]:
    """:func:`_autodiff` of every law at ``X`` but its ends, in one compiled program."""
    derivatives = jax.jit(lambda x: jnp.stack([_autodiff(name, x) for name in LAWS]))(X[1:-1])
    return dict(zip(LAWS, np.asarray(derivatives), strict=True))


@jax.jit
def call(motion, theta):
    """``motion(theta)``, the motion's own evaluation, compiled."""
    return motion(theta)


@pytest.mark.slow  # every law's third derivative by autodiff, one program (3-5 s of compile)
@pytest.mark.parametrize("name", LAWS)
def test_law_derivatives_match_autodiff(name):
    vals = every_law()[name]
    # piece boundaries are measure-zero; autodiff picks one side there, as the closed form does
    derivatives = every_law_autodiff()[name]
    for k in (1, 2, 3):
        np.testing.assert_allclose(derivatives[k - 1], vals[k, 1:-1], rtol=1e-9, atol=1e-8, err_msg=f"{name} order {k}")


@pytest.mark.slow  # every law in one program (2 s of compile)
def test_law_in_jax_is_law_host():
    got = jax.jit(lambda x: jnp.stack([law(name, x) for name in LAWS]))(X)
    np.testing.assert_allclose(got, np.stack(list(every_law().values())), rtol=1e-12, atol=1e-11)


@pytest.mark.parametrize("name", [n for n in LAWS if n != "dwell"])
def test_law_boundary_values(name):
    y0, y1 = every_law()[name][:, [0, -1]].T
    assert y0[0] == pytest.approx(0.0, abs=1e-14) and y1[0] == pytest.approx(1.0, abs=1e-12)
    expected_v = 1.0 if name == "constant-velocity" else 0.0
    assert y0[1] == pytest.approx(expected_v, abs=1e-12) and y1[1] == pytest.approx(expected_v, abs=1e-12)


# Peak velocity, acceleration and jerk coefficients of the normalized rise (Norton, Design of Machinery, table 8-3)
NORTON = {
    "harmonic": (1.5708, 4.9348, None),
    "cycloidal": (2.0, 6.2832, 39.478),
    "polynomial-345": (1.8750, 5.7735, 60.0),
    "polynomial-4567": (2.1875, 7.5132, 52.5),
    "modified-trapezoid": (2.0, 4.8881, 61.426),
    "modified-sine": (1.7596, 5.5280, 69.466),
    "constant-acceleration": (2.0, 4.0, None),
}


@pytest.mark.parametrize("name", NORTON)
def test_peak_coefficients(name):
    vals = np.abs(every_law(200001)[name])
    cv, ca, cj = NORTON[name]
    assert vals[1].max() == pytest.approx(cv, rel=2e-4)
    assert vals[2].max() == pytest.approx(ca, rel=2e-4)
    if cj is not None:
        assert vals[3].max() == pytest.approx(cj, rel=2e-4)


def test_closed_forms():
    x, y = X, {name: v[0] for name, v in every_law().items()}
    np.testing.assert_allclose(y["cycloidal"], x - np.sin(2 * np.pi * x) / (2 * np.pi), atol=1e-14)
    np.testing.assert_allclose(y["harmonic"], (1 - np.cos(np.pi * x)) / 2, atol=1e-14)
    np.testing.assert_allclose(y["polynomial-345"], 10 * x**3 - 15 * x**4 + 6 * x**5, atol=1e-14)
    np.testing.assert_allclose(y["polynomial-4567"], 35 * x**4 - 84 * x**5 + 70 * x**6 - 20 * x**7, atol=1e-13)


LECTURE = [
    {"law": "dwell", "end": 90},
    {"law": "cycloidal", "end": 180, "lift": 20},
    {"law": "dwell", "end": 240},
    {"law": "harmonic", "end": 360, "lift": -20},
]

# The lecture's table (cm): angle, f, f', f''. Misread digits in the OCR are corrected here and listed:
# 110 deg f'' printed 5.018 (is 5.016), 250 deg f printed 1.968 (is 1.966), 320 deg f' printed -1.289 (is -1.299),
# 150 deg f'' printed "- 441" (lost digits: -4.411), 180 deg f printed 2.0G0.
LECTURE_TABLE = [
    (100, 0.018, 0.298, 3.274),
    (110, 0.131, 1.052, 5.016),
    (120, 0.391, 1.910, 4.411),
    (130, 0.780, 2.470, 1.742),
    (140, 1.220, 2.470, -1.742),
    (150, 1.609, 1.910, -4.411),
    (160, 1.869, 1.052, -5.016),
    (170, 1.982, 0.298, -3.274),
    (180, 2.000, 0.000, 0.000),
    (250, 1.966, -0.388, -2.173),
    (260, 1.866, -0.750, -1.949),
    (270, 1.707, -1.061, -1.591),
    (280, 1.500, -1.299, -1.125),
    (290, 1.259, -1.449, -0.582),
    (300, 1.000, -1.500, 0.000),
    (310, 0.741, -1.449, 0.582),
    (320, 0.500, -1.299, 1.125),
    (330, 0.293, -1.061, 1.591),
    (340, 0.134, -0.750, 1.949),
    (350, 0.034, -0.388, 2.173),
]


def test_lecture_table():
    prog = Program.from_segments(LECTURE)
    table = np.array(LECTURE_TABLE)
    vals = np.asarray(evaluate(prog, np.deg2rad(table[:, 0]))) / 10.0  # mm -> cm
    np.testing.assert_allclose(vals[:3].T, table[:, 1:], atol=5.1e-4)  # the table's 3 decimals


def test_lecture_program_warnings_name_angle_and_jump():
    warnings = Program.from_segments(LECTURE).continuity_warnings()
    assert len(warnings) == 2
    assert "240 deg" in warnings[0] and "-22.5 mm/rad^2" in warnings[0]  # -(h/2)(pi/beta)^2 = -10 (1.5)^2
    assert "0 deg" in warnings[1]


def test_oscillating_program_warnings_are_in_degrees_of_swing():
    # the lecture's shape as an arm swing of 15 deg: lift is given in deg, the motion is in rad; the jump is
    # reported in the user's unit, deg of swing per rad of cam angle: -(h/2)(pi/beta)^2 = -7.5 (1.5)^2
    segs = [{**s, "lift": s.get("lift", 0.0) * 0.75} for s in LECTURE]
    warnings = Program.from_segments(segs, unit="rad").continuity_warnings()
    assert len(warnings) == 2
    assert "240 deg" in warnings[0] and "-16.88 deg/rad^2" in warnings[0]
    assert all("mm" not in w for w in warnings)
    jumps = Program.from_segments(
        [{"law": "constant-velocity", "end": 180, "lift": 10}, {"law": "constant-velocity", "end": 360, "lift": -10}],
        unit="rad",
    ).continuity_warnings()
    # 10 deg over pi rad, then back: the velocity jumps by -2 * 10 / pi deg/rad at 180 deg
    assert any("velocity jumps by -6.366 deg/rad at 180 deg" in w for w in jumps)


def test_smooth_program_has_no_warnings():
    prog = Program.from_segments(
        [
            {"law": "dwell", "end": 60},
            {"law": "cycloidal", "end": 180, "lift": 10},
            {"law": "dwell", "end": 200},
            {"law": "polynomial-345", "end": 360, "lift": -10},
        ]
    )
    assert prog.continuity_warnings() == []


@pytest.mark.parametrize("name", ["lecture-optimized", "valvetrain", "polynomial", "oscillating"])
def test_every_segments_end_at_once_is_its_left_limit(name):
    """The left side of every boundary in one evaluation (the continuity check of 1000 segments: 0.15 -> 0.016 s;
    B-splines, boundary polynomials and named laws alike) is the program just before the boundary, by its piece
    table: within 1e-6 of each derivative's largest magnitude at 1e-8 rad before it."""
    program = load_case(Path(__file__).resolve().parents[1] / "cases" / f"{name}.toml").motion
    assert isinstance(program, Program)
    ends = program.segment_ends()
    assert ends.shape == (4, len(program.segments))
    peak = np.max(np.abs(program.host(np.linspace(0.0, 2 * np.pi, 3601))), axis=1)
    before = program.host(np.deg2rad(np.array([seg.end for seg in program.segments])) - 1e-8)
    assert np.all(np.abs(ends - before) <= 1e-6 * peak[:, None])
    assert np.array_equal(ends[:, 1], program.segment_end(program.segments[1]))


def test_velocity_jump_is_reported():
    prog = Program.from_segments(
        [{"law": "constant-velocity", "end": 180, "lift": 10}, {"law": "constant-velocity", "end": 360, "lift": -10}]
    )
    w = prog.continuity_warnings()
    assert any("velocity jumps" in s and "180 deg" in s for s in w)


def test_program_periodic_and_jittable():
    prog = Program.from_segments(LECTURE)
    th = np.linspace(-1.0, 7.0, 50)
    np.testing.assert_allclose(
        np.asarray(jax.jit(lambda p, t: p(t))(prog, th)), np.asarray(evaluate(prog, th + 2 * np.pi)), atol=1e-12
    )
    np.testing.assert_allclose(np.asarray(prog.host(th)), np.asarray(evaluate(prog, th)), atol=1e-12)


def test_program_derivatives_match_finite_differences():
    prog = Program.from_segments(LECTURE)
    th = np.deg2rad(np.array([100.0, 135.0, 170.0, 250.0, 300.0, 355.0]))
    h = 1e-5
    v, up, down = np.moveaxis(np.asarray(evaluate(prog, np.stack([th, th + h, th - h]))), 1, 0)  # each (4, 6)
    for k in range(3):
        fd = (up[k] - down[k]) / (2 * h)
        np.testing.assert_allclose(fd, v[k + 1], rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize(
    "segments, where, text",
    [
        ([{"law": "cycloidl", "end": 360, "lift": 0}], "law", "did you mean 'cycloidal'"),
        ([{"law": "dwell", "end": 90}, {"law": "dwell", "end": 80}], "[1].end", "overlaps"),
        ([{"law": "dwell", "end": 300}], "[0].end", "not 360"),
        (
            [{"law": "harmonic", "end": 180, "lift": 5}, {"law": "harmonic", "end": 360, "lift": -4}],
            "motion.segments",
            "does not close",
        ),
        (
            [{"law": "harmonic", "end": 180, "lift": -5}, {"law": "harmonic", "end": 360, "lift": 5}],
            "[0].lift",
            "below zero",
        ),
        ([{"law": "dwell", "end": 180, "lift": 3}, {"law": "dwell", "end": 360}], "[0].lift", "cannot lift"),
    ],
)
def test_program_errors(segments, where, text):
    with pytest.raises(InputError) as err:
        Program.from_segments(segments)
    assert where in err.value.where and text in err.value.message


# ------------------------------------------------------------------------------------------ Hermite table
def test_hermite_table_reproduces_a_program():
    """The quintic table of the lecture program: exact at the knots, O(h^6) between, one-sided at the breaks."""
    prog = Program.from_segments(LECTURE)
    tab = HermiteMotion.from_motion(prog, n=720)
    err = tab.max_error(prog)
    assert err[0] < 1e-12 and err[1] < 1e-9 and err[2] < 1e-6
    # an independent check off the midpoints, on a random sample of angles
    th = np.random.default_rng(0).uniform(0, 2 * np.pi, 5000)
    np.testing.assert_allclose(np.asarray(call(tab, th))[:3], np.asarray(evaluate(prog, th))[:3], atol=1e-6)
    # the s'' jump at 240 deg (harmonic return after a dwell) is kept, not smeared over a step
    sides = np.deg2rad(240.0) + np.array([-1e-9, 1e-9])
    np.testing.assert_allclose(np.asarray(call(tab, sides))[2], np.asarray(evaluate(prog, sides))[2], atol=1e-5)
    # s is at round-off already; s'' converges as h^4: halving the step cuts its error 16-fold
    fine = HermiteMotion.from_motion(prog, n=1440).max_error(prog)
    assert 12 < err[2] / fine[2] < 20


def test_hermite_table_derivatives_are_its_own():
    """s', s'', s''' of the table are the derivatives of its s (autodiff), so the dynamics see one curve."""
    tab = HermiteMotion.from_motion(Program.from_segments(LECTURE), n=360)
    th = np.deg2rad(np.array([10.3, 95.0, 171.7, 250.2, 333.3]))

    @jax.jit
    def values_and_autodiff(tab, th):
        s = lambda t: tab(t)[0]  # noqa: E731
        return tab(th), jax.vmap(jax.grad(s))(th), jax.vmap(jax.grad(jax.grad(s)))(th)

    v, d1, d2 = (np.asarray(a) for a in values_and_autodiff(tab, th))
    np.testing.assert_allclose(d1, v[1], rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(d2, v[2], rtol=1e-9, atol=1e-9)
    assert tab.unit == "mm" and tab.breaks_deg == Program.from_segments(LECTURE).breaks_deg


def test_the_schema_names_every_law_the_model_implements():
    """A law is added in two places (docs/extending.md): the model's pieces and the schema's name list."""
    assert tuple(LAW_NAMES) == tuple(LAWS)


def _dense_program() -> Program:
    """100 cycloids of 0.02 deg (+-0.01 mm) after a dwell: about 4.5 piece starts a bin of 4096."""
    segs = [{"law": "dwell", "end": 10}]
    segs += [{"law": "cycloidal", "end": round(10 + 0.02 * (k + 1), 6), "lift": 0.01 * (-1) ** k} for k in range(100)]
    return Program.from_segments([*segs, {"law": "dwell", "end": 360}])


@pytest.mark.parametrize(
    "name",
    ["lecture", "polynomial", "lecture-optimized", "valvetrain", "dense", "hermite", "valve-lift", "measured-cam"],
)
def test_a_compiled_program_finds_each_angles_interval_as_the_search_does(name):
    """In a compiled program the piece of a motion program, or the interval of a quintic table (a path's tabulated
    motion, here the lecture's with its breaks among the knots; a lift table's, a contour's), comes from a bin
    lookup, not numpy's search (issue 23): the same row at every start, an ulp either side of it, every bin edge and
    an ulp either side, and 10^5 angles between; a program of 100 segments in 2 deg gets 4 x the bins (16384)."""
    cases = Path(__file__).resolve().parents[1] / "cases"
    if name == "dense":
        form = _dense_program().jit_form()
    elif name == "hermite":
        form = HermiteMotion.from_motion(load_case(cases / "lecture.toml").motion).jit_form()
    else:
        form = load_case(cases / f"{name}.toml").motion.jit_form()
    starts = np.asarray(form.start if isinstance(form, PieceTable) else form.knots)
    n_bins = form.bins.shape[0]
    assert n_bins == (16384 if name == "dense" else 4096)
    marks = np.concatenate([starts[np.isfinite(starts)], np.arange(n_bins) * (2 * np.pi / n_bins)])
    theta = np.concatenate(
        [marks, np.nextafter(marks, -1.0), np.nextafter(marks, 10.0), np.linspace(0, 2 * np.pi, 10**5)]
    )
    theta = theta[(theta >= 0.0) & (theta < 2 * np.pi)]
    found = np.asarray(jax.jit(lambda t: interval(jnp, starts, form.bins, t))(theta))
    np.testing.assert_array_equal(found, interval(np, starts, form.bins, theta))


def test_pieces_too_crowded_for_the_lookup_are_one_line():
    """Ten dwells of 1e-10 deg in a row: no bins of the lookup separate them (8 starts at most within four bins, up
    to 4.2 million bins); the program is refused with its key and angle, not looped over without end."""
    segs = [{"law": "dwell", "end": 10}, {"law": "cycloidal", "end": 20, "lift": 5}]
    segs += [{"law": "dwell", "end": 20 + 1e-10 * (k + 1)} for k in range(10)]
    segs += [{"law": "cycloidal", "end": 40, "lift": -5}, {"law": "dwell", "end": 360}]
    with pytest.raises(InputError, match=r"motion\.segments: more than 8 pieces .* near 20 deg: .* merge them"):
        Program.from_segments(segs)
