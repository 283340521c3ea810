"""Inverse kinematics: closed forms per arm family, results, numerical IK for comparison."""

from .api import solve, solve_batch
from .result import BatchIKResult, Branch, IKResult

__all__ = ["solve", "solve_batch", "IKResult", "BatchIKResult", "Branch"]
