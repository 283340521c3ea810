"""The two cells every arm exercise notebook starts with, kept in one place.

``python3 tools/make_exercises.py`` copies the section after ``# %% [setup]``
into the notebook cell tagged ``setup`` and the section after
``# %% [checks]`` into the cell tagged ``checks``, in solutions/ and in
exercises/. Edit them here, never in a notebook.

The checks are the visible, public ones a student runs: fixed public cases,
FK round trips through the student's own FK, counts, and the same cases with every
length scaled (a function that ignores its length arguments fails). They never call
a reference solution of the arm being exercised. A failed check raises
``CheckFailed`` with a message in the student's terms; the notebook shows that message
alone (``%tb`` shows the traceback), and each hint names the cause the check saw
(a length argument whose change does not change the answer, a target on the edge of
the workspace that the function refuses although it answers 1e-9 of the arm's size
away, angles that look like degrees, a missing tool).

They call the student's functions as the grader does (positionally, in the
stub's order, with float64 numpy arrays and float lengths), read the answers
with the grader's rule (``rikingrade.hidden._common.as_array``/``student_rows``)
and judge them with the statement's tolerance, the grader's: poses to 1e-6 times
the arm's size (the sum of its lengths, at least 1, plus the tool) in position and
1e-6 in each rotation entry; joint values to 1e-6 rad, or 1e-6 times the arm's
size for a prismatic joint. ``tests/test_visible_checks_agree.py`` runs the checks
and the grader on the same answers and fails where they disagree.
"""
# ruff: noqa: E402  (each section is a notebook cell: imports follow code on purpose)

# %% [setup]
#@title Setup: import rikin (the notebook's first cell installs it when missing)
import numpy as np

import rikin

rikin.i18n.set_language("en")
np.set_printoptions(precision=4, suppress=True)
print(f"rikin {rikin.__version__}, numpy {np.__version__}")

# %% [checks]
#@title Checking helpers (run this cell; you do not need to read it)
import numpy as np

import rikin


class CheckFailed(AssertionError):
    """A visible check found a problem; the message says what, in your terms."""


def _t(text, **values):
    """A message in the notebook's language, with ``values`` put into its {placeholders}.

    tools/make_exercises.py writes the translated text here in the other languages'
    notebooks (from solutions/locales/), so this cell reads in the notebook's language.
    """
    return text.format(**values)


def _show_only_the_message(shell, etype, value, tb, tb_offset=None):
    """A failed check, or a task not written yet, shows its message; %tb shows where.

    A task not written yet is the exercise's own stub, ``raise NotImplementedError("task N:
    fn")``, reached by any check that calls it; a NotImplementedError of the student's own
    keeps its traceback.
    """
    if etype is NotImplementedError and not str(value).startswith("task "):
        shell.showtraceback((etype, value, tb), tb_offset=tb_offset)
        return
    shell.showtraceback((etype, value, tb), exception_only=True)
    if etype is NotImplementedError:
        number, _, name = str(value)[len("task "):].partition(": ")
        print(_t("(task {number}: {name} is not written yet: replace its raise "
                 "NotImplementedError line with your code, run that cell, then this one.)",
                 number=number, name=name))


try:
    get_ipython().set_custom_exc(  # noqa: F821
        (CheckFailed, NotImplementedError), _show_only_the_message)
except NameError:  # not in IPython (a script): the usual traceback
    pass

CHECK_TOL = 1e-6      # the statement's tolerance: rad, or times the arm's size for lengths
TWO_PI = 2 * np.pi
SCALE = 1.7           # the lengths-matter check multiplies every length by this
BRANCH_TOL = 0.05     # a row that reaches the target belongs to the branch this close
EDGE = 1e-9           # a target this close (times the arm's size) to a limit is on it


def _size(lengths):
    """The arm's size, as the grader has it: the sum of its lengths (at least 1) + the tool."""
    links = [float(v) for k, v in lengths.items() if k != "tool"]
    return max(1.0, sum(links)) + float(lengths.get("tool", 0.0))


def _call(f, first, lengths):
    """f(first, *lengths) as the grader calls it: positionally, a float64 array first."""
    args = [] if first is None else [np.array(first, dtype=float)]
    return f(*args, *[float(v) for v in lengths.values()])


def _as_numbers(value, what):
    """``value`` as a float array, read as the grader reads it, or CheckFailed."""
    try:
        A = np.asarray(value)
        if A.dtype.kind == "O":
            A = A.astype(complex)
        if A.dtype.kind == "c":
            if np.any(np.abs(A.imag) > 1e-9 * np.maximum(1.0, np.abs(A.real))):
                raise TypeError("complex")
            A = A.real
        if A.dtype.kind not in "biuf":
            raise TypeError(A.dtype)
        return np.asarray(A, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise CheckFailed(_t("{what} returned {kind}, which is not an array of real numbers: "
                             "return a numpy array (sympy matrices of numbers, lists and "
                             "tuples are fine too)", what=what, kind=type(value).__name__)
                          ) from None


def _fmt(v, digits=4):
    """Numbers as '(1.2346, -0.5, 3)', with no '-0'."""
    a = np.round(np.asarray(v, dtype=float), digits) + 0.0
    return "(" + ", ".join(f"{x:.{digits}f}".rstrip("0").rstrip(".") for x in np.ravel(a)) + ")"


def _as_rows(Q, n, name):
    """The solutions returned by an IK function as an array (k, n), or CheckFailed."""
    A = _as_numbers(Q, name)
    if A.shape == (n,):
        print(_t("(note: {name} returned one solution as shape ({n},); the docstring asks for "
                 "(k, {n}), here (1, {n}). The grader reads it as one row too.)", name=name, n=n))
        A = A[None, :]
    if A.ndim != 2 or A.shape[1] != n:
        raise CheckFailed(_t("{name} returned shape {shape}; return shape (k, {n}), one "
                             "solution per row (also when there is only one: shape (1, {n}))",
                             name=name, shape=A.shape, n=n))
    if not np.all(np.isfinite(A)):
        raise CheckFailed(_t("{name} returned NaN or infinity:\n{A}\nnumpy's arccos/sqrt give "
                             "NaN out of their domain: clip the cosine, or raise ValueError if "
                             "the target is out of reach", name=name, A=A))
    return A


def _arm_from_rows(rows):
    if isinstance(rows, (list, tuple)) and rows and all(isinstance(r, rikin.Link) for r in rows):
        raise CheckFailed(_t("dh_table returned rikin.Link objects: return plain dicts, e.g. "
                             "dict(joint='R', d=l1, a=0.0, alpha=np.pi / 2), so the grader "
                             "can read them"))
    if not isinstance(rows, (list, tuple)) or not all(isinstance(r, dict) for r in rows):
        raise CheckFailed(_t("dh_table returned {kind}; return a list of dicts, one per joint, "
                             "with the keywords of rikin.Link", kind=type(rows).__name__))
    try:
        return rikin.SerialArm(tuple(rikin.Link(**r) for r in rows))
    except (TypeError, ValueError) as exc:
        raise CheckFailed(_t("these rows do not make a rikin arm: {exc}", exc=exc)) from None


def _pose_text(T):
    T = np.asarray(T, dtype=float)
    return _t("origin {o}, x axis {x}, y axis {y}, z axis {z}", o=_fmt(T[:3, 3]),
              x=_fmt(T[:3, 0]), y=_fmt(T[:3, 1]), z=_fmt(T[:3, 2]))


def _pose_gap(T, T_expected, size):
    """(position error / size, largest rotation-entry error), as the grader measures them."""
    return (float(np.linalg.norm(T[:3, 3] - T_expected[:3, 3])) / size,
            float(np.abs(T[:3, :3] - T_expected[:3, :3]).max()))


def _compare_pose(T, T_expected, what, q, size):
    T = _as_numbers(T, what)
    T_expected = np.asarray(T_expected, dtype=float)
    if T.shape != (4, 4):
        raise CheckFailed(_t("for q = {q} {what} has shape {shape}; expected a (4, 4) matrix",
                             q=_fmt(q), what=what, shape=T.shape))
    if not np.all(np.isfinite(T)):
        raise CheckFailed(_t("for q = {q} {what} contains NaN or infinity:\n{T}",
                             q=_fmt(q), what=what, T=T))
    dp, dr = _pose_gap(T, T_expected, size)
    if dp > CHECK_TOL:
        return _t("for q = {q} {what} puts the TCP at {p}, expected {p_expected}", q=_fmt(q),
                  what=what, p=_fmt(T[:3, 3]), p_expected=_fmt(T_expected[:3, 3]))
    if dr > CHECK_TOL or np.abs(T[3] - [0, 0, 0, 1]).max() > CHECK_TOL:
        return _t("for q = {q} {what} has the TCP in the right place but the wrong "
                  "orientation:\n  yours:    {yours}\n  expected: {expected}", q=_fmt(q),
                  what=what, yours=_pose_text(T), expected=_pose_text(T_expected))
    return ""


def _degrees_hint(fk, q, kwargs, revolute):
    """Whether fk changes when a revolute joint turns a full 2*pi (then it reads degrees)."""
    q = np.asarray(q, dtype=float)
    size = _size(kwargs)
    T = _as_numbers(_call(fk, q, kwargs), "fk")
    for i in np.flatnonzero(revolute):
        q2 = q.copy()
        q2[i] += -TWO_PI if q2[i] > 0 else TWO_PI
        try:
            T2 = _as_numbers(_call(fk, q2, kwargs), "fk")
        except Exception:  # noqa: BLE001 - an FK that refuses angles beyond 2*pi
            return _t("\nHint: your FK fails when joint {i} turns a full 2*pi rad; any angle "
                      "modulo 2*pi is allowed (q is in radians).", i=i + 1)
        if T2.shape != (4, 4) or max(_pose_gap(T2, T, size)) > CHECK_TOL:
            return _t("\nHint: your FK changes when joint {i} turns a full 2*pi rad, so it "
                      "probably reads the angles as degrees. q is in radians.", i=i + 1)
    return ""


def check_dh(dh_table, lengths, cases):
    """Check a DH table (list of dicts) against public poses of frame 3.

    cases : list of (q, T_0_3 expected)
    """
    rows = _call(dh_table, None, lengths)
    arm = _arm_from_rows(rows)
    if arm.n != 3:
        raise CheckFailed(_t("dh_table has {n} rows; the positioning arm has 3 joints", n=arm.n))
    for q, T_expected in cases:
        msg = _compare_pose(arm.fk(q), T_expected, _t("your table"), q, _size(lengths))
        if msg:
            raise CheckFailed(msg + _t("\n(frame 3 of your table, built with rikin.SerialArm)"))
    big = _arm_from_rows(_call(dh_table, None, _scaled_lengths(lengths)))
    prismatic = np.array([link.joint == "P" for link in arm.links])
    for q, T_expected in cases:
        msg = _compare_pose(big.fk(_scaled_q(q, ~prismatic)), _scaled_pose(T_expected),
                            _t("your table"), _scaled_q(q, ~prismatic), SCALE * _size(lengths))
        if msg:
            raise CheckFailed(_lengths_hint(msg, dh_table, None, lengths))
    print(_t("✓ dh_table: frame 3 is where it should be for {n} public joint vectors, also "
             "with every length x{scale}", n=len(cases), scale=SCALE))


def check_fk(fk, lengths, cases, revolute, *, tool=None):
    """Check an FK function against public poses.

    cases : list of (q, T expected); revolute : which joints are revolute.
    tool : the tool length of a 6-DOF arm, to recognise a missing tool.
    """
    name = getattr(fk, "__name__", "fk")
    revolute = np.asarray(revolute, dtype=bool)
    size = _size(lengths)
    for q, T_expected in cases:
        T = _call(fk, q, lengths)
        msg = _compare_pose(T, T_expected, _t("your {name}", name=name), q, size)
        if msg:
            T = _as_numbers(T, name)
            T_expected = np.asarray(T_expected, dtype=float)
            flange = T_expected[:3, 3] - (tool or 0.0) * T_expected[:3, 2]
            if tool and np.linalg.norm(T[:3, 3] - flange) / size <= CHECK_TOL:
                msg += _t("\nHint: that is the flange (frame 6, at the wrist centre), not the "
                          "TCP: the tool is missing")
            msg += _degrees_hint(fk, q, lengths, revolute)
            raise CheckFailed(msg)
    for q, T_expected in cases:
        q_big = _scaled_q(q, revolute)
        msg = _compare_pose(_call(fk, q_big, _scaled_lengths(lengths)), _scaled_pose(T_expected),
                            _t("your {name}", name=name), q_big, SCALE * size)
        if msg:
            raise CheckFailed(_lengths_hint(msg, fk, q_big, lengths))
    print(_t("✓ {name}: right for {n} public joint vectors, also with every length x{scale}",
             name=name, n=len(cases), scale=SCALE))


def _scaled_lengths(lengths):
    return {k: SCALE * float(v) for k, v in lengths.items()}


def _scaled_q(q, revolute):
    """q with its prismatic (length) values scaled like the lengths."""
    q = np.asarray(q, dtype=float)
    return np.where(revolute, q, SCALE * q)


def _scaled_pose(T):
    T = np.array(T, dtype=float)
    T[:3, 3] *= SCALE
    return T


def _answer(f, first, lengths):
    """What f gives: ("value", array) or ("raised", "Type: message")."""
    try:
        value = _call(f, first, lengths)
    except Exception as exc:  # noqa: BLE001 - any outcome is compared, none is judged
        return ("raised", f"{type(exc).__name__}: {exc}")
    if isinstance(value, (list, tuple)) and value and all(isinstance(r, dict) for r in value):
        value = [sorted((k, float(v) if np.isscalar(v) and not isinstance(v, str) else str(v))
                        for k, v in r.items()) for r in value]  # dh_table rows
        return ("value", repr(value))
    try:
        return ("value", np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        return ("value", repr(value))


def _same(a, b):
    if a[0] != b[0] or type(a[1]) is not type(b[1]):
        return False
    if isinstance(a[1], np.ndarray):
        return a[1].shape == b[1].shape and bool(np.allclose(a[1], b[1], rtol=1e-12,
                                                              atol=1e-12, equal_nan=True))
    return a[1] == b[1]


def _ignored_lengths(f, first, lengths):
    """The length arguments whose change (x SCALE, alone) leaves f's answer as it was."""
    base = _scaled_lengths(lengths)
    before = _answer(f, first, base)
    ignored = []
    for k in lengths:
        other = dict(base, **{k: float(lengths[k])})
        if _same(_answer(f, first, other), before):
            ignored.append(k)
    return ignored


def _lengths_hint(msg, f, first, lengths):
    """The scaled case failed: say so, and which length ``f`` ignores, if one is."""
    name = getattr(f, "__name__", "f")
    names = ", ".join(lengths)
    text = _t("with every length multiplied by {scale} ({names}), and the prismatic joint "
              "values with them, the arm is the same shape {scale} times bigger; but {msg}.",
              scale=SCALE, names=names, msg=msg)
    ignored = _ignored_lengths(f, first, lengths)
    if ignored:
        return text + _t("\n{name} gives the same answer when {which} changes: does it use "
                         "its own argument(s) {which} (not the notebook's L or a number typed "
                         "in)? The grader uses random lengths.", name=name,
                         which=", ".join(ignored))
    return text + _t("\n{name} does read each of {names} (its answer changes with each), so "
                     "look for a number that should grow with the arm: a tolerance or an "
                     "offset typed as a fixed length.", name=name, names=names)


def _matches(row, expected, revolute, size):
    """Whether a solution (that reaches the target) is of an expected one's branch.

    As the grader judges it: near a singular configuration a right answer can sit
    1e-4 from the representative, so a row that reaches the target belongs to the
    branch within BRANCH_TOL of it (rad, or times the arm's size). None in
    ``expected`` marks a free joint.
    """
    for i, e in enumerate(expected):
        if e is None:
            continue
        d = row[i] - e
        d = rikin.wrap_angle(d) if revolute[i] else d / size
        if abs(d) > BRANCH_TOL:
            return False
    return True


def check_ik(ik, fk, lengths, target, expected, revolute):
    """Check that an IK function returns every expected solution and only those.

    target : p (3,) or T (4, 4); expected : dict label -> solution (None marks a
    free joint of a singular family: any value is accepted if FK reaches the target).
    Each returned solution is also put through your own FK.
    """
    name = getattr(ik, "__name__", "ik")
    target = np.asarray(target, dtype=float)
    revolute = np.asarray(revolute, dtype=bool)
    Q = _check_ik_once(ik, fk, lengths, target, expected, revolute)
    big = dict(expected)
    for lab, row in expected.items():
        big[lab] = [None if v is None else (v if r else SCALE * v)
                    for v, r in zip(row, revolute, strict=True)]
    target_big = np.array(target)
    if target_big.shape == (3,):
        target_big = SCALE * target_big
    else:
        target_big[:3, 3] *= SCALE
    try:
        _check_ik_once(ik, fk, _scaled_lengths(lengths), target_big, big, revolute)
    except CheckFailed as exc:
        if getattr(exc, "edge", False):  # the cause is known: the edge of the workspace
            raise CheckFailed(_t("with every length multiplied by {scale}: {exc}",
                                 scale=SCALE, exc=exc)) from None
        raise CheckFailed(_lengths_hint(str(exc).rstrip("."), ik, target_big, lengths)) from None
    dup = len(Q) - len(_distinct(Q, revolute, _size(lengths)))
    note = _t(" ({dup} duplicate row(s) merged)", dup=dup) if dup else ""
    print(_t("✓ {name}: {n} of {n} solutions, each reaching the target with your {fk}{note}; "
             "also with every length x{scale}", name=name, n=len(expected),
             fk=getattr(fk, "__name__", "fk"), note=note, scale=SCALE))


def _distinct(Q, revolute, size):
    distinct = []
    for row in Q:
        if not any(np.abs(np.where(revolute, rikin.wrap_angle(row - d), (row - d) / size)).max()
                   <= CHECK_TOL for d in distinct):
            distinct.append(row)
    return distinct


def _nudged(target, size):
    """Targets EDGE x size away from ``target`` (a point or a pose), in a few directions."""
    target = np.asarray(target, dtype=float)
    p = target if target.shape == (3,) else target[:3, 3]
    steps = [EDGE * size * p / max(np.linalg.norm(p), 1e-300)]
    steps += [EDGE * size * np.append(p[:2] / max(np.linalg.norm(p[:2]), 1e-300), 0.0),
              EDGE * size * np.array([0.0, 0.0, 1.0])]
    for step in steps:
        for sign in (-1.0, 1.0):
            moved = np.array(target)
            if moved.shape == (3,):
                moved = moved + sign * step
            else:
                moved[:3, 3] += sign * step
            yield moved


def _refused(ik, lengths, target, expected, exc):
    """CheckFailed for an IK that raised ValueError on a target it can reach."""
    name = getattr(ik, "__name__", "ik")
    labels = ", ".join(expected)
    msg = _t("{name} raised {error} for a target it can reach ({labels})", name=name,
             error=f"{type(exc).__name__}({str(exc)!r})", labels=labels)
    for moved in _nudged(target, _size(lengths)):
        try:
            _call(ik, moved, lengths)
        except Exception:  # noqa: BLE001 - it refuses this one too
            continue
        failed = CheckFailed(msg + _t(
            ".\nIt answers for a target {edge} x the arm's size away: this one is on the edge "
            "of the workspace (stretched or folded), where rounding can put a cosine a hair "
            "past 1 (1.0000000000000002). Treat a cosine within 1e-9 of +-1 as +-1 (np.clip) "
            "and raise only beyond that, as the statement says.", edge=f"{EDGE:g}"))
        failed.edge = True
        return failed
    return CheckFailed(msg)


def _check_ik_once(ik, fk, lengths, target, expected, revolute):
    """One target of check_ik: CheckFailed, or the rows returned."""
    name = getattr(ik, "__name__", "ik")
    fk_name = getattr(fk, "__name__", "fk")
    size = _size(lengths)
    try:
        answer = _call(ik, target, lengths)
    except ValueError as exc:
        raise _refused(ik, lengths, target, expected, exc) from None
    Q = _as_rows(answer, len(revolute), name)
    distinct = _distinct(Q, revolute, size)
    for row in distinct:
        _check_row_reaches(row, fk, lengths, target, revolute, name, fk_name)
    labels = list(expected)
    found = [lab for lab in labels
             if any(_matches(r, expected[lab], revolute, size) for r in distinct)]
    extra = [r for r in distinct
             if not any(_matches(r, expected[lab], revolute, size) for lab in labels)]
    missing = [lab for lab in labels if lab not in found]
    if missing:
        lines = [_t("{found} of {n} solutions found; missing:", found=len(found), n=len(labels))]
        for lab in missing:
            shown = ", ".join(_t("any") if v is None else _fmt([v])[1:-1]
                              for v in expected[lab])
            lines.append(_t("  - {label}: expected about ({values})", label=lab, values=shown))
        raise CheckFailed("\n".join(lines))
    if extra:
        raise CheckFailed(_t("{name} found all {n} expected solutions but also {row}, which "
                             "reaches the target yet is not allowed here (check the joint "
                             "limits: prismatic joints only extend, q >= 0)", name=name,
                             n=len(labels), row=_fmt(extra[0])))
    return Q


def _check_row_reaches(row, fk, lengths, target, revolute, name, fk_name):
    """CheckFailed unless the student's FK puts solution ``row`` on the target."""
    size = _size(lengths)
    hint = ""
    if np.abs(row[revolute]).max(initial=0.0) > TWO_PI + 1e-9:
        hint = _t("\nIts angles look like degrees: return radians (np.radians converts); any "
                  "angle modulo 2*pi is fine.")
    try:  # any angle modulo 2*pi is a right answer: your FK sees it wrapped
        T = _as_numbers(_call(fk, np.where(revolute, rikin.wrap_angle(row), row), lengths),
                        fk_name)
    except CheckFailed:
        raise
    except Exception as exc:  # noqa: BLE001 - the student's FK refused the row
        raise CheckFailed(_t("your {fk} raised {error} on the solution {row} that {name} "
                             "returned: {exc}{hint}", fk=fk_name, error=type(exc).__name__,
                             row=_fmt(row), name=name, exc=exc, hint=hint)) from None
    p_target = target if target.shape == (3,) else target[:3, 3]
    if T.shape != (4, 4):
        raise CheckFailed(_t("your {fk} returned shape {shape}; expected (4, 4)", fk=fk_name,
                             shape=T.shape))
    if np.linalg.norm(T[:3, 3] - p_target) / size > CHECK_TOL:
        raise CheckFailed(_t("solution {row} does not reach the target: your {fk} puts the TCP "
                             "at {p}, target {target}{hint}", row=_fmt(row), fk=fk_name,
                             p=_fmt(T[:3, 3]), target=_fmt(p_target), hint=hint))
    if target.shape == (4, 4) and np.abs(T[:3, :3] - target[:3, :3]).max() > CHECK_TOL:
        raise CheckFailed(_t("solution {row} puts the TCP in the right place with the wrong "
                             "orientation (checked with your {fk})", row=_fmt(row), fk=fk_name))


def check_unreachable(ik, lengths, cases):
    """Check that each unreachable target raises ValueError. cases: list of (target, why)."""
    name = getattr(ik, "__name__", "ik")
    messages = []
    for target, why in cases:
        try:
            result = _call(ik, target, lengths)
        except NotImplementedError:
            raise
        except ValueError as exc:
            if str(exc).strip() == "math domain error":
                raise CheckFailed(_t("{why}: {name} raised ValueError('math domain error') "
                                     "from math.sqrt/acos; check reachability yourself and "
                                     "say why in the message", why=why, name=name)) from None
            messages.append(f"  {why}: ValueError: {exc}")
            continue
        except Exception as exc:  # noqa: BLE001 - any other error is the wrong kind
            raise CheckFailed(_t("{why}: {name} raised {error}: {exc}; expected ValueError "
                                 "with a message that says why", why=why, name=name,
                                 error=type(exc).__name__, exc=exc)) from None
        raise CheckFailed(_t("{why}: {name} returned\n{result}\ninstead of raising ValueError",
                             why=why, name=name, result=np.asarray(result)))
    print(_t("✓ {name}: all {n} unreachable targets raise ValueError:", name=name,
             n=len(cases)))
    print("\n".join(messages))


def print_dh(rows):
    """Print a DH table given as a list of dicts."""
    head = [_t("joint"), _t("type"), "theta", "d", "a", "alpha", _t("offset")]
    widths = [max(w, len(h)) for h, w in zip(head, (5, 4, 9, 9, 9, 9, 9), strict=True)]
    print(" ".join(f"{h:>{w}}" for h, w in zip(head, widths, strict=True)))
    for i, r in enumerate(rows, 1):
        j = r.get("joint", "R")
        theta = f"q{i}" if j == "R" else f"{r.get('theta', 0.0):.4f}"
        d = f"{r.get('d', 0.0):.4f}" if j == "R" else f"q{i}+{r.get('d', 0.0):.4g}"
        vals = [str(i), j, theta, d, f"{r.get('a', 0.0):.4f}", f"{r.get('alpha', 0.0):.4f}",
                f"{r.get('offset', 0.0):.4f}"]
        print(" ".join(f"{v.replace('-0.0000', '0.0000'):>{w}}"
                       for v, w in zip(vals, widths, strict=True)))


def print_solutions(Q, names):
    """Print IK solutions, one per row, rounded to 4 decimals (no '-0')."""
    Q = np.asarray(Q, dtype=float)
    print("    " + " ".join(f"{n:>9}" for n in names))
    for k, row in enumerate(np.round(Q, 4) + 0.0, 1):
        print(f"{k:>3} " + " ".join(f"{v:>9.4f}" for v in row))


def show_arm(rows, q, *, wrist_rows=(), tool=0.0, ax=None, title=""):
    """Draw an arm from DH rows (dicts) at joint values q: links, joints, frames and TCP.

    Each link is drawn as its d piece (along z) then its a piece (along x); frame axes
    are x red, y green, z blue. Returns the matplotlib Axes (rikin.plot.plot_arm).
    """
    import matplotlib.pyplot as plt

    import rikin.plot

    arm = _arm_from_rows([*rows, *wrist_rows]).replace(tool=rikin.transl(0.0, 0.0, tool))
    if ax is None:
        fig = plt.figure(figsize=(5, 4.2), dpi=80)
        ax = fig.add_subplot(projection="3d")
    return rikin.plot.plot_arm(arm, q, ax=ax, title=title or f"q = {_fmt(q, 2)}")
