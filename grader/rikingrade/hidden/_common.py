"""Hidden-test building blocks shared by the four arm exercises.

Each factory returns a :class:`~rikingrade.spec.HiddenTest` whose
``make_calls`` draws random link lengths and targets from the engine's rng
and whose ``check`` scores the student's outcomes against the reference
(:mod:`rikingrade.reference`), in the grader process:

* FK and DH answers are compared pose by pose;
* IK answers are compared with the reference **as a set**: order free,
  angles modulo 2*pi, prismatic values to a tolerance; duplicates are merged;
  missing and extra solutions are reported separately; every returned
  solution is also put through the reference FK, which says why an extra
  one is wrong; at a singular target any member of a family counts;
* at and near a singular configuration a solution is judged by FK and by the
  family it belongs to, not by its joint distance to the reference's representative:
  every returned row that reaches the target (FK within POSE_TOL) and respects the
  joint limits is a solution, counted for the nearest reference branch;
* the cost of an answer is bounded: at most MAX_ROWS rows are read, and matching
  is linear in the rows (a few vectorised passes);
* unreachable targets must raise ValueError (or a subclass); a value the grader cannot
  read is a wrong return, never a pass of "must raise".

Inputs reach the student's function as the stubs annotate them: ``q``, ``p`` and ``T``
as float64 numpy arrays, lengths as Python floats, passed positionally in the order of
the stub's signature (parameter names do not matter).

Partial credit: a test's fraction is the mean over its cases; an IK case
scores ``matched / (expected + wrong)``. Feedback is composed by the grader from a
whitelist (test names, counts, the grader's own words, exception class names that
are Python's or rikin's): no student-controlled text (messages, class or type names
of the notebook's own) is echoed next to hidden values, and numbers equal to a hidden
input or expected value are masked as a last guard, unless ``reveal``.
"""

from __future__ import annotations

import builtins
import re
import reprlib
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import rikin

from ..i18n import N_, label, t
from ..reference._common import (
    NEAR_SINGULAR,
    REACH_TOL,
    ExerciseArm,
    FloatArray,
    Solutions,
    wrap,
)
from ..spec import Call, HiddenTest, Outcome, Score, _plain

#: A student's joint value within this of the reference's matches (rad; for
#: prismatic joints times the arm's size).
JOINT_TOL = 1e-6
#: A pose within this of the target is reached (position: times the arm's size).
POSE_TOL = 1e-6
#: Revolute values beyond this (rad) look like degrees.
DEGREES_SUSPECT = 2 * np.pi + 1e-6
#: Exception names accepted as "raised ValueError" (rikin's errors subclass it).
RIKIN_VALUE_ERRORS = {"RikinError", "InputError", "IKError", "UnreachableError"}
#: At most this many rows of an IK answer are read (the arms have at most 4 solutions;
#: duplicates are free, but an answer may not cost the grader without bound: matching is
#: linear in the rows, about 1 s for this many on one core).
MAX_ROWS = 10_000
#: Wrong rows explained one by one (FK in degrees etc.); more are counted, not explained.
MAX_WRONG_EXPLAINED = 64
#: A row that reaches the target belongs to the nearest reference branch when it is
#: within this of it (rad, or times the arm's size): near a singularity the IK is
#: ill-conditioned, so a right answer can sit 1e-4 from the representative.
BRANCH_TOL = 0.05
#: Imaginary parts up to this (times max(1, |value|)) are rounding, not complex answers.
IMAG_TOL = 1e-9

#: Wall-clock seconds per call. The reference answers a call in about a millisecond
#: and a student's numerical solution (scipy, sympy.nsolve) in about 50 ms; what
#: needs longer is a loop that does not end (sympy.solve on these equations takes
#: minutes). An instructor can change it with ``rikin-grade --timeout``.
TIMEOUT = 2.0

#: Reference answers kept per hidden test (a run has a few dozen distinct calls).
REF_CACHE_SIZE = 4096

N_FK = 5
N_DH = 4
N_IK = 5


# ------------------------------------------------------------------ outcomes and text
def _fmt(v: Any, digits: int = 4) -> str:
    a = np.asarray(v, dtype=float).round(digits) + 0.0
    return "(" + ", ".join(f"{x:.{digits}g}" for x in a.ravel()) + ")"


_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def mask_numbers(text: str) -> str:
    """The text with every number replaced by '#' (for the instructor's tools only)."""
    return _NUMBER.sub("#", text)


def hidden_numbers(calls: list[Call]) -> np.ndarray:
    """Every number of the calls' inputs (absolute values), for :func:`mask_hidden`."""
    vals: list[float] = []
    for c in calls:
        for v in c.kwargs.values():
            try:
                vals.extend(np.abs(np.ravel(np.asarray(v, dtype=float))).tolist())
            except (TypeError, ValueError):
                pass
    return np.unique(np.array([v for v in vals if v > 1e-3 and np.isfinite(v)]))


def mask_hidden(text: str, hidden: np.ndarray) -> str:
    """``text`` with the numbers that show a hidden value to 3 or more significant digits
    masked as '#'. Only those: counts ("3/5"), a student's words, rikin's "l2 + l3" and
    "joint 3" stay as they are.
    """
    if not hidden.size:
        return text

    def sub(m: re.Match) -> str:
        token = m.group(0)
        mantissa, _, exp = token.lstrip("+-").lower().partition("e")
        digits = mantissa.replace(".", "").lstrip("0")
        if len(digits) < 3:
            return token
        decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
        try:
            x = abs(float(token))
            tol = 0.5 * 10.0 ** (-decimals + (int(exp) if exp else 0))
        except (ValueError, OverflowError):
            return token
        return "#" if np.any(np.abs(hidden - x) <= tol * (1 + 1e-9)) else token

    return _NUMBER.sub(sub, text)


def sentences(parts: list[str]) -> str:
    """Join feedback fragments into sentences, each starting with a capital letter."""
    return " ".join(p[:1].upper() + p[1:] + ("" if p.endswith(".") else ".") for p in parts if p)


#: Python's and rikin's exception messages that carry nothing a call's input could
#: choose beyond a known type name or a one- or two-digit count; only these are shown.
_TYPE = (
    r"'?(?:list|tuple|dict|set|str|int|float|complex|bool|NoneType|numpy\.ndarray|ndarray"
    r"|function|numpy\.float64)'?"
)
_SAFE_MESSAGES = tuple(
    re.compile(p + r"\Z")
    for p in (
        r"math domain error",
        r"list indices must be integers or slices, not " + _TYPE,
        r"tuple indices must be integers or slices, not " + _TYPE,
        _TYPE + r" object is not (?:subscriptable|callable|iterable)",
        _TYPE
        + r" object has no attribute "
        + r"'(?:shape|T|dot|reshape|astype|ndim|size|copy|flatten|ravel|tolist|item)'",
        r"unsupported operand type\(s\) for [-+*/@]{1,2}: " + _TYPE + " and " + _TYPE,
        r"can only concatenate \w{1,10} \(not \"?\w{1,10}\"?\) to \w{1,10}",
        r"setting an array element with a sequence\..{0,200}",
        r"too many indices for array: array is \d-dimensional, but \d were indexed",
        r"cannot convert expression to float",
        r"only (?:length-1|0-dimensional) arrays can be converted to Python scalars",
        r"The truth value of an array with more than one element is ambiguous\. "
        r"Use a\.any\(\) or a\.all\(\)",
        r"float division by zero|division by zero|integer division or modulo by zero",
        r"not enough values to unpack \(expected \d{1,2}, got \d{1,2}\)",
        r"too many values to unpack \(expected \d{1,2}\)",
        r"No module named '(?:scipy|sympy|numpy|math|rikin|matplotlib)'",
        r"name '(?:dh_table|(?:fk|ik)_(?:cartesian|cylindrical|spherical|scara)(?:_6dof)?"
        r"|np|numpy|math|scipy|sympy|rikin|L|TOOL|REVOLUTE)' is not defined",
    )
)


def safe_message(msg: str) -> str:
    """``msg`` if it is one of the fixed messages above, else ""."""
    msg = " ".join(str(msg).split())[:300]
    return msg if any(p.match(msg) for p in _SAFE_MESSAGES) else ""


def exception_words(out: Outcome) -> str:
    """The exception's class in words the grader vouches for.

    Python's own and rikin's classes by name; a class the notebook defines (its name is
    student-controlled text) as "an exception of your own (a subclass of ValueError)".
    """
    name = out.error_type or t("an exception")
    bases = out.error_bases
    known = name in RIKIN_VALUE_ERRORS or name == "CheckFailed"
    cls = getattr(builtins, name, None)
    builtin = isinstance(cls, type) and issubclass(cls, BaseException)
    if bases:
        builtin = bases[0] == f"builtins.{name}"
        known = known and bases[0].startswith("rikin")
    if builtin or known:
        return name
    base = next(
        (
            b.split(".", 1)[1]
            for b in bases[1:]
            if b.startswith("builtins.") and b != "builtins.object"
        ),
        "Exception",
    )
    base = base if base.isidentifier() else "Exception"
    return t("an exception of your own (a subclass of {base})", base=base)


def describe_failure(out: Outcome, reveal: bool, timeout: float, context: str = "") -> str:
    """The student-facing reason why a call did not return a readable value.

    ``context`` (e.g. "on a reachable target") goes after the exception's name. Composed
    from the grader's own words: the student's message is shown only when it is one of
    Python's fixed messages (:func:`safe_message`), or with ``reveal``.
    """
    if out.timed_out:
        return out.detail or t("timed out (over {seconds} s)", seconds=f"{timeout:g}")
    if out.crashed:
        return t("the notebook's process died ({detail})", detail=out.detail or t("no detail"))
    if out.unreadable:  # the grader's words (see spec.Outcome)
        return out.error_message or t("returned a value the grader cannot read")
    if out.error_type == "NameError" and not out.error_bases:  # the engine: no such function
        return t("not run: the function is not defined (see the notes on your notebook above)")
    if out.error_type == "NotImplementedError":
        return t("not implemented yet (raises NotImplementedError)")
    lines = (out.error_message or "").strip().splitlines()
    first = lines[0][:160] if lines else ""
    msg = first if reveal else safe_message(first)
    ctx = f" {context}" if context else ""
    head = t("raised {error}{context}", error=exception_words(out) if not reveal
             else out.error_type, context=ctx)
    if msg:
        return f"{head}: {msg}"
    if first:
        return head + t(" (its message is not shown here, as it could carry the hidden input)")
    return head


def raised_value_error(out: Outcome) -> bool:
    """Whether the call raised ValueError or a subclass of it (a student's own included).

    Decided from the exception's bases when the engine sent them, else from its name.
    A value the grader could not read was returned, not raised: never a ValueError.
    """
    if out.unreadable or out.timed_out or out.crashed:
        return False
    if out.error_bases:
        return "builtins.ValueError" in out.error_bases
    return is_value_error(out.error_type)


def is_value_error(name: str | None) -> bool:
    """Whether an exception class name stands for ValueError or a subclass of it.

    For outcomes without bases (the engine sends them for every exception a call
    raises): builtin and rikin names are checked; any other name is not a ValueError.
    """
    if not name:
        return False
    if name in RIKIN_VALUE_ERRORS:
        return True
    cls = getattr(builtins, name, None)
    if isinstance(cls, type) and issubclass(cls, BaseException):
        return issubclass(cls, ValueError)
    return False


def as_array(value: Any) -> np.ndarray | None:
    """The returned value as a float64 array, or None if it is not numbers.

    The same rule as the visible checks' ``_as_numbers``: numbers of any kind, nested
    lists of them; complex numbers only with a zero (rounding) imaginary part; strings,
    None and numbers beyond float64 are not numbers.
    """
    try:
        arr = np.asarray(value)
        if arr.dtype.kind == "O":
            arr = arr.astype(np.complex128)
        if arr.dtype.kind not in "biufc":
            return None
        if arr.dtype.kind == "c":
            if np.any(np.abs(arr.imag) > IMAG_TOL * np.maximum(1.0, np.abs(arr.real))):
                return None
            arr = arr.real
        return np.asarray(arr, dtype=np.float64)
    except (TypeError, ValueError, OverflowError, MemoryError, RecursionError):
        return None


def pose_error(T: np.ndarray, T_ref: np.ndarray, scale: float) -> tuple[float, float]:
    """(position error / scale, max abs rotation-matrix difference)."""
    return (
        float(np.linalg.norm(T[:3, 3] - T_ref[:3, 3])) / scale,
        float(np.abs(T[:3, :3] - T_ref[:3, :3]).max()),
    )


def radians_of(q: np.ndarray, revolute: np.ndarray) -> np.ndarray:
    """``q`` with its revolute entries read as degrees and converted to radians."""
    return np.where(revolute, np.radians(q), q)


# ------------------------------------------------------------------ case specs
@dataclass
class Spec:
    """Everything a check needs about one exercise arm (kept out of the calls)."""

    arm: ExerciseArm
    six: bool = False
    _cache: dict[tuple[str, str], Any] = field(default_factory=dict, repr=False, compare=False)

    @property
    def n(self) -> int:
        return 6 if self.six else 3

    @property
    def revolute(self) -> np.ndarray:
        return self.arm.revolute_6dof if self.six else self.arm.revolute

    @property
    def fk_name(self) -> str:
        return self.arm.function_names["fk6" if self.six else "fk"]

    @property
    def ik_name(self) -> str:
        return self.arm.function_names["ik6" if self.six else "ik"]

    def lengths(self, kwargs: dict[str, Any]) -> dict[str, float]:
        return {n: float(kwargs[n]) for n in self.arm.lengths}

    def tool(self, kwargs: dict[str, Any]) -> float:
        return float(kwargs["tool"])

    def scale(self, kwargs: dict[str, Any]) -> float:
        s = self.arm.scale(self.lengths(kwargs))
        return s + (self.tool(kwargs) if self.six else 0.0)

    def ref_fk(self, q: np.ndarray, kwargs: dict[str, Any]) -> np.ndarray:
        """The reference pose at ``q`` (n,) or poses at rows ``q`` (k, n)."""
        q = np.where(self.revolute, wrap(q), q)
        if self.six:
            return self.arm.fk_6dof(q, self.tool(kwargs), **self.lengths(kwargs))
        return self.arm.fk(q, **self.lengths(kwargs))

    def cached(self, what: str, kwargs: dict[str, Any], compute: Callable[[], Any]) -> Any:
        """``compute()``, remembered per call's inputs: every submission is graded on
        the same calls, so reference answers and texts are worked out once per run."""
        key = (what, repr(sorted((k, _plain(v)) for k, v in kwargs.items())))
        try:
            return self._cache[key]
        except KeyError:
            pass
        value = compute()
        for arr in (value, getattr(value, "q", None), *(value if isinstance(value, tuple) else ())):
            if isinstance(arr, np.ndarray):  # shared by every submission: nobody may edit it
                arr.setflags(write=False)
        if len(self._cache) >= REF_CACHE_SIZE:
            self._cache.clear()
        self._cache[key] = value
        return value

    def ref_ik(self, kwargs: dict[str, Any]) -> Solutions:
        """The reference's solutions for a call's inputs (raises UnreachableError like it)."""

        def compute() -> Solutions | rikin.UnreachableError:
            try:
                if self.six:
                    return self.arm.ik_6dof(kwargs["T"], self.tool(kwargs), **self.lengths(kwargs))
                return self.arm.ik(kwargs["p"], **self.lengths(kwargs))
            except rikin.UnreachableError as exc:
                return exc

        hit = self.cached("ik", kwargs, compute)
        if isinstance(hit, rikin.UnreachableError):
            raise hit.with_traceback(None)
        return hit

    def call_pose(self, kwargs: dict[str, Any]) -> np.ndarray:
        """The reference pose for an FK call's joint values ``kwargs["q"]``."""
        return self.cached(
            "fk", kwargs, lambda: self.ref_fk(np.asarray(kwargs["q"], dtype=float), kwargs)
        )

    def target_pose(self, kwargs: dict[str, Any]) -> np.ndarray:
        if self.six:
            return np.asarray(kwargs["T"], dtype=float)
        T = np.eye(4)
        T[:3, 3] = kwargs["p"]
        return T

    def reaches(self, q: np.ndarray, kwargs: dict[str, Any]) -> tuple[bool, float]:
        """Whether FK(q) reaches the target; and by how much it misses (length units)."""
        ok, miss = self.reaches_rows(np.asarray(q, dtype=float)[None, :], kwargs)
        return bool(ok[0]), float(miss[0])

    def reaches_rows(
        self, Q: np.ndarray, kwargs: dict[str, Any]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Per row of ``Q`` (k, n): whether FK reaches the target, and the miss (one pass)."""
        if not len(Q):
            return np.zeros(0, bool), np.zeros(0)
        T = np.reshape(self.ref_fk(Q, kwargs), (-1, 4, 4))
        T_t = self.target_pose(kwargs)
        scale = self.scale(kwargs)
        dp = np.linalg.norm(T[:, :3, 3] - T_t[:3, 3], axis=1) / scale
        dr = np.abs(T[:, :3, :3] - T_t[:3, :3]).max(axis=(1, 2))
        ok = (dp <= POSE_TOL) & ((dr <= POSE_TOL) | (not self.six))
        return ok, dp * scale + (dr if self.six else 0.0)

    def case_kwargs(self, L: dict[str, float], tool: float | None, **extra: Any) -> dict[str, Any]:
        """A call's inputs in the order of the stub's signature: ``q``/``p``/``T`` (as
        float64 arrays, as the stubs annotate them), the lengths, then ``tool``."""
        kw: dict[str, Any] = {k: np.array(v, dtype=np.float64) for k, v in extra.items()}
        kw.update({k: float(v) for k, v in L.items()})
        if self.six:
            kw["tool"] = float(tool)  # type: ignore[arg-type]
        return kw

    def call(self, function: str, kwargs: dict[str, Any]) -> Call:
        """A call that passes every input positionally, in the signature's order."""
        return Call(function, kwargs, tuple(kwargs))

    def hidden_text(self, kwargs: dict[str, Any]) -> str:
        """The call's hidden inputs in words (for the instructor's detail or ``reveal``)."""
        return self.cached("text", kwargs, lambda: self._hidden_text(kwargs))

    def _hidden_text(self, kwargs: dict[str, Any]) -> str:
        parts = [f"{k} = {kwargs[k]:.6g}" for k in self.arm.lengths]
        if self.six:
            parts.append(f"tool = {kwargs['tool']:.6g}")
        if "q" in kwargs:
            parts.insert(0, f"q = {_fmt(kwargs['q'], 6)}")
        if "p" in kwargs:
            parts.insert(0, f"p = {_fmt(kwargs['p'], 6)}")
        if "T" in kwargs:
            T = np.asarray(kwargs["T"])
            rpy = _fmt(rikin.r_to_rpy(T[:3, :3]), 6)
            parts.insert(0, f"T: p = {_fmt(T[:3, 3], 6)}, RPY = {rpy} rad")
        return ", ".join(parts)


# ------------------------------------------------------------------ IK set comparison
@dataclass
class IKCase:
    """How one IK answer compares with the reference set."""

    credit: float = 0.0
    expected: int = 0
    matched: int = 0
    missing: list[str] = field(default_factory=list)
    wrong: list[str] = field(default_factory=list)
    duplicates: int = 0
    degrees: bool = False
    failure: str = ""  # the call did not return a usable array
    notes: list[str] = field(default_factory=list)

    @property
    def full(self) -> bool:
        return self.credit >= 1.0 - 1e-12


def student_rows(value: Any, n: int) -> tuple[np.ndarray | None, str, str]:
    """The returned solutions as (k, n), or None and why; plus a note on the shape.

    The same rule as the visible checks' ``_as_rows``: numbers, shape (k, n), or (n,)
    for a single solution; at most MAX_ROWS rows are read.
    """
    arr = as_array(value)
    if arr is None:
        return None, t("returned something that is not an array of numbers"), ""
    note = ""
    if arr.ndim == 1 and arr.shape[0] == n:
        arr = arr[None, :]
        note = t("a single solution came back as shape ({n},); the docstring asks for (k, {n})",
                 n=n)
    if arr.size == 0:
        return np.zeros((0, n)), "", note
    if arr.ndim != 2 or arr.shape[1] != n:
        shape = tuple(int(x) for x in arr.shape)
        return None, t("returned shape {shape}, expected (k, {n}): one solution per row",
                       shape=shape, n=n), note
    if arr.shape[0] > MAX_ROWS:
        return (
            None,
            t("returned more than {rows} rows (this arm has at most 4 solutions per target)",
              rows=MAX_ROWS),
            note,
        )
    return arr, "", note


def _wrapped_distance(spec: Spec, rows: np.ndarray, refs: np.ndarray, scale: float,
                      compared: np.ndarray) -> np.ndarray:
    """(k, m) max joint distance of each row to each reference row (angles modulo 2*pi,
    prismatic values over ``scale``), over the joints ``compared`` (m, n) of each reference."""
    rev = spec.revolute
    d = rows[:, None, :] - refs[None, :, :]
    d = np.abs(np.where(rev, wrap(d), d / scale))
    return np.where(compared[None, :, :], d, 0.0).max(axis=2)


def _why_wrong(spec: Spec, r: np.ndarray, reaches: bool, kwargs: dict[str, Any],
               case: IKCase) -> str:
    """Why one returned row is not a solution, in the student's terms."""
    rev = spec.revolute
    if reaches:
        scale = spec.scale(kwargs)
        neg = [k + 1 for k in range(spec.n) if not rev[k] and r[k] < -JOINT_TOL * scale]
        return t("a solution that needs q{i} < 0 (prismatic joints only extend)", i=neg[0])
    if np.any(np.abs(r[rev]) > DEGREES_SUSPECT):
        case.degrees = True
        if spec.reaches(radians_of(r, rev), kwargs)[0]:
            return t("a right solution written in degrees")
    return t("a solution that does not reach the target (FK check)")


def compare_ik(spec: Spec, kwargs: dict[str, Any], value: Any) -> IKCase:
    """Score one IK answer against the reference set (see the module docstring).

    Linear in the rows: one FK pass over all rows, one (k, m) distance table to the m
    (at most 4) reference rows, one greedy pass to merge the wrong rows that repeat.
    """
    ref = spec.ref_ik(kwargs)
    rev = spec.revolute
    scale = spec.scale(kwargs)
    case = IKCase(expected=len(ref))
    rows, why, note = student_rows(value, spec.n)
    if note:
        case.notes.append(note)
    if rows is None:
        case.failure = why
        return case
    finite = np.all(np.isfinite(rows), axis=1)
    case.wrong += [t("a solution with NaN or infinity")] * int((~finite).sum())
    rows = rows[finite]
    # a singular family's free joints are not compared
    compared = np.ones(ref.q.shape, bool)
    for j, free in enumerate(ref.free):
        compared[j, list(free)] = False
    # reference rows that lie within BRANCH_TOL of each other (near a singularity) are
    # one branch for the student: any one row of them stands for all
    cluster = np.arange(len(ref))
    if len(ref) > 1:
        dref = _wrapped_distance(spec, ref.q, ref.q, scale, compared)
        for j in range(len(ref)):
            close = np.flatnonzero(dref[j] <= JOINT_TOL * 1e3)
            cluster[close] = cluster[close].min()
    reach, _ = spec.reaches_rows(rows, kwargs)
    prismatic_ok = np.all(rev | (rows >= -REACH_TOL * scale - JOINT_TOL * scale), axis=1)
    dist = (
        _wrapped_distance(spec, rows, ref.q, scale, compared)
        if len(rows)
        else np.zeros((0, len(ref)))
    )
    nearest = dist.argmin(axis=1) if len(ref) else np.zeros(len(rows), int)
    near = dist[np.arange(len(rows)), nearest] if len(ref) else np.full(len(rows), np.inf)
    good = reach & prismatic_ok & (near <= BRANCH_TOL)
    hit = cluster[nearest[good]] if len(ref) else np.zeros(0, int)
    matched = {int(c) for c in hit}
    case.duplicates += int(good.sum()) - len(matched)
    unlisted = reach & prismatic_ok & ~good
    if unlisted.any():  # pragma: no cover - would mean the reference misses a solution
        case.notes.append(
            t("a returned solution reaches the target but the reference does not list it "
              "(not penalised; please tell the instructor)")
        )
    bad = ~(reach & prismatic_ok)
    if bad.any():
        # the same wrong row twice costs once: rows equal to JOINT_TOL (angles wrapped)
        key = np.where(rev, wrap(rows[bad]), rows[bad] / scale)
        _, first = np.unique(np.round(key / JOINT_TOL), axis=0, return_index=True)
        case.duplicates += int(bad.sum()) - len(first)
        for i in np.flatnonzero(bad)[np.sort(first)][:MAX_WRONG_EXPLAINED]:
            case.wrong.append(_why_wrong(spec, rows[i], bool(reach[i]), kwargs, case))
        extra = len(first) - MAX_WRONG_EXPLAINED
        case.wrong += [t("a solution that does not reach the target (FK check)")] * max(0, extra)
    reps = sorted({int(c) for c in cluster})
    case.expected = len(reps)
    case.matched = len(matched)
    case.missing = [ref.labels[j] for j in reps if j not in matched]
    case.credit = case.matched / (case.expected + len(case.wrong))
    return case


def summarize_ik(title: str, cases: list[IKCase], what: str = N_("targets")) -> str:
    """One feedback line for a list of IK cases, in the student's terms (``title`` and
    ``what`` already in the feedback's language)."""
    n = len(cases)
    full = sum(c.full for c in cases)
    parts = [t("{title}: {full}/{n} {what} fully right", title=title, full=full, n=n,
               what=t(what))]
    fails = Counter(c.failure for c in cases if c.failure)
    for reason, k in fails.items():
        parts.append(f"{reason} ({k}x)")
    answered = [c for c in cases if not c.failure]
    if answered and any(not c.full for c in answered):
        found = Counter(t("{matched} of {expected}", matched=c.matched, expected=c.expected)
                        for c in answered if not c.full)
        parts.append(t("solutions found: ") + ", ".join(f"{k} ({v}x)" for k, v in found.items()))
    missing = Counter(label(m) for c in answered for m in c.missing)
    if missing:
        parts.append(t("missing: ") + "; ".join(f"{m} ({k}x)" for m, k in missing.items()))
    wrong = Counter(w for c in answered for w in c.wrong)
    if wrong:
        parts.append(t("wrong or extra: ") + "; ".join(f"{w} ({k}x)" for w, k in wrong.items()))
    if any(c.degrees for c in answered):
        parts.append(t("some angles look like degrees: return radians"))
    notes = {nt for c in answered for nt in c.notes}
    parts.extend(sorted(notes))
    dup = sum(c.duplicates for c in answered)
    if dup:
        parts.append(t("{dup} duplicate solution(s) merged (not penalised)", dup=dup))
    return sentences(parts)


# ------------------------------------------------------------------ test factories
def _first_failing_hint(
    reveal: bool,
    spec: Spec,
    calls: list[Call],
    good: list[bool],
    extra: Callable[[int], str] = lambda i: "",
) -> str:
    if not reveal:
        return ""
    for i, ok in enumerate(good):
        if not ok:
            return t(" First failing case: {case}.", case=spec.hidden_text(calls[i].kwargs)
                     + extra(i))
    return ""


_REPR = reprlib.Repr()
_REPR.maxlist = _REPR.maxtuple = 8
_REPR.maxstring = _REPR.maxother = 200
_REPR.maxlevel = 3


def _detail(spec: Spec, calls: list[Call], outcomes: list[Outcome], notes: list[str]) -> str:
    """The instructor's log lines of one test (bounded: a huge answer is not printed whole)."""
    lines = []
    for i, (c, o) in enumerate(zip(calls, outcomes, strict=True)):
        got = _REPR.repr(o.value) if o.ok else f"{o.error_type}: {o.error_message!s:.300}"
        lines.append(f"[{i}] {spec.hidden_text(c.kwargs)} -> {notes[i]} | got {got:.400}")
    return "\n".join(lines)


def _guarded(check: Callable[[list[Call], list[Outcome], bool], Score]):
    """``check`` timed (the time goes to the instructor's detail) and with the last guard
    on its feedback: numbers equal to a hidden input are masked unless ``reveal``."""

    def run(calls: list[Call], outcomes: list[Outcome], reveal: bool) -> Score:
        t0 = time.perf_counter()
        score = check(calls, outcomes, reveal)
        feedback = score.feedback
        if not reveal:
            feedback = mask_hidden(feedback, hidden_numbers(calls))
        ms = (time.perf_counter() - t0) * 1e3
        return Score(score.fraction, feedback, f"{score.detail}\nscored in {ms:.1f} ms")

    run.__doc__ = check.__doc__
    return run


@dataclass
class Tally:
    """Pass/fail results of the cases of one test, and why the failures failed."""

    good: list[bool] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    reasons: Counter = field(default_factory=Counter)

    def add(self, reason: str) -> None:
        """Record one case: ``reason`` is "" when it passed."""
        self.good.append(not reason)
        self.notes.append(reason or "ok")
        if reason:
            self.reasons[reason] += 1

    @property
    def fraction(self) -> float:
        return sum(self.good) / len(self.good)

    def feedback(self, head: str) -> str:
        return sentences([head, "; ".join(f"{r} ({m}x)" for r, m in self.reasons.items())])


def fk_test(arm: ExerciseArm, six: bool, weight: float, name: str, n: int = N_FK) -> HiddenTest:
    """FK at random joint values and lengths, compared with the reference pose."""
    spec = Spec(arm, six)
    fname = spec.fk_name
    title = f"FK of the {'6-DOF arm' if six else 'positioning arm'} ({fname})"

    def heading() -> str:
        """The title in the feedback's language."""
        if six:
            return t("FK of the 6-DOF arm ({function})", function=fname)
        return t("FK of the positioning arm ({function})", function=fname)

    def make_calls(rng: np.random.Generator) -> list[Call]:
        calls = []
        for _ in range(n):
            L = arm.sample_lengths(rng)
            tool = arm.sample_tool(rng) if six else None
            q = arm.sample_q_6dof(rng, L) if six else arm.sample_q(rng, L)
            calls.append(spec.call(fname, spec.case_kwargs(L, tool, q=q)))
        return calls

    def check(calls: list[Call], outcomes: list[Outcome], reveal: bool) -> Score:
        tally = Tally()
        for c, o in zip(calls, outcomes, strict=True):
            tally.add(_fk_case(spec, c.kwargs, o, reveal))
        head = t("{title}: {good}/{n} random configurations right", title=heading(),
                 good=sum(tally.good), n=len(calls))
        fb = tally.feedback(head) + _first_failing_hint(reveal, spec, calls, tally.good)
        return Score(tally.fraction, fb, _detail(spec, calls, outcomes, tally.notes))

    return HiddenTest(
        name, weight, title, make_calls, _guarded(check), timeout=TIMEOUT, tags=("fk",)
    )


def _fk_case(spec: Spec, kw: dict[str, Any], out: Outcome, reveal: bool) -> str:
    """Why one FK answer is wrong, or "" if it is right."""
    if not out.ok:
        return describe_failure(out, reveal, TIMEOUT)
    T = as_array(out.value)
    if T is None:
        return t("returned something that is not a matrix of numbers, expected a (4, 4) matrix")
    if T.shape != (4, 4):
        shape = tuple(int(x) for x in T.shape)
        return t("returned shape {shape}, expected a (4, 4) matrix", shape=shape)
    if not np.all(np.isfinite(T)):
        return t("the matrix contains NaN or infinity")
    q = np.asarray(kw["q"], dtype=float)
    dp, dr = pose_error(T, spec.call_pose(kw), spec.scale(kw))
    if dp <= POSE_TOL and dr <= POSE_TOL:
        return ""
    return _diagnose_fk(spec, T, q, kw, dp, dr)


def _diagnose_fk(
    spec: Spec, T: np.ndarray, q: np.ndarray, kw: dict[str, Any], dp: float, dr: float
) -> str:
    """Why a student's FK pose differs from the reference, in the student's terms."""
    scale = spec.scale(kw)
    rev = spec.revolute
    if rev.any():
        T_deg = spec.ref_fk(radians_of(q, rev), kw)
        if max(pose_error(T, T_deg, scale)) <= POSE_TOL:
            return t("it reads the joint angles as degrees: q is in radians")
    if spec.six:
        L = spec.lengths(kw)
        T_fl = spec.arm.fk_flange_6dof(np.where(rev, wrap(q), q), spec.tool(kw), **L)
        if max(pose_error(T, T_fl, scale)) <= POSE_TOL:
            return t("it returns the flange frame 6 (at the wrist centre), not the TCP: "
                     "the tool is missing")
    if not np.allclose(T[3], [0.0, 0.0, 0.0, 1.0], atol=POSE_TOL):
        return t("the last row is not (0, 0, 0, 1)")
    if dp <= POSE_TOL:
        return t("the TCP position is right but the orientation (rotation part) is not")
    if dr <= POSE_TOL:
        return t("the orientation is right but the TCP position is not")
    return t("both the TCP position and the orientation are wrong")


DH_FIELDS = ("joint", "d", "a", "alpha", "offset", "theta", "qlim")


def rows_to_arm(arm: ExerciseArm, value: Any) -> tuple[rikin.SerialArm | None, str]:
    """The student's DH rows as a rikin arm, or None and what is wrong with them."""
    if not isinstance(value, list) or not all(isinstance(r, dict) for r in value):
        return None, t("it must return a list of dicts (one per joint, rikin.Link keywords)")
    if len(value) != 3:
        return None, t("it has {n} rows; the positioning arm has 3 joints", n=len(value))
    links = []
    for i, row in enumerate(value, 1):
        bad = set(row) - set(DH_FIELDS)
        if bad:  # the keys are the student's text: not echoed
            return None, t("row {i} has keys rikin.Link does not know; use {keys}", i=i,
                           keys=list(DH_FIELDS[:-1]))
        joint = row.get("joint", "R")
        want = arm.joint_types[i - 1]
        if joint != want:
            kind = {"R": t("revolute ('R')"), "P": t("prismatic ('P')")}[want]
            says = repr(joint) if joint in ("R", "P") else t("something else")
            return None, t("joint {i} is {kind}, the table says {says}", i=i, kind=kind,
                           says=says)
        try:
            vals = {k: float(row[k]) for k in DH_FIELDS[1:-1] if k in row}
        except (TypeError, ValueError, OverflowError):
            return None, t("row {i} has a value that is not a number", i=i)
        if not all(np.isfinite(v) for v in vals.values()):
            return None, t("row {i} has a value that is NaN or infinity", i=i)
        for k in ("alpha", "offset", "theta"):
            angle = not (k == "offset" and joint == "P")  # a prismatic offset is a length
            if k in vals and angle and abs(vals[k]) > DEGREES_SUSPECT:
                return None, t("row {i}: {key} looks like degrees: DH angles are radians", i=i,
                               key=k)
        try:
            links.append(
                rikin.Link(
                    joint,
                    d=vals.get("d", 0.0),
                    a=vals.get("a", 0.0),
                    alpha=vals.get("alpha", 0.0),
                    offset=vals.get("offset", 0.0),
                    theta=vals.get("theta", 0.0),
                )
            )
        except ValueError:
            return None, t("row {i} is not a valid rikin.Link", i=i)
    try:
        return rikin.SerialArm(tuple(links)), ""
    except ValueError:
        return None, t("the rows do not make a valid arm")


def dh_test(arm: ExerciseArm, weight: float, name: str = "dh_table", n: int = N_DH) -> HiddenTest:
    """The DH rows, turned into a rikin arm, must give the reference T_0_3 at random q."""
    spec = Spec(arm, False)
    title = "DH table (dh_table)"

    def make_calls(rng: np.random.Generator) -> list[Call]:
        return [
            spec.call("dh_table", {k: float(v) for k, v in arm.sample_lengths(rng).items()})
            for _ in range(n)
        ]

    def probe(kw: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
        """Joint values to compare the rows at (not hidden inputs), and the reference T_0_3."""
        L = spec.lengths(kw)
        rng = np.random.default_rng(12345)
        Q = np.array([arm.sample_q(rng, L) for _ in range(4)])
        return Q, arm.fk(Q, **L)

    def case(kw: dict[str, Any], out: Outcome, reveal: bool) -> str:
        if not out.ok:
            return describe_failure(out, reveal, TIMEOUT)
        student, why = rows_to_arm(arm, out.value)
        if student is None:
            return why
        Q, T_ref = spec.cached("dh", kw, lambda: probe(kw))
        T = student.fk(Q)
        scale = spec.scale(kw)
        dp = float(np.linalg.norm(T[:, :3, 3] - T_ref[:, :3, 3], axis=1).max()) / scale
        dr = float(np.abs(T[:, :3, :3] - T_ref[:, :3, :3]).max())
        if max(dp, dr) <= POSE_TOL:
            return ""
        if dp <= POSE_TOL:
            return t("the origin of frame 3 is right but its axes are not "
                     "(check alpha and the theta offsets)")
        return t("frame 3 (the TCP) ends up in the wrong place for some joint values")

    def check(calls: list[Call], outcomes: list[Outcome], reveal: bool) -> Score:
        tally = Tally()
        for c, o in zip(calls, outcomes, strict=True):
            tally.add(case(c.kwargs, o, reveal))
        head = t("{title}: {good}/{n} random sets of link lengths right (checked by FK of "
                 "your rows)", title=t("DH table (dh_table)"), good=sum(tally.good), n=len(calls))
        fb = tally.feedback(head) + _first_failing_hint(reveal, spec, calls, tally.good)
        return Score(tally.fraction, fb, _detail(spec, calls, outcomes, tally.notes))

    return HiddenTest(
        name, weight, title, make_calls, _guarded(check), timeout=TIMEOUT, tags=("dh",)
    )


def _special_q(
    arm: ExerciseArm, rng: np.random.Generator, L: dict[str, float], i: int
) -> tuple[str, FloatArray]:
    """The ``i``-th singular or boundary configuration (kind, q) of an arm that has one."""
    special = arm.sample_special_q(rng, L, i)
    if special is None:
        raise ValueError(f"{arm.title}: no singular or boundary configuration to test")
    return special


def ik_test(
    arm: ExerciseArm, six: bool, weight: float, name: str, *, special: str = "", n: int = N_IK
) -> HiddenTest:
    """IK of reachable targets, compared with the reference as a set.

    ``special``: "" for regular targets; "positioning" for the positioning
    arm's singular or boundary configuration (``arm.sample_special_q``);
    "wrist" for wrist-singular poses (q5 = 0 and q5 = pi).
    """
    spec = Spec(arm, six)
    fname = spec.ik_name
    what = "6-DOF arm, by decoupling" if six else "positioning arm"
    kinds: list[str] = []
    if special == "wrist":
        title = f"IK at and near the wrist singularity, any member of the family ({fname})"
    elif special == "positioning":
        rng0 = np.random.default_rng(0)
        L0 = arm.sample_lengths(rng0)
        kinds = list(dict.fromkeys(_special_q(arm, rng0, L0, i)[0] for i in range(2)))
        them = "them" if len(kinds) > 1 else "it"
        title = f"IK {' and '.join(kinds)}, and near {them} ({fname})"
    else:
        title = f"IK of the {what}, all solutions ({fname})"


    def target(q: FloatArray, L: dict[str, float], tool: float | None) -> Call:
        if six:
            assert tool is not None  # a 6-DOF target always has a tool
            kw = spec.case_kwargs(L, tool, T=arm.fk_6dof(q, tool, **L))
        else:
            kw = spec.case_kwargs(L, None, p=arm.fk(q, **L)[:3, 3])
        return spec.call(fname, kw)

    def make_calls(rng: np.random.Generator) -> list[Call]:
        calls = []
        count = {"": n, "positioning": 4}.get(special, 2)
        for i in range(count):
            L = arm.sample_lengths(rng)
            tool = arm.sample_tool(rng) if six else None
            if special == "wrist":
                q = arm.sample_wrist_singular_q(rng, L, (0.0, np.pi)[i % 2])
            elif special == "positioning":
                q = _special_q(arm, rng, L, i)[1]
            else:
                q = arm.sample_q_6dof(rng, L) if six else arm.sample_q(rng, L)
                if i == 0:  # the statement allows a prismatic joint exactly at zero
                    q[: len(arm.revolute)][~arm.revolute] = 0.0
            calls.append(target(q, L, tool))
        if special:
            calls += [target(*near) for near in _near_singular(arm, six, special, rng)]
        return calls

    def check(calls: list[Call], outcomes: list[Outcome], reveal: bool) -> Score:
        cases, notes = [], []
        for c, o in zip(calls, outcomes, strict=True):
            if not o.ok:
                case = IKCase(expected=len(spec.ref_ik(c.kwargs)))
                ctx = t(" on a reachable target") if raised_value_error(o) else ""
                case.failure = describe_failure(o, reveal, TIMEOUT, ctx)
            else:
                case = compare_ik(spec, c.kwargs, o.value)
            cases.append(case)
            notes.append(
                f"credit {case.credit:.3f}; missing {case.missing}; "
                f"wrong {case.wrong}; {case.failure}"
            )
        frac = float(np.mean([c.credit for c in cases]))
        fb = summarize_ik(_ik_heading(special, six, fname, kinds), cases)
        fb += _first_failing_hint(reveal, spec, calls, [c.full for c in cases])
        return Score(frac, fb, _detail(spec, calls, outcomes, notes))

    tags = ("ik",) + (("singular",) if special else ())
    return HiddenTest(name, weight, title, make_calls, _guarded(check), timeout=TIMEOUT, tags=tags)


def _ik_heading(special: str, six: bool, fname: str, kinds: list[str]) -> str:
    """The title of an IK test (see :func:`ik_test`) in the feedback's language."""
    if special == "wrist":
        return t("IK at and near the wrist singularity, any member of the family "
                 "({function})", function=fname)
    if special == "positioning":
        words = t(" and ").join(t(k) for k in kinds)
        near = t("them") if len(kinds) > 1 else t("it")
        return t("IK {kinds}, and near {them} ({function})", kinds=words, them=near,
                 function=fname)
    if six:
        return t("IK of the 6-DOF arm, by decoupling, all solutions ({function})",
                 function=fname)
    return t("IK of the positioning arm, all solutions ({function})", function=fname)


def _near_singular(
    arm: ExerciseArm, six: bool, special: str, rng: np.random.Generator
) -> list[tuple[FloatArray, dict[str, float], float | None]]:
    """(q, lengths, tool) of targets NEAR each singular configuration a special test is
    about (``NEAR_SINGULAR`` from it): the wrist's q5 near 0 and near pi; the positioning
    arm's special configurations (SCARA: near stretched and near folded; spherical: near
    the vertical axis). An answer that takes a band around the singularity for it loses
    them. Drawn from a generator spawned from ``rng``, which leaves ``rng``'s own draws
    (the other tests' inputs) as they were."""
    side = _spawned(rng)
    out = []
    for i in range(2):
        L = arm.sample_lengths(side)
        tool = arm.sample_tool(side) if six else None
        if special == "wrist":
            q5 = side.choice([-1.0, 1.0]) * (NEAR_SINGULAR, np.pi - NEAR_SINGULAR)[i]
            q = arm.sample_wrist_singular_q(side, L, q5)
        else:
            near = arm.sample_near_special_q(side, L, i)
            if near is None:  # pragma: no cover - every special test's arm has them
                continue
            q = near
        out.append((q, L, tool))
    return out


def _spawned(rng: np.random.Generator) -> np.random.Generator:
    """A generator derived from ``rng`` without drawing from it (numpy >= 1.25 spawns)."""
    try:
        return rng.spawn(1)[0]
    except AttributeError:  # pragma: no cover - numpy 1.24
        seq = rng.bit_generator._seed_seq  # type: ignore[attr-defined]
        return np.random.default_rng(seq.spawn(1)[0])


def unreachable_test(arm: ExerciseArm, six: bool, weight: float, name: str) -> HiddenTest:
    """Unreachable targets must raise ValueError with a message of the student's own."""
    spec = Spec(arm, six)
    fname = spec.ik_name
    title = f"unreachable {'poses' if six else 'targets'} raise ValueError ({fname})"

    def heading() -> str:
        """The title in the feedback's language."""
        if six:
            return t("unreachable poses raise ValueError ({function})", function=fname)
        return t("unreachable targets raise ValueError ({function})", function=fname)

    def make_calls(rng: np.random.Generator) -> list[Call]:
        L = arm.sample_lengths(rng)
        if six:
            tool = arm.sample_tool(rng)
            return [
                spec.call(fname, spec.case_kwargs(L, tool, T=T))
                for _, T in arm.unreachable_poses(rng, L, tool)
            ]
        return [
            spec.call(fname, spec.case_kwargs(L, None, p=p))
            for _, p in arm.unreachable_points(rng, L)
        ]

    def kind_of(kwargs: dict[str, Any]) -> str:
        return _unreachable_kind(spec, kwargs)

    def check(calls: list[Call], outcomes: list[Outcome], reveal: bool) -> Score:
        credits: list[float] = []
        notes: list[str] = []
        reasons: Counter[str] = Counter()
        for c, o in zip(calls, outcomes, strict=True):
            k = kind_of(c.kwargs)
            if o.ok:
                arr = as_array(o.value)
                nan = arr is not None and arr.size and not np.all(np.isfinite(arr))
                r = (t("{kind}: returned NaN values instead of raising ValueError", kind=k) if nan
                     else t("{kind}: returned values instead of raising ValueError", kind=k))
                credits.append(0.0)
            elif o.unreadable:
                r = t("{kind}: {failure} instead of raising ValueError", kind=k,
                      failure=describe_failure(o, reveal, TIMEOUT))
                credits.append(0.0)
            elif (
                o.error_type == "ValueError"
                and (o.error_message or "").strip() == "math domain error"
            ):
                r = t("{kind}: raised ValueError('math domain error') from math.sqrt/acos, "
                      "which Task 5 says is not enough: check reachability yourself and say "
                      "why", kind=k)
                credits.append(0.0)
            elif raised_value_error(o):
                r = ""
                credits.append(1.0)
            else:
                r = t("{kind}: {failure} instead of ValueError", kind=k,
                      failure=describe_failure(o, reveal, TIMEOUT))
                credits.append(0.0)
            notes.append(r or "ok")
            if r:
                reasons.update([r])
        full = sum(cr == 1.0 for cr in credits)
        fb = sentences(
            [
                t("{title}: {full}/{n} raised ValueError", title=heading(), full=full,
                  n=len(calls)),
                "; ".join(r + (f" ({m}x)" if m > 1 else "") for r, m in reasons.items()),
            ]
        )
        fb += _first_failing_hint(reveal, spec, calls, [cr == 1.0 for cr in credits])
        return Score(float(np.mean(credits)), fb, _detail(spec, calls, outcomes, notes))

    return HiddenTest(
        name, weight, title, make_calls, _guarded(check), timeout=TIMEOUT, tags=("unreachable",)
    )


def _unreachable_kind(spec: Spec, kwargs: dict[str, Any]) -> str:
    """What makes an unreachable target unreachable, in words without numbers."""
    try:
        spec.ref_ik(kwargs)
    except rikin.UnreachableError as exc:
        msg = str(exc)
        if spec.six:
            p = spec.target_pose(kwargs)[:3, 3]
            try:
                spec.arm.ik(p, **spec.lengths(kwargs))
                prefix = N_("a pose whose TCP is within reach but whose wrist centre is not")
            except rikin.UnreachableError:
                prefix = N_("a pose whose wrist centre is out of reach")
            return t(prefix)
        for key, words in (
            ("below", N_("a target below a prismatic joint's zero position")),
            ("above", N_("a target above the top of the quill's stroke")),
            ("beyond", N_("a target beyond full reach")),
            ("inside the circle", N_("a target inside the inner circle")),
            ("closer than the retracted boom", N_("a target closer to the shoulder than l2")),
            ("closer than the retracted radial", N_("a target closer to the column axis than l2")),
        ):
            if key in msg:
                return t(words)
        return t("an unreachable target")
    return t("a target the reference can reach (please tell the instructor)")  # pragma: no cover
