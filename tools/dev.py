#!/usr/bin/env python3
"""One-command developer entry points for rikin (standard library only).

    python3 tools/dev.py book [--cached]   set up .venv, build the book (HTML in _build/html/)
    python3 tools/dev.py test [-- ARGS]    set up .venv, run every test (pytest + nbval)

Both create ``.venv`` in the repository root with the Python running this script if it
is missing, and (re)install ``requirements.txt`` into it whenever requirements.txt or
pyproject.toml changed since the last install (a sha256 stamp is kept inside .venv).
Works from any current directory. Every command run is printed first.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = ROOT / ".venv"
STAMP = VENV / ".rikin-requirements.sha256"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PY = BIN / ("python.exe" if os.name == "nt" else "python")
BUILD = ROOT / "_build"
NOTEBOOK_DIRS = ("solutions", "exercises")


def run(cmd: list[str], env: dict[str, str] | None = None) -> int:
    """Print ``cmd`` (shell-quoted, with the env vars we set) and run it from ROOT."""
    shown = " ".join(shlex.quote(str(c)) for c in cmd)
    if env is not None:
        extra = {k: v for k, v in env.items() if k in ("PYTHONHASHSEED", "MPLBACKEND")}
        shown = " ".join(f"{k}={v}" for k, v in extra.items()) + (" " if extra else "") + shown
    print(f"+ {shown}", flush=True)
    return subprocess.call([str(c) for c in cmd], cwd=ROOT, env=env)


def check(cmd: list[str], env: dict[str, str] | None = None) -> None:
    rc = run(cmd, env)
    if rc != 0:
        sys.exit(f"dev.py: command failed with exit code {rc}")


def deps_hash() -> str:
    h = hashlib.sha256()
    for name in ("requirements.txt", "pyproject.toml"):
        h.update(name.encode() + b"\0" + (ROOT / name).read_bytes() + b"\0")
    return h.hexdigest()


def ensure_venv() -> None:
    # The script itself may be started by an older python3: say so clearly.
    if sys.version_info < (3, 10):  # noqa: UP036
        sys.exit("dev.py: Python 3.10+ is required (this is " + sys.version.split()[0] + ")")
    if not PY.exists():
        if VENV.exists():
            print(f"dev.py: {VENV} is incomplete (no {PY.name}); recreating it", flush=True)
            shutil.rmtree(VENV)
        check([sys.executable, "-m", "venv", str(VENV)])
    wanted = deps_hash()
    have = STAMP.read_text().strip() if STAMP.exists() else ""
    if have == wanted:
        print(
            f"dev.py: {VENV.name} is up to date with requirements.txt + pyproject.toml "
            "(skipping install)",
            flush=True,
        )
        return
    check(
        [
            PY,
            "-m",
            "pip",
            "install",
            "--disable-pip-version-check",
            "--progress-bar",
            "off",
            "-r",
            ROOT / "requirements.txt",
        ]
    )
    STAMP.write_text(wanted + "\n")


def child_env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONHASHSEED"] = "0"
    env.setdefault("MPLBACKEND", "Agg")
    env["VIRTUAL_ENV"] = str(VENV)
    env["PATH"] = str(BIN) + os.pathsep + env.get("PATH", "")
    env.pop("PYTHONHOME", None)
    # Kernels must come from .venv (where rikin is installed), not from ~/.local.
    env["JUPYTER_PREFER_ENV_PATH"] = "1"
    return env


def cmd_book(args: argparse.Namespace) -> int:
    ensure_venv()
    jb = [BIN / "jupyter-book", "build", ROOT, "-W", "-n", "--keep-going"]
    if args.cached:
        # Reuse the jupyter-cache and Sphinx's incremental build: only pages whose code
        # changed are re-executed. Edits to rikin/ are NOT noticed in this mode.
        config = ROOT / "_config.yml"
        text, n = re.subn(
            r"(?m)^(\s*execute_notebooks\s*:\s*)force\b", r"\1cache", config.read_text()
        )
        if n != 1:
            sys.exit("dev.py: could not find 'execute_notebooks: force' in _config.yml")
        # next to _config.yml: jupyter-book resolves local_extensions (book/_ext) relative to
        # the config file's folder (git-ignored)
        cached_config = ROOT / "_config.cached.yml"
        cached_config.write_text(text)
        jb += ["--config", cached_config]
    else:
        # Fresh: re-read every page (--all) and execute every notebook (execute: force).
        jb += ["--all"]
    rc = run(jb, child_env())
    index = BUILD / "html" / "index.html"
    if rc == 0:
        print(f"\nBook built: {index}\n(open file://{index} in a browser)", flush=True)
    else:
        print(
            f"\ndev.py: book build FAILED (exit code {rc}); see the warnings/errors above.",
            file=sys.stderr,
            flush=True,
        )
    return rc


def _names_a_path(arg: str) -> bool:
    if arg.startswith("-"):
        return False
    target = arg.split("::", 1)[0]
    return bool(target) and ((ROOT / target).exists() or Path(target).exists())


# Debian packages some tests need: the grader's sandbox (bwrap) and the book's browser
# test (headless Chromium and its driver).
SYSTEM_PACKAGES = {"bwrap": "bubblewrap", "chromium": "chromium", "chromedriver": "chromium-driver"}
# The same on Fedora, for the instructions printed when dev.py cannot install them itself.
FEDORA_PACKAGES = {"bwrap": "bubblewrap", "chromium": "chromium", "chromedriver": "chromedriver"}
NEEDED_BY = {
    "bwrap": "the grader's sandbox tests",
    "chromium": "the book's browser tests",
    "chromedriver": "the book's browser tests",
}


def _missing() -> list[str]:
    return [exe for exe in SYSTEM_PACKAGES if shutil.which(exe) is None]


def ensure_system_packages() -> None:
    """Install the missing Debian packages when we can (root with apt-get); else say how.

    Nothing is skipped for want of them: the tests that need a package fail, saying why.
    """
    missing = _missing()
    if not missing:
        return
    can_install = (
        shutil.which("apt-get") is not None and hasattr(os, "geteuid") and os.geteuid() == 0
    )
    if can_install:
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        pkgs = [SYSTEM_PACKAGES[e] for e in missing]
        lock = ["-o", "DPkg::Lock::Timeout=300"]
        check(["apt-get", "update", "-qq"], env)
        check(["apt-get", "install", "-y", "-qq", *lock, "--no-install-recommends", *pkgs], env)
        missing = _missing()
        if not missing:
            return
        print(
            "dev.py: WARNING: installed, but still not on PATH: " + " ".join(missing),
            flush=True,
        )
    print(
        "dev.py: WARNING: missing "
        + ", ".join(f"{e} ({NEEDED_BY[e]})" for e in missing)
        + ": those tests will FAIL, not skip. Install:\n"
        "  Debian/Ubuntu: sudo apt-get install -y "
        + " ".join(SYSTEM_PACKAGES[e] for e in missing)
        + "\n  Fedora:        sudo dnf install -y "
        + " ".join(FEDORA_PACKAGES[e] for e in missing)
        + "\n  (run as root, tools/dev.py installs them itself with apt-get)",
        flush=True,
    )


def cmd_test(args: argparse.Namespace, extra: list[str]) -> int:
    ensure_venv()
    ensure_system_packages()
    # Paths given relative to the caller's cwd keep working (we run from ROOT).
    passthrough = []
    for a in extra:
        target = a.split("::", 1)[0]
        if (
            not a.startswith("-")
            and target
            and Path(target).exists()
            and not (ROOT / target).exists()
        ):
            a = str(Path(target).resolve()) + a[len(target) :]
        passthrough.append(a)
    targets: list[str] = []
    if not any(_names_a_path(a) for a in passthrough):
        targets.append("tests")
        for d in NOTEBOOK_DIRS:
            nbs = [p for p in (ROOT / d).rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts]
            if nbs:
                targets.append(d)
    cmd = [
        PY,
        "-m",
        "pytest",
        "-n",
        "2",
        "--dist",
        "loadfile",
        "--nbval-lax",
        *targets,
        *passthrough,
    ]
    return run(cmd, child_env())


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    extra: list[str] = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i + 1 :]
    p = argparse.ArgumentParser(
        prog="tools/dev.py",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = p.add_subparsers(dest="command", required=True)
    b = sub.add_parser("book", help="set up .venv and build the book, executing every notebook")
    b.add_argument(
        "--cached",
        action="store_true",
        help="quick local rebuild: reuse the execution cache and only rebuild "
        "changed pages (does NOT notice edits to rikin/)",
    )
    sub.add_parser("test", help="set up .venv and run every test; pytest args after --")
    args = p.parse_args(argv)
    if args.command == "book":
        if extra:
            p.error("book takes no arguments after --")
        return cmd_book(args)
    return cmd_test(args, extra)


if __name__ == "__main__":
    sys.exit(main())
