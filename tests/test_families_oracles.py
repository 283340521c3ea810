"""The course families and reversed joints against roboticstoolbox, a solver no one here wrote.

roboticstoolbox-python is in requirements.txt (CI has it: a missing one fails this module's
import, it is not skipped). Its model zoo's DH tables are read here as data
(``rtb.models.DH.Stanford``, ``Planar3``, ``Jaco``, ``Mico``), its FK (``fkine``) checks
every solution rikin returns, and its C++ Levenberg-Marquardt (``ik_LM``), from 300 random
starts, finds the solutions; rikin's set must be exactly what it finds (rikin's are
FK-checked, so more would mean the numerical search missed some: the counts must equal),
the generating joints among them. Jaco and Mico count joint 1 the other way (``flip``): a
row with ``direction=-1`` gives the zoo's FK at the zoo's joint values.

Seeded property tests: every course family of ``test_families`` typed with random lengths,
base and tool (standard and modified DH), each joint reversed at random, becomes a
roboticstoolbox ``DHRobot`` (``flip`` for a reversed joint) whose FK must be rikin's and
whose ik_LM must find exactly rikin's solutions; the UR arms (the zoo's UR3/5/10, UR's
published UR3e/5e/10e/16e tables) likewise against EAIK's closed form (C++, Ostermeier et
al. 2024), whose solutions of the flange pose are rikin's in DH joint values.
"""

from __future__ import annotations

from dataclasses import replace

import eaik.IK_DH
import numpy as np
import pytest
import roboticstoolbox as rtb
from spatialmath import SE3
from test_families import FAMILIES, MODIFIED, random_q, target, typed

import rikin
from rikin import Link, SerialArm

pi = np.pi
SAME_Q = 1e-6
LM_SAME_Q = 1e-4  # rad (or relative length): ik_LM stops at tol 1e-12 on its own measure
FK_TOL = 1e-9


def close(A, B, revolute, tol):
    """Every row of A has one of B within tol (revolute joints modulo 2 pi)."""
    d = np.abs(A[:, None] - B[None])
    d = np.where(revolute, np.abs((d + pi) % (2 * pi) - pi), d)
    return bool((d.max(-1).min(1) <= tol).all())


def from_zoo(robot):
    """The rikin arm of a model zoo robot's DH table, flips as ``direction=-1``."""
    links = []
    for L in robot.links:
        kw = dict(a=L.a, alpha=L.alpha, offset=L.offset, direction=-1 if L.isflip else 1)
        links.append(Link(d=L.d, **kw) if L.isrevolute else Link("P", theta=L.theta, **kw))
    return SerialArm(tuple(links), base=robot.base.A, tool=robot.tool.A, units="m",
                     name=robot.name)


def lm_solutions(robot, T, rng, revolute, mask=None, starts=300):
    found = []
    for q0 in rng.uniform(-pi, pi, size=(starts, robot.n)):
        q0[~revolute] = rng.uniform(0.1, 1.0, int((~revolute).sum()))
        sol = robot.ik_LM(T, q0=q0, ilimit=60, slimit=1, tol=1e-12, joint_limits=False,
                          mask=mask)
        if sol.success and not (found and close(np.array([sol.q]), np.array(found),
                                                revolute, LM_SAME_Q)):
            found.append(np.array(sol.q))
    return np.array(found)


def check(arm, robot, q, rng, mask=None, target=lambda T: T):
    T = arm.fk(q)
    assert np.allclose(robot.fkine(q).A, T, atol=1e-12)  # the same arm, the same q
    res = arm.ik(target(T))
    assert close(q[None], res.q, arm.revolute, SAME_Q)
    for row in res.q:
        F = robot.fkine(row).A
        w = np.ones(6) if mask is None else np.asarray(mask)
        assert np.abs(F[:3, 3] - T[:3, 3]).max() * w[:3].max() <= FK_TOL * arm.scale
        if w[3:].all():
            assert np.abs(F[:3, :3] - T[:3, :3]).max() <= FK_TOL
    theirs = lm_solutions(robot, T, rng, arm.revolute, mask)
    assert len(theirs) >= 2
    assert close(theirs, res.q, arm.revolute, LM_SAME_Q)
    assert close(res.q, theirs, arm.revolute, LM_SAME_Q)
    assert len(res) == len(theirs)
    return len(res)


def test_the_stanford_arm_of_the_model_zoo_gets_every_solution_ik_lm_finds():
    robot = rtb.models.DH.Stanford()
    arm = from_zoo(robot)
    assert arm.solver is None and arm.joint_types == "RRPRRR"
    assert rikin.ik.classify(arm).family.startswith("spherical (polar) arm with a spherical "
                                                    "wrist (as on the Stanford arm")
    rng = np.random.default_rng(70)
    counts = []
    for _ in range(3):
        q = rng.uniform(-pi, pi, 6)
        q[2] = rng.uniform(0.3048, 1.27)  # the boom within its stroke
        counts.append(check(arm, robot, q, rng))
    assert max(counts) == 8


def test_the_planar_3r_of_the_model_zoo_gets_every_solution_ik_lm_finds():
    robot = rtb.models.DH.Planar3()
    arm = from_zoo(robot)
    assert rikin.ik.classify(arm).family.startswith("planar 3R")
    rng = np.random.default_rng(71)
    for _ in range(3):
        q = rng.uniform(-pi, pi, 3)
        assert check(arm, robot, q, rng, mask=[1, 1, 0, 0, 0, 1]) == 2


@pytest.mark.parametrize("modified", [False, True])
def test_a_scara_typed_as_a_table_gets_every_solution_ik_lm_finds(modified):
    """The exercises' SCARA (standard DH) and the same arm in modified DH, as roboticstoolbox
    builds them from the same rows."""
    if modified:
        rows = [rtb.RevoluteMDH(d=0.4), rtb.RevoluteMDH(a=0.35),
                rtb.PrismaticMDH(a=0.25, alpha=pi)]
        arm = SerialArm((Link(d=0.4), Link(a=0.35), Link("P", a=0.25, alpha=pi)),
                        convention="modified")
    else:
        rows = [rtb.RevoluteDH(d=0.4, a=0.35), rtb.RevoluteDH(a=0.25, alpha=pi),
                rtb.PrismaticDH()]
        arm = SerialArm((Link(d=0.4, a=0.35), Link(a=0.25, alpha=pi), Link("P")))
    robot = rtb.DHRobot(rows)
    assert rikin.ik.classify(arm).family.startswith("SCARA")
    rng = np.random.default_rng(72)
    for _ in range(3):
        q = np.array([rng.uniform(-pi, pi), rng.uniform(0.3, 2.8) * rng.choice([-1, 1]),
                      rng.uniform(0.1, 0.3)])
        assert check(arm, robot, q, rng, mask=[1, 1, 1, 0, 0, 0],
                     target=lambda T: T[:3, 3]) == 2


@pytest.mark.parametrize("make", [rtb.models.DH.Jaco, rtb.models.DH.Mico])
def test_a_flipped_joint_of_the_model_zoo_is_a_row_with_direction_minus_one(make):
    """The zoo counts Jaco's and Mico's joint 1 the other way: typed with direction=-1, rikin's
    FK is the zoo's at the same joint values, and every IK solution passes the zoo's FK."""
    robot = make()
    arm = from_zoo(robot)
    assert arm.reversed_joints == (1,)
    rng = np.random.default_rng(73)
    for q in rng.uniform(-pi, pi, size=(5, 6)):
        T = robot.fkine(q).A
        assert np.abs(arm.fk(q) - T).max() < 1e-12
        res = arm.ik(T)
        assert close(q[None], res.q, arm.revolute, SAME_Q)
        for row in res.q:
            F = robot.fkine(row).A
            assert np.abs(F[:3, 3] - T[:3, 3]).max() <= FK_TOL * arm.scale
            assert np.abs(F[:3, :3] - T[:3, :3]).max() <= FK_TOL


# ------------------------------------------------------------------ seeded property tests
def to_rtb(arm):
    """roboticstoolbox's DHRobot of a rikin arm: the same rows, ``flip`` where rikin's
    direction is -1, a prismatic joint's fixed d moved into rtb's offset (rtb's d = q +
    offset), rikin's base and tool."""
    modified = arm.convention == "modified"
    rows = []
    for L in arm.links:
        flip = L.direction < 0
        if L.is_revolute:
            make = rtb.RevoluteMDH if modified else rtb.RevoluteDH
            rows.append(make(d=L.d, a=L.a, alpha=L.alpha, offset=L.offset, flip=flip))
        else:
            make = rtb.PrismaticMDH if modified else rtb.PrismaticDH
            rows.append(make(theta=L.theta, a=L.a, alpha=L.alpha, offset=L.d + L.offset,
                             flip=flip))
    return rtb.DHRobot(rows, base=SE3(arm.base, check=False), tool=SE3(arm.tool, check=False))


def reversed_at_random(arm, rng):
    """The arm with each joint's direction -1 or +1 at random (at least one -1)."""
    s = rng.choice([-1, 1], arm.n)
    s[rng.integers(arm.n)] = -1
    return arm.replace(links=tuple(replace(L, direction=int(x)) for L, x in zip(arm.links, s,
                                                                                strict=True)))


def lm_flange_solutions(arm, T, rng, position, starts=200):
    """The distinct solutions ik_LM finds of the world target ``T`` from ``starts`` random
    starts, on rtb's arm without base and tool solving for the flange pose (ik_LM drops a
    DHRobot's tool), each checked by the full arm's fkine."""
    bare = to_rtb(arm.replace(base=np.eye(4), tool=np.eye(4)))
    T_0 = np.linalg.inv(arm.base) @ T
    if not position:
        T_0 = T_0 @ np.linalg.inv(arm.tool)
    slides = ~arm.revolute
    mask = [1, 1, 1, 0, 0, 0] if position else None
    found = []
    for q0 in rng.uniform(-pi, pi, size=(starts, arm.n)):
        q0[slides] = rng.uniform(-1.0, 1.0, int(slides.sum())) * arm.scale
        sol = bare.ik_LM(T_0, q0=q0, ilimit=60, slimit=1, tol=1e-12, joint_limits=False,
                         mask=mask)
        if sol.success:  # polished: near a singular pose 1e-12 leaves 1e-3 rad of slack
            sol = bare.ik_LM(T_0, q0=sol.q, ilimit=100, slimit=1, tol=1e-20,
                             joint_limits=False, mask=mask)
        if sol.success and not (found and close(np.array([sol.q]), np.array(found),
                                                arm.revolute, LM_SAME_Q)):
            found.append(np.array(sol.q))
    return np.array(found)


#: The joint whose DH angle 0 is a singular configuration of each family's typed table:
#: the elbow stretched (planar, angular, SCARA) or the wrist's axes 4 and 6 in line.
SINGULAR_JOINT = {"planar 2R": 1, "planar 3R": 1, "angular 3R": 2, "SCARA": 1,
                  "SCARA with a wrist": 4, "cylindrical with a wrist": 4, "Stanford": 4,
                  "cartesian with a wrist": 4}


def near_singular_q(arm, name, rng):
    """Random joints, but the family's singular joint 2e-3..1e-2 rad from DH angle 0 (in
    the data sheet's count: ``q = direction * (theta - offset)``)."""
    q = random_q(arm, rng)
    j = SINGULAR_JOINT[name]
    theta = rng.uniform(2e-3, 1e-2) * rng.choice([-1, 1])
    q[j] = arm.links[j].direction * (theta - arm.links[j].offset)
    return q


@pytest.mark.parametrize(("name", "modified"), [(n, False) for n in sorted(FAMILIES)]
                         + [(n, True) for n in MODIFIED])
def test_course_family_with_reversed_joints_base_and_tool_matches_ik_lm(name, modified):
    """Each course family typed at random (lengths, base, tool, reversed joints), at a
    random pose and, where the family has one, 2e-3..1e-2 rad from a singular one: rikin's
    FK is roboticstoolbox's at the same joint values, every solution (one pose at a time
    and in a batch) passes rtb's fkine, and the set is what ik_LM finds from 200 starts."""
    rng = np.random.default_rng([29, len(name), int(modified), sum(map(ord, name))])
    position = FAMILIES[name][3] == "position"
    for k in range(3 if name in SINGULAR_JOINT else 2):
        arm = reversed_at_random(typed(name, rng, modified), rng)
        robot = to_rtb(arm)
        assert rikin.ik.classify(arm).family.startswith(FAMILIES[name][1])
        q = near_singular_q(arm, name, rng) if k == 2 else random_q(arm, rng)
        T = arm.fk(q)
        assert np.abs(robot.fkine(q).A - T).max() <= 1e-12 * max(1.0, arm.scale)
        res = arm.ik(target(arm, T, name))
        assert close(q[None], res.q, arm.revolute, SAME_Q)
        for row in res.q:
            F = robot.fkine(row).A
            assert np.abs(F[:3, 3] - T[:3, 3]).max() <= FK_TOL * arm.scale
            if not position:
                assert np.abs(F[:3, :3] - T[:3, :3]).max() <= FK_TOL
        batch = arm.ik_batch(T[None])
        got = batch.q[0][batch.valid[0]]
        assert len(got) == len(res) and close(got, res.q, arm.revolute, SAME_Q)
        theirs = lm_flange_solutions(arm, T, rng, position)
        assert len(theirs) == len(res) == FAMILIES[name][2]
        assert close(theirs, res.q, arm.revolute, LM_SAME_Q)
        assert close(res.q, theirs, arm.revolute, LM_SAME_Q)


def ur_table(d1, a2, a3, d4, d5, d6, name):
    """A UR arm from Universal Robots' published standard DH table, m."""
    return SerialArm((Link(d=d1, alpha=pi / 2), Link(a=a2), Link(a=a3), Link(d=d4, alpha=pi / 2),
                      Link(d=d5, alpha=-pi / 2), Link(d=d6)), name=name, units="m")


def zoo_table(robot):
    return SerialArm(tuple(Link(d=L.d, a=L.a, alpha=L.alpha, offset=L.offset)
                           for L in robot.links), name=robot.name, units="m")


#: The UR arms: the zoo's CB3 tables, and the e-series as Universal Robots publishes them
#: ("DH parameters for calculations of kinematics and dynamics", universal-robots.com).
UR = {
    "UR3": lambda: zoo_table(rtb.models.DH.UR3()),
    "UR5": lambda: zoo_table(rtb.models.DH.UR5()),
    "UR10": lambda: zoo_table(rtb.models.DH.UR10()),
    "UR3e": lambda: ur_table(0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921, "UR3e"),
    "UR5e": lambda: ur_table(0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996, "UR5e"),
    "UR10e": lambda: ur_table(0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655, "UR10e"),
    "UR16e": lambda: ur_table(0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655, "UR16e"),
}


@pytest.mark.parametrize("name", list(UR))
def test_ur_arm_with_reversed_joints_base_and_tool_matches_eaik(name):
    """A UR arm typed with random reversed joints, base and tool: every solution passes
    rtb's fkine (with its flips), one pose at a time and in a batch, and the set, in DH joint
    values, is EAIK's set of the flange pose."""
    rng = np.random.default_rng([29, sum(map(ord, name))])
    plain = UR[name]()
    solver = eaik.IK_DH.DhRobot(np.array([L.alpha for L in plain.links]),
                                np.array([L.a for L in plain.links]),
                                np.array([L.d for L in plain.links]))
    off = np.array([L.offset for L in plain.links])
    counts = []
    for _ in range(3):
        arm = reversed_at_random(plain, rng).replace(
            base=rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-pi, pi, 3)),
                                   rng.uniform(-1, 1, 3)),
            tool=rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-pi, pi, 3)),
                                   rng.uniform(-0.2, 0.2, 3)))
        verdict = rikin.ik.classify(arm)
        assert str(verdict).startswith("three parallel axes (2, 3, 4)") and verdict.solutions == 8
        robot = to_rtb(arm)
        s = arm.directions
        for q in rng.uniform(-pi, pi, size=(4, 6)):
            T = arm.fk(q)
            assert np.abs(robot.fkine(q).A - T).max() <= 1e-12
            res = arm.ik(T)
            assert close(q[None], res.q, arm.revolute, SAME_Q)
            for row in res.q:
                F = robot.fkine(row).A
                assert np.abs(F[:3, 3] - T[:3, 3]).max() <= FK_TOL * arm.scale
                assert np.abs(F[:3, :3] - T[:3, :3]).max() <= FK_TOL
            sol = solver.IK(np.linalg.inv(arm.base) @ T @ np.linalg.inv(arm.tool))
            theirs = np.asarray(sol.Q)[~np.asarray(sol.is_LS, dtype=bool)] - off
            ours = res.q * s  # the DH joint values EAIK uses
            assert len(ours) == len(theirs)
            assert close(ours, theirs, arm.revolute, SAME_Q)
            assert close(theirs, ours, arm.revolute, SAME_Q)
            batch = arm.ik_batch(T[None])
            got = batch.q[0][batch.valid[0]]
            assert len(got) == len(res) and close(got, res.q, arm.revolute, SAME_Q)
            counts.append(len(ours))
    assert max(counts) == 8
