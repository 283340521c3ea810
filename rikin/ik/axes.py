"""An arm's joint axes at ``q = 0``, and the two rotation subproblems the families solve.

Every joint moves its link about (revolute) or along (prismatic) a line fixed in the
previous link. At ``q = 0`` these lines, in frame 0, are the arm's *axes*: a unit
direction ``w_i`` and a point ``r_i`` on each. Moving joint ``i`` by ``q_i`` from there
turns everything beyond it about that line by ``q_i`` (or shifts it by ``q_i w_i``), so
a point ``c`` fixed in link ``k`` is at

    ``p(q) = E_1(q_1) E_2(q_2) ... E_k(q_k) c``

with ``E_i`` the motion of joint ``i`` about its axis at ``q = 0`` (the product of
exponentials). The same ``q`` as in the DH table, whatever its convention, offsets and
twists; the families (:mod:`rikin.ik.positioning`) read their geometry from these axes.

The subproblems (Paden and Kahan):

* :func:`turn_angle` (subproblem 1): the angle about an axis that turns one vector
  onto another;
* :func:`two_turns` (subproblem 2): the angles about two axes through one point that
  turn one vector onto another, up to two ways;
* :func:`turn_between`: the angle about an axis that best turns one rotation onto
  others (the heading of a SCARA's tool, the pitch of an articulated arm's).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm



@dataclass(frozen=True)
class ZeroAxes:
    """The joint axes of an arm at ``q = 0``, in frame 0 (no base, no tool).

    Attributes
    ----------
    w : ndarray, shape (n, 3)
        Unit direction of each joint: the right-hand axis of a revolute joint, the
        direction a prismatic joint slides as ``q`` grows (DH joint values).
    r : ndarray, shape (n, 3)
        A point on each axis (the origin of the frame the joint moves about).
    frames : ndarray, shape (n + 1, 4, 4)
        Frames 0..n of the table at ``q = 0``: ``frames[-1]`` is ``T_0_n(0)``.
    scale : float
        The arm's size (sum of |a| and |d|), for relative tolerances.
    """

    w: FloatArray
    r: FloatArray
    frames: FloatArray
    scale: float

    def point(self, c_n: FloatArray) -> FloatArray:
        """Where the point ``c_n (3,)``, given in frame n, is at ``q = 0`` (frame 0)."""
        F = self.frames[-1]
        return F[:3, :3] @ c_n + F[:3, 3]


def zero_axes(arm: SerialArm) -> ZeroAxes:
    """The axes of ``arm`` (read in DH joint values: its :attr:`~rikin.SerialArm._flange`)."""
    bare = arm._flange
    F = bare._fk(np.zeros(arm.n), frames=True)[:-1]  # frames 0..n (the last is the TCP)
    idx = np.arange(arm.n) if arm.convention == "standard" else np.arange(1, arm.n + 1)
    return ZeroAxes(F[idx, :3, 2].copy(), F[idx, :3, 3].copy(), F, arm.scale)


def rotate(w: FloatArray, theta: FloatArray, v: FloatArray) -> FloatArray:
    """``v (..., 3)`` turned about the unit axis ``w (3,)`` by ``theta (...)`` (Rodrigues)."""
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    along = (v @ w)[..., None] * w
    return c * v + s * np.cross(w, v) + (1.0 - c) * along


def turn_angle(w: FloatArray, a: FloatArray, b: FloatArray, free: FloatArray | float = 0.0
               ) -> tuple[FloatArray, np.ndarray]:
    """The angle about the unit axis ``w (3,)`` that turns ``a`` towards ``b`` (both
    ``(..., 3)``), measured between their parts across ``w``; and where that is free
    (either part is below ``1e-300``; there the angle is ``free``)."""
    a_perp = a - (a @ w)[..., None] * w
    b_perp = b - (b @ w)[..., None] * w
    sin = np.cross(a_perp, b_perp) @ w
    cos = np.einsum("...i,...i->...", a_perp, b_perp)
    degenerate = (sin == 0.0) & (cos == 0.0)
    return np.where(degenerate, free, np.arctan2(sin, cos)), degenerate


def turn_between(w: FloatArray, A: FloatArray, R: FloatArray) -> FloatArray:
    """The angles ``(N,)`` about the unit axis ``w (3,)`` that best turn the rotation ``A (3,
    3)`` onto each ``R (N, 3, 3)``, column by column (the least squares angle; exact where
    ``R`` is such a turn of ``A``): ``atan2`` of the summed sines and cosines of the
    columns' turns, their parts along ``w`` left out."""
    sin = np.einsum("k,nk->n", w, np.cross(A.T[None], np.swapaxes(R, -1, -2)).sum(axis=1))
    cos = np.einsum("ij,nij->n", A, R) - (np.swapaxes(R, -1, -2) @ w) @ (A.T @ w)
    return np.arctan2(sin, cos)


def two_turns(w1: FloatArray, w2: FloatArray, u: FloatArray, v: FloatArray
              ) -> tuple[FloatArray, FloatArray]:
    """The vectors ``z`` with ``z = R2 u`` and ``v = R1 z`` for turns ``R1`` about ``w1``
    and ``R2`` about ``w2`` (unit, not parallel), for ``u, v`` of shape ``(..., 3)``.

    ``z`` keeps ``u``'s component along ``w2`` and ``v``'s along ``w1``, and ``|u|``:
    ``z = x w1 + y w2 + g (w1 x w2)`` with ``g = +-sqrt(g2)``.

    Returns
    -------
    z : ndarray, shape (..., 2, 3)
        The two candidates, ``g >= 0`` first (equal when ``g2 <= 0``).
    g2 : ndarray, shape (...)
        ``g^2`` times ``|w1 x w2|^2``, relative to ``|u|^2``: negative when no turn
        reaches ``v`` (then ``z`` takes ``g = 0``, the nearest).
    """
    c = float(w1 @ w2)
    n = np.cross(w1, w2)
    nn = float(n @ n)
    a1, a2 = v @ w1, u @ w2
    x = (a1 - c * a2) / nn
    y = (a2 - c * a1) / nn
    uu = np.einsum("...i,...i->...", u, u)
    rest = uu - (x * x + y * y + 2.0 * c * x * y)
    g = np.sqrt(np.maximum(rest, 0.0) / nn)
    base = x[..., None] * w1 + y[..., None] * w2
    z = np.stack([base + g[..., None] * n, base - g[..., None] * n], axis=-2)
    safe = np.where(uu > 0.0, uu, 1.0)
    return z, rest / safe
