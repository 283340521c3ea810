"""Indexing rikin's results (issue 10): ``res[i]`` as a student writes it.

An IKResult is a sequence of solutions: a whole number in range (negative from the end),
a slice, ``res[i, j]``, a list or array of whole numbers, a boolean mask, as numpy takes
them. Anything else is rikin's InputError naming the index, what was wrong, and the valid
range (an index beyond the solutions: OutOfRangeError, which is also an IndexError, so code
written for lists keeps working). BatchIKResult and NumericalIKResult are not sequences:
indexing one says how to read it. The named tuples (Branch, LessonArm) index as tuples do,
with the same errors. Before: Python's and numpy's bare IndexError / TypeError.
"""

from __future__ import annotations

import copy
import pickle
from dataclasses import replace

import numpy as np
import pytest
import sympy

import rikin
from rikin import InputError, NotIndexedError, OutOfRangeError, robots
from rikin.ik import ik_numerical
from rikin.symbolic import lesson_arm

ARM = robots.aula10_6r()
RES = ARM.ik(ARM.fk(np.array([0.3, -1.2, 2.0, 0.4, -0.7, 3.0])))  # 8 solutions of 6 joints
K, N = RES.q.shape


def test_the_result_has_the_solutions_this_file_assumes():
    assert (K, N) == (8, 6)


@pytest.mark.parametrize(
    "key",
    [0, 7, -1, -8, np.int64(3), np.uint8(2), sympy.Integer(1), np.array(2), slice(None),
     slice(1, 5, 2), slice(None, None, -1), slice(-100, 100), (0, 1), (-1, -1), (slice(None), 0),
     (Ellipsis, 5), Ellipsis, [0, -1], [], np.array([1, 2]), np.array([[0, 1], [2, 3]]),
     [True] * 4 + [False] * 4, np.arange(8) % 3 == 0, (), (2, slice(1, 3))],
    ids=repr,
)
def test_a_valid_index_reads_what_numpy_reads_from_q(key):
    want = RES.q[int(key) if isinstance(key, sympy.Integer) else key]
    got = RES[key]
    assert np.array_equal(got, want) and got.shape == want.shape


def test_iteration_unpacking_and_the_sequence_protocols():
    rows = list(RES)
    assert len(rows) == K and all(np.array_equal(r, q) for r, q in zip(rows, RES.q, strict=True))
    first, *rest = RES
    assert np.array_equal(first, RES.q[0]) and len(rest) == K - 1
    assert [np.array_equal(a, b) for a, b in zip(reversed(RES), RES.q[::-1], strict=True)] == [
        True] * K
    seen = []
    for s in RES:
        seen.append(s)
    assert len(seen) == K
    # code written for lists: index until IndexError
    i, count = 0, 0
    while True:
        try:
            RES[i]
        except IndexError:
            break
        i, count = i + 1, count + 1
    assert count == K
    small = ARM.ik(ARM.fk(np.array([0.3, -1.2, 2.0, 0.4, -0.7, 3.0])))
    a, b, c, d, e, f, g, h = small  # unpacking the eight solutions
    assert np.array_equal(h, small.q[-1])


@pytest.mark.parametrize("key, by", [(8, 1), (100, 93), (-9, 1), (-20, 12), (np.int64(8), 1),
                                     ((8, 0), 1), ((0, 6), 1), ((0, -7), 1), ([0, 8], 1),
                                     (np.array([-9]), 1)])
def test_an_index_beyond_the_solutions_says_the_range_and_by_how_much(key, by):
    with pytest.raises(OutOfRangeError, match=rf"index -?\d+ .*out of range by {by}\b") as exc:
        RES[key]
    err = exc.value
    assert isinstance(err, IndexError) and isinstance(err, InputError)
    assert isinstance(err, ValueError)  # every rikin error is one
    text = str(err)
    assert "IKResult" in text and ("0 to 7" in text or "0 to 5" in text)


@pytest.mark.parametrize(
    "key, words",
    [("x", "is text.*solution number.*0 to 7.*attributes: q, "),
     ("q", "q is an attribute, read it as result.q"),
     ("labels", "read it as result.labels"),
     (b"0", "is text"),
     (1.5, "1.5 is not a whole number's type"),
     (1.0, r"write int\(1.0\)"),
     (np.float64(2.0), r"write int\(2.0\)"),
     (1 + 0j, "not a whole number's type"),
     (True, "True is a boolean, not a solution number.*mask is an array of 8 booleans"),
     (np.bool_(False), "is a boolean"),
     (None, "index is None, not a solution number"),
     ({"a": 1}, "is not a solution number"),
     (sympy.Float(1.0), "is not a solution number"),
     ((0, 1, 2), "has 3 entries, but IKResult has 2 axes \\(solution, joint\\)"),
     ((Ellipsis, Ellipsis), "more than one '...'"),
     ((0, "a"), "is text.*joint number.*0 to 5"),
     ((None, 0), "index is None"),
     ([0.0, 1.0], "must hold whole numbers.*float64"),
     (np.array([0.5]), "must hold whole numbers"),
     ([[]], "must hold whole numbers"),
     (np.array([], dtype=float), "must hold whole numbers"),
     (["a"], "must hold whole numbers"),
     ([0, None], "must hold whole numbers"),
     ([True, False], r"boolean mask must have one entry per solution, shape \(8,\), got shape "
                     r"\(2,\)"),
     (slice(0.5, None), "slice's start must be a whole number"),
     (slice(None, "3"), "slice's stop must be a whole number"),
     (slice(None, None, 0), "slice step cannot be zero")],
    ids=repr,
)
def test_a_bad_index_is_an_input_error_saying_what_is_valid(key, words):
    with pytest.raises(InputError, match=words) as exc:
        RES[key]
    assert "IKResult index" in str(exc.value)
    assert not isinstance(exc.value, OutOfRangeError)


def test_an_empty_result_says_it_has_no_solutions():
    """Every solution of this PPRRR pose needs slide 1 at -2: the limit (>= 0) drops both."""
    arm = robots.pprrr()
    arm = arm.replace(links=(replace(arm.links[0], qlim=(0.0, np.inf)),) + arm.links[1:])
    res = arm.ik(arm.fk([-2.0, 3.0, 0.5, 0.7, 0.2]), within_limits=True)
    assert len(res) == 0 and res.discarded == 2 and list(res) == []
    with pytest.raises(OutOfRangeError, match="it has no solutions"):
        res[0]
    assert res[:].shape == (0, 5)


def test_a_batch_result_is_not_indexed_and_says_how_to_read_a_pose():
    T = ARM.fk(np.array([[0.3, -1.2, 2.0, 0.4, -0.7, 3.0], [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]]))
    b = ARM.ik_batch(T)
    for key in (0, -1, "x", slice(None), None, 1.5):
        with pytest.raises(NotIndexedError, match=r"result\.q\[i\]\[result\.valid\[i\]\]"):
            b[key]
    with pytest.raises(NotIndexedError, match="read it as result.valid"):
        b["valid"]
    with pytest.raises(NotIndexedError, match="iterated: a batch result is not indexed by pose"):
        list(b)
    with pytest.raises(NotIndexedError, match="not indexed by pose"):
        for _ in b:
            pass
    # a TypeError too, as Python's own: code that tells sequences apart that way still can
    with pytest.raises(TypeError):
        tuple(b)
    with pytest.raises(InputError, match="links must be a sequence of rikin.Link"):
        rikin.SerialArm(b)
    # ... and what the message says to write gives pose 0's solutions
    sols = b.q[0][b.valid[0]]
    assert len(sols) == 8 and np.abs(ARM.fk(sols) - T[0]).max() < 1e-9


def test_a_numerical_result_holds_one_solution_and_says_so():
    sol = ik_numerical(ARM, ARM.fk(np.full(6, 0.3)), np.full(6, 0.25))
    with pytest.raises(NotIndexedError, match=r"holds one solution, result\.q"):
        sol[0]
    with pytest.raises(NotIndexedError, match="read it as result.success"):
        sol["success"]
    with pytest.raises(NotIndexedError, match="NumericalIKResult was iterated"):
        q1, *_ = sol


def test_a_branch_indexes_as_the_tuple_it_is():
    br = RES.branches[0]
    assert (br[0], br[1], br[2], br[3]) == (br.shoulder, br.elbow, br.wrist, br.root) == tuple(br)
    assert br[-1] == br.root is None and br[:2] == (br.shoulder, br.elbow)
    assert br[np.int64(1)] == br.elbow
    shoulder, elbow, wrist, root = br
    assert br._asdict() == {"shoulder": shoulder, "elbow": elbow, "wrist": wrist, "root": root}
    assert pickle.loads(pickle.dumps(br)) == br and copy.deepcopy(br) == br
    assert br.label == f"{shoulder}/{elbow}/{wrist}"
    with pytest.raises(OutOfRangeError, match="Branch index 4 is out of range by 1.*0 to 3"):
        br[4]
    with pytest.raises(InputError, match="elbow is an attribute, read it as branch.elbow"):
        br["elbow"]
    for key in (None, 1.0, [0], (0,), True):
        with pytest.raises(InputError, match="Branch index"):
            br[key]


def test_a_lesson_arm_indexes_as_the_tuple_it_is():
    la = lesson_arm("planar_2r")
    links, lengths, joints, convention = la
    assert la[0] is links and la[-1] == convention == "standard" and la[1:3] == (lengths, joints)
    with pytest.raises(OutOfRangeError, match="LessonArm index 4 is out of range by 1"):
        la[4]
    with pytest.raises(InputError, match="read it as arm.links"):
        la["links"]


def test_the_new_error_is_exported_with_the_others():
    assert rikin.OutOfRangeError is rikin.errors.OutOfRangeError
    assert issubclass(rikin.OutOfRangeError, rikin.InputError)
    assert issubclass(rikin.OutOfRangeError, IndexError)
    assert rikin.NotIndexedError is rikin.errors.NotIndexedError
    assert issubclass(rikin.NotIndexedError, rikin.InputError)
    assert issubclass(rikin.NotIndexedError, TypeError)
