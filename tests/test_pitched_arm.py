"""The four-axis articulated arm typed as a table: a waist, then three parallel pitch axes.

The small arms of teaching labs (ROBOTIS' OpenManipulator-X and the like) were refused
("it has 4 joints, RRRR, and no course family has those"). Here, typed as a student types
the data sheet's table: every solution reaches the target by FK (checked here with
arm.fk), the generating joints are among them, the elbows are labelled up and down, ik
and ik_batch agree, with base, tool and joints counted the other way; a target whose pitch
axis is not level, or off the arm's plane, or beyond reach is refused with the reason; a
rounded pose is solved for the nearest reachable one. The comparison with numerical IK
from many starts is in tests/test_families.py with the other families.
"""

import re
from dataclasses import replace

import numpy as np
import pytest
from test_rolled_scara import assert_both_elbows

import rikin
from rikin import InputError, Link, SerialArm, UnreachableError
from rikin.dhtext import arm_from_table
from rikin.ik import classify

pi = np.pi

#: The OpenManipulator-X as its manual's DH table gives it (the shoulder's 24 mm step makes
#: the 0.130 link and the +-79.38 deg offsets), typed with rounded degrees.
OMX_TABLE = """
| joint | theta        | d     | a     | alpha |
| 1     | q1           | 0.077 | 0     | 90    |
| 2     | q2 - 79.38   | 0     | 0.130 | 0     |
| 3     | q3 + 79.38   | 0     | 0.124 | 0     |
| 4     | q4           | 0     | 0.126 | 0     |
"""


def omx():
    return arm_from_table(OMX_TABLE, units="m", name="OpenManipulator-X")


def near(arm, Q, q, tol=1e-9):
    return np.abs(rikin.wrap_angle(Q - q)).max(axis=-1).min() <= tol


def _about(axis, angle):
    """The rotation by ``angle`` about ``axis`` (Rodrigues)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def _arms():
    base = rikin.homogeneous(rikin.rpy_to_r(0.02, -0.03, 0.4), np.array([0.1, 0.2, 0.3]))
    tool = rikin.homogeneous(rikin.rpy_to_r(0.3, -0.2, 0.5), np.array([0.02, 0.01, 0.05]))
    flipped = tuple(replace(lk, direction=-1) if i in (1, 3) else lk
                    for i, lk in enumerate(omx().links))
    return {
        "OpenManipulator-X": omx(),
        "with base and tool": omx().replace(base=base, tool=tool),
        "joints 2 and 4 reversed": omx().replace(links=flipped),
    }


@pytest.mark.parametrize("name", sorted(_arms()))
def test_every_solution_reaches_the_target_and_the_generating_joints_are_among_them(name):
    arm = _arms()[name]
    c = classify(arm)
    assert c.closed_form and c.family.startswith("four-axis articulated arm")
    assert c.solutions == 2
    rng = np.random.default_rng([5, len(name)])
    for _ in range(25):
        assert_both_elbows(arm, rng.uniform(-pi, pi, 4), {"up", "down"})


def test_the_elbow_up_solution_has_its_elbow_above_the_shoulder_wrist_line():
    """The label is the geometry: at a pose in front of the arm with the tool level, the
    'up' solution's elbow (axis 3) is higher than the line from the shoulder to axis 4."""
    arm = omx()
    q = np.radians([20.0, -10.0, 30.0, -20.0])
    res = arm.ik(arm.fk(q))
    for row, branch in zip(res.q, res.branches, strict=True):
        F = arm.fk(row, frames=True)
        shoulder, elbow, wrist = F[1, :3, 3], F[2, :3, 3], F[3, :3, 3]
        d = wrist - shoulder
        up = np.array([0.0, 0.0, 1.0]) - (d[2] / (d @ d)) * d  # vertical, across the line
        assert ((elbow - shoulder) @ up > 0) == (branch.elbow == "up")


def test_targets_out_of_reach_say_why():
    arm = omx()
    T = arm.fk(np.radians([10.0, 20.0, 30.0, 40.0]))
    pitch = arm.fk(np.radians([10.0, 20.0, 30.0, 40.0]), frames=True)[3, :3, 2]  # axis 4
    tilted = T.copy()  # turned 3 deg about the level line across the pitch axis
    tilted[:3, :3] = _about(np.cross(pitch, [0.0, 0.0, 1.0]), np.radians(3.0)) @ T[:3, :3]
    with pytest.raises(UnreachableError, match=r"keeps the tool's pitch axis level: the target "
                       r"tilts it 3 deg") as exc:
        arm.ik(tilted)
    assert exc.value.excess == pytest.approx(np.radians(3.0), rel=1e-9)
    aside = T.copy()  # moved 0.05 along axis 4 (across the arm's plane), orientation kept
    aside[:3, 3] += 0.05 * pitch
    with pytest.raises(UnreachableError, match=r"0\.05 m off the plane joints 2-3 move it in"):
        arm.ik(aside)
    far = T.copy()
    far[:3, 3] *= 3.0
    with pytest.raises(UnreachableError, match=r"beyond the reach of links 2-3"):
        arm.ik(far)


def test_rounded_poses_are_solved_for_the_nearest_reachable_one():
    arm = omx()
    q = np.radians([10.0, 20.0, 30.0, 40.0])
    T = arm.fk(q)
    res = arm.ik(np.round(T, 4))  # the pose printed with 4 decimals
    # 5e-5 m of rounding over links of 0.12-0.13 m: a few 1e-4 rad per joint
    assert len(res) == 2 and near(arm, res.q, q, 1e-3)
    pitch = arm.fk(q, frames=True)[3, :3, 2]
    level_line = np.cross(pitch, [0.0, 0.0, 1.0])
    tilted = T.copy()  # the pitch axis tilted 5e-5 rad by rounding
    tilted[:3, :3] = _about(level_line, 5e-5) @ T[:3, :3]
    res = arm.ik(tilted)
    assert len(res) == 2 and res.reach_distance == pytest.approx(5e-5 * arm.scale, rel=1e-6)
    assert near(arm, res.q, q, 1e-9)  # levelled about the flange: the pose that was typed
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - tilted[:3, 3]).max() <= 1e-4 * arm.scale
    batch = arm.ik_batch(tilted[None])
    assert batch.counts[0] == 2 and batch.reach_distance[0] == pytest.approx(res.reach_distance)
    tilted[:3, :3] = _about(level_line, 4e-3) @ T[:3, :3]
    with pytest.raises(UnreachableError, match="taken as rounded"):
        arm.ik(tilted)


def test_the_stretched_elbow_is_flagged_with_one_solution():
    arm = SerialArm((Link(d=0.1, alpha=pi / 2), Link(a=0.2), Link(a=0.2), Link(a=0.05)))
    q = np.array([0.4, 0.7, 0.0, -0.3])
    res = arm.ik(arm.fk(q))
    assert res.singular and len(res) == 1 and near(arm, res.q, q)


@pytest.mark.parametrize(("why", "links"), [
    (r"all four axes are parallel", (Link(a=1.0), Link(a=1.0), Link(a=1.0), Link(a=0.5))),
    (r"axes 2 and 3 are the same line",
     (Link(d=1.0, alpha=pi / 2), Link(), Link(a=1.0), Link(a=0.5))),
])
def test_near_misses_are_refused_with_the_reason(why, links):
    arm = SerialArm(links)
    c = classify(arm)
    assert not c.closed_form and re.search(why, c.reason), c.reason
    with pytest.raises(InputError, match=why):
        arm.ik(arm.fk(np.array([0.1, 0.2, 0.3, 0.4])))
