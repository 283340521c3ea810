"""The notebook a page publishes has its outputs also when a cached build did not run it.

``tools/dev.py book --cached`` builds with ``nb_execution_mode: cache``: a page re-read
whose code jupyter-cache already ran is rendered from the cached outputs, not executed.
myst-nb 1.4 merges those outputs into a *copy* of the page's notebook
(``NotebookClientCache``) and writes ``jupyter_execute/<page>.ipynb`` from the notebook it
read, which has none; book/_ext/rikin_book.py publishes that file as the page's download
(``_sources/<page>.ipynb``), which then offered no output at all (and the student's
download test, tests/test_book_download_language.py, found nothing to compare).
``rikin_book.with_cached_outputs`` gives the published notebook the outputs the page shows.

A small Sphinx project with myst-nb, built twice in cache mode, the page touched in
between (as after an edit of its text), one kernel run in all.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_book  # noqa: E402

PAGE = """---
jupytext:
  text_representation:
    format_name: myst
kernelspec:
  name: python3
  display_name: Python 3
---
# A page

```{code-cell} ipython3
print("the wrist centre")
```

Some text.

```{code-cell} ipython3
:tags: [remove-input]

6 * 7
```
"""


def _build(src: Path, out: Path) -> Path:
    """Build ``src`` into ``out/html``; the notebook myst-nb wrote for the page."""
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-q", str(src),
                           str(out / "html")], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out / "jupyter_execute" / "index.ipynb"


def _outputs(nb: nbformat.NotebookNode) -> list[list[str]]:
    """Each code cell's outputs, as the text they show."""
    return [[o.get("text") or o.get("data", {}).get("text/plain", "") for o in cell.outputs]
            for cell in nb.cells if cell.cell_type == "code"]


@pytest.fixture(scope="module")
def cached_build(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list, Path]:
    """The project built twice: (its cache, the first build's outputs, the notebook the
    second build wrote)."""
    root = tmp_path_factory.mktemp("cached")
    src, cache = root / "src", root / "cache"
    src.mkdir()
    (src / "conf.py").write_text(
        f'extensions = ["myst_nb"]\nnb_execution_mode = "cache"\n'
        f"nb_execution_cache_path = {str(cache)!r}\nnb_execution_timeout = 300\n",
        encoding="utf-8")
    page = src / "index.md"
    page.write_text(PAGE, encoding="utf-8")
    first = _outputs(nbformat.read(_build(src, root / "_build"), as_version=4))
    later = time.time() + 60  # newer than the first build's reading of it
    os.utime(page, (later, later))  # an edit of the text: the page is read again
    return cache, first, _build(src, root / "_build")


def test_myst_nb_writes_a_cached_page_without_outputs(cached_build: tuple) -> None:
    """The cause (myst-nb 1.4): the page was rendered from the cache, the notebook written
    for it has no output. Should an upgrade of myst-nb write them, this fails, and
    rikin_book.with_cached_outputs is no longer needed."""
    _, first, written = cached_build
    assert first == [["the wrist centre\n"], ["42"]], "the first build ran the page"
    assert _outputs(nbformat.read(written, as_version=4)) == [[], []]


def test_a_cached_page_publishes_the_outputs_it_shows(cached_build: tuple) -> None:
    cache, first, written = cached_build
    assert first == [["the wrist centre\n"], ["42"]], "the first build ran the page"
    nb = nbformat.read(written, as_version=4)

    assert rikin_book.with_cached_outputs(nb, cache)

    assert _outputs(nb) == first
    assert [c.execution_count for c in nb.cells if c.cell_type == "code"] == [1, 2]
    assert "language_info" in nb.metadata
    assert "remove-input" in nb.cells[-1].metadata.get("tags", []), "the page's tags kept"


def test_outputs_are_taken_only_for_the_code_the_cache_ran(cached_build: tuple,
                                                             tmp_path: Path) -> None:
    cache, _, written = cached_build
    nb = nbformat.read(written, as_version=4)
    nb.cells[-1].source = "6 * 9"  # code the cache never ran
    assert not rikin_book.with_cached_outputs(nb, cache)
    assert _outputs(nb)[-1] == _outputs(nbformat.read(written, as_version=4))[-1]
    assert not rikin_book.with_cached_outputs(nb, tmp_path / "no-cache")
