"""What the four exercise arms share: the spherical wrist, solution sets, decoupling.

Every exercise arm is a 3-joint positioning arm (standard DH, frame 3's origin
is the point it positions) that can carry the same spherical wrist:

====  =====  ===  ===  ========
row   joint   d    a   alpha
====  =====  ===  ===  ========
4     R       0    0   -pi/2
5     R       0    0   +pi/2
6     R       0    0    0
====  =====  ===  ===  ========

plus a tool ``T_6_tcp = Tz(tool)``. Frames 4, 5 and 6 all sit at the wrist
centre (the origin of frame 3), the flange frame 6 included, so the TCP is
``tool`` ahead of the wrist centre along ``z_6`` and ``R_3_6 = Rz(q4) Ry(q5)
Rz(q6)`` (ZYZ Euler angles). Decoupling (desacople cinemático):
``p_w = p - tool * z_6``; the positioning arm's IK puts frame 3 at ``p_w``;
``R_3_6 = R_0_3^T R_0_6`` gives the wrist, two branches (q5 > 0, q5 < 0) that
merge at the wrist singularity q5 = 0 or pi, where only q4 + q6 (q5 = 0) or
q6 - q4 (q5 = pi) is fixed.

Conventions shared by the exercises: radians; revolute joints have no limits;
prismatic joints only extend, ``q >= 0`` (no upper limit); lengths positive.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

import rikin
from rikin import Link, SerialArm, UnreachableError

from ..i18n import N_

FloatArray = NDArray[np.float64]

#: Relative slack on a reach limit or a prismatic joint's zero (times the arm's
#: size): a target this close beyond it is clamped onto it, not rejected.
REACH_TOL = 1e-9
#: A sine (or relative distance) below this is a singularity.
SINGULAR_TOL = 1e-9
#: 1 - |cos| below this: the elbow is exactly stretched or folded (acos would
#: turn the rounding of such a cosine into ~1e-8 rad of fake elbow angle).
STRETCH_TOL = 1e-13
#: How far from orthonormal a target's rotation may be.
ROTATION_TOL = 1e-6
#: How near a singular configuration the hidden tests' "near" targets are: this many
#: radians from a singular joint value (q5 = 0 or pi, the elbow stretched or folded), or
#: this fraction of the arm's size from a singular position (the spherical arm's axis).
#: There the IK is ill-conditioned but regular: every branch is a distinct solution.
NEAR_SINGULAR = 1e-3

#: The wrist rows 4-6 (standard DH), shared by every exercise arm.
WRIST_LINKS: tuple[Link, ...] = (
    Link("R", alpha=-np.pi / 2),
    Link("R", alpha=np.pi / 2),
    Link("R"),
)

WRIST_LABELS = (N_("wrist q5 > 0"), N_("wrist q5 < 0"))


@dataclass(frozen=True)
class Solutions:
    """Every IK solution of one target.

    Attributes
    ----------
    q : ndarray, shape (k, n)
        One solution per row: radians (revolute, wrapped to (-pi, pi]), length
        units (prismatic).
    labels : tuple of str
        The branch of each row in words, e.g. ``"elbow left (q2 < 0), wrist q5 > 0"``.
    free : tuple of tuple of int
        Per row, the 0-based joints that are free within its singular family
        (empty for a regular solution). The row is one representative.
    revolute : ndarray of bool, shape (n,)
    """

    q: FloatArray
    labels: tuple[str, ...]
    free: tuple[tuple[int, ...], ...]
    revolute: NDArray[np.bool_]

    def __len__(self) -> int:
        return int(self.q.shape[0])

    @property
    def singular(self) -> bool:
        """True when some row stands for a whole family (a singular target)."""
        return any(self.free)


def wrap(q: Any) -> FloatArray:
    """Angles wrapped to (-pi, pi]."""
    return rikin.wrap_angle(np.asarray(q, dtype=np.float64))


def check_lengths(names: tuple[str, ...], values: dict[str, float]) -> dict[str, float]:
    """Return the lengths as floats; InputError unless every one is given, finite and > 0."""
    missing = [n for n in names if n not in values]
    extra = [n for n in values if n not in names]
    if missing or extra:
        raise rikin.InputError(f"expected lengths {names}, got {tuple(values)}")
    out = {}
    for n in names:
        v = float(values[n])
        if not np.isfinite(v) or v <= 0:
            raise rikin.InputError(f"{n} must be a positive length, got {values[n]!r}")
        out[n] = v
    return out


def as_point(p: Any) -> FloatArray:
    arr = np.asarray(p, dtype=np.float64)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise rikin.InputError(f"p must be 3 finite numbers (x, y, z), got {p!r}")
    return arr


def as_pose(T: Any) -> FloatArray:
    arr = np.asarray(T, dtype=np.float64)
    if arr.shape != (4, 4) or not np.all(np.isfinite(arr)):
        raise rikin.InputError(
            f"T must be a finite (4, 4) homogeneous transform, got shape {arr.shape}"
        )
    R = arr[:3, :3]
    if np.abs(R.T @ R - np.eye(3)).max() > ROTATION_TOL or np.linalg.det(R) < 0:
        raise rikin.InputError("the rotation part of T is not a rotation matrix")
    return arr


def wrist_solutions(R_3_6: FloatArray) -> tuple[list[FloatArray], bool]:
    """(q4, q5, q6) of ``R_3_6 = Rz(q4) Ry(q5) Rz(q6)``: both branches, or one if singular.

    At the singularity (sin q5 = 0) the representative has q4 = 0.
    """
    M = R_3_6
    s5 = float(np.hypot(M[0, 2], M[1, 2]))
    if s5 < SINGULAR_TOL:
        if M[2, 2] > 0:  # q5 = 0: M = Rz(q4 + q6)
            return [np.array([0.0, 0.0, np.arctan2(M[1, 0], M[0, 0])])], True
        # q5 = pi: M = Ry(pi) Rz(q6 - q4) = [[-c, s, 0], [s, c, 0], [0, 0, -1]]
        return [np.array([0.0, np.pi, np.arctan2(M[1, 0], M[1, 1])])], True
    q5 = np.arctan2(s5, M[2, 2])
    q4 = np.arctan2(M[1, 2], M[0, 2])
    q6 = np.arctan2(M[2, 1], -M[2, 0])
    first = np.array([q4, q5, q6])
    second = wrap(np.array([q4 + np.pi, -q5, q6 + np.pi]))
    return [first, second], False


class ExerciseArm:
    """A positioning arm of the exercises, with and without the spherical wrist.

    Subclasses set ``name``, ``title``, ``lengths``, ``joint_types`` and
    implement :meth:`links`, :meth:`_position_ik` and the samplers.
    """

    name: str = ""
    title: str = ""
    lengths: tuple[str, ...] = ()
    joint_types: str = ""

    # ---------------------------------------------------------------- model
    def links(self, **L: float) -> list[Link]:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def revolute(self) -> NDArray[np.bool_]:
        return np.array([j == "R" for j in self.joint_types])

    @property
    def revolute_6dof(self) -> NDArray[np.bool_]:
        return np.concatenate([self.revolute, [True, True, True]])

    @property
    def function_names(self) -> dict[str, str]:
        """The student's function names, by task."""
        n = self.name
        return {
            "dh": "dh_table",
            "fk": f"fk_{n}",
            "ik": f"ik_{n}",
            "fk6": f"fk_{n}_6dof",
            "ik6": f"ik_{n}_6dof",
        }

    def scale(self, L: dict[str, float]) -> float:
        return max(1.0, sum(L.values()))

    def arm(self, **L: float) -> SerialArm:
        """The positioning arm as a rikin SerialArm (TCP = origin of frame 3)."""
        L = check_lengths(self.lengths, L)
        return self._arm(tuple(L[n] for n in self.lengths))

    def arm_6dof(self, tool: float, **L: float) -> SerialArm:
        """The arm with the spherical wrist and the tool ``Tz(tool)``."""
        L = check_lengths(self.lengths, L)
        tool = check_lengths(("tool",), {"tool": tool})["tool"]
        return self._arm_6dof(tuple(L[n] for n in self.lengths), tool)

    # A grading run asks for the same few arms thousands of times (every submission
    # gets the same hidden inputs); SerialArm is immutable, so one object per set of
    # lengths serves them all.
    @lru_cache(maxsize=1024)  # noqa: B019 - arms live as long as the process anyway
    def _arm(self, values: tuple[float, ...]) -> SerialArm:
        L = dict(zip(self.lengths, values, strict=True))
        return SerialArm(tuple(self.links(**L)), name=self.title)

    @lru_cache(maxsize=1024)  # noqa: B019
    def _arm_6dof(self, values: tuple[float, ...], tool: float) -> SerialArm:
        L = dict(zip(self.lengths, values, strict=True))
        return SerialArm(
            tuple(self.links(**L)) + WRIST_LINKS,
            tool=rikin.transl(0.0, 0.0, tool),
            name=f"{self.title} with a spherical wrist",
        )

    def fk(self, q: Any, **L: float) -> FloatArray:
        """``T_0_3``, shape (4, 4) (or (N, 4, 4) for q of shape (N, 3))."""
        return self.arm(**L).fk(q)

    def fk_6dof(self, q: Any, tool: float, **L: float) -> FloatArray:
        """``T_0_tcp`` of the 6-DOF arm, shape (4, 4) (or (N, 4, 4))."""
        return self.arm_6dof(tool, **L).fk(q)

    def fk_flange_6dof(self, q: Any, tool: float, **L: float) -> FloatArray:
        """``T_0_6``: the flange frame (at the wrist centre), without the tool."""
        return self.arm_6dof(tool, **L).fk_flange(q)

    # ---------------------------------------------------------------- IK
    def _position_ik(
        self, p: FloatArray, L: dict[str, float]
    ) -> list[tuple[FloatArray, str, tuple[int, ...]]]:  # pragma: no cover
        raise NotImplementedError

    def ik(self, p: Any, **L: float) -> Solutions:
        """Every solution that puts the origin of frame 3 at ``p``.

        Raises
        ------
        rikin.UnreachableError
            ``p`` is outside the workspace (the message says which limit).
        """
        L = check_lengths(self.lengths, L)
        rows = self._position_ik(as_point(p), L)
        q = np.array([np.where(self.revolute, wrap(r[0]), r[0]) for r in rows])
        return Solutions(q, tuple(r[1] for r in rows), tuple(r[2] for r in rows), self.revolute)

    def ik_6dof(self, T: Any, tool: float, **L: float) -> Solutions:
        """Every solution of the 6-DOF arm for the TCP pose ``T``, by decoupling.

        Raises
        ------
        rikin.UnreachableError
            The wrist centre ``p - tool z_6`` is outside the positioning arm's workspace.
        """
        L = check_lengths(self.lengths, L)
        tool = check_lengths(("tool",), {"tool": tool})["tool"]
        T = as_pose(T)
        R_0_6 = T[:3, :3]
        p_w = T[:3, 3] - tool * R_0_6[:, 2]
        try:
            pos = self.ik(p_w, **L)
        except UnreachableError as exc:
            raise UnreachableError(
                f"the wrist centre p - tool*z6 cannot be reached: {exc}",
                excess=exc.excess,
                units=exc.units,
            ) from None
        arm = self.arm(**L)
        rows, labels, free = [], [], []
        for q123, label, free123 in zip(pos.q, pos.labels, pos.free, strict=True):
            R_0_3 = arm.fk(q123)[:3, :3]
            wrist, singular = wrist_solutions(R_0_3.T @ R_0_6)
            for i, q456 in enumerate(wrist):
                rows.append(np.concatenate([q123, q456]))
                if singular:
                    which = N_("wrist singular (q5 = 0)") if abs(q456[1]) < 1 else N_(
                        "wrist singular (q5 = pi)")
                    labels.append(f"{label}, {which}")
                    free.append(tuple(free123) + (3, 5))
                else:
                    labels.append(f"{label}, {WRIST_LABELS[i]}")
                    free.append(tuple(free123))
        q = np.array(rows)
        q = np.where(self.revolute_6dof, wrap(q), q)
        return Solutions(q, tuple(labels), tuple(free), self.revolute_6dof)

    # ---------------------------------------------------------------- sampling
    def sample_lengths(self, rng: np.random.Generator) -> dict[str, float]:  # pragma: no cover
        raise NotImplementedError

    def sample_q(
        self, rng: np.random.Generator, L: dict[str, float]
    ) -> FloatArray:  # pragma: no cover
        """Joint values of a regular (non-singular, not boundary) reachable configuration."""
        raise NotImplementedError

    def sample_special_q(
        self, rng: np.random.Generator, L: dict[str, float], i: int = 0
    ) -> tuple[str, FloatArray] | None:
        """A singular or boundary configuration of the positioning arm (kind, q), or None.

        ``i`` counts the special cases of one test, so an arm with several kinds of
        special configuration (SCARA: stretched and folded) samples each of them.
        """
        return None

    def sample_near_special_q(
        self, rng: np.random.Generator, L: dict[str, float], i: int = 0
    ) -> FloatArray | None:
        """A regular configuration NEAR the ``i``-th kind of :meth:`sample_special_q`
        (:data:`NEAR_SINGULAR` from it), or None for an arm without special ones."""
        return None

    def unreachable_points(
        self, rng: np.random.Generator, L: dict[str, float], near: bool = False
    ) -> list[tuple[str, FloatArray]]:  # pragma: no cover
        """Unreachable targets, each with what makes it unreachable (in words).

        With ``near``, every target is only 0.05-0.3 length units out of reach.
        """
        raise NotImplementedError

    def sample_tool(self, rng: np.random.Generator) -> float:
        return float(rng.uniform(0.5, 4.0))

    def sample_wrist(self, rng: np.random.Generator) -> FloatArray:
        """(q4, q5, q6) away from the wrist singularity (|sin q5| >= sin 0.2)."""
        q5 = rng.uniform(0.2, np.pi - 0.2) * rng.choice([-1.0, 1.0])
        return np.array([rng.uniform(-np.pi, np.pi), q5, rng.uniform(-np.pi, np.pi)])

    def sample_q_6dof(self, rng: np.random.Generator, L: dict[str, float]) -> FloatArray:
        return np.concatenate([self.sample_q(rng, L), self.sample_wrist(rng)])

    def sample_wrist_singular_q(
        self, rng: np.random.Generator, L: dict[str, float], q5: float
    ) -> FloatArray:
        """A regular positioning configuration with the wrist singular at ``q5`` (0 or pi)."""
        return np.concatenate(
            [self.sample_q(rng, L), [rng.uniform(-np.pi, np.pi), q5, rng.uniform(-np.pi, np.pi)]]
        )

    def unreachable_poses(
        self, rng: np.random.Generator, L: dict[str, float], tool: float
    ) -> list[tuple[str, FloatArray]]:
        """Unreachable TCP poses: one with a random orientation, and two whose TCP
        the positioning arm could reach although the wrist centre is out of reach."""
        out = []
        points = self.unreachable_points(rng, L)
        kind, p_w = points[0]
        R = random_rotation(rng)
        out.append(
            (f"a pose whose wrist centre is {kind}", rikin.homogeneous(R, p_w + tool * R[:, 2]))
        )
        for kind, p_w in self.unreachable_points(rng, L, near=True):
            if len(out) == 3:
                break
            for _ in range(400):
                R = random_rotation(rng)
                p = p_w + tool * R[:, 2]
                try:
                    self.ik(p, **L)
                except UnreachableError:
                    continue
                out.append(
                    (
                        f"a pose whose TCP is within reach but whose wrist centre is {kind}",
                        rikin.homogeneous(R, p),
                    )
                )
                break
        while len(out) < 3:  # pragma: no cover - samplers are built so this does not happen
            kind, p_w = points[len(out) % len(points)]
            R = random_rotation(rng)
            out.append(
                (f"a pose whose wrist centre is {kind}", rikin.homogeneous(R, p_w + tool * R[:, 2]))
            )
        return out


def random_rotation(rng: np.random.Generator) -> FloatArray:
    """A uniformly random rotation matrix (from a random unit quaternion)."""
    w, x, y, z = rng.normal(size=4) / 1.0
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def excess(rng: np.random.Generator, near: bool, lo: float = 0.5, hi: float = 5.0) -> float:
    """How far out of reach a sampled unreachable target is."""
    return float(rng.uniform(0.05, 0.3) if near else rng.uniform(lo, hi))
