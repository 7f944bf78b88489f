"""Closed target paths: closure, exact derivatives, precision points, Ye & Smith eq. 9, input errors."""

import math

import jax
import numpy as np
import pytest
from _helpers import assert_keys_by_type

import camdyn.model  # noqa: F401  (float64)
from camdyn import InputError
from camdyn.model.paths import build_path, parse_path
from camdyn.schema import PATH_TYPES, PathSpec

TABLE_I_X = [28, 29, 33, 38, 44, 50, 57, 63, 68, 74, 77, 79, 79, 78, 75, 70, 65, 59, 53, 45, 41, 35, 30, 27, 26, 25, 28]
TABLE_I_Y = [
    11,
    12,
    15,
    18,
    24,
    32,
    34,
    41,
    47,
    53,
    58,
    62,
    64.5,
    65.5,
    65,
    63,
    60,
    55,
    49,
    42,
    36,
    29,
    24,
    19,
    15,
    13,
    11,
]


@jax.jit
def points(path, u):
    """``path(u)``, compiled (eager jax.numpy compiles one small program per operation): (*u.shape, 2)."""
    return path(u)


@jax.jit
def derivatives(path, u):
    """``path.derivatives`` at each of the parameters ``u`` (n,), compiled: (n, 4, 2)."""
    return jax.vmap(path.derivatives)(u)


PATHS = {
    "ellipse": dict(type="ellipse", center=[10, -5], semi_major=30, semi_minor=12, rotation=25),
    "circle": dict(type="circle", center=[0, 0], radius=20, reverse=True),
    "rectangle": dict(type="rectangle", center=[5, 5], width=60, height=40, corner_radius=6, rotation=10),
    "eight": dict(type="eight", center=[0, 0], width=40, height=20, phase=0.1),
    "line": dict(type="line", start=[-20, 0], end=[20, 10]),
    "racetrack": dict(type="racetrack", center=[-300, 200], straight=100, radius=100 / math.pi),
    "points": dict(type="points", x=TABLE_I_X, y=TABLE_I_Y),
}


# each path compiles its own programs (1-1.6 s a test): the quick set keeps the seed's numbers (the racetrack)
@pytest.mark.slow
@pytest.mark.parametrize("name", list(PATHS))
def test_closed_and_derivatives_match_finite_differences(name):
    path = build_path(PATHS[name])
    assert np.allclose(*np.asarray(points(path, np.array([[0.0, 1.0], [1.0, 2.0]]))), atol=1e-9)
    rng = np.random.default_rng(1)
    breaks = np.array(path.breaks_u + (1.0,))
    h = 1e-6
    us = rng.uniform(0, 1, 6)
    # one compiled call: the derivatives at each u and at u +- h
    at, up, down = np.asarray(derivatives(path, np.concatenate([us, us + h, us - h]))).reshape(3, len(us), 4, 2)
    for i, u in enumerate(us):
        if np.min(np.abs((breaks - u + 0.5) % 1.0 - 0.5)) < 5 * h:  # central differences need a smooth stencil
            continue
        d = at[i]
        for k in (1, 2, 3):
            fd = (up[i, k - 1] - down[i, k - 1]) / (2 * h)
            scale = np.max(np.abs(d[k])) + 1e-12
            assert np.max(np.abs(fd - d[k])) < 1e-6 * scale * 10 ** (k - 1), (name, k, fd, d[k])


@pytest.mark.slow
def test_precision_points_are_passed_exactly_in_order():
    path = build_path(PATHS["points"])
    pts = np.column_stack([TABLE_I_X, TABLE_I_Y])[:-1].astype(float)
    knots = np.asarray(path.knots)[: len(pts)]  # the points' knots: not the closing 1, nor the padding past it
    assert np.max(np.abs(np.asarray(points(path, knots)) - pts)) < 1e-10
    # C2 at the knots (periodic cubic spline): second derivative continuous, third jumps
    sides = np.asarray(derivatives(path, np.concatenate([knots[1:4] - 1e-9, knots[1:4] + 1e-9]))).reshape(2, 3, 4, 2)
    for left, right in zip(*sides, strict=True):
        assert np.max(np.abs(left[2] - right[2])) < 1e-3 * np.max(np.abs(left[2]))


def test_racetrack_is_ye_smith_eq9():
    path = build_path(PATHS["racetrack"])
    index = np.array([0, 800, 1500, 2500, 3500])
    xy = np.asarray(points(path, index / 4000))
    xg, yg, r = -250.0, 200.0, 100 / math.pi
    expect = [
        (xg, yg - r),  # F0 = (-250, 168.169)
        (xg + r * math.sin(math.pi * 0.8), yg - r * math.cos(math.pi * 0.8)),  # (-231.29, 225.75)
        (xg - 50, yg + r),
        (xg - 100 - r * math.sin(math.pi / 2), yg + r * math.cos(math.pi / 2)),
        (xg - 100 + 50, yg - r),
    ]
    assert np.allclose(xy, expect, atol=1e-10)
    assert np.allclose(xy[1], [-231.29, 225.75], atol=5e-3)
    # dXF/dI at I = 800 (the paper prints -0.080917, 0.0587795: its pi is rounded; exact is -0.1 cos 36 deg)
    v = np.asarray(derivatives(path, np.array([0.2])))[0, 1] / 4000
    assert np.allclose(v, [-0.1 * math.cos(math.radians(36)), 0.1 * math.sin(math.radians(36))], atol=1e-12)
    assert path.breaks_u == (0.0, 0.25, 0.5, 0.75)


@pytest.mark.slow
def test_rectangle_corners():
    sharp = build_path(dict(type="rectangle", center=[0, 0], width=40, height=20))
    round_ = build_path(dict(type="rectangle", center=[0, 0], width=40, height=20, corner_radius=4))
    assert len(sharp.sharp_u) == 4 and round_.sharp_u == () and len(round_.breaks_u) == 8
    assert float(sharp.total) == pytest.approx(120.0) and float(round_.total) == pytest.approx(
        120 - 8 * 4 + 2 * math.pi * 4
    )
    xy = np.asarray(points(round_, np.linspace(0, 1, 2001)))
    assert xy[:, 0].max() == pytest.approx(20.0) and xy[:, 1].min() == pytest.approx(-10.0)
    # unit speed in arc length: |P'| = perimeter everywhere
    speed = np.linalg.norm(np.asarray(derivatives(round_, np.array([0.03, 0.1, 0.37, 0.8])))[:, 1], axis=-1)
    assert np.allclose(speed, float(round_.total))


@pytest.mark.parametrize(
    "table, key",
    [
        (dict(type="ellipse", center=[0, 0], semi_major=3), "path.semi_minor"),
        (dict(type="circle", center=[0, 0], radius=-1), "path.radius"),
        (dict(type="circle", center=[0, 0], radius=1, width=3), "path.width"),
        (dict(type="rectangle", center=[0, 0], width=10, height=10, corner_radius=6), "path.corner_radius"),
        (dict(type="points", x=[0, 1, 2, 3], y=[0, 1, 2]), "path.y"),
        (dict(type="spiral"), "path.type"),
        (dict(type="line", start=[1, 1], end=[1, 1]), "path.end"),
    ],
)
def test_invalid_tables_name_the_key(table, key):
    with pytest.raises(InputError) as err:
        parse_path(table)
    assert err.value.where == key


def test_json_schema_declares_the_keys_each_type_needs_and_takes():
    """The schema's per-type rules are the validator's: each needed key missing is refused, each key another type
    uses is refused, and the keys the schema lists are accepted."""
    rules = {r["if"]["properties"]["type"]["const"]: r["then"] for r in PathSpec.model_json_schema()["allOf"]}
    assert set(rules) == set(PATH_TYPES) == {t["type"] for t in PATHS.values()}
    values = {k: v for table in PATHS.values() for k, v in table.items() if k != "type"}
    for table in PATHS.values():
        assert_keys_by_type(table, rules[table["type"]], parse_path, values, table["type"], "path")
