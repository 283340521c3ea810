"""The files a student hands in beside the notebook are there when its cells run, as in
Jupyter (a kernel started in the notebook's folder), and only that student's.

The reference is a real kernel: nbclient runs the same folder and the grader must see
what it sees (the same outputs, no failing cell). Every notebook runs in the sandbox.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import nbclient
import nbformat
import pytest
from grader_fixtures.helpers import ASSIGNMENT, FAST, require_bwrap
from rikingrade import api, handedfiles
from rikingrade.notebook import discover

FK = (
    "def fk_2r(l1, l2, q1, q2):\n"
    "    x = l1 * np.cos(q1) + l2 * np.cos(q1 + q2)\n"
    "    y = l1 * np.sin(q1) + l2 * np.sin(q1 + q2)\n"
    "    return np.array([x, y])\n"
)
BATCH = (
    "def fk_2r_batch(l1, l2, q):\n"
    "    q = np.asarray(q, dtype=float)\n"
    "    return np.stack([fk_2r(l1, l2, a, b) for a, b in q])\n"
)


def _notebook(path: Path, marker_module: str = "helper") -> None:
    """A fake2r notebook that reads a data file, imports a helper module and %runs a
    file in a sub-folder: all handed in beside it."""
    cells = [
        "import json\nimport numpy as np\nwith open('lengths.json') as f:\n"
        "    lengths = json.load(f)\nprint('lengths', lengths)",
        f"import {marker_module}\nfrom {marker_module} import add\nprint({marker_module}.WHO)",
        "%run tools/fk.py\nprint(fk_2r(1.0, 1.0, 0.0, 0.0))",
        BATCH,
    ]
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(c) for c in cells]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    path.write_text(nbformat.writes(nb), encoding="utf-8")


def _student_folder(d: Path, who: str) -> Path:
    d.mkdir(parents=True)
    _notebook(d / "fake2r.ipynb")
    (d / "lengths.json").write_text(json.dumps({"l1": 1.0, "l2": 0.5}), encoding="utf-8")
    (d / "helper.py").write_text(
        f"WHO = {who!r}\n\ndef add(a, b):\n    return a + b\n", encoding="utf-8"
    )
    (d / "tools").mkdir()
    (d / "tools" / "fk.py").write_text("import numpy as np\n\n" + FK, encoding="utf-8")
    return d


def _nbclient_outputs(folder: Path, tmp: Path) -> list[tuple[str, str]]:
    """(stdout text, error name) of each code cell, run by a real kernel in a copy of
    ``folder`` (as ``jupyter nbconvert --execute`` does: the kernel starts there)."""
    work = tmp / "nbclient"
    shutil.copytree(folder, work)
    nb = nbformat.read(work / "fake2r.ipynb", as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=60, allow_errors=True, resources={"metadata": {"path": str(work)}}
    )
    client.execute()
    out = []
    for c in nb.cells:
        text = "".join(o.get("text", "") for o in c.outputs if o.output_type == "stream")
        err = next((o.ename for o in c.outputs if o.output_type == "error"), "")
        out.append((text, err))
    return out


def _grade(paths, out: Path, **kw):
    return api.grade(str(ASSIGNMENT), [str(p) for p in paths], out, **{**FAST, **kw})


def test_a_student_folders_files_are_there_as_a_real_kernel_sees_them(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    _student_folder(cls / "alice", "alice")
    _student_folder(cls / "bob", "bob")
    kernel = _nbclient_outputs(cls / "alice", tmp_path)
    assert [err for _, err in kernel] == ["", "", "", ""], kernel  # the reference runs clean
    report = _grade([cls], tmp_path / "out")
    res = report.by_student()["alice"]
    assert res.score == pytest.approx(5.0), (res.problems, res.cells)
    failing = [c for c in res.cells if c.status != "ok"]
    assert not failing, failing
    shown = {c.number: c.output for c in res.cells}
    for n, (text, _) in enumerate(kernel, start=1):
        assert shown.get(n, "") == text, (n, shown.get(n), text)
    bob = {c.number: c.output for c in report.by_student()["bob"].cells}
    assert bob[2] == "bob\n"  # each their own helper


def test_a_changed_helper_file_is_a_changed_submission(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    _student_folder(cls / "alice", "alice")
    db = tmp_path / "gradebook.sqlite"
    first = _grade([cls], tmp_path / "out1", gradebook=str(db)).by_student()["alice"]
    (cls / "alice" / "helper.py").write_text(
        "WHO = 'alice'\n\ndef add(a, b):\n    return a - b\n", encoding="utf-8"
    )
    again = _grade([cls], tmp_path / "out2", gradebook=str(db)).by_student()["alice"]
    assert again.sha256 != first.sha256
    assert again.score < first.score  # regraded with the new helper, not skipped


def test_a_notebook_passed_alone_from_its_folder_keeps_its_files(tmp_path, monkeypatch):
    """Regraded alone (the notebook's path, as the guide says), a student of a folder per
    student has the same files, so the same identity: unchanged, it is not run again."""
    require_bwrap()
    monkeypatch.chdir(tmp_path)
    _student_folder(Path("class/alice"), "alice")
    _student_folder(Path("class/bob"), "bob")
    db = str(tmp_path / "gradebook.sqlite")
    first = _grade([Path("class")], Path("out"), gradebook=db).by_student()["alice"]
    report = _grade([Path("class/alice/fake2r.ipynb")], Path("out"), gradebook=db)
    assert report.summary["resumed"] == 1
    assert report.by_student()["alice"].sha256 == first.sha256


def _canvas(folder: Path, name: str, uid: int, fid: int, orig: str, data: bytes) -> None:
    (folder / f"{name}_{uid}_{fid}_{orig}").write_bytes(data)


def test_a_flat_download_gives_each_student_only_their_own_helper(tmp_path):
    require_bwrap()
    src = tmp_path / "src"
    _student_folder(src / "a", "ngamy")
    _student_folder(src / "b", "doejane")
    flat = tmp_path / "canvas"
    flat.mkdir()
    for i, who in enumerate(["ngamy", "doejane"]):
        d, uid = src / "ab"[i], 1001 + i
        for k, orig in enumerate(["fake2r.ipynb", "helper.py", "lengths.json"]):
            _canvas(flat, who, uid, 5000 + 10 * i + k, orig, (d / orig).read_bytes())
    subs, notes = discover([flat], "fake2r.ipynb")
    handed = {s.student: sorted(n for n, _ in s.handed) for s in subs}
    assert handed == {
        "doejane_1002": ["helper.py", "lengths.json"],
        "ngamy_1001": ["helper.py", "lengths.json"],
    }, notes
    db = str(tmp_path / "gradebook.sqlite")
    report = _grade([flat], tmp_path / "out", gradebook=db)
    for who in ("ngamy", "doejane"):
        res = next(r for r in report.results if r.student.startswith(who))
        cells = {c.number: c for c in res.cells}
        assert cells[1].status == "ok" and cells[2].output == f"{who}\n", res.cells
    # one student's notebook given alone: the same files, so unchanged (not run again)
    (alone,), _ = discover([flat / "ngamy_1001_5000_fake2r.ipynb"], "fake2r.ipynb")
    assert sorted(n for n, _ in alone.handed) == ["helper.py", "lengths.json"]
    again = _grade([flat / "ngamy_1001_5000_fake2r.ipynb"], tmp_path / "out", gradebook=db)
    assert again.summary["resumed"] == 1


def test_a_link_and_an_oversize_file_are_refused_with_a_reason(tmp_path):
    require_bwrap()
    cls = tmp_path / "class"
    d = _student_folder(cls / "alice", "alice")
    secret = tmp_path / "hidden_tests.py"
    secret.write_text("SECRET = 1\n", encoding="utf-8")
    os.symlink(secret, d / "answers.py")
    (d / "big.bin").write_bytes(b"\0" * (2 * 1024 * 1024 + 1))
    report = _grade([cls], tmp_path / "out", max_file_mb=2)
    res = report.by_student()["alice"]
    text = "\n".join(res.problems)
    assert "answers.py: not given to the notebook's cells" in text and "link" in text, text
    assert "big.bin: not given to the notebook's cells: larger than the 2 MiB" in text, text
    assert res.score == pytest.approx(5.0)  # the rest of the folder is still there


def test_too_many_files_are_named_not_a_crash(tmp_path, monkeypatch):
    monkeypatch.setattr(handedfiles, "MAX_FILES", 3)
    d = tmp_path / "class" / "alice"
    d.mkdir(parents=True)
    _notebook(d / "fake2r.ipynb")
    for i in range(5):
        (d / f"f{i}.txt").write_text(str(i), encoding="utf-8")
    (sub,), _ = discover([tmp_path / "class"], "fake2r.ipynb")
    got = sub.read_handed()
    assert [n for n, _ in got.files] == ["f0.txt", "f1.txt", "f2.txt"]
    assert any("only the first 3 files" in n for n in got.notes), got.notes
