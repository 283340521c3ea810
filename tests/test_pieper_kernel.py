"""The plain-float one-pose kernel of the general 6R solver (rikin.ik.pieper_kernel).

``arm.ik`` of a float64 4x4 array takes the kernel; the same pose as a list takes the
general (numpy) solver. Away from singularities the two must agree exactly: the same
solutions in the same order (to 1e-9 rad), the same labels, no singular flag. Near a
singularity the kernel must hand the pose to the general path (or still agree). Every
solution is put back through FK here, independently of the solver's own check.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from singular_poses import CROSSING_JOINT, singular_q
from test_pieper import (  # the arms of the general solver's tests
    GENERAL,
    KINDS,
    assert_all_reach,
    puma560,
    spherical_wrist_arms,
)

import rikin
from rikin import Link, SerialArm
from rikin.ik.pieper import classify, general_solver
from rikin.ik.pieper_kernel import _quartic

pi = np.pi
SAME_Q = 1e-9


def kernel_of(arm):
    k = general_solver(arm).single_kernel(arm)
    assert k is not None
    return k


def assert_fast_equals_general(arm, T):
    """The fast path's result equals the general path's; returns whether the kernel took
    the pose (False: it declined, and arm.ik fell back to the general path)."""
    out = kernel_of(arm).solve(T.tolist())
    fast, general = arm.ik(T), arm.ik(T.tolist())
    assert fast.labels == general.labels
    assert fast.q.shape == general.q.shape
    assert np.abs(fast.q - general.q).max(initial=0.0) <= SAME_Q
    assert (fast.singular, fast.free_joints) == (general.singular, general.free_joints)
    assert np.isin(fast.q, [-pi]).sum() == 0  # wrapped to (-pi, pi]
    assert_all_reach(arm, fast, T)
    if out is None:
        return False
    # what the kernel returned is what arm.ik handed back, and the pose was regular
    flat, branches = out
    assert np.array_equal(np.array(flat).reshape(-1, 6), fast.q)
    assert tuple(branches) == fast.branches
    assert not general.singular
    return True


@pytest.mark.parametrize("make", GENERAL)
def test_fast_path_equals_general_on_random_poses(make):
    arm = make()
    rng = np.random.default_rng(11)
    q = rng.uniform(-pi, pi, (80, 6))
    taken = 0
    for row, T in zip(q, arm.fk(q), strict=True):
        taken += assert_fast_equals_general(arm, T)
        res = arm.ik(T)
        assert np.abs(rikin.wrap_angle(res.q - row)).max(axis=1).min() < 1e-6  # q among them
    assert taken >= 75  # random poses are regular: the kernel must take nearly all of them


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("make", GENERAL)
def test_near_singular_poses_fall_back_or_agree(make, kind):
    """On each singularity the kernel declines; 1e-9..3e-2 rad off it, it declines or agrees."""
    arm = make()
    kernel = kernel_of(arm)
    rng = np.random.default_rng(20 + KINDS.index(kind))
    for delta in (0.0, 1e-9, 1e-7, 1e-5, 1e-4, 1e-3, 1e-2, 3e-2):
        q = singular_q(arm, kind, rng)
        q[CROSSING_JOINT[kind]] += delta * rng.choice([-1, 1])
        T = arm.fk(q)
        took = assert_fast_equals_general(arm, T)
        if delta == 0.0 and arm.ik(T.tolist()).singular:
            assert not took, (kind, "a singular pose went through the kernel")
        if delta <= 1e-7 and kind != "shoulder":  # the Puma's shoulder is never singular
            assert kernel.solve(T.tolist()) is None, (kind, delta)


def test_exact_singularities_decline():
    """The wrist at q5 = 0 and pi, the wrist centre on axis 1 (KR5: no shoulder offset)."""
    arm = GENERAL[1]()
    kernel = kernel_of(arm)
    q = np.array([0.3, -0.4, 0.5, 0.6, 0.0, 0.8])
    for q5 in (0.0, pi, 1e-8):
        q[4] = q5
        assert kernel.solve(arm.fk(q).tolist()) is None
        assert arm.ik(arm.fk(q)).singular == (q5 != 1e-8)


def test_unreachable_pose_goes_to_the_general_path():
    arm = GENERAL[0]()
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.0]  # 5 m: far outside the Puma's reach
    assert kernel_of(arm).solve(T.tolist()) is None
    with pytest.raises(rikin.UnreachableError):
        arm.ik(T)


def test_non_orthogonal_wrist_and_unreachable_orientations():
    """A wrist with twists 60 and -45 deg: some orientations are out of its reach for some
    positions (no solution there), others give both branches; fast == general."""
    arm = SerialArm(puma560().links[:3] + (
        Link(d=0.4318, alpha=np.radians(60)), Link(alpha=np.radians(-45)), Link(d=0.05),
    ), name="tilted wrist", units="m")
    assert not general_solver(arm).orthogonal
    rng = np.random.default_rng(4)
    taken = 0
    for _ in range(60):
        T = arm.fk(rng.uniform(-pi, pi, 6))
        taken += assert_fast_equals_general(arm, T)
    assert taken >= 50


@settings(max_examples=120, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(spherical_wrist_arms(), st.integers(0, 2**32 - 1))
def test_random_spherical_wrist_tables(arm, seed):
    """Random tables (both conventions, random base, tool, offsets and twists): fast ==
    general on random poses, every solution reaches the pose."""
    if not classify(arm).closed_form:
        return
    kernel = general_solver(arm).single_kernel(arm)
    if kernel is None:  # a skew arm without a z^4 term: the general path alone
        assert general_solver(arm).case == "skew"
        return
    rng = np.random.default_rng(seed)
    for q in rng.uniform(-pi, pi, (4, 6)):
        T = arm.fk(q)
        assert_fast_equals_general(arm, T)


def test_random_tables_mostly_take_the_kernel():
    """Over many random tables and poses the kernel takes most poses, so the equality
    above is not vacuous. Tables whose elbow point sits on axis 2 (no shift along the
    common normal of axes 2 and 3) are left out: their elbow label is decided by rounding
    in the general solver (the elbow lies on the shoulder-wrist line), so the kernel
    declines every pose of them."""
    rng = np.random.default_rng(8)
    draws = taken = tried = 0
    while tried < 150 and draws < 600:
        arm = _random_table(rng)
        draws += 1
        if not classify(arm).closed_form or general_solver(arm).single_kernel(arm) is None:
            continue
        if general_solver(arm).model.M[2][0, 3] == 0.0:
            continue
        T = arm.fk(rng.uniform(-pi, pi, 6))
        tried += 1
        taken += assert_fast_equals_general(arm, T)
    assert tried >= 100 and taken >= 0.7 * tried, (taken, tried, draws)


def _random_table(rng):
    """A random spherical-wrist arm (numpy draws, for the count above)."""
    convention = rng.choice(["standard", "modified"])
    ln = lambda: float(rng.choice([0.0, rng.uniform(0.05, 2.0) * rng.choice([-1, 1])]))  # noqa: E731
    tw = lambda: float(rng.choice([0.0, pi / 2, -pi / 2, rng.uniform(-3, 3)]))  # noqa: E731
    wt = lambda: float(rng.choice([pi / 2, -pi / 2, rng.uniform(0.3, 2.8) * rng.choice([-1, 1])]))  # noqa: E731
    off = lambda: float(rng.choice([0.0, rng.uniform(-pi, pi)]))  # noqa: E731
    b1, b2 = wt(), wt()
    if convention == "standard":
        links = [Link(d=ln(), a=ln(), alpha=tw(), offset=off()) for _ in range(3)]
        links += [Link(d=ln(), alpha=b1, offset=off()), Link(alpha=b2, offset=off()),
                  Link(d=ln(), a=ln(), alpha=tw(), offset=off())]
    else:
        links = [Link(alpha=tw(), a=ln(), d=ln(), offset=off()) for _ in range(4)]
        links += [Link(alpha=b1, offset=off()), Link(alpha=b2, d=ln(), offset=off())]
    base = rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-1.5, 1.5, 3)), rng.uniform(-1, 1, 3))
    tool = rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-1.5, 1.5, 3)), rng.uniform(-1, 1, 3))
    return SerialArm(tuple(links), convention=str(convention), base=base, tool=tool)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.lists(st.complex_numbers(max_magnitude=10.0, allow_nan=False, allow_infinity=False),
                min_size=4, max_size=4))
def test_quartic_roots_are_the_polynomials_roots(coeffs):
    """Ferrari's roots (or None) against numpy's: the same four roots as a multiset."""
    A, B, C, D = coeffs
    roots = _quartic(A, B, C, D)
    ref = np.roots([1.0, A, B, C, D])
    if roots is None:
        return  # declined (a multiple root or worse): the general path takes it
    got = np.array(roots)
    scale = 1.0 + np.abs(ref).max()
    for r in ref:  # each reference root has a computed root near it, and vice versa
        assert np.abs(got - r).min() <= 1e-6 * scale
    for g in got:
        assert np.abs(ref - g).min() <= 1e-6 * scale


def test_vectorised_ferrari_agrees_with_eigenvalues_and_declines_double_roots():
    """The batch solvers' ``ferrari`` (rikin.ik.kernels): the confirmed roots of 20,000
    random quartics are the companion matrix's eigenvalues; quartics built with a double
    root, or two roots 1e-5 apart, are never confirmed (the eigenvalues take them)."""
    from rikin.ik.kernels import SEPARATE_ROOTS
    from rikin.ik.kernels import ferrari as _ferrari

    rng = np.random.default_rng(17)
    M = 20000
    coeffs = rng.normal(size=(M, 4)) + 1j * rng.normal(size=(M, 4))
    z, sure = _ferrari(*coeffs.T)
    assert sure.mean() > 0.99  # random quartics: Ferrari takes nearly all
    C = np.zeros((M, 4, 4), dtype=complex)
    C[:, 1:, :3] = np.eye(3)
    C[:, 0, :] = -coeffs
    ref = np.linalg.eigvals(C)
    scale = 1.0 + np.abs(ref).max(axis=1)
    gap = np.abs(z[:, :, None] - ref[:, None, :])
    assert (gap.min(axis=2).max(axis=1)[sure] <= 1e-12 * scale[sure]).all()  # each is a root
    assert (gap.min(axis=1).max(axis=1)[sure] <= 1e-12 * scale[sure]).all()  # none missed
    # roots on the unit circle (a trigonometric polynomial's), two of them (nearly) equal
    for split in (0.0, 1e-9, 1e-5, 0.5 * SEPARATE_ROOTS):
        th = rng.uniform(-pi, pi, (500, 3))
        roots = np.exp(1j * np.concatenate([th, th[:, :1] + split], axis=1))
        poly = np.array([np.poly(r) for r in roots])  # (500, 5), monic
        _, sure = _ferrari(*poly[:, 1:].T)
        assert not sure.any(), split


def _wrist_centre(kernel, T):
    """The kernel's wrist centre p' (frame of axis 1, solver units) of a pose ``T``."""
    (r00, r01, r02, tx), (r10, r11, r12, ty), (r20, r21, r22, tz) = T.tolist()[:3]
    u = kernel.unit
    cx, cy, cz = kernel.c_tcp
    w = (r00 * cx + r01 * cy + r02 * cz + tx * u, r10 * cx + r11 * cy + r12 * cz + ty * u,
         r20 * cx + r21 * cy + r22 * cz + tz * u)
    return [sum(g * x for g, x in zip(row, w, strict=True)) + t
            for row, t in zip(kernel.G, kernel.Gt, strict=True)]


@pytest.mark.parametrize("make", [m for m in GENERAL if m.__name__ != "puma560"])
def test_planar_arms_closed_form_roots_are_the_quartics(make):
    """The KR5, KR6 and C4 tables (axes 1 and 2 skew at right angles, axes 2 and 3
    parallel) take the closed form; the IRB 120 (axes 1 and 2 meet) does not. On random
    poses and poses 1e-9..3e-2 rad from each singularity, the closed form's joint-3 roots
    are the quartic's (to 1e-9 rad, same order), or both decline, or the closed form
    declines a pose the quartic solves only within ROOT_SEP (never the other way)."""
    arm = make()
    kernel = kernel_of(arm)
    assert kernel.planar == (make.__name__ != "abb_irb120")
    if not kernel.planar:
        return
    rng = np.random.default_rng(31)
    poses = list(arm.fk(rng.uniform(-pi, pi, (400, 6))))
    for kind in KINDS:
        for delta in (0.0, 1e-9, 1e-6, 1e-4, 1e-3, 3e-2):
            q = singular_q(arm, kind, rng)
            q[CROSSING_JOINT[kind]] += delta * rng.choice([-1, 1])
            poses.append(arm.fk(q))
    solved = 0
    for T in poses:
        p = _wrist_centre(kernel, T)
        closed, quartic = kernel._th3_planar(*p), kernel._th3_skew(*p)
        if closed is None or quartic is None:
            assert closed is None, (closed, quartic)  # the closed form is never bolder
            continue
        assert len(closed) == len(quartic)
        assert np.abs(np.array(closed) - np.array(quartic)).max(initial=0.0) <= 1e-9
        solved += len(closed) > 0
    assert solved >= 380


@pytest.mark.parametrize("make", [m for m in GENERAL if m.__name__ != "puma560"])
def test_wrist_centre_near_axis_1_takes_the_kernel_and_agrees(make):
    """1e-4 to 1e-3 of the arm's size from axis 1 (the shoulder singularity of an arm
    without shoulder offset, which random poses meet once in 500), the kernel takes the
    pose and agrees with the general path; on the axis it declines."""
    from rikin.ik.pieper_kernel import NEAR_AXIS1

    arm = make()
    kernel = kernel_of(arm)
    rng = np.random.default_rng(41)
    taken = 0
    for _ in range(6):
        q0 = singular_q(arm, "shoulder", rng)
        assert kernel.solve(arm.fk(q0).tolist()) is None
        lever = np.linalg.norm(arm.joint_axes(q0)[0][4] - arm.joint_axes(q0)[0][1])
        for rel in (2 * NEAR_AXIS1, 5 * NEAR_AXIS1, 10 * NEAR_AXIS1):
            q = q0.copy()
            q[1] += rel * arm.scale / lever * rng.choice([-1, 1])  # moves the centre ~rel
            taken += assert_fast_equals_general(arm, arm.fk(q))
    assert taken >= 12
