#!/usr/bin/env python3
"""One-command developer entry points for rikin (standard library only).

    python3 tools/dev.py book [--cached]   set up .venv for the book, build it (_build/html/)
    python3 tools/dev.py test [-- ARGS]    set up .venv with everything, run every test
    python3 tools/dev.py lint              set up .venv with everything, run ruff (the whole
                                           repository) and mypy (rikin, grader/rikingrade)
    python3 tools/dev.py translations      refresh every Spanish catalogue (the book's in
                                           book/locales/, the exercises' and the grader's)
    python3 tools/dev.py lab [-- ARGS]     set up .venv with everything, start JupyterLab
                                           at the repository root (book/, exercises/, ...)

Each creates ``.venv`` in the repository root with the Python running this script if it is
missing, and installs into it what the command needs: ``book`` only requirements-book.txt
(rikin, Jupyter Book, the kernel, the wheel builder), ``test``, ``lint`` and ``lab``
requirements.txt (that, plus the grader and the test tools). It reinstalls only when one of
the requirements files or pyproject.toml changed since the last install (a sha256 stamp per
set is kept inside .venv). Works from any current directory. Every command run is printed
first.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = ROOT / ".venv"
STAMP = VENV / ".rikin-requirements.json"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PY = BIN / ("python.exe" if os.name == "nt" else "python")
BUILD = ROOT / "_build"
NOTEBOOK_DIRS = ("solutions", "exercises")
#: What each command installs: the book alone, or everything (book + grader + test tools).
REQUIREMENTS = {"book": "requirements-book.txt", "all": "requirements.txt"}
#: Files whose change means reinstalling (requirements*.txt include each other).
DEPENDENCY_FILES = (
    "requirements.txt",
    "requirements-book.txt",
    "requirements-grader.txt",
    "pyproject.toml",
    "grader/pyproject.toml",
)
#: Kernels started from .venv read this IPython config (sys.prefix/etc/ipython). It drops
#: one notice of ipykernel >= 7, printed by every kernel the build starts: "Kernel is running
#: over TCP without encryption". The book's kernels are started by the build itself, listen
#: on 127.0.0.1 only, and every message to them is signed with a key that only this user can
#: read (the 0600 connection file); nothing crosses a network. Every other log line stays.
KERNEL_CONFIG = VENV / "etc" / "ipython" / "ipython_kernel_config.py"
KERNEL_CONFIG_TEXT = """\
# Written by tools/dev.py (see KERNEL_CONFIG there): hide ipykernel's notice that a kernel
# started by the book build or the tests talks to it over TCP on 127.0.0.1 without CurveZMQ.
import logging


class _LocalTcpNotice(logging.Filter):
    def filter(self, record):
        return not str(record.msg).startswith("Kernel is running over TCP without encryption")


logging.getLogger("IPKernelApp").addFilter(_LocalTcpNotice())
"""


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
    for name in DEPENDENCY_FILES:
        path = ROOT / name
        h.update(name.encode() + b"\0" + (path.read_bytes() if path.exists() else b"") + b"\0")
    return h.hexdigest()


def _stamps() -> dict[str, str]:
    try:
        data = json.loads(STAMP.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def ensure_venv(what: str = "all") -> None:
    """Create .venv if needed and install ``REQUIREMENTS[what]`` unless already current."""
    # The script itself may be started by an older python3: say so clearly.
    if sys.version_info < (3, 10):  # noqa: UP036
        sys.exit("dev.py: Python 3.10+ is required (this is " + sys.version.split()[0] + ")")
    if not PY.exists():
        if VENV.exists():
            print(f"dev.py: {VENV} is incomplete (no {PY.name}); recreating it", flush=True)
            shutil.rmtree(VENV)
        check([sys.executable, "-m", "venv", str(VENV)])
    KERNEL_CONFIG.parent.mkdir(parents=True, exist_ok=True)
    if not KERNEL_CONFIG.exists() or KERNEL_CONFIG.read_text() != KERNEL_CONFIG_TEXT:
        KERNEL_CONFIG.write_text(KERNEL_CONFIG_TEXT)
    wanted = deps_hash()
    stamps = _stamps()
    # everything ("all") includes the book's requirements
    if stamps.get(what) == wanted or stamps.get("all") == wanted:
        print(
            f"dev.py: {VENV.name} is up to date with {REQUIREMENTS[what]} (skipping install)",
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
            ROOT / REQUIREMENTS[what],
        ]
    )
    stamps = {k: v for k, v in stamps.items() if v == wanted}
    stamps[what] = wanted
    STAMP.write_text(json.dumps(stamps, indent=1, sort_keys=True) + "\n")


def child_env(bin_dir: Path = BIN) -> dict[str, str]:
    """The environment of every command run: .venv (``bin_dir``'s) first on PATH, seeded."""
    env = dict(os.environ)
    env["PYTHONHASHSEED"] = "0"
    env.setdefault("MPLBACKEND", "Agg")
    env["VIRTUAL_ENV"] = str(bin_dir.parent)
    env["PATH"] = str(bin_dir) + os.pathsep + env.get("PATH", "")
    env.pop("PYTHONHOME", None)
    # Kernels must come from .venv (where rikin is installed), not from ~/.local.
    env["JUPYTER_PREFER_ENV_PATH"] = "1"
    return env


#: The book's other editions: language code -> folder of the built site (``_build/html/es``).
#: Each is built from the same sources with Sphinx's gettext catalogues in book/locales/.
EDITIONS = {"es": "es"}


@dataclass(frozen=True)
class BookBuild:
    """How one build of the book differs from ``_config.yml`` as it is.

    The instructor's ``tools/dev.py book`` and the tests' one shared build
    (tests/book_build.py) both go through :func:`build_book` with one of these.

    Parameters
    ----------
    cached : bool
        Reuse the jupyter-cache and Sphinx's incremental build (``execute_notebooks: cache``,
        no ``--all``): only pages whose code changed are re-executed; edits to rikin/ are
        NOT noticed. Otherwise every page is re-read and every notebook executed.
    base_url : str or None
        ``html.baseurl`` (where the notebooks install rikin from); None keeps _config.yml's.
    launch_repository : str or None
        ``rikin_launch_repository`` (the launch links' key); None keeps _config.yml's.
    output : Path or None
        ``--path-output`` (the site lands in ``output/_build/html``); None: the repository.
    tag : str
        Names the derived config file, ``_config.<tag>.yml``.
    """

    cached: bool = False
    base_url: str | None = None
    launch_repository: str | None = None
    output: Path | None = None
    tag: str = "cached"


def _substitute(text: str, pattern: str, replacement: str, what: str) -> str:
    """``text`` with the one line matching ``pattern`` replaced (exit when it is not one)."""
    new, n = re.subn(pattern, replacement, text, flags=re.M)
    if n != 1:
        sys.exit(f"dev.py: could not find {what} in _config.yml")
    return new


def book_config(build: BookBuild, language: str = "en") -> Path | None:
    """The config file ``build`` is made with (``None``: _config.yml as it is), for the
    edition in ``language`` (another than English sets ``language`` and puts the edition's
    ``html.baseurl`` in its folder, :data:`EDITIONS`).

    Written next to _config.yml (jupyter-book resolves local_extensions, book/_ext, relative
    to the config file's folder); git-ignored, and removed after the build.
    """
    if (not build.cached and build.base_url is None and build.launch_repository is None
            and language == "en"):
        return None
    text = (ROOT / "_config.yml").read_text(encoding="utf-8")
    if build.cached:
        text = _substitute(text, r"^(\s*execute_notebooks\s*:\s*)force\b", r"\1cache",
                           "'execute_notebooks: force'")
    if build.base_url is not None:
        text = _substitute(text, r"^(\s+baseurl:\s*).*$", rf'\g<1>"{build.base_url}"',
                           "one html.baseurl line")
    if build.launch_repository is not None:
        text = _substitute(text, r"^(\s+rikin_launch_repository:\s*).*$",
                           rf'\g<1>"{build.launch_repository}"',
                           "one rikin_launch_repository line")
    if language != "en":
        text = _substitute(text, r"^(\s*language\s*:\s*)en\s*$", rf"\g<1>{language}",
                           "'language: en' (under sphinx: config:)")
        text = _substitute(text, r'^(\s*baseurl\s*:\s*)"([^"]*?)/?"',
                           rf'\g<1>"\g<2>/{EDITIONS[language]}/"', "html.baseurl")
    suffix = "" if language == "en" else f".{language}"
    path = ROOT / f"_config.{build.tag}{suffix}.yml"
    path.write_text(text, encoding="utf-8")
    return path


def book_command(build: BookBuild, config: Path | None, bin_dir: Path = BIN) -> list[str]:
    """The ``jupyter-book build`` command line of ``build``: strict (-W -n --keep-going)."""
    jb: list[str | Path] = [bin_dir / "jupyter-book", "build", ROOT, "-W", "-n", "--keep-going"]
    if config is not None:
        jb += ["--config", config]
    if build.output is not None:
        jb += ["--path-output", build.output]
    if not build.cached:
        jb += ["--all"]
    return [str(c) for c in jb]


def build_book(build: BookBuild,
               runner: Callable[[list[str], dict[str, str]], int] | None = None,
               bin_dir: Path = BIN) -> int:
    """Build the book as ``build`` says; the exit code of the first build that failed, or 0.

    ``runner(cmd, env)`` runs one command (default :func:`run`: printed, output shown); the
    tests pass their own, which keeps the log. Every edition the book has is built here, so
    that the tests build exactly what instructors build: another language is one more
    command after the English one (same ``build``, its own config and output, its site
    copied into ``<output>/_build/html/<language>/``).
    """
    rc = _build_edition(build, "en", runner, bin_dir)
    for language in EDITIONS if rc == 0 else ():
        rc = _build_edition(build, language, runner, bin_dir)
        if rc:
            break
    return rc


def _build_edition(build: BookBuild, language: str,
                   runner: Callable[[list[str], dict[str, str]], int] | None,
                   bin_dir: Path) -> int:
    """Build one edition; a translated one is built in ``_build/_<language>`` (its own
    jupyter-cache: its cells print in its language) and copied into ``_build/html/<folder>``."""
    config = book_config(build, language)
    env = child_env(bin_dir)
    root = build.output if build.output is not None else ROOT
    if language != "en":
        # Cells print rikin's table headers, branch names and figure titles in the language.
        env["RIKIN_LANG"] = language
        work = root / "_build" / f"_{language}"
        work.mkdir(parents=True, exist_ok=True)
        build = replace(build, output=work)
    try:
        rc = (runner or run)(book_command(build, config, bin_dir), env)
    finally:
        if config is not None:
            config.unlink(missing_ok=True)
    if rc == 0 and language != "en":
        dest = root / "_build" / "html" / EDITIONS[language]
        shutil.rmtree(dest, ignore_errors=True)
        shutil.copytree(root / "_build" / f"_{language}" / "_build" / "html", dest)
    return rc


def cmd_book(args: argparse.Namespace) -> int:
    ensure_venv("book")
    rc = build_book(BookBuild(cached=args.cached))
    index = BUILD / "html" / "index.html"
    if rc == 0:
        print(f"\nBook built: {index}\n(open file://{index} in a browser; the Spanish "
              f"edition is in {index.parent / 'es'})", flush=True)
        print(_published_note(), flush=True)
    else:
        print(
            f"\ndev.py: book build FAILED (exit code {rc}); see the warnings/errors above.",
            file=sys.stderr,
            flush=True,
        )
    return rc


def cmd_translations() -> int:
    """Refresh every translation catalogue from the sources: the book's
    (book/locales/<lang>/LC_MESSAGES/), then the exercises' and the grader's.

    Sphinx's gettext builder extracts every paragraph, heading, caption and admonition of
    the book (notebooks are not executed for this) into ``_build/gettext/*.pot``; sphinx-intl
    merges them into each language's ``.po`` files: new text gets an empty translation,
    changed text keeps the old one marked ``fuzzy`` until a translator checks it. The texts
    the code cells print (rikin.booktext templates) are merged the same way into
    ``cells.po`` by tools/cell_messages.py. The tests refuse a catalogue with an empty or
    fuzzy entry. ``tools/make_exercises.py --translations`` does the same for the exercises
    (solutions/locales/) and the grader (grader/rikingrade/locales/), then makes the
    exercises in each language; it refuses (exit 2) while a message there has no current
    translation, and so does this command then, after every catalogue is refreshed.
    """
    ensure_venv("all")
    text = (ROOT / "_config.yml").read_text()
    config = ROOT / "_config.gettext.yml"
    config.write_text(_substitute(text, r"^(\s*execute_notebooks\s*:\s*)force\b", r'\1"off"',
                                  "'execute_notebooks: force'"))
    pot = BUILD / "gettext"
    shutil.rmtree(pot, ignore_errors=True)
    # --all: every page read again (nothing is executed), so that a text the config or the
    # book's extensions give (rikin_i18n.site_messages) reaches the catalogue even when no
    # page's source changed since the last refresh
    check([BIN / "jupyter-book", "build", ROOT, "--config", config, "--builder", "custom",
           "--custom-builder", "gettext", "--path-output", BUILD / "_gettext", "--all"],
          child_env())
    shutil.copytree(BUILD / "_gettext" / "_build" / "gettext", pot)
    for language in EDITIONS:
        check([BIN / "sphinx-intl", "update", "-p", pot, "-d", ROOT / "book" / "locales",
               "-l", language, "-w", "0"], child_env())
    # the texts the cells print (✓ lines, table headers): book/locales/<lang>/.../cells.po
    check([PY, ROOT / "tools" / "cell_messages.py"], child_env())
    rc = run([PY, ROOT / "tools" / "make_exercises.py", "--translations"], child_env())
    if rc != 0:
        print("dev.py: the exercises' catalogues are refreshed, but the exercises were not "
              "made in every language (see above): translate what is new or fuzzy in "
              "solutions/locales/ and grader/rikingrade/locales/, then run python3 "
              "tools/make_exercises.py", file=sys.stderr, flush=True)
    return rc


def _published_note() -> str:
    """Where the built book's notebooks install rikin from, and how to try that locally."""
    manifest = BUILD / "html" / "_static" / "dist" / "rikin-dist.json"
    try:
        data = json.loads(manifest.read_text())
    except (OSError, ValueError):
        return f"dev.py: WARNING: {manifest} is missing: the notebooks have no wheel to install"
    sys.path.insert(0, str(ROOT / "book" / "_ext"))
    import rikin_site

    base = rikin_site.read_base_url()
    lines = [
        f"rikin {data['version']} is published in the book: {rikin_site.DIST_PATH}/"
        f"{data['wheel']['file']} (sha256 {data['wheel']['sha256']}).",
        f"Its notebooks install it, when missing, from {base} (html.baseurl in _config.yml).",
    ]
    if base.startswith(("http://127.0.0.1", "http://localhost")):
        port = base.split(":")[2].split("/")[0] if base.count(":") > 1 else "80"
        lines.append(
            f"That is a local preview: `python3 -m http.server -d _build/html {port}` serves it; "
            "set html.baseurl to the public URL before hosting the book "
            "(book/instructor/hosting.md)."
        )
    return "\n".join(lines)


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


#: How long ``apt-get update`` waits for another apt (another clone's tests, unattended
#: upgrades) to let go of the package lists. apt 2.6 honours DPkg::Lock::Timeout for
#: install but not for update, which fails at once with "Could not get lock".
APT_LOCK_WAIT_S = 600


def apt_update(env: dict[str, str]) -> None:
    """Run ``apt-get update``, waiting (up to APT_LOCK_WAIT_S) while another apt holds its lock."""
    cmd = ["apt-get", "update", "-qq"]
    print("$ " + " ".join(cmd), flush=True)
    for attempt in range(APT_LOCK_WAIT_S // 5 + 1):
        r = subprocess.run(cmd, env=env, cwd=ROOT, capture_output=True, text=True)
        sys.stdout.write(r.stdout)
        sys.stderr.write(r.stderr)
        if r.returncode == 0:
            return
        if "Could not get lock" not in r.stderr and "Unable to lock" not in r.stderr:
            break
        if attempt == 0:
            print("dev.py: another apt holds the package lists; waiting for it", flush=True)
        time.sleep(5)
    sys.exit(f"dev.py: command failed with exit code {r.returncode}")


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
        apt_update(env)
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
    ensure_venv("all")
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


#: What ``lint`` checks: ruff on the repository (configured in pyproject.toml), then mypy on
#: the two typed packages (the [tool.mypy] section of pyproject.toml).
LINT_COMMANDS = (
    ("ruff", "check", "."),
    ("mypy",),
)


def cmd_lint() -> int:
    """Run every command of LINT_COMMANDS (all of them, even after a failure); 1 if one failed."""
    ensure_venv("all")
    failed = [cmd[0] for cmd in LINT_COMMANDS if run([BIN / cmd[0], *cmd[1:]], child_env())]
    if failed:
        print(f"dev.py: lint FAILED: {', '.join(failed)}", file=sys.stderr, flush=True)
        return 1
    return 0


def cmd_lab(extra: list[str]) -> int:
    """JupyterLab at the repository root: book/ (chapters open as notebooks), exercises/, ..."""
    ensure_venv("all")
    cmd = [BIN / "jupyter", "lab", f"--ServerApp.root_dir={ROOT}"]
    if hasattr(os, "geteuid") and os.geteuid() == 0 and "--allow-root" not in extra:
        cmd.append("--allow-root")  # Jupyter refuses root otherwise (containers)
    return run([*cmd, *extra], child_env())


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
    sub.add_parser("lint", help="set up .venv and run ruff and mypy (pyproject.toml)")
    sub.add_parser("translations", help="refresh the book's translation catalogues "
                   "(book/locales/) from its sources")
    sub.add_parser("lab", help="set up .venv and start JupyterLab at the repository root; "
                   "jupyter lab args after --")
    args = p.parse_args(argv)
    if args.command == "book":
        if extra:
            p.error("book takes no arguments after --")
        return cmd_book(args)
    if args.command == "lab":
        return cmd_lab(extra)
    if args.command == "lint":
        if extra:
            p.error("lint takes no arguments after --")
        return cmd_lint()
    if args.command == "translations":
        return cmd_translations()
    return cmd_test(args, extra)


if __name__ == "__main__":
    sys.exit(main())
