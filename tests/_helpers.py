"""Helpers the test modules share: the CLI run in-process, and the reproducer cases of issue 13."""

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
