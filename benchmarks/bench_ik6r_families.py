"""Time of all-solution IK per 6R family, rikin against EAIK, side by side, with ratios.

Arms typed from their DH tables: the Puma 560 (spherical wrist; roboticstoolbox's table),
UR5e and UR10e (three parallel axes; Universal Robots' tables), the Kinova Jaco
(roboticstoolbox's table: a general 6R for rikin) and a random 6R (random twists, lengths and
offsets, seeded). Poses: FK of ``--poses`` seeded random joint vectors per arm.

Printed per arm, microseconds per pose (best of ``--rounds`` alternating rounds, so that
the machine's load hits all sides alike):

* ``ik``: rikin ``arm.ik(T)``, one float64 4x4 array at a time;
* ``batch``: rikin ``arm.ik_batch(Ts, workers=2)`` of all poses (2 threads);
* ``eaik``: EAIK's ``DhRobot.IK(T)`` one pose at a time (C++; arms it decomposes only);
* ``eaik/ik``, ``eaik/batch``: EAIK's time over rikin's (1 = as fast as EAIK);
* ``x sph``: this arm's ``arm.ik`` time over the Puma's (the general 6R's goal: <= 10).

    python benchmarks/bench_ik6r_families.py             # 300 poses per arm
    python benchmarks/bench_ik6r_families.py --poses 30  # a smoke run

EAIK (``pip install eaik``) is in requirements.txt; without it its columns are blank.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import rikin
from rikin import Link, SerialArm

try:
    from eaik.IK_DH import DhRobot
except ImportError:  # pragma: no cover - optional for a plain rikin install
    DhRobot = None

pi = np.pi


def arms() -> list[SerialArm]:
    """The arms, each from its published table (source in its docstring line)."""
    puma = SerialArm((  # Corke's Puma 560 (roboticstoolbox models.DH.Puma560), standard DH
        Link(d=0.6718, alpha=pi / 2), Link(a=0.4318), Link(d=0.15005, a=0.0203, alpha=-pi / 2),
        Link(d=0.4318, alpha=pi / 2), Link(alpha=-pi / 2), Link(),
    ), name="Puma 560", units="m")

    def ur(name: str, d1: float, a2: float, a3: float, d4: float, d5: float, d6: float):
        # Universal Robots, "DH parameters for calculations of kinematics and dynamics"
        return SerialArm((
            Link(d=d1, alpha=pi / 2), Link(a=a2), Link(a=a3), Link(d=d4, alpha=pi / 2),
            Link(d=d5, alpha=-pi / 2), Link(d=d6),
        ), name=name, units="m")

    s, s2 = np.sin(pi / 6), np.sin(pi / 3)  # roboticstoolbox models.DH.Jaco, joint 1 as typed
    d4b, d5b, d6b = 0.2073 + s / s2 * 0.0743, 2 * s / s2 * 0.0743, s / s2 * 0.0743 + 0.1687
    jaco = SerialArm((
        Link(d=0.2755, alpha=pi / 2), Link(a=0.41, alpha=pi, offset=-pi / 2),
        Link(d=-0.0098, alpha=pi / 2, offset=pi / 2), Link(d=-d4b, alpha=pi / 3),
        Link(d=-d5b, alpha=pi / 3, offset=-pi), Link(d=-d6b, alpha=pi, offset=5 * pi / 9),
    ), name="Kinova Jaco", units="m")
    rng = np.random.default_rng(1)
    general = SerialArm(tuple(
        Link(a=rng.uniform(-1, 1), d=rng.uniform(-1, 1), alpha=rng.uniform(-pi, pi))
        for _ in range(6)), name="random 6R", units="m")
    return [puma, ur("UR5e", 0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
            ur("UR10e", 0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655), jaco, general]


def eaik_of(arm: SerialArm):
    """EAIK's robot of the same table, when EAIK has it and decomposes it, else None."""
    if DhRobot is None or any(lk.offset for lk in arm.links):
        return None
    robot = DhRobot(*(np.array([getattr(lk, k) for lk in arm.links]) for k in ("alpha", "a", "d")))
    return robot if robot.hasKnownDecomposition() else None


def per_pose(fn, Ts: np.ndarray) -> float:
    start = time.perf_counter()
    for T in Ts:
        fn(T)
    return (time.perf_counter() - start) / len(Ts)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=300, help="random poses per arm")
    ap.add_argument("--rounds", type=int, default=3, help="alternating timing rounds")
    args = ap.parse_args()
    rng = np.random.default_rng(2026)
    head = f"{'arm':12} {'family':28} {'ik':>9} {'batch':>8} {'eaik':>7} {'eaik/ik':>8} " \
           f"{'eaik/batch':>10} {'x sph':>6}"
    print(head)
    sph = None
    for arm in arms():
        Ts = arm.fk(rng.uniform(-pi, pi, size=(args.poses, 6)))
        arm.ik(Ts[0])  # build the solver once (no derivation step: reading the table)
        robot = eaik_of(arm)
        best = {"ik": np.inf, "batch": np.inf, "eaik": np.inf}
        for _ in range(args.rounds):
            best["ik"] = min(best["ik"], per_pose(arm.ik, Ts))
            start = time.perf_counter()
            arm.ik_batch(Ts, workers=2)
            best["batch"] = min(best["batch"], (time.perf_counter() - start) / len(Ts))
            if robot is not None:
                best["eaik"] = min(best["eaik"], per_pose(robot.IK, Ts))
        sph = best["ik"] if sph is None else sph
        family = str(rikin.ik.classify(arm)).split(":")[0][:28]
        us = {k: v * 1e6 for k, v in best.items()}
        e = f"{us['eaik']:7.1f}" if robot is not None else f"{'-':>7}"
        r1 = f"{best['eaik'] / best['ik']:8.3f}" if robot is not None else f"{'-':>8}"
        r2 = f"{best['eaik'] / best['batch']:10.3f}" if robot is not None else f"{'-':>10}"
        print(f"{arm.name:12} {family:28} {us['ik']:9.1f} {us['batch']:8.1f} {e} {r1} {r2} "
              f"{best['ik'] / sph:6.1f}")


if __name__ == "__main__":
    main()
