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
* ``x sph``: this arm's ``arm.ik`` time over the Puma's (the general 6R's goal: <= 10);
* with ``--baseline CHECKOUT``: the same two times of the rikin in another checkout (run in
  a subprocess, in turn with this one, round by round), and ``base/ik``, ``base/batch``: its
  times over this checkout's (2 = this one twice as fast).

    python benchmarks/bench_ik6r_families.py             # 300 poses per arm
    python benchmarks/bench_ik6r_families.py --poses 30  # a smoke run
    python benchmarks/bench_ik6r_families.py --baseline /work/main  # against main

EAIK (``pip install eaik``) is in requirements.txt; without it its columns are blank.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
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


def timings(poses: int, rounds: int) -> list[dict]:
    """Per arm: its name, family, and the best of ``rounds`` of ``ik``, ``batch`` and
    ``eaik`` (seconds per pose; eaik None where EAIK has no solver for the arm)."""
    rng = np.random.default_rng(2026)
    out = []
    for arm in arms():
        Ts = arm.fk(rng.uniform(-pi, pi, size=(poses, 6)))
        arm.ik(Ts[0])  # build the solver once (no derivation step: reading the table)
        robot = eaik_of(arm)
        best = {"ik": np.inf, "batch": np.inf, "eaik": np.inf}
        for _ in range(rounds):
            best["ik"] = min(best["ik"], per_pose(arm.ik, Ts))
            start = time.perf_counter()
            arm.ik_batch(Ts, workers=2)
            best["batch"] = min(best["batch"], (time.perf_counter() - start) / len(Ts))
            if robot is not None:
                best["eaik"] = min(best["eaik"], per_pose(robot.IK, Ts))
        family = str(rikin.ik.classify(arm)).split(":")[0][:28]
        out.append({"arm": arm.name, "family": family, "ik": best["ik"], "batch": best["batch"],
                    "eaik": best["eaik"] if robot is not None else None})
    return out


def baseline_timings(checkout: str, poses: int) -> list[dict]:
    """:func:`timings` (one round) of the rikin in another checkout, in a subprocess."""
    env = dict(os.environ, PYTHONPATH=os.path.abspath(checkout))
    done = subprocess.run([sys.executable, __file__, "--poses", str(poses), "--rounds", "1",
                           "--json"], env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def best_of(runs: list[list[dict]]) -> list[dict]:
    """Each arm's fastest time per column over several runs of :func:`timings`."""
    out = [dict(row) for row in runs[0]]
    for run in runs[1:]:
        for mine, row in zip(out, run, strict=True):
            for key in ("ik", "batch", "eaik"):
                if mine[key] is not None:
                    mine[key] = min(mine[key], row[key])
    return out


def print_table(rows: list[dict], base: list[dict] | None) -> None:
    """The table of the module docstring; with a baseline, its times over these."""
    head = f"{'arm':12} {'family':28} {'ik':>9} {'batch':>8} {'eaik':>7} {'eaik/ik':>8} " \
           f"{'eaik/batch':>10} {'x sph':>6}"
    if base is not None:
        head += f" {'base ik':>9} {'base batch':>10} {'base/ik':>8} {'base/batch':>10}"
    print(head)
    sph = rows[0]["ik"]
    for n, row in enumerate(rows):
        us = {k: (v or 0.0) * 1e6 for k, v in row.items() if k in ("ik", "batch", "eaik")}
        has = row["eaik"] is not None
        e = f"{us['eaik']:7.1f}" if has else f"{'-':>7}"
        r1 = f"{row['eaik'] / row['ik']:8.3f}" if has else f"{'-':>8}"
        r2 = f"{row['eaik'] / row['batch']:10.3f}" if has else f"{'-':>10}"
        line = (f"{row['arm']:12} {row['family']:28} {us['ik']:9.1f} {us['batch']:8.1f} {e} "
                f"{r1} {r2} {row['ik'] / sph:6.1f}")
        if base is not None:
            b = base[n]
            line += (f" {b['ik'] * 1e6:9.1f} {b['batch'] * 1e6:10.1f} "
                     f"{b['ik'] / row['ik']:8.2f} {b['batch'] / row['batch']:10.2f}")
        print(line)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=300, help="random poses per arm")
    ap.add_argument("--rounds", type=int, default=3, help="alternating timing rounds")
    ap.add_argument("--baseline", metavar="CHECKOUT",
                    help="another checkout of rikin (e.g. /work/main), timed in turn with this one")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.json:
        print(json.dumps(timings(args.poses, args.rounds)))
        return
    if args.baseline is None:
        print_table(timings(args.poses, args.rounds), None)
        return
    mine, theirs = [], []
    for _ in range(args.rounds):  # in turn, so that the machine's load hits both alike
        theirs.append(baseline_timings(args.baseline, args.poses))
        mine.append(timings(args.poses, 1))
    print_table(best_of(mine), best_of(theirs))


if __name__ == "__main__":
    main()
