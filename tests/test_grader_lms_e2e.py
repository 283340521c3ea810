"""A small class graded for real, through the command line, in each LMS's layout.

Eight people of :mod:`grader_fixtures.lmsclass`: both John Smiths, Blackboard usernames
``li_wei`` and ``zhang_wei`` (and ``ama_mensah``, who handed in twice, the second time
late), a hand-in at 1:04 AM and one at 1:15 PM on the due day (due 2 PM), one who withdrew
and one who handed in nothing. Every notebook runs in the sandbox.
"""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys
from pathlib import Path

import pytest
from grader_fixtures import lmsclass as L
from grader_fixtures.helpers import ASSIGNMENT, require_bwrap

PY = sys.executable
FAST = ["--memory-mb", "512", "--cell-timeout", "5", "--cpu-seconds", "30", "--workers", "2"]
ONLY = {0, 1, 4, 14, 15, 17, L.WITHDRAWN, L.MISSING}


def _score(p: L.Person, lms: str) -> float:
    raw = 3.0 if p.idx in L.WRONG else 5.0
    return raw - min(raw, 5.0 * min(100, 10 * p.late_days(lms)) / 100)


@pytest.mark.parametrize("layout", ["canvas", "moodle-worksheet", "blackboard", "brightspace"])
def test_grading_a_small_class_for_real_on_each_lms(tmp_path, layout):
    require_bwrap()
    lms = layout.split("-")[0]
    people = L.make_class()
    folder, roster = L.write(people, layout, tmp_path, ONLY)
    out = tmp_path / "out"
    r = subprocess.run(
        [PY, "-m", "rikingrade.cli", "grade", str(ASSIGNMENT), str(folder), "--out", str(out)]
        + ["--roster", str(roster), "--due", L.DUE_TEXT, "--late-per-day", "10", *FAST],
        capture_output=True,
        text=True,
        timeout=600,
    )
    ambiguous = lms == "brightspace"  # two John Smiths, named by name only
    assert r.returncode == (1 if ambiguous else 0), r.stdout + r.stderr
    rows = list(csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8"))))
    got = {}
    for row in rows:
        who, attempt = L.token(Path(row["notebook"]).read_bytes())
        assert who not in got, f"{people[who].name} graded twice"
        assert attempt == len(people[who].attempts) - 1
        got[who] = row
    assert set(got) == ONLY - {L.MISSING}
    for who, row in got.items():
        p = people[who]
        assert (int(row["late_days"]), float(row["score"])) == (
            p.late_days(lms),
            pytest.approx(_score(p, lms)),
        ), (p.name, row)
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert len(summary["roster"]["missing"]) == 1
    assert summary["roster"]["not_on_roster"] == [got[L.WITHDRAWN]["student"]]
    text = (out / f"{lms}-{L.EXERCISE}.csv").read_text(encoding="utf-8")
    table = list(csv.reader(io.StringIO(text)))
    # the withdrawn student's id is in no LMS file; each other student's is, once
    ids = {
        "canvas": lambda p: p.canvas_id,
        "moodle": lambda p: f"Participant {p.moodle_id}",
        "blackboard": lambda p: p.username,
        "brightspace": lambda p: p.org_id,
    }[lms]
    cells = [c for row in table for c in row]
    assert ids(people[L.WITHDRAWN]) not in cells
    for who in ONLY - {L.WITHDRAWN, L.MISSING} - ({0, 1} if ambiguous else set()):
        assert cells.count(ids(people[who])) == 1, people[who].name
    if ambiguous:
        assert "not told apart" in r.stdout
