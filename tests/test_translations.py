"""The Spanish edition's catalogues (book/locales/es/LC_MESSAGES/book/*.po) are complete,
current and faithful: every message translated and none fuzzy, one catalogue per page with
exactly the messages the sources have today, and each translation keeping its message's
numbers, formulas and cross-references.

``python3 tools/dev.py translations`` refreshes the catalogues after the English text
changed: new messages come in empty and changed ones fuzzy, and these tests then fail until
a translator has dealt with each.

One more catalogue per language, ``cells.po``, holds the texts the pages' code cells print
(the ✓ lines, table headers and figure words; rikin.booktext): the same checks, plus that it
holds exactly the templates the pages have today and that each translation keeps the
template's placeholders and numbers in their order (the editions' numbers are compared in
order, tests/test_book_editions.py).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest
from babel.messages.pofile import read_po

ROOT = Path(__file__).resolve().parents[1]
LOCALES = ROOT / "book" / "locales"
LANGUAGES = ("es",)
#: The catalogue of the texts the code cells print (not a page's).
CELLS = "cells"
sys.path.insert(0, str(ROOT / "tools"))
import cell_messages  # noqa: E402


def _catalogues(language: str) -> dict[str, Path]:
    folder = LOCALES / language / "LC_MESSAGES"
    return {str(p.relative_to(folder).with_suffix("")): p for p in sorted(folder.rglob("*.po"))}


def _pages() -> list[str]:
    """The pages the book builds (every ``file:`` of _toc.yml)."""
    toc = (ROOT / "_toc.yml").read_text(encoding="utf-8")
    return sorted(set(re.findall(r"(?:root|file):\s*(\S+)", toc)))


def _messages(path: Path) -> list:
    with path.open("rb") as f:
        return [m for m in read_po(f) if m.id]


@pytest.mark.parametrize("language", LANGUAGES)
def test_every_page_has_a_catalogue(language):
    assert sorted(set(_catalogues(language)) - {CELLS}) == _pages()
    assert CELLS in _catalogues(language), "no catalogue of the cells' texts"


# ----------------------------------------------------- the texts the code cells print
def stale_cell_messages(catalogue: Path, book: Path) -> list[str]:
    """Templates of the pages of ``book`` missing from ``catalogue``, and entries of the
    catalogue no page has any more (tools/cell_messages.py, rikin.booktext)."""
    source = {m for found in cell_messages.book_messages(book).values() for m in found}
    held = {m.id for m in _messages(catalogue)}
    return ([f"new in the pages, not in the catalogue: {m[:70]!r}" for m in sorted(source - held)]
            + [f"in the catalogue, gone from the pages: {m[:70]!r}" for m in sorted(held - source)])


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_cells_catalogue_holds_exactly_the_templates_of_the_pages(language):
    stale = stale_cell_messages(_catalogues(language)[CELLS], ROOT / "book")
    assert not stale, (f"{len(stale)} entries of {CELLS}.po are stale: run python3 tools/dev.py "
                       "translations, then translate what it marks\n" + "\n".join(stale[:40]))


def test_a_changed_template_makes_the_cells_catalogue_stale(tmp_path):
    """Change one ✓ template of a copy of decoupling.md: the catalogue is stale (the new
    template is missing, the old one is left over); the page as it is is not."""
    page = (ROOT / "book" / "decoupling.md").read_text(encoding="utf-8")
    old = "the transpose is the inverse (to {inv:.0e}), and the lesson's "
    assert page.count(old) == 1
    catalogue = _catalogues("es")[CELLS]
    for name, text in (("same", page), ("changed", page.replace(old, old.replace("to", "up to")))):
        (tmp_path / name / "book").mkdir(parents=True)
        (tmp_path / name / "book" / "decoupling.md").write_text(text, encoding="utf-8")
    same = {m for m in stale_cell_messages(catalogue, tmp_path / "same" / "book")
            if m.startswith("new")}
    changed = stale_cell_messages(catalogue, tmp_path / "changed" / "book")
    assert not same
    assert any(m.startswith("new") and "up to {inv:.0e}" in m for m in changed)
    assert any(m.startswith("in the catalogue") and "(to {inv:.0e})" in m for m in changed)


#: What a cell text's translation keeps in order: ``{placeholders}`` (with their format) and
#: the numbers written in the template.
_TOKEN = re.compile(r"\{[^{}]*\}|(?<![\w.])-?\d+(?:\.\d+)?(?![\w])")


def reordered(catalogue: Path) -> list[str]:
    """Translations whose placeholders and numbers are not the template's, in its order."""
    bad = []
    for m in _messages(catalogue):
        if m.string and _TOKEN.findall(m.id) != _TOKEN.findall(m.string):
            bad.append(f"{m.id[:60]!r}: {_TOKEN.findall(m.id)} -> {_TOKEN.findall(m.string)}")
    return bad


@pytest.mark.parametrize("language", LANGUAGES)
def test_cell_translations_keep_placeholders_and_numbers_in_order(language, tmp_path):
    bad = reordered(_catalogues(language)[CELLS])
    assert not bad, "translations that drop, change or move a value:\n" + "\n".join(bad[:30])
    # the check sees a moved value and a changed format
    for msgstr in ("{b} y {a:.1e}", "{a:.2e} y {b}"):
        broken = tmp_path / f"{len(msgstr)}.po"
        broken.write_text(f'msgid "{{a:.1e}} and {{b}}"\nmsgstr "{msgstr}"\n', encoding="utf-8")
        assert len(reordered(broken)) == 1


@pytest.mark.parametrize("language", LANGUAGES)
def test_every_message_is_translated_and_none_is_fuzzy(language):
    untranslated, fuzzy = [], []
    for page, path in _catalogues(language).items():
        for m in _messages(path):
            if m.fuzzy:
                fuzzy.append(f"{page}: {m.id[:70]!r}")
            elif not m.string:
                untranslated.append(f"{page}: {m.id[:70]!r}")
    assert not fuzzy, f"{len(fuzzy)} fuzzy (the English changed; check each):\n" + "\n".join(
        fuzzy[:40])
    assert not untranslated, f"{len(untranslated)} untranslated:\n" + "\n".join(untranslated[:40])


#: What a translation must keep exactly as its message has it: inline and display maths,
#: cross-reference roles with their targets, inline code, and the numbers outside those.
_MATH = re.compile(r"\$\$.*?\$\$|\$[^$]+\$", re.S)
_ROLE = re.compile(r"\{(?:doc|ref|numref|eq|term|download|glue:\w+|glue)\}`[^`]*`")
_CODE = re.compile(r"``?[^`]+``?")
_NUMBER = re.compile(r"(?<![\w.])-?\d+(?:[.,]\d+)?(?![\w])")


def _kept(text: str) -> Counter:
    parts: Counter = Counter()
    for pattern in (_MATH, _ROLE):
        parts.update(pattern.findall(text))
        text = pattern.sub(" ", text)
    parts.update(_CODE.findall(text))
    text = _CODE.sub(" ", text)
    parts.update(n.replace(",", ".") for n in _NUMBER.findall(text))
    return parts


def _role_target(role: str) -> str:
    """``{ref}`text <target>``` -> ``{ref}target``; the visible text may be translated."""
    name, body = role.split("`", 1)
    body = body.rstrip("`")
    m = re.search(r"<([^<>]+)>\s*$", body)
    return f"{name}{m.group(1) if m else body}"


def _faithful_parts(text: str) -> Counter:
    parts = _kept(text)
    out: Counter = Counter()
    for part, n in parts.items():
        key = _role_target(part) if _ROLE.fullmatch(part) and "<" in part else part
        if _ROLE.fullmatch(part) and part.startswith("{term}"):
            continue  # a glossary term is written in the reader's language (its target too)
        out[key] += n
    return out


def _translated(catalogues: dict[str, Path]):
    """(page, message) for every translated, not fuzzy message of ``catalogues``."""
    for page, path in catalogues.items():
        for m in _messages(path):
            if m.string and not m.fuzzy:
                yield page, m


def unfaithful(catalogues: dict[str, Path]) -> list[str]:
    """Translations that lose or add a number, formula, code span or reference target."""
    bad = []
    for page, m in _translated(catalogues):
        want, got = _faithful_parts(m.id), _faithful_parts(m.string)
        if want != got:
            bad.append(f"{page}: {m.id[:60]!r}\n    missing {dict(want - got)}, "
                       f"added {dict(got - want)}")
    return bad


@pytest.mark.parametrize("language", LANGUAGES)
def test_translations_keep_numbers_formulas_and_references(language):
    bad = unfaithful(_catalogues(language))
    assert not bad, f"{len(bad)} translations change what they must keep:\n" + "\n".join(bad[:30])


#: A markdown link's target: ``[text](target)`` (the text is translated, the target kept).
_LINK = re.compile(r"\]\(([^()\s]+)(?:\s+\"[^\"]*\")?\)")


def lost_links(catalogues: dict[str, Path]) -> list[str]:
    """Translations whose markdown links do not go where the message's links go."""
    bad = []
    for page, m in _translated(catalogues):
        want, got = Counter(_LINK.findall(m.id)), Counter(_LINK.findall(m.string))
        if want != got:
            bad.append(f"{page}: {m.id[:60]!r}: links {dict(want)}, translated {dict(got)}")
    return bad


@pytest.mark.parametrize("language", LANGUAGES)
def test_translations_keep_link_targets(language):
    bad = lost_links(_catalogues(language))
    assert not bad, f"{len(bad)} translations change a link's target:\n" + "\n".join(bad[:30])


_TERM = re.compile(r"\{term\}`([^`]*)`")


def glossary_terms(glossary_md: Path) -> list[str]:
    """The terms of the ``{glossary}`` in ``glossary_md`` (its unindented lines), in English."""
    text = glossary_md.read_text(encoding="utf-8")
    block = re.search(r"^```\{glossary\}\n(.*?)^```", text, re.S | re.M)
    assert block, f"no {{glossary}} block in {glossary_md}"
    return [line.strip() for line in block.group(1).splitlines()
            if line.strip() and not line[0].isspace() and not line.startswith(":")]


def missing_terms(catalogues: dict[str, Path], terms: list[str]) -> list[str]:
    """``{term}`` roles of the translations whose target is not a term of the translated
    glossary (the ``msgstr`` of each English term of ``terms`` in the glossary catalogue)."""
    glossary = {m.id: m.string for m in _messages(catalogues["book/glossary"])}
    entries = {glossary.get(t, "").strip().lower() for t in terms} - {""}
    bad = []
    for page, m in _translated(catalogues):
        for body in _TERM.findall(m.string):
            target = re.search(r"<([^<>]+)>\s*$", body)
            name = (target.group(1) if target else body).strip()
            if name.lower() not in entries:
                bad.append(f"{page}: {{term}}`{body}`: no glossary entry {name!r}")
    return bad


@pytest.mark.parametrize("language", LANGUAGES)
def test_term_targets_are_entries_of_the_translated_glossary(language):
    terms = glossary_terms(ROOT / "book" / "glossary.md")
    assert len(terms) > 20 and "inverse kinematics" in terms
    bad = missing_terms(_catalogues(language), terms)
    assert not bad, f"{len(bad)} {{term}} targets are not glossary entries:\n" + "\n".join(
        bad[:30])


#: A line MyST reads as a list item, heading or quote rather than as text.
_BLOCK_START = re.compile(r"(\d+[.)]|[-*+]|#{1,6})(\s|$)|>")


def new_blocks(catalogues: dict[str, Path]) -> list[str]:
    """Translations that MyST would parse as a list, heading or quote: a heading
    "1. The target" must be translated "1\\. El objetivo" (a message copied unchanged,
    such as code, is left alone)."""
    bad = []
    for page, m in _translated(catalogues):
        if m.string != m.id and _BLOCK_START.match(m.string):
            bad.append(f"{page}: {m.string[:60]!r} (escape the marker, e.g. 1\\. or \\-)")
    return bad


@pytest.mark.parametrize("language", LANGUAGES)
def test_no_translation_becomes_a_list_heading_or_quote(language):
    bad = new_blocks(_catalogues(language))
    assert not bad, f"{len(bad)} translations start a list, heading or quote:\n" + "\n".join(
        bad[:30])


# ----------------------------------------------------- each check catches what it is for
_BROKEN_CASES = {
    # the broken msgstr of each check: (msgid, msgstr) -> the check that must refuse it
    "number": ("joint 2 turns by 30 degrees", "la articulación 2 gira 3 grados", unfaithful),
    "formula": ("with $q_1 = 0$ the arm", "con $q_1 = 1$ el brazo", unfaithful),
    "reference": ("see {ref}`the wrist <sec-wrist>`", "ver {ref}`la muñeca <sec-muneca>`",
                  unfaithful),
    "link": ("read [the notes](https://example.org/a.pdf)",
             "lee [los apuntes](https://example.org/b.pdf)", lost_links),
    "term": ("a {term}`spherical wrist`", "una {term}`muñeca redonda`", None),
    "heading": ("1. The target", "1. El objetivo", new_blocks),
}


def _catalogue_with(tmp_path: Path, msgid: str, msgstr: str) -> dict[str, Path]:
    """A copy of the Spanish glossary catalogue plus one page catalogue holding one entry."""
    folder = tmp_path / "LC_MESSAGES" / "book"
    folder.mkdir(parents=True)
    glossary = folder / "glossary.po"
    glossary.write_bytes((LOCALES / "es" / "LC_MESSAGES" / "book" / "glossary.po").read_bytes())
    page = folder / "page.po"

    def quoted(text: str) -> str:
        return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'

    page.write_text(f'msgid ""\nmsgstr ""\n"Content-Type: text/plain; charset=UTF-8\\n"\n\n'
                    f"msgid {quoted(msgid)}\nmsgstr {quoted(msgstr)}\n", encoding="utf-8")
    return {"book/glossary": glossary, "book/page": page}


@pytest.mark.parametrize("case", sorted(_BROKEN_CASES))
def test_each_check_refuses_a_broken_catalogue(tmp_path, case):
    msgid, msgstr, check = _BROKEN_CASES[case]
    catalogues = _catalogue_with(tmp_path, msgid, msgstr)
    if check is None:
        problems = missing_terms(catalogues, glossary_terms(ROOT / "book" / "glossary.md"))
    else:
        problems = check(catalogues)
    assert len(problems) == 1 and "page" in problems[0], problems
    # and the same message translated right passes every check
    good = {"number": "la articulación 2 gira 30 grados", "formula": "con $q_1 = 0$ el brazo",
            "reference": "ver {ref}`la muñeca <sec-wrist>`",
            "link": "lee [los apuntes](https://example.org/a.pdf)",
            "term": "una {term}`muñeca esférica`", "heading": "1\\. El objetivo"}[case]
    fixed = _catalogue_with(tmp_path / "fixed", msgid, good)
    terms = glossary_terms(ROOT / "book" / "glossary.md")
    assert not (unfaithful(fixed) + lost_links(fixed) + missing_terms(fixed, terms)
                + new_blocks(fixed))


def test_an_untranslated_or_fuzzy_message_is_refused(tmp_path, monkeypatch):
    """The completeness test fails on a catalogue with an empty or a fuzzy entry."""
    catalogues = _catalogue_with(tmp_path, "joint 2", "")
    page = catalogues["book/page"]
    page.write_text(page.read_text(encoding="utf-8") + '\n#, fuzzy\nmsgid "joint 3"\n'
                    'msgstr "articulación 3"\n', encoding="utf-8")
    monkeypatch.setattr(sys.modules[__name__], "_catalogues", lambda language: {"book/page": page})
    with pytest.raises(AssertionError, match=r"1 fuzzy"):
        test_every_message_is_translated_and_none_is_fuzzy("es")
    page.write_text(page.read_text(encoding="utf-8").replace("#, fuzzy\n", ""), encoding="utf-8")
    with pytest.raises(AssertionError, match=r"1 untranslated:\n  book/page: 'joint 2'"):
        test_every_message_is_translated_and_none_is_fuzzy("es")


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("language", LANGUAGES)
def test_catalogues_hold_exactly_the_messages_of_the_sources(tmp_path, language):
    """Extract the messages again (Sphinx's gettext builder, nothing executed) and compare."""
    config = ROOT / f"_config.gettext.test-{os.getpid()}.yml"
    text = (ROOT / "_config.yml").read_text(encoding="utf-8")
    config.write_text(re.sub(r"(?m)^(\s*execute_notebooks\s*:\s*)force\b", r'\1"off"', text),
                      encoding="utf-8")
    exe = Path(sys.executable).parent / "jupyter-book"
    try:
        proc = subprocess.run(
            [str(exe), "build", str(ROOT), "--config", str(config), "--builder", "custom",
             "--custom-builder", "gettext", "--path-output", str(tmp_path)],
            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
            timeout=900, env=dict(os.environ, PYTHONHASHSEED="0"))
    finally:
        config.unlink(missing_ok=True)
    assert proc.returncode == 0, proc.stdout[-5000:]
    pot = tmp_path / "_build" / "gettext"
    stale = []
    for page, path in _catalogues(language).items():
        if page == CELLS:
            continue  # not a page: test_the_cells_catalogue_holds_exactly_the_templates_...
        source = {m.id for m in _messages(pot / f"{page}.pot")}
        catalogue = {m.id for m in _messages(path)}
        stale += [f"{page}: new in the source, not in the catalogue: {i[:70]!r}"
                  for i in sorted(source - catalogue)]
        stale += [f"{page}: in the catalogue, gone from the source: {i[:70]!r}"
                  for i in sorted(catalogue - source)]
    assert not stale, (f"{len(stale)} catalogue entries are stale: run python3 tools/dev.py "
                       "translations, then translate what it marks\n" + "\n".join(stale[:40]))


def _i18n_extension():
    sys.path.insert(0, str(ROOT / "book" / "_ext"))
    import rikin_i18n

    return rikin_i18n


def test_caption_messages_are_what_sphinx_looks_up():
    """A caption from cell metadata is extracted as the message Sphinx's Locale looks up in
    the executed build: the source of each paragraph MyST makes of it, newlines as spaces."""
    from docutils import nodes
    from docutils.core import publish_doctree
    from myst_parser.parsers.docutils_ import Parser

    text = ("DH frames at $q = 0$. $z_0$ (blue) is the\n  vertical axis; *see* `fk`\n"
            "and {numref}`fig-x`.\n\nA second paragraph\non two lines.\n")
    doc = publish_doctree(text, parser=Parser(), settings_overrides={
        "myst_enable_extensions": ["dollarmath"], "report_level": 5})
    sphinx_messages = [p.rawsource.replace("\n", " ").strip()
                       for p in doc.children if isinstance(p, nodes.paragraph)]
    assert len(sphinx_messages) == 2
    assert _i18n_extension().caption_messages(text) == sphinx_messages


def test_cell_texts_read_caption_and_alt_from_cell_metadata():
    ext = _i18n_extension()
    meta = {"tags": ["hide-input"], "mystnb": {
        "figure": {"caption": "Two arms.\nBoth reach.\n", "name": "fig-a"},
        "image": {"alt": "Two arms side by side."}}}
    assert ext.cell_texts(meta) == ["Two arms. Both reach.", "Two arms side by side."]
    assert ext.cell_texts({"tags": ["hide-input"]}) == []
    assert ext.cell_texts({"mystnb": {"figure": {"name": "fig-b"}}}) == []


@pytest.mark.parametrize("exercises_rc", [0, 2])
def test_the_translations_command_refreshes_every_catalogue(tmp_path, monkeypatch, capsys,
                                                            exercises_rc):
    """``tools/dev.py translations`` refreshes the book's catalogues (Sphinx's gettext
    builder, then sphinx-intl), then the exercises' and the grader's
    (``make_exercises.py --translations``), and fails when those cannot be made."""
    sys.path.insert(0, str(ROOT / "tools"))
    import dev

    (tmp_path / "_config.yml").write_text((ROOT / "_config.yml").read_text(encoding="utf-8"),
                                          encoding="utf-8")
    monkeypatch.setattr(dev, "ROOT", tmp_path)
    monkeypatch.setattr(dev, "BUILD", tmp_path / "_build")
    monkeypatch.setattr(dev, "ensure_venv", lambda what="all": None)
    ran: list[list[str]] = []

    def run(cmd, env=None):
        ran.append([Path(str(c)).name if i < 2 else str(c) for i, c in enumerate(cmd)])
        if "--custom-builder" in ran[-1]:
            (tmp_path / "_build" / "_gettext" / "_build" / "gettext").mkdir(parents=True)
        return exercises_rc if ran[-1][1] == "make_exercises.py" else 0

    monkeypatch.setattr(dev, "run", run)
    assert dev.cmd_translations() == exercises_rc
    assert [c[1] if c[1].endswith(".py") else c[0] for c in ran] == [
        "jupyter-book", *["sphinx-intl"] * len(dev.EDITIONS), "cell_messages.py",
        "make_exercises.py"]
    assert ran[-1][2:] == ["--translations"]
    assert "--all" in ran[0], "pages not read again: a new site text would not be extracted"
    if exercises_rc:
        assert "solutions/locales/" in capsys.readouterr().err


def test_translate_markdown_translates_prose_and_keeps_code():
    """A chapter's markdown cell in the catalogue's language (the Spanish edition's
    published notebooks): headings, paragraphs (their lines joined), list items and an
    admonition's title and body translated; targets, code, maths and a block the catalogue
    lacks as they are."""
    ext = _i18n_extension()
    spanish = {"The planar 2R": "El 2R plano", "Two links turn and reach a point.":
               "Dos eslabones giran y alcanzan un punto.", "first item on two lines":
               "primer elemento", "Errata: Aula 23": "Erratas: Aula 23", "Clamp it.":
               "Limítalo.", "Errata": "Erratas"}

    def lookup(messages):
        return next((spanish[m] for m in messages if m in spanish), None)

    text = ("(sec-2r)=\n## The planar 2R\n\nTwo links turn\nand reach a point.\n\n"
            "- first item\n  on two lines\n- an item not in the catalogue\n\n"
            "```{admonition} Errata: Aula 23\n:class: warning\nClamp it.\n```\n\n"
            "```python\n# Errata\nx = 1\n```\n\n$$\nq = 1\n$$\n")
    assert ext.translate_markdown(text, lookup) == (
        "(sec-2r)=\n## El 2R plano\n\nDos eslabones giran y alcanzan un punto.\n\n"
        "- primer elemento\n- an item not in the catalogue\n\n"
        "```{admonition} Erratas: Aula 23\n:class: warning\nLimítalo.\n```\n\n"
        "```python\n# Errata\nx = 1\n```\n\n$$\nq = 1\n$$\n")
