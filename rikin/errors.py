"""The exceptions rikin raises, in one small hierarchy.

Every error is a :class:`ValueError`, so ``except ValueError`` still catches
them, and a caller can also catch precisely:

``RikinError(ValueError)``
    ``InputError``          the argument itself is malformed (shape, NaN,
                            not a rotation, degrees where radians are expected)
        ``OutOfRangeError`` an index beyond a result's solutions (also an
                            ``IndexError``, as Python's sequences raise)
        ``NotIndexedError`` a result that is no sequence indexed or iterated
                            (also a ``TypeError``, as Python raises)
    ``IKError``             the argument is well formed but has no IK answer
        ``UnreachableError`` the target lies outside the workspace
"""

from __future__ import annotations

__all__ = ["RikinError", "InputError", "OutOfRangeError", "NotIndexedError",
           "IKError", "UnreachableError"]


class RikinError(ValueError):
    """Base class of every error raised by rikin."""


class InputError(RikinError):
    """An argument has the wrong shape, a NaN, or is not what the docstring asks for."""


class OutOfRangeError(InputError, IndexError):
    """An index is outside a result's range (``res[5]`` of a result with 2 solutions).

    Also an :class:`IndexError`, so that code written for Python sequences (``except
    IndexError``, iteration by index) treats a rikin result as it treats a list.
    """


class NotIndexedError(InputError, TypeError):
    """A result that is not a sequence (``BatchIKResult``, ``NumericalIKResult``) was
    indexed or iterated; the message says how to read it.

    Also a :class:`TypeError`, as Python raises for an object that is not subscriptable
    or not iterable, so code that tells sequences apart that way (``tuple(x)`` in a
    ``try``) keeps working.
    """


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
