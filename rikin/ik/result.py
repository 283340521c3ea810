"""What IK returns: every solution with its branch, and singularity flags."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from typing import Any, NamedTuple

import numpy as np

from .._validate import FloatArray, check_index
from ..errors import InputError, NotIndexedError
from ..i18n import branch_name, word

__all__ = ["Branch", "IKResult", "BatchIKResult", "LABEL_WORDS"]


#: Every word a branch label is made of (what :mod:`rikin.i18n` translates), by field; a
#: root's numbers stay as they are. See :class:`Branch` for what each means.
LABEL_WORDS = {
    "shoulder": ("front", "back"),
    "elbow": ("up", "down", "left", "right", "towards", "away"),
    "wrist": ("no-flip", "flip", "singular"),
    "root": ("root", "of"),
    "none": ("unique",),
}


class Branch(NamedTuple):
    """Which branch of the IK a solution lies on.

    Each field is ``None`` when the arm has no such choice; the label joins the others
    with "/", root first (``"root 2 of 4/up"``), and is "unique" when every field is None.
    Within one result no two solutions have the same label.

    shoulder : "front" or "back"
        Front: joint 1 turns the arm towards the target (the wrist centre is
        on the arm's forward side); back: joint 1 turned by pi, the arm
        reaching over its own axis.
    elbow : "up" or "down" (a SCARA: "left" or "right"; a spherical arm's boom:
        "towards" or "away" from the target)
        Up: the elbow lies above the straight line from the shoulder to the
        wrist centre (for planar arms: on the +y side when reaching along +x).
    wrist : "no-flip", "flip" or "singular"
        No-flip when the middle wrist joint's variable has sin >= 0.
    root : "root k of n", or None
        For arms with no shoulder, elbow or wrist to tell their solutions apart: the
        solutions are the real roots of one polynomial in one joint ``q_j`` (a general
        6R: degree 16, from the eigenvalue problem; three parallel axes with an offset
        wrist: a quartic in joint 1, or 6, each root with two elbows); n counts the real
        roots that give a solution, numbered 1 to n by increasing ``q_j`` in
        (-pi, pi] as the DH table counts it (``-q_j`` for a reversed joint); a general
        6R's two solutions at one root (rare) by the joints after it. ``IKResult`` lists
        them in that order.
    """

    shoulder: str | None = None
    elbow: str | None = None
    wrist: str | None = None
    root: str | None = None

    @property
    def label(self) -> str:
        """The branch as text, e.g. ``"front/up/no-flip"`` or ``"root 3 of 8"``."""
        parts = [p for p in (self.root, self.shoulder, self.elbow, self.wrist) if p is not None]
        return "/".join(parts) if parts else "unique"

    def __getitem__(self, key: Any) -> Any:
        """``branch[0]`` is ``branch.shoulder`` (a tuple's indexing); a bad index is an
        InputError naming the fields (an :class:`~rikin.errors.OutOfRangeError` beyond them)."""
        check_index(key, (4,), "Branch", ("field",), attributes=self._fields, arrays=False,
                    var="branch")
        return tuple.__getitem__(self, key)


#: rad: two solutions whose polynomial joint is this close share its root
ROOT_TOL = 1e-6


def root_names(key: FloatArray, grouped: bool) -> tuple[list[str], list[int]]:
    """``"root k of n"`` for each row of ``key (m, p)``, and the rows in root order.

    ``key`` holds joint values, ``key[:, 0]`` the polynomial's joint (wrapped to
    (-pi, pi]), the others only to order solutions that share it. ``grouped``: rows whose
    first value is within ``ROOT_TOL`` share one root (a quartic root and its two elbows);
    else each row is its own root, ordered by all its values.
    """
    if grouped:
        order = np.argsort(key[:, 0], kind="stable").tolist()
    else:
        order = np.lexsort(key.T[::-1]).tolist()
    number = [0] * len(key)
    k, last = 0, 0.0
    for i in order:
        if not grouped or k == 0 or abs(key[i, 0] - last) > ROOT_TOL:
            k += 1
            last = float(key[i, 0])
        number[i] = k
    return [f"root {r} of {k}" for r in number], order


@dataclass(frozen=True)
class IKResult:
    """All IK solutions of one target.

    Attributes
    ----------
    q : ndarray, shape (k, n)
        One solution per row; revolute values in radians wrapped to
        (-pi, pi] (or the in-limit 2*pi equivalent when filtered by limits),
        prismatic values in the arm's length units.
    branches : tuple of Branch, length k
    target : ndarray, shape (4, 4)
        The target pose in the world frame (the TCP pose every row of ``q``
        reaches).
    singular : bool
        True when the target is at a singularity; then ``q`` holds one
        representative per family of solutions.
    singularity : str or None
        What is singular, in words.
    free_joints : tuple of int
        Joints (numbered from 1) whose values can change along the family
        without moving the TCP; empty at a boundary singularity (arm stretched).
    discarded : int
        How many solutions the joint-limit filter removed.
    rotation_distance : float
        How far the rotation block of the given 4x4 target was from a rotation
        matrix (Frobenius norm of the difference, unitless): a target rounded to
        4 decimals is ~1e-4 off. IK solved for the nearest rotation, which is
        ``target``'s (for a 5-DOF arm, then moved to the nearest reachable pose:
        see ``reach_distance``); 0 when the block was a rotation to rounding (1e-12), or
        no 4x4 matrix was given.
    reach_distance : float
        How far the target's wrist centre was from where the positioning joints
        can put it, in the arm's length units (the least TCP move, orientation
        kept, that makes the pose reachable): for a 5-DOF arm (PPRRR, RPRRR),
        which reaches only a 5-dimensional set of poses, and for a 6R pose just
        beyond the arm's reach (stretched out, rounded). A pose within
        ``ROUNDED_POSE_TOL`` of that set (rounded, float32) is solved for the
        nearest reachable pose, which is ``target``'s: the least sum of squared
        changes of the entries of ``[R | p]``. 0 when the target was reachable
        as given.
    directions : ndarray, shape (n,)
        The solved arm's :attr:`rikin.SerialArm.directions`: -1 for a joint its data sheet
        counts against the DH z axis (``q`` holds the data sheet's values; :meth:`table`
        marks the column ``q1(-z)``); empty, read as all +1, when not known.
    """

    q: FloatArray
    branches: tuple[Branch, ...]
    target: FloatArray
    singular: bool = False
    singularity: str | None = None
    free_joints: tuple[int, ...] = ()
    discarded: int = 0
    arm_name: str = ""
    revolute: FloatArray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    rotation_distance: float = 0.0
    reach_distance: float = 0.0
    directions: FloatArray = field(default_factory=lambda: np.zeros(0))

    @classmethod
    def _regular(
        cls, q: FloatArray, branches: tuple[Branch, ...], target: FloatArray, arm: Any
    ) -> IKResult:
        """The result of a regular pose, built without the dataclass ``__init__`` (trusted
        input; the one-pose fast path spends a tenth of its time there otherwise)."""
        self = object.__new__(cls)
        object.__setattr__(self, "__dict__", {
            "q": q,
            "branches": branches,
            "target": target,
            "singular": False,
            "singularity": None,
            "free_joints": (),
            "discarded": 0,
            "arm_name": arm.name,
            "revolute": arm.revolute,
            "rotation_distance": 0.0,
            "reach_distance": 0.0,
            "directions": arm.directions,
        })
        return self

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def __iter__(self) -> Iterator[FloatArray]:
        return iter(self.q)

    def __getitem__(self, key: Any) -> FloatArray:
        """``res[i]``: solution ``i``, the row ``q[i]`` (negative counts from the end);
        ``res[i, j]`` its joint ``j``; slices, lists and boolean masks as numpy takes them.

        Raises
        ------
        OutOfRangeError
            ``i`` beyond the solutions (an InputError that is also an IndexError).
        InputError
            ``key`` is text (``res["q"]``: read ``res.q``), a float, a bool, None...
        """
        q = self.q
        if type(key) is int and -len(q) <= key < len(q):
            return q[key]
        return q[check_index(key, q.shape, "IKResult", ("solution", "joint"),
                             attributes=_IK_ATTRIBUTES)]

    @property
    def labels(self) -> tuple[str, ...]:
        """Branch labels as text, one per solution."""
        return tuple(b.label for b in self.branches)

    def degrees(self) -> FloatArray:
        """``q`` with revolute columns in degrees, shape ``(k, n)``."""
        return np.where(self.revolute, np.degrees(self.q), self.q)

    def table(self, decimals: int = 4) -> str:
        """The solutions as text, revolute joints in degrees, one row each.

        A last line says when the target was singular, when its rotation
        block was replaced by the nearest rotation (``rotation_distance``), and
        when it was moved to the nearest reachable pose (``reach_distance``).
        """
        whole = isinstance(decimals, (int, np.integer)) and not isinstance(
            decimals, (bool, np.bool_)
        )
        if not whole or not 0 <= decimals <= 15:
            raise InputError(f"decimals must be a whole number from 0 to 15, got {decimals!r}")
        k, n = self.q.shape
        names = [branch_name(label) for label in self.labels]
        w = max([22, *map(len, names)])
        head = f"{'#':>2}  {word('branch'):<{w}}" + "".join(f"{name:>11}"
                                                          for name in self._joint_names(n))
        rows = [head]
        qd = self.degrees()
        for i in range(k):
            rows.append(
                f"{i + 1:>2}  {names[i]:<{w}}"
                + "".join(f"{v:>11.{decimals}f}" for v in qd[i])
            )
        if self.singular:
            rows.append(f"singular: {self.singularity}; free joints {self.free_joints}")
        if self.rotation_distance > 0:
            rows.append(
                f"target rotation block was {self.rotation_distance:.2g} from a rotation "
                "(rounded?): solved for the nearest rotation"
            )
        if self.reach_distance > 0:
            rows.append(
                f"target {self.reach_distance:.2g} off the poses this arm reaches (rounded?): "
                "solved for the nearest reachable pose"
            )
        return "\n".join(rows)

    def _joint_names(self, n: int) -> list[str]:
        """Column names ``q1 .. qn``, ``q1(-z)`` for a joint counted against the DH z axis."""
        reversed_ = [len(self.directions) == n and self.directions[j] < 0 for j in range(n)]
        return [f"q{j + 1}" + ("(-z)" if r else "") for j, r in enumerate(reversed_)]

    def __repr__(self) -> str:
        extra = f", singular={self.singularity!r}" if self.singular else ""
        return f"IKResult({len(self)} solutions of {self.arm_name!r}{extra})\n{self.table()}"

    def _take(self, idx: Any, q: FloatArray | None = None, **changes: Any) -> IKResult:
        idx = list(idx)
        qq = self.q[idx] if q is None else q
        return replace(self, q=qq, branches=tuple(self.branches[i] for i in idx), **changes)


@dataclass(frozen=True)
class BatchIKResult:
    """IK solutions of many poses at once (no dedupe, fixed slots).

    Attributes
    ----------
    q : ndarray, shape (N, k, n)
        Slot ``j`` of every pose holds solutions of one kind, ``branches[j]``.
        Revolute values in radians, wrapped to (-pi, pi]. Slots that are not
        valid hold NaN: always read ``valid`` first.
    valid : ndarray of bool, shape (N, k)
        The slot holds a real solution.
    singular : ndarray of bool, shape (N,)
        The pose is at a singularity (some slots are then representatives
        of an infinite family, and may repeat).
    branches : tuple of Branch, length k
        What slot ``j`` fixes, the same for every pose: a field is None where the
        pose decides it (the shoulder and elbow of an arm whose solver tells them by
        the geometry, as for a spherical wrist solved from its DH table or a UR; the
        wrist flip that the middle wrist joint's sign gives; a root). A slot never
        names a branch its solutions may lack (but at a wrist singularity, where a
        slot's wrist, a UR's, is one representative of the family ``labels`` calls
        "singular"): :meth:`labels` gives each solution's full label.
    rotation_distance : ndarray, shape (N,)
        Per pose, as :attr:`IKResult.rotation_distance`: how far its rotation
        block was from the rotation it was solved for (0 for most poses).
    reach_distance : ndarray, shape (N,)
        Per pose, as :attr:`IKResult.reach_distance`: how far (length units) the
        pose was from reachable, when it was solved for the nearest reachable
        pose (a 5-DOF arm's rounded pose, or a 6R pose rounded just beyond its
        reach); 0 for the others.
    labeller : callable or None
        ``labeller(i, q_i, slots) -> list of Branch``: the branches of pose ``i``'s
        solutions ``q_i (m, n)`` held in ``slots (m,)``, as ``arm.ik`` labels them (the
        same function labels both); used by :meth:`labels`. None: the slots' branches.

    Notes
    -----
    Which branch a slot's solution lies on may depend on the pose (which root of the
    position problem it holds, where the elbow lies): :meth:`labels` gives pose ``i``'s
    labels, computed when asked (``ik_batch`` itself labels nothing).
    """

    q: FloatArray
    valid: Any
    singular: Any
    branches: tuple[Branch, ...]
    rotation_distance: Any = None
    reach_distance: Any = None
    labeller: Callable[[int, FloatArray, Any], list[Branch]] | None = field(
        default=None, repr=False, compare=False)

    def labels(self, i: Any) -> tuple[str, ...]:
        """The branch labels of pose ``i``'s solutions ``q[i][valid[i]]``, in that order,
        each the label ``arm.ik`` gives the same joints (shoulder, elbow, wrist, or
        ``"root k of n"``; at a wrist singularity ``"singular"``), computed on the call by
        the arm's solver for that pose (about one ``arm.ik``'s time). ``i`` is a whole
        number, negative from the end."""
        i = check_index(i, self.valid.shape[:1], "BatchIKResult.labels", ("pose",),
                        arrays=False, var="labels")
        slots = np.flatnonzero(self.valid[i])
        if self.labeller is None or not slots.size:
            return tuple(self.branches[s].label for s in slots)
        return tuple(b.label for b in self.labeller(i, self.q[i, slots], slots))

    @property
    def counts(self) -> Any:
        """Number of valid solutions per pose, shape ``(N,)``."""
        return self.valid.sum(axis=1)

    def __getitem__(self, key: Any) -> Any:
        """Not indexed: :class:`~rikin.errors.NotIndexedError` saying how to read pose ``i``.

        A batch keeps fixed slots with NaN where a pose has no such solution, so
        ``res[i]`` could only mean NaN-padded rows; ``res.q[i][res.valid[i]]`` are the
        solutions of pose ``i``.
        """
        raise not_indexed(self, _BATCH_HOW, key)

    def __iter__(self) -> Iterator[Any]:
        """Not iterable: :class:`~rikin.errors.NotIndexedError`, as for an index."""
        raise not_indexed(self, _BATCH_HOW, iterated=True)


_BATCH_HOW = (
    "a batch result is not indexed by pose; the solutions of pose i are "
    "result.q[i][result.valid[i]] (q has shape (N, k, n), NaN in the slots that are not valid)"
)


def not_indexed(
    record: Any, how: str, key: Any = None, *, iterated: bool = False
) -> NotIndexedError:
    """The error for indexing (with ``key``) or iterating a result that is no sequence:
    ``how`` to read it instead, and its attributes (a text key naming one: read it so)."""
    kind = type(record).__name__
    names = [f.name for f in dataclasses.fields(record)]
    listed = ", ".join(names)
    if iterated:
        return NotIndexedError(f"a {kind} was iterated: {how}; its attributes: {listed}")
    if isinstance(key, str) and key in names:
        return NotIndexedError(
            f"{kind} index {key!r} is text: {key} is an attribute, read it as result.{key}"
        )
    return NotIndexedError(f"{kind} index {key!r:.60}: {how}; its attributes: {listed}")


#: What a text index of an IKResult may mean instead: its attributes.
_IK_ATTRIBUTES = tuple(f.name for f in dataclasses.fields(IKResult)) + (
    "labels", "degrees", "table")
