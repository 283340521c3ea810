"""Learning-management systems: the names their downloads give files, and the files they import.

Download names (each parsed into who submitted, the LMS's own id for them, and when)::

    Canvas       smithjohn_12345_67890_scara.ipynb        sortable name, user id, file id
                 smithjohn_late_12345_67890_scara-1.ipynb  late; "-1" is a re-upload
    Moodle       Jane Doe_12345_assignsubmission_file_/scara.ipynb   (folder per student)
                 Jane Doe_12345_assignsubmission_file_scara.ipynb    (flat)
                 12345 is the participant id the grading worksheet calls "Participant 12345"
    Blackboard   HW 3_jdoe_attempt_2026-11-20-23-10-05_scara.ipynb   username, attempt time
    Brightspace  123-456 - Jane Doe - Nov 20, 2026 1110 PM - scara.ipynb (or a folder without
                 the last part): submission and user ids, name, submission time
    nbgrader     submitted/<student>/<assignment>/scara.ipynb (+ timestamp.txt)

Imports written from the gradebook (:func:`canvas_csv`, :func:`moodle_csv`):

* Canvas's gradebook import reads a header ``Student, ID, SIS User ID, SIS Login ID,
  Section`` followed by one column per assignment (``title`` or ``title (id)``; a new title
  creates the assignment) and matches students on ID (the Canvas user id of the download
  names), SIS User ID or SIS Login ID; a first data row starting ``Points Possible`` gives
  the maximum; ``EX`` marks a grade excused.
* Moodle's assignment "Upload grading worksheet" reads the columns ``Identifier``
  (``Participant <id>``, the id of the download names), ``Grade`` and ``Last modified
  (grade)`` (a grade changed in Moodle after that time is not overwritten unless the import
  is told to ignore it), plus ``Feedback comments`` when that feedback type is on; the other
  worksheet columns are read back unchanged.
"""

from __future__ import annotations

import csv
import io
import re
import time
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path

CANVAS = "canvas"
MOODLE = "moodle"
BLACKBOARD = "blackboard"
BRIGHTSPACE = "brightspace"
NBGRADER = "nbgrader"
FOLDER = "folder"  # a folder per student, id = folder name
FILE = "file"  # a loose notebook, id = file name

_CANVAS = re.compile(
    r"^(?P<name>[^\W_]+)_(?:(?P<late>late|LATE)_)?(?P<uid>\d+)_(?P<fid>\d+)_"
    r"(?P<orig>.+?)(?:-(?P<n>\d+))?(?P<ext>\.ipynb)$"
)
_MOODLE_DIR = re.compile(r"^(?P<name>.+?)_(?P<uid>\d+)_assignsubmission_(?P<plugin>[a-z]+)_?$")
_MOODLE_FILE = re.compile(
    r"^(?P<name>.+?)_(?P<uid>\d+)_assignsubmission_(?P<plugin>[a-z]+)_(?P<orig>.+)$"
)
_BLACKBOARD = re.compile(
    r"^(?P<assignment>.+)_(?P<uid>[^_]+)_attempt_"
    r"(?P<ts>\d{4}-\d{2}-\d{2}-\d{2}-\d{2}-\d{2})(?:_(?P<orig>.+))?$"
)
_BRIGHTSPACE = re.compile(
    r"^(?P<sid>\d+)-(?P<uid>\d+) - (?P<name>.+?) - "
    r"(?P<date>[A-Z][a-z]{2} \d{1,2}, \d{4} \d{3,4} [AP]M)(?: - (?P<orig>.+))?$"
)


@dataclass
class Parsed:
    """What a download name says about its submission."""

    lms: str
    name: str  # the person as the LMS names them ("Jane Doe", "smithjohn", "jdoe")
    lms_id: str  # Canvas user id, Moodle participant id, Blackboard username, D2L user id
    order: tuple = ()  # sorts attempts of one student, oldest first
    submitted_at: float | None = None  # seconds since the epoch, when the name says
    late: bool = False  # the LMS flagged it late

    @property
    def key(self) -> str:
        """Who submitted: the same for every attempt of one student in one LMS."""
        return f"{self.lms}:{self.lms_id}"


def parse_file(name: str) -> Parsed | None:
    """A notebook file's download name, or None when no LMS pattern fits."""
    m = _CANVAS.match(name)
    if m:
        return Parsed(
            CANVAS,
            m["name"],
            m["uid"],
            (int(m["fid"]), int(m["n"] or 0)),
            late=bool(m["late"]),
        )
    stem = name[:-6] if name.lower().endswith(".ipynb") else name
    m = _MOODLE_FILE.match(stem)
    if m:
        return Parsed(MOODLE, m["name"], m["uid"])
    m = _BLACKBOARD.match(stem)
    if m:
        t = _time(m["ts"], "%Y-%m-%d-%H-%M-%S")
        return Parsed(BLACKBOARD, m["uid"], m["uid"], (t or 0.0,), submitted_at=t)
    m = _BRIGHTSPACE.match(stem)
    if m:
        t = _time(m["date"], "%b %d, %Y %I%M %p")
        return Parsed(BRIGHTSPACE, m["name"], m["uid"], (t or 0.0, int(m["sid"])), t)
    return None


def parse_folder(name: str) -> Parsed | None:
    """A student folder's download name (Moodle, Brightspace), or None."""
    m = _MOODLE_DIR.match(name)
    if m:
        return Parsed(MOODLE, m["name"], m["uid"])
    m = _BRIGHTSPACE.match(name)
    if m and not m["orig"]:
        t = _time(m["date"], "%b %d, %Y %I%M %p")
        return Parsed(BRIGHTSPACE, m["name"], m["uid"], (t or 0.0, int(m["sid"])), t)
    return None


def _time(text: str, fmt: str) -> float | None:
    """Local time as the LMS wrote it, in seconds since the epoch."""
    try:
        return time.mktime(datetime.strptime(text, fmt).timetuple())
    except (ValueError, OverflowError):
        return None


def nbgrader_timestamp(folder: Path) -> float | None:
    """nbgrader's ``timestamp.txt`` beside a submitted notebook (``2026-11-20 23:10:05.1 UTC``)."""
    from .studentfiles import ReadFailed, read_in_process

    try:  # a student's file: no link followed, one name, a few bytes
        text = read_in_process(folder / "timestamp.txt", 4096).decode(errors="replace").strip()
    except ReadFailed:
        return None
    for fmt in ("%Y-%m-%d %H:%M:%S.%f %Z", "%Y-%m-%d %H:%M:%S %Z", "%Y-%m-%d %H:%M:%S.%f"):
        try:
            dt = datetime.strptime(text, fmt)
        except ValueError:
            continue
        if text.endswith(("UTC", "GMT")):
            from datetime import timezone

            return dt.replace(tzinfo=timezone.utc).timestamp()
        return time.mktime(dt.timetuple())
    return None


# ----------------------------------------------------------------------------- roster
@dataclass
class RosterEntry:
    """One row of an instructor's roster CSV."""

    id: str
    name: str = ""
    email: str = ""
    sis_id: str = ""
    section: str = ""
    login: str = ""


_ROSTER_COLUMNS = {
    "id": ("id", "student id", "canvas id", "user id", "participant", "identifier", "username"),
    "name": ("name", "student", "full name", "student name"),
    "email": ("email", "email address", "e-mail"),
    "sis_id": ("sis_id", "sis id", "sis user id", "student number", "id number", "idnumber"),
    "section": ("section", "group", "class"),
    "login": ("login", "sis login id", "login id", "netid"),
}


class RosterError(ValueError):
    """A roster file that cannot be used; the message says why."""


def read_roster(path: str | Path) -> list[RosterEntry]:
    """The students of a roster CSV (columns id, name, email, SIS id, section; any case).

    A Canvas gradebook export works as it is (Student, ID, SIS User ID, SIS Login ID,
    Section); its "Points Possible" row is skipped.
    """
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise RosterError(f"cannot read the roster {path}: {exc}") from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        raise RosterError(f"the roster {path} is empty")
    header = [h.strip().lower() for h in rows[0]]
    col: dict[str, int] = {}
    for field, names in _ROSTER_COLUMNS.items():
        for i, h in enumerate(header):
            if h in names and i not in col.values():
                col[field] = i
                break
    if "id" not in col and "sis_id" not in col and "email" not in col:
        raise RosterError(
            f"the roster {path} has no id column: found {', '.join(rows[0])}; "
            "expected id (or SIS User ID or email), name, email, SIS id, section"
        )
    out = []
    for r in rows[1:]:
        if not any(c.strip() for c in r) or r[0].strip().startswith("Points Possible"):
            continue
        get = {f: (r[i].strip() if i < len(r) else "") for f, i in col.items()}
        e = RosterEntry(**{f: get.get(f, "") for f in _ROSTER_COLUMNS})
        e.id = e.id or e.sis_id or e.email
        out.append(e)
    return out


def _norm(text: str) -> str:
    return "".join(ch for ch in text.lower() if ch.isalnum())


def match_roster(parsed: Parsed | None, raw_name: str, roster: list[RosterEntry]):
    """The roster row a submission belongs to, or None.

    Matched on the LMS id (Canvas/Moodle/D2L user id, Blackboard username) against the
    roster's id, SIS id, login or e-mail user part, else on the name with case, spaces and
    punctuation ignored, in either order of first and last name ("smithjohn" is "John Smith").
    """
    ids = {parsed.lms_id} if parsed else set()
    names = {_norm(parsed.name)} if parsed else set()
    names.add(_norm(raw_name))
    for e in roster:
        theirs = {e.id, e.id.removeprefix("Participant ").strip(), e.sis_id, e.login}
        if ids & (theirs | {e.email.split("@")[0]}) - {""}:
            return e
    for e in roster:
        parts = [p for p in re.split(r"[\s,]+", e.name) if p]
        forms = {_norm(e.name), _norm("".join(reversed(parts)))}
        if "," in e.name:  # "Smith, John"
            last, _, first = e.name.partition(",")
            forms |= {_norm(first + last), _norm(last + first)}
        if names & forms - {""}:
            return e
    return None


# ----------------------------------------------------------------------------- exports
def _cell(text: str) -> str:
    """A CSV cell a spreadsheet will not run as a formula (CSV injection)."""
    text = str(text)
    return "'" + text if text[:1] in ("=", "+", "-", "@", "\t", "\r") else text


def _num(x: float) -> str:
    return f"{x:.6g}"


def canvas_csv(rows: list[dict], title: str, max_score: float) -> tuple[str, list[str]]:
    """Canvas's gradebook import file for one assignment, and the students left out.

    ``rows`` are the gradebook's final grades (:meth:`Gradebook.final_grades`). A student
    needs a Canvas user id (from Canvas download names or the roster) or a SIS id.
    """
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\r\n")
    w.writerow(["Student", "ID", "SIS User ID", "SIS Login ID", "Section", title])
    w.writerow(["Points Possible", "", "", "", "", _num(max_score)])
    skipped = []
    for r in rows:
        canvas_id = r.get("canvas_id") or ""
        if not canvas_id and not r.get("sis_id"):
            skipped.append(r["student"])
            continue
        grade = "EX" if r["excused"] else _num(r["final"])
        w.writerow(
            [
                _cell(r.get("name") or r["student"]),
                canvas_id,
                _cell(r.get("sis_id") or ""),
                _cell(r.get("login") or ""),
                _cell(r.get("section") or ""),
                grade,
            ]
        )
    return buf.getvalue(), skipped


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


def _moodle_time(t: float | None) -> str:
    # Moodle reads it with PHP's strtotime: an unambiguous ISO local time.
    return "-" if not t else time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(t))


def moodle_csv(rows: list[dict], max_score: float) -> tuple[str, list[str]]:
    """Moodle's "Upload grading worksheet" file for one assignment, and the students left out.

    A student needs a Moodle participant id (from Moodle download names or the roster's id
    column written ``Participant 123``); excused students are left out (Moodle has no
    excused grade in the worksheet).
    """
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(MOODLE_COLUMNS)
    skipped = []
    for r in rows:
        pid = r.get("moodle_id") or ""
        if not pid or r["excused"]:
            skipped.append(r["student"])
            continue
        w.writerow(
            [
                f"Participant {pid}",
                _cell(r.get("name") or r["student"]),
                _cell(r.get("email") or ""),
                "Submitted for grading" if r.get("submitted_at") else "No submission",
                _num(r["final"]),
                _num(max_score),
                "Yes",
                _moodle_time(r.get("submitted_at")),
                _moodle_time(r.get("changed_at")),
                _cell(r.get("comment") or ""),
            ]
        )
    return buf.getvalue(), skipped
