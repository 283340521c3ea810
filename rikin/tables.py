"""Tables for the book and notebooks: HTML where HTML is shown, aligned text elsewhere.

A notebook or the built book shows :class:`Table` as an HTML table that
fits the page (numbers right-aligned, in a scrolling box on a narrow
screen); ``print(table)`` gives the same rows as aligned text. Numbers are
formatted here, so no ``np.float64(...)`` or ``np.int64(...)`` reaches the
reader.

>>> import rikin
>>> from rikin.tables import solutions_table
>>> arm = rikin.robots.planar_2r(10, 10)
>>> print(solutions_table(arm.ik([15.0, 5.0]), decimals=2))
#  branch  q1 (°)  q2 (°)
1  down    -19.33   75.52
2  up       56.20  -75.52
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import Any

import numpy as np

from ._validate import as_count, as_flag, as_text
from .dh import check_arm
from .errors import InputError
from .i18n import branch_name, phrase, word
from .ik.result import IKResult

__all__ = ["Table", "dh_table", "solutions_table", "table"]

#: The CSS class of every table (the book's stylesheet may style it).
CSS_CLASS = "rikin-table"


def _cell(v: Any, decimals: int) -> str:
    if isinstance(v, (bool, np.bool_)):
        return word("yes" if v else "no")
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if not np.isfinite(f):
            raise InputError(f"rows hold {f}: a table shows numbers, so the NaN or infinity "
                             "must be dealt with before (or written as text)")
        text = f"{f:.{decimals}f}"
        return "0" + text[2:] if text.startswith("-0") and float(text) == 0 else text
    return str(v)


class Table:
    """Rows of cells with a header; displays as HTML, prints as aligned text.

    Parameters
    ----------
    header : sequence of str
    rows : sequence of sequences
        Numbers are formatted with ``decimals`` decimals (integers as they are).
    decimals : int
    caption : str, optional
    """

    def __init__(self, header: Sequence[str], rows: Sequence[Sequence[Any]], decimals: int = 4,
                 caption: str | None = None) -> None:
        if not _is_sequence(header) or not all(isinstance(h, str) for h in header):
            raise InputError(f"header must be a list of column names (str), got {header!r:.80}")
        self.header = list(header)
        decimals = _decimals(decimals)
        if isinstance(rows, np.ndarray):
            rows = rows.tolist() if rows.ndim == 2 else rows
        if not _is_sequence(rows) or not all(_is_sequence(r) for r in rows):
            raise InputError(f"rows must be a list of rows (each a list of cells), got "
                             f"{rows!r:.80}")
        self.cells = [[_cell(v, decimals) for v in row] for row in rows]
        for i, row in enumerate(self.cells):
            if len(row) != len(self.header):
                raise InputError(f"rows: row {i + 1} has {len(row)} cells for the "
                                 f"{len(self.header)} columns of header")
        self.caption = as_text(caption, "caption", optional=True)
        self._numeric = [all(_is_number(r[j]) for r in self.cells) and bool(self.cells)
                         for j in range(len(self.header))]

    def __str__(self) -> str:
        widths = [max([len(h)] + [len(r[j]) for r in self.cells])
                  for j, h in enumerate(self.header)]

        def line(cells: Sequence[str]) -> str:
            return "  ".join(c.rjust(w) if num else c.ljust(w)
                             for c, w, num in zip(cells, widths, self._numeric, strict=True)
                             ).rstrip()

        out = ([self.caption] if self.caption else []) + [line(self.header)]
        return "\n".join(out + [line(r) for r in self.cells])

    __repr__ = __str__

    def _repr_html_(self) -> str:
        def td(c: str, j: int, tag: str = "td") -> str:
            # numbers stay on one line; text and headings may wrap to fit the page
            align, wrap = ("right", "nowrap") if self._numeric[j] else ("left", "normal")
            if tag == "th":
                wrap = "normal"
            style = f' style="text-align:{align};padding:0.1em 0.45em;white-space:{wrap}"'
            return f"<{tag}{style}>{html.escape(c)}</{tag}>"

        head = "".join(td(h, j, "th") for j, h in enumerate(self.header))
        body = "".join("<tr>" + "".join(td(c, j) for j, c in enumerate(r)) + "</tr>"
                       for r in self.cells)
        cap = f"<caption>{html.escape(self.caption)}</caption>" if self.caption else ""
        return (f'<div class="{CSS_CLASS}-wrap" style="max-width:100%;overflow-x:auto">'
                f'<table class="{CSS_CLASS}" style="margin:0.4em 0;'
                f'border-collapse:collapse;font-size:0.92em">'
                f"{cap}<thead><tr>{head}</tr></thead>"
                f"<tbody>{body}</tbody></table></div>")


def _is_sequence(x: Any) -> bool:
    return isinstance(x, (list, tuple)) or (isinstance(x, np.ndarray) and x.ndim == 1)


def _decimals(decimals: Any) -> int:
    return as_count(decimals, "decimals", minimum=0, maximum=15)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def table(header: Sequence[str], rows: Any, decimals: int = 4, caption: str | None = None) -> Table:
    """A :class:`Table` of any rows (lists, tuples or a 2-D array)."""
    if isinstance(rows, np.ndarray) and rows.size == 0:
        rows = []
    if isinstance(rows, np.ndarray):
        if rows.ndim != 2:
            raise InputError(f"rows must be 2-D, got shape {rows.shape}")
        rows = rows.tolist()
    return Table(header, rows, decimals, caption)


def solutions_table(result: IKResult, decimals: int = 4, caption: str | None = None,
                    units: str = "", arm: Any = None) -> Table:
    """Every solution of an IK result: number, branch, joint values (degrees for revolute).

    Parameters
    ----------
    result : IKResult
    decimals : int
    caption : str, optional
        Default: none; a singular result says so in the caption.
    units : str
        Length units of the prismatic joints, for their column headers (default: the
        arm's units when ``arm`` is given).
    arm : rikin.SerialArm, optional
        The arm solved. With it, the header of a joint its data sheet counts against the
        DH z axis (``direction=-1``) says so: ``q1 (°, −z)``; the values are the data
        sheet's ``q`` either way.

    Returns
    -------
    Table
    """
    if not isinstance(result, IKResult):
        raise InputError(f"result must be an IKResult, got {type(result).__name__}")
    decimals = _decimals(decimals)
    as_text(units, "units")
    caption = as_text(caption, "caption", optional=True)
    qd = result.degrees()
    n = qd.shape[1] if qd.ndim == 2 else len(result.revolute)
    directions = _directions(arm, n)
    units = units or (arm.units if arm is not None else "")
    header = ["#", word("branch")] + [_q_header(j, bool(r), units, int(s)) for j, r, s in
                                      zip(range(n), result.revolute, directions, strict=True)]
    rows = [[i + 1, branch_name(lab), *map(float, q)]
            for i, (lab, q) in enumerate(zip(result.labels, qd, strict=True))]
    if caption is None and result.singular:
        caption = phrase("singular: {why}; free joints {free}", why=result.singularity,
                         free=result.free_joints)
    return Table(header, rows, decimals, caption)


def _directions(arm: Any, n: int) -> np.ndarray:
    """Each joint's direction (+1 or -1) of ``arm``, shape ``(n,)``; all +1 without one."""
    if arm is None:
        return np.ones(n, dtype=np.int64)
    check_arm(arm)
    if arm.n != n:
        raise InputError(f"arm has {arm.n} joints, the result {n}: give the arm solved")
    return np.asarray(arm.directions)


def _q_header(j: int, revolute: bool, units: str, direction: int) -> str:
    """A joint column's header: ``q2 (°)``, ``q3 (mm)``, ``q1 (°, −z)`` when reversed."""
    inside = [u for u in ("°" if revolute else units, "−z" if direction < 0 else "") if u]
    return f"q{j + 1} ({', '.join(inside)})" if inside else f"q{j + 1}"


def _limits_cell(lk: Any, deg: Any, length: Any) -> str:
    """A joint's limits as the data sheet prints them (its ``q``), or ``—`` for none."""
    lim = getattr(lk, "qlim", None)
    if lim is None:
        return "—"
    show = deg if lk.is_revolute else length
    lo, hi = (show(v) if np.isfinite(v) else ("−∞" if v < 0 else "∞") for v in lim)
    return f"{lo} … {hi}"


def dh_table(arm: Any, decimals: int = 4, limits: bool = False) -> Table:
    """An arm's DH table: one row per joint, angles in degrees, the joint variable by name.

    The HTML counterpart of ``arm.dh_table()`` (aligned text, angles in radians): columns
    theta, d, a, alpha for standard DH and alpha_{i-1}, a_{i-1}, theta, d for modified DH,
    then the joint offset. A revolute joint's theta reads ``q<i>`` (plus its offset), a
    prismatic joint's d reads ``q<i> + d``; a joint whose ``direction`` is -1 (its data
    sheet counts it against the DH z axis) reads ``−q<i>``.

    Parameters
    ----------
    arm : rikin.SerialArm
    decimals : int
        Most decimals of a length, shown without trailing zeros (angles: 4 significant
        digits).
    limits : bool
        Add a column of the joint limits, as the data sheet prints them (``q``'s, so a
        reversed joint's as printed too).

    Returns
    -------
    Table
    """
    links = getattr(arm, "links", None)
    if links is None or not hasattr(arm, "convention"):
        raise InputError(f"arm must be a rikin.SerialArm, got {type(arm).__name__}")
    decimals = _decimals(decimals)
    limits = as_flag(limits, "limits")
    unit = f" ({arm.units})" if getattr(arm, "units", "") else ""

    def deg(x: Any) -> str:
        return f"{float(np.degrees(float(x))):.4g}°"

    def length(x: Any) -> str:  # as typed: 10, 0.25, -250 (no trailing zeros)
        return str(np.format_float_positional(round(float(x), decimals) + 0.0, trim="-"))

    modified = arm.convention == "modified"
    joint, kind, offset = word("joint"), word("type"), word("offset")
    header = ([joint, kind, "α(i−1)", f"a(i−1){unit}", "θ(i)", f"d(i){unit}", offset]
              if modified else
              [joint, kind, "θ(i)", f"d(i){unit}", f"a(i){unit}", "α(i)", offset])
    rows = []
    for i, lk in enumerate(links, 1):
        qi = f"q{i}" if getattr(lk, "direction", 1) > 0 else f"−q{i}"  # counted against z
        theta = qi if lk.is_revolute else deg(lk.theta)
        d = length(lk.d) if lk.is_revolute else f"{qi} + {length(lk.d)}"
        cells = ([deg(lk.alpha), length(lk.a), theta, d] if modified
                 else [theta, d, length(lk.a), deg(lk.alpha)])
        rows.append([i, lk.joint, *cells, deg(lk.offset)]
                    + ([_limits_cell(lk, deg, length)] if limits else []))
    if limits:
        kinds = [u for u, there in (("°", any(lk.is_revolute for lk in links)),
                                    (arm.units, not all(lk.is_revolute for lk in links)))
                 if u and there]
        header.append(f"{word('limits')} ({', '.join(kinds)})" if kinds else word("limits"))
    return Table(header, rows, decimals)
