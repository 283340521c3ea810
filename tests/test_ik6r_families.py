"""The 6R families beyond the spherical wrist, typed as DH tables (rikin.ik.families6r,
parallel3, general6r): seeded random tables of each family, every solution put back through
FK here, the generating joints among them; batch against one pose at a time; singular and
unreachable poses. The comparison with solvers no one here wrote is in
test_ik6r_oracles.py."""

from __future__ import annotations

import numpy as np
import pytest

import rikin
from rikin import Link, SerialArm
from rikin.errors import UnreachableError
from rikin.ik import families6r as families

pi = np.pi
SAME_Q = 1e-6


def wrap(x):
    return (np.asarray(x) + pi) % (2 * pi) - pi


def assert_reaches(arm, Q, T):
    F = arm.fk(Q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * max(arm.scale, 1.0)
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= 1e-9


def ur5e(**kw):
    return SerialArm((
        Link(d=0.1625, alpha=pi / 2), Link(a=-0.425), Link(a=-0.3922),
        Link(d=0.1333, alpha=pi / 2), Link(d=0.0997, alpha=-pi / 2), Link(d=0.0996),
    ), name="UR5e", units="m", **kw)


def parallel_arm(rng, convention, first, wrist_offset):
    """Random table with axes ``first``..``first + 2`` parallel (twists 0 or pi between
    them), random other twists, lengths and offsets; ``wrist_offset`` False keeps the
    point of axis 6 in one plane as joint 5 turns (a UR's a5 = 0)."""
    twist = list(rng.uniform(-pi, pi, 6))
    # the twist between axes i and i+1 is row i (standard) or row i+1 (modified), 1-based
    k = first - 1 if convention == "standard" else first
    twist[k] = rng.choice([0.0, pi])
    twist[k + 1] = rng.choice([0.0, pi])
    a = rng.uniform(-1, 1, 6)
    if not wrist_offset:  # the a between axes 5 and 6 (and first = 2 only)
        a[4 if convention == "standard" else 5] = 0.0
    links = tuple(Link(a=a[i], d=rng.uniform(-1, 1), alpha=twist[i],
                       offset=rng.uniform(-pi, pi)) for i in range(6))
    return SerialArm(links, convention=convention, name="parallel", units="m")


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize(("first", "wrist_offset"), [(2, False), (2, True), (3, True)])
def test_random_parallel_axes_tables(convention, first, wrist_offset):
    rng = np.random.default_rng(100 * first + wrist_offset + (convention == "modified"))
    for _ in range(4):
        arm = parallel_arm(rng, convention, first, wrist_offset)
        verdict = str(rikin.ik.classify(arm))
        assert verdict.startswith(f"three parallel axes ({first}, {first + 1}, {first + 2})")
        assert "up to 8 solutions" in verdict
        for q in rng.uniform(-pi, pi, size=(10, 6)):
            T = arm.fk(q)
            res = arm.ik(T)
            assert 1 <= len(res) <= 8
            assert_reaches(arm, res.q, T)
            assert np.abs(wrap(res.q - q)).max(1).min() <= SAME_Q


def test_ur5e_with_base_and_tool_every_solution_reaches():
    base = rikin.homogeneous(rikin.rotz(0.7), [0.2, 0.1, 0.3])
    tool = rikin.homogeneous(rikin.rotx(0.4), [0.0, 0.05, 0.12])
    arm = ur5e(base=base, tool=tool)
    rng = np.random.default_rng(3)
    for q in rng.uniform(-pi, pi, size=(20, 6)):
        T = arm.fk(q)
        res = arm.ik(T)
        assert_reaches(arm, res.q, T)
        assert np.abs(wrap(res.q - q)).max(1).min() <= SAME_Q
        assert len(set(res.labels)) == len(res)  # 8 branches, 8 labels


def test_ur5e_singular_poses_flagged_and_solved():
    arm = ur5e()
    for q, words in (([0.3, -1.0, 1.2, 0.4, 0.0, 0.5], "wrist singularity"),
                     ([0.3, -1.0, 0.0, 0.4, 1.1, 0.5], "stretched or folded")):
        T = arm.fk(np.array(q))
        res = arm.ik(T)
        assert res.singular and words in res.singularity
        assert_reaches(arm, res.q, T)


def test_ur5e_unreachable_says_by_how_much():
    arm = ur5e()
    T = arm.fk(np.zeros(6))
    T[0, 3] += 3.0
    with pytest.raises(UnreachableError) as err:
        arm.ik(T)
    assert "unreachable" in str(err.value)


def random_6r(rng, convention):
    links = tuple(Link(a=rng.uniform(-1, 1), d=rng.uniform(-1, 1), alpha=rng.uniform(-pi, pi),
                       offset=rng.uniform(-pi, pi)) for _ in range(6))
    return SerialArm(links, convention=convention, name="random 6R", units="m")


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_general_6r_random_tables(convention):
    rng = np.random.default_rng(7 if convention == "standard" else 8)
    for _ in range(3):
        arm = random_6r(rng, convention)
        assert str(rikin.ik.classify(arm)).startswith("general 6R: up to 16 solutions, by "
                                                      "elimination to an eigenvalue problem")
        for q in rng.uniform(-pi, pi, size=(6, 6)):
            T = arm.fk(q)
            res = arm.ik(T)
            assert len(res) % 2 == 0 and 2 <= len(res) <= 16  # real roots come in pairs
            assert_reaches(arm, res.q, T)
            assert np.abs(wrap(res.q - q)).max(1).min() <= SAME_Q


@pytest.mark.parametrize("make", [ur5e, lambda: random_6r(np.random.default_rng(9), "standard")])
def test_batch_holds_the_solutions_of_one_pose_at_a_time(make):
    arm = make()
    rng = np.random.default_rng(11)
    Ts = arm.fk(rng.uniform(-pi, pi, size=(8, 6)))
    batch = arm.ik_batch(Ts)
    for n, T in enumerate(Ts):
        one = arm.ik(T).q
        got = batch.q[n][batch.valid[n]]
        assert_reaches(arm, got, T)
        gap = np.abs(wrap(one[:, None] - got[None])).max(-1)
        assert (gap.min(1) <= SAME_Q).all() and (gap.min(0) <= SAME_Q).all()


def test_one_path_from_a_table_to_its_solver():
    """solve, solve_batch and classify find a typed arm's solver by one ordered registry:
    the course families (rikin.ik.families, registered once) first, then the 6R families;
    what solver_for builds is what arm.ik uses."""
    from rikin.ik import api
    from rikin.ik import families as course

    assert families.BEFORE == [course._course_match]
    scara = SerialArm((Link(d=0.4, a=0.35), Link(a=0.25, alpha=pi), Link("P")))
    for arm, family in ((scara, "SCARA"), (ur5e(), "three parallel axes"),
                        (kr5(), "6R with a spherical wrist")):
        assert str(rikin.ik.classify(arm)).startswith(family)
        assert api._solver(arm) is families.solver_for(arm)
    assert families.solver_for(scara) is course.family_of(scara).solver


def test_families_in_order_and_an_arm_outside_all_says_why():
    assert [f.name for f in families.FAMILIES] == [
        "spherical wrist", "three parallel axes", "general 6R"]
    # a UR5e with axis 1 parallel to axes 2-4: every family says why not
    links = (Link(d=0.1625),) + ur5e().links[1:]
    verdict = rikin.ik.classify(SerialArm(links))
    assert not verdict.closed_form
    assert "axis 1 is parallel to them too" in verdict.reason
    assert "degenerates" in verdict.reason


def test_classify_says_how_many_solutions_each_6r_family_gives():
    """classify's count (issue 29, Wanted 5): 8 for a spherical wrist and three parallel
    axes, 16 for the general 6R, and a pose of each has no more."""
    rng = np.random.default_rng(16)
    for arm, most in ((kr5(), 8), (ur5e(), 8), (random_6r(rng, "standard"), 16),
                      (random_6r(rng, "modified"), 16)):
        verdict = rikin.ik.classify(arm)
        assert verdict.closed_form and verdict.solutions == most, str(verdict)
        assert f"up to {most} solutions" in verdict.family
        for q in rng.uniform(-pi, pi, size=(3, 6)):
            assert 1 <= len(arm.ik(arm.fk(q))) <= most


def kr5():
    return SerialArm((
        Link(d=0.4, a=0.18, alpha=pi / 2), Link(a=0.6), Link(a=0.12, alpha=pi / 2),
        Link(d=-0.62, alpha=-pi / 2), Link(alpha=pi / 2), Link(d=-0.115, alpha=pi),
    ), name="KUKA KR5", units="m")


@pytest.mark.parametrize("make", [ur5e, kr5])
def test_elimination_agrees_with_the_closed_forms(make):
    """The general 6R solver, given an arm a closed form takes (three parallel axes, a
    spherical wrist), finds the same solution sets: two methods that share nothing but the
    polish."""
    from rikin.ik.general6r import General6RSolver

    arm = make()
    general = General6RSolver(arm)
    rng = np.random.default_rng(12)
    for q in rng.uniform(-pi, pi, size=(10, 6)):
        T = arm.fk(q)
        closed = arm.ik(T).q
        raw = general.solve(arm, T[None], None)
        mine = raw.q[0][raw.valid[0]]
        gap = np.abs(wrap(closed[:, None] - mine[None])).max(-1)
        assert (gap.min(1) <= SAME_Q).all() and (gap.min(0) <= SAME_Q).all()


def test_ur5e_batch_flags_singular_poses_and_holds_their_solutions():
    arm = ur5e()
    rng = np.random.default_rng(13)
    Q = rng.uniform(-pi, pi, size=(6, 6))
    Q[1, 4] = 0.0  # wrist singular
    Q[3, 2] = 0.0  # elbow stretched
    Ts = arm.fk(Q)
    batch = arm.ik_batch(Ts)
    assert batch.singular.tolist() == [False, True, False, True, False, False]
    for n, T in enumerate(Ts):
        got = batch.q[n][batch.valid[n]]
        assert_reaches(arm, got, T)
        assert np.abs(wrap(got - Q[n])).max(1).min() <= SAME_Q or n in (1, 3)


def test_ur5e_on_and_near_the_wrist_singularity_every_pose_solved():
    """q5 = 0 or pi, and 1e-9..1e-6 rad off: the pose is reached, and the generating q is
    among the solutions (on the singularity: one with its q1 and q5, as q6 is free there).
    A free joint 6 must be one joints 2-4 can follow, and 1e-7 off the singularity joint 6
    is not free (both refused such poses as unreachable)."""
    arm = ur5e()
    rng = np.random.default_rng(4)
    for k in range(120):
        q = rng.uniform(-pi, pi, 6)
        q[4] = rng.choice([0.0, pi]) + (0.0 if k % 3 == 0 else rng.choice([-1, 1])
                                        * 10.0 ** rng.uniform(-9, -6))
        T = arm.fk(q)
        res = arm.ik(T)
        assert_reaches(arm, res.q, T)
        gap = np.abs(wrap(res.q - q))
        if res.singular and "wrist" in res.singularity:
            assert gap[:, [0, 4]].max(1).min() <= SAME_Q
        else:
            assert gap.max(1).min() <= SAME_Q


@pytest.mark.parametrize("error", [1e-7, 1e-3])
def test_a_solution_that_misses_is_never_handed_back(monkeypatch, error):
    """The general path's last FK check (the one-pose path's stricter check first, each
    solution's error where that is not met) refuses a solver's answer that misses."""
    from rikin.ik.general6r import General6RSolver

    arm = random_6r(np.random.default_rng(9), "standard")
    T = arm.fk(np.random.default_rng(4).uniform(-pi, pi, 6))
    assert len(arm.ik(T)) >= 2
    solve = General6RSolver.solve

    def off_by(self, *args, **kwargs):
        raw = solve(self, *args, **kwargs)
        raw.q[0, np.flatnonzero(raw.valid[0])[-1], 2] += error
        return raw

    monkeypatch.setattr(General6RSolver, "solve", off_by)
    with pytest.raises(RuntimeError, match="rikin bug"):
        arm.ik(T)
