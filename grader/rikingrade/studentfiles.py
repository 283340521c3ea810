"""Reading submission files without the grader's privileges.

A grader run as root (the uid sandbox needs it; many instructors unzip and grade with
sudo) would otherwise open whatever a submission names: a hard link to ``/etc/shadow`` or
to the course's hidden tests is a regular file. So a root grader reads each student file
through a helper process (:mod:`rikingrade.filereader`) that has dropped to an
unprivileged uid and gid with no supplementary groups:

- the owner of the folder holding the file, or of the nearest folder above it up to the
  submissions folder given, that is not root: a student folder on a shared machine is
  read as its student, a download unzipped by an instructor as that instructor;
- else (everything owned by root: unzipped or extracted as root) a uid of its own,
  leased from the sandbox's reserved range, that owns nothing and is in no group, so it
  reads only what every user may read.

A file that uid may not read is refused, unless every folder from the submissions folder
down is owned by root or by the owner of the submissions folder passed (the instructor)
and writable by no one else: then only they can have put it there (a download unzipped as
root whose entries say 0600, as Python's and some LMS zips do), and it is read as root,
still only if it has a single name. So pass a folder that you or root own: student
folders below it, owned by their students, are read with their rights alone.

Not root, the grader reads in-process: the OS already stops it. Either way the file is
opened relative to the submissions folder's directory fd with ``O_NOFOLLOW`` at every
step, must be a regular file with a single name (a hard link is a file linked in from
elsewhere) and at most the size cap.
"""

from __future__ import annotations

import json
import os
import pwd
import socket
import subprocess
import sys
import threading
from collections import OrderedDict
from pathlib import Path
from typing import TYPE_CHECKING

from . import filereader
from .filereader import DENIED, GONE, REFUSED, TOO_LARGE, ReadFailed

if TYPE_CHECKING:  # pragma: no cover
    from .sandbox.uidmode import UidLease

HELPER = Path(filereader.__file__).resolve()
#: Helper processes kept at once (one per reading identity; the least recent is closed).
MAX_HELPERS = 4
#: Seconds a helper may take to answer one packet before it is killed.
READ_TIMEOUT = 60.0
NOGROUP = 65534

__all__ = [
    "GONE",
    "REFUSED",
    "TOO_LARGE",
    "ReadFailed",
    "StudentFiles",
    "default_files",
    "read_in_process",
]


class _Closed(Exception):
    """The helper was closed (evicted) before it could serve this request."""


class _Helper:
    def __init__(self, uid: int, gid: int, who: str) -> None:
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        cfg = {"fd": theirs.fileno(), "uid": uid, "gid": gid, "who": who}
        try:
            self.proc = subprocess.Popen(
                [sys.executable, "-S", "-E", "-s", str(HELPER), json.dumps(cfg)],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                pass_fds=[theirs.fileno()],
                cwd="/",
            )
        finally:
            theirs.close()
        self.sock = ours
        self.sock.settimeout(READ_TIMEOUT)
        self.lock = threading.Lock()
        try:
            hello = json.loads(self.sock.recv(4096) or b"{}")
        except (OSError, ValueError):
            hello = {}
        if not hello.get("ready"):
            err = b""
            try:
                self.proc.kill()
                _, err = self.proc.communicate(timeout=5)
            except (OSError, subprocess.SubprocessError):
                pass
            self.close()
            raise OSError(f"the file reader as uid {uid} did not start: {err.decode()[-500:]}")

    def read(self, dirfd: int, rel: list[bytes], cap: int, links: bool) -> bytes:
        req = json.dumps({"rel": [n.hex() for n in rel], "cap": cap, "links": links}).encode()
        with self.lock:
            if self.sock is None:
                raise _Closed()
            try:
                socket.send_fds(self.sock, [req], [dirfd])
                head = json.loads(self.sock.recv(65536))
                if not head.get("ok"):
                    raise ReadFailed(
                        head.get("kind", REFUSED),
                        str(head.get("why", "")),
                        int(head.get("size", 0)),
                        str(head.get("reason", "")),
                    )
                n = int(head["n"])
                buf = bytearray(n)  # filled in place: one copy of a large notebook
                view, got = memoryview(buf), 0
                while got < n:
                    k = self.sock.recv_into(view[got:], min(filereader.CHUNK, n - got))
                    if not k:
                        raise OSError("the file reader ended")
                    got += k
                return buf  # type: ignore[return-value]
            except ReadFailed:
                raise
            except (OSError, ValueError, KeyError) as exc:
                self.close()
                raise ReadFailed(REFUSED, f"the file could not be read ({exc})") from None

    @property
    def alive(self) -> bool:
        return self.sock is not None and self.proc.poll() is None

    def close(self) -> None:
        if self.sock is not None:
            self.sock.close()
            self.sock = None  # type: ignore[assignment]
        try:
            self.proc.kill()
            self.proc.wait(timeout=5)
        except (OSError, subprocess.SubprocessError):
            pass


class StudentFiles:
    """Reads files below submissions folders (see the module docstring); thread-safe."""

    def __init__(self) -> None:
        self._roots: dict[str, int] = {}
        self._helpers: OrderedDict[tuple[int, int], _Helper] = OrderedDict()
        self._lock = threading.Lock()
        self._lease: UidLease | None = None  # the uid leased for root-owned folders
        self.root = os.geteuid() == 0

    def _root_fd(self, root: Path) -> int:
        key = os.fsdecode(root)
        with self._lock:
            fd = self._roots.get(key)
            if fd is None:
                fd = os.open(root, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
                self._roots[key] = fd
            return fd

    def read(self, root: Path, path: Path, cap: int, *, links: bool = False) -> bytes:
        """The bytes of ``path``, a file below the submissions folder ``root``.

        Raises
        ------
        ReadFailed
            Refused (a link, no right to read it), too large, or gone; ``why`` says which
            in words for the instructor and the student.
        """
        try:
            rel = [os.fsencode(p) for p in Path(path).relative_to(root).parts]
        except ValueError:
            root, rel = Path(path).parent, [os.fsencode(Path(path).name)]
        try:
            dirfd = self._root_fd(Path(root))
        except OSError as exc:
            raise ReadFailed(GONE, f"its folder cannot be opened ({exc.strerror})") from None
        if not self.root:
            try:
                return filereader.read_at(dirfd, rel, cap, links)
            except ReadFailed as exc:
                if exc.kind == DENIED:
                    raise ReadFailed(REFUSED, exc.why, reason=exc.reason) from None
                raise
        uid, gid, who, root_only = self._identity(dirfd, rel)
        try:
            for _attempt in range(3):
                try:
                    return self._helper(uid, gid, who).read(dirfd, rel, cap, links)
                except _Closed:
                    continue
            raise ReadFailed(REFUSED, "the file could not be read (its reader kept closing)")
        except ReadFailed as exc:
            if exc.kind != DENIED:
                raise
            if root_only:
                # Every folder from the submissions folder down is writable only by root
                # and that folder's owner (the instructor): only they can have put this
                # file (of one name) here, e.g. by unzipping as root a download whose
                # entries say 0600. Read it as root, once more refusing links.
                return filereader.read_at(dirfd, rel, cap, False)
            raise ReadFailed(REFUSED, exc.why, reason=exc.reason) from None

    def _identity(self, dirfd: int, rel: list[bytes]) -> tuple[int, int, str, bool]:
        """Whom to read ``rel`` as: the nearest folder owner that is not root, else a uid
        of the grader's own; and whether only root and the owner of the folder passed (the
        instructor) could write every folder on the way."""
        st = os.fstat(dirfd)
        owners = [st.st_uid]
        top = (0, st.st_uid)  # root and whoever owns the folder passed (the instructor)
        root_only = not st.st_mode & 0o022
        fd, opened = dirfd, []
        try:
            for name in rel[:-1]:
                try:
                    fd = os.open(name, os.O_PATH | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=fd)
                except OSError:
                    root_only = False
                    break  # the helper says why
                opened.append(fd)
                st = os.fstat(fd)
                owners.append(st.st_uid)
                root_only = root_only and st.st_uid in top and not st.st_mode & 0o022
        finally:
            for f in opened:
                os.close(f)
        uid = next((u for u in reversed(owners) if u != 0), 0)
        if uid:
            try:
                pw = pwd.getpwuid(uid)
                gid, who = (pw.pw_gid or NOGROUP), f"{pw.pw_name} (uid {uid})"
            except KeyError:
                gid, who = NOGROUP, f"uid {uid}"
            return uid, gid, f"the folder's owner {who}", root_only
        with self._lock:
            if self._lease is None:
                from .sandbox.uidmode import UidLease

                self._lease = UidLease.acquire()
            lease = self._lease.uid
        return lease, lease, f"an unprivileged user (uid {lease})", root_only

    def _helper(self, uid: int, gid: int, who: str) -> _Helper:
        with self._lock:
            h = self._helpers.get((uid, gid))
            if h is not None and h.alive:
                self._helpers.move_to_end((uid, gid))
                return h
            h = _Helper(uid, gid, who)
            self._helpers[(uid, gid)] = h
            while len(self._helpers) > MAX_HELPERS:
                _, old = self._helpers.popitem(last=False)
                with old.lock:
                    old.close()
            return h

    def close(self) -> None:
        with self._lock:
            for h in self._helpers.values():
                h.close()
            self._helpers.clear()
            for fd in self._roots.values():
                os.close(fd)
            self._roots.clear()
            if self._lease is not None:
                from .sandbox import uidmode

                uidmode.reap(self._lease.uid)
                self._lease.release()
                self._lease = None

    def __enter__(self) -> StudentFiles:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def read_in_process(path: Path, cap: int) -> bytes:
    """``path``'s bytes read by this process (no link followed, one name, at most ``cap``)."""
    path = Path(path)
    try:
        dirfd = os.open(path.parent, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError as exc:
        raise ReadFailed(GONE, f"its folder cannot be opened ({exc.strerror})") from None
    try:
        return filereader.read_at(dirfd, [os.fsencode(path.name)], cap)
    except ReadFailed as exc:
        if exc.kind == DENIED:
            raise ReadFailed(REFUSED, exc.why, reason=exc.reason) from None
        raise
    finally:
        os.close(dirfd)


_default: StudentFiles | None = None


def default_files() -> StudentFiles:
    """A reader for submissions made without one (closed at exit)."""
    global _default
    if _default is None:
        import atexit

        _default = StudentFiles()
        atexit.register(_default.close)
    return _default
