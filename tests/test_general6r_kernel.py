"""``arm.ik`` of one pose of a general 6R through the solver's ``single_kernel``
(rikin.ik.general6r_kernel): the result is the general path's (``arm.ik`` of the same
pose as a nested list, which takes the general path), bit for bit, on seeded random
poses of the Kinova Jaco and of random tables (both conventions, base and tool), and the
kernel declines (None) the poses the general path flags singular or cannot reach."""

import numpy as np
import pytest
from test_ik6r_families import random_6r

import rikin
from rikin import Link, SerialArm
from rikin.ik import families6r

pi = np.pi


def jaco():
    """roboticstoolbox's ``models.DH.Jaco`` table, joint 1 as typed (a general 6R here)."""
    s, s2 = np.sin(pi / 6), np.sin(pi / 3)
    d4b, d5b, d6b = 0.2073 + s / s2 * 0.0743, 2 * s / s2 * 0.0743, s / s2 * 0.0743 + 0.1687
    return SerialArm((
        Link(d=0.2755, alpha=pi / 2), Link(a=0.41, alpha=pi, offset=-pi / 2),
        Link(d=-0.0098, alpha=pi / 2, offset=pi / 2), Link(d=-d4b, alpha=pi / 3),
        Link(d=-d5b, alpha=pi / 3, offset=-pi), Link(d=-d6b, alpha=pi, offset=5 * pi / 9),
    ), name="Kinova Jaco", units="m")


def framed_random(seed, convention):
    arm = random_6r(np.random.default_rng(seed), convention)
    base = rikin.homogeneous(rikin.rotz(0.4) @ rikin.rotx(-0.2), [0.1, 0.3, -0.2])
    tool = rikin.homogeneous(rikin.roty(0.3), [0.02, -0.01, 0.15])
    return SerialArm(arm.links, convention=convention, base=base, tool=tool, name="framed")


ARMS = [jaco, lambda: random_6r(np.random.default_rng(31), "standard"),
        lambda: random_6r(np.random.default_rng(32), "modified"),
        lambda: framed_random(33, "standard")]


def assert_fast_equals_general(arm, T):
    """Returns whether the kernel took the pose; either way ``arm.ik(T)`` is the general
    path's result exactly (joints, labels, flags) and every solution reaches the pose."""
    out = families6r.solver_for(arm).single_kernel(arm).solve(T.tolist())
    fast, general = arm.ik(T), arm.ik(T.tolist())
    assert fast.labels == general.labels
    assert np.array_equal(fast.q, general.q)
    assert (fast.singular, fast.singularity) == (general.singular, general.singularity)
    F = arm.fk(fast.q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max(initial=0.0) <= 1e-9 * arm.scale
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max(initial=0.0) <= 1e-9
    if out is None:
        return False
    flat, branches = out
    assert np.array_equal(np.array(flat).reshape(-1, 6), fast.q)
    assert tuple(branches) == fast.branches
    assert not general.singular
    return True


@pytest.mark.parametrize("make", ARMS)
def test_fast_path_equals_general_on_random_poses(make):
    arm = make()
    assert str(rikin.ik.classify(arm)).startswith("general 6R")
    rng = np.random.default_rng(12)
    q = rng.uniform(-pi, pi, (40, 6))
    taken = 0
    for row, T in zip(q, arm.fk(q), strict=True):
        taken += assert_fast_equals_general(arm, T)
        res = arm.ik(T)
        assert np.abs(rikin.wrap_angle(res.q - row)).max(axis=1).min() < 1e-6  # q among them
    assert taken >= 38  # random poses are regular: the kernel takes nearly all


def test_kernel_declines_unreachable_and_singular_poses():
    arm = jaco()
    kernel = families6r.solver_for(arm).single_kernel(arm)
    far = arm.fk(np.full(6, 0.4))
    far[:3, 3] *= 10.0  # ten times out: no real root reaches it
    assert kernel.solve(far.tolist()) is None
    with pytest.raises(rikin.UnreachableError):
        arm.ik(far)
    # singular poses: joint 5 at 0 with joints 2, 3 at pi, the arm stretched
    singular = 0
    for q in ([0.3, pi, pi, 0.5, 0.0, 0.7], [0.2, 0.0, pi, 0.0, 0.0, 0.0]):
        T = arm.fk(np.array(q))
        general = arm.ik(T.tolist())
        if general.singular:
            singular += 1
            assert kernel.solve(T.tolist()) is None
        assert_fast_equals_general(arm, T)
    assert singular
