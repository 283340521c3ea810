"""A DH table typed as text the way a slide prints it (issue: student run, stu40).

* A twist typed as ``1.5708`` in a degree column (a bare number: degrees) is pi/2 rounded,
  not a twist of 1.5708 deg. Read as degrees, a UR5e typed so still has a closed form (axes
  2, 3 and 4 stay parallel) and ``arm.ik`` answered 4 FK-checked solutions of another arm,
  without a word. The cell is refused, naming its line and column and how to write it.
* A Markdown table whose joint-number column is headed ``#`` (``| # | θ | d | a | α |``)
  lost its header to the comment rule, and its first row was refused as a row of numbers.
"""

from __future__ import annotations

import numpy as np
import pytest

from rikin import InputError
from rikin.dhtext import arm_from_table

pi = np.pi

UR5E = """
| i | theta | d{unit} | a | alpha{angle} |
|---|-------|--------|---|-------|
| 1 | q1 | 0.1625 | 0       | {right}  |
| 2 | q2 | 0      | -0.425  | 0        |
| 3 | q3 | 0      | -0.3922 | 0        |
| 4 | q4 | 0.1333 | 0       | {right}  |
| 5 | q5 | 0.0997 | 0       | -{right} |
| 6 | q6 | 0.0996 | 0       | 0        |
"""


def _ur5e(right: str, angle: str = "") -> str:
    return UR5E.format(unit="", angle=angle, right=right)


@pytest.mark.parametrize("typed", ["1.5708", "1.571", "1,5708", "1.57"])
def test_a_right_angle_in_radians_typed_bare_in_a_degree_column_is_refused(typed):
    with pytest.raises(InputError) as err:
        arm_from_table(_ur5e(typed), units="m", name="UR5e")
    msg = str(err.value)
    assert "DH table line 4" in msg and "column alpha" in msg, msg
    assert "90 degrees in radians" in msg and "pi/2" in msg, msg
    assert "'alpha (rad)'" in msg and "\n" not in msg, msg


@pytest.mark.parametrize("row, column, right", [
    ("R 0.4 0 3.1416 0", "alpha", "180"), ("R 0.4 0 0 -1.5708", "offset", "-90"),
    ("R 0.4 0 0 4.7124", "offset", "270")])
def test_rows_of_numbers_name_the_rounded_column(row, column, right):
    with pytest.raises(InputError) as err:
        arm_from_table(f"{row}\nR 0 0.3 0 0")
    assert f"column {column} = " in str(err.value), err.value
    assert f"write {right} (or {right}°" in str(err.value), err.value


def test_the_same_table_solves_when_its_angles_say_their_unit():
    q = np.radians([10, -60, 80, -30, 45, 20])
    exact = arm_from_table(_ur5e("90"), units="m")
    for text in (_ur5e("pi/2"), _ur5e("90°"), _ur5e("90 deg")):
        assert np.abs(arm_from_table(text, units="m").fk(q) - exact.fk(q)).max() < 1e-15
    # a (rad) column reads the rounded number as radians; "1.5708°" is taken as written
    rad = arm_from_table(_ur5e("1.5708", " (rad)"), units="m")
    assert rad.links[0].alpha == pytest.approx(1.5708, abs=0)
    for text in (_ur5e("1.5708°"), _ur5e("1.5708", " (deg)")):
        assert arm_from_table(text).links[0].alpha == pytest.approx(np.radians(1.5708))
    res = exact.ik(exact.fk(q))
    assert len(res) == 8 and np.abs(res.q - q).max(axis=1).min() < 1e-9


def test_a_small_twist_and_a_plain_angle_are_read_as_degrees():
    arm = arm_from_table("R 0.4 0 1.5 0\nR 0 0.3 0 45\nR 0 0.3 0 3")
    assert arm.links[0].alpha == pytest.approx(np.radians(1.5))
    assert arm.links[1].offset == pytest.approx(pi / 4)
    assert arm.links[2].offset == pytest.approx(np.radians(3))


def test_a_hash_headed_joint_column_is_a_header_not_a_comment():
    text = ("| # | θ | d | a | α |  # the slide's table\n|---|---|---|---|---|\n"
            "| 1 | q1 | 0 | 1 | 0 |\n| 2 | q2 + 90° | 0 | 1 | 0 |  # elbow\n")
    arm = arm_from_table(text)
    assert arm.n == 2
    assert np.allclose(arm.fk([0.0, 0.0])[:3, 3], [1.0, 1.0, 0.0])
    # a comment after the rows of numbers is still one
    assert arm_from_table("R 0 1 0  # upper arm\n# forearm:\nR 0 1 0").n == 2
