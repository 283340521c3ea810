"""Before grading: the submissions matched to the roster, and their times checked.

:func:`match_roster` fills in each submission's roster row (name, e-mail, section, every
LMS id) or says why none: not on the roster, or ambiguous (several rows, or several
students for one row: reported by name, matched to nobody). :func:`time_notes` says when
the times used for lateness cannot be what they claim: file times that all fall within a
few seconds (an unzip or a copy) or all after the due date (those are then not used), and
Canvas's LATE mark disagreeing with the file's time (the mark is used).
"""

from __future__ import annotations

import sqlite3
from pathlib import Path

from . import handedfiles
from .lms import person_key
from .notebook import Submission, shown, student_id
from .policy import UNRELIABLE_TIME, show_time
from .roster import MOODLE_WORKSHEET, Person, RosterEntry, bare, match_people

#: Fewest files whose times are judged together, and the spread under which they are the
#: time of an unzip or a copy (seconds).
SAME_TIME_FILES = 5
SAME_TIME_SECONDS = 5.0


def _read_only(path: Path, sql: str, args: tuple) -> list[tuple]:
    """The rows of ``sql`` in the gradebook ``path`` opened read-only; [] when there is no
    such file or SQLite cannot read it (opening it for grading says why)."""
    if not Path(path).is_file():
        return []
    try:
        conn = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        try:
            return conn.execute(sql, args).fetchall()
        finally:
            conn.close()
    except sqlite3.Error:
        return []


def stored_roster(path: Path, assignment: str) -> list[RosterEntry]:
    """The roster the gradebook ``path`` keeps for ``assignment`` ([] if none, or if the
    file cannot be read: opening it says why)."""
    rows = _read_only(
        path,
        "SELECT entry FROM roster WHERE assignment = ? AND import_id = "
        "(SELECT MAX(import_id) FROM roster WHERE assignment = ?) ORDER BY id",
        (assignment, assignment),
    )
    import json

    fields = RosterEntry.__dataclass_fields__
    return [RosterEntry(**{k: v for k, v in json.loads(r[0]).items() if k in fields}) for r in rows]


def _stored_files(path: Path, assignment: str) -> dict[str, tuple[str, str, list[str]]]:
    """Each student the gradebook ``path`` holds for ``assignment``: (their ``lms``, their
    name, the paths of their files as recorded); {} if none."""
    rows = _read_only(
        path,
        "SELECT s.student, st.lms, st.name, s.path FROM submissions s "
        "JOIN students st ON st.id = s.student WHERE s.assignment = ?",
        (assignment,),
    )
    out: dict[str, tuple[str, str, list[str]]] = {}
    for sid, lms, name, where in rows:
        out.setdefault(sid, (lms, name, []))[2].append(where)
    return out


def keep_folder_students(subs: list[Submission], path: Path, assignment: str) -> list[str]:
    """A notebook passed alone that the class's run found in a student's own folder (one
    folder per student, nbgrader's ``<student>/<assignment>/``) is that student again,
    wherever the command is typed from: the student whose id the folder gives and whose
    files the gradebook ``path`` holds at the same place below that folder (else the file
    is a student of its own, named after it), with the files beside it in that folder
    (:mod:`rikingrade.handedfiles`). The notes say who was kept."""
    stored = (
        _stored_files(path, assignment) if any(s.named and s.lms == "file" for s in subs) else {}
    )
    notes = []
    for s in subs:
        if not (s.named and s.lms == "file"):
            continue
        parts = Path(s.path).parts
        for up in (1, 2):  # <student>/<file>, or <student>/<assignment>/<file>
            if len(parts) <= up:
                break
            sid = student_id(parts[-up - 1])
            lms, name, paths = stored.get(sid, ("", "", []))
            if sid != s.student and any(
                Path(p).parts[-up - 1 :] == parts[-up - 1 :] for p in paths
            ):
                notes.append(
                    f"{s.shown_path}: graded as {sid}, the student of the folder "
                    f"{shown(parts[-up - 1])} when the class was graded"
                )
                s.student, s.lms, s.name = sid, lms, name or s.name
                # the student's folder: their files beside the notebook, as in the class run
                s.handed = handedfiles.beside(s.path)
                break
    return notes


def _fill(s: Submission, e: RosterEntry) -> None:
    """The roster row's details into the submission (the LMS id from the download stays)."""
    s.name = e.name or s.name
    s.email, s.sis_id, s.section = e.email or s.email, e.sis_id or s.sis_id, e.section
    s.login = e.login or s.login
    s.roster_key = e.key
    if s.lms == "moodle" and e.kind == MOODLE_WORKSHEET and e.submitted_at:
        s.submitted_at, s.time_source = e.submitted_at, "Moodle grading worksheet"
    if s.lms in ("canvas", "moodle", "blackboard", "brightspace", "gradescope"):
        return
    # No LMS in the download names (plain folders): the roster's ids are the LMS's.
    if e.canvas_id:
        s.lms, s.lms_id = "canvas", e.canvas_id
    elif e.moodle_id or e.id.startswith("Participant "):
        s.lms, s.lms_id = "moodle", e.moodle_id or e.id.removeprefix("Participant ").strip()
    elif e.kind == "blackboard" and e.username:
        s.lms, s.lms_id = "blackboard", e.username
    elif not s.lms_id and e.kind == "csv":
        s.lms, s.lms_id = "canvas", e.id


def match_roster(
    subs: list[Submission], roster: list[RosterEntry], missing_note: bool = True
) -> list[str]:
    """Match each submission to the roster (see the module); notes on what did not match
    and (``missing_note``) on who on the roster has no submission among ``subs``."""
    people = [
        Person(s.student, s.lms, s.lms_id, s.download_name or s.name, s.student) for s in subs
    ]
    for person, s in zip(people, subs, strict=True):
        if s.lms == "gradescope":  # its record gives both: the roster matches either
            person.ids = tuple(x for x in (s.sis_id, s.email) if x)
    found = match_people(people, roster)
    notes: list[str] = []
    used: set[str] = set()
    unsure: set[str] = set()
    for s in subs:
        m = found[s.student]
        if m.status == "matched" and m.entry is not None:
            _fill(s, m.entry)
            used.add(m.entry.key)
        elif m.status == "ambiguous":
            s.roster_key = "ambiguous:" + person_key(m.rows[0].name if m.rows else s.name)
            unsure |= {e.key for e in m.rows}
            notes.append(f"ambiguous: {s.student} ({s.shown_path}): {m.note}")
        else:
            s.roster_key = "absent"
            notes.append(f"{s.student}: {m.note} ({s.shown_path})")
    missing = [e for e in roster if e.key not in used and e.key not in unsure]
    if missing and missing_note:
        notes.append(
            f"{len(missing)} student(s) on the roster have no submission: "
            + ", ".join(e.name or e.id for e in missing[:10])
            + (" ..." if len(missing) > 10 else "")
        )
    return notes


def ids_of_class(subs: list[Submission], roster: list[RosterEntry]) -> dict[str, str]:
    """Every id an instructor may name a student of ``subs`` by (the download's student id,
    LMS id, name; their roster row's ids: SIS id, e-mail, login, Canvas or Moodle id, the
    Blackboard or Brightspace username and OrgDefinedId with or without ``#``) -> the
    student id the gradebook keeps them under."""
    rows = {e.key: e for e in roster}
    out: dict[str, str] = {}
    for s in subs:
        ids = [s.student, s.lms_id, s.sis_id, s.email, s.login, s.name]
        e = rows.get(s.roster_key)
        if e is not None:
            ids += [e.id, e.sis_id, e.email, e.login, e.canvas_id, e.moodle_id]
            ids += [e.username, bare(e.username), e.org_id, bare(e.org_id)]
        for k in ids:
            if k.strip():
                out.setdefault(k.strip(), s.student)
                out.setdefault(k.strip().casefold(), s.student)
    return out


def _examples(subs: list[Submission], n: int = 4) -> str:
    names = [s.student for s in subs]
    return ", ".join(names[:n]) + (f" and {len(names) - n} more" if len(names) > n else "")


def time_notes(subs: list[Submission], policy) -> list[str]:
    """Warnings on the submission times (see the module); file times that cannot be the
    hand-in times get the time source :data:`rikingrade.policy.UNRELIABLE_TIME`."""
    due = policy["due"] if policy is not None else None
    grace = (policy["grace_minutes"] if policy is not None else 0.0) * 60
    notes = []
    mt = [s for s in subs if s.time_source == "file modification time" and not s.refused]
    times = [s.submitted_at or 0.0 for s in mt]
    same = len(mt) >= SAME_TIME_FILES and max(times) - min(times) <= SAME_TIME_SECONDS
    after = len(mt) >= 3 and due is not None and min(times) > due + grace
    if same or after:
        why = (
            f"all within {SAME_TIME_SECONDS:g} s of each other (the time of an unzip or a copy)"
            if same
            else f"all after the due date ({show_time(due)})"
        )
        notes.append(
            f"the file times of the {len(mt)} submissions that have no other time are {why}: "
            "they are not when the work was handed in, so they are not used for lateness. "
            "Keep the times when unzipping the LMS's download (unzip does; copy with cp -p or "
            "rsync -t), or give the times by --extensions"
        )
        for s in mt:
            s.time_source = UNRELIABLE_TIME
    if due is None:
        return notes
    canvas = [
        s for s in subs if s.lms == "canvas" and not s.refused and s.time_source != UNRELIABLE_TIME
    ]
    early = [s for s in canvas if s.late and (s.submitted_at or 0.0) <= due]
    graced = [s for s in canvas if s.late and due < (s.submitted_at or 0.0) <= due + grace]
    late = [s for s in canvas if not s.late and (s.submitted_at or 0.0) > due + grace]
    if late:
        notes.append(
            f"{len(late)} Canvas submission(s) without Canvas's LATE mark have a file time after "
            f"the due date ({_examples(late)}): Canvas's mark is used, they are on time"
        )
    if early:
        notes.append(
            f"{len(early)} Canvas submission(s) marked LATE by Canvas have a file time before "
            f"the due date ({_examples(early)}): Canvas's mark is used, each counts 1 day late"
        )
    if graced:
        notes.append(
            f"{len(graced)} Canvas submission(s) marked LATE by Canvas were handed in within the "
            f"{grace / 60:g} min grace after the due date, by their file time "
            f"({_examples(graced)}): on time (Canvas's mark knows no grace)"
        )
    return notes
