"""The order the test files run in (tests/conftest.py): every file that needs the book's
build comes after every file that does not, so that xdist's workers run those while the
build runs instead of waiting for it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import BOOK_SITE_ON_DEMAND, wants_book_site

TESTS = Path(__file__).resolve().parent


def test_every_module_that_asks_for_the_site_at_run_time_is_known() -> None:
    """A module that asks for ``book_site`` inside a test or fixture (not as an argument,
    which pytest sees) is named in BOOK_SITE_ON_DEMAND: else its tests would run while
    the build runs and wait for it, and a session of that module alone would not start
    the build early."""
    asking = {p.name for p in TESTS.glob("test_*.py")
              if re.search(r"getfixturevalue\(\s*[\"']book_site[\"']",
                           p.read_text(encoding="utf-8"))}
    assert asking, "no module asks for book_site at run time: is the pattern still right?"
    assert asking <= set(BOOK_SITE_ON_DEMAND), asking - set(BOOK_SITE_ON_DEMAND)


def test_the_files_that_need_the_site_run_last(request: pytest.FixtureRequest) -> None:
    """In this session's collection (which xdist hands out in order, file by file), no
    file without a test that needs the site comes after one with such a test."""
    files: list[str] = []
    needs: dict[str, bool] = {}
    for item in request.session.items:
        name = item.nodeid.split("::", 1)[0]
        if name not in needs:
            files.append(name)
        needs[name] = needs.get(name, False) or wants_book_site(item)
    flags = [needs[f] for f in files]
    assert flags == sorted(flags), [f for f in files if needs[f]]
    assert getattr(request.config.option, "loadscopereorder", False) is False
