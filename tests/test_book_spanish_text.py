"""No English left in what a Spanish reader of the book reads.

* Every page of the Spanish edition (``_build/html/es/**.html``, the built static HTML): its
  visible text (prose, headings, captions, tables, what the book's own folded cells print,
  the site around the page, tooltips and alt texts) has no English word, outside code and
  what stays English on purpose (below).
* The install cell of every Spanish notebook (the exercises' and the chapters' downloads)
  says each of its messages in Spanish, and says them when it runs.
* The drawing attached to every exercise notebook is one picture for both languages: the
  code that draws it writes no word on it.

Stays English on purpose, and is left out here: code the student reads and runs (a code
cell's source, whose comments tests/test_book_editions.py checks are translated, and what
a code cell whose source is shown prints: ``print(classify(arm))``
shows rikin's own description), inline code and identifiers, formulas, a program's
message quoted in «…» or printed as ``SomeError: ...`` (rikin's, Python's and the
grader's errors, matched by tests; what ``classify`` says), English cited in italics (a
glossary entry's English term, an LMS's menu, a cited title), all-capital abbreviations
("CC BY"), and the language switch's tooltip, which speaks the language it leads to.

A Spanish word left without its accent by a theme's own translation ("Descarga esta
pagina") is reported too (:data:`UNACCENTED`).

English is found by its function words (:data:`ENGLISH`: words that no Spanish or
Portuguese sentence has), which every English phrase longer than a name carries ("as in
the lab", "+ with q1", "Link to this heading"), and by the few English words that the
book's computed labels use alone (:data:`ENGLISH_LABELS`).

The site: ``RIKIN_BOOK_HTML`` (a ``_build/html`` that ``python3 tools/dev.py book`` made,
with its ``es/``), else the session's one strict build (``book_site``, tests/book_build.py).
"""

from __future__ import annotations

import ast
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from bs4 import BeautifulSoup, Comment

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_i18n  # noqa: E402
import rikin_site  # noqa: E402

#: English words that are no Spanish (nor Portuguese: the notes') word.
ENGLISH = frozenset("""
    the and with of is are was were to for this that these those from by on which it its
    be or an at into every each some not have does you your what when where how why but
    can will only than then there their they we our if installed says here all after
    before would could should must been being out in
""".split())
#: English words the book's computed row labels and family names use without a
#: function word ("derived (some branch)", "cartesian + wrist", "PPRRR (notes)").
ENGLISH_LABELS = frozenset("derived branch lab arm wrist notes".split())
#: A family name in English word order: "planar 2R", "general 6R" (Spanish: "2R plano",
#: "6R general"; the lesson's own "robot 3R planar" is Spanish).
ENGLISH_ORDER = re.compile(r"\b(?:planar|general|angular) \d+R\b")
#: Elements whose text is code, maths or not shown.
NOT_PROSE = ("script, style, noscript, template, pre, code, kbd, samp, var, .highlight, "
             "div.cell_input, .math, span.pre, .MathJax")
#: Attributes a reader sees (tooltips, alt texts) or hears (a screen reader's labels).
SHOWN_ATTRIBUTES = ("title", "alt", "aria-label", "placeholder")
#: Cells whose source the page folds or removes: the book's own checks and drawings, whose
#: printed texts are the book's (rikin.booktext), not the student's code's.
FOLDED = ("tag_hide-input", "tag_remove-input", "tag_hide-cell")
#: A program's message quoted as it prints it.
QUOTED = re.compile(r"«[^»]*»")
#: A word; one with an underscore is an identifier (``arm_slot``, ``rikin.r_to_rpy``).
WORD = re.compile(r"[A-Za-z_À-ÿ]+(?:'[a-z]+)?")
#: What stays English on purpose in a Spanish page (see the module's docstring): the
#: switch's tooltip; a Python or rikin error as printed ("UnreachableError: ..."); names.
ON_PURPOSE = (rikin_i18n.SWITCH_TITLE["en"],)
PRINTED_ERROR = re.compile(r"^\w*(?:Error|Exception): ")
NAMES = ("Robotics Toolbox for MATLAB",)
#: Spanish words that a theme's own translations write without their accent
#: (sphinx-book-theme 1.3: "Descarga esta pagina", "pagina anterior", "Ultima actualización").
UNACCENTED = re.compile(r"\b(?:pagina|paginas|Ultima|ultima|codigo|busqueda|Busqueda)\b")
#: Cited English, the book's italics: a glossary entry's English term, a menu of an LMS or
#: JupyterLab, what the grader's report writes, a cited title (*Modern Robotics*, ...).
CITED = "em, cite"


# ------------------------------------------------------------------ what a reader sees
def visible_texts(html_file: Path) -> list[str]:
    """The texts a reader of ``html_file`` sees outside code: every text node of the page
    (not of code, maths, scripts, comments, nor of the output of a code cell whose source
    is shown), then the tooltips, alt texts and screen-reader labels."""
    soup = BeautifulSoup(html_file.read_text(encoding="utf-8"), "html.parser")
    for comment in soup.find_all(string=lambda s: isinstance(s, Comment)):
        comment.extract()
    for element in soup.select(f"{NOT_PROSE}, {CITED}"):
        element.decompose()
    for cell in soup.select("div.cell"):
        if not set(cell.get("class", [])) & set(FOLDED):
            for output in cell.select("div.cell_output"):
                output.decompose()
    texts = [" ".join(s.split()) for s in soup.find_all(string=True)]
    for element in soup.find_all(True):
        texts += [str(element[a]) for a in SHOWN_ATTRIBUTES if element.get(a)]
    return [t for t in texts if t.strip()]


def english_words(text: str) -> list[str]:
    """The English words of ``text`` (outside «quoted messages»), in order."""
    if text.strip() in ON_PURPOSE or PRINTED_ERROR.match(text.strip()):
        return []
    for name in NAMES:
        text = text.replace(name, " ")
    text = QUOTED.sub(" ", text)
    words = [w for w in WORD.findall(text) if "_" not in w and not w.isupper()]
    return ([w for w in words if w.lower() in ENGLISH or w.lower() in ENGLISH_LABELS]
            + ENGLISH_ORDER.findall(text))


def english_left(html_file: Path) -> list[str]:
    """Every text of ``html_file`` a reader sees that has an English word, with them."""
    out = []
    for text in visible_texts(html_file):
        found = english_words(text) + UNACCENTED.findall(text)
        if found:
            out.append(f"{text[:110]!r}  <- {', '.join(dict.fromkeys(found))}")
    return list(dict.fromkeys(out))


def test_the_english_finder_sees_english_and_passes_spanish(tmp_path: Path) -> None:
    """english_left finds English prose, labels, tooltips and folded cells' outputs; it
    passes Spanish, code, maths, quoted messages and the outputs of shown code."""
    page = tmp_path / "page.html"
    page.write_text(
        '<html><body><p>El brazo alcanza el objetivo en <code>ik(T)</code>, '
        '<span class="math">\\(q = 0\\)</span>.</p>'
        '<p>El corrector dice «the file is empty …» (archivo vacío).</p>'
        '<p>El 6R general; volteo de muñeca (<em>wrist flip</em>); CC BY 4.0.</p>'
        '<a class="headerlink" title="Enlace a este encabezado">#</a>'
        '<a title="Read this page in English">English</a>'
        '<div class="cell"><div class="cell_input"><pre>print("as in the lab")</pre></div>'
        '<div class="cell_output"><pre>the arm at q</pre></div></div>'
        '<div class="cell tag_hide-input"><div class="cell_output"><table><tr>'
        '<td>como en el laboratorio</td><td>θ1 (°)</td><td>arm_slot</td></tr></table>'
        '<p>UnreachableError: the target is out of reach</p></div></div>'
        "</body></html>", encoding="utf-8")
    assert english_left(page) == []
    page.write_text(
        '<html><body><p>El brazo está in the plane.</p>'
        '<a class="headerlink" title="Link to this heading">#</a>'
        '<button title="Descarga esta pagina"></button>'
        '<img alt="The arm at q = 0"/>'
        '<div class="cell tag_hide-input"><div class="cell_output"><table><tr>'
        '<td>+ with q1</td><td>planar 2R</td><td>derived (some branch)</td></tr></table>'
        "</div></div></body></html>", encoding="utf-8")
    left = english_left(page)
    assert [t.split("  <- ")[1] for t in left] == [
        "in, the", "with", "planar 2R", "derived, some, branch", "to, this", "pagina",
        "The, arm, at"]


# ------------------------------------------------------------------ the built Spanish pages
@pytest.fixture(scope="module")
def spanish_site(request: pytest.FixtureRequest) -> Path:
    """The Spanish edition's folder of the built site."""
    given = os.environ.get("RIKIN_BOOK_HTML")
    if given:
        html = Path(given)
    else:
        site = request.getfixturevalue("book_site")
        assert site.returncode == 0, f"the book did not build:\n{site.log[-20000:]}"
        html = Path(site.html)
    folder = html / rikin_i18n.EDITIONS["es"][0]
    assert (folder / "index.html").is_file(), f"{folder}: no Spanish edition built"
    return folder


def spanish_pages(folder: Path) -> list[Path]:
    """Every page of the Spanish edition (not the copies of sources and static files)."""
    return [p for p in sorted(folder.rglob("*.html"))
            if not p.relative_to(folder).parts[0].startswith("_")]


@pytest.mark.book
@pytest.mark.slow
def test_no_spanish_page_shows_english(spanish_site: Path) -> None:
    pages = spanish_pages(spanish_site)
    assert len(pages) >= 20, f"{spanish_site}: only {len(pages)} pages"
    left = {p.relative_to(spanish_site).as_posix(): english_left(p) for p in pages}
    left = {page: texts for page, texts in left.items() if texts}
    report = "\n".join(f"{page}: {len(texts)} texts\n    " + "\n    ".join(texts[:40])
                       for page, texts in left.items())
    assert not left, (f"English in {sum(map(len, left.values()))} texts of {len(left)} "
                      f"Spanish pages:\n{report}")


# ------------------------------------------------------------------ the install cell
def _says(source: str) -> dict[str, str]:
    """The ``RIKIN_SAYS`` an install cell's source sets (its messages' translations)."""
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "RIKIN_SAYS":
            return ast.literal_eval(node.value)
    raise AssertionError("the install cell sets no RIKIN_SAYS")


def _install_source(notebook: Path) -> str:
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    found = [c for c in cells if rikin_site.INSTALL_TAG in c.get("metadata", {}).get("tags", [])]
    assert len(found) == 1, f"{notebook}: {len(found)} install cells"
    source = found[0]["source"]
    return "".join(source) if isinstance(source, list) else source


SPANISH_EXERCISES = sorted((ROOT / "exercises" / "es").glob("*.ipynb"))


def english_install_comments(source: str) -> list[str]:
    """The comments of an install cell's ``source`` left as the English cell writes them
    (rikin_site.INSTALL_COMMENTS: its body's and its dictionaries')."""
    import rikin_comments

    return [c.text for c in rikin_comments.code_comments(source)
            if c.text in rikin_site.INSTALL_COMMENTS]


def test_the_install_cell_comments_are_messages() -> None:
    """Every comment a reader reads in an install cell (English, with its dictionaries) is
    one of its messages; a Spanish one (the exercises' catalogue) has none left."""
    english = rikin_site.install_cell_source(
        "https://x.org/", "0.1.0", texts={m: m + "!" for m in rikin_site.INSTALL_MESSAGES},
        language="es", cell_texts={"side": "lado"})
    import rikin_comments

    comments = [c.text for c in rikin_comments.code_comments(english)
                if not c.text.startswith("@title")]
    assert len(comments) >= 4 and set(comments) <= {rikin_site.INSTALL_NOTE,
                                                    *rikin_site.INSTALL_COMMENTS}, comments
    assert sorted(english_install_comments(english)) == sorted(rikin_site.INSTALL_COMMENTS)
    texts = rikin_i18n.catalogue_strings([ROOT / rikin_i18n.EXERCISE_LOCALES], "es")
    spanish = rikin_site.install_cell_source(
        "https://x.org/", "0.1.0", texts=texts, language="es", cell_texts={"side": "lado"})
    assert english_install_comments(spanish) == []
    compile(spanish, "<install cell>", "exec")


def test_the_install_cell_has_every_message() -> None:
    """The install cell's messages are every template it says (so none is left out of
    the catalogues), and none is an f-string any more."""
    assert "rikin {version} is installed" in rikin_site.INSTALL_MESSAGES
    assert len(rikin_site.INSTALL_MESSAGES) >= 15
    assert set(rikin_site.INSTALL_MESSAGES) <= set(rikin_site.INSTALL_TEXTS)
    written = [" ".join(str(part.value) for part in node.values
                        if isinstance(part, ast.Constant))
               for node in ast.walk(ast.parse(rikin_site.INSTALL_BODY))
               if isinstance(node, ast.JoinedStr)]
    english = [text for text in written if english_words(text)]
    assert not english, f"the install cell writes English, not by _rikin_say: {english}"


@pytest.mark.parametrize("notebook", SPANISH_EXERCISES, ids=lambda p: p.name)
def test_a_spanish_exercise_install_cell_speaks_spanish(notebook: Path, tmp_path: Path) -> None:
    """Every message of the install cell of a Spanish exercise is translated, and what it
    prints when rikin is there is Spanish (run in this interpreter, where rikin is)."""
    source = _install_source(notebook)
    says = _says(source)
    missing = [m for m in rikin_site.INSTALL_MESSAGES if m not in says]
    assert not missing, f"{notebook.name}: install messages left English: {missing}"
    left = english_install_comments(source)
    assert not left, f"{notebook.name}: install cell comments left English: {left}"
    for spanish in says.values():
        words = english_words(re.sub(r"\{[^{}]*\}", " ", spanish))  # not its {placeholders}
        assert not words, f"{notebook.name}: {spanish!r} reads English"
    ran = subprocess.run([sys.executable, "-c", source], cwd=tmp_path, capture_output=True,
                         text=True, timeout=120, env={**os.environ, "PYTHONPATH": ""})
    assert ran.returncode == 0, ran.stderr
    import importlib.metadata as md
    printed = ran.stdout.strip()
    assert md.version("rikin") in printed and not english_words(printed), printed


def test_an_english_exercise_install_cell_speaks_english() -> None:
    """English notebooks carry no translations: their install cell says the templates."""
    for notebook in sorted((ROOT / "exercises").glob("*.ipynb")):
        assert _says(_install_source(notebook)) == {}, notebook.name


@pytest.mark.book
@pytest.mark.slow
def test_the_spanish_chapter_downloads_install_cell_speaks_spanish(spanish_site: Path) -> None:
    """The install cell of every chapter notebook a Spanish reader downloads, and of the
    exercises the Spanish edition publishes, has every message and comment in Spanish."""
    notebooks = [*sorted((spanish_site / "_sources").rglob("*.ipynb")),
                 *sorted((spanish_site / rikin_site.EXERCISES_PATH).glob("*.ipynb"))]
    assert len(notebooks) >= 10, notebooks
    for notebook in notebooks:
        says = _says(_install_source(notebook))
        missing = [m for m in rikin_site.INSTALL_MESSAGES if m not in says]
        assert not missing, f"{notebook}: install messages left English: {missing}"
        left = english_install_comments(_install_source(notebook))
        assert not left, f"{notebook}: install cell comments left English: {left}"


# ------------------------------------------------------------------ the exercises' drawing
def test_the_exercises_drawing_writes_no_word() -> None:
    """The drawing of each exercise arm is made once, by its solution's cell tagged
    ``figure-source``, and attached to the notebook in every language: the texts that
    cell writes on it are symbols, numbers and joint types ("PPP, q = (1.0, ...)")."""
    for solution in sorted((ROOT / "solutions").glob("*.ipynb")):
        cells = json.loads(solution.read_text(encoding="utf-8"))["cells"]
        sources = ["".join(c["source"]) for c in cells
                   if "figure-source" in c.get("metadata", {}).get("tags", [])]
        assert len(sources) == 1, solution.name
        texts = [n.value for n in ast.walk(ast.parse(sources[0]))
                 if isinstance(n, ast.Constant) and isinstance(n.value, str)]
        words = [w for t in texts for w in re.findall(r"[A-Za-z]{2,}", t)
                 if not re.fullmatch(r"[RP]{2,6}", w)]
        assert not words, f"{solution.name}: the drawing says {words} in every language"
