#!/usr/bin/env python3
"""Benchmark: grade the same generated class with rikin-grade and (if installed) nbgrader.

    python benchmarks/bench_grade.py                 # SCARA exercise, 200 submissions, 2 workers
    python benchmarks/bench_grade.py --assignment cartesian --n 40 --nbgrader-n 40
    python benchmarks/bench_grade.py --assignment tests/grader_fixtures/fake2r.py \
        --solution tests/grader_fixtures/fake2r_solution.ipynb   # the engine's tiny test exercise

Submissions are made from a solution notebook: mostly correct (each with a unique comment
cell, so every file hash differs), some wrong (a required function redefined to return
None) and a few hostile (an endless loop, a fork bomb, a memory bomb, os._exit, a numpy
monkeypatch with wrong answers, reading the course's files). rikin-grade grades them all
with its default limits and timeouts, from scratch (no resume), sandbox start-up included.

nbgrader autograde (found as ``--nbgrader``, $NBGRADER or ``nbgrader`` on PATH) runs on
the correct and wrong submissions only: it executes notebooks without any sandbox or
resource limit, so the hostile ones would run fork and memory bombs on this machine. Its
rate (notebooks/min) is compared with rikin-grade's on the whole set. Without nbgrader the
script says so and prints our figures.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FAKE_ASSIGNMENT = ROOT / "tests" / "grader_fixtures" / "fake2r.py"
FAKE_SOLUTION = ROOT / "tests" / "grader_fixtures" / "fake2r_solution.ipynb"

HOSTILE = {
    "endless_loop": "def {f}(*args, **kwargs):\n    while True:\n        pass",
    "fork_bomb": "import os\nwhile True:\n    os.fork()",
    "memory_bomb": "junk = bytearray(64 * 2**30)",
    "os_exit": "import os\nos._exit(0)",
    "monkeypatch": "import numpy as np\nnp.allclose = lambda *a, **k: True\nnp.isclose = lambda *a, **k: True\n"  # noqa: E501
    "def {f}(*args, **kwargs):\n    return None",
    "read_files": "import os\nfor p in ['/work/main/grader', '/work/main/solutions', '/etc/shadow', '..', '../..']:\n"  # noqa: E501
    "    try:\n        print(os.listdir(p) if os.path.isdir(p) else open(p).read())\n"
    "    except OSError:\n        pass",
}
# Variants that keep every required function correct (so full marks are right).
HOSTILE_FULL_MARKS = {"fork_bomb", "memory_bomb", "os_exit", "read_files"}


def code_cell(src: str) -> dict:
    return {
        "cell_type": "code",
        "execution_count": None,
        "metadata": {},
        "outputs": [],
        "source": src,
    }


def make_class(
    solution: dict, functions: list[str], n: int, wrong_every: int = 8, hostile_every: int = 33
) -> list[tuple[str, str, dict]]:
    """(student id, kind, notebook) for ``n`` students: mostly correct, some wrong, a few
    hostile (none if ``hostile_every`` is 0). Each student's cells that define the answer
    functions differ (a comment line of their own), as in a real class; the exercise's
    setup and check cells are the same in every notebook."""
    out = []
    hostile_kinds = list(HOSTILE)
    h = w = 0
    for i in range(n):
        nb = copy.deepcopy(solution)
        for c in nb["cells"]:
            src = "".join(c["source"])
            if c["cell_type"] == "code" and any(f"def {f}(" in src for f in functions):
                c["source"] = f"# student {i:04d}'s answer\n" + src
        nb["cells"].append(code_cell(f"# student {i:04d}: my answers are above"))
        if hostile_every and i % hostile_every == hostile_every - 1:
            kind = hostile_kinds[h % len(hostile_kinds)]
            h += 1
            nb["cells"].append(code_cell(HOSTILE[kind].format(f=functions[h % len(functions)])))
            out.append((f"s{i:04d}_{kind}", kind, nb))
        elif i % wrong_every == wrong_every - 1:
            f = functions[w % len(functions)]
            w += 1
            nb["cells"].append(code_cell(f"def {f}(*args, **kwargs):\n    return None"))
            out.append((f"s{i:04d}_wrong", "wrong", nb))
        else:
            out.append((f"s{i:04d}_ok", "correct", nb))
    return out


def _cpu() -> float:
    """CPU seconds of this process and of the children it has waited for (the sandboxes:
    every process in one is a descendant its bubblewrap waits for)."""
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def find_nbgrader(explicit: str | None) -> str | None:
    for cand in (
        explicit,
        os.environ.get("NBGRADER"),
        shutil.which("nbgrader"),
    ):
        if cand and Path(cand).exists():
            return cand
    return None


def bench_rikin(assignment: str, folder: Path, workers: int) -> dict:
    from rikingrade import grade

    out = folder.parent / "rikin_out"
    t0 = time.perf_counter()
    cpu0 = _cpu()
    report = grade(
        assignment, [folder], out, workers=workers, regrade=True, quiet=True, progress=False
    )
    dt = time.perf_counter() - t0
    return {
        "seconds": dt,
        "cpu_seconds": _cpu() - cpu0,
        "n": len(report.results),
        "per_min": len(report.results) / dt * 60,
        "results": {r.student: (r.score, r.max_score, r.status) for r in report.results},
    }


def bench_nbgrader(
    nbgrader: str,
    solution: dict,
    notebook: str,
    class_: list[tuple[str, str, dict]],
    work: Path,
    timeout: int,
) -> dict:
    """Time ``nbgrader autograde`` on ``class_`` (a course folder is built in ``work``)."""
    course = work / "nbgrader_course"
    (course / "source" / "ps1").mkdir(parents=True)
    (course / "nbgrader_config.py").write_text(
        "c = get_config()\n"
        f"c.CourseDirectory.root = {str(course)!r}\n"
        "c.CourseDirectory.course_id = 'bench'\n"
        f"c.ExecutePreprocessor.timeout = {int(timeout)}\n"
        "# our solutions may carry their own solution markers: nbgrader must leave them alone\n"
        "c.ClearSolutions.begin_solution_delimeter = 'RIKIN BENCH NO SOLUTION BEGIN'\n"
        "c.ClearSolutions.end_solution_delimeter = 'RIKIN BENCH NO SOLUTION END'\n"
        "c.ClearSolutions.enforce_metadata = False\n"
    )
    src = copy.deepcopy(solution)
    # One grade cell: the notebook's last code cell that checks something (its visible
    # checks), else its last code cell.
    code = [c for c in src["cells"] if c["cell_type"] == "code"]
    checks = [c for c in code if any(w in "".join(c["source"]) for w in ("assert", "check"))]
    target = (checks or code)[-1]
    target["metadata"]["nbgrader"] = {
        "grade": True,
        "grade_id": "checks",
        "locked": True,
        "points": 5,
        "schema_version": 3,
        "solution": False,
        "task": False,
    }
    (course / "source" / "ps1" / notebook).write_text(json.dumps(src))
    # nbgrader runs helpers (alembic) from its own environment's bin folder
    path = os.pathsep.join([str(Path(nbgrader).parent), os.environ.get("PATH", "")])
    env = dict(os.environ, MPLBACKEND="Agg", PATH=path)
    gen = subprocess.run(
        [nbgrader, "generate_assignment", "ps1", "--force"],
        cwd=course,
        capture_output=True,
        text=True,
        env=env,
    )
    if gen.returncode != 0:
        raise RuntimeError(f"nbgrader generate_assignment failed:\n{gen.stdout}\n{gen.stderr}")
    release = json.loads((course / "release" / "ps1" / notebook).read_text())
    for student, _kind, nb in class_:
        rel = copy.deepcopy(release)
        rel["cells"] += nb["cells"][len(solution["cells"]) :]  # the same additions as ours
        d = course / "submitted" / student / "ps1"
        d.mkdir(parents=True)
        (d / notebook).write_text(json.dumps(rel))
    t0 = time.perf_counter()
    proc = subprocess.run(
        [nbgrader, "autograde", "ps1", "--force"],
        cwd=course,
        capture_output=True,
        text=True,
        env=env,
    )
    dt = time.perf_counter() - t0
    graded = sum(1 for _ in (course / "autograded").glob(f"*/ps1/{notebook}"))
    return {
        "seconds": dt,
        "n": len(class_),
        "graded": graded,
        "per_min": len(class_) / dt * 60,
        "returncode": proc.returncode,
        "log_tail": proc.stderr[-1500:],
    }


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--n", type=int, default=200, help="submissions to generate (default 200)")
    p.add_argument("--workers", type=int, default=2, help="rikin-grade workers (default 2)")
    p.add_argument(
        "--assignment",
        default="scara",
        help="exercise name (cartesian, cylindrical, spherical, scara) or hidden-test .py "
        "(default: scara)",
    )
    p.add_argument("--solution", default=None, help="solution notebook the class is made from")
    p.add_argument("--nbgrader", default=None, help="path of the nbgrader executable")
    p.add_argument(
        "--nbgrader-n",
        type=int,
        default=40,
        help="correct/wrong submissions given to nbgrader (default 40; 0 skips it)",
    )
    p.add_argument("--nbgrader-timeout", type=int, default=30, help="nbgrader's cell timeout, s")
    p.add_argument(
        "--hostile-every",
        type=int,
        default=33,
        help="one hostile submission in this many (default 33; 0: none, only correct and "
        "wrong ones, to compare graders on a loaded machine where a hang's cost varies)",
    )
    p.add_argument("--json", action="store_true", help="print the figures as JSON too")
    p.add_argument("--keep", action="store_true", help="keep the generated folder")
    return p


def _solution_path(args: argparse.Namespace, notebook: str) -> Path:
    """The solution notebook the class is made from (``--solution``, or the assignment's)."""
    if args.solution:
        return Path(args.solution)
    if Path(args.assignment).resolve() == FAKE_ASSIGNMENT:
        return FAKE_SOLUTION
    return ROOT / "solutions" / notebook


def _write_class(class_: list, folder: Path) -> dict[str, int]:
    """Each submission of ``class_`` as ``<student>.ipynb`` in ``folder``; count per kind."""
    folder.mkdir()
    for student, _kind, nb in class_:
        (folder / f"{student}.ipynb").write_text(json.dumps(nb))
    return {k: sum(1 for _, kk, _ in class_ if kk == k) for k in {k for _, k, _ in class_}}


def _report_rikin(ours: dict, class_: list, workers: int) -> dict:
    """Print rikin-grade's rate and correctness; its figures (with the misgraded students)."""
    res = ours["results"]
    full = [s for s, k, _ in class_ if k == "correct" or k in HOSTILE_FULL_MARKS]
    not_full = [s for s, k, _ in class_ if s not in full]
    missed = [s for s in full if res[s][0] != res[s][1]]
    false_pass = [s for s in not_full if res[s][0] >= res[s][1]]
    print(
        f"rikin-grade: {ours['n']} notebooks in {ours['seconds']:.1f} s = {ours['per_min']:.0f} "
        f"notebooks/min ({workers} workers, sandbox start included; "
        f"1-minute load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs); "
        f"{ours['cpu_seconds']:.1f} s of CPU"
    )
    print(
        f"  correct notebooks with full marks: {len(full) - len(missed)}/{len(full)}; "
        f"false passes among wrong/hostile: {len(false_pass)}/{len(not_full)}"
    )
    return {
        "n": ours["n"],
        "workers": workers,
        "seconds": round(ours["seconds"], 3),
        "notebooks_per_min": round(ours["per_min"], 1),
        "cpu_seconds": round(ours["cpu_seconds"], 2),
        "missed_full_marks": missed,
        "false_passes": false_pass,
    }


def _compare_nbgrader(args: argparse.Namespace, ours: dict, class_: list, solution: dict,
                      notebook: str, work: Path) -> dict:
    """Grade the correct and wrong submissions with nbgrader when it is there; print the
    ratio of the rates; the figures to add (none when nbgrader is skipped or missing)."""
    nbg = find_nbgrader(args.nbgrader) if args.nbgrader_n > 0 else None
    if args.nbgrader_n <= 0:
        print("nbgrader: skipped (--nbgrader-n 0)")
        return {}
    if nbg is None:
        print(
            "nbgrader: not installed (pip install nbgrader, or set NBGRADER=/path/to/nbgrader); "
            "no ratio"
        )
        return {}
    subset = [c for c in class_ if c[1] in ("correct", "wrong")][: args.nbgrader_n]
    theirs = bench_nbgrader(nbg, solution, notebook, subset, work, args.nbgrader_timeout)
    print(
        f"nbgrader autograde: {theirs['n']} notebooks in {theirs['seconds']:.1f} s = "
        f"{theirs['per_min']:.1f} notebooks/min (serial; {theirs['graded']} graded; hostile "
        "notebooks excluded: no sandbox)"
    )
    if theirs["returncode"] != 0:
        print(f"  nbgrader exited with {theirs['returncode']}:\n{theirs['log_tail']}")
    ratio = ours["per_min"] / theirs["per_min"] if theirs["per_min"] else float("inf")
    print(f"ratio: rikin-grade is {ratio:.1f}x nbgrader autograde (notebooks/min)")
    return {
        "nbgrader_n": theirs["n"],
        "nbgrader_seconds": round(theirs["seconds"], 3),
        "nbgrader_per_min": round(theirs["per_min"], 2),
        "ratio": round(ratio, 1),
    }


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)

    from rikingrade.assignment import load_assignment

    a = load_assignment(args.assignment)
    solution_path = _solution_path(args, a.notebook)
    solution = json.loads(solution_path.read_text())
    class_ = make_class(solution, list(a.functions), args.n, hostile_every=args.hostile_every)
    work = Path(tempfile.mkdtemp(prefix="bench-grade-"))
    try:
        kinds = _write_class(class_, work / "class")
        print(f"class: {args.n} submissions of {a.exercise} from {solution_path.name}: {kinds}")
        ours = bench_rikin(args.assignment, work / "class", args.workers)
        figures = _report_rikin(ours, class_, args.workers)
        figures.update(_compare_nbgrader(args, ours, class_, solution, a.notebook, work))
        if args.json:
            print(json.dumps(figures))
        return 0 if not figures["missed_full_marks"] and not figures["false_passes"] else 1
    finally:
        if args.keep:
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
