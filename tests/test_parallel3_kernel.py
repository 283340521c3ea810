"""The plain-float one-pose kernel of the three-parallel-axes solver
(rikin.ik.parallel3_kernel).

``arm.ik`` of a float64 4x4 array takes the kernel; the same pose as a list takes the
general (numpy) solver, which polishes every solution and flags singular poses. Away from
singularities the two must agree: the same solutions in the same order, the same labels,
no singular flag. Near a singularity the kernel must hand the pose to the general path (or
still agree). Every solution is put back through FK here, independently of the solver's
own check.
"""

import numpy as np
import pytest

import rikin
from rikin import Link, SerialArm
from rikin.ik import families6r

pi = np.pi
SAME_Q = 1e-9


def ur(name, d1, a2, a3, d4, d5, d6, **kw):
    """A UR arm from Universal Robots' DH table."""
    return SerialArm((
        Link(d=d1, alpha=pi / 2), Link(a=a2), Link(a=a3), Link(d=d4, alpha=pi / 2),
        Link(d=d5, alpha=-pi / 2), Link(d=d6),
    ), name=name, units="m", **kw)


def ur5e(**kw):
    return ur("UR5e", 0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996, **kw)


def ur10e_base_tool():
    base = rikin.homogeneous(rikin.rotz(0.7) @ rikin.rotx(0.2), [0.2, 0.1, 0.3])
    tool = rikin.homogeneous(rikin.rotx(0.4), [0.0, 0.05, 0.12])
    return ur("UR10e", 0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655, base=base,
              tool=tool)


def plane_wrist_arm(seed, convention, first):
    """A random table with axes ``first``..``first + 2`` parallel whose end point stays in
    one plane as the joint next to them turns (the UR's kind: axis 6's point as joint 5
    turns, or, for axes 3-5, axis 1's as joint 2 turns), random base and tool."""
    rng = np.random.default_rng(seed)
    twist = list(rng.uniform(-pi, pi, 6))
    k = first - 1 if convention == "standard" else first
    twist[k] = rng.choice([0.0, pi])
    twist[k + 1] = rng.choice([0.0, pi])
    a = rng.uniform(-1, 1, 6)
    if first == 2:
        a[4 if convention == "standard" else 5] = 0.0
    else:
        a[0 if convention == "standard" else 1] = 0.0
    links = tuple(Link(a=a[i], d=rng.uniform(-1, 1), alpha=twist[i],
                       offset=rng.uniform(-pi, pi)) for i in range(6))
    base = rikin.homogeneous(rikin.rotz(rng.uniform(-3, 3)) @ rikin.rotx(rng.uniform(-3, 3)),
                             rng.uniform(-1, 1, 3))
    tool = rikin.homogeneous(rikin.roty(rng.uniform(-3, 3)), rng.uniform(-1, 1, 3))
    return SerialArm(links, convention=convention, base=base, tool=tool, name="parallel",
                     units="m")


UR_ARMS = [ur5e, ur10e_base_tool]
RANDOM_ARMS = [
    pytest.param(lambda c=c, f=f, s=s: plane_wrist_arm(s, c, f), id=f"{c}-{f}-{s}")
    for c in ("standard", "modified") for f in (2, 3) for s in (1, 2)
]


def kernel_of(arm):
    k = families6r.solver_for(arm).single_kernel(arm)
    assert k is not None
    return k


def assert_all_reach(arm, res, T):
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max(initial=0.0) <= 1e-9 * arm.scale
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max(initial=0.0) <= 1e-9


def same_q_bound(arm, q):
    """How closely the pose fixes the joints ``q (k, 6)``: 1e-9 rad, or the rounding of the
    pose over the Jacobian's smallest relative singular value where that is larger (a
    random table has singular poses the kernel's margins do not name)."""
    sv = np.linalg.svd(arm.jacobian(q), compute_uv=False)
    return max(SAME_Q, 1e-14 / float((sv[..., -1] / sv[..., 0]).min()))


def assert_fast_equals_general(arm, T, strict=True):
    """The fast path's result equals the general path's; returns whether the kernel took
    the pose (False: it declined, and arm.ik fell back to the general path)."""
    out = kernel_of(arm).solve(T.tolist())
    fast, general = arm.ik(T), arm.ik(T.tolist())
    assert fast.labels == general.labels
    assert fast.q.shape == general.q.shape
    bound = SAME_Q if strict else same_q_bound(arm, general.q)
    assert np.abs(rikin.wrap_angle(fast.q - general.q)).max(initial=0.0) <= bound
    assert (fast.singular, fast.free_joints) == (general.singular, general.free_joints)
    assert np.isin(fast.q, [-pi]).sum() == 0  # wrapped to (-pi, pi]
    assert_all_reach(arm, fast, T)
    if out is None:
        return False
    flat, branches = out  # what the kernel returned is what arm.ik handed back
    assert np.array_equal(np.array(flat).reshape(-1, 6), fast.q)
    assert tuple(branches) == fast.branches
    assert not general.singular
    return True


@pytest.mark.parametrize("make", UR_ARMS)
def test_ur_fast_path_equals_general_on_random_poses(make):
    arm = make()
    rng = np.random.default_rng(11)
    q = rng.uniform(-pi, pi, (150, 6))
    taken = 0
    for row, T in zip(q, arm.fk(q), strict=True):
        taken += assert_fast_equals_general(arm, T)
        res = arm.ik(T)
        assert np.abs(rikin.wrap_angle(res.q - row)).max(axis=1).min() < 1e-6  # q among them
        assert len(set(res.labels)) == len(res)  # 8 branches, 8 labels
    assert taken >= 145  # random poses are regular: the kernel must take nearly all


@pytest.mark.parametrize("make", RANDOM_ARMS)
def test_random_plane_wrist_tables_fast_path_equals_general(make):
    arm = make()
    assert str(rikin.ik.classify(arm)).startswith("three parallel axes")
    rng = np.random.default_rng(12)
    q = rng.uniform(-pi, pi, (40, 6))
    taken = sum(assert_fast_equals_general(arm, T, strict=False) for T in arm.fk(q))
    assert taken >= 36


def det_j_roots(arm, rng, n):
    """Singular joint vectors: roots of det J along a random joint from random q."""
    out = []
    while len(out) < n:
        q, j = rng.uniform(-pi, pi, 6), int(rng.integers(6))

        def det(x, q=q, j=j):
            qq = q.copy()
            qq[j] = x
            return np.linalg.det(arm.jacobian(qq))

        grid = np.linspace(-pi, pi, 37)
        d = [det(x) for x in grid]
        k = next((k for k in range(36) if np.sign(d[k]) != np.sign(d[k + 1])), None)
        if k is None:
            continue
        lo, hi, f_lo = grid[k], grid[k + 1], d[k]
        for _ in range(60):
            mid = (lo + hi) / 2
            f_mid = det(mid)
            lo, hi, f_lo = (mid, hi, f_mid) if np.sign(f_mid) == np.sign(f_lo) else (lo, mid, f_lo)
        q[j] = (lo + hi) / 2
        out.append((q, j))
    return out


@pytest.mark.parametrize("make", UR_ARMS)
def test_ur_near_singular_poses_fall_back_or_agree(make):
    """On a singularity (det J = 0) the kernel declines; 1e-9..3e-2 rad off it, it
    declines or agrees to 1e-9."""
    arm = make()
    rng = np.random.default_rng(21)
    taken = 0
    for q, j in det_j_roots(arm, rng, 12):
        assert kernel_of(arm).solve(arm.fk(q).tolist()) is None
        for delta in (1e-9, 1e-7, 1e-5, 1e-4, 1e-3, 1e-2, 3e-2):
            qq = q.copy()
            qq[j] += delta * rng.choice([-1, 1])
            taken += assert_fast_equals_general(arm, arm.fk(qq))
    assert taken >= 12  # 1e-2 rad off a singularity is regular


@pytest.mark.parametrize("q", [
    [0.3, -1.0, 1.2, 0.4, 0.0, 0.5],  # wrist: axis 6 parallel to axes 2-4
    [0.3, -1.0, 0.0, 0.4, 1.1, 0.5],  # elbow stretched
    [0.3, -1.0, pi, 0.4, 1.1, 0.5],  # folded
])
def test_ur_named_singularities_decline(q):
    arm = ur5e()
    T = arm.fk(np.array(q))
    assert kernel_of(arm).solve(T.tolist()) is None
    res = arm.ik(T)  # the general path
    assert_all_reach(arm, res, T)
    if not res.singular:  # (on the wrist's, q6 is free: one of its family stands for q)
        assert np.abs(rikin.wrap_angle(res.q - q)).max(axis=1).min() < 1e-6


def test_unreachable_pose_goes_to_the_general_path():
    arm = ur5e()
    T = arm.fk(np.zeros(6))
    T[0, 3] += 3.0
    assert kernel_of(arm).solve(T.tolist()) is None
    with pytest.raises(rikin.UnreachableError):
        arm.ik(T)


def test_offset_wrist_has_no_kernel_and_is_solved():
    """Axis 6's point off the plane (a5 != 0): joint 1 from a quartic, no kernel."""
    arm = SerialArm((
        Link(d=0.1625, alpha=pi / 2), Link(a=-0.425), Link(a=-0.3922), Link(d=0.1333, alpha=pi / 2),
        Link(d=0.0997, a=0.05, alpha=-pi / 2), Link(d=0.0996),
    ), name="offset wrist", units="m")
    assert families6r.solver_for(arm).single_kernel(arm) is None
    rng = np.random.default_rng(5)
    for q in rng.uniform(-pi, pi, (5, 6)):
        T = arm.fk(q)
        res = arm.ik(T)
        assert_all_reach(arm, res, T)
        assert np.abs(rikin.wrap_angle(res.q - q)).max(axis=1).min() < 1e-6


# ------------------------------------------------------------------ the batch on arrays
def batch_poses(arm, rng, n):
    """FK of random joints, and of joints 1e-9..1e-3 rad from q5 = 0 (wrist), q3 = 0
    (stretched) and exactly on them."""
    q = rng.uniform(-pi, pi, (4 * n, 6))
    eps = 10.0 ** rng.uniform(-9, -3, 3 * n) * rng.choice([-1, 1], 3 * n)
    eps[::5] = 0.0
    q[n:2 * n, 4], q[2 * n:3 * n, 2] = eps[:n], eps[n:2 * n]
    q[3 * n:, 2], q[3 * n:, 4] = eps[2 * n:], -eps[2 * n:]
    return arm.fk(q)


def assert_batch_fast_equals_closed_form(arm, Ts):
    """The array kernel's slots equal the closed form's (the numpy path it replaces) on
    every pose neither calls suspect, to 1e-9 rad or what the pose fixes (``same_q_bound``:
    1e-4 rad from two singularities at once, neither path's unpolished joints are better
    than 1e-8); what the old path flags, the kernel does."""
    kernel = families6r.solver_for(arm).batch_kernel(arm)
    assert kernel.fast is not None
    X = np.ascontiguousarray(Ts.transpose(1, 2, 0))
    q, valid, suspect = kernel.solve(X)
    kernel.fast = None
    q0, valid0, suspect0 = kernel.solve(X)
    assert not (suspect0 & ~suspect).any()  # wider margins: what the old path flags, too
    keep = ~suspect
    assert np.array_equal(valid[:, keep], valid0[:, keep])
    for n in np.flatnonzero(keep):
        ok = valid[:, n]
        assert np.isnan(q[~ok, :, n]).all()
        gap = np.abs(rikin.wrap_angle(q[ok, :, n] - q0[ok, :, n]))
        assert gap.max(initial=0.0) <= same_q_bound(arm, q0[ok, :, n])
    return int(keep.sum())


@pytest.mark.parametrize("make", UR_ARMS)
def test_ur_batch_on_arrays_equals_closed_form_and_general_path(make):
    arm = make()
    rng = np.random.default_rng(31)
    Ts = batch_poses(arm, rng, 60)
    assert assert_batch_fast_equals_closed_form(arm, Ts) >= 60
    batch = arm.ik_batch(Ts, workers=2)
    for n, T in enumerate(Ts):
        got = batch.q[n][batch.valid[n]]
        F = arm.fk(got)  # every slot by FK, independently of the kernel's own check
        assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * arm.scale
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= 1e-9
        if batch.singular[n]:
            continue
        ref = arm.ik(T.tolist()).q  # the general path: polished, de-duplicated
        gap = np.abs(rikin.wrap_angle(got[:, None] - ref[None])).max(-1)
        bound = same_q_bound(arm, ref)
        assert gap.min(1).max() <= bound and gap.min(0).max() <= bound


@pytest.mark.parametrize("make", RANDOM_ARMS)
def test_random_plane_wrist_tables_batch_on_arrays(make):
    arm = make()
    rng = np.random.default_rng(32)
    Ts = batch_poses(arm, rng, 20)
    assert assert_batch_fast_equals_closed_form(arm, Ts) >= 20
    batch = arm.ik_batch(Ts)
    for n, T in enumerate(Ts):
        F = arm.fk(batch.q[n][batch.valid[n]])
        assert np.abs(F[:, :3, 3] - T[:3, 3]).max(initial=0.0) <= 1e-9 * arm.scale
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max(initial=0.0) <= 1e-9


def test_batch_on_arrays_sends_bad_rows_to_the_general_path():
    """An unreachable pose and exact singular poses in a batch: no slot of the first,
    every slot of the others reaches its pose and they are flagged singular."""
    arm = ur5e()
    q = np.array([[0.3, -1.0, 1.2, 0.4, 0.0, 0.5], [0.3, -1.0, 0.0, 0.4, 1.1, 0.5],
                  [0.3, -1.0, 1.2, 0.4, 1.1, 0.5]])
    Ts = arm.fk(q)
    Ts[2, 0, 3] += 3.0
    batch = arm.ik_batch(Ts)
    assert not batch.valid[2].any() and np.isnan(batch.q[2]).all()
    assert batch.singular[:2].all()
    for n in range(2):
        F = arm.fk(batch.q[n][batch.valid[n]])
        assert np.abs(F[:, :3, 3] - Ts[n, :3, 3]).max() <= 1e-9 * arm.scale
