"""Checks applied at the public boundary; the code inside trusts their output."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .errors import InputError
from .tolerances import DEGREES_SUSPECT, ORTHONORMAL_TOL

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


def check_radians(values: FloatArray, name: str, index_names: list[str] | None = None) -> None:
    """Raise InputError when angles look like degrees (|value| > 2*pi)."""
    big = np.abs(values) > DEGREES_SUSPECT
    if np.any(big):
        idx = np.argwhere(big)[0]
        flat_pos = int(idx[-1]) if idx.size else 0
        label = index_names[flat_pos] if index_names and flat_pos < len(index_names) else name
        value = float(values[tuple(idx)])
        raise InputError(
            f"{label} = {value:g} looks like degrees: rikin takes radians "
            f"(|angle| <= 2*pi). Convert with numpy.radians({value:g}) = {np.radians(value):.6g}"
        )
