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
    for entry in TOC.get("chapters", []):
        files.append(entry["file"])
        files += [sub["file"] for sub in entry.get("sections", [])]
    return files


PAGES = _toc_files()
CHAPTERS = PAGES[1:]  # everything after the introduction
CODE_CELL = re.compile(r"^```\{code-cell\}[^\n]*\n(.*?)^```", re.S | re.M)


def _source(page: str) -> str:
    return (ROOT / f"{page}.md").read_text(encoding="utf-8")


def _code_cells(text: str) -> list[str]:
    return CODE_CELL.findall(text)


def test_toc_lists_the_seven_chapters() -> None:
    names = [Path(p).name for p in CHAPTERS]
    assert names == [
        "conventions",
        "planar",
        "angular",
        "dh_product",
        "decoupling",
        "epson_c4",
        "exercises",
    ], names


@pytest.mark.parametrize("page", PAGES)
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
    assert sphinx["local_extensions"] == {"rikin_book": "book/_ext"}
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
    spec = CONFIG["sphinx"]["config"]["rikin_pip_spec"]
    cell = ext.install_cell(spec)
    compile(cell.source, "install-cell", "exec")
    assert repr(spec) in cell.source and 'find_spec("rikin")' in cell.source
    assert "remove-cell" in cell.metadata["tags"]
