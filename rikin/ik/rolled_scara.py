"""The four-axis SCARA: a SCARA whose tool also turns about the vertical (RRPR or RRRP).

The SCARA of most labs has a fourth joint: the quill turns the tool about its own axis,
which is parallel to the arm's two turning axes (tables ``theta1, theta2, d3, theta4``,
RRPR, or with the roll before the quill, ``theta1, theta2, theta3, d4``, RRRP). Four
joints reach four numbers of a pose: where the tool is (3) and its heading about the
vertical (1); its vertical axis is the arm's.

Written on the joint axes at ``q = 0`` (:mod:`rikin.ik.axes`), with ``w`` the common
direction of every axis:

* a point ``c`` on the roll axis, fixed in the flange frame, is not moved by the roll
  (it lies on that axis), nor does the quill move it off that axis' line: joints 1, 2
  and the quill place it exactly as they place the TCP of the three-joint SCARA
  (:class:`rikin.ik.positioning.Scara`: the height gives the quill, then the planar
  two-link chain, elbow right or left);
* turns about parallel axes add up, so the flange's rotation is ``Rot(w, psi) R_n(0)``
  with ``psi = q1 + s2 q2 + s_roll q_roll`` (``s``: +-1, each axis' sense against
  axis 1's): the target's heading gives ``psi`` (the turn about ``w`` that best carries
  ``R_n(0)`` onto the target's rotation, column by column), and then the roll.

A target whose tool axis is tilted from ``w`` is out of reach ("a SCARA turns the tool
only about the vertical"); tilted by rounding only (within ``ROUNDED_POSE_TOL`` rad), it
is solved for the nearest reachable pose, like the other arms' rounded poses.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import REACH_TOL, ROUNDED_POSE_TOL
from .api import ClosedForm
from .axes import ZeroAxes, turn_between
from .base import RawSolutions
from .positioning import Scara, finds_joints, fit_joints
from .reach import _turn, rounding_note, rounding_size

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

#: The joint types of the four-axis SCARA: the roll after the quill, or before it.
TYPES = ("RRPR", "RRRP")


class RolledScaraSolver(ClosedForm):
    """Closed-form IK of a four-axis SCARA (RRPR or RRRP): two solutions (elbow right, left).

    Parameters
    ----------
    arm : SerialArm
        The arm, in DH joint values (its axes at ``q = 0`` are ``ax``).
    ax : ZeroAxes
        The arm's joint axes at ``q = 0``, all parallel (checked by the caller).
    """

    target_kind = "pose"
    wrist_middle = None
    count = 2

    def __init__(self, arm: SerialArm, ax: ZeroAxes) -> None:
        self.types = arm.joint_types
        self.roll, self.slide = (3, 2) if self.types == "RRPR" else (2, 3)
        order = [0, 1, self.slide]
        F_n = ax.frames[-1]
        #: a point of the roll axis and its direction, in the flange frame (frame n)
        self.c_n = F_n[:3, :3].T @ (ax.r[self.roll] - F_n[:3, 3])
        self.u_n = F_n[:3, :3].T @ ax.w[self.roll]
        self.w, self.w_roll = ax.w[0], ax.w[self.roll]
        self.R_n0 = F_n[:3, :3].copy()
        self.senses = np.sign(ax.w[[1, self.roll]] @ self.w)  # joints 2 and roll against 1
        self.family = Scara(ZeroAxes(ax.w[order], ax.r[order], ax.frames, ax.scale),
                            ax.r[self.roll])
        self.slots, self.singularities = self.family.slots, self.family.singularities

    def check(self, arm: SerialArm) -> None:
        """Raise InputError unless this solver finds, at random joint values of ``arm``,
        the joints that made the pose (the fit checked by FK)."""
        if arm.joint_types != self.types:
            raise InputError(f"{arm.name}: the four-axis SCARA solver was fitted to a "
                             f"{self.types} arm, got {arm.joint_types}")
        q = fit_joints(arm)
        raw = self.solve(arm, arm._flange._fk(q), None)
        if not finds_joints(arm, q, raw.q, raw.valid):
            raise InputError(f"{arm.name}: rikin could not fit the four-axis SCARA to this "
                             "table (it misses the joints that made a pose)")

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        """Both solutions of each flange pose ``T_0_n (N, 4, 4)`` (frame 0)."""
        p = T_0_n[:, :3, :3] @ self.c_n + T_0_n[:, :3, 3]
        placed = self.family.place(p, hint)  # (N, 2, 3): q1, q2 and the quill
        psi = turn_between(self.w, self.R_n0, T_0_n[:, :3, :3])
        s2, s_roll = self.senses
        roll = s_roll * (psi[:, None] - placed.q[..., 0] - s2 * placed.q[..., 1])
        q = np.empty(placed.q.shape[:2] + (4,))
        q[..., :2] = placed.q[..., :2]
        q[..., self.slide] = placed.q[..., 2]
        q[..., self.roll] = roll
        # a tool axis tilted from the arm's: no solution (a rounded tilt goes to
        # nearest_reachable), as the 5-DOF arms' wrist centre off their plane
        u = T_0_n[:, :3, :3] @ self.u_n
        level = np.linalg.norm(np.cross(u, self.w), axis=-1) <= 10 * REACH_TOL
        level &= u @ self.w_roll > 0.0
        valid = placed.valid & level[:, None]
        singular = {name: m & level[:, None] for name, m in placed.singular.items()}
        return RawSolutions(q=q, valid=valid, slots=self.slots, singular=singular)

    def _tilt(self, T_0_n: FloatArray) -> float:
        """How far (rad) the target tilts the roll axis from the arm's axes."""
        u = T_0_n[:3, :3] @ self.u_n
        return math.atan2(float(np.linalg.norm(np.cross(u, self.w))), float(u @ self.w_roll))

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        """Why one flange pose ``(4, 4)`` has no solution: a tilted tool, or out of reach."""
        tilt = self._tilt(T_0_n)
        if tilt > ROUNDED_POSE_TOL:
            return (f"a four-axis SCARA turns its tool only about its vertical axes: the target "
                    f"tilts the tool's axis {math.degrees(tilt):.4g} deg from them (a tilt up to "
                    f"{ROUNDED_POSE_TOL:g} rad is taken as rounded)", tilt)
        p = T_0_n[:3, :3] @ self.c_n + T_0_n[:3, 3]
        message, excess = self.family.explain(p, arm.units, "the roll axis")
        return message + rounding_note(arm, p), excess

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable` for this arm: a rounded pose's tool axis
        turned onto the arm's (about the TCP), then the TCP moved so that the roll axis
        is within the reach of links 1-2. Returns the poses ``(N, 4, 4)`` (world), how far
        each was from reachable ``(N,)`` (length units: the TCP's move and the tilt times
        the arm's size, in quadrature) and which were close: tilted by at most
        ``ROUNDED_POSE_TOL`` rad and the TCP moved by at most that times the arm's size
        (or the point's distance from the base, when larger)."""
        B, b = arm.base[:3, :3], arm.base[:3, 3]
        tool_R, tool_p = arm.tool[:3, :3], arm.tool[:3, 3]
        u = T_world[:, :3, :3] @ (tool_R.T @ self.u_n)  # the roll axis, world
        axis = np.cross(u, B @ self.w_roll)
        s = np.linalg.norm(axis, axis=-1)
        tilt = np.arctan2(s, u @ (B @ self.w_roll))
        out = T_world.copy()
        turn = axis * (tilt / np.where(s > 0.0, s, 1.0))[:, None]
        out[:, :3, :3] = _turn(T_world[:, :3, :3], turn)
        c = tool_R.T @ (self.c_n - tool_p)  # the roll axis' point, in the TCP frame
        p_axis = ((out[:, :3, :3] @ c + out[:, :3, 3] - b) @ B)  # base frame
        r, J, _ = self.family.gap(p_axis, None)
        move = -np.einsum("nk,nkj->nj", r, J) @ B.T  # world
        out[:, :3, 3] += move
        dist = np.linalg.norm(move, axis=-1)
        close = (tilt <= ROUNDED_POSE_TOL) & (
            dist <= ROUNDED_POSE_TOL * rounding_size(arm, p_axis))
        return out, np.hypot(dist, tilt * arm.scale), close

