"""The real exercises: each solution notebook gets full marks in the sandbox; the exercise
stub and a monkeypatching cheat get nothing."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import rikingrade
from grader_fixtures import corpus
from grader_fixtures.helpers import FAST, require_bwrap
from rikingrade import grade
from rikingrade.assignment import available_exercises, load_assignment

import rikin

ROOT = Path(__file__).resolve().parent.parent
EXERCISES = [e for e in available_exercises() if (ROOT / "solutions" / f"{e}.ipynb").is_file()]

CHEAT = (
    "import builtins, numpy as np\n"
    "np.allclose = lambda *a, **k: True\n"
    "np.isclose = lambda *a, **k: np.True_\n"
    "np.testing.assert_allclose = lambda *a, **k: None\n"
    "builtins.isinstance = lambda *a: True\n"
    "print('All tests passed!')\n"
)


def test_every_exercise_has_a_solution():
    assert set(EXERCISES) == {"scara", "cartesian", "cylindrical", "spherical"}


@pytest.mark.parametrize("exercise", EXERCISES)
def test_solution_full_marks_stub_and_cheat_nothing(exercise, tmp_path):
    require_bwrap()
    a = load_assignment(exercise)
    cls = tmp_path / "class"
    cls.mkdir()
    solution = ROOT / "solutions" / a.notebook
    (cls / "solution.ipynb").write_bytes(solution.read_bytes())
    (cls / "stub.ipynb").write_bytes((ROOT / "exercises" / a.notebook).read_bytes())
    nb = json.loads(solution.read_text())
    redefine = "\n".join(f"def {f}(*args, **kwargs):\n    return None\n" for f in a.functions)
    nb["cells"].append(
        {
            "cell_type": "code",
            "metadata": {},
            "outputs": [],
            "execution_count": None,
            "source": CHEAT + redefine,
        }
    )
    (cls / "cheat.ipynb").write_text(json.dumps(nb))
    report = grade(exercise, [cls], tmp_path / "out", workers=2, **dict(FAST, cell_timeout=30.0))
    res = report.by_student()
    assert res["solution"].score == pytest.approx(a.max_score), res["solution"].tests
    assert res["solution"].status == "ok", res["solution"].problems
    assert res["stub"].score == 0
    # the stub's visible checks would raise NotImplementedError, but they are not run while
    # grading (they only call the answer functions): its cells all run cleanly
    assert res["stub"].status == "ok", res["stub"].problems
    assert res["cheat"].score == 0, [(t.name, t.points) for t in res["cheat"].tests]


def test_unreachable_must_raise_a_value_error_subclass_not_any_exception(tmp_path):
    # The exercises ask for ValueError: a notebook's own subclass of it counts, its own
    # subclass of Exception does not (the engine sends the exception's bases).
    require_bwrap()
    a = load_assignment("scara")
    solution = json.loads((ROOT / "solutions" / a.notebook).read_text())
    cls = tmp_path / "class"
    cls.mkdir()
    for name, base in (("own_value_error", "ValueError"), ("own_exception", "Exception")):
        nb = json.loads(json.dumps(solution))
        nb["cells"].append(
            {
                "cell_type": "code",
                "metadata": {},
                "outputs": [],
                "execution_count": None,
                "source": (
                    f"class OutOfReach({base}):\n    pass\n\n"
                    "_ik, _ik6 = ik_scara, ik_scara_6dof\n"
                    "def _own(f):\n"
                    "    def g(*args, **kwargs):\n"
                    "        try:\n            return f(*args, **kwargs)\n"
                    "        except ValueError as exc:\n            raise OutOfReach(str(exc))\n"
                    "    return g\n"
                    "ik_scara, ik_scara_6dof = _own(_ik), _own(_ik6)\n"
                ),
            }
        )
        (cls / f"{name}.ipynb").write_text(json.dumps(nb))
    report = grade("scara", [cls], tmp_path / "out", workers=2, **dict(FAST, cell_timeout=30.0))
    res = report.by_student()
    assert res["own_value_error"].score == pytest.approx(a.max_score)
    lost = {t.name: t.fraction for t in res["own_exception"].tests if t.fraction < 1}
    assert lost == {"ik_unreachable": 0.0, "ik_6dof_unreachable": 0.0}
    fb = next(t.feedback for t in res["own_exception"].tests if t.name == "ik_unreachable")
    # the class is the notebook's own: named by what it is, not by its (student-chosen) name
    assert "raised an exception of your own (a subclass of Exception)" in fb, fb
    assert "instead of ValueError" in fb and "OutOfReach" not in fb


# Process-level hostility appended to each real solution (the required functions stay
# right): the notebook must keep full marks, the batch must survive, and nothing may leak.
_LEAK = "\nif found:\n    dh_table = None  # a leak would cost the DH test\n"
_SOCKETS = corpus.SOCKETS.split("def add(")[0].replace("connected", "found") + _LEAK
_READ = (
    "import os\n"
    f"found = []\nfor p in {[str(p) for p in (ROOT / 'grader', ROOT / 'solutions', ROOT / 'tests', ROOT / '.git', Path(rikingrade.__file__).parent, Path('/etc/shadow'))]!r}:\n"  # noqa: E501
    "    try:\n"
    "        os.listdir(p) if os.path.isdir(p) else open(p, 'rb').read(10)\n"
    "        found.append(p)\n"
    "    except OSError:\n"
    "        pass\n"
    "d = os.getcwd()\n"
    "for _ in range(10):\n"
    "    try:\n"
    "        found += [n for n in os.listdir(d) if n in ('solutions', 'grader', 'hidden')]\n"
    "    except OSError:\n"
    "        pass\n"
    "    d = os.path.dirname(d)\n"
    "try:\n"
    "    import rikingrade\n"
    "    found.append('rikingrade importable')\n"
    "except ImportError:\n"
    "    pass\n" + _LEAK
)
HOSTILE_CELLS = {  # name: (cell, status, words in the feedback)
    "fork_bomb": ("import os\nwhile True:\n    os.fork()", "cell-errors", "BlockingIOError"),
    "memory_bomb": ("junk = bytearray(64 * 2**30)", "cell-errors", "MemoryError"),
    "os_exit": ("import os\nos._exit(0)", "crashed", "stopped the notebook's process"),
    "sockets": (_SOCKETS, "ok", ""),
    "read_course": (_READ, "ok", ""),
    "delete_files": (corpus.DELETE, "ok", ""),
}


@pytest.mark.parametrize("exercise", EXERCISES)
def test_process_level_hostility_costs_nothing_and_leaks_nothing(exercise, tmp_path):
    require_bwrap()
    a = load_assignment(exercise)
    solution = json.loads((ROOT / "solutions" / a.notebook).read_text())
    cls = tmp_path / "class"
    cls.mkdir()
    for name, (cell, _, _) in HOSTILE_CELLS.items():
        nb = json.loads(json.dumps(solution))
        nb["cells"].append(
            {"cell_type": "code", "metadata": {}, "outputs": [], "execution_count": None,
             "source": cell}
        )
        (cls / f"{name}.ipynb").write_text(json.dumps(nb))
    report = grade(exercise, [cls], tmp_path / "out", workers=2, **dict(FAST, cell_timeout=30.0))
    res = report.by_student()
    for name, (_, status, says) in HOSTILE_CELLS.items():
        r = res[name]
        assert r.score == pytest.approx(a.max_score), (name, r.status, r.problems)
        assert r.status == status, (name, r.reason, r.problems)
        feedback = (tmp_path / "out" / "feedback" / f"{name}.md").read_text()
        assert says in feedback, (name, feedback)
    assert (ROOT / "solutions" / a.notebook).is_file() and rikin.__file__


# ------------------------------------------------------------------ fairness, in the sandbox
_FORGED = (
    "import os\n"
    "_orig_ik_scara = ik_scara\n\n\n"
    "def ik_scara(p, l1, l2, l3):\n"
    "    big = '1' + '0' * 400\n"
    "    os.write(3, ''.join('{\"id\": %d, \"value\": [[%s, 0, 0]]}\\n' % (i, big)\n"
    "                        for i in range(1, 300)).encode())\n"
    "    return _orig_ik_scara(p, l1, l2, l3)\n"
)


def test_fairness_variants_score_their_reasoned_points_in_the_sandbox(tmp_path):
    # The same variants as tests/test_fairness.py, through the real engine: inputs as
    # numpy arrays, positional calls, the child's encoder, the feedback files.
    import fairness_variants as F
    import nbformat
    import wrong_variants as W

    require_bwrap()
    a = load_assignment("scara")
    solution = nbformat.read(str(ROOT / "solutions" / a.notebook), as_version=4)
    cls = tmp_path / "class"
    cls.mkdir()
    variants = [f for f in F.FAIR if f.arm == "scara" and f.cls != "15.4"]
    for f in variants:
        nb = W.apply(solution, f.variant())
        if f.cell:
            nb.cells.append(nbformat.v4.new_code_cell(f.cell))
        nbformat.write(nb, str(cls / f"{f.name}.ipynb"))
    forged = nbformat.read(str(ROOT / "solutions" / a.notebook), as_version=4)
    forged.cells.append(nbformat.v4.new_code_cell(_FORGED))
    nbformat.write(forged, str(cls / "forged_bigint.ipynb"))
    report = grade("scara", [cls], tmp_path / "out", workers=2, **dict(FAST, cell_timeout=30.0))
    res = report.by_student()
    for f in variants:
        want = W.expected_points(f.variant(), a.tests)
        got = {t.name: t.points for t in res[f.name].tests}
        assert got == pytest.approx(want, abs=1e-9), (f.id, res[f.name].problems)
        assert res[f.name].status != "grader-error", f.id
    # a forged 400-digit number is the student's problem: scored, never a grader error
    r = res["forged_bigint"]
    assert r.status != "grader-error" and not any(t.grader_error for t in r.tests), r.reason
    assert r.score < a.max_score
    fb = {n: (tmp_path / "out" / "feedback" / f"{n}.md").read_text() for n in res}
    # the real cause once, at the top; no checker helper names; Markdown, not HTML escapes
    helper = fb["missing_helper"]
    top, tests = helper.split("## Tests")
    assert "ModuleNotFoundError: No module named 'my_ik_helpers'" in top
    assert top.count("No module named 'my_ik_helpers'") == 1, top
    assert top.count("name 'ik_scara' is not defined (it starts") <= 1  # repeats are folded
    assert "ik_scara is not defined because code cell" in top, top
    assert "ModuleNotFoundError" not in tests and "did you rename" not in helper
    for text in fb.values():
        assert "&lt;" not in text and "&gt;" not in text and "UnsupportedResult" not in text
        assert "defines CheckFailed" not in text and "_arm_from_rows" not in text
    assert "returned a set" in fb["returns_set"]
    results = json.loads((tmp_path / "out" / "results" / "returns_set.json").read_text())
    assert all(t["output_format"] == "md" for t in results["tests"])
    import csv

    with open(tmp_path / "out" / "grades.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(r["seed"] == "20240901" for r in rows)
    assert "seed 20240901" in (tmp_path / "out" / "grading.log").read_text()
