"""The grading benchmark runs end to end on a tiny class (figures are not asserted here)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from grader_fixtures.helpers import require_bwrap

ROOT = Path(__file__).resolve().parent.parent


def test_bench_grade_tiny():
    require_bwrap()
    r = subprocess.run(
        [
            sys.executable,
            str(ROOT / "benchmarks" / "bench_grade.py"),
            "--n",
            "34",
            "--nbgrader-n",
            "0",
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stdout + r.stderr
    assert "notebooks/min" in r.stdout
    figures = json.loads(r.stdout.strip().splitlines()[-1])
    assert figures["n"] == 34 and figures["notebooks_per_min"] > 0
    assert figures["missed_full_marks"] == [] and figures["false_passes"] == []
    assert "nbgrader: skipped" in r.stdout
