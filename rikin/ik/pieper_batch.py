"""Many regular poses of the spherical-wrist 6R solver (:mod:`rikin.ik.pieper`) at once.

The one-pose kernel's closed form (:mod:`rikin.ik.pieper_kernel`) on stacks: every Python
float of :meth:`PieperKernel.solve` becomes an array over the poses (the last axis), the
four position branches an axis in front of it and the two wrist slots another, in the
general solver's slot order (position slot ``a``, wrist slot ``b``: ``2 a + b``). The
per-arm constants are the one-pose kernel's, read once per arm.

A pose on which the one-pose kernel would decline (returns None: near a singularity, two
roots near each other, a label or a joint near its boundary; the margins are its module's)
is ``suspect``, and so is a pose with a slot whose FK misses the target by more than the
general solver's acceptance; the caller (:func:`rikin.ik.api.solve_batch`) solves those
again on the general path. Everywhere else the slots hold what ``arm.ik`` returns for the
pose, computed by the same formulas.

The position problem: two sinusoids where axes 1 and 2 meet or are parallel; where they
are skew, a quadratic in ``|g|^2`` when they are skew at right angles with axes 2 and 3
parallel (the KUKA KR 5 and ABB IRB 140 kind: :meth:`PieperKernel._th3_planar`), else a
quartic (Ferrari's formulas, shared with the general solver in :mod:`rikin.ik.kernels`).
"""

from __future__ import annotations

from math import atan2, cos, hypot, pi, sin
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import FloatArray
from ..tolerances import SINGULAR_TOL
from ..transforms import _inv_transform
from .kernels import (
    affine_const_mul,
    affine_mul_const,
    as_affine,
    chain_fk_error,
    ferrari,
    norm2,
    wrap_in_place,
)
from .pieper_kernel import (
    EDGE,
    LABEL,
    NEAR,
    NEAR_AXIS1,
    OUT,
    REAL_IN,
    REAL_OUT,
    ROOT_SEP,
    WRAP_EDGE,
    KernelSource,
    PieperKernel,
    _wrist_rest,
)
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

__all__ = ["PieperBatchKernel", "batch_kernel"]

_TAU = 2.0 * pi

#: Positions as arrays ``(4, n)``: ``th2, c2, s2, th3, c3, s3, gx, gy, gz``, which exist
#: ``(4, n)``, and the poses ``(n,)`` the one-pose kernel declines.
Positions = tuple[list[FloatArray], np.ndarray, np.ndarray]


def batch_kernel(
    solver: KernelSource, arm: SerialArm, kernel: PieperKernel | None, slots: tuple[Branch, ...],
    accept: float,
) -> PieperBatchKernel | None:
    """The batch kernel of ``solver`` for ``arm`` (from its one-pose ``kernel``), or None
    when the kernel takes no batch of this arm (no one-pose kernel; a constant sinusoid)."""
    if kernel is None:
        return None
    n0, nc, ns = kernel.n
    z0, zc, zs = kernel.z
    if kernel.case == "parallel":
        nc, ns = kernel.ca1 * zc, kernel.ca1 * zs
    if hypot(nc, ns) <= 1e-300:
        return None
    return PieperBatchKernel(solver, arm, kernel, slots, accept)


class PieperBatchKernel:
    """:meth:`PieperKernel.solve` on ``n`` poses at once (module docstring); ``slots`` and
    :meth:`solve` are what :func:`rikin.ik.api.solve_batch` reads."""

    def __init__(self, solver: KernelSource, arm: SerialArm, kernel: PieperKernel,
                 slots: tuple[Branch, ...], accept: float) -> None:
        self.k = kernel
        self.slots = slots
        self.accept = accept
        self.M = [as_affine(m) for m in solver.model.M]
        self.base_inv = as_affine(solver._to_unit(_inv_transform(arm.base)))
        self.tool_inv = as_affine(solver._to_unit(_inv_transform(arm.tool)))
        self.offsets = np.array(kernel.offsets)
        self.cos_o5, self.sin_o5 = np.cos(kernel.offsets[4]), np.sin(kernel.offsets[4])

    def solve(self, X: FloatArray) -> tuple[FloatArray, np.ndarray, np.ndarray]:
        """Poses ``X (4, 4, n)`` (world frame, checked rigid) -> ``q (8, 6, n)`` wrapped
        (NaN where no solution), ``valid (8, n)`` and ``suspect (n,)``."""
        k = self.k
        n = X.shape[-1]
        rows = list(X[:3].reshape(12, n))
        u = k.unit
        for i in (3, 7, 11):
            rows[i] = rows[i] * u
        with np.errstate(all="ignore"):  # NaN and inf end up in suspect
            px, py, pz = _wrist_centre(k, rows)
            rho_p = norm2(px, py)
            suspect = ~(rho_p >= NEAR_AXIS1 * k.L)
            P = px * px + py * py + pz * pz - k.a1 * k.a1 + k.d1 * k.d1 - 2.0 * k.d1 * pz
            if k.case == "skew":
                pos, valid, bad = _positions_skew(k, px, py, pz, P)
            else:
                pos, valid, bad = _positions_sinusoid(k, pz, P)
            th1, c1, s1, bad1 = _joint1(k, px, py, pos, valid)
            rw = _wrist_columns(k, rows, c1, s1, pos)
            wrist = _wrist_orthogonal(k, rw) if k.orthogonal else _wrist_general(k, rw)
            th456, cs456, ok_w, bad_w = wrist
            wvalid = (valid[:, None] & ok_w).reshape(8, n)  # (4, 2, n) -> slots
            cs = [(c1[:, None], s1[:, None]), (pos[1][:, None], pos[2][:, None]),
                  (pos[4][:, None], pos[5][:, None]), *cs456]
            goal = affine_const_mul(self.base_inv, affine_mul_const(tuple(rows), self.tool_inv))
            err = chain_fk_error(self.M, cs, goal, k.L, split=3).reshape(8, n)
            q = np.empty((4, 2, 6, n))
            for j, t in enumerate((th1, pos[0], pos[3])):
                np.subtract(t[:, None], self.offsets[j], out=q[:, :, j])
            for j, (t0, t1) in enumerate(th456):
                np.subtract(t0, self.offsets[3 + j], out=q[:, 0, 3 + j])
                np.subtract(t1, self.offsets[3 + j], out=q[:, 1, 3 + j])
            q = wrap_in_place(q.reshape(8, 6, n))
            c5, s5 = (np.broadcast_to(x, (4, 2, n)).reshape(8, n) for x in cs456[1])
            sin_q5 = s5 * self.cos_o5 - c5 * self.sin_o5
            suspect |= bad | (valid & (bad1 | bad_w)).any(axis=0)
            suspect |= (wvalid & ~((np.abs(sin_q5) >= LABEL) & (np.abs(q).max(axis=1) <= WRAP_EDGE)
                                   & (err <= self.accept))).any(axis=0)
        np.copyto(q, np.nan, where=~wvalid[:, None, :])
        return q, wvalid, suspect


def _wrist_centre(k: PieperKernel, rows: list[Any]) -> tuple[FloatArray, ...]:
    """``p'``, the wrist centre in the frame of axis 1, three arrays ``(n,)``."""
    cx, cy, cz = k.c_tcp
    w = [rows[4 * i] * cx + rows[4 * i + 1] * cy + rows[4 * i + 2] * cz + rows[4 * i + 3]
         for i in range(3)]
    gt = k.Gt
    return tuple(g[0] * w[0] + g[1] * w[1] + g[2] * w[2] + t for g, t in zip(k.G, gt,
                                                                           strict=True))


def _plus_minus(phi: Any, c_phi: Any, s_phi: Any, ratio: FloatArray, axis: int
                ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``phi +- acos(ratio)`` (stacked on ``axis``: plus first), with their cosines and
    sines from those of ``phi`` (the ratio clipped to [-1, 1])."""
    cd = np.clip(ratio, -1.0, 1.0)
    delta = np.arccos(cd)
    sd = np.sqrt(1.0 - cd * cd)
    a, b = c_phi * cd, s_phi * sd
    c, d = s_phi * cd, c_phi * sd
    return (np.stack([phi + delta, phi - delta], axis=axis), np.stack([a - b, a + b], axis=axis),
            np.stack([c + d, c - d], axis=axis))


def _g_of(k: PieperKernel, c3: FloatArray, s3: FloatArray) -> list[FloatArray]:
    """``g = g0 + cos(th3) gc + sin(th3) gs``, three arrays."""
    return [k.g0[i] + c3 * k.gc[i] + s3 * k.gs[i] for i in range(3)]


def _positions_sinusoid(k: PieperKernel, pz: FloatArray, P: FloatArray) -> Positions:
    """:meth:`PieperKernel._sinusoid_th3` and the two ``th2`` of each root (axes 1 and 2
    meet or are parallel): slot ``2 m + j`` is root ``m`` of ``th3``, root ``j`` of ``th2``."""
    n0, nc, ns = k.n
    z0, zc, zs = k.z
    meet = k.case == "meet"
    if meet:
        k0, kc, ks = P - n0, -nc, -ns
    else:
        k0, kc, ks = pz - k.d1 - k.ca1 * z0, -k.ca1 * zc, -k.ca1 * zs
    ratio = -k0 / hypot(kc, ks)
    ok3 = np.abs(ratio) <= 1.0 + OUT
    bad = ok3 & ~(np.abs(ratio) <= 1.0 - EDGE)
    phi = atan2(ks, kc)
    th3, c3, s3 = _plus_minus(phi, cos(phi), sin(phi), ratio, axis=0)  # (2, n)
    gx, gy, gz = _g_of(k, c3, s3)
    gxy = gx * gx + gy * gy
    bad |= (ok3 & ~(gxy >= (NEAR * k.L) ** 2)).any(axis=0)
    rho2 = np.sqrt(gxy)
    if meet:  # gy cos2 + gx sin2 = A / sa1
        ratio2 = (pz - k.d1 - k.ca1 * gz) / k.sa1 / rho2
        phi2, c_phi2, s_phi2 = np.arctan2(gx, gy), gy / rho2, gx / rho2
    else:  # gx cos2 - gy sin2 = B / (2 a1)
        ratio2 = (P - (gxy + gz * gz)) / (2.0 * k.a1) / rho2
        phi2, c_phi2, s_phi2 = np.arctan2(-gy, gx), gx / rho2, -gy / rho2
    ok2 = ok3 & (np.abs(ratio2) <= 1.0 + OUT)
    bad |= (ok2 & ~(np.abs(ratio2) <= 1.0 - EDGE)).any(axis=0)
    th2 = _plus_minus(phi2, c_phi2, s_phi2, ratio2, axis=1)
    pos = [x.reshape(4, -1) for x in th2] + [np.repeat(x, 2, axis=0)
                                             for x in (th3, c3, s3, gx, gy, gz)]
    return pos, np.repeat(ok2, 2, axis=0), bad


def _positions_skew(
    k: PieperKernel, px: FloatArray, py: FloatArray, pz: FloatArray, P: FloatArray
) -> Positions:
    """``th3`` of axes 1 and 2 skew (:meth:`PieperKernel._th3_planar` or
    :meth:`PieperKernel._th3_skew`), its roots sorted by angle into the slots (the
    general solver's order), and ``th2`` of each from both equations."""
    if k.planar:
        th3, ok, bad = _th3_planar(k, px, py, P)
    else:
        th3, ok, bad = _th3_quartic(k, pz, P)
    c3, s3 = np.cos(th3), np.sin(th3)
    gx, gy, gz = _g_of(k, c3, s3)
    gxy = gx * gx + gy * gy
    bad |= (ok & ~(gxy >= (NEAR * k.L) ** 2)).any(axis=0)
    X = (P - (gxy + gz * gz)) / (2.0 * k.a1)
    Y = (pz - k.d1 - k.ca1 * gz) / k.sa1
    sn, cs = gx * Y - gy * X, gx * X + gy * Y
    h = norm2(sn, cs)
    return [np.arctan2(sn, cs), cs / h, sn / h, th3, c3, s3, gx, gy, gz], ok, bad


def _sorted_roots(th: FloatArray, ok: np.ndarray, bad: np.ndarray, polished: FloatArray
                  ) -> tuple[FloatArray, np.ndarray, np.ndarray]:
    """Roots ``th (4, n)`` that exist (``ok``) sorted by angle, the others last, as the
    general solver orders them; declined where near +-pi (where the two orders could
    differ) or not ``ROOT_SEP`` apart. Returns ``polished`` in that order, ``ok``, ``bad``."""
    bad = bad | (ok & ~(np.abs(th) <= pi - 1e-8)).any(axis=0)
    order = np.argsort(np.where(ok, th, np.inf), axis=0)
    th = np.take_along_axis(th, order, axis=0)
    ok = np.take_along_axis(ok, order, axis=0)
    bad |= _close_roots(th, ok)
    return np.take_along_axis(polished, order, axis=0), ok, bad


def _th3_planar(
    k: PieperKernel, px: FloatArray, py: FloatArray, P: FloatArray
) -> tuple[FloatArray, np.ndarray, np.ndarray]:
    """:meth:`PieperKernel._th3_planar`: ``th3 (4, n)`` sorted, which exist, declined."""
    n0, nc, ns = k.n
    z0 = k.z[0]
    a1 = k.a1
    rho_n = hypot(nc, ns)
    lateral = px * px + py * py - z0 * z0
    neg = ~(lateral >= 0.0)
    bad = neg & (2.0 * abs(a1) * np.sqrt(np.where(neg, -lateral, 0.0)) / rho_n < REAL_OUT)
    root = 2.0 * abs(a1) * np.sqrt(np.where(neg, 0.0, lateral))
    u = np.stack([P + 2.0 * a1 * a1 + root, P + 2.0 * a1 * a1 - root])  # (2, n)
    ratio = (u - n0) / rho_n
    over = np.abs(ratio) - 1.0
    ok = ~neg & (over <= 0.0)
    bad |= (~neg & (over > 0.0) & (over < REAL_OUT * REAL_OUT / 2)).any(axis=0)
    delta = np.arccos(np.clip(ratio, -1.0, 1.0))
    phi = atan2(ns, nc)
    th = wrap_in_place(np.stack([phi + delta, phi - delta], axis=1).reshape(4, -1))
    return _sorted_roots(th, np.repeat(ok, 2, axis=0), bad, th)


def _th3_quartic(
    k: PieperKernel, pz: FloatArray, P: FloatArray
) -> tuple[FloatArray, np.ndarray, np.ndarray]:
    """:meth:`PieperKernel._th3_skew`: the real roots of the quartic in ``exp(i th3)``
    (Ferrari's formulas, :func:`rikin.ik.kernels.ferrari`), each then polished by one
    Newton step on the trigonometric equation; ``th3 (4, n)`` sorted, which exist,
    declined (also where the formulas are not confirmed)."""
    Pb, Hb = P - k.n[0], pz - k.d1 - k.ca1 * k.z[0]
    s2, a2_ = k.F1
    a0 = s2 * Pb * Pb + a2_ * Hb * Hb + k.K0
    a1c = k.kP[0] * Pb + k.kH[0] * Hb + k.k1[0]
    b1s = k.kP[1] * Pb + k.kH[1] * Hb + k.k1[1]
    c1 = (a1c - 1j * b1s) * 0.5
    big = np.maximum(np.maximum(np.abs(c1), np.abs(a0)), k.c2abs)
    z, sure = ferrari(c1 * k.inv_c2, a0 * k.inv_c2, np.conj(c1) * k.inv_c2,
                      np.full(a0.shape, k.D))
    bad = ~(k.c2abs > 1e-8 * big) | ~sure
    z = z.T  # (4, n)
    m = np.abs(z)
    gap = np.abs(m - 1.0)
    ok = gap < REAL_OUT
    bad |= (ok & ~(gap <= REAL_IN)).any(axis=0)
    c, s = z.real / m, z.imag / m
    cc, ss = c * c - s * s, 2.0 * c * s
    f = a0 + a1c * c + b1s * s + k.a2c * cc + k.b2s * ss
    df = b1s * c - a1c * s + 2.0 * (k.b2s * cc - k.a2c * ss)
    bad |= (ok & ~(df != 0.0)).any(axis=0)
    th = np.arctan2(s, c)
    return _sorted_roots(th, ok, bad, th - f / df)


def _close_roots(th: FloatArray, ok: np.ndarray) -> np.ndarray:
    """Poses ``(n,)`` whose existing roots ``th (4, n)`` (sorted, the missing ones last)
    are not ``ROOT_SEP`` apart around the circle (``pieper_kernel._apart``)."""
    gaps = np.diff(th, axis=0)
    bad = (ok[1:] & ~(gaps >= ROOT_SEP)).any(axis=0)
    first = th[0]
    last = np.where(ok, th, -np.inf).max(axis=0)
    return bad | ((ok.sum(axis=0) >= 2) & ~(first + _TAU - last >= ROOT_SEP))


def _joint1(
    k: PieperKernel, px: FloatArray, py: FloatArray, pos: list[FloatArray], valid: np.ndarray
) -> tuple[FloatArray, FloatArray, FloatArray, np.ndarray]:
    """``th1, cos th1, sin th1`` ``(4, n)`` of :meth:`PieperKernel._joint1_and_labels`, and
    where its labels (front, elbow up) are too near their boundaries, ``(4, n)``."""
    _, c2, s2, _, _, _, gx, gy, gz = pos
    L = k.L
    ca1s, sa1s = k.x1
    t1x, t1y, _ = k.t1
    t2x, t2y, _ = k.t2
    ux, uy = k.up1
    label_tol = LABEL * L
    xp, yp = c2 * gx - s2 * gy, s2 * gx + c2 * gy
    rx, ry = xp + t1x, ca1s * yp - sa1s * gz + t1y
    th1 = np.arctan2(py, px) - np.arctan2(ry, rx)
    # cos and sin of that difference, from the arguments of the two atan2
    h1 = norm2(px, py) * norm2(rx, ry)
    c1, s1 = (px * rx + py * ry) / h1, (py * rx - px * ry) / h1
    bad = ~(np.abs(px * c1 + py * s1) >= label_tol)
    ex, ey = c2 * t2x - s2 * t2y, s2 * t2x + c2 * t2y
    nl = xp * xp + yp * yp
    el = ex * xp + ey * yp
    across = np.abs(xp * uy - yp * ux)
    span = np.sqrt(nl) + L
    vertical = across <= SINGULAR_TOL * span
    bad |= ~vertical & ~(across >= 1e-7 * span)
    hu = np.where(vertical, ex - el / nl * xp,
                  ex * ux + ey * uy - el * (xp * ux + yp * uy) / nl)
    hn = np.where(vertical, 1.0, hypot(ux, uy))
    bad |= ~(np.abs(hu) >= label_tol * hn)
    return th1, c1, s1, bad & valid


def _wrist_columns(k: PieperKernel, rows: list[Any], c1: FloatArray, s1: FloatArray,
                   pos: list[FloatArray]) -> list[FloatArray]:
    """``R_w``'s columns, flat (:meth:`PieperKernel._wrist_columns` of the columns of
    :meth:`PieperKernel._goal_columns`), arrays ``(4, n)``."""
    (g00, g01, g02), (g10, g11, g12), (g20, g21, g22) = k.G
    r00, r01, r02, _, r10, r11, r12, _, r20, r21, r22, _ = rows
    _, c2, s2, _, c3, s3, _, _, _ = pos
    cols = []
    for j in ((0, 2) if k.orthogonal else (0, 1, 2)):
        h0, h1, h2 = k.Hcols[j]
        a = r00 * h0 + r01 * h1 + r02 * h2
        b = r10 * h0 + r11 * h1 + r12 * h2
        c = r20 * h0 + r21 * h1 + r22 * h2
        cols.append((g00 * a + g01 * b + g02 * c, g10 * a + g11 * b + g12 * c,
                     g20 * a + g21 * b + g22 * c))
    # the one-pose kernel's chain, plain arithmetic: the same on arrays of poses
    return k._wrist_columns(cols, c1, s1, c2, s2, c3, s3)


#: The wrist of every position: ``th4, th5, th6``, each a pair (wrist slot 0, slot 1) of
#: arrays ``(4, n)``; their cosines and sines (pairs of arrays broadcasting to
#: ``(4, 2, n)``, the wrist slot on axis 1); which slots exist (broadcasting to it); and
#: the positions ``(4, n)`` the one-pose kernel declines.
Wrist = tuple[list[tuple[FloatArray, FloatArray]], list[tuple[FloatArray, FloatArray]],
              np.ndarray, np.ndarray]


def _wrist_orthogonal(k: PieperKernel, rw: list[FloatArray]) -> Wrist:
    """:meth:`PieperKernel._wrist_orthogonal`. Slot 1 is slot 0 turned by pi at joints 4
    and 6 and mirrored at joint 5; each angle's cosine and sine are those of its
    ``atan2`` (the ratios of its arguments)."""
    ca3, sa3 = k.x3
    kappa, sigma = k.kappa, k.sigma
    m00, y5, z4, m02, y5b, z4b = rw
    m10, m20 = ca3 * y5 + sa3 * z4, ca3 * z4 - sa3 * y5
    m12, m22 = ca3 * y5b + sa3 * z4b, ca3 * z4b - sa3 * y5b
    if kappa < 0:  # C = diag(1, -1, -1)
        m02, m12, m22 = -m02, -m12, -m22
    sw = norm2(m02, m12)
    bad = ~(sw >= NEAR)
    theta = sigma * np.arctan2(sw, m22)
    phi = np.arctan2(m12, m02)
    cp, sp = m02 / sw, m12 / sw
    y6, x6 = cp * m10 - sp * m00, m22 * (cp * m00 + sp * m10) - sw * m20
    psi = kappa * np.arctan2(y6, x6)
    h5, h6 = norm2(sw, m22), norm2(y6, x6)
    c5, s5 = m22 / h5, sigma * sw / h5
    c6, s6 = x6 / h6, kappa * y6 / h6

    def slots(a: FloatArray, b: FloatArray) -> FloatArray:
        return np.stack([a, b], axis=1)

    th = [(phi, phi + pi), (-theta, theta), (psi, psi + kappa * pi)]
    cs = [(slots(cp, -cp), slots(sp, -sp)), (c5[:, None], slots(-s5, s5)),
          (slots(c6, -c6), slots(s6, -s6))]
    return th, cs, np.ones((1, 2, 1), dtype=bool), bad


def _wrist_general(k: PieperKernel, rw: list[FloatArray]) -> Wrist:
    """:meth:`PieperKernel._wrist_general` (a wrist with any twists), shaped as
    :func:`_wrist_orthogonal`'s."""
    ca3, sa3 = k.x3
    (w00, w10, w20), (w01, w11, w21), (w02, w12, w22) = (
        (rw[i], ca3 * rw[i + 1] + sa3 * rw[i + 2], ca3 * rw[i + 2] - sa3 * rw[i + 1])
        for i in (0, 3, 6))
    sb1, cb1, sb2, cb2 = k.wb
    c5 = (cb1 * cb2 - w22) / (sb1 * sb2)
    ok = np.abs(c5) <= 1.0 + OUT
    s5 = 1.0 - c5 * c5
    bad = ok & ~(s5 >= NEAR * NEAR)
    s5 = np.sqrt(np.where(s5 > 0.0, s5, 0.0))
    c1b, s1b, c2b, s2b = k.wbx
    phi_w = np.arctan2(w12, w02)
    out: list[list[FloatArray]] = [[] for _ in range(9)]  # th, cos, sin of joints 4-6
    for s in (s5, -s5):
        ax, ay = sb2 * s, -cb1 * sb2 * c5 - sb1 * cb2
        bad |= ok & ~(norm2(ax, ay) >= NEAR)
        th4 = phi_w - np.arctan2(ay, ax)
        c4, s4 = np.cos(th4), np.sin(th4)
        (r00, r10), (r01, r11) = _wrist_rest(((w00, w10, w20), (w01, w11, w21)), (c4, s4),
                                            (c1b, s1b), (c5, s), (c2b, s2b))
        y6, x6 = r10 - r01, r00 + r11
        h6 = norm2(y6, x6)
        values = (th4, np.arctan2(s, c5), np.arctan2(y6, x6), c4, s4, c5, s, x6 / h6, y6 / h6)
        for acc, v in zip(out, values, strict=True):
            acc.append(v)
    th = [(v[0], v[1]) for v in out[:3]]
    cos_sin = [np.stack(v, axis=1) for v in out[3:]]
    cs = [(cos_sin[0], cos_sin[1]), (cos_sin[2], cos_sin[3]), (cos_sin[4], cos_sin[5])]
    return th, cs, np.stack([ok, ok], axis=1), bad
