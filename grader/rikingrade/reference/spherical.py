"""Reference FK/IK of the spherical (polar, RRP) exercise arm, with and without the wrist.

Standard DH (joint variable in brackets; the prismatic boom extends, ``q3 >= 0``):

====  =====  ==============  ============  ===  ========
row   joint  theta           d             a    alpha
====  =====  ==============  ============  ===  ========
1     R      [q1]            l1            0    +pi/2
2     R      [q2] + pi/2     0             0    +pi/2
3     P      0               l2 + [q3]     0    0
====  =====  ==============  ============  ===  ========

Joint 1 turns about z0, joint 2 raises the boom (q2 = 0: horizontal, q2 > 0:
up), joint 3 extends it: ``p = (0, 0, l1) + (l2 + q3) (cos q2 cos q1,
cos q2 sin q1, sin q2)``; at q = 0 the TCP is at ``(l2, 0, l1)``; z3 points
along the boom.

Two solutions: "front" (q1 = atan2(y, x), |q2| <= pi/2) and "back" (q1 + pi,
q2 -> pi - q2: the boom reaches over the top), same q3. Singular on the
vertical line through the shoulder: q1 is free (one family). Unreachable:
closer than l2 to the shoulder (0, 0, l1).
"""

from __future__ import annotations

import numpy as np

from rikin import Link, UnreachableError

from ..i18n import N_
from ._common import NEAR_SINGULAR, REACH_TOL, SINGULAR_TOL, ExerciseArm

__all__ = ["ARM", "Spherical", "FRONT", "BACK"]

FRONT = N_("front (q1 towards the target, |q2| <= pi/2)")
BACK = N_("back (q1 + pi, the boom over the top)")


class Spherical(ExerciseArm):
    name = "spherical"
    title = "spherical RRP arm"
    lengths = ("l1", "l2")
    joint_types = "RRP"

    def links(self, l1: float, l2: float) -> list[Link]:  # type: ignore[override]
        return [
            Link("R", d=l1, alpha=np.pi / 2),
            Link("R", alpha=np.pi / 2, offset=np.pi / 2),
            Link("P", d=l2),
        ]

    def _position_ik(self, p, L):
        x, y, z = p
        scale = self.scale(L)
        rho = float(np.hypot(x, y))
        h = z - L["l1"]
        dist = float(np.hypot(rho, h))
        q3 = dist - L["l2"]
        if q3 < -REACH_TOL * scale:
            raise UnreachableError(
                f"the target is {dist:.6g} from the shoulder (0, 0, l1), closer than the retracted "
                f"boom l2 = {L['l2']:.6g}: joint 3 would have to retract by {-q3:.6g}",
                excess=-q3,
            )
        q3 = max(q3, 0.0)
        if rho < SINGULAR_TOL * scale:
            return [
                (
                    np.array([0.0, np.copysign(np.pi / 2, h), q3]),
                    N_("on the vertical line through the shoulder (q1 free)"),
                    (0,),
                )
            ]
        q1 = np.arctan2(y, x)
        return [
            (np.array([q1, np.arctan2(h, rho), q3]), FRONT, ()),
            (np.array([q1 + np.pi, np.arctan2(h, -rho), q3]), BACK, ()),
        ]

    def sample_lengths(self, rng):
        return {"l1": float(rng.uniform(2.0, 10.0)), "l2": float(rng.uniform(1.0, 6.0))}

    def sample_q(self, rng, L):
        return np.array(
            [rng.uniform(-np.pi, np.pi), rng.uniform(-1.3, 1.3), rng.uniform(0.2, 10.0)]
        )

    def sample_special_q(self, rng, L, i=0):
        q = self.sample_q(rng, L)
        q[1] = np.pi / 2 * rng.choice([-1.0, 1.0])
        return N_("on the vertical line through the shoulder (q1 free)"), q

    def sample_near_special_q(self, rng, L, i=0):
        """The boom tilted so that frame 3's origin is NEAR_SINGULAR times the arm's size
        from the vertical line through the shoulder."""
        q = self.sample_q(rng, L)
        reach = L["l2"] + q[2]  # distance of the point from the shoulder
        tilt = np.arcsin(min(1.0, NEAR_SINGULAR * self.scale(L) / reach))
        q[1] = rng.choice([-1.0, 1.0]) * (np.pi / 2 - tilt)
        return q

    def unreachable_points(self, rng, L, near=False):
        out = []
        for _ in range(2):
            q = self.sample_q(rng, L)
            q[2] = -(rng.uniform(0.05, 0.3) if near else rng.uniform(0.1, 0.9) * L["l2"])
            out.append(("closer to the shoulder than l2", self.fk(q, **L)[:3, 3]))
        q = self.sample_q(rng, L)
        q[1] = np.pi / 2
        q[2] = -(rng.uniform(0.05, 0.3) if near else L["l2"])
        out.append(
            (
                "above the shoulder, closer than l2" if near else "the shoulder point itself",
                self.fk(q, **L)[:3, 3],
            )
        )
        return out


ARM = Spherical()
