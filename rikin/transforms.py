"""Rotations, homogeneous transforms, RPY and ZYZ angles.

Every function works on one value or a batch: angles of shape ``(...)`` give
matrices of shape ``(..., 3, 3)`` or ``(..., 4, 4)``. Angles are radians.
Conventions (stated once, in the book's conventions page):

* RPY: ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)`` (ZYX, fixed axes X, Y, Z).
* ZYZ Euler: ``R = Rz(phi) @ Ry(theta) @ Rz(psi)``.
* Names carry frames: ``T_0_6`` maps coordinates in frame 6 to frame 0.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._validate import (
    FloatArray,
    _to_float64,
    as_flag,
    as_float_array,
    as_pose,
    as_rotation,
    check_length_range,
    check_radians,
)
from .errors import InputError
from .tolerances import MAX_LENGTH, SINGULAR_TOL

__all__ = [
    "rotx",
    "roty",
    "rotz",
    "transl",
    "homogeneous",
    "trotx",
    "troty",
    "trotz",
    "inv_transform",
    "rpy_to_r",
    "r_to_rpy",
    "zyz_to_r",
    "r_to_zyz",
    "wrap_angle",
    "deg",
    "rad",
]


def _broadcast(name: str, *shapes: tuple[int, ...]) -> tuple[int, ...]:
    try:
        return np.broadcast_shapes(*shapes)
    except ValueError as exc:
        raise InputError(
            f"{name}: the shapes {', '.join(map(str, shapes))} do not broadcast together"
        ) from exc


def _angles(theta: Any, name: str) -> FloatArray:
    arr = as_float_array(theta, name)
    check_radians(arr, name)
    return arr


def _rot(theta: Any, axis: int, name: str) -> FloatArray:
    t = _angles(theta, name)
    c, s = np.cos(t), np.sin(t)
    R = np.zeros(t.shape + (3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R[..., axis, axis] = 1.0
    R[..., i, i] = c
    R[..., j, j] = c
    R[..., i, j] = -s
    R[..., j, i] = s
    return R


def rotx(theta: Any) -> FloatArray:
    """Rotation about x by ``theta``.

    Parameters
    ----------
    theta : float or array_like, shape (...)
        Angle in radians.

    Returns
    -------
    R : ndarray, shape (..., 3, 3)

    Examples
    --------
    >>> rotx(np.pi / 2).round(6)
    array([[ 1.,  0.,  0.],
           [ 0.,  0., -1.],
           [ 0.,  1.,  0.]])
    """
    return _rot(theta, 0, "theta")


def roty(theta: Any) -> FloatArray:
    """Rotation about y by ``theta`` (radians), shape ``(..., 3, 3)``."""
    return _rot(theta, 1, "theta")


def rotz(theta: Any) -> FloatArray:
    """Rotation about z by ``theta`` (radians), shape ``(..., 3, 3)``."""
    return _rot(theta, 2, "theta")


def homogeneous(R: Any = None, p: Any = None) -> FloatArray:
    """Homogeneous transform from a rotation and a translation.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3), optional
        Rotation (identity when omitted).
    p : array_like, shape (..., 3), optional
        Translation, in length units (zero when omitted).

    Returns
    -------
    T : ndarray, shape (..., 4, 4)
    """
    Rm = np.eye(3) if R is None else as_rotation(R, "R")
    pv = np.zeros(3) if p is None else as_float_array(p, "p")
    if pv.shape[-1:] != (3,):
        raise InputError(f"p must have shape (..., 3), got shape {pv.shape}")
    check_length_range(float(np.abs(pv).max(initial=0.0)), "p")
    shape = _broadcast("homogeneous(R, p)", Rm.shape[:-2], pv.shape[:-1])
    T = np.zeros(shape + (4, 4))
    T[..., :3, :3] = Rm
    T[..., :3, 3] = pv
    T[..., 3, 3] = 1.0
    return T


def transl(x: Any, y: Any = None, z: Any = None) -> FloatArray:
    """Pure translation ``(..., 4, 4)``: ``transl([x, y, z])`` or ``transl(x, y, z)``."""
    if y is None:
        if z is not None:
            raise InputError("transl takes transl([x, y, z]) or transl(x, y, z), not x and z alone")
        p = as_float_array(x, "x")
        if p.shape[-1:] != (3,):
            raise InputError(f"x must be [x, y, z], shape (..., 3), got shape {p.shape}")
        if p.size and np.abs(p).max() > MAX_LENGTH:
            check_length_range(float(np.abs(p).max()), "x")
        return homogeneous(None, p)
    xs = [as_float_array(v, n) for v, n in ((x, "x"), (y, "y"), (0.0 if z is None else z, "z"))]
    for v, n in zip(xs, "xyz", strict=True):
        if v.size and np.abs(v).max() > MAX_LENGTH:
            check_length_range(float(np.abs(v).max()), n)
    shape = _broadcast("transl(x, y, z)", *(v.shape for v in xs))
    return homogeneous(None, np.stack([np.broadcast_to(v, shape) for v in xs], axis=-1))


def trotx(theta: Any) -> FloatArray:
    """Pure rotation about x as a homogeneous transform ``(..., 4, 4)``."""
    return homogeneous(rotx(theta))


def troty(theta: Any) -> FloatArray:
    """Pure rotation about y as a homogeneous transform ``(..., 4, 4)``."""
    return homogeneous(roty(theta))


def trotz(theta: Any) -> FloatArray:
    """Pure rotation about z as a homogeneous transform ``(..., 4, 4)``."""
    return homogeneous(rotz(theta))


def inv_transform(T: Any) -> FloatArray:
    """Inverse of a homogeneous transform, using ``R^T`` (no general matrix inverse).

    Parameters
    ----------
    T : array_like, shape (..., 4, 4)
        ``T_a_b``.

    Returns
    -------
    T_inv : ndarray, shape (..., 4, 4)
        ``T_b_a``.
    """
    return _inv_transform(as_pose(T, "T"))


def _inv_transform(T: FloatArray) -> FloatArray:
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    out = np.zeros(T.shape)
    out[..., :3, :3] = Rt
    out[..., :3, 3] = -(Rt @ T[..., :3, 3:4])[..., 0]
    out[..., 3, 3] = 1.0
    return out


def rpy_to_r(roll: Any, pitch: Any, yaw: Any, *, degrees: bool = False) -> FloatArray:
    """Rotation from roll, pitch, yaw: ``Rz(yaw) @ Ry(pitch) @ Rx(roll)``.

    Parameters
    ----------
    roll, pitch, yaw : float or array_like, shape (...)
        Angles about the fixed x, y and z axes, radians (degrees with
        ``degrees=True``).

    Returns
    -------
    R : ndarray, shape (..., 3, 3)
    """
    r, p, y = (as_float_array(a, n) for a, n in ((roll, "roll"), (pitch, "pitch"), (yaw, "yaw")))
    _broadcast("rpy_to_r(roll, pitch, yaw)", r.shape, p.shape, y.shape)
    if as_flag(degrees, "degrees"):
        r, p, y = np.radians(r), np.radians(p), np.radians(y)
    return _rot(y, 2, "yaw") @ _rot(p, 1, "pitch") @ _rot(r, 0, "roll")


def r_to_rpy(R: Any, *, degrees: bool = False) -> FloatArray:
    """Roll, pitch, yaw of a rotation, inverse of :func:`rpy_to_r`.

    Pitch is in ``[-pi/2, pi/2]``. At gimbal lock (pitch = +-pi/2) roll and
    yaw are not separately defined; roll is set to 0 and yaw carries the whole
    rotation about the vertical, so ``rpy_to_r(*r_to_rpy(R))`` still gives R.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)

    Returns
    -------
    rpy : ndarray, shape (..., 3)
        ``[roll, pitch, yaw]`` in radians (degrees with ``degrees=True``).
    """
    degrees = as_flag(degrees, "degrees")
    Rm = as_rotation(R, "R")
    cp = np.hypot(Rm[..., 0, 0], Rm[..., 1, 0])
    pitch = np.arctan2(-Rm[..., 2, 0], cp)
    lock = cp < SINGULAR_TOL
    roll = np.where(lock, 0.0, np.arctan2(Rm[..., 2, 1], Rm[..., 2, 2]))
    # at lock, R = Rz(yaw) Ry(+-pi/2) Rx(0): yaw from the first two entries of column 1
    yaw_lock = np.arctan2(-Rm[..., 0, 1], Rm[..., 1, 1])
    yaw = np.where(lock, yaw_lock, np.arctan2(Rm[..., 1, 0], Rm[..., 0, 0]))
    out = np.stack([roll, pitch, yaw], axis=-1)
    return np.degrees(out) if degrees else out


def zyz_to_r(phi: Any, theta: Any, psi: Any, *, degrees: bool = False) -> FloatArray:
    """Rotation from ZYZ Euler angles: ``Rz(phi) @ Ry(theta) @ Rz(psi)``, shape ``(..., 3, 3)``."""
    a, b, c = (as_float_array(v, n) for v, n in ((phi, "phi"), (theta, "theta"), (psi, "psi")))
    _broadcast("zyz_to_r(phi, theta, psi)", a.shape, b.shape, c.shape)
    if as_flag(degrees, "degrees"):
        a, b, c = np.radians(a), np.radians(b), np.radians(c)
    return _rot(a, 2, "phi") @ _rot(b, 1, "theta") @ _rot(c, 2, "psi")


def r_to_zyz(R: Any, *, branch: int = 1, degrees: bool = False) -> FloatArray:
    """ZYZ Euler angles of a rotation, inverse of :func:`zyz_to_r`.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
    branch : {1, -1}
        ``1`` gives theta in ``[0, pi]``, ``-1`` the other solution
        ``(phi + pi, -theta, psi + pi)`` with theta in ``[-pi, 0]``.

    Returns
    -------
    angles : ndarray, shape (..., 3)
        ``[phi, theta, psi]``, radians wrapped to (-pi, pi]. When theta is 0
        or pi (singular), phi is 0 and psi carries the rotation.
    """
    if isinstance(branch, (bool, np.bool_)) or not isinstance(branch, (int, np.integer)) or (
        branch not in (1, -1)
    ):
        raise InputError(f"branch must be 1 or -1, got {branch!r}")
    degrees = as_flag(degrees, "degrees")
    Rm = as_rotation(R, "R")
    phi, theta, psi, _ = zyz_branches(Rm)
    slot = 0 if branch == 1 else 1
    out = _wrap_angle(np.stack([phi[..., slot], theta[..., slot], psi[..., slot]], axis=-1))
    return np.degrees(out) if degrees else out


def wrap_angle(theta: Any) -> FloatArray:
    """Wrap angles (radians) to the interval (-pi, pi]; shape preserved.

    Every finite value is wrapped exactly as the double it is (``numpy.where(revolute,
    wrap_angle(q), q)`` wraps a prismatic joint's length too, and drops it).

    Raises
    ------
    InputError
        ``theta`` is not real numbers (None, text, booleans, complex, symbols), or
        contains NaN or infinity: no angle to wrap (the message says where the first is).
    """
    if type(theta) is np.ndarray and theta.dtype == np.float64:
        t = theta
    else:
        t = _to_float64(theta, "theta")
    with np.errstate(invalid="ignore"):  # infinity: refused below
        w = _wrap_angle(t)
    if not np.isfinite(w).all():  # NaN or infinity came in: say where
        as_float_array(t, "theta")
    return w


def _wrap_angle(t: FloatArray) -> FloatArray:
    """:func:`wrap_angle` for trusted float arrays."""
    w = np.remainder(t + np.pi, 2 * np.pi) - np.pi
    return np.where(w <= -np.pi, w + 2 * np.pi, w)


def zyz_branches(
    M: FloatArray, hint_phi: FloatArray | float = 0.0
) -> tuple[FloatArray, FloatArray, FloatArray, np.ndarray]:
    """ZYZ angles of ``M = Rz(phi) Ry(theta) Rz(psi)``, both branches (trusted input).

    The spherical wrist of every IK family uses this decomposition.

    Parameters
    ----------
    M : ndarray, shape (..., 3, 3)
    hint_phi : float or ndarray broadcastable to (...)
        At the singularity (theta = 0 or pi) only phi + psi (or phi - psi) is
        fixed; phi takes this value.

    Returns
    -------
    phi, theta, psi : ndarray, shape (..., 2)
        Slot 0 has ``theta in [0, pi]``; slot 1 is ``(phi + pi, -theta, psi + pi)``
        (at the singularity, slot 1 repeats slot 0).
    singular : ndarray of bool, shape (...)
    """
    m02, m12, m22 = M[..., 0, 2], M[..., 1, 2], M[..., 2, 2]
    s = np.hypot(m02, m12)
    singular = s < SINGULAR_TOL
    theta = np.arctan2(s, m22)
    phi = np.arctan2(m12, m02)
    # psi from the rotation left after Rz(phi) Ry(theta), not from m31/m32 directly: near
    # the singularity phi carries a rounding error of ~eps/s, and this psi absorbs it, so
    # Rz(phi) Ry(theta) Rz(psi) reproduces M to ~eps instead of ~eps/s.
    safe = np.where(singular, 1.0, s)
    cp, sp = m02 / safe, m12 / safe
    a00 = cp * M[..., 0, 0] + sp * M[..., 1, 0]
    a10 = -sp * M[..., 0, 0] + cp * M[..., 1, 0]
    psi = np.arctan2(a10, m22 * a00 - s * M[..., 2, 0])
    if np.any(singular):
        hp = np.broadcast_to(np.asarray(hint_phi, dtype=np.float64), s.shape)
        up = m22 > 0  # theta = 0: M = Rz(phi + psi); theta = pi: M = Rz(phi - psi) Ry(pi)
        # Rz(a) Ry(pi) = [[-cos a, -sin a, 0], [-sin a, cos a, 0], [0, 0, -1]]
        total = np.where(
            up, np.arctan2(M[..., 1, 0], M[..., 0, 0]), np.arctan2(-M[..., 1, 0], -M[..., 0, 0])
        )
        phi = np.where(singular, hp, phi)
        psi = np.where(singular, np.where(up, total - hp, hp - total), psi)
        theta = np.where(singular, np.where(up, 0.0, np.pi), theta)
    # at the singularity both slots hold the same representative (phi = hint_phi)
    flip = np.where(singular, 0.0, np.pi)
    phis = np.stack([phi, phi + flip], axis=-1)
    thetas = np.stack([theta, np.where(singular, theta, -theta)], axis=-1)
    psis = np.stack([psi, psi + flip], axis=-1)
    return phis, thetas, psis, singular



def deg(theta: Any) -> FloatArray:
    """Radians to degrees (``numpy.degrees`` with input checking)."""
    return np.degrees(as_float_array(theta, "theta"))


def rad(theta: Any) -> FloatArray:
    """Degrees to radians (``numpy.radians`` with input checking)."""
    return np.radians(as_float_array(theta, "theta"))
