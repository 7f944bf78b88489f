import os

os.environ.setdefault("EQX_ON_ERROR", "nan")  # as the CLI runs: solver results are checked explicitly

import camdyn.model  # noqa: E402,F401  (float64 on)


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: compiles the dynamics (minutes on a 2-core machine); deselect with -m 'not slow'")


import pytest  # noqa: E402


@pytest.fixture(scope="session")
def lecture_check():
    """``check --json`` of the shipped lecture case (compiled once for the session)."""
    from pathlib import Path

    from camdyn import load_case, run_check

    return run_check(load_case(Path(__file__).resolve().parents[1] / "cases" / "lecture.toml")).json()
