"""The course's arm families typed as DH tables (issue 29, Wanted 2 and 5).

Each family is typed from its table with random lengths, base and tool, in standard and
modified DH: classify names it; every solution reaches the target by FK (checked here,
not by the solver); the generating joints are among the solutions; every solution that a
numerical solver finds from many random starts is among them (a lower bound on the set
that no closed form wrote); the lesson robots' tables give the lesson solvers' sets and
labels; the exercise arms' tables give what the grader's reference solvers give; near
misses and arms outside every family are refused with the reason, and numerical IK is
what rikin then offers.
"""

import re
import warnings

import numpy as np
import pytest
from rikingrade.reference import ARMS as EXERCISE_ARMS

import rikin
from rikin import InputError, Link, SerialArm, UnreachableError, robots
from rikin.ik import classify, ik_numerical, ik_numerical_multistart

pi = np.pi
WRIST = (Link(alpha=-pi / 2), Link(alpha=pi / 2))


def _pose(rng, size=1.0):
    return rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-pi, pi, 3)), rng.uniform(-size, size, 3))


def _turn(rng):
    return rikin.homogeneous(rikin.rpy_to_r(*rng.uniform(-pi, pi, 3)), None)


# ------------------------------------------------------------------ the families, as typed
def scara(L, modified=False):
    if modified:
        return SerialArm((Link(d=L[0]), Link(a=L[1]), Link("P", a=L[2], alpha=pi)),
                         convention="modified")
    return SerialArm((Link(d=L[0], a=L[1]), Link(a=L[2], alpha=pi), Link("P")))


def scara_wrist(L, modified=False):
    return SerialArm(scara(L).links + WRIST + (Link(d=L[3]),))


def scara4(L, modified=False):
    """A four-axis SCARA (RRPR: the quill, then the tool's roll about it)."""
    if modified:
        return SerialArm((Link(d=L[0]), Link(a=L[1]), Link("P", a=L[2], alpha=pi),
                          Link(d=0.1 * L[3], offset=0.4)), convention="modified")
    return SerialArm((Link(d=L[0], a=L[1]), Link(a=L[2], alpha=pi), Link("P"),
                      Link(d=0.2 * L[3], offset=0.4)))


def scara4_roll_first(L, modified=False):
    """A four-axis SCARA typed with the roll before the quill (RRRP)."""
    return SerialArm((Link(d=L[0], a=L[1]), Link(a=L[2], alpha=pi), Link(offset=0.3),
                      Link("P", d=0.1 * L[3])))


def pitched(L, modified=False):
    """A four-axis articulated arm (a waist, then shoulder, elbow and wrist pitch axes),
    with a shoulder offset along the pitch axes, as the small lab arms have."""
    if modified:
        return SerialArm((Link(d=L[0]), Link(alpha=pi / 2, d=0.1 * L[3]), Link(a=L[1], offset=0.3),
                          Link(a=L[2])), convention="modified", tool=rikin.transl(0.2 * L[3], 0, 0))
    return SerialArm((Link(d=L[0], alpha=pi / 2), Link(a=L[1], d=0.1 * L[3], offset=-0.3),
                      Link(a=L[2], offset=0.3), Link(a=0.2 * L[3])))


def cylindrical(L, modified=False):
    if modified:
        return SerialArm((Link(d=L[0]), Link("P", theta=pi / 2), Link("P", alpha=pi / 2, d=L[1])),
                         convention="modified")
    return SerialArm((Link(d=L[0]), Link("P", alpha=-pi / 2), Link("P", d=L[1])))


def cylindrical_wrist(L, modified=False):
    return SerialArm(cylindrical(L).links + WRIST + (Link(d=L[2]),))


def spherical(L, modified=False):
    return SerialArm((Link(d=L[0], alpha=pi / 2), Link(alpha=pi / 2, offset=pi / 2),
                      Link("P", d=L[1])))


def stanford(L, modified=False):
    """The Stanford arm (Corke's table: shoulder offset d2, the boom's offset a3)."""
    return SerialArm((Link(d=L[0], alpha=-pi / 2), Link(d=L[1], alpha=pi / 2),
                      Link("P", theta=-pi / 2, a=L[2] / 10), Link(alpha=-pi / 2),
                      Link(alpha=pi / 2), Link(d=L[3])))


def cartesian(L, modified=False):
    return SerialArm((Link("P", d=L[0], alpha=-pi / 2),
                      Link("P", theta=-pi / 2, alpha=-pi / 2, d=L[1]), Link("P", d=L[2])))


def cartesian_wrist(L, modified=False):
    return SerialArm(cartesian(L).links + WRIST + (Link(d=L[3]),))


def planar_3r(L, modified=False):
    if modified:
        return SerialArm((Link(), Link(a=L[0]), Link(a=L[1])), convention="modified",
                         tool=rikin.transl(L[2], 0, 0))
    return SerialArm((Link(a=L[0], d=0.2 * L[3]), Link(a=L[1], alpha=pi, offset=0.3),
                      Link(a=L[2])))


def planar_2r(L, modified=False):
    return SerialArm((Link(a=L[0], offset=-0.4), Link(a=L[1], d=0.1 * L[2])))


def angular_3r(L, modified=False):
    """The angular 3R typed with its upper arm along x at q = 0 and axis 3 reversed."""
    return SerialArm((Link(d=L[0], alpha=-pi / 2, offset=0.2), Link(a=L[1], offset=-pi / 2),
                      Link(a=L[2], alpha=pi)))


#: name -> (table maker, family name classify gives, solutions of a regular target, kind)
FAMILIES = {
    "planar 2R": (planar_2r, "planar 2R", 2, "position"),
    "planar 3R": (planar_3r, "planar 3R", 2, "pose"),
    "angular 3R": (angular_3r, "angular (anthropomorphic) 3R", 4, "position"),
    "SCARA": (scara, "SCARA", 2, "position"),
    "SCARA with a wrist": (scara_wrist, "SCARA with a spherical wrist", 4, "pose"),
    "four-axis SCARA": (scara4, "four-axis SCARA", 2, "pose"),
    "four-axis SCARA, roll first": (scara4_roll_first, "four-axis SCARA", 2, "pose"),
    "four-axis articulated": (pitched, "four-axis articulated arm", 2, "pose"),
    "cylindrical": (cylindrical, "cylindrical arm", 2, "position"),
    "cylindrical with a wrist": (cylindrical_wrist, "cylindrical arm with a spherical wrist", 4,
                                 "pose"),
    "spherical": (spherical, "spherical (polar) arm", 4, "position"),
    "Stanford": (stanford, "spherical (polar) arm with a spherical wrist (as on the Stanford", 8,
                 "pose"),
    "cartesian": (cartesian, "cartesian arm", 1, "position"),
    "cartesian with a wrist": (cartesian_wrist, "cartesian arm with a spherical wrist", 2,
                               "pose"),
}
MODIFIED = ("planar 3R", "SCARA", "cylindrical", "four-axis SCARA", "four-axis articulated")


def typed(name, rng, modified=False):
    """The family's table with random lengths, a random base, and a random tool (one that
    only turns the TCP for an arm that solves for a position)."""
    make, _, _, kind = FAMILIES[name]
    arm = make(rng.uniform(0.5, 2.0, 4), modified)
    tool = _pose(rng, 0.3) if kind == "pose" else _turn(rng)
    return arm.replace(base=_pose(rng, 2.0), tool=tool, name=name)


def random_q(arm, rng):
    q = rng.uniform(-pi, pi, arm.n)
    q[~arm.revolute] = rng.uniform(0.1, 1.0, int((~arm.revolute).sum())) * arm.scale / 3
    return q


def target(arm, T, name):
    if FAMILIES[name][3] == "position" and name.startswith("planar"):
        return T  # a 4x4 pose whose position is used: the arm's plane is not z = 0 here
    if FAMILIES[name][3] == "position":
        return T[:3, 3]
    return T


def near(arm, Q, q, tol=1e-7):
    d = np.where(arm.revolute, np.abs(rikin.wrap_angle(Q - q)), np.abs(Q - q) / arm.scale)
    return d.max(axis=-1).min() <= tol


def assert_fk(arm, res, T, name):
    F = arm.fk(res.q)
    assert np.abs(F[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * arm.scale
    if FAMILIES[name][3] == "pose":
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= 1e-9


# ------------------------------------------------------------------ every family
@pytest.mark.parametrize(("name", "modified"), [(n, False) for n in sorted(FAMILIES)]
                         + [(n, True) for n in MODIFIED])
def test_typed_family_solves_every_target_with_every_solution(name, modified):
    rng = np.random.default_rng([len(name), int(modified), sum(map(ord, name))])
    for _ in range(3):
        arm = typed(name, rng, modified)
        c = classify(arm)
        assert c.closed_form and c.family.startswith(FAMILIES[name][1]), str(c)
        assert c.solutions == FAMILIES[name][2]
        for _ in range(6):
            q = random_q(arm, rng)
            T = arm.fk(q)
            res = arm.ik(target(arm, T, name))
            assert_fk(arm, res, T, name)
            assert near(arm, res.q, q), f"{name}: the generating joints are missing"
            assert len(res) == FAMILIES[name][2] or res.singular
            batch = arm.ik_batch(T[None])
            got = batch.q[0][batch.valid[0]]
            assert all(near(arm, got, row) for row in res.q)


@pytest.mark.parametrize("s", [1e-90, 1e-8, 1e8, 1e90])
def test_every_family_at_any_size_rikin_takes(s):
    """Lengths from 1e-100 to 1e100 are input (the lesson arms are checked so in
    test_real_input): the families' geometry and tolerances scale with the arm."""
    rng = np.random.default_rng(12)
    base = rikin.homogeneous(rikin.rpy_to_r(0.1, 0.2, 0.3), np.array([1.0, 2.0, 3.0]) * s)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name, (make, family, count, _) in FAMILIES.items():
            arm = make(rng.uniform(0.5, 2.0, 4) * s).replace(base=base)
            assert classify(arm).family.startswith(family), (name, str(classify(arm)))
            for _ in range(2):
                q = random_q(arm, rng)
                T = arm.fk(q)
                res = arm.ik(target(arm, T, name))
                assert_fk(arm, res, T, name)
                assert near(arm, res.q, q, 1e-6) and (len(res) == count or res.singular)


@pytest.mark.parametrize("name", ["planar 3R", "SCARA", "Stanford", "SCARA with a wrist",
                                  "cylindrical with a wrist", "spherical", "angular 3R",
                                  "cartesian with a wrist", "four-axis SCARA",
                                  "four-axis SCARA, roll first", "four-axis articulated"])
def test_every_solution_a_numerical_solver_finds_is_in_the_closed_forms_set(name):
    """The done-when of issue 29 for the course families: the numerical solver, started
    from 40 random joint vectors, finds no solution the closed form lacks, and for these
    targets it finds them all."""
    rng = np.random.default_rng(7)
    arm = typed(name, rng)
    mask = None if FAMILIES[name][3] == "pose" else (1, 1, 1, 0, 0, 0)
    if name == "planar 3R":
        mask = (1, 1, 1, 1, 1, 1)
    found_all = 0
    for _ in range(3):
        q = random_q(arm, rng)
        T = arm.fk(q)
        res = arm.ik(target(arm, T, name))
        numerical = ik_numerical_multistart(arm, T, 40, rng=int(rng.integers(1000)), mask=mask)
        assert numerical, "the numerical solver found nothing"
        for row in numerical:
            assert near(arm, res.q, row, 1e-6), f"{name}: numerical found {row} not in the set"
        found_all += all(near(arm, np.array(numerical), row, 1e-6) for row in res.q)
    assert found_all >= 1  # the lower bound is tight on some target


@pytest.mark.parametrize("make", [robots.planar_2r, robots.planar_3r, robots.angular_3r,
                                  robots.pprrr, robots.rprrr])
def test_a_lesson_robots_table_gets_the_lesson_solvers_set_and_labels(make):
    lesson = make()
    rng = np.random.default_rng(8)
    for base, tool in ((None, None), (_pose(rng, 3.0), _turn(rng))):
        if lesson.n < 5 and base is not None:
            base = rikin.transl(*rng.uniform(-3, 3, 2), 0.0) @ rikin.transforms.trotz(0.7)
            tool = rikin.transforms.trotz(-0.4)  # (x, y, phi) targets: the plane stays z = 0
        lesson_arm = make(base=base, tool=tool)
        table = SerialArm(lesson_arm.links, convention=lesson_arm.convention,
                          base=lesson_arm.base, tool=lesson_arm.tool, name="typed")
        assert table.solver is None and classify(table).closed_form
        for _ in range(5):
            q = random_q(lesson_arm, rng)
            T = lesson_arm.fk(q)
            t = T[:2, 3] if lesson.n == 2 else T[:3, 3] if make is robots.angular_3r else T
            if make is robots.planar_3r:
                t = np.array([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])])
            a, b = lesson_arm.ik(t), table.ik(t)
            assert np.abs(a.q - b.q).max() < 1e-9 and a.labels == b.labels
            assert a.singular == b.singular


def test_a_lesson_arm_typed_another_way_gets_the_lesson_solvers_set():
    """The planar 3R typed in modified DH (frame 3 at joint 3, the last link in the tool)
    is the lesson arm at the same joint values: the same solutions and labels. The angular
    3R typed with its upper arm along x at q = 0 and axis 3 reversed counts its joints
    otherwise, but places the same elbows: the same configurations."""
    rng = np.random.default_rng(9)
    lesson = robots.planar_3r(1.0, 0.8, 0.5)
    mod = SerialArm((Link(), Link(a=1.0), Link(a=0.8)), convention="modified",
                    tool=rikin.transl(0.5, 0, 0))
    ang = robots.angular_3r(1.0, 0.8, 0.6)
    other = angular_3r((1.0, 0.8, 0.6))
    for _ in range(5):
        q = rng.uniform(-pi, pi, 3)
        T = lesson.fk(q)
        a, b = lesson.ik(T), mod.ik(T)
        assert np.abs(rikin.wrap_angle(a.q - b.q)).max() < 1e-9 and a.labels == b.labels
        p = ang.fk(q)[:3, 3]
        c, d = ang.ik(p), other.ik(p)
        assert len(c) == len(d) and c.labels == d.labels
        elbows_c = ang.fk(c.q, frames=True)[:, 2, :3, 3]
        elbows_d = other.fk(d.q, frames=True)[:, 2, :3, 3]
        assert np.abs(elbows_c - elbows_d).max() < 1e-9
        assert_fk(other, d, ang.fk(q), "angular 3R")


# ------------------------------------------------------------------ the exercises' arms
@pytest.mark.parametrize("exercise", sorted(EXERCISE_ARMS))
def test_the_exercise_arms_tables_give_the_grader_references_solutions(exercise):
    """The grader's reference solvers (written for the exercises, with slides that only
    extend): rikin's set, kept to q >= 0 for the slides, is theirs, with and without the
    wrist."""
    ex = EXERCISE_ARMS[exercise]
    rng = np.random.default_rng(10)
    for _ in range(3):
        L = ex.sample_lengths(rng)
        arm = ex.arm(**L)
        assert arm.solver is None and classify(arm).closed_form, classify(arm)
        q = ex.sample_q(rng, L)
        p = ex.fk(q, **L)[:3, 3]
        ref = ex.ik(p, **L)
        mine = arm.ik(p).q
        mine = mine[(mine[:, ~arm.revolute] >= -1e-12).all(axis=1)]
        assert len(mine) == len(ref) and all(near(arm, mine, row) for row in ref.q)
        tool = ex.sample_tool(rng)
        arm6 = ex.arm_6dof(tool, **L)
        q6 = ex.sample_q_6dof(rng, L)
        T = ex.fk_6dof(q6, tool, **L)
        ref6 = ex.ik_6dof(T, tool, **L)
        mine6 = arm6.ik(T).q
        mine6 = mine6[(mine6[:, ~arm6.revolute] >= -1e-12).all(axis=1)]
        assert len(mine6) == len(ref6) and all(near(arm6, mine6, row) for row in ref6.q)


# ------------------------------------------------------------------ edges of the families
def test_unreachable_targets_say_why_and_by_how_much():
    cases = [
        (scara((1.0, 1.0, 0.6)), np.array([1.7, 0.0, 0.0]), r"0\.1 beyond the reach of links 1-2"),
        (scara((1.0, 1.0, 0.6)), np.array([0.3, 0.0, 0.0]), r"0\.1 too close to axis 1"),
        (SerialArm((Link(d=1.0), Link("P", alpha=-pi / 2), Link("P", d=0.5, a=0.4))),
         np.array([0.1, 0.2, 0.3]), r"closer than the slides can bring it"),
        (stanford((0.4, 0.15, 0.2, 0.2))._dh, None, r"closer than the boom's line"),
        (stanford((0.412, 0.154, 0.203, 0.263)), rikin.homogeneous(
            rikin.rotx(pi), np.array([0.1, 0.0, 0.649])),
         r"0\.1 from axis 1, 0\.0337 inside the cylinder of radius 0\.1337"),
    ]
    for arm, p, why in cases:
        if p is not None and p.shape == (4, 4):
            with pytest.raises(UnreachableError, match=why) as exc:
                arm.ik(p)
        elif p is None:  # the Stanford arm's wrist centre 0.05 from the shoulder point
            T = rikin.transl(0.0, 0.05, 0.4 - 0.2)
            T[:3, :3] = rikin.rotx(pi)
            with pytest.raises(UnreachableError, match=why) as exc:
                arm.ik(T)
        else:
            with pytest.raises(UnreachableError, match=why) as exc:
                arm.ik(p)
        assert 0 < exc.value.excess < arm.scale


def test_targets_rounded_off_the_edge_of_reach_are_solved_for_the_nearest_reachable_pose():
    """Rounded numbers are input: a target typed 4e-5 beyond a SCARA's stretched reach,
    inside a cylindrical arm's offset or the Stanford arm's shoulder offset is solved for
    the nearest pose the arm reaches, and says how far that was; 4e-3 off is unreachable."""
    scara_arm = scara((0.4, 0.35, 0.25))
    stan = stanford((0.412, 0.154, 0.203, 0.263))  # a3 = 0.0203
    T_in = rikin.homogeneous(rikin.rotx(pi), np.array([0.154 - 0.0203 - 4e-5, 0.0, 0.649]))
    cyl = SerialArm((Link(d=1.0), Link("P", alpha=-pi / 2), Link("P", d=0.5, a=0.4)))
    T_far = T_in.copy()
    T_far[0, 3] -= 4e-3
    cases = [  # arm, target 4e-5 off, the same 4e-3 off, solutions
        (scara_arm, np.array([0.6 + 4e-5, 0.0, 0.3]), np.array([0.604, 0.0, 0.3]), 1),
        (scara_arm, np.array([0.1 - 4e-5, 0.0, 0.3]), np.array([0.096, 0.0, 0.3]), 1),
        (cyl, np.array([0.4 - 4e-5, 0.0, 0.7]), np.array([0.396, 0.0, 0.7]), 1),
        (stan, T_in, T_far, 4),
    ]
    for arm, t, far, count in cases:
        res = arm.ik(t)
        assert len(res) == count and res.singular
        assert res.reach_distance == pytest.approx(4e-5, rel=1e-6)
        F = arm.fk(res.q)
        p = t if t.shape == (3,) else t[:3, 3]
        assert np.abs(F[:, :3, 3] - p).max() <= 4e-5 * (1 + 1e-6)
        batch = arm.ik_batch((rikin.transl(*t) if t.shape == (3,) else t)[None])
        assert batch.counts[0] >= count and batch.reach_distance[0] == pytest.approx(4e-5)
        with pytest.raises(UnreachableError, match="taken as rounded"):
            arm.ik(far)


def test_singular_targets_are_flagged_with_their_free_joints():
    arm = scara((1.0, 1.0, 0.6))
    res = arm.ik([1.6, 0.0, 0.5])  # stretched
    assert res.singular and len(res) == 1 and res.free_joints == ()
    cyl = cylindrical((1.0, 0.0))
    res = cyl.ik([0.0, 0.0, 1.3], near=[0.7, 0.0, 0.0])  # on axis 1: q1 free, from near
    assert res.singular and 1 in res.free_joints and np.isclose(res.q[0, 0], 0.7)
    wristed = scara_wrist((1.0, 0.8, 0.6, 0.2))
    q = np.array([0.3, 0.9, 0.4, 0.5, 0.0, 0.2])  # q5 = 0: axes 4 and 6 line up
    res = wristed.ik(wristed.fk(q))
    assert res.singular and res.free_joints == (4, 6)
    assert_fk(wristed, res, wristed.fk(q), "SCARA with a wrist")


# ------------------------------------------------------------------ outside every family
NEAR_MISSES = {
    "SCARA whose axis 2 leans 0.3 deg": (
        SerialArm((Link(d=1.0, a=1.0, alpha=np.radians(0.3)), Link(a=0.8, alpha=pi), Link("P"))),
        r"axes 1 and 2 neither meet nor are parallel: they pass .* apart at 0\.3 deg"),
    "spherical arm whose axes 1 and 2 pass 0.1 apart": (
        SerialArm((Link(d=1.0, a=0.1, alpha=pi / 2), Link(alpha=pi / 2), Link("P", d=0.5))),
        r"axes 1 and 2 neither meet nor are parallel: they pass 0\.1 apart at 90 deg"),
    "planar 3R whose axis 3 tilts 0.5 deg": (
        SerialArm((Link(a=1.0), Link(a=1.0, alpha=np.radians(0.5)), Link(a=0.5))),
        r"axes 1 and 3 are 0\.5 deg from parallel"),
    "Stanford arm whose wrist axes miss by 0.1": (
        SerialArm(stanford((0.4, 0.15, 0.2, 0.2)).links[:3]
                  + (Link(a=0.1, alpha=-pi / 2), Link(alpha=pi / 2), Link(d=0.2))),
        r"axes 4, 5, 6 do not meet: axis 5 passes 0\.1 from axis 4"),
    "angular 3R with a shoulder offset": (
        SerialArm((Link(d=1.0, alpha=pi / 2), Link(a=1.0, d=0.15), Link(a=0.8))),
        r"the flange origin is 0\.15 off axis 1's plane"),
    "a redundant 7R": (SerialArm(tuple(Link(a=0.3, alpha=pi / 2) for _ in range(7))),
                       r"it has 7 joints, more than the six a pose fixes"),
    "an RPRP": (SerialArm((Link(a=1.0), Link("P", alpha=pi / 2), Link(a=1.0), Link("P"))),
                r"it has 4 joints, RPRP, and no course family has those"),
    "four-axis articulated arm whose wrist axis leans 0.5 deg": (
        SerialArm((Link(d=1.0, alpha=pi / 2), Link(a=1.0), Link(a=1.0, alpha=np.radians(0.5)),
                   Link(a=0.3))),
        r"axes 2 and 4 are 0\.5 deg from parallel"),
    "four-axis SCARA whose quill leans 0.3 deg": (
        SerialArm((Link(a=1.0), Link(a=1.0, alpha=np.radians(0.3)), Link("P"), Link())),
        r"the quill \(joint 3\) is 0\.3 deg from axis 1"),
    "four-axis SCARA whose roll axis is axis 2": (
        SerialArm((Link(a=1.0), Link(), Link("P"), Link(d=0.1))),
        r"the roll axis \(joint 4\) is axis 2's line, so joint 2 cannot move it"),
    "cylindrical arm whose slides move along axis 1 only": (
        SerialArm((Link(d=1.0), Link("P"), Link("P"))),
        r"the slides cannot change the distance from axis 1"),
}


@pytest.mark.parametrize("name", sorted(NEAR_MISSES))
def test_outside_every_family_classify_says_why_and_what_rikin_then_does(name):
    arm, why = NEAR_MISSES[name]
    c = classify(arm)
    assert not c.closed_form and c.solutions == 0
    assert re.search(why, c.reason), c.reason
    assert "ik_numerical" in c.fallback and "ik_numerical_multistart" in str(c)
    q = np.linspace(0.2, 0.8, arm.n)
    T = arm.fk(q)
    with pytest.raises(InputError, match=why + r".*ik_numerical"):
        arm.ik(T)
    mask = (1, 1, 1, 0, 0, 0) if arm.n < 6 else None
    sol = ik_numerical(arm, T, q + 0.05, mask=mask)  # what rikin offers instead
    assert sol.success


def test_a_lesson_solver_given_to_an_arm_it_does_not_fit_is_refused_not_a_rikin_bug():
    """Issue 29's leftover: Aula 10's solver handed to the Epson C4's table raised
    RuntimeError 'rikin bug' at the first pose; every pairing of a lesson solver with
    another lesson arm is now either refused when the arm is built (saying which solver
    and why) or, where the solver does fit, solves every pose right."""
    rng = np.random.default_rng(11)
    for a_name, make_a in robots.LESSON_ROBOTS.items():
        for b_name, make_b in robots.LESSON_ROBOTS.items():
            a, solver = make_a(), make_b().solver
            try:
                arm = SerialArm(a.links, convention=a.convention, tool=a.tool, solver=solver)
            except InputError as exc:
                assert f"solver={type(solver).__name__} does not fit" in str(exc)
                continue
            for _ in range(3):
                q = random_q(arm, rng)
                T = arm.fk(q)
                t = T[:2, 3] if arm.n == 2 else T[:3, 3] if solver.target_kind == "position" \
                    else T
                if solver.target_kind == "planar_pose":
                    t = np.array([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])])
                res = arm.ik(t)
                assert near(arm, res.q, q), (a_name, b_name)


def test_a_fitted_solver_given_to_another_arm_is_refused():
    """The same class of defect as the lesson solvers': a family's solver fitted to one
    table and handed to another through solver= is refused when that arm is built."""
    from rikin.ik.families import family_of

    rng = np.random.default_rng(13)
    for name in ("planar 3R", "angular 3R", "SCARA", "Stanford", "cylindrical with a wrist"):
        make = FAMILIES[name][0]
        mine = typed(name, rng)
        solver = family_of(mine).solver
        again = mine.replace(solver=solver, base=np.eye(4))  # the same table: it fits
        q = random_q(again, rng)
        T = again.fk(q)
        assert near(again, again.ik(target(again, T, name)).q, q)
        other = make(rng.uniform(0.5, 2.0, 4))
        with pytest.raises(InputError, match=f"solver={type(solver).__name__} does not fit"):
            other.replace(solver=solver)


def test_classify_says_how_many_solutions_to_expect_for_the_lesson_robots_too():
    expected = {"planar_2r": 2, "planar_3r": 2, "angular_3r": 4, "aula10_6r": 8,
                "barrientos_6r": 8, "pprrr": 2, "rprrr": 4, "epson_c4": 8}
    for name, make in robots.LESSON_ROBOTS.items():
        arm = make()
        c = classify(arm)
        assert c.closed_form and c.solutions == expected[name]
        table = SerialArm(arm.links, convention=arm.convention, tool=arm.tool)
        assert classify(table).solutions == expected[name]
