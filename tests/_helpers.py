"""Helpers the test modules share: the CLI run in-process, and the reproducer cases of issue 13."""

import numpy as np
import pytest

from camdyn import InputError
from camdyn.cli import main


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
    """Exact distance of points (m, 2) from the closed polyline (k, 2): every chord, in blocks."""
    a, b = poly, np.roll(poly, -1, axis=0)
    d = b - a
    L2 = np.sum(d * d, 1)
    out = np.empty(len(pts))
    for i in range(0, len(pts), 256):
        p = pts[i : i + 256, None, :]
        w = np.clip(np.sum((p - a) * d, -1) / L2, 0.0, 1.0)
        out[i : i + 256] = np.min(np.linalg.norm(p - a - w[..., None] * d, axis=-1), axis=1)
    return out
