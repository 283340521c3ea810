"""A small fake exercise for developing and testing the grading engine.

It follows ``rikingrade.spec`` like the real ``rikingrade.hidden.<exercise>`` modules:
``add(a, b)`` and the forward kinematics of a planar 2R arm, ``fk_2r(l1, l2, q1, q2)`` ->
``[x, y]`` and ``fk_2r_batch(l1, l2, q)`` with ``q`` an (N, 2) numpy array -> (N, 2).
Expected values come from ``rikin`` (planar_2r FK), computed in the grader. Max score 5.
"""

from __future__ import annotations

import math

import numpy as np
from rikingrade.spec import Call, HiddenTest, Outcome, Score

import rikin

EXERCISE = "fake2r"
NOTEBOOK = "fake2r.ipynb"
FUNCTIONS = ("add", "fk_2r", "fk_2r_batch")
TIMEOUT = 1.0  # seconds per call: short, so hostile cases are cheap to test


def _why(o: Outcome) -> str:
    if o.timed_out:
        return "it did not return in time (an endless loop?)"
    if o.crashed:
        return f"the notebook's process stopped ({o.detail})"
    if o.error_type:
        return f"it raised {o.error_type}: {o.error_message}"
    return "it returned a wrong value"


def _score(calls, outcomes, reveal, expected, close, what) -> Score:
    good, bad = 0, None
    details = []
    for c, o in zip(calls, outcomes, strict=True):
        want = expected(c)
        ok = o.ok and close(o.value, want)
        good += ok
        if not ok and bad is None:
            bad = (c, o)
        details.append(f"{c.function}({c.kwargs}) -> {o.value!r} want {want!r} ok={ok}")
    n = len(calls)
    if good == n:
        fb = f"{what}: all {n} cases correct"
    else:
        c, o = bad
        fb = f"{what}: {good} of {n} cases correct; one failed because {_why(o)}"
        if reveal:
            fb += f" (input {c.kwargs}, expected {expected(c)!r})"
    return Score(good / n, fb, "; ".join(details))


def _num_equal(value, want) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and value == want


def _allclose(value, want) -> bool:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    want = np.asarray(want, dtype=float)
    return (
        arr.shape == want.shape
        and bool(np.all(np.isfinite(arr)))
        and bool(np.allclose(arr, want, rtol=1e-9, atol=1e-9))
    )


def _fk(l1, l2, q):
    T = rikin.robots.planar_2r(l1, l2).fk(np.asarray(q, dtype=float))
    return T[..., :2, 3]


# --------------------------------------------------------------------------- tests
def _add_int_calls(rng):
    return [
        Call("add", {"a": int(rng.integers(-50, 50)), "b": int(rng.integers(-50, 50))})
        for _ in range(4)
    ]


def _add_float_calls(rng):
    return [
        Call("add", {"a": float(rng.uniform(-5, 5)), "b": float(rng.uniform(-5, 5))})
        for _ in range(3)
    ]


def _fk_calls(rng):
    # Four poses: the first has q2 = 0 (arm stretched), the others a bent elbow.
    calls = []
    for i in range(4):
        l1, l2 = (float(x) for x in rng.uniform(0.5, 2.0, 2))
        q1 = float(rng.uniform(-math.pi, math.pi))
        q2 = 0.0 if i == 0 else float(rng.uniform(0.3, 2.5))
        calls.append(Call("fk_2r", {"l1": l1, "l2": l2, "q1": q1, "q2": q2}))
    return calls


def _fk_batch_calls(rng):
    return [
        Call("fk_2r_batch", {"l1": 1.5, "l2": 0.75, "q": rng.uniform(-math.pi, math.pi, (5, 2))})
    ]


def _check_add_int(calls, outcomes, reveal):
    return _score(
        calls,
        outcomes,
        reveal,
        lambda c: c.kwargs["a"] + c.kwargs["b"],
        _num_equal,
        "add with integers",
    )


def _check_add_float(calls, outcomes, reveal):
    return _score(
        calls,
        outcomes,
        reveal,
        lambda c: c.kwargs["a"] + c.kwargs["b"],
        lambda v, w: (
            isinstance(v, (int, float))
            and not isinstance(v, bool)
            and math.isclose(v, w, rel_tol=1e-12, abs_tol=1e-12)
        ),
        "add with floats",
    )


def _check_fk(calls, outcomes, reveal):
    return _score(
        calls,
        outcomes,
        reveal,
        lambda c: _fk(c.kwargs["l1"], c.kwargs["l2"], [c.kwargs["q1"], c.kwargs["q2"]]).tolist(),
        _allclose,
        "fk_2r gives the tool position",
    )


def _check_fk_batch(calls, outcomes, reveal):
    return _score(
        calls,
        outcomes,
        reveal,
        lambda c: _fk(c.kwargs["l1"], c.kwargs["l2"], c.kwargs["q"]).tolist(),
        _allclose,
        "fk_2r_batch gives one position per row of q",
    )


TESTS = [
    HiddenTest("add_int", 1.0, "add two integers", _add_int_calls, _check_add_int, TIMEOUT),
    HiddenTest("add_float", 1.0, "add two floats", _add_float_calls, _check_add_float, TIMEOUT),
    HiddenTest("fk_2r", 2.0, "planar 2R forward kinematics", _fk_calls, _check_fk, TIMEOUT),
    HiddenTest(
        "fk_2r_batch",
        1.0,
        "planar 2R FK for many q at once",
        _fk_batch_calls,
        _check_fk_batch,
        TIMEOUT,
    ),
]
