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
#: environment variable names a site built before (tests/test_session_order.py checks that
#: every module asking so is here).
BOOK_SITE_ON_DEMAND = {"test_book_browser.py": "RIKIN_BOOK_HTML",
                       "test_book_download_language.py": "RIKIN_BOOK_HTML",
                       "test_book_editions.py": "RIKIN_BOOK_HTML",
                       "test_book_spanish_text.py": "RIKIN_BOOK_HTML",
                       "test_student_download.py": "RIKIN_STUDENT_SITE"}


def wants_book_site(item: pytest.Item) -> bool:
    """True when ``item`` needs the session's build of the book: it names ``book_site``, or
    its module asks for it at run time (BOOK_SITE_ON_DEMAND)."""
    if "book_site" in getattr(item, "fixturenames", ()):
        return True
    variable = BOOK_SITE_ON_DEMAND.get(item.path.name)
    return variable is not None and not os.environ.get(variable)


def pytest_configure(config: pytest.Config) -> None:
    """xdist hands out test files in the collection's order, which
    pytest_collection_modifyitems below sets, instead of by their number of tests."""
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Files whose tests need the book's build run last, so that both xdist workers run
    every other file while the build runs (``_book_site_started_early``) instead of
    waiting for it. A stable sort on what each file holds, after every other reordering
    (``--ff``, pytest-randomly): every worker collects the same items and so reaches the
    same order, as xdist requires."""
    needs_site: dict[str, bool] = {}
    for item in items:
        f = _file_of(item)
        needs_site[f] = needs_site.get(f, False) or wants_book_site(item)
    items.sort(key=lambda i: needs_site[_file_of(i)])


def _file_of(item: pytest.Item) -> str:
    """The test file of ``item``, as xdist's ``--dist loadfile`` groups them."""
    return item.nodeid.split("::", 1)[0]


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
    if any(wants_book_site(item) for item in request.session.items):
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
