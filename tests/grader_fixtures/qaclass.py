"""A second generated class of 43, written as each LMS writes its download and roster.

Independent of :mod:`grader_fixtures.lmsclass` (other names, other edge cases): accents,
apostrophes, hyphens, Cyrillic, Greek, Arabic, CJK, Hangul, Devanagari and Thai names (whose
vowel signs are combining marks) and a name typed decomposed; two John Smiths; Li Wei and
Wei Li (the same two words in the other order); usernames holding ``_`` and ``.``; a
student with three resubmissions; one who withdrew (handed in, not on the roster); one who
handed in nothing; work late by an hour and by three days; an extension; times from
12:00 AM to 12:59 PM; a due time on the Saturday before the end of summer time (Europe's
clocks go back on Sunday 25 October 2026), so lateness is counted across the change.

Times are in :data:`ZONE`; a test sets ``TZ`` to it (:func:`local_zone`), as an instructor
grades in the zone of the LMS's server.

Each notebook carries ``metadata.qa27 = {"who": i, "attempt": k, "frac": f}``: who handed it
in, which of their attempts it is, and the share of every hidden test's points it earns
(:func:`fake_pool` scores it so, without running a cell; the real sandbox scores the real
notebooks of :func:`write` with ``base=`` the exercise's solution or stub).
"""

from __future__ import annotations

import csv
import html
import io
import json
import os
import time
import unicodedata
from dataclasses import dataclass, field
from datetime import UTC, datetime, timedelta
from pathlib import Path
from zoneinfo import ZoneInfo

from .helpers import SOLUTION

ZONE = "Europe/Berlin"
TZ = ZoneInfo(ZONE)
#: Due at noon on Saturday 24 October 2026 (summer time, UTC+2); the clocks go back an
#: hour at 03:00 on Sunday 25 October.
DUE = datetime(2026, 10, 24, 12, 0, tzinfo=TZ)
DUE_TEXT = "2026-10-24 12:00"
GRACE_MIN = 15.0
LATE_PER_DAY = 10.0
LATE_CAP = 50.0
DOWNLOADED = datetime(2026, 10, 29, 9, 30, tzinfo=TZ)
EXTENDED = datetime(2026, 10, 27, 12, 0, tzinfo=TZ)

CANVAS_ASSIGNMENT_ID = "7311"
MOODLE_ASSIGNMENT = "HW3 SCARA"
BLACKBOARD_ASSIGNMENT = "HW3 SCARA"
BLACKBOARD_COLUMN_ID = "40417"
BRIGHTSPACE_ITEM = "HW3 SCARA"
#: The assignment's points in the LMS (its column in the roster exports): fake2r's maximum.
POINTS = 5.0


def local_zone(monkeypatch) -> None:
    """Run the test in :data:`ZONE`, as the LMS's server writes its local times."""
    monkeypatch.setenv("TZ", ZONE)
    time.tzset()


def at(day: int, hour: int, minute: int, month: int = 10) -> datetime:
    return datetime(2026, month, day, hour, minute, tzinfo=TZ)


@dataclass
class Attempt:
    when: datetime
    frac: float  # the share of each test's points; -1: not a notebook at all (corrupt)


@dataclass
class Person:
    idx: int
    first: str
    last: str
    username: str
    attempts: list[Attempt] = field(default_factory=list)
    on_roster: bool = True
    section: str = "Lab 1"
    extension: datetime | None = None
    also: tuple[str, ...] = ()  # other files handed in with the notebook

    @property
    def name(self) -> str:
        return f"{self.first} {self.last}"

    @property
    def canvas_id(self) -> str:
        return str(52000 + 7 * self.idx)

    @property
    def moodle_id(self) -> str:
        return str(880100 + 3 * self.idx)

    @property
    def org_id(self) -> str:
        return f"00{4410 + self.idx}"

    @property
    def sis_id(self) -> str:
        return f"S{20260 + self.idx}"

    @property
    def email(self) -> str:
        return f"{self.username}@uni.example"

    @property
    def newest(self) -> Attempt:
        return max(self.attempts, key=lambda a: a.when)

    @property
    def due(self) -> datetime:
        return self.extension or DUE

    def late_days(self, lms: str) -> int:
        """Started days after the due time plus the grace, in real (UTC) time; Canvas's
        download has no time, only its ``LATE`` mark (one day)."""
        if lms == "canvas":
            return 1 if self.canvas_late else 0
        # aware datetimes of one zone subtract by the wall clock: count in UTC
        late = self.newest.when.astimezone(UTC) - self.due.astimezone(UTC)
        late -= timedelta(minutes=GRACE_MIN)
        if late <= timedelta(0):
            return 0
        return -(-int(late.total_seconds()) // 86400)

    @property
    def canvas_late(self) -> bool:
        """Canvas marks a submission late after the student's due time (no grace)."""
        return self.newest.when > self.due

    def final(self, lms: str, max_score: float) -> float:
        raw = max(self.newest.frac, 0.0) * max_score
        pen = min(LATE_CAP, LATE_PER_DAY * self.late_days(lms)) / 100 * max_score
        return round(max(0.0, raw - pen), 6)


# (first, last, username); the index is the person's number
_PEOPLE = [
    ("John", "Smith", "jsmith"),
    ("John", "Smith", "jsmith2"),
    ("Seán", "O'Brien", "sobrien"),
    ("Zoë", "Müller-Lüdenscheidt", "zmuller"),
    ("Иван", "Петров", "ipetrov"),
    ("Ольга", "Смирнова-Ким", "osmirnova"),
    ("Γιώργος", "Παπαδόπουλος", "gpapadopoulos"),
    ("محمد", "العلي", "malali"),
    ("芳", "王", "wang_fang"),
    ("花子", "佐藤", "hsato"),
    ("민준", "김", "mkim"),
    ("José María", "de la Cruz", "jmdelacruz"),
    ("Anne-Marie", "D'Arcy", "amdarcy"),
    ("François", "Lefèvre", "flefevre"),
    ("Văn An", "Nguyễn", "vnguyen"),
    ("Björk", "Guðmundsdóttir", "bgudmundsdottir"),
    ("Li", "Wei", "li_wei"),
    ("Wei", "Li", "wei.li"),
    ("Mary-Kate", "O'Neil-Smith", "mkoneil"),
    ("Dmitri", "Ivanov", "d.ivanov"),
    ("Ahmed", "Hassan", "ahmed_hassan_2"),
    ("Priya", "Patel", "ppatel"),  # three resubmissions
    ("Lars", "Ørsted", "lorsted"),  # withdrew
    ("Jie", "Chen", "jchen"),  # handed in nothing
    ("Emma", "Johnson", "ejohnson"),  # an hour late
    ("Noah", "Williams", "nwilliams"),  # three days late
    ("Fatima", "Zahra", "fzahra"),  # an extension
    ("Olivia", "Brown", "obrown"),  # 12:00 AM
    ("Liam", "García", "lgarcia"),  # 12:30 AM
    ("Sofía", "Hernández", "shernandez"),  # 12:10 PM (grace)
    ("Lucas", "Martin", "lmartin"),  # 12:59 PM
    ("Mia", "Rossi", "mrossi"),  # 1:10 PM
    ("Ethan", "Nowak", "enowak"),  # Sunday after the change
    ("Ava", "Kowalski", "akowalski"),  # 10:10 AM
    ("Mateo", "Silva", "msilva"),  # a broken notebook
    ("Isla", "MacLeod", "imacleod"),  # half the points
    ("Yuki", "Tanaka", "ytanaka"),  # a notebook that is not JSON
    ("Amara", "Okonkwo", "aokonkwo"),  # a notebook and a screenshot
    ("Hiroshi", "Yamamoto", "hyamamoto"),
    ("Kateřina", "Dvořáková", "kdvorakova"),
    ("प्रिया", "शर्मा", "psharma"),  # Devanagari: vowel signs are marks (Mc, Mn)
    ("สมชาย", "ใจดี", "somchai.j"),  # Thai: a vowel sign that is a mark (Mn)
    ("Rene\u0301e", "Dubois", "rdubois"),  # typed decomposed: e + a combining accent
]
WITHDRAWN, MISSING, RESUBMITTER = 22, 23, 21
WANG, LI_WEI, WEI_LI = 8, 16, 17
CORRUPT, SCREENSHOT = 36, 37


def make_class() -> list[Person]:
    """The class: who handed in what, when."""
    people = [Person(i, f, la, u) for i, (f, la, u) in enumerate(_PEOPLE)]
    for p in people:
        p.section = "Lab 1" if p.idx % 2 == 0 else "Lab 2"
        p.attempts = [Attempt(at(22, 9 + p.idx % 10, (7 * p.idx) % 60), 1.0)]
    special = {
        1: [Attempt(at(23, 18, 45), 0.5)],
        RESUBMITTER: [
            Attempt(at(20, 10, 0), 0.0),
            Attempt(at(22, 23, 15), 0.5),
            Attempt(at(23, 8, 5), 0.5),
            Attempt(at(24, 11, 40), 1.0),
        ],
        MISSING: [],
        24: [Attempt(at(24, 13, 0), 1.0)],  # 1 h late (45 min past the grace)
        25: [Attempt(at(27, 10, 0), 1.0)],  # 2 d 23 h late: 3 days
        26: [Attempt(at(26, 22, 0), 1.0)],  # before the extended due time
        27: [Attempt(at(24, 0, 0), 1.0)],
        28: [Attempt(at(24, 0, 30), 1.0)],  # as 12:30 PM it would be late
        29: [Attempt(at(24, 12, 10), 1.0)],  # within the grace (Canvas: LATE)
        30: [Attempt(at(24, 12, 59), 1.0)],  # as 00:59 it would be on time
        31: [Attempt(at(24, 13, 10), 1.0)],
        # 23 h 30 min after noon by the wall clock, 24 h 30 min in real time
        32: [Attempt(at(25, 11, 30), 1.0)],
        33: [Attempt(at(24, 10, 10), 1.0)],
        34: [Attempt(at(23, 16, 20), 0.0)],
        35: [Attempt(at(23, 17, 25), 0.5)],
        CORRUPT: [Attempt(at(23, 19, 5), -1.0)],
        WEI_LI: [Attempt(at(23, 21, 15), 0.5)],
    }
    for i, attempts in special.items():
        people[i].attempts = attempts
    people[WITHDRAWN].on_roster = False
    people[26].extension = EXTENDED
    people[SCREENSHOT].also = ("screenshot.png",)
    return people


# ---------------------------------------------------------------- the notebooks


def notebook(p: Person, k: int, base: dict[float, bytes] | None = None) -> bytes:
    """Attempt ``k`` of ``p``: ``base[frac]`` (a notebook of the exercise earning that share;
    fake2r's solution by default) with the token in its metadata; a corrupt attempt is not
    JSON at all."""
    a = p.attempts[k]
    if a.frac < 0:
        return b'{"cells": [ {"cell_type": "code", "source": "trunca'
    nb = json.loads(base[a.frac] if base is not None else SOLUTION.read_bytes())
    nb["metadata"]["qa27"] = {"who": p.idx, "attempt": k, "frac": a.frac}
    return json.dumps(nb, ensure_ascii=False, indent=1).encode("utf-8")


def token(data: bytes) -> tuple[int, int] | None:
    try:
        meta = json.loads(data)["metadata"]["qa27"]
    except (ValueError, KeyError, TypeError):
        return None
    return meta["who"], meta["attempt"]


def _put(path: Path, data: bytes, when: datetime) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    os.utime(path, (when.timestamp(), when.timestamp()))


def _ordered(p: Person) -> list[int]:
    return sorted(range(len(p.attempts)), key=lambda k: p.attempts[k].when)


# ---------------------------------------------------------------- Canvas


def canvas_sanitize(text: str) -> str:
    """Canvas's ``gsub(/[^[[:word:]]]/, '').downcase``: keeps letters, marks, digits, ``_``."""
    keep = (
        c
        for c in text
        if unicodedata.category(c)[0] in "LM" or unicodedata.category(c) in ("Nd", "Pc")
    )
    return "".join(keep).lower()


def canvas_prefix(p: Person) -> str:
    late = "_LATE" if p.canvas_late else ""
    return f"{canvas_sanitize(p.last + ', ' + p.first)}{late}_{p.canvas_id}"


def write_canvas(
    people: list[Person], folder: Path, base: dict[float, bytes] | None = None
) -> None:
    """*Download Submissions*: the newest submission's files, flat; a file uploaded again
    under the same name is ``scara-<n>.ipynb``; the zip's times are the download's."""
    file_id = 910000
    for p in people:
        if not p.attempts:
            continue
        k = _ordered(p)[-1]
        shown = "scara.ipynb" if k == 0 else f"scara-{k}.ipynb"
        file_id += 13
        _put(folder / f"{canvas_prefix(p)}_{file_id}_{shown}", notebook(p, k, base), DOWNLOADED)
        for extra in p.also:
            file_id += 13
            _put(folder / f"{canvas_prefix(p)}_{file_id}_{extra}", b"\x89PNG\r\n\x1a\n", DOWNLOADED)


def canvas_roster(people: list[Person], path: Path) -> None:
    column = f"HW3 SCARA ({CANVAS_ASSIGNMENT_ID})"
    head = [
        "Student",
        "ID",
        "SIS User ID",
        "SIS Login ID",
        "Section",
        "HW2 DH tables (7300)",
        column,
        "Current Points",
        "Final Points",
        "Current Score",
        "Final Score",
    ]
    rows = [
        head,
        [
            "    Points Possible",
            "",
            "",
            "",
            "",
            "10.00",
            f"{POINTS:.2f}",
            "(read only)",
            "(read only)",
            "(read only)",
            "(read only)",
        ],
    ]
    for p in people:
        if p.on_roster:
            rows.append(
                [
                    f"{p.last}, {p.first}",
                    p.canvas_id,
                    p.sis_id,
                    p.username,
                    p.section,
                    "9.00",
                    "",
                    "9.00",
                    "9.00",
                    "90.00",
                    "90.00",
                ]
            )
    rows.append(["Student, Test", "51999", "", "", "Lab 1", "", "", "", "", "", ""])
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\r\n").writerows(rows)
    path.write_bytes(b"\xef\xbb\xbf" + buf.getvalue().encode("utf-8"))


# ---------------------------------------------------------------- Moodle


def moodle_folder(p: Person) -> str:
    return f"{p.name.replace('_', ' ')}_{p.moodle_id}_assignsubmission_file_"


def write_moodle(
    people: list[Person], folder: Path, base: dict[float, bytes] | None = None
) -> None:
    """*Download all submissions*, a folder per student (Moodle 3.1+'s default): the
    latest submission, its files with their own time."""
    for p in people:
        if not p.attempts:
            continue
        k = _ordered(p)[-1]
        d = folder / moodle_folder(p)
        _put(d / "scara.ipynb", notebook(p, k, base), p.attempts[k].when)
        for extra in p.also:
            _put(d / extra, b"\x89PNG\r\n\x1a\n", p.attempts[k].when)


def moodle_roster(people: list[Person], path: Path) -> None:
    """The course gradebook's *Export to plain text file* (no participant id in it)."""
    head = [
        "First name",
        "Last name",
        "ID number",
        "Institution",
        "Department",
        "Email address",
        f"Assignment: {MOODLE_ASSIGNMENT} (Real)",
        "Last downloaded from this course",
    ]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(head)
    for p in people:
        if p.on_roster:
            w.writerow([p.first, p.last, p.sis_id, "Uni", p.section, p.email, "-", "1761730000"])
    path.write_text(buf.getvalue(), encoding="utf-8")


def moodle_worksheet(people: list[Person], path: Path) -> None:
    """The assignment's *Download grading worksheet*."""
    head = [
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
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(head)
    for p in people:
        if not p.on_roster:
            continue
        if p.attempts:
            t = p.newest.when.strftime("%A, %d %B %Y, %I:%M %p")
            status = "Submitted for grading - Graded"
        else:
            t, status = "-", "No submission"
        w.writerow(
            [
                f"Participant {p.moodle_id}",
                p.name,
                p.email,
                status,
                "",
                f"{POINTS:.2f}",
                "Yes",
                t,
                "-",
                "",
            ]
        )
    path.write_text(buf.getvalue(), encoding="utf-8")


# ---------------------------------------------------------------- Blackboard


def bb_stamp(t: datetime) -> str:
    return t.strftime("%Y-%m-%d-%H-%M-%S")


def bb_long(t: datetime) -> str:
    """``Saturday, October 24, 2026 12:59:00 PM CEST`` (no leading zero on the hour)."""
    hour = t.strftime("%I").lstrip("0")
    return f"{t:%A, %B} {t.day}, {t.year} {hour}:{t:%M:%S %p %Z}"


def write_blackboard(
    people: list[Person], folder: Path, base: dict[float, bytes] | None = None
) -> None:
    """*Assignment File Download*, all attempts: a ``.txt`` record and the files of each."""
    for p in people:
        for k in _ordered(p):
            a = p.attempts[k]
            stem = f"{BLACKBOARD_ASSIGNMENT}_{p.username}_attempt_{bb_stamp(a.when)}"
            files = ["scara.ipynb", *p.also]
            listing = "".join(f"\tOriginal filename: {f}\n\tFilename: {stem}_{f}\n" for f in files)
            record = (
                f"Name: {p.name} ({p.username})\n"
                f"Assignment: {BLACKBOARD_ASSIGNMENT}\n"
                f"Date Submitted: {bb_long(a.when)}\n"
                "Current Grade: Needs Grading\n\n"
                "Submission Field:\n"
                "There is no student submission text data for this assignment.\n\n"
                "Comments:\nThere are no student comments for this assignment.\n\n"
                f"Files:\n{listing}"
            )
            _put(folder / f"{stem}.txt", record.encode("utf-8"), DOWNLOADED)
            _put(folder / f"{stem}_scara.ipynb", notebook(p, k, base), DOWNLOADED)
            for extra in p.also:
                _put(folder / f"{stem}_{extra}", b"\x89PNG\r\n\x1a\n", DOWNLOADED)


def blackboard_column() -> str:
    return f"{BLACKBOARD_ASSIGNMENT} [Total Pts: {POINTS:g} Score] |{BLACKBOARD_COLUMN_ID}"


def blackboard_roster(people: list[Person], path: Path) -> None:
    """Grade Center *Work Offline > Download*, full Grade Center, tab delimited: an
    ``.xls`` that is UTF-16 text with a byte-order mark."""
    head = [
        "Last Name",
        "First Name",
        "Username",
        "Student ID",
        "Last Access",
        "Availability",
        "HW2 DH tables [Total Pts: 10 Score] |40400",
        blackboard_column(),
        "Weighted Total [Total Pts: up to 0 Percentage] |40380",
    ]
    buf = io.StringIO()
    w = csv.writer(buf, delimiter="\t", lineterminator="\r\n", quoting=csv.QUOTE_ALL)
    w.writerow(head)
    for p in people:
        if p.on_roster:
            w.writerow(
                [
                    p.last,
                    p.first,
                    p.username,
                    p.sis_id,
                    "2026-10-22 10:12:00",
                    "Available",
                    "9.00",
                    "",
                    "",
                ]
            )
    path.write_bytes(buf.getvalue().encode("utf-16"))


# ---------------------------------------------------------------- Brightspace


def d2l_time(t: datetime, colon: bool = False) -> str:
    """``Oct 24, 2026 1259 PM`` in a file name, ``Oct 24, 2026 12:59 PM`` in a folder's."""
    hour = t.strftime("%I").lstrip("0")
    sep = ":" if colon else ""
    return f"{t:%b} {t.day}, {t.year} {hour}{sep}{t:%M %p}"


def write_brightspace(
    people: list[Person], folder: Path, base: dict[float, bytes] | None = None
) -> None:
    """The folder's *Download* of every submission, with ``index.html``."""
    rows = []
    sub = 131000
    for p in people:
        for k in _ordered(p):
            a = p.attempts[k]
            sub += 17
            name = f"{sub}-{602000 + p.idx} - {p.name} - {d2l_time(a.when)} - scara.ipynb"
            _put(folder / name, notebook(p, k, base), DOWNLOADED)
            files = [("scara.ipynb", name)]
            for extra in p.also:
                other = f"{sub}-{602000 + p.idx} - {p.name} - {d2l_time(a.when)} - {extra}"
                _put(folder / other, b"\x89PNG\r\n\x1a\n", DOWNLOADED)
                files.append((extra, other))
            links = "<br>".join(
                f'<a href="{html.escape(f)}">{html.escape(o)}</a>' for o, f in files
            )
            rows.append(
                f"<tr><td>{html.escape(p.name)}</td><td>{html.escape(d2l_time(a.when, True))}"
                f"</td><td>{links}</td></tr>"
            )
    page = (
        '<html><head><meta charset="UTF-8"><title>HW3 SCARA</title></head><body>\n'
        '<table border="1">\n<tr><th>Submitted By</th><th>Date Submitted</th>'
        "<th>Files</th></tr>\n" + "\n".join(rows) + "\n</table></body></html>\n"
    )
    _put(folder / "index.html", page.encode("utf-8"), DOWNLOADED)


def brightspace_column() -> str:
    return (
        f"{BRIGHTSPACE_ITEM} Points Grade <Numeric MaxPoints:{POINTS:g} Weight:15 "
        "Category:Homework CategoryWeight:40>"
    )


def brightspace_roster(people: list[Person], path: Path) -> None:
    """Grades *Export*: org defined id, username, names, e-mail, points, end of line."""
    head = [
        "OrgDefinedId",
        "Username",
        "Last Name",
        "First Name",
        "Email",
        "HW2 DH tables Points Grade <Numeric MaxPoints:10 Weight:15>",
        brightspace_column(),
        "End-of-Line Indicator",
    ]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\r\n")
    w.writerow(head)
    for p in people:
        if p.on_roster:
            w.writerow([f"#{p.org_id}", f"#{p.username}", p.last, p.first, p.email, "9", "", "#"])
    path.write_text(buf.getvalue(), encoding="utf-8")


WRITERS = {
    "canvas": (write_canvas, canvas_roster),
    "moodle": (write_moodle, moodle_roster),
    "moodle-worksheet": (write_moodle, moodle_worksheet),
    "blackboard": (write_blackboard, blackboard_roster),
    "brightspace": (write_brightspace, brightspace_roster),
}
ROSTER_NAMES = {
    "canvas": "2026-10-29T0930_Grades-ROB301.csv",
    "moodle": "ROB301 Grades.csv",
    "moodle-worksheet": "Grades-ROB301-HW3 SCARA.csv",
    "blackboard": "gc_ROB301_fullgc_2026-10-29-09-30-00.xls",
    "brightspace": "ROB301_GradesExport_2026-10-29-09-30.csv",
}


def write(
    people: list[Person], layout: str, root: Path, base: dict[float, bytes] | None = None
) -> tuple[Path, Path]:
    """The unzipped download ``root/<layout>/`` and the roster export beside it."""
    files, roster = WRITERS[layout]
    folder = root / layout
    folder.mkdir(parents=True)
    files(people, folder, base)
    path = root / ROSTER_NAMES[layout]
    roster(people, path)
    return folder, path


def extensions(people: list[Person], path: Path, lms: str) -> None:
    """The extension as the instructor writes it: the student by the LMS's id."""
    ids = {
        "canvas": lambda p: p.canvas_id,
        "moodle": lambda p: p.moodle_id,
        "blackboard": lambda p: p.username,
        "brightspace": lambda p: p.username,
    }
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["student", "due", "reason"])
    for p in people:
        if p.extension:
            w.writerow([ids[lms](p), p.extension.strftime("%Y-%m-%d %H:%M"), "medical"])
    path.write_text(buf.getvalue(), encoding="utf-8")


# ---------------------------------------------------------------- the fast path


def fake_pool(batch, todo, workers, done, bar, results):
    """Stands for ``api._run_pool``: each notebook earns ``frac`` of every test's points
    (no cell is run); a file that is not a notebook is ``invalid``; each result is
    committed as the real pool does."""
    from rikingrade.report import SubmissionResult, TestResult

    a, key = batch.assignment, batch.key
    for s in todo:
        try:
            frac = json.loads(s.read_bytes())["metadata"]["qa27"]["frac"]
        except ValueError:
            res = SubmissionResult(
                s.student,
                s.shown_path,
                s.hash(),
                "invalid",
                reason="not a notebook (not JSON)",
                max_score=a.max_score,
                key=key,
            )
        else:
            tests = [
                TestResult(t.name, float(t.weight), frac, "ok" if frac >= 1 else "not right")
                for t in a.tests
            ]
            res = SubmissionResult(
                s.student, s.shown_path, s.hash(), "ok", tests=tests, max_score=a.max_score, key=key
            )
        assert done(s, res)
        results[s.student] = res
        bar.update(res)
