"""Notebook-level feedback: which cell failed, and what that costs, said once.

A cell runs before any hidden input exists, so its error message is the student's own
and is shown as it is (no masking). Cells are named as a student finds them: "code cell
7", counted like Jupyter's ``[7]`` after Run All in a fresh kernel, plus the cell's first
line, which identifies it even when empty cells or reordering make the counts differ.
"""

from __future__ import annotations

import difflib
import re

from .i18n import t
from .report import CellReport

#: Names the exercises' shared setup and checks cells define (never the student's own).
HELPER_PREFIXES = ("check_", "print_", "show_")


def cell_name(number: int, source: str) -> str:
    """``code cell 7``: counted among code cells from 1, as Jupyter's ``[7]`` after Run All."""
    return t("code cell {number}", number=number)


def cell_start(source: str) -> str:
    """``it starts "def ik_scara(p, l1, l2, l3):"``: the first line, to find the cell by."""
    first = next((ln.strip() for ln in source.splitlines() if ln.strip()), "")
    if len(first) > 60:
        first = first[:57] + "..."
    return t('it starts "{line}"', line=first) if first else t("it is empty")


def student_names(defined: set[str]) -> list[str]:
    """The callables a student wrote: not private, not classes, not the checker's helpers."""
    return sorted(
        f
        for f in defined
        if not f.startswith("_") and not f[:1].isupper() and not f.startswith(HELPER_PREFIXES)
    )


def defining_cell(name: str, cells: list[tuple[int, str]]) -> int | None:
    """The last code cell whose source defines ``name`` (``def name(`` or ``name =``)."""
    pat = re.compile(rf"^(?:def\s+{re.escape(name)}\s*\(|{re.escape(name)}\s*=)", re.M)
    found = [n for n, src in cells if pat.search(src)]
    return found[-1] if found else None


def missing_cause(
    name: str,
    defined: set[str],
    expected: tuple[str, ...],
    cells: list[tuple[int, str]],
    reports: dict[int, CellReport],
) -> str:
    """Why a function the tests call is not defined, in one sentence (said once)."""
    n = defining_cell(name, cells)
    if n is not None and n in reports and reports[n].status != "ok":
        c = reports[n]
        what = {"timeout": t("did not finish"),
                "crashed": t("stopped the notebook's process")}.get(
            c.status, t("raised {error}{context}", error=c.error_type, context="")
        )
        return t("{name} is not defined because {cell}, which defines it, {what} (see above): "
                 "the tests that call {name} score 0", name=name, cell=cell_name(n, ""),
                 what=what)
    others = [f for f in student_names(defined) if f not in expected]
    close = difflib.get_close_matches(name, others, n=3, cutoff=0.4)
    msg = t("function {name} not found: did you rename it?", name=name)
    if close:
        return msg + t(" (your notebook defines {names})", names=", ".join(close))
    if others:
        names = ", ".join(others[:3]) + (", ..." if len(others) > 3 else "")
        return msg + t(" (your notebook defines {names})", names=names)
    return msg + t(" (or is the cell that defines it deleted or failing?)")


def cell_problems(reports: dict[int, CellReport], cells: list[tuple[int, str]]) -> list[str]:
    """One line per distinct cell error, in cell order: the first cell that raised it named
    with its first line; the later cells that raised the very same error (the usual
    consequence of the first: a function it should have defined) folded into that line."""
    sources = dict(cells)
    lines: list[str] = []
    seen: dict[tuple[str, str, str], int] = {}
    later: dict[int, list[int]] = {}
    for n in sorted(reports):
        c = reports[n]
        if c.status == "error":
            what = f"{c.error_type}: {c.message}" if c.message else c.error_type
            key = ("error", c.error_type, c.message)
            if key in seen:
                later[seen[key]].append(n)
            else:
                seen[key] = len(lines)
                later[len(lines)] = []
                lines.append(t("{cell} raised {error} ({start}", cell=cell_name(n, ""), error=what,
                               start=cell_start(sources.get(n, ""))))
        elif c.status in ("timeout", "crashed"):
            lines.append(f"{cell_name(n, '')} {c.message} ({cell_start(sources.get(n, ''))})")
        for note in c.notes:
            lines.append(f"{cell_name(n, '')}: {note}")
    for i, more in later.items():
        also = ""
        if more:
            listed = ", ".join(str(m) for m in more[:-1])
            cells_ = (t("{cells} and {last}", cells=listed, last=more[-1]) if listed
                      else str(more[-1]))
            also = (t("; so did code cells {cells}", cells=cells_) if len(more) > 1
                    else t("; so did code cell {cells}", cells=cells_))
        lines[i] += also + t("; later cells still ran)")
    return lines
