"""One regular pose of the three-parallel-axes solver (:mod:`rikin.ik.parallel3`), in plain
floats.

:meth:`ParallelAxesSolver.solve` works on stacks of poses with numpy: 4x4 products of every
slot, a Gauss-Newton polish and labels from the FK of every joint. For ONE pose numpy's cost
per call is nearly all of the time, so :class:`ParallelKernel` does the same closed form on
Python floats, with every per-arm constant read once from the solver. In the solver's
notation (``W = Rz(th1) M1 ... M5 Rz(th6)``, ``n = Rz(th1) u`` the parallel axes'
direction):

1. ``W`` from the target: base, tool, the solver's unit, its chain (reversed for axes 3-5)
   and ``M0``, ``M6`` folded into two constant affine maps;
2. joint 1: the combination of (A) and (B) free of joint 5, a sinusoid (2 roots); joint 5
   from (A) or (B), a sinusoid (2 roots each): the arms whose axis-6 point stays in one
   plane as joint 5 turns (a UR). Arms without that (a trigonometric quartic in joint 1)
   have no kernel, and take the general path;
3. joint 6 turns axis 2's direction into place; ``V = Rz(th2) M2 Rz(th3) M3 Rz(th4)`` is
   read off as two vectors (its origin's and its x axis's in-plane parts), each a constant
   sinusoid in joint 5 turned by joint 6, ``W``'s rotation and joint 1; joints 2-4 are the
   planar 3R of ``V``: two elbows, with no trigonometric call beyond one ``acos`` and the
   angles reported;
4. the labels of :meth:`ParallelAxesSolver._labels` and of :func:`rikin.ik.api.solve`'s
   wrist, read in the frame of axis 2, where "flattened along the parallel axes" is
   "the first two coordinates".

The slots come in the general solver's order (joint-1 root, joint-5 root, elbow), so that
the fast path returns the general path's solutions in the same order.

:func:`solve_batch` is the same closed form on arrays (``arm.ik_batch``): each scalar an
array over the poses, the roots of joints 1 and 5 and the elbows axes of 2; no labels (a
batch's slots carry theirs), an FK check of every slot, and the margins below as a pose's
``suspect`` flag.

:meth:`ParallelKernel.solve` returns None, and the caller takes the general path, for a
pose near anything the general solver decides with a tolerance: joint 1 near free (the
shoulder), two roots of a sinusoid near each other (joint 1, joint 5, the elbow at its
reach), axis 6 near the parallel axes (joint 6 free), a label near its boundary, a joint
value near +-pi, or nothing reachable. The margins are :mod:`rikin.ik.pieper_kernel`'s.
"""

from __future__ import annotations

from math import acos, atan2, cos, hypot, pi, remainder, sin, sqrt
from typing import TYPE_CHECKING, Protocol

import numpy as np

from .._validate import FloatArray
from ..tolerances import REACH_TOL
from ..transforms import _inv_transform
from .kernels import affine_mul as _mul
from .kernels import affine_mul_const as _mul_const
from .kernels import as_affine as _affine
from .kernels import chain_fk_error, norm2, wrap_in_place
from .pieper import ACCEPT_TOL
from .pieper_kernel import LABEL, NEAR_AXIS1, WRAP_EDGE
from .result import Branch

#: A joint's cosine and sine, two arrays broadcasting to the slots' shape.
CosSin = tuple[np.ndarray, np.ndarray]

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

__all__ = ["ParallelKernel", "single_kernel", "solve_batch"]


# What the kernel reads from the general solver, once per arm. The solver
# (:class:`rikin.ik.parallel3.ParallelAxesSolver`) imports this module, never the reverse:
# these protocols name the few attributes the kernel needs instead of the solver's class.
class _Model(Protocol):
    """The arm as ``M0 Rz(th1) M1 ... Rz(th6) M6`` (``pieper.ChainModel``), reversed when
    the parallel axes are 3-5."""

    @property
    def M(self) -> FloatArray: ...  # (7, 4, 4)
    @property
    def scale(self) -> float: ...


class KernelSource(Protocol):
    """The per-arm constants of the general solver that :class:`ParallelKernel` reads (their
    meaning is in :class:`rikin.ik.parallel3.ParallelAxesSolver`)."""

    @property
    def model(self) -> _Model: ...
    @property
    def unit(self) -> float: ...
    @property
    def reverse(self) -> bool: ...
    @property
    def offsets(self) -> FloatArray: ...  # (6,), rad
    @property
    def M0_inv(self) -> FloatArray: ...  # (4, 4)
    @property
    def M6_inv(self) -> FloatArray: ...  # (4, 4)
    @property
    def rank1(self) -> bool: ...
    @property
    def u(self) -> FloatArray: ...  # (3,)
    @property
    def c0(self) -> FloatArray: ...  # (2,)
    @property
    def lam(self) -> FloatArray: ...  # (2,)
    @property
    def K(self) -> FloatArray: ...  # (2, 2)
    @property
    def row(self) -> int: ...
    @property
    def tilt_row(self) -> bool: ...
    @property
    def sigma(self) -> float: ...
    @property
    def s2(self) -> float: ...
    @property
    def a(self) -> FloatArray: ...  # (2,)
    @property
    def b(self) -> FloatArray: ...  # (2,)

#: ``M2``, ``M3`` that turn z into +-z to within this are taken as exactly that (a DH twist
#: of 0 or pi as typed: its sine rounds to 1.2e-16); else no kernel, as joint 4 is read off
#: as an angle about z.
EXACT = 1e-14

#: Roots of a sinusoid closer than this (rad) send the pose to the general path: one joint
#: near a double root (joint 1, joint 5, the elbow at its reach). The pose fixes such a
#: pair to ~1e-16 / ROOT_SEP (1e-12 rad here), the general path polishes to that, and the
#: two paths agree to it. The spherical wrist's kernel keeps 1e-3 for its elbow; here the
#: sinusoids are solved in closed form, with no quartic near a double root.
ROOT_SEP = 1e-4

#: For a sinusoid ``cos(x) = ratio``: roots closer than ROOT_SEP when |ratio| is above
#: ``1 - EDGE``.
EDGE = ROOT_SEP * ROOT_SEP / 2

#: ... and no root at all when |ratio| is above ``1 + OUT``: twice the general solver's
#: slack ``sqrt(REACH_TOL)`` (both paths compute the ratio alike, to ~1e-16).
OUT = 2.0 * sqrt(REACH_TOL)

_TAU = 2.0 * pi


def single_kernel(solver: KernelSource, arm: SerialArm) -> ParallelKernel | None:
    """The plain-float kernel of ``solver`` for ``arm``, or None when the arm is not of the
    kind it takes (joint 1 from a quartic; parallel axes' factors not exactly turns about z)."""
    kernel = ParallelKernel(solver, arm)
    return kernel if kernel.usable else None


def _z_turn(M: np.ndarray) -> tuple[bool, float]:
    """Whether ``M``'s rotation is exactly ``Rz(gamma)`` or ``Rz(gamma) Rx(pi)``, and
    ``gamma``."""
    R = M[:3, :3]
    exact = (abs(abs(R[2, 2]) - 1.0) <= EXACT and max(abs(R[2, 0]), abs(R[2, 1]), abs(R[0, 2]),
                                                       abs(R[1, 2])) <= EXACT)
    return bool(exact), float(atan2(R[1, 0], R[0, 0]))


def _sinusoid_vectors(R: np.ndarray, m: np.ndarray, shift: np.ndarray) -> tuple[tuple[float, ...],
                                                                              ...]:
    """``R^T (Rz(-t) m - shift) = V0 + cos t Vc + sin t Vs`` for constant ``R (3, 3)``,
    ``m, shift (3,)``: the three vectors, each as 3 floats."""
    Rt = R.T
    V0 = Rt @ (np.array([0.0, 0.0, m[2]]) - shift)
    Vc = Rt @ np.array([m[0], m[1], 0.0])
    Vs = Rt @ np.array([m[1], -m[0], 0.0])
    return tuple(tuple(float(x) for x in v) for v in (V0, Vc, Vs))


class ParallelKernel:
    """:meth:`ParallelAxesSolver.solve` for one regular pose, on Python floats (see the
    module docstring). Built once per arm; :meth:`solve` is the one-pose interface of
    :func:`rikin.ik.api.solve`."""

    def __init__(self, solver: KernelSource, arm: SerialArm) -> None:
        sv = solver
        M = sv.model.M
        self.L = float(sv.model.scale)
        ok2, gamma2 = _z_turn(M[2])
        ok3, gamma3 = _z_turn(M[3])
        up = M[1, 2, :2]  # axis 1 seen in frame 2, flattened along the parallel axes
        self.usable = sv.rank1 and ok2 and ok3 and float(np.hypot(*up)) > 1e-6
        # W = A X B (X the world pose), or A X^-1 B for the reversed chain
        U = np.diag([sv.unit] * 3 + [1.0])
        U_inv = np.diag([1.0 / sv.unit] * 3 + [1.0])
        base, tool = np.array(arm.base, dtype=float), np.array(arm.tool, dtype=float)
        if sv.reverse:
            A, B = sv.M0_inv @ U @ tool, base @ U_inv @ sv.M6_inv
        else:
            A, B = sv.M0_inv @ U @ _inv_transform(base), _inv_transform(tool) @ U_inv @ sv.M6_inv
        self.reverse = sv.reverse
        self.A, self.B = _affine(A), _affine(B)
        # (A), (B): n . W[:, 2] and n . W[:, 3] minus c0; joint 1 from lam . (A, B)
        self.u = tuple(float(x) for x in sv.u)
        self.c0 = (float(sv.c0[0]), float(sv.c0[1]))
        self.lam = (float(sv.lam[0]), float(sv.lam[1]))
        self.row = sv.row
        kc, ks = (float(x) for x in sv.K[sv.row])
        self.rho5, self.phi5 = hypot(kc, ks), atan2(ks, kc)
        self.tilt_row = sv.tilt_row
        # joint 6: b = sigma R5^T Rz(-th5) r (its in-plane part) = b0 + c5 bc + s5 bs
        r = M[4, 2, :3]
        R5, t5 = M[5, :3, :3], M[5, :3, 3]
        sig = sv.sigma
        b = [sig * (R5.T @ v)[:2] for v in (np.array([0.0, 0.0, r[2]]), np.array([r[0], r[1], 0.0]),
                                            np.array([r[1], -r[0], 0.0]))]
        self.b = tuple(float(x) for v in b for x in v)
        # V = M1^-1 Rz(-th1) W Rz(-th6) M5^-1 Rz(-th5) M4^-1: its origin and x axis before
        # Rz(-th6), as sinusoids in joint 5
        R4, t4 = M[4, :3, :3], M[4, :3, 3]
        self.vp = _sinusoid_vectors(R5, -R4.T @ t4, t5)
        self.vd = _sinusoid_vectors(R5, R4[0].copy(), np.zeros(3))
        R1, t1 = M[1, :3, :3], M[1, :3, 3]
        self.R1cols = tuple(tuple(float(x) for x in R1[:, j]) for j in range(2))
        self.R1t1 = tuple(float(x) for x in (R1.T @ t1)[:2])
        # the planar 3R: |a + Rz(psi) b| = |P|
        a, bb = sv.a, sv.b
        self.a = (float(a[0]), float(a[1]))
        self.bp = (float(bb[0]), float(bb[1]))
        ab, axb = float(a @ bb), float(a[1] * bb[0] - a[0] * bb[1])
        self.rho_ab, self.phi_ab = hypot(ab, axb), atan2(axb, ab)
        self.aabb = float(a @ a + bb @ bb)
        self.s2, self.sig = sv.s2, sig
        self.g4 = gamma2 + sv.s2 * gamma3  # th4 = sigma (phi_V - th2 - s2 th3 - g4)
        self.gamma2 = gamma2
        self.up = (float(up[0]), float(up[1]))
        self.offsets = tuple(float(o) for o in sv.offsets)
        self.M = [_affine(M[k]) for k in range(7)]  # the batch's FK check
        #: ``labels[front][elbow up][joint 5 the root phi5 + d5 (no-flip), not phi5 - d5]``
        self.labels = [
            [[Branch("front" if f else "back", "up" if u_ else "down",
                     "no-flip" if w else "flip") for w in (False, True)]
             for u_ in (False, True)]
            for f in (False, True)
        ]

    # ------------------------------------------------------------------ one pose
    def _chain(self, rows: list[list[float]]) -> tuple[float, ...]:
        """``W`` (top three rows, 12 floats) of the world pose ``rows`` (4 lists of 4)."""
        (x00, x01, x02, x03), (x10, x11, x12, x13), (x20, x21, x22, x23) = rows[:3]
        if self.reverse:  # the rigid inverse
            x01, x02, x10, x12, x20, x21 = x10, x20, x01, x21, x02, x12
            x03, x13, x23 = (-(x00 * x03 + x01 * x13 + x02 * x23),
                             -(x10 * x03 + x11 * x13 + x12 * x23),
                             -(x20 * x03 + x21 * x13 + x22 * x23))
        return _mul(self.A, _mul((x00, x01, x02, x03, x10, x11, x12, x13, x20, x21, x22, x23),
                                 self.B))

    def solve(self, rows: list[list[float]]) -> tuple[list[float], list[Branch]] | None:
        """Every solution of the world pose ``rows`` (``T.tolist()``, a checked rigid pose):
        ``(q, branches)`` with ``q`` the solutions' joints one after another (6 each,
        wrapped to (-pi, pi]), in slot order; None sends the pose to the general path."""
        w00, w01, w02, w03, w10, w11, w12, w13, w20, w21, w22, w23 = self._chain(rows)
        u0, u1, u2 = self.u
        c0a, c0b = self.c0
        # (A) and (B) as e0 + ec cos th1 + es sin th1
        A0, Ac, As = u2 * w22 - c0a, u0 * w02 + u1 * w12, u0 * w12 - u1 * w02
        B0, Bc, Bs = u2 * w23 - c0b, u0 * w03 + u1 * w13, u0 * w13 - u1 * w03
        la, lb = self.lam
        e0, ec, es = la * A0 + lb * B0, la * Ac + lb * Bc, la * As + lb * Bs
        rho1 = hypot(ec, es)
        if rho1 < NEAR_AXIS1 * (1.0 + abs(e0)):
            return None  # joint 1 near free: the shoulder singularity
        ratio = -e0 / rho1
        if not abs(ratio) <= 1.0 - EDGE:
            return None  # joint 1's roots near each other, or none
        phi1, d1 = atan2(es, ec), acos(ratio)
        side = (A0, Ac, As) if self.row == 0 else (B0, Bc, Bs)
        q_out: list[float] = []
        branches: list[Branch] = []
        for th1 in (phi1 + d1, phi1 - d1):
            if not self._shoulder(th1, side, (w00, w01, w02, w03, w10, w11, w12, w13, w20, w21,
                                                w22, w23), q_out, branches):
                return None
        if not q_out or max(map(abs, q_out)) > WRAP_EDGE:
            return None
        return q_out, branches

    def _shoulder(self, th1: float, side: tuple[float, float, float], W: tuple[float, ...],
                  q_out: list[float], branches: list[Branch]) -> bool:
        """The (up to 4) solutions with joint 1 at ``th1``, appended to ``q_out`` and
        ``branches``; False when the pose is to go to the general path."""
        w00, w01, w02, w03, w10, w11, w12, w13, w20, w21, w22, w23 = W
        c1, s1 = cos(th1), sin(th1)
        u0, u1, u2 = self.u
        nx, ny = c1 * u0 - s1 * u1, s1 * u0 + c1 * u1
        L = self.L
        # front: axis 6 on the side of axis 1 that n x z1 points to
        f = w03 * ny - w13 * nx
        if abs(f) < LABEL * L:
            return False
        front = f >= 0.0
        # joint 6 turns a = R_W^T n (in-plane part) onto b(th5)
        ax = w00 * nx + w10 * ny + w20 * u2
        ay = w01 * nx + w11 * ny + w21 * u2
        na = hypot(ax, ay)
        if na < NEAR_AXIS1:
            return False  # axis 6 near the parallel axes: joint 6 near free (the pose
            # fixes joints 4-6 to ~1e-16 / na there)
        # joint 5: kc cos th5 + ks sin th5 = (A) or (B)
        if self.tilt_row:  # (A) is cos(th5 - phi5) = n . z6 (as the general path reads it)
            d5 = atan2(na, w02 * nx + w12 * ny + w22 * u2)
        else:
            ratio = (side[0] + side[1] * c1 + side[2] * s1) / self.rho5
            if abs(ratio) > 1.0 + OUT:
                return True  # no joint 5 for this joint 1
            if abs(ratio) > 1.0 - EDGE:
                return False
            d5 = acos(ratio)
        # Z = (R1^T Rz(-th1))[:2] and Z W (2 x 3), and Z W_p - (R1^T t1)[:2]
        (k0, k1, k2), (m0, m1, m2) = self.R1cols
        za0, za1, za2 = c1 * k0 - s1 * k1, s1 * k0 + c1 * k1, k2
        zb0, zb1, zb2 = c1 * m0 - s1 * m1, s1 * m0 + c1 * m1, m2
        g00 = za0 * w00 + za1 * w10 + za2 * w20
        g01 = za0 * w01 + za1 * w11 + za2 * w21
        g02 = za0 * w02 + za1 * w12 + za2 * w22
        g10 = zb0 * w00 + zb1 * w10 + zb2 * w20
        g11 = zb0 * w01 + zb1 * w11 + zb2 * w21
        g12 = zb0 * w02 + zb1 * w12 + zb2 * w22
        t1x, t1y = self.R1t1
        zpx = za0 * w03 + za1 * w13 + za2 * w23 - t1x
        zpy = zb0 * w03 + zb1 * w13 + zb2 * w23 - t1y
        b0x, b0y, bcx, bcy, bsx, bsy = self.b
        (p0x, p0y, p0z), (pcx, pcy, pcz), (psx, psy, psz) = self.vp
        (d0x, d0y, d0z), (dcx, dcy, dcz), (dsx, dsy, dsz) = self.vd
        if abs(sin(d5)) < LABEL:
            return False  # joint 5's two roots (the wrist's two branches) nearly one
        for no_flip, th5 in ((True, self.phi5 + d5), (False, self.phi5 - d5)):
            c5, s5 = cos(th5), sin(th5)
            bx, by = b0x + c5 * bcx + s5 * bsx, b0y + c5 * bcy + s5 * bsy
            dot, cross = ax * bx + ay * by, ax * by - ay * bx
            th6 = atan2(cross, dot)
            h = hypot(dot, cross)
            c6, s6 = dot / h, cross / h
            # V's origin and x axis before Rz(-th6), then turned and carried to frame 2
            x, y = p0x + c5 * pcx + s5 * psx, p0y + c5 * pcy + s5 * psy
            z = p0z + c5 * pcz + s5 * psz
            x, y = c6 * x + s6 * y, c6 * y - s6 * x
            Px = g00 * x + g01 * y + g02 * z + zpx
            Py = g10 * x + g11 * y + g12 * z + zpy
            x, y = d0x + c5 * dcx + s5 * dsx, d0y + c5 * dcy + s5 * dsy
            z = d0z + c5 * dcz + s5 * dsz
            x, y = c6 * x + s6 * y, c6 * y - s6 * x
            phi_v = atan2(g10 * x + g11 * y + g12 * z, g00 * x + g01 * y + g02 * z)
            if not self._planar(th1, th5, th6, Px, Py, phi_v, (front, no_flip), q_out,
                                branches):
                return False
        return True

    def _planar(self, th1: float, th5: float, th6: float, Px: float, Py: float, phi_v: float,
                sides: tuple[bool, bool], q_out: list[float], branches: list[Branch]) -> bool:
        """Joints 2-4 (two elbows) putting axis 4 at ``(Px, Py)`` with ``V``'s x axis at
        ``phi_v``, and the solutions appended, labelled with ``sides`` (front, no-flip: which
        root of joints 1 and 5 they are); False: to the general path."""
        P2 = Px * Px + Py * Py
        ratio = (P2 - self.aabb) / 2.0 / self.rho_ab
        if abs(ratio) > 1.0 + OUT:
            return True  # joints 2-4 cannot span the distance
        if abs(ratio) > 1.0 - EDGE:
            return False  # the elbow near stretched or folded
        dpsi = acos(ratio)
        front, no_flip = sides
        a0, a1 = self.a
        b0, b1 = self.bp
        ux, uy = self.up
        L = self.L
        s2, sig, g4, gamma2 = self.s2, self.sig, self.g4, self.gamma2
        o1, o2, o3, o4, o5, o6 = self.offsets
        up_tol = LABEL * L * hypot(ux, uy)
        for psi in (self.phi_ab + dpsi, self.phi_ab - dpsi):
            cp, sp = cos(psi), sin(psi)
            ex, ey = a0 + cp * b0 - sp * b1, a1 + sp * b0 + cp * b1
            # Rz(th2) turns (ex, ey) onto P (the same length)
            c, s = Px * ex + Py * ey, ex * Py - ey * Px
            th2 = atan2(s, c)
            c, s = c / P2, s / P2
            elx, ely = c * a0 - s * a1, s * a0 + c * a1  # the elbow, Rz(th2) a
            hu = elx * ux + ely * uy - (elx * Px + ely * Py) * (Px * ux + Py * uy) / P2
            if abs(hu) < up_tol:
                return False
            th3 = s2 * (psi - gamma2)
            th4 = sig * (phi_v - th2 - s2 * th3 - g4)
            rem, tau = remainder, _TAU
            if self.reverse:
                q_out += (rem(th6 - o1, tau), rem(th5 - o2, tau), rem(th4 - o3, tau),
                          rem(th3 - o4, tau), rem(th2 - o5, tau), rem(th1 - o6, tau))
            else:
                q_out += (rem(th1 - o1, tau), rem(th2 - o2, tau), rem(th3 - o3, tau),
                          rem(th4 - o4, tau), rem(th5 - o5, tau), rem(th6 - o6, tau))
            branches.append(self.labels[front][hu > 0.0][no_flip])
        return True


# ------------------------------------------------------------------------- many poses
# The same closed form on stacks: every scalar above becomes an array over the poses (last
# axis), joint 1's roots an axis of 2, joint 5's a second, the elbows a third (the slots in
# the general solver's order), and "decline" a pose's ``suspect`` flag.

def solve_batch(k: ParallelKernel, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel's closed form for poses ``X (4, 4, n)`` (world frame, checked rigid).

    Returns ``q (8, 6, n)`` wrapped (NaN where no solution), ``valid (8, n)`` and
    ``suspect (n,)``: poses the one-pose kernel would decline (a margin of the module
    docstring) or with a slot whose FK misses its pose by more than ``ACCEPT_TOL``; the
    caller solves those on the general path.
    """
    n = X.shape[-1]
    with np.errstate(all="ignore"):  # NaN and inf end up in suspect
        W = _batch_chain(k, X)
        th1, side, suspect = _batch_joint1(k, W)
        th, cs, valid, bad = _batch_rest(k, W, th1, side)
        err = _batch_fk_error(k, W, cs)
        suspect = suspect | bad | (valid & ~(err <= ACCEPT_TOL)).any(axis=(0, 1, 2))
        full = (2, 2, 2, n)
        th = [np.broadcast_to(t, full).reshape(8, n) for t in th]
        valid = np.broadcast_to(valid, full).reshape(8, n)
    if k.reverse:
        th = th[::-1]
    q = np.stack(th, axis=1) - np.array(k.offsets)[:, None]  # (8, 6, n)
    q = wrap_in_place(q)
    q[np.broadcast_to(~valid[:, None], q.shape)] = np.nan
    return q, valid, suspect


def _batch_chain(k: ParallelKernel, X: np.ndarray) -> tuple[np.ndarray, ...]:
    """``W`` of the poses ``X (4, 4, n)``: its top three rows, 12 arrays ``(n,)``."""
    x00, x01, x02, x03, x10, x11, x12, x13, x20, x21, x22, x23 = X[:3].reshape(12, -1)
    if k.reverse:  # the rigid inverse
        x01, x02, x10, x12, x20, x21 = x10, x20, x01, x21, x02, x12
        x03, x13, x23 = (-(x00 * x03 + x01 * x13 + x02 * x23),
                         -(x10 * x03 + x11 * x13 + x12 * x23),
                         -(x20 * x03 + x21 * x13 + x22 * x23))
    x = (x00, x01, x02, x03, x10, x11, x12, x13, x20, x21, x22, x23)
    return _mul(k.A, _mul_const(x, k.B))


def _batch_joint1(k: ParallelKernel, W: tuple[np.ndarray, ...]
                  ) -> tuple[np.ndarray, tuple[np.ndarray, ...], np.ndarray]:
    """Joint 1's two roots ``(2, n)``, the sinusoid (A) or (B) that gives joint 5, and the
    poses with joint 1 near free or its roots near each other (or none)."""
    _, _, w02, w03, _, _, w12, w13, _, _, w22, w23 = W
    u0, u1, u2 = k.u
    c0a, c0b = k.c0
    A0, Ac, As = u2 * w22 - c0a, u0 * w02 + u1 * w12, u0 * w12 - u1 * w02
    B0, Bc, Bs = u2 * w23 - c0b, u0 * w03 + u1 * w13, u0 * w13 - u1 * w03
    la, lb = k.lam
    e0, ec, es = la * A0 + lb * B0, la * Ac + lb * Bc, la * As + lb * Bs
    rho1 = norm2(ec, es)
    ratio = -e0 / rho1
    suspect = ~(rho1 >= NEAR_AXIS1 * (1.0 + np.abs(e0))) | ~(np.abs(ratio) <= 1.0 - EDGE)
    phi1, d1 = np.arctan2(es, ec), np.arccos(np.clip(ratio, -1.0, 1.0))
    side = (A0, Ac, As) if k.row == 0 else (B0, Bc, Bs)
    return np.stack([phi1 + d1, phi1 - d1]), side, suspect


def _batch_rest(k: ParallelKernel, W: tuple[np.ndarray, ...], th1: np.ndarray,
                side: tuple[np.ndarray, ...]
                ) -> tuple[list[np.ndarray], list[CosSin], np.ndarray, np.ndarray]:
    """Joints 1-6 (broadcasting to ``(2, 2, 2, n)``: joint 1's root, joint 5's, the elbow),
    their cosines and sines (from the closed form's arguments where it has them: the FK
    check then takes no ``cos`` or ``sin`` of joints 1-3, 5 and 6), which slots exist, and
    the poses :meth:`ParallelKernel._shoulder` would decline."""
    w00, w01, w02, w03, w10, w11, w12, w13, w20, w21, w22, w23 = W
    c1, s1 = np.cos(th1), np.sin(th1)  # (2, n)
    u0, u1, u2 = k.u
    nx, ny = c1 * u0 - s1 * u1, s1 * u0 + c1 * u1
    ax, ay = w00 * nx + w10 * ny + w20 * u2, w01 * nx + w11 * ny + w21 * u2
    na = norm2(ax, ay)
    bad = ~(na >= NEAR_AXIS1)  # no labels here: only the margins of singularities
    if k.tilt_row:
        d5 = np.arctan2(na, w02 * nx + w12 * ny + w22 * u2)
        ok5 = np.ones_like(bad)
    else:
        ratio = (side[0] + side[1] * c1 + side[2] * s1) / k.rho5
        ok5 = np.abs(ratio) <= 1.0 + OUT
        bad |= ok5 & ~(np.abs(ratio) <= 1.0 - EDGE)
        d5 = np.arccos(np.clip(ratio, -1.0, 1.0))
    th5 = k.phi5 + np.stack([d5, -d5], axis=1)  # (2, 2, n)
    (r0, r1, r2), (m0, m1, m2) = k.R1cols
    za = (c1 * r0 - s1 * r1, s1 * r0 + c1 * r1, r2)
    zb = (c1 * m0 - s1 * m1, s1 * m0 + c1 * m1, m2)
    # Z W (2 x 3) and Z W_p - (R1^T t1)[:2], each (2, 1, n)
    g = [(z[0] * wa + z[1] * wb + z[2] * wc)[:, None] for z in (za, zb)
         for wa, wb, wc in ((w00, w10, w20), (w01, w11, w21), (w02, w12, w22))]
    zp = [(z[0] * w03 + z[1] * w13 + z[2] * w23 - t)[:, None] for z, t in
          zip((za, zb), k.R1t1, strict=True)]
    c5, s5 = np.cos(th5), np.sin(th5)
    b0x, b0y, bcx, bcy, bsx, bsy = k.b
    bx, by = b0x + c5 * bcx + s5 * bsx, b0y + c5 * bcy + s5 * bsy
    ax, ay = ax[:, None], ay[:, None]
    dot, cross = ax * bx + ay * by, ax * by - ay * bx
    th6 = np.arctan2(cross, dot)
    h = norm2(dot, cross)
    c6, s6 = dot / h, cross / h

    def in_frame2(v: tuple[tuple[float, ...], ...]) -> tuple[np.ndarray, np.ndarray]:
        """``V``'s vector ``v0 + c5 vc + s5 vs`` turned by joint 6, in frame 2 (xy)."""
        (p0x, p0y, p0z), (pcx, pcy, pcz), (psx, psy, psz) = v
        x, y = p0x + c5 * pcx + s5 * psx, p0y + c5 * pcy + s5 * psy
        z = p0z + c5 * pcz + s5 * psz
        x, y = c6 * x + s6 * y, c6 * y - s6 * x
        return g[0] * x + g[1] * y + g[2] * z, g[3] * x + g[4] * y + g[5] * z

    Px, Py = in_frame2(k.vp)
    Px, Py = Px + zp[0], Py + zp[1]
    dx, dy = in_frame2(k.vd)
    th234, cs234, valid, bad_p = _batch_planar(k, th5, Px, Py, np.arctan2(dy, dx),
                                               ok5[:, None])
    th = [th1[:, None, None], *th234, th5[:, :, None], th6[:, :, None]]
    cs = [(c1[:, None, None], s1[:, None, None]), *cs234, (c5[:, :, None], s5[:, :, None]),
          (c6[:, :, None], s6[:, :, None])]
    return th, cs, valid, bad.any(axis=0) | bad_p


def _batch_planar(k: ParallelKernel, th5: np.ndarray, Px: np.ndarray, Py: np.ndarray,
                  phi_v: np.ndarray, ok5: np.ndarray
                  ) -> tuple[list[np.ndarray], list[CosSin], np.ndarray, np.ndarray]:
    """Joints 2-4 ``(2, 2, 2, n)`` (the elbows last but one) of :meth:`ParallelKernel._planar`,
    their cosines and sines (joint 2's from its ``atan2``'s arguments, joint 3's from
    ``psi``'s), which slots exist, and the poses with an elbow near stretched or folded."""
    P2 = Px * Px + Py * Py
    ratio = (P2 - k.aabb) / 2.0 / k.rho_ab
    okp = ok5 & (np.abs(ratio) <= 1.0 + OUT)
    bad = (okp & ~(np.abs(ratio) <= 1.0 - EDGE)).any(axis=(0, 1))
    dpsi = np.arccos(np.clip(ratio, -1.0, 1.0))
    psi = k.phi_ab + np.stack([dpsi, -dpsi], axis=2)  # (2, 2, 2, n)
    a0, a1 = k.a
    b0, b1 = k.bp
    cp, sp = np.cos(psi), np.sin(psi)
    ex, ey = a0 + cp * b0 - sp * b1, a1 + sp * b0 + cp * b1
    Px, Py = Px[:, :, None], Py[:, :, None]
    y2, x2 = ex * Py - ey * Px, Px * ex + Py * ey
    th2 = np.arctan2(y2, x2)
    h2 = norm2(x2, y2)  # 0 at a singular pose: NaN cosines, an FK miss, suspect
    th3 = k.s2 * (psi - k.gamma2)
    cg, sg = cos(k.gamma2), sin(k.gamma2)
    c3, s3 = cp * cg + sp * sg, k.s2 * (sp * cg - cp * sg)
    th4 = k.sig * (phi_v[:, :, None] - th2 - k.s2 * th3 - k.g4)
    cs = [(x2 / h2, y2 / h2), (c3, s3), (np.cos(th4), np.sin(th4))]
    return [th2, th3, th4], cs, np.repeat(okp[:, :, None], 2, axis=2), bad


def _batch_fk_error(k: ParallelKernel, W: tuple[np.ndarray, ...], cs: list[CosSin]
                    ) -> np.ndarray:
    """``max(|p - p_goal| / scale, max |R - R_goal|)`` ``(2, 2, 2, n)`` of the chain's
    joints (their cosines and sines ``cs``, 6 pairs of arrays broadcasting to that shape)
    against ``W``, both between ``M0``
    and ``M6`` (the general batch kernel's check). Joints 5 and 6 have fewer distinct
    values than slots: the chain's tail is multiplied out on its own shape."""
    goal = _mul_const(_mul(k.M[0], W), k.M[6])
    return chain_fk_error(k.M, cs, goal, k.L, split=4)
