"""Grading runs a notebook as Jupyter runs it (issue 26), on all four exercises.

Each solution notebook, changed the way students write notebooks that run in Jupyter or
Colab, is graded in the bubblewrap sandbox (one batch per exercise, 2 workers):

* ``writefile``: the IK lives in a module the notebook writes with ``%%writefile`` and
  imports in the next cell (item 1: the cell magic was skipped, every IK test scored 0);
* ``open_helper``: the same module written with ``open`` (item 1: the notebook's folder was
  not on ``sys.path``, ``ModuleNotFoundError``);
* ``longdouble``: FK and IK return ``numpy.longdouble`` arrays (item 2: "nested too deeply",
  10 -> 2.5);
* ``offline_pip``: Colab's ``!pip install`` of a library the grader does not have: it fails
  as it would offline and the feedback says why (item 1);
* ``escapes``: terminal escapes in a cell's output, a shell command's colours and an
  exception message: no output file holds a control character (item 4);
* ``cached_fk``: an FK that keeps the lengths of its first call; the statement says the
  check cells are not run, and the grade is what that gives (item 5);
* ``source_a_number``, ``five_thousand_digits``: files that are not notebooks, refused with
  the reason, never a grader error (item 3).

Some of the same notebooks also run in a fresh Jupyter kernel (nbclient, this checkout's
``python3`` kernel) and their functions' answers to the hidden calls are scored there: the
grader must give the same points (item 1: "a notebook that runs top to bottom in a fresh
Jupyter kernel gets the same function results graded").
"""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import nbformat
import numpy as np
import pytest
from grader_fixtures.helpers import FAST, require_bwrap
from rikingrade import grade
from rikingrade.assignment import load_assignment
from rikingrade.runner import _outcome
from rikingrade.wire import decode_message

ROOT = Path(__file__).resolve().parent.parent
ARMS = ("cartesian", "cylindrical", "spherical", "scara")
SEED = 20240901
SLOW = dict(FAST, cell_timeout=30.0)


def _names(arm: str) -> tuple[str, str, str, str]:
    return f"fk_{arm}", f"ik_{arm}", f"fk_{arm}_6dof", f"ik_{arm}_6dof"


def _solution(arm: str) -> dict:
    return json.loads((ROOT / "solutions" / f"{arm}.ipynb").read_text())


def _code(src: str) -> dict:
    return {"cell_type": "code", "metadata": {}, "outputs": [], "execution_count": None,
            "source": src, "id": f"added-{abs(hash(src)) % 10**8:08d}"}


def _at(nb: dict, start: str) -> int:
    (i,) = [i for i, c in enumerate(nb["cells"])
            if c["cell_type"] == "code" and "".join(c["source"]).startswith(start)]
    return i


def _writefile(arm: str) -> dict:
    nb = _solution(arm)
    i = _at(nb, f"def ik_{arm}(")
    src = "".join(nb["cells"][i]["source"])
    head = f"%%writefile {arm}_ik.py\nimport numpy as np\nimport rikin\n\n\n"
    nb["cells"][i]["source"] = head + src
    nb["cells"].insert(i + 1, _code(f"from {arm}_ik import ik_{arm}"))
    return nb


def _open_helper(arm: str) -> dict:
    nb = _solution(arm)
    i = _at(nb, f"def ik_{arm}(")
    src = "import numpy as np\nimport rikin\n\n\n" + "".join(nb["cells"][i]["source"])
    nb["cells"][i]["source"] = (
        f"with open('helpers_{arm}.py', 'w') as f:\n    f.write({src!r})"
    )
    nb["cells"].insert(i + 1, _code(f"from helpers_{arm} import ik_{arm}"))
    return nb


def _longdouble(arm: str) -> dict:
    nb = _solution(arm)
    fk, ik, fk6, ik6 = _names(arm)
    wrap = "import numpy as np\n_orig = {}\n"
    for f in (fk, ik, fk6, ik6):
        wrap += (f"_orig[{f!r}] = {f}\n\n\ndef {f}(*args):\n"
                 f"    return np.asarray(_orig[{f!r}](*args)).astype(np.longdouble)\n\n\n")
    nb["cells"].append(_code(wrap))
    return nb


def _offline_pip(arm: str) -> dict:
    nb = _solution(arm)
    nb["cells"].insert(1, _code("!pip install -q rikin-course-extras"))  # on no index here
    return nb


ESCAPES = (
    "print('\\x1b[2J\\x1b[31mred\\r\\x07')\n"
    "!printf '\\033]0;owned\\007\\033[1;31mshell\\033[0m\\n'\n"
    "raise ValueError('\\x1b[31mwrong\\x1b[0m \\x1b]0;title\\x07 here\\x9b')"
)


def _escapes(arm: str) -> dict:
    nb = _solution(arm)
    nb["cells"].insert(2, _code(ESCAPES))
    return nb


def _cached_fk(arm: str) -> dict:
    nb = _solution(arm)
    fk = f"fk_{arm}"
    nb["cells"].append(_code(
        f"_first = {{}}\n_fk_plain = {fk}\n\n\ndef {fk}(q, *lengths):\n"
        "    # keeps the lengths of its first call (a bug Run All would show at once)\n"
        "    _first.setdefault('lengths', lengths)\n"
        f"    return _fk_plain(q, *_first['lengths'])\n"))
    return nb


def _source_a_number(arm: str) -> dict:
    nb = _solution(arm)
    nb["cells"][0]["source"] = 26  # the title cell
    return nb


VARIANTS = {  # name: (builder, score, status, words in the feedback)
    "solution": (_solution, 10.0, "ok", []),
    "writefile": (_writefile, 10.0, "ok", []),
    "open_helper": (_open_helper, 10.0, "ok", []),
    "longdouble": (_longdouble, 10.0, "ok", []),
    "offline_pip": (_offline_pip, 10.0, "ok", [
        'the shell command "pip install -q rikin-course-extras" exited with status 1: '
        'grading runs offline']),
    "escapes": (_escapes, 10.0, "cell-errors", ["code cell 2 raised ValueError: wrong here"]),
    # the checks are not run (the statement says so): the first hidden call's lengths stay,
    # 1 of the 5 FK cases is right (fk 1.5 -> 0.3); R_0_3 in the 6-DOF IK does not depend on
    # the lengths
    "cached_fk": (_cached_fk, 8.8, "ok", ["1/5 random configurations right"]),
    "source_a_number": (_source_a_number, 0.0, "invalid",
                        ["not a notebook: the source of cell 1 is a number"]),
}


def _write_class(arm: str, folder: Path) -> None:
    folder.mkdir(parents=True)
    for name, (build, *_rest) in VARIANTS.items():
        (folder / f"{name}.ipynb").write_text(json.dumps(build(arm)))
    text = (ROOT / "solutions" / f"{arm}.ipynb").read_text()
    (folder / "five_thousand_digits.ipynb").write_text(
        text.replace('"nbformat": 4', '"n": ' + "1" * 5000 + ', "nbformat": 4', 1))


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    require_bwrap()
    root = tmp_path_factory.mktemp("jupyter")
    reports = {}
    for arm in ARMS:
        _write_class(arm, root / arm / "class")
        reports[arm] = grade(arm, [root / arm / "class"], root / arm / "out", workers=2,
                             seed=SEED, **SLOW)
    return root, reports


@pytest.mark.parametrize("name", [*VARIANTS, "five_thousand_digits"])
@pytest.mark.parametrize("arm", ARMS)
def test_a_notebook_that_runs_in_jupyter_gets_its_grade(graded, arm, name):
    root, reports = graded
    res = reports[arm].by_student()[name]
    _, score, status, says = VARIANTS.get(name, (None, 0.0, "invalid",
                                                 ["JSON that Jupyter cannot open"]))
    assert res.score == pytest.approx(score), (res.status, res.reason, res.problems,
                                               [(t.name, t.points) for t in res.tests])
    assert res.status == status, (res.reason, res.problems)
    feedback = (root / arm / "out" / "feedback" / f"{name}.md").read_text()
    for words in says:
        assert words in " ".join(feedback.split()), feedback


def test_files_that_are_not_notebooks_never_make_a_grader_error(graded):
    _, reports = graded
    for arm in ARMS:
        s = reports[arm].summary
        assert s["grader_errors"] == 0 and s["invalid"] == s["refused"] == 2, (arm, s)


def test_no_control_character_reaches_any_output_file(graded):
    root, _ = graded
    for arm in ARMS:
        for f in (root / arm / "out").rglob("*"):
            if not f.is_file() or f.suffix not in (".json", ".md", ".html", ".csv", ".log"):
                continue
            text = f.read_text(encoding="utf-8")
            if f.suffix == ".json":
                text = "\n".join(_strings(json.loads(text)))
            bad = {c for c in text if (ord(c) < 32 and c not in "\n\t") or 127 <= ord(c) < 160}
            assert not bad, (arm, f.name, bad)


def _strings(value):
    if isinstance(value, str):
        yield value
    elif isinstance(value, (list, dict)):
        for v in value.items() if isinstance(value, dict) else value:
            yield from _strings(v)


@pytest.mark.parametrize("arm", ARMS)
def test_the_statement_says_which_cells_run_and_how_a_call_is_timed(arm):
    # item 5: "as Run All would" while the check cells were skipped; item 6: the limit's clock
    for folder in ("solutions", "exercises"):
        nb = json.loads((ROOT / folder / f"{arm}.ipynb").read_text())
        text = " ".join(" ".join("".join(c["source"]) for c in nb["cells"]
                                 if c["cell_type"] == "markdown").split())
        assert "except the cells that only call your five functions" in text
        assert "those are not run" in text
        assert "counted as on an idle machine" in text and "not counted" in text
        assert "`%%writefile` and `!` commands included" in text


# ------------------------------------------------------------------ a fresh Jupyter kernel
FRESH = [(arm, name) for arm in ARMS for name in ("writefile", "longdouble")]
FRESH.append(("scara", "open_helper"))

CALL_ALL = """
import json as _json, pickle as _pickle, numpy as _np
from rikingrade.sandbox import child as _child
_child.np = _np
_answers = []
for _f, _args in _pickle.load(open({calls!r}, "rb")):
    try:
        _v = globals()[_f](*_args)
    except Exception as _e:
        _answers.append({{"id": 0, "error_type": type(_e).__name__, "error_message": str(_e),
                          "error_bases": _child._class_path(type(_e))}})
        continue
    try:
        _answers.append({{"id": 0, "value": _child.encode(_v)}})
    except (_child.EncodeError, RecursionError) as _e:
        _answers.append({{"id": 0, "error_type": "UnreadableResult", "error_message": str(_e),
                          "error_bases": ["rikingrade.UnreadableResult"]}})
_json.dump(_answers, open({out!r}, "w"), allow_nan=False)
"""


def _run_in_fresh_kernel(nb: dict, calls: list, folder: Path) -> list:
    """Every code cell of ``nb`` in a fresh kernel (Run All, errors allowed), then each
    call: the answers as the child's encoder sends them."""
    import nbclient

    folder.mkdir(parents=True)
    with open(folder / "calls.pkl", "wb") as f:
        pickle.dump([(c.function, list(c.arguments()[0])) for c in calls], f)
    node = nbformat.reads(json.dumps(nb), as_version=4)
    node.cells.append(nbformat.v4.new_code_cell(
        CALL_ALL.format(calls=str(folder / "calls.pkl"), out=str(folder / "answers.json"))))
    nbclient.NotebookClient(node, timeout=300, kernel_name="python3", allow_errors=True,
                            resources={"metadata": {"path": str(folder)}}).execute()
    return json.loads((folder / "answers.json").read_text())


@pytest.mark.parametrize(("arm", "name"), FRESH)
def test_a_fresh_kernel_and_the_grader_give_the_same_points(graded, tmp_path, arm, name):
    _, reports = graded
    a = load_assignment(arm)
    per_test = a.calls(SEED)
    flat = [c for calls in per_test for c in calls]
    answers = _run_in_fresh_kernel(VARIANTS[name][0](arm), flat, tmp_path / "kernel")
    outcomes = [_outcome(decode_message(json.dumps(m))) for m in answers]
    kernel, k = {}, 0
    for test, calls in zip(a.tests, per_test, strict=True):
        score = test.check(calls, outcomes[k:k + len(calls)], False)
        kernel[test.name] = float(test.weight) * score.fraction
        k += len(calls)
    got = {t.name: t.points for t in reports[arm].by_student()[name].tests}
    assert got == pytest.approx(kernel, abs=1e-9)
    assert sum(kernel.values()) == pytest.approx(10.0)  # and the notebook is right there
    assert np.isfinite(list(got.values())).all()


# ------------------------------------------------------------------ compiled in the zygote
WARM_SCRIPT = r"""
import importlib.util, json, os, socket, sys
spec = importlib.util.spec_from_file_location("child", sys.argv[1])
child = importlib.util.module_from_spec(spec)
spec.loader.exec_module(child)
child.preload(["numpy", "IPython"], sys.argv[2])
shared = ["import numpy as np\n\n\ndef f(x):\n    y = 1.0\n    return y / x\n",
          "def g():\n    while True:\n        pass\n",
          "from __future__ import annotations\nz = 1\n"]
added = child.SHELL.warm(shared)
os.makedirs(sys.argv[3])
os.chdir(sys.argv[3])
ours, theirs = socket.socketpair()
runner = child.Runner(child.Channel(theirs.fileno()), os.getpid())
runner.limit = 0.3
# the shared cells sit at other positions than in the notebook the zygote compiled
runner.run_cells([[1, "x = 1\nx"], [2, "q = 2\n"], [3, shared[0]], [4, shared[1]],
                  [5, "f(0)\n"], [6, "g()\n"], [7, "y = f(4.0)\ny\n"]], ["g"])
runner.chan.close()  # the channel holds its own copy of the socket
theirs.close()
events = [json.loads(line) for line in ours.makefile().read().splitlines()]
print(json.dumps({"added": added, "events": events,
                  "files": [runner.ns["f"].__code__.co_filename,
                            runner.ns["g"].__code__.co_filename]}))
"""


def test_cells_compiled_in_the_zygote_run_as_the_notebooks_own(tmp_path):
    """The zygote compiles the first notebook's cells once (``warm``); a later notebook
    with the same cell at another place runs that code under its own cell's name: its
    tracebacks and time limits name its cells and functions, and what it prints is the same.
    A cell with a ``__future__`` import is not compiled ahead (it changes later cells)."""
    import subprocess
    import sys

    child = ROOT / "grader" / "rikingrade" / "sandbox" / "child.py"
    r = subprocess.run([sys.executable, "-c", WARM_SCRIPT, str(child), str(tmp_path / "scr"),
                        str(tmp_path / "scr" / "work-1")], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout.splitlines()[-1])
    assert got["added"] == 2  # not the __future__ cell
    assert got["files"] == ["<cell 3>", "<cell 4>"]
    ends = {e["cell"]: e for e in got["events"] if e.get("event") == "cell_end"}
    assert ends[1]["output"] == "Out[1]: 1\n"  # the displayhook, as IPython shows it
    err = ends[5]["error"]
    assert err["type"] == "ZeroDivisionError"
    assert "cell 5, line 1" in err["traceback"] and "cell 3, line 6, in f" in err["traceback"]
    assert "return y / x" in err["traceback"]  # the line, from the cell's own source
    stop = ends[6]["timed_out"]
    assert stop["function"] == "g" and stop["stack"] == ["g"]
    assert ends[7]["error"] is None and ends[7]["output"] == "Out[7]: 0.25\n"


# ------------------------------------------------------------------ a failed shell command
def test_a_failed_pip_magic_is_shown_as_written_with_the_whole_reason():
    """``%pip install x`` runs ``<the grader's python> -m pip install x``: the note shows
    the command as the student wrote it (never the grader's interpreter path), and the
    reason reaches the feedback whole (the grader keeps a note's first characters only),
    even after a long command, which is shortened instead."""
    import sys

    from rikingrade.runner import _cell_report
    from rikingrade.sandbox import child

    runner = child.Runner(None, 0)
    reason = ("grading runs offline, so nothing can be downloaded or installed (the grader "
              "has numpy, sympy, matplotlib and rikin)")
    runner.note_command(f"{sys.executable} -m pip install modern_robotics", 1)
    runner.note_command("pip install " + " ".join(f"package-number-{i}" for i in range(20)), 1)
    magic, long = _cell_report(3, {"notes": runner.notes}).notes
    assert magic == (
        f'the shell command "%pip install modern_robotics" exited with status 1: {reason}')
    assert long.startswith('the shell command "pip install package-number-0 ')
    assert long.endswith(f'..." exited with status 1: {reason}')
