"""Which cells grading runs: the cells that only call the answer functions are left out."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from rikingrade.assignment import load_assignment
from rikingrade.cellplan import calling_cells
from rikingrade.notebook import read_notebook

ROOT = Path(__file__).resolve().parent.parent
ARMS = ("cartesian", "cylindrical", "spherical", "scara")
MARKS = {"exercises": "raises-exception", "solutions": "nbval-check-output"}


@pytest.mark.parametrize("folder", sorted(MARKS))
@pytest.mark.parametrize("arm", ARMS)
def test_the_visible_checks_are_exactly_the_cells_left_out(folder, arm):
    """The rule finds, by reading the code, the cells the exercise tags as its checks."""
    path = ROOT / folder / f"{arm}.ipynb"
    raw = json.loads(path.read_text())
    code = [c for c in raw["cells"] if c["cell_type"] == "code"]
    tags = [set(c.get("metadata", {}).get("tags", [])) for c in code]
    marked = {i + 1 for i, t in enumerate(tags) if MARKS[folder] in t}
    drawing = {i + 1 for i, t in enumerate(tags) if "solution-only" in t}  # show_arm(...)
    left_out = calling_cells(read_notebook(path).cells, load_assignment(arm).functions)
    assert marked and left_out - drawing == marked


def _plan(*cells: str) -> set[int]:
    return calling_cells(list(enumerate(cells, 1)), ("fk", "ik"))


def test_a_cell_that_binds_what_a_running_cell_uses_runs():
    # T is used by ik's body: the cell that makes it must run although it calls fk
    assert _plan("T = fk([0, 0])", "def ik(p):\n    return T") == set()
    # ... but not when ik only has a parameter or a local of that name
    assert _plan("T = fk([0, 0])", "def ik(T):\n    return T") == {1}
    assert _plan("T = fk([0, 0])", "def ik(p):\n    T = p\n    return T") == {1}
    # two check cells sharing a name are both left out
    assert _plan("T = fk([0])", "print(ik(T))", "def fk(q):\n    return q") == {1, 2}


def test_cells_in_doubt_run():
    assert _plan("def fk(q):\n    return q\nprint(fk(1))") == set()  # defines an answer
    assert _plan("fk = lambda q: q") == set()
    assert _plan("%time print(fk(1))") == set()  # IPython syntax: not parsed
    assert _plan("globals()['x'] = fk(1)") == set()  # binds who knows what
    assert _plan("from math import *\nprint(fk(1))") == set()
    assert _plan("print('fk')") == set()  # only the word
    # an unparseable cell that mentions a name keeps the cell that binds it
    assert _plan("x = fk(1)", "%time y = x") == set()
    assert _plan("x = fk(1)", "%time y = 2") == {1}


def test_two_grader_workers_parse_cells_at_once():
    """The grader's worker threads plan cells concurrently; CPython 3.11's parser raised
    "SystemError: AST constructor recursion depth mismatch" when two threads parsed at once,
    which turned a correct notebook into an internal grader error."""
    import threading

    deep = "x = " + "(" * 40 + "1" + ")" * 40 + "\n" + "ik(" + "[" * 30 + "0" + "]" * 30 + ")\n"
    cells = [(i, deep) for i in range(40)]
    errors = []

    def work():
        try:
            for _ in range(30):
                calling_cells(cells, ["ik"])
        except Exception as exc:  # pragma: no cover - the failure being tested for
            errors.append(exc)

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
