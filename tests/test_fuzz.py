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
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
import pytest
import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import rikin
from rikin import InputError, UnreachableError, robots
from rikin.ik import ik_numerical, ik_numerical_multistart
from rikin.ik.numerical import pose_error

EXAMPLES = 12

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


def bad_values(valid: Any) -> st.SearchStrategy[Any]:
    return st.one_of(st.sampled_from(SCALARS), _arrays(), _near_valid(valid))


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
    return np.allclose(np.asarray(a, float), np.asarray(b, float))


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
        return True
    return bool(np.isfinite(np.asarray(result, dtype=float)).all())


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
        add(Case(f"{rname}.fk", "q", lambda v, a=arm: a.fk(v), q))
        add(Case(f"{rname}.fk_flange", "q", lambda v, a=arm: a.fk_flange(v), q))
        add(Case(f"{rname}.jacobian", "q", lambda v, a=arm: a.jacobian(v), q))
        add(Case(f"{rname}.joint_axes", "q", lambda v, a=arm: a.joint_axes(v), q))
        add(Case(f"{rname}.world_to_base", "T_world", lambda v, a=arm: a.world_to_base(v), T))
        add(Case(f"{rname}.ik", "target", lambda v, a=arm: a.ik(v), tg))
        add(Case(f"{rname}.ik near", "near", lambda v, a=arm, t=tg: a.ik(t, near=v), q,
                 accepts_none=True))
        add(Case(f"{rname}.ik within_limits", "within_limits",
                 lambda v, a=arm, t=tg: a.ik(t, within_limits=v), True))
        add(Case(f"{rname}.ik_batch", "T", lambda v, a=arm: a.ik_batch(v), T[None]))
        add(Case(f"{rname}.ik_batch chunk_size", "chunk_size",
                 lambda v, a=arm, t=T: a.ik_batch(t[None], chunk_size=v), 16))
        add(Case(f"{rname}.ik_batch workers", "workers",
                 lambda v, a=arm, t=T: a.ik_batch(t[None], workers=v), 1, accepts_none=True))
        add(Case(f"{rname}.ik_numerical T", "T",
                 lambda v, a=arm, m=mask: ik_numerical(a, v, max_iter=15, mask=m), T))
        add(Case(f"{rname}.ik_numerical q0", "q0",
                 lambda v, a=arm, t=T, m=mask: ik_numerical(a, t, v, max_iter=15, mask=m), q,
                 accepts_none=True))
        add(Case(f"{rname}.ik_numerical tol", "tol",
                 lambda v, a=arm, t=T, m=mask: ik_numerical(a, t, tol=v, max_iter=15, mask=m),
                 1e-6))
        add(Case(f"{rname}.ik_numerical mask", "mask",
                 lambda v, a=arm, t=T: ik_numerical(a, t, mask=v, max_iter=15),
                 (1, 1, 1, 0, 0, 0), accepts_none=arm.n == 6))
        add(Case(f"{rname}.pose_error q", "q", lambda v, a=arm, t=T: pose_error(a, v, t), q))
        add(Case(f"{rname}.pose_error T", "T", lambda v, a=arm: pose_error(a, np.where(
            a.revolute, 0.3, 1.0), v), T))
        add(Case(f"{rname}.table", "decimals", lambda v, s=sol: s.table(v), 3))
        # the constructor, one length at a time
        import inspect

        params = [
            p for p in inspect.signature(robots.LESSON_ROBOTS[rname]).parameters.values()
            if isinstance(p.default, float)
        ]
        for p in params:
            add(Case(f"robots.{rname}({p.name}=...)", p.name,
                     lambda v, mk=robots.LESSON_ROBOTS[rname], n=p.name: mk(**{n: v}), p.default))
        for which in ("base", "tool"):
            add(Case(f"robots.{rname}({which}=...)", which,
                     lambda v, mk=robots.LESSON_ROBOTS[rname], w=which: mk(**{w: v}),
                     np.eye(4), accepts_none=True))
    arm6 = ARMS["aula10_6r"]
    T6 = _pose_of(arm6)
    T06 = arm6.world_to_base(T6)
    cases += [
        Case("solver.steps T_0_6", "T_0_6", lambda v: arm6.solver.steps(arm6, v), T06),
        Case("solver.steps arm_slot", "arm_slot", lambda v: arm6.solver.steps(arm6, T06, v), 1),
        Case("ik_numerical_multistart", "n_starts",
             lambda v: ik_numerical_multistart(arm6, T6, v, max_iter=10), 2),
        Case("ik.solve arm", "arm", lambda v: rikin.ik.solve(v, T6), None),
        Case("ik_numerical arm", "arm", lambda v: ik_numerical(v, T6), None),
        Case("wrap_angle", "theta", rikin.wrap_angle, [0.5, 7.0], nan_in_nan_out=True),
        Case("deg", "theta", rikin.deg, [0.5, 1.0]),
        Case("rad", "theta", rikin.rad, [30.0, 45.0]),
        Case("rotx", "theta", rikin.rotx, 0.3),
        Case("roty", "theta", rikin.roty, [0.3, -0.2]),
        Case("rotz", "theta", rikin.rotz, 0.3),
        Case("transforms.trotx", "theta", rikin.transforms.trotx, 0.3),
        Case("transl", "x", rikin.transl, [1.0, 2.0, 3.0]),
        Case("transl(x, y, z)", "y", lambda v: rikin.transl(1.0, v, 2.0), 0.5),
        Case("homogeneous R", "R", lambda v: rikin.homogeneous(v, [1.0, 2.0, 3.0]),
             rikin.rotz(0.4), accepts_none=True),
        Case("homogeneous p", "p", lambda v: rikin.homogeneous(rikin.rotz(0.4), v),
             [1.0, 2.0, 3.0], accepts_none=True),
        Case("inv_transform", "T", rikin.inv_transform, T6),
        Case("rpy_to_r roll", "roll", lambda v: rikin.rpy_to_r(v, 0.1, 0.2), 0.3),
        Case("rpy_to_r yaw", "yaw", lambda v: rikin.rpy_to_r(0.3, 0.1, v), 0.2),
        Case("rpy_to_r degrees", "degrees", lambda v: rikin.rpy_to_r(30, 10, 20, degrees=v), True),
        Case("r_to_rpy", "R", rikin.r_to_rpy, rikin.rotz(0.3)),
        Case("zyz_to_r", "theta", lambda v: rikin.zyz_to_r(0.1, v, 0.3), 0.2),
        Case("r_to_zyz R", "R", rikin.r_to_zyz, rikin.rotx(0.3)),
        Case("r_to_zyz branch", "branch", lambda v: rikin.r_to_zyz(rikin.rotx(0.3), branch=v), -1),
        Case("Link a", "a", lambda v: rikin.Link(a=v), symbolic=True, valid=1.0),
        Case("Link d", "d", lambda v: rikin.Link(d=v), symbolic=True, valid=1.0),
        Case("Link alpha", "alpha", lambda v: rikin.Link(alpha=v), symbolic=True, valid=0.5),
        Case("Link offset", "offset", lambda v: rikin.Link(offset=v), symbolic=True, valid=0.5),
        Case("Link qlim", "qlim", lambda v: rikin.Link(qlim=v), (-1.0, 1.0), accepts_none=True),
        Case("SerialArm base", "base",
             lambda v: rikin.SerialArm((rikin.Link(a=1.0),), base=v), np.eye(4)),
        Case("SerialArm tool", "tool",
             lambda v: rikin.SerialArm((rikin.Link(a=1.0),), tool=v), np.eye(4)),
        Case("SerialArm links", "links", lambda v: rikin.SerialArm(v), None),
        Case("SerialArm convention", "convention",
             lambda v: rikin.SerialArm((rikin.Link(a=1.0),), convention=v), None),
    ]
    return cases


CASES = {c.name: c for c in _cases()}


def _check(case: Case, value: Any) -> None:
    equiv = float_equivalent(value)
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
    # returned: right only for a plainly numeric value (or None where None is the default)
    assert value is not None or case.accepts_none or case.valid is None, (
        f"{case.name} accepted {value!r}"
    )
    if value is None:
        return
    if case.symbolic and isinstance(value, sympy.Basic):
        return
    if isinstance(case.valid, (bool, int)) and isinstance(value, (bool, np.bool_, int, np.integer)):
        return  # a flag given as a flag, a count given as a count
    assert equiv is not None or isinstance(value, (str,)) and case.arg == "convention", (
        f"{case.name} accepted the non-number {value!r} and returned {result!r:.200}"
    )
    if case.nan_in_nan_out and equiv is not None and not np.isfinite(equiv).all():
        got = np.asarray(result, dtype=float)
        assert np.array_equal(np.isnan(got), ~np.isfinite(equiv)), f"{case.name}({value!r})"
        return
    assert _finite(result), f"{case.name}({value!r}) returned NaN or infinity"
    if equiv is not None and equiv.dtype == np.float64:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            clean = case.call(equiv if equiv.ndim else float(equiv))
        assert _same(result, clean), f"{case.name}({value!r}) differs from the float64 call"


@pytest.mark.parametrize("name", sorted(CASES))
@settings(max_examples=EXAMPLES, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_every_public_boundary_raises_rikins_own_errors(name, data):
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
