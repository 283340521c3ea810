"""Forward kinematics from DH tables, against expectations computed independently."""

import numpy as np
import pytest

import rikin
from rikin import InputError, Link, SerialArm, robots


def test_epson_c4_zero_pose_from_the_lab():
    # lab 2 (and ERRATA): at q = 0 the TCP is at (415, 0, 570) mm, tool z pointing along +x
    T = robots.epson_c4().fk(np.zeros(6))
    assert np.allclose(T[:3, 3], [415, 0, 570], atol=1e-9)
    assert np.allclose(T[:3, :3], [[0, 0, 1], [0, -1, 0], [1, 0, 0]], atol=1e-12)


def test_epson_c4_config_row_gives_the_same_pose():
    # ERRATA 004: configs row (0, -90, 180, 0, -90, 0) deg gives the calibration pose
    c4 = robots.epson_c4()
    assert np.allclose(c4.fk(rikin.rad([0, -90, 180, 0, -90, 0])), c4.fk(np.zeros(6)), atol=1e-9)


def test_aula10_pose_of_the_lesson():
    arm = robots.aula10_6r()
    T = arm.fk(rikin.rad([99.6, 9, 26.4, 68.4, 30, 151]))
    # the lesson's Paso 1 (rounded to 4 decimals) and ERRATA's corrected R06
    assert np.allclose(T[:3, 3], [-9.4519, 33.8090, 42.7623], atol=1e-4)
    R06 = [[0.6091, -0.7512, -0.2543], [0.7735, 0.4919, 0.3998], [-0.1753, -0.4402, 0.8806]]
    assert np.allclose(T[:3, :3], R06, atol=1e-4)
    assert np.allclose(
        T[:3, :3], rikin.rpy_to_r(-26.5610, 10.0935, 51.7776, degrees=True), atol=1e-4
    )


def test_planar_2r_by_hand():
    arm = robots.planar_2r(3.0, 2.0)
    q = np.array([0.4, -1.1])
    x = 3 * np.cos(0.4) + 2 * np.cos(0.4 - 1.1)
    y = 3 * np.sin(0.4) + 2 * np.sin(0.4 - 1.1)
    assert np.allclose(arm.fk(q)[:3, 3], [x, y, 0])


def test_angular_3r_by_hand():
    arm = robots.angular_3r(10, 10, 10)
    q1, q2, q3 = 0.3, 0.5, -0.8
    r = 10 * np.cos(q2) + 10 * np.cos(q2 + q3)
    z = 10 + 10 * np.sin(q2) + 10 * np.sin(q2 + q3)
    assert np.allclose(arm.fk([q1, q2, q3])[:3, 3], [r * np.cos(q1), r * np.sin(q1), z])


def test_standard_and_modified_dh_agree_on_the_same_arm():
    # the planar 2R written both ways: modified puts a_{i-1} in the next row and the last
    # link's length into the tool
    std = SerialArm((Link(a=3.0), Link(a=2.0)))
    mod = SerialArm((Link(a=0.0), Link(a=3.0)), convention="modified", tool=rikin.transl(2.0, 0, 0))
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, size=(50, 2))
    assert np.allclose(std.fk(q), mod.fk(q))


def test_prismatic_joint_moves_along_z():
    arm = SerialArm((Link("P", theta=0.0, d=1.0),))
    assert np.allclose(arm.fk([2.5])[:3, 3], [0, 0, 3.5])


def test_batch_and_frames_shapes():
    arm = robots.aula10_6r()
    q = np.zeros((7, 6))
    assert arm.fk(q).shape == (7, 4, 4)
    F = arm.fk(q, frames=True)
    assert F.shape == (7, 8, 4, 4)
    assert np.allclose(F[:, 0], np.eye(4))
    assert np.allclose(F[:, -1], arm.fk(q))


def test_base_and_tool_are_applied_on_the_correct_side():
    base = rikin.homogeneous(rikin.rotz(0.7), [1.0, 2.0, 3.0])
    tool = rikin.homogeneous(rikin.rotx(0.2), [0.0, 0.5, 1.5])
    arm = robots.aula10_6r(base=base, tool=tool)
    plain = robots.aula10_6r()
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    assert np.allclose(arm.fk(q), base @ plain.fk(q) @ tool)


def test_jacobian_matches_finite_differences():
    arm = robots.epson_c4()
    q = np.array([0.2, -0.4, 0.9, 0.3, 0.7, -0.2])
    J = arm.jacobian(q)
    h = 1e-6
    for j in range(6):
        dq = np.zeros(6)
        dq[j] = h
        Tp, Tm = arm.fk(q + dq), arm.fk(q - dq)
        v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ arm.fk(q)[:3, :3].T
        w = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
        assert np.allclose(J[:3, j], v, atol=1e-5)
        assert np.allclose(J[3:, j], w, atol=1e-7)


def test_wrong_joint_count_message():
    with pytest.raises(InputError, match=r"shape \(6,\) or \(N, 6\).*got shape \(5,\)"):
        robots.aula10_6r().fk(np.zeros(5))


def test_degrees_in_fk_message():
    with pytest.raises(InputError, match=r"joint 2.*looks like degrees"):
        robots.aula10_6r().fk([0, 90, 0, 0, 0, 0])


@pytest.mark.parametrize(("kwargs", "name", "value"), [
    ({"alpha": 90}, "alpha", 90), ({"alpha": -90.0}, "alpha", -90),
    ({"offset": -90}, "offset", -90),
    ({"joint": "P", "theta": 180}, "theta", 180), ({"qlim": (-170, 170)}, "qlim", -170),
    ({"qlim": (-np.inf, 185)}, "qlim", 185),
])
def test_dh_table_angles_typed_in_degrees(kwargs, name, value):
    """A twist, offset or limit copied in degrees from a data sheet is refused, naming it
    and the radians it means; radians (and limits beyond a turn that are not round) pass."""
    with pytest.raises(InputError, match=rf"{name} = {value:g} looks like degrees") as got:
        Link(**kwargs)
    assert f"{np.radians(value):.6g}" in str(got.value)
    for ok in ({"alpha": np.pi / 2}, {"offset": -1.5708}, {"qlim": (-2.97, 2.97)},
               {"qlim": (-7.0, 7.0)}, {"joint": "P", "qlim": (0, 300)}):
        Link(**ok)


def test_prismatic_values_are_not_taken_for_degrees():
    arm = robots.pprrr()
    arm.fk([40.0, 25.0, 0.1, 0.2, 0.3])  # lengths may be large


def test_c4_joint_limits_are_the_real_robot():
    lim = np.degrees(robots.epson_c4().qlim)
    assert np.allclose(lim[:, 0], [-170, -160, -51, -200, -135, -360])
    assert np.allclose(lim[:, 1], [170, 65, 225, 200, 135, 360])


def test_bad_lengths_and_tables():
    with pytest.raises(InputError, match="positive length"):
        robots.aula10_6r(l2=-1)
    broken = SerialArm(tuple(robots.aula10_6r_links()[:4]) + (Link(a=1.0, alpha=np.pi / 2), Link()))
    with pytest.raises(InputError, match="not a spherical wrist"):
        robots.aula10_6r().solver.check(broken)


def test_batched_jacobian_and_axes_shapes():
    arm = robots.epson_c4()
    q = np.random.default_rng(2).uniform(-1, 1, size=(5, 6))
    origins, axes = arm.joint_axes(q)
    assert origins.shape == axes.shape == (5, 6, 3)
    J = arm.jacobian(q)
    assert J.shape == (5, 6, 6)
    for i in range(5):
        assert np.allclose(J[i], arm.jacobian(q[i]))


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("joint", ["R", "P"])
def test_one_pose_fast_path_matches_the_batched_formulas(convention, joint):
    # FK of one q uses scalar arithmetic; it must give the batched (array) result.
    rng = np.random.default_rng(7)
    for _ in range(50):
        d, a, alpha, offset, theta = rng.uniform(-3, 3, 5)
        link = Link(joint, d=d, a=a, alpha=alpha, offset=offset, theta=theta)
        q = rng.uniform(-3, 3)
        one = rikin.dh.link_transform(link, np.float64(q), convention)
        batch = rikin.dh.link_transform(link, np.array([q, q + 1.0]), convention)[0]
        assert one.shape == (4, 4)
        np.testing.assert_allclose(one, batch, rtol=0, atol=1e-15)


def test_one_pose_validation_still_rejects_bad_base_and_tool():
    links = (Link(a=1.0), Link(a=1.0))
    flipped = np.diag([1.0, 1.0, -1.0, 1.0])  # a reflection: det = -1
    with pytest.raises(InputError, match="reflection"):
        SerialArm(links, base=flipped)
    skewed = np.eye(4)
    skewed[0, 1] = 0.1  # columns no longer orthonormal
    with pytest.raises(InputError, match="orthonormal"):
        SerialArm(links, tool=skewed)
    bottom = np.eye(4)
    bottom[3, 0] = 0.5
    with pytest.raises(InputError, match="last row"):
        SerialArm(links, tool=bottom)
    assert SerialArm(links).revolute.flags.writeable is False


def test_imports_flow_one_way_robots_dh_ik():
    """dh (and what it builds on) never imports ik, not even lazily: rikin.ik builds on dh."""
    import ast
    import pathlib

    root = pathlib.Path(rikin.__file__).parent
    for module in ("dh.py", "transforms.py", "_validate.py", "errors.py", "tolerances.py"):
        tree = ast.parse((root / module).read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                target = ("." * node.level) + (node.module or "")
                assert not target.startswith((".ik", "rikin.ik")), (module, target)
                assert "robots" not in target, (module, target)
            elif isinstance(node, ast.Import):
                assert not any(a.name.startswith("rikin.ik") for a in node.names), module


def test_dh_table_text_keeps_the_typed_digits():
    """``arm.dh_table()`` prints what was typed (the Puma's d3 = 0.15005, not 0.15)."""
    arm = SerialArm([Link(d=0.6718, alpha=np.pi / 2), Link(a=0.4318),
                     Link(d=0.15005, a=0.0203, alpha=-np.pi / 2)])
    text = arm.dh_table()
    assert "0.15005" in text and "0.6718" in text and "0.0203" in text and "1.5708" in text
