"""The gradebook in real runs: LMS layouts in, LMS files out, regrades, overrides, kills."""

from __future__ import annotations

import csv
import io
import json
import os
import random
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

from grader_fixtures.helpers import ASSIGNMENT, SOLUTION, require_bwrap
from rikingrade.gradebook import Gradebook

PY = sys.executable
FAST = ["--memory-mb", "512", "--cell-timeout", "5", "--cpu-seconds", "30"]


def cli(*args: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [PY, "-m", "rikingrade.cli", *args], capture_output=True, text=True, timeout=timeout
    )


def notebook(wrong: bool = False, slow: float = 0.0) -> str:
    nb = json.loads(SOLUTION.read_text())
    for c in nb["cells"]:
        src = "".join(c["source"])
        if wrong and "def add(" in src:
            c["source"] = "def add(a, b):\n    return a - b"
    if slow:
        nb["cells"].insert(
            1,
            {
                "cell_type": "code",
                "metadata": {},
                "outputs": [],
                "execution_count": None,
                "source": f"import time\ntime.sleep({slow})",
            },
        )
    return json.dumps(nb)


def rows(path: Path) -> dict[str, dict[str, str]]:
    return {r["student"]: r for r in csv.DictReader(io.StringIO(path.read_text()))}


def test_canvas_download_roster_late_regrade_and_override(tmp_path):
    require_bwrap()
    c = tmp_path / "canvas"
    c.mkdir()
    due = time.mktime(time.strptime("2026-11-20 23:59", "%Y-%m-%d %H:%M"))
    people = {"smithjohn": 1000, "ngamy": 1001, "rossimarco": 1002}
    for i, (name, uid) in enumerate(people.items()):
        p = c / f"{name}_{uid}_{5000 + i}_fake2r.ipynb"
        p.write_text(notebook(wrong=name == "ngamy"))
        os.utime(p, (due - 60, due - 60))
    late = c / "rossimarco_late_1002_5100_fake2r-1.ipynb"  # a newer, late re-upload
    late.write_text(notebook())
    os.utime(late, (due + 2 * 86400, due + 2 * 86400))
    roster = tmp_path / "roster.csv"
    roster.write_text(
        "Student,ID,SIS User ID,SIS Login ID,Section\n"
        '"Smith, John",1000,S1,jsmith,A\n"Ng, Amy",1001,S2,amyng,A\n'
        '"Rossi, Marco",1002,S3,mrossi,B\n"Absent, Al",1003,S4,al,B\n'
    )
    ext = tmp_path / "extensions.csv"
    ext.write_text("student,due,reason\n1000,2026-11-19 12:00,early exam\n")
    out = tmp_path / "out"
    r = cli(
        "grade",
        str(ASSIGNMENT),
        str(c),
        "--extensions",
        str(ext),
        "--out",
        str(out),
        "--roster",
        str(roster),
        "--due",
        "2026-11-20 23:59",
        "--late-per-day",
        "10",
        "--late-cap",
        "30",
        *FAST,
    )
    assert r.returncode == 0, r.stderr
    assert "1 student(s) on the roster have no submission: Absent, Al" in r.stderr
    assert (
        "rossimarco_1002: 2 attempts; the newest (rossimarco_late_1002_5100_fake2r-1.ipynb)"
        in r.stderr
    )
    g = rows(out / "grades.csv")
    assert set(g) == {"smithjohn_1000", "ngamy_1001", "rossimarco_1002"}
    assert (g["smithjohn_1000"]["raw_score"], g["ngamy_1001"]["score"]) == ("5", "3")
    marco = g["rossimarco_1002"]
    assert (marco["raw_score"], marco["late_days"], marco["score"]) == ("5", "2", "4")
    canvas = list(csv.reader(io.StringIO((out / "canvas-fake2r.csv").read_text())))
    assert canvas[:2] == [
        ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "fake2r"],
        ["Points Possible", "", "", "", "", "5"],
    ]
    assert sorted(canvas[2:]) == [
        ["Ng, Amy", "1001", "S2", "amyng", "A", "3"],
        ["Rossi, Marco", "1002", "S3", "mrossi", "B", "4"],
        ["Smith, John", "1000", "S1", "jsmith", "A", "4"],
    ]
    fb = (out / "feedback" / "rossimarco_1002.md").read_text()
    assert "2 day(s) late, 10% per day (at most 30%), -1 points" in fb and "**Final: 4 / 5**" in fb
    # John's extension (to an earlier time: due 2026-11-19 12:00) makes his 23:58 hand-in late.
    john = rows(out / "grades.csv")["smithjohn_1000"]
    assert (john["late_days"], john["score"]) == ("2", "4")
    assert (
        "Extension: due 2026-11-19 12:00 (early exam)"
        in (out / "feedback" / "smithjohn_1000.md").read_text()
    )
    report = (out / "report" / "fake2r.html").read_text()
    assert "class report" in report and (out / "report" / "fake2r-run1.png").exists()

    # Amy fixes her notebook; regrading her file alone changes her row only.
    before = (out / "grades.csv").read_text().splitlines()
    amy = c / "ngamy_1001_5001_fake2r.ipynb"
    amy.write_text(notebook())
    os.utime(amy, (due - 60, due - 60))
    r = cli("grade", str(ASSIGNMENT), str(amy), "--out", str(out), *FAST)
    assert r.returncode == 0, r.stderr
    after = (out / "grades.csv").read_text().splitlines()
    assert len(after) == len(before) == 4
    changed = [(b, a) for b, a in zip(before, after, strict=True) if b != a]
    assert len(changed) == 1 and changed[0][1].startswith("ngamy_1001,ok,5,5,")
    assert rows(out / "grades.csv")["rossimarco_1002"]["score"] == "4"  # the policy is kept

    # An override with a reason: in grades.csv, the Canvas file and the feedback.
    r = cli(
        "override",
        "fake2r",
        "smithjohn_1000",
        "--out",
        str(out),
        "--score",
        "4.5",
        "--reason",
        "copied cell 3 from the lecture",
    )
    assert r.returncode == 0, r.stderr
    assert rows(out / "grades.csv")["smithjohn_1000"]["score"] == "4.5"
    assert "copied cell 3 from the lecture" in (out / "feedback" / "smithjohn_1000.md").read_text()
    r = cli("override", "fake2r", "nobody", "--out", str(out), "--excused", "--reason", "x")
    assert r.returncode == 2 and "no student 'nobody'" in r.stderr
    with Gradebook.open(out / "gradebook.sqlite") as gb:
        assert gb.check() == []
        assert len(gb.submissions("fake2r", "ngamy_1001")) == 2  # the wrong file is kept
        assert len(gb.submissions("fake2r", "rossimarco_1002")) == 2  # so is the early attempt
        assert [h["score"] for h in gb.history("fake2r", "ngamy_1001")] == [3.0, 5.0]


def test_moodle_folders_and_worksheet(tmp_path):
    require_bwrap()
    m = tmp_path / "moodle"
    for i, (name, wrong) in enumerate([("Jane Doe", False), ("Amy Ng", True)]):
        d = m / f"{name}_{70000 + i}_assignsubmission_file_"
        d.mkdir(parents=True)
        (d / "fake2r.ipynb").write_text(notebook(wrong))
    out = tmp_path / "out"
    r = cli("grade", str(ASSIGNMENT), str(m), "--out", str(out), *FAST)
    assert r.returncode == 0, r.stderr
    assert "Moodle import:" in r.stdout
    sheet = list(csv.DictReader(io.StringIO((out / "moodle-fake2r.csv").read_text())))
    assert [(s["Identifier"], s["Full name"], s["Grade"], s["Maximum Grade"]) for s in sheet] == [
        ("Participant 70001", "Amy Ng", "3", "5"),
        ("Participant 70000", "Jane Doe", "5", "5"),
    ]
    assert all(s["Last modified (grade)"] for s in sheet)


def test_bad_submission_paths_exit_2_with_the_reason(tmp_path):
    r = cli("grade", str(ASSIGNMENT), str(tmp_path / "no" / "such"), "--out", str(tmp_path / "o"))
    assert r.returncode == 2 and "no such file or folder" in r.stderr
    cls = tmp_path / "class"
    (cls / "alice").mkdir(parents=True)
    (cls / "alice" / "fake2r.ipynb").write_text("{}")
    (cls / "fake2r.ipynb").write_text("{}")
    r = cli("grade", str(ASSIGNMENT), str(cls), "--out", str(tmp_path / "o"))
    assert r.returncode == 2 and "does not look like a class" in r.stderr


def test_undecodable_file_name_does_not_empty_the_gradebook(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    (cls / "alice.ipynb").write_text(notebook())
    with open(os.path.join(os.fsencode(cls), b"jos\xe9.ipynb"), "w") as f:
        f.write(notebook(wrong=True))
    out = tmp_path / "out"
    r = cli("grade", str(ASSIGNMENT), str(cls), "--out", str(out), *FAST)
    assert r.returncode == 0, r.stderr
    g = rows(out / "grades.csv")
    assert len(g) == 2 and g["alice"]["score"] == "5"
    odd = next(v for k, v in g.items() if k != "alice")
    assert odd["score"] == "3" and odd["notebook"].endswith("jos\\xe9.ipynb")
    assert json.loads((out / "summary.json").read_text())["graded"] == 2


def test_a_link_to_the_solution_is_graded_zero_with_the_reason(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    (cls / "alice.ipynb").write_text(notebook())
    (cls / "mallory.ipynb").symlink_to(SOLUTION)
    out = tmp_path / "out"
    r = cli("grade", str(ASSIGNMENT), str(cls), "--out", str(out), *FAST)
    assert r.returncode == 1, r.stderr  # a refused file: graded 0, and the instructor must look
    assert "mallory.ipynb: a symbolic link: links are not followed" in r.stderr
    assert "REFUSED 1" in r.stdout
    g = rows(out / "grades.csv")
    assert (g["alice"]["score"], g["mallory"]["score"], g["mallory"]["status"]) == (
        "5",
        "0",
        "invalid",
    )
    fb = (out / "feedback" / "mallory.md").read_text()
    assert "is a symbolic link: links are not followed" in fb
    assert "fake2r_solution" not in fb  # the target is never named nor read


def _ctrl_c_as_in_a_terminal() -> None:
    """SIGINT at its default in the grader, as in a terminal's foreground job.

    A job a non-interactive shell starts with ``&`` (a CI script, three suites run side by
    side) ignores SIGINT, and Python keeps an ignored SIGINT ignored: the grader then rightly
    finishes the class (exit 0), which is not the Ctrl-C this test is about.
    """
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_ctrl_c_keeps_every_committed_grade_in_the_views(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    # enough work that the class cannot be finished before the interrupt, however slowly
    # the poll below runs on a busy machine (with 8 it once was: exit status 0, not 130)
    n_class = 40
    for i in range(n_class):
        (cls / f"s{i}.ipynb").write_text(notebook(slow=1.0))
    out = tmp_path / "out"
    p = subprocess.Popen(
        [
            PY,
            "-m",
            "rikingrade.cli",
            "grade",
            str(ASSIGNMENT),
            str(cls),
            "--out",
            str(out),
            "--workers",
            "1",
            *FAST,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=_ctrl_c_as_in_a_terminal,
    )
    db = out / "gradebook.sqlite"
    deadline = time.monotonic() + 600
    while time.monotonic() < deadline and p.poll() is None:  # wait for two committed grades
        time.sleep(0.2)
        try:
            with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5) as conn:
                if conn.execute("SELECT COUNT(*) FROM results").fetchone()[0] >= 2:
                    break
        except sqlite3.Error:
            pass
    assert p.poll() is None, "the grader ended before two grades were committed"
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert "interrupted; run the same command again to resume" in err
    with sqlite3.connect(db) as conn:
        n = conn.execute("SELECT COUNT(*) FROM results").fetchone()[0]
    g = rows(out / "grades.csv")
    assert 2 <= len(g) == n < n_class and all(v["score"] == "5" for v in g.values())


def test_killed_at_random_moments_nothing_committed_is_lost_or_doubled(tmp_path):
    """SIGKILL the grader mid-batch at seeded random moments, then finish: every result
    committed before a kill is still there, no submission is graded twice with the same
    settings, the database checks clean, and the final views hold every student."""
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    # enough work that five kills each after a few commits leave some to do: each run
    # grades only what is left (CI once saw 20 finish before the third kill)
    n = 60
    for i in range(n):
        (cls / f"s{i:02d}.ipynb").write_text(notebook(wrong=i % 3 == 0, slow=0.3))
    out = tmp_path / "out"
    db = out / "gradebook.sqlite"
    cmd = [
        PY,
        "-m",
        "rikingrade.cli",
        "grade",
        str(ASSIGNMENT),
        str(cls),
        "--out",
        str(out),
        "--workers",
        "2",
        *FAST,
    ]
    rng = random.Random(13)
    committed: set[int] = set()
    mid_run_kills = 0

    def count(table: str) -> int:
        try:
            with sqlite3.connect(f"file:{db}?mode=ro", uri=True) as conn:
                return conn.execute(f"SELECT COUNT(*) FROM {table}").fetchone()[0]
        except sqlite3.Error:
            return 0

    for attempt in range(6):
        before = count("results")
        p = subprocess.Popen(
            cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
        )
        if attempt == 0:  # at start-up, wherever it is (imports, discovery, schema)
            time.sleep(rng.uniform(0.1, 1.5))
        else:  # mid-batch: after this run's first commit, at a random moment
            deadline = time.monotonic() + 120
            while count("results") == before and p.poll() is None and time.monotonic() < deadline:
                time.sleep(0.02)
            time.sleep(rng.uniform(0.0, 0.8))
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            mid_run_kills += attempt > 0
        p.wait()
        if not db.exists():
            continue
        conn = sqlite3.connect(db)
        ids = {r[0] for r in conn.execute("SELECT id FROM results")}
        assert committed <= ids, "a committed result was lost"
        committed = ids
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
        conn.close()
    assert mid_run_kills >= 3, "the grader finished before it could be killed: make it slower"
    assert committed  # the kills fell after grades were committed
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    with Gradebook.open(db) as gb:
        assert gb.check() == []
        per_sub = gb.conn.execute(
            "SELECT submission_id, key, COUNT(*) FROM results GROUP BY submission_id, key"
        ).fetchall()
        assert len(per_sub) == n and all(c == 1 for _, _, c in per_sub)
        assert {r["id"] for r in gb.conn.execute("SELECT id FROM results")} >= committed
        states = [r["state"] for r in gb.runs()]
        # Every killed run says so (a kill at start-up may come before its run began).
        assert states[-1] == "finished" and "running" not in states
        # (a kill may also land after a run ended, while it writes the views)
        assert 1 <= states.count("interrupted") <= mid_run_kills + 1
    g = rows(out / "grades.csv")
    assert sorted(g) == [f"s{i:02d}" for i in range(n)]
    assert all(g[f"s{i:02d}"]["score"] == ("3" if i % 3 == 0 else "5") for i in range(n))
