"""The course's arm families, recognised from a DH table, each with its closed form.

A student who types a planar 2R or 3R, the angular 3R, one of Aula 10's positioning
arms (cartesian, cylindrical, spherical, SCARA; with or without a spherical wrist; the
Stanford arm), or the notes' PPRRR and RPRRR as a DH table gets the closed form rikin
uses for the lesson robots, fitted to the table:

* planar 2R and 3R and the angular 3R: the lesson solvers themselves, on the lesson
  arm the table is, up to constant frames and a change of joint zero and sign
  (:class:`rikin.ik.fitted.Fitted`);
* PPRRR, RPRRR: the notes' solvers, which read any such table;
* cartesian, cylindrical, spherical, SCARA (and with a spherical wrist, Aula 10's
  decoupling): :mod:`rikin.ik.positioning`, written on the joint axes.

:func:`family_of` says which family an arm is, with its closed form in words and how
many solutions to expect, or why it is none of them (a near miss is named: "axes 1 and 2
are 0.3 deg from parallel: not a SCARA"). Arms with six revolute joints are left to
:mod:`rikin.ik.pieper`. Every fit is checked by FK at random joint values before use.

The module registers itself with :func:`rikin.ik.solve` and :func:`rikin.ik.classify`
(:mod:`rikin.ik.families6r`, ahead of the 6R families) when :mod:`rikin.ik` is imported
(it imports them; they never import it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import FloatArray
from ..errors import InputError
from ..tolerances import ROUNDED_RIGHT_ANGLE
from . import families6r
from .anthropomorphic import Angular3RSolver, RRRGeometry
from .axes import ZeroAxes, zero_axes
from .decoupled import wrist_model
from .fitted import Fitted
from .pitched import PitchedArmSolver
from .planar import Planar2RSolver, Planar3RSolver
from .positioning import (
    Cartesian,
    Cylindrical,
    PositionFamily,
    PositioningSolver,
    Scara,
    Spherical,
    WristedSolver,
)
from .prismatic import PPRRRSolver, RPRRRSolver
from .rolled_scara import TYPES as ROLLED_SCARA_TYPES
from .rolled_scara import RolledScaraSolver

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm


#: Directions whose cross product is below this are parallel (sine of the angle); axes
#: closer than this times the arm's size meet. DH tables carry exact zeros, so this only
#: absorbs the rounding of cos(pi / 2) and of the FK at q = 0.
GEOMETRY_TOL = 1e-9

#: The four-joint families' names (the book's words), and a reason several families give.
ROLLED_SCARA = "four-axis SCARA (the tool turns about the vertical)"
PITCHED = "four-axis articulated arm (a waist, then three parallel pitch axes)"
_ONE_LINE = "axes 1 and 2 are the same line, so joints 1 and 2 do the same motion"

#: The families, in the book's words, with the most solutions each has.
FAMILIES = (
    ("planar 2R", "RR", 2),
    ("planar 3R", "RRR", 2),
    ("angular (anthropomorphic) 3R", "RRR", 4),
    ("cartesian", "PPP", 1),
    ("cylindrical", "RPP", 2),
    ("spherical (polar)", "RRP", 4),
    ("SCARA", "RRP", 2),
    ("cartesian with a spherical wrist", "PPPRRR", 2),
    ("cylindrical with a spherical wrist", "RPPRRR", 4),
    ("spherical with a spherical wrist (the Stanford arm)", "RRPRRR", 8),
    ("SCARA with a spherical wrist", "RRPRRR", 4),
    (ROLLED_SCARA, "RRPR, RRRP", 2),
    (PITCHED, "RRRR", 2),
    ("PPRRR of the notes (5 DOF)", "PPRRR", 2),
    ("RPRRR of the notes (5 DOF)", "RPRRR", 4),
    ("6R with a spherical wrist (Pieper)", "RRRRRR", 8),
)


@dataclass(frozen=True)
class Family:
    """An arm's course family and its closed form.

    Attributes
    ----------
    name : str
        The family in the book's words, e.g. ``"SCARA with a spherical wrist"``.
    how : str
        The closed form in words.
    count : int
        The most solutions a target has.
    solver : object
        The closed-form solver, fitted to the arm's table.
    """

    name: str
    how: str
    count: int
    solver: Any

    def __str__(self) -> str:
        return f"{self.name}: {self.how}; up to {self.count} solution{'s' * (self.count > 1)}"


def family_of(arm: SerialArm) -> Family | str | None:
    """The course family of ``arm`` (read in DH joint values), or why it is none of them
    (text); None for an arm of six revolute joints (:mod:`rikin.ik.pieper` decides those).

    Built once per arm (arms are immutable).
    """
    dh = arm._dh
    cached = dh.__dict__.get("_course_family", False)
    if cached is False:
        cached = _recognise(dh)
        if isinstance(cached, str):
            cached += _rounded_angles(dh)
        object.__setattr__(dh, "_course_family", cached)
    return cached


def _units(arm: SerialArm) -> str:
    return f" {arm.units}" if arm.units else ""


def _angle(u: FloatArray, v: FloatArray) -> float:
    """The angle between two lines' directions, degrees in [0, 90]."""
    return math.degrees(math.atan2(float(np.linalg.norm(np.cross(u, v))), abs(float(u @ v))))


def _parallel(u: FloatArray, v: FloatArray) -> bool:
    return float(np.linalg.norm(np.cross(u, v))) <= GEOMETRY_TOL


def _same_line(ax: ZeroAxes, i: int, j: int, scale: float) -> bool:
    """Whether the parallel axes ``i`` and ``j`` (0-based) are one line: the way from a
    point of one to a point of the other has no part across them."""
    off, w = ax.r[j] - ax.r[i], ax.w[i]
    return float(np.linalg.norm(off - (off @ w) * w)) <= GEOMETRY_TOL * scale


def _closest(ax: ZeroAxes, i: int, j: int) -> tuple[FloatArray, FloatArray, float]:
    """The closest points of axes ``i`` and ``j`` (not parallel) and their distance."""
    p1, d1, p2, d2 = ax.r[i], ax.w[i], ax.r[j], ax.w[j]
    b = float(d1 @ d2)
    w0 = p1 - p2
    denom = 1.0 - b * b
    s1 = (b * float(d2 @ w0) - float(d1 @ w0)) / denom
    s2 = (float(d2 @ w0) - b * float(d1 @ w0)) / denom
    a, c = p1 + s1 * d1, p2 + s2 * d2
    return a, c, float(np.linalg.norm(a - c))


def _rounded_angles(arm: SerialArm) -> str:
    """The table's angles that look like a right angle typed rounded, as a clause to add to
    the reason an arm is in no family (``""`` when there are none)."""
    found = []
    for row, link in enumerate(arm.links, start=1):
        fields = (("alpha", link.alpha), ("offset" if link.is_revolute else "theta",
                                           link.offset if link.is_revolute else link.theta))
        for field, value in fields:
            quarters = round(float(value) / (math.pi / 2))
            off = abs(float(value) - quarters * math.pi / 2)
            if GEOMETRY_TOL < off <= ROUNDED_RIGHT_ANGLE:
                found.append(f"row {row}'s {field} = {float(value):g} is {off:.1g} rad from "
                             f"{quarters * 90} deg")
    if not found:
        return ""
    return (f" ({', '.join(found)}: if the table means that right angle, type it exactly, "
            "e.g. numpy.pi / 2 or numpy.pi, not a rounded number, which makes another arm)")


# ------------------------------------------------------------------ recognition
def _recognise(arm: SerialArm) -> Family | str | None:
    types, n = arm.joint_types, arm.n
    if types == "RRRRRR":
        return None
    if n > 6:
        return (f"it has {n} joints, more than the six a pose fixes: a redundant arm reaches "
                "a pose in infinitely many ways, so there is no list of solutions to give")
    ax = zero_axes(arm)
    if types == "RR":
        return _planar(arm, ax)
    if types == "RRR":
        planar = _planar(arm, ax)
        if isinstance(planar, Family):
            return planar
        angular = _angular(arm, ax)
        if isinstance(angular, Family):
            return angular
        return f"it is neither planar ({planar}) nor angular ({angular})"
    if types in ("PPP", "RPP", "RRP"):
        return _positioning(arm, ax, np.zeros(3), "the TCP")
    if n == 6 and types[:3] in ("PPP", "RPP", "RRP") and types[3:] == "RRR":
        return _wristed(arm, ax)
    if types in ("PPRRR", "RPRRR"):
        return _notes_5dof(arm)
    if types in ROLLED_SCARA_TYPES:
        return _rolled_scara(arm, ax)
    if types == "RRRR":
        return _pitched(arm, ax)
    slides = [i + 1 for i, t in enumerate(types) if t == "P"]
    which = ""
    if n == 6:  # the six-joint closed forms are for six revolute joints
        which = (f" (joint{'s' * (len(slides) > 1)} {', '.join(map(str, slides))} "
                 f"{'are' if len(slides) > 1 else 'is'} prismatic, and six-joint arms other "
                 "than the positioning arms with a spherical wrist need six revolute joints)")
    return (f"it has {n} joint{'s' * (n != 1)}, {types}{which}, and no course family has "
            "those: the families are " + ", ".join(f"{name} ({t})" for name, t, _ in FAMILIES))


def _positions_span(arm: SerialArm, ax: ZeroAxes, c_n: FloatArray) -> bool:
    """True when joints 1-3 move the point ``c_n`` (frame n) in three independent
    directions at one of a few random configurations (the position Jacobian's rank)."""
    rng = np.random.default_rng(0)
    q = rng.uniform(-np.pi, np.pi, size=(6, arm.n))
    q[:, np.logical_not(arm.revolute)] *= arm.scale
    F = arm._flange._fk(q, frames=True)
    pts = F[:, arm.n, :3, :3] @ c_n + F[:, arm.n, :3, 3]
    idx = np.arange(3) if arm.convention == "standard" else np.arange(1, 4)
    Fj = F[:, idx]
    z, o = Fj[..., :3, 2], Fj[..., :3, 3]
    # a turn moves the point by its distance from the axis, a slide by its own length: both
    # per unit of the arm's size, so that the rank does not depend on the unit
    cols = np.where(arm.revolute[:3, None], np.cross(z, pts[:, None, :] - o) / arm.scale, z)
    sv = np.linalg.svd(cols, compute_uv=False)
    return bool((sv[:, -1] > 1e-9).any())


def _positioning(arm: SerialArm, ax: ZeroAxes, c_n: FloatArray, what: str
                 ) -> Family | str:
    """The family of joints 1-3 placing ``c_n`` (frame n): a 3-joint arm's solver, or
    the reason. ``what`` names the point in messages."""
    family = _position_family(arm, ax, ax.point(c_n), what)
    if isinstance(family, str):
        return family
    if not _positions_span(arm, ax, c_n):
        return (f"joints 1-3 cannot move {what} in three independent directions at any "
                "configuration")
    solver: PositioningSolver | WristedSolver = (
        PositioningSolver(family, arm.joint_types) if arm.n == 3 else WristedSolver(family, arm))
    try:
        solver.check(arm)
    except InputError:
        return f"rikin could not fit the {family.name} to this table (its FK check failed)"
    how = f"{family.words}; {_HOW[type(family)]}"
    if arm.n == 3:
        return Family(family.name, how, family.count, solver)
    name = family.name + " with a spherical wrist"
    if isinstance(family, Spherical) and float(np.linalg.norm(np.cross(
            family.x0, ax.w[2]))) > GEOMETRY_TOL * arm.scale:
        name += " (as on the Stanford arm, the boom's line misses the shoulder point)"
    return Family(name, how + "; then the spherical wrist, two ways", 2 * family.count, solver)


_HOW = {
    Cartesian: "the slides' values are the target's coordinates along them (one linear "
               "system)",
    Cylindrical: "joint 1 keeps the height and the distance from axis 1: a quadratic in one "
                 "slide (front and back), the other slide from the height",
    Spherical: "turns about the shoulder point keep the distance from it: a quadratic in the "
               "boom (towards or away), then the two turns that bring it onto the target "
               "(front or back)",
    Scara: "the height gives the quill, then the planar two-link chain (elbow right or left)",
}


def _position_family(arm: SerialArm, ax: ZeroAxes, c0: FloatArray, what: str
                     ) -> PositionFamily | str:
    """The positioning family of joints 1-3 (PPP, RPP or RRP), or why none fits."""
    types = arm.joint_types[:3]
    w = ax.w
    if types == "PPP":
        if abs(float(np.linalg.det(w[:3]))) <= GEOMETRY_TOL:
            return "the three slides' directions lie in one plane: they cannot place a point in 3D"
        return Cartesian(ax, c0)
    if types == "RPP":
        heights = np.abs(w[1:3] @ w[0])
        if heights.max() <= GEOMETRY_TOL:
            return ("both slides are at right angles to axis 1, so nothing changes the height "
                    "along it: not a cylindrical arm")
        family = Cylindrical(ax, c0)
        if float(np.linalg.norm(family.B)) <= GEOMETRY_TOL:
            return ("the slides cannot change the distance from axis 1 (both move along it, or "
                    "one undoes the other's): not a cylindrical arm")
        return family
    if _parallel(w[0], w[1]):
        if not _parallel(w[2], w[0]):
            return (f"axes 1 and 2 are parallel but the slide (joint 3) is "
                    f"{_angle(w[2], w[0]):.4g} deg from them: a SCARA's quill moves along them")
        if _same_line(ax, 0, 1, arm.scale):
            return _ONE_LINE
        scara = Scara(ax, c0)
        if scara.L2 <= GEOMETRY_TOL * arm.scale:
            return f"{what} lies on axis 2, so joint 2 cannot move it"
        return scara
    a, b, dist = _closest(ax, 0, 1)
    if dist > GEOMETRY_TOL * arm.scale:
        return (f"axes 1 and 2 neither meet nor are parallel: they pass {dist:.6g}{_units(arm)} "
                f"apart at {_angle(w[0], w[1]):.4g} deg (a spherical arm's meet, a SCARA's are "
                "parallel)")
    return Spherical(ax, c0, (a + b) / 2)


def _wristed(arm: SerialArm, ax: ZeroAxes) -> Family | str:
    """A positioning arm with a spherical wrist (joints 4-6), or why not."""
    try:
        W = wrist_model(arm, 3)
    except InputError:
        return _wrist_reason(arm, ax)
    return _positioning(arm, ax, W.centre, "the wrist centre")


def _wrist_reason(arm: SerialArm, ax: ZeroAxes) -> str:
    """Why joints 4-6 are not a spherical wrist rikin's decoupling takes, in the arm's terms."""
    tol = GEOMETRY_TOL * arm.scale
    u = _units(arm)
    for i, j in ((3, 4), (4, 5)):
        if _parallel(ax.w[i], ax.w[j]):
            return f"axes {i + 1} and {j + 1} are parallel, so joints 4-6 have no wrist centre"
    a45, b45, d45 = _closest(ax, 3, 4)
    if d45 > tol:
        return f"axes 4, 5, 6 do not meet: axis 5 passes {d45:.6g}{u} from axis 4"
    centre = (a45 + b45) / 2
    off = centre - ax.r[5]
    d6 = float(np.linalg.norm(off - (off @ ax.w[5]) * ax.w[5]))
    if d6 > tol:
        return (f"axes 4, 5, 6 do not meet: axis 6 passes {d6:.6g}{u} from the point where "
                "axes 4 and 5 meet")
    return ("joints 4-6 meet in one point, but their twists are not the +-90 deg of the "
            "course's spherical wrist (alpha_4 = -alpha_5 = +-90 deg)")


def _notes_5dof(arm: SerialArm) -> Family | str:
    solver = PPRRRSolver() if arm.joint_types == "PPRRR" else RPRRRSolver()
    try:
        solver.check(arm)
    except InputError as exc:
        return str(exc).split(": ", 1)[-1]
    if arm.joint_types == "PPRRR":
        return Family("PPRRR of the notes (5 DOF)", "the two slides place the wrist centre "
                      "(one linear system), then the spherical wrist, two ways", 2, solver)
    return Family("RPRRR of the notes (5 DOF)", "joint 1 and the slide place the wrist centre "
                  "in its plane (two ways), then the spherical wrist, two ways", 4, solver)


def _rolled_scara(arm: SerialArm, ax: ZeroAxes) -> Family | str:
    """A four-axis SCARA (every axis parallel, the roll axis apart from axis 2), or why not."""
    roll = 3 if arm.joint_types == "RRPR" else 2
    names = {1: "axis 2", roll: "the roll axis", 5 - roll: "the quill"}
    for j in (1, 2, 3):
        if not _parallel(ax.w[j], ax.w[0]):
            return (f"{names[j]} (joint {j + 1}) is {_angle(ax.w[j], ax.w[0]):.4g} deg from "
                    "axis 1: a four-axis SCARA's axes and quill are all parallel")
    if _same_line(ax, 0, 1, arm.scale):
        return _ONE_LINE
    if _same_line(ax, 1, roll, arm.scale):
        return f"the roll axis (joint {roll + 1}) is axis 2's line, so joint 2 cannot move it"
    solver = RolledScaraSolver(arm, ax)
    try:
        solver.check(arm)
    except InputError:
        return "rikin could not fit the four-axis SCARA to this table (its FK check failed)"
    how = ("the roll axis is placed as a SCARA places its TCP (the height gives the quill, "
           "then the planar two-link chain, elbow right or left), then the roll from the "
           "tool's heading")
    return Family(ROLLED_SCARA, how, 2, solver)


def _pitched(arm: SerialArm, ax: ZeroAxes) -> Family | str:
    """A four-axis articulated arm (axes 2-4 parallel, not parallel to axis 1, on three
    lines), or why not."""
    for j in (2, 3):
        if not _parallel(ax.w[j], ax.w[1]):
            return (f"axes 2 and {j + 1} are {_angle(ax.w[j], ax.w[1]):.4g} deg from parallel: "
                    "a four-axis articulated arm pitches about three parallel axes")
    if _parallel(ax.w[1], ax.w[0]):
        return "all four axes are parallel: a planar arm with one joint too many"
    for i in (1, 2):
        if _same_line(ax, i, i + 1, arm.scale):
            return (f"axes {i + 1} and {i + 2} are the same line, so joints {i + 1} and {i + 2} "
                    "do the same motion")
    solver = PitchedArmSolver(arm, ax)
    try:
        solver.check(arm)
    except InputError:
        return ("rikin could not fit the four-axis articulated arm to this table (its FK check "
                "failed)")
    how = ("the tool's pitch axis gives the waist (q1), joints 2-3 place axis 4 as a planar "
           "two-link chain (elbow up or down), then q4 from the tool's pitch")
    return Family(PITCHED, how, 2, solver)


# ------------------------------------------------------------------ the lesson solvers, fitted
def _frame(z: FloatArray, x: FloatArray, origin: FloatArray) -> FloatArray:
    """The frame with axes ``x``, ``z x x``, ``z`` at ``origin`` (x across z, unit)."""
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, origin
    return T


def _turn(w: FloatArray, a: FloatArray, b: FloatArray) -> float:
    """The angle about ``w`` from ``a`` to ``b`` (both across ``w``)."""
    return math.atan2(float(np.cross(a, b) @ w), float(a @ b))


def _planar(arm: SerialArm, ax: ZeroAxes) -> Family | str:
    """A planar 2R or 3R (every axis parallel): the lesson solver, fitted; or why not."""
    n, w1 = arm.n, ax.w[0]
    for i in range(1, n):
        if not _parallel(ax.w[i], w1):
            return f"axes 1 and {i + 1} are {_angle(ax.w[i], w1):.4g} deg from parallel"
    f = ax.frames[-1]
    origin = ax.r[0] + ((f[:3, 3] - ax.r[0]) @ w1) * w1  # on axis 1, at the flange's height

    def across(x: FloatArray) -> FloatArray:
        v = x - origin
        return v - (v @ w1) * w1

    pts = [across(ax.r[i]) for i in range(n)] + [across(f[:3, 3])]
    links = [pts[i + 1] - pts[i] for i in range(n)]
    lengths = [float(np.linalg.norm(v)) for v in links]
    tol = GEOMETRY_TOL * arm.scale
    for i in range(n - 1):
        if lengths[i] <= tol:
            return f"axes {i + 1} and {i + 2} are the same line"
    if lengths[-1] <= tol:
        if n == 2:
            return "the flange origin is on axis 2, so joint 2 cannot move it"
        x_last = across(f[:3, 3] + f[:3, 0]) if not _parallel(f[:3, 0], w1) else \
            across(f[:3, 3] + f[:3, 1])
        links[-1] = x_last / np.linalg.norm(x_last)  # link 3's direction: the flange's x
    pre = _frame(w1, links[0] / lengths[0], origin)
    shift = np.zeros(n)
    for i in range(1, n):
        shift[i] = _turn(w1, links[i - 1], links[i])
    sign = np.array([float(np.sign(ax.w[i] @ w1)) for i in range(n)])
    lesson = _lesson_arm(arm, [dict(a=L) for L in lengths],
                         Planar2RSolver() if n == 2 else Planar3RSolver())
    post = np.linalg.inv(lesson._fk(shift) ) @ np.linalg.inv(pre) @ f
    post[:3, 3] = 0.0  # the flange origin is the lesson arm's (rounding aside)
    fitted = Fitted(lesson, pre, post, sign, shift)
    try:
        fitted.check(arm)
    except InputError:
        return "it is not planar (the fitted planar arm's FK differs from the table's)"
    if n == 2:
        return Family("planar 2R", "the law of cosines (elbow up and down), for a position "
                      "in its plane", 2, fitted)
    return Family("planar 3R", "the wrist point (target minus link 3 along the tool angle), "
                  "then the planar 2R, for a position and tool angle in its plane", 2, fitted)


def _lesson_arm(arm: SerialArm, rows: list[dict[str, Any]], solver: Any,
                **kw: Any) -> SerialArm:
    from ..dh import Link, SerialArm

    return SerialArm(tuple(Link(**r) for r in rows), solver=solver, name=arm.name,
                     units=arm.units, **kw)


def _angular(arm: SerialArm, ax: ZeroAxes) -> Family | str:
    """The angular 3R of Aula 23 (axis 1 across axes 2 and 3, which are parallel): the
    lesson solver, fitted; or why not."""
    w1, w2 = ax.w[0], ax.w[1]
    u = _units(arm)
    if not _parallel(ax.w[2], w2):
        return f"axes 2 and 3 are {_angle(ax.w[2], w2):.4g} deg from parallel"
    if abs(float(w1 @ w2)) > GEOMETRY_TOL:
        return f"axes 1 and 2 are {90 - _angle(w1, w2):.4g} deg from perpendicular"
    f = ax.frames[-1][:3, 3]
    tol = GEOMETRY_TOL * arm.scale
    side = float((f - ax.r[0]) @ w2)
    if abs(side) > tol:
        return (f"the flange origin is {abs(side):.6g}{u} off axis 1's plane across axis 2 "
                "(a shoulder offset, as the Puma's d3): the angular 3R has none")
    o1, o2, _ = _closest(ax, 0, 1)
    x = np.cross(w1, w2)
    r0 = float((o2 - o1) @ x)

    def across(v: FloatArray) -> FloatArray:
        return v - (v @ w2) * w2

    upper = across(ax.r[2] - o2)
    fore = across(f - ax.r[2])
    L2, L3 = float(np.linalg.norm(upper)), float(np.linalg.norm(fore))
    if L2 <= tol:
        return "axes 2 and 3 are the same line"
    if L3 <= tol:
        return "the flange origin is on axis 3, so joint 3 cannot move it"
    pre = _frame(w1, x, o1)
    shift = np.array([0.0, _turn(w2, x, upper), _turn(w2, upper, fore)])
    sign = np.array([1.0, 1.0, float(np.sign(ax.w[2] @ w2))])
    g = RRRGeometry(z0=0.0, r0=r0, L2=L2, L3=L3)
    lesson = _lesson_arm(arm, [dict(a=r0, alpha=np.pi / 2), dict(a=L2), dict(a=L3)],
                         Angular3RSolver(g))
    post = np.linalg.inv(lesson._fk(shift)) @ np.linalg.inv(pre) @ ax.frames[-1]
    post[:3, 3] = 0.0
    fitted = Fitted(lesson, pre, post, sign, shift)
    try:
        fitted.check(arm)
    except InputError:
        return "it is not the angular 3R (the fitted arm's FK differs from the table's)"
    return Family("angular (anthropomorphic) 3R", "joint 1 turns to the target, then the "
                  "planar two-link chain of joints 2-3 (front or back, elbow up or down), for "
                  "a position", 4, fitted)


# ------------------------------------------------------------------ the hook into rikin.ik
def _course_match(arm: SerialArm) -> families6r.Match | str | None:
    """For :mod:`rikin.ik.families6r`: the course family's match, the reason an arm that is
    not a 6R has no closed form, or None for a 6R (the 6R families decide those)."""
    found = family_of(arm)
    if isinstance(found, Family):
        solver = found.solver
        return families6r.Match(str(found), lambda _arm: solver, found.count)
    return found


families6r.BEFORE.append(_course_match)
