"""Gradescope's "Export Submissions" download, graded for real through the command line.

The export as Gradescope lays it out: ``assignment_<id>_export/`` with a folder
``submission_<id>/`` per submission and ``submission_metadata.yml`` saying whose each is
(Ruby symbol keys, ``:submitters:``, ``:created_at:`` with its zone, ``:history:``), and
Gradescope's grades export as the roster (``First Name, Last Name, SID, Email, Sections``).
"""

from __future__ import annotations

import csv
import io
import json
import shutil
import subprocess
import sys
from datetime import datetime, timedelta, timezone
from pathlib import Path

import pytest
from grader_fixtures import lmsclass as L
from grader_fixtures.helpers import ASSIGNMENT, SOLUTION, require_bwrap

PY = sys.executable
FAST = ["--memory-mb", "512", "--cell-timeout", "5", "--cpu-seconds", "30", "--workers", "2"]
COLUMN = "HW3 fake2r"


def _ruby_time(t: float, hours: int) -> str:
    """``t`` as Gradescope writes ``:created_at:`` (Ruby: nanoseconds, the zone's offset)."""
    dt = datetime.fromtimestamp(t, timezone(timedelta(hours=hours)))
    sign = "+" if hours >= 0 else "-"
    return dt.strftime("%Y-%m-%d %H:%M:%S.%f") + f"000 {sign}{abs(hours):02d}:00"


def _wrong() -> str:
    """The solution with ``add`` subtracting (3 of 5 points)."""
    nb = json.loads(SOLUTION.read_text())
    for c in nb["cells"]:
        if "def add(" in "".join(c["source"]):
            c["source"] = "def add(a, b):\n    return a - b"
    return json.dumps(nb)


def _submitter(name: str, sid: str | None, email: str) -> str:
    sid_text = f"'{sid}'" if sid is not None else ""
    return f"  - :name: {name}\n    :sid: {sid_text}\n    :email: {email}\n"


def _record(folder: str, people: list[tuple], t: float, hours: int, history=()) -> str:
    text = f"{folder}:\n  :submitters:\n" + "".join(_submitter(*p) for p in people)
    text += f"  :created_at: {_ruby_time(t, hours)}\n  :score: \n  :status: processed\n"
    if not history:
        return text + "  :history: []\n"
    text += "  :history:\n"
    for h in history:
        text += f"  - :id: 77{int(h) % 1000}\n    :created_at: {_ruby_time(h, hours)}\n"
        text += "    :score: \n"
    return text


ANA = ("Ana Single", "1001", "ana@x.edu")
BO = ("Bo Group", "1002", "bo@x.edu")
CY = ("Cy Group", None, "cy@x.edu")  # no SID in Gradescope: the roster matches the e-mail
DI = ("Di Late", "1004", "di@x.edu")
ED = ("Ed Twofiles", "1005", "ed@x.edu")
FAY = ("Fay Nofolder", "1006", "fay@x.edu")


def _export(tmp: Path) -> tuple[Path, Path]:
    """The export and Gradescope's grades export (the roster)."""
    root = tmp / "assignment_4455_export"
    right, wrong = SOLUTION.read_text(), _wrong()
    files = {
        "submission_101": {"fake2r.ipynb": right},
        "submission_102": {"fake2r.ipynb": wrong},
        "submission_103": {"fake2r.ipynb": right},
        "submission_104": {"fake2r.ipynb": right, "helpers.py": "X = 1\n"},
        "submission_105": {"fake2r.ipynb": right},  # a folder the record does not list
    }
    for folder, named in files.items():
        (root / folder).mkdir(parents=True)
        for name, text in named.items():
            (root / folder / name).write_text(text)
    # Ana two hours early, written in +09:00 (as local time it would be 7 hours late)
    yml = "---\n" + _record("submission_101", [ANA], L.DUE - 7200, 9)
    yml += _record("submission_102", [BO, CY], L.DUE - 3600, 0)
    yml += _record("submission_103", [DI], L.DUE + 1.5 * L.DAY, -8)  # 2 days late
    yml += _record("submission_104", [ED], L.DUE - 600, -5, history=[L.DUE - L.DAY])
    yml += _record("submission_106", [FAY], L.DUE - 60, 0)  # no folder in the export
    (root / "submission_metadata.yml").write_text(yml)
    roster = tmp / "gradescope_grades.csv"
    with roster.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["First Name", "Last Name", "SID", "Email", "Sections", COLUMN]
                   + [f"{COLUMN} - {x}" for x in
                      ("Max Points", "Submission Time", "Lateness (H:M:S)")])  # fmt: skip
        for name, sid, email in [ANA, BO, ("Cy Group", "1003", "cy@x.edu"), DI, ED, FAY,
                                 ("Gil Absent", "1007", "gil@x.edu")]:  # fmt: skip
            first, last = name.split()
            w.writerow([first, last, sid, email, "A", "", "5.0", "", ""])
    return root, roster


def _grade(root: Path, roster: Path, out: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [PY, "-m", "rikingrade.cli", "grade", str(ASSIGNMENT), str(root), "--out", str(out)]
        + ["--roster", str(roster), "--due", L.DUE_TEXT, "--late-per-day", "10", *FAST],
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_a_gradescope_export_is_graded_by_its_metadata(tmp_path):
    require_bwrap()
    root, roster = _export(tmp_path)
    out = tmp_path / "out"
    r = _grade(root, roster, out)
    assert r.returncode in (0, 1), r.stdout + r.stderr
    rows = list(csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8"))))
    by_name = {row["name"]: row for row in rows}
    # the record is never graded, and no student is named after a submission folder
    assert not any("submission_metadata" in row["student"] for row in rows), rows
    assert not any(row["notebook"].endswith(".yml") and row["status"] == "ok" for row in rows)
    named = {ANA[0], BO[0], CY[0], DI[0], ED[0], FAY[0]}
    assert named <= set(by_name), sorted(by_name)
    # each member of the group has a row with the group's grade
    assert float(by_name[BO[0]]["score"]) == pytest.approx(3.0)
    assert float(by_name[CY[0]]["score"]) == pytest.approx(3.0)
    assert by_name[BO[0]]["notebook"] == by_name[CY[0]]["notebook"]
    assert by_name[BO[0]]["student"] != by_name[CY[0]]["student"]
    # :created_at: with its zone decides lateness (not the file's time, not the wall clock)
    assert (int(by_name[ANA[0]]["late_days"]), float(by_name[ANA[0]]["score"])) == (0, 5.0)
    ana_at = datetime.strptime(by_name[ANA[0]]["submitted_at"], "%Y-%m-%dT%H:%M:%S%z")
    assert ana_at.timestamp() == pytest.approx(L.DUE - 7200, abs=1)
    assert int(by_name[DI[0]]["late_days"]) == 2
    assert float(by_name[DI[0]]["score"]) == pytest.approx(4.0)
    # two files handed in: the notebook is graded
    assert float(by_name[ED[0]]["score"]) == pytest.approx(5.0)
    assert by_name[ED[0]]["notebook"].endswith("submission_104/fake2r.ipynb")
    # a record with no folder: a row for its student, 0 with the reason, never dropped
    assert float(by_name[FAY[0]]["score"]) == 0
    assert "no such folder" in by_name[FAY[0]]["reason"]
    # a folder the record does not list: graded under its own name, and said
    unlisted = [row for row in rows if "submission_105" in row["notebook"]]
    assert len(unlisted) == 1 and unlisted[0]["student"] == "submission_105"
    said = r.stdout + r.stderr
    assert "submission_105: a folder of the export that submission_metadata.yml" in said
    # the resubmission is said
    assert "submission_104: submitted 2 times on Gradescope" in said
    # every submitter is matched to their roster row (Cy by e-mail: no SID in the export)
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["roster"]["missing"] == ["Gil Absent"], summary
    assert summary["roster"]["not_on_roster"] == ["submission_105"], summary
    for who in named:
        assert by_name[who]["roster"] not in ("", "absent"), by_name[who]
    # grades go back in the columns of Gradescope's export, one row per roster student
    # graded (its SID and e-mail as exported: Cy's SID comes from the export), none other
    table = list(csv.reader(io.StringIO((out / "gradescope-fake2r.csv").read_text())))
    assert table[0] == ["First Name", "Last Name", "SID", "Email", COLUMN]
    got = {(r[2], r[3]): r[4] for r in table[1:]}
    assert len(got) == len(table) - 1
    assert got == {
        ("1001", "ana@x.edu"): "5",
        ("1002", "bo@x.edu"): "3",
        ("1003", "cy@x.edu"): "3",
        ("1004", "di@x.edu"): "4",
        ("1005", "ed@x.edu"): "5",
        ("1006", "fay@x.edu"): "0",
    }


def test_a_group_notebook_regraded_alone_keeps_its_members(tmp_path):
    """One notebook of the export passed alone is its submitters again, under their ids."""
    require_bwrap()
    root, roster = _export(tmp_path)
    out = tmp_path / "out"
    assert _grade(root, roster, out).returncode in (0, 1)
    before = list(csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8"))))
    r = _grade(root / "submission_102" / "fake2r.ipynb", roster, out)
    assert r.returncode in (0, 1), r.stdout + r.stderr
    after = list(csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8"))))
    assert sorted(x["student"] for x in after) == sorted(x["student"] for x in before)
    group = [x for x in after if x["name"] in (BO[0], CY[0])]
    assert len(group) == 2 and all(float(x["score"]) == pytest.approx(3.0) for x in group)


def test_an_unreadable_metadata_file_is_refused_with_the_reason(tmp_path):
    root, roster = _export(tmp_path)
    (root / "submission_metadata.yml").write_text("submission_101: [unclosed\n")
    r = _grade(root, roster, tmp_path / "out")
    assert r.returncode not in (0, 1) or "submission_metadata.yml" in r.stderr
    assert "submission_metadata.yml" in r.stdout + r.stderr
    assert "not YAML" in r.stdout + r.stderr
    shutil.rmtree(tmp_path / "out", ignore_errors=True)


def test_metadata_times_and_ids_are_read_as_gradescope_writes_them():
    from rikingrade import lms

    text = (
        "---\n"
        "submission_1:\n  :submitters:\n  - :name: A B\n    :sid: 1001\n    :email: a@x.edu\n"
        "  :created_at: '2026-11-20 14:50:12.345678000 -08:00'\n  :history: []\n"
        "submission_2:\n  :submitters:\n  - :name: C D\n    :sid: \n    :email: c@x.edu\n"
        "  :created_at: 2026-11-20 22:50:12.345678000 +00:00\n"
        "submission_3:\n  :score: 1.0\n"
    )
    entries, notes = lms.read_gradescope_metadata(text)
    want = datetime(2026, 11, 20, 22, 50, 12, 345678, tzinfo=timezone.utc).timestamp()
    assert entries["submission_1"].created_at == pytest.approx(want)  # quoted: a string
    assert entries["submission_2"].created_at == pytest.approx(want)  # YAML's timestamp
    assert entries["submission_1"].submitters == [lms.Submitter("A B", "1001", "a@x.edu")]
    assert entries["submission_2"].submitters == [lms.Submitter("C D", "", "c@x.edu")]
    assert entries["submission_3"].submitters == []
    assert any("submission_3 has no list of :submitters:" in n for n in notes)
    with pytest.raises(lms.GradescopeError):
        lms.read_gradescope_metadata("- just\n- a list\n")


def test_the_files_beside_an_exported_notebook_are_given_to_its_cells(tmp_path):
    from rikingrade.notebook import discover

    root, _ = _export(tmp_path)
    subs, _ = discover([root], "fake2r.ipynb")
    handed = {s.email: [name for name, _ in s.handed] for s in subs if s.email}
    assert handed["ed@x.edu"] == ["helpers.py"]  # submission_104: a notebook and helpers.py
    assert not [e for e, names in handed.items() if names and e != "ed@x.edu"], handed
    alone, _ = discover([root / "submission_104" / "fake2r.ipynb"], "fake2r.ipynb")
    assert [[name for name, _ in s.handed] for s in alone] == [["helpers.py"]]
