"""Position IK of the anthropomorphic (angular) RRR arm: joint 1 vertical, joints 2 and 3 parallel.

The same geometry positions the wrist centre of the 6R arms (Aula 10,
Barrientos, Epson C4), so it is written once here. In the vertical plane
that joint 1 turns, with ``u`` horizontal (away from axis 1) and ``w`` up:

* the shoulder (axis 2) sits at ``u = r0``, ``w = z0``;
* the upper arm, length ``L2``, points at angle ``A = q2 + phi2``;
* the forearm, length ``L3``, points at ``A + B`` with ``B = q3 + phi3``.

Four slots: (front, B >= 0), (front, B <= 0), (back, B >= 0), (back, B <= 0).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import AXIS_TOL
from .api import ClosedForm
from .base import RawSolutions, Singularity
from .kernels import elbow_above, reach_excess, two_link_parts, two_link_slots
from .reach import Gap, nearest_reachable, rounding_note
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

ARM_SLOTS = (("front", 0), ("front", 1), ("back", 0), ("back", 1))


@dataclass(frozen=True)
class RRRGeometry:
    """The in-plane geometry of an anthropomorphic arm (lengths in the arm's units, angles rad)."""

    z0: float
    r0: float
    L2: float
    L3: float
    phi2: float = 0.0
    phi3: float = 0.0

    @property
    def size(self) -> float:
        """A length for relative tolerances."""
        return abs(self.z0) + abs(self.r0) + self.L2 + self.L3

    def forward(self, q: FloatArray) -> FloatArray:
        """End point of the RRR chain for joints ``q`` of shape ``(..., 3)``, shape ``(..., 3)``."""
        A = q[..., 1] + self.phi2
        B = q[..., 2] + self.phi3
        u = self.r0 + self.L2 * np.cos(A) + self.L3 * np.cos(A + B)
        w = self.z0 + self.L2 * np.sin(A) + self.L3 * np.sin(A + B)
        return np.stack([u * np.cos(q[..., 0]), u * np.sin(q[..., 0]), w], axis=-1)


@dataclass
class RRRPosition:
    """Output of :func:`position_rrr` (N targets, 4 slots)."""

    q: FloatArray            # (N, 4, 3)
    valid: np.ndarray        # (N, 4)
    elbow_up: np.ndarray     # (N, 4)
    shoulder_singular: np.ndarray  # (N, 4)
    elbow_singular: np.ndarray     # (N, 4)
    fold_singular: np.ndarray      # (N, 4): L2 = L3 folded onto axis 2, q2 free


def position_rrr(
    p: FloatArray,
    g: RRRGeometry,
    hint_q1: FloatArray | float = 0.0,
    hint_q2: FloatArray | float = 0.0,
) -> RRRPosition:
    """All joint triples putting the RRR end point at ``p`` of shape ``(N, 3)``.

    On axis 1 (within ``AXIS_TOL`` of the arm's size) q1 takes ``hint_q1``; with
    equal links folded onto axis 2, q2 takes ``hint_q2``.
    """
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    rho = np.hypot(x, y)
    on_axis = rho <= AXIS_TOL * g.size
    q1 = np.where(on_axis, hint_q1, np.arctan2(y, x))
    w = z - g.z0
    N = p.shape[0]
    q = np.empty((N, 4, 3))
    valid = np.empty((N, 4), dtype=bool)
    up = np.empty((N, 4), dtype=bool)
    stretched = np.empty((N, 4), dtype=bool)
    fold = np.empty((N, 4), dtype=bool)
    for k, (side, u) in enumerate(((0, rho - g.r0), (1, -rho - g.r0))):
        t = two_link_parts(u, w, g.L2, g.L3)
        A, B = two_link_slots(t)
        A = np.where(t.fold[:, None], np.asarray(hint_q2) + g.phi2, A)
        sl = slice(2 * k, 2 * k + 2)
        q[:, sl, 0] = (q1 + side * np.pi)[:, None]
        q[:, sl, 1] = A - g.phi2
        q[:, sl, 2] = B - g.phi3
        valid[:, sl] = t.reachable[:, None]
        stretched[:, sl] = t.stretched[:, None]
        fold[:, sl] = t.fold[:, None]
        up[:, sl] = elbow_above(u, w, A, g.L2)
    shoulder = np.broadcast_to(on_axis[:, None], (N, 4))
    return RRRPosition(q, valid, up, shoulder, stretched, fold)


def rrr_gap(g: RRRGeometry) -> Callable[[FloatArray, np.ndarray | None], Gap]:
    """The ``gap`` of :func:`rikin.ik.reach.nearest_reachable` for points ``p (N, 3)`` the
    RRR chain places (base frame): the signed distance of ``p`` from the shell joints 2-3
    sweep around the shoulder (``d - L2 - L3`` beyond it, ``d - |L2 - L3|`` inside its
    inner radius, 0 between), of the front arm (row 0) or the back one (row 1), whichever
    is nearer on the first call; and its gradient. In the vertical plane through axis 1
    and ``p``, the set is the annulus around the shoulder, so the nearest point lies in
    that plane, along the line from the shoulder (the planar arms: ``z0 = r0 = 0``)."""
    Lp, Lm = g.L2 + g.L3, abs(g.L2 - g.L3)

    def gap(p: FloatArray, active: np.ndarray | None) -> Gap:
        rho = np.hypot(p[:, 0], p[:, 1])
        u = np.stack([rho - g.r0, rho + g.r0], axis=-1)  # front, back (mirrored): (N, 2)
        w = (p[:, 2] - g.z0)[:, None]
        d = np.hypot(u, w)
        r = d - np.clip(d, Lm, Lp)
        if active is None:
            front = np.abs(r[:, 0]) <= np.abs(r[:, 1])
            active = np.stack([front, ~front], axis=-1)
        active = active & (d > 0)  # no direction is nearest at the shoulder itself
        safe_d = np.where(active, d, 1.0)
        # the horizontal direction away from axis 1; on the axis every one is as near (the
        # arm straight up), and x is taken
        safe_rho = np.where(rho > 0, rho, 1.0)
        cx, cy = np.where(rho > 0, p[:, 0] / safe_rho, 1.0), p[:, 1] / safe_rho
        J = np.zeros((len(p), 2, 3))
        J[..., 0] = u / safe_d * cx[:, None]
        J[..., 1] = u / safe_d * cy[:, None]
        J[..., 2] = w / safe_d
        J[~active] = 0.0
        return np.where(active, r, 0.0), J, active

    return gap


def explain_rrr(
    p: FloatArray, g: RRRGeometry, units: str, what: str, note: str = ""
) -> tuple[str, float]:
    """Why the point ``p (3,)`` is out of reach of the RRR chain, and by how much
    (``note``, e.g. :func:`rikin.ik.reach.rounding_note`, ends the sentence)."""
    rho = float(np.hypot(p[0], p[1]))
    w = float(p[2] - g.z0)
    d_front = float(np.hypot(rho - g.r0, w))
    d_back = float(np.hypot(-rho - g.r0, w))
    ex = float(min(reach_excess(np.array(d_front), g.L2, g.L3),
                   reach_excess(np.array(d_back), g.L2, g.L3)))
    d = d_front if g.r0 <= 0 or d_front < d_back else d_back
    u = f" {units}" if units else ""
    if d > g.L2 + g.L3:
        return (f"{what} is {ex:.4g}{u} beyond the reach of links 2-3 "
                f"(it is {d:.6g}{u} from the shoulder axis; links 2-3 reach {g.L2 + g.L3:.6g}{u})"
                + note, ex)
    return (f"{what} is {ex:.4g}{u} too close to the shoulder axis for links 2-3 "
            f"(distance {d:.6g}{u}, the folded arm reaches no closer than "
            f"{abs(g.L2 - g.L3):.6g}{u})"
            + note, ex)


SHOULDER = Singularity("the wrist centre is on the axis of joint 1, so q1 is free", (1,),
                       drop_back=True)
ELBOW = Singularity("the arm is fully stretched or folded (elbow at 0 or pi): the two elbow "
                    "branches coincide", ())
FOLD = Singularity("links 2 and 3 are equal and folded, so the end of link 3 is on the axis of "
                   "joint 2 and q2 is free", (2,))


def check_rrr_geometry(
    arm: SerialArm, g: RRRGeometry, point_of: Callable[[FloatArray], FloatArray], family: str
) -> None:
    """Raise InputError unless the arm's FK matches ``g`` at a few random joint values."""
    rng = np.random.default_rng(0)
    q = rng.uniform(-np.pi, np.pi, size=(5, arm.n))
    flange = arm._flange._fk(q)
    got = point_of(flange)
    want = g.forward(q[:, :3])
    if np.abs(got - want).max() > 1e-9 * g.size:
        raise InputError(f"{arm.name}: its DH table is not of the {family} family this solver "
                         "handles (its FK does not match the family's geometry)")


class Angular3RSolver(ClosedForm):
    """Position IK of the angular 3R arm of Aula 23: up to 4 solutions."""

    target_kind = "position"
    wrist_middle = None
    count = 4
    singularities = {"shoulder": Singularity("the target is on the axis of joint 1, so q1 is free",
                                             (1,), drop_back=True),
                     "elbow": ELBOW, "fold": FOLD}

    def __init__(self, geometry: RRRGeometry) -> None:
        self.geometry = geometry

    def check(self, arm: SerialArm) -> None:
        if arm.joint_types != "RRR":
            raise InputError(
                f"{arm.name}: the angular 3R solver needs an RRR arm, got {arm.joint_types}"
            )
        check_rrr_geometry(arm, self.geometry, lambda F: F[:, :3, 3], "angular 3R")

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        h1, h2 = (0.0, 0.0) if hint is None else (hint[0], hint[1])
        pos = position_rrr(T_0_n[:, :3, 3], self.geometry, h1, h2)
        slots = tuple(Branch(side, None, None) for side, _ in ARM_SLOTS)
        return RawSolutions(q=pos.q, valid=pos.valid, slots=slots, elbow_up=pos.elbow_up,
                            singular={"shoulder": pos.shoulder_singular,
                                      "elbow": pos.elbow_singular,
                                      "fold": pos.fold_singular & pos.valid})

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable`: the target moved onto the shell."""
        return nearest_reachable(arm, rrr_gap(self.geometry), T_world, np.zeros(3))

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        p = T_0_n[:3, 3]
        return explain_rrr(p, self.geometry, arm.units, "the target", rounding_note(arm, p))
