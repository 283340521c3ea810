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
number degrees unless the column's header says ``(rad)``. Lengths are in the arm's units.
A cell that cannot be read is refused naming its line, its column and how to write it.
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

__all__ = ["arm_from_table", "row_tokens"]

#: Column names as books print them -> the column. Matched after :func:`_header_key`.
COLUMNS = {
    "theta": "theta", "θ": "theta", "th": "theta", "q": "theta", "jointangle": "theta",
    "d": "d", "a": "a", "r": "a", "alpha": "alpha", "α": "alpha", "twist": "alpha",
    "offset": "offset", "off": "offset", "thetaoffset": "offset", "θoffset": "offset",
    "θ0": "offset", "theta0": "offset", "type": "type", "jointtype": "type", "kind": "type",
    "rp": "type", "r/p": "type", "i": "index", "joint": "index", "link": "index",
    "#": "index", "n": "index", "j": "index", "axis": "index", "no.": "index", "no": "index",
}
ANGLES = ("theta", "alpha", "offset")
#: How to write a value, said when one cannot be read.
HOW = {"angle": "a number of degrees (90, -90°, 90 deg) or radians with pi (pi/2, -π/2)",
       "length": "a number in the arm's units (0.4318, 431.8; 1e-3)",
       "type": "R (revolute) or P (prismatic)"}

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


def _evaluate(node: ast.AST) -> float:
    """An arithmetic expression of numbers, pi and DEG; anything else is refused."""
    if isinstance(node, ast.Expression):
        return _evaluate(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not \
            isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id in ("pi", "DEG"):
        return math.pi if node.id == "pi" else math.pi / 180.0
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        v = _evaluate(node.operand)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult,
                                                            ast.Div)):
        left, right = _evaluate(node.left), _evaluate(node.right)
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
    for part in parts:
        if out and re.fullmatch(r"(?i)°|deg|degrees?|rad|radians?", part):
            out[-1] += part  # a unit after its number: 90 deg
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


def _header_key(token: str) -> tuple[str, str]:
    """A header cell as (column name key, unit the header gives: "rad", "deg" or "")."""
    t = token.strip().lower().replace("$", "").replace("\\", "")
    unit = ""
    m = re.search(r"[\(\[]\s*(rad|radians|deg|degrees|°|mm|m|cm|in)\s*[\)\]]", t)
    if m:
        unit = {"rad": "rad", "radians": "rad", "deg": "deg", "degrees": "deg",
                "°": "deg"}.get(m.group(1), "")
        t = t[:m.start()] + t[m.end():]
    t = re.sub(r"[{}\s]", "", t).translate(_SUBSCRIPTS)
    t = re.sub(r"_?\(?i(-1|−1)?\)?$", "", t) if len(t) > 1 else t  # θ_i, a_{i-1}, αi-1
    return t.rstrip("_"), unit


def _header(tokens: list[str]) -> list[tuple[str, str]] | None:
    """The columns a header row names, or None when it is not a header."""
    if any(_is_number(t) for t in tokens):
        return None
    keys = [_header_key(t) for t in tokens]
    named = [(COLUMNS.get(k), unit) for k, unit in keys]
    if sum(1 for c, _ in named if c in ("d", "a", "alpha", "theta")) < 2:
        return None
    if any(c is None for c, _ in named):
        unknown = [t for t, (c, _) in zip(tokens, named, strict=True) if c is None]
        raise InputError(f"DH table header: column {unknown[0]!r} is not one rikin knows; name "
                         "the columns theta (θ, q), d, a, alpha (α), offset, type (R or P) "
                         "or joint (its number)")
    cols = [c for c, _ in named]
    dup = [c for c in set(cols) if cols.count(c) > 1 and c != "index"]
    if dup:
        raise InputError(f"DH table header: two columns are {dup[0]!r}")
    return [(c, u) for c, u in named if c is not None]


@dataclass
class _Cell:
    line: int
    raw: str
    column: str

    def fail(self, what: str, how: str) -> InputError:
        return InputError(f"DH table line {self.line} ({self.raw!r}), column {self.column} = "
                          f"{what}: write {HOW[how] if how in HOW else how}")


def _read(cell: _Cell, token: str, kind: str, column_unit: str = "") -> float:
    """A length or an angle (radians) from one cell."""
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
    return v.number if column_unit == "rad" else math.radians(v.number)


def _variable(token: str) -> tuple[bool, str]:
    """Whether a theta or d cell holds the joint variable, and the cell without it."""
    m = _VARIABLE.search(token)
    if not m:
        return False, token
    rest = (token[:m.start()] + "0" + token[m.end():]).strip()
    return True, rest


def _typed_row(cell: _Cell, values: dict[str, str], units: dict[str, str]) -> Link:
    """One row of a table with a header: its joint type from the type column or from
    where its joint variable is."""
    theta_var, theta = _variable(values.get("theta", "0"))
    d_var, d = _variable(values.get("d", "0")) if "d" in values else (False, "0")
    joint = values.get("type", "").strip().upper()[:1]
    if joint and joint not in ("R", "P"):
        raise _Cell(cell.line, cell.raw, "type").fail(f"{values['type']!r}", "type")
    if not joint and "theta" not in values:
        joint = "R"  # no theta column and no type: revolute, as in the plain rows
    if not joint:
        if not theta_var and not d_var:
            raise cell.fail("no joint variable", "the joint variable (q3, θ3) in theta for a "
                            "revolute joint or in d for a prismatic one, or add a type column "
                            "(R or P)")
        joint = "R" if theta_var else "P"
    if joint == "R" and d_var:
        raise _Cell(cell.line, cell.raw, "d").fail(
            f"{values['d']!r}, a symbol", "its value, a number in the arm's units (this "
            "joint's variable is in theta)")
    if joint == "P" and theta_var:
        raise _Cell(cell.line, cell.raw, "theta").fail(
            f"{values['theta']!r}, a symbol", "its fixed angle, e.g. 0 or 90° (a prismatic "
            "joint's variable is in d)")

    def angle(col: str, token: str) -> float:
        return _read(_Cell(cell.line, cell.raw, col), token, "angle", units.get(col, ""))

    def length(col: str, token: str) -> float:
        return _read(_Cell(cell.line, cell.raw, col), token, "length")

    a = length("a", values.get("a", "0"))
    alpha = angle("alpha", values.get("alpha", "0"))
    extra = values.get("offset")
    if joint == "R":
        offset = angle("theta", theta) + (angle("offset", extra) if extra else 0.0)
        return Link("R", d=length("d", d), a=a, alpha=alpha, offset=offset)
    offset = length("d", d) if d_var else 0.0
    d_fixed = 0.0 if d_var else length("d", d)
    offset += length("offset", extra) if extra else 0.0
    return Link("P", d=d_fixed, a=a, alpha=alpha, offset=offset, theta=angle("theta", theta))


def _plain_row(cell: _Cell, tokens: list[str]) -> Link:
    """One row of numbers: ``[type] d a alpha [offset]``."""
    joint = "R"
    if tokens[0].upper() in ("R", "P"):
        joint, tokens = tokens[0].upper(), tokens[1:]
    if not 3 <= len(tokens) <= 4:
        raise InputError(
            f"DH table line {cell.line} ({cell.raw!r}): expected 'type d a alpha offset' "
            f"(3 or 4 numbers after R or P), got {len(tokens)} values; or name the columns "
            "in a header row (theta d a alpha, in any order)")
    names = ("d", "a", "alpha", "offset")
    values = dict(zip(names, tokens, strict=False))
    kinds = {"d": "length", "a": "length", "alpha": "angle",
             "offset": "angle" if joint == "R" else "length"}
    v = {k: _read(_Cell(cell.line, cell.raw, k), t, kinds[k]) for k, t in values.items()}
    return Link("P" if joint == "P" else "R", d=v["d"], a=v["a"], alpha=v["alpha"],
                offset=v.get("offset", 0.0))


def _map_row(cell: _Cell, tokens: list[str],
             header: list[tuple[str, str]]) -> dict[str, str]:
    """The cells of a row by column name (a row may leave out the type, or the offset)."""
    cols = [c for c, _ in header]
    if len(tokens) == len(cols) - 1 and "type" in cols and tokens[0].upper() not in ("R", "P"):
        cols = [c for c in cols if c != "type"]
    elif len(tokens) == len(cols) - 1 and cols[-1] == "offset":
        cols = cols[:-1]
    if len(tokens) != len(cols):
        raise InputError(f"DH table line {cell.line} ({cell.raw!r}): {len(tokens)} values "
                         f"under a header of {len(cols)} columns ({', '.join(cols)}): one "
                         "value per column")
    return {c: t for c, t in zip(cols, tokens, strict=True) if c != "index"}


def arm_from_table(text: str, convention: str = "standard", units: str = "",
                   name: str = "your arm", tool: Any = None, base: Any = None) -> SerialArm:
    """A :class:`~rikin.SerialArm` from a DH table typed as text, one row per joint.

    Parameters
    ----------
    text : str
        The table (see the module's description): rows ``type d a alpha offset``, or any
        column order under a header row naming them (``| joint | theta | d | a | alpha |``);
        cells may be expressions (``pi/2``, ``-90°``, ``q2 + 90°``). ``#`` starts a
        comment; blank lines are skipped. For a modified-DH arm ``a`` and ``alpha`` of row
        i are ``a_{i-1}``, ``alpha_{i-1}`` (Craig), as in :class:`~rikin.Link`.
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
        line = raw.split("#", 1)[0].strip()
        if not line or _SEPARATOR_ROW.match(line):
            continue
        tokens = row_tokens(line)
        if not tokens:
            continue
        if not links and header is None:
            header = _header(tokens)
            if header is not None or not any(_is_number(t) or _variable(t)[0] for t in tokens):
                continue  # a header row (or a line of words before the table)
        cell = _Cell(number, raw.strip(), "")
        if header is not None:
            values = _map_row(cell, tokens, header)
            links.append(_typed_row(cell, values, {c: u for c, u in header}))
        else:
            links.append(_plain_row(cell, tokens))
    if not links:
        raise InputError("the DH table has no rows: type one row 'R d a alpha offset' per joint")
    return SerialArm(tuple(links), convention=convention,  # type: ignore[arg-type]
                     base=np.eye(4) if base is None else base,
                     tool=np.eye(4) if tool is None else tool, units=units, name=name)
