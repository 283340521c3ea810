"""Read a student's file with the rights of whoever handed it in, never root's.

Two uses, one code path (:func:`read_at`):

- imported by the grader (:mod:`rikingrade.studentfiles`) when it does not run as root:
  the operating system already stops it reading what its user may not;
- run as a helper process by a root grader (``python -S -E -s filereader.py CONFIG``):
  it drops to the uid and gid in ``CONFIG`` with no supplementary groups (and
  ``PR_SET_NO_NEW_PRIVS``; nobody may ptrace it), then serves requests on the
  SOCK_SEQPACKET socket ``CONFIG["fd"]``: each a JSON packet ``{"rel": [hex names],
  "cap": bytes, "links": bool}`` carrying the submissions folder's directory fd, answered
  by a JSON header ``{"ok": true, "n": size}`` and the bytes in packets of 64 KiB, or
  ``{"ok": false, "kind": ..., "why": ...}``.

Either way the file is opened relative to the submissions folder's directory fd, one
name at a time with ``O_NOFOLLOW`` (a symbolic link anywhere on the way is refused, even
one swapped in after discovery), must be a regular file with one name (a hard link to a
file elsewhere is refused) and at most ``cap`` bytes. Standard library only.
"""

import errno
import json
import os
import socket
import stat
import sys

CHUNK = 64 * 1024
_DIR = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC
_FILE = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC
REFUSED, TOO_LARGE, GONE = "refused", "too-large", "gone"
DENIED = "denied"  # refused because these rights may not read it (EACCES)
#: Why a file was refused, as a code the grader words in the student's language:
LINK, HARD_LINK, NOT_A_FILE, NO_RIGHT, UNREADABLE = (
    "link", "hard-link", "not-a-file", "no-right", "unreadable")


class ReadFailed(Exception):
    """``kind`` is REFUSED (links), DENIED (no right), TOO_LARGE (``size`` bytes) or GONE;
    ``reason`` (LINK, HARD_LINK, NOT_A_FILE, NO_RIGHT, UNREADABLE, or "") says which
    refusal, for words in another language than ``why``'s English."""

    def __init__(self, kind, why, size=0, reason=""):
        super().__init__(why)
        self.kind = kind
        self.why = why
        self.size = size
        self.reason = reason


def _failure(exc, name, is_dir, who, dirfd=None):
    shown = name.decode("utf-8", "backslashreplace")
    if exc.errno == errno.ELOOP or (is_dir and exc.errno == errno.ENOTDIR):
        what = "a folder on its path" if is_dir else "it"
        return ReadFailed(
            REFUSED,
            f"{what} ({shown}) is a symbolic link or not a folder: links are not followed",
            reason=LINK,
        )
    if exc.errno in (errno.EACCES, errno.EPERM):
        try:
            st = os.stat(name, dir_fd=dirfd, follow_symlinks=False)
            what = f" (mode {stat.S_IMODE(st.st_mode):04o}, owner uid {st.st_uid})"
        except OSError:
            what = ""
        return ReadFailed(
            DENIED,
            f"{shown}{what} cannot be read by {who or 'its folder owner'}: the grader reads "
            "student files with no more rights than that, never root's (a real submission: "
            "make it readable, e.g. chmod -R a+rX on the class folder)",
            reason=NO_RIGHT,
        )
    if exc.errno == errno.ENOENT:
        return ReadFailed(GONE, f"{shown} is no longer there (moved or deleted during grading)")
    return ReadFailed(
        REFUSED, f"{shown} cannot be read ({os.strerror(exc.errno or 0)})", reason=UNREADABLE
    )


def read_at(dirfd, rel, cap, links=False, who=""):
    """The bytes of the file ``rel`` (names, as bytes) below the directory fd ``dirfd``.

    Raises
    ------
    ReadFailed
        A link on the way, not a regular file, several names (``links`` False), no right
        to read it, more than ``cap`` bytes, or gone.
    """
    if not rel:
        raise ReadFailed(REFUSED, "no file name")
    opened = []
    fd = dirfd
    try:
        for name in rel[:-1]:
            try:
                fd = os.open(name, _DIR, dir_fd=fd)
            except OSError as exc:
                raise _failure(exc, name, True, who, fd) from None
            opened.append(fd)
        try:
            fd = os.open(rel[-1], _FILE, dir_fd=fd)
        except OSError as exc:
            raise _failure(exc, rel[-1], False, who, fd) from None
        opened.append(fd)
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise ReadFailed(REFUSED, "not a regular file", reason=NOT_A_FILE)
        if st.st_nlink > 1 and not links:
            raise ReadFailed(
                REFUSED,
                f"a hard link ({st.st_nlink} names for one file): a file linked in from "
                "elsewhere is not read",
                reason=HARD_LINK,
            )
        if st.st_size > cap:
            raise ReadFailed(TOO_LARGE, f"{st.st_size} bytes", st.st_size)
        os.set_blocking(fd, True)
        parts = []
        got = 0
        while True:
            block = os.read(fd, min(CHUNK * 16, cap + 1 - got))
            if not block:
                break
            parts.append(block)
            got += len(block)
            if got > cap:  # grew while being read
                raise ReadFailed(TOO_LARGE, f"over {cap} bytes", got)
        return b"".join(parts)
    finally:
        for f in opened:
            os.close(f)


# ----------------------------------------------------------------------------- helper
def _drop(uid, gid):
    import ctypes

    os.setgroups([])
    os.setresgid(gid, gid, gid)
    os.setresuid(uid, uid, uid)
    if 0 in os.getresuid() or 0 in os.getresgid() or os.getgroups():
        raise SystemExit("filereader: could not drop root privileges")
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(38, 1, 0, 0, 0)  # PR_SET_NO_NEW_PRIVS
    libc.prctl(4, 0, 0, 0, 0)  # PR_SET_DUMPABLE 0: no ptrace, no /proc/pid/mem


def serve(sock, who):
    while True:
        try:
            data, fds, _flags, _addr = socket.recv_fds(sock, 65536, 2)
        except InterruptedError:
            continue
        if not data:
            return
        try:
            req = json.loads(data)
            if len(fds) != 1:
                raise ReadFailed(REFUSED, "no folder received")
            rel = [bytes.fromhex(n) for n in req["rel"]]
            body = read_at(fds[0], rel, int(req["cap"]), bool(req.get("links")), who)
        except ReadFailed as exc:
            sock.send(
                json.dumps(
                    {"ok": False, "kind": exc.kind, "why": exc.why, "size": exc.size,
                     "reason": exc.reason}
                ).encode()
            )
            continue
        except Exception as exc:  # a bad request: say so, keep serving
            sock.send(
                json.dumps({"ok": False, "kind": REFUSED, "why": f"reader: {exc!r}"}).encode()
            )
            continue
        finally:
            for f in fds:
                os.close(f)
        sock.send(json.dumps({"ok": True, "n": len(body)}).encode())
        view = memoryview(body)
        for i in range(0, len(body), CHUNK):
            sock.send(view[i : i + CHUNK])


def main(argv):
    cfg = json.loads(argv[1])
    sock = socket.socket(fileno=int(cfg["fd"]))
    _drop(int(cfg["uid"]), int(cfg["gid"]))
    sock.send(json.dumps({"ready": True, "uid": os.getuid()}).encode())
    serve(sock, cfg.get("who", ""))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
