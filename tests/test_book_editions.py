"""The book's two editions, English at the site root and Spanish in ``es/``, built together.

* both build strict (``-W -n --keep-going``, every notebook executed, the Spanish one with
  ``RIKIN_LANG=es``) with no warning;
* every page shows the same numbers in both: the text of every code cell's output and
  glued output, and the coordinates of every interactive figure, compared page by page;
* every code cell's comments read in the edition's language (the code shown is the same,
  and stays within 80 columns);
* every page has ``<html lang>`` of its edition, and every text the Spanish edition looked
  up in the catalogues was found there (Sphinx marks a text it found no translation for
  with the class ``untranslated``, book/_ext/rikin_i18n.py);
* in headless Chromium, the language switch of every page goes to the same page of the
  other edition and back, and the Spanish search finds a Spanish word.

The site comes from the ``editions`` fixture: ``RIKIN_BOOK_HTML`` (a ``_build/html`` that
``tools/dev.py book`` made, with its ``es/``), else the session's one strict build
(``book_site``, tests/book_build.py), which builds every edition as ``tools/dev.py book``
does (``dev.build_book``).
"""

from __future__ import annotations

import json
import os
import re
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
import test_book_browser as _browser
import yaml
from book_build import Site
from bs4 import BeautifulSoup

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import dev  # noqa: E402
import rikin_comments  # noqa: E402
import rikin_site  # noqa: E402

# The browser test's fixtures (Chromium, a local server of ``book_html``) and pages.
browser_paths, server = _browser.browser_paths, _browser.server
PAGES, _open = _browser.PAGES, _browser._open

#: The other editions: language code -> folder of the site.
EDITIONS = dev.EDITIONS
#: Every page with a switch (index.html only redirects to the first chapter), and the
#: book's pages (Sphinx's search and index pages have no cell outputs to compare).
SWITCH_PAGES = [p for p in PAGES if p != "index.html"]
BOOK_PAGES = [p for p in PAGES if p.startswith("book/")]
#: The pages published with their notebook: those written as MyST notebooks (the glossary,
#: the references and the instructor's guide are plain pages).
NOTEBOOK_PAGES = [p for p in BOOK_PAGES
                  if "kernelspec:" in (ROOT / p.replace(".html", ".md")).read_text()[:1000]]
#: Numbers as a page prints them (a sign, decimals, an exponent).
_NUMBER = re.compile(r"(?<![\w.])[-−]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")
#: An interactive figure's coordinates in its script: "x": [..] (also y, z).
_COORDINATES = re.compile(r'"([xyz])":\s*\[([^\]]*)\]')


@dataclass(frozen=True)
class Editions:
    """Both editions built: the site (``html``, Spanish in ``html/es``), and how it went."""

    html: Path
    returncode: int
    log: str


@pytest.fixture(scope="module")
def editions(request: pytest.FixtureRequest) -> Editions:
    given = os.environ.get("RIKIN_BOOK_HTML")
    if given:
        html = Path(given)
        missing = [str(html / f / "index.html") for f in ("", *EDITIONS.values())
                   if not (html / f / "index.html").is_file()]
        if missing:
            pytest.fail(f"RIKIN_BOOK_HTML={given}: no {missing}: build the book first "
                        "(python3 tools/dev.py book)")
        return Editions(html, 0, "")
    # the session's one strict build of both editions (tests/book_build.py, dev.build_book)
    site: Site = request.getfixturevalue("book_site")
    return Editions(Path(site.html), site.returncode, site.log)


@pytest.fixture(scope="module")
def book_html(editions: Editions) -> Path:
    """The site the browser fixture serves (both editions)."""
    assert editions.returncode == 0, f"the book's editions did not build:\n{editions.log[-20000:]}"
    return editions.html


def _article(html_file: Path) -> BeautifulSoup:
    soup = BeautifulSoup(html_file.read_text(encoding="utf-8"), "html.parser")
    article = soup.select_one("article.bd-article")
    assert article is not None, f"{html_file}: no article"
    return article


def output_numbers(html_file: Path) -> list[str]:
    """Every number a page's code cells printed or glued, in order: the visible text of each
    output (not its scripts), then the coordinates of each interactive figure."""
    article = _article(html_file)
    numbers: list[str] = []
    for output in article.select("div.cell_output, div.output"):
        for script in output.select("script, style"):
            script.extract()
            if script.name == "script":
                numbers += [f"{axis}:{values}" for axis, values in
                            _COORDINATES.findall(script.get_text())]
        numbers += [n.replace("−", "-") for n in _NUMBER.findall(output.get_text(" "))]
    return numbers


#: ipykernel 7.4's shutdown race (upstream; the newest release here): after a
#: ``shutdown_request`` the control thread flushes stderr (``process_control``) while the
#: main thread has already closed the IOPub thread's pipe, and tornado logs the ZMQError
#: from the kernel process, after the notebook ran to its end (ipykernel PR 1518 catches
#: the same race in ``_really_send``, not in ``schedule``). Only this traceback, whole.
_KERNEL_SHUTDOWN_RACE = re.compile(
    r"ERROR:tornado\.general:Uncaught exception in ZMQStream callback\n"
    r"Traceback \(most recent call last\):\n"
    r"(?:  .*\n)*?"
    r'  File "[^"\n]*ipykernel/kernelbase\.py", line \d+, in process_control\n'
    r"(?:  .*\n)*?"
    r'  File "[^"\n]*ipykernel/iostream\.py", line \d+, in schedule\n'
    r"(?:  .*\n)*?"
    r"zmq\.error\.ZMQError: Socket operation on non-socket\n")


def without_kernel_shutdown_race(log: str) -> str:
    """``log`` without the kernel shutdown race's traceback (every other line kept)."""
    return _KERNEL_SHUTDOWN_RACE.sub("", log)


def test_only_the_kernel_shutdown_race_is_left_out_of_the_build_log() -> None:
    frames = ('  File "/v/zmq/eventloop/zmqstream.py", line 585, in _log_error\n'
              "    f.result()\n"
              '  File "/v/ipykernel/kernelbase.py", line 372, in dispatch_control\n'
              "    await self.process_control(msg)\n"
              '  File "/v/ipykernel/kernelbase.py", line 408, in process_control\n'
              "    sys.stderr.flush()\n"
              '  File "/v/ipykernel/iostream.py", line 343, in schedule\n'
              '    self._event_pipe.send(b"")\n'
              '  File "zmq/backend/cython/_zmq.py", line 190, in _check_rc\n')
    race = ("ERROR:tornado.general:Uncaught exception in ZMQStream callback\n"
            "Traceback (most recent call last):\n" + frames +
            "zmq.error.ZMQError: Socket operation on non-socket\n")
    before, after = "book/numbers.md: Executed notebook in 2.25 seconds\n", "done\n"
    assert without_kernel_shutdown_race(before + race + after) == before + after
    other_error = race.replace("Socket operation on non-socket", "Operation cannot be accomplished")
    assert "ERROR" in without_kernel_shutdown_race(before + other_error + after)
    not_kernel = race.replace("in process_control", "in run_cell")
    assert "ERROR" in without_kernel_shutdown_race(not_kernel)
    warning = "book/planar.md:12: WARNING: undefined label\n"
    assert without_kernel_shutdown_race(race + warning) == warning


# ------------------------------------------------------------------ the built site
def assert_none_left(left: list[str], where: str, what: str) -> None:
    """Fail naming the first 30 ``what`` (e.g. "captions") of page ``where`` still English."""
    assert not left, (f"{where}: {len(left)} {what} still English:\n"
                      + "\n".join(repr(t[:100]) for t in left[:30]))


@pytest.mark.book
@pytest.mark.slow
def test_both_editions_build_strict_with_no_warning(editions: Editions) -> None:
    assert editions.returncode == 0, f"build failed:\n{editions.log[-20000:]}"
    log = without_kernel_shutdown_race(editions.log)
    assert "WARNING" not in log and "ERROR" not in log, log[-20000:]
    for folder in ("", *EDITIONS.values()):
        for page in BOOK_PAGES:
            assert (editions.html / folder / page).is_file(), f"{folder}/{page} not built"


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", BOOK_PAGES)
def test_same_numbers_in_both_editions(page: str, book_html: Path) -> None:
    english = output_numbers(book_html / page)
    for folder in EDITIONS.values():
        other = output_numbers(book_html / folder / page)
        assert other == english, (
            f"{folder}/{page}: the outputs' numbers differ from the English page's "
            f"(first difference at {_first_difference(english, other)})")


def _first_difference(a: list[str], b: list[str]) -> str:
    for i, (x, y) in enumerate(zip(a, b, strict=False)):
        if x != y:
            return f"number {i}: {x[:40]!r} vs {y[:40]!r}"
    return f"lengths {len(a)} vs {len(b)}"


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", ["en", *EDITIONS])
def test_pages_say_their_language(language: str, book_html: Path) -> None:
    folder = EDITIONS.get(language, "")
    for page in SWITCH_PAGES:
        head = (book_html / folder / page).read_text(encoding="utf-8")[:2000]
        assert re.search(rf'<html lang="{language}"', head), f"{folder}/{page}: not lang={language}"


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", list(EDITIONS))
def test_every_text_of_a_translated_page_is_translated(language: str, book_html: Path) -> None:
    """What the translated build looked up and did not find (a new or changed message not
    yet in the catalogue, or one whose msgid the extraction wrote differently)."""
    missing = []
    for page in BOOK_PAGES:
        article = _article(book_html / EDITIONS[language] / page)
        for el in article.select(".untranslated"):
            text = el.get("alt") or el.get_text(" ", strip=True)
            missing.append(f"{page}: <{el.name}> {text[:80]!r}")
    assert not missing, (f"{len(missing)} texts not translated (python3 tools/dev.py "
                         f"translations, then translate them):\n" + "\n".join(missing[:40]))


#: Words a cell text may share with the English one: units, functions and the names the
#: Spanish edition keeps (roll, pitch, yaw; TCP).
SAME_IN_BOTH = {"rad", "mm", "cos", "sin", "tan", "atan", "arccos", "arcsin", "arctan",
                "roll", "pitch", "yaw", "TCP", "DH"}
_CODE_LIKE = re.compile(r"`[^`]*`|\S*[_\d(){}\[\]]\S*")


def _has_words(text: str) -> bool:
    """Whether ``text`` has a word to translate (not only numbers, symbols, code, units)."""
    bare = _CODE_LIKE.sub(" ", text)
    return any(w not in SAME_IN_BOTH for w in re.findall(r"[A-Za-z]{2,}", bare))


def cell_texts(html_file: Path) -> list[str]:
    """The texts a page's code cells printed: every ✓ line and every table header cell."""
    article = _article(html_file)
    texts = []
    for output in article.select("div.cell_output, div.output"):
        texts += [" ".join(th.get_text(" ").split()) for th in output.select("th")]
        for el in output.select("p, pre, li"):
            texts += [" ".join(line.split()) for line in el.get_text().split("\n")
                      if line.strip().startswith("✓")]
    return texts


def caption_texts(html_file: Path) -> list[str]:
    """The texts of a page's figure captions (without their numbers), those written in a
    code cell's metadata among them."""
    return [" ".join(span.get_text(" ").split())
            for span in _article(html_file).select("figcaption .caption-text")]


def english_captions(english_html: Path, other_html: Path) -> list[str]:
    """The figure captions of the English page that the other edition's page shows
    unchanged."""
    other = set(caption_texts(other_html))
    return [t for t in caption_texts(english_html) if t in other and _has_words(t)]


def english_cell_texts(english_html: Path, other_html: Path) -> list[str]:
    """The ✓ lines and headers of the English page with words in them that the other
    edition's page shows unchanged."""
    other = set(cell_texts(other_html))
    return [t for t in dict.fromkeys(cell_texts(english_html)) if t in other and _has_words(t)]


#: Where a printed line starts quoting a message that stays English in every edition, by
#: policy (searched for, quoted in forums, matched by tests): rikin's own words after
#: ``rikin:`` (its error messages, the notes of ``IKResult.table()``, a singularity's
#: description, ``rikin.ik.classify``'s verdict) and, from an exception's class name on,
#: its name and message (rikin's ``InputError: ...``; Python's ``TypeError - Cannot
#: convert complex to float`` where the lesson's code fails).
_QUOTED = re.compile(r"(?:^|\s)(?:rikin:|\w*Error\b).*$")
#: A code identifier shown with its value ("excess = 4.1661", "alpha = 46.8011°").
_SHOWN_NAME = re.compile(r"\b\w+(?= =)")
#: Punctuation around a printed word ("(deg)", "target:", "[180.0]").
_AROUND = "()[]{},;:.!?'\"|<>"
#: Words a printed line may share with the English one beyond :data:`SAME_IN_BOTH`:
#: Python's reprs and a constant of the formulas.
PRINTED_ALIKE = {"True", "False", "None", "nan", "inf", "pi"}
#: Whole printed lines that stay English by policy, with why.
KEPT_OUTPUT_LINES = {
    "j type theta_i d_i a_i alpha_i offset":
        "Robot.dh_table()'s header: the DH fields as rikin's own-arm rows name them "
        "(type d a alpha offset), code identifiers in every edition",
}


def printed_words(line: str) -> list[str]:
    """The words of a printed line to translate: not what it quotes (:data:`_QUOTED`), a
    name shown with its value, code (``p_z``, ``fk(q``, ``l1``), numbers, units, reprs."""
    if line in KEPT_OUTPUT_LINES:
        return []
    text = _SHOWN_NAME.sub(" ", _QUOTED.sub("", line))
    words = [token.strip(_AROUND) for token in text.split()]
    return [w for w in words if re.fullmatch(r"[A-Za-z]{2,}(?:[-'][A-Za-z]+)*", w)
            and w not in SAME_IN_BOTH and w not in PRINTED_ALIKE]


def printed_lines(html_file: Path) -> list[str]:
    """Every line a page's code cells printed as text (streams and ``text/plain`` reprs),
    its spaces collapsed, in order."""
    lines = []
    for output in _article(html_file).select("div.cell_output"):
        for pre in output.select("pre"):
            lines += [" ".join(line.split()) for line in pre.get_text().split("\n")
                      if line.strip()]
    return lines


def english_printed_lines(english_html: Path, other_html: Path) -> list[str]:
    """The lines the English page's cells printed with words to translate in them
    (:func:`printed_words`) that the other edition's page prints unchanged."""
    other = set(printed_lines(other_html))
    return [t for t in dict.fromkeys(printed_lines(english_html))
            if t in other and printed_words(t)]


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", BOOK_PAGES)
def test_no_printed_line_is_english(page: str, book_html: Path) -> None:
    """Every line the cells print (``print(tr(...))``, not a plain English string) reads
    in the edition's language, but for the messages quoted as they are (``rikin: ...``,
    an exception's name and message) and :data:`KEPT_OUTPUT_LINES`."""
    english = book_html / page
    for folder in EDITIONS.values():
        left = english_printed_lines(english, book_html / folder / page)
        assert_none_left(left, f"{folder}/{page}", "printed lines")


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", BOOK_PAGES)
def test_no_check_line_or_table_header_is_english(page: str, book_html: Path) -> None:
    """The ✓ lines and table headers the cells print read in the edition's language
    (rikin.booktext and book/locales/<lang>/LC_MESSAGES/cells.po; rikin.i18n)."""
    english = book_html / page
    assert english.is_file()
    for folder in EDITIONS.values():
        left = english_cell_texts(english, book_html / folder / page)
        assert_none_left(left, f"{folder}/{page}", "cell texts")


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", BOOK_PAGES)
def test_no_figure_caption_is_english(page: str, book_html: Path) -> None:
    """Every figure's caption reads in the edition's language, those a code cell's metadata
    gives too (they sit in the cell's output, whose printed texts are not looked up)."""
    english = book_html / page
    for folder in EDITIONS.values():
        left = english_captions(english, book_html / folder / page)
        assert_none_left(left, f"{folder}/{page}", "captions")


def shown_sources(html_file: Path) -> list[str]:
    """The source of every code cell a page shows, folded ones too (its highlighted text)."""
    return [pre.get_text() for pre in _article(html_file).select("div.cell_input pre")]


def shown_comments(html_file: Path) -> list[str]:
    """The comments of a page's code cells as the page shows them, as messages
    (rikin_comments.code_comments: a block of comment lines is one)."""
    return [c.text for source in shown_sources(html_file)
            for c in rikin_comments.code_comments(source)]


def spelt_alike(language: str, page: str) -> set[str]:
    """The messages of a page's catalogue translated as they are (a comment that is a
    formula, ``# q5 = 0``, or a name, ``# SCARA``) with no English function word."""
    from babel.messages.pofile import read_po

    po = ROOT / "book" / "locales" / language / "LC_MESSAGES" / Path(page).with_suffix(".po")
    if not po.is_file():
        return set()
    with po.open("rb") as f:
        alike = {m.id for m in read_po(f) if m.id and m.string == m.id and not m.fuzzy}
    return {m for m in alike if not set(re.findall(r"[a-z]+", m.lower())) & _ENGLISH_WORDS}


#: English function words (no Spanish word): a comment copied with one is still English.
_ENGLISH_WORDS = frozenset("the and with of is are to for this that from by on which it "
                           "its be or at into each not what when where how but only than "
                           "then there as in".split())


def left_english(english: list[str], other: list[str], alike: set[str]) -> list[str]:
    """The English edition's comments (each once, in order) that the other edition has
    unchanged, but for those its catalogue translates as they are (``alike``)."""
    theirs = set(other)
    return [c for c in dict.fromkeys(english) if c in theirs and c not in alike]


def english_comments(english_html: Path, other_html: Path, alike: set[str]) -> list[str]:
    """:func:`left_english` of the comments two editions' pages show."""
    return left_english(shown_comments(english_html), shown_comments(other_html), alike)


def long_code_lines(sources: list[str]) -> list[str]:
    """The lines of code cells' ``sources`` wider than the book's 80 columns."""
    return [line for source in sources for line in source.split("\n")
            if len(line) > rikin_comments.CODE_COLUMNS]


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", BOOK_PAGES)
def test_no_code_comment_is_english(page: str, book_html: Path) -> None:
    """The comments of every code cell a page shows (folded ones too) read in the
    edition's language: the page's catalogue translates them (rikin_comments)."""
    english = book_html / page
    for language, folder in EDITIONS.items():
        left = english_comments(english, book_html / folder / page, spelt_alike(language, page))
        assert_none_left(left, f"{folder}/{page}", "code comments")


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", BOOK_PAGES)
def test_translated_code_lines_fit_80_columns(page: str, book_html: Path) -> None:
    """A translated comment leaves every line of a code cell within 80 columns (as
    tests/test_book_content.py checks the English source), and the code the cells show is
    the English code: only comments differ."""
    english = shown_sources(book_html / page)
    for folder in EDITIONS.values():
        shown = shown_sources(book_html / folder / page)
        long = long_code_lines(shown)
        assert not long, f"{folder}/{page}: {len(long)} code lines over 80 columns: {long[:3]}"
        assert [_code_only(s) for s in shown] == [_code_only(s) for s in english], (
            f"{folder}/{page}: a code cell shows other code than the English page")


def notebook_sources(notebook: Path) -> list[str]:
    """The source of every code cell of a published notebook (``_sources/<page>.ipynb``),
    shown on its page or not (``remove-input``), but its install cell (rikin_site's, the
    same in every notebook, its comments not the page's: tests/test_book_spanish_text.py
    checks them)."""
    if not notebook.is_file():
        return []
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    return ["".join(c["source"]) for c in cells if c["cell_type"] == "code"
            and rikin_site.INSTALL_TAG not in c.get("metadata", {}).get("tags", [])]


def notebook_comments(notebook: Path) -> list[str]:
    """The comments of :func:`notebook_sources`, as messages (rikin_comments)."""
    return [c.text for source in notebook_sources(notebook)
            for c in rikin_comments.code_comments(source)]


def english_notebook_comments(english: Path, other: Path, alike: set[str]) -> list[str]:
    """:func:`left_english` of the comments of two editions' notebooks."""
    return left_english(notebook_comments(english), notebook_comments(other), alike)


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", NOTEBOOK_PAGES)
def test_no_code_comment_of_a_downloaded_notebook_is_english(page: str,
                                                             book_html: Path) -> None:
    """The notebook a translated page offers has every code cell's comments in the
    edition's language, also in the cells the page never shows (``remove-input``: checks,
    figures), and its code lines within 80 columns."""
    name = Path("_sources") / page.replace(".html", ".ipynb")
    english = book_html / name
    assert english.is_file(), f"{english}: the page's notebook is not published"
    for language, folder in EDITIONS.items():
        other = book_html / folder / name
        assert other.is_file(), f"{other}: not published"
        left = english_notebook_comments(english, other, spelt_alike(language, page))
        assert_none_left(left, f"{folder}/{name}", "code comments")
        long = long_code_lines(notebook_sources(other))
        assert not long, f"{folder}/{name}: {len(long)} code lines over 80 columns: {long[:3]}"


def _code_only(source: str) -> list[str]:
    """The lines of ``source`` that are code, without their comments."""
    lines = source.split("\n")
    for c in reversed(rikin_comments.code_comments(source)):
        if c.trailing:
            lines[c.row] = lines[c.row][:c.col]
        else:
            del lines[c.row:c.row + c.rows]
    return [line.rstrip() for line in lines if line.strip()]


def test_the_comment_comparison_sees_english(tmp_path: Path) -> None:
    """shown_comments reads the comments of shown and folded cells (not a ``#`` in a
    string); a comment the catalogue writes as it is may stay."""
    def page(name: str, *cells: str) -> Path:
        body = "".join(f'<div class="cell_input"><div class="highlight"><pre>{c}</pre></div>'
                       f"</div>" for c in cells)
        return article_page(tmp_path / f"{name}.html",
                            f'<div class="cell"><details>{body}</details></div>')

    english = page("en", "x = '#1'  # the wrist centre\n# q5 = 0\n", "y = 2  # front, back")
    assert shown_comments(english) == ["the wrist centre", "q5 = 0", "front, back"]
    spanish = page("es", "x = '#1'  # el centro de la muñeca\n# q5 = 0\n",
                   "y = 2  # delante, detrás")
    assert english_comments(english, spanish, {"q5 = 0"}) == []
    half = page("half", "x = '#1'  # the wrist centre\n# q5 = 0\n", "y = 2  # delante, detrás")
    assert english_comments(english, half, {"q5 = 0"}) == ["the wrist centre"]
    assert english_comments(english, half, set()) == ["the wrist centre", "q5 = 0"]
    assert _code_only("x = '#1'  # a\n# b\n# c\ny = 2\n") == ["x = '#1'", "y = 2"]


def test_the_notebook_comment_comparison_sees_a_hidden_cell(tmp_path: Path) -> None:
    """notebook_comments reads every code cell of a downloaded notebook, those its page
    removes too, and leaves its install cell out."""
    def notebook(name: str, *cells: tuple[str, list[str]]) -> Path:
        path = tmp_path / f"{name}.ipynb"
        path.write_text(json.dumps({"cells": [
            {"cell_type": "code", "source": source, "metadata": {"tags": tags}}
            for source, tags in [("x = 1  # set up\n", [rikin_site.INSTALL_TAG]), *cells]
        ] + [{"cell_type": "markdown", "source": "# the title", "metadata": {}}]}),
            encoding="utf-8")
        return path

    english = notebook("en", ("y = 2  # the wrist centre\n", []),
                       ("# checks: q5 = 0\nassert y\n", ["remove-input"]))
    assert notebook_comments(english) == ["the wrist centre", "checks: q5 = 0"]
    spanish = notebook("es", ("y = 2  # el centro de la muñeca\n", []),
                       ("# comprobaciones: q5 = 0\nassert y\n", ["remove-input"]))
    assert english_notebook_comments(english, spanish, set()) == []
    shown_only = notebook("half", ("y = 2  # el centro de la muñeca\n", []),
                          ("# checks: q5 = 0\nassert y\n", ["remove-input"]))
    assert english_notebook_comments(english, shown_only, set()) == ["checks: q5 = 0"]
    assert notebook_comments(tmp_path / "none.ipynb") == []


def article_page(path: Path, body: str) -> Path:
    """A page at ``path`` whose article (what the checks read) is ``body``."""
    path.write_text(f'<html><body><article class="bd-article">{body}</article></body></html>',
                    encoding="utf-8")
    return path


def test_the_caption_comparison_sees_english(tmp_path: Path) -> None:
    """caption_texts reads the caption's text, not its number."""
    def page(name: str, number: str, caption: str) -> Path:
        return article_page(
            tmp_path / f"{name}.html",
            f'<figure><img alt="x"/><figcaption><p><span class="caption-number">{number} '
            f'</span><span class="caption-text">{caption}</span></p></figcaption></figure>')

    english = page("en", "Fig. 3", "The arm at q = 0")
    assert caption_texts(english) == ["The arm at q = 0"]
    assert english_captions(english, page("es", "Figura 3", "El brazo en q = 0")) == []
    assert english_captions(english, page("half", "Figura 3", "The arm at q = 0")) == [
        "The arm at q = 0"]


def test_the_printed_line_comparison_sees_english(tmp_path: Path) -> None:
    """printed_lines reads what cells print (not the prose); a line left in English is
    flagged, a translated one, one of numbers, code and reprs only, or one quoting rikin's
    or an exception's message is not."""
    def page(name: str, *lines: str) -> Path:
        body = "\n".join(lines)
        return article_page(tmp_path / f"{name}.html",
                            f'<p>the wrist centre</p><div class="cell_output"><pre>{body}'
                            f"</pre></div>")

    lines = ("wrist centre p_w = [ 1. 2. ]", "θ1, θ2, θ3 = [ 1. 2. ] (deg)",
             "rpy_to_r gives the same: True", "excess = 4.1661", "fk(q + 2 pi k): 1e-14",
             "rikin: planar 3R: target is unreachable", "InputError: l1 must be numbers",
             "as in the lesson: TypeError - Cannot convert complex to float")
    english = page("en", *lines)
    assert printed_lines(english) == list(lines)
    assert english_printed_lines(english, page("same", *lines)) == [
        "wrist centre p_w = [ 1. 2. ]", "θ1, θ2, θ3 = [ 1. 2. ] (deg)",
        "rpy_to_r gives the same: True",
        "as in the lesson: TypeError - Cannot convert complex to float"]
    spanish = page("es", "centro de la muñeca p_w = [ 1. 2. ]",
                   "θ1, θ2, θ3 = [ 1. 2. ] (grados)", "rpy_to_r da la misma: True",
                   *lines[3:7], "como en la lección: TypeError - Cannot convert complex to "
                   "float")
    assert english_printed_lines(english, spanish) == []
    assert printed_words("moved 0.5 along y: UnreachableError, 0.5 off") == ["moved", "along"]
    assert printed_words("j type theta_i d_i a_i alpha_i offset") == []


def test_the_cell_text_comparison_sees_english(tmp_path: Path) -> None:
    """cell_texts reads ✓ lines and headers of cell outputs (not the prose); a text with
    only numbers, symbols, code or units may stay as it is."""
    def page(name: str, check: str, header: str) -> Path:
        return article_page(
            tmp_path / f"{name}.html",
            f'<p>✓ prose is not a cell</p><div class="cell_output"><p>{check}</p><table><tr>'
            f"<th>{header}</th><th>q1 (°)</th><th>θ1 (rad)</th><th>arm_slot</th></tr></table>"
            f"</div>")

    english = page("en", "✓ both reach the target (gap 1e-12)", "joint")
    assert cell_texts(english) == ["joint", "q1 (°)", "θ1 (rad)", "arm_slot",
                                   "✓ both reach the target (gap 1e-12)"]
    spanish = page("es", "✓ las dos alcanzan el objetivo (diferencia 1e-12)", "articulación")
    assert english_cell_texts(english, spanish) == []
    assert english_cell_texts(english, page("half", "✓ both reach the target (gap 1e-12)",
                                            "articulación")) == [
        "✓ both reach the target (gap 1e-12)"]
    assert english_cell_texts(english, page("head", "✓ las dos", "joint")) == ["joint"]


def _site_texts(page_html: str) -> list[str]:
    """The texts a page has from the config: the book's title, the search box, the
    buttons that fold a cell, the footer."""
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    placeholder = re.search(r'placeholder="([^"]+)"', page_html)
    folds = re.findall(r"(?:Show|Hide) code cell \w+", page_html)[:1]
    return [config["title"], config["copyright"], *folds,
            *(placeholder.group(1) for _ in [0] if placeholder)]


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", list(EDITIONS))
def test_the_site_texts_are_translated(language: str, book_html: Path) -> None:
    """The title, search box, fold buttons and footer come from the config, not from a page:
    the translated edition takes them from its catalogues (rikin_i18n.SITE_TEXTS)."""
    english = _site_texts((book_html / "book/decoupling.html").read_text(encoding="utf-8"))
    assert len(english) == 4, english
    left = []
    for page in BOOK_PAGES:
        text = (book_html / EDITIONS[language] / page).read_text(encoding="utf-8")
        left += [f"{page}: {t!r}" for t in english if t in text.replace("&#39;", "'")]
    assert not left, "English left in the Spanish pages:\n" + "\n".join(left[:20])


#: Where a page shows words of the site around its text (the theme, the book's extension):
#: the sidebar's part captions, the preview banner, the launch lines, the fold buttons,
#: the previous/next links, the headings and buttons of the header and of both sidebars,
#: the footer (author, copyright).
_CHROME = ("nav.bd-links p.caption", ".rikin-preview-banner", ".rikin-launch",
           "details.hide summary p", ".prev-next-area .prev-next-subtitle",
           ".bd-sidebar-secondary .onthispage", ".bd-header-article .btn__text-container",
           ".bd-header-article .dropdown-item", "footer .footer-item")
#: ... and the tooltips and labels for screen readers there.
_TIPS = (".bd-header-article [{a}]", ".bd-sidebar-primary [{a}]", ".bd-sidebar-secondary [{a}]",
         "details.hide summary[{a}]", ".prev-next-area [{a}]", ".bd-header [{a}]")
#: Words the Spanish edition keeps as they are: names (of programs, settings, keys), the
#: words the word list keeps (notebook, URL), and words both languages spell alike.
_KEPT_WORDS = {"notebook", "notebooks", "jupyter", "jupyterlab", "colab", "binder", "rikin",
               "ipynb", "ctrl", "html", "baseurl", "_config", "yml", "pdf", "url", "local",
               "copyright", "mit"}
_WORDS = re.compile(r"[A-Za-z_]{3,}")
#: Addresses and file names in a text (kept as they are).
_NAMES = re.compile(r"\b\w+://\S+|[\w.-]+\.(?:ipynb|yml|html)\b")


#: The last compound of a selector of :data:`_CHROME` or :data:`_TIPS`: its tag, classes
#: and attributes.
_LAST_COMPOUND = re.compile(r"(?:^|\s)([a-z]*)((?:\.[\w-]+)*)((?:\[[\w-]+\])*)$")


def _select(tags: list, where: str) -> list:
    """``soup.select(where)`` of the soup whose elements (in document order) are ``tags``:
    the same elements in the same order, matched against the whole selector only when they
    have the tag, classes and attributes of its last compound (soupsieve matching every
    element of a page against 34 selectors took minutes for the 48 pages)."""
    import soupsieve

    tag, classes, attributes = _LAST_COMPOUND.search(where).groups()
    classes, attributes = classes.split(".")[1:], re.findall(r"[\w-]+", attributes)

    def candidate(el: object) -> bool:
        if tag and el.name != tag:
            return False
        have = el.attrs.get("class") or ()
        return (all(c in have for c in classes) if classes else True) and (
            all(a in el.attrs for a in attributes) if attributes else True)

    return [el for el in tags if candidate(el) and soupsieve.match(where, el)]


def _tags(soup: BeautifulSoup) -> list:
    """Every element of ``soup`` in document order."""
    from bs4 import Tag

    return [el for el in soup.descendants if isinstance(el, Tag)]


def chrome_texts(html_file: Path) -> list[tuple[str, str]]:
    """The texts of the site around a page's text (:data:`_CHROME`, :data:`_TIPS`), as
    (where, text) in the page's order; not the language switch, which speaks the other
    edition's language on purpose."""
    soup = BeautifulSoup(html_file.read_text(encoding="utf-8"), "html.parser")
    for switch in _select(_tags(soup), ".rikin-language-switch"):
        switch.decompose()
    tags = _tags(soup)
    found = [(where, el.get_text(" ", strip=True)) for where in _CHROME
             for el in _select(tags, where)]
    for attribute in ("title", "aria-label", "data-bs-title", "placeholder"):
        for where in _TIPS:
            found += [(f"{where.format(a=attribute)}", str(el[attribute]))
                      for el in _select(tags, where.format(a=attribute))]
    return [(where, re.sub(r"\s+", " ", text)) for where, text in found if text.strip()]


def english_left(english: list[tuple[str, str]], other: list[tuple[str, str]]) -> list[str]:
    """The English words of ``english`` (a page's :func:`chrome_texts`) still in ``other``
    (the same page's in another edition), text by text: each place must hold as many texts
    in both, and no text of ``other`` a word of its English one but the names it keeps."""
    left = []
    places = dict.fromkeys(where for where, _ in english + other)
    for where in places:
        mine = [t for w, t in english if w == where]
        theirs = [t for w, t in other if w == where]
        if len(mine) != len(theirs):
            left.append(f"{where}: {len(theirs)} texts, the English page has {len(mine)}: "
                        f"{theirs[:3]}")
            continue
        for en, es in zip(mine, theirs, strict=True):
            words = {w.lower() for w in _WORDS.findall(_NAMES.sub(" ", en))} - _KEPT_WORDS
            same = sorted(w for w in words if re.search(rf"(?<![A-Za-z]){re.escape(w)}"
                                                        r"(?![A-Za-z])", es, re.I))
            if same:
                left.append(f"{where}: {es!r} (English {en!r}: {same})")
    return left


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", list(EDITIONS))
def test_the_site_around_a_page_speaks_its_language(language: str, book_html: Path) -> None:
    """What a reader of the translated edition sees around the text: the sidebar's part
    captions, the local-preview banner, the "Run this page yourself" launch lines, the fold
    buttons ("Show code cell source", "... outputs", "... content"), previous and next, the
    header's buttons and tooltips; none still in English."""
    english_chrome = chrome_texts(book_html / "book/planar.html")
    wheres = {where for where, _ in english_chrome}
    for needed in ("nav.bd-links p.caption", ".rikin-preview-banner", ".rikin-launch",
                   "details.hide summary p", "details.hide summary[aria-label]"):
        assert needed in wheres, f"the English planar page has no {needed}: {english_chrome}"
    left = []
    for page in SWITCH_PAGES:
        english = chrome_texts(book_html / page)
        other = chrome_texts(book_html / EDITIONS[language] / page)
        left += [f"{page}: {text}" for text in english_left(english, other)]
    assert not left, f"{len(left)} texts around the pages still in English:\n" + "\n".join(
        left[:40])


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", list(EDITIONS))
def test_a_translated_page_offers_its_languages_notebooks(language: str,
                                                          book_html: Path) -> None:
    """The exercises page of a translated edition downloads the exercises in its language
    (the download links and the stable copies in ``<edition>/_static/exercises/``), and
    every launch link (Colab, Binder) of its pages opens the edition's copy, in its folder
    of the published site, not the English one."""
    site = book_html / EDITIONS[language]
    page = site / "book" / "exercises.html"
    soup = BeautifulSoup(page.read_text(encoding="utf-8"), "html.parser")
    downloads = [a["href"] for a in soup.select("a.reference.download")
                 if str(a["href"]).endswith(".ipynb")]
    assert len(downloads) >= 4, downloads
    for href in downloads:
        name = href.rsplit("/", 1)[-1]
        for notebook in (page.parent / href, site / "_static" / "exercises" / name):
            data = json.loads(notebook.read_text(encoding="utf-8"))
            assert data["metadata"].get("language") == language, notebook
            title = "".join(data["cells"][0]["source"]).splitlines()[0]
            assert "install rikin" not in title, f"{notebook}: {title}"
    wrong = []
    for name in SWITCH_PAGES:
        html = BeautifulSoup((site / name).read_text(encoding="utf-8"), "html.parser")
        for a in html.select(".rikin-launch a[target=_blank]"):
            url = unquote(str(a["href"]))
            if not re.search(rf"/{EDITIONS[language]}/(_sources|_static)/", url):
                wrong.append(f"{name}: {url}")
    assert not wrong, "launch links to the English notebooks:\n" + "\n".join(wrong[:20])


#: A markdown block of a notebook that has no prose to translate: display maths, a
#: table, HTML, code.
_NO_PROSE = re.compile(r"^(?:\$\$|\||<|```|~~~)")
#: A fenced code block (in a markdown cell), blank lines and all.
_CODE_BLOCK = re.compile(r"(?ms)^```(?!\{)[^\n]*\n.*?^```[ \t]*$")


def _blocks(cell: dict) -> list[str]:
    """A markdown cell's blocks (split at blank lines), its code blocks left out."""
    return _CODE_BLOCK.sub("", "".join(cell["source"])).split("\n\n")


def _spelt_alike(language: str) -> set[str]:
    """The messages the catalogues of ``language`` translate as they are ("Magnitudes")."""
    from babel.messages.pofile import read_po

    alike = set()
    for po in (ROOT / "book" / "locales" / language / "LC_MESSAGES").rglob("*.po"):
        with po.open("rb") as f:
            alike |= {m.id for m in read_po(f) if m.id and m.string == m.id}
    return alike


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", list(EDITIONS))
def test_a_translated_chapter_notebook_is_in_its_language(language: str,
                                                          book_html: Path) -> None:
    """The notebook a translated page offers (``<edition>/_sources/<page>.ipynb``: the
    header's download button, "Run this page yourself") has the page's text in the
    edition's language: its title is the page's, and no prose block is the English
    notebook's."""
    site = book_html / EDITIONS[language]
    left, seen = [], 0
    alike = _spelt_alike(language)
    for page in BOOK_PAGES:
        notebook = site / "_sources" / page.replace(".html", ".ipynb")
        if not notebook.is_file():
            continue
        seen += 1
        data = json.loads(notebook.read_text(encoding="utf-8"))
        english = json.loads((book_html / "_sources" / page.replace(".html", ".ipynb"))
                             .read_text(encoding="utf-8"))
        assert data["metadata"].get("language") == language, notebook
        title = _article(site / page).select_one("h1").get_text(" ", strip=True).rstrip("#")
        markdown = [c for c in data["cells"] if c["cell_type"] == "markdown"]
        first = "".join(markdown[0]["source"]).splitlines()[0]
        assert first == f"# {title.strip()}", (page, first)
        prose = {b for c in english["cells"] if c["cell_type"] == "markdown"
                 for b in _blocks(c) if not _NO_PROSE.match(b)}
        left += [f"{page}: {b[:80]!r}" for c in markdown for b in _blocks(c)
                 if b in prose and re.search(r"[A-Za-z]{4,}", b) and b.strip("# ") not in alike]
    assert seen >= 10, f"only {seen} chapter notebooks in {site / '_sources'}"
    assert not left, f"{len(left)} English blocks in the notebooks:\n" + "\n".join(left[:30])


def test_english_left_sees_an_english_caption_fold_or_banner() -> None:
    """english_left flags a text left in English, or with an English word in it, and lets
    the names the translation keeps and a translated text pass."""
    english = [("caption", "Inverse kinematics"), ("fold", "Show code cell source"),
               ("launch", "Run this page yourself: download the notebook (.ipynb) and open it "
                          "in Jupyter, JupyterLab or Colab (File → Upload notebook)")]
    spanish = [("caption", "Cinemática inversa"),
               ("fold", "Mostrar el código de la celda"),
               ("launch", "Ejecuta esta página tú: descarga el notebook (.ipynb) y ábrelo en "
                          "Jupyter, JupyterLab o Colab (Archivo → Subir cuaderno)")]
    assert english_left(english, spanish) == []
    assert english_left(english, [spanish[0], ("fold", "Mostrar celda de código (source)"),
                                  spanish[2]]) != []
    assert english_left(english, [("caption", "Inverse kinematics"), *spanish[1:]]) != []
    assert english_left(english, spanish[:2]) != []  # a text missing is reported too


def test_the_number_comparison_sees_a_changed_number(tmp_path: Path) -> None:
    """output_numbers reads cell outputs and interactive coordinates, not the prose."""
    def page(prose: str, value: str, x: str) -> Path:
        return article_page(
            tmp_path / f"{prose}-{value}-{x}.html",
            f'<p>{prose} 7</p><div class="cell_output"><table><tr><th>rama</th></tr><tr>'
            f'<td>{value}</td></tr></table></div><figure><div class="output"><div '
            f'style="height:600px"></div><script>Plotly.newPlot(el, [{{"x": [{x}], "y": [2]}}])'
            f"</script></div></figure>")

    english = output_numbers(page("joint", "12.5", "1.0"))
    assert english == ["12.5", "x:1.0", "y:2"]
    assert output_numbers(page("articulación", "12.5", "1.0")) == english
    assert output_numbers(page("joint", "12.6", "1.0")) != english
    assert output_numbers(page("joint", "12.5", "1.5")) != english


# ------------------------------------------------------------------ in the browser
@pytest.fixture(scope="module")
def driver(browser_paths: tuple[str, str]) -> Iterator[object]:
    """The browser test's Chromium, whose navigations are done once a page is parsed (a
    check that needs a page loaded in full waits for it: :func:`_switch`, ``_open``)."""
    drv = _browser.chrome(browser_paths, page_load_strategy="eager")
    try:
        yield drv
    finally:
        drv.quit()


def _switch(driver: object, language: str) -> str:
    """Click the page's switch to ``language``; the URL it arrives at."""
    from selenium.webdriver.support.ui import WebDriverWait

    link = driver.find_element("css selector", f"a.rikin-language-switch[hreflang='{language}']")
    link.click()
    WebDriverWait(driver, 30, poll_frequency=0.05).until(
        lambda d: d.execute_script("return document.readyState") == "complete",
        "the other edition's page did not load")
    return driver.current_url


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", SWITCH_PAGES)
def test_the_switch_goes_to_the_same_page_and_back(page: str, book_html: Path, server: str,
                                                   driver: object) -> None:
    """The page is opened once (the switch needs no typeset maths): each edition's switch
    is clicked there, and the switch back of the page it went to returns to it."""
    driver.get(f"{server}/{page}")  # returns once the page is parsed (its switch is there)
    for language, folder in EDITIONS.items():
        there = urlsplit(_switch(driver, language)).path
        assert there == f"/{folder}/{page}", f"{page}: the switch went to {there}"
        assert driver.execute_script("return document.documentElement.lang") == language
        back = urlsplit(_switch(driver, "en")).path
        assert back == f"/{page}", f"{folder}/{page}: the switch back went to {back}"
        assert driver.execute_script("return document.documentElement.lang") == "en"


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize(("word", "page"), [("desacople", "book/decoupling.html"),
                                            ("muñeca", "book/glossary.html")])
def test_the_spanish_search_finds_a_spanish_word(word: str, page: str, book_html: Path,
                                                 server: str, driver: object) -> None:
    _open(driver, f"{server}/es/search.html?q={word}")
    deadline = time.monotonic() + 30
    found: list[str] = []
    while time.monotonic() < deadline:
        found = driver.execute_script(
            "return Array.from(document.querySelectorAll('#search-results a'))"
            ".map(a => a.getAttribute('href'))")
        if found:
            break
        time.sleep(0.2)
    assert any(href.split("?")[0].endswith(page.split("/")[-1]) for href in found), (
        f"searching {word!r} in the Spanish edition found {found}")


def test_build_book_builds_every_edition(tmp_path: Path) -> None:
    """dev.build_book (the instructors' and the tests' one build) runs English, then each
    other edition with its language, its base URL folder and RIKIN_LANG, and puts its site
    into the English one's folder; the derived configs are removed."""
    tag = f"test-{os.getpid()}-editions"
    seen: list[tuple[str | None, str]] = []

    def runner(cmd: list[str], env: dict[str, str]) -> int:
        config = Path(cmd[cmd.index("--config") + 1]).read_text(encoding="utf-8")
        seen.append((env.get("RIKIN_LANG"), config))
        site = Path(cmd[cmd.index("--path-output") + 1]) / "_build" / "html"
        site.mkdir(parents=True, exist_ok=True)
        (site / "index.html").write_text(env.get("RIKIN_LANG", "en"), encoding="utf-8")
        return 0

    build = dev.BookBuild(base_url="http://127.0.0.1:20001/", output=tmp_path, tag=tag)
    assert dev.build_book(build, runner) == 0
    assert [language for language, _ in seen] == [None, *EDITIONS]
    for (language, config), folder in zip(seen[1:], EDITIONS.values(), strict=True):
        assert re.search(rf"^\s*language:\s*{language}\s*$", config, re.M)
        assert f'baseurl: "http://127.0.0.1:20001/{folder}/"' in config
        assert (tmp_path / "_build" / "html" / folder / "index.html").read_text() == language
    assert re.search(r"^\s*language:\s*en\s*$", seen[0][1], re.M)
    assert not list(ROOT.glob(f"_config.{tag}*.yml"))
