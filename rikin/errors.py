"""The exceptions rikin raises, in one small hierarchy.

Every error is a :class:`ValueError`, so ``except ValueError`` still catches
them, and a caller can also catch precisely:

``RikinError(ValueError)``
    ``InputError``          the argument itself is malformed (shape, NaN,
                            not a rotation, degrees where radians are expected)
    ``IKError``             the argument is well formed but has no IK answer
        ``UnreachableError`` the target lies outside the workspace
"""

from __future__ import annotations

__all__ = ["RikinError", "InputError", "IKError", "UnreachableError"]


class RikinError(ValueError):
    """Base class of every error raised by rikin."""


class InputError(RikinError):
    """An argument has the wrong shape, a NaN, or is not what the docstring asks for."""


class IKError(RikinError):
    """Inverse kinematics has no answer for a well-formed target."""


class UnreachableError(IKError):
    """The target pose is outside the arm's workspace.

    Attributes
    ----------
    excess : float
        How far the target is from the nearest reachable one, in the arm's
        length units (for a reach limit) or in radians (for an orientation
        constraint). Always positive.
    units : str
        The units of ``excess`` ("mm", "cm", "rad", or "" when unitless).
    """

    def __init__(self, message: str, *, excess: float = float("nan"), units: str = "") -> None:
        super().__init__(message)
        self.excess = excess
        self.units = units
