"""A class of 60 in the four LMS download layouts, with each LMS's roster export: nobody
lost, merged, mismatched or misdated, and each LMS's files right for everyone.

The class is :mod:`grader_fixtures.lmsclass`. Here the notebooks' cells are not run: the
sandboxed run (tested in test_grader_sandbox.py and the others) is replaced by one that
scores each notebook from the points its metadata carries, so the test follows every
other step of a real ``grade`` (discovery, roster, gradebook, policy, exports) for 300
files in seconds. ``test_grader_lms_e2e.py`` grades a smaller class per LMS for real.
"""

from __future__ import annotations

import csv
import html
import io
import json
import math
import subprocess
import sys
import urllib.parse
import zipfile
from pathlib import Path

import pytest
from grader_fixtures import lmsclass as L
from grader_fixtures.helpers import ASSIGNMENT
from rikingrade import api

LATE_PER_DAY = 10.0


def _grade(tmp_path, layout, monkeypatch, **kw):
    people = L.make_class()
    folder, roster = L.write(people, layout, tmp_path)
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    report = api.grade(
        str(ASSIGNMENT),
        [folder],
        out,
        roster=str(roster),
        due=L.DUE_TEXT,
        late_per_day=LATE_PER_DAY,
        unsafe_no_sandbox=True,
        quiet=True,
        **kw,
    )
    return people, out, report


def _final(p: L.Person, lms: str) -> float:
    raw = p.newest.raw
    days = p.late_days(lms)
    return round(raw - min(raw, L.MAX_SCORE * min(100.0, LATE_PER_DAY * days) / 100), 6)


def _rows(out: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8"))))


LAYOUTS = ["canvas", "moodle", "moodle-worksheet", "blackboard", "brightspace"]


@pytest.mark.parametrize("layout", LAYOUTS)
def test_a_class_of_60_nobody_lost_merged_mismatched_or_misdated(tmp_path, monkeypatch, layout):
    lms = layout.split("-")[0]
    people, out, report = _grade(tmp_path, layout, monkeypatch)
    rows = _rows(out)
    seen: dict[int, list[dict[str, str]]] = {}
    for r in rows:
        path = Path(r["notebook"])
        if path.suffix == ".ipynb":
            who, attempt = L.token(path.read_bytes())
            assert attempt == len(people[who].attempts) - 1, (r["student"], "not the newest")
        else:  # the .zip and the .py: refused with the reason, graded 0
            who = L.ZIPPED if path.suffix == ".zip" else L.SCRIPT
            assert r["status"] == "invalid" and r["score"] == "0", r
        seen.setdefault(who, []).append(r)
    handed = {p.idx for p in people if p.attempts}
    assert set(seen) == handed, "lost: " + ", ".join(people[i].name for i in handed - set(seen))
    merged = {i: len(v) for i, v in seen.items() if len(v) > 1}
    assert not merged, f"one person graded twice: {merged}"
    students = [r["student"] for r in rows]
    assert len(set(students)) == len(students) == len(handed), "two people share a row"
    for i, (r,) in seen.items():
        p = people[i]
        if p.handed != "notebook":
            continue
        assert float(r["raw_score"]) == pytest.approx(p.newest.raw), (p.name, r)
        assert int(r["late_days"]) == p.late_days(lms), ("misdated", p.name, r)
        assert float(r["score"]) == pytest.approx(_final(p, lms)), (p.name, r)
    _check_lms_file(people, out, lms, layout)
    _check_summary(people, out, layout, report)


def _expected_ambiguous(layout: str) -> set[int]:
    """Whom the roster cannot tell apart: the John Smiths, where only names match."""
    return {0, 1} if layout in ("moodle", "brightspace") else set()


def _check_summary(people, out: Path, layout: str, report) -> None:
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    roster = summary["roster"]
    assert [_who(people, n) for n in roster["missing"]] == [L.MISSING]
    withdrawn = [r for r in _rows(out) if r["roster"] == "not on roster"]
    assert [r["student"] for r in withdrawn] == roster["not_on_roster"]
    assert len(withdrawn) == 1
    path = Path(withdrawn[0]["notebook"])
    assert L.token(path.read_bytes())[0] == L.WITHDRAWN
    unsure = _expected_ambiguous(layout)
    assert len(roster["ambiguous"]) == len(unsure)
    assert {_who(people, n) for n in roster["ambiguous"]} <= unsure
    assert summary["refused"] == 2  # the .zip and the .py: the exit status is 1
    assert (summary["ambiguous"] > 0) == bool(unsure)


def _who(people, name: str) -> int:
    """The person a roster export names ("First Last", or Canvas's "Last, First")."""
    found = [p.idx for p in people if name in (p.name, f"{p.last}, {p.first}")]
    return found[0] if found else -1


def _lms_table(out: Path, lms: str) -> tuple[list[str], list[list[str]]]:
    text = (out / f"{lms}-{L.EXERCISE}.csv").read_text(encoding="utf-8")
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def _check_lms_file(people, out: Path, lms: str, layout: str) -> None:
    """Each person on the roster who handed something in appears once, under their own
    LMS id, with their grade; the withdrawn and the missing do not appear."""
    head, body = _lms_table(out, lms)
    if lms == "canvas":
        assert head == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", L.CANVAS_COLUMN]
        assert body[0][0] == "Points Possible" and body[0][5] == "5"
        body = body[1:]
        got = {r[1]: r[5] for r in body}
        ids = {p.canvas_id: p for p in people}
    elif lms == "moodle":
        assert head[:5] == ["Identifier", "Full name", "Email address", "Status", "Grade"]
        got = {r[0].removeprefix("Participant "): r[4] for r in body}
        ids = {p.moodle_id: p for p in people}
    elif lms == "blackboard":
        assert head == ["Last Name", "First Name", "Username", L.BLACKBOARD_COLUMN]
        got = {r[2]: r[3] for r in body}
        ids = {p.username: p for p in people}
    else:
        assert head == ["OrgDefinedId", "Username", "Last Name", "First Name", "Email"] + [
            L.BRIGHTSPACE_ITEM,
            "End-of-Line Indicator",
        ]
        assert all(r[-1] == "#" for r in body)
        got = {r[0]: r[5] for r in body}
        ids = {p.org_id: p for p in people}
    assert len(got) == len(body), "a student twice in the LMS file"
    unsure = _expected_ambiguous(layout) if lms == "brightspace" else set()
    wanted = {i: p for i, p in enumerate(people) if p.on_roster and p.attempts and i not in unsure}
    assert {ids[k].idx for k in got} == set(wanted), "wrong people in the LMS file"
    for k, grade in got.items():
        p = ids[k]
        want = 0.0 if p.handed != "notebook" else _final(p, lms)
        assert math.isclose(float(grade), want, abs_tol=1e-9), (lms, p.name, grade, want)


@pytest.mark.parametrize("lms", ["canvas", "moodle-worksheet"])
def test_feedback_zips_pair_each_file_with_its_student_as_the_lms_reads_names(
    tmp_path, monkeypatch, lms
):
    """Canvas's re-upload reads the first two all-digit ``_`` pieces of a name as the user
    id and the submitted file's id; Moodle's feedback upload splits a name at its first
    four ``_`` into name, participant id, plugin type and plugin name."""
    people, out, _ = _grade(tmp_path, lms, monkeypatch)
    zpath = out / f"{lms.split('-')[0]}-feedback-{L.EXERCISE}.zip"
    with zipfile.ZipFile(zpath) as z:
        names = z.namelist()
        pages = {n: z.read(n).decode() for n in names}
    by_canvas = {p.canvas_id: p for p in people}
    by_moodle = {p.moodle_id: p for p in people}
    download = {f.name for f in (tmp_path / f"{lms}-download").rglob("*")}
    graded = {p.idx for p in people if p.attempts}
    assert len(names) == len(graded)
    for name in names:
        if lms == "canvas":
            uid, fid = [x for x in name.split("_") if x.isdigit()][:2]
            p = by_canvas[uid]
            # the file id is the one of the file this student handed in
            assert any(f.split("_")[:0] == [] and f"_{uid}_{fid}_" in f for f in download), name
        else:
            info = name.split("_", 4)
            assert info[2:4] == ["assignsubmission", "file"] and info[4]
            p = by_moodle[info[1]]
        page = html.unescape(pages[name])
        # the final score first, in the page's header
        head = page[page.index("<h1>") : page.index("</p>")]
        if p.handed == "notebook" and p.late_days(lms.split("-")[0]):
            assert f"Final score: {_final(p, lms.split('-')[0]):.4g} / 5" in head, head
        assert p.name in head or L.canvas_name(p) in head or p.first in head, head


def test_the_class_report_names_links_lists_sections_and_spread(tmp_path, monkeypatch):
    people, out, _ = _grade(tmp_path, "canvas", monkeypatch)
    stats = json.loads((out / "report" / f"{L.EXERCISE}.json").read_text(encoding="utf-8"))
    rows = _rows(out)
    finals = sorted(float(r["score"]) for r in rows)
    sp = stats["spread"]
    n = len(finals)
    mean = sum(finals) / n
    assert sp["n"] == n and sp["mean"] == pytest.approx(mean)
    assert sp["sd"] == pytest.approx(math.sqrt(sum((x - mean) ** 2 for x in finals) / (n - 1)))
    assert (sp["min"], sp["max"]) == (finals[0], finals[-1])
    assert sp["p50"] == pytest.approx(
        (finals[n // 2 - 1] + finals[n // 2]) / 2 if n % 2 == 0 else finals[n // 2]
    )
    sections = {s["section"]: s for s in stats["sections"]}
    assert set(sections) == {"Section A", "Section B", "(no section)"}  # (the withdrawn)
    for name, sec in sections.items():
        mine = [float(r["score"]) for r in rows if (r["section"] or "(no section)") == name]
        assert (sec["n"], sec["mean"]) == (len(mine), pytest.approx(sum(mine) / len(mine)))
    for t in stats["tests"]:
        assert sum(t["histogram"].values()) == t["students"] == n
    page = (out / "report" / f"{L.EXERCISE}.html").read_text(encoding="utf-8")
    for p in people:
        if p.on_roster and p.attempts:
            # names from the roster (Canvas's export writes "Last, First")
            assert html.escape(f"{p.last}, {p.first}") in page, p.name
    missing = people[L.MISSING]
    assert '<h2 id="missing">Missing: on the roster, nothing handed in (1)</h2>' in page
    assert html.escape(f"{missing.last}, {missing.first}") in page
    late = [r for r in rows if int(r["late_days"])]
    assert f'<h2 id="late">Late ({len(late)})</h2>' in page
    assert '<h2 id="failed">Failed to run, crashed or timed out (2)</h2>' in page  # zip, py
    for r in rows:  # every row links to that student's feedback, which exists
        link = f'href="../feedback/{urllib.parse.quote(r["student"])}.html"'
        assert link in page, r["student"]
        assert (out / "feedback" / f"{r['student']}.html").exists()
    png = (out / "report" / f"{L.EXERCISE}-tests.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and 'src="fake2r-tests.png"' in page


def test_progress_bar_time_left_and_failures():
    from rikingrade.progress import Progress
    from rikingrade.report import SubmissionResult

    now = [0.0]
    stream = io.StringIO()
    stream.isatty = lambda: True  # type: ignore[method-assign]
    bar = Progress(10, stream=stream, clock=lambda: now[0])
    bar.update(SubmissionResult("old", "", "", "ok", max_score=5), resumed=True)
    assert "left       ?" in stream.getvalue()  # nothing graded in this run yet
    for i, status in enumerate(["ok", "invalid", "ok", "timeout"]):
        now[0] += 3.0
        bar.update(SubmissionResult(f"s{i}", "", "", status, max_score=5))
    # 4 graded in 12 s: 5 left at 3 s each
    assert bar.eta() == pytest.approx(15.0)
    last = stream.getvalue().split("\r")[-1]
    assert "5/10" in last and "left    15 s" in last and "failed 2" in last, last


def test_missing_work_is_left_out_or_given_zero_by_policy(tmp_path, monkeypatch):
    only = {2, 3, L.MISSING, L.WITHDRAWN}
    people = L.make_class()
    folder, roster = L.write(people, "blackboard", tmp_path, only)
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    kw = dict(roster=str(roster), unsafe_no_sandbox=True, quiet=True)
    api.grade(str(ASSIGNMENT), [folder], out, **kw)
    _, body = _lms_table(out, "blackboard")
    assert {r[2] for r in body} == {people[2].username, people[3].username}  # blank: left out
    # --missing zero is kept in the gradebook: a later export gives 0 too
    api.grade(str(ASSIGNMENT), [folder], out, missing="zero", **kw)
    r = subprocess.run(
        [sys.executable, "-m", "rikingrade.cli", "export", L.EXERCISE, "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    _, body = _lms_table(out, "blackboard")
    got = {r[2]: r[3] for r in body}
    assert got[people[L.MISSING].username] == "0" and len(got) == 3
    assert people[L.WITHDRAWN].username not in got
    with pytest.raises(api.PolicyError, match="--missing is blank or zero"):
        api.grade(str(ASSIGNMENT), [folder], out, missing="none", **kw)


def test_a_zip_and_an_exported_script_are_rows_refused_counted_and_logged(tmp_path, monkeypatch):
    """Issue 26 item 4 / issue 27 item 9: nothing in a class folder is simply absent."""
    from rikingrade import cli

    people = L.make_class()
    cls = tmp_path / "class"
    cls.mkdir()
    (cls / "alice.ipynb").write_bytes(L.notebook(people[2], 0))
    (cls / "bob.zip").write_bytes(b"PK\x05\x06" + bytes(18))
    (cls / "carol.py").write_text("def add(a, b):\n    return a + b\n")
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    code = cli.main(
        [str(ASSIGNMENT), str(cls), "--out", str(out), "--unsafe-no-sandbox", "--quiet"]
    )
    assert code == 1  # refused files: the instructor must look
    rows = {r["student"]: r for r in _rows(out)}
    assert set(rows) == {"alice", "bob", "carol"}
    assert (rows["bob"]["status"], rows["bob"]["score"]) == ("invalid", "0")
    assert "unzip it first" in rows["bob"]["reason"]
    assert "an exported script, not a notebook" in rows["carol"]["reason"]
    summary = json.loads((out / "summary.json").read_text())
    assert (summary["refused"], summary["submissions"]) == (2, 3)
    log = (out / "grading.log").read_text()
    assert "bob.zip: not graded: a .zip" in log and "carol.py: not graded: an exported" in log
    fb = (out / "feedback" / "bob.md").read_text()
    assert "unzip it first" in fb


def test_lms_column_given_on_a_later_run_is_found_in_the_kept_roster(tmp_path, monkeypatch):
    """The roster is kept in the gradebook, so the run that follows the note "pass
    --lms-column" may leave --roster out: the part given is then looked up among the kept
    roster's columns, and the LMS file gets the header as downloaded, with Blackboard's
    ``|12345`` (a bare "HW 3" would make Blackboard add a new column)."""
    only = {2, 3}
    people = L.make_class()
    folder, roster = L.write(people, "blackboard", tmp_path, only)
    header = "HW 3 [Total Pts: 5 Score] |12345"
    roster.write_text(roster.read_text(encoding="utf-8").replace(L.BLACKBOARD_COLUMN, header))
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    kw = dict(unsafe_no_sandbox=True, quiet=True)
    report = api.grade(str(ASSIGNMENT), [folder], out, roster=str(roster), **kw)
    assert any("pass --lms-column" in n for n in report.notes)
    assert report.summary["lms_column"] == 1  # the run asks for the instructor: exit 1
    report = api.grade(str(ASSIGNMENT), [folder], out, lms_column="HW 3", **kw)
    assert report.summary["lms_column"] == 0
    head, body = _lms_table(out, "blackboard")
    assert head[3] == header
    assert {r[2] for r in body} == {people[2].username, people[3].username}


def test_a_run_that_cannot_tell_the_assignments_roster_column_exits_1(tmp_path, monkeypatch):
    """A Blackboard roster whose columns do not name the exercise: the LMS file would get a
    header of rikin's, which Blackboard adds as a new column, so the run says which
    --lms-column to pass and ends with exit status 1 (the instructor must look); with the
    column given, 0."""
    from rikingrade import cli

    people = L.make_class()
    folder, roster = L.write(people, "blackboard", tmp_path, {2, 3})
    roster.write_text(roster.read_text(encoding="utf-8").replace(
        L.BLACKBOARD_COLUMN, "HW 3 [Total Pts: 5 Score] |12345"))
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    args = [str(ASSIGNMENT), str(folder), "--out", str(out), "--unsafe-no-sandbox", "--quiet"]
    assert cli.main(args + ["--roster", str(roster)]) == 1
    assert cli.main(args + ["--lms-column", "HW 3"]) == 0


def test_override_names_a_student_by_any_id_the_download_or_roster_gave(tmp_path, monkeypatch):
    """``rikin-grade override`` takes the student as --extensions does: the id in
    grades.csv, or their LMS id, SIS id or login, e-mail or name (case aside); a
    name two students share is refused with both ids, never guessed."""
    from rikingrade import cli

    people = L.make_class()
    only = {2, 3}
    folder, roster = L.write(people, "canvas", tmp_path, only)
    monkeypatch.setattr(api, "_run_pool", L.fake_pool)
    out = tmp_path / "out"
    api.grade(str(ASSIGNMENT), [folder], out, roster=str(roster), unsafe_no_sandbox=True,
              quiet=True)
    a, b = people[2], people[3]
    by = {"login": a.username, "name": f"{a.last.upper()}, {a.first}", "sis": f"S{b.idx:04d}"}
    for what, given in by.items():
        code = cli.main(["override", L.EXERCISE, given, "--out", str(out), "--score", "1",
                         "--reason", f"by {what}"])
        assert code == 0, (what, given)
    head, body = _lms_table(out, "canvas")
    got = {r[1]: r[5] for r in body[1:]}
    assert got == {a.canvas_id: "1", b.canvas_id: "1"}
    assert cli.main(["override", L.EXERCISE, "nobody-at-all", "--out", str(out), "--score",
                     "1", "--reason", "x"]) == 2
