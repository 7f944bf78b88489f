"""The traced-program cache: persisted programs give the same answers, and anything static changes the key."""

import json
import os
import subprocess
import sys
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import camdyn.model  # noqa: F401  (float64)
from camdyn._core import jit as programs

ROOT = Path(__file__).resolve().parents[1]


class Poly(eqx.Module):
    coef: jax.Array
    power: int = eqx.field(static=True)

    def __call__(self, x):
        return self.coef * x**self.power


def _value(p, x, shift):
    return p(x) + shift


def test_programs_persist_and_static_fields_are_part_of_the_key(tmp_path, monkeypatch):
    monkeypatch.setattr(programs, "_DIR", None)
    programs.enable(tmp_path)
    x = jnp.linspace(0.0, 2.0, 5)
    square, cube = Poly(jnp.asarray(3.0), 2), Poly(jnp.asarray(3.0), 3)
    first = programs.cached_jit(_value)
    assert np.allclose(first(square, x, 1.0), 3 * x**2 + 1) and np.allclose(first(cube, x, 1.0), 3 * x**3 + 1)
    assert np.allclose(first(cube, x, 2.0), 3 * x**3 + 2)  # a Python number is static: its own program
    assert np.allclose(first(cube, x, shift=jnp.asarray(2.0)), 3 * x**3 + 2)  # keywords too
    assert len(list(tmp_path.glob("_value-*.jaxexport"))) == 4
    # a new wrapper (as in a fresh process) reads the programs back instead of tracing
    second = programs.cached_jit(_value)
    assert np.allclose(second(cube, x, 1.0), 3 * x**3 + 1) and np.allclose(
        second(Poly(jnp.asarray(-1.0), 2), x, 1.0), 1 - x**2
    )
    assert len(list(tmp_path.glob("_value-*.jaxexport"))) == 4
    # under a transformation the plain jit runs (exported programs have no batching rule)
    assert np.allclose(jax.vmap(lambda c: second(Poly(c, 2), x, 0.0))(jnp.arange(3.0)), np.arange(3.0)[:, None] * x**2)
    (next(tmp_path.glob("_value-*.jaxexport"))).write_bytes(b"truncated")  # a damaged file: trace afresh
    assert np.allclose(programs.cached_jit(_value)(square, x, 1.0), 3 * x**2 + 1)


@pytest.mark.slow  # three fresh processes, two of them compiling every program
def test_fresh_check_processes_agree_with_and_without_the_caches(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "CAMDYN_NO_CACHE"} | {"XDG_CACHE_HOME": str(tmp_path)}
    cmd = [sys.executable, "-m", "camdyn", "check", str(ROOT / "cases" / "lecture.toml"), "--json"]
    runs = [subprocess.run(cmd, env=env, capture_output=True, text=True, check=True) for _ in range(2)]
    plain = subprocess.run(cmd, env=env | {"CAMDYN_NO_CACHE": "1"}, capture_output=True, text=True, check=True)
    assert list((tmp_path / "camdyn" / "programs").glob("_rev_with_sensitivity-*.jaxexport"))
    docs = [json.loads(r.stdout) for r in (*runs, plain)]
    assert docs[0] == docs[1] == docs[2]
