"""Unreachable targets raise with why and by how much; bad input gets a clear message."""

import numpy as np
import pytest

import rikin
from rikin import InputError, Link, SerialArm, UnreachableError, robots


def test_6r_wrist_centre_beyond_reach_says_how_far():
    arm = robots.aula10_6r()
    # R = I, so z6 = +z and the wrist centre is p - 20 z = (100, 0, -20); the shoulder is at
    # height 12 and links 2-3 reach 10 + 20 = 30
    excess = np.hypot(100, -20 - 12) - 30
    with pytest.raises(
        UnreachableError,
        match=r"wrist centre is 75 beyond the reach of links 2-3 \(it is 104\.995 from",
    ) as e:
        arm.ik(rikin.transl(100, 0, 0))
    assert e.value.excess == pytest.approx(excess)
    assert isinstance(e.value, ValueError)


def test_6r_wrist_centre_too_close_to_the_shoulder():
    arm = robots.aula10_6r()
    # wrist centre at the shoulder point (0, 0, 12): closer than |10 - 20| = 10
    with pytest.raises(UnreachableError, match="too close to the shoulder axis") as e:
        arm.ik(rikin.transl(0, 0, 32))
    assert e.value.excess == pytest.approx(10.0)


def test_epson_c4_message_has_units():
    c4 = robots.epson_c4()
    T = c4.fk(np.zeros(6))
    T[0, 3] += 1000
    with pytest.raises(UnreachableError, match=r"mm beyond the reach of links 2-3") as e:
        c4.ik(T)
    # wrist centre = flange origin = (350 + 1000, 0, 570); shoulder axis at (100, 320)
    assert e.value.units == "mm"
    assert e.value.excess == pytest.approx(np.hypot(1350 - 100, 570 - 320) - 500)


def test_planar_2r_and_3r_reach():
    with pytest.raises(UnreachableError, match=r"target is 10 beyond the reach of links 1-2") as e:
        robots.planar_2r().ik([30.0, 0.0])
    assert e.value.excess == pytest.approx(10.0)
    with pytest.raises(UnreachableError, match=r"wrist point .* 5 beyond"):
        robots.planar_3r().ik([35.0, 0.0, 0.0])  # wrist point (25, 0), reach 20


def test_planar_3r_pose_out_of_plane():
    T = rikin.homogeneous(rikin.rotx(0.3), [10.0, 5.0, 0.0])
    with pytest.raises(UnreachableError, match="tilted .* out of the plane"):
        robots.planar_3r().ik(T)
    with pytest.raises(UnreachableError, match="out of the arm's plane"):
        robots.planar_3r().ik(rikin.transl(10.0, 5.0, 2.0))


def test_angular_3r_unreachable():
    with pytest.raises(UnreachableError, match="target is .* beyond the reach of links 2-3"):
        robots.angular_3r().ik([50.0, 0.0, 10.0])


def test_pprrr_constraint_violation_says_by_how_much():
    arm = robots.pprrr()
    T = arm.fk([1.0, 2.0, 0.3, 0.7, -0.4])
    # move the target along the direction the prismatic joints cannot reach
    c0, U, _ = arm.solver._affine(arm)
    normal = np.cross(U[:, 0], U[:, 1])
    normal /= np.linalg.norm(normal)
    T2 = T.copy()
    T2[:3, 3] += 0.5 * normal
    with pytest.raises(UnreachableError, match=r"0\.5 off the plane") as e:
        arm.ik(T2)
    assert e.value.excess == pytest.approx(0.5)


def test_rprrr_constraints():
    arm = robots.rprrr()
    T = arm.fk([0.4, 1.0, 0.3, 0.7, -0.4])
    T[2, 3] += 0.25
    with pytest.raises(UnreachableError, match=r"0\.25 above the plane"):
        arm.ik(T)
    # wrist centre inside the cylinder of radius a2 = 3 around axis 1
    R = np.eye(3)
    T = rikin.homogeneous(R, [1.0, 0.0, 8.0])  # z5 = +z, so wrist centre = (1, 0, 0)
    with pytest.raises(UnreachableError, match="inside the cylinder") as e:
        arm.ik(T)
    assert e.value.excess == pytest.approx(2.0)


@pytest.mark.parametrize(
    "bad, msg",
    [
        (np.zeros(3), r"takes as target a 4x4"),
        (np.full((4, 4), np.nan), "NaN"),
        (np.diag([1.0, 2.0, 1.0, 1.0]), "not a rotation matrix"),
        (np.diag([1.0, 1.0, -1.0, 1.0]), "reflection"),
        ("pose", "must be numbers"),
    ],
)
def test_bad_targets(bad, msg):
    with pytest.raises(InputError, match=msg):
        robots.aula10_6r().ik(bad)


def test_degrees_for_the_tool_angle():
    with pytest.raises(InputError, match=r"phi .* looks like degrees"):
        robots.planar_3r().ik([20.0, 5.0, 45.0])


def test_near_with_wrong_length():
    arm = robots.aula10_6r()
    with pytest.raises(InputError, match=r"near must have shape \(6,\)"):
        arm.ik(arm.fk(np.zeros(6)), near=np.zeros(4))


def test_position_only_arm_refuses_a_tool_offset():
    arm = robots.angular_3r(tool=rikin.transl(0, 0, 1))
    with pytest.raises(InputError, match="tool may rotate but not offset"):
        arm.ik([5.0, 5.0, 15.0])


def test_arm_without_closed_form():
    # twisted between axes 1 and 2, so not planar (a twist after joint 2 would only turn the
    # flange: that arm is a planar 2R, solved by the lesson's solver)
    arm = SerialArm((Link(a=1.0, alpha=0.3), Link(a=1.0)))
    with pytest.raises(InputError, match="no closed-form IK.*17.19 deg from parallel"):
        arm.ik(np.eye(4))
    assert len(SerialArm((Link(a=1.0), Link(a=1.0, alpha=0.3))).ik([1.5, 0.5])) == 2


def test_batch_never_returns_nan_in_valid_slots_and_marks_unreachable():
    arm = robots.epson_c4()
    rng = np.random.default_rng(11)
    T = arm.fk(rng.uniform(-np.pi, np.pi, size=(300, 6)))
    T[::10, 0, 3] += 5000  # every tenth pose out of reach
    res = arm.ik_batch(T)
    assert not res.valid[::10].any()
    assert np.isfinite(res.q[res.valid]).all()
    assert np.isnan(res.q[~res.valid]).all()
    with pytest.raises(InputError, match=r"shape \(N, 4, 4\)"):
        arm.ik_batch(T[0])


def test_a_misspelled_option_is_an_input_error_naming_it():
    arm = robots.aula10_6r()
    T = arm.fk(np.full(6, 0.3))
    with pytest.raises(InputError, match="no option within_limit; its options are within_limits"):
        arm.ik(T, within_limit=True)
    with pytest.raises(InputError, match="no option chunk; its options are chunk_size, workers"):
        arm.ik_batch(T[None], chunk=3)
    assert len(arm.ik(T, within_limits=False, near=np.zeros(6))) == 8


def test_rounded_copy_and_transposed_pose_get_a_hint():
    """A rotation copied with 3 decimals that misses the orthonormality check says to copy
    more decimals; a transposed pose (position in the last row) says to pass T.T."""
    arm = rikin.robots.aula10_6r()
    rng = np.random.default_rng(4)
    refused = 0
    for q in rng.uniform(-np.pi, np.pi, (60, 6)):
        T = np.round(arm.fk(q), 3)
        try:
            arm.ik(T)
        except rikin.InputError as exc:
            refused += 1
            assert "copy at least 4 decimals" in str(exc), str(exc)
        except rikin.UnreachableError:
            pass
    assert refused >= 3, refused
    T = arm.fk(np.full(6, 0.3))
    with pytest.raises(rikin.InputError, match=r"looks transposed.*pass T\.T"):
        arm.ik(T.T)
    with pytest.raises(rikin.InputError) as other:  # a wrong last row, not a transpose
        bad = T.copy()
        bad[3, 0] = 5.0
        arm.ik(bad)
    assert "transposed" not in str(other.value)
