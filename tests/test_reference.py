"""The instructor's reference FK/IK of the four exercise arms, tested like rikin.

Every IK solution is put back through FK; the joint vector a target was made
from must be among the solutions (so every branch is exercised as a
generator); solution counts; singular families; unreachable targets raise.
FK is also checked against closed forms written here by hand from the
geometry of each arm (not from the reference code).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from rikingrade.reference import ARMS
from rikingrade.reference._common import wrist_solutions
from rikingrade.reference.scara import ELBOW_LEFT, ELBOW_RIGHT
from rikingrade.reference.spherical import BACK, FRONT

import rikin

PI = np.pi
ROUND_TRIP = 1e-9        # relative to the arm's size
SAME = 1e-9

length = st.floats(0.5, 20.0)
angle = st.floats(-PI, PI)
extension = st.floats(0.0, 20.0)
wrist_angle = st.floats(-PI, PI)


def lengths_of(name: str, values: list[float]) -> dict[str, float]:
    return dict(zip(ARMS[name].lengths, values, strict=False))


def contains(Q: np.ndarray, q: np.ndarray, revolute: np.ndarray,
             ignore: tuple[int, ...] = ()) -> bool:
    keep = np.ones(len(q), bool)
    keep[list(ignore)] = False
    d = np.where(revolute, rikin.wrap_angle(Q - q), Q - q)[:, keep]
    return bool(np.any(np.all(np.abs(d) < 1e-7, axis=1)))


def assert_round_trip(arm, S, target, L, tool=None):
    scale = arm.scale(L) + (tool or 0.0)
    for q in S.q:
        if tool is None:
            p = arm.fk(q, **L)[:3, 3]
            assert np.abs(p - target).max() <= ROUND_TRIP * scale, (q, p, target)
        else:
            T = arm.fk_6dof(q, tool, **L)
            assert np.abs(T[:3, 3] - target[:3, 3]).max() <= ROUND_TRIP * scale
            assert np.abs(T[:3, :3] - target[:3, :3]).max() <= ROUND_TRIP
        assert np.all(q[~S.revolute] >= 0.0), "prismatic joints only extend"
        assert np.all(np.abs(q[S.revolute]) <= PI + 1e-12), "angles wrapped to (-pi, pi]"


def assert_distinct(S):
    for i in range(len(S)):
        for j in range(i):
            d = np.where(S.revolute, rikin.wrap_angle(S.q[i] - S.q[j]), S.q[i] - S.q[j])
            assert np.abs(d).max() > SAME, "duplicate solutions"


# ------------------------------------------------------------------ FK against hand formulas
@given(st.lists(length, min_size=3, max_size=3), st.lists(extension, min_size=3, max_size=3))
def test_cartesian_fk_formula(ls, q):
    L = lengths_of("cartesian", ls)
    T = ARMS["cartesian"].fk(q, **L)
    np.testing.assert_allclose(T[:3, 3], [ls[1] + q[1], ls[2] + q[2], ls[0] + q[0]], atol=1e-9)
    np.testing.assert_allclose(T[:3, 2], [0, 1, 0], atol=1e-12)   # z3 along y0, as joint 3 moves


@given(st.lists(length, min_size=2, max_size=2), angle, extension, extension)
def test_cylindrical_fk_formula(ls, q1, q2, q3):
    l1, l2 = ls
    T = ARMS["cylindrical"].fk([q1, q2, q3], l1=l1, l2=l2)
    r = l2 + q3
    np.testing.assert_allclose(T[:3, 3], [r * np.cos(q1), r * np.sin(q1), l1 + q2], atol=1e-9)
    np.testing.assert_allclose(T[:3, 2], [np.cos(q1), np.sin(q1), 0], atol=1e-12)  # radial


@given(st.lists(length, min_size=2, max_size=2), angle, angle, extension)
def test_spherical_fk_formula(ls, q1, q2, q3):
    l1, l2 = ls
    T = ARMS["spherical"].fk([q1, q2, q3], l1=l1, l2=l2)
    u = np.array([np.cos(q2) * np.cos(q1), np.cos(q2) * np.sin(q1), np.sin(q2)])   # the boom
    np.testing.assert_allclose(T[:3, 3], [0, 0, l1] + (l2 + q3) * u, atol=1e-9)
    np.testing.assert_allclose(T[:3, 2], u, atol=1e-12)


@given(st.lists(length, min_size=3, max_size=3), angle, angle, extension)
def test_scara_fk_formula(ls, q1, q2, q3):
    l1, l2, l3 = ls
    T = ARMS["scara"].fk([q1, q2, q3], l1=l1, l2=l2, l3=l3)
    expected = [l2 * np.cos(q1) + l3 * np.cos(q1 + q2), l2 * np.sin(q1) + l3 * np.sin(q1 + q2),
                l1 - q3]
    np.testing.assert_allclose(T[:3, 3], expected, atol=1e-9)
    np.testing.assert_allclose(T[:3, 2], [0, 0, -1], atol=1e-12)   # the quill points down


@pytest.mark.parametrize("name", list(ARMS))
@given(q=st.lists(wrist_angle, min_size=3, max_size=3), tool=st.floats(0.1, 5.0))
def test_wrist_is_zyz_on_frame_3_with_tool(name, q, tool):
    arm = ARMS[name]
    L = {n: 2.0 + i for i, n in enumerate(arm.lengths)}
    q123 = np.array([0.3, 0.4, 1.5])
    T_0_3 = arm.fk(q123, **L)
    T = arm.fk_6dof(np.concatenate([q123, q]), tool, **L)
    R_3_6 = rikin.rotz(q[0]) @ rikin.roty(q[1]) @ rikin.rotz(q[2])
    np.testing.assert_allclose(T[:3, :3], T_0_3[:3, :3] @ R_3_6, atol=1e-12)
    # the wrist centre is the origin of frame 3, the TCP is `tool` ahead of it along z6
    np.testing.assert_allclose(T[:3, 3] - tool * T[:3, 2], T_0_3[:3, 3], atol=1e-12)
    F = arm.fk_flange_6dof(np.concatenate([q123, q]), tool, **L)
    np.testing.assert_allclose(F[:3, 3], T_0_3[:3, 3], atol=1e-12)


# ------------------------------------------------------------------ IK round trips
COUNTS = {"cartesian": 1, "cylindrical": 1, "spherical": 2, "scara": 2}


@st.composite
def regular_case(draw, name):
    """Lengths and a regular q on any branch (spherical: also back; SCARA: both elbows)."""
    arm = ARMS[name]
    L = lengths_of(name, [draw(length) for _ in arm.lengths])
    if name == "cartesian":
        q = [draw(extension) for _ in range(3)]
    elif name == "cylindrical":
        q = [draw(angle), draw(extension), draw(extension)]
    elif name == "spherical":
        q2 = draw(st.one_of(st.floats(-1.45, 1.45), st.floats(1.7, PI), st.floats(-PI, -1.7)))
        q = [draw(angle), q2, draw(extension)]
    else:
        if abs(L["l2"] - L["l3"]) < 1e-3:
            L["l3"] = L["l2"] + 0.5
        q2 = draw(st.one_of(st.floats(0.05, PI - 0.05), st.floats(-PI + 0.05, -0.05)))
        q = [draw(angle), q2, draw(extension)]
    return L, np.array(q)


@pytest.mark.parametrize("name", list(ARMS))
@given(data=st.data())
def test_ik_round_trip_every_branch(name, data):
    arm = ARMS[name]
    L, q = data.draw(regular_case(name))
    p = arm.fk(q, **L)[:3, 3]
    S = arm.ik(p, **L)
    assert len(S) == COUNTS[name]
    assert not S.singular
    assert_round_trip(arm, S, p, L)
    assert_distinct(S)
    assert contains(S.q, q, S.revolute), (q, S.q)


@pytest.mark.parametrize("name", list(ARMS))
@given(data=st.data(), w=st.lists(wrist_angle, min_size=3, max_size=3),
       sign=st.sampled_from([-1.0, 1.0]), tool=st.floats(0.1, 5.0))
def test_ik_6dof_round_trip_every_branch(name, data, w, sign, tool):
    arm = ARMS[name]
    L, q123 = data.draw(regular_case(name))
    q5 = sign * np.clip(abs(w[1]), 0.05, PI - 0.05)
    q = np.concatenate([q123, [w[0], q5, w[2]]])
    T = arm.fk_6dof(q, tool, **L)
    S = arm.ik_6dof(T, tool, **L)
    assert len(S) == 2 * COUNTS[name]
    assert not S.singular
    assert_round_trip(arm, S, T, L, tool)
    assert_distinct(S)
    assert contains(S.q, q, S.revolute)
    assert len(set(S.labels)) == len(S)


def test_branch_labels_mean_what_they_say():
    S = ARMS["scara"].ik([2.0, 3.0, 2.5], l1=4.0, l2=3.0, l3=2.0)
    by = dict(zip(S.labels, S.q, strict=True))
    assert by[ELBOW_RIGHT][1] > 0 > by[ELBOW_LEFT][1]
    # seen from above, the elbow of "elbow right" is right of the base -> TCP line
    for label, sign in ((ELBOW_RIGHT, -1), (ELBOW_LEFT, 1)):
        q1 = by[label][0]
        elbow = 3.0 * np.array([np.cos(q1), np.sin(q1)])
        assert np.sign(2.0 * elbow[1] - 3.0 * elbow[0]) == sign   # z of (TCP x elbow)
    S = ARMS["spherical"].ik([2.0, 1.5, 4.5], l1=3.0, l2=2.0)
    by = dict(zip(S.labels, S.q, strict=True))
    assert abs(by[FRONT][1]) < PI / 2 < abs(by[BACK][1])
    assert abs(rikin.wrap_angle(by[FRONT][0] - np.arctan2(1.5, 2.0))) < 1e-12


# ------------------------------------------------------------------ singular and boundary targets
@given(ls=st.lists(length, min_size=2, max_size=2), q1=angle, up=st.booleans(), q3=extension,
       t=angle)
def test_spherical_on_axis_is_one_family_with_q1_free(ls, q1, up, q3, t):
    arm = ARMS["spherical"]
    L = lengths_of("spherical", ls)
    p = arm.fk([q1, PI / 2 if up else -PI / 2, q3], **L)[:3, 3]
    S = arm.ik(p, **L)
    assert len(S) == 1 and S.free == ((0,),)
    member = S.q[0].copy()
    member[0] = t                       # any q1 reaches the target
    np.testing.assert_allclose(arm.fk(member, **L)[:3, 3], p, atol=1e-9 * arm.scale(L))


@given(ls=st.lists(length, min_size=3, max_size=3), q1=angle, q3=extension,
       folded=st.booleans())
def test_scara_stretched_or_folded_has_one_solution(ls, q1, q3, folded):
    arm = ARMS["scara"]
    L = lengths_of("scara", ls)
    if abs(L["l2"] - L["l3"]) < 0.1:
        L["l3"] = L["l2"] + 0.5
    q = np.array([q1, PI if folded else 0.0, q3])
    p = arm.fk(q, **L)[:3, 3]           # rounding may put it a hair beyond the limit
    S = arm.ik(p, **L)
    assert len(S) == 1
    assert_round_trip(arm, S, p, L)
    assert contains(S.q, q, S.revolute)


@pytest.mark.parametrize("name", list(ARMS))
@pytest.mark.parametrize("q5", [0.0, PI])
@given(data=st.data(), q4=wrist_angle, q6=wrist_angle, t=angle, tool=st.floats(0.1, 5.0))
def test_wrist_singularity_is_one_family_per_arm_solution(name, q5, data, q4, q6, t, tool):
    arm = ARMS[name]
    L, q123 = data.draw(regular_case(name))
    q = np.concatenate([q123, [q4, q5, q6]])
    T = arm.fk_6dof(q, tool, **L)
    S = arm.ik_6dof(T, tool, **L)
    assert len(S) == COUNTS[name]
    assert all(f == (3, 5) for f in S.free)
    assert_round_trip(arm, S, T, L, tool)
    assert contains(S.q, q, S.revolute, ignore=(3, 5))
    # moving along the family keeps the pose: q5 = 0 fixes q4 + q6, q5 = pi fixes q6 - q4
    member = S.q[0].copy()
    member[3] += t
    member[5] += -t if q5 == 0.0 else t
    member[3:] = rikin.wrap_angle(member[3:])
    Tm = arm.fk_6dof(member, tool, **L)
    np.testing.assert_allclose(Tm, T, atol=1e-9 * (arm.scale(L) + tool))


def test_wrist_solutions_regular_and_singular():
    R = rikin.rotz(0.3) @ rikin.roty(-0.8) @ rikin.rotz(1.9)
    sols, singular = wrist_solutions(R)
    assert not singular and len(sols) == 2
    for q4, q5, q6 in sols:
        np.testing.assert_allclose(rikin.rotz(q4) @ rikin.roty(q5) @ rikin.rotz(q6), R, atol=1e-12)
    sols, singular = wrist_solutions(rikin.rotz(0.7))
    assert singular and len(sols) == 1 and sols[0][1] == 0.0
    sols, singular = wrist_solutions(rikin.roty(PI) @ rikin.rotz(0.7))
    assert singular and sols[0][1] == PI
    q4, q5, q6 = sols[0]
    np.testing.assert_allclose(rikin.rotz(q4) @ rikin.roty(q5) @ rikin.rotz(q6),
                               rikin.roty(PI) @ rikin.rotz(0.7), atol=1e-12)


# ------------------------------------------------------------------ unreachable
@given(ls=st.lists(length, min_size=3, max_size=3), q=st.lists(extension, min_size=3, max_size=3),
       which=st.integers(0, 2), short=st.floats(1e-6, 10.0))
def test_cartesian_below_a_slide_start_raises(ls, q, which, short):
    arm = ARMS["cartesian"]
    L = lengths_of("cartesian", ls)
    q = np.array(q)
    q[which] = -short
    with pytest.raises(rikin.UnreachableError, match="retract"):
        arm.ik(arm.fk(q, **L)[:3, 3], **L)


@given(ls=st.lists(length, min_size=2, max_size=2), q1=angle, frac=st.floats(0.0, 0.999),
       z=st.floats(0.0, 20.0))
def test_cylindrical_inside_the_retracted_radius_raises(ls, q1, frac, z):
    l1, l2 = ls
    r = frac * l2
    with pytest.raises(rikin.UnreachableError, match="column axis"):
        ARMS["cylindrical"].ik([r * np.cos(q1), r * np.sin(q1), l1 + z], l1=l1, l2=l2)
    with pytest.raises(rikin.UnreachableError, match="below"):
        ARMS["cylindrical"].ik([l2 + 1, 0.0, l1 - 1e-3 - z], l1=l1, l2=l2)


@given(ls=st.lists(length, min_size=2, max_size=2),
       d=st.lists(st.floats(-1, 1), min_size=3, max_size=3), frac=st.floats(0.0, 0.999))
def test_spherical_inside_the_retracted_boom_raises(ls, d, frac):
    l1, l2 = ls
    d = np.array(d)
    n = np.linalg.norm(d)
    u = d / n if n > 1e-6 else np.array([0.0, 0.0, 1.0])
    with pytest.raises(rikin.UnreachableError, match="shoulder"):
        ARMS["spherical"].ik(np.array([0, 0, l1]) + frac * l2 * u, l1=l1, l2=l2)


@given(ls=st.lists(length, min_size=3, max_size=3), a=angle, more=st.floats(1e-6, 10.0),
       z=st.floats(0.0, 10.0))
def test_scara_out_of_reach_raises(ls, a, more, z):
    l1, l2, l3 = ls
    L = dict(l1=l1, l2=l2, l3=l3)
    far = l2 + l3 + more
    with pytest.raises(rikin.UnreachableError, match="beyond the full reach"):
        ARMS["scara"].ik([far * np.cos(a), far * np.sin(a), l1 - z], **L)
    with pytest.raises(rikin.UnreachableError, match="above"):
        ARMS["scara"].ik([l2, l3, l1 + more], **L)
    inner = abs(l2 - l3) - more
    if inner > 0:
        with pytest.raises(rikin.UnreachableError, match="inside the circle"):
            ARMS["scara"].ik([inner * np.cos(a), inner * np.sin(a), l1 - z], **L)


@pytest.mark.parametrize("name", list(ARMS))
def test_samplers_make_what_they_promise(name):
    """The hidden tests rely on these: unreachable stays unreachable, 'TCP within reach' holds."""
    arm = ARMS[name]
    rng = np.random.default_rng(7)
    for _ in range(30):
        L = arm.sample_lengths(rng)
        for near in (False, True):
            for _kind, p in arm.unreachable_points(rng, L, near=near):
                with pytest.raises(rikin.UnreachableError):
                    arm.ik(p, **L)
        tool = arm.sample_tool(rng)
        poses = arm.unreachable_poses(rng, L, tool)
        assert len(poses) == 3
        for k, (kind, T) in enumerate(poses):
            with pytest.raises(rikin.UnreachableError, match="wrist centre"):
                arm.ik_6dof(T, tool, **L)
            if k > 0:
                assert "TCP is within reach" in kind
                arm.ik(T[:3, 3], **L)           # the TCP alone would be reachable
        q = arm.sample_q(rng, L)
        S = arm.ik(arm.fk(q, **L)[:3, 3], **L)
        assert len(S) == COUNTS[name] and not S.singular


@pytest.mark.parametrize("name", list(ARMS))
def test_bad_input_is_refused(name):
    arm = ARMS[name]
    L = {n: 2.0 for n in arm.lengths}
    with pytest.raises(rikin.InputError, match="positive length"):
        arm.ik([1.0, 1.0, 1.0], **dict(L, **{arm.lengths[0]: -1.0}))
    with pytest.raises(rikin.InputError, match="expected lengths"):
        arm.ik([1.0, 1.0, 1.0], **L, extra=1.0)
    with pytest.raises(rikin.InputError, match="3 finite numbers"):
        arm.ik([1.0, np.nan, 1.0], **L)
    with pytest.raises(rikin.InputError, match="not a rotation"):
        arm.ik_6dof(np.diag([1.0, 2.0, 1.0, 1.0]), 1.0, **L)
