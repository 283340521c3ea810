"""LMS downloads: who handed in each file, and when, read from what the LMS itself writes.

Each LMS names the files of its "download all submissions" zip its own way, and some write a
record beside them. Nothing here guesses an id from a fragment: a name that does not say
who handed it in, unambiguously, is left for the caller to refuse with the reason.

Canvas       ``<name>[_LATE]_<user id>_<file id>_<file>``, e.g.
             ``smithjohn_LATE_1000_5200_scara-1.ipynb``; ``<name>[_LATE]_<user id>_text.html``
             and ``..._link.html`` for a text entry or a URL; ``anon_<id>_<file id>_<file>``
             when grading is anonymous. Canvas writes the sortable name in lower case with
             every non-word character removed ("O'Brien, Seán" -> ``obrienseán``), ``LATE``
             (``late`` in older versions) when its own due date had passed, the user id (the
             "ID" of its gradebook export) and the attachment id, then the student's file
             name (``-1``, ``-2``: a file uploaded again under the same name). No time.
Moodle       ``<Full Name>_<participant id>_assignsubmission_<plugin>_/<file>`` (a folder
             per student), or ``..._assignsubmission_<plugin>_<file>`` flat. Moodle writes
             ``_`` in a name as a space; the id is the grading worksheet's "Participant N".
             No time in the name (the zip entries keep the file's time).
Blackboard   ``<prefix>_<username>_attempt_<yyyy-mm-dd-hh-mm-ss>.txt``, the attempt's
             record (``Name: First Last (username)``, ``Assignment:``, ``Date Submitted:``,
             ``Files:`` with ``Original filename:`` and ``Filename:`` per file), and each
             file as ``<prefix>_<username>_attempt_<ts>_<file>``. A username may hold ``_``,
             so it is read from the record (or the record's prefix), never cut at a ``_``.
Brightspace  ``<n>-<n> - <First Last> - <Mon d, yyyy hmm AM> - <file>`` (files) or
             ``... - <Mon d, yyyy h:mm AM>`` (a folder per submission), and ``index.html``,
             a table of who handed in which file when. Neither number is documented as the
             user's: students are told apart by name, and namesakes by the roster.
Gradescope   "Export Submissions": ``assignment_<id>_export/`` with a folder
             ``submission_<id>/`` per submission (the student's files as uploaded) and
             ``submission_metadata.yml``, a YAML map of each folder's name to its record in
             Ruby symbol keys (``:submitters:``, a list of ``:name:``, ``:sid:``, ``:email:``:
             several for a group; ``:created_at:`` with its zone, ``2026-11-20 22:50:12.3
             +00:00``; ``:score:``; ``:history:``, the earlier submissions, which the export
             holds no files of). The folder's number is Gradescope's submission id, not a
             student's: who it is comes from the record only.
nbgrader     ``submitted/<student>/<assignment>/<file>`` with ``timestamp.txt``.

Times without a zone are the grading machine's local time, like ``--due``.
"""

from __future__ import annotations

import re
import time
import unicodedata
import urllib.parse
from dataclasses import dataclass, field
from datetime import date, datetime, timedelta, timezone
from html.parser import HTMLParser
from pathlib import Path

from .lmsfiles import MOODLE_COLUMNS, _cell, canvas_csv, moodle_csv  # noqa: F401
from .roster import (  # noqa: F401  (the names this module always offered)
    RosterEntry,
    RosterError,
    match_roster,
    name_key,
    read_roster,
)

CANVAS = "canvas"
MOODLE = "moodle"
BLACKBOARD = "blackboard"
BRIGHTSPACE = "brightspace"
GRADESCOPE = "gradescope"
NBGRADER = "nbgrader"
FOLDER = "folder"  # a folder per student, id = folder name
FILE = "file"  # a loose notebook, id = file name

#: Files an LMS writes about the submissions, read and never graded.
BRIGHTSPACE_INDEX = "index.html"
GRADESCOPE_METADATA = "submission_metadata.yml"

_DIGITS = re.compile(r"^\d+$")
_CANVAS_ANON = re.compile(r"^(?:(?P<late>LATE|late)_)?anon_(?P<anon>[A-Za-z0-9]+)_(?P<rest>.+)$")
_REUPLOAD = re.compile(r"^(?P<stem>.+?)-(?P<n>\d+)(?P<ext>\.[^.]*)?$")
_MOODLE_DIR = re.compile(r"^(?P<name>[^_]+)_(?P<uid>\d+)_assignsubmission_(?P<plugin>[a-z]+)_?$")
_MOODLE_FILE = re.compile(
    r"^(?P<name>[^_]+)_(?P<uid>\d+)_assignsubmission_(?P<plugin>[a-z]+)_(?P<orig>.+)$"
)
_BLACKBOARD = re.compile(
    r"^(?P<stem>.+)_attempt_(?P<ts>\d{4}-\d{2}-\d{2}-\d{2}-\d{2}-\d{2})(?:_(?P<orig>.+))?$"
)
_D2L_DATE = r"[A-Z][a-z]{2} \d{1,2}, \d{4} \d{1,2}:?\d{2} [AP]M"
_BRIGHTSPACE = re.compile(
    rf"^(?P<n1>\d+)-(?P<n2>\d+) - (?P<name>.+?) - (?P<date>{_D2L_DATE})(?: - (?P<orig>.+))?$"
)


@dataclass
class Parsed:
    """What a download name (and the LMS's record, when there is one) says about a file.

    ``lms_id`` is the LMS's own id for the student (Canvas user id, Moodle participant id,
    Blackboard username); '' when the LMS gives none (Brightspace) or the name alone cannot
    say (a Blackboard name whose username holds ``_``, without its record: ``unsure`` says
    why). ``kind`` is ``file``, or ``text``/``link`` for a Canvas or Moodle text entry or URL.
    """

    lms: str
    name: str  # the person as the LMS names them ("Jane Doe", "smithjohn", "jdoe")
    lms_id: str
    order: tuple = ()  # sorts attempts of one student, oldest first
    submitted_at: float | None = None  # seconds since the epoch, when the LMS says
    late: bool = False  # the LMS flagged it late (Canvas)
    file_id: str = ""  # Canvas's attachment id (its re-upload pairs feedback with it)
    orig: str = ""  # the student's own file name
    kind: str = "file"
    time_source: str = ""
    unsure: str = ""  # why the name alone does not say who handed it in
    email: str = ""  # as the LMS's record gives it (Gradescope)
    sis_id: str = ""  # the student id the LMS's record gives (Gradescope's SID)

    @property
    def key(self) -> str:
        """Who submitted: the same for every attempt of one student in one LMS."""
        if self.lms_id:
            return f"{self.lms}:{self.lms_id}"
        return f"{self.lms}:name:{person_key(self.name)}"


def person_key(name: str) -> str:
    """A person's name as one key whatever the order ("Smith, John" is "John Smith")."""
    return " ".join(sorted(k for k in (name_key(t) for t in re.split(r"[\s,]+", name)) if k))


# ----------------------------------------------------------------------------- names
def parse_file(name: str, usernames=(), prefixes=()) -> Parsed | None:
    """A file's download name (any extension), or None when no LMS writes names like it.

    ``usernames`` (a roster's) and ``prefixes`` (what Blackboard's records put before
    ``_<username>_attempt_``) let a Blackboard name whose username holds ``_`` be read.
    """
    return (
        _canvas(name)
        or _moodle_file(name)
        or _blackboard(name, usernames, prefixes)
        or _brightspace(name, True)
    )


def parse_folder(name: str) -> Parsed | None:
    """A student folder's download name (Moodle, Brightspace), or None."""
    m = _MOODLE_DIR.match(name)
    if m:
        kind = "file" if m["plugin"] == "file" else "text"
        return Parsed(MOODLE, m["name"], m["uid"], kind=kind)
    return _brightspace(name, False)


def _canvas(name: str) -> Parsed | None:
    m = _CANVAS_ANON.match(name)
    if m:
        pieces = m["rest"].split("_")
        return _canvas_rest(f"anon_{m['anon']}", "", bool(m["late"]), pieces)
    pieces = name.split("_")
    first = next((i for i, p in enumerate(pieces) if _DIGITS.match(p)), None)
    if first is None or first == 0 or first + 1 >= len(pieces):
        return None
    who = pieces[:first]
    late = who[-1] in ("LATE", "late")
    if late:
        who = who[:-1]
    if not who or not all(canvas_word(w) for w in who):
        return None
    return _canvas_rest(pieces[first], "_".join(who), late, pieces[first + 1 :])


def canvas_word(piece: str) -> bool:
    """Whether ``piece`` (of a name cut at ``_``) is what Canvas leaves of a name: it keeps
    only Ruby's ``[[:word:]]``, letters, marks, decimal digits and connector punctuation.
    Marks count (the vowel signs of Devanagari or Thai, an accent typed as its own
    character), though Python's ``\\w`` leaves them out."""
    return bool(piece) and all(
        unicodedata.category(c)[0] in "LM" or unicodedata.category(c) in ("Nd", "Pc") for c in piece
    )


def _canvas_rest(uid: str, who: str, late: bool, rest: list[str]) -> Parsed | None:
    tail = "_".join(rest)
    if tail in ("text.html", "link.html"):
        return Parsed(CANVAS, who, uid, late=late, kind=tail[:4], orig=tail)
    if len(rest) < 2 or not _DIGITS.match(rest[0]):
        return None
    orig = "_".join(rest[1:])
    again = _REUPLOAD.match(orig)
    order = (int(rest[0]), int(again["n"]) if again else 0)
    return Parsed(CANVAS, who, uid, order, late=late, file_id=rest[0], orig=orig)


def _moodle_file(name: str) -> Parsed | None:
    m = _MOODLE_FILE.match(name)
    if not m:
        return None
    kind = "file" if m["plugin"] == "file" else "text"
    return Parsed(MOODLE, m["name"], m["uid"], orig=m["orig"], kind=kind)


def _blackboard(name: str, usernames=(), prefixes=()) -> Parsed | None:
    m = _BLACKBOARD.match(name)
    record = m is None and name.endswith(".txt")
    if record:
        m = _BLACKBOARD.match(name[:-4])  # the attempt's record, ..._attempt_<ts>.txt
    if m is None or (record and m["orig"]):
        return None
    t = local_time(m["ts"], "%Y-%m-%d-%H-%M-%S")
    user, why = blackboard_username(m["stem"], usernames, prefixes)
    return Parsed(
        BLACKBOARD,
        user,
        user,
        (t or 0.0,),
        t,
        orig="" if record else m["orig"] or "",
        kind="record" if record else "file",
        time_source="download name" if t else "",
        unsure=why,
    )


def blackboard_record(name: str) -> str:
    """The name of the record (``..._attempt_<ts>.txt``) of a Blackboard attempt's file, or
    '' when ``name`` is not one."""
    m = _BLACKBOARD.match(name)
    return f"{m['stem']}_attempt_{m['ts']}.txt" if m and m["orig"] else ""


def blackboard_username(stem: str, usernames=(), prefixes=()) -> tuple[str, str]:
    """The username in ``<prefix>_<username>`` (the part before ``_attempt_``), or
    ('', why not): from a record's known prefix, else the one roster username it ends with,
    else only when the stem holds a single ``_``."""
    for prefix in sorted(prefixes, key=len, reverse=True):
        if prefix and stem.startswith(prefix + "_") and len(stem) > len(prefix) + 1:
            return stem[len(prefix) + 1 :], ""
    ends = [u for u in usernames if u and stem.endswith("_" + u)]
    if len(ends) == 1:
        return ends[0], ""
    if len(ends) > 1:
        return "", f"it could be the attempt of {' or '.join(sorted(ends))} (roster usernames)"
    if stem.count("_") == 1:
        return stem.split("_")[1], ""
    return "", (
        "the name does not say where the assignment's name ends and the username begins, "
        "and Blackboard's record of the attempt (the .txt beside it) is missing"
    )


def _brightspace(name: str, is_file: bool) -> Parsed | None:
    m = _BRIGHTSPACE.match(name)
    if not m or (is_file and not m["orig"]) or (not is_file and m["orig"]):
        return None
    t = brightspace_time(m["date"])
    return Parsed(
        BRIGHTSPACE,
        m["name"],
        "",
        (t or 0.0, int(m["n1"])),
        t,
        orig=m["orig"] or "",
        time_source="download name" if t else "",
    )


_MONTHS = {
    m: i + 1 for i, m in enumerate("Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec".split())
}
_D2L_PARTS = re.compile(r"^([A-Z][a-z]{2}) (\d{1,2}), (\d{4}) (\d{1,2}):?(\d{2}) ([AP]M)$")


def brightspace_time(text: str) -> float | None:
    """``Dec 4, 2026 110 PM`` (a file name: hour and minutes run together), or ``1:10 PM``,
    as local time: the last two digits are the minutes, whatever the hour."""
    m = _D2L_PARTS.match(" ".join(text.split()))
    if not m or m[1] not in _MONTHS:
        return None
    hour, minute = int(m[4]), int(m[5])
    if not 1 <= hour <= 12 or minute > 59:
        return None
    hour = hour % 12 + (12 if m[6] == "PM" else 0)
    try:
        dt = datetime(int(m[3]), _MONTHS[m[1]], int(m[2]), hour, minute)
    except ValueError:
        return None
    return time.mktime(dt.timetuple())


def local_time(text: str, fmt: str) -> float | None:
    """Local time as the LMS wrote it, in seconds since the epoch."""
    try:
        return time.mktime(datetime.strptime(text, fmt).timetuple())
    except (ValueError, OverflowError):
        return None


_time = local_time  # the name this module used before


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


# ----------------------------------------------------------------------------- Blackboard
@dataclass
class BlackboardRecord:
    """One attempt's ``.txt``: who (name, username), when, which files."""

    record: str  # the .txt's own name
    name: str
    username: str
    assignment: str = ""
    submitted_text: str = ""  # "Date Submitted:" as written
    files: dict[str, str] = field(default_factory=dict)  # stored name -> original name
    text: bool = False  # the attempt has text in its submission field
    prefix: str = ""  # what Blackboard put before _<username>_attempt_ (from the name)
    attempt: str = ""  # the attempt's time stamp in the names


_NO_TEXT = ("there is no student submission text data", "there are no student comments")


def read_blackboard_record(record: str, text: str) -> BlackboardRecord | None:
    """A Blackboard attempt record (``..._attempt_<ts>.txt``), or None if it is not one."""
    m = _BLACKBOARD.match(record[:-4]) if record.endswith(".txt") else None
    lines = text.replace("\r\n", "\n").split("\n")
    head = re.match(r"^Name:\s*(.*?)\s*\(([^()]*)\)\s*$", lines[0].strip()) if lines else None
    if m is None or m["orig"] or head is None or not head[2].strip():
        return None
    rec = BlackboardRecord(record, head[1].strip(), head[2].strip(), attempt=m["ts"])
    stem = m["stem"]
    if stem.endswith("_" + rec.username):
        rec.prefix = stem[: -len(rec.username) - 1]
    section, original = "", ""
    for raw in lines[1:]:
        line = raw.strip()
        label, _, value = line.partition(":")
        if not raw.startswith(("\t", " ")) and label in (
            "Assignment",
            "Date Submitted",
            "Current Grade",
            "Submission Field",
            "Comments",
            "Files",
        ):
            section = label
            if label == "Assignment":
                rec.assignment = value.strip()
            elif label == "Date Submitted":
                rec.submitted_text = value.strip()
            continue
        if section == "Submission Field" and line and not line.lower().startswith(_NO_TEXT):
            rec.text = True
        elif section == "Files" and label == "Original filename":
            original = value.strip()
        elif section == "Files" and label == "Filename":
            rec.files[value.strip()] = original
            original = ""
    return rec


# ----------------------------------------------------------------------------- Brightspace
@dataclass
class IndexRow:
    """One row of a Brightspace ``index.html``: who, when, which files."""

    name: str
    when: float | None
    when_text: str
    files: list[str]
    user_id: str = ""


class _Tables(HTMLParser):
    """Every table row of a page: its cells' text and links (``th`` marks a header row)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.rows: list[tuple[bool, list[tuple[str, list[str]]]]] = []
        self._row: list[tuple[str, list[str]]] | None = None
        self._cell: list[str] | None = None
        self._links: list[str] = []
        self._header = False

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self._row, self._header = [], False
        elif tag in ("td", "th") and self._row is not None:
            self._cell, self._links = [], []
            self._header = self._header or tag == "th"
        elif tag == "a" and self._cell is not None:
            href = dict(attrs).get("href") or ""
            if href and not href.startswith(("#", "mailto:", "javascript:")):
                self._links.append(urllib.parse.unquote(href.split("?")[0]).split("/")[-1])
        elif tag == "br" and self._cell is not None:
            self._cell.append("\n")

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._row is not None and self._cell is not None:
            self._row.append(("".join(self._cell).strip(), self._links))
            self._cell = None
        elif tag == "tr" and self._row is not None:
            if self._row:
                self.rows.append((self._header, self._row))
            self._row = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


_ROLES = {
    "id": ("orgdefinedid", "org defined id", "username", "user id", "userid"),
    "name": ("submitted by", "student", "user", "name", "learner"),
    "when": ("date", "submitted", "time"),
    "files": ("file", "attachment", "submission"),
}


def read_brightspace_index(text: str) -> list[IndexRow]:
    """The rows of a Brightspace download's ``index.html`` (``[]`` if it has no table with
    columns for the student, the date and the files)."""
    p = _Tables()
    try:
        p.feed(text)
        p.close()
    except Exception:  # html.parser is lenient; anything it still rejects is no index
        return []
    head = next((cells for is_head, cells in p.rows if is_head), None)
    if head is None:
        return []
    col: dict[str, int] = {}
    for role, words in _ROLES.items():
        for i, (label, _) in enumerate(head):
            lab = label.lower()
            if i not in col.values() and any(w in lab for w in words):
                col[role] = i
                break
    if not {"name", "when", "files"} <= set(col):
        return []
    out = []
    for is_head, cells in p.rows:
        if is_head or len(cells) <= max(col.values()):
            continue
        name = " ".join(cells[col["name"]][0].split())
        when_text = " ".join(cells[col["when"]][0].split())
        text_, links = cells[col["files"]]
        files = links or [f.strip() for f in text_.split("\n") if f.strip()]
        uid = cells[col["id"]][0].strip().lstrip("#") if "id" in col else ""
        if name and files:
            out.append(IndexRow(name, brightspace_time(when_text), when_text, files, uid))
    return out


# ----------------------------------------------------------------------------- a download
#: Largest record (Blackboard .txt) or index.html read, bytes.
MAX_RECORD_BYTES = 4 * 1024 * 1024


def _read_text(path: Path) -> str | None:
    from .studentfiles import ReadFailed, read_in_process

    try:  # a file in the download: no link followed, one name, capped
        return read_in_process(path, MAX_RECORD_BYTES).decode("utf-8-sig", errors="replace")
    except ReadFailed:
        return None


@dataclass
class Download:
    """What an LMS wrote about one class folder's files: Blackboard's attempt records and
    Brightspace's ``index.html``; :meth:`owner` says who handed in each file.

    ``consumed`` are the LMS's own files (records, index), read and never graded.
    """

    records: dict[str, BlackboardRecord] = field(default_factory=dict)  # file -> record
    attempts: list[BlackboardRecord] = field(default_factory=list)
    prefixes: set[str] = field(default_factory=set)
    index: list[IndexRow] = field(default_factory=list)
    usernames: tuple[str, ...] = ()
    consumed: set[str] = field(default_factory=set)
    notes: list[str] = field(default_factory=list)

    @classmethod
    def read(
        cls, folder: Path, names: list[str], usernames=(), reader=_read_text, folders=()
    ) -> Download:
        """Read the LMS's records among ``names`` (the folder's file names).

        ``usernames`` are the roster's Blackboard usernames, if any; ``folders`` the names
        of the folder's sub-folders (Brightspace's folder per submission).
        """
        d = cls(usernames=tuple(u for u in usernames if u))
        brightspace = any(_brightspace(n, True) for n in names) or any(
            _brightspace(n, False) for n in folders
        )
        for name in names:
            p = _blackboard(name)
            if p is not None and p.kind == "record":
                text = reader(folder / name)
                rec = read_blackboard_record(name, text) if text is not None else None
                if rec is None:
                    d.notes.append(f"{name}: not a Blackboard attempt record that can be read")
                    continue
                d.consumed.add(name)
                d.attempts.append(rec)
                if rec.prefix:
                    d.prefixes.add(rec.prefix)
                for stored in rec.files:
                    d.records[stored] = rec
            elif name == BRIGHTSPACE_INDEX and brightspace:
                text = reader(folder / name)
                d.index = read_brightspace_index(text or "")
                d.consumed.add(name)  # Brightspace's own file, whatever it holds
                if not d.index:
                    d.notes.append(
                        f"{name}: Brightspace's index of the download has no table of who "
                        "handed in which file: students are told apart by the file names"
                    )
        return d

    def owner(self, name: str) -> Parsed | None:
        """Who handed in the file ``name`` of this folder (None: no LMS wrote the name)."""
        rec = self.records.get(name)
        if rec is not None:
            t = local_time(rec.attempt, "%Y-%m-%d-%H-%M-%S")
            return Parsed(
                BLACKBOARD,
                rec.name,
                rec.username,
                (t or 0.0,),
                t,
                orig=rec.files[name] or "",
                time_source="download name" if t else "",
            )
        p = parse_file(name, self.usernames, tuple(self.prefixes))
        if p is not None and p.lms == BRIGHTSPACE and self.index:
            self._from_index(name, p)
        return p

    def _from_index(self, name: str, p: Parsed) -> None:
        mine = name_key(p.name)
        rows = [r for r in self.index if name in r.files] or [
            r
            for r in self.index
            if name_key(r.name) in (mine, name_key(" ".join(reversed(r.name.split(", ")))))
            and (p.orig in r.files or not p.orig)
            and (r.when is None or p.submitted_at is None or abs(r.when - p.submitted_at) < 60)
        ]
        if len(rows) != 1:
            return
        row = rows[0]
        p.name, p.lms_id = row.name, row.user_id
        if row.when is not None:
            p.submitted_at, p.time_source = row.when, "Brightspace index.html"
            p.order = (row.when, *p.order[1:])


# ----------------------------------------------------------------------------- Gradescope
class GradescopeError(ValueError):
    """A ``submission_metadata.yml`` that cannot be read; the message says why."""


@dataclass
class Submitter:
    """One student of a Gradescope submission (a group's submission has several)."""

    name: str
    sid: str
    email: str


@dataclass
class GradescopeEntry:
    """One ``submission_<id>`` of Gradescope's export, as ``submission_metadata.yml`` has it."""

    folder: str  # submission_<id>
    submitters: list[Submitter]
    created_at: float | None  # seconds since the epoch
    created_text: str  # as written
    earlier: list[str] = field(default_factory=list)  # :history: times, as written


_GS_TIME = re.compile(
    r"^(\d{4}-\d{2}-\d{2})[ T](\d{2}):(\d{2}):(\d{2})(?:\.(\d+))?\s*(Z|UTC|[+-]\d{2}:?\d{2})?$"
)


def gradescope_time(value: object) -> float | None:
    """``:created_at:`` as seconds since the epoch: Ruby's ``2026-11-20 22:50:12.345678000
    +00:00`` (a string, or the datetime YAML makes of it); no zone is local time."""
    if isinstance(value, datetime):
        dt = value
    elif isinstance(value, date):
        dt = datetime(value.year, value.month, value.day)
    else:
        m = _GS_TIME.match(" ".join(str(value or "").split()))
        if not m:
            return None
        frac = (m[5] or "0")[:6].ljust(6, "0")
        try:
            dt = datetime.fromisoformat(f"{m[1]}T{m[2]}:{m[3]}:{m[4]}.{frac}")
        except ValueError:
            return None
        zone = m[6]
        if zone in ("Z", "UTC"):
            dt = dt.replace(tzinfo=timezone.utc)
        elif zone:
            sign = -1 if zone[0] == "-" else 1
            hh, mm = int(zone[1:3]), int(zone[-2:])
            dt = dt.replace(tzinfo=timezone(sign * timedelta(hours=hh, minutes=mm)))
    if dt.tzinfo is None:
        return time.mktime(dt.timetuple()) + dt.microsecond / 1e6
    return dt.timestamp()


def _field(record: dict, key: str) -> object:
    """A record's value under Gradescope's symbol key (``:name``), or its plain spelling."""
    return record.get(f":{key}", record.get(key))


def _text_of(value: object) -> str:
    return "" if value is None else str(value).strip()


def _submitters(folder: str, raw: object, notes: list[str]) -> list[Submitter]:
    if not isinstance(raw, list):
        notes.append(f"{GRADESCOPE_METADATA}: {folder} has no list of :submitters:")
        return []
    out = []
    for one in raw:
        if not isinstance(one, dict):
            notes.append(f"{GRADESCOPE_METADATA}: {folder}: a submitter that is not a record")
            continue
        s = Submitter(*(_text_of(_field(one, k)) for k in ("name", "sid", "email")))
        if not (s.email or s.sid or s.name):
            notes.append(f"{GRADESCOPE_METADATA}: {folder}: a submitter with no name, sid or email")
            continue
        out.append(s)
    return out


def read_gradescope_metadata(text: str) -> tuple[dict[str, GradescopeEntry], list[str]]:
    """The records of Gradescope's ``submission_metadata.yml`` (folder name -> record), and
    notes on records that cannot be used (left out, each said).

    Raises
    ------
    GradescopeError
        Not YAML, or not a map of submission folders to records.
    """
    import yaml  # type: ignore[import-untyped]  # PyYAML ships no type hints

    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise GradescopeError(f"not YAML that can be read ({exc})") from None
    if not isinstance(data, dict):
        raise GradescopeError("not a map of submission_<id> folders to their records")
    out: dict[str, GradescopeEntry] = {}
    notes: list[str] = []
    for folder, record in data.items():
        folder = str(folder)
        if not isinstance(record, dict):
            notes.append(f"{GRADESCOPE_METADATA}: {folder} has no record of who submitted it")
            continue
        people = _submitters(folder, _field(record, "submitters"), notes)
        created = _field(record, "created_at")
        history = _field(record, "history")
        earlier = [
            _text_of(_field(h, "created_at"))
            for h in (history if isinstance(history, list) else [])
            if isinstance(h, dict)
        ]
        out[folder] = GradescopeEntry(
            folder, people, gradescope_time(created), _text_of(created), earlier
        )
    return out, notes
