"""All-solution IK of industrial 6R arms from their DH tables: rikin against roboticstoolbox.

The arms (DH numbers in ``ROBOTS`` below, each with its source): the Puma 560, KUKA KR5,
KUKA KR6/2, ABB IRB 120 and the Epson C4 of the lab (rikin's modified-DH table, rewritten
as standard DH for roboticstoolbox; both FK are compared first). The Epson C4 is solved
twice by rikin: by ``robots.epson_c4()`` (the lesson's decoupling solver) and by the same
table given to ``SerialArm`` alone (the general closed form of :mod:`rikin.ik.pieper`).

Poses, seeded: FK of ``--poses`` uniform random joint vectors per arm, and ``--singular``
poses of each kind near a singularity (a fifth of them exactly on it, the rest
``10**U(-9, -5)`` rad away): wrist (theta5 = 0 and pi), shoulder (the wrist centre on
axis 1, or as near as the arm's offsets let it come), elbow stretched and folded
(distance of the wrist centre from axis 2 at its largest and smallest).

Both sides solve every pose: rikin ``arm.ik(T)`` (no derivation step), roboticstoolbox 1.5
``robot.analytic_ik()`` (a sympy derivation, timed apart) then ``.solve(T_flange,
joint_limits=False)`` per pose. Printed per arm:

* ``equal``: poses whose solution sets are equal modulo 2 pi to 1e-9 rad (every solution
  of each side has one of the other within 1e-9), regular and near-singular poses apart;
* ``miss``: real solutions (FK residual <= 1e-9) one side lacks: no solution of its own
  within 1e-6 rad, nor one that Newton's method in 40-digit arithmetic takes to the same
  exact root (near a singularity the pose fixes some joints only to ~1e-4 rad, and both
  sides hold one solution that far apart), nor one of the same singular family (at a
  wrist singularity only q4 + q6 or q4 - q6 is fixed; with the wrist centre on axis 1,
  q1 is free). The notes say, for those ill-conditioned pairs, which side was nearer the
  exact root;
* ``wrong``: solutions whose FK misses the pose by more than 1e-9 (relative to the arm's
  size for positions);
* ``res``: the largest FK residual of a side over all its solutions and poses;
* ``us/pose``: wall time per pose on the regular poses, rikin ``arm.ik`` one float64 4x4
  array at a time (the one-pose fast path), rikin's ``ik_batch`` of all of them on one
  thread (``workers=1``), and roboticstoolbox's ``solve``; the derivation apart. The three
  are timed in alternating rounds on the same poses (best of ``--rounds``, so that a
  change of the machine's load hits all), after freezing the garbage collector's view of
  the sympy objects the derivation leaves (otherwise every collection walks them, and the
  side that allocates more pays for the other's derivation); ``ratio`` is rtb time /
  rikin ``arm.ik`` time, by wall clock and by process CPU time (``cpu``), and ``batch``
  rtb time / ``ik_batch`` time (wall clock, one thread each).

    python benchmarks/bench_ik6r.py                          # 1,000 + 5 x 50 poses per arm
    python benchmarks/bench_ik6r.py --poses 50 --singular 10 # a smoke run
    python benchmarks/bench_ik6r.py --time-only --arms "Puma 560" "KUKA KR5" "IRB 140"

``--time-only`` times the three sides on the random poses and prints the ratios, without
comparing the solution sets (minutes instead of most of an hour on a busy machine: the
derivation of rtb's closed form is still timed apart); ``--arms`` keeps the arms whose
name contains one of the words given; ``--breakdown`` (with ``--time-only``) then prints
where ``arm.ik``'s time goes, stage by stage, by thread CPU time (``stage_times``), beside
a tenth of rtb's CPU time per pose (what ``arm.ik`` would have to take for 10x).

roboticstoolbox is optional (``pip install "roboticstoolbox-python[ik]"``); without it
only rikin's figures (FK residuals, time) are printed.
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

import rikin
from rikin import Link, SerialArm, robots

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from mp_reference import exact_root  # noqa: E402  (the 40-digit reference the tests use)
from singular_poses import CROSSING_JOINT, singular_q  # noqa: E402  (the tests' singular poses)

SEED = 20261202
pi = np.pi
SAME = 1e-9  # rad: the same solution
LOOSE = 1e-6  # rad: the same solution, ill-conditioned near a singularity
REAL = 1e-9  # FK residual (relative) of a real solution


# (name, source, standard-DH rows (d, a, alpha, offset) in metres)
ROBOTS = [
    ("Puma 560",
     "roboticstoolbox 1.5 models.DH.Puma560 (Corke & Armstrong-Helouvry, ICRA 1994)",
     [(0.67183, 0, pi / 2, 0), (0, 0.4318, 0, 0), (0.15005, 0.0203, -pi / 2, 0),
      (0.4318, 0, pi / 2, 0), (0, 0, -pi / 2, 0), (0, 0, 0, 0)]),
    ("KUKA KR5",
     "roboticstoolbox 1.5 models.DH.KR5 (from ARTE robots/KUKA/KR5_arc/parameters.m)",
     [(0.4, 0.18, -pi / 2, 0), (0, 0.6, 0, 0), (0, 0.12, pi / 2, 0),
      (-0.62, 0, -pi / 2, 0), (0, 0, pi / 2, 0), (-0.115, 0, pi, 0)]),
    ("KUKA KR6",
     "ARTE (A. Gil, UMH) robots/KUKA/KR6_2/parameters.m",
     [(0.675, 0.26, -pi / 2, 0), (0, 0.68, 0, -pi / 2), (0, -0.035, pi / 2, 0),
      (-0.67, 0, -pi / 2, 0), (0, 0, pi / 2, 0), (-0.115, 0, pi, 0)]),
    ("ABB IRB 120",
     "ARTE (A. Gil, UMH) robots/ABB/IRB120/parameters.m",
     [(0.29, 0, -pi / 2, 0), (0, 0.27, 0, -pi / 2), (0, 0.07, -pi / 2, 0),
      (0.302, 0, pi / 2, 0), (0, 0, -pi / 2, 0), (0.072, 0, 0, pi)]),
    ("ABB IRB 140",
     "roboticstoolbox 1.5 models.DH.IRB140",
     [(0.352, 0.07, -pi / 2, 0), (0, 0.36, 0, 0), (0, 0, -pi / 2, 0),
      (0.38, 0, pi / 2, 0), (0, 0, -pi / 2, 0), (0.065, 0, 0, 0)]),
]
EPSON_SOURCE = "rikin.robots.epson_c4(): the lab's modified-DH table (mm), rewritten as standard DH"


def epson_standard_rows(c4: SerialArm) -> list[tuple[float, float, float, float]]:
    """The modified table as standard DH: the same factors of the FK grouped differently.

    Modified link i is ``Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``; standard link i
    is ``Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``; ``Tx`` and ``Rx`` commute, so standard
    row i takes ``d_i`` and the offset of modified row i and ``a, alpha`` of row i + 1 (the
    C4's row 1 has ``a_0 = alpha_0 = 0``, and nothing follows row 6).
    """
    mod = c4.links
    assert float(mod[0].a) == 0.0 and float(mod[0].alpha) == 0.0
    rows = []
    for i in range(6):
        nxt = mod[i + 1] if i < 5 else Link()
        rows.append((float(mod[i].d), float(nxt.a), float(nxt.alpha), float(mod[i].offset)))
    return rows


@dataclass
class Case:
    name: str
    source: str
    arm: SerialArm  # what rikin solves
    rows: list  # standard DH for roboticstoolbox
    base: np.ndarray
    tool: np.ndarray
    rtb: object = None
    ik: object = None
    derive_s: float = float("nan")
    fk_agreement: float = float("nan")


def cases() -> list[Case]:
    out = []
    for name, source, rows in ROBOTS:
        arm = SerialArm(tuple(Link(d=d, a=a, alpha=al, offset=o) for d, a, al, o in rows),
                        name=name, units="m")
        out.append(Case(name, source, arm, rows, np.eye(4), np.eye(4)))
    c4 = robots.epson_c4()
    rows = epson_standard_rows(c4)
    out.append(Case("Epson C4 (lesson solver)", EPSON_SOURCE, c4, rows, c4.base, c4.tool))
    table = SerialArm(c4.links, convention="modified", base=c4.base, tool=c4.tool,
                      units=c4.units, name="Epson C4 (table)")
    out.append(Case("Epson C4 (from its table)", EPSON_SOURCE, table, rows, c4.base, c4.tool))
    return out


def attach_rtb(case: Case, rng: np.random.Generator) -> None:
    """roboticstoolbox's arm of the same standard-DH rows, its FK agreement, and its IK."""
    import roboticstoolbox as rtb

    case.rtb = rtb.DHRobot([rtb.RevoluteDH(d=d, a=a, alpha=al, offset=o)
                            for d, a, al, o in case.rows], name=case.name)
    q = rng.uniform(-pi, pi, (200, 6))
    ours = case.arm.fk(q)
    theirs = np.array([case.base @ case.rtb.fkine(qi).A @ case.tool for qi in q])
    case.fk_agreement = float(np.abs(ours - theirs).max() / case.arm.scale)
    assert case.fk_agreement < 1e-12, (case.name, case.fk_agreement)
    t0 = time.perf_counter()
    case.ik = case.rtb.analytic_ik()
    case.derive_s = time.perf_counter() - t0


# ------------------------------------------------------------------ poses near singularities
SINGULAR_KINDS = tuple(CROSSING_JOINT)


def singular_poses(arm: SerialArm, n: int, rng: np.random.Generator):
    """``n`` joints per kind near it: a fifth exactly on it, the rest 1e-9..1e-5 rad off
    along the joint that crosses it (q5; q2 for the shoulder; q3 for the elbow)."""
    qs, kinds = [], []
    for kind in SINGULAR_KINDS:
        for m in range(n):
            q = singular_q(arm, kind, rng, regular_wrist=False)
            if m >= n // 5:
                q[CROSSING_JOINT[kind]] += rng.choice([-1, 1]) * 10.0 ** rng.uniform(-9, -5)
            qs.append(q)
            kinds.append(kind)
    return np.array(qs), kinds


# ------------------------------------------------------------------ comparing solution sets
def residuals(arm: SerialArm, q: np.ndarray, T: np.ndarray) -> np.ndarray:
    """FK residual of each row: position error / arm size, and rotation entries."""
    if len(q) == 0:
        return np.zeros(0)
    F = arm.fk(q, check_degrees=False)
    pos = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1) / arm.scale
    return np.maximum(pos, np.abs(F[:, :3, :3] - T[:3, :3]).max(axis=(1, 2)))


def _wrapped(x: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * x)))


def nearest(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Distance (max abs, modulo 2 pi) from each row of A to the nearest row of B."""
    if len(B) == 0:
        return np.full(len(A), np.inf)
    return _wrapped(A[:, None, :] - B[None, :, :]).max(-1).min(axis=1) if len(A) else np.zeros(0)


def refine(case: Case, q: np.ndarray, T: np.ndarray):
    """Newton's method on the pose in 40-digit arithmetic from ``q``: the exact solution
    near it (float64 array), or None when it does not converge (a double root of a pose at
    a fold to rounding, or a family at an exact singularity). 14 steps: quadratic from a
    float solution, while a double root stalls."""
    return exact_root(case.arm, q, T, steps=14, tol=1e-30)


def in_family(row: np.ndarray, B: np.ndarray, free: tuple[int, ...]) -> bool:
    """``row`` belongs to the singular family of a row of B: equal in what the pose fixes."""
    for b in B:
        d = _wrapped(row - b)
        if 4 in free and 6 in free:  # only q4 + q6 (theta5 = 0) or q4 - q6 (pi) fixed
            fixed = max(d[[0, 1, 2, 4]].max(initial=0.0) if 1 not in free else d[[1, 2, 4]].max(),
                        min(_wrapped((row[3] + row[5]) - (b[3] + b[5])),
                            _wrapped((row[3] - row[5]) - (b[3] - b[5]))))
            if fixed < LOOSE:
                return True
        if 1 in free and d[[1, 2]].max() < LOOSE:  # q1 free: the wrist follows it
            return True
        if 2 in free and d[[0, 2]].max() < LOOSE:
            return True
    return False


def covers(case: Case, T: np.ndarray, row: np.ndarray, Y: np.ndarray,
           free: tuple[int, ...]) -> bool:
    """One of the solutions ``Y`` is ``row`` (to 1e-9, or refined to the same exact root),
    or ``row`` is in the singular family of one of them."""
    if len(Y) and nearest(row[None], Y)[0] <= LOOSE:
        return True
    if free and in_family(row, Y, free):
        return True
    exact = refine(case, row, T)
    near = [y for y in Y if _wrapped(y - row).max() < 1e-3]
    if exact is None:
        return bool(near)
    return any((e := refine(case, y, T)) is not None and _wrapped(e - exact).max() < 1e-12
               for y in near)


@dataclass
class Tally:
    poses: int = 0
    equal: int = 0
    miss: list = field(default_factory=lambda: [0, 0])  # rikin, rtb
    wrong: list = field(default_factory=lambda: [0, 0])
    res: list = field(default_factory=lambda: [0.0, 0.0])
    none: list = field(default_factory=lambda: [0, 0])  # poses with no solution at all
    missed: list = field(default_factory=lambda: [0, 0])  # notes of misses written
    nearer: list = field(default_factory=lambda: [0, 0])  # ill-conditioned: rikin/rtb nearer
    unresolved: int = 0  # no isolated exact root near the solution
    family: int = 0  # solutions matched only through a singular family
    loose: int = 0  # matched only to 1e-6
    notes: list = field(default_factory=list)


def compare(case: Case, T: np.ndarray, A: np.ndarray, free: tuple[int, ...],
            B: np.ndarray, tally: Tally, label: str, regular: bool = False) -> None:
    """Fold one pose's two solution sets into ``tally`` (A: rikin, B: roboticstoolbox)."""
    arm = case.arm
    tally.poses += 1
    rA, rB = residuals(arm, A, T), residuals(arm, B, T)
    for side, (X, rX, _Y) in enumerate(((A, rA, B), (B, rB, A))):
        if len(X):
            tally.res[side] = max(tally.res[side], float(rX.max()))
        else:
            tally.none[side] += 1
        tally.wrong[side] += int((rX > REAL).sum())
    dAB, dBA = nearest(A, B), nearest(B, A)
    if (dAB <= SAME).all() and (dBA <= SAME).all():
        tally.equal += 1
        return
    if regular and len(tally.notes) < 4:
        far = max(dAB[np.isfinite(dAB)].max(initial=0.0), dBA[np.isfinite(dBA)].max(initial=0.0))
        tally.notes.append(f"{label}: {len(A)}/{len(B)} solutions, farthest pair {far:.1e} rad "
                           f"apart; largest FK residual rikin {rA.max(initial=0):.1e}, "
                           f"rtb {rB.max(initial=0):.1e}")
    # a real solution of one side, absent from the other: a miss of the other side
    for side, (X, rX, dX, Y) in enumerate(((B, rB, dBA, A), (A, rA, dAB, B))):
        for row, r, dist in zip(X, rX, dX, strict=True):
            if dist <= SAME or r > REAL:
                continue
            if free and in_family(row, Y, free):
                tally.family += 1
                continue
            if dist <= LOOSE:  # one solution, ill-conditioned (near a singularity)
                tally.loose += 1
                continue
            exact = refine(case, row, T)
            if exact is None:  # no isolated root there: a fold or family to rounding
                tally.unresolved += 1
                continue
            own = [y for y in Y if _wrapped(y - row).max() < 1e-3]
            same = [y for y in own if (e := refine(case, y, T)) is not None
                    and _wrapped(e - exact).max() < 1e-12]
            if same:  # one solution, ill-conditioned: who is nearer the exact one?
                tally.loose += 1
                err_own = min(_wrapped(y - exact).max() for y in same)
                err_other = _wrapped(row - exact).max()
                tally.nearer[side if err_own < err_other else 1 - side] += 1
            else:
                tally.miss[side] += 1
                tally.missed[side] += 1
                if tally.missed[side] <= (8 if side == 0 else 2):
                    who = "rikin" if side == 0 else "rtb"
                    tally.notes.append(f"{label}: {who} misses q={np.round(row, 9).tolist()} "
                                       f"(FK residual {r:.1e}, nearest of its own {dist:.1e} rad)")


# ------------------------------------------------------------------ running both sides
def solve_rikin(arm: SerialArm, Ts: np.ndarray):
    sols, free = [], []
    t0 = time.perf_counter()
    for T in Ts:
        try:
            res = arm.ik(T)
        except rikin.UnreachableError:
            sols.append(np.zeros((0, 6)))
            free.append(())
            continue
        sols.append(res.q)
        free.append(res.free_joints)
    return sols, free, time.perf_counter() - t0


def solve_rtb(case: Case, Ts: np.ndarray):
    flange = np.linalg.inv(case.base) @ Ts @ np.linalg.inv(case.tool)
    t0 = time.perf_counter()
    out = [np.atleast_2d(case.ik.solve(F, joint_limits=False).q).reshape(-1, 6) for F in flange]
    return out, time.perf_counter() - t0


def time_sides(case: Case, Ts: np.ndarray, rounds: int) -> tuple[float, float, float, float,
                                                                 float]:
    """Best wall-clock and CPU seconds over all of ``Ts``: ``(rikin wall, rtb wall, rikin
    cpu, rtb cpu, rikin batch wall)``, rikin's ``arm.ik``, roboticstoolbox's ``solve`` and
    rikin's ``ik_batch`` on one thread in alternating rounds on the same poses (module
    docstring)."""
    gc.collect()
    gc.freeze()
    poses = [np.array(T) for T in Ts]  # what a caller passes: one float64 4x4 array each
    flange = list(np.linalg.inv(case.base) @ Ts @ np.linalg.inv(case.tool))
    arm, solve = case.arm, case.ik.solve

    def rikin_round() -> None:
        for T in poses:
            try:
                arm.ik(T)
            except rikin.UnreachableError:
                pass

    def rtb_round() -> None:
        for F in flange:
            solve(F, joint_limits=False)

    batch = np.array(Ts)

    def batch_round() -> None:
        arm.ik_batch(batch, workers=1)

    best = [np.inf] * 6
    for _ in range(rounds):
        for k, fn in enumerate((rikin_round, rtb_round, batch_round)):
            t0, c0 = time.perf_counter(), time.process_time()
            fn()
            best[k] = min(best[k], time.perf_counter() - t0)
            best[3 + k] = min(best[3 + k], time.process_time() - c0)
    return best[0], best[1], best[3], best[4], best[2]


def _case_note(case: Case, lost: object, reg: Tally, sing: Tally) -> str:
    """The note printed under the table for one arm: FK agreement and what the two
    tallies (random and singular poses) hold beyond the table's counts."""
    return (
        f"{case.name}: FK of rikin and roboticstoolbox agree to {case.fk_agreement:.1e}; "
        f"generating q not among rikin's solutions: {lost}; "
        f"solutions the sides hold only up to conditioning: {sing.loose + reg.loose}, only "
        f"within a singular family: {sing.family + reg.family}; of the ill-conditioned, "
        f"nearer the 40-digit root rikin/rtb: {reg.nearer[0] + sing.nearer[0]}/"
        f"{reg.nearer[1] + sing.nearer[1]}; no isolated root near: "
        f"{reg.unresolved + sing.unresolved}; poses without any "
        f"solution rikin/rtb: {reg.none[0] + sing.none[0]}/{reg.none[1] + sing.none[1]}")


def time_only(chosen: list[Case], poses: int, rounds: int, rng: np.random.Generator,
              breakdown: bool = False) -> None:
    """``--time-only``: per arm, rikin ``arm.ik``, rtb's ``solve`` and rikin's ``ik_batch``
    on the same random poses in alternating rounds (:func:`time_sides`), and the ratios;
    with ``--breakdown``, where ``arm.ik``'s time goes (:func:`stage_times`) and rtb's
    CPU time per pose over ten, the time ``arm.ik`` would have to take for 10x."""
    head = (f"{'arm':<26}{'rikin us':>9}{'batch us':>9}{'rtb us':>8}{'ratio':>7}{'cpu':>6}"
            f"{'batch':>7}{'derive s':>9}")
    print(head, flush=True)
    table = []
    for case in chosen:
        T_reg = case.arm.fk(rng.uniform(-pi, pi, (poses, 6)))
        attach_rtb(case, rng)
        t_r, t_t, c_r, c_t, t_b = time_sides(case, T_reg, rounds)
        us = 1e6 / poses
        print(f"{case.name:<26}{t_r * us:>9.0f}{t_b * us:>9.1f}{t_t * us:>8.0f}{t_t / t_r:>7.2f}"
              f"{c_t / c_r:>6.1f}{t_t / t_b:>7.1f}{case.derive_s:>9.1f}", flush=True)
        if breakdown:
            table.append((case.name, c_t * us, stage_times(case.arm, T_reg, rounds)))
    if table:
        print_stages(table)


#: The stages of :func:`stage_times`, in the order printed.
STAGES = ("arm.ik", "closed form", "FK check", "checks+result", "call+declined")


def stage_times(arm: SerialArm, Ts: np.ndarray, rounds: int) -> dict[str, float]:
    """Thread CPU µs per pose of ``arm.ik`` and of its stages, found by timing the one-pose
    path whole and with stages left out, in alternating rounds (best of ``rounds``, at
    least 5), each stage in the context of the others (timed alone, a stage runs in warm
    caches and looks up to 20% cheaper).

    The stages: ``closed form``, the plain-float kernel (``PieperKernel.solve``, with the
    pose read into lists); ``FK check``, :class:`rikin.ik.fkcheck.FKCheck` of every
    solution; ``checks+result``, the pose's checks, the solutions' array and the
    ``IKResult``; ``call+declined``, the calls from ``arm.ik`` down and the general solver
    on the poses the kernel declines (``declined``: how many, ``per declined``: the µs
    each costs). Reads rikin's private one-pose path (``rikin.ik.api._solve_regular``
    and the kernel cached on the arm): a profile, not an interface.
    """
    from rikin.ik import api  # noqa: PLC0415  (only here: the private path profiled)

    poses = [np.array(T) for T in Ts]
    try:
        arm.ik(poses[0])
    except rikin.UnreachableError:
        pass
    kernel, fk_check = arm.__dict__["_single_kernel"]  # cached by the first arm.ik

    def no_check(q: np.ndarray, T: np.ndarray) -> float:
        return 0.0

    declined = [T for T in poses if kernel.solve(T.tolist()) is None]
    regular = api._solve_regular

    def ik(Ts: list[np.ndarray]) -> None:
        for T in Ts:
            try:
                arm.ik(T)
            except rikin.UnreachableError:
                pass

    runs = {
        "arm.ik": lambda: ik(poses),
        "regular": lambda: [regular(arm, kernel, fk_check, T) for T in poses],
        "unchecked": lambda: [regular(arm, kernel, no_check, T) for T in poses],
        "closed form": lambda: [kernel.solve(T.tolist()) for T in poses],
        "declined": lambda: ik(declined),
    }
    best = dict.fromkeys(runs, np.inf)
    gc.collect()
    for _ in range(max(rounds, 5)):
        for name, fn in runs.items():
            t0 = time.thread_time()
            fn()
            best[name] = min(best[name], time.thread_time() - t0)
    us = {name: t * 1e6 / len(poses) for name, t in best.items()}
    return {"arm.ik": us["arm.ik"], "closed form": us["closed form"],
            "FK check": us["regular"] - us["unchecked"],
            "checks+result": us["unchecked"] - us["closed form"],
            "call+declined": us["arm.ik"] - us["regular"],
            "declined": float(len(declined)),
            "per declined": (best["declined"] * 1e6 / len(declined) if declined
                             else float("nan"))}


def print_stages(table: list[tuple[str, float, dict[str, float]]]) -> None:
    """The ``--breakdown`` table: thread CPU µs per pose of each stage (and its share of
    ``arm.ik``), the declined poses, and rtb's CPU µs per pose over 10."""
    print("\nwhere arm.ik's time goes, thread CPU us per pose (share of arm.ik):")
    print(f"{'arm':<26}" + "".join(f"{s:>19}" for s in STAGES)
          + f"{'declined':>10}{'us each':>9}{'rtb cpu / 10':>13}")
    for name, rtb_us, st in table:
        cells = "".join(f"{st[s]:>10.1f} ({st[s] / st['arm.ik']:>4.0%})" for s in STAGES)
        print(f"{name:<26}{cells}{st['declined']:>10.0f}{st['per declined']:>9.0f}"
              f"{rtb_us / 10:>13.1f}", flush=True)


def _arguments() -> argparse.Namespace:
    """The command line (module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=1000, help="random poses per arm")
    ap.add_argument("--singular", type=int, default=50, help="poses per singularity kind")
    ap.add_argument("--rounds", type=int, default=3, help="alternating timing rounds")
    ap.add_argument("--arms", nargs="+", help="only the arms whose name contains one of these")
    ap.add_argument("--time-only", action="store_true",
                    help="time the sides on the random poses, without comparing solution sets")
    ap.add_argument("--breakdown", action="store_true",
                    help="with --time-only: where arm.ik's time goes, stage by stage")
    return ap.parse_args()


def main() -> None:
    args = _arguments()
    try:
        import roboticstoolbox  # noqa: F401

        with_rtb = True
    except ImportError:
        with_rtb = False
        print("roboticstoolbox not installed: rikin's figures only")
    rng = np.random.default_rng(SEED)
    print(f"load average {os.getloadavg()[0]:.1f} {os.getloadavg()[1]:.1f}, {os.cpu_count()} "
          f"CPUs; seed {SEED}; per arm {args.poses} random poses"
          + ("" if args.time_only else
             f" + {len(SINGULAR_KINDS)} x {args.singular} near singularities"))
    head = (f"{'arm':<26}{'equal reg':>10}{'equal sing':>11}{'miss rikin/rtb':>15}"
            f"{'wrong':>7}{'res rikin':>10}{'res rtb':>9}{'rikin us':>9}{'batch us':>9}"
            f"{'rtb us':>8}{'ratio':>7}{'cpu':>6}{'batch':>7}{'derive s':>9}")
    rows, notes = [], []
    chosen = [case for case in cases()
              if not args.arms or any(word in case.name for word in args.arms)]
    if args.time_only and with_rtb:
        time_only(chosen, args.poses, args.rounds, rng, args.breakdown)
        return
    print(head, flush=True)  # each arm's row as it is done (the run takes a while)
    for case in chosen:
        n_notes = len(notes)
        arm = case.arm
        q_reg = rng.uniform(-pi, pi, (args.poses, 6))
        q_sing, kinds = singular_poses(arm, args.singular, rng)
        T_reg, T_sing = arm.fk(q_reg), arm.fk(q_sing)
        sols_r, free_r, t_r = solve_rikin(arm, T_reg)
        sols_s, free_s, _ = solve_rikin(arm, T_sing)
        t0 = time.perf_counter()
        arm.ik_batch(T_reg, workers=1)
        t_b = time.perf_counter() - t0
        # rikin alone: the generating q among the solutions (or in their singular family)
        lost = sum(
            not covers(case, T, q, sols, free)
            for q, T, sols, free in zip(np.vstack([q_reg, q_sing]), np.vstack([T_reg, T_sing]),
                                        sols_r + sols_s, free_r + free_s, strict=True))
        us = 1e6 / args.poses
        if not with_rtb:
            res = max(residuals(arm, s, T).max(initial=0) for s, T in
                      zip(sols_r + sols_s, np.vstack([T_reg, T_sing]), strict=True))
            rows.append(f"{case.name:<26}{'':>10}{'':>11}{'':>15}{'':>7}{res:>10.1e}{'':>9}"
                        f"{t_r * us:>9.0f}{t_b * us:>9.1f}")
            notes.append(f"{case.name}: generating q not among rikin's solutions: {lost}")
            continue
        attach_rtb(case, rng)
        rtb_r, _ = solve_rtb(case, T_reg)
        rtb_s, _ = solve_rtb(case, T_sing)
        t_r, t_t, c_r, c_t, t_b = time_sides(case, T_reg, args.rounds)
        reg, sing = Tally(), Tally()
        for i, T in enumerate(T_reg):
            compare(case, T, sols_r[i], free_r[i], rtb_r[i], reg, f"{case.name} random #{i}",
                    regular=True)
        for i, T in enumerate(T_sing):
            compare(case, T, sols_s[i], free_s[i], rtb_s[i], sing,
                    f"{case.name} {kinds[i]} #{i}")
        miss = [reg.miss[s] + sing.miss[s] for s in (0, 1)]
        wrong = [reg.wrong[s] + sing.wrong[s] for s in (0, 1)]
        res = [max(reg.res[s], sing.res[s]) for s in (0, 1)]
        rows.append(
            f"{case.name:<26}{f'{reg.equal}/{reg.poses}':>10}{f'{sing.equal}/{sing.poses}':>11}"
            f"{f'{miss[0]}/{miss[1]}':>15}{f'{wrong[0]}/{wrong[1]}':>7}{res[0]:>10.1e}"
            f"{res[1]:>9.1e}{t_r * us:>9.0f}{t_b * us:>9.1f}{t_t * us:>8.0f}"
            f"{t_t / t_r:>7.2f}{c_t / c_r:>6.1f}{t_t / t_b:>7.1f}{case.derive_s:>9.1f}")
        print(rows[-1], flush=True)
        notes.append(_case_note(case, lost, reg, sing))
        notes += reg.notes + sing.notes
        print("\n".join(notes[n_notes:]), flush=True)
    print("\n" + head)
    print("\n".join(rows))
    print("\n".join(notes))
    sources = "; ".join(f"{n}: {s}" for n, s, _ in ROBOTS)
    print(f"sources: {sources}; Epson C4: {EPSON_SOURCE}")


if __name__ == "__main__":
    main()
