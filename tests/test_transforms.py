"""Rotations, RPY/ZYZ and homogeneous transforms."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import rikin
from rikin import InputError

angle = st.floats(-np.pi, np.pi, allow_nan=False)


def test_elementary_rotations_match_textbook_matrices():
    c, s = np.cos(0.3), np.sin(0.3)
    assert np.allclose(rikin.rotx(0.3), [[1, 0, 0], [0, c, -s], [0, s, c]])
    assert np.allclose(rikin.roty(0.3), [[c, 0, s], [0, 1, 0], [-s, 0, c]])
    assert np.allclose(rikin.rotz(0.3), [[c, -s, 0], [s, c, 0], [0, 0, 1]])


def test_rotations_broadcast_over_batches():
    R = rikin.rotz(np.zeros((4, 5)))
    assert R.shape == (4, 5, 3, 3)
    assert np.allclose(R, np.eye(3))


def test_rpy_is_zyx_fixed_axes():
    # independent expectation: R = Rz(yaw) Ry(pitch) Rx(roll) multiplied out by hand for pitch = 0
    R = rikin.rpy_to_r(0.0, 0.0, np.pi / 2)
    assert np.allclose(R, [[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    R = rikin.rpy_to_r(np.pi / 2, 0.0, 0.0)
    assert np.allclose(R, [[1, 0, 0], [0, 0, -1], [0, 1, 0]])


@given(angle, st.floats(-1.5, 1.5), angle)
def test_rpy_round_trip(roll, pitch, yaw):
    rpy = rikin.r_to_rpy(rikin.rpy_to_r(roll, pitch, yaw))
    assert np.allclose(rikin.rpy_to_r(*rpy), rikin.rpy_to_r(roll, pitch, yaw), atol=1e-12)
    assert np.allclose(rikin.wrap_angle(rpy - [roll, pitch, yaw]), 0, atol=1e-9)


@given(angle, st.sampled_from([np.pi / 2, -np.pi / 2]), angle)
def test_rpy_gimbal_lock_still_reproduces_the_rotation(roll, pitch, yaw):
    R = rikin.rpy_to_r(roll, pitch, yaw)
    rpy = rikin.r_to_rpy(R)
    assert rpy[0] == 0.0
    assert np.allclose(rikin.rpy_to_r(*rpy), R, atol=1e-9)


@given(angle, st.floats(0, np.pi), angle, st.sampled_from([1, -1]))
def test_zyz_round_trip_both_branches(phi, theta, psi, branch):
    R = rikin.zyz_to_r(phi, theta, psi)
    ang = rikin.r_to_zyz(R, branch=branch)
    assert np.allclose(rikin.zyz_to_r(*ang), R, atol=1e-9)
    # theta = -pi and pi are one angle; wrapping to (-pi, pi] writes it as pi
    assert branch * ang[1] >= -1e-12 or np.isclose(abs(ang[1]), np.pi)


def test_inverse_transform():
    T = rikin.homogeneous(rikin.rpy_to_r(0.1, 0.2, 0.3), [1.0, -2.0, 3.0])
    assert np.allclose(rikin.inv_transform(T) @ T, np.eye(4))


@given(st.floats(-100, 100))
def test_wrap_angle_range(x):
    w = rikin.wrap_angle(x)
    assert -np.pi < w <= np.pi
    assert np.isclose(np.cos(w), np.cos(x)) and np.isclose(np.sin(w), np.sin(x))


def test_wrap_angle_keeps_pi():
    assert rikin.wrap_angle(np.pi) == np.pi
    assert rikin.wrap_angle(-np.pi) == np.pi


def test_degrees_are_detected():
    with pytest.raises(InputError, match="looks like degrees"):
        rikin.rotz(45)


def test_not_a_rotation():
    with pytest.raises(InputError, match="not a rotation matrix"):
        rikin.r_to_rpy(np.ones((3, 3)))
    with pytest.raises(InputError, match="reflection"):
        rikin.r_to_rpy(np.diag([1.0, 1.0, -1.0]))


def test_nan_and_shape_errors():
    with pytest.raises(InputError, match="NaN"):
        rikin.rotx(float("nan"))
    with pytest.raises(InputError, match=r"shape \(\.\.\., 3, 3\)"):
        rikin.r_to_rpy(np.eye(4))
    with pytest.raises(InputError, match="last row"):
        rikin.inv_transform(np.ones((4, 4)))


def test_wrap_angle_refuses_nan_and_infinity_saying_where():
    """Issue 29's leftover: rikin.wrap_angle(float('nan')) returned nan."""
    with pytest.raises(InputError, match=r"^theta is NaN, not a number rikin can use"):
        rikin.wrap_angle(float("nan"))
    with pytest.raises(InputError, match=r"^theta is -inf \(infinite\)"):
        rikin.wrap_angle(-np.inf)
    with pytest.raises(InputError, match=r"NaN or infinity \(first at index \(1, 0\)\)"):
        rikin.wrap_angle(np.array([[0.5, 1.0], [np.nan, 2.0]]))
    # finite values, however large, are wrapped as the doubles they are (a prismatic
    # joint's length in numpy.where(revolute, wrap_angle(q), q) is dropped anyway)
    assert rikin.wrap_angle(3 * np.pi / 2) == pytest.approx(-np.pi / 2)
    assert np.isfinite(rikin.wrap_angle(1e300))
