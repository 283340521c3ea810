"""The real exercises: each solution notebook gets full marks in the sandbox; the exercise
stub and a monkeypatching cheat get nothing."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from grader_fixtures.helpers import FAST, require_bwrap
from rikingrade import grade
from rikingrade.assignment import available_exercises, load_assignment

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
    assert res["stub"].status == "cell-errors"
    assert res["cheat"].score == 0, [(t.name, t.points) for t in res["cheat"].tests]
