"""A tiny in-process runner of the hidden tests, for OUR notebooks in tests only.

The real engine (``rikingrade``) runs student code in a sandboxed child and
never in its own process. Here the notebooks are the project's own solutions
and deliberately wrong variants of them, so running them with ``exec`` is fine:

* every code cell is executed in one fresh namespace, in order; a cell that
  raises is skipped and the next one runs, as in Jupyter (IPython magics are
  not used in the exercise notebooks);
* each :class:`~rikingrade.spec.Call` is made as the engine makes it: its arguments
  go through the wire (positionally in signature order, numpy arrays stay arrays),
  its return value through the child's encoder and JSON (arrays become lists; an
  unreadable value becomes an ``UnreadableResult``), into an
  :class:`~rikingrade.spec.Outcome`.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rikingrade.sandbox import child
from rikingrade.spec import UNREADABLE_BASE, Call, HiddenTest, Outcome, Score
from rikingrade.wire import decode_message, encode_input, unreadable_text

child.np = np  # the engine's child preloads numpy

os.environ.setdefault("MPLBACKEND", "Agg")


@dataclass
class CellRun:
    """One executed code cell: its index among all cells, tags, and the exception if any."""

    index: int
    tags: tuple[str, ...]
    error: BaseException | None


def code_cells(nb: Any) -> list[tuple[int, str, tuple[str, ...]]]:
    return [(i, c.source, tuple(c.get("metadata", {}).get("tags", ())))
            for i, c in enumerate(nb.cells) if c.cell_type == "code"]


def run_notebook(nb: Any) -> tuple[dict[str, Any], list[CellRun]]:
    """Execute the notebook's code cells like Jupyter: a raising cell is skipped."""
    ns: dict[str, Any] = {"__name__": "__main__"}
    runs = []
    for index, source, tags in code_cells(nb):
        err = None
        with contextlib.redirect_stdout(io.StringIO()):
            try:
                exec(compile(source, f"<cell {index}>", "exec"), ns)
            except Exception as exc:  # noqa: BLE001 - a notebook cell may raise anything
                err = exc
        runs.append(CellRun(index, tags, err))
    try:
        import matplotlib.pyplot as plt

        plt.close("all")
    except ImportError:  # pragma: no cover
        pass
    return ns, runs


def _through_the_wire(value: Any) -> Any:
    """A grader-side value as the student's function receives it (wire encode, JSON,
    the child's decode: numpy arrays stay numpy arrays)."""
    return child.decode(json.loads(json.dumps(encode_input(value))))


def call(ns: dict[str, Any], c: Call) -> Outcome:
    """Run one call in the namespace as the engine does, and describe it as an Outcome."""
    fn = ns.get(c.function)
    if not callable(fn):
        return Outcome(error_type="NameError", error_message=f"function {c.function} not found")
    args, kwargs = c.arguments()
    args = [_through_the_wire(a) for a in args]
    kwargs = {k: _through_the_wire(v) for k, v in kwargs.items()}
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            value = fn(*args, **kwargs)
    except Exception as exc:  # noqa: BLE001
        return Outcome(error_type=type(exc).__name__, error_message=str(exc),
                       error_bases=tuple(child._class_path(type(exc))))
    try:
        wire = child.encode(value)
    except (child.EncodeError, RecursionError) as exc:
        why = str(exc) if isinstance(exc, child.EncodeError) else "depth"
        return Outcome(error_type="UnreadableResult", error_message=unreadable_text(why),
                       error_bases=(UNREADABLE_BASE,))
    return Outcome(value=decode_message(json.dumps({"value": wire}))["value"])


def grade(module: Any, ns: dict[str, Any], seed: int, reveal: bool = False
          ) -> list[tuple[HiddenTest, Score]]:
    """Every hidden test of ``module`` on the namespace, with one rng seeded by ``seed``."""
    rng = np.random.default_rng(seed)
    out = []
    for test in module.TESTS:
        calls = test.make_calls(rng)
        outcomes = [call(ns, c) for c in calls]
        out.append((test, test.check(calls, outcomes, reveal)))
    return out


def points(results: list[tuple[HiddenTest, Score]]) -> dict[str, float]:
    return {t.name: t.weight * s.fraction for t, s in results}


def load(path: Path) -> Any:
    import nbformat

    return nbformat.read(str(path), as_version=4)
