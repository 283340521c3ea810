"""6R arms of every family typed from their DH tables, against solvers no one here wrote.

The oracles are in requirements.txt, so CI has them: a missing one fails this module's
import (it is not skipped).

* EAIK (``pip install eaik``, C++ IK by subproblem decomposition, Ostermeier et al. 2024):
  the solution sets of the UR arms (three parallel axes) and the Puma 560 (spherical
  wrist), on seeded random and near-singular poses.
* roboticstoolbox-python 1.5 (``pip install roboticstoolbox-python``): its model zoo's DH
  tables are read here as data (``rtb.models.DH.UR3/UR5/UR10/Puma560/Jaco/Mico``, with
  their offsets, and the joint 1 of Jaco and Mico counted the other way, ``flip``), its FK
  (``fkine``) checks every solution rikin returns, and its C++ Levenberg-Marquardt
  (``ik_LM``) from 300 random starts finds the solutions a general 6R has, which rikin's
  set must hold, and hold no more of (rikin's are FK-checked, so more would mean the
  numerical search missed some: the count must equal).
"""

from __future__ import annotations

import eaik.IK_DH
import numpy as np
import pytest
import roboticstoolbox as rtb

import rikin
from rikin import Link, SerialArm

pi = np.pi
SAME_Q = 1e-6  # rad: two closed-form solutions are one
LM_SAME_Q = 1e-4  # rad: ik_LM stops at tol 1e-12 on its own error measure (~1e-6 rad)
FK_TOL = 1e-9


def wrap(x):
    return (np.asarray(x) + pi) % (2 * pi) - pi


def from_rtb(robot):
    """A rikin arm with ``robot``'s DH table, base and tool, and the sign per joint that
    turns rikin's joint values into the robot's (-1 where the robot flips the joint)."""
    links = tuple(Link(d=L.d, a=L.a, alpha=L.alpha, offset=L.offset) for L in robot.links)
    sign = np.array([-1.0 if L.isflip else 1.0 for L in robot.links])
    arm = SerialArm(links, name=robot.name, units="m", base=robot.base.A, tool=robot.tool.A)
    return arm, sign


def ur_e(name, d1, a2, a3, d4, d5, d6):
    """A UR e-series arm from Universal Robots' published DH table ("DH parameters for
    calculations of kinematics and dynamics", universal-robots.com), standard DH, m."""
    return SerialArm((
        Link(d=d1, alpha=pi / 2), Link(a=a2), Link(a=a3), Link(d=d4, alpha=pi / 2),
        Link(d=d5, alpha=-pi / 2), Link(d=d6),
    ), name=name, units="m")


UR5E = ("UR5e", 0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996)
UR10E = ("UR10e", 0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655)


def eaik_robot(arm):
    """EAIK's robot of the same table (no offsets: EAIK's joints are rikin's th = q + offset)."""
    links = arm.links
    return eaik.IK_DH.DhRobot(np.array([L.alpha for L in links]), np.array([L.a for L in links]),
                              np.array([L.d for L in links]))


def same_sets(A, B, tol):
    """Every row of A has one of B within tol (modulo 2 pi), and the other way round."""
    if len(A) == 0 or len(B) == 0:
        return len(A) == len(B)
    gap = np.abs(wrap(A[:, None] - B[None])).max(-1)
    return bool((gap.min(1) <= tol).all() and (gap.min(0) <= tol).all())


def assert_fk_checked(arm, Q, T, fk):
    """Every solution ``Q (k, 6)`` of rikin reaches the flange pose T by the oracle's FK."""
    for q in Q:
        F = fk(q)
        assert np.abs(F[:3, 3] - T[:3, 3]).max() <= FK_TOL * arm.scale
        assert np.abs(F[:3, :3] - T[:3, :3]).max() <= FK_TOL


def poses_near_singular(rng, n):
    """Joint vectors: random, and 1e-4..1e-3 rad from the wrist (q5 = 0), the elbow
    (q3 = 0, stretched) and both (n each)."""
    q = rng.uniform(-pi, pi, size=(4 * n, 6))
    eps = rng.uniform(1e-4, 1e-3, size=(3 * n,)) * rng.choice([-1, 1], size=3 * n)
    q[n:2 * n, 4] = eps[:n]
    q[2 * n:3 * n, 2] = eps[n:2 * n]
    q[3 * n:, 2], q[3 * n:, 4] = eps[2 * n:], -eps[2 * n:]
    return q


# ------------------------------------------------------------------ UR family and Puma: EAIK
UR_ARMS = {
    "UR3": lambda: from_rtb(rtb.models.DH.UR3())[0],
    "UR5": lambda: from_rtb(rtb.models.DH.UR5())[0],
    "UR10": lambda: from_rtb(rtb.models.DH.UR10())[0],
    "UR5e": lambda: ur_e(*UR5E),
    "UR10e": lambda: ur_e(*UR10E),
    "Puma560": lambda: from_rtb(rtb.models.DH.Puma560())[0],
}


@pytest.mark.parametrize("name", list(UR_ARMS))
def test_solution_sets_equal_eaik(name):
    arm = UR_ARMS[name]().replace(base=np.eye(4), tool=np.eye(4))
    family = str(rikin.ik.classify(arm))
    if name.startswith("UR"):
        assert family.startswith("three parallel axes (2, 3, 4), like a UR arm: up to 8")
    robot = eaik_robot(arm)
    off = np.array([L.offset for L in arm.links])
    rng = np.random.default_rng(29)
    counts = []
    for q in poses_near_singular(rng, 10):
        T = arm.fk(q)
        ours = arm.ik(T).q
        sol = robot.IK(T)
        theirs = np.asarray(sol.Q)[~np.asarray(sol.is_LS, dtype=bool)] - off
        assert same_sets(ours, theirs, SAME_Q), (name, q, len(ours), len(theirs))
        assert np.abs(wrap(ours - q)).max(1).min() <= SAME_Q
        assert_fk_checked(arm, ours, T, lambda x: robot.fwdKin(x + off))
        counts.append(len(ours))
    assert max(counts) == 8


@pytest.mark.parametrize("name", ["UR5e", "UR10e", "UR3"])
def test_ur_with_base_tool_and_modified_dh(name):
    """The same arm with a base and a tool, and typed in modified DH (Craig): the solutions
    of a pose are those of its flange pose, FK-checked by EAIK."""
    arm = UR_ARMS[name]()
    base = rikin.homogeneous(rikin.rpy_to_r(0.3, -0.2, 1.1), [0.1, -0.4, 0.7])
    tool = rikin.homogeneous(rikin.rpy_to_r(-0.5, 0.1, 0.2), [0.02, 0.03, 0.15])
    dressed = arm.replace(base=base, tool=tool)
    L = arm.links  # the modified table: a and alpha one row down, the flange turned back
    mdh = SerialArm(
        tuple(Link(d=L[i].d, a=L[i - 1].a if i else 0.0, alpha=L[i - 1].alpha if i else 0.0)
              for i in range(6)),
        convention="modified", tool=rikin.homogeneous(rikin.rotx(L[5].alpha), [L[5].a, 0, 0]),
    )
    robot = eaik_robot(arm)
    rng = np.random.default_rng(5)
    for q in rng.uniform(-pi, pi, size=(10, 6)):
        T_flange = arm.fk(q)
        plain = arm.ik(T_flange).q
        with_tool = dressed.ik(base @ T_flange @ tool).q
        modified = mdh.ik(mdh.fk(q)).q
        assert np.allclose(mdh.fk(q), T_flange, atol=1e-12)
        sol = robot.IK(T_flange)
        theirs = np.asarray(sol.Q)[~np.asarray(sol.is_LS, dtype=bool)]
        for Q in (plain, with_tool, modified):
            assert same_sets(Q, theirs, SAME_Q), (len(Q), len(theirs))


# ------------------------------------------------------------------ numerical oracle
def lm_solutions(robot, T, rng, starts=300):
    """Distinct solutions roboticstoolbox's C++ ik_LM finds from ``starts`` random starts
    (as the robot counts joints), each within LM_SAME_Q of its group's first."""
    found = []
    for q0 in rng.uniform(-pi, pi, size=(starts, robot.n)):
        sol = robot.ik_LM(T, q0=q0, ilimit=60, slimit=1, tol=1e-12, joint_limits=False)
        if sol.success and not any(np.abs(wrap(sol.q - f)).max() <= LM_SAME_Q for f in found):
            found.append(np.array(sol.q))
    return np.array(found)


def check_against_lm(arm, sign, robot, q, rng):
    """rikin's solutions of FK(q) hold q, pass roboticstoolbox's FK, and are the solutions
    ik_LM finds from 300 starts, no more and no fewer."""
    T = arm.fk(q)
    res = arm.ik(T)
    ours = res.q * sign  # as the robot counts its joints
    assert np.abs(wrap(res.q - q)).max(1).min() <= SAME_Q
    T_robot = robot.fkine(q * sign).A
    assert np.allclose(T_robot, T, atol=1e-12)
    assert_fk_checked(arm, ours, T, lambda x: robot.fkine(x).A)
    theirs = lm_solutions(robot, T, rng)
    assert len(theirs) >= 2
    assert same_sets(ours, theirs, LM_SAME_Q), (len(ours), len(theirs))
    assert len(ours) == len(theirs)
    return len(ours)


@pytest.mark.parametrize("make", [rtb.models.DH.Jaco, rtb.models.DH.Mico])
def test_kinova_jaco_and_mico_from_the_model_zoo(make):
    robot = make()
    arm, sign = from_rtb(robot)
    assert sign[0] == -1  # the zoo counts joint 1 the other way
    assert "general 6R" in str(rikin.ik.classify(arm))
    rng = np.random.default_rng(60)
    for q in rng.uniform(-pi, pi, size=(2, 6)):
        check_against_lm(arm, sign, robot, q, rng)


def random_6r(rng, convention):
    """A 6R arm with random twists, lengths, offsets: no family but the general one."""
    links = tuple(
        Link(a=rng.uniform(-1, 1), d=rng.uniform(-1, 1), alpha=rng.uniform(-pi, pi),
             offset=rng.uniform(-pi, pi))
        for _ in range(6)
    )
    return SerialArm(links, convention=convention, name=f"random {convention} 6R", units="m")


def rtb_twin(arm):
    """roboticstoolbox's robot of the same table (standard or modified)."""
    kind = rtb.RevoluteDH if arm.convention == "standard" else rtb.RevoluteMDH
    return rtb.DHRobot([kind(d=L.d, a=L.a, alpha=L.alpha, offset=L.offset) for L in arm.links])


@pytest.mark.parametrize(("seed", "convention"), [(1, "standard"), (2, "standard"),
                                                   (3, "modified"), (4, "standard")])
def test_general_6r_random_table_against_multistart_lm(seed, convention):
    rng = np.random.default_rng(seed)
    arm = random_6r(rng, convention)
    assert str(rikin.ik.classify(arm)).startswith("general 6R: up to 16 solutions")
    robot = rtb_twin(arm)
    q = rng.uniform(-pi, pi, 6)
    check_against_lm(arm, np.ones(6), robot, q, rng)


def test_jaco_near_its_elbow_fold_holds_every_precise_lm_solution():
    """1e-2 rad from a fold of the elbow (found by golden-section search on the smallest
    singular value of roboticstoolbox's Jacobian), ik_LM converges slowly; each of its
    answers that reaches the pose to 1e-9 (by roboticstoolbox's FK) is one of rikin's."""
    robot = rtb.models.DH.Jaco()
    arm, sign = from_rtb(robot)
    q = np.random.default_rng(0).uniform(-pi, pi, 6)

    def smallest(v):
        qq = q.copy()
        qq[2] = v
        s = np.linalg.svd(robot.jacob0(qq * sign), compute_uv=False)
        return s[-1] / s[0]

    lo, hi = -3.13, -3.10
    for _ in range(60):
        m1, m2 = lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo)
        lo, hi = (lo, m2) if smallest(m1) < smallest(m2) else (m1, hi)
    assert smallest(lo) < 1e-6  # a fold
    q[2] = lo + 1e-2
    T = arm.fk(q)
    ours = arm.ik(T).q * sign
    assert_fk_checked(arm, ours, T, lambda x: robot.fkine(x).A)
    assert np.abs(wrap(ours - q * sign)).max(1).min() <= SAME_Q
    theirs = lm_solutions(robot, T, np.random.default_rng(1))
    precise = [t for t in theirs if np.abs(robot.fkine(t).A - T).max() <= 1e-9]
    assert precise
    gap = np.abs(wrap(np.array(precise)[:, None] - ours[None])).max(-1)
    assert (gap.min(1) <= LM_SAME_Q).all()
