"""The test list of one arm exercise, from the shared factories (weights sum to 10)."""

from __future__ import annotations

from ..reference._common import ExerciseArm
from ..spec import HiddenTest
from ._common import dh_test, fk_test, ik_test, unreachable_test


def exercise_tests(arm: ExerciseArm, special: str = "") -> list[HiddenTest]:
    """The hidden tests of one arm.

    ``special`` names the positioning arm's singular or boundary test (e.g.
    "ik_full_reach"); without it the regular IK test carries its 0.5 points.
    """
    tests = [
        dh_test(arm, 1.0),
        fk_test(arm, False, 1.5, "fk"),
        ik_test(arm, False, 1.5 if special else 2.0, "ik"),
    ]
    if special:
        tests.append(ik_test(arm, False, 0.5, special, special="positioning"))
    tests += [
        unreachable_test(arm, False, 1.0, "ik_unreachable"),
        fk_test(arm, True, 1.5, "fk_6dof"),
        ik_test(arm, True, 2.0, "ik_6dof"),
        ik_test(arm, True, 0.5, "ik_6dof_singular", special="wrist"),
        unreachable_test(arm, True, 0.5, "ik_6dof_unreachable"),
    ]
    return tests
