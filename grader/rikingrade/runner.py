"""Grading one submission: run its cells in a sandboxed child, call its functions, score.

The steps, in order:

1. read the notebook as JSON (no code runs); unreadable -> status ``invalid``, score 0;
2. fork a child and run the code cells in file order, as "Run All" would, except the
   cells that only call the answer functions (the visible checks: see ``cellplan``): a
   cell that raises is recorded and the next cells still run; a cell that hangs past
   ``cell_timeout`` (as on an idle machine: stretched by the load, ``calllimits.cell_wall``)
   or kills its process is recorded and skipped in a fresh child;
3. for each hidden test, send its calls one at a time with that test's wall-clock
   timeout; a call that times out or kills the child costs that test only: the rest of
   its calls are not run and the next test gets a fresh child (cells re-run); a function
   that ran out of time gets a short limit from then on, wherever it is called from
   (``calllimits``);
4. score every test in the grader with ``HiddenTest.check`` (never in the child).

Nothing the child sends extends a deadline: cell events count only in the order the cells
were sent (a repeated or forged ``cell_start`` is ignored), answers only with the id asked
for, and the whole submission has a wall-clock budget (``time_budget``) that no deadline
passes. Every text from the child is cut to size (and made valid Unicode by the channel);
what one submission may leave in the results (cell reports, output, problems) is capped.
"""

from __future__ import annotations

import base64
import difflib
import logging
import math
import socket
import time
import traceback
from dataclasses import dataclass, replace

from .assignment import Assignment
from .calllimits import CallLimits, backstop, cell_wall
from .cellplan import calling_cells
from .feedback import cell_problems, missing_cause
from .i18n import t, use
from .notebook import FileRefused, Notebook, NotebookError, Submission
from .report import (
    CELL_ERRORS,
    CRASHED,
    GRADER_ERROR,
    INVALID,
    OK,
    TIMEOUT,
    CellReport,
    SubmissionResult,
    TestResult,
)
from .safetext import printable
from .sandbox import (
    Child,
    ChildDied,
    ChildTimeout,
    Limits,
    ProtocolError,
    Sandbox,
    SandboxUnavailable,
)
from .sandbox.zygote import CONTROL_TIMEOUT
from .spec import UNREADABLE, UNREADABLE_BASE, Call, HiddenTest, Outcome, Score
from .wire import WireError, encode_input, unreadable_text

log = logging.getLogger("rikingrade")

GRADER_PROBLEM = (
    "this test could not be scored because of a problem in the grader; "
    "your instructor has been told"
)
#: Cells reported one by one (a failing cell beyond these is only counted).
MAX_CELL_REPORTS = 50
#: Notebook problems listed for the student (the rest are counted).
MAX_PROBLEMS = 40
#: Cells slower than this (seconds, all together) are not run again after a call hangs:
#: the process that ran them stays as a template and each test's calls run in a fork of it.
TEMPLATE_AFTER = 0.25


@dataclass(frozen=True)
class RunOptions:
    """Per-submission settings (see :func:`rikingrade.grade`)."""

    limits: Limits
    cell_timeout: float = 30.0
    timeout: float | None = None
    output_limit: int = 10_000
    reveal: bool = False
    #: wall-clock seconds for everything one submission may cost (cells, calls, retries)
    time_budget: float = 180.0
    #: characters of printed output kept per submission, all cells together
    output_total: int = 100_000


class BudgetSpent(Exception):
    """The submission used its whole wall-clock budget."""


class ExecFailed(Exception):
    """The notebook's cells could not be run at all."""


def missing_message(name: str, defined: set[str], expected: tuple[str, ...] = ()) -> str:
    """Feedback for a function the tests need that the notebook does not define."""
    others = sorted(f for f in defined if f not in expected)
    close = difflib.get_close_matches(name, others, n=3, cutoff=0.4)
    msg = f"function {name} not found: did you rename it?"
    if close:
        msg += f" (your notebook defines {', '.join(close)})"
    elif others:
        msg += (
            f" (your notebook defines {', '.join(others[:3])}{', ...' if len(others) > 3 else ''})"
        )
    else:
        msg += " (or is the cell that defines it deleted or failing?)"
    return msg


class SubmissionRunner:
    """Grades submissions one after another in one sandbox."""

    def __init__(
        self,
        sandbox: Sandbox,
        assignment: Assignment,
        calls: list[list[Call]],
        options: RunOptions,
        key: str = "",
    ) -> None:
        self.sandbox = sandbox
        self.assignment = assignment
        self.calls = calls
        self.opt = options
        self.key = key

    # ------------------------------------------------------------------ entry point
    def grade(self, sub: Submission) -> SubmissionResult:
        t0 = time.monotonic()
        a = self.assignment
        result = SubmissionResult(
            student=sub.student,
            path=str(sub.path),
            sha256=sub.hash(),
            status=OK,
            max_score=a.max_score,
            key=self.key,
        )
        try:
            nb = sub.load()  # read without root's rights, even as root (studentfiles)
            result.sha256 = sub.sha256
        except NotebookError as exc:
            result.status = INVALID
            result.reason = str(exc)
            # not read, or not a notebook: refused with the reason, counted as refused (the
            # summary, the exit status) like any other file handed in that is not a notebook
            result.refused = sub.refused if isinstance(exc, FileRefused) else str(exc)
            result.problems = [f"the notebook could not be read: {exc}"]
            result.tests = [
                TestResult(t.name, float(t.weight), 0.0, "not run: the notebook could not be read")
                for t in a.tests
            ]
            result.elapsed = time.monotonic() - t0
            return result
        run = _Run(self, nb)
        result.language = nb.language
        try:
            with use(nb.language):  # the notes on files not given are feedback too
                if sub.handed:
                    mb = self.opt.limits.max_file_mb
                    handed = sub.read_handed(mb * 1024 * 1024) if mb else sub.read_handed()
                    run.files, run.file_notes = handed.files, handed.notes
                run.execute(result)
        except SandboxUnavailable as exc:
            log.error("%s: sandbox failure: %s", sub.student, exc)
            result.status = GRADER_ERROR
            result.reason = f"the sandbox failed: {exc}"
            done = len(result.tests)
            result.tests += [
                TestResult(
                    t.name,
                    float(t.weight),
                    0.0,
                    "not run: the grader's sandbox failed",
                    grader_error=True,
                )
                for t in a.tests[done:]
            ]
        finally:
            run.close()
        result.elapsed = time.monotonic() - t0
        return result


class _Run:
    """The state of grading one notebook (children come and go, skipped cells stay)."""

    def __init__(self, runner: SubmissionRunner, nb: Notebook) -> None:
        self.r = runner
        self.nb = nb
        self.t_end = time.monotonic() + runner.opt.time_budget
        self.budget_spent = False
        # cells that only call the answer functions: the hidden tests call them instead
        self.not_run = calling_cells(nb.cells, runner.assignment.functions)
        self.skip: set[int] = set()
        self.cells: dict[int, CellReport] = {}
        self.child: Child | None = None
        self.functions: set[str] = set()
        self.exec_error: str = ""
        self.call_id = 0
        self.timed_out = False
        self.crashed = False
        self.output_used = 0  # characters of cell output kept so far
        self.quiet_ok = 0  # cells that ran without error or output (not reported)
        self.unlisted: dict[str, int] = {}  # reports beyond MAX_CELL_REPORTS, by status
        self.seen: set[int] = set()  # cells whose end was recorded (a retry re-runs them)
        self.template: Child | None = None  # the process that ran the cells, when kept
        self.templates_ok = True  # False once a template failed to fork a worker
        self.cell_seconds = 0.0
        self.limits = CallLimits()  # the functions' times, and where they ran out
        #: the student's files for the cells' working folder (name, bytes), and why any
        #: file handed in beside the notebook was not given (see rikingrade.handedfiles)
        self.files: list[tuple[str, bytes]] = []
        self.file_notes: list[str] = []
        opt, tests = runner.opt, runner.assignment.tests
        #: seconds per call of an answer function, also from a cell that runs
        self.call_limit = (
            opt.timeout
            if opt.timeout is not None
            else max((float(t.timeout) for t in tests), default=5.0)
        )

    def deadline(self, seconds: float) -> float:
        """``seconds`` from now, but never past the submission's budget."""
        return min(time.monotonic() + seconds, self.t_end)

    def _spent(self) -> str:
        return t("the notebook used its whole time budget ({seconds} s)",
                 seconds=f"{self.r.opt.time_budget:g}")

    def _check_budget(self) -> None:
        if time.monotonic() >= self.t_end - 1e-3:
            self.budget_spent = True
            self.timed_out = True
            raise BudgetSpent()

    def close(self) -> None:
        for c in (self.child, self.template):
            if c is not None:
                try:
                    c.send({"op": "bye"}, time.monotonic() + 1.0)
                except (ChildDied, ChildTimeout):
                    pass
                c.close()
        self.child = self.template = None

    def _drop_child(self) -> None:
        """End the process that hung or died (and all it started); keep the template."""
        if self.child is not None:
            self.child.close()
            self.child = None
        if self.template is not None:
            if self.r.sandbox.kill_except(self.template.pid):
                return
            self.template.close()
            self.template = None
        self.r.sandbox.reset()

    def _worker(self) -> Child | None:
        """A fork of the template to run calls in, or None (the template is then gone)."""
        assert self.template is not None
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        worker = Child(ours, -1)
        deadline = self.deadline(CONTROL_TIMEOUT)
        try:
            try:
                self.template.send_fd({"op": "fork"}, theirs.fileno())
            finally:
                theirs.close()
            while True:  # the template's answer (its student threads may write too)
                msg = self.template.recv(deadline)
                if msg.get("event") == "forked":
                    break
            hello = worker.recv(deadline) if msg.get("ok") is True else {}
            pid = _int(hello.get("pid"))
            if hello.get("event") == "worker" and pid is not None and pid > 1:
                worker.pid = pid
                return worker
        except (ChildDied, ChildTimeout, ProtocolError):
            pass
        log.info("no worker from the template; running the cells again")
        self.templates_ok = False
        worker.close()
        self.template.close()
        self.template = None
        self.r.sandbox.reset()
        return None

    # ------------------------------------------------------------------ cells
    def start_child(self) -> None:
        """Fork a child and run the cells; cells that hang or kill are skipped on retry.

        Only the grader's own order counts: ``cell_start`` is accepted for the next cell
        sent and ``cell_end`` for the running one; anything else the child writes (a
        forged or repeated event) is ignored and moves no deadline.
        """
        opt = self.r.opt
        attempts = 0
        while True:
            attempts += 1
            if attempts > len(self.nb.cells) + 3:
                raise ExecFailed("the notebook's process could not be started")
            self._check_budget()
            cells = [
                (n, src) for n, src in self.nb.cells if n not in self.skip and n not in self.not_run
            ]
            child = self.r.sandbox.spawn(opt.limits, warm=[src for _, src in cells])
            order = [n for n, _ in cells]
            pos = 0  # index in order of the next cell that may start
            current: int | None = None
            last: int | None = None  # the last cell that started (blamed if none is running)
            try:
                deadline = self.deadline(cell_wall(opt.cell_timeout))
                child.send(self._exec_message(cells), deadline)
                while True:
                    msg = child.recv(deadline)
                    ev = msg.get("event")
                    n = _int(msg.get("cell"))
                    if ev == "cell_start":
                        if current is None and pos < len(order) and n == order[pos]:
                            current = last = n
                            pos += 1
                            deadline = self.deadline(cell_wall(opt.cell_timeout))
                    elif ev == "cell_end":
                        if n is not None and n == current:
                            sec = msg.get("seconds")
                            if isinstance(sec, (int, float)) and math.isfinite(sec):
                                self.cell_seconds += max(0.0, min(float(sec), opt.cell_timeout))
                            if n not in self.seen:
                                self.seen.add(n)
                                self._record(n, msg)
                                self._cell_ran_out(n, msg)
                            current = None
                            deadline = self.deadline(cell_wall(opt.cell_timeout))
                    elif ev == "exec_done" and current is None and pos == len(order):
                        if self._cells_done(child, msg):
                            return
                        break  # the template could not fork: run the cells again
            except ChildTimeout:
                self._cells_timed_out(child, current, last)
            except (ChildDied, ProtocolError) as exc:
                why = self._why_died(child, exc)
                self.crashed = True
                self._skip_cell(
                    child, current, last, "crashed",
                    t("stopped the notebook's process ({why})", why=why)
                )

    def _exec_message(self, cells: list[tuple[int, str]]) -> dict:
        """The request to run ``cells`` ((number, source) pairs) with this run's limits."""
        opt = self.r.opt
        return {
            "op": "exec",
            "cells": [[n, src] for n, src in cells],
            "output_limit": opt.output_limit,
            "output_total": max(0, opt.output_total - self.output_used),
            "want": list(self.r.assignment.functions),
            "limit": self.call_limit,
            "leash": self.limits.leash(self.call_limit),
            "files": [[name, base64.b64encode(data).decode()] for name, data in self.files],
        }

    def _cells_done(self, child: Child, msg: dict) -> bool:
        """The cells have run: note the functions defined and take ``child`` to call them
        (keeping it as a template when the cells were slow); False when the template
        could not fork a worker (the cells must run again)."""
        funcs = msg.get("functions")
        self.functions = (
            {f for f in funcs[:10_000] if isinstance(f, str)} if isinstance(funcs, list) else set()
        )
        self.child = child
        if self.templates_ok and self.cell_seconds > TEMPLATE_AFTER:
            self.template = child
            self.child = self._worker()
        return self.child is not None

    def _cells_timed_out(self, child: Child, current: int | None, last: int | None) -> None:
        """A cell hung: skip it next time (BudgetSpent when the whole budget is gone)."""
        opt = self.r.opt
        self.timed_out = True
        if time.monotonic() >= self.t_end - 1e-3:
            child.close()
            self.r.sandbox.reset()
            if current is not None:
                self.cells[current] = CellReport(
                    current, "timeout", message=t("was still running: {why}", why=self._spent())
                )
            self._check_budget()
        what = t("did not finish within {seconds} s", seconds=f"{opt.cell_timeout:g}")
        self._skip_cell(child, current, last, "timeout", what)

    def _record(self, n: int, msg: dict) -> None:
        """Keep one cell's report, within the submission's caps."""
        rep = _cell_report(n, msg)
        if rep.status == "ok" and not rep.output and not rep.notes:
            self.quiet_ok += 1
            return
        left = max(0, self.r.opt.output_total - self.output_used)
        if len(rep.output) > left:
            cut = "\n... [cut: the notebook's output limit]" if left else ""
            rep.output = rep.output[:left] + cut
            self.output_used = self.r.opt.output_total
        else:
            self.output_used += len(rep.output)
        if len(self.cells) >= MAX_CELL_REPORTS:
            self.unlisted[rep.status] = self.unlisted.get(rep.status, 0) + 1
            return
        self.cells[n] = rep

    def _cell_ran_out(self, n: int, msg: dict) -> None:
        """A call in cell ``n`` was stopped at its limit: its functions get short ones."""
        fired = msg.get("timed_out")
        if isinstance(fired, dict):
            self.timed_out = True
            self.limits.timed_out(_names(fired.get("stack")), f"code cell {n}")

    def _why_died(self, child: Child, exc: Exception) -> str:
        """Why a child stopped answering, in words ("killed (SIGKILL)", a protocol error)."""
        return str(exc) if isinstance(exc, ProtocolError) else self.r.sandbox.status_of(child.pid)

    def _skip_cell(
        self, child: Child, current: int | None, last: int | None, status: str, what: str
    ) -> None:
        """Drop the child and mark the cell to blame, so the next child runs without it."""
        child.close()
        self.r.sandbox.reset()
        cell = self._blame(current, last)
        self.cells[cell] = CellReport(
            cell, status, message=t("{what}; skipped (later cells still ran)", what=what)
        )
        self.skip.add(cell)

    def _blame(self, current: int | None, last: int | None) -> int:
        """The cell to skip next time; ExecFailed when no retry could make progress."""
        cell = current if current is not None else last
        numbers = {n for n, _ in self.nb.cells}
        if cell is None or cell not in numbers or cell in self.skip:
            raise ExecFailed("the notebook's process stopped answering while its cells ran")
        return cell

    # ------------------------------------------------------------------ tests
    def call_batch(
        self, calls: list[Call], timeout: float, test: str = ""
    ) -> tuple[list[Outcome], bool, bool]:
        """Run calls in order in the current child; returns (outcomes, timed out, crashed).

        All calls go in one message and the child answers each as soon as it returns,
        so the ``timeout`` applies per call: call k's clock starts when call k - 1's
        answer arrives (or when the batch is sent). The child stops a call at its limit
        (``timeout``, or the short limit of a function that already ran out: see
        ``calllimits``), counting time as on an idle machine, and says which functions
        were running; the grader's own wall clock waits longer (``backstop``: the load
        stretches the wall-clock time of a call). A call that times out or kills the
        child ends the batch: the child is dropped and the calls after it are not run.
        """
        assert self.child is not None
        items = [self._call_item(call) for call in calls]
        ids = [item["id"] for item in items]
        outcomes: list[Outcome] = []
        limits = self.limits
        leash = limits.leash(timeout)
        started = time.monotonic()
        deadline = self.deadline(backstop(limits.limit_of(calls[0].function, timeout)))
        fired: dict = {}
        try:
            msg = {"op": "calls", "calls": items, "limit": timeout, "leash": leash}
            self.child.send(msg, deadline)
            for k, cid in enumerate(ids):
                while True:  # only the answer to the call asked for moves the clock on
                    msg = self.child.recv(deadline)
                    if msg.get("id") == cid:
                        break
                stop = msg.get("timed_out")
                if isinstance(stop, dict):  # the child stopped it
                    fired = stop
                    raise ChildTimeout()
                limits.returned(calls[k].function, _took(msg, started), timeout)
                seen = msg.get("seen")
                for name, sec in list(seen.items())[:50] if isinstance(seen, dict) else ():
                    limits.returned(name, sec, timeout)
                outcomes.append(_outcome(msg))
                started = time.monotonic()
                if k + 1 < len(calls):
                    nxt = limits.limit_of(calls[k + 1].function, timeout)
                    deadline = self.deadline(backstop(nxt))
        except ChildTimeout:
            self.timed_out = True
            self._drop_child()
            call = calls[len(outcomes)].function
            outcomes.append(self._call_timed_out(call, fired, timeout, leash, test))
            rest = Outcome(timed_out=True,
                           detail=t("not run: an earlier call of this test timed out"))
            outcomes += [rest] * (len(calls) - len(outcomes))
            return outcomes, True, False
        except (ChildDied, ProtocolError) as exc:
            why = self._why_died(self.child, exc)
            self.crashed = True
            self._drop_child()
            outcomes.append(Outcome(crashed=True, detail=why))
            rest = Outcome(
                crashed=True,
                detail=t("not run: the notebook's process died in an earlier call of this test"),
            )
            outcomes += [rest] * (len(calls) - len(outcomes))
            return outcomes, False, True
        return outcomes, False, False

    def _call_item(self, call: Call) -> dict:
        """One call as the child reads it, under a fresh id."""
        self.call_id += 1
        args, kw = call.arguments()
        return {
            "id": self.call_id,
            "function": call.function,
            "args": [encode_input(v) for v in args],
            "kwargs": {k: encode_input(v) for k, v in kw.items()},
        }

    def _call_timed_out(
        self, call: str, fired: dict, timeout: float, leash: dict[str, float], test: str
    ) -> Outcome:
        """The outcome of a call of ``call`` that ran out of time, and what it teaches the
        limits: ``fired`` is the child's stop ({} when the grader's own clock ran out)."""
        spent = time.monotonic() >= self.t_end - 1e-3 and not fired
        self.budget_spent |= spent
        names = _names(fired.get("stack")) or [call]
        stopped = fired.get("function")
        name = stopped if isinstance(stopped, str) else call
        short = name in leash
        if spent:
            detail = t("stopped: {why}", why=self._spent())
        elif short:
            detail = self.limits.stopped_text(name, timeout, self.r.assignment.functions)
        else:
            inner = [n for n in names if n in self.r.assignment.functions and n != call]
            detail = t("timed out: no result within {seconds} s", seconds=f"{timeout:g}") + (
                t(" (it was running {function})", function=inner[-1]) if inner else ""
            )
        if not spent:
            self.limits.timed_out(names, test, name if short else "")
        return Outcome(timed_out=True, detail=detail)

    def run_test(self, index: int) -> TestResult:
        test = self.r.assignment.tests[index]
        calls = self.r.calls[index]
        timeout = self.r.opt.timeout if self.r.opt.timeout is not None else float(test.timeout)
        outcomes: list[Outcome | None] = [None] * len(calls)
        pending: list[int] = []  # the calls the notebook's functions must answer
        for i, call in enumerate(calls):
            if self.exec_error:
                outcomes[i] = Outcome(crashed=True, detail=self.exec_error)
            elif call.function not in self.functions:
                outcomes[i] = Outcome(
                    error_type="NameError",
                    error_message=missing_message(
                        call.function, self.functions, self.r.assignment.functions
                    ),
                )
            else:
                pending.append(i)
        t_out = crashed = False
        if pending:
            self._ensure_child()
            if self.child is None:
                lost = Outcome(
                    crashed=True, detail=self.exec_error or t("the notebook could not be run")
                )
                for i in pending:
                    outcomes[i] = lost
            else:
                answers, t_out, crashed = self.call_batch(
                    [calls[i] for i in pending], timeout, test.name
                )
                for i, o in zip(pending, answers, strict=True):
                    outcomes[i] = o
        return self.check(test, calls, outcomes, t_out, crashed)

    def _ensure_child(self) -> None:
        if self.child is None and self.template is not None:
            self.child = self._worker()
        if self.child is None and not self.exec_error:
            try:
                self.start_child()
            except ExecFailed as exc:
                self.exec_error = str(exc)

    def check(self, test, calls, outcomes, t_out, crashed) -> TestResult:
        w = float(test.weight)
        try:
            score = test.check(calls, outcomes, self.r.opt.reveal)
            if not isinstance(score, Score):
                raise TypeError(f"check returned {type(score).__name__}, not Score")
            frac = float(score.fraction)
            if not (math.isfinite(frac) and -1e-9 <= frac <= 1 + 1e-9):
                raise ValueError(f"check returned fraction {frac!r} outside [0, 1]")
            frac = min(1.0, max(0.0, frac))
            return TestResult(
                test.name,
                w,
                frac,
                str(score.feedback),
                str(score.detail),
                timed_out=t_out,
                crashed=crashed,
            )
        except Exception:
            tb = traceback.format_exc()
            log.error("hidden test %s raised while scoring:\n%s", test.name, tb)
            return TestResult(
                test.name,
                w,
                0.0,
                GRADER_PROBLEM,
                tb[-2000:],
                timed_out=t_out,
                crashed=crashed,
                grader_error=True,
            )

    # ------------------------------------------------------------------ all
    def execute(self, result: SubmissionResult) -> None:
        """Run the cells, then every hidden test; fill in ``result`` (tests, cells,
        problems, status and its reason)."""
        a = self.r.assignment
        try:
            if self.nb.cells:
                self._ensure_child()
        except BudgetSpent:
            pass
        for i in range(len(a.tests)):
            result.tests.append(self._test_result(i))
        result.cells = [self.cells[n] for n in sorted(self.cells)]
        missing = [f for f in a.functions if f not in self.functions]
        result.problems = self._problems(missing)
        result.status, result.reason = self._status(result, missing)

    def _test_result(self, index: int) -> TestResult:
        """Hidden test ``index`` run and scored, or scored 0 when the budget is spent or
        the test cannot send its input."""
        test = self.r.assignment.tests[index]
        if self.budget_spent or time.monotonic() >= self.t_end:
            self.budget_spent = self.timed_out = True
            return self._not_run(test)
        try:
            return self.run_test(index)
        except BudgetSpent:
            return self._not_run(test)
        except WireError as exc:  # a hidden test built an input that cannot be sent
            log.error("hidden test %s: %s", test.name, exc)
            return TestResult(
                test.name,
                float(test.weight),
                0.0,
                GRADER_PROBLEM,
                str(exc),
                grader_error=True,
            )

    def _not_run(self, test: HiddenTest) -> TestResult:
        return TestResult(
            test.name,
            float(test.weight),
            0.0,
            t("not run: {why}", why=self._spent()),
            timed_out=True,
        )

    def _problems(self, missing: list[str]) -> list[str]:
        """What the student reads about the notebook: its warnings, failing cells (capped),
        missing functions, functions that ran out of time, and why grading stopped."""
        a = self.r.assignment
        problems = list(self.nb.warnings)[:10] + self.file_notes[:10]
        if not self.nb.cells:
            problems.append(t("the notebook has no code cells"))
        cell_lines = cell_problems(self.cells, self.nb.cells)
        more = len(cell_lines) - MAX_PROBLEMS + sum(self.unlisted.values())
        problems += cell_lines[:MAX_PROBLEMS]
        if more > 0:
            problems.append(t("... and {n} more problems in code cells (not listed)", n=more))
        problems += [
            missing_cause(f, self.functions, a.functions, self.nb.cells, self.cells)
            for f in missing
        ]
        problems += self.limits.summary(a.functions, self.call_limit)
        if self.exec_error:
            problems.append(self.exec_error)
        if self.budget_spent:
            problems.append(t("grading stopped: {why}; the tests not run score 0",
                              why=self._spent()))
        return problems

    def _status(self, result: SubmissionResult, missing: list[str]) -> tuple[str, str]:
        """The submission's status and its reason (the worst thing that happened first)."""
        a = self.r.assignment
        timeouts = [
            f"code cell {n}" for n, c in sorted(self.cells.items()) if c.status == "timeout"
        ]
        timeouts += [t.name for t in result.tests if t.timed_out]
        crashes = [
            f"code cell {n}" for n, c in sorted(self.cells.items()) if c.status == "crashed"
        ][:10]
        crashes += [t.name for t in result.tests if t.crashed]
        status = result.status
        reasons = []
        if any(t.grader_error for t in result.tests):
            status = GRADER_ERROR
            reasons.append("a hidden test failed while scoring (see the log)")
        elif self.timed_out or timeouts:
            status = TIMEOUT
            if self.budget_spent:
                reasons.append(self._spent())
            reasons.append(
                "did not finish in time: " + (", ".join(timeouts[:10]) or "the notebook")
            )
        elif self.crashed or crashes or self.exec_error:
            status = CRASHED
            reasons.append(
                self.exec_error
                or "the notebook's process died in: " + (", ".join(crashes) or "a cell")
            )
        elif any(c.status == "error" for c in self.cells.values()) or self.unlisted.get("error"):
            status = CELL_ERRORS
            errors = {n: replace(c, notes=[]) for n, c in self.cells.items() if c.status == "error"}
            first = cell_problems(errors, self.nb.cells)  # in the notebook's language
            reasons.append(
                (first[0] if first else "a code cell raised an error")
                + (f" (and {len(first) - 1} more)" if len(first) > 1 else "")
            )
        reasons += [
            missing_cause(f, self.functions, a.functions, self.nb.cells, self.cells)
            for f in missing
        ]
        return status, "; ".join(reasons)[:1000]

def _text(v: object, limit: int) -> str:
    """A child's text as a string of at most ``limit`` characters, without control
    characters (anything else: "")."""
    return printable(v[:limit]) if isinstance(v, str) else ""


def _outcome(msg: dict) -> Outcome:
    """A child's answer to one call as an Outcome (value or exception name and message)."""
    et = msg.get("error_type")
    if et is not None:
        bases = msg.get("error_bases")
        if bases == [UNREADABLE_BASE]:  # it returned; the words are the grader's, from a code
            return Outcome(
                error_type=UNREADABLE,
                error_message=unreadable_text(str(msg.get("error_message", ""))),
                error_bases=(UNREADABLE_BASE,),
            )
        return Outcome(
            error_type=_text(et, 200) or "Error",
            error_message=_text(msg.get("error_message"), 4000),
            error_bases=tuple(_text(b, 200) for b in bases[:20]) if isinstance(bases, list) else (),
        )
    return Outcome(value=msg.get("value"))


def _took(msg: dict, started: float) -> float:
    """How long a call took as its limit counts time (the child's ``busy_clock``: not
    the time it waited for a processor), at most the wall-clock time it took."""
    wall = time.monotonic() - started
    sec = msg.get("seconds")
    if isinstance(sec, (int, float)) and not isinstance(sec, bool) and math.isfinite(sec):
        return min(max(float(sec), 0.0), wall)
    return wall


def _names(v: object) -> list[str]:
    """The function names a child reported (at most 50 of 200 characters), else []."""
    return [x[:200] for x in v[:50] if isinstance(x, str)] if isinstance(v, list) else []


def _int(v: object) -> int | None:
    return v if isinstance(v, int) and not isinstance(v, bool) else None


#: Characters kept of each note a child sends on a cell (a failed shell command's, with
#: its reason: see ``MAX_SHOWN_COMMAND`` in the child).
MAX_NOTE = 300


def _cell_report(n: int, msg: dict) -> CellReport:
    err = msg.get("error")
    raw_notes = msg.get("notes")
    notes = [_text(x, MAX_NOTE) for x in raw_notes[:10]] if isinstance(raw_notes, list) else []
    output = _text(msg.get("output"), 20000)
    raw_sec = msg.get("seconds")
    sec = 0.0
    if isinstance(raw_sec, (int, float)) and not isinstance(raw_sec, bool):
        sec = float(raw_sec) if math.isfinite(raw_sec) else 0.0
    if isinstance(err, dict):
        return CellReport(
            n,
            "error",
            _text(err.get("type"), 100) or "Error",
            _text(err.get("message"), 2000),
            _text(err.get("traceback"), 2000),
            output,
            [x for x in notes if x],
            sec,
        )
    return CellReport(n, "ok", output=output, notes=[x for x in notes if x], seconds=sec)
