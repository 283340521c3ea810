"""Closed-form IK of any 6R arm with a spherical wrist, read from its DH table (Pieper).

Every revolute DH link, standard or modified, is ``A_i = P_i Rz(theta_i) Q_i``
with constant ``P_i, Q_i`` (standard: ``P = I, Q = Tz(d) Tx(a) Rx(alpha)``;
modified: ``P = Rx(alpha) Tx(a), Q = Tz(d)``), so the whole arm is

    T_0_6 = M0 Rz(th1) M1 Rz(th2) M2 Rz(th3) M3 Rz(th4) M4 Rz(th5) M5 Rz(th6) M6

with ``M0 = P_1``, ``M_i = Q_i P_{i+1}``, ``M6 = Q_6`` and ``th_i = q_i + offset_i``.
Each ``M_i`` (i = 1..5) is again of the form ``Tz(d) Tx(a) Rx(alpha)``: the
distance ``a``, offset ``d`` and twist ``alpha`` between axes i and i+1.

The arm has a *spherical wrist* when axes 4, 5 and 6 meet in one point ``c``,
the wrist centre. Then (Pieper 1968) the pose splits in two problems:

1. **position**: joints 1-3 put the wrist centre where the target puts it,
   ``Rz(th1) M1 Rz(th2) M2 Rz(th3) v = p'``. Writing ``g(th3) = M2 Rz(th3) v``,
   the rotation about axis 1 keeps the height ``p'_z`` and the distance
   ``|p'|``; with ``M1 = (a1, d1, alpha1)`` that gives two equations in
   ``th2, th3``::

       2 a1 (c2 g_x - s2 g_y)        = |p'|^2 - |g|^2 - a1^2 + d1^2 - 2 d1 p'_z
       sin(alpha1) (s2 g_x + c2 g_y) = p'_z - d1 - cos(alpha1) g_z

   Squaring and adding removes ``th2`` and leaves a trigonometric polynomial
   of degree 2 in ``th3`` (a quartic, up to 4 roots). When axes 1 and 2 meet
   (``a1 = 0``) or are parallel (``sin alpha1 = 0``) one equation alone fixes
   ``th3`` (a quadratic: 2 roots) and the other gives 2 values of ``th2``.
   ``th1`` then turns the point into place.
2. **orientation**: ``Rz(th4) Rx(b1) Rz(th5) Rx(b2) Rz(th6) = R_w``, the
   wrist's rotation left after joints 1-3; two solutions (no-flip and flip).

Up to 8 solutions in all, in 8 fixed slots (position slot ``a`` times wrist
slot ``b`` -> ``2 a + b``). Every solution is polished by two Gauss-Newton
steps on the full pose and kept only if it reaches the target.
"""

from __future__ import annotations

import itertools
import math
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import FloatArray
from ..dh import SerialArm, check_arm
from ..errors import InputError
from ..tolerances import REACH_TOL, ROUNDED_POSE_TOL, SINGULAR_TOL
from .base import RawSolutions, Singularity, TargetKind
from .kernels import cross3, spherical_wrist, wrap_in_place
from .kernels import ferrari as _ferrari
from .pieper_batch import PieperBatchKernel, batch_kernel
from .pieper_kernel import PieperKernel, single_kernel
from .reach import nearest_reachable, rounding_note
from .result import Branch

__all__ = ["IKClass", "classify", "Pieper6RSolver", "general_solver"]

#: Axes closer than this (relative to the arm's size) meet; twists whose sine is
#: below it are parallel axes. DH tables are typed with exact zeros, so this
#: only absorbs the rounding of ``cos(pi / 2)``.
GEOMETRY_TOL = 1e-9

#: A root ``z`` of the quartic counts as real (``|z| = 1``) within this. A double
#: root (arm at its reach) splits into a pair ``1 +- ~sqrt(eps)``; the final FK
#: check decides whether the polished solution reaches the target.
ROOT_TOL = 1e-5

#: A polished solution is kept when its pose error (position / arm size, and
#: rotation) is at most this: the reach slack of the lesson solvers.
ACCEPT_TOL = max(REACH_TOL, 1e-10)

#: Joint values closer than this (rad) are one root of the closed form.
SAME_ROOT_TOL = 1e-7

#: Two position branches nearer than this (rad, each joint) are compared for
#: coinciding (see ``Pieper6RSolver._merge_coinciding``); branches farther apart
#: are always distinct solutions.
NEAR_PAIR = 1e-2

#: Two branches coincide when the pose error halfway between them is at most this
#: many times that of either, or below ``COINCIDE_FLOOR`` (a few rounding units).
COINCIDE_FACTOR = 4.0
COINCIDE_FLOOR = 2e-15
#: Gauss-Newton steps that put the midpoint of two close roots on the valley's floor
VALLEY_STEPS = 3

POSITION_SLOTS = 4

#: |sin q5| below this on a wrist whose axes 4 and 6 do not line up: the wrist is at
#: its fold (axes 4, 5, 6 coplanar), known only to ~sqrt(rounding) there.
WRIST_FOLD_TOL = 1e-6

#: A wrist centre closer than this to axis 1 (relative to the arm's size) may hide
#: its second shoulder in a rounded double root (see ``_split_near_axis``).
NEAR_AXIS = 1e-6

#: A wrist centre closer than this to axis 1 (relative to the arm's size; ten times the
#: kernels' ``NEAR_AXIS1``, below which they hand the pose to this solver) has its two
#: shoulders re-solved from the local geometry (``_axis_pairs``) where the closed form
#: gives them as two joint-2/3 roots within ``AXIS_PAIR_GAP`` (rad) of each other.
AXIS_PAIR = 1e-3
AXIS_PAIR_GAP = 1e-2
#: Newton steps onto the pair's midpoint: each squares the error (1e-7 rad, the rounding
#: of a double root, to 1e-14 to rounding)
AXIS_PAIR_STEPS = 4

#: A wrist centre this close to axis 1 or 2 (relative to the arm's size) leaves that
#: joint to rounding. Farther, but within ``SINGULAR_TOL``, the singularity is flagged and
#: the joint is free within the FK check; it takes ``near``'s value when the caller gives
#: one, else the pose's, which fixes it to ~ eps / distance (2.7e-10 of the arm's size
#: off the axis: 4e-4 rad; 1e-14: 0.2 rad), not an arbitrary 0.
DIRECTION_FLOOR = 1e-14

#: Singular values of the pose Jacobian below this (relative to the largest) are
#: rounding: the polish takes no step along them.
POLISH_RCOND = 1e-13

#: The polish's fallback step keeps only directions above this (relative).
STRONG_RCOND = 1e-6

#: Polishing stops once every pose error (relative) is below this, or stops improving:
#: rounding level (a pair of roots near a fold is told apart only there).
POLISHED = 5e-16

#: Joints 2 and 3 move the wrist centre along one line (the elbow at a fold) when the
#: smaller of their velocities, across the larger's direction, is below this (relative to
#: the arm's size): a pose within rounding of a fold is ~1e-8 from it, a bent arm ~1.
ELBOW_FOLD = 1e-4

#: A solution with no other within ``NEAR_PAIR`` stops polishing already below this
#: pose error: tens of rounding units, a millionth of the FK check's tolerance. (Only a
#: close pair needs its ends at rounding level, to be told apart from one solution.)
POLISHED_ALONE = 1e-14

#: ... or once a solution's step has been shortened below this fraction.
MIN_STEP = 1e-3

SHOULDER = Singularity(
    "the wrist centre is on the axis of joint 1, so q1 is free", (1,)
)
UPPER_ARM = Singularity(
    "the wrist centre is on the axis of joint 2, so q2 is free", (2,)
)
ELBOW = Singularity(
    "the wrist centre is at the edge of what joints 1-3 reach: two position branches coincide",
    (),
)
WRIST = Singularity(
    "wrist singularity: axes 4 and 6 line up, so only q4 + q6 (or q4 - q6) is fixed",
    (4, 6),
    drop_flip=True,
)

WRIST_FOLD = Singularity(
    "wrist singularity: axes 4, 5 and 6 lie in one plane (q5 = 0 or pi on a wrist whose "
    "twists are not 90 deg), so the tool is at the least or most tilt this wrist reaches "
    "and its two branches coincide",
    (),
)


# ------------------------------------------------------------------ geometry
def _rx(alpha: float) -> FloatArray:
    c, s = math.cos(alpha), math.sin(alpha)
    if abs(c) < 1e-15:  # cos(pi / 2) is 6e-17, not 0: keep the table's exact zeros
        c = 0.0
    if abs(s) < 1e-15:
        s = 0.0
    return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _translate(x: float = 0.0, z: float = 0.0) -> FloatArray:
    T = np.eye(4)
    T[0, 3], T[2, 3] = x, z
    return T


@dataclass(frozen=True)
class ChainModel:
    """An arm as ``M0 Rz(th1) M1 ... Rz(th6) M6`` (see the module docstring).

    Attributes
    ----------
    M : ndarray, shape (7, 4, 4)
    offsets : ndarray, shape (6,)
        ``th_i = q_i + offsets[i - 1]``, rad.
    scale : float
        A length of the arm, for relative tolerances.
    """

    M: FloatArray
    offsets: FloatArray
    scale: float

    def dh(self, i: int) -> tuple[float, float, float]:
        """``(a, d, alpha)`` of ``M_i = Tz(d) Tx(a) Rx(alpha)``, i = 1..5."""
        Mi = self.M[i]
        return float(Mi[0, 3]), float(Mi[2, 3]), math.atan2(Mi[2, 1], Mi[1, 1])


def chain_model(arm: SerialArm) -> ChainModel:
    """The constant factors of a 6R arm's FK (no base, no tool)."""
    P, Q = [], []
    for lk in arm.links:
        d, a, al = float(lk.d), float(lk.a), float(lk.alpha)
        if arm.convention == "standard":
            P.append(np.eye(4))
            Q.append(_translate(a, d) @ _rx(al))
        else:
            P.append(_rx(al) @ _translate(a, 0.0))
            Q.append(_translate(0.0, d))
    M = [P[0]] + [Q[i] @ P[i + 1] for i in range(5)] + [Q[5]]
    offsets = np.array([float(lk.offset) for lk in arm.links])
    scale = max(sum(abs(float(lk.a)) + abs(float(lk.d)) for lk in arm.links), 1e-300)
    return ChainModel(np.stack(M), offsets, scale)


def _unit_model(model: ChainModel) -> tuple[ChainModel, float]:
    """``model`` with every length times ``unit = 2**k``, its size in [0.5, 1), and
    ``unit``: exact, unlike a division by the size itself (see
    :meth:`Pieper6RSolver._to_unit`)."""
    k = -math.frexp(model.scale)[1]
    M = model.M.copy()
    M[:, :3, 3] = np.ldexp(M[:, :3, 3], k)
    return ChainModel(M, model.offsets, math.ldexp(model.scale, k)), math.ldexp(1.0, k)


def _meet_geometry(model: ChainModel, wg: WristGeometry) -> tuple[float, float, float, float]:
    """``(m, M, phi, rho)`` of ``|g(th3)|^2 = G0 + rho cos(th3 - phi)``, the squared
    distance of the wrist centre from frame 2's origin, which it runs from ``m^2`` to
    ``M^2`` (see :meth:`Pieper6RSolver._th3_meet`)."""
    R2, t2 = model.M[2, :3, :3], model.M[2, :3, 3]
    u, v = R2.T @ t2, wg.v  # |g|^2 = |u|^2 + |v|^2 + 2 u . Rz(th3) v
    uxy, vxy, z = math.hypot(u[0], u[1]), math.hypot(v[0], v[1]), float(u[2] + v[2])
    # u . Rz v = u_z v_z + (u_x v_x + u_y v_y) cos + (u_y v_x - u_x v_y) sin
    phi = math.atan2(u[1] * v[0] - u[0] * v[1], u[0] * v[0] + u[1] * v[1])
    return math.hypot(uxy - vxy, z), math.hypot(uxy + vxy, z), phi, 2 * uxy * vxy


def _closest(p1: FloatArray, d1: FloatArray, p2: FloatArray, d2: FloatArray):
    """Closest points of two lines ``p + s d`` (unit ``d``): ``(s1, s2, distance)``,
    or None when the lines are parallel."""
    w0 = p1 - p2
    b = float(d1 @ d2)
    denom = 1.0 - b * b
    if denom < GEOMETRY_TOL**2:
        return None
    dd, ee = float(d1 @ w0), float(d2 @ w0)
    s1 = (b * ee - dd) / denom
    s2 = (ee - b * dd) / denom
    dist = float(np.linalg.norm(p1 + s1 * d1 - (p2 + s2 * d2)))
    return s1, s2, dist


@dataclass(frozen=True)
class WristGeometry:
    """Where the wrist centre sits, and the wrist's twists.

    ``c4``: the centre in the frame before ``Rz(th4)`` (on its z axis);
    ``c_flange``: the centre in the flange frame 6; ``v``: the centre in the
    frame after ``Rz(th3)`` (``M3 c4``); ``b1, b2``: the twists of ``M4, M5``.
    """

    c4: FloatArray
    c_flange: FloatArray
    v: FloatArray
    b1: float
    b2: float


def _units(arm: SerialArm) -> str:
    return f" {arm.units}" if arm.units else ""


def wrist_geometry(arm: SerialArm, model: ChainModel) -> WristGeometry | str:
    """The wrist centre of ``arm``, or the reason (text) why axes 4, 5, 6 do not meet."""
    tol = GEOMETRY_TOL * model.scale
    u = _units(arm)
    M4, M5, M6 = model.M[4], model.M[5], model.M[6]
    z = np.array([0.0, 0.0, 1.0])
    o = np.zeros(3)
    # axis 4 is the z axis of the frame before Rz(th4); axis 5 the z axis of M4 there
    hit = _closest(o, z, M4[:3, 3], M4[:3, 2])
    if hit is None:
        return "axes 4 and 5 are parallel, so the wrist has no centre"
    s4, _, dist = hit
    if dist > tol:
        return f"axes 4, 5, 6 do not meet: axis 5 passes {dist:.6g}{u} from axis 4"
    c4 = np.array([0.0, 0.0, s4])
    c5 = np.linalg.solve(M4, np.append(c4, 1.0))[:3]  # on axis 5 = z of that frame
    e6 = M5[:3, 2]
    if np.linalg.norm(np.cross(e6, z)) < GEOMETRY_TOL:
        return "axes 5 and 6 are parallel, so the wrist has no centre"
    off = c5 - M5[:3, 3]
    dist6 = float(np.linalg.norm(off - (off @ e6) * e6))
    if dist6 > tol:
        return (
            f"axes 4, 5, 6 do not meet: axis 6 passes {dist6:.6g}{u} from the point "
            "where axes 4 and 5 meet"
        )
    c6 = np.linalg.solve(M5, np.append(c5, 1.0))[:3]
    c_flange = np.linalg.solve(M6, np.append(c6, 1.0))[:3]
    v = (model.M[3] @ np.append(c4, 1.0))[:3]
    b1 = math.atan2(M4[2, 1], M4[1, 1])
    b2 = math.atan2(M5[2, 1], M5[1, 1])
    return WristGeometry(c4, c_flange, v, b1, b2)


@dataclass(frozen=True)
class IKClass:
    """Which closed form solves an arm, or why none does.

    Attributes
    ----------
    closed_form : bool
    family : str
        The solver in words (e.g. ``"6R with a spherical wrist: axes 1 and 2
        meet, so placing the wrist centre gives a quadratic equation in q3"``), or ``""``.
    reason : str
        Why there is no closed form, in the arm's terms; ``""`` when there is.
    solutions : int
        The most solutions a target has (0 when unknown or there is no closed form).
    fallback : str
        What rikin offers instead when there is no closed form (numerical IK).
    """

    closed_form: bool
    family: str = ""
    reason: str = ""
    solutions: int = 0
    fallback: str = ""

    def __str__(self) -> str:
        if self.closed_form:
            return self.family
        return f"no closed form: {self.reason}" + (f". {self.fallback}" if self.fallback else "")


def six_revolute_reason(arm: SerialArm) -> str:
    """Why ``arm`` is not a 6R arm (the general closed forms' arms), or ``""``."""
    if arm.n != 6:
        return f"it has {arm.n} joints; the general closed form is for six revolute joints"
    prismatic = [i + 1 for i, lk in enumerate(arm.links) if not lk.is_revolute]
    if prismatic:
        which = ", ".join(str(j) for j in prismatic)
        return (
            f"joint{'s' if len(prismatic) > 1 else ''} {which} "
            f"{'are' if len(prismatic) > 1 else 'is'} prismatic; the general closed form is "
            "for six revolute joints"
        )
    return ""


def _general_reason(arm: SerialArm) -> tuple[str, str]:
    """``(family, "")`` for an arm the general solver takes, else ``("", reason)``."""
    not_6r = six_revolute_reason(arm)
    if not_6r:
        return "", not_6r
    model = chain_model(arm)
    wg = wrist_geometry(arm, model)
    if isinstance(wg, str):
        return "", wg
    a1, _, al1 = model.dh(1)
    a2, _, al2 = model.dh(2)
    tol = GEOMETRY_TOL * model.scale
    meet12, parallel12 = abs(a1) <= tol, abs(math.sin(al1)) <= GEOMETRY_TOL
    if meet12 and parallel12:
        return "", "axes 1 and 2 are the same line, so joints 1 and 2 do the same motion"
    if abs(a2) <= tol and abs(math.sin(al2)) <= GEOMETRY_TOL:
        return "", "axes 2 and 3 are the same line, so joints 2 and 3 do the same motion"
    if math.hypot(wg.v[0], wg.v[1]) <= tol:
        return "", (
            "the wrist centre lies on axis 3, so joint 3 cannot move it and joints 1-2 "
            "alone cannot place it in 3D"
        )
    if not _positions_span_3d(model, wg):
        if abs(a2) <= tol and meet12:
            return "", (
                "axes 1, 2 and 3 meet in one point, so joints 1-3 only move the wrist centre "
                "on a sphere around it"
            )
        return "", (
            "joints 1-3 cannot move the wrist centre in three independent directions at any "
            "configuration"
        )
    if meet12:
        how = "axes 1 and 2 meet, so placing the wrist centre gives a quadratic equation in q3"
    elif parallel12:
        how = ("axes 1 and 2 are parallel, so placing the wrist centre gives a quadratic "
               "equation in q3")
    elif _planar_elbow(model, wg, al1):
        how = ("axes 1 and 2 are perpendicular, a shoulder offset apart (as on the KUKA KR "
               "5), and the elbow moves in a plane across axis 2, so placing the wrist centre "
               "gives a quadratic equation in its squared distance from the shoulder, then "
               "q3 from the elbow triangle")
    else:
        how = "axes 1 and 2 are skew, so placing the wrist centre gives a quartic equation in q3"
    return f"6R with a spherical wrist (Pieper's decoupling): {how}", ""


def _planar_elbow(model: ChainModel, wg: WristGeometry, al1: float) -> bool:
    """True when skew axes 1 and 2 are perpendicular and the wrist centre's height along
    axis 2 does not change with q3 (the kernel's ``planar`` case): the quartic is then a
    quadratic in ``|g|^2``, as :meth:`PieperKernel._th3_planar` solves it."""
    v, R2 = wg.v, model.M[2][:3, :3]
    gc_z = float(R2[2] @ np.array([v[0], v[1], 0.0]))
    gs_z = float(R2[2] @ np.array([-v[1], v[0], 0.0]))
    return (abs(math.cos(al1)) <= GEOMETRY_TOL
            and max(abs(gc_z), abs(gs_z)) <= GEOMETRY_TOL * model.scale)


def _positions_span_3d(model: ChainModel, wg: WristGeometry) -> bool:
    """True when joints 1-3 move the wrist centre in 3 independent directions somewhere
    (the position Jacobian has full rank at one of a few random configurations)."""
    rng = np.random.default_rng(0)
    th = rng.uniform(-np.pi, np.pi, size=(8, 3))
    M = model.M
    T = np.broadcast_to(M[0], (8, 4, 4))
    axes, origins = [], []
    for i in range(3):
        axes.append(T[:, :3, 2])
        origins.append(T[:, :3, 3])
        T = T @ _rz4(th[:, i]) @ M[i + 1]
    W = (T @ np.append(wg.c4, 1.0))[:, :3]
    J = np.stack([np.cross(z, W - o) for z, o in zip(axes, origins, strict=True)], axis=-1)
    sv = np.linalg.svd(J, compute_uv=False)
    return bool((sv[:, -1] > 1e-9 * model.scale).any())


def classify(arm: SerialArm) -> IKClass:
    """Which closed-form IK rikin uses for ``arm``, or exactly why it has none.

    Parameters
    ----------
    arm : SerialArm

    Returns
    -------
    IKClass
        ``closed_form`` and the family in words, or the reason in the arm's
        terms (e.g. ``"axes 4, 5, 6 do not meet: axis 5 passes 12 mm from
        axis 4"``).

    Examples
    --------
    >>> from rikin import robots
    >>> classify(robots.aula10_6r()).closed_form
    True
    """
    if not isinstance(arm, SerialArm):
        raise InputError(f"arm must be a rikin.SerialArm, got {type(arm).__name__}")
    arm = arm._dh  # the geometry, in DH joint values (a reversed joint changes nothing here)
    if arm.solver is not None:
        doc = (type(arm.solver).__doc__ or type(arm.solver).__name__).strip()
        return IKClass(True, " ".join(doc.split("\n\n")[0].split()),
                       solutions=getattr(arm.solver, "count", 0))
    family, reason = _general_reason(arm)
    return IKClass(not reason, family, reason, solutions=0 if reason else 8,
                   fallback=NUMERICAL if reason else "")


#: What rikin offers an arm with no closed form.
NUMERICAL = ("rikin.ik.ik_numerical finds one solution, the one its iteration falls into "
             "from a start q0; rikin.ik.ik_numerical_multistart tries many starts and lists "
             "the distinct solutions found, with no promise that none is missed")


_SOLVERS: weakref.WeakKeyDictionary[SerialArm, Pieper6RSolver] = weakref.WeakKeyDictionary()


def general_solver(arm: SerialArm) -> Pieper6RSolver:
    """The general closed-form solver for ``arm`` (built once per arm).

    Raises
    ------
    InputError
        The arm has no closed form; the message says why and points at the
        numerical IK.
    """
    check_arm(arm)
    solver = _SOLVERS.get(arm)
    if solver is None:
        family, reason = _general_reason(arm)
        if reason:
            raise InputError(f"{arm.name!r} has no closed-form IK in rikin: {reason}. "
                             f"Instead: {NUMERICAL}")
        solver = Pieper6RSolver(arm)
        _SOLVERS[arm] = solver
    return solver


# ------------------------------------------------------------------ batched FK
def _chain_fk(
    M: FloatArray, th: FloatArray, frames: bool = False
) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
    """``M0 Rz(th1) M1 ... Rz(th6) M6`` for joints ``th (..., 6)``: the flange poses
    ``(..., 4, 4)`` and, with ``frames``, the joint axes and origins ``(..., 6, 3)``.

    ``Rz(th_i) M_i`` for all joints at once, then their running product from ``M0``:
    stacked 4x4 products, which numpy hands to BLAS one 4x4 product at a time, the same
    call for every row. So a row's result does not depend on how many other rows there are
    or where it stands among them, and a pose is solved alike alone and in a batch (one
    product of a ``(n, 4)`` by a ``(4, 4)`` matrix would be rounded by BLAS's blocking of
    the n rows; an algorithm chosen by the number of rows, by that choice).
    """
    shape = th.shape[:-1]
    rows = th.reshape(-1, 6)
    n = rows.shape[0]
    c, s = np.cos(rows), np.sin(rows)
    RM = np.zeros((n, 6, 4, 4))
    RM[..., 0, 0], RM[..., 0, 1], RM[..., 1, 0], RM[..., 1, 1] = c, -s, s, c
    RM[..., 2, 2] = RM[..., 3, 3] = 1.0
    RM = RM @ M[1:]
    A = np.broadcast_to(M[0], (n, 4, 4))
    before = np.empty((n, 6, 4, 4)) if frames else None
    for i in range(6):
        if before is not None:
            before[:, i] = A
        A = A @ RM[:, i]
    T = A.reshape(shape + (4, 4))
    if before is None:
        return T, None, None
    return (T, before[:, :, :3, 2].reshape(shape + (6, 3)),
            before[:, :, :3, 3].reshape(shape + (6, 3)))


# ------------------------------------------------------------------ batched helpers
def _rz4(theta: FloatArray) -> FloatArray:
    """``Rz(theta)`` as 4x4 matrices, shape ``theta.shape + (4, 4)``."""
    c, s = np.cos(theta), np.sin(theta)
    R = np.zeros(np.shape(theta) + (4, 4))
    R[..., 0, 0], R[..., 0, 1], R[..., 1, 0], R[..., 1, 1] = c, -s, s, c
    R[..., 2, 2] = R[..., 3, 3] = 1.0
    return R


def _solve_sinusoid(
    a: FloatArray, b: FloatArray, c: FloatArray
) -> tuple[FloatArray, FloatArray, np.ndarray, np.ndarray]:
    """Both ``x`` with ``a cos x + b sin x = c``: ``(x+, x-, reachable, degenerate)``.

    ``degenerate`` where ``a = b = 0`` (every x, or none).
    """
    rho = np.hypot(a, b)
    degenerate = rho <= 1e-300
    safe = np.where(degenerate, 1.0, rho)
    ratio = c / safe
    reachable = ~degenerate & (np.abs(ratio) <= 1.0 + math.sqrt(REACH_TOL))
    phi = np.arctan2(b, a)
    delta = np.arccos(np.clip(ratio, -1.0, 1.0))
    return phi + delta, phi - delta, reachable, degenerate


def _slot_pairs(n: int) -> tuple[list[tuple[int, int]], np.ndarray, np.ndarray]:
    """The pairs of slots of different position branches among ``n`` (a branch's two
    wrist slots are ``2 k`` and ``2 k + 1``), as a list and as index arrays."""
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n) if i // 2 != j // 2]
    return pairs, np.array([i for i, _ in pairs]), np.array([j for _, j in pairs])


#: The six pairs of position branches, as index arrays.
_BRANCH_PAIRS = tuple(
    np.array(x) for x in zip(*itertools.combinations(range(POSITION_SLOTS), 2), strict=True)
)


def _close_pairs(
    th: FloatArray, valid: np.ndarray, ii: np.ndarray, jj: np.ndarray, margin: float = 1.0
) -> tuple[FloatArray, np.ndarray]:
    """Half the wrapped difference of each pair's joints ``(N, P, 6)``, and which pairs
    are both valid and within ``margin * NEAR_PAIR`` in every joint ``(N, P)``."""
    half = wrap_in_place(th[:, jj] - th[:, ii]) / 2
    close = valid[:, ii] & valid[:, jj] & (np.abs(half).max(-1) < margin * NEAR_PAIR)
    return half, close


def _trig2_roots(F: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """Real roots of trigonometric polynomials of degree 2 sampled at 5 angles.

    Parameters
    ----------
    F : ndarray, shape (N, 5)
        ``F(2 pi j / 5)`` for j = 0..4.

    Returns
    -------
    theta : ndarray, shape (N, 4)
    real : ndarray of bool, shape (N, 4)
        The root is real (on the unit circle), after Newton polishing. Real roots come
        first, by angle (of the unpolished root, in (-pi, pi]). A double root (the elbow at
        a fold) may come as two roots ~sqrt(rounding) apart, or as a complex pair within
        ``ROOT_TOL`` of the circle: both are kept, and whether they are one solution or two
        is decided on the whole pose (``Pieper6RSolver._merge_coinciding``), not on ``F``.
    """
    j = np.arange(5)
    ang = 2 * np.pi * j / 5
    a0 = F.mean(axis=1)
    # sums of products written out (F @ cos would be BLAS's, whose rounding depends on how
    # many rows F has: a root at a fold, known to ~sqrt(eps), would move with the batch)
    a = [2 / 5 * (F * np.cos(k * ang)).sum(-1) for k in (1, 2)]
    b = [2 / 5 * (F * np.sin(k * ang)).sum(-1) for k in (1, 2)]
    # z = exp(i theta): z^2 F = c2 z^4 + c1 z^3 + c0 z^2 + conj(c1) z + conj(c2)
    c2 = (a[1] - 1j * b[1]) / 2
    c1 = (a[0] - 1j * b[0]) / 2
    big = np.maximum.reduce([np.abs(c2), np.abs(c1), np.abs(a0)])
    big = np.where(big > 0, big, 1.0)
    N = F.shape[0]
    theta = np.zeros((N, 4))
    real = np.zeros((N, 4), dtype=bool)
    quartic = np.abs(c2) > 1e-12 * big
    if quartic.any():
        lead = c2[quartic]
        # monic: z^4 + A z^3 + B z^2 + C z + D; Ferrari's formulas, and the companion
        # matrix's eigenvalues where they are not confirmed (a multiple root or worse):
        # which of the two a pose takes is decided by that pose alone, not by the batch
        A, B = c1[quartic] / lead, a0[quartic] / lead
        C, D = np.conj(c1[quartic]) / lead, np.conj(lead) / lead
        z, sure = _ferrari(A, B, C, D)
        if not sure.all():
            unsure = ~sure
            M = np.zeros((int(unsure.sum()), 4, 4), dtype=complex)
            M[:, 1:, :3] = np.eye(3)
            for col, coef in enumerate((A, B, C, D)):
                M[:, 0, col] = -coef[unsure]
            z[unsure] = np.linalg.eigvals(M)
        th_q, real_q = np.angle(z), np.abs(np.abs(z) - 1.0) < ROOT_TOL
        # eigvals' order is LAPACK's: sort (real roots first, by angle) so that the slots,
        # and the solutions of arm.ik, come in an order the one-pose kernel can reproduce
        order = np.lexsort((th_q, ~real_q))
        theta[quartic] = np.take_along_axis(th_q, order, axis=1)
        real[quartic] = np.take_along_axis(real_q, order, axis=1)
    lin = ~quartic
    if lin.any():  # degree 1: a0 + a1 cos + b1 sin = 0
        xp, xm, ok, _ = _solve_sinusoid(a[0][lin], b[0][lin], -a0[lin])
        theta[lin, 0], theta[lin, 1] = xp, xm
        real[lin, 0] = real[lin, 1] = ok
    # Newton on F(theta) = a0 + sum a_k cos k theta + b_k sin k theta
    a1, a2, b1, b2 = a[0][:, None], a[1][:, None], b[0][:, None], b[1][:, None]
    for _ in range(3):
        cos1, sin1 = np.cos(theta), np.sin(theta)
        cos2, sin2 = cos1 * cos1 - sin1 * sin1, 2 * sin1 * cos1
        f = a0[:, None] + a1 * cos1 + b1 * sin1 + a2 * cos2 + b2 * sin2
        df = b1 * cos1 - a1 * sin1 + 2 * (b2 * cos2 - a2 * sin2)
        step = np.where(np.abs(df) > 1e-8 * big[:, None], f / np.where(df == 0, 1.0, df), 0.0)
        step = np.clip(step, -1e-3, 1e-3)
        theta = theta - step
    return theta, real


class ChainPolish:
    """Gauss-Newton polish of joint values on the whole pose, for solvers of an arm given as
    a :class:`ChainModel` (``self.model``)."""

    model: ChainModel

    def _fk_frames(self, th: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Flange pose, joint axes and origins for thetas ``(..., 6)``."""
        T, axes, origins = _chain_fk(self.model.M, th, frames=True)
        assert axes is not None and origins is not None
        return T, axes, origins

    def _pose_error(self, T: FloatArray, T_goal: FloatArray) -> FloatArray:
        """6-vector error ``(dp, dw)``: position and rotation (axis-angle, small) to the goal."""
        dp = T_goal[..., :3, 3] - T[..., :3, 3]
        Rd = T_goal[..., :3, :3] @ np.swapaxes(T[..., :3, :3], -1, -2)
        dw = 0.5 * np.stack(
            [Rd[..., 2, 1] - Rd[..., 1, 2], Rd[..., 0, 2] - Rd[..., 2, 0],
             Rd[..., 1, 0] - Rd[..., 0, 1]], axis=-1
        )
        return np.concatenate([dp, dw], axis=-1)

    def _step(
        self, th: FloatArray, goal: FloatArray, svd: tuple[FloatArray, ...], w: FloatArray,
        rcond: float, scale: FloatArray,
    ) -> list[FloatArray]:
        """One Gauss-Newton step of :meth:`_polish` for ``m`` solutions ``th (m, 6)``: the
        least-squares step through the SVD ``(sv, 1 / sv, Vt, U^T e)`` of the weighted
        Jacobians, directions below ``rcond`` (relative) dropped, times ``scale (m,)``.
        Returns the new joints and their flange poses, axes, origins, weighted errors and
        largest error."""
        sv, safe, Vt, Ue = svd
        inv = np.where(sv > rcond * sv[..., :1], safe, 0.0)
        step = (np.swapaxes(Vt, -1, -2) @ (inv[..., None] * Ue))[..., 0]
        cand = th + scale[:, None] * step
        Tc, zc, oc = self._fk_frames(cand)
        ec = self._pose_error(Tc, goal) * w
        return [cand, Tc, zc, oc, ec, np.abs(ec).max(-1)]

    def _polish(
        self, th: FloatArray, T_goal: FloatArray, alone: np.ndarray, steps: int = 16
    ) -> tuple[FloatArray, FloatArray]:
        """Gauss-Newton steps on the whole pose (least squares through the SVD), each
        shortened while it does not improve, until every error is at rounding level
        (``POLISHED``; ``POLISHED_ALONE`` where ``alone``, shape ``th.shape[:-1]``) or
        stops improving (at most ``steps``). Returns the joints and their flange poses.

        A simple root needs none or one. Near a fold of the arm (elbow at its reach, a
        non-orthogonal wrist with coplanar axes) a full step overshoots when the pose is
        outside the fold by rounding; shorter steps then walk to the fold, where the two
        branches meet and are one (see ``_merge_coinciding``).
        """
        L = self.model.scale
        w = np.array([1 / L] * 3 + [1.0] * 3)
        shape = th.shape
        th = th.reshape(-1, 6).copy()  # one row per solution; each step takes the busy ones
        goal = np.broadcast_to(T_goal, shape[:-1] + (4, 4)).reshape(-1, 4, 4)
        t = np.ones(len(th))  # the step's length, per solution
        enough = np.where(alone.reshape(-1), POLISHED_ALONE, POLISHED)
        T, z, o = self._fk_frames(th)
        e = self._pose_error(T, goal) * w
        err = np.abs(e).max(-1)
        for _ in range(steps):
            rows = np.flatnonzero((err > enough) & (t > MIN_STEP))
            if not rows.size:
                break
            th_b, T_b, z_b, o_b, e_b, err_b, t_b, goal_b = (
                x[rows] for x in (th, T, z, o, e, err, t, goal)
            )
            p_e = T_b[..., None, :3, 3]
            J = np.concatenate([cross3(z_b, p_e - o_b), z_b], axis=-1)  # (m, 6, 6): rows joints
            J = np.swapaxes(J, -1, -2) * w[:, None]
            # least squares through the SVD, directions below rounding dropped: a damped
            # step (J^T J + lambda) would not move along a fold's weak direction, whose
            # singular value is ~ the distance to the fold and may be 1e-7
            # ... or, when that step is no better, the one without the weak directions
            # (a wrist centre 1e-10 off axis 1 leaves q1 to them: the rest must give way)
            U, sv, Vt = np.linalg.svd(J)
            Ue = np.swapaxes(U, -1, -2) @ e_b[..., None]
            safe = 1.0 / np.where(sv > 0, sv, 1.0)

            svd = (sv, safe, Vt, Ue)
            best = self._step(th_b, goal_b, svd, w, POLISH_RCOND, t_b)
            retry = np.flatnonzero(~(best[5] < err_b))  # the second try only where it counts
            if retry.size:
                alt = self._step(th_b[retry], goal_b[retry], tuple(x[retry] for x in svd), w,
                                 STRONG_RCOND, np.ones(retry.size))
                use = alt[5] < best[5][retry]
                for x, y in zip(best, alt, strict=True):
                    x[retry[use]] = y[use]
            cand, Tc, zc, oc, ec, errc = best
            better = errc < err_b
            th[rows] = np.where(better[:, None], cand, th_b)
            T[rows] = np.where(better[:, None, None], Tc, T_b)
            z[rows] = np.where(better[:, None, None], zc, z_b)
            o[rows] = np.where(better[:, None, None], oc, o_b)
            e[rows] = np.where(better[:, None], ec, e_b)
            err[rows] = np.where(better, errc, err_b)
            t[rows] = np.where(better, np.minimum(1.0, 2.0 * t_b), t_b / 4.0)
        return th.reshape(shape), T.reshape(shape[:-1] + (4, 4))

    def _residual(self, th: FloatArray, T_goal: FloatArray) -> FloatArray:
        """FK error of joints ``th (..., 6)``: position over the arm's size, or rotation entry."""
        return self._residual_of(self._fk_frames(th)[0], T_goal)

    def _residual_of(self, T: FloatArray, T_goal: FloatArray) -> FloatArray:
        """:meth:`_residual` of the flange poses ``T (..., 4, 4)``."""
        pos = np.linalg.norm(T[..., :3, 3] - T_goal[..., :3, 3], axis=-1) / self.model.scale
        rot = np.abs(T[..., :3, :3] - T_goal[..., :3, :3]).max(axis=(-1, -2))
        return np.maximum(pos, rot)


class Pieper6RSolver(ChainPolish):
    """Closed-form IK of a 6R arm with a spherical wrist, from its DH table: up to 8 solutions."""

    target_kind: TargetKind = "pose"
    wrist_middle: int | None = 4
    labels_optional = True
    singularities = {
        "shoulder": SHOULDER,
        "upper_arm": UPPER_ARM,
        "elbow": ELBOW,
        "wrist": WRIST,
        "wrist_fold": WRIST_FOLD,
    }

    def __init__(self, arm: SerialArm) -> None:
        check_arm(arm)
        family, reason = _general_reason(arm)
        if reason:
            raise InputError(f"{arm.name}: {reason}")
        self.family = family
        # the solver works on the arm scaled by a power of two to a size near 1 (exact: the
        # same digits), so that its quartic, which is of degree 4 in the lengths, neither
        # overflows nor underflows for any arm rikin takes (1e-100 to 1e100 in its units)
        self.model, self.unit = _unit_model(chain_model(arm))
        model = self.model
        wg = wrist_geometry(arm, model)
        assert not isinstance(wg, str)
        self.wrist = wg
        self.a1, self.d1, al1 = model.dh(1)
        self.ca1, self.sa1 = math.cos(al1), math.sin(al1)
        tol = GEOMETRY_TOL * model.scale
        self.case = (
            "meet" if abs(self.a1) <= tol else "parallel" if abs(self.sa1) <= GEOMETRY_TOL
            else "skew"
        )
        sb1 = math.sin(wg.b1)
        self.orthogonal = (
            abs(abs(sb1) - 1.0) <= GEOMETRY_TOL
            and abs(math.sin(wg.b1 + wg.b2)) <= GEOMETRY_TOL
        )
        self.sigma = float(np.sign(sb1))
        self.kappa = 1.0 if math.cos(wg.b1 + wg.b2) > 0 else -1.0
        self.M0_inv = np.linalg.inv(model.M[0])
        self.meet_geometry = _meet_geometry(model, wg) if self.case == "meet" else None
        self.slots = tuple(Branch(None, None, w) for _ in range(POSITION_SLOTS)
                           for w in ("no-flip", "flip"))

    def check(self, arm: SerialArm) -> None:  # noqa: D102 - the Solver protocol
        _ = arm

    def _to_unit(self, T: FloatArray) -> FloatArray:
        """Poses ``(..., 4, 4)`` in the arm's units -> in the solver's (``self.unit`` per
        arm unit, a power of two: exact)."""
        T = np.array(T, dtype=float)
        T[..., :3, 3] *= self.unit
        return T

    def single_kernel(self, arm: SerialArm) -> PieperKernel | None:
        """The plain-float kernel for one regular pose (:mod:`rikin.ik.pieper_kernel`), or
        None; :func:`rikin.ik.api.solve` looks it up once per arm."""
        return single_kernel(self, arm)

    def batch_kernel(self, arm: SerialArm) -> PieperBatchKernel | None:
        """The many-pose kernel (:mod:`rikin.ik.pieper_batch`), or None; built once per arm,
        :func:`rikin.ik.api.solve_batch` looks it up."""
        cache = self.__dict__.setdefault("_batch_kernels", weakref.WeakKeyDictionary())
        if arm not in cache:
            cache[arm] = batch_kernel(self, arm, self.single_kernel(arm), self.slots, ACCEPT_TOL)
        return cache[arm]

    # -------------------------------------------------------------- position
    def _g(self, th3: FloatArray) -> FloatArray:
        """``g = M2 Rz(th3) v``, shape ``th3.shape + (3,)``."""
        G0, Gc, Gs, _, _ = self._arm_constants()
        th3 = np.asarray(th3)[..., None]
        return G0 + np.cos(th3) * Gc + np.sin(th3) * Gs

    def _arm_constants(self) -> tuple[FloatArray, ...]:
        """``G0, Gc, Gs`` with ``g(th3) = M2 Rz(th3) v = G0 + cos th3 Gc + sin th3 Gs``, and
        ``M1``'s rotation and translation (computed once per solver)."""
        consts = self.__dict__.get("_arm_consts")
        if consts is None:
            v = self.wrist.v
            R2, t2 = self.model.M[2][:3, :3], self.model.M[2][:3, 3]
            G0 = R2 @ np.array([0.0, 0.0, v[2]]) + t2
            Gc = R2 @ np.array([v[0], v[1], 0.0])
            Gs = R2 @ np.array([-v[1], v[0], 0.0])
            M1 = self.model.M[1]
            consts = (G0, Gc, Gs, M1[:3, :3], M1[:3, 3])
            self.__dict__["_arm_consts"] = consts
        return consts

    def _position_equations(self, p: FloatArray, g: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Right-hand sides ``(B, A)`` of the two equations (module docstring)."""
        a1, d1 = self.a1, self.d1
        pz = p[..., 2]
        B = (p * p).sum(-1) - (g * g).sum(-1) - a1 * a1 + d1 * d1 - 2 * d1 * pz
        A = pz - d1 - self.ca1 * g[..., 2]
        return B, A

    def _position(
        self, p: FloatArray, hint_th1: float, hint_th2: float = 0.0, hinted: bool = False
    ) -> tuple[FloatArray, np.ndarray, dict[str, np.ndarray]]:
        """Joints 1-3 (as theta, offsets included) putting the wrist centre at ``p'`` (N, 3).

        Returns ``th (N, 4, 3)``, ``valid (N, 4)`` and singular masks ``(N, 4)``. A joint
        flagged free (the centre within ``SINGULAR_TOL`` of its axis) takes the hint when
        one was given (``hinted``: the caller's ``near``), else the value the pose gives it
        while that is above rounding (``DIRECTION_FLOOR``).
        """
        N = p.shape[0]
        L = self.model.scale
        hint_tol = (SINGULAR_TOL if hinted else DIRECTION_FLOOR) * L
        a1, sa1 = self.a1, self.sa1
        th = np.zeros((N, POSITION_SLOTS, 3))
        valid = np.zeros((N, POSITION_SLOTS), dtype=bool)
        upper = np.zeros((N, POSITION_SLOTS), dtype=bool)
        if self.case == "skew":
            samples = 2 * np.pi * np.arange(5) / 5
            g = self._g(samples)  # (5, 3)
            B, A = self._position_equations(p[:, None, :], g[None])
            gxy2 = (g[None, :, :2] ** 2).sum(-1)
            terms = (sa1 * sa1 * B * B, 4 * a1 * a1 * A * A, 4 * a1 * a1 * sa1 * sa1 * gxy2)
            F = terms[0] + terms[1] - terms[2]
            th3, real = _trig2_roots(F)
            th2, dist2 = self._th2_skew(p, th3)
            upper = dist2 <= (SINGULAR_TOL * L) ** 2  # flagged
            free = dist2 <= hint_tol**2  # q2 from the hint
            th[..., 1], th[..., 2], valid = np.where(free, hint_th2, th2), th3, real
        else:
            if self.case == "meet":
                r1, r2, ok = self._th3_meet(p)
            else:
                # one equation in th3 alone: (k0 + kc cos + ks sin) = 0, fitted from 3 samples
                samples = np.array([0.0, np.pi / 2, np.pi])
                g = self._g(samples)
                _, E = self._position_equations(p[:, None, :], g[None])
                k0 = (E[:, 0] + E[:, 2]) / 2
                kc = (E[:, 0] - E[:, 2]) / 2
                ks = E[:, 1] - k0
                r1, r2, ok, _ = _solve_sinusoid(kc, ks, -k0)
            for m, th3 in enumerate((r1, r2)):
                g3 = self._g(th3)
                B3, A3 = self._position_equations(p, g3)
                gx, gy = g3[:, 0], g3[:, 1]
                if self.case == "meet":  # sa1 (s2 gx + c2 gy) = A
                    t2p, t2m, ok2, deg = _solve_sinusoid(gy, gx, A3 / sa1)
                else:  # 2 a1 (c2 gx - s2 gy) = B
                    t2p, t2m, ok2, deg = _solve_sinusoid(gx, -gy, B3 / (2 * a1))
                gxy2 = gx * gx + gy * gy  # the centre's squared distance from axis 2
                flagged = deg | (gxy2 <= (SINGULAR_TOL * L) ** 2)
                free = deg | (gxy2 <= hint_tol**2)
                for n_, t2 in enumerate((t2p, t2m)):
                    s = 2 * m + n_
                    th[:, s, 1] = np.where(free, hint_th2, t2)
                    th[:, s, 2] = th3
                    valid[:, s] = ok & (ok2 | flagged)
                    upper[:, s] = flagged
        # joint 1 turns r = M1 Rz(th2) g onto p'
        r = self._arm_point(th[..., 1], th[..., 2])
        rho_p = np.hypot(p[:, 0], p[:, 1])[:, None]
        on_axis = rho_p <= SINGULAR_TOL * L
        free1 = rho_p <= hint_tol
        th1 = np.arctan2(p[:, 1], p[:, 0])[:, None] - np.arctan2(r[..., 1], r[..., 0])
        th[..., 0] = np.where(free1, hint_th1, th1)
        self._axis_pairs(p, th, valid, free1[:, 0])
        self._split_near_axis(th, valid, rho_p[:, 0], free1[:, 0])
        shoulder = np.broadcast_to(on_axis, valid.shape) & valid
        return th, valid, {"shoulder": shoulder, "upper_arm": upper & valid}

    def _th3_meet(self, p: FloatArray) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """Both joint-3 roots (theta) when axes 1 and 2 meet: ``|g(th3)| = D``, ``D`` the
        wrist centre's distance from the point where they meet, ``(r-, r+, reachable)``.

        ``|g|^2 = G0 + rho cos(th3 - phi)`` runs from ``m^2`` (folded) to ``M^2``
        (stretched), so ``th3 = phi +- 2 atan2(sqrt(M^2 - D^2), sqrt(D^2 - m^2))`` with
        both differences taken as products, ``(D - m)(D + m)``: as exact as ``D`` itself.
        The same equation fitted as a sinusoid loses half the digits near a fold, where
        ``D^2 - m^2`` is a difference of large numbers; with equal links (``m = 0``, the
        wrist centre folded onto the shoulder) that alone moved the two roots by
        ``~sqrt(eps)`` while they were 1e-8 apart, and a reachable pose was declared out
        of reach.
        """
        assert self.meet_geometry is not None
        m, M, phi, rho = self.meet_geometry
        D = np.hypot(np.hypot(p[:, 0], p[:, 1]), p[:, 2] - self.d1)
        inner, outer = (D - m) * (D + m), (M - D) * (M + D)
        slack = -math.sqrt(REACH_TOL) * rho
        ok = (inner >= slack) & (outer >= slack) & (rho > 0)
        half = 2 * np.arctan2(np.sqrt(np.maximum(outer, 0.0)), np.sqrt(np.maximum(inner, 0.0)))
        return phi - half, phi + half, ok  # the order of the one-pose kernel's roots

    def _th2_skew(
        self, p: FloatArray, th3: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Joint 2 (theta) of each joint-3 root when axes 1 and 2 are skew, and the squared
        distance of the wrist centre from axis 2.

        ``(X, Y)`` is the wrist centre's offset from axis 2 turned by joint 2, ``Rz(th2)
        g_xy``. That distance is taken from ``(X, Y)``, not from ``g_xy``: near the fold of
        equal links (the centre just off axis 2) a double root of joint 3 is known only to
        ``~sqrt(eps)``, which moves ``g_xy`` by more than the distance itself (and would
        call a centre 2e-6 of the arm's size off axis 2 one on it), while ``(X, Y)`` hardly
        depends on joint 3 there.
        """
        g3 = self._g(th3)  # (N, 4, 3)
        B3, A3 = self._position_equations(p[:, None, :], g3)
        X, Y = B3 / (2 * self.a1), A3 / self.sa1
        gx, gy = g3[..., 0], g3[..., 1]
        return np.arctan2(gx * Y - gy * X, gx * X + gy * Y), X * X + Y * Y

    def _axis_pairs(
        self, p: FloatArray, th: FloatArray, valid: np.ndarray, free1: np.ndarray
    ) -> None:
        """Re-solve the two shoulders of a wrist centre near axis 1 from the local
        geometry (in place): ``th (N, 4, 3)`` for the wrist centres ``p (N, 3)``.

        Near axis 1 the two shoulders are two nearby roots of joints 2-3 (a double root
        on the axis): the closed form gives them only to ~sqrt(rounding), 1e-8..1e-7 rad,
        while the centre's distance ``rho`` from the axis, which joint 1 turns into place,
        may be far smaller (1e-9 of the arm's size): joint 1 then comes out arbitrary, and
        no polish of the whole pose recovers it (its steps along joint 1, ``~error / rho``,
        leave the range where the pose is linear in the joints). So each such pair is
        solved again where the surface of points joints 2-3 reach crosses the axis: a few
        Newton steps put the pair's midpoint (the point of that surface at the centre's
        height, along its level curve, nearest the axis) to rounding, and the two
        shoulders are where that curve, linear over ``~rho``, meets the circle of radius
        ``rho`` the centre turns on: joint 1 from each, to ~rounding / rho. A pair the
        new points fit worse (a curve that misses the circle) keeps its old values; the
        polish and the FK check then decide as before. Where joint 1 is free (``free1``)
        it keeps its value and both slots take the midpoint.
        """
        L = self.model.scale
        rho = np.hypot(p[:, 0], p[:, 1])
        near = rho <= AXIS_PAIR * L
        if not near.any():
            return
        done = np.zeros(valid.shape, dtype=bool)
        for i, j in itertools.combinations(range(POSITION_SLOTS), 2):
            gap = np.abs(wrap_in_place(th[:, j, 1:] - th[:, i, 1:])).max(-1)
            rows = np.flatnonzero(near & valid[:, i] & valid[:, j] & ~done[:, i] & ~done[:, j]
                                  & (gap <= AXIS_PAIR_GAP))
            if not rows.size:
                continue
            mid = th[rows, i, 1:] + wrap_in_place(th[rows, j, 1:] - th[rows, i, 1:]) / 2
            new, ok = self._axis_pair(p[rows], mid, free1[rows])
            old = th[rows][:, [i, j]]
            new[..., 0] = np.where(free1[rows, None], old[..., 0], new[..., 0])
            better = ok & (self._position_miss(p[rows], new) <= self._position_miss(p[rows], old))
            th[rows[better], i] = new[better, 0]
            th[rows[better], j] = new[better, 1]
            done[rows[better], i] = done[rows[better], j] = True

    def _axis_pair(
        self, p: FloatArray, mid: FloatArray, free1: np.ndarray
    ) -> tuple[FloatArray, np.ndarray]:
        """The two shoulders near axis 1 for wrist centres ``p (m, 3)``, from a midpoint
        ``mid (m, 2)`` of joints 2-3 within ~1e-7 rad (:meth:`_axis_pairs`): ``(m, 2, 3)``,
        and which rows have them ``(m,)``: not where the level curve is degenerate (joints
        2-3 do not move the centre along axis 1, or along it not across the axis). Each
        row on its own, whatever the others."""
        ok = np.ones(len(p), dtype=bool)
        for step in range(AXIS_PAIR_STEPS + 1):
            r, d2, d3 = self._arm_point(mid[:, 0], mid[:, 1], jacobian=True)
            jz = np.stack([d2[:, 2], d3[:, 2]], -1)  # the height's gradient in joints 2-3
            jz2 = (jz * jz).sum(-1)
            ok &= jz2 > 0
            jz2 = np.where(ok, jz2, 1.0)
            along = np.stack([-jz[:, 1], jz[:, 0]], -1) / np.sqrt(jz2)[:, None]
            level = jz * ((p[:, 2] - r[:, 2]) / jz2)[:, None]  # onto the centre's height
            # the curve a + s b: where joints 2-3 put the centre (before joint 1), written
            # out (a stacked matmul's rounding may depend on how many rows it has)
            a = r[:, :2] + level[:, :1] * d2[:, :2] + level[:, 1:] * d3[:, :2]
            b = along[:, :1] * d2[:, :2] + along[:, 1:] * d3[:, :2]
            bb = (b * b).sum(-1)
            ok &= bb > 0
            bb = np.where(ok, bb, 1.0)
            s0 = -(a * b).sum(-1) / bb  # its point nearest the axis
            if step < AXIS_PAIR_STEPS:
                mid = mid + level + s0[:, None] * along
        rho2 = (p[:, :2] ** 2).sum(-1)
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        half = np.sqrt(np.maximum(bb * rho2 - cross * cross, 0.0)) / bb
        half = np.where(free1, 0.0, half)
        out = np.empty((len(p), 2, 3))
        for k, s in enumerate((s0 - half, s0 + half)):
            out[:, k, 1:] = mid + level + s[:, None] * along
            at = a + s[:, None] * b
            out[:, k, 0] = np.arctan2(p[:, 1], p[:, 0]) - np.arctan2(at[:, 1], at[:, 0])
        return out, ok & np.isfinite(out).all(axis=(-1, -2))

    def _position_miss(self, p: FloatArray, th: FloatArray) -> FloatArray:
        """The larger distance from ``p (m, 3)`` of the wrist centres joints ``th (m, 2,
        3)`` put, per row ``(m,)``."""
        r = self._arm_point(th[..., 1], th[..., 2])
        c, s = np.cos(th[..., 0]), np.sin(th[..., 0])
        turned = np.stack([c * r[..., 0] - s * r[..., 1], s * r[..., 0] + c * r[..., 1],
                           r[..., 2]], -1)
        return np.abs(turned - p[:, None]).max(axis=(-1, -2))

    def _split_near_axis(
        self, th: FloatArray, valid: np.ndarray, rho_p: FloatArray, on_axis: np.ndarray
    ) -> None:
        """Give back the second shoulder of a wrist centre just off axis 1 (in place).

        A centre ``rho`` from axis 1 is reached by two joint-2 values whose points sit
        ``+-rho`` across the axis, with joint 1 half a turn apart. For ``rho`` near
        rounding those two joint-2 values agree to within ``SAME_ROOT_TOL`` (the sinusoid's
        discriminant rounds to 0), both slots get the same joint 1, and the other
        shoulder would be lost. The second slot of such a pair starts from joint 1 + pi
        instead: within ``2 rho`` of its solution, which the polish then reaches (and the
        FK check confirms). Exactly on the axis joint 1 is free and comes from the hint.
        """
        near = (rho_p <= NEAR_AXIS * self.model.scale) & ~on_axis
        if not near.any():
            return
        for i in range(POSITION_SLOTS):
            for j in range(i + 1, POSITION_SLOTS):
                d = np.abs(np.angle(np.exp(1j * (th[:, i, 1:] - th[:, j, 1:])))).max(-1)
                same = near & valid[:, i] & valid[:, j] & (d < SAME_ROOT_TOL)
                same &= np.abs(np.angle(np.exp(1j * (th[:, i, 0] - th[:, j, 0])))) < SAME_ROOT_TOL
                th[same, j, 0] += np.pi

    def _arm_point(self, th2: FloatArray, th3: FloatArray, jacobian: bool = False) -> Any:
        """``r = M1 Rz(th2) M2 Rz(th3) v``: the wrist centre after ``Rz(th1)``, shape
        ``(..., 3)`` for ``th2, th3`` of one shape ``(...)``; with ``jacobian``, the tuple of
        ``r`` and its derivatives in ``th2`` and ``th3``."""
        _, Gc, Gs, R1, t1 = self._arm_constants()
        th3 = np.asarray(th3)
        g = self._g(th3)
        c2, s2 = np.cos(th2), np.sin(th2)

        def turn(x: FloatArray) -> FloatArray:  # M1's rotation times Rz(th2) x
            return np.stack([c2 * x[..., 0] - s2 * x[..., 1], s2 * x[..., 0] + c2 * x[..., 1],
                             x[..., 2]], -1) @ R1.T

        r = turn(g) + t1
        if not jacobian:
            return r
        dg = -np.sin(th3)[..., None] * Gc + np.cos(th3)[..., None] * Gs
        dturn = np.stack([-s2 * g[..., 0] - c2 * g[..., 1], c2 * g[..., 0] - s2 * g[..., 1],
                          np.zeros_like(c2)], -1) @ R1.T
        return r, dturn, turn(dg)

    # -------------------------------------------------------------- orientation
    def _wrist(
        self, R_w: FloatArray, hint_th4: float
    ) -> tuple[FloatArray, np.ndarray, np.ndarray, np.ndarray]:
        """``th4, th5, th6`` of both wrist slots: ``(..., 2, 3)``, ``ok (..., 2)``, and the
        masks (axes 4 and 6 aligned, the wrist at a fold), ``(..., 2)``."""
        if self.orthogonal:
            C = np.eye(3) if self.kappa > 0 else np.diag([1.0, -1.0, -1.0])
            M = R_w @ C.T
            phi, theta, psi, sing = spherical_wrist(M, hint_th4)
            out = np.stack([phi, -self.sigma * theta, self.kappa * psi], axis=-1)
            ok = np.ones(out.shape[:-1], dtype=bool)
            return out, ok, np.broadcast_to(sing[..., None], ok.shape), np.zeros_like(ok)
        b1, b2 = self.wrist.b1, self.wrist.b2
        sb1, cb1, sb2, cb2 = math.sin(b1), math.cos(b1), math.sin(b2), math.cos(b2)
        c5_raw = (cb1 * cb2 - R_w[..., 2, 2]) / (sb1 * sb2)
        ok = np.abs(c5_raw) <= 1.0 + math.sqrt(REACH_TOL)
        c5 = np.clip(c5_raw, -1.0, 1.0)
        s5_abs = np.sqrt(1.0 - c5 * c5)
        # q5 = 0 or pi to within what the pose fixes there: a fold of the wrist, or (when
        # the twists cancel at that q5: b1 + b2 = 0 or pi for q5 = 0, b1 - b2 for q5 = pi)
        # axes 4 and 6 in line
        near5 = s5_abs < WRIST_FOLD_TOL
        in_line = near5 & np.where(
            c5 > 0, abs(math.sin(b1 + b2)) <= GEOMETRY_TOL, abs(math.sin(b1 - b2)) <= GEOMETRY_TOL
        )
        outs = []
        sing_k_both = []
        for sgn in (1.0, -1.0):
            s5 = sgn * s5_abs
            th5 = np.arctan2(s5, c5)
            ax, ay = sb2 * s5, -cb1 * sb2 * c5 - sb1 * cb2
            sing_k = (np.hypot(ax, ay) < SINGULAR_TOL) | in_line
            th4 = np.arctan2(R_w[..., 1, 2], R_w[..., 0, 2]) - np.arctan2(ay, ax)
            th4 = np.where(sing_k, hint_th4, th4)
            # th6 from what is left, Rz(th6) = (Rz(th4) Rx(b1) Rz(th5) Rx(b2))^T R_w: consistent
            # with th4 near the singularity, where th4 and th6 alone are ill-conditioned
            lead = (
                _rz4(th4)[..., :3, :3] @ _rx(b1)[:3, :3] @ _rz4(th5)[..., :3, :3]
                @ _rx(b2)[:3, :3]
            )
            rest = np.swapaxes(lead, -1, -2) @ R_w
            th6 = np.arctan2(rest[..., 1, 0] - rest[..., 0, 1], rest[..., 0, 0] + rest[..., 1, 1])
            outs.append(np.stack([th4, th5, th6], axis=-1))
            sing_k_both.append(sing_k)
        sing = sing_k_both[0] | sing_k_both[1]
        both = np.stack([ok, ok], axis=-1)
        # q5 = 0 or pi with axes 4 and 6 not aligned: the three axes in one plane, the tilt
        # between axes 4 and 6 at its least or most, and the two branches (+-q5) one. A
        # fold fixes q5 only to ~ the square root of the pose's rounding (1e-8..1e-7 here)
        fold = near5 & ~sing & ok
        return (np.stack(outs, axis=-2), both, np.broadcast_to(sing[..., None], both.shape),
                np.broadcast_to(fold[..., None], both.shape))

    # -------------------------------------------------------------- polish
    def _merge_coinciding(
        self, th: FloatArray, goal: FloatArray, valid: np.ndarray, res: FloatArray,
        near: np.ndarray,
    ) -> np.ndarray:
        """Make position branches the pose cannot tell apart one solution (in place), and
        say which they are, ``(N, 8)``.

        Near a fold of joints 1-3 (the wrist centre at the edge of what they reach, or
        just off axis 2 where the two joint-2 values meet) two branches ``s`` apart are
        fixed by the pose only to ``~eps / (k s)``, ``k`` the fold's curvature, while the
        pose error halfway between them is ``~k s^2 / 4``. So the pair is two solutions
        when that halfway error stands out of the rounding of the two ends, and one
        (the elbow singularity, no free joint) when it does not: a pose within rounding
        of the fold, on either side. Halfway is measured on the valley's floor
        (:meth:`_valley`), not at the straight midpoint in joint space. The kept point is
        the best of the two and that halfway point. Only the poses ``near (N,)`` are
        looked at: those with two branches near each other before the polish.
        """
        elbow = np.zeros(valid.shape, dtype=bool)
        pairs, ii, jj = _slot_pairs(th.shape[1])
        sub = np.flatnonzero(near)
        half, close = _close_pairs(th[sub], valid[sub], ii, jj)
        if not close.any():
            return elbow
        mid = th[sub][:, ii] + half
        rows = sub[np.nonzero(close)[0]]
        mid[close] = self._valley(mid[close], goal[rows, 0])
        r_mid = np.full(close.shape, np.inf)
        r_mid[close] = self._residual(mid[close], goal[rows, 0])
        ends = np.maximum(res[sub][:, ii], res[sub][:, jj])
        same = close & (r_mid <= np.maximum(COINCIDE_FACTOR * ends, COINCIDE_FLOOR))
        for k in zip(*np.nonzero(same), strict=True):
            row, p = int(sub[k[0]]), int(k[1])
            i, j = pairs[p]
            best = min((res[row, i], 0), (res[row, j], 1), (r_mid[k], 2))[1]
            keep = (th[row, i], th[row, j], mid[k])[best].copy()
            th[row, i] = th[row, j] = keep
            res[row, i] = res[row, j] = min(res[row, i], res[row, j], r_mid[k])
            elbow[row, i] = elbow[row, j] = True
        return elbow

    def _valley(self, th: FloatArray, T_goal: FloatArray) -> FloatArray:
        """Move joint values ``(..., 6)`` onto the floor of the pose error's valley.

        Between two roots of a fold the error is least along a curve (the valley) whose
        height halfway is the fold's bump ``~k s^2 / 4``. The straight midpoint in joint
        space lies off that curve by ``~s^2`` times the other joints' curvature, which can
        hide the bump or invent one. ``VALLEY_STEPS`` Gauss-Newton steps without the
        weakest direction (the one along the valley, the fold's) settle on the floor and
        stay halfway.
        """
        L = self.model.scale
        w = np.array([1 / L] * 3 + [1.0] * 3)
        shape = th.shape
        x = th.reshape(-1, 6).copy()
        goal = np.broadcast_to(T_goal, shape[:-1] + (4, 4)).reshape(-1, 4, 4)
        for _ in range(VALLEY_STEPS):
            T, z, o = self._fk_frames(x)
            e = self._pose_error(T, goal) * w
            J = np.concatenate([cross3(z, T[..., None, :3, 3] - o), z], axis=-1)
            J = np.swapaxes(J, -1, -2) * w[:, None]
            U, sv, Vt = np.linalg.svd(J)
            inv = np.where(sv > POLISH_RCOND * sv[..., :1], 1.0 / np.where(sv > 0, sv, 1.0), 0.0)
            inv[..., -1] = 0.0  # not along the valley
            Ue = np.swapaxes(U, -1, -2) @ e[..., None]
            x = x + (np.swapaxes(Vt, -1, -2) @ (inv[..., None] * Ue))[..., 0]
        return x.reshape(shape)

    # -------------------------------------------------------------- solve
    def solve(
        self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None, labels: bool = True
    ) -> RawSolutions:
        """All solutions of N flange poses ``T_0_n (N, 4, 4)``; 8 slots. Without
        ``labels``, no ``elbow_up`` and ``shoulder_front`` (the batch path reports slots)."""
        T_0_n = self._to_unit(T_0_n)
        off = self.model.offsets
        N = T_0_n.shape[0]
        h1 = (0.0 if hint is None else float(hint[0])) + off[0]
        h4 = (0.0 if hint is None else float(hint[3])) + off[3]
        c = np.append(self.wrist.c_flange, 1.0)
        p_w = (T_0_n @ c)[:, :3]
        p = (self.M0_inv @ np.append(p_w, np.ones((N, 1)), axis=1)[..., None])[:, :3, 0]
        h2 = (0.0 if hint is None else float(hint[1])) + off[1]
        th123, valid_pos, sing = self._position(p, h1, h2, hint is not None)
        # wrist: R_w = R_F4^T R_0_6 R_M6^T
        M = self.model.M
        R_F4 = (
            M[0, :3, :3] @ _rz4(th123[..., 0])[..., :3, :3] @ M[1, :3, :3]
            @ _rz4(th123[..., 1])[..., :3, :3] @ M[2, :3, :3]
            @ _rz4(th123[..., 2])[..., :3, :3] @ M[3, :3, :3]
        )
        R_w = np.swapaxes(R_F4, -1, -2) @ T_0_n[:, None, :3, :3] @ M[6, :3, :3].T
        th456, ok_w, wsing, wfold = self._wrist(R_w, h4)  # (N, 4, 2, 3)
        th: FloatArray = np.empty((N, POSITION_SLOTS, 2, 6))
        th[..., :3] = th123[:, :, None, :]
        th[..., 3:] = th456
        th = th.reshape(N, 2 * POSITION_SLOTS, 6)
        valid = (valid_pos[:, :, None] & ok_w).reshape(N, -1)
        goal = np.broadcast_to(T_0_n[:, None], th.shape[:-1] + (4, 4))
        th = np.where(valid[..., None], th, 0.0)
        # only the slots that hold a solution: the others would take every step of the
        # polish for nothing (2,000 random KR5 poses: 1,700 of 7,461 rows, 2/3 of the time)
        res = np.full(valid.shape, np.inf)  # the slots without a solution stay out
        paired, near = self._pairs_before_polish(th, valid)
        th[valid], T_valid = self._polish(th[valid], goal[valid], ~paired[valid])
        res[valid] = self._residual_of(T_valid, goal[valid])
        valid &= res <= ACCEPT_TOL
        elbow = self._merge_coinciding(th, goal, valid, res, near)
        elbow = self._elbow_or_shoulder(th, elbow, np.repeat(sing["shoulder"], 2, axis=1))
        q = th - off
        front = up = None
        if labels:  # per position branch: its two wrist slots share joints 1-3, and a label
            # at a singular pose (on the line that splits the labels) is rounding
            arm_joints = np.where(valid[:, ::2, None], th[:, ::2], th[:, 1::2])
            front, up = (np.repeat(x, 2, axis=1) for x in self._labels(arm_joints))
        q[~valid] = np.nan

        def per_slot(mask: np.ndarray) -> np.ndarray:
            return np.repeat(mask, 2, axis=1) & valid

        return RawSolutions(
            q=q,
            valid=valid,
            slots=self.slots,
            elbow_up=up,
            shoulder_front=front,
            singular={
                "shoulder": per_slot(sing["shoulder"]),
                "upper_arm": per_slot(sing["upper_arm"]),
                "elbow": elbow & valid,
                "wrist": wsing.reshape(N, -1) & valid,
                "wrist_fold": wfold.reshape(N, -1) & valid,
            },
        )

    def _elbow_or_shoulder(
        self, th: FloatArray, elbow: np.ndarray, shoulder: np.ndarray
    ) -> np.ndarray:
        """``elbow (N, 8)`` without the merged slots whose coincidence is the shoulder's.

        With the wrist centre on axis 1 the two shoulders are one solution (q1 free), and
        the merge finds them coinciding although the elbow is not at a fold. The elbow is
        at a fold (too) only where joints 2 and 3 move the wrist centre along one line:
        their velocity vectors ``z_i x (w - o_i)`` parallel (the arm stretched or folded).
        """
        check = elbow & shoulder
        if not check.any():
            return elbow
        T, z, o = self._fk_frames(th[check])
        w = T[:, :3, :3] @ self.wrist.c_flange + T[:, :3, 3]
        a = np.cross(z[:, 1], w - o[:, 1])
        b = np.cross(z[:, 2], w - o[:, 2])
        longer = np.maximum(np.linalg.norm(a, axis=-1), np.linalg.norm(b, axis=-1))
        parallel = np.linalg.norm(np.cross(a, b), axis=-1) <= ELBOW_FOLD * self.model.scale * longer
        out = elbow.copy()
        out[check] = parallel
        return out

    def _pairs_before_polish(
        self, th: FloatArray, valid: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """The slots ``(N, 8)`` with a slot of another position branch within twice
        ``NEAR_PAIR`` in every joint, and the poses ``(N,)`` that have such a pair.

        Before the polish a branch's two wrist slots share joints 1-3, so only the poses
        whose branches come that close in joints 1-3 (few) are compared in all six.
        """
        N = th.shape[0]
        paired = np.zeros(valid.shape, dtype=bool)
        near = np.zeros(N, dtype=bool)
        bi, bj = _BRANCH_PAIRS
        branch = th[:, ::2, :3]  # joints 1-3 of each position branch
        gap = np.abs(wrap_in_place(branch[:, bj] - branch[:, bi])).max(-1)  # (N, 6)
        rows = np.flatnonzero((gap < 4.0 * NEAR_PAIR).any(axis=1))  # = 2 * margin / 2
        if not rows.size:
            return paired, near
        _, ii, jj = _slot_pairs(th.shape[1])
        _, close = _close_pairs(th[rows], valid[rows], ii, jj, margin=2.0)
        sub = np.zeros((rows.size, th.shape[1]), dtype=bool)
        for k in range(len(ii)):
            sub[:, ii[k]] |= close[:, k]
            sub[:, jj[k]] |= close[:, k]
        paired[rows] = sub
        near[rows] = close.any(axis=1)
        return paired, near

    def label_rows(self, q: FloatArray) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Shoulder front and elbow up ``(m,)`` of joint rows ``q (m, 6)`` (the table's
        values), as :meth:`solve` labels its solutions (:meth:`_labels`)."""
        front, up = self._labels((q + self.model.offsets)[None])
        return front[0], up[0]

    def _labels(self, th: FloatArray) -> tuple[np.ndarray, np.ndarray]:
        """Shoulder front (wrist centre ahead of axis 1 along the turned x axis) and elbow up
        (elbow above the shoulder-wrist line, along axis 1) of joints ``th (N, k, 3+)``,
        ``(N, k)``."""
        th = np.where(np.isfinite(th), th, 0.0)
        M = self.model.M
        F1 = np.broadcast_to(M[0], th.shape[:-1] + (4, 4)) @ _rz4(th[..., 0])
        F2 = F1 @ M[1]
        F3 = F2 @ _rz4(th[..., 1]) @ M[2]
        W = (F3 @ _rz4(th[..., 2]) @ np.append(self.wrist.v, 1.0))[..., :3]
        fwd, axis1 = F1[..., :3, 0], F1[..., :3, 2]
        S, E = F2[..., :3, 3], F3[..., :3, 3]
        front = ((W - F1[..., :3, 3]) * fwd).sum(-1) >= -SINGULAR_TOL * self.model.scale
        # the elbow's side of the shoulder-wrist line, seen along axis 2 (in the plane
        # joint 2 swings the elbow in): "up" means towards +axis 1
        n2 = F2[..., :3, 2]

        def flat(x: FloatArray) -> FloatArray:
            return x - (x * n2).sum(-1, keepdims=True) * n2

        line, e, up_dir, fwd_p = flat(W - S), flat(E - S), flat(axis1), flat(fwd)
        n_line = (line * line).sum(-1, keepdims=True)
        h = e - (e * line).sum(-1, keepdims=True) / np.where(n_line > 0, n_line, 1.0) * line
        across = np.linalg.norm(np.cross(line, up_dir), axis=-1)
        vertical = across <= SINGULAR_TOL * (np.sqrt(n_line[..., 0]) + self.model.scale)
        up = np.where(vertical, (h * fwd_p).sum(-1) > 0, (h * up_dir).sum(-1) > 0)
        return front, up

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        """Why one flange pose has no solution, and by how much (length units or rad)."""
        T_0_n = self._to_unit(T_0_n)
        c = np.append(self.wrist.c_flange, 1.0)
        p_w = (T_0_n @ c)[:3]
        p = (self.M0_inv @ np.append(p_w, 1.0))[:3]
        u = _units(arm)
        th, valid, _ = self._position(p[None], 0.0)
        if not valid[0].any():
            gap = float(self._reach_nearest(p[None], np.inf)[0][0]) / self.unit  # exact
            return (
                f"the wrist centre is {gap:.4g}{u} out of reach of joints 1-3 (that far "
                "from the nearest point they can put it)"
                + rounding_note(arm, p_w / self.unit),
                gap,
            )
        if not self.orthogonal:
            b1, b2 = self.wrist.b1, self.wrist.b2
            # axis 6 makes an angle with axis 4 between those of q5 = 0 and q5 = pi
            lo, hi = sorted(
                float(np.arccos(np.clip(math.cos(x), -1.0, 1.0))) for x in (b1 + b2, b1 - b2)
            )
            needed = [self._tilt_needed(th[0, k], T_0_n) for k in np.flatnonzero(valid[0])]
            excess = [max(lo - a, a - hi, 0.0) for a in needed]
            k = int(np.argmin(excess))
            if excess[k] > 0:
                return (
                    f"the wrist cannot tilt the tool that far: axis 6 must make "
                    f"{math.degrees(needed[k]):.4g} deg with axis 4, and this wrist only "
                    f"reaches {math.degrees(lo):.4g}-{math.degrees(hi):.4g} deg",
                    excess[k],
                )
        return "no joint values reproduce this pose (numerically at the edge of reach)", 0.0

    def _tilt_needed(self, th123: FloatArray, T_0_n: FloatArray) -> float:
        """Angle between axis 4 (after joints 1-3 at ``th123``) and the target's axis 6."""
        M = self.model.M
        R = M[0, :3, :3]
        for i in range(3):
            R = R @ _rz4(th123[i])[:3, :3] @ M[i + 1, :3, :3]
        z4 = R[:, 2]
        z6 = (T_0_n[:3, :3] @ M[6, :3, :3].T)[:, 2]
        return float(np.arccos(np.clip(z4 @ z6, -1.0, 1.0)))

    def _reach_nearest(self, p: FloatArray, near: FloatArray | float
                       ) -> tuple[FloatArray, FloatArray]:
        """Distance of points ``p' (N, 3)`` (frame of axis 1, solver units) from where
        joints 1-3 can put the wrist centre, and the nearest such point ``(N, 3)``.

        Joint 1 turns the point ``r(th2, th3)`` about axis 1, so the distance is that of
        ``(|r_xy|, r_z)`` to ``(|p'_xy|, p'_z)`` in the plane through axis 1 and ``p'``:
        first on a 48 x 48 grid of ``th2, th3``. A grid node is at most ``s / sqrt(2)``
        from any ``(th2, th3)`` (``s`` its spacing), and ``r`` moves at most the arm's size
        ``L`` per radian of either, so the true distance is within ``L s`` of the grid's.
        Points the grid puts within ``L s + near`` get the exact minimum: Levenberg-
        Marquardt on the two differences from the grid's six best nodes (the distance
        then to rounding, and a root where the point is reachable); the others keep the
        grid's (an upper bound, beyond ``near`` either way).
        """
        grid = self.__dict__.get("_reach_grid")
        t = 2 * np.pi * np.arange(48) / 48
        if grid is None:
            g2, g3 = (x.ravel() for x in np.meshgrid(t, t, indexing="ij"))
            r = self._arm_point(g2, g3)
            grid = (g2, g3, np.hypot(r[:, 0], r[:, 1]), r[:, 2])
            self.__dict__["_reach_grid"] = grid
        g2, g3, rho_g, z_g = grid
        spacing = t[1] - t[0]
        rho_p = np.hypot(p[:, 0], p[:, 1])
        near = np.broadcast_to(near, rho_p.shape)
        dist = np.empty(len(p))
        best = np.empty((len(p), 2))
        for start in range(0, len(p), 512):  # (chunk, 2304) distances at a time
            sl = slice(start, start + 512)
            D = np.hypot(rho_g - rho_p[sl, None], z_g - p[sl, 2, None])
            i = np.argmin(D, axis=1)
            dist[sl] = D[np.arange(len(i)), i]
            best[sl] = np.stack([g2[i], g3[i]], axis=-1)
            close = np.flatnonzero(dist[sl] <= self.model.scale * spacing + near[sl])
            if close.size:
                rows = start + close
                top = np.argpartition(D[close], 6, axis=1)[:, :6]  # (n, 6) nodes
                th = np.stack([g2[top], g3[top]], axis=-1)  # (n, 6, 2)
                d, th = self._reach_lm(th, rho_p[rows, None], p[rows, 2, None])
                j = d.argmin(-1)
                pick = np.arange(len(rows))
                dist[rows] = d[pick, j]
                best[rows] = th[pick, j]
        r = self._arm_point(best[:, 0], best[:, 1])
        az = np.arctan2(p[:, 1], p[:, 0])
        rho_r = np.hypot(r[:, 0], r[:, 1])
        nearest = np.stack([rho_r * np.cos(az), rho_r * np.sin(az), r[:, 2]], axis=-1)
        return dist, nearest

    def _reach_lm(self, th: FloatArray, rho_p: FloatArray, z_p: FloatArray
                  ) -> tuple[FloatArray, FloatArray]:
        """Levenberg-Marquardt from ``th = (th2, th3) (..., 2)`` on ``e = (|r_xy| - rho_p,
        r_z - z_p)``: the least ``|e|`` found from each start, and where, ``(...)``,
        ``(..., 2)``."""
        shape = th.shape[:-1]
        th = th.reshape(-1, 2)
        rho_p = np.broadcast_to(rho_p, shape).ravel()
        z_p = np.broadcast_to(z_p, shape).ravel()
        mu = np.full(len(th), 1e-3)

        def residual(x: FloatArray) -> tuple[FloatArray, FloatArray]:
            r, dr2, dr3 = self._arm_point(x[:, 0], x[:, 1], jacobian=True)
            rho = np.hypot(r[:, 0], r[:, 1])
            safe = np.where(rho > 0, rho, 1.0)
            e = np.stack([rho - rho_p, r[:, 2] - z_p], axis=-1)
            J = np.empty((len(x), 2, 2))
            for k, dr in enumerate((dr2, dr3)):
                J[:, 0, k] = (r[:, 0] * dr[:, 0] + r[:, 1] * dr[:, 1]) / safe
                J[:, 1, k] = dr[:, 2]
            return e, J

        e, J = residual(th)
        cost = (e * e).sum(-1)
        for _ in range(60):
            JtJ = np.swapaxes(J, -1, -2) @ J
            g = (np.swapaxes(J, -1, -2) @ e[..., None])[..., 0]
            # damping relative to J's size, never 0 (J vanishes where r is on axis 1)
            scale = np.trace(JtJ, axis1=-2, axis2=-1) + 1e-20 * self.model.scale**2
            A = JtJ + (mu * scale)[:, None, None] * np.eye(2)
            step = -np.linalg.solve(A, g[..., None])[..., 0]
            trial = th + step
            e_t, J_t = residual(trial)
            cost_t = (e_t * e_t).sum(-1)
            better = cost_t < cost
            th = np.where(better[:, None], trial, th)
            e = np.where(better[:, None], e_t, e)
            J = np.where(better[:, None, None], J_t, J)
            cost = np.where(better, cost_t, cost)
            mu = np.where(better, np.maximum(mu * 0.3, 1e-12), mu * 10.0)
            if ((mu > 1e12) | (cost <= (1e-15 * self.model.scale) ** 2)).all():
                break  # each start stuck, or on a root to rounding
        return np.sqrt(cost).reshape(shape), th.reshape(*shape, 2)

    def nearest_reachable(
        self, arm: SerialArm, T_world: FloatArray
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """:func:`rikin.ik.reach.nearest_reachable`: the wrist centre moved onto the set
        joints 1-3 reach (found by :meth:`_reach_nearest`)."""
        M0 = self.model.M[0]
        L = self.model.scale
        near = 2 * ROUNDED_POSE_TOL * L  # the exact search where the pose can be rounded

        last_J: list[FloatArray] = []

        def gap(pw: FloatArray, active: np.ndarray | None) -> tuple[FloatArray, ...]:
            p = (self.M0_inv[:3, :3] @ (pw * self.unit)[..., None])[..., 0] + self.M0_inv[:3, 3]
            far = np.abs(p).max(axis=-1)
            dist, nearest = self._reach_nearest(p, near * np.maximum(1.0, far / L))
            out = dist > 1e-13 * np.maximum(L, far)  # else reachable to rounding: no direction
            u = (p - nearest) / np.where(out, dist, 1.0)[:, None]
            J = np.swapaxes(M0[:3, :3] @ u[..., None], -1, -2)  # a product per pose
            if active is None:  # the poses that miss the set; the others stay as given
                active = out[:, None]
            else:  # on the set now: the last direction, to keep the step made along it
                J = np.where(out[:, None, None], J, last_J[0])
            last_J[:] = [J]
            return np.where(active & out[:, None], dist[:, None] / self.unit, 0.0), J * active[
                ..., None], active

        return nearest_reachable(arm, gap, T_world, self.wrist.c_flange / self.unit)
