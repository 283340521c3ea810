"""What grading one submission produced: per-test results, per-cell notes, a status."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

#: Submission statuses, from best to worst.
OK = "ok"  # every cell ran, nothing timed out or crashed
CELL_ERRORS = "cell-errors"  # graded; some cells raised (later cells still ran)
TIMEOUT = "timeout"  # graded; a cell or a call hit its wall-clock limit
CRASHED = "crashed"  # graded; the notebook's process died at least once
INVALID = "invalid"  # not a readable notebook: scored 0, with the reason
GRADER_ERROR = "grader-error"  # a hidden test or the sandbox failed: the instructor must look

STATUSES = (OK, CELL_ERRORS, TIMEOUT, CRASHED, INVALID, GRADER_ERROR)


@dataclass
class CellReport:
    """What happened in one code cell (numbered from 1 among code cells)."""

    number: int
    status: str  # "ok" | "error" | "timeout" | "crashed"
    error_type: str = ""
    message: str = ""
    traceback: str = ""
    output: str = ""
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0


@dataclass
class TestResult:
    """One hidden test's score for one submission."""

    name: str
    weight: float
    fraction: float
    feedback: str
    detail: str = ""
    timed_out: bool = False
    crashed: bool = False
    grader_error: bool = False

    @property
    def points(self) -> float:
        return self.weight * self.fraction

    @property
    def verdict(self) -> str:
        if self.fraction >= 1.0:
            return "pass"
        return "partial" if self.fraction > 0 else "fail"


@dataclass
class SubmissionResult:
    """Everything the outputs are written from (also the resume record)."""

    student: str
    path: str
    sha256: str
    status: str
    reason: str = ""
    tests: list[TestResult] = field(default_factory=list)
    cells: list[CellReport] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)  # notebook-level notes for the student
    max_score: float = 0.0
    elapsed: float = 0.0
    key: str = ""  # grader version + assignment + settings; resume only when equal
    refused: str = ""  # why the grader would not read the file (a link, no right to it)
    language: str = "en"  # the notebook's: its feedback is written in it (rikingrade.i18n)

    @property
    def score(self) -> float:
        return float(sum(t.points for t in self.tests))

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["score"] = self.score
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> SubmissionResult:
        d = dict(d)
        d.pop("score", None)
        d["tests"] = [TestResult(**t) for t in d.get("tests", [])]
        d["cells"] = [CellReport(**c) for c in d.get("cells", [])]
        return cls(**d)
