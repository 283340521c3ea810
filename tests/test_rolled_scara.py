"""The four-axis SCARA typed as a table (RRPR, or RRRP with the roll before the quill).

The SCARA of most labs turns its tool about the vertical with a fourth joint; rikin
refused it ("it has 4 joints, RRPR, and no course family has those"). Here: typed as a
student types it (text, mm, a data sheet's limits, joints counted the other way), every
solution reaches the target by FK (checked here with arm.fk), the generating joints are
among them, ik and ik_batch agree, a tilted tool is refused with the reason, a rounded
pose is solved for the nearest one the arm reaches, and the stretched elbow is flagged.
The numerical comparison (every solution ik_numerical_multistart finds is in the set) is
in tests/test_families.py with the other families.
"""

import re
from dataclasses import replace

import numpy as np
import pytest

import rikin
from rikin import InputError, Link, SerialArm, UnreachableError
from rikin.dhtext import arm_from_table
from rikin.ik import classify

pi = np.pi

#: A lab SCARA as its data sheet gives it (lengths in mm, limits in deg and mm), the
#: quill counted downwards and joint 4 the other way: what a student types.
TABLE = """
| joint | theta   | d (mm)   | a (mm) | alpha | min   | max  |
| 1     | q1      | 0        | 325    | 0     | -132  | 132  |
| 2     | q2      | 0        | 275    | 180   | -150  | 150  |
| 3     | 0       | d3       | 0      | 0     | 0     | 180  |
| 4     | q4      | 0        | 0      | 0     | -360  | 360  |
"""


def lab_scara():
    return arm_from_table(TABLE, name="lab SCARA")


def rrrp():
    return SerialArm((Link(d=0.4, a=0.35), Link(a=0.25, alpha=pi), Link(offset=0.3),
                      Link("P", d=0.05)), name="RRRP SCARA")


def reversed_arm(arm, joints):
    links = tuple(replace(lk, direction=-lk.direction) if i in joints else lk
                  for i, lk in enumerate(arm.links))
    return arm.replace(links=links)


def near(arm, Q, q, tol=1e-9):
    d = np.where(arm.revolute, np.abs(rikin.wrap_angle(Q - q)), np.abs(Q - q) / arm.scale)
    return d.max(axis=-1).min() <= tol


def random_q(arm, rng):
    q = rng.uniform(-pi, pi, arm.n)
    q[~arm.revolute] = rng.uniform(0.05, 0.3, int((~arm.revolute).sum())) * arm.scale
    return q


def _arms():
    base = rikin.homogeneous(rikin.rpy_to_r(0.02, -0.03, 0.4), np.array([0.1, 0.2, 0.3]))
    tool = rikin.homogeneous(rikin.rpy_to_r(0.3, -0.2, 0.5), np.array([0.02, 0.01, 0.05]))
    return {
        "lab (mm)": lab_scara(),
        "lab, base and tool": lab_scara().replace(base=base * [1, 1, 1, 1], tool=tool),
        "joints 1 and 4 reversed": reversed_arm(lab_scara(), (0, 3)),
        "RRRP": rrrp(),
        "RRRP, base, tool, joint 2 reversed": reversed_arm(rrrp(), (1,)).replace(
            base=base, tool=tool),
    }


@pytest.mark.parametrize("name", sorted(_arms()))
def test_every_solution_reaches_the_target_and_the_generating_joints_are_among_them(name):
    arm = _arms()[name]
    c = classify(arm)
    assert c.closed_form and c.family.startswith("four-axis SCARA") and c.solutions == 2
    rng = np.random.default_rng([4, len(name)])
    for _ in range(25):
        assert_both_elbows(arm, random_q(arm, rng), {"right", "left"})


def assert_both_elbows(arm, q, elbows):
    """arm.ik of the pose of ``q``: two solutions, each reaching it by FK, ``q`` among them,
    the two ``elbows`` labels, and ik_batch giving the same two."""
    T = arm.fk(q)
    res = arm.ik(T)
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * arm.scale
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= 1e-9
    assert near(arm, res.q, q), "the joints that made the pose are missing"
    assert len(res) == 2 and {b.elbow for b in res.branches} == elbows
    batch = arm.ik_batch(T[None])
    got = batch.q[0][batch.valid[0]]
    assert len(got) == 2 and all(near(arm, got, row) for row in res.q)


def test_the_data_sheets_limits_choose_among_the_solutions():
    """Joint 1's +-132 deg and the quill's 0-180 mm stroke as typed: within_limits keeps
    the elbow that fits them."""
    arm = lab_scara()
    assert arm.units == "mm" and arm.joint_types == "RRPR"
    q = np.array([np.radians(60), np.radians(100), 120.0, np.radians(200)])
    T = arm.fk(q)
    both = arm.ik(T)
    assert len(both) == 2 and near(arm, both.q, q)
    other = both.q[~np.isclose(both.q[:, 0], q[0])][0]
    assert abs(np.degrees(other[0])) > 132  # the other elbow turns joint 1 too far
    kept = arm.ik(T, within_limits=True)
    assert len(kept) == 1 and near(arm, kept.q, q)
    above = arm.fk(np.array([0.3, 0.5, -20.0, 0.1]))  # 20 mm above the quill's top
    assert len(arm.ik(above)) == 2
    none = arm.ik(above, within_limits=True)
    assert len(none) == 0 and none.discarded == 2


def test_a_tilted_tool_is_refused_saying_why():
    arm = lab_scara()
    T = arm.fk(np.array([0.3, 0.5, 50.0, 0.2]))
    T[:3, :3] = rikin.rotx(np.radians(0.5)) @ T[:3, :3]
    with pytest.raises(UnreachableError, match=r"turns its tool only about its vertical axes: "
                       r"the target tilts the tool's axis 0\.5 deg") as exc:
        arm.ik(T)
    assert exc.value.excess == pytest.approx(np.radians(0.5))


def test_out_of_reach_says_by_how_much():
    arm = lab_scara()  # links 325 + 275 mm
    T = rikin.transl(700.0, 0.0, -50.0)
    T[:3, :3] = rikin.rotx(pi)  # the tool down, as the table's twist makes it
    with pytest.raises(UnreachableError, match=r"100 mm beyond the reach of links 1-2"):
        arm.ik(T)


def test_rounded_poses_are_solved_for_the_nearest_reachable_one():
    """Rounded numbers are input: the pose printed to 4 decimals, a tool tilted 5e-5 rad
    by rounding, a roll axis 4e-5 of the size beyond the reach; 4e-3 rad is a tilt."""
    arm = SerialArm(lab_scara().links, units="mm")
    q = np.array([0.3, 0.5, 50.0, 0.2])
    T = arm.fk(q)
    res = arm.ik(np.round(T, 4))
    assert len(res) == 2 and near(arm, res.q, q, 1e-4)  # 4 decimals: ~5e-5 rad
    tilted = T.copy()
    tilted[:3, :3] = rikin.rotx(5e-5) @ T[:3, :3]
    res = arm.ik(tilted)
    assert len(res) == 2 and res.reach_distance == pytest.approx(5e-5 * arm.scale, rel=1e-6)
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * arm.scale
    batch = arm.ik_batch(tilted[None])
    assert batch.counts[0] == 2 and batch.reach_distance[0] == pytest.approx(res.reach_distance)
    stretched = rikin.transl(600.0 + 600.0 * 4e-5, 0.0, -50.0)
    stretched[:3, :3] = rikin.rotx(pi)
    res = arm.ik(stretched)
    assert res.singular and len(res) == 1
    assert res.reach_distance == pytest.approx(600.0 * 4e-5, rel=1e-6)
    tilted[:3, :3] = rikin.rotx(4e-3) @ T[:3, :3]
    with pytest.raises(UnreachableError, match="taken as rounded"):
        arm.ik(tilted)


def test_the_stretched_elbow_is_flagged_with_one_solution():
    arm = lab_scara()
    res = arm.ik(arm.fk(np.array([0.4, 0.0, 30.0, -1.0])))
    assert res.singular and len(res) == 1 and near(arm, res.q, [0.4, 0.0, 30.0, -1.0])


def test_near_misses_are_refused_with_the_reason():
    cases = {
        r"the roll axis \(joint 4\) is 2 deg from axis 1":
            SerialArm((Link(a=1.0), Link(a=1.0), Link("P", alpha=np.radians(2)), Link())),
        r"axes 1 and 2 are the same line":
            SerialArm((Link(), Link(a=1.0), Link("P"), Link())),
        r"the quill \(joint 4\) is 90 deg from axis 1":
            SerialArm((Link(a=1.0), Link(a=1.0), Link(alpha=pi / 2), Link("P"))),
    }
    for why, arm in cases.items():
        c = classify(arm)
        assert not c.closed_form and re.search(why, c.reason), c.reason
        with pytest.raises(InputError, match=why):
            arm.ik(arm.fk(np.array([0.1, 0.2, 0.3, 0.4])))
