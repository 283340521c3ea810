"""Static checks on the book's sources (fast: nothing is built or executed).

* every page in ``_toc.yml`` exists as a MyST markdown notebook (jupytext front matter,
  a Python kernel) and no chapter is stored as ``.ipynb`` (no outputs in git);
* every chapter after the introduction has an errata section with an admonition, and
  code cells that assert what the chapter claims;
* randomness in the chapters is seeded;
* the offline-MathJax and notebook-publishing extension is wired up and its MathJax
  files are installed.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
CONFIG = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
TOC = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))


def _toc_files() -> list[str]:
    files = [TOC["root"]]
    parts = TOC.get("parts") or [{"chapters": TOC.get("chapters", [])}]
    for entry in (c for part in parts for c in part["chapters"]):
        files.append(entry["file"])
        files += [sub["file"] for sub in entry.get("sections", [])]
    return files


PAGES = _toc_files()
#: The instructor's guide (a part of its own): plain MyST markdown, nothing executed.
INSTRUCTOR = [p for p in PAGES if p.startswith("book/instructor/")]
#: Reference pages: plain MyST markdown, nothing executed, no errata.
REFERENCE_PAGES = ["book/glossary", "book/references", *INSTRUCTOR]
NOTEBOOK_PAGES = [p for p in PAGES if p not in REFERENCE_PAGES]
#: Sections that teach beyond the lessons (no lesson, so no errata of one).
SECTIONS = ["book/own_arm"]
#: Chapters and appendices beyond the lessons: no lesson, so no errata of one.
BEYOND = ["book/what_is_ik", "book/path", "book/numbers"]
CHAPTERS = [p for p in NOTEBOOK_PAGES[1:]
            if p not in BEYOND and p not in SECTIONS]  # the lessons' chapters
#: Chapters with the full teaching apparatus (item 5 of issue 16; issue 30: every one).
TAUGHT = ["book/what_is_ik", "book/conventions", "book/planar", "book/angular",
          "book/dh_product", "book/decoupling", "book/epson_c4", "book/path"]
#: Chapters whose asserting cells are all folded away.
FOLDED = ["book/what_is_ik", "book/conventions", "book/planar", "book/angular",
          "book/dh_product", "book/decoupling", "book/own_arm", "book/epson_c4",
          "book/path", "book/numbers"]
CODE_CELL = re.compile(r"^```\{code-cell\}[^\n]*\n(.*?)^```", re.S | re.M)


def _source(page: str) -> str:
    return (ROOT / f"{page}.md").read_text(encoding="utf-8")


def _code_cells(text: str) -> list[str]:
    return CODE_CELL.findall(text)


def test_toc_lists_the_chapters() -> None:
    names = [Path(p).name for p in PAGES[1:] if p not in INSTRUCTOR]
    assert names == [
        "what_is_ik",
        "conventions",
        "planar",
        "angular",
        "dh_product",
        "decoupling",
        "own_arm",
        "epson_c4",
        "path",
        "exercises",
        "numbers",
        "glossary",
        "references",
    ], names


def test_the_instructors_guide_is_a_part_of_the_book() -> None:
    parts = {p["caption"]: p["chapters"] for p in TOC["parts"]}
    guide = parts["Instructor's guide"]
    files = [guide[0]["file"]] + [s["file"] for s in guide[0]["sections"]]
    assert [Path(f).name for f in files] == [
        "index",
        "hosting",
        "releasing",
        "grading",
        "lms",
        "gradescope",
        "gradebook",
        "report",
    ]
    for f in files:
        assert (ROOT / f"{f}.md").is_file(), f
    for png in ("class-report.png", "class-report-tests.png"):
        assert (BOOK / "instructor" / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("page", NOTEBOOK_PAGES)
def test_page_is_a_myst_notebook(page: str) -> None:
    path = ROOT / f"{page}.md"
    assert path.is_file(), f"{page} is listed in _toc.yml but {path} does not exist"
    text = _source(page)
    front = yaml.safe_load(text.split("---", 2)[1])
    assert front["jupytext"]["text_representation"]["format_name"] == "myst", page
    assert front["kernelspec"]["language"] == "python", page
    assert _code_cells(text), f"{page} has no code cell: it would not be executed"


def test_no_stored_notebooks_in_book() -> None:
    stored = sorted(
        str(p.relative_to(ROOT))
        for p in BOOK.rglob("*.ipynb")
        if ".ipynb_checkpoints" not in p.parts
    )
    assert not stored, f"chapters are MyST markdown; stored notebooks (with outputs?): {stored}"


@pytest.mark.parametrize("page", CHAPTERS)
def test_chapter_has_an_errata_section_checked_by_code(page: str) -> None:
    text = _source(page)
    assert re.search(r"^#+ .*Errata", text, re.M), f"{page}: no Errata heading"
    boxes = re.findall(r"^```\{admonition\} Errata[^\n]*\n:class: warning", text, re.M)
    assert boxes, f"{page}: no errata admonition (```{{admonition}} Errata... with :class: warning)"
    asserts = sum(len(re.findall(r"^\s*assert ", cell, re.M)) for cell in _code_cells(text))
    assert asserts >= 1, f"{page}: no code cell asserts anything"


@pytest.mark.parametrize("page", PAGES)
def test_randomness_is_seeded(page: str) -> None:
    code = "\n".join(_code_cells(_source(page)))
    assert "default_rng()" not in code, f"{page}: unseeded numpy Generator"
    assert not re.search(r"np\.random\.(rand|randn|uniform|normal|random)\(", code), (
        f"{page}: global numpy random state; use a seeded default_rng"
    )


@pytest.mark.parametrize("page", CHAPTERS)
def test_chapter_uses_rikin(page: str) -> None:
    code = "\n".join(_code_cells(_source(page)))
    assert re.search(r"^import rikin$", code, re.M), f"{page} does not import rikin"


def test_doc_references_point_to_pages() -> None:
    stems = {Path(p).name for p in PAGES}
    for page in PAGES:
        for target in re.findall(r"\{doc\}`(?:[^`<]*<)?([^`>]+)>?`", _source(page)):
            assert Path(target).name in stems, f"{page}: {{doc}} to unknown page {target!r}"


def _extension():
    spec = importlib.util.spec_from_file_location("rikin_book", BOOK / "_ext" / "rikin_book.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_extension_is_configured() -> None:
    sphinx = CONFIG["sphinx"]
    assert sphinx["local_extensions"] == {"rikin_book": "book/_ext", "rikin_i18n": "book/_ext"}
    assert "mathjax_path" not in sphinx.get("config", {}), "rikin_book sets mathjax_path itself"
    assert CONFIG["launch_buttons"]["thebe"] is False


def test_mathjax_is_installed_locally() -> None:
    ext = _extension()
    src = ext.mathjax_source()
    assert (src / "tex-chtml.js").is_file()
    assert "3.2" in (src / "tex-chtml.js").read_text(encoding="utf-8", errors="replace")[:400000]
    for part in ext.MATHJAX_PARTS:
        assert (src / part).exists(), part
    assert not ext.MATHJAX_ENTRY.startswith(("http:", "https:", "//"))


def test_published_notebooks_install_rikin_first() -> None:
    ext = _extension()
    site = ext.rikin_site
    base = site.read_base_url()
    assert base == CONFIG["html"]["baseurl"].rstrip("/") + "/"
    wheel = f"{base}_static/dist/rikin-0.0.0-py3-none-any.whl#sha256={'0' * 64}"
    cell = site.install_cell(base, "0.0.0", wheel, extra_tags=("remove-cell",))
    compile(cell["source"], "install-cell", "exec")
    assert repr(wheel) in cell["source"] and repr(base) in cell["source"]
    assert "remove-cell" in cell["metadata"]["tags"]


def _all_sources() -> dict[str, str]:
    return {p: _source(p) for p in PAGES}


def _labels() -> set[str]:
    labels: set[str] = set()
    for text in _all_sources().values():
        labels |= set(re.findall(r"^\(([\w-]+)\)=\s*$", text, re.M))
    return labels


def test_ref_roles_point_to_labels() -> None:
    labels = _labels()
    for page, text in _all_sources().items():
        for target in re.findall(r"\{ref\}`(?:[^`<]*<)?([^`>]+)>?`", text):
            assert target in labels, f"{page}: {{ref}} to unknown label {target!r}"


def _glossary_terms() -> set[str]:
    text = _source("book/glossary")
    body = re.search(r"^```\{glossary\}\n(.*?)^```", text, re.S | re.M)
    assert body, "book/glossary.md has no glossary directive"
    return {line.strip().lower() for line in body.group(1).splitlines()
            if line.strip() and not line.startswith((" ", "\t"))}


def test_term_roles_point_to_glossary_entries() -> None:
    terms = _glossary_terms()
    used = 0
    for page, text in _all_sources().items():
        for term in re.findall(r"\{term\}`(?:[^`<]*<)?([^`>]+)>?`", text):
            used += 1
            assert term.lower() in terms, f"{page}: {{term}} {term!r} is not in the glossary"
    assert used >= 10, f"only {used} {{term}} links from the chapters to the glossary"


def test_glossary_has_the_lessons_terms() -> None:
    text = _source("book/glossary").lower()
    for word in ["postura", "configuración", "límites articulares", "punto de calibración",
                 "hombro", "espacio articular", "espacio operativo", "formulación cerrada",
                 "redundancia", "junta", "muñeca", "desacople", "codo arriba", "eslabón"]:
        assert word in text, f"the glossary does not explain the lessons' term {word!r}"


@pytest.mark.parametrize("page", TAUGHT + SECTIONS)
def test_chapter_has_the_teaching_apparatus(page: str) -> None:
    text = _source(page)
    first_code = text.index("```{code-cell}")
    what = "section" if page in SECTIONS else "chapter"
    assert f"```{{admonition}} In this {what}" in text[:first_code], (
        f"{page}: no 'In this {what}' box (objectives and prerequisites) before the first cell"
    )
    box = text[text.index(f"```{{admonition}} In this {what}"):first_code]
    assert "You will be able to" in box and "It assumes" in box, page
    for heading in ("Summary", "Check yourself", "Exercises"):
        assert re.search(rf"^## {heading}\s*$", text, re.M), f"{page}: no '## {heading}' section"
    check = text[text.index("## Check yourself"):]
    assert len(re.findall(r"^(?:```|:::)\{dropdown\}", check, re.M)) >= 3, (
        f"{page}: fewer than 3 self-check questions with hidden answers ({{dropdown}})"
    )
    assert "{ref}`" in text and "references" in text, f"{page}: cites no reference"


@pytest.mark.parametrize("page", FOLDED)
def test_checks_are_folded(page: str) -> None:
    """Cells that assert are folded away (hide-input / hide-cell / remove-input)."""
    blocks = re.findall(r"^```\{code-cell\}[^\n]*\n(.*?)^```", _source(page), re.S | re.M)
    folded = re.compile(r"(?:^:tags: |^tags: )\[[^\]]*(hide-input|hide-cell|remove-input)", re.M)

    def options(block: str) -> str:
        """A cell's options: ``:key: value`` lines, or the YAML between ``---`` lines."""
        if block.startswith("---\n"):
            return block.split("\n---\n", 1)[0]
        return "\n".join(line for line in block.splitlines() if line.startswith(":"))

    unfolded = [b.splitlines()[0] if b.strip() else "" for b in blocks
                if re.search(r"^\s*assert ", b, re.M) and not folded.search(options(b))]
    assert not unfolded, (
        f"{page}: {len(unfolded)} asserting cells are shown unfolded: {unfolded[:3]}")


def test_exercises_chapter_states_the_problems() -> None:
    """The Exercises chapter states each arm's problem with its drawing (not a generated
    list of notebook headings and grader weights)."""
    text = _source("book/exercises")
    for arm in ("cartesian", "cylindrical", "spherical", "scara"):
        assert f'arm_figure("{arm}",' in text, f"exercises: no drawing of the {arm} arm"
        assert f"{{download}}`{arm}.ipynb" in text, f"exercises: no link to {arm}.ipynb"
    for heading in ("Cartesian", "Cylindrical", "Spherical", "SCARA", "Angular"):
        assert re.search(rf"^### \d\. {heading}", text, re.M), f"exercises: no problem {heading}"
    assert "How your notebook is graded" not in text, "exercises: grader weights copied in"
    for page in TAUGHT:
        assert f"{{doc}}`{Path(page).name}`" in text, f"exercises: no pointer to {page}'s exercises"


# ------------------------------------------------------------------ figures (issue 16, item 6)
def _cell_options(block: str) -> dict:
    """The YAML options of a code cell (between ``---`` lines), or {}."""
    if not block.startswith("---\n"):
        return {}
    return yaml.safe_load(block.split("\n---\n", 1)[0][4:]) or {}


def _draws(block: str) -> bool:
    code = block.split("\n---\n", 1)[-1] if block.startswith("---\n") else block
    return bool(re.search(r"plt\.show\(\)|\.savefig\(", code))


@pytest.mark.parametrize("page", NOTEBOOK_PAGES)
def test_every_figure_is_numbered_captioned_and_referenced(page: str) -> None:
    """A cell that draws is a numbered figure (mystnb figure: caption and name) with real
    alt text, and the text refers to it with {numref}; so is every glued figure."""
    text = _source(page)
    names = []
    for block in _code_cells(text):
        opts = _cell_options(block)   # raises on bad YAML, which the build would too
        if not _draws(block):
            continue
        nb = opts.get("mystnb", {})
        fig, image = nb.get("figure", {}), nb.get("image", {})
        first = block.split("\n---\n", 1)[-1].strip().splitlines()[0]
        assert fig.get("caption") and fig.get("name"), f"{page}: figure without caption: {first}"
        alt = str(image.get("alt", ""))
        assert len(alt.split()) >= 8, f"{page}: figure {fig['name']} has no real alt text"
        code = block.split("\n---\n", 1)[-1]
        # myst-nb gives every output of the cell the figure's name: draw nothing else
        assert not re.search(r"^\s*(ok|display|print|say)\(", code, re.M), (
            f"{page}: figure {fig['name']} shares its cell with other output")
        names.append(fig["name"])
    for m in re.finditer(r"^```\{glue:figure\} \S+\n((?::\w+:.*\n)+)", text, re.M):
        opts = dict(re.findall(r"^:(\w+): (.*)$", m.group(1), re.M))
        assert opts.get("name") and len(opts.get("alt", "").split()) >= 8, (
            f"{page}: glued figure without name or alt text: {m.group(0)[:80]}")
        names.append(opts["name"])
    for name in names:
        assert f"{{numref}}`{name}`" in text, f"{page}: figure {name} is never referred to"
    assert len(set(names)) == len(names), f"{page}: two figures share a name"


@pytest.mark.parametrize("page", PAGES)
def test_directives_open_with_a_fence_that_allows_their_title(page: str) -> None:
    """A directive whose title has inline code (a backtick) must open with a colon fence
    (``:::{dropdown} ...``): CommonMark forbids a backtick in a backtick fence's info
    string, so "```{dropdown} Why `x`?" is no fence at all: the reader gets the raw markup,
    and the next fence turns the following text into a code block."""
    bad = [
        f"{page}.md:{n}: {line[:70]}"
        for n, line in enumerate(_source(page).splitlines(), 1)
        if re.match(r"^`{3,}\{[a-z-]+\}", line) and "`" in line.lstrip("`")
    ]
    assert not bad, "use :::{directive} ... ::: for these:\n" + "\n".join(bad)


# ------------------------------------------------------------------ issue 30
#: Columns of code that fit the text column at 1280 px (the book's stylesheet sets the
#: code font so; tests/test_book_browser.py checks that nothing wraps there).
CODE_COLUMNS = 80
PYTHON_BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


@pytest.mark.parametrize("page", NOTEBOOK_PAGES)
def test_code_lines_fit_80_columns(page: str) -> None:
    """Every line of code on the page, folded cells too (a reader unfolds them), is at most
    80 characters: a longer one wraps on a laptop and reads as a new statement."""
    text = _source(page)
    # a cell's options (its caption, alt text, tags) are not shown as code
    code = [b.split("\n---\n", 1)[1] if b.startswith("---\n") else b
            for b in _code_cells(text)]
    blocks = code + PYTHON_BLOCK.findall(text)
    long = [line for block in blocks for line in block.splitlines()
            if len(line) > CODE_COLUMNS and not line.startswith(":")]
    assert not long, f"{page}: {len(long)} code lines over {CODE_COLUMNS} columns: {long[:3]}"


def _first_ik_page() -> int:
    for i, page in enumerate(PAGES):
        if re.search(r"\.ik\(", "\n".join(_code_cells(_source(page)))):
            return i
    raise AssertionError("no page solves IK")


def test_tolerances_are_introduced_where_needed() -> None:
    """No tolerance of rikin.tolerances is named before the book has solved IK once, and
    Conventions names none: each is introduced in the chapter that first needs it (the
    Numbers appendix collects them)."""
    from rikin import tolerances

    names = [n for n in dir(tolerances) if n.endswith("_TOL")]
    assert len(names) >= 8, names
    first_ik = _first_ik_page()
    for name in names:
        pages = [i for i, p in enumerate(PAGES) if name in _source(p)]
        assert pages, f"{name} is never introduced in the book"
        assert pages[0] >= first_ik, (
            f"{name} is first named in {PAGES[pages[0]]}, before any IK is shown "
            f"({PAGES[first_ik]})")
    assert not [n for n in names if n in _source("book/conventions")]
    assert "| name | value |" not in _source("book/conventions")


#: Pages whose prose must link the glossary where a glossary term first appears.
GLOSSED = TAUGHT
#: Glossary terms to look for in prose, with the plain words that count as a use.
_PROSE_FORMS = {
    "wrist centre": ["wrist centre"],
    "spherical wrist": ["spherical wrist"],
    "kinematic decoupling": ["kinematic decoupling"],
    "singularity": ["singularity", "singular"],
    "workspace": ["workspace"],
    "joint limits": ["joint limits"],
    "redundancy": ["redundancy", "redundant"],
    "law of cosines": ["law of cosines"],
    "wrist flip": ["wrist flip"],
    "branch": ["branch"],
    "homogeneous transform": ["homogeneous transform"],
    "reachable": ["reachable"],
}


def _prose(text: str) -> str:
    """The page's prose: no front matter, code cells, math, headings or directive lines."""
    text = text.split("---", 2)[2]
    text = re.sub(r"^```\{code-cell\}.*?^```", "", text, flags=re.S | re.M)
    text = re.sub(r"^```[a-z]+\n.*?^```[ \t]*$", "", text, flags=re.S | re.M)
    text = re.sub(r"\$\$.*?\$\$", "", text, flags=re.S)
    text = re.sub(r"\$[^$\n]+\$", "", text)
    text = re.sub(r"^#.*$", "", text, flags=re.M)
    text = re.sub(r"^(?:```|:::)\{[^\n]*$|^:\w+:.*$", "", text, flags=re.M)
    return text


@pytest.mark.parametrize("page", GLOSSED)
def test_glossary_linked_where_a_term_first_appears(page: str) -> None:
    """Where a chapter's prose first uses a glossary term, it links the glossary
    ({term}`...`), so a reader meeting the word for the first time can look it up."""
    prose = _prose(_source(page))
    problems = []
    for term, forms in _PROSE_FORMS.items():
        pattern = "|".join(re.escape(f) for f in forms)
        first = re.search(rf"(?i)(?<![\w-])(?:{pattern})(?!\w)", prose)
        if first is None:
            continue
        before = prose[max(0, first.start() - 60):first.start()]
        linked = re.search(r"\{term\}`[^`]*$", before)
        if not linked:
            problems.append(f"{term!r}: {prose[first.start() - 30:first.end() + 20]!r}")
    assert not problems, f"{page}: first use without a glossary link: " + "; ".join(problems)


def test_glossary_gives_juntas() -> None:
    """The handwritten notes write 'Juntas' (joints): the glossary has the plural."""
    assert "juntas" in _source("book/glossary").lower()
