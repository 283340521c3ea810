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

from rikin import SerialArm, robots
from rikin.errors import InputError
from rikin.ik.api import _solver
from rikin.ik.result import LABEL_WORDS

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
