"""Text a student controls, made safe for every output the grader writes.

A student controls much of what the grader writes: file and folder names, exception
messages and types, printed output, a cell's first line, what a shell command printed.
Before any of it reaches an output (grades.csv and the LMS files, grading.log, the class
report, the feedback, the terminal) it goes through :func:`printable`, the one function
for that: valid UTF-8, and no control character but newline and tab, so that
``cat grades.csv`` cannot recolour, retitle or clear the instructor's terminal
(``\\x1b[31m``, ``\\x1b]0;...\\x07``, ``\\r``) and no byte a spreadsheet or a browser
would act on gets through. :class:`SafeFormatter` applies it to every log line.
"""

from __future__ import annotations

import logging
import re

#: Terminal escape sequences, removed whole: CSI (``ESC [ ... m``, also the one-byte
#: C1 form 0x9B), OSC (``ESC ] ... BEL`` or ``ESC \\``, 0x9D), and any other ``ESC x``.
_ESCAPES = re.compile(
    r"(?:\x1b\[|\x9b)[0-?]*[ -/]*[@-~]"
    r"|(?:\x1b\]|\x9d)[^\x07\x1b\x9c]*(?:\x07|\x1b\\|\x9c)?"
    r"|\x1b[@-Z\\-_]"
)
#: C0 and C1 control characters (and DEL), except tab (0x09) and newline (0x0a).
_CONTROLS = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]")


def printable(text: str) -> str:
    """``text`` as any output can hold it: UTF-8, no control character but ``\\n``, ``\\t``.

    A byte that a file name could not decode (kept by Python as a lone surrogate) is
    written ``\\xe9``, any other lone surrogate ``\\udcff``; terminal escape sequences are
    removed whole, and every other C0/C1 control character (``\\r``, ``\\x07``, ...) is
    removed.
    """
    text = str(text)
    try:
        text = text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    except UnicodeEncodeError:
        text = text.encode("utf-8", "backslashreplace").decode("utf-8")
    if _CONTROLS.search(text) is None:
        return text
    return _CONTROLS.sub("", _ESCAPES.sub("", text))


class SafeFormatter(logging.Formatter):
    """A log formatter whose lines hold no control character (see :func:`printable`)."""

    def format(self, record: logging.LogRecord) -> str:
        return printable(super().format(record))
