"""What a sandbox may see and use: resource limits, bind mounts and the bubblewrap command.

The child sees, read-only, only what Python and the preloaded libraries need: ``/usr`` (and
the ``/lib*``, ``/bin`` links), the Python installation, the virtual environment's
site-packages and the directory of each preloaded package that lives elsewhere (``rikin``
installed editable: its package directory alone, never the course repository). Everything
else is absent: the course, the grader package with its hidden tests and reference, the
submissions and the output folder (hidden even when they sit inside a bound directory).
``/scratch`` (not /tmp, so a checkout under /tmp stays visible) is a small private tmpfs; there is no network, a new PID/IPC/UTS namespace and an
unprivileged user.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import site
import stat
import sys
import sysconfig
from dataclasses import dataclass, field
from pathlib import Path

#: Libraries the zygote imports before forking (missing ones are reported, not fatal).
PRELOAD = ("numpy", "sympy", "matplotlib", "IPython.core.inputtransformer2", "rikin")
#: Where the engine script and the matplotlib font cache appear inside the sandbox.
CHILD_PATH = "/opt/rikingrade/child.py"
# The private writable scratch is not /tmp: a checkout or venv under /tmp (a CI clone) must be
# bound read-only at its own path without a tmpfs shadowing it.
SCRATCH = "/scratch"
MPL_DIR = "/scratch/.mpl"
#: The uid a root grader drops to before starting bubblewrap (so process limits apply).
NOBODY = 65534

INSTALL_HINT = (
    "bubblewrap (bwrap) is needed to run student code in a sandbox.\n"
    "  Debian/Ubuntu:  sudo apt-get install -y bubblewrap\n"
    "  Fedora:         sudo dnf install -y bubblewrap\n"
    "Check it with:    rikin-grade check-sandbox\n"
    "For development only, --unsafe-no-sandbox runs student code without isolation."
)


class SandboxUnavailable(RuntimeError):
    """bubblewrap is missing or cannot create namespaces here."""


@dataclass(frozen=True)
class Limits:
    """Per-child resource limits (see ``grade`` for the meaning of each)."""

    memory_mb: int = 1024
    cpu_seconds: int = 120
    max_processes: int = 32
    max_file_mb: int = 16
    max_open_files: int = 128

    def as_dict(self) -> dict[str, int]:
        return {
            "memory_mb": self.memory_mb,
            "cpu_seconds": self.cpu_seconds,
            "max_processes": self.max_processes,
            "max_file_mb": self.max_file_mb,
            "max_open_files": self.max_open_files,
        }


@dataclass
class SandboxConfig:
    """How to start a zygote: sandboxed with bubblewrap, or (development) unsandboxed."""

    sandbox: bool = True
    python: str = sys.executable
    tmp_mb: int = 64
    preload: tuple[str, ...] = PRELOAD
    hidden: list[Path] = field(default_factory=list)
    extra_ro_binds: list[Path] = field(default_factory=list)
    bwrap: str = "bwrap"
    uid: int = NOBODY


def _under(path: Path, parent: Path) -> bool:
    try:
        path.relative_to(parent)
        return True
    except ValueError:
        return False


def package_dir(module: str) -> Path | None:
    """The directory a top-level package is imported from, without importing it."""
    top = module.split(".")[0]
    try:
        spec = importlib.util.find_spec(top)
    except (ImportError, ValueError):
        return None
    if spec is None:
        return None
    if spec.submodule_search_locations:
        locs = list(spec.submodule_search_locations)
        return Path(locs[0]).resolve() if locs else None
    if spec.origin and spec.origin not in ("built-in", "frozen"):
        return Path(spec.origin).resolve().parent
    return None


def read_only_binds(config: SandboxConfig) -> list[Path]:
    """Host directories the child needs, read-only (deduplicated, outermost first)."""
    cands: list[Path] = []
    for p in (sys.base_prefix, sys.prefix, sys.exec_prefix, sys.base_exec_prefix):
        cands.append(Path(p))
    exe = Path(config.python)
    cands.append(exe.parent)
    cands.append(exe.resolve().parent.parent)
    for p in site.getsitepackages():
        cands.append(Path(p))
    for key in ("purelib", "platlib", "stdlib", "platstdlib"):
        p = sysconfig.get_paths().get(key)
        if p:
            cands.append(Path(p))
    if site.ENABLE_USER_SITE and os.path.isdir(site.getusersitepackages()):
        cands.append(Path(site.getusersitepackages()))
    for mod in config.preload:
        d = package_dir(mod)
        if d is not None:
            cands.append(d)
    cands.extend(config.extra_ro_binds)
    out: list[Path] = []
    for c in sorted(
        {Path(os.path.realpath(c)) for c in cands if os.path.exists(c)}, key=lambda p: len(p.parts)
    ):
        if c == Path("/") or _under(c, Path("/usr")) or _under(c, Path("/proc")):
            continue
        if any(_under(c, o) for o in out):
            continue
        out.append(c)
    # The python executable may be a symlink out of the venv (pyenv, uv): keep its chain.
    return out


def hidden_paths(config: SandboxConfig, binds: list[Path]) -> list[Path]:
    """Paths to mask because they lie inside a bound directory."""
    out = []
    for h in config.hidden:
        h = Path(os.path.realpath(h))
        if not h.exists():
            continue
        if any(_under(h, b) for b in binds) or _under(h, Path("/usr")):
            out.append(h)
    kept: list[Path] = []
    for h in sorted(set(out), key=lambda p: len(p.parts)):
        if not any(_under(h, k) for k in kept):  # already inside a masked directory
            kept.append(h)
    return kept


def world_readable(path: Path) -> bool:
    """True when any user could reach and read ``path`` (every parent is o+x)."""
    p = Path(os.path.realpath(path))
    for parent in list(p.parents)[::-1]:
        try:
            mode = os.stat(parent).st_mode
        except OSError:
            return False
        if not mode & stat.S_IXOTH:
            return False
    try:
        mode = os.stat(p).st_mode
    except OSError:
        return False
    need = stat.S_IROTH | (stat.S_IXOTH if stat.S_ISDIR(mode) else 0)
    return mode & need == need


def bwrap_command(
    config: SandboxConfig,
    binds: list[tuple[str, str]],
    hidden: list[Path],
    files: list[tuple[str, str]],
    child_args: list[str],
    env: dict[str, str],
) -> list[str]:
    """The bubblewrap command line.

    binds : (host source, sandbox destination) directories, read-only.
    files : (host source, sandbox destination) single files, read-only, bound after /tmp.
    """
    cmd = [
        config.bwrap,
        "--unshare-all",  # user, ipc, pid, net, uts, cgroup namespaces: no network
        "--unshare-user",
        "--disable-userns",  # no nested namespaces from inside
        "--die-with-parent",
        "--as-pid-1",  # the zygote is init: SIGKILL/SIGSTOP from inside cannot reach it
        "--new-session",  # no TIOCSTI into the grader's terminal
        "--uid",
        str(NOBODY),
        "--gid",
        str(NOBODY),
        "--hostname",
        "sandbox",
        "--clearenv",
        "--ro-bind",
        "/usr",
        "/usr",
    ]
    for name in ("bin", "sbin", "lib", "lib32", "lib64", "libx32"):
        host = Path("/") / name
        if host.is_symlink():
            cmd += ["--symlink", os.readlink(host), str(host)]
        elif host.is_dir():
            cmd += ["--ro-bind", str(host), str(host)]
    if os.path.exists("/etc/ld.so.cache"):
        cmd += ["--ro-bind", "/etc/ld.so.cache", "/etc/ld.so.cache"]
    # /tmp first: a checkout or venv that itself lives under /tmp (a CI clone) is bound on
    # top of the private tmpfs instead of being hidden by it
    cmd += [
        "--proc",
        "/proc",
        "--dev",
        "/dev",
        "--remount-ro",  # nothing may be written in /dev/shm (unlimited); devices still work
        "/dev",
        "--size",
        str(int(config.tmp_mb) * 1024 * 1024),
        "--tmpfs",
        SCRATCH,
        "--dir",
        MPL_DIR,
    ]
    for src, dest in binds:
        cmd += ["--ro-bind", src, dest]
    for h in hidden:  # mask what must stay invisible even inside a bound directory
        if h.is_dir():
            cmd += ["--tmpfs", str(h), "--remount-ro", str(h)]
        else:
            cmd += ["--ro-bind", "/dev/null", str(h)]
    for src, dest in files:
        cmd += ["--ro-bind", src, dest]
    cmd += ["--remount-ro", "/", "--chdir", SCRATCH]
    for k, v in sorted(env.items()):
        cmd += ["--setenv", k, v]
    cmd += ["--", *child_args]
    return cmd


def find_bwrap(config: SandboxConfig) -> str:
    path = shutil.which(config.bwrap)
    if path is None:
        raise SandboxUnavailable(INSTALL_HINT)
    return path
