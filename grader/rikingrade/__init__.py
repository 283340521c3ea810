"""rikingrade: the instructor side: reference solutions, hidden tests, the autograder.

Never imported by student code; not shipped in the exercises or the book.

>>> from rikingrade import grade                                    # doctest: +SKIP
>>> report = grade("scara", ["submissions/"], "graded/")            # doctest: +SKIP
>>> report.summary["mean_score"]                                    # doctest: +SKIP
"""

from ._version import __version__

__all__ = ["__version__", "grade", "check_sandbox", "gradescope_bundle"]


def __getattr__(name: str):
    # Lazy, so that hidden-test modules importing rikingrade.spec stay light.
    if name == "grade":
        from .api import grade

        return grade
    if name == "check_sandbox":
        from .probe import check_sandbox

        return check_sandbox
    if name == "gradescope_bundle":
        from .gradescope import gradescope_bundle

        return gradescope_bundle
    raise AttributeError(f"module 'rikingrade' has no attribute {name!r}")
