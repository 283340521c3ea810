"""Files exported from the gradebook: every one is a view, rewritten whole after each run.

In the output folder, for the assignment graded (``<a>`` its exercise name)::

    grades.csv            every student's grade that counts: status, final score, max, per-test
                          points, late penalty, override, attempt time, notebook, sha256, seed
    summary.json          the batch summary and the class statistics
    canvas-<a>.csv        Canvas gradebook import (students with a Canvas or SIS id)
    moodle-<a>.csv        Moodle "upload grading worksheet" (students with a participant id)
    report/<a>.html/.png/.json           the class report of the newest run
    report/<a>-run<N>.html/.png/.json    the class report as it was after run N
    results/<id>.json     Gradescope-format results per student
    feedback/<id>.md/.html               what the student sees, with the grade section

``rikin-grade export`` rewrites them from the gradebook alone (e.g. after a kill).
"""

from __future__ import annotations

import csv
import html
import io
import json
from pathlib import Path
from typing import Any

from . import lms
from .gradebook import Gradebook
from .notebook import printable
from .outputs import atomic_write, feedback_html, feedback_markdown, gradescope_json
from .policy import Grade, Rules, apply
from .policy import feedback_markdown as grade_markdown
from .report import SubmissionResult

EXCUSED = "excused"


def rules_of(gb: Gradebook, assignment: str) -> Rules:
    p = gb.policy(assignment)
    if p is None:
        return Rules()
    return Rules(p["due"], p["per_day"], p["cap"], p["grace_minutes"])


def final_grades(gb: Gradebook, assignment: str) -> list[dict[str, Any]]:
    """One row per student who has a grade for ``assignment``, sorted by id."""
    rules = rules_of(gb, assignment)
    ext = gb.extensions(assignment)
    ovr = gb.overrides(assignment)
    students = gb.students()
    pol = gb.policy(assignment)
    rows = []
    for cur in gb.current(assignment):
        sid = cur["student"]
        res = sane(SubmissionResult.from_dict(json.loads(cur["result"])))
        e = ext.get(sid)
        o = ovr.get(sid)
        g = apply(
            res.score,
            res.max_score,
            cur["submitted_at"],
            cur["time_source"] or "file modification time",
            rules,
            (e["due"], e["reason"]) if e else None,
            (o["kind"], o["score"], o["reason"]) if o else None,
        )
        st = students.get(sid)
        # When this grade last changed (Moodle keeps a grade edited there after this).
        changed = max([cur["graded_at"]] + [r["created_at"] for r in (e, o, pol) if r])
        rows.append(
            {
                "student": sid,
                "name": st["name"] if st else "",
                "email": st["email"] if st else "",
                "sis_id": st["sis_id"] if st else "",
                "login": st["login"] if st else "",
                "section": st["section"] if st else "",
                "canvas_id": st["canvas_id"] if st else "",
                "moodle_id": st["moodle_id"] if st else "",
                "status": res.status,
                "raw": res.score,
                "final": g.final,
                "max_score": res.max_score,
                "excused": g.excused,
                "grade": g,
                "result": res,
                "run_id": cur["run_id"],
                "seed": cur["seed"],
                "submitted_at": cur["submitted_at"],
                "lms_late": bool(cur["lms_late"]),
                "changed_at": changed,
                "comment": _comment(res, g),
            }
        )
    return rows


def _comment(res: SubmissionResult, g: Grade) -> str:
    fails = [t.name for t in res.tests if t.fraction < 1]
    head = f"{res.score:.4g}/{res.max_score:.4g} from the autograder"
    head += f" ({res.status})" if res.status != "ok" else ""
    head += "; not full marks: " + ", ".join(fails) if fails else "; every test passed"
    return " ".join([head + "."] + g.notes)


def _cell(text: str) -> str:
    return lms._cell(text)


def grades_csv(rows: list[dict[str, Any]], test_names: list[str]) -> str:
    """grades.csv: one row per student, the final score and every part of how it was made."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        [
            "student",
            "status",
            "score",
            "max_score",
            *test_names,
            "raw_score",
            "late_days",
            "late_penalty",
            "override",
            "submitted_at",
            "reason",
            "notebook",
            "sha256",
            "seed",
            "run",
        ]
    )
    for r in rows:
        res: SubmissionResult = r["result"]
        g: Grade = r["grade"]
        pts = {t.name: t.points for t in res.tests}
        w.writerow(
            [
                _cell(r["student"]),
                EXCUSED if g.excused else res.status,
                "" if g.excused else f"{g.final:.4g}",
                f"{res.max_score:.4g}",
                *[f"{pts.get(n, 0.0):.4g}" for n in test_names],
                f"{res.score:.4g}",
                g.late_days,
                f"{g.penalty:.4g}",
                g.override,
                _iso(r["submitted_at"]),
                _cell(_one_line(res.reason, 300)),
                _cell(res.path),
                res.sha256,
                r["seed"],
                r["run_id"],
            ]
        )
    return buf.getvalue()


def _iso(t: float | None) -> str:
    import time

    return "" if t is None else time.strftime("%Y-%m-%dT%H:%M:%S%z", time.localtime(t))


def _one_line(text: str, limit: int = 600) -> str:
    t = " ".join(str(text).split())
    return t if len(t) <= limit else t[: limit - 1] + "…"


def sane(res: SubmissionResult) -> SubmissionResult:
    """``res`` with every text writable as UTF-8 (a lone surrogate from a file name or a
    student's message becomes ``\\udcff``), so one odd byte cannot stop the class's files."""

    def clean(v: Any) -> Any:
        if isinstance(v, str):
            return printable(v)
        if isinstance(v, list):
            return [clean(x) for x in v]
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        return v

    return SubmissionResult.from_dict(clean(res.to_dict()))


def write_student(out: Path, res: SubmissionResult, exercise: str, g: Grade | None) -> None:
    """One student's results.json and feedback, with the grade section when policy applied."""
    res = sane(res)
    gs = gradescope_json(res, exercise)
    md = feedback_markdown(res, exercise)
    page = feedback_html(res, exercise)
    if g is not None and g.notes:
        gs["score"] = 0.0 if g.excused else round(g.final, 6)
        gs["output"] += "\n\n" + "\n".join(html.escape(n, quote=False) for n in g.notes)
        md += "\n" + grade_markdown(g)
        items = "".join(f"<li>{html.escape(n)}</li>" for n in g.notes)
        final = "excused" if g.excused else f"{g.final:.4g} / {g.max_score:.4g}"
        page = page.replace(
            "</body>",
            f"<h2>Grade</h2>\n<ul>{items}</ul>\n<p><strong>Final: {html.escape(final)}"
            "</strong></p>\n</body>",
        )
    atomic_write(out / "results" / f"{res.student}.json", json.dumps(gs, indent=2))
    atomic_write(out / "feedback" / f"{res.student}.md", md)
    atomic_write(out / "feedback" / f"{res.student}.html", page)


def export(
    gb: Gradebook,
    assignment: str,
    exercise: str,
    out: Path,
    run_id: int | None = None,
    summary: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Rewrite every view of ``assignment`` in ``out`` from the gradebook.

    Every student's feedback is rewritten (a policy change can change anyone's grade).
    Returns the paths written and the students each LMS file left out.
    """
    from .classreport import write_report

    out = Path(out)
    rows = final_grades(gb, assignment)
    tests = [name for name, _ in gb.tests(assignment)]
    max_score = gb.max_score(assignment)
    atomic_write(out / "grades.csv", grades_csv(rows, tests), fsync=True)
    canvas, canvas_skipped = lms.canvas_csv(rows, exercise, max_score)
    moodle, moodle_skipped = lms.moodle_csv(rows, max_score)
    info: dict[str, Any] = {"grades": str(out / "grades.csv")}
    if len(canvas_skipped) < len(rows):
        atomic_write(out / f"canvas-{exercise}.csv", canvas, fsync=True)
        info["canvas"] = str(out / f"canvas-{exercise}.csv")
        info["canvas_skipped"] = canvas_skipped
    if len(moodle_skipped) < len(rows):
        atomic_write(out / f"moodle-{exercise}.csv", moodle, fsync=True)
        info["moodle"] = str(out / f"moodle-{exercise}.csv")
        info["moodle_skipped"] = moodle_skipped
    for r in rows:
        write_student(out, r["result"], exercise, r["grade"])
    stats = write_report(gb, assignment, exercise, out, rows, run_id)
    info["report"] = stats["paths"]
    full = dict(summary or {})
    full["class"] = {k: v for k, v in stats.items() if k != "paths"}
    full["students_in_gradebook"] = len(rows)
    atomic_write(out / "summary.json", json.dumps(full, indent=2))
    return info
