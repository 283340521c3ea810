"""The hostile and broken corpus: every submission gets exactly its score, the batch survives.

One batch grades the whole corpus (tests/grader_fixtures/corpus.py) in the bubblewrap
sandbox with 2 workers; each case then checks its score, its status and what its feedback
says. Other tests check what must hold for the whole batch: no hidden input in any
feedback, the host's files untouched, the gradebook complete, and resuming.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from grader_fixtures import corpus
from grader_fixtures.helpers import ASSIGNMENT, FAST, require_bwrap
from rikingrade import grade, repair
from rikingrade.assignment import load_assignment

import rikin

SEED = 7


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    require_bwrap()
    root = tmp_path_factory.mktemp("corpus")
    cases = corpus.write_corpus(root / "class")
    report = grade(ASSIGNMENT, [root / "class"], root / "out", workers=2, seed=SEED, **FAST)
    return root, cases, report


@pytest.mark.parametrize("case", corpus.CASES, ids=[c.name for c in corpus.CASES])
def test_case_scores_exactly(graded, case):
    root, _, report = graded
    res = report.by_student()[case.name]
    assert res.score == pytest.approx(case.score, abs=1e-9), (res.status, res.reason, res.problems)
    assert res.max_score == corpus.MAX
    assert res.status == case.status, (res.reason, res.problems)
    feedback = (root / "out" / "feedback" / f"{case.name}.md").read_text()
    for text in case.says:
        assert text in feedback, f"{text!r} not in feedback:\n{feedback}"


def test_every_submission_is_in_the_gradebook(graded):
    root, cases, report = graded
    rows = (root / "out" / "grades.csv").read_text().splitlines()
    assert rows[0].split(",")[:8] == [
        "student",
        "status",
        "score",
        "max_score",
        "add_int",
        "add_float",
        "fk_2r",
        "fk_2r_batch",
    ]
    assert sorted(r.split(",")[0] for r in rows[1:]) == sorted(cases)
    assert report.summary["submissions"] == len(cases)
    assert report.summary["invalid"] == sum(c.status == "invalid" for c in corpus.CASES)
    assert report.summary["timed_out"] == sum(c.status == "timeout" for c in corpus.CASES)
    for name in cases:
        data = json.loads((root / "out" / "results" / f"{name}.json").read_text())
        assert {t["name"] for t in data["tests"]} == {
            "add_int",
            "add_float",
            "fk_2r",
            "fk_2r_batch",
        }
        assert data["score"] == pytest.approx(report.by_student()[name].score)


def test_feedback_never_shows_hidden_inputs(graded):
    root, cases, _ = graded
    a = load_assignment(ASSIGNMENT)
    secrets = set()
    for calls in a.calls(SEED):
        for c in calls:
            for v in c.kwargs.values():
                if isinstance(v, float) and len(repr(v)) >= 12:
                    secrets.add(repr(v)[:9])
    assert secrets
    for name in cases:
        for suffix in ("md", "html"):
            text = (root / "out" / "feedback" / f"{name}.{suffix}").read_text()
            leaked = [s for s in secrets if s in text]
            assert not leaked, (name, leaked)
        text = (root / "out" / "results" / f"{name}.json").read_text()
        assert not [s for s in secrets if s in text], name
    # ... while the instructor's log has them
    log = (root / "out" / "grading.log").read_text()
    assert any(s in log for s in secrets)


def test_student_text_cannot_inject_html(graded):
    root, cases, _ = graded
    for name in cases:
        for f in ("feedback/{}.md", "feedback/{}.html", "results/{}.json"):
            assert "<script>" not in (root / "out" / f.format(name)).read_text(), (name, f)


def test_fake_pass_output_is_ignored(graded):
    root, _, report = graded
    res = report.by_student()["fake_all_passed_output"]
    assert res.score == 0
    text = (root / "out" / "results" / "fake_all_passed_output.json").read_text()
    assert "All tests passed" not in text


def test_host_files_survive_deleting_submission(graded):
    # the delete_files case tried to remove these inside its sandbox
    assert Path(rikin.__file__).is_file()
    import numpy

    assert Path(numpy.__file__).is_file()
    assert ASSIGNMENT.is_file() and corpus.SOLUTION.is_file()


def test_resume_skips_unchanged_and_regrades_changed(graded, tmp_path):
    root, cases, first = graded
    out = root / "out"
    # Unchanged files and settings: nothing is graded again, no sandbox is even started.
    again = grade(ASSIGNMENT, [root / "class"], out, workers=2, seed=SEED, **FAST)
    assert again.summary["resumed"] == len(cases)
    assert {s: r.score for s, r in again.by_student().items()} == {
        s: r.score for s, r in first.by_student().items()
    }
    assert not list(out.rglob("*.tmp")), "a temporary file was left behind"
    # Another seed is another grading key: everything would be regraded; a changed file too.
    sub = root / "class2"
    sub.mkdir()
    for name in ("solution", "renamed_fk"):
        (sub / f"{name}.ipynb").write_bytes((root / "class" / f"{name}.ipynb").read_bytes())
    grade(ASSIGNMENT, [sub], out, workers=1, seed=SEED, **FAST)
    (sub / "renamed_fk.ipynb").write_bytes((root / "class" / "solution.ipynb").read_bytes())
    third = grade(ASSIGNMENT, [sub], out, workers=1, seed=SEED, **FAST)
    assert third.summary["resumed"] == 1
    assert third.by_student()["renamed_fk"].score == 5


def test_huge_output_is_truncated(graded):
    _, _, report = graded
    res = report.by_student()["huge_output_cell"]
    noisy = [c for c in res.cells if "truncated" in c.output]
    assert len(noisy) == 1
    assert len(noisy[0].output) < 10_000 + 200
    # 5,000,001 + 588,890 characters printed, 10,000 kept (the default output_limit)
    assert noisy[0].output.endswith("[5578891 more characters of output truncated]")


def test_output_amplification_is_capped(graded):
    """2,000 failing, printing cells: every file of that student stays small (was ~53 KiB/cell)."""
    root, _, report = graded
    name = "many_failing_cells"
    res = report.by_student()[name]
    assert len(res.cells) <= 50 and len(res.problems) <= 45
    out = root / "out"
    assert len(json.dumps(res.to_dict())) < 400_000  # the gradebook's record of it
    files = [
        out / "results" / f"{name}.json",
        out / "feedback" / f"{name}.md",
        out / "feedback" / f"{name}.html",
    ]
    sizes = {f.name + f.parent.name: f.stat().st_size for f in files}
    assert all(size < 400_000 for size in sizes.values()), sizes
    kept = sum(len(c.output) for c in res.cells)
    assert kept <= 100_000 + 100
    log = (out / "grading.log").read_text()
    assert log.count(f"{name} cell ") <= 50


def test_grading_log_has_a_line_for_every_submission(graded, capfd):
    """A student's text in the log's message (a lone surrogate in a cell's source) does not
    drop that student's line (it did: a UnicodeEncodeError inside logging)."""
    root, cases, _ = graded
    log = (root / "out" / "grading.log").read_text(encoding="utf-8")
    missing = [name for name in cases if f" {name}: " not in log]
    assert not missing, missing


def test_no_text_from_a_child_can_break_the_outputs(graded):
    """Lone surrogates in messages, output, results: every file is valid UTF-8."""
    root, _, _ = graded
    for f in (root / "out").rglob("*"):
        if f.is_file() and f.suffix in (".json", ".md", ".html", ".csv", ".log"):
            f.read_bytes().decode("utf-8")  # raises on a surrogate written with surrogateescape


def _controls(text: str) -> list[str]:
    """The C0/C1 control characters (but newline and tab) in ``text``."""
    return sorted({c for c in text if (ord(c) < 32 and c not in "\n\t") or 127 <= ord(c) < 160})


def _strings(value):
    if isinstance(value, str):
        yield value
    elif isinstance(value, list):
        for v in value:
            yield from _strings(v)
    elif isinstance(value, dict):
        for k, v in value.items():
            yield k
            yield from _strings(v)


def test_no_control_character_reaches_any_output(graded):
    """Issue 26 item 4: what a student controls (messages, output, a shell command's
    colours, file names) reaches no output with a control character in it: not the CSV,
    the log, the report, the feedback, nor (JSON-escaped) the results."""
    root, _, report = graded
    res = report.by_student()["terminal_escapes"]
    assert any("[31m" in c.output or "shell" in c.output for c in res.cells)  # it did print
    for f in (root / "out").rglob("*"):
        if not f.is_file() or f.suffix not in (".json", ".md", ".html", ".csv", ".log"):
            continue
        text = f.read_text(encoding="utf-8")
        assert not _controls(text), (f.name, _controls(text))
        if f.suffix == ".json":
            bad = [s for s in _strings(json.loads(text)) if _controls(s)]
            assert not bad, (f.name, bad[:3])
    # the gradebook's record in each results file, decoded as repair reads it, too
    recs = repair.records(root / "out")
    assert len(recs) == len(list((root / "out" / "results").glob("*.json"))) > 0
    bad = [s for r in recs for s in _strings(r) if _controls(s)]
    assert not bad, bad[:3]


def test_the_gradebook_record_holds_the_grade_and_no_readable_student_text(graded):
    """``extra_data.rikin`` (what ``rikin-grade repair`` rebuilds a grade from) carries the
    whole result, but as data: the student's texts of the hostile cases (a ``<script>``
    in a message, a printed "All tests passed") appear in it only when decoded."""
    root, _, report = graded
    recs = {r["student"]["id"]: r for r in repair.records(root / "out")}
    for name in report.by_student():
        rec = recs[name]
        stored = json.loads((root / "out" / "results" / f"{name}.json").read_text())
        assert set(stored["extra_data"]["rikin"]) == {"version", "encoding", "data"}
        assert rec["result"]["score"] == stored["score"]  # no late rules in this class
        assert rec["submission"]["sha256"] == stored["extra_data"]["sha256"]
    printed = [c.output for c in report.by_student()["fake_all_passed_output"].cells]
    assert any("All tests passed" in o for o in printed)  # the student did print it
    assert "All tests passed" in json.dumps(recs["fake_all_passed_output"]["result"])
