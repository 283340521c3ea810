"""rikin.symbolic: symbolic DH products against numeric FK and the lessons' printed matrices.

The lessons' matrices below are typed in from the seed texts (Aula 10 Pasos 3, 4, 6; the
handwritten PPRRR/RPRRR notes) with the corrections ERRATA.md lists; they are the independent
expectation, never output of rikin.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
import sympy as sp

import rikin
from rikin import InputError, robots
from rikin.symbolic import (
    abbreviate,
    dh_matrix,
    joint_symbols,
    latex_short,
    lesson_arm,
    link_matrix,
    numeric,
    rotation,
    short_trig,
    simplify_trig,
    transform,
)

FK_TOL = 1e-9  # symbolic product evaluated in floats vs numeric FK, relative to the arm's size
C, S = sp.cos, sp.sin


def is_zero_matrix(M: sp.Matrix) -> bool:
    """Every entry simplifies to exactly 0 (angle sums expanded first)."""
    return all(sp.simplify(sp.expand(sp.expand_trig(e))) == 0 for e in M)


@cache
def symbolic_T(name: str, simplify: bool = True):
    links, lengths, q, conv = lesson_arm(name)
    return transform(links, conv, simplify=simplify), lengths, q


def random_case(name: str, rng: np.random.Generator):
    """Random lengths (positive; the C4's d4 of either sign) and joint values."""
    n_len = len(lesson_arm(name).lengths)
    lengths = rng.uniform(1.0, 20.0, n_len)
    if name == "epson_c4":
        lengths[3] *= rng.choice([-1.0, 1.0])
    arm = robots.LESSON_ROBOTS[name](*lengths)
    q = np.where(arm.revolute, rng.uniform(-np.pi, np.pi, arm.n), rng.uniform(-5.0, 5.0, arm.n))
    return lengths, arm, q


# ---------------------------------------------------------------- T_0_n == numeric FK
@pytest.mark.parametrize("name", sorted(robots.LESSON_ROBOTS))
def test_symbolic_T_0_n_matches_flange_fk(name):
    rng = np.random.default_rng(sorted(robots.LESSON_ROBOTS).index(name) + 100)
    T_sym, length_syms, q_syms = symbolic_T(name)
    assert T_sym.shape == (4, 4)
    assert T_sym.free_symbols <= set(length_syms) | set(q_syms)
    for _ in range(3):
        lengths, arm, q = random_case(name, rng)
        subs = dict(zip(length_syms, lengths, strict=True)) | dict(zip(q_syms, q, strict=True))
        T_num = numeric(T_sym, subs)
        T_fk = arm.replace(tool=np.eye(4)).fk(q)
        assert np.abs(T_num - T_fk).max() <= FK_TOL * arm.scale, name


@pytest.mark.parametrize("name", ["aula10_6r", "epson_c4", "rprrr"])
def test_unsimplified_product_is_the_same_matrix(name):
    rng = np.random.default_rng(7)
    T_simple, length_syms, q_syms = symbolic_T(name)
    T_raw, _, _ = symbolic_T(name, simplify=False)
    lengths, arm, q = random_case(name, rng)
    subs = dict(zip(length_syms, lengths, strict=True)) | dict(zip(q_syms, q, strict=True))
    assert np.abs(numeric(T_raw, subs) - numeric(T_simple, subs)).max() <= FK_TOL * arm.scale


@pytest.mark.parametrize("name", ["aula10_6r", "epson_c4", "pprrr"])
def test_every_intermediate_transform_and_its_inverse(name):
    # T_i_j from the frames of numeric FK: inv(F_i) @ F_j, for every pair (also i > j)
    rng = np.random.default_rng(11)
    links, length_syms, q_syms, conv = lesson_arm(name)
    lengths, arm, q = random_case(name, rng)
    F = arm.fk(q, frames=True)
    subs = dict(zip(length_syms, lengths, strict=True)) | dict(zip(q_syms, q, strict=True))
    for i in range(arm.n + 1):
        for j in range(arm.n + 1):
            expected = np.linalg.inv(F[i]) @ F[j]
            got = numeric(transform(links, conv, i, j, simplify=False), subs)
            assert np.abs(got - expected).max() <= FK_TOL * arm.scale, (i, j)
            R = numeric(rotation(links, conv, i, j, simplify=False), subs)
            assert np.abs(R - expected[:3, :3]).max() <= FK_TOL, (i, j)


def test_transform_accepts_an_arm_and_numbers():
    arm = robots.aula10_6r()
    q = rikin.rad([99.6, 9, 26.4, 68.4, 30, 151])
    T = transform(arm, q=q)  # numeric links made exact, q as floats
    assert T.free_symbols == set()
    assert np.allclose(numeric(T, {}), arm.fk(q), atol=FK_TOL * arm.scale)


def test_float_pi_fields_become_exact():
    # robots.*_links() with floats uses numpy's pi: the symbolic product must still be exact
    links = robots.angular_3r_links()  # alpha1 = np.pi / 2
    T = transform(links)
    q1, q2, q3 = sp.symbols("q1:4", real=True)
    assert T[2, 3] == 10 + 10 * S(q2) + 10 * S(q2 + q3)
    assert T[2, 2] == 0  # cos(pi/2) exactly, not 6e-17


# ---------------------------------------------------------------- dh_matrix and link_matrix
def test_dh_matrix_standard_and_modified_by_hand():
    th, d, a, al = sp.symbols("theta d a alpha", real=True)
    std = dh_matrix(th, d, a, al)
    expected_std = sp.Matrix([
        [C(th), -S(th) * C(al), S(th) * S(al), a * C(th)],
        [S(th), C(th) * C(al), -C(th) * S(al), a * S(th)],
        [0, S(al), C(al), d],
        [0, 0, 0, 1]])
    assert is_zero_matrix(std - expected_std)
    mod = dh_matrix(th, d, a, al, "modified")
    expected_mod = sp.Matrix([
        [C(th), -S(th), 0, a],
        [S(th) * C(al), C(th) * C(al), -S(al), -S(al) * d],
        [S(th) * S(al), C(th) * S(al), C(al), C(al) * d],
        [0, 0, 0, 1]])
    assert is_zero_matrix(mod - expected_mod)


def test_link_matrix_prismatic_uses_fixed_theta_and_variable_d():
    d2 = sp.Symbol("d2", real=True)
    a2 = sp.Symbol("a2", positive=True)
    link = rikin.Link("P", theta=-sp.pi / 2, d=a2)
    T = link_matrix(link, d2)
    assert T == sp.Matrix([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 1, a2 + d2], [0, 0, 0, 1]])


def test_joint_symbols_name_revolute_q_and_prismatic_d():
    assert [s.name for s in joint_symbols(robots.pprrr_links())] == ["d1", "d2", "q3", "q4", "q5"]
    assert [s.name for s in joint_symbols(robots.rprrr_links())] == ["q1", "d2", "q3", "q4", "q5"]
    assert [s.name for s in joint_symbols(robots.planar_2r_links(), revolute="theta")] == \
        ["theta1", "theta2"]


def test_lesson_arm_uses_the_lessons_length_names():
    expected = {
        "planar_2r": "l1 l2", "planar_3r": "l1 l2 l3", "angular_3r": "l1 l2 l3",
        "aula10_6r": "l1 l2 l3 l4 l5 l6", "barrientos_6r": "l1 l2 l3 l4", "pprrr": "a1 a2 a3",
        "rprrr": "a1 a2 a3 a4", "epson_c4": "d1 a1 a2 d4",
    }
    assert set(expected) == set(robots.LESSON_ROBOTS)
    for name, names in expected.items():
        links, lengths, q, conv = lesson_arm(name)
        assert " ".join(s.name for s in lengths) == names
        assert conv == ("modified" if name == "epson_c4" else "standard")
        assert len(links) == len(q)
    links, _, _, _ = lesson_arm("epson_c4")
    assert all(lk.qlim is None for lk in links)


# ---------------------------------------------------------------- Aula 10, printed matrices
@cache
def aula10():
    links, lengths, _, conv = lesson_arm("aula10_6r")
    th = joint_symbols(links, revolute="theta")
    return links, conv, th


def test_aula10_single_link_rotations_as_printed():
    links, conv, th = aula10()
    C1, C2, C3, C4, C5, C6 = (C(t) for t in th)
    S1, S2, S3, S4, S5, S6 = (S(t) for t in th)
    printed = {
        (0, 1): [[C1, 0, S1], [S1, 0, -C1], [0, 1, 0]],
        (1, 2): [[C2, -S2, 0], [S2, C2, 0], [0, 0, 1]],
        (2, 3): [[-S3, 0, C3], [C3, 0, S3], [0, 1, 0]],
        (3, 4): [[S4, 0, C4], [-C4, 0, S4], [0, -1, 0]],
        (4, 5): [[C5, 0, S5], [S5, 0, -C5], [0, 1, 0]],
        (5, 6): [[C6, -S6, 0], [S6, C6, 0], [0, 0, 1]],
    }
    for (i, j), M in printed.items():
        assert is_zero_matrix(rotation(links, conv, i, j, q=th) - sp.Matrix(M)), (i, j)


def test_aula10_R_0_3_and_its_inverse_as_printed():
    links, conv, th = aula10()
    C1, S1 = C(th[0]), S(th[0])
    C23, S23 = C(th[1] + th[2]), S(th[1] + th[2])
    R_0_3 = sp.Matrix([[-S23 * C1, S1, C23 * C1], [-S23 * S1, -C1, C23 * S1], [C23, 0, S23]])
    R_3_0 = sp.Matrix([[-S23 * C1, -S23 * S1, C23], [S1, -C1, 0], [C23 * C1, C23 * S1, S23]])
    assert is_zero_matrix(rotation(links, conv, 0, 3, q=th) - R_0_3)
    assert is_zero_matrix(rotation(links, conv, 3, 0, q=th) - R_3_0)
    # Paso 3's numbers at theta = (99.6, 9, 26.4) deg, printed with 4 decimals
    printed = [[0.0966, 0.986, -0.1359], [-0.5712, 0.1668, 0.8037], [0.8151, 0, 0.5793]]
    vals = dict(zip(th[:3], rikin.rad([99.6, 9, 26.4]), strict=True))
    assert np.abs(numeric(R_0_3, vals) - printed).max() <= 5e-5  # half a unit of the 4th decimal


def test_aula10_R_3_6_as_printed_in_paso_6():
    links, conv, th = aula10()
    C4, C5, C6 = (C(t) for t in th[3:])
    S4, S5, S6 = (S(t) for t in th[3:])
    R_3_6 = sp.Matrix([
        [C4 * S6 + C5 * C6 * S4, C4 * C6 - C5 * S4 * S6, S4 * S5],
        [S4 * S6 - C4 * C5 * C6, C6 * S4 + C4 * C5 * S6, -C4 * S5],
        [-C6 * S5, S5 * S6, C5]])
    assert is_zero_matrix(rotation(links, conv, 3, 6, q=th) - R_3_6)
    # and a deliberately wrong sign is caught (the check can fail)
    wrong = R_3_6.copy()
    wrong[2, 0] = C6 * S5
    assert not is_zero_matrix(rotation(links, conv, 3, 6, q=th) - wrong)


# ---------------------------------------------------------------- handwritten notes (001)
def pprrr_symbols(theta1=None):
    options = {} if theta1 is None else {"theta1": theta1}
    links, (a1, a2, a3), (d1, d2, q3, q4, q5), conv = lesson_arm("pprrr", **options)
    return links, conv, (a1, a2, a3), (d1, d2, q3, q4, q5)


def note_pprrr_R_0_EE(q3, q4, q5, *, ocr: bool = False):
    """The note's 0T_EE rotation (columns m, s, a), with ERRATA 001 #4's corrections."""
    C3, C4, C5, S3, S4, S5 = C(q3), C(q4), C(q5), S(q3), S(q4), S(q5)
    e22 = -C3 * S5 - C4 * C3 * S5 if ocr else -C3 * S5 - C4 * C5 * S3
    e31 = -C3 * S3 - C3 * C4 * S5 if ocr else -C5 * S3 - C3 * C4 * S5
    return sp.Matrix([
        [-S4 * S5, -C5 * S4, -C4],
        [C3 * C5 - C4 * S3 * S5, e22, S3 * S4],
        [e31, S3 * S5 - C3 * C4 * C5, C3 * S4]])


def test_pprrr_note_0T2_follows_the_literal_table():
    links, conv, (a1, a2, a3), (d1, d2, *_) = pprrr_symbols()
    note_0T2 = sp.Matrix([[0, 0, 1, a2 + d2], [0, -1, 0, 0], [1, 0, 0, a1 + d1], [0, 0, 0, 1]])
    assert is_zero_matrix(transform(links, conv, 0, 2) - note_0T2)


def test_pprrr_note_0T_EE_needs_theta1_plus_pi_over_2():
    # ERRATA 001 #1: the literal table (theta1 = -pi/2) does not give the note's 0T_EE ...
    links, conv, _, (_, _, q3, q4, q5) = pprrr_symbols()
    note = note_pprrr_R_0_EE(q3, q4, q5)
    assert not is_zero_matrix(rotation(links, conv) - note)
    # ... theta1 = +pi/2 does, with the two OCR'd entries corrected ...
    links, conv, (a1, a2, a3), (d1, d2, q3, q4, q5) = pprrr_symbols(sp.pi / 2)
    assert is_zero_matrix(rotation(links, conv) - note_pprrr_R_0_EE(q3, q4, q5))
    assert not is_zero_matrix(rotation(links, conv) - note_pprrr_R_0_EE(q3, q4, q5, ocr=True))
    # ... and then t_x = -a2 - d2 - a3 C4, t_z = a1 + d1 + a3 C3 S4, and 0T2 is ERRATA's matrix
    T = transform(links, conv)
    assert sp.simplify(T[0, 3] - (-a2 - d2 - a3 * C(q4))) == 0
    assert sp.simplify(T[2, 3] - (a1 + d1 + a3 * C(q3) * S(q4))) == 0
    errata_0T2 = sp.Matrix([[0, 0, -1, -a2 - d2], [0, 1, 0, 0], [1, 0, 0, a1 + d1], [0, 0, 0, 1]])
    assert is_zero_matrix(transform(links, conv, 0, 2) - errata_0T2)


def test_rprrr_note_0T2_and_0T_EE():
    links, (a1, a2, a3, a4), (q1, d2, q3, q4, q5), conv = lesson_arm("rprrr")
    C1, C3, C4, C5 = C(q1), C(q3), C(q4), C(q5)
    S1, S3, S4, S5 = S(q1), S(q3), S(q4), S(q5)
    note_0T2 = sp.Matrix([
        [-S1, 0, C1, a1 * C1 + a3 * C1 + d2 * C1 - a2 * S1],
        [C1, 0, S1, a2 * C1 + a1 * S1 + a3 * S1 + d2 * S1],
        [0, 1, 0, 0],
        [0, 0, 0, 1]])
    assert is_zero_matrix(transform(links, conv, 0, 2) - note_0T2)
    note_R = sp.Matrix([
        [C5 * S1 * S3 + C1 * S4 * S5 + C3 * C4 * S1 * S5,
         C1 * C5 * S4 - S1 * S3 * S5 + C3 * C4 * C5 * S1, C1 * C4 - C3 * S1 * S4],
        [S1 * S4 * S5 - C1 * C5 * S3 - C1 * C3 * C4 * S5,
         C1 * S3 * S5 + C5 * S1 * S4 - C1 * C3 * C4 * C5, C4 * S1 + C1 * C3 * S4],
        [C3 * C5 - C4 * S3 * S5, -C3 * S5 - C4 * C5 * S3, S3 * S4]])
    T = transform(links, conv)
    assert is_zero_matrix(T[:3, :3] - note_R)
    # the position column, with l1 = a1 + a3 and ERRATA 001 #6 (C3S3S4 -> C3S1S4)
    l1 = a1 + a3
    t = sp.Matrix([d2 * C1 + l1 * C1 - a2 * S1 + a4 * C1 * C4 - a4 * C3 * S1 * S4,
                   a2 * C1 + d2 * S1 + l1 * S1 + a4 * C4 * S1 + a4 * C1 * C3 * S4,
                   a4 * S3 * S4])
    assert is_zero_matrix(T[:3, 3] - t)
    t_ocr = t.copy()
    t_ocr[0] = d2 * C1 + l1 * C1 - a2 * S1 + a4 * C1 * C4 - a4 * C3 * S3 * S4
    assert not is_zero_matrix(T[:3, 3] - t_ocr)


# ---------------------------------------------------------------- notation and numbers
def test_short_trig_and_latex_short_use_the_lessons_notation():
    q1, q2, q3 = sp.symbols("q1:4", real=True)
    assert short_trig(C(q1) * S(q2 + q3)) == "C1*S23"
    assert short_trig(C(q1 - q2)) == "cos(q1 - q2)"  # not a plain sum: left alone
    links, conv, th = aula10()
    text = latex_short(rotation(links, conv, 0, 3, q=th))
    assert "C_{1}" in text and "S_{23}" in text and "C_{23}" in text
    assert "cos" not in text and "sin" not in text
    M = abbreviate(sp.Matrix([[C(q1 + q2 + q3)]]))
    assert M[0, 0] == sp.Symbol("C123", real=True)


def test_simplify_trig_folds_angle_sums():
    q1, q2 = sp.symbols("q1:3", real=True)
    assert simplify_trig(C(q1) * C(q2) - S(q1) * S(q2)) == C(q1 + q2)
    assert simplify_trig(S(q1) * C(q2) + C(q1) * S(q2)) == S(q1 + q2)


def test_numeric_accepts_names_and_reports_missing_values():
    q1, l1 = sp.Symbol("q1", real=True), sp.Symbol("l1", positive=True)
    M = sp.Matrix([[l1 * C(q1), 1]])
    assert np.allclose(numeric(M, {"q1": 0.5, l1: 2.0}), [[2 * np.cos(0.5), 1.0]], atol=1e-15)
    assert numeric(l1 * 2, {"l1": 1.5}) == 3.0
    with pytest.raises(InputError, match="no value given for l1"):
        numeric(M, {"q1": 0.5})
    with pytest.raises(InputError, match="must be a number"):
        numeric(M, {"q1": "abc", "l1": 1})
    with pytest.raises(InputError, match="complex"):
        numeric(sp.sqrt(q1), {"q1": -1.0})


def test_bad_input_is_rejected_clearly():
    links = robots.planar_2r_links()
    with pytest.raises(InputError, match="frame number 0..2"):
        transform(links, start=0, end=3)
    with pytest.raises(InputError, match="2 entries"):
        transform(links, q=[0.1])
    with pytest.raises(InputError, match="convention"):
        transform(links, "craig")
    with pytest.raises(InputError, match="unknown lesson robot"):
        lesson_arm("scara")
    with pytest.raises(InputError, match="rikin.Link"):
        transform([1, 2])
