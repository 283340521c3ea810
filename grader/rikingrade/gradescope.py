"""Gradescope: build the autograder bundle, and grade the one submission inside it.

Gradescope unzips the bundle into ``/autograder/source``, runs ``setup.sh`` once when the
image is built, then for each submission copies ``run_autograder`` to
``/autograder/run_autograder``, runs it with the upload in ``/autograder/submission`` and
reads ``/autograder/results/results.json``. ``AUTOGRADER_ROOT`` (default ``/autograder``)
and ``RIKIN_GRADE_PYTHON`` override those locations, which is how the tests run a bundle
locally.
"""

from __future__ import annotations

import io
import json
import shutil
import stat
import tempfile
import zipfile
from pathlib import Path

from . import __version__
from .api import DEFAULT_SEED, grade
from .assignment import load_assignment
from .notebook import _notebooks_in, pick_notebook
from .outputs import atomic_write
from .report import GRADER_ERROR, SubmissionResult
from .sandbox.config import SandboxUnavailable, package_dir

SETUP_SH = """#!/usr/bin/env bash
# Gradescope runs this once while building the autograder image (Ubuntu, as root).
set -euo pipefail
cd "$(dirname "$0")"
export DEBIAN_FRONTEND=noninteractive
apt-get update
apt-get install -y --no-install-recommends bubblewrap python3 python3-venv python3-pip
python3 -m venv /opt/rikin-venv
/opt/rikin-venv/bin/pip install --upgrade pip
/opt/rikin-venv/bin/pip install ./packages/rikin ./packages/rikingrade
# Fail the image build (Gradescope shows this log on the Configure Autograder page) rather
# than every student's submission later, if student code cannot be isolated here.
if ! /opt/rikin-venv/bin/python -m rikingrade.cli check-sandbox {check_flag}; then
    echo "ERROR: bubblewrap cannot isolate student code in this container." >&2
    echo "Rebuild the bundle with: rikin-grade gradescope-bundle ... --unsafe-no-sandbox" >&2
    echo "(only if you accept that student code then runs as root beside the grader" >&2
    echo " and could read the hidden tests and the reference solutions)." >&2
    exit 1
fi
"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Gradescope runs this for every submission. Paths can be overridden to test locally.
set -uo pipefail
ROOT="${{AUTOGRADER_ROOT:-/autograder}}"
PY="${{RIKIN_GRADE_PYTHON:-/opt/rikin-venv/bin/python}}"
mkdir -p "$ROOT/results"
exec "$PY" -m rikingrade.cli gradescope-run {assignment} \\
    --submission "$ROOT/submission" --results "$ROOT/results/results.json" {options}
"""

PYPROJECT = """[build-system]
requires = ["setuptools>=64", "wheel"]
build-backend = "setuptools.build_meta"

[project]
name = "{name}"
version = "{version}"
requires-python = ">=3.10"
dependencies = [{deps}]

[tool.setuptools.packages.find]
where = ["."]
include = ["{name}", "{name}.*"]
"""


def _add_tree(z: zipfile.ZipFile, src: Path, arc: str) -> None:
    for p in sorted(src.rglob("*")):
        if "__pycache__" in p.parts or p.suffix in (".pyc", ".pyo") or not p.is_file():
            continue
        z.write(p, f"{arc}/{p.relative_to(src).as_posix()}")


def _add_text(z: zipfile.ZipFile, arc: str, text: str, executable: bool = False) -> None:
    info = zipfile.ZipInfo(arc, date_time=(2024, 1, 1, 0, 0, 0))
    info.external_attr = ((0o755 if executable else 0o644) | stat.S_IFREG) << 16
    info.compress_type = zipfile.ZIP_DEFLATED
    z.writestr(info, text)


def gradescope_bundle(
    assignment: str | Path,
    out: str | Path = "bundle.zip",
    *,
    seed: int = DEFAULT_SEED,
    reveal: bool = False,
    timeout: float | None = None,
    cell_timeout: float = 30.0,
    memory_mb: int = 1024,
    unsafe_no_sandbox: bool = False,
) -> Path:
    """Write the Gradescope autograder zip for ``assignment``; returns its path.

    The zip holds ``setup.sh``, ``run_autograder``, ``packages/rikin`` and
    ``packages/rikingrade`` (with the hidden tests and the reference), and, when the
    assignment was given as a ``.py`` path, ``assignment.py``.
    """
    import rikin

    a = load_assignment(assignment)
    out = Path(out)
    rikin_dir = package_dir("rikin")
    grader_dir = package_dir("rikingrade")
    assert rikin_dir is not None and grader_dir is not None
    is_path = str(assignment).endswith(".py") or Path(str(assignment)).is_file()
    target = '"$ROOT/source/assignment.py"' if is_path else a.name
    opts = [
        f"--seed {int(seed)}",
        f"--cell-timeout {float(cell_timeout):g}",
        f"--memory-mb {int(memory_mb)}",
    ]
    if timeout is not None:
        opts.append(f"--timeout {float(timeout):g}")
    if reveal:
        opts.append("--reveal")
    if unsafe_no_sandbox:
        opts.append("--unsafe-no-sandbox")
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        _add_text(
            z,
            "setup.sh",
            SETUP_SH.format(check_flag="--unsafe-no-sandbox " if unsafe_no_sandbox else ""),
            executable=True,
        )
        _add_text(
            z,
            "run_autograder",
            RUN_AUTOGRADER.format(assignment=target, options=" ".join(opts)),
            executable=True,
        )
        _add_text(
            z,
            "packages/rikin/pyproject.toml",
            PYPROJECT.format(
                name="rikin",
                version=rikin.__version__,
                deps='"numpy>=1.24,<3", "sympy>=1.12,<2", "matplotlib>=3.7,<4"',
            ),
        )
        _add_tree(z, rikin_dir, "packages/rikin/rikin")
        _add_text(
            z,
            "packages/rikingrade/pyproject.toml",
            PYPROJECT.format(
                name="rikingrade",
                version=__version__,
                deps='"rikin", "numpy>=1.24,<3", "ipython>=8,<10"',
            ),
        )
        _add_tree(z, grader_dir, "packages/rikingrade/rikingrade")
        if is_path and a.source_path is not None:
            z.write(a.source_path, "assignment.py")
        _add_text(
            z,
            "README.txt",
            f"rikin-grade {__version__} autograder for {a.exercise} "
            f"({len(a.tests)} tests, max {a.max_score:g} points). Built by "
            "`rikin-grade gradescope-bundle`.\n",
        )
    atomic_write(out, buf.getvalue())
    return out


def gradescope_run(
    assignment: str | Path,
    *,
    submission: str = "/autograder/submission",
    results: str = "/autograder/results/results.json",
    seed: int = DEFAULT_SEED,
    reveal: bool = False,
    timeout: float | None = None,
    cell_timeout: float = 30.0,
    memory_mb: int = 1024,
    unsafe_no_sandbox: bool = False,
) -> SubmissionResult:
    """Grade the notebook in ``submission`` and write Gradescope's ``results.json``."""
    a = load_assignment(assignment)
    sub_dir = Path(submission)
    nb, note = pick_notebook(_notebooks_in(sub_dir) if sub_dir.is_dir() else [], a.notebook)
    results_path = Path(results)
    if nb is None:
        data = _not_graded(
            a,
            f"No .ipynb notebook found in the upload: submit {a.notebook}.",
            "no notebook submitted",
        )
        atomic_write(results_path, json.dumps(data, indent=2))
        return SubmissionResult(
            student="submission",
            path="",
            sha256="",
            status="invalid",
            reason="no notebook",
            max_score=a.max_score,
        )
    work = Path(tempfile.mkdtemp(prefix="rikingrade-gs-"))
    try:
        staged = work / "in" / "submission.ipynb"
        staged.parent.mkdir()
        shutil.copyfile(nb, staged)
        try:
            report = grade(
                a.source_path if a.source_path and str(assignment).endswith(".py") else assignment,
                [staged],
                work / "out",
                workers=1,
                seed=seed,
                reveal=reveal,
                timeout=timeout,
                cell_timeout=cell_timeout,
                memory_mb=memory_mb,
                regrade=True,
                unsafe_no_sandbox=unsafe_no_sandbox,
                progress=False,
                quiet=True,
            )
        except SandboxUnavailable as exc:  # Gradescope must always get a results.json
            print(f"rikin-grade: the sandbox could not start: {exc}")
            data = _not_graded(a, SANDBOX_DOWN, "the autograder could not start")
            atomic_write(results_path, json.dumps(data, indent=2))
            return SubmissionResult(
                student="submission",
                path=str(nb),
                sha256="",
                status=GRADER_ERROR,
                reason=f"the sandbox could not start: {exc}",
                max_score=a.max_score,
            )
        res = report.results[0]
        data = json.loads((work / "out" / "results" / f"{res.student}.json").read_text())
        if note:
            data["output"] = note + "\n\n" + data.get("output", "")
        atomic_write(results_path, json.dumps(data, indent=2))
        if res.status == GRADER_ERROR:
            print((work / "out" / "grading.log").read_text()[-5000:])
        return res
    finally:
        shutil.rmtree(work, ignore_errors=True)


SANDBOX_DOWN = (
    "Your notebook was not graded: the autograder could not start its sandbox on this "
    "platform. This is not a problem with your work; your instructor needs to fix the "
    "autograder and will regrade."
)


def _not_graded(a, output: str, why: str) -> dict:
    """A Gradescope results.json for a submission that could not be graded."""
    return {
        "score": 0.0,
        "output": output,
        "tests": [
            {
                "name": t.name,
                "score": 0.0,
                "max_score": t.weight,
                "status": "failed",
                "output": f"not run: {why}",
            }
            for t in a.tests
        ],
    }
