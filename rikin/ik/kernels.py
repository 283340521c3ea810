"""Vectorised building blocks shared by the arm families.

* :func:`two_link`: the law of cosines for a planar two-link chain, both elbows.
* :func:`elbow_above`: which side of the shoulder-wrist line the elbow is on.
* :func:`spherical_wrist`: the three wrist angles from ``Rz Ry Rz``, both branches.

The batch IK (:func:`rikin.ik.solve_batch`) also uses a few helpers that work
on a *structure of arrays*: a batch of 3x3 matrices held as a nested list
``X[i][j]`` of arrays of shape ``(n,)`` (or ``(k, n)``), so that every entry
is one contiguous array and small matrix products become a handful of
whole-array multiply-adds (:func:`const_matmul`, :func:`matmul_const`,
:func:`rz_inverse_times`), plus :func:`pose_defects` and
:func:`wrap_in_place`; and the same for batches of affine maps held as their top
three rows, 12 entries (:func:`affine_mul`, :func:`affine_mul_const`,
:func:`affine_const_mul`, :func:`affine_turn`),
with which :func:`chain_fk_error` checks a 6R chain's solutions by FK.

Inputs are trusted arrays; shapes are given per function.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from .._validate import FloatArray
from ..tolerances import MAX_LENGTH, ORTHONORMAL_TOL, REACH_TOL, SINGULAR_TOL, STRETCH_TOL
from ..transforms import zyz_branches as spherical_wrist  # noqa: F401  (re-exported: the one ZYZ decomposition)

#: A batch of 3x3 matrices as a structure of arrays: ``X[i][j]`` is entry (i, j)
#: of every matrix, an array of shape ``(n,)`` or ``(k, n)``.
Mat3 = list[list[FloatArray]]


class TwoLinkParts(NamedTuple):
    """The pieces of :func:`two_link`; ``A = base -+ beta``, ``B = +-B0``.

    All arrays have the shape of the target coordinates ``(...)``.
    """

    base: FloatArray  #: atan2(w, u), rad
    beta: FloatArray  #: angle at the shoulder between the target and link 2, in [0, pi], rad
    B0: FloatArray  #: the elbow angle of slot 0, in [0, pi], rad
    stretched: np.ndarray  #: bool: B0 is exactly 0 or pi (both slots coincide)
    fold: np.ndarray  #: bool: equal links folded onto the origin: A is free
    reachable: np.ndarray  #: bool, see :func:`two_link`
    edge: FloatArray  #: distance of the target from the boundary of the reach, / (L2 + L3)


def two_link_parts(u: FloatArray, w: FloatArray, L2: float, L3: float) -> TwoLinkParts:
    """The angles :func:`two_link` combines, without stacking them into slots.

    Half-angle forms of the law of cosines, accurate to rounding up to the
    stretched and folded boundaries (``cos B`` loses half its digits there):
    with ``r = |(u, w)|``, ``dp = L2 + L3 - r``, ``dm = r - |L2 - L3|``,
    ``tan(B/2) = sqrt(dp (L2 + L3 + r) / (dm (r + |L2 - L3|)))`` and the
    shoulder angle ``beta`` from the same four factors (Heron's half angles).
    """
    Lp, Lm = L2 + L3, abs(L2 - L3)
    r = np.hypot(u, w)
    tol = REACH_TOL * Lp
    reachable = (r <= Lp + tol) & (r >= Lm - tol)
    snap = STRETCH_TOL * Lp
    dp = Lp - r
    dm = r - Lm
    dp = np.where(dp <= snap, 0.0, dp)
    dm = np.where(dm <= snap, 0.0, dm)
    rc = np.where(dp == 0.0, Lp, np.where(dm == 0.0, Lm, r))
    sp, sm = Lp + rc, rc + Lm
    B0 = 2.0 * np.arctan2(np.sqrt(dp * sp), np.sqrt(dm * sm))
    if L2 >= L3:
        beta = 2.0 * np.arctan2(np.sqrt(dm * dp), np.sqrt(sp * sm))
    else:
        beta = 2.0 * np.arctan2(np.sqrt(sm * dp), np.sqrt(sp * dm))
    fold = (dm == 0.0) & (Lm <= snap)
    return TwoLinkParts(
        base=np.arctan2(w, u),
        beta=np.where(fold, 0.0, beta),
        B0=B0,
        stretched=(dp == 0.0) | (dm == 0.0),
        fold=fold,
        reachable=reachable,
        edge=np.minimum(np.abs(Lp - r), np.abs(r - Lm)) / Lp,
    )


def two_link(
    u: FloatArray, w: FloatArray, L2: float, L3: float
) -> tuple[FloatArray, FloatArray, np.ndarray, np.ndarray]:
    """Both solutions of a planar two-link chain reaching ``(u, w)`` from its origin.

    The chain: link 2 of length ``L2`` at angle ``A`` from the u axis, link 3
    of length ``L3`` at angle ``A + B``. ``cos B = (u^2 + w^2 - L2^2 - L3^2) /
    (2 L2 L3)`` (law of cosines), ``A = atan2(w, u) - atan2(L3 sin B, L2 + L3 cos B)``
    (computed in the accurate half-angle form of :func:`two_link_parts`).

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
        The target is within ``STRETCH_TOL`` (relative) of the boundary: the
        chain is exactly stretched or folded, and both slots are equal.

    See :func:`two_link_parts` for the equal-link fold, where ``A`` is free.
    """
    p = two_link_parts(u, w, L2, L3)
    A, B = two_link_slots(p)
    return A, B, p.reachable, p.stretched


def two_link_slots(p: TwoLinkParts) -> tuple[FloatArray, FloatArray]:
    """``A, B`` of shape ``(..., 2)`` from the parts (slot 0: ``B >= 0``)."""
    A = np.stack([p.base - p.beta, p.base + p.beta], axis=-1)
    B = np.stack([p.B0, -p.B0], axis=-1)
    return A, B


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


# ---------------------------------------------------------------- structure-of-arrays helpers
#: Constant matrix entries this close to 0 or +-1 are taken as exact (cos(pi/2)
#: is 6e-17 in floating point), so that multiplying by a signed permutation,
#: like Rx(pi/2), costs nothing. The change is far below the FK check's tolerance.
EXACT_ENTRY_TOL = 1e-15


def snap_exact(C: FloatArray) -> FloatArray:
    """A copy of the constant matrix ``C`` with entries near 0, +1 or -1 made exact."""
    out = np.array(C, dtype=np.float64)
    for v in (0.0, 1.0, -1.0):
        out[np.abs(out - v) < EXACT_ENTRY_TOL] = v
    return out


def lincomb(coeffs: Sequence[float] | FloatArray, terms: Sequence[FloatArray]) -> FloatArray:
    """``sum_k coeffs[k] * terms[k]``, skipping zero coefficients and not multiplying by +-1.

    The result may be one of ``terms`` itself (when a single coefficient is
    1): never modify it in place.
    """
    out: FloatArray | None = None
    for c, t in zip(coeffs, terms, strict=True):
        if c == 0.0:
            continue
        term = t if c == 1.0 else (-t if c == -1.0 else c * t)
        out = term if out is None else out + term
    return np.zeros_like(terms[0]) if out is None else out


def const_matmul(C: FloatArray, X: Mat3) -> Mat3:
    """``C @ X`` for a constant ``(3, 3)`` matrix ``C`` and a batch ``X`` (structure of arrays)."""
    return [[lincomb(C[i], [X[0][j], X[1][j], X[2][j]]) for j in range(3)] for i in range(3)]


def matmul_const(X: Mat3, C: FloatArray) -> Mat3:
    """``X @ C`` for a batch ``X`` (structure of arrays) and a constant ``(3, 3)`` matrix ``C``."""
    return [[lincomb(C[:, j], X[i]) for j in range(3)] for i in range(3)]


def rz_inverse_times(c: FloatArray, s: FloatArray, X: Mat3, rows: int = 3) -> Mat3:
    """``Rz(-theta) @ X`` from ``c = cos(theta)``, ``s = sin(theta)``; only rows 0 and 1 change.

    ``rows`` < 3 returns only the first ``rows`` rows (the others are not computed).
    """
    r0 = [c * X[0][j] + s * X[1][j] for j in range(3)]
    r1 = [c * X[1][j] - s * X[0][j] for j in range(3)]
    return [r0, r1, X[2]][:rows]


def pose_defects(X: FloatArray) -> tuple[bool, FloatArray]:
    """Check a batch of poses ``X`` (structure of arrays, shape ``(4, 4, n)``) as
    :func:`rikin._validate.as_pose` does, cheaply enough for every chunk of a batch.

    Returns
    -------
    ok : bool
        Every pose is finite, has last row ``[0, 0, 0, 1]``, orthonormal columns
        within ``ORTHONORMAL_TOL``, ``det > 0`` and a position within
        ``MAX_LENGTH``. When False, the caller runs ``as_pose`` for the message.
    defect : ndarray, shape (n,)
        Max abs entry of ``R^T R - I`` per pose (meaningful when ``ok``).
    """
    n = X.shape[-1]
    if not np.isfinite(X).all():
        return False, np.zeros(n)
    bottom = np.abs(X[3, :3]).max(initial=0.0), np.abs(X[3, 3] - 1.0).max(initial=0.0)
    if max(bottom) > 1e-9 or np.abs(X[:3, 3]).max(initial=0.0) > MAX_LENGTH:
        return False, np.zeros(n)
    if np.abs(X[:3, :3]).max(initial=0.0) > 2.0:  # no rotation; its R^T R could overflow
        return False, np.zeros(n)
    col = [X[:3, j] for j in range(3)]  # the columns, each (3, n)
    defect = np.zeros(n)
    for j in range(3):
        for k in range(j, 3):
            g = col[j][0] * col[k][0] + col[j][1] * col[k][1] + col[j][2] * col[k][2]
            if j == k:
                g -= 1.0
            np.maximum(defect, np.abs(g), out=defect)
    if defect.max(initial=0.0) > ORTHONORMAL_TOL:
        return False, defect
    c1, c2 = col[1], col[2]
    det = (
        col[0][0] * (c1[1] * c2[2] - c1[2] * c2[1])
        + col[0][1] * (c1[2] * c2[0] - c1[0] * c2[2])
        + col[0][2] * (c1[0] * c2[1] - c1[1] * c2[0])
    )
    return not bool((det < 0).any()), defect


def norm2(x: FloatArray, y: FloatArray) -> FloatArray:
    """``sqrt(x^2 + y^2)``, a twentieth of ``np.hypot``'s time (which guards against
    overflow; the batch kernels' values are of the arm's size, near 1 in their units)."""
    return np.sqrt(x * x + y * y)


def wrap_in_place(q: FloatArray) -> FloatArray:
    """Wrap angles (rad) to (-pi, pi] in place, without ``remainder`` (four times faster).

    Agrees with :func:`rikin.transforms.wrap_angle` to rounding (within 1e-15
    rad for angles of a few turns); returns ``q``.
    """
    k = np.multiply(q, 0.5 / np.pi)
    np.rint(k, out=k)
    k *= 2.0 * np.pi
    q -= k
    np.add(q, 2.0 * np.pi, out=q, where=q <= -np.pi)
    np.minimum(q, np.pi, out=q)
    return q


# ---------------------------------------------------------------- affine maps, 12 entries
#: An affine map (or a batch of them) as the top three rows of its 4x4 matrix, row by row:
#: 12 floats, or 12 arrays of one shape.
Affine = tuple[Any, ...]


def as_affine(M: FloatArray) -> tuple[float, ...]:
    """The top three rows of a 4x4 matrix, row by row, as 12 floats."""
    return tuple(float(v) for v in np.asarray(M)[:3].ravel())


def affine_mul(a: Affine, b: Affine) -> Affine:
    """The product ``a b`` of two affine maps (12 entries each: floats or arrays)."""
    a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23 = a
    b00, b01, b02, b03, b10, b11, b12, b13, b20, b21, b22, b23 = b
    return (a00 * b00 + a01 * b10 + a02 * b20, a00 * b01 + a01 * b11 + a02 * b21,
            a00 * b02 + a01 * b12 + a02 * b22, a00 * b03 + a01 * b13 + a02 * b23 + a03,
            a10 * b00 + a11 * b10 + a12 * b20, a10 * b01 + a11 * b11 + a12 * b21,
            a10 * b02 + a11 * b12 + a12 * b22, a10 * b03 + a11 * b13 + a12 * b23 + a13,
            a20 * b00 + a21 * b10 + a22 * b20, a20 * b01 + a21 * b11 + a22 * b21,
            a20 * b02 + a21 * b12 + a22 * b22, a20 * b03 + a21 * b13 + a22 * b23 + a23)


def affine_turn(T: Affine, c: Any, s: Any) -> Affine:
    """``T Rz(t)`` of an affine map given as 12 entries, with ``c, s`` the cosine and sine.
    Entries of ``T`` that are the floats 0 or +-1 (a constant DH factor's) cost nothing."""
    out = list(T)
    for r in (0, 4, 8):
        x, y = T[r], T[r + 1]
        out[r] = _combine(_times(x, c), _times(y, s), 1.0)
        out[r + 1] = _combine(_times(y, c), _times(x, s), -1.0)
    return tuple(out)


def _combine(a: Any, b: Any, sign: float) -> Any:
    """``a + sign b`` where either may be None (no term)."""
    if b is None:
        return 0.0 if a is None else a
    if a is None:
        return b if sign > 0 else -b
    return a + b if sign > 0 else a - b


def _times(x: Any, c: Any) -> Any:
    """``x c``; None when ``x`` is the float 0 (no term)."""
    if type(x) is float:
        if x == 0.0:
            return None
        if x == 1.0:
            return c
        if x == -1.0:
            return -c
    return x * c


def affine_const_mul(a: tuple[float, ...], b: Affine) -> Affine:
    """``a b`` for a constant affine map ``a`` (12 floats), skipping its zero and unit
    entries."""
    out: list[Any] = []
    for i in (0, 4, 8):
        for j in range(4):
            acc: Any = a[i + 3] if j == 3 else 0.0
            for m in range(3):
                v = a[i + m]
                if v != 0.0:
                    term = b[4 * m + j] if v == 1.0 else b[4 * m + j] * v
                    acc = term if type(acc) is float and acc == 0.0 else acc + term
            out.append(acc)
    return tuple(out)


def affine_mul_const(a: Affine, b: tuple[float, ...]) -> Affine:
    """``a b`` for a constant affine map ``b`` (12 floats), skipping its zero and unit
    entries (a DH table's matrices are mostly 0 and 1) and the float zeros of ``a``."""
    out: list[Any] = []
    for i in (0, 4, 8):
        for j in range(4):
            acc: Any = a[i + 3] if j == 3 else None
            if type(acc) is float and acc == 0.0:
                acc = None
            for m in range(3):
                v, e = b[4 * m + j], a[i + m]
                if v == 0.0 or (type(e) is float and e == 0.0):
                    continue
                if v == -1.0:
                    acc = -e if acc is None else acc - e
                else:
                    term = e if v == 1.0 else e * v
                    acc = term if acc is None else acc + term
            out.append(0.0 if acc is None else acc)
    return tuple(out)


def chain_fk_error(
    M: Sequence[tuple[float, ...]], cs: Sequence[tuple[FloatArray, FloatArray]], goal: Affine,
    scale: float, split: int,
) -> FloatArray:
    """How far the chain ``M0 Rz(th1) M1 ... Rz(th6) M6`` is from ``goal``, per solution:
    ``max(|p - p_goal| / scale, max |R - R_goal|)``.

    Parameters
    ----------
    M : sequence of 7 affine maps (12 floats each)
        The chain's constant factors (:func:`as_affine` of ``pieper.ChainModel.M``).
    cs : sequence of 6 pairs of arrays
        The cosine and sine of each joint's theta, broadcasting to the solutions' shape
        ``S`` (callers that have them from the closed form pass them on). Joints
        ``1..split`` and ``split+1..6`` may each have fewer distinct values than
        solutions (an arm's position branches share joints 1-3): the two ends of the
        chain are multiplied out on their own shapes, then once together.
    goal : affine map, 12 arrays broadcasting to ``S``
        The target pose in the chain's frame (and length units).
    scale : float
        The arm's size, in the chain's length units.

    Returns
    -------
    ndarray, shape ``S``
    """
    c, s = [x for x, _ in cs], [y for _, y in cs]
    head: Affine = tuple(M[0])
    for i in range(split):
        head = affine_turn(head, c[i], s[i])
        if i + 1 < split:
            head = affine_mul_const(head, M[i + 1])
    tail: Affine = tuple(M[split])
    for i in range(split, len(cs)):
        tail = affine_mul_const(affine_turn(tail, c[i], s[i]), M[i + 1])
    T = affine_mul(head, tail)
    dp = [T[i] - goal[i] for i in (3, 7, 11)]
    err = np.sqrt(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]) / scale
    for i in (0, 1, 2, 4, 5, 6, 8, 9, 10):
        err = np.maximum(err, np.abs(T[i] - goal[i]))
    return err


# ---------------------------------------------------------------- quartics
#: Roots of a quartic closer than this (relative) are left to the companion matrix's
#: eigenvalues rather than Ferrari's formulas (:func:`ferrari`).
SEPARATE_ROOTS = 1e-3


def ferrari(
    A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The roots ``(M, 4)`` of the monic quartics ``z^4 + A z^3 + B z^2 + C z + D``
    (complex arrays ``(M,)``) by Ferrari's method, each polished by one Newton step, and
    ``(M,)`` whether they are confirmed: every step small and the roots' sum ``-A`` (four
    distinct roots, none found twice), and none within ``SEPARATE_ROOTS`` of another. The
    vectorised form of the one-pose kernel's ``pieper_kernel._quartic``; where unconfirmed,
    the roots are to be found otherwise."""
    with np.errstate(all="ignore"):
        a = A / 4
        aa = a * a
        p = B - 6 * aa
        q = C - 2 * B * a + 8 * aa * a
        r = D - C * a + B * aa - 3 * aa * aa
        # resolvent cubic, depressed: x^3 + P x + Q with m = x - p / 3
        P = -p * p / 12 - r
        Q = -p * p * p / 108 + p * r / 3 - q * q / 8
        disc = np.sqrt(Q * Q / 4 + P * P * P / 27)
        u3 = np.where(np.abs(-Q / 2 - disc) > np.abs(-Q / 2 + disc), -Q / 2 - disc, -Q / 2 + disc)
        u = u3 ** (1 / 3)
        safe_u = np.where(u == 0, 1.0, u)
        m = np.full(u.shape, -p / 3, dtype=complex)
        best = np.full(u.shape, -1.0)
        for w in (1.0, complex(-0.5, 0.8660254037844386), complex(-0.5, -0.8660254037844386)):
            uw = safe_u * w
            cand = np.where(u == 0, -p / 3, uw - P / (3 * uw) - p / 3)
            bigger = np.abs(cand) > best
            m, best = np.where(bigger, cand, m), np.where(bigger, np.abs(cand), best)
        s = np.sqrt(2 * m)
        qs = q / (2 * np.where(s == 0, 1.0, s))
        half = p / 2 + m
        roots = []
        sure = (m != 0) & (s != 0)
        for b, c in ((-s, half + qs), (s, half - qs)):  # y^2 + b y + c = 0
            d = np.sqrt(b * b - 4 * c)
            d = np.where((np.conj(b) * d).real < 0, -d, d)
            t = -(b + d) / 2
            sure &= t != 0
            roots += [t - a, c / np.where(t == 0, 1.0, t) - a]
        z = np.stack(roots, axis=-1)
        f = (((z + A[:, None]) * z + B[:, None]) * z + C[:, None]) * z + D[:, None]
        df = ((4 * z + 3 * A[:, None]) * z + 2 * B[:, None]) * z + C[:, None]
        step = f / np.where(df == 0, 1.0, df)
        z = z - step
        sure &= (
            np.all(np.isfinite(z), axis=-1) & np.all(df != 0, axis=-1)
            & np.all(np.abs(step) <= 1e-6 * (1 + np.abs(z)), axis=-1)
            & (np.abs(z.sum(-1) + A) <= 1e-9 * (np.abs(A) + 4 * np.abs(z).max(-1)))
        )
        # near a multiple root (a fold of the arm) the companion matrix's eigenvalues
        # split it the way the fold handling downstream was tuned for: leave it to them
        for i, j in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
            sure &= np.abs(z[:, i] - z[:, j]) > SEPARATE_ROOTS * (1 + np.abs(z[:, i]))
    return z, sure


def cross3(a: FloatArray, b: FloatArray) -> FloatArray:
    """``np.cross(a, b)`` of 3-vectors in the last axis (broadcast), with the same products
    in the same order (so the same bits), in fewer numpy calls: it is in every polish."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    np.subtract(a1 * b2, a2 * b1, out=out[..., 0])
    np.subtract(a2 * b0, a0 * b2, out=out[..., 1])
    np.subtract(a0 * b1, a1 * b0, out=out[..., 2])
    return out
