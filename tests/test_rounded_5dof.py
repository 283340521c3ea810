"""Rounded poses of the 5-DOF arms (issue 10, item 1): a PPRRR or RPRRR pose printed with 4
or 6 decimals, or stored as float32, is a few 1e-5 off the 5-dimensional set of poses the
arm reaches. IK solves the nearest reachable pose and says how far the given one was; a pose
further off than ROUNDED_POSE_TOL stays unreachable, with the right distance.

Every expectation here is computed independently of the solver: the wrist centre from FK
frames, the plane joints 1-2 sweep from FK of many configurations, and the nearest pose by
a Gauss-Newton least squares over the joint values."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rikin
from rikin import robots
from rikin.ik import ik_numerical, ik_numerical_multistart
from rikin.tolerances import ROUNDED_POSE_TOL

BASE = rikin.transforms.trotz(0.7) @ rikin.transforms.trotx(0.4) @ rikin.transl(2.0, -1.0, 3.0)
TOOL = rikin.transforms.troty(0.3) @ rikin.transl(0.5, 0.0, 2.0)
ARMS = {
    (name, mount): robots.LESSON_ROBOTS[name](**({"base": BASE, "tool": TOOL} if mount else {}))
    for name in ("pprrr", "rprrr")
    for mount in (False, True)
}
FULL = {"pprrr": 2, "rprrr": 4}


def random_q(arm, rng):
    return np.where(arm.revolute, rng.uniform(-np.pi, np.pi, 5), rng.uniform(-6.0, 6.0, 5))


def rounded(T, how):
    return T.astype(np.float32).astype(float) if how == "float32" else np.round(T, how)


def polar(T):
    """``T`` with its rotation block replaced by the nearest rotation (SVD), as the 6R path."""
    U, _, Vt = np.linalg.svd(T[:3, :3])
    out = T.copy()
    out[:3, :3] = U @ Vt
    return out


def centre_in_tcp(arm):
    """The wrist centre (origin of frame 3, where the axes of joints 3-5 meet) in TCP
    coordinates: the same for every q, read off FK frames."""
    F = arm.fk([0.3, 1.0, 0.4, 0.5, 0.6], frames=True)
    return (np.linalg.inv(F[-1]) @ np.append(F[3, :3, 3], 1.0))[:3]


def swept_plane(arm):
    """Point and unit normal (world frame) of the plane the wrist centres of many random
    configurations lie in."""
    rng = np.random.default_rng(11)
    P = arm.fk(np.stack([random_q(arm, rng) for _ in range(20)]), frames=True)[:, 3, :3, 3]
    o = P.mean(axis=0)
    _, sv, Vt = np.linalg.svd(P - o)
    assert sv[2] <= 1e-12 * sv[0]  # they do lie in a plane
    return o, Vt[2]


def wrist_gap(arm, T):
    """Independent distance of the pose ``T``'s wrist centre from where joints 1-2 put it:
    from the swept plane, and for the RPRRR also out of the cylinder of radius a2."""
    pw = (T @ np.append(centre_in_tcp(arm), 1.0))[:3]
    o, n = swept_plane(arm)
    dz = float(n @ (pw - o))
    if arm.joint_types == "RPRRR":
        local = np.linalg.inv(arm.base) @ np.append(pw, 1.0)
        inside = max(float(arm.links[0].a) - float(np.hypot(local[0], local[1])), 0.0)
        return float(np.hypot(dz, inside))
    return abs(dz)


def size(arm, T):
    return max(arm.scale, float(np.abs(T[:3, 3]).max()))


def nearest_by_joint_least_squares(arm, T, q0, iterations=8):
    """The reachable pose nearest to ``T`` (least squares over the 12 entries of [R | p]),
    found in joint space by Gauss-Newton with central-difference Jacobians from ``q0``."""
    h = 1e-6 * np.where(arm.revolute, 1.0, arm.scale)
    q = np.array(q0, float)
    for _ in range(iterations):
        steps = np.concatenate([q + np.diag(h), q - np.diag(h), q[None]])
        F = arm.fk(steps)[:, :3, :].reshape(len(steps), 12)
        J = ((F[:5] - F[5:10]) / (2 * h)[:, None]).T  # (12, 5)
        r = F[10] - T[:3, :].reshape(12)
        q = q - np.linalg.lstsq(J, r, rcond=None)[0]
    return arm.fk(q)


def solve_quietly(arm, T):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return arm.ik(T)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@settings(max_examples=40)
@given(seed=st.integers(0, 2**32 - 1), how=st.sampled_from([4, 6, "float32"]))
def test_rounded_poses_solve_for_the_nearest_reachable_pose(name, mount, seed, how):
    arm = ARMS[name, mount]
    q_true = random_q(arm, np.random.default_rng(seed))
    T_true = arm.fk(q_true)
    G = rounded(T_true, how)
    res = solve_quietly(arm, G)
    s = size(arm, G)
    assert len(res) == FULL[name] or res.singular
    # every solution reaches the pose solved: exactly when it was moved onto the reachable
    # set; within the FK check's bound when it was within the solvers' rounding slack
    # (REACH_TOL, relative) and solved as given, as before
    tol = 1e-12 if res.reach_distance > 0 else 1e-8
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - res.target[:3, 3]).max() <= tol * s
    assert np.abs(F[:, :3, :3] - res.target[:3, :3]).max() <= tol
    assert wrist_gap(arm, res.target) <= tol * s
    # ... and within the tolerance of the pose given: no entry moved more than the two distances
    moved = np.abs(res.target - G).max()
    assert moved <= res.reach_distance + res.rotation_distance + 1e-13 * s
    assert moved <= ROUNDED_POSE_TOL * s
    # the distance reported is the wrist centre's, computed independently
    want = wrist_gap(arm, polar(G))
    if res.reach_distance > 0:
        assert res.reach_distance == pytest.approx(want, rel=1e-6)
        assert "nearest reachable pose" in res.table().splitlines()[-1]
        # nearest: what a joint-space least squares from the true joints finds, and at least
        # as near the given numbers as the true pose they were rounded from
        best = nearest_by_joint_least_squares(arm, polar(G), q_true)
        assert np.abs(best - res.target)[:3].max() <= 1e-9 * s
        assert np.linalg.norm(res.target - polar(G)) <= np.linalg.norm(T_true - polar(G)) + 1e-12
    else:  # reachable as given, to the solver's own rounding slack (REACH_TOL)
        assert want <= 1e-8 * s
        assert np.array_equal(res.target, polar(G) if res.rotation_distance else G)
        assert "reachable pose" not in res.table()


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_four_decimals_never_refused_and_measured(name, mount):
    """All of 100 random poses rounded to 4 decimals solve (today: none does)."""
    arm = ARMS[name, mount]
    rng = np.random.default_rng(3)
    reach = []
    for _ in range(100):
        res = solve_quietly(arm, np.round(arm.fk(random_q(arm, rng)), 4))
        reach.append(res.reach_distance / arm.scale)
    assert 0 < max(reach) <= ROUNDED_POSE_TOL / 3  # the margin tolerances.py states


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@given(seed=st.integers(0, 2**32 - 1))
@settings(max_examples=30)
def test_exact_poses_are_solved_as_given(name, mount, seed):
    arm = ARMS[name, mount]
    T = arm.fk(random_q(arm, np.random.default_rng(seed)))
    res = solve_quietly(arm, T)
    assert res.reach_distance == 0.0 and np.array_equal(res.target, T)
    assert np.abs(arm.fk(res.q) - T).max() <= 1e-10 * size(arm, T)


def off_plane(arm, T, delta):
    """``T`` with the TCP moved by ``delta`` along the normal of the swept plane (world)."""
    out = T.copy()
    out[:3, 3] += delta * swept_plane(arm)[1]
    return out


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@pytest.mark.parametrize("delta", [1e-2, -1e-2, "2 tol", "10 scale"])
def test_poses_further_off_stay_unreachable_with_the_distance(name, mount, delta):
    arm = ARMS[name, mount]
    rng = np.random.default_rng(5)
    for _ in range(10):
        T = arm.fk(random_q(arm, rng))
        named = {"2 tol": 2 * ROUNDED_POSE_TOL * size(arm, T), "10 scale": 1e-2 * arm.scale}
        d = named.get(delta, delta)
        with pytest.raises(rikin.UnreachableError, match="5-DOF.*taken as rounded") as exc:
            solve_quietly(arm, off_plane(arm, T, d))
        assert exc.value.excess == pytest.approx(abs(d), rel=1e-9)
        assert exc.value.excess == pytest.approx(wrist_gap(arm, off_plane(arm, T, d)), rel=1e-9)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_half_the_tolerance_off_is_solved_and_reported(name, mount):
    arm = ARMS[name, mount]
    T = arm.fk([0.4, 2.0, 0.5, 0.7, 0.2])
    d = 0.5 * ROUNDED_POSE_TOL * size(arm, T)
    res = solve_quietly(arm, off_plane(arm, T, d))
    assert res.reach_distance == pytest.approx(d, rel=1e-9)
    assert np.abs(arm.fk(res.q) - res.target).max() <= 1e-12 * arm.scale
    assert np.abs(res.target - off_plane(arm, T, d)).max() <= d


@pytest.mark.parametrize("mount", [False, True])
def test_rprrr_wrist_centre_just_inside_the_cylinder(mount):
    """At d2 = -(a1 + a3) the wrist centre is on the cylinder r = a2; moved inside by rounding
    it is solved at the (radial singular) nearest pose, moved inside by 1e-2 it is refused."""
    arm = ARMS["rprrr", mount]
    T = arm.fk([0.3, -10.0, 0.5, 0.7, 0.2])
    a = swept_plane(arm)
    pw = (T @ np.append(centre_in_tcp(arm), 1.0))[:3]
    axis_point = arm.base[:3, 3] + np.dot(pw - arm.base[:3, 3], arm.base[:3, 2]) * arm.base[:3, 2]
    inward = (axis_point - pw) / np.linalg.norm(axis_point - pw)
    assert abs(inward @ a[1]) < 1e-12
    for eps, ok in ((1e-5, True), (1e-2, False)):
        G = T.copy()
        G[:3, 3] += eps * inward
        if ok:
            res = solve_quietly(arm, G)
            assert res.reach_distance == pytest.approx(eps, rel=1e-6)
            assert res.reach_distance == pytest.approx(wrist_gap(arm, G), rel=1e-6)
            assert "radial" in (res.singularity or "") or "a2" in (res.singularity or "")
            assert np.abs(arm.fk(res.q) - res.target).max() <= 1e-10 * arm.scale
        else:
            with pytest.raises(rikin.UnreachableError, match="inside the cylinder") as exc:
                solve_quietly(arm, G)
            assert exc.value.excess == pytest.approx(eps, rel=1e-6)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@pytest.mark.parametrize("how", [4, 6, "float32"])
def test_batch_solves_rounded_poses_as_one_pose_does(name, mount, how):
    arm = ARMS[name, mount]
    rng = np.random.default_rng(9)
    T = arm.fk(np.stack([random_q(arm, rng) for _ in range(40)]))
    G = np.stack([rounded(t, how) for t in T])
    G[::4] = T[::4]  # some exact
    G[1::8] = np.stack([off_plane(arm, t, 1e-2) for t in T[1::8]])  # some far off
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b = arm.ik_batch(G)
    assert b.reach_distance.shape == (40,)
    assert np.all(b.reach_distance[::4] == 0)
    assert not b.valid[1::8].any() and np.all(b.reach_distance[1::8] == 0)
    for i in range(40):
        if i % 8 == 1:
            continue
        single = arm.ik(G[i])
        # the same distance to rounding: it is a difference of nearby poses, so its absolute
        # precision is that of the pose entries (a few ulps of the arm's size), not 1e-12 of
        # itself (the batch's stacked products round differently from the one pose's, by
        # 1e-11 relative on a 1e-4 distance with base and tool on this project's CI CPU)
        assert b.reach_distance[i] == pytest.approx(
            single.reach_distance, rel=1e-12, abs=1e-13 * size(arm, G[i]))
        q = b.q[i][b.valid[i]]
        assert len(q) == FULL[name]
        tol = 1e-12 if single.reach_distance > 0 else 1e-8  # as in the one-pose test
        assert np.abs(arm.fk(q) - single.target).max() <= tol * size(arm, G[i])
    if how == 4:
        assert np.all(b.reach_distance[2::4] > 0)


def test_other_arms_report_no_reach_distance():
    arm = robots.aula10_6r()
    T = arm.fk([0.3, -1.2, 2.0, 0.4, -0.7, 3.0])
    assert arm.ik(T).reach_distance == 0.0  # the one-pose fast path
    assert arm.ik(np.round(T, 4)).reach_distance == 0.0  # the general path
    b = arm.ik_batch(np.stack([T, np.round(T, 4)]))
    assert np.array_equal(b.reach_distance, [0.0, 0.0])


# ------------------------------------------------------------------ numerical IK, same poses
def _numerical(arm, T, q0, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return ik_numerical(arm, T, q0, **options)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), how=st.sampled_from([4, 6, "float32"]),
       full_mask=st.booleans())
def test_numerical_ik_solves_rounded_poses_for_the_nearest_reachable_pose(
        name, mount, seed, how, full_mask):
    """ik_numerical on the poses arm.ik takes (a whole 6-D pose of a 5-DOF arm, rounded):
    converges, to the nearest reachable pose, and says how far the given one was."""
    arm = ARMS[name, mount]
    rng = np.random.default_rng(seed)
    q_true = random_q(arm, rng)
    G = rounded(arm.fk(q_true), how)
    s = size(arm, G)
    q0 = q_true + np.where(arm.revolute, 0.05, 0.05 * arm.scale) * rng.uniform(-1, 1, 5)
    sol = _numerical(arm, G, q0, mask=(1,) * 6 if full_mask else None)
    assert sol.success, sol.reason
    assert np.abs(arm.fk(sol.q) - sol.target).max() <= 1e-9 * s
    want = wrist_gap(arm, polar(G))
    if sol.reach_distance > 0:
        assert sol.reach_distance == pytest.approx(want, rel=1e-6)
        best = nearest_by_joint_least_squares(arm, polar(G), q_true)
        assert np.abs(best - sol.target)[:3].max() <= 1e-9 * s
        res = solve_quietly(arm, G)  # the same pose as arm.ik's, whenever arm.ik moved it
        if res.reach_distance > 0:
            assert sol.reach_distance == pytest.approx(res.reach_distance, rel=1e-12)
            assert np.abs(sol.target - res.target).max() <= 1e-13 * s
    else:  # reachable as given to the iteration's own tolerance
        assert want <= 1e-10 * s
        assert np.array_equal(sol.target, polar(G) if sol.rotation_distance else G)
    assert np.abs(sol.target - G).max() <= ROUNDED_POSE_TOL * s
    if how == 4:
        assert sol.rotation_distance > 0


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_numerical_ik_of_four_decimal_poses_moves_them_as_arm_ik_does(name, mount):
    arm = ARMS[name, mount]
    rng = np.random.default_rng(3)
    moved = 0
    for _ in range(20):
        q_true = random_q(arm, rng)
        G = np.round(arm.fk(q_true), 4)
        sol = _numerical(arm, G, q_true)
        res = solve_quietly(arm, G)
        assert sol.success, sol.reason
        assert (sol.reach_distance > 0) == (res.reach_distance > 0)
        assert sol.reach_distance == pytest.approx(res.reach_distance, rel=1e-12)
        moved += res.reach_distance > 0
    assert moved >= 15


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_numerical_ik_of_exact_poses_solves_them_as_given(name, mount):
    arm = ARMS[name, mount]
    rng = np.random.default_rng(4)
    for _ in range(10):
        q_true = random_q(arm, rng)
        T = arm.fk(q_true)
        sol = _numerical(arm, T, q_true + 0.01)
        assert sol.success and sol.reach_distance == 0.0 and sol.rotation_distance == 0.0
        assert np.array_equal(sol.target, T)
        assert np.abs(arm.fk(sol.q) - T).max() <= 1e-9 * size(arm, T)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@pytest.mark.parametrize("delta", [1e-2, "2 tol"])
def test_numerical_ik_of_poses_further_off_is_unreachable_by_how_much(name, mount, delta):
    arm = ARMS[name, mount]
    T = arm.fk([0.4, 2.0, 0.5, 0.7, 0.2])
    d = 2 * ROUNDED_POSE_TOL * size(arm, T) if delta == "2 tol" else delta
    far = off_plane(arm, T, d)
    for call in (lambda: _numerical(arm, far, None),
                 lambda: ik_numerical_multistart(arm, far, 3)):
        with pytest.raises(rikin.UnreachableError, match="5-DOF.*taken as rounded") as exc:
            call()
        assert exc.value.excess == pytest.approx(abs(d), rel=1e-9)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_numerical_multistart_finds_every_solution_of_a_rounded_pose(name, mount):
    arm = ARMS[name, mount]
    G = np.round(arm.fk([0.4, 2.0, 0.5, 0.7, 0.2]), 4)
    res = solve_quietly(arm, G)
    assert res.reach_distance > 0
    found = ik_numerical_multistart(arm, G, 24, rng=1)
    assert len(found) == FULL[name]
    for q in found:
        assert np.abs(arm.fk(q) - res.target).max() <= 1e-9 * size(arm, G)


def test_numerical_ik_of_other_arms_is_unchanged():
    """A 6R arm reaches every pose near its workspace: a rounded pose is solved as given
    (nearest rotation only); a 5-DOF arm of one's own, with no closed form to say which poses
    it reaches, still needs a mask. (The PPRRR typed from its table has one since issue 29:
    its rounded poses are solved as the lesson arm's are.)"""
    arm = robots.aula10_6r()
    q = np.array([0.3, -1.2, 2.0, 0.4, -0.7, 3.0])
    G = np.round(arm.fk(q), 4)
    sol = _numerical(arm, G, q)
    assert sol.success and sol.reach_distance == 0.0 and sol.rotation_distance > 0
    own = rikin.SerialArm(robots.aula10_6r().links[:5])
    assert own.solver is None and not rikin.ik.classify(own).closed_form
    with pytest.raises(rikin.InputError, match="mask"):
        ik_numerical(own, own.fk([1.0, 2.0, 0.3, 0.4, 0.5]))
    typed = rikin.SerialArm(robots.pprrr().links)
    qp = np.array([1.0, 2.0, 0.3, 0.4, 0.5])
    Gp = np.round(typed.fk(qp), 4)
    a, b = _numerical(typed, Gp, qp), _numerical(robots.pprrr(), Gp, qp)
    assert a.success and b.reach_distance > 0
    assert a.reach_distance == pytest.approx(b.reach_distance)
