"""The general closed-form IK of 6R arms with a spherical wrist (rikin.ik.pieper).

Every solution is put back through FK here (independently of the solver's own
check); the generating joints must be among the solutions; lesson arms solved
through their DH table alone must give the lesson solvers' solution sets and
branch labels; arms without a closed form must say why in the arm's terms.
"""

import math
import warnings
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from singular_poses import CROSSING_JOINT, off_axis, singular_q, wrist_centre

import rikin
from rikin import Link, SerialArm, robots
from rikin.ik import classify

pi = np.pi
POS_TOL = 1e-9  # times the arm's size
ROT_TOL = 1e-9
SAME_Q = 1e-6


# ------------------------------------------------------------------ arms from their DH tables
def puma560():
    """Standard-DH Puma 560 (Corke's table, metres): shoulder offset d3, elbow offset a3."""
    return SerialArm((
        Link(d=0.6718, alpha=pi / 2), Link(a=0.4318), Link(d=0.15005, a=0.0203, alpha=-pi / 2),
        Link(d=0.4318, alpha=pi / 2), Link(alpha=-pi / 2), Link(),
    ), name="Puma 560", units="m")


def kuka_kr5():
    """Standard-DH KUKA KR5 (metres): shoulder offset a1, alpha1 = +pi/2, flipped flange."""
    return SerialArm((
        Link(d=0.4, a=0.18, alpha=pi / 2), Link(a=0.6), Link(a=0.12, alpha=pi / 2),
        Link(d=-0.62, alpha=-pi / 2), Link(alpha=pi / 2), Link(d=-0.115, alpha=pi),
    ), name="KUKA KR5", units="m")


def kuka_kr6():
    """Standard-DH KUKA KR6 (metres): alpha1 = -pi/2, joint-3 offset."""
    return SerialArm((
        Link(d=0.675, a=0.26, alpha=-pi / 2), Link(a=0.68),
        Link(a=-0.035, alpha=pi / 2, offset=-pi / 2),
        Link(d=-0.67, alpha=-pi / 2), Link(alpha=pi / 2), Link(d=-0.115, alpha=pi),
    ), name="KUKA KR6", units="m")


def abb_irb120():
    """Standard-DH ABB IRB 120 (metres): joint offsets on 2 and 6."""
    return SerialArm((
        Link(d=0.29, alpha=-pi / 2), Link(a=0.27, offset=-pi / 2), Link(a=0.07, alpha=-pi / 2),
        Link(d=0.302, alpha=pi / 2), Link(alpha=-pi / 2), Link(d=0.072, offset=pi),
    ), name="ABB IRB 120", units="m")


def ur5():
    """Standard-DH UR5: no spherical wrist (d5 separates axes 5 and 6)."""
    return SerialArm((
        Link(d=0.089159, alpha=pi / 2), Link(a=-0.425), Link(a=-0.39225),
        Link(d=0.10915, alpha=pi / 2), Link(d=0.09465, alpha=-pi / 2), Link(d=0.0823),
    ), name="UR5", units="m")


def from_table(arm):
    """The same arm built from its DH table alone (no lesson solver attached)."""
    return SerialArm(arm.links, convention=arm.convention, base=arm.base, tool=arm.tool,
                     units=arm.units, name=arm.name + " (table)")


INDUSTRIAL = [puma560, kuka_kr5, kuka_kr6, abb_irb120]
LESSON_6R = [robots.aula10_6r, robots.epson_c4, robots.barrientos_6r]


def fk_errors(arm, q, T):
    F = arm.fk(q)
    pos = np.linalg.norm(F[..., :3, 3] - T[:3, 3], axis=-1) / arm.scale
    rot = np.abs(F[..., :3, :3] - T[:3, :3]).max(axis=(-1, -2))
    return pos, rot


def assert_all_reach(arm, res, T):
    pos, rot = fk_errors(arm, res.q, T)
    assert pos.max() <= POS_TOL and rot.max() <= ROT_TOL, (pos.max(), rot.max())


NEAR_WRIST = 1e-6  # wrist axes this close to aligned or coplanar: a singular wrist
SINGULAR_WRIST_Q = 1e-4  # what such a pose fixes q4..q6 to (~ the square root of rounding)


def distance_to(res, q, arm=None):
    """Joint distance from ``q`` to the nearest solution.

    At a wrist singularity the pose fixes q4..q6 far less well than the rest: with axes 4
    and 6 aligned only their sum or difference, with the three wrist axes coplanar (a
    non-orthogonal wrist at q5 = 0 or pi) each to about the square root of the pose's
    rounding. There q4..q6 are compared to ``SINGULAR_WRIST_Q``; the FK check of every
    solution (assert_all_reach) still holds them to the pose.
    """
    d = np.abs(rikin.wrap_angle(res.q - q))
    if arm is not None:
        F = arm.fk(q, frames=True)
        k = 3 if arm.convention == "standard" else 4  # frame whose z is axis 4
        z4, z5, z6 = F[k, :3, 2], F[k + 1, :3, 2], F[k + 2, :3, 2]
        aligned = np.linalg.norm(np.cross(z4, z6)) < NEAR_WRIST
        coplanar = abs(np.linalg.det(np.stack([z4, z5, z6]))) < NEAR_WRIST
        if aligned:
            d = d[:, [0, 1, 2, 4]]
        elif coplanar:
            d = np.concatenate([d[:, :3], d[:, 3:] * (SAME_Q / SINGULAR_WRIST_Q)], axis=1)
    return d.max(axis=1).min()


def random_pose(rng):
    return rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-pi, pi, 3)), rng.uniform(-1, 1, 3))


# ------------------------------------------------------------------ classify
def test_classify_names_the_closed_form():
    assert "quadratic" in str(classify(puma560()))  # axes 1 and 2 meet (a1 = 0)
    # a1 != 0 and alpha1 = -90 deg, axes 2 and 3 parallel: the quartic is a quadratic in
    # the squared shoulder-wrist distance (what the kernel solves, _th3_planar)
    assert "quadratic" in str(classify(kuka_kr5()))
    skew = SerialArm((replace(kuka_kr5().links[0], alpha=pi / 3),) + kuka_kr5().links[1:],
                     units="mm")
    assert "quartic" in str(classify(skew))  # a1 != 0 and alpha1 not 0 or 90 deg: skew
    assert classify(robots.aula10_6r()).closed_form  # the lesson solver


def test_classify_says_why_not_in_the_arms_terms():
    c = classify(ur5())  # another family, and why not the spherical wrist
    assert c.closed_form and c.family.startswith("three parallel axes (2, 3, 4), like a UR arm")
    assert "axes 4, 5, 6 do not meet: axis 6 passes 0.09465 m" in c.family
    offset = SerialArm(kuka_kr5().links[:3] + (
        Link(d=-620.0, a=12.0, alpha=-pi / 2), Link(alpha=pi / 2), Link(d=-115.0)
    ), units="mm")
    assert "general 6R: up to 16 solutions" in classify(offset).family
    assert "axis 5 passes 12 mm from axis 4" in classify(offset).family
    prismatic = SerialArm((Link(), Link("P", alpha=pi / 2)) + puma560().links[2:])
    assert "joint 2 is prismatic" in classify(prismatic).reason
    assert "5 joints" in classify(SerialArm(puma560().links[:5])).reason


def test_ik_of_an_arm_without_closed_form_points_at_numerical_ik():
    # the UR5 with axis 1 parallel to axes 2-4: outside every family
    arm = SerialArm((Link(d=0.089159),) + ur5().links[1:])
    with pytest.raises(rikin.InputError, match=r"axis 6 passes .*ik_numerical"):
        arm.ik(arm.fk(np.full(6, 0.3)))


# ------------------------------------------------------------------ the lesson arms
@pytest.mark.parametrize("make", LESSON_6R)
def test_lesson_arms_from_their_table_match_the_lesson_solver(make):
    rng = np.random.default_rng(7)
    base = random_pose(rng)
    tool = random_pose(rng)
    for arm in (make(), make(base=base, tool=tool)):
        general = from_table(arm)
        for _ in range(60):
            T = arm.fk(rng.uniform(-pi, pi, 6))
            lesson, other = arm.ik(T), general.ik(T)
            assert len(lesson) == len(other)
            assert_all_reach(general, other, T)
            for q, label in zip(lesson.q, lesson.labels, strict=True):
                d = np.abs(rikin.wrap_angle(other.q - q)).max(axis=1)
                j = int(np.argmin(d))
                assert d[j] < 1e-9
                assert other.labels[j] == label


# ------------------------------------------------------------------ industrial arms
@pytest.mark.parametrize("make", INDUSTRIAL)
def test_industrial_arms_round_trip(make):
    arm = make()
    rng = np.random.default_rng(11)
    counts = []
    for _ in range(150):
        q = rng.uniform(-pi, pi, 6)
        T = arm.fk(q)
        res = arm.ik(T)
        assert_all_reach(arm, res, T)
        assert distance_to(res, q) < SAME_Q
        assert len(set(res.labels)) == len(res)  # every solution its own branch
        counts.append(len(res))
    assert max(counts) == 8


@pytest.mark.parametrize("make", INDUSTRIAL)
def test_batch_matches_single_pose(make):
    arm = make()
    rng = np.random.default_rng(5)
    q = rng.uniform(-pi, pi, (40, 6))
    T = arm.fk(q)
    batch = arm.ik_batch(T)
    assert batch.valid.shape == (40, 8)
    for i in range(40):
        single = arm.ik(T[i])
        got = batch.q[i][batch.valid[i]]
        assert len(got) >= len(single)
        for row in single.q:
            assert np.abs(rikin.wrap_angle(got - row)).max(axis=1).min() < 1e-9
        pos, rot = fk_errors(arm, got, T[i])
        assert pos.max() <= POS_TOL and rot.max() <= ROT_TOL


# ------------------------------------------------------------------ random tables
angle = st.floats(-pi, pi, allow_nan=False)
# Exact zeros as tables are typed, else values away from zero: a table with a2 = 1e-5 next
# to a3 = 1 is a near-degenerate arm whose joints the pose fixes only to ~eps / 1e-5.
special_twist = st.sampled_from([0.0, pi / 2, -pi / 2, pi])
twist = st.one_of(special_twist, st.floats(0.1, 3.0), st.floats(-3.0, -0.1))
wrist_twist = st.one_of(st.sampled_from([pi / 2, -pi / 2]), st.floats(0.3, 2.8),
                        st.floats(-2.8, -0.3))
length = st.one_of(st.just(0.0), st.floats(0.05, 2.0), st.floats(-2.0, -0.05))


@st.composite
def spherical_wrist_arms(draw):
    convention = draw(st.sampled_from(["standard", "modified"]))
    a = [draw(length) for _ in range(3)]
    d = [draw(length) for _ in range(4)]
    al = [draw(twist) for _ in range(3)]
    b1, b2 = draw(wrist_twist), draw(wrist_twist)
    off = [draw(st.one_of(st.just(0.0), angle)) for _ in range(6)]
    d6, a6, al6 = draw(length), draw(length), draw(twist)
    if convention == "standard":
        links = [Link(d=d[i], a=a[i], alpha=al[i], offset=off[i]) for i in range(3)]
        links += [Link(d=d[3], alpha=b1, offset=off[3]), Link(alpha=b2, offset=off[4]),
                  Link(d=d6, a=a6, alpha=al6, offset=off[5])]
    else:  # link i holds alpha_{i-1}, a_{i-1}; the wrist: a4 = d5 = a5 = 0
        links = [Link(alpha=al[0], a=a[0], d=d[0], offset=off[0]),
                 Link(alpha=al[1], a=a[1], d=d[1], offset=off[1]),
                 Link(alpha=al[2], a=a[2], d=d[2], offset=off[2]),
                 Link(alpha=draw(twist), a=draw(length), d=d[3], offset=off[3]),
                 Link(alpha=b1, offset=off[4]), Link(alpha=b2, d=d6, offset=off[5])]
    rpy = [draw(angle), draw(st.floats(-1.5, 1.5)), draw(angle)]
    base = rikin.homogeneous(rikin.rpy_to_r(*rpy), [draw(st.floats(-1, 1)) for _ in range(3)])
    tool = rikin.homogeneous(rikin.rpy_to_r(draw(angle), 0.3, draw(angle)),
                             [draw(st.floats(-1, 1)) for _ in range(3)])
    arm = SerialArm(tuple(links), convention=convention, base=base, tool=tool)
    return arm


@settings(max_examples=150, deadline=None)
@given(spherical_wrist_arms(), st.lists(angle, min_size=6, max_size=6))
def test_random_spherical_wrist_tables_round_trip(arm, q):
    c = classify(arm)
    if not c.closed_form:  # degenerate draws (axes 1-2 or 2-3 the same line, ...)
        assert c.reason
        return
    q = np.array(q)
    T = arm.fk(q)
    res = arm.ik(T, near=q)  # at a singularity the free joints come from near
    assert_all_reach(arm, res, T)
    assert distance_to(res, q, arm) < SAME_Q


def test_non_orthogonal_wrist_round_trip_and_unreachable_orientation():
    arm = SerialArm(puma560().links[:3] + (
        Link(d=0.4318, alpha=math.radians(60)), Link(alpha=math.radians(-45)), Link(d=0.05),
    ), name="tilted wrist", units="m")
    rng = np.random.default_rng(3)
    for _ in range(100):
        q = rng.uniform(-pi, pi, 6)
        T = arm.fk(q)
        res = arm.ik(T)
        assert_all_reach(arm, res, T)
        assert distance_to(res, q) < SAME_Q
    # axis 6 can only make 15..105 degrees with axis 4: orientations asking for less or more,
    # at a wrist centre joints 1-3 reach, are out of reach; numerical IK must agree
    T0 = arm.fk(np.array([0.3, -0.5, 0.4, 0.0, 0.7, 0.0]))
    centre = T0[:3, 3] - 0.05 * T0[:3, 2]
    raised = 0
    for _ in range(40):
        R = rikin.rpy_to_r(*rng.uniform(-pi, pi, 3))
        T = rikin.homogeneous(R, centre + 0.05 * R[:, 2])
        try:
            res = arm.ik(T)
        except rikin.UnreachableError as err:
            raised += 1
            assert "cannot tilt" in str(err) and err.excess > 0
            if raised <= 2:
                num = rikin.ik.ik_numerical_multistart(arm, T, 30, rng=1)
                assert len(num) == 0
        else:
            assert_all_reach(arm, res, T)
    assert raised > 0


# ------------------------------------------------------------------ singular poses
def test_wrist_singularity_is_flagged_with_its_free_joints():
    arm = puma560()
    q = np.array([0.3, -0.4, 0.5, 0.7, 0.0, -0.2])
    res = arm.ik(arm.fk(q), near=q)
    assert res.singular and 4 in res.free_joints and 6 in res.free_joints
    assert distance_to(res, q) < SAME_Q
    assert_all_reach(arm, res, arm.fk(q))


def test_shoulder_singularity_wrist_centre_on_axis_1():
    """Aula 10 from its table with the wrist centre straight above the base: q1 is free."""
    arm = from_table(robots.aula10_6r())
    R = rikin.rpy_to_r(0.3, -0.4, 1.1)
    T = rikin.homogeneous(R, np.array([0.0, 0.0, 25.0]) + 20.0 * R[:, 2])  # centre (0, 0, 25)
    for hint in (0.0, 0.7):
        near = np.array([hint, 0, 0, 0, 0, 0])
        res = arm.ik(T, near=near)
        assert res.singular and 1 in res.free_joints
        assert_all_reach(arm, res, T)
        assert np.allclose(rikin.wrap_angle(res.q[:, 0] - hint), 0.0)  # q1 from near


def test_elbow_at_full_reach_gives_the_coinciding_branches_once():
    arm = from_table(robots.aula10_6r())
    lesson = robots.aula10_6r()
    q = np.array([0.2, 0.3, 0.0, 0.5, 0.6, 0.7])  # q3 = 0 is the stretched elbow of Aula 10?
    # find the stretched q3: where the wrist centre is farthest from the shoulder
    best = max(np.linspace(-pi, pi, 721), key=lambda t: np.linalg.norm(
        lesson.fk(np.r_[q[:2], t, q[3:]])[:3, 3] - [0, 0, 12]))
    q[2] = best
    T = lesson.fk(q)
    a, b = lesson.ik(T), arm.ik(T)
    assert len(a) == len(b)
    assert_all_reach(arm, b, T)


# ------------------------------------------------------------------ unreachable
@pytest.mark.parametrize("make", [robots.aula10_6r, robots.epson_c4])
def test_unreachable_says_by_how_much_like_the_lesson_solver(make):
    lesson = make()
    general = from_table(lesson)
    T = lesson.fk(np.zeros(6))
    T[:3, 3] *= 4.0
    with pytest.raises(rikin.UnreachableError) as want:
        lesson.ik(T)
    with pytest.raises(rikin.UnreachableError, match="out of reach of joints 1-3") as got:
        general.ik(T)
    assert got.value.excess == pytest.approx(want.value.excess, rel=1e-6)
    assert str(got.value).count(f"{got.value.excess:.4g}") == 1  # said once, not twice


# ------------------------------------------------------------------ complete sets, singular poses
# The singular poses come from singular_poses.py: built from the arm's geometry alone.
def epson_c4_table():
    return from_table(robots.epson_c4())


GENERAL = INDUSTRIAL + [epson_c4_table]


# ------------------------------------------------------------------ magnitudes
def scaled(arm, s):
    """``arm`` with every length (links, base and tool offsets) times ``s``."""
    def grow(T):
        T = T.copy()
        T[:3, 3] *= s
        return T

    links = tuple(Link(a=lk.a * s, d=lk.d * s, alpha=lk.alpha, offset=lk.offset)
                  for lk in arm.links)
    return SerialArm(links, convention=arm.convention, base=grow(arm.base),
                     tool=grow(arm.tool), units=arm.units, name=f"{arm.name} x {s:g}")


@pytest.mark.parametrize("s", [1e-90, 1e-50, 1e-8, 1e8, 1e50, 1e90])
@pytest.mark.parametrize("make", GENERAL)
def test_scaled_tables_solve_every_reachable_target(make, s):
    """Any size rikin takes (lengths 1e-100 to 1e100): the closed form's quartic is of
    degree 4 in the lengths, so at 1e90 it overflowed (RuntimeWarning, no solution) and at
    1e-90 it underflowed (every target 'out of reach by 1e-95'), on the arms whose axes 1
    and 2 are skew (KR5, KR6, IRB 120, C4)."""
    rng = np.random.default_rng(23)
    arm = make()
    base, tool = random_pose(rng), random_pose(rng)
    base[:3, 3] *= 0.3 * arm.scale
    tool[:3, 3] *= 0.1 * arm.scale
    arm = scaled(arm.replace(base=base, tool=tool), s)
    q = rng.uniform(-pi, pi, (8, 6))
    T = arm.fk(q)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for k in range(len(q)):
            res = arm.ik(T[k])
            assert_all_reach(arm, res, T[k])
            assert np.abs(rikin.wrap_angle(res.q - q[k])).max(axis=1).min() < 1e-8
        batch = arm.ik_batch(T)
        assert batch.valid.any(axis=1).all()
        far = T[0].copy()
        far[:3, 3] *= 1e3
        with pytest.raises(rikin.UnreachableError) as err:
            arm.ik(far)
    assert 0 < err.value.excess < 1e4 * arm.scale


KINDS = list(CROSSING_JOINT)


def sigma_ratio(arm, q):
    """Smallest over largest singular value of the Jacobian, positions over the arm's size."""
    J = arm.jacobian(q)
    J = np.concatenate([J[:3] / arm.scale, J[3:]])
    s = np.linalg.svd(J, compute_uv=False)
    return s[-1] / s[0]


def indistinguishable(arm, T, q, Q):
    """Some row of ``Q`` is joined to ``q`` by a straight joint path on which every point
    reaches ``T`` within the FK tolerance."""
    for row in Q:
        path = q + np.outer(np.linspace(0, 1, 11), rikin.wrap_angle(row - q))
        pos, rot = fk_errors(arm, path, T)
        if pos.max() <= POS_TOL and rot.max() <= ROT_TOL:
            return True
    return False


def near_axis2(arm, q, Q):
    """The wrist centre within 1e-5 of the arm's size from axis 2 (the Epson C4 folded:
    a2 = |d4| puts it on axis 2), where q2 and the wrist are fixed only loosely: some row
    of ``Q`` then has q1 and q3 of ``q``."""
    if np.linalg.norm(off_axis(arm, q, 2)) > 1e-5 * arm.scale:
        return False
    return np.abs(rikin.wrap_angle(Q[:, [0, 2]] - q[[0, 2]])).max(axis=1).min() < SAME_Q


def assert_distinct(res):
    if len(res) > 1:
        d = np.abs(rikin.wrap_angle(res.q[:, None] - res.q[None])).max(-1)
        assert d[~np.eye(len(res), dtype=bool)].min() > 1e-9


def brute_force_positions(arm, T, q_wrist):
    """Joints 2, 3 of every way joints 1-3 put the wrist centre where ``T`` needs it, by a
    grid over (q2, q3) and Newton: joint 1 keeps the centre's height along axis 1 and its
    distance from it, so those two numbers fix (q2, q3); q1 then follows."""
    o, z = arm.joint_axes(q_wrist)
    o1, z1 = o[0], z[0]

    def invariants(Q):
        shape = Q.shape[:-1]
        v = wrist_centre(arm, Q.reshape(-1, 6)).reshape(shape + (3,)) - o1
        h = v @ z1
        return np.stack([h, np.linalg.norm(v - h[..., None] * z1, axis=-1)], axis=-1)

    goal = invariants(q_wrist[None])[0]
    g = np.linspace(-pi, pi, 121)[:-1]
    G2, G3 = np.meshgrid(g, g, indexing="ij")
    Q = np.zeros((G2.size, 6))
    Q[:, 1], Q[:, 2] = G2.ravel(), G3.ravel()
    E = np.linalg.norm(invariants(Q) - goal, axis=-1).reshape(G2.shape)
    minima = E <= np.minimum.reduce([np.roll(E, s, a) for s in (-1, 1) for a in (0, 1)])
    X = np.stack([G2[minima], G3[minima]], axis=-1)  # seeds, Newton on all at once
    H = np.array([[0.0, 0.0], [1e-7, 0], [-1e-7, 0], [0, 1e-7], [0, -1e-7]])
    for _ in range(40):
        Q = np.zeros((len(X), 5, 6))
        Q[..., 1:3] = X[:, None, :] + H
        V = invariants(Q) - goal  # (k, 5, 2)
        J = np.stack([V[:, 1] - V[:, 2], V[:, 3] - V[:, 4]], axis=-1) / 2e-7
        step = np.linalg.lstsq(J[0], V[0, 0], rcond=None)[0] if len(X) == 1 else np.stack(
            [np.linalg.lstsq(Jk, r, rcond=None)[0] for Jk, r in zip(J, V[:, 0], strict=True)])
        X = rikin.wrap_angle(X - np.clip(step, -0.2, 0.2))
    Q = np.zeros((len(X), 6))
    Q[:, 1:3] = X
    ok = np.abs(invariants(Q) - goal).max(-1) < 1e-10 * arm.scale
    roots = []
    for x in X[ok]:
        if not any(np.abs(rikin.wrap_angle(x - y)).max() < 1e-6 for y in roots):
            roots.append(x)
    return np.array(roots)


@pytest.mark.parametrize("make", GENERAL)
def test_solution_count_matches_a_brute_force_count(make):
    """Twice (two wrist branches) as many solutions as a grid search finds ways to place the
    wrist centre, and joints 2-3 of each solution are one of those ways."""
    arm = make()
    rng = np.random.default_rng(23)
    for _ in range(2):
        q = rng.uniform(-pi, pi, 6)
        q[4] = rng.uniform(0.3, 2.8) - float(arm.links[4].offset)
        T = arm.fk(q)
        res = arm.ik(T)
        roots = brute_force_positions(arm, T, q)
        assert len(res) == 2 * len(roots), (len(res), len(roots))
        for row in res.q:
            assert np.abs(rikin.wrap_angle(roots - row[1:3])).max(axis=1).min() < 1e-7
        assert_all_reach(arm, res, T)
        assert_distinct(res)


def test_solutions_match_numerical_multistart():
    """Every solution numerical IK finds from 40 random starts is one of arm.ik's."""
    for make in (kuka_kr5, epson_c4_table):
        arm = make()
        rng = np.random.default_rng(4)
        q = rng.uniform(-pi, pi, 6)
        T = arm.fk(q)
        res = arm.ik(T)
        found = rikin.ik.ik_numerical_multistart(arm, T, 40, rng=5)
        assert len(found) >= 2
        for row in found:
            assert np.abs(rikin.wrap_angle(res.q - row)).max(axis=1).min() < 1e-6


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("make", GENERAL)
def test_near_singular_poses_keep_every_solution(make, kind):
    """Poses on and 1e-9..1e-5 rad off each singularity: every solution real and distinct,
    the generating joints among them (without any hint: both shoulders of a wrist centre
    just off axis 1 included)."""
    arm = make()
    rng = np.random.default_rng(KINDS.index(kind))
    for delta in (0.0, 1e-9, 1e-7, 1e-5):
        q = singular_q(arm, kind, rng)
        q[CROSSING_JOINT[kind]] += delta * rng.choice([-1, 1])
        T = arm.fk(q)
        res = arm.ik(T, near=q) if delta == 0 else arm.ik(T)
        if {1, 2} & set(res.free_joints):  # on the axis to within the tolerance: q1 or q2 free
            res = arm.ik(T, near=q)
        assert_all_reach(arm, res, T)
        assert_distinct(res)
        if kind in ("stretched", "folded") and delta <= 1e-7:
            # a pose within ~1e-16 of a fold fixes the joints only to ~1e-8 along it, more
            # where (Puma, folded) the wrist centre passes 0.5 mm from axis 2: the generating
            # joints must then be indistinguishable from a solution by the pose
            assert indistinguishable(arm, T, q, res.q) or near_axis2(arm, q, res.q)
        else:
            assert distance_to(res, q, arm) < SAME_Q, (kind, delta, distance_to(res, q, arm))


@pytest.mark.parametrize("make", [kuka_kr5, kuka_kr6, abb_irb120, epson_c4_table])
def test_wrist_centre_on_axis_1_is_a_shoulder_not_an_elbow_singularity(make):
    """With the wrist centre on axis 1 and the elbow bent, the two shoulders coincide (q1
    free): the result says so, and not that the wrist centre is at the edge of what joints
    1-3 reach (which the merge of the coinciding shoulders used to add)."""
    arm = make()
    rng = np.random.default_rng(11)
    for _ in range(3):
        q = singular_q(arm, "shoulder", rng)
        res = arm.ik(arm.fk(q), near=q)
        assert 1 in res.free_joints and "axis of joint 1" in res.singularity, res.singularity
        assert "edge of what joints 1-3 reach" not in res.singularity, res.singularity


def test_stretched_on_axis_1_is_both_singularities():
    """An arm without shoulder offset stretched straight along axis 1: the wrist centre is
    on the axis and at the edge of its reach, and the result names both."""
    arm = abb_irb120()
    q = singular_q(arm, "stretched", np.random.default_rng(2))
    q[4] = 0.6  # no wrist singularity as well
    for _ in range(60):  # q2 (then q3) onto the stretched line along axis 1
        r = off_axis(arm, q, 1)
        dq = np.zeros(6)
        dq[1] = 1e-7
        J = (off_axis(arm, q + dq, 1) - off_axis(arm, q - dq, 1)) / 2e-7
        q[1] -= float(J @ r / (J @ J))
    assert np.linalg.norm(off_axis(arm, q, 1)) < 1e-9 * arm.scale
    res = arm.ik(arm.fk(q), near=q)
    assert "axis of joint 1" in res.singularity, res.singularity
    assert "edge of what joints 1-3 reach" in res.singularity, res.singularity


@pytest.mark.parametrize("make", GENERAL)
def test_one_arm_configuration_one_shoulder_and_elbow_label(make):
    """Solutions with the same joints 1-3 (the wrist slots of one position branch) carry
    the same shoulder and elbow labels, also on and next to each singularity, where the
    elbow or the wrist centre lies on the line between two labels: the label may be
    either there, but not both for one arm configuration."""
    arm = make()
    rng = np.random.default_rng(5)
    seen = 0
    for kind in KINDS:
        for delta in (0.0, 0.0, 1e-12, 1e-9):
            q = singular_q(arm, kind, rng)
            q[CROSSING_JOINT[kind]] += delta * rng.choice([-1, 1])
            res = arm.ik(arm.fk(q), near=q)
            for i in range(len(res.q)):
                for j in range(i + 1, len(res.q)):
                    if np.abs(rikin.wrap_angle(res.q[i, :3] - res.q[j, :3])).max() < 1e-10:
                        seen += 1
                        a, b = res.branches[i], res.branches[j]
                        assert (a.shoulder, a.elbow) == (b.shoulder, b.elbow), (kind, delta, a, b)
    assert seen >= 10, seen


@pytest.mark.parametrize("make", [kuka_kr5, kuka_kr6, abb_irb120, epson_c4_table])
def test_a_free_joint_comes_from_near_or_else_from_the_pose(make):
    """A wrist centre ~1e-11 of the arm's size off axis 1 is flagged (q1 free within
    SINGULAR_TOL: any q1 reproduces the pose within the FK check), yet the pose still fixes
    q1 to ~1e-5 rad. Without near, q1 is the pose's (the generating q among the solutions),
    not an arbitrary 0; with near, near's."""
    arm = make()
    rng = np.random.default_rng(31)
    for _ in range(3):
        q = singular_q(arm, "shoulder", rng)
        q[1] += 1e-10 * rng.choice([-1, 1])  # the centre ~1e-10 x its distance off the axis
        off = np.linalg.norm(off_axis(arm, q, 1)) / arm.scale
        assert 1e-13 < off < 1e-9, off
        T = arm.fk(q)
        res = arm.ik(T)
        assert res.singular and 1 in res.free_joints
        assert_all_reach(arm, res, T)
        assert distance_to(res, q, arm) < 1e-4, distance_to(res, q, arm)
        near = q.copy()
        near[0] += 0.7
        moved = arm.ik(T, near=near)
        assert_all_reach(arm, moved, T)
        # from near, up to what the polish moves it towards the pose's root (~1e-4 rad)
        assert np.abs(rikin.wrap_angle(moved.q[:, 0] - near[0])).min() < 1e-3


# The Puma's shoulder offset keeps its wrist centre 0.15 m from axis 1: onto_axis1 (a
# least-squares minimum) does not land on that fold exactly enough to be one, so that
# combination is left to the near-singular test above.
@pytest.mark.parametrize(("make", "kind"), [
    (make, kind) for make in GENERAL for kind in KINDS
    if not (make is puma560 and kind == "shoulder")
])
def test_singular_poses_flagged_with_free_joints_that_are_free(make, kind):
    """On the singularity: flagged; each free joint takes any value from near (and the pose
    still holds); a singularity without free joints is a fold (Jacobian rank-deficient)."""
    arm = make()
    rng = np.random.default_rng(10 + KINDS.index(kind))
    q = singular_q(arm, kind, rng)
    T = arm.fk(q)
    res = arm.ik(T, near=q)
    on_axis1 = np.linalg.norm(off_axis(arm, q, 1)) < 1e-9 * arm.scale
    if kind.startswith("wrist"):
        assert res.singular and {4, 6} <= set(res.free_joints)
    elif kind == "shoulder" and on_axis1:
        assert res.singular and 1 in res.free_joints
    elif not res.singular and near_axis2(arm, q, res.q):
        assert_all_reach(arm, res, T)
        return
    elif not res.singular:
        # a fold (elbow stretched or folded; the Puma's wrist centre nearest axis 1): built
        # to ~1e-8 rad, where the pose is at the fold to rounding but the two coinciding
        # branches can still differ by ~1e-5 rad in a joint the fold amplifies. Unflagged,
        # both must be there: two solutions that close, both at a singular Jacobian
        d = np.abs(rikin.wrap_angle(res.q[:, None] - res.q[None])).max(-1)
        d[np.eye(len(res), dtype=bool)] = np.inf
        i, j = np.unravel_index(int(np.argmin(d)), d.shape)
        assert d[i, j] < 1e-4, d[i, j]
        assert max(sigma_ratio(arm, res.q[i]), sigma_ratio(arm, res.q[j])) < 1e-4
        return
    # joint 4 of the pair (4, 6), whose sum or difference alone the pose fixes, 1 and 2 alone
    for j in {4 if j == 6 else j for j in res.free_joints}:
        near = q.copy()
        near[j - 1] += 0.7
        moved = arm.ik(T, near=near)
        assert_all_reach(arm, moved, T)
        # from near, up to the polish of a centre ~1e-12 off the axis (q1 then moves ~1e-8)
        assert np.abs(rikin.wrap_angle(moved.q[:, j - 1] - near[j - 1])).min() < SAME_Q
    if not res.free_joints:
        assert "edge" in res.singularity
        assert min(sigma_ratio(arm, row) for row in res.q) < 1e-6


@pytest.mark.parametrize("twists", [(60, -45), (60, -60), (60, 60), (-70, 110)])
def test_non_orthogonal_wrist_singularities_flagged(twists):
    """q5 = 0 or pi on a wrist with twists other than 90 deg: axes 4 and 6 line up only when
    the twists cancel (q4, q6 free); otherwise axes 4, 5, 6 lie in one plane, the tilt of
    the tool is at this wrist's least or most and its two branches coincide: flagged, no
    free joint, a rank-deficient Jacobian. Just off it both branches come back."""
    b1, b2 = np.radians(twists)
    arm = SerialArm(puma560().links[:3] + (
        Link(d=0.4318, alpha=b1), Link(alpha=b2), Link(d=0.05),
    ), name="tilted wrist", units="m")
    rng = np.random.default_rng(31)
    for th5 in (0.0, pi):
        q = rng.uniform(-pi, pi, 6)
        q[4] = th5
        T = arm.fk(q)
        res = arm.ik(T, near=q)
        _, z = arm.joint_axes(q)
        aligned = np.linalg.norm(np.cross(z[3], z[5])) < 1e-9
        assert_all_reach(arm, res, T)
        assert distance_to(res, q, arm) < SAME_Q
        assert res.singular
        if aligned:
            assert {4, 6} <= set(res.free_joints)
            near = q.copy()
            near[3] += 0.7
            moved = arm.ik(T, near=near)
            assert_all_reach(arm, moved, T)
            assert np.abs(rikin.wrap_angle(moved.q[:, 3] - near[3])).min() < SAME_Q
        else:
            assert res.free_joints == () and "one plane" in res.singularity
            j = int(np.argmin(np.abs(rikin.wrap_angle(res.q - q)).max(axis=1)))
            assert sigma_ratio(arm, res.q[j]) < 1e-6
        # just off the singularity: not flagged there, both wrist branches (+-q5) back
        q[4] = th5 + 1e-3
        T = arm.fk(q)
        off = arm.ik(T)
        assert_all_reach(arm, off, T)
        assert distance_to(off, q) < SAME_Q
        if not off.singular:
            assert len(off) % 2 == 0
