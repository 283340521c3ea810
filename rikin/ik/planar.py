"""Geometric IK of the planar 2R and 3R arms of Aula 23 (law of cosines).

Planar 3R: the wrist point ``(x - l3 cos phi, y - l3 sin phi)`` is reached by
the 2R made of links 1-2 (two elbows), then ``q3 = phi - q1 - q2``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import SINGULAR_TOL
from .anthropomorphic import RRRGeometry, rrr_gap
from .api import ClosedForm
from .base import RawSolutions, Singularity
from .kernels import elbow_above, reach_excess, two_link_parts, two_link_slots
from .reach import nearest_reachable, rounding_note
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

_ELBOW = Singularity("the arm is fully stretched or folded: both elbow branches coincide", ())
_ORIGIN = Singularity(
    "links 1 and 2 are equal and folded, so the wrist point is on the axis of joint 1 and "
    "q1 is free",
    (1,),
)


def _lengths(arm: SerialArm, n: int) -> list[float]:
    if arm.convention != "standard" or arm.joint_types != "R" * n or any(
        float(lk.d) != 0 or float(lk.alpha) != 0 or float(lk.offset) != 0 for lk in arm.links
    ):
        raise InputError(
            f"{arm.name}: the planar {n}R solver needs {n} revolute standard-DH links with "
            "d = alpha = offset = 0"
        )
    return [float(lk.a) for lk in arm.links]


def _in_plane(T: FloatArray, size: float, need_rotation: bool) -> np.ndarray:
    ok = np.abs(T[:, 2, 3]) <= SINGULAR_TOL * size * 10
    if need_rotation:
        ok &= np.abs(T[:, 2, 2] - 1.0) <= 1e-9
    return ok


def _explain_plane(T: FloatArray, units: str, size: float, need_rotation: bool) -> str | None:
    u = f" {units}" if units else ""
    if abs(T[2, 3]) > SINGULAR_TOL * size * 10:
        return f"the target is {abs(T[2, 3]):.4g}{u} out of the arm's plane (z must be 0)"
    if need_rotation and abs(T[2, 2] - 1.0) > 1e-9:
        tilt = float(np.degrees(np.arccos(np.clip(T[2, 2], -1, 1))))
        return f"the target's orientation is tilted {tilt:.4g} deg out of the plane (z axes differ)"
    return None


class _PlanarBase(ClosedForm):
    wrist_middle = None
    singularities = {"elbow": _ELBOW, "origin": _ORIGIN}
    n = 2

    def _two(
        self, x: FloatArray, y: FloatArray, L1: float, L2: float, hint1: float
    ) -> tuple[FloatArray, FloatArray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        t = two_link_parts(x, y, L1, L2)
        A, B = two_link_slots(t)
        A = np.where(t.fold[:, None], hint1, A)
        up = elbow_above(x, y, A, L1)
        return A, B, t.reachable, t.stretched, t.fold, up

    def _explain_reach(
        self, arm: SerialArm, p: FloatArray, L1: float, L2: float, what: str
    ) -> tuple[str, float]:
        """Why the point ``p (3,)`` (base frame) is out of reach of links 1-2."""
        d = float(np.hypot(p[0], p[1]))
        ex = float(reach_excess(np.array(d), L1, L2))
        u = f" {arm.units}" if arm.units else ""
        note = rounding_note(arm, p)
        if d > L1 + L2:
            return (
                f"{what} is {ex:.4g}{u} beyond the reach of links 1-2 "
                f"(distance {d:.6g}{u} from joint 1, reach {L1 + L2:.6g}{u})" + note,
                ex,
            )
        return (
            f"{what} is {ex:.4g}{u} too close to joint 1 for links 1-2 "
            f"(distance {d:.6g}{u}, the folded arm reaches no closer than {abs(L1 - L2):.6g}{u})"
            + note,
            ex,
        )

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable`: the point links 1-2 place (the target,
        or the 3R's wrist point) moved onto the annulus they sweep."""
        L1, L2, *rest = _lengths(arm, arm.n)
        centre = np.array([-rest[0], 0.0, 0.0]) if rest else np.zeros(3)
        return nearest_reachable(arm, rrr_gap(RRRGeometry(0.0, 0.0, L1, L2)), T_world, centre)


class Planar2RSolver(_PlanarBase):
    """IK of the planar 2R arm: up to 2 solutions (elbow up and down)."""

    target_kind = "planar_position"
    count = 2

    def check(self, arm: SerialArm) -> None:
        _lengths(arm, 2)

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        L1, L2 = _lengths(arm, 2)
        x, y = T_0_n[:, 0, 3], T_0_n[:, 1, 3]
        A, B, ok, st, origin, up = self._two(x, y, L1, L2, 0.0 if hint is None else hint[0])
        ok &= _in_plane(T_0_n, L1 + L2, False)
        q = np.stack([A, B], axis=-1)
        return _two_slots(q, ok, st, origin, up)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        L1, L2 = _lengths(arm, 2)
        plane = _explain_plane(T_0_n, arm.units, L1 + L2, False)
        if plane:
            return plane, abs(float(T_0_n[2, 3]))
        return self._explain_reach(arm, T_0_n[:3, 3], L1, L2, "the target")


def _two_slots(q: FloatArray, ok: np.ndarray, stretched: np.ndarray, origin: np.ndarray,
               up: np.ndarray) -> RawSolutions:
    """The two elbow solutions of a planar arm; per-pose flags (N,) apply to both slots."""
    both = lambda m: np.repeat(m[:, None], 2, axis=1)  # noqa: E731
    return RawSolutions(
        q=q,
        valid=both(ok),
        slots=(Branch(), Branch()),
        elbow_up=up,
        singular={"elbow": both(stretched), "origin": both(origin)},
    )


class Planar3RSolver(_PlanarBase):
    """IK of the planar 3R arm for ``(x, y, phi)``: up to 2 solutions."""

    target_kind = "planar_pose"
    count = 2

    def check(self, arm: SerialArm) -> None:
        _lengths(arm, 3)

    @staticmethod
    def wrist_point(T_0_n: FloatArray, L3: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Tool angle ``phi`` and the wrist point ``(x - L3 cos phi, y - L3 sin phi)``, (N,)."""
        phi = np.arctan2(T_0_n[:, 1, 0], T_0_n[:, 0, 0])
        return phi, T_0_n[:, 0, 3] - L3 * np.cos(phi), T_0_n[:, 1, 3] - L3 * np.sin(phi)

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        L1, L2, L3 = _lengths(arm, 3)
        phi, e, c = self.wrist_point(T_0_n, L3)
        A, B, ok, st, origin, up = self._two(e, c, L1, L2, 0.0 if hint is None else hint[0])
        ok &= _in_plane(T_0_n, L1 + L2 + L3, True)
        q = np.stack([A, B, phi[:, None] - A - B], axis=-1)
        return _two_slots(q, ok, st, origin, up)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        L1, L2, L3 = _lengths(arm, 3)
        plane = _explain_plane(T_0_n, arm.units, L1 + L2 + L3, True)
        if plane:
            return plane, abs(float(T_0_n[2, 3]))
        _, e, c = self.wrist_point(T_0_n[None], L3)
        return self._explain_reach(
            arm, np.array([e[0], c[0], 0.0]), L1, L2, "the wrist point (target minus link 3)"
        )
