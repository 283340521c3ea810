"""One regular pose of the general 6R solver (:mod:`rikin.ik.general6r`) for ``arm.ik``.

:func:`rikin.ik.api.solve` turns a solver's raw slots into an :class:`IKResult` with
checks and labels that a family of closed forms needs (dropped slots at singularities,
shoulder, elbow and wrist labels, an FK check of every solution by the arm's own FK): for
one pose of a general 6R they cost a quarter of its time. :class:`General6RKernel` is the
one-pose interface that ``solve`` offers a solver for that (``single_kernel``): it runs
the solver's own :meth:`solve` on the pose and does what ``solve`` would do with its
slots when the pose is regular (no slot flagged singular, at least one solution): wrap
the joints to (-pi, pi], keep the first of solutions equal to ``SAME_SOLUTION_TOL``,
name each by its root and list them in root order. The caller then checks every
solution by FK (:class:`rikin.ik.fkcheck.FKCheck`) and takes the general path for any
pose the kernel declines (None), so the result is the general path's, bit for bit.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np

from ..tolerances import SAME_SOLUTION_TOL
from ..transforms import _wrap_angle
from .base import RawSolutions
from .result import Branch, root_names

if TYPE_CHECKING:  # pragma: no cover
    from .._validate import FloatArray
    from ..dh import SerialArm

__all__ = ["General6RKernel"]


class KernelSource(Protocol):
    """What :class:`General6RKernel` uses of :class:`rikin.ik.general6r.General6RSolver`."""

    @property
    def root_joint(self) -> int: ...  # the joint (0-5) whose values number the roots

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None,
              labels: bool = True) -> RawSolutions: ...


class General6RKernel:
    """``arm.ik`` of one regular pose through :meth:`General6RSolver.solve` (see the
    module docstring); built once per arm."""

    def __init__(self, solver: KernelSource, arm: SerialArm) -> None:
        self.solver, self.arm = solver, arm
        self.root_joint = solver.root_joint
        #: the columns of a solution with the root's joint first: ``np.roll(q, -root_joint,
        #: axis=1)`` as one indexing (the same copy, without np.roll's calls)
        self._root_first = np.roll(np.arange(6), -self.root_joint)

    def solve(self, rows: list[list[float]]) -> tuple[list[float], list[Branch]] | None:
        """The solutions (flat, row after row) of the world pose ``rows`` (4 x 4 nested
        lists, validated by the caller) and their branches, or None where the general path
        must answer (no solution, or a slot at a singularity)."""
        arm = self.arm
        raw = self.solver.solve(arm, arm._world_to_base(np.array(rows))[None], None)
        valid = raw.valid[0]
        if not valid.any() or raw.singular["singular"][0].any():
            return None
        q = _wrap_angle(raw.q[0, valid])  # every joint revolute
        q = q[_first_of_each(q)]
        names, order = root_names(_wrap_angle(q)[:, self._root_first], False)
        return q[order].ravel().tolist(), [Branch(root=names[i]) for i in order]


def _first_of_each(q: FloatArray) -> list[int]:
    """The rows of ``q (k, 6)`` to keep: the first of each group equal modulo 2 pi to
    ``SAME_SOLUTION_TOL`` (as :func:`rikin.ik.api.solve` keeps them)."""
    same_ = np.abs(_wrap_angle(q[:, None, :] - q[None, :, :])).max(axis=-1) <= SAME_SOLUTION_TOL
    if np.count_nonzero(same_) == len(q):  # each row equal to itself alone: keep all
        return list(range(len(q)))
    same = same_.tolist()
    kept: list[int] = []
    for i in range(len(q)):
        if not any(same[i][j] for j in kept):
            kept.append(i)
    return kept
