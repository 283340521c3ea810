"""Hidden tests of the cartesian exercise (cartesian.ipynb).

Cartesian PPP arm: no positioning singularity, one positioning solution.
Weights (10 points): see :func:`rikingrade.hidden._build.exercise_tests`.
"""

from __future__ import annotations

from ..reference.cartesian import ARM
from ._build import exercise_tests

EXERCISE = "cartesian"
NOTEBOOK = "cartesian.ipynb"
FUNCTIONS = tuple(ARM.function_names.values())
TESTS = exercise_tests(ARM, special="")
