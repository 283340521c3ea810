"""The book builds from scratch, executing every page, with no warning or cell error."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest
from book_build import lost_port_race, run_build

import rikin

ROOT = Path(__file__).resolve().parents[1]


def _jupyter_book() -> Path:
    exe = Path(sys.executable).parent / ("jupyter-book.exe" if os.name == "nt" else "jupyter-book")
    if not exe.exists():
        pytest.fail(
            f"jupyter-book not found next to {sys.executable}; "
            "install requirements.txt (python3 tools/dev.py test does)"
        )
    return exe


@pytest.mark.book
@pytest.mark.slow
def test_book_builds_fresh_and_strict(tmp_path: Path) -> None:
    env = dict(os.environ)
    env["PYTHONHASHSEED"] = "0"
    env.setdefault("MPLBACKEND", "Agg")
    env["JUPYTER_PREFER_ENV_PATH"] = "1"
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    # A new output dir means a new Sphinx environment and a new jupyter-cache: every page
    # is read and every notebook executed (_config.yml has execute_notebooks: force).
    cmd = [
        str(_jupyter_book()),
        "build",
        str(ROOT),
        "--path-output",
        str(tmp_path),
        "--all",
        "-W",
        "-n",
        "--keep-going",
    ]
    proc = run_build(cmd, cwd=tmp_path, env=env)
    log = proc.stdout
    assert proc.returncode == 0, f"book build failed ({proc.returncode}):\n{log[-20000:]}"

    html = tmp_path / "_build" / "html"
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
