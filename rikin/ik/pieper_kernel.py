"""One regular pose of the general 6R solver (:mod:`rikin.ik.pieper`), in plain floats.

:meth:`Pieper6RSolver.solve` works on stacks of poses with numpy: sampled Fourier
coefficients, a 4x4 companion matrix and its eigenvalues, 8 slots of 4x4 products and two
Gauss-Newton passes on the whole pose. For ONE pose numpy's per-call overhead is most of
the time, so :class:`PieperKernel` does the same decoupling on Python floats, with every
per-arm constant read once from the solver:

1. the wrist centre ``p'`` in the frame of axis 1 (base, tool and ``M0`` folded into one
   affine map), and ``S``, the target's rotation with the constant factors folded in, so
   that the wrist's rotation is ``R_w = Rx(-al3) Rz(-th3) Rx(-al2) Rz(-th2) Rx(-al1)
   Rz(-th1) S``;
2. joints 1-3: when axes 1 and 2 meet or are parallel, two sinusoids (``th3``, then two
   ``th2`` each); when they are skew, the degree-2 trigonometric polynomial in ``th3`` of
   :func:`rikin.ik.pieper._trig2_roots`, whose Fourier coefficients are closed forms in
   ``|p'|^2`` and ``p'_z`` here, as the quartic in ``z = exp(i th3)`` solved by Ferrari's
   method, each root polished once by Newton's method on the complex quartic and the
   real ones once more on the trigonometric equation; ``th2`` and ``th1`` then follow;
3. the wrist's two solutions (orthogonal wrist: ZYZ angles; other twists: ``q5`` from
   the ``(3, 3)`` entry), and the branch labels of :meth:`Pieper6RSolver._labels`.

The slots come in the general solver's order (position roots as
:func:`~rikin.ik.pieper._trig2_roots` sorts them, real ones by angle; wrist slot 0 before
1), so that the fast path returns the general path's solutions in the same order.

:meth:`PieperKernel.solve` returns None, and the caller takes the general path, for a pose
near anything the general solver decides with a tolerance: the wrist centre near axis 1 or
axis 2, two position roots near each other (the elbow near its reach edge or fold, a double
root), a root of the quartic near the unit circle without being on it, a wrist near q5 = 0
or pi (or near its fold), a branch label near its boundary, a joint value near +-pi (where
the two paths could wrap it to different ends), or nothing reachable. Away from those, the
solutions are distinct by far more than the de-duplication tolerance, and every decision
(real or complex, reachable or not, front or back, up or down, flip or not) is the general
solver's with margins of several orders of magnitude.
"""

from __future__ import annotations

from cmath import sqrt as csqrt
from collections.abc import Sequence
from math import acos, atan2, cos, hypot, pi, remainder, sin, sqrt
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from .._validate import FloatArray
from ..tolerances import REACH_TOL, SINGULAR_TOL
from ..transforms import _inv_transform
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

__all__ = ["PieperKernel", "single_kernel"]


# What the kernel reads from the general solver, once per arm. The solver
# (:class:`rikin.ik.pieper.Pieper6RSolver`) imports this module, never the reverse: these
# protocols name the few attributes the kernel needs instead of the solver's classes.
class _Model(Protocol):
    """The arm as ``M0 Rz(th1) M1 ... Rz(th6) M6`` (``pieper.ChainModel``)."""

    @property
    def M(self) -> FloatArray: ...  # (7, 4, 4)
    @property
    def offsets(self) -> FloatArray: ...  # (6,), rad
    @property
    def scale(self) -> float: ...


class _Wrist(Protocol):
    """The wrist centre and twists (``pieper.WristGeometry``)."""

    @property
    def c_flange(self) -> FloatArray: ...  # (3,), the centre in the flange frame
    @property
    def v(self) -> FloatArray: ...  # (3,), the centre after Rz(th3)
    @property
    def b1(self) -> float: ...
    @property
    def b2(self) -> float: ...


class KernelSource(Protocol):
    """The per-arm constants of the general solver that :class:`PieperKernel` reads."""

    @property
    def model(self) -> _Model: ...
    @property
    def wrist(self) -> _Wrist: ...
    @property
    def unit(self) -> float: ...
    @property
    def case(self) -> str: ...
    @property
    def M0_inv(self) -> FloatArray: ...
    @property
    def a1(self) -> float: ...
    @property
    def d1(self) -> float: ...
    @property
    def ca1(self) -> float: ...
    @property
    def sa1(self) -> float: ...
    @property
    def orthogonal(self) -> bool: ...
    @property
    def sigma(self) -> float: ...
    @property
    def kappa(self) -> float: ...

    def _to_unit(self, T: FloatArray) -> FloatArray: ...
    def _arm_constants(self) -> tuple[FloatArray, ...]: ...


#: Relative distances below this send the pose to the general path: the wrist centre
#: from axis 1 or 2 (times the arm's size), |sin q5| (and what the wrist formulas divide
#: by). Not the general solver's own thresholds (1e-9 to 1e-6) but where the pose starts
#: to fix the joints loosely: there the Jacobian's smallest singular value (relative)
#: falls below ~1e-6, the general solver's Gauss-Newton polish moves the joints by
#: ~1e-16 / sigma along the ill-conditioned direction, and the two paths could then
#: differ by more than 1e-9 rad while both reproduce the pose to rounding.
NEAR = 1e-3

#: ... except for the wrist centre's distance from axis 1, where this is the line. Both
#: paths take joint 1 from the same wrist centre, and its rounding (~1e-16 of the arm's
#: size) moves joint 1 by ~1e-16 / distance: 1e-12 rad here. For an arm with no shoulder
#: offset the shoulder singularity is one equation in the joints, so uniformly random
#: poses come within 1e-3 of it once in 500 (within 1e-4 once in 5,000).
NEAR_AXIS1 = 1e-4

#: Position roots closer than this (rad) send the pose to the general path (the elbow
#: near its reach edge or fold, a double root); the same conditioning argument.
ROOT_SEP = 1e-3

#: For a sinusoid ``cos(x) = ratio``: roots closer than ROOT_SEP when |ratio| is above
#: ``1 - EDGE``; no root at all (for the general solver too, whose slack is
#: ``sqrt(REACH_TOL)``) when |ratio| is above ``1 + OUT``.
EDGE = ROOT_SEP * ROOT_SEP / 2
OUT = 10.0 * sqrt(REACH_TOL)

#: A root ``z`` of the quartic is real when ``||z| - 1|`` is below REAL_IN and complex
#: when it is above REAL_OUT (the general solver's line is ``ROOT_TOL = 1e-5``); between
#: them the pose goes to the general path.
REAL_IN, REAL_OUT = 1e-9, 1e-3

#: A label decided by a sign (front/back, elbow up/down, flip) whose quantity is this
#: close to its boundary (relative) sends the pose to the general path.
LABEL = 1e-7

#: Joint values this close to +-pi could wrap to either end in the two paths.
WRAP_EDGE = pi - 1e-10

_TAU = 2.0 * pi
_CUBE_ROOTS_OF_1 = (complex(-0.5, 0.8660254037844386), complex(-0.5, -0.8660254037844386))

def single_kernel(solver: KernelSource, arm: SerialArm) -> PieperKernel | None:
    """The plain-float kernel of ``solver`` for ``arm``, or None when the arm's position
    problem is of a degree the kernel does not take (a skew arm whose quartic has no
    z^4 term: the general solver's degree-1 branch)."""
    kernel = PieperKernel(solver, arm)
    return kernel if kernel.usable else None


def _rows(M: np.ndarray) -> list[list[float]]:
    return [[float(v) for v in row] for row in M]


class PieperKernel:
    """:meth:`Pieper6RSolver.solve` for one regular pose, on Python floats (see the
    module docstring). Built once per arm; :meth:`solve` is the one-pose interface of
    :func:`rikin.ik.api.solve` (it hands back each solution's Branch from ``labels``)."""

    def __init__(self, solver: KernelSource, arm: SerialArm) -> None:
        model, wg = solver.model, solver.wrist
        M = [_rows(m) for m in model.M]
        self.L = float(model.scale)
        self.case = solver.case
        # in the solver's units (``solver.unit`` per arm unit, a power of two)
        base_inv, tool_inv = solver._to_unit(_inv_transform(arm.base)), solver._to_unit(
            _inv_transform(arm.tool)
        )
        self.unit = solver.unit
        # wrist centre: p' = G (T c_tcp); rotation S = G_R R H
        G = solver.M0_inv @ base_inv
        self.G = _rows(G[:3, :3])
        self.Gt = [float(v) for v in G[:3, 3]]
        self.c_tcp = [float(v) for v in (tool_inv @ np.append(wg.c_flange, 1.0))[:3]]
        H = tool_inv[:3, :3] @ model.M[6, :3, :3].T
        self.Hcols = [[float(H[i, j]) for i in range(3)] for j in range(3)]
        # the constant twists Rx(alpha_i) of M1, M2, M3 (exact zeros kept) and M1, M2 shifts
        self.x1 = (M[1][1][1], M[1][2][1])
        self.x2 = (M[2][1][1], M[2][2][1])
        self.x3 = (M[3][1][1], M[3][2][1])
        self.t1 = (M[1][0][3], M[1][1][3], M[1][2][3])
        self.t2 = (M[2][0][3], M[2][1][3], M[2][2][3])
        self.up1 = (M[1][2][0], M[1][2][1])  # axis 1 in frame 2's xy plane
        #: what :meth:`_joint1_and_labels` reads, in one tuple (one lookup per call)
        self._j1 = (float(model.scale), *self.x1, *self.t1[:2], *self.t2[:2], *self.up1,
                    LABEL * float(model.scale))
        # g(th3) = M2 Rz(th3) v = g0 + cos(th3) gc + sin(th3) gs
        vx, vy, _ = (float(x) for x in wg.v)
        g0, gc, gs, _, _ = solver._arm_constants()
        self.g0 = [float(x) for x in g0]
        self.gc = [float(x) for x in gc]
        self.gs = [float(x) for x in gs]
        # |g|^2 = n0 + nc cos + ns sin; g_z = z0 + zc cos + zs sin
        n0 = float(g0 @ g0 + vx * vx + vy * vy)
        nc, ns = float(2 * g0 @ gc), float(2 * g0 @ gs)
        z0, zc, zs = float(g0[2]), float(gc[2]), float(gs[2])
        self.n = (n0, nc, ns)
        self.z = (z0, zc, zs)
        a1, d1, ca1, sa1 = solver.a1, solver.d1, solver.ca1, solver.sa1
        self.a1, self.d1, self.ca1, self.sa1 = a1, d1, ca1, sa1
        # skew: F(th3) = sa1^2 B^2 + 4 a1^2 A^2 - 4 a1^2 sa1^2 (gx^2 + gy^2), with
        # B = Pb - (nc cos + ns sin), A = Hb - ca1 (zc cos + zs sin), Pb = P - n0,
        # Hb = H - ca1 z0 (P, H from the pose, see solve); its Fourier coefficients:
        s2, a2_, one = sa1 * sa1, 4.0 * a1 * a1, ca1 * ca1 + sa1 * sa1
        self.K0 = (s2 * (nc * nc + ns * ns) / 2 + a2_ / 2 * one * (zc * zc + zs * zs)
                   - a2_ * s2 * (n0 - z0 * z0))
        self.F1 = (s2, a2_)
        # a1c = -2 s2 nc Pb - 2 a2_ ca1 zc Hb - a2_ s2 (nc - 2 z0 zc) (and b1s with ns, zs)
        self.kP = (-2.0 * s2 * nc, -2.0 * s2 * ns)
        self.kH = (-2.0 * a2_ * ca1 * zc, -2.0 * a2_ * ca1 * zs)
        self.k1 = (-a2_ * s2 * (nc - 2 * z0 * zc), -a2_ * s2 * (ns - 2 * z0 * zs))
        a2c = s2 * (nc * nc - ns * ns) / 2 + a2_ / 2 * one * (zc * zc - zs * zs)
        b2s = s2 * nc * ns + a2_ * one * zc * zs
        self.a2c, self.b2s = a2c, b2s
        c2 = complex(a2c, -b2s) / 2
        self.c2abs = abs(c2)
        self.usable = self.case != "skew" or self.c2abs > 0.0
        if self.usable and self.case == "skew":
            self.inv_c2 = 1.0 / c2
            self.D = c2.conjugate() / c2
        #: axes 1 and 2 skew at right angles, and the wrist centre's height along axis 2
        #: constant (axes 2 and 3 parallel): the quartic is a quadratic in |g|^2
        #: (:meth:`_th3_planar`), as for the KUKA KR5 and KR6 and the Epson C4
        self.planar = (self.case == "skew" and abs(ca1) <= 1e-12
                       and max(abs(zc), abs(zs)) <= 1e-12 * self.L)
        # wrist
        self.orthogonal = solver.orthogonal
        self.sigma, self.kappa = solver.sigma, solver.kappa
        b1, b2 = wg.b1, wg.b2
        self.wb = (sin(b1), cos(b1), sin(b2), cos(b2))
        R4, R5 = model.M[4, :3, :3], model.M[5, :3, :3]  # Rx(b1), Rx(b2), exact zeros kept
        self.wbx = (float(R4[1, 1]), float(R4[2, 1]), float(R5[1, 1]), float(R5[2, 1]))
        self.offsets = tuple(float(o) for o in model.offsets)
        self._loop_constants()

    def _loop_constants(self) -> None:
        """What :meth:`solve` and :meth:`_finish_orthogonal` read once per pose, in one
        tuple: the twists of M1-M3, the wrist's kappa, sigma and kappa pi; the thresholds
        near axes 1 and 2 times the arm's size."""
        #: ``labels[front][elbow up][sin(q5) >= 0]``: the Branch of a solution
        self.labels = [
            [[Branch("front" if f else "back", "up" if u else "down", "no-flip" if w else "flip")
              for w in (False, True)] for u in (False, True)]
            for f in (False, True)
        ]
        self._ortho = (*self.x1, *self.x2, *self.x3, self.kappa, self.sigma, self.kappa * pi)
        self._near_axis1 = NEAR_AXIS1 * self.L
        self._near2 = (NEAR * self.L) ** 2

    # ------------------------------------------------------------------ position
    def _th3_skew(self, px: float, py: float, pz: float) -> list[float] | None:
        """The real roots ``th3`` of the quartic, sorted by angle, or None (near a
        double root, a root near the unit circle, or the degree dropping)."""
        d1, a1, ca1 = self.d1, self.a1, self.ca1
        P = px * px + py * py + pz * pz - a1 * a1 + d1 * d1 - 2.0 * d1 * pz
        H = pz - d1
        n0, _, _ = self.n
        z0 = self.z[0]
        Pb, Hb = P - n0, H - ca1 * z0
        s2, a2_ = self.F1
        a0 = s2 * Pb * Pb + a2_ * Hb * Hb + self.K0
        kP, kH, k1 = self.kP, self.kH, self.k1
        a1c = kP[0] * Pb + kH[0] * Hb + k1[0]
        b1s = kP[1] * Pb + kH[1] * Hb + k1[1]
        c1 = complex(a1c, -b1s) * 0.5
        big = max(self.c2abs, abs(c1), abs(a0))
        if self.c2abs <= 1e-8 * big:
            return None
        # monic quartic z^4 + A z^3 + B z^2 + C z + D (z^2 F(theta), F real on |z| = 1)
        ic2 = self.inv_c2
        A = c1 * ic2
        B = a0 * ic2
        C = c1.conjugate() * ic2
        D = self.D
        roots = _quartic(A, B, C, D)
        if roots is None:
            return None
        a2c, b2s = self.a2c, self.b2s
        out = []
        for z in roots:
            m = abs(z)
            gap = abs(m - 1.0)
            if gap >= REAL_OUT:
                continue
            if gap > REAL_IN:
                return None
            c, s = z.real / m, z.imag / m
            th = atan2(s, c)
            if abs(th) > pi - 1e-8:  # the general solver sorts by angle in (-pi, pi]
                return None
            # one Newton step on F(theta) = a0 + a1c cos + b1s sin + a2c cos 2 + b2s sin 2
            cc, ss = c * c - s * s, 2.0 * c * s
            f = a0 + a1c * c + b1s * s + a2c * cc + b2s * ss
            df = b1s * c - a1c * s + 2.0 * (b2s * cc - a2c * ss)
            if df == 0.0:
                return None
            out.append((th, th - f / df))
        out.sort()
        if not _apart([th for th, _ in out]):
            return None
        return [t for _, t in out]

    def _th3_planar(self, px: float, py: float, pz: float) -> list[float] | None:
        """:meth:`_th3_skew` for a planar arm (``self.planar``), in closed form.

        With ``cos(al1) = 0`` and ``g_z = z0`` constant, ``F`` is a quadratic in
        ``u = |g|^2 = n0 + nc cos(th3) + ns sin(th3)``: ``(P - u)^2 + 4 a1^2 (H^2 + z0^2 - u)``,
        whose roots are ``u = P + 2 a1^2 +- 2 |a1| sqrt(rho^2 - z0^2)`` (``rho`` the wrist
        centre's distance from axis 1, ``z0`` its offset along axis 2: the two shoulders);
        each ``u`` is a sinusoid in ``th3`` (the two elbows). The same roots, sorted the
        same way, with the quartic's margins for None: roots off the unit circle by less
        than ``REAL_OUT``, or closer than ``ROOT_SEP`` to each other.
        """
        n0, nc, ns = self.n
        z0 = self.z[0]
        a1, d1 = self.a1, self.d1
        P = px * px + py * py + pz * pz - a1 * a1 + d1 * d1 - 2.0 * d1 * pz
        rho_n = hypot(nc, ns)
        if rho_n <= 1e-300:
            return None
        lateral = px * px + py * py - z0 * z0
        if lateral < 0.0:  # complex u: roots off the unit circle by ~ this much
            if 2.0 * abs(a1) * sqrt(-lateral) / rho_n < REAL_OUT:
                return None
            return []
        root = 2.0 * abs(a1) * sqrt(lateral)
        phi = atan2(ns, nc)
        out = []
        for u in (P + 2.0 * a1 * a1 + root, P + 2.0 * a1 * a1 - root):
            ratio = (u - n0) / rho_n
            if abs(ratio) > 1.0:  # complex: roots off the unit circle by acosh(|ratio|)
                if abs(ratio) - 1.0 >= REAL_OUT * REAL_OUT / 2:  # acosh(1 + x) ~ sqrt(2 x)
                    continue
                return None
            delta = acos(ratio)
            for th in (phi + delta, phi - delta):
                th = remainder(th, _TAU)
                if abs(th) > pi - 1e-8:  # the general solver sorts by angle in (-pi, pi]
                    return None
                out.append(th)
        out.sort()
        return out if _apart(out) else None

    def _sinusoid_th3(self, px: float, py: float, pz: float) -> list[float] | None:
        """``th3`` of the one equation in ``th3`` (axes 1 and 2 meet or are parallel),
        in the general solver's order, or None (near a double root or the reach edge)."""
        n0, nc, ns = self.n
        z0, zc, zs = self.z
        if self.case == "meet":  # B = P - |g|^2 = 0
            d1 = self.d1
            P = px * px + py * py + pz * pz - self.a1 * self.a1 + d1 * d1 - 2.0 * d1 * pz
            k0, kc, ks = P - n0, -nc, -ns
        else:  # A = pz - d1 - ca1 g_z = 0
            ca1 = self.ca1
            k0, kc, ks = pz - self.d1 - ca1 * z0, -ca1 * zc, -ca1 * zs
        rho = hypot(kc, ks)
        if rho <= 1e-300:
            return None
        ratio = -k0 / rho
        if abs(ratio) > 1.0 + OUT:
            return []
        if abs(ratio) > 1.0 - EDGE:
            return None
        phi, delta = atan2(ks, kc), acos(ratio)
        return [phi + delta, phi - delta]

    # ------------------------------------------------------------------ solve
    def solve(self, T: list[list[float]]) -> tuple[list[float], list[Branch]] | None:
        """Joint values of every solution (wrapped to (-pi, pi]) as one flat list of 6 per
        solution, and the Branch of each; None for the general path (module docstring).

        ``T`` is the validated world pose as nested lists.
        """
        (r00, r01, r02, tx), (r10, r11, r12, ty), (r20, r21, r22, tz) = T[0], T[1], T[2]
        u = self.unit
        tx, ty, tz = tx * u, ty * u, tz * u
        cx, cy, cz = self.c_tcp
        wx = r00 * cx + r01 * cy + r02 * cz + tx
        wy = r10 * cx + r11 * cy + r12 * cz + ty
        wz = r20 * cx + r21 * cy + r22 * cz + tz
        (g00, g01, g02), (g10, g11, g12), (g20, g21, g22) = self.G
        gt = self.Gt
        px = g00 * wx + g01 * wy + g02 * wz + gt[0]
        py = g10 * wx + g11 * wy + g12 * wz + gt[1]
        pz = g20 * wx + g21 * wy + g22 * wz + gt[2]
        rho_p = hypot(px, py)
        if rho_p < self._near_axis1:  # near axis 1: the shoulder singularity
            return None
        # positions: (th2, th3, cos, sin of both, g)
        case = self.case
        g0, gc, gs = self.g0, self.gc, self.gs
        near2 = self._near2
        skew, meet = case == "skew", case == "meet"
        if self.planar:
            roots = self._th3_planar(px, py, pz)
        else:
            roots = self._th3_skew(px, py, pz) if skew else self._sinusoid_th3(px, py, pz)
        if roots is None:
            return None
        d1, a1, ca1, sa1 = self.d1, self.a1, self.ca1, self.sa1
        P = px * px + py * py + pz * pz - a1 * a1 + d1 * d1 - 2.0 * d1 * pz
        positions = []
        for th3 in roots:
            c3, s3 = cos(th3), sin(th3)
            gx = g0[0] + c3 * gc[0] + s3 * gs[0]
            gy = g0[1] + c3 * gc[1] + s3 * gs[1]
            gz = g0[2] + c3 * gc[2] + s3 * gs[2]
            gxy = gx * gx + gy * gy
            if gxy < near2:  # near axis 2 (q2 free on it)
                return None
            if skew:  # th2 from both equations
                X = (P - (gxy + gz * gz)) / (2.0 * a1)
                Y = (pz - d1 - ca1 * gz) / sa1
                sn, cs = gx * Y - gy * X, gx * X + gy * Y
                h = hypot(sn, cs)
                positions.append((atan2(sn, cs), cs / h, sn / h, th3, c3, s3, gx, gy, gz))
                continue
            rho2 = sqrt(gxy)
            if meet:  # gy cos2 + gx sin2 = A / sa1
                ratio = (pz - d1 - ca1 * gz) / sa1 / rho2
                phi = atan2(gx, gy)
            else:  # gx cos2 - gy sin2 = B / (2 a1)
                ratio = (P - (gxy + gz * gz)) / (2.0 * a1) / rho2
                phi = atan2(-gy, gx)
            if abs(ratio) > 1.0 + OUT:
                continue
            if abs(ratio) > 1.0 - EDGE:
                return None
            delta = acos(ratio)
            for th2 in (phi + delta, phi - delta):
                positions.append((th2, cos(th2), sin(th2), th3, c3, s3, gx, gy, gz))
        if not positions:
            return None
        return self._finish(positions, px, py, r00, r01, r02, r10, r11, r12, r20, r21, r22)

    def _finish(self, positions, px, py, r00, r01, r02, r10, r11, r12, r20, r21, r22):
        """Joint 1, the wrist and the labels of every position (see :meth:`solve`)."""
        phi_p = atan2(py, px)
        cols = self._goal_columns(r00, r01, r02, r10, r11, r12, r20, r21, r22)
        if self.orthogonal:
            return self._finish_orthogonal(positions, px, py, phi_p, cols)
        o1, o2, o3, o4, o5, o6 = self.offsets
        rem, tau = remainder, _TAU
        ca3, sa3 = self.x3
        q_out: list[float] = []
        branches: list[Branch] = []
        labels = self.labels
        for th2, c2, s2, th3, c3, s3, gx, gy, gz in positions:
            arm = self._joint1_and_labels(px, py, phi_p, c2, s2, gx, gy, gz)
            if arm is None:
                return None
            th1, c1, s1, front, up = arm
            rw = self._wrist_columns(cols, c1, s1, c2, s2, c3, s3)
            wrist = self._wrist_general(
                [(rw[i], ca3 * rw[i + 1] + sa3 * rw[i + 2], ca3 * rw[i + 2] - sa3 * rw[i + 1])
                 for i in (0, 3, 6)])
            if wrist is None:
                return None
            a1, a2, a3 = rem(th1 - o1, tau), rem(th2 - o2, tau), rem(th3 - o3, tau)
            for th4, th5, th6 in wrist:
                q5 = rem(th5 - o5, tau)
                sq5 = sin(q5)
                if abs(sq5) < LABEL:
                    return None
                q_out += (a1, a2, a3, rem(th4 - o4, tau), q5, rem(th6 - o6, tau))
                branches.append(labels[front][up][sq5 >= 0.0])
        # not max(map(abs, .)): a call of abs per value costs as much as the two passes
        if not q_out or max(q_out) > WRAP_EDGE or min(q_out) < -WRAP_EDGE:
            return None
        return q_out, branches

    def _finish_orthogonal(self, positions, px, py, phi_p, cols):
        """:meth:`_finish` for an orthogonal wrist: joint 1 and the labels by
        :meth:`_joint1_and_labels` (the one place they are decided), :meth:`_wrist_columns`
        and :meth:`_wrist_orthogonal` written out in the loop (the same operations in the
        same order, so the same floats, without their calls and lookups per position)."""
        ca1s, sa1s, ca2, sa2, ca3, sa3, kappa, sigma, kpi = self._ortho
        (x0, y0, z0), (xb, yb, zb) = cols
        o1, o2, o3, o4, o5, o6 = self.offsets
        rem, tau, labels = remainder, _TAU, self.labels
        q_out: list[float] = []
        branches: list[Branch] = []
        for th2, c2, s2, th3, c3, s3, gx, gy, gz in positions:
            arm = self._joint1_and_labels(px, py, phi_p, c2, s2, gx, gy, gz)
            if arm is None:
                return None
            th1, c1, s1, front, up = arm
            # the wrist's columns 0 and 2 (_wrist_columns), then R_w C^T (_wrist_orthogonal)
            x1, y1 = c1 * x0 + s1 * y0, c1 * y0 - s1 * x0
            y2, z2 = ca1s * y1 + sa1s * z0, ca1s * z0 - sa1s * y1
            x3, y3 = c2 * x1 + s2 * y2, c2 * y2 - s2 * x1
            y4, z4 = ca2 * y3 + sa2 * z2, ca2 * z2 - sa2 * y3
            m00, y5 = c3 * x3 + s3 * y4, c3 * y4 - s3 * x3
            x1, y1 = c1 * xb + s1 * yb, c1 * yb - s1 * xb
            y2, z2 = ca1s * y1 + sa1s * zb, ca1s * zb - sa1s * y1
            x3, y3 = c2 * x1 + s2 * y2, c2 * y2 - s2 * x1
            y4, z4b = ca2 * y3 + sa2 * z2, ca2 * z2 - sa2 * y3
            m02, y5b = c3 * x3 + s3 * y4, c3 * y4 - s3 * x3
            m10, m20 = ca3 * y5 + sa3 * z4, ca3 * z4 - sa3 * y5
            m12, m22 = ca3 * y5b + sa3 * z4b, ca3 * z4b - sa3 * y5b
            if kappa < 0:  # C = diag(1, -1, -1)
                m02, m12, m22 = -m02, -m12, -m22
            sw = hypot(m02, m12)
            if sw < NEAR:
                return None
            theta = sigma * atan2(sw, m22)
            phi = atan2(m12, m02)
            cp, sp = m02 / sw, m12 / sw
            psi = kappa * atan2(cp * m10 - sp * m00, m22 * (cp * m00 + sp * m10) - sw * m20)
            a1, a2, a3 = rem(th1 - o1, tau), rem(th2 - o2, tau), rem(th3 - o3, tau)
            by_flip = labels[front][up]
            for th4, th5, th6 in ((phi, -theta, psi), (phi + pi, theta, psi + kpi)):
                q5 = rem(th5 - o5, tau)
                sq5 = sin(q5)
                if abs(sq5) < LABEL:
                    return None
                q_out += (a1, a2, a3, rem(th4 - o4, tau), q5, rem(th6 - o6, tau))
                branches.append(by_flip[sq5 >= 0.0])
        if not q_out or max(q_out) > WRAP_EDGE or min(q_out) < -WRAP_EDGE:
            return None
        return q_out, branches

    def _goal_columns(self, r00, r01, r02, r10, r11, r12, r20, r21, r22):
        """Columns of ``S = G_R R H`` (0 and 2; all three for a non-orthogonal wrist)."""
        (g00, g01, g02), (g10, g11, g12), (g20, g21, g22) = self.G
        Hc = self.Hcols
        cols = []
        for j in ((0, 2) if self.orthogonal else (0, 1, 2)):
            h0, h1, h2 = Hc[j]
            x = r00 * h0 + r01 * h1 + r02 * h2
            y = r10 * h0 + r11 * h1 + r12 * h2
            z = r20 * h0 + r21 * h1 + r22 * h2
            cols.append((g00 * x + g01 * y + g02 * z, g10 * x + g11 * y + g12 * z,
                         g20 * x + g21 * y + g22 * z))
        return cols

    def _joint1_and_labels(self, px, py, phi_p, c2, s2, gx, gy, gz):
        """``(th1, cos th1, sin th1, front, elbow up)`` of one position, or None when a
        label is too near its boundary to be decided the same way as the general path."""
        L, ca1s, sa1s, t1x, t1y, t2x, t2y, ux, uy, label_tol = self._j1
        # joint 1 turns r = M1 Rz(th2) g onto p'
        xp, yp = c2 * gx - s2 * gy, s2 * gx + c2 * gy
        rx, ry = xp + t1x, ca1s * yp - sa1s * gz + t1y
        th1 = phi_p - atan2(ry, rx)
        c1, s1 = cos(th1), sin(th1)
        # labels: front (p' ahead of axis 1 along the turned x axis), elbow up
        fr = px * c1 + py * s1
        if abs(fr) < label_tol:
            return None
        ex, ey = c2 * t2x - s2 * t2y, s2 * t2x + c2 * t2y
        nl = xp * xp + yp * yp
        el = ex * xp + ey * yp
        across = abs(xp * uy - yp * ux)
        span = sqrt(nl) + L
        if across <= SINGULAR_TOL * span:
            hu = ex - el / nl * xp  # h . (1, 0)
            hn = 1.0
        elif across < 1e-7 * span:
            return None
        else:
            hu = ex * ux + ey * uy - el * (xp * ux + yp * uy) / nl
            hn = hypot(ux, uy)
        if abs(hu) < label_tol * hn:
            return None
        return th1, c1, s1, fr >= 0.0, hu > 0.0

    def _wrist_columns(self, cols, c1, s1, c2, s2, c3, s3) -> list[Any]:
        """``R_w``'s columns, flat: Rx(-al3) Rz(-th3) Rx(-al2) Rz(-th2) Rx(-al1) Rz(-th1) S
        (the last Rx(-al3) left to the wrist). Plain arithmetic: floats for one pose, arrays
        of poses for the batch kernel."""
        ca1s, sa1s = self.x1
        ca2, sa2 = self.x2
        rw: list[float] = []
        for x, y, z in cols:
            x1 = c1 * x + s1 * y
            y1 = c1 * y - s1 * x
            y2 = ca1s * y1 + sa1s * z
            z2 = ca1s * z - sa1s * y1
            x3 = c2 * x1 + s2 * y2
            y3 = c2 * y2 - s2 * x1
            y4 = ca2 * y3 + sa2 * z2
            z4 = ca2 * z2 - sa2 * y3
            rw += (c3 * x3 + s3 * y4, c3 * y4 - s3 * x3, z4)
        return rw

    def _wrist_orthogonal(self, rw: list[float]):
        """Both wrist slots of an orthogonal wrist: ZYZ angles of ``R_w C^T``
        (:meth:`Pieper6RSolver._wrist`) from columns 0 and 2; None near the wrist fold."""
        ca3, sa3 = self.x3
        kappa = self.kappa
        m00, y5, z4, m02, y5b, z4b = rw
        m10, m20 = ca3 * y5 + sa3 * z4, ca3 * z4 - sa3 * y5
        m12, m22 = ca3 * y5b + sa3 * z4b, ca3 * z4b - sa3 * y5b
        if kappa < 0:  # C = diag(1, -1, -1)
            m02, m12, m22 = -m02, -m12, -m22
        sw = hypot(m02, m12)
        if sw < NEAR:
            return None
        theta = self.sigma * atan2(sw, m22)
        phi = atan2(m12, m02)
        cp, sp = m02 / sw, m12 / sw
        psi = kappa * atan2(cp * m10 - sp * m00, m22 * (cp * m00 + sp * m10) - sw * m20)
        return ((phi, -theta, psi), (phi + pi, theta, psi + kappa * pi))

    def _wrist_general(self, rw):
        """Both wrist slots of a wrist with any twists (:meth:`Pieper6RSolver._wrist`);
        ``rw`` holds the three columns of ``R_w``. ``[]``: the orientation is out of reach."""
        (w00, w10, w20), (w01, w11, w21), (w02, w12, w22) = rw
        sb1, cb1, sb2, cb2 = self.wb
        c5 = (cb1 * cb2 - w22) / (sb1 * sb2)
        if abs(c5) > 1.0 + OUT:
            return []
        s5 = 1.0 - c5 * c5
        if s5 < NEAR * NEAR:  # q5 near 0 or pi: a fold, or axes 4 and 6 in line
            return None
        s5 = sqrt(s5)
        c1b, s1b, c2b, s2b = self.wbx
        phi_w = atan2(w12, w02)
        out = []
        for s in (s5, -s5):
            ax, ay = sb2 * s, -cb1 * sb2 * c5 - sb1 * cb2
            if hypot(ax, ay) < NEAR:
                return None
            th4 = phi_w - atan2(ay, ax)
            c4, s4 = cos(th4), sin(th4)
            (r00, r10), (r01, r11) = _wrist_rest(((w00, w10, w20), (w01, w11, w21)), (c4, s4),
                                                (c1b, s1b), (c5, s), (c2b, s2b))
            out.append((th4, atan2(s, c5), atan2(r10 - r01, r00 + r11)))
        return out


def _wrist_rest(columns: Sequence[tuple[Any, Any, Any]], turn4: tuple[Any, Any],
                twist1: tuple[Any, Any], turn5: tuple[Any, Any],
                twist2: tuple[Any, Any]) -> list[tuple[Any, Any]]:
    """Rows 0 and 1 of columns 0 and 1 of ``Rx(-b2) Rz(-th5) Rx(-b1) Rz(-th4) R_w``: what is
    left of the wrist's rotation once joints 4 and 5 are undone, from which joint 6 is read.

    Plain arithmetic, so one code serves the one-pose kernel (floats) and the batch kernel
    (arrays of poses alike).

    Parameters
    ----------
    columns : two tuples (x, y, z)
        Columns 0 and 1 of the wrist rotation ``R_w`` (floats, or arrays of shape (n,)).
    turn4, twist1, turn5, twist2 : tuple (cos, sin)
        Joint 4's angle, the twist between axes 4 and 5, joint 5's angle, the twist
        between axes 5 and 6.

    Returns
    -------
    list of two tuples (r0j, r1j)
        Rows 0 and 1 of columns 0 and 1 of the rest rotation.
    """
    c4, s4 = turn4
    c1b, s1b = twist1
    c5, s5 = turn5
    c2b, s2b = twist2
    rest: list[tuple[Any, Any]] = []
    for x, y, z in columns:
        x1 = c4 * x + s4 * y
        y1 = c4 * y - s4 * x
        y2 = c1b * y1 + s1b * z
        z2 = c1b * z - s1b * y1
        x3 = c5 * x1 + s5 * y2
        y3 = c5 * y2 - s5 * x1
        rest.append((x3, c2b * y3 + s2b * z2))
    return rest


def _apart(angles: list[float]) -> bool:
    """Whether sorted angles in (-pi, pi] are at least ``ROOT_SEP`` apart around the circle."""
    if any(b - a < ROOT_SEP for a, b in zip(angles[:-1], angles[1:], strict=True)):
        return False
    return len(angles) < 2 or angles[0] + _TAU - angles[-1] >= ROOT_SEP


def _quartic(A: complex, B: complex, C: complex, D: complex) -> list[complex] | None:
    """The four roots of ``z^4 + A z^3 + B z^2 + C z + D`` (Ferrari), each polished by one
    Newton step; None when the polish does not confirm them (a multiple root or worse).

    Every product has its complex operand first: ``float * complex`` takes CPython's slow
    path (float's multiply declines, then complex's reflected one), 5x the cost.
    """
    a = A * 0.25
    aa = a * a
    p = B - aa * 6.0
    q = C - B * a * 2.0 + aa * a * 8.0
    r = D - C * a + B * aa - aa * aa * 3.0
    # resolvent cubic m^3 + p m^2 + (p^2/4 - r) m - q^2/8 = 0, depressed with m = x - p/3
    pp = p * p
    P = pp / -12.0 - r
    Q = pp * p / -108.0 + p * r / 3.0 - q * q / 8.0
    disc = csqrt(Q * Q / 4.0 + P * P * P / 27.0)
    u3 = Q / -2.0 + disc
    u3b = Q / -2.0 - disc
    if abs(u3b) > abs(u3):
        u3 = u3b
    p3 = p / 3.0
    if u3 == 0:
        m = -p3
    else:
        u = u3 ** (1.0 / 3.0)
        m = u - P / (u * 3.0) - p3
        for w in _CUBE_ROOTS_OF_1:
            uw = u * w
            m2 = uw - P / (uw * 3.0) - p3
            if abs(m2) > abs(m):
                m = m2
    if m == 0:
        return None
    s = csqrt(m * 2.0)
    qs = q / (s * 2.0)
    half = p * 0.5 + m
    roots: list[complex] = []
    for b, c in ((-s, half + qs), (s, half - qs)):  # y^2 + b y + c
        d = csqrt(b * b - c * 4.0)
        if (b.conjugate() * d).real < 0:
            d = -d
        t = (b + d) * -0.5
        if t == 0:
            return None
        roots += (t - a, c / t - a)
    out = []
    total = 0j
    for z in roots:
        f = (((z + A) * z + B) * z + C) * z + D
        df = ((z * 4.0 + A * 3.0) * z + B * 2.0) * z + C
        if df == 0:
            return None
        step = f / df
        if abs(step) > 1e-6 * (1.0 + abs(z)):
            return None
        z -= step
        out.append(z)
        total += z
    if abs(total + A) > 1e-9 * (abs(A) + 4.0 * max(map(abs, out))):
        return None  # two roots found twice, one lost: not four distinct roots
    return out
