"""The book built for the tests: once per test session, shared by every module that needs it.

:func:`shared_site` builds the book the way ``tools/dev.py book`` does (its
:func:`dev.build_book`), strict and from scratch (``-W -n --keep-going --all``, every
notebook executed), for a loopback base URL ``http://127.0.0.1:<port>/`` and with the launch
key set, so that one build serves every module: the strict build test, the browser test
and the student's download test (which serves the site at that base URL). xdist's workers
are separate processes: the first to ask builds, under a lock file in the folder the
session's workers share, and writes what it built (or how it failed) next to it; the others
wait for the lock and read that.

A build is run once more if a notebook's kernel lost the race for its TCP port.
jupyter_client picks a kernel's ports by binding and releasing them, and the kernel binds
them a moment later; a kernel another process (an nbval or grader test on the other xdist
worker) starts in between may take one first. The kernel then dies with ZMQError "Address
already in use" before it replies to kernel_info, and the build fails although no page is
wrong (jupyter_client and ipykernel issues; papermill #511). That failure, and only that
one, is retried: any other failure, or the same one twice, fails the build.
"""

from __future__ import annotations

import fcntl
import json
import os
import random
import socket
import subprocess
import sys
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import dev  # noqa: E402

#: What the build log holds when a kernel lost its port, and nothing else went wrong.
PORT_RACE = ("Address already in use", "Kernel died before replying to kernel_info")
#: The launch key the shared build is given (the links are checked, not followed).
LAUNCH_REPOSITORY = "https://github.com/rikin-course/book/tree/gh-pages"
#: Where the base URL's port is picked: below Linux's ephemeral range (32768-60999), which
#: is where every "any free port" (port 0: kernels, test servers) comes from, so no other
#: test takes it between the build and the server that serves the site there.
BASE_PORTS = range(20000, 32000)


def lost_port_race(log: str) -> bool:
    """True when the build failed because a kernel could not bind its port."""
    return all(marker in log for marker in PORT_RACE)


def run_build(cmd: list[Any], *, cwd: Path, env: dict[str, str],
              timeout: float = 1800) -> subprocess.CompletedProcess[str]:
    """``jupyter-book build`` (``cmd``) with its output in ``stdout``; rerun once after a
    kernel's port race (module docstring), saying so in the log."""
    def once() -> subprocess.CompletedProcess[str]:
        return subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=timeout)

    proc = once()
    if proc.returncode != 0 and lost_port_race(proc.stdout):
        first = proc.stdout
        proc = once()
        proc.stdout = (f"[a kernel lost its port to another process; the build was rerun. "
                       f"First run's log ends:]\n{first[-3000:]}\n[rerun:]\n{proc.stdout}")
    return proc


@dataclass(frozen=True)
class Site:
    """The session's build of the book.

    Attributes
    ----------
    html : str
        The built site, ``<output>/_build/html`` (a str: the record is JSON).
    base : str
        Its ``html.baseurl``, ``http://127.0.0.1:<port>/``.
    launch_repository : str
        Its launch key.
    commands : list of list of str
        Every command the build ran (strict and fresh: ``-W -n --keep-going --all``).
    returncode : int
        0 when every command succeeded, else the first failure's exit code.
    log : str
        The commands' output (stdout and stderr), in order.
    """

    html: str
    base: str
    launch_repository: str
    commands: list[list[str]]
    returncode: int
    log: str

    @property
    def port(self) -> int:
        return int(self.base.rstrip("/").rsplit(":", 1)[1])


def _free_base_port() -> int:
    """A port of BASE_PORTS nothing listens on now (module constant's note)."""
    for port in random.Random(os.getpid()).sample(BASE_PORTS, 200):
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return port
    raise RuntimeError(f"no free port in {BASE_PORTS} on 127.0.0.1")


def _build(out: Path) -> Site:
    """Build the book into ``out`` as ``tools/dev.py book`` does, for a loopback base URL."""
    base = f"http://127.0.0.1:{_free_base_port()}/"
    commands: list[list[str]] = []
    logs: list[str] = []

    def runner(cmd: list[str], env: dict[str, str]) -> int:
        commands.append(cmd)
        proc = run_build(cmd, cwd=out, env=env)
        logs.append(f"$ {' '.join(cmd)}\n{proc.stdout}")
        return proc.returncode

    build = dev.BookBuild(base_url=base, launch_repository=LAUNCH_REPOSITORY, output=out,
                          tag=f"test-{os.getpid()}")
    rc = dev.build_book(build, runner, bin_dir=Path(sys.executable).parent)
    return Site(str(out / "_build" / "html"), base, LAUNCH_REPOSITORY, commands, rc,
                "\n".join(logs))


def _session_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The folder this test session's processes share: the parent of a worker's base
    temporary folder under xdist (pytest-xdist's "making session-scoped fixtures execute
    only once"), the base temporary folder itself without it."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def shared_site(tmp_path_factory: pytest.TempPathFactory) -> Site:
    """The session's one build of the book (module docstring)."""
    return built_once(_session_folder(tmp_path_factory), _build)


def built_once(folder: Path, build: Callable[[Path], Site]) -> Site:
    """``build(out)`` run by the first caller of any process sharing ``folder``, read from
    its record by every later one. A failed build is recorded too (every module then
    reports its log, none rebuilds)."""
    record = folder / "rikin-book.json"
    with open(folder / "rikin-book.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file is closed
        if record.is_file():
            return Site(**json.loads(record.read_text(encoding="utf-8")))
        # this process's own folder: a build that raised (a timeout) leaves no record, and
        # the next caller starts afresh
        out = folder / f"rikin-book-{os.getpid()}"
        out.mkdir(exist_ok=True)
        site = build(out)
        record.write_text(json.dumps(asdict(site)), encoding="utf-8")
        return site
