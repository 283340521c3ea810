"""Closed-form IK of a 6R arm with three consecutive parallel axes (a UR arm), from its table.

With the arm written as ``W = Rz(th1) M1 Rz(th2) M2 Rz(th3) M3 Rz(th4) M4 Rz(th5) M5 Rz(th6)``
(``W = M0^-1 T_0_6 M6^-1``, see :mod:`rikin.ik.pieper`), axes 2, 3 and 4 are parallel when
``M2`` and ``M3`` turn the z axis into +-z. Call ``n = Rz(th1) u`` their common direction
(``u`` the z axis of ``M1``). Joints 2-4 turn everything after them about ``n``, so along
``n`` nothing they do shows:

* (A) ``n . z6`` (axis 6 of the target) equals what joint 5 alone makes of it:
  ``A0 + Ac cos th5 + As sin th5``;
* (B) ``n . p`` (a point of axis 6) minus the fixed offsets along ``n`` equals
  ``B0 + Bc cos th5 + Bs sin th5``.

Both left sides are sinusoids in ``th1``. Where axis 6's point stays in one plane as joint
5 turns (a UR: ``Bc = Bs = 0``), a combination of (A) and (B) is free of ``th5``: a
sinusoid in ``th1`` (2 roots), then (A) gives ``th5`` (2 roots). Otherwise solving (A), (B)
for ``cos th5, sin th5`` and asking ``cos^2 + sin^2 = 1`` leaves a trigonometric quartic in
``th1`` (4 roots, one ``th5`` each). Then ``th6`` turns axis 2's direction into place, and
joints 2-4 are a planar 3R: two elbows. Up to 8 solutions in 8 slots; every one polished
on the whole pose (Gauss-Newton) and kept only if it reaches the target.

Axes 3, 4, 5 parallel is the same problem for the arm seen from its flange (the chain
reversed), which the solver builds from the table.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import FloatArray
from ..dh import check_arm
from ..errors import InputError
from ..tolerances import SINGULAR_TOL
from .base import RawSolutions, Singularity, TargetKind
from .kernels import wrap_in_place
from .parallel3_kernel import ParallelKernel, single_kernel, solve_batch
from .pieper import (
    ACCEPT_TOL,
    DIRECTION_FLOOR,
    GEOMETRY_TOL,
    ChainModel,
    ChainPolish,
    _rz4,
    _solve_sinusoid,
    _trig2_roots,
    _unit_model,
    _units,
    chain_model,
    six_revolute_reason,
)
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

__all__ = ["recognise", "reversed_model", "ParallelAxesSolver"]

_X = np.diag([1.0, -1.0, -1.0, 1.0])  # Rx(pi): Rz(-t) = X Rz(t) X

SHOULDER = Singularity(
    "axis 6 and the target leave joint 1 free (shoulder singularity): q1 is free", (1,)
)
ELBOW = Singularity(
    "the elbow is stretched or folded: joints 2-4 at the edge of their reach, two "
    "elbows coincide", (),
)
WRIST = Singularity(
    "wrist singularity: axis 6 is parallel to the three parallel axes, so joint 6 and "
    "joints 2-4 turn about one direction", (6,),
)


def reversed_model(model: ChainModel) -> ChainModel:
    """The chain seen from its flange: ``T^-1 = M'0 Rz(th6) M'1 ... Rz(th1) M'6``.

    Joint ``i`` of the result is joint ``7 - i`` of ``model``, with the same angle
    (``Rz(-t) = Rx(pi) Rz(t) Rx(pi)``), so its ``offsets`` are reversed too.
    """
    M = model.M
    inv = [np.linalg.inv(m) for m in M]
    out = [inv[6] @ _X] + [_X @ inv[6 - i] @ _X for i in range(1, 6)] + [_X @ inv[0]]
    return ChainModel(np.stack(out), model.offsets[::-1].copy(), model.scale)


def _parallel_234(model: ChainModel) -> str | None:
    """None when axes 2, 3, 4 of ``model`` are parallel and the closed form applies, else
    the reason."""
    tol = GEOMETRY_TOL * model.scale
    M = model.M
    if not (abs(abs(M[2, 2, 2]) - 1.0) <= GEOMETRY_TOL and abs(abs(M[3, 2, 2]) - 1.0)
            <= GEOMETRY_TOL):
        return "not parallel"
    if abs(abs(M[1, 2, 2]) - 1.0) <= GEOMETRY_TOL:
        return "axis 1 is parallel to them too, so the arm cannot move along that direction"
    s2 = math.copysign(1.0, M[2, 2, 2])
    if math.hypot(M[2, 0, 3], M[2, 1, 3]) <= tol or math.hypot(M[3, 0, 3], s2 * M[3, 1, 3]) <= tol:
        return "two of them are the same line, so two joints do the same motion"
    K = _joint5_terms(M, s2 * math.copysign(1.0, M[3, 2, 2]))[1]
    if np.abs(K).max() <= GEOMETRY_TOL:
        return "axis 5 is parallel to them too, so joint 5 cannot tilt axis 6 out of their plane"
    return None


def _joint5_terms(M: FloatArray, sigma: float) -> tuple[FloatArray, FloatArray]:
    """``(c0, K)``: the right sides of (A) and (B) are ``c0 + K @ (cos th5, sin th5)``."""
    r = M[4, 2, :3]  # n . R_F4 R_M4 x = sigma * r . x

    def trig(w: FloatArray) -> tuple[float, float, float]:  # r . Rz(th5) w
        return (float(r[2] * w[2]), float(r[0] * w[0] + r[1] * w[1]),
                float(r[1] * w[0] - r[0] * w[1]))

    a0, ac, as_ = trig(M[5, :3, 2])
    b0, bc, bs = trig(M[5, :3, 3])
    c0 = sigma * np.array([a0, b0 + M[4, 2, 3]])
    return c0, sigma * np.array([[ac, as_], [bc, bs]])


def recognise(arm: SerialArm) -> tuple[str, str]:
    """``(family, "")`` in words when ``arm`` has three consecutive parallel axes (2-4 or
    3-5) and the closed form applies, else ``("", reason)``."""
    check_arm(arm)
    not_6r = six_revolute_reason(arm)
    if not_6r:
        return "", not_6r
    model = chain_model(arm)
    for first, m in ((2, model), (3, reversed_model(model))):
        why = _parallel_234(m)
        if why is None:
            axes = f"({first}, {first + 1}, {first + 2})"
            return f"three parallel axes {axes}, like a UR arm: up to 8 solutions", ""
        if why != "not parallel":
            return "", f"axes {first}, {first + 1}, {first + 2} are parallel but {why}"
    return "", "no three consecutive axes are parallel (2-4 or 3-5)"


class ParallelAxesSolver(ChainPolish):
    """Closed-form IK of a 6R arm with three consecutive parallel axes (a UR arm), from its
    DH table: up to 8 solutions."""

    target_kind: TargetKind = "pose"
    labels_optional = True
    singularities = {"shoulder": SHOULDER, "elbow": ELBOW, "wrist": WRIST}

    def __init__(self, arm: SerialArm) -> None:
        check_arm(arm)
        family, reason = recognise(arm)
        if reason:
            raise InputError(f"{arm.name}: {reason}")
        self.family = family
        model, self.unit = _unit_model(chain_model(arm))
        self.reverse = _parallel_234(model) is not None
        self.offsets = model.offsets
        self.model = reversed_model(model) if self.reverse else model
        M = self.model.M
        #: the wrist label is the slot's: joint 5's root ``phi + d`` (no-flip) or ``phi - d``
        #: (flip), ``d`` in [0, pi], as the kernel names it (the sign of sin q5 on a UR's
        #: table; with a turned joint 5 or twisted axes that sign does not tell them apart)
        self.wrist_middle: int | None = None
        self.wrist_from_slot = True
        self.M0_inv, self.M6_inv = np.linalg.inv(M[0]), np.linalg.inv(M[6])
        self.M1_inv, self.M4_inv, self.M5_inv = (np.linalg.inv(M[i]) for i in (1, 4, 5))
        self.u = M[1, :3, 2]
        self.s2 = math.copysign(1.0, M[2, 2, 2])
        self.sigma = self.s2 * math.copysign(1.0, M[3, 2, 2])
        c0, K = _joint5_terms(M, self.sigma)
        self.c0 = c0 + np.array([0.0, self.u @ M[1, :3, 3] + M[2, 2, 3] + self.s2 * M[3, 2, 3]])
        self.K = K
        U, sv, _ = np.linalg.svd(K)
        self.rank1 = bool(sv[1] <= GEOMETRY_TOL * sv[0])
        self.lam = U[:, 1]  # lam . K = 0 where K has rank 1
        self.row = int(np.argmax(np.abs(K).sum(axis=1)))
        #: (A) alone fixes joint 5 as ``cos(th5 - phi) = n . z6`` (a UR: axes 5 and 6 at
        #: right angles, joint 5 tilting axis 6 off the parallel axes by th5 itself). Then
        #: th5 - phi is the angle between n and axis 6, read as atan2 of its sine and
        #: cosine: acos of the cosine alone loses half the digits where it is near 0 or pi
        #: (at the wrist singularity), and joint 6, read from that tilt, all of them.
        self.tilt_row = bool(self.rank1 and self.row == 0 and abs(c0[0]) <= 1e-15
                             and abs(math.hypot(*K[0]) - 1.0) <= 1e-15)
        self.K_inv: Any = np.zeros((2, 2)) if self.rank1 else np.linalg.inv(K)
        self.gamma2 = math.atan2(M[2, 1, 0], M[2, 0, 0])
        self.a = M[2, :2, 3].copy()
        self.b = np.array([M[3, 0, 3], self.s2 * M[3, 1, 3]])
        self.slots = tuple(
            Branch(sh, el, wr) for sh in ("front", "back") for wr in ("no-flip", "flip")
            for el in ("up", "down")
        )
        if not self.rank1:  # joints 1 and 5 from a quartic: its roots, not a shoulder and
            # a wrist, tell the four pairs apart; joints 2-4 still have an up and down elbow
            self.root_joint: int | None = 5 if self.reverse else 0
            self.root_grouped = True
            self.slots = tuple(Branch(None, b.elbow, None) for b in self.slots)

    def check(self, arm: SerialArm) -> None:  # noqa: D102 - the Solver protocol
        _ = arm

    # -------------------------------------------------------------- joints 1 and 5
    def _sides(self, W: FloatArray) -> FloatArray:
        """(A) and (B) minus their constants, as ``(N, 2, 3)`` coefficients of
        ``(1, cos th1, sin th1)`` (left sides) for the targets ``W (N, 4, 4)``."""
        u = self.u
        out = np.empty((W.shape[0], 2, 3))
        for k, col in enumerate((2, 3)):
            v = W[:, :3, col]
            out[:, k, 0] = u[2] * v[:, 2] - self.c0[k]
            out[:, k, 1] = u[0] * v[:, 0] + u[1] * v[:, 1]
            out[:, k, 2] = u[0] * v[:, 1] - u[1] * v[:, 0]
        return out

    def _joints_1_5(
        self, W: FloatArray, h1: float
    ) -> tuple[FloatArray, FloatArray, np.ndarray, np.ndarray]:
        """``th1, th5 (N, 4)``, which pairs exist ``(N, 4)``, and the shoulder-singular poses."""
        S = self._sides(W)
        N = W.shape[0]
        if self.rank1:
            e = self.lam @ S  # (N, 3): e0 + ec cos th1 + es sin th1 = 0
            xp, xm, ok1, free = _solve_sinusoid(e[:, 1], e[:, 2], -e[:, 0])
            tiny = np.hypot(e[:, 1], e[:, 2]) <= SINGULAR_TOL * (1 + np.abs(e[:, 0]))
            free = free | (tiny & (np.abs(e[:, 0]) <= SINGULAR_TOL))
            xp, xm = np.where(free, h1, xp), np.where(free, h1, xm)
            ok1 = ok1 | free
            t1 = np.stack([xp, xm], axis=1)  # (N, 2)
            side = S[:, self.row]
            val = side[:, None, 0] + side[:, None, 1] * np.cos(t1) + side[:, None, 2] * np.sin(t1)
            kc, ks = self.K[self.row]
            yp, ym, ok5, _ = _solve_sinusoid(np.full_like(val, kc), np.full_like(val, ks), val)
            if self.tilt_row:  # (A) is cos(th5 - phi) = n . z6: the angle from both parts
                n = _rz4(t1)[..., :3, :3] @ self.u  # (N, 2, 3)
                a = n @ W[:, :3, :3]  # R_W^T n, a product per pose
                half = np.arctan2(np.hypot(a[..., 0], a[..., 1]), a[..., 2])
                phi = math.atan2(ks, kc)
                yp, ym, ok5 = phi + half, phi - half, np.ones_like(ok5)
            th1 = np.repeat(t1, 2, axis=1)
            th5 = np.stack([yp, ym], axis=2).reshape(N, 4)
            ok = np.repeat(ok1[:, None], 4, axis=1) & np.repeat(ok5, 2, axis=1)
            return th1, th5, ok, free
        ang = 2 * np.pi * np.arange(5) / 5
        trig = np.stack([np.ones(5), np.cos(ang), np.sin(ang)])  # (3, 5)
        cs = self.K_inv @ (S @ trig)  # (N, 2, 5): cos, sin of th5 (products per pose)
        th1, real = _trig2_roots((cs * cs).sum(axis=1) - 1.0)
        basis = np.stack([np.ones_like(th1), np.cos(th1), np.sin(th1)], axis=-1)  # (N, 4, 3)
        c5s5 = np.swapaxes(self.K_inv @ S @ np.swapaxes(basis, -1, -2), -1, -2)
        th5 = np.arctan2(c5s5[..., 1], c5s5[..., 0])
        return th1, th5, real, np.zeros(N, dtype=bool)

    # -------------------------------------------------------------- the rest
    def _joint6(self, W: FloatArray, th1: FloatArray, th5: FloatArray, h6: float,
                hinted: bool = False) -> tuple[FloatArray, np.ndarray, np.ndarray]:
        """``th6 (N, 4)`` turning axis 2's direction into place, where it is free (taken
        from ``h6``), and where the wrist is flagged singular.

        With axis 6 within ``1e3 * SINGULAR_TOL`` of the parallel axes' direction the pose
        is flagged; joint 6 is taken as free only within ``SINGULAR_TOL`` of it when the
        caller gave a hint, else within ``DIRECTION_FLOOR`` (rounding): 1e-7 off it, joint 6
        is still fixed by the pose to 1e-9 rad, and any other value moves what joints 2-4
        must reach (a pose 1e-7 rad off the singularity was refused as unreachable)."""
        n = _rz4(th1)[..., :3, :3] @ self.u  # (N, 4, 3)
        a = n @ W[:, :3, :3]  # R_W^T n, a product per pose
        r = self.model.M[4, 2, :3]
        R5t = self.model.M[5, :3, :3].T
        turned = np.swapaxes(_rz4(th5)[..., :3, :3], -1, -2) @ r
        b = self.sigma * (R5t @ turned[..., None])[..., 0]
        off_axis = np.hypot(a[..., 0], a[..., 1])
        free = off_axis <= (SINGULAR_TOL if hinted else DIRECTION_FLOOR)
        th6 = np.arctan2(b[..., 1], b[..., 0]) - np.arctan2(a[..., 1], a[..., 0])
        return np.where(free, h6, th6), free, off_axis <= 1e3 * SINGULAR_TOL

    def _reachable_th6(self, W: FloatArray, th1: FloatArray, th5: FloatArray,
                       th6: FloatArray) -> FloatArray:
        """A free joint 6 ``(N, 4)`` that joints 2-4 can follow: nearest ``th6`` among those
        that put axis 4 at the middle of their reach (or as near it as any does).

        At the wrist singularity axes 2-4 and 6 are parallel and joint 6 swings the point
        joints 2-4 must reach around a circle in their plane: a value the hint (or 0)
        gives may leave it out of their reach while others do not."""
        f = [(self._V(W, th1, th5, np.full_like(th1, t))[..., :2, 3] ** 2).sum(-1)
             for t in (0.0, np.pi / 2, np.pi)]  # |P|^2 = k0 + kc cos th6 + ks sin th6
        k0 = (f[0] + f[2]) / 2
        kc, ks = (f[0] - f[2]) / 2, f[1] - k0
        mid = self.a @ self.a + self.b @ self.b
        xp, xm, ok, _ = _solve_sinusoid(kc, ks, np.broadcast_to(mid - k0, kc.shape))
        nearer = np.abs(wrap_in_place(xp - th6)) <= np.abs(wrap_in_place(xm - th6))
        phi = np.arctan2(ks, kc)
        return np.where(ok, np.where(nearer, xp, xm), np.where(mid > k0, phi, phi + np.pi))

    def _V(self, W: FloatArray, th1: FloatArray, th5: FloatArray, th6: FloatArray
           ) -> FloatArray:
        """``V = Rz(th2) M2 Rz(th3) M3 Rz(th4) (N, 4, 4, 4)``, what joints 2-4 must make."""
        return (self.M1_inv @ _rz4(-th1) @ W[:, None] @ _rz4(-th6) @ self.M5_inv @ _rz4(-th5)
                @ self.M4_inv)

    def _planar(self, W: FloatArray, th1: FloatArray, th5: FloatArray, th6: FloatArray
                ) -> tuple[FloatArray, np.ndarray, np.ndarray]:
        """Joints 2-4 ``(N, 4, 2, 3)`` (two elbows), which exist, and the stretched ones."""
        M = self.model.M
        V = self._V(W, th1, th5, th6)
        P = V[..., :2, 3]
        a, b = self.a, self.b
        rhs = ((P * P).sum(-1) - a @ a - b @ b) / 2
        psi_p, psi_m, ok, _ = _solve_sinusoid(
            np.full_like(rhs, a @ b), np.full_like(rhs, a[1] * b[0] - a[0] * b[1]), rhs
        )
        psi = np.stack([psi_p, psi_m], axis=-1)  # (N, 4, 2)
        stretched = np.abs(psi_p - psi_m) <= 1e-7
        th3 = self.s2 * (psi - self.gamma2)
        c, s = np.cos(psi), np.sin(psi)
        ex = a[0] + c * b[0] - s * b[1]
        ey = a[1] + s * b[0] + c * b[1]
        th2 = np.arctan2(P[..., None, 1], P[..., None, 0]) - np.arctan2(ey, ex)
        R23 = (_rz4(th2) @ M[2] @ _rz4(th3) @ M[3])[..., :3, :3]
        R4 = np.swapaxes(R23, -1, -2) @ V[..., None, :3, :3]
        th4 = np.arctan2(R4[..., 1, 0], R4[..., 0, 0])
        return np.stack([th2, th3, th4], axis=-1), ok, stretched

    def _closed_form(
        self, W: FloatArray, h1: float, h6: float, hinted: bool = False
    ) -> tuple[FloatArray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Every closed-form solution ``th (N, 8, 6)`` of ``W (N, 4, 4)``, which exist, and
        the singular masks (shoulder per pose, elbow and wrist per slot)."""
        N = W.shape[0]
        th1, th5, ok15, free1 = self._joints_1_5(W, h1)
        th6, free6, flag6 = self._joint6(W, th1, th5, h6, hinted)
        th234, ok234, stretched = self._planar(W, th1, th5, th6)
        # joint 6 free (or nearly, where rounding picks it) that joints 2-4 cannot follow;
        # the polish and the FK check then say whether the slot holds a solution
        redo = flag6 & ok15 & ~ok234
        if redo.any():
            th6 = np.where(redo, self._reachable_th6(W, th1, th5, th6), th6)
            th234, ok234, stretched = self._planar(W, th1, th5, th6)
        th = np.empty((N, 4, 2, 6))
        th[..., 0] = th1[..., None]
        th[..., 1:4] = th234
        th[..., 4] = th5[..., None]
        th[..., 5] = th6[..., None]
        valid = np.repeat((ok15 & ok234)[..., None], 2, axis=-1)
        wrist = np.repeat(flag6, 2, axis=1)
        return (th.reshape(N, 8, 6), valid.reshape(N, 8), free1,
                np.repeat(stretched, 2, axis=1), wrist)

    def _to_chain(self, T_0_n: FloatArray) -> FloatArray:
        """Flange poses in the solver's units and chain (reversed: inverted), ``W (N, 4, 4)``."""
        T = np.array(T_0_n, dtype=float)
        T[..., :3, 3] *= self.unit
        if self.reverse:
            T = np.linalg.inv(T)
        return self.M0_inv @ T @ self.M6_inv

    def _hints(self, hint: FloatArray | None) -> tuple[float, float, bool]:
        """The values of the chain's joints 1 and 6 (th) to take where they are free, and
        whether the caller gave them."""
        if hint is None:
            return 0.0, 0.0, False
        th = np.asarray(hint, dtype=float) + self.offsets
        if self.reverse:
            th = th[::-1]
        return float(th[0]), float(th[5]), True

    def solve(
        self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None, labels: bool = True
    ) -> RawSolutions:
        """All solutions of N flange poses ``T_0_n (N, 4, 4)``; 8 slots."""
        W = self._to_chain(T_0_n)
        h1, h6, hinted = self._hints(hint)
        th, valid, shoulder, elbow, wrist = self._closed_form(W, h1, h6, hinted)
        goal = self.model.M[0] @ W @ self.model.M[6]  # the chain's own flange pose
        goal = np.broadcast_to(goal[:, None], th.shape[:-1] + (4, 4))
        th = np.where(valid[..., None], th, 0.0)
        res = np.full(valid.shape, np.inf)
        th[valid], T_valid = self._polish(th[valid], goal[valid], np.zeros(int(valid.sum()), bool))
        res[valid] = self._residual_of(T_valid, goal[valid])
        valid &= res <= ACCEPT_TOL
        front = up = None
        if labels:
            front, up = self._labels(np.where(valid[..., None], th, 0.0))
            if not self.rank1:
                front = None  # named by the quartic's roots (see __init__)
        if self.reverse:
            th = th[..., ::-1]
        q = th - self.offsets
        q[~valid] = np.nan
        return RawSolutions(
            q=q, valid=valid, slots=self.slots, elbow_up=up, shoulder_front=front,
            singular={
                "shoulder": np.repeat(shoulder[:, None], 8, axis=1) & valid,
                "elbow": elbow & valid,
                "wrist": wrist & valid,
            },
        )

    def single_kernel(self, arm: SerialArm) -> ParallelKernel | None:
        """The plain-float kernel for one regular pose (:mod:`rikin.ik.parallel3_kernel`),
        or None; :func:`rikin.ik.api.solve` looks it up once per arm."""
        return single_kernel(self, arm)

    def batch_kernel(self, arm: SerialArm) -> ParallelBatchKernel:
        """The batch path's kernel (:func:`rikin.ik.api.solve_batch` looks it up)."""
        return ParallelBatchKernel(self, arm)

    def label_rows(self, q: FloatArray) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Shoulder front (None without a rank-1 wrist: named by roots) and elbow up
        ``(m,)`` of joint rows ``q (m, 6)`` (the table's values), as :meth:`solve` labels
        its solutions (:meth:`_labels`)."""
        th = q + self.offsets
        front, up = self._labels((th[:, ::-1] if self.reverse else th)[None])
        return (front[0] if self.rank1 else None), up[0]

    def _labels(self, th: FloatArray) -> tuple[np.ndarray, np.ndarray]:
        """Shoulder front (axis 6 ahead of axis 1, seen across the parallel axes) and elbow
        up (axis 3 above the line from axis 2 to axis 4, seen along them, towards +axis 1),
        ``(N, 8)`` each, of the chain's joints ``th (N, 8, 6)``."""
        _, z, o = self._fk_frames(th)
        n = z[..., 1, :]
        # ahead: axis 6 lies on the side of axis 1 that n x z1 points to (joint 1 alone
        # decides it: the two shoulders of a UR put it on opposite sides)
        front = ((o[..., 5, :] - o[..., 0, :]) * np.cross(n, z[..., 0, :])).sum(-1) >= 0

        def flat(x: FloatArray) -> FloatArray:
            return x - (x * n).sum(-1, keepdims=True) * n

        line, e, up_dir = flat(o[..., 3, :] - o[..., 1, :]), flat(o[..., 2, :] - o[..., 1, :]), \
            flat(z[..., 0, :])
        nl = np.maximum((line * line).sum(-1, keepdims=True), 1e-300)
        h = e - (e * line).sum(-1, keepdims=True) / nl * line
        if np.abs(up_dir).max() <= GEOMETRY_TOL:
            up_dir = np.cross(n, line)
        return front, (h * up_dir).sum(-1) > 0

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        """Why one flange pose has no solution, and by how much (length units, or nan)."""
        W = self._to_chain(T_0_n[None])
        h1, h6, _ = self._hints(None)
        th1, th5, ok15, _ = self._joints_1_5(W, h1)
        if not ok15.any():
            return (
                "no turn of joints 1 and 5 puts axis 6 where the target wants it: the tool's "
                "tilt against the parallel axes and its offset along them do not fit",
                float("nan"),
            )
        th6 = self._joint6(W, th1, th5, h6)[0]
        V = self._V(W, th1, th5, th6)
        dist = np.linalg.norm(V[..., :2, 3], axis=-1)[ok15]
        la, lb = float(np.linalg.norm(self.a)), float(np.linalg.norm(self.b))
        gap = np.maximum(dist - (la + lb), abs(la - lb) - dist)
        excess = float(gap.min()) / self.unit
        return (
            f"joints 2-4 (the parallel axes) cannot span the distance: it is "
            f"{excess:.4g}{_units(arm)} beyond what they reach",
            excess,
        )


class ParallelBatchKernel:
    """:meth:`ParallelAxesSolver.solve` for a batch, without polish or labels: the closed
    form, then an FK check of every slot. A pose with a slot that misses its target by more
    than ``ACCEPT_TOL``, or at a singularity, is handed back as suspect, and the general
    path (polish, flags) solves it."""

    def __init__(self, solver: ParallelAxesSolver, arm: SerialArm) -> None:
        self.solver = solver
        self.slots = solver.slots
        self.base_inv = np.linalg.inv(arm.base)
        self.tool_inv = np.linalg.inv(arm.tool)
        #: the plain-float kernel's closed form on arrays, for the arms it takes
        self.fast = single_kernel(solver, arm)

    def solve(self, X: FloatArray) -> tuple[FloatArray, np.ndarray, np.ndarray]:
        """Poses ``X (4, 4, n)`` (world frame) -> ``q (8, 6, n)`` wrapped (NaN where no
        solution), ``valid (8, n)`` and ``suspect (n,)``."""
        if self.fast is not None:
            return solve_batch(self.fast, X)
        sv = self.solver
        T = self.base_inv @ X.transpose(2, 0, 1) @ self.tool_inv
        W = sv._to_chain(T)
        th, valid, shoulder, elbow, wrist = sv._closed_form(W, 0.0, 0.0)
        goal = sv.model.M[0] @ W @ sv.model.M[6]
        th = np.where(valid[..., None], th, 0.0)
        F = sv._fk_frames(th)[0]
        err = sv._residual_of(F, goal[:, None])
        suspect = shoulder | ((elbow | wrist) & valid).any(axis=1)
        suspect |= (valid & ~(err <= ACCEPT_TOL)).any(axis=1)
        if sv.reverse:
            th = th[..., ::-1]
        q = wrap_in_place(th - sv.offsets)
        q[~valid] = np.nan
        return q.transpose(1, 2, 0), valid.T, suspect
