"""The language of a student's feedback: the language of the notebook they handed in.

The exercise notebooks exist in English (``exercises/``) and Spanish (``exercises/es/``),
with the same code, functions and tests, so one grader grades either. A notebook says its
language in its metadata (``"language": "es"``, written by tools/make_exercises.py) and in
its setup cell (``rikin.i18n.set_language("es")``, in case a front end drops the metadata):
:func:`notebook_language`. Grading a notebook runs inside :func:`use` with its language, and
every sentence the student reads is written with :func:`t`, which gives the text in that
language. The instructor's side (the log, the LMS export columns, the gradebook) stays
English, as do Python's own exception messages quoted in the feedback.

The translations are a gettext catalogue per language, ``locales/<lang>/LC_MESSAGES/
rikingrade.po`` next to this module (refreshed with the exercises' catalogues by
``python3 tools/make_exercises.py --translations``), read here with the standard library.
``tests/test_exercises_i18n.py`` fails when a message written with :func:`t` has no current
translation.
"""

from __future__ import annotations

import ast
import contextlib
import contextvars
import functools
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

#: The languages feedback is written in; English is the source.
LANGUAGES = ("en", "es")
CATALOGUE = Path(__file__).resolve().parent / "locales" / "{lang}" / "LC_MESSAGES" / "rikingrade.po"

_language: contextvars.ContextVar[str] = contextvars.ContextVar("rikingrade_language",
                                                                default="en")
_SET_LANGUAGE = re.compile(r"""set_language\(\s*["'](\w+)["']\s*\)""")


def notebook_language(metadata: Any, sources: list[str]) -> str:
    """The language of a notebook: its metadata's ``language``, else the one its code sets
    with ``rikin.i18n.set_language(...)`` (the last call), else English."""
    if isinstance(metadata, dict):
        lang = metadata.get("language")
        if isinstance(lang, str) and lang.strip().lower() in LANGUAGES:
            return lang.strip().lower()
    found = [m.group(1).lower() for src in sources for m in _SET_LANGUAGE.finditer(src)]
    found = [lang for lang in found if lang in LANGUAGES]
    return found[-1] if found else "en"


def language() -> str:
    """The language feedback is being written in now."""
    return _language.get()


@contextlib.contextmanager
def use(lang: str) -> Iterator[None]:
    """Write feedback in ``lang`` inside this block."""
    token = _language.set(lang if lang in LANGUAGES else "en")
    try:
        yield
    finally:
        _language.reset(token)


def _unquote(text: str) -> str:
    return ast.literal_eval(text) if text.startswith('"') else text


@functools.cache
def catalogue(lang: str) -> dict[str, str]:
    """The translations of ``lang`` (msgid -> msgstr), fuzzy and empty entries left out."""
    path = Path(str(CATALOGUE).format(lang=lang))
    if lang == "en" or not path.exists():
        return {}
    out: dict[str, str] = {}
    entries: list[dict[str, Any]] = [{}]
    key = None
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.strip()
        if not line:
            entries.append({})
            key = None
        elif line.startswith("#,"):
            entries[-1]["fuzzy"] = "fuzzy" in line
        elif line.startswith(("msgid ", "msgstr ")):
            key, _, rest = line.partition(" ")
            entries[-1][key] = _unquote(rest)
        elif line.startswith('"') and key:
            entries[-1][key] += _unquote(line)
    for e in entries:
        if e.get("msgid") and e.get("msgstr") and not e.get("fuzzy"):
            out[e["msgid"]] = e["msgstr"]
    return out


def t(text: str, **values: Any) -> str:
    """``text`` in the current language, with ``values`` put into its ``{placeholders}``."""
    if values:
        return catalogue(language()).get(text, text).format(**values)
    return catalogue(language()).get(text, text)


def N_(text: str) -> str:
    """Mark ``text`` as a message (translated later, with :func:`t`, where it is shown)."""
    return text


def label(text: str) -> str:
    """A solution's branch label ("elbow left (q2 < 0), wrist q5 > 0") in the current
    language, part by part (a part with no translation stays as it is)."""
    words = catalogue(language())
    return ", ".join(words.get(part, part) for part in label_parts(text))


def label_parts(text: str) -> list[str]:
    """A branch label split at its ", " outside parentheses."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        depth += {"(": 1, ")": -1}.get(ch, 0)
        if depth == 0 and text.startswith(", ", i):
            parts.append(text[start:i])
            start = i + 2
    return [*parts, text[start:]]
