"""Time of all-solution IK per 6R family, rikin against EAIK, side by side, with ratios.

Arms typed from their DH tables: the Puma 560 (spherical wrist; roboticstoolbox's table),
the KUKA KR5, ABB IRB 140 and IRB 2400 (spherical wrist, axes 1 and 2 skew; standard DH
without joint offsets, so that EAIK takes them too), Craig's Puma 560 in modified DH on a
tilted base with a tool and joints 2 and 5 reversed (as a user types a data sheet; EAIK
takes standard DH only), UR5e and UR10e (three parallel axes; Universal Robots' tables),
the Kinova Jaco (roboticstoolbox's table: a general 6R for rikin) and a random 6R (random
twists, lengths and offsets, seeded). Poses: FK of ``--poses`` seeded random joint vectors
per arm, and for the batch of a closed-form family ``--batch-poses`` more (a batch is
split into chunks of at least 1,024 poses per thread: 2 threads need 2,048).

Printed per arm, microseconds per pose (best of ``--rounds`` alternating rounds, so that
the machine's load hits all sides alike):

* ``ik``: rikin ``arm.ik(T)``, one float64 4x4 array at a time;
* ``batch``: rikin ``arm.ik_batch(Ts, workers=2)`` of all ``N batch`` poses (2 threads);
* ``eaik``: EAIK's ``DhRobot.IK(T)`` one pose at a time (C++; arms it decomposes only);
* ``eaik/ik``, ``eaik/batch``: EAIK's time over rikin's (1 = as fast as EAIK);
* ``cpu batch``, ``cpu eaik``, ``cpu e/b``: the batch's CPU time per pose (both threads),
  EAIK's, and EAIK's over the batch's (what each pose costs, whatever the machine's load
  does to the wall clock);
* ``batch 1t``, ``cpu b 1t``, ``1t/2t``: the same batch on one thread (``workers=1``), wall
  and CPU time per pose, and its wall time over the 2 threads' (about 1.8 on an idle
  2-CPU machine, where the threads share the poses; near 1 or below when other work
  keeps both CPUs busy);
* ``x sph``: this arm's ``arm.ik`` time over the Puma's (the general 6R's goal: <= 10);
* ``cpu ik``, ``cpu x sph``: ``arm.ik``'s CPU time per pose and its ratio to the Puma's
  (steadier than the wall clock on a machine shared with other work); ``cpu b x sph``: the
  same ratio of the batches' CPU time per pose. The arms alternate round by round, so
  that these ratios compare times taken under the same load;
* with ``--baseline CHECKOUT``: the same times of the rikin in another checkout (run in
  a subprocess, in turn with this one, round by round), its ``arm.ik`` CPU time per pose
  (``base cpu ik``), and ``base/ik``, ``base/batch``, ``base/cpu ik``: its times over this
  checkout's (2 = this one twice as fast), its ``cpu x sph``, and its batch's CPU time per
  pose on 2 threads and on one (``base cpu b``, ``base cpu b 1t``) and their ratios to this
  checkout's (``base/cpu b``, ``base/cpu b 1t``);
* with ``--breakdown`` (only that): where a general 6R's ``arm.ik`` time goes, stage by
  stage, each stage's thread CPU time per pose beside the spherical wrist's whole
  ``arm.ik`` (:func:`general_stages`): the goal, a general 6R within 10x of the spherical
  wrist, leaves each pose 10 of them.

    python benchmarks/bench_ik6r_families.py             # 300 poses per arm
    python benchmarks/bench_ik6r_families.py --poses 30 --batch-poses 30  # a smoke run
    python benchmarks/bench_ik6r_families.py --baseline /work/main  # against main
    python benchmarks/bench_ik6r_families.py --breakdown --poses 100  # a general 6R's stages

EAIK (``pip install eaik``) is in requirements.txt; without it its columns are blank.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from functools import partial

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
    return [puma, *skew_wrist_arms(), craig_puma(),
            ur("UR5e", 0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
            ur("UR10e", 0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655), jaco, general]


def skew_wrist_arms() -> list[SerialArm]:
    """KUKA KR5, ABB IRB 140 and IRB 2400 (standard DH, metres; the makers' lengths,
    zero poses without the joint offsets of their data sheets)."""
    def arm(name: str, d1: float, a1: float, a2: float, a3: float, d4: float, d6: float,
            sign: float) -> SerialArm:
        return SerialArm((
            Link(d=d1, a=a1, alpha=sign * pi / 2), Link(a=a2), Link(a=a3, alpha=sign * pi / 2),
            Link(d=sign * d4, alpha=-sign * pi / 2), Link(alpha=sign * pi / 2),
            Link(d=sign * d6, alpha=pi if sign > 0 else 0.0),
        ), name=name, units="m")

    return [arm("KUKA KR5", 0.4, 0.18, 0.6, 0.12, -0.62, -0.115, 1.0),
            arm("ABB IRB 140", 0.352, 0.07, 0.36, 0.0, 0.38, 0.065, -1.0),
            arm("ABB IRB 2400", 0.615, 0.1, 0.705, 0.135, 0.755, 0.085, -1.0)]


def craig_puma() -> SerialArm:
    """Craig's Puma 560 in modified DH, joints 2 and 5 counted the other way, on a tilted
    base with a tool."""
    base = rikin.homogeneous(rikin.rotz(0.7) @ rikin.rotx(0.3), [0.2, -0.1, 0.4])
    tool = rikin.homogeneous(rikin.roty(0.5), [0.03, 0.0, 0.11])
    return SerialArm((
        Link(), Link(alpha=-pi / 2, direction=-1), Link(a=0.4318, d=0.15005),
        Link(alpha=-pi / 2, a=0.0203, d=0.4318), Link(alpha=pi / 2, direction=-1),
        Link(alpha=-pi / 2),
    ), convention="modified", base=base, tool=tool, name="Puma (Craig)", units="m")


def eaik_of(arm: SerialArm):
    """EAIK's robot of the same table, when EAIK has it and decomposes it, else None."""
    if DhRobot is None or any(lk.offset for lk in arm.links) or arm.convention != "standard" \
            or arm.reversed_joints or not (np.array_equal(arm.base, np.eye(4))
                                           and np.array_equal(arm.tool, np.eye(4))):
        return None
    robot = DhRobot(*(np.array([getattr(lk, k) for lk in arm.links]) for k in ("alpha", "a", "d")))
    return robot if robot.hasKnownDecomposition() else None


def per_pose(fn, Ts: np.ndarray) -> tuple[float, float]:
    """Wall and CPU seconds per pose of ``fn(T)`` for each pose."""
    start, cpu = time.perf_counter(), time.process_time()
    for T in Ts:
        fn(T)
    return (time.perf_counter() - start) / len(Ts), (time.process_time() - cpu) / len(Ts)


#: The timed columns: seconds per pose (also in CPU seconds).
KEYS = ("ik", "ik_cpu", "batch", "batch_cpu", "batch1", "batch1_cpu", "eaik", "eaik_cpu")


def timings(poses: int, rounds: int, batch_poses: int) -> list[dict]:
    """Per arm: its name, family, and the best of ``rounds`` of ``ik``, ``batch`` and
    ``eaik`` (seconds per pose; eaik None where EAIK has no solver for the arm), and how
    many poses the batch had (``batch_poses`` for a closed-form family, else ``poses``).

    Each round times every arm in turn (the arms alternate, round by round), so that the
    ratios between arms (``x sph``: a general 6R's time over the spherical wrist's) compare
    times taken under the same load."""
    rng = np.random.default_rng(2026)
    setup = []
    for arm in arms():
        Ts = arm.fk(rng.uniform(-pi, pi, size=(poses, 6)))
        family = str(rikin.ik.classify(arm)).split(":")[0][:28]
        nb = poses if family.startswith("general") else batch_poses
        Tb = arm.fk(rng.uniform(-pi, pi, size=(nb, 6)))
        arm.ik(Ts[0])  # build the solver once (no derivation step: reading the table)
        arm.ik_batch(Ts[:2])
        setup.append((arm, family, nb, Ts, Tb, eaik_of(arm)))
    best = [dict.fromkeys(KEYS, np.inf) for _ in setup]
    for _ in range(rounds):
        for row, (arm, _, nb, Ts, Tb, robot) in zip(best, setup, strict=True):
            _time_round(row, arm, nb, Ts, Tb, robot)
    out = []
    for row, (arm, family, nb, _, _, robot) in zip(best, setup, strict=True):
        if robot is None:
            row["eaik"] = row["eaik_cpu"] = None
        out.append({"arm": arm.name, "family": family, "n": nb, **row})
    return out


def _time_round(best: dict, arm: SerialArm, nb: int, Ts: np.ndarray, Tb: np.ndarray,
                robot: object) -> None:
    """One round of one arm: ``arm.ik`` of each of ``Ts``, ``ik_batch`` of the ``nb`` poses
    ``Tb`` (2 threads, then one) and EAIK's ``IK`` of each of ``Ts`` (``robot``, or None), each kept
    in ``best`` (seconds per pose, wall and CPU) where faster than before."""
    wall, cpu = per_pose(arm.ik, Ts)
    best["ik"], best["ik_cpu"] = min(best["ik"], wall), min(best["ik_cpu"], cpu)
    batch = per_pose(partial(arm.ik_batch, workers=2), Tb[None])
    best["batch"] = min(best["batch"], batch[0] / nb)
    best["batch_cpu"] = min(best["batch_cpu"], batch[1] / nb)
    batch = per_pose(partial(arm.ik_batch, workers=1), Tb[None])
    best["batch1"] = min(best["batch1"], batch[0] / nb)
    best["batch1_cpu"] = min(best["batch1_cpu"], batch[1] / nb)
    if robot is not None:
        wall, cpu = per_pose(robot.IK, Ts)
        best["eaik"], best["eaik_cpu"] = min(best["eaik"], wall), min(best["eaik_cpu"], cpu)


#: The stages of :func:`general_stages`, in the order printed.
STAGES = ("arm.ik", "matrices", "eigen step", "LAPACK alone", "roots to joints",
          "polish + checks", "rest")


def general_stages(puma: SerialArm, arm: SerialArm, poses: int, rounds: int) -> dict[str, float]:
    """Where one pose of a general 6R's ``arm.ik`` goes, in thread CPU µs per pose, next to
    the spherical wrist's ``arm.ik`` (``puma``), all timed in alternating rounds (best of
    ``rounds``, at least 3) on the same seeded poses.

    The stages: ``matrices``, the 12 x 12 matrix polynomial of the pose
    (``_Elimination.matrices``); ``eigen step``, its roots and eigenvectors
    (``_eig_quadratic``); ``LAPACK alone``, that step's four LAPACK calls by themselves (the
    SVD of both ends, the 12 x 12 solve, the 24 x 24 ``eig``): the floor of this method in
    numpy; ``roots to joints``, the rest of ``_candidates`` (joints 1, 2, 4-6 of the real
    roots); ``polish + checks``, the rest of ``_polished`` (Newton steps, residuals,
    merging, the singular check); ``rest``, ``arm.ik`` less ``_polished`` (the pose into the
    chain's frame, wrapping, naming, the FK check, the result). Reads the solver's private
    methods: a profile, not an interface.
    """
    from rikin.ik import general6r  # noqa: PLC0415  (only here: the private path profiled)

    rng = np.random.default_rng(7)
    Ts = [np.array(T) for T in arm.fk(rng.uniform(-pi, pi, size=(poses, 6)))]
    Tp = [np.array(T) for T in puma.fk(rng.uniform(-pi, pi, size=(10 * poses, 6)))]
    arm.ik(Ts[0])  # build both solvers and their one-pose kernels
    puma.ik(Tp[0])
    solver = arm.__dict__["_single_kernel"][0].solver
    Ws = [solver._to_chain(arm._world_to_base(T)[None]) for T in Ts]
    Ss = [solver.elim.matrices(W)[0] for W in Ws]
    flip = [_flipped(S) for S in Ss]

    def lapack(S: np.ndarray, flipped: bool) -> None:
        with np.errstate(all="ignore"):
            np.linalg.svd(S[:, ::2], compute_uv=False)
            A, B = (S[0, 2], S[0, 0]) if flipped else (S[0, 0], S[0, 2])
            X = np.linalg.solve(B, np.concatenate([A, S[0, 1]], axis=-1))
        C = np.zeros((24, 24))
        C[:12, 12:] = np.eye(12)
        C[12:] = np.where(np.isfinite(X), -X, 0.0)
        np.linalg.eig(C)

    def each(fn, items) -> None:  # noqa: ANN001
        for x in items:
            try:
                fn(x)
            except rikin.UnreachableError:
                pass

    runs = {
        "sph": lambda: each(puma.ik, Tp),
        "arm.ik": lambda: each(arm.ik, Ts),
        "polished": lambda: each(solver._polished, Ws),
        "candidates": lambda: each(solver._candidates, Ws),
        "matrices": lambda: each(solver.elim.matrices, Ws),
        "eigen step": lambda: each(general6r._eig_quadratic, Ss),
        "LAPACK alone": lambda: [lapack(S, f) for S, f in zip(Ss, flip, strict=True)],
    }
    best = dict.fromkeys(runs, np.inf)
    for _ in range(max(rounds, 3)):
        for name, fn in runs.items():
            t0 = time.thread_time()
            fn()
            best[name] = min(best[name], time.thread_time() - t0)
    us = {name: t * 1e6 / poses for name, t in best.items()}
    us["sph"] /= 10
    return {"sph": us["sph"], "arm.ik": us["arm.ik"], "matrices": us["matrices"],
            "eigen step": us["eigen step"], "LAPACK alone": us["LAPACK alone"],
            "roots to joints": us["candidates"] - us["matrices"] - us["eigen step"],
            "polish + checks": us["polished"] - us["candidates"],
            "rest": us["arm.ik"] - us["polished"]}


def _flipped(S: np.ndarray) -> bool:
    """Whether ``_eig_quadratic`` inverts the far end of the matrix polynomial ``S (1, 3,
    12, 12)`` (the better conditioned one), as it decides."""
    with np.errstate(all="ignore"):
        sv = np.linalg.svd(S[:, ::2], compute_uv=False)
        cond = np.nan_to_num(sv[..., 0] / sv[..., -1], nan=np.inf)
    return not cond[0, 1] <= cond[0, 0]


def print_stages(table: list[tuple[str, dict[str, float]]]) -> None:
    """The ``--breakdown`` table: each stage's thread CPU µs per pose and its ratio to the
    spherical wrist's whole ``arm.ik`` (the goal: ``arm.ik`` at most 10 of them)."""
    print("\ngeneral 6R: thread CPU us per pose of each stage (x the spherical wrist's "
          "arm.ik, timed in the same rounds)")
    print(f"{'arm':12} {'sph arm.ik':>10}" + "".join(f" {s:>22}" for s in STAGES))
    for name, st in table:
        cells = "".join(f" {st[s]:>13.1f} ({st[s] / st['sph']:>5.1f}x)" for s in STAGES)
        print(f"{name[:12]:12} {st['sph']:>10.1f}{cells}", flush=True)


def baseline_timings(checkout: str, poses: int, batch_poses: int) -> list[dict]:
    """:func:`timings` (one round) of the rikin in another checkout, in a subprocess."""
    env = dict(os.environ, PYTHONPATH=os.path.abspath(checkout))
    done = subprocess.run([sys.executable, __file__, "--poses", str(poses), "--batch-poses",
                           str(batch_poses), "--rounds", "1", "--json"],
                          env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def best_of(runs: list[list[dict]]) -> list[dict]:
    """Each arm's fastest time per column over several runs of :func:`timings`."""
    out = [dict(row) for row in runs[0]]
    for run in runs[1:]:
        for mine, row in zip(out, run, strict=True):
            for key in KEYS:
                if mine[key] is not None:
                    mine[key] = min(mine[key], row[key])
    return out


def _ratio(a: float | None, b: float | None, width: int) -> str:
    return f"{a / b:{width}.3f}" if a is not None and b else f"{'-':>{width}}"


def _us(v: float | None, width: int) -> str:
    return f"{v * 1e6:{width}.1f}" if v is not None else f"{'-':>{width}}"


def print_table(rows: list[dict], base: list[dict] | None) -> None:
    """The table of the module docstring (``cpu``: the batch's and EAIK's CPU time per pose,
    and EAIK's over the batch's); with a baseline, its times over these."""
    head = (f"{'arm':12} {'family':28} {'ik':>9} {'N batch':>7} {'batch':>8} {'eaik':>7} "
            f"{'eaik/ik':>8} {'eaik/batch':>10} {'cpu batch':>9} {'cpu eaik':>8} "
            f"{'cpu e/b':>7} {'x sph':>6} {'cpu ik':>8} {'cpu x sph':>9} {'cpu b x sph':>11} "
            f"{'batch 1t':>8} {'cpu b 1t':>8} {'1t/2t':>6}")
    if base is not None:
        head += (f" {'base ik':>9} {'base batch':>10} {'base/ik':>8} {'base/batch':>10} "
                 f"{'base cpu ik':>11} {'base/cpu ik':>11} {'base cpu x sph':>14} "
                 f"{'base cpu b':>10} {'base/cpu b':>10} {'base cpu b 1t':>13} "
                 f"{'base/cpu b 1t':>13}")
    print(head)
    sph, sph_cpu, sph_batch = rows[0]["ik"], rows[0]["ik_cpu"], rows[0]["batch_cpu"]
    for n, row in enumerate(rows):
        line = (f"{row['arm'][:12]:12} {row['family']:28} {_us(row['ik'], 9)} {row['n']:7d} "
                f"{_us(row['batch'], 8)} {_us(row['eaik'], 7)} "
                f"{_ratio(row['eaik'], row['ik'], 8)} {_ratio(row['eaik'], row['batch'], 10)} "
                f"{_us(row['batch_cpu'], 9)} {_us(row['eaik_cpu'], 8)} "
                f"{_ratio(row['eaik_cpu'], row['batch_cpu'], 7)} {row['ik'] / sph:6.1f} "
                f"{_us(row['ik_cpu'], 8)} {row['ik_cpu'] / sph_cpu:9.1f} "
                f"{row['batch_cpu'] / sph_batch:11.1f} {_us(row['batch1'], 8)} "
                f"{_us(row['batch1_cpu'], 8)} {_ratio(row['batch1'], row['batch'], 6)}")
        if base is not None:
            b = base[n]
            line += (f" {_us(b['ik'], 9)} {_us(b['batch'], 10)} "
                     f"{_ratio(b['ik'], row['ik'], 8)} {_ratio(b['batch'], row['batch'], 10)} "
                     f"{_us(b['ik_cpu'], 11)} {_ratio(b['ik_cpu'], row['ik_cpu'], 11)} "
                     f"{b['ik_cpu'] / base[0]['ik_cpu']:14.1f} {_us(b['batch_cpu'], 10)} "
                     f"{_ratio(b['batch_cpu'], row['batch_cpu'], 10)} "
                     f"{_us(b['batch1_cpu'], 13)} {_ratio(b['batch1_cpu'], row['batch1_cpu'], 13)}")
        print(line)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=300, help="random poses per arm")
    ap.add_argument("--batch-poses", type=int, default=4096,
                    help="poses of a closed-form family's batch (a general 6R's: --poses)")
    ap.add_argument("--rounds", type=int, default=3, help="alternating timing rounds")
    ap.add_argument("--baseline", metavar="CHECKOUT",
                    help="another checkout of rikin (e.g. /work/main), timed in turn with this one")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--breakdown", action="store_true",
                    help="only where a general 6R's arm.ik time goes, against the Puma's")
    args = ap.parse_args()
    if args.breakdown:
        every = arms()
        print_stages([(arm.name, general_stages(every[0], arm, args.poses, args.rounds))
                      for arm in every if str(rikin.ik.classify(arm)).startswith("general")])
        return
    if args.json:
        print(json.dumps(timings(args.poses, args.rounds, args.batch_poses)))
        return
    if args.baseline is None:
        print_table(timings(args.poses, args.rounds, args.batch_poses), None)
        return
    mine, theirs = [], []
    for _ in range(args.rounds):  # in turn, so that the machine's load hits both alike
        theirs.append(baseline_timings(args.baseline, args.poses, args.batch_poses))
        mine.append(timings(args.poses, 1, args.batch_poses))
    print_table(best_of(mine), best_of(theirs))


if __name__ == "__main__":
    main()
