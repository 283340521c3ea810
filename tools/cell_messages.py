#!/usr/bin/env python3
"""Refresh the catalogue of the texts the book's code cells print (the ✓ lines, table
headers and figure words: rikin.booktext) from the pages' sources.

    .venv/bin/python tools/cell_messages.py     (python3 tools/dev.py translations runs it)

Every template of every page ``book/**/*.md`` (:func:`rikin.booktext.page_messages`) goes
into ``book/locales/<lang>/LC_MESSAGES/cells.po`` with Babel, as the exercises'
catalogues are (tools/exercise_i18n.py): a new template gets an empty translation, a
changed one keeps the old translation marked fuzzy, a gone one is dropped.
``tests/test_translations.py`` fails until a translator has dealt with each.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import exercise_i18n as i18n  # noqa: E402  (Babel's catalogue reading and writing)

from rikin.booktext import CATALOGUE, page_messages  # noqa: E402

BOOK = ROOT / "book"
LOCALES = BOOK / "locales"
LANGUAGES = ("es",)


def book_messages(book: Path = BOOK) -> dict[str, list[str]]:
    """The templates of every page of ``book`` that has some: page path -> templates."""
    out: dict[str, list[str]] = {}
    for page in sorted(book.rglob("*.md")):
        if "locales" in page.parts or "_ext" in page.parts:
            continue
        found = [text for _, text in page_messages(page.read_text(encoding="utf-8"))]
        if found:
            out[page.relative_to(book.parent).as_posix()] = found
    return out


def catalogue_path(lang: str, locales: Path = LOCALES) -> Path:
    return locales / CATALOGUE.format(lang=lang)


def main() -> int:
    tmpl = i18n.template(book_messages())
    tmpl.project = "rikin book cells"
    for lang in LANGUAGES:
        path = catalogue_path(lang)
        cat = i18n.read_catalogue(path, lang)
        cat.project = "rikin book cells"
        i18n.write_catalogue(path, i18n.updated(cat, tmpl))
        print(f"cell_messages.py: {path.relative_to(ROOT)}: {len(tmpl)} templates")
    return 0


if __name__ == "__main__":
    sys.exit(main())
