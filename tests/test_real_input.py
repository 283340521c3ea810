"""rikin on input as students type it (issue 10): angles modulo 2*pi, rounded poses,
targets near stretched/folded/axis configurations, magnitudes at the edge of double precision."""

import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import rikin
from rikin import InputError, robots

ARMS = {name: make() for name, make in robots.LESSON_ROBOTS.items()}
turns = st.integers(-3, 3)


# ---------------------------------------------------------------- angles modulo 2*pi (item 5)
@pytest.mark.parametrize("name", sorted(ARMS))
@given(data=st.data())
def test_fk_reads_angles_modulo_two_pi(name, data):
    arm = ARMS[name]
    q = np.array(
        [data.draw(st.floats(-np.pi, np.pi)) if r else data.draw(st.floats(-5, 5)) for r in arm.revolute]
    )
    k = np.array([data.draw(turns) if r else 0 for r in arm.revolute])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        T = arm.fk(q + 2 * np.pi * k)
    assert np.abs(T - arm.fk(q)).max() <= 1e-12 * arm.scale


def test_unwrapped_solutions_go_back_through_fk_and_ik():
    arm = robots.aula10_6r()
    q = np.array([0.3, -1.2, 2.0, 0.4, -0.7, 3.0]) + 2 * np.pi * np.array([1, -1, 2, 0, 1, -2])
    T = arm.fk(q)  # 12.8, 8.4, ... rad: not degrees
    res = arm.ik(T, near=q)
    assert np.allclose(arm.fk(res.q[0]), T, atol=1e-9 * arm.scale)
    assert np.allclose(rikin.wrap_angle(res.q[0] - q), 0, atol=1e-9)
    assert rikin.rotz(7.5).shape == (3, 3)
    assert len(robots.planar_3r().ik([20.0, 5.0, 0.7 + 2 * np.pi])) == 2


@pytest.mark.parametrize(
    "q, joint",
    [
        ([0, 90, 0, 0, 0, 0], "joint 2"),  # a round number of degrees
        ([99.6, 9, 26.4, 68.4, 30, 151], "joint 5"),  # the lesson's angles: 30 is round
        ([99.6, 9, 26.4, 68.4, 31.2, 151.3], "joint 1"),  # several values beyond four turns
        ([0, 0, 0, 0, 0, -180], "joint 6"),
    ],
)
def test_degrees_beyond_doubt_still_raise(q, joint):
    with pytest.raises(InputError, match=joint + r".*looks like degrees.*radians"):
        robots.aula10_6r().fk(q)


def test_degrees_check_can_be_switched_off_but_not_the_magnitude_check():
    arm = robots.aula10_6r()
    T = arm.fk([0, 90, 0, 0, 0, 0], check_degrees=False)
    assert np.allclose(T, arm.fk([0, 90 - 14 * 2 * np.pi, 0, 0, 0, 0]), atol=1e-12)
    with pytest.raises(InputError, match=r"joint 1.*too large for an angle"):
        arm.fk([1e7, 0, 0, 0, 0, 0], check_degrees=False)
