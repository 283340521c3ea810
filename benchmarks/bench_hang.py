#!/usr/bin/env python3
"""Benchmark: what one hung student function costs the grader (issue 11 item 7).

    .venv/bin/python benchmarks/bench_hang.py              # SCARA, default limits, 2 workers
    .venv/bin/python benchmarks/bench_hang.py --batch 0    # the single notebooks only

Grades, with rikin-grade's default limits (2 s per call), the SCARA solution notebook with
one more cell that makes a function hang (``while True: pass``):

* ``hang_ik``: ``ik_scara`` hangs; six hidden tests reach it, three of them through
  ``ik_scara_6dof`` (which calls ``ik_scara``);
* ``hang_helper``: a helper that no hidden test calls hangs; ``ik_scara`` and
  ``ik_scara_6dof`` both call it (the hang is reached only through other functions);
* ``hang_in_cell``: as ``hang_ik``, and the cell that defines it also calls it (so the
  cell runs while grading);
* ``hang_some``: ``ik_scara`` hangs only on unreachable targets (a search that never
  ends) and answers every other target: it must keep the points of the other tests.

For each it prints the wall-clock seconds of the notebook beside the correct solution's,
the calls that ran to the full per-call limit and those stopped at a shorter one, and the
score. Then a batch of ``--batch`` notebooks (default 30: correct solutions, each with a
unique comment) is graded twice, as is and with one of them replaced by ``hang_ik``: the
difference is what the hung notebook costs the class. The load average is printed beside
the figures (the machine may be shared).
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import sys
import tempfile
import time
from pathlib import Path

from bench_grade import code_cell  # this folder is on sys.path when run as a script

ROOT = Path(__file__).resolve().parent.parent

HANGS = {
    "hang_ik": "def ik_scara(p, l1, l2, l3):\n    while True:\n        pass\n",
    "hang_helper": (
        "import numpy as np\n"
        "def _positioning(x, y, z, l1, l2, l3):\n    while True:\n        pass\n"
        "def ik_scara(p, l1, l2, l3):\n    return _positioning(*np.asarray(p), l1, l2, l3)\n"
        "def ik_scara_6dof(T, l1, l2, l3, tool):\n"
        "    T = np.asarray(T, dtype=float)\n"
        "    p_w = T[:3, 3] - tool * T[:3, 2]\n"
        "    return _positioning(*p_w, l1, l2, l3)\n"
    ),
    "hang_in_cell": (
        "def ik_scara(p, l1, l2, l3):\n    while True:\n        pass\n"
        "print(ik_scara([1.0, 0.5, 0.2], 1.0, 1.0, 0.8))  # a cell that defines and tries it\n"
    ),
    "hang_some": (
        "_good_ik = ik_scara\n"
        "def ik_scara(p, l1, l2, l3):\n"
        "    try:\n        return _good_ik(p, l1, l2, l3)\n"
        "    except ValueError:\n"
        "        while True:  # 'search harder' for a solution that does not exist\n"
        "            pass\n"
    ),
}


def notebook(solution: dict, extra: str, i: int = 0) -> dict:
    nb = copy.deepcopy(solution)
    nb["cells"].append(code_cell(f"# student {i:04d}"))
    if extra:
        nb["cells"].append(code_cell(extra))
    return nb


def timeouts(result) -> tuple[int, int]:
    """(calls stopped at the full per-call limit, calls stopped at a shorter limit)."""
    full = short = 0
    for t in result.tests:
        if t.timed_out:
            full += t.feedback.count("no result within")
            short += t.feedback.count("short limit")
    return full, short


def grade_folder(folder: Path, out: Path, workers: int):
    from rikingrade import grade

    t0 = time.perf_counter()
    report = grade(
        "scara", [folder], out, workers=workers, regrade=True, quiet=True, progress=False
    )
    return report, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--batch", type=int, default=30, help="notebooks in the batch (0: none)")
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args(argv)
    solution = json.loads((ROOT / "solutions" / "scara.ipynb").read_text())
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        single = tmp / "single"
        single.mkdir()
        (single / "correct.ipynb").write_text(json.dumps(notebook(solution, "")))
        for name, src in HANGS.items():
            (single / f"{name}.ipynb").write_text(json.dumps(notebook(solution, src)))
        report, _ = grade_folder(single, tmp / "out1", 1)
        print(f"{'notebook':<12} {'seconds':>8} {'full-limit':>10} {'short':>6} {'score':>6}")
        for r in sorted(report.results, key=lambda r: r.student):
            full, short = timeouts(r)
            print(f"{r.student:<12} {r.elapsed:8.2f} {full:10d} {short:6d} {r.score:6.2f}")
        if args.batch:
            batch = {}
            for label, hung in (("without", False), ("with one hung", True)):
                folder = tmp / f"batch-{int(hung)}"
                folder.mkdir()
                for i in range(args.batch):
                    extra = HANGS["hang_ik"] if hung and i == 0 else ""
                    (folder / f"s{i:03d}.ipynb").write_text(
                        json.dumps(notebook(solution, extra, i))
                    )
                _, dt = grade_folder(folder, tmp / f"out-b{int(hung)}", args.workers)
                batch[label] = dt
            for label, dt in batch.items():
                print(
                    f"batch of {args.batch}, {label}: {dt:.1f} s "
                    f"({args.batch / dt * 60:.0f} notebooks/min, {args.workers} workers)"
                )
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
