"""rikingrade: the instructor side: reference solutions, hidden tests, the autograder.

Never imported by student code; not shipped in the exercises or the book.
"""

__version__ = "0.1.0"
