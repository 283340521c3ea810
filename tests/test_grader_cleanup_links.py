"""Cleaning up after a uid sandbox never changes a file outside what the sandbox left.

``_make_removable`` gives a left folder tree its bits back before it is removed. A student's
process may swap a folder for a link to a file or folder of the grader's at any moment: the
cleanup must change nothing through it. The swap is made deterministic here: the first
time the cleanup touches the victim folder by any name (a check, a stat, an open), the
folder is replaced by a link right after that call returns, the worst moment for a check
followed by a change.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest
from rikingrade.sandbox import uidmode


def _mode(p: Path) -> int:
    return stat.S_IMODE(os.lstat(p).st_mode)


def _outside(tmp_path: Path) -> tuple[Path, Path]:
    """A file and a folder (with a sub-folder) of the grader's, outside the left tree."""
    keep = tmp_path / "grader"
    (keep / "sub").mkdir(parents=True)
    secret = keep / "hidden_tests.py"
    secret.write_text("SECRET = 1\n", encoding="utf-8")
    os.chmod(secret, 0o600)
    os.chmod(keep / "sub", 0o755)
    return secret, keep


def _swap_after_first_touch(monkeypatch, victim: Path, target: Path) -> list[str]:
    """Replace the folder ``victim`` by a link to ``target`` right after the first call of
    a path check, stat or open that names it (by path, or by name relative to a folder)."""
    done: list[str] = []

    def swap() -> None:
        if not done:
            os.rename(victim, victim.with_name("moved-away"))
            os.symlink(target, victim)
            done.append("swapped")

    def names_victim(args, kw) -> bool:
        p = os.fsdecode(args[0]) if args and isinstance(args[0], (str, bytes, os.PathLike)) else ""
        return p == str(victim) or (p == victim.name and kw.get("dir_fd") is not None)

    for mod, name in [(os.path, "islink"), (os.path, "isdir"), (os, "lstat"), (os, "stat"),
                      (os, "open")]:
        real = getattr(mod, name)

        def wrapped(*args, _real=real, **kw):
            out = _real(*args, **kw)
            if names_victim(args, kw):
                swap()
            return out

        monkeypatch.setattr(mod, name, wrapped)
    return done


@pytest.mark.parametrize("target", ["file", "folder"])
def test_a_folder_swapped_for_a_link_mid_cleanup_changes_nothing_outside(
    tmp_path, monkeypatch, target
):
    secret, keep = _outside(tmp_path)
    left = tmp_path / "tmp" / "left-by-sandbox"
    victim = left / "a" / "victim"
    (victim / "deeper").mkdir(parents=True)
    os.chmod(victim / "deeper", 0)
    os.chmod(victim, 0)
    before = {p: _mode(p) for p in (secret, keep, keep / "sub")}
    done = _swap_after_first_touch(monkeypatch, victim, secret if target == "file" else keep)
    uidmode._make_removable(str(left))
    monkeypatch.undo()
    assert done == ["swapped"]  # the cleanup did look at the victim: the race was run
    assert {p: _mode(p) for p in before} == before
    assert _mode(left / "a") == 0o700  # the rest of the tree still got its bits back


def test_a_left_folder_that_is_a_link_is_not_walked(tmp_path):
    """The folder itself swapped for a link between the sweep's lstat and the cleanup."""
    secret, keep = _outside(tmp_path)
    link = tmp_path / "tmp" / "left-by-sandbox"
    link.parent.mkdir()
    os.symlink(keep, link)
    before = {p: _mode(p) for p in (secret, keep, keep / "sub")}
    uidmode._make_removable(str(link))
    assert {p: _mode(p) for p in before} == before


def test_folders_left_with_no_bits_get_them_back(tmp_path):
    left = tmp_path / "left"
    (left / "a" / "b" / "c").mkdir(parents=True)
    (left / "a" / "f.txt").write_text("x", encoding="utf-8")
    for d in (left / "a" / "b" / "c", left / "a" / "b", left / "a"):
        os.chmod(d, 0)
    uidmode._make_removable(str(left))
    assert [_mode(d) for d in (left / "a", left / "a" / "b", left / "a" / "b" / "c")] == [
        0o700
    ] * 3
