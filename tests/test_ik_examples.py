"""The lessons' worked examples give the solution sets of ERRATA.md (typed in by hand)."""

import numpy as np
import pytest

import rikin
from rikin import robots


def assert_same_set(got_deg, want_deg, atol):
    """Every wanted row is in got (modulo 360 deg) and the counts agree."""
    got = np.asarray(got_deg)
    want = np.asarray(want_deg)
    assert len(got) == len(want), f"{len(got)} solutions, expected {len(want)}"
    for row in want:
        d = (got - row + 180) % 360 - 180
        assert np.any(np.all(np.abs(d) < atol, axis=1)), f"missing {row}"


AULA10_ALL = [
    (99.6, 9, 26.4, 68.4, 30, 151),
    (99.6, 9, 26.4, -111.6, -30, -29),
    (99.6, 44.341, -26.4, 75.334, 46.634, 142.262),
    (99.6, 44.341, -26.4, -104.666, -46.634, -37.738),
    (-80.4, 135.659, 26.4, -104.666, 46.634, 142.262),
    (-80.4, 135.659, 26.4, 75.334, -46.634, -37.738),
    (-80.4, 171, -26.4, -111.6, 30, 151),
    (-80.4, 171, -26.4, 68.4, -30, -29),
]


def test_aula10_all_eight_solutions_of_the_lesson_pose():
    arm = robots.aula10_6r()
    T = rikin.homogeneous(
        rikin.rpy_to_r(-26.5610, 10.0935, 51.7776, degrees=True), [-9.4519, 33.8090, 42.7623]
    )
    res = arm.ik(T)
    assert_same_set(res.degrees(), AULA10_ALL, atol=5e-3)  # the pose is rounded to 4 decimals
    assert not res.singular


def test_aula10_wrist_centre_and_stated_matrices():
    arm = robots.aula10_6r()
    T = rikin.homogeneous(
        rikin.rpy_to_r(-26.5610, 10.0935, 51.7776, degrees=True), [-9.4519, 33.8090, 42.7623]
    )
    steps = arm.solver.steps(arm, arm.world_to_base(T), arm_slot=0)
    assert np.allclose(steps.wrist_centre, [-4.3659, 25.8128, 25.1500], atol=1e-3)
    R03 = [[0.0966, 0.986, -0.1359], [-0.5712, 0.1668, 0.8037], [0.8151, 0, 0.5793]]
    assert np.allclose(steps.R_0_3, R03, atol=1e-3)
    assert np.allclose(steps.R_3_0, np.array(R03).T, atol=1e-3)
    R36A = [[-0.5258, -0.7123, 0.4649], [0.7296, -0.6586, -0.1841], [0.4373, 0.2424, 0.866]]
    assert np.allclose(steps.R_3_6, R36A, atol=3e-3)
    # the stated theta (1.7383, 0.1571, 0.4608, 1.1938, 0.5236, 2.6354) rad
    q = np.concatenate([steps.q123, steps.q456[0]])
    assert np.allclose(q, [1.7383, 0.1571, 0.4608, 1.1938, 0.5236, 2.6354], atol=2e-4)


def test_aula10_commented_out_poses_have_eight_solutions_each():
    arm = robots.aula10_6r()
    ds = [
        (-4.6, 11.75, 52.992),
        (20.507, 37.305, 25.669),
        (-3.656, -1.032, 47.478),
        (-2.737, 12.770, 53.891),
    ]
    rpys = [(36.5, 11.5, -110.6), (69.5, -13.5, -168.9), (22.9, -46.8, 82.6), (11.3, 0.6, 35.3)]
    for d, (r, p, y) in zip(ds, rpys, strict=True):
        res = arm.ik(rikin.homogeneous(rikin.rpy_to_r(r, p, y, degrees=True), d))
        assert len(res) == 8


def test_angular_3r_four_solutions():
    res = robots.angular_3r().ik([-9.545, 7.896, 23.192])
    want = [
        (140.4011, 21.6007, 50.4008),
        (140.4011, 72.0015, -50.4008),
        (-39.5989, 107.9985, 50.4008),
        (-39.5989, 158.3993, -50.4008),
    ]
    assert_same_set(res.degrees(), want, atol=1e-3)
    # ERRATA 002/6: with joints that raise the arm for positive angles, sin q3 > 0 on the
    # front branch is elbow DOWN
    lab = dict(zip(map(tuple, np.round(res.degrees(), 1)), res.labels, strict=True))
    assert lab[(140.4, 21.6, 50.4)] == "front/down"
    assert lab[(140.4, 72.0, -50.4)] == "front/up"


def test_planar_3r_two_solutions_of_the_lesson_and_of_the_commented_point():
    arm = robots.planar_3r()
    res = arm.ik([27.071, 7.071, np.radians(45)])
    assert_same_set(res.degrees(), [(-0.1494, 0.2984, 44.851), (0.149, -0.2984, 45.1494)], 1e-3)
    res = arm.ik([7.739, 22.885, np.radians(95.2)])
    assert_same_set(res.degrees(), [(17.2603, 77.9283, 0.0114), (95.1886, -77.9283, 77.9397)], 1e-3)


def test_epson_c4_calibration_pose_solution_families():
    c4 = robots.epson_c4()
    res = c4.ik(c4.fk(np.zeros(6)))
    deg = res.degrees()
    # ERRATA 004/7: the configs row, its wrist flip, and the singular family (0, 0, 0, t, 0, -t)
    regular = np.array([b.wrist != "singular" for b in res.branches])
    assert_same_set(deg[regular], [(0, -90, 180, 0, -90, 0), (0, -90, 180, 180, 90, 180)], 1e-9)
    sing = [q for q, b in zip(res.q, res.branches, strict=True) if b.wrist == "singular"]
    assert len(sing) == 1
    assert np.allclose(sing[0][[0, 1, 2, 4]], 0, atol=1e-9)
    assert np.isclose(np.cos(sing[0][3] + sing[0][5]), 1.0)
    assert res.singular and res.free_joints == (4, 6)


def test_epson_c4_singular_representative_follows_near():
    c4 = robots.epson_c4()
    near = np.array([0.0, 0.0, 0.0, 0.5, 0.0, -0.5])
    res = c4.ik(c4.fk(np.zeros(6)), near=near)
    assert np.allclose(res.q[0], near, atol=1e-9)


def test_epson_c4_rst_pose_has_eight_solutions_none_within_limits():
    # ERRATA 004: expEEPose (RST model, metres, no J2 offset, no tool) has 8 exact solutions,
    # q_RST = q_RVC + [0, pi/2, 0, 0, 0, 0]; none fits the C4's limits
    c4 = robots.epson_c4(tool=np.eye(4))
    exp_config = np.array([1.9775, 2.5497, -2.3437, 2.5973, 0.8316, -2.5287])
    T = c4.fk(exp_config - [0, np.pi / 2, 0, 0, 0, 0])
    T_lab = np.array(
        [
            [-0.5367, -0.8283, 0.1612, 22.3],
            [0.7234, -0.3533, 0.5932, -51.7],
            [-0.4344, 0.4349, 0.7887, 214.8],
            [0, 0, 0, 1],
        ]
    )
    assert np.allclose(T, T_lab, atol=1e-3 * 100)
    res = c4.ik(T)
    assert len(res) == 8
    assert_same_set(
        res.degrees()[
            [
                np.argmin(
                    np.abs(rikin.wrap_angle(res.q - (exp_config - [0, np.pi / 2, 0, 0, 0, 0]))).sum(
                        1
                    )
                )
            ]
        ],
        [np.degrees(rikin.wrap_angle(exp_config - [0, np.pi / 2, 0, 0, 0, 0]))],
        1e-6,
    )
    assert len(c4.ik(T, within_limits=True)) == 0


def test_within_limits_keeps_in_limit_two_pi_equivalents():
    c4 = robots.epson_c4()
    q = rikin.rad([10, -20, 30, 40, 50, 300])  # J6 = 300 deg is allowed (+-360)
    res = c4.ik(c4.fk(q), within_limits=True, near=q)
    assert np.allclose(res.q[0], q, atol=1e-9)  # the 300 deg equivalent, not -60
    assert all(np.all((r >= c4.qlim[:, 0]) & (r <= c4.qlim[:, 1])) for r in res.q)


def test_sorted_by_distance_to_near():
    arm = robots.aula10_6r()
    q = rikin.rad([-80.4, 171, -26.4, 68.4, -30, -29])
    res = arm.ik(arm.fk(q), near=q)
    assert np.allclose(res.q[0], rikin.wrap_angle(q), atol=1e-9)
    dist = np.linalg.norm(rikin.wrap_angle(res.q - q), axis=1)
    assert np.all(np.diff(dist) >= -1e-12)


@pytest.mark.parametrize("name", ["aula10_6r", "barrientos_6r"])
def test_wrist_singularity_is_at_q5_zero_not_ninety(name):
    # ERRATA 000/3: the lesson says q5 = 90 deg is singular; it is q5 = 0 or pi
    arm = robots.LESSON_ROBOTS[name]()
    at_90 = arm.ik(arm.fk(rikin.rad([10, 20, 30, 40, 90, 50])))
    assert not at_90.singular and len(at_90) == 8
    at_0 = arm.ik(arm.fk(rikin.rad([10, 20, 30, 40, 0, 50])))
    assert at_0.singular and at_0.free_joints == (4, 6)
    # q5 = 0 only on the generating arm branch and its mirror (same |q5|, ERRATA's table
    # pairs 1/7 and 3/5): one representative each, plus 2 x 2 regular solutions
    assert len(at_0) == 6
    assert sum(b.wrist == "singular" for b in at_0.branches) == 2
