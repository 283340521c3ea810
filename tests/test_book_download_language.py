"""A chapter's notebook downloaded from one edition of the book and run alone prints in
that edition's language.

A student downloads ``_sources/book/<chapter>.ipynb`` from a page of the Spanish edition
(the page's download button), saves it into an empty folder (no repository, no
``locales`` catalogue beside it, no ``RIKIN_LANG``) and runs it: every output a cell
shows (the ✓ lines, table headers, branch names, rikin's figures and live panels) reads
as on the Spanish page, which the build executed in Spanish. The English download still
prints English. rikin comes from this checkout's virtual environment (the install cell
finds it installed; tests/test_student_download.py installs it from the book's wheel).

What is compared, cell by cell: the text of every output (printed text, ``text/plain``,
``text/markdown`` and the visible text of ``text/html``, images left out) against the
same notebook's outputs as the build saved them (what the page shows).

The site: ``RIKIN_BOOK_HTML`` (a ``_build/html`` that ``python3 tools/dev.py book`` made,
with its ``es/``), else the session's one strict build (``book_site``, tests/book_build.py).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest
from bs4 import BeautifulSoup

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_i18n  # noqa: E402
import rikin_site  # noqa: E402

#: Chapters with ✓ lines, tables, branch names, interactive figures and live panels.
CHAPTERS = ("book/own_arm", "book/planar")
#: English words no Spanish line has: a line of the English page with one of them, and
#: not on the Spanish page, is English the Spanish page translates.
ENGLISH = re.compile(r"\b(?:the|and|with|of|is|are|from|each|every|branch|joint)\b")
#: The MIME types of an output myst-nb's ``glue`` keeps for the page to show elsewhere.
GLUED = "application/papermill.record/"
#: Run a notebook (argv[1]) in the current folder as Jupyter would; save it as argv[2].
DRIVER = """
import sys
import nbformat
from nbclient import NotebookClient
nb = nbformat.read(sys.argv[1], as_version=4)
NotebookClient(nb, timeout=900, kernel_name="python3",
               resources={"metadata": {"path": "."}}).execute()
nbformat.write(nb, sys.argv[2])
"""


@pytest.fixture(scope="module")
def site(request: pytest.FixtureRequest) -> Path:
    """The built site's ``_build/html`` (the English edition; the Spanish one in ``es/``)."""
    given = os.environ.get("RIKIN_BOOK_HTML")
    if given:
        html = Path(given)
    else:
        built = request.getfixturevalue("book_site")
        assert built.returncode == 0, f"the book did not build:\n{built.log[-20000:]}"
        html = Path(built.html)
    assert (html / rikin_i18n.EDITIONS["es"][0] / "index.html").is_file(), \
        f"{html}: no Spanish edition built"
    return html


def _download(site: Path, lang: str, chapter: str) -> Path:
    folder = site / rikin_i18n.EDITIONS[lang][0] if lang != "en" else site
    path = folder / "_sources" / f"{chapter}.ipynb"
    assert path.is_file(), f"{path}: not published"
    return path


def _run_alone(notebook: Path, folder: Path) -> nbformat.NotebookNode:
    """``notebook`` saved alone into the empty ``folder`` and run there by a fresh kernel
    with no language set in its environment."""
    folder.mkdir(parents=True)
    shutil.copy(notebook, folder / notebook.name)
    env = {k: v for k, v in os.environ.items()
           if k not in ("RIKIN_LANG", "RIKIN_BOOK_BUILD", "PYTHONPATH")}
    proc = subprocess.run([sys.executable, "-c", DRIVER, notebook.name, "ran.ipynb"],
                          cwd=folder, env=env, capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, f"{notebook.name} failed run alone:\n{proc.stderr[-5000:]}"
    return nbformat.read(folder / "ran.ipynb", as_version=4)


def _html_text(html: str) -> str:
    soup = BeautifulSoup(html, "html.parser")
    for tag in soup(["script", "style", "img", "svg"]):
        tag.decompose()
    return soup.get_text(" ", strip=True)


def shown(nb: nbformat.NotebookNode) -> list[tuple[int, str]]:
    """(code cell, text) of every output after the install cell that a front end shows;
    consecutive prints of a cell to one stream are one text (how a kernel cuts them into
    messages is timing)."""
    out: list[tuple[int, str]] = []
    for i, cell in enumerate(nb.cells):
        tags = cell.get("metadata", {}).get("tags", [])
        if cell.cell_type != "code" or rikin_site.INSTALL_TAG in tags:
            continue
        last_stream = None
        for o in cell.outputs:
            if o.output_type == "stream" and o.get("name") == last_stream:
                out[-1] = (i, out[-1][1] + o.get("text", ""))
                continue
            data = o.get("data", {})
            if data and all(k.startswith(GLUED) for k in data):
                continue  # kept for the page (myst-nb's glue), shown by no front end
            last_stream = o.get("name") if o.output_type == "stream" else None
            text = o.get("text", "") or "\n".join(
                [data.get("text/plain", ""), data.get("text/markdown", ""),
                 _html_text(data.get("text/html", ""))])
            if o.output_type == "error":
                text = f"{o.ename}: {o.evalue}"
            out.append((i, text))
    return out


def _lines(shown_: list[tuple[int, str]]) -> set[str]:
    return {line.strip() for _, text in shown_ for line in text.splitlines() if line.strip()}


def _differences(ran: list[tuple[int, str]], page: list[tuple[int, str]]) -> str:
    counts = f"{len(ran)} outputs run alone, {len(page)} on the page\n"
    return counts + "\n".join(f"cell {i}:\n  alone: {a[:300]!r}\n  page:  {b[:300]!r}"
                               for (i, a), (_, b) in zip(ran, page, strict=False)
                               if a != b)[:6000]


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("chapter", CHAPTERS)
def test_a_spanish_chapter_downloaded_alone_prints_what_the_spanish_page_shows(
        site: Path, chapter: str, tmp_path: Path) -> None:
    spanish, english = _download(site, "es", chapter), _download(site, "en", chapter)
    page = shown(nbformat.read(spanish, as_version=4))
    page_en = shown(nbformat.read(english, as_version=4))
    translated = {line for line in _lines(page_en) - _lines(page) if ENGLISH.search(line)}
    assert translated, f"{chapter}: the Spanish page translates no line of the English one"

    ran = shown(_run_alone(spanish, tmp_path / "student"))

    assert ran == page, f"{chapter}: run alone, it shows what the page does not:\n" \
        + _differences(ran, page)
    left = sorted(translated & _lines(ran))
    assert not left, f"{chapter}: run alone, the Spanish notebook prints English: {left[:8]}"


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("chapter", CHAPTERS)
def test_an_english_chapter_downloaded_alone_still_prints_english(
        site: Path, chapter: str, tmp_path: Path) -> None:
    english = _download(site, "en", chapter)
    nb = nbformat.read(english, as_version=4)
    assert "RIKIN_LANGUAGE" not in nb.cells[0].source, "the English install cell sets a language"
    page = shown(nb)

    ran = shown(_run_alone(english, tmp_path / "student"))

    assert ran == page, f"{chapter}: run alone, it shows what the page does not:\n" \
        + _differences(ran, page)
    assert any(ENGLISH.search(line) for line in _lines(ran)), f"{chapter}: no English printed"
