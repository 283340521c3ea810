"""Branch labels: within one result no two solutions share a label, for every family, and
every label is made of the words ``rikin.ik.result.LABEL_WORDS`` lists (what rikin.i18n
translates).

Seeded property tests over arms typed from tables: the course families (random lengths,
base and tool), the three-parallel-axes family (random twists, lengths and offsets, axes
2-4 or 3-5, with and without a wrist offset), the general 6R (random tables, standard and
modified DH), each also with joints reversed at random, and the lesson robots. Where a
family names its solutions by the roots of a polynomial ("root k of n"), k runs 1..n in
the order the result lists them, by increasing value of the polynomial's joint.
"""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest
from test_families import FAMILIES, random_q, target, typed
from test_ik6r_families import parallel_arm, random_6r, ur5e
from test_pieper_batch import irb140, kr5, puma_modified, puma_standard

from rikin import SerialArm, robots
from rikin.errors import InputError
from rikin.ik.api import _solver
from rikin.ik.result import LABEL_WORDS, Branch

pi = np.pi
ROOT = re.compile(r"root (\d+) of (\d+)")
WORDS = {w for words in LABEL_WORDS.values() for w in words}


def reversed_at_random(arm: SerialArm, rng) -> SerialArm:
    """The arm with each joint counted the other way with probability 1/2 (same motion)."""
    flips = rng.random(arm.n) < 0.5
    links = tuple(replace(lk, direction=-lk.direction) if f else lk
                  for lk, f in zip(arm.links, flips, strict=True))
    return arm.replace(links=links)


def assert_labels(arm: SerialArm, res) -> None:
    """Distinct labels, made of the documented words; roots numbered in listed order."""
    labels = res.labels
    assert len(set(labels)) == len(labels), (arm.name, labels)
    roots = []
    for lab in labels:
        for part in lab.split("/"):
            m = ROOT.fullmatch(part)
            if m:
                roots.append((int(m[1]), int(m[2])))
            else:
                assert part in WORDS, (arm.name, lab)
    if roots:
        assert len(roots) == len(labels)
        k = [r[0] for r in roots]
        n = {r[1] for r in roots}
        assert len(n) == 1 and sorted(set(k)) == list(range(1, n.pop() + 1))
        assert k == sorted(k)  # listed in root order
        j = _solver(arm._dh if arm.reversed_joints else arm).root_joint
        qj = np.remainder(res.q[:, j] * arm.directions[j] + pi, 2 * pi) - pi
        firsts = [qj[k.index(r)] for r in sorted(set(k))]
        assert firsts == sorted(firsts)


def arms(rng):
    """(arm, target maker) for the families, each typed with random numbers."""
    out = []
    for name in FAMILIES:
        arm = typed(name, rng)
        out.append((arm, lambda T, a=arm, n=name: target(a, T, n)))
    for first, offset in ((2, False), (2, True), (3, True)):
        for convention in ("standard", "modified"):
            out.append((parallel_arm(rng, convention, first, offset), None))
    out += [(random_6r(rng, "standard"), None), (random_6r(rng, "modified"), None),
            (ur5e(), None)]
    return out


@pytest.mark.parametrize("seed", range(4))
def test_labels_are_distinct_within_every_result(seed):
    rng = np.random.default_rng([29, seed])
    for arm, make_target in arms(rng):
        for candidate in (arm, reversed_at_random(arm, rng)):
            for _ in range(4):
                T = candidate.fk(random_q(candidate, rng))
                res = candidate.ik(T if make_target is None else make_target(T))
                assert len(res) >= 1
                assert_labels(candidate, res)


@pytest.mark.parametrize("make", [robots.aula10_6r, robots.kuka_kr5_arc, robots.epson_c4,
                                  robots.fanuc_lrmate200id, robots.rprrr, robots.pprrr,
                                  robots.angular_3r, robots.planar_3r])
def test_lesson_robots_labels_are_distinct(make):
    arm = make()
    rng = np.random.default_rng(7)
    for _ in range(20):
        assert_labels(arm, arm.ik(arm.fk(random_q(arm, rng))))


def test_a_general_6r_names_each_solution_by_its_root():
    """The issue's example: a random general 6R gave "down/flip" three times."""
    arm = random_6r(np.random.default_rng(3), "standard")
    q = np.random.default_rng(4).uniform(-pi, pi, 6)
    res = arm.ik(arm.fk(q))
    n = len(res)
    assert n >= 4
    assert list(res.labels) == [f"root {k} of {n}" for k in range(1, n + 1)]


@pytest.mark.parametrize("seed", range(3))
def test_batch_labels_are_those_of_one_pose_at_a_time(seed):
    """``ik_batch(...).labels(i)`` of a general 6R names pose i's solutions as ``arm.ik``
    does, each solution by the same label, standard and modified DH, with joints reversed
    at random. Fails before: a general 6R's batch slots were all "unique"."""
    rng = np.random.default_rng([29, 2, seed])
    arms_ = [random_6r(rng, "standard"), random_6r(rng, "modified")]
    for arm in arms_ + [reversed_at_random(a, rng) for a in arms_]:
        Ts = arm.fk(rng.uniform(-pi, pi, (6, 6)))
        batch = arm.ik_batch(Ts, workers=1)
        for i, T in enumerate(Ts):
            labels = batch.labels(i)
            assert len(set(labels)) == len(labels), (arm.name, labels)
            one = arm.ik(T)
            assert sorted(labels) == sorted(one.labels), (arm.name, labels, one.labels)
            got = dict(zip(labels, batch.q[i][batch.valid[i]], strict=True))
            for label, q in zip(one.labels, one.q, strict=True):
                gap = np.abs(np.remainder(got[label] - q + pi, 2 * pi) - pi).max()
                assert gap <= 1e-9, (arm.name, label, gap)
    assert batch.labels(-1) == batch.labels(len(Ts) - 1)
    with pytest.raises(InputError, match="pose"):
        batch.labels(len(Ts))


def _world(rng, scale: float):
    """A random rigid transform, its translation up to ``scale``."""
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    R *= np.sign(np.linalg.det(R))
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, rng.uniform(-scale, scale, 3)
    return T


def batch_arms(rng):
    """Every family for the batch: the course families and three-parallel-axes tables and
    general 6Rs of :func:`arms`, spherical-wrist arms typed from their tables (standard and
    modified DH), a UR5e and the lesson robots, those that take a 6-D pose with a random
    base and tool; each also with joints reversed at random."""
    out = [arm for arm, _ in arms(rng)]
    out += [puma_standard(), puma_modified(), kr5(), irb140(), ur5e()]
    out += [make() for make in (robots.aula10_6r, robots.barrientos_6r, robots.epson_c4,
                                robots.kuka_kr5_arc, robots.fanuc_lrmate200id, robots.rprrr,
                                robots.pprrr, robots.angular_3r, robots.planar_3r,
                                robots.planar_2r)]
    placed = []
    for arm in out:
        if _solver(arm).target_kind == "pose" and np.array_equal(arm.base, np.eye(4)):
            arm = arm.replace(base=_world(rng, arm.scale), tool=_world(rng, 0.3 * arm.scale))
        placed += [arm, reversed_at_random(arm, rng)]
    return placed


def _field_names(label: str) -> Branch:
    """The branch a label names (its root as the root field)."""
    fields: dict[str, str] = {}
    for part in label.split("/") if label != "unique" else ():
        kind = "root" if ROOT.fullmatch(part) else next(
            k for k in ("shoulder", "elbow", "wrist") if part in LABEL_WORDS[k])
        fields[kind] = part
    return Branch(**fields)


def mislabelled(arm: SerialArm, Ts) -> list:
    """The batch solutions of poses ``Ts (N, 4, 4)`` whose label is not the one ``arm.ik``
    gives the same joints (matched within 1e-9 rad, wrapped), or whose slot's ``branches``
    names a field their label lacks (but for "singular" wrists): (batch label, slot's
    branch, arm.ik's label)."""
    batch = arm.ik_batch(Ts, workers=1)
    wrong = []
    for i, T in enumerate(Ts):
        one = arm.ik(T)
        slots = np.flatnonzero(batch.valid[i])
        labels = batch.labels(i)
        assert len(labels) == len(slots)
        for s, q, label in zip(slots, batch.q[i, slots], labels, strict=True):
            gap = np.where(arm.revolute, np.abs(np.remainder(one.q - q + pi, 2 * pi) - pi),
                           np.abs(one.q - q)).max(axis=1)
            k = int(gap.argmin())
            assert gap[k] <= 1e-9, (arm.name, i, s, gap[k])
            named = _field_names(one.labels[k])
            # a slot's wrist (a UR's) at a wrist singularity: arm.ik says "singular"
            claims = [fixed is None or getattr(named, f) in (fixed, "singular" * (f == "wrist"))
                      for f, fixed in zip(Branch._fields, batch.branches[s], strict=True)]
            if label != one.labels[k] or not all(claims):
                wrong.append((label, batch.branches[s].label, one.labels[k]))
    return wrong


@pytest.mark.parametrize("seed", range(2))
def test_every_batch_solution_has_the_label_arm_ik_gives_its_joints(seed):
    """Issue 29: ``ik_batch(...).labels(i)`` labels each solution as ``arm.ik`` labels the
    same joints, for every family, with base, tool and reversed joints; and a slot's
    ``branches`` names no field its solution lacks. Fails before for the UR5e (elbows) and
    every spherical wrist typed as a table (only "no-flip"/"flip"), among others."""
    rng = np.random.default_rng([29, 29, seed])
    wrong = {}  # arm -> its mislabelled solutions, to see every family
    for arm in batch_arms(rng):
        bad = mislabelled(arm, arm.fk(np.array([random_q(arm, rng) for _ in range(5)])))
        if bad:
            wrong[arm.name] = bad
    assert not wrong, "; ".join(f"{name}: {len(w)}, e.g. {w[0]}" for name, w in wrong.items())


@pytest.mark.parametrize("make", [puma_standard, puma_modified, kr5, ur5e, robots.aula10_6r,
                                  robots.epson_c4, robots.kuka_kr5_arc])
def test_batch_labels_at_a_wrist_singularity_are_those_of_arm_ik(make):
    """At a wrist singularity (joint 5 at 0) the batch labels what ``arm.ik`` does,
    "singular" wrists included (a batch may repeat a solution there: the same label)."""
    rng = np.random.default_rng(31)
    arm = make()
    Q = rng.uniform(-pi, pi, (4, 6))
    Q[:, 4] = 0.0
    Ts = arm.fk(Q)
    assert mislabelled(arm, Ts) == []
    batch = arm.ik_batch(Ts, workers=1)
    assert batch.singular.all()
    assert any("singular" in label for label in batch.labels(0))


def test_batch_labels_do_not_change_when_the_poses_array_does():
    """``labels(i)`` may solve pose i again (a family with no ``label_rows``, or a singular
    pose): it solves the pose given to ``ik_batch``, not what the caller's array holds now."""
    arm = robots.aula10_6r()
    rng = np.random.default_rng(37)
    Ts = arm.fk(rng.uniform(-pi, pi, (3, 6)))
    batch = arm.ik_batch(Ts, workers=1)
    before = [batch.labels(i) for i in range(3)]
    Ts[:] = Ts[::-1].copy()
    assert [batch.labels(i) for i in range(3)] == before
    assert mislabelled(arm, arm.fk(rng.uniform(-pi, pi, (3, 6)))) == []
