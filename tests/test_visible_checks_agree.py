"""The visible checks and the grader judge the same answers alike (issue 26 item 8, Wanted 7).

The statement of every exercise says: a pose is right to 1e-6 times the arm's size in
position (and 1e-6 in each rotation entry), a joint to 1e-6 rad or 1e-6 times the arm's
size, and any value ``numpy.asarray`` reads as real numbers is read. Each answer below is
a solution function changed in one way (moved by a fraction of that tolerance, or
returned as another type); the notebook's check cells that test that function and the
grader's hidden tests of it (through ``tests/_hidden_harness.py``, which calls and reads
as the engine does) must both accept it or both refuse it.

And the checks' messages name the cause they saw (issue 28 item 6): a textbook guard
``if abs(c2) > 1: raise ValueError`` at full reach is told about rounding at the edge of
the workspace (not about length arguments); a function that really ignores a length is
told which one; a failed check shows as its message alone in IPython.
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import _hidden_harness as H
import numpy as np
import pytest
import sympy
from test_hidden import module, solution, solution_namespace

ARMS = ("cartesian", "cylindrical", "spherical", "scara")
TOL = 1e-6
SEED = 20240901


def _size(fn_name: str, lengths: tuple[float, ...]) -> float:
    """The arm's size as the statement defines it (the grader's ``Spec.scale``)."""
    if fn_name.endswith("_6dof"):
        return max(1.0, sum(lengths[:-1])) + lengths[-1]
    return max(1.0, sum(lengths))


def _lengths(fn: Callable[..., Any], args: tuple[Any, ...]) -> tuple[float, ...]:
    """The length arguments of a call (every argument after the first array, if any)."""
    first = next(iter(inspect.signature(fn).parameters), "")
    rest = args[1:] if first in ("q", "p", "T") else args
    return tuple(float(v) for v in rest)


@dataclass(frozen=True)
class Change:
    """One way to change a function's answer; ``ok`` is what the statement says of it."""

    name: str
    kind: str  # "dh", "fk" or "ik": which functions it applies to
    ok: bool
    apply: Callable[[Any, float, Any], Any]  # (answer, size, revolute) -> new answer

    def wrap(self, fn: Callable[..., Any], fn_name: str, revolute: np.ndarray
             ) -> Callable[..., Any]:
        def changed(*args: Any) -> Any:
            answer = fn(*args)
            return self.apply(answer, _size(fn_name, _lengths(fn, args)), revolute)

        changed.__name__ = fn_name
        changed.__signature__ = inspect.signature(fn)  # type: ignore[attr-defined]
        return changed


def _move_tcp(k: float) -> Callable[[Any, float, Any], Any]:
    def apply(T: Any, size: float, _rev: Any) -> Any:
        T = np.array(T, dtype=float)
        T[:3, 3] += k * TOL * size * np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
        return T
    return apply


def _move_prismatic(k: float) -> Callable[[Any, float, Any], Any]:
    def apply(Q: Any, size: float, rev: Any) -> Any:
        Q = np.array(Q, dtype=float)
        prismatic = np.flatnonzero(~np.asarray(rev, dtype=bool))
        Q[..., prismatic[0]] += k * TOL * size
        return Q
    return apply


def _turn_revolute(k: float) -> Callable[[Any, float, Any], Any]:
    def apply(Q: Any, size: float, rev: Any) -> Any:
        Q = np.array(Q, dtype=float)
        Q[..., np.asarray(rev, dtype=bool)] += k * TOL / 10.0
        return Q
    return apply


def _move_d(k: float) -> Callable[[Any, float, Any], Any]:
    def apply(rows: Any, size: float, _rev: Any) -> Any:
        rows = [dict(r) for r in rows]
        rows[0]["d"] = float(rows[0].get("d", 0.0)) + k * TOL * size
        return rows
    return apply


def _as(convert: Callable[[np.ndarray], Any]) -> Callable[[Any, float, Any], Any]:
    return lambda answer, _size, _rev: convert(np.asarray(answer, dtype=float))


CHANGES = (
    Change("tcp moved 0.4 tol", "fk", True, _move_tcp(0.4)),
    Change("tcp moved 0.9 tol", "fk", True, _move_tcp(0.9)),
    Change("tcp moved 3 tol", "fk", False, _move_tcp(3.0)),
    Change("fk as nested lists", "fk", True, _as(lambda a: a.tolist())),
    Change("fk as float32", "fk", True, _as(lambda a: a.astype(np.float32))),
    Change("fk as longdouble", "fk", True, _as(lambda a: a.astype(np.longdouble))),
    Change("fk as a sympy Matrix", "fk", True, _as(sympy.Matrix)),
    Change("fk as complex, zero imaginary part", "fk", True, _as(lambda a: a + 0j)),
    Change("fk as complex, imaginary part 1e-3", "fk", False, _as(lambda a: a + 1e-3j)),
    Change("prismatic joint 0.4 tol out", "ik", True, _move_prismatic(0.4)),
    Change("prismatic joint 3 tol out", "ik", False, _move_prismatic(3.0)),
    Change("revolute joints 0.1 tol turned", "ik", True, _turn_revolute(1.0)),
    Change("ik as nested lists", "ik", True, _as(lambda a: a.tolist())),
    Change("ik as tuples", "ik", True, _as(lambda a: tuple(tuple(r) for r in a))),
    Change("ik as float32", "ik", True, _as(lambda a: a.astype(np.float32))),
    Change("ik as a sympy Matrix", "ik", True, _as(sympy.Matrix)),
    Change("ik as a set of tuples", "ik", False, _as(lambda a: {tuple(r) for r in a})),
    Change("d of row 1 moved 0.4 tol", "dh", True, _move_d(0.4)),
    Change("d of row 1 moved 3 tol", "dh", False, _move_d(3.0)),
)


def _kind(fn_name: str) -> str:
    return "dh" if fn_name == "dh_table" else fn_name.split("_", 1)[0]


def _functions(arm: str) -> list[str]:
    return sorted({c.function for t in module(arm).TESTS
                   for c in t.make_calls(np.random.default_rng(0))})


def _revolute(arm: str, fn_name: str) -> np.ndarray:
    ns = solution_namespace(arm)
    rev = list(ns["REVOLUTE"])
    return np.array(rev + [True, True, True] if fn_name.endswith("_6dof") else rev)


def _visible_ok(arm: str, ns: dict[str, Any], fn_name: str) -> tuple[bool, list[str]]:
    """Whether every check cell of the notebook that tests ``fn_name`` passes."""
    said = []
    cells = [src for _, src, _ in H.code_cells(solution(arm))
             if re.search(rf"^check_\w+\(\s*{fn_name}\b", src, re.M)]
    assert cells, f"{arm}: no check cell tests {fn_name}"
    for src in cells:
        try:
            exec(compile(src, "<check>", "exec"), dict(ns))
        except Exception as exc:  # noqa: BLE001 - a check fails with CheckFailed or the error
            said.append(f"{type(exc).__name__}: {exc}")
    return not said, said


def _graded_ok(arm: str, ns: dict[str, Any], fn_name: str) -> tuple[bool, list[str]]:
    """Whether every hidden test of ``fn_name`` gives full credit."""
    m = module(arm)
    rng = np.random.default_rng(SEED)
    said = []
    for test in m.TESTS:
        calls = test.make_calls(rng)
        if calls and calls[0].function == fn_name:
            score = test.check(calls, [H.call(ns, c) for c in calls], True)
            if score.fraction < 1.0 - 1e-12:
                said.append(f"{test.name}: {score.fraction:.2f} {score.feedback}")
    return not said, said


def _grader_reads_longdouble() -> bool:
    """Whether the grader's child reads a longdouble array (issue 26 item 3 fixes it)."""
    from rikingrade.sandbox import child

    try:
        child.encode(np.eye(2, dtype=np.longdouble))
    except (RecursionError, child.EncodeError):
        return False
    return True


#: Until the grader reads longdouble (issue 26 item 3, another branch), the checks accept
#: it and the grader does not: those cases must fail, and pass once the grader is fixed.
_LONGDOUBLE = pytest.mark.xfail(not _grader_reads_longdouble(), strict=True,
                                reason="the grader does not read longdouble yet (issue 26.3)")
CASES = [pytest.param(arm, fn, ch, marks=_LONGDOUBLE if "longdouble" in ch.name else (),
                      id=f"{arm}-{fn}-{ch.name}")
         for arm in ARMS for fn in _functions(arm) for ch in CHANGES if ch.kind == _kind(fn)]


@pytest.mark.parametrize("arm,fn_name,change", CASES)
def test_visible_checks_and_grader_agree(arm: str, fn_name: str, change: Change) -> None:
    ns = dict(solution_namespace(arm))
    ns[fn_name] = change.wrap(ns[fn_name], fn_name, _revolute(arm, fn_name))
    seen, seen_said = _visible_ok(arm, ns, fn_name)
    graded, graded_said = _graded_ok(arm, ns, fn_name)
    assert seen == graded == change.ok, (
        f"statement: {'right' if change.ok else 'wrong'}; visible checks: "
        f"{'pass' if seen else 'fail'} {seen_said[:1]}; grader: "
        f"{'full marks' if graded else 'not full'} {graded_said[:2]}")


# ------------------------------------------------------------------ the cause each hint names
def _checks_namespace(arm: str) -> dict[str, Any]:
    return dict(solution_namespace(arm))


def _failed(ns: dict[str, Any], cell_pattern: str, arm: str) -> str:
    for _, src, _ in H.code_cells(solution(arm)):
        if re.search(cell_pattern, src):
            try:
                exec(compile(src, "<check>", "exec"), dict(ns))
            except Exception as exc:  # noqa: BLE001
                assert type(exc).__name__ == "CheckFailed", repr(exc)
                return str(exc)
    raise AssertionError(f"no check cell matching {cell_pattern} failed")


def test_a_textbook_guard_at_full_reach_is_told_about_rounding_not_lengths() -> None:
    """``if abs(c2) > 1: raise ValueError`` fails at full reach by rounding (issue 28)."""
    ns = _checks_namespace("scara")
    src = "".join(c for _, c, _ in H.code_cells(solution("scara")) if "def ik_scara(" in c)
    guarded = re.sub(r"(?m)^(\s*)c2 = np\.clip\(c2, -1\.0, 1\.0\).*$",
                     r"\1if abs(c2) > 1:\n\1    raise ValueError('out of reach')", src)
    assert guarded != src, "the scara solution's clip line moved: update this test"
    exec(compile(guarded, "<ik>", "exec"), ns)
    said = _failed(ns, r"check_ik\(ik_scara, fk_scara, L, \[3\.0, 4\.0, 3\.0\]", "scara")
    assert "edge of the workspace" in said and "np.clip" in said, said
    assert "own argument" not in said, said


def test_a_function_that_ignores_a_length_is_told_which() -> None:
    ns = _checks_namespace("scara")
    fk = ns["fk_scara"]

    def fk_scara(q, l1, l2, l3):  # uses the notebook's l2 whatever it is given
        return fk(q, l1, 3.0, l3)

    ns["fk_scara"] = fk_scara
    said = _failed(ns, r"^check_fk\(fk_scara,", "scara")
    assert "fk_scara gives the same answer when l2 changes" in said, said
    assert "l1" not in said.split("changes")[1].split("?")[0], said


def test_a_length_read_wrongly_is_not_blamed_on_an_ignored_argument() -> None:
    ns = _checks_namespace("scara")
    fk = ns["fk_scara"]

    def fk_scara(q, l1, l2, l3):  # reads every length, but adds a fixed offset
        T = np.array(fk(q, l1, l2, l3), dtype=float)
        T[2, 3] += 0.001 * (l1 - 4.0)
        return T

    ns["fk_scara"] = fk_scara
    said = _failed(ns, r"^check_fk\(fk_scara,", "scara")
    assert "does read each of l1, l2, l3" in said and "own argument" not in said, said


def test_a_failed_check_shows_its_message_alone_in_ipython() -> None:
    from IPython.core.interactiveshell import InteractiveShell
    from IPython.utils.capture import capture_output

    shell = InteractiveShell.instance()
    try:
        nb = solution("scara")
        checks = next(c.source for c in nb.cells if "checks" in c.metadata.get("tags", []))
        shell.run_cell(checks, store_history=False)
        with capture_output() as out:
            result = shell.run_cell("raise CheckFailed('your fk_scara puts the TCP at (1, 2, 3)')",
                                    store_history=False)
        assert result.error_in_exec is not None and not result.success
        text = re.sub(r"\x1b\[[0-9;]*m", "", out.stdout + out.stderr)  # IPython's colours
        assert "CheckFailed: your fk_scara puts the TCP at (1, 2, 3)" in text, text
        assert "Traceback" not in text and "<ipython-input" not in text and "%tb" in text, text
    finally:
        InteractiveShell.clear_instance()


def test_a_task_not_written_yet_shows_one_line_in_ipython() -> None:
    """Run All on an exercise stops at its first unwritten task: a check reaching the stub
    says which task, in one line and a hint, not a traceback through the checking helpers;
    a NotImplementedError of the student's own keeps its traceback."""
    from IPython.core.interactiveshell import InteractiveShell
    from IPython.utils.capture import capture_output

    shell = InteractiveShell.instance()
    try:
        nb = solution("scara")
        checks = next(c.source for c in nb.cells if "checks" in c.metadata.get("tags", []))
        shell.run_cell(checks, store_history=False)
        stub = ("def ik_scara_6dof(T, l1, l2, l3):\n"
                "    raise NotImplementedError('task 4: ik_scara_6dof')\n")
        with capture_output() as out:
            call = ("check_unreachable(ik_scara_6dof, {'l1': 1.0, 'l2': 1.0, 'l3': 1.0}, "
                    "[([9.0, 9.0, 9.0], 'far away')])")
            result = shell.run_cell(stub + call, store_history=False)
        assert result.error_in_exec is not None and not result.success
        text = re.sub(r"\x1b\[[0-9;]*m", "", out.stdout + out.stderr)
        assert "NotImplementedError: task 4: ik_scara_6dof" in text, text
        assert "is not written yet" in text, text
        assert "Traceback" not in text and "_call" not in text, text
        with capture_output() as out:
            shell.run_cell("def mine():\n    raise NotImplementedError('my own')\nmine()",
                           store_history=False)
        text = re.sub(r"\x1b\[[0-9;]*m", "", out.stdout + out.stderr)
        assert "Traceback" in text and "not written yet" not in text, text
    finally:
        InteractiveShell.clear_instance()
