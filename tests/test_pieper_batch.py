"""``ik_batch`` of a 6R with a spherical wrist typed as a DH table: the array kernel
(rikin.ik.pieper_batch) and the batch against ``arm.ik`` pose by pose.

Arms as a user types them: standard and modified DH, base and tool, joint offsets, joints
that turn against their z axis (``Link(direction=-1)``), axes 1 and 2 meeting (Puma 560),
skew at right angles (KUKA KR5, ABB IRB 140 and IRB 2400) or at another angle (a quartic),
and random tables. Poses:
seeded random ones, and poses 1e-9..1e-3 rad from a singularity and exactly on it (the
wrist at q5 = 0 or pi, the wrist centre on axis 1, the elbow stretched or folded), where
the kernel must hand the pose to the general solver or still agree with it. Every
solution goes back through FK here, independently of the solvers' own checks.
"""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from singular_poses import CROSSING_JOINT, singular_q
from test_pieper import spherical_wrist_arms

import rikin
from rikin import Link, SerialArm, robots
from rikin.ik import families6r

pi = np.pi
SAME_Q = 1e-9
BASE = rikin.homogeneous(rikin.rotz(0.7) @ rikin.rotx(0.3), [0.2, -0.1, 0.4])
TOOL = rikin.homogeneous(rikin.roty(0.5) @ rikin.rotz(-1.1), [0.03, 0.0, 0.11])


def puma_standard(**kw):
    """Corke's Puma 560 (standard DH, metres): axes 1 and 2 meet."""
    return SerialArm((
        Link(d=0.6718, alpha=pi / 2), Link(a=0.4318), Link(d=0.15005, a=0.0203, alpha=-pi / 2),
        Link(d=0.4318, alpha=pi / 2), Link(alpha=-pi / 2), Link(),
    ), name="Puma 560", units="m", **kw)


def puma_modified(**kw):
    """Craig's Puma 560 (modified DH, metres), joints 2 and 5 reversed."""
    return SerialArm((
        Link(), Link(alpha=-pi / 2, direction=-1), Link(a=0.4318, d=0.15005),
        Link(alpha=-pi / 2, a=0.0203, d=0.4318), Link(alpha=pi / 2, direction=-1),
        Link(alpha=-pi / 2),
    ), convention="modified", name="Puma 560 (Craig)", units="m", **kw)


def kr5(**kw):
    """KUKA KR5 (standard DH, metres): axes 1 and 2 skew at right angles."""
    return SerialArm((
        Link(d=0.4, a=0.18, alpha=pi / 2), Link(a=0.6), Link(a=0.12, alpha=pi / 2),
        Link(d=-0.62, alpha=-pi / 2), Link(alpha=pi / 2), Link(d=-0.115, alpha=pi),
    ), name="KUKA KR5", units="m", **kw)


def irb140(**kw):
    """ABB IRB 140 (standard DH, metres), joint 2's zero upright, joints 1, 4, 6 reversed."""
    return SerialArm((
        Link(d=0.352, a=0.07, alpha=-pi / 2, direction=-1), Link(a=0.36, offset=-pi / 2),
        Link(alpha=-pi / 2), Link(d=0.38, alpha=pi / 2, direction=-1), Link(alpha=-pi / 2),
        Link(d=0.065, direction=-1),
    ), name="ABB IRB 140", units="m", **kw)


def irb2400(**kw):
    """ABB IRB 2400 (modified DH, metres: the standard table's rows shifted by one)."""
    return SerialArm((
        Link(d=0.615), Link(alpha=-pi / 2, a=0.1, offset=-pi / 2), Link(a=0.705),
        Link(alpha=-pi / 2, a=0.135, d=0.755), Link(alpha=pi / 2), Link(alpha=-pi / 2, d=0.085),
    ), convention="modified", name="ABB IRB 2400", units="m", **kw)


def skew_quartic(**kw):
    """Axes 1 and 2 skew at 63 deg, axes 2 and 3 not parallel: joint 3 from a quartic."""
    return SerialArm((
        Link(d=0.4, a=0.2, alpha=1.1), Link(a=0.6, d=0.1, alpha=0.3), Link(a=0.1, alpha=pi / 2),
        Link(d=0.5, alpha=-pi / 2, direction=-1), Link(alpha=pi / 2), Link(d=0.1),
    ), name="skew (quartic)", units="m", **kw)


ARMS = [
    puma_standard, puma_modified, kr5, irb140, irb2400, skew_quartic,
    lambda **kw: robots.kuka_kr5_arc(limits=False, **kw),
    lambda **kw: robots.fanuc_lrmate200id(limits=False, **kw),
]
IDS = ["puma", "puma-craig", "kr5", "irb140", "irb2400", "quartic", "kr5-arc", "lrmate"]


def with_base_tool(make):
    """The arm on a tilted base with a tool (as a lab mounts it)."""
    arm = make()
    tool = arm.tool @ TOOL
    return arm.replace(base=BASE, tool=tool)


def dh_twin(arm):
    """The arm the solvers see (a reversed arm is solved through its DH twin)."""
    return arm._dh if arm.reversed_joints else arm


def near_singular_q(arm, rng, n):
    """Joints at each singularity of the arm and 1e-9..1e-3 rad off it along the joint
    that crosses it (``singular_poses``), ``(n * 5, 6)``."""
    out = []
    for kind, joint in CROSSING_JOINT.items():
        for k in range(n):
            q = singular_q(arm, kind, rng)
            if k % 4:
                q[joint] += 10.0 ** rng.uniform(-9, -3) * rng.choice([-1, 1])
            out.append(q)
    return np.array(out)


def same_q_bound(arm, q):
    """How closely a pose fixes its joints ``q (k, 6)``: 1e-9 rad, or where larger the
    rounding of the pose over the Jacobian's smallest relative singular value ``r`` (a
    simple root), or its square root over ``r`` (two roots about to meet, a fold: there
    the plain-float kernel of ``arm.ik`` and the general solver of the batch may round a
    root ~1e-5 rad apart); no bound at an exactly singular pose, whose free joints FK
    checks."""
    sv = np.linalg.svd(arm.jacobian(q), compute_uv=False)
    ratio = float((sv[..., -1] / sv[..., 0]).min())
    return np.inf if ratio == 0.0 else max(SAME_Q, 1e-14 / ratio, np.sqrt(1e-16 / ratio))


def assert_fast_equals_general(arm, Ts):
    """The array kernel's slots equal the general solver's (``solve`` without labels, the
    path the batch took before) on every pose the kernel does not call suspect: the same
    slots valid, the same joints to ``SAME_Q``. Returns how many poses it kept."""
    twin = dh_twin(arm)
    solver = families6r.solver_for(twin)
    kernel = solver.batch_kernel(twin)
    assert kernel is not None, f"{arm.name}: no array kernel"
    q, valid, suspect = kernel.solve(np.ascontiguousarray(Ts.transpose(1, 2, 0)))
    raw = solver.solve(twin, twin._world_to_base(Ts), None, labels=False)
    keep = ~suspect
    assert np.array_equal(valid.T[keep], raw.valid[keep])
    ok = valid.T[keep]
    assert np.isnan(q.transpose(2, 0, 1)[keep][~ok]).all()
    gap = np.abs(rikin.wrap_angle(q.transpose(2, 0, 1)[keep][ok] - raw.q[keep][ok]))
    assert gap.max(initial=0.0) <= SAME_Q
    return int(keep.sum())


def assert_batch_equals_ik(arm, Ts):
    """``arm.ik_batch`` (2 threads) against ``arm.ik`` pose by pose: every slot reaches its
    pose by FK; a regular pose has ``arm.ik``'s solutions in its order, a singular one
    holds every solution of ``arm.ik`` among its slots. Where the array kernel took the
    pose: to ``SAME_Q``, and neither flags it singular. Where both took the general
    solver: to what the pose fixes (``same_q_bound``), and the flags are that solver's
    (``arm.ik`` may have taken such a pose by its plain-float kernel, which flags none)."""
    batch = arm.ik_batch(Ts, workers=2)
    twin = dh_twin(arm)
    kernel = families6r.solver_for(twin).batch_kernel(twin)
    suspect = np.ones(len(Ts), dtype=bool)
    if kernel is not None:
        suspect = kernel.solve(np.ascontiguousarray(Ts.transpose(1, 2, 0)))[2]
    for n, T in enumerate(Ts):
        got = batch.q[n][batch.valid[n]]
        F = arm.fk(got)
        assert np.abs(F[:, :3, 3] - T[:3, 3]).max(initial=0.0) <= 1e-9 * arm.scale
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max(initial=0.0) <= 1e-9
        res = arm.ik(T)
        if not suspect[n]:
            assert not batch.singular[n] and not res.singular, n
        bound = same_q_bound(arm, res.q) if suspect[n] else SAME_Q
        if res.singular:
            gap = np.abs(rikin.wrap_angle(res.q[:, None] - got[None])).max(-1)
            assert gap.min(axis=1).max() <= bound, n
        else:
            assert got.shape == res.q.shape, n
            assert np.abs(rikin.wrap_angle(got - res.q)).max(initial=0.0) <= bound, n


@pytest.mark.parametrize("make", ARMS, ids=IDS)
def test_regular_poses_take_the_array_kernel_and_equal_the_general_solver(make):
    """Fails before pieper_batch: the batch had no kernel for a typed spherical wrist."""
    rng = np.random.default_rng(41)
    for arm in (make(), with_base_tool(make)):
        Ts = arm.fk(rng.uniform(-pi, pi, (400, 6)))
        assert assert_fast_equals_general(arm, Ts) >= 390  # the kernel's margins: ~0.3%
        Ts = arm.fk(near_singular_q(arm, rng, 8))
        assert_fast_equals_general(arm, Ts)


@pytest.mark.parametrize("make", ARMS, ids=IDS)
def test_batch_equals_ik_pose_by_pose_random_and_near_singular(make):
    rng = np.random.default_rng(42)
    arm = with_base_tool(make)
    q = np.concatenate([rng.uniform(-pi, pi, (40, 6)), near_singular_q(arm, rng, 4)])
    Ts = arm.fk(q)
    assert_batch_equals_ik(arm, Ts)
    batch = arm.ik_batch(Ts, workers=2)
    assert batch.singular[40:].any() and not batch.singular[:40].all()
    diff = np.where(batch.valid[..., None], batch.q - q[:, None], pi)
    gen = np.abs(rikin.wrap_angle(diff)).max(-1)
    assert (gen.min(axis=1) <= 1e-6).mean() >= 0.95  # the generating joints


def test_batch_of_many_poses_in_chunks_and_threads_equals_one_chunk():
    """Chunks split across threads fill the same rows as one chunk on one thread, to the
    bit: the general solver takes a chunk's suspect poses together, and a pose's answer
    does not depend on the others (tests/test_alone_or_in_a_batch.py)."""
    arm = with_base_tool(irb140)
    rng = np.random.default_rng(43)
    Ts = arm.fk(rng.uniform(-pi, pi, (2500, 6)))
    one = arm.ik_batch(Ts, workers=1, chunk_size=4096)
    many = arm.ik_batch(Ts, workers=2, chunk_size=700)
    assert np.array_equal(one.valid, many.valid)
    assert np.array_equal(one.singular, many.singular)
    assert np.array_equal(np.isnan(one.q), np.isnan(many.q))
    assert np.array_equal(one.q, many.q, equal_nan=True)


@st.composite
def typed_arms(draw):
    """A random spherical-wrist table (standard or modified DH, offsets, base and tool:
    ``test_pieper.spherical_wrist_arms``) with random joints reversed."""
    arm = draw(spherical_wrist_arms())
    flips = draw(st.lists(st.sampled_from([1, -1]), min_size=6, max_size=6))
    links = tuple(replace(lk, direction=s) for lk, s in zip(arm.links, flips, strict=True))
    return arm.replace(links=links)


@settings(max_examples=30, deadline=None)
@given(typed_arms(), st.integers(0, 2**32 - 1))
def test_random_typed_tables_batch_equals_ik(arm, seed):
    verdict = rikin.ik.classify(arm)
    if not verdict.closed_form or "spherical wrist" not in verdict.family:
        return  # degenerate draws (axes 1-2 or 2-3 the same line, ...)
    rng = np.random.default_rng(seed)
    q = rng.uniform(-pi, pi, (6, 6))
    q[1, 4] = -float(arm.links[4].offset) * arm.links[4].direction + 1e-7  # near q5 = 0
    q[2, 4] = -float(arm.links[4].offset) * arm.links[4].direction  # on it
    Ts = arm.fk(q)
    assert_batch_equals_ik(arm, Ts)
    twin = dh_twin(arm)
    if families6r.solver_for(twin).batch_kernel(twin) is not None:
        assert_fast_equals_general(arm, Ts)
