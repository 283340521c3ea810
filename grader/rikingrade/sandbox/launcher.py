"""Started as root only: make private copies of unreadable paths, drop to nobody, exec bwrap.

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
Standard library only; never imported by the grader.
"""

import ctypes
import json
import os
import sys

CLONE_NEWNS = 0x00020000
MS_RDONLY = 1
MS_REMOUNT = 32
MS_BIND = 4096
MS_REC = 16384
MS_PRIVATE = 1 << 18


def _check(ret, what):
    if ret != 0:
        err = ctypes.get_errno()
        raise OSError(err, f"{what}: {os.strerror(err)}")


def main(argv):
    cfg = json.loads(argv[1])
    libc = ctypes.CDLL(None, use_errno=True)
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
    os.setgroups([])
    os.setgid(int(cfg["gid"]))
    os.setuid(int(cfg["uid"]))
    if os.getuid() == 0 or os.geteuid() == 0:
        raise SystemExit("launcher: could not drop root privileges")
    os.execvp(cfg["argv"][0], cfg["argv"])


if __name__ == "__main__":
    main(sys.argv)
