"""A reversed joint and data-sheet limits typed as text (issue 29, Wanted 3):
:func:`rikin.dhtext.arm_from_table` reads a direction column, a minus on the joint variable
(``-q1``, ``-(q3 - 90°)``, ``-d3``) and the type ``R-``/``P-`` as ``Link(direction=-1)``,
and ``limits``/``min``/``max`` columns as the data sheet prints them. Oracles: the arm built
from ``rikin.Link`` by hand, the same table with the signs flipped by hand, and
roboticstoolbox's Jaco and Mico (their ``flip=True`` joint 1) for FK.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import rikin
from rikin import InputError, Link, SerialArm, robots, widgets
from rikin.dhtext import arm_from_table
from rikin.tables import dh_table, solutions_table

pi = np.pi
KR5_EXAMPLE = "KUKA KR 5 arc (as KUKA counts A1-A6)"

# joint 1 and 2 revolute, joint 3 prismatic, each counted against its DH z axis
REFERENCE = SerialArm((Link(d=0.4, a=0.18, alpha=-pi / 2, direction=-1),
                       Link(a=0.6, offset=pi / 2, direction=-1),
                       Link("P", a=0.1, alpha=pi / 2, offset=0.05, direction=-1)))

WAYS = {
    "direction column": "theta d a alpha offset direction\n"
                        "q1 0.4 0.18 -90 0 -1\nq2 0 0.6 0 90 -1\n0 d3 0.1 90 0.05 -1",
    "direction as + and -, last": "theta d a alpha dir\n"
                                  "q1 0.4 0.18 -90 -\nq2+90 0 0.6 0 −\n0 q3+0.05 0.1 90 -",
    "sign column in a markdown table": "| i | sign | θ | d | a | α |\n|---|---|---|---|---|---|\n"
                                       "| 1 | -1 | q1 | 0.4 | 0.18 | -pi/2 |\n"
                                       "| 2 | − | θ2 + 90° | 0 | 0.6 | 0 |\n"
                                       "| 3 | -1.0 | 0 | q3 + 0.05 | 0.1 | 90° |",
    "minus on the variable": "theta d a alpha\n-q1 0.4 0.18 -90\n-(θ2 - 90°) 0 0.6 0\n"
                             "0 -d3+0.05 0.1 90",
    "minus on the variable, spaced": "| θ | d | a | α |\n| −θ₁ | 0.4 | 0.18 | -90 |\n"
                                     "| -θ2 + 90° | 0 | 0.6 | 0 |\n"
                                     "| 0 | 0.05 - q3 | 0.1 | 90 |",
    "type R- and P-": "R- 0.4 0.18 -90\nR- 0 0.6 0 90\nP- 0 0.1 90 0.05",
    "type column R-": "type theta d a alpha offset\nR- 0 0.4 0.18 -90 0\nr- 90 0 0.6 0 0\n"
                      "P− 0 0 0.1 90 0.05",
}


def _same_links(arm, ref):
    assert arm.joint_types == ref.joint_types
    assert arm.directions.tolist() == ref.directions.tolist()
    for got, want in zip(arm.links, ref.links, strict=True):
        for f in ("d", "a", "alpha", "offset", "theta"):
            assert getattr(got, f) == pytest.approx(getattr(want, f), abs=1e-15), f


@pytest.mark.parametrize("way", list(WAYS))
def test_every_way_of_writing_a_reversed_joint_is_direction_minus_one(way):
    arm = arm_from_table(WAYS[way])
    _same_links(arm, REFERENCE)
    q = np.random.default_rng(1).uniform(-3, 3, size=(20, 3))
    assert np.abs(arm.fk(q) - REFERENCE.fk(q)).max() < 1e-14


def test_a_plus_joint_stays_plus_and_a_minus_on_a_constant_is_an_offset():
    arm = arm_from_table("theta d a alpha dir\nq1 + (-90°) 0.4 0 -90 +1\n-90° d2 0 0 +\n")
    assert arm.directions.tolist() == [1, 1]
    assert arm.links[0].offset == pytest.approx(-pi / 2)
    assert arm.links[1].theta == pytest.approx(-pi / 2)
    assert arm_from_table("R+ 0 1 0 -1").links[0].offset == pytest.approx(np.radians(-1))


# ------------------------------------------------------------------ IK of a typed arm
KR5_TEXT = widgets.EXAMPLES[KR5_EXAMPLE]["table"]
# the same KR 5 arc typed with no joint reversed and no limits: the signs flipped by hand
KR5_PLAIN = """\
| axis | θ        | d     | a    | α   |
| A1   | q1       | 0.4   | 0.18 | -90 |
| A2   | q2       | 0     | 0.6  | 0   |
| A3   | q3 - 90° | 0     | 0.12 | -90 |
| A4   | q4       | 0.62  | 0    | 90  |
| A5   | q5       | 0     | 0    | -90 |
| A6   | q6       | 0.115 | 0    | 0   |
"""


def test_the_hand_flipped_table_is_what_the_test_means():
    plain = arm_from_table(KR5_PLAIN)
    assert not plain.reversed_joints and np.isinf(plain.qlim).all()
    assert "-q" in KR5_TEXT and "±" in KR5_TEXT


def test_ik_of_the_typed_arm_with_base_and_tool_is_the_plain_arms_with_signs_flipped():
    base = rikin.homogeneous(rikin.rpy_to_r(10, -5, 30, degrees=True), [0.2, -0.1, 0.3])
    tool = rikin.homogeneous(rikin.rpy_to_r(0, 20, 90, degrees=True), [0.01, 0.02, 0.15])
    arm = arm_from_table(KR5_TEXT, units="m", base=base, tool=tool)
    plain = arm_from_table(KR5_PLAIN, units="m", base=base, tool=tool)
    s = np.array([-1, 1, 1, -1, 1, -1])
    assert arm.directions.tolist() == s.tolist()
    ref = robots.kuka_kr5_arc(base=base, tool=tool)
    rng = np.random.default_rng(7)
    for q in rng.uniform(-pi, pi, size=(25, 6)):
        T = arm.fk(q)
        assert np.abs(T - plain.fk(s * q)).max() < 1e-13  # q_reversed = -q_plain
        assert np.abs(T - ref.fk(q)).max() < 1e-13  # rikin.robots' KR 5 arc
        res, res_plain = arm.ik(T), plain.ik(T)
        assert len(res) == len(res_plain) >= 1
        F = arm.fk(res.q)  # every solution put back through FK, base and tool too
        assert np.abs(F[:, :3, 3] - T[:3, 3]).max() < 1e-9 * arm.scale
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max() < 1e-9
        flipped = rikin.wrap_angle(res_plain.q * s)
        for row in res.q:
            assert np.abs(rikin.wrap_angle(flipped - row)).max(axis=1).min() < 1e-9
        assert np.abs(rikin.wrap_angle(res.q - q)).max(axis=1).min() < 1e-7


def _rtb_text(model):
    """A roboticstoolbox DH model typed as a student would from its table: a flipped
    joint's theta as ``-q<i>`` (plus its offset, in degrees)."""
    rows = ["| θ | d | a | α |", "|---|---|---|---|"]
    for i, lk in enumerate(model.links, 1):
        sign = "-" if lk.isflip else ""
        offset, d, a, alpha = (float(v) for v in (np.degrees(lk.offset), lk.d, lk.a,
                                                  np.degrees(lk.alpha)))
        rows.append(f"| {sign}q{i} + {offset!r}° | {d!r} | {a!r} | {alpha!r} |")
    return "\n".join(rows)


@pytest.mark.parametrize("name", ["Jaco", "Mico"])
def test_kinovas_reversed_joint_one_typed_as_text_is_roboticstoolboxs_fk(name):
    rtb = pytest.importorskip("roboticstoolbox")  # requirements.txt: a test oracle
    model = getattr(rtb.models.DH, name)()
    assert model.links[0].isflip and not any(lk.isflip for lk in model.links[1:])
    base = rikin.homogeneous(rikin.rotz(0.4), [0.1, 0.2, 0.05])
    tool = rikin.transl(0, 0, 0.12)
    model.base, model.tool = base, tool
    arm = arm_from_table(_rtb_text(model), base=base, tool=tool)
    assert arm.reversed_joints == (1,)
    for q in np.random.default_rng(3).uniform(-pi, pi, size=(20, 6)):
        assert np.abs(arm.fk(q) - model.fkine(q).A).max() < 1e-12


def test_each_typed_kr5_solution_is_a_pose_of_roboticstoolboxs_flipped_model():
    """An FK no one here wrote: roboticstoolbox's DHRobot with ``flip=True`` on A1, A4, A6."""
    rtb = pytest.importorskip("roboticstoolbox")
    arm = arm_from_table(KR5_TEXT, units="m")
    model = rtb.DHRobot([rtb.RevoluteDH(d=float(lk.d), a=float(lk.a), alpha=float(lk.alpha),
                                        offset=float(lk.offset), flip=lk.direction < 0)
                         for lk in arm.links])
    rng = np.random.default_rng(8)
    for q in rng.uniform(-pi, pi, size=(10, 6)):
        T = model.fkine(q).A
        res = arm.ik(T)
        assert len(res) >= 1
        for row in res.q:
            assert np.abs(model.fkine(row).A - T).max() < 1e-9


# ------------------------------------------------------------------ limits as printed
def test_limits_are_read_as_printed_in_the_data_sheets_direction():
    arm = arm_from_table(KR5_TEXT)
    assert np.allclose(np.degrees(arm.qlim), robots.KUKA_KR5_ARC_LIMITS_DEG)
    assert np.allclose(arm.qlim, robots.kuka_kr5_arc().qlim)
    same = arm_from_table(
        "| θ | d | a | α | min (°) | max (°) |\n| -q1 | 0.4 | 0.18 | -90 | -155 | 155 |\n"
        "| q2 | 0 | 0.6 | 0 | -180 | 65 |\n| q3 - pi/2 | 0 | 0.12 | -90 | -15 | 158 |\n"
        "| -q4 | 0.62 | 0 | 90 | -350 | 350 |\n| q5 | 0 | 0 | -90 | -130 | 130 |\n"
        "| -q6 | 0.115 | 0 | 0 | -350 | 350 |")
    assert np.allclose(same.qlim, arm.qlim)
    text = ("theta(rad) d a alpha lower(rad) upper\n-q1 0.4 0.18 -pi/2 -2.7 pi\n"
            "0 d2 0 0 none 0.3")
    odd = arm_from_table(text)
    assert odd.qlim[0].tolist() == pytest.approx([-2.7, pi])
    assert odd.qlim[1].tolist() == [-np.inf, 0.3]


def _in_limits(arm, row):
    lo, hi = arm.qlim[:, 0], arm.qlim[:, 1]
    shifts = 2 * pi * np.arange(-2, 3)
    return all(((v + shifts >= lo[j] - 1e-9) & (v + shifts <= hi[j] + 1e-9)).any()
               for j, v in enumerate(row))


def test_asymmetric_limits_of_a_reversed_joint_bound_q_not_the_dh_value():
    """A1 typed ``-q1`` with limits -20..150: q1 = 140° is allowed, q1 = -40° is not,
    although the DH value -q1 = 40° would lie inside them."""
    text = KR5_TEXT.replace("| ±155     |", "| -20..150 |")
    arm = arm_from_table(text, units="m")
    assert arm.qlim[0].tolist() == pytest.approx(np.radians([-20, 150]).tolist())
    for q1, kept in ((140, True), (-40, False)):
        q = np.radians([q1, -70, 90, 10, 50, 20])
        T = arm.fk(q)
        every, fit = arm.ik(T), arm.ik(T, within_limits=True)
        assert np.abs(rikin.wrap_angle(every.q - q)).max(axis=1).min() < 1e-7
        near = np.abs(rikin.wrap_angle(fit.q - q)).max(axis=1) < 1e-7 if len(fit) else []
        assert any(near) is kept
        assert len(fit) == sum(_in_limits(arm, row) for row in every.q)
        assert fit.discarded == len(every) - len(fit) and fit.discarded >= 1
        assert all(_in_limits(arm, row) for row in fit.q)


def test_the_panel_solves_within_the_typed_limits_and_says_what_it_left_out():
    panel = widgets.dh_panel(**widgets.EXAMPLES[KR5_EXAMPLE])
    st = panel.state
    every = st.arm.ik(st.target)
    assert st.result.discarded >= 1 and len(st.result) + st.result.discarded == len(every)
    assert all(_in_limits(st.arm, row) for row in st.result.q)
    assert f"{st.result.discarded} more outside the joint limits left out" in st.message
    assert "the joints you typed are solution" in st.message  # data-sheet values shown
    q_typed = np.radians([float(v) for v in widgets.EXAMPLES[KR5_EXAMPLE]["target"].split()])
    assert np.abs(rikin.wrap_angle(st.result.q - q_typed)).max(axis=1).min() < 1e-9
    page = panel.html()
    assert "−q1" in page and "−q4" in page and "−q6" in page and "−q2" not in page
    assert "-155° … 155°" in page and "-180° … 65°" in page
    assert "q1 (°, −z)" in page and "q2 (°)" in page


def test_an_arm_with_no_reversed_joint_and_no_limit_shows_no_read_back_table():
    panel = widgets.dh_panel(**widgets.EXAMPLES["Puma 560"])
    assert "−q" not in panel.html() and "limits" not in panel.html()


# ------------------------------------------------------------------ tables
def test_solutions_table_marks_the_reversed_joints_columns():
    arm = robots.kuka_kr5_arc()
    res = arm.ik(arm.fk(np.radians([30, -60, 90, 0, 45, 0])))
    header = str(solutions_table(res, 1, arm=arm)).splitlines()[0]
    assert re.findall(r"q\d \([^)]*\)", header) == [
        "q1 (°, −z)", "q2 (°)", "q3 (°)", "q4 (°, −z)", "q5 (°)", "q6 (°, −z)"]
    assert "−z" not in str(solutions_table(res, 1))
    with pytest.raises(InputError, match="joints"):
        solutions_table(res, arm=robots.planar_2r())


def test_dh_table_shows_the_limits_as_printed_when_asked():
    text = str(dh_table(arm_from_table(KR5_TEXT, units="m"), limits=True))
    rows = text.splitlines()
    assert rows[0].endswith("limits (°)")
    assert rows[1].endswith("-155° … 155°") and "−q1" in rows[1]
    assert rows[2].endswith("-180° … 65°")
    assert "limits" not in str(dh_table(arm_from_table(KR5_TEXT)))


# ------------------------------------------------------------------ bad input
BAD = {
    "direction 0": ("theta d a alpha dir\nq1 0 1 0 +1\nq2 0 1 0 0", 3, "direction"),
    "direction 2": ("theta d a alpha dir\nq1 0 1 0 2", 2, "direction"),
    "direction x": ("| θ | d | a | α | direction |\n| q1 | 0 | 1 | 0 | x |", 2, "direction"),
    "direction -0.5": ("theta d a alpha sign\nq1 0 1 0 -0.5", 2, "direction"),
    "a minus alone": ("| type | θ | d | a | α |\n| R | - | 0 | 1 | 0 |", 2, "theta"),
    "a minus alone in d": ("R 0 1 0\nR - 1 0", 2, None),
    "said twice": ("theta d a alpha dir\n-q1 0 1 0 -1", 2, "direction"),
    "said both ways": ("theta d a alpha dir\n-q1 0 1 0 +1", 2, "direction"),
    "R- and -q": ("type theta d a alpha\nR- -q1 0 1 0", 2, "theta"),
    "twice the variable": ("theta d a alpha\nq1 - 2*q1 0 1 0", 2, "theta"),
    "a factor": ("theta d a alpha\n2*q1 0 1 0", 2, "theta"),
    "limits upside down": ("theta d a alpha limits\nq1 0 1 0 170..-170", 2, "limits"),
    "limits unreadable": ("| θ | d | a | α | limits |\n| q1 | 0 | 1 | 0 | 170 |", 2, "limits"),
    "limits ± of a negative": ("theta d a alpha limits\nq1 0 1 0 ±-3", 2, "limits"),
    "min above max": ("theta d a alpha min max\nq1 0 1 0 10 -10", 2, "min"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_a_bad_direction_or_limit_is_refused_naming_line_and_column(case):
    text, line, column = BAD[case]
    with pytest.raises(InputError) as err:
        arm_from_table(text)
    msg = str(err.value)
    assert f"DH table line {line} " in msg, msg
    if column is not None:
        assert f"column {column} = " in msg, msg
    assert "write " in msg or "expected " in msg, msg  # and how to write it


def test_the_errors_say_how_to_write_a_reversed_joint():
    with pytest.raises(InputError, match=r"-q3 in theta .*-1 in a direction column .*R-"):
        arm_from_table("| type | θ | d | a | α |\n| R | − | 0 | 1 | 0 |")
    with pytest.raises(InputError, match=r"R- or P- for a joint its data sheet counts"):
        arm_from_table("R 0 1 0 0 -1")
    with pytest.raises(InputError, match=r"direction \(\+1 or -1\), min and max or limits"):
        arm_from_table("theta d a alpha flip\nq1 0 1 0 1")
    with pytest.raises(InputError, match="keep one"):
        arm_from_table("theta d a alpha limits min\nq1 0 1 0 ±10 -10")


def test_tables_of_direction_and_limit_words_read_or_are_refused_never_crash():
    """Seeded: tables made of this syntax's pieces, some cells wrong, are an arm (finite
    FK, the direction and limits read) or an InputError, never another exception."""
    import random

    cells = {
        "theta": ["q{i}", "-q{i}", "-(q{i} - 90°)", "−θ{i} + 90°", "0", "-90°", "2*q{i}", "-",
                  "q{i} - q{i}", "(q{i}+90)°", "x"],
        "d": ["0", "0.4", "-0.2", "d{i}", "-d{i}", "-q{i} + 0.1", "-", "1e-3"],
        "a": ["0", "0.3", "-0.1", "-", "pi"],
        "alpha": ["0", "90", "-90°", "pi/2", "-", "x"],
        "dir": ["+1", "-1", "+", "-", "−", "0", "2", "x", "-0.5", "1"],
        "type": ["R", "P", "R-", "P-", "r+", "revolute", "Q", "-"],
        "limits": ["±170", "-180..65", "-15 to 158", "none", "170..-170", "±-3", "10", "—"],
        "min": ["-170", "none", "-", "10", "x"],
        "max": ["170", "none", "65", "-10", "x"],
    }
    extras = [[], ["dir"], ["type"], ["limits"], ["min", "max"], ["dir", "limits"],
              ["type", "dir"], ["limits", "min"]]
    rng = random.Random(29)
    read = 0
    for _ in range(1500):
        cols = ["theta", "d", "a", "alpha", *rng.choice(extras)]
        rows = ["| " + " | ".join(cols) + " |"]
        for i in range(1, rng.randint(1, 6) + 1):
            rows.append("| " + " | ".join(rng.choice(cells[c]).format(i=i) for c in cols)
                        + " |")
        try:
            arm = arm_from_table("\n".join(rows))
        except InputError:
            continue
        read += 1
        assert np.isfinite(arm.fk(np.full(arm.n, 0.3))).all()
        assert set(arm.directions.tolist()) <= {-1, 1}
        assert (arm.qlim[:, 0] <= arm.qlim[:, 1]).all()
    assert read > 15  # the generator does make tables rikin reads (22 of 1500, seed 29)
