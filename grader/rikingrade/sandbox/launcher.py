"""Started as root only: drop to an unprivileged user, then exec bwrap or the zygote itself.

A process whose real uid is 0 is exempt from ``RLIMIT_NPROC`` (so a fork bomb would not be
stopped) and bubblewrap started by root maps the sandbox user back to uid 0. So a root
grader runs this tiny script instead, which

1. enters a private mount namespace (the host's mounts are untouched);
2. mounts a small tmpfs on a staging directory and bind-mounts there, read-only, each
   path that user ``nobody`` could not reach (e.g. a Python under ``/root/.pyenv``);
3. drops to uid/gid ``nobody`` with no supplementary groups;
4. execs bubblewrap, which then creates its unprivileged user namespace as ``nobody``.

Usage: ``python -S -E -s launcher.py CONFIG_JSON`` with
``{"uid", "gid", "staging", "stage": [[host_path, name], ...], "argv": [...]}``.

Without namespaces (``"op": "uid"``, see ``uidmode.py``) it instead drops to the worker's
own uid, checks as that uid that none of ``"secret"`` can be read, removes the network
(a new network namespace where possible, and a seccomp filter refusing ``socket()``),
sets ``PR_SET_NO_NEW_PRIVS`` and execs the zygote. ``"op": "reap"`` kills every process
of a uid with ``kill(-1)`` as that uid; ``"op": "check"`` prints which paths a uid can read.
Standard library only; never imported by the grader.
"""

import ctypes
import json
import os
import platform
import signal
import struct
import sys
import time

CLONE_NEWNS = 0x00020000
CLONE_NEWNET = 0x40000000
PR_SET_NO_NEW_PRIVS = 38
PR_SET_SECCOMP = 22
SECCOMP_MODE_FILTER = 2
MS_RDONLY = 1
MS_REMOUNT = 32
MS_BIND = 4096
MS_REC = 16384
MS_PRIVATE = 1 << 18


def _check(ret, what):
    if ret != 0:
        err = ctypes.get_errno()
        raise OSError(err, f"{what}: {os.strerror(err)}")


def _drop(uid, gid):
    os.setgroups([])
    os.setresgid(gid, gid, gid)
    os.setresuid(uid, uid, uid)
    if 0 in os.getresuid() or 0 in os.getresgid():
        raise SystemExit("launcher: could not drop root privileges")


def _readable(path):
    try:
        if os.path.isdir(path):
            os.listdir(path)
        else:
            os.close(os.open(path, os.O_RDONLY | os.O_NONBLOCK))
        return True
    except OSError:
        return False


# ----------------------------------------------------------------------------- seccomp
# struct sock_filter {u16 code; u8 jt; u8 jf; u32 k}; offsets in struct seccomp_data
_LD_W_ABS, _JEQ_K, _JGE_K, _RET_K = 0x20, 0x15, 0x35, 0x06
_ALLOW, _ERRNO = 0x7FFF0000, 0x00050000
#: machine -> (AUDIT_ARCH, socket(2) number, io_uring_setup(2) number, x32 bit or 0)
_ARCH = {
    "x86_64": (0xC000003E, 41, 425, 0x40000000),
    "aarch64": (0xC00000B7, 198, 425, 0),
}


class _Fprog(ctypes.Structure):
    _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]


def no_sockets(libc):
    """Refuse socket() (EACCES) and io_uring (EPERM), and any foreign-ABI syscall."""
    arch = _ARCH.get(platform.machine())
    if arch is None:
        return f"no seccomp filter for {platform.machine()}"
    audit, nr_socket, nr_uring, x32 = arch
    ins = [
        (_LD_W_ABS, 0, 0, 4),  # arch
        (_JEQ_K, 1, 0, audit),
        (_RET_K, 0, 0, _ERRNO | 1),  # another ABI (i386, x32 calls): EPERM
        (_LD_W_ABS, 0, 0, 0),  # syscall number
        (_JGE_K, 0, 1, x32 or 0xFFFFFFFF),
        (_RET_K, 0, 0, _ERRNO | 1),
        (_JEQ_K, 0, 1, nr_socket),
        (_RET_K, 0, 0, _ERRNO | 13),  # EACCES
        (_JEQ_K, 0, 1, nr_uring),
        (_RET_K, 0, 0, _ERRNO | 1),
        (_RET_K, 0, 0, _ALLOW),
    ]
    raw = b"".join(struct.pack("=HBBI", *i) for i in ins)
    buf = ctypes.create_string_buffer(raw, len(raw))
    prog = _Fprog(len(ins), ctypes.cast(buf, ctypes.c_void_p))
    libc.prctl.argtypes = [
        ctypes.c_int,
        ctypes.c_ulong,
        ctypes.c_void_p,
        ctypes.c_ulong,
        ctypes.c_ulong,
    ]
    if libc.prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, ctypes.byref(prog), 0, 0) != 0:
        return f"seccomp filter refused: {os.strerror(ctypes.get_errno())}"
    return ""


def uid_main(cfg, libc):
    """Start the zygote as the worker's own uid, with no network and no way back to root."""
    uid, gid = int(cfg["uid"]), int(cfg["gid"])
    notes: dict[str, bool | str] = {}
    if libc.unshare(CLONE_NEWNET) == 0:  # possible with CAP_SYS_ADMIN (not on Docker)
        notes["netns"] = True
    else:
        notes["netns"] = os.strerror(ctypes.get_errno())
    if cfg.get("cgroup"):  # join the sandbox's memory cgroup while still root
        with open(cfg["cgroup"], "w") as f:
            f.write(str(os.getpid()))
    os.umask(0o077)
    _drop(uid, gid)
    if libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
        raise SystemExit(f"launcher: PR_SET_NO_NEW_PRIVS failed: {os.strerror(ctypes.get_errno())}")
    problems = []
    python = cfg["argv"][0]
    if not os.access(python, os.X_OK):
        problems.append(
            f"uid {uid} cannot run the Python interpreter {python} (a parent directory is "
            "private?): use a Python that every user can read, e.g. a venv made with "
            "/usr/bin/python3"
        )
    for script in cfg.get("readable", []):
        if not _readable(script):
            problems.append(f"uid {uid} cannot read {script}")
    leaked = [p for p in cfg.get("secret", []) if _readable(p)]
    if leaked:
        problems.append(
            f"uid {uid} (the sandbox user) can read the grader's files: {', '.join(leaked)}. "
            "Without namespaces the sandbox relies on file permissions: make them unreadable "
            "to other users (chmod -R o-rwx, or install rikingrade root-only as the Gradescope "
            "bundle's setup.sh does)"
        )
    if problems:
        print(
            "rikingrade uid sandbox refused to start:\n  " + "\n  ".join(problems),
            file=sys.stderr,
            flush=True,
        )
        os._exit(3)
    err = no_sockets(libc)
    notes["seccomp"] = err or True
    os.chdir(cfg["cwd"])
    ctl = int(cfg["ctl_fd"])
    try:
        os.write(ctl, json.dumps({"launcher": notes}).encode())
    except OSError:
        pass
    os.execve(python, cfg["argv"], cfg.get("env", {}))


def _live_others(uid):
    """Whether ``uid`` owns a live process besides this one (zombies are dead already)."""
    me = os.getpid()
    for name in os.listdir("/proc"):
        if not name.isdigit() or int(name) == me:
            continue
        try:
            with open(f"/proc/{name}/status") as f:
                status = f.read()
        except OSError:
            continue
        fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
        try:
            owner = int(fields.get("Uid", "").split()[0])
        except (IndexError, ValueError):
            continue
        if owner == uid and not fields.get("State", "").strip().startswith("Z"):
            return True
    return False


def reap_main(cfg):
    """kill(-1, SIGKILL) as the uid until it owns no live process (or the time is up).

    kill(-1) also "signals" zombies, so it is no test of being done: /proc is. The zombies
    left are collected by their parent (the grader, their subreaper).
    """
    uid = int(cfg["uid"])
    _drop(uid, uid)
    deadline = time.monotonic() + float(cfg.get("timeout", 5.0))
    while True:
        try:
            os.kill(-1, signal.SIGKILL)  # every process of this uid but ourselves
        except ProcessLookupError:
            return 0
        except OSError:
            pass
        if not _live_others(uid):
            return 0
        if time.monotonic() > deadline:
            return 1
        time.sleep(0.005)


def check_main(cfg):
    _drop(int(cfg["uid"]), int(cfg["uid"]))
    found = [p for p in cfg.get("secret", []) if _readable(p)]
    print(json.dumps(found))
    return 3 if found else 0


def main(argv):
    cfg = json.loads(argv[1])
    libc = ctypes.CDLL(None, use_errno=True)
    op = cfg.get("op")
    if op == "uid":
        return uid_main(cfg, libc)
    if op == "reap":
        return reap_main(cfg)
    if op == "check":
        return check_main(cfg)
    libc.mount.argtypes = [ctypes.c_char_p] * 3 + [ctypes.c_ulong, ctypes.c_char_p]
    stage = cfg.get("stage") or []
    if stage:
        staging = cfg["staging"].encode()
        _check(libc.unshare(CLONE_NEWNS), "unshare(CLONE_NEWNS)")
        _check(libc.mount(None, b"/", None, MS_REC | MS_PRIVATE, None), "make / private")
        _check(libc.mount(b"tmpfs", staging, b"tmpfs", 0, b"mode=0755,size=1m"), "tmpfs")
        for src, name in stage:
            dest = os.path.join(cfg["staging"], name)
            if os.path.isdir(src):
                os.mkdir(dest, 0o755)
            else:
                with open(dest, "w"):
                    pass
            _check(
                libc.mount(src.encode(), dest.encode(), None, MS_BIND | MS_REC, None), f"bind {src}"
            )
            _check(
                libc.mount(
                    None, dest.encode(), None, MS_BIND | MS_REMOUNT | MS_RDONLY | MS_REC, None
                ),
                f"read-only {src}",
            )
    if cfg.get("cgroup"):  # join the sandbox's memory cgroup while still root
        with open(cfg["cgroup"], "w") as f:
            f.write(str(os.getpid()))
    os.setgroups([])
    os.setgid(int(cfg["gid"]))
    os.setuid(int(cfg["uid"]))
    if os.getuid() == 0 or os.geteuid() == 0:
        raise SystemExit("launcher: could not drop root privileges")
    os.execvp(cfg["argv"][0], cfg["argv"])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
