"""Three leftovers of issue 29 for an arm typed as a table:

* ``IKResult.table()`` (what ``print(arm.ik(T))`` shows) marks a joint its data sheet counts
  against the DH z axis, as ``solutions_table(arm=)`` does;
* a header's units are read, not dropped: ``d (mm)`` names the arm's units, and a header
  rikin would have to guess at (lengths in two units, a prismatic joint's limits in mm beside
  a table in m, an angle unit on a length column, a unit rikin does not know) is refused;
* ``classify`` says "quadratic" for the spherical-wrist arms whose position problem the
  solver solves as a quadratic (the KUKA KR 5 kind), "quartic" only where it is one.
"""

from __future__ import annotations

import numpy as np
import pytest

from rikin import InputError, robots
from rikin.dhtext import arm_from_table
from rikin.ik import classify
from rikin.ik.pieper import Pieper6RSolver
from rikin.ik.pieper_kernel import PieperKernel

pi = np.pi


def _header_line(text: str) -> str:
    return text.splitlines()[0]


def test_print_of_a_result_marks_the_reversed_joints():
    arm = robots.kuka_kr5_arc()
    assert arm.reversed_joints == (1, 4, 6)
    T = arm.fk(np.radians([10, -30, 40, 20, 30, 40]))
    for res in (arm.ik(T), arm.ik(T, within_limits=True)):
        head = _header_line(res.table()).split()
        assert head[2:] == ["q1(-z)", "q2", "q3", "q4(-z)", "q5", "q6(-z)"]
        assert "q4(-z)" in repr(res)
        assert list(res.directions) == [-1, 1, 1, -1, 1, -1]


def test_a_result_of_an_arm_with_no_reversed_joint_is_printed_as_before():
    arm = robots.aula10_6r()
    res = arm.ik(arm.fk([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]))
    assert _header_line(res.table()).split()[2:] == [f"q{j}" for j in range(1, 7)]


TABLE = """type theta d{d} a{a} alpha {limits}
R q1 300 0 90 -170..170
P 0 q2 0 0 0..500
R q3 0 200 0 none"""


def test_a_length_unit_in_the_header_names_the_arms_units():
    arm = arm_from_table(TABLE.format(d=" (mm)", a="(mm)", limits="limits (mm)"))
    assert arm.units == "mm"
    assert arm.links[1].qlim == (0.0, 500.0)
    assert np.allclose(arm.links[0].qlim, np.radians([-170, 170]))
    assert arm_from_table(TABLE.format(d="", a="", limits="limits")).units == ""
    assert arm_from_table(TABLE.format(d=" (mm)", a="", limits="limits"), units="mm").units == "mm"


@pytest.mark.parametrize("d, a, limits, units, said", [
    (" (m)", " (m)", "limits (mm)", "", "lengths in m and mm"),
    (" (m)", "", "limits", "mm", "the arm's units are 'mm'"),
    (" (deg)", "", "limits", "", "column d (deg) holds lengths"),
    ("", " [rad]", "limits", "", "column a (rad) holds lengths"),
    ("", " (ft)", "limits", "", "not 'ft'"),
])
def test_a_header_whose_units_would_be_guessed_at_is_refused(d, a, limits, units, said):
    with pytest.raises(InputError, match=said.replace("(", r"\(").replace(")", r"\)")):
        arm_from_table(TABLE.format(d=d, a=a, limits=limits), units=units)


def test_an_angle_column_with_a_length_unit_is_refused():
    with pytest.raises(InputError, match=r"column alpha \(mm\) holds angles"):
        arm_from_table("theta d a alpha (mm)\nq1 0 1 0")


def _kernel_planar(arm) -> bool:
    return bool(PieperKernel(Pieper6RSolver(arm), arm).planar)


# a skew arm whose axes 1 and 2 are not perpendicular, and one whose elbow leaves the plane
SKEW_60 = "R 0.4 0.18 60\nR 0 0.6 0\nR 0 0.12 90\nR 0.62 0 -90\nR 0 0 90\nR 0.1 0 0"
SKEW_TWISTED_ELBOW = "R 0.4 0.18 -90\nR 0 0.6 30\nR 0 0.12 90\nR 0.62 0 -90\nR 0 0 90\nR 0.1 0 0"


@pytest.mark.parametrize("arm", [
    robots.kuka_kr5_arc(), robots.fanuc_lrmate200id(), arm_from_table(SKEW_60),
    arm_from_table(SKEW_TWISTED_ELBOW),
], ids=["KR 5 arc", "LR Mate 200iD", "skew 60 deg", "skew, elbow twisted"])
def test_classify_says_quadratic_exactly_where_the_solver_solves_a_quadratic(arm):
    verdict = str(classify(arm))
    planar = _kernel_planar(arm)
    assert ("quadratic equation" in verdict) == planar, verdict
    assert ("quartic" in verdict) == (not planar), verdict
    assert "up to 8 solutions" in verdict


def test_the_kr5_kind_is_the_planar_case():
    assert _kernel_planar(robots.kuka_kr5_arc())
    assert not _kernel_planar(arm_from_table(SKEW_60))
