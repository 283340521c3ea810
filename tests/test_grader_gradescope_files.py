"""Gradescope's autograder gives the cells the files handed in beside the notebook.

Gradescope puts an upload's files under ``/autograder/submission/`` as uploaded (sub-folders
kept). As in the LMS modes, the files below the notebook's folder are in the cells' working
folder (read by the safe reader, with its limits); a file not given is a line of the
feedback, in the notebook's language. The ``/autograder`` tree is laid out as Gradescope
lays it out (``submission/``, ``submission_metadata.json``, ``results/``).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import nbformat
import pytest
from grader_fixtures.helpers import ASSIGNMENT, require_bwrap
from rikingrade import handedfiles
from rikingrade.gradescope import gradescope_run
from test_grader_student_files import _student_folder


def _autograder(tmp_path: Path) -> Path:
    """``/autograder`` with a student's upload: the notebook, a data file, a helper module
    and a sub-folder it %runs, a link to a file of the grader's and a file too large."""
    root = tmp_path / "autograder"
    sub = _student_folder(root / "submission", "alice")
    (root / "results").mkdir()
    meta = {"created_at": "2026-11-20T10:00:00.000000-08:00", "users": [{"name": "Alice"}],
            "assignment": {"due_date": "2026-11-21T23:59:00.000000-08:00"}}
    (root / "submission_metadata.json").write_text(json.dumps(meta), encoding="utf-8")
    secret = tmp_path / "source" / "hidden_tests.py"
    secret.parent.mkdir()
    secret.write_text("SECRET = 1\n", encoding="utf-8")
    os.symlink(secret, sub / "answers.py")
    (sub / "big.bin").write_bytes(b"\0" * (1024 * 1024 + 1))
    return root


def _grade(root: Path):
    """Gradescope's autograder run on the fake ``/autograder`` tree ``root``."""
    return gradescope_run(
        str(ASSIGNMENT),
        submission=str(root / "submission"),
        results=str(root / "results" / "results.json"),
        cell_timeout=5.0,
        memory_mb=512,
    )


def _run(root: Path) -> dict:
    res = _grade(root)
    assert res.status == "ok", (res.status, res.reason, res.problems)
    return json.loads((root / "results" / "results.json").read_text(encoding="utf-8"))


def test_the_files_of_a_gradescope_upload_are_given_to_its_cells(tmp_path, monkeypatch):
    require_bwrap()
    monkeypatch.setattr(handedfiles, "MAX_FILE_BYTES", 1024 * 1024)
    root = _autograder(tmp_path)
    data = _run(root)
    # fk_2r comes from tools/fk.py (%run), the first cells read lengths.json and helper.py:
    # without them the cells fail and fk_2r is not defined
    assert data["score"] == pytest.approx(5.0), data["output"]
    assert [t["status"] for t in data["tests"]] == ["passed"] * 4, data["tests"]
    out = data["output"]
    assert "answers.py: not given to the notebook's cells: a symbolic link" in out, out
    assert "big.bin: not given to the notebook's cells: larger than the 1 MiB" in out, out
    assert "SECRET" not in out


def test_a_spanish_upload_hears_why_a_file_was_not_given_in_spanish(tmp_path, monkeypatch):
    require_bwrap()
    monkeypatch.setattr(handedfiles, "MAX_FILE_BYTES", 1024 * 1024)
    root = _autograder(tmp_path)
    path = root / "submission" / "fake2r.ipynb"
    nb = nbformat.read(path, as_version=4)
    nb.metadata["language"] = "es"
    nbformat.write(nb, path)
    out = _run(root)["output"]
    assert "answers.py: no se pasó a las celdas del notebook: es un enlace simbólico" in out, out
    assert "big.bin: no se pasó a las celdas del notebook: ocupa más de 1 MiB" in out, out
    assert "not given to the notebook's cells" not in out, out


def test_a_spanish_notebook_whose_cell_raises_is_graded_not_a_grader_error(tmp_path):
    """The status's reason names the first failing cell from the feedback's own lines,
    whatever their language (it looked for the English words, and a Spanish notebook with
    a failing cell was an internal grader error)."""
    require_bwrap()
    root = _autograder(tmp_path)
    path = root / "submission" / "fake2r.ipynb"
    nb = nbformat.read(path, as_version=4)
    nb.metadata["language"] = "es"
    nb.cells.insert(0, nbformat.v4.new_code_cell("1 / 0"))
    nbformat.write(nb, path)
    res = _grade(root)
    assert res.status == "cell-errors", (res.status, res.reason)
    assert res.reason.startswith("celda de código 1 lanzó ZeroDivisionError"), res.reason
    assert res.score == pytest.approx(5.0)
