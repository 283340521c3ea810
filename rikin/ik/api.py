"""``solve`` and ``solve_batch``: the public IK entry points behind ``arm.ik``.

They read the target, remove base and tool, call the arm family's kernel,
then wrap, de-duplicate, label, check every solution by FK, and on request
filter by joint limits and sort by distance to previous joints.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np

from .. import dh
from .._validate import (
    FloatArray,
    _rotation_errors,
    as_flag,
    as_float_array,
    as_pose,
    check_distances,
    check_length_range,
    check_radians,
    clean_pose,
    clean_poses,
)
from ..dh import SerialArm
from ..errors import InputError, UnreachableError
from ..tolerances import (
    FK_CHECK_TOL,
    MAX_DISTANCE_RATIO,
    MAX_LENGTH,
    ROTATION_CLEAN_TOL,
    SAME_SOLUTION_TOL,
)
from ..transforms import _wrap_angle, homogeneous, rotz
from .base import RawSolutions, Solver
from .families6r import solver_for
from .fkcheck import FKCheck
from .kernels import pose_defects
from .result import BatchIKResult, Branch, IKResult, root_names

__all__ = ["solve", "solve_batch", "ClosedForm"]


def _register() -> None:
    """Give rikin.dh its IK entry points without dh importing ik (data flows dh -> ik)."""
    dh._IK_ENTRY.update(solve=solve, solve_batch=solve_batch)


class ClosedForm:
    """The IK entry points every closed-form solver offers (``arm.ik`` calls them)."""

    def ik(self, arm: SerialArm, target: Any, **options: Any) -> IKResult:
        """:func:`solve` for ``arm``."""
        return solve(arm, target, **options)

    def ik_batch(self, arm: SerialArm, T: Any, **options: Any) -> BatchIKResult:
        """:func:`solve_batch` for ``arm``."""
        return solve_batch(arm, T, **options)


def _count(value: Any, name: str) -> int:
    """A positive whole number (not a bool, not a float)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{name} must be a positive whole number, got {value!r}")
    if value < 1:
        raise InputError(f"{name} must be a positive whole number, got {value}")
    return int(value)

_KIND_HELP = {
    "pose": "a 4x4 homogeneous transform (the TCP pose in the world frame)",
    "position": "a position (x, y, z) or a 4x4 pose whose position is used",
    "planar_pose": "(x, y, phi) with phi the tool angle in radians, or a 4x4 pose in the xy plane",
    "planar_position": "(x, y) or a 4x4 pose in the xy plane whose position is used",
}


def _solver(arm: Any) -> Solver:
    """The arm's own solver (lesson robots), else the first family that takes its table
    (:func:`rikin.ik.families6r.solver_for`: the course families, then the 6R families;
    raises if none does)."""
    if not isinstance(arm, SerialArm):
        raise InputError(f"arm must be a rikin.SerialArm, got {type(arm).__name__}")
    if arm.solver is not None:
        return arm.solver
    # kept on the (immutable) arm: the registry's lookup hashes the whole table, which
    # cost a general 6R's arm.ik a twentieth of its time
    solver = arm.__dict__.get("_family_solver")
    if solver is None:
        solver = solver_for(arm)
        object.__setattr__(arm, "_family_solver", solver)
    return solver


def _target_pose(arm: SerialArm, target: Any, kind: str) -> tuple[FloatArray, float]:
    """The target as a world pose ``(4, 4)``, validated, and how far its rotation block was
    from a rotation (Frobenius norm; 0 when it was one to rounding, or when no 4x4 was given).

    A block within ``ORTHONORMAL_TOL`` of a rotation (rounded, float32) is replaced by the
    nearest rotation, which IK then solves for.
    """
    arr = as_float_array(target, "target")
    if kind in ("position", "planar_position") and arm.tool[:3, 3].any():
        raise InputError(
            f"{arm.name!r} solves for a position only, so its tool may rotate but not offset the "
            "TCP (the offset would depend on an orientation the arm does not choose); use a tool "
            "without translation"
        )
    if arr.shape == (4, 4):
        return clean_pose(as_pose(arr, "target"))
    if kind == "position" and arr.shape == (3,):
        _check_position(arr)
        return homogeneous(None, arr), 0.0
    if kind == "planar_pose" and arr.shape == (3,):
        _check_position(arr[:2])
        check_radians(arr[2:], "phi", ["phi (the tool angle, target[2])"])
        return homogeneous(rotz(arr[2]), np.array([arr[0], arr[1], 0.0])), 0.0
    if kind == "planar_position" and arr.shape == (2,):
        _check_position(arr)
        return homogeneous(None, np.array([arr[0], arr[1], 0.0])), 0.0
    raise InputError(f"{arm.name!r} takes as target {_KIND_HELP[kind]}; got shape {arr.shape}")


def _check_position(p: FloatArray) -> None:
    big = float(np.abs(p).max(initial=0.0))
    if big > MAX_LENGTH:
        check_length_range(big, "target")


def _wrap(q: FloatArray, revolute: FloatArray) -> FloatArray:
    return np.where(revolute, _wrap_angle(q), q)


def _fk_error(arm: SerialArm, q: FloatArray, T: FloatArray, kind: str) -> FloatArray:
    """Per-solution error of FK(q) against T: max of the position error (relative to the
    arm's size, its tool's length included; never to the target's distance, which would let
    a far target's rounding pass for an answer) and the rotation error."""
    F = arm._fk(q)
    size = arm.scale + float(np.linalg.norm(arm.tool[:3, 3]))
    pos = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=-1) / size
    if kind in ("position", "planar_position"):
        return pos
    rot = np.abs(F[:, :3, :3] - T[:3, :3]).max(axis=(-1, -2))
    return np.maximum(pos, rot)


def _fk_miss(arm: SerialArm, q: FloatArray, T: FloatArray, kind: str) -> float | None:
    """None when every solution ``q (k, n)`` reaches ``T`` by FK within ``FK_CHECK_TOL``
    (:func:`_fk_error`), else the largest miss. An all-revolute arm's pose is checked first
    by :class:`FKCheck` (the one-pose path's check: stricter, in fewer numpy calls, kept on
    the immutable arm); only where that is not met is every solution's error computed."""
    if kind == "pose" and len(q) and bool(np.all(arm.revolute)):
        check = arm.__dict__.get("_fk_check")
        if check is None:
            check = FKCheck(arm)
            object.__setattr__(arm, "_fk_check", check)
        if check(q, T) <= _FK_CHECK_TOL2:
            return None
    err = _fk_error(arm, q, T, kind)
    return float(err.max()) if np.any(err > FK_CHECK_TOL) else None


def _limits_filter(
    q: FloatArray, arm: SerialArm, near: FloatArray | None
) -> tuple[FloatArray, np.ndarray]:
    """Move each revolute value to an in-limit 2*pi equivalent; mask the rows that fit."""
    lim = arm.qlim
    out = q.copy()
    keep = np.ones(len(q), dtype=bool)
    shifts = 2 * np.pi * np.arange(-2, 3)
    for i, row in enumerate(q):
        for j, v in enumerate(row):
            lo, hi = lim[j]
            if not arm.links[j].is_revolute:
                keep[i] &= bool(lo - SAME_SOLUTION_TOL <= v <= hi + SAME_SOLUTION_TOL)
                continue
            cands = v + shifts
            ok = cands[(cands >= lo - SAME_SOLUTION_TOL) & (cands <= hi + SAME_SOLUTION_TOL)]
            if ok.size == 0:
                keep[i] = False
                break
            ref = near[j] if near is not None else v
            out[i, j] = ok[np.argmin(np.abs(ok - ref))]
    return out, keep


def _dedupe(q: FloatArray, revolute: FloatArray) -> list[int]:
    """Indices of the rows to keep: the first of each group equal modulo 2*pi."""
    diff = np.abs(_wrap(q[:, None, :] - q[None, :, :], revolute)).max(axis=-1)
    same = (diff <= SAME_SOLUTION_TOL).tolist()
    kept: list[int] = []
    for i in range(len(q)):
        if not any(same[i][j] for j in kept):
            kept.append(i)
    return kept


def solve(
    arm: SerialArm, target: Any, *, within_limits: bool = False, near: Any = None
) -> IKResult:
    """Every closed-form IK solution of ``target``, each labelled with its branch.

    Parameters
    ----------
    arm : SerialArm
        An arm built by :mod:`rikin.robots` (it carries its family's solver).
    target : array_like
        A 4x4 TCP pose in the world frame, or what the family takes instead:
        a position ``(3,)`` for position-only arms, ``(x, y, phi)`` for the
        planar 3R, ``(x, y)`` for the planar 2R. Lengths in ``arm.units``,
        angles in radians.
    within_limits : bool
        Keep only solutions inside the joint limits, moving revolute values
        to an in-limit ``+-2*pi`` equivalent where one exists.
    near : array_like, shape (n,), optional
        Previous joint values: solutions are sorted by distance to them, and
        at a singularity the free joints take their values from here.

    Returns
    -------
    IKResult
        ``q`` of shape ``(k, n)``; every row reproduces the target by FK.

    Raises
    ------
    UnreachableError
        The target is outside the workspace; the message says why and by how much.
    InputError
        Malformed target or ``near``.
    """
    if isinstance(arm, SerialArm) and arm.reversed_joints:
        return _solve_reversed(arm, target, within_limits, near)
    if near is None and within_limits is False and type(target) is np.ndarray:
        # the one-pose fast path, looked up once per arm (arms are immutable) and first,
        # before _solver: finding a table's general solver costs as much as a tenth of a pose
        fast_path = None
        if isinstance(arm, SerialArm):
            fast_path = arm.__dict__.get("_single_kernel", False)
        if fast_path is False:
            single = getattr(_solver(arm), "single_kernel", None)
            kernel = single(arm) if single is not None else None
            fast_path = None if kernel is None else (kernel, FKCheck(arm))
            object.__setattr__(arm, "_single_kernel", fast_path)
        if fast_path is not None:
            kernel, fk_check = fast_path
            fast = _solve_regular(arm, kernel, fk_check, target)
            if fast is not None:
                return fast
    solver = _solver(arm)
    kind = solver.target_kind
    within_limits = as_flag(within_limits, "within_limits")
    T_world, rot_dist = _target_pose(arm, target, kind)
    hint = None if near is None else arm.check_q(near, "near")
    if hint is not None and hint.ndim != 1:
        raise InputError(f"near must have shape ({arm.n},), got shape {hint.shape}")
    if kind in ("position", "planar_position"):  # the target's rotation plays no part
        T_world = homogeneous(None, T_world[:3, 3])
    _check_distances(arm, T_world[None, :3, 3], "target")
    T_0_n = arm._world_to_base(T_world)
    raw = solver.solve(arm, T_0_n[None], hint)
    raw, T_solved, reach = _onto_reach(arm, solver, T_world[None], raw, hint)
    valid = raw.valid[0]
    if not valid.any():
        raise _unreachable(arm, solver, T_0_n)
    return _finish(
        arm, solver, raw, T_solved[0], kind, hint, within_limits, rot_dist, float(reach[0])
    )


def _check_distances(arm: SerialArm, P: FloatArray, name: str, first: int = 0) -> None:
    """InputError when the targets' positions ``P (N, 3)`` (world frame; ``name[first + i]``
    in messages), the base or the tool lie so far off that double precision cannot resolve
    the arm there (see ``MAX_DISTANCE_RATIO``)."""
    size = arm.scale
    if not arm.__dict__.get("_frames_checked", False):  # once per (immutable) arm
        check_distances(arm.base[None, :3, 3], size, "the arm's base")
        check_distances(arm.tool[None, :3, 3], size, "the tool's offset", "the flange")
        object.__setattr__(arm, "_frames_checked", True)
    if len(P) == 1 and not first:
        check_distances(P, size, name)
        return
    try:
        check_distances(P, size, name)
    except InputError:  # name the pose in the whole batch
        i = int(np.argmax(np.linalg.norm(P, axis=-1) > MAX_DISTANCE_RATIO * size))
        check_distances(P[i : i + 1], size, f"{name}[{first + i}]")
        raise


def _solve_reversed(arm: SerialArm, target: Any, within_limits: Any, near: Any) -> IKResult:
    """:func:`solve` for an arm with reversed joints: its DH twin solves (in DH joint
    values, ``directions * q``), and the solutions come back as the data sheet counts
    them, then meet the data sheet's limits and ``near``."""
    within_limits = as_flag(within_limits, "within_limits")
    hint = None if near is None else arm.check_q(near, "near")
    if hint is not None and hint.ndim != 1:
        raise InputError(f"near must have shape ({arm.n},), got shape {hint.shape}")
    s = arm.directions
    res = solve(arm._dh, target, near=None if hint is None else hint * s)
    q = _wrap(res.q * s, arm.revolute)
    q, branches, discarded = _select(arm, q, list(res.branches), hint, within_limits)
    return replace(res, q=q, branches=tuple(branches), discarded=discarded,
                   directions=arm.directions)


def _select(
    arm: SerialArm, q: FloatArray, branches: list[Branch], hint: FloatArray | None,
    within_limits: bool,
) -> tuple[FloatArray, list[Branch], int]:
    """The solutions ``q (k, n)`` that meet the joint limits (moved to an in-limit ``2 pi``
    equivalent) when ``within_limits``, sorted by distance to ``hint`` when given; and how
    many the limits removed."""
    discarded = 0
    if within_limits:
        q, fits = _limits_filter(q, arm, hint)
        discarded = int((~fits).sum())
        q = q[fits]
        branches = [b for b, f in zip(branches, fits, strict=True) if f]
    if hint is not None and len(q):
        diff = q - hint
        diff = diff if within_limits else _wrap(diff, arm.revolute)
        order = list(np.argsort(np.linalg.norm(diff, axis=1), kind="stable"))
        q = q[order]
        branches = [branches[i] for i in order]
    return q, branches, discarded


def _unreachable(arm: SerialArm, solver: Solver, T_0_n: FloatArray) -> UnreachableError:
    """The error for a target ``T_0_n (4, 4)`` (base frame) the solver found no solution of:
    why, in the arm's terms, and by how much (``excess``, in ``arm.units``)."""
    message, excess = solver.explain(arm, T_0_n)
    units = arm.units if np.isfinite(excess) else ""
    return UnreachableError(
        f"{arm.name}: target is unreachable: {message}", excess=excess, units=units
    )


def _onto_reach(
    arm: SerialArm,
    solver: Solver,
    T_world: FloatArray,
    raw: RawSolutions,
    hint: FloatArray | None,
) -> tuple[RawSolutions, FloatArray, FloatArray]:
    """Solve again, for their nearest reachable pose, the poses ``T_world (N, 4, 4)`` with no
    solution that the arm misses by rounding only (``ROUNDED_POSE_TOL``).

    Returns ``raw`` (those poses' rows replaced), the poses solved ``(N, 4, 4)``, and how far
    each given pose was from reachable ``(N,)`` (0 where it was solved as given). Solvers
    without ``nearest_reachable`` pass through unchanged.
    """
    reach = np.zeros(len(T_world))
    nearest = getattr(solver, "nearest_reachable", None)
    if nearest is None:
        return raw, T_world, reach
    miss = np.flatnonzero(~raw.valid.any(axis=1))
    if not miss.size:
        return raw, T_world, reach
    T_near, dist, close = nearest(arm, T_world[miss])
    fix = miss[close]
    if not fix.size:
        return raw, T_world, reach
    again = solver.solve(arm, arm._world_to_base(T_near[close]), hint)
    for name in ("q", "valid", "elbow_up", "shoulder_front"):
        mine = getattr(raw, name)
        if mine is not None:
            mine = np.array(mine)  # a copy: solvers may hand back read-only broadcasts
            mine[fix] = getattr(again, name)
            setattr(raw, name, mine)
    for name, mask in raw.singular.items():
        mask = np.array(mask)
        mask[fix] = again.singular[name]
        raw.singular[name] = mask
    T_solved = T_world.copy()
    T_solved[fix] = T_near[close]
    reach[fix] = dist[close]
    return raw, T_solved, reach


def _solve_regular(
    arm: SerialArm, kernel: Any, fk_check: FKCheck, target: FloatArray
) -> IKResult | None:
    """The whole of :func:`solve` for one regular pose, with the plain-float kernel.

    Returns None (the caller takes the general path, which validates, explains and
    handles singularities) unless ``target`` is a float64 4x4 pose that passes every
    check of the general path exactly, lies away from every singularity, and its
    solutions pass :class:`FKCheck`, which is the general path's FK check or stricter.
    """
    if target.shape != (4, 4) or target.dtype != np.float64:
        return None
    rows = target.tolist()
    r0, r1, r2 = rows[0], rows[1], rows[2]
    if rows[3] != [0.0, 0.0, 0.0, 1.0]:
        return None
    # written so that NaN fails every test: a NaN or inf entry makes err NaN or inf
    err, det = _rotation_errors(r0, r1, r2)
    if not (err <= ROTATION_CLEAN_TOL and det > 0.0):
        return None
    if not (abs(r0[3]) <= MAX_LENGTH and abs(r1[3]) <= MAX_LENGTH and abs(r2[3]) <= MAX_LENGTH):
        return None
    out = kernel.solve(rows)
    if out is None:
        return None
    flat, branches = out
    q = np.fromiter(flat, np.float64, len(flat)).reshape(-1, 6)  # no type inference
    if not fk_check(q, target) <= _FK_CHECK_TOL2:  # every solution: see FKCheck
        return None  # the general path checks again and reports
    return IKResult._regular(q, tuple(branches), target, arm)


_FK_CHECK_TOL2 = FK_CHECK_TOL * FK_CHECK_TOL


def _finish(
    arm: SerialArm,
    solver: Solver,
    raw: RawSolutions,
    T_world: FloatArray,
    kind: str,
    hint: FloatArray | None,
    within_limits: bool,
    rot_dist: float,
    reach_dist: float = 0.0,
) -> IKResult:
    rev = arm.revolute
    slots = np.flatnonzero(raw.valid[0])
    q = _wrap(raw.q[0, slots], rev)
    masks = {name: m[0, slots] for name, m in raw.singular.items()}
    keep = np.ones(len(slots), dtype=bool)
    for name, m in masks.items():
        spec = solver.singularities[name]
        if spec.drop_back:
            keep &= ~(m & np.array([raw.slots[s].shoulder == "back" for s in slots]))
        if spec.drop_flip:
            keep &= ~(m & np.array([raw.slots[s].wrist == "flip" for s in slots]))
    if not keep.any():  # never drop everything: fall back to the first slot
        keep[0] = True
    slots, q = slots[keep], q[keep]
    masks = {name: m[keep] for name, m in masks.items()}
    order = _dedupe(q, rev)
    slots, q = slots[order], q[order]
    masks = {name: m[order] for name, m in masks.items()}
    active = [name for name, m in masks.items() if m.any()]
    specs = [solver.singularities[name] for name in active]

    branches, in_order = _branches(solver, raw, q, slots, masks.get("wrist"))
    if in_order is not None:
        q, branches = q[in_order], [branches[i] for i in in_order]
    miss = _fk_miss(arm, q, T_world, kind)
    if miss is not None:  # a bug in rikin: never hand back a wrong answer
        raise RuntimeError(
            f"rikin bug: IK of {arm.name} produced a solution whose FK misses the target by "
            f"{miss:.3g} (relative); please report it with the target pose"
        )

    q, branches, discarded = _select(arm, q, branches, hint, within_limits)

    free = tuple(sorted({j for spec in specs for j in spec.free_joints}))
    return IKResult(
        q=q,
        branches=tuple(branches),
        target=T_world,
        singular=bool(specs),
        singularity="; ".join(spec.description for spec in specs) or None,
        free_joints=free,
        discarded=discarded,
        arm_name=arm.name,
        revolute=rev,
        rotation_distance=rot_dist,
        reach_distance=reach_dist,
        directions=arm.directions,
    )


def _branches(solver: Solver, raw: RawSolutions, q: FloatArray, slots: np.ndarray,
              wrist_singular: np.ndarray | None) -> tuple[list[Branch], list[int] | None]:
    """The branch of each solution ``q[i]`` (of pose 0's slot ``slots[i]`` in ``raw``):
    the slot's, with the elbow and shoulder the solver computed, the wrist flip from the
    middle wrist joint (or the slot's, for a solver with ``wrist_from_slot``), and, for a
    solver that numbers its solutions by a polynomial's roots (``root_joint``: the joint,
    ``root_grouped``: whether solutions share roots), the root. Returns the branches in
    the order of ``q``, and the order to list them in (root order; None: as they are).
    ``arm.ik`` and :meth:`BatchIKResult.labels` both label by this function."""
    mid = solver.wrist_middle
    from_slot = getattr(solver, "wrist_from_slot", False)
    branches = []
    for i, (row, s) in enumerate(zip(q, slots, strict=True)):
        elbow = raw.slots[s].elbow
        if raw.elbow_up is not None:
            elbow = "up" if raw.elbow_up[0, s] else "down"
        wrist = raw.slots[s].wrist if from_slot else None
        if wrist_singular is not None and wrist_singular[i] and (from_slot or mid is not None):
            wrist = "singular"
        elif mid is not None:
            wrist = "no-flip" if np.sin(row[mid]) >= 0 else "flip"
        shoulder = raw.slots[s].shoulder
        if raw.shoulder_front is not None:
            shoulder = "front" if raw.shoulder_front[0, s] else "back"
        branches.append(Branch(shoulder, elbow, wrist))
    j = getattr(solver, "root_joint", None)
    if j is None:
        return branches, None
    key = np.roll(_wrap_angle(q), -j, axis=1)
    names, order = root_names(key, bool(getattr(solver, "root_grouped", False)))
    return [b._replace(root=r) for b, r in zip(branches, names, strict=True)], order


def _slot_branches(arm: SerialArm, solver: Solver, slots: tuple[Branch, ...]
                   ) -> tuple[Branch, ...]:
    """:attr:`BatchIKResult.branches`: each slot's branch with None where :func:`_branches`
    takes that field from the pose rather than the slot (the elbow and shoulder a solver
    computes, the wrist from the middle wrist joint), so that no slot claims a branch its
    solution may not have. Kept on the (immutable) arm."""
    kept = arm.__dict__.get("_batch_branches")
    if kept is not None and kept[0] is solver and kept[1] == slots:
        return cast(tuple[Branch, ...], kept[2])
    raw = solver.solve(arm, arm._world_to_base(np.eye(4))[None], None)
    changes: dict[str, None] = {}
    if raw.elbow_up is not None:
        changes["elbow"] = None
    if raw.shoulder_front is not None:
        changes["shoulder"] = None
    if solver.wrist_middle is not None and not getattr(solver, "wrist_from_slot", False):
        changes["wrist"] = None
    honest = tuple(b._replace(**changes) for b in slots)
    object.__setattr__(arm, "_batch_branches", (solver, slots, honest))
    return honest


@dataclass(frozen=True)
class _PoseLabels:
    """:attr:`BatchIKResult.labeller`: the branches of one pose's batch solutions, as
    ``arm.ik`` labels them, by :func:`_branches`: from the joint rows, where the solver
    offers ``label_rows`` and the pose is regular; else on the solver's labelled solve
    of that pose, each batch solution taking the slot whose joints are nearest its own.

    ``arm`` is the arm solved (a reversed arm's DH twin), ``Tw (N, 4, 4)`` the batch's world
    poses, ``slots`` its slots as the solver gives them, ``singular (N,)`` its singular
    poses, ``directions`` (+-1 per joint) turn the batch's joints into ``arm``'s.
    """

    arm: SerialArm
    solver: Solver
    Tw: FloatArray
    slots: tuple[Branch, ...]
    singular: np.ndarray
    directions: FloatArray | None = None

    def __call__(self, i: int, q: FloatArray, slots: np.ndarray) -> list[Branch]:
        """The branches of pose ``i``'s solutions ``q (m, n)`` (of the batch's ``slots``)."""
        arm, solver = self.arm, self.solver
        if self.directions is not None:
            q = _wrap(q * self.directions, arm.revolute)
        label_rows = getattr(solver, "label_rows", None)
        if label_rows is not None and not self.singular[i]:
            front, up = label_rows(q)
            raw = RawSolutions(
                q=q[None], valid=np.ones((1, len(q)), dtype=bool),
                slots=tuple(self.slots[s] for s in slots),
                elbow_up=None if up is None else up[None],
                shoulder_front=None if front is None else front[None])
            return _branches(solver, raw, q, np.arange(len(q)), None)[0]
        T_world, _ = _target_pose(arm, self.Tw[i], "pose")
        raw = solver.solve(arm, arm._world_to_base(T_world)[None], None)
        raw, _, _ = _onto_reach(arm, solver, T_world[None], raw, None)
        gap = np.abs(_wrap(raw.q[0][None] - q[:, None], arm.revolute)).max(axis=-1)
        gap = np.where(raw.valid[0][None] & np.isfinite(gap), gap, np.inf)
        near = gap.argmin(axis=1)
        wrist = raw.singular.get("wrist")
        branches, _ = _branches(solver, raw, q, near, None if wrist is None else wrist[0, near])
        return branches


def solve_batch(
    arm: SerialArm, T: Any, *, chunk_size: int = 4096, workers: int | None = None
) -> BatchIKResult:
    """All IK solutions of N poses, vectorised, in fixed branch slots.

    Memory stays bounded: poses are validated and solved ``chunk_size`` at a
    time (in ``workers`` threads; numpy releases the GIL), and only the output
    ``(N, k, n)`` grows with N.

    Parameters
    ----------
    arm : SerialArm
    T : array_like, shape (N, 4, 4)
        TCP poses in the world frame.
    chunk_size : int
        Poses per chunk at most; the default keeps a chunk's temporaries in
        the cache. Chunks are evened out so that every thread gets as many.
    workers : int, optional
        Threads; defaults to the number of CPUs (at most 4).

    Returns
    -------
    BatchIKResult
        ``q (N, k, n)`` with NaN in invalid slots, ``valid (N, k)``,
        ``singular (N,)``, ``rotation_distance (N,)``, ``reach_distance (N,)``.
        No de-duplication, no FK check; ``labels(i)`` names pose i's solutions as
        ``arm.ik`` does, when asked (``branches``: what each slot fixes). A
        pose whose rotation block is not a rotation to rounding (but within
        ``ORTHONORMAL_TOL``) is solved for the nearest rotation, and a pose the
        arm misses by rounding (within ``ROUNDED_POSE_TOL``: a 5-DOF arm's
        wrist centre off the set it reaches, a stretched arm's beyond its reach)
        for the nearest reachable pose, as :func:`solve` does.

    Raises
    ------
    InputError
        ``T`` is not an ``(N, 4, 4)`` array of homogeneous transforms (the same
        checks and messages as a single pose), or bad ``chunk_size``/``workers``.
    """
    if isinstance(arm, SerialArm) and arm.reversed_joints:
        res = solve_batch(arm._dh, T, chunk_size=chunk_size, workers=workers)
        labeller = replace(cast(_PoseLabels, res.labeller), directions=arm.directions)
        return replace(res, q=_wrap(res.q * arm.directions, arm.revolute), labeller=labeller)
    solver = _solver(arm)
    chunk_size = _count(chunk_size, "chunk_size")
    if workers is not None:
        workers = _count(workers, "workers")
    batch = _Batch(arm, solver, _batch_poses(T))
    n_workers = workers if workers is not None else min(4, os.cpu_count() or 1)
    size = _chunk_length(batch.N, chunk_size, n_workers)
    starts = range(0, batch.N, size)
    if n_workers <= 1 or len(starts) <= 1:
        for st in starts:
            batch.solve_chunk(st, min(st + size, batch.N))
    else:
        with ThreadPoolExecutor(n_workers) as pool:
            list(pool.map(lambda st: batch.solve_chunk(st, min(st + size, batch.N)), starts))
    batch.solve_deferred(size)
    return batch.result()


class _Batch:
    """One :func:`solve_batch` call: its arm, solver and checked world poses ``Tw (N, 4, 4)``,
    the output arrays, and how a chunk of poses fills its rows of them (chunks fill disjoint
    rows, so threads share one ``_Batch``)."""

    def __init__(self, arm: SerialArm, solver: Solver, Tw: FloatArray) -> None:
        self.arm, self.solver, self.Tw = arm, solver, Tw
        self.N = N = Tw.shape[0]
        make_kernel = getattr(solver, "batch_kernel", None)
        self.kernel = make_kernel(arm) if make_kernel is not None else None
        slots = self.kernel.slots if self.kernel is not None else getattr(solver, "slots", None)
        if slots is None:  # the slots of this family: solve one pose
            slots = solver.solve(arm, arm._world_to_base(np.eye(4))[None], None).slots
        self.slots = slots
        k = len(slots)
        self.q = np.empty((N, k, arm.n))
        self.valid = np.empty((N, k), dtype=bool)
        self.singular = np.zeros(N, dtype=bool)
        self.rotation_distance = np.zeros(N)
        self.reach_distance = np.zeros(N)
        self.rounds_onto_reach = hasattr(solver, "nearest_reachable")
        #: The rows the batch kernel left to the general solver, and their (cleaned) poses,
        #: chunk by chunk (list.append is atomic: the threads share the list)
        self.deferred: list[tuple[np.ndarray, FloatArray]] = []

    def solve_chunk(self, start: int, stop: int) -> None:
        """Rows ``start:stop``: the batch kernel where the family has one (the poses it
        flags as suspect, and those it finds no solution of when rounding may have put them
        beyond the reach, are left to :meth:`solve_deferred`), else the general solver."""
        T_chunk, X = self._clean_chunk(start, stop)
        if self.kernel is None:
            self.general(slice(start, stop), T_chunk)
            return
        q, valid, suspect = self.kernel.solve(X)
        self.q[start:stop] = q.transpose(2, 0, 1)
        self.valid[start:stop] = valid.T
        if self.rounds_onto_reach:  # no solution: maybe rounded beyond the reach
            suspect = suspect | ~valid.any(axis=0)
        redo = np.flatnonzero(suspect)
        if redo.size:
            self.deferred.append((start + redo, T_chunk[redo]))

    def solve_deferred(self, size: int) -> None:
        """The poses the batch kernel left over, on the general solver, at most ``size`` per
        call. Once for the whole batch rather than once per chunk: a call of the general
        solver costs some milliseconds of Python whether it has one pose or fifty (0.2-0.4%
        of random poses are left over), and it solves each pose as alone."""
        if not self.deferred:
            return
        rows = np.concatenate([r for r, _ in self.deferred])
        T = np.concatenate([t for _, t in self.deferred])
        self.deferred = []
        for st in range(0, rows.size, size):
            self.general(rows[st:st + size], T[st:st + size])

    def _clean_chunk(self, start: int, stop: int) -> tuple[FloatArray, FloatArray]:
        """The chunk's poses checked (rigid, within the distances rikin handles) and rounded
        rotations made rotations (their distances recorded): ``T_chunk (n, 4, 4)`` and the
        same as ``X (4, 4, n)``, the kernels' layout."""
        T_chunk = self.Tw[start:stop]
        X = np.ascontiguousarray(T_chunk.transpose(1, 2, 0))  # (4, 4, n)
        valid_poses, defect = pose_defects(X)
        if not valid_poses:
            as_pose(self.Tw, "T")  # raises with the detailed message
            raise AssertionError("rikin bug: pose_defects and as_pose disagree")
        _check_distances(self.arm, T_chunk[:, :3, 3], "T", start)
        if defect.max(initial=0.0) > ROTATION_CLEAN_TOL:  # rounded poses: nearest rotations
            T_chunk = T_chunk.copy()
            self.rotation_distance[start:stop] = clean_poses(T_chunk, defect)
            X = np.ascontiguousarray(T_chunk.transpose(1, 2, 0))
        return T_chunk, X

    def general(self, rows: slice | np.ndarray, T_chunk: FloatArray) -> None:
        """The general solver (every family; exact singular handling) for some poses."""
        arm, solver = self.arm, self.solver
        T_0_n = arm._world_to_base(T_chunk)
        if getattr(solver, "labels_optional", False):
            raw = cast(Any, solver).solve(arm, T_0_n, None, labels=False)
        else:
            raw = solver.solve(arm, T_0_n, None)
        raw, _, reach = _onto_reach(arm, solver, T_chunk, raw, None)
        self.reach_distance[rows] = reach
        qq = _wrap(raw.q, arm.revolute)
        qq[~raw.valid] = np.nan
        self.q[rows] = qq
        self.valid[rows] = raw.valid
        s = np.zeros(len(qq), dtype=bool)
        for mask in raw.singular.values():
            s |= (mask & raw.valid).any(axis=1)
        self.singular[rows] = s

    def result(self) -> BatchIKResult:
        """The filled arrays as a :class:`BatchIKResult`."""
        return BatchIKResult(
            q=self.q,
            valid=self.valid,
            singular=self.singular,
            branches=_slot_branches(self.arm, self.solver, self.slots),
            rotation_distance=self.rotation_distance,
            reach_distance=self.reach_distance,
            # the poses copied: labels(i) may solve pose i again after the caller's array changed
            labeller=_PoseLabels(self.arm, self.solver, self.Tw.copy(), self.slots, self.singular),
        )


#: Below this many poses per chunk, splitting a batch across threads costs more than it saves.
_MIN_THREAD_CHUNK = 1024


def _chunk_length(N: int, chunk_size: int, n_workers: int) -> int:
    """Poses per chunk: at most ``chunk_size``, and a multiple of ``n_workers`` chunks in
    all when the batch is large enough to share, so that no thread idles at the end."""
    n_chunks = -(-N // chunk_size)
    if n_workers > 1 and N >= 2 * _MIN_THREAD_CHUNK:
        n_chunks = -(-max(n_chunks, n_workers) // n_workers) * n_workers
    return max(1, -(-N // max(n_chunks, 1)))


def _batch_poses(T: Any) -> FloatArray:
    """``T`` as a float array of shape (N, 4, 4), checked for shape (values per chunk)."""
    if type(T) is np.ndarray and T.dtype == np.float64:
        Tw = T  # a float64 array: its values are checked chunk by chunk
    else:
        Tw = as_float_array(T, "T")  # anything else: converted and checked here
    if Tw.ndim != 3 or Tw.shape[1:] != (4, 4):
        as_pose(Tw, "T")  # NaN, wrong tail shape or bad values: the single-pose message first
        raise InputError(f"T must have shape (N, 4, 4), got shape {Tw.shape}")
    return Tw


_register()
