"""Helpers the test modules share: the CLI run in-process, the reproducer cases of issue 13, the form-closed
cams' scaffolding (test_closure.py, test_conjugate.py), and the first three derivatives by autodiff."""

import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import brentq

from camdyn import InputError
from camdyn.cli import main


def up_to_third_derivative(f):
    """``t -> (f, f', f'', f''')`` at each element of ``t``, for an elementwise ``f``, by forward-mode autodiff (a
    tangent of ones gives each point's derivative): one nested evaluation for the three orders, half the trace and
    compile of one for each order, a third of nested ``grad``'s."""

    def with_derivative(g):
        return lambda t: jax.jvp(g, (t,), (jnp.ones_like(t),))

    def values(t):
        ((f0, f1), (_, f2)), (_, (_, f3)) = with_derivative(with_derivative(with_derivative(f)))(t)
        return f0, f1, f2, f3

    return values


def run(capsys, *argv):
    """``camdyn ARGV`` in this process: (exit code, stdout, stderr)."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def assert_keys_by_type(table: dict, then: dict, parse, values: dict, kind: str, where: str) -> None:
    """The JSON schema's rules for one type (``then``) are the validator's (``parse``): ``table`` holds only keys it
    lists, each needed key missing is refused, and each key of ``values`` the type does not use is refused by name
    (``where.key``)."""
    assert set(table) <= set(then["propertyNames"]["enum"]) and set(then["required"]) <= set(table)
    for key in then["required"]:
        with pytest.raises(InputError, match="required for"):
            parse({k: v for k, v in table.items() if k != key})
    for key in set(values) - set(then["propertyNames"]["enum"]):
        with pytest.raises(InputError, match=f"not used by an? {kind} {where}") as err:
            parse(dict(table, **{key: values[key]}))
        assert err.value.where == f"{where}.{key}"


# The case a new user hit: a rigid follower whose lift-off falls on a segment boundary (issue 13, finding 1).
RIGID_BOUNDARY = """
name = "rigid-boundary"
[motion]
segments = [
  { law = "harmonic", end = 120, lift = 15 },
  { law = "dwell", end = 180 },
  { law = "harmonic", end = 300, lift = -15 },
  { law = "dwell", end = 360 },
]
[follower]
type = "translating-roller"
base_radius = 45
roller_radius = 12
offset = 0
rotation = "cw"
[dynamics]
speed = 1200
mass = 0.4
spring_rate = 3
preload = 40
damping_ratio = 0.05
restitution = 0.3
"""


def distance_to_outline(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Exact distance of points (m, 2) from the closed polyline (k, 2). Each point is measured against the chords
    that meet its nearest vertices, more of them until no other chord can be nearer: every point of a chord lies
    within half its length of one of its ends, so a chord whose ends are both farther than the farthest vertex asked
    for, less half the longest chord, is farther than one already measured."""
    from scipy.spatial import cKDTree

    a = np.asarray(poly, float)
    pts = np.asarray(pts, float)
    d = np.roll(a, -1, axis=0) - a
    L2 = np.sum(d * d, 1)
    half = 0.5 * np.sqrt(L2.max())
    tree, n = cKDTree(a), len(a)
    out = np.full(len(pts), np.nan)
    todo, k = np.arange(len(pts)), 32
    while todo.size:
        k = min(k, n)
        far, near = tree.query(pts[todo], k=k)
        chords = np.concatenate([near, (near - 1) % n], axis=1)  # the chords from and to each vertex
        p = pts[todo, None, :]
        w = np.clip(np.sum((p - a[chords]) * d[chords], -1) / L2[chords], 0.0, 1.0)
        dist = np.min(np.linalg.norm(p - a[chords] - w[..., None] * d[chords], axis=-1), axis=1)
        sure = (dist <= far[:, -1] - half) | (k == n)
        out[todo[sure]] = dist[sure]
        todo, k = todo[~sure], 4 * k
    return out


# form-closed cams (a groove, conjugate cams): test_closure.py and test_conjugate.py


def omega(case) -> float:
    """The case's cam speed, rad/s."""
    return case.speed_rpm * 2 * np.pi / 60


def host(case, theta) -> np.ndarray:
    """(4, n): the motion and its first three derivatives (per rad) at ``theta`` (rad, a scalar or an array)."""
    return np.asarray(case.motion.host(np.atleast_1d(theta)))


def write_case(folder: Path, name: str, text: str) -> Path:
    """``folder/name`` holding the case file ``text``."""
    path = folder / name
    path.write_text(text)
    return path


def check_value(doc: dict, name: str) -> float:
    """The value of the check ``name`` in a ``check --json`` document."""
    return next(c for c in doc["checks"] if c["name"] == name)["value"]


def check_json(capsys, case_file) -> dict:
    """``camdyn check CASE --json`` in this process, parsed."""
    return json.loads(run(capsys, "check", case_file, "--json")[1])


def constant_velocity_landing(case, tc: float, gap: float, side: float = 1.0) -> float:
    """The cam angle d (rad) after ``tc`` at which a follower that left its flank at ``tc`` with the cam's velocity
    (and keeps it) has crossed ``gap`` (the motion's unit) to the other: side (s'(tc) d - (s(tc + d) - s(tc))) = gap,
    side +1 leaving the inner or primary flank, -1 the other."""
    s0 = host(case, tc)[:, 0]
    return brentq(lambda d: side * (s0[1] * d - (host(case, tc + d)[0, 0] - s0[0])) - gap, 1e-6, 1.0, xtol=1e-15)


def assert_pages_inked(folder: Path) -> None:
    """Every PNG page in ``folder`` is drawn on: between 2 % and 60 % of its pixels not (near) white."""
    from matplotlib.image import imread

    for p in folder.glob("*.png"):
        ink = np.any(imread(p)[..., :3] < 0.9, axis=-1).mean()
        assert 0.02 < ink < 0.6, p.name


def drawn_pages(data) -> dict:
    """slug -> the report page (a matplotlib Figure) drawn from ``data`` (a ``ReportData``), for each page that
    applies."""
    from matplotlib.figure import Figure

    from camdyn.report import A4, PAGES

    figures = {}
    for page in PAGES:
        if page.applies(data):
            figures[page.slug] = fig = Figure(figsize=A4)
            page.draw(fig, data)
    return figures


def figure_text(fig) -> str:
    """Every text on a figure, joined by spaces."""
    return " ".join(t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text")))
