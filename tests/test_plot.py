"""rikin.plot: figure types, artist counts, and drawn geometry against independent FK."""

from __future__ import annotations

import os

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.path import Path

import rikin
from rikin import InputError, UnreachableError, robots
from rikin.plot import (
    MARKER_KEY,
    gripper_path,
    is_planar,
    plot_arm,
    plot_dh_frames,
    plot_solutions,
    plot_two_link_triangle,
    plot_workspace_3d,
    plot_workspace_planar,
    plot_wrist_centre,
    same_joint_points,
    turned_axes,
    wrist_centre,
)

AULA10_Q_DEG = [99.6, 9, 26.4, 68.4, 30, 151]


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def test_backend_is_headless():
    assert os.environ.get("MPLBACKEND") == "Agg"
    assert matplotlib.get_backend().lower() == "agg"


def lines(ax, gid):
    return [ln for ln in ax.lines if ln.get_gid() == gid]


def line_vertices(line, three_d):
    if three_d:
        return np.column_stack(line.get_data_3d())
    return np.column_stack(line.get_data())


# ---------------------------------------------------------------- is_planar
@pytest.mark.parametrize("name, planar", [
    ("planar_2r", True), ("planar_3r", True), ("angular_3r", False), ("aula10_6r", False),
    ("barrientos_6r", False), ("pprrr", False), ("rprrr", False), ("epson_c4", False)])
def test_is_planar(name, planar):
    assert is_planar(robots.LESSON_ROBOTS[name]()) is planar


def test_a_tilted_base_makes_a_planar_table_spatial():
    arm = robots.planar_2r(base=rikin.homogeneous(rikin.rotx(0.3)))
    assert not is_planar(arm)


# ---------------------------------------------------------------- plot_arm
@pytest.mark.parametrize("name", sorted(robots.LESSON_ROBOTS))
def test_plot_arm_draws_each_dh_link_as_its_d_and_a_pieces(name):
    rng = np.random.default_rng(3)
    arm = robots.LESSON_ROBOTS[name]()
    q = np.where(arm.revolute, rng.uniform(-np.pi, np.pi, arm.n), rng.uniform(0.0, 5.0, arm.n))
    ax = plot_arm(arm, q)
    assert isinstance(ax, Axes)
    three_d = ax.name == "3d"
    assert three_d is (not is_planar(arm))
    # independent: the origins of base, frames 1..n and the TCP from FK, and between
    # o_{i-1} and o_i the corner after d_i along z_{i-1} (standard DH) or after
    # a_{i-1} along x_{i-1} (modified), from the DH parameters themselves
    F = arm.fk(q, frames=True)
    origins = F[:, :3, 3]
    path = [origins[0]]
    for i, lk in enumerate(arm.links):
        if arm.convention == "modified":
            path.append(origins[i] + lk.a * F[i, :3, 0])
        else:
            d = lk.d + (0.0 if lk.is_revolute else q[i] + lk.offset)
            path.append(origins[i] + d * F[i, :3, 2])
        path.append(origins[i + 1])
    path.append(origins[-1])
    (stick,) = lines(ax, "arm")
    dims = 3 if three_d else 2
    drawn_path = line_vertices(stick, three_d)
    assert np.allclose(drawn_path, np.array(path)[:, :dims], atol=1e-9 * arm.scale)
    assert np.allclose(drawn_path[0::2][: arm.n + 1], origins[: arm.n + 1, :dims])
    (tcp,) = lines(ax, "tcp")
    assert np.allclose(line_vertices(tcp, three_d)[0], origins[-1, :dims])
    # one marker per joint, on its axis where the DH common normal meets it
    F = arm.fk(q, frames=True)
    expected = []
    for i, lk in enumerate(arm.links):
        if arm.convention == "modified":
            expected.append(F[i + 1, :3, 3])            # frame i on axis i
        elif i == arm.n - 1:
            expected.append(F[i, :3, 3])                # last joint: o_{n-1}
        else:
            d = lk.d + (0.0 if lk.is_revolute else q[i] + lk.offset)
            expected.append(F[i, :3, 3] + d * F[i, :3, 2])   # o_{i-1} + d_i z_{i-1}
    expected = np.array(expected)
    drawn = {True: [], False: []}
    for ln in lines(ax, "joints"):
        drawn[ln.get_marker() == "o"].append(line_vertices(ln, three_d))
    for revolute, pts in drawn.items():
        mask = arm.revolute == revolute
        got = np.vstack(pts) if pts else np.zeros((0, dims))
        assert np.allclose(got, expected[mask, :dims], atol=1e-9 * arm.scale)
    # a triad per frame: n + 2 frames, 3 axes in 3D, 2 in the plane; one line per colour,
    # its segments (origin, origin + s * axis) separated by NaN
    for k, name in enumerate("xyz"):
        drawn_axes = lines(ax, f"frame-{name}")
        if k == 2 and not three_d:
            assert drawn_axes == []
            continue
        (axis_line,) = drawn_axes
        v = line_vertices(axis_line, three_d)
        assert v.shape[0] == 3 * (arm.n + 2) and np.isnan(v[2::3]).all()
        assert np.allclose(v[0::3], origins[:, :dims])
        d = v[1::3] - v[0::3]
        unit = d / np.linalg.norm(d, axis=1, keepdims=True)
        assert np.allclose(unit, F[:, :dims, k] / np.linalg.norm(F[:, :dims, k], axis=1,
                                                                 keepdims=True))
    # everything drawn is inside the view
    lim = [ax.get_xlim(), ax.get_ylim()] + ([ax.get_zlim()] if three_d else [])
    for d in range(dims):
        assert lim[d][0] < origins[:, d].min() and origins[:, d].max() < lim[d][1]


def test_plot_arm_3d_view_has_equal_scale():
    arm = robots.epson_c4()
    ax = plot_arm(arm, rikin.rad([20, -30, 40, 10, 30, 0]))
    spans = [np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()), np.ptp(ax.get_zlim())]
    assert np.allclose(spans, spans[0])
    assert np.allclose(ax.get_box_aspect() / ax.get_box_aspect()[0], 1.0)
    assert "mm" in ax.get_xlabel()


def test_plot_arm_planar_draws_the_tool_direction_and_joint_labels():
    arm = robots.planar_3r()
    q = np.array([0.3, 0.8, -0.5])
    ax = plot_arm(arm, q, frames=False)
    assert ax.name != "3d"
    assert lines(ax, "frame-x") == []
    tool = [t for t in ax.texts if t.get_gid() == "tool"]
    assert len(tool) == 1
    tcp = arm.fk(q)
    start, tip = np.array(tool[0].xyann), np.array(tool[0].xy)
    assert np.allclose(start, tcp[:2, 3])
    direction = (tip - start) / np.linalg.norm(tip - start)
    assert np.allclose(direction, tcp[:2, 0])  # along the tool's x axis
    assert {t.get_text() for t in ax.texts} >= {"J1", "J2", "J3"}


def test_plot_arm_groups_the_spherical_wrist_label():
    ax = plot_arm(robots.aula10_6r(), rikin.rad(AULA10_Q_DEG))
    # shoulder joints 1-2 meet at the shoulder, the three wrist axes at the wrist centre
    texts = {t.get_text() for t in ax.texts}
    assert texts >= {"J1,2", "J3", "J4,5,6"}


def test_plot_arm_into_given_axes_and_bad_input():
    arm = robots.angular_3r()
    fig = plt.figure()
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    assert plot_arm(arm, [0.1, 0.2, 0.3], ax=ax3, title="mine") is ax3
    assert ax3.get_title() == "mine"
    with pytest.raises(InputError, match="3D axes"):
        plot_arm(arm, [0.1, 0.2, 0.3], ax=fig.add_subplot(1, 2, 2))
    with pytest.raises(InputError, match="degrees"):
        plot_arm(arm, [10.0, 45.0, 90.0])
    with pytest.raises(InputError, match="plot_solutions"):
        plot_arm(arm, np.zeros((2, 3)))


# ---------------------------------------------------------------- plot_solutions
def test_plot_solutions_aula10_draws_all_eight_branches():
    arm = robots.aula10_6r()
    result = arm.ik(arm.fk(rikin.rad(AULA10_Q_DEG)))
    fig = plot_solutions(arm, result)
    assert isinstance(fig, Figure)
    assert len(fig.axes) == 8 == len(result)
    limits = {(ax.get_xlim(), ax.get_ylim(), ax.get_zlim()) for ax in fig.axes}
    assert len(limits) == 1  # same view in every subplot
    for ax, label, q in zip(fig.axes, result.labels, result.q, strict=True):
        assert ax.name == "3d"
        assert label in ax.get_title()
        assert f"{np.degrees(q[0]):.1f}°" in ax.get_title()
        # each subplot really draws its own solution, which reaches the target
        (stick,) = lines(ax, "arm")
        origins = arm.fk(q, frames=True)[:, :3, 3]
        drawn_path = line_vertices(stick, True)
        assert np.allclose(drawn_path[0::2], origins[:-1])
        assert np.allclose(drawn_path[-1], origins[-1])
        (target,) = lines(ax, "target")
        assert np.allclose(line_vertices(target, True)[0], result.target[:3, 3])
    assert {lab.split("/")[0] for lab in result.labels} == {"front", "back"}
    fig.savefig(os.devnull, format="png")  # renders without error


def test_plot_solutions_from_an_array_and_layout():
    arm = robots.planar_3r()
    Q = arm.ik([27.071, 7.071, np.radians(45)]).q
    fig = plot_solutions(arm, Q, ncols=1, frames=True)
    assert len(fig.axes) == 2
    assert all(ax.name != "3d" for ax in fig.axes)
    assert [ax.get_title().splitlines()[0] for ax in fig.axes] == ["solution 1", "solution 2"]
    assert all(len(lines(ax, "target")) == 0 for ax in fig.axes)
    with pytest.raises(InputError, match="ncols"):
        plot_solutions(arm, Q, ncols=0)
    with pytest.raises(InputError, match="no solutions"):
        plot_solutions(arm, np.zeros((0, 3)))


def test_plot_solutions_singular_result_is_titled():
    arm = robots.epson_c4()
    result = arm.ik(arm.fk(np.zeros(6)))
    fig = plot_solutions(arm, result)
    assert len(fig.axes) == len(result) == 3
    assert "singular" in fig.get_suptitle()


# ---------------------------------------------------------------- two-link triangle
def test_two_link_triangle_draws_both_elbows_with_the_right_geometry():
    L1, L2, P = 10.0, 7.0, np.array([12.0, 5.0])
    ax = plot_two_link_triangle(L1, L2, P)
    links1, links2 = lines(ax, "link1"), lines(ax, "link2")
    assert len(links1) == len(links2) == 2
    assert links1[0].get_linestyle() == "-" and links1[1].get_linestyle() == "--"
    elbows = []
    for l1, l2 in zip(links1, links2, strict=True):
        start, E = line_vertices(l1, False)
        E2, T = line_vertices(l2, False)
        assert np.allclose(start, 0) and np.allclose(E, E2) and np.allclose(T, P)
        assert np.isclose(np.linalg.norm(E), L1) and np.isclose(np.linalg.norm(T - E), L2)
        elbows.append(E)
    # the two elbows mirror each other across the line OP; the solid one is above it
    cross = [P[0] * e[1] - P[1] * e[0] for e in elbows]
    assert cross[0] > 0 > cross[1]
    # the angles by the law of cosines, computed here independently
    r = np.hypot(*P)
    theta2 = np.degrees(np.arccos((r**2 - L1**2 - L2**2) / (2 * L1 * L2)))
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert f"{-theta2:.2f}°" in legend[0] and f"{theta2:.2f}°" in legend[1]
    labels = {t.get_text() for t in ax.texts}
    assert {"$l_1$", "$l_2$", "$\\alpha$", "$\\phi$", "$\\theta_2$"} <= labels


def test_two_link_triangle_one_elbow_and_custom_labels():
    ax = plot_two_link_triangle(3.0, 2.0, (2.0, 3.0), elbow="down", labels=("a_2", "a_3"))
    assert len(lines(ax, "link1")) == 1
    (l1,) = lines(ax, "link1")
    E = line_vertices(l1, False)[1]
    assert 2.0 * E[1] - 3.0 * E[0] < 0  # below the line OP
    assert {"$a_2$", "$a_3$"} <= {t.get_text() for t in ax.texts}


@pytest.mark.parametrize("target, excess", [((20.0, 0.0), 3.0), ((0.0, 1.0), 2.0)])
def test_two_link_triangle_out_of_reach_raises(target, excess):
    # l1 = 10, l2 = 7: reach 17 (20 is 3 beyond); the folded chain reaches no closer than 3
    with pytest.raises(UnreachableError, match="distance") as info:
        plot_two_link_triangle(10.0, 7.0, target)
    assert np.isclose(info.value.excess, excess)


def test_two_link_triangle_bad_input():
    with pytest.raises(InputError, match="L2 must be a positive"):
        plot_two_link_triangle(1.0, -1.0, (1.0, 0.0))
    with pytest.raises(InputError, match="shape"):
        plot_two_link_triangle(1.0, 1.0, (1.0, 0.0, 0.0))
    with pytest.raises(InputError, match="elbow"):
        plot_two_link_triangle(1.0, 1.0, (1.0, 0.0), elbow="left")


# ---------------------------------------------------------------- workspace
class Region:
    """A shaded region as drawn: inside its outer polygon and outside its hole (if any)."""

    def __init__(self, ax, gid):
        (patch,) = [p for p in ax.patches if p.get_gid() == gid]
        polys = patch.get_path().to_polygons()
        self.outer = Path(polys[0])
        self.holes = [Path(p) for p in polys[1:]]

    def contains_points(self, pts):
        pts = np.asarray(pts, dtype=float)
        inside = self.outer.contains_points(pts)
        for h in self.holes:
            inside &= ~h.contains_points(pts)
        return inside


def region(ax, gid):
    return Region(ax, gid)


def pixel(ax, xy):
    """RGB of the rendered figure at data point xy."""
    fig = ax.figure
    fig.canvas.draw()
    img = np.asarray(fig.canvas.buffer_rgba())
    x, y = ax.transData.transform(xy)
    return img[img.shape[0] - int(round(y)), int(round(x)), :3].astype(int)


def test_workspace_2r_is_the_annulus_and_holds_every_fk_point():
    arm = robots.planar_2r(10.0, 6.0)
    ax = plot_workspace_planar(arm, n=720)
    path = region(ax, "tcp-region")
    assert [p.get_gid() for p in ax.patches] == ["tcp-region"]
    rng = np.random.default_rng(5)
    tcp = arm.fk(rng.uniform(-np.pi, np.pi, (400, 2)))[:, :2, 3]
    r = np.hypot(tcp[:, 0], tcp[:, 1])
    inside = path.contains_points(tcp)
    # the polygon is inscribed: away from the boundary circles every FK point is inside
    clear = (r > 4.0 + 0.01) & (r < 16.0 * np.cos(np.pi / 720) - 0.01)
    assert inside[clear].all() and clear.sum() > 300
    # and points outside the annulus are outside the shaded region
    assert not path.contains_points([[16.5, 0.0], [0.0, -17.0], [3.5, 0.0], [0.0, 0.0]]).any()


def test_workspace_3r_has_wrist_and_tcp_regions():
    arm = robots.planar_3r(10.0, 6.0, 3.0)
    ax = plot_workspace_planar(arm)
    tcp_path, wrist_path = region(ax, "tcp-region"), region(ax, "wrist-region")
    rng = np.random.default_rng(9)
    F = arm.fk(rng.uniform(-np.pi, np.pi, (400, 3)), frames=True)
    wrist = F[:, 2, :2, 3]   # origin of frame 2: where link 3 starts
    tcp = F[:, -1, :2, 3]
    rw, rt = np.hypot(*wrist.T), np.hypot(*tcp.T)
    ok_w = (rw > 4.05) & (rw < 15.9)
    ok_t = (rt > 1.05) & (rt < 18.9)
    assert wrist_path.contains_points(wrist[ok_w]).all()
    assert tcp_path.contains_points(tcp[ok_t]).all()
    assert not wrist_path.contains_points([[3.0, 0.0], [16.5, 0.0]]).any()
    assert not tcp_path.contains_points([[0.5, 0.0], [19.5, 0.0]]).any()
    assert tcp_path.contains_points([[2.0, 0.0]]).all()
    # what is rendered: white in the TCP hole (r < 1), shaded between 1 and 4 and beyond 16
    white = np.array([255, 255, 255])
    assert np.abs(pixel(ax, (0.5, 0.5)) - white).max() <= 2  # off the + at the centre
    for xy in [(0.0, 2.5), (17.5, 0.0)]:
        assert np.abs(pixel(ax, xy) - white).max() > 20, xy


def test_workspace_rejects_spatial_or_limited_arms():
    with pytest.raises(InputError, match="not planar"):
        plot_workspace_planar(robots.angular_3r())
    limited = rikin.SerialArm((rikin.Link(a=1.0, qlim=(-1.0, 1.0)), rikin.Link(a=1.0)))
    with pytest.raises(InputError, match="limits"):
        plot_workspace_planar(limited)
    with pytest.raises(InputError, match="n must be"):
        plot_workspace_planar(robots.planar_2r(), n=3)


# ---------------------------------------------------------------- telling solutions apart
def test_gripper_follows_the_tool_frame():
    arm = robots.aula10_6r()
    q = rikin.rad(AULA10_Q_DEG)
    T = arm.fk(q)
    g = gripper_path(T, 2.0)
    stub, palm, gap, tip_a, palm_a, palm_b, tip_b = g
    assert np.isnan(gap).all()
    # the fingers end at the TCP, 1 apart along y; the palm is 2 back along z (approach)
    assert np.allclose((tip_a + tip_b) / 2, T[:3, 3])
    assert np.allclose(tip_a - tip_b, 2.0 * T[:3, 1])
    assert np.allclose(palm, T[:3, 3] - 2.0 * T[:3, 2])
    assert np.allclose(palm_a - tip_a, -2.0 * T[:3, 2])
    assert np.allclose(stub, palm - 1.2 * T[:3, 2])
    ax = plot_arm(arm, q)
    (drawn,) = lines(ax, "gripper")
    v = line_vertices(drawn, True)
    fs = 0.09 * np.ptp(ax.get_xlim())
    assert np.allclose(v, gripper_path(T, 0.9 * fs), equal_nan=True)
    assert lines(plot_arm(arm, q, gripper=False), "gripper") == []


def test_planar_gripper_approaches_along_the_tool_x_axis():
    arm = robots.planar_3r()
    T = arm.fk([0.2, 0.4, 0.6])
    g = gripper_path(T, 1.0, planar=True)
    assert np.allclose(g[1], T[:3, 3] - T[:3, 0])


def test_same_joint_points_finds_the_aula10_coincidences():
    # no shoulder offset: front/down and back/down... share joint points (checked from FK
    # here, not from rikin.plot), and the wrist flip moves no joint
    arm = robots.aula10_6r()
    res = arm.ik(arm.fk(rikin.rad(AULA10_Q_DEG)))
    F = arm.fk(res.q, frames=True)
    o = F[:, :, :3, 3]
    twins = same_joint_points(arm, res.q)
    for i in range(len(res)):
        for j in range(len(res)):
            if i == j:
                continue
            # joint 4..6 points coincide at the wrist centre; the origins of frames 1..n
            # and the link corners decide
            same = np.allclose(o[i, :-1], o[j, :-1], atol=1e-6) and np.allclose(
                o[i, -1], o[j, -1], atol=1e-6)
            if (j + 1 in twins[i]) and not same:
                # drawn shapes equal although some origin differs: only possible when the
                # origins that differ are not drawn; not the case for this arm
                raise AssertionError((i, j))
    assert sorted(map(len, twins)) == [3] * 8
    assert twins[0] == [2, 7, 8]
    # with a shoulder offset (the C4's a1) the elbows differ: only the wrist-flip partner
    # (same shoulder and elbow) puts its joints at the same points
    b = robots.epson_c4()
    rb = b.ik(b.fk(rikin.rad([20, -30, 40, 10, 30, 0])))
    assert len(rb) == 4
    tw = same_joint_points(b, rb.q)
    for i, t in enumerate(tw):
        partner = [j + 1 for j, br in enumerate(rb.branches)
                   if j != i and br[:2] == rb.branches[i][:2]]
        assert t == partner, (i, t, rb.labels)


def test_plot_solutions_says_which_solutions_coincide_and_has_a_key():
    arm = robots.aula10_6r()
    res = arm.ik(arm.fk(rikin.rad(AULA10_Q_DEG)))
    fig = plot_solutions(arm, res)
    titles = [ax.get_title() for ax in fig.axes]
    assert "#2, #7, #8" in titles[0]
    keys = [t for t in fig.texts if t.get_gid() == "key"]
    assert len(keys) == 1 and keys[0].get_text().startswith(MARKER_KEY)
    assert "the other solutions" in keys[0].get_text() and "reversed" in keys[0].get_text()
    # the frames are drawn (default) and differ between solutions 1 and 7, whose joints
    # coincide: what tells them apart is drawn
    v1 = line_vertices(lines(fig.axes[0], "frame-z")[0], True)
    v7 = line_vertices(lines(fig.axes[6], "frame-z")[0], True)
    assert not np.allclose(v1, v7, equal_nan=True)
    for ax in fig.axes:
        assert len(lines(ax, "gripper")) == 1
        for ticks, lim in ((ax.get_xticks(), ax.get_xlim()), (ax.get_zticks(), ax.get_zlim())):
            shown = [t for t in ticks if lim[0] <= t <= lim[1]]
            assert 2 <= len(shown) <= 4, shown
    no_key = plot_solutions(arm, res, key=False, frames=False)
    assert not [t for t in no_key.texts if t.get_gid() == "key"]
    assert lines(no_key.axes[0], "frame-z") == []


def test_plot_solutions_view_is_the_given_one():
    arm = robots.angular_3r()
    res = arm.ik([-9.545, 7.896, 23.192])
    fig = plot_solutions(arm, res, view=(30.0, -45.0))
    assert all(np.isclose(ax.elev, 30.0) and np.isclose(ax.azim, -45.0) for ax in fig.axes)
    with pytest.raises(InputError, match="view"):
        plot_solutions(arm, res, view=(1.0, 2.0, 3.0))


# ---------------------------------------------------------------- new figures
def test_wrist_centre_is_tcp_minus_l_z():
    arm = robots.aula10_6r()
    q = rikin.rad(AULA10_Q_DEG)
    F = arm.fk(q, frames=True)
    w = wrist_centre(arm, F)
    # independent: for this arm's spherical wrist the centre is the origin of frame 4
    # (= 5), and the TCP lies d6 ahead of it along z6
    d6 = float(arm.links[5].d)
    assert np.allclose(w, F[4, :3, 3]) and np.allclose(w, F[-1, :3, 3] - d6 * F[-1, :3, 2])
    ax = plot_wrist_centre(arm, q)
    (mark,) = lines(ax, "wrist-centre")
    assert np.allclose(line_vertices(mark, True)[0], w)
    (approach,) = lines(ax, "approach")
    assert np.allclose(line_vertices(approach, True), [w, F[-1, :3, 3]])
    assert f"l = {d6:.4g}" in ax.get_title()


def test_dh_frames_labels_every_frame():
    arm = robots.angular_3r()
    ax = plot_dh_frames(arm)
    labels = {t.get_text() for t in ax.texts if t.get_gid() == "frame-label"}
    assert {"$x_{0}$", "$z_{0}$", "$x_{3}$", "$z_{3}$", "xTCP", "zTCP"} <= labels
    assert len(labels) == 2 * (arm.n + 2)
    planar = plot_dh_frames(robots.planar_2r(), [0.3, 0.4])
    assert {"$x_{1}$", "$y_{1}$"} <= {t.get_text() for t in planar.texts}


def test_workspace_3d_points_are_fk_of_joints_in_the_limits():
    arm = robots.epson_c4()
    ax = plot_workspace_3d(arm, n=300, seed=4)
    (cloud,) = [c for c in ax.collections if c.get_gid() == "workspace"]
    pts = np.column_stack(cloud._offsets3d)
    assert pts.shape == (300, 3)
    # every point is reachable: IK finds a solution within the limits for a sample of them
    rng = np.random.default_rng(4)
    Q = rng.uniform(arm.qlim[:, 0], arm.qlim[:, 1], size=(300, arm.n))
    assert np.allclose(pts, arm.fk(Q)[:, :3, 3])
    again = np.column_stack([c for c in plot_workspace_3d(arm, n=300, seed=4).collections
                             if c.get_gid() == "workspace"][0]._offsets3d)
    assert np.array_equal(pts, again)   # deterministic
    wrist = plot_workspace_3d(robots.aula10_6r(), n=200, point="wrist")
    assert "wrist centre" in wrist.get_title()
    with pytest.raises(InputError, match="point"):
        plot_workspace_3d(arm, point="elbow")
    with pytest.raises(InputError, match="n must"):
        plot_workspace_3d(arm, n=5)
    with pytest.raises(InputError, match="limits"):
        plot_workspace_3d(robots.pprrr())


# ---------------------------------------------------------------- readable, telling panels
def _font_sizes(fig):
    """Every text's size (points) in a drawn figure, tick labels included."""
    fig.canvas.draw()
    return [t.get_fontsize() for t in fig.findobj(matplotlib.text.Text)
            if t.get_text().strip() and t.get_visible()]


@pytest.mark.parametrize("name, q_deg", [
    ("aula10_6r", AULA10_Q_DEG), ("angular_3r", [140.4, 21.6, 50.4]),
    ("epson_c4", [10, 20, 30, 40, 50, 60])])
def test_plot_solutions_fits_the_book_column_with_readable_text(name, q_deg):
    """At most 7.5 inches wide (shown at its natural size, 720 px, in the book) and no text
    under SMALLEST_FONT_PT: 10 px on the page. The old 4-column layout was 13 inches wide
    with 6 pt ticks: 5 px once shrunk to the column."""
    arm = getattr(robots, name)()
    res = arm.ik(arm.fk(rikin.rad(q_deg)))
    fig = plot_solutions(arm, res)
    assert fig.get_size_inches()[0] <= 7.5
    assert min(_font_sizes(fig)) >= rikin.plot.SMALLEST_FONT_PT


def test_plot_solutions_ghosts_the_other_solutions():
    """Each panel draws the solutions whose stick figure differs from its own, faintly."""
    arm = robots.aula10_6r()
    res = arm.ik(arm.fk(rikin.rad(AULA10_Q_DEG)))
    fig = plot_solutions(arm, res)
    twins = same_joint_points(arm, res.q)
    F = arm.fk(res.q, frames=True)
    for i, ax in enumerate(fig.axes):
        ghosts = lines(ax, "ghost")
        others = [j for j in range(len(res)) if j != i and j + 1 not in twins[i]]
        assert len(ghosts) == len(others) == 4
        for g, j in zip(ghosts, others, strict=True):
            assert np.allclose(line_vertices(g, True)[0::2], F[j, :-1, :3, 3])
    assert all(lines(ax, "ghost") == [] for ax in plot_solutions(arm, res, ghosts=False).axes)


def test_turned_axes_are_the_joints_that_turn_the_other_way():
    """Independent: a wrist flip (q4 + pi, -q5, q6 + pi) reverses the axis of joint 5 only;
    the PPRRR's flip reverses joint 4's; a front/back pair of the angular 3R reverses the
    axes of joints 2 and 3 (z1, z2) and not joint 1's."""
    arm = robots.aula10_6r()
    q = rikin.rad(AULA10_Q_DEG)
    flip = q + np.array([0, 0, 0, np.pi, 0, np.pi])
    flip[4] = -q[4]
    assert turned_axes(arm, q, flip) == [5]
    p = robots.pprrr()
    res = p.ik(p.fk([2.0, 3.0, 0.5, 0.7, 0.2]))
    assert turned_axes(p, res.q[0], res.q[1]) == [4]
    a = robots.angular_3r()
    qa = rikin.rad([140.4, 21.6, 50.4])
    back = np.array([qa[0] + np.pi, np.pi - qa[1], -qa[2]])
    assert np.allclose(a.fk(qa)[:3, 3], a.fk(back)[:3, 3], atol=1e-9)  # one TCP position
    assert turned_axes(a, qa, back) == [2, 3]


def test_twin_panels_differ_where_the_stick_figures_coincide():
    """The PPRRR's two solutions (a wrist flip) have the same stick figure: the old panels
    were identical but for small frame triads. Each panel now draws the reversed axis
    (purple), and the two drawings point opposite ways."""
    arm = robots.pprrr()
    res = arm.ik(arm.fk([2.0, 3.0, 0.5, 0.7, 0.2]))
    fig = plot_solutions(arm, res)
    a, b = (lines(ax, "turned-axis")[0] for ax in fig.axes)
    va, vb = line_vertices(a, True), line_vertices(b, True)
    assert np.allclose(va[0], vb[0])                       # from the same joint point
    da, db = va[1] - va[0], vb[1] - vb[0]
    assert np.dot(da, db) < -0.99 * np.dot(da, da)         # pointing opposite ways
    solo = plot_solutions(robots.planar_2r(), robots.planar_2r().ik([15.0, 5.0]))
    assert all(lines(ax, "turned-axis") == [] for ax in solo.axes)  # no twins: none drawn


def test_book_style_makes_text_svg_text_without_a_date(tmp_path):
    rikin.plot.book_style()
    fig = plot_solutions(robots.planar_2r(), robots.planar_2r().ik([15.0, 5.0]))
    fig.savefig(tmp_path / "a.svg", metadata={"Date": None})
    fig.savefig(tmp_path / "b.svg", metadata={"Date": None})
    text = (tmp_path / "a.svg").read_text()
    assert "<text" in text and "font-size" in text       # text, not glyph outlines
    assert "dc:date" not in text
    assert text == (tmp_path / "b.svg").read_text()        # the same file every time


# ---------------------------------------------------------------- flat views with dimensions
@pytest.mark.parametrize("view, axes", [("xz", (0, 2)), ("yz", (1, 2)), ("xy", (0, 1))])
def test_plot_view_projects_fk_and_dimensions_the_tcp(view, axes):
    """The drawn links are FK's frame origins projected onto the view's two world axes, and
    the two dimension lines ("cotas") end at the TCP's coordinates and say them."""
    arm = robots.epson_c4()
    q = rikin.rad([20, -10, 40, 30, 50, 60])
    ax = rikin.plot.plot_view(arm, q, view)
    F = arm.fk(q, frames=True)
    (stick,) = lines(ax, "arm")
    drawn = line_vertices(stick, False)
    assert np.allclose(drawn[0::2][:len(F) - 1], F[:-1, :3, 3][:, axes])
    tcp = F[-1, :3, 3]
    texts = [t.get_text() for t in ax.texts if t.get_gid() == "dimension-text"]
    names = "xyz"
    assert texts == [f"{names[axes[0]]} = {tcp[axes[0]]:.4g}",
                     f"{names[axes[1]]} = {tcp[axes[1]]:.4g}"]
    arrows = [a for a in ax.texts if a.get_gid() == "dimension" and hasattr(a, "xy")]
    ends = sorted(abs(a.xy[0] - a.xyann[0]) + abs(a.xy[1] - a.xyann[1]) for a in arrows)
    assert np.allclose(sorted(abs(tcp[list(axes)])), ends)
    assert not [t for t in rikin.plot.plot_view(arm, q, view, dimensions=False).texts
                if t.get_gid() == "dimension-text"]


def test_plot_view_bad_input():
    arm = robots.epson_c4()
    with pytest.raises(InputError, match="view"):
        rikin.plot.plot_view(arm, np.zeros(6), "xq")
    ax3 = plt.figure().add_subplot(projection="3d")
    with pytest.raises(InputError, match="2D"):
        rikin.plot.plot_view(arm, np.zeros(6), ax=ax3)
