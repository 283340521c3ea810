"""The four-axis articulated arm: a waist, then three parallel pitch axes (RRRR).

The small arms of many teaching labs (ROBOTIS' OpenManipulator-X, uArm- and Dobot-like
arms without their parallelogram) turn about a vertical waist (joint 1) and pitch the rest
of the arm with three parallel axes (shoulder, elbow, wrist). Four joints reach four
numbers of a pose: where the tool is and how far it pitches; the pitch axis of the tool
stays level (at its angle to the waist's axis at ``q = 0``).

Written on the joint axes at ``q = 0`` (:mod:`rikin.ik.axes`), with ``w1`` the waist's
axis and ``w`` the common direction of axes 2-4:

* the target's pitch axis ``u`` (axis 4 as the tool carries it) is axis 4 turned about
  the waist by ``q1``: the waist angle that turns ``w4`` onto ``u`` (Paden-Kahan
  subproblem 1), one value;
* turned back by ``q1``, the point ``c`` where the tool meets axis 4 lies in the plane
  joints 2 and 3 move it in, where they are a planar two-link chain (both elbows, as the
  SCARA's links 1-2; :class:`rikin.ik.positioning.Scara` with no quill);
* turns about parallel axes add up: the pitch ``q2 + s3 q3 + s4 q4`` (``s``: +-1, each
  axis' sense against axis 2's) is the turn about ``w`` that carries the flange's
  rotation at ``q = 0`` onto the target's, turned back by ``q1``; then ``q4``.

A target whose pitch axis is not level, or whose point ``c`` is off the arm's plane, is out
of reach (with the reason); off by rounding only, it is solved for the nearest pose the arm
reaches, like the other arms' rounded poses.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import REACH_TOL, ROUNDED_POSE_TOL
from .api import ClosedForm
from .axes import ZeroAxes, rotate, turn_angle, turn_between
from .base import RawSolutions
from .positioning import Scara, finds_joints, fit_joints
from .reach import _turn, rounding_note, rounding_size
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm


class PitchedArmSolver(ClosedForm):
    """Closed-form IK of a four-axis articulated arm (RRRR, axes 2-4 parallel and not
    parallel to axis 1): two solutions (elbow up, down).

    Parameters
    ----------
    arm : SerialArm
        The arm, in DH joint values.
    ax : ZeroAxes
        Its joint axes at ``q = 0`` (axes 2-4 parallel, checked by the caller).
    """

    target_kind = "pose"
    wrist_middle = None
    count = 2

    def __init__(self, arm: SerialArm, ax: ZeroAxes) -> None:
        self.ax = ax
        F_n = ax.frames[-1]
        self.R_n0 = F_n[:3, :3].copy()
        #: a point of axis 4 and axis 4's direction, in the flange frame
        self.c_n = F_n[:3, :3].T @ (ax.r[3] - F_n[:3, 3])
        self.u_n = F_n[:3, :3].T @ ax.w[3]
        self.w1, self.w = ax.w[0], ax.w[1]
        self.level = float(ax.w[3] @ self.w1)  # the pitch axis' component along the waist
        self.senses = np.sign(ax.w[2:4] @ self.w)  # axes 3 and 4 against axis 2
        # joints 2 and 3 as a SCARA's links 1-2, with a "quill" across their plane that
        # measures how far a point is off it (0 on every pose the arm reaches)
        plane = ZeroAxes(np.stack([ax.w[1], ax.w[2], ax.w[1]]),
                         np.stack([ax.r[1], ax.r[2], ax.r[3]]), ax.frames, ax.scale)
        self.family = Scara(plane, ax.r[3])
        self.slots = (Branch(None, None), Branch(None, None))
        self.singularities = self.family.singularities

    def check(self, arm: SerialArm) -> None:
        """Raise InputError unless this solver finds, at random joint values of ``arm``,
        the joints that made the pose."""
        if arm.joint_types != "RRRR":
            raise InputError(f"{arm.name}: the four-axis articulated arm's solver needs an RRRR "
                             f"arm, got {arm.joint_types}")
        q = fit_joints(arm)
        raw = self.solve(arm, arm._flange._fk(q), None)
        if not finds_joints(arm, q, raw.q, raw.valid):
            raise InputError(f"{arm.name}: rikin could not fit the four-axis articulated arm "
                             "to this table (it misses the joints that made a pose)")

    def _waist(self, R: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``q1 (N,)`` from the targets' rotations ``R (N, 3, 3)``, and how far (rad) each
        target's pitch axis is from level."""
        u = R @ self.u_n
        q1, _ = turn_angle(self.w1, self.ax.w[3], u)
        off = np.abs(np.arcsin(np.clip(u @ self.w1, -1.0, 1.0)) - math.asin(self.level))
        return q1, off

    def _unturned(self, T_0_n: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray,
                                                    FloatArray]:
        """``q1``, the pitch axis' tilt, the point ``c`` and the rotation of each target
        with the waist turned back (``(N,)``, ``(N,)``, ``(N, 3)``, ``(N, 3, 3)``)."""
        R = T_0_n[:, :3, :3]
        q1, off = self._waist(R)
        r1 = self.ax.r[0]
        p = rotate(self.w1, -q1, R @ self.c_n + T_0_n[:, :3, 3] - r1) + r1
        back = np.stack([rotate(self.w1, -q1, R[:, :, j]) for j in range(3)], axis=-1)
        return q1, off, p, back

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        """Both solutions of each flange pose ``T_0_n (N, 4, 4)`` (frame 0)."""
        q1, off, p, back = self._unturned(T_0_n)
        placed = self.family.place(p, None if hint is None else hint[1:])
        s3, s4 = self.senses
        q = np.empty(placed.q.shape[:2] + (4,))
        q[..., 0] = q1[:, None]
        q[..., 1:3] = placed.q[..., :2]
        pitch = turn_between(self.w, self.R_n0, back)[:, None]
        q[..., 3] = s4 * (pitch - q[..., 1] - s3 * q[..., 2])
        # a target off the arm's plane or with its pitch axis not level: no solution (a
        # rounded one goes to nearest_reachable), as the 5-DOF arms' wrist centre off theirs
        tol = 10 * REACH_TOL
        ok = (np.abs(placed.q[..., 2]) <= tol * np.maximum(arm.scale, np.abs(p).max(-1))[:, None]) \
            & (off <= tol)[:, None]
        singular = {name: m & ok for name, m in placed.singular.items()}
        return RawSolutions(q=q, valid=placed.valid & ok, slots=self.slots,
                            elbow_up=self._elbow_up(p, placed.q), singular=singular)

    def _elbow_up(self, p: FloatArray, q23: FloatArray) -> np.ndarray:
        """``(N, 2)``: the elbow (axis 3) above the line from the shoulder (axis 2) to the
        point ``c``, "above" along the waist's axis (ahead, when that line is vertical)."""
        ax = self.ax
        s = ax.r[1] + ((ax.r[3] - ax.r[1]) @ self.w) * self.w  # the shoulder, in c's plane
        elbow = rotate(self.w, q23[..., 0], ax.r[2] - ax.r[1]) + ax.r[1]  # (N, 2, 3)
        d = p - s
        d_hat = d / np.maximum(np.linalg.norm(d, axis=-1), 1e-300)[:, None]
        up = self.w1 - (d_hat @ self.w1)[:, None] * d_hat
        up = np.where((np.linalg.norm(up, axis=-1) > 1e-9)[:, None], up, np.cross(self.w, d_hat))
        return np.einsum("nkj,nj->nk", elbow - s, up) > 0.0

    def _gaps(self, p: FloatArray) -> tuple[FloatArray, FloatArray]:
        """For unturned points ``p (N, 3)``: how far each is off the arm's plane (along
        ``w``) and the move ``(N, 3)`` (unturned frame) that puts it on the plane and within
        the reach of links 2-3."""
        h = (p - self.ax.r[3]) @ self.w
        r, J, _ = self.family.gap(p, None)
        return h, -(h[:, None] * self.w + np.einsum("nk,nkj->nj", r, J))

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        """Why one flange pose ``(4, 4)`` has no solution: the pitch axis not level, the
        tool's point off the arm's plane, or out of the reach of links 2-3."""
        _, off, p, _ = self._unturned(T_0_n[None])
        u = f" {arm.units}" if arm.units else ""
        if off[0] > ROUNDED_POSE_TOL:
            return (f"a four-axis articulated arm keeps the tool's pitch axis level: the target "
                    f"tilts it {math.degrees(float(off[0])):.4g} deg (a tilt up to "
                    f"{ROUNDED_POSE_TOL:g} rad is taken as rounded)", float(off[0]))
        h, move = self._gaps(p)
        if abs(h[0]) > ROUNDED_POSE_TOL * arm.scale:
            return (f"the point where the tool meets axis 4 is {abs(h[0]):.4g}{u} off the plane "
                    "joints 2-3 move it in" + rounding_note(arm, p[0]), abs(float(h[0])))
        fam = self.family
        t = (p[0] - self.ax.r[1]) @ fam.basis.T
        d, reach = float(np.hypot(t[0], t[1])), fam.L1 + fam.L2
        where = (f"beyond the reach of links 2-3 (distance {d:.6g}{u} from axis 2, reach "
                 f"{reach:.6g}{u})" if d > reach else
                 f"too close to axis 2 for links 2-3 (distance {d:.6g}{u}, the folded arm "
                 f"reaches no closer than {abs(fam.L1 - fam.L2):.6g}{u})")
        excess = float(np.linalg.norm(move[0]))
        return f"axis 4 is {excess:.4g}{u} {where}" + rounding_note(arm, p[0]), excess

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable` for this arm: a rounded pose's pitch
        axis levelled (the flange turned about its origin), then the flange moved so that
        the tool's point on axis 4 is on the arm's plane and within reach. Returns the poses
        ``(N, 4, 4)`` (world), how far each was from reachable ``(N,)`` (length units: the
        move and the tilt times the arm's size, in quadrature) and which were close (a tilt
        and a move within ``ROUNDED_POSE_TOL``, the move relative to the arm's size)."""
        F = arm._world_to_base(T_world)
        u = F[:, :3, :3] @ self.u_n
        n = np.cross(u, self.w1)
        s = np.linalg.norm(n, axis=-1)
        tilt = math.asin(self.level) - np.arcsin(np.clip(u @ self.w1, -1.0, 1.0))
        F[:, :3, :3] = _turn(F[:, :3, :3], n * (tilt / np.where(s > 0.0, s, 1.0))[:, None])
        q1, _, p, _ = self._unturned(F)
        _, move = self._gaps(p)
        F[:, :3, 3] += rotate(self.w1, q1, move)
        dist = np.linalg.norm(move, axis=-1)
        close = (np.abs(tilt) <= ROUNDED_POSE_TOL) & (
            dist <= ROUNDED_POSE_TOL * rounding_size(arm, p))
        out = arm.base @ F @ arm.tool
        return out, np.hypot(dist, tilt * arm.scale), close
