"""Shared setup of the grader tests: the fake exercise, and whether a sandbox can run here."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

FIXTURES = Path(__file__).resolve().parent
ASSIGNMENT = FIXTURES / "fake2r.py"
SOLUTION = FIXTURES / "fake2r_solution.ipynb"

#: Small limits, so hostile submissions stay cheap on a shared machine.
FAST = {"memory_mb": 512, "cell_timeout": 2.0, "cpu_seconds": 30, "quiet": True}


def require_bwrap() -> None:
    """Skip without bubblewrap locally; in CI (CI=true) its absence is a failure."""
    if shutil.which("bwrap") is None:
        msg = "bubblewrap is not installed (apt-get install -y bubblewrap)"
        if os.environ.get("CI"):
            pytest.fail(msg + ": CI must install it")
        pytest.skip(msg)
