"""The book builds from scratch, executing every page, with no warning or cell error.

The build is the session's one shared build (tests/book_build.py, the ``book_site``
fixture of conftest.py), made by the same function as ``tools/dev.py book``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from book_build import Site, lost_port_race

import rikin


@pytest.mark.book
@pytest.mark.slow
def test_the_shared_build_is_fresh_and_strict(book_site: Site) -> None:
    """Every command of the session's build re-reads every page (--all; _config.yml has
    execute_notebooks: force, so every notebook runs) and fails on any warning."""
    assert book_site.commands
    for cmd in book_site.commands:
        assert cmd[1] == "build" and {"--all", "-W", "-n", "--keep-going"} <= set(cmd), cmd


@pytest.mark.book
@pytest.mark.slow
def test_book_builds_fresh_and_strict(book_site: Site) -> None:
    site = book_site
    assert site.returncode == 0, f"book build failed ({site.returncode}):\n{site.log[-20000:]}"

    html = Path(book_site.html)
    intro = html / "book" / "intro.html"
    assert intro.is_file(), f"{intro} missing; built: {sorted(p.name for p in html.iterdir())}"
    assert rikin.__version__ in intro.read_text(encoding="utf-8"), (
        "intro page does not show the rikin version printed by its code cell"
    )
    assert (html / "index.html").is_file()


def test_only_a_kernel_port_race_is_retried() -> None:
    """The build's one rerun is for a kernel that lost its port, not for a failing page."""
    race = ("zmq.error.ZMQError: Address already in use (addr='tcp://127.0.0.1:41795')\n"
            "RuntimeError: Kernel died before replying to kernel_info")
    assert lost_port_race(race)
    assert not lost_port_race("CellExecutionError: ... AssertionError")
    assert not lost_port_race("RuntimeError: Kernel died before replying to kernel_info")
    assert not lost_port_race("OSError: [Errno 98] Address already in use")


#: Run by each of two processes: ``built_once`` with a stand-in build that takes a moment
#: and counts its runs in a file.
_ASK = """
import sys, time
from pathlib import Path
sys.path.insert(0, sys.argv[2])
from book_build import Site, built_once

def build(out):
    with open(Path(sys.argv[1]) / "runs", "a") as f:
        f.write("x")
    time.sleep(1.0)
    return Site(str(out), "http://127.0.0.1:1/", "", [["build"]], 0, "log")

print(built_once(Path(sys.argv[1]), build).html)
"""


def test_two_processes_share_one_build(tmp_path: Path) -> None:
    """xdist's workers are processes: the second to ask waits for the first's build and
    reads it; nothing is built twice."""
    tests = str(Path(__file__).parent)
    asks = [subprocess.Popen([sys.executable, "-c", _ASK, str(tmp_path), tests],
                             stdout=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=60)[0].strip() for p in asks]
    assert [p.returncode for p in asks] == [0, 0]
    assert (tmp_path / "runs").read_text() == "x"
    assert outs[0] == outs[1] and Path(outs[0]).is_dir()
