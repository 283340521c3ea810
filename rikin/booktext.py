"""The book's own sentences in the reader's language: the ✓ lines, table headers and figure
words that the chapters' code cells print.

A chapter writes each such text in English as a template with named values, and the
values are put in by :meth:`str.format` in every language, so the numbers read the same
in both editions::

    ok("both reach the target (largest difference {err:.1e})", err=gap(A, B))
    show_table(["joint", "limits (°)"], rows)
    ax.set_title(tr("joint space"))

The English template is the message. :func:`page_messages` finds the messages of a page
(the literal first argument of every ``ok(...)`` and ``tr(...)`` call, and the texts of the
header list of every ``show_table(...)``, in the page's code cells) and ``python3
tools/dev.py translations`` writes them into one gettext catalogue per language,
``book/locales/<lang>/LC_MESSAGES/cells.po``. A cell run in another language
(:func:`rikin.i18n.language`, ``RIKIN_LANG=es`` in the Spanish build) shows the translation
of each template instead, read from that catalogue by :class:`BookText`. English is shown
where there is no catalogue, no entry, or an empty or fuzzy one. rikin's own words (branch
names, ``rikin.tables``' headers) are translated by :mod:`rikin.i18n`, not here.

A chapter's notebook downloaded alone has no ``locales`` folder beside it: the book puts
the translations its cells use into its (folded) install cell, which hands them to
:func:`add_translations`; a :class:`BookText` whose catalogue is missing reads those.

Examples
--------
>>> from rikin.booktext import BookText
>>> text = BookText("no-such-folder")     # no catalogue: English as written
>>> text.tr("the gap is {gap:.1e}", gap=1.5e-12)
'the gap is 1.5e-12'
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator, Sequence
from pathlib import Path

from .errors import InputError
from .i18n import LANGUAGES, language

__all__ = ["BookText", "add_translations", "cell_messages", "page_messages", "read_catalogue"]

#: The catalogue of one language below a book's ``locales`` folder.
CATALOGUE = "{lang}/LC_MESSAGES/cells.po"
#: Calls whose first argument (a string literal) is a message.
MESSAGE_FUNCTIONS = ("ok", "tr")
#: Calls whose first argument (a list of string literals) is a table header.
HEADER_FUNCTIONS = ("show_table",)
#: A header text is a message when it has a word in it ("joint", "TCP error (m)"); a
#: symbol or a variable's name alone ("#", "d", "θ3", "q1 (°)") is the same in every language.
WORD = re.compile(r"[A-Za-z]{2,}")
#: A ``{placeholder}`` of a template (``{{`` and ``}}`` are literal braces).
PLACEHOLDER = re.compile(r"(?<!\{)\{([^{}]*)\}(?!\})")
#: A code cell of a MyST notebook page: its options and source.
CODE_CELL = re.compile(r"^```\{code-cell\}[^\n]*\n(.*?)^```", re.S | re.M)

#: Translations handed over without a catalogue (:func:`add_translations`): language ->
#: English template -> translation.
_GIVEN: dict[str, dict[str, str]] = {}


def add_translations(lang: str, texts: dict[str, str]) -> None:
    """Translations of cell texts into ``lang`` for every :class:`BookText` that finds no
    catalogue of ``lang`` (a notebook downloaded from the book, run outside it).

    Parameters
    ----------
    lang : str
        A language of :data:`rikin.i18n.LANGUAGES` other than English.
    texts : dict of str to str
        English template -> its translation (the same ``{placeholders}``).

    Examples
    --------
    >>> add_translations("es", {"the gap is {gap:.1e}": "la diferencia es {gap:.1e}"})
    >>> from rikin.i18n import set_language
    >>> set_language("es")
    >>> BookText("no-such-folder").tr("the gap is {gap:.1e}", gap=1.5e-12)
    'la diferencia es 1.5e-12'
    >>> set_language("en")
    """
    if lang not in LANGUAGES or lang == "en":
        raise InputError(f"lang must be one of {[x for x in LANGUAGES if x != 'en']}, "
                         f"got {lang!r:.80}")
    if not isinstance(texts, dict) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in texts.items()):
        raise InputError("texts must be a dict of English template -> translation (str -> str)")
    for english, said in texts.items():
        if _placeholders(said) != _placeholders(english):
            raise InputError(f"the translation of {english!r:.80} has other "
                             f"{{placeholders}}: {said!r:.80}")
    _GIVEN.setdefault(lang, {}).update(texts)


class BookText:
    """The translations of one book's cell texts, in the language rikin prints in.

    Parameters
    ----------
    locales : str or Path
        The book's ``locales`` folder (relative to the current folder: a chapter's
        kernel starts in the chapter's folder); its catalogue of language ``lang`` is
        ``locales/<lang>/LC_MESSAGES/cells.po``.

    Notes
    -----
    The language is looked up at every call (:func:`rikin.i18n.language`), so
    :func:`rikin.i18n.set_language` takes effect at once; each catalogue is read once.
    """

    def __init__(self, locales: str | Path = "locales") -> None:
        if not isinstance(locales, (str, Path)):
            raise InputError(f"locales must be a folder (str or Path), got {locales!r:.80}")
        self.locales = Path(locales).resolve()
        self._read: dict[str, dict[str, str]] = {}

    def translations(self, lang: str | None = None) -> dict[str, str]:
        """English template -> translation, for ``lang`` (default: the current language);
        empty for English; where the language has no catalogue, those given by
        :func:`add_translations` (empty if none)."""
        lang = language() if lang is None else lang
        if lang == "en":
            return {}
        if lang not in self._read:
            path = self.locales / CATALOGUE.format(lang=lang)
            if not path.is_file():
                return _GIVEN.get(lang, {})
            self._read[lang] = read_catalogue(path)
        return self._read[lang]

    def tr(self, template: str, **values: object) -> str:
        """``template`` in the current language with ``values`` put into its placeholders
        (formatted as the template says, the same in every language)."""
        if not isinstance(template, str):
            raise InputError(f"template must be a str, got {template!r:.80}")
        text = self.translations().get(template, template)
        if _placeholders(text) != _placeholders(template):
            raise InputError(f"the {language()!r} catalogue in {self.locales} translates "
                             f"{template!r:.80} with other {{placeholders}}: {text!r:.80}")
        return text.format(**values) if values else text

    def header(self, names: Sequence[str]) -> list[str]:
        """A table header in the current language, text by text."""
        return [self.tr(name) if isinstance(name, str) else name for name in names]


def _placeholders(text: str) -> list[str]:
    return sorted(PLACEHOLDER.findall(text))


def read_catalogue(path: str | Path) -> dict[str, str]:
    """The translated entries of a gettext catalogue (``.po``): msgid -> msgstr.

    Read by Babel (which Sphinx, and so the book's build, depends on). Entries marked
    ``fuzzy``, with an empty translation, with a context or plural forms are left out (an
    English template is then shown as it is).
    """
    from babel.messages.pofile import read_po  # only a book with catalogues needs it

    with Path(path).open("rb") as po:
        catalogue = read_po(po)
    return {m.id: m.string for m in catalogue
            if isinstance(m.id, str) and m.id and isinstance(m.string, str) and m.string
            and not m.fuzzy and m.context is None}


# ----------------------------------------------------------------------------- extraction
def _literal(node: ast.expr | None, what: str, lineno: int) -> str:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    raise InputError(f"line {lineno}: the first argument of {what}(...) must be a string "
                     "literal (a template with named values, not an f-string)")


def cell_messages(source: str) -> list[tuple[int, str]]:
    """The messages of one code cell's source: (line, template), in the order written.

    IPython's ``%magic`` and ``!shell`` lines are skipped. A message function called with
    a variable (``tr(h)`` inside ``show_table``) translates a text written elsewhere and
    is passed over; with any other expression (an f-string, a sum of strings) it is an
    :class:`~rikin.errors.InputError`: its text could not be translated.
    """
    python = "\n".join("" if line.lstrip().startswith(("%", "!")) else line
                       for line in source.split("\n"))
    found: list[tuple[int, int, str]] = []
    for node in ast.walk(ast.parse(python)):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
            continue
        first = node.args[0] if node.args else None
        if node.func.id in MESSAGE_FUNCTIONS and isinstance(first, ast.Name):
            continue
        if node.func.id in MESSAGE_FUNCTIONS:
            found.append((node.lineno, node.col_offset,
                          _literal(first, node.func.id, node.lineno)))
        elif node.func.id in HEADER_FUNCTIONS:
            if not isinstance(first, (ast.List, ast.Tuple)):
                raise InputError(f"line {node.lineno}: the header of {node.func.id}(...) must "
                                 "be a list of string literals")
            for item in first.elts:
                text = _literal(item, f"{node.func.id}'s header", node.lineno)
                if WORD.search(text):
                    found.append((item.lineno, item.col_offset, text))
    return [(line, text) for line, _, text in sorted(found)]


def _cell_code(cell: str) -> tuple[int, str]:
    """(lines of options, code) of a code cell's text: options are ``:key: value`` lines
    or a YAML block between ``---`` lines."""
    if cell.startswith("---\n"):
        head, _, code = cell[4:].partition("\n---\n")
        return head.count("\n") + 3, code
    lines = cell.split("\n")
    n = 0
    while n < len(lines) and lines[n].startswith(":"):
        n += 1
    return n, "\n".join(lines[n:])


def page_messages(text: str) -> Iterator[tuple[int, str]]:
    """The messages of a MyST notebook page (the text of ``book/X.md``): (line in the
    page, template), cell by cell."""
    for m in CODE_CELL.finditer(text):
        start = text.count("\n", 0, m.start(1)) + 1
        skipped, code = _cell_code(m.group(1))
        try:
            found = cell_messages(code)
        except (InputError, SyntaxError) as exc:
            raise InputError(f"the code cell at line {start}: {exc}") from None
        for line, message in found:
            yield start + skipped + line - 1, message
