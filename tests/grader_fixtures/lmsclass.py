"""A generated class in the four LMS download layouts, with each LMS's roster export.

The class (:func:`make_class`): 60 people with names in many scripts (accents, apostrophes,
Cyrillic, Arabic, CJK), two both called John Smith, Blackboard usernames holding ``_``
(``li_wei`` and ``zhang_wei``; four Mensahs), one who withdrew (handed in, not on the
roster), one who handed in nothing (on the roster), one who handed in a .zip, one an
exported .py, late work and resubmissions. Each notebook carries a token (who, which
attempt) in its metadata and the points each hidden test of ``fake2r`` would give, so a
test knows which file a grade came from and what it must be.

:func:`write` lays the class out as each LMS's "download all submissions" does, with the
roster export of that LMS (see the formats in :mod:`rikingrade.lms` and
:mod:`rikingrade.roster`): Canvas flat, only the newest attempt, files copied without
their times; Moodle a folder per student, newest attempt, file times kept (and either the
gradebook export or the grading worksheet as roster); Blackboard every attempt with its
``.txt`` record; Brightspace every submission with ``index.html``.
"""

from __future__ import annotations

import csv
import html
import io
import json
import os
import random
import time
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path

from .helpers import SOLUTION

#: Due at 2 PM, so that a time between 1:00 and 1:29 PM on the day is on time (Brightspace's
#: "110 PM" read as 11:00 PM would make it late).
DUE_TEXT = "2026-12-04 14:00"
DUE = time.mktime(datetime(2026, 12, 4, 14, 0).timetuple())
DAY = 86400.0
EXERCISE = "fake2r"
MAX_SCORE = 5.0
TESTS = ("add_int", "add_float", "fk_2r", "fk_2r_batch")
WEIGHTS = (1.0, 1.0, 2.0, 1.0)
CANVAS_COLUMN = "HW3 fake2r (4455)"
BLACKBOARD_ASSIGNMENT = "HW_3 fake2r"
BLACKBOARD_COLUMN = "HW_3 fake2r [Total Pts: 5 Score] |12345"
BRIGHTSPACE_ITEM = "HW3 fake2r Points Grade <Numeric MaxPoints:5 Weight:10>"

_NAMES = [
    ("John", "Smith"),
    ("John", "Smith"),
    ("José", "Núñez"),
    ("Zoë", "Åberg"),
    ("François", "Lefèvre"),
    ("Seán", "O'Brien"),
    ("D'Arcy", "McCall"),
    ("Иван", "Петров"),
    ("Анна", "Смирнова"),
    ("محمد", "علي"),
    ("فاطمة", "حسن"),
    ("小明", "王"),
    ("花子", "佐藤"),
    ("지민", "김"),
    ("Wei", "Li"),
    ("Wei", "Zhang"),
    ("Kwame", "Mensah"),
    ("Ama", "Mensah"),
    ("Kofi", "Mensah"),
    ("Yaw", "Mensah"),
    ("Ngozi", "Okafor"),
    ("Søren", "Kierkegård"),
    ("Łukasz", "Wróbel"),
    ("Ümit", "Yılmaz"),
    ("Chloé", "Dubois-Martin"),
]
#: Blackboard usernames that hold "_" (the rest are first letter + last name).
_USERNAMES = {
    14: "li_wei",
    15: "zhang_wei",
    16: "kwame_mensah",
    17: "ama_mensah",
    18: "kofi_mensah",
    19: "yaw_mensah",
}
WITHDRAWN, MISSING, ZIPPED, SCRIPT = 56, 57, 58, 59
#: People whose notebook is wrong (graded for real: 3 of 5).
WRONG = {1, 15}


@dataclass
class Attempt:
    when: float
    fractions: tuple[float, ...]

    @property
    def raw(self) -> float:
        return sum(f * w for f, w in zip(self.fractions, WEIGHTS, strict=True))


@dataclass
class Person:
    """One student, with every id each LMS gives them, and what they handed in."""

    idx: int
    first: str
    last: str
    canvas_id: str
    moodle_id: str
    username: str
    org_id: str
    email: str
    section: str
    attempts: list[Attempt] = field(default_factory=list)
    on_roster: bool = True
    handed: str = "notebook"  # notebook, zip, py, nothing

    @property
    def name(self) -> str:
        return f"{self.first} {self.last}"

    @property
    def newest(self) -> Attempt:
        return self.attempts[-1]

    def late_days(self, lms: str) -> int:
        """Days late as each LMS's own data says (Canvas: a LATE mark, counted 1 day)."""
        late = self.newest.when - DUE
        if late <= 0:
            return 0
        if lms == "canvas":
            return 1
        if lms == "brightspace":  # times to the minute
            late = (self.newest.when // 60) * 60 - DUE
        return int(-(-late // DAY))


def make_class(seed: int = 27) -> list[Person]:
    """The 60 people (see the module's documentation), seeded."""
    rng = random.Random(seed)
    people = []
    for i in range(60):
        first, last = _NAMES[i] if i < len(_NAMES) else (f"Student{i:02d}", f"Family{i:02d}")
        user = f"{first[0]}{last}".lower().replace("'", "")
        if not user.isascii() or not user.isalnum():
            user = f"u{i:03d}"
        user = _USERNAMES.get(i, user)
        p = Person(
            i,
            first,
            last,
            canvas_id=str(1000 + 7 * i),
            moodle_id=str(70000 + 3 * i),
            username=user if i != 1 else "jsmith2",
            org_id=f"#{20260000 + i}",
            email=f"s{i:03d}@uni.example",
            section="A" if i % 2 else "B",
        )
        if i != MISSING:
            p.attempts = _attempts(i, rng)
        p.on_roster = i != WITHDRAWN
        p.handed = {MISSING: "nothing", ZIPPED: "zip", SCRIPT: "py"}.get(i, "notebook")
        people.append(p)
    return people


def _attempts(i: int, rng: random.Random) -> list[Attempt]:
    def fr() -> tuple[float, ...]:
        return tuple(rng.choice((0.0, 0.5, 1.0)) for _ in TESTS)

    early = DUE - rng.uniform(1, 72) * 3600
    late = i % 7 == 3
    when = DUE + rng.uniform(0.2, 2.5) * DAY if late else early
    if i in (0, 1):  # the John Smiths: one attempt each, one of them late
        return [Attempt(DUE + 0.5 * DAY if i == 1 else early, fr())]
    if i % 5 == 2:  # a resubmission: the newest counts (sometimes late)
        return [Attempt(early - DAY, fr()), Attempt(when if late else early, fr())]
    if i % 11 == 4:  # handed in at 1:00-1:29 AM/PM on the due day (Brightspace's "110 PM")
        base = datetime.fromtimestamp(DUE).replace(hour=13 if i % 2 else 1, minute=i % 30)
        return [Attempt(time.mktime(base.timetuple()), fr())]
    return [Attempt(when, fr())]


def notebook(p: Person, k: int) -> bytes:
    """The fake2r solution with the token of person ``p``'s attempt ``k`` (for the people
    in :data:`WRONG`, ``add`` subtracts: 3 of 5 points when graded for real)."""
    nb = json.loads(SOLUTION.read_text())
    if p.idx in WRONG:
        for c in nb["cells"]:
            if "def add(" in "".join(c["source"]):
                c["source"] = "def add(a, b):\n    return a - b"
    a = p.attempts[k]
    nb["metadata"]["rikin_test"] = {"person": p.idx, "attempt": k, "fractions": a.fractions}
    return json.dumps(nb, ensure_ascii=False).encode()


def token(data: bytes) -> tuple[int, int]:
    """(person, attempt) of a notebook written by :func:`notebook`."""
    meta = json.loads(data)["metadata"]["rikin_test"]
    return meta["person"], meta["attempt"]


def _files(p: Person, k: int) -> tuple[str, bytes]:
    """The file person ``p`` handed in at attempt ``k``: (its own name, its bytes)."""
    if p.handed == "zip":
        return f"{EXERCISE}.zip", b"PK\x05\x06" + bytes(18)
    if p.handed == "py":
        return f"{EXERCISE}.py", b"def add(a, b):\n    return a + b\n"
    return f"{EXERCISE}.ipynb", notebook(p, k)


def _write(path: Path, data: bytes, mtime: float | None = None) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    if mtime is not None:
        os.utime(path, (mtime, mtime))


# ----------------------------------------------------------------------------- Canvas
def canvas_name(p: Person) -> str:
    """Canvas's sortable name in its download names: lower case, non-word characters out."""
    return "".join(ch for ch in f"{p.last}, {p.first}".lower() if ch.isalnum() or ch == "_")


def write_canvas(people: list[Person], folder: Path) -> Path:
    copied = time.time()  # unzipped with a tool that did not keep the times
    for p in people:
        if not p.attempts:
            continue
        orig, data = _files(p, len(p.attempts) - 1)
        if len(p.attempts) > 1:  # uploaded again under the same name: Canvas adds -1
            stem, _, ext = orig.rpartition(".")
            orig = f"{stem}-{len(p.attempts) - 1}.{ext}"
        late = "_LATE" if p.newest.when > DUE else ""
        fid = 50000 + 10 * p.idx + len(p.attempts)
        _write(folder / f"{canvas_name(p)}{late}_{p.canvas_id}_{fid}_{orig}", data, copied)
    return folder


def canvas_roster(people: list[Person], path: Path) -> Path:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", CANVAS_COLUMN, "HW2 (4454)"]
        + ["Current Score", "Final Score"]
    )
    w.writerow(["    Points Possible", "", "", "", "", "5", "10", "(read only)", "(read only)"])
    w.writerow(["", "", "", "", "", "Manual Posting", "", "", ""])
    for p in people:
        if p.on_roster:
            w.writerow(
                [f"{p.last}, {p.first}", p.canvas_id, f"S{p.idx:04d}", p.username]
                + [f"Section {p.section}", "", "8", "80", "80"]
            )
    w.writerow(["Student, Test", "99999", "", "", "Section A", "", "", "", ""])
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


# ----------------------------------------------------------------------------- Moodle
def write_moodle(people: list[Person], folder: Path) -> Path:
    for p in people:
        if not p.attempts:
            continue
        orig, data = _files(p, len(p.attempts) - 1)
        d = folder / f"{p.name}_{p.moodle_id}_assignsubmission_file_"
        _write(d / orig, data, p.newest.when)  # Moodle's zip keeps the file's time
    return folder


def moodle_roster(people: list[Person], path: Path) -> Path:
    """Moodle's course gradebook export (no participant ids: matched by name)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        ["First name", "Last name", "ID number", "Institution", "Department", "Email address"]
        + ["Assignment: HW3 fake2r (Real)", "Last downloaded from this course"]
    )
    for p in people:
        if p.on_roster:
            w.writerow([p.first, p.last, f"S{p.idx:04d}", "Uni", "Robotics", p.email, "-", ""])
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


def moodle_worksheet(people: list[Person], path: Path) -> Path:
    """Moodle's grading worksheet of the assignment (participant ids)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        ["Identifier", "Full name", "Email address", "Status", "Grade", "Maximum Grade"]
        + ["Grade can be changed", "Last modified (submission)", "Last modified (grade)"]
        + ["Feedback comments"]
    )
    for p in people:
        if p.on_roster:
            when = (
                time.strftime("%A, %d %B %Y, %I:%M %p", time.localtime(p.newest.when))
                if p.attempts
                else "-"
            )
            status = "Submitted for grading" if p.attempts else "No submission"
            w.writerow(
                [f"Participant {p.moodle_id}", p.name, p.email, status, "", "5.00", "Yes"]
                + [when, "-", ""]
            )
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


# ----------------------------------------------------------------------------- Blackboard
def _stamp(t: float) -> str:
    return time.strftime("%Y-%m-%d-%H-%M-%S", time.localtime(t))


def write_blackboard(people: list[Person], folder: Path) -> Path:
    for p in people:
        for k, a in enumerate(p.attempts):
            stem = f"{BLACKBOARD_ASSIGNMENT}_{p.username}_attempt_{_stamp(a.when)}"
            orig, data = _files(p, k)
            _write(folder / f"{stem}_{orig}", data)
            when = time.strftime("%A, %B %d, %Y %I:%M:%S %p", time.localtime(a.when))
            record = (
                f"Name: {p.name} ({p.username})\nAssignment: HW 3 fake2r\n"
                f"Date Submitted: {when} EST\nCurrent Grade: Needs Grading\n\n"
                "Submission Field:\nThere is no student submission text data for this "
                "assignment.\n\nComments:\nThere are no student comments for this "
                f"assignment.\n\nFiles:\n\tOriginal filename: {orig}\n\tFilename: {stem}_{orig}\n\n"
            )
            _write(folder / f"{stem}.txt", record.encode())
    return folder


def blackboard_roster(people: list[Person], path: Path) -> Path:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n", quoting=csv.QUOTE_ALL)
    w.writerow(
        ["Last Name", "First Name", "Username", "Student ID", "Last Access", "Availability"]
        + [BLACKBOARD_COLUMN, "HW_2 [Total Pts: 10 Score] |12344"]
    )
    for p in people:
        if p.on_roster:
            w.writerow([p.last, p.first, p.username, f"S{p.idx:04d}", "", "Yes", "", "8"])
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


# ----------------------------------------------------------------------------- Brightspace
def d2l_time(t: float, colon: bool) -> str:
    """``Dec 4, 2026 110 PM`` (a file name) or ``Dec 4, 2026 1:10 PM`` (index.html)."""
    lt = time.localtime(t)
    hour = lt.tm_hour % 12 or 12
    clock = f"{hour}:{lt.tm_min:02d}" if colon else f"{hour}{lt.tm_min:02d}"
    half = "PM" if lt.tm_hour >= 12 else "AM"
    return f"{time.strftime('%b', lt)} {lt.tm_mday}, {lt.tm_year} {clock} {half}"


def write_brightspace(people: list[Person], folder: Path) -> Path:
    rows = []
    for p in people:
        for k, a in enumerate(p.attempts):
            orig, data = _files(p, k)
            name = f"{81000 + 17 * p.idx + k}-{700000 + 31 * p.idx + 5 * k} - {p.name} - "
            name += f"{d2l_time(a.when, False)} - {orig}"
            _write(folder / name, data)
            rows.append((p.name, d2l_time(a.when, True), name, orig))
    cells = "\n".join(
        f"<tr><td>{html.escape(n)}</td><td>{html.escape(t)}</td>"
        f'<td><a href="{html.escape(f)}">{html.escape(o)}</a></td><td></td></tr>'
        for n, t, f, o in rows
    )
    page = (
        '<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>HW3 fake2r</title></head>'
        f"<body><h1>HW3 fake2r</h1>\n<table>\n<tr><th>Submitted By</th><th>Date Submitted</th>"
        f"<th>Submitted Files</th><th>Comments</th></tr>\n{cells}\n</table></body></html>\n"
    )
    _write(folder / "index.html", page.encode())
    return folder


def brightspace_roster(people: list[Person], path: Path) -> Path:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        ["OrgDefinedId", "Username", "Last Name", "First Name", "Email", BRIGHTSPACE_ITEM]
        + ["Calculated Final Grade Numerator", "End-of-Line Indicator"]
    )
    for p in people:
        if p.on_roster:
            w.writerow([p.org_id, f"#{p.username}", p.last, p.first, p.email, "", "", "#"])
    path.write_text(buf.getvalue(), encoding="utf-8")
    return path


WRITERS = {
    "canvas": (write_canvas, canvas_roster),
    "moodle": (write_moodle, moodle_roster),
    "moodle-worksheet": (write_moodle, moodle_worksheet),
    "blackboard": (write_blackboard, blackboard_roster),
    "brightspace": (write_brightspace, brightspace_roster),
}


def write(
    people: list[Person], layout: str, where: Path, only: set[int] | None = None
) -> tuple[Path, Path]:
    """The class as ``layout`` downloads it, and the roster export: (folder, roster).
    ``only``: the people (by index) in this class; the others are left out entirely."""
    chosen = [p for p in people if only is None or p.idx in only]
    folder_writer, roster_writer = WRITERS[layout]
    folder = folder_writer(chosen, where / f"{layout}-download")
    return folder, roster_writer(chosen, where / f"{layout}-roster.csv")


def fake_pool(batch, todo, workers, done, bar, results):
    """Stands for :func:`rikingrade.api._run_pool`: grades each notebook by the points its
    metadata gives (no cell is run), committing each result as the real pool does."""
    from rikingrade.report import SubmissionResult, TestResult

    a, key = batch.assignment, batch.key
    for s in todo:
        meta = json.loads(s.read_bytes())["metadata"]["rikin_test"]
        tests = [
            TestResult(t.name, float(t.weight), f, "ok" if f >= 1 else "not right")
            for t, f in zip(a.tests, meta["fractions"], strict=True)
        ]
        res = SubmissionResult(
            s.student, s.shown_path, s.hash(), "ok", tests=tests, max_score=a.max_score, key=key
        )
        assert done(s, res)
        results[s.student] = res
        bar.update(res)
