"""All-solution IK of industrial 6R arms from their DH tables: rikin against roboticstoolbox.

For each arm (Puma 560, KUKA KR5 and IRB 140 from roboticstoolbox's own models; a KR6-like
and an IRB 120-like table; the Epson C4's modified table rewritten as standard DH), the
same seeded poses (FK of random joints, plus poses near the wrist singularity and near
full reach) are solved by

* rikin: ``arm.ik(T)`` of a ``SerialArm`` built from the DH table alone (the general
  closed form of :mod:`rikin.ik.pieper`; no derivation step), and
* roboticstoolbox 1.5: ``robot.analytic_ik()`` (a sympy derivation, timed apart) then
  ``.solve(T, joint_limits=False)`` per pose.

Printed per arm: solution sets of the regular poses compared modulo 2 pi (solutions one
finds that the other lacks, at 1e-9 rad, and both ways at 1e-6), the largest FK residual of
each over all poses (near-singular ones included), and poses/s of both with
their ratio, from one run. roboticstoolbox is optional (``pip install
"roboticstoolbox-python[ik]"``); without it only rikin's figures are printed.

    python benchmarks/bench_ik6r.py            # 1,000 poses per arm
    python benchmarks/bench_ik6r.py --poses 50 # a smoke run
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import rikin
from rikin import Link, SerialArm, robots

SEED = 20261201
pi = np.pi


def tables() -> dict[str, tuple[list[tuple[float, float, float, float]], np.ndarray]]:
    """DH rows ``(d, a, alpha, offset)`` (standard DH) and a tool, per arm not in rtb."""
    c4 = robots.epson_c4()
    # modified (alpha_{i-1}, a_{i-1}, d_i) -> standard (d_i, a_i, alpha_i) with a_i, alpha_i
    # read from link i+1: the same product of factors, grouped differently (base alpha0 = a0 = 0)
    mod = c4.links
    rows = []
    for i in range(6):
        nxt = mod[i + 1] if i < 5 else Link()
        rows.append((float(mod[i].d), float(nxt.a), float(nxt.alpha), float(mod[i].offset)))
    return {
        "KR6-like": ([(0.675, 0.26, -pi / 2, 0), (0, 0.68, 0, 0), (0, -0.035, pi / 2, -pi / 2),
                      (-0.67, 0, -pi / 2, 0), (0, 0, pi / 2, 0), (-0.115, 0, pi, 0)], np.eye(4)),
        "IRB 120-like": ([(0.29, 0, -pi / 2, 0), (0, 0.27, 0, -pi / 2), (0, 0.07, -pi / 2, 0),
                          (0.302, 0, pi / 2, 0), (0, 0, -pi / 2, 0), (0.072, 0, 0, pi)],
                         np.eye(4)),
        "Epson C4 (as standard DH)": (rows, np.asarray(c4.tool)),
    }


def arms(with_rtb: bool):
    """(name, rikin arm, rtb robot without base/tool or None)."""
    out = []
    if with_rtb:
        import roboticstoolbox as rtb

        for name, model in (("Puma 560", rtb.models.DH.Puma560()),
                            ("KUKA KR5", rtb.models.DH.KR5()),
                            ("ABB IRB 140", rtb.models.DH.IRB140())):
            links = tuple(Link(d=float(lk.d), a=float(lk.a), alpha=float(lk.alpha),
                               offset=float(lk.offset)) for lk in model.links)
            arm = SerialArm(links, base=model.base.A, tool=model.tool.A, name=name, units="m")
            bare = rtb.DHRobot([rtb.RevoluteDH(d=lk.d, a=lk.a, alpha=lk.alpha, offset=lk.offset)
                                for lk in model.links], name=name)
            out.append((name, arm, bare))
    for name, (rows, tool) in tables().items():
        links = tuple(Link(d=d, a=a, alpha=al, offset=o) for d, a, al, o in rows)
        arm = SerialArm(links, tool=tool, name=name)
        bare = None
        if with_rtb:
            import roboticstoolbox as rtb

            bare = rtb.DHRobot([rtb.RevoluteDH(d=d, a=a, alpha=al, offset=o)
                                for d, a, al, o in rows], name=name)
        out.append((name, arm, bare))
    return out


def poses(arm: SerialArm, n: int, rng: np.random.Generator) -> np.ndarray:
    """FK of random joints; a tenth each near the wrist singularity and near full reach."""
    q = rng.uniform(-pi, pi, (n, 6))
    k = n // 10
    q[:k, 4] = rng.choice([-1, 1], k) * 10.0 ** rng.uniform(-9, -4, k)  # q5 near 0
    # near full reach: joint 3 at the value that stretches the arm, found by search
    grid = np.linspace(-pi, pi, 3601)
    Q = np.zeros((grid.size, 6))
    Q[:, 2] = grid
    F = arm.fk(Q, frames=True)
    far = np.linalg.norm(F[:, 4, :3, 3] - F[:, 2, :3, 3], axis=1)
    q[k:2 * k, 2] = grid[int(np.argmax(far))] + rng.uniform(-1e-6, 1e-6, k)
    return arm.fk(q)


def missing(A: np.ndarray, B: np.ndarray, tol: float) -> int:
    """How many rows of A have no row of B within ``tol`` (max abs, modulo 2 pi)."""
    if len(A) == 0:
        return 0
    if len(B) == 0:
        return len(A)
    d = np.abs(rikin.wrap_angle(A[:, None, :] - B[None, :, :])).max(-1)
    return int((d.min(axis=1) > tol).sum())


def residual(arm: SerialArm, q: np.ndarray, T: np.ndarray) -> float:
    if len(q) == 0:
        return 0.0
    F = arm.fk(q, check_degrees=False)
    pos = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1).max() / arm.scale
    return float(max(pos, np.abs(F[:, :3, :3] - T[:3, :3]).max()))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=1000)
    args = ap.parse_args()
    try:
        import roboticstoolbox  # noqa: F401

        with_rtb = True
    except ImportError:
        with_rtb = False
        print("roboticstoolbox not installed: rikin's figures only")
    print(f"load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs, {args.poses} poses/arm")
    head = (f"{'arm':<27}{'rtb derive s':>13}{'rikin/s':>9}{'rtb/s':>8}{'ratio':>7}"
            f"{'rikin-only':>11}{'rtb-only':>9}{'(1e-6)':>8}{'rikin res':>10}{'rtb res':>9}")
    print(head)
    rng = np.random.default_rng(SEED)
    for name, arm, bare in arms(with_rtb):
        Ts = poses(arm, args.poses, rng)
        t0 = time.perf_counter()
        sols = []
        for T in Ts:
            try:
                sols.append(arm.ik(T).q)
            except rikin.UnreachableError:
                sols.append(np.zeros((0, 6)))
        t_rikin = time.perf_counter() - t0
        res_r = max(residual(arm, q, T) for q, T in zip(sols, Ts, strict=True))
        line = f"{name:<27}"
        if bare is None:
            print(line + f"{'':>13}{args.poses / t_rikin:>9.0f}{'':>8}{'':>7}{'':>11}{'':>9}"
                  f"{'':>8}{res_r:>10.1e}")
            continue
        t0 = time.perf_counter()
        ik = bare.analytic_ik()
        t_derive = time.perf_counter() - t0
        base_inv, tool_inv = np.linalg.inv(arm.base), np.linalg.inv(arm.tool)
        flange = base_inv @ Ts @ tool_inv
        t0 = time.perf_counter()
        rtb_sols = [np.atleast_2d(ik.solve(F, joint_limits=False).q).reshape(-1, 6) for F in flange]
        t_rtb = time.perf_counter() - t0
        # the regular poses only (the first fifth are near a singularity by construction,
        # where the pose fixes some joints only loosely and the sets are not comparable)
        k = args.poses // 5
        pairs = list(zip(sols[k:], rtb_sols[k:], strict=True))
        only_r = sum(missing(a, b, 1e-9) for a, b in pairs)
        only_t = sum(missing(b, a, 1e-9) for a, b in pairs)
        loose = sum(missing(a, b, 1e-6) + missing(b, a, 1e-6) for a, b in pairs)
        res_t = max(residual(arm, q, T) for q, T in zip(rtb_sols, Ts, strict=True))
        r_rate, t_rate = args.poses / t_rikin, args.poses / t_rtb
        print(line + f"{t_derive:>13.1f}{r_rate:>9.0f}{t_rate:>8.0f}{r_rate / t_rate:>7.2f}"
              f"{only_r:>11}{only_t:>9}{loose:>8}{res_r:>10.1e}{res_t:>9.1e}")


if __name__ == "__main__":
    main()
