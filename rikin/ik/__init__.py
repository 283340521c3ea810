"""Inverse kinematics: closed forms per arm family, results, numerical IK for comparison."""

from . import families  # noqa: F401  (registers the course families with solve and classify)
from .api import solve, solve_batch
from .families6r import classify
from .numerical import NumericalIKResult, ik_numerical, ik_numerical_multistart
from .pieper import IKClass
from .result import BatchIKResult, Branch, IKResult

__all__ = [
    "solve",
    "solve_batch",
    "classify",
    "IKClass",
    "IKResult",
    "BatchIKResult",
    "Branch",
    "ik_numerical",
    "ik_numerical_multistart",
    "NumericalIKResult",
]
