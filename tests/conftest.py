import os

os.environ.setdefault("EQX_ON_ERROR", "nan")  # as the CLI runs: solver results are checked explicitly

import camdyn.model  # noqa: E402,F401  (float64 on)

from pathlib import Path  # noqa: E402

import pytest  # noqa: E402

from camdyn.design.checks import run_check  # noqa: E402
from camdyn.model.case import load_case  # noqa: E402

CASES = Path(__file__).resolve().parents[1] / "cases"


# shared, session-wide: a case and its check at the case speed (each compiles JAX programs once per session)
@pytest.fixture(scope="session")
def lecture_case():
    return load_case(CASES / "lecture.toml")


@pytest.fixture(scope="session")
def lecture_check(lecture_case):
    return run_check(lecture_case)


@pytest.fixture(scope="session")
def racetrack_case():
    """The quickest path case: an oscillating cam-linkage, rigid follower."""
    return load_case(CASES / "racetrack.toml")


@pytest.fixture(scope="session")
def racetrack_check(racetrack_case):
    return run_check(racetrack_case)
