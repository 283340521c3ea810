"""Which solver takes a 6R arm typed as a DH table: the 6R families, tried in order.

Each family is a *recogniser*: a function of the arm that returns a :class:`Match` (the
family in the book's words, and how to build its solver) or a string, the reason the arm
is not of that family. :func:`classify` and :func:`solver_for` (the one path from a table
to its solver: :func:`rikin.ik.solve` asks it) try the recognisers of :data:`BEFORE` (the
course's families of :mod:`rikin.ik.families`, which decide every arm that is not a 6R),
then :data:`FAMILIES` in order, and take the first match, so a family that is a special
case of a later one (a spherical wrist is a special 6R) comes first.

To add a family: write its recogniser (cheap, no solving: it reads the table) and its
solver (the :class:`~rikin.ik.base.Solver` protocol), and insert
``Family(name, recognise)`` into :data:`FAMILIES` before the families it specialises.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..dh import check_arm
from ..errors import InputError
from . import general6r, parallel3, pieper
from .base import Solver
from .pieper import IKClass

if TYPE_CHECKING:  # pragma: no cover
    from ..dh import SerialArm

__all__ = ["Match", "Family", "FAMILIES", "classify", "solver_for"]


@dataclass(frozen=True)
class Match:
    """An arm recognised as one family: its name in words (with how many solutions to
    expect), the solver's constructor, and the most solutions a target has (0: unknown)."""

    family: str
    build: Callable[[SerialArm], Solver]
    solutions: int = 0


@dataclass(frozen=True)
class Family:
    """One family of arms: a short name, and the recogniser (a :class:`Match`, or the
    reason the arm is not of the family)."""

    name: str
    recognise: Callable[[SerialArm], Match | str]


def _spherical_wrist(arm: SerialArm) -> Match | str:
    family, reason = pieper._general_reason(arm)
    if reason:
        return reason
    return Match(f"{family}: up to 8 solutions", pieper.general_solver, 8)


def _parallel(arm: SerialArm) -> Match | str:
    family, reason = parallel3.recognise(arm)
    return reason or Match(family, parallel3.ParallelAxesSolver, 8)


def _general(arm: SerialArm) -> Match | str:
    family, reason = general6r.recognise(arm)
    return reason or Match(family, general6r.General6RSolver, 16)


#: Recognisers tried before :data:`FAMILIES`: the course's families of arms that are not
#: 6R (:mod:`rikin.ik.families` registers its own when :mod:`rikin.ik` is imported). Each
#: returns a Match, the reason the arm has no closed form (then no 6R family is tried), or
#: None to leave the arm to FAMILIES.
BEFORE: list[Callable[[SerialArm], Match | str | None]] = []

#: The families tried, in order (the first that matches solves the arm).
FAMILIES: list[Family] = [
    Family("spherical wrist", _spherical_wrist),
    Family("three parallel axes", _parallel),
    Family("general 6R", _general),
]


def _first_match(arm: SerialArm) -> tuple[Match | None, list[tuple[str, str]]]:
    """The first family's match (or None), and the ``(name, reason)`` of those before it."""
    for before in BEFORE:
        ahead = before(arm)
        if ahead is not None:
            return (ahead, []) if isinstance(ahead, Match) else (None, [("", ahead)])
    reasons: list[tuple[str, str]] = []
    for fam in FAMILIES:
        found = fam.recognise(arm)
        if isinstance(found, Match):
            return found, reasons
        reasons.append((fam.name, found))
    return None, reasons


def _why_not(reasons: list[tuple[str, str]]) -> str:
    """The reasons as one sentence, the first (the most specific family's) first."""
    unique: list[str] = []
    for _, why in reasons:
        if why not in unique:
            unique.append(why)
    return "; ".join(unique)


def _why_not_named(reasons: list[tuple[str, str]]) -> str:
    """``"a spherical wrist: <reason>; three parallel axes: <reason>"``."""
    article = {"spherical wrist": "a spherical wrist"}
    return "; ".join(f"{article.get(name, name)}: {why}" for name, why in reasons)


def classify(arm: SerialArm) -> IKClass:
    """Which closed-form IK rikin uses for ``arm``, or exactly why it has none.

    Parameters
    ----------
    arm : SerialArm

    Returns
    -------
    IKClass
        ``closed_form`` and the family in words with how many solutions to expect
        (e.g. ``"three parallel axes (2, 3, 4), like a UR arm: up to 8 solutions"``),
        or the reason in the arm's terms (e.g. ``"it has 5 joints"``).

    Examples
    --------
    >>> from rikin import robots
    >>> classify(robots.aula10_6r()).closed_form
    True
    """
    check_arm(arm)
    arm = arm._dh  # the geometry, in DH joint values (a reversed joint changes nothing here)
    if arm.solver is not None:
        doc = (type(arm.solver).__doc__ or type(arm.solver).__name__).strip()
        return IKClass(True, " ".join(doc.split("\n\n")[0].split()),
                       solutions=getattr(arm.solver, "count", 0))
    match, reasons = _first_match(arm)
    if match is None:
        return IKClass(False, "", _why_not(reasons), fallback=pieper.NUMERICAL)
    if not reasons:
        return IKClass(True, match.family, solutions=match.solutions)
    # why the simpler families do not apply: the book's reading of the table
    return IKClass(True, f"{match.family} (not {_why_not_named(reasons)})",
                   solutions=match.solutions)


_SOLVERS: weakref.WeakKeyDictionary[SerialArm, Solver] = weakref.WeakKeyDictionary()


def solver_for(arm: SerialArm) -> Solver:
    """The solver of the first family that takes ``arm`` (built once per arm).

    Raises
    ------
    InputError
        No family takes the arm; the message says why and points at the numerical IK.
    """
    check_arm(arm)
    solver = _SOLVERS.get(arm)
    if solver is None:
        match, reasons = _first_match(arm)
        if match is None:
            raise InputError(
                f"{arm.name!r} has no closed-form IK in rikin: {_why_not(reasons)}. "
                "Use rikin.ik.ik_numerical (one solution near a start) or "
                "rikin.ik.ik_numerical_multistart (several)"
            )
        solver = match.build(arm)
        _SOLVERS[arm] = solver
    return solver
