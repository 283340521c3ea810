"""Reading submissions without running them: find notebooks, extract their code cells.

A submission is read as data only (JSON), leniently: notebooks saved by classic Jupyter,
JupyterLab 4, Notebook 7 or Colab (any nbformat 4.x minor, extra metadata, missing or
duplicate cell ids, sources as strings or lists of lines) and nbformat 3 worksheets all give
their code cells in file order, the order "Run All" would use. What cannot be read gets a
clear reason instead of an exception.
"""

from __future__ import annotations

import difflib
import hashlib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path

MAX_NOTEBOOK_BYTES = 100 * 1024 * 1024
SKIP_DIRS = {".ipynb_checkpoints", "__pycache__", "__MACOSX", ".git"}


class NotebookError(ValueError):
    """A submission that is not a readable notebook; the message is shown to the student."""


@dataclass
class Notebook:
    """The code cells of one submission, in file order.

    cells : (number, source) with ``number`` counting code cells from 1, as the feedback
        calls them ("code cell 3").
    warnings : things worth telling (duplicate ids, nbformat 3, ...); never fatal.
    """

    cells: list[tuple[int, str]]
    nbformat: str
    warnings: list[str] = field(default_factory=list)


@dataclass
class Submission:
    """One student's notebook file."""

    student: str
    path: Path
    sha256: str = ""

    def hash(self) -> str:
        if not self.sha256:
            h = hashlib.sha256()
            with open(self.path, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    h.update(block)
            self.sha256 = h.hexdigest()
        return self.sha256


def _source(value: object) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, list):
        return "".join(x for x in value if isinstance(x, str))
    return ""


def read_notebook(path: Path) -> Notebook:
    """The code cells of the notebook at ``path``.

    Raises
    ------
    NotebookError
        Not a file, too large, not UTF-8 JSON, or JSON that is not a notebook.
    """
    path = Path(path)
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise NotebookError(f"cannot read the file: {exc.strerror}") from None
    if size == 0:
        raise NotebookError("the file is empty (0 bytes): it was probably not saved")
    if size > MAX_NOTEBOOK_BYTES:
        raise NotebookError(
            f"the file is {size / 2**20:.0f} MiB, over the {MAX_NOTEBOOK_BYTES // 2**20} MiB "
            "limit (clear the outputs and save again)"
        )
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise NotebookError(
            f"the file is not a notebook: it is not UTF-8 text (byte {exc.start})"
        ) from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise NotebookError(
            f"the file is not valid notebook JSON (line {exc.lineno}, column {exc.colno}: "
            f"{exc.msg}); it may be truncated or edited by hand. Open it in Jupyter and "
            "save it again"
        ) from None
    except RecursionError:
        raise NotebookError("the file is not a notebook: JSON nested too deeply") from None
    if not isinstance(data, dict):
        raise NotebookError("the file is JSON but not a notebook (no top-level object)")
    warnings: list[str] = []
    major = data.get("nbformat")
    minor = data.get("nbformat_minor")
    version = f"{major}.{minor}" if major is not None else "unknown"
    if isinstance(data.get("cells"), list):
        raw_cells = data["cells"]
        src_key = "source"
    elif isinstance(data.get("worksheets"), list):
        raw_cells = []
        for ws in data["worksheets"]:
            if isinstance(ws, dict) and isinstance(ws.get("cells"), list):
                raw_cells.extend(ws["cells"])
        src_key = "input"
        warnings.append("old notebook format (nbformat 3): read anyway")
    else:
        raise NotebookError("the file is JSON but not a notebook (it has no 'cells')")
    cells: list[tuple[int, str]] = []
    ids: dict[str, int] = {}
    dup = 0
    for c in raw_cells:
        if not isinstance(c, dict):
            continue
        cid = c.get("id")
        if isinstance(cid, str):
            ids[cid] = ids.get(cid, 0) + 1
            dup += ids[cid] == 2
        if c.get("cell_type") != "code":
            continue
        src = _source(c.get(src_key, c.get("source")))
        cells.append((len(cells) + 1, src))
    if dup:
        warnings.append(f"{dup} duplicated cell id(s) (ignored)")
    return Notebook(cells=cells, nbformat=version, warnings=warnings)


_SAFE = re.compile(r"[^\w.@+-]+")


def safe_id(name: str) -> str:
    """A student id usable as a file name (letters, digits, ``_`` and ``.@+-``)."""
    s = _SAFE.sub("_", name).strip("._") or "student"
    return s[:120]


def _notebooks_in(folder: Path) -> list[Path]:
    out = []
    for p in sorted(folder.rglob("*.ipynb")):
        if any(part in SKIP_DIRS for part in p.relative_to(folder).parts[:-1]):
            continue
        if p.is_file():
            out.append(p)
    return out


def pick_notebook(candidates: list[Path], expected: str) -> tuple[Path | None, str]:
    """The student's notebook among ``candidates`` (the expected name wins), with a note."""
    if not candidates:
        return None, ""
    if len(candidates) == 1:
        return candidates[0], ""
    exact = [p for p in candidates if p.name == expected]
    if exact:
        others = ", ".join(p.name for p in candidates if p != exact[0])
        return exact[0], f"several notebooks found; graded {exact[0].name} (also found: {others})"
    stem = Path(expected).stem.lower()
    named = [p for p in candidates if stem and stem in p.stem.lower()]
    pool = named or candidates
    best = max(
        pool,
        key=lambda p: (difflib.SequenceMatcher(None, p.name, expected).ratio(), p.stat().st_mtime),
    )
    others = ", ".join(p.name for p in candidates if p != best)
    return best, f"several notebooks found; graded {best.name} (also found: {others})"


def discover(paths: list[Path | str], expected: str) -> tuple[list[Submission], list[str]]:
    """Submissions from files and folders, with one warning per thing skipped.

    Each ``.ipynb`` argument is one student (id = file name without extension). A folder
    holds a class: each ``.ipynb`` directly inside is one student (id = its stem), and each
    sub-folder is one student (id = folder name; the notebook named ``expected`` is taken,
    or the only/most similar ``.ipynb`` inside).
    """
    subs: list[Submission] = []
    notes: list[str] = []
    for arg in paths:
        p = Path(arg)
        if p.is_file():
            if p.suffix.lower() != ".ipynb":
                notes.append(f"{p}: not a .ipynb file, skipped")
                continue
            subs.append(Submission(safe_id(p.stem), p))
        elif p.is_dir():
            for entry in sorted(p.iterdir()):
                if entry.name in SKIP_DIRS or entry.name.startswith("."):
                    continue
                if entry.is_file() and entry.suffix.lower() == ".ipynb":
                    subs.append(Submission(safe_id(entry.stem), entry))
                elif entry.is_dir():
                    nb, note = pick_notebook(_notebooks_in(entry), expected)
                    if nb is None:
                        notes.append(f"{entry}: no .ipynb inside, skipped")
                        continue
                    if note:
                        notes.append(f"{entry.name}: {note}")
                    subs.append(Submission(safe_id(entry.name), nb))
        else:
            notes.append(f"{p}: no such file or folder")
    taken: set[str] = set()
    for s in subs:
        if s.student in taken:
            k = 2
            while f"{s.student}-{k}" in taken:
                k += 1
            new = f"{s.student}-{k}"
            notes.append(f"two submissions named {s.student}: {s.path} graded as {new}")
            s.student = new
        taken.add(s.student)
    return subs, notes
