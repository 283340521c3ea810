"""Checks applied at the public boundary; the code inside trusts their output."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .errors import InputError
from .tolerances import (
    DEGREES_FAR,
    DEGREES_ROUND,
    DEGREES_SUSPECT,
    MAX_ANGLE,
    ORTHONORMAL_TOL,
)

FloatArray = NDArray[np.float64]


def as_float_array(x: Any, name: str) -> FloatArray:
    """Return ``x`` as a float64 array, or raise InputError for non-numbers and NaN."""
    try:
        arr = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numbers, got {x!r}") from exc
    if not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))
        where = tuple(int(i) for i in bad[0])
        raise InputError(
            f"{name} contains NaN or infinity (first at index {where}); "
            "check the computation that produced it"
        )
    return arr


def check_shape_tail(arr: FloatArray, tail: tuple[int, ...], name: str, what: str) -> None:
    """Raise InputError unless ``arr.shape`` ends with ``tail``."""
    if arr.ndim < len(tail) or arr.shape[arr.ndim - len(tail) :] != tail:
        shape = "(..., " + ", ".join(map(str, tail)) + ")"
        raise InputError(f"{name} must be {what} of shape {shape}, got shape {arr.shape}")


def as_rotation(R: Any, name: str = "R") -> FloatArray:
    """Validate one or many rotation matrices ``(..., 3, 3)``.

    Raises
    ------
    InputError
        Wrong shape, NaN, columns not orthonormal, or a reflection (det = -1).
    """
    arr = as_float_array(R, name)
    check_shape_tail(arr, (3, 3), name, "a rotation matrix")
    check_rotation_values(arr, name)
    return arr


def _rotation_errors(R: list[list[float]]) -> tuple[float, float]:
    """(max |R^T R - I|, det R) of one 3x3 matrix, in scalar arithmetic."""
    (a, b, c), (d, e, f), (g, h, k) = R  # columns (a, d, g), (b, e, h), (c, f, k)
    err = max(
        abs(a * a + d * d + g * g - 1.0),
        abs(b * b + e * e + h * h - 1.0),
        abs(c * c + f * f + k * k - 1.0),
        abs(a * b + d * e + g * h),
        abs(a * c + d * f + g * k),
        abs(b * c + e * f + h * k),
    )
    det = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g)
    return err, det


def check_rotation_values(arr: FloatArray, name: str) -> None:
    """Raise InputError if any ``(3, 3)`` block of ``arr`` is not a proper rotation."""
    if arr.shape == (3, 3):  # one matrix: scalar arithmetic is ten times faster
        err1, det1 = _rotation_errors(arr.tolist())
        if err1 <= ORTHONORMAL_TOL and det1 >= 0:
            return
    gram = np.swapaxes(arr, -1, -2) @ arr
    err = np.abs(gram - np.eye(3)).max(axis=(-1, -2))
    if np.any(err > ORTHONORMAL_TOL):
        worst = float(err.max())
        raise InputError(
            f"{name} is not a rotation matrix: its columns are not orthonormal "
            f"(R^T R differs from the identity by {worst:.3g}, allowed {ORTHONORMAL_TOL:g})"
        )
    det = np.linalg.det(arr)
    if np.any(det < 0):
        raise InputError(
            f"{name} is a reflection, not a rotation (det = {float(det.min()):.3g}); "
            "a sign in one column is probably wrong"
        )


def as_pose(T: Any, name: str = "T") -> FloatArray:
    """Validate one or many homogeneous transforms ``(..., 4, 4)``."""
    arr = as_float_array(T, name)
    check_shape_tail(arr, (4, 4), name, "a homogeneous transform")
    bottom = arr[..., 3, :]
    if arr.shape == (4, 4):
        b = bottom.tolist()
        if max(abs(b[0]), abs(b[1]), abs(b[2]), abs(b[3] - 1.0)) <= 1e-9:
            check_rotation_values(arr[:3, :3], f"the rotation part of {name}")
            return arr
    if np.any(np.abs(bottom - np.array([0.0, 0.0, 0.0, 1.0])) > 1e-9):
        raise InputError(f"{name} must have last row [0, 0, 0, 1], got {bottom.reshape(-1, 4)[0]}")
    check_rotation_values(arr[..., :3, :3], f"the rotation part of {name}")
    return arr


def as_vector(x: Any, n: int, name: str) -> FloatArray:
    """Validate a vector of exactly ``n`` numbers (shape ``(n,)``)."""
    arr = as_float_array(x, name)
    if arr.shape != (n,):
        raise InputError(f"{name} must have shape ({n},), got shape {arr.shape}")
    return arr


def check_radians(
    values: FloatArray,
    name: str,
    index_names: list[str] | None = None,
    *,
    joint_vectors: bool = False,
    degrees_hint: bool = True,
) -> None:
    """Raise InputError when angles (rad) are degrees beyond reasonable doubt.

    Any angle is accepted and read modulo 2*pi (see the book's conventions
    page), except:

    * ``|value| > MAX_ANGLE``: too large to carry a meaningful fraction of a turn;
    * a value beyond one turn that is a whole multiple of 5 in ``DEGREES_ROUND``
      (10, 30, 45, 90, 180, ...): a round number of degrees;
    * with ``joint_vectors=True`` (``values`` of shape ``(..., n)``, one joint
      vector per row): two or more values of one row beyond ``DEGREES_FAR``
      (four turns), as the lesson's ``[99.6, 9, 26.4, 68.4, 30, 151]`` is.

    ``index_names`` names the entries of the last axis in the message.
    ``degrees_hint=False`` keeps only the first check.
    """
    a = np.abs(values)
    if a.size == 0 or a.max() <= DEGREES_SUSPECT:
        return
    lo, hi = DEGREES_ROUND
    huge = a > MAX_ANGLE
    whole5 = (a >= lo) & (a <= hi) & (np.remainder(a, 5.0) == 0.0) & degrees_hint
    far = (a > DEGREES_FAR) & (joint_vectors and degrees_hint)
    far_rows = (far.sum(axis=-1, keepdims=True) >= 2) & far
    for mask, why in (
        (huge, "huge"),
        (whole5, "a round number of degrees"),
        (far_rows, "one of several values beyond four turns"),
    ):
        if not np.any(mask):
            continue
        idx = tuple(int(i) for i in np.argwhere(mask)[0])
        pos = idx[-1] if idx else 0
        label = index_names[pos] if index_names and pos < len(index_names) else name
        value = float(values[idx])
        if why == "huge":
            raise InputError(
                f"{label} = {value:g} rad is too large for an angle: beyond {MAX_ANGLE:g} rad the "
                "rounding of the value alone moves the angle by more than 1e-10 rad. Wrap it "
                "first (rikin.wrap_angle) or check where it came from"
            )
        raise InputError(
            f"{label} = {value:g} looks like degrees ({why}): rikin takes radians "
            f"(any angle, read modulo 2*pi). Convert with numpy.radians({value:g}) = "
            f"{np.radians(value):.6g}"
        )
