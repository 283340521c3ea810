"""The grader's version, in a module of its own: the package's ``__init__`` and the modules
it loads lazily (``api``, ``gradescope``, ``repair``, ``cli``) import it from here, so none of
them imports the package that imports them."""

__version__ = "0.1.0"
