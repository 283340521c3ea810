"""Files exported from the gradebook: every one is a view, rewritten whole after each run.

In the output folder, for the assignment graded (``<a>`` its exercise name)::

    grades.csv            every student's grade that counts: status, final score, max, per-test
                          points, late penalty, override, attempt time, notebook, sha256, seed,
                          and the student's name, section and roster match
    summary.json          the batch summary, the class statistics, who is missing, who is not
                          on the roster, who could not be told apart, what each LMS file left out
    canvas-<a>.csv        Canvas gradebook import          } for the LMSs the class uses (its
    moodle-<a>.csv        Moodle grading worksheet upload  } download names and roster): see
    blackboard-<a>.csv    Blackboard Grade Center upload   } :mod:`rikingrade.lmsfiles`
    brightspace-<a>.csv   Brightspace grades import        }
    gradescope-<a>.csv    Gradescope grades (its export)   }
    canvas-feedback-<a>.zip, moodle-feedback-<a>.zip     feedback files for their bulk upload
    report/<a>.html/.png/.json           the class report of the newest run
    report/<a>-run<N>.html/.png/.json    the class report as it was after run N
    results/<id>.json     Gradescope-format results per student; ``extra_data.rikin`` holds
                          what the gradebook knows of that grade (``rikin-grade repair``
                          rebuilds a gradebook from these files), control characters
                          removed, as compressed base64 data: no student text in it reads
                          as text
    feedback/<id>.md/.html               what the student sees: the final score first

``rikin-grade export`` rewrites them from the gradebook alone (e.g. after a kill).
"""

from __future__ import annotations

import base64
import binascii
import csv
import html
import io
import json
import time
import zlib
from pathlib import Path
from typing import Any

from . import lms, lmsfiles
from .classreport import write_report
from .gradebook import Gradebook
from .outputs import atomic_write, feedback_html, feedback_markdown, gradescope_json
from .policy import Grade, Rules, apply
from .policy import feedback_markdown as grade_markdown
from .report import SubmissionResult
from .roster import LMS_OF, RosterEntry
from .safetext import printable

EXCUSED = "excused"
#: What ``extra_data.rikin`` of a results file holds (see :mod:`rikingrade.repair`).
RECORD_VERSION = 2
RECORD_ENCODING = "json+zlib+base64"
LMS_NAMES = ("canvas", "moodle", "blackboard", "brightspace", "gradescope")


def rules_of(gb: Gradebook, assignment: str) -> Rules:
    p = gb.policy(assignment)
    if p is None:
        return Rules()
    return Rules(p["due"], p["per_day"], p["cap"], p["grace_minutes"])


def roster_rows(gb: Gradebook, assignment: str) -> dict[str, dict[str, Any]]:
    """The roster in force for ``assignment``: row key -> the row (every id it gave)."""
    return dict(gb.roster(assignment)[1])


def _lms_ids(st, entry: dict[str, Any], path: str) -> dict[str, str]:
    """Every LMS id known for a student: the download's, then the roster row's."""
    own = lms.parse_file(Path(path).name) if path else None
    canvas = own if own is not None and own.lms == lms.CANVAS else None
    student_lms = st["lms"] if st else ""
    return {
        "canvas_id": (st["canvas_id"] if st else "") or entry.get("canvas_id", ""),
        "canvas_file_id": canvas.file_id if canvas else "",
        "canvas_name": canvas.name if canvas else "",
        "moodle_id": (st["moodle_id"] if st else "") or entry.get("moodle_id", ""),
        "bb_username": (st["lms_id"] if student_lms == lms.BLACKBOARD else "")
        or (entry.get("username", "").lstrip("#") if entry.get("kind") == "blackboard" else ""),
        "d2l_org_id": entry.get("org_id", ""),
        "d2l_username": entry.get("username", "") if entry.get("kind") == "brightspace" else "",
        "first": entry.get("first", ""),
        "last": entry.get("last", ""),
    }


def final_grades(
    gb: Gradebook, assignment: str, only: set[str] | None = None
) -> list[dict[str, Any]]:
    """One row per student who has a grade for ``assignment`` (or those in ``only``),
    sorted by id."""
    rules = rules_of(gb, assignment)
    one = next(iter(only)) if only is not None and len(only) == 1 else None
    ext = gb.extensions(assignment, one)
    ovr = gb.overrides(assignment, one)
    students = gb.students(one)
    if one is not None:  # one student (after each result): their roster row only
        key = students[one]["roster_key"] if one in students else ""
        roster = dict(gb.roster(assignment, key)[1]) if key else {}
        has_roster = bool(roster) or bool(gb.roster_kind(assignment))
    else:
        roster = roster_rows(gb, assignment)
        has_roster = bool(roster)
    pol = gb.policy(assignment)
    rows = []
    for cur in gb.current(assignment, one):
        sid = cur["student"]
        if only is not None and sid not in only:
            continue
        res = sane(SubmissionResult.from_dict(json.loads(cur["result"])))
        e, o, st = ext.get(sid), ovr.get(sid), students.get(sid)
        canvas = st is not None and st["lms"] == "canvas"
        g = apply(
            res.score,
            res.max_score,
            cur["submitted_at"],
            cur["time_source"] or "file modification time",
            rules,
            (e["due"], e["reason"]) if e else None,
            (o["kind"], o["score"], o["reason"]) if o else None,
            lms_late=bool(cur["lms_late"]) if canvas else None,
        )
        key = st["roster_key"] if st else ""
        entry = roster.get(key, {})
        # When this grade last changed (Moodle keeps a grade edited there after this).
        changed = max([cur["graded_at"]] + [r["created_at"] for r in (e, o, pol) if r])
        rows.append(
            {
                "student": sid,
                "name": (st["name"] if st else "") or entry.get("name", ""),
                "email": (st["email"] if st else "") or entry.get("email", ""),
                "sis_id": (st["sis_id"] if st else "") or entry.get("sis_id", ""),
                "login": (st["login"] if st else "") or entry.get("login", ""),
                "section": (st["section"] if st else "") or entry.get("section", ""),
                **_lms_ids(st, entry, cur["path"]),
                "lms": st["lms"] if st else "",
                "roster_key": key,
                "on_roster": bool(entry) or not has_roster,
                "status": res.status,
                "raw": res.score,
                "final": g.final,
                "max_score": res.max_score,
                "excused": g.excused,
                "grade": g,
                "result": res,
                "run_id": cur["run_id"],
                "seed": cur["seed"],
                "key": cur["key"],
                "graded_at": cur["graded_at"],
                "sha256": cur["sha256"],
                "path": cur["path"],
                "submitted_at": cur["submitted_at"],
                "time_source": cur["time_source"],
                "lms_late": bool(cur["lms_late"]),
                "changed_at": changed,
                "comment": _comment(res, g),
                "records": {"policy": pol, "extension": e, "override": o, "student": st},
            }
        )
    return rows


def missing_rows(gb: Gradebook, assignment: str, rows: list[dict[str, Any]]) -> dict[str, list]:
    """The roster's students without a grade: ``missing`` (no submission) and ``ambiguous``
    (a submission may be theirs, but several roster rows share its name)."""
    roster = roster_rows(gb, assignment)
    matched = {r["roster_key"] for r in rows}
    unsure = {k.removeprefix("ambiguous:") for k in matched if k.startswith("ambiguous:")}
    out: dict[str, list] = {"missing": [], "ambiguous": []}
    for key, entry in roster.items():
        if key in matched:
            continue
        fields = {k: v for k, v in entry.items() if k in RosterEntry.__dataclass_fields__}
        e = RosterEntry(**fields)

        who = {
            "student": "",
            "name": e.name,
            "email": e.email,
            "sis_id": e.sis_id,
            "login": e.login,
            "section": e.section,
            "canvas_id": e.canvas_id,
            "moodle_id": e.moodle_id,
            "bb_username": e.username.lstrip("#") if e.kind == "blackboard" else "",
            "d2l_org_id": e.org_id,
            "d2l_username": e.username if e.kind == "brightspace" else "",
            "first": e.first,
            "last": e.last,
            "final": None,
            "roster_key": key,
        }
        out["ambiguous" if lms.person_key(e.name) in unsure else "missing"].append(who)
    return out


def _comment(res: SubmissionResult, g: Grade) -> str:
    fails = [t.name for t in res.tests if t.fraction < 1]
    final = "excused" if g.excused else f"{g.final:.4g}/{res.max_score:.4g}"
    head = f"Final score {final}; {res.score:.4g}/{res.max_score:.4g} from the autograder"
    head += f" ({res.status})" if res.status != "ok" else ""
    head += "; not full marks: " + ", ".join(fails) if fails else "; every test passed"
    return " ".join([head + "."] + g.notes)


def _cell(text: str) -> str:
    return lmsfiles._cell(printable(str(text)))


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
            "name",
            "section",
            "roster",
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
                _cell(r.get("name") or ""),
                _cell(r.get("section") or ""),
                _roster_word(r),
            ]
        )
    return buf.getvalue()


def _roster_word(r: dict[str, Any]) -> str:
    key = r.get("roster_key") or ""
    if key.startswith("ambiguous:"):
        return "ambiguous"
    if key == "absent":
        return "not on roster"
    return "matched" if key else ""


def _iso(t: float | None) -> str:
    return "" if t is None else time.strftime("%Y-%m-%dT%H:%M:%S%z", time.localtime(t))


def _one_line(text: str, limit: int = 600) -> str:
    t = " ".join(str(text).split())
    return t if len(t) <= limit else t[: limit - 1] + "…"


def sane(res: SubmissionResult) -> SubmissionResult:
    """``res`` with every text writable as UTF-8 (a lone surrogate from a file name or a
    student's message becomes ``\\udcff``) and free of control characters (a terminal
    escape in a student's message), so one odd byte cannot stop or garble the class's
    files (see :func:`rikingrade.safetext.printable`)."""

    return SubmissionResult.from_dict(_printable_all(res.to_dict()))


def _printable_all(v: Any) -> Any:
    """``v`` (JSON-like data) with :func:`printable` applied to every string in it."""
    if isinstance(v, str):
        return printable(v)
    if isinstance(v, list):
        return [_printable_all(x) for x in v]
    if isinstance(v, dict):
        return {k: _printable_all(x) for k, x in v.items()}
    return v


def encode_record(record: dict[str, Any]) -> dict[str, Any]:
    """The gradebook's record of a grade as ``extra_data.rikin`` stores it.

    Its strings pass :func:`printable` as every other output does, and the whole is
    compressed JSON in base64: the results file is read by people and by LMS tools, and a
    student's text (a ``<script>`` in a message, a printed "All tests passed") must not read
    as the grader's there. :func:`decode_record` reads it back.
    """
    raw = json.dumps(_printable_all(record), sort_keys=True).encode("utf-8")
    data = base64.b64encode(zlib.compress(raw, 6)).decode("ascii")
    return {"version": RECORD_VERSION, "encoding": RECORD_ENCODING, "data": data}


def decode_record(stored: Any) -> dict[str, Any] | None:
    """The record :func:`encode_record` stored, or None (not one, another version, damaged)."""
    if not isinstance(stored, dict) or stored.get("version") != RECORD_VERSION:
        return None
    if stored.get("encoding") != RECORD_ENCODING or not isinstance(stored.get("data"), str):
        return None
    try:
        rec = json.loads(zlib.decompress(base64.b64decode(stored["data"], validate=True)))
    except (binascii.Error, zlib.error, ValueError):
        return None
    return rec if isinstance(rec, dict) else None


def _final_line(g: Grade | None, res: SubmissionResult) -> str:
    """The header line of the feedback: the final score, then how it was made."""
    if g is None or not g.notes:
        return ""
    if g.excused:
        return "Final: excused"
    parts = [f"autograder {res.score:.4g}"]
    if g.penalty:
        parts.append(f"late -{g.penalty:.4g}")
    if g.override:
        parts.append("set by your instructor")
    return f"Final score: {g.final:.4g} / {g.max_score:.4g} ({', '.join(parts)})"


def _record(row: dict[str, Any], gb_id: str, assignment: str, tests) -> dict[str, Any]:
    """What the gradebook knows of this grade, to rebuild it (test details left out: the
    record holds no more than the feedback shows; :func:`encode_record` stores it)."""
    res = row["result"].to_dict()
    for t in res["tests"]:
        t["detail"] = ""

    def plain(r, names):
        return {n: r[n] for n in names} if r is not None else None

    recs = row["records"]
    st = recs["student"]
    return {
        "version": RECORD_VERSION,
        "gradebook_id": gb_id,
        "assignment": assignment,
        "max_score": row["max_score"],
        "tests": [list(t) for t in tests],
        "student": dict(st) if st is not None else {"id": row["student"]},
        "submission": {
            "sha256": row["sha256"],
            "path": row["path"],
            "submitted_at": row["submitted_at"],
            "time_source": row["time_source"],
            "lms_late": row["lms_late"],
        },
        "result": res,
        "key": row["key"],
        "seed": row["seed"],
        "graded_at": row["graded_at"],
        "policy": plain(recs["policy"], ("due", "per_day", "cap", "grace_minutes", "created_at")),
        "extension": plain(recs["extension"], ("due", "reason", "created_at")),
        "override": plain(recs["override"], ("kind", "score", "reason", "created_at")),
    }


def student_pages(
    res: SubmissionResult, g: Grade | None, exercise: str, who: str = ""
) -> tuple[dict, str, str]:
    """One student's Gradescope results, Markdown and HTML feedback (final score first)."""
    final = _final_line(g, res)
    who = who or res.student
    gs = gradescope_json(res, exercise)
    md = feedback_markdown(res, exercise, final=final, who=who)
    page = feedback_html(res, exercise, final=final, who=who)
    if g is not None and g.notes:
        gs["score"] = 0.0 if g.excused else round(g.final, 6)
        gs["output"] += "\n\n" + "\n".join(html.escape(n, quote=False) for n in g.notes)
        md += "\n" + grade_markdown(g)
        items = "".join(f"<li>{html.escape(n)}</li>" for n in g.notes)
        last = "excused" if g.excused else f"{g.final:.4g} / {g.max_score:.4g}"
        page = page.replace(
            "</body>",
            f"<h2>Grade</h2>\n<ul>{items}</ul>\n<p><strong>Final: {html.escape(last)}"
            "</strong></p>\n</body>",
        )
    return gs, md, page


def write_student(
    out: Path,
    res: SubmissionResult,
    exercise: str,
    g: Grade | None = None,
    record: dict[str, Any] | None = None,
    who: str = "",
) -> None:
    """One student's results.json and feedback, with the grade section when policy applied
    and (``record``) what rebuilds their grade in the gradebook."""
    res = sane(res)
    gs, md, page = student_pages(res, g, exercise, who)
    if record is not None:
        gs.setdefault("extra_data", {})["rikin"] = encode_record(record)
    atomic_write(out / "results" / f"{res.student}.json", json.dumps(gs, indent=2))
    atomic_write(out / "feedback" / f"{res.student}.md", md)
    atomic_write(out / "feedback" / f"{res.student}.html", page)


def student_view(
    gb: Gradebook, assignment: str, student: str
) -> list[tuple[SubmissionResult, Grade, dict[str, Any], str]]:
    """What :func:`write_student` writes for one student, from the gradebook as it is now:
    (result, grade, record, name), or nothing if they have no grade."""
    rows = final_grades(gb, assignment, {student})
    tests = gb.tests(assignment)
    gb_id = gb.gradebook_id()
    return [
        (r["result"], r["grade"], _record(r, gb_id, assignment, tests), r["name"]) for r in rows
    ]


def write_one(gb: Gradebook, assignment: str, exercise: str, out: Path, student: str) -> None:
    """Rewrite one student's results and feedback from the gradebook (their grade as it is
    now, with the record that rebuilds it)."""
    for res, g, record, who in student_view(gb, assignment, student):
        write_student(Path(out), res, exercise, g, record, who)


def _lms_files(gb, assignment, exercise, out, rows, info) -> dict[str, list]:
    """The LMS import files and feedback zips; returns who each left out."""
    kind, roster = gb.roster(assignment)

    class_lms = {LMS_OF.get(kind, "")} | {r["lms"] for r in rows}
    withdrawn = [r["student"] for r in rows if roster and r["roster_key"] in ("", "absent")]
    keep = [r for r in rows if not roster or r["on_roster"] or _own_id(r)]
    keep = [r for r in keep if r["student"] not in withdrawn]
    gone = missing_rows(gb, assignment, rows) if roster else {"missing": [], "ambiguous": []}
    policy = gb.setting(assignment, "missing", lmsfiles.MISSING_BLANK) or "blank"
    # blank: a missing student is left out of the file (the LMS keeps what it has)
    zeros = gone["missing"] if policy == lmsfiles.MISSING_ZERO else []
    column = gb.setting(assignment, "lms_column", "") or ""
    max_score = gb.max_score(assignment)
    made = {
        "canvas": lambda: lmsfiles.canvas_csv(keep, column or exercise, max_score, zeros, policy),
        "moodle": lambda: lmsfiles.moodle_csv(keep, max_score, zeros, policy),
        "blackboard": lambda: lmsfiles.blackboard_csv(
            keep, column or f"{exercise} [Total Pts: {max_score:g} Score]", zeros, policy
        ),
        "brightspace": lambda: lmsfiles.brightspace_csv(
            keep,
            column or f"{exercise} Points Grade <Numeric MaxPoints:{max_score:g}>",
            zeros,
            policy,
        ),
        "gradescope": lambda: lmsfiles.gradescope_csv(keep, column or exercise, zeros, policy),
    }
    left: dict[str, list] = {"not_on_roster": withdrawn, **gone}
    for name in LMS_NAMES:
        text, skipped = made[name]()
        wanted = name in class_lms or (name in ("canvas", "moodle") and not class_lms - {""})
        head = 2 if name == "canvas" else 1  # Canvas: the header and Points Possible
        if not wanted or len(list(csv.reader(io.StringIO(text)))) <= head:
            continue
        path = out / f"{name}-{exercise}.csv"
        atomic_write(path, text, fsync=True)
        info[name], info[f"{name}_skipped"] = str(path), skipped
    return left


def _own_id(r: dict[str, Any]) -> bool:
    """A student the roster cannot tell apart, who has their own LMS id from the download
    (their grade can go back by it)."""
    return (r.get("roster_key") or "").startswith("ambiguous:") and bool(
        r.get("canvas_id") or r.get("moodle_id") or r.get("bb_username")
    )


def _feedback_zips(out: Path, exercise: str, rows, pages, info) -> None:
    for name in ("canvas", "moodle"):
        if name not in info:
            continue
        data, skipped = lmsfiles.feedback_zip(rows, pages, exercise, name)
        if len(skipped) < len(rows):
            path = out / f"{name}-feedback-{exercise}.zip"
            atomic_write(path, data, fsync=True)
            info[f"{name}_feedback"], info[f"{name}_feedback_skipped"] = str(path), skipped


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
    Returns the paths written, what each LMS file left out, and the roster's lists
    (``missing``, ``not_on_roster``, ``ambiguous``).
    """
    out = Path(out)
    rows = final_grades(gb, assignment)
    tests = gb.tests(assignment)
    atomic_write(out / "grades.csv", grades_csv(rows, [n for n, _ in tests]), fsync=True)
    info: dict[str, Any] = {"grades": str(out / "grades.csv")}
    left = _lms_files(gb, assignment, exercise, out, rows, info)
    info.update(left)
    gb_id = gb.gradebook_id()
    pages = {}
    for r in rows:
        record = _record(r, gb_id, assignment, tests)
        write_student(out, r["result"], exercise, r["grade"], record, r["name"])
        pages[r["student"]] = (out / "feedback" / f"{r['student']}.html").read_bytes()
    _feedback_zips(out, exercise, rows, pages, info)
    stats = write_report(gb, assignment, exercise, out, rows, run_id, left)
    info["report"] = stats["paths"]
    full = dict(summary or {})
    full["class"] = {k: v for k, v in stats.items() if k != "paths"}
    full["students_in_gradebook"] = len(rows)
    full["roster"] = {
        "not_on_roster": left["not_on_roster"],
        "missing": [w.get("name") or "" for w in left["missing"]],
        "ambiguous": [w.get("name") or "" for w in left["ambiguous"]],
    }
    full["lms_files"] = {
        k: info[k] for k in info if k.split("_")[0] in LMS_NAMES and not k.endswith("skipped")
    }
    full["lms_left_out"] = {k: info[k] for k in info if k.endswith("skipped")}
    atomic_write(out / "summary.json", json.dumps(full, indent=2))
    return info
