"""Shared setup of the grader tests: the fake exercise, and whether a sandbox can run here."""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

FIXTURES = Path(__file__).resolve().parent
ASSIGNMENT = FIXTURES / "fake2r.py"
SOLUTION = FIXTURES / "fake2r_solution.ipynb"

#: Small limits, so hostile submissions stay cheap on a shared machine.
FAST = {"memory_mb": 512, "cell_timeout": 2.0, "cpu_seconds": 30, "quiet": True}


@functools.lru_cache(maxsize=1)
def _bwrap_problem() -> str:
    from rikingrade.sandbox.config import SandboxConfig, bwrap_works

    return bwrap_works(SandboxConfig())


def require_bwrap() -> None:
    """Fail (never skip) when the bubblewrap sandbox cannot run here, saying why.

    A grader test that cannot run is not a pass: without bubblewrap, or where it cannot
    create namespaces, every sandbox test fails with the reason and how to fix it.
    """
    why = _bwrap_problem()
    if why:
        how = (
            "install it: python3 tools/dev.py test does as root (apt-get install -y "
            "bubblewrap); elsewhere: sudo apt-get install -y bubblewrap (Debian/Ubuntu) or "
            "sudo dnf install -y bubblewrap (Fedora)"
        )
        pytest.fail(f"the grader's sandbox cannot run here: {why}\n{how}", pytrace=False)
