"""Symbolic DH matrices (sympy), to reproduce the lessons' derivations in the book.

The numeric side of rikin (:mod:`rikin.dh`) computes poses; this module
writes the same products as formulas, so a chapter can show ``R_0_3`` or
``T_0_5`` the way a lesson prints it and check the lesson's matrix against it.

Conventions
-----------
* Joint variables (see :func:`joint_symbols`): joint ``i`` (numbered from 1)
  is the real sympy Symbol ``q{i}`` when revolute and ``d{i}`` when
  prismatic, e.g. ``(d1, d2, q3, q4, q5)`` for the PPRRR of the notes.
  ``q{i}`` is the joint *variable*: the link's offset is added to it, as in
  :mod:`rikin.dh` (``theta_i = q_i + offset``). Pass ``revolute="theta"`` to
  get ``theta1, ...`` (printed as :math:`\\theta_{1}`) like Aula 10.
* Frames are numbered 0..n; :func:`transform` returns ``T_start_end`` (the
  pose of frame ``end`` in frame ``start``), without the arm's base or tool.
* Angles given as floats that are multiples of pi/12 become exact (``pi/2``
  instead of ``1.5707963267948966``), so products simplify exactly.
* :func:`abbreviate`, :func:`short_trig` and :func:`latex_short` write
  ``cos(q1)`` as ``C1`` and ``sin(q2 + q3)`` as ``S23``, the lessons' notation.

Examples
--------
>>> import sympy
>>> links, lengths, q, conv = lesson_arm("angular_3r")
>>> R_0_3 = rotation(links, conv, 0, 3)
>>> short_trig(R_0_3[2, 0])
'S23'
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np
import sympy as sp
from sympy.simplify.fu import TR10i

from . import robots
from ._validate import as_choice, as_flag, as_real, check_index
from .dh import Link, SerialArm
from .errors import InputError

__all__ = [
    "dh_matrix", "joint_symbols", "link_matrix", "transform", "rotation", "simplify_trig",
    "abbreviate", "short_trig", "latex_short", "numeric", "lesson_arm", "LessonArm",
    "LESSON_LENGTHS",
]

#: Float angles within this of a multiple of pi/12 are replaced by the exact multiple.
EXACT_ANGLE_TOL = 1e-12

#: The lessons' names of each lesson robot's length parameters, in constructor order.
LESSON_LENGTHS: dict[str, tuple[str, ...]] = {
    "planar_2r": ("l1", "l2"),
    "planar_3r": ("l1", "l2", "l3"),
    "angular_3r": ("l1", "l2", "l3"),
    "aula10_6r": ("l1", "l2", "l3", "l4", "l5", "l6"),
    "barrientos_6r": ("l1", "l2", "l3", "l4"),
    "pprrr": ("a1", "a2", "a3"),
    "rprrr": ("a1", "a2", "a3", "a4"),
    "epson_c4": ("d1", "a1", "a2", "d4"),
}

#: Lengths that may be negative (the C4's d4 = -250 mm): real, not positive, symbols.
_SIGNED_LENGTHS = {("epson_c4", "d4")}

_CONVENTIONS = ("standard", "modified")


# ------------------------------------------------------------------ exact values
def _exact(x: Any, angle: bool = False, name: str = "the value") -> sp.Expr:
    """``x`` as a sympy expression; floats made exact where that is safe.

    Integers stay integers; a float angle near ``k pi / 12`` becomes exactly
    that; other floats become a short rational when their decimal form is
    short (``0.065`` -> ``13/200``) and a ``Float`` otherwise.
    """
    if isinstance(x, sp.Basic):
        if not isinstance(x, sp.Expr):
            raise InputError(f"{name} must be a number or a sympy expression, got {x!r:.80}")
        return x
    if isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_)):
        return sp.Integer(int(x))
    f = as_real(x, name)  # refuses text, booleans, complex numbers, None, NaN, infinity
    if angle:
        k = round(f / (np.pi / 12))
        if abs(f - k * np.pi / 12) <= EXACT_ANGLE_TOL:
            return sp.Rational(k, 12) * sp.pi
    if f == int(f):
        return sp.Integer(int(f))
    text = repr(f)
    if "e" not in text and len(text.replace("-", "").replace(".", "").lstrip("0")) <= 8:
        return sp.Rational(text)
    return sp.Float(f)


def _check_convention(convention: Any) -> str:
    return as_choice(convention, "convention", _CONVENTIONS)


def _sympify(expr: Any, name: str) -> Any:
    """A sympy expression or matrix from ``expr``: numbers and sympy objects, never text
    (sympify would evaluate it as Python) nor booleans, None or arrays of objects."""
    if isinstance(expr, sp.MatrixBase):
        return expr
    if expr is None or isinstance(expr, (str, bytes, bool, np.bool_)):
        raise InputError(f"{name} must be a sympy expression or Matrix, got {expr!r:.80}")
    try:
        out = sp.sympify(expr, strict=True)
    except (sp.SympifyError, TypeError, ValueError, AttributeError) as exc:
        raise InputError(f"{name} must be a sympy expression or Matrix, got {expr!r:.80}") from exc
    if not isinstance(out, (sp.Expr, sp.MatrixBase)):
        raise InputError(f"{name} must be a sympy expression or Matrix, got {expr!r:.80}")
    if out.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise InputError(f"{name} holds NaN or infinity: {expr!r:.80}")
    return out


# ------------------------------------------------------------------ elementary matrices
def _rotz(t: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def _rotx(t: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def _trans(x: Any = 0, y: Any = 0, z: Any = 0) -> sp.Matrix:
    M = sp.eye(4)
    M[0, 3], M[1, 3], M[2, 3] = x, y, z
    return M


def dh_matrix(theta: Any, d: Any, a: Any, alpha: Any, convention: str = "standard") -> sp.Matrix:
    """The 4x4 homogeneous transform ``T_{i-1,i}`` of one DH row, exact.

    Parameters
    ----------
    theta, d, a, alpha : number or sympy expression
        The row's joint angle (rad), offset and length (length units) and
        twist (rad). For ``"modified"``, ``a`` and ``alpha`` are ``a_{i-1}``
        and ``alpha_{i-1}``. Float angles that are multiples of pi/12 are
        made exact (``sympy.pi / 2``).
    convention : {"standard", "modified"}
        ``"standard"``: ``Rz(theta) Tz(d) Tx(a) Rx(alpha)``;
        ``"modified"`` (Craig): ``Rx(alpha) Tx(a) Rz(theta) Tz(d)``.

    Returns
    -------
    T : sympy.Matrix, shape (4, 4)

    Examples
    --------
    >>> import sympy
    >>> th = sympy.Symbol("q1", real=True)
    >>> dh_matrix(th, 0, 0, sympy.pi / 2)[:3, :3]
    Matrix([
    [cos(q1), 0,  sin(q1)],
    [sin(q1), 0, -cos(q1)],
    [      0, 1,        0]])
    """
    _check_convention(convention)
    th, dd = _exact(theta, angle=True, name="theta"), _exact(d, name="d")
    aa, al = _exact(a, name="a"), _exact(alpha, angle=True, name="alpha")
    if convention == "standard":
        return _rotz(th) * _trans(z=dd) * _trans(x=aa) * _rotx(al)
    return _rotx(al) * _trans(x=aa) * _rotz(th) * _trans(z=dd)


# ------------------------------------------------------------------ symbols and links
def _links_of(links: Any, convention: str | None) -> tuple[tuple[Link, ...], str]:
    if isinstance(links, SerialArm):
        return links.links, _check_convention(links.convention if convention is None
                                              else convention)
    if not isinstance(links, (list, tuple)):
        raise InputError(f"links must be a list of rikin.Link or a SerialArm, got {links!r:.80}")
    seq = tuple(links)
    if not seq:
        raise InputError("links is empty: give at least one rikin.Link")
    for i, lk in enumerate(seq, 1):
        if not isinstance(lk, Link):
            raise InputError(f"links[{i - 1}] must be a rikin.Link, got {type(lk).__name__}")
    return seq, _check_convention("standard" if convention is None else convention)


def joint_symbols(links: Any, revolute: str = "q", prismatic: str = "d") -> tuple[sp.Symbol, ...]:
    """One real sympy Symbol per joint: ``q{i}`` (revolute) or ``d{i}`` (prismatic).

    Parameters
    ----------
    links : sequence of Link or SerialArm
    revolute, prismatic : str
        Name prefixes; ``revolute="theta"`` gives ``theta1, ...`` as in Aula 10.

    Returns
    -------
    q : tuple of sympy.Symbol, length n
        Joints numbered from 1, e.g. ``(d1, d2, q3, q4, q5)`` for the PPRRR.

    Examples
    --------
    >>> from rikin.robots import rprrr_links
    >>> joint_symbols(rprrr_links())
    (q1, d2, q3, q4, q5)
    """
    seq, _ = _links_of(links, None)
    for p in (revolute, prismatic):
        if not isinstance(p, str) or not re.fullmatch(r"[A-Za-z]+", p):
            which = "revolute" if p is revolute else "prismatic"
            raise InputError(f"{which} (a symbol prefix) must be letters only, got {p!r:.80}")
    return tuple(sp.Symbol(f"{revolute if lk.is_revolute else prismatic}{i}", real=True)
                 for i, lk in enumerate(seq, 1))


def link_matrix(link: Link, q_symbol: Any, convention: str = "standard") -> sp.Matrix:
    """``T_{i-1,i}`` of one :class:`~rikin.dh.Link` with joint variable ``q_symbol``.

    Revolute: ``theta = s q + offset`` and ``d = link.d``; prismatic:
    ``theta = link.theta`` and ``d = link.d + s q + offset`` (as :mod:`rikin.dh`), with
    ``s = link.direction`` (+1, or -1 for a joint its data sheet counts the other way).

    Parameters
    ----------
    link : Link
        Its fields may be numbers or sympy expressions.
    q_symbol : sympy expression or number
        The joint variable (rad or length units).
    convention : {"standard", "modified"}

    Returns
    -------
    T : sympy.Matrix, shape (4, 4)
    """
    if not isinstance(link, Link):
        raise InputError(f"link must be a rikin.Link, got {type(link).__name__}")
    q = _exact(q_symbol, name="q_symbol") * link.direction
    offset = _exact(link.offset, angle=link.is_revolute, name="link.offset")
    if link.is_revolute:
        return dh_matrix(q + offset, link.d, link.a, link.alpha, convention)
    return dh_matrix(link.theta, _exact(link.d) + q + offset, link.a, link.alpha, convention)


# ------------------------------------------------------------------ simplification
def simplify_trig(expr: Any) -> Any:
    """Expand, then fold ``C1 C2 - S1 S2`` into ``cos(q1 + q2)`` (sympy's ``TR10i``).

    Fast (a fraction of a second for a 6R ``T_0_6``, where ``trigsimp`` takes
    seconds) and enough for DH products, whose only identities are the
    angle-sum formulas of parallel joints. Works entrywise on matrices.
    """
    def one(e: sp.Expr) -> sp.Expr:
        return TR10i(sp.expand(e))

    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(one)
    return one(_sympify(expr, "expr"))


def _frames(links: Any, convention: str | None, start: int, end: int | None,
            q: Any) -> tuple[tuple[Link, ...], str, int, int, tuple[sp.Expr, ...]]:
    seq, conv = _links_of(links, convention)
    n = len(seq)
    end = n if end is None else end
    for name, v in (("start", start), ("end", end)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v <= n:
            raise InputError(f"{name} must be a frame number 0..{n} for this {n}-joint arm, "
                             f"got {v!r}")
    if q is None:
        qs = joint_symbols(seq)
    else:
        if not isinstance(q, (list, tuple, np.ndarray, sp.MatrixBase)) or (
                isinstance(q, np.ndarray) and q.ndim != 1) or (
                isinstance(q, sp.MatrixBase) and q.shape[1] != 1):
            raise InputError(f"q must be a sequence of {n} joint values or symbols, "
                             f"got {q!r:.80}")
        qs = tuple(_exact(v, name=f"q[{i}]") for i, v in enumerate(q))
        if len(qs) != n:
            raise InputError(f"q must have {n} entries (one per joint), got {len(qs)}")
    return seq, conv, int(start), int(end), qs


def transform(links: Any, convention: str | None = None, start: int = 0, end: int | None = None,
              q: Any = None, simplify: bool = True) -> sp.Matrix:
    """``T_start_end``: the pose of frame ``end`` in frame ``start``, as formulas.

    The product ``T_{start,start+1} ... T_{end-1,end}`` of the DH link
    matrices (frames 0..n; no base, no tool). With ``start > end`` it is the
    inverse, ``T_end_start^-1`` (e.g. ``(R_3^0)^-1`` of Aula 10).

    Parameters
    ----------
    links : sequence of Link or SerialArm
        A DH table, e.g. ``rikin.robots.aula10_6r_links(*sympy.symbols("l1:7"))``.
    convention : {"standard", "modified"}, optional
        Default: the arm's convention, or ``"standard"`` for a list of links.
    start, end : int
        Frame numbers in 0..n; ``end`` defaults to n.
    q : sequence of n sympy expressions or numbers, optional
        The joint variables; default :func:`joint_symbols` (``q1``, ``d2``, ...).
    simplify : bool
        Apply :func:`simplify_trig` to every entry.

    Returns
    -------
    T : sympy.Matrix, shape (4, 4)

    Raises
    ------
    InputError
        Bad links, convention, frame numbers or number of joint values.

    Examples
    --------
    >>> links, lengths, q, conv = lesson_arm("planar_2r")
    >>> transform(links, conv)[0, 3]
    l1*cos(q1) + l2*cos(q1 + q2)
    """
    seq, conv, i0, i1, qs = _frames(links, convention, start, end, q)
    simplify = as_flag(simplify, "simplify")
    lo, hi = min(i0, i1), max(i0, i1)
    T = sp.eye(4)
    for k in range(lo, hi):
        T = T * link_matrix(seq[k], qs[k], conv)
        if simplify:
            T = simplify_trig(T)
    if i0 > i1:
        R_t = T[:3, :3].T
        p = -R_t * T[:3, 3]
        T = R_t.row_join(p).col_join(sp.Matrix([[0, 0, 0, 1]]))
        if simplify:
            T = simplify_trig(T)
    return T


def rotation(links: Any, convention: str | None = None, start: int = 0, end: int | None = None,
             q: Any = None, simplify: bool = True) -> sp.Matrix:
    """``R_start_end``: the rotation block of :func:`transform`, shape (3, 3).

    Computed from 3x3 products only, which is quicker than the 4x4 product.
    Parameters as in :func:`transform`.

    Examples
    --------
    >>> links, lengths, q, conv = lesson_arm("aula10_6r")
    >>> rotation(links, conv, 0, 1)
    Matrix([
    [cos(q1), 0,  sin(q1)],
    [sin(q1), 0, -cos(q1)],
    [      0, 1,        0]])
    """
    seq, conv, i0, i1, qs = _frames(links, convention, start, end, q)
    simplify = as_flag(simplify, "simplify")
    lo, hi = min(i0, i1), max(i0, i1)
    R = sp.eye(3)
    for k in range(lo, hi):
        lk = seq[k]
        # lengths do not change a rotation: only theta and alpha enter
        theta = (_exact(qs[k]) * lk.direction + _exact(lk.offset, angle=True)
                 if lk.is_revolute else lk.theta)
        R = R * dh_matrix(theta, 0, 0, lk.alpha, conv)[:3, :3]
        if simplify:
            R = simplify_trig(R)
    return R.T if i0 > i1 else R


# ------------------------------------------------------------------ lesson notation
_JOINT_NAME = re.compile(r"^(?:q|theta|θ|d)_?\{?(\d+)\}?$")


def _joint_index(sym: sp.Symbol, joints: dict[sp.Symbol, int] | None) -> int | None:
    if joints is not None:
        return joints.get(sym)
    m = _JOINT_NAME.match(sym.name)
    return int(m.group(1)) if m else None


def _short_name(arg: sp.Expr, joints: dict[sp.Symbol, int] | None) -> str | None:
    """``"23"`` for ``q2 + q3``; None when ``arg`` is not a plain sum of joint symbols."""
    terms = sp.Add.make_args(arg)
    idx = []
    for t in terms:
        if not isinstance(t, sp.Symbol):
            return None
        i = _joint_index(t, joints)
        if i is None:
            return None
        idx.append(i)
    if len(set(idx)) != len(idx):
        return None
    idx.sort()
    return "".join(map(str, idx)) if all(i < 10 for i in idx) else ",".join(map(str, idx))


def _joint_map(joints: Sequence[sp.Symbol] | None) -> dict[sp.Symbol, int] | None:
    if joints is None:
        return None
    if not isinstance(joints, (list, tuple)) or not all(isinstance(s, sp.Symbol) for s in joints):
        raise InputError(f"joints must be a sequence of sympy Symbols (q1, q2, ...) or None, "
                         f"got {joints!r:.80}")
    return {s: i for i, s in enumerate(joints, 1)}


def abbreviate(expr: Any, joints: Sequence[sp.Symbol] | None = None) -> Any:
    """``expr`` with ``cos(q1)`` replaced by a Symbol ``C1``, ``sin(q2 + q3)`` by ``S23``.

    Parameters
    ----------
    expr : sympy expression or Matrix
    joints : sequence of sympy.Symbol, optional
        The joint variables, numbered from 1 in order. Default: any symbol
        named ``q<i>``, ``theta<i>`` or ``d<i>`` counts as joint ``i``.

    Returns
    -------
    sympy expression or Matrix
        Arguments that are not plain sums of joint symbols (``q1 - q2``,
        ``2 q1``) are left as they are.
    """
    jm = _joint_map(joints)
    expr = _sympify(expr, "expr")

    def short(x: Any) -> Any:
        """``sin``/``cos`` of a plain sum of joints as its symbol ``S12``/``C1_2``, else ``x``."""
        name = _short_name(x.args[0], jm) if isinstance(x, (sp.sin, sp.cos)) else None
        if name is None:
            return x
        return sp.Symbol(("S" if isinstance(x, sp.sin) else "C") + name.replace(",", "_"),
                         real=True)

    def repl(e: sp.Expr) -> sp.Expr:
        return e.replace(lambda x: isinstance(x, (sp.sin, sp.cos)), short)

    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(repl)
    return repl(expr)


def short_trig(expr: Any, joints: Sequence[sp.Symbol] | None = None) -> str:
    """``expr`` as text in the lessons' notation: ``C1*S23`` for ``cos(q1) sin(q2 + q3)``.

    Examples
    --------
    >>> import sympy
    >>> q1, q2, q3 = sympy.symbols("q1:4", real=True)
    >>> short_trig(sympy.cos(q1) * sympy.sin(q2 + q3))
    'C1*S23'
    """
    return str(abbreviate(expr, joints))


def latex_short(expr: Any, joints: Sequence[sp.Symbol] | None = None) -> str:
    """LaTeX of ``expr`` (a matrix or expression) with ``C_{1}``, ``S_{23}`` as the lessons print.

    Examples
    --------
    >>> import sympy
    >>> q1 = sympy.Symbol("q1", real=True)
    >>> latex_short(sympy.Matrix([[sympy.cos(q1), -sympy.sin(q1)]]))
    '\\\\left[\\\\begin{matrix}C_{1} & - S_{1}\\\\end{matrix}\\\\right]'
    """
    short = abbreviate(expr, joints)
    names = {s: f"{s.name[0]}_{{{s.name[1:].replace('_', ',')}}}" for s in short.free_symbols
             if re.fullmatch(r"[CS]\d+(?:_\d+)*", s.name)}
    return sp.latex(short, symbol_names=names)


# ------------------------------------------------------------------ numbers
def numeric(expr_or_matrix: Any, subs: dict[Any, Any]) -> Any:
    """Evaluate a formula or matrix with float values for every symbol.

    Parameters
    ----------
    expr_or_matrix : sympy expression or Matrix
    subs : dict
        Symbol (or symbol name, a str) -> number. Every free symbol needs a value.

    Returns
    -------
    numpy.ndarray of float, the matrix's shape; numpy.float64 for a scalar.

    Raises
    ------
    InputError
        A symbol has no value, a value is not a finite number, or the result
        is not real.

    Examples
    --------
    >>> import sympy
    >>> q1 = sympy.Symbol("q1", real=True)
    >>> numeric(sympy.cos(q1), {"q1": 0.0})
    np.float64(1.0)
    """
    obj = _sympify(expr_or_matrix, "expr_or_matrix")
    if not isinstance(subs, dict):
        raise InputError(f"subs must be a dict of symbol (or its name) -> number, got "
                         f"{subs!r:.80}")
    free = obj.free_symbols
    by_name = {s.name: s for s in free}
    values: dict[sp.Symbol, sp.Float] = {}
    for k, v in dict(subs).items():
        sym = by_name.get(k) if isinstance(k, str) else k
        if sym is None:
            continue  # a name that does not appear: nothing to substitute
        try:
            values[sym] = sp.Float(as_real(v, str(k)), 30)
        except InputError as exc:
            raise InputError(f"the value of {k} must be a number ({exc})") from None
    missing = sorted(s.name for s in free if s not in values)
    if missing:
        raise InputError(f"no value given for {', '.join(missing)} in subs (symbols of "
                         "expr_or_matrix)")
    out = obj.xreplace(values).evalf(20)
    try:
        arr = np.array(out.tolist() if isinstance(out, sp.MatrixBase) else out, dtype=np.complex128)
    except TypeError as exc:
        raise InputError(f"expr_or_matrix does not evaluate to numbers: {out}") from exc
    if np.any(np.abs(arr.imag) > 0):
        raise InputError("expr_or_matrix evaluates to a complex number with these subs: a "
                         "square root or log of a negative value?")
    res = arr.real.astype(np.float64)
    return res if res.ndim else np.float64(res)


# ------------------------------------------------------------------ lesson robots
class LessonArm(NamedTuple):
    """A lesson robot's DH table with symbols (see :func:`lesson_arm`)."""

    links: list[Link]
    lengths: tuple[sp.Symbol, ...]
    joints: tuple[sp.Symbol, ...]
    convention: str

    def __getitem__(self, key: Any) -> Any:
        """``arm[0]`` is ``arm.links`` (a tuple's indexing); a bad index is an InputError
        naming the fields (an :class:`~rikin.errors.OutOfRangeError` beyond them)."""
        check_index(key, (4,), "LessonArm", ("field",), attributes=self._fields, arrays=False,
                    var="arm")
        return tuple.__getitem__(self, key)


def lesson_arm(name: str, **options: Any) -> LessonArm:
    """A lesson robot's DH table with the lesson's length symbols, for symbolic work.

    Parameters
    ----------
    name : str
        A key of :data:`rikin.robots.LESSON_ROBOTS`.
    **options
        Passed to ``rikin.robots.<name>_links``, e.g. ``theta1=sympy.pi / 2``
        for the PPRRR (the reconstruction in the errata).

    Returns
    -------
    LessonArm
        ``(links, lengths, joints, convention)``; unpack it as a tuple. Length
        symbols are positive except the C4's ``d4`` (real: it is -250 mm).
        The C4's joint limits are dropped. ``T_0_n`` excludes any tool (the
        C4's tool is ``Rx(pi) Tz(65)``, its ``SerialArm.tool``).

    Examples
    --------
    >>> links, lengths, q, conv = lesson_arm("epson_c4")
    >>> lengths, q, conv
    ((d1, a1, a2, d4), (q1, q2, q3, q4, q5, q6), 'modified')
    """
    if not isinstance(name, str) or name not in LESSON_LENGTHS:
        raise InputError(f"unknown lesson robot name {name!r:.80}; choose one of "
                         f"{sorted(LESSON_LENGTHS)}")
    lengths = tuple(sp.Symbol(s, real=True) if (name, s) in _SIGNED_LENGTHS
                    else sp.Symbol(s, positive=True) for s in LESSON_LENGTHS[name])
    table = getattr(robots, f"{name}_links")
    if name == "epson_c4":
        options.setdefault("limits", False)
    links = table(*lengths, **options)
    convention = "modified" if name == "epson_c4" else "standard"
    return LessonArm(links, lengths, joint_symbols(links), convention)
