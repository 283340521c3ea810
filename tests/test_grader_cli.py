"""The command line, its agreement with the API, outputs, reveal, and the Gradescope bundle."""

from __future__ import annotations

import inspect
import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from grader_fixtures.helpers import ASSIGNMENT, FAST, SOLUTION, require_bwrap
from rikingrade import cli
from rikingrade.api import grade
from rikingrade.gradescope import gradescope_bundle, gradescope_run
from rikingrade.report import GRADER_ERROR

PY = sys.executable


def run_cli(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [PY, "-m", "rikingrade.cli", *args], capture_output=True, text=True, env=env, timeout=300
    )


def test_help_explains_every_option_with_the_api_defaults(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["--help"])
    assert exc.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    sig = inspect.signature(grade).parameters
    options = [n for n, p in sig.items() if p.kind is inspect.Parameter.KEYWORD_ONLY]
    assert {n for n, _ in cli.GRADE_OPTIONS} == set(options)
    for name in options:
        flag = "--" + name.replace("_", "-")
        assert flag in text, flag
        default = sig[name].default
        if default is not None and not isinstance(default, bool):
            assert f"{flag} {name.upper()}" in text and f"(default: {default})" in text, name
    for word in ("gradescope-bundle", "check-sandbox", "--out", "SUBMISSIONS"):
        assert word in text


def test_parsed_defaults_are_the_api_defaults():
    ns = cli.grade_parser().parse_args(["scara", "subs/", "--out", "o"])
    for name, p in inspect.signature(grade).parameters.items():
        if p.kind is inspect.Parameter.KEYWORD_ONLY:
            assert getattr(ns, name) == p.default, name


def test_subcommand_help():
    for sub in ("gradescope-bundle", "gradescope-run", "check-sandbox"):
        r = run_cli(sub, "--help")
        assert r.returncode == 0 and "usage: rikin-grade " + sub in r.stdout


def test_bad_assignment_is_a_usage_error(tmp_path):
    r = run_cli("no_such_exercise", str(tmp_path), "--out", str(tmp_path / "o"))
    assert r.returncode == 2
    assert "no assignment named 'no_such_exercise'" in r.stderr


def test_missing_bwrap_exit_code_and_instructions(tmp_path):
    env = dict(os.environ, PATH=str(tmp_path))
    (tmp_path / "s.ipynb").write_bytes(SOLUTION.read_bytes())
    r = run_cli(str(ASSIGNMENT), str(tmp_path / "s.ipynb"), "--out", str(tmp_path / "o"), env=env)
    assert r.returncode == 3
    assert "apt-get install -y bubblewrap" in r.stderr and "--unsafe-no-sandbox" in r.stderr


def test_cli_grades_a_class_and_writes_every_output(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    (cls / "bob").mkdir(parents=True)
    (cls / "alice.ipynb").write_bytes(SOLUTION.read_bytes())
    nb = json.loads(SOLUTION.read_text())
    for c in nb["cells"]:
        if "def add(" in "".join(c["source"]):
            c["source"] = "def add(a, b):\n    return a - b"
    (cls / "bob" / "fake2r.ipynb").write_text(json.dumps(nb))
    out = tmp_path / "out"
    r = run_cli(
        str(ASSIGNMENT),
        str(cls),
        "--out",
        str(out),
        "--memory-mb",
        "512",
        "--workers",
        "2",
        "--seed",
        "3",
        "--reveal",
    )
    assert r.returncode == 0, r.stderr
    assert re.search(r"graded 2 of 2 .*mean score 4/5", r.stdout), r.stdout
    rows = (out / "grades.csv").read_text().splitlines()
    assert rows[1].startswith("alice,ok,5,5,1,1,2,1,")
    # status ok: the visible checks that would fail are not run while grading
    assert rows[2].startswith("bob,ok,3,5,0,0,2,1,")
    for student in ("alice", "bob"):
        gs = json.loads((out / "results" / f"{student}.json").read_text())
        assert set(gs) >= {"score", "tests", "output"}
        assert all(
            set(t) >= {"name", "score", "max_score", "status", "output"} for t in gs["tests"]
        )
        assert (out / "feedback" / f"{student}.html").read_text().startswith("<!DOCTYPE html>")
    md = (out / "feedback" / "bob.md").read_text()
    assert "[fail] **add_int** (0/1)" in md and "[pass] **fk_2r** (2/2)" in md
    assert "(input {" in md  # --reveal shows the hidden inputs
    assert "bob: 3/5 ok" in (out / "grading.log").read_text()
    assert json.loads((out / "summary.json").read_text())["graded"] == 2
    assert not list(out.rglob("*.tmp"))


def test_gradescope_bundle_runs_locally(tmp_path):
    require_bwrap()
    bundle = gradescope_bundle(ASSIGNMENT, tmp_path / "bundle.zip", cell_timeout=5, memory_mb=512)
    with zipfile.ZipFile(bundle) as z:
        names = set(z.namelist())
        assert {
            "setup.sh",
            "run_autograder",
            "assignment.py",
            "packages/rikin/pyproject.toml",
            "packages/rikingrade/pyproject.toml",
            "packages/rikingrade/rikingrade/spec.py",
            "packages/rikingrade/rikingrade/sandbox/child.py",
            "packages/rikin/rikin/__init__.py",
        } <= names
        assert not [n for n in names if "__pycache__" in n]
        assert (z.getinfo("run_autograder").external_attr >> 16) & 0o111
        setup = z.read("setup.sh").decode()
        assert "--no-install-recommends \\\n    bubblewrap python3 python3-venv" in setup
        # only this assignment's hidden tests: a .py assignment ships none of the exercises'
        for ex in ("scara", "cartesian", "cylindrical", "spherical"):
            assert f"packages/rikingrade/rikingrade/hidden/{ex}.py" not in names
            assert f"packages/rikingrade/rikingrade/reference/{ex}.py" not in names
        root = tmp_path / "autograder"
        z.extractall(root / "source")
    (root / "submission").mkdir()
    nb = json.loads(SOLUTION.read_text())
    nb["cells"] = [c for c in nb["cells"] if "def fk_2r_batch(" not in "".join(c["source"])]
    (root / "submission" / "fake2r.ipynb").write_text(json.dumps(nb))
    env = dict(os.environ, AUTOGRADER_ROOT=str(root), RIKIN_GRADE_PYTHON=PY)
    r = subprocess.run(
        ["bash", str(root / "source" / "run_autograder")],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert r.returncode == 0, r.stdout + r.stderr
    results = json.loads((root / "results" / "results.json").read_text())
    assert results["score"] == 4
    assert [t["status"] for t in results["tests"]] == ["passed", "passed", "passed", "failed"]
    assert "function fk_2r_batch not found" in results["output"]


def test_gradescope_run_without_a_notebook(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "answers.txt").write_text("I forgot")
    res = gradescope_run(
        str(ASSIGNMENT),
        submission=str(tmp_path / "sub"),
        results=str(tmp_path / "r" / "results.json"),
    )
    assert res.status == "invalid"
    data = json.loads((tmp_path / "r" / "results.json").read_text())
    assert data["score"] == 0 and "No .ipynb notebook found" in data["output"]


def test_api_accepts_a_single_path_and_progress_lines(tmp_path, capsys):
    require_bwrap()
    (tmp_path / "x.ipynb").write_bytes(SOLUTION.read_bytes())
    opts = dict(FAST, quiet=False)
    report = grade(
        str(ASSIGNMENT),
        tmp_path / "x.ipynb",
        tmp_path / "o",
        workers=1,
        progress=True,
        **{k: v for k, v in opts.items() if k != "quiet"},
    )
    err = capsys.readouterr()
    assert report.results[0].score == 5
    assert "1/1 x: 5/5 ok" in err.err
    assert "graded 1 of 1" in err.out
    assert Path(report.out) == (tmp_path / "o").resolve()


def test_gradescope_run_marks_not_graded_when_no_sandbox_can_start(tmp_path, monkeypatch, capsys):
    # A submission that could not be graded must not be recorded as 0: no results.json
    # (Gradescope shows an autograder failure, no score), the reason in the output.
    monkeypatch.setenv("PATH", str(tmp_path))  # no bwrap on PATH
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "fake2r.ipynb").write_bytes(SOLUTION.read_bytes())
    results = tmp_path / "r" / "results.json"
    results.parent.mkdir()
    results.write_text('{"score": 0}')  # a stale one must not stand in for this run
    res = gradescope_run(str(ASSIGNMENT), submission=str(tmp_path / "sub"), results=str(results))
    out = capsys.readouterr().out
    assert res.status == GRADER_ERROR
    assert not results.exists()
    assert "NOT GRADED" in out and "bubblewrap (bwrap) is not installed" in out
    assert "apt-get install -y bubblewrap" in out


def test_gradescope_bundle_ships_only_its_exercise(tmp_path):
    bundle = gradescope_bundle("scara", tmp_path / "b.zip")
    with zipfile.ZipFile(bundle) as z:
        names = set(z.namelist())
        z.extractall(tmp_path / "x")
    pkg = "packages/rikingrade/rikingrade"
    assert {f"{pkg}/hidden/scara.py", f"{pkg}/reference/scara.py"} <= names
    for other in ("cartesian", "cylindrical", "spherical"):
        assert not [n for n in names if other in n], other
    # the bundled grader still loads and grades its one exercise
    code = (
        "from rikingrade.assignment import load_assignment, available_exercises\n"
        "from rikingrade.reference import ARMS\n"
        "a = load_assignment('scara')\n"
        "print(available_exercises(), sorted(ARMS), len(a.tests), a.max_score)\n"
    )
    env = dict(os.environ, PYTHONPATH=str(tmp_path / "x" / "packages" / "rikingrade"))
    r = subprocess.run([PY, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("['scara'] ['scara'] "), r.stdout
    from rikingrade.assignment import load_assignment

    a = load_assignment("scara")
    assert r.stdout.split()[-2:] == [str(len(a.tests)), str(a.max_score)]


def test_gradescope_setup_fails_the_image_build_without_a_sandbox(tmp_path):
    # The instructor must learn at upload time, not from every student's submission; an
    # --unsafe-no-sandbox bundle warns there instead (its setup used to fail its own check).
    for unsafe in (False, True):
        bundle = gradescope_bundle(
            ASSIGNMENT, tmp_path / f"b{unsafe}.zip", unsafe_no_sandbox=unsafe
        )
        with zipfile.ZipFile(bundle) as z:
            setup = z.read("setup.sh").decode()
            run = z.read("run_autograder").decode()
        assert setup.startswith("#!/usr/bin/env bash") and "set -euo pipefail" in setup
        check = re.search(r"if ! (.*check-sandbox.*); then\n(.*?)\nfi", setup, re.S)
        assert check and "--unsafe-no-sandbox" not in check.group(1)
        assert ("exit 1" in check.group(2)) != unsafe
        assert ("WARNING" in check.group(2)) == unsafe
        assert ("--unsafe-no-sandbox" in run) == unsafe


def test_gradescope_lateness_from_submission_metadata(tmp_path):
    """Gradescope's submission_metadata.json says when the student handed in and their own
    due date (an extension); the score is reduced by those times, and the output says why."""
    from rikingrade.gradescope import submission_times

    meta = {
        "created_at": "2026-11-22T10:00:00.000000-05:00",
        "assignment": {"due_date": "2026-11-20T23:59:00.000000-05:00", "title": "HW3"},
        "users": [{"name": "Ana", "email": "a@x.edu", "id": 1, "assignment": {}}],
    }
    handed, due = submission_times(meta)
    assert handed - due == pytest.approx(34 * 3600 + 60)
    ext = dict(meta, users=[{"assignment": {"due_date": "2026-11-23T23:59:00-05:00"}}])
    assert submission_times(ext)[1] - due == pytest.approx(3 * 86400)  # the student's own
    require_bwrap()
    root = tmp_path / "autograder"
    (root / "submission").mkdir(parents=True)
    (root / "submission" / "fake2r.ipynb").write_bytes(SOLUTION.read_bytes())
    (root / "submission_metadata.json").write_text(json.dumps(meta))
    res = gradescope_run(
        str(ASSIGNMENT),
        submission=str(root / "submission"),
        results=str(root / "results" / "results.json"),
        late_per_day=10,
        cell_timeout=5,
        memory_mb=512,
    )
    assert res.score == 5
    data = json.loads((root / "results" / "results.json").read_text())
    assert data["score"] == 4.0  # 2 started days late, 10% of 5 each
    assert data["output"].startswith("Late: submitted") and "2 day(s) late" in data["output"]
    assert "rikin" not in data.get("extra_data", {})  # the grader's record stays local


def test_gradescope_bundle_refuses_an_old_python_and_passes_the_late_rules(tmp_path):
    bundle = gradescope_bundle(ASSIGNMENT, tmp_path / "b.zip", late_per_day=5, late_cap=20)
    with zipfile.ZipFile(bundle) as z:
        setup = z.read("setup.sh").decode()
        run = z.read("run_autograder").decode()
    assert "sys.version_info < (3, 10)" in setup and "Ubuntu 22.04" in setup
    assert "--late-per-day 5 --late-cap 20 --grace-minutes 0" in run
    r = subprocess.run(["bash", "-n", "-c", setup], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_files_that_are_not_notebooks_are_invalid_with_a_reason_never_a_grader_error(tmp_path):
    """Issue 26: a 5,000-digit number in one student's JSON put the class in grader-error;
    JSON that is not a notebook was graded 'ok'. Each is refused with its reason (status
    invalid, counted as refused in summary.json), and the run exits 1 as for any file that
    is not a notebook (the instructor's guide), with no grader error."""
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    (cls / "alice.ipynb").write_bytes(SOLUTION.read_bytes())
    text = SOLUTION.read_text()
    (cls / "bob.ipynb").write_text(text.replace('"nbformat": 4', '"x": ' + "1" * 5000
                                                + ', "nbformat": 4', 1))
    nb = json.loads(text)
    nb["cells"][0]["source"] = 12
    (cls / "carol.ipynb").write_text(json.dumps(nb))
    nb = json.loads(text)
    nb["metadata"] = ["kernelspec"]
    (cls / "dave.ipynb").write_text(json.dumps(nb))
    out = tmp_path / "out"
    r = run_cli(str(ASSIGNMENT), str(cls), "--out", str(out), "--memory-mb", "512")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "REFUSED 3" in r.stdout and "Traceback" not in r.stdout + r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["invalid"] == 3 and summary["grader_errors"] == 0, summary
    assert summary["refused"] == 3, summary
    assert summary["submissions"] == 4 and summary["failed_to_run"] == 3
    rows = {row.split(",")[0]: row for row in (out / "grades.csv").read_text().splitlines()}
    assert rows["alice"].startswith("alice,ok,5,")
    assert rows["bob"].startswith("bob,invalid,0,")
    assert "JSON that Jupyter cannot open" in rows["bob"]
    assert "not a notebook: the source of cell 1 is a number" in rows["carol"]
    assert "not a notebook: its 'metadata' is a list" in rows["dave"]


def test_terminal_escapes_from_a_student_never_reach_the_terminal_or_a_file(tmp_path):
    """Issue 26 item 4: a file name and an exception message with terminal escapes; the
    instructor's terminal (the CLI's output) and every file written stay free of them."""
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    nb = json.loads(SOLUTION.read_text())
    nb["cells"].insert(1, {"cell_type": "code", "metadata": {}, "outputs": [],
                           "execution_count": None,
                           "source": "raise ValueError('\\x1b]0;owned\\x07\\x1b[31mred\\r')"})
    (cls / "mal\x1b[31mlory\r.ipynb").write_text(json.dumps(nb))
    (cls / "alice.ipynb").write_bytes(SOLUTION.read_bytes())
    out = tmp_path / "out"
    r = run_cli(str(ASSIGNMENT), str(cls), "--out", str(out), "--memory-mb", "512",
                "--progress")
    assert r.returncode == 0, r.stdout + r.stderr
    for text in (r.stdout, r.stderr):
        assert "\x1b" not in text and "\r" not in text and "\x07" not in text, text
    seen = 0
    for f in out.rglob("*"):
        if f.is_file() and f.suffix in (".json", ".md", ".html", ".csv", ".log"):
            text = f.read_text(encoding="utf-8")
            if f.suffix == ".json":  # escaped as \\u001b there: look at the strings
                text = "\n".join(_json_strings(json.loads(text)))
            assert not any(c in text for c in "\x1b\r\x07"), f
            seen += "red" in text
    assert seen >= 4  # the message is there, without its escapes


def _json_strings(value):
    if isinstance(value, str):
        yield value
    elif isinstance(value, (list, dict)):
        for v in value.items() if isinstance(value, dict) else value:
            yield from _json_strings(v)
