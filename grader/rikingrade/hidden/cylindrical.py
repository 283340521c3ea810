"""Hidden tests of the cylindrical exercise (cylindrical.ipynb).

Cylindrical RPP arm: one positioning solution (prismatic joints only extend).
Weights (10 points): see :func:`rikingrade.hidden._build.exercise_tests`.
"""

from __future__ import annotations

from ..reference.cylindrical import ARM
from ._build import exercise_tests

EXERCISE = "cylindrical"
NOTEBOOK = "cylindrical.ipynb"
FUNCTIONS = tuple(ARM.function_names.values())
TESTS = exercise_tests(ARM, special="")
