"""A second class (:mod:`grader_fixtures.qaclass`), graded as an instructor would after
issue 27: each LMS's download and roster export, a late rule with a grace period, an
extension given by the LMS's own id, across the end of summer time.

The notebooks' cells are not run (:func:`qaclass.fake_pool` scores each by the share its
metadata gives), so every other step of a real ``grade`` is followed for 43 students in
seconds; ``test_grader_lms_e2e.py`` grades small classes for real.
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import pytest
from grader_fixtures import qaclass as Q
from grader_fixtures.helpers import ASSIGNMENT
from rikingrade import api

MAX = 5.0  # fake2r's maximum
LAYOUTS = ["canvas", "moodle", "moodle-worksheet", "blackboard", "brightspace"]


def _grade(tmp_path, layout, monkeypatch, people=None, relative=False, **kw):
    Q.local_zone(monkeypatch)
    people = people or Q.make_class()
    folder, roster = Q.write(people, layout, tmp_path)
    ext = tmp_path / "extensions.csv"
    Q.extensions(people, ext, layout.split("-")[0])
    monkeypatch.setattr(api, "_run_pool", Q.fake_pool)
    out = tmp_path / "out"
    args = dict(
        roster=str(roster),
        lms_column="HW3",
        due=Q.DUE_TEXT,
        late_per_day=Q.LATE_PER_DAY,
        late_cap=Q.LATE_CAP,
        grace_minutes=Q.GRACE_MIN,
        extensions=str(ext),
        unsafe_no_sandbox=True,
        quiet=True,
    )
    args.update(kw)
    if relative:  # the class folder as typed in a terminal opened beside it
        monkeypatch.chdir(tmp_path)
        folder = Path(folder.name)
    report = api.grade(str(ASSIGNMENT), [folder], out, **args)
    return people, folder, out, report


def _rows(out: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO((out / "grades.csv").read_text(encoding="utf-8"))))


def _who(out: Path, row: dict[str, str]) -> tuple[int, int]:
    """Whose file a grades.csv row graded (the corrupt notebook has no token)."""
    got = Q.token(Path(row["notebook"]).read_bytes())
    return got if got is not None else (Q.CORRUPT, 0)


def _ambiguous(layout: str) -> set[int]:
    """Whom a roster without the download's ids cannot tell apart by name."""
    return {0, 1} if layout in ("moodle", "brightspace") else set()


def _problems(people: list[Q.Person], out: Path, layout: str) -> list[str]:
    """Everything wrong in grades.csv: each person who handed in anything is one row, of
    their newest attempt, dated and graded right."""
    lms = layout.split("-")[0]
    seen: dict[int, list[tuple[int, dict]]] = {}
    for r in _rows(out):
        who, attempt = _who(out, r)
        seen.setdefault(who, []).append((attempt, r))
    bad = []
    for p in people:
        got = seen.pop(p.idx, [])
        if not p.attempts:
            bad += [f"{p.name}: a row, but nothing handed in"] * bool(got)
            continue
        if len(got) != 1:
            bad.append(f"{p.name}: {len(got)} rows")
            continue
        (attempt, r), newest = got[0], max(range(len(p.attempts)), key=lambda k: p.attempts[k].when)
        if attempt != newest:
            bad.append(f"{p.name}: attempt {attempt} graded, not the newest ({newest})")
        if int(r["late_days"]) != p.late_days(lms):
            bad.append(f"{p.name}: {r['late_days']} days late, not {p.late_days(lms)}")
        if not math.isclose(float(r["score"]), p.final(lms, MAX), abs_tol=1e-9):
            bad.append(f"{p.name}: final {r['score']}, not {p.final(lms, MAX)}")
        on = (
            "not on roster"
            if not p.on_roster
            else ("ambiguous" if p.idx in _ambiguous(layout) else "matched")
        )
        if r["roster"] != on:
            bad.append(f"{p.name}: roster {r['roster']!r}, not {on!r}")
    bad += [f"a row of nobody's file: {v}" for v in seen.values()]
    return bad


def _lms_rows(out: Path, lms: str) -> tuple[list[str], list[list[str]], bytes]:
    raw = (out / f"{lms}-fake2r.csv").read_bytes()
    rows = list(csv.reader(io.StringIO(raw.decode("utf-8-sig"))))
    return rows[0], rows[1:], raw


def _lms_problems(people: list[Q.Person], out: Path, layout: str) -> list[str]:
    """The LMS's grade file: the roster's column, each person on the roster who handed in
    something once under their own id with their grade; nobody else."""
    lms = layout.split("-")[0]
    head, body, raw = _lms_rows(out, lms)
    bad = []
    if lms == "canvas":
        want_head = [
            "Student",
            "ID",
            "SIS User ID",
            "SIS Login ID",
            "Section",
            f"HW3 SCARA ({Q.CANVAS_ASSIGNMENT_ID})",
        ]
        body = [r for r in body if r[0].strip() != "Points Possible"]
        key, col, ids = 1, 5, {p.canvas_id: p for p in people}
    elif lms == "moodle":
        want_head = (
            head[:5]
            if head[:5] == ["Identifier", "Full name", "Email address", "Status", "Grade"]
            else ["Identifier", "..."]
        )
        key, col = 0, 4
        ids = {f"Participant {p.moodle_id}": p for p in people}
    elif lms == "blackboard":
        want_head = ["Last Name", "First Name", "Username", Q.blackboard_column()]
        key, col, ids = 2, 3, {p.username: p for p in people}
    else:
        want_head = [
            "OrgDefinedId",
            "Username",
            "Last Name",
            "First Name",
            "Email",
            Q.brightspace_column(),
            "End-of-Line Indicator",
        ]
        key, col, ids = 0, 5, {f"#{p.org_id}": p for p in people}
        bad += [f"end of line {r[-1]!r}" for r in body if r[-1] != "#"]
    if head[: len(want_head)] != want_head:
        bad.append(f"header {head}, not {want_head}")
    got = {}
    for r in body:
        p = ids.get(r[key])
        if p is None:
            bad.append(f"a row of no one on the roster: {r}")
        elif p.idx in got:
            bad.append(f"{p.name} twice")
        else:
            got[p.idx] = r[col]
    unsure = _ambiguous(layout) if lms == "brightspace" else set()
    want = {p.idx for p in people if p.on_roster and p.attempts and p.idx not in unsure}
    bad += [f"{people[i].name} missing from the LMS file" for i in want - set(got)]
    bad += [f"{people[i].name} should not be in the LMS file" for i in set(got) - want]
    for i in set(got) & want:
        if not math.isclose(float(got[i]), people[i].final(lms, MAX), abs_tol=1e-9):
            bad.append(
                f"{people[i].name}: {got[i]} in the LMS file, not {people[i].final(lms, MAX)}"
            )
    return bad


@pytest.mark.parametrize("layout", LAYOUTS)
def test_a_class_of_43_each_lms_nobody_lost_merged_mismatched_or_misdated(
    tmp_path, monkeypatch, layout
):
    people, _, out, _ = _grade(tmp_path, layout, monkeypatch)
    assert _problems(people, out, layout) == []
    assert _lms_problems(people, out, layout) == []
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["roster"]["missing"] and len(summary["roster"]["missing"]) == 1
    assert len(summary["roster"]["not_on_roster"]) == 1


@pytest.mark.parametrize(
    "name",
    [
        "शर्माप्रिया_52300_910600_scara.ipynb",  # Devanagari vowel signs: Mc, Mn
        "สมชายใจดี_LATE_52301_910601_scara.ipynb",  # a Thai vowel sign: Mn
        "duboisrene\u0301e_52302_910602_scara-2.ipynb",  # an accent typed on its own
    ],
)
def test_canvas_names_keep_marks_as_canvas_does(name):
    """Canvas keeps Ruby's [[:word:]] of a name, marks included: such a name is still
    Canvas's (its user id read), not a loose file nobody on the roster matches."""
    from rikingrade import lms

    p = lms.parse_file(name)
    assert p is not None and p.lms == "canvas", name
    assert (p.lms_id, p.file_id) == (name.split("_")[-3], name.split("_")[-2])
    assert p.late == ("_LATE_" in name)


def _table(out: Path) -> dict[str, dict[str, str]]:
    """grades.csv by student, without the run that made each row (and each notebook's path
    as the file itself, however it was typed)."""
    table = {r["student"]: {k: v for k, v in r.items() if k != "run"} for r in _rows(out)}
    for r in table.values():
        r["notebook"] = str(Path(r["notebook"]).resolve())
    return table


def _files_of(folder: Path, p: Q.Person, layout: str) -> list[Path]:
    """Every file of ``p``'s in the download, oldest attempt first."""
    if layout.startswith("moodle"):
        return [folder / Q.moodle_folder(p) / "scara.ipynb"]
    if layout == "canvas":
        return sorted(folder.glob(f"{Q.canvas_prefix(p)}_*.ipynb"))
    mine = [f for f in folder.rglob("*.ipynb") if (Q.token(f.read_bytes()) or (-1,))[0] == p.idx]
    return sorted(mine, key=lambda f: Q.token(f.read_bytes())[1])


@pytest.mark.parametrize(
    "layout, who",
    [
        ("canvas", 4),
        ("moodle", 4),  # a file in its student's folder
        ("moodle-worksheet", Q.RESUBMITTER),
        ("blackboard", Q.WANG),  # a username holding "_"
        ("brightspace", 0),  # a John Smith: told by name only, and the roster has two
        ("brightspace-folders", 1),
    ],
)
def test_one_student_regraded_by_their_file_changes_only_that_student(
    tmp_path, monkeypatch, layout, who
):
    """The guide: to regrade one student, pass their file (here by its absolute path,
    while the class was graded by the folder's): the same student id, the same grade, and
    nobody else's row changes."""
    lms_layout = layout.removesuffix("-folders")
    people, folder, out, _ = _grade(tmp_path, lms_layout, monkeypatch, relative=True)
    if layout.endswith("-folders"):  # Brightspace's other download: a folder per submission
        folder = _brightspace_folders(folder)
        out = tmp_path / "out2"
        roster = str(next(tmp_path.glob("*Grades*")))
        kw = dict(roster=roster, lms_column="HW3", unsafe_no_sandbox=True, quiet=True)
        api.grade(str(ASSIGNMENT), [Path(folder.name)], out, **kw)
    before = _table(out)
    newest = _files_of(folder, people[who], lms_layout)[-1].resolve()
    api.grade(str(ASSIGNMENT), [newest], out, regrade=True, unsafe_no_sandbox=True, quiet=True)
    after = _table(out)
    assert set(after) == set(before), "a new student, or one lost"
    assert after == before
    runs = {r["student"]: r["run"] for r in _rows(out)}
    changed = [s for s, run in runs.items() if run == max(runs.values())]
    assert len(changed) == 1 and Q.token(Path(after[changed[0]]["notebook"]).read_bytes())[0] == who


def _brightspace_folders(folder: Path) -> Path:
    """The Brightspace download with a folder per submission (``... - Oct 24, 2026 1:10
    PM/scara.ipynb``) instead of loose files."""
    import re

    other = folder.resolve().with_name("brightspace-folders")
    other.mkdir()
    for f in folder.iterdir():
        m = re.match(r"(.*) - (\w{3} \d+, \d{4}) (\d{1,2})(\d\d) ([AP]M) - (.*)$", f.name)
        if m is None:
            continue
        d = other / f"{m[1]} - {m[2]} {m[3]}:{m[4]} {m[5]}"
        d.mkdir(exist_ok=True)
        (d / m[6]).write_bytes(f.read_bytes())
    return other


@pytest.mark.parametrize("layout", ["blackboard", "brightspace"])
def test_an_earlier_attempt_regraded_alone_does_not_replace_the_newest(
    tmp_path, monkeypatch, layout
):
    """Every attempt is kept; the one handed in last counts, even when an earlier one is
    graded after it (passed alone), and the instructor is told how to count that one."""
    people, folder, out, _ = _grade(tmp_path, layout, monkeypatch)
    before = _table(out)
    p = people[Q.RESUBMITTER]
    first = _files_of(folder, p, layout)[0]
    assert Q.token(first.read_bytes()) == (Q.RESUBMITTER, 0)
    report = api.grade(
        str(ASSIGNMENT), [first], out, regrade=True, unsafe_no_sandbox=True, quiet=True
    )
    assert _table(out) == before, "the earlier attempt's grade replaced the newest's"
    assert any("is an earlier attempt than" in n and "override" in n for n in report.notes)
    # graded and kept: its result is in the gradebook
    from rikingrade.gradebook import Gradebook

    with Gradebook.open(out / "gradebook.sqlite", readonly=True) as gb:
        sid = next(
            s for s, r in before.items() if Q.token(Path(r["notebook"]).read_bytes())[0] == p.idx
        )
        scores = [h["score"] for h in gb.history("fake2r", sid)]
    assert 0.0 in scores and scores[-1] == 0.0


@pytest.mark.parametrize("layout", ["folders", "nbgrader"])
def test_a_notebook_in_a_plain_student_folder_regraded_alone_keeps_its_student(
    tmp_path, monkeypatch, layout
):
    """A class of one folder per student (or nbgrader's submitted/<student>/<assignment>/):
    the student's notebook passed alone, as the guide says to regrade one student, is that
    student, whether typed as in the class run or by its absolute path; never a new
    student named after the file ("scara", beside the old row)."""
    monkeypatch.setattr(api, "_run_pool", Q.fake_pool)
    monkeypatch.chdir(tmp_path)
    base = Path("course/submitted") if layout == "nbgrader" else Path("class")
    inner = "scara" if layout == "nbgrader" else ""
    for who, frac in (("alice", 1.0), ("bob", 0.5)):
        nb = json.loads(Q.SOLUTION.read_bytes())
        nb["metadata"]["qa27"] = {"who": who, "attempt": 0, "frac": frac}
        path = base / who / inner / "scara.ipynb"
        path.parent.mkdir(parents=True)
        path.write_text(json.dumps(nb))
    kw = dict(unsafe_no_sandbox=True, quiet=True)
    api.grade(str(ASSIGNMENT), [base], Path("out"), **kw)
    before = {r["student"]: r for r in _rows(Path("out"))}
    assert set(before) == {"alice", "bob"}
    bob = base / "bob" / inner / "scara.ipynb"
    nb = json.loads(bob.read_text())
    nb["metadata"]["qa27"]["frac"] = 1.0  # bob's notebook, fixed
    bob.write_text(json.dumps(nb))
    for typed in (bob, bob.resolve()):
        api.grade(str(ASSIGNMENT), [typed], Path("out"), regrade=True, **kw)
        after = {r["student"]: r for r in _rows(Path("out"))}
        assert set(after) == {"alice", "bob"}, "a new student, or one lost"
        assert after["alice"] == before["alice"]
        assert float(after["bob"]["score"]) > float(before["bob"]["score"])
