"""The sandbox probe: :func:`check_sandbox` starts a sandbox and reports what a notebook
inside it can see and do (the command ``rikin-grade check-sandbox``)."""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .sandbox import Limits, Sandbox, SandboxConfig, SandboxUnavailable, prepare_workdir
from .sandbox.config import DESCRIBE, NONE, UID, package_dir, resolve_mode, sandbox_workdir
from .sandbox.uidmode import SHARED_WRITABLE

PROBE = r"""
import os, socket, subprocess
def probe(paths):
    r = {"uid": os.getuid(), "gid": os.getgid(), "cwd": os.getcwd()}
    r["root"] = sorted(os.listdir("/"))
    def readable(p):
        try:
            if os.path.isdir(p):
                return bool(os.listdir(p))
            with open(p, "rb") as f:
                return bool(f.read(1))
        except OSError:
            return False
    r["visible"] = [p for p in paths if readable(p)]
    try:
        socket.create_connection(("1.1.1.1", 53), timeout=2).close()
        r["network"] = True
    except OSError as e:
        r["network"] = False
    written = []
    stdlib = os.path.dirname(os.__file__)
    for d in ("/", "/tmp", "/usr", "/etc", stdlib, "/opt", "/dev", "/dev/shm"):
        try:
            with open(os.path.join(d, "rikingrade-probe"), "w") as f:
                f.write("x")
            written.append(d)
            os.unlink(os.path.join(d, "rikingrade-probe"))
        except OSError:
            pass
    r["writable"] = written
    with open("/proc/self/status") as f:
        r["status_uid"] = [l.split()[1:] for l in f if l.startswith("Uid:")][0]
    return r
"""


def _host_uid(pid: int) -> int | None:
    """The real uid of ``pid`` as the host sees it (what RLIMIT_NPROC counts against)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("Uid:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def check_sandbox(
    unsafe_no_sandbox: bool = False,
    paths: Sequence[str | Path] = (),
    hidden: Sequence[str | Path] = (),
    sandbox: str = "auto",
) -> dict[str, Any]:
    """Start a sandbox and report what a notebook inside it can see and do.

    ``paths`` must be unreadable from inside; ``hidden`` are masked like the grader package
    (use it for paths inside a bound directory) and must be unreadable too. ``sandbox`` is
    the mode to probe (``auto``: the one :func:`rikingrade.api.grade` would use here).

    Returns a dict with ``ok`` (True when none of those paths, the grader package or the
    course is readable, there is no network and nothing outside the places the mode wipes
    is writable), ``mode`` and its description, why stronger modes were not used
    (``notes``), the probe's raw findings and the command used.

    Raises
    ------
    SandboxUnavailable
        No sandbox of that mode can start here (the message says what failed).
    """
    config = SandboxConfig(sandbox=not unsafe_no_sandbox, mode=sandbox)
    secret = _mask(config, paths, hidden)
    resolve_mode(config)
    workdir = sandbox_workdir()
    sandbox_ = Sandbox(config, workdir)
    try:
        prepare_workdir(workdir, config.sandbox)
        try:
            sandbox_.start()
        except SandboxUnavailable as exc:
            raise SandboxUnavailable("\n".join([*config.notes, str(exc)])) from None
        reply = _probe(sandbox_, secret)
        found = reply.get("value") or {}
        host_uid = _host_uid(sandbox_.proc.pid) if sandbox_.proc is not None else None
        return {
            "ok": _isolated(config, found, host_uid),
            "mode": config.mode,
            "mode_description": DESCRIBE[config.mode],
            "notes": list(config.notes),
            "sandboxed": config.sandbox,
            "probe": found,
            "error": reply.get("error_message"),
            "preload_errors": sandbox_.preload_errors,
            "launcher": sandbox_.launcher_notes,
            "command": getattr(sandbox_, "command", None),
            "grader_uid": os.geteuid(),
            "sandbox_host_uid": host_uid,
        }
    finally:
        sandbox_.close()
        shutil.rmtree(workdir, ignore_errors=True)


def _mask(
    config: SandboxConfig, paths: Sequence[str | Path], hidden: Sequence[str | Path]
) -> list[str]:
    """Mask ``hidden`` and the grader package in ``config``; the paths the probe must not
    read: those, the grader's hidden tests and the course's solutions, grader and .git."""
    grader_pkg = package_dir("rikingrade")
    secret = [str(p) for p in [*paths, *hidden]]
    config.hidden = [Path(h) for h in hidden]
    if grader_pkg is not None:
        course = grader_pkg.parent.parent
        config.hidden.append(grader_pkg)
        secret += [
            str(grader_pkg),
            str(grader_pkg / "hidden"),
            str(course / "solutions"),
            str(course / "grader"),
            str(course / ".git"),
        ]
    return secret


def _probe(sandbox_: Sandbox, secret: list[str]) -> dict[str, Any]:
    """Run :data:`PROBE` in a notebook process of ``sandbox_``; the call's reply."""
    child = sandbox_.spawn(Limits())
    deadline = time.monotonic() + 30
    child.send({"op": "exec", "cells": [[1, PROBE]], "output_limit": 1000}, deadline)
    while child.recv(deadline).get("event") != "exec_done":
        pass
    child.send({"op": "call", "id": 1, "function": "probe", "kwargs": {"paths": secret}}, deadline)
    reply = child.recv(deadline)
    child.close()
    return reply


def _isolated(config: SandboxConfig, found: dict[str, Any], host_uid: int | None) -> bool:
    """Whether the probe's findings show isolation: a sandbox, not root inside or on the
    host, nothing secret readable, no network, nothing writable the mode does not wipe."""
    # the uid mode cannot stop writes to the world-writable folders: it wipes them after
    wiped = set(SHARED_WRITABLE) if config.mode == UID else set()
    writable = [d for d in found.get("writable") or [] if d not in wiped]
    return bool(
        config.mode != NONE
        and host_uid not in (0, None)
        and not found.get("visible")
        and found.get("network") is False
        and not writable
        and found.get("uid") != 0
    )
