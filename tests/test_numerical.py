"""Numerical IK (rikin.ik.numerical): convergence, FK check, agreement with the closed form,
honest failure on unreachable targets, input errors, multistart."""

from __future__ import annotations

import numpy as np
import pytest

import rikin
from rikin.ik.numerical import (
    NumericalIKResult,
    _rotation_vector,
    ik_numerical,
    ik_numerical_multistart,
    pose_error,
)

AULA10_Q_DEG = [99.6, 9, 26.4, 68.4, 30, 151]
#: converged solutions are compared with the closed form to this (rad): the
#: iteration stops at a pose error of 1e-10, not at rounding.
SAME_Q = 1e-6


def _fk_error(arm: rikin.SerialArm, q: np.ndarray, T: np.ndarray) -> float:
    F = arm.fk(q)
    pos = np.linalg.norm(F[:3, 3] - T[:3, 3]) / arm.scale
    return float(max(pos, np.abs(F[:3, :3] - T[:3, :3]).max()))


def _wrapped_distance(a: np.ndarray, b: np.ndarray) -> float:
    d = np.asarray(a) - np.asarray(b)
    return float(np.abs(np.remainder(d + np.pi, 2 * np.pi) - np.pi).max())


def _is_one_of(q: np.ndarray, solutions: np.ndarray) -> bool:
    return min(_wrapped_distance(q, s) for s in solutions) < SAME_Q


def _rodrigues(v: np.ndarray) -> np.ndarray:
    """exp([v]x), written independently of the code under test."""
    angle = np.linalg.norm(v)
    if angle == 0:
        return np.eye(3)
    k = v / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


# ---------------------------------------------------------------- convergence
@pytest.mark.parametrize("seed", range(25))
def test_aula10_converges_and_lands_on_a_closed_form_solution(seed):
    arm = rikin.robots.aula10_6r()
    rng = np.random.default_rng(seed)
    T = arm.fk(rng.uniform(-np.pi, np.pi, 6))
    sol = ik_numerical(arm, T, rng=rng)
    assert isinstance(sol, NumericalIKResult)
    assert sol.success, sol.reason
    assert sol.reason == "converged"
    assert _fk_error(arm, sol.q, T) < 1e-9
    assert sol.error_position < 1e-9 * arm.scale and sol.error_rotation < 1e-9
    assert np.all(np.abs(sol.q) <= np.pi)
    assert _is_one_of(sol.q, arm.ik(T).q)


@pytest.mark.parametrize("seed", range(15))
def test_epson_c4_converges_from_a_nearby_start(seed):
    # mm-sized arm with a tool: the position error is weighted by 1/arm.scale
    arm = rikin.robots.epson_c4()
    rng = np.random.default_rng(100 + seed)
    q_true = rng.uniform(-np.pi, np.pi, 6)
    T = arm.fk(q_true)
    start = q_true + rng.normal(0.0, 0.3, 6)
    start = np.remainder(start + np.pi, 2 * np.pi) - np.pi
    sol = ik_numerical(arm, T, start)
    assert sol.success, sol.reason
    assert _fk_error(arm, sol.q, T) < 1e-9
    assert np.linalg.norm(arm.fk(sol.q)[:3, 3] - T[:3, 3]) < 1e-9 * arm.scale
    assert _is_one_of(sol.q, arm.ik(T).q)


def test_epson_c4_with_base_and_tool_from_random_starts():
    base = rikin.homogeneous(rikin.rpy_to_r(0.1, -0.2, 0.7), np.array([200.0, -50.0, 30.0]))
    tool = rikin.homogeneous(rikin.rotx(np.pi) @ rikin.rotz(0.4), np.array([10.0, 5.0, -80.0]))
    arm = rikin.robots.epson_c4(base=base, tool=tool)
    rng = np.random.default_rng(7)
    converged = 0
    for _ in range(20):
        T = arm.fk(rng.uniform(-np.pi, np.pi, 6))
        sol = ik_numerical(arm, T, rng=rng)
        # a random start may fall into a local minimum; then it must say so
        assert sol.success or "stalled" in sol.reason or "max_iter" in sol.reason
        assert np.all(np.isfinite(sol.q))
        if sol.success:
            converged += 1
            assert _fk_error(arm, sol.q, T) < 1e-9
            assert _is_one_of(sol.q, arm.ik(T).q)
    assert converged >= 15


def test_the_aula10_worked_example_from_a_start_near_the_lesson_answer():
    arm = rikin.robots.aula10_6r()
    q_lesson = rikin.rad(AULA10_Q_DEG)
    T = arm.fk(q_lesson)
    sol = ik_numerical(arm, T, q_lesson + 0.2)
    assert sol.success
    assert _wrapped_distance(sol.q, q_lesson) < SAME_Q


def test_dls_method_converges_near_the_solution():
    arm = rikin.robots.barrientos_6r()
    q_true = np.array([0.3, -0.4, 0.9, 0.2, -1.1, 0.5])
    T = arm.fk(q_true)
    sol = ik_numerical(arm, T, q_true + 0.1, method="dls")
    assert sol.success, sol.reason
    assert _wrapped_distance(sol.q, q_true) < SAME_Q


def test_default_start_is_reproducible():
    arm = rikin.robots.aula10_6r()
    T = arm.fk(rikin.rad(AULA10_Q_DEG))
    a, b = ik_numerical(arm, T), ik_numerical(arm, T)
    assert np.array_equal(a.q, b.q) and a.iterations == b.iterations


def test_within_limits_keeps_the_c4_inside_its_joint_limits():
    arm = rikin.robots.epson_c4()
    lim = arm.qlim
    rng = np.random.default_rng(11)
    for _ in range(5):
        q_true = rng.uniform(lim[:, 0], lim[:, 1])
        T = arm.fk(q_true)
        sol = ik_numerical(arm, T, q_true * 0.9, within_limits=True)
        assert np.all(sol.q >= lim[:, 0] - 1e-12) and np.all(sol.q <= lim[:, 1] + 1e-12)
        if sol.success:
            assert _fk_error(arm, sol.q, T) < 1e-9


# ---------------------------------------------------------------- fewer joints: mask
def test_planar_2r_position_only_with_a_mask():
    arm = rikin.robots.planar_2r(10.0, 10.0)
    target = rikin.transl(15.0, 5.0, 0.0)
    sol = ik_numerical(arm, target, [0.3, 0.3], mask=(1, 1, 0, 0, 0, 0))
    assert sol.success, sol.reason
    assert np.allclose(arm.fk(sol.q)[:2, 3], [15.0, 5.0], atol=1e-9)
    assert _is_one_of(sol.q, arm.ik([15.0, 5.0]).q)


def test_angular_3r_position_only_with_a_mask():
    arm = rikin.robots.angular_3r()
    p = np.array([-9.545, 7.896, 23.192])
    sol = ik_numerical(arm, rikin.transl(*p), [2.0, 0.5, 0.5], mask=(1, 1, 1, 0, 0, 0))
    assert sol.success, sol.reason
    assert np.allclose(arm.fk(sol.q)[:3, 3], p, atol=1e-9)
    assert _is_one_of(sol.q, arm.ik(p).q)


def test_fewer_than_six_joints_need_a_mask():
    arm = rikin.robots.angular_3r()
    with pytest.raises(rikin.InputError, match="mask"):
        ik_numerical(arm, rikin.transl(5.0, 5.0, 15.0))


# ---------------------------------------------------------------- failure is reported, not raised
@pytest.mark.parametrize("factor", [3.0, 10.0])
def test_unreachable_target_gives_success_false_with_a_reason(factor):
    arm = rikin.robots.aula10_6r()
    T = arm.fk(rikin.rad(AULA10_Q_DEG))
    T[:3, 3] *= factor
    with pytest.raises(rikin.UnreachableError):
        arm.ik(T)  # the closed form agrees that it is out of reach
    sol = ik_numerical(arm, T)
    assert sol.success is False
    assert "stalled" in sol.reason or "max_iter" in sol.reason
    assert "error" in sol.reason
    assert np.all(np.isfinite(sol.q))
    assert np.isfinite(sol.error_position) and np.isfinite(sol.error_rotation)
    # no TCP is farther from the origin than the sum of the DH lengths, arm.scale
    assert sol.error_position >= np.linalg.norm(T[:3, 3]) - arm.scale


def test_max_iter_is_reported():
    arm = rikin.robots.aula10_6r()
    T = arm.fk(rikin.rad(AULA10_Q_DEG))
    sol = ik_numerical(arm, T, np.zeros(6) + 0.1, max_iter=2)
    assert not sol.success and sol.iterations == 2
    assert sol.reason.startswith("max_iter reached (error ")


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"T": np.eye(3)}, "4, 4"),
        ({"T": np.full((4, 4), np.nan)}, "NaN"),
        ({"T": np.diag([1.0, 1.0, -1.0, 1.0])}, "reflection"),
        ({"T": np.stack([np.eye(4)] * 2)}, "one 4x4 pose"),
        ({"q0": np.zeros(5)}, "shape"),
        ({"q0": [0, 0, 90, 0, 0, 0]}, "degrees"),
        ({"q0": [0, 0, np.nan, 0, 0, 0]}, "NaN"),
        ({"method": "newton"}, "method"),
        ({"tol": 0.0}, "tol"),
        ({"max_iter": 0}, "max_iter"),
        ({"mask": (1, 1, 1)}, "mask"),
        ({"mask": (0, 0, 0, 0, 0, 0)}, "mask"),
        ({"rng": "seed"}, "rng"),
    ],
)
def test_bad_input_raises_input_error(kwargs, match):
    arm = rikin.robots.aula10_6r()
    args = {"T": arm.fk(np.full(6, 0.3))}
    args.update(kwargs)
    T = args.pop("T")
    with pytest.raises(rikin.InputError, match=match):
        ik_numerical(arm, T, **args)


def test_multistart_rejects_bad_arguments():
    arm = rikin.robots.aula10_6r()
    T = arm.fk(np.full(6, 0.3))
    with pytest.raises(rikin.InputError, match="n_starts"):
        ik_numerical_multistart(arm, T, 0)
    with pytest.raises(rikin.InputError, match="q0"):
        ik_numerical_multistart(arm, T, 3, q0=np.zeros(6))


# ---------------------------------------------------------------- multistart
def test_multistart_finds_all_eight_solutions_of_the_aula10_example():
    arm = rikin.robots.aula10_6r()
    T = arm.fk(rikin.rad(AULA10_Q_DEG))
    closed = arm.ik(T).q
    assert len(closed) == 8
    found = ik_numerical_multistart(arm, T, 60, rng=1)
    assert len(found) == 8
    for q in found:
        assert _fk_error(arm, q, T) < 1e-9
        assert _is_one_of(q, closed)
    for q in closed:  # and every closed-form solution was found
        assert _is_one_of(q, np.array(found))


def test_multistart_with_one_start_finds_at_most_one():
    arm = rikin.robots.aula10_6r()
    T = arm.fk(rikin.rad(AULA10_Q_DEG))
    assert len(ik_numerical_multistart(arm, T, 1, rng=2)) <= 1


# ---------------------------------------------------------------- the error measure
@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-7, 0.5, 2.0, np.pi - 1e-3, np.pi - 1e-8, np.pi])
def test_rotation_vector_inverts_rodrigues_even_near_pi(angle):
    rng = np.random.default_rng(int(angle * 1000) + 3)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    R = _rodrigues(angle * axis)
    v = _rotation_vector(R)
    assert abs(np.linalg.norm(v) - angle) < 1e-7
    assert np.abs(_rodrigues(v) - R).max() < 1e-12


def test_pose_error_is_zero_at_the_target_and_scaled_by_the_arm_size():
    arm = rikin.robots.epson_c4()
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    T = arm.fk(q)
    assert np.abs(pose_error(arm, q, T)).max() < 1e-14
    T2 = T.copy()
    T2[0, 3] += 10.0  # 10 mm off in x
    e = pose_error(arm, q, T2)
    assert e[0] == pytest.approx(10.0 / arm.scale)
    assert np.abs(e[1:]).max() < 1e-14


@pytest.mark.parametrize(
    "make", [rikin.robots.aula10_6r, rikin.robots.epson_c4, rikin.robots.pprrr, rikin.robots.rprrr]
)
def test_the_iteration_jacobian_is_arm_jacobian(make):
    from rikin.ik.numerical import _pose_and_jacobian

    arm = make()
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = rng.uniform(-1.0, 1.0, arm.n)
        F, J = _pose_and_jacobian(arm, q)
        assert np.abs(F - arm.fk(q)).max() < 1e-12 * arm.scale
        assert np.abs(J - arm.jacobian(q)).max() < 1e-12 * arm.scale
