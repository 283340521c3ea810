"""Rosters as the LMSs export them, and matching submissions to them without guessing.

Read as they are (the kind is told by the columns):

Canvas       gradebook export: ``Student, ID, SIS User ID, SIS Login ID, [Integration ID,]
             Section, <assignment> (<id>), ...``; a ``Points Possible`` row (and a ``Manual
             Posting`` row for assignments posted by hand) under the header; the test
             student ``Student, Test`` is left out.
Moodle       grading worksheet (assignment > Download grading worksheet): ``Identifier``
             (``Participant N``, the id of the download names), ``Full name``, ``Email
             address``, ``Status``, ..., ``Last modified (submission)``; or the course
             gradebook export: ``First name, Last name, ID number, Institution, Department,
             Email address, Assignment: <name> (Real), ...`` (no participant id: matched by
             name).
Blackboard   Grade Center download: ``Last Name, First Name, Username, Student ID, Last
             Access, Availability, <column> [Total Pts: 10 Score] |<column id>``, comma or
             tab delimited, UTF-8 or UTF-16 (the ``.xls`` it offers is tab-delimited UTF-16).
Brightspace  grades export: ``OrgDefinedId, Username, Last Name, First Name, Email, <item>
             Points Grade <Numeric MaxPoints:10>, ..., End-of-Line Indicator`` (ids written
             ``#123``).
Gradescope   grades export (the course's, or one assignment's): ``First Name, Last Name``
             (or ``Name``), ``SID, Email, Sections, <assignment>, <assignment> - Max
             Points, <assignment> - Submission Time, <assignment> - Lateness (H:M:S)``.
Any CSV      with columns id, name, email, SIS id, section, login (any case).

A submission is matched on the id its LMS gives (Canvas user id, Moodle participant id,
Blackboard username, Gradescope SID or e-mail) when the roster has that id; otherwise on the
name (accents, case, spaces and punctuation ignored, first and last in either order). Two
roster rows that fit, or two students that fit one row, are an ambiguity: reported by name,
matched to nobody.
"""

from __future__ import annotations

import csv
import io
import re
import time
import unicodedata
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path

CANVAS_ROSTER = "canvas"
MOODLE_WORKSHEET = "moodle-worksheet"
MOODLE_GRADEBOOK = "moodle"
BLACKBOARD_ROSTER = "blackboard"
BRIGHTSPACE_ROSTER = "brightspace"
GRADESCOPE_ROSTER = "gradescope"
PLAIN = "csv"

#: Which LMS each roster kind belongs to.
LMS_OF = {
    CANVAS_ROSTER: "canvas",
    MOODLE_WORKSHEET: "moodle",
    MOODLE_GRADEBOOK: "moodle",
    BLACKBOARD_ROSTER: "blackboard",
    BRIGHTSPACE_ROSTER: "brightspace",
    GRADESCOPE_ROSTER: "gradescope",
    PLAIN: "",
}


class RosterError(ValueError):
    """A roster file that cannot be used; the message says why."""


@dataclass
class RosterEntry:
    """One student of a roster, with every id the LMS's export gives for them."""

    id: str
    name: str = ""
    email: str = ""
    sis_id: str = ""
    section: str = ""
    login: str = ""
    first: str = ""
    last: str = ""
    canvas_id: str = ""
    moodle_id: str = ""  # the participant id of the assignment (grading worksheet)
    username: str = ""  # Blackboard or Brightspace username, as written in the export
    org_id: str = ""  # Brightspace OrgDefinedId, as written (``#123``)
    submitted_at: float | None = None  # Moodle worksheet: Last modified (submission)
    kind: str = PLAIN
    line: int = 0

    @property
    def key(self) -> str:
        """A stable name for this row (its LMS id, else its name)."""
        for prefix, value in (
            ("canvas", self.canvas_id),
            ("moodle", self.moodle_id),
            ("user", bare(self.username)),
            ("org", bare(self.org_id)),
            ("id", self.id),
            ("sis", self.sis_id),
            ("email", self.email.lower()),
        ):
            if value:
                return f"{prefix}:{value}"
        return f"name:{name_key(self.name)}:{self.line}"

    def names_in_order(self) -> set[str]:
        """The forms of this row's name as written (first name first, or ``Smith, John``
        read as John Smith): a submission's name in this order is this row's before any
        row whose name is the same words the other way round (Li Wei and Wei Li)."""
        forms = {name_key(self.name)}
        if self.first or self.last:
            forms.add(name_key(self.first + self.last))
        if "," in self.name:
            last, _, first = self.name.partition(",")
            forms.add(name_key(first + last))
        return forms - {""}

    def names(self) -> set[str]:
        """The forms of this row's name a submission's name is compared with."""
        forms = {name_key(self.name)}
        if self.first or self.last:
            forms |= {name_key(self.first + self.last), name_key(self.last + self.first)}
        parts = [p for p in re.split(r"[\s,]+", self.name) if p]
        forms.add(name_key("".join(reversed(parts))))
        if "," in self.name:  # "Smith, John"
            last, _, first = self.name.partition(",")
            forms |= {name_key(first + last), name_key(last + first)}
        return forms - {""}

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass
class Roster:
    """A roster file read: its kind, students, and the assignment columns it has."""

    path: str
    kind: str
    entries: list[RosterEntry]
    columns: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def lms(self) -> str:
        return LMS_OF.get(self.kind, "")


def name_key(name: str) -> str:
    """A name as compared: accents, case, spaces and punctuation ignored, any script."""
    text = unicodedata.normalize("NFKD", name).casefold()
    return "".join(ch for ch in text if ch.isalnum() and not unicodedata.combining(ch))


def bare(value: str) -> str:
    """An id as Brightspace exports it (``#123``) without its ``#``."""
    return value.strip().lstrip("#").strip()


# ----------------------------------------------------------------------------- reading
def _text(path: Path, what: str = "the roster") -> str:
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise RosterError(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        return raw.decode("utf-16")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RosterError(
            f"{what} {path} is not UTF-8 text (byte {exc.start}): export it again from "
            "the LMS, or save it from a spreadsheet as 'CSV UTF-8'"
        ) from None


def read_table(path: Path, what: str) -> list[list[str]]:
    """The rows of a CSV ``path`` as an LMS or a spreadsheet saves it (a BOM, UTF-16,
    ``,``/``;``/tab separated); :class:`RosterError` naming ``what`` if it cannot be read."""
    return _rows(_text(Path(path), what))


def _rows(text: str) -> list[list[str]]:
    first = text.split("\n", 1)[0]
    delim = max(",;\t", key=first.count)
    return [r for r in csv.reader(io.StringIO(text), delimiter=delim)]


def _kind(header: list[str]) -> str:
    h = {c.strip().lower() for c in header}
    if "orgdefinedid" in h or "end-of-line indicator" in h:
        return BRIGHTSPACE_ROSTER
    if {"sid", "email"} <= h:
        return GRADESCOPE_ROSTER
    if "identifier" in h and "full name" in h:
        return MOODLE_WORKSHEET
    if {"last name", "first name", "username"} <= h:
        return BLACKBOARD_ROSTER
    if {"first name", "last name"} <= h and ("email address" in h or "id number" in h):
        return MOODLE_GRADEBOOK
    if {"student", "id"} <= h and ("sis user id" in h or "sis login id" in h):
        return CANVAS_ROSTER
    return PLAIN


_PLAIN_COLUMNS = {
    "id": ("id", "student id", "canvas id", "user id", "participant", "identifier", "username"),
    "name": ("name", "student", "full name", "student name"),
    "email": ("email", "email address", "e-mail"),
    "sis_id": ("sis_id", "sis id", "sis user id", "student number", "id number", "idnumber"),
    "section": ("section", "group", "class"),
    "login": ("login", "sis login id", "login id", "netid"),
    "first": ("first name", "given name", "first"),
    "last": ("last name", "surname", "family name", "last"),
}

#: Each kind's columns: field -> the header as the LMS writes it (lower case).
_LMS_COLUMNS = {
    CANVAS_ROSTER: {
        "name": "student",
        "canvas_id": "id",
        "sis_id": "sis user id",
        "login": "sis login id",
        "section": "section",
    },
    MOODLE_WORKSHEET: {
        "moodle_id": "identifier",
        "name": "full name",
        "email": "email address",
        "sis_id": "id number",
        "submitted": "last modified (submission)",
    },
    MOODLE_GRADEBOOK: {
        "first": "first name",
        "last": "last name",
        "sis_id": "id number",
        "email": "email address",
    },
    BLACKBOARD_ROSTER: {
        "last": "last name",
        "first": "first name",
        "username": "username",
        "sis_id": "student id",
    },
    GRADESCOPE_ROSTER: {
        "first": "first name",
        "last": "last name",
        "name": "name",
        "sis_id": "sid",
        "email": "email",
        "section": "sections",
    },
    BRIGHTSPACE_ROSTER: {
        "org_id": "orgdefinedid",
        "username": "username",
        "last": "last name",
        "first": "first name",
        "email": "email",
    },
}

_ASSIGNMENT_COLUMN = {
    CANVAS_ROSTER: re.compile(r"^.+ \(\d+\)$"),
    MOODLE_GRADEBOOK: re.compile(r"^[^:]+: .+$"),
    BLACKBOARD_ROSTER: re.compile(r"^.+\|\s*\d+$"),
    BRIGHTSPACE_ROSTER: re.compile(r"^.+ Points Grade\b.*$"),
}


def load_roster(path: str | Path) -> Roster:
    """A roster file as its LMS exported it (see the module's documentation).

    Raises
    ------
    RosterError
        Unreadable, empty, not UTF-8/UTF-16 text, or with no column that identifies a
        student; the message says what was found.
    """
    path = Path(path)
    rows = _rows(_text(path))
    rows = [r for r in rows if any(c.strip() for c in r)]
    if not rows:
        raise RosterError(f"the roster {path} is empty")
    header = [c.strip().lstrip("#").strip() for c in rows[0]]
    kind = _kind(header)
    roster = Roster(str(path), kind, [])
    if kind == PLAIN:
        col = _plain_columns(path, header)
    else:
        lower = [h.lower() for h in header]
        col = {f: lower.index(h) for f, h in _LMS_COLUMNS[kind].items() if h in lower}
        pat = _ASSIGNMENT_COLUMN.get(kind)
        roster.columns = [
            h for i, h in enumerate(header) if pat and pat.match(h) and i not in col.values()
        ]
        if kind == GRADESCOPE_ROSTER:  # <assignment> beside <assignment> - Max Points
            roster.columns = [h for h in header if f"{h} - Max Points" in header]
    for line, r in enumerate(rows[1:], start=2):
        e = _entry(kind, col, r, line)
        if e is None:
            continue
        if kind == CANVAS_ROSTER and name_key(e.name) == "studenttest":
            roster.notes.append(f"{path}: Canvas's test student ({e.name}) left out")
            continue
        roster.entries.append(e)
    if not roster.entries:
        raise RosterError(f"the roster {path} lists no student (its columns: {', '.join(header)})")
    return roster


def _plain_columns(path: Path, header: list[str]) -> dict[str, int]:
    lower = [h.lower() for h in header]
    col: dict[str, int] = {}
    for f, names in _PLAIN_COLUMNS.items():
        for i, h in enumerate(lower):
            if h in names and i not in col.values():
                col[f] = i
                break
    if not {"id", "sis_id", "email"} & set(col):
        raise RosterError(
            f"the roster {path} has no id column: found {', '.join(header)}; expected an LMS "
            "export (Canvas gradebook, Moodle grading worksheet or gradebook, Blackboard Grade "
            "Center, Brightspace grades) or columns id (or SIS User ID or email), name, email, "
            "SIS id, section"
        )
    return col


def _entry(kind: str, col: dict[str, int], r: list[str], line: int) -> RosterEntry | None:
    get = {f: (r[i].strip() if i < len(r) else "") for f, i in col.items()}
    if kind == CANVAS_ROSTER and (
        get.get("name", "").startswith("Points Possible") or not get.get("canvas_id")
    ):
        return None  # "Points Possible", "Manual Posting" and other rows under the header
    e = RosterEntry("", kind=kind, line=line)
    for f, v in get.items():
        if f == "submitted":
            e.submitted_at = moodle_time(v)
        elif hasattr(e, f):
            setattr(e, f, v)
    if not e.name and (e.first or e.last):
        e.name = f"{e.first} {e.last}".strip()
    if kind == MOODLE_WORKSHEET:
        e.moodle_id = e.moodle_id.removeprefix("Participant").strip()
    e.id = (
        e.id
        or e.canvas_id
        or (f"Participant {e.moodle_id}" if e.moodle_id else "")
        or bare(e.username)
        or bare(e.org_id)
        or e.sis_id
        or e.email
    )
    if not e.id and not e.name:
        return None
    return e


def moodle_time(text: str) -> float | None:
    """Moodle's worksheet time (``Friday, 20 November 2026, 11:10 PM``, local), or None."""
    t = " ".join(text.split())
    for fmt in ("%A, %d %B %Y, %I:%M %p", "%A, %d %B %Y, %H:%M", "%Y-%m-%d %H:%M:%S"):
        try:
            return time.mktime(datetime.strptime(t, fmt).timetuple())
        except ValueError:
            continue
    return None


def read_roster(path: str | Path) -> list[RosterEntry]:
    """The students of a roster file (see :func:`load_roster`)."""
    return load_roster(path).entries


#: How a note of :func:`assignment_column` begins: the run then ends with exit status 1
#: (the LMS file's header is not one the roster has, so the LMS would add a new column).
COLUMN_NOTE = "LMS column: "


def assignment_column(roster: Roster, wanted: str, exercise: str) -> tuple[str, str]:
    """The roster's column for this assignment, and a note ('' when sure; else it begins
    with ``COLUMN_NOTE``).

    ``wanted`` (``--lms-column``) is the header itself or a part of it found in one column
    only; without it, the one column whose header holds the exercise's name.
    """
    cols = roster.columns
    if wanted:
        exact = [c for c in cols if c == wanted]
        some = exact or [c for c in cols if wanted.lower() in c.lower()]
        if len(some) == 1:
            return some[0], ""
        if not cols or not some:
            return wanted, ""  # not in this export: used as written
        return "", (f"{COLUMN_NOTE}--lms-column {wanted!r} fits {len(some)} columns of "
                    f"{roster.path}: " + "; ".join(some))
    some = [c for c in cols if exercise.lower() in c.lower()]
    if len(some) == 1:
        return some[0], ""
    if not cols:
        return "", ""
    listed = "; ".join(some or cols)
    return "", (
        f"{COLUMN_NOTE}which column of {roster.path} is this assignment? "
        + (f"{len(some)} fit" if some else "none holds " + repr(exercise))
        + f" ({listed}): pass --lms-column"
    )


# ----------------------------------------------------------------------------- matching
@dataclass
class Person:
    """A student found in the submissions, as matching sees them."""

    key: str
    lms: str
    lms_id: str
    name: str
    student: str = ""
    ids: tuple[str, ...] = ()  # the LMS's other ids of them (Gradescope: SID and e-mail)


@dataclass
class Match:
    """How one student was matched: ``matched`` (with the row), ``ambiguous`` (several rows,
    or several students for one row: nobody matched) or ``absent`` (not on the roster)."""

    status: str
    entry: RosterEntry | None = None
    note: str = ""
    rows: list[RosterEntry] = field(default_factory=list)


#: The roster fields holding each LMS's own id (an LMS export has them: the id decides).
_LMS_IDS = {
    "canvas": ("canvas_id",),
    "moodle": ("moodle_id",),
    "blackboard": ("username",),
    "brightspace": ("org_id", "username"),
    "gradescope": ("sis_id", "email"),
}
_ANY_IDS = ("id", "sis_id", "login", "username", "canvas_id", "moodle_id", "org_id")


def _id_of(e: RosterEntry, f: str) -> str:
    v = getattr(e, f)
    if f in ("username", "org_id"):
        return bare(v)
    return v.removeprefix("Participant ").strip() if f == "id" else v


def _by_id(p: Person, entries: list[RosterEntry]) -> tuple[bool, list[RosterEntry]]:
    """(whether the roster is this LMS's export, with its ids; the rows with this student's
    id). A Blackboard username, or a plain folder's name, also matches an e-mail's user part."""
    own = _LMS_IDS.get(p.lms, ())
    has = bool(p.lms_id) and any(_id_of(e, f) for e in entries for f in own)
    wanted = {p.lms_id, *p.ids} if p.lms in _LMS_IDS else {p.lms_id, p.student}
    wanted -= {""}
    if not wanted:
        return False, []
    fields = own + ("id",) if p.lms in ("canvas", "moodle", "gradescope") else own or _ANY_IDS
    if p.lms == "blackboard":
        fields = ("username", "login", "id")
    mail = p.lms not in ("canvas", "moodle", "brightspace", "gradescope")
    hits = [
        e
        for e in entries
        if any(_id_of(e, f) in wanted for f in fields)
        or (mail and e.email and e.email.split("@")[0] in wanted)
    ]
    return has, hits


def _named(name: str, entries: list[RosterEntry]) -> list[RosterEntry]:
    """The rows named ``name``: those with its words in its order, else (none such) those
    with them the other way round (a download naming people last name first)."""
    key = name_key(name)
    if not key:
        return []
    same = [e for e in entries if key in e.names_in_order()]
    if same:
        return same
    mine = {key, name_key("".join(reversed(name.split())))} - {""}
    return [e for e in entries if mine & e.names()]


def match_people(people: list[Person], entries: list[RosterEntry]) -> dict[str, Match]:
    """Each student's match (keyed by :attr:`Person.key`); see the module's documentation."""
    out: dict[str, Match] = {}
    by_name: dict[int, list[str]] = {}
    for p in people:
        has_ids, hits = _by_id(p, entries)
        if len(hits) == 1:
            out[p.key] = Match("matched", hits[0])
            continue
        if len(hits) > 1:
            out[p.key] = Match(
                "ambiguous", rows=hits, note=f"{len(hits)} roster rows have the id {p.lms_id}"
            )
            continue
        named = _named(p.name, entries)
        if has_ids:  # the LMS's id decides: a row with the same name is someone else
            also = (
                f" (roster has {', '.join(e.name for e in named)} under another id)"
                if named
                else ""
            )
            out[p.key] = Match("absent", note=f"not on the roster{also}")
        elif len(named) == 1:
            out[p.key] = Match("matched", named[0])
            by_name.setdefault(id(named[0]), []).append(p.key)
        elif len(named) > 1:
            out[p.key] = Match(
                "ambiguous",
                rows=named,
                note=f"{len(named)} roster rows are named {p.name} ("
                + ", ".join(e.id or e.email or f"line {e.line}" for e in named)
                + "): matched to none",
            )
        else:
            out[p.key] = Match("absent", note="not on the roster")
    names = {p.key: p for p in people}
    for keys in by_name.values():
        if len(keys) > 1:  # two students, one roster row: neither is matched
            row = out[keys[0]].entry
            assert row is not None
            for k in keys:
                out[k] = Match(
                    "ambiguous",
                    rows=[row],
                    note=f"{len(keys)} students ("
                    + ", ".join(f"{names[x].name} {names[x].lms_id}".strip() for x in keys)
                    + f") fit the one roster row {row.name} ({row.id}): matched to none",
                )
    return out


def match_roster(parsed, raw_name: str, roster: list[RosterEntry]) -> RosterEntry | None:
    """The one roster row a submission belongs to, or None (none, or several: ambiguous)."""
    p = Person(
        getattr(parsed, "key", "x"),
        getattr(parsed, "lms", "") or "",
        getattr(parsed, "lms_id", "") or "",
        getattr(parsed, "name", "") or raw_name,
        raw_name,
    )
    m = match_people([p], roster)[p.key]
    if m.entry is None and parsed is not None and raw_name and raw_name != p.name:
        p.name = raw_name
        m = match_people([p], roster)[p.key]
    return m.entry
