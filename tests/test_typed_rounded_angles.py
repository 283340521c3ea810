"""A course arm typed with a right angle rounded (1.571 for pi/2, 3.142 for pi) is another
arm, outside its family: the refusal names the rounded angle and says to type it exactly.

A student copies a DH table from a slide that prints 1.571 or 3.142; the arm they typed
then has axes a fraction of a degree off parallel or off the wrist's +-90 deg, and no
closed form fits it. The one-line reason must lead back to the number they typed, not
only to the geometry it produced; the exact table still solves, FK-checked.
"""

import re

import numpy as np
import pytest

from rikin import InputError, Link, SerialArm
from rikin.ik import classify

pi = np.pi


def stanford(quarter):
    """The Stanford arm (RRPRRR) with ``quarter`` written for pi/2."""
    return SerialArm((
        Link(d=0.412, alpha=-quarter), Link(d=0.154, alpha=quarter),
        Link("P", theta=-quarter, a=0.0203), Link(alpha=-quarter),
        Link(alpha=quarter), Link(d=0.263)))


def scara(half):
    """A SCARA (RRP) with ``half`` written for pi."""
    return SerialArm((Link(d=0.4, a=0.35), Link(a=0.25, alpha=half), Link("P")))


def planar_3r_angular_typo(quarter):
    """An angular 3R with ``quarter`` written for pi/2."""
    return SerialArm((Link(d=0.4, alpha=quarter), Link(a=0.5), Link(a=0.4)))


ROUNDED = [
    (stanford, 1.571, pi / 2, "90"),
    (stanford, 1.5708, pi / 2, "90"),
    (scara, 3.142, pi, "180"),
    (scara, 3.14, pi, "180"),
    (planar_3r_angular_typo, 1.571, pi / 2, "90"),
]


@pytest.mark.parametrize("make, typed, exact, degrees", ROUNDED)
def test_a_rounded_right_angle_is_named_in_the_reason_and_in_the_error(
        make, typed, exact, degrees):
    arm = make(typed)
    verdict = classify(arm)
    if verdict.closed_form:  # rounding did not break the family: it must solve, FK-checked
        q = np.random.default_rng(3).uniform(-1, 1, arm.n)
        T = arm.fk(q)
        res = arm.ik(T)
        assert np.abs(arm.fk(res.q) - T).max() < 1e-9
        return
    reason = verdict.reason
    assert f"{typed:g}" in reason, reason
    assert re.search(rf"\b{degrees} deg\b", reason), reason
    assert "exactly" in reason and "numpy.pi" in reason, reason
    with pytest.raises(InputError) as err:
        arm.ik(arm.fk(np.full(arm.n, 0.3)))
    assert f"{typed:g}" in str(err.value) and "\n" not in str(err.value)
    # typed exactly, the same arm is in its family and every solution reaches the target
    exact_arm = make(exact)
    assert classify(exact_arm).closed_form
    q = np.random.default_rng(4).uniform(0.2, 1.0, exact_arm.n)
    T = exact_arm.fk(q)
    res = exact_arm.ik(T if exact_arm.n == 6 else T[:3, 3])
    F = exact_arm.fk(res.q)
    assert len(res) >= 1
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max() < 1e-9
    assert np.abs(res.q - q).max(axis=1).min() < 1e-9


def test_a_twist_that_truly_leans_gets_no_rounding_hint():
    # 0.3 deg is a lean (the book's example), not a rounding of a right angle
    leaning = SerialArm((Link(d=0.4, a=0.35, alpha=np.radians(0.3)),
                         Link(a=0.25, alpha=pi), Link("P")))
    reason = classify(leaning).reason
    assert not classify(leaning).closed_form
    assert "exactly" not in reason and "SCARA" in reason
