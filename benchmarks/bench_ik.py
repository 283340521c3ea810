"""IK speed on the Aula 10 6R: rikin's batch closed form, its per-pose loop, numerical IK.

Every method solves the SAME seeded random reachable poses (FK of random
joint values, generated once). Printed: poses/s of each method, its ratio
against rikin's batch at the largest N, and the peak memory of a separate
batch run at N = 1,000,000 (measured in a child process: the high-water
mark of its resident memory, ``VmHWM``, and that peak minus the baseline
after importing numpy and rikin).

    python benchmarks/bench_ik.py            # full run (about 20 s)
    python benchmarks/bench_ik.py --quick    # small N, a smoke run
    python benchmarks/bench_ik.py --json results.json

roboticstoolbox-python (``pip install "roboticstoolbox-python[ik]"``) is optional:
when it is importable, its ``ik_LM`` is timed on the same poses, and its all-solution
closed form ``DHRobot.analytic_ik().solve`` (derived first: 3-4 s here) against rikin's
``arm.ik`` one pose at a time: both in alternating rounds on the same poses, best round
of each, printed as a ratio.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import platform
import resource
import subprocess
import sys
import time
from typing import Any

import numpy as np

import rikin
from rikin.ik.numerical import ik_numerical

SEED = 20240607


def machine() -> dict[str, Any]:
    """CPU count and model, Python and numpy versions."""
    model = platform.processor() or "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {
        "nproc": os.cpu_count(),
        "cpu": model,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "rikin": rikin.__version__,
    }


def reachable_poses(
    arm: rikin.SerialArm, n: int, seed: int = SEED, out: np.ndarray | None = None
) -> np.ndarray:
    """``n`` world poses ``(n, 4, 4)`` from FK of seeded random joint values, built in chunks."""
    rng = np.random.default_rng(seed)
    T = np.empty((n, 4, 4)) if out is None else out
    for start in range(0, n, 50_000):
        stop = min(start + 50_000, n)
        T[start:stop] = arm.fk(rng.uniform(-np.pi, np.pi, (stop - start, arm.n)))
    return T


def best_of(fn: Any, repeat: int) -> tuple[float, float]:
    """Smallest wall time of ``repeat`` calls, and the process CPU time of that call, s.

    On a shared machine the wall time depends on the other processes; the CPU
    time (all threads added up) much less so.
    """
    best, cpu = np.inf, np.inf
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        t, c = time.perf_counter() - t0, time.process_time() - c0
        if t < best:
            best, cpu = t, c
    return best, cpu


def load_average() -> float | None:
    """The 1-minute load average (other processes competing for the CPUs), if known."""
    try:
        return os.getloadavg()[0]
    except OSError:
        return None


def bench_batch(arm: rikin.SerialArm, T: np.ndarray, sizes: list[int]) -> list[dict[str, Any]]:
    rows = []
    for n in sizes:
        sub = T[:n]
        res = arm.ik_batch(sub)
        t, cpu = best_of(lambda sub=sub: arm.ik_batch(sub), 3)
        rows.append(
            {
                "method": "rikin ik_batch (8 slots)",
                "n": n,
                "seconds": t,
                "cpu_seconds": cpu,
                "poses_per_s": n / t,
                "poses_per_cpu_s": n / cpu if cpu > 0 else None,
                "solutions_per_pose": float(res.counts.mean()),
                "load_average": load_average(),
            }
        )
    return rows


def bench_loop(arm: rikin.SerialArm, T: np.ndarray, n: int) -> dict[str, Any]:
    t0 = time.perf_counter()
    count = sum(len(arm.ik(T[i])) for i in range(n))
    t = time.perf_counter() - t0
    return {
        "method": "rikin arm.ik per pose (all solutions, labelled, FK-checked)",
        "n": n,
        "seconds": t,
        "poses_per_s": n / t,
        "solutions_per_pose": count / n,
    }


def bench_numerical(arm: rikin.SerialArm, T: np.ndarray, n: int) -> dict[str, Any]:
    rng = np.random.default_rng(SEED + 1)
    t0 = time.perf_counter()
    ok = sum(ik_numerical(arm, T[i], rng=rng).success for i in range(n))
    t = time.perf_counter() - t0
    return {
        "method": "rikin ik_numerical (LM, 1 solution, tol 1e-10)",
        "n": n,
        "seconds": t,
        "poses_per_s": n / t,
        "success_rate": ok / n,
    }


def rtb_robot(arm: rikin.SerialArm) -> Any:
    """The same standard-DH arm in roboticstoolbox-python, or None if it is not installed."""
    try:
        from roboticstoolbox import DHRobot, RevoluteDH
    except Exception:  # noqa: BLE001 - any import failure means "not available"
        return None
    robot = DHRobot(
        [
            RevoluteDH(d=float(lk.d), a=float(lk.a), alpha=float(lk.alpha), offset=float(lk.offset))
            for lk in arm.links
        ],
        name=arm.name,
    )
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (5, arm.n))
    for qi in q:  # the two models must agree, or the comparison means nothing
        if np.abs(robot.fkine(qi).A - arm.fk(qi)).max() > 1e-9:
            raise RuntimeError("roboticstoolbox model does not match rikin's DH table")
    return robot


def bench_rtb(
    robot: Any, arm: rikin.SerialArm, T: np.ndarray, n: int, tol: float | None
) -> dict[str, Any]:
    """``robot.ik_LM`` per pose; success = its own flag AND FK within 1e-6 * arm.scale.

    rtb's ``tol`` bounds ``0.5 e^T W e`` (squared error); its default 1e-6 leaves
    FK errors up to ~1e-3 length units, so the run with ``tol=1e-16`` is the
    one comparable with rikin's 1e-10 relative tolerance.
    """
    kw = {} if tol is None else {"tol": tol}
    t0 = time.perf_counter()
    sols = [robot.ik_LM(T[i], **kw) for i in range(n)]
    t = time.perf_counter() - t0
    err = np.array([np.abs(arm.fk(s.q) - T[i]).max() for i, s in enumerate(sols)])
    flag = np.array([bool(s.success) for s in sols])
    label = "default tol 1e-6" if tol is None else f"tol={tol:g}"
    return {
        "method": f"roboticstoolbox ik_LM (1 solution, {label})",
        "n": n,
        "seconds": t,
        "poses_per_s": n / t,
        "success_rate": float((flag & (err < 1e-6 * arm.scale)).mean()),
        "own_success_rate": float(flag.mean()),
        "max_fk_error": float(err.max()),
    }


def bench_single(
    arm: rikin.SerialArm, T: np.ndarray, robot: Any, rounds: int = 5
) -> dict[str, Any]:
    """rikin ``arm.ik`` and (if given) rtb ``analytic_ik().solve`` one pose at a time.

    Rounds alternate between the two on the same poses, so a change of the
    machine's load hits both; the best round of each is kept, by wall clock
    and by process CPU time (what the process itself spent: the figure that
    other processes on a shared machine disturb least). Both are
    single-threaded here, so their ratios compare like with like.
    """
    solve = None
    derive_s = None
    if robot is not None:
        t0 = time.perf_counter()
        solve = robot.analytic_ik().solve
        derive_s = time.perf_counter() - t0
        solve(T[0])
    arm.ik(T[0])
    # The derivation leaves millions of sympy objects alive; without this every later
    # garbage collection walks them all, and whichever solver allocates more Python objects
    # per pose pays the most for the other's derivation (rikin ran 11,100 instead of 17,700
    # poses/s next to it). Freezing moves them out of the collector's way for both sides.
    gc.collect()
    gc.freeze()
    poses = [np.array(t) for t in T]  # what a caller passes: one float64 4x4 array each
    wall = {"rikin": np.inf, "rtb": np.inf}
    cpu = {"rikin": np.inf, "rtb": np.inf}
    n_sol = n_rtb = 0

    def rikin_round() -> int:
        return sum(len(arm.ik(t)) for t in poses)

    def rtb_round() -> int:
        return sum(len(np.atleast_2d(solve(t).q)) for t in poses)  # type: ignore[misc]

    for _ in range(rounds):
        for name, fn in (("rikin", rikin_round), ("rtb", rtb_round)):
            if name == "rtb" and solve is None:
                continue
            t0, c0 = time.perf_counter(), time.process_time()
            count = fn()
            wall[name] = min(wall[name], time.perf_counter() - t0)
            cpu[name] = min(cpu[name], time.process_time() - c0)
            if name == "rikin":
                n_sol = count
            else:
                n_rtb = count
    out: dict[str, Any] = {
        "arm": arm.name,
        "n": len(T),
        "rikin_poses_per_s": len(T) / wall["rikin"],
        "rikin_poses_per_cpu_s": len(T) / cpu["rikin"],
        "rikin_solutions_per_pose": n_sol / len(T),
        "load_average": load_average(),
    }
    if solve is not None:
        out.update(
            rtb_poses_per_s=len(T) / wall["rtb"],
            rtb_poses_per_cpu_s=len(T) / cpu["rtb"],
            rtb_solutions_per_pose=n_rtb / len(T),
            rtb_derivation_s=derive_s,
            ratio=wall["rtb"] / wall["rikin"],
            ratio_cpu=cpu["rtb"] / cpu["rikin"],
        )
    return out


def _proc_status_kib(field: str) -> int | None:
    """A ``/proc/self/status`` memory field (``VmHWM``, ``VmRSS``) in KiB, None off Linux."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def _peak_kib() -> tuple[int, str]:
    """This process's peak RSS so far, KiB, and how it was measured.

    ``VmHWM`` (the high-water mark of this process's own memory map) is
    preferred: ``ru_maxrss`` survives ``exec`` on Linux, so in a child it
    would start at the parent's RSS at the time of the fork.
    """
    hwm = _proc_status_kib("VmHWM")
    if hwm is not None:
        return hwm, "VmHWM of the child process (/proc/self/status)"
    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss), "ru_maxrss of the child"


def memory_child(n: int) -> None:
    """Run in a child process: print its peak RSS at three moments, as JSON (KiB)."""
    arm = rikin.robots.aula10_6r()
    arm.ik_batch(reachable_poses(arm, 100))  # warm up imports and caches
    after_import, how = _peak_kib()
    T = reachable_poses(arm, n)
    after_poses = _proc_status_kib("VmRSS") or _peak_kib()[0]
    res = arm.ik_batch(T)
    peak, _ = _peak_kib()
    print(
        json.dumps(
            {
                "n": n,
                "how": how,
                "after_import_kib": after_import,
                "before_batch_kib": after_poses,
                "peak_kib": peak,
                "output_bytes": res.q.nbytes + res.valid.nbytes,
                "input_bytes": T.nbytes,
            }
        )
    )


def bench_memory(n: int) -> dict[str, Any]:
    out = subprocess.run(
        [sys.executable, os.path.abspath(__file__), "--memory-child", str(n)],
        capture_output=True,
        text=True,
        check=True,
    )
    m = json.loads(out.stdout.strip().splitlines()[-1])
    mib = 1024.0
    return {
        "n": n,
        "method": m["how"],
        "peak_rss_mib": m["peak_kib"] / mib,
        "baseline_import_mib": m["after_import_kib"] / mib,
        "peak_minus_import_mib": (m["peak_kib"] - m["after_import_kib"]) / mib,
        "batch_increase_mib": (m["peak_kib"] - m["before_batch_kib"]) / mib,
        "input_mib": m["input_bytes"] / 2**20,
        "output_mib": m["output_bytes"] / 2**20,
    }


def _print_batch_table(rows: list[dict], sizes: list[int], info: dict) -> None:
    """The batch rows, each with its ratio to rikin's ik_batch at the largest N (added to
    the row as ``ratio_vs_batch``)."""
    ref = rows[len(sizes) - 1]["poses_per_s"]
    print(f"{'method':<62} {'N':>8} {'poses/s':>12} {'x slower':>9}  note")
    for r in rows:
        note = (
            f"{r['solutions_per_pose']:.2f} solutions/pose"
            if "solutions_per_pose" in r
            else f"success {100 * r['success_rate']:.0f}%"
        )
        if r.get("poses_per_cpu_s"):
            note += f"; {r['poses_per_cpu_s']:,.0f} poses per CPU-second"
        if "own_success_rate" in r:
            note += (
                f" (own flag {100 * r['own_success_rate']:.0f}%, max FK error "
                f"{r['max_fk_error']:.1e})"
            )
        print(
            f"{r['method']:<62} {r['n']:>8,} {r['poses_per_s']:>12,.0f} "
            f"{ref / r['poses_per_s']:>9.1f}  {note}"
        )
        r["ratio_vs_batch"] = ref / r["poses_per_s"]
    print(f"(x slower: rikin ik_batch at N = {sizes[-1]:,} poses/s divided by the method's)")
    load = load_average()
    if load is not None:
        print(
            f"(1-minute load average now {load:.2f} on {info['nproc']} CPUs: above ~0.5 other "
            "processes share the CPUs and the wall-clock figures drop)"
        )


def _print_single(single: list[dict], robot: object) -> None:
    """One pose at a time: rikin's arm.ik and (when timed) roboticstoolbox's analytic IK."""
    print(f"\none pose at a time ({single[0]['n']} seeded poses, best of 5 alternating rounds):")
    for r in single:
        print(
            f"  {r['arm']:<12} rikin arm.ik (all solutions, labelled, FK-checked) "
            f"{r['rikin_poses_per_s']:>9,.0f} poses/s, {r['rikin_poses_per_cpu_s']:>9,.0f} per "
            f"CPU-s ({r['rikin_solutions_per_pose']:.2f} solutions/pose)"
        )
        if "ratio" in r:
            print(
                f"  {r['arm']:<12} roboticstoolbox analytic_ik().solve             "
                f"{r['rtb_poses_per_s']:>9,.0f} poses/s, {r['rtb_poses_per_cpu_s']:>9,.0f} per "
                f"CPU-s ({r['rtb_solutions_per_pose']:.2f} solutions/pose; derivation "
                f"{r['rtb_derivation_s']:.1f} s)"
            )
            print(
                f"  {r['arm']:<12} ratio rikin / roboticstoolbox: {r['ratio']:.1f}x by wall "
                f"clock, {r['ratio_cpu']:.1f}x by CPU time"
            )
    if robot is None:
        print("  (roboticstoolbox analytic_ik not timed: not installed, or --quick)")
    load = load_average()
    if load is not None:
        print(f"  (1-minute load average now {load:.2f})")


def _report_memory(n_mem: int) -> dict:
    """ik_batch's peak memory for ``n_mem`` poses, measured in a child process; printed."""
    memory = bench_memory(n_mem)
    print(f"\nmemory, ik_batch of N = {n_mem:,} in a child process ({memory['method']}):")
    print(
        f"  peak RSS {memory['peak_rss_mib']:.0f} MiB; after importing numpy + rikin "
        f"{memory['baseline_import_mib']:.0f} MiB; peak minus that "
        f"{memory['peak_minus_import_mib']:.0f} MiB (input poses "
        f"{memory['input_mib']:.0f} MiB + output {memory['output_mib']:.0f} MiB + working "
        f"memory); rise during ik_batch (over the RSS just before it) "
        f"{memory['batch_increase_mib']:.0f} MiB"
    )
    return memory


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, for a smoke run")
    ap.add_argument("--json", metavar="PATH", help="also write the figures to this JSON file")
    ap.add_argument("--no-memory", action="store_true", help="skip the N = 1,000,000 memory run")
    ap.add_argument("--memory-child", type=int, metavar="N", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.memory_child:
        memory_child(args.memory_child)
        return 0

    if args.quick:
        sizes, n_loop, n_num, n_rtb, n_mem = [1_000, 5_000], 100, 10, 20, 20_000
    else:
        sizes, n_loop, n_num, n_rtb, n_mem = [1_000, 10_000, 100_000], 2_000, 200, 500, 1_000_000

    info = machine()
    print(
        f"machine: {info['nproc']} CPUs, {info['cpu']}; Python {info['python']}, "
        f"numpy {info['numpy']}, rikin {info['rikin']}"
    )
    arm = rikin.robots.aula10_6r()
    T = reachable_poses(arm, max(sizes))
    print(
        f"arm: {arm.name}; {len(T):,} seeded random reachable poses (FK of random q), seed {SEED}\n"
    )

    rows = bench_batch(arm, T, sizes)
    rows.append(bench_loop(arm, T, n_loop))
    rows.append(bench_numerical(arm, T, n_num))
    robot = rtb_robot(arm)
    if robot is None:
        print(
            "roboticstoolbox-python is missing (pip install roboticstoolbox-python): "
            "its ik_LM is not timed\n"
        )
    else:
        rows.append(bench_rtb(robot, arm, T, n_rtb, None))
        rows.append(bench_rtb(robot, arm, T, n_rtb, 1e-16))

    n_single = 100 if args.quick else 500
    single = [bench_single(arm, T[:n_single], robot if not args.quick else None)]
    c4 = rikin.robots.epson_c4()
    single.append(bench_single(c4, reachable_poses(c4, n_single), None))

    _print_batch_table(rows, sizes, info)
    _print_single(single, robot)

    memory = None if args.no_memory else _report_memory(n_mem)

    if args.json:
        with open(args.json, "w") as f:
            json.dump(
                {"machine": info, "seed": SEED, "results": rows, "single_pose": single,
                 "memory": memory},
                f,
                indent=2,
            )
        print(f"\nwrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
