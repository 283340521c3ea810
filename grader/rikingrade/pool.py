"""The worker pool: the submissions left to grade, each in one of ``workers`` sandboxes.

Every submission handed to :func:`run_pool` ends committed: graded, or as a grader error
with the reason (a bug or a disk error costs one submission, a stopped worker what it had
not graded), unless the batch is interrupted.
"""

from __future__ import annotations

import logging
import queue
import shutil
import threading
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from .assignment import Assignment
from .notebook import Submission
from .progress import Progress
from .report import GRADER_ERROR, SubmissionResult, TestResult
from .runner import RunOptions, SubmissionRunner
from .sandbox import Sandbox, SandboxConfig, SandboxUnavailable, prepare_workdir
from .sandbox.config import sandbox_workdir
from .spec import Call

log = logging.getLogger("rikingrade")

#: Commits one result (gradebook and views); False: not committed, the batch is interrupted.
Commit = Callable[[Submission, SubmissionResult], bool]


@dataclass(frozen=True)
class Batch:
    """What every submission of one grading batch is graded with.

    Attributes
    ----------
    assignment : Assignment
        The exercise and its tests.
    calls : list of list of Call
        Each test's calls, drawn with the batch's seed.
    options : RunOptions
        The runner's limits and timeouts.
    key : str
        The grading key every result records (assignment, seed, grader version).
    config : SandboxConfig
        The sandbox each worker starts.
    """

    assignment: Assignment
    calls: list[list[Call]]
    options: RunOptions
    key: str
    config: SandboxConfig


def run_pool(
    batch: Batch,
    todo: list[Submission],
    workers: int,
    done: Commit,
    bar: Progress,
    results: dict[str, SubmissionResult],
) -> None:
    """Grade ``todo`` with ``workers`` sandboxes; ``done`` commits each result as it comes
    (False: it was not committed, the batch is being interrupted)."""
    workdir = sandbox_workdir()
    prepare_workdir(workdir, batch.config.sandbox)
    pool = _Pool(batch, workdir, done, bar, results, todo)
    try:
        pool.run(min(workers, len(todo)))
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    pool.check_started()
    pool.account_for_the_rest(todo)


class _Pool:
    """The workers' shared state: the queue of submissions, the results, the stop flag."""

    def __init__(
        self,
        batch: Batch,
        workdir: Path,
        done: Commit,
        bar: Progress,
        results: dict[str, SubmissionResult],
        todo: list[Submission],
    ) -> None:
        self.batch, self.workdir = batch, workdir
        self.a, self.key, self.config = batch.assignment, batch.key, batch.config
        self.done, self.bar, self.results = done, bar, results
        self.jobs: queue.Queue[Submission] = queue.Queue()
        for s in todo:
            self.jobs.put(s)
        self.start_errors: list[str] = []
        self.lock = threading.Lock()
        self.stop = threading.Event()
        self.threads: list[threading.Thread] = []

    def run(self, n: int) -> None:
        """Start ``n`` workers and wait for them (Ctrl-C: they stop after their current
        submission, whose result is not committed)."""
        self.threads = [
            threading.Thread(target=self.worker, args=(i,), name=f"grader-{i}", daemon=True)
            for i in range(n)
        ]
        try:
            for t in self.threads:
                t.start()
            for t in self.threads:
                while t.is_alive():
                    t.join(0.2)
        except KeyboardInterrupt:
            self.stop.set()
            raise

    def worker(self, n: int) -> None:
        """One sandbox grading submissions from the queue until it is empty."""
        sandbox = Sandbox(self.config, self.workdir)
        try:
            try:
                sandbox.start()
            except SandboxUnavailable as exc:
                with self.lock:
                    self.start_errors.append(str(exc))
                return
            runner = SubmissionRunner(sandbox, self.a, self.batch.calls, self.batch.options,
                                      self.key)
            while not self.stop.is_set():
                try:
                    sub = self.jobs.get_nowait()
                except queue.Empty:
                    return
                res = self.grade_one(runner, sandbox, sub)
                if res is None:  # interrupted: the views are being written
                    return
                with self.lock:
                    self.results[sub.student] = res
                self.bar.update(res)
        except Exception:  # the worker itself: what it had not graded is reported after
            log.error("grader worker %d stopped:\n%s", n, traceback.format_exc())
        finally:
            sandbox.close()

    def grade_one(
        self, runner: SubmissionRunner, sandbox: Sandbox, sub: Submission
    ) -> SubmissionResult | None:
        """Grade and commit ``sub``; its result, None when it was not committed."""
        try:
            res = runner.grade(sub)
        except Exception:  # a bug must cost one submission, not the batch
            log.error("%s: internal error:\n%s", sub.student, traceback.format_exc())
            res = failed_result(self.a, sub, self.key)
            sandbox.close()
        try:
            if not self.done(sub, res):
                return None
            log_result(res)
        except Exception:  # e.g. a disk error: this submission only, never the batch
            log.error("%s: writing the results failed:\n%s", sub.student, traceback.format_exc())
            res = failed_result(self.a, sub, self.key, "writing this submission's results failed")
            try:
                if not self.done(sub, res):
                    return None
            except Exception:
                log.error("%s: its failure could not be recorded either", sub.student)
        return res

    def check_started(self) -> None:
        """Raise when no worker's sandbox started; log those that did not."""
        if self.start_errors and len(self.start_errors) == len(self.threads):
            raise SandboxUnavailable("\n".join([*self.config.notes, self.start_errors[0]]))
        for e in self.start_errors:
            log.warning("a worker's sandbox did not start: %s", e)

    def account_for_the_rest(self, todo: list[Submission]) -> None:
        """Every submission ends in the gradebook, graded or with the reason."""
        for s in todo:
            if s.student in self.results or self.stop.is_set():
                continue
            res = failed_result(self.a, s, self.key, "not graded: a grader worker stopped")
            self.results[s.student] = res
            try:
                self.done(s, res)
            except Exception:
                log.error("%s: not graded, and that could not be recorded", s.student)
            self.bar.update(res)


def failed_result(
    a: Assignment,
    sub: Submission,
    key: str,
    why: str = "",
    status: str = GRADER_ERROR,
    test_note: str = "not run: internal grader error",
) -> SubmissionResult:
    """The result of a submission the grader failed on (status grader-error, score 0), or
    did not read (``status`` invalid: a link)."""
    try:
        sha = sub.hash()
    except OSError:
        sha = ""
    return SubmissionResult(
        student=sub.student,
        path=sub.shown_path,
        sha256=sha,
        status=status,
        reason=why or "internal grader error (see the log)",
        max_score=a.max_score,
        key=key,
        tests=[
            TestResult(t.name, float(t.weight), 0.0, test_note, grader_error=status == GRADER_ERROR)
            for t in a.tests
        ],
    )


def log_result(res: SubmissionResult) -> None:
    """One submission's score, tests and failed cells into the grading log."""
    log.info(
        "%s: %.4g/%.4g %s %s (%.2f s) %s",
        res.student,
        res.score,
        res.max_score,
        res.status,
        res.reason,
        res.elapsed,
        res.path,
    )
    for t in res.tests:
        log.info(
            "  %s %s %.4g/%.4g: %s%s",
            res.student,
            t.name,
            t.points,
            t.weight,
            t.feedback,
            f" | {t.detail}" if t.detail else "",
        )
    for c in res.cells:
        if c.status != "ok":
            log.info(
                "  %s cell %d %s %s: %s\n%s",
                res.student,
                c.number,
                c.status,
                c.error_type,
                c.message,
                c.traceback,
            )
