"""The Spanish edition's catalogues (book/locales/es/LC_MESSAGES/book/*.po) are complete,
current and faithful: every message translated and none fuzzy, one catalogue per page with
exactly the messages the sources have today, and each translation keeping its message's
numbers, formulas and cross-references.

``python3 tools/dev.py translations`` refreshes the catalogues after the English text
changed: new messages come in empty and changed ones fuzzy, and these tests then fail until
a translator has dealt with each.
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
    assert sorted(_catalogues(language)) == _pages()


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


@pytest.mark.parametrize("language", LANGUAGES)
def test_translations_keep_numbers_formulas_and_references(language):
    bad = []
    for page, path in _catalogues(language).items():
        for m in _messages(path):
            if not m.string or m.fuzzy:
                continue
            want, got = _faithful_parts(m.id), _faithful_parts(m.string)
            if want != got:
                lost = dict(want - got)
                added = dict(got - want)
                bad.append(f"{page}: {m.id[:60]!r}\n    missing {lost}, added {added}")
    assert not bad, f"{len(bad)} translations change what they must keep:\n" + "\n".join(bad[:30])


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
        source = {m.id for m in _messages(pot / f"{page}.pot")}
        catalogue = {m.id for m in _messages(path)}
        stale += [f"{page}: new in the source, not in the catalogue: {i[:70]!r}"
                  for i in sorted(source - catalogue)]
        stale += [f"{page}: in the catalogue, gone from the source: {i[:70]!r}"
                  for i in sorted(catalogue - source)]
    assert not stale, (f"{len(stale)} catalogue entries are stale: run python3 tools/dev.py "
                       "translations, then translate what it marks\n" + "\n".join(stale[:40]))
