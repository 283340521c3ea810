"""The files a student hands in beside their notebook, given to its cells as Jupyter would.

A kernel started for a notebook runs in the notebook's folder: ``open("lengths.json")``,
``import helper`` and ``%run helper.py`` find the student's own files there. The grader
runs the cells in an empty working folder of its sandbox, so it copies into it, before
the first cell runs, the files that are that student's own, under the names the cells use:

- a student's folder (one folder per student, a Moodle or Brightspace student folder,
  nbgrader's tree): every file below the folder that holds the notebook, sub-folders too
  (hidden files and folders, ``__pycache__``, checkpoints and system files are left out,
  as when submissions are found);
- a flat LMS download (everyone's files in one folder): the other files the LMS's names
  give to the same student, each under the name the student gave it (the LMS's ``orig``).

Each file is read through the grader's safe reader (:mod:`rikingrade.studentfiles`: no
link followed, one name, the rights of whoever handed it in, at most a size), at most
:data:`MAX_FILES` files and :data:`MAX_TOTAL_BYTES` together; a file not given says why
in the student's feedback. The files count in the submission's identity
(:func:`identity`): a changed helper file is a changed submission.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass, field
from pathlib import Path

from .filereader import GONE, HARD_LINK, LINK, NO_RIGHT, NOT_A_FILE, TOO_LARGE, UNREADABLE
from .i18n import N_, t
from .studentfiles import ReadFailed, StudentFiles

#: Files given to one notebook's cells at most (the rest are named in a note).
MAX_FILES = 200
#: Bytes of one file at most (also at most the sandbox's largest file, ``max_file_mb``).
MAX_FILE_BYTES = 16 * 1024 * 1024
#: Bytes of all the files of one submission together.
MAX_TOTAL_BYTES = 48 * 1024 * 1024
#: Folders never copied (as when submissions are found), and how deep folders are copied.
SKIP_DIRS = {".ipynb_checkpoints", "__pycache__", "__MACOSX", ".git"}
SYSTEM_FILES = {".ds_store", "thumbs.db", "desktop.ini"}
MAX_DEPTH = 8


@dataclass
class Handed:
    """The files read for one submission: ``files`` (name in the working folder, bytes)
    to copy, and ``notes`` on the files not given (for the student's feedback)."""

    files: list[tuple[str, bytes]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    digests: list[str] = field(default_factory=list)  # one line per file, for identity()


def safe_name(name: str) -> bool:
    """Whether ``name`` is a relative path of plain names (no ``..``, no root, no NUL)."""
    if not name or "\0" in name or name.startswith(("/", "\\")):
        return False
    parts = name.split("/")
    return all(p not in ("", ".", "..") and "\\" not in p for p in parts)


def beside(notebook: Path) -> list[tuple[str, Path]]:
    """The files below the folder of ``notebook`` (a student's own folder), but for the
    notebook itself: (name relative to that folder, path). Links are listed, not followed
    (reading refuses them with the reason); at most ``MAX_FILES + 1`` are listed."""
    top = Path(notebook).parent
    out: list[tuple[str, Path]] = []
    stack: list[tuple[Path, str, int]] = [(top, "", 0)]
    while stack and len(out) <= MAX_FILES:
        folder, prefix, depth = stack.pop()
        try:
            entries = sorted(os.scandir(folder), key=lambda e: os.fsencode(e.name))
        except OSError:
            continue
        subs = []
        for e in entries:
            name = os.fsdecode(e.name)
            if name.startswith(".") or name.lower() in SYSTEM_FILES:
                continue
            path = Path(e.path)
            if e.is_dir(follow_symlinks=False):
                if name not in SKIP_DIRS and depth < MAX_DEPTH:
                    subs.append((path, f"{prefix}{name}/", depth + 1))
            elif path != Path(notebook):
                out.append((prefix + name, path))
        stack += reversed(subs)
    return out[: MAX_FILES + 1]


def _why(exc: ReadFailed, file_cap: int) -> str:
    """Why the safe reader did not give a file, in the feedback's language (the reader's
    own English ``why`` when the refusal has no code)."""
    if exc.kind == TOO_LARGE:
        return t("larger than the {mib} MiB a file handed in may have ({size} bytes)",
                 mib=file_cap // (1024 * 1024), size=exc.size)
    if exc.kind == GONE:
        return t("it was no longer there (moved or deleted during grading)")
    words = {
        LINK: N_("a symbolic link (or a folder on its path is one): links are not followed"),
        HARD_LINK: N_("a hard link (several names for one file): a file linked in from "
                      "elsewhere is not read"),
        NOT_A_FILE: N_("not a regular file"),
        NO_RIGHT: N_("it may not be read with the rights of whoever handed it in"),
        UNREADABLE: N_("it could not be read"),
    }
    return t(words[exc.reason]) if exc.reason in words else exc.why


def _not_given(name: str, why: str) -> str:
    return t("{name}: not given to the notebook's cells: {why}", name=name, why=why)


def read(files: StudentFiles, root: Path, listed: list[tuple[str, Path]],
         file_cap: int = MAX_FILE_BYTES) -> Handed:
    """The files ``listed`` (name, path below the submissions folder ``root``), read with
    the safe reader; each one refused, too large, beyond the count or the total cap is
    left out with a note saying why, in the feedback's language (:func:`rikingrade.i18n.t`:
    call it inside the notebook's :func:`rikingrade.i18n.use`)."""
    out = Handed()
    file_cap = min(file_cap, MAX_FILE_BYTES)
    total = 0
    for i, (name, path) in enumerate(listed):
        if i >= MAX_FILES:
            out.notes.append(t(
                "only the first {count} files handed in beside the notebook were given to its "
                "cells (more were found; {name} and the rest were not given)",
                count=MAX_FILES, name=name))
            out.digests.append(f"more than {MAX_FILES}")
            break
        if not safe_name(name):
            out.notes.append(_not_given(repr(name), t("not a plain file name")))
            out.digests.append(f"{name}\0bad name")
            continue
        try:
            data = files.read(root, path, file_cap)
        except ReadFailed as exc:
            out.notes.append(_not_given(name, _why(exc, file_cap)))
            out.digests.append(f"{name}\0{exc.kind}\0{exc.size}")
            continue
        if total + len(data) > MAX_TOTAL_BYTES:
            out.notes.append(_not_given(name, t(
                "the files handed in beside the notebook may have {mib} MiB together",
                mib=MAX_TOTAL_BYTES // (1024 * 1024))))
            out.digests.append(f"{name}\0total\0{len(data)}")
            continue
        total += len(data)
        out.files.append((name, bytes(data)))
        out.digests.append(f"{name}\0{hashlib.sha256(data).hexdigest()}")
    return out


def identity(notebook_sha: str, digests: list[str]) -> str:
    """The submission's sha256: the notebook's own when nothing is handed in beside it
    (as before these files were read), else one over the notebook and every file."""
    if not digests:
        return notebook_sha
    h = hashlib.sha256(b"rikin-submission\0" + notebook_sha.encode())
    for line in digests:
        h.update(b"\n" + line.encode("utf-8", "surrogateescape"))
    return h.hexdigest()
