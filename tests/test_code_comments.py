"""The comments of the book's code cells in the Spanish edition (book/_ext/rikin_comments.py).

* what counts as a comment to translate: found by :mod:`tokenize` (a ``#`` in a string is
  none), a block of comment lines one message, a tool's comment (``# noqa``) or a shebang
  none;
* how a translated cell is written: a block re-wrapped, a trailing comment after its
  code, or above it when the line would pass 80 columns;
* every comment of every code cell of a page, shown or hidden (the downloaded notebook
  has the hidden ones), has its translation in the page's catalogue, and the Spanish
  source it makes keeps every line within 80 columns (the built pages and notebooks are
  checked in tests/test_book_editions.py).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from babel.messages.pofile import read_po

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_comments  # noqa: E402
from rikin_comments import code_comments, translated_source  # noqa: E402

CODE_CELL = re.compile(r"^```\{code-cell\}[^\n]*\n(.*?)^```", re.S | re.M)
PAGES = sorted(p.stem for p in (ROOT / "book").glob("*.md")
               if CODE_CELL.search(p.read_text(encoding="utf-8")))
LANGUAGES = ("es",)


def test_only_real_comments_are_messages() -> None:
    source = ('#!/usr/bin/env python\n'
              'url = "https://x.org/#frag"  # the page\'s address\n'
              "import numpy as np  # noqa: F401\n"
              "x = 1  # type: ignore\n"
              "%matplotlib inline\n"
              "# the wrist centre is d6 back\n"
              "# along the approach axis\n"
              "\n"
              "    # (-pi, pi]\n"
              "#: the arms' names\n"
              "# 90\n")  # no letter in it: nothing to translate
    found = code_comments(source)
    assert [c.text for c in found] == [
        "the page's address", "the wrist centre is d6 back along the approach axis",
        "(-pi, pi]", "the arms' names"]
    assert [(c.row, c.rows, c.trailing, c.marker) for c in found] == [
        (1, 1, True, "# "), (5, 2, False, "# "), (8, 1, False, "# "), (9, 1, False, "#: ")]


def test_a_cell_that_does_not_parse_has_no_messages() -> None:
    assert code_comments("x = (1,  # open\n") == []


def test_translated_source_keeps_the_code_and_wraps_the_comments() -> None:
    source = ("q = arm.ik(T)  # the two elbows\n"
              "# the wrist centre is d6 back\n"
              "# along the approach axis\n"
              "p = T[:3, 3]" + " " * 52 + "# the target\n"
              "s = '# not a comment'\n")
    spanish = {"the two elbows": "los dos codos",
               "the wrist centre is d6 back along the approach axis":
                   "el centro de la muñeca está d6 hacia atrás a lo largo del eje de "
                   "aproximación",
               "the target": "la posición del objetivo"}
    text, missing = translated_source(source, spanish.get, width=40)
    assert missing == []
    assert text.split("\n") == [
        "q = arm.ik(T)  # los dos codos",
        "# el centro de la muñeca está d6 hacia",
        "# atrás a lo largo del eje de",
        "# aproximación",
        "# la posición del objetivo",
        "p = T[:3, 3]",
        "s = '# not a comment'",
        ""]
    code = [line.split("#")[0].rstrip() for line in text.split("\n") if "#" not in line[:1]]
    assert "q = arm.ik(T)" in code and "p = T[:3, 3]" in code


def test_a_comment_without_translation_stays_and_is_reported() -> None:
    source = "x = 1  # one\ny = 2  # two\n"
    text, missing = translated_source(source, {"one": "uno"}.get)
    assert text == "x = 1  # uno\ny = 2  # two\n"
    assert missing == ["two"]


def test_no_comment_line_goes_after_a_backslash() -> None:
    source = "x = 1 + \\\n    2  # a short note\n"
    text, _ = translated_source(source, lambda m: "una nota mucho más larga que cabe mal",
                                width=20)
    assert text == "x = 1 + \\\n    2  # una nota mucho más larga que cabe mal\n"
    compile(text, "<cell>", "exec")


def test_a_translation_may_break_its_lines() -> None:
    source = "# p = Rz(q1) h and\n# |p|^2 = a1^2 + h^2\n"
    text, _ = translated_source(source, lambda m: "p = Rz(q1) h y\n|p|^2 = a1^2 + h^2")
    assert text == "# p = Rz(q1) h y\n# |p|^2 = a1^2 + h^2\n"


# ------------------------------------------------------------------ the book's cells
def code_cells(page: str, shown_only: bool = False) -> list[str]:
    """The sources of the page's code cells: every one (the notebook a reader downloads
    has them all), or only those the page shows (not ``remove-input``, ``remove-cell``)."""
    cells = []
    for cell in CODE_CELL.findall((ROOT / "book" / f"{page}.md").read_text(encoding="utf-8")):
        head, body = cell.split("\n---\n", 1) if cell.startswith("---\n") else ("", cell)
        head += "\n".join(line for line in body.split("\n") if line.startswith(":"))
        if shown_only and re.search(r"remove-(?:input|cell)", head):
            continue
        cells.append("\n".join(line for line in body.split("\n") if not line.startswith(":")))
    return cells


def shown_cells(page: str) -> list[str]:
    """The sources of the page's code cells that the page shows."""
    return code_cells(page, shown_only=True)


def catalogue(language: str, page: str) -> dict[str, str]:
    path = ROOT / "book" / "locales" / language / "LC_MESSAGES" / "book" / f"{page}.po"
    with path.open("rb") as f:
        return {m.id: m.string for m in read_po(f) if m.id and m.string and not m.fuzzy}


@pytest.mark.parametrize("language", LANGUAGES)
@pytest.mark.parametrize("page", PAGES)
def test_every_comment_is_translated_within_80_columns(language: str, page: str) -> None:
    """Every comment of every code cell, shown or hidden (``remove-input``: the page never
    shows it, the downloaded notebook does), has its translation in the page's catalogue,
    and the translated source keeps every line within 80 columns."""
    strings = catalogue(language, page)
    missing, long = [], []
    for cell in code_cells(page):
        text, left = translated_source(cell, strings.get)
        missing += left
        long += [line for line in text.split("\n")
                 if len(line) > rikin_comments.CODE_COLUMNS]
    assert not missing, (f"{page}: {len(missing)} comments without translation (python3 "
                         f"tools/dev.py translations, then translate them): {missing[:10]}")
    assert not long, f"{page}: {len(long)} lines over 80 columns in {language}: {long[:3]}"


def test_the_catalogue_gets_the_comments_of_hidden_cells_too(tmp_path: Path) -> None:
    """The gettext build reads every code cell's comments from the page's notebook source
    (rikin_i18n.notebook_comment_texts), a ``remove-input`` cell's included: its
    doctree shows no source for it, the downloaded notebook does."""
    import rikin_i18n

    page = tmp_path / "page.md"
    page.write_text("---\njupytext:\n  text_representation:\n    format_name: myst\n"
                    "kernelspec:\n  name: python3\n  display_name: Python 3\n---\n"
                    "# A page\n\n"
                    "```{code-cell} ipython3\nx = 1  # shown\n```\n\n"
                    "```{code-cell} ipython3\n:tags: [remove-input]\n\n"
                    "# checks: x is one\n# and stays so\nassert x == 1\n```\n",
                    encoding="utf-8")
    assert rikin_i18n.notebook_comment_texts(page) == [
        (11, ["shown"]), (15, ["checks: x is one and stays so"])]
    prose = tmp_path / "prose.md"
    prose.write_text("# No notebook\n\n```python\nx = 1  # a code block\n```\n")
    assert rikin_i18n.notebook_comment_texts(prose) == []


def test_the_book_has_comments_to_translate() -> None:
    assert sum(len(code_comments(c)) for p in PAGES for c in shown_cells(p)) > 150
    hidden = [c for p in PAGES for c in code_cells(p) if c not in shown_cells(p)]
    assert sum(len(code_comments(c)) for c in hidden) >= 6, "no hidden cell has a comment"
