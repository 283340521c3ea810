"""exercises/ is exactly what tools/make_exercises.py makes from solutions/.

Also: the exercises give nothing away, their stubs fail the way the notebook
expects (cells tagged raises-exception raise NotImplementedError, no other cell
raises), and the solutions carry only the outputs nbval checks.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import _hidden_harness as H
import nbformat
import pytest
from exercise_tree import copy_exercise_tree

ROOT = Path(__file__).resolve().parent.parent
ARMS = ("cartesian", "cylindrical", "spherical", "scara")


def _load_generator():
    path = ROOT / "tools" / "make_exercises.py"
    spec = importlib.util.spec_from_file_location("make_exercises", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


mx = _load_generator()


def tags(cell) -> list[str]:
    return list(cell.get("metadata", {}).get("tags", []))


def test_exercises_are_up_to_date():
    differ = mx.generate(check=True)
    assert differ == [], "run: python3 tools/make_exercises.py\n" + "\n".join(differ)


def test_check_command_exit_codes(tmp_path, monkeypatch):
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "make_exercises.py"), "--check"],
                            capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    # a copy of the tree where an exercise was hand-edited and the shared cells changed
    copy_exercise_tree(mx, tmp_path, monkeypatch)
    ex = tmp_path / "exercises" / "scara.ipynb"
    ex.write_text(ex.read_text().replace("task 3: ik_scara", "task 3: done"))
    assert mx.generate(check=True) == ["exercises/scara.ipynb"]
    checks = tmp_path / "tools" / "exercise_checks.py"
    checks.write_text(checks.read_text().replace("CHECK_TOL = 1e-6", "CHECK_TOL = 1e-5"))
    differ = mx.generate(check=True)
    # the four solutions, their exercises and the Spanish exercises
    assert len(differ) == 12 and all(d.endswith(".ipynb") for d in differ), differ
    assert sum(d.startswith("exercises/es/") for d in differ) == 4
    assert mx.main(["--check"]) == 1
    # writing fixes everything, and the shared cell now carries the edit
    assert mx.main([]) == 0
    assert mx.generate(check=True) == []
    nb = nbformat.read(tmp_path / "solutions" / "cartesian.ipynb", as_version=4)
    assert "CHECK_TOL = 1e-5" in next(c.source for c in nb.cells if "checks" in tags(c))


#: The exercises' folders: English, and each translation (tools/exercise_i18n.py).
FOLDERS = ("exercises", "exercises/es")


@pytest.mark.parametrize("folder", FOLDERS)
@pytest.mark.parametrize("name", ARMS)
def test_exercise_gives_no_answer_away(name, folder):
    sol = nbformat.read(ROOT / "solutions" / f"{name}.ipynb", as_version=4)
    if folder != "exercises":
        sol = mx.translated_solution(f"{name}.ipynb", folder.rsplit("/", 1)[1])
    ex = nbformat.read(ROOT / folder / f"{name}.ipynb", as_version=4)
    text = nbformat.writes(ex)
    assert "BEGIN SOLUTION" not in text and "END SOLUTION" not in text
    assert "**Solution.**" not in text and "**Solución.**" not in text
    own_code = [line for c in ex.cells if c.cell_type == "code"
                and not {"setup", "checks"} & set(tags(c)) for line in c.source.splitlines()]
    assert not any("solution-only" in tags(c) or "nbval-check-output" in tags(c) for c in ex.cells)
    for cell in ex.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None
    # every line of every solution region is gone
    for cell in sol.cells:
        if cell.cell_type != "code" or "### BEGIN SOLUTION" not in cell.source:
            continue
        inside = False
        for line in cell.source.splitlines():
            if "### BEGIN SOLUTION" in line:
                inside = True
            elif "### END SOLUTION" in line:
                inside = False
            elif inside and len(line.strip()) > 12 and not line.strip().startswith("#"):
                assert line not in own_code, f"{name}: answer line left in the exercise: {line!r}"
    # the drawing is there, the code that drew it (with the DH table) is not
    fig = [c for c in ex.cells if "arm-figure" in tags(c)]
    assert len(fig) == 1 and f"{name}.png" in fig[0].get("attachments", {})
    assert not any("figure-source" in tags(c) for c in ex.cells)


@pytest.mark.parametrize("folder", FOLDERS)
@pytest.mark.parametrize("name", ARMS)
def test_exercise_stubs_fail_as_the_notebook_expects(name, folder):
    ex = H.load(ROOT / folder / f"{name}.ipynb")
    _, runs = H.run_notebook(ex)
    tagged = [r for r in runs if "raises-exception" in r.tags]
    assert len(tagged) >= 10
    for r in runs:
        if "raises-exception" in r.tags:
            assert isinstance(r.error, NotImplementedError), (r.index, repr(r.error))
            assert str(r.error).startswith("task "), str(r.error)
        else:
            assert r.error is None, (r.index, repr(r.error))


@pytest.mark.parametrize("name", ARMS)
def test_solutions_are_clean_and_shared_cells_match(name):
    nb = nbformat.read(ROOT / "solutions" / f"{name}.ipynb", as_version=4)
    shared = mx.shared_sources()
    assert set(nb.metadata) == {"kernelspec", "language_info"}
    first_code = next(c for c in nb.cells if c.cell_type == "code")
    assert "setup" in tags(first_code)
    for tag in ("setup", "checks"):
        assert [c.source for c in nb.cells if tag in tags(c)] == [shared[tag]]
    for folder in ("solutions", *FOLDERS):
        for cell in nbformat.read(ROOT / folder / f"{name}.ipynb", as_version=4).cells:
            assert set(cell.metadata) <= {"tags", "jupyter", "cellView"}, (folder, cell.metadata)
    checked = 0
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        if "nbval-check-output" in tags(cell):
            checked += 1
            assert cell.outputs and cell.execution_count == checked
            assert all(o.output_type in ("stream", "execute_result") for o in cell.outputs)
        else:
            assert cell.outputs == [] and cell.execution_count is None
    assert checked >= 10
    _, runs = H.run_notebook(H.load(ROOT / "solutions" / f"{name}.ipynb"))
    assert [r.index for r in runs if r.error] == []


def test_stub_code_rules():
    src = ("def f(x):\n    \"\"\"doc\"\"\"\n    ### BEGIN SOLUTION (task 2)\n    y = x + 1\n"
           "    return y\n    ### END SOLUTION\n")
    out, names = mx.stub_code(src, "t")
    assert names == ["f"]
    assert out == 'def f(x):\n    """doc"""\n    raise NotImplementedError("task 2: f")\n'
    for bad, words in (("def f():\n    ### BEGIN SOLUTION\n    pass\n", "without an END"),
                       ("def f():\n    pass\n    ### END SOLUTION\n", "without a BEGIN"),
                       ("### BEGIN SOLUTION\nx = 1\n### END SOLUTION\n", "inside a function"),
                       ("def f():\n    ### BEGIN SOLUTION\n    ### BEGIN SOLUTION\n"
                        "    ### END SOLUTION\n", "nested")):
        with pytest.raises(mx.GenerationError, match=words):
            mx.stub_code(bad, "t")
    assert mx.top_level_names("def g():\n    return f(1)\nh(2)\n") == {"h"}
