"""The course families and reversed joints against roboticstoolbox, a solver no one here wrote.

roboticstoolbox-python is in requirements.txt (CI has it: a missing one fails this module's
import, it is not skipped). Its model zoo's DH tables are read here as data
(``rtb.models.DH.Stanford``, ``Planar3``, ``Jaco``, ``Mico``), its FK (``fkine``) checks
every solution rikin returns, and its C++ Levenberg-Marquardt (``ik_LM``), from 300 random
starts, finds the solutions; rikin's set must be exactly what it finds (rikin's are
FK-checked, so more would mean the numerical search missed some: the counts must equal),
the generating joints among them. Jaco and Mico count joint 1 the other way (``flip``): a
row with ``direction=-1`` gives the zoo's FK at the zoo's joint values.
"""

from __future__ import annotations

import numpy as np
import pytest
import roboticstoolbox as rtb

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
