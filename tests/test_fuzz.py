"""One error hierarchy at every public boundary (issue 10, item 4).

Every public function of rikin's numeric API, and every lesson robot's ``fk``, ``ik``,
``ik_batch`` and ``ik_numerical``, is called with one argument replaced by a hostile
value: a wrong shape, a bool / int / complex / object / text dtype, None, NaN, inf,
1e300, zero, negative or tiny lengths, sympy objects, degrees, scalars, lists and tuples.
A call passes only if it

* raises ``InputError`` or ``UnreachableError`` whose message names the argument, or
* returns the right answer: the value has a real-number equivalent (a list, a tuple, an
  int array, a sympy number) and the call returns what it returns for that float64
  array, with no NaN in it;

and prints no warning (warnings are errors here). ``RuntimeError("rikin bug")`` and any
bare ``TypeError``/``ValueError``/``IndexError``/``ZeroDivisionError`` fail the test.
Seeded (the "ci" Hypothesis profile is derandomized) and bounded: ``EXAMPLES`` per case.

(``rikin.plot``, ``rikin.symbolic`` and ``rikin.widgets`` are not fuzzed here.)
"""

from __future__ import annotations

import dataclasses
import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import matplotlib
import numpy as np
import pytest
import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import rikin  # noqa: E402
from rikin import InputError, UnreachableError, robots
from rikin.ik import ik_numerical, ik_numerical_multistart
from rikin.ik.numerical import pose_error

SA = rikin.SerialArm

EXAMPLES = 12
#: Per case that draws a figure or builds a panel (tens of milliseconds a call).
EXAMPLES_SLOW = 6

ARMS = {name: make() for name, make in robots.LESSON_ROBOTS.items()}
RNG = np.random.default_rng(20261201)


class _Opaque:
    def __repr__(self) -> str:
        return "<opaque object>"


SCALARS = [
    None, "x", "1.5", b"1", True, False, 1 + 2j, np.complex128(1.0), np.nan, np.inf, -np.inf,
    1e300, -1e300, 0.0, -1.0, 1e-300, 90.0, 45, 720.0, 1e7, 3, np.float32(0.5), np.int64(2),
    sympy.Symbol("l"), sympy.Integer(7), sympy.pi / 4, sympy.Float(2.5), sympy.I, _Opaque(),
    {"a": 1}, [], (), [[1.0, 2.0], [3.0]], ["a", "b"], [None, 1.0], [1.0, np.nan],
]
DTYPES = st.sampled_from([np.bool_, np.int64, np.float64, np.float32, np.complex128, "U3"])


def _arrays() -> st.SearchStrategy[Any]:
    shapes = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=5)
    return DTYPES.flatmap(
        lambda dt: hnp.arrays(
            dt,
            shapes,
            elements=(
                st.floats(-1e3, 1e3, width=32) if np.dtype(dt).kind == "f"
                else st.integers(-1000, 1000) if np.dtype(dt).kind == "i"
                else None
            ),
        )
    )


def _near_valid(valid: Any) -> st.SearchStrategy[Any]:
    """The valid value spoiled in one entry, as a list, as a tuple, or reshaped."""
    arr = np.asarray(valid, dtype=float)
    if arr.ndim == 0:
        return st.sampled_from([float(arr), int(arr), [float(arr)], (float(arr),)])
    poison = st.sampled_from([np.nan, np.inf, 1e300, None, "x", 1j, True, sympy.Symbol("q")])

    def spoil(data: tuple[int, Any]) -> Any:
        i, bad = data
        flat = arr.ravel().tolist()
        flat[i % len(flat)] = bad
        return np.array(flat, dtype=object).reshape(arr.shape).tolist()

    return st.one_of(
        st.just(arr.tolist()),
        st.just(tuple(map(tuple, arr)) if arr.ndim == 2 else tuple(arr.tolist())),
        st.just(arr.astype(np.float32)),
        st.just(arr.ravel()),
        st.just(arr[..., :-1]),
        st.just(arr[None]),
        st.tuples(st.integers(0, 10**6), poison).map(spoil),
    )


def _wrong_objects() -> list[Any]:
    """Objects of rikin and matplotlib that are the wrong thing for most arguments."""
    arm = robots.planar_2r()
    fig = plt.figure()  # never shown; a Figure where an Axes (or an arm) is wanted
    plt.close(fig)
    return [rikin.Link(a=1.0), [rikin.Link(a=1.0)], arm.ik([15.0, 5.0]),
            arm.ik_batch(arm.fk(np.array([[0.1, 0.2]]))), np.eye(4), fig, np.float64,
            {"x": 1.0}, lambda: 0, "standard", "  ", "\u00e9", sympy.Matrix([[1, 2]])]


WRONG_OBJECTS = _wrong_objects()


def bad_values(valid: Any) -> st.SearchStrategy[Any]:
    try:
        numeric_valid = valid is not None and np.asarray(valid, dtype=float) is not None
    except (TypeError, ValueError):
        numeric_valid = False
    near = _near_valid(valid if numeric_valid else 0.0)
    return st.one_of(st.sampled_from(SCALARS), _arrays(), near, st.sampled_from(WRONG_OBJECTS))


def float_equivalent(v: Any) -> Any:
    """``v`` as float64 if it is plainly real numbers (not bool, text, complex, None), else None."""
    if v is None or isinstance(v, (str, bytes, bool, np.bool_, dict, _Opaque)):
        return None
    try:
        arr = np.asarray(v)
    except (TypeError, ValueError):
        return None
    if arr.dtype.kind in "fiu":
        return arr.astype(np.float64)
    if arr.dtype.kind == "O" and arr.size:
        out = []
        for e in arr.ravel().tolist():
            if e is None or isinstance(e, (str, bytes, bool, complex, dict, list, _Opaque)):
                return None
            if isinstance(e, sympy.Basic) and not (e.is_number and e.is_real):
                return None
            try:
                out.append(float(e))
            except (TypeError, ValueError):
                return None
        return np.array(out).reshape(arr.shape)
    if arr.dtype.kind == "O":
        return None
    return None


def _same(a: Any, b: Any) -> bool:
    """Whether two results of the same call agree (arrays allclose, NaN nowhere)."""
    if isinstance(a, rikin.IKResult):
        return a.q.shape == b.q.shape and np.allclose(a.q, b.q) and a.labels == b.labels
    if isinstance(a, rikin.BatchIKResult):
        return np.array_equal(a.valid, b.valid) and np.allclose(
            a.q[a.valid], b.q[b.valid]
        )
    if isinstance(a, rikin.SerialArm):
        z = np.zeros(a.n)
        return np.allclose(a.fk(z), b.fk(z))
    if isinstance(a, rikin.Link):
        return a == b
    if hasattr(a, "q") and hasattr(a, "success"):
        return np.allclose(a.q, b.q)
    if isinstance(a, tuple):
        return all(_same(x, y) for x, y in zip(a, b, strict=True))
    if dataclasses.is_dataclass(a):
        return all(_same(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a))
    if isinstance(a, (str, float, int)):
        return a == b
    if isinstance(a, sympy.MatrixBase | sympy.Basic):
        return _sym_close(a, b)
    if not _numbers_only(a):
        return type(a) is type(b)
    return np.allclose(np.asarray(a, float), np.asarray(b, float))


def _sym_close(a: Any, b: Any) -> bool:
    """Two sympy results agree numerically at one generic point of their symbols."""
    syms = sorted(a.free_symbols | b.free_symbols, key=str)
    at = {x: 0.3 + 0.1 * i for i, x in enumerate(syms)}
    fa, fb = (np.array(sympy.Matrix([e]).subs(at).evalf().tolist(), dtype=complex) for e in (a, b))
    return fa.shape == fb.shape and np.allclose(fa, fb)


def _finite(result: Any) -> bool:
    if isinstance(result, rikin.IKResult):
        return bool(np.isfinite(result.q).all())
    if isinstance(result, rikin.BatchIKResult):
        return bool(np.isfinite(result.q[result.valid]).all())
    if isinstance(result, (rikin.SerialArm, rikin.Link)):
        return True
    if hasattr(result, "q") and hasattr(result, "success"):
        return bool(np.isfinite(result.q).all())
    if isinstance(result, tuple):
        return all(_finite(r) for r in result)
    if dataclasses.is_dataclass(result):
        return all(_finite(getattr(result, f.name)) for f in dataclasses.fields(result))
    if isinstance(result, str):
        return re.search(r"\b(nan|inf)\b", result, re.IGNORECASE) is None
    if isinstance(result, (list, dict)) and not _numbers_only(result):
        items = result.values() if isinstance(result, dict) else result
        return all(_finite(r) for r in items)
    if isinstance(result, sympy.MatrixBase | sympy.Basic):
        return not result.has(sympy.nan, sympy.zoo, sympy.oo, -sympy.oo)
    if result is None or not _numbers_only(result):
        return True  # a panel, a figure, a table: what it shows is checked by its own tests
    return bool(np.isfinite(np.asarray(result, dtype=float)).all())


def _numbers_only(x: Any) -> bool:
    try:
        np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


@dataclass
class Case:
    """``call(value)``: the function with its argument ``arg`` set to ``value``."""

    name: str
    arg: str
    call: Callable[[Any], Any]
    valid: Any
    accepts_none: bool = False  # None is the argument's documented default
    symbolic: bool = False  # sympy expressions are documented input (a symbolic DH table)
    nan_in_nan_out: bool = False  # documented: NaN (and inf) map to NaN, like numpy's ufuncs
    fn: Any = None  # the public callable(s) this case fuzzes (see test_every_public_callable_...)
    numeric: bool = True  # False: the argument is not a number (an arm, a text, an Axes...)
    accept: Callable[[Any], bool] | None = None  # values that are documented input as they are
    slow: bool = False  # draws or builds a panel: fewer examples (see EXAMPLES_SLOW)
    param: str | None = None  # the parameter fuzzed, when messages call it ``arg`` instead


def _pose_of(arm: rikin.SerialArm) -> np.ndarray:
    q = np.where(arm.revolute, RNG.uniform(-np.pi, np.pi, arm.n), RNG.uniform(0.5, 2, arm.n))
    return arm.fk(q)


def _target(arm: rikin.SerialArm, T: np.ndarray) -> np.ndarray:
    kind = arm.solver.target_kind
    if kind == "pose":
        return T
    if kind == "position":
        return T[:3, 3].copy()
    if kind == "planar_position":
        return T[:2, 3].copy()
    return np.array([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])])


def _cases() -> list[Case]:
    cases: list[Case] = []
    for rname, arm in ARMS.items():
        T = _pose_of(arm)
        tg = _target(arm, T)
        q = np.where(arm.revolute, 0.3, 1.0)
        mask = None if arm.n == 6 else (1, 1, 1, 0, 0, 0)
        sol = arm.ik(tg)
        add = cases.append
        add(Case(f"{rname}.fk", "q", lambda v, a=arm: a.fk(v), q, fn=SA.fk))
        add(Case(f"{rname}.fk_flange", "q", lambda v, a=arm: a.fk_flange(v), q, fn=SA.fk_flange))
        add(Case(f"{rname}.jacobian", "q", lambda v, a=arm: a.jacobian(v), q, fn=SA.jacobian))
        add(Case(f"{rname}.joint_axes", "q", lambda v, a=arm: a.joint_axes(v), q, fn=SA.joint_axes))
        add(Case(f"{rname}.world_to_base", "T_world", lambda v, a=arm: a.world_to_base(v), T,
                 fn=SA.world_to_base))
        add(Case(f"{rname}.ik", "target", lambda v, a=arm: a.ik(v), tg, fn=SA.ik))
        add(Case(f"{rname}.ik near", "near", lambda v, a=arm, t=tg: a.ik(t, near=v), q,
                 accepts_none=True, fn=SA.ik))
        add(Case(f"{rname}.ik within_limits", "within_limits",
                 lambda v, a=arm, t=tg: a.ik(t, within_limits=v), True, fn=SA.ik,
                 numeric=False, accept=_flag))
        add(Case(f"{rname}.ik_batch", "T", lambda v, a=arm: a.ik_batch(v), T[None], fn=SA.ik_batch))
        add(Case(f"{rname}.ik_batch chunk_size", "chunk_size",
                 lambda v, a=arm, t=T: a.ik_batch(t[None], chunk_size=v), 16, fn=SA.ik_batch))
        add(Case(f"{rname}.ik_batch workers", "workers",
                 lambda v, a=arm, t=T: a.ik_batch(t[None], workers=v), 1, accepts_none=True,
                     fn=SA.ik_batch))
        add(Case(f"{rname}.ik_numerical T", "T",
                 lambda v, a=arm, m=mask: ik_numerical(a, v, max_iter=15, mask=m), T,
                     fn=ik_numerical))
        add(Case(f"{rname}.ik_numerical q0", "q0",
                 lambda v, a=arm, t=T, m=mask: ik_numerical(a, t, v, max_iter=15, mask=m), q,
                 accepts_none=True, fn=ik_numerical))
        add(Case(f"{rname}.ik_numerical tol", "tol",
                 lambda v, a=arm, t=T, m=mask: ik_numerical(a, t, tol=v, max_iter=15, mask=m),
                 1e-6, fn=ik_numerical))
        whole = arm.n == 6 or (arm.n == 5 and hasattr(arm.solver, "nearest_reachable"))  # mask=None
        add(Case(f"{rname}.ik_numerical mask", "mask",
                 lambda v, a=arm, t=T: ik_numerical(a, t, mask=v, max_iter=15),
                 (1, 1, 1, 0, 0, 0), accepts_none=whole, fn=ik_numerical))
        if arm.n < 6 and whole:  # a 5-DOF lesson arm given its whole pose, as arm.ik takes it
            add(Case(f"{rname}.ik_numerical T (whole pose)", "T",
                     lambda v, a=arm: ik_numerical(a, v, max_iter=15), T, fn=ik_numerical))
        add(Case(f"{rname}.pose_error q", "q", lambda v, a=arm, t=T: pose_error(a, v, t), q,
                 fn=pose_error))
        add(Case(f"{rname}.pose_error T", "T", lambda v, a=arm: pose_error(a, np.where(
            a.revolute, 0.3, 1.0), v), T, fn=pose_error))
        add(Case(f"{rname}.table", "decimals", lambda v, s=sol: s.table(v), 3,
                 fn=rikin.IKResult.table))
        # the constructor, one length at a time
        import inspect

        params = [
            p for p in inspect.signature(robots.LESSON_ROBOTS[rname]).parameters.values()
            if isinstance(p.default, float)
        ]
        for p in params:
            add(Case(f"robots.{rname}({p.name}=...)", p.name,
                     lambda v, mk=robots.LESSON_ROBOTS[rname], n=p.name: mk(**{n: v}), p.default,
                         fn=robots.LESSON_ROBOTS[rname]))
        for which in ("base", "tool"):
            add(Case(f"robots.{rname}({which}=...)", which,
                     lambda v, mk=robots.LESSON_ROBOTS[rname], w=which: mk(**{w: v}),
                     np.eye(4), accepts_none=True, fn=robots.LESSON_ROBOTS[rname]))
    arm6 = ARMS["aula10_6r"]
    T6 = _pose_of(arm6)
    T06 = arm6.world_to_base(T6)
    cases += [
        Case("solver.steps T_0_6", "T_0_6", lambda v: arm6.solver.steps(arm6, v), T06,
             fn=type(arm6.solver).steps),
        Case("solver.steps arm_slot", "arm_slot", lambda v: arm6.solver.steps(arm6, T06, v), 1,
             fn=type(arm6.solver).steps),
        Case("ik_numerical_multistart", "n_starts",
             lambda v: ik_numerical_multistart(arm6, T6, v, max_iter=10), 2,
                 fn=ik_numerical_multistart),
        Case("ik.solve arm", "arm", lambda v: rikin.ik.solve(v, T6), None, fn=rikin.ik.solve),
        Case("ik_numerical arm", "arm", lambda v: ik_numerical(v, T6), None, fn=ik_numerical),
        Case("wrap_angle", "theta", rikin.wrap_angle, [0.5, 7.0], fn=rikin.wrap_angle),
        Case("deg", "theta", rikin.deg, [0.5, 1.0], fn=rikin.deg),
        Case("rad", "theta", rikin.rad, [30.0, 45.0], fn=rikin.rad),
        Case("rotx", "theta", rikin.rotx, 0.3, fn=rikin.rotx),
        Case("roty", "theta", rikin.roty, [0.3, -0.2], fn=rikin.roty),
        Case("rotz", "theta", rikin.rotz, 0.3, fn=rikin.rotz),
        Case("transforms.trotx", "theta", rikin.transforms.trotx, 0.3, fn=rikin.transforms.trotx),
        Case("transl", "x", rikin.transl, [1.0, 2.0, 3.0], fn=rikin.transl),
        Case("transl(x, y, z)", "y", lambda v: rikin.transl(1.0, v, 2.0), 0.5, fn=rikin.transl),
        Case("homogeneous R", "R", lambda v: rikin.homogeneous(v, [1.0, 2.0, 3.0]),
             rikin.rotz(0.4), accepts_none=True, fn=rikin.homogeneous),
        Case("homogeneous p", "p", lambda v: rikin.homogeneous(rikin.rotz(0.4), v),
             [1.0, 2.0, 3.0], accepts_none=True, fn=rikin.homogeneous),
        Case("inv_transform", "T", rikin.inv_transform, T6, fn=rikin.inv_transform),
        Case("rpy_to_r roll", "roll", lambda v: rikin.rpy_to_r(v, 0.1, 0.2), 0.3,
             fn=rikin.rpy_to_r),
        Case("rpy_to_r yaw", "yaw", lambda v: rikin.rpy_to_r(0.3, 0.1, v), 0.2, fn=rikin.rpy_to_r),
        Case("rpy_to_r degrees", "degrees", lambda v: rikin.rpy_to_r(30, 10, 20, degrees=v), True,
             fn=rikin.rpy_to_r, numeric=False, accept=_flag),
        Case("r_to_rpy", "R", rikin.r_to_rpy, rikin.rotz(0.3), fn=rikin.r_to_rpy),
        Case("zyz_to_r", "theta", lambda v: rikin.zyz_to_r(0.1, v, 0.3), 0.2, fn=rikin.zyz_to_r),
        Case("r_to_zyz R", "R", rikin.r_to_zyz, rikin.rotx(0.3), fn=rikin.r_to_zyz),
        Case("r_to_zyz branch", "branch", lambda v: rikin.r_to_zyz(rikin.rotx(0.3), branch=v), -1,
             fn=rikin.r_to_zyz),
        Case("Link a", "a", lambda v: rikin.Link(a=v), symbolic=True, valid=1.0, fn=rikin.Link),
        Case("Link d", "d", lambda v: rikin.Link(d=v), symbolic=True, valid=1.0, fn=rikin.Link),
        Case("Link alpha", "alpha", lambda v: rikin.Link(alpha=v), symbolic=True, valid=0.5,
             fn=rikin.Link),
        Case("Link offset", "offset", lambda v: rikin.Link(offset=v), symbolic=True, valid=0.5,
             fn=rikin.Link),
        Case("Link qlim", "qlim", lambda v: rikin.Link(qlim=v), (-1.0, 1.0), accepts_none=True,
             fn=rikin.Link),
        Case("Link direction", "direction", lambda v: rikin.Link(direction=v), -1, fn=rikin.Link,
             numeric=False, accept=_sign),
        Case("SerialArm base", "base",
             lambda v: rikin.SerialArm((rikin.Link(a=1.0),), base=v), np.eye(4), fn=SA),
        Case("SerialArm tool", "tool",
             lambda v: rikin.SerialArm((rikin.Link(a=1.0),), tool=v), np.eye(4), fn=SA),
        Case("SerialArm links", "links", lambda v: rikin.SerialArm(v), None, fn=SA,
             numeric=False, accept=_links),
        Case("SerialArm convention", "convention",
             lambda v: rikin.SerialArm((rikin.Link(a=1.0),), convention=v), None, fn=SA,
             numeric=False, accept=_one_of("standard", "modified")),
    ]
    return cases


# ------------------------------------------------------------------ the rest of the public API
def _drawn(obj: Any) -> np.ndarray:
    """What a drawing shows, as numbers: every line's and marker set's coordinates (the
    NaN that break a polyline counted, not kept), then the figure is closed."""
    fig = obj if isinstance(obj, matplotlib.figure.Figure) else obj.figure
    parts = []
    for ax in fig.axes:
        for line in ax.get_lines():
            data = line.get_data_3d() if hasattr(line, "get_data_3d") else line.get_xydata().T
            parts.append(np.asarray(data, dtype=float).ravel())
        for coll in ax.collections:
            off = getattr(coll, "_offsets3d", None)
            parts.append(np.asarray(coll.get_offsets() if off is None else off, float).ravel())
    plt.close(fig)
    flat = np.concatenate(parts) if parts else np.zeros(0)
    nan = np.isnan(flat)
    return np.append(np.where(nan, 0.0, flat), nan.sum())


def _traces(fig: Any) -> np.ndarray:
    """The coordinates of an interactive (plotly) figure's traces, as :func:`_drawn`."""
    parts = []
    for tr in fig.figure.data:
        for k in ("x", "y", "z"):
            v = getattr(tr, k, None)
            if v is not None:
                parts.append(np.array([np.nan if e is None else e for e in v], dtype=float))
    flat = np.concatenate(parts) if parts else np.zeros(0)
    nan = np.isnan(flat)
    return np.append(np.where(nan, 0.0, flat), nan.sum())


def _panel(panel: Any) -> Any:
    """A DH panel that could not read an input says so in its status line: raised here as
    InputError, so the check asks that the status names the input."""
    msg = panel.state.message
    if "cannot be read" in msg:
        raise InputError(msg)
    return panel


def _text(v: Any) -> bool:
    return isinstance(v, str)


def _flag(v: Any) -> bool:
    return isinstance(v, (bool, np.bool_))


def _sign(v: Any) -> bool:
    """+1 or -1 as a number (a joint's direction), not a bool."""
    return (isinstance(v, (int, float, np.integer, np.floating))
            and not isinstance(v, (bool, np.bool_)) and v in (1, -1))


def _one_of(*choices: str) -> Callable[[Any], bool]:
    return lambda v: isinstance(v, str) and v in choices


def _colour(v: Any) -> bool:
    try:
        return bool(matplotlib.colors.is_color_like(v))
    except Exception:  # noqa: BLE001 - not a colour, whatever the reason
        return False


def _in_language(language: Any) -> str:
    """The language tables print in after ``set_language(language)`` (then back to default)."""
    try:
        rikin.i18n.set_language(language)
        return rikin.i18n.language()
    finally:
        rikin.i18n.set_language(None)


def _texts(k: int) -> Callable[[Any], bool]:
    return lambda v: isinstance(v, (list, tuple)) and len(v) == k and all(map(_text, v))


def _links(v: Any) -> bool:
    return isinstance(v, rikin.SerialArm) or isinstance(v, (list, tuple)) and bool(v) and all(
        isinstance(e, rikin.Link) for e in v)


def _expression(v: Any) -> bool:
    """A formula: a sympy expression or matrix, or a plain (even complex) number."""
    if isinstance(v, (bool, np.bool_)):
        return False
    if isinstance(v, np.ndarray):
        return v.ndim == 0 and v.dtype.kind in "iufc"
    return isinstance(v, (sympy.Expr, sympy.MatrixBase, int, float, complex, np.number))


def _index(n: int, arrays: bool = True) -> Callable[[Any], bool]:
    """Valid indices of a sequence of ``n`` items (as a tuple takes them, or with ``arrays``
    as numpy takes them: lists and arrays of whole numbers in range, masks of n booleans)."""
    import operator

    def ok(v: Any) -> bool:
        if isinstance(v, (bool, np.bool_, str, bytes)):
            return False
        if isinstance(v, tuple):
            return arrays and len(v) == 0  # (): everything, as numpy reads it
        if isinstance(v, list) or (arrays and isinstance(v, np.ndarray)):
            if not arrays:
                return False
            if isinstance(v, list) and not v:
                return True
            try:
                a = np.asarray(v)
            except (TypeError, ValueError):
                return False
            if a.dtype.kind == "b":
                return a.shape == (n,)
            return a.dtype.kind in "iu" and bool(((a >= -n) & (a < n)).all())
        try:
            i = operator.index(v)
        except TypeError:
            return False
        return -n <= i < n

    return ok


def _rows(k: int) -> Callable[[Any], bool]:
    """Rows of ``k`` cells: a cell may be text (a branch name) as well as a number."""
    return lambda v: isinstance(v, (list, tuple)) and all(
        isinstance(r, (list, tuple)) and len(r) == k for r in v)


def _api_cases() -> list[Case]:
    """Drawings, interactive figures, widgets, tables, sympy DH, the general 6R solver
    through a user-built arm, and the keywords the first part leaves out."""
    from rikin import dhtext, interactive, plot, symbolic, tables, widgets
    from rikin.ik import api, families6r, general6r, parallel3, pieper

    p2, p3, a6 = robots.planar_2r(), robots.planar_3r(), ARMS["aula10_6r"]
    q3, q6 = np.array([0.3, 0.5, -0.2]), np.full(6, 0.3)
    res2 = p2.ik([15.0, 5.0])
    res6 = a6.ik(a6.fk(q6))
    T6 = a6.fk(q6)
    num6 = ik_numerical(a6, T6, q6 + 0.05)
    F3 = p3.fk(q3, frames=True)
    F6 = a6.fk(q6, frames=True)
    puma = widgets.arm_from_table(widgets.PUMA560_TABLE, units="m", name="puma")
    Lk, half = rikin.Link, np.pi / 2
    ur5 = rikin.SerialArm((Lk(d=0.089159, alpha=half), Lk(a=-0.425), Lk(a=-0.39225),
                           Lk(d=0.10915, alpha=half), Lk(d=0.09465, alpha=-half),
                           Lk(d=0.0823)), name="UR5")
    skew = rikin.SerialArm(tuple(Lk(a=0.3 + 0.1 * i, d=0.2 - 0.05 * i, alpha=0.4 + 0.3 * i)
                                 for i in range(6)), name="general 6R")
    scara4 = rikin.SerialArm((Lk(d=0.4, a=0.325), Lk(a=0.275, alpha=np.pi), Lk("P"),
                              Lk(d=0.05)), name="four-axis SCARA")
    pitched = rikin.SerialArm((Lk(d=0.077, alpha=half), Lk(a=0.13, offset=-1.3855),
                               Lk(a=0.124, offset=1.3855), Lk(a=0.126)), name="four-axis arm")
    Tp = puma.fk(np.full(6, 0.4))
    l_sym = sympy.Symbol("l", positive=True)
    q_sym = sympy.Symbol("q1", real=True)
    expr = l_sym * sympy.cos(q_sym) + sympy.sin(q_sym) ** 2 + sympy.cos(q_sym) ** 2
    links2 = robots.planar_2r_links()
    fig2 = interactive.solutions_figure(p2, res2)
    unread = widgets.DHPanel(table="# no rows")  # nothing to draw: static_html stays quick
    C = Case
    obj = {"numeric": False}
    text = {"numeric": False, "accept": _text}
    flag = {"numeric": False, "accept": _flag}
    opt_text = {"numeric": False, "accept": _text, "accepts_none": True}
    opt_ax = {"numeric": False, "accepts_none": True}
    is_arm_ik = lambda v: isinstance(v, rikin.IKResult) and v.q.shape[1:] == (2,)  # noqa: E731
    cases = [
        # rikin.plot
        C("plot.is_planar", "arm", plot.is_planar, p3, fn=plot.is_planar, **obj),
        C("plot.plot_arm arm", "arm", lambda v: _drawn(plot.plot_arm(v, q3)), p3,
          fn=plot.plot_arm, slow=True, **obj),
        C("plot.plot_arm q", "q", lambda v: _drawn(plot.plot_arm(p3, v)), q3, fn=plot.plot_arm,
          slow=True),
        C("plot.plot_arm q 3D", "q", lambda v: _drawn(plot.plot_arm(a6, v)), q6,
          fn=plot.plot_arm, slow=True),
        C("plot.plot_arm ax", "ax", lambda v: _drawn(plot.plot_arm(p3, q3, ax=v)), None,
          fn=plot.plot_arm, slow=True, **opt_ax),
        C("plot.plot_arm frames", "frames", lambda v: _drawn(plot.plot_arm(p3, q3, frames=v)),
          True, fn=plot.plot_arm, slow=True, **flag),
        C("plot.plot_arm frame_scale", "frame_scale",
          lambda v: _drawn(plot.plot_arm(p3, q3, frame_scale=v)), 2.0, accepts_none=True,
          fn=plot.plot_arm, slow=True),
        C("plot.plot_arm title", "title", lambda v: _drawn(plot.plot_arm(p3, q3, title=v)), "t",
          fn=plot.plot_arm, slow=True, **opt_text),
        C("plot.plot_arm color", "color", lambda v: _drawn(plot.plot_arm(p3, q3, color=v)), "k",
          fn=plot.plot_arm, slow=True, numeric=False, accept=_colour, accepts_none=True),
        C("plot.plot_arm label_joints", "label_joints",
          lambda v: _drawn(plot.plot_arm(p3, q3, label_joints=v)), True, fn=plot.plot_arm,
          slow=True, **flag),
        C("plot.plot_arm limits", "limits",
          lambda v: _drawn(plot.plot_arm(p3, q3, limits=v)), [[-40.0, 40.0], [-40.0, 40.0]],
          accepts_none=True, fn=plot.plot_arm, slow=True),
        C("plot.plot_arm gripper", "gripper", lambda v: _drawn(plot.plot_arm(p3, q3, gripper=v)),
          True, fn=plot.plot_arm, slow=True, **flag),
        C("plot.plot_arm view", "view", lambda v: _drawn(plot.plot_arm(a6, q6, view=v)),
          (20.0, 30.0), accepts_none=True, fn=plot.plot_arm, slow=True),
        C("plot.plot_dh_frames q", "q", lambda v: _drawn(plot.plot_dh_frames(p3, v)), q3,
          accepts_none=True, fn=plot.plot_dh_frames, slow=True),
        C("plot.plot_dh_frames arm", "arm", lambda v: _drawn(plot.plot_dh_frames(v)), p3,
          fn=plot.plot_dh_frames, slow=True, **obj),
        C("plot.plot_dh_frames ax", "ax", lambda v: _drawn(plot.plot_dh_frames(p3, ax=v)), None,
          fn=plot.plot_dh_frames, slow=True, **opt_ax),
        C("plot.plot_dh_frames title", "title",
          lambda v: _drawn(plot.plot_dh_frames(p3, title=v)), "t", fn=plot.plot_dh_frames,
          slow=True, **opt_text),
        C("plot.plot_dh_frames view", "view", lambda v: _drawn(plot.plot_dh_frames(a6, view=v)),
          (20.0, 30.0), accepts_none=True, fn=plot.plot_dh_frames, slow=True),
        C("plot.plot_dh_frames frame_scale", "frame_scale",
          lambda v: _drawn(plot.plot_dh_frames(p3, frame_scale=v)), 2.0, accepts_none=True,
          fn=plot.plot_dh_frames, slow=True),
        C("plot.plot_solutions arm", "arm", lambda v: _drawn(plot.plot_solutions(v, res2)), p2,
          fn=plot.plot_solutions, slow=True, **obj),
        C("plot.plot_solutions result", "result", lambda v: _drawn(plot.plot_solutions(p2, v)),
          res2.q, fn=plot.plot_solutions, slow=True, accept=is_arm_ik),
        C("plot.plot_solutions ncols", "ncols",
          lambda v: _drawn(plot.plot_solutions(p2, res2, ncols=v)), 2, fn=plot.plot_solutions,
          slow=True),
        C("plot.plot_solutions figsize", "figsize",
          lambda v: _drawn(plot.plot_solutions(p2, res2, figsize=v)), (4.0, 3.0),
          accepts_none=True, fn=plot.plot_solutions, slow=True),
        C("plot.plot_solutions frames", "frames",
          lambda v: _drawn(plot.plot_solutions(p2, res2, frames=v)), True,
          fn=plot.plot_solutions, slow=True, **flag),
        C("plot.plot_solutions target", "target",
          lambda v: _drawn(plot.plot_solutions(p2, res2.q, target=v)), res2.target,
          accepts_none=True, fn=plot.plot_solutions, slow=True),
        C("plot.plot_solutions gripper", "gripper",
          lambda v: _drawn(plot.plot_solutions(p2, res2, gripper=v)), True,
          fn=plot.plot_solutions, slow=True, **flag),
        C("plot.plot_solutions view", "view",
          lambda v: _drawn(plot.plot_solutions(a6, res6[:1], view=v)), (20.0, 30.0),
          accepts_none=True, fn=plot.plot_solutions, slow=True),
        C("plot.plot_solutions key", "key",
          lambda v: _drawn(plot.plot_solutions(p2, res2, key=v)), True,
          fn=plot.plot_solutions, slow=True, **flag),
        C("plot.plot_solutions ghosts", "ghosts",
          lambda v: _drawn(plot.plot_solutions(p2, res2, ghosts=v)), True,
          fn=plot.plot_solutions, slow=True, **flag),
        C("plot.turned_axes arm", "arm", lambda v: plot.turned_axes(v, q3, -q3), p3,
          fn=plot.turned_axes, **obj),
        C("plot.turned_axes q", "q", lambda v: plot.turned_axes(a6, v, q6), q6,
          fn=plot.turned_axes),
        C("plot.turned_axes q_other", "q_other", lambda v: plot.turned_axes(a6, q6, v), q6,
          fn=plot.turned_axes),
        C("plot.plot_view arm", "arm", lambda v: _drawn(plot.plot_view(v, q3)), p3,
          fn=plot.plot_view, slow=True, **obj),
        C("plot.plot_view q", "q", lambda v: _drawn(plot.plot_view(a6, v)), q6,
          fn=plot.plot_view, slow=True),
        C("plot.plot_view view", "view", lambda v: _drawn(plot.plot_view(a6, q6, view=v)), "yz",
          fn=plot.plot_view, slow=True, numeric=False, accept=_one_of("xz", "yz", "xy")),
        C("plot.plot_view ax", "ax", lambda v: _drawn(plot.plot_view(a6, q6, ax=v)), None,
          fn=plot.plot_view, slow=True, **opt_ax),
        C("plot.plot_view dimensions", "dimensions",
          lambda v: _drawn(plot.plot_view(a6, q6, dimensions=v)), True, fn=plot.plot_view,
          slow=True, **flag),
        C("plot.plot_view color", "color", lambda v: _drawn(plot.plot_view(a6, q6, color=v)),
          "k", fn=plot.plot_view, slow=True, numeric=False, accept=_colour, accepts_none=True),
        C("plot.plot_view title", "title", lambda v: _drawn(plot.plot_view(a6, q6, title=v)),
          "t", fn=plot.plot_view, slow=True, **opt_text),
        C("plot.plot_two_link_triangle L1", "L1",
          lambda v: _drawn(plot.plot_two_link_triangle(v, 10.0, [12.0, 5.0])), 10.0,
          fn=plot.plot_two_link_triangle, slow=True),
        C("plot.plot_two_link_triangle L2", "L2",
          lambda v: _drawn(plot.plot_two_link_triangle(10.0, v, [12.0, 5.0])), 10.0,
          fn=plot.plot_two_link_triangle, slow=True),
        C("plot.plot_two_link_triangle target_uv", "target_uv",
          lambda v: _drawn(plot.plot_two_link_triangle(10.0, 10.0, v)), [12.0, 5.0],
          fn=plot.plot_two_link_triangle, slow=True),
        C("plot.plot_two_link_triangle elbow", "elbow",
          lambda v: _drawn(plot.plot_two_link_triangle(10.0, 10.0, [12.0, 5.0], elbow=v)),
          "up", fn=plot.plot_two_link_triangle, slow=True, numeric=False,
          accept=_one_of("both", "up", "down")),
        C("plot.plot_two_link_triangle ax", "ax",
          lambda v: _drawn(plot.plot_two_link_triangle(10.0, 10.0, [12.0, 5.0], ax=v)), None,
          fn=plot.plot_two_link_triangle, slow=True, **opt_ax),
        C("plot.plot_two_link_triangle labels", "labels",
          lambda v: _drawn(plot.plot_two_link_triangle(10.0, 10.0, [12.0, 5.0], labels=v)),
          ("a", "b"), fn=plot.plot_two_link_triangle, slow=True, numeric=False,
          accept=_texts(2)),
        C("plot.plot_two_link_triangle angle_labels", "angle_labels",
          lambda v: _drawn(plot.plot_two_link_triangle(10.0, 10.0, [12.0, 5.0],
                                                       angle_labels=v)),
          ("a", "b", "c"), fn=plot.plot_two_link_triangle, slow=True, numeric=False,
          accept=_texts(3)),
        C("plot.plot_workspace_3d arm", "arm", lambda v: _drawn(plot.plot_workspace_3d(v, n=100)),
          a6, fn=plot.plot_workspace_3d, slow=True, **obj),
        C("plot.plot_workspace_3d ax", "ax",
          lambda v: _drawn(plot.plot_workspace_3d(a6, ax=v, n=100)), None,
          fn=plot.plot_workspace_3d, slow=True, **opt_ax),
        C("plot.plot_workspace_3d n", "n", lambda v: _drawn(plot.plot_workspace_3d(a6, n=v)), 100,
          fn=plot.plot_workspace_3d, slow=True),
        C("plot.plot_workspace_3d point", "point",
          lambda v: _drawn(plot.plot_workspace_3d(a6, n=100, point=v)), "wrist",
          fn=plot.plot_workspace_3d, slow=True, numeric=False, accept=_one_of("tcp", "wrist")),
        C("plot.plot_workspace_3d seed", "seed",
          lambda v: _drawn(plot.plot_workspace_3d(a6, n=100, seed=v)), 1,
          fn=plot.plot_workspace_3d, slow=True),
        C("plot.plot_workspace_3d q", "q",
          lambda v: _drawn(plot.plot_workspace_3d(a6, n=100, q=v)), q6, accepts_none=True,
          fn=plot.plot_workspace_3d, slow=True),
        C("plot.plot_workspace_planar arm", "arm", lambda v: _drawn(plot.plot_workspace_planar(v)),
          p3, fn=plot.plot_workspace_planar, slow=True, **obj),
        C("plot.plot_workspace_planar ax", "ax",
          lambda v: _drawn(plot.plot_workspace_planar(p3, ax=v)), None,
          fn=plot.plot_workspace_planar, slow=True, **opt_ax),
        C("plot.plot_workspace_planar n", "n",
          lambda v: _drawn(plot.plot_workspace_planar(p3, n=v)), 32,
          fn=plot.plot_workspace_planar, slow=True),
        C("plot.plot_wrist_centre arm", "arm", lambda v: _drawn(plot.plot_wrist_centre(v, q6)),
          a6, fn=plot.plot_wrist_centre, slow=True, **obj),
        C("plot.plot_wrist_centre q", "q", lambda v: _drawn(plot.plot_wrist_centre(a6, v)), q6,
          fn=plot.plot_wrist_centre, slow=True),
        C("plot.plot_wrist_centre ax", "ax",
          lambda v: _drawn(plot.plot_wrist_centre(a6, q6, ax=v)), None,
          fn=plot.plot_wrist_centre, slow=True, **opt_ax),
        C("plot.plot_wrist_centre title", "title",
          lambda v: _drawn(plot.plot_wrist_centre(a6, q6, title=v)), "t",
          fn=plot.plot_wrist_centre, slow=True, **opt_text),
        C("plot.same_joint_points arm", "arm", lambda v: plot.same_joint_points(v, res6.q), a6,
          fn=plot.same_joint_points, **obj),
        C("plot.same_joint_points Q", "Q", lambda v: plot.same_joint_points(a6, v), res6.q,
          fn=plot.same_joint_points),
        C("plot.gripper_path T_tcp", "T_tcp",
          lambda v: np.delete(plot.gripper_path(v, 1.0), 2, axis=0), T6, fn=plot.gripper_path),
        C("plot.gripper_path size", "size",
          lambda v: np.delete(plot.gripper_path(T6, v), 2, axis=0), 1.0, fn=plot.gripper_path),
        C("plot.gripper_path planar", "planar",
          lambda v: np.delete(plot.gripper_path(T6, 1.0, v), 2, axis=0), False,
          fn=plot.gripper_path, **flag),
        C("plot.joint_points arm", "arm", lambda v: plot.joint_points(v, F6), a6,
          fn=plot.joint_points, **obj),
        C("plot.joint_points F", "F", lambda v: plot.joint_points(a6, v), F6,
          fn=plot.joint_points),
        C("plot.link_path arm", "arm", lambda v: plot.link_path(v, F3), p3, fn=plot.link_path,
          **obj),
        C("plot.link_path F", "F", lambda v: plot.link_path(p3, v), F3, fn=plot.link_path),
        C("plot.wrist_centre arm", "arm", lambda v: plot.wrist_centre(v, F6), a6,
          fn=plot.wrist_centre, **obj),
        C("plot.wrist_centre F", "F", lambda v: plot.wrist_centre(a6, v), F6,
          fn=plot.wrist_centre),
        # rikin.interactive
        C("interactive.arm_figure arm", "arm", lambda v: _traces(interactive.arm_figure(v, q3)),
          p3, fn=interactive.arm_figure, slow=True, **obj),
        C("interactive.arm_figure q", "q", lambda v: _traces(interactive.arm_figure(a6, v)), q6,
          fn=interactive.arm_figure, slow=True),
        C("interactive.arm_figure frames", "frames",
          lambda v: _traces(interactive.arm_figure(p3, q3, frames=v)), True,
          fn=interactive.arm_figure, slow=True, **flag),
        C("interactive.arm_figure height", "height",
          lambda v: _traces(interactive.arm_figure(p3, q3, height=v)), 400,
          fn=interactive.arm_figure, slow=True),
        C("interactive.arm_figure title", "title",
          lambda v: _traces(interactive.arm_figure(p3, q3, title=v)), "t",
          fn=interactive.arm_figure, slow=True, **opt_text),
        C("interactive.solutions_figure arm", "arm",
          lambda v: _traces(interactive.solutions_figure(v, res2)), p2,
          fn=interactive.solutions_figure, slow=True, **obj),
        C("interactive.solutions_figure result", "result",
          lambda v: _traces(interactive.solutions_figure(p2, v)), res2.q,
          fn=interactive.solutions_figure, slow=True, accept=is_arm_ik),
        C("interactive.solutions_figure frames", "frames",
          lambda v: _traces(interactive.solutions_figure(p2, res2, frames=v)), True,
          fn=interactive.solutions_figure, slow=True, **flag),
        C("interactive.solutions_figure height", "height",
          lambda v: _traces(interactive.solutions_figure(p2, res2, height=v)), 400,
          fn=interactive.solutions_figure, slow=True),
        C("interactive.solutions_figure title", "title",
          lambda v: _traces(interactive.solutions_figure(p2, res2, title=v)), "t",
          fn=interactive.solutions_figure, slow=True, **opt_text),
        C("interactive.solutions_figure selected", "selected",
          lambda v: _traces(interactive.solutions_figure(p2, res2, selected=v)), 2,
          fn=interactive.solutions_figure, slow=True),
        C("interactive.path_figure arm", "arm",
          lambda v: _traces(interactive.path_figure(v, [[15.0, 5.0], [14.0, 6.0]])), p2,
          fn=interactive.path_figure, slow=True, **obj),
        C("interactive.path_figure targets", "targets",
          lambda v: _traces(interactive.path_figure(p2, v)), [[15.0, 5.0], [14.0, 6.0]],
          fn=interactive.path_figure, slow=True),
        C("interactive.path_figure frames", "frames",
          lambda v: _traces(interactive.path_figure(p2, [[15.0, 5.0], [14.0, 6.0]], frames=v)),
          True, fn=interactive.path_figure, slow=True, **flag),
        C("interactive.path_figure height", "height",
          lambda v: _traces(interactive.path_figure(p2, [[15.0, 5.0], [14.0, 6.0]], height=v)),
          400, fn=interactive.path_figure, slow=True),
        C("interactive.path_figure title", "title",
          lambda v: _traces(interactive.path_figure(p2, [[15.0, 5.0], [14.0, 6.0]], title=v)),
          "t", fn=interactive.path_figure, slow=True, **opt_text),
        C("interactive.path_figure step_labels", "step_labels",
          lambda v: _traces(interactive.path_figure(p2, [[15.0, 5.0], [14.0, 6.0]],
                                                    step_labels=v)),
          ("a", "b"), fn=interactive.path_figure, slow=True, numeric=False, accept=_texts(2),
          accepts_none=True),
        # rikin.widgets
        C("dhtext.row_tokens line", "line", lambda v: len(dhtext.row_tokens(v)), "R 0 1 0",
          fn=dhtext.row_tokens, **text),
        C("interactive.InteractiveFigure.to_html div_id", "div_id",
          lambda v: len(fig2.to_html(v)), "later", fn=interactive.InteractiveFigure.to_html,
          **opt_text),
        C("widgets.arm_from_table text", "table", widgets.arm_from_table, "R 0 1 0\nR 0 1 0",
          fn=widgets.arm_from_table, numeric=False, param="text",
          accept=lambda v: isinstance(v, str) and v.strip() != ""),
        C("widgets.arm_from_table convention", "convention",
          lambda v: widgets.arm_from_table("R 0 1 0", convention=v), "modified",
          fn=widgets.arm_from_table, numeric=False, accept=_one_of("standard", "modified")),
        C("widgets.arm_from_table units", "units",
          lambda v: widgets.arm_from_table("R 0 1 0", units=v), "mm",
          fn=widgets.arm_from_table, **text),
        C("widgets.arm_from_table name", "name",
          lambda v: widgets.arm_from_table("R 0 1 0", name=v), "mine",
          fn=widgets.arm_from_table, **text),
        C("widgets.arm_from_table tool", "tool",
          lambda v: widgets.arm_from_table("R 0 1 0", tool=v), np.eye(4), accepts_none=True,
          fn=widgets.arm_from_table),
        C("widgets.arm_from_table base", "base",
          lambda v: widgets.arm_from_table("R 0 1 0", base=v), np.eye(4), accepts_none=True,
          fn=widgets.arm_from_table),
        C("widgets.dh_panel table", "table", lambda v: _panel(widgets.dh_panel(v)),
          widgets.PUMA560_TABLE, fn=[widgets.dh_panel, widgets.DHPanel], slow=True, **text),
        C("widgets.dh_panel convention", "convention",
          lambda v: _panel(widgets.dh_panel(convention=v)), "standard",
          fn=[widgets.dh_panel, widgets.DHPanel], slow=True, numeric=False,
          accept=_one_of("standard", "modified")),
        C("widgets.dh_panel units", "units", lambda v: _panel(widgets.dh_panel(units=v)), "m",
          fn=[widgets.dh_panel, widgets.DHPanel], slow=True, **text),
        C("widgets.dh_panel target", "target", lambda v: _panel(widgets.dh_panel(target=v)),
          [20.0, -30.0, 40.0, 10.0, 50.0, 60.0], fn=[widgets.dh_panel, widgets.DHPanel],
          slow=True, accept=_text),
        C("widgets.dh_panel mode", "mode", lambda v: _panel(widgets.dh_panel(mode=v)), "pose",
          fn=[widgets.dh_panel, widgets.DHPanel], slow=True, numeric=False,
          accept=_one_of("joints", "pose")),
        C("widgets.dh_panel tool", "tool", lambda v: _panel(widgets.dh_panel(tool=v)),
          [0.0, 0.0, 0.1], fn=[widgets.dh_panel, widgets.DHPanel], slow=True, accept=_text),
        C("widgets.dh_panel name", "name", lambda v: _panel(widgets.dh_panel(name=v)), "mine",
          fn=[widgets.dh_panel, widgets.DHPanel], slow=True, **text),
        C("widgets.DHPanel.set redraw", "redraw", lambda v: widgets.DHPanel().set(redraw=v),
          False, fn=widgets.DHPanel.set, slow=True, **flag),
        C("widgets.IKPanel.set redraw", "redraw", lambda v: widgets.IKPanel(p2).set(redraw=v),
          False, fn=widgets.IKPanel.set, slow=True, **flag),
        C("widgets.TeachPanel.set redraw", "redraw",
          lambda v: widgets.TeachPanel(p3).set(redraw=v), False, fn=widgets.TeachPanel.set,
          **flag),
        C("widgets.DHPanel width", "width", lambda v: widgets.DHPanel(width=v), 10.0,
          fn=widgets.DHPanel, slow=True),
        C("widgets.DHPanel.set", "target", lambda v: _panel(_set(widgets.DHPanel(), target=v)),
          [20.0, -30.0, 40.0, 10.0, 50.0, 60.0], fn=widgets.DHPanel.set, slow=True,
          accept=_text),
        C("widgets.DHPanel.static_html", "alt", lambda v: unread.static_html(v), "a",
          fn=widgets.DHPanel.static_html, slow=True, **text),
        C("widgets.pose_sliders_for", "arm", widgets.pose_sliders_for, a6,
          fn=widgets.pose_sliders_for, **obj),
        C("widgets.ik_panel arm", "arm", widgets.ik_panel, p2,
          fn=[widgets.ik_panel, widgets.IKPanel], slow=True, **obj),
        C("widgets.ik_panel x", "x", lambda v: widgets.ik_panel(p2, x=v), 12.0,
          fn=[widgets.ik_panel, widgets.IKPanel.set], slow=True),
        C("widgets.IKPanel values", "values", lambda v: widgets.IKPanel(p2, v),
          {"x": 12.0, "y": 3.0}, accepts_none=True, fn=widgets.IKPanel, slow=True,
          numeric=False, accept=lambda v: isinstance(v, dict) and set(v) <= {"x", "y"}
          and all(isinstance(e, float) for e in v.values())),
        C("widgets.IKPanel width", "width", lambda v: widgets.IKPanel(p2, width=v), 8.0,
          fn=widgets.IKPanel, slow=True),
        C("widgets.IKPanel.values_of", "T", lambda v: widgets.IKPanel(a6).values_of(v), T6,
          fn=widgets.IKPanel.values_of, slow=True),
        C("widgets.teach arm", "arm", widgets.teach, p3, fn=[widgets.teach, widgets.TeachPanel],
          **obj),
        C("widgets.teach q", "q", lambda v: widgets.teach(p3, v), q3, accepts_none=True,
          fn=[widgets.teach, widgets.TeachPanel]),
        C("widgets.TeachPanel width", "width", lambda v: widgets.TeachPanel(p3, width=v), 5.0,
          fn=widgets.TeachPanel),
        C("widgets.TeachPanel.set", "q2", lambda v: _set(widgets.TeachPanel(p3), False, q2=v),
          30.0, fn=widgets.TeachPanel.set),
        C("widgets.IKPanel.set", "y", lambda v: _set(widgets.IKPanel(p2), False, y=v), 3.0,
          fn=widgets.IKPanel.set, slow=True),
        # rikin.i18n
        C("i18n.set_language", "language", _in_language, "es", fn=rikin.i18n.set_language,
          accepts_none=True, numeric=False,
          accept=lambda v: isinstance(v, str) and v.strip().lower() in rikin.i18n.LANGUAGES),
        # rikin.tables
        C("tables.table header", "header", lambda v: str(tables.table(v, [[1.0, 2.0]])),
          ["a", "b"], fn=[tables.table, tables.Table], numeric=False, accept=_texts(2)),
        C("tables.table rows", "rows", lambda v: str(tables.table(["a", "b"], v)),
          [[1.0, 2.0], [3.0, 4.0]], fn=[tables.table, tables.Table], accept=_rows(2)),
        C("tables.table decimals", "decimals",
          lambda v: str(tables.table(["a"], [[1.25]], decimals=v)), 2,
          fn=[tables.table, tables.Table]),
        C("tables.table caption", "caption",
          lambda v: str(tables.table(["a"], [[1.25]], caption=v)), "c",
          fn=[tables.table, tables.Table], **opt_text),
        C("tables.Table rows", "rows", lambda v: str(tables.Table(["a", "b"], v)),
          [[1.0, 2.0]], fn=tables.Table, accept=_rows(2)),
        C("tables.dh_table arm", "arm", lambda v: str(tables.dh_table(v)), a6,
          fn=tables.dh_table, **obj),
        C("tables.dh_table decimals", "decimals", lambda v: str(tables.dh_table(a6, v)), 3,
          fn=tables.dh_table),
        C("tables.solutions_table result", "result",
          lambda v: str(tables.solutions_table(v)), res2, fn=tables.solutions_table,
          numeric=False, accept=lambda v: isinstance(v, rikin.IKResult)),
        C("tables.solutions_table decimals", "decimals",
          lambda v: str(tables.solutions_table(res2, v)), 3, fn=tables.solutions_table),
        C("tables.solutions_table caption", "caption",
          lambda v: str(tables.solutions_table(res2, caption=v)), "c",
          fn=tables.solutions_table, **opt_text),
        C("tables.solutions_table units", "units",
          lambda v: str(tables.solutions_table(res2, units=v)), "mm",
          fn=tables.solutions_table, **text),
        C("tables.solutions_table arm", "arm",
          lambda v: str(tables.solutions_table(res2, arm=v)), p2, accepts_none=True,
          fn=tables.solutions_table, **obj),
        C("tables.dh_table limits", "limits", lambda v: str(tables.dh_table(a6, limits=v)),
          True, fn=tables.dh_table, **flag),
        # rikin.symbolic
        C("symbolic.dh_matrix theta", "theta", lambda v: symbolic.dh_matrix(v, 1, 2, 0.5),
          0.3, symbolic=True, fn=symbolic.dh_matrix),
        C("symbolic.dh_matrix d", "d", lambda v: symbolic.dh_matrix(q_sym, v, 2, 0.5),
          1.0, symbolic=True, fn=symbolic.dh_matrix),
        C("symbolic.dh_matrix a", "a", lambda v: symbolic.dh_matrix(q_sym, 1, v, 0.5),
          2.0, symbolic=True, fn=symbolic.dh_matrix),
        C("symbolic.dh_matrix alpha", "alpha", lambda v: symbolic.dh_matrix(q_sym, 1, 2, v),
          0.5, symbolic=True, fn=symbolic.dh_matrix),
        C("symbolic.dh_matrix convention", "convention",
          lambda v: symbolic.dh_matrix(q_sym, 1, 2, 0.5, v), "modified",
          fn=symbolic.dh_matrix, numeric=False, accept=_one_of("standard", "modified")),
        C("symbolic.joint_symbols links", "links", symbolic.joint_symbols, links2,
          fn=symbolic.joint_symbols, numeric=False,
          accept=_links),
        C("symbolic.joint_symbols revolute", "revolute",
          lambda v: symbolic.joint_symbols(links2, v), "theta", fn=symbolic.joint_symbols,
          numeric=False, accept=lambda v: isinstance(v, str) and v.isalpha() and v.isascii()),
        C("symbolic.joint_symbols prismatic", "prismatic",
          lambda v: symbolic.joint_symbols(links2, prismatic=v), "s", fn=symbolic.joint_symbols,
          numeric=False, accept=lambda v: isinstance(v, str) and v.isalpha() and v.isascii()),
        C("symbolic.link_matrix link", "link", lambda v: symbolic.link_matrix(v, q_sym),
          links2[0], fn=symbolic.link_matrix, numeric=False,
          accept=lambda v: isinstance(v, rikin.Link)),
        C("symbolic.link_matrix q_symbol", "q_symbol",
          lambda v: symbolic.link_matrix(links2[0], v), 0.3, fn=symbolic.link_matrix,
          symbolic=True),
        C("symbolic.link_matrix convention", "convention",
          lambda v: symbolic.link_matrix(links2[0], q_sym, v), "modified",
          fn=symbolic.link_matrix, numeric=False, accept=_one_of("standard", "modified")),
        C("symbolic.transform links", "links", lambda v: symbolic.transform(v, simplify=False),
          links2, fn=symbolic.transform, numeric=False,
          accept=_links),
        C("symbolic.transform convention", "convention",
          lambda v: symbolic.transform(links2, v, simplify=False), "modified",
          fn=symbolic.transform, accepts_none=True, numeric=False,
          accept=_one_of("standard", "modified")),
        C("symbolic.transform start", "start",
          lambda v: symbolic.transform(links2, start=v, simplify=False), 1,
          fn=symbolic.transform),
        C("symbolic.transform end", "end",
          lambda v: symbolic.transform(links2, end=v, simplify=False), 1, accepts_none=True,
          fn=symbolic.transform),
        C("symbolic.transform q", "q", lambda v: symbolic.transform(links2, q=v, simplify=False),
          [0.3, 0.2], accepts_none=True, symbolic=True, fn=symbolic.transform),
        C("symbolic.transform simplify", "simplify",
          lambda v: symbolic.transform(links2, simplify=v), False, fn=symbolic.transform,
          slow=True, **flag),
        C("symbolic.rotation links", "links", lambda v: symbolic.rotation(v, simplify=False),
          links2, fn=symbolic.rotation, numeric=False,
          accept=_links),
        C("symbolic.rotation convention", "convention",
          lambda v: symbolic.rotation(links2, v, simplify=False), "modified",
          fn=symbolic.rotation, accepts_none=True, numeric=False,
          accept=_one_of("standard", "modified")),
        C("symbolic.rotation start", "start",
          lambda v: symbolic.rotation(links2, start=v, simplify=False), 1,
          fn=symbolic.rotation),
        C("symbolic.rotation q", "q", lambda v: symbolic.rotation(links2, q=v, simplify=False),
          [0.3, 0.2], accepts_none=True, symbolic=True, fn=symbolic.rotation),
        C("symbolic.rotation simplify", "simplify",
          lambda v: symbolic.rotation(links2, simplify=v), False, fn=symbolic.rotation,
          slow=True, **flag),
        C("symbolic.latex_short joints", "joints", lambda v: symbolic.latex_short(expr, v),
          (q_sym,), accepts_none=True, fn=symbolic.latex_short, numeric=False,
          accept=lambda v: isinstance(v, (list, tuple)) and all(
              isinstance(e, sympy.Symbol) for e in v)),
        C("symbolic.rotation end", "end",
          lambda v: symbolic.rotation(links2, end=v, simplify=False), 1, accepts_none=True,
          fn=symbolic.rotation),
        C("symbolic.simplify_trig", "expr", symbolic.simplify_trig, expr,
          fn=symbolic.simplify_trig, numeric=False, accept=_expression, slow=True),
        C("symbolic.abbreviate expr", "expr", symbolic.abbreviate, expr, fn=symbolic.abbreviate,
          numeric=False, accept=_expression),
        C("symbolic.abbreviate joints", "joints", lambda v: symbolic.abbreviate(expr, v),
          (q_sym,), accepts_none=True, fn=symbolic.abbreviate, numeric=False,
          accept=lambda v: isinstance(v, (list, tuple)) and all(
              isinstance(e, sympy.Symbol) for e in v)),
        C("symbolic.short_trig", "expr", symbolic.short_trig, expr, fn=symbolic.short_trig,
          numeric=False, accept=_expression),
        C("symbolic.short_trig joints", "joints", lambda v: symbolic.short_trig(expr, v),
          (q_sym,), accepts_none=True, fn=symbolic.short_trig, numeric=False,
          accept=lambda v: isinstance(v, (list, tuple)) and all(
              isinstance(e, sympy.Symbol) for e in v)),
        C("symbolic.latex_short", "expr", symbolic.latex_short, expr, fn=symbolic.latex_short,
          numeric=False, accept=_expression),
        C("symbolic.numeric expr", "expr_or_matrix", lambda v: symbolic.numeric(v, {}),
          sympy.Matrix([[1, 2]]), fn=symbolic.numeric, numeric=False, accept=_expression),
        C("symbolic.numeric subs", "subs",
          lambda v: symbolic.numeric(expr, v), {"l": 2.0, "q1": 0.3}, fn=symbolic.numeric,
          numeric=False, accept=lambda v: isinstance(v, dict) and set(map(str, v)) == {
              "l", "q1"} and all(float_equivalent(e) is not None for e in v.values())),
        C("symbolic.numeric subs value", "q1",
          lambda v: symbolic.numeric(expr, {"l": 2.0, "q1": v}), 0.3, fn=symbolic.numeric,
          param="subs"),
        C("symbolic.lesson_arm", "name", symbolic.lesson_arm, "planar_2r",
          fn=symbolic.lesson_arm, numeric=False, accept=lambda v: v in robots.LESSON_ROBOTS),
        C("symbolic.lesson_arm options", "theta1",
          lambda v: symbolic.lesson_arm("pprrr", theta1=v), 0.5, fn=symbolic.lesson_arm,
          symbolic=True, accepts_none=True),
        C("symbolic.LessonArm[index]", "index", lambda v: symbolic.lesson_arm("planar_2r")[v], 0,
          fn=symbolic.LessonArm.__getitem__, param="key", numeric=False, accept=_index(4, False)),
        # indexing the results: a sequence of solutions (IKResult), tuples of labels (Branch),
        # records that are no sequence (BatchIKResult, NumericalIKResult)
        C("IKResult[index]", "index", lambda v: res6[v], 0, fn=rikin.IKResult.__getitem__,
          param="key", numeric=False, accept=_index(len(res6))),
        C("Branch[index]", "index", lambda v: res6.branches[0][v], 0, fn=rikin.Branch.__getitem__,
          param="key", numeric=False, accept=_index(4, False)),
        C("BatchIKResult[index]", "index", lambda v: a6.ik_batch(T6[None])[v], None,
          fn=rikin.BatchIKResult.__getitem__, param="key", numeric=False, accept=lambda v: False),
        C("BatchIKResult.labels", "index", lambda v: a6.ik_batch(T6[None]).labels(v), 0,
          fn=rikin.BatchIKResult.labels, param="i", numeric=False, accept=_index(1, False)),
        C("NumericalIKResult[index]", "index", lambda v: num6[v], None,
          fn=rikin.ik.numerical.NumericalIKResult.__getitem__, param="key", numeric=False,
          accept=lambda v: False),
        # rikin.ik: classify, the general 6R solver through an arm typed as a DH table
        C("ik.classify", "arm", rikin.ik.classify, puma, fn=rikin.ik.classify, **obj),
        C("ik.pieper.general_solver", "arm", pieper.general_solver, puma,
          fn=pieper.general_solver, **obj),
        C("ik.pieper.Pieper6RSolver", "arm", pieper.Pieper6RSolver, puma,
          fn=pieper.Pieper6RSolver, **obj),
        C("ik.pieper.classify", "arm", pieper.classify, puma, fn=pieper.classify, **obj),
        C("ik.families6r.solver_for", "arm", families6r.solver_for, ur5,
          fn=families6r.solver_for, **obj),
        C("ik.parallel3.recognise", "arm", parallel3.recognise, ur5, fn=parallel3.recognise,
          **obj),
        C("ik.parallel3.ParallelAxesSolver", "arm", parallel3.ParallelAxesSolver, ur5,
          fn=parallel3.ParallelAxesSolver, **obj),
        C("ik.general6r.recognise", "arm", general6r.recognise, skew, fn=general6r.recognise,
          **obj),
        C("ik.general6r.General6RSolver", "arm", general6r.General6RSolver, skew,
          fn=general6r.General6RSolver, **obj),
        C("ur5 (user-built).ik", "target", ur5.ik, ur5.fk(np.full(6, 0.3)), fn=SA.ik),
        C("general 6R (user-built).ik", "target", skew.ik, skew.fk(np.full(6, 0.3)), fn=SA.ik),
        C("four-axis SCARA (user-built).ik", "target", scara4.ik, scara4.fk(np.full(4, 0.3)),
          fn=SA.ik),
        C("four-axis SCARA (user-built).ik_batch", "T", scara4.ik_batch,
          scara4.fk(np.full(4, 0.3))[None], fn=SA.ik_batch),
        C("four-axis articulated arm (user-built).ik", "target", pitched.ik,
          pitched.fk(np.full(4, 0.3)), fn=SA.ik),
        C("puma (user-built).ik", "target", puma.ik, Tp, fn=SA.ik),
        C("puma (user-built).ik_batch", "T", puma.ik_batch, Tp[None], fn=SA.ik_batch),
        C("ik.solve within_limits", "within_limits",
          lambda v: rikin.ik.solve(p2, [15.0, 5.0], within_limits=v), True, fn=rikin.ik.solve,
          **flag),
        C("ik.solve near", "near", lambda v: rikin.ik.solve(p2, [15.0, 5.0], near=v), [0.1, 0.2],
          accepts_none=True, fn=rikin.ik.solve),
        C("ik.solve_batch chunk_size", "chunk_size",
          lambda v: rikin.ik.solve_batch(a6, T6[None], chunk_size=v), 16,
          fn=rikin.ik.solve_batch),
        C("ik.solve_batch workers", "workers",
          lambda v: rikin.ik.solve_batch(a6, T6[None], workers=v), 1, accepts_none=True,
          fn=rikin.ik.solve_batch),
        C("ClosedForm.ik arm", "arm", lambda v: a6.solver.ik(v, T6), a6, fn=api.ClosedForm.ik,
          **obj),
        C("ClosedForm.ik_batch arm", "arm", lambda v: a6.solver.ik_batch(v, T6[None]), a6,
          fn=api.ClosedForm.ik_batch, **obj),
        C("ik_numerical_multistart arm", "arm",
          lambda v: ik_numerical_multistart(v, T6, 2, max_iter=5), a6,
          fn=ik_numerical_multistart, **obj),
        C("ik.solve target", "target", lambda v: rikin.ik.solve(p2, v), [15.0, 5.0],
          fn=rikin.ik.solve),
        C("ik.solve_batch arm", "arm", lambda v: rikin.ik.solve_batch(v, T6[None]), a6,
          fn=rikin.ik.solve_batch, **obj),
        C("ik.solve_batch T", "T", lambda v: rikin.ik.solve_batch(a6, v), T6[None],
          fn=rikin.ik.solve_batch),
        C("ClosedForm.ik", "target", lambda v: a6.solver.ik(a6, v), T6, fn=api.ClosedForm.ik),
        C("ClosedForm.ik_batch", "T", lambda v: a6.solver.ik_batch(a6, v), T6[None],
          fn=api.ClosedForm.ik_batch),
        C("ik_numerical method", "method", lambda v: ik_numerical(a6, T6, method=v, max_iter=5),
          "lm", fn=ik_numerical, numeric=False, accept=_one_of("lm", "gn", "dls", "newton")),
        C("ik_numerical max_iter", "max_iter", lambda v: ik_numerical(a6, T6, max_iter=v), 5,
          fn=ik_numerical),
        C("ik_numerical rng", "rng", lambda v: ik_numerical(a6, T6, rng=v, max_iter=5), 1,
          accepts_none=True, fn=ik_numerical),
        C("ik_numerical within_limits", "within_limits",
          lambda v: ik_numerical(a6, T6, within_limits=v, max_iter=5), True, fn=ik_numerical,
          **flag),
        C("ik_numerical_multistart within_limits", "within_limits",
          lambda v: ik_numerical_multistart(a6, T6, 2, within_limits=v, max_iter=5), True,
          fn=ik_numerical_multistart, **flag),
        C("ik_numerical_multistart T", "T",
          lambda v: ik_numerical_multistart(a6, v, 2, max_iter=5), T6,
          fn=ik_numerical_multistart),
        C("ik_numerical_multistart rng", "rng",
          lambda v: ik_numerical_multistart(a6, T6, 2, v, max_iter=5), 1, accepts_none=True,
          fn=ik_numerical_multistart),
        C("ik_numerical_multistart distinct_tol", "distinct_tol",
          lambda v: ik_numerical_multistart(a6, T6, 2, distinct_tol=v, max_iter=5), 1e-6,
          fn=ik_numerical_multistart),
        C("pose_error arm", "arm", lambda v: pose_error(v, q6, T6), a6, fn=pose_error, **obj),
        # rikin.dh: what the first part leaves out
        C("SerialArm units", "units", lambda v: SA((rikin.Link(a=1.0),), units=v), "mm",
          fn=SA, **text),
        C("SerialArm name", "name", lambda v: SA((rikin.Link(a=1.0),), name=v), "mine",
          fn=SA, **text),
        C("SerialArm solver", "solver", lambda v: SA((rikin.Link(a=1.0),), solver=v), None,
          fn=SA, **opt_ax),
        C("SerialArm.replace", "base", lambda v: a6.replace(base=v), np.eye(4), fn=SA.replace),
        C("SerialArm.replace name", "name", lambda v: a6.replace(name=v), "x", fn=SA.replace,
          **text),
        C("SerialArm.check_q q", "q", a6.check_q, q6, fn=SA.check_q),
        C("SerialArm.check_q name", "name", lambda v: a6.check_q(q6, v), "qq",
          fn=SA.check_q, **text),
        C("SerialArm.check_q check_degrees", "check_degrees",
          lambda v: a6.check_q(q6, check_degrees=v), True, fn=SA.check_q, **flag),
        C("SerialArm.fk frames", "frames", lambda v: a6.fk(q6, frames=v), False, fn=SA.fk,
          **flag),
        C("SerialArm.fk check_degrees", "check_degrees",
          lambda v: a6.fk(q6, check_degrees=v), True, fn=SA.fk, **flag),
        C("Link joint", "joint", lambda v: rikin.Link(joint=v), "P", fn=rikin.Link,
          numeric=False, accept=_one_of("R", "P")),
        C("Link theta", "theta", lambda v: rikin.Link("P", theta=v), 0.5, symbolic=True,
          fn=rikin.Link),
        # rikin.transforms: the keywords the first part leaves out
        C("transforms.troty", "theta", rikin.transforms.troty, 0.3, fn=rikin.transforms.troty),
        C("transforms.trotz", "theta", rikin.transforms.trotz, 0.3, fn=rikin.transforms.trotz),
        C("transl z", "z", lambda v: rikin.transl(1.0, 2.0, v), 0.5, fn=rikin.transl,
          accepts_none=True),  # transl(x, y) is in the xy plane
        C("r_to_rpy degrees", "degrees", lambda v: rikin.r_to_rpy(rikin.rotz(0.3), degrees=v),
          True, fn=rikin.r_to_rpy, **flag),
        C("zyz_to_r phi", "phi", lambda v: rikin.zyz_to_r(v, 0.2, 0.3), 0.1, fn=rikin.zyz_to_r),
        C("zyz_to_r psi", "psi", lambda v: rikin.zyz_to_r(0.1, 0.2, v), 0.3, fn=rikin.zyz_to_r),
        C("zyz_to_r degrees", "degrees", lambda v: rikin.zyz_to_r(10, 20, 30, degrees=v), True,
          fn=rikin.zyz_to_r, **flag),
        C("r_to_zyz degrees", "degrees",
          lambda v: rikin.r_to_zyz(rikin.rotx(0.3), degrees=v), True, fn=rikin.r_to_zyz, **flag),
        C("rpy_to_r pitch", "pitch", lambda v: rikin.rpy_to_r(0.3, v, 0.2), 0.1,
          fn=rikin.rpy_to_r),
        C("robots.epson_c4 units", "units", lambda v: robots.epson_c4(units=v), "mm",
          fn=robots.epson_c4, **text),
        C("robots.epson_c4_links limits", "limits", lambda v: robots.epson_c4_links(limits=v),
          True, fn=robots.epson_c4_links, **flag),
    ]
    for make in (robots.kuka_kr5_arc, robots.fanuc_lrmate200id):
        name = f"robots.{make.__name__}"
        cases += [
            C(f"{name} limits", "limits", lambda v, mk=make: mk(limits=v), True, fn=make, **flag),
            C(f"{name} base", "base", lambda v, mk=make: mk(base=v), np.eye(4),
              accepts_none=True, fn=make),
            C(f"{name} tool", "tool", lambda v, mk=make: mk(tool=v), np.eye(4),
              accepts_none=True, fn=make),
        ]
    # the lesson robots' DH rows, one length at a time (sympy lengths are documented input)
    import inspect

    for rname in robots.LESSON_ROBOTS:
        make = getattr(robots, f"{rname}_links")
        for p in inspect.signature(make).parameters.values():
            if p.name == "limits":
                continue
            valid = p.default if p.default is not None else 0.5
            cases.append(C(f"robots.{rname}_links({p.name}=...)", p.name,
                           lambda v, mk=make, n=p.name: mk(**{n: v}), valid, symbolic=True,
                           accepts_none=p.default is None, fn=make))
    return cases


def _set(panel: Any, redraw: bool = True, **values: Any) -> Any:
    panel.set(redraw=redraw, **values)
    return panel


CASES = {c.name: c for c in _cases() + _api_cases()}


def _check(case: Case, value: Any) -> None:
    equiv = float_equivalent(value) if case.numeric else None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            result = case.call(value)
        except (InputError, UnreachableError) as exc:
            msg = str(exc)
            assert re.search(rf"(?<![A-Za-z_]){re.escape(case.arg)}(?![A-Za-z_])", msg) or (
                isinstance(exc, UnreachableError)
            ), f"{case.name}: the message does not name {case.arg!r}: {msg}"
            assert "rikin bug" not in msg
            return
        finally:
            plt.close("all")
    # returned: right only for a plainly numeric value (or None where None is the default)
    assert value is not None or case.accepts_none or case.valid is None and case.numeric, (
        f"{case.name} accepted {value!r}"
    )
    if value is None:
        return
    if case.accept is not None and case.accept(value):
        assert _finite(result), f"{case.name}({value!r}) returned NaN or infinity"
        return
    assert case.numeric, f"{case.name} accepted {_short(value)} and returned {_short(result)}"
    if case.symbolic and isinstance(value, sympy.Basic):
        return
    if isinstance(case.valid, (bool, int)) and isinstance(value, (bool, np.bool_, int, np.integer)):
        return  # a flag given as a flag, a count given as a count
    assert equiv is not None, (
        f"{case.name} accepted the non-number {_short(value)} and returned {_short(result)}"
    )
    if case.nan_in_nan_out and equiv is not None and not np.isfinite(equiv).all():
        got = np.asarray(result, dtype=float)
        assert np.array_equal(np.isnan(got), ~np.isfinite(equiv)), f"{case.name}({value!r})"
        return
    assert _finite(result), f"{case.name}({value!r}) returned NaN or infinity"
    if equiv is not None and equiv.dtype == np.float64:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            try:
                clean = case.call(equiv if equiv.ndim else float(equiv))
            finally:
                plt.close("all")
        assert _same(result, clean), f"{case.name}({value!r}) differs from the float64 call"


def _short(x: Any) -> str:
    text = repr(x)
    return text if len(text) <= 200 else text[:197] + "..."


@pytest.mark.parametrize("name", sorted(n for n, c in CASES.items() if not c.slow))
@settings(max_examples=EXAMPLES, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_every_public_boundary_raises_rikins_own_errors(name, data):
    case = CASES[name]
    value = data.draw(bad_values(case.valid if case.valid is not None else 0.0), label=case.arg)
    _check(case, value)


@pytest.mark.parametrize("name", sorted(n for n, c in CASES.items() if c.slow))
@settings(max_examples=EXAMPLES_SLOW, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_drawings_and_panels_raise_rikins_own_errors(name, data):
    case = CASES[name]
    value = data.draw(bad_values(case.valid if case.valid is not None else 0.0), label=case.arg)
    _check(case, value)


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_valid_value_passes(name):
    case = CASES[name]
    if case.valid is None:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        case.call(case.valid)


def test_issue_examples():
    for bad in (None, "10", 1 + 1j, sympy.Symbol("l")):
        with pytest.raises(InputError, match="l1"):
            robots.planar_2r(bad)
    assert np.allclose(robots.planar_2r(sympy.Integer(10)).fk([0.1, 0.2]),
                       robots.planar_2r(10.0).fk([0.1, 0.2]))
    with pytest.raises(InputError, match="d4"):
        robots.epson_c4(d4=0)
    arm = ARMS["aula10_6r"]
    with pytest.raises(InputError, match="chunk_size"):
        arm.ik_batch(np.eye(4)[None], chunk_size=2.0)
    with pytest.raises(InputError, match="qlim"):
        rikin.Link(qlim=1.0)
    with pytest.raises(InputError, match="theta"):
        rikin.wrap_angle("x")
    with pytest.raises(InputError, match="T_0_6"):
        arm.solver.steps(arm, np.eye(3))
    with pytest.raises(InputError, match=r"\bT\b"):
        pose_error(arm, np.zeros(6), np.eye(3))
    with pytest.raises(InputError, match="complex"):
        arm.fk(np.zeros(6) + 0j)
    with pytest.raises(InputError, match="text"):
        arm.fk(np.array(["0"] * 6))


# ------------------------------------------------------------------ nothing public escapes
#: Public callables with a user-facing argument that have no fuzz case, and why. Callables
#: whose only argument is ``self`` (``DHPanel.compute``, ``plotly_js``...) take no input and
#: need no entry.
NOT_FUZZED = {
    "rikin.errors.RikinError": "an exception: rikin builds it with its message",
    "rikin.errors.InputError": "an exception: rikin builds it with its message",
    "rikin.errors.IKError": "an exception: rikin builds it with its message",
    "rikin.errors.UnreachableError": "an exception: rikin builds it with its message",
    "rikin.errors.OutOfRangeError": "an exception: rikin builds it with its message",
    "rikin.errors.NotIndexedError": "an exception: rikin builds it with its message",
    "rikin.ik.result.IKResult": "a result record rikin builds (its table() is fuzzed)",
    "rikin.ik.result.BatchIKResult": "a result record rikin builds",
    "rikin.ik.result.Branch": "a result record rikin builds (a named tuple of labels)",
    "rikin.ik.numerical.NumericalIKResult": "a result record rikin builds",
    "rikin.ik.pieper.IKClass": "a result record classify() builds",
    "rikin.ik.families6r.Family": "a record of the family list rikin builds",
    "rikin.ik.families6r.Match": "a record the recognisers build",
    "rikin.ik.parallel3.reversed_model": "takes the ChainModel rikin builds from a checked arm",
    "rikin.ik.parallel3.ParallelAxesSolver.check": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.parallel3.ParallelAxesSolver.solve": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.parallel3.ParallelAxesSolver.explain": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.parallel3.ParallelAxesSolver.batch_kernel": "solver protocol, as "
    "Pieper6RSolver.check (fuzzed through SerialArm.ik_batch)",
    "rikin.ik.general6r.General6RSolver.check": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.general6r.General6RSolver.solve": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.general6r.General6RSolver.explain": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.general6r.General6RSolver.single_kernel": "solver protocol, as "
    "Pieper6RSolver.check",
    "rikin.ik.general6r_kernel.General6RKernel": "the one-pose kernel rikin.ik.solve builds "
    "from a solver it made (fuzzed through SerialArm.ik of a general 6R typed as a table)",
    "rikin.ik.general6r_kernel.General6RKernel.solve": "one-pose kernel on the validated "
    "pose, as General6RKernel",
    "rikin.symbolic.LessonArm": "a result record lesson_arm() builds",
    "rikin.interactive.InteractiveFigure": "wraps the plotly figure arm_figure() & co. build",
    "rikin.ik.pieper.Pieper6RSolver.check": "solver protocol: rikin.ik.solve calls it on "
    "validated input (fuzzed through SerialArm.ik and ik_batch of an arm typed as a table)",
    "rikin.ik.pieper.Pieper6RSolver.solve": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.pieper.Pieper6RSolver.explain": "solver protocol, as Pieper6RSolver.check",
    "rikin.ik.pieper.Pieper6RSolver.nearest_reachable": "solver protocol, as "
    "Pieper6RSolver.check (rikin.ik.solve calls it on validated poses)",
    "rikin.ik.pieper.Pieper6RSolver.single_kernel": "solver protocol, as "
    "Pieper6RSolver.check",
    "rikin.ik.fkcheck.FKCheck": "the one-pose path's FK check, which rikin.ik.solve builds "
    "for an arm it solved (fuzzed through SerialArm.ik of every robot and typed table)",
    "rikin.ik.pieper_kernel.PieperKernel": "the one-pose kernel rikin.ik.solve builds from "
    "a solver it made (fuzzed through SerialArm.ik of an arm typed as a table)",
    "rikin.ik.pieper_kernel.PieperKernel.solve": "one-pose kernel on the validated pose, "
    "as PieperKernel",
    "rikin.ik.pieper_kernel.single_kernel": "builds the one-pose kernel, as PieperKernel",
    "rikin.ik.parallel3.ParallelAxesSolver.single_kernel": "solver protocol, as "
    "Pieper6RSolver.check",
    "rikin.ik.parallel3_kernel.ParallelKernel": "the one-pose kernel rikin.ik.solve builds "
    "from a solver it made (fuzzed through SerialArm.ik of a UR arm typed as a table)",
    "rikin.ik.parallel3_kernel.ParallelKernel.solve": "one-pose kernel on the validated "
    "pose, as ParallelKernel",
    "rikin.ik.parallel3_kernel.single_kernel": "builds the one-pose kernel, as ParallelKernel",
    "rikin.ik.parallel3_kernel.solve_batch": "the batch kernel on validated poses, as "
    "ParallelKernel (fuzzed through SerialArm.ik_batch of a UR arm typed as a table)",
    "rikin.ik.pieper.Pieper6RSolver.batch_kernel": "solver protocol: builds the array kernel "
    "ik_batch uses, as single_kernel (fuzzed through SerialArm.ik_batch of typed arms)",
    "rikin.ik.pieper_batch.PieperBatchKernel": "the array kernel ik_batch builds from a "
    "solver it made (fuzzed through SerialArm.ik_batch of a Puma typed as a table)",
    "rikin.ik.pieper_batch.PieperBatchKernel.solve": "the array kernel on validated poses, "
    "as PieperBatchKernel",
    "rikin.ik.pieper_batch.batch_kernel": "builds the array kernel, as PieperBatchKernel",
    "rikin.ik.pieper.Pieper6RSolver.label_rows": "solver protocol, as "
    "Pieper6RSolver.check: BatchIKResult.labels calls it on the batch's own joint rows "
    "(fuzzed through BatchIKResult.labels)",
    "rikin.ik.parallel3.ParallelAxesSolver.label_rows": "as Pieper6RSolver.label_rows",
    "rikin.ik.general6r.General6RSolver.label_rows": "as Pieper6RSolver.label_rows",
    "rikin.booktext.BookText": "the book's own cells call it with string literals, which "
    "tools/cell_messages.py extracts (refusing anything else); its checks are in "
    "tests/test_booktext.py",
    "rikin.booktext.BookText.tr": "as BookText",
    "rikin.booktext.BookText.header": "as BookText",
    "rikin.booktext.BookText.translations": "as BookText",
    "rikin.booktext.cell_messages": "book tooling (tools/cell_messages.py, dev.py "
    "translations) on the book's own sources and catalogues; tested in tests/test_booktext.py",
    "rikin.booktext.page_messages": "as cell_messages",
    "rikin.booktext.read_catalogue": "as cell_messages",
    "rikin.booktext.add_translations": "called by the folded install cell of a chapter "
    "downloaded from a translated edition, with the page's catalogue entries (book/_ext); "
    "its refusals of a bad language, non-str texts and other placeholders are tested in "
    "tests/test_booktext.py",
    "rikin.dh.link_transform": "documented kernel on validated input, FK's and the IK "
    "solvers' inner loop; users call SerialArm.fk (fuzzed)",
}


def _public_modules() -> list[Any]:
    import importlib
    import pkgutil

    names = ["rikin", "rikin.ik"]
    names += [f"rikin.{m.name}" for m in pkgutil.iter_modules(rikin.__path__)
              if not m.name.startswith("_") and m.name != "ik"]
    names += [f"rikin.ik.{m.name}" for m in pkgutil.iter_modules(rikin.ik.__path__)
              if not m.name.startswith("_")]
    return [importlib.import_module(n) for n in names]


def _key(obj: Any) -> str:
    return f"{obj.__module__}.{obj.__qualname__}"


def _takes_input(fn: Any) -> bool:
    import inspect

    try:
        params = list(inspect.signature(fn).parameters.values())
    except (TypeError, ValueError):
        return True
    return any(p.name != "self" for p in params)


def public_callables() -> dict[str, Any]:
    """Every function, class (its constructor) and public method named in an ``__all__``."""
    import inspect

    out: dict[str, Any] = {}
    for mod in _public_modules():
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            if inspect.isfunction(obj):
                out[_key(obj)] = obj
            elif inspect.isclass(obj) and obj.__module__.startswith("rikin"):
                if _takes_input(obj):
                    out[_key(obj)] = obj
                for mname, member in vars(obj).items():
                    if not mname.startswith("_") and inspect.isfunction(member):
                        out[_key(member)] = member
    return {k: v for k, v in out.items() if _takes_input(v)}


def _fuzzed() -> set[str]:
    keys = set()
    for case in CASES.values():
        fns = case.fn if isinstance(case.fn, list) else [case.fn]
        keys.update(_key(f) for f in fns if f is not None)
    return keys


def test_every_public_callable_has_a_fuzz_case():
    public = public_callables()
    assert len(public) > 60  # the enumeration itself works
    missing = sorted(set(public) - _fuzzed() - set(NOT_FUZZED))
    assert not missing, (
        "public callables with no case in tests/test_fuzz.py (add one, or a justified entry "
        f"in NOT_FUZZED): {missing}"
    )
    stale = sorted(set(NOT_FUZZED) - set(public))
    assert not stale, f"NOT_FUZZED names what is no longer public: {stale}"
    both = sorted(set(NOT_FUZZED) & _fuzzed())
    assert not both, f"NOT_FUZZED names what is fuzzed: {both}"


def _params(fn: Any) -> tuple[list[str], bool]:
    """The named parameters of ``fn`` (not self), and whether it takes ``**keywords``."""
    import inspect

    ps = inspect.signature(fn).parameters.values()
    named = [p.name for p in ps if p.name != "self" and p.kind not in (p.VAR_KEYWORD,
                                                                        p.VAR_POSITIONAL)]
    return named, any(p.kind is p.VAR_KEYWORD for p in ps)


def test_every_argument_of_every_public_callable_has_a_fuzz_case():
    """Per argument, not only per callable: a new keyword cannot escape either."""
    covered: dict[str, set[str]] = {}
    for case in CASES.values():
        for f in case.fn if isinstance(case.fn, list) else [case.fn]:
            covered.setdefault(_key(f), set()).add(case.param or case.arg)
    missing = []
    for key, fn in sorted(public_callables().items()):
        if key in NOT_FUZZED:
            continue
        named, _ = _params(fn)
        missing += [f"{key}({p}=...)" for p in named if p not in covered.get(key, set())]
    assert not missing, f"arguments with no fuzz case: {missing}"


def test_every_case_names_a_real_argument():
    """A case's parameter is one of what it fuzzes (or a keyword it takes by **)."""
    for case in CASES.values():
        fns = case.fn if isinstance(case.fn, list) else [case.fn]
        params, var_kw = set(), False
        for f in fns:
            named, kw = _params(f)
            params |= set(named)
            var_kw |= kw
        assert (case.param or case.arg) in params or var_kw, (
            f"{case.name}: {case.param or case.arg!r} is not an argument of {fns}")


# ------------------------------------------------------------------ yes/no options are strict
def _flag_parameters() -> list[tuple[str, str]]:
    """(callable, parameter) of every public callable's yes/no option: a parameter whose
    default is True or False."""
    import inspect

    out = []
    for key, fn in sorted(public_callables().items()):
        if key in NOT_FUZZED:
            continue
        for p in inspect.signature(fn).parameters.values():
            if isinstance(p.default, bool):
                out.append((key, p.name))
    return out


def _flag_cases() -> dict[tuple[str, str], list[Case]]:
    by: dict[tuple[str, str], list[Case]] = {}
    for case in CASES.values():
        for f in case.fn if isinstance(case.fn, list) else [case.fn]:
            by.setdefault((_key(f), case.param or case.arg), []).append(case)
    return by


def test_every_yes_no_option_is_fuzzed_as_a_flag():
    """A bool option's case takes only True and False (numpy's too) as valid: with a numeric
    case, 0 and 1 would pass as 'a flag given as a count'."""
    flags = _flag_parameters()
    assert len(flags) >= 20  # the enumeration itself works
    by = _flag_cases()
    loose = [f"{k}({p}=...)" for k, p in flags
             if not any(c.accept is _flag and not c.numeric for c in by.get((k, p), []))]
    assert not loose, f"bool options whose fuzz case accepts non-bools: {loose}"


FLAG_CASES = sorted({c.name for cs in _flag_cases().values() for c in cs if c.accept is _flag})


@pytest.mark.parametrize("name", FLAG_CASES)
def test_a_yes_no_option_takes_true_and_false_only(name):
    case = CASES[name]
    for ok in (case.valid, np.bool_(case.valid)):  # the other one may be refused otherwise
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            case.call(ok)
        plt.close("all")
    for bad in (0, 1, 1.0, np.int64(1), np.float64(0.0), "yes", "False", "", None,
                np.array(True), [True], (False,), 1 + 0j, sympy.true):
        with pytest.raises(InputError, match=rf"\b{re.escape(case.arg)} must be True or False"):
            case.call(bad)
        plt.close("all")
