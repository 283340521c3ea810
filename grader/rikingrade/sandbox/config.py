"""What a sandbox may see and use: resource limits, bind mounts and the bubblewrap command.

The child sees, read-only, only what Python and the preloaded libraries need: ``/usr`` (and
the ``/lib*``, ``/bin`` links), the Python installation, the virtual environment's
site-packages and the directory of each preloaded package that lives elsewhere (``rikin``
installed editable: its package directory alone, never the course repository). Everything
else is absent: the course, the grader package with its hidden tests and reference, the
submissions and the output folder (hidden even when they sit inside a bound directory).
``/scratch`` (not /tmp, so a checkout under /tmp stays visible) is a small private tmpfs;
there is no network, a new PID/IPC/UTS namespace and an unprivileged user.

That is the ``bwrap`` mode. Where user namespaces are refused (a Docker container with the
default seccomp profile, such as Gradescope's), a root grader uses the ``uid`` mode instead
(see ``uidmode.py``): no private view of the filesystem, but the grader's files are proven
unreadable to the sandbox's own uid. :func:`resolve_mode` picks the strongest that works.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import site
import stat
import subprocess
import sys
import sysconfig
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

#: Libraries the zygote imports before forking (missing ones are reported, not fatal).
PRELOAD = ("numpy", "sympy", "matplotlib", "IPython", "rikin")
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
NAMESPACE_HINT = (
    "This system refuses the user namespaces bubblewrap needs (e.g. a Docker container with "
    "the default seccomp profile, or a chroot). Run the grader as root there: it then uses "
    "the uid sandbox (--sandbox uid), which needs the grader's files unreadable to other "
    "users (the Gradescope bundle's setup.sh installs it that way)."
)

#: Sandbox modes, strongest first; "auto" picks the first that works here.
AUTO, BWRAP, UID, NONE = "auto", "bwrap", "uid", "none"
MODES = (AUTO, BWRAP, UID)
DESCRIBE = {
    BWRAP: "bwrap (bubblewrap namespaces: private read-only filesystem view, no network, "
    "own PID namespace, unprivileged user)",
    UID: "uid (no namespaces: each worker's own unprivileged uid, grader files proven "
    "unreadable to it, no sockets, per-uid process limit, kill(-1) cleanup)",
    NONE: "none (UNSAFE: student code runs as the grader, with no isolation)",
}


class SandboxUnavailable(RuntimeError):
    """No sandbox can start here (bubblewrap missing or refused, uid mode impossible)."""


@dataclass(frozen=True)
class Limits:
    """Per-child resource limits (see ``grade`` for the meaning of each)."""

    memory_mb: int = 1024
    cpu_seconds: int = 120
    max_processes: int = 32
    max_file_mb: int = 16
    max_open_files: int = 128
    #: the sandbox's share of the machine's memory (MiB; the machine's divided among the
    #: workers): without a memory cgroup, processes x per-process limit stays within it
    share_mb: int | None = None

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
    #: "bwrap", "uid" or "none" once resolved ("auto" until :func:`resolve_mode`)
    mode: str = AUTO
    #: why stronger modes were not used (shown in the log and by check-sandbox)
    notes: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not self.sandbox:
            self.mode = NONE
        elif self.mode not in MODES:
            raise ValueError(f"sandbox mode must be one of {', '.join(MODES)}, not {self.mode!r}")


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
        lib = sysconfig.get_paths().get(key)
        if lib:
            cands.append(Path(lib))
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
    cmd += _system_dirs()
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
    cmd += _mount_points(binds)
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


def _system_dirs() -> list[str]:
    """bwrap arguments for the host's /bin, /sbin and /lib* (symlinks into /usr on a merged
    system, folders otherwise) and the dynamic linker's cache, all read-only."""
    args: list[str] = []
    for name in ("bin", "sbin", "lib", "lib32", "lib64", "libx32"):
        host = Path("/") / name
        if host.is_symlink():
            args += ["--symlink", os.readlink(host), str(host)]
        elif host.is_dir():
            args += ["--ro-bind", str(host), str(host)]
    if os.path.exists("/etc/ld.so.cache"):
        args += ["--ro-bind", "/etc/ld.so.cache", "/etc/ld.so.cache"]
    return args


def _mount_points(binds: list[tuple[str, str]]) -> list[str]:
    """bwrap arguments that make the folders above each bind (/home, /home/<user>,
    /root/.pyenv, ...) bare mount points: traversable but not listable (mode 0111; / is
    remounted read-only, so nobody can chmod them back), so a checkout under /home shows
    nothing of /home, the user or the course around .venv and rikin."""
    args: list[str] = []
    made: set[str] = set()
    for _src, dest in binds:
        for parent in reversed(Path(dest).parents):
            sp = str(parent)
            if sp == "/" or sp in made or _under(parent, Path("/usr")):
                continue
            made.add(sp)
            if not any(sp == d for _s, d in binds):
                args += ["--perms", "0111", "--dir", sp]
    return args


def find_bwrap(config: SandboxConfig) -> str:
    path = shutil.which(config.bwrap)
    if path is None:
        raise SandboxUnavailable(INSTALL_HINT)
    return path


def reachable_tmpdir() -> Path:
    """A temporary directory every user can traverse (for what the sandbox user must read).

    ``tempfile.gettempdir()`` may be a private (0700) folder (a TMPDIR under a home
    directory): a root grader's sandbox runs as another user and could not reach it.
    """
    for cand in (tempfile.gettempdir(), "/tmp", "/var/tmp", "/dev/shm"):
        p = Path(cand)
        if p.is_dir() and world_readable(p) and os.access(p, os.W_OK | os.X_OK):
            st = os.stat(p)
            if st.st_mode & stat.S_IXOTH:
                return p
    raise SandboxUnavailable(
        f"no temporary directory the sandbox user can reach (TMPDIR={tempfile.gettempdir()} "
        "is private, and /tmp, /var/tmp and /dev/shm are not usable): set TMPDIR to a "
        "directory every user can traverse, e.g. TMPDIR=/tmp"
    )


def sandbox_workdir(prefix: str = "rikingrade-") -> Path:
    """A fresh grader work folder (mode 0755) where the sandbox user can read its scripts."""
    d = Path(tempfile.mkdtemp(prefix=prefix, dir=reachable_tmpdir() if os.geteuid() == 0 else None))
    os.chmod(d, 0o755)
    return d


def bwrap_failure(stderr: str) -> str:
    """What a bubblewrap error means, in words, with what to do about it."""
    text = stderr.strip()
    if "Can't find source path" in text and "Permission denied" in text:
        return (
            f"bubblewrap could not start: {text}\nThe sandbox user cannot reach a folder it "
            "must see (a parent directory is private, e.g. TMPDIR or a home directory): "
            "make it traversable (chmod o+x) or set TMPDIR=/tmp."
        )
    if any(
        w in text
        for w in (
            "No permissions to create new namespace",
            "Creating new namespace failed",
            "setting up uid map",
            "Operation not permitted",
            "unshare",
        )
    ):
        return f"bubblewrap could not create its namespaces: {text}\n{NAMESPACE_HINT}"
    return f"bubblewrap could not start: {text}" if text else "bubblewrap could not start"


def bwrap_works(config: SandboxConfig) -> str:
    """Empty when bubblewrap can create its namespaces here, else why not (in words)."""
    path = shutil.which(config.bwrap)
    if path is None:
        return "bubblewrap (bwrap) is not installed"
    as_root = os.geteuid() == 0
    try:
        r = subprocess.run(
            [
                path,
                "--unshare-all",
                "--unshare-user",
                "--die-with-parent",
                "--ro-bind",
                "/",
                "/",
                "--proc",
                "/proc",
                "true",
            ],
            capture_output=True,
            text=True,
            timeout=30,
            stdin=subprocess.DEVNULL,
            # a root grader starts bwrap as nobody (see launcher.py): probe the same way
            user=config.uid if as_root else None,
            group=config.uid if as_root else None,
            extra_groups=[] if as_root else None,
            cwd="/",
        )
    except (OSError, subprocess.SubprocessError) as exc:
        return f"bubblewrap could not run: {exc}"
    return "" if r.returncode == 0 else bwrap_failure(r.stderr)


def resolve_mode(config: SandboxConfig) -> SandboxConfig:
    """Settle ``config.mode`` on the strongest sandbox that works here; raise if none does.

    ``auto`` tries bubblewrap, then (as root) the uid mode; an explicit mode is checked the
    same way. Why a stronger mode was not used is kept in ``config.notes``. Whether the uid
    mode's file permissions hold is proven when its zygote starts.
    """
    if config.mode == NONE:
        return config
    if config.mode in (AUTO, BWRAP):
        why = bwrap_works(config)
        if not why:
            config.mode = BWRAP
            return config
        if config.mode == BWRAP or os.geteuid() != 0:
            hint = INSTALL_HINT if shutil.which(config.bwrap) is None else ""
            if os.geteuid() != 0 and shutil.which(config.bwrap) is not None:
                hint = NAMESPACE_HINT
            raise SandboxUnavailable("\n".join(x for x in (why, hint) if x))
        missing = shutil.which(config.bwrap) is None
        config.notes.append(
            f"bwrap mode unavailable: {why.splitlines()[0]}"
            + ("\n" + INSTALL_HINT if missing else "")
        )
    if os.geteuid() != 0:
        raise SandboxUnavailable(
            "the uid sandbox needs a root grader (it runs each worker as its own uid)"
        )
    from .uidmode import candidate_uids

    if not candidate_uids():
        raise SandboxUnavailable("the uid sandbox found no unused uid range in this user namespace")
    config.mode = UID
    return config
