"""Reference FK/IK of the cartesian (PPP) exercise arm, with and without the wrist.

Standard DH (joint variable in brackets; prismatic joints extend, ``q >= 0``):

====  =====  =========  ============  ===  ========
row   joint  theta      d             a    alpha
====  =====  =========  ============  ===  ========
1     P      -pi/2      l1 + [q1]     0    -pi/2
2     P      +pi/2      l2 + [q2]     0    -pi/2
3     P      0          l3 + [q3]     0    0
====  =====  =========  ============  ===  ========

Joint 1 lifts along z0, joint 2 moves along x0, joint 3 along y0, so
``p = (l2 + q2, l3 + q3, l1 + q1)``; at q = 0 the TCP is at ``(l2, l3, l1)``.
``R_0_3 = [[0, -1, 0], [0, 0, 1], [-1, 0, 0]]`` (z3 = y0: the wrist's first
axis continues joint 3's motion). One solution; unreachable when a coordinate
is below its joint's zero position.
"""

from __future__ import annotations

import numpy as np

from rikin import Link, UnreachableError

from ..i18n import N_
from ._common import REACH_TOL, ExerciseArm, excess

__all__ = ["ARM", "Cartesian"]

_AXES = ("z", "x", "y")
_LENGTH_OF = ("l1", "l2", "l3")


class Cartesian(ExerciseArm):
    name = "cartesian"
    title = "cartesian PPP arm"
    lengths = ("l1", "l2", "l3")
    joint_types = "PPP"

    def links(self, l1: float, l2: float, l3: float) -> list[Link]:  # type: ignore[override]
        return [
            Link("P", d=l1, theta=-np.pi / 2, alpha=-np.pi / 2),
            Link("P", d=l2, theta=np.pi / 2, alpha=-np.pi / 2),
            Link("P", d=l3),
        ]

    def _position_ik(self, p, L):
        x, y, z = p
        q = np.array([z - L["l1"], x - L["l2"], y - L["l3"]])
        tol = REACH_TOL * self.scale(L)
        for i in range(3):
            if q[i] < -tol:
                raise UnreachableError(
                    f"{_AXES[i]} = {p[(i + 2) % 3]:.6g} is below {_LENGTH_OF[i]} = "
                    f"{L[_LENGTH_OF[i]]:.6g}: joint {i + 1} would have to retract by {-q[i]:.6g} "
                    "(prismatic joints only extend, q >= 0)",
                    excess=float(-q[i]),
                )
        return [(np.maximum(q, 0.0), N_("the only solution"), ())]

    def sample_lengths(self, rng):
        return {n: float(rng.uniform(1.0, 10.0)) for n in self.lengths}

    def sample_q(self, rng, L):
        return rng.uniform(0.5, 10.0, size=3)

    def unreachable_points(self, rng, L, near=False):
        out = []
        for i, what in enumerate(
            (
                "below l1 in z (joint 1 would retract)",
                "below l2 in x (joint 2 would retract)",
                "below l3 in y (joint 3 would retract)",
            )
        ):
            q = self.sample_q(rng, L)
            q[i] = -excess(rng, near)
            out.append((what, self.fk(q, **L)[:3, 3]))  # FK has no joint limits
        return out


ARM = Cartesian()
