"""The before/after table of the fairness classes, measured with the real (sandboxed) grader.

    python tests/fairness_table.py [--before COMMIT] [--arms scara,...]

Writes every variant of fairness_variants.py as a notebook, grades them with this
checkout's grader and with the grader of ``COMMIT`` (extracted with ``git archive``,
run with its own rikin and rikingrade first on ``PYTHONPATH``), runs the visible checks
of both versions in-process, and prints per class: how many variants got a score other
than their reasoned one (too low: a correct answer lost points; too high: a wrong one got
too much), and how many had visible checks that disagree with the hidden tests.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import re
import subprocess
import sys
import tarfile
import tempfile
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

import _hidden_harness as H  # noqa: E402
import fairness_variants as F  # noqa: E402
import nbformat  # noqa: E402
import wrong_variants as W  # noqa: E402
from test_fairness import _visible_failures  # noqa: E402

GRADE = (
    "import json, sys\n"
    "from rikingrade import grade\n"
    "r = grade(sys.argv[1], [sys.argv[2]], sys.argv[3], workers=2, progress=False, quiet=True)\n"
    "print(json.dumps({x.student: [x.score, x.status] for x in r.results}))\n"
)


def _notebook(f: F.Fair, solution):
    nb = W.apply(solution, f.variant())
    if f.cell:
        nb.cells.append(nbformat.v4.new_code_cell(f.cell))
    return nb


def _grade(arm: str, folder: Path, out: Path, pythonpath: str | None) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    res = subprocess.run([sys.executable, "-c", GRADE, arm, str(folder), str(out)], env=env,
                         capture_output=True, text=True, check=False)
    if res.returncode not in (0, 1):
        raise SystemExit(f"grading {arm} failed:\n{res.stderr[-3000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def _old_checks(commit: str) -> str:
    text = subprocess.run(["git", "-C", str(ROOT), "show", f"{commit}:tools/exercise_checks.py"],
                          capture_output=True, text=True, check=True).stdout
    return re.split(r"(?m)^# %% \[checks\]\s*$", text, maxsplit=1)[1].strip("\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", default="09b17a1", help="the commit before the fix")
    ap.add_argument("--arms", default=",".join(F.ARMS))
    ap.add_argument("--visible-only", action="store_true",
                    help="only the visible checks (in-process), no grading")
    args = ap.parse_args()
    arms = args.arms.split(",")
    tmp = Path(tempfile.mkdtemp(prefix="fairness-", dir="/tmp"))
    os.chmod(tmp, 0o755)
    old = tmp / "before"
    old.mkdir()
    archive = tmp / "before.tar"
    subprocess.run(["git", "-C", str(ROOT), "archive", "-o", str(archive), args.before,
                    "grader", "rikin", "solutions"], check=True)
    with tarfile.open(archive) as t:
        t.extractall(old, filter="data")
    old_path = f"{old / 'grader'}:{old}"
    old_checks = _old_checks(args.before)
    rows = []
    for arm in arms:
        mod = __import__(f"rikingrade.hidden.{arm}", fromlist=["TESTS"])
        variants = [f for f in F.FAIR if f.arm == arm]
        new_sol = H.load(ROOT / "solutions" / f"{arm}.ipynb")
        old_sol = H.load(old / "solutions" / f"{arm}.ipynb")
        folder = tmp / arm
        folder.mkdir()
        for f in variants:
            nbformat.write(_notebook(f, new_sol), str(folder / f"{f.name}.ipynb"))
        if args.visible_only:
            after = before = {f.name: [0.0, "not graded"] for f in variants}
        else:
            after = _grade(arm, folder, tmp / f"out-{arm}-after", None)
            before = _grade(arm, folder, tmp / f"out-{arm}-before", old_path)
        for f in variants:
            want = sum(W.expected_points(f.variant(), mod.TESTS).values())
            nb_new = _notebook(f, new_sol)
            ns, _ = H.run_notebook(nb_new)
            with contextlib.redirect_stdout(io.StringIO()):
                vis_after = bool(_visible_failures(nb_new, ns))
            nb_old = _notebook(f, old_sol)
            for c in nb_old.cells:
                if "checks" in c.get("metadata", {}).get("tags", []):
                    c.source = old_checks
            try:
                ns_old, _ = H.run_notebook(nb_old)
                with contextlib.redirect_stdout(io.StringIO()):
                    vis_before = bool(_visible_failures(nb_old, ns_old))
            except Exception:  # noqa: BLE001
                vis_before = None
            rows.append((f, want, before[f.name], after[f.name], vis_before, vis_after))
    by_cls = defaultdict(list)
    for r in rows:
        by_cls[r[0].cls].append(r)
    print(f"{'class':>6} {'n':>3} | before: {'low':>3} {'high':>4} {'gr-err':>6} {'vis':>3} | "
          f"after: {'low':>3} {'high':>4} {'gr-err':>6} {'vis':>3}")
    for cls in sorted(by_cls, key=lambda c: [float(x) for x in c.split(".")]):
        rs = by_cls[cls]

        def count(i, pred, rs=rs):
            return sum(1 for r in rs if pred(r, r[i]))

        def low(r, g):
            return g[1] != "grader-error" and g[0] < r[1] - 1e-6

        def high(r, g):
            return g[1] != "grader-error" and g[0] > r[1] + 1e-6

        def err(r, g):
            return g[1] == "grader-error"

        def vis(r, v):
            return r[0].visible is not None and v is not None and v != r[0].visible

        print(f"{cls:>6} {len(rs):>3} | before: {count(2, low):>3} {count(2, high):>4} "
              f"{count(2, err):>6} {count(4, vis):>3} | after: {count(3, low):>3} "
              f"{count(3, high):>4} {count(3, err):>6} {count(5, vis):>3}")
    print()
    print(f"{'variant':<36} {'reasoned':>8} {'before':>7} {'after':>7}  visible before/after")
    for f, want, b, a, vb, va in rows:
        print(f"{f.id:<36} {want:>8.4g} {b[0]:>7.4g} {a[0]:>7.4g}  {vb}/{va} (want {f.visible})"
              + ("" if b[1] != "grader-error" else "  before: grader-error"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
