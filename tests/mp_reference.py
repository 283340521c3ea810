"""40-digit reference for the 6R tests and ``benchmarks/bench_ik6r.py``: FK of a rikin arm
in mpmath and Newton's method on a float pose, to settle whether a solution one side
lacks is a real root (a miss) or the same root badly conditioned."""

import math

import mpmath as mp
import numpy as np

pi = math.pi


def _mp_link(lk, convention, q):
    th = q + mp.mpf(float(lk.offset))
    al = float(lk.alpha)
    ca, sa = mp.cos(mp.mpf(al)), mp.sin(mp.mpf(al))
    if abs(abs(al) - pi / 2) < 1e-15:  # the table's exact twists, not their float values
        ca, sa = mp.mpf(0), mp.mpf(math.copysign(1, al))
    elif abs(abs(al) - pi) < 1e-15:
        ca, sa = mp.mpf(-1), mp.mpf(0)
    elif al == 0:
        ca, sa = mp.mpf(1), mp.mpf(0)
    ct, st = mp.cos(th), mp.sin(th)
    a, d = mp.mpf(float(lk.a)), mp.mpf(float(lk.d))
    Rz = mp.matrix([[ct, -st, 0, 0], [st, ct, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    Tz = mp.matrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, d], [0, 0, 0, 1]])
    TxRx = mp.matrix([[1, 0, 0, a], [0, ca, -sa, 0], [0, sa, ca, 0], [0, 0, 0, 1]])
    return Rz * Tz * TxRx if convention == "standard" else TxRx * Rz * Tz


def _mp_links(arm, q):
    """Each link's transform at its joint value ``q[i]`` (mpmath 4 x 4 matrices)."""
    return [_mp_link(lk, arm.convention, qi) for lk, qi in zip(arm.links, q, strict=True)]


def _error_at(F, arm, T):
    """The error of the pose ``F`` (base and links, before the tool) from ``T``: position
    (over the arm's scale) and rotation (the skew part of F^T T), a 6-vector."""
    F = F * mp.matrix(arm.tool.tolist())
    R = F[:3, :3].T * mp.matrix(T[:3, :3].tolist())
    e = [(mp.mpf(T[i, 3]) - F[i, 3]) / arm.scale for i in range(3)]
    e += [(R[2, 1] - R[1, 2]) / 2, (R[0, 2] - R[2, 0]) / 2, (R[1, 0] - R[0, 1]) / 2]
    return mp.matrix(e)


def _chain(arm, q):
    """The links at ``q`` and their running products: ``before[j]`` is the base times
    links 0 .. j-1 (``before[-1]``: the whole arm but the tool)."""
    links = _mp_links(arm, q)
    before = [mp.matrix(arm.base.tolist())]
    for L in links:
        before.append(before[-1] * L)
    return links, before


def mp_error(arm, q, T):
    return _error_at(_chain(arm, q)[1][-1], arm, T)


def _jacobian(arm, x, T, h, chain, e):
    """The forward-difference Jacobian of ``mp_error`` at ``x`` (step ``h`` in each joint;
    ``chain`` and ``e`` at ``x``), the same numbers to the bit as ``mp_error`` at each moved
    ``x`` gives: the products before the moved joint, and the links after it, are reused."""
    links, before = chain
    J = mp.matrix(6, 6)
    for j, lk in enumerate(arm.links):
        F = before[j] * _mp_link(lk, arm.convention, x[j] + h)
        for L in links[j + 1:]:
            F = F * L
        col = (_error_at(F, arm, T) - e) / h
        for i in range(6):
            J[i, j] = col[i]
    return J


def exact_root(arm, q, T, steps=30, tol=1e-32):
    """Newton's method in 40-digit arithmetic on the float pose ``T`` from ``q``: the
    isolated root it converges to, or None (no root there: a pose outside the fold by
    rounding, or a double root)."""
    with mp.workdps(40):
        x = [mp.mpf(float(v)) for v in q]
        h = mp.mpf(10) ** -25
        for _ in range(steps):
            chain = _chain(arm, x)
            e = _error_at(chain[1][-1], arm, T)
            if mp.norm(e) < mp.mpf(tol):
                # modulo 2 pi, as rikin reports joints (Newton may wander turns away)
                return np.angle(np.exp(1j * np.array([float(v) for v in x])))
            try:
                dx = mp.lu_solve(_jacobian(arm, x, T, h, chain, e), e)
            except (ZeroDivisionError, TypeError):
                return None
            x = [xi - dxi for xi, dxi in zip(x, dx, strict=True)]  # e = T - FK
    return None
