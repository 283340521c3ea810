"""The positioning arms of the course's exercises, read from any DH table.

Aula 10's exercise arms place a point (the TCP, or the wrist centre of a spherical wrist)
with three joints; each family has its own closed form, written here once on the joint
axes at ``q = 0`` (:mod:`rikin.ik.axes`), so that it holds for any table of the family
(standard or modified DH, any offsets, twists and signs):

* **cartesian** (PPP): three slides, ``p = c + q1 w1 + q2 w2 + q3 w3``: one solution;
* **cylindrical** (RPP): a column turning about axis 1 and two slides: joint 1 keeps
  the height along axis 1 and the distance from it, so one slide's value is linear in
  the other's and that one solves a quadratic: two solutions (front, back);
* **spherical** (RRP, axes 1 and 2 meeting in a point ``O``, the Stanford arm's first
  three joints): turns about ``O`` keep the distance from it, a quadratic in the slide
  (the boom towards the target or away from it), then the two turns that bring the
  boom onto the target (Paden-Kahan subproblem 2: front or back): four solutions;
* **SCARA** (RRP, axes 1 and 2 parallel, the quill along them): the height gives the
  quill, then the planar two-link chain of the lesson (elbow left or right).

Each family solves N points at once in fixed slots; :class:`PositioningSolver` (3
joints, a position target) and :class:`WristedSolver` (6 joints, the last three a
spherical wrist: both wrist branches per position slot, as in Aula 10's decoupling)
turn them into the closed-form solvers of :mod:`rikin.ik`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import AXIS_TOL, REACH_TOL, SINGULAR_TOL
from .api import ClosedForm
from .axes import ZeroAxes, rotate, turn_angle, two_turns
from .base import RawSolutions, Singularity
from .decoupled import WRIST, rotation_0_3, wrist_angles, wrist_model, wrist_slot_labels
from .kernels import reach_excess, two_link_parts, two_link_slots
from .reach import Gap, nearest_reachable, rounding_note
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm


SHOULDER = Singularity("the point joints 1-3 place is on the axis of joint 1, so q1 is free",
                       (1,))


@dataclass
class Placed:
    """What a family returns for N points: ``q (N, k, 3)``, ``valid (N, k)``, per-slot
    singular masks ``(N, k)`` by name, and per-solution shoulder side ``(N, k)`` (or None)."""

    q: FloatArray
    valid: np.ndarray
    singular: dict[str, np.ndarray]
    shoulder_front: np.ndarray | None = None


def _units(units: str) -> str:
    return f" {units}" if units else ""


class PositionFamily:
    """Joints 1-3 of a family: every joint triple that puts a point ``c`` of link 3 at
    ``p``. ``c0`` is ``c`` at ``q = 0`` (frame 0)."""

    #: The family in the book's words, what it is made of, and the most solutions it has.
    name = ""
    words = ""
    count = 1
    slots: tuple[Branch, ...] = (Branch(),)
    singularities: dict[str, Singularity] = {}

    def __init__(self, ax: ZeroAxes, c0: FloatArray) -> None:
        self.ax, self.c0, self.size = ax, np.asarray(c0, dtype=float), ax.scale

    def place(self, p: FloatArray, hint: FloatArray | None) -> Placed:
        """All joint triples for the points ``p (N, 3)`` (frame 0)."""
        raise NotImplementedError

    def explain(self, p: FloatArray, units: str, what: str) -> tuple[str, float]:
        """Why ``what`` at ``p (3,)`` is out of reach, and by how much (length units)."""
        return f"{what} is out of reach of joints 1-3", float("inf")

    def gap(self, p: FloatArray, active: np.ndarray | None) -> Gap:
        """The ``gap`` of :func:`rikin.ik.reach.nearest_reachable` for points ``p (N, 3)``
        (frame 0): signed distances from the set joints 1-3 reach, their gradients, and which
        apply. A family that reaches every point has none: nothing applies."""
        N = len(p)
        return np.zeros((N, 1)), np.zeros((N, 1, 3)), np.zeros((N, 1), dtype=bool)


class Cartesian(PositionFamily):
    """Three slides: ``q = W^-1 (p - c0)``, one solution."""

    name, words = "cartesian arm", "three slides"

    def __init__(self, ax: ZeroAxes, c0: FloatArray) -> None:
        super().__init__(ax, c0)
        self.inverse = np.linalg.inv(ax.w[:3].T)

    def place(self, p: FloatArray, hint: FloatArray | None) -> Placed:
        q = (p - self.c0) @ self.inverse.T
        return Placed(q[:, None, :], np.ones((len(p), 1), dtype=bool), {})


class Cylindrical(PositionFamily):
    """A turning column and two slides: two solutions, front and back."""

    name, words = "cylindrical arm", "a turning column and two slides"
    count = 2
    slots = (Branch("front"), Branch("back"))
    singularities = {
        "shoulder": SHOULDER,
        "radial": Singularity("the point is as close to axis 1 as the slides can bring it: "
                              "the front and back solutions coincide", ()),
    }

    def __init__(self, ax: ZeroAxes, c0: FloatArray) -> None:
        super().__init__(ax, c0)
        w1 = ax.w[0]
        e1 = np.cross(w1, [1.0, 0.0, 0.0] if abs(w1[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        self.basis = np.stack([e1, np.cross(w1, e1), w1])  # rows: axis-1 coordinates
        u = ax.w[1:3] @ self.basis.T  # the slides in those coordinates, (2, 3)
        self.height = int(np.argmax(np.abs(u[:, 2])))  # the slide that sets the height
        j, k = self.height, 1 - self.height
        self.u_h, self.u_r = u[j], u[k]
        self.c = self.basis @ (self.c0 - ax.r[0])
        #: radial part: v_xy = A(h) + q_k B, with B fixed
        self.B = self.u_r[:2] - (self.u_r[2] / self.u_h[2]) * self.u_h[:2]

    def _line(self, p: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``A (N, 2)``, the target in axis-1 coordinates ``(N, 3)``, and ``rho (N,)``."""
        t = (p - self.ax.r[0]) @ self.basis.T
        A = self.c[:2] + ((t[:, 2] - self.c[2]) / self.u_h[2])[:, None] * self.u_h[:2]
        return A, t, np.hypot(t[:, 0], t[:, 1])

    def place(self, p: FloatArray, hint: FloatArray | None) -> Placed:
        A, t, rho = self._line(p)
        B = self.B
        BB = float(B @ B)
        AB = A @ B
        cross = A[:, 0] * B[1] - A[:, 1] * B[0]
        disc = BB * rho * rho - cross * cross  # |B|^2 (rho^2 - d^2), d: the line's distance
        tol = REACH_TOL * self.size
        ok = disc >= -2.0 * BB * tol * np.maximum(rho, tol)  # rho short of d by <= tol
        root = np.sqrt(np.maximum(disc, 0.0))
        qk = np.stack([(-AB + root) / BB, (-AB - root) / BB], axis=-1)  # (N, 2)
        qh = (t[:, 2, None] - self.c[2] - qk * self.u_r[2]) / self.u_h[2]
        v = A[:, None, :] + qk[..., None] * B  # the point's part across axis 1, (N, 2, 2)
        v3 = np.concatenate([v, np.zeros(v.shape[:-1] + (1,))], axis=-1)
        t3 = np.concatenate([t[:, :2], np.zeros((len(t), 1))], axis=-1)
        h = 0.0 if hint is None else float(hint[0])
        q1, _ = turn_angle(np.array([0.0, 0.0, 1.0]), v3, t3[:, None, :], h)
        on_axis = rho <= AXIS_TOL * self.size
        q1 = np.where(on_axis[:, None], h, q1)
        q = np.empty((len(p), 2, 3))
        q[..., 0] = q1
        q[..., 1 + self.height] = qh
        q[..., 2 - self.height] = qk
        both = lambda m: np.repeat(m[:, None], 2, axis=1)  # noqa: E731
        return Placed(q, both(ok), {"shoulder": both(on_axis & ok),
                                    "radial": both((root <= SINGULAR_TOL * np.sqrt(BB) * self.size)
                                                   & ok)})

    def gap(self, p: FloatArray, active: np.ndarray | None) -> Gap:
        """Inside the cylinder around axis 1 that the slides' line cannot enter: the
        distance to its wall, along the way out from axis 1."""
        A, t, rho = self._line(p)
        B = self.B
        d = np.abs(A[:, 0] * B[1] - A[:, 1] * B[0]) / np.sqrt(B @ B)
        if active is None:
            active = (rho < d)[:, None]
        on = active[:, 0] & (rho > 0)  # on axis 1 no way out is nearest: none taken
        out = np.zeros((len(p), 3))
        safe = np.where(on, rho, 1.0)
        out[:, :2] = t[:, :2] / safe[:, None]
        J = np.where(on[:, None], -(out @ self.basis), 0.0)[:, None, :]
        return np.where(on, d - rho, 0.0)[:, None], J, on[:, None]

    def explain(self, p: FloatArray, units: str, what: str) -> tuple[str, float]:
        A, _, rho = self._line(p[None])
        B = self.B
        d = float(abs(A[0, 0] * B[1] - A[0, 1] * B[0]) / np.sqrt(B @ B))
        u = _units(units)
        ex = d - float(rho[0])
        return (f"{what} is {float(rho[0]):.6g}{u} from axis 1, {ex:.4g}{u} closer than the "
                f"slides can bring it at that height ({d:.6g}{u})", ex)


class Spherical(PositionFamily):
    """Two turning axes that meet in ``O`` and a slide (the boom): up to four solutions."""

    name, words = "spherical (polar) arm", "two turning axes that meet, and a slide (the boom)"
    count = 4
    slots = (Branch(None, "towards"), Branch(None, "towards"),
             Branch(None, "away"), Branch(None, "away"))
    singularities = {
        "shoulder": SHOULDER,
        "boom": Singularity("the target is as close to the shoulder point as the boom's "
                            "line passes: its two slide values coincide", ()),
        "turns": Singularity("the two ways joints 1-2 turn the boom onto the target coincide",
                             ()),
        "upper_arm": Singularity("the point is on the axis of joint 2, so q2 is free", (2,)),
    }

    def __init__(self, ax: ZeroAxes, c0: FloatArray, centre: FloatArray) -> None:
        super().__init__(ax, c0)
        self.O = np.asarray(centre, dtype=float)
        self.x0 = self.c0 - self.O
        w1, w2, u3 = ax.w[0], ax.w[1], ax.w[2]
        # link 1's forward side: across axes 1 and 2, where the boom points at q = 0 (or,
        # when it points along axis 1 there, where joint 2 tilts it)
        fwd = np.cross(w2, w1)
        fwd /= np.linalg.norm(fwd)
        lean = float(u3 @ fwd)
        if abs(lean) < 1e-9:
            lean = float(np.cross(w2, u3) @ fwd)
        self.forward = fwd if lean >= 0 else -fwd

    def _boom(self, R2: FloatArray) -> tuple[FloatArray, FloatArray, float]:
        """The slide's two roots ``(N, 2)`` for squared distances ``R2 (N,)`` from O, the
        discriminant ``(N,)``, and the line's squared distance from O."""
        b = float(self.x0 @ self.ax.w[2])
        e2 = float(self.x0 @ self.x0) - b * b
        disc = R2 - e2
        root = np.sqrt(np.maximum(disc, 0.0))
        return np.stack([-b + root, -b - root], axis=-1), disc, e2

    def place(self, p: FloatArray, hint: FloatArray | None) -> Placed:
        w1, w2, u3 = self.ax.w[0], self.ax.w[1], self.ax.w[2]
        v = p - self.O
        R2 = np.einsum("ni,ni->n", v, v)
        q3, disc, _ = self._boom(R2)
        tol = REACH_TOL * self.size
        ok3 = disc >= -2.0 * tol * np.sqrt(np.maximum(R2, tol * tol))
        x = self.x0 + q3[..., None] * u3  # the boom's point at q1 = q2 = 0, (N, 2, 3)
        z, g2 = two_turns(w1, w2, x, v[:, None, :])  # (N, 2, 2, 3), (N, 2)
        ok = ok3[:, None] & (g2 >= -2.0 * REACH_TOL)
        h1, h2 = (0.0, 0.0) if hint is None else (float(hint[0]), float(hint[1]))
        q2, free2 = turn_angle(w2, x[:, :, None, :], z, h2)
        q1, _ = turn_angle(w1, z, v[:, None, None, :], h1)
        across = v - (v @ w1)[:, None] * w1
        on_axis = np.linalg.norm(across, axis=-1) <= AXIS_TOL * self.size
        q1 = np.where(on_axis[:, None, None], h1, q1)
        N = len(p)
        q = np.empty((N, 2, 2, 3))
        q[..., 0], q[..., 1], q[..., 2] = q1, q2, q3[..., None]
        front = np.einsum("nabi,ni->nab", rotate(w1, q1, self.forward), v) >= 0.0
        flat = lambda m: np.reshape(m, (N, 4))  # noqa: E731
        okk = np.repeat(ok[..., None], 2, axis=-1)
        return Placed(
            q.reshape(N, 4, 3), flat(okk),
            {"shoulder": flat(np.broadcast_to(on_axis[:, None, None], (N, 2, 2))) & flat(okk),
             "boom": flat(np.broadcast_to((disc <= SINGULAR_TOL * self.size * self.size)
                                          [:, None, None], (N, 2, 2))) & flat(okk),
             "turns": flat(np.repeat((np.abs(g2) <= SINGULAR_TOL)[..., None], 2, axis=-1))
             & flat(okk) & ~flat(np.broadcast_to(on_axis[:, None, None], (N, 2, 2))),
             "upper_arm": flat(free2) & flat(okk)},
            shoulder_front=flat(front),
        )

    def gap(self, p: FloatArray, active: np.ndarray | None) -> Gap:
        """Two walls the boom cannot pass: the sphere around the shoulder point its line
        never comes closer than, and the cylinder around axis 1 of the boom's offset along
        axis 2 (the Stanford arm's d2): the distance inside each, outwards."""
        w1, w2 = self.ax.w[0], self.ax.w[1]
        v = p - self.O
        R = np.linalg.norm(v, axis=-1)
        _, disc, e2 = self._boom(R * R)
        e = np.sqrt(e2)
        side = abs(float(self.x0 @ w2))  # the boom's offset along axis 2
        across = v - (v @ w1)[:, None] * w1
        rho = np.linalg.norm(across, axis=-1)
        if active is None:
            active = np.stack([R < e, rho < side], axis=-1)
        on = active & np.stack([R > 0, rho > 0], axis=-1)
        J = np.zeros((len(p), 2, 3))
        J[:, 0] = -v / np.where(on[:, 0], R, 1.0)[:, None]
        J[:, 1] = -across / np.where(on[:, 1], rho, 1.0)[:, None]
        J[~on] = 0.0
        r = np.stack([e - R, side - rho], axis=-1)
        return np.where(on, r, 0.0), J, on

    def explain(self, p: FloatArray, units: str, what: str) -> tuple[str, float]:
        v = p - self.O
        R = float(np.linalg.norm(v))
        _, disc, e2 = self._boom(np.array([R * R]))
        u = _units(units)
        e = float(np.sqrt(e2))
        if disc[0] < 0:
            return (f"{what} is {R:.6g}{u} from the point where axes 1 and 2 meet, {e - R:.4g}{u} "
                    f"closer than the boom's line ever passes it ({e:.6g}{u})", e - R)
        w1 = self.ax.w[0]
        rho = float(np.linalg.norm(v - (v @ w1) * w1))
        side = abs(float(self.x0 @ self.ax.w[1]))
        return (f"{what} is {rho:.6g}{u} from axis 1, {side - rho:.4g}{u} inside the cylinder "
                f"of radius {side:.6g}{u} around it (the boom's offset along axis 2) that "
                "joints 1-2 cannot turn the boom into", side - rho)


class Scara(PositionFamily):
    """Two parallel turning axes and a quill along them: two solutions (elbow right, left)."""

    name, words = "SCARA", "two parallel turning axes and a quill along them"
    count = 2
    slots = (Branch(None, "right"), Branch(None, "left"))
    singularities = {
        "elbow": Singularity("links 1-2 are fully stretched or folded: the two elbows "
                             "coincide", ()),
        "origin": Singularity("links 1 and 2 are equal and folded, so the point is on the "
                              "axis of joint 1 and q1 is free", (1,)),
    }

    def __init__(self, ax: ZeroAxes, c0: FloatArray) -> None:
        super().__init__(ax, c0)
        w1, r1 = ax.w[0], ax.r[0]
        self.s2 = float(np.sign(ax.w[1] @ w1))
        a = self._across(ax.r[1] - r1)
        self.L1 = float(np.linalg.norm(a))
        e1 = a / self.L1
        self.basis = np.stack([e1, np.cross(w1, e1)])  # the plane across the axes
        self.k = float(ax.w[2] @ w1)  # how far the quill moves along axis 1 per unit
        e = self.basis @ (c0 - ax.r[1])
        self.L2 = float(np.hypot(e[0], e[1]))
        self.phi0 = float(np.arctan2(e[1], e[0]))  # link 2's angle from link 1 at q = 0

    def _across(self, v: FloatArray) -> FloatArray:
        w1 = self.ax.w[0]
        return v - (v @ w1)[..., None] * w1

    def place(self, p: FloatArray, hint: FloatArray | None) -> Placed:
        w1 = self.ax.w[0]
        q3 = ((p - self.c0) @ w1) / self.k
        t = (p - self.ax.r[0]) @ self.basis.T  # (N, 2) in the plane
        parts = two_link_parts(t[:, 0], t[:, 1], self.L1, self.L2)
        A, B = two_link_slots(parts)
        h = 0.0 if hint is None else float(hint[0])
        A = np.where(parts.fold[:, None], h, A)
        q = np.empty((len(p), 2, 3))
        q[..., 0] = A
        q[..., 1] = self.s2 * (B - self.phi0)
        q[..., 2] = q3[:, None]
        both = lambda m: np.repeat(m[:, None], 2, axis=1)  # noqa: E731
        ok = parts.reachable
        return Placed(q, both(ok), {"elbow": both(parts.stretched & ok),
                                    "origin": both(parts.fold & ok)})

    def gap(self, p: FloatArray, active: np.ndarray | None) -> Gap:
        """Across the axes, the annulus links 1-2 sweep around axis 1: the distance beyond
        it (or inside its hole), along the way from axis 1."""
        t = (p - self.ax.r[0]) @ self.basis.T
        d = np.hypot(t[:, 0], t[:, 1])
        r = d - np.clip(d, abs(self.L1 - self.L2), self.L1 + self.L2)
        if active is None:
            active = (r != 0.0)[:, None]
        on = active[:, 0] & (d > 0)
        J = ((t / np.where(on, d, 1.0)[:, None]) @ self.basis)[:, None, :]
        return np.where(on, r, 0.0)[:, None], np.where(on[:, None, None], J, 0.0), on[:, None]

    def explain(self, p: FloatArray, units: str, what: str) -> tuple[str, float]:
        t = (p - self.ax.r[0]) @ self.basis.T
        d = float(np.hypot(t[0], t[1]))
        ex = float(reach_excess(np.array(d), self.L1, self.L2))
        u = _units(units)
        if d > self.L1 + self.L2:
            return (f"{what} is {ex:.4g}{u} beyond the reach of links 1-2 (distance "
                    f"{d:.6g}{u} from axis 1, reach {self.L1 + self.L2:.6g}{u})", ex)
        return (f"{what} is {ex:.4g}{u} too close to axis 1 for links 1-2 (distance {d:.6g}{u}, "
                f"the folded arm reaches no closer than {abs(self.L1 - self.L2):.6g}{u})", ex)


def check_family(arm: SerialArm, family: PositionFamily, c_n: FloatArray, types: str) -> None:
    """Raise InputError unless ``family`` solves joints 1-3 of ``arm`` (in DH joint values)
    placing ``c_n`` (frame n): its joint types, and at random joint values the joints that
    placed the point are among what ``family`` finds for it."""
    if arm.joint_types != types:
        raise InputError(f"{arm.name}: the {family.name} solver was fitted to a {types} arm, "
                         f"got {arm.joint_types}")
    q = fit_joints(arm)
    F = arm._flange._fk(q)
    placed = family.place(F[:, :3, :3] @ c_n + F[:, :3, 3], None)
    if not finds_joints(arm, q, placed.q, placed.valid):
        raise InputError(f"{arm.name}: its joints 1-3 are not the {family.name} this solver was "
                         "fitted to (it misses the joints that placed a point)")


def fit_joints(arm: SerialArm) -> FloatArray:
    """Eight seeded random joint vectors ``(8, n)`` of ``arm`` (DH joint values; a slide's
    up to pi times the arm's size), at which a fitted solver is checked."""
    rng = np.random.default_rng(1)
    q = rng.uniform(-np.pi, np.pi, size=(8, arm.n))
    q[:, np.logical_not(arm.revolute)] *= arm.scale * rng.uniform(0.1, 1.0, size=(8, 1))
    return q


def finds_joints(arm: SerialArm, q: FloatArray, found: FloatArray, valid: np.ndarray) -> bool:
    """Whether each of the joint vectors ``q (N, n)`` has its first ``m`` joints among
    ``found (N, k, m)`` (the valid slots, ``valid (N, k)``) within ``FIT_TOL`` (radians; a
    slide's relative to the arm's size)."""
    m = found.shape[-1]
    d = np.abs(found - q[:, None, :m])
    d = np.where(np.logical_not(arm.revolute[:m]), d / arm.scale,
                 np.abs(np.remainder(d + np.pi, 2 * np.pi) - np.pi))
    d = np.where(valid[..., None], d, np.inf)
    return bool((d.max(axis=-1).min(axis=-1) <= FIT_TOL).all())


#: How close (rad, or relative to the arm's size) a fitted family finds the joints.
FIT_TOL = 1e-7


class PositioningSolver(ClosedForm):
    """Closed-form IK of a 3-joint positioning arm of the exercises: the TCP's position."""

    target_kind = "position"
    wrist_middle = None

    def __init__(self, family: PositionFamily, types: str) -> None:
        self.family, self.types = family, types
        self.count = family.count
        self.singularities = family.singularities
        self.slots = family.slots

    def check(self, arm: SerialArm) -> None:
        """Raise InputError unless ``arm`` is the arm this solver was fitted to."""
        check_family(arm, self.family, np.zeros(3), self.types)

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        placed = self.family.place(T_0_n[:, :3, 3], hint)
        return RawSolutions(q=placed.q, valid=placed.valid, slots=self.slots,
                            shoulder_front=placed.shoulder_front, singular=placed.singular)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        message, excess = self.family.explain(T_0_n[:3, 3], arm.units, "the target")
        return message + rounding_note(arm, T_0_n[:3, 3]), excess

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable`: a target rounded off the reach moved
        onto it."""
        return nearest_reachable(arm, self.family.gap, T_world, np.zeros(3))


class WristedSolver(ClosedForm):
    """Closed-form IK of a positioning arm of the exercises with a spherical wrist: joints
    1-3 place the wrist centre, joints 4-6 turn the tool, two ways (Aula 10's decoupling)."""

    target_kind = "pose"
    wrist_middle = 4

    def __init__(self, family: PositionFamily, arm: SerialArm) -> None:
        self.family, self.types = family, arm.joint_types
        self.count = 2 * family.count
        self.wrist = wrist_model(arm, 3)
        self.singularities = {**family.singularities, "wrist": WRIST}
        labels = wrist_slot_labels(self.wrist)
        self.slots = tuple(Branch(b.shoulder, b.elbow, labels[k])
                           for b in family.slots for k in (0, 1))

    def check(self, arm: SerialArm) -> None:
        """Raise InputError unless ``arm`` is the arm this solver was fitted to: its
        positioning joints (:func:`check_family`) and the same spherical wrist."""
        check_family(arm, self.family, self.wrist.centre, self.types)
        W, mine = wrist_model(arm, 3), self.wrist
        same = (W.s == mine.s and np.allclose(W.pre, mine.pre, atol=FIT_TOL)
                and np.allclose(W.post, mine.post, atol=FIT_TOL)
                and np.allclose(W.offsets, mine.offsets, atol=FIT_TOL)
                and np.allclose(W.centre, mine.centre, atol=FIT_TOL * arm.scale))
        if not same:
            raise InputError(f"{arm.name}: its wrist is not the one this solver was fitted to")

    def solve(self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None) -> RawSolutions:
        R_0_6 = T_0_n[:, :3, :3]
        pw = R_0_6 @ self.wrist.centre + T_0_n[:, :3, 3]
        placed = self.family.place(pw, hint)
        N, k = placed.valid.shape
        R_0_3 = rotation_0_3(arm, placed.q)  # (N, k, 3, 3)
        R_3_6 = np.swapaxes(R_0_3, -1, -2) @ R_0_6[:, None]
        q456, wsing = wrist_angles(self.wrist, R_3_6, 0.0 if hint is None else hint[3])
        q = np.empty((N, k, 2, 6))
        q[..., :3] = placed.q[:, :, None, :]
        q[..., 3:] = q456
        per = lambda m: np.repeat(m, 2, axis=1)  # noqa: E731
        singular = {name: per(m) for name, m in placed.singular.items()}
        singular["wrist"] = per(wsing & placed.valid)
        front = None if placed.shoulder_front is None else per(placed.shoulder_front)
        return RawSolutions(q=q.reshape(N, 2 * k, 6), valid=per(placed.valid), slots=self.slots,
                            shoulder_front=front, singular=singular)

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        pw = T_0_n[:3, :3] @ self.wrist.centre + T_0_n[:3, 3]
        message, excess = self.family.explain(pw, arm.units, "the wrist centre")
        return message + rounding_note(arm, pw), excess

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable`: the wrist centre of a pose rounded off
        the reach moved onto it."""
        return nearest_reachable(arm, self.family.gap, T_world, self.wrist.centre)
