"""A pose's solutions do not depend on the other poses solved with it.

``arm.ik`` hands the array solvers (rikin.ik.pieper, parallel3, general6r) one pose,
``arm.ik_batch`` hands them a chunk's poses together: both must give the same bits for
the same pose. Near a fold of the arm (two solutions about to meet) a root is fixed by the
pose only to ~sqrt(rounding), so any rounding that depends on the batch (a BLAS product
whose blocking follows the number of rows, an algorithm chosen by how many poses there
are) shows there as 1e-8..1e-5 rad, or as a solution kept or merged. Here each pose is
solved alone and among others (in two orders, and duplicated), on seeded random tables of
every array solver's family and on poses on and 1e-9..1e-3 rad off their folds (found
from the Jacobian's determinant, not from a solver).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from singular_poses import singular_q, wrist_centre
from test_ik6r_families import parallel_arm, random_6r, ur5e
from test_pieper import spherical_wrist_arms
from test_pieper_batch import (
    irb2400,
    kr5,
    near_singular_q,
    puma_standard,
    skew_quartic,
    with_base_tool,
)

import rikin
from rikin.ik import families6r

pi = np.pi


def fold_q(arm, rng):
    """Joints where the Jacobian's determinant changes sign along one random joint (a fold:
    two solutions meet), by bisection on a grid's bracket; and that joint."""
    while True:
        q, j = rng.uniform(-pi, pi, 6), int(rng.integers(6))
        x = np.linspace(-pi, pi, 721)
        Q = np.tile(q, (x.size, 1))
        Q[:, j] = x
        det = np.linalg.det(arm.jacobian(Q))
        cross = np.flatnonzero(np.sign(det[:-1]) != np.sign(det[1:]))
        if not cross.size:
            continue
        lo, hi = x[cross[0]], x[cross[0] + 1]
        sign_lo = np.sign(det[cross[0]])
        for _ in range(60):
            q[j] = (lo + hi) / 2
            if np.sign(np.linalg.det(arm.jacobian(q))) == sign_lo:
                lo = q[j]
            else:
                hi = q[j]
        return q, j


def near_fold_q(arm, rng, n):
    """``n`` joints on a fold of ``arm`` or 1e-9..1e-3 rad off it, ``(n, 6)``."""
    out = []
    for k in range(n):
        q, j = fold_q(arm, rng)
        if k % 3:
            q[j] += 10.0 ** rng.uniform(-9, -3) * rng.choice([-1, 1])
        out.append(q)
    return np.array(out)


def assert_alone_as_in_a_batch(arm, q, rng):
    """Every pose of ``arm.fk(q)``: ``solve`` of it alone gives the bits it gets among all
    the others (shuffled, reversed, and once more in order: a batch of three times as many),
    every slot's joints, validity and singularity flags."""
    T = arm._world_to_base(arm.fk(q))
    solver = families6r.solver_for(arm)
    kw = {"labels": False} if getattr(solver, "labels_optional", False) else {}
    n = len(q)
    perm = rng.permutation(n)
    batch = solver.solve(arm, np.concatenate([T[perm], T[perm[::-1]], T]), None, **kw)
    where = np.argsort(perm)
    for k in range(n):
        alone = solver.solve(arm, T[[k]], None, **kw)
        for row in (where[k], 2 * n - 1 - where[k], 2 * n + k):
            assert np.array_equal(alone.valid[0], batch.valid[row]), (k, row)
            assert np.array_equal(alone.q[0], batch.q[row], equal_nan=True), (k, row)
            for name, mask in alone.singular.items():
                assert np.array_equal(mask[0], batch.singular[name][row]), (k, row, name)


def test_the_pose_near_a_wrist_fold_that_moved_8e_6_rad():
    """Fails before: the skew quartic's wrist-fold pose below was answered 8.6e-6 rad apart
    (the fold's flag on in one, off in the other) alone and among 19 others; Ferrari's
    formulas or eigenvalues were chosen by how many poses there were, the Fourier
    coefficients and FK were BLAS products rounded by the batch's size."""
    arm = with_base_tool(skew_quartic)
    rng = np.random.default_rng(42)
    q = np.concatenate([rng.uniform(-pi, pi, (40, 6)), near_singular_q(arm, rng, 4)])
    T0 = arm._world_to_base(arm.fk(q))
    solver = families6r.solver_for(arm)
    group = solver.solve(arm, T0[40:], None, labels=False)
    for k in range(len(q) - 40):
        alone = solver.solve(arm, T0[[40 + k]], None, labels=False)
        assert np.array_equal(alone.valid[0], group.valid[k])
        assert np.array_equal(alone.q[0], group.q[k], equal_nan=True), k
        for name, mask in alone.singular.items():
            assert np.array_equal(mask[0], group.singular[name][k]), (k, name)


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["standard", "modified"]))
def test_general_6r_random_tables_and_folds(seed, convention):
    """Fails before: 1e-10..6e-7 rad apart, and a solution kept alone but merged in a batch."""
    rng = np.random.default_rng(seed)
    arm = random_6r(rng, convention)
    q = np.concatenate([rng.uniform(-pi, pi, (6, 6)), near_fold_q(arm, rng, 6)])
    assert_alone_as_in_a_batch(arm, q, rng)


@settings(max_examples=20, deadline=None)
@given(spherical_wrist_arms(), st.integers(0, 2**32 - 1))
def test_spherical_wrist_random_tables_and_singular_poses(arm, seed):
    if "spherical wrist" not in rikin.ik.classify(arm).family:
        return  # degenerate draws (axes 1-2 or 2-3 the same line, ...)
    rng = np.random.default_rng(seed)
    q = np.concatenate([rng.uniform(-pi, pi, (4, 6)), near_singular_q(arm, rng, 2)])
    assert_alone_as_in_a_batch(arm, q, rng)


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["standard", "modified"]))
def test_three_parallel_axes_random_tables_and_folds(seed, convention):
    rng = np.random.default_rng(seed)
    arm = parallel_arm(rng, convention, 2, bool(seed % 2))
    q = np.concatenate([rng.uniform(-pi, pi, (6, 6)), near_fold_q(arm, rng, 6)])
    assert_alone_as_in_a_batch(arm, q, rng)


def test_ur5e_random_and_singular_poses():
    rng = np.random.default_rng(5)
    q = np.concatenate([rng.uniform(-pi, pi, (10, 6)), near_fold_q(ur5e(), rng, 10),
                        [[0.3, -1.0, 1.2, 0.4, 0.0, 0.5], [0.3, -1.0, 0.0, 0.4, 1.1, 0.5]]])
    assert_alone_as_in_a_batch(ur5e(), q, rng)


@pytest.mark.parametrize("make", [kr5, puma_standard, irb2400])
def test_a_pose_rounded_beyond_the_reach_is_moved_alike_alone_and_in_a_batch(make):
    """The nearest reachable pose (``_onto_reach``: a stretched arm's pose rounded 1e-12..1e-9
    of the arm's size beyond its reach) is the same alone and among 19 others, to the bit.
    Fails before: 1e-16 apart (products of ``(N, 3)`` by ``(3, 3)`` matrices by BLAS), which
    the fold of the stretched elbow then magnifies."""
    arm = with_base_tool(make)
    rng = np.random.default_rng(3)
    q = np.array([singular_q(arm, "stretched", rng) for _ in range(20)])
    T = arm.fk(q)
    out = wrist_centre(arm, q) - arm.joint_axes(q)[0][:, 1]
    out /= np.linalg.norm(out, axis=-1, keepdims=True)
    T[:, :3, 3] += out * 10.0 ** rng.uniform(-12, -9, (20, 1)) * arm.scale
    solver = families6r.solver_for(arm)
    T_near, dist, close = solver.nearest_reachable(arm, T)
    assert close.all() and (dist > 0).any()
    for k in range(len(T)):
        alone = solver.nearest_reachable(arm, T[[k]])
        assert np.array_equal(alone[0][0], T_near[k]), k
        assert alone[1][0] == dist[k] and alone[2][0] == close[k], k
