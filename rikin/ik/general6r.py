"""IK of any 6R arm from its table: elimination to an eigenvalue problem (Raghavan and Roth).

With the arm written as ``W = Rz(th1) M1 Rz(th2) M2 Rz(th3) M3 Rz(th4) M4 Rz(th5) M5 Rz(th6)``
(``W = M0^-1 T_0_6 M6^-1``, see :mod:`rikin.ik.pieper`), the line of axis 6 seen from frame 3
is reached two ways:

    L(th3, th4, th5) = Rz(th3) M3 Rz(th4) M4 Rz(th5) M5        (point p, direction l)
    R(th1, th2)      = M2^-1 Rz(-th2) M1^-1 Rz(-th1) W

and ``Rz(th6)`` drops out. Raghavan and Roth (1993) take the 14 quantities ``l, p, p.p,
p.l, p x l, (p.p) l - 2 (p.l) p``: on each side they stay sums of products of one cosine or
sine (or 1) per joint, so equating them gives ``P(th3) m45 = Q m12``, with ``m45`` the 9
products of ``(1, cos, sin)`` of joints 4 and 5 and ``m12`` those of joints 1 and 2. Here the
coefficients are not derived by hand: ``P`` (the arm's alone) and ``Q`` (per pose) are read
off by evaluating both sides on a 3 x 3 (x 3) grid of angles, which fixes such sums exactly.

Eliminating the 8 non-constant products of joints 1, 2 (the left null space of ``Q``) leaves 6
equations in joints 3-5; with half-angle tangents ``x_i = tan(th_i / 2)`` and the 6 equations
again times ``x4``, 12 equations linear in the 12 monomials ``x4^i x5^j`` (``i <= 3``, ``j <=
2``) with a matrix quadratic in ``x3``: ``(S0 + x3 S1 + x3^2 S2) v = 0``. Its 24 eigenvalues
(a companion matrix) hold every ``th3``: up to 16 real ones, and 8 at ``+-i`` (Manocha and
Canny 1994). Each eigenvector gives ``th4, th5``; the 14 equations give ``th1, th2``; the
pose gives ``th6``. Only the real roots go on from the eigenvalues; each is polished by
Newton steps on the whole pose (the careful Gauss-Newton of :class:`ChainPolish` where
they stall) and kept only if it reaches the target. To keep every joint's half-angle
tangent finite at the joint values people type (0, pi), the solver works on joints turned
by fixed odd angles.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import FloatArray
from ..dh import check_arm
from ..errors import InputError
from ..tolerances import SAME_SOLUTION_TOL
from .base import RawSolutions, Singularity, TargetKind
from .general6r_kernel import General6RKernel
from .kernels import cross3, wrap_in_place
from .parallel3 import reversed_model
from .pieper import (
    ACCEPT_TOL,
    POLISHED,
    POLISHED_ALONE,
    ChainModel,
    ChainPolish,
    _rz4,
    _unit_model,
    chain_model,
    six_revolute_reason,
)
from .result import Branch

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

__all__ = ["recognise", "General6RSolver"]

#: Solutions in all (the most a 6R arm has).
SLOTS = 16

#: The fixed turns (rad) of the joints' zeros the elimination works with.
SHIFT = np.array([0.4142, 0.9131, 1.3719, 0.6180, 1.1547, 0.2718])

#: An eigenvalue is taken as real (and polished) when its imaginary part is below this,
#: relative; two roots that meet at a fold split into a pair ~sqrt(eps) off the line.
IMAG_TOL = 1e-4

#: A formulation is used only where the better end of its matrix polynomial has a condition
#: number below this on a few poses: 1e2..1e5 on random tables and on the formulations that
#: solve a Kinova Jaco or a UR5e, 5e16 and more on those that degenerate (both ends singular).
PENCIL_COND = 1e12

#: The 3 angles of the grid on which a sum ``a + b cos + c sin`` is read.
_GRID = 2 * np.pi * np.arange(3) / 3
_BASIS_INV = np.linalg.inv(np.stack([np.ones(3), np.cos(_GRID), np.sin(_GRID)], axis=1))
#: the same for two joints' grid ``(i, j)`` at once: coefficients ``(a, b)``
_BASIS_INV2 = np.kron(_BASIS_INV, _BASIS_INV)
#: ``(1, cos, sin)`` times ``1 + x^2`` as coefficients of ``(1, x, x^2)``.
_HALF = np.array([[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]])

#: ``_HALF`` for joints 3, 4 and 5 at once: ``(k, i, j), (a, b, c)`` entries
#: ``_HALF[a, k] _HALF[b, i] _HALF[c, j]``
_HALF3 = np.einsum("ak,bi,cj->kijabc", _HALF, _HALF, _HALF).reshape(27, 27)

#: Newton steps before a candidate still above ``POLISHED`` takes the careful polish (a
#: root of the eigenvalue problem reaches the pose to ~1e-13: one step, or two).
NEWTON_STEPS = 4

#: A solution is flagged singular where its Jacobian's singular values are this far apart.
SINGULAR_RCOND = 1e-7

SINGULAR = Singularity(
    "the arm is at a singular configuration (its Jacobian loses rank): solutions meet", ()
)


def _fourteen(T: FloatArray) -> FloatArray:
    """Raghavan and Roth's 14 quantities of the axis-6 line of frames ``T (..., 4, 4)``:
    ``l, p, p.p, p.l, p x l, (p.p) l - 2 (p.l) p``, shape ``(..., 14)``."""
    ax, p = T[..., :3, 2], T[..., :3, 3]
    pp = (p * p).sum(-1, keepdims=True)
    pl = (p * ax).sum(-1, keepdims=True)
    return np.concatenate([ax, p, pp, pl, cross3(p, ax), pp * ax - 2 * pl * p], axis=-1)


def _fit(F: FloatArray, axes: int) -> FloatArray:
    """Coefficients over ``(1, cos, sin)`` per joint of values ``F`` sampled on the grid in
    the last ``axes`` axes before the quantities' axis: ``(..., 3, ..., 3, 14)``."""
    for k in range(axes):  # a (3, 3) @ (3, 14) product per pose and grid point: the same
        # BLAS call for each, whatever the batch (a tensordot's one product would round by it)
        F = np.moveaxis(_BASIS_INV @ np.moveaxis(F, -2 - k, -2), -2, -2 - k)
    return F


def _shifted(model: ChainModel) -> ChainModel:
    """``model`` with joint ``i`` turned by ``SHIFT[i]``: ``Rz(th) = Rz(SHIFT) Rz(th')``."""
    M = model.M.copy()
    for i in range(6):
        M[i] = M[i] @ _rz4(np.array(SHIFT[i]))
    return ChainModel(M, model.offsets, model.scale)


class _Elimination:
    """The elimination for one chain model (joints already shifted), with the loop
    ``Rz(th1) M1 ... Rz(th6) W^-1 = I`` started at joint ``start + 1``: the joints that
    play the parts of 1-6 above are ``start + 1, ..., 6, 1, ..., start`` (so the target
    ``W^-1`` may stand among the constant factors). Some tables (two axes meeting and two
    parallel, as on a Kinova Jaco) make the 12 x 12 matrix singular for every ``x3`` when
    started at joint 1, and not when started elsewhere."""

    def __init__(self, model: ChainModel, start: int) -> None:
        self.M = model.M
        self.start = start
        #: loop position i (1-6) -> the chain's joint index (0-5)
        self.joint = np.array([(start + i) % 6 for i in range(6)])
        self.P_const = None
        if start in (0, 4, 5):  # the target is not among the left side's factors
            self.P_const = self._left(
                [self.M[0]] + [self.M[1 + (start + i - 1) % 6] for i in range(1, 6)]
            )
        #: ``W'`` where it is a constant factor (``M_start^-1``), else None (``W' = W``)
        Wp = np.linalg.inv(self.M[start])
        self.Wp_const = Wp if start else None
        t1, t2 = np.meshgrid(_GRID, _GRID, indexing="ij")
        #: the right sides on the grid ``(3, 3, 4, 4)`` are ``pre @ X @ post``, with ``X``
        #: ``W'`` (start 0-3: the target is neither factor), or the inverse of the factor
        #: ``W^-1`` (the second at start 4, the first at start 5); None: the identity
        self.pre: FloatArray | None = None
        self.post: FloatArray | None = None
        if start <= 3:
            inv1, inv2 = np.linalg.inv(self.M[start + 1]), np.linalg.inv(self.M[start + 2])
            self.pre = inv2 @ _rz4(-t2) @ inv1 @ _rz4(-t1)
        elif start == 4:
            self.post = _rz4(-t2) @ np.linalg.inv(self.M[5]) @ _rz4(-t1) @ Wp
        else:
            self.pre = (np.linalg.inv(self.M[1]) @ _rz4(-t2[:1]))  # (1, 3, 4, 4): over t2
            self.post = _rz4(-t1[:, :1]) @ Wp  # (3, 1, 4, 4): over t1
        #: ``_HALF3 @ P`` where the left sides are the arm's alone ``(27, 14)``, else None
        self.HP = None if self.P_const is None else _HALF3 @ self.P_const.reshape(27, 14)

    def factors(self, W: FloatArray) -> tuple[list[FloatArray], FloatArray]:
        """The loop's factors ``M'1..M'5`` (index 1-5; constant or per pose) and ``W'``."""
        if not self.start:  # W' = W, and W^-1 is not among the factors
            return [self.M[0]] + [self.M[i] for i in range(1, 6)], W
        ms = [self.M[0]] + [self.M[i] for i in range(1, 6)] + [np.linalg.inv(W)]
        Mp = [ms[0]] + [ms[(self.start + i - 1) % 6 + 1] for i in range(1, 6)]
        assert self.Wp_const is not None
        return Mp, self.Wp_const

    def _right(self, Mp: list[FloatArray], Wp: FloatArray, N: int) -> FloatArray:
        """The right sides ``R (N, 3, 3, 4, 4)`` on the grid of joints 1, 2 (see ``pre``),
        from the loop's factors ``Mp`` and ``W'`` of ``N`` poses (:meth:`factors`)."""
        X = np.linalg.inv(Mp[6 - self.start]) if self.start >= 4 else Wp
        X = X[:, None, None] if X.ndim == 3 else X  # start 1-3: W' is constant
        if self.pre is not None:
            X = self.pre @ X
        if self.post is not None:
            X = X @ self.post
        return np.broadcast_to(X, (N, 3, 3, 4, 4))

    @staticmethod
    def _left(Mp: list[FloatArray]) -> FloatArray:
        """``P (..., 3, 3, 3, 14)``: the left sides' coefficients over joints 3-5."""
        g = _GRID
        t3, t4, t5 = np.meshgrid(g, g, g, indexing="ij")
        lead = [m[:, None, None, None] if m.ndim == 3 else m for m in Mp]
        L = _rz4(t3) @ lead[3] @ _rz4(t4) @ lead[4] @ _rz4(t5) @ lead[5]
        return _fit(_fourteen(L), 3)

    def matrices(self, W: FloatArray) -> tuple[Any, ...]:
        """The quadratic matrix polynomial ``S (N, 3, 12, 12)`` in ``x3``, the left sides'
        coefficients ``P (N, 3, 3, 3, 14)``, the pseudo-inverse ``(N, 8, 14)`` of the right
        sides' coefficients of their 8 non-constant monomials, their constant ones ``Q0 (N,
        14)``, and the loop's factors."""
        N = W.shape[0]
        Mp, Wp = self.factors(W)
        P = self.P_const if self.P_const is not None else self._left(Mp)
        P = np.broadcast_to(P, (N, 3, 3, 3, 14))
        # per pose one (9, 9) @ (9, 14) product: the fit over joints 1 and 2 at once
        Q = _BASIS_INV2 @ _fourteen(self._right(Mp, Wp, N)).reshape(N, 9, 14)
        Q0 = Q[:, 0]
        Q8 = Q[:, 1:].transpose(0, 2, 1)
        U, sv, Vt = np.linalg.svd(Q8, full_matrices=True)
        null = U[:, :, 8:]  # (N, 14, 6)
        inv = np.where(sv > 1e-12 * sv[:, :1], 1.0 / np.where(sv > 0, sv, 1.0), 0.0)
        Q8_pinv = np.swapaxes(Vt, -1, -2) @ (inv[..., None] * np.swapaxes(U[:, :, :8], -1, -2))
        # (P - Q0 in the constant row) @ null, rows (a, b, c): (1, cos, sin) of joints 3-5,
        # in the half-angle basis: per pose (27, 14) @ (14, 6) and (27, 27) @ (27, 6)
        Q0null = Q0[:, None] @ null  # (N, 1, 6)
        if self.HP is not None:
            E = self.HP @ null - _HALF3[:, :1] * Q0null
        else:
            E = P.reshape(N, 27, 14) @ null
            E[:, :1] -= Q0null
            E = _HALF3 @ E
        D = E.reshape(N, 3, 3, 3, 6).transpose(0, 1, 4, 2, 3)  # (N, 3, 6, 3, 3)
        S = np.zeros((N, 3, 12, 12))
        S[:, :, :6, :9] = D.reshape(N, 3, 6, 9)
        S[:, :, 6:, 3:] = D.reshape(N, 3, 6, 9)
        return S, P, Q8_pinv, Q0, Mp, Wp


def _eig_quadratic(S: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Eigenvalues of ``S0 + x S1 + x^2 S2`` as ``th = 2 atan(x)`` ``(N, 24)``, how far each is
    from real ``(N, 24)``, and the eigenvectors' monomials ``(N, 24, 4, 3)`` (``x4^i x5^j``)."""
    N = S.shape[0]
    S0, S1, S2 = S[:, 0], S[:, 1], S[:, 2]
    with np.errstate(all="ignore"):  # both ends' condition numbers in one SVD call, 0 / 0
        sv = np.linalg.svd(S[:, ::2], compute_uv=False)  # taken as inf (as np.linalg.cond)
        cond = np.nan_to_num(sv[..., 0] / sv[..., -1], nan=np.inf)
    c0, c2 = cond[:, 0], cond[:, 1]
    flip = ~(c2 <= c0)  # the better conditioned end is inverted: x, or y = 1 / x
    A, B = np.where(flip[:, None, None], S2, S0), np.where(flip[:, None, None], S0, S2)
    C = np.zeros((N, 24, 24))
    C[:, :12, 12:] = np.eye(12)
    with np.errstate(all="ignore"):
        C[:, 12:] = -_solve_each(B, np.concatenate([A, S1], axis=-1))
    C = np.where(np.isfinite(C), C, 0.0)
    lam, vec = np.linalg.eig(C)
    num, den = np.where(flip[:, None], 1.0 + 0j, lam), np.where(flip[:, None], lam, 1.0 + 0j)
    # x = num / den: th = 2 atan2(num, den) for real x, pi where den = 0
    mag = np.maximum(np.abs(num), np.abs(den))
    imag = np.abs((num * np.conj(den)).imag) / mag**2
    th = 2 * np.arctan2((num * np.conj(den)).real, np.abs(den) ** 2)
    th = np.where(np.abs(den) == 0, np.pi, th)
    top, bottom = vec[:, :12], vec[:, 12:]
    pick = (np.abs(top) ** 2).sum(1, keepdims=True) >= (np.abs(bottom) ** 2).sum(1, keepdims=True)
    v = np.where(pick, top, bottom).transpose(0, 2, 1).reshape(N, 24, 4, 3)
    return th, imag, v


def _solve_each(B: FloatArray, rhs: FloatArray) -> FloatArray:
    """``B^-1 rhs`` per pose, ``B (N, 12, 12)``, ``rhs (N, 12, k)``: where LAPACK meets an
    exactly zero pivot (both ends of the matrix polynomial singular, as on a table that has
    a closed form), least squares for that pose alone, so the others' answers stay those
    they get alone."""
    try:
        return np.asarray(np.linalg.solve(B, rhs), dtype=float)
    except np.linalg.LinAlgError:
        out = np.empty(rhs.shape)
        for k in range(len(B)):
            try:
                out[k] = np.linalg.solve(B[k], rhs[k])
            except np.linalg.LinAlgError:
                out[k] = np.linalg.lstsq(B[k], rhs[k], rcond=None)[0]
        return out


def _half_angle(lo: FloatArray, hi: FloatArray) -> FloatArray:
    """``th`` with ``(lo, hi)`` proportional to ``(1, tan(th / 2))`` in every entry (the
    best such fit, finite at th = pi): arrays ``(..., k)`` complex -> ``(...)``."""
    a = (np.abs(lo) ** 2).sum(-1)
    b = (np.conj(lo) * hi).sum(-1).real
    c = (np.abs(hi) ** 2).sum(-1)
    # the top eigenvector of [[a, b], [b, c]]: (cos phi, sin phi), phi = th / 2
    phi = 0.5 * np.arctan2(2 * b, a - c)
    return 2 * phi


class General6RSolver(ChainPolish):
    """IK of any 6R arm from its DH table by elimination to an eigenvalue problem (Raghavan
    and Roth): up to 16 solutions."""

    target_kind: TargetKind = "pose"
    #: no wrist, shoulder or elbow: a solution is named by its root (see ``root_joint``)
    wrist_middle: int | None = None
    labels_optional = True
    singularities = {"singular": SINGULAR}
    #: the solutions are numbered by each one's own root (two at one root are two)
    root_grouped = False

    def __init__(self, arm: SerialArm) -> None:
        check_arm(arm)
        model, self.unit = _unit_model(chain_model(arm))
        #: the pose error's weights: position over the arm's size, rotation
        self._weights = np.array([1 / model.scale] * 3 + [1.0] * 3)
        self.offsets = model.offsets
        self.slots = tuple(Branch() for _ in range(SLOTS))
        for start, reverse in _FORMULATIONS:
            m = _shifted(reversed_model(model) if reverse else model)
            self.reverse, self.model = reverse, m
            self.elim = _Elimination(m, start)
            self.M0_inv, self.M6_inv = np.linalg.inv(m.M[0]), np.linalg.inv(m.M[6])
            if _works(self):
                #: the joint (0-based, the arm's) whose half-angle tangent the eigenvalues are
                self.root_joint = int(5 - self.elim.joint[2] if reverse else self.elim.joint[2])
                return
        raise InputError(f"{arm.name}: {_DEGENERATE}")

    def label_rows(self, q: FloatArray) -> tuple[None, None]:
        """No shoulder or elbow (``q (m, 6)``): the roots name the solutions."""
        return None, None

    def check(self, arm: SerialArm) -> None:  # noqa: D102 - the Solver protocol
        _ = arm

    def single_kernel(self, arm: SerialArm) -> General6RKernel:
        """The one-pose interface of ``arm.ik`` (see :mod:`rikin.ik.general6r_kernel`)."""
        return General6RKernel(self, arm)

    def _to_chain(self, T_0_n: FloatArray) -> FloatArray:
        T = np.array(T_0_n, dtype=float)
        T[..., :3, 3] *= self.unit
        if self.reverse:
            T = np.linalg.inv(T)
        return self.M0_inv @ T @ self.M6_inv

    def _candidates(self, W: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """Unpolished ``th' (N, 16, 6)`` (shifted joints, the chain's order; 0 in the
        slots without one) and which slots hold one: the real roots only."""
        N = W.shape[0]
        S, P, Q8_pinv, Q0, Mp, Wp = self.elim.matrices(W)
        th3, imag, v = _eig_quadratic(S)
        order = np.argsort(imag, axis=1, kind="stable")[:, :SLOTS]
        ok = np.take_along_axis(imag, order, 1) <= IMAG_TOL
        pose, slot = np.nonzero(ok)  # one row per real root from here on
        root = order[pose, slot]
        t3, v = th3[pose, root], v[pose, root]  # (K,), (K, 4, 3)
        K = len(t3)
        t4 = _half_angle(v[:, :3, :].reshape(K, 9), v[:, 1:, :].reshape(K, 9))
        t5 = _half_angle(v[:, :, :2].reshape(K, 8), v[:, :, 1:].reshape(K, 8))
        # joints 1, 2 from the 14 equations: Q8 m12 = P(th3, th4, th5) - Q0
        t345 = np.stack([t3, t4, t5], axis=-1)
        b = np.ones((K, 3, 3))
        b[:, :, 1], b[:, :, 2] = np.cos(t345), np.sin(t345)
        m345 = b[:, 0, :, None, None] * b[:, 1, None, :, None] * b[:, 2, None, None, :]
        # per root one (1, 27) @ (27, 14) and one (1, 14) @ (14, 8) product
        Pk = P[pose] if P.shape[0] == N else P[0]
        lhs = m345.reshape(K, 1, 27) @ Pk.reshape(-1, 27, 14) - Q0[pose, None]
        m12 = (lhs @ np.swapaxes(Q8_pinv[pose], -1, -2))[:, 0]  # (1,c2,s2,c1,..)[1:]
        t1 = np.arctan2(m12[:, 5], m12[:, 2])
        t2 = np.arctan2(m12[:, 1], m12[:, 0])
        Rz = _rz4(np.stack([t1, t2, t3, t4, t5], axis=-1))
        F = Rz[:, 0]
        for i in range(1, 6):
            F = F @ (Mp[i][pose] if Mp[i].ndim == 3 else Mp[i])
            if i < 5:
                F = F @ Rz[:, i]
        Wk = Wp[pose] if Wp.ndim == 3 else Wp
        R6 = np.swapaxes(F[:, :3, :3], -1, -2) @ Wk[..., :3, :3]
        t6 = np.arctan2(R6[:, 1, 0], R6[:, 0, 0])
        th = np.zeros((N, SLOTS, 6))
        th[pose[:, None], slot[:, None], self.elim.joint] = np.stack([t1, t2, t3, t4, t5, t6], -1)
        return th, ok

    def _polished(self, W: FloatArray) -> tuple[FloatArray, np.ndarray, np.ndarray]:
        """Polished, distinct solutions ``th' (N, 16, 6)``, which are valid, which singular."""
        th, ok = self._candidates(W)
        goal = self.model.M[0] @ W @ self.model.M[6]
        pose, slot = np.nonzero(ok)
        th[pose, slot], T, z, o = self._newton(th[pose, slot], goal[pose])
        res = np.full(ok.shape, np.inf)
        res[pose, slot] = self._residual_of(T, goal[pose])
        valid = ok & (res <= ACCEPT_TOL)
        row = np.zeros(ok.shape, dtype=int)  # the slot's row of T, z, o
        row[pose, slot] = np.arange(len(pose))
        _distinct(th, valid, res, row)
        sing = np.zeros(valid.shape, dtype=bool)
        if valid.any():
            k = row[valid]
            J = np.concatenate([cross3(z[k], T[k, None, :3, 3] - o[k]), z[k]], axis=-1)
            sing[valid] = _singular(J)
        return th, valid, sing

    def _newton(self, th: FloatArray, goal: FloatArray) -> tuple[FloatArray, ...]:
        """Candidates ``th (m, 6)`` of the flange poses ``goal (m, 4, 4)`` polished: Newton
        steps on the whole pose (the 6 x 6 Jacobian solved, each step kept only where it
        lowers the error) until the error is at rounding level (``POLISHED``), then the
        careful polish (:meth:`ChainPolish._polish`: least squares without the directions
        below rounding, shortened steps) for any left above ``POLISHED_ALONE`` (a root
        near a fold, a candidate that is no solution). Returns the joints and their flange
        poses, joint axes and origins (the last Jacobian's)."""
        w = self._weights
        T, z, o = self._fk_frames(th)
        e = self._pose_error(T, goal) * w
        err = np.abs(e).max(-1)
        busy = np.flatnonzero(err > POLISHED)
        for _ in range(NEWTON_STEPS):
            if not busy.size:
                break
            J = np.concatenate([cross3(z[busy], T[busy, None, :3, 3] - o[busy]), z[busy]], -1)
            try:
                with np.errstate(all="ignore"):
                    step = np.linalg.solve(np.swapaxes(J, -1, -2) * w[:, None],
                                           e[busy, :, None])[..., 0]
            except np.linalg.LinAlgError:  # an exactly singular Jacobian: the careful way
                break
            cand = th[busy] + step
            Tc, zc, oc = self._fk_frames(cand)
            ec = self._pose_error(Tc, goal[busy]) * w
            errc = np.abs(ec).max(-1)
            better = errc < err[busy]
            b = busy[better]
            th[b], T[b], z[b], o[b], e[b], err[b] = (
                x[better] for x in (cand, Tc, zc, oc, ec, errc))
            busy = busy[better & (errc > POLISHED)]
        hard = np.flatnonzero(err > POLISHED_ALONE)
        if hard.size:
            th[hard], T[hard] = self._polish(th[hard], goal[hard], np.zeros(hard.size, bool))
            _, z[hard], o[hard] = self._fk_frames(th[hard])
        return th, T, z, o

    def solve(
        self, arm: SerialArm, T_0_n: FloatArray, hint: FloatArray | None, labels: bool = True
    ) -> RawSolutions:
        """All solutions of N flange poses ``T_0_n (N, 4, 4)``; 16 slots."""
        _ = hint
        W = self._to_chain(T_0_n)
        th, valid, sing = self._polished(W)
        th = th + SHIFT
        if self.reverse:
            th = th[..., ::-1]
        q = th - self.offsets
        q[~valid] = np.nan
        _ = labels  # named by their roots when the result is built (rikin.ik.api)
        return RawSolutions(q=q, valid=valid, slots=self.slots,
                            singular={"singular": sing & valid})

    def explain(self, arm: SerialArm, T_0_n: FloatArray) -> tuple[str, float]:
        """Why one flange pose has no solution (every root of the eigenvalue problem is
        complex, or none reaches it after polishing)."""
        _ = arm, T_0_n
        return (
            "no real root of the eigenvalue problem reaches it (the pose is outside the "
            "arm's workspace, or needs a tilt the wrist cannot make)",
            float("nan"),
        )


#: The loop's starting joint and the chain's direction, in the order tried: first those
#: whose left side is the arm's alone (computed once).
_FORMULATIONS = [(0, False), (0, True), (4, False), (4, True), (5, False), (5, True),
                 (1, False), (1, True), (2, False), (2, True), (3, False), (3, True)]

_DEGENERATE = (
    "the elimination to an eigenvalue problem degenerates for this table (two joints do "
    "the same motion, or the 14 equations lose rank)"
)


#: ``_LATER[a, b]``: slot b comes after slot a
_LATER = np.triu(np.ones((SLOTS, SLOTS), dtype=bool), 1)


def _distinct(th: FloatArray, valid: np.ndarray, res: FloatArray, row: np.ndarray) -> None:
    """Keep one of each group of valid slots ``(N, k)`` that are the same solution: the
    first slot of the group, holding the group's best polished joints, residual and
    ``row`` (in place)."""
    gap = np.abs(wrap_in_place(th[:, :, None] - th[:, None, :])).max(-1)  # (N, k, k)
    same = valid[:, :, None] & valid[:, None, :] & (gap <= 1e3 * SAME_SOLUTION_TOL)
    rows, i, j = np.nonzero(same & _LATER[: th.shape[1], : th.shape[1]])
    for r, a, b in zip(rows.tolist(), i.tolist(), j.tolist(), strict=True):
        if not valid[r, b] or not valid[r, a]:
            continue  # already merged into an earlier slot
        if res[r, b] < res[r, a]:
            th[r, a], res[r, a], row[r, a] = th[r, b], res[r, b], row[r, b]
        valid[r, b] = False


def _singular(J: FloatArray) -> np.ndarray:
    """Whether each Jacobian ``J (m, 6, 6)`` has singular values ``SINGULAR_RCOND`` apart.
    The SVD only where ``|det J|`` does not rule it out: the smallest singular value is at
    least ``|det J| (5 / |J|_F^2)^(5/2)`` (the other five's product is at most that
    power), the largest at most ``|J|_F``."""
    F2 = (J * J).sum(axis=(-1, -2))
    sure = np.abs(np.linalg.det(J)) * 5.0**2.5 > 2 * SINGULAR_RCOND * F2**3
    out = np.zeros(len(J), dtype=bool)
    check = np.flatnonzero(~sure)
    if check.size:
        sv = np.linalg.svd(J[check], compute_uv=False)
        out[check] = sv[:, -1] <= SINGULAR_RCOND * sv[:, 0]
    return out


def _works(solver: General6RSolver) -> bool:
    """Whether the elimination finds known solutions of a few poses of the arm, from a
    matrix polynomial one of whose ends is invertible (a table on which it degenerates
    does not: there both ends are singular to rounding, and which roots come out of the
    eigenvalues is luck, which four poses do not reveal)."""
    rng = np.random.default_rng(6)
    th = rng.uniform(-np.pi, np.pi, size=(4, 6))
    W = solver.M0_inv @ solver._fk_frames(th)[0] @ solver.M6_inv
    try:
        with np.errstate(all="ignore"):
            sv = np.linalg.svd(solver.elim.matrices(W)[0][:, ::2], compute_uv=False)
            if not np.all((sv[..., 0] / sv[..., -1]).min(axis=-1) <= PENCIL_COND):
                return False
            found, valid, _ = solver._polished(W)
    except np.linalg.LinAlgError:  # a factor of the loop not invertible: not this way
        return False
    gap = np.abs(wrap_in_place(found - th[:, None])).max(-1)
    return bool(np.all(((gap <= 1e-6) & valid).any(axis=1)))


def recognise(arm: SerialArm) -> tuple[str, str]:
    """``(family, "")`` for a 6R arm the elimination solves, else ``("", reason)``."""
    check_arm(arm)
    not_6r = six_revolute_reason(arm)
    if not_6r:
        return "", not_6r
    try:
        General6RSolver(arm)
    except InputError:
        return "", _DEGENERATE
    return "general 6R: up to 16 solutions, by elimination to an eigenvalue problem", ""

