"""``arm.ik`` one pose at a time against ``arm.ik_batch``: the same solutions with the same
labels, for a 6R with a spherical wrist typed as a DH table.

``arm.ik`` of a regular pose takes the plain-float kernel (``PieperKernel``, its orthogonal
wrist written out in ``_finish_orthogonal``); the batch takes the array kernel
(``pieper_batch``) and hands suspect poses to the general solver. Both must give every
solution and label it the same way. Arms on a tilted base with a tool, standard and
modified DH, reversed joints; seeded random poses and poses near the wrist flip (q5 = 0
or pi), the shoulder singularity (wrist centre on axis 1) and the elbow's reach edge and
fold, 1e-9..1e-3 rad off, where the one-pose kernel declines or decides near its margins.
"""

import numpy as np
import pytest
from test_pieper_batch import ARMS, IDS, dh_twin, near_singular_q, same_q_bound, with_base_tool

import rikin

pi = np.pi
SAME_Q = 1e-9


def matched(res_q, res_labels, got, got_labels, bound, singular=False):
    """Each of ``arm.ik``'s solutions has one of the batch's within ``bound`` (rad, modulo
    2 pi) with the same label, and (unless the pose is singular, where the batch keeps a
    slot per branch, duplicates included) the batch has no other: the sets equal, sorted."""
    gap = np.abs(rikin.wrap_angle(res_q[:, None] - got[None])).max(-1)
    for i, label in enumerate(res_labels):
        near = np.flatnonzero(gap[i] <= bound)
        assert any(got_labels[j] == label for j in near), (i, label, gap[i].min())
    if not singular:
        assert got.shape == res_q.shape
        assert sorted(gap.argmin(axis=1).tolist()) == list(range(len(got)))  # one to one


@pytest.mark.parametrize("make", ARMS, ids=IDS)
def test_one_pose_and_batch_same_solutions_and_labels(make):
    rng = np.random.default_rng(29)
    arm = with_base_tool(make)
    q = np.concatenate([rng.uniform(-pi, pi, (60, 6)), near_singular_q(arm, rng, 6)])
    off = ~np.isin(np.arange(len(q)), np.arange(60, len(q), 6))  # the exactly singular
    Ts = arm.fk(q)
    batch = arm.ik_batch(Ts, workers=2)
    kernel, _ = dh_twin(arm).__dict__.get("_single_kernel") or (None, None)
    fast = 0
    for n, T in enumerate(Ts):
        res = arm.ik(T)  # FK of joints: reachable (tests/test_reachable_near_singular.py)
        if kernel is None:
            kernel, _ = dh_twin(arm).__dict__["_single_kernel"]
        took_fast = kernel.solve(T.tolist()) is not None  # (a reversed arm: its DH twin)
        fast += took_fast and n < 60
        got = batch.q[n][batch.valid[n]]
        if res.singular or batch.singular[n]:
            assert res.singular == batch.singular[n], n
            if not off[n]:
                continue  # exactly singular: representatives of a family, FK-checked apart
        bound = SAME_Q if took_fast else same_q_bound(arm, res.q)
        matched(res.q, res.labels, got, batch.labels(n), bound, bool(res.singular))
        F = arm.fk(res.q)
        assert np.abs(F[:, :3, 3] - T[:3, 3]).max(initial=0.0) <= 1e-9 * arm.scale
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max(initial=0.0) <= 1e-9
    assert fast >= 57  # regular random poses take the one-pose kernel (~0.3% declined)
