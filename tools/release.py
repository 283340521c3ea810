#!/usr/bin/env python3
"""Release rikin: one command (standard library only, any python3 >= 3.10).

    python3 tools/release.py 0.2.0 [--date 2026-12-24]

Refused at once when ``html.baseurl`` in ``_config.yml`` is a loopback address (the default
local preview on 127.0.0.1): the book a release builds is for publishing.

1. ``CHANGELOG.md``: the entries under ``## [Unreleased]`` become ``## [0.2.0] - <date>``
   (refused when there are none: a release says what changed), and a new empty
   ``## [Unreleased]`` goes on top.
2. ``rikin/__init__.py``: ``__version__ = "0.2.0"``, the one place the version lives
   (pyproject.toml reads it from there).
3. ``tools/make_exercises.py``: the exercises' first cell now asks for rikin >= 0.2.0.
4. ``python -m build`` (in .venv, no isolation, reproducible): ``dist/rikin-0.2.0.tar.gz``,
   ``dist/rikin-0.2.0-py3-none-any.whl``, ``dist/SHA256SUMS``, ``dist/rikin-dist.json``.
5. ``python3 tools/dev.py book``: the book, which builds and hosts the same wheel in
   ``_build/html/_static/dist/`` (checked: same sha256 as ``dist/``); its notebooks install
   that wheel from ``html.baseurl``.

Then commit, tag, and upload ``_build/html`` where html.baseurl points (README: Releasing).
Exit code 0 when released, 1 when refused (nothing changed) or failed (the files it already
changed are left as they are for a look, ``git checkout .`` undoes them; it never commits).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CHANGELOG = ROOT / "CHANGELOG.md"
INIT = ROOT / "rikin" / "__init__.py"
DIST = ROOT / "dist"
CONFIG = ROOT / "_config.yml"
VERSION_RE = re.compile(r"^\d+\.\d+\.\d+(?:(?:a|b|rc)\d+)?$")

sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402


class ReleaseError(Exception):
    """The release is refused; the message says why."""


def _key(version: str) -> tuple:
    m = re.match(r"^(\d+)\.(\d+)\.(\d+)(?:(a|b|rc)(\d+))?$", version)
    assert m, version
    pre = (m.group(4), int(m.group(5))) if m.group(4) else ("z", 0)  # final after pre-releases
    return (int(m.group(1)), int(m.group(2)), int(m.group(3)), pre)


def changelog_released(text: str, version: str, date: str) -> str:
    """``text`` with its Unreleased entries turned into the section of ``version``."""
    if re.search(rf"(?m)^## \[{re.escape(version)}\]", text):
        raise ReleaseError(f"CHANGELOG.md already has a section for {version}")
    m = re.search(r"(?ms)^## \[Unreleased\][ \t]*\n(.*?)(?=^## \[|\Z)", text)
    if not m:
        raise ReleaseError("CHANGELOG.md has no '## [Unreleased]' section")
    entries = m.group(1).strip("\n")
    if not re.search(r"(?m)^\s*[-*] \S", entries):
        raise ReleaseError(
            "CHANGELOG.md: nothing under '## [Unreleased]': list what changed before releasing"
        )
    section = f"## [Unreleased]\n\n## [{version}] - {date}\n\n{entries}\n\n"
    return text[: m.start()] + section + text[m.end() :].lstrip("\n")


def version_set(text: str, version: str) -> str:
    pattern = r'(?m)^__version__\s*=\s*["\'][^"\']*["\']'
    new, n = re.subn(pattern, f'__version__ = "{version}"', text)
    if n != 1:
        raise ReleaseError("rikin/__init__.py must have exactly one __version__ = '...' line")
    return new


def _venv_python() -> Path:
    sys.path.insert(0, str(ROOT / "tools"))
    import dev

    dev.ensure_venv("book")
    return dev.PY


def check_public_url(config: Path) -> str:
    """html.baseurl of ``config``, refused when only this computer can reach it."""
    base = rikin_site.read_base_url(config)
    if rikin_site.is_loopback(base):
        raise ReleaseError(f"html.baseurl is {base}, a loopback address: the released book's "
                           "notebooks would install rikin from this computer only. Set it in "
                           "_config.yml to the public URL the book will be served from "
                           "(README: Hosting the book)")
    return base


def release(version: str, date: str) -> dict:
    if not VERSION_RE.match(version):
        raise ReleaseError(f"{version!r} is not a version like 1.2.3 (or 1.2.3rc1)")
    check_public_url(CONFIG)
    current = rikin_site.read_version()
    if _key(version) < _key(current):
        raise ReleaseError(f"{version} is older than the current version {current}")
    text = CHANGELOG.read_text(encoding="utf-8") if CHANGELOG.exists() else ""
    new_changelog = changelog_released(text, version, date)
    new_init = version_set(INIT.read_text(encoding="utf-8"), version)
    python = _venv_python()
    CHANGELOG.write_text(new_changelog, encoding="utf-8")
    INIT.write_text(new_init, encoding="utf-8")
    print(f"release: CHANGELOG.md and rikin/__init__.py say {version}", flush=True)
    cmd = [sys.executable, str(ROOT / "tools" / "make_exercises.py")]
    print("+ " + " ".join(cmd), flush=True)
    if subprocess.call(cmd, cwd=ROOT) != 0:
        raise ReleaseError("tools/make_exercises.py failed")
    print(f"+ {python} -m build --no-isolation --outdir dist/ .", flush=True)
    manifest = rikin_site.build_distributions(DIST, python=str(python))
    cmd = [sys.executable, str(ROOT / "tools" / "dev.py"), "book"]
    print("+ " + " ".join(cmd), flush=True)
    if subprocess.call(cmd, cwd=ROOT) != 0:
        raise ReleaseError("the book build failed")
    hosted = json.loads(
        (ROOT / "_build" / "html" / rikin_site.DIST_PATH / rikin_site.MANIFEST).read_text()
    )
    if hosted["wheel"] != manifest["wheel"] or hosted["version"] != version:
        raise ReleaseError(
            f"the book hosts {hosted['wheel']} but dist/ has {manifest['wheel']}: "
            "the wheel is not reproducible"
        )
    return manifest


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="tools/release.py",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("version", help="the new version, e.g. 0.2.0")
    ap.add_argument("--date", default=dt.date.today().isoformat(), help="release date (today)")
    args = ap.parse_args(argv)
    try:
        manifest = release(args.version, args.date)
    except (ReleaseError, rikin_site.SiteError) as exc:
        print(f"release: {exc}", file=sys.stderr)
        return 1
    base = rikin_site.read_base_url()
    w, s = manifest["wheel"], manifest["sdist"]
    print(
        f"\nrikin {args.version} released into dist/ and the book (_build/html):\n"
        f"  {w['file']}  sha256 {w['sha256']}\n  {s['file']}  sha256 {s['sha256']}\n"
        f"The book's notebooks install {base}{rikin_site.DIST_PATH}/{w['file']}.\n"
        "Next:\n"
        f"  git commit -am 'Release {args.version}' && git tag v{args.version}\n"
        f"  upload _build/html to {base} (README: Hosting the book)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
