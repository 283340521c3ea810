"""Kinematic decoupling (desacople cinemático) of a 6R arm with a spherical wrist.

The eight steps of Aula 10, vectorised over N poses:

1. wrist centre ``p_w = T_0_6 @ w_6`` (for the Aula 10 arm ``p_w = p - 20 z_6``);
2. joints 1-3 put the wrist centre there (:mod:`rikin.ik.anthropomorphic`, 4 ways);
3. ``R_0_3`` from the DH table at those joints;
4. its inverse ``R_3_0 = R_0_3^T``;
5. ``R_3_6 = R_0_3^T R_0_6`` (numeric);
6. the same matrix in terms of q4, q5, q6 (symbolic, :mod:`rikin.symbolic`);
7. equating them: after removing the constant twists, ``R_3_6`` is a ZYZ
   rotation ``Rz(q4 + o4) Ry(-s (q5 + o5)) Rz(q6 + o6)``, solved both ways
   (no-flip and flip);
8. check by FK (done for every solution by :func:`rikin.ik.solve`).

Eight slots: arm slot ``a`` (see ``ARM_SLOTS``) times wrist slot ``b`` -> ``2 a + b``.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from math import atan2, cos, hypot, pi, remainder, sin, sqrt

import numpy as np

from .._validate import FloatArray, as_pose, clean_pose
from ..dh import SerialArm, link_transform
from ..errors import InputError, UnreachableError
from ..tolerances import REACH_TOL, SINGULAR_TOL
from ..transforms import _inv_transform, _rot
from .anthropomorphic import (
    ARM_SLOTS,
    ELBOW,
    FOLD,
    SHOULDER,
    RRRGeometry,
    check_rrr_geometry,
    explain_rrr,
    position_rrr,
    rrr_gap,
)
from .api import ClosedForm
from .base import RawSolutions, Singularity
from .kernels import (
    Mat3,
    const_matmul,
    lincomb,
    matmul_const,
    rz_inverse_times,
    snap_exact,
    spherical_wrist,
    two_link_parts,
    wrap_in_place,
)
from .reach import nearest_reachable, rounding_note
from .result import Branch

WRIST = Singularity(
    "wrist singularity: q5 is 0 or pi, axes 4 and 6 line up, so only q4 + q6 (or q4 - q6) is fixed",
    (4, 6),
    drop_flip=True,
)


def _rx(alpha: float) -> FloatArray:
    return _rot(np.float64(alpha), 0, "alpha")


@dataclass(frozen=True)
class WristModel:
    """Constants of a spherical wrist:
    ``M = pre^T R_3_6 post^T = Rz(q4+o4) Ry(-s(q5+o5)) Rz(q6+o6)``."""

    pre: FloatArray  # (3, 3)
    post: FloatArray  # (3, 3)
    s: float  # sin of the middle twist, +1 or -1
    offsets: tuple[float, float, float]
    centre: FloatArray  # (3,) wrist centre in the last wrist frame's coordinates


def wrist_model(arm: SerialArm, first: int) -> WristModel:
    """Read the spherical-wrist constants of joints ``first``..``first+2`` (0-based) from the table.

    Raises InputError when the three axes do not meet in one point.
    """
    l4, l5, l6 = arm.links[first : first + 3]
    fl = [float(v) for v in (l4.a, l5.a, l6.a, l4.alpha, l5.alpha, l6.alpha, l5.d, l6.d)]
    a4, a5, a6, al4, al5, al6, d5, d6 = fl
    j = first + 1
    msg = (
        f"{arm.name}: joints {j}-{j + 2} are not a spherical wrist "
        "(their axes must meet in one point)"
    )
    if arm.convention == "standard":
        if (
            abs(a4) > 0
            or abs(a5) > 0
            or abs(d5) > 0
            or abs(abs(np.sin(al4)) - 1) > 1e-12
            or abs(np.sin(al5) + np.sin(al4)) > 1e-12
        ):
            raise InputError(msg)
        pre, post, s = np.eye(3), _rx(al6), float(np.sign(np.sin(al4)))
        centre = _rx(-al6) @ np.array([-a6, 0.0, -d6])
    else:
        if (
            abs(a5) > 0
            or abs(a6) > 0
            or abs(d5) > 0
            or abs(abs(np.sin(al5)) - 1) > 1e-12
            or abs(np.sin(al6) + np.sin(al5)) > 1e-12
        ):
            raise InputError(msg)
        pre, post, s = _rx(al4), np.eye(3), float(np.sign(np.sin(al5)))
        centre = np.array([0.0, 0.0, -d6])
    offs = (float(l4.offset), float(l5.offset), float(l6.offset))
    return WristModel(pre, post, s, offs, centre)


def wrist_angles(
    W: WristModel, R_3_6: FloatArray, hint4: FloatArray | float
) -> tuple[FloatArray, np.ndarray]:
    """Wrist joints of both branches: ``(..., 2, 3)`` and the singular mask ``(...)``."""
    M = W.pre.T @ R_3_6 @ W.post.T
    o4, o5, o6 = W.offsets
    phi, theta, psi, sing = spherical_wrist(M, np.asarray(hint4) + o4)
    q = np.stack([phi - o4, -W.s * theta - o5, psi - o6], axis=-1)
    return q, sing


def wrist_slot_labels(W: WristModel) -> tuple[str, str]:
    """Which wrist slot is "no-flip" (q_mid with sin >= 0): slot 0 has q_mid = -s * theta."""
    return ("no-flip", "flip") if W.s < 0 else ("flip", "no-flip")


def branch_slots(W: WristModel) -> tuple[Branch, ...]:
    """The 8 slots of the decoupled 6R: arm slot ``a`` (``ARM_SLOTS``) times wrist slot ``b``."""
    labels = wrist_slot_labels(W)
    return tuple(Branch(side, None, labels[b]) for side, _ in ARM_SLOTS for b in (0, 1))


def rotation_0_3(arm: SerialArm, q123: FloatArray) -> FloatArray:
    """``R_0_3`` for joints ``q123`` of shape ``(..., 3)``: shape ``(..., 3, 3)``."""
    R = np.broadcast_to(np.eye(3), q123.shape[:-1] + (3, 3))
    for i in range(3):
        R = R @ link_transform(arm.links[i], q123[..., i], arm.convention)[..., :3, :3]
    return R


@dataclass(frozen=True)
class DecouplingSteps:
    """The intermediate values of the decoupling, for one pose and one arm branch.

    All matrices are (3, 3), vectors (3,), in frame 0 of the arm.
    """

    T_0_6: FloatArray
    wrist_centre: FloatArray
    q123: FloatArray
    R_0_3: FloatArray
    R_3_0: FloatArray
    R_0_6: FloatArray
    R_3_6: FloatArray
    q456: FloatArray  # (2, 3): no-flip/flip as in ``wrist_labels``
    wrist_labels: tuple[str, str]
    formulas: str


class Decoupled6RSolver(ClosedForm):
    """Closed-form IK of a 6R arm whose first three joints are anthropomorphic
    and whose last three form a spherical wrist: up to 8 solutions."""

    target_kind = "pose"
    wrist_middle = 4
    count = 8
    singularities = {"shoulder": SHOULDER, "elbow": ELBOW, "fold": FOLD, "wrist": WRIST}

    def __init__(self, geometry: RRRGeometry) -> None:
        self.geometry = geometry

    def check(self, arm: SerialArm) -> None:
        if arm.joint_types != "RRRRRR":
            raise InputError(f"{arm.name}: decoupling needs a 6R arm, got {arm.joint_types}")
        W = wrist_model(arm, 3)
        check_rrr_geometry(
            arm,
            self.geometry,
            lambda F: (F[:, :3, :3] @ W.centre) + F[:, :3, 3],
            "anthropomorphic 6R",
        )

    def wrist(self, arm: SerialArm) -> WristModel:
        return wrist_model(arm, 3)

    def batch_kernel(self, arm: SerialArm) -> BatchKernel | None:
        """The fast many-pose kernel for ``arm`` (see :class:`BatchKernel`), or None if its
        table does not have the form the kernel assumes (then the batch uses :meth:`solve`).

        Built once per arm (arms are immutable) and kept while the arm lives.
        """
        cache = self.__dict__.setdefault("_kernels", weakref.WeakKeyDictionary())
        if arm not in cache:
            try:
                cache[arm] = BatchKernel(arm, self)
            except _NotSupported:
                cache[arm] = None
        return cache[arm]

    def single_kernel(self, arm: SerialArm) -> SingleKernel | None:
        """The plain-float kernel for one regular pose (see :class:`SingleKernel`), or None."""
        cache = self.__dict__.setdefault("_single", weakref.WeakKeyDictionary())
        if arm not in cache:
            batch = self.batch_kernel(arm)
            kernel = None if batch is None else SingleKernel(batch)
            if kernel is not None and math.isnan(sum(kernel.twists)):
                kernel = None  # twists other than the lesson arms' +-90 deg: numpy path
            cache[arm] = kernel
        return cache[arm]

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        W = self.wrist(arm)
        R_0_6 = T_0_n[:, :3, :3]
        pw = R_0_6 @ W.centre + T_0_n[:, :3, 3]
        h1, h2 = (0.0, 0.0) if hint is None else (hint[0], hint[1])
        pos = position_rrr(pw, self.geometry, h1, h2)
        R_0_3 = rotation_0_3(arm, pos.q)  # (N, 4, 3, 3)
        R_3_6 = np.swapaxes(R_0_3, -1, -2) @ R_0_6[:, None]  # (N, 4, 3, 3)
        q456, wsing = wrist_angles(W, R_3_6, 0.0 if hint is None else hint[3])  # (N,4,2,3)
        N = T_0_n.shape[0]
        q = np.empty((N, 4, 2, 6))
        q[..., :3] = pos.q[:, :, None, :]
        q[..., 3:] = q456
        slots = branch_slots(W)

        def per_slot(mask: np.ndarray) -> np.ndarray:
            return np.repeat(mask, 2, axis=1)

        return RawSolutions(
            q=q.reshape(N, 8, 6),
            valid=per_slot(pos.valid),
            slots=slots,
            elbow_up=per_slot(pos.elbow_up),
            singular={
                "shoulder": per_slot(pos.shoulder_singular),
                "elbow": per_slot(pos.elbow_singular),
                "fold": per_slot(pos.fold_singular & pos.valid),
                "wrist": per_slot(wsing & pos.valid),
            },
        )

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable`: the wrist centre moved onto the shell
        joints 1-3 sweep."""
        return nearest_reachable(arm, rrr_gap(self.geometry), T_world, self.wrist(arm).centre)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        W = self.wrist(arm)
        pw = T_0_n[:3, :3] @ W.centre + T_0_n[:3, 3]
        return explain_rrr(pw, self.geometry, arm.units, "the wrist centre",
                           rounding_note(arm, pw))

    def steps(self, arm: SerialArm, T_0_6: FloatArray, arm_slot: int = 0) -> DecouplingSteps:
        """The decoupling's intermediate values for one pose ``T_0_6`` and one arm slot (0-3).

        ``T_0_6`` is the flange pose in frame 0 (``arm.world_to_base(T)`` of a world
        TCP pose); a rotation block that is not a rotation to rounding is replaced by
        the nearest one, as ``arm.ik`` does.

        Raises
        ------
        InputError
            ``arm`` is not of this solver's family, ``T_0_6`` is not one 4x4 pose, or
            ``arm_slot`` is not 0, 1, 2 or 3.
        UnreachableError
            That arm branch cannot put the wrist centre where ``T_0_6`` needs it.
        """
        if not isinstance(arm, SerialArm) or arm.solver is not self:
            raise InputError("arm must be the rikin.SerialArm this solver belongs to (arm.solver)")
        if (
            isinstance(arm_slot, (bool, np.bool_))
            or not isinstance(arm_slot, (int, np.integer))
            or not 0 <= arm_slot <= 3
        ):
            raise InputError(f"arm_slot must be 0, 1, 2 or 3 (see ARM_SLOTS), got {arm_slot!r}")
        T_0_6 = as_pose(T_0_6, "T_0_6")
        if T_0_6.shape != (4, 4):
            raise InputError(f"T_0_6 must be one 4x4 pose, got shape {T_0_6.shape}")
        T_0_6 = clean_pose(T_0_6)[0]
        W = self.wrist(arm)
        R_0_6 = T_0_6[:3, :3]
        pw = R_0_6 @ W.centre + T_0_6[:3, 3]
        pos = position_rrr(pw[None], self.geometry)
        if not pos.valid[0, arm_slot]:
            msg, ex = self.explain(arm, T_0_6)
            raise UnreachableError(
                f"{arm.name}: arm branch {arm_slot} cannot reach: {msg}", excess=ex, units=arm.units
            )
        q123 = pos.q[0, arm_slot]
        R_0_3 = rotation_0_3(arm, q123)
        R_3_6 = R_0_3.T @ R_0_6
        q456, _ = wrist_angles(W, R_3_6, 0.0)
        return DecouplingSteps(
            T_0_6=T_0_6,
            wrist_centre=pw,
            q123=q123,
            R_0_3=R_0_3,
            R_3_0=R_0_3.T,
            R_0_6=R_0_6,
            R_3_6=R_3_6,
            q456=q456,
            wrist_labels=wrist_slot_labels(W),
            formulas=wrist_formulas(W),
        )


def wrist_formulas(W: WristModel) -> str:
    """Which entries of R_3_6 give q4, q5, q6, as text (entries m_ij of M, 1-based)."""
    pre = "" if np.allclose(W.pre, np.eye(3)) else "pre^T "
    post = "" if np.allclose(W.post, np.eye(3)) else " post^T"
    o4, o5, o6 = (f"{-o:+.4g}" if abs(o) > SINGULAR_TOL else "" for o in W.offsets)
    sgn = "" if W.s < 0 else "-"
    return (
        f"M = {pre}R_3_6{post}\n"
        f"q5 = {sgn}atan2(+-sqrt(m13^2 + m23^2), m33){o5}\n"
        f"q4 = atan2(+-m23, +-m13){o4}\n"
        f"q6 = atan2(+-m32, -+m31){o6}\n"
        "(upper signs: the first wrist slot; lower signs: the other, q5 -> -q5)"
    )


# ---------------------------------------------------------------- many poses at once
class _NotSupported(Exception):
    """The arm's table is not of the form :class:`BatchKernel` assumes."""


def _rx_const(alpha: float) -> FloatArray:
    c, s = np.cos(alpha), np.sin(alpha)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


class BatchKernel:
    """The decoupling of one arm specialised for many poses (structure of arrays).

    The general :meth:`Decoupled6RSolver.solve` builds ``T_0_n``, ``R_0_3``
    and ``R_3_6`` as stacks of matrices; this kernel computes the same
    joint values with per-arm constants read once from the DH table:

    * the rotations of links 1-3 are ``R_0_3 = E0 Rz(th1) E1 Rz(th2) E2 Rz(th3) E3``
      with constant twists ``E = Rx(alpha)``; axes 2 and 3 are parallel
      (``E2 = Rx(0 or pi)``), so ``Rz(th2) E2 Rz(th3) = Rz(phi) E2`` with
      ``phi = th2 + sigma th3``, ``sigma = cos(alpha) = +-1``;
    * the wrist matrix of :func:`wrist_angles` is then
      ``M = pre^T R_0_3^T (base^-1 R tool^-1) post^T = K Rz(-phi) E1^T Rz(-th1) G R H``
      with ``R`` the world rotation of the TCP and constants ``K = pre^T (E2 E3)^T``,
      ``G = E0^T base_R^-1``, ``H = tool_R^-1 post^T``;
    * only the five entries of ``M`` the ZYZ angles need are formed.

    Poses near a singularity (shoulder, elbow or wrist, with a margin far
    wider than ``SINGULAR_TOL``) are reported as ``suspect``; the caller
    solves those again with :meth:`Decoupled6RSolver.solve`, so singular
    poses get exactly the general solver's representatives and flags.

    Raises ``_NotSupported`` when axes 2 and 3 are not parallel.
    """

    #: Margins that send a pose back to the general solver (relative to the
    #: singularity tests of ``position_rrr`` and ``spherical_wrist``).
    SUSPECT_SIN = 1e-6
    SUSPECT_EDGE = 1e-10  # relative distance of the wrist centre from the reach boundary

    def __init__(self, arm: SerialArm, solver: Decoupled6RSolver) -> None:
        l1, l2, l3 = arm.links[:3]
        al = [float(lk.alpha) for lk in (l1, l2, l3)]
        if arm.convention == "standard":
            E0, E1, E2, E3 = np.eye(3), _rx_const(al[0]), _rx_const(al[1]), _rx_const(al[2])
            alpha_23 = al[1]
        else:
            E0, E1, E2, E3 = _rx_const(al[0]), _rx_const(al[1]), _rx_const(al[2]), np.eye(3)
            alpha_23 = al[2]
        if abs(np.sin(alpha_23)) > 1e-12:
            raise _NotSupported
        W = wrist_model(arm, 3)
        base_inv, tool_inv = _inv_transform(arm.base), _inv_transform(arm.tool)
        self.geometry = solver.geometry
        self.sigma = float(np.sign(np.cos(alpha_23)))
        self.K = snap_exact(W.pre.T @ (E2 @ E3).T)
        self.E1t = snap_exact(E1.T)
        self.G = snap_exact(E0.T @ base_inv[:3, :3])
        self.H = snap_exact(tool_inv[:3, :3] @ W.post.T)
        self.base_R, self.base_p = snap_exact(base_inv[:3, :3]), base_inv[:3, 3].copy()
        self.centre_tcp = tool_inv[:3, :3] @ W.centre + tool_inv[:3, 3]
        self.offsets = tuple(float(lk.offset) for lk in arm.links)
        self.wrist_s = W.s
        self.slots = branch_slots(W)

    # --------------------------------------------------------- steps
    def _wrist_centre(self, R: Mat3, p: FloatArray) -> FloatArray:
        """Step 1: the wrist centre in frame 0, ``base^-1 (R c_tcp + p)``, shape ``(3, n)``."""
        c = self.centre_tcp
        v = [R[i][0] * c[0] + R[i][1] * c[1] + R[i][2] * c[2] + p[i] for i in range(3)]
        B, b = self.base_R, self.base_p
        return np.stack([B[i, 0] * v[0] + B[i, 1] * v[1] + B[i, 2] * v[2] + b[i] for i in range(3)])

    def _arm_joints(
        self, pw: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, np.ndarray, np.ndarray]:
        """Step 2: joints 1-3 of the four arm slots.

        Returns ``q1`` (n,) of the front slots (the back ones add pi),
        ``q2, q3`` (4, n), ``valid`` (4, n) and ``suspect`` (n,): near the
        shoulder or elbow singularity.
        """
        g = self.geometry
        x, y, z = pw
        rho = np.sqrt(x * x + y * y)
        q1 = np.arctan2(y, x)
        w = z - g.z0
        A, B, valid, suspect = [], [], [], rho < self.SUSPECT_SIN * g.size
        for u in (rho - g.r0, -rho - g.r0):
            t = two_link_parts(u, w, g.L2, g.L3)
            A += [t.base - t.beta, t.base + t.beta]
            B += [t.B0, -t.B0]
            valid += [t.reachable, t.reachable]
            suspect |= t.edge < self.SUSPECT_EDGE
        q2 = np.stack(A) - g.phi2
        q3 = np.stack(B) - g.phi3
        return q1, q2, q3, np.stack(valid), suspect

    def _wrist_matrix(
        self, S: Mat3, q1: FloatArray, q2: FloatArray, q3: FloatArray
    ) -> tuple[list[FloatArray], list[FloatArray], FloatArray]:
        """Step 3: rows 0 and 1 and entry ``m22`` of ``M`` for the four arm slots.

        ``S = G R H`` has (n,) entries; ``q2, q3`` have shape (4, n). The back
        slots have ``th1 + pi``: rows 0 and 1 of ``Rz(-th1) S`` negated. Returns
        the rows as lists of three (4, n) arrays, and ``m22`` (4, n).
        """
        o1, o2, o3 = self.offsets[:3]
        th1 = q1 + o1
        U = rz_inverse_times(np.cos(th1), np.sin(th1), S)
        # (side, 1, n): front and back; the back negates rows 0 and 1
        Us = [
            [np.stack([U[i][j], -U[i][j] if i < 2 else U[i][j]])[:, None] for j in range(3)]
            for i in range(3)
        ]
        V = const_matmul(self.E1t, Us)
        phi = ((q2 + o2) + self.sigma * (q3 + o3)).reshape(2, 2, -1)  # (side, elbow, n)
        Wm = rz_inverse_times(np.cos(phi), np.sin(phi), V)
        Wm[2] = [np.broadcast_to(v, phi.shape) for v in Wm[2]]
        K = self.K
        rows = [
            [lincomb(K[i], [Wm[0][j], Wm[1][j], Wm[2][j]]).reshape(4, -1) for j in range(3)]
            for i in range(2)
        ]
        m22 = lincomb(K[2], [Wm[0][2], Wm[1][2], Wm[2][2]]).reshape(4, -1)
        return rows[0], rows[1], m22

    def _wrist_joints(
        self, row0: list[FloatArray], row1: list[FloatArray], m22: FloatArray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Step 4: ZYZ angles ``M = Rz(phi) Ry(theta) Rz(psi)`` of wrist slot 0, and
        ``suspect`` (n,): near the wrist singularity in some arm slot.

        ``phi`` and ``theta`` as in :func:`spherical_wrist`; ``psi`` is read from
        row 1 of ``Rz(-phi) M = Ry(theta) Rz(psi)``, i.e. ``(sin psi, cos psi, 0)``.
        Unlike ``atan2(m21, -m20)`` this stays consistent with ``phi`` near the
        singularity (where ``phi`` and ``psi`` are each ill-conditioned but the
        pose depends only on their sum or difference), so FK reproduces the
        pose to rounding even when ``sin(theta)`` is 1e-6.
        """
        m02, m12 = row0[2], row1[2]
        s = np.sqrt(m02 * m02 + m12 * m12)
        theta = np.arctan2(s, m22)
        phi = np.arctan2(m12, m02)
        safe = np.where(s > 0.0, s, 1.0)
        c_phi, s_phi = m02 / safe, m12 / safe
        psi = np.arctan2(c_phi * row1[0] - s_phi * row0[0], c_phi * row1[1] - s_phi * row0[1])
        return phi, theta, psi, np.asarray((s < self.SUSPECT_SIN).any(axis=0))

    def solve(self, X: FloatArray) -> tuple[FloatArray, np.ndarray, np.ndarray]:
        """All 8 slots of ``n`` validated world poses.

        Parameters
        ----------
        X : ndarray, shape (4, 4, n)
            World TCP poses as a structure of arrays (``X[:, :, i]`` is pose i).

        Returns
        -------
        q : ndarray, shape (8, 6, n)
            Slot ``2 a + b`` (arm slot a, wrist slot b, as :meth:`Decoupled6RSolver.solve`),
            wrapped to (-pi, pi], NaN where not valid.
        valid : ndarray of bool, shape (8, n)
        suspect : ndarray of bool, shape (n,)
            Near a singularity: solve these poses again with the general solver.
        """
        n = X.shape[-1]
        R = [[X[i, j] for j in range(3)] for i in range(3)]
        S = matmul_const(const_matmul(self.G, R), self.H)
        pw = self._wrist_centre(R, X[:3, 3])
        q1, q2, q3, valid4, suspect = self._arm_joints(pw)
        phi, theta, psi, wrist_suspect = self._wrist_joints(*self._wrist_matrix(S, q1, q2, q3))
        o4, o5, o6 = self.offsets[3:]
        q = np.empty((4, 2, 6, n))
        q[:2, :, 0] = q1
        q[2:, :, 0] = q1 + np.pi
        q[:, :, 1] = q2[:, None]
        q[:, :, 2] = q3[:, None]
        q[:, 0, 3] = phi - o4
        q[:, 1, 3] = phi + (np.pi - o4)
        np.multiply(theta, -self.wrist_s, out=q[:, 0, 4])
        np.multiply(theta, self.wrist_s, out=q[:, 1, 4])
        q[:, :, 4] -= o5
        q[:, 0, 5] = psi - o6
        q[:, 1, 5] = psi + (np.pi - o6)
        q = wrap_in_place(q.reshape(8, 6, n))
        valid = np.repeat(valid4, 2, axis=0)
        np.copyto(q, np.nan, where=~valid[:, None, :])
        return q, valid, suspect | wrist_suspect


# ---------------------------------------------------------------- one pose, plain floats
class SingleKernel:
    """The decoupling of :class:`BatchKernel` for ONE regular pose, in plain ``math``.

    For one pose numpy's per-call overhead dominates (a hundred small array
    operations); the same formulas on Python floats take a third of the time.
    :meth:`solve` returns None for a pose near a singularity (the margins of
    :class:`BatchKernel`), which the caller then solves with the general
    :meth:`Decoupled6RSolver.solve`; away from them the 8 slots are distinct
    (front and back differ by pi in q1, the elbows by at least ~1e-5 rad in q3,
    the wrist flips by pi in q4), so no de-duplication is needed.
    """

    def __init__(self, batch: BatchKernel) -> None:
        tl = lambda M: [[float(v) for v in row] for row in M]  # noqa: E731
        self.G, self.H, self.K, self.E1t = tl(batch.G), tl(batch.H), tl(batch.K), tl(batch.E1t)
        self.base_R, self.base_p = tl(batch.base_R), [float(v) for v in batch.base_p]
        self.no_base = bool(np.array_equal(batch.base_R, np.eye(3)) and not batch.base_p.any())
        self.c = [float(v) for v in batch.centre_tcp]
        g = batch.geometry
        self.g = (float(g.z0), float(g.r0), float(g.L2), float(g.L3), float(g.phi2), float(g.phi3))
        self.size = float(g.size)
        self.sigma, self.s = batch.sigma, batch.wrist_s
        self.offsets = batch.offsets
        self.slots = batch.slots
        #: ``labels[slot][elbow up][sin(q5) >= 0]``: the Branch of a solution
        self.labels = [
            [[Branch(b.shoulder, "up" if up else "down", "no-flip" if nf else "flip")
              for nf in (False, True)] for up in (False, True)]
            for b in batch.slots
        ]
        # with no offset on joint 5 the no-flip/flip slots' labels are fixed: per even slot
        # plus elbow up (0 or 1), the Branches of that slot and the next
        s_w = batch.wrist_s
        self.pair_labels = [
            (self.labels[slot][up][s_w < 0], self.labels[slot + 1][up][s_w > 0])
            for slot in range(0, len(batch.slots), 2) for up in (0, 1)
        ]
        self.sus_sin, self.sus_edge = batch.SUSPECT_SIN, batch.SUSPECT_EDGE
        #: (e1, k6) with E1^T = Rx(-e1 pi/2) and K = Rx(-k6 pi/2): the twists of the arms
        #: this kernel takes (``single_kernel`` gives None for others)
        self.twists = (_rx_quarter(batch.E1t), _rx_quarter(batch.K))
        self.plain = bool(np.array_equal(batch.G, np.eye(3)) and np.array_equal(batch.H, np.eye(3)))

    def _GRH(self, R: list[list[float]]) -> list[list[float]]:
        """Rows of ``S = G R H`` (see :class:`BatchKernel`)."""
        return _mul3(_mul3(self.G, R), self.H)

    def solve(self, T: list[list[float]]) -> tuple[list[float], list[Branch]] | None:
        """Joint values of the valid slots (wrapped to (-pi, pi]), as one flat list of
        6 per solution, and the Branch of each solution.

        ``T`` is the validated world pose as nested lists. None: near a singularity,
        or nothing reachable (let the general solver decide and explain).
        """
        S, (x, y, z) = self._goal(T)
        rho = hypot(x, y)
        if rho < self.sus_sin * self.size:
            return None
        q1 = atan2(y, x)
        z0, r0 = self.g[0], self.g[1]
        w = z - z0
        o1 = self.offsets[0]
        c1q, s1q = cos(q1 + o1), sin(q1 + o1)
        q_out: list[float] = []
        branches: list[Branch] = []
        for side, u in ((0, rho - r0), (1, -rho - r0)):
            triangle = self._triangle(u, w)
            if triangle is None:
                return None
            if not triangle:
                continue
            if side:  # joint 1 turned by pi: q1 + pi in (-pi, pi], its cos and sin negated
                a1, ct, st = q1 - pi if q1 > 0.0 else q1 + pi, -c1q, -s1q
            else:  # atan2's range [-pi, pi]
                a1, ct, st = q1, c1q, s1q
            if not self._side(side, a1, ct, st, S, u, triangle, q_out, branches):
                return None
        if not q_out:
            return None
        if -pi in q_out:  # remainder's range is [-pi, pi]; wrap_angle's is (-pi, pi]
            q_out = [pi if v == -pi else v for v in q_out]
        return q_out, branches

    def _goal(self, T: list[list[float]]) -> tuple[list[list[float]], tuple[float, ...]]:
        """Rows of ``S = G R H`` and the wrist centre ``(x, y, z)`` in the arm's base frame
        (after the base) for the world pose ``T``."""
        (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz) = T[0], T[1], T[2]
        if self.plain:  # G and H are the identity (no base rotation, no tool twist)
            S = [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]]
        else:
            S = self._GRH([[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]])
        c0, c1_, c2 = self.c
        v0 = r00 * c0 + r01 * c1_ + r02 * c2 + px
        v1 = r10 * c0 + r11 * c1_ + r12 * c2 + py
        v2 = r20 * c0 + r21 * c1_ + r22 * c2 + pz
        if self.no_base:
            return S, (v0, v1, v2)
        B, b = self.base_R, self.base_p
        return S, (
            B[0][0] * v0 + B[0][1] * v1 + B[0][2] * v2 + b[0],
            B[1][0] * v0 + B[1][1] * v1 + B[1][2] * v2 + b[1],
            B[2][0] * v0 + B[2][1] * v1 + B[2][2] * v2 + b[2],
        )

    def _triangle(
        self, u: float, w: float
    ) -> tuple[float, float, float, bool] | tuple[()] | None:
        """Links 2-3 reaching ``(u, w)`` (the wrist centre in the plane of joint 1, from the
        shoulder): ``(base, beta, B0, vertical)`` (the law of cosines), ``()`` when out of
        reach on this side, None at or near the edge of the reach."""
        L2, L3 = self.g[2], self.g[3]
        r = hypot(u, w)
        Lp, Lm = L2 + L3, abs(L2 - L3)
        tol = REACH_TOL * Lp
        if not Lm - tol <= r <= Lp + tol:
            return ()
        dp, dm = Lp - r, r - Lm
        edge = self.sus_edge * Lp
        if dp < edge or dm < edge:  # at or near the edge of the reach
            return None
        sp, sm = Lp + r, r + Lm
        B0 = 2.0 * atan2(sqrt(dp * sp), sqrt(dm * sm))
        if L2 >= L3:
            beta = 2.0 * atan2(sqrt(dm * dp), sqrt(sp * sm))
        else:
            beta = 2.0 * atan2(sqrt(sm * dp), sqrt(sp * dm))
        return atan2(w, u), beta, B0, abs(u) <= SINGULAR_TOL * L2

    def _side(
        self,
        side: int,
        a1: float,
        ct: float,
        st: float,
        S: list[list[float]],
        u: float,
        triangle: tuple[float, float, float, bool],
        q_out: list[float],
        branches: list[Branch],
    ) -> bool:
        """Append both elbows' solutions (each with its wrist flip) of one side of joint 1
        (``a1``, its cosine ``ct`` and sine ``st``) to ``q_out`` and ``branches``; False
        near the wrist singularity."""
        base, beta, B0, vertical = triangle
        _, _, _, _, phi2, phi3 = self.g
        _, o2, o3, o4, o5, o6 = self.offsets
        e1, k6 = self.twists
        ek = -e1 * k6
        sig, s_w, sus_sin = self.sigma, self.s, self.sus_sin
        rem, tau = remainder, 2.0 * pi
        (s00, s01, s02), (s10, s11, s12), S2 = S
        V10, V11, V12 = e1 * S2[0], e1 * S2[1], e1 * S2[2]
        # U = Rz(-th1) S (rows 0, 1), then V = E1^T U
        u00, u01, u02 = ct * s00 + st * s10, ct * s01 + st * s11, ct * s02 + st * s12
        u10, u11, u12 = ct * s10 - st * s00, ct * s11 - st * s01, ct * s12 - st * s02
        # V = E1^T U with E1^T = [[1, 0, 0], [0, 0, e1], [0, -e1, 0]] (its row 1, V1*,
        # is the same for both sides); M = K W likewise, so M's row 1 is -e1 k6 U's
        # row 1 whatever the elbow
        V00, V01, V02 = u00, u01, u02
        m10, m11, m12 = ek * u10, ek * u11, ek * u12
        pairs = None if o5 else self.pair_labels
        for elbow, (A, Bv) in enumerate(((base - beta, B0), (base + beta, -B0))):
            q2, q3 = A - phi2, Bv - phi3
            ph = (q2 + o2) + sig * (q3 + o3)
            cp, sq = cos(ph), sin(ph)
            m00, m01, m02 = cp * V00 + sq * V10, cp * V01 + sq * V11, cp * V02 + sq * V12
            m22 = -k6 * (cp * V12 - sq * V02)
            sw = sqrt(m02 * m02 + m12 * m12)
            if sw < sus_sin:
                return False
            theta = atan2(sw, m22)
            phw = atan2(m12, m02)
            cph, sph = m02 / sw, m12 / sw
            psi = atan2(cph * m10 - sph * m00, cph * m11 - sph * m01)
            # elbow up: the elbow (L2 along A) lies on the upper side of the line from
            # the shoulder to the wrist centre (direction ``base``): sign(sin(A - base))
            # = sign(-+beta), beta in (0, pi) here; a vertical line compares heights
            is_up = cos(A) > 0 if vertical else (u > 0) == (elbow == 1)
            t5 = s_w * theta
            q5a, q5b = rem(-t5 - o5, tau), rem(t5 - o5, tau)
            a2, a3 = rem(q2, tau), rem(q3, tau)
            a4, a6 = rem(phw - o4, tau), rem(psi - o6, tau)
            # the flip: q4 + pi and q6 + pi, in (-pi, pi] from a4, a6 in [-pi, pi]
            q_out += (a1, a2, a3, a4, q5a, a6,
                      a1, a2, a3, a4 - pi if a4 > 0.0 else a4 + pi, q5b,
                      a6 - pi if a6 > 0.0 else a6 + pi)
            slot = 4 * side + 2 * elbow
            if pairs is None:  # sin(q5) of each flip: its label
                branches += (self.labels[slot][is_up][sin(q5a) >= 0.0],
                             self.labels[slot + 1][is_up][sin(q5b) >= 0.0])
            else:  # no offset on joint 5: sin(q5) = -+s_w sin(theta), theta in (0, pi)
                branches += pairs[slot + is_up]
        return True


def _rx_quarter(A: FloatArray) -> float:
    """``e`` if ``A`` is exactly ``[[1, 0, 0], [0, 0, e], [0, -e, 0]]`` (e = +-1), else NaN."""
    for e in (1.0, -1.0):
        if np.array_equal(A, [[1.0, 0, 0], [0, 0, e], [0, -e, 0]]):
            return e
    return math.nan


def _mul3(A: list[list[float]], B: list[list[float]]) -> list[list[float]]:
    """The product of two 3x3 matrices given as nested lists, in plain floats."""
    cols = list(zip(*B, strict=True))
    return [[a0 * b0 + a1 * b1 + a2 * b2 for b0, b1, b2 in cols] for a0, a1, a2 in A]
