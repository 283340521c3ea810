"""The files each LMS imports: grades, and feedback files in bulk.

Grades (one row per student; ``rows`` are :func:`rikingrade.views.final_grades` rows, and
``missing`` the roster's students with no submission, given 0 by the ``zero`` policy; with
``blank``, the default, they are left out and the LMS keeps what it has):

Canvas       gradebook import: ``Student, ID, SIS User ID, SIS Login ID, Section, <title>``;
             a ``Points Possible`` row; students matched on ID (the Canvas user id), SIS User
             ID or SIS Login ID; ``<title>`` as in the gradebook export (``HW3 (4455)``: the
             id picks the existing assignment; a new title creates one); ``EX`` = excused.
Moodle       assignment "Upload grading worksheet": ``Identifier`` (``Participant N``),
             ``Grade``, ``Last modified (grade)`` (a grade changed in Moodle after it is kept
             unless the upload is told otherwise), ``Feedback comments``; other columns are
             read back unchanged.
Blackboard   Grade Center "Upload": ``Last Name, First Name, Username, <column>`` where the
             column is written as downloaded, ``HW3 [Total Pts: 10 Score] |12345`` (the
             ``|id`` names the existing column; without it a new column is made).
Brightspace  grades import: ``OrgDefinedId, Username, Last Name, First Name, Email,
             <item> Points Grade, End-of-Line Indicator`` with ids written as exported
             (``#123``) and ``#`` in the last column.
Gradescope   the columns of its own grades export: ``First Name, Last Name, SID, Email,
             <assignment>``; a student is the SID and e-mail Gradescope gave (its export's
             row, or ``submission_metadata.yml``), copied as they are.

Feedback in bulk (a zip each):

Canvas       "Re-upload submissions" takes files named as downloaded: it reads the first two
             all-digit ``_`` pieces of a name as the user id and the attachment id of the
             submitted file, so feedback is ``<name>_<user id>_<file id>_<a>-feedback.html``.
Moodle       "Upload multiple feedback files in a zip" reads ``<name>_<participant
             id>_assignsubmission_file_<file>``; a file of a new name becomes a feedback file.
"""

from __future__ import annotations

import csv
import io
import time
import zipfile
from typing import Any

#: A grade left empty (the LMS keeps what it had) or 0, for students with no submission.
MISSING_BLANK = "blank"
MISSING_ZERO = "zero"

MOODLE_COLUMNS = [
    "Identifier",
    "Full name",
    "Email address",
    "Status",
    "Grade",
    "Maximum Grade",
    "Grade can be changed",
    "Last modified (submission)",
    "Last modified (grade)",
    "Feedback comments",
]
BLACKBOARD_COLUMNS = ["Last Name", "First Name", "Username"]
BRIGHTSPACE_COLUMNS = ["OrgDefinedId", "Username", "Last Name", "First Name", "Email"]
EOL = "End-of-Line Indicator"
GRADESCOPE_COLUMNS = ["First Name", "Last Name", "SID", "Email"]


def _cell(text: Any) -> str:
    """A CSV cell a spreadsheet will not run as a formula (CSV injection)."""
    text = str(text)
    return "'" + text if text[:1] in ("=", "+", "-", "@", "\t", "\r") else text


def _num(x: float) -> str:
    return f"{x:.6g}"


def _grade(r: dict[str, Any], missing: str) -> str:
    """The grade cell: the final score, EX (excused), or a missing student's blank or 0."""
    if r.get("final") is None:
        return "0" if missing == MISSING_ZERO else ""
    return "EX" if r.get("excused") else _num(r["final"])


def _first_last(r: dict[str, Any]) -> tuple[str, str]:
    first, last = r.get("first") or "", r.get("last") or ""
    if first or last:
        return first, last
    name = r.get("name") or ""
    if "," in name:
        last, _, first = name.partition(",")
        return first.strip(), last.strip()
    first, _, last = name.rpartition(" ")
    return (first, last) if first else ("", last)


def canvas_csv(
    rows: list[dict], title: str, max_score: float, missing=(), policy: str = MISSING_BLANK
) -> tuple[str, list[str]]:
    """Canvas's gradebook import file for one assignment, and the students left out (no
    Canvas user id, SIS id or login)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\r\n")
    w.writerow(["Student", "ID", "SIS User ID", "SIS Login ID", "Section", title])
    w.writerow(["Points Possible", "", "", "", "", _num(max_score)])
    skipped = []
    for r in [*rows, *missing]:
        canvas_id = r.get("canvas_id") or ""
        if not canvas_id and not r.get("sis_id") and not r.get("login"):
            skipped.append(r.get("student") or r.get("name") or "?")
            continue
        w.writerow(
            [
                _cell(r.get("name") or r.get("student") or ""),
                canvas_id,
                _cell(r.get("sis_id") or ""),
                _cell(r.get("login") or ""),
                _cell(r.get("section") or ""),
                _grade(r, policy),
            ]
        )
    return buf.getvalue(), skipped


def _moodle_time(t: float | None) -> str:
    # Moodle reads it with PHP's strtotime: an unambiguous ISO local time.
    return "-" if not t else time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(t))


def moodle_csv(
    rows: list[dict], max_score: float, missing=(), policy: str = MISSING_BLANK
) -> tuple[str, list[str]]:
    """Moodle's "Upload grading worksheet" file for one assignment, and the students left out
    (no participant id; excused: the worksheet has no excused grade)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(MOODLE_COLUMNS)
    skipped = []
    for r in [*rows, *missing]:
        pid = r.get("moodle_id") or ""
        if r.get("final") is None and policy != MISSING_ZERO:
            continue  # blank: Moodle keeps what it has
        if not pid or r.get("excused"):
            skipped.append(r.get("student") or r.get("name") or "?")
            continue
        w.writerow(
            [
                f"Participant {pid}",
                _cell(r.get("name") or r.get("student") or ""),
                _cell(r.get("email") or ""),
                "Submitted for grading" if r.get("submitted_at") else "No submission",
                _grade(r, policy),
                _num(max_score),
                "Yes",
                _moodle_time(r.get("submitted_at")),
                _moodle_time(r.get("changed_at") or time.time()),
                _cell(r.get("comment") or ""),
            ]
        )
    return buf.getvalue(), skipped


def blackboard_csv(
    rows: list[dict], column: str, missing=(), policy: str = MISSING_BLANK
) -> tuple[str, list[str]]:
    """Blackboard's Grade Center upload file for one column, and the students left out (no
    username). ``column`` is the header as downloaded (``HW3 [Total Pts: 10 Score] |12345``)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\r\n", quoting=csv.QUOTE_ALL)
    w.writerow([*BLACKBOARD_COLUMNS, column])
    skipped = []
    for r in [*rows, *missing]:
        user = r.get("bb_username") or ""
        if not user:
            skipped.append(r.get("student") or r.get("name") or "?")
            continue
        first, last = _first_last(r)
        grade = "" if r.get("excused") else _grade(r, policy)
        w.writerow([_cell(last), _cell(first), _cell(user), grade])
    return buf.getvalue(), skipped


def brightspace_csv(
    rows: list[dict], item: str, missing=(), policy: str = MISSING_BLANK
) -> tuple[str, list[str]]:
    """Brightspace's grades import file for one item, and the students left out (no
    OrgDefinedId or Username from the roster). ``item`` is the grade column's header
    (``HW3 Points Grade``, with any ``<Numeric MaxPoints:..>`` the export had)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\r\n")
    w.writerow([*BRIGHTSPACE_COLUMNS, item, EOL])
    skipped = []
    for r in [*rows, *missing]:
        org, user = r.get("d2l_org_id") or "", r.get("d2l_username") or ""
        if not org and not user:
            skipped.append(r.get("student") or r.get("name") or "?")
            continue
        first, last = _first_last(r)
        grade = "" if r.get("excused") else _grade(r, policy)
        w.writerow([org, user, _cell(last), _cell(first), _cell(r.get("email") or ""), grade, "#"])
    return buf.getvalue(), skipped


def _zip(files: list[tuple[str, bytes]]) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in sorted(files):
            info = zipfile.ZipInfo(name, date_time=(2024, 1, 1, 0, 0, 0))
            info.external_attr = 0o644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
    return buf.getvalue()


def canvas_feedback_name(r: dict[str, Any], exercise: str) -> str:
    """``<name>_<user id>_<file id>_<exercise>-feedback.html``, or '' without both ids."""
    uid, fid = r.get("canvas_id") or "", r.get("canvas_file_id") or ""
    if not uid or not fid:
        return ""
    who = "".join(ch for ch in (r.get("canvas_name") or "") if ch.isalnum())
    if not who or who.isdigit():  # Canvas would read an all-digit name as the user id
        who = "student"
    return f"{who}_{uid}_{fid}_{exercise}-feedback.html"


def moodle_feedback_name(r: dict[str, Any], exercise: str) -> str:
    """``<name>_<participant id>_assignsubmission_file_<exercise>-feedback.html``, or ''."""
    pid = r.get("moodle_id") or ""
    if not pid:
        return ""
    bad = '_/\\:*?"<>|\0'
    who = "".join(" " if ch in bad else ch for ch in (r.get("name") or "Student")).strip()
    return f"{who or 'Student'}_{pid}_assignsubmission_file_{exercise}-feedback.html"


def feedback_zip(
    rows: list[dict], pages: dict[str, bytes], exercise: str, lms: str
) -> tuple[bytes, list[str]]:
    """The feedback zip Canvas's re-upload or Moodle's feedback-files upload takes, and the
    students left out (no id pairing them with their submission). ``pages`` maps each
    student id to their HTML feedback."""
    namer = canvas_feedback_name if lms == "canvas" else moodle_feedback_name
    files, skipped = [], []
    for r in rows:
        name = namer(r, exercise)
        if name and r["student"] in pages:
            files.append((name, pages[r["student"]]))
        else:
            skipped.append(r["student"])
    return _zip(files), skipped


def gradescope_csv(
    rows: list[dict], column: str, missing=(), policy: str = MISSING_BLANK
) -> tuple[str, list[str]]:
    """Grades in the columns of Gradescope's grades export (``column``: the assignment's
    header there), and the students left out (neither SID nor e-mail)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\r\n")
    w.writerow([*GRADESCOPE_COLUMNS, column])
    skipped = []
    for r in [*rows, *missing]:
        sid, email = r.get("sis_id") or "", r.get("email") or ""
        if not sid and not email:
            skipped.append(r.get("student") or r.get("name") or "?")
            continue
        first, last = _first_last(r)
        grade = "" if r.get("excused") else _grade(r, policy)
        w.writerow([_cell(first), _cell(last), _cell(sid), _cell(email), grade])
    return buf.getvalue(), skipped
