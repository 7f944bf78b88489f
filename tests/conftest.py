import os

os.environ.setdefault("EQX_ON_ERROR", "nan")  # as the CLI runs: solver results are checked explicitly

import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import tomllib  # noqa: E402
from pathlib import Path  # noqa: E402

import pytest  # noqa: E402

CASES = Path(__file__).resolve().parents[1] / "cases"
_CACHE = "CAMDYN_TEST_CACHE"


def pytest_configure(config):
    """One program cache for the session, shared by the xdist workers (they inherit the variable): a program one
    worker traced and compiled, the other loads. Every test runs as the CLI does, in float64 and with the caches on
    from the start (an in-process ``camdyn.cli.main`` turned them on in ``~/.cache`` half-way through a worker
    before); the subprocesses the tests start use the same folder. ``CAMDYN_TEST_CACHE=DIR`` keeps it between
    sessions. xdist's controller runs no test: it does not load JAX (1.5-2 s before the workers start)."""
    if not os.environ.get(_CACHE):  # the controller (or the one process of -n 0): a fresh folder, removed after
        os.environ[_CACHE] = config._camdyn_cache_made = tempfile.mkdtemp(prefix="camdyn-tests-")
    os.environ["XDG_CACHE_HOME"] = os.environ[_CACHE]
    if _controller(config):
        return
    import camdyn
    from camdyn.cli import _enable_caches

    camdyn.enable_x64()
    _enable_caches()


def _controller(config) -> bool:
    """Whether this process only hands tests to xdist's workers."""
    return not hasattr(config, "workerinput") and bool(getattr(config.option, "numprocesses", None))


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    made = getattr(config, "_camdyn_cache_made", None)
    if made:
        shutil.rmtree(made, ignore_errors=True)
    if hasattr(config, "workerinput"):
        # an xdist worker has sent its results (at sessionfinish) and the controller waits for it to end: the
        # interpreter's teardown of JAX's runtime and every module took 2.5-3 s at the end of each run. Ended here,
        # as the command line ends (camdyn.cli._end_process)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(0)


# shared cases, built once per session
@pytest.fixture(scope="session")
def lecture_case():
    """cases/lecture.toml: a compliant translating roller follower."""
    from camdyn.model.case import load_case

    return load_case(CASES / "lecture.toml")


@pytest.fixture(scope="session")
def lecture_fast_case():
    """cases/lecture-fast.toml: the lecture cam run past its jump speed."""
    from camdyn.model.case import load_case

    return load_case(CASES / "lecture-fast.toml")


@pytest.fixture(scope="session")
def lecture_rigid_case():
    """The lecture cam with a rigid follower (no follower train)."""
    from camdyn.model.case import case_from_dict

    raw = tomllib.loads((CASES / "lecture.toml").read_text())
    for key in ("train_stiffness", "train_damping_ratio"):
        raw["dynamics"].pop(key)
    return case_from_dict(raw)


@pytest.fixture(scope="session")
def lecture_check(lecture_case):
    from camdyn.design.checks import run_check

    return run_check(lecture_case)


@pytest.fixture(scope="session")
def racetrack_case():
    """The quickest path case: an oscillating cam-linkage, rigid follower."""
    from camdyn.model.case import load_case

    return load_case(CASES / "racetrack.toml")


@pytest.fixture(scope="session")
def racetrack_check(racetrack_case):
    from camdyn.design.checks import run_check

    return run_check(racetrack_case)


@pytest.fixture(scope="session")
def shipped_check():
    """``shipped_check(name)``: (case, check) of ``cases/<name>.toml``, made once per test session (several test
    files read the same shipped case's verdict)."""
    from camdyn.design.checks import run_check
    from camdyn.model.case import load_case

    made: dict = {}

    def get(name: str):
        if name not in made:
            case = load_case(CASES / f"{name}.toml")
            made[name] = case, run_check(case)
        return made[name]

    return get


@pytest.fixture(scope="session")
def lecture_check_json(lecture_check):
    """``check --json`` of the shipped lecture case."""
    return lecture_check.json()


def load_toml(name: str) -> dict:
    """The parsed TOML of ``cases/<name>.toml``."""
    return tomllib.loads((CASES / f"{name}.toml").read_text())


@pytest.fixture(scope="session")
def path_synthesis():
    """``path_synthesis(name)``: the synthesis of the shipped path case ``name``, made once per test session
    (each compiles its motion program for seconds)."""
    from camdyn.model.linkage import synthesize_motion

    made: dict = {}

    def get(name: str):
        if name not in made:
            case = load_toml(name)
            made[name] = synthesize_motion(case["path"], case["mechanism"])
        return made[name]

    return get
