"""``ik_batch``'s leftover poses: those the array kernel of a family (spherical wrist, three
parallel axes) hands to the general solver are gathered from every chunk and thread and
solved together at the end, at most a chunk's worth per call (``_Batch.solve_deferred``).
Each must land in its own row, whatever the chunks, the threads and the number of calls.
"""

import numpy as np
import pytest
from singular_poses import CROSSING_JOINT, singular_q
from test_pieper_batch import puma_modified, with_base_tool

import rikin
from rikin import Link, SerialArm
from rikin.ik import api, families6r

pi = np.pi


def ur5e():
    """Universal Robots UR5e (its published DH table, metres): three parallel axes."""
    return SerialArm((
        Link(d=0.1625, alpha=pi / 2), Link(a=-0.425), Link(a=-0.3922),
        Link(d=0.1333, alpha=pi / 2), Link(d=0.0997, alpha=-pi / 2), Link(d=0.0996),
    ), name="UR5e", units="m")


def poses_with_many_leftovers(arm, seed):
    """Random poses interleaved with singular and near-singular ones (which the array
    kernels leave to the general solver), ``(n, 4, 4)``, and the joints."""
    rng = np.random.default_rng(seed)
    q = list(rng.uniform(-pi, pi, (120, 6)))
    for k in range(40):
        kind = list(CROSSING_JOINT)[k % len(CROSSING_JOINT)]
        qs = singular_q(arm, kind, rng)
        if k % 3:
            qs[CROSSING_JOINT[kind]] += 10.0 ** rng.uniform(-9, -4)
        q.insert(3 * k + 1, qs)
    q = np.array(q)
    return arm.fk(q), q


@pytest.mark.parametrize("make", [lambda: with_base_tool(puma_modified), ur5e],
                         ids=["puma-craig", "ur5e"])
def test_leftovers_of_every_chunk_fill_their_own_rows(make):
    arm = make()
    Ts, q = poses_with_many_leftovers(arm, 5)
    twin = arm._dh if arm.reversed_joints else arm
    kernel = families6r.solver_for(twin).batch_kernel(twin)
    suspect = kernel.solve(np.ascontiguousarray(Ts.transpose(1, 2, 0)))[2]
    assert suspect.sum() >= 10  # enough leftovers for several general calls below
    one = arm.ik_batch(Ts, workers=1, chunk_size=4096)
    for workers, chunk in ((1, 7), (2, 16), (2, 33)):
        many = arm.ik_batch(Ts, workers=workers, chunk_size=chunk)
        assert np.array_equal(one.valid, many.valid)
        assert np.array_equal(one.singular, many.singular)
        assert np.array_equal(one.q, many.q, equal_nan=True)
    # and each row is its own pose's: every valid slot reaches it, and away from a
    # singularity (where joints 4 and 6 share one turn) the generating joints are a slot
    for i in range(len(Ts)):
        for s in np.flatnonzero(one.valid[i]):
            assert np.allclose(arm.fk(one.q[i, s]), Ts[i], atol=1e-8)
        if one.singular[i]:
            continue
        diff = np.where(one.valid[i][:, None], one.q[i] - q[i], pi)
        assert np.abs(rikin.wrap_angle(diff)).max(axis=1).min() <= 1e-5
    assert one.singular.any()


def test_leftovers_are_solved_at_most_a_chunk_per_call(monkeypatch):
    arm = with_base_tool(puma_modified)
    Ts, _ = poses_with_many_leftovers(arm, 6)
    sizes = []
    general = api._Batch.general

    def spy(self, rows, T_chunk):
        sizes.append(len(T_chunk))
        return general(self, rows, T_chunk)

    monkeypatch.setattr(api._Batch, "general", spy)
    arm.ik_batch(Ts, workers=1, chunk_size=9)
    size = api._chunk_length(len(Ts), 9, 1)
    assert sizes and max(sizes) <= size and sum(sizes) >= 10
    assert len(sizes) == -(-sum(sizes) // size)  # gathered: full calls but the last
