"""What a hung student function costs (issue 11 item 7): the per-call limit once, per notebook.

The SCARA solution with one more cell that makes a function hang, graded in the sandbox
with the default limits (2 s per call). Six hidden tests reach ``ik_scara``, three of them
through ``ik_scara_6dof``; before, each of them ran a call to the full limit (12.4 s for
the notebook). What is counted here does not depend on the machine's speed: how many
calls ran to the full limit, and how many were stopped at a short one; one wall-clock
bound per notebook checks the total against the per-call limit plus a constant, stretched
as the grader stretches its own clock on a busy machine (``calllimits.backstop``: the
child counts a call's time as on an idle machine).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from grader_fixtures.helpers import FAST, require_bwrap
from rikingrade import grade
from rikingrade.calllimits import FACTOR, FLOOR, CallLimits, backstop
from rikingrade.hidden._common import TIMEOUT

ROOT = Path(__file__).resolve().parent.parent
#: Seconds a hung notebook may cost beyond one call at the limit: about 1.3 s of short
#: limits (five calls of 0.25 s), the cells run again after each stop, and the notebook's
#: own grading (0.2-0.3 s). Measured 1.7-2.1 s with the machine's load average at 2-5.
CONSTANT = 4.0
SLOW = dict(FAST, cell_timeout=30.0)

HANG_IK = "def ik_scara(p, l1, l2, l3):\n    while True:\n        pass\n"
#: The hang is in a helper that no hidden test calls: reached only through other functions.
HANG_HELPER = (
    "import numpy as np\n"
    "def _positioning(x, y, z, l1, l2, l3):\n    while True:\n        pass\n"
    "def ik_scara(p, l1, l2, l3):\n    return _positioning(*np.asarray(p), l1, l2, l3)\n"
    "def ik_scara_6dof(T, l1, l2, l3, tool):\n"
    "    T = np.asarray(T, dtype=float)\n"
    "    return _positioning(*(T[:3, 3] - tool * T[:3, 2]), l1, l2, l3)\n"
)
#: Right everywhere, but a target out of reach makes it search for ever.
HANG_SOME = (
    "import time\n_good_ik = ik_scara\n"
    "def ik_scara(p, l1, l2, l3):\n"
    "    time.sleep({sleep})\n"
    "    try:\n        return _good_ik(p, l1, l2, l3)\n"
    "    except ValueError:\n"
    "        while True:\n            pass\n"
)
#: The cell that defines it also tries it, so it runs while grading (it binds ik_scara).
HANG_IN_CELL = HANG_IK + "print(ik_scara([1.0, 0.5, 0.2], 1.0, 1.0, 0.8))\n"
#: Swallows the child's stop: only the grader's own clock ends its calls.
HANG_SWALLOW = (
    "def ik_scara(p, l1, l2, l3):\n"
    "    while True:\n"
    "        try:\n            while True:\n                pass\n"
    "        except BaseException:\n            pass\n"
)
IK_TESTS = ["ik", "ik_full_reach", "ik_unreachable", "ik_6dof", "ik_6dof_singular"]
IK_TESTS += ["ik_6dof_unreachable"]


def _grade(tmp_path: Path, **cells: str):
    nb = json.loads((ROOT / "solutions" / "scara.ipynb").read_text())
    cls = tmp_path / "class"
    cls.mkdir()
    for name, src in cells.items():
        one = json.loads(json.dumps(nb))
        one["cells"].append(
            {
                "cell_type": "code",
                "metadata": {},
                "outputs": [],
                "execution_count": None,
                "source": src,
            }
        )
        (cls / f"{name}.ipynb").write_text(json.dumps(one))
    return grade("scara", [cls], tmp_path / "out", workers=2, **SLOW).by_student()


def _stops(res) -> tuple[int, int]:
    """(calls that ran to the full limit, calls stopped at a short limit)."""
    full = sum(t.feedback.count(f"no result within {TIMEOUT:g} s") for t in res.tests)
    short = sum(t.feedback.count("stopped at the short limit") for t in res.tests)
    return full, short


def test_a_hung_function_costs_the_call_limit_once_wherever_it_is_called_from(tmp_path):
    require_bwrap()
    res = _grade(tmp_path, hang_ik=HANG_IK, hang_helper=HANG_HELPER)
    for name in ("hang_ik", "hang_helper"):
        r = res[name]
        assert [t.name for t in r.tests if t.timed_out] == IK_TESTS, name
        assert r.score == pytest.approx(4.0), name  # DH 1, FK 1.5, FK 6-DOF 1.5
        assert _stops(r) == (1, 5), (name, [t.feedback for t in r.tests])
        assert r.elapsed < backstop(TIMEOUT + CONSTANT), (name, r.elapsed)
    # the student is told why the later tests stopped early, once, at the top
    (line,) = [p for p in res["hang_ik"].problems if "short limit" in p]
    assert line.startswith(f"ik_scara did not return within {TIMEOUT:g} s in test ik;")
    assert "test ik_6dof" in line
    # a helper's name (the student's words) is not echoed next to hidden values
    fb = next(t.feedback for t in res["hang_helper"].tests if t.name == "ik_6dof")
    assert "short limit of a function it calls" in fb and "_positioning" not in fb


def test_a_function_that_hangs_on_some_inputs_keeps_the_points_where_it_returns(tmp_path):
    # ik_scara takes 0.3 s per call (more than the 0.25 s floor) and hangs on unreachable
    # targets: after its first stop it gets 4 x 0.3 s, so ik_6dof's calls through it pass.
    require_bwrap()
    res = _grade(tmp_path, some=HANG_SOME.format(sleep=0.3))["some"]
    lost = {t.name: t.fraction for t in res.tests if t.fraction < 1}
    assert lost == {"ik_unreachable": 0.0, "ik_6dof_unreachable": 0.0}, res.tests
    assert _stops(res) == (1, 1)
    # the short limit said is derived from its calls (each took at least 0.3 s, more on a
    # loaded machine), not the floor
    (said,) = re.findall(r"a short limit of ([0-9.]+) s", " ".join(res.problems))
    assert FACTOR * 0.3 - 0.05 <= float(said) <= TIMEOUT, res.problems


def test_a_hung_function_called_by_a_cell_costs_the_call_limit_not_the_cell_limit(tmp_path):
    require_bwrap()
    res = _grade(tmp_path, cell=HANG_IN_CELL)["cell"]
    (cell,) = [c for c in res.cells if c.status != "ok"]
    assert cell.error_type == "CallTimedOut" and "ik_scara did not return within 2 s" in (
        cell.message
    )
    assert [t.name for t in res.tests if t.timed_out] == IK_TESTS
    assert _stops(res) == (0, 6)  # the cell's call was the one at the full limit
    assert res.elapsed < backstop(TIMEOUT + CONSTANT), res.elapsed


def test_a_notebook_that_swallows_the_stop_meets_the_graders_clock(tmp_path):
    require_bwrap()
    res = _grade(tmp_path, swallow=HANG_SWALLOW)["swallow"]
    assert [t.name for t in res.tests if t.timed_out] == IK_TESTS
    assert res.score == pytest.approx(4.0)
    # two calls at the limit (ik_scara, then ik_scara_6dof around it) and short ones after
    assert _stops(res)[0] == 2, [t.feedback for t in res.tests]


def test_short_limits_derive_from_the_functions_own_successful_calls():
    lim = CallLimits()
    lim.returned("ik", 0.01, 2.0)
    lim.returned("slow", 0.4, 2.0)
    lim.returned("slower", 0.9, 2.0)
    lim.returned("forged", float("inf"), 2.0)  # not finite: ignored
    assert lim.leash(2.0) == {}  # nothing ran out: every call gets the full limit
    lim.timed_out(["ik", "slow", "slower", "never_returned"], "ik")
    assert lim.short("ik", 2.0) == pytest.approx(FLOOR * 2.0)  # at least 1/8 of the limit
    assert lim.short("never_returned", 2.0) == pytest.approx(FLOOR * 2.0)
    assert lim.short("slow", 2.0) == pytest.approx(FACTOR * 0.4)
    assert lim.short("slower", 2.0) == 2.0  # never more than the limit
    assert set(lim.leash(2.0)) == {"ik", "slow", "never_returned"}
    assert lim.limit_of("fk", 2.0) == 2.0 and lim.limit_of("slow", 2.0) == pytest.approx(1.6)
    # a stop at one function's short limit charges that function, not its callers
    lim.timed_out(["ik_6dof", "ik"], "ik_6dof", short="ik")
    assert "ik_6dof" not in lim.ran_out and lim.ran_out["ik"] == ["ik", "ik_6dof"]


def test_the_exercises_state_the_short_limit_as_the_grader_applies_it():
    said = f"{FACTOR:g} times its longest call that returned, at least {FLOOR * TIMEOUT:g} s"
    for arm in ("cartesian", "cylindrical", "spherical", "scara"):
        for folder in ("exercises", "solutions"):
            cells = json.loads((ROOT / folder / f"{arm}.ipynb").read_text())["cells"]
            text = " ".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
            assert said in " ".join(text.split()), (folder, arm)


def _cell_functions(source: str) -> dict:
    """A namespace with ``source`` run as a notebook cell (its functions' file is "<cell 1>")."""
    ns: dict = {"__name__": "__main__"}
    exec(compile(source, "<cell 1>", "exec"), ns)
    return ns


def test_the_child_stops_a_call_at_its_limit_and_names_what_was_running():
    from rikingrade.sandbox import child

    ns = _cell_functions(
        "import time\n"
        "def helper(n):\n    while True:\n        pass\n"
        "def outer():\n    return helper(0)\n"
        "def swallows():\n    try:\n        helper(0)\n    except BaseException:\n        pass\n"
        "    return 42\n"
        "def quick():\n    time.sleep(0.05)\n    return 1\n"
        "def caller():\n    return [quick() for _ in range(3)]\n"
    )
    watch = child.Watch()

    def run(name, limit, leash=None):
        # the child's clock: time waiting for a processor (the machine busy) not counted
        watch.start(ns, limit, leash or {}, call=name)
        t0 = child.busy_clock()
        try:
            return ns[name](), child.busy_clock() - t0
        except child.CallTimedOut:
            return None, child.busy_clock() - t0
        finally:
            watch.stop()

    value, took = run("outer", 0.2)
    assert value is None and 0.2 <= took < 0.2 + 5 * child.TICK
    assert watch.fired["stack"] == ["outer", "helper"] and watch.fired["function"] == "outer"
    # a short limit on the helper stops it inside a caller that has the full limit
    value, took = run("outer", 5.0, {"helper": 0.1})
    assert watch.fired["function"] == "helper" and took < 0.1 + 5 * child.TICK
    # swallowed, it still counts: the child reports the call as stopped (call() reads fired)
    value, took = run("swallows", 0.2)
    assert value == 42 and watch.fired["function"] == "swallows"
    # a call that returns in time is not stopped, and says how long its callees ran
    watch.fired = None
    value, took = run("caller", 2.0)
    assert value == [1, 1, 1] and watch.fired is None
    assert 0.0 <= watch.finished.get("quick", 0.0) < 0.1
