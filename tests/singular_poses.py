"""Joint values at the singularities of a 6R arm with a spherical wrist, from its geometry.

Shared by the general solver's tests and ``benchmarks/bench_ik6r.py``. The poses are built
from the arm's joint axes alone (FK), never from a solver: the wrist centre where axes 4 and
5 meet, and its distance from axes 1 and 2.
"""

from __future__ import annotations

import numpy as np

pi = np.pi

#: the kinds of :func:`singular_q`, and the joint (0-based) whose change crosses each
CROSSING_JOINT = {"wrist0": 4, "wrist_pi": 4, "shoulder": 1, "stretched": 2, "folded": 2}


def wrist_centre(arm, q):
    """Where axes 4 and 5 meet (their closest points), world frame, ``q.shape[:-1] + (3,)``."""
    o, z = arm.joint_axes(q)
    w = o[..., 3, :] - o[..., 4, :]
    b = (z[..., 3, :] * z[..., 4, :]).sum(-1)
    d, e = (z[..., 3, :] * w).sum(-1), (z[..., 4, :] * w).sum(-1)
    return o[..., 3, :] + ((b * e - d) / (1 - b * b))[..., None] * z[..., 3, :]


def off_axis(arm, q, i):
    """The wrist centre's offset from joint axis ``i`` (1-based), perpendicular to it."""
    o, z = arm.joint_axes(q)
    v = wrist_centre(arm, q) - o[..., i - 1, :]
    zi = z[..., i - 1, :]
    return v - (v * zi).sum(-1, keepdims=True) * zi


def onto_axis1(arm, q):
    """``q`` with joints 2, 3 moved (Gauss-Newton) to bring the wrist centre onto axis 1, or
    as near as the arm's offsets let it come."""
    q = np.array(q, dtype=float)
    g = np.linspace(-pi, pi, 121)[:-1]
    Q = np.tile(q, (g.size**2, 1))
    Q[:, 1], Q[:, 2] = np.repeat(g, g.size), np.tile(g, g.size)
    q = Q[int(np.argmin(np.linalg.norm(off_axis(arm, Q, 1), axis=-1)))]  # then Gauss-Newton
    # Where the centre touches axis 1 only at a fold (the Epson C4's equal links), the
    # Jacobian is singular at the answer and the iterates wander around it at 1e-11..1e-9
    # of the arm's size, differently on each CPU's BLAS: the nearest iterate is the answer.
    best, best_q = np.inf, q.copy()
    for _ in range(60):
        r = off_axis(arm, q, 1)
        if np.linalg.norm(r) < best:
            best, best_q = np.linalg.norm(r), q.copy()
        J = np.empty((3, 2))
        for c, j in enumerate((1, 2)):
            dq = np.zeros(6)
            dq[j] = 1e-7
            J[:, c] = (off_axis(arm, q + dq, 1) - off_axis(arm, q - dq, 1)) / 2e-7
        step = np.linalg.lstsq(J, -r, rcond=None)[0]
        q[1:3] += np.clip(step, -0.3, 0.3)
        if np.abs(step).max() < 1e-15:
            break
    return q if np.linalg.norm(off_axis(arm, q, 1)) < best else best_q


def elbow_extreme(arm, q, stretched):
    """``q`` with joint 3 where the wrist centre is farthest from (or nearest to) axis 2."""
    q = np.array(q, dtype=float)
    x = np.linspace(-pi, pi, 3601)
    for _ in range(7):
        Q = np.tile(q, (len(x), 1))
        Q[:, 2] = x
        r = np.linalg.norm(off_axis(arm, Q, 2), axis=-1)
        i = int(np.argmax(r if stretched else -r))
        h = x[1] - x[0]
        x = np.linspace(x[i] - 2 * h, x[i] + 2 * h, 41)
    q[2] = x[20]
    return q


def singular_q(arm, kind, rng, regular_wrist=True):
    """Random joints put exactly at a singularity of ``kind`` (a key of ``CROSSING_JOINT``).

    With ``regular_wrist``, q5 is kept 0.3..2.8 rad from the wrist's singularities (unless
    ``kind`` is one of them); otherwise it is uniform like the others.
    """
    off = np.array([float(lk.offset) for lk in arm.links])
    q = rng.uniform(-pi, pi, 6)
    if regular_wrist:
        q[4] = rng.uniform(0.3, 2.8) * rng.choice([-1, 1]) - off[4]
    if kind in ("wrist0", "wrist_pi"):
        q[4] = (0.0 if kind == "wrist0" else pi) - off[4]
    elif kind == "shoulder":
        q = onto_axis1(arm, q)
    elif kind in ("stretched", "folded"):
        q = elbow_extreme(arm, q, kind == "stretched")
    else:
        raise ValueError(f"unknown singularity kind {kind!r}")
    return q
