"""Checks applied at the public boundary; the code inside trusts their output."""

from __future__ import annotations

import math
import operator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .errors import InputError, OutOfRangeError
from .tolerances import (
    DEGREES_FAR,
    DEGREES_ROUND,
    DEGREES_SUSPECT,
    MAX_ANGLE,
    MAX_DISTANCE_RATIO,
    MAX_LENGTH,
    MIN_LENGTH,
    ORTHONORMAL_TOL,
    ROTATION_CLEAN_TOL,
)

FloatArray = NDArray[np.float64]


def _describe(x: Any) -> str:
    """A short ``repr`` of a rejected argument, for messages."""
    text = repr(x)
    return text if len(text) <= 80 else text[:77] + "..."


def _real(v: Any, name: str) -> float:
    """One element of an object array (or one scalar) as a float, or InputError."""
    if v is None:
        raise InputError(f"{name} contains None where a number is expected")
    if isinstance(v, (bool, np.bool_)):
        raise InputError(f"{name} contains the boolean {v!r} where a number is expected")
    if isinstance(v, (str, bytes)):
        raise InputError(f"{name} contains the text {v!r}; give numbers, not strings")
    if isinstance(v, (complex, np.complexfloating)):
        raise InputError(f"{name} contains the complex number {v!r}; rikin takes real values")
    try:
        return float(v)
    except (TypeError, ValueError, OverflowError) as exc:
        kind = "a symbolic expression" if type(v).__module__.startswith("sympy") else "not a number"
        raise InputError(
            f"{name} contains {_describe(v)}, {kind}; give real numbers"
            + (" (substitute the symbols first, or use rikin.symbolic)"
               if "symbolic" in kind else "")
        ) from exc


def as_float_array(x: Any, name: str) -> FloatArray:
    """Return ``x`` as a float64 array, or raise InputError.

    Accepted: real numbers (Python, numpy of any real dtype, sympy numbers) and
    nested lists or tuples of them. Refused, naming ``name``: None, text,
    booleans, complex numbers (never silently cut to their real part),
    symbols, ragged lists, NaN and infinity.
    """
    if type(x) is np.ndarray and x.dtype == np.float64:
        arr = x
    else:
        arr = _to_float64(x, name)
    if not np.isfinite(arr).all():
        if arr.ndim == 0:
            what = "NaN" if np.isnan(arr) else f"{float(arr)} (infinite)"
            raise InputError(f"{name} is {what}, not a number rikin can use; check the "
                             "computation that produced it")
        bad = np.argwhere(~np.isfinite(arr))
        where = tuple(int(i) for i in bad[0])
        raise InputError(
            f"{name} contains NaN or infinity (first at index {where}); "
            "check the computation that produced it"
        )
    return arr


def _to_float64(x: Any, name: str) -> FloatArray:
    if x is None:
        raise InputError(f"{name} is None; expected numbers")
    if isinstance(x, (str, bytes)):
        raise InputError(f"{name} must be numbers, got the text {_describe(x)}")
    try:
        raw = np.asarray(x)
    except (TypeError, ValueError) as exc:  # ragged nesting
        raise InputError(
            f"{name} must be a number or a rectangular array of numbers, got {_describe(x)}"
        ) from exc
    kind = raw.dtype.kind
    if kind in "fiu":
        with np.errstate(over="ignore"):  # float128 beyond double: caught as infinity
            return raw.astype(np.float64)
    if kind == "b":
        raise InputError(f"{name} must be numbers, got booleans ({_describe(x)})")
    if kind == "c":
        raise InputError(
            f"{name} must be real numbers, got complex values ({_describe(x)}); rikin does "
            "not drop an imaginary part silently"
        )
    if kind in "US":
        raise InputError(f"{name} must be numbers, got text ({_describe(x)})")
    if kind == "O":
        flat = [_real(v, name) for v in raw.ravel().tolist()]
        return np.array(flat, dtype=np.float64).reshape(raw.shape)
    raise InputError(f"{name} must be numbers, got {raw.dtype} values ({_describe(x)})")


def as_real(x: Any, name: str) -> float:
    """One finite real number (Python, numpy or sympy number), or InputError."""
    if isinstance(x, float) and math.isfinite(x):
        return x
    arr = as_float_array(x, name)
    if arr.shape != ():
        raise InputError(f"{name} must be one number, got shape {arr.shape}")
    return float(arr)


def as_length(x: Any, name: str, *, positive: bool = False, nonzero: bool = False) -> float:
    """One length of an arm: a finite real number within ``MAX_LENGTH`` and, unless
    zero, at least ``MIN_LENGTH`` in absolute value (see the conventions page); or InputError."""
    v = as_real(x, name)
    if positive and not v > 0:
        raise InputError(f"{name} must be a positive length, got {v!r}")
    if nonzero and v == 0:
        raise InputError(f"{name} must be a nonzero length, got 0")
    check_length_range(abs(v), name, lower=True)
    return v


def check_length_range(a: float, name: str, *, lower: bool = False) -> None:
    """Raise InputError if the absolute length ``a`` exceeds ``MAX_LENGTH`` (or, with
    ``lower``, is nonzero and below ``MIN_LENGTH``: an arm that small)."""
    if a > MAX_LENGTH or (lower and 0 < a < MIN_LENGTH):
        raise InputError(
            f"{name} = {a:g} is outside the lengths rikin handles, {MIN_LENGTH:g} to "
            f"{MAX_LENGTH:g} in the arm's units: its formulas square and multiply lengths, "
            "which overflows or underflows double precision beyond that; change the unit "
            "(e.g. mm to m)"
        )


def check_distances(P: FloatArray, size: float, name: str, what: str = "the world origin"
                    ) -> None:
    """Raise InputError when a position among ``P (N, 3)`` is farther than
    ``MAX_DISTANCE_RATIO`` times ``size`` (the arm's) from ``what``: double precision
    resolves it too coarsely for any IK answer there to be checked (say how coarsely).
    ``name`` names the positions; with several, the message gives the first one's index."""
    dist = np.linalg.norm(P, axis=-1)
    limit = MAX_DISTANCE_RATIO * size
    if not dist.max(initial=0.0) > limit:
        return
    i = int(np.argmax(dist > limit))
    label = name if len(dist) == 1 else f"{name}[{i}]"
    d = float(dist[i])
    grain = d * np.finfo(float).eps
    raise InputError(
        f"{label} is {d:.3g} from {what}, {d / size:.3g} times the arm's size ({size:.6g}): "
        f"double precision places a point that far only to about {grain:.2g}, "
        f"{grain / size:.2g} of the arm's size, so no IK answer there could be checked. rikin "
        f"solves within {MAX_DISTANCE_RATIO:g} times the arm's size ({limit:.3g}) of {what}: "
        "give the target, base and tool in a frame near the arm"
    )


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


def _rotation_errors(r0: list[float], r1: list[float], r2: list[float]) -> tuple[float, float]:
    """(max |R^T R - I|, det R) of one 3x3 matrix given by its rows (the first three
    entries of each: the rows of a 4x4 pose will do), in scalar arithmetic."""
    a, b, c = r0[0], r0[1], r0[2]  # columns (a, d, g), (b, e, h), (c, f, k)
    d, e, f = r1[0], r1[1], r1[2]
    g, h, k = r2[0], r2[1], r2[2]
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
        err1, det1 = _rotation_errors(*arr.tolist())
        if err1 <= ORTHONORMAL_TOL and det1 >= 0:
            return
    biggest = float(np.abs(arr).max(initial=0.0))
    if biggest > 2.0:  # a rotation's entries are at most 1: no R^T R (it could overflow)
        raise InputError(
            f"{name} is not a rotation matrix: it has an entry of {biggest:.3g} "
            "(a rotation's entries are between -1 and 1)"
        )
    gram = np.swapaxes(arr, -1, -2) @ arr
    err = np.abs(gram - np.eye(3)).max(axis=(-1, -2))
    if np.any(err > ORTHONORMAL_TOL):
        worst = float(err.max())
        hint = (
            "; if you copied it rounded, copy at least 4 decimals (3 leave up to ~2e-3)"
            if worst < 1e-2 else ""
        )
        raise InputError(
            f"{name} is not a rotation matrix: its columns are not orthonormal "
            f"(R^T R differs from the identity by {worst:.3g}, allowed {ORTHONORMAL_TOL:g})"
            + hint
        )
    det = np.linalg.det(arr)
    if np.any(det < 0):
        raise InputError(
            f"{name} is a reflection, not a rotation (det = {float(det.min()):.3g}); "
            "a sign in one column is probably wrong"
        )


def as_pose(T: Any, name: str = "T") -> FloatArray:
    """Validate one or many homogeneous transforms ``(..., 4, 4)``.

    Raises InputError for a wrong shape, NaN, a last row other than
    ``[0, 0, 0, 1]``, a rotation block that is not a rotation within
    ``ORTHONORMAL_TOL``, or a translation beyond ``MAX_LENGTH``.
    """
    arr = as_float_array(T, name)
    check_shape_tail(arr, (4, 4), name, "a homogeneous transform")
    bottom = arr[..., 3, :]
    if arr.shape == (4, 4):
        rows = arr.tolist()
        b = rows[3]
        if max(abs(b[0]), abs(b[1]), abs(b[2]), abs(b[3] - 1.0)) <= 1e-9:
            err, det = _rotation_errors(rows[0], rows[1], rows[2])
            if not (err <= ORTHONORMAL_TOL and det >= 0):
                check_rotation_values(arr[:3, :3], f"the rotation part of {name}")
            big = max(abs(rows[0][3]), abs(rows[1][3]), abs(rows[2][3]))
            if big > MAX_LENGTH:
                check_length_range(big, f"the position in {name}")
            return arr
    if np.any(np.abs(bottom - np.array([0.0, 0.0, 0.0, 1.0])) > 1e-9):
        last_col = arr[..., :, 3].reshape(-1, 4)[0]
        hint = (
            " (its last column is [0, 0, 0, 1]: it looks transposed, with the position in the "
            "last row; pass T.T)"
            if np.all(np.abs(last_col - np.array([0.0, 0.0, 0.0, 1.0])) <= 1e-9) else ""
        )
        raise InputError(
            f"{name} must have last row [0, 0, 0, 1], got {bottom.reshape(-1, 4)[0]}" + hint
        )
    check_rotation_values(arr[..., :3, :3], f"the rotation part of {name}")
    big = float(np.abs(arr[..., :3, 3]).max(initial=0.0))
    if big > MAX_LENGTH:
        check_length_range(big, f"the position in {name}")
    return arr


def nearest_rotation(R: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The rotation nearest to each ``(3, 3)`` block of ``R`` (polar decomposition, by SVD).

    Parameters
    ----------
    R : ndarray, shape (..., 3, 3)
        Matrices close to rotations (validated, ``det > 0``).

    Returns
    -------
    R_near : ndarray, shape (..., 3, 3)
        ``U V^T`` from ``R = U S V^T``: the rotation closest to ``R`` in the
        Frobenius norm.
    distance : ndarray, shape (...)
        ``||R - R_near||_F``, unitless.
    """
    U, _, Vt = np.linalg.svd(R)
    R_near = U @ Vt
    flip = np.linalg.det(R_near) < 0  # cannot happen within ORTHONORMAL_TOL; kept exact anyway
    if np.any(flip):
        U = U.copy()
        U[flip, :, 2] *= -1
        R_near = U @ Vt
    return R_near, np.sqrt(((R - R_near) ** 2).sum(axis=(-1, -2)))


def clean_pose(T: FloatArray) -> tuple[FloatArray, float]:
    """A validated pose ``(4, 4)`` with its rotation block made exactly a rotation.

    Returns ``(T, 0.0)`` when the block is a rotation to ``ROTATION_CLEAN_TOL``,
    else a copy with the nearest rotation and the Frobenius distance to it.
    """
    rows = T.tolist()
    err, _ = _rotation_errors(rows[0], rows[1], rows[2])
    if err <= ROTATION_CLEAN_TOL:
        return T, 0.0
    R_near, dist = nearest_rotation(T[:3, :3])
    out = T.copy()
    out[:3, :3] = R_near
    return out, float(dist)


def clean_poses(T: FloatArray, defect: FloatArray) -> FloatArray:
    """:func:`clean_pose` in place on the poses ``T (N, 4, 4)`` whose orthonormality
    ``defect (N,)`` (max abs entry of ``R^T R - I``) is above ``ROTATION_CLEAN_TOL``.

    Returns the distances ``(N,)`` (0 where nothing changed).
    """
    dist = np.zeros(len(T))
    fix = np.flatnonzero(defect > ROTATION_CLEAN_TOL)
    if fix.size:
        R_near, d = nearest_rotation(T[fix, :3, :3])
        T[fix, :3, :3] = R_near
        dist[fix] = d
    return dist


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


# ---------------------------------------------------------------- non-numeric arguments
def as_flag(x: Any, name: str) -> bool:
    """A yes/no argument: ``True`` or ``False`` (numpy's too), or InputError.

    Text such as ``"no"`` is refused rather than read as true, and so are 0 and 1:
    a flag given as a number is usually an argument in the wrong place.
    """
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    why = ""
    if isinstance(x, (int, float, np.integer, np.floating)):
        why = " (a number: rikin does not read 0 and 1 as a flag, write True or False)"
    elif isinstance(x, (str, bytes)):
        why = " (text: rikin does not read words as a flag, write True or False)"
    elif isinstance(x, np.ndarray) and x.dtype.kind == "b" and x.size == 1:
        why = f" (an array of shape {x.shape}: give the bool itself, e.g. bool(x.item()))"
    raise InputError(f"{name} must be True or False, got {_describe(x)}{why}")


def as_text(x: Any, name: str, *, optional: bool = False) -> str | None:
    """A text argument (a title, a name, a unit), or None when ``optional``; else InputError."""
    if x is None and optional:
        return None
    if isinstance(x, str):
        return x
    raise InputError(
        f"{name} must be text (a str){' or None' if optional else ''}, got {_describe(x)}"
    )


def as_choice(x: Any, name: str, choices: tuple[str, ...]) -> str:
    """One of ``choices`` (exact text), or InputError listing them."""
    if isinstance(x, str) and x in choices:
        return x
    listed = ", ".join(repr(c) for c in choices)
    raise InputError(f"{name} must be one of {listed}, got {_describe(x)}")


def as_count(x: Any, name: str, *, minimum: int = 0, maximum: int | None = None,
             what: str = "") -> int:
    """A whole number (Python or numpy int, not a bool or a float) within the bounds;
    ``what`` says what it counts, in messages."""
    of = f" ({what})" if what else ""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise InputError(f"{name} must be a whole number{of}, got {_describe(x)}")
    v = int(x)
    if v < minimum or (maximum is not None and v > maximum):
        bound = f"from {minimum} to {maximum}" if maximum is not None else f">= {minimum}"
        raise InputError(f"{name} must be a whole number {bound}{of}, got {v}")
    return v


def as_positive(x: Any, name: str, *, optional: bool = False) -> float | None:
    """A finite real number > 0 (None when ``optional``), or InputError saying by how much."""
    if x is None and optional:
        return None
    if isinstance(x, (bool, np.bool_)):
        raise InputError(f"{name} must be a positive number, got the boolean {x!r}")
    v = as_real(x, name)
    if not v > 0:
        raise InputError(f"{name} must be a positive number, got {v:g}")
    return v


def as_texts(x: Any, name: str, count: int) -> tuple[str, ...]:
    """Exactly ``count`` texts (a list or tuple of str), or InputError."""
    if isinstance(x, (list, tuple)) and len(x) == count and all(isinstance(e, str) for e in x):
        return tuple(x)
    raise InputError(f"{name} must be {count} texts (a tuple of str), got {_describe(x)}")


def check_instance(x: Any, cls: type, name: str, what: str) -> Any:
    """``x`` if it is a ``cls``, else InputError saying ``what`` was expected."""
    if not isinstance(x, cls):
        raise InputError(f"{name} must be {what}, got {_describe(x)}")
    return x


def as_dh_value(x: Any, name: str, *, angle: bool = False) -> Any:
    """One entry of a DH table: a sympy expression (a symbolic table) as it is, else a finite
    real number (a length within the range rikin handles, or an angle in radians below
    ``MAX_ANGLE``), or InputError naming ``name``."""
    if type(x).__module__.startswith("sympy"):
        import sympy

        if not isinstance(x, sympy.Expr):
            raise InputError(f"{name} must be a number or a sympy expression, got {_describe(x)}")
        return x
    v = as_real(x, name)
    if angle:
        check_radians(np.array(v), name)  # theta1=90: degrees
    else:
        check_length_range(abs(v), name, lower=True)
    return v


# ---------------------------------------------------------------- indexing a result
def check_index(
    key: Any,
    shape: tuple[int, ...],
    what: str,
    axes: tuple[str, ...],
    *,
    attributes: tuple[str, ...] = (),
    arrays: bool = True,
    var: str = "result",
) -> Any:
    """``key`` if it indexes a container of ``shape`` as a list (or numpy array) is indexed,
    else InputError saying what the valid indices are.

    Parameters
    ----------
    key
        What ``container[key]`` received.
    shape : tuple of int
        The container's extent per axis (``(k, n)``: k solutions of n joints).
    what : str
        The container's name in messages (``"IKResult"``).
    axes : tuple of str
        What each axis counts, singular (``("solution", "joint")``).
    attributes : tuple of str
        Its attributes: a text key that names one is told to read it as an attribute.
    var : str
        The name messages give the container (``"branch"``: ``read it as branch.elbow``).
    arrays : bool
        Whether lists and arrays of indices (and boolean masks) are accepted, as numpy
        accepts them; tuples of the Python kind take only whole numbers and slices.

    Accepted: whole numbers (Python or numpy, not bools) in range, negative ones counting
    from the end; slices of whole numbers; with ``arrays``, a tuple of those (one per axis at
    most, ``...`` allowed), lists or arrays of whole numbers in range and boolean masks as
    long as the axis. Refused with InputError: text, real numbers that are not whole
    numbers' types (``1.0``), booleans, None, anything else; an index out of range with
    :class:`~rikin.errors.OutOfRangeError` (an InputError that is also an IndexError, as
    Python's sequences raise, so iteration by index stops as it does on a list).
    """
    parts = key if (arrays and isinstance(key, tuple)) else (key,)
    dots = sum(1 for p in parts if p is Ellipsis)
    if dots > 1:
        raise InputError(f"{what} index {_describe(key)} has more than one '...'")
    if len(parts) - dots > len(shape):
        names = ", ".join(axes)
        raise InputError(
            f"{what} index {_describe(key)} has {len(parts) - dots} entries, but {what} has "
            f"{len(shape)} ax{'es' if len(shape) > 1 else 'is'} ({names})"
        )
    axis = 0
    for p in parts:
        if p is Ellipsis:
            axis += len(shape) - (len(parts) - 1)
            continue
        _check_axis_index(p, shape[axis], what, axes[axis], attributes, arrays, var)
        axis += 1
    return key


def _valid_range(n: int, item: str) -> str:
    if n == 0:
        return f"it has no {item}s"
    plural = "s" if n != 1 else ""
    return f"it has {n} {item}{plural}: valid indices are 0 to {n - 1}, or -{n} to -1"


def _check_axis_index(
    p: Any, n: int, what: str, item: str, attributes: tuple[str, ...], arrays: bool, var: str
) -> None:
    """One entry of an index along an axis of length ``n`` counting ``item``s."""
    i = _whole_index(p, arrays)
    if i is not None:
        _check_in_range(i, n, what, item)
    elif isinstance(p, slice):
        _check_slice(p, what)
    elif arrays and isinstance(p, (list, np.ndarray)):
        _check_index_array(p, n, what, item)
    else:
        _refuse_index(p, n, what, item, attributes, arrays, var)


def _whole_index(p: Any, arrays: bool) -> int | None:
    """``p`` as a whole number if it is one (an int, numpy's, sympy's, a 0-d int array: what a
    list takes), else None; never for a bool, text or a list (nor an array with ``arrays``,
    which is checked as an array of indices)."""
    if isinstance(p, (bool, np.bool_, str, bytes, list)) or (arrays and isinstance(p, np.ndarray)):
        return None
    try:
        return operator.index(p)
    except TypeError:
        return None


def _check_in_range(i: int, n: int, what: str, item: str) -> None:
    """OutOfRangeError, saying by how much, unless ``-n <= i < n``."""
    if not -n <= i < n:
        beyond = i - (n - 1) if i >= 0 else -n - i
        raise OutOfRangeError(
            f"{what} index {i} is out of range by {beyond}: {_valid_range(n, item)}"
        )


def _check_slice(p: slice, what: str) -> None:
    """A slice of whole numbers (or None) with a step other than zero, else InputError."""
    for name in ("start", "stop", "step"):
        v = getattr(p, name)
        if v is not None and (
            isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer))
        ):
            raise InputError(
                f"{what} index {_describe(p)}: the slice's {name} must be a whole number "
                f"or None, got {_describe(v)}"
            )
    if p.step == 0:
        raise InputError(f"{what} index {_describe(p)}: a slice step cannot be zero")


def _check_index_array(p: list[Any] | np.ndarray, n: int, what: str, item: str) -> None:
    """A list or array of whole numbers in range, or a boolean mask of ``n`` entries."""
    if isinstance(p, list) and not p:  # []: none of them, as numpy reads it
        return
    try:
        arr = np.asarray(p)
    except (TypeError, ValueError):
        arr = np.asarray(p, dtype=object)
    if arr.dtype.kind == "b":
        if arr.shape != (n,):
            raise InputError(
                f"{what} index: a boolean mask must have one entry per {item}, shape "
                f"({n},), got shape {arr.shape}"
            )
        return
    if arr.dtype.kind in "iu":
        bad = (arr < -n) | (arr >= n)
        if bad.any():
            first = int(arr[bad].ravel()[0])
            beyond = first - (n - 1) if first >= 0 else -n - first
            raise OutOfRangeError(
                f"{what} index {first} (in {_describe(p)}) is out of range by {beyond}: "
                f"{_valid_range(n, item)}"
            )
        return
    raise InputError(
        f"{what} index {_describe(p)} must hold whole numbers (or be a boolean mask), "
        f"got {arr.dtype} values; {_valid_range(n, item)}"
    )


def _refuse_index(
    p: Any, n: int, what: str, item: str, attributes: tuple[str, ...], arrays: bool, var: str
) -> None:
    """InputError for an index entry that is no whole number, slice or array of indices,
    saying what it is and what the valid indices are."""
    hint = f"; {_valid_range(n, item)}"
    if isinstance(p, (str, bytes)):
        if p in attributes:
            raise InputError(
                f"{what} index {p!r} is text: {p} is an attribute, read it as "
                f"{var}.{p} ({what} is indexed by {item} number{hint})"
            )
        listed = f" (its attributes: {', '.join(attributes)})" if attributes else ""
        raise InputError(
            f"{what} index {_describe(p)} is text: {what} is indexed by {item} "
            f"number{hint}{listed}"
        )
    if isinstance(p, (bool, np.bool_)):
        raise InputError(
            f"{what} index {p!r} is a boolean, not a {item} number{hint}"
            + (f" (a mask is an array of {n} booleans)" if arrays else "")
        )
    if p is None:
        raise InputError(f"{what} index is None, not a {item} number{hint}")
    if isinstance(p, (float, complex, np.floating, np.complexfloating)):
        whole = isinstance(p, (float, np.floating)) and float(p).is_integer()
        raise InputError(
            f"{what} index {_describe(p)} is not a whole number's type: a {item} number is "
            f"an int{hint}" + (f"; write int({float(p.real)!r})" if whole else "")
        )
    raise InputError(f"{what} index {_describe(p)} is not a {item} number{hint}")
