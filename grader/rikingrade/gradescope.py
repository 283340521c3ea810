"""Gradescope: build the autograder bundle, and grade the one submission inside it.

Gradescope unzips the bundle into ``/autograder/source``, runs ``setup.sh`` once when the
image is built, then for each submission copies ``run_autograder`` to
``/autograder/run_autograder``, runs it with the upload in ``/autograder/submission`` and
``/autograder/submission_metadata.json`` beside it (when it was handed in, the due date, the
student's own due date after an extension), and reads ``/autograder/results/results.json``.
``AUTOGRADER_ROOT`` (default ``/autograder``) and ``RIKIN_GRADE_PYTHON`` override those
locations, which is how the tests run a bundle locally.

``setup.sh`` uses the image's own ``python3`` (3.10 or newer: Ubuntu 22.04 or newer, the
plain variant of the base image) and refuses an older one with that advice.
"""

from __future__ import annotations

import io
import json
import os
import re
import shutil
import stat
import tempfile
import zipfile
from pathlib import Path

from ._version import __version__
from .api import DEFAULT_SEED, grade_upload
from .assignment import load_assignment
from .notebook import MAX_NOTEBOOK_BYTES, _notebooks_in, _too_large, pick_notebook
from .outputs import atomic_write
from .policy import Rules, apply
from .report import GRADER_ERROR, SubmissionResult
from .sandbox.config import SandboxUnavailable, package_dir
from .studentfiles import TOO_LARGE, ReadFailed, read_in_process

SETUP_SH = """#!/usr/bin/env bash
# Gradescope runs this once while building the autograder image (Ubuntu, as root).
# Student code then runs in the strongest sandbox the container allows: bubblewrap
# namespaces, or, where user namespaces are refused (Docker's default seccomp profile),
# its own unprivileged uid. For that uid mode the grader is installed root-only:
#   $VENV       every user can read it: the Python student code runs with (rikin, numpy, ...)
#   $GRADER     root only: rikingrade with the hidden tests and the reference
#   this folder root only: the bundle itself
set -euo pipefail
cd "$(dirname "$0")"
SOURCE="$(pwd)"
VENV="${{RIKIN_GRADE_VENV:-/opt/rikin-venv}}"
GRADER="${{RIKIN_GRADE_HOME:-/opt/rikingrade}}"
export DEBIAN_FRONTEND=noninteractive
# apt-get update fails at once while another apt holds the package lists (apt 2.6 does not
# honour DPkg::Lock::Timeout for update, only for install): wait for it, up to 10 minutes.
APT_ERR="$(mktemp)"
for attempt in $(seq 120); do
    if apt-get update 2>"$APT_ERR"; then break; fi
    cat "$APT_ERR" >&2
    if [ "$attempt" = 120 ] || ! grep -q "Could not get lock\\|Unable to lock" \\
            "$APT_ERR"; then
        exit 1
    fi
    sleep 5
done
rm -f "$APT_ERR"
apt-get install -y -o DPkg::Lock::Timeout=600 --no-install-recommends \\
    bubblewrap python3 python3-venv
umask 022
# The system Python: the sandbox's uid must be able to run it (not one under /root).
if ! /usr/bin/python3 -c 'import sys; sys.exit(sys.version_info < (3, 10))'; then
    echo "ERROR: rikin needs Python 3.10 or newer; this image's python3 is" \
        "$(/usr/bin/python3 -V 2>&1). On Gradescope's Configure Autograder page choose the" \
        "base image Ubuntu 22.04 (Python 3.10) or newer, the plain variant." >&2
    exit 1
fi
/usr/bin/python3 -m venv --clear "$VENV"
"$VENV/bin/pip" install --disable-pip-version-check --progress-bar off \\
    ./packages/rikin "ipython>=8,<10"
rm -rf "$GRADER"
mkdir -p -m 0700 "$GRADER"
"$VENV/bin/pip" install --disable-pip-version-check --progress-bar off --no-deps \\
    --target "$GRADER/lib" ./packages/rikingrade
chmod -R go-rwx "$GRADER" "$SOURCE"
export PYTHONPATH="$GRADER/lib"
# Fail the image build (Gradescope shows this log on the Configure Autograder page) rather
# than every student's submission later, if student code cannot be isolated here.
if ! "$VENV/bin/python" -m rikingrade.cli check-sandbox "$SOURCE" "$GRADER"; then
{on_failure}
fi
"""

SETUP_FAIL = """\
    echo "ERROR: no sandbox can isolate student code in this container (see above)." >&2
    exit 1"""

SETUP_FAIL_UNSAFE = """\
    echo "WARNING: no sandbox can isolate student code here; this bundle was built with" >&2
    echo "--unsafe-no-sandbox, so student code runs as root beside the grader and could" >&2
    echo "read the hidden tests and the reference solutions." >&2"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Gradescope runs this for every submission. Paths can be overridden to test locally.
set -uo pipefail
ROOT="${{AUTOGRADER_ROOT:-/autograder}}"
PY="${{RIKIN_GRADE_PYTHON:-${{RIKIN_GRADE_VENV:-/opt/rikin-venv}}/bin/python}}"
GRADER="${{RIKIN_GRADE_HOME:-/opt/rikingrade}}"
mkdir -p "$ROOT/results"
# Nothing of the grader, the upload or the results may be readable by the sandbox's uid.
chmod 0700 "$ROOT/results" "$ROOT/source" "$ROOT/submission" 2>/dev/null || true
export PYTHONPATH="$GRADER/lib${{PYTHONPATH:+:$PYTHONPATH}}"
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


def _add_tree(z: zipfile.ZipFile, src: Path, arc: str, skip=lambda rel: False) -> None:
    for p in sorted(src.rglob("*")):
        if "__pycache__" in p.parts or p.suffix in (".pyc", ".pyo") or not p.is_file():
            continue
        rel = p.relative_to(src).as_posix()
        if not skip(rel):
            z.write(p, f"{arc}/{rel}")


def _add_text(z: zipfile.ZipFile, arc: str, text: str, executable: bool = False) -> None:
    info = zipfile.ZipInfo(arc, date_time=(2024, 1, 1, 0, 0, 0))
    info.external_attr = ((0o755 if executable else 0o644) | stat.S_IFREG) << 16
    info.compress_type = zipfile.ZIP_DEFLATED
    z.writestr(info, text)


HIDDEN_INIT = '''"""Hidden tests of the one exercise this Gradescope bundle grades."""

EXERCISES = {exercises!r}
'''

REFERENCE_INIT = '''"""Reference of the one exercise this bundle grades (instructor side only)."""

from __future__ import annotations

{imports}from ._common import ExerciseArm, Solutions

ARMS: dict[str, ExerciseArm] = {{{arms}}}

__all__ = ["ARMS", "ExerciseArm", "Solutions"{names}]
'''


def _exercise_of(a) -> str | None:
    """The built-in exercise an assignment is (``scara``), or None for a custom module."""
    from .hidden import EXERCISES

    parts = a.module.__name__.split(".")
    if parts[:2] == ["rikingrade", "hidden"] and len(parts) == 3 and parts[2] in EXERCISES:
        return parts[2]
    return None


def _skip_other_exercises(keep: str | None):
    """Leave out every built-in exercise's hidden tests and reference but ``keep``'s."""
    from .hidden import EXERCISES

    others = {e for e in EXERCISES if e != keep}
    generated = {"hidden/__init__.py", "reference/__init__.py"}

    def skip(rel: str) -> bool:
        if rel in generated:
            return True
        folder, _, name = rel.partition("/")
        return folder in ("hidden", "reference") and name.removesuffix(".py") in others

    return skip


def gradescope_bundle(
    assignment: str | Path,
    out: str | Path = "bundle.zip",
    *,
    seed: int = DEFAULT_SEED,
    reveal: bool = False,
    timeout: float | None = None,
    cell_timeout: float = 30.0,
    memory_mb: int = 1024,
    late_per_day: float = 0.0,
    late_cap: float = 100.0,
    grace_minutes: float = 0.0,
    unsafe_no_sandbox: bool = False,
) -> Path:
    """Write the Gradescope autograder zip for ``assignment``; returns its path.

    The zip holds ``setup.sh``, ``run_autograder``, ``packages/rikin`` and
    ``packages/rikingrade`` with the hidden tests and the reference of this assignment only
    (none of the other exercises'), and, when the assignment was given as a ``.py`` path,
    ``assignment.py``. ``setup.sh`` installs the grader root-only and checks that a sandbox
    works (bubblewrap, or the uid mode where the container refuses user namespaces).
    ``late_per_day`` (with ``late_cap``, ``grace_minutes``) takes a late penalty by
    Gradescope's own times (``submission_metadata.json``: the hand-in time against the
    student's due date, extensions included).
    """
    a = load_assignment(assignment)
    out = Path(out)
    is_path = str(assignment).endswith(".py") or Path(str(assignment)).is_file()
    exercise = None if is_path else _exercise_of(a)
    opts = _run_options(
        seed=seed,
        reveal=reveal,
        timeout=timeout,
        cell_timeout=cell_timeout,
        memory_mb=memory_mb,
        late_per_day=late_per_day,
        late_cap=late_cap,
        grace_minutes=grace_minutes,
        unsafe_no_sandbox=unsafe_no_sandbox,
    )
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        _add_text(
            z,
            "setup.sh",
            SETUP_SH.format(on_failure=SETUP_FAIL_UNSAFE if unsafe_no_sandbox else SETUP_FAIL),
            executable=True,
        )
        target = '"$ROOT/source/assignment.py"' if is_path else a.name
        _add_text(
            z,
            "run_autograder",
            RUN_AUTOGRADER.format(assignment=target, options=" ".join(opts)),
            executable=True,
        )
        _add_packages(z, exercise)
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


def _run_options(
    *,
    seed: int,
    reveal: bool,
    timeout: float | None,
    cell_timeout: float,
    memory_mb: int,
    late_per_day: float,
    late_cap: float,
    grace_minutes: float,
    unsafe_no_sandbox: bool,
) -> list[str]:
    """The options ``run_autograder`` passes to ``rikin-grade gradescope-run``."""
    opts = [
        f"--seed {int(seed)}",
        f"--cell-timeout {float(cell_timeout):g}",
        f"--memory-mb {int(memory_mb)}",
    ]
    if timeout is not None:
        opts.append(f"--timeout {float(timeout):g}")
    if reveal:
        opts.append("--reveal")
    if late_per_day:
        opts += [
            f"--late-per-day {float(late_per_day):g}",
            f"--late-cap {float(late_cap):g}",
            f"--grace-minutes {float(grace_minutes):g}",
        ]
    if unsafe_no_sandbox:
        opts.append("--unsafe-no-sandbox")
    return opts


def _add_packages(z: zipfile.ZipFile, exercise: str | None) -> None:
    """``packages/rikin`` and ``packages/rikingrade`` (only ``exercise``'s hidden tests and
    reference, none for a custom assignment), each with a pyproject.toml to install it."""
    import rikin

    rikin_dir = package_dir("rikin")
    grader_dir = package_dir("rikingrade")
    assert rikin_dir is not None and grader_dir is not None
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
    kept = [exercise] if exercise else []
    pkg = "packages/rikingrade/rikingrade"
    _add_tree(z, grader_dir, pkg, _skip_other_exercises(exercise))
    _add_text(z, f"{pkg}/hidden/__init__.py", HIDDEN_INIT.format(exercises=tuple(kept)))
    _add_text(
        z,
        f"{pkg}/reference/__init__.py",
        REFERENCE_INIT.format(
            imports="".join(f"from . import {e}\n" for e in kept),
            arms=", ".join(f"{e}.ARM.name: {e}.ARM" for e in kept),
            names="".join(f', "{e}"' for e in kept),
        ),
    )


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
    late_per_day: float = 0.0,
    late_cap: float = 100.0,
    grace_minutes: float = 0.0,
    sandbox: str = "auto",
    unsafe_no_sandbox: bool = False,
) -> SubmissionResult:
    """Grade the notebook in ``submission`` and write Gradescope's ``results.json``.

    The other files of the upload, below the notebook's folder (sub-folders kept), are in
    the cells' working folder as in Jupyter, read as a student folder's files are
    (:func:`rikingrade.api.grade_upload`); a file not given is named in the output, why.

    A submission that could not be graded (no sandbox could start, or a hidden test failed
    inside the grader) gets no ``results.json``: Gradescope then shows an autograder
    failure with no score, for the instructor to fix and rerun, instead of a 0. The reason
    is printed (Gradescope keeps it in the autograder output). A missing notebook is the
    student's to fix: it gets a results.json with 0 that says what to submit.

    Lateness comes from Gradescope's ``submission_metadata.json`` beside the submission
    folder: ``created_at`` against the student's due date (``users[].assignment.due_date``,
    an extension, else ``assignment.due_date``); with ``late_per_day`` the score is reduced
    as :func:`rikingrade.policy.apply` says, and the output says why.
    """
    a = load_assignment(assignment)
    sub_dir = Path(submission)
    results_path = Path(results)
    upload = _read_upload(a, sub_dir, results_path)
    if isinstance(upload, SubmissionResult):
        return upload
    nb, note, data = upload
    work = Path(tempfile.mkdtemp(prefix="rikingrade-gs-"))  # 0700: unreadable to the sandbox
    try:
        staged = _stage(work, data)
        try:
            report = grade_upload(  # with the files handed in beside the notebook
                a.source_path if a.source_path and str(assignment).endswith(".py") else assignment,
                staged,
                nb,
                work / "out",
                workers=1,
                seed=seed,
                reveal=reveal,
                timeout=timeout,
                cell_timeout=cell_timeout,
                memory_mb=memory_mb,
                regrade=True,
                sandbox=sandbox,
                unsafe_no_sandbox=unsafe_no_sandbox,
                progress=False,
                quiet=True,
            )
        except SandboxUnavailable as exc:
            _not_graded(results_path, f"the sandbox could not start:\n{exc}")
            return _unread(a, nb, GRADER_ERROR, f"the sandbox could not start: {exc}")
        rules = Rules(None, late_per_day, late_cap, grace_minutes)
        return _write_results(report.results[0], work / "out", results_path, note, sub_dir, rules)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _unread(a, nb: Path | None, status: str, why: str, refused: str = "") -> SubmissionResult:
    """The result of an upload that was not graded (no notebook, unreadable, no sandbox)."""
    return SubmissionResult(
        student="submission",
        path="" if nb is None else str(nb),
        sha256="",
        status=status,
        reason=why,
        max_score=a.max_score,
        refused=refused,
    )


def _read_upload(
    a, sub_dir: Path, results_path: Path
) -> tuple[Path, str, bytes] | SubmissionResult:
    """(the notebook, the note on how it was picked, its bytes) from the upload; when there
    is none to grade, results.json says so (0 points) and its result is returned instead."""
    nb, note = pick_notebook(_notebooks_in(sub_dir) if sub_dir.is_dir() else [], a.notebook)
    if nb is None:
        atomic_write(results_path, json.dumps(_no_notebook(a), indent=2))
        return _unread(a, None, "invalid", "no notebook")
    try:  # the upload is Gradescope's (read as root), but a link in it is not followed
        data = read_in_process(nb, MAX_NOTEBOOK_BYTES)
    except ReadFailed as exc:
        large = exc.kind == TOO_LARGE
        why = _too_large(exc.size) if large else f"not read: {exc.why}"
        atomic_write(results_path, json.dumps(_no_notebook(a, f"The upload: {why}.")))
        return _unread(a, nb, "invalid", why, refused="" if large else exc.why)
    return nb, note, data


def _stage(work: Path, data: bytes) -> Path:
    """The upload's notebook copied inside ``work``, readable by the grader's unprivileged
    file reader (the files beside it are read from the upload itself, when it runs)."""
    staged = work / "in" / "submission.ipynb"
    staged.parent.mkdir()
    os.chmod(staged.parent, 0o755)
    staged.write_bytes(data)
    os.chmod(staged, 0o644)
    return staged


def _write_results(
    res: SubmissionResult, out: Path, results_path: Path, note: str, sub_dir: Path, rules: Rules
) -> SubmissionResult:
    """Gradescope's results.json from the grader's own results of the one submission, with
    the late rules applied; none (an autograder failure) when the grader failed."""
    log_text = (out / "grading.log").read_text(errors="replace")
    mode = re.search(r"sandbox: (\w+)", log_text)
    print(f"rikin-grade: student code ran in the {mode.group(1) if mode else '?'} sandbox")
    if res.status == GRADER_ERROR:
        _not_graded(results_path, f"{res.reason}\n\n{log_text[-5000:]}")
        return res
    data = json.loads((out / "results" / f"{res.student}.json").read_text())
    data.get("extra_data", {}).pop("rikin", None)  # the local gradebook's record
    if note:
        data["output"] = note + "\n\n" + data.get("output", "")
    _late(data, res, sub_dir, rules)
    atomic_write(results_path, json.dumps(data, indent=2))
    return res


def submission_times(metadata: dict) -> tuple[float | None, float | None]:
    """(handed in, due) from Gradescope's ``submission_metadata.json``: the student's own due
    date when an extension gave one, else the assignment's."""
    from .policy import PolicyError, parse_time

    def when(text) -> float | None:
        try:
            return parse_time(text) if text else None
        except PolicyError:
            return None

    users = metadata.get("users") or [{}]
    own = (users[0] or {}).get("assignment") or {}
    due = own.get("due_date") or (metadata.get("assignment") or {}).get("due_date")
    return when(metadata.get("created_at")), when(due)


def _late(data: dict, res: SubmissionResult, sub_dir: Path, rules: Rules) -> None:
    """Apply the late rules to results.json by Gradescope's own times (when it says them)."""
    path = sub_dir.parent / "submission_metadata.json"
    try:
        meta = json.loads(read_in_process(path, 1 << 20))
    except (ReadFailed, ValueError):
        return
    if not isinstance(meta, dict):
        return
    handed, due = submission_times(meta)
    if due is None or handed is None:
        return
    g = apply(
        res.score,
        res.max_score,
        handed,
        "Gradescope's submission time",
        Rules(due, rules.per_day, rules.cap, rules.grace_minutes),
    )
    if g.notes:
        data["score"] = round(g.final, 6)
        data["output"] = "\n".join(g.notes) + "\n\n" + data.get("output", "")


def _not_graded(results_path: Path, why: str) -> None:
    """Leave no results.json (Gradescope: "autograder failed", no score) and say why."""
    results_path.unlink(missing_ok=True)
    print(
        "rikin-grade: NOT GRADED. No results.json was written, so Gradescope records an "
        "autograder failure with no score (not a 0): fix the autograder and rerun it on "
        f"this submission. Reason: {why}"
    )


def _no_notebook(a, why: str = "") -> dict:
    """A Gradescope results.json for an upload without a notebook (the student's to fix)."""
    return {
        "score": 0.0,
        "output": why or f"No .ipynb notebook found in the upload: submit {a.notebook}.",
        "tests": [
            {
                "name": t.name,
                "score": 0.0,
                "max_score": t.weight,
                "status": "failed",
                "output": "not run: no notebook submitted",
            }
            for t in a.tests
        ],
    }
