"""The sandbox without namespaces: each worker's zygote runs as its own unprivileged uid.

Where user namespaces are refused (a Docker container with the default seccomp profile, as
on Gradescope, or a chroot) bubblewrap cannot start. A root grader can still isolate
student code with plain Unix permissions:

- each worker leases a uid of its own from a reserved range (a lock file per uid, so two
  graders on one machine never share one) that owns no process, no file and no account;
- the zygote runs as that uid and group with no supplementary groups and
  ``PR_SET_NO_NEW_PRIVS`` (setuid programs cannot give root back), so ``RLIMIT_NPROC``
  counts that worker's processes alone and a fork bomb stops at its limit;
- before starting, the launcher checks *as that uid* that none of the grader's files (the
  grader package with its hidden tests and reference, the assignment, the submissions and
  the output folder) can be read, and refuses to start otherwise: this mode is only as safe
  as those permissions, so it proves them instead of assuming them;
- network sockets are refused by a seccomp filter (``socket()`` fails with EACCES; a new
  network namespace is used as well where one can be made);
- ``kill(-1)`` as that uid ends every process it owns, daemonised grandchildren included
  (the zygote does it between submissions; the grader, through the launcher, when the
  zygote itself is gone);
- the machine's world-writable directories (``SHARED_WRITABLE``: /tmp, /var/tmp, /dev/shm,
  ...) are not private here, so before the zygote forks for a notebook the grader ends
  that uid's processes and removes what the uid owns there (:func:`sweep_files`, from
  ``Sandbox.spawn``): each notebook of a worker finds them as the first one did, as
  bubblewrap's wiped /scratch is (children's TMPDIR and HOME are the private scratch);
  notebooks run *at the same time* by other workers (other uids) can still see files
  there that a notebook made readable to all, until its own worker sweeps them;
  the ``rikin-grade`` command makes itself the subreaper of what it starts
  (:func:`adopt_orphans`), so a process orphaned when a zygote dies is adopted and reaped
  by the grader, not left a zombie of a container's init that reaps late or never
  (Docker's without ``--init``), where it would count for the uid's process limit and keep
  the uid from being leased again;
  after a hung call the zygote kills every live process of that uid but the template that
  ran the cells, so those are not run again (as in the bwrap mode);
- a root grader puts each zygote in a memory cgroup of its own where the cgroup fs is
  writable (not in most containers: there the process count bounds memory, see cgroup.py).

What it does not hide: the rest of the machine's world-readable files (``/etc/passwd``,
the Python installation), and the shared directories above from notebooks graded at the
same moment by other workers. On Gradescope (one submission per container) those hold
nothing of the course.
"""

from __future__ import annotations

import errno
import fcntl
import json
import logging
import os
import pwd
import shutil
import stat
import subprocess
import sys
import time
from pathlib import Path

log = logging.getLogger("rikingrade.sandbox")

#: Preferred uids (far above any account); used when this user namespace maps them.
UID_BASE = 2_100_000_000
#: Fallback inside a user namespace that maps only the usual 65,536 ids.
UID_BASE_SMALL = 64_000
UID_COUNT = 256
#: Directories anyone may write to: what a sandbox uid leaves there is removed.
SHARED_WRITABLE = ("/tmp", "/var/tmp", "/dev/shm", "/run/lock", "/var/lock")
LAUNCHER = Path(__file__).resolve().parent / "launcher.py"


def _mapped_ranges() -> list[tuple[int, int]]:
    try:
        with open("/proc/self/uid_map") as f:
            rows = [line.split() for line in f if line.strip()]
        return [(int(r[0]), int(r[0]) + int(r[2])) for r in rows]
    except OSError:
        return [(0, 2**32 - 1)]


def candidate_uids() -> list[int]:
    """The uids a worker may lease here, preferred first."""
    ranges = _mapped_ranges()
    for base in (UID_BASE, UID_BASE_SMALL):
        if any(lo <= base and base + UID_COUNT <= hi for lo, hi in ranges):
            return list(range(base, base + UID_COUNT))
    return []


def _lock_dir() -> Path:
    """A directory only root can write, for one lock file per leased uid."""
    for parent in ("/run", "/var/lock", "/tmp"):
        d = Path(parent) / "rikingrade-uids"
        try:
            d.mkdir(mode=0o700, exist_ok=True)
            st = os.lstat(d)
        except OSError:
            continue
        if stat.S_ISDIR(st.st_mode) and st.st_uid == 0 and not st.st_mode & 0o077:
            return d
    raise OSError("no private directory for the sandbox's uid locks (tried /run, /var/lock, /tmp)")


class UidLease:
    """One uid reserved for one zygote until :meth:`release`."""

    def __init__(self, uid: int, fd: int) -> None:
        self.uid = uid
        self.fd = fd

    @classmethod
    def acquire(cls) -> UidLease:
        lock_dir = _lock_dir()
        for uid in candidate_uids():
            try:
                pwd.getpwuid(uid)
                continue  # a real account: never borrow it
            except KeyError:
                pass
            fd = os.open(lock_dir / f"uid-{uid}.lock", os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o600)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                continue
            if processes_of(uid):  # left by a grader that was killed: end them first
                reap(uid)
            if processes_of(uid):
                os.close(fd)
                continue
            sweep_files(uid)
            return cls(uid, fd)
        raise OSError("every sandbox uid is in use (too many graders on this machine?)")

    def release(self) -> None:
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1


def processes_of(uid: int) -> list[int]:
    """Pids whose real uid is ``uid`` (zombies included: they still count for RLIMIT_NPROC)."""
    found = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/status") as f:
                for line in f:
                    if line.startswith("Uid:"):
                        if int(line.split()[1]) == uid:
                            found.append(int(name))
                        break
        except (OSError, ValueError):
            continue
    return found


def adopt_orphans() -> None:
    """Make this process the subreaper of its descendants (idempotent, Linux >= 3.4).

    A zygote that dies (killed by :meth:`Zygote.close`, or by the OOM killer) leaves its
    children to the nearest subreaper, else to init; in a container whose init reaps late
    or never they stay zombies of the sandbox uid. As the subreaper the grader adopts them
    and :func:`reap` collects them. The ``rikin-grade`` command calls this at its start; a
    program that grades through the API may call it too (it then adopts every orphan of its
    descendants, so it is not done behind the caller's back).
    """
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        pass


def _parent(pid: int) -> int | None:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return int(f.read().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return None


def _collect_zombies(uid: int) -> None:
    """waitpid() the zombies of ``uid`` this process adopted (never another child of ours)."""
    me = os.getpid()
    for pid in processes_of(uid):
        if _parent(pid) == me and _zombie(pid):
            try:
                os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:
                pass


def reap(uid: int, timeout: float = 5.0) -> list[int]:
    """Kill every process of ``uid`` with ``kill(-1)`` as that uid and collect the zombies.

    Returns the pids of ``uid`` still listed after that (zombies of another parent included:
    they still count for the uid's process limit).
    """
    if not processes_of(uid):
        return []
    cfg = {"op": "reap", "uid": uid, "timeout": timeout}
    try:
        subprocess.run(
            [sys.executable, "-S", "-E", "-s", str(LAUNCHER), json.dumps(cfg)],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            timeout=timeout + 5,
            check=False,
        )
    except subprocess.TimeoutExpired:
        pass
    deadline = time.monotonic() + 2.0
    _collect_zombies(uid)
    left = processes_of(uid)
    while left and time.monotonic() < deadline:
        time.sleep(0.02)  # a SIGKILLed process still exiting, or a zombie's parent reaping it
        _collect_zombies(uid)
        left = processes_of(uid)
    if left:
        log.error("processes of sandbox uid %d survived kill(-1): %s", uid, left)
    return left


def _zombie(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except (OSError, IndexError):
        return False


def sweep_files(uid: int, roots: tuple[str, ...] = SHARED_WRITABLE) -> int:
    """Remove what ``uid`` created in the world-writable directories; returns the count."""
    removed = 0

    def walk(d: str, depth: int) -> None:
        nonlocal removed
        try:
            entries = list(os.scandir(d))
        except OSError:
            return
        for e in entries:
            try:
                st = e.stat(follow_symlinks=False)
            except OSError:
                continue
            if st.st_uid == uid:
                try:
                    if stat.S_ISDIR(st.st_mode):
                        _make_removable(e.path)
                        shutil.rmtree(e.path)
                    else:
                        os.unlink(e.path)
                    removed += 1
                except OSError as exc:
                    log.warning("could not remove %s left by sandbox uid %d: %s", e.path, uid, exc)
            elif stat.S_ISDIR(st.st_mode) and st.st_mode & stat.S_IWOTH and depth < 8:
                walk(e.path, depth + 1)  # the uid could write only here

    for root in roots:
        if os.path.isdir(root) and not os.path.islink(root):
            walk(root, 0)
    return removed


#: Folders below a left folder are given their bits back down to this depth (deeper ones
#: are left as they are: root's rmtree needs no bits, so this is only a courtesy).
REMOVABLE_DEPTH = 64
_DIR_NOFOLLOW = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC


def _subfolders(fd: int) -> list[str]:
    """The names of the folders in the open folder ``fd`` (links are not folders here)."""
    with os.scandir(fd) as it:
        return [e.name for e in it if e.is_dir(follow_symlinks=False)]


def _make_removable(path: str) -> None:
    """A sandbox may leave chmod 000 folders: give the owner (us, root) the bits back.

    Never through a link: ``path`` and every folder below it are opened with ``O_NOFOLLOW``
    (each relative to its parent's descriptor) and changed through that descriptor
    (``fchmod``), so a link, or a folder swapped for a link after it was listed, is neither
    changed nor entered: a student's link cannot make the grader chmod anything outside.
    Only the folders on the current path are open at once (at most ``REMOVABLE_DEPTH``).
    """
    try:
        top = os.open(path, _DIR_NOFOLLOW)
    except OSError:
        return  # a link (ELOOP, ENOTDIR) or gone: nothing of the sandbox's to change
    stack: list[tuple[int, list[str]]] = []
    try:
        os.fchmod(top, 0o700)
        stack.append((top, _subfolders(top)))
    except OSError:
        os.close(top)
    while stack:
        fd, names = stack[-1]
        if not names or len(stack) > REMOVABLE_DEPTH:
            os.close(fd)
            stack.pop()
            continue
        try:
            child = os.open(names.pop(), _DIR_NOFOLLOW, dir_fd=fd)
        except OSError:
            continue  # swapped for a link or a file, or gone
        try:
            os.fchmod(child, 0o700)
            stack.append((child, _subfolders(child)))
        except OSError:
            os.close(child)


def private_scratch(parent: Path, uid: int) -> Path:
    """A folder owned by ``uid`` (mode 0700) for the zygote's scratch space."""
    d = parent / f"scratch-{uid}"
    if d.exists():
        shutil.rmtree(d, ignore_errors=True)
    d.mkdir(mode=0o700)
    os.chown(d, uid, uid)
    return d


def readable_by(uid: int, paths: list[str]) -> list[str]:
    """Which of ``paths`` the user ``uid`` could read (checked as that user)."""
    cfg = {"op": "check", "uid": uid, "secret": [str(p) for p in paths]}
    r = subprocess.run(
        [sys.executable, "-S", "-E", "-s", str(LAUNCHER), json.dumps(cfg)],
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    if r.returncode not in (0, 3):
        raise OSError(errno.EPERM, f"could not check permissions as uid {uid}: {r.stderr.strip()}")
    return json.loads(r.stdout or "[]")


__all__ = [
    "UidLease",
    "candidate_uids",
    "private_scratch",
    "processes_of",
    "readable_by",
    "reap",
    "sweep_files",
]
