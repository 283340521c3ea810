"""A copy of the exercise generator's tree for tests that change it: solutions/ (with its
catalogues), exercises/ (both languages) and the shared checks file, with
tools/make_exercises.py (loaded as ``mx``) pointed at the copy."""

from __future__ import annotations

import shutil
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parents[1]


def copy_exercise_tree(mx: ModuleType, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Copy the tree into ``tmp_path``, point ``mx`` at it, check it starts up to date."""
    shutil.copytree(ROOT / "solutions", tmp_path / "solutions")
    shutil.copytree(ROOT / "exercises", tmp_path / "exercises")
    (tmp_path / "tools").mkdir()
    shutil.copy(ROOT / "tools" / "exercise_checks.py", tmp_path / "tools")
    monkeypatch.setattr(mx, "ROOT", tmp_path)
    monkeypatch.setattr(mx, "SOLUTIONS", tmp_path / "solutions")
    monkeypatch.setattr(mx, "EXERCISES", tmp_path / "exercises")
    monkeypatch.setattr(mx, "CHECKS_FILE", tmp_path / "tools" / "exercise_checks.py")
    assert mx.generate(check=True) == []
    return tmp_path
