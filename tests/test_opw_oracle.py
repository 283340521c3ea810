"""Industrial arms of the ortho-parallel family (OPW) against py-opw-kinematics (Rust).

py-opw-kinematics (``pip install py-opw-kinematics``, CEAD Group's Python wrapper of
rs-opw-kinematics, Bourumir Wyngs' Rust port of the closed form of Brandstötter, Angerer
and Hofbaur 2014) is in requirements.txt, so CI has it: a missing one fails this module's
import (it is not skipped). The arms are the parameter sets published with the C++
opw_kinematics (Jmeyer1292/opw_kinematics, ``include/opw_kinematics/opw_parameters_examples.h``),
kept below as data with the seven lengths, the joint offsets and the sign corrections exactly
as printed there, plus an ABB IRB 6700 (not in that file; see ``IRB6700``).

Each is converted once to a DH table (:func:`dh_of_opw`): the conversion is checked by FK
against py-opw-kinematics' own forward kinematics. Then rikin's solution set of a pose and
py-opw-kinematics' (all eight branches of ``Robot.reach``, those that exist) must be the same
set: every solution of one within ``SAME_Q`` of one of the other, modulo 2 pi, on seeded
random poses and poses 1e-4..1e-3 rad from the wrist, elbow and shoulder singularities.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

if sys.version_info < (3, 11):  # pragma: no cover - reported as skipped, never as passed
    pytest.skip("py-opw-kinematics and scipy's RigidTransform publish no wheels for Python "
                "3.10: the OPW oracle runs on Python >= 3.11", allow_module_level=True)

try:
    from py_opw_kinematics import KinematicModel, Robot
    from scipy.spatial.transform import RigidTransform
except ImportError as exc:  # pragma: no cover - fail, do not skip
    raise ImportError(
        "py-opw-kinematics (the independent OPW solver these tests compare rikin with) is "
        "missing: `python3 tools/dev.py test` installs requirements.txt (Python >= 3.11)"
    ) from exc

import rikin
from rikin import Link, SerialArm

pi = np.pi
#: rad: two solutions of a pose are one (both solvers are closed forms)
SAME_Q = 1e-6
#: relative to the arm's size (position) and absolute (rotation entries)
FK_TOL = 1e-9

#: opw_kinematics' published parameter sets (Jmeyer1292/opw_kinematics,
#: include/opw_kinematics/opw_parameters_examples.h: makeIrb2400_10, makeKukaKR6_R700_sixx,
#: makeFanucR2000iB_200R, makeStaubliTX40): lengths in m, offsets in rad, sign corrections.
#: That file marks the Fanuc and the Staubli "UN-TESTED" (their offsets "a guess"): they are
#: still arms, and both solvers must agree on them.
OPW_EXAMPLES = {
    "ABB IRB 2400/10": dict(a1=0.100, a2=-0.135, b=0.000, c1=0.615, c2=0.705, c3=0.755,
                            c4=0.085, offsets=(0, 0, -pi / 2, 0, 0, 0), signs=(1,) * 6),
    "KUKA KR 6 R700 sixx": dict(a1=0.025, a2=-0.035, b=0.000, c1=0.400, c2=0.315, c3=0.365,
                                c4=0.080, offsets=(0, -pi / 2, 0, 0, 0, 0),
                                signs=(-1, 1, 1, -1, 1, -1)),
    "Fanuc R-2000iB/200R": dict(a1=0.720, a2=-0.225, b=0.000, c1=0.600, c2=1.075, c3=1.280,
                                c4=0.235, offsets=(0, 0, -pi / 2, 0, 0, 0), signs=(1,) * 6),
    "Staubli TX40": dict(a1=0.000, a2=0.000, b=0.035, c1=0.320, c2=0.225, c3=0.225,
                         c4=0.065, offsets=(0, 0, -pi / 2, 0, 0, 0), signs=(1,) * 6),
}
#: ABB IRB 6700-205/2.80, data sheet values (mm in the source): the modified DH table of
#: SaltworkerMLU/robotkinematicscatalogue (``ABB_IRB_6700_205_280``) gives the same arm
#: (``test_irb6700_parameters_are_the_catalogues_table``); offsets as opw_kinematics' ABB.
IRB6700 = dict(a1=0.320, a2=-0.200, b=0.000, c1=0.780, c2=1.280, c3=1.1825, c4=0.200,
               offsets=(0, 0, -pi / 2, 0, 0, 0), signs=(1,) * 6)
ARMS = {**OPW_EXAMPLES, "ABB IRB 6700-205/2.80": IRB6700}

#: The DH joint angle of each OPW joint at the OPW paper's zero (arm straight up).
_DH_ZERO = (0.0, -pi / 2, pi / 2, 0.0, 0.0, 0.0)


def dh_of_opw(name: str, p: dict) -> SerialArm:
    """The standard DH table of an OPW parameter set, with its offsets and signs.

    The OPW paper's joint angles are ``raw_i = sign_i q_i - offset_i`` (``q`` as the robot
    counts its joints); its axes 1 (up), 2 and 3 (parallel, along the base's y turned by
    joint 1) and the spherical wrist ``Rz(q4) Ry(q5) Rz(q6)`` are DH z axes of the same
    directions, so the DH angle is ``raw_i + _DH_ZERO[i]``: ``direction = sign_i`` and
    ``offset = _DH_ZERO[i] - offset_i``.
    """
    rows = (dict(d=p["c1"], a=p["a1"], alpha=-pi / 2), dict(d=p["b"], a=p["c2"]),
            dict(a=p["a2"], alpha=pi / 2), dict(d=p["c3"], alpha=-pi / 2),
            dict(alpha=pi / 2), dict(d=p["c4"]))
    return SerialArm(tuple(
        Link(**row, offset=_DH_ZERO[i] - p["offsets"][i], direction=p["signs"][i])
        for i, row in enumerate(rows)), name=name, units="m")


def opw_robot(p: dict) -> Robot:
    """py-opw-kinematics' robot of the parameter set, joints in radians."""
    lengths = {k: p[k] for k in ("a1", "a2", "b", "c1", "c2", "c3", "c4")}
    model = KinematicModel(**lengths, offsets=tuple(float(o) for o in p["offsets"]),
                           flip_axes=tuple(s < 0 for s in p["signs"]))
    return Robot(model, degrees=False)


def wrap(x):
    return (np.asarray(x) + pi) % (2 * pi) - pi


def same_sets(A, B, tol):
    """Every row of A has one of B within tol (modulo 2 pi), and the other way round."""
    if len(A) == 0 or len(B) == 0:
        return len(A) == len(B)
    gap = np.abs(wrap(A[:, None] - B[None])).max(-1)
    return bool((gap.min(1) <= tol).all() and (gap.min(0) <= tol).all())


def opw_tool(tool: np.ndarray | None) -> RigidTransform | None:
    """py-opw-kinematics' ``ee_transform`` of a rikin tool ``[R | t]``: its FK is
    ``flange @ Rot(R) @ Trans(t')`` (the tool's offset in the turned frame, as found by
    comparing FKs), so it gets ``t' = R^T t``; :func:`check_pose` checks FK with it."""
    if tool is None:
        return None
    ee = np.array(tool, dtype=float)
    ee[:3, 3] = ee[:3, :3].T @ ee[:3, 3]
    return RigidTransform.from_matrix(ee)


def opw_solutions(robot: Robot, T: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
    """Every branch py-opw-kinematics finds for the pose ``T`` (those that exist)."""
    ee = opw_tool(tool)
    joints = robot.reach(RigidTransform.from_matrix(T[None]), ee_transform=ee).joints[0]
    return joints[np.isfinite(joints).all(1)]


def joints_of_raw(p: dict, raw: np.ndarray) -> np.ndarray:
    """The robot's joint values of OPW paper angles ``raw (..., 6)``."""
    return (raw + np.asarray(p["offsets"])) * np.asarray(p["signs"])


def near_singular_raw(p: dict, rng, n: int) -> np.ndarray:
    """OPW paper angles ``(4 n, 6)``: random, then 1e-4..1e-3 rad from the wrist (raw q5 =
    0), from the elbow stretched (``raw q3 = -atan2(a2, c3)``) and, where the wrist centre can
    reach axis 1 (``b = 0``), from the shoulder singularity (the wrist centre on axis 1)."""
    raw = rng.uniform(-pi, pi, size=(4 * n, 6))
    eps = rng.uniform(1e-4, 1e-3, size=4 * n) * rng.choice([-1, 1], size=4 * n)
    raw[n:2 * n, 4] = eps[n:2 * n]
    raw[2 * n:3 * n, 2] = -np.arctan2(p["a2"], p["c3"]) + eps[2 * n:3 * n]
    k = np.hypot(p["a2"], p["c3"])
    rows = np.arange(3 * n, 4 * n)
    if p["b"] == 0.0:  # c2 sin q2 + k sin(q2 + q3 + psi3) + a1 = 0: the wrist centre on axis 1
        s = -(p["a1"] + p["c2"] * np.sin(raw[rows, 1])) / k
        rows = rows[np.abs(s) < 1]
        raw[rows, 2] = (np.arcsin(s[np.abs(s) < 1]) - raw[rows, 1]
                        - np.arctan2(p["a2"], p["c3"]) + eps[rows])
    return raw


@pytest.mark.parametrize("name", list(ARMS))
def test_dh_table_is_the_opw_arm(name):
    """The conversion: rikin's FK of the DH table is py-opw-kinematics' FK, at 300 seeded
    joint vectors as the robot counts them (offsets and sign corrections included)."""
    p = ARMS[name]
    arm, robot = dh_of_opw(name, p), opw_robot(p)
    q = np.random.default_rng(11).uniform(-pi, pi, size=(300, 6))
    theirs = robot.batch_forward(q).as_matrix()
    assert np.abs(arm.fk(q) - theirs).max() <= 1e-12 * arm.scale
    assert set(arm.reversed_joints) == {i + 1 for i, s in enumerate(p["signs"]) if s < 0}


def test_irb6700_parameters_are_the_catalogues_table():
    """The IRB 6700 lengths typed here are the arm of robotkinematicscatalogue's modified DH
    table (alpha, a, d, theta; mm, rad), to rounding, flange frame included."""
    mdh = ((0, 0, 780, 0), (-pi / 2, 320, 0, -pi / 2), (0, 1280, 0, 0),
           (-pi / 2, 200, 1182.5, 0), (pi / 2, 0, 0, 0), (-pi / 2, 0, 200, pi))
    catalogue = SerialArm(tuple(Link(alpha=al, a=a / 1000, d=d / 1000, offset=th)
                                for al, a, d, th in mdh), convention="modified", units="m")
    arm = dh_of_opw("IRB 6700", IRB6700)
    q = np.random.default_rng(12).uniform(-pi, pi, size=(100, 6))
    assert np.abs(arm.fk(q) - catalogue.fk(q)).max() <= 1e-12


def check_pose(arm, robot, q, tool=None):
    """rikin's and py-opw-kinematics' solution sets of FK(q) are equal, hold q, and each
    solution of rikin reaches the pose by py-opw-kinematics' FK. Returns the count."""
    T = arm.fk(q)
    ours = arm.ik(T).q
    theirs = opw_solutions(robot, T, tool)
    assert same_sets(ours, theirs, SAME_Q), (arm.name, q, len(ours), len(theirs))
    assert np.abs(wrap(ours - q)).max(1).min() <= SAME_Q
    for F in robot.batch_forward(ours, ee_transform=opw_tool(tool)).as_matrix():
        assert np.abs(F[:3, 3] - T[:3, 3]).max() <= FK_TOL * arm.scale
        assert np.abs(F[:3, :3] - T[:3, :3]).max() <= FK_TOL
    return len(ours)


@pytest.mark.parametrize("name", list(ARMS))
def test_solution_sets_equal_py_opw_kinematics(name):
    p = ARMS[name]
    arm, robot = dh_of_opw(name, p), opw_robot(p)
    assert str(rikin.ik.classify(arm)).startswith("6R with a spherical wrist")
    rng = np.random.default_rng(29)
    counts = [check_pose(arm, robot, q)
              for q in joints_of_raw(p, near_singular_raw(p, rng, 12))]
    assert max(counts) == 8


@pytest.mark.parametrize("name", ["KUKA KR 6 R700 sixx", "ABB IRB 6700-205/2.80"])
def test_solution_sets_equal_with_a_tool(name):
    """With a tool: rikin's arm carries it, py-opw-kinematics gets it as its ee_transform."""
    p = ARMS[name]
    tool = rikin.homogeneous(rikin.rpy_to_r(-0.5, 0.1, 0.2), [0.02, 0.03, 0.15])
    arm, robot = dh_of_opw(name, p).replace(tool=tool), opw_robot(p)
    rng = np.random.default_rng(30)
    for q in rng.uniform(-pi, pi, size=(15, 6)):
        check_pose(arm, robot, q, tool)
