"""FK of joints near a singularity is a reachable pose: ``arm.ik`` and ``arm.ik_batch``
solve it, every solution reaches it, and the joints it came from are among them.

Seeded joint sets 1e-12..1e-3 rad (or that fraction of the arm's size, for a slide) off
each singularity, every decade alike: the wrist at q5 = 0 or pi, the wrist centre on axis
1, the elbow stretched or folded (``singular_poses``, from the arm's axes alone), for
every 6R of ``test_pieper_batch.ARMS`` and the lesson 6R arms (Aula 10, Barrientos,
Epson C4), and the wrist flip and the prismatic joint's double root (``d2 + a1 + a3 = 0``)
of the 5-DOF PPRRR and RPRRR; all on a tilted base with a tool. Such a pose is reachable
by construction, so neither path may call it unreachable (before the general solver
re-solved the shoulders near axis 1 it refused some poses of the quartic arm there, and
gave others with joint 1 off by up to a radian). Where a result is flagged singular the
free joints are a family: ``arm.ik(T, near=q)`` takes them from ``q`` and must hold ``q``
whole, and the batch must hold ``q``'s other joints.
"""

import numpy as np
import pytest
from singular_poses import CROSSING_JOINT, singular_q
from test_pieper_batch import ARMS, IDS, same_q_bound, with_base_tool

import rikin
from rikin import robots

pi = np.pi
FK_TOL = 1e-9
PER_KIND = 10

LESSON_6R = [robots.aula10_6r, robots.barrientos_6r, robots.epson_c4]
LESSON_IDS = ["aula10", "barrientos", "epson-c4"]


def offsets(rng, n):
    """``n`` signed offsets, one per slice of the decades 1e-12..1e-3, ``(n,)``."""
    exps = -12 + 9 * (np.arange(n) + rng.uniform(size=n)) / n
    return 10.0**exps * rng.choice([-1.0, 1.0], n)


def near_6r(arm, rng):
    """Joint sets ``(5 * PER_KIND, 6)`` off each singularity of a 6R with a spherical
    wrist, along the joint that crosses it."""
    out = []
    for kind, joint in CROSSING_JOINT.items():
        for off in offsets(rng, PER_KIND):
            q = singular_q(arm, kind, rng)
            q[joint] += off
            out.append(q)
    return np.array(out)


def near_5dof(arm, rng):
    """Joint sets off the wrist flip (q4 = 0 or pi) of a PPRRR or RPRRR, and for the
    RPRRR off the prismatic joint's double root (the wrist centre at distance a2 from
    axis 1), ``(k * PER_KIND, 5)``."""
    theta_off = np.array([float(lk.offset) for lk in arm.links])
    kinds = ["wrist0", "wrist_pi"] + (["radial"] if arm.joint_types == "RPRRR" else [])
    out = []
    for kind in kinds:
        for off in offsets(rng, PER_KIND):
            q = rng.uniform(-pi, pi, 5)
            slide = ~arm.revolute
            q[slide] = rng.uniform(-1.0, 1.0, int(slide.sum())) * arm.scale
            if kind == "radial":
                lk = arm.links[1]
                q[1] = -(float(lk.d) + float(lk.offset)) + off * arm.scale
            else:
                q[3] = (0.0 if kind == "wrist0" else pi) - theta_off[3] + off
            out.append(q)
    return np.array(out)


def joint_gap(arm, Q, q, joints=None):
    """The least, over the rows of ``Q (k, n)``, of the largest difference from ``q (n,)``
    in ``joints`` (0-based; all by default): revolute modulo 2 pi (rad), slides relative
    to the arm's size. ``inf`` when ``Q`` has no row."""
    d = np.where(arm.revolute, rikin.wrap_angle(Q - q), (Q - q) / arm.scale)
    d = np.abs(d if joints is None else d[:, joints])
    return float(d.max(-1).min()) if len(Q) else np.inf


def fixed_joints(arm, free):
    """The joints (0-based) a singular family keeps: all but the free ones (``free``,
    1-based), and, where a positioning joint is free, but the wrist's too (they turn
    with it)."""
    n = arm.n
    keep = [j for j in range(n) if j + 1 not in free]
    if any(f <= n - 3 for f in free):
        keep = [j for j in keep if j < n - 3]
    return keep


def assert_reaches(arm, Q, T, what):
    """Every row of ``Q (k, n)`` reaches ``T`` by FK: position to ``FK_TOL`` of the
    arm's size, rotation entries to ``FK_TOL``."""
    F = arm.fk(Q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max(initial=0.0) <= FK_TOL * arm.scale, what
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max(initial=0.0) <= FK_TOL, what


def assert_solved(arm, q):
    """``arm.ik`` and ``arm.ik_batch`` of the poses ``arm.fk(q)``: never unreachable,
    every solution reaches its pose, ``q`` among them (to what the pose fixes,
    ``same_q_bound``; in a singular family, up to its free joints)."""
    Ts = arm.fk(q)
    batch = arm.ik_batch(Ts, workers=2)
    for n, T in enumerate(Ts):
        what = f"{arm.name}: pose {n}, q = {q[n].tolist()}"
        bound = same_q_bound(arm, q[n][None])
        res = arm.ik(T)  # raises UnreachableError on the defect
        assert len(res) > 0, what
        assert_reaches(arm, res.q, T, what)
        if res.singular:
            keep = fixed_joints(arm, res.free_joints)
            assert joint_gap(arm, res.q, q[n], keep) <= bound, what
            res = arm.ik(T, near=q[n])  # the free joints from q
            assert_reaches(arm, res.q, T, what)
        assert joint_gap(arm, res.q, q[n]) <= bound, (what, joint_gap(arm, res.q, q[n]))
        got = batch.q[n][batch.valid[n]]
        assert len(got) > 0, what + ": the batch has no solution"
        assert_reaches(arm, got, T, what + " (batch)")
        keep = fixed_joints(arm, res.free_joints) if batch.singular[n] else None
        assert joint_gap(arm, got, q[n], keep) <= bound, what + " (batch)"


@pytest.mark.parametrize("make", ARMS, ids=IDS)
def test_typed_6r_near_each_singularity(make):
    """Fails before the shoulders near axis 1 were re-solved: the quartic arm."""
    rng = np.random.default_rng(2900)
    arm = with_base_tool(make)
    assert_solved(arm, near_6r(arm, rng))


@pytest.mark.parametrize("make", LESSON_6R, ids=LESSON_IDS)
def test_lesson_6r_near_each_singularity(make):
    rng = np.random.default_rng(2901)
    arm = with_base_tool(make)
    assert_solved(arm, near_6r(arm, rng))


@pytest.mark.parametrize("make", [robots.pprrr, robots.rprrr], ids=["pprrr", "rprrr"])
def test_5dof_near_each_singularity(make):
    rng = np.random.default_rng(2902)
    arm = with_base_tool(make)
    assert_solved(arm, near_5dof(arm, rng))


def test_quartic_arm_pose_near_its_shoulder_singularity():
    """The pose ``test_ik_fast_path_labels`` found refused ("at the edge of reach"): the
    wrist centre 4e-9 of the arm's size from axis 1, both shoulders reached."""
    arm = with_base_tool(ARMS[IDS.index("quartic")])
    q = np.array([-1.3491687564215764, -2.597564047847945, -1.392578559657072,
                  -2.6597689612852373, -1.7644395870605376, -1.1833092125086626])
    T = arm.fk(q)
    res = arm.ik(T)
    assert not res.singular and len(res) == 4  # two shoulders, two wrists each
    assert_reaches(arm, res.q, T, "quartic")
    assert joint_gap(arm, res.q, q) <= same_q_bound(arm, q[None])
    front = {b.shoulder for b in res.branches}
    assert front == {"front", "back"}
    assert_solved(arm, q[None])
