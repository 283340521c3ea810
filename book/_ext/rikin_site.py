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

import ast
import hashlib
import ipaddress
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import urllib.parse
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rikin_comments  # noqa: E402  (the install cell's comments; standard library only)

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "_config.yml"
#: Where the distributions live inside the built site (relative to its root).
DIST_PATH = "_static/dist"
#: Where the book publishes the exercise notebooks under stable names (relative to its root).
EXERCISES_PATH = "_static/exercises"
#: The page that offers the exercise notebooks (relative to the site's root).
EXERCISES_PAGE = "book/exercises.html"
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


def is_loopback(url: str) -> bool:
    """Whether ``url`` names this computer only (127.0.0.0/8, ::1, localhost, 0.0.0.0).

    A book built for such an address works in a local preview and nowhere else: its
    notebooks install rikin from there.
    """
    host = (urllib.parse.urlsplit(url).hostname or "").lower()
    if host == "localhost" or host.endswith(".localhost"):
        return True
    try:
        ip = ipaddress.ip_address(host)
    except ValueError:
        return False
    return ip.is_loopback or ip.is_unspecified


#: What a build for a loopback address says, on every page and in the log ({url}: the
#: address). It and the other texts the book's extension writes on its pages
#: (:data:`PAGE_TEXTS`) are messages: a translated edition shows them as its catalogues
#: translate them (book/_ext/rikin_i18n.py).
LOOPBACK_WARNING = ("A local preview: this book's notebooks install rikin from {url}, an "
                    "address only this computer can reach. Set html.baseurl in _config.yml to "
                    "the public URL the book is served from, then build it again before "
                    "publishing it.")
#: The preview banner's first words (then :data:`LOOPBACK_WARNING`).
PREVIEW_TITLE = "Not for publishing."
#: The launch line of a page published as a notebook, and of an exercise ({name}: its file).
LAUNCH_PAGE = "Run this page yourself:"
LAUNCH_FILE = "Run {name} yourself:"
#: The launch line's download link, and what it says when there are no launch links.
LAUNCH_DOWNLOAD = "download the notebook (.ipynb)"
LAUNCH_UPLOAD = "and open it in Jupyter, JupyterLab or Colab (File → Upload notebook)"
#: After an exercise's download link, when there are no launch links.
LAUNCH_OPEN = "Open it in Jupyter, JupyterLab or Colab (File → Upload notebook)."
PAGE_TEXTS = (PREVIEW_TITLE, LOOPBACK_WARNING, LAUNCH_PAGE, LAUNCH_FILE, LAUNCH_DOWNLOAD,
              LAUNCH_UPLOAD, LAUNCH_OPEN)


def loopback_warning(url: str, template: str = LOOPBACK_WARNING) -> str:
    """What a build for a loopback ``url`` says (``template``: :data:`LOOPBACK_WARNING` or
    its translation)."""
    return template.format(url=url)


#: The GitHub address of a folder of a branch: owner, repository, branch, folder.
_GITHUB_TREE = re.compile(r"^https://github\.com/(?P<owner>[\w.-]+)/(?P<repo>[\w.-]+)"
                          r"/tree/(?P<branch>[\w.-]+)(?P<folder>(?:/[^?#\s]*)?)/?$")


def read_launch_repository(value: str | None,
                           where: str = "rikin_launch_repository") -> tuple[str, ...] | None:
    """The launch key: the GitHub folder holding the built site, as (owner, repo, branch,
    folder), or None when it is empty (no launch links but the download)."""
    value = (value or "").strip()
    if not value:
        return None
    m = _GITHUB_TREE.match(value)
    if not m:
        raise SiteError(
            f"{where} must be the GitHub address of the folder that holds the built site, "
            f"like https://github.com/<user>/<repo>/tree/gh-pages (a branch without '/'), "
            f"not {value!r}")
    return (m["owner"], m["repo"], m["branch"], m["folder"].strip("/"))


def launch_links(repository: tuple[str, ...], path: str) -> dict[str, str]:
    """Where a published notebook (``path`` in the site) opens with one click.

    ``repository`` is :func:`read_launch_repository`'s answer. Colab opens a notebook
    from GitHub; Binder starts JupyterLab on the repository's branch and opens it there.
    """
    owner, repo, branch, folder = repository
    inside = f"{folder}/{path}" if folder else path
    q = urllib.parse.quote
    return {
        "Colab": f"https://colab.research.google.com/github/{owner}/{repo}/blob/{branch}/"
                 f"{q(inside)}",
        "JupyterLab (Binder)": f"https://mybinder.org/v2/gh/{owner}/{repo}/{branch}"
                               f"?urlpath={q('lab/tree/' + inside, safe='')}",
    }


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


#: The install cell's code after its settings (RIKIN_BOOK, RIKIN_PAGE, RIKIN_NEEDED,
#: RIKIN_EXTRAS, RIKIN_WHEEL, RIKIN_SAYS). Plain Python that any notebook kernel runs (Colab's too):
#: standard library only, every step a small function, one line of news per run.
INSTALL_BODY = r'''

class RikinSetupError(Exception):
    """This cell cannot go on; the message says what to do. Run All stops here."""


def _rikin_say(template, **values):
    """One of this cell's messages in the notebook's language (RIKIN_SAYS: English ->
    the notebook's language), with ``values`` put into its {placeholders}."""
    return RIKIN_SAYS.get(template, template).format(**values)


def _rikin_say_only_the_message():
    """A RikinSetupError shows as its message, not a traceback (%tb shows it)."""
    try:
        shell = get_ipython()  # noqa: F821 (defined in IPython and Jupyter kernels)
    except NameError:
        return

    def message_only(shell, etype, value, tb, tb_offset=None):
        shell.showtraceback((etype, value, tb), exception_only=True)

    shell.set_custom_exc((RikinSetupError,), message_only)


def _rikin_version_key(v):
    import re
    return tuple(int(x) for x in re.findall(r"\d+", v.split("+")[0])[:3])


def _rikin_missing():
    """Why rikin (with the extras this notebook uses) must be installed, or None."""
    import importlib.metadata as md
    import re
    try:
        have = md.version("rikin")
    except md.PackageNotFoundError:
        return _rikin_say("rikin is not installed")
    if _rikin_version_key(have) < _rikin_version_key(RIKIN_NEEDED):
        return _rikin_say("rikin {have} is older than this notebook needs ({needed})",
                          have=have, needed=RIKIN_NEEDED)
    for req in md.requires("rikin") or []:
        m = re.match(r"([A-Za-z0-9._-]+).*extra *== *.(\w+)", req)
        if m and m.group(2) in RIKIN_EXTRAS:
            try:
                md.version(m.group(1))
            except md.PackageNotFoundError:
                return _rikin_say("{package} (rikin[{extra}]) is not installed",
                                  package=m.group(1), extra=m.group(2))
    return None


def _rikin_checkout():
    """The folder of a checkout of the course around this notebook, or None."""
    import pathlib
    here = pathlib.Path.cwd().resolve()
    for folder in (here, *here.parents):
        if (folder / "rikin" / "__init__.py").is_file() and (folder / "pyproject.toml").is_file():
            return folder
    return None


def _rikin_wheel(why):
    """The pinned URL of the wheel the book hosts (asking the book when not written here)."""
    import json
    import urllib.request
    if RIKIN_WHEEL:
        return RIKIN_WHEEL
    url = RIKIN_BOOK + "_static/dist/rikin-dist.json"
    try:
        with urllib.request.urlopen(url, timeout=60) as r:
            w = json.load(r)["wheel"]
    except (OSError, ValueError, KeyError) as exc:
        raise RikinSetupError(_rikin_say(
            "{why}, and the course's book, {book}, could not tell which rikin to install "
            "({error}). Are you online? Or download this notebook again from {page}",
            why=why, book=RIKIN_BOOK, error=exc, page=RIKIN_PAGE)) from None
    return f"{RIKIN_BOOK}_static/dist/{w['file']}#sha256={w['sha256']}"


def _rikin_pip(wheel):
    """pip install rikin from ``wheel``, showing pip's progress; its exit code and output."""
    import subprocess
    import sys
    import time
    extras = f"[{','.join(RIKIN_EXTRAS)}]" if RIKIN_EXTRAS else ""
    pip = subprocess.Popen([sys.executable, "-m", "pip", "install", "--progress-bar", "off",
                            "--no-compile", "--disable-pip-version-check",
                            f"rikin{extras} @ {wheel}"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines, t0 = [], time.monotonic()
    for line in pip.stdout:
        lines.append(line)
        news = _rikin_pip_news(line)
        if news:
            print(f"  [{time.monotonic() - t0:4.0f} s] {news}", flush=True)
    return pip.wait(), "".join(lines)


def _rikin_pip_news(line):
    """One of pip's lines as a short progress line ('getting numpy 2.4.6'), or None."""
    import re
    m = re.match(r"(Collecting|Processing|Downloading)\s+(\S+)", line)
    if m:
        wheel = re.search(r"([A-Za-z0-9_.]+)-(\d[\w.]*)-[^/]*\.whl", m.group(2))
        what = f"{wheel.group(1)} {wheel.group(2)}" if wheel else m.group(2).split("@")[0]
        name = re.split(r"[<>=!~;@\[]", what)[0]
        return _rikin_say("getting {name}", name=name)
    if line.startswith("Installing collected packages:"):
        return _rikin_say("installing {n} packages", n=len(line.split(":", 1)[1].split(",")))
    return None


def _rikin_pip_failed(code, out, wheel):
    """The one line that says why pip failed, and what to do."""
    if "DO NOT MATCH THE HASHES" in out or ("404" in out and wheel.split("#")[0] in out):
        why = _rikin_say("this notebook is older than the book: the book now hosts another "
                         "rikin. Download this notebook again from {page}", page=RIKIN_PAGE)
    elif any(s in out for s in ("Failed to establish a new connection", "Network is unreachable",
                                "Name or service not known", "Temporary failure in name",
                                "nodename nor servname", "getaddrinfo failed",
                                "Connection refused", "timed out", "No matching distribution")):
        host = wheel.split("/")[2] if wheel.count("/") >= 2 else wheel
        why = _rikin_say("pip could not download rikin or a package it needs (from {host} "
                         "or your package index): are you online?", host=host)
    else:
        last = [ln.strip() for ln in out.splitlines() if ln.strip()][-3:]
        why = _rikin_say("pip exit code {code}: {last}", code=code, last=" / ".join(last))
    return RikinSetupError(_rikin_say("could not install rikin: {why}", why=why))


def _rikin_imported_versions():
    """Distributions whose modules this kernel has imported, with their versions."""
    import importlib.metadata as md
    import sys
    out = {}
    for name in ("rikin", "numpy", "sympy", "matplotlib", "plotly", "ipywidgets"):
        if name in sys.modules:
            try:
                out[name] = md.version(name)
            except md.PackageNotFoundError:
                out[name] = None
    return out


def _rikin_restart_needed(before):
    """The packages pip changed under modules this kernel has imported (restart for them)."""
    import importlib.metadata as md
    import sys
    changed = []
    for name, old in before.items():
        try:
            new = md.version(name)
        except md.PackageNotFoundError:
            new = None
        if new != old:
            changed.append(f"{name} {old} -> {new}")
    mod = sys.modules.get("rikin")
    if mod is not None and not any(c.startswith("rikin ") for c in changed) and getattr(
            mod, "__version__", None) not in (None, md.version("rikin")):
        changed.append(f"rikin {mod.__version__} (imported) -> {md.version('rikin')}")
    return sorted(set(changed))


def _rikin_front_end():
    """Colab: turn on its widget manager for ipywidgets 8 (the live panels)."""
    import sys
    if "google.colab" in sys.modules:
        from google.colab import output
        output.enable_custom_widget_manager()


def _rikin_setup():
    import importlib
    import importlib.metadata as md
    import importlib.util
    import sys
    _rikin_say_only_the_message()
    _rikin_front_end()
    why = _rikin_missing()
    if why is None:
        stale = _rikin_restart_needed({"rikin": md.version("rikin")})
        if stale:
            raise RikinSetupError(_rikin_say(
                "rikin {version} is installed, but this kernel still runs the one it imported "
                "first ({stale}): restart the kernel (Kernel > Restart Kernel), then run all "
                "cells.", version=md.version("rikin"), stale=stale[0]))
        return _rikin_say("rikin {version} is installed", version=md.version("rikin"))
    folder = _rikin_checkout()
    if folder is not None:  # inside a checkout of the course: use it
        sys.path.insert(0, str(folder))
        return _rikin_say("rikin from the checkout at {folder}", folder=folder)
    wheel = _rikin_wheel(why)
    had_widgets = importlib.util.find_spec("ipywidgets") is not None
    before = _rikin_imported_versions()
    print(_rikin_say("{why}: installing it from {url} (about a minute) ...", why=why,
                     url=wheel.split("#")[0]), flush=True)
    code, out = _rikin_pip(wheel)
    if code != 0:
        raise _rikin_pip_failed(code, out, wheel)
    importlib.invalidate_caches()
    changed = _rikin_restart_needed(before)
    if changed:
        raise RikinSetupError(_rikin_say(
            "rikin {version} is installed, over packages this kernel had imported "
            "({changed}): restart the kernel (Kernel > Restart Kernel), then run all cells "
            "again.", version=md.version("rikin"), changed=", ".join(changed)))
    if "widgets" in RIKIN_EXTRAS and not had_widgets and "google.colab" not in sys.modules:
        return _rikin_say("rikin {version} installed. The live panels need this page "
                          "reloaded once (F5), then Run All again: until then they show still "
                          "pictures", version=md.version("rikin"))
    return _rikin_say("rikin {version} installed", version=md.version("rikin"))


try:
    print(_rikin_setup())
finally:
    for _name in [n for n in globals() if n.startswith("_rikin_")]:
        del globals()[_name]
    del _name
'''


#: The install cell's title (Colab shows it on the folded cell) and the comment under it:
#: messages, translated in the exercises' catalogue (solutions/locales/, see
#: tools/make_exercises.py) for the notebooks of the other languages, the book's too.
INSTALL_TITLE = "Setup: install rikin if it is missing (Colab, a fresh Jupyter)"
INSTALL_NOTE = ("Installs the rikin wheel published with this course's book, pinned by its "
                "sha256, never a package of that name from a public index. A no-op where "
                "rikin is already installed.")


def _said(body: str) -> tuple[str, ...]:
    """The messages of the install cell's code ``body``: the literal first argument of
    every ``_rikin_say(...)`` call, in the order written (each once).

    The same walk as ``rikin.booktext.cell_messages`` for one function: not shared, since
    this module runs under the system ``python3`` too, where importing rikin (numpy) fails.
    """
    found: list[tuple[int, int, str]] = []
    for node in ast.walk(ast.parse(body)):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "_rikin_say":
            first = node.args[0] if node.args else None
            if not (isinstance(first, ast.Constant) and isinstance(first.value, str)):
                raise SiteError(f"install cell line {node.lineno}: _rikin_say(...) needs a "
                                "string literal (a template with named values)")
            found.append((node.lineno, node.col_offset, first.value))
    return tuple(dict.fromkeys(text for _, _, text in sorted(found)))


#: What the install cell prints or raises (its :data:`INSTALL_BODY`'s ``_rikin_say``
#: templates): messages too, so a Spanish notebook's install cell says them in Spanish
#: (pip's own lines stay as pip writes them).
INSTALL_MESSAGES = _said(INSTALL_BODY)
#: What :func:`_says_source` says of each of its dictionaries, in a comment.
SAYS_WHAT = {"RIKIN_SAYS": "the messages below", "RIKIN_CELL_TEXTS": "what the cells print"}
#: The install cell's code comments (rikin_comments' rules: its body's, and the one over
#: each dictionary): messages too, so that every comment of a notebook in another
#: language reads in it (the cell is folded, not hidden from a reader who opens it).
INSTALL_COMMENTS = (
    *dict.fromkeys(c.text for c in rikin_comments.code_comments(INSTALL_BODY)),
    *(f"{what}, English -> the notebook's language" for what in SAYS_WHAT.values()),
)
INSTALL_TEXTS = (INSTALL_TITLE, INSTALL_NOTE, *INSTALL_MESSAGES, *INSTALL_COMMENTS)


def _comment(text: str, width: int = 92) -> str:
    """``text`` as comment lines ("# ...") of at most about ``width`` characters."""
    lines: list[str] = []
    for word in text.split():
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += " " + word
        else:
            lines.append("# " + word)
    return "".join(line + "\n" for line in lines)


def _install_cell_header(book: str, page: str, version: str, wheel: str | None,
                         extras: tuple[str, ...], texts: dict[str, str]) -> str:
    return (
        f"#@title {texts.get(INSTALL_TITLE, INSTALL_TITLE)}\n"
        + _comment(texts.get(INSTALL_NOTE, INSTALL_NOTE)) +
        f"RIKIN_BOOK = {book!r}\n"
        f"RIKIN_PAGE = {page!r}\n"
        f"RIKIN_NEEDED = {version!r}\n"
        f"RIKIN_EXTRAS = {tuple(extras)!r}\n"
        f"RIKIN_WHEEL = {wheel!r}\n"
        + _says_source(_says(texts))
    )


def _literal_lines(text: str, indent: str, width: int = 92) -> list[str]:
    """``text`` as Python string literals of at most about ``width`` characters, one per
    line, that concatenate back to it (split after spaces)."""
    chunks: list[str] = []
    for piece in re.split(r"(?<= )", text):
        if chunks and len(indent) + len(repr(chunks[-1] + piece)) <= width:
            chunks[-1] += piece
        else:
            chunks.append(piece)
    return [indent + repr(chunk) for chunk in chunks or [""]]


def _says_source(says: dict[str, str], name: str = "RIKIN_SAYS") -> str:
    """The install cell's ``RIKIN_SAYS = {...}`` line(s) (or another ``name``'s of
    :data:`SAYS_WHAT`), its lines short enough to read."""
    if not says:
        return f"{name} = {{}}\n"
    lines = [f"{name} = {{  # {SAYS_WHAT[name]}, English -> the notebook's language"]
    for english, said in says.items():
        lines += _literal_lines(english, "    ")
        lines[-1] += ":"
        lines += _literal_lines(said, "        ")
        lines[-1] += ","
    return "\n".join([*lines, "}"]) + "\n"


#: The install cell's end in a notebook of another language than English (after
#: :data:`INSTALL_BODY`, so only once rikin is there): rikin prints in the notebook's
#: language (its tables, branch names, live panels), and the chapter's cells' own texts
#: (``BookText("locales").tr``, whose catalogue is not beside a downloaded notebook) are
#: translated by the ones the book wrote into this cell (``RIKIN_CELL_TEXTS``).
INSTALL_LANGUAGE_TAIL = """
import rikin.booktext  # noqa: E402
import rikin.i18n  # noqa: E402

rikin.i18n.set_language(RIKIN_LANGUAGE)
rikin.booktext.add_translations(RIKIN_LANGUAGE, RIKIN_CELL_TEXTS)
"""


def _language_source(language: str, cell_texts: dict[str, str]) -> str:
    """The settings :data:`INSTALL_LANGUAGE_TAIL` reads: ``RIKIN_LANGUAGE`` and
    ``RIKIN_CELL_TEXTS``."""
    if not re.fullmatch(r"[a-z]{2}", language) or language == "en":
        raise SiteError(f"an install cell's language is a two-letter code other than 'en', "
                        f"got {language!r:.80}")
    return (f"RIKIN_LANGUAGE = {language!r}\n"
            + _says_source(cell_texts, "RIKIN_CELL_TEXTS"))


def _says(texts: dict[str, str]) -> dict[str, str]:
    """The install cell's messages that ``texts`` translates (English -> translation)."""
    return {m: texts[m] for m in INSTALL_MESSAGES if texts.get(m, m) != m}


def install_cell_source(
    book: str, version: str, wheel: str | None = None, extras: tuple[str, ...] = (),
    page: str | None = None, texts: dict[str, str] | None = None,
    language: str | None = None, cell_texts: dict[str, str] | None = None,
) -> str:
    """The install cell's code: needs rikin >= ``version``, published by the book at ``book``.

    ``extras`` are rikin's optional dependencies the notebook uses (``CHAPTER_EXTRAS`` for
    the chapters); the cell installs them too when one is missing.

    ``wheel`` is the pinned URL of the wheel (:func:`wheel_url`), which every notebook the
    book publishes carries. A notebook made outside a book build (``exercises/`` in git,
    which must not change whenever rikin's code does) has ``wheel=None``: it then reads the
    wheel's name and sha256 from the book's manifest, ``<book>_static/dist/rikin-dist.json``.

    ``page`` is where a student downloads this notebook again (default: the book).

    ``texts`` translates the cell's title and comments (:data:`INSTALL_TEXTS`, English ->
    the notebook's language) and what it prints
    (:data:`INSTALL_MESSAGES`, written into the cell as ``RIKIN_SAYS``).

    ``language`` (a notebook in another language than English; None: English, or a
    notebook that sets rikin's language itself, as the exercises do) makes the cell end by
    setting rikin's language to it and handing ``cell_texts`` (the English templates the
    notebook's cells translate with ``rikin.booktext.BookText`` -> ``language``) to
    ``rikin.booktext.add_translations`` (:data:`INSTALL_LANGUAGE_TAIL`), so the notebook
    prints in its language where no catalogue is beside it.

    What a student sees: one line when rikin is there; pip's progress and one line when it
    installs; otherwise one line (a ``RikinSetupError``, which stops Run All) saying what
    to do: restart the kernel (pip changed a package this kernel had imported), download
    the notebook again (the book hosts another wheel now), or go online.
    """
    texts = texts or {}
    head = _install_cell_header(book, page or book, version, wheel, extras, texts)
    if language is None:
        source = head + INSTALL_BODY
    else:
        source = (head + _language_source(language, cell_texts or {}) + INSTALL_BODY
                  + INSTALL_LANGUAGE_TAIL)

    def translate(message: str) -> str | None:
        said = texts.get(message) if message in INSTALL_COMMENTS else None
        return said if said and said != message else None

    # its code comments in the notebook's language (:data:`INSTALL_COMMENTS`)
    return rikin_comments.translated_source(source, translate, width=92)[0]


def install_cell(book: str, version: str, wheel: str | None = None,
                 extras: tuple[str, ...] = (), extra_tags: tuple[str, ...] = (),
                 page: str | None = None, texts: dict[str, str] | None = None,
                 language: str | None = None,
                 cell_texts: dict[str, str] | None = None) -> dict[str, Any]:
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
        "source": install_cell_source(book, version, wheel, extras, page, texts, language,
                                      cell_texts),
    }
