"""Reference FK/IK of the cylindrical (RPP) exercise arm, with and without the wrist.

Standard DH (joint variable in brackets; prismatic joints extend, ``q >= 0``):

====  =====  =========  ============  ===  ========
row   joint  theta      d             a    alpha
====  =====  =========  ============  ===  ========
1     R      [q1]       l1            0    0
2     P      -pi/2      [q2]          0    -pi/2
3     P      0          l2 + [q3]     0    0
====  =====  =========  ============  ===  ========

Joint 1 turns the column about z0, joint 2 lifts the carriage, joint 3 pushes
the radial arm out: ``p = ((l2 + q3) cos q1, (l2 + q3) sin q1, l1 + q2)``; at
q = 0 the TCP is at ``(l2, 0, l1)``, z3 points radially out.

One solution: the other root, ``q1 + pi`` with radius ``-(l2 + q3)``, would
need ``q3 < -2 l2 < 0``. Unreachable: below ``z = l1`` or closer than ``l2``
to the column axis (which, as l2 > 0, also rules out the axis singularity).
"""

from __future__ import annotations

import numpy as np

from rikin import Link, UnreachableError

from ..i18n import N_
from ._common import REACH_TOL, ExerciseArm, excess

__all__ = ["ARM", "Cylindrical"]


class Cylindrical(ExerciseArm):
    name = "cylindrical"
    title = "cylindrical RPP arm"
    lengths = ("l1", "l2")
    joint_types = "RPP"

    def links(self, l1: float, l2: float) -> list[Link]:  # type: ignore[override]
        return [Link("R", d=l1), Link("P", theta=-np.pi / 2, alpha=-np.pi / 2), Link("P", d=l2)]

    def _position_ik(self, p, L):
        x, y, z = p
        tol = REACH_TOL * self.scale(L)
        r = float(np.hypot(x, y))
        q2 = z - L["l1"]
        q3 = r - L["l2"]
        if q2 < -tol:
            raise UnreachableError(
                f"z = {z:.6g} is below l1 = {L['l1']:.6g}: the lift (joint 2) would have to "
                f"retract by {-q2:.6g} (prismatic joints only extend, q >= 0)",
                excess=-q2,
            )
        if q3 < -tol:
            raise UnreachableError(
                f"the target is {r:.6g} from the column axis, closer than the retracted radial "
                f"arm l2 = {L['l2']:.6g}: joint 3 would have to retract by {-q3:.6g}",
                excess=-q3,
            )
        q = np.array([np.arctan2(y, x), max(q2, 0.0), max(q3, 0.0)])
        return [(q, N_("the only solution"), ())]

    def sample_lengths(self, rng):
        return {"l1": float(rng.uniform(2.0, 10.0)), "l2": float(rng.uniform(1.0, 6.0))}

    def sample_q(self, rng, L):
        return np.array(
            [rng.uniform(-np.pi, np.pi), rng.uniform(0.2, 10.0), rng.uniform(0.2, 10.0)]
        )

    def unreachable_points(self, rng, L, near=False):
        a = self.sample_q(rng, L)
        inside = a.copy()
        inside[2] = -(rng.uniform(0.05, 0.3) if near else rng.uniform(0.1, 0.9) * L["l2"])
        below = self.sample_q(rng, L)
        below[1] = -excess(rng, near)
        axis = self.sample_q(rng, L)
        axis[2] = -L["l2"] if not near else -rng.uniform(0.05, 0.3)
        return [
            ("closer to the column axis than l2", self.fk(inside, **L)[:3, 3]),
            ("below z = l1", self.fk(below, **L)[:3, 3]),
            (
                "on the column axis" if not near else "closer to the column axis than l2",
                self.fk(axis, **L)[:3, 3],
            ),
        ]


ARM = Cylindrical()
