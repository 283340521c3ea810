"""LMS download names, class discovery, the gradebook, policy, LMS exports and the class report.

No student code runs here (see test_grader_gradebook_cli.py for real runs).
"""

from __future__ import annotations

import csv
import io
import json
import os
import sys
import time
from datetime import datetime, timezone

import pytest
from rikingrade import lms
from rikingrade.classreport import histogram, statistics
from rikingrade.gradebook import Gradebook, GradebookBusy
from rikingrade.notebook import SubmissionsError, discover, student_id
from rikingrade.policy import PolicyError, Rules, apply, parse_time
from rikingrade.report import SubmissionResult, TestResult
from rikingrade.views import export, final_grades

NB = "scara.ipynb"


def touch(path, text="{}", mtime=None):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    if mtime is not None:
        os.utime(path, (mtime, mtime))
    return path


# ----------------------------------------------------------------------------- names
def test_canvas_names():
    p = lms.parse_file("smithjohn_12345_67890_scara.ipynb")
    assert (p.lms, p.name, p.lms_id, p.late, p.key) == (
        "canvas",
        "smithjohn",
        "12345",
        False,
        "canvas:12345",
    )
    late = lms.parse_file("smithjohn_late_12345_67891_scara-1.ipynb")
    assert late.late and late.lms_id == "12345" and late.order == (67891, 1)
    assert late.order > p.order  # the re-upload sorts after the first upload
    assert lms.parse_file("scara.ipynb") is None
    assert lms.parse_file("alice.ipynb") is None


def test_moodle_blackboard_brightspace_names():
    d = lms.parse_folder("Jane Doe_70001_assignsubmission_file_")
    assert (d.lms, d.name, d.lms_id) == ("moodle", "Jane Doe", "70001")
    f = lms.parse_file("Jane Doe_70001_assignsubmission_file_scara.ipynb")
    assert (f.lms, f.name, f.lms_id) == ("moodle", "Jane Doe", "70001")
    b = lms.parse_file("HW 3_jdoe_attempt_2026-11-20-23-10-05_scara.ipynb")
    assert (b.lms, b.lms_id) == ("blackboard", "jdoe")
    assert time.localtime(b.submitted_at)[:6] == (2026, 11, 20, 23, 10, 5)
    s = lms.parse_file("123-456 - Jane Doe - Nov 20, 2026 1110 PM - scara.ipynb")
    # Neither number is documented as the user's: Brightspace names students by name.
    assert (s.lms, s.name, s.lms_id, s.key) == (
        "brightspace",
        "Jane Doe",
        "",
        "brightspace:name:doe jane",
    )
    assert time.localtime(s.submitted_at)[:5] == (2026, 11, 20, 23, 10)
    assert lms.parse_folder("123-456 - Jane Doe - Nov 20, 2026 1110 PM").lms == "brightspace"


# ----------------------------------------------------------------------------- discovery
def test_canvas_attempts_newest_counts_earlier_kept(tmp_path):
    c = tmp_path / "canvas"
    touch(c / "smithjohn_1000_5000_scara.ipynb", mtime=100)
    touch(c / "smithjohn_1000_5100_scara-1.ipynb", mtime=50)  # newer upload, older mtime
    touch(c / "smithjohn_late_1000_5200_scara-2.ipynb", mtime=10)
    touch(c / "ngamy_1002_5002_scara.ipynb")
    subs, notes = discover([c], NB)
    assert [s.student for s in subs] == ["ngamy_1002", "smithjohn_1000"]
    john = subs[1]
    assert john.path.name == "smithjohn_late_1000_5200_scara-2.ipynb" and john.late
    assert [e.path.name for e in john.earlier] == [
        "smithjohn_1000_5000_scara.ipynb",
        "smithjohn_1000_5100_scara-1.ipynb",
    ]
    assert john.lms == "canvas" and john.lms_id == "1000"
    assert any(
        "3 attempts; the newest (smithjohn_late_1000_5200_scara-2.ipynb)" in n for n in notes
    )


def test_blackboard_and_brightspace_attempts(tmp_path):
    bb = tmp_path / "bb"
    touch(bb / "HW 3_jdoe_attempt_2026-11-21-09-00-00_scara.ipynb", "new")
    touch(bb / "HW 3_jdoe_attempt_2026-11-20-23-10-05_scara.ipynb", "old")
    touch(bb / "HW 3_jdoe_attempt_2026-11-20-23-10-05.txt", "")
    subs, _ = discover([bb], NB)
    assert [s.student for s in subs] == ["jdoe"]
    assert subs[0].path.read_text() == "new" and subs[0].time_source == "download name"
    assert [e.path.read_text() for e in subs[0].earlier] == ["old"]
    d2l = tmp_path / "d2l"
    touch(d2l / "11-456 - Jane Doe - Nov 20, 2026 1110 PM" / NB, "first")
    touch(d2l / "12-456 - Jane Doe - Nov 21, 2026 0905 AM" / NB, "second")
    subs, _ = discover([d2l], NB)
    assert [(s.student, s.path.read_text()) for s in subs] == [("Jane_Doe", "second")]


def test_roster_matches_on_ids_and_names():
    roster = [
        lms.RosterEntry("1000", "Smith, John", "js@uni.edu", "S1"),
        lms.RosterEntry("Participant 70001", "Jane Doe", "jane@uni.edu"),
        lms.RosterEntry("u3", "Amy Ng", "amyng@uni.edu"),
    ]
    canvas = lms.parse_file("smithjohn_1000_1_scara.ipynb")
    assert lms.match_roster(canvas, "x", roster).sis_id == "S1"
    moodle = lms.parse_folder("Jane Doe_70001_assignsubmission_file_")
    assert lms.match_roster(moodle, "x", roster).email == "jane@uni.edu"
    bb = lms.parse_file("HW_amyng_attempt_2026-11-21-09-00-00_scara.ipynb")
    assert lms.match_roster(bb, "x", roster).id == "u3"  # the e-mail's user part
    assert lms.match_roster(None, "Ng Amy", roster).id == "u3"  # a name, either order
    assert lms.match_roster(None, "Nobody", roster) is None


def test_moodle_folders_and_one_student_folder(tmp_path):
    m = tmp_path / "moodle"
    touch(m / "Jane Doe_70001_assignsubmission_file_" / NB)
    touch(m / "Amy Ng_70002_assignsubmission_file_" / "my scara.ipynb")
    subs, _ = discover([m], NB)
    assert {s.student: (s.lms, s.lms_id, s.name) for s in subs} == {
        "Jane_Doe_70001": ("moodle", "70001", "Jane Doe"),
        "Amy_Ng_70002": ("moodle", "70002", "Amy Ng"),
    }
    # One student's folder passed alone is that student (a one-student regrade).
    one, _ = discover([m / "Jane Doe_70001_assignsubmission_file_"], NB)
    assert [s.student for s in one] == ["Jane_Doe_70001"]


def test_folder_per_student_passed_alone_is_that_student(tmp_path):
    touch(tmp_path / "class" / "alice" / NB)
    touch(tmp_path / "class" / "bob" / NB)
    subs, _ = discover([tmp_path / "class" / "alice"], NB)
    assert [s.student for s in subs] == ["alice"]


def test_nbgrader_tree(tmp_path):
    course = tmp_path / "course"
    touch(course / "submitted" / "alice" / "scara" / NB)
    (course / "submitted" / "alice" / "scara" / "timestamp.txt").write_text(
        "2026-11-20 22:00:00.000000 UTC"
    )
    touch(course / "submitted" / "bob" / "scara" / NB)
    for arg in (course, course / "submitted"):
        subs, _ = discover([arg], NB)
        assert [s.student for s in subs] == ["alice", "bob"]
        assert subs[0].submitted_at == datetime(2026, 11, 20, 22, tzinfo=timezone.utc).timestamp()
        assert subs[0].time_source == "nbgrader timestamp.txt"
        assert subs[1].time_source == "file modification time"


def test_refuses_what_is_not_a_class(tmp_path):
    cls = tmp_path / "class"
    touch(cls / NB)
    touch(cls / "alice" / NB)
    touch(cls / "bob" / NB)
    with pytest.raises(SubmissionsError) as exc:
        discover([cls], NB)
    msg = str(exc.value)
    assert (
        "holds scara.ipynb (the exercise's own notebook name, not a student's) beside 2 "
        "student folder(s) (alice, bob)" in msg
    )
    assert "Move scara.ipynb out of the class folder" in msg
    # One folder too high: a single "student" holding a class.
    top = tmp_path / "top"
    for who in ("a", "b", "c"):
        touch(top / "submissions" / who / NB)
    with pytest.raises(
        SubmissionsError,
        match=r"holds 3 folders with a notebook of the same "
        r"name \(a, b, c\).*Pass .*submissions itself",
    ):
        discover([top], NB)
    flat = tmp_path / "download"
    touch(flat / "submissions" / "smithjohn_1000_1_scara.ipynb")
    touch(flat / "submissions" / "ngamy_1001_2_scara.ipynb")
    with pytest.raises(
        SubmissionsError,
        match=r"holds notebooks of 2 different students by "
        r"their download names .*Pass .*submissions itself",
    ):
        discover([flat], NB)
    (tmp_path / "zipped").mkdir()
    (tmp_path / "zipped" / "submissions.zip").write_bytes(b"PK")
    with pytest.raises(SubmissionsError, match="unzip the LMS download first"):
        discover([tmp_path / "zipped"], NB)
    with pytest.raises(SubmissionsError, match="no such file or folder"):
        discover([tmp_path / "no" / "such"], NB)


@pytest.mark.skipif(sys.platform != "linux", reason="bytes file names")
def test_undecodable_names_deep_trees_and_dot_folders(tmp_path):
    cls = tmp_path / "class"
    cls.mkdir()
    raw = os.path.join(os.fsencode(cls), b"caf\xe9.ipynb")
    with open(raw, "w") as f:
        f.write("{}")
    touch(cls / "alice.ipynb")
    hidden = touch(cls / ".bob" / NB)
    subs, notes = discover([cls], NB)
    ids = [s.student for s in subs]
    assert "alice" in ids and len(ids) == 2
    odd = next(s for s in subs if s.student != "alice")
    assert odd.student.startswith("caf-") and odd.student.isascii()
    assert odd.shown_path.endswith("caf\\xe9.ipynb")
    odd.shown_path.encode("utf-8")  # writable anywhere
    assert any(".bob: a hidden folder" in n for n in notes), notes
    assert hidden.exists()
    # 1,200 nested folders in one student's folder: no RecursionError, and it is said.
    deep = tmp_path / "deep"
    d = deep / "carol"
    os.makedirs(d)
    touch(d / NB)
    path = os.fsencode(d)
    os.chdir(d)
    try:
        for _ in range(1200):
            os.mkdir("d")
            os.chdir("d")
        with open("x.ipynb", "w") as f:
            f.write("{}")
    finally:
        os.chdir(tmp_path)
    touch(deep / "dave" / NB)
    try:
        subs, notes = discover([deep], NB)
        assert [s.student for s in subs] == ["carol", "dave"]
        assert subs[0].path == d / NB
        assert any("nested more than" in n for n in notes)
    finally:
        _remove_chain(path)


def _remove_chain(top: bytes) -> None:
    """Remove a deep d/d/d/... chain without recursion (pytest's cleanup would recurse)."""
    depth = 0
    os.chdir(top)
    while os.path.isdir(b"d"):
        os.chdir(b"d")
        depth += 1
    for name in os.listdir(b"."):
        os.unlink(name)
    for _ in range(depth):
        os.chdir(b"..")
        os.rmdir(b"d")
    os.chdir(b"/")


def test_links_are_not_followed(tmp_path):
    outside = touch(tmp_path / "solution" / NB, '{"secret": 1}')
    cls = tmp_path / "class"
    touch(cls / "alice.ipynb")
    (cls / "mallory.ipynb").symlink_to(outside)
    (cls / "eve").mkdir()
    (cls / "eve" / NB).symlink_to(outside)
    os.link(outside, cls / "trudy.ipynb")
    (cls / "bob").symlink_to(tmp_path / "solution", target_is_directory=True)
    subs, notes = discover([cls], NB)
    got = {s.student: s.refused for s in subs}
    # Each link is a student graded 0 with the reason, never a read of what it points to.
    assert got == {
        "alice": "",
        "bob": "a symbolic link: links are not followed",
        "eve": "a symbolic link: links are not followed",
        "mallory": "a symbolic link: links are not followed",
        "trudy": "a hard link to a file elsewhere: not read",
    }
    text = "\n".join(notes)
    assert "mallory.ipynb: a symbolic link: links are not followed" in text
    assert "eve/scara.ipynb: a symbolic link" in text
    assert "trudy.ipynb: a hard link" in text
    assert "bob: a symbolic link" in text
    hashes = {s.hash() for s in subs}  # never opens the target
    assert len(hashes) == 5


def test_ids_are_unique_traceable_and_order_free(tmp_path):
    cls = tmp_path / "class"
    touch(cls / "al ice.ipynb", "1")
    touch(cls / "al_ice.ipynb", "2")
    touch(cls / "+cmd.ipynb", "3")
    subs, _ = discover([cls], NB)
    by = {s.student: s.path.name for s in subs}
    assert by["al_ice"] == "al_ice.ipynb"  # the real name keeps its id
    assert by[student_id("al ice")] == "al ice.ipynb" != "al_ice"
    assert student_id("al ice").startswith("al_ice-")
    assert all(s[0] not in "+-@=" for s in by)
    # Alone, each file gets the same id as in the class.
    assert discover([cls / "al ice.ipynb"], NB)[0][0].student == student_id("al ice")


# ----------------------------------------------------------------------------- policy
DAY = 86400.0


def test_late_penalty_per_day_cap_grace_extension_override():
    rules = Rules(due=1000 * DAY, per_day=10, cap=25, grace_minutes=15)
    on_time = apply(8, 10, 1000 * DAY + 14 * 60, "download name", rules)
    assert (on_time.final, on_time.late_days, on_time.notes) == (8, 0, [])
    one = apply(8, 10, 1000 * DAY + 16 * 60, "download name", rules)
    assert (one.late_days, one.penalty, one.final) == (1, 1.0, 7.0)
    assert "1 day(s) late, 10% per day (at most 25%), -1 points" in one.notes[0]
    five = apply(8, 10, 1005 * DAY, "download name", rules)
    assert (five.late_days, five.penalty, five.final) == (5, 2.5, 5.5)  # capped at 25%
    low = apply(1, 10, 1005 * DAY, "x", rules)
    assert low.final == 0  # never below zero
    ext = apply(8, 10, 1005 * DAY, "x", rules, extension=(1006 * DAY, "illness"))
    assert ext.final == 8 and "Extension" in ext.notes[0] and "illness" in ext.notes[0]
    ovr = apply(8, 10, 1005 * DAY, "x", rules, override=("score", 9.0, "regraded by hand"))
    assert (
        ovr.final == 9
        and "regraded by hand" in ovr.notes[-1]
        and "(computed: 5.5)" in ovr.notes[-1]
    )
    exc = apply(8, 10, None, "x", rules, override=("excused", None, "medical"))
    assert exc.excused and "medical" in exc.notes[0]
    with pytest.raises(PolicyError, match="per_day"):
        Rules(per_day=-1)
    with pytest.raises(PolicyError, match="cannot read the time"):
        parse_time("next friday")
    utc = datetime(2026, 11, 20, 23, 59, tzinfo=timezone.utc).timestamp()
    assert parse_time("2026-11-20T23:59:00+00:00") == utc
    assert parse_time("2026-11-20T23:59:00+01:00") == utc - 3600
    assert parse_time("2026-11-20") == parse_time("2026-11-20 23:59:59")


# ----------------------------------------------------------------------------- gradebook
def result(student, points, status="ok", key="k1", feedback="wrong"):
    tests = [
        TestResult("t1", 1.0, points[0], "ok" if points[0] == 1 else feedback),
        TestResult("t2", 2.0, points[1], "ok" if points[1] == 1 else feedback),
    ]
    return SubmissionResult(
        student, f"/s/{student}.ipynb", "h" + student, status, tests=tests, max_score=3.0, key=key
    )


def filled(tmp_path, students=("alice", "bob", "carol")):
    gb = Gradebook.open(tmp_path / "gb.sqlite")
    gb.add_assignment("scara", 3.0, [("t1", 1.0), ("t2", 2.0)])
    run = gb.start_run("scara", "0", 1, "k1", {})
    for i, s in enumerate(students):
        gb.add_student(s, name=s.title(), canvas_id=str(100 + i), moodle_id=str(700 + i))
        sid = gb.add_submission(s, "scara", "h" + s, f"/s/{s}.ipynb", 1000.0 + i)
        gb.record(run, sid, result(s, (1, min(1.0, 0.4 * i))), "scara", 1)
    gb.end_run(run, "finished")
    return gb


def test_regrading_one_student_changes_only_their_rows(tmp_path):
    gb = filled(tmp_path)
    before = {r["student"]: dict(r) for r in gb.current("scara")}
    run = gb.start_run("scara", "0", 1, "k1", {})
    sid = gb.add_submission("bob", "scara", "hbob2", "/s/bob2.ipynb", 2000.0)
    gb.record(run, sid, result("bob", (0, 0)), "scara", 1)
    after = {r["student"]: dict(r) for r in gb.current("scara")}
    assert set(after) == {"alice", "bob", "carol"}
    assert after["alice"] == before["alice"] and after["carol"] == before["carol"]
    assert after["bob"]["score"] == 0 and after["bob"]["sha256"] == "hbob2"
    # Nothing deleted: bob's first file and grade are still there.
    assert [h["score"] for h in gb.history("scara", "bob")] == [1.8, 0.0]
    assert len(gb.submissions("scara", "bob")) == 2
    assert gb.check() == []


def test_one_writer_and_interrupted_runs(tmp_path):
    gb = filled(tmp_path)
    run = gb.start_run("scara", "0", 1, "k1", {})
    with pytest.raises(GradebookBusy, match="another rikin-grade .* is writing"):
        Gradebook.open(tmp_path / "gb.sqlite")
    gb.close()  # as if killed: the run never ended
    gb = Gradebook.open(tmp_path / "gb.sqlite")
    assert gb.runs()[-1]["id"] == run and gb.runs()[-1]["state"] == "interrupted"
    assert gb.conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    gb.close()


def test_cached_results_are_reused_not_copied(tmp_path):
    gb = filled(tmp_path)
    sid = gb.add_submission("alice", "scara", "halice", "/s/alice.ipynb", 1000.0)
    prev = gb.cached(sid, "k1")
    assert prev is not None and prev.score == 1.0 and gb.cached(sid, "other-key") is None
    run = gb.start_run("scara", "0", 1, "k1", {})
    gb.record(run, sid, prev, "scara", 1, reuse=prev.result_id)
    n = gb.conn.execute("SELECT COUNT(*) FROM results WHERE student = 'alice'").fetchone()[0]
    assert n == 1


# ----------------------------------------------------------------------------- exports
def test_canvas_and_moodle_files_follow_their_import_formats(tmp_path):
    gb = filled(tmp_path)
    gb.add_student("alice", sis_id="S1", section="A", email="alice@uni.edu")
    gb.set_policy("scara", 1001.5, 10, 100, 0)  # carol (1002) is late by one day
    gb.add_override("bob", "scara", "excused", None, "medical")
    rows = final_grades(gb, "scara")
    canvas, skipped = lms.canvas_csv(rows, "scara", 3.0)
    got = list(csv.reader(io.StringIO(canvas)))
    # Canvas: Student, ID, SIS User ID, SIS Login ID, Section, then the assignment column;
    # a "Points Possible" row; EX for excused.
    assert got[0] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "scara"]
    assert got[1] == ["Points Possible", "", "", "", "", "3"]
    assert got[2:] == [
        ["Alice", "100", "S1", "", "A", "1"],
        ["Bob", "101", "", "", "", "EX"],
        ["Carol", "102", "", "", "", "2.3"],  # 2.6 points - 10% of 3
    ]
    assert skipped == []
    moodle, skipped = lms.moodle_csv(rows, 3.0)
    got = list(csv.reader(io.StringIO(moodle)))
    # Moodle's worksheet import needs Identifier ("Participant N"), Grade, Last modified (grade).
    assert got[0] == lms.MOODLE_COLUMNS
    head = got[0]
    alice = dict(zip(head, got[1], strict=True))
    assert alice["Identifier"] == "Participant 700" and alice["Grade"] == "1"
    assert alice["Email address"] == "alice@uni.edu" and alice["Maximum Grade"] == "3"
    assert time.strptime(alice["Last modified (grade)"], "%Y-%m-%d %H:%M:%S")
    assert skipped == ["bob"]  # excused: Moodle's worksheet has no excused grade
    carol = dict(zip(head, got[2], strict=True))
    assert carol["Grade"] == "2.3" and "Late:" in carol["Feedback comments"]


def test_formula_like_text_is_escaped_in_every_csv(tmp_path):
    gb = Gradebook.open(tmp_path / "gb.sqlite")
    gb.add_assignment("scara", 3.0, [("t1", 1.0), ("t2", 2.0)])
    run = gb.start_run("scara", "0", 1, "k1", {})
    gb.add_student("x", name='=HYPERLINK("http://evil")', canvas_id="1", moodle_id="2")
    sid = gb.add_submission("x", "scara", "hx", "/s/x.ipynb", 1.0)
    gb.record(run, sid, result("x", (1, 1)), "scara", 1)
    rows = final_grades(gb, "scara")
    for text in (lms.canvas_csv(rows, "scara", 3)[0], lms.moodle_csv(rows, 3)[0]):
        cells = [c for r in csv.reader(io.StringIO(text)) for c in r]
        assert '\'=HYPERLINK("http://evil")' in cells and not any(c.startswith("=") for c in cells)


def test_export_views_and_class_report(tmp_path):
    gb = filled(tmp_path, ("a", "b", "c", "d"))
    info = export(gb, "scara", "scara", tmp_path / "out", run_id=1)
    out = tmp_path / "out"
    rows = (out / "grades.csv").read_text().splitlines()
    assert rows[0].startswith("student,status,score,max_score,t1,t2,raw_score,late_days")
    assert [r.split(",")[0] for r in rows[1:]] == ["a", "b", "c", "d"]
    assert "seed" in rows[0].split(",")
    assert (out / "canvas-scara.csv").exists() and (out / "moodle-scara.csv").exists()
    stats = json.loads((out / "report" / "scara-run1.json").read_text())
    # t2's fraction 0, 0.4, 0.8, 1: scores a 1, b 1.8, c 2.6, d 3
    assert stats["students"] == 4 and stats["mean"] == pytest.approx((1 + 1.8 + 2.6 + 3) / 4)
    t2 = next(t for t in stats["tests"] if t["test"] == "t2")
    assert t2["pass_rate"] == pytest.approx(1 / 4)  # full marks only for d
    assert t2["mean"] == pytest.approx((0 + 0.8 + 1.6 + 2) / 4)
    assert stats["failures"][0] == {
        "test": "t2",
        "message": "wrong",
        "students": 3,
        "examples": ["a", "b", "c"],
        "example_message": "wrong",
    }
    page = (out / "report" / "scara.html").read_text()
    assert '<img src="scara.png"' in page and "Most common failures" in page
    assert (out / "report" / "scara-run1.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert info["report"][0].endswith("scara.html")


def test_histogram_bins():
    bins = histogram([0, 0.5, 9.99, 10, 10], 10)
    assert len(bins) == 10 and bins[0]["count"] == 2 and bins[-1]["count"] == 3
    assert sum(b["count"] for b in bins) == 5


def test_statistics_list_who_failed_to_run():
    from rikingrade.policy import Grade

    def row(s, status, pts):
        res = result(s, pts, status=status)
        g = Grade(res.score, 3.0, res.score)
        return {
            "student": s,
            "status": status,
            "final": res.score,
            "max_score": 3.0,
            "excused": False,
            "grade": g,
            "result": res,
        }

    stats = statistics(
        [row("a", "ok", (1, 1)), row("b", "invalid", (0, 0)), row("c", "timeout", (1, 0))],
        [("t1", 1.0), ("t2", 2.0)],
    )
    assert [t["student"] for t in stats["failed_to_run_or_timed_out"]] == ["b", "c"]
    # b's "not run" failures are not counted as failure messages (b is listed above).
    assert all("b" not in f["examples"] for f in stats["failures"])


# ----------------------------------------------------------------------------- issue 27
def test_brightspace_times_every_hour_and_minute():
    """``Dec 4, 2026 110 PM`` is 13:10: the last two digits are the minutes, whatever the
    hour (file names run hour and minutes together; folders and index.html write 1:10)."""
    for half, offset in (("AM", 0), ("PM", 12)):
        for hour in range(1, 13):
            for minute in range(60):
                want = datetime(2026, 12, 4, hour % 12 + offset, minute)
                for clock in (f"{hour}{minute:02d}", f"{hour}:{minute:02d}"):
                    name = f"81017-700000 - Jane Doe - Dec 4, 2026 {clock} {half}"
                    p = lms.parse_file(name + " - scara.ipynb") if ":" not in clock else None
                    p = p or lms.parse_folder(name)
                    got = datetime.fromtimestamp(p.submitted_at)
                    assert got == want, (name, got)


def test_brightspace_index_beside_a_folder_per_submission_is_read_not_graded(tmp_path):
    """Brightspace's download with a folder per submission keeps ``index.html`` beside the
    folders: it is the LMS's own record, never a student ("index", refused, graded 0)."""
    bs = tmp_path / "bs"
    for k, (who, when) in enumerate([("Jane Doe", "1:10 PM"), ("Bo Li", "12:05 AM")]):
        touch(bs / f"8101{k}-70000{k} - {who} - Dec 4, 2026 {when}" / NB)
    touch(bs / "index.html", "<html><body><table><tr><th>Submitted By</th></tr>"
          "</table></body></html>")
    subs, _ = discover([bs], NB)
    assert sorted(s.student for s in subs) == ["Bo_Li", "Jane_Doe"]
    assert not any(s.refused for s in subs)
    times = {s.student: datetime.fromtimestamp(s.submitted_at) for s in subs}
    assert times == {"Jane_Doe": datetime(2026, 12, 4, 13, 10),
                     "Bo_Li": datetime(2026, 12, 4, 0, 5)}


def _bb_record(folder, user, stamp, name, files=("scara.ipynb",), prefix="HW_3 IK"):
    stem = f"{prefix}_{user}_attempt_{stamp}"
    lines = [f"Name: {name} ({user})", "Assignment: HW 3 IK", "Date Submitted: x", ""]
    lines += ["Submission Field:", "There is no student submission text data for this "]
    lines += ["assignment.", "", "Comments:", "There are no student comments.", "", "Files:"]
    for f in files:
        lines += [f"\tOriginal filename: {f}", f"\tFilename: {stem}_{f}", ""]
        touch(folder / f"{stem}_{f}", json.dumps({"who": user, "at": stamp}))
    touch(folder / f"{stem}.txt", "\n".join(lines))


def test_blackboard_usernames_holding_underscores_are_read_from_the_records(tmp_path):
    """Usernames li_wei, zhang_wei and four *_mensah: each a student of their own, read
    from Blackboard's .txt beside each attempt (never cut at a '_')."""
    bb = tmp_path / "bb"
    users = ["li_wei", "zhang_wei", "kwame_mensah", "ama_mensah", "kofi_mensah", "yaw_mensah"]
    for i, u in enumerate(users):
        _bb_record(bb, u, f"2026-11-20-23-1{i}-05", u.replace("_", " ").title())
    _bb_record(bb, "ama_mensah", "2026-11-21-09-00-00", "Ama Mensah")  # a resubmission
    subs, notes = discover([bb], NB)
    assert sorted(s.lms_id for s in subs) == sorted(users)
    ama = next(s for s in subs if s.lms_id == "ama_mensah")
    assert json.loads(ama.path.read_text())["at"] == "2026-11-21-09-00-00"
    assert len(ama.earlier) == 1 and ama.name == "Ama Mensah"
    assert time.localtime(ama.submitted_at)[:6] == (2026, 11, 21, 9, 0, 0)
    # One attempt regraded alone is read with its record, as in its class.
    one, _ = discover([bb / "HW_3 IK_zhang_wei_attempt_2026-11-20-23-11-05_scara.ipynb"], NB)
    assert [(s.student, s.lms_id) for s in one] == [("zhang_wei", "zhang_wei")]
    # Without its record, a name is read with the prefix the other records show ...
    (bb / "HW_3 IK_li_wei_attempt_2026-11-20-23-10-05.txt").unlink()
    subs, _ = discover([bb], NB)
    assert sorted(s.lms_id for s in subs) == sorted(users)
    # ... or the roster's usernames; and with neither it is refused with the reason.
    alone = tmp_path / "alone"
    alone.mkdir()
    name = "HW_3 IK_li_wei_attempt_2026-11-20-23-10-05_scara.ipynb"
    (alone / name).write_bytes((bb / name).read_bytes())
    roster = [lms.RosterEntry("li_wei", "Wei Li", username="li_wei", kind="blackboard")]
    subs, _ = discover([alone], NB, roster=roster)
    assert [s.lms_id for s in subs] == ["li_wei"]
    subs, notes = discover([alone], NB)
    assert subs[0].refused.startswith("whose attempt this is cannot be told")
    assert any("not graded: whose attempt" in n for n in notes)


def test_rosters_as_each_lms_exports_them(tmp_path):
    from grader_fixtures import lmsclass as L
    from rikingrade.roster import assignment_column, load_roster

    people = L.make_class()
    want = {p.name for p in people if p.on_roster}
    for layout, kind, column in (
        ("canvas", "canvas", L.CANVAS_COLUMN),
        ("moodle", "moodle", "Assignment: HW3 fake2r (Real)"),
        ("moodle-worksheet", "moodle-worksheet", ""),
        ("blackboard", "blackboard", L.BLACKBOARD_COLUMN),
        ("brightspace", "brightspace", L.BRIGHTSPACE_ITEM),
    ):
        path = L.WRITERS[layout][1](people, tmp_path / f"{layout}.csv")
        r = load_roster(path)
        assert r.kind == kind
        names = {
            e.name if "," not in e.name else " ".join(reversed(e.name.split(", ")))
            for e in r.entries
        }
        assert names == want, layout  # Points Possible, Manual Posting, Test Student: out
        assert assignment_column(r, "", "fake2r")[0] == column, layout
        smith = [e for e in r.entries if "Smith" in e.name]
        assert len(smith) == 2 and smith[0].key != smith[1].key, layout
    bb = load_roster(tmp_path / "blackboard.csv")
    assert {e.username for e in bb.entries} >= {"li_wei", "kwame_mensah"}
    d2l = load_roster(tmp_path / "brightspace.csv")
    assert d2l.entries[0].org_id == "#20260000" and d2l.entries[0].username == "#jsmith"
    # Blackboard's .xls download: tab-delimited UTF-16
    text = (tmp_path / "blackboard.csv").read_text(encoding="utf-8").replace('","', '"\t"')
    (tmp_path / "bb.xls").write_bytes(text.encode("utf-16"))
    assert [e.username for e in load_roster(tmp_path / "bb.xls").entries] == [
        e.username for e in bb.entries
    ]
    ws = load_roster(tmp_path / "moodle-worksheet.csv")
    jose = next(e for e in ws.entries if e.name == "José Núñez")
    assert jose.moodle_id == people[2].moodle_id
    assert abs(jose.submitted_at - people[2].newest.when) < 60
    # headers written with Brightspace's "#" too
    (tmp_path / "d2l.csv").write_text(
        "#OrgDefinedId,#Username,Last Name,First Name,Email,HW3 Points Grade,"
        "End-of-Line Indicator\n#123,#li_wei,Li,Wei,w@x.edu,,#\n"
    )
    e = load_roster(tmp_path / "d2l.csv").entries[0]
    assert (e.kind, e.org_id, e.username, e.name) == ("brightspace", "#123", "#li_wei", "Wei Li")
    # a column named by --lms-column, or a part of it
    assert assignment_column(bb, "HW_2", "fake2r")[0] == "HW_2 [Total Pts: 10 Score] |12344"


def test_namesakes_are_never_matched_on_a_guess():
    from rikingrade.roster import Person, match_people

    roster = [
        lms.RosterEntry("1000", "Smith, John", "js1@uni.edu", canvas_id="1000", kind="canvas"),
        lms.RosterEntry("1007", "Smith, John", "js2@uni.edu", canvas_id="1007", kind="canvas"),
        lms.RosterEntry("2000", "Ng, Amy", "amy@uni.edu", canvas_id="2000", kind="canvas"),
    ]
    # Canvas's ids tell the two John Smiths apart; each gets their own row.
    people = [
        Person("a", "canvas", "1007", "smithjohn"),
        Person("b", "canvas", "1000", "smithjohn"),
    ]
    got = match_people(people, roster)
    assert (got["a"].entry.email, got["b"].entry.email) == ("js2@uni.edu", "js1@uni.edu")
    # A name alone (Brightspace): two rows fit, so nobody is matched, and it is said.
    d2l = match_people([Person("c", "brightspace", "", "John Smith")], roster)["c"]
    assert d2l.status == "ambiguous" and d2l.entry is None
    assert "2 roster rows are named John Smith" in d2l.note
    # Two students (two ids) whose name fits one row: neither is matched.
    plain = [lms.RosterEntry("x", "Amy Ng"), lms.RosterEntry("y", "Bo Li")]
    two = match_people(
        [Person("d", "folder", "", "Amy Ng"), Person("e", "folder", "", "amy ng")], plain
    )
    assert {m.status for m in two.values()} == {"ambiguous"}
    # An id the roster does not have: not on the roster, though a row has the same name.
    gone = match_people([Person("f", "canvas", "3000", "ngamy")], roster)["f"]
    assert gone.status == "absent" and "Ng, Amy" in gone.note
    assert (
        lms.match_roster(lms.parse_file("smithjohn_1007_5_scara.ipynb"), "x", roster).id == "1007"
    )


def test_every_file_of_a_class_is_graded_or_refused_with_the_reason(tmp_path):
    c = tmp_path / "canvas"
    touch(c / "ngamy_1001_5001_scara.ipynb")
    touch(c / "ngamy_1001_5002_helper.py")  # beside a notebook: given to its cells, noted
    touch(c / "smithjohn_1000_5000_scara.zip")
    touch(c / "lefevrefrancois_LATE_1002_text.html")
    touch(c / "rossimarco_1003_link.html")
    touch(c / "ossobo_1004_5004_scara.py")
    touch(c / "anon_Xy7Qz_5005_scara.ipynb")
    touch(c / ".DS_Store")
    subs, notes = discover([c], NB)
    got = {s.student: s.refused for s in subs}
    assert got == {
        "ngamy_1001": "",
        "smithjohn_1000": "a .zip (or other archive): unzip it first and grade the notebook inside",
        "lefevrefrancois_1002": "an online text entry (text.html), not a notebook: ask for the "
        ".ipynb file",
        "rossimarco_1003": "a web link (link.html), not a notebook: ask for the .ipynb file",
        "ossobo_1004": "an exported script, not a notebook: ask for the .ipynb file",
        "anon_Xy7Qz": "",
    }
    text = "\n".join(notes)
    assert (
        "ngamy_1001: also handed in ngamy_1001_5002_helper.py: given to the notebook's cells "
        "as helper.py" in text
    )
    assert [n for n, _ in next(s for s in subs if s.student == "ngamy_1001").handed] == [
        "helper.py"
    ]
    assert ".DS_Store: a system file, skipped" in text
    late = next(s for s in subs if s.student == "lefevrefrancois_1002")
    assert late.late and late.lms_id == "1002"
    # Moodle: an online text folder beside the file folder is the same student's
    m = tmp_path / "moodle"
    touch(m / "Jane Doe_70001_assignsubmission_file_" / NB)
    touch(m / "Jane Doe_70001_assignsubmission_onlinetext_" / "onlinetext.html")
    touch(m / "Bo Li_70002_assignsubmission_file_" / "scara.zip")
    subs, notes = discover([m], NB)
    assert {s.student: bool(s.refused) for s in subs} == {
        "Jane_Doe_70001": False,
        "Bo_Li_70002": True,
    }
    assert "unzip it first" in next(s.refused for s in subs if s.refused)


def test_canvas_late_mark_decides_and_file_times_are_checked(tmp_path):
    from rikingrade.intake import time_notes
    from rikingrade.policy import UNRELIABLE_TIME

    due = 1000 * DAY
    copied = due + 30 * DAY  # unzipped a month later, without the times
    c = tmp_path / "canvas"
    for i in range(12):
        late = "_LATE" if i < 2 else ""
        touch(c / f"student{i:02d}{late}_{100 + i}_{500 + i}_scara.ipynb", mtime=copied)
    subs, _ = discover([c], NB)
    notes = time_notes(subs, {"due": due, "grace_minutes": 0.0})
    assert any("are all within 5 s of each other" in n for n in notes), notes
    assert all(s.time_source == UNRELIABLE_TIME for s in subs)
    rules = Rules(due=due, per_day=10)
    for s in subs:
        g = apply(5, 5, s.submitted_at, s.time_source, rules, lms_late=s.late)
        assert g.late_days == (1 if s.late else 0), s.student  # not 31 days, not 0
    # Times kept, and one disagreeing with Canvas's mark: the mark is used, and it is said.
    d = tmp_path / "kept"
    touch(d / "a_100_1_scara.ipynb", mtime=due - 3600)
    touch(d / "b_101_2_scara.ipynb", mtime=due + 2 * DAY)  # no LATE mark
    touch(d / "c_LATE_102_3_scara.ipynb", mtime=due + 1.5 * DAY)
    touch(d / "e_LATE_103_4_scara.ipynb", mtime=due - 60)  # LATE, file time on time
    subs, _ = discover([d], NB)
    notes = "\n".join(time_notes(subs, {"due": due, "grace_minutes": 0.0}))
    assert "1 Canvas submission(s) without Canvas's LATE mark have a file time after" in notes
    assert "1 Canvas submission(s) marked LATE by Canvas have a file time before" in notes
    days = {
        s.student[0]: apply(5, 5, s.submitted_at, s.time_source, rules, lms_late=s.late).late_days
        for s in subs
    }
    assert days == {"a": 0, "b": 0, "c": 2, "e": 1}


def test_canvas_late_mark_within_the_grace_minutes_is_on_time(tmp_path):
    """Canvas marks LATE anything after its due time; it knows nothing of --grace-minutes.
    A LATE file whose kept time is after the due time but within the grace agrees with
    the mark and is on time by the instructor's rule: no day counted, and the note does
    not call its time "before the due date"."""
    from rikingrade.intake import time_notes

    due = 1000 * DAY
    d = tmp_path / "kept"
    touch(d / "a_100_1_scara.ipynb", mtime=due - 3600)
    touch(d / "g_LATE_101_2_scara.ipynb", mtime=due + 10 * 60)  # in the 15 min grace
    touch(d / "h_LATE_102_3_scara.ipynb", mtime=due + 20 * 60)  # after it
    touch(d / "e_LATE_103_4_scara.ipynb", mtime=due - 60)  # LATE, file time on time
    subs, _ = discover([d], NB)
    notes = "\n".join(time_notes(subs, {"due": due, "grace_minutes": 15.0}))
    assert "1 Canvas submission(s) marked LATE by Canvas have a file time before" in notes
    before = next(n for n in notes.splitlines() if "file time before" in n)
    assert "(e_103)" in before and "g_101" not in before
    assert "1 Canvas submission(s) marked LATE by Canvas were handed in within the 15 min" in notes
    rules = Rules(due=due, per_day=10, grace_minutes=15)
    grades = {s.student[0]: apply(5, 5, s.submitted_at, s.time_source, rules, lms_late=s.late)
              for s in subs}
    assert {k: g.late_days for k, g in grades.items()} == {"a": 0, "g": 0, "h": 1, "e": 1}
    assert grades["g"].final == 5 and "within the 15 min grace" in " ".join(grades["g"].notes)


def test_names_in_their_order_before_the_same_words_reversed():
    """Li Wei and Wei Li are two students (a Moodle export has no participant id): each
    download name is its own row's; a name only the other way round still finds its row."""
    from rikingrade.roster import Person, match_people

    rows = [
        lms.RosterEntry("", "Li Wei", first="Li", last="Wei", line=2),
        lms.RosterEntry("", "Wei Li", first="Wei", last="Li", line=3),
        lms.RosterEntry("", "Ana Ruiz", first="Ana", last="Ruiz", line=4),
    ]
    people = [Person(f"k{i}", "", "", n, n) for i, n in enumerate(["Li Wei", "Wei Li", "Ruiz Ana"])]
    got = match_people(people, rows)
    assert [(got[p.key].status, got[p.key].entry.line) for p in people] == [
        ("matched", 2),
        ("matched", 3),
        ("matched", 4),
    ]


def test_an_extension_by_a_roster_id_reaches_its_student_and_an_unknown_one_is_noted(tmp_path):
    """Brightspace's download names students only; the extension names them by the roster's
    username or OrgDefinedId (as typed, with or without #, any case)."""
    from rikingrade.api import _read_extensions
    from rikingrade.notebook import Submission

    e = lms.RosterEntry("", "Fatima Zahra", username="fzahra", org_id="#0042", line=2)
    s = Submission("Fatima Zahra", tmp_path / "a.ipynb", lms="brightspace", roster_key=e.key)
    ext = tmp_path / "ext.csv"
    ext.write_text(
        "student,due,reason\nfzahra,2026-10-27 12:00,x\n0042,2026-10-27 12:00,x\n"
        "#0042,2026-10-27 12:00,x\nFZahra,2026-10-27 12:00,x\nnobody,2026-10-27 12:00,x\n"
    )
    notes: list[str] = []
    rows = _read_extensions(str(ext), [s], [e], notes)
    assert [r[0] for r in rows] == ["Fatima Zahra"] * 4 + ["nobody"]
    assert len(notes) == 1 and "nobody" in notes[0] and "line 6" in notes[0]


@pytest.mark.parametrize("sep, enc", [(";", "utf-8-sig"), ("\t", "utf-16"), (",", "utf-8-sig")])
def test_an_extensions_file_saved_from_a_spreadsheet_is_read(tmp_path, sep, enc):
    """Excel saves a CSV with a BOM, with ';' where ',' is the decimal comma, or as UTF-16
    'Unicode text' with tabs: each is read as the extensions it holds."""
    from rikingrade.api import _read_extensions
    from rikingrade.notebook import Submission

    e = lms.RosterEntry("", "Ana Ruiz", username="aruiz", line=2)
    s = Submission("Ana Ruiz", tmp_path / "a.ipynb", lms="brightspace", roster_key=e.key)
    ext = tmp_path / "ext.csv"
    buf = io.StringIO()
    w = csv.writer(buf, delimiter=sep)
    w.writerows([["student", "due", "reason"], ["aruiz", "2026-10-27 12:00", "medical; see note"]])
    ext.write_bytes(buf.getvalue().encode(enc))
    notes: list[str] = []
    rows = _read_extensions(str(ext), [s], [e], notes)
    assert [(r[0], r[1], r[2]) for r in rows] == [
        ("Ana Ruiz", parse_time("2026-10-27 12:00"), "medical; see note")
    ] and notes == []


def test_a_blackboard_attempt_of_text_only_keeps_the_attempts_time(tmp_path):
    """An attempt with no file (only text typed into Blackboard) is refused with the
    reason, at the time its name gives: never the file's time (an unzip's, which made a
    student who handed in on time some days late in grades.csv)."""
    bb = tmp_path / "bb"
    _bb_record(bb, "li_wei", "2026-11-20-22-59-00", "Wei Li", files=())
    _bb_record(bb, "sob", "2026-11-20-22-58-00", "Sean OBrien")
    for p in bb.iterdir():  # the unzip's time, some days after the attempts
        os.utime(p, (time.mktime((2026, 12, 6, 17, 0, 0, 0, 0, -1)),) * 2)
    subs, _ = discover([bb], NB)
    li = next(s for s in subs if s.lms_id == "li_wei")
    assert li.refused.startswith("the attempt has no file")
    assert time.localtime(li.submitted_at)[:6] == (2026, 11, 20, 22, 59, 0)
    assert li.time_source == "download name"
