"""Vectorised building blocks shared by the arm families.

* :func:`two_link`: the law of cosines for a planar two-link chain, both elbows.
* :func:`elbow_above`: which side of the shoulder-wrist line the elbow is on.
* :func:`spherical_wrist`: the three wrist angles from ``Rz Ry Rz``, both branches.

Inputs are trusted arrays; shapes are given per function.
"""

from __future__ import annotations

import numpy as np

from .._validate import FloatArray
from ..tolerances import REACH_TOL, SINGULAR_TOL, STRETCH_TOL


def two_link(u: FloatArray, w: FloatArray, L2: float, L3: float
             ) -> tuple[FloatArray, FloatArray, np.ndarray, np.ndarray]:
    """Both solutions of a planar two-link chain reaching ``(u, w)`` from its origin.

    The chain: link 2 of length ``L2`` at angle ``A`` from the u axis, link 3
    of length ``L3`` at angle ``A + B``. ``cos B = (u^2 + w^2 - L2^2 - L3^2) /
    (2 L2 L3)`` (law of cosines), ``A = atan2(w, u) - atan2(L3 sin B, L2 + L3 cos B)``.

    Parameters
    ----------
    u, w : ndarray, shape (...)
        Target in the chain's plane, length units.

    Returns
    -------
    A, B : ndarray, shape (..., 2)
        Slot 0 has ``B >= 0``, slot 1 ``B <= 0``.
    reachable : ndarray of bool, shape (...)
        ``|L2 - L3| <= sqrt(u^2 + w^2) <= L2 + L3`` (with a relative slack of
        ``REACH_TOL`` that is clamped onto the boundary).
    stretched : ndarray of bool, shape (...)
        ``sin B = 0`` (within ``STRETCH_TOL`` on the cosine): the chain is fully
        stretched or folded, and both slots are equal.
    """
    c = (u * u + w * w - L2 * L2 - L3 * L3) / (2.0 * L2 * L3)
    slack = REACH_TOL * (L2 + L3) / min(L2, L3)
    reachable = np.abs(c) <= 1.0 + slack
    c = np.clip(c, -1.0, 1.0)
    c = np.where(1.0 - np.abs(c) < STRETCH_TOL, np.sign(c), c)
    s = np.sqrt(1.0 - c * c)
    B0 = np.arctan2(s, c)
    base = np.arctan2(w, u)
    A0 = base - np.arctan2(L3 * s, L2 + L3 * c)
    A1 = base + np.arctan2(L3 * s, L2 + L3 * c)
    A = np.stack([A0, A1], axis=-1)
    B = np.stack([B0, -B0], axis=-1)
    return A, B, reachable, s == 0.0


def reach_excess(dist: FloatArray, L2: float, L3: float) -> FloatArray:
    """How far ``dist`` lies outside ``[|L2 - L3|, L2 + L3]`` (0 inside), length units."""
    return np.maximum(np.maximum(dist - (L2 + L3), abs(L2 - L3) - dist), 0.0)


def elbow_above(u: FloatArray, w: FloatArray, A: FloatArray, L2: float) -> np.ndarray:
    """True where the elbow lies above the line from the shoulder to ``(u, w)``.

    ``u, w`` have shape (...), ``A`` shape (..., k). When the target is
    straight above or below the shoulder (u = 0) the elbow counts as "up"
    when it is on the forward side (u > 0).
    """
    eu, ew = L2 * np.cos(A), L2 * np.sin(A)
    uu, ww = u[..., None], w[..., None]
    cross = uu * ew - ww * eu
    vertical = np.abs(uu) <= SINGULAR_TOL * L2
    return np.where(vertical, eu > 0, cross * np.sign(uu) > 0)


def spherical_wrist(M: FloatArray, hint_phi: FloatArray | float = 0.0
                    ) -> tuple[FloatArray, FloatArray, FloatArray, np.ndarray]:
    """ZYZ angles of ``M = Rz(phi) Ry(theta) Rz(psi)``, both branches.

    Parameters
    ----------
    M : ndarray, shape (..., 3, 3)
    hint_phi : float or ndarray broadcastable to (...)
        At the singularity (theta = 0 or pi) only phi + psi (or phi - psi) is
        fixed; phi takes this value.

    Returns
    -------
    phi, theta, psi : ndarray, shape (..., 2)
        Slot 0 has ``theta in [0, pi]``; slot 1 is ``(phi + pi, -theta, psi + pi)``
        (at the singularity, slot 1 repeats slot 0).
    singular : ndarray of bool, shape (...)
    """
    m02, m12, m22 = M[..., 0, 2], M[..., 1, 2], M[..., 2, 2]
    s = np.hypot(m02, m12)
    singular = s < SINGULAR_TOL
    theta = np.arctan2(s, m22)
    phi = np.arctan2(m12, m02)
    # psi from the rotation left after Rz(phi) Ry(theta), not from m31/m32 directly: near
    # the singularity phi carries a rounding error of ~eps/s, and this psi absorbs it, so
    # Rz(phi) Ry(theta) Rz(psi) reproduces M to ~eps instead of ~eps/s.
    safe = np.where(singular, 1.0, s)
    cp, sp = m02 / safe, m12 / safe
    a00 = cp * M[..., 0, 0] + sp * M[..., 1, 0]
    a10 = -sp * M[..., 0, 0] + cp * M[..., 1, 0]
    psi = np.arctan2(a10, m22 * a00 - s * M[..., 2, 0])
    if np.any(singular):
        hp = np.broadcast_to(np.asarray(hint_phi, dtype=np.float64), s.shape)
        up = m22 > 0  # theta = 0: M = Rz(phi + psi); theta = pi: M = Rz(phi - psi) Ry(pi)
        # Rz(a) Ry(pi) = [[-cos a, -sin a, 0], [-sin a, cos a, 0], [0, 0, -1]]
        total = np.where(up, np.arctan2(M[..., 1, 0], M[..., 0, 0]),
                         np.arctan2(-M[..., 1, 0], -M[..., 0, 0]))
        phi = np.where(singular, hp, phi)
        psi = np.where(singular, np.where(up, total - hp, hp - total), psi)
        theta = np.where(singular, np.where(up, 0.0, np.pi), theta)
    # at the singularity both slots hold the same representative (phi = hint_phi)
    flip = np.where(singular, 0.0, np.pi)
    phis = np.stack([phi, phi + flip], axis=-1)
    thetas = np.stack([theta, np.where(singular, theta, -theta)], axis=-1)
    psis = np.stack([psi, psi + flip], axis=-1)
    return phis, thetas, psis, singular
