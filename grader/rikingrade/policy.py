"""Grading policy: late penalties, extensions and manual overrides, applied to a raw score.

A late rule is ``per_day`` percent of the maximum score for each started day after the due
time plus ``grace_minutes``, at most ``cap`` percent (and never below zero). A student's
extension replaces the due time. An override sets the grade (or excuses the student) with a
reason; it wins over the computed grade. Every step is written into the student's feedback
(:func:`feedback_lines`) and into the gradebook's exports.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from datetime import datetime

#: The time source of a file time that is not when the file was handed in (the class's
#: file times all fall within a minute, or all after the due date: an unzip or a copy
#: that did not keep them). It never makes work late.
UNRELIABLE_TIME = "file modification time, which is not when it was handed in"


class PolicyError(ValueError):
    """A due date, extension or override that cannot be used; the message says why."""


def parse_time(text: str) -> float:
    """Seconds since the epoch from ``2026-11-20``, ``2026-11-20 23:59`` or ISO 8601 (local
    time unless it carries an offset, e.g. ``2026-11-20T23:59+01:00``)."""
    t = str(text).strip()
    try:
        dt = datetime.fromisoformat(t.replace("Z", "+00:00"))
    except ValueError:
        raise PolicyError(
            f"cannot read the time {text!r}: write it as 2026-11-20 23:59 (local time) or "
            "ISO 8601 with an offset"
        ) from None
    if len(t) == 10:  # a date alone: the end of that day
        dt = dt.replace(hour=23, minute=59, second=59)
    return dt.timestamp() if dt.tzinfo else time.mktime(dt.timetuple())


def show_time(t: float | None) -> str:
    return "unknown" if t is None else time.strftime("%Y-%m-%d %H:%M", time.localtime(t))


@dataclass
class Rules:
    """The late rules of an assignment (``due`` None: no late penalty)."""

    due: float | None = None
    per_day: float = 0.0  # percent of the maximum per started day late
    cap: float = 100.0  # percent of the maximum at most
    grace_minutes: float = 0.0

    def __post_init__(self) -> None:
        for name in ("per_day", "cap", "grace_minutes"):
            v = float(getattr(self, name))
            if not math.isfinite(v) or v < 0:
                raise PolicyError(f"{name} must be a number >= 0, got {v!r}")
        if self.cap > 100:
            raise PolicyError(f"cap is a percentage of the maximum score (0-100), got {self.cap}")


@dataclass
class Grade:
    """A student's grade after policy: what every export and the feedback show."""

    raw: float
    max_score: float
    final: float
    excused: bool = False
    late_days: int = 0
    penalty: float = 0.0
    due: float | None = None
    override: str = ""  # "", "score" or "excused"
    notes: list[str] = field(default_factory=list)  # one line each, for the student


def apply(
    raw: float,
    max_score: float,
    submitted_at: float | None,
    time_source: str,
    rules: Rules,
    extension: tuple[float, str] | None = None,
    override: tuple[str, float | None, str] | None = None,
    lms_late: bool | None = None,
) -> Grade:
    """The grade of one submission under ``rules``, an extension and an override.

    Parameters
    ----------
    raw, max_score : float
        Points from the hidden tests, and the maximum.
    submitted_at : float or None
        When it was handed in (seconds since the epoch); None: unknown, never penalised.
    time_source : str
        Where that time came from ("download name", "file modification time", ...).
    extension : (due, reason) or None
    override : (kind, score, reason) or None
        ``kind`` "score" sets the grade to ``score``; "excused" excuses the student.
    lms_late : bool or None
        The LMS's own late mark, where its download gives one and no time (Canvas): not
        late is on time whatever the file's time; late is at least one day late (more when
        the submission time says so). None: the time decides. An extension makes the time
        decide again (the LMS's mark was made against its own due date).
    """
    g = Grade(raw=raw, max_score=max_score, final=raw)
    due = rules.due
    if extension is not None:
        due = extension[0]
        g.notes.append(f"Extension: due {show_time(due)} ({extension[1]}).")
    g.due = due
    if lms_late is not None and extension is None and due is not None:
        trusted = submitted_at if time_source != UNRELIABLE_TIME else None
        _lms_mark(g, raw, max_score, trusted, rules, due, lms_late)
    elif due is not None and time_source == UNRELIABLE_TIME:
        g.notes.append(
            "When you handed it in is not known (the file's time is not it): no late penalty."
        )
    elif due is not None and submitted_at is not None:
        late_s = submitted_at - due - rules.grace_minutes * 60
        if late_s > 0 and rules.per_day > 0:
            g.late_days = math.ceil(late_s / 86400)
            pct = min(rules.cap, rules.per_day * g.late_days)
            g.penalty = min(raw, max_score * pct / 100)
            g.final = raw - g.penalty
            g.notes.append(
                f"Late: submitted {show_time(submitted_at)} (from the {time_source}), due "
                f"{show_time(due)}"
                + (f" with {rules.grace_minutes:g} min grace" if rules.grace_minutes else "")
                + f": {g.late_days} day(s) late, {rules.per_day:g}% per day"
                + (f" (at most {rules.cap:g}%)" if rules.cap < 100 else "")
                + f", -{_pts(g.penalty)} points."
            )
        elif late_s > 0:
            g.late_days = math.ceil(late_s / 86400)
            g.notes.append(
                f"Submitted {show_time(submitted_at)}, after the due time {show_time(due)} "
                "(no late penalty)."
            )
    if override is not None:
        kind, score, reason = override
        g.override = kind
        if kind == "excused":
            g.excused = True
            g.notes.append(f"Excused by your instructor: {reason}")
        else:
            assert score is not None, "a score override carries its score"
            g.final = float(score)
            g.notes.append(
                f"Grade set to {_pts(g.final)}/{_pts(max_score)} by your instructor "
                f"(computed: {_pts(raw - g.penalty)}): {reason}"
            )
    g.final = round(g.final, 6)
    return g


def _lms_mark(
    g: Grade,
    raw: float,
    max_score: float,
    submitted_at: float | None,
    rules: Rules,
    due: float,
    late: bool,
) -> None:
    """The late penalty from the LMS's mark (Canvas's LATE): its download gives no time, so
    a late submission counts the days its file time gives when that time can be trusted
    and is after the due time plus the grace (none when it is within the grace, which the
    LMS does not know), else one day."""
    if not late:
        return
    grace = rules.grace_minutes
    if grace and submitted_at is not None and due < submitted_at <= due + grace * 60:
        g.notes.append(  # the LMS knows no grace: after the due time, as it says, yet on time
            f"Marked late by the LMS, but handed in {show_time(submitted_at)}, within the "
            f"{grace:g} min grace after the due time {show_time(due)}: on time."
        )
        return
    late_s = (submitted_at or 0.0) - due - grace * 60
    g.late_days = math.ceil(late_s / 86400) if submitted_at is not None and late_s > 0 else 1
    if rules.per_day <= 0:
        g.notes.append("Marked late by the LMS (no late penalty).")
        return
    pct = min(rules.cap, rules.per_day * g.late_days)
    g.penalty = min(raw, max_score * pct / 100)
    g.final = raw - g.penalty
    g.notes.append(
        f"Late: marked late by the LMS, due {show_time(due)}: counted {g.late_days} day(s) "
        f"late, {rules.per_day:g}% per day"
        + (f" (at most {rules.cap:g}%)" if rules.cap < 100 else "")
        + f", -{_pts(g.penalty)} points."
    )


def _pts(x: float) -> str:
    return f"{x:.4g}"


def feedback_markdown(g: Grade) -> str:
    """The grade section appended to a student's Markdown feedback ('' when nothing applies)."""
    if not g.notes:
        return ""
    final = "excused" if g.excused else f"{_pts(g.final)} / {_pts(g.max_score)}"
    return "\n".join(["## Grade", "", *[f"- {n}" for n in g.notes], "", f"**Final: {final}**", ""])
