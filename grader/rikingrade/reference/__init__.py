"""Reference FK and all-solution IK of the exercise arms (instructor side only).

Never imported by student code. One module per exercise arm, each exposing
``ARM``, an :class:`~rikingrade.reference._common.ExerciseArm` with ``fk``,
``ik``, ``fk_6dof``, ``ik_6dof`` (unreachable targets raise
:class:`rikin.UnreachableError`) and the samplers the hidden tests use.
"""

from __future__ import annotations

from . import cartesian, cylindrical, scara, spherical
from ._common import ExerciseArm, Solutions

ARMS: dict[str, ExerciseArm] = {
    m.ARM.name: m.ARM for m in (cartesian, cylindrical, spherical, scara)
}

__all__ = ["ARMS", "ExerciseArm", "Solutions", "cartesian", "cylindrical", "spherical", "scara"]
