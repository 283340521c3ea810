"""Reading notebooks as data and finding submissions (no code runs here)."""

from __future__ import annotations

import json
import re

import pytest
from grader_fixtures.helpers import SOLUTION
from rikingrade.notebook import NotebookError, discover, pick_notebook, read_notebook, safe_id


def test_solution_cells_in_file_order():
    nb = read_notebook(SOLUTION)
    assert [n for n, _ in nb.cells] == list(range(1, len(nb.cells) + 1))
    assert nb.cells[0][1].startswith("import matplotlib.pyplot as plt\nimport numpy as np")
    assert "def add(a, b)" in nb.cells[1][1]
    assert nb.nbformat == "4.5"


@pytest.mark.parametrize(
    "data, message",
    [
        (b"", "empty"),
        (b'{"cells": [', "not valid notebook JSON (line 1"),
        (b'"just a string"', "not a notebook"),
        (b'{"metadata": {}}', "has no 'cells'"),
        (b"\xff\xfe\x00", "not UTF-8"),
    ],
)
def test_unreadable_files_get_a_reason(tmp_path, data, message):
    p = tmp_path / "x.ipynb"
    p.write_bytes(data)
    with pytest.raises(NotebookError, match=re.escape(message)):
        read_notebook(p)


def test_lenient_reading(tmp_path):
    cells = [
        {"cell_type": "code", "source": ["a = 1\n", "b = 2"], "id": "x"},
        {"cell_type": "markdown", "source": "text", "id": "x"},
        {"cell_type": "code", "metadata": {"colab": {"id": "q"}}, "outputs": []},
        {"cell_type": "raw", "source": "raw"},
    ]
    p = tmp_path / "n.ipynb"
    p.write_text("\ufeff" + json.dumps({"nbformat": 4, "nbformat_minor": 2, "cells": cells}))
    nb = read_notebook(p)
    assert nb.cells == [(1, "a = 1\nb = 2"), (2, "")]
    assert any("duplicated" in w for w in nb.warnings)


def _nb(**top) -> dict:
    cells = [{"cell_type": "code", "source": "x = 1", "metadata": {}, "outputs": []}]
    return {"nbformat": 4, "nbformat_minor": 5, "metadata": {}, "cells": cells, **top}


def _cell(**fields) -> dict:
    return _nb(cells=[{"cell_type": "code", "source": "x = 1", "metadata": {}, **fields}])


@pytest.mark.parametrize(
    "data, message",
    [
        # issue 26: an uncaught ValueError put the whole class in grader-error (exit 1)
        (b'{"cells": [], "x": ' + b"7" * 5000 + b"}", "JSON that Jupyter cannot open"),
        # issue 26: these got status ok and "did you rename it?"
        (json.dumps(_cell(source=5)).encode(), "not a notebook: the source of cell 1 is a number"),
        (json.dumps(_nb(metadata=[1, 2])).encode(), "not a notebook: its 'metadata' is a list"),
        (json.dumps(_cell(source=None)).encode(), "the source of cell 1 is null"),
        (json.dumps(_cell(source=["a", 3])).encode(), "the source of cell 1 is a list"),
        (json.dumps(_nb(cells=["x = 1"])).encode(), "cell 1 is text, not an object"),
        (json.dumps(_nb(cells=[{"source": "x = 1"}])).encode(), "cell 1 has cell_type null"),
        (json.dumps(_cell(metadata=[])).encode(), "the metadata of cell 1 is a list"),
        (json.dumps(_cell(outputs={})).encode(), "the outputs of cell 1 are not a list"),
        (json.dumps(_nb(nbformat="4")).encode(), "its 'nbformat' is text"),
    ],
    ids=["5000-digits", "source-5", "metadata-list", "source-null", "source-list-mixed",
         "cell-a-string", "no-cell-type", "cell-metadata-list", "outputs-dict", "nbformat-text"],
)
def test_json_that_is_not_a_notebook_is_refused_with_the_reason(tmp_path, data, message):
    p = tmp_path / "x.ipynb"
    p.write_bytes(data)
    with pytest.raises(NotebookError, match=re.escape(message)):
        read_notebook(p)


def test_discover_student_folders_and_loose_files(tmp_path):
    cls = tmp_path / "class"
    (cls / "carol").mkdir(parents=True)
    (cls / "dave" / "sub").mkdir(parents=True)
    (cls / "erin" / ".ipynb_checkpoints").mkdir(parents=True)
    (cls / "empty").mkdir()
    (cls / "notes.txt").write_text("")
    (cls / "alice.ipynb").write_text("{}")
    (cls / "carol" / "fake2r.ipynb").write_text("{}")
    (cls / "carol" / "scratch.ipynb").write_text("{}")
    (cls / "dave" / "sub" / "my work.ipynb").write_text("{}")
    (cls / "erin" / ".ipynb_checkpoints" / "fake2r-checkpoint.ipynb").write_text("{}")
    (tmp_path / "bob smith (late).ipynb").write_text("{}")
    subs, notes = discover([cls, tmp_path / "bob smith (late).ipynb"], "fake2r.ipynb")
    got = {s.student: s.path.name for s in subs if not s.refused}
    bob = [k for k in got if k.startswith("bob_smith_late-")]
    assert len(bob) == 1 and re.fullmatch(r"bob_smith_late-[0-9a-f]{6}", bob[0])
    assert got == {
        "alice": "alice.ipynb",
        "carol": "fake2r.ipynb",
        "dave": "my work.ipynb",
        bob[0]: "bob smith (late).ipynb",
    }
    # Every other file and folder ends in one place: refused, with the reason.
    refused = {s.student: s.refused for s in subs if s.refused}
    assert refused == {
        "empty": "the folder is empty: nothing was handed in",
        "erin": "no notebook in the folder, only Jupyter's checkpoint copies (.ipynb_checkpoints)",
        "notes": "not a notebook (.txt)",
    }
    text = "\n".join(notes)
    assert "erin: not graded: no notebook in the folder" in text
    assert "carol: several notebooks found; graded fake2r.ipynb" in text


def test_same_name_from_two_folders_is_two_students_and_said(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (tmp_path / "a" / "x.ipynb").write_text("{}")
    (tmp_path / "b" / "x.ipynb").write_text("{}")
    subs, notes = discover([tmp_path / "a" / "x.ipynb", tmp_path / "b" / "x.ipynb"], "x.ipynb")
    ids = [s.student for s in subs]
    assert len(set(ids)) == 2 and all(re.fullmatch(r"x-[0-9a-f]{6}", i) for i in ids)
    assert "2 submissions named x" in notes[0]
    # The same two files in the other order get the same ids (traceable, not order-made).
    again, _ = discover([tmp_path / "b" / "x.ipynb", tmp_path / "a" / "x.ipynb"], "x.ipynb")
    assert {s.student: s.path for s in again} == {s.student: s.path for s in subs}


def test_safe_ids_and_picking():
    assert safe_id("../../etc/passwd") == "etc_passwd"
    assert safe_id("José García") == "José_García"
    for bad in ("+1", "-alice", "@bob", "=HYPERLINK(1)", "..x"):
        assert safe_id(bad)[0] not in "+-@=.", bad
    assert pick_notebook([], "a.ipynb") == (None, "")


def test_printable_is_the_one_place_control_characters_are_removed():
    from rikingrade import notebook
    from rikingrade.safetext import printable

    assert notebook.printable is printable  # one function (gradebook and views call it)
    assert printable("\x1b[1;31mred\x1b[0m\tok\n") == "red\tok\n"
    assert printable("a\x1b]0;title\x07b\x1b]8;;http://x\x1b\\c") == "abc"  # OSC: whole
    assert printable("x\r\x07\x00\x7f\x85y\x9b") == "xy"  # C0, DEL, C1
    assert printable("caf\udce9") == "caf\\xe9" and printable("\ud800") == "\\ud800"  # as before
    assert printable("plain text: l2 + l3 < 5") == "plain text: l2 + l3 < 5"
    assert notebook.shown("a\x1b[2Jb.ipynb") == "ab.ipynb"
