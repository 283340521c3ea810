"""Sphinx extension for the book's two editions: English at the site root, Spanish in ``es/``.

Both editions are built from the same MyST sources. The Spanish one is Sphinx's own
translation mechanism: ``language: es`` and the gettext catalogues in ``book/locales/es/``
(one ``.po`` file per page, ``gettext_compact: false``); ``tools/dev.py book`` builds it
into ``_build/html/es/`` after the English one, and ``tools/dev.py translations`` refreshes
the catalogues from the sources (see CONTRIBUTING: "Translating the book").

What this extension adds to every page of either edition:

* a **language switch** in the article header, a plain link to the same page in the other
  edition (``es/<page>.html`` from the English site, ``../<page>.html`` back);
* ``<link rel="alternate" hreflang=...>`` for both editions, so a search engine offers a
  reader the page in their language.

And what makes the catalogues hold every text a page shows, not only its markdown: a
figure's caption and alt text written in a code cell's metadata (``mystnb: figure: caption``,
``mystnb: image: alt``) or in a ``glue:figure`` directive exist in the page only once its
notebook ran, and ``tools/dev.py translations`` extracts without running any. In that
(gettext) build the texts are added to the page as :class:`late_texts` nodes, with exactly
the messages Sphinx's ``Locale`` transform looks up in the executed Spanish build (a
caption's paragraph, its lines joined by spaces; an image's alt text).

The comments of the code cells a page shows are teaching text too: the gettext build adds
them to the page's catalogue (one message per trailing comment or block of comment lines,
found with :mod:`tokenize`, ``rikin_comments``), and a translated edition shows each cell's
source with its comments translated (:class:`TranslatedComments`), while the notebook
that runs is the English source, so the numbers stay the same. The cells a page never
shows (``remove-input``, ``remove-cell``: checks, figures) are in the notebook a reader
downloads all the same: their comments are read from the page's notebook source
(:func:`notebook_comment_texts`; the doctree has no source for them) into the catalogue
too, and the published notebook has them translated (rikin_book.translate_notebook).

And what makes the site around the pages speak the edition's language:

* the texts the site shows that no page's source has (:func:`site_messages`: the config's
  title, footer and search box; each fold button's text as myst-nb fills it in, "Show code
  cell source", "... outputs", and its label for screen readers; the theme's tooltips
  that its templates leave English; the book extension's preview banner and launch lines)
  go into the first page's catalogue, and a translated edition takes them from there
  (:func:`site_text`); the install cell's title and comment come from the exercises'
  catalogue, which has them for the exercise notebooks;
* the parts' captions of the sidebar ("Inverse kinematics"), which sphinx-external-toc
  adds after Sphinx translated the root page, are translated from its catalogue then;
* an image whose alt text Sphinx translated is marked translated (Sphinx 7 leaves it
  marked untranslated).

What cells print is not looked up in the catalogues (rikin prints its words in the
page's language, see ``rikin/i18n.py``). The Spanish build marks every text it found no
translation for with the class ``untranslated`` (``translation_progress_classes``), which
the tests look for.

And in a translated edition, a ``{download}`` of an exercise notebook
(``exercises/<arm>.ipynb``) offers that edition's notebook, ``exercises/<lang>/<arm>.ipynb``
(made by tools/make_exercises.py), when there is one: the catalogues keep the English
target, the reader gets the notebook in their language; its launch links (Colab, Binder)
name the edition's copy, ``es/_static/exercises/<arm>.ipynb`` (book/_ext/rikin_book.py).
"""

from __future__ import annotations

import gettext
import html
import re
import sys
from pathlib import Path
from typing import Any

from docutils import nodes
from myst_nb.core.read import is_myst_markdown_notebook, read_myst_markdown_notebook
from myst_nb.ext.glue.directives import PasteFigureDirective
from myst_nb.sphinx_ import HideCodeCellNode, depart_HideCellInput, visit_HideCellInput
from sphinx import addnodes
from sphinx import locale as sphinx_locale
from sphinx.application import Sphinx
from sphinx.locale import init as init_locale
from sphinx.transforms import SphinxTransform
from sphinx.transforms.post_transforms import SphinxPostTransform
from sphinx.util.i18n import docname_to_domain

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rikin_comments  # noqa: E402  (the code cells' comments, as messages)
import rikin_site  # noqa: E402  (the texts the book's extension writes on its pages)

#: The editions: language code -> (folder below the site root, the language's own name).
EDITIONS: dict[str, tuple[str, str]] = {"en": ("", "English"), "es": ("es/", "Español")}
#: The switch's tooltip, in the language of the edition it leads to (who wants that edition
#: reads that language).
SWITCH_TITLE = {"en": "Read this page in English", "es": "Lee esta página en español"}
#: The site's texts that the config gives, not a page (the title, the footer's author and
#: copyright, the search box): they, the fold buttons' texts and the book extension's
#: (:func:`site_messages`) go into the first page's catalogue in the gettext build, and a
#: translated edition takes them from its catalogues (:func:`translated_config`,
#: :func:`site_text`).
SITE_TEXTS = ("html_title", "author", "copyright", "search_bar_text")
#: The words myst-nb puts for ``{type}`` in the fold buttons' texts (``nb_code_prompt_show``
#: "Show code cell {type}", ``nb_code_prompt_hide``; myst_nb.sphinx_.HideInputCells): a
#: whole cell, its source, its output, its outputs. Each filled-in text is one message.
FOLD_TYPES = ("content", "source", "output", "outputs")
#: What myst-nb's fold button says to a screen reader (its ``aria-label``).
FOLD_LABEL = "Toggle hidden content"
#: The theme's words that its templates write untranslated (sphinx-book-theme 1.3's
#: sidebar buttons' tooltips, the sidebar's label for screen readers): the book's copies of
#: those templates (``templates/``) write ``rikin_text(...)`` of them (:func:`add_switch`).
THEME_TEXTS = ("Toggle primary sidebar", "Toggle secondary sidebar", "Main")
#: Texts that Sphinx and the theme translate themselves, from their own catalogues
#: (catalogue -> messages), some of them wrongly or not at all in Spanish (sphinx-book-theme
#: 1.3: "Descarga esta pagina" without its accent; Sphinx 7.4: "Link to this heading" left
#: English): they are site messages too, and a translated edition's catalogue translation
#: is looked up before theirs (:func:`correct_builtin_texts`).
BUILTIN_TEXTS: dict[str, tuple[str, ...]] = {
    "booktheme": ("Download this page", "Download source file", "Download notebook file",
                  "Print to PDF", "Fullscreen mode", "previous page", "next page"),
    "sphinx": ("Link to this heading", "Link to this image", "Link to this term",
               "Link to this table", "Link to this equation", "Link to this code",
               "Link to this definition"),
}
#: Where a translated edition keeps its site texts' translations (an attribute of the app).
SITE_STRINGS = "rikin_site_strings"
#: The exercises' catalogues (below the book's source folder), which also translate the
#: install cell of every notebook the book publishes (``rikin_site.INSTALL_TEXTS``).
EXERCISE_LOCALES = "solutions/locales"
#: The builder that extracts the messages (``tools/dev.py translations``).
GETTEXT = "gettext"
#: The template (in ``templates/``) that draws the switch in the article header.
SWITCH_TEMPLATE = "rikin-language-switch.html"
TEMPLATES = Path(__file__).resolve().parent / "templates"


def edition(language: str | None) -> str:
    """The edition a build makes: its language if the book has one in it, else English."""
    return language if language in EDITIONS else "en"


def page_url(pagename: str, here: str, there: str) -> str:
    """The relative URL, from page ``pagename`` of edition ``here``, of that page in ``there``.

    Parameters
    ----------
    pagename : str
        Sphinx's page name, e.g. ``"book/planar"`` (folders separated by ``/``).
    here, there : str
        Language codes of the edition showing the page and of the one linked to.
    """
    up = "../" * pagename.count("/")
    site_root = up + "../" * EDITIONS[here][0].count("/")
    return f"{site_root}{EDITIONS[there][0]}{pagename}.html"


def add_switch_template(app: Sphinx, config: Any) -> None:
    """Put the switch after the theme's own header buttons (download, full screen, ...);
    the book's templates first, before the themes' components (which they replace)."""
    config.templates_path = [str(TEMPLATES), *config.templates_path]
    options = dict(config.html_theme_options or {})
    end = options.get("article_header_end", "article-header-buttons.html")
    end = [end] if isinstance(end, str) else list(end)
    if SWITCH_TEMPLATE not in end:
        end.append(SWITCH_TEMPLATE)
    options["article_header_end"] = end
    config.html_theme_options = options


def add_switch(
    app: Sphinx, pagename: str, templatename: str, context: dict[str, Any], doctree: Any
) -> None:
    """Give the page's template the other editions' links (switch and hreflang), and
    ``rikin_text``, the site's texts in the edition's language (:func:`site_text`)."""
    if app.builder.format != "html":
        return
    context["rikin_text"] = lambda message: site_text(app, message)
    here = edition(app.config.language)
    others = [lang for lang in EDITIONS if lang != here]
    context["rikin_editions"] = [
        {"lang": lang, "name": EDITIONS[lang][1], "title": SWITCH_TITLE[lang],
         "url": page_url(pagename, here, lang)}
        for lang in others
    ]
    links = "".join(
        f'<link rel="alternate" hreflang="{e["lang"]}" href="{e["url"]}" />\n'
        for e in context["rikin_editions"]
    )
    context["metatags"] = context.get("metatags", "") + links


class ExercisesInLanguage(SphinxTransform):
    """``{download}`` of ``exercises/<name>.ipynb`` -> ``exercises/<lang>/<name>.ipynb``.

    Runs after Sphinx's translation of the page (priority 20) and before the download
    files are collected (the ``doctree-read`` event), in an edition other than English.
    """

    default_priority = 800

    def apply(self, **kwargs: Any) -> None:
        lang = edition(self.config.language)
        if lang == "en":
            return
        here = Path(self.env.doc2path(self.env.docname)).parent
        for node in self.document.findall(addnodes.download_reference):
            target = str(node.get("reftarget", ""))
            folder, _, name = target.rpartition("/")
            if not name.endswith(".ipynb") or folder.rsplit("/", 1)[-1] != "exercises":
                continue
            translated = f"{folder}/{lang}/{name}"
            base = Path(self.env.srcdir) if translated.startswith("/") else here
            if (base / translated.lstrip("/")).is_file():
                node["reftarget"] = translated


class late_texts(nodes.Element, addnodes.translatable):
    """Texts of a figure that a page shows only after its notebook ran, in the gettext build.

    ``self["messages"]`` are the messages, as Sphinx's ``Locale`` transform looks them up in
    the executed build (:func:`caption_messages`, an alt text as it is). The node exists
    only in the doctrees of the gettext builder, which renders none.
    """

    def preserve_original_messages(self) -> None:
        pass

    def apply_translated_message(self, original_message: str, translated_message: str) -> None:
        pass

    def extract_original_messages(self) -> list[str]:
        return list(self["messages"])


def caption_messages(text: str) -> list[str]:
    """The messages of a caption written in markdown: one per paragraph, lines joined by spaces.

    The same as Sphinx extracts from the caption (and legend) paragraphs MyST makes of
    ``text`` (a paragraph's source with its newlines replaced by spaces).
    """
    paragraphs: list[list[str]] = [[]]
    for line in text.strip().splitlines():
        if line.strip():
            paragraphs[-1].append(line)
        elif paragraphs[-1]:
            paragraphs.append([])
    # a paragraph's source keeps the inner lines' indentation, not its ends' whitespace
    return [" ".join(p).strip() for p in paragraphs if p]


def cell_texts(metadata: Any) -> list[str]:
    """A code cell's figure caption and image alt text (myst-nb cell metadata), as messages."""
    mystnb = metadata.get("mystnb") if isinstance(metadata, dict) else None
    if not isinstance(mystnb, dict):
        return []
    figure, image = mystnb.get("figure") or {}, mystnb.get("image") or {}
    texts = caption_messages(str(figure.get("caption") or ""))
    alt = str(image.get("alt") or "").strip()
    return texts + ([alt] if alt else [])


def _late_node(messages: list[str], source: str, line: int | None) -> late_texts:
    node = late_texts(messages=messages)
    node.source, node.line = source, line
    return node


class ExtractCellTexts(SphinxTransform):
    """In the gettext build, give each code cell's caption and alt text to the catalogue
    (and the site's texts, :data:`SITE_TEXTS`, to the first page's)."""

    default_priority = 15  # before Locale (20) and the UIDs the gettext builder needs (880)

    def apply(self, **kwargs: Any) -> None:
        if self.app.builder.name != GETTEXT:
            return
        if self.env.docname == self.config.root_doc:
            self.document += _late_node(site_messages(self.config), self.document["source"],
                                        None)
        for cell in list(self.document.findall(nodes.container)):
            if cell.get("nb_element") != "cell_code":
                continue
            texts = cell_texts(cell.get("cell_metadata")) + comment_texts(cell)
            if texts:
                cell += _late_node(texts, self.document["source"], cell.line)
        # the comments of the cells the page does not show (remove-input, remove-cell):
        # the doctree has no source for them, the notebook a reader downloads has
        shown = {text for cell in self.document.findall(nodes.container)
                 if cell.get("nb_element") == "cell_code" for text in comment_texts(cell)}
        for line, texts in notebook_comment_texts(Path(self.document["source"])):
            hidden = [text for text in texts if text not in shown]
            if hidden:
                self.document += _late_node(hidden, self.document["source"], line)


def _shown_sources(cell: nodes.Element) -> list[nodes.literal_block]:
    """The literal blocks that show a code cell's source (none when its input is removed)."""
    return [block for source in cell.findall(nodes.container)
            if source.get("nb_element") == "cell_code_source"
            for block in source.findall(nodes.literal_block)]


def comment_texts(cell: nodes.Element) -> list[str]:
    """The messages of the comments a code cell shows (rikin_comments.code_comments)."""
    return [c.text for block in _shown_sources(cell)
            for c in rikin_comments.code_comments(block.astext())]


def notebook_comment_texts(path: Path) -> list[tuple[int | None, list[str]]]:
    """The comments of every code cell of the MyST notebook at ``path``, shown or not, as
    messages (rikin_comments.code_comments): (the cell's first line, its messages) for each
    cell with one; none when ``path`` is not a notebook (a page without code cells).

    A translated edition's downloaded notebook has every cell, also those its page never
    shows (``remove-input``, ``remove-cell``), whose source the page's doctree lacks."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError:
        return []
    if not is_myst_markdown_notebook(text):
        return []
    nb = read_myst_markdown_notebook(text, add_source_map=True, path=path)
    lines = list(nb.metadata.get("source_map") or [])
    found = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        texts = [c.text for c in rikin_comments.code_comments(cell.source)]
        if texts:
            found.append((lines[i] if i < len(lines) else None, texts))  # its fence, 1-based
    return found


def _has_message(catalogue: gettext.NullTranslations | None, message: str) -> bool:
    """Whether ``catalogue`` (or one it falls back on) translates ``message``, also when
    its translation is the message itself (a comment that is a formula, ``# q5 = 0``)."""
    while catalogue is not None:
        if getattr(catalogue, "_catalog", {}).get(message):
            return True
        catalogue = getattr(catalogue, "_fallback", None)
    return False


class TranslatedComments(SphinxTransform):
    """In a translated edition, each code cell shows its comments in the edition's language.

    Only the literal block that shows the cell's source changes (the notebook that ran is
    the English source, so the numbers are the same); a cell with a comment the catalogue
    does not translate keeps it and is marked ``untranslated`` (what the tests look for).
    """

    default_priority = 21  # after Locale (20), which loads the page's catalogue

    def apply(self, **kwargs: Any) -> None:
        if edition(self.config.language) == "en" or self.app.builder.name == GETTEXT:
            return
        catalogue, _ = page_catalogue(self.app, self.env.docname)

        def translate(message: str) -> str | None:
            return catalogue.gettext(message) if _has_message(catalogue, message) else None

        for block in list(self.document.findall(nodes.literal_block)):
            parent = block.parent
            if parent is None or parent.get("nb_element") != "cell_code_source":
                continue
            text, missing = rikin_comments.translated_source(block.astext(), translate)
            if text == block.astext() and not missing:
                continue
            shown = nodes.literal_block(text, text, **block.attributes)
            shown.source, shown.line = block.source, block.line
            if missing:
                shown["classes"] = [*shown["classes"], "untranslated"]
            parent.replace(block, shown)


class GlueFigure(PasteFigureDirective):
    """myst-nb's ``glue:figure``; in the gettext build its caption and alt text are extracted
    even though no notebook ran (the glued output is missing there)."""

    def run(self) -> list[nodes.Node]:
        result = super().run()
        env = getattr(self.state.document.settings, "env", None)
        if env is None or env.app.builder.name != GETTEXT:
            return result
        texts = caption_messages("\n".join(self.content))
        alt = str(self.options.get("alt") or "").strip()
        source, line = self.state_machine.get_source_and_line(self.lineno)
        return [*result, _late_node(texts + ([alt] if alt else []), source or "", line)]


def site_texts(config: Any) -> dict[str, str]:
    """The config's :data:`SITE_TEXTS` (the search box's is a theme option)."""
    options = config.html_theme_options or {}
    values = {"html_title": config.html_title, "author": config.author,
              "copyright": config.copyright, "search_bar_text": options.get("search_bar_text")}
    return {name: str(values[name] or "") for name in SITE_TEXTS}


def fold_texts(config: Any) -> list[str]:
    """What the fold buttons say, each ``{type}`` (:data:`FOLD_TYPES`) filled in as myst-nb
    does: "Show code cell source", "Hide code cell outputs", ..."""
    prompts = (config.nb_code_prompt_show, config.nb_code_prompt_hide)
    return [str(prompt).replace("{type}", kind) for prompt in prompts for kind in FOLD_TYPES]


def site_messages(config: Any) -> list[str]:
    """Every text the site shows that no page's source has, as a message: the config's
    (:func:`site_texts`), the fold buttons' (:func:`fold_texts`, :data:`FOLD_LABEL`), the
    theme's untranslated ones (:data:`THEME_TEXTS`), and what the book's extension writes
    on pages (the preview banner, the launch lines:
    ``rikin_site.PAGE_TEXTS``, some with ``{placeholders}``)."""
    texts = [*site_texts(config).values(), *fold_texts(config), FOLD_LABEL, *THEME_TEXTS,
             *[m for messages in BUILTIN_TEXTS.values() for m in messages],
             *rikin_site.PAGE_TEXTS]
    return [t for t in dict.fromkeys(texts) if t]


def all_site_messages(config: Any) -> list[str]:
    """:func:`site_messages` and the install cell's (``rikin_site.INSTALL_TEXTS``, whose
    translations are the exercises' catalogue's)."""
    return [*site_messages(config), *rikin_site.INSTALL_TEXTS]


def site_text(app: Sphinx, message: str, **values: str) -> str:
    """``message`` (one of :func:`site_messages`, or of the install cell's
    ``rikin_site.INSTALL_TEXTS``) in the edition's language, its ``{placeholders}`` filled
    in with ``values``."""
    text = getattr(app, SITE_STRINGS, {}).get(message, message)
    return text.format(**values) if values else text


def catalogue_strings(folders: list[Path], language: str) -> dict[str, str]:
    """Every translated, not fuzzy message of ``language`` in the catalogue ``folders``."""
    from babel.messages.pofile import read_po

    strings: dict[str, str] = {}
    for folder in folders:
        for po in sorted((folder / language / "LC_MESSAGES").rglob("*.po")):
            with po.open("rb") as f:
                for m in read_po(f):
                    if isinstance(m.id, str) and m.id and m.string and not m.fuzzy:
                        strings.setdefault(m.id, str(m.string))
    return strings


def translated_config(app: Sphinx, config: Any) -> None:
    """A translated edition: the site's texts (:func:`site_messages`) as its catalogues
    translate them (the title, footer and search box set here in the config, the others
    looked up by :func:`site_text`), and each text of a page it has no translation for
    marked (class ``untranslated``, which the tests look for)."""
    language = edition(config.language)
    if language == "en":
        config.rikin_site_translations = [(m, m) for m in all_site_messages(config)]
        return
    config.translation_progress_classes = "untranslated"
    strings = catalogue_strings([Path(app.srcdir) / d for d in config.locale_dirs], language)
    exercises = catalogue_strings([Path(app.srcdir) / EXERCISE_LOCALES], language)
    found = {m: strings[m] for m in site_messages(config) if m in strings}
    found |= {m: exercises[m] for m in rikin_site.INSTALL_TEXTS if m in exercises}
    setattr(app, SITE_STRINGS, found)
    # a config value of the html build: a changed site text or translation rewrites every
    # page, also in an incremental build (tools/dev.py book --cached), which rewrites only
    # the pages whose source changed
    config.rikin_site_translations = [(m, found.get(m, m)) for m in all_site_messages(config)]
    texts = {name: strings.get(text, text) for name, text in site_texts(config).items()}
    config.html_title, config.copyright = texts["html_title"], texts["copyright"]
    config.author = texts["author"]
    if texts["search_bar_text"]:
        config.html_theme_options = {**(config.html_theme_options or {}),
                                     "search_bar_text": texts["search_bar_text"]}


class _Corrected(gettext.NullTranslations):
    """A gettext catalogue that says ``strings`` (message -> translation) first, and asks
    ``fallback`` (Sphinx's or the theme's own catalogue) for every other message."""

    def __init__(self, strings: dict[str, str], fallback: gettext.NullTranslations) -> None:
        super().__init__()
        self.strings = strings
        self.add_fallback(fallback)

    def gettext(self, message: str) -> str:
        return self.strings.get(message) or super().gettext(message)


def correct_builtin_texts(app: Sphinx, *args: Any) -> None:
    """In a translated edition, put the site catalogue's translations of
    :data:`BUILTIN_TEXTS` before Sphinx's and the theme's own (which, lazily, look their
    messages up when a page is written: the theme's buttons, Sphinx's ``¶`` tooltips).
    Idempotent: a catalogue is replaced once."""
    strings = getattr(app, SITE_STRINGS, {})
    for catalogue, messages in BUILTIN_TEXTS.items():
        key = ("general", catalogue)
        current = sphinx_locale.translators.get(key, gettext.NullTranslations())
        if isinstance(current, _Corrected):
            continue
        ours = {m: strings[m] for m in messages if strings.get(m, m) != m}
        if ours:
            sphinx_locale.translators[key] = _Corrected(ours, current)


class TranslatedFolds(SphinxPostTransform):
    """The fold buttons' texts in the edition's language (:func:`fold_texts`).

    myst-nb fills ``{type}`` of ``nb_code_prompt_show`` with an English word when it folds
    a cell (after the page was translated), so each filled-in text is its own message."""

    default_priority = 200  # after myst-nb's HideInputCells (199), which writes them
    formats = ("html",)

    def run(self, **kwargs: Any) -> None:
        for node in self.document.findall(HideCodeCellNode):
            for key in ("prompt_show", "prompt_hide"):
                node[key] = site_text(self.app, str(node[key]))


def visit_fold(self: Any, node: HideCodeCellNode) -> None:
    """myst-nb's fold button, its label for screen readers (:data:`FOLD_LABEL`) translated."""
    start = len(self.body)
    visit_HideCellInput(self, node)
    label = html.escape(site_text(self.builder.app, FOLD_LABEL))
    self.body[start:] = [part.replace(f'aria-label="{FOLD_LABEL}"', f'aria-label="{label}"')
                         for part in self.body[start:]]


class TranslatedPartCaptions(SphinxTransform):
    """The captions of the book's parts ("Inverse kinematics", the sidebar's headings) from
    the page's catalogue: sphinx-external-toc adds the toctrees that carry them after
    Sphinx translated the page (the gettext build extracts them all the same)."""

    default_priority = 101  # after sphinx-external-toc's InsertToctrees (100)

    def apply(self, **kwargs: Any) -> None:
        if edition(self.config.language) == "en" or self.app.builder.name == GETTEXT:
            return
        catalogue, found = page_catalogue(self.app, self.env.docname)
        for node in self.document.findall(addnodes.toctree):
            caption = node.get("rawcaption") or node.get("caption")
            translated = catalogue.gettext(caption) if found and caption else caption
            if caption and translated != caption:
                node["rawcaption"] = caption
                node.apply_translated_message(caption, translated)


#: The attribute an image keeps its alt text in while Sphinx translates the page.
ORIGINAL_ALT = "rikin_original_alt"


class RememberAlt(SphinxTransform):
    """Before Sphinx translates the page: each image's alt text as written."""

    default_priority = 19  # before Locale (20)

    def apply(self, **kwargs: Any) -> None:
        for node in self.document.findall(nodes.image):
            if node.get("alt"):
                node[ORIGINAL_ALT] = node["alt"]


class MarkAltTranslated(SphinxTransform):
    """An image whose alt text Sphinx's ``Locale`` looked up and replaced by its translation
    marked translated: Sphinx 7 replaces it but leaves the image marked not translated, so
    it would show with the class ``untranslated``. An alt text not found stays marked."""

    default_priority = 21  # after Locale (20), before the translation progress (25, 950)

    def apply(self, **kwargs: Any) -> None:
        for node in self.document.findall(nodes.image):
            original = node.attributes.pop(ORIGINAL_ALT, None)
            if (original is not None and node.get("translated") is False
                    and node.get("alt") != original):
                node["translated"] = True


#: A markdown line that starts a list item (its marker, then its text).
_ITEM = re.compile(r"^(?P<marker>[ ]{0,3}(?:[-*+]|\d+[.)])[ ]+)(?P<text>\S.*)$")
_HEADING = re.compile(r"^(?P<marker>#{1,6}[ ]+)(?P<text>.+?)[ ]*$")
_TARGET = re.compile(r"^\s*\([^()\s]+\)=\s*$")
#: The opening line of a fenced block: a directive (``{name}``, its argument) or code.
_FENCE = re.compile(r"^(?P<indent>[ ]{0,3})(?P<fence>`{3,}|~{3,}|:{3,})"
                    r"(?:\{(?P<name>[\w:.-]+)\}[ \t]*(?P<arg>.*?)|[^`{]*?)\s*$")
#: Directives whose body is not prose (kept as they are).
_VERBATIM = ("code", "code-block", "code-cell", "math", "sourcecode", "raw", "glue:figure",
             "figure", "image", "toctree", "literalinclude", "tableofcontents")


def _message_of(lines: list[str]) -> list[str]:
    """The ways Sphinx may have written the message of a paragraph of ``lines``: its
    source with newlines as spaces (inner indentation kept), or each line stripped."""
    kept = " ".join(lines).strip()
    return list(dict.fromkeys([kept, " ".join(line.strip() for line in lines)]))


def _translated_block(lines: list[str], lookup: Any) -> list[str]:
    """One block of markdown (no blank line, no fence) in the catalogue's language: a
    heading, a list (each item), or a paragraph; as it is when a part is not found."""
    heading = _HEADING.match(lines[0])
    if heading and len(lines) == 1:
        found = lookup([heading["text"]])
        return [heading["marker"] + found] if found else lines
    if lines[0].lstrip().startswith(("|", "$$", "<")):
        return lines
    if _ITEM.match(lines[0]):
        items: list[tuple[str, list[str]]] = []
        for line in lines:
            m = _ITEM.match(line)
            if m:
                items.append((m["marker"], [m["text"]]))
            else:
                items[-1][1].append(line)
        out = []
        for marker, text in items:
            found = lookup(_message_of(text))
            out += [marker + found] if found else [marker + text[0], *text[1:]]
        return out
    found = lookup(_message_of(lines))
    return [found] if found else lines


def translate_markdown(text: str, lookup: Any) -> str:
    """A markdown cell of a page in the catalogue's language, block by block.

    ``lookup(messages)`` is the translation of the first of ``messages`` the catalogue has,
    or None. Headings, paragraphs, list items and a directive's argument and body are
    looked up as Sphinx extracted them; code, maths, tables and HTML stay as they are, and
    so does a block the catalogue does not have."""
    out: list[str] = []
    block: list[str] = []
    lines = text.split("\n")
    i = 0
    while i <= len(lines):
        line = lines[i] if i < len(lines) else ""
        fence = _FENCE.match(line) if i < len(lines) else None
        if fence or not line.strip():
            out += _translated_block(block, lookup) if block else []
            block = []
        if fence:
            end = next((j for j in range(i + 1, len(lines))
                        if lines[j].strip() == fence["fence"]), len(lines))
            name, arg = fence["name"], fence["arg"]
            if name is None or name in _VERBATIM:
                out += lines[i:end + 1]
            else:
                found = lookup([arg]) if arg else None
                out.append(line.replace(arg, found) if found else line)
                body = lines[i + 1:end]
                options = [b for b in body if re.match(r"^:[\w-]+:", b)]
                rest = "\n".join(body[len(options):])
                out += options + translate_markdown(rest, lookup).split("\n")
                out += lines[end:end + 1]
            i = end + 1
            continue
        if _HEADING.match(line) or _TARGET.match(line):  # a block of one line
            out += _translated_block(block, lookup) if block else []
            out += _translated_block([line], lookup)
            block = []
        elif line.strip():
            block.append(line)
        elif i < len(lines):
            out.append(line)
        i += 1
    return "\n".join(out)


def page_catalogue(app: Sphinx, docname: str) -> tuple[Any, bool]:
    """The gettext catalogue of page ``docname`` in the edition's language (one ``.po``
    per page, ``gettext_compact: false``), and whether one was found."""
    dirs = [str(Path(app.srcdir) / d) for d in app.config.locale_dirs]
    domain = docname_to_domain(docname, app.config.gettext_compact)
    return init_locale(dirs, app.config.language, domain)


def page_lookup(app: Sphinx, docname: str) -> Any:
    """The translation of a message of page ``docname`` in the edition's language, as
    :func:`translate_markdown` wants it; None in the English edition."""
    if edition(app.config.language) == "en":
        return None
    catalogue, found = page_catalogue(app, docname)
    if not found:
        return None

    def lookup(messages: list[str]) -> str | None:
        for message in messages:
            translated = catalogue.gettext(message)
            if message and translated != message:
                return translated
        return None

    return lookup


class KeepCellOutputs(SphinxTransform):
    """What a cell printed is not looked up in the catalogues (it is not in them: it exists
    only once the notebook ran, in the language rikin prints in, see rikin.i18n); marked
    so, a Markdown output is neither translated nor reported untranslated. A figure's
    caption and legend, which myst-nb puts in the output too but takes from the cell's
    metadata (``mystnb: figure: caption``), are in the catalogue and are translated."""

    default_priority = 15  # before Locale (20)

    def apply(self, **kwargs: Any) -> None:
        for output in self.document.findall(nodes.container):
            if output.get("nb_element") != "cell_code_output":
                continue
            for node in output.findall(nodes.TextElement):
                if not _in_caption(node):
                    node["translatable"] = False


def _in_caption(node: nodes.Node | None) -> bool:
    """``node`` is, or is inside, a figure's caption or legend."""
    while node is not None:
        if isinstance(node, (nodes.caption, nodes.legend)):
            return True
        node = node.parent
    return False


def setup(app: Sphinx) -> dict[str, Any]:
    app.setup_extension("myst_nb")  # its glue domain first: GlueFigure replaces a directive
    app.add_node(late_texts)
    app.add_config_value("rikin_site_translations", [], "html")
    app.add_transform(ExtractCellTexts)
    app.add_transform(KeepCellOutputs)
    app.add_transform(ExercisesInLanguage)
    app.add_transform(TranslatedPartCaptions)
    app.add_transform(RememberAlt)
    app.add_transform(MarkAltTranslated)
    app.add_transform(TranslatedComments)
    app.add_post_transform(TranslatedFolds)
    app.add_node(HideCodeCellNode, override=True, html=(visit_fold, depart_HideCellInput))
    app.add_directive_to_domain("glue", "figure", GlueFigure, override=True)
    app.connect("config-inited", add_switch_template)
    app.connect("config-inited", translated_config)
    app.connect("html-page-context", add_switch)
    # once the builder (and so the theme) is set up, before a page is written; and again
    # before the theme's buttons of each page, should a catalogue have been loaded since
    app.connect("builder-inited", correct_builtin_texts)
    app.connect("html-page-context", correct_builtin_texts, priority=100)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
