"""Memory for a sandbox as a whole: a memory cgroup where the grader may make one.

An rlimit (``RLIMIT_AS``) bounds one process; a notebook that forks gets that much again
for every process (four forks held 4 x 700 MiB under a 1 GiB limit). So a root grader puts
each sandbox in a memory cgroup of its own (cgroup v2, or the v1 ``memory`` hierarchy),
whose limit counts every process in it together, tmpfs pages of ``/scratch`` included;
the kernel's OOM killer then stops a process inside it (the children ask to be chosen
first), never anything outside. Where no cgroup can be made (no root, a read-only
cgroupfs as in most containers), :func:`fallback_processes` bounds the process count
instead, so that processes x per-process limit stays within the sandbox's share of the
machine's memory.
"""

from __future__ import annotations

import logging
import os
import time
from pathlib import Path

log = logging.getLogger("rikingrade.sandbox")

MIB = 1024 * 1024
ROOT = Path("/sys/fs/cgroup")


def _own_path(controller: str) -> str | None:
    """This process's cgroup path in ``controller``'s hierarchy ("" for v2)."""
    try:
        lines = Path("/proc/self/cgroup").read_text().splitlines()
    except OSError:
        return None
    for line in lines:
        parts = line.split(":", 2)
        if len(parts) == 3 and controller in parts[1].split(","):
            return parts[2]
        if len(parts) == 3 and controller == "" and parts[0] == "0" and parts[1] == "":
            return parts[2]
    return None


def _read_int(path: Path) -> int | None:
    try:
        text = path.read_text().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


class MemoryGroup:
    """One sandbox's memory cgroup (v2 ``memory.max`` or v1 ``memory.limit_in_bytes``)."""

    def __init__(self, path: Path, v2: bool) -> None:
        self.path = path
        self.v2 = v2
        self.limit: int | None = None

    @property
    def procs(self) -> str:
        """The file a process writes its pid to, to join the group."""
        return str(self.path / "cgroup.procs")

    @classmethod
    def create(cls, name: str) -> MemoryGroup | None:
        """A new empty group below this process's own, or None where none can be made."""
        if os.geteuid() != 0:
            return None
        v2_own = _own_path("")
        if v2_own is not None and (ROOT / "cgroup.controllers").exists():
            parent = ROOT / v2_own.lstrip("/")
            try:
                if "memory" in (parent / "cgroup.subtree_control").read_text().split():
                    path = parent / name
                    path.mkdir()
                    return cls(path, True)
            except OSError as exc:
                log.info("no cgroup v2 memory group here: %s", exc)
        v1_own = _own_path("memory")
        if v1_own is not None and (ROOT / "memory").is_dir():
            path = ROOT / "memory" / v1_own.lstrip("/") / name
            try:
                path.mkdir()
                return cls(path, False)
            except OSError as exc:
                log.info("no cgroup v1 memory group here: %s", exc)
        return None

    def usage(self) -> int:
        name = "memory.current" if self.v2 else "memory.usage_in_bytes"
        return _read_int(self.path / name) or 0

    def set_limit(self, nbytes: int) -> None:
        """Memory (and no swap) for every process in the group together."""
        if nbytes == self.limit:
            return
        if self.v2:
            files = [("memory.max", nbytes), ("memory.swap.max", 0)]
        else:
            # memsw (memory + swap) must stay >= the memory limit: order the writes
            up = self.limit is not None and nbytes > self.limit
            pair = [("memory.memsw.limit_in_bytes", nbytes), ("memory.limit_in_bytes", nbytes)]
            files = pair if up else pair[::-1]
        for fname, value in files:
            try:
                (self.path / fname).write_text(str(value))
            except OSError as exc:
                if fname in ("memory.max", "memory.limit_in_bytes"):
                    raise
                log.debug("cgroup %s: %s", fname, exc)  # no swap accounting: nothing to bound
        self.limit = nbytes

    def close(self) -> None:
        """Kill what is left in the group and remove it."""
        for _ in range(200):
            try:
                pids = [int(p) for p in Path(self.procs).read_text().split()]
            except OSError:
                return
            for pid in pids:
                try:
                    os.kill(pid, 9)
                except OSError:
                    pass
            try:
                self.path.rmdir()
                return
            except OSError:
                time.sleep(0.01)
        log.warning("could not remove the sandbox's cgroup %s", self.path)


def machine_memory_mb() -> int:
    """The memory this grader may use: the machine's, or its own cgroup's limit if lower."""
    total = 0
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                total = int(line.split()[1]) // 1024
    except (OSError, ValueError):
        total = 4096
    limits = []
    own = _own_path("")
    if own is not None:
        limits.append(_read_int(ROOT / own.lstrip("/") / "memory.max"))
    own1 = _own_path("memory")
    if own1 is not None:
        limits.append(_read_int(ROOT / "memory" / own1.lstrip("/") / "memory.limit_in_bytes"))
    for lim in limits:
        if lim is not None and lim // MIB < total:
            total = lim // MIB
    return max(total, 1)
