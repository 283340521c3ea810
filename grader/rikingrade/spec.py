"""The contract between hidden tests and the grading engine.

A hidden test never runs student code itself. The engine executes the
student's notebook in a sandboxed child process, calls the named function
with JSON-able keyword arguments, and hands back an :class:`Outcome`; the
test's ``check`` then scores it inside the grader process, against the
instructor's reference (``rikingrade.reference``).

Every exercise module ``rikingrade.hidden.<exercise>`` exposes::

    EXERCISE: str                 # e.g. "scara"
    NOTEBOOK: str                 # file name of the exercise notebook, e.g. "scara.ipynb"
    FUNCTIONS: tuple[str, ...]    # student functions the tests call
    TESTS: list[HiddenTest]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np


@dataclass(frozen=True)
class Call:
    """One call of a student function: ``function(**kwargs)``; kwargs are JSON-able."""

    function: str
    kwargs: dict[str, Any]


@dataclass(frozen=True)
class Outcome:
    """What one call returned, as seen from the grader.

    value : the JSON-decoded return value (lists for arrays), or None.
    error_type, error_message : the exception's class name and text, if it raised.
    error_bases : the exception's class and its bases (its MRO) as ``"module.Name"``:
        ``"builtins.ValueError"`` for Python's own, ``"__main__.Name"`` for a class the
        notebook defines. Empty when unknown.
    timed_out : the call exceeded its wall-clock limit.
    crashed : the child died (memory, os._exit, signal); ``detail`` says how.
    """

    value: Any = None
    error_type: str | None = None
    error_message: str | None = None
    error_bases: tuple[str, ...] = ()
    timed_out: bool = False
    crashed: bool = False
    detail: str = ""

    @property
    def ok(self) -> bool:
        """The call returned normally."""
        return self.error_type is None and not self.timed_out and not self.crashed


@dataclass(frozen=True)
class Score:
    """A test's result: ``fraction`` of its weight (0..1) and one feedback line.

    ``feedback`` speaks in the student's terms and never shows a hidden input
    unless ``reveal`` was granted; ``detail`` may show hidden values and goes
    only to the instructor's log.
    """

    fraction: float
    feedback: str
    detail: str = ""


@dataclass(frozen=True)
class HiddenTest:
    """One weighted hidden test.

    make_calls(rng) -> list[Call]
        The calls to run (random link lengths and targets from ``rng``).
    check(calls, outcomes, reveal) -> Score
        Scores the outcomes (same order as the calls), in the grader process.
    timeout : seconds of wall clock per call.
    """

    name: str
    weight: float
    description: str
    make_calls: Callable[[np.random.Generator], list[Call]]
    check: Callable[[list[Call], list[Outcome], bool], Score]
    timeout: float = 5.0
    tags: tuple[str, ...] = field(default_factory=tuple)
