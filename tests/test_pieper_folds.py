"""The general 6R closed form near the folds of joints 1-3, settled by 40-digit Newton.

A fold is where two position branches meet: the elbow at the inner or outer edge of
what joints 1-3 reach, and (the Puma 560, whose shoulder offset keeps the wrist centre
at least |d2 + d3| from axis 1) the centre on the cylinder of that radius, where the two
shoulders meet. A pose ``x`` (relative) inside a fold has two solutions ``~sqrt(x)``
apart, each fixed by the float pose only to ``~eps / sigma_min`` of its Jacobian. So
near a fold ``arm.ik`` must return both while the pose tells them apart, each as exact
as that (checked against Newton's method on the same float pose in 40-digit
arithmetic), and one solution flagged as the elbow singularity where they coincide
to rounding, never two near-identical unflagged ones, never losing a root.
"""

import numpy as np
import pytest
from mp_reference import exact_root
from singular_poses import elbow_extreme, onto_axis1
from test_pieper import (
    abb_irb120,
    assert_all_reach,
    epson_c4_table,
    kuka_kr5,
    kuka_kr6,
    puma560,
)

import rikin
from rikin import Link, SerialArm

pi = np.pi
ARMS = [puma560, kuka_kr5, kuka_kr6, abb_irb120, epson_c4_table]
#: how far (rad) the joint that crosses the fold is moved from it; a fold is quadratic in
#: that joint, so the pose moves by about their squares: from 1e-6 (two branches well
#: apart) to below rounding (the pose at the fold, on either side of it)
JOINT_OFFSETS = [1e-3, 1e-5, 1e-7, 1e-8, 1e-9, 1e-10, 1e-12]


def wrapped(x):
    return np.abs(rikin.wrap_angle(x))


def sigma_min(arm, q):
    J = arm.jacobian(q)
    return np.linalg.svd(np.concatenate([J[:3] / arm.scale, J[3:]]), compute_uv=False)[-1]


def resolution(arm, q):
    """How well the float pose fixes the joints at the root ``q`` (rad)."""
    return 1e-9 + 1e-13 / sigma_min(arm, q)


def check_against_exact(arm, T, res, guesses):
    """Every exact root near the fold (from the solutions there or the guesses) is a
    solution, to what the pose fixes; every solution there is an exact root, or the
    flagged meeting point of two; no two solutions are one root. Solutions farther than
    0.1 rad from every other and from the guesses are regular roots: FK-checked only."""
    assert_all_reach(arm, res, T)
    Q = res.q
    D = wrapped(Q[:, None] - Q[None]).max(-1)
    D[np.eye(len(Q), dtype=bool)] = np.inf
    G = np.array(guesses)
    near = (D.min(axis=1) < 0.1) | (wrapped(Q[:, None] - G[None]).max(-1).min(axis=1) < 0.1)
    own = {i: exact_root(arm, Q[i], T) for i in np.flatnonzero(near)}
    roots = []
    for e in list(own.values()) + [exact_root(arm, g, T) for g in G]:
        if e is not None and not any(wrapped(e - r).max() < 1e-12 for r in roots):
            roots.append(e)
    # no isolated root there: the meeting point of two branches, or joint 2 free (the wrist
    # centre on axis 2 within SINGULAR_TOL, where FK holds whatever q2)
    why = res.singularity or ""
    coincide = "edge of what joints 1-3 reach" in why or "on the axis of joint 2" in why
    for r in roots:
        d = wrapped(Q - r).max(axis=1).min()
        assert d <= resolution(arm, r), ("root lost", r, d, resolution(arm, r))
    for i, e in own.items():
        if e is None:  # no isolated root there: only as the flagged meeting point
            assert coincide, ("unflagged solution that is no root", Q[i], why)
        else:
            assert wrapped(Q[i] - e).max() <= resolution(arm, e), ("inexact", Q[i], e)
    found = [e for e in own.values() if e is not None]
    for i in range(len(found)):
        for j in range(i + 1, len(found)):
            assert wrapped(found[i] - found[j]).max() > 1e-12, "one root returned twice"
    return roots


def fold_poses(arm, kind, rng, n=1):
    """(offset, q, T, mirror guess) at each of ``JOINT_OFFSETS`` from the fold ``kind``."""
    for _ in range(n):
        q0 = rng.uniform(-pi, pi, 6)
        q0[4] = rng.uniform(0.4, 2.6) * rng.choice([-1, 1]) - float(arm.links[4].offset)
        if kind == "shoulder":
            q0 = onto_axis1(arm, q0)
            j = 1
        else:
            q0 = elbow_extreme(arm, q0, kind == "stretched")
            j = 2
        for x in JOINT_OFFSETS:
            dq = x * rng.choice([-1, 1])
            q = q0.copy()
            q[j] += dq
            mirror = q0.copy()
            mirror[j] -= dq
            yield x, q, arm.fk(q), mirror


#: more folded elbows, where judging a close pair at its straight midpoint in joint space
#: (not on the valley's floor) or on F alone lost a root or left two unflagged solutions;
#: and the C4's, whose equal links fold the wrist centre onto axis 2: 1e-8 rad from there
#: its distance from axis 2 (2.5e-6 mm) was read from the joint-3 double root, known only
#: to ~sqrt(eps), called zero, and the generating q's shoulder (4 solutions) was lost
MORE_FOLDS = [(kuka_kr6, "folded", 1), (kuka_kr6, "folded", 2), (abb_irb120, "folded", 1)] + [
    (epson_c4_table, "folded", seed) for seed in (1, 3, 6, 10)
]


@pytest.mark.parametrize(
    ("make", "kind", "seed"),
    [(make, kind, 0) for make in ARMS for kind in ("folded", "stretched")] + MORE_FOLDS,
)
def test_elbow_fold_both_branches_or_one_flagged(make, kind, seed):
    """(a) Joint 3 1e-3 ... 1e-12 rad from the elbow's fold: both branches, each an exact root,
    while they are two; one flagged solution where they meet; the generating q kept."""
    arm = make()
    rng = np.random.default_rng(1000 * seed + 41 + ARMS.index(make))
    for x, q, T, mirror in fold_poses(arm, kind, rng):
        res = arm.ik(T)
        roots = check_against_exact(arm, T, res, [q, mirror])
        if not roots:  # the pose at the fold to rounding
            assert wrapped(res.q - q).max(axis=1).min() < 1e-6
        # two distinct exact roots, near enough for Newton from the mirrored q to reach the
        # other (folded, the other branch turns joint 2 by ~ dq3 L / the centre's least
        # distance from axis 2: farther)
        if kind == "stretched" and x >= 1e-5:
            assert len(roots) >= 2, (x, len(roots))


def equal_links(convention):
    """A 6R whose links 2 and 3 are equal and whose axes 1 and 2 meet (a Puma without its
    offsets): folded, the wrist centre comes onto the shoulder, where axes 1 and 2 meet."""
    if convention == "standard":
        links = (Link(d=0.6718, alpha=pi / 2), Link(a=0.4318), Link(alpha=-pi / 2),
                 Link(d=0.4318, alpha=pi / 2), Link(alpha=-pi / 2), Link())
    else:
        links = (Link(d=0.3), Link(alpha=-pi / 2), Link(a=0.25), Link(d=0.25, alpha=-pi / 2),
                 Link(alpha=pi / 2), Link(alpha=-pi / 2))
    return SerialArm(links, convention=convention, name=f"equal links ({convention})", units="m")


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("seed", [0, 1])
def test_equal_links_folded_onto_the_shoulder(convention, seed):
    """Equal links, axes 1 and 2 meeting: joint 3 1e-3 ... 1e-12 rad from folded puts the
    wrist centre ~l dq from the shoulder. That distance is exact to rounding, so both elbow
    branches are fixed by the pose (they are ~2 dq apart, not ~sqrt(dq)); solved from the
    squared distance, as a sinusoid, joint 3 was off by ~sqrt(eps) and the pose 1e-8 rad
    from folded was declared out of reach."""
    arm = equal_links(convention)
    rng = np.random.default_rng(7 + seed)
    for x, q, T, mirror in fold_poses(arm, "folded", rng):
        res = arm.ik(T)
        check_against_exact(arm, T, res, [q, mirror])
        assert len(res) == 8, (x, len(res))


def test_puma_shoulder_offset_fold():
    """(c) The Puma's joint 2 1e-3 ... 1e-12 rad from where its wrist centre is on the
    cylinder of radius |d3| around axis 1, where its two shoulders meet: both shoulders while they
    are two, each an exact root; one flagged solution where they meet."""
    arm = puma560()
    rng = np.random.default_rng(5)
    for x, q, T, mirror in fold_poses(arm, "shoulder", rng):
        o, z = arm.joint_axes(q)
        res = arm.ik(T)
        check_against_exact(arm, T, res, [q, mirror])
        assert wrapped(res.q - q).max(axis=1).min() <= resolution(arm, q) + 1e-6 * (x < 1e-6)
        if x >= 1e-5:  # two shoulders 2e-5 rad or more apart: both there
            assert len({b.shoulder for b in res.branches}) == 2, x
