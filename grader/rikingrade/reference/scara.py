"""Reference FK/IK of the SCARA (RRP) exercise arm, with and without the wrist.

Standard DH (joint variable in brackets; the quill moves down, ``q3 >= 0``):

====  =====  =======  ======  ===  =====
row   joint  theta    d       a    alpha
====  =====  =======  ======  ===  =====
1     R      [q1]     l1      l2   0
2     R      [q2]     0       l3   pi
3     P      0        [q3]    0    0
====  =====  =======  ======  ===  =====

``p = (l2 c1 + l3 c12, l2 s1 + l3 s12, l1 - q3)``; at q = 0 the arm is
stretched along x0 with the TCP at ``(l2 + l3, 0, l1)``; z3 points down.

Two solutions, elbow right (q2 > 0: seen from above, the elbow lies to the
right of the line from the base to the TCP) and elbow left (q2 < 0); one at
full reach (q2 = 0) or folded (q2 = pi). Unreachable: horizontal distance
above l2 + l3 or below |l2 - l3|, or z above l1 (the quill would retract).
"""

from __future__ import annotations

import numpy as np

from rikin import Link, UnreachableError

from ..i18n import N_
from ._common import NEAR_SINGULAR, REACH_TOL, SINGULAR_TOL, STRETCH_TOL, ExerciseArm

__all__ = ["ARM", "Scara", "ELBOW_RIGHT", "ELBOW_LEFT"]

ELBOW_RIGHT = N_("elbow right (q2 > 0)")
ELBOW_LEFT = N_("elbow left (q2 < 0)")


class Scara(ExerciseArm):
    name = "scara"
    title = "SCARA RRP arm"
    lengths = ("l1", "l2", "l3")
    joint_types = "RRP"

    def links(self, l1: float, l2: float, l3: float) -> list[Link]:  # type: ignore[override]
        return [Link("R", d=l1, a=l2), Link("R", a=l3, alpha=np.pi), Link("P")]

    def _position_ik(self, p, L):
        x, y, z = p
        l1, l2, l3 = L["l1"], L["l2"], L["l3"]
        tol = REACH_TOL * self.scale(L)
        q3 = l1 - z
        if q3 < -tol:
            raise UnreachableError(
                f"z = {z:.6g} is above l1 = {l1:.6g}: the quill (joint 3) would have to retract "
                f"by {-q3:.6g} (prismatic joints only extend, q >= 0)",
                excess=-q3,
            )
        q3 = max(q3, 0.0)
        rho = float(np.hypot(x, y))
        if rho > l2 + l3 + tol:
            raise UnreachableError(
                f"the target is {rho:.6g} from the z0 axis, beyond the full reach "
                f"l2 + l3 = {l2 + l3:.6g} by {rho - l2 - l3:.6g}",
                excess=rho - l2 - l3,
            )
        if rho < abs(l2 - l3) - tol:
            raise UnreachableError(
                f"the target is {rho:.6g} from the z0 axis, inside the circle of radius "
                f"|l2 - l3| = {abs(l2 - l3):.6g} the folded arm cannot enter",
                excess=abs(l2 - l3) - rho,
            )
        c2 = float(np.clip((rho**2 - l2**2 - l3**2) / (2 * l2 * l3), -1.0, 1.0))
        if 1.0 - abs(c2) < STRETCH_TOL:
            q2 = 0.0 if c2 > 0 else np.pi
            if rho < SINGULAR_TOL * self.scale(L):  # folded with l2 == l3: at the base axis
                return [(np.array([0.0, q2, q3]), N_("folded onto the base axis (q1 free)"), (0,))]
            q1 = np.arctan2(y, x) - (0.0 if c2 > 0 else np.arctan2(0.0, l2 - l3))
            label = N_("stretched (q2 = 0)") if c2 > 0 else N_("folded (q2 = pi)")
            return [(np.array([q1, q2, q3]), label, ())]
        out = []
        for sign, label in ((1.0, ELBOW_RIGHT), (-1.0, ELBOW_LEFT)):
            s2 = sign * np.sqrt(1.0 - c2 * c2)
            q2 = np.arctan2(s2, c2)
            q1 = np.arctan2(y, x) - np.arctan2(l3 * s2, l2 + l3 * c2)
            out.append((np.array([q1, q2, q3]), label, ()))
        return out

    def sample_lengths(self, rng):
        while True:
            L = {
                "l1": float(rng.uniform(3.0, 10.0)),
                "l2": float(rng.uniform(2.0, 10.0)),
                "l3": float(rng.uniform(2.0, 10.0)),
            }
            if abs(L["l2"] - L["l3"]) >= 0.5:
                return L

    def sample_q(self, rng, L):
        q2 = rng.uniform(0.25, np.pi - 0.25) * rng.choice([-1.0, 1.0])
        return np.array([rng.uniform(-np.pi, np.pi), q2, rng.uniform(0.2, 10.0)])

    def sample_special_q(self, rng, L, i=0):
        q = self.sample_q(rng, L)
        if i % 2:
            q[1] = np.pi
            return N_("fully folded (q2 = pi)"), q
        q[1] = 0.0
        return N_("at full reach (elbow straight, q2 = 0)"), q

    def sample_near_special_q(self, rng, L, i=0):
        """The elbow NEAR_SINGULAR rad from straight (i even) or folded (i odd)."""
        q = self.sample_q(rng, L)
        side = rng.choice([-1.0, 1.0])
        q[1] = side * (np.pi - NEAR_SINGULAR if i % 2 else NEAR_SINGULAR)
        return q

    def unreachable_points(self, rng, L, near=False):
        l2, l3 = L["l2"], L["l3"]
        z_ok = L["l1"] - rng.uniform(0.2, 10.0)
        ang = rng.uniform(-np.pi, np.pi, size=3)
        far = (l2 + l3) + (rng.uniform(0.05, 0.3) if near else (l2 + l3) * rng.uniform(0.05, 0.5))
        inner = abs(l2 - l3) - (
            rng.uniform(0.05, 0.3) * min(1.0, abs(l2 - l3))
            if near
            else abs(l2 - l3) * rng.uniform(0.1, 1.0)
        )
        q = self.sample_q(rng, L)
        q[2] = -(rng.uniform(0.05, 0.3) if near else rng.uniform(0.5, 5.0))
        return [
            (
                "beyond full reach (farther than l2 + l3 from the z0 axis)",
                np.array([far * np.cos(ang[0]), far * np.sin(ang[0]), z_ok]),
            ),
            (
                "inside the inner circle (closer than |l2 - l3| to the z0 axis)",
                np.array([inner * np.cos(ang[1]), inner * np.sin(ang[1]), z_ok]),
            ),
            ("above z = l1 (the quill would retract)", self.fk(q, **L)[:3, 3]),
        ]


ARM = Scara()
