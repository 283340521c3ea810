"""A lesson solver fitted to another table of its family.

The lesson robots' solvers read their own tables (:mod:`rikin.ik.planar`,
:mod:`rikin.ik.anthropomorphic`). The same arm typed another way (modified DH, other
offsets, a base frame turned, an axis pointing down, a joint zero elsewhere) is still
the lesson's arm up to constant transforms and an affine change of joint values:

    ``T_0_n(q) = pre @ L(theta) @ post``, ``theta = sign * q + shift``

with ``L`` the lesson arm's FK. :class:`Fitted` solves with the lesson arm and solver
and hands back ``q = sign * (theta - shift)``: the same solutions, branch labels and
singularities as the lesson robot, for the typed arm. :mod:`rikin.ik.families` finds
``pre``, ``post``, ``sign`` and ``shift`` from the table and checks them by FK.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..transforms import _inv_transform
from .api import ClosedForm
from .base import RawSolutions

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

#: How close (relative to the arm's size for positions) a fitted arm reproduces the table.
FIT_TOL = 1e-9


class Fitted(ClosedForm):
    """The solver of ``lesson`` (a lesson arm with no base and no tool), for an arm whose
    flange pose is ``pre @ lesson.fk(sign * q + shift) @ post``.

    Parameters
    ----------
    lesson : SerialArm
        The lesson arm with its solver (``lesson.solver``), base and tool the identity.
    pre, post : ndarray, shape (4, 4)
    sign : ndarray of +1/-1, shape (n,)
    shift : ndarray, shape (n,)
        Radians (revolute) or length units (prismatic).
    """

    def __init__(self, lesson: SerialArm, pre: FloatArray, post: FloatArray,
                 sign: FloatArray, shift: FloatArray) -> None:
        self.lesson, self.inner = lesson, lesson.solver
        self.pre, self.post = pre, post
        self.pre_inv, self.post_inv = _inv_transform(pre), _inv_transform(post)
        self.sign, self.shift = np.asarray(sign, dtype=float), np.asarray(shift, dtype=float)
        self.target_kind = self.inner.target_kind
        self.count = self.inner.count
        self.wrist_middle = self.inner.wrist_middle
        self.singularities = self.inner.singularities

    def __repr__(self) -> str:
        return f"Fitted({type(self.inner).__name__} of {self.lesson.links!r:.80})"

    def check(self, arm: SerialArm) -> None:
        """Raise InputError unless ``arm``'s flange pose is ``pre @ lesson(sign q + shift) @
        post`` at random joint values (``FIT_TOL``): the arm this solver was fitted to."""
        if arm.joint_types != self.lesson.joint_types:
            raise InputError(f"{arm.name}: this {type(self.inner).__name__} was fitted to a "
                             f"{self.lesson.joint_types} arm, got {arm.joint_types}")
        rng = np.random.default_rng(2)
        q = rng.uniform(-np.pi, np.pi, size=(8, arm.n))
        err = np.abs(arm._flange._fk(q)
                     - self.pre @ self.lesson._fk(self.sign * q + self.shift) @ self.post)
        if not (err[:, :3, :3].max() <= FIT_TOL and err[:, :3, 3].max() <= FIT_TOL * arm.scale):
            raise InputError(f"{arm.name}: its table is not the {self.lesson.joint_types} arm "
                             f"this {type(self.inner).__name__} was fitted to")

    def to_lesson(self, T_0_n: FloatArray) -> FloatArray:
        """The lesson arm's flange poses ``(N, 4, 4)`` for the arm's ``T_0_n (N, 4, 4)``."""
        return self.pre_inv @ T_0_n @ self.post_inv

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        theta_hint = None if hint is None else self.sign * hint + self.shift
        raw = self.inner.solve(self.lesson, self.to_lesson(T_0_n), theta_hint)
        raw.q = self.sign * (raw.q - self.shift)
        return raw

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        named = self.lesson.replace(name=arm.name, units=arm.units)
        return self.inner.explain(named, self.to_lesson(T_0_n[None])[0])

    def nearest_reachable(self, arm: SerialArm, T_world: FloatArray) -> Any:
        """The lesson solver's nearest reachable poses (world frame), for the lesson arm
        placed where the typed arm is (base ``arm.base @ pre``, tool ``post @ arm.tool``)."""
        placed = self.lesson.replace(base=arm.base @ self.pre, tool=self.post @ arm.tool,
                                     name=arm.name, units=arm.units)
        return self.inner.nearest_reachable(placed, T_world)
