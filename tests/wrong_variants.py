"""Deliberately wrong solutions, made from the solution notebooks by text edits.

Each :class:`Variant` changes a few lines of one solution notebook's code (each
``old`` text must occur exactly once, so a variant cannot silently stop
applying when a solution is edited) and states, per hidden test, which
fraction of that test's weight the bug must cost. The fractions were worked out
by reading the solution code and the tests, not by running the grader; the
reasoning is in each ``why``. Tests missing from ``lost`` must keep full marks.

Facts the reasoning uses (see the solution notebooks):

* ``ik_<arm>_6dof`` calls the student's ``ik_<arm>`` at the wrist centre and
  ``fk_<arm>`` for R_0_3, so a bug in either reaches the 6-DOF IK;
  ``fk_<arm>`` builds its arm from ``dh_table``; ``fk_<arm>_6dof`` is called by
  no other function;
* the reach checks come first in ``ik_<arm>``, so an unreachable target still
  raises when a later line is wrong;
* the wrist-singular branch of ``ik_<arm>_6dof`` has its own formulas, so a bug
  in the regular wrist formulas does not reach it;
* an IK case scores matched / (expected + wrong), so returning one of two
  solutions and nothing wrong scores 1/2, and wrong rows in place of right
  ones score 0; a wrist-singular case of a two-branch arm has two families.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any

WRIST_BOTH = "wrist = [(q4, q5, q6), (q4 + np.pi, -q5, q6 + np.pi)]"
WRIST_ONE = "wrist = [(q4, q5, q6)]"
TOOL_ON = ", tool=rikin.transl(0.0, 0.0, tool))"
TOOL_OFF = ")"


@dataclass(frozen=True)
class Variant:
    arm: str
    name: str
    bug: str
    edits: tuple[tuple[str, str], ...]
    lost: dict[str, float] = field(default_factory=dict)
    why: str = ""

    @property
    def id(self) -> str:
        return f"{self.arm}-{self.name}"


def _flange(arm: str) -> Variant:
    return Variant(arm, "flange", "fk_6dof returns the flange frame 6 instead of the TCP",
                   ((TOOL_ON, TOOL_OFF),), {"fk_6dof": 1.0},
                   "only fk_6dof uses the tool transform; no other function calls fk_6dof")


VARIANTS: list[Variant] = [
    # ------------------------------------------------------------ cartesian
    Variant("cartesian", "sign_error", "DH row 2 with theta = -pi/2 instead of +pi/2",
            (('dict(joint="P", theta=np.pi / 2, d=l2', 'dict(joint="P", theta=-np.pi / 2, d=l2'),),
            {"dh_table": 1, "fk": 1, "fk_6dof": 1, "ik_6dof": 1, "ik_6dof_singular": 1},
            "z2 becomes -y0: frame 3 moves to -y, so the table, both FKs and R_0_3 in the 6-DOF "
            "IK are wrong on every case; ik_cartesian does not use the table; the reach checks "
            "still raise"),
    Variant("cartesian", "missing_branch", "the wrist flip (q4 + pi, -q5, q6 + pi) is missing",
            ((WRIST_BOTH, WRIST_ONE),), {"ik_6dof": 0.5, "ik_6dof_singular": 0.25},
            "1 of 2 solutions on every regular pose; the singular branch returns one row anyway, "
            "but the two poses near the singularity (q5 1e-3 from 0 and pi) are regular: 1 of 2 "
            "there, so 1/2 on 2 of the 4 singular-test poses"),
    Variant("cartesian", "degrees", "the 6-DOF IK returns its (wrist) angles in degrees",
            (("Q[:, revolute] = rikin.wrap_angle(Q[:, revolute])",
              "Q[:, revolute] = np.degrees(rikin.wrap_angle(Q[:, revolute]))"),),
            {"ik_6dof": 1, "ik_6dof_singular": 1},
            "the cartesian positioning arm has no revolute joint, so only the wrist angles turn "
            "into degrees: no 6-DOF row is right (the singular ones have q6 in degrees or "
            "q5 = 180)"),
    _flange("cartesian"),
    Variant("cartesian", "unreachable",
            "no reach check: negative slide extensions are clamped to 0",
            (("if q[i] < -tol:", "if False:"),),
            {"ik_unreachable": 1, "ik_6dof_unreachable": 1},
            "every unreachable target returns a (clamped) solution instead of raising, also at "
            "the wrist centre"),
    # ------------------------------------------------------------ cylindrical
    Variant("cylindrical", "sign_error", "q1 = atan2(-y, x)",
            (("q1 = np.arctan2(y, x)", "q1 = np.arctan2(-y, x)"),),
            {"ik": 1, "ik_6dof": 1, "ik_6dof_singular": 1},
            "q1 is mirrored on every target with y != 0 (random), and the 6-DOF IK inherits it; "
            "q2/q3 and the reach checks are unchanged"),
    Variant("cylindrical", "missing_branch", "the wrist flip is missing",
            ((WRIST_BOTH, WRIST_ONE),), {"ik_6dof": 0.5, "ik_6dof_singular": 0.25},
            "1 of 2 solutions on every regular pose; the singular branch is separate, the two "
            "poses near it are regular (1 of 2 there: 1/2 on 2 of 4)"),
    Variant("cylindrical", "degrees", "q1 returned in degrees",
            (("return np.array([[q1, max(q2, 0.0), max(q3, 0.0)]])",
              "return np.array([[np.degrees(q1), max(q2, 0.0), max(q3, 0.0)]])"),),
            {"ik": 1, "ik_6dof": 1, "ik_6dof_singular": 1},
            "every positioning row is wrong; the 6-DOF IK feeds those degrees to fk_cylindrical, "
            "which either refuses them (rikin: 'looks like degrees') or gives a wrong R_0_3"),
    _flange("cylindrical"),
    Variant("cylindrical", "unreachable", "no reach checks",
            (("if q2 < -tol:", "if False:"), ("if q3 < -tol:", "if False:")),
            {"ik_unreachable": 1, "ik_6dof_unreachable": 1},
            "unreachable targets return clamped or axis solutions instead of raising"),
    # ------------------------------------------------------------ spherical
    Variant("spherical", "sign_error", "q2 = atan2(-h, rho): the boom elevation mirrored",
            (("q2 = np.arctan2(h, rho)", "q2 = np.arctan2(-h, rho)"),),
            {"ik": 1, "ik_on_axis": 1, "ik_6dof": 1, "ik_6dof_singular": 1},
            "both rows (back = pi - q2) reach (rho, -h) instead of (rho, h), h != 0 on every "
            "sampled target; on the axis the boom points down instead of up"),
    Variant("spherical", "swapped_elbow", "front and back elevations swapped between the branches",
            (("front = [q1, q2, q3]", "front = [q1, np.pi - q2, q3]"),
             ("back = [q1 + np.pi, np.pi - q2, q3]", "back = [q1 + np.pi, q2, q3]")),
            {"ik": 1, "ik_on_axis": 1 / 3, "ik_6dof": 1, "ik_6dof_singular": 1},
            "each row pairs q1 of one branch with q2 of the other: both wrong; on the vertical "
            "axis q2 = +-pi/2 and pi - q2 is the same angle, so the 4 targets on it keep their "
            "marks, but near it (2 of 6 targets) q2 != pi - q2: both rows wrong"),
    Variant("spherical", "missing_branch", "the back solution is missing",
            (("Q = np.array([front, back])", "Q = np.array([front])"),),
            {"ik": 0.5, "ik_on_axis": 1 / 6, "ik_6dof": 0.5, "ik_6dof_singular": 0.5},
            "1 of 2 positioning solutions, so 2 of 4 (regular) and 1 of 2 families (singular) for "
            "the 6-DOF arm; on the axis one family is all there is, near it (2 of 6 targets) "
            "there are two: 1/2 there"),
    Variant("spherical", "degrees", "q1, q2 returned in degrees",
            (("Q[:, :2] = rikin.wrap_angle(Q[:, :2])",
              "Q[:, :2] = np.degrees(rikin.wrap_angle(Q[:, :2]))"),),
            {"ik": 1, "ik_on_axis": 1, "ik_6dof": 1, "ik_6dof_singular": 1},
            "every row wrong (on the axis q2 = 90); the 6-DOF IK inherits the degrees"),
    _flange("spherical"),
    Variant("spherical", "unreachable", "no reach check",
            (("if q3 < -1e-9 * (l1 + l2):", "if False:"),),
            {"ik_unreachable": 1, "ik_6dof_unreachable": 1},
            "a target inside the sphere returns a clamped q3 = 0 instead of raising"),
    # ------------------------------------------------------------ SCARA
    Variant("scara", "sign_error", "q6 = atan2(m32, m31) instead of atan2(m32, -m31)",
            (("q6 = np.arctan2(M[2, 1], -M[2, 0])", "q6 = np.arctan2(M[2, 1], M[2, 0])"),),
            {"ik_6dof": 1, "ik_6dof_singular": 0.5},
            "q6 becomes pi - q6 on both wrist branches of every regular pose; the singular "
            "branch uses its own formula, but the 2 of 4 poses near the singularity are regular"),
    Variant("scara", "swapped_elbow", "q1 computed with the other elbow's q2",
            (("q1 = np.arctan2(y, x) - np.arctan2(l3 * s2, l2 + l3 * c2)",
              "q1 = np.arctan2(y, x) + np.arctan2(l3 * s2, l2 + l3 * c2)"),),
            {"ik": 1, "ik_full_reach": 1 / 3, "ik_6dof": 1, "ik_6dof_singular": 1},
            "both elbow rows are wrong on every regular target; at full reach s2 = 0 so the "
            "correction vanishes (4 targets right), but near full reach and near folded (2 of "
            "6) s2 != 0: both rows wrong"),
    Variant("scara", "missing_branch", "the elbow-left solution is missing",
            (("sines = [np.sqrt(1.0 - c2**2), -np.sqrt(1.0 - c2**2)]",
              "sines = [np.sqrt(1.0 - c2**2)]"),),
            {"ik": 0.5, "ik_full_reach": 1 / 6, "ik_6dof": 0.5, "ik_6dof_singular": 0.5},
            "1 of 2 positioning solutions (2 of 4, 1 of 2 families for the 6-DOF arm); at full "
            "reach there is only one solution, which it finds; near it (2 of 6 targets) 1 of 2"),
    Variant("scara", "degrees", "q1, q2 returned in degrees",
            (("Q[:, :2] = rikin.wrap_angle(Q[:, :2])",
              "Q[:, :2] = np.degrees(rikin.wrap_angle(Q[:, :2]))"),),
            {"ik": 1, "ik_full_reach": 1, "ik_6dof": 1, "ik_6dof_singular": 1},
            "every row wrong (q1 in degrees, also at full reach); the 6-DOF IK inherits it"),
    _flange("scara"),
    Variant("scara", "unreachable", "no reach checks (the clipped cosine hides them)",
            (("if q3 < -tol:", "if False:"), ("if rho > l2 + l3 + tol:", "if False:"),
             ("if rho < abs(l2 - l3) - tol:", "if False:")),
            {"ik_unreachable": 1, "ik_6dof_unreachable": 1},
            "beyond reach the clipped cosine gives a stretched 'solution', inside it a folded "
            "one, above the top q3 is clamped to 0: no unreachable target raises"),
]


def apply(nb: Any, variant: Variant) -> Any:
    """A copy of the solution notebook with the variant's edits; ValueError if an edit misses."""
    out = copy.deepcopy(nb)
    for old, new in variant.edits:
        hits = [c for c in out.cells if c.cell_type == "code" and old in c.source]
        count = sum(c.source.count(old) for c in hits)
        if count != 1:
            raise ValueError(f"{variant.id}: {old!r} occurs {count} times in the code cells, "
                             "not once")
        hits[0].source = hits[0].source.replace(old, new)
    return out


def expected_points(variant: Variant, tests: list[Any]) -> dict[str, float]:
    """The points each hidden test must give the variant."""
    names = {t.name for t in tests}
    unknown = set(variant.lost) - names
    if unknown:
        raise ValueError(f"{variant.id}: unknown test names {sorted(unknown)}")
    return {t.name: t.weight * (1.0 - variant.lost.get(t.name, 0.0)) for t in tests}
