"""Submissions the fairness issue (11, and 15's items 4, 5, 10, 11) is about, per class.

Each :class:`Fair` is one of the solution notebooks changed the way a student's
answer differs: correct answers written differently (they must keep 10/10) and wrong
answers the grader used to over- or under-score. Like ``wrong_variants.py`` each states,
per hidden test, the fraction of its weight it must lose (``lost``, worked out by
reading the code and the tests, not by running the grader), and ``before``: the total
the grader gave before the fix (from the reasoning too; the before/after table in the
report is measured with the real grader, see ``benchmarks/fairness_table.py``).

``visible``: whether a visible check in the notebook must fail (``True``), must pass
(``False``), or is not asked (``None``). A variant's change is a list of text edits
(each must occur exactly once) and/or a code cell appended at the end (a wrapper that
redefines functions, as a student's last cell would).

The classes (issue 11 items, 15.x for issue 15's):
1 input types, 2 calling convention, 3 return types, 4 singular configurations,
5 named cases never sampled, 6 visible checks vs the statement, 8 feedback,
15.4 bounded comparison, 15.5 leaks, 15.10 unreadable returns, 15.11 forged numbers; 26.5
targets near (not only at) a singular configuration (issue 26).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from wrong_variants import Variant

ARMS = ("cartesian", "cylindrical", "spherical", "scara")
LENGTHS = {
    "cartesian": ("l1", "l2", "l3"),
    "cylindrical": ("l1", "l2"),
    "spherical": ("l1", "l2"),
    "scara": ("l1", "l2", "l3"),
}
#: The positioning arm's special test (half a point), if any.
SPECIAL = {"spherical": "ik_on_axis", "scara": "ik_full_reach"}
ALL_IK = ("ik", "ik_unreachable", "ik_6dof", "ik_6dof_singular", "ik_6dof_unreachable")


@dataclass(frozen=True)
class Fair:
    arm: str
    cls: str
    name: str
    what: str
    edits: tuple[tuple[str, str], ...] = ()
    cell: str = ""
    lost: dict[str, float] = field(default_factory=dict)
    before: float = 10.0
    visible: bool | None = None
    visible_before: bool | None = None
    why: str = ""

    @property
    def id(self) -> str:
        return f"{self.arm}-{self.name}"

    def variant(self) -> Variant:
        """As a wrong_variants.Variant (its ``apply`` and ``expected_points`` work)."""
        return Variant(self.arm, self.name, self.what, self.edits, self.lost, self.why)


def _sig(arm: str, which: str, first: str = "", lengths: tuple[str, ...] | None = None,
         tool: str = "tool") -> tuple[str, str]:
    """(function name, parameter list) of one of the arm's five functions."""
    L = ", ".join(lengths or LENGTHS[arm])
    name = {"dh": "dh_table", "fk": f"fk_{arm}", "ik": f"ik_{arm}", "fk6": f"fk_{arm}_6dof",
            "ik6": f"ik_{arm}_6dof"}[which]
    if which == "dh":
        return name, L
    if which in ("fk", "ik"):
        return name, f"{first or ('q' if which == 'fk' else 'p')}, {L}"
    return name, f"{first or ('q' if which == 'fk6' else 'T')}, {L}, {tool}"


def _wrap(arm: str, which: str, body: str, first: str = "", lengths=None, tool="tool") -> str:
    """A cell that redefines one function around the original (kept as ``_orig_<name>``)."""
    name, params = _sig(arm, which, first, lengths, tool)
    args = params
    return (f"_orig_{name} = {name}\n\n\ndef {name}({params}):\n"
            + "\n".join("    " + ln for ln in body.format(orig=f"_orig_{name}", args=args)
                        .splitlines()) + "\n\n\n")


def _lost(arm: str, *tests: str, **fractions: float) -> dict[str, float]:
    out = {t: 1.0 for t in tests}
    if "ik" in tests and arm in SPECIAL:
        out[SPECIAL[arm]] = 1.0
    out.update(fractions)
    return out


def _points(arm: str, lost: dict[str, float]) -> float:
    w = {"dh_table": 1.0, "fk": 1.5, "ik": 1.5 if arm in SPECIAL else 2.0,
         "ik_unreachable": 1.0, "fk_6dof": 1.5, "ik_6dof": 2.0, "ik_6dof_singular": 0.5,
         "ik_6dof_unreachable": 0.5}
    if arm in SPECIAL:
        w[SPECIAL[arm]] = 0.5
    return sum(w.values()) - sum(w[t] * f for t, f in lost.items())


def _for_arm(arm: str) -> list[Fair]:
    L = LENGTHS[arm]
    Ls = ", ".join(L)
    out: list[Fair] = []
    everything = ("dh_table", "fk", "fk_6dof", *ALL_IK)
    # ---------------------------------------------------------------- 1: input types
    shape = "".join(_wrap(arm, w, "{first}.shape, {first}.dtype  # the stub says np.ndarray\n"
                          "return {orig}({args})".replace("{first}", f), first=f)
                    for w, f in (("fk", "q"), ("ik", "p"), ("fk6", "q"), ("ik6", "T")))
    out.append(Fair(arm, "1", "array_methods",
                    "every function uses .shape and .dtype of its array input, as the stubs "
                    "annotate it (np.ndarray)", cell=shape,
                    before=_points(arm, _lost(arm, "fk", "fk_6dof", *ALL_IK)),
                    visible=False,
                    why="correct under the contract; the grader used to pass lists: "
                        "AttributeError everywhere but dh_table (also on unreachable targets)"))
    out.append(Fair(arm, "1", "T_indexing",
                    "the 6-DOF IK indexes T[:3, :3] without np.asarray (the issue's example)",
                    edits=(("    T = np.asarray(T, dtype=float)\n    R_0_6 = T[:3, :3]",
                            "    R_0_6 = T[:3, :3]"),),
                    before=_points(arm, _lost(arm, "ik_6dof", "ik_6dof_singular",
                                              "ik_6dof_unreachable")),
                    visible=False,
                    why="a list T raised TypeError on every 6-DOF IK call (7/10 in the issue)"))
    # ---------------------------------------------------------------- 2: calling convention
    renamed = (_wrap(arm, "dh", "return {orig}(" + ", ".join(f"_{n}" for n in L) + ")",
                     lengths=tuple(f"_{n}" for n in L))
               + _wrap(arm, "fk", "return {orig}({args})", first="joints")
               + _wrap(arm, "ik", "return {orig}({args})", first="target")
               + _wrap(arm, "fk6", "return {orig}({args})", first="joints", tool="t")
               + _wrap(arm, "ik6", "return {orig}({args})", first="pose", tool="t"))
    out.append(Fair(arm, "2", "renamed_parameters",
                    "every parameter renamed (p -> target, l1 -> _l1, tool -> t, ...), "
                    "order kept", cell=renamed, before=0.0, visible=False,
                    why="the grader called by keyword: TypeError on every call"))
    # ---------------------------------------------------------------- 3: return types
    out.append(Fair(arm, "3", "sympy_fk6", "the 6-DOF FK returns a sympy Matrix of numbers",
                    cell="import sympy\n\n" + _wrap(arm, "fk6", "return sympy.Matrix({orig}"
                                                    "({args}))"),
                    before=_points(arm, {"fk_6dof": 1.0}), visible=False,
                    why="the visible checks accept it (numpy.asarray reads it); the encoder "
                        "refused it: fk_6dof lost"))
    out.append(Fair(arm, "3", "sympy_ik6", "the 6-DOF IK returns a sympy Matrix of numbers",
                    cell="import sympy\n\n" + _wrap(arm, "ik6", "return sympy.Matrix({orig}"
                                                    "({args}))"),
                    before=_points(arm, {"ik_6dof": 1.0, "ik_6dof_singular": 1.0}),
                    visible=False,
                    why="refused by the encoder; unreachable poses still raise"))
    # ---------------------------------------------------------------- 4: singular
    if arm == "scara":
        for tag, eps in (("clip_1e-9", "1e-9"), ("clip_1e-12", "1e-12")):
            out.append(Fair(arm, "4", tag,
                            f"the common guard clip(c2, -1 + {eps}, 1 - {eps}): at full reach "
                            "and folded two rows a hair from the straight elbow",
                            edits=(("c2 = np.clip(c2, -1.0, 1.0)",
                                    f"c2 = np.clip(c2, -1.0 + {eps}, 1.0 - {eps})"),),
                            before=_points(arm, {"ik_full_reach": 1.0}), visible=False,
                            why="both rows reach the target to ~1e-9 (FK) and are the stretched "
                                "(folded) solution; joint distance to the representative "
                                "4.5e-5 (1.4e-6) > 1e-6 used to make them 'unlisted' and wrong"))
    out.append(Fair(arm, "4", "wrist_pair",
                    "at the wrist singularity both branch formulas' rows, q5 = +-1e-7",
                    edits=(("wrist = [(0.0, 0.0, np.arctan2(M[1, 0], M[0, 0]))]",
                            "wrist = [(0.0, 1e-7, np.arctan2(M[1, 0], M[0, 0])), "
                            "(np.pi, -1e-7, np.arctan2(M[1, 0], M[0, 0]) + np.pi)]"),),
                    visible=False,
                    why="both rows reach (orientation error 1e-7) and are one family: one "
                        "match and a duplicate (it held before too)"))
    # ---------------------------------------------------------------- 5: named, never sampled
    strict = {"cartesian": "if q[i] < -tol:", "cylindrical": "if q2 < -tol:",
              "spherical": "if q3 < -1e-9 * (l1 + l2):", "scara": "if q3 < -tol:"}[arm]
    strict_new = strict.replace("< -tol", "< 1e-9").replace("< -1e-9 * (l1 + l2)", "< 1e-9")
    out.append(Fair(arm, "5", "prismatic_zero_refused",
                    "a prismatic joint exactly at 0 is refused (the statement allows q >= 0)",
                    edits=((strict, strict_new),),
                    lost={"ik": 0.2, "ik_6dof": 0.2}, before=10.0,
                    why="one of the five regular IK targets (and 6-DOF poses) has its prismatic "
                        "joints exactly at 0: that case raises; the tests never sampled it"))
    domain = {
        "cartesian": (("if q[i] < -tol:", 'if __import__("math").sqrt(q[i] + tol) < 0:'),),
        "cylindrical": (("if q2 < -tol:", 'if __import__("math").sqrt(q2 + tol) < 0:'),
                        ("if q3 < -tol:", 'if __import__("math").sqrt(q3 + tol) < 0:')),
        "spherical": (("if q3 < -1e-9 * (l1 + l2):",
                       'if __import__("math").sqrt(q3 + 1e-9 * (l1 + l2)) < 0:'),),
        "scara": (("if rho > l2 + l3 + tol:", "if False:"),
                  ("if rho < abs(l2 - l3) - tol:", "if False:"),
                  ("c2 = np.clip(c2, -1.0, 1.0)",
                   'c2 = c2 if abs(c2) <= 1.0 + 1e-12 else __import__("math").acos(c2)\n'
                   "    c2 = np.clip(c2, -1.0, 1.0)")),
    }[arm]
    if arm == "scara":
        lost_d, before_d = {"ik_unreachable": 2 / 3, "ik_6dof_unreachable": 1.0}, 10 - 1 / 3 - 0.25
        why_d = ("beyond reach and inside the inner circle raise 'math domain error' (above "
                 "the top still raises properly): 2 of 3 targets, and every 6-DOF pose (its "
                 "wrist centres are beyond or inside); it used to get half credit for them")
    else:
        lost_d, before_d = {"ik_unreachable": 1.0, "ik_6dof_unreachable": 1.0}, 9.25
        why_d = ("every unreachable target raises 'math domain error' from math.sqrt; it used "
                 "to get half credit, Task 5 says it is not enough")
    out.append(Fair(arm, "5", "math_domain_error",
                    "reach is 'checked' by letting math.sqrt/acos fail", edits=domain,
                    lost=lost_d, before=before_d, visible=True, why=why_d))
    if arm == "scara":
        out.append(Fair(arm, "5", "folded_refused",
                        "the fully folded arm is refused as out of reach ('<=' for '<')",
                        edits=(("if rho < abs(l2 - l3) - tol:",
                                "if rho <= abs(l2 - l3) + tol:"),),
                        lost={"ik_full_reach": 1 / 3}, before=10.0,
                        why="the statement names the folded arm; now 2 of the 6 special targets "
                            "are folded (the one near folded is farther than |l2 - l3|)"))
    # ---------------------------------------------------------------- 6: visible checks
    out.append(Fair(arm, "6", "angles_beyond_2pi",
                    "the 6-DOF IK returns its angles in (pi, 3 pi] (allowed: modulo 2 pi)",
                    edits=(("Q[:, revolute] = rikin.wrap_angle(Q[:, revolute])",
                            "Q[:, revolute] = rikin.wrap_angle(Q[:, revolute]) + 2 * np.pi"),),
                    visible=False, visible_before=True,
                    why="right modulo 2 pi; the visible check called them degrees"))
    if arm in ("cartesian", "cylindrical"):
        one = {"cartesian": ("return np.maximum(q, 0.0).reshape(1, 3)",
                             "return np.maximum(q, 0.0)"),
               "cylindrical": ("return np.array([[q1, max(q2, 0.0), max(q3, 0.0)]])",
                               "return np.array([q1, max(q2, 0.0), max(q3, 0.0)])")}[arm]
        loop = f"for q123 in ik_{arm}(p_w, {Ls}):"
        out.append(Fair(arm, "6", "single_row_shape",
                        "the one-solution IK returns shape (3,)",
                        edits=(one, (loop, f"for q123 in np.atleast_2d(ik_{arm}(p_w, {Ls})):")),
                        visible=False, visible_before=True,
                        why="the grader reads (3,) as one row; the visible check refused it"))
    out.append(Fair(arm, "6", "global_lengths",
                    "the FK builds its arm from the notebook's global L, not its arguments",
                    edits=((f"rikin.SerialArm([rikin.Link(**row) for row in dh_table({Ls})])",
                            "rikin.SerialArm([rikin.Link(**row) for row in dh_table(**L)])"),),
                    lost={"fk": 1.0}, before=8.5, visible=True, visible_before=False,
                    why="right at the public lengths only; R_0_3 (for the 6-DOF IK) does not "
                        "depend on the lengths, the 6-DOF FK has its own arm"))
    out.append(Fair(arm, "6", "wrist_q5_pi_wrong",
                    "the q5 = pi singular branch uses the q5 = 0 formula",
                    edits=(("wrist = [(0.0, np.pi, np.arctan2(M[1, 0], M[1, 1]))]",
                            "wrist = [(0.0, np.pi, np.arctan2(M[1, 0], M[0, 0]))]"),),
                    lost={"ik_6dof_singular": 0.25}, before=9.75, visible=True,
                    visible_before=False,
                    why="one of the four wrist-singular-test poses has q5 = pi (the one near "
                        "pi is regular); no visible case had"))
    # ---------------------------------------------------------------- 26.5: near singular
    out.append(Fair(arm, "26.5", "wrist_band",
                    "the 6-DOF IK takes |sin q5| < 0.05 for the wrist singularity",
                    edits=(("if s5 < 1e-9:", "if s5 < 0.05:"),),
                    lost={"ik_6dof_singular": 0.5}, before=10.0, visible=False,
                    why="2 of the 4 singular-test poses are near it (q5 1e-3 from 0 and pi), "
                        "where both branches are distinct solutions: it returns one "
                        "singular-family row per positioning solution, 1e-3 off in orientation "
                        "(FK), so no row is right there; no hidden pose was near before"))
    if arm == "scara":
        out.append(Fair(arm, "26.5", "stretch_band",
                        "the elbow within 0.045 rad of straight is taken as straight (one row)",
                        edits=(("if 1.0 - abs(c2) < 1e-12:",
                                "if c2 > 1.0 - 1e-3 or c2 < -1.0 + 1e-12:"),),
                        lost={"ik_full_reach": 1 / 12}, before=10.0, visible=False,
                        why="1 of the 6 special targets is 1e-3 rad from straight: its one "
                            "straight row reaches the target (1e-7 of the arm's size) and is "
                            "one branch, the other is missing: 1/2 there"))
    if arm == "spherical":
        out.append(Fair(arm, "26.5", "axis_band",
                        "the target within 0.05 of the vertical axis is taken as on it (one "
                        "row)",
                        edits=(("if rho < 1e-9 * (l1 + l2):", "if rho < 0.05:"),),
                        lost={"ik_on_axis": 1 / 6}, before=10.0, visible=False,
                        why="2 of the 6 special targets are 1e-3 of the arm's size from the "
                            "axis: front and back are distinct there, it returns front only"))
    # ---------------------------------------------------------------- 8: feedback
    out.append(Fair(arm, "8", "missing_helper",
                    "the IK cell starts with 'from my_ik_helpers import wrap_angle', a module "
                    "of the student's own that was not handed in",
                    edits=((f"def ik_{arm}(p", f"from my_ik_helpers import wrap_angle\n\n\n"
                                                f"def ik_{arm}(p"),),
                    lost=_lost(arm, *ALL_IK), before=4.0,
                    why="the cell fails (no such module beside the notebook, whatever the "
                        "grader has installed), ik is undefined, the 6-DOF IK calls it "
                        "(NameError)"))
    # ---------------------------------------------------------------- 15.4, 15.5, 15.10
    out.append(Fair(arm, "15.4", "many_rows",
                    "the 6-DOF IK returns every solution 100 times",
                    cell=_wrap(arm, "ik6", "return np.repeat({orig}({args}), 100, axis=0)"),
                    visible=False,
                    why="duplicates are merged, not penalised; comparing used to cost k^2"))
    leak = _wrap(arm, "ik", "raise type('q=' + repr(np.asarray(p).tolist()), (Exception,), {{}})"
                 "()", first="p")
    out.append(Fair(arm, "15.5", "class_name_leak",
                    "the IK raises an exception class named after its input",
                    cell=leak, lost=_lost(arm, *ALL_IK), before=4.0,
                    why="raises on every call, also inside the 6-DOF IK; the class name must "
                        "not reach the feedback"))
    letters = _wrap(arm, "ik", "raise ValueError(''.join('abcdefghij'[int(c)] if c.isdigit() "
                    "else c for c in repr(np.asarray(p).tolist())))", first="p")
    out.append(Fair(arm, "15.5", "digits_as_letters",
                    "the IK raises ValueError with its input spelled in letters",
                    cell=letters, lost=_lost(arm, "ik", "ik_6dof", "ik_6dof_singular"),
                    before=5.5,
                    why="ValueError on every call: right on unreachable targets only"))
    sets = "".join(_wrap(arm, w, "return set()") for w in ("dh", "fk", "ik", "fk6", "ik6"))
    out.append(Fair(arm, "15.10", "returns_set",
                    "a stub whose five functions return set()", cell=sets,
                    lost=_lost(arm, *everything), before=1.5,
                    why="a set is not numbers and not a raise; it used to count as "
                        "'raised ValueError' on the unreachable tests"))
    gen = _wrap(arm, "ik", "try:\n    return {orig}({args})\nexcept ValueError:\n"
                "    return (q for q in [])")
    out.append(Fair(arm, "15.10", "generator_not_raise",
                    "on unreachable targets the IK returns an empty generator instead of "
                    "raising", cell=gen,
                    lost={"ik_unreachable": 1.0, "ik_6dof_unreachable": 1.0}, before=9.5,
                    why="returning is not raising; the 6-DOF IK then fails with IndexError"))
    return out


FAIR: list[Fair] = [f for arm in ARMS for f in _for_arm(arm)]


def by_id(variant_id: str) -> Fair:
    return next(f for f in FAIR if f.id == variant_id)
