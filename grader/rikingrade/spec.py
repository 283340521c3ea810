"""The contract between hidden tests and the grading engine.

A hidden test never runs student code itself. The engine executes the
student's notebook in a sandboxed child process, calls the named function
with the call's arguments (wire data: numbers, lists, numpy arrays), positionally
in the order of the exercise's signature, and hands back an :class:`Outcome`; the
test's ``check`` then scores it inside the grader process, against the
instructor's reference (``rikingrade.reference``).

Every exercise module ``rikingrade.hidden.<exercise>`` exposes::

    EXERCISE: str                 # e.g. "scara"
    NOTEBOOK: str                 # file name of the exercise notebook, e.g. "scara.ipynb"
    FUNCTIONS: tuple[str, ...]    # student functions the tests call
    TESTS: list[HiddenTest]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True, eq=False)
class Call:
    """One call of a student function.

    ``kwargs`` holds every input by its name in the exercise's signature (what the
    checks read); the ``positional`` ones (in signature order) are passed positionally,
    so a student may rename parameters, and the rest by keyword. Values are wire data
    (:mod:`rikingrade.wire`): numbers, lists, numpy arrays.
    """

    function: str
    kwargs: dict[str, Any]
    positional: tuple[str, ...] = ()

    def arguments(self) -> tuple[list[Any], dict[str, Any]]:
        """(args, kwargs) of the call as the student's function receives them."""
        args = [self.kwargs[n] for n in self.positional]
        rest = {k: v for k, v in self.kwargs.items() if k not in self.positional}
        return args, rest

    def key(self) -> str:
        """A text that identifies the call's inputs (arrays by their values)."""
        return repr(
            (
                self.function,
                self.positional,
                sorted((k, _plain(v)) for k, v in self.kwargs.items()),
            )
        )

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Call) and self.key() == other.key()

    def __hash__(self) -> int:
        return hash(self.key())


def _plain(v: Any) -> Any:
    """``v`` with numpy arrays as (dtype, nested lists), for comparing and hashing."""
    if isinstance(v, np.ndarray):
        return ("ndarray", v.dtype.str, v.tolist())
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    return v


#: The ``error_type`` and ``error_bases`` of an Outcome whose call returned a value the
#: engine could not read; its ``error_message`` is the grader's words for why.
UNREADABLE = "UnreadableResult"
UNREADABLE_BASE = "rikingrade.UnreadableResult"


@dataclass(frozen=True)
class Outcome:
    """What one call returned, as seen from the grader.

    value : the JSON-decoded return value (lists for arrays), or None.
    error_type, error_message : the exception's class name and text, if it raised.
    error_bases : the exception's class and its bases (its MRO) as ``"module.Name"``:
        ``"builtins.ValueError"`` for Python's own, ``"__main__.Name"`` for a class the
        notebook defines. Empty when unknown. ``(UNREADABLE_BASE,)`` marks a call that
        returned a value the engine could not read (``error_message``: the grader's words
        for why, composed from the child's reason code, never the child's text).
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
        """The call returned a value the grader could read."""
        return self.error_type is None and not self.timed_out and not self.crashed

    @property
    def unreadable(self) -> bool:
        """The call returned, but with a value the engine could not read (never a raise)."""
        return self.error_bases == (UNREADABLE_BASE,)


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
