"""Shared pytest setup: headless matplotlib, deterministic Hypothesis runs, and the book
built once per test session (``book_site``)."""

from __future__ import annotations

import os
import threading

# Must happen before anything imports matplotlib.pyplot.
os.environ.setdefault("MPLBACKEND", "Agg")

import pytest  # noqa: E402
from book_build import Site, shared_site  # noqa: E402
from hypothesis import HealthCheck, settings  # noqa: E402

# Property tests are derandomized (same examples on every run and machine), have no
# per-example deadline (CI machines are slow and shared) and try 200 examples each.
settings.register_profile(
    "ci",
    derandomize=True,
    deadline=None,
    max_examples=200,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
# A quicker local profile is available with HYPOTHESIS_PROFILE=dev; "ci" is the default.
settings.register_profile("dev", parent=settings.get_profile("ci"), max_examples=50)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def pytest_report_header(config):
    """Say up front whether the grader's sandbox can run here (its tests fail if not)."""
    try:
        from grader_fixtures.helpers import _bwrap_problem
    except Exception as exc:  # pragma: no cover - the grader is not installed
        return f"grader sandbox: cannot check ({type(exc).__name__}: {exc})"
    why = _bwrap_problem()
    if not why:
        return "grader sandbox: bubblewrap works"
    return (
        f"grader sandbox: UNAVAILABLE, the grader's sandbox tests will FAIL: {why.splitlines()[0]}"
    )


#: Modules that ask for ``book_site`` at run time (``request.getfixturevalue``) unless the
#: environment variable names a site built before.
_BOOK_SITE_ON_DEMAND = {"test_book_browser.py": "RIKIN_BOOK_HTML",
                        "test_student_download.py": "RIKIN_STUDENT_SITE"}


def _wants_book_site(item: pytest.Item) -> bool:
    if "book_site" in getattr(item, "fixturenames", ()):
        return True
    variable = _BOOK_SITE_ON_DEMAND.get(item.path.name)
    return variable is not None and not os.environ.get(variable)


@pytest.fixture(scope="session", autouse=True)
def _book_site_started_early(request: pytest.FixtureRequest,
                             tmp_path_factory: pytest.TempPathFactory) -> None:
    """Start the session's book build in the background at the first test when any
    collected test will need it, so that this worker goes on running other tests while the
    build runs, instead of the build starting at the first book test and the other xdist
    worker idling on the build's lock meanwhile. The thread only waits on the build's
    subprocesses; a test that needs the site waits for the same lock (tests/book_build.py).
    A build that raises in the thread leaves no record: the fixture then builds again and
    reports the error."""
    if any(_wants_book_site(item) for item in request.session.items):
        threading.Thread(target=_build_quietly, args=(tmp_path_factory,), daemon=True,
                         name="rikin-book-build").start()


def _build_quietly(tmp_path_factory: pytest.TempPathFactory) -> None:
    try:
        shared_site(tmp_path_factory)
    except Exception:  # noqa: BLE001 - reported by the fixture, which builds again
        pass


@pytest.fixture(scope="session")
def book_site(tmp_path_factory: pytest.TempPathFactory) -> Site:
    """The session's one strict fresh build of the book, shared by every module and every
    xdist worker (tests/book_build.py); built by the first test that asks for it."""
    return shared_site(tmp_path_factory)
