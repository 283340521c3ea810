"""A correct answer's grade does not depend on the grader machine's load (issue 26 item 6).

The same class is graded twice with the same seed: as the machine is, and with both CPUs
kept busy by two more processes that spin for ever. A correct notebook whose first FK call
spends 1.2 s of CPU time (as one that builds its formula with sympy does; the limit per
call is 2 s) must keep 10/10 both times: the limit counts a call's time as on an idle
machine. Before, under the grader's own parallel load it ran out (10 -> 8.5 in the issue's
class of 38); on this shared machine it often ran out alone too.

The spin is measured in CPU time inside the notebook, so the call costs 1.2 s of CPU on
any machine; what the load changes is only how long that takes on the wall clock.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from grader_fixtures.helpers import FAST, require_bwrap
from rikingrade import grade

ROOT = Path(__file__).resolve().parent.parent
ARMS = ("scara", "spherical")

FIRST_CALL_SLOW = (
    "import time\n"
    "_fk_fast = {fk}\n"
    "_built = []\n\n\n"
    "def {fk}(q, *lengths):\n"
    "    if not _built:  # the first call builds its formula: 1.2 s of CPU time\n"
    "        t0 = time.process_time()\n"
    "        while time.process_time() - t0 < 1.2:\n"
    "            pass\n"
    "        _built.append(True)\n"
    "    return _fk_fast(q, *lengths)\n"
)


def _class(folder: Path) -> None:
    """Per arm, its solution and the same with a first FK call that costs 1.2 s of CPU."""
    for arm in ARMS:
        (folder / arm).mkdir(parents=True)
        nb = json.loads((ROOT / "solutions" / f"{arm}.ipynb").read_text())
        (folder / arm / "solution.ipynb").write_text(json.dumps(nb))
        nb["cells"].append({"cell_type": "code", "metadata": {}, "outputs": [],
                            "execution_count": None,
                            "source": FIRST_CALL_SLOW.format(fk=f"fk_{arm}")})
        (folder / arm / "first_call_slow.ipynb").write_text(json.dumps(nb))


def _scores(folder: Path, out: Path) -> dict[str, dict[str, float]]:
    got = {}
    for arm in ARMS:
        report = grade(arm, [folder / arm], out / arm, workers=2,
                       **dict(FAST, cell_timeout=60.0))
        for student, res in report.by_student().items():
            got[f"{arm}/{student}"] = {t.name: t.points for t in res.tests}
    return got


def test_the_same_notebooks_get_the_same_scores_alone_and_with_both_cpus_busy(tmp_path):
    require_bwrap()
    _class(tmp_path / "class")
    alone = _scores(tmp_path / "class", tmp_path / "alone")
    spin = [subprocess.Popen([sys.executable, "-c", "while True:\n    pass"]) for _ in range(2)]
    try:
        busy = _scores(tmp_path / "class", tmp_path / "busy")
    finally:
        for p in spin:
            p.kill()
            p.wait()
    assert busy == alone
    for name, points in alone.items():
        assert sum(points.values()) == pytest.approx(10.0), (name, points)
