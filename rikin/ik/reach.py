"""The reachable pose nearest to a rounded one.

A pose typed with 4 decimals, or stored as float32, can miss the poses an arm reaches by
its rounding: the wrist centre of a 5-DOF arm off the set its slides sweep, a stretched
arm's wrist centre a few 1e-5 beyond its reach. Within ``ROUNDED_POSE_TOL`` of reachable
(relative, see there) IK solves :func:`nearest_reachable` instead and reports the distance
(``reach_distance``); further off, the pose is unreachable. Each solver says where its
reachable set is through a ``gap`` function (signed distances and their gradients).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import FloatArray
from ..tolerances import ROUNDED_POSE_TOL

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

def _turn(R: FloatArray, w: FloatArray) -> FloatArray:
    """``exp([w]x) @ R`` for rotation vectors ``w (N, 3)`` (Rodrigues), ``R (N, 3, 3)``."""
    t = np.linalg.norm(w, axis=-1)[:, None, None]
    K = np.zeros(R.shape)
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -w[:, 2], w[:, 1], -w[:, 0]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = w[:, 2], -w[:, 1], w[:, 0]
    a = np.sinc(t / np.pi)  # sin(t) / t
    b = 0.5 * np.sinc(t / (2 * np.pi)) ** 2  # (1 - cos t) / t^2
    return (np.eye(3) + a * K + b * (K @ K)) @ R


#: What the ``gap`` of :func:`nearest_reachable` returns: residuals, gradients, active rows.
Gap = tuple[FloatArray, FloatArray, np.ndarray]


def rounding_size(arm: SerialArm, pw: FloatArray) -> FloatArray:
    """What ``ROUNDED_POSE_TOL`` is relative to: the arm's size, or the wrist centre's
    distance from the base when larger (the solvers' own notion, ``far``)."""
    return np.maximum(arm.scale, np.abs(pw).max(axis=-1))


def nearest_reachable(
    arm: SerialArm, gap: Any, T_world: FloatArray, centre: FloatArray
) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """The reachable pose nearest to each world pose ``T_world (N, 4, 4)``.

    Nearest means: the least sum of squared changes of the twelve numbers of
    ``[R | p]`` (the numbers a student types, each carrying the same rounding;
    ``R`` stays a rotation), the same entry-by-entry measure as the nearest
    rotation. Turning ``R`` by a small rotation vector ``w`` changes its entries by
    ``|w| sqrt(2)``, so this is the least ``|dp|^2 + 2 |w|^2`` that puts the wrist centre
    ``p_w = p + R c`` (``c``: the wrist centre in the TCP frame) on the set the positioning
    joints reach: the TCP moves and the approach direction tilts, each in proportion to
    how much it moves the wrist centre off the set (when ``c`` is 0, a position-only arm's
    TCP, only the TCP moves). Solved by Gauss-Newton with the
    minimum-norm step (the constraints are linear in ``dp``, nearly so in ``w``; three
    steps reach rounding), then one step of ``dp`` alone onto the set.

    Parameters
    ----------
    arm : SerialArm
        The arm (with any base and tool).
    gap : callable
        ``gap(p_w (N, 3), active) -> (r (N, k), J (N, k, 3), active (N, k))``: the
        solver's signed distances of base-frame wrist centres from the reachable set along
        ``k`` orthogonal unit directions, their gradients, and which of the constraints
        apply (decided on the first call, ``active=None``, then kept; rows that do not
        apply are zero).
    T_world : ndarray, shape (N, 4, 4)
        Validated poses with exact rotation blocks.
    centre : ndarray, shape (3,)
        The point ``gap`` constrains (the wrist centre; for an arm without a wrist, the
        point its positioning joints place), in the flange frame (frame n).

    Returns
    -------
    T_near : ndarray, shape (N, 4, 4)
        The nearest reachable poses (world frame); the poses not ``close`` as given.
    distance : ndarray, shape (N,)
        How far each given wrist centre is from the reachable set, in the arm's length
        units: also the least TCP move that reaches the set with the orientation kept.
    close : ndarray of bool, shape (N,)
        ``distance`` is within ``ROUNDED_POSE_TOL`` (relative, see there).
    """
    tool, base = arm.tool, arm.base
    c = tool[:3, :3].T @ (centre - tool[:3, 3])  # wrist centre in the TCP frame
    B, b = base[:3, :3], base[:3, 3]
    pw = _rows_times(T_world[:, :3, 3] + T_world[:, :3, :3] @ c - b, B)  # base frame
    r, _, active = gap(pw, None)
    distance = np.linalg.norm(r, axis=-1)
    close = distance <= ROUNDED_POSE_TOL * rounding_size(arm, pw)
    out = T_world.copy()
    move = np.flatnonzero(close & active.any(axis=-1))  # the others are left as they are
    if move.size:
        out[move] = _onto_set(gap, T_world[move], c, B, b)
    return out, distance, close


def _rows_times(x: FloatArray, B: FloatArray) -> FloatArray:
    """Each row of ``x (N, k)`` times ``B`` (one ``(k, m)`` matrix, or one per row ``(N, k,
    m)``): ``(N, m)``, a product per row (BLAS would round one ``(N, k) @ (k, m)`` product by
    its blocking of the N rows, so a pose would not be moved alike alone and in a batch)."""
    return (x[:, None, :] @ B)[:, 0]


def _onto_set(gap: Any, T_world: FloatArray, c: FloatArray, B: FloatArray, b: FloatArray
              ) -> FloatArray:
    """The steps of :func:`nearest_reachable` for poses ``T_world (N, 4, 4)`` that miss the
    set by rounding (``c``: the wrist centre in the TCP frame; ``B, b``: the base)."""
    R0, p0 = T_world[:, :3, :3], T_world[:, :3, 3]
    R, x = R0.copy(), np.zeros((len(T_world), 6))
    half = np.array([1.0, 1.0, 1.0, 0.5, 0.5, 0.5])  # inverse of the metric diag(1, 1, 1, 2, 2, 2)
    active = None
    for _ in range(4):
        v = R @ c
        pw = _rows_times(p0 + x[:, :3] + v - b, B)  # base frame
        r, J, active = gap(pw, active)
        G = J @ B.T  # gradient with respect to the world wrist centre, (N, k, 3)
        # d p_w = dp + dw x v, and g . (dw x v) = dw . (v x g): the w columns are v x g
        A = np.concatenate([G, np.cross(v[:, None, :], G)], axis=-1)  # (N, k, 6)
        M = (A * half) @ np.swapaxes(A, -1, -2)
        M += (~active)[..., None] * np.eye(M.shape[-1])  # a row that does not apply: lambda 0
        rhs = (A @ x[..., None])[..., 0] - r
        lam = np.linalg.solve(M, rhs[..., None])[..., 0]
        x_new = _rows_times(lam, A) * half
        R = _turn(R, x_new[:, 3:] - x[:, 3:])
        x = x_new
    # last, the TCP alone moves by what is left along each direction: exact for the gaps'
    # orthonormal directions, and it ends the steps that alternate between two faces of
    # the set where they meet in an edge (the Puma 560's reach near its folded elbow)
    pw = _rows_times(p0 + x[:, :3] + R @ c - b, B)
    r, J, active = gap(pw, active)
    x[:, :3] -= _rows_times(r, J @ B.T)
    out = T_world.copy()
    out[:, :3, :3] = R
    out[:, :3, 3] = p0 + x[:, :3]
    return out


def rounding_note(arm: SerialArm, pw: FloatArray) -> str:
    """What an UnreachableError says of rounding, for a wrist centre ``pw (3,)`` (base
    frame): how far off a pose is still taken as rounded."""
    u = f" {arm.units}" if arm.units else ""
    tol = ROUNDED_POSE_TOL * float(rounding_size(arm, pw[None])[0])
    return (
        f" (a pose up to {tol:.4g}{u} off is taken as rounded and solved for the nearest "
        "reachable pose)"
    )
