"""A progress bar for terminals and the end-of-batch summary (standard library only)."""

from __future__ import annotations

import sys
import threading
import time
from typing import TextIO

from .report import CELL_ERRORS, CRASHED, GRADER_ERROR, INVALID, OK, TIMEOUT, SubmissionResult


class Progress:
    """``[#####.....] 37/200  12.3/s  alice`` on a TTY; one line per submission otherwise."""

    def __init__(
        self,
        total: int,
        enabled: bool | None = None,
        stream: TextIO | None = None,
        quiet: bool = False,
    ) -> None:
        self.total = total
        self.done = 0
        self.stream = stream or sys.stderr
        isatty = self.stream.isatty()
        self.tty = isatty and enabled is not False
        self.lines = enabled is True and not isatty
        self.quiet = quiet
        self.t0 = time.monotonic()
        self.lock = threading.Lock()

    def update(self, res: SubmissionResult, resumed: bool = False) -> None:
        with self.lock:
            self.done += 1
            if self.quiet:
                return
            if self.tty:
                width = 30
                filled = int(width * self.done / max(1, self.total))
                rate = self.done / max(1e-9, time.monotonic() - self.t0) * 60
                line = (
                    f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
                    f"{rate:6.0f} nb/min  {res.student[:30]:<30}"
                )
                self.stream.write(line)
                if self.done == self.total:
                    self.stream.write("\n")
            elif self.lines:
                tag = " (resumed)" if resumed else ""
                self.stream.write(
                    f"{self.done}/{self.total} {res.student}: {res.score:.4g}/"
                    f"{res.max_score:.4g} {res.status}{tag}\n"
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
            f"REFUSED {s['refused']} (links or unreadable files: see the notes); "
            if s.get("refused")
            else ""
        )
        + f"mean score {s['mean_score']:.3g}/{s['max_score']:.4g}; "
        f"{s['seconds']:.1f} s ({s['notebooks_per_min']:.0f} notebooks/min)"
    )
