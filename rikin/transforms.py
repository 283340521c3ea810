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

from ._validate import FloatArray, as_float_array, as_pose, as_rotation, check_radians
from .errors import InputError
from .tolerances import SINGULAR_TOL

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
    shape = np.broadcast_shapes(Rm.shape[:-2], pv.shape[:-1])
    T = np.zeros(shape + (4, 4))
    T[..., :3, :3] = Rm
    T[..., :3, 3] = pv
    T[..., 3, 3] = 1.0
    return T


def transl(x: Any, y: Any = None, z: Any = None) -> FloatArray:
    """Pure translation ``(..., 4, 4)``: ``transl([x, y, z])`` or ``transl(x, y, z)``."""
    p = (
        as_float_array(x, "x")
        if y is None
        else np.stack(
            np.broadcast_arrays(
                as_float_array(x, "x"),
                as_float_array(y, "y"),
                as_float_array(0.0 if z is None else z, "z"),
            ),
            axis=-1,
        )
    )
    return homogeneous(None, p)


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
    if degrees:
        r, p, y = np.radians(r), np.radians(p), np.radians(y)
    return rotz(y) @ roty(p) @ rotx(r)


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
    if degrees:
        a, b, c = np.radians(a), np.radians(b), np.radians(c)
    return rotz(a) @ roty(b) @ rotz(c)


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
    if branch not in (1, -1):
        raise InputError(f"branch must be 1 or -1, got {branch!r}")
    from .ik.kernels import spherical_wrist  # the one ZYZ decomposition (imported late: cycle)

    Rm = as_rotation(R, "R")
    phi, theta, psi, _ = spherical_wrist(Rm)
    slot = 0 if branch == 1 else 1
    out = wrap_angle(np.stack([phi[..., slot], theta[..., slot], psi[..., slot]], axis=-1))
    return np.degrees(out) if degrees else out


def wrap_angle(theta: Any) -> FloatArray:
    """Wrap angles (radians) to the interval (-pi, pi]; shape preserved."""
    t = np.asarray(theta, dtype=np.float64)
    w = np.remainder(t + np.pi, 2 * np.pi) - np.pi
    return np.where(w <= -np.pi, w + 2 * np.pi, w)


def deg(theta: Any) -> FloatArray:
    """Radians to degrees (``numpy.degrees`` with input checking)."""
    return np.degrees(as_float_array(theta, "theta"))


def rad(theta: Any) -> FloatArray:
    """Degrees to radians (``numpy.radians`` with input checking)."""
    return np.radians(as_float_array(theta, "theta"))
