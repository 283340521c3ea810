"""A file refused at intake is recorded once per (student, file), as a graded notebook is.

Run again on the same download (resumed, or with ``regrade``), a refused file keeps its one
result: the gradebook (its results, a student's history) and grades.csv list it once. The
same file changed is a new attempt (a second result); the others still have one.
"""

from __future__ import annotations

import csv
import os
import sqlite3
from pathlib import Path

from grader_fixtures.helpers import ASSIGNMENT, FAST, SOLUTION, require_bwrap
from rikingrade import api
from rikingrade.gradebook import Gradebook
from rikingrade.notebook import MAX_NOTEBOOK_BYTES


def _class(d: Path) -> None:
    """A class with one notebook to grade and one of each kind of file refused at intake."""
    d.mkdir(parents=True)
    (d / "alice.ipynb").write_bytes(SOLUTION.read_bytes())
    (d / "bob.zip").write_bytes(b"PK\x03\x04 a zip handed in instead of the notebook")
    (d / "carol.ipynb").write_text("this is not JSON", encoding="utf-8")  # read, not a notebook
    (d / "dave").mkdir()
    (d / "dave" / "answers.py").write_text("print('no notebook')\n", encoding="utf-8")
    secret = d.parent / "elsewhere.ipynb"
    secret.write_bytes(SOLUTION.read_bytes())
    os.symlink(secret, d / "erin.ipynb")  # a link: not read
    with open(d / "frank.ipynb", "wb") as f:  # too large to be read
        f.truncate(MAX_NOTEBOOK_BYTES + 1)


def _rows(db: Path) -> dict[str, int]:
    with sqlite3.connect(db) as c:
        return dict(c.execute("SELECT student, COUNT(*) FROM results GROUP BY student"))


def _grade(cls: Path, out: Path, **kw):
    return api.grade(str(ASSIGNMENT), [cls], out, **{**FAST, **kw})


def test_a_refused_file_run_again_or_regraded_is_recorded_once(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    _class(cls)
    out = tmp_path / "out"
    first = _grade(cls, out)
    refused = {r.student for r in first.results if r.refused}
    assert len(refused) == 5 and {r.student for r in first.results} - refused == {"alice"}, [
        (r.student, r.status, r.refused) for r in first.results
    ]
    db = out / "gradebook.sqlite"
    assert set(_rows(db).values()) == {1}
    _grade(cls, out)  # resumed
    again = _grade(cls, out, regrade=True)
    rows = _rows(db)
    assert rows == {**{s: 1 for s in refused}, "alice": 2}, rows  # alice regraded: 2
    assert {r.student: r.sha256 for r in again.results} == {
        r.student: r.sha256 for r in first.results
    }
    with open(out / "grades.csv", newline="", encoding="utf-8") as f:
        students = [row["student"] for row in csv.DictReader(f)]
    assert sorted(students) == sorted(set(students)) and len(students) == 6
    with Gradebook.open(db) as gb:
        assert {len(gb.history("fake2r", who)) for who in refused} == {1}

    # a changed file is a new attempt: one more result for that student alone
    (cls / "bob.zip").write_bytes(b"PK\x03\x04 another zip, still not a notebook")
    (cls / "dave" / "answers.py").write_text("print('changed')\n", encoding="utf-8")
    _grade(cls, out)
    rows = _rows(db)
    assert rows["bob"] == 2 and rows["dave"] == 2, rows
    assert {s: rows[s] for s in refused - {"bob", "dave"}} == {
        s: 1 for s in refused - {"bob", "dave"}
    }
