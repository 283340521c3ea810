"""The exercise notebooks in other languages: one gettext catalogue, from the one source.

``tools/make_exercises.py`` imports this module. The solution notebooks (``solutions/*.ipynb``)
and ``tools/exercise_checks.py`` are written in English; their translatable text is
extracted into one catalogue per language, ``solutions/locales/<lang>/LC_MESSAGES/
exercises.po`` (Babel, the library the book's catalogues are written with), and a
notebook in that language is the English one with every message replaced by its
translation:

* **markdown cells**: each block (a paragraph, a list, a table, a heading; blocks are
  separated by blank lines; the solution markers ``<!-- BEGIN/END SOLUTION -->`` are never
  translated) is one message;
* **code cells** with words in them (a comment, a docstring, a label such as
  ``"elbow right (q2 > 0)"``): the whole cell is one message, and its translation must be
  the same code (:func:`same_code`: the same syntax tree, names, numbers and short
  strings; only comments and strings with spaces may differ), so one grader grades
  either language;
* **the shared cells** (``exercise_checks.py``): the ``#@title`` lines, and the messages
  the checks print, written there as ``_t("... {name} ...", name=...)``; the translated
  cell has the translated text in place of each ``_t`` literal (same ``{placeholders}``).

A message with no translation, or one marked fuzzy (its English changed after it was
translated), stops the translated notebook from being made: :class:`Untranslated`.
"""

from __future__ import annotations

import ast
import copy
import io
import re
import tokenize
from collections.abc import Iterator
from pathlib import Path

from babel.messages.catalog import Catalog
from babel.messages.pofile import read_po, write_po

#: The languages the exercises are made in besides English.
LANGUAGES = ("es",)
#: The catalogue of one language, below the solutions folder.
CATALOGUE = "locales/{lang}/LC_MESSAGES/exercises.po"
#: The shared cells' message function (in tools/exercise_checks.py).
MESSAGE_FUNCTION = "_t"
#: The grader's message functions (rikingrade.i18n): translate, and mark for translation.
GRADER_FUNCTIONS = ("t", "N_")
#: The grader's catalogue of one language, below its package (grader/rikingrade/).
GRADER_CATALOGUE = "locales/{lang}/LC_MESSAGES/rikingrade.po"

MARKER = re.compile(r"^\s*<!-- (?:BEGIN|END) SOLUTION -->\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")
WORD = re.compile(r"[A-Za-z]{3,}")
PLACEHOLDER = re.compile(r"(?<!\{)\{([^{}]*)\}(?!\})")
CODE_SPAN = re.compile(r"`[^`\n]+`")
TITLE = re.compile(r"^#@title (.*)$", re.M)


class Untranslated(Exception):
    """A translated notebook cannot be made: messages without a current translation."""

    def __init__(self, lang: str, missing: list[str]) -> None:
        self.lang = lang
        self.missing = missing
        shown = "\n".join(f"  {m[:90]!r}" for m in missing[:8])
        more = f"\n  ... and {len(missing) - 8} more" if len(missing) > 8 else ""
        super().__init__(f"{len(missing)} message(s) without a current '{lang}' translation "
                         f"(empty or fuzzy):\n{shown}{more}")


class BadTranslation(Exception):
    """A translation changes what must stay the same (code, placeholders, inline code)."""


# ----------------------------------------------------------------------------- extraction
def _words(text: str) -> bool:
    """Whether ``text`` has words to translate (outside maths and inline code)."""
    bare = re.sub(r"\$\$.*?\$\$|\$[^$]*\$|`[^`]*`|\(attachment:[^)]*\)", " ", text, flags=re.S)
    return bool(WORD.search(bare))


def markdown_pieces(source: str) -> list[tuple[str, bool]]:
    """A markdown cell as (text, translatable) pieces; joining them with "\\n" gives it back.

    A translatable piece is a block of lines (a paragraph, list, table, heading or fenced
    block) with words in it; blank lines and the solution markers are pieces of their own.
    """
    pieces: list[tuple[str, bool]] = []
    block: list[str] = []
    fence = None

    def flush() -> None:
        if block:
            text = "\n".join(block)
            pieces.append((text, _words(text)))
            block.clear()

    for line in source.split("\n"):
        m = FENCE.match(line)
        if fence is not None:
            block.append(line)
            if m and m.group(1) == fence:
                fence = None
            continue
        if m:
            fence = m.group(1)
            block.append(line)
        elif not line.strip() or MARKER.match(line):
            flush()
            pieces.append((line, False))
        else:
            block.append(line)
    flush()
    return pieces


def code_has_words(source: str) -> bool:
    """Whether a code cell has a comment, or a string with words, to translate."""
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(source).readline))
    except (tokenize.TokenError, SyntaxError):
        return False
    for tok in tokens:
        if tok.type == tokenize.COMMENT and WORD.search(tok.string):
            return True
        if tok.type == tokenize.STRING and " " in tok.string and WORD.search(tok.string):
            return True
    return False


def message_calls(source: str) -> list[tuple[int, int, str]]:
    """The ``_t("...")`` literals of ``source``: (start, end) character offsets and text."""
    tree = ast.parse(source)
    starts = [0]
    for line in source.split("\n"):
        starts.append(starts[-1] + len(line) + 1)

    def offset(lineno: int, col_bytes: int) -> int:
        line = source.split("\n")[lineno - 1]
        return starts[lineno - 1] + len(line.encode("utf-8")[:col_bytes].decode("utf-8"))

    found = []
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id == MESSAGE_FUNCTION):
            arg = node.args[0] if node.args else None
            if not (isinstance(arg, ast.Constant) and isinstance(arg.value, str)):
                raise BadTranslation(f"line {node.lineno}: {MESSAGE_FUNCTION}() needs a plain "
                                     "string literal as its first argument")
            assert arg.end_lineno is not None and arg.end_col_offset is not None
            found.append((offset(arg.lineno, arg.col_offset),
                          offset(arg.end_lineno, arg.end_col_offset), arg.value))
    return sorted(found)


def shared_messages(shared: dict[str, str]) -> Iterator[str]:
    """The messages of the shared cells: their ``#@title`` lines and ``_t`` literals."""
    for source in shared.values():
        yield from TITLE.findall(source)
        for _, _, text in message_calls(source):
            yield text


def notebook_messages(nb, shared_tags: tuple[str, ...]) -> Iterator[str]:
    """The messages of one solution notebook, in cell order (shared cells left out)."""
    for cell in nb.cells:
        tags = cell.get("metadata", {}).get("tags", [])
        if set(tags) & set(shared_tags):
            continue
        if cell.cell_type == "markdown":
            yield from (text for text, yes in markdown_pieces(cell.source) if yes)
        elif cell.cell_type == "code" and code_has_words(cell.source):
            yield cell.source


def grader_messages(package: Path) -> dict[str, list[str]]:
    """The grader's messages by file: the literals of its ``t("...")`` and ``N_("...")``
    calls (rikingrade.i18n)."""
    out: dict[str, list[str]] = {}
    for path in sorted(package.rglob("*.py")):
        found = []
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                    and node.func.id in GRADER_FUNCTIONS and node.args
                    and isinstance(node.args[0], ast.Constant)
                    and isinstance(node.args[0].value, str)):
                found.append((node.lineno, node.args[0].value))
        if found:
            out[path.relative_to(package.parent).as_posix()] = [m for _, m in sorted(found)]
    return out


# ----------------------------------------------------------------------------- catalogue
def catalogue_path(solutions: Path, lang: str) -> Path:
    return solutions / CATALOGUE.format(lang=lang)


def template(sources: dict[str, list[str]]) -> Catalog:
    """The catalogue template: every message once, with the files it comes from."""
    cat = Catalog(project="rikin exercises", fuzzy=False)
    for where, messages in sources.items():
        for i, text in enumerate(messages, 1):
            if text in cat:
                cat[text].locations.append((where, i))
            else:
                cat.add(text, locations=[(where, i)])
    return cat


def read_catalogue(path: Path, lang: str) -> Catalog:
    if not path.exists():
        return Catalog(locale=lang, project="rikin exercises", fuzzy=False)
    with path.open("rb") as f:
        return read_po(f, locale=lang)


def write_catalogue(path: Path, cat: Catalog) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    buf = io.BytesIO()
    write_po(buf, cat, width=0, omit_header=False, sort_output=False, include_previous=False,
             no_location=False)
    text = buf.getvalue().decode("utf-8")
    text = re.sub(r'(?m)^"POT-Creation-Date: .*\\n"\n', "", text)
    # no date that changes with every refresh (a merge conflict in every branch)
    revision = '"PO-Revision-Date: YEAR-MO-DA HO:MI+ZONE\\n"'
    text = re.sub(r'(?m)^"PO-Revision-Date: .*\\n"$', lambda m: revision, text)
    path.write_text(text, encoding="utf-8")


def updated(cat: Catalog, tmpl: Catalog) -> Catalog:
    """``cat`` refreshed from ``tmpl``: new messages empty, changed ones fuzzy, gone ones
    dropped (Babel's own merge, as sphinx-intl does for the book)."""
    cat = copy.deepcopy(cat)
    cat.update(tmpl, no_fuzzy_matching=False, update_header_comment=False)
    cat.obsolete.clear()
    return cat


def translations(cat: Catalog, wanted: list[str], lang: str) -> dict[str, str]:
    """The current translation of every message in ``wanted``, or :class:`Untranslated`."""
    out: dict[str, str] = {}
    missing = []
    for text in dict.fromkeys(wanted):
        msg = cat.get(text)
        if msg is None or not msg.string or msg.fuzzy:
            missing.append(text)
        else:
            out[text] = str(msg.string)
    if missing:
        raise Untranslated(lang, missing)
    return out


# ----------------------------------------------------------------------------- checks
def _code_shape(source: str) -> str:
    """The syntax tree with comments gone, and strings with spaces and the messages of
    ``_t(...)`` blanked out."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id == MESSAGE_FUNCTION and node.args
                and isinstance(node.args[0], ast.Constant)):
            node.args[0].value = "<text>"
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and (
                " " in node.value or "\n" in node.value):
            node.value = "<text>"
    return ast.dump(tree, include_attributes=False)


def same_code(english: str, translated: str) -> bool:
    """Whether a translated code cell is the same code (names, numbers, short strings)."""
    try:
        return _code_shape(english) == _code_shape(translated)
    except SyntaxError:
        return False


def check_translation(english: str, translated: str, kind: str) -> None:
    """:class:`BadTranslation` when ``translated`` changes what must stay the same."""
    if kind == "code":
        if not same_code(english, translated):
            raise BadTranslation(f"the translation of this code cell is not the same code "
                                 f"(only comments and texts may change):\n{english[:300]}")
        return
    if kind == "message":
        if sorted(PLACEHOLDER.findall(english)) != sorted(PLACEHOLDER.findall(translated)):
            raise BadTranslation(f"the translation of {english!r} has other {{placeholders}}")
        return
    if sorted(CODE_SPAN.findall(english)) != sorted(CODE_SPAN.findall(translated)):
        raise BadTranslation(f"the translation of {english[:200]!r} changes its inline "
                             "`code`")


# ----------------------------------------------------------------------------- translating
def _literal(text: str, indent: int, tail: int = 0, width: int = 99) -> str:
    """``text`` as Python string literal(s), split at spaces to fit in ``width`` columns
    with ``tail`` more characters after the last one."""
    room = max(30, width - indent - 2 - tail)
    parts: list[str] = []
    rest = text
    while len(rest) > room:
        cut = rest.rfind(" ", 0, room)
        cut = room if cut <= 0 else cut + 1
        parts.append(rest[:cut])
        rest = rest[cut:]
    parts.append(rest)

    def quoted(s: str) -> str:
        return '"' + s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'

    return ("\n" + " " * indent).join(quoted(p) for p in parts if p or len(parts) == 1)


def translate_shared(source: str, tr: dict[str, str]) -> str:
    """A shared cell with its ``#@title`` line and ``_t`` literals translated."""
    out = source
    for start, end, text in reversed(message_calls(source)):
        check_translation(text, tr[text], "message")
        indent = start - (out.rfind("\n", 0, start) + 1)
        line_end = out.find("\n", end)
        tail = (len(out) if line_end < 0 else line_end) - end
        out = out[:start] + _literal(tr[text], indent, tail) + out[end:]
    return TITLE.sub(lambda m: "#@title " + tr[m.group(1)], out)


def translate_notebook(nb, tr: dict[str, str], shared_tags: tuple[str, ...]):
    """A copy of solution notebook ``nb`` with every message translated (shared cells as
    they are: the caller puts the translated ones in)."""
    nb = copy.deepcopy(nb)
    for cell in nb.cells:
        tags = cell.get("metadata", {}).get("tags", [])
        if set(tags) & set(shared_tags):
            continue
        if cell.cell_type == "markdown":
            pieces = []
            for text, yes in markdown_pieces(cell.source):
                if yes:
                    check_translation(text, tr[text], "markdown")
                pieces.append(tr[text] if yes else text)
            cell.source = "\n".join(pieces)
        elif cell.cell_type == "code" and code_has_words(cell.source):
            check_translation(cell.source, tr[cell.source], "code")
            cell.source = tr[cell.source]
    return nb
