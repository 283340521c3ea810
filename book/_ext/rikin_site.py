"""Where the book is hosted, the rikin distributions it hosts, and the install cell.

Standard library only: the book extension (``rikin_book``), ``tools/make_exercises.py`` and
``tools/release.py`` all import it, the last two possibly under the system ``python3``.

* **One URL.** The site's public address is ``html.baseurl`` in ``_config.yml``
  (:func:`read_base_url`); nothing else names it.
* **The distributions.** :func:`build_distributions` runs ``python -m build`` on the
  repository (sdist, then the wheel from that sdist), reproducibly (``SOURCE_DATE_EPOCH``),
  and writes them with ``SHA256SUMS`` and a JSON manifest into a folder that the book build
  publishes as ``<baseurl>_static/dist/``.
* **The install cell.** :func:`install_cell_source` is the first code cell of every
  notebook the book publishes (chapters and exercises). When rikin is missing or older than
  the notebook needs, it installs exactly the wheel published with the book, by URL and
  pinned to its sha256 (pip checks the ``#sha256=`` fragment), never a package called
  ``rikin`` from a public index. Inside a checkout of this repository it uses the checkout.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "_config.yml"
#: Where the distributions live inside the built site (relative to its root).
DIST_PATH = "_static/dist"
#: Where the book publishes the exercise notebooks under stable names (relative to its root).
EXERCISES_PATH = "_static/exercises"
#: The manifest written next to them: version, file names, sizes, sha256.
MANIFEST = "rikin-dist.json"
#: The tag of the install cell in every published notebook.
INSTALL_TAG = "rikin-install"
#: rikin's extras the chapters may use (the book's rotatable figures, the live IK panel):
#: their published notebooks install them with rikin. The exercises need none.
CHAPTER_EXTRAS = ("interactive", "widgets")
#: Timestamps written into the wheel and sdist (zip's earliest date, 1980-01-01): the same
#: sources give the same bytes, so the same sha256, on every build and machine.
SOURCE_DATE_EPOCH = "315532800"


class SiteError(Exception):
    """The site's configuration or the distributions cannot be made (the message says why)."""


def read_base_url(config: Path = CONFIG) -> str:
    """The site's public URL, ``html.baseurl`` of ``_config.yml``, ending in ``/``.

    A small reader for this one key (the file is ours; no YAML library needed): the
    ``baseurl:`` line indented under the top-level ``html:`` block, quoted or not.
    """
    text = config.read_text(encoding="utf-8")
    block = re.search(r"(?ms)^html:[ \t]*(?:#[^\n]*)?\n((?:[ \t]+[^\n]*\n|[ \t]*\n)*)", text)
    url = None
    if block:
        m = re.search(r"(?m)^[ \t]+baseurl:[ \t]*(?P<v>\"[^\"]*\"|'[^']*'|[^#\s]*)", block.group(1))
        if m:
            url = m.group("v").strip("\"'")
    return read_base_url_value(url, f"{config}: html.baseurl")


def read_base_url_value(url: str | None, where: str = "html.baseurl") -> str:
    """``url`` checked (an absolute http(s) URL) and ending in ``/``."""
    url = (url or "").strip()
    if not url:
        raise SiteError(
            f"{where} is not set: set it to the public URL the book is served from "
            "(e.g. https://<user>.github.io/<repo>/); the published notebooks install rikin "
            f"from <baseurl>{DIST_PATH}/"
        )
    if not re.match(r"^https?://[^/\s]+", url):
        raise SiteError(f"{where} must be an absolute http(s) URL, not {url!r}")
    return url if url.endswith("/") else url + "/"


def read_version(root: Path = ROOT) -> str:
    """rikin's version: ``__version__`` in ``rikin/__init__.py`` (its one place)."""
    text = (root / "rikin" / "__init__.py").read_text(encoding="utf-8")
    m = re.search(r"(?m)^__version__\s*=\s*[\"']([^\"']+)[\"']", text)
    if not m:
        raise SiteError(f"{root / 'rikin' / '__init__.py'} has no __version__ = '...' line")
    return m.group(1)


def sha256_of(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


#: What the sdist is built from (see MANIFEST.in): the package and its metadata files.
PACKAGE_SOURCES = ("pyproject.toml", "MANIFEST.in", "README.md", "LICENSE", "LICENSES", "rikin")


def _copy_package_sources(root: Path, dest: Path) -> None:
    """Copy :data:`PACKAGE_SOURCES` of ``root`` (those that exist) into ``dest``, keeping
    modification times (the sdist's tar records them)."""
    dest.mkdir(parents=True)
    skip = shutil.ignore_patterns("__pycache__", "*.pyc")
    for name in PACKAGE_SOURCES:
        path = root / name
        if path.is_dir():
            shutil.copytree(path, dest / name, ignore=skip)
        elif path.exists():
            shutil.copy2(path, dest / name)


def build_distributions(outdir: Path, root: Path = ROOT, python: str = sys.executable) -> dict:
    """``python -m build`` rikin into ``outdir``: the sdist, the wheel, SHA256SUMS, manifest.

    No build isolation (the running environment's setuptools builds it, so no network), and
    ``SOURCE_DATE_EPOCH`` fixed, so a rebuild of the same sources gives the same wheel.
    ``outdir`` is emptied first. Returns the manifest (also written as ``rikin-dist.json``).
    """
    outdir = Path(outdir)
    env = dict(os.environ, SOURCE_DATE_EPOCH=SOURCE_DATE_EPOCH, PYTHONHASHSEED="0")
    with tempfile.TemporaryDirectory(prefix="rikin-dist-") as work:
        # setuptools stages the sdist in rikin-<version>/ and build/ beside pyproject.toml:
        # two builds of one checkout at once (the book and the packaging tests, two book
        # builds) delete each other's files. Each build gets its own copy of the sources.
        src, tmp = Path(work) / "src", Path(work) / "dist"
        _copy_package_sources(Path(root), src)
        cmd = [python, "-m", "build", "--no-isolation", "--outdir", str(tmp), str(src)]
        proc = subprocess.run(
            cmd, cwd=src, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
        )
        if proc.returncode != 0:
            raise SiteError(
                "building rikin's wheel and sdist failed (`" + " ".join(cmd) + "`):\n"
                + proc.stdout[-4000:]
            )
        wheels = sorted(Path(tmp).glob("rikin-*.whl"))
        sdists = sorted(Path(tmp).glob("rikin-*.tar.gz"))
        if len(wheels) != 1 or len(sdists) != 1:
            made = [p.name for p in wheels + sdists]
            raise SiteError(f"python -m build made {made}, expected one wheel and one sdist")
        if outdir.exists():
            shutil.rmtree(outdir)
        outdir.mkdir(parents=True)
        files = {}
        for kind, src in (("wheel", wheels[0]), ("sdist", sdists[0])):
            dest = outdir / src.name
            shutil.copy2(src, dest)
            files[kind] = {
                "file": dest.name, "sha256": sha256_of(dest), "size": dest.stat().st_size
            }
    manifest = {"name": "rikin", "version": read_version(root), **files}
    (outdir / "SHA256SUMS").write_text(
        "".join(f"{files[k]['sha256']}  {files[k]['file']}\n" for k in ("wheel", "sdist")),
        encoding="utf-8",
    )
    (outdir / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n", encoding="utf-8")
    return manifest


def wheel_url(base_url: str, manifest: dict) -> str:
    """The pinned URL of the published wheel: ``<baseurl>_static/dist/<file>#sha256=<hex>``."""
    w = manifest["wheel"]
    return f"{base_url}{DIST_PATH}/{w['file']}#sha256={w['sha256']}"


INSTALL_CELL = '''\
#@title Setup: install rikin if it is missing (Colab, a fresh Jupyter)
# Installs the rikin wheel published with this course's book, pinned by its sha256, never a
# package of that name from a public index. A no-op where rikin is already installed.
RIKIN_BOOK = {book!r}
RIKIN_NEEDED = {version!r}
RIKIN_EXTRAS = {extras!r}
RIKIN_WHEEL = {wheel!r}


def _rikin_setup():
    import importlib
    import importlib.metadata
    import json
    import pathlib
    import re
    import subprocess
    import sys
    import urllib.request

    def key(v):
        return tuple(int(x) for x in re.findall(r"\\d+", v.split("+")[0])[:3])

    def missing():  # why rikin must be installed, or None
        try:
            have = importlib.metadata.version("rikin")
        except importlib.metadata.PackageNotFoundError:
            return "rikin is not installed"
        if key(have) < key(RIKIN_NEEDED):
            return f"rikin {{have}} is older than this notebook needs ({{RIKIN_NEEDED}})"
        for req in importlib.metadata.requires("rikin") or []:
            m = re.match(r"([A-Za-z0-9._-]+).*extra *== *.(\\w+)", req)
            if m and m.group(2) in RIKIN_EXTRAS:
                try:
                    importlib.metadata.version(m.group(1))
                except importlib.metadata.PackageNotFoundError:
                    return f"{{m.group(1)}} (rikin[{{m.group(2)}}]) is not installed"
        return None

    why = missing()
    if why is None:
        return f"rikin {{importlib.metadata.version('rikin')}} is installed"
    here = pathlib.Path.cwd().resolve()
    for folder in (here, *here.parents):  # inside a checkout of the course: use it
        if (folder / "rikin" / "__init__.py").is_file() and (folder / "pyproject.toml").is_file():
            sys.path.insert(0, str(folder))
            return f"rikin from the checkout at {{folder}}"
    wheel = RIKIN_WHEEL
    if wheel is None:  # a copy made outside the book: ask the book which wheel it hosts
        try:
            with urllib.request.urlopen(RIKIN_BOOK + "{dist}/{manifest}", timeout=60) as r:
                w = json.load(r)["wheel"]
        except (OSError, ValueError, KeyError) as exc:
            raise RuntimeError(f"rikin is not installed, and the course's book, {{RIKIN_BOOK}}, "
                               f"could not tell which rikin to install ({{exc}}). Are you "
                               "online? Or download this notebook again from the book.") from None
        wheel = f"{{RIKIN_BOOK}}{dist}/{{w['file']}}#sha256={{w['sha256']}}"
    print(f"{{why}}: installing it from {{wheel.split('#')[0]}} ...", flush=True)
    extras = f"[{{','.join(RIKIN_EXTRAS)}}]" if RIKIN_EXTRAS else ""
    pip = subprocess.run([sys.executable, "-m", "pip", "install", "--quiet",
                          "--disable-pip-version-check", f"rikin{{extras}} @ {{wheel}}"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if pip.returncode != 0:
        raise RuntimeError(f"could not install rikin (pip exit code {{pip.returncode}}):\\n"
                           f"{{pip.stdout[-3000:]}}\\nAre you online? rikin comes from the "
                           f"course's book, {{RIKIN_BOOK}}; if the book has moved, download "
                           "this notebook again from it.")
    importlib.invalidate_caches()
    if "rikin" in sys.modules:
        return "rikin was updated: restart the kernel (Kernel > Restart), then run all cells"
    return f"rikin {{importlib.metadata.version('rikin')}} installed"


print(_rikin_setup())
del _rikin_setup
'''


def install_cell_source(
    book: str, version: str, wheel: str | None = None, extras: tuple[str, ...] = ()
) -> str:
    """The install cell's code: needs rikin >= ``version``, published by the book at ``book``.

    ``extras`` are rikin's optional dependencies the notebook uses (``CHAPTER_EXTRAS`` for
    the chapters); the cell installs them too when one is missing.

    ``wheel`` is the pinned URL of the wheel (:func:`wheel_url`), which every notebook the
    book publishes carries. A notebook made outside a book build (``exercises/`` in git,
    which must not change whenever rikin's code does) has ``wheel=None``: it then reads the
    wheel's name and sha256 from the book's manifest, ``<book>_static/dist/rikin-dist.json``.
    """
    return INSTALL_CELL.format(book=book, version=version, wheel=wheel, extras=tuple(extras),
                               dist=DIST_PATH, manifest=MANIFEST)


def install_cell(book: str, version: str, wheel: str | None = None,
                 extras: tuple[str, ...] = (), extra_tags: tuple[str, ...] = ()) -> dict[str, Any]:
    """The install cell as an nbformat 4 code cell (a plain dict), its code folded away.

    Colab shows it as a form titled by its ``#@title`` line; Jupyter folds its source.
    """
    return {
        "cell_type": "code",
        "execution_count": None,
        "id": INSTALL_TAG,
        "metadata": {
            "cellView": "form",
            "jupyter": {"source_hidden": True},
            "tags": [INSTALL_TAG, *extra_tags],
        },
        "outputs": [],
        "source": install_cell_source(book, version, wheel, extras),
    }
