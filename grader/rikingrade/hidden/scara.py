"""Hidden tests of the scara exercise (scara.ipynb).

SCARA RRP arm: two positioning solutions (elbow right/left); one at full reach.
Weights (10 points): see :func:`rikingrade.hidden._build.exercise_tests`.
"""

from __future__ import annotations

from ..reference.scara import ARM
from ._build import exercise_tests

EXERCISE = "scara"
NOTEBOOK = "scara.ipynb"
FUNCTIONS = tuple(ARM.function_names.values())
TESTS = exercise_tests(ARM, special="ik_full_reach")
