"""The language of the words rikin prints in its tables: English, or Spanish for the
Spanish edition of the book.

Only what a table shows is translated: column headers ("branch", "joint", ...) and branch
names ("front/up/no-flip" -> "delante/arriba/sin voltear"). The data stays as it is: a
solution's ``branch.label`` and ``result.labels`` are English whatever the language, so
code that selects a branch by name works in every edition. Error messages are English too
(they are searched for, quoted in forums and matched by tests).

The language is read from the environment variable ``RIKIN_LANG`` (``en`` or ``es``; the
book's Spanish build sets it for its kernels, and the Spanish notebooks' first cell does
too) and can be set in a notebook with :func:`set_language`.

Examples
--------
>>> import rikin
>>> rikin.i18n.set_language("es")
>>> rikin.i18n.branch_name("front/up/no-flip")
'delante/arriba/sin voltear'
>>> rikin.i18n.set_language("en")
"""

from __future__ import annotations

import os

from .errors import InputError

__all__ = ["LANGUAGES", "language", "set_language"]

#: The languages rikin prints tables in.
LANGUAGES = ("en", "es")
#: The environment variable that chooses the language when :func:`set_language` was not called.
ENV_VAR = "RIKIN_LANG"

#: Spanish for the words tables print (the book's glossary gives the same terms).
_SPANISH = {
    # column headers
    "branch": "rama",
    "joint": "articulación",
    "type": "tipo",
    "offset": "desfase",
    # branch names: shoulder, elbow, wrist
    "front": "delante",
    "back": "detrás",
    "up": "arriba",
    "down": "abajo",
    "no-flip": "sin voltear",
    "flip": "volteada",
    "left": "izquierda",
    "right": "derecha",
    # cells
    "yes": "sí",
    "no": "no",
}
_WORDS = {"en": {}, "es": _SPANISH}

_chosen: str | None = None


def _checked(lang: object, where: str) -> str:
    if not isinstance(lang, str) or lang.strip().lower() not in LANGUAGES:
        raise InputError(f"{where} must be one of {', '.join(LANGUAGES)}, got {lang!r}")
    return lang.strip().lower()


def set_language(language: str | None) -> None:
    """Print tables in ``language`` ("en" or "es") from now on; ``None`` goes back to
    ``RIKIN_LANG`` (English when it is not set)."""
    global _chosen
    _chosen = None if language is None else _checked(language, "language")


def language() -> str:
    """The language tables are printed in now: "en" or "es"."""
    if _chosen is not None:
        return _chosen
    value = os.environ.get(ENV_VAR, "").strip()
    return _checked(value, f"the environment variable {ENV_VAR}") if value else "en"


def word(text: str) -> str:
    """``text`` in the current language (unchanged when it has no translation)."""
    return _WORDS[language()].get(text, text)


def branch_name(label: str) -> str:
    """A branch label such as ``"front/up/no-flip"`` in the current language, part by part."""
    return "/".join(word(part) for part in label.split("/"))
