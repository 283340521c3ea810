"""A progress bar for terminals and the end-of-batch summary (standard library only)."""

from __future__ import annotations

import sys
import threading
import time
from typing import TextIO

from .report import CELL_ERRORS, CRASHED, GRADER_ERROR, INVALID, OK, TIMEOUT, SubmissionResult

#: Statuses counted as failures on the progress bar (the notebook did not run through).
FAILED = (INVALID, GRADER_ERROR, CRASHED, TIMEOUT)


def _clock(seconds: float) -> str:
    """``1:05:09``, ``5:09`` or ``9 s``."""
    s = int(round(seconds))
    h, m = divmod(s, 3600)
    m, sec = divmod(m, 60)
    if h:
        return f"{h}:{m:02d}:{sec:02d}"
    return f"{m}:{sec:02d}" if m else f"{sec} s"


class Progress:
    """``[#####.....] 37/200  12/min  left 13:35  failed 2  alice`` on a TTY; one line per
    submission otherwise. The time left is estimated from the notebooks graded in this run
    (resumed ones cost nothing); failures are the notebooks that did not run through
    (not readable, crashed, timed out, grader error)."""

    def __init__(
        self,
        total: int,
        enabled: bool | None = None,
        stream: TextIO | None = None,
        quiet: bool = False,
        clock=time.monotonic,
    ) -> None:
        self.total = total
        self.done = 0
        self.graded = 0  # graded in this run (not resumed)
        self.failed = 0
        self.stream = stream or sys.stderr
        isatty = self.stream.isatty()
        self.tty = isatty and enabled is not False
        self.lines = enabled is True and not isatty
        self.quiet = quiet
        self.clock = clock
        self.t0 = clock()
        self.lock = threading.Lock()

    def eta(self) -> float | None:
        """Seconds left at the rate of this run, or None before the first graded notebook."""
        if not self.graded:
            return None
        rate = self.graded / max(1e-9, self.clock() - self.t0)
        return (self.total - self.done) / rate

    def line(self, res: SubmissionResult) -> str:
        """The bar as shown after ``res``."""
        width = 30
        filled = int(width * self.done / max(1, self.total))
        rate = self.graded / max(1e-9, self.clock() - self.t0) * 60
        left = self.eta()
        return (
            f"[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
            f"{rate:5.0f}/min  left {'?' if left is None else _clock(left):>7}  "
            f"failed {self.failed}  {res.student[:30]:<30}"
        )

    def update(self, res: SubmissionResult, resumed: bool = False) -> None:
        with self.lock:
            self.done += 1
            self.graded += not resumed
            self.failed += res.status in FAILED
            if self.quiet:
                return
            if self.tty:
                self.stream.write("\r" + self.line(res))
                if self.done == self.total:
                    self.stream.write("\n")
            elif self.lines:
                tag = " (resumed)" if resumed else ""
                left = self.eta()
                self.stream.write(
                    f"{self.done}/{self.total} {res.student}: {res.score:.4g}/"
                    f"{res.max_score:.4g} {res.status}{tag}"
                    + (f" (left {_clock(left)}, failed {self.failed})" if left else "")
                    + "\n"
                )
            self.stream.flush()


def summarize(
    results: list[SubmissionResult], elapsed: float, resumed: int = 0
) -> dict[str, float | int]:
    """Counts and mean score of a batch."""
    n = len(results)
    by = {
        s: sum(r.status == s for r in results)
        for s in (OK, CELL_ERRORS, TIMEOUT, CRASHED, INVALID, GRADER_ERROR)
    }
    scores = [r.score for r in results]
    max_score = max((r.max_score for r in results), default=0.0)
    return {
        "submissions": n,
        "graded": n - by[INVALID] - by[GRADER_ERROR],
        "failed_to_run": by[INVALID] + by[GRADER_ERROR],
        "timed_out": by[TIMEOUT],
        "crashed": by[CRASHED],
        "cell_errors": by[CELL_ERRORS],
        "invalid": by[INVALID],
        "grader_errors": by[GRADER_ERROR],
        # files the grader would not read (links, no right to read them): the instructor's
        "refused": sum(bool(getattr(r, "refused", "")) for r in results),
        "resumed": resumed,
        "mean_score": (sum(scores) / n) if n else 0.0,
        "max_score": max_score,
        "seconds": round(elapsed, 3),
        "notebooks_per_min": round((n - resumed) / elapsed * 60, 1)
        if elapsed > 0 and n > resumed
        else 0.0,
    }


def summary_text(s: dict[str, float | int]) -> str:
    return (
        f"graded {s['graded']} of {s['submissions']} (resumed {s['resumed']}); "
        f"failed to run {s['failed_to_run']}; timed out {s['timed_out']}; crashed {s['crashed']}; "
        f"cell errors {s['cell_errors']}; "
        + (
            f"REFUSED {s['refused']} (not notebooks, links or unreadable files: see the notes); "
            if s.get("refused")
            else ""
        )
        + f"mean score {s['mean_score']:.3g}/{s['max_score']:.4g}; "
        f"{s['seconds']:.1f} s ({s['notebooks_per_min']:.0f} notebooks/min)"
    )
