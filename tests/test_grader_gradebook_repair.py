"""A gradebook that explains and repairs itself: damaged, emptied, copied without its -wal.

Each case takes a graded class (the notebooks scored from their metadata, see
:func:`grader_fixtures.lmsclass.fake_pool`), damages the gradebook as it happens, checks
that every command stops with one paragraph naming the command that repairs it (exit 2,
never a traceback, nothing rewritten), runs that command, and checks every grade is back.
"""

from __future__ import annotations

import csv
import io
import json
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

from grader_fixtures import lmsclass as L
from grader_fixtures.helpers import ASSIGNMENT
from rikingrade import api
from rikingrade.gradebook import Gradebook
from rikingrade.repair import records as repair_records

PY = sys.executable
TESTS = Path(__file__).resolve().parent
ONLY = set(range(12)) | {L.WITHDRAWN}
#: grades.csv columns that make a grade (not the run that wrote it)
GRADE = ["student", "status", "score", "max_score", "raw_score", "late_days", "late_penalty"]
GRADE += ["override", "submitted_at", "reason", "notebook", "sha256", "seed"]


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [PY, "-m", "rikingrade.cli", *args], capture_output=True, text=True, timeout=300
    )


def grades(out: Path) -> dict[str, tuple]:
    rows = csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8")))
    return {r["student"]: tuple(r[c] for c in GRADE) for r in rows}


def graded(tmp_path: Path, monkeypatch) -> Path:
    """A Canvas class graded into ``tmp_path/out``, with a late rule, an extension and an
    override (all of which a repair must bring back)."""
    people = L.make_class()
    folder, roster = L.write(people, "canvas", tmp_path, ONLY)
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    ext = tmp_path / "ext.csv"
    ext.write_text(f"student,due,reason\n{people[3].canvas_id},2026-12-10 12:00,illness\n")
    api.grade(
        str(ASSIGNMENT),
        [folder],
        out,
        roster=str(roster),
        due=L.DUE_TEXT,
        late_per_day=10,
        extensions=str(ext),
        unsafe_no_sandbox=True,
        quiet=True,
    )
    student = sorted(grades(out))[0]
    r = cli("override", L.EXERCISE, student, "--out", str(out), "--score", "4.5", "--reason", "x")
    assert r.returncode == 0, r.stderr
    return out


def _stopped_with_the_repair_command(out: Path, before: str) -> None:
    """Every command on the gradebook stops with the advice, exit 2, nothing rewritten."""
    for args in (
        ["export", L.EXERCISE, "--out", str(out)],
        ["override", L.EXERCISE, "x", "--out", str(out), "--excused", "--reason", "y"],
    ):
        r = cli(*args)
        assert r.returncode == 2, r.stdout + r.stderr
        assert "Traceback" not in r.stderr
        assert f"rikin-grade repair {L.EXERCISE} --out {out}" in r.stderr, r.stderr
        assert "--from-backup FILE" in r.stderr and r.stderr.count("\n") == 1, r.stderr
    assert (out / "grades.csv").read_text(encoding="utf-8") == before


def _repaired(out: Path, want: dict[str, tuple], *extra: str) -> str:
    r = cli("repair", L.EXERCISE, "--out", str(out), *extra)
    assert r.returncode == 0, r.stdout + r.stderr
    assert grades(out) == want
    with Gradebook.open(out / "gradebook.sqlite") as gb:
        assert gb.check() == []
        assert len(gb.current(L.EXERCISE)) == len(want)
    return r.stdout


def test_a_truncated_gradebook(tmp_path, monkeypatch):
    out = graded(tmp_path, monkeypatch)
    want, before = grades(out), (out / "grades.csv").read_text(encoding="utf-8")
    db = out / "gradebook.sqlite"
    size = db.stat().st_size
    with open(db, "r+b") as f:
        f.truncate(size // 2)
    _stopped_with_the_repair_command(out, before)
    said = _repaired(out, want)
    assert "moved the unusable gradebook aside" in said
    assert [p.name for p in out.glob("gradebook.sqlite.damaged-*")]  # kept, never deleted


def test_a_zero_length_gradebook_does_not_start_a_new_class(tmp_path, monkeypatch):
    out = graded(tmp_path, monkeypatch)
    want, before = grades(out), (out / "grades.csv").read_text(encoding="utf-8")
    (out / "gradebook.sqlite").write_bytes(b"")
    _stopped_with_the_repair_command(out, before)
    # grading again would have replaced grades.csv with a new class: it stops too
    folder = tmp_path / "canvas-download"
    r = cli("grade", str(ASSIGNMENT), str(folder), "--out", str(out), "--unsafe-no-sandbox")
    assert r.returncode == 2 and "rikin-grade repair" in r.stderr, r.stderr
    assert (out / "grades.csv").read_text(encoding="utf-8") == before
    _repaired(out, want)


KILLED = """
import os, signal, sys
sys.path.insert(0, {tests!r})
from grader_fixtures import lmsclass as L
from rikingrade import api

done_n = [0]

def pool(batch, todo, workers, done, bar, results):
    def counted(s, res):
        ok = done(s, res)
        done_n[0] += 1
        if done_n[0] == {k}:
            os.kill(os.getpid(), signal.SIGKILL)  # killed right after a commit
        return ok
    L.fake_pool(batch, todo, workers, counted, bar, results)

api._run_pool = pool
api.grade({assignment!r}, [{folder!r}], {out!r}, due=L.DUE_TEXT, late_per_day=10,
          unsafe_no_sandbox=True, quiet=True)
"""


def test_a_copy_without_its_wal_after_a_kill(tmp_path):
    people = L.make_class()
    folder, _ = L.write(people, "canvas", tmp_path, ONLY)
    out = tmp_path / "out"
    k = 9
    script = KILLED.format(
        tests=str(TESTS), k=k, assignment=str(ASSIGNMENT), folder=str(folder), out=str(out)
    )
    p = subprocess.run([PY, "-c", script], capture_output=True, text=True, timeout=300)
    assert p.returncode == -signal.SIGKILL, p.stderr
    # What an instructor copies: the folder, but gradebook.sqlite without its -wal.
    copy = tmp_path / "copy"
    shutil.copytree(out, copy, ignore=shutil.ignore_patterns("*-wal", "*-shm", "*.lock"))
    assert not (copy / "gradebook.sqlite-wal").exists()
    with sqlite3.connect(copy / "gradebook.sqlite") as conn:
        tables = {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
        in_copy = 0
        if "results" in tables:  # (the schema itself may still be in the -wal)
            in_copy = conn.execute("SELECT COUNT(*) FROM results").fetchone()[0]
    assert in_copy < k, "the kill left the grades in the .sqlite: no case to test"
    records = repair_records(copy)
    written = {r["student"]["id"]: r["result"]["score"] for r in records}
    assert len(written) == k
    r = cli("export", L.EXERCISE, "--out", str(copy))
    assert r.returncode == 2, r.stdout + r.stderr
    assert f"lacks {k - in_copy} grade(s)" in r.stderr and "-wal" in r.stderr, r.stderr
    r = cli("repair", L.EXERCISE, "--out", str(copy))
    assert r.returncode == 0, r.stderr
    with Gradebook.open(copy / "gradebook.sqlite") as gb:
        got = {row["student"]: row["score"] for row in gb.current(L.EXERCISE)}
        assert gb.check() == []
    assert got == written  # every grade committed before the kill is back
    # and the next run grades what the kill stopped, reusing those grades
    r = cli("grade", str(ASSIGNMENT), str(folder), "--out", str(copy), "--unsafe-no-sandbox")
    assert r.returncode == 0, r.stderr
    summary = json.loads((copy / "summary.json").read_text())
    assert (summary["resumed"], summary["submissions"]) == (k, len(ONLY))


def test_backup_holds_what_is_still_in_the_wal_and_restores(tmp_path, monkeypatch):
    out = graded(tmp_path, monkeypatch)
    want = grades(out)
    db = out / "gradebook.sqlite"
    writer = Gradebook.open(db)  # a grader at work: its commits are in the -wal
    try:
        writer.add_override(sorted(want)[1], L.EXERCISE, "score", 1.0, "in the wal only")
        assert (out / "gradebook.sqlite-wal").stat().st_size > 0
        r = cli("backup", "--out", str(out), "--to", str(tmp_path / "b.sqlite"))
        assert r.returncode == 0, r.stderr
    finally:
        writer.close()
    with sqlite3.connect(tmp_path / "b.sqlite") as conn:  # one file, nothing beside it
        reasons = [row[0] for row in conn.execute("SELECT reason FROM overrides")]
    assert "in the wal only" in reasons
    assert not Path(f"{tmp_path / 'b.sqlite'}-wal").exists()
    r = cli("backup", "--out", str(out), "--to", str(tmp_path / "b.sqlite"))
    assert r.returncode == 2 and "never overwritten" in r.stderr
    # a damaged gradebook, restored from the backup
    os.truncate(db, 4096)
    said = _repaired(
        out, _with_override(want, sorted(want)[1]), "--from-backup", str(tmp_path / "b.sqlite")
    )
    assert "restored the backup" in said


def _with_override(want: dict[str, tuple], student: str) -> dict[str, tuple]:
    row = list(want[student])
    row[GRADE.index("score")] = "1"
    row[GRADE.index("override")] = "score"
    return {**want, student: tuple(row)}
