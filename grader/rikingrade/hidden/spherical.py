"""Hidden tests of the spherical exercise (spherical.ipynb).

Spherical RRP arm: two positioning solutions; singular on the vertical axis through the shoulder.
Weights (10 points): see :func:`rikingrade.hidden._build.exercise_tests`.
"""

from __future__ import annotations

from ..reference.spherical import ARM
from ._build import exercise_tests

EXERCISE = "spherical"
NOTEBOOK = "spherical.ipynb"
FUNCTIONS = tuple(ARM.function_names.values())
TESTS = exercise_tests(ARM, special="ik_on_axis")
