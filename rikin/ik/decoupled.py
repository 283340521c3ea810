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

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import SINGULAR_TOL
from ..transforms import _rot
from .anthropomorphic import (ARM_SLOTS, ELBOW, SHOULDER, RRRGeometry, check_rrr_geometry,
                              explain_rrr, position_rrr)
from .base import RawSolutions, Singularity
from .kernels import spherical_wrist
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

WRIST = Singularity("wrist singularity: q5 is 0 or pi, axes 4 and 6 line up, so only "
                    "q4 + q6 (or q4 - q6) is fixed", (4, 6), drop_flip=True)


def _rx(alpha: float) -> FloatArray:
    return _rot(np.float64(alpha), 0, "alpha")


@dataclass(frozen=True)
class WristModel:
    """Constants of a spherical wrist: ``M = pre^T R_3_6 post^T = Rz(q4+o4) Ry(-s(q5+o5)) Rz(q6+o6)``."""

    pre: FloatArray     # (3, 3)
    post: FloatArray    # (3, 3)
    s: float            # sin of the middle twist, +1 or -1
    offsets: tuple[float, float, float]
    centre: FloatArray  # (3,) wrist centre in the last wrist frame's coordinates


def wrist_model(arm: "SerialArm", first: int) -> WristModel:
    """Read the spherical-wrist constants of joints ``first``..``first+2`` (0-based) from the table.

    Raises InputError when the three axes do not meet in one point.
    """
    l4, l5, l6 = arm.links[first:first + 3]
    fl = [float(v) for v in (l4.a, l5.a, l6.a, l4.alpha, l5.alpha, l6.alpha, l5.d, l6.d)]
    a4, a5, a6, al4, al5, al6, d5, d6 = fl
    j = first + 1
    msg = (f"{arm.name}: joints {j}-{j + 2} are not a spherical wrist "
           "(their axes must meet in one point)")
    if arm.convention == "standard":
        if abs(a4) > 0 or abs(a5) > 0 or abs(d5) > 0 or abs(abs(np.sin(al4)) - 1) > 1e-12 \
                or abs(np.sin(al5) + np.sin(al4)) > 1e-12:
            raise InputError(msg)
        pre, post, s = np.eye(3), _rx(al6), float(np.sign(np.sin(al4)))
        centre = _rx(-al6) @ np.array([-a6, 0.0, -d6])
    else:
        if abs(a5) > 0 or abs(a6) > 0 or abs(d5) > 0 or abs(abs(np.sin(al5)) - 1) > 1e-12 \
                or abs(np.sin(al6) + np.sin(al5)) > 1e-12:
            raise InputError(msg)
        pre, post, s = _rx(al4), np.eye(3), float(np.sign(np.sin(al5)))
        centre = np.array([0.0, 0.0, -d6])
    offs = (float(l4.offset), float(l5.offset), float(l6.offset))
    return WristModel(pre, post, s, offs, centre)


def wrist_angles(W: WristModel, R_3_6: FloatArray, hint4: FloatArray | float
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


def rotation_0_3(arm: "SerialArm", q123: FloatArray) -> FloatArray:
    """``R_0_3`` for joints ``q123`` of shape ``(..., 3)``: shape ``(..., 3, 3)``."""
    from ..dh import link_transform

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
    q456: FloatArray          # (2, 3): no-flip/flip as in ``wrist_labels``
    wrist_labels: tuple[str, str]
    formulas: str


class Decoupled6RSolver:
    """Closed-form IK of a 6R arm whose first three joints are anthropomorphic
    and whose last three form a spherical wrist: up to 8 solutions."""

    target_kind = "pose"
    wrist_middle = 4
    singularities = {"shoulder": SHOULDER, "elbow": ELBOW, "wrist": WRIST}

    def __init__(self, geometry: RRRGeometry) -> None:
        self.geometry = geometry

    def check(self, arm: "SerialArm") -> None:
        if arm.joint_types != "RRRRRR":
            raise InputError(f"{arm.name}: decoupling needs a 6R arm, got {arm.joint_types}")
        W = wrist_model(arm, 3)
        check_rrr_geometry(arm, self.geometry,
                           lambda F: (F[:, :3, :3] @ W.centre) + F[:, :3, 3], "anthropomorphic 6R")

    def wrist(self, arm: "SerialArm") -> WristModel:
        return wrist_model(arm, 3)

    def solve(self, arm: "SerialArm", T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        W = self.wrist(arm)
        R_0_6 = T_0_n[:, :3, :3]
        pw = R_0_6 @ W.centre + T_0_n[:, :3, 3]
        pos = position_rrr(pw, self.geometry, 0.0 if hint is None else hint[0])
        R_0_3 = rotation_0_3(arm, pos.q)                          # (N, 4, 3, 3)
        R_3_6 = np.swapaxes(R_0_3, -1, -2) @ R_0_6[:, None]       # (N, 4, 3, 3)
        q456, wsing = wrist_angles(W, R_3_6, 0.0 if hint is None else hint[3])  # (N,4,2,3)
        N = T_0_n.shape[0]
        q = np.empty((N, 4, 2, 6))
        q[..., :3] = pos.q[:, :, None, :]
        q[..., 3:] = q456
        labels = wrist_slot_labels(W)
        slots = tuple(Branch(side, None, labels[b]) for side, _ in ARM_SLOTS for b in (0, 1))

        def per_slot(mask: np.ndarray) -> np.ndarray:
            return np.repeat(mask, 2, axis=1)

        return RawSolutions(
            q=q.reshape(N, 8, 6), valid=per_slot(pos.valid), slots=slots,
            elbow_up=per_slot(pos.elbow_up),
            singular={"shoulder": per_slot(pos.shoulder_singular),
                      "elbow": per_slot(pos.elbow_singular),
                      "wrist": per_slot(wsing & pos.valid)},
        )

    def explain(self, arm: "SerialArm", T_0_n: FloatArray) -> tuple[str, float]:
        W = self.wrist(arm)
        pw = T_0_n[:3, :3] @ W.centre + T_0_n[:3, 3]
        return explain_rrr(pw, self.geometry, arm.units, "the wrist centre")

    def steps(self, arm: "SerialArm", T_0_6: FloatArray, arm_slot: int = 0) -> DecouplingSteps:
        """The decoupling's intermediate values for one pose ``T_0_6`` and one arm slot (0-3)."""
        W = self.wrist(arm)
        R_0_6 = T_0_6[:3, :3]
        pw = R_0_6 @ W.centre + T_0_6[:3, 3]
        pos = position_rrr(pw[None], self.geometry)
        if not pos.valid[0, arm_slot]:
            msg, ex = self.explain(arm, T_0_6)
            from ..errors import UnreachableError
            raise UnreachableError(f"{arm.name}: arm branch {arm_slot} cannot reach: {msg}",
                                   excess=ex, units=arm.units)
        q123 = pos.q[0, arm_slot]
        R_0_3 = rotation_0_3(arm, q123)
        R_3_6 = R_0_3.T @ R_0_6
        q456, _ = wrist_angles(W, R_3_6, 0.0)
        return DecouplingSteps(T_0_6=T_0_6, wrist_centre=pw, q123=q123, R_0_3=R_0_3,
                               R_3_0=R_0_3.T, R_0_6=R_0_6, R_3_6=R_3_6, q456=q456,
                               wrist_labels=wrist_slot_labels(W), formulas=wrist_formulas(W))


def wrist_formulas(W: WristModel) -> str:
    """Which entries of R_3_6 give q4, q5, q6, as text (entries m_ij of M, 1-based)."""
    pre = "" if np.allclose(W.pre, np.eye(3)) else "pre^T "
    post = "" if np.allclose(W.post, np.eye(3)) else " post^T"
    o4, o5, o6 = (f"{-o:+.4g}" if abs(o) > SINGULAR_TOL else "" for o in W.offsets)
    sgn = "" if W.s < 0 else "-"
    return (f"M = {pre}R_3_6{post}\n"
            f"q5 = {sgn}atan2(+-sqrt(m13^2 + m23^2), m33){o5}\n"
            f"q4 = atan2(+-m23, +-m13){o4}\n"
            f"q6 = atan2(+-m32, -+m31){o6}\n"
            "(upper signs: the first wrist slot; lower signs: the other, q5 -> -q5)")
