"""The comments of the book's code cells, as messages of the page's catalogue.

A comment in a code cell (``# the wrist centre``) is teaching text: a translated edition
shows the cell with its comments in the edition's language. The code that runs is the
English source (so both editions compute the same numbers); only the source the page
*shows*, the literal block myst-nb makes of the cell's input, gets the translated comments.

* :func:`code_comments` finds a cell's comments with Python's :mod:`tokenize` (a ``#``
  inside a string is no comment), one message per trailing comment and per block of
  full-line comments on consecutive lines (one paragraph, its lines joined by spaces, so
  a translator translates a sentence, not the pieces the English happened to wrap into).
  A comment that is code's business stays out: a shebang, ``# noqa``, ``# type: ...``,
  ``# pragma ...``, ``# fmt: ...``, a cell marker ``# %%``, one without a letter.
* :func:`translated_source` writes a cell's source with each comment's translation in its
  place: a block re-wrapped to the English block's width, a trailing comment after its
  code, or on its own line above the code (same indentation) when the line would be
  longer than :data:`CODE_COLUMNS` (and the line does not continue one that ends with a
  backslash, where no comment line may go).

rikin_i18n extracts the messages in the gettext build and replaces the shown source in a
translated one (:class:`TranslatedComments`); a comment the catalogue has no translation
for is left English and its cell marked ``untranslated``, as Sphinx marks prose.
"""

from __future__ import annotations

import io
import re
import textwrap
import tokenize
from collections.abc import Callable
from dataclasses import dataclass

#: Columns a line of code may take (tests/test_book_content.py checks the English source).
CODE_COLUMNS = 80
#: A comment's marker: ``#``, or Sphinx's ``#:``, with the spaces after it.
_MARKER = re.compile(r"^#:?[ \t]*")
#: Comments that are instructions to a tool, not text for a reader.
_TOOL = re.compile(r"^(?:noqa\b|type:|pragma\b|fmt:|pylint:|mypy:|isort:|ruff:|%%|In\[)")
#: A line that IPython runs and Python would not parse (a magic, a shell command).
_IPYTHON = re.compile(r"^\s*[%!]")


@dataclass(frozen=True)
class Comment:
    """One message of a cell's source: a trailing comment, or a block of full-line ones.

    ``row`` is its first line (0-based) and ``rows`` how many it spans, ``col`` the column
    of its ``#``, ``marker`` what precedes the text (``"# "``), ``text`` the message.
    """

    row: int
    col: int
    rows: int
    marker: str
    text: str
    trailing: bool


def _tokens(source: str) -> list[tokenize.TokenInfo]:
    """The tokens of ``source``, IPython's magic lines blanked; none if it does not parse."""
    lines = ["" if _IPYTHON.match(line) else line for line in source.split("\n")]
    try:
        return list(tokenize.generate_tokens(io.StringIO("\n".join(lines)).readline))
    except (tokenize.TokenError, SyntaxError):
        return []


def code_comments(source: str) -> list[Comment]:
    """The comments of a code cell's ``source`` that a reader reads, in order (see the
    module's docstring: trailing ones alone, consecutive full-line ones as one block)."""
    lines = source.split("\n")
    found: list[Comment] = []
    for token in _tokens(source):
        if token.type != tokenize.COMMENT:
            continue
        (row, col), string = token.start, token.string
        row -= 1
        if row == 0 and string.startswith("#!"):
            continue
        marker = _MARKER.match(string)
        prefix = marker.group(0) if marker else "#"
        text = string[len(prefix):].rstrip()
        if not re.search(r"[A-Za-z]", text) or _TOOL.match(text):
            continue
        trailing = bool(lines[row][:col].strip())
        last = found[-1] if found else None
        if (last is not None and not trailing and not last.trailing and last.col == col
                and last.row + last.rows == row and last.marker == prefix):
            found[-1] = Comment(last.row, col, last.rows + 1, prefix,
                                f"{last.text} {text.strip()}", False)
        else:
            found.append(Comment(row, col, 1, prefix, text.strip(), trailing))
    return found


def _wrapped(text: str, indent: str, marker: str, width: int) -> list[str]:
    """``text`` as comment lines of at most ``width`` columns (a longer word kept whole);
    a line break in ``text`` starts a new line."""
    room = max(width - len(indent) - len(marker), 20)
    out = []
    for paragraph in text.split("\n"):
        out += [indent + marker + line for line in
                textwrap.wrap(paragraph, room, break_long_words=False, break_on_hyphens=False)
                or [""]]
    return out


def translated_source(
    source: str, translate: Callable[[str], str | None], width: int = CODE_COLUMNS
) -> tuple[str, list[str]]:
    """``source`` with its comments (:func:`code_comments`) as ``translate`` gives them.

    Parameters
    ----------
    source : str
        A code cell's source.
    translate : callable
        A message's translation, or None when there is none (the comment stays).
    width : int
        Columns a line may take: a block is wrapped to the English block's width (at most
        this); a trailing comment that would make its line longer goes above its code.

    Returns
    -------
    source : str
        The source to show.
    missing : list of str
        The messages ``translate`` had no translation for.
    """
    lines = source.split("\n")
    missing: list[str] = []
    for c in reversed(code_comments(source)):
        translation = translate(c.text)
        if translation is None:
            missing.insert(0, c.text)
            continue
        here = lines[c.row:c.row + c.rows]
        if c.trailing:
            code = here[0][:c.col]
            line = code + c.marker + translation
            continued = c.row > 0 and lines[c.row - 1].rstrip().endswith("\\")
            if continued or (len(line) <= width and "\n" not in translation):
                # (no comment line can go between a backslash and the line it continues)
                lines[c.row] = line
            else:
                indent = re.match(r"\s*", code).group(0)
                lines[c.row:c.row + 1] = [*_wrapped(translation, indent, c.marker, width),
                                          code.rstrip()]
            continue
        indent = here[0][:c.col]
        if c.rows == 1 and len(indent + c.marker + translation) <= width:
            lines[c.row] = indent + c.marker + translation
            continue
        block = width if c.rows == 1 else min(width, max(60, *(len(h) for h in here)))
        lines[c.row:c.row + c.rows] = _wrapped(translation, indent, c.marker, block)
    return "\n".join(lines), missing
