"""Run a command the way a Docker container with the default seccomp profile would.

``python nouserns.py CMD ARGS...`` installs a seccomp filter like Docker's default profile
for a container without CAP_SYS_ADMIN (``unshare`` and ``setns`` fail with EPERM, ``clone``
with any CLONE_NEW* flag with EPERM, ``clone3`` with ENOSYS), then execs the command: no
user namespaces, so bubblewrap cannot start, as on Gradescope. The same filter as the
shared ``nouserns.c`` tool, in Python so the tests need no compiler.
"""

from __future__ import annotations

import ctypes
import os
import platform
import struct
import sys

# machine -> (AUDIT_ARCH, unshare, setns, clone, clone3)
ARCH = {
    "x86_64": (0xC000003E, 272, 308, 56, 435),
    "aarch64": (0xC00000B7, 97, 268, 220, 435),
}
NS_FLAGS = 0x00020000 | 0x04000000 | 0x08000000 | 0x10000000 | 0x20000000 | 0x40000000 | 0x02000000
LD_W_ABS, JEQ_K, JSET_K, RET_K = 0x20, 0x15, 0x45, 0x06
ALLOW, ERRNO = 0x7FFF0000, 0x00050000
EPERM, ENOSYS = 1, 38


class _Fprog(ctypes.Structure):
    _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]


def install() -> None:
    audit, unshare, setns, clone, clone3 = ARCH[platform.machine()]
    ins = [
        (LD_W_ABS, 0, 0, 4),  # arch
        (JEQ_K, 1, 0, audit),
        (RET_K, 0, 0, ALLOW),
        (LD_W_ABS, 0, 0, 0),  # syscall number
        (JEQ_K, 0, 1, unshare),
        (RET_K, 0, 0, ERRNO | EPERM),
        (JEQ_K, 0, 1, setns),
        (RET_K, 0, 0, ERRNO | EPERM),
        (JEQ_K, 0, 1, clone3),
        (RET_K, 0, 0, ERRNO | ENOSYS),
        (JEQ_K, 0, 3, clone),
        (LD_W_ABS, 0, 0, 16),  # args[0]: the clone flags
        (JSET_K, 0, 1, NS_FLAGS),
        (RET_K, 0, 0, ERRNO | EPERM),
        (RET_K, 0, 0, ALLOW),
    ]
    raw = b"".join(struct.pack("=HBBI", *i) for i in ins)
    buf = ctypes.create_string_buffer(raw, len(raw))
    prog = _Fprog(len(ins), ctypes.cast(buf, ctypes.c_void_p))
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl.argtypes = [
        ctypes.c_int,
        ctypes.c_ulong,
        ctypes.c_void_p,
        ctypes.c_ulong,
        ctypes.c_ulong,
    ]
    if libc.prctl(38, 1, None, 0, 0) != 0:  # PR_SET_NO_NEW_PRIVS
        raise OSError(ctypes.get_errno(), "PR_SET_NO_NEW_PRIVS")
    if libc.prctl(22, 2, ctypes.byref(prog), 0, 0) != 0:  # PR_SET_SECCOMP, FILTER
        raise OSError(ctypes.get_errno(), "PR_SET_SECCOMP")


if __name__ == "__main__":
    install()
    os.execvp(sys.argv[1], sys.argv[1:])
