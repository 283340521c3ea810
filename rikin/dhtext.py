"""DH tables typed as text, read as books and data sheets print them.

:func:`arm_from_table` turns a table into a :class:`~rikin.SerialArm`. It reads

* rows of numbers, ``type d a alpha offset`` (the type and the offset may be left out), as
  the DH panel's examples write them; or
* a table with a header row that names its columns, in any order and with any of the
  names books use: ``theta``/``θ``/``q``, ``d``, ``a``/``r``, ``alpha``/``α``,
  ``offset``, ``type``/``joint type`` (and a joint number column, ``i``/``joint``/``link``,
  which is skipped). With a ``theta`` column the joint variable says the joint type:
  ``θ1``, ``q2 + 90°``, ``theta_3 - pi/2`` in the theta column is a revolute joint with
  that offset; ``d3`` or ``q3`` in the d column a prismatic one;
* columns separated by spaces, tabs, ``;``, ``,`` or ``|`` (a pasted Markdown table; its
  ``|---|`` row is skipped), decimal commas (``0,4318``) where commas do not separate;
* each cell a number or an arithmetic expression: ``pi/2``, ``-π/2``, ``2*pi/3``,
  ``-90°``, ``90 deg``, ``1e-3`` (parsed, never evaluated as Python code).

Angles: a value with ``pi``/``π`` is radians, one marked ``°`` or ``deg`` degrees, a bare
number degrees unless the column's header says ``(rad)``. A bare number that is a right
angle (or several) in radians rounded, ``1.5708``, ``3.1416``, is refused under a header
that names no unit: read as degrees it would make another arm; ``1.5708°`` (or a ``(deg)``
header) is read as written. Lengths are in the arm's units, which a header may name
(``d (mm)``, ``a [m]``: ``mm``, ``m``, ``cm``, ``in``); rikin converts no length, so a
header naming two length units, or another unit than ``units=``, is refused, as is an
angle unit on ``d``/``a``. A cell that cannot be read is refused naming its line,
its column and how to write it.

A joint its data sheet counts the other way (against the DH z axis: KUKA's A1, A4, A6;
``direction=-1`` of :class:`~rikin.Link`) is written in one of three ways, once per row:

* a ``direction`` (or ``dir``, ``sign``) column holding ``+1``/``-1`` (or ``+``/``-``);
* a minus on the joint variable: ``-q1``, ``-θ2 + 90°``, ``-(q3 - 90°)`` in the theta
  column of a revolute joint (theta = -q + offset), ``-d3`` or ``-q3 + 0.1`` in the d
  column of a prismatic one (the variable appears once, times +1 or -1);
* in rows of numbers, the type followed by a minus: ``R- 0.4 0.18 -90`` (``P-`` for a
  prismatic joint). A trailing column cannot say it: ``R 0 1 0 -1`` is an offset of -1°.

A header may also give the data sheet's joint limits as printed, in its joints' own
direction (so a reversed joint's limits keep their printed signs): ``min`` and ``max``
(or ``lower``/``upper``) columns, or one ``limits`` (``range``) column written
``-170..170``, ``±170`` or ``-170 to 170`` (``|`` tables), ``none`` for a joint without;
degrees unless the header says ``(rad)``, the arm's units for a prismatic joint. They
become :attr:`rikin.Link.qlim`: ``arm.ik(T, within_limits=True)`` keeps the solutions the
data sheet allows, and the DH panel shows only those (saying how many it left out).
"""

from __future__ import annotations

import ast
import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import as_text
from .dh import Link, SerialArm
from .errors import InputError
from .tolerances import ROUNDED_RIGHT_ANGLE

__all__ = ["arm_from_table", "row_tokens"]

#: Column names as books print them -> the column. Matched after :func:`_header_key`.
COLUMNS = {
    "theta": "theta", "θ": "theta", "th": "theta", "q": "theta", "jointangle": "theta",
    "d": "d", "a": "a", "r": "a", "alpha": "alpha", "α": "alpha", "twist": "alpha",
    "offset": "offset", "off": "offset", "thetaoffset": "offset", "θoffset": "offset",
    "θ0": "offset", "theta0": "offset", "type": "type", "jointtype": "type", "kind": "type",
    "rp": "type", "r/p": "type", "i": "index", "joint": "index", "link": "index",
    "#": "index", "n": "index", "j": "index", "axis": "index", "no.": "index", "no": "index",
    "direction": "direction", "dir": "direction", "sign": "direction", "dir.": "direction",
    "min": "min", "max": "max", "lower": "min", "upper": "max", "qmin": "min", "qmax": "max",
    "lowerlimit": "min", "upperlimit": "max", "min.": "min", "max.": "max",
    "limits": "limits", "limit": "limits", "range": "limits", "qlim": "limits",
    "jointlimits": "limits", "jointrange": "limits", "motionrange": "limits",
}
ANGLES = ("theta", "alpha", "offset")
#: How to write a value, said when one cannot be read.
HOW = {"angle": "a number of degrees (90, -90°, 90 deg) or radians with pi (pi/2, -π/2)",
       "length": "a number in the arm's units (0.4318, 431.8; 1e-3)",
       "type": "R (revolute) or P (prismatic), R- or P- for a joint counted the other way",
       "direction": "+1 or -1 (also + or -): -1 where the data sheet counts the joint "
                    "against the DH z axis",
       "limits": "lower..upper as printed (-170..170), ±170, or none",
       "variable": "the joint variable once, plus or minus: q3, -q3, -θ3 + 90°, -(q3 - 90°)"}
#: A joint's direction as a direction cell or a type's suffix writes it.
_DIRECTIONS = {"+": 1, "+1": 1, "1": 1, "1.0": 1, "+1.0": 1, "-": -1, "-1": -1, "-1.0": -1}
_DASHES = str.maketrans({"−": "-", "–": "-", "—": "-"})
#: No limit on that side (a limits, min or max cell).
_NO_LIMIT = ("none", "-", "n/a", "free", "")

_DECIMAL_COMMA = re.compile(r"^[-+]?\d+,\d+$")
_SEPARATOR_ROW = re.compile(r"^\s*\|?\s*:?-{2,}:?\s*(\|\s*:?-{2,}:?\s*)*\|?\s*$")
#: A joint variable in a theta or d cell: q1, θ2, theta_3, θ₄, d3*, q_{5}.
_VARIABLE = re.compile(r"(?:q|θ|theta|th|d)\s*_?\{?\s*[0-9₀-₉]+\s*\}?\s*\*?", re.I)
_SUBSCRIPTS = str.maketrans("₀₁₂₃₄₅₆₇₈₉", "0123456789")


def _normalise(text: str) -> str:
    """Typographic forms as Python writes them: π, −, ×, ·, degree words."""
    t = text.strip().replace("−", "-").replace("–", "-").replace("×", "*").replace("·", "*")
    t = t.replace("π", "pi").replace("\\pi", "pi").replace("$", "").replace("{", "(")
    t = t.replace("}", ")").replace("^\\circ", "°").replace("^{\\circ}", "°").replace("º", "°")
    t = re.sub(r"(?i)\s*(°|degrees|degree|deg)\b", "°", t)
    t = re.sub(r"(?i)\s*(rad|radians)\b", "", t)
    return t.replace("°", "*DEG")


def _evaluate(node: ast.AST, q: float | None = None) -> float:
    """An arithmetic expression of numbers, pi and DEG (and the joint variable QVAR,
    worth ``q``, when ``q`` is given); anything else is refused."""
    if isinstance(node, ast.Expression):
        return _evaluate(node.body, q)
    if isinstance(node, ast.Name) and node.id == "QVAR" and q is not None:
        return q
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not \
            isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id in ("pi", "DEG"):
        return math.pi if node.id == "pi" else math.pi / 180.0
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        v = _evaluate(node.operand, q)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult,
                                                            ast.Div)):
        left, right = _evaluate(node.left, q), _evaluate(node.right, q)
        ops = {ast.Add: left + right, ast.Sub: left - right, ast.Mult: left * right}
        if isinstance(node.op, ast.Div):
            if right == 0:
                raise ValueError("division by zero")
            return left / right
        return ops[type(node.op)]
    raise ValueError(f"{type(node).__name__} is not arithmetic")


@dataclass(frozen=True)
class Value:
    """A cell read: its number, and whether it was marked radians (pi) or degrees (°)."""

    number: float
    unit: str  # "rad", "deg" or "" (a bare number)


def _table_value(text: str) -> Value:
    """One cell: a number or an arithmetic expression (``pi/2``, ``-90°``, ``2*pi/3``).

    Raises
    ------
    ValueError
        Not such an expression (nothing is evaluated as code).
    """
    raw = text.strip()
    if not raw or len(raw) > 80:
        raise ValueError("empty" if not raw else "too long")
    if _DECIMAL_COMMA.match(raw):
        raw = raw.replace(",", ".")
    expr = _normalise(raw)
    number = _evaluate(ast.parse(expr, mode="eval"))
    if not math.isfinite(number):
        raise ValueError("not finite")
    unit = "deg" if "DEG" in expr else ("rad" if "pi" in expr else "")
    return Value(number, unit)


def _is_number(token: str) -> bool:
    try:
        _table_value(token)
    except (ValueError, SyntaxError, TypeError, RecursionError, OverflowError):
        return False
    return True


def _glue_operators(parts: list[str]) -> list[str]:
    """Rejoin an expression that spaces cut: ``q2 + 90°`` or ``pi / 2`` is one cell."""
    out: list[str] = []
    for k, part in enumerate(parts):
        last = k == len(parts) - 1
        if out and re.fullmatch(r"(?i)°|deg|degrees?|rad|radians?", part):
            out[-1] += part  # a unit after its number: 90 deg
        elif out and len(out[-1]) > 1 and _is_type(out[-1]) is not None:
            out.append(part)  # R- 0.4 ...: the type with its direction, then a number
        elif last and part in ("+", "-", "−"):
            out.append(part)  # a direction cell at the end of the row
        elif out and (part in ("+", "-", "*", "/") or out[-1][-1:] in ("+", "*", "/")
                    or (out[-1].endswith("-") and len(out[-1]) > 1)):
            out[-1] += part
        elif out and part[:1] in ("*", "/") and len(part) > 1:
            out[-1] += part
        else:
            out.append(part)
    return out


def row_tokens(line: str) -> list[str]:
    """The cells of one table row.

    Cells are separated by ``|`` when the row has one (a Markdown table), else by tabs or
    ``;`` when it has them, else by spaces and commas; on a row with one comma per number at
    most and none between cells, ``0,4318`` is a decimal comma. Spaces around an operator
    do not cut a cell (``q2 + 90°``).

    Raises
    ------
    InputError
        ``line`` is not text.
    """
    line = str(as_text(line, "line")).strip()
    for sep in ("|", "\t", ";"):
        if sep in line:
            cells = [c.strip() for c in line.strip("|").split(sep)] if sep == "|" else [
                c.strip() for c in line.split(sep)]
            return [c.replace(",", ".") if _DECIMAL_COMMA.match(c) else c for c in cells if c]
    parts = [t for t in re.split(r"\s+", line) if t]
    if sum(t.count(",") for t in parts) and all(_DECIMAL_COMMA.match(t) or "," not in t
                                                 for t in parts):
        parts = [t.replace(",", ".") for t in parts]
    else:
        parts = [t for part in parts for t in part.split(",") if t]
    return _glue_operators(parts)


#: The units a header cell may name, as rikin keeps them: angles, and lengths.
_HEADER_UNITS = {"rad": "rad", "radians": "rad", "deg": "deg", "degrees": "deg", "°": "deg",
                 "mm": "mm", "m": "m", "cm": "cm", "in": "in"}
#: Columns that only ever hold an angle, or only a length (offset, min, max and limits
#: hold either, by the row's joint type).
_ANGLE_COLUMNS, _LENGTH_COLUMNS = ("theta", "alpha"), ("d", "a")


def _header_key(token: str) -> tuple[str, str]:
    """A header cell as (column name key, unit the header gives: "rad", "deg", a length
    unit "mm", "m", "cm", "in", or "")."""
    t = token.strip().lower().replace("$", "").replace("\\", "")
    unit = ""
    m = re.search(r"[\(\[]\s*(rad|radians|deg|degrees|°|mm|m|cm|in)\s*[\)\]]", t)
    if m:
        unit = _HEADER_UNITS[m.group(1)]
        t = t[:m.start()] + t[m.end():]
    t = re.sub(r"[{}\s]", "", t).translate(_SUBSCRIPTS)
    t = re.sub(r"_?\(?i(-1|−1)?\)?$", "", t) if len(t) > 1 else t  # θ_i, a_{i-1}, αi-1
    return t.rstrip("_"), unit


def _header(tokens: list[str]) -> list[tuple[str, str]] | None:
    """The columns a header row names, or None when it is not a header."""
    if any(_is_number(t) for t in tokens):
        return None
    tokens = _units_joined(tokens)
    keys = [_header_key(t) for t in tokens]
    named = [(COLUMNS.get(k), unit) for k, unit in keys]
    if sum(1 for c, _ in named if c in ("d", "a", "alpha", "theta")) < 2:
        return None
    if any(c is None for c, _ in named):
        unknown = [t for t, (c, _) in zip(tokens, named, strict=True) if c is None]
        unit = re.search(r"[\(\[]\s*([^()\[\]]*?)\s*[\)\]]", unknown[0])
        if unit and COLUMNS.get(_header_key(unknown[0][:unit.start()])[0]):
            raise InputError(f"DH table header: column {unknown[0]!r}: rikin reads the units "
                             "(deg), (rad), (mm), (m), (cm) and (in) in a header, not "
                             f"{unit.group(1)!r}")
        raise InputError(f"DH table header: column {unknown[0]!r} is not one rikin knows; name "
                         "the columns theta (θ, q), d, a, alpha (α), offset, type (R or P), "
                         "joint (its number), direction (+1 or -1), min and max or limits")
    cols = [c for c, _ in named]
    dup = [c for c in set(cols) if cols.count(c) > 1 and c != "index"]
    if dup:
        raise InputError(f"DH table header: two columns are {dup[0]!r}")
    if "limits" in cols and ("min" in cols or "max" in cols):
        raise InputError("DH table header: a limits column and min/max columns say the same "
                         "thing: keep one (limits as -170..170, or min and max)")
    columns = [(c, u) for c, u in named if c is not None]
    _check_header_units(columns)
    return columns


def _units_joined(tokens: list[str]) -> list[str]:
    """Header tokens with a unit typed apart (``d (mm)`` in a table of spaces) joined to
    the column before it: ``["d", "(mm)"]`` is ``["d (mm)"]``."""
    out: list[str] = []
    for t in tokens:
        if out and re.fullmatch(r"[\(\[]\s*[^\s()\[\]]+\s*[\)\]]", t.strip()):
            out[-1] += " " + t
        else:
            out.append(t)
    return out


def _check_header_units(columns: list[tuple[str, str]]) -> None:
    """Refuse a header whose units rikin would have to guess at: an angle unit on a
    length column (or the reverse), or two length units (rikin reads every length of the
    table, prismatic limits included, in one unit, the arm's; it converts none)."""
    for col, unit in columns:
        if col in _LENGTH_COLUMNS and unit in ("rad", "deg"):
            raise InputError(f"DH table header: column {col} ({unit}) holds lengths, not "
                             "angles: drop the unit, or name the length unit (mm, m)")
        if col in _ANGLE_COLUMNS and unit not in ("", "rad", "deg"):
            raise InputError(f"DH table header: column {col} ({unit}) holds angles: name "
                             "(deg) or (rad), or no unit (degrees)")
    lengths = sorted({u for _, u in columns if u not in ("", "rad", "deg")})
    if len(lengths) > 1:
        raise InputError(f"DH table header: lengths in {' and '.join(lengths)}: rikin reads "
                         "every length of a table (a, d, a prismatic joint's limits) in one "
                         "unit and converts none: write them all in one, e.g. "
                         f"{lengths[0]}")


def _length_unit(header: list[tuple[str, str]] | None, units: str) -> str:
    """The arm's length unit: ``units`` as given, else the one the header names; a header
    naming another unit than ``units`` is refused (rikin converts no length)."""
    named = {u for _, u in header or () if u not in ("", "rad", "deg")}
    if named and units and units not in named:
        raise InputError(f"the DH table's header gives lengths in {named.pop()}, the arm's "
                         f"units are {units!r}: rikin converts no length, so write the "
                         "table in the arm's units (or give units to match)")
    return units or (named.pop() if named else "")


@dataclass
class _Cell:
    line: int
    raw: str
    column: str

    def fail(self, what: str, how: str) -> InputError:
        return InputError(f"DH table line {self.line} ({self.raw!r}), column {self.column} = "
                          f"{what}: write {HOW[how] if how in HOW else how}")


def _no_lone_sign(cell: _Cell, token: str, kind: str) -> None:
    """Refuse a cell that is a sign alone (``-``), saying how a reversed joint is written."""
    if token.strip().translate(_DASHES) in ("-", "+"):
        raise cell.fail(f"{token!r}, a sign on no number", f"{HOW[kind]}; a joint its data "
                        "sheet counts the other way is -q3 in theta (-d3 in d for a prismatic "
                        "joint), -1 in a direction column or the type R-")


def _read(cell: _Cell, token: str, kind: str, column_unit: str = "") -> float:
    """A length or an angle (radians) from one cell."""
    _no_lone_sign(cell, token, kind)
    try:
        v = _table_value(token)
    except (ValueError, SyntaxError, TypeError, RecursionError, OverflowError):
        raise cell.fail(f"{token!r} is not a number", kind) from None
    if kind == "length":
        if v.unit:
            raise cell.fail(f"{token!r} is an angle", "length")
        return v.number
    if v.unit in ("rad", "deg"):
        return v.number  # already radians (° multiplies by pi/180)
    if column_unit == "rad":
        return v.number
    if not column_unit:  # a header's "(deg)" says what its numbers are
        _no_rounded_radians(cell, token, v.number)
    return math.radians(v.number)


def _no_rounded_radians(cell: _Cell, token: str, number: float) -> None:
    """Refuse a bare number in a degree column that is a right angle (or several) in
    radians rounded, as slides print them: 1.5708, 1.571, 3.1416, -4.712. Read as degrees
    it would silently make another arm (a 1.5708 deg twist); ``1.5708°`` says it is meant."""
    quarters = round(number / (math.pi / 2))
    off = abs(number - quarters * math.pi / 2)
    if quarters and abs(quarters) <= 4 and off <= ROUNDED_RIGHT_ANGLE:
        degrees, exact = f"{quarters * 90}", _quarter_pi(quarters)
        raise cell.fail(
            f"{token!r}, a bare number, is read as {token} degrees, yet it looks like "
            f"{degrees} degrees in radians ({exact} rounded)",
            f"{degrees} (or {degrees}°, or {exact}) for that angle, {token}° if you do "
            f"mean {token} degrees, or name the column '{cell.column} (rad)' in a header "
            "row to read its numbers as radians")


def _quarter_pi(quarters: int) -> str:
    """``quarters`` times pi/2 written with pi: ``pi/2``, ``-pi``, ``3*pi/2``, ``2*pi``."""
    sign, n = ("-" if quarters < 0 else ""), abs(quarters)
    return {1: f"{sign}pi/2", 2: f"{sign}pi", 3: f"{sign}3*pi/2", 4: f"{sign}2*pi"}[n]


def _is_type(token: str) -> tuple[str, int] | None:
    """A joint type cell, ``R``, ``P``, ``R-`` or ``P+`` (any case), as (type, direction);
    None for anything else."""
    m = re.fullmatch(r"([RrPp])\s*([-+−–]?)", token.strip())
    if not m:
        return None
    return m.group(1).upper(), -1 if m.group(2) and m.group(2) != "+" else 1


def _variable(token: str) -> tuple[bool, str, int]:
    """Whether a theta or d cell holds the joint variable, the cell without it (the
    variable read as 0: the offset) and the variable's sign (``-q3`` is -1).

    Raises
    ------
    ValueError
        The variable is not there once, times +1 or -1 (``2*q3``, ``q3 - q3``), with why.
    """
    m = _VARIABLE.search(token)
    if not m:
        return False, token, 1
    rest = (token[:m.start()] + "0" + token[m.end():]).strip()
    if _VARIABLE.search(token, m.end()):
        raise ValueError("the joint variable is there twice")
    expr = _normalise(token[:m.start()] + "QVAR" + token[m.end():])
    try:
        tree = ast.parse(expr, mode="eval")
        f0, f1, f2 = (_evaluate(tree, q) for q in (0.0, 1.0, 2.0))
    except (ValueError, SyntaxError, TypeError, RecursionError, OverflowError):
        return True, rest, 1  # not arithmetic: reading the rest says what is wrong
    slope = f1 - f0
    # the variable inside a degree mark, (q2 + 90)°, counts in degrees: slope pi/180
    unit = 1.0 if abs(abs(slope) - 1.0) < abs(abs(slope) - math.pi / 180) else math.pi / 180
    if abs(abs(slope) - unit) > 1e-12 * unit or abs(f2 - f0 - 2 * slope) > 1e-12:
        raise ValueError(f"the joint variable is multiplied by {slope / unit:g}")
    return True, rest, 1 if slope > 0 else -1


def _joint_of(cell: _Cell, values: dict[str, str], theta_var: bool,
              d_var: bool) -> tuple[str, int]:
    """The joint type, from the type column or from where the joint variable is, and the
    direction the type says (``R-`` is -1, anything else +1)."""
    typed = values.get("type", "").strip()
    kind = _is_type(typed) if typed else None
    if typed and kind is None and typed.isalpha() and typed[:1].upper() in ("R", "P"):
        kind = (typed[:1].upper(), 1)  # revolute, prismatic
    if typed and kind is None:
        raise _Cell(cell.line, cell.raw, "type").fail(f"{values['type']!r}", "type")
    if kind is not None:
        joint, sign = kind
    elif "theta" not in values:
        joint, sign = "R", 1  # no theta column and no type: revolute, as in the plain rows
    elif not theta_var and not d_var:
        raise _Cell(cell.line, cell.raw, "theta").fail(
            "no joint variable", "the joint variable (q3, θ3) in theta for a revolute joint "
            "or in d for a prismatic one, or add a type column (R or P)")
    else:
        joint, sign = ("R" if theta_var else "P"), 1
    if joint == "R" and d_var:
        raise _Cell(cell.line, cell.raw, "d").fail(
            f"{values['d']!r}, a symbol", "its value, a number in the arm's units (this "
            "joint's variable is in theta)")
    if joint == "P" and theta_var:
        raise _Cell(cell.line, cell.raw, "theta").fail(
            f"{values['theta']!r}, a symbol", "its fixed angle, e.g. 0 or 90° (a prismatic "
            "joint's variable is in d)")
    return joint, sign


def _direction_of(cell: _Cell, values: dict[str, str], marks: dict[str, int]) -> int:
    """The joint's direction from the one place that says it: the direction column, a
    minus on the joint variable (``marks["theta"]``/``marks["d"]``) or the type (``R-``).
    Two places saying it is refused: two minuses would cancel, a ``+1`` and a ``-q3``
    contradict."""
    said = {col: s for col, s in marks.items() if s < 0}
    if "direction" in values:
        token = values["direction"].strip().translate(_DASHES).replace(" ", "")
        if token not in _DIRECTIONS:
            raise _Cell(cell.line, cell.raw, "direction").fail(f"{values['direction']!r}",
                                                                "direction")
        if said:
            col = next(iter(said))
            raise _Cell(cell.line, cell.raw, "direction").fail(
                f"{values['direction']!r} while {col} is {values[col]!r}",
                "the direction once: -1 in the direction column and q3 (not -q3) in "
                "theta, or -q3 and no direction column (two minuses would cancel)")
        return _DIRECTIONS[token]
    if len(said) > 1:
        first, second = list(said)
        raise _Cell(cell.line, cell.raw, second).fail(
            f"{values[second]!r} while {first} is {values[first]!r}",
            "the direction once: R- with q3 (not -q3), or R with -q3")
    return -1 if said else 1


def _bound(cell: _Cell, token: str, kind: str, unit: str, default: float) -> float:
    """One joint limit; ``default`` (an infinity) for ``none``."""
    t = token.strip().translate(_DASHES).lower()
    if t in _NO_LIMIT or t.lstrip("+-") in ("inf", "∞", "infinity"):
        return default
    return _read(cell, token, kind, unit)


def _range(cell: _Cell, token: str, kind: str, unit: str) -> tuple[float, float]:
    """A limits cell: ``-170..170``, ``-170 to 170``, ``±170``, or ``none``."""
    t = token.strip()
    for plus_minus in ("±", "+/-", "+-"):
        if t.startswith(plus_minus):
            v = _bound(cell, t[len(plus_minus):], kind, unit, math.inf)
            if v < 0:
                raise cell.fail(f"{token!r}", "limits")
            return -v, v
    if t.lower().translate(_DASHES) in _NO_LIMIT:
        return -math.inf, math.inf
    parts = re.split(r"\s*(?:\.\.\.?|…|\s+to\s+|(?<=[0-9°)])\s*[–—]\s*)\s*", t)
    if len(parts) != 2:
        raise cell.fail(f"{token!r}", "limits")
    return (_bound(cell, parts[0], kind, unit, -math.inf),
            _bound(cell, parts[1], kind, unit, math.inf))


def _limits_of(cell: _Cell, values: dict[str, str], joint: str,
               units: dict[str, str]) -> tuple[float, float] | None:
    """The joint's limits as the data sheet prints them (``limits``, or ``min`` and
    ``max`` columns), radians for a revolute joint; None when the table gives none."""
    if not {"limits", "min", "max"} & set(values):
        return None
    kind = "angle" if joint == "R" else "length"

    def at(col: str) -> _Cell:
        return _Cell(cell.line, cell.raw, col)

    if "limits" in values:
        lo, hi = _range(at("limits"), values["limits"], kind, units.get("limits", ""))
    else:
        lo = _bound(at("min"), values.get("min", "none"), kind, units.get("min", ""),
                    -math.inf)
        hi = _bound(at("max"), values.get("max", "none"), kind, units.get("max", ""),
                    math.inf)
    if lo > hi:
        col = "limits" if "limits" in values else "min"
        raise at(col).fail(f"a lower limit above the upper one ({values[col]!r})", "limits")
    return None if math.isinf(lo) and math.isinf(hi) else (lo, hi)


def _typed_row(cell: _Cell, values: dict[str, str], units: dict[str, str]) -> Link:
    """One row of a table with a header: its joint type from the type column or from
    where its joint variable is; its direction and limits when the table gives them."""
    read: dict[str, tuple[bool, str, int]] = {}
    for col in ("theta", "d"):
        _no_lone_sign(_Cell(cell.line, cell.raw, col), values.get(col, "0"),
                      "angle" if col == "theta" else "length")
        try:
            read[col] = _variable(values[col]) if col in values else (False, "0", 1)
        except ValueError as exc:
            raise _Cell(cell.line, cell.raw, col).fail(
                f"{values[col]!r}: {exc}", "variable") from None
    (theta_var, theta, theta_sign), (d_var, d, d_sign) = read["theta"], read["d"]
    joint, type_sign = _joint_of(cell, values, theta_var, d_var)
    direction = _direction_of(cell, values, {"type": type_sign, "theta": theta_sign,
                                             "d": d_sign})
    qlim = _limits_of(cell, values, joint, units)

    def angle(col: str, token: str) -> float:
        return _read(_Cell(cell.line, cell.raw, col), token, "angle", units.get(col, ""))

    def length(col: str, token: str) -> float:
        return _read(_Cell(cell.line, cell.raw, col), token, "length")

    a = length("a", values.get("a", "0"))
    alpha = angle("alpha", values.get("alpha", "0"))
    extra = values.get("offset")
    if joint == "R":
        offset = angle("theta", theta) + (angle("offset", extra) if extra else 0.0)
        return _link(cell, "R", d=length("d", d), a=a, alpha=alpha, offset=offset,
                     direction=direction, qlim=qlim)
    offset = length("d", d) if d_var else 0.0
    d_fixed = 0.0 if d_var else length("d", d)
    offset += length("offset", extra) if extra else 0.0
    return _link(cell, "P", d=d_fixed, a=a, alpha=alpha, offset=offset,
                 theta=angle("theta", theta), direction=direction, qlim=qlim)


def _link(cell: _Cell, joint: str, **fields: Any) -> Link:
    """``Link(joint, **fields)``; what it refuses is said with the row's line."""
    try:
        return Link(joint, **fields)  # type: ignore[arg-type]
    except InputError as exc:
        raise InputError(f"DH table line {cell.line} ({cell.raw!r}): {exc}") from None


def _plain_row(cell: _Cell, tokens: list[str]) -> Link:
    """One row of numbers: ``[type] d a alpha [offset]``, the type ``R-`` or ``P-`` for a
    joint its data sheet counts the other way."""
    joint, direction = "R", 1
    kind = _is_type(tokens[0])
    if kind is not None:
        (joint, direction), tokens = kind, tokens[1:]
    if not 3 <= len(tokens) <= 4:
        raise InputError(
            f"DH table line {cell.line} ({cell.raw!r}): expected 'type d a alpha offset' "
            f"(3 or 4 numbers after R or P; R- or P- for a joint its data sheet counts the "
            f"other way), got {len(tokens)} values; or name the columns in a header row "
            "(theta d a alpha, in any order; direction and limits too)")
    names = ("d", "a", "alpha", "offset")
    values = dict(zip(names, tokens, strict=False))
    kinds = {"d": "length", "a": "length", "alpha": "angle",
             "offset": "angle" if joint == "R" else "length"}
    v = {k: _read(_Cell(cell.line, cell.raw, k), t, kinds[k]) for k, t in values.items()}
    return _link(cell, joint, d=v["d"], a=v["a"], alpha=v["alpha"],
                 offset=v.get("offset", 0.0), direction=direction)


def _map_row(cell: _Cell, tokens: list[str],
             header: list[tuple[str, str]]) -> dict[str, str]:
    """The cells of a row by column name (a row may leave out the type, or the offset)."""
    cols = [c for c, _ in header]
    if len(tokens) == len(cols) - 1 and "type" in cols and _is_type(tokens[0]) is None:
        cols = [c for c in cols if c != "type"]
    elif len(tokens) == len(cols) - 1 and cols[-1] == "offset":
        cols = cols[:-1]
    if len(tokens) != len(cols):
        raise InputError(f"DH table line {cell.line} ({cell.raw!r}): {len(tokens)} values "
                         f"under a header of {len(cols)} columns ({', '.join(cols)}): one "
                         "value per column")
    return {c: t for c, t in zip(cols, tokens, strict=True) if c != "index"}


def _without_comment(raw: str) -> str:
    """The line before its ``#`` comment; a ``#`` that is a cell of its own in a ``|``
    table (``| # | θ | d | a | α |``, the joint number's column) starts none."""
    start = 0
    while (i := raw.find("#", start)) >= 0:
        if not (raw[:i].rstrip().endswith("|") and raw[i + 1:].lstrip().startswith("|")):
            return raw[:i]
        start = i + 1
    return raw


def arm_from_table(text: str, convention: str = "standard", units: str = "",
                   name: str = "your arm", tool: Any = None, base: Any = None) -> SerialArm:
    """A :class:`~rikin.SerialArm` from a DH table typed as text, one row per joint.

    Parameters
    ----------
    text : str
        The table (see the module's description): rows ``type d a alpha offset``, or any
        column order under a header row naming them (``| joint | theta | d | a | alpha |``);
        cells may be expressions (``pi/2``, ``-90°``, ``q2 + 90°``). ``#`` starts a
        comment (a ``| # |`` cell is the joint number's header); blank lines are skipped.
        For a modified-DH arm ``a`` and ``alpha`` of row i are ``a_{i-1}``,
        ``alpha_{i-1}`` (Craig), as in :class:`~rikin.Link`.
    convention : {"standard", "modified"}
    units : str
        Name of the length unit.
    name : str
    tool, base : array_like, shape (4, 4), optional
        ``T_n_tcp`` and ``T_world_0``; identity by default.

    Returns
    -------
    SerialArm

    Raises
    ------
    InputError
        A cell that cannot be read, naming the line, the column and how to write it.

    Examples
    --------
    >>> arm = arm_from_table("R 0 1 0\\nR 0 1 0", name="2R")
    >>> arm.fk([0.0, 0.0])[:3, 3]
    array([2., 0., 0.])
    >>> arm = arm_from_table("| i | θ | d | a | α |\\n|---|---|---|---|---|\\n"
    ...                      "| 1 | q1 | 0 | 1 | 0 |\\n| 2 | q2 + 90° | 0 | 1 | 0 |")
    >>> arm.fk([0.0, 0.0])[:3, 3].round(12)
    array([1., 1., 0.])
    """
    if not isinstance(text, str):
        raise InputError(f"the DH table must be text, got {type(text).__name__}")
    links: list[Link] = []
    header: list[tuple[str, str]] | None = None
    for number, raw in enumerate(text.splitlines(), 1):
        line = _without_comment(raw).strip()
        if not line or _SEPARATOR_ROW.match(line):
            continue
        tokens = row_tokens(line)
        if not tokens:
            continue
        if not links and header is None:
            header = _header(tokens)
            if header is not None or not any(_is_number(t) or _VARIABLE.search(t)
                                                   for t in tokens):
                continue  # a header row (or a line of words before the table)
        cell = _Cell(number, raw.strip(), "")
        if header is not None:
            values = _map_row(cell, tokens, header)
            links.append(_typed_row(cell, values, {c: u for c, u in header}))
        else:
            links.append(_plain_row(cell, tokens))
    if not links:
        raise InputError("the DH table has no rows: type one row 'R d a alpha offset' per joint")
    units = _length_unit(header, as_text(units, "units") or "")
    return SerialArm(tuple(links), convention=convention,  # type: ignore[arg-type]
                     base=np.eye(4) if base is None else base,
                     tool=np.eye(4) if tool is None else tool, units=units, name=name)
