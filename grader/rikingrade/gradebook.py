"""The course gradebook: one SQLite database that never loses or rewrites a grade.

Tables (nothing is ever updated in place except a run's end, nor deleted)::

    students     one row per student id: name, email, SIS id, section, LMS ids
    submissions  one row per file a student handed in for an assignment, and when
                 (sha256, path, attempt time and where that time came from, LMS late flag)
    runs         one row per ``rikin-grade`` invocation: grader version, seed, settings key,
                 arguments, start/end, how it ended (running, finished, interrupted)
    results      one row per grading of a submission: status, score, the full result (JSON)
    test_points  per result and hidden test: weight, points, fraction, feedback
    picks        which submission counts for a student, as decided by a run (the newest
                 attempt it saw); written in the same transaction as the result, so a run
                 killed half-way leaves every student with the last grade committed
    policies, extensions, overrides
                 late rules, per-student due dates, manual grades (newest row applies)

A regrade adds results and picks for the students it graded only; grades.csv and the other
exports are views of the newest pick and result of each student. The database runs in WAL
mode with one writer: :meth:`Gradebook.open` takes an exclusive lock on ``<db>.lock`` for
the process's lifetime (a second grader on the same gradebook is refused with the holder's
pid), and every write is one transaction, so a kill at any moment leaves either all of a
submission's rows or none.
"""

from __future__ import annotations

import fcntl
import json
import os
import sqlite3
import threading
import time
import uuid
from pathlib import Path
from typing import Any

from .notebook import printable
from .report import SubmissionResult

SCHEMA_VERSION = 2

SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS students (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL DEFAULT '',
    email TEXT NOT NULL DEFAULT '',
    sis_id TEXT NOT NULL DEFAULT '',
    login TEXT NOT NULL DEFAULT '',
    section TEXT NOT NULL DEFAULT '',
    canvas_id TEXT NOT NULL DEFAULT '',
    moodle_id TEXT NOT NULL DEFAULT '',
    lms TEXT NOT NULL DEFAULT '',
    lms_id TEXT NOT NULL DEFAULT '',
    first_seen REAL NOT NULL,
    roster_key TEXT NOT NULL DEFAULT ''
);
CREATE TABLE IF NOT EXISTS assignments (
    name TEXT PRIMARY KEY,
    max_score REAL NOT NULL,
    tests TEXT NOT NULL,
    first_seen REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS submissions (
    id INTEGER PRIMARY KEY,
    student TEXT NOT NULL REFERENCES students(id),
    assignment TEXT NOT NULL REFERENCES assignments(name),
    sha256 TEXT NOT NULL,
    path TEXT NOT NULL,
    submitted_at REAL NOT NULL,
    time_source TEXT NOT NULL DEFAULT '',
    lms_late INTEGER NOT NULL DEFAULT 0,
    first_seen REAL NOT NULL,
    UNIQUE (student, assignment, sha256, submitted_at)
);
CREATE TABLE IF NOT EXISTS runs (
    id INTEGER PRIMARY KEY,
    assignment TEXT NOT NULL,
    grader_version TEXT NOT NULL,
    seed INTEGER NOT NULL,
    key TEXT NOT NULL,
    args TEXT NOT NULL,
    pid INTEGER NOT NULL,
    started_at REAL NOT NULL,
    ended_at REAL,
    state TEXT NOT NULL DEFAULT 'running',
    summary TEXT
);
CREATE TABLE IF NOT EXISTS results (
    id INTEGER PRIMARY KEY,
    run_id INTEGER NOT NULL REFERENCES runs(id),
    submission_id INTEGER NOT NULL REFERENCES submissions(id),
    student TEXT NOT NULL,
    assignment TEXT NOT NULL,
    key TEXT NOT NULL,
    seed INTEGER NOT NULL,
    status TEXT NOT NULL,
    reason TEXT NOT NULL,
    score REAL NOT NULL,
    max_score REAL NOT NULL,
    elapsed REAL NOT NULL,
    graded_at REAL NOT NULL,
    result TEXT NOT NULL
);
CREATE INDEX IF NOT EXISTS results_by_submission ON results (submission_id, key);
CREATE TABLE IF NOT EXISTS test_points (
    result_id INTEGER NOT NULL REFERENCES results(id),
    test TEXT NOT NULL,
    weight REAL NOT NULL,
    points REAL NOT NULL,
    fraction REAL NOT NULL,
    feedback TEXT NOT NULL,
    timed_out INTEGER NOT NULL,
    crashed INTEGER NOT NULL,
    grader_error INTEGER NOT NULL,
    PRIMARY KEY (result_id, test)
);
CREATE TABLE IF NOT EXISTS picks (
    id INTEGER PRIMARY KEY,
    run_id INTEGER NOT NULL REFERENCES runs(id),
    student TEXT NOT NULL,
    assignment TEXT NOT NULL,
    submission_id INTEGER NOT NULL REFERENCES submissions(id),
    result_id INTEGER NOT NULL REFERENCES results(id),
    picked_at REAL NOT NULL
);
CREATE INDEX IF NOT EXISTS picks_by_student ON picks (assignment, student, id);
CREATE TABLE IF NOT EXISTS policies (
    id INTEGER PRIMARY KEY,
    assignment TEXT NOT NULL,
    due REAL,
    per_day REAL NOT NULL,
    cap REAL NOT NULL,
    grace_minutes REAL NOT NULL,
    created_at REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS extensions (
    id INTEGER PRIMARY KEY,
    student TEXT NOT NULL,
    assignment TEXT NOT NULL,
    due REAL NOT NULL,
    reason TEXT NOT NULL,
    created_at REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS overrides (
    id INTEGER PRIMARY KEY,
    student TEXT NOT NULL,
    assignment TEXT NOT NULL,
    kind TEXT NOT NULL CHECK (kind IN ('score', 'excused', 'cleared')),
    score REAL,
    reason TEXT NOT NULL,
    created_at REAL NOT NULL
);
-- Rosters as exported by the LMS, one import per --roster run (the newest applies).
CREATE TABLE IF NOT EXISTS roster (
    id INTEGER PRIMARY KEY,
    import_id INTEGER NOT NULL,
    assignment TEXT NOT NULL,
    kind TEXT NOT NULL,
    source TEXT NOT NULL,
    key TEXT NOT NULL,
    entry TEXT NOT NULL,
    created_at REAL NOT NULL
);
CREATE INDEX IF NOT EXISTS roster_by_assignment ON roster (assignment, import_id);
-- Per-assignment settings (the LMS's column, the policy for missing work); newest applies.
CREATE TABLE IF NOT EXISTS settings (
    id INTEGER PRIMARY KEY,
    assignment TEXT NOT NULL,
    key TEXT NOT NULL,
    value TEXT NOT NULL,
    created_at REAL NOT NULL
);
"""

#: The grade that counts: of each student's picks, the one of the submission handed in last
#: (an earlier attempt regraded alone does not replace it), the newest pick of that one.
CURRENT_VIEW = """CREATE VIEW current AS
SELECT p.assignment, p.student, p.submission_id, p.run_id, r.id AS result_id, r.status,
       r.reason, r.score, r.max_score, r.seed, r.key, r.graded_at, r.result,
       s.sha256, s.path, s.submitted_at, s.time_source, s.lms_late
FROM picks p
JOIN results r ON r.id = p.result_id
JOIN submissions s ON s.id = p.submission_id
WHERE p.id = (SELECT p2.id FROM picks p2 JOIN submissions s2 ON s2.id = p2.submission_id
              WHERE p2.assignment = p.assignment AND p2.student = p.student
              ORDER BY s2.submitted_at DESC, p2.id DESC LIMIT 1)"""


class GradebookBusy(RuntimeError):
    """Another grader process holds the gradebook."""


class GradebookDamaged(RuntimeError):
    """The gradebook file cannot be used as it is (damaged, empty, not a gradebook, or
    missing results that the output folder holds); ``why`` says what was found."""

    def __init__(self, path: Path, why: str) -> None:
        super().__init__(f"{path}: {why}")
        self.path = Path(path)
        self.why = why
        self.advice = ""  # the paragraph for the instructor, with the repair command

    def __str__(self) -> str:
        return self.advice or super().__str__()


_MAGIC = b"SQLite format 3\x00"


def _text(s: Any) -> str:
    """Text SQLite and every output can hold (see :func:`rikingrade.notebook.printable`)."""
    return printable(str(s))


def lock(path: str | Path) -> int:
    """Take the one-writer lock of the gradebook ``path`` (``<path>.lock``); its fd.

    Raises
    ------
    GradebookBusy
        Another process holds it (the message gives its pid).
    """
    fd = os.open(f"{path}.lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = os.pread(fd, 32, 0).decode(errors="replace").strip()
        os.close(fd)
        raise GradebookBusy(
            f"another rikin-grade (pid {holder or '?'}) is writing {path}; "
            "wait for it to finish (one writer per gradebook)"
        ) from None
    os.ftruncate(fd, 0)
    os.pwrite(fd, str(os.getpid()).encode(), 0)
    return fd


def _check_file(path: Path) -> None:
    """Refuse a file that is not an SQLite database. (An empty file is a new database to
    SQLite, as to the grader: the output folder's grades tell a gradebook emptied by
    accident, see :func:`rikingrade.repair.check`.)"""
    try:
        with open(path, "rb") as f:
            head = f.read(16)
    except FileNotFoundError:
        return
    except OSError as exc:
        raise GradebookDamaged(path, f"cannot be read ({exc.strerror})") from None
    if head and head != _MAGIC:
        raise GradebookDamaged(
            path, "the file is not an SQLite database (damaged, or another file)"
        )


def _connect(path: Path, readonly: bool) -> sqlite3.Connection:
    """Open and check the database: SQLite's quick check, and that it is a gradebook."""
    existed = path.exists()
    _check_file(path)
    conn = sqlite3.connect(path, timeout=30, isolation_level=None, check_same_thread=False)
    conn.row_factory = sqlite3.Row
    try:
        if existed:
            bad = [r[0] for r in conn.execute("PRAGMA quick_check") if r[0] != "ok"]
            if bad:
                raise GradebookDamaged(path, f"SQLite finds it damaged ({bad[0]})")
            tables = {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
            if tables and ("meta" not in tables or "results" not in tables):
                raise GradebookDamaged(path, "an SQLite database, but not a rikin-grade gradebook")
        if not readonly:
            conn.execute("PRAGMA journal_mode=WAL")
            conn.execute("PRAGMA synchronous=FULL")
            conn.execute("PRAGMA foreign_keys=ON")
            conn.executescript("BEGIN;" + SCHEMA + "COMMIT;")
            _migrate(conn)
            # the .sqlite alone holds everything committed before this run (and its id)
            conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
            # A run still 'running' was killed (this process holds the lock now).
            conn.execute(
                "UPDATE runs SET state = 'interrupted' WHERE state = 'running' AND ended_at IS NULL"
            )
    except sqlite3.DatabaseError as exc:
        conn.close()
        raise GradebookDamaged(path, f"SQLite cannot read it ({exc})") from None
    except BaseException:
        conn.close()
        raise
    return conn


def _migrate(conn: sqlite3.Connection) -> None:
    """Bring a gradebook of an earlier version up to this schema (columns added, the view
    of the grade that counts replaced)."""
    cols = {r[1] for r in conn.execute("PRAGMA table_info(students)")}
    if "roster_key" not in cols:
        conn.execute("ALTER TABLE students ADD COLUMN roster_key TEXT NOT NULL DEFAULT ''")
    view = conn.execute("SELECT sql FROM sqlite_master WHERE name = 'current'").fetchone()
    if view is None or view[0] != CURRENT_VIEW:  # new, or the view of an earlier version
        conn.execute("DROP VIEW IF EXISTS current")
        conn.execute(CURRENT_VIEW)
    conn.execute("INSERT OR IGNORE INTO meta VALUES ('schema_version', ?)", (str(SCHEMA_VERSION),))
    conn.execute("UPDATE meta SET value = ? WHERE key = 'schema_version'", (str(SCHEMA_VERSION),))
    conn.execute("INSERT OR IGNORE INTO meta VALUES ('gradebook_id', ?)", (uuid.uuid4().hex,))


def backup(src: str | Path, dst: str | Path) -> Path:
    """Copy the gradebook ``src`` into the one consistent file ``dst`` with SQLite's backup
    API (it includes what is still in ``src``'s -wal; a grader may be writing meanwhile).

    Raises
    ------
    GradebookDamaged
        ``src`` cannot be read as a gradebook.
    FileExistsError
        ``dst`` exists (a backup is never overwritten).
    """
    src, dst = Path(src), Path(dst)
    if dst.exists():
        raise FileExistsError(f"{dst} exists: a backup is never overwritten")
    conn = _connect(src, readonly=True)
    tmp = dst.with_name(f".{dst.name}.tmp")
    try:
        out = sqlite3.connect(tmp)
        try:
            conn.backup(out)
            out.execute("PRAGMA journal_mode=DELETE")
        finally:
            out.close()
        os.replace(tmp, dst)
    finally:
        conn.close()
        tmp.unlink(missing_ok=True)
    return dst


class Gradebook:
    """One course's gradebook file; use :meth:`open` (one writer per file)."""

    def __init__(self, path: Path, conn: sqlite3.Connection, lock_fd: int | None) -> None:
        self.path = path
        self.conn = conn
        self._lock_fd = lock_fd
        self._mutex = threading.Lock()

    # ------------------------------------------------------------------ opening
    @classmethod
    def open(
        cls, path: str | Path, readonly: bool = False, lock_fd: int | None = None
    ) -> Gradebook:
        """Open (creating if needed) the gradebook at ``path`` as its only writer
        (``lock_fd``: the lock, already taken with :func:`lock`).

        Raises
        ------
        GradebookBusy
            Another process writes it.
        GradebookDamaged
            It cannot be used as it is (damaged, empty, not a gradebook).
        """
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        if not readonly and lock_fd is None:
            lock_fd = lock(path)
        try:
            conn = _connect(path, readonly)
        except BaseException:
            if lock_fd is not None:
                os.close(lock_fd)
            raise
        return cls(path, conn, lock_fd)

    def close(self) -> None:
        if self._lock_fd is not None:
            try:  # at rest the .sqlite alone holds every grade (a copy without -wal too)
                self.conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
            except sqlite3.Error:
                pass
        self.conn.close()
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None

    def __enter__(self) -> Gradebook:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _tx(self):
        return _Tx(self)

    # ------------------------------------------------------------------ runs
    def start_run(
        self, assignment: str, version: str, seed: int, key: str, args: dict[str, Any]
    ) -> int:
        with self._tx() as c:
            cur = c.execute(
                "INSERT INTO runs (assignment, grader_version, seed, key, args, pid, started_at)"
                " VALUES (?, ?, ?, ?, ?, ?, ?)",
                (
                    assignment,
                    version,
                    int(seed),
                    key,
                    json.dumps(args, default=str),
                    os.getpid(),
                    time.time(),
                ),
            )
            return int(cur.lastrowid)

    def end_run(self, run_id: int, state: str, summary: dict[str, Any] | None = None) -> None:
        with self._tx() as c:
            c.execute(
                "UPDATE runs SET ended_at = ?, state = ?, summary = ? WHERE id = ?",
                (time.time(), state, json.dumps(summary) if summary else None, run_id),
            )

    def runs(self, assignment: str | None = None) -> list[sqlite3.Row]:
        q = "SELECT * FROM runs" + (" WHERE assignment = ?" if assignment else "") + " ORDER BY id"
        return self.conn.execute(q, (assignment,) if assignment else ()).fetchall()

    # ------------------------------------------------------------------ students, files
    def add_assignment(self, name: str, max_score: float, tests: list[tuple[str, float]]) -> None:
        with self._tx() as c:
            c.execute(
                "INSERT INTO assignments VALUES (?, ?, ?, ?) ON CONFLICT (name) DO UPDATE SET "
                "max_score = excluded.max_score, tests = excluded.tests",
                (name, float(max_score), json.dumps(tests), time.time()),
            )

    def tests(self, assignment: str) -> list[tuple[str, float]]:
        row = self.conn.execute(
            "SELECT tests FROM assignments WHERE name = ?", (assignment,)
        ).fetchone()
        return [tuple(t) for t in json.loads(row["tests"])] if row else []

    def max_score(self, assignment: str) -> float:
        row = self.conn.execute(
            "SELECT max_score FROM assignments WHERE name = ?", (assignment,)
        ).fetchone()
        return float(row["max_score"]) if row else 0.0

    def add_student(self, sid: str, **info: str) -> None:
        """Insert a student, or fill in what was unknown about them (never blanks a field)."""
        cols = (
            "name",
            "email",
            "sis_id",
            "login",
            "section",
            "canvas_id",
            "moodle_id",
            "lms",
            "lms_id",
        )
        values = {k: _text(info.get(k) or "") for k in cols}
        with self._tx() as c:
            c.execute(
                f"INSERT OR IGNORE INTO students (id, {', '.join(cols)}, first_seen) "
                f"VALUES (?, {', '.join('?' for _ in cols)}, ?)",
                (sid, *values.values(), time.time()),
            )
            for k, v in values.items():
                if v:
                    c.execute(f"UPDATE students SET {k} = ? WHERE id = ? AND {k} != ?", (v, sid, v))

    def students(self, student: str | None = None) -> dict[str, sqlite3.Row]:
        """Every student (or the one ``student``), by id."""
        q = "SELECT * FROM students"
        args: tuple[str, ...] = ()
        if student is not None:
            q, args = q + " WHERE id = ?", (student,)
        return {r["id"]: r for r in self.conn.execute(q, args)}

    def add_submission(
        self,
        student: str,
        assignment: str,
        sha256: str,
        path: str,
        submitted_at: float | None,
        time_source: str = "",
        lms_late: bool = False,
    ) -> int:
        """The submission's id (the same file handed in at the same time is one submission;
        the same content handed in again later is a new one: its time may be late)."""
        submitted_at = float(submitted_at or 0.0)
        with self._tx() as c:
            c.execute(
                "INSERT OR IGNORE INTO submissions (student, assignment, sha256, path, "
                "submitted_at, time_source, lms_late, first_seen) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    student,
                    assignment,
                    sha256,
                    _text(path),
                    submitted_at,
                    time_source,
                    int(lms_late),
                    time.time(),
                ),
            )
            row = c.execute(
                "SELECT id FROM submissions WHERE student = ? AND assignment = ? AND sha256 = ? "
                "AND submitted_at = ?",
                (student, assignment, sha256, submitted_at),
            ).fetchone()
            return int(row["id"])

    def submissions(self, assignment: str, student: str | None = None) -> list[sqlite3.Row]:
        q = "SELECT * FROM submissions WHERE assignment = ?"
        args: tuple = (assignment,)
        if student is not None:
            q += " AND student = ?"
            args += (student,)
        return self.conn.execute(q + " ORDER BY id", args).fetchall()

    # ------------------------------------------------------------------ results
    def cached(self, submission_id: int, key: str) -> SubmissionResult | None:
        """The newest result of this file (this student, the same content) graded with these
        settings, or None."""
        row = self.conn.execute(
            "SELECT r.id, r.result FROM results r "
            "JOIN submissions s ON s.id = r.submission_id "
            "JOIN submissions me ON me.id = ? "
            "WHERE s.student = me.student AND s.assignment = me.assignment "
            "AND s.sha256 = me.sha256 AND r.key = ? ORDER BY r.id DESC LIMIT 1",
            (submission_id, key),
        ).fetchone()
        if row is None:
            return None
        try:
            res = SubmissionResult.from_dict(json.loads(row["result"]))
        except (ValueError, TypeError, KeyError):
            return None
        res.result_id = int(row["id"])  # type: ignore[attr-defined]
        return res

    def record(
        self,
        run_id: int,
        submission_id: int,
        res: SubmissionResult,
        assignment: str,
        seed: int,
        reuse: int | None = None,
        graded_at: float | None = None,
    ) -> int:
        """Commit a result and make it the student's grade, in one transaction.

        ``reuse`` is the id of an earlier result with the same file and settings (a resumed
        submission): only the pick is written, no second copy of the result. ``graded_at``
        (default now) is when it was graded (a result restored by a repair keeps its own).
        """
        now = time.time()
        graded = now if graded_at is None else float(graded_at)
        with self._tx() as c:
            if reuse is None:
                data = json.dumps(res.to_dict(), ensure_ascii=True)
                cur = c.execute(
                    "INSERT INTO results (run_id, submission_id, student, assignment, key, seed,"
                    " status, reason, score, max_score, elapsed, graded_at, result)"
                    " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    (
                        run_id,
                        submission_id,
                        res.student,
                        assignment,
                        res.key,
                        int(seed),
                        res.status,
                        _text(res.reason),
                        res.score,
                        res.max_score,
                        res.elapsed,
                        graded,
                        data,
                    ),
                )
                result_id = int(cur.lastrowid)
                c.executemany(
                    "INSERT INTO test_points VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    [
                        (
                            result_id,
                            t.name,
                            t.weight,
                            t.points,
                            t.fraction,
                            _text(t.feedback),
                            int(t.timed_out),
                            int(t.crashed),
                            int(t.grader_error),
                        )
                        for t in res.tests
                    ],
                )
            else:
                result_id = reuse
            c.execute(
                "INSERT INTO picks (run_id, student, assignment, submission_id, result_id, "
                "picked_at) VALUES (?, ?, ?, ?, ?, ?)",
                (run_id, res.student, assignment, submission_id, result_id, now),
            )
            return result_id

    def has_result(self, student: str, assignment: str, sha256: str, key: str) -> bool:
        """Whether this student's file was graded with these settings (any run)."""
        row = self.conn.execute(
            "SELECT 1 FROM results r JOIN submissions s ON s.id = r.submission_id "
            "WHERE r.student = ? AND r.assignment = ? AND s.sha256 = ? AND r.key = ? LIMIT 1",
            (student, assignment, sha256, key),
        ).fetchone()
        return row is not None

    def current(self, assignment: str, student: str | None = None) -> list[sqlite3.Row]:
        """Each student's grade that counts (newest pick), sorted by student id (or the one
        of ``student``)."""
        if student is not None:
            return self.conn.execute(
                "SELECT * FROM current WHERE assignment = ? AND student = ?", (assignment, student)
            ).fetchall()
        return self.conn.execute(
            "SELECT * FROM current WHERE assignment = ? ORDER BY student", (assignment,)
        ).fetchall()

    def run_results(self, run_id: int) -> list[sqlite3.Row]:
        """The results a run graded or resumed (its picks), sorted by student."""
        return self.conn.execute(
            "SELECT p.student, r.* FROM picks p JOIN results r ON r.id = p.result_id "
            "WHERE p.run_id = ? ORDER BY p.student",
            (run_id,),
        ).fetchall()

    def history(self, assignment: str, student: str) -> list[sqlite3.Row]:
        return self.conn.execute(
            "SELECT r.id, r.run_id, r.status, r.score, r.graded_at, s.sha256, s.path "
            "FROM results r JOIN submissions s ON s.id = r.submission_id "
            "WHERE r.assignment = ? AND r.student = ? ORDER BY r.id",
            (assignment, student),
        ).fetchall()

    # ------------------------------------------------------------------ policy
    def set_policy(
        self, assignment: str, due: float | None, per_day: float, cap: float, grace: float
    ) -> None:
        """Record the late rules, unless they are the ones already in force."""
        cur = self.policy(assignment)
        new = (due, float(per_day), float(cap), float(grace))
        if (
            cur is not None
            and (cur["due"], cur["per_day"], cur["cap"], cur["grace_minutes"]) == new
        ):
            return
        with self._tx() as c:
            c.execute(
                "INSERT INTO policies (assignment, due, per_day, cap, grace_minutes, created_at)"
                " VALUES (?, ?, ?, ?, ?, ?)",
                (assignment, *new, time.time()),
            )

    def policy(self, assignment: str) -> sqlite3.Row | None:
        return self.conn.execute(
            "SELECT * FROM policies WHERE assignment = ? ORDER BY id DESC LIMIT 1", (assignment,)
        ).fetchone()

    def add_extension(self, student: str, assignment: str, due: float, reason: str) -> None:
        cur = self.extensions(assignment).get(student)
        if cur is not None and cur["due"] == due and cur["reason"] == reason:
            return
        with self._tx() as c:
            c.execute(
                "INSERT INTO extensions (student, assignment, due, reason, created_at) "
                "VALUES (?, ?, ?, ?, ?)",
                (student, assignment, float(due), _text(reason), time.time()),
            )

    def extensions(self, assignment: str, student: str | None = None) -> dict[str, sqlite3.Row]:
        """Each student's extension in force (the newest), or the one of ``student``."""
        q = "SELECT * FROM extensions WHERE assignment = ?"
        args: tuple[str, ...] = (assignment,)
        if student is not None:
            q, args = q + " AND student = ?", (assignment, student)
        return {r["student"]: r for r in self.conn.execute(q + " ORDER BY id", args)}

    def add_override(
        self, student: str, assignment: str, kind: str, score: float | None, reason: str
    ) -> None:
        if not reason.strip():
            raise ValueError("an override needs a reason (it is shown to the student)")
        with self._tx() as c:
            c.execute(
                "INSERT INTO overrides (student, assignment, kind, score, reason, created_at) "
                "VALUES (?, ?, ?, ?, ?, ?)",
                (student, assignment, kind, score, _text(reason), time.time()),
            )

    def overrides(self, assignment: str, student: str | None = None) -> dict[str, sqlite3.Row]:
        """Each student's override in force (a 'cleared' one means none), or the one of
        ``student``."""
        q = "SELECT * FROM overrides WHERE assignment = ?"
        args: tuple[str, ...] = (assignment,)
        if student is not None:
            q, args = q + " AND student = ?", (assignment, student)
        out = {r["student"]: r for r in self.conn.execute(q + " ORDER BY id", args)}
        return {k: v for k, v in out.items() if v["kind"] != "cleared"}

    # ------------------------------------------------------------------ identity
    def gradebook_id(self) -> str:
        """A random id of this gradebook, written in every result file of its views."""
        row = self.conn.execute("SELECT value FROM meta WHERE key = 'gradebook_id'").fetchone()
        return row["value"] if row else ""

    # ------------------------------------------------------------------ roster, settings
    def set_roster(
        self, assignment: str, kind: str, source: str, entries: list[tuple[str, dict]]
    ) -> int:
        """Record a roster import for ``assignment`` (``(key, row)`` pairs); it applies from
        now on (earlier imports are kept). Returns the import's id."""
        now = time.time()
        with self._tx() as c:
            row = c.execute("SELECT COALESCE(MAX(import_id), 0) + 1 FROM roster").fetchone()
            imp = int(row[0])
            c.executemany(
                "INSERT INTO roster (import_id, assignment, kind, source, key, entry, created_at)"
                " VALUES (?, ?, ?, ?, ?, ?, ?)",
                [
                    (imp, assignment, kind, _text(source), key, json.dumps(e, default=str), now)
                    for key, e in entries
                ],
            )
            return imp

    def roster(self, assignment: str, key: str | None = None) -> tuple[str, list[tuple[str, dict]]]:
        """The roster in force for ``assignment``: its kind and ``(key, row)`` pairs (only
        the row of ``key``, when given)."""
        q = (
            "SELECT kind, key, entry FROM roster WHERE assignment = ? AND import_id = "
            "(SELECT MAX(import_id) FROM roster WHERE assignment = ?)"
        )
        args: tuple = (assignment, assignment)
        if key is not None:
            q, args = q + " AND key = ?", (*args, key)
        rows = self.conn.execute(q + " ORDER BY id", args).fetchall()
        if not rows:
            return "", []
        return rows[0]["kind"], [(r["key"], json.loads(r["entry"])) for r in rows]

    def roster_kind(self, assignment: str) -> str:
        """The kind of the roster in force for ``assignment`` ('' when there is none)."""
        row = self.conn.execute(
            "SELECT kind FROM roster WHERE assignment = ? ORDER BY import_id DESC LIMIT 1",
            (assignment,),
        ).fetchone()
        return row["kind"] if row else ""

    def set_roster_key(self, student: str, key: str) -> None:
        """Which roster row the student matched (``ambiguous:...``, ``absent``)."""
        with self._tx() as c:
            c.execute(
                "UPDATE students SET roster_key = ? WHERE id = ? AND roster_key != ?",
                (key, student, key),
            )

    def set_setting(self, assignment: str, key: str, value: str) -> None:
        """Record a setting of ``assignment`` unless it is the one in force."""
        if self.setting(assignment, key) == value:
            return
        with self._tx() as c:
            c.execute(
                "INSERT INTO settings (assignment, key, value, created_at) VALUES (?, ?, ?, ?)",
                (assignment, key, _text(value), time.time()),
            )

    def setting(self, assignment: str, key: str, default: str | None = None) -> str | None:
        row = self.conn.execute(
            "SELECT value FROM settings WHERE assignment = ? AND key = ? ORDER BY id DESC LIMIT 1",
            (assignment, key),
        ).fetchone()
        return row["value"] if row else default

    def check(self) -> list[str]:
        """Integrity problems (empty when consistent): SQLite's check and our invariants."""
        out = [r[0] for r in self.conn.execute("PRAGMA integrity_check") if r[0] != "ok"]
        out += [
            f"result {r[0]} has {r[1]} test rows"
            for r in self.conn.execute(
                "SELECT r.id, (SELECT COUNT(*) FROM test_points t WHERE t.result_id = r.id) n "
                "FROM results r WHERE n != json_array_length(json_extract(r.result, '$.tests'))"
            )
        ]
        out += [
            f"pick {r[0]} points at a missing result"
            for r in self.conn.execute(
                "SELECT p.id FROM picks p LEFT JOIN results r ON r.id = p.result_id "
                "WHERE r.id IS NULL"
            )
        ]
        return out


class _Tx:
    """``with gb._tx() as c``: one immediate transaction, serialised between threads."""

    def __init__(self, gb: Gradebook) -> None:
        self.gb = gb

    def __enter__(self) -> sqlite3.Connection:
        self.gb._mutex.acquire()
        try:
            self.gb.conn.execute("BEGIN IMMEDIATE")
        except BaseException:
            self.gb._mutex.release()
            raise
        return self.gb.conn

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            self.gb.conn.execute("COMMIT" if exc_type is None else "ROLLBACK")
        finally:
            self.gb._mutex.release()
