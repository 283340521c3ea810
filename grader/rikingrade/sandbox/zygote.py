"""The grader's side of a sandbox: start a zygote, fork children, talk to them with deadlines.

A :class:`Sandbox` owns one zygote process (inside bubblewrap unless unsafe). Each
submission gets a :class:`Child` forked from it; the grader talks JSON lines with the
child over its own socket and never waits without a deadline. On a timeout the zygote
kills every process in the sandbox but itself; if the zygote does not answer (a student
stopped or killed it) the whole sandbox is killed and a fresh one started.
"""

from __future__ import annotations

import atexit
import json
import logging
import os
import selectors
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import weakref
from pathlib import Path
from typing import Any

from ..wire import WireError, decode_message, encode_message
from . import uidmode
from .cgroup import MIB, MemoryGroup
from .config import (
    CHILD_PATH,
    MPL_DIR,
    NOBODY,
    SCRATCH,
    UID,
    Limits,
    SandboxConfig,
    SandboxUnavailable,
    bwrap_command,
    bwrap_failure,
    find_bwrap,
    hidden_paths,
    reachable_tmpdir,
    read_only_binds,
    world_readable,
)

log = logging.getLogger("rikingrade.sandbox")

HERE = Path(__file__).resolve().parent
CHILD_SCRIPT = HERE / "child.py"
LAUNCHER_SCRIPT = HERE / "launcher.py"
START_TIMEOUT = 120.0  # seconds for a zygote to import numpy, sympy, matplotlib, rikin
CONTROL_TIMEOUT = 2.0  # seconds for the zygote to answer a control message
MAX_MESSAGE = 64 * 1024 * 1024  # bytes in one message from a child
WARM_BYTES = 60_000  # bytes of cells sent to a zygote to compile ahead (one message)
SANDBOX_STOPPED = (
    "the sandbox itself was stopped (the notebook killed or stopped the grader's helper)"
)


#: uid mode: the sandboxes holding a lease, for :func:`_sweep_at_exit`
_LEASED: weakref.WeakSet[Sandbox] = weakref.WeakSet()


def _sweep_at_exit() -> None:
    """uid mode: end the processes of every uid still leased and remove its files.

    A grader interrupted (Ctrl-C) leaves its daemon worker threads without running their
    ``finally: sandbox.close()``; the zygote dies with the grader, but what the notebook
    being graded wrote in /tmp or /dev/shm would stay there until that uid is leased
    again, readable by another grader's notebooks meanwhile.
    """
    for sandbox in list(_LEASED):
        lease = sandbox.lease
        if lease is not None:
            try:
                uidmode.reap(lease.uid)
                uidmode.sweep_files(lease.uid)
            except Exception as exc:  # at exit: say it, never stop the others' cleanup
                log.warning("could not clean up after sandbox uid %d: %s", lease.uid, exc)


atexit.register(_sweep_at_exit)


class ChildDied(Exception):
    """The child's socket closed: the process ended (crash, os._exit, limit)."""


class ChildTimeout(Exception):
    """No message from the child before the deadline."""


class ProtocolError(Exception):
    """The child sent something that is not a valid message."""


def _valid_str(s: str) -> str:
    try:
        s.encode("utf-8")
        return s
    except UnicodeEncodeError:
        return s.encode("utf-8", "replace").decode("utf-8")  # each lone surrogate -> "?"


def valid_unicode(obj: Any) -> Any:
    """``obj`` with every string (keys too) made encodable as UTF-8."""
    if isinstance(obj, str):
        return _valid_str(obj)
    if isinstance(obj, list):
        return [valid_unicode(x) for x in obj]
    if isinstance(obj, dict):
        return {_valid_str(k): valid_unicode(v) for k, v in obj.items()}
    return obj


class Child:
    """One forked child: a socket and a pid inside the sandbox."""

    def __init__(self, sock: socket.socket, pid: int) -> None:
        self.sock = sock
        self.pid = pid
        self.buf = bytearray()
        self.scanned = 0  # bytes of buf known to hold no newline
        self.sock.setblocking(False)
        self.sel = selectors.DefaultSelector()
        self.sel.register(self.sock, selectors.EVENT_READ)
        self.closed = False

    def send(self, msg: dict[str, Any], deadline: float) -> None:
        data = memoryview(encode_message(msg))
        while data:
            if time.monotonic() > deadline:
                raise ChildTimeout("the notebook process did not read its input")
            try:
                n = self.sock.send(data)
                data = data[n:]
            except BlockingIOError:
                time.sleep(0.001)
            except (BrokenPipeError, ConnectionResetError, OSError) as exc:
                raise ChildDied(str(exc)) from None

    def send_fd(self, msg: dict[str, Any], fd: int) -> None:
        """A short message with a file descriptor attached (it fits the socket buffer)."""
        try:
            socket.send_fds(self.sock, [encode_message(msg)], [fd])
        except OSError as exc:
            raise ChildDied(str(exc)) from None

    def recv(self, deadline: float) -> dict[str, Any]:
        while True:
            nl = self.buf.find(b"\n", self.scanned)
            self.scanned = 0 if nl >= 0 else len(self.buf)  # never scan the same bytes twice
            if nl >= 0:
                line = bytes(self.buf[:nl])
                del self.buf[: nl + 1]
                try:
                    msg = decode_message(line)
                except WireError as exc:
                    raise ProtocolError(str(exc)) from None
                # A lone surrogate ("\udcff", escaped or raw) is valid JSON but no file,
                # log or terminal can take it: every text from a child is made valid here.
                if b"\\u" in line or b"\xed" in line:
                    try:
                        msg = valid_unicode(msg)
                    except RecursionError:
                        raise ProtocolError("a message nested too deeply") from None
                return msg
            if len(self.buf) > MAX_MESSAGE:
                raise ProtocolError(
                    f"a message from the notebook process exceeded {MAX_MESSAGE} bytes"
                )
            left = deadline - time.monotonic()
            if left <= 0:
                raise ChildTimeout()
            if not self.sel.select(timeout=left):
                continue
            try:
                chunk = self.sock.recv(1 << 20)
            except BlockingIOError:
                continue
            except (ConnectionResetError, OSError) as exc:
                raise ChildDied(str(exc)) from None
            if not chunk:
                raise ChildDied("the notebook process ended")
            self.buf += chunk

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            try:
                self.sel.close()
            finally:
                self.sock.close()


class Sandbox:
    """A zygote process that forks one child per submission.

    Parameters
    ----------
    config : SandboxConfig
        Sandboxed (bubblewrap) or not, what to bind and hide.
    workdir : Path
        A private directory of the grader for the files the sandbox needs
        (the engine script, the font cache); created world-readable.
    """

    def __init__(self, config: SandboxConfig, workdir: Path) -> None:
        self.config = config
        self.workdir = Path(workdir)
        self.proc: subprocess.Popen[bytes] | None = None
        self.ctl: socket.socket | None = None
        self.starts = 0
        self.lock = threading.Lock()
        self.stderr_path = self.workdir / f"zygote-{id(self):x}.stderr"
        self.staging: Path | None = None
        self.lease: uidmode.UidLease | None = None  # uid mode: this zygote's own uid
        self.scratch: Path | None = None
        self.launcher_notes: dict[str, Any] = {}
        self.group: MemoryGroup | None = None  # the sandbox's memory cgroup (root only)
        self.warmed = 0  # the start whose zygote compiled a notebook's cells ahead
        self.forked = False  # uid mode: a child ran since the shared folders were swept
        self.base = 0  # bytes the group holds once the zygote is ready

    # ------------------------------------------------------------------ lifecycle
    def start(self) -> None:
        self.close()
        self.starts += 1
        self.forked = False  # uid mode: the lease swept the shared folders (UidLease.acquire)
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        argv, env, pass_fds = self._command(theirs.fileno())
        stderr = open(self.stderr_path, "wb")
        try:
            self.proc = subprocess.Popen(
                argv,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=stderr,
                pass_fds=pass_fds,
                env=env,
                start_new_session=True,
                cwd=str(self.workdir),
            )
        finally:
            stderr.close()
            theirs.close()
        self.ctl = ours
        try:
            msg = self._ctl_recv(START_TIMEOUT)
            if "launcher" in msg:  # uid mode: what the launcher could remove (network)
                self.launcher_notes = msg["launcher"]
                msg = self._ctl_recv(START_TIMEOUT)
        except Exception as exc:
            err = self._stderr_tail()
            self.close()
            if self.config.mode == UID or not self.config.sandbox:
                raise SandboxUnavailable(
                    f"the sandbox did not start ({exc}).\n{err}".rstrip()
                ) from None
            raise SandboxUnavailable(
                f"{bwrap_failure(err)}\n(the sandbox did not start: {exc})"
            ) from None
        if not msg.get("ready"):
            self.close()
            raise SandboxUnavailable(f"the sandbox did not start: {msg}")
        if self.group is not None:
            self.base = self.group.usage()
        for e in msg.get("preload_errors", []):
            log.warning("sandbox could not preload %s", e)
        self.preload_errors = msg.get("preload_errors", [])

    def _stderr_tail(self) -> str:
        try:
            return self.stderr_path.read_text(errors="replace")[-3000:]
        except OSError:
            return ""

    def _command(self, ctl_fd: int) -> tuple[list[str], dict[str, str], list[int]]:
        cfg = self.config
        env = {
            "PATH": "/usr/bin:/bin",
            "LANG": "C.UTF-8",
            "MPLBACKEND": "Agg",
            "MPLCONFIGDIR": MPL_DIR,
            "OPENBLAS_NUM_THREADS": "1",
            "OMP_NUM_THREADS": "1",
            "MKL_NUM_THREADS": "1",
            "NUMEXPR_NUM_THREADS": "1",
            "PYTHONDONTWRITEBYTECODE": "1",
            "PYTHONHASHSEED": "0",
            "PYTHONIOENCODING": "utf-8",
        }
        scratch = SCRATCH if cfg.sandbox else str(self._unsafe_scratch())
        child_cfg = {
            "ctl_fd": ctl_fd,
            "preload": list(cfg.preload),
            "pidns": cfg.sandbox,
            "scratch": scratch,
            "env": {},
        }
        if not cfg.sandbox:
            env["MPLCONFIGDIR"] = str(self.workdir / "mpl")
            env["HOME"] = scratch
            argv = [cfg.python, "-s", str(self.workdir / "child.py"), json.dumps(child_cfg)]
            return argv, env, [ctl_fd]
        if cfg.mode == UID:
            return self._uid_command(ctl_fd, env, child_cfg)
        bwrap = find_bwrap(cfg)
        binds = read_only_binds(cfg)
        hidden = hidden_paths(cfg, binds)
        files = [(str(self.workdir / "child.py"), CHILD_PATH)]
        font = self._font_cache()
        if font is not None:
            files.append((str(font), f"{MPL_DIR}/{font.name}"))
        root = os.geteuid() == 0
        stage: list[list[str]] = []
        bind_pairs: list[tuple[str, str]] = []
        staging = None  # made when root
        if root:  # bubblewrap runs as nobody: stage where nobody can reach (not a 0700 TMPDIR)
            staging = Path(tempfile.mkdtemp(prefix="rikingrade-stage-", dir=reachable_tmpdir()))
            os.chmod(staging, 0o755)
            self.staging = staging
        for i, b in enumerate(binds):
            if staging is not None and not world_readable(b):
                name = f"s{i}"
                stage.append([str(b), name])
                bind_pairs.append((str(staging / name), str(b)))
            else:
                bind_pairs.append((str(b), str(b)))
        child_args = [cfg.python, "-s", CHILD_PATH, json.dumps(child_cfg)]
        argv = bwrap_command(cfg, bind_pairs, hidden, files, child_args, env)
        argv[0] = bwrap
        log.debug("sandbox command: %s", argv)
        self.command = argv
        if root:
            self.group = MemoryGroup.create(f"rikingrade-{os.getpid()}-{id(self):x}-{self.starts}")
            launcher = {
                "uid": cfg.uid,
                "gid": cfg.uid,
                "staging": str(self.staging),
                "stage": stage,
                "argv": argv,
                "cgroup": self.group.procs if self.group is not None else None,
            }
            lpath = self.workdir / "launcher.py"
            return (
                [sys.executable, "-S", "-E", "-s", str(lpath), json.dumps(launcher)],
                {},
                [ctl_fd],
            )
        return argv, {}, [ctl_fd]

    def _uid_command(
        self, ctl_fd: int, env: dict[str, str], child_cfg: dict[str, Any]
    ) -> tuple[list[str], dict[str, str], list[int]]:
        """No namespaces: the launcher drops to this zygote's own uid and execs it."""
        cfg = self.config
        self.lease = uidmode.UidLease.acquire()
        _LEASED.add(self)
        uid = self.lease.uid
        self.scratch = uidmode.private_scratch(self.workdir, uid)
        mpl = self.scratch / ".mpl"
        mpl.mkdir(mode=0o700)
        font = self._font_cache()
        if font is not None:
            shutil.copyfile(font, mpl / font.name)
            os.chown(mpl / font.name, uid, uid)
        os.chown(mpl, uid, uid)
        env.update({"MPLCONFIGDIR": str(mpl), "HOME": str(self.scratch)})
        child_cfg.update({"pidns": False, "reap": "uid", "scratch": str(self.scratch)})
        child = str(self.workdir / "child.py")
        argv = [cfg.python, "-I", "-B", child, json.dumps(child_cfg)]
        secret = [str(h) for h in cfg.hidden if os.path.exists(h)]
        self.command = argv
        # Memory for the sandbox as a whole, where the cgroup fs is writable (a root grader
        # on a machine or VM; not in most containers: then the process-count fallback).
        self.group = MemoryGroup.create(f"rikingrade-{os.getpid()}-{id(self):x}-{self.starts}")
        launcher = {
            "op": "uid",
            "uid": uid,
            "gid": uid,
            "ctl_fd": ctl_fd,
            "cwd": str(self.scratch),
            "readable": [child],
            "secret": secret,
            "argv": argv,
            "env": env,
            "cgroup": self.group.procs if self.group is not None else None,
        }
        log.info("sandbox (uid mode) as uid %d: %s", uid, argv)
        return (
            [sys.executable, "-S", "-E", "-s", str(LAUNCHER_SCRIPT), json.dumps(launcher)],
            {},
            [ctl_fd],
        )

    @property
    def uid(self) -> int | None:
        """The host uid student code runs as (uid mode), else None."""
        return self.lease.uid if self.lease is not None else None

    def _unsafe_scratch(self) -> Path:
        d = self.workdir / f"scratch-{id(self):x}"
        d.mkdir(exist_ok=True)
        return d

    def _font_cache(self) -> Path | None:
        found = sorted(self.workdir.glob("fontlist-v*.json"))
        return found[0] if found else None

    def close(self) -> None:
        """Stop the zygote and everything in its sandbox."""
        if self.proc is not None and not self.config.sandbox and self.ctl is not None:
            try:  # unsandboxed there is no PID namespace: let the zygote kill its children
                self.ctl.send(json.dumps({"op": "quit"}).encode())
                self.proc.wait(timeout=1.0)
            except (OSError, subprocess.TimeoutExpired):
                pass
        if self.proc is not None:
            # Nothing inside needs a clean exit: kill bwrap (its --die-with-parent child and
            # the whole PID namespace follow) or, unsandboxed, the zygote's process group.
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except OSError:
                pass
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                log.error("sandbox process %s did not exit after SIGKILL", self.proc.pid)
            self.proc = None
        if self.ctl is not None:
            self.ctl.close()
            self.ctl = None
        if self.group is not None:
            self.group.close()
            self.group = None
        if self.staging is not None:
            try:
                os.rmdir(self.staging)
            except OSError:
                pass
            self.staging = None
        if not self.config.sandbox:
            shutil.rmtree(self.workdir / f"scratch-{id(self):x}", ignore_errors=True)
        if self.lease is not None:  # uid mode: kill(-1) as that uid, then what it left
            uidmode.reap(self.lease.uid)
            uidmode.sweep_files(self.lease.uid)
            if self.scratch is not None:
                shutil.rmtree(self.scratch, ignore_errors=True)
                self.scratch = None
            self.lease.release()
            self.lease = None

    @property
    def alive(self) -> bool:
        return self.proc is not None and self.proc.poll() is None and self.ctl is not None

    # ------------------------------------------------------------------ control
    def _ctl_recv(self, timeout: float) -> dict[str, Any]:
        assert self.ctl is not None
        self.ctl.settimeout(timeout)
        data = self.ctl.recv(65536)
        if not data:
            raise ChildDied("the sandbox's zygote ended")
        msg = json.loads(data)
        if not isinstance(msg, dict):
            raise ProtocolError("bad control message")
        return msg

    def _ctl(
        self, msg: dict[str, Any], fds: list[int] | None = None, timeout: float = CONTROL_TIMEOUT
    ) -> dict[str, Any]:
        assert self.ctl is not None
        self.ctl.settimeout(timeout)
        data = json.dumps(msg).encode()
        if fds:
            socket.send_fds(self.ctl, [data], fds)
        else:
            self.ctl.send(data)
        return self._ctl_recv(timeout)

    def spawn(self, limits: Limits, warm: list[str] | None = None) -> Child:
        """A fresh child forked from the zygote (restarting the sandbox if needed).

        ``warm``: the code cells of the notebook about to run; the first notebook after
        the zygote starts has them compiled in the zygote (:meth:`warm`).
        """
        for _attempt in range(2):
            if not self.alive:
                self.start()
            if warm and self.warmed != self.starts:
                self.warm(warm)
            if self.forked and self.lease is not None and not self._clear_shared():
                continue
            ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
            try:
                reply = self._ctl({"op": "fork", "limits": self._limits(limits)}, [theirs.fileno()])
            except (OSError, ValueError, ChildDied, ProtocolError) as exc:
                log.warning("zygote did not fork (%s); restarting the sandbox", exc)
                ours.close()
                self.close()
                continue
            finally:
                theirs.close()
            if reply.get("ok"):
                self.forked = True
                return Child(ours, int(reply["pid"]))
            ours.close()
            log.warning("zygote refused to fork: %s", reply)
            self.close()
        raise SandboxUnavailable("could not start a notebook process in the sandbox")

    def _clear_shared(self) -> bool:
        """uid mode: end every process of the sandbox's uid but the zygote, then remove what
        that uid left in the machine's world-writable folders (/tmp, /dev/shm, ...).

        Done before each fork of the zygote, so every notebook (and every fresh start of a
        notebook's cells) finds those folders as the first one did, as /scratch is wiped
        for it: nothing written by the notebook graded before it on this worker, and no room
        of /dev/shm taken by it. Processes first, so nothing writes again after the sweep;
        only files the uid owns are removed. The zygote keeps no file there (its scratch and
        matplotlib folder are private). False when the zygote did not answer: it was then
        closed (which sweeps as well) and a fresh one must be started.
        """
        assert self.lease is not None
        try:
            ok = bool(self._ctl({"op": "kill"}).get("ok"))
        except (OSError, ValueError, ChildDied, ProtocolError) as exc:
            log.info("zygote did not answer kill (%s); restarting the sandbox", exc)
            ok = False
        if not ok:
            self.close()
            return False
        uidmode.sweep_files(self.lease.uid)
        self.forked = False
        return True

    def warm(self, cells: list[str]) -> None:
        """Have the zygote parse and compile ``cells`` once for every child it forks.

        The cells most notebooks of a class share (the exercise's setup and checks, often
        most of a notebook's code) then cost a child nothing to compile; a cell a notebook
        changed is compiled by its child as before. Sent once per zygote, in one control
        message (cells that do not fit are left out); a zygote that does not answer is
        replaced by a fresh one, which is not asked again.
        """
        self.warmed = self.starts
        sent: list[str] = []
        size = 0
        for cell in cells:
            n = len(json.dumps(cell))
            if size + n < WARM_BYTES:
                sent.append(cell)
                size += n
        if not sent:
            return
        try:
            self._ctl({"op": "warm", "cells": sent}, timeout=CONTROL_TIMEOUT + 3)
        except (OSError, ValueError, ChildDied, ProtocolError) as exc:
            # a notebook's cells must never stop grading: a fresh zygote, without them
            log.info("zygote did not answer warm (%s); restarting the sandbox", exc)
            self.close()
            self.start()
            self.warmed = self.starts

    def _limits(self, limits: Limits) -> dict[str, Any]:
        """A child's limits: the whole sandbox's memory in its cgroup, or a process count
        that keeps processes x per-process memory within its share of the machine."""
        out: dict[str, Any] = limits.as_dict()
        if self.group is not None:
            # the notebook's memory_mb on top of what the zygote holds, /scratch's tmpfs
            # pages and a little for the kernel's bookkeeping
            extra = (limits.memory_mb + self.config.tmp_mb + 64) * MIB
            try:
                self.group.set_limit(self.base + extra)
            except OSError as exc:  # the rlimits still hold; say so rather than stop
                log.warning("could not set the sandbox's memory cgroup limit: %s", exc)
        elif limits.share_mb is not None:
            out["share_mb"] = int(limits.share_mb)
        return out

    def reset(self) -> None:
        """Kill every process in the sandbox but the zygote and wipe its scratch space.

        A zygote that does not answer in time is replaced by a fresh sandbox.
        """
        if not self.alive:
            self.close()
            return
        try:
            reply = self._ctl({"op": "kill"})
            if reply.get("ok"):
                return
        except (OSError, ValueError, ChildDied, ProtocolError) as exc:
            log.info("zygote did not answer kill (%s); restarting the sandbox", exc)
        self.close()

    def kill_except(self, keep: int) -> bool:
        """Kill every process in the sandbox but the zygote and ``keep`` (a template).

        False when ``keep`` is gone or cannot be kept (unsandboxed: no PID namespace nor uid
        of its own): then everything was killed and the scratch wiped, as :meth:`reset` does.
        """
        if not self.alive:
            self.close()
            return False
        try:
            reply = self._ctl({"op": "kill_except", "keep": keep}, timeout=CONTROL_TIMEOUT + 3)
            if reply.get("ok"):
                return bool(reply.get("kept"))
        except (OSError, ValueError, ChildDied, ProtocolError) as exc:
            log.info("zygote did not answer kill_except (%s); restarting the sandbox", exc)
        self.close()
        return False

    def status_of(self, pid: int, timeout: float = 1.0) -> str:
        """Why child ``pid`` ended, in words ("killed (SIGKILL)", "exited with code 0")."""
        if not self.alive:
            return SANDBOX_STOPPED
        try:
            reply = self._ctl(
                {"op": "wait", "pid": pid, "timeout": timeout}, timeout=timeout + CONTROL_TIMEOUT
            )
        except (OSError, ValueError, ChildDied, ProtocolError):
            self.close()
            return SANDBOX_STOPPED
        return reply.get("status") or "ended"


def prepare_workdir(workdir: Path, sandboxed: bool) -> None:
    """Copy the engine scripts and a matplotlib font cache where the sandbox can read them."""
    workdir.mkdir(parents=True, exist_ok=True)
    os.chmod(workdir, 0o755)
    for script in (CHILD_SCRIPT, LAUNCHER_SCRIPT):
        dest = workdir / script.name
        shutil.copyfile(script, dest)
        os.chmod(dest, 0o644)
    try:  # build the font cache once here, so no sandbox spends a second rebuilding it
        import matplotlib
        from matplotlib import font_manager

        cache = Path(matplotlib.get_cachedir())
        name = f"fontlist-v{font_manager.FontManager.__version__}.json"
        if (cache / name).exists():
            dest = workdir / name
            shutil.copyfile(cache / name, dest)
            os.chmod(dest, 0o644)
            if not sandboxed:
                (workdir / "mpl").mkdir(exist_ok=True)
                shutil.copyfile(cache / name, workdir / "mpl" / name)
    except Exception as exc:  # pragma: no cover - matplotlib missing: plots are just slower
        log.info("no matplotlib font cache to share with the sandbox: %s", exc)


__all__ = [
    "Child",
    "ChildDied",
    "ChildTimeout",
    "ProtocolError",
    "Sandbox",
    "SandboxUnavailable",
    "prepare_workdir",
    "NOBODY",
]
