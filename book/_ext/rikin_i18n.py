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

And in a translated edition, a ``{download}`` of an exercise notebook
(``exercises/<arm>.ipynb``) offers that edition's notebook, ``exercises/<lang>/<arm>.ipynb``
(made by tools/make_exercises.py), when there is one: the catalogues keep the English
target, the reader gets the notebook in their language.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from sphinx import addnodes
from sphinx.application import Sphinx
from sphinx.transforms import SphinxTransform

#: The editions: language code -> (folder below the site root, the language's own name).
EDITIONS: dict[str, tuple[str, str]] = {"en": ("", "English"), "es": ("es/", "Español")}
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
    """Put the switch after the theme's own header buttons (download, full screen, ...)."""
    config.templates_path = [*config.templates_path, str(TEMPLATES)]
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
    """Give the page's template the other editions' links (switch and hreflang)."""
    if app.builder.format != "html":
        return
    here = edition(app.config.language)
    others = [lang for lang in EDITIONS if lang != here]
    context["rikin_editions"] = [
        {"lang": lang, "name": EDITIONS[lang][1], "url": page_url(pagename, here, lang)}
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


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_transform(ExercisesInLanguage)
    app.connect("config-inited", add_switch_template)
    app.connect("html-page-context", add_switch)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
