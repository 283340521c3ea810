"""IK from the DH product for the 5-DOF PPRRR and RPRRR arms of the handwritten notes.

Both end in a spherical wrist (joints 3-5), so the problem decouples: the
wrist centre ``p_w = p - a_tool z_5`` fixes joints 1-2, and
``R_2_5 = R_0_2^T R_0_5`` fixes joints 3-5 (two wrist branches).

A 5-DOF arm cannot reach every pose: the wrist centre must lie where joints
1-2 can put it. For the PPRRR that is a plane (the notes' constraint
``t_y = a3 a_y``), for the RPRRR the plane ``z = d_1`` outside the cylinder of
radius ``a_2`` (constraint ``t_z = a4 a_z``). A target whose wrist centre is
within ``ROUNDED_POSE_TOL`` of that set (a pose rounded to 4 decimals, or
float32) is moved to the nearest reachable pose (:func:`rikin.ik.reach.nearest_reachable`);
targets further off raise :class:`~rikin.errors.UnreachableError` with the distance.
"""

from __future__ import annotations

import numpy as np

from .._validate import FloatArray
from ..dh import SerialArm, link_transform
from ..errors import InputError
from ..tolerances import REACH_TOL, SINGULAR_TOL
from .api import ClosedForm
from .base import RawSolutions, Singularity
from .decoupled import wrist_angles, wrist_model, wrist_slot_labels
from .reach import Gap, nearest_reachable, rounding_note
from .result import Branch

_WRIST = Singularity(
    "wrist singularity: q4 is 0 or pi, axes 3 and 5 line up, so only q3 + q5 (or q3 - q5) is fixed",
    (3, 5),
    drop_flip=True,
)


def _origin_2(arm: SerialArm, q: FloatArray) -> FloatArray:
    """World-free position of the wrist centre for joint values ``q (..., 5)``."""
    W = wrist_model(arm, 2)
    F = arm._flange._fk(q)
    return F[..., :3, :3] @ W.centre + F[..., :3, 3]


def _w(arm: SerialArm) -> float:
    """Distance from the wrist centre to the flange origin (the notes' a3 or a4)."""
    return float(np.linalg.norm(wrist_model(arm, 2).centre))


class PPRRRSolver(ClosedForm):
    """Two prismatic joints then a spherical wrist: 2 solutions (wrist no-flip/flip)."""

    target_kind = "pose"
    wrist_middle = 3
    count = 2
    singularities = {"wrist": _WRIST}

    def check(self, arm: SerialArm) -> None:
        if arm.joint_types != "PPRRR":
            raise InputError(
                f"{arm.name}: the PPRRR solver needs a PPRRR arm, got {arm.joint_types}"
            )
        wrist_model(arm, 2)

    def _affine(self, arm: SerialArm) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``p_w(d1, d2) = c0 + [u1 u2] @ (d1, d2)`` and the constant ``R_0_2`` (computed once
        per arm: arms are immutable; a rounded pose needs them three times)."""
        cached = arm.__dict__.get("_pprrr_affine")
        if cached is None:
            cached = self._affine_of(arm)
            object.__setattr__(arm, "_pprrr_affine", cached)
        return cached

    def _affine_of(self, arm: SerialArm) -> tuple[FloatArray, FloatArray, FloatArray]:
        q = np.zeros((3, 5))
        step = arm.scale  # a displacement of the arm's own size: no rounding at any scale
        q[1, 0] = step
        q[2, 1] = step
        p = _origin_2(arm, q)
        U = np.stack([p[1] - p[0], p[2] - p[0]], axis=-1) / step  # (3, 2)
        R_0_2 = arm._flange._fk(np.zeros(5), frames=True)[2, :3, :3]
        return p[0], U, R_0_2

    def _wrist_centre(self, arm: SerialArm, T: FloatArray) -> FloatArray:
        W = wrist_model(arm, 2)
        return T[..., :3, :3] @ W.centre + T[..., :3, 3]

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        c0, U, R_0_2 = self._affine(arm)
        pw = self._wrist_centre(arm, T_0_n)
        d, *_ = np.linalg.lstsq(U, (pw - c0).T, rcond=None)
        d = d.T  # (N, 2)
        resid = np.linalg.norm(pw - c0 - d @ U.T, axis=-1)
        size = np.maximum(arm.scale, np.abs(pw).max(axis=-1))  # far targets: relative rounding
        ok = resid <= REACH_TOL * size * 10
        W = wrist_model(arm, 2)
        q345, sing = wrist_angles(W, R_0_2.T @ T_0_n[:, :3, :3], 0.0 if hint is None else hint[2])
        N = T_0_n.shape[0]
        q = np.empty((N, 2, 5))
        q[..., :2] = d[:, None, :]
        q[..., 2:] = q345
        labels = wrist_slot_labels(W)
        k2 = lambda m: np.repeat(m[:, None], 2, axis=1)  # noqa: E731
        return RawSolutions(
            q=q,
            valid=k2(ok),
            slots=(Branch(None, None, labels[0]), Branch(None, None, labels[1])),
            singular={"wrist": k2(sing & ok)},
        )

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`nearest_reachable` for the plane of the two slides."""
        c0, U, _ = self._affine(arm)
        left, sv, _ = np.linalg.svd(U)
        rank = int((sv > 1e-12 * sv.max()).sum())
        normal = left[:, rank:].T  # (k, 3): unit normals of the plane (or line) joints 1-2 sweep

        def gap(pw: FloatArray, active: np.ndarray | None) -> Gap:
            N = len(pw)
            on = np.ones((N, len(normal)), dtype=bool)
            return (pw - c0) @ normal.T, np.broadcast_to(normal, (N, *normal.shape)), on

        return nearest_reachable(arm, gap, T_world, wrist_model(arm, 2).centre)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        c0, U, _ = self._affine(arm)
        pw = self._wrist_centre(arm, T_0_n)
        d, *_ = np.linalg.lstsq(U, pw - c0, rcond=None)
        r = float(np.linalg.norm(pw - c0 - U @ d))
        u = f" {arm.units}" if arm.units else ""
        return (
            f"a 5-DOF arm cannot reach every pose: the wrist centre (target minus "
            f"{_w(arm):.4g}{u} along z_5) is {r:.4g}{u} off the plane joints 1-2 can reach"
            + rounding_note(arm, pw),
            r,
        )


class RPRRRSolver(ClosedForm):
    """Revolute, prismatic, then a spherical wrist: 4 solutions."""

    target_kind = "pose"
    wrist_middle = 3
    count = 4
    singularities = {
        "wrist": _WRIST,
        "radial": Singularity(
            "the wrist centre is at distance a2 from axis 1: the two roots "
            "of the prismatic joint coincide (d2 + a1 + a3 = 0)",
            (),
        ),
    }

    def check(self, arm: SerialArm) -> None:
        if arm.joint_types != "RPRRR":
            raise InputError(
                f"{arm.name}: the RPRRR solver needs an RPRRR arm, got {arm.joint_types}"
            )
        l1, l2 = arm.links[:2]
        if (
            arm.convention != "standard"
            or abs(abs(np.sin(float(l1.alpha))) - 1) > 1e-12
            or float(l2.alpha) != 0
            or float(l2.a) != 0
            or float(l2.theta) != 0
        ):
            raise InputError(f"{arm.name}: not of the notes' RPRRR family")
        wrist_model(arm, 2)
        rng = np.random.default_rng(0)
        q = rng.uniform(-1, 1, size=(5, 5))
        q[:, 1] *= arm.scale  # the prismatic joint, in the arm's units
        want = _origin_2(arm, q)
        got = self._forward_12(arm, q[:, 0], q[:, 1])
        if np.abs(got - want).max() > 1e-9 * arm.scale:
            raise InputError(f"{arm.name}: not of the notes' RPRRR family (geometry check failed)")

    @staticmethod
    def _params(arm: SerialArm) -> tuple[float, float, float, float, float]:
        l1, l2 = arm.links[:2]
        sa = float(np.sign(np.sin(float(l1.alpha))))
        return float(l1.a), float(l1.d), float(l1.offset), float(l2.d) + float(l2.offset), sa

    def _forward_12(self, arm: SerialArm, q1: FloatArray, d2: FloatArray) -> FloatArray:
        a2, d1, off1, l1, sa = self._params(arm)
        t = q1 + off1
        rho = d2 + l1
        c, s = np.cos(t), np.sin(t)
        v = -sa * rho
        return np.stack([a2 * c - v * s, a2 * s + v * c, np.full_like(t, d1)], axis=-1)

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        a2, d1, off1, l1, sa = self._params(arm)
        W = wrist_model(arm, 2)
        pw = T_0_n[:, :3, :3] @ W.centre + T_0_n[:, :3, 3]
        x, y, z = pw[:, 0], pw[:, 1], pw[:, 2]
        r = np.hypot(x, y)
        size = arm.scale
        far = np.maximum(size, np.abs(pw).max(axis=-1))  # far targets: relative rounding
        ok = (np.abs(z - d1) <= REACH_TOL * far * 10) & (r >= a2 - REACH_TOL * size)
        # distance along the prismatic axis, sqrt(r^2 - a2^2) in a form exact near r = a2
        rho0 = np.sqrt(np.maximum(r - a2, 0.0) * (r + a2))
        N = T_0_n.shape[0]
        q = np.empty((N, 2, 2, 5))
        wrist_sing = np.empty((N, 2, 2), dtype=bool)
        for k, rho in enumerate((rho0, -rho0)):
            t = np.arctan2(y, x) - np.arctan2(-sa * rho, a2)
            q1 = t - off1
            d2 = rho - l1
            R_0_2 = (
                link_transform(arm.links[0], q1, "standard")[..., :3, :3]
                @ link_transform(arm.links[1], d2, "standard")[..., :3, :3]
            )
            q345, sing = wrist_angles(
                W, np.swapaxes(R_0_2, -1, -2) @ T_0_n[:, :3, :3], 0.0 if hint is None else hint[2]
            )
            q[:, k, :, 0] = q1[:, None]
            q[:, k, :, 1] = d2[:, None]
            q[:, k, :, 2:] = q345
            wrist_sing[:, k, :] = sing[:, None]
        labels = wrist_slot_labels(W)
        slots = tuple(Branch(side, None, labels[b]) for side in ("front", "back") for b in (0, 1))
        k4 = lambda m: np.repeat(m[:, None], 4, axis=1)  # noqa: E731
        return RawSolutions(
            q=q.reshape(N, 4, 5),
            valid=k4(ok),
            slots=slots,
            singular={
                "wrist": wrist_sing.reshape(N, 4) & ok[:, None],
                "radial": k4((rho0 < SINGULAR_TOL * size) & ok),
            },
        )

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`nearest_reachable` for the plane ``z = d1`` outside the cylinder ``r = a2``."""
        a2, d1, *_ = self._params(arm)

        def gap(pw: FloatArray, active: np.ndarray | None) -> Gap:
            N = len(pw)
            rho = np.hypot(pw[:, 0], pw[:, 1])
            if active is None:  # the plane always; the cylinder when the centre is inside it
                active = np.stack([np.ones(N, dtype=bool), rho < a2], axis=-1)
            r = np.stack([pw[:, 2] - d1, np.where(active[:, 1], rho - a2, 0.0)], axis=-1)
            J = np.zeros((N, 2, 3))
            J[:, 0, 2] = 1.0
            radial = active[:, 1] & (rho > 0)  # on axis 1 no direction is nearest: none taken
            J[radial, 1, :2] = pw[radial, :2] / rho[radial, None]
            active = active & np.stack([np.ones(N, dtype=bool), radial | ~active[:, 1]], axis=-1)
            return r, J, active

        return nearest_reachable(arm, gap, T_world, wrist_model(arm, 2).centre)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        a2, d1, *_ = self._params(arm)
        W = wrist_model(arm, 2)
        pw = T_0_n[:3, :3] @ W.centre + T_0_n[:3, 3]
        u = f" {arm.units}" if arm.units else ""
        dz = float(pw[2] - d1)
        inside = max(a2 - float(np.hypot(pw[0], pw[1])), 0.0)
        dist = float(np.hypot(dz, inside))  # from the nearest point the wrist centre can take
        cyl = (
            f"{inside:.4g}{u} inside the cylinder of radius a2 = {a2:.4g}{u} around axis 1, "
            "which joints 1-2 cannot enter"
        )
        if abs(dz) > REACH_TOL * arm.scale * 10:
            also = f", and {cyl} ({dist:.4g}{u} in all)" if inside > 0 else ""
            return (
                f"a 5-DOF arm cannot reach every pose: the wrist centre (target minus "
                f"{_w(arm):.4g}{u} along z_5) is {abs(dz):.4g}{u} "
                f"{'above' if dz > 0 else 'below'} the plane z = {d1:.4g} joints 1-2 move it in"
                + also
                + rounding_note(arm, pw),
                dist,
            )
        return (f"the wrist centre is {cyl}" + rounding_note(arm, pw), dist)
