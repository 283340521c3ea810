"""book/_ext/rikin_markdown.py: the book's MyST as plain Jupyter Markdown (issue 28 item 3).

Fast checks without a build: every chapter's markdown converts with nothing of MyST left,
and each construct becomes what Jupyter renders. The published notebooks of a real build
are checked in tests/test_student_download.py (no MyST left, every link lands on a page
and an anchor of the book).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_markdown as md  # noqa: E402

BOOK = "https://me.github.io/ik/"


def links(role: str, target: str, text: str | None) -> md.Link | None:
    """A stand-in for the book build's resolver: every target exists, figures are Fig. 7."""
    if role == "numref":
        return (text or "Fig. %s").replace("%s", "7").replace("{number}", "7"), \
            f"{BOOK}book/x.html#{target}"
    return text or f"<{target}>", f"{BOOK}book/{target}.html"


def _markdown_of(page: Path) -> str:
    """A chapter's text without its code cells and front matter (what notebooks' markdown
    cells hold)."""
    text = page.read_text(encoding="utf-8")
    text = re.sub(r"\A---\n.*?\n---\n", "", text, flags=re.S)
    return re.sub(r"(?ms)^```\{code-cell\}.*?^```\s*$", "", text)


@pytest.mark.parametrize("page", sorted((ROOT / "book").glob("*.md")), ids=lambda p: p.stem)
def test_every_chapter_converts_with_no_myst_left(page: Path) -> None:
    text = _markdown_of(page)
    out = md.to_jupyter(text, links)
    assert md.myst_left(out) == [], md.myst_left(out)[:5]
    if md.myst_left(text):  # the chapter uses MyST: the conversion changed something
        assert out != text


def test_each_construct_becomes_jupyter_markdown() -> None:
    text = "\n".join([
        "(chapter-x)=", "# Title", "",
        "See {numref}`fig-a`, {term}`joint limits <joint limit>` and `{term}` in code, "
        "{doc}`conventions`, {math}`x^2`.",
        "", "````{admonition} Errata: foo", ":class: warning", "1. item $x$ with {ref}`c4-gui`",
        "", "   ```python", "   x = 1  # {numref}`stays`", "   ```", "````", "",
        ":::{dropdown} Why `q` and $x$?", "Body {term}`branch`.", ":::", "",
        "```{glue:figure} c4-interactive", ":name: fig-c4-interactive", ":alt: An arm", "",
        "Interactive: the IK solutions.", "```", "",
        "```{note}", "A note.", "```",
    ])
    out = md.to_jupyter(text, links)
    assert "(chapter-x)=" not in out and out.startswith("# Title")
    assert f"[Fig. 7]({BOOK}book/x.html#fig-a)" in out
    assert f"[joint limits]({BOOK}book/joint limit.html)" in out and "`{term}` in code" in out
    assert "$x^2$" in out
    assert "> **Errata: foo**" in out and ":class:" not in out
    assert f"> 1. item $x$ with [<c4-gui>]({BOOK}book/c4-gui.html)" in out
    assert ">    x = 1  # {numref}`stays`" in out          # code is never changed
    assert "<details>\n<summary>Why <code>q</code> and $x$?</summary>" in out
    assert "</details>" in out and f"Body [<branch>]({BOOK}book/branch.html)." in out
    assert "**Fig. 7.** Interactive: the IK solutions. (the output of the cell above)" in out
    assert "> **Note**\n>\n> A note." in out
    assert md.myst_left(out) == []


def test_myst_left_finds_what_a_notebook_would_show_as_text() -> None:
    assert md.myst_left("(label)=\n# T")[0].startswith("target")
    assert md.myst_left("see {numref}`fig-x`")[0].startswith("role")
    assert md.myst_left("```{dropdown} x\ny\n```")[0].startswith("directive")
    assert md.myst_left(":class: tip")[0].startswith("option")
    assert md.myst_left("`{numref}` in code and\n```\n{term}`x`\n```") == []
