"""Sphinx extension for the rikin book: offline MathJax and downloadable chapter notebooks.

Loaded from ``_config.yml`` (``sphinx.local_extensions``). It does two things:

* **MathJax without a network.** ``mathjax_path`` is set to a local copy of MathJax 3
  (``_static/mathjax/tex-chtml.js``), and the files that page needs (the combined
  component, its fonts, the TeX extensions it may autoload, the menu and accessibility
  modules) are copied into the build from the ``sphinx-mathjax-offline`` package. A
  downloaded copy of the book typesets its formulas with no internet access.
* **Interactive figures without a network.** Pages with a ``rikin.interactive``
  figure load ``_static/plotly/plotly.min.js``, copied into the build from the
  installed plotly package; other pages load nothing extra.
* **The book's stylesheet.** ``book/_static/rikin.css`` (code and output wrap inside
  the text column) is served and loaded on every page.
* **No other network access.** sphinx-thebe's scripts (unused: the book has no live-code
  button) are dropped from every page.
* **rikin's wheel and sdist in the site.** Before any page is written, ``python -m build``
  makes them (see ``rikin_site.build_distributions``) into ``_static/dist/``, with
  ``SHA256SUMS`` and ``rikin-dist.json``.
* **Chapters as notebooks.** Each chapter is a MyST markdown notebook, executed during
  the build; the executed ``.ipynb`` that myst-nb writes (with outputs) is published next
  to the page's source as ``_sources/<page>.ipynb`` and offered by the theme's download
  button. A first cell is prepended that, when rikin is missing or too old (Colab, a fresh
  Jupyter), installs exactly that wheel from ``html.baseurl`` (``_config.yml``), pinned to
  its sha256. The exercise notebooks the book offers for download (``_downloads/``) get
  the same pinned cell in place of the one ``tools/make_exercises.py`` wrote.
"""

from __future__ import annotations

import importlib.util
import json
import shutil
import sys
from pathlib import Path
from typing import Any

import nbformat
from sphinx.application import Sphinx
from sphinx.errors import ExtensionError
from sphinx.util import logging

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rikin_site  # noqa: E402  (next to this file; standard library only)

LOGGER = logging.getLogger(__name__)

#: The PyPI distribution that ships MathJax 3 (its import name has dashes).
MATHJAX_PACKAGE = "sphinx-mathjax-offline"
#: The MathJax entry point, relative to ``_static/``.
MATHJAX_ENTRY = "mathjax/tex-chtml.js"
#: Files and folders of the MathJax tree that ``tex-chtml.js`` loads (or may load lazily).
MATHJAX_PARTS = (
    "tex-chtml.js",
    "output/chtml/fonts/woff-v2",
    "input/tex/extensions",
    "a11y",
    "ui",
    "sre",
    "adaptors",
)

def mathjax_source() -> Path:
    """The ``static/mathjax`` folder of the installed ``sphinx-mathjax-offline``."""
    spec = importlib.util.find_spec(MATHJAX_PACKAGE)
    if spec is None or not spec.submodule_search_locations:
        raise ExtensionError(
            f"the book serves MathJax locally and needs the PyPI package {MATHJAX_PACKAGE!r} "
            "(pip install 'sphinx-mathjax-offline==0.0.2'), which is not installed"
        )
    root = Path(list(spec.submodule_search_locations)[0]) / "static" / "mathjax"
    if not (root / "tex-chtml.js").is_file():
        raise ExtensionError(f"{root} has no tex-chtml.js: the {MATHJAX_PACKAGE} install is broken")
    return root


def set_mathjax_path(app: Sphinx, config: Any) -> None:
    mathjax_source()  # fail early and clearly when the package is missing
    config.mathjax_path = MATHJAX_ENTRY


def copy_mathjax(app: Sphinx, exc: Exception | None) -> None:
    if exc is not None or app.builder.format != "html":
        return
    src = mathjax_source()
    dest = Path(app.outdir) / "_static" / "mathjax"
    for part in MATHJAX_PARTS:
        s, d = src / part, dest / part
        if s.is_dir():
            shutil.copytree(s, d, dirs_exist_ok=True)
        elif s.is_file():
            d.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(s, d)


def _interactive() -> Any:
    try:
        import rikin.interactive as interactive
    except ImportError as exc:  # pragma: no cover - rikin is installed with the book
        raise ExtensionError(f"the book needs rikin installed to build: {exc}") from exc
    return interactive


def add_plotly(
    app: Sphinx, pagename: str, templatename: str, context: dict[str, Any], doctree: Any
) -> None:
    """Load the local plotly.js on the pages that have an interactive figure."""
    if app.builder.format == "html" and _interactive().HTML_MARKER in context.get("body", ""):
        app.add_js_file(_interactive().PLOTLY_JS)


def copy_plotly(app: Sphinx, exc: Exception | None) -> None:
    if exc is not None or app.builder.format != "html":
        return
    interactive = _interactive()
    dest = Path(app.outdir) / "_static" / interactive.PLOTLY_JS
    dest.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy2(interactive.plotly_js(), dest)


#: The book's own static folder (its stylesheet) and the stylesheet's name.
BOOK_STATIC = Path(__file__).resolve().parent.parent / "_static"
BOOK_CSS = "rikin.css"


def add_book_static(app: Sphinx, config: Any) -> None:
    config.html_static_path = [*config.html_static_path, str(BOOK_STATIC)]


def build_rikin_dists(app: Sphinx) -> None:
    """Build rikin's sdist and wheel into ``<outdir>/_static/dist`` (before pages are written)."""
    if app.builder.format != "html":
        return
    try:
        base = rikin_site.read_base_url_value(app.config.html_baseurl, "_config.yml html.baseurl")
        manifest = rikin_site.build_distributions(Path(app.outdir) / rikin_site.DIST_PATH)
    except rikin_site.SiteError as exc:
        raise ExtensionError(str(exc)) from None
    app.env.rikin_install = {"book": base, "version": manifest["version"],
                             "wheel": rikin_site.wheel_url(base, manifest)}
    LOGGER.info("rikin %s: published %s (sha256 %s) for %s", manifest["version"],
                manifest["wheel"]["file"], manifest["wheel"]["sha256"], base)


def _install_cell(app: Sphinx, extras: tuple[str, ...] = ()) -> nbformat.NotebookNode:
    info = app.env.rikin_install
    cell = rikin_site.install_cell(info["book"], info["version"], info["wheel"], extras=extras,
                                   extra_tags=("remove-cell",))
    return nbformat.from_dict(cell)


def publish_notebook(
    app: Sphinx, pagename: str, templatename: str, context: dict[str, Any], doctree: Any
) -> None:
    """Copy the executed notebook of a page to ``_sources/`` and announce it to the theme."""
    if doctree is None or app.builder.format != "html":
        return
    executed = Path(app.outdir).parent / "jupyter_execute" / f"{pagename}.ipynb"
    if not executed.is_file():
        return
    nb = nbformat.read(executed, as_version=4)
    for key in ("jupytext", "source_map"):  # build-time metadata, noise for a reader
        nb.metadata.pop(key, None)
    nb.cells.insert(0, _install_cell(app, rikin_site.CHAPTER_EXTRAS))
    out = Path(app.outdir) / "_sources" / f"{pagename}.ipynb"
    out.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(_with_ids(nb), out)
    context["ipynb_source"] = f"{pagename}.ipynb"


def pin_downloaded_notebooks(app: Sphinx, exc: Exception | None) -> None:
    """Give every notebook offered for download (the exercises) the book's pinned install cell.

    Its cell tagged ``rikin-install`` (written by tools/make_exercises.py, which cannot know
    the wheel's hash) is replaced; a notebook without one gets it as its first cell. Each is
    also published at a stable address, ``_static/exercises/<name>.ipynb`` (the download
    links carry a hash in their path), where a downloaded copy of the exercises chapter
    reads them.
    """
    if exc is not None or app.builder.format != "html":
        return
    stable = Path(app.outdir) / rikin_site.EXERCISES_PATH
    for path in sorted((Path(app.outdir) / "_downloads").rglob("*.ipynb")):
        data = json.loads(path.read_text(encoding="utf-8"))
        cell = json.loads(json.dumps(_install_cell(app)))
        cells = data.get("cells", [])
        at = [i for i, c in enumerate(cells)
              if rikin_site.INSTALL_TAG in c.get("metadata", {}).get("tags", [])]
        if at:
            cell["metadata"] = cells[at[0]]["metadata"]
            cell["id"] = cells[at[0]].get("id", cell["id"])
            cells[at[0]] = cell
        else:
            cell["metadata"]["tags"].remove("remove-cell")
            cells.insert(0, cell)
        text = json.dumps(data, indent=1, sort_keys=True, ensure_ascii=False) + "\n"
        path.write_text(text, encoding="utf-8")
        stable.mkdir(parents=True, exist_ok=True)
        (stable / path.name).write_text(text, encoding="utf-8")


def _with_ids(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    """Give every cell a deterministic id (nbformat 4.5), so rebuilds write identical files."""
    nb.nbformat, nb.nbformat_minor = 4, max(int(nb.get("nbformat_minor", 5)), 5)
    for i, cell in enumerate(nb.cells):
        cell["id"] = f"cell-{i:03d}"
    return nb


def drop_thebe_scripts(
    app: Sphinx, pagename: str, templatename: str, context: dict[str, Any], doctree: Any
) -> None:
    """Remove sphinx-thebe's scripts (jupyter-book always loads that extension).

    The book has no live-code button, so thebe is never used; its inline script is
    emitted twice (a ``SyntaxError`` in the console) and names a CDN URL.
    """

    def is_thebe(js: Any) -> bool:
        name = str(getattr(js, "filename", "") or js)
        body = str(getattr(js, "attributes", {}).get("body", ""))
        return "sphinx-thebe" in name or "THEBE_JS_URL" in body

    if "script_files" in context:
        context["script_files"] = [js for js in context["script_files"] if not is_thebe(js)]


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("config-inited", set_mathjax_path)
    app.connect("config-inited", add_book_static)
    app.add_css_file(BOOK_CSS)
    app.connect("builder-inited", build_rikin_dists)
    app.connect("build-finished", copy_mathjax)
    app.connect("build-finished", copy_plotly)
    app.connect("build-finished", pin_downloaded_notebooks)
    app.connect("html-page-context", add_plotly)  # before drop_thebe_scripts (900)
    # before sphinx-book-theme's header buttons (priority 501), which read ipynb_source
    app.connect("html-page-context", publish_notebook, priority=500)
    app.connect("html-page-context", drop_thebe_scripts, priority=900)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
