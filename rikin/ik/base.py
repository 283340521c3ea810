"""The interface every closed-form solver implements, and what it hands back."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, Protocol

import numpy as np

from .._validate import FloatArray
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

TargetKind = Literal["pose", "position", "planar_pose", "planar_position"]


@dataclass
class RawSolutions:
    """Fixed-slot solutions of N targets, as the kernels compute them.

    q : (N, k, n) joint values (not yet wrapped); invalid slots hold NaN.
    valid : (N, k) bool.
    slots : tuple of Branch, one per slot: the slot's shoulder and wrist branch
        (the elbow label is geometric and comes from ``elbow_up``).
    elbow_up : (N, k) bool or None: elbow above the shoulder-wrist line.
    shoulder_front : (N, k) bool or None: the wrist centre ahead of axis 1, for
        solvers whose slots do not fix the shoulder (then it overrides the slot's).
    singular : name -> (N,) bool mask (e.g. "wrist", "shoulder", "elbow").
    """

    q: FloatArray
    valid: np.ndarray
    slots: tuple[Branch, ...]
    elbow_up: np.ndarray | None = None
    shoulder_front: np.ndarray | None = None
    singular: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass(frozen=True)
class Singularity:
    """How one kind of singularity is reported: its words and its free joints."""

    description: str
    free_joints: tuple[int, ...]
    drop_flip: bool = False  # one member per family: keep the no-flip slots only
    drop_back: bool = False  # front and back are the same family


class Solver(Protocol):
    """A closed-form IK of one arm family, working on ``T_0_n`` (no base, no tool).

    A family may also offer ``nearest_reachable(arm, T_world)``: the reachable poses it
    solves instead of rounded ones that miss its reach (see :mod:`rikin.ik.reach`), and
    ``labels_optional = True``: its ``solve`` then takes ``labels=False`` and skips
    ``elbow_up`` and ``shoulder_front``, which the batch path does not report; and
    ``slots``, the ``RawSolutions.slots`` its ``solve`` always returns. Its labels
    (:class:`~rikin.ik.result.Branch`) may come from ``wrist_from_slot = True`` (the
    slot's wrist, not the middle wrist joint's sign) and ``root_joint`` (0-based, with
    ``root_grouped``): its solutions named and ordered by the roots of a polynomial in
    that joint, where no shoulder, elbow or wrist tells them apart; and
    ``label_rows(q)``: the ``shoulder_front`` and ``elbow_up`` ``(m,)`` (or None) its
    ``solve`` gives joint rows ``q (m, n)``, which label a batch's regular poses
    without solving them again.
    """

    target_kind: TargetKind
    #: index (0-based) of the middle wrist joint, for the flip label; None if no wrist
    wrist_middle: int | None
    singularities: dict[str, Singularity]

    def check(self, arm: SerialArm) -> None:
        """Raise InputError if ``arm`` is not of this family."""

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        """All solutions of N targets ``(N, 4, 4)``; trusted input."""

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        """Why one target ``(4, 4)`` has no solution: a sentence, and by how much."""
