"""The FK check of the one-pose fast path: how far a few solutions' FK is from the target.

For one pose numpy's cost per call (about a microsecond), not the arithmetic, is what
counts, so :class:`FKCheck` computes the check in few calls: eight for a 5R or 6R arm
(one more per further pair of links):

* Each link of an all-revolute arm is ``cos(q) C1 + sin(q) C2 + C3`` with constant
  4x4 matrices (:meth:`rikin.SerialArm._link_constants`; the joint offset folds into
  ``C1, C2`` since ``cos(q + o)`` and ``sin(q + o)`` are linear in ``cos q, sin q``; the
  base into the first link, the tool into the last). The product of two neighbouring
  links is then linear in the 9 products ``v_i[a] v_j[b]`` of their rows ``v = [cos q,
  sin q, 1]`` (one broadcast multiplication for all pairs), so one matmul with a
  constant gives every pair's product of every solution: a stacked ``matmul`` of 4x4
  matrices costs a BLAS call per matrix, which this saves three times in five.
* The weight of the position column (``1 / arm.scale``) is folded into the last link:
  ``F diag(1, 1, 1, w)`` scales the position column and leaves the rotation alone.
* The last product and the subtraction of the target are one matmul,
  ``[A | -I] @ [B ; T W] = A B - T W``, whose halves live in buffers that the earlier
  calls write into (``out=``); one ``vdot`` then gives the sum of squares.

The buffers are per thread (``threading.local``), so arms may be solved from several
threads at once.
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np

from .._validate import FloatArray

__all__ = ["FKCheck"]


class _PerThread(threading.local):
    """Each thread's buffers, by number of solutions."""

    def __init__(self) -> None:
        self.views: dict[int, tuple[Any, ...]] = {}


class FKCheck:
    """Sum of squared FK errors of ``k`` solutions of one pose, for an all-revolute arm.

    ``check(q, T)`` is ``sum over solutions of ||R(q) - R_T||_F^2 + |p(q) - p_T|^2 /
    scale^2`` with ``F(q) = [R(q), p(q)]`` the world TCP pose by FK (base and tool
    included). ``check(q, T) <= tol**2`` implies that every solution's rotation entries
    are within ``tol`` of the target's and its position within ``tol * arm.scale``:
    the general path's check (relative to ``max(scale, |p_T|)``), or stricter.

    Parameters
    ----------
    arm : SerialArm
        An arm whose joints are all revolute.
    """

    def __init__(self, arm: Any) -> None:
        C1, C2, C3, offsets = arm._link_constants()
        co, so = np.cos(offsets)[:, None, None], np.sin(offsets)[:, None, None]
        A1, A2 = co * C1 + so * C2, co * C2 - so * C1  # Rz(q + o) in cos q, sin q
        A3 = C3.copy()
        w = 1.0 / arm.scale
        for X in (A1, A2, A3):
            X[-1][:, 3] *= w
        n = arm.n
        padded = max(4, n + n % 2)  # identity links pad the chain to pairs (>= 2 pairs)
        eye = np.eye(4)
        links = [(A1[j], A2[j], A3[j]) for j in range(n)]
        links += [(0.0 * eye, 0.0 * eye, eye)] * (padded - n)
        m = padded // 2
        # pair i (links 2i, 2i+1): the sum over a, b of v_2i[a] v_2i+1[b] K_2i[a] K_2i+1[b]
        # (K = A1, A2, A3; v = [cos q, sin q, 1]), one block of C per pair
        C = np.zeros((9 * m, 16 * m))
        for i in range(m):
            first, second = links[2 * i], links[2 * i + 1]
            for a in range(3):
                for b in range(3):
                    C[9 * i + 3 * a + b, 16 * i : 16 * i + 16] = (first[a] @ second[b]).ravel()
        self._C = C
        self._W = np.ones((4, 4))
        self._W[:, 3] = w
        self._n, self._pairs = n, m
        self._local = _PerThread()

    def _buffers(self, k: int) -> tuple[Any, ...]:
        """Views of this thread's buffers for ``k`` solutions, made once per ``k``."""
        n, m = self._n, self._pairs
        v = np.zeros((k, 2 * m, 3))  # [cos q, sin q, 1] per joint; padding joints [0, 0, 1]
        v[:, :, 2] = 1.0
        features = np.empty((k, m, 3, 3))  # each pair's v_2i[a] v_2i+1[b]
        # the pairs, then the weighted target right after the last pair: [B ; T W]
        pairs = np.empty((k, 16 * (m + 1)))
        P = pairs[:, : 16 * m]
        lower = pairs[:, 16 * (m - 1) :].reshape(k, 8, 4)
        TW = pairs[:, 16 * m :].reshape(k, 4, 4)
        left = np.empty((k, 4, 8))  # [A | -I]
        left[:, :, 4:] = -np.eye(4)
        P4 = P.reshape(k, m, 4, 4)
        heads = [P4[:, i] for i in range(m - 1)]
        A = left[:, :, :4]
        return (v[:, :n, 0], v[:, :n, 1], v[:, 0::2, :, None], v[:, 1::2, None, :], features,
                features.reshape(k, 9 * m), P, heads, A, TW, left, lower)

    def __call__(self, q: FloatArray, T: FloatArray) -> float:
        """The sum of squares above for ``q (k, n)`` (radians) and the world pose ``T (4, 4)``."""
        views = self._local.views
        b = views.get(len(q))
        if b is None:
            b = views[len(q)] = self._buffers(len(q))
        cos, sin, even, odd, features, flat, P, heads, A, TW, left, lower = b
        # out given by position: a keyword costs a ufunc call a tenth more
        _cos(q, cos)
        _sin(q, sin)
        _multiply(even, odd, features)
        _matmul(flat, self._C, P)
        if len(heads) == 2:  # a 5R or 6R
            _matmul(heads[0], heads[1], A)
        elif len(heads) == 1:
            np.copyto(A, heads[0])
        else:
            head = heads[0]
            for nxt in heads[1:-1]:
                head = head @ nxt
            _matmul(head, heads[-1], out=A)
        _multiply(T, self._W, TW)
        D = _matmul(left, lower)
        return float(_vdot(D, D))


# bound once: a module attribute lookup per call is a tenth of a small ufunc call
_cos, _sin, _matmul, _multiply, _vdot = np.cos, np.sin, np.matmul, np.multiply, np.vdot
