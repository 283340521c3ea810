"""Hidden tests, one module per exercise (see :mod:`rikingrade.spec`).

Modules whose name starts with an underscore are helpers, not exercises.
"""

EXERCISES = ("cartesian", "cylindrical", "spherical", "scara")
