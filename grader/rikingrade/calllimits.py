"""How long a notebook's functions may run: the per-call limit, and a short one after a hang.

Every call of a student's function gets the test's limit (2 s in the arm exercises,
``--timeout``), wherever it is called from: the hidden tests call the answer functions, and
the answer functions call each other (``ik_scara_6dof`` calls ``ik_scara``) and their
helpers. The child enforces the limits itself (``sandbox/child.py``, ``Watch``): it looks at
its stack every 20 ms, stops the call when it runs out and says which of the notebook's
functions were running (none of them returned in time). It counts time as on an idle
machine: wall-clock time less the time the process waited for a processor while the
machine was busy (``busy_clock``), so a correct answer keeps its points however loaded the
grader's machine is. The grader's own clock, for code that cannot be interrupted, waits
longer (:func:`backstop`): the limit stretched by the machine's load, plus :data:`GRACE`.

An endless loop would otherwise cost the full limit again in every test that reaches it.
So once a function has run out of time, each later call of it (direct, or from another
function, in any later test or cell) gets a short limit: :data:`FACTOR` times the longest
it was seen taking in a call that returned, at least :data:`FLOOR` of the per-call limit
(0.25 s of 2 s), never more than the limit. A function that hangs on every input costs
the limit once and a quarter of a second per later test; one that hangs only on some inputs
keeps the points of every test where it returns in its usual time; a slow but correct
function never runs out, so it never gets a short limit. The feedback of a test stopped at a
short limit says so, and why.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

from .i18n import t

#: A function that ran out of time gets this many times its longest successful call.
FACTOR = 4.0
#: ... and never less than this fraction of the per-call limit.
FLOOR = 1 / 8
#: Seconds the grader's clock waits beyond the child's (which stops the call itself).
GRACE = 0.5
#: Functions the grader keeps figures for, per notebook.
MAX_FUNCTIONS = 200
#: The grader's clock allows a call at most this many times its limit (a busy machine).
MAX_STRETCH = 20.0


def _load_per_cpu() -> float:
    """The 1-minute load average per processor (0 where the system does not say)."""
    try:
        return os.getloadavg()[0] / (os.cpu_count() or 1)
    except OSError:
        return 0.0


def backstop(limit: float) -> float:
    """Wall-clock seconds the grader waits for a call that the child limits to ``limit``.

    The child stops a call after ``limit`` seconds of its own time (not counting waits for
    a processor); on a machine with more runnable processes than processors that takes
    longer on the wall clock, about the load per processor times as long. The grader's
    clock, which only catches what the child cannot interrupt, allows twice that.
    """
    return limit * min(MAX_STRETCH, max(1.0, 2.0 * _load_per_cpu())) + GRACE


def cell_wall(limit: float) -> float:
    """Wall-clock seconds a code cell limited to ``limit`` seconds gets: as on an idle
    machine, so ``limit`` times the load per processor when there are more runnable
    processes than processors (at most :data:`MAX_STRETCH` times). Only the grader's
    clock stops a cell, so a busy machine must not shorten what a cell may do."""
    return limit * min(MAX_STRETCH, max(1.0, _load_per_cpu()))


@dataclass
class CallLimits:
    """What one notebook's functions did so far: their times, and where they ran out."""

    #: function -> longest seconds seen for a call of it that returned
    ok: dict[str, float] = field(default_factory=dict)
    #: function -> where it ran out of time, in order (test names, "code cell N")
    ran_out: dict[str, list[str]] = field(default_factory=dict)

    def short(self, name: str, limit: float) -> float:
        """The short limit of ``name`` once it has run out of time (seconds)."""
        return min(limit, max(FLOOR * limit, FACTOR * self.ok.get(name, 0.0)))

    def leash(self, limit: float) -> dict[str, float]:
        """The short limits to enforce now: function -> seconds (below ``limit`` only)."""
        out = {n: self.short(n, limit) for n in self.ran_out}
        return {n: s for n, s in out.items() if s < limit}

    def limit_of(self, name: str, limit: float) -> float:
        """The limit of a call of ``name``: its short one if it has one, else ``limit``."""
        return self.short(name, limit) if name in self.ran_out else limit

    def returned(self, name: str, seconds: object, limit: float) -> None:
        """A call of ``name`` was seen to take ``seconds`` and finish (clamped to the limit)."""
        if not isinstance(name, str) or isinstance(seconds, bool):
            return
        if not isinstance(seconds, (int, float)) or not math.isfinite(seconds):
            return
        if name not in self.ok and len(self.ok) >= MAX_FUNCTIONS:
            return
        self.ok[name] = max(self.ok.get(name, 0.0), min(max(float(seconds), 0.0), limit))

    def timed_out(self, names: list[str], where: str, short: str = "") -> None:
        """A call (or a cell) ran out of time in ``where`` with ``names`` running.

        At the full limit every function on the stack gets a short limit (none of them
        returned in time); at the short limit of ``short``, only that function is charged
        (the functions around it did not run out of their own time).
        """
        for n in [short] if short else names:
            if n in self.ran_out:
                self.ran_out[n].append(where)
            elif len(self.ran_out) < MAX_FUNCTIONS:
                self.ran_out[n] = [where]

    def summary(self, answers: tuple[str, ...], limit: float) -> list[str]:
        """One line per answer function that ran out of time, for the student."""
        lines = []
        for name in answers:
            where = self.ran_out.get(name)
            if not where:
                continue
            text = t(
                "{name} did not return within {limit} s in {where}; from then on each call of "
                "it got a short limit of {short} s ({factor} times its longest call that "
                "returned, at least {floor} s), so that an endless loop costs the full limit "
                "once", name=name, limit=f"{limit:g}", where=_where(where[0]),
                short=f"{self.short(name, limit):.2g}", factor=f"{FACTOR:g}",
                floor=f"{FLOOR * limit:.2g}")
            if len(where) > 1:
                more = ", ".join(_where(w) for w in where[1:6]) + (
                    ", ..." if len(where) > 6 else ""
                )
                text += t("; it ran out of that too in {more}", more=more)
            lines.append(text)
        return lines

    def stopped_text(self, name: str, limit: float, answers: tuple[str, ...]) -> str:
        """The feedback of a call stopped at the short limit of ``name``."""
        who = name if name in answers else t("a function it calls")
        first = self.ran_out.get(name, [EARLIER])[0]
        return t("timed out: stopped at the short limit of {who} ({short} s), which did not "
                 "return within {limit} s in {where}", who=who,
                 short=f"{self.short(name, limit):.2g}", limit=f"{limit:g}",
                 where=_where(first))


#: Where a function ran out of time when that is not known.
EARLIER = "an earlier test"


def _where(w: str) -> str:
    """A place a function ran out of time ("code cell 7", a test's name, EARLIER) in words."""
    if w.startswith("code cell "):
        return t("code cell {number}", number=w[len("code cell "):])
    if w == EARLIER:
        return t("an earlier test")
    return t("test {name}", name=w)
