"""Numerical IK: Levenberg-Marquardt / damped least squares on the pose error.

The closed forms of :mod:`rikin.ik` give every solution at once; a numerical
method gives one solution, the one its iteration falls into from the start
``q0``. The book uses it to compare the two ("how many random starts does it
take to find all 8 solutions of the Epson C4?") and for arms without a closed
form.

The error of joint values ``q`` against a target pose ``T`` (world frame) is a
6-vector, position first:

* ``(p_T - p(q)) / arm.scale``: the position error, made unitless so that an
  arm in mm and an arm in lesson units converge alike;
* ``log(R_T R(q)^T)``: the rotation vector (axis times angle, rad) that turns
  the current orientation into the target's, in the world frame.

Both match the rows of the geometric Jacobian ``arm.jacobian(q)`` (linear
velocity, then angular velocity, world frame at the TCP), so a step ``dq``
changes the error by about ``-W J dq`` with ``W = diag(1/scale, 1)``. (The
iteration computes the pose and that Jacobian from one FK pass per step.)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import FloatArray, as_flag, as_float_array, as_pose, as_real, clean_pose
from ..dh import SerialArm
from ..errors import InputError
from .api import _limits_filter, _solver, _unreachable
from .result import not_indexed

__all__ = ["NumericalIKResult", "ik_numerical", "ik_numerical_multistart", "pose_error"]

_METHODS = ("lm", "dls")
#: Damping of the plain damped-least-squares method (``method="dls"``), in the
#: units of the weighted Jacobian (unitless).
DLS_DAMPING = 1e-3
#: Levenberg-Marquardt gives up when its damping grows past this factor times
#: the largest diagonal entry of ``J^T J``: no step reduces the error.
LM_MAX_DAMPING = 1e12
#: ... or when the gradient ``J^T e`` of the squared error is flatter than this
#: (a minimum that is not a solution: the target is out of reach) ...
LM_FLAT_GRADIENT = 1e-14
#: ... or when its step is shorter than this times ``1 + |q|``.
LM_TINY_STEP = 1e-13
#: ... or when ``LM_WINDOW`` iterations lowered the squared error by less
#: than a relative ``LM_CREEP`` (creeping along a flat valley, as near a wrist
#: singularity with the target out of reach). Also stops ``method="dls"``.
LM_WINDOW = 10
LM_CREEP = 1e-6


@dataclass(frozen=True)
class NumericalIKResult:
    """What :func:`ik_numerical` found.

    Attributes
    ----------
    q : ndarray, shape (n,)
        The last iterate: revolute joints in radians wrapped to (-pi, pi] (or
        the in-limit equivalent with ``within_limits=True``), prismatic joints
        in the arm's length units. Always finite, also when ``success`` is False.
    success : bool
        The masked error is below ``tol``: ``|p_T - p| / arm.scale < tol`` and
        rotation error ``< tol`` rad (for the components the mask keeps).
    reason : str
        "converged", or why not: "max_iter reached (error ...)", "stalled at a
        singularity / local minimum (error ...)", "converged outside the joint limits".
    iterations : int
        Jacobian evaluations (one per iteration).
    error_position : float
        ``|p_T - p(q)|``, in the arm's length units.
    error_rotation : float
        Angle of ``R_T R(q)^T``, rad.
    target : ndarray, shape (4, 4)
        The pose the iteration solved for, ``T_T`` above (world frame): the given ``T``
        with its rotation block replaced by the nearest rotation when it was not one to
        rounding, and for a 5-DOF arm asked for a whole pose, moved to the nearest
        reachable pose (see ``reach_distance``).
    rotation_distance : float
        As :attr:`rikin.IKResult.rotation_distance`: how far the rotation block of ``T``
        was from a rotation (Frobenius norm; 0 when it was one to rounding).
    reach_distance : float
        As :attr:`rikin.IKResult.reach_distance`, for a 5-DOF lesson arm (PPRRR, RPRRR)
        or a 6R with a closed form asked for a whole pose (``mask`` None or all ones):
        how far, in the arm's length units, the wrist centre of ``T`` was from where the
        positioning joints can put it, when the iteration solved the nearest reachable
        pose instead (the same pose ``arm.ik`` solves). 0 when ``T`` was solved as given:
        every other arm and mask, and a pose reachable to within ``tol`` (``arm.ik`` also
        solves as given a pose up to its ``REACH_TOL`` slack off, and reports 0 there).
    """

    q: FloatArray
    success: bool
    reason: str
    iterations: int
    error_position: float
    error_rotation: float
    target: FloatArray | None = None
    rotation_distance: float = 0.0
    reach_distance: float = 0.0

    def __getitem__(self, key: Any) -> Any:
        """Not indexed: one solution, ``result.q``; :class:`~rikin.errors.NotIndexedError`
        saying so."""
        raise not_indexed(self, _ONE_SOLUTION, key)

    def __iter__(self) -> Any:
        """Not iterable: :class:`~rikin.errors.NotIndexedError`, as for an index."""
        raise not_indexed(self, _ONE_SOLUTION, iterated=True)


_ONE_SOLUTION = "a numerical result holds one solution, result.q (shape (n,)), and is not indexed"


def _rotation_vector(R: FloatArray) -> FloatArray:
    """The rotation vector (axis * angle, rad, angle in [0, pi]) of a rotation matrix (3, 3)."""
    v = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    s = float(np.linalg.norm(v))  # sin(angle)
    c = float(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0))
    angle = float(np.arctan2(s, c))
    if s > 1e-6 or c > 0.0:
        # away from pi; for tiny angles angle / sin(angle) -> 1 + angle^2 / 6
        factor = angle / s if s > 1e-12 else 1.0 + angle * angle / 6.0
        return factor * v
    # angle close to pi: the symmetric part of R is cos(angle) I + (1 - cos(angle)) a a^T,
    # so a a^T is known exactly; its dominant column gives the axis
    B = (0.5 * (R + R.T) - c * np.eye(3)) / (1.0 - c)
    k = int(np.argmax(np.diag(B)))
    axis = B[:, k] / np.sqrt(max(B[k, k], 1e-300))
    axis /= np.linalg.norm(axis)
    if float(axis @ v) < 0.0:
        axis = -axis
    return angle * axis


def _pose_and_jacobian(arm: SerialArm, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``arm.fk(q)`` (4, 4) and ``arm.jacobian(q)`` (6, n) from one FK pass over the frames.

    Same formulas as :meth:`rikin.SerialArm.jacobian` (world frame, at the TCP),
    without validating ``q`` again and without recomputing the frames.
    """
    F = arm._fk(q, frames=True)  # (n + 2, 4, 4)
    idx = np.arange(arm.n) if arm.convention == "standard" else np.arange(1, arm.n + 1)
    origins, axes = F[idx, :3, 3], F[idx, :3, 2] * arm.directions[:, None]  # reversed: -z
    p_e = F[-1, :3, 3]
    rev = arm.revolute[:, None]
    lin = np.where(rev, np.cross(axes, p_e - origins), axes)
    ang = np.where(rev, axes, 0.0)
    return F[-1], np.concatenate([lin, ang], axis=-1).T


def _error_from_pose(arm: SerialArm, F: FloatArray, T: FloatArray) -> FloatArray:
    dp = (T[:3, 3] - F[:3, 3]) / arm.scale
    return np.concatenate([dp, _rotation_vector(T[:3, :3] @ F[:3, :3].T)])


def pose_error(arm: SerialArm, q: FloatArray, T: FloatArray) -> FloatArray:
    """The 6-vector error of ``fk(q)`` against the world pose ``T`` (see the module docstring).

    Parameters
    ----------
    arm : SerialArm
    q : ndarray, shape (n,)
        Joint values (rad / length units).
    T : ndarray, shape (4, 4)
        Target TCP pose in the world frame.

    Returns
    -------
    e : ndarray, shape (6,)
        ``[(p_T - p) / arm.scale, rotation vector of R_T R^T]`` (unitless, rad).
    """
    _check_arm(arm)
    qv = arm.check_q(q)
    if qv.ndim != 1:
        raise InputError(f"q must have shape ({arm.n},), got shape {qv.shape}")
    return _error_from_pose(arm, arm._fk(qv), _one_target(T))


def _check_arm(arm: Any) -> None:
    if not isinstance(arm, SerialArm):
        raise InputError(f"arm must be a rikin.SerialArm, got {type(arm).__name__}")


def _one_target(T: Any) -> FloatArray:
    """One validated 4x4 target ``T``, its rotation block made exactly a rotation."""
    return _clean_target(T)[0]


def _clean_target(T: Any) -> tuple[FloatArray, float]:
    """:func:`_one_target` and how far the rotation block was from a rotation."""
    T_t = as_pose(T, "T")
    if T_t.shape != (4, 4):
        raise InputError(
            f"T must be one 4x4 pose, got shape {T_t.shape}; for many poses "
            "call ik_numerical once per pose"
        )
    return clean_pose(T_t)


def _nearest_reachable(arm: SerialArm) -> Any:
    """The closed-form solver's ``nearest_reachable`` for a whole pose: of a 4- or 5-DOF arm,
    which reaches only a 4- or 5-dimensional set of poses (the four-axis SCARA; the PPRRR and
    RPRRR lesson arms), or of a 6R with a closed form, whose rounded poses near its reach can
    miss it; else None."""
    if arm.n not in (4, 5, 6):
        return None
    try:
        solver = _solver(arm)  # the lesson arm's, else the general 6R one
    except InputError:  # no closed form: nothing to measure the reach with
        return None
    if solver.target_kind != "pose":
        return None
    return getattr(solver, "nearest_reachable", None)


def _reachable_target(
    arm: SerialArm, T_t: FloatArray, weights: FloatArray, tol: float
) -> tuple[FloatArray, float]:
    """The pose to iterate on for the clean world pose ``T_t`` and how far ``T_t`` was from
    it (``reach_distance``), as ``arm.ik`` decides them.

    A 5-DOF lesson arm asked for a whole pose (every component of ``weights``) reaches it
    only if the wrist centre lies where joints 1-2 put it: a pose rounded to 4 decimals
    misses by a few 1e-5, and no iteration converges to it. Within ``ROUNDED_POSE_TOL`` it is
    replaced by the nearest reachable pose (the one ``arm.ik`` solves); further off it is an
    UnreachableError with ``arm.ik``'s message and excess. Within ``tol`` (what the
    iteration counts as converged, relative to the arm's size, with a margin of 10) it is
    solved as given. Every other arm and mask: ``T_t`` as given (a 6R's pose rounded
    beyond its reach is moved only if the iteration does not converge to it:
    :func:`_rounded_beyond_reach`).
    """
    nearest = _nearest_reachable(arm)
    if nearest is None or not weights.all() or arm.n == 6:  # a 6R: after the iteration
        return T_t, 0.0
    T_near, dist, close = nearest(arm, T_t[None])
    d = float(dist[0])
    if not close[0]:
        raise _unreachable(arm, arm.solver, arm._world_to_base(T_t))
    if d <= 0.1 * tol * arm.scale:
        return T_t, 0.0
    return T_near[0], d


def _rounded_beyond_reach(
    arm: SerialArm, T_t: FloatArray, weights: FloatArray, tol: float
) -> tuple[FloatArray | None, float]:
    """For a 6R with a closed form asked for a whole pose it did not converge to: the
    nearest reachable pose and the distance, when ``T_t`` misses the reach by rounding
    (``ROUNDED_POSE_TOL``) and by more than ``tol``; else ``(None, 0.0)``."""
    nearest = _nearest_reachable(arm)
    if arm.n != 6 or nearest is None or not weights.all():
        return None, 0.0
    T_near, dist, close = nearest(arm, T_t[None])
    d = float(dist[0])
    if not close[0] or d <= 0.1 * tol * arm.scale:
        return None, 0.0
    return T_near[0], d


def _check_mask(arm: SerialArm, mask: Any) -> FloatArray:
    if mask is None:
        if arm.n < 6 and _nearest_reachable(arm) is None:
            raise InputError(
                f"{arm.name!r} has {arm.n} joints, so it cannot match a full 6-DOF pose: pass "
                "mask, which error components to use, e.g. mask=(1, 1, 1, 0, 0, 0) for the "
                "position only or (1, 1, 0, 0, 0, 1) for x, y and the angle about z"
            )
        return np.ones(6)
    m = as_float_array(mask, "mask")
    if m.shape != (6,) or not np.all((m == 0) | (m == 1)) or not m.any():
        raise InputError(
            f"mask must be 6 values, each 0 or 1 (x, y, z, rx, ry, rz), not all 0; got {mask!r}"
        )
    return m


def _check_settings(method: str, tol: float, max_iter: int) -> None:
    if not isinstance(method, str) or method not in _METHODS:
        raise InputError(f"method must be one of {_METHODS}, got {method!r}")
    if (
        isinstance(tol, bool)
        or not isinstance(tol, (int, float, np.integer, np.floating))
        or not np.isfinite(tol)
        or tol <= 0
    ):
        raise InputError(f"tol must be a positive number, got {tol!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise InputError(f"max_iter must be a positive integer, got {max_iter!r}")


def _limits(arm: SerialArm) -> FloatArray:
    """Joint limits used to clamp iterates, (n, 2); revolute ones at most +-2*pi."""
    lim = arm.qlim.copy()
    rev = arm.revolute
    lim[rev, 0] = np.maximum(lim[rev, 0], -2 * np.pi)
    lim[rev, 1] = np.minimum(lim[rev, 1], 2 * np.pi)
    return lim


def _random_start(arm: SerialArm, rng: np.random.Generator, within_limits: bool) -> FloatArray:
    """A random joint vector: revolute in [-pi, pi) (or inside finite limits), prismatic
    inside its limits (or 0 when it has none)."""
    lo, hi = arm.qlim[:, 0].copy(), arm.qlim[:, 1].copy()
    rev = arm.revolute
    if not within_limits:
        lo[rev], hi[rev] = -np.pi, np.pi
    lo = np.where(np.isfinite(lo), lo, np.where(rev, -np.pi, 0.0))
    hi = np.where(np.isfinite(hi), hi, np.where(rev, np.pi, 0.0))
    return rng.uniform(lo, hi)


def _as_rng(rng: Any) -> np.random.Generator:
    if rng is None:
        return np.random.default_rng(0)
    if isinstance(rng, np.random.Generator):
        return rng
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, (bool, np.bool_)) and rng >= 0:
        return np.random.default_rng(int(rng))
    raise InputError(
        f"rng must be None, a non-negative integer seed or a numpy Generator, got {rng!r}"
    )


def _wrap_revolute(arm: SerialArm, q: FloatArray) -> FloatArray:
    w = np.remainder(q + np.pi, 2 * np.pi) - np.pi
    w = np.where(w <= -np.pi, w + 2 * np.pi, w)
    return np.where(arm.revolute, w, q)


def _step(J: FloatArray, e: FloatArray, damping: float) -> FloatArray:
    """The damped Gauss-Newton step ``(J^T J + damping I)^-1 J^T e`` (both methods)."""
    A = J.T @ J
    A[np.diag_indices_from(A)] += damping
    return np.linalg.solve(A, J.T @ e)


def ik_numerical(
    arm: SerialArm,
    T: Any,
    q0: Any = None,
    *,
    method: str = "lm",
    tol: float = 1e-10,
    max_iter: int = 200,
    rng: Any = None,
    within_limits: bool = False,
    mask: Any = None,
) -> NumericalIKResult:
    """One IK solution by Levenberg-Marquardt (or damped least squares) from a start ``q0``.

    Parameters
    ----------
    arm : SerialArm
        Any arm (a closed form is not needed).
    T : array_like, shape (4, 4)
        Target TCP pose in the world frame (lengths in ``arm.units``).
    q0 : array_like, shape (n,), optional
        Start (rad / length units). Default: a random start drawn from ``rng``.
    method : {"lm", "dls"}
        "lm": Levenberg-Marquardt with adaptive damping (a step is kept only if it lowers
        the error; the damping shrinks after good steps and grows after bad ones).
        "dls": damped least squares with the fixed damping ``DLS_DAMPING``.
    tol : float
        Convergence threshold on the masked error (position / ``arm.scale``; rotation, rad).
    max_iter : int
        Maximum number of iterations (Jacobian evaluations).
    rng : None, int or numpy.random.Generator
        For the random start; None means seed 0 (reproducible).
    within_limits : bool
        Keep the iterates inside the joint limits (clamping each step), start inside them.
    mask : array_like of 6 values 0/1, optional
        Which error components count (x, y, z, rx, ry, rz). Required for arms with fewer
        than 6 joints, e.g. ``(1, 1, 1, 0, 0, 0)``: position only, except the 5-DOF lesson
        arms (PPRRR, RPRRR), which take a whole pose as ``arm.ik`` does: a pose they miss by
        rounding (within ``ROUNDED_POSE_TOL``) is solved for the nearest reachable pose
        (``reach_distance``), as is a 6R's with a closed form rounded beyond its reach.

    Returns
    -------
    NumericalIKResult
        ``success`` False (never an exception, never NaN) when the iteration stalls or runs
        out of iterations, e.g. for an unreachable target.

    Raises
    ------
    InputError
        Malformed ``T``, ``q0`` (shape, NaN, degrees), ``mask`` or settings.
    UnreachableError
        A whole pose that a 5-DOF lesson arm misses by more than ``ROUNDED_POSE_TOL``: the
        error, message and ``excess`` (the wrist centre's distance from the poses the arm
        reaches) that ``arm.ik`` raises.

    Examples
    --------
    >>> import rikin
    >>> arm = rikin.robots.aula10_6r()
    >>> T = arm.fk(rikin.rad([99.6, 9, 26.4, 68.4, 30, 151]))
    >>> sol = ik_numerical(arm, T, q0=rikin.rad([90, 0, 20, 60, 20, 140]))
    >>> sol.success, bool(np.allclose(arm.fk(sol.q), T, atol=1e-9))
    (True, True)
    """
    _check_arm(arm)
    _check_settings(method, tol, max_iter)
    within_limits = as_flag(within_limits, "within_limits")
    T_t, rot_dist = _clean_target(T)
    weights = _check_mask(arm, mask)
    q = _start(arm, q0, rng, within_limits)
    T_t, reach = _reachable_target(arm, T_t, weights, tol)
    run = _Iteration(arm, method, tol, max_iter, weights, within_limits)
    q, reason, it = run.towards(run.settle(q), T_t)
    if reason != "converged" and reach == 0.0:  # a 6R's pose rounded beyond its reach?
        q, reason, it, T_t, reach = _retry_on_nearest(run, q, reason, it, T_t)
    return _result(arm, q, reason, it, T_t, rot_dist, reach, within_limits)


def _retry_on_nearest(
    run: _Iteration, q: FloatArray, reason: str, it: int, T_t: FloatArray
) -> tuple[FloatArray, str, int, FloatArray, float]:
    """``(q, reason, iterations, target, reach_distance)``: when ``T_t`` is a 6R's pose
    rounded beyond its reach, which no iteration reaches, the iteration goes on from ``q``
    towards the nearest reachable pose; else the first run's end, unchanged."""
    T_near, d = _rounded_beyond_reach(run.arm, T_t, run.weights, run.tol)
    if T_near is None:
        return q, reason, it, T_t, 0.0
    q, reason, more = run.towards(q, T_near)
    return q, reason, it + more, T_near, d


def _start(arm: SerialArm, q0: Any, rng: Any, within_limits: bool) -> FloatArray:
    """The first iterate: ``q0`` checked, or a random start drawn from ``rng``."""
    if q0 is None:
        return _random_start(arm, _as_rng(rng), within_limits)
    q = arm.check_q(q0, "q0").copy()
    if q.ndim != 1:
        raise InputError(f"q0 must have shape ({arm.n},), got shape {q.shape}")
    return q


class _Damping:
    """The Levenberg-Marquardt damping and its growth factor, carried between steps."""

    def __init__(self) -> None:
        self.damping, self.nu = -1.0, 2.0


class _Iteration:
    """The damped Gauss-Newton iteration of one arm (``method`` "lm" or "dls"), with the
    error mask ``weights`` (6,), the convergence ``tol`` and ``max_iter``."""

    def __init__(
        self,
        arm: SerialArm,
        method: str,
        tol: float,
        max_iter: int,
        weights: FloatArray,
        within_limits: bool,
    ) -> None:
        self.arm, self.method, self.tol, self.max_iter = arm, method, tol, max_iter
        self.weights, self.within_limits = weights, within_limits
        self.lim = _limits(arm)
        self.scale_J = np.concatenate([np.full(3, 1.0 / arm.scale), np.ones(3)]) * weights

    def settle(self, q: FloatArray) -> FloatArray:
        """Keep the iterate where arm.fk accepts it: clamped or wrapped."""
        if self.within_limits:
            return np.clip(q, self.lim[:, 0], self.lim[:, 1])
        return _wrap_revolute(self.arm, q)

    def evaluate(self, q: FloatArray, T_t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Masked error (6,) and scaled, masked Jacobian (6, n) at ``q``."""
        F, J_geo = _pose_and_jacobian(self.arm, q)
        return _error_from_pose(self.arm, F, T_t) * self.weights, self.scale_J[:, None] * J_geo

    def towards(self, q: FloatArray, T_t: FloatArray) -> tuple[FloatArray, str, int]:
        """The iteration from ``q`` towards ``T_t``: where it ends, why, in how many steps."""
        e, J = self.evaluate(q, T_t)
        lm = _Damping()
        it = 0
        costs: list[float] = []
        while True:
            err = float(np.abs(e).max())
            if err < self.tol:
                return q, "converged", it
            if it >= self.max_iter:
                return q, f"max_iter reached (error {err:.3g})", it
            stalled = f"stalled at a singularity / local minimum (error {err:.3g})"
            costs.append(min(float(e @ e), costs[-1] if costs else np.inf))  # best so far
            if len(costs) > LM_WINDOW and costs[-LM_WINDOW - 1] - costs[-1] <= LM_CREEP * costs[-1]:
                return q, stalled, it
            it += 1
            if self.method == "dls":
                q = self.settle(q + _step(J, e, DLS_DAMPING))
                e, J = self.evaluate(q, T_t)
                continue
            moved = self._lm_step(q, e, J, T_t, lm)
            if moved is None:
                return q, stalled, it
            q, e, J = moved

    def _lm_step(
        self, q: FloatArray, e: FloatArray, J: FloatArray, T_t: FloatArray, lm: _Damping
    ) -> tuple[FloatArray, FloatArray, FloatArray] | None:
        """One Levenberg-Marquardt trial: the new ``(q, e, J)`` when the step lowers the
        error, the old ones when it does not (the damping grows), None when stalled."""
        diag_max = float(np.max(np.diag(J.T @ J), initial=0.0)) or 1.0
        if lm.damping < 0:
            lm.damping = 1e-3 * diag_max
        g = J.T @ e
        if float(np.abs(g).max()) < LM_FLAT_GRADIENT:
            return None
        dq = _step(J, e, lm.damping)
        if float(np.linalg.norm(dq)) < LM_TINY_STEP * (1.0 + float(np.linalg.norm(q))):
            return None
        q_new = self.settle(q + dq)
        e_new, J_new = self.evaluate(q_new, T_t)
        gain = float(e @ e - e_new @ e_new)
        predicted = float(dq @ (lm.damping * dq + g))
        if gain > 0 and predicted > 0:
            rho = gain / predicted
            lm.damping *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            lm.nu = 2.0
            return q_new, e_new, J_new
        lm.damping *= lm.nu
        lm.nu *= 2.0
        if lm.damping > LM_MAX_DAMPING * diag_max:
            return None
        return q, e, J


def _result(
    arm: SerialArm,
    q: FloatArray,
    reason: str,
    it: int,
    T_t: FloatArray,
    rot_dist: float,
    reach: float,
    within_limits: bool,
) -> NumericalIKResult:
    """Where the iteration ended as a result: wrapped (moved inside the joint limits when
    asked) and measured against the target ``T_t`` it iterated on."""
    q_out = _wrap_revolute(arm, q)
    if within_limits:
        moved, fits = _limits_filter(q_out[None], arm, None)
        q_out = moved[0] if fits[0] else q
        if reason == "converged" and not fits[0]:  # pragma: no cover - q is clamped inside
            reason = "converged outside the joint limits"
    F = arm.fk(q_out)
    return NumericalIKResult(
        q=q_out,
        success=reason == "converged",
        reason=reason,
        iterations=it,
        error_position=float(np.linalg.norm(T_t[:3, 3] - F[:3, 3])),
        error_rotation=float(np.linalg.norm(_rotation_vector(T_t[:3, :3] @ F[:3, :3].T))),
        target=T_t,
        rotation_distance=rot_dist,
        reach_distance=reach,
    )


def ik_numerical_multistart(
    arm: SerialArm,
    T: Any,
    n_starts: int,
    rng: Any = None,
    *,
    distinct_tol: float = 1e-6,
    **options: Any,
) -> list[FloatArray]:
    """Distinct solutions found by :func:`ik_numerical` from ``n_starts`` random starts.

    Parameters
    ----------
    arm, T
        As for :func:`ik_numerical`.
    n_starts : int
        Number of random starts (each one a full :func:`ik_numerical` run).
    rng : None, int or numpy.random.Generator
        Source of the starts; None means seed 0.
    distinct_tol : float
        Two converged solutions closer than this (max abs difference of the
        joint values, revolute ones modulo 2*pi) are one solution, rad.
    **options
        Passed to :func:`ik_numerical` (``method``, ``tol``, ``max_iter``,
        ``within_limits``, ``mask``).

    Returns
    -------
    list of ndarray, each shape (n,)
        The distinct converged solutions, in the order they were first found.
        For an arm with a closed form, compare with ``arm.ik(T)``: the
        numerical method finds a solution only if some start falls into its
        basin of attraction.
    """
    _check_arm(arm)
    if isinstance(n_starts, bool) or not isinstance(n_starts, (int, np.integer)) or n_starts < 1:
        raise InputError(f"n_starts must be a positive integer, got {n_starts!r}")
    if "q0" in options:
        raise InputError("ik_numerical_multistart draws its own starts; do not pass q0")
    if isinstance(distinct_tol, (bool, np.bool_)) or not as_real(distinct_tol, "distinct_tol") > 0:
        raise InputError(f"distinct_tol must be a positive number, got {distinct_tol!r}")
    gen = _as_rng(rng)
    within = as_flag(options.get("within_limits", False), "within_limits")
    rev = arm.revolute
    found: list[FloatArray] = []
    for _ in range(int(n_starts)):
        sol = ik_numerical(arm, T, _random_start(arm, gen, within), **options)
        if not sol.success:
            continue
        diffs = [sol.q - f for f in found]
        if not any(
            np.abs(np.where(rev, _wrap_revolute(arm, d), d)).max() <= distinct_tol for d in diffs
        ):
            found.append(sol.q)
    return found
