"""rikin.widgets: the live IK panel and teach(), driven without a front end.

Setting a slider's value runs the same observer a browser would; the tests
check what the panel then shows (the image bytes, the table, the words).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import rikin
from rikin import robots, widgets

AULA10_Q_DEG = [99.6, 9, 26.4, 68.4, 30, 151]


def test_pose_sliders_follow_the_arms_target_kind():
    names = lambda arm: [s[0] for s in widgets.pose_sliders_for(arm)]  # noqa: E731
    assert names(robots.aula10_6r()) == ["x", "y", "z", "roll", "pitch", "yaw"]
    assert names(robots.angular_3r()) == ["x", "y", "z"]
    assert names(robots.planar_3r()) == ["x", "y", "phi"]
    assert names(robots.planar_2r()) == ["x", "y"]


def test_ik_panel_shows_every_solution_of_the_slider_pose():
    arm = robots.aula10_6r()
    T = arm.fk(rikin.rad(AULA10_Q_DEG))
    panel = widgets.ik_panel(arm)
    box = panel.widget()
    sliders = panel._sliders
    # move the sliders to the lesson's pose, as a user would
    for name, value in panel.values_of(T).items():
        sliders[name].value = value
    assert np.allclose(panel.target(), T, atol=1e-9)
    st = panel.state
    assert st.result is not None and len(st.result) == 8 and st.message == "8 solutions"
    # every branch is named in the table, and each solution reaches the slider pose (FK)
    for lab in st.result.labels:
        assert lab in panel._table.value
    assert np.allclose(arm.fk(st.result.q), panel.target(), atol=1e-9)
    img = panel._image.value
    assert img[:8] == b"\x89PNG\r\n\x1a\n"
    assert box.children[-1] is panel._image


def test_ik_panel_says_how_far_out_of_reach():
    arm = robots.aula10_6r()
    panel = widgets.ik_panel(arm)
    panel.widget()
    before = panel._image.value
    panel._sliders["x"].value = panel._sliders["x"].max
    st = panel.state
    assert st.result is None and st.excess is not None and st.excess > 0
    assert st.message.startswith(f"out of reach by {st.excess:.4g}: "), st.message
    # in plain words: how far, where the wrist centre is, what links 2-3 reach; said once,
    # with no note on rounded poses
    assert re.fullmatch(r"out of reach by [\d.]+: the wrist centre is [\d.]+ from the shoulder "
                        r"axis, links 2-3 reach 30", st.message), st.message
    assert st.message in panel._table.value
    assert panel._image.value != before        # the drawing changed (the arm, no solutions)


def test_ik_panel_planar_and_bad_names():
    panel = widgets.ik_panel(robots.planar_3r(), x=27.071, y=7.071, phi=45.0)
    assert len(panel.state.result) == 2
    with pytest.raises(rikin.InputError, match="no target coordinate 'z'"):
        panel.set(z=1.0)
    with pytest.raises(rikin.InputError, match="finite"):
        panel.set(x=float("nan"))


def test_teach_moves_the_arm_by_fk():
    arm = robots.epson_c4()
    panel = widgets.teach(arm)
    panel.widget()
    before = panel._image.value
    panel._sliders[1].value = -30.0
    panel._sliders[2].value = 40.0
    q = rikin.rad([0, -30, 40, 0, 0, 0])
    assert np.allclose(panel.q, q)
    T = arm.fk(q)
    assert f"({T[0, 3]:.4g}, {T[1, 3]:.4g}, {T[2, 3]:.4g})" in panel._readout.value
    assert panel._image.value != before
    # the sliders stay inside the C4's joint limits
    for s, lim in zip(panel._sliders, np.degrees(arm.qlim), strict=True):
        assert np.isclose(s.min, lim[0]) and np.isclose(s.max, lim[1])
    with pytest.raises(rikin.InputError, match="no joint"):
        panel.set(q7=1.0)


# ------------------------------------------------------------------ laid out for a notebook
#: A notebook column on a 1366 x 768 laptop screen (JupyterLab, file browser open).
COLUMN_PX = 1000


def _title_boxes(fig):
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    return [ax.title.get_window_extent(renderer) for ax in fig.axes if ax.get_title()]


@pytest.mark.parametrize("make", [robots.aula10_6r, robots.epson_c4, robots.barrientos_6r,
                                  robots.angular_3r, robots.planar_3r, robots.pprrr])
def test_panel_drawings_fit_a_notebook_column_without_overlap(make):
    """Issue 28 item 7: every solution's title stays clear of its neighbours' and inside the
    drawing, and the drawing is no wider than a 1000 px column (at the panel's DPI)."""
    import matplotlib.pyplot as plt

    panel = widgets.ik_panel(make())
    for fig in (panel.figure(), widgets.dh_panel().figure()):
        width_px = fig.get_size_inches()[0] * widgets.DPI
        assert 300 <= width_px <= COLUMN_PX - 40, width_px
        boxes = _title_boxes(fig)
        assert len(boxes) >= 1
        for i, a in enumerate(boxes):
            assert a.x0 >= -1 and a.x1 <= fig.bbox.x1 + 1, (i, a, fig.bbox)
            for j, b in enumerate(boxes[i + 1:], i + 1):
                assert not a.overlaps(b), f"titles {i + 1} and {j + 1} overlap: {a} {b}"
        plt.close(fig)


def test_small_drawings_are_small():
    """The teach pendant's drawing fits beside its sliders; the out-of-reach drawing is
    not bigger than the solutions' drawing it replaces."""
    import matplotlib.pyplot as plt

    fig = widgets.teach(robots.epson_c4()).figure()
    assert fig.get_size_inches()[0] * widgets.DPI <= 400
    far = widgets.ik_panel(robots.epson_c4(), x=900.0, y=0.0, z=900.0, roll=0.0, pitch=0.0,
                           yaw=0.0)
    fig2 = far.figure()
    assert far.state.result is None and fig2.get_size_inches()[0] * widgets.DPI <= 400
    plt.close(fig)
    plt.close(fig2)
