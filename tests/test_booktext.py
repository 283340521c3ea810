"""The texts the book's code cells print, in the reader's language (rikin.booktext): the
templates found in a page's cells, their translations read from a gettext catalogue, and
English wherever a translation is missing, empty or fuzzy."""

from __future__ import annotations

from pathlib import Path

import pytest

import rikin
from rikin import InputError
from rikin.booktext import BookText, cell_messages, page_messages, read_catalogue

ROOT = Path(__file__).resolve().parents[1]

CATALOGUE = r'''# a comment
msgid ""
msgstr ""
"Content-Type: text/plain; charset=UTF-8\n"

#: book/page.md:1
msgid "both reach the target (gap {gap:.1e})"
msgstr "las dos alcanzan el objetivo (diferencia {gap:.1e})"

msgid "joint"
msgstr "articulación"

#, fuzzy
msgid "elbow"
msgstr "hombro"

msgid "wrist"
msgstr ""

msgid "a \"quoted\" "
"word"
msgstr "una palabra "
"«citada»"

msgid "bad {n}"
msgstr "mal {m}"
'''


@pytest.fixture
def locales(tmp_path: Path) -> Path:
    folder = tmp_path / "locales" / "es" / "LC_MESSAGES"
    folder.mkdir(parents=True)
    (folder / "cells.po").write_text(CATALOGUE, encoding="utf-8")
    return tmp_path / "locales"


@pytest.fixture
def spanish():
    rikin.i18n.set_language("es")
    yield
    rikin.i18n.set_language(None)


def test_read_catalogue_keeps_translated_entries_only(locales: Path) -> None:
    entries = read_catalogue(locales / "es" / "LC_MESSAGES" / "cells.po")
    assert entries == {"both reach the target (gap {gap:.1e})":
                       "las dos alcanzan el objetivo (diferencia {gap:.1e})",
                       "joint": "articulación",
                       'a "quoted" word': "una palabra «citada»",
                       "bad {n}": "mal {m}"}


def test_spanish_from_the_catalogue_with_the_same_numbers(locales: Path, spanish) -> None:
    text = BookText(locales)
    assert text.tr("both reach the target (gap {gap:.1e})", gap=2.5e-13) == (
        "las dos alcanzan el objetivo (diferencia 2.5e-13)")
    assert text.header(["#", "joint", "q1 (°)"]) == ["#", "articulación", "q1 (°)"]
    # fuzzy, empty or missing: the English as written
    assert [text.tr(w) for w in ("elbow", "wrist", "shoulder")] == ["elbow", "wrist", "shoulder"]


def test_english_is_untouched(locales: Path, monkeypatch) -> None:
    monkeypatch.delenv("RIKIN_LANG", raising=False)
    text = BookText(locales)
    assert text.tr("both reach the target (gap {gap:.1e})", gap=2.5e-13) == (
        "both reach the target (gap 2.5e-13)")
    assert text.tr("joint") == "joint"


def test_no_catalogue_shows_english(tmp_path: Path, spanish) -> None:
    assert BookText(tmp_path / "nowhere").tr("joint {n}", n=3) == "joint 3"


def test_the_environment_chooses_the_language(locales: Path, monkeypatch) -> None:
    monkeypatch.setenv("RIKIN_LANG", "es")
    assert BookText(locales).tr("joint") == "articulación"


def test_a_translation_with_other_placeholders_is_refused(locales: Path, spanish) -> None:
    with pytest.raises(InputError, match=r"other \{placeholders\}"):
        BookText(locales).tr("bad {n}", n=1)


@pytest.mark.parametrize("bad", [3, None, b"x"])
def test_bad_templates_and_folders_are_refused(bad: object, locales: Path) -> None:
    with pytest.raises(InputError):
        BookText(locales).tr(bad)  # type: ignore[arg-type]
    if bad is not None:
        with pytest.raises(InputError):
            BookText(bad)  # type: ignore[arg-type]


def test_cell_messages_finds_templates_headers_and_calls_in_order() -> None:
    source = ('%matplotlib inline\n'
              'ok("both reach the target "\n'
              '   "(gap {gap:.1e})", gap=g)\n'
              'show_table(["#", "joint", "q1 (°)", "TCP error (m)"], rows)\n'
              'ax.set_title(tr("joint space"))\n'
              'def show(header):\n'
              '    return [tr(h) for h in header]   # a text given elsewhere\n')
    assert cell_messages(source) == [(2, "both reach the target (gap {gap:.1e})"),
                                     (4, "joint"), (4, "TCP error (m)"), (5, "joint space")]


@pytest.mark.parametrize("call", ['ok(f"gap {g:.1e}")', 'tr("a" + b)', "show_table(h, rows)",
                                  'show_table([f"q{i}"], rows)'])
def test_a_text_that_cannot_be_translated_is_refused(call: str) -> None:
    with pytest.raises(InputError, match="literal"):
        cell_messages(call)


def test_page_messages_give_the_line_in_the_page() -> None:
    page = ("# Title\n\n```{code-cell} ipython3\n:tags: [hide-input]\n\nx = 1\n"
            'ok("x is {x}", x=x)\n```\n\n```{code-cell} ipython3\n---\ntags: [hide-input]\n'
            '---\nshow_table(["joint"], [])\n```\n')
    assert list(page_messages(page)) == [(7, "x is {x}"), (14, "joint")]
    lines = page.split("\n")
    assert "x is" in lines[6] and "joint" in lines[13]


def test_the_book_pages_print_no_f_string_check() -> None:
    """Every ✓ line, header and figure word of the book is a template (no page raises), and
    no cell prints a ✓ line of its own."""
    for page in sorted((ROOT / "book").glob("*.md")):
        text = page.read_text(encoding="utf-8")
        list(page_messages(text))
        code = "\n".join(m.group(1) for m in rikin.booktext.CODE_CELL.finditer(text))
        assert '"✓ ' not in code.replace('Markdown("✓ " + tr(', ""), (
            f"{page.name}: a ✓ line not written with ok(...)")


# ------------------------------------------------ translations handed over (a downloaded notebook)
@pytest.fixture
def given(monkeypatch):
    """An empty registry of handed-over translations, restored after the test."""
    monkeypatch.setattr(rikin.booktext, "_GIVEN", {})


def test_handed_over_translations_are_read_where_no_catalogue_is(tmp_path: Path, spanish,
                                                                  given) -> None:
    alone = BookText(tmp_path / "locales")  # a downloaded notebook's folder: no catalogue
    rikin.booktext.add_translations("es", {"joint {n}": "articulación {n}"})
    assert alone.tr("joint {n}", n=3) == "articulación 3"
    assert alone.header(["#", "joint {n}"]) == ["#", "articulación {n}"]
    assert alone.tr("elbow") == "elbow"  # not handed over: English


def test_a_catalogue_beside_the_page_wins_and_english_is_untouched(locales: Path, monkeypatch,
                                                                   given) -> None:
    rikin.booktext.add_translations("es", {"joint": "eslabón"})
    monkeypatch.setenv("RIKIN_LANG", "es")
    assert BookText(locales).tr("joint") == "articulación"
    monkeypatch.setenv("RIKIN_LANG", "en")
    assert BookText(locales.parent / "nowhere").tr("joint") == "joint"


@pytest.mark.parametrize("lang, texts", [
    ("en", {"joint": "joint"}), ("xx", {"joint": "x"}), (None, {"joint": "x"}),
    ("es", ["joint"]), ("es", {"joint": 3}), ("es", {"gap {g}": "diferencia {h}"}),
])
def test_bad_handed_over_translations_are_refused(lang, texts, given) -> None:
    with pytest.raises(InputError):
        rikin.booktext.add_translations(lang, texts)
    assert rikin.booktext._GIVEN == {}
