"""The DH panel with the course's smaller arms, typed as a student types them.

A SCARA, a planar arm or any arm with fewer than six joints: the panel's status either
gives the solutions with an FK error measured on what the arm's IK solves (a SCARA
places a point: its orientation follows from the joints and is not a target), or says in
words why there is none. Nothing raises out of the panel (in a notebook, an exception
in the Solve button's callback leaves the panel as it was, with no message).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from rikin import widgets

SCARA = "R 0.4 0.35 0 0\nR 0 0.25 180 0\nP 0 0 0 0"
PLANAR_3R = "R 0 0.5 0 0\nR 0 0.4 0 0\nR 0 0.2 0 0"
# two and three joints outside every family: axis 2 at right angles to axis 1
BENT_2 = "R 0,4 0 90 0\nR 0 0,3 0 0"
BENT_3 = "R 0.4 0 1.5 0\nR 0 0.3 0 0\nR 0 0.3 0 0"


def _largest_error(message):
    m = re.search(r"largest pose error (\S+?)[;.]?(\s|$)", message)
    assert m, message
    return float(m.group(1))


@pytest.mark.parametrize("table, target", [(SCARA, "30 40 0.1"), (SCARA, "-120 75 0.25"),
                                           (PLANAR_3R, "30 40 50")])
def test_a_positioning_arms_solutions_reach_the_target_and_the_status_says_so(table, target):
    st = widgets.dh_panel(table=table, target=target).state
    assert st.result is not None and len(st.result) >= 1, st.message
    F = st.arm.fk(st.result.q)
    # every solution puts the TCP on the target (checked here, not by the panel)
    assert np.abs(F[:, :3, 3] - st.target[:3, 3]).max() < 1e-9
    assert _largest_error(st.message) < 1e-9, st.message
    assert "the joints you typed are solution" in st.message


@pytest.mark.parametrize("table, target", [(BENT_2, "10 20"), (BENT_3, "10 20 30")])
def test_an_arm_of_fewer_than_six_joints_outside_every_family_gets_a_status(table, target):
    panel = widgets.dh_panel(table=table, target=target)  # must not raise
    st = panel.state
    assert st.result is None
    assert st.message.startswith("No closed form:"), st.message
    assert "\n" not in st.message
    if st.numerical is not None and st.numerical.success:
        # the numerical solution reaches the typed joints' TCP position
        F = st.arm.fk(st.numerical.q)
        assert np.abs(F[:3, 3] - st.target[:3, 3]).max() < 1e-6
    panel.html()  # and the panel can show it


@pytest.mark.parametrize("row, shown, right", [
    ("R 0.4 0 1.571 0", "1.571", "90"), ("R 0.4 0 1.5708 0", "1.5708", "90"),
    ("R 0.4 0 -3.1416 0", "-3.1416", "-180")])
def test_a_right_angle_typed_in_radians_in_the_degree_cells_is_named(row, shown, right):
    # refused where it is typed, not solved as a twist of 1.5708 deg (or, when that arm has
    # no closed form, left to a hint after the reason)
    st = widgets.dh_panel(table=f"{row}\nR 0 0.3 0 0\nR 0 0.3 0 0", target="10 20 30").state
    assert st.message.startswith("The table cannot be read:"), st.message
    assert f"column alpha = '{shown}'" in st.message, st.message
    assert f"write {right} (or {right}°" in st.message, st.message


def test_the_panels_own_examples_and_a_real_small_twist_get_no_radians_hint():
    # 1.5 deg is a twist someone means; the examples solve
    st = widgets.dh_panel(table="R 0.4 0 1.5 0\nR 0 0.3 0 0\nR 0 0.3 0 0",
                          target="10 20 30").state
    assert "write 90" not in st.message
    for example in widgets.EXAMPLES.values():
        assert widgets.dh_panel(**example).state.result is not None
