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
  the build; the executed ``.ipynb`` that myst-nb writes (with outputs; in a cached
  build, the outputs of a page taken from the cache are merged in from it,
  :func:`with_cached_outputs`) is published next to the page's source as
  ``_sources/<page>.ipynb`` and offered by the theme's download button. A first
  cell is prepended that, when rikin is missing or too old (Colab, a fresh Jupyter),
  installs exactly that wheel from ``html.baseurl`` (``_config.yml``), pinned to its
  sha256. The exercise notebooks the book offers for download (``_downloads/``) get the
  same pinned cell in place of the one ``tools/make_exercises.py`` wrote.
* **Jupyter Markdown in them.** The chapters' MyST (targets, roles, directives) becomes
  Markdown that JupyterLab, Notebook 7 and Colab render (``rikin_markdown``), its
  cross-references links to the hosted book resolved by Sphinx (:class:`BookLinks`), and
  each numbered figure's number and caption follow the cell that draws it.
* **Launch links and the preview banner.** Every page published as a notebook, and every
  exercise on the exercises page, gets links that open it in Colab and in JupyterLab on
  Binder, from one key (``rikin_launch_repository``); a build whose ``html.baseurl`` is a
  loopback address says on every page that it is a local preview.
* **Printed tables keep their columns on a phone.** A cell's printed output whose lines
  hold columns (two or more lines with a run of spaces between words: the IK tables, DH
  tables) gets the class ``rikin-columns`` (:class:`TabularOutputs`); below 600 px the
  stylesheet keeps its lines and lets it scroll sideways in its own box, where the prose
  a cell prints still wraps.
* **Figures without plotly.js in the build.** The kernels that execute the chapters get
  ``RIKIN_BOOK_BUILD=1`` (their figures' HTML carries no plotly.js: the page loads it).
"""

from __future__ import annotations

import functools
import html
import importlib.util
import json
import os
import posixpath
import re
import shutil
import sys
from pathlib import Path
from typing import Any

import nbformat
from docutils import nodes
from sphinx.application import Sphinx
from sphinx.errors import ExtensionError
from sphinx.transforms.post_transforms import SphinxPostTransform
from sphinx.util import logging

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rikin_comments  # noqa: E402  (the code cells' comments in the edition's language)
import rikin_i18n  # noqa: E402  (the editions, and the site's texts in their language)
import rikin_markdown  # noqa: E402  (next to this file; standard library only)
import rikin_site  # noqa: E402

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


#: The book's own static folder (its stylesheet and script) and their names.
BOOK_STATIC = Path(__file__).resolve().parent.parent / "_static"
BOOK_CSS = "rikin.css"
BOOK_JS = "rikin.js"


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


def _install_cell(app: Sphinx, extras: tuple[str, ...] = (), page: str | None = None,
                  cell_texts: dict[str, str] | None = None) -> nbformat.NotebookNode:
    """The book's install cell in the edition's language; with ``cell_texts`` (a chapter's
    notebook in another edition than English) it also sets rikin's language and hands
    over those translations of the chapter's cell texts (``rikin_site.install_cell``)."""
    info = app.env.rikin_install
    texts = {m: rikin_i18n.site_text(app, m) for m in rikin_site.INSTALL_TEXTS}
    language = None if cell_texts is None else rikin_i18n.edition(app.config.language)
    cell = rikin_site.install_cell(info["book"], info["version"], info["wheel"], extras=extras,
                                   extra_tags=("remove-cell",), page=page, texts=texts,
                                   language=language, cell_texts=cell_texts)
    return nbformat.from_dict(cell)


def chapter_cell_texts(app: Sphinx, pagename: str,
                       nb: nbformat.NotebookNode) -> dict[str, str] | None:
    """The translations, in the edition's language, of the texts the chapter's code cells
    print through ``BookText("locales").tr`` (``rikin.booktext.cell_messages``: ``ok``,
    ``tr`` and ``show_table`` headers), read from the catalogue beside the page
    (``locales/<lang>/LC_MESSAGES/cells.po``): only those, so a downloaded notebook
    carries its own. None in the English edition."""
    lang = rikin_i18n.edition(app.config.language)
    if lang == "en":
        return None
    from rikin.booktext import CATALOGUE, cell_messages, read_catalogue
    from rikin.errors import InputError

    path = Path(app.env.doc2path(pagename)).parent / "locales" / CATALOGUE.format(lang=lang)
    catalogue = read_catalogue(path) if path.is_file() else {}
    used: dict[str, None] = {}
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        try:
            used.update(dict.fromkeys(m for _, m in cell_messages(cell.source)))
        except (InputError, SyntaxError) as exc:
            raise ExtensionError(f"{pagename}: code cell {i}: {exc}") from None
    return {m: catalogue[m] for m in used if m in catalogue}


class BookLinks:
    """The book's cross-references as links to the hosted book (a ``rikin_markdown.Resolve``).

    ``links(role, target, text)`` -> (text shown, URL) for ``{numref}``, ``{ref}``,
    ``{doc}``, ``{term}``, ``{eq}`` and ``{download}`` as they appear on page ``docname``;
    None where Sphinx knows no such target.
    """

    def __init__(self, app: Sphinx, docname: str) -> None:
        self.app, self.env, self.docname = app, app.env, docname
        self.base = app.env.rikin_install["book"]
        self.std: Any = app.env.get_domain("std")

    def url(self, docname: str, anchor: str = "") -> str:
        return self.base + self.app.builder.get_target_uri(docname) + (
            f"#{anchor}" if anchor else "")

    def __call__(self, role: str, target: str, text: str | None) -> rikin_markdown.Link | None:
        how = {"numref": self.numref, "ref": self.ref, "doc": self.doc, "term": self.term,
               "eq": self.eq, "download": self.download}.get(role)
        return how(target, text) if how else None

    def _label(self, label: str) -> tuple[str, str] | None:
        found = self.std.labels.get(label) or self.std.anonlabels.get(label)
        return (found[0], found[1]) if found else None

    def numref(self, label: str, text: str | None) -> rikin_markdown.Link | None:
        found = self._label(label)
        if found is None:
            return None
        doc, anchor = found
        numbers = self.env.toc_fignumbers.get(doc, {})
        for kind in ("figure", "table", "code-block", "section"):
            number = numbers.get(kind, {}).get(anchor)
            if number:
                n = ".".join(map(str, number))
                fmt = text or self.app.config.numfig_format.get(kind, "%s")
                return fmt.replace("{number}", n).replace("%s", n), self.url(doc, anchor)
        return text or label, self.url(doc, anchor)

    def ref(self, label: str, text: str | None) -> rikin_markdown.Link | None:
        found = self.std.labels.get(label)
        if found:
            return text or found[2] or label, self.url(found[0], found[1])
        anon = self.std.anonlabels.get(label)
        return (text or label, self.url(anon[0], anon[1])) if anon else None

    def doc(self, target: str, text: str | None) -> rikin_markdown.Link | None:
        doc = target.lstrip("/") if target.startswith("/") else posixpath.normpath(
            posixpath.join(posixpath.dirname(self.docname), target))
        doc = doc.removesuffix(".md")
        if doc not in self.env.titles:
            return None
        return text or self.env.titles[doc].astext(), self.url(doc)

    def term(self, name: str, text: str | None) -> rikin_markdown.Link | None:
        for (kind, term), (doc, anchor) in self.std.objects.items():
            if kind == "term" and term.lower() == name.lower():
                return text or name, self.url(doc, anchor)
        return None

    def eq(self, label: str, text: str | None) -> rikin_markdown.Link | None:
        math: Any = self.env.get_domain("math")
        found = math.equations.get(label)
        if not found:
            return None
        return text or f"({found[1]})", self.url(found[0], f"equation-{label}")

    def download(self, target: str, text: str | None) -> rikin_markdown.Link | None:
        rel, _ = self.env.relfn2path(target, self.docname)
        found = self.env.dlfiles.get(rel)
        if not found:
            return None
        name = posixpath.basename(rel)
        if name.endswith(".ipynb"):  # published at a stable address too
            return text or name, f"{self.base}{rikin_site.EXERCISES_PATH}/{name}"
        return text or name, f"{self.base}_downloads/{found[1]}"


def _glued(nb: nbformat.NotebookNode) -> rikin_markdown.Glue:
    """The values a notebook glued (``myst_nb.glue``), as text."""
    text: dict[str, str] = {}
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            name = out.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                data = out.get("data", {})
                plain = [v for k, v in data.items() if k.endswith("text/plain")]
                if plain:
                    text[name] = str(plain[0]).strip("'\"")
    return rikin_markdown.Glue(text)


def jupyter_markdown(nb: nbformat.NotebookNode, links: rikin_markdown.Resolve) -> None:
    """A chapter's executed notebook as Jupyter reads it (in place).

    Every markdown cell in plain Jupyter Markdown (:mod:`rikin_markdown`); after every cell
    that draws a numbered figure, a markdown cell with the figure's number and caption
    (the book shows them under the figure; the notebook's own run draws it).
    """
    glue = _glued(nb)
    cells = []
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            cell.source = rikin_markdown.to_jupyter(cell.source, links, glue).strip("\n")
        cells.append(cell)
        figure = cell.get("metadata", {}).get("mystnb", {}).get("figure", {})
        if cell.cell_type == "code" and figure.get("caption"):
            caption = rikin_markdown.to_jupyter(
                str(figure["caption"]).strip(), links, glue).strip()
            found = links("numref", figure["name"], None) if figure.get("name") else None
            head = f"**{found[0]}.** " if found else ""
            cells.append(nbformat.v4.new_markdown_cell(head + caption))
    nb.cells = cells


def translate_notebook(nb: nbformat.NotebookNode, lookup: Any, language: str) -> None:
    """A chapter's executed notebook in a translated edition's language (in place): its
    markdown and its figures' captions, as the page's catalogue translates them
    (``rikin_i18n.translate_markdown``), and its code cells' comments as the page shows
    them (``rikin_comments``); the code and what it printed stay as they are (the cells
    printed in the edition's language); its metadata says ``language`` (as the exercises
    in other languages do). ``lookup`` None: English, unchanged."""
    if lookup is None:
        return
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            cell.source = rikin_i18n.translate_markdown(cell.source, lookup)
        elif cell.cell_type == "code":
            cell.source = rikin_comments.translated_source(
                cell.source, lambda message: lookup([message]))[0]
        figure = cell.get("metadata", {}).get("mystnb", {}).get("figure", {})
        if cell.cell_type == "code" and figure.get("caption"):
            figure["caption"] = rikin_i18n.translate_markdown(str(figure["caption"]).strip(),
                                                              lookup)
    nb.metadata["language"] = language


#: The notebook metadata myst-nb takes from the cache with the outputs (its
#: ``merge_match_into_notebook``'s default): the widgets' state draws the live panels.
CACHED_METADATA = ("kernelspec", "language_info", "widgets")


def with_cached_outputs(nb: nbformat.NotebookNode, cache_path: Path) -> bool:
    """Give ``nb`` (in place) the outputs jupyter-cache keeps for its code, as the page
    shows them; whether the cache had them.

    With ``nb_execution_mode: cache`` (``tools/dev.py book --cached``), a page re-read whose
    code the cache already ran is not executed: myst-nb 1.4 renders the page from a
    *copy* of its notebook merged with the cached outputs (``NotebookClientCache``), and
    writes ``jupyter_execute/<page>.ipynb`` from the notebook it read, which has none. The
    published notebook would then offer the reader no output at all. Only the outputs,
    execution counts and :data:`CACHED_METADATA` are taken (the cells' sources and tags
    are the page's: the cache matched the code only)."""
    from jupyter_cache import get_cache

    if not cache_path.is_dir():
        return False
    cache = get_cache(str(cache_path))
    try:
        cached = cache.get_cache_bundle(cache.match_cache_notebook(nb).pk).nb
    except KeyError:  # the page's code as it is now was never run into this cache
        return False
    code = [cell for cell in nb.cells if cell.cell_type == "code"]
    for cell, done in zip(code, [c for c in cached.cells if c.cell_type == "code"],
                          strict=True):
        cell.outputs = done.get("outputs", [])
        cell.execution_count = done.get("execution_count")
    for key in CACHED_METADATA:
        if key in cached.metadata:
            nb.metadata[key] = cached.metadata[key]
    return True


def publish_notebook(
    app: Sphinx, pagename: str, templatename: str, context: dict[str, Any], doctree: Any
) -> None:
    """Publish the executed notebook of a page as ``_sources/<page>.ipynb``, in Jupyter
    Markdown and with its install cell, and announce it to the theme's download button."""
    if doctree is None or app.builder.format != "html":
        return
    executed = Path(app.outdir).parent / "jupyter_execute" / f"{pagename}.ipynb"
    if not executed.is_file():
        return
    nb = nbformat.read(executed, as_version=4)
    config = app.env.mystnb_config
    if config.execution_mode == "cache" and config.execution_cache_path:
        with_cached_outputs(nb, Path(config.execution_cache_path))
    for key in ("jupytext", "source_map"):  # build-time metadata, noise for a reader
        nb.metadata.pop(key, None)
    translate_notebook(nb, rikin_i18n.page_lookup(app, pagename),
                       rikin_i18n.edition(app.config.language))
    cell_texts = chapter_cell_texts(app, pagename, nb)
    jupyter_markdown(nb, BookLinks(app, pagename))
    page = BookLinks(app, pagename).url(pagename)
    nb.cells.insert(0, _install_cell(app, rikin_site.CHAPTER_EXTRAS, page=page,
                                     cell_texts=cell_texts))
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
        cell = json.loads(json.dumps(_install_cell(app, page=_download_page(app, path))))
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


def _download_page(app: Sphinx, path: Path) -> str | None:
    """The URL of the page that offers the downloaded file at ``path`` (None if unknown)."""
    dest = path.relative_to(Path(app.outdir) / "_downloads").as_posix()
    for docnames, found in app.env.dlfiles.values():
        if found == dest and docnames:
            return BookLinks(app, sorted(docnames)[0]).url(sorted(docnames)[0])
    return None


def _with_ids(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    """Give every cell a deterministic id (nbformat 4.5), so rebuilds write identical files."""
    nb.nbformat, nb.nbformat_minor = 4, max(int(nb.get("nbformat_minor", 5)), 5)
    for i, cell in enumerate(nb.cells):
        cell["id"] = f"cell-{i:03d}"
    return nb


def _launch_html(app: Sphinx, path: str, download: str | None, what: str | None) -> str:
    """Links that open the published notebook at ``path`` (in the edition's site) with one
    click, in the edition's language: "Run this page yourself" (``what`` None) or "Run
    <what> yourself". The launch links name the file in the published repository, where a
    translated edition's site is a folder of the English one's (``es/``)."""
    repo = rikin_site.read_launch_repository(app.config.rikin_launch_repository,
                                             "_config.yml sphinx.config.rikin_launch_repository")
    inside = rikin_i18n.EDITIONS[rikin_i18n.edition(app.config.language)][0] + path
    links = [f'<a class="rikin-launch-{name.split()[0].lower()}" href="{html.escape(url)}" '
             f'target="_blank" rel="noopener">{html.escape(name)}</a>'
             for name, url in (rikin_site.launch_links(repo, inside).items() if repo else ())]
    say = functools.partial(rikin_i18n.site_text, app)
    if download:
        links.append(f'<a href="{html.escape(download)}" download>'
                     f"{html.escape(say(rikin_site.LAUNCH_DOWNLOAD))}</a>")
    if not links:  # an exercise, no launch links: its download link is just before this
        return ('<p class="rikin-launch" style="margin:.2em 0 1em">'
                f"{html.escape(say(rikin_site.LAUNCH_OPEN))}</p>")
    tail = [] if repo else [html.escape(say(rikin_site.LAUNCH_UPLOAD))]
    run = (say(rikin_site.LAUNCH_PAGE) if what is None
           else say(rikin_site.LAUNCH_FILE, name=what))
    words = " ".join(w for w in (html.escape(run), " · ".join(links), *tail) if w)
    return f'<p class="rikin-launch" style="margin:.2em 0 1em">{words}</p>'


def _preview_banner(app: Sphinx) -> str:
    base = app.env.rikin_install["book"]
    if not rikin_site.is_loopback(base):
        return ""
    say = functools.partial(rikin_i18n.site_text, app)
    warning = rikin_site.loopback_warning(base, say(rikin_site.LOOPBACK_WARNING))
    return ('<div class="rikin-preview-banner" role="note" style="border-left:4px solid '
            'var(--pst-color-danger, #c00);padding:.4em .8em;margin:0 0 1em">'
            f"<b>{html.escape(say(rikin_site.PREVIEW_TITLE))}</b> {html.escape(warning)}</div>")


#: A download link to an exercise notebook in a page's HTML (Sphinx's ``{download}`` role).
_DOWNLOAD_LINK = re.compile(r'(<a class="reference download internal"[^>]*href="(?P<href>'
                            r'[^"]*_downloads/[^"]*/(?P<name>[\w.-]+\.ipynb))"[^>]*>.*?</a>)',
                            re.S)


def add_launch_links(
    app: Sphinx, pagename: str, templatename: str, context: dict[str, Any], doctree: Any
) -> None:
    """On every page: the preview banner of a loopback build; on a page published as a
    notebook, its launch links; after every exercise download link, that exercise's."""
    if app.builder.format != "html" or "body" not in context:
        return
    top = _preview_banner(app)
    if context.get("ipynb_source"):
        path = f"_sources/{context['ipynb_source']}"
        top += _launch_html(app, path, context.get("pathto", lambda p, _=1: p)(path, 1),
                            None)

    def with_links(m: re.Match[str]) -> str:
        path = f"{rikin_site.EXERCISES_PATH}/{m['name']}"
        return m[1] + " " + _launch_html(app, path, None, m["name"]).replace(
            '<p class="rikin-launch" style="margin:.2em 0 1em">', "<span class=\"rikin-launch\">"
        ).replace("</p>", "</span>")

    context["body"] = top + _DOWNLOAD_LINK.sub(with_links, context["body"])


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


#: A line with columns: two words (or numbers) apart by a run of two spaces or more.
_COLUMNS = re.compile(r"\S {2,}\S")


class TabularOutputs(SphinxPostTransform):
    """Mark the printed outputs that are tables (see the module's description)."""

    default_priority = 400

    def run(self, **kwargs: Any) -> None:
        for node in self.document.findall(nodes.literal_block):
            if "output" not in node["classes"]:
                continue
            lines = node.astext().splitlines()
            if sum(bool(_COLUMNS.search(line)) for line in lines) >= 2:
                node["classes"].append("rikin-columns")


def setup(app: Sphinx) -> dict[str, Any]:
    # the kernels that execute the chapters inherit this: their interactive figures carry
    # no plotly.js (the pages load it from _static; see rikin.interactive.BOOK_BUILD_ENV)
    os.environ[_interactive().BOOK_BUILD_ENV] = "1"
    app.add_config_value("rikin_launch_repository", "", "html")
    app.connect("config-inited", set_mathjax_path)
    app.connect("config-inited", add_book_static)
    app.add_css_file(BOOK_CSS)
    app.add_post_transform(TabularOutputs)
    app.add_js_file(BOOK_JS)
    app.connect("builder-inited", build_rikin_dists)
    app.connect("build-finished", copy_mathjax)
    app.connect("build-finished", copy_plotly)
    app.connect("build-finished", pin_downloaded_notebooks)
    app.connect("html-page-context", add_plotly)  # before drop_thebe_scripts (900)
    # before sphinx-book-theme's header buttons (priority 501), which read ipynb_source
    app.connect("html-page-context", publish_notebook, priority=500)
    app.connect("html-page-context", add_launch_links, priority=510)
    app.connect("html-page-context", drop_thebe_scripts, priority=900)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
