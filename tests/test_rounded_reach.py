"""Rounded targets at the edge of the reach (issue 10, item 1): a lesson arm's target with
its elbow near stretched (or folded, for unequal links), printed with 4 or 6 decimals or
stored as float32, can land a few 1e-5 beyond the reach. It is input, not an unreachable
target: IK solves the nearest reachable pose and says how far the given one was; a target
further off than ROUNDED_POSE_TOL stays unreachable, with the right distance.

Before: 20-45% of such targets of the planar 2R/3R, angular 3R and Aula 10 6R raised
UnreachableError ("... 4.2e-05 beyond the reach of links 2-3").

Every expectation is computed independently of the solver: FK of the solutions, the wrist
centre from FK frames, and the nearest pose by a joint-space least squares from the joint
values the target was made from.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from singular_poses import singular_q, wrist_centre
from test_pieper import abb_irb120, epson_c4_table, kuka_kr5, kuka_kr6, puma560

import rikin
from rikin import robots
from rikin.tolerances import ROUNDED_POSE_TOL

BASE = rikin.transforms.trotz(0.7) @ rikin.transforms.trotx(0.4) @ rikin.transl(2.0, -1.0, 3.0)
TOOL = rikin.transforms.troty(0.3) @ rikin.transl(0.5, 0.0, 2.0)
TURN = rikin.transforms.trotz(0.4) @ rikin.transforms.trotx(0.2)  # a tool that only turns

#: name -> (the joint (0-based) that bends the elbow, its angle at stretched)
ELBOW = {
    "planar_2r": (1, 0.0),
    "planar_3r": (1, 0.0),
    "angular_3r": (2, 0.0),
    "aula10_6r": (2, 0.0),
    "barrientos_6r": (2, np.pi / 2),
    "epson_c4": (2, np.pi / 2),
}
MOUNTS = {
    "planar_2r": [{}],
    "planar_3r": [{}],
    "angular_3r": [{}, {"base": BASE, "tool": TURN}],
    "aula10_6r": [{}, {"base": BASE, "tool": TOOL}],
    "barrientos_6r": [{}, {"base": BASE, "tool": TOOL}],
    "epson_c4": [{}, {"base": BASE, "tool": TOOL}],
}
ARMS = {
    (name, i): robots.LESSON_ROBOTS[name](**mount)
    for name, mounts in MOUNTS.items()
    for i, mount in enumerate(mounts)
}
KIND = {name: rikin.ik.api._solver(robots.LESSON_ROBOTS[name]()).target_kind for name in ELBOW}


def target_of(name, T):
    """What a student passes for the world pose ``T``: the arm family's target."""
    kind = KIND[name]
    if kind == "planar_position":
        return T[:2, 3].copy()
    if kind == "planar_pose":
        return np.array([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])])
    if kind == "position":
        return T[:3, 3].copy()
    return T.copy()


def as_pose(name, t):
    """The world 4x4 pose a target stands for (planar: in the plane z = 0)."""
    kind = KIND[name]
    if kind == "pose":
        U, _, Vt = np.linalg.svd(t[:3, :3])  # the rounded block's nearest rotation
        out = t.copy()
        out[:3, :3] = U @ Vt
        return out
    p = np.zeros(3)
    p[: 2 if kind.startswith("planar") else 3] = t[: 2 if kind.startswith("planar") else 3]
    R = rikin.rotz(t[2]) if kind == "planar_pose" else np.eye(3)
    return rikin.homogeneous(R, p)


#: the entries of the 4x4 pose a target fixes (those the least squares fits)
ENTRIES = {
    "pose": (slice(0, 3), slice(0, 4)),
    "position": (slice(0, 3), 3),
    "planar_position": (slice(0, 2), 3),
    "planar_pose": (slice(0, 2), [0, 1, 3]),
}


def entries(name, T):
    rows, cols = ENTRIES[KIND[name]]
    return T[..., rows, cols].reshape(*T.shape[:-2], -1)


def rounded(t, how):
    return t.astype(np.float32).astype(float) if how == "float32" else np.round(t, how)


def near_edge_q(name, arm, rng, folded):
    """Random joints with the elbow 1e-3 rad or less from stretched (or folded)."""
    q = rng.uniform(-np.pi, np.pi, arm.n)
    j, stretched = ELBOW[name]
    q[j] = stretched + (np.pi if folded else 0.0) + rng.uniform(-1e-3, 1e-3)
    return q


def placed_point(name, arm, q):
    """The point the positioning links place (world frame), from the joint axes: the wrist
    centre of a 6R (where axes 4 and 5 meet), the planar 3R's joint 3, else the TCP."""
    if arm.n == 6:
        return wrist_centre(arm, q)
    F = arm.fk(q, frames=True)
    if name == "planar_3r":
        return F[2, :3, 3]
    return F[-1, :3, 3]


def placed_point_of_pose(name, arm, T):
    """The same point for the world pose ``T``: fixed in the TCP frame, read at q = 0."""
    q0 = np.zeros(arm.n)
    c = np.linalg.inv(arm.fk(q0)) @ np.append(placed_point(name, arm, q0), 1.0)
    return (T @ c)[:3]


def in_base(arm, x):
    """The world point ``x (3,)`` in the arm's base frame."""
    return (np.linalg.inv(arm.base) @ np.append(x, 1.0))[:3]


def shoulder(arm, q):
    """The shoulder at joints ``q``, base frame: the point of axis 2 nearest axis 1 (the
    base frame's z axis)."""
    o, z = arm.joint_axes(q)
    o2, z2 = in_base(arm, o[1]), np.linalg.inv(arm.base)[:3, :3] @ z[1]
    return o2 - (o2[:2] @ z2[:2]) / (z2[:2] @ z2[:2]) * z2


def distance_from_reach(name, arm, p, sides=False):
    """How far the world point ``p (3,)`` is from where the positioning links can place
    their point, from FK alone: in the base frame, the shell of radii ``Lm``..``Lp`` around
    the shoulder ``S`` (``r0`` from axis 1), turned about axis 1, with ``Lp`` and ``Lm``
    measured from ``S`` on the stretched and the folded arm (for a planar arm, ``S`` is
    joint 1). With ``sides``: the front and the back arm's distances."""
    j, stretched = ELBOW[name]
    q = np.zeros(arm.n)
    q[j] = stretched
    q_fold = q.copy()
    q_fold[j] += np.pi
    S = np.zeros(3) if name.startswith("planar") else shoulder(arm, q)
    Lp = np.linalg.norm(in_base(arm, placed_point(name, arm, q)) - S)
    Lm = np.linalg.norm(in_base(arm, placed_point(name, arm, q_fold)) - S)
    r0 = np.hypot(S[0], S[1])
    P = in_base(arm, p)
    rho = np.hypot(P[0], P[1])
    d = np.hypot(np.array([rho - r0, rho + r0]), P[2] - S[2])
    per_side = np.abs(d - np.clip(d, Lm, Lp))  # the front arm's, the back arm's
    return per_side if sides else float(per_side.min())


def made_with_side(arm, q):
    """0 when the joints ``q`` of a 6R reach forward (the shoulder on the wrist centre's
    side of axis 1), 1 when they reach back."""
    S, c = shoulder(arm, q), in_base(arm, wrist_centre(arm, q))
    return 0 if S[:2] @ c[:2] >= 0 else 1


def no_nearer_pose_around(name, arm, T_near, q_near, G, rng):
    """True when no configuration around ``q_near`` (steps of 1e-6 to 1e-2 rad) reaches a
    pose nearer to ``G`` (in the entries the target fixes) than ``T_near``: the pose
    reported as nearest is at least a local minimum of the distance."""
    best = np.linalg.norm(entries(name, T_near) - entries(name, G))
    scales = 10.0 ** rng.uniform(-6, -2, (400, 1))
    Q = q_near + scales * rng.standard_normal((400, arm.n))
    d = np.linalg.norm(entries(name, arm.fk(Q)) - entries(name, G), axis=-1)
    return bool(d.min() >= best * (1 - 1e-9) - 1e-13 * arm.scale), (d.min(), best)


def size(arm, T):
    return max(arm.scale, float(np.abs(T[:3, 3]).max()))


def solve_quietly(arm, t):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return arm.ik(t)


@pytest.mark.parametrize("name, mount", sorted(ARMS))
@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), how=st.sampled_from([4, 6, "float32"]),
       folded=st.booleans())
def test_rounded_targets_at_the_edge_solve_for_the_nearest_reachable_pose(
        name, mount, seed, how, folded):
    arm = ARMS[name, mount]
    rng = np.random.default_rng(seed)
    q_true = near_edge_q(name, arm, rng, folded)
    T_true = arm.fk(q_true)
    t = rounded(target_of(name, T_true), how)
    G = as_pose(name, t)
    res = solve_quietly(arm, t)
    s = size(arm, G)
    # every solution reaches the pose solved
    tol = 1e-12 if res.reach_distance > 0 else 1e-8
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - res.target[:3, 3]).max() <= tol * s
    if KIND[name] in ("planar_pose", "pose"):  # the planar 3R's tool angle, the 6R's rotation
        k = 2 if KIND[name] == "planar_pose" else 3
        assert np.abs(F[:, :k, :k] - res.target[:k, :k]).max() <= tol
    # ... which is within the distances reported of the numbers given
    moved = np.abs(entries(name, res.target) - entries(name, G)).max()
    assert moved <= res.reach_distance + res.rotation_distance + 1e-13 * s
    assert res.reach_distance <= ROUNDED_POSE_TOL * s
    # the positioning joints the target was made from are among the solutions, up to what
    # the rounding moves them near the fold (~sqrt(1e-5) rad); not so with equal links
    # folded, where the point is within 1e-2 of axis 2 and rounding turns joint 2 by up to
    # ~1e-1 rad (nor the wrist's joints near q5 = 0 or pi: other tests cover the wrist)
    # A shoulder offset (the C4) gives the front and the back arm different reaches: the
    # rounding can put the target beyond the reach of the arm it was made with and within
    # the other's. Then it is reachable as given, and that arm has no solution.
    g = getattr(arm.solver, "geometry", None)
    equal = g.L2 == g.L3 if g is not None else arm.links[0].a == arm.links[1].a
    made_with = 0 if arm.n < 6 else made_with_side(arm, q_true)
    lost = distance_from_reach(name, arm, placed_point_of_pose(name, arm, G), True)[made_with] > 0
    if not (folded and equal) and not (lost and res.reach_distance == 0):
        gap = np.abs(rikin.wrap_angle(res.q[:, :3] - q_true[:3])).max(axis=1).min()
        assert gap < 0.03, gap
    if res.reach_distance > 0:
        assert "nearest reachable pose" in res.table().splitlines()[-1]
        # the distance reported is the placed point's from the reach; the pose solved has
        # that point on it
        want = distance_from_reach(name, arm, placed_point_of_pose(name, arm, G))
        assert res.reach_distance == pytest.approx(want, rel=1e-6)
        on_reach = placed_point_of_pose(name, arm, res.target)
        assert distance_from_reach(name, arm, on_reach) <= 1e-12 * s
        # nearest: at least as near the numbers given as the pose they were rounded from,
        # and no configuration around a solution reaches a nearer one
        assert (np.linalg.norm(entries(name, res.target) - entries(name, G))
                <= np.linalg.norm(entries(name, T_true) - entries(name, G)) + 1e-12 * s)
        ok, why = no_nearer_pose_around(name, arm, res.target, res.q[0], G, rng)
        assert ok, why
    else:
        assert "reachable pose" not in res.table()


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_four_decimals_at_the_edge_never_refused_and_batch_agrees(name, mount):
    """100 targets with the elbow within 1e-3 rad of stretched, rounded to 4 decimals: all
    solve (before: 20-45 of them raised), and ik_batch solves each as arm.ik does."""
    arm = ARMS[name, mount]
    rng = np.random.default_rng(7)
    targets = np.stack([
        np.round(target_of(name, arm.fk(near_edge_q(name, arm, rng, False))), 4)
        for _ in range(100)
    ])
    singles = [solve_quietly(arm, t) for t in targets]
    moved = sum(r.reach_distance > 0 for r in singles)
    assert moved >= 10, moved  # the edge is crossed: the test exercises what it is about
    batch = arm.ik_batch(np.stack([t if KIND[name] == "pose" else as_pose(name, t)
                                   for t in targets]))  # ik_batch takes 4x4 poses
    assert np.allclose(batch.reach_distance, [r.reach_distance for r in singles],
                       rtol=1e-9, atol=1e-13 * arm.scale)
    for i, r in enumerate(singles):
        q = batch.q[i][batch.valid[i]]
        assert len(q) >= len(r)
        F = arm.fk(q)
        assert np.abs(F[:, :3, 3] - r.target[:3, 3]).max() <= 1e-8 * size(arm, r.target)
        for row in r.q:  # every one-pose solution is one of the batch's
            assert np.abs(rikin.wrap_angle(q - row)).max(axis=1).min() < 1e-7


@pytest.mark.parametrize("name, mount", sorted(ARMS))
def test_beyond_rounding_the_target_stays_unreachable_with_its_distance(name, mount):
    """Stretched and then moved out by 1e-2 of the arm's size along the arm: refused, the
    excess is that distance, and the message says how far off a rounded pose may be."""
    arm = ARMS[name, mount]
    q = near_edge_q(name, arm, np.random.default_rng(2), False)
    j, stretched = ELBOW[name]
    q[j] = stretched
    F = arm.fk(q, frames=True)
    T = F[-1].copy()
    # along the stretched links: from the elbow's joint to the point they place
    p = placed_point(name, arm, q)
    direction = p - F[j - 1 if arm.convention == "standard" else j, :3, 3]
    out = 1e-2 * arm.scale
    T[:3, 3] += out * direction / np.linalg.norm(direction)
    with pytest.raises(rikin.UnreachableError) as err:
        arm.ik(target_of(name, T))
    assert err.value.excess == pytest.approx(out, rel=1e-6)
    assert "taken as rounded" in str(err.value)


# ------------------------------------------------------------------ the general 6R solver
GENERAL = [puma560, kuka_kr5, kuka_kr6, abb_irb120, epson_c4_table]


@pytest.mark.parametrize("make", GENERAL)
@pytest.mark.parametrize("kind", ["stretched", "folded"])
@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), how=st.sampled_from([4, "float32"]),
       mounted=st.booleans())
def test_general_arms_solve_rounded_poses_at_their_folds(make, kind, seed, how, mounted):
    """An industrial table (solved by the general 6R solver) with the elbow within 1e-3 rad
    of a fold of its reach (the wrist centre farthest from or nearest to axis 2), printed
    with 4 decimals or as float32: solved, for the pose given or the nearest reachable one.
    Before: UnreachableError for every one that rounding put beyond the reach: with the
    elbow within 1e-3 rad of stretched, 7 (C4 table) to 19 (Puma) of 40 random poses per arm,
    folded 19 (IRB 120) and 26 (Puma) of 40."""
    arm = make()
    if mounted:
        arm = arm.replace(base=BASE, tool=TOOL)
    rng = np.random.default_rng(seed)
    q_true = singular_q(arm, kind, rng)
    q_true[2] += rng.uniform(-1e-3, 1e-3)
    T = rounded(arm.fk(q_true), how)
    res = solve_quietly(arm, T)
    G = as_pose("aula10_6r", T)  # the rounded pose with its nearest rotation
    s = size(arm, G)
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - res.target[:3, 3]).max() <= 1e-8 * s
    assert np.abs(F[:, :3, :3] - res.target[:3, :3]).max() <= 1e-8
    assert np.abs(res.target - G).max() <= res.reach_distance + 1e-13 * s
    c_given = placed_point_of_pose("aula10_6r", arm, G)
    assert res.reach_distance <= ROUNDED_POSE_TOL * s
    # the distance reported is no more than the true pose's (which is reachable), and
    # no configuration around a solution puts the wrist centre nearer
    assert res.reach_distance <= np.linalg.norm(c_given - wrist_centre(arm, q_true)) + 1e-12 * s
    if res.reach_distance > 0:
        Q = res.q[0] + 10.0 ** rng.uniform(-6, -2, (400, 1)) * rng.standard_normal((400, 6))
        d = np.linalg.norm(wrist_centre(arm, Q) - c_given, axis=-1)
        assert d.min() >= res.reach_distance * (1 - 1e-9) - 1e-13 * s, (d.min(), res.reach_distance)
    batch = arm.ik_batch(T[None])
    assert batch.reach_distance[0] == pytest.approx(res.reach_distance, rel=1e-9, abs=1e-13 * s)
    assert batch.valid[0].sum() >= 1


LESSON_6R = [robots.aula10_6r, robots.barrientos_6r, robots.epson_c4]


@pytest.mark.parametrize("make", GENERAL + LESSON_6R)
def test_numerical_ik_solves_what_arm_ik_solves_for_a_rounded_pose_beyond_the_reach(make):
    """ik_numerical (the whole pose, no mask) on the 6R poses above that rounding put beyond
    the reach: it converges, to the same nearest reachable pose arm.ik solves, with the same
    reach_distance (before: 'stalled at a singularity / local minimum')."""
    arm = make()
    rng = np.random.default_rng(5)
    seen = 0
    for _ in range(40):
        if make in GENERAL:
            q = singular_q(arm, "stretched", rng)
            q[2] += rng.uniform(-1e-3, 1e-3)
        else:
            q = near_edge_q(make.__name__, arm, rng, False)  # the LESSON_ROBOTS name
        T = np.round(arm.fk(q), 4)
        res = solve_quietly(arm, T)
        if res.reach_distance == 0:
            continue
        seen += 1
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            num = rikin.ik.ik_numerical(arm, T, q + 0.01)
        assert num.success, num.reason
        assert num.reach_distance == pytest.approx(res.reach_distance, rel=1e-9)
        assert np.abs(num.target - res.target).max() <= 1e-12 * size(arm, T)
        assert np.abs(arm.fk(num.q) - res.target)[:3, 3].max() <= 1e-8 * size(arm, T)
    assert seen >= 3, seen  # the edge was crossed


@pytest.mark.parametrize("up", [1.0, -1.0])
def test_the_arm_straight_along_axis_1_rounded_beyond_its_reach(up):
    """The angular 3R stretched along axis 1 (up or down), its target 3e-5 further: on the
    axis every azimuth is as near, and the target still moves onto the reach (before:
    UnreachableError, no direction being taken there)."""
    arm = robots.angular_3r()
    target = np.array([0.0, 0.0, 10.0 + up * 20.00003])  # shoulder at z = 10, reach 20
    res = solve_quietly(arm, target)
    assert res.reach_distance == pytest.approx(3e-5, rel=1e-6)
    assert np.abs(arm.fk(res.q)[:, :3, 3] - res.target[:3, 3]).max() <= 1e-12 * arm.scale
    assert np.allclose(res.target[:3, 3], [0.0, 0.0, 10.0 + up * 20.0], atol=1e-12 * arm.scale)
