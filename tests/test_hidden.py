"""The hidden tests: full marks for the solutions, exact partial marks for wrong ones.

The notebooks are run in-process by tests/_hidden_harness.py (our own
notebooks only; the real engine sandboxes student code).
"""

from __future__ import annotations

import importlib
import inspect
import json
import math
import re
from functools import cache
from pathlib import Path

import _hidden_harness as H
import numpy as np
import pytest
import wrong_variants as W
from rikingrade.hidden import EXERCISES
from rikingrade.hidden._common import (
    Spec,
    compare_ik,
    describe_failure,
    is_value_error,
    mask_numbers,
    raised_value_error,
)
from rikingrade.reference import ARMS
from rikingrade.spec import Call, HiddenTest, Outcome
from rikingrade.wire import encode_input

ROOT = Path(__file__).resolve().parent.parent
SEEDS = (0, 1)

#: The expected total of every wrong variant, out of 10, written out from the
#: per-test reasoning in wrong_variants.py (weights: dh_table 1, fk 1.5, ik 2 or
#: 1.5 + 0.5 for the special target, ik_unreachable 1, fk_6dof 1.5, ik_6dof 2,
#: ik_6dof_singular 0.5, ik_6dof_unreachable 0.5).
TOTALS = {
    "cartesian-sign_error": 3.5,        # loses dh 1, fk 1.5, fk_6dof 1.5, ik_6dof 2, singular 0.5
    "cartesian-missing_branch": 8.875,  # half of ik_6dof, a quarter of singular (near it)
    "cartesian-degrees": 7.5,           # ik_6dof 2, ik_6dof_singular 0.5
    "cartesian-flange": 8.5,            # fk_6dof 1.5
    "cartesian-unreachable": 8.5,       # ik_unreachable 1, ik_6dof_unreachable 0.5
    "cylindrical-sign_error": 5.5,      # ik 2, ik_6dof 2, ik_6dof_singular 0.5
    "cylindrical-missing_branch": 8.875,
    "cylindrical-degrees": 5.5,
    "cylindrical-flange": 8.5,
    "cylindrical-unreachable": 8.5,
    "spherical-sign_error": 5.5,        # ik 1.5, ik_on_axis 0.5, ik_6dof 2, singular 0.5
    "spherical-swapped_elbow": 6 - 1 / 6,  # ik 1.5, ik_6dof 2, singular 0.5, near the axis
    "spherical-missing_branch": 8 - 1 / 12,  # half of ik, ik_6dof, singular; near the axis
    "spherical-degrees": 5.5,
    "spherical-flange": 8.5,
    "spherical-unreachable": 8.5,
    "scara-sign_error": 7.75,           # ik_6dof 2, near-singular half of singular 0.5
    "scara-swapped_elbow": 6 - 1 / 6,   # ik 1.5, ik_6dof 2, singular 0.5, near full reach
    "scara-missing_branch": 8 - 1 / 12,
    "scara-degrees": 5.5,               # ik 1.5, ik_full_reach 0.5, ik_6dof 2, singular 0.5
    "scara-flange": 8.5,
    "scara-unreachable": 8.5,
}

REQUIRED_BUGS = ("sign_error", "missing_branch", "degrees", "flange", "unreachable")


def module(name: str):
    return importlib.import_module(f"rikingrade.hidden.{name}")


@cache
def solution(name: str):
    return H.load(ROOT / "solutions" / f"{name}.ipynb")


@cache
def solution_namespace(name: str):
    ns, runs = H.run_notebook(solution(name))
    failed = [(r.index, repr(r.error)) for r in runs if r.error]
    assert not failed, f"solution cells raised: {failed}"
    return ns


# ------------------------------------------------------------------ the contract
@pytest.mark.parametrize("name", EXERCISES)
def test_module_follows_the_spec(name):
    m = module(name)
    assert m.EXERCISE == name
    assert (ROOT / "exercises" / m.NOTEBOOK).exists() and (ROOT / "solutions" / m.NOTEBOOK).exists()
    assert all(isinstance(t, HiddenTest) for t in m.TESTS)
    names = [t.name for t in m.TESTS]
    assert len(set(names)) == len(names)
    assert all(t.weight > 0 and t.timeout > 0 for t in m.TESTS)
    assert math.isclose(sum(t.weight for t in m.TESTS), 10.0)
    ns = solution_namespace(name)
    rng = np.random.default_rng(3)
    for t in m.TESTS:
        calls = t.make_calls(rng)
        assert calls
        for c in calls:
            assert c.function in m.FUNCTIONS
            json.dumps({k: encode_input(v) for k, v in c.kwargs.items()})  # crosses the wire
            params = tuple(inspect.signature(ns[c.function]).parameters)
            # every input positionally, in the stub's order (parameter names do not matter)
            assert c.positional == params == tuple(c.kwargs), (c.function, c.positional, params)
            for name, v in c.kwargs.items():   # as the stubs annotate them
                if name in ("q", "p", "T"):
                    assert isinstance(v, np.ndarray) and v.dtype == np.float64, (name, type(v))
                else:
                    assert type(v) is float, (name, type(v))


@pytest.mark.parametrize("name", EXERCISES)
def test_calls_depend_only_on_the_seed(name):
    m = module(name)
    a = [c for t in m.TESTS for c in t.make_calls(np.random.default_rng(11))]
    b = [c for t in m.TESTS for c in t.make_calls(np.random.default_rng(11))]
    c = [c for t in m.TESTS for c in t.make_calls(np.random.default_rng(12))]
    assert a == b
    assert a != c


# ------------------------------------------------------------------ solutions and exercises
@pytest.mark.parametrize("seed", (0, 1, 2, 3))
@pytest.mark.parametrize("name", EXERCISES)
def test_solutions_get_full_marks(name, seed):
    results = H.grade(module(name), solution_namespace(name), seed)
    for test, score in results:
        assert score.fraction == 1.0, (test.name, score.feedback)
        assert score.feedback


@pytest.mark.parametrize("name", EXERCISES)
def test_unsolved_exercise_gets_zero_and_says_not_implemented(name):
    ns, _ = H.run_notebook(H.load(ROOT / "exercises" / f"{name}.ipynb"))
    results = H.grade(module(name), ns, 0)
    for test, score in results:
        assert score.fraction == 0.0, test.name
        assert "not implemented yet" in score.feedback.lower(), score.feedback


# ------------------------------------------------------------------ wrong variants
def test_every_arm_has_the_required_wrong_variants():
    have = {(v.arm, v.name) for v in W.VARIANTS}
    for arm in EXERCISES:
        for bug in REQUIRED_BUGS:
            assert (arm, bug) in have, (arm, bug)
    assert ("scara", "swapped_elbow") in have and ("spherical", "swapped_elbow") in have
    assert set(TOTALS) == {v.id for v in W.VARIANTS}


@pytest.mark.parametrize("variant", W.VARIANTS, ids=lambda v: v.id)
def test_wrong_variant_loses_exactly_its_points(variant):
    m = module(variant.arm)
    expected = W.expected_points(variant, m.TESTS)
    assert math.isclose(sum(expected.values()), TOTALS[variant.id]), "table and reasoning disagree"
    nb = W.apply(solution(variant.arm), variant)
    ns, runs = H.run_notebook(nb)
    for seed in SEEDS:
        results = H.grade(m, ns, seed)
        got = H.points(results)
        for test, score in results:
            assert math.isclose(got[test.name], expected[test.name], abs_tol=1e-9), (
                seed, test.name, got[test.name], expected[test.name], score.feedback)
        assert math.isclose(sum(got.values()), TOTALS[variant.id], abs_tol=1e-9)
    # the visible checks in the notebook catch it too
    caught = [r for r in runs if r.error is not None and type(r.error).__name__ == "CheckFailed"]
    assert caught, f"{variant.id}: no visible check failed"


def test_feedback_names_the_missing_branch_and_the_flange():
    v = next(v for v in W.VARIANTS if v.id == "scara-missing_branch")
    ns, _ = H.run_notebook(W.apply(solution("scara"), v))
    fb = {t.name: s.feedback for t, s in H.grade(module("scara"), ns, 0)}
    assert "Solutions found: 1 of 2" in fb["ik"] and "Missing: elbow left (q2 < 0)" in fb["ik"]
    assert "2 of 4" in fb["ik_6dof"]
    v = next(v for v in W.VARIANTS if v.id == "cartesian-flange")
    ns, _ = H.run_notebook(W.apply(solution("cartesian"), v))
    fb = {t.name: s.feedback for t, s in H.grade(module("cartesian"), ns, 0)}
    assert "flange" in fb["fk_6dof"] and "tool is missing" in fb["fk_6dof"]
    v = next(v for v in W.VARIANTS if v.id == "spherical-degrees")
    ns, _ = H.run_notebook(W.apply(solution("spherical"), v))
    fb = {t.name: s.feedback for t, s in H.grade(module("spherical"), ns, 0)}
    assert "look like degrees" in fb["ik"]


# ------------------------------------------------------------------ hidden inputs stay hidden
def _numbers(call: Call) -> list[str]:
    out = []
    for v in call.kwargs.values():
        for x in np.ravel(np.asarray(v, dtype=float)):
            if abs(x) > 0.01 and not np.isclose(x, np.round(x)):
                out.append(f"{x:.4g}")
    return out


@pytest.mark.parametrize("variant_id", ["scara-swapped_elbow", "cylindrical-unreachable",
                                        "spherical-degrees", "cartesian-sign_error"])
def test_feedback_reveals_hidden_values_only_when_allowed(variant_id):
    v = next(v for v in W.VARIANTS if v.id == variant_id)
    ns, _ = H.run_notebook(W.apply(solution(v.arm), v))
    m = module(v.arm)
    rng = np.random.default_rng(5)
    revealed_any = False
    for test in m.TESTS:
        calls = test.make_calls(rng)
        outcomes = [H.call(ns, c) for c in calls]
        hidden = {s for c in calls for s in _numbers(c)}
        closed = test.check(calls, outcomes, False)
        opened = test.check(calls, outcomes, True)
        assert closed.fraction == opened.fraction
        leaked = {s for s in hidden if re.search(rf"(?<![\d.]){re.escape(s)}", closed.feedback)}
        assert not leaked, (test.name, leaked, closed.feedback)
        assert closed.detail        # the instructor's log has the details
        if closed.fraction < 1:
            revealed_any |= any(s in opened.feedback for s in hidden)
    assert revealed_any


# ------------------------------------------------------------------ scoring rules, one by one
def _spec(name="scara", six=False):
    return Spec(ARMS[name], six)


def _ik_call(name="scara"):
    arm = ARMS[name]
    L = {"l1": 4.0, "l2": 3.0, "l3": 2.0}
    p = arm.fk([0.4, 1.1, 1.5], **L)[:3, 3]
    kwargs = {"p": p.tolist(), **L}
    return kwargs, arm.ik(p, **L).q


def test_ik_set_comparison_rules():
    spec = _spec()
    kw, Q = _ik_call()
    assert compare_ik(spec, kw, Q[::-1].tolist()).credit == 1.0            # order free
    shifted = Q.copy()
    shifted[:, :2] += 2 * np.pi
    assert compare_ik(spec, kw, shifted.tolist()).credit == 1.0            # modulo 2*pi
    case = compare_ik(spec, kw, np.vstack([Q, Q]).tolist())
    assert case.credit == 1.0 and case.duplicates == 2                      # duplicates merged
    case = compare_ik(spec, kw, Q[:1].tolist())
    assert case.credit == 0.5 and case.missing == ["elbow left (q2 < 0)"] and not case.wrong
    case = compare_ik(spec, kw, Q[0].tolist())                               # shape (3,)
    assert case.credit == 0.5 and case.notes
    wrong = Q.copy()
    wrong[1, 0] += 0.3
    case = compare_ik(spec, kw, wrong.tolist())
    assert case.credit == 1 / 3
    assert case.wrong == ["a solution that does not reach the target (FK check)"]
    deg = Q.copy()
    deg[:, :2] = np.degrees(deg[:, :2])
    case = compare_ik(spec, kw, deg.tolist())
    assert case.credit == 0.0 and case.degrees
    assert compare_ik(spec, kw, [[np.nan, 0, 0]]).credit == 0.0
    assert compare_ik(spec, kw, "no").failure
    assert compare_ik(spec, kw, [[1, 2], [3, 4]]).failure


def test_negative_prismatic_solution_is_explained():
    spec = Spec(ARMS["cylindrical"], False)
    L = {"l1": 3.0, "l2": 1.0}
    p = np.array([2.0, 0.0, 4.0])
    kw = {"p": p.tolist(), **L}
    other = [np.pi, 1.0, -2.0 - 1.0]       # turned around with a negative radial extension
    np.testing.assert_allclose(ARMS["cylindrical"].fk(other, **L)[:3, 3], p, atol=1e-12)
    case = compare_ik(spec, kw, [[0.0, 1.0, 1.0], other])
    assert case.credit == 0.5 and "q3 < 0" in case.wrong[0]


def test_unreachable_scoring():
    m = module("scara")
    test = next(t for t in m.TESTS if t.name == "ik_unreachable")
    calls = test.make_calls(np.random.default_rng(0))
    outs = [Outcome(error_type="ValueError", error_message="beyond reach by 1.234"),
            Outcome(error_type="ValueError", error_message="math domain error"),
            Outcome(value=[[float("nan"), 0.0, 1.0]])]
    s = test.check(calls, outs, False)
    # Task 5 says a "math domain error" is not enough (and the visible check fails it)
    assert math.isclose(s.fraction, 1 / 3)
    assert "math domain error" in s.feedback and "returned NaN values" in s.feedback
    outs = [Outcome(error_type="UnreachableError", error_message="x"),
            Outcome(error_type="MyUnreachable", error_message="x"),   # no bases: not vouched for
            Outcome(error_type="ZeroDivisionError", error_message="division by zero")]
    s = test.check(calls, outs, False)
    assert math.isclose(s.fraction, 1 / 3) and "ZeroDivisionError" in s.feedback


def test_outcome_failures_in_words():
    assert "timed out" in describe_failure(Outcome(timed_out=True), False, 5.0)
    assert "died" in describe_failure(Outcome(crashed=True, detail="SIGKILL"), False, 5.0)
    not_done = Outcome(error_type="NotImplementedError")
    assert "not implemented" in describe_failure(not_done, False, 5.0)
    msg = describe_failure(Outcome(error_type="ValueError", error_message="p = (1.25, -3e-2)"),
                           False, 5.0)
    assert "1.25" not in msg and "not shown" in msg        # a student's message: never echoed
    fixed = Outcome(error_type="TypeError",
                    error_message="list indices must be integers or slices, not tuple")
    assert describe_failure(fixed, False, 5.0).endswith("not tuple")   # Python's own: shown
    assert mask_numbers("q3 = -0.5e3 at 12") == "q# = # at #"
    assert is_value_error("ValueError") and is_value_error("UnreachableError")
    assert not is_value_error("TypeError") and not is_value_error(None)
    assert not is_value_error("TargetOutOfReach")  # a name without bases: not vouched for
    # with the exception's bases (what the engine sends) there is no doubt left
    own_value = Outcome(error_type="OutOfReach",
                        error_bases=("__main__.OutOfReach", "builtins.ValueError",
                                     "builtins.Exception", "builtins.BaseException",
                                     "builtins.object"))
    own_other = Outcome(error_type="OutOfReach",
                        error_bases=("__main__.OutOfReach", "builtins.Exception",
                                     "builtins.BaseException", "builtins.object"))
    fake_name = Outcome(error_type="ValueError",
                        error_bases=("__main__.ValueError", "builtins.Exception",
                                     "builtins.BaseException", "builtins.object"))
    assert raised_value_error(own_value)
    assert not raised_value_error(own_other) and not raised_value_error(fake_name)
    assert not raised_value_error(Outcome(error_type="MyUnreachable"))  # no bases: by name


def test_dh_table_rows_are_validated():
    m = module("scara")
    test = next(t for t in m.TESTS if t.name == "dh_table")
    calls = test.make_calls(np.random.default_rng(0))[:1]
    good = [{"joint": "R", "d": calls[0].kwargs["l1"], "a": calls[0].kwargs["l2"]},
            {"joint": "R", "a": calls[0].kwargs["l3"], "alpha": np.pi}, {"joint": "P"}]
    assert test.check(calls, [Outcome(value=good)], False).fraction == 1.0
    for bad, words in (("rows", "list of dicts"), (good[:2], "has 2 rows"),
                       ([dict(good[0], joint="P"), *good[1:]], "joint 1 is revolute"),
                       ([good[0], dict(good[1], alpha=180.0), good[2]], "degrees"),
                       ([good[0], dict(good[1], colour=1), good[2]],
                        "keys rikin.link does not know"),
                       ([good[0], good[1], dict(good[2], theta=np.pi / 2)], "axes are not")):
        s = test.check(calls, [Outcome(value=bad)], False)
        assert s.fraction == 0.0 and words in s.feedback.lower(), (words, s.feedback)


def test_reference_answers_are_remembered_per_call_not_shared_between_calls():
    # Every submission is scored on the same calls, so the reference's answers are kept;
    # a different call must still get its own answer, and unreachable must raise each time.
    spec = _spec()
    kw, Q = _ik_call()
    first = spec.ref_ik(kw)
    assert spec.ref_ik(dict(kw)) is first                     # same inputs: kept
    other = dict(kw, p=ARMS["scara"].fk([-1.0, 0.7, 0.5], **{"l1": 4.0, "l2": 3.0, "l3": 2.0})[
        :3, 3].tolist())
    assert not np.allclose(spec.ref_ik(other).q, first.q)      # other inputs: their own
    far = dict(kw, p=[50.0, 0.0, 1.0])
    for _ in range(3):
        with pytest.raises(ValueError) as info:
            spec.ref_ik(far)
        assert len(list(_frames(info.value.__traceback__))) <= 3  # no traceback growth
    # scoring the same answer twice gives the same result (the second from the memo)
    assert compare_ik(spec, kw, Q.tolist()) == compare_ik(spec, kw, Q.tolist())


def _frames(tb):
    while tb is not None:
        yield tb
        tb = tb.tb_next


def test_a_timeout_says_which_call_hung_and_which_were_not_run():
    m = module("scara")
    test = next(t for t in m.TESTS if t.name.startswith("fk") and "6" not in t.name)
    calls = test.make_calls(np.random.default_rng(0))
    hung = Outcome(timed_out=True, detail="timed out: no result within 2 s")
    skipped = Outcome(timed_out=True, detail="not run: an earlier call of this test timed out")
    outs = [hung] + [skipped] * (len(calls) - 1)
    s = test.check(calls, outs, False)
    assert s.fraction == 0.0
    assert "no result within 2 s (1x)" in s.feedback
    assert f"not run: an earlier call of this test timed out ({len(calls) - 1}x)" in s.feedback


def test_remembered_reference_answers_are_read_only():
    spec = _spec()
    kw, _ = _ik_call()
    ref = spec.ref_ik(kw)
    with pytest.raises(ValueError, match="read-only"):
        ref.q[0, 0] = 0.0
