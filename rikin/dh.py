"""Links and serial arms from Denavit-Hartenberg tables; forward kinematics.

Two conventions (see the book's conventions page):

* ``"standard"`` (distal, Denavit-Hartenberg 1955 as in Corke's ``DHRobot``):
  ``T_{i-1,i} = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``; joint i moves about
  or along ``z_{i-1}``.
* ``"modified"`` (proximal, Craig): ``T_{i-1,i} = Rx(alpha_{i-1}) Tx(a_{i-1})
  Rz(theta_i) Tz(d_i)``; joint i moves about or along ``z_i``. A modified
  link stores ``alpha_{i-1}`` and ``a_{i-1}`` in its ``alpha`` and ``a``.

For a revolute joint ``theta_i = s_i q_i + offset``; for a prismatic joint
``theta_i`` is the link's fixed ``theta`` and ``d_i = d + s_i q_i + offset``,
where ``s_i`` is the link's ``direction``: +1 (the default) when the joint
turns about (or slides along) its DH z axis as ``q_i`` grows, -1 when the
robot's data sheet counts it the other way (KUKA's A1, A4, A6). ``q`` and the
joint limits are always the data sheet's values; IK solvers see the DH values
``s_i q_i`` (see :attr:`SerialArm.directions`).
The arm's pose is ``T_world_tcp = base @ T_0_n(q) @ tool``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np

from ._validate import (
    FloatArray,
    _describe,
    as_flag,
    as_float_array,
    as_pose,
    as_real,
    check_length_range,
    check_radians,
    clean_pose,
)
from .errors import InputError
from .tolerances import DEGREES_SUSPECT, MAX_LENGTH
from .transforms import _inv_transform

#: rikin.ik.solve and solve_batch, registered by rikin.ik.api when it is imported.
_IK_ENTRY: dict[str, Any] = {}


def _one_pose(T: Any, name: str) -> FloatArray:
    arr = as_pose(T, name)
    if arr.shape != (4, 4):
        raise InputError(f"{name} must be one 4x4 homogeneous transform, got shape {arr.shape}")
    return arr

Convention = Literal["standard", "modified"]
JointType = Literal["R", "P"]

__all__ = ["Link", "SerialArm", "link_transform"]


@dataclass(frozen=True)
class Link:
    """One row of a DH table.

    Parameters
    ----------
    joint : {"R", "P"}
        Revolute or prismatic.
    d, a : float
        Link offset and length, in the arm's length units.
    alpha : float
        Link twist, radians. For a modified-DH arm this is ``alpha_{i-1}``.
    offset : float
        Added to the joint variable: to theta (revolute, rad) or d (prismatic).
    theta : float
        Fixed joint angle of a prismatic joint, radians (ignored if revolute).
    qlim : (float, float) or None
        Joint limits (rad or length units), inclusive, of the joint value ``q`` as the
        data sheet counts it (so with ``direction=-1`` exactly as printed).
    direction : {1, -1}
        +1: ``q`` turns the joint about (or slides it along) its DH z axis, so
        ``theta = q + offset``. -1: the data sheet counts the joint the other way,
        ``theta = -q + offset`` (``d = d - q + offset`` for a prismatic joint).

    The fields accept sympy expressions too, so the same table function can
    build a numeric arm and a symbolic one (see :mod:`rikin.symbolic`).

    Examples
    --------
    KUKA counts A1 clockwise seen from above, about -z:

    >>> a1 = Link(d=0.4, a=0.18, alpha=-np.pi / 2, direction=-1)
    >>> float(link_transform(a1, np.array(0.3), "standard")[1, 0].round(6))  # sin(theta)
    -0.29552
    """

    joint: JointType = "R"
    d: Any = 0.0
    a: Any = 0.0
    alpha: Any = 0.0
    offset: Any = 0.0
    theta: Any = 0.0
    qlim: tuple[float, float] | None = None
    direction: int = 1

    def __post_init__(self) -> None:
        if not isinstance(self.joint, str) or self.joint not in ("R", "P"):
            raise InputError(f"joint must be 'R' or 'P', got {self.joint!r}")
        object.__setattr__(self, "direction", _direction(self.direction))
        for fname in ("d", "a", "alpha", "offset", "theta"):
            value = getattr(self, fname)
            if type(value).__module__.startswith("sympy"):
                if getattr(value, "is_Matrix", False):
                    raise InputError(f"{fname} must be one number or sympy expression, got a "
                                     f"Matrix {value!r:.60}")
                continue  # a symbolic table (rikin.symbolic); numeric arms check again
            number = as_real(value, fname)
            object.__setattr__(self, fname, number)
            if fname in ("d", "a") or (fname == "offset" and self.joint == "P"):
                check_length_range(abs(number), fname)
            elif abs(number) > DEGREES_SUSPECT:  # a twist typed in degrees (alpha=90)
                check_radians(np.array(number), fname)
        if self.qlim is not None:
            try:
                if getattr(self.qlim, "shape", (2,)) != (2,):
                    raise ValueError
                lo, hi = self.qlim
            except (TypeError, ValueError):
                raise InputError(
                    f"qlim must be a pair (lower, upper) or None, got {self.qlim!r}"
                ) from None
            lo_f, hi_f = _limit(lo, "qlim lower"), _limit(hi, "qlim upper")
            if not lo_f <= hi_f:
                raise InputError(
                    f"qlim must be (lower, upper) with lower <= upper, got {self.qlim}"
                )
            if self.joint == "R":  # (-170, 170) from a data sheet: degrees
                finite = [v for v in (lo_f, hi_f) if math.isfinite(v)]
                check_radians(np.array(finite), "qlim")
            object.__setattr__(self, "qlim", (lo_f, hi_f))

    @property
    def is_revolute(self) -> bool:
        """True for a revolute joint."""
        return self.joint == "R"


def _direction(value: Any) -> int:
    """A joint's direction, +1 or -1 (numbers only: not a bool, not text), or InputError."""
    if not isinstance(value, (bool, np.bool_)) and isinstance(
        value, (int, float, np.integer, np.floating)
    ) and value in (1, -1):
        return int(value)
    raise InputError(
        f"direction must be +1 (q turns the joint about, or slides it along, its DH z axis) "
        f"or -1 (the data sheet counts the joint the other way), got {value!r:.60}"
    )


def _limit(value: Any, name: str) -> float:
    """One joint limit: a real number, possibly infinite, never NaN."""
    if isinstance(value, float) and value == value:
        return value
    v = _number(value, name)
    if v != v:
        raise InputError(f"{name} is NaN")
    return v


def _number(value: Any, name: str) -> float:
    """A real scalar (infinity allowed) without the finiteness check of ``as_real``."""
    not_real = (bool, np.bool_, str, bytes, complex, np.complexfloating)
    if value is None or isinstance(value, not_real):
        raise InputError(f"{name} must be a number, got {value!r}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if raw.shape != () or raw.dtype.kind not in "fiuO":
        raise InputError(f"{name} must be one number, got {value!r}")
    try:
        return float(raw)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be a number, got {value!r}") from None


def link_transform(link: Link, q: FloatArray, convention: Convention) -> FloatArray:
    """Transform ``T_{i-1,i}`` of one link for joint values ``q`` of shape ``(...)``.

    Returns an array of shape ``(..., 4, 4)``. Inputs are trusted (already validated).
    """
    if q.ndim == 0:
        return _link_transform_one(link, float(q), convention)
    if link.direction < 0:
        q = -q
    if link.is_revolute:
        theta = q + link.offset
        d = np.full_like(q, link.d)
    else:
        theta = np.full_like(q, link.theta)
        d = q + link.d + link.offset
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(link.alpha), np.sin(link.alpha)
    a = link.a
    T = np.zeros(q.shape + (4, 4))
    if convention == "standard":
        T[..., 0, 0] = ct
        T[..., 0, 1] = -st * ca
        T[..., 0, 2] = st * sa
        T[..., 0, 3] = a * ct
        T[..., 1, 0] = st
        T[..., 1, 1] = ct * ca
        T[..., 1, 2] = -ct * sa
        T[..., 1, 3] = a * st
        T[..., 2, 1] = sa
        T[..., 2, 2] = ca
        T[..., 2, 3] = d
    else:
        T[..., 0, 0] = ct
        T[..., 0, 1] = -st
        T[..., 0, 3] = a
        T[..., 1, 0] = st * ca
        T[..., 1, 1] = ct * ca
        T[..., 1, 2] = -sa
        T[..., 1, 3] = -sa * d
        T[..., 2, 0] = st * sa
        T[..., 2, 1] = ct * sa
        T[..., 2, 2] = ca
        T[..., 2, 3] = ca * d
    T[..., 3, 3] = 1.0
    return T


def _link_transform_one(link: Link, q: float, convention: Convention) -> FloatArray:
    """:func:`link_transform` for one joint value, in scalar arithmetic (same formulas)."""
    q = q * link.direction
    if link.is_revolute:
        theta, d = q + float(link.offset), float(link.d)
    else:
        theta, d = float(link.theta), q + float(link.d) + float(link.offset)
    ct, st = math.cos(theta), math.sin(theta)
    alpha, a = float(link.alpha), float(link.a)
    ca, sa = math.cos(alpha), math.sin(alpha)
    if convention == "standard":
        rows = [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0.0, sa, ca, d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    else:
        rows = [
            [ct, -st, 0.0, a],
            [st * ca, ct * ca, -sa, -sa * d],
            [st * sa, ct * sa, ca, ca * d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    return np.array(rows)


def _unknown_options(method: str, unknown: dict[str, Any], known: tuple[str, ...]) -> None:
    names = ", ".join(sorted(unknown))
    raise InputError(
        f"arm.{method}() has no option {names}; its options are {', '.join(known)}"
    )


@dataclass(frozen=True, eq=False)
class SerialArm:
    """A serial arm: a DH table, a convention, base and tool transforms, units.

    Parameters
    ----------
    links : tuple of Link
    convention : {"standard", "modified"}
    base : ndarray, shape (4, 4)
        ``T_world_0``. Identity by default.
    tool : ndarray, shape (4, 4)
        ``T_n_tcp``: the tool centre point in the last link's frame.
    units : str
        Name of the length unit ("mm", "cm", "" for unitless lesson arms).
    name : str
    solver : object, optional
        The closed-form IK of this arm's family (set by :mod:`rikin.robots`).

    Examples
    --------
    >>> arm = SerialArm((Link(a=1.0), Link(a=1.0)), name="2R")
    >>> arm.fk([0.0, np.pi / 2])[:3, 3].round(6)
    array([1., 1., 0.])
    """

    links: tuple[Link, ...]
    convention: Convention = "standard"
    base: FloatArray = field(default_factory=lambda: np.eye(4))
    tool: FloatArray = field(default_factory=lambda: np.eye(4))
    units: str = ""
    name: str = "arm"
    solver: Any = None

    def __post_init__(self) -> None:
        if not isinstance(self.convention, str) or self.convention not in ("standard", "modified"):
            raise InputError(
                f"convention must be 'standard' or 'modified', got {self.convention!r}"
            )
        for fname in ("units", "name"):
            if not isinstance(getattr(self, fname), str):
                raise InputError(f"{fname} must be a string, got {getattr(self, fname)!r}")
        if isinstance(self.links, Link):
            raise InputError(
                "links must be a sequence of rikin.Link, got one Link: wrap it, (link,)"
            )
        try:
            links = tuple(self.links)
        except TypeError:
            raise InputError(
                f"links must be a sequence of rikin.Link, got {type(self.links).__name__}"
            ) from None
        if not links:
            raise InputError("links is empty: an arm needs at least one link")
        for i, lk in enumerate(links, 1):
            if not isinstance(lk, Link):
                raise InputError(f"links: link {i} must be a rikin.Link, got {type(lk).__name__}")
            for fname in ("d", "a", "alpha", "offset", "theta"):
                val = getattr(lk, fname)
                try:
                    fval = float(val)
                except (TypeError, ValueError) as exc:
                    raise InputError(
                        f"link {i} field {fname} must be a number for a numeric arm, got {val!r}; "
                        "use rikin.symbolic for symbolic tables"
                    ) from exc
                if not math.isfinite(fval):
                    raise InputError(f"link {i} field {fname} is {fval}")
        if self.solver is not None and not (hasattr(self.solver, "ik")
                                            and hasattr(self.solver, "check")):
            raise InputError(f"solver must be a closed-form IK solver of rikin.ik (or None), "
                             f"got {self.solver!r:.60}")
        object.__setattr__(self, "links", links)
        revolute = np.array([lk.is_revolute for lk in links])
        revolute.setflags(write=False)
        object.__setattr__(self, "_revolute", revolute)
        directions = np.array([lk.direction for lk in links], dtype=np.int64)
        directions.setflags(write=False)
        object.__setattr__(self, "_directions", directions)
        reversed_joints = tuple(i for i, lk in enumerate(links, 1) if lk.direction < 0)
        object.__setattr__(self, "_reversed_joints", reversed_joints)
        for fname in ("base", "tool"):
            T, dist = clean_pose(_one_pose(getattr(self, fname), fname))
            T = T.copy()
            T.setflags(write=False)
            object.__setattr__(self, fname, T)
        # their inverses, which every IK call applies (_world_to_base): taken once here
        object.__setattr__(self, "_frames_inv", (_inv_transform(self.base),
                                                 _inv_transform(self.tool)))
        size = sum(abs(float(lk.a)) + abs(float(lk.d)) for lk in links)
        check_length_range(size, "the arm's size (sum of |a| and |d|)", lower=True)
        object.__setattr__(self, "_scale", size if size > 0 else 1.0)
        if self.solver is not None:
            self._check_solver()

    def _check_solver(self) -> None:
        """Raise InputError unless ``self.solver`` solves this arm: a lesson solver handed
        to another arm would otherwise give wrong solutions (or none) without saying why.
        The solver sees the arm in DH joint values (:attr:`_dh`)."""
        if self.reversed_joints:
            self._dh  # noqa: B018 - building the twin checks its solver (this same one)
            return
        try:
            self.solver.check(self)
        except InputError as exc:
            raise InputError(
                f"solver={type(self.solver).__name__} does not fit this arm, so it cannot "
                f"solve its IK: {exc}. Leave solver out: rikin then finds the arm's family "
                "from its table (rikin.ik.classify says which)"
            ) from None

    # ------------------------------------------------------------------ info
    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.links)

    @property
    def revolute(self) -> FloatArray:
        """Boolean mask, shape ``(n,)``: True where the joint is revolute (read-only)."""
        return self._revolute  # type: ignore[attr-defined]

    @property
    def directions(self) -> FloatArray:
        """Each joint's direction, shape ``(n,)``: +1 where ``q`` turns (slides) about
        (along) the DH z axis, -1 where the data sheet counts the joint the other way
        (read-only). The DH joint values are ``directions * q``."""
        return self._directions  # type: ignore[attr-defined]

    @property
    def reversed_joints(self) -> tuple[int, ...]:
        """The joints (numbered from 1) whose direction is -1; empty for most arms."""
        return self._reversed_joints  # type: ignore[attr-defined]

    @property
    def _dh(self) -> SerialArm:
        """The arm as its IK solvers see it: the same table with every direction +1, so
        its joint values are the DH ones (``directions * q``); no joint limits (the
        data sheet's apply to ``q``). ``self`` when no joint is reversed."""
        if not self.reversed_joints:
            return self
        twin = self.__dict__.get("_dh_twin")
        if twin is None:
            links = tuple(replace(lk, direction=1, qlim=None) for lk in self.links)
            twin = replace(self, links=links)
            object.__setattr__(self, "_dh_twin", twin)
        return twin

    @property
    def _flange(self) -> SerialArm:
        """:attr:`_dh` with no base, no tool and no solver: ``_flange._fk(q_dh)`` is
        ``T_0_n`` in DH joint values (what solvers fit their geometry to)."""
        bare = self.__dict__.get("_flange_arm")
        if bare is None:
            bare = replace(self._dh, base=np.eye(4), tool=np.eye(4), solver=None)
            object.__setattr__(self, "_flange_arm", bare)
        return bare

    @property
    def qlim(self) -> FloatArray:
        """Joint limits, shape ``(n, 2)``; ``-inf``/``inf`` where a joint has none."""
        return np.array(
            [lk.qlim if lk.qlim is not None else (-np.inf, np.inf) for lk in self.links],
            dtype=np.float64,
        )

    @property
    def joint_types(self) -> str:
        """The joint types as a string, e.g. ``"RRRRRR"`` or ``"PPRRR"``."""
        return "".join(lk.joint for lk in self.links)

    @property
    def scale(self) -> float:
        """A characteristic length of the arm, for relative tolerances: the sum of |a| and
        |d| over its links (1 when they are all zero), in the arm's units."""
        return self._scale  # type: ignore[attr-defined]

    def replace(self, **changes: Any) -> SerialArm:
        """A copy with some fields changed, e.g. ``arm.replace(tool=T)``."""
        try:
            return replace(self, **changes)
        except TypeError as exc:
            fields = ", ".join(self.__dataclass_fields__)
            raise InputError(f"replace: {exc}; the fields are {fields}") from None

    def __repr__(self) -> str:
        return (
            f"SerialArm(name={self.name!r}, {self.joint_types}, {self.convention} DH, "
            f"units={self.units!r})"
        )

    def dh_table(self) -> str:
        """The DH table as aligned text, one row per joint; a joint whose ``direction`` is -1
        reads ``-q<i>``."""
        head = (
            ("alpha_{i-1}", "a_{i-1}", "theta_i", "d_i")
            if self.convention == "modified"
            else ("theta_i", "d_i", "a_i", "alpha_i")
        )
        rows = [f"{'j':>2} {'type':>4} " + " ".join(f"{h:>11}" for h in head) + f" {'offset':>9}"]
        for i, lk in enumerate(self.links, 1):
            qi = f"q{i}" if lk.direction > 0 else f"-q{i}"
            th = qi if lk.is_revolute else f"{float(lk.theta):.6g}"
            d = f"{float(lk.d):.6g}" if lk.is_revolute else f"{qi}+{float(lk.d):.6g}"
            vals = (
                (f"{float(lk.alpha):.6g}", f"{float(lk.a):.6g}", th, d)
                if self.convention == "modified"
                else (th, d, f"{float(lk.a):.6g}", f"{float(lk.alpha):.6g}")
            )
            rows.append(
                f"{i:>2} {lk.joint:>4} "
                + " ".join(f"{v:>11}" for v in vals)
                + f" {float(lk.offset):>9.6g}"
            )
        return "\n".join(rows)

    # ------------------------------------------------------------------ FK
    def check_q(self, q: Any, name: str = "q", *, check_degrees: bool = True) -> FloatArray:
        """Validate joint values: shape ``(n,)`` or ``(N, n)``, finite.

        Revolute values are radians, any value (read modulo 2*pi); with
        ``check_degrees`` (the default) values that are degrees beyond
        reasonable doubt raise (see :func:`rikin._validate.check_radians`).
        """
        if not isinstance(name, str):
            raise InputError(
                f"name must be text (the argument's name in messages), got {name!r:.60}"
            )
        if check_degrees is not True and check_degrees is not False:
            as_flag(check_degrees, "check_degrees")
        arr = as_float_array(q, name)
        if arr.ndim not in (1, 2) or arr.shape[-1] != self.n:
            raise InputError(
                f"{name} must have shape ({self.n},) or (N, {self.n}) for this {self.n}-joint arm "
                f"({self.joint_types}), got shape {arr.shape}"
            )
        a = np.abs(arr)
        if a.max(initial=0.0) > DEGREES_SUSPECT:  # say which joint, in words
            names = [f"{name}[{i}] (joint {i + 1})" for i in range(self.n)]
            angles = np.where(self.revolute, arr, 0.0)
            check_radians(angles, name, names, joint_vectors=True, degrees_hint=check_degrees)
            lengths = np.where(self.revolute, 0.0, a)
            if lengths.max(initial=0.0) > MAX_LENGTH:
                j = int(np.argmax(lengths.max(axis=0) if lengths.ndim == 2 else lengths))
                check_length_range(float(lengths.max()), names[j])
        return arr

    def fk(self, q: Any, *, frames: bool = False, check_degrees: bool = True) -> FloatArray:
        """Pose of the tool centre point, ``T_world_tcp = base @ T_0_n(q) @ tool``.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint values: radians (revolute), length units (prismatic).
        frames : bool
            Also return every intermediate frame.
        check_degrees : bool
            Refuse joint values that are degrees beyond reasonable doubt (a
            round number of degrees such as 90, or several values beyond four
            turns). False accepts every finite angle below ``MAX_ANGLE``.

        Returns
        -------
        T : ndarray, shape (4, 4) or (N, 4, 4)
            The TCP pose in the world frame. With ``frames=True``, shape
            ``(n + 2, 4, 4)`` or ``(N, n + 2, 4, 4)``: frame 0 (the base),
            frames 1..n, then the TCP, all in world coordinates.

        Raises
        ------
        InputError
            Wrong number of joints, NaN, or angles that look like degrees.
            Any other angle is read modulo 2*pi: ``fk(q + 2*pi*k) == fk(q)``.
        """
        qv = self.check_q(q, check_degrees=check_degrees)
        if frames is not False and frames is not True:
            frames = as_flag(frames, "frames")
        return self._fk(qv, frames)

    def _fk(self, q: FloatArray, frames: bool = False) -> FloatArray:
        T = np.broadcast_to(self.base, q.shape[:-1] + (4, 4)).copy()
        out = [T] if frames else None
        for i, lk in enumerate(self.links):
            T = T @ link_transform(lk, q[..., i], self.convention)
            if out is not None:
                out.append(T)
        T = T @ self.tool
        if out is not None:
            out.append(T)
            return np.stack(out, axis=-3)
        return T

    def _link_constants(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Each link as ``Rz(theta) = cos(theta) P + sin(theta) Q + E`` makes it: constants
        ``C1, C2, C3 (n, 4, 4)`` with link i ``= cos(theta_i) C1[i] + sin(theta_i) C2[i] +
        C3[i]`` (theta_i = q_i + offset_i of a revolute joint; standard: ``Rz(theta) [Tz(d)
        Tx(a) Rx(alpha)]``, modified: ``[Rx(alpha) Tx(a) Tz(d)] Rz(theta)``, as Rz and Tz
        commute), the base folded into the first link and the tool into the last, and
        the offsets ``(n,)``."""
        P = np.zeros((4, 4))
        P[0, 0] = P[1, 1] = 1.0
        Q = np.zeros((4, 4))
        Q[0, 1], Q[1, 0] = -1.0, 1.0
        E = np.diag([0.0, 0.0, 1.0, 1.0])
        C1, C2, C3 = (np.empty((self.n, 4, 4)) for _ in range(3))
        for i, lk in enumerate(self.links):
            D = _link_transform_one(replace(lk, offset=0.0), 0.0, self.convention)
            for out, Z in ((C1, P), (C2, Q), (C3, E)):
                out[i] = Z @ D if self.convention == "standard" else D @ Z
        for out in (C1, C2, C3):
            out[0] = self.base @ out[0]
            out[-1] = out[-1] @ self.tool
        # a reversed joint: theta = -q + o, and cos(-q + o) C1 + sin(-q + o) C2 is
        # cos(q - o) C1 + sin(q - o) (-C2)
        s = self.directions.astype(np.float64)
        C2 *= s[:, None, None]
        return C1, C2, C3, s * np.array([float(lk.offset) for lk in self.links])

    def fk_flange(self, q: Any) -> FloatArray:
        """``T_0_n(q)``: the last link's frame in frame 0 (no base, no tool)."""
        qv = self.check_q(q)
        return self._flange._fk(qv * self.directions)

    def joint_axes(self, q: Any) -> tuple[FloatArray, FloatArray]:
        """World position and direction of every joint axis at ``q``.

        Returns
        -------
        origins, axes : ndarray, shape (..., n, 3)
            A point on each axis, and its unit direction: the way a revolute joint
            turns (right hand) or a prismatic joint slides as its ``q`` grows, so the
            DH z axis times the joint's ``direction``.
        """
        qv = self.check_q(q)
        F = self._fk(qv, frames=True)
        if self.convention == "standard":
            idx = np.arange(self.n)  # joint i moves about z_{i-1}
        else:
            idx = np.arange(1, self.n + 1)  # joint i moves about z_i
        Fj = np.take(F, idx, axis=-3)  # (..., n, 4, 4): the frame each joint moves about
        return Fj[..., :3, 3], Fj[..., :3, 2] * self.directions[:, None]

    def jacobian(self, q: Any) -> FloatArray:
        """Geometric Jacobian in the world frame at the TCP.

        Returns
        -------
        J : ndarray, shape (6, n) or (N, 6, n)
            Rows 0-2 linear velocity (length units per unit joint rate),
            rows 3-5 angular velocity (rad per unit joint rate).
        """
        qv = self.check_q(q)
        F = self._fk(qv, frames=True)
        p_e = F[..., -1, :3, 3]
        origins, axes = self.joint_axes(qv)
        rev = self.revolute
        lin = np.where(rev[:, None], np.cross(axes, p_e[..., None, :] - origins), axes)
        ang = np.where(rev[:, None], axes, 0.0)
        return np.swapaxes(np.concatenate([lin, ang], axis=-1), -1, -2)

    # ------------------------------------------------------------------ IK
    def ik(
        self, target: Any, *, within_limits: Any = False, near: Any = None, **unknown: Any
    ) -> Any:
        """Every closed-form IK solution of ``target`` (an ``IKResult``); see
        :func:`rikin.ik.solve`. rikin.ik registers it here, so this module never
        imports :mod:`rikin.ik` (data flows robots -> dh -> ik)."""
        if unknown:
            _unknown_options("ik", unknown, ("within_limits", "near"))
        if within_limits is False and near is None:  # the one-pose fast path: no kwargs
            return _IK_ENTRY["solve"](self, target)
        return _IK_ENTRY["solve"](self, target, within_limits=within_limits, near=near)

    def ik_batch(
        self, T: Any, *, chunk_size: Any = 4096, workers: Any = None, **unknown: Any
    ) -> Any:
        """All solutions for many poses at once (a ``BatchIKResult``); see
        :func:`rikin.ik.solve_batch`."""
        if unknown:
            _unknown_options("ik_batch", unknown, ("chunk_size", "workers"))
        return _IK_ENTRY["solve_batch"](self, T, chunk_size=chunk_size, workers=workers)

    def world_to_base(self, T_world: Any) -> FloatArray:
        """``T_0_n = base^-1 @ T_world_tcp @ tool^-1`` for poses ``(..., 4, 4)``."""
        return self._world_to_base(as_pose(T_world, "T_world"))

    def _world_to_base(self, T_world: FloatArray) -> FloatArray:
        """:meth:`world_to_base` for trusted input."""
        base_inv, tool_inv = self._frames_inv  # type: ignore[attr-defined]
        return base_inv @ T_world @ tool_inv


def check_arm(arm: Any, name: str = "arm") -> SerialArm:
    """``arm`` if it is a :class:`SerialArm`, else InputError naming ``name``.

    The boundary check of every function that takes an arm; it lives beside the class it
    checks, so that :mod:`rikin._validate` (which this module imports) needs no arm."""
    if not isinstance(arm, SerialArm):
        raise InputError(f"{name} must be a rikin.SerialArm, got {_describe(arm)}")
    return arm
