"""A joint's direction as data (issue 29): ``Link(direction=-1)`` for a joint its data sheet
counts against the DH z axis, honoured by FK, every IK solver, limits, tables, drawings
and widgets, with the KUKA KR 5 arc and the FANUC LR Mate 200iD as their makers count them.

The two industrial arms are checked against ROS-Industrial's published models, read here
as data (joint origins ``xyz``/``rpy`` and axes, from ``kuka_experimental/kuka_kr5_support/
urdf/kr5_arc_macro.xacro`` and ``fanuc/fanuc_lrmate200id_support/urdf/lrmate200id_macro.
xacro``), whose joint values are the controllers' (KUKA A1..A6; FANUC's with J2/J3
decoupled), with the URDF's own forward kinematics written out below.
"""

import re

import matplotlib
import numpy as np
import pytest
import sympy

import rikin
from rikin import InputError, Link, SerialArm, robots, symbolic
from rikin.ik import classify, ik_numerical
from rikin.tables import dh_table

matplotlib.use("Agg")
pi = np.pi


# ------------------------------------------------------------------ ROS-Industrial's models
def _rpy(r, p, y):
    return rikin.rotz(y) @ rikin.roty(p) @ rikin.rotx(r)


def _turn(axis, q):
    k = np.array(axis, dtype=float)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return rikin.homogeneous(np.eye(3) + np.sin(q) * K + (1 - np.cos(q)) * K @ K, None)


def urdf_fk(joints, tool, q, base=None):
    """FK of a URDF chain: per joint ``T(xyz) R(rpy) Rot(axis, q)``, then the fixed tool0."""
    T = np.eye(4) if base is None else base.copy()
    for (xyz, rpy, axis), qi in zip(joints, q, strict=True):
        T = T @ rikin.homogeneous(_rpy(*rpy), np.array(xyz, dtype=float)) @ _turn(axis, qi)
    return T @ tool


KR5_ARC = [((0, 0, 0.4), (pi, 0, 0), (0, 0, 1)), ((0.18, 0, 0), (pi / 2, 0, 0), (0, 0, 1)),
           ((0.6, 0, 0), (0, 0, 0), (0, 0, 1)), ((0.62, -0.12, 0), (0, -pi / 2, 0), (0, 0, 1)),
           ((0, 0, 0), (0, pi / 2, 0), (0, 0, 1)), ((0, 0, 0), (0, -pi / 2, 0), (0, 0, 1))]
KR5_ARC_TOOL0 = rikin.homogeneous(_rpy(0, -pi, 0), np.array([0, 0, -0.115]))
KR5_ARC_LIMITS_URDF_DEG = [(-155, 155), (-180, 65), (-15, 158), (-350, 350), (-130, 130),
                           (-350, 350)]  # A4's lower limit is printed as 350 there (a typo)

LRMATE_200ID = [((0, 0, 0.33), (0, 0, 0), (0, 0, 1)), ((0.05, 0, 0), (0, 0, 0), (0, 1, 0)),
                ((0, 0, 0.33), (0, 0, 0), (0, -1, 0)), ((0, 0, 0.035), (0, 0, 0), (-1, 0, 0)),
                ((0.335, 0, 0), (0, 0, 0), (0, -1, 0)), ((0.08, 0, 0), (0, 0, 0), (-1, 0, 0))]
LRMATE_200ID_TOOL0 = rikin.homogeneous(_rpy(pi, -pi / 2, 0), None)
LRMATE_BASE = rikin.transl(0, 0, -0.33)  # base_link seen from the "base" (FANUC World) frame
LRMATE_LIMITS_URDF = [(-2.965, 2.965), (-1.745329, 2.530727), (-2.450966, 4.886922),
                      (-3.315, 3.315), (-2.18, 2.18), (-6.285, 6.285)]

DATA_SHEET = {
    "kr5": (robots.kuka_kr5_arc, KR5_ARC, KR5_ARC_TOOL0, np.eye(4)),
    "lrmate": (robots.fanuc_lrmate200id, LRMATE_200ID, LRMATE_200ID_TOOL0, LRMATE_BASE),
}


def in_limits(arm, rng, k=1):
    lo, hi = arm.qlim[:, 0], arm.qlim[:, 1]
    return rng.uniform(np.maximum(lo, -pi) + 0.05, np.minimum(hi, pi) - 0.05, size=(k, arm.n))


def same(arm, Q, q, tol=1e-7):
    """The row of ``Q`` nearest ``q`` (revolute joints modulo 2 pi), and whether it is ``q``."""
    d = np.where(arm.revolute, np.abs(rikin.wrap_angle(Q - q)), np.abs(Q - q) / arm.scale)
    return d.max(axis=1).min() <= tol


def assert_reaches(arm, Q, T, tol=1e-9):
    F = arm.fk(Q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= tol * arm.scale
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= tol


# ------------------------------------------------------------------ the row
@pytest.mark.parametrize("value", [1, -1, 1.0, -1.0, np.int64(-1), np.float32(1.0)])
def test_direction_takes_plus_or_minus_one(value):
    assert Link(direction=value).direction == int(value)


@pytest.mark.parametrize("value", [0, 2, -0.5, True, False, "-1", None, np.nan, [1], 1j])
def test_any_other_direction_is_refused_naming_it(value):
    with pytest.raises(InputError, match=r"^direction must be \+1 .* or -1 "):
        Link(direction=value)


# ------------------------------------------------------------------ FK
@pytest.mark.parametrize("name", sorted(DATA_SHEET))
def test_fk_is_the_makers_model_at_any_joints(name):
    make, joints, tool0, base = DATA_SHEET[name]
    arm = make()
    rng = np.random.default_rng(1)
    for q in rng.uniform(-2 * pi, 2 * pi, size=(20, 6)):
        assert np.abs(arm.fk(q) - urdf_fk(joints, tool0, q, base)).max() < 1e-14
    # the same table with every direction +1 is a different arm: the signs are what matter
    plain = arm._dh
    q = np.radians([30, 20, 10, 40, 50, 60])
    assert np.abs(plain.fk(q) - urdf_fk(joints, tool0, q, base)).max() > 0.05


@pytest.mark.parametrize("name", sorted(DATA_SHEET))
def test_limits_are_the_data_sheets_as_printed(name):
    make, *_ = DATA_SHEET[name]
    arm = make()
    if name == "kr5":
        assert np.allclose(np.degrees(arm.qlim), robots.KUKA_KR5_ARC_LIMITS_DEG)
        assert np.allclose(np.degrees(arm.qlim), KR5_ARC_LIMITS_URDF_DEG)
    else:
        assert np.allclose(arm.qlim, LRMATE_LIMITS_URDF)
    assert np.isinf(make(limits=False).qlim).all()


def test_reversed_prismatic_and_revolute_joints_fk_as_the_dh_table_at_minus_q():
    links = (Link(d=0.3, alpha=pi / 2, offset=0.2), Link("P", theta=0.4, d=0.5, offset=0.1),
             Link(a=0.7, alpha=-pi / 3), Link("P", d=0.2))
    rng = np.random.default_rng(2)
    for signs in ([1, -1, 1, -1], [-1, 1, -1, 1], [-1, -1, -1, -1]):
        rev = SerialArm(tuple(Link(**{**lk.__dict__, "direction": s})
                              for lk, s in zip(links, signs, strict=True)))
        plain = SerialArm(links)
        q = rng.uniform(-2, 2, size=(5, 4))
        assert np.allclose(rev.fk(q), plain.fk(q * signs), atol=1e-15)
        assert np.allclose(rev.fk(q[0], frames=True), plain.fk(q[0] * signs, frames=True))
        assert np.allclose(rev.fk_flange(q[0]), plain.fk_flange(q[0] * signs))


def test_jacobian_is_the_derivative_of_fk_in_the_data_sheets_joints():
    arm = robots.kuka_kr5_arc().replace(tool=rikin.transl(0.1, 0.0, 0.2))
    links = arm.links[:3] + (Link("P", d=0.2, direction=-1),)
    mixed = SerialArm(links, units="m")
    for a in (arm, mixed):
        q = np.linspace(0.3, 1.1, a.n)
        J = a.jacobian(q)
        h = 1e-7
        for j in range(a.n):
            dq = np.zeros(a.n)
            dq[j] = h
            Fp, Fm = a.fk(q + dq), a.fk(q - dq)
            v = (Fp[:3, 3] - Fm[:3, 3]) / (2 * h)
            dR = (Fp[:3, :3] - Fm[:3, :3]) / (2 * h) @ a.fk(q)[:3, :3].T
            w = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
            assert np.allclose(J[:3, j], v, atol=1e-6) and np.allclose(J[3:, j], w, atol=1e-6)


# ------------------------------------------------------------------ IK, end to end
@pytest.mark.parametrize("name", sorted(DATA_SHEET))
def test_ik_answers_in_the_data_sheets_joints_and_limits(name):
    make, joints, tool0, base = DATA_SHEET[name]
    arm = make()
    rng = np.random.default_rng(3)
    for q in in_limits(arm, rng, 15):
        T = urdf_fk(joints, tool0, q, base)  # the maker's model gives the pose
        res = arm.ik(T)
        assert same(arm, res.q, q)
        assert_reaches(arm, res.q, T)
        for row in res.q:  # and the maker's model agrees with every answer
            assert np.abs(urdf_fk(joints, tool0, row, base) - T).max() < 1e-9
        fit = arm.ik(T, within_limits=True)
        assert same(arm, fit.q, q) and len(fit) + fit.discarded == len(res)
        lo, hi = arm.qlim[:, 0], arm.qlim[:, 1]
        assert ((fit.q >= lo - 1e-9) & (fit.q <= hi + 1e-9)).all()
        near = arm.ik(T, near=q)
        assert np.abs(near.q[0] - q).max() < 1e-7
        batch = arm.ik_batch(T[None])
        got = batch.q[0][batch.valid[0]]
        assert len(got) >= len(res)
        assert all(same(arm, got, row) for row in res.q)


def test_within_limits_keeps_what_the_data_sheet_allows_not_the_dh_values():
    """A reversed joint with limits that are not symmetric (-20..150 deg): they bound the
    data sheet's q1 (140 deg is in), not the DH value -q1 (-140 deg would be out)."""
    arm = SerialArm((Link(d=0.4, a=0.18, alpha=-pi / 2, direction=-1,
                          qlim=(np.radians(-20), np.radians(150))),)
                    + robots.kuka_kr5_arc().links[1:], tool=robots.kuka_kr5_arc().tool)
    q = np.radians([140, -60, 80, 10, 40, 20])
    T = arm.fk(q)
    fit = arm.ik(T, within_limits=True)
    assert same(arm, fit.q, q)
    assert (fit.q[:, 0] >= np.radians(-20) - 1e-12).all()
    assert (fit.q[:, 0] <= np.radians(150) + 1e-12).all()


def _reverse(arm, signs):
    links = tuple(Link(**{**lk.__dict__, "direction": s})
                  for lk, s in zip(arm.links, signs, strict=True))
    return SerialArm(links, convention=arm.convention, base=arm.base, tool=arm.tool,
                     units=arm.units, name=arm.name + " reversed", solver=arm.solver)


def _target(arm, T):
    kind = rikin.ik.api._solver(arm._dh).target_kind
    if kind == "planar_position":
        return T[:2, 3]
    if kind == "position":
        return T[:3, 3]
    return T


TYPED = {
    "SCARA with a wrist": SerialArm((Link(d=0.4, a=0.3), Link(a=0.25, alpha=pi), Link("P"),
                                     Link(alpha=-pi / 2), Link(alpha=pi / 2), Link(d=0.1))),
    "Stanford": SerialArm((Link(d=0.412, alpha=-pi / 2), Link(d=0.154, alpha=pi / 2),
                           Link("P", theta=-pi / 2, a=0.0203), Link(alpha=-pi / 2),
                           Link(alpha=pi / 2), Link(d=0.263))),
    "cylindrical": SerialArm((Link(d=1.0), Link("P", alpha=-pi / 2), Link("P", d=0.5))),
    "KR5 (table)": robots.kuka_kr5_arc(limits=False)._dh,
}


@pytest.mark.parametrize("make", list(robots.LESSON_ROBOTS.values()) + list(TYPED.values()),
                         ids=list(robots.LESSON_ROBOTS) + list(TYPED))
def test_every_solver_sees_dh_values_and_hands_back_data_sheet_values(make):
    """Reversing joints changes no pose, only how q counts: every solution of the reversed
    arm is a solution of the plain one with the signs applied, one for one."""
    plain = make if isinstance(make, SerialArm) else make()
    rng = np.random.default_rng(4)
    for _ in range(4):
        signs = rng.choice([-1, 1], size=plain.n)
        signs[rng.integers(plain.n)] = -1
        rev = _reverse(plain, signs)
        q = rng.uniform(-pi, pi, plain.n)
        q[~plain.revolute] = rng.uniform(0.2, 1.0, (~plain.revolute).sum()) * plain.scale / 4
        T = rev.fk(q)
        assert np.allclose(T, plain.fk(q * signs))
        a, b = rev.ik(_target(rev, T)), plain.ik(_target(plain, T))
        assert len(a) == len(b) and same(rev, a.q, q)
        assert all(same(rev, a.q, row * signs) for row in b.q)
        assert a.labels == b.labels
        F = rev.fk(a.q)
        assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * rev.scale
        batch = rev.ik_batch(rev.fk(q)[None])
        got = batch.q[0][batch.valid[0]]
        assert all(same(rev, got, row) for row in a.q)


def test_classify_of_a_reversed_arm_is_its_tables():
    kr5 = robots.kuka_kr5_arc()
    assert str(classify(kr5)) == str(classify(kr5._dh))
    assert "quadratic" in str(classify(kr5))


def test_numerical_ik_of_a_reversed_arm_converges_in_data_sheet_values():
    arm = robots.kuka_kr5_arc()
    q = np.radians([40, -70, 100, 20, 60, -30])
    T = arm.fk(q)
    sol = ik_numerical(arm, T, q + 0.05)
    assert sol.success and np.abs(rikin.wrap_angle(sol.q - q)).max() < 1e-6


# ------------------------------------------------------------------ tables, drawings, widgets
def test_tables_print_the_reversed_joints_as_minus_q():
    kr5 = robots.kuka_kr5_arc()
    rows = kr5.dh_table().splitlines()
    assert re.search(r"^ 1 +R +-q1 ", rows[1]) and re.search(r"^ 2 +R +q2 ", rows[2])
    assert re.search(r"^ 4 +R +-q4 ", rows[4]) and re.search(r"^ 6 +R +-q6 ", rows[6])
    html = dh_table(kr5)._repr_html_()
    assert "−q1" in html and "−q4" in html and "−q6" in html and "−q2" not in html
    slide = SerialArm((Link("P", d=0.5, direction=-1),))
    assert "-q1+0.5" in slide.dh_table()
    assert "−q1 + 0.5" in dh_table(slide)._repr_html_()


def test_symbolic_fk_counts_the_reversed_joints_too():
    arm = robots.fanuc_lrmate200id()
    q = sympy.symbols("q1:7")
    T = symbolic.transform(arm.links, arm.convention, q=q)
    vals = np.radians([10, 20, 30, 40, 50, 60])
    num = np.array(T.subs(dict(zip(q, vals, strict=True))).evalf(), dtype=float)
    assert np.allclose(num, arm.fk_flange(vals), atol=1e-12)


def test_drawings_and_sliders_follow_the_data_sheets_joints():
    from rikin.plot import _link_path, plot_arm
    from rikin.widgets import TeachPanel

    arm = robots.kuka_kr5_arc()
    q = np.radians([50, -30, 40, 0, 30, 0])
    ax = plot_arm(arm, q)
    path = _link_path(arm, arm.fk(q, frames=True))
    drawn = np.concatenate([np.asarray(ln.get_data_3d()).T for ln in ax.get_lines()])
    assert np.nanmin(np.abs(drawn - path[-1]).sum(axis=1)) < 1e-12  # the TCP drawn where FK is
    assert path[-1][1] < 0  # A1 = +50 deg turns the arm clockwise seen from above
    panel = TeachPanel(arm)
    panel.set(redraw=False, q1=50.0, q2=-30.0, q3=40.0, q5=30.0)
    assert np.allclose(panel.q, q)
    lo, hi = panel.ranges()[0][2:]
    assert (lo, hi) == pytest.approx((-155.0, 155.0))  # the data sheet's range, as printed
    assert f"{arm.fk(q)[1, 3]:.4g}" in panel.pose_text()


def test_the_fast_paths_fk_check_counts_reversed_joints():
    """FKCheck folds each link into constant matrices (rikin.SerialArm._link_constants);
    a reversed joint negates its sine part and its offset there."""
    from rikin.ik.fkcheck import FKCheck

    arm = robots.kuka_kr5_arc().replace(base=rikin.transl(0.1, 0.2, 0.3))
    arm = SerialArm(tuple(Link(**{**lk.__dict__, "offset": 0.3 * i})
                          for i, lk in enumerate(arm.links)), base=arm.base, tool=arm.tool)
    rng = np.random.default_rng(6)
    q = rng.uniform(-pi, pi, size=(3, 6))
    T = arm.fk(q[0])
    check = FKCheck(arm)
    assert check(q[:1], T) < 1e-28
    F = arm.fk(q)
    want = sum(np.sum((F[k, :3, :3] - T[:3, :3]) ** 2)
               + np.sum((F[k, :3, 3] - T[:3, 3]) ** 2) / arm.scale**2 for k in range(3))
    assert check(q, T) == pytest.approx(want, rel=1e-9)
