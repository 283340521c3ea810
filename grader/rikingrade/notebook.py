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
import logging
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path

from . import handedfiles
from .i18n import notebook_language
from .safetext import printable
from .studentfiles import REFUSED, TOO_LARGE, ReadFailed, StudentFiles, default_files

log = logging.getLogger("rikingrade")

MAX_NOTEBOOK_BYTES = 100 * 1024 * 1024
SKIP_DIRS = {".ipynb_checkpoints", "__pycache__", "__MACOSX", ".git"}
#: The file the grader puts in its output folder: a folder holding it is the grader's own
#: output (``--out`` inside the class folder, this run's or an earlier one), never a student.
OUTPUT_MARK = ".rikin-grade-output"


class NotebookError(ValueError):
    """A submission that is not a readable notebook; the message is shown to the student."""


class FileRefused(NotebookError):
    """A file the grader will not read (a link, or one its folder's owner may not read)."""


def _too_large(size: int) -> str:
    return (
        f"the file is {size / 2**20:.0f} MiB, over the {MAX_NOTEBOOK_BYTES // 2**20} MiB "
        "limit (clear the outputs and save again)"
    )


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
    #: the notebook's language ("en", "es"): its feedback is written in it (rikingrade.i18n)
    language: str = "en"


@dataclass
class Submission:
    """One student's notebook file, and where it came from.

    ``student`` is the id in every output (unique in a batch, a file name); ``source`` the
    path as given, for the instructor; ``lms``/``lms_id``/``name`` what the download name
    says (see :mod:`rikingrade.lms`); ``submitted_at`` when it was handed in (from the name
    or nbgrader's timestamp, else the file's modification time: ``time_source`` says which);
    ``earlier`` the student's older attempts, kept in the gradebook but not graded.
    """

    student: str
    path: Path
    sha256: str = ""
    name: str = ""
    lms: str = ""
    lms_id: str = ""
    submitted_at: float | None = None
    time_source: str = ""
    late: bool = False
    email: str = ""
    sis_id: str = ""
    section: str = ""
    login: str = ""
    earlier: list[Submission] = field(default_factory=list)
    refused: str = ""  # why the file is not read at all (a link): graded 0 with this reason
    #: the submissions folder it was found in (files are read relative to it), and whether
    #: the instructor named the file itself (then a hard link is read: they chose it)
    root: Path | None = None
    named: bool = False
    files: StudentFiles | None = field(default=None, repr=False, compare=False)
    #: Canvas's attachment id of the file (its re-upload pairs feedback with it), and the
    #: student's name as the download wrote it (the roster's may replace ``name``)
    file_id: str = ""
    download_name: str = ""
    #: the roster row it matched (``roster.RosterEntry.key``), or why none:
    #: ``ambiguous:<name>`` (several fit) or ``absent`` (not on the roster)
    roster_key: str = ""
    #: the student's other files, given to the cells (see :mod:`rikingrade.handedfiles`):
    #: (name in the working folder, path)
    handed: list[tuple[str, Path]] = field(default_factory=list)
    _digests: list[str] | None = field(default=None, repr=False, compare=False)

    def read_bytes(self, cap: int = MAX_NOTEBOOK_BYTES) -> bytes:
        """The file's bytes, read without privileges it should not need (see
        :mod:`rikingrade.studentfiles`).

        Raises
        ------
        ReadFailed
            Refused (a link, a file its folder's owner may not read), larger than ``cap``
            or gone.
        """
        files = self.files or default_files()
        return files.read(self.root or self.path.parent, self.path, cap, links=self.named)

    def read_handed(self, file_cap: int = handedfiles.MAX_FILE_BYTES) -> handedfiles.Handed:
        """The files handed in beside the notebook, read as :meth:`read_bytes` does."""
        return handedfiles.read(
            self.files or default_files(), self.root or self.path.parent, self.handed, file_cap
        )

    def _identity(self, notebook_sha: str) -> str:
        """The submission's sha256 from the notebook's: with its other files when it has
        some (:func:`rikingrade.handedfiles.identity`)."""
        if self._digests is None:
            self._digests = self.read_handed().digests if self.handed else []
        return handedfiles.identity(notebook_sha, self._digests)

    def hash(self) -> str:
        """The sha256 of the file (of the refusal, for a file that is not read), and of the
        files handed in beside it when there are some.

        A file the grader refuses to read gets ``refused`` set here, with the reason.
        """
        if not self.sha256 and not self.refused:
            try:
                self.sha256 = self._identity(hashlib.sha256(self.read_bytes()).hexdigest())
            except ReadFailed as exc:
                if exc.kind == REFUSED:
                    self.refused = exc.why
                else:  # too large or gone: read_notebook says so when grading
                    text = f"{exc.kind}\0{exc.size}\0{shown(self.path)}"
                    self.sha256 = hashlib.sha256(text.encode()).hexdigest()
        if not self.sha256 and self.refused:
            self.sha256 = self._refused_identity()
        return self.sha256

    def _refused_identity(self) -> str:
        """The sha256 of a refused file: of the refusal, the path and a link's target, and
        of the file's bytes when they can be read (a .zip or a script handed in instead of
        a notebook), so that the same file is one submission and a changed file a new one."""
        try:
            st = os.lstat(self.path)
        except OSError:
            st = None
        link = os.readlink(self.path) if st and stat.S_ISLNK(st.st_mode) else ""
        content = ""
        if st and stat.S_ISREG(st.st_mode):
            try:
                content = hashlib.sha256(self.read_bytes()).hexdigest()
            except ReadFailed as exc:
                content = f"{exc.kind}\0{exc.size}"
        text = f"refused\0{self.refused}\0{shown(self.path)}\0{shown(link)}\0{content}"
        return hashlib.sha256(text.encode()).hexdigest()

    def load(self) -> Notebook:
        """The notebook's code cells, read as :meth:`read_bytes` does (``sha256`` follows
        what was read, should the file have changed since it was hashed).

        Raises
        ------
        NotebookError
            Unreadable, refused (``FileRefused``), too large, or not a notebook.
        """
        try:
            raw = self.read_bytes()
        except ReadFailed as exc:
            if exc.kind == TOO_LARGE:
                raise NotebookError(_too_large(exc.size)) from None
            if exc.kind == REFUSED:
                self.refused = exc.why
                raise FileRefused(f"not read: {exc.why}") from None
            raise NotebookError(f"cannot read the file: {exc.why}") from None
        sha = self._identity(hashlib.sha256(raw).hexdigest())
        if self.sha256 and sha != self.sha256:
            log.warning("%s: %s changed since it was found", self.student, self.shown_path)
        self.sha256 = sha
        return parse_notebook(raw)

    @property
    def shown_path(self) -> str:
        """The path as text that any output can hold (undecodable bytes as ``\\xff``)."""
        return shown(self.path)


def shown(path: Path | str) -> str:
    """A path as printable UTF-8 text, whatever bytes its name holds (no control
    characters: see :func:`rikingrade.safetext.printable`)."""
    return printable(os.fsencode(path).decode("utf-8", "backslashreplace"))


def _open_student_file(path: Path):
    """Open a student's file for reading without following a link at its last component."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0))
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise OSError(f"{shown(path)}: not a regular file")
    return os.fdopen(fd, "rb")


def _source(value: object) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, list):
        return "".join(x for x in value if isinstance(x, str))
    return ""


def read_notebook(path: Path) -> Notebook:
    """The code cells of the notebook at ``path`` (a link at its last name is not followed).

    Raises
    ------
    NotebookError
        Not a file, too large, not UTF-8 JSON, or JSON that is not a notebook.
    """
    path = Path(path)
    try:
        with _open_student_file(path) as f:
            size = os.fstat(f.fileno()).st_size
            if size > MAX_NOTEBOOK_BYTES:
                raise NotebookError(_too_large(size))
            raw = f.read(MAX_NOTEBOOK_BYTES + 1)
    except OSError as exc:
        raise NotebookError(f"cannot read the file: {exc.strerror or exc}") from None
    if len(raw) > MAX_NOTEBOOK_BYTES:
        raise NotebookError(_too_large(len(raw)))
    return parse_notebook(raw)


def parse_notebook(raw: bytes) -> Notebook:
    """The code cells of a notebook file's bytes (see :func:`read_notebook`).

    Raises
    ------
    NotebookError
        Empty, not UTF-8, JSON that Jupyter cannot open (invalid, a number too long for
        Python's reader, nested too deeply), or JSON that is not a notebook (no cells, a
        cell or field of the wrong kind: a ``source`` that is a number, ``metadata`` a
        list, ...).
    """
    if not raw:
        raise NotebookError("the file is empty (0 bytes): it was probably not saved")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise NotebookError(
            f"the file is not a notebook: it is not UTF-8 text (byte {exc.start})"
        ) from None
    data = _json(text)
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
    why = _not_a_notebook(data, raw_cells, src_key)
    if why:
        raise NotebookError(
            f"not a notebook: {why}; Jupyter cannot open it either (was it edited by hand "
            "or made by another program? Save it again from Jupyter)"
        )
    cells: list[tuple[int, str]] = []
    ids: dict[str, int] = {}
    dup = 0
    for c in raw_cells:
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
    lang = notebook_language(data.get("metadata"), [src for _, src in cells])
    return Notebook(cells=cells, nbformat=version, warnings=warnings, language=lang)


def _json(text: str) -> object:
    """The file's JSON, or NotebookError saying why Jupyter could not open it either."""
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise NotebookError(
            f"the file is not valid notebook JSON (line {exc.lineno}, column {exc.colno}: "
            f"{exc.msg}); it may be truncated or edited by hand. Open it in Jupyter and "
            "save it again"
        ) from None
    except RecursionError:
        raise NotebookError("the file is not a notebook: JSON nested too deeply") from None
    except (ValueError, MemoryError) as exc:  # e.g. a number of more than 4,300 digits
        digits = "a number with more digits than Python reads" if "digits" in str(exc) else ""
        raise NotebookError(
            "JSON that Jupyter cannot open: "
            + (digits or f"{type(exc).__name__} while reading it")
            + "; it was not saved by Jupyter (edited by hand or by another program?)"
        ) from None


_CELL_TYPES = {"code", "markdown", "raw", "heading"}  # heading: nbformat 3
_KIND = {
    bool: "true/false",
    int: "a number",
    float: "a number",
    str: "text",
    list: "a list",
    dict: "an object",
    type(None): "null",
}


def _kind(v: object) -> str:
    return _KIND.get(type(v), type(v).__name__)


def _not_a_notebook(data: dict, raw_cells: list, src_key: str) -> str:
    """What makes ``data`` something Jupyter cannot open as a notebook, or ''.

    Only the kinds of the fields Jupyter reads are checked (a notebook from any Jupyter,
    JupyterLab, Colab or nbformat 3 passes; missing ids, extra metadata and duplicates do).
    """
    for key, ok in (("metadata", dict), ("nbformat", int), ("nbformat_minor", int)):
        v = data.get(key, ok())
        if not isinstance(v, ok) or isinstance(v, bool):
            return f"its {key!r} is {_kind(v)}, not {_kind(ok())}"
    for i, c in enumerate(raw_cells, 1):
        if not isinstance(c, dict):
            return f"cell {i} is {_kind(c)}, not an object"
        kind = c.get("cell_type")
        if kind not in _CELL_TYPES:
            what = repr(kind)[:40] if isinstance(kind, str) else _kind(kind)
            return f"cell {i} has cell_type {what} (a cell is code, markdown or raw)"
        src = c.get(src_key, c.get("source", ""))
        if not (
            isinstance(src, str) or (isinstance(src, list) and all(isinstance(x, str) for x in src))
        ):
            return f"the source of cell {i} is {_kind(src)}, not text"
        if not isinstance(c.get("metadata", {}), dict):
            return f"the metadata of cell {i} is {_kind(c['metadata'])}, not an object"
        outputs = c.get("outputs", [])
        if not isinstance(outputs, list) or not all(isinstance(o, dict) for o in outputs):
            return f"the outputs of cell {i} are not a list of objects"
    return ""


# ----------------------------------------------------------------------------- discovery
_SAFE = re.compile(r"[^\w.@+-]+")

#: Folders searched below a student's folder (deeper ones are reported, not searched).
MAX_DEPTH = 8


class SubmissionsError(ValueError):
    """The paths given are not a class; the message says what was found and what to pass."""


def safe_id(name: str) -> str:
    """A student id usable as a file name and a CSV cell (letters, digits, ``_`` and ``.@+-``).

    It never starts with ``+ - @ =`` (a spreadsheet would read a formula) or a dot.
    """
    s = _SAFE.sub("_", name).strip("._").lstrip("+-@._") or "student"
    return s[:120]


def _tag(raw: str) -> str:
    return hashlib.sha256(os.fsencode(raw)).hexdigest()[:6]


def student_id(raw: str) -> str:
    """The id of a student known only by a file or folder name.

    The name itself when it is already a safe id; otherwise the safe form plus a short
    hash of the exact name, so that ``al ice`` and ``al_ice`` stay two students whatever
    order they are found in, and each id leads back to its file.
    """
    s = safe_id(raw)
    return s if s == raw else f"{s[:113]}-{_tag(raw)}"


def _refusal(entry: os.DirEntry | Path) -> str:
    """Why a path in the submissions is not read, or ''."""
    try:
        st = os.lstat(entry)
    except OSError as exc:
        return f"cannot be read ({exc.strerror})"
    if stat.S_ISLNK(st.st_mode):
        return "a symbolic link: links are not followed"
    if stat.S_ISREG(st.st_mode) and st.st_nlink > 1:
        return "a hard link to a file elsewhere: not read"
    return ""


#: Files that systems leave in folders (never a student's work): skipped with a note.
SYSTEM_FILES = {".ds_store", "thumbs.db", "desktop.ini"}
_ARCHIVES = (".zip", ".tar", ".tgz", ".tar.gz", ".gz", ".7z", ".rar", ".bz2", ".xz")


def not_a_notebook(name: str, kind: str = "file") -> str:
    """Why a file handed in is not graded (it is not a notebook), in a few words."""
    low = name.lower()
    if kind == "text":
        return f"an online text entry ({name}), not a notebook: ask for the .ipynb file"
    if kind == "link":
        return f"a web link ({name}), not a notebook: ask for the .ipynb file"
    if low.endswith(_ARCHIVES):
        return "a .zip (or other archive): unzip it first and grade the notebook inside"
    if low.endswith(".py"):
        return "an exported script, not a notebook: ask for the .ipynb file"
    if ".ipynb" in low:
        return (
            f"named {name}, not .ipynb (renamed by a browser?): rename it to end in .ipynb "
            "and grade it again"
        )
    ext = os.path.splitext(name)[1]
    return f"not a notebook ({ext or 'a file with no extension'})"


def _scan(
    folder: Path, notes: list[str], refused: list[tuple[Path, str]] | None = None
) -> tuple[list[Path], list[Path], list[Path]]:
    """(notebook files, sub-folders, other files) directly in ``folder``.

    Links are not followed: a symbolic link to a notebook or a folder, and a hard-linked
    notebook, go into ``refused`` with the reason (and a note). Hidden files and folders
    and the files systems leave (``.DS_Store``, ``Thumbs.db``) are skipped with a note.
    """
    refused = [] if refused is None else refused
    files: list[Path] = []
    dirs: list[Path] = []
    other: list[Path] = []
    try:
        entries = sorted(os.scandir(folder), key=lambda e: os.fsencode(e.name))
    except OSError as exc:
        notes.append(f"{shown(folder)}: cannot be listed ({exc.strerror})")
        return files, dirs, other
    for e in entries:
        path = Path(e.path)
        if e.is_symlink():
            notes.append(f"{shown(path)}: a symbolic link: links are not followed, skipped")
            refused.append((path, "a symbolic link: links are not followed"))
            continue
        if e.is_dir(follow_symlinks=False):
            if e.name in SKIP_DIRS:
                continue
            if os.path.isfile(os.path.join(e.path, OUTPUT_MARK)):
                notes.append(f"{shown(path)}: the grader's own output folder, skipped")
                continue
            if e.name.startswith("."):
                notes.append(
                    f"{shown(path)}: a hidden folder (name starts with '.'), skipped: "
                    "pass it by name to grade it"
                )
                continue
            dirs.append(path)
        elif e.name.startswith(".") or e.name.lower() in SYSTEM_FILES:
            system = e.name.lower() in SYSTEM_FILES or e.name.startswith("._")
            what = "a system file" if system else "a hidden file (name starts with '.')"
            notes.append(f"{shown(path)}: {what}, skipped")
        elif e.name.lower().endswith(".ipynb"):
            why = _refusal(e)
            if why:
                notes.append(f"{shown(path)}: {why}, skipped")
                refused.append((path, why))
            else:
                files.append(path)
        else:
            other.append(path)
    return files, dirs, other


def _notebooks_in(
    folder: Path,
    notes: list[str] | None = None,
    refused: list[tuple[Path, str]] | None = None,
    others: list[Path] | None = None,
) -> list[Path]:
    """Every notebook below ``folder`` (iteratively, links not followed, at most MAX_DEPTH);
    the other files found go into ``others``."""
    notes = [] if notes is None else notes
    out: list[Path] = []
    stack = [(Path(folder), 0)]
    deep = False
    while stack:
        d, depth = stack.pop()
        files, dirs, other = _scan(d, notes, refused)
        out += files
        if others is not None:
            others += other
        if depth >= MAX_DEPTH:
            deep = deep or bool(dirs)
            continue
        stack += [(s, depth + 1) for s in reversed(dirs)]
    if deep:
        notes.append(
            f"{shown(folder)}: folders nested more than {MAX_DEPTH} deep were not searched"
        )
    return sorted(out, key=lambda p: os.fsencode(p))


def pick_notebook(candidates: list[Path], expected: str) -> tuple[Path | None, str]:
    """The student's notebook among ``candidates`` (the expected name wins), with a note."""
    if not candidates:
        return None, ""
    if len(candidates) == 1:
        return candidates[0], ""
    exact = [p for p in candidates if p.name == expected]
    if exact:
        others = ", ".join(shown(p.name) for p in candidates if p != exact[0])
        return exact[0], f"several notebooks found; graded {exact[0].name} (also found: {others})"
    stem = Path(expected).stem.lower()
    named = [p for p in candidates if stem and stem in p.stem.lower()]
    pool = named or candidates
    best = max(
        pool,
        key=lambda p: (difflib.SequenceMatcher(None, p.name, expected).ratio(), p.stat().st_mtime),
    )
    others = ", ".join(shown(p.name) for p in candidates if p != best)
    return best, f"several notebooks found; graded {shown(best.name)} (also found: {others})"


@dataclass
class _Found:
    key: str  # who: "canvas:123", "folder:alice", ...
    student: str
    path: Path
    parsed: object = None  # lms.Parsed or None
    order: tuple = ()
    submitted_at: float | None = None
    time_source: str = ""
    name: str = ""
    refused: str = ""  # why the file is not read (a link, not a notebook)
    root: Path | None = None  # the submissions folder given (files are read relative to it)
    named: bool = False  # the instructor named this file itself
    other: bool = False  # not a notebook: graded (0, with why) only if the student has none
    #: the student's other files for the cells: (name in the working folder, path)
    handed: list[tuple[str, Path]] = field(default_factory=list)


def _examples(paths: list, n: int = 4) -> str:
    names = [shown(p.name) if isinstance(p, Path) else str(p) for p in paths]
    more = f" and {len(names) - n} more" if len(names) > n else ""
    return ", ".join(names[:n]) + more


def _lms_id(parsed) -> str:
    """The student id of an LMS's student (its name and id: unique, and leads back)."""
    from . import lms

    if parsed.lms == lms.BLACKBOARD:
        return student_id(parsed.lms_id)
    if not parsed.lms_id:
        return safe_id(parsed.name)
    return safe_id(f"{parsed.name}_{parsed.lms_id}" if parsed.name else parsed.lms_id)


def _plain_stem(name: str) -> str:
    stem = name[:-6] if name.lower().endswith(".ipynb") else os.path.splitext(name)[0]
    return stem[:-6] if stem.lower().endswith(".ipynb") else stem


def _from_file(p: Path, download=None) -> _Found:
    """Who handed in the file ``p`` (a notebook, or any other file: ``other``)."""
    from . import lms

    raw = os.fsdecode(p.name)
    other = not raw.lower().endswith(".ipynb")
    parsed = download.owner(raw) if download is not None else lms.parse_file(raw)
    if parsed is not None and parsed.lms == lms.BLACKBOARD and not parsed.lms_id:
        sid = student_id(_plain_stem(raw))
        why = f"whose attempt this is cannot be told: {parsed.unsure}"
        return _Found(f"unknown:{sid}", sid, p, name=shown(raw), refused=why)
    if parsed is None:
        sid = student_id(_plain_stem(raw))
        why = not_a_notebook(shown(raw)) if other else ""
        return _Found(f"file:{sid}", sid, p, name=shown(_plain_stem(raw)), refused=why, other=other)
    if parsed.kind in ("text", "link") or other:
        why = not_a_notebook(shown(parsed.orig or raw), parsed.kind)
    else:
        why = ""
    return _found_parsed(parsed, p, why)



def _found_parsed(parsed, p: Path, why: str) -> _Found:
    """The file ``p`` of the LMS submission ``parsed``; refused with ``why`` when not empty."""
    return _Found(parsed.key, _lms_id(parsed), p, parsed, parsed.order, parsed.submitted_at,
                  parsed.time_source, parsed.name, refused=why, other=bool(why))

def _nothing_inside(d: Path, others: list[Path], links) -> str:
    if others:
        return (
            "no notebook in the folder: "
            + "; ".join(f"{shown(o.name)} ({not_a_notebook(shown(o.name))})" for o in others[:3])
            + (f" and {len(others) - 3} more" if len(others) > 3 else "")
        )
    if (d / ".ipynb_checkpoints").is_dir():
        return "no notebook in the folder, only Jupyter's checkpoint copies (.ipynb_checkpoints)"
    return "the folder is empty: nothing was handed in"


def _from_folder(d: Path, expected: str, notes: list[str], nbgrader: bool = False) -> _Found:
    """The submission in one student's folder (refused with the reason when it holds no
    notebook)."""
    from . import lms

    where = d
    when, source = None, ""
    if nbgrader:
        stem = Path(expected).stem
        subs = [s for s in _scan(d, notes)[1]]
        named = [s for s in subs if s.name == stem]
        if named or len(subs) == 1:
            where = (named or subs)[0]
            when = lms.nbgrader_timestamp(where)
            source = "nbgrader timestamp.txt" if when else ""
    links: list[tuple[Path, str]] = []
    others: list[Path] = []
    nbs = _notebooks_in(where, notes, links, others)
    nb, note = pick_notebook(nbs, expected)
    refused, other = "", False
    if nb is None and links:  # only links: the student is graded 0 with the reason
        nb, refused = links[0]
    elif nb is None:
        nb, refused, other = (others[0] if others else d), _nothing_inside(d, others, links), True
    if note:
        notes.append(f"{shown(d.name)}: {note}")
    parsed = None if nbgrader else lms.parse_folder(os.fsdecode(d.name))
    handed = handedfiles.beside(nb) if not (refused or other) else []
    if parsed is not None:
        if parsed.kind != "file" and not refused:
            refused, other, handed = not_a_notebook(shown(nb.name), parsed.kind), True, []
        return _Found(
            parsed.key,
            _lms_id(parsed),
            nb,
            parsed,
            parsed.order,
            parsed.submitted_at,
            parsed.time_source,
            parsed.name,
            refused,
            other=other,
            handed=handed,
        )
    sid = student_id(os.fsdecode(d.name))
    kind = "nbgrader" if nbgrader else "folder"
    return _Found(
        f"{kind}:{sid}", sid, nb, None, (), when, source, shown(d.name), refused, other=other,
        handed=handed,
    )


def _looks_like_a_class(d: Path) -> str:
    """Why the folder ``d`` holds a class rather than one student's work, or ''.

    Several sub-folders each holding a notebook of the same name (folders per student), or
    notebooks whose download names belong to several students (a flat LMS download).
    """
    from . import lms

    by_name: dict[bytes, list[Path]] = {}
    for sub in _scan(d, [])[1]:
        for nb in _notebooks_in(sub, []):
            by_name.setdefault(os.fsencode(nb.name), []).append(sub)
    same = max(by_name.values(), key=len, default=[])
    if len(same) >= 2:
        return f"{len(same)} folders with a notebook of the same name ({_examples(same)})"
    owners: dict[str, Path] = {}
    for nb in _scan(d, [])[0]:
        parsed = lms.parse_file(os.fsdecode(nb.name))
        if parsed is not None:
            owners.setdefault(parsed.key, nb)
    if len(owners) >= 2:
        return (
            f"notebooks of {len(owners)} different students by their download names "
            f"({_examples(list(owners.values()))})"
        )
    return ""


def _download(
    p: Path, files: list[Path], other: list[Path], notes: list[str], roster, dirs=()
):
    """The LMS's records in the class folder ``p`` (Blackboard's .txt, Brightspace's
    index.html, beside its files or its folders ``dirs``), read once, and the students
    whose Blackboard attempt has no file."""
    from . import lms

    usernames = [e.username.lstrip("#") for e in roster or () if e.username]
    usernames += [e.login for e in roster or () if e.login]
    names = [os.fsdecode(o.name) for o in files + other]
    folders = [os.fsdecode(d.name) for d in dirs]
    d = lms.Download.read(p, names, usernames, folders=folders)
    notes += d.notes
    textonly = []
    for rec in d.attempts:  # an attempt with no file: the student handed in only text
        if rec.files:
            continue
        t = lms.local_time(rec.attempt, "%Y-%m-%d-%H-%M-%S")  # the attempt's, not the file's
        parsed = lms.Parsed(lms.BLACKBOARD, rec.name, rec.username, (t or 0.0,), t,
                            time_source="download name" if t else "")
        why = "the attempt has no file" + (" (only text typed into Blackboard)" if rec.text else "")
        textonly.append(
            _Found(
                parsed.key,
                _lms_id(parsed),
                p / rec.record,
                parsed,
                parsed.order,
                parsed.submitted_at,
                parsed.time_source,
                name=rec.name,
                refused=why,
                other=True,
            )
        )
    return d, textonly


def _class(p: Path, expected: str, notes: list[str], roster=None) -> list[_Found]:
    """The submissions in a folder given on the command line."""
    nbgrader = False
    if (p / "submitted").is_dir() and not (p / "submitted").is_symlink():
        p, nbgrader = p / "submitted", True
    elif p.name == "submitted":
        nbgrader = True
    links: list[tuple[Path, str]] = []
    files, dirs, other = _scan(p, notes, links)
    refused = []
    for path, why in links:
        raw = os.fsdecode(path.name)
        sid = student_id(raw[:-6] if raw.lower().endswith(".ipynb") else raw)
        refused.append(_Found(f"file:{sid}", sid, path, name=shown(path.name), refused=why))
    if nbgrader:
        return [_from_folder(d, expected, notes, nbgrader=True) for d in dirs] + refused
    from . import lms

    if any(o.name == lms.GRADESCOPE_METADATA for o in other):
        return _gradescope_export(p, expected, notes, files + other, dirs) + refused

    student_dirs = []
    empty_dirs = []
    for d in dirs:
        inner: list[tuple[Path, str]] = []
        if _notebooks_in(d, [], inner) or inner:
            student_dirs.append(d)
        else:
            empty_dirs.append(d)
    plain = [f for f in files if lms.parse_file(os.fsdecode(f.name)) is None]
    exercise_named = [f for f in plain if f.name == expected]
    own = lms.parse_folder(os.fsdecode(p.name))
    if (own is not None and (files or other) and not student_dirs) or (
        files and not student_dirs and exercise_named == files
    ):
        # One student's folder (a Moodle/Brightspace student folder, or a folder holding
        # only the exercise's own notebook): the student is the folder.
        return [_from_folder(p, expected, notes)]
    if exercise_named and student_dirs:
        # The exercise's own notebook cannot be a student: this is the course folder, or a
        # class folder with the handout left in it.
        raise SubmissionsError(
            f"{shown(p)} does not look like a class: it holds {_examples(exercise_named)} "
            f"(the exercise's own notebook name, not a student's) beside "
            f"{len(student_dirs)} student folder(s) ({_examples(student_dirs)}). Move "
            f"{_examples(exercise_named)} out of the class folder, or pass the student "
            "folders you mean."
        )
    for d in student_dirs:
        why = "" if lms.parse_folder(os.fsdecode(d.name)) else _looks_like_a_class(d)
        if why:
            raise SubmissionsError(
                f"{shown(p)} holds {why}: it looks like a class, not one student's work. "
                f"Pass {shown(d)} itself."
            )
    download, textonly = _download(p, files, other, notes, roster, student_dirs)
    handed = [o for o in other if os.fsdecode(o.name) not in download.consumed]
    lms_named = [o for o in handed if download.owner(os.fsdecode(o.name)) is not None]
    if not files and not student_dirs and not refused and not lms_named:
        zips = [o for o in handed if o.name.lower().endswith(".zip")]
        hint = (
            f" It holds {_examples(zips)}: unzip the LMS download first and pass the folder."
            if zips
            else " Pass the folder that holds the notebooks (one .ipynb or one folder per "
            "student), or the .ipynb files themselves."
        )
        raise SubmissionsError(
            f"no notebook found in {shown(p)} ({len(handed)} other file(s)"
            + (f": {_examples(handed)}" if handed else "")
            + f", {len(dirs)} folder(s) without a notebook).{hint}"
        )
    found = [_from_file(f, download) for f in files + handed] + refused
    found += textonly
    for d in student_dirs + empty_dirs:
        found.append(_from_folder(d, expected, notes))
    return found


def _gradescope_export(
    p: Path,
    expected: str,
    notes: list[str],
    files: list[Path],
    dirs: list[Path],
    only: str | None = None,
) -> list[_Found]:
    """Gradescope's "Export Submissions" folder ``p``: a submission per folder its
    ``submission_metadata.yml`` lists, one student per submitter (a group's members share
    the notebook), at the record's ``:created_at:``. A folder the record does not list, or a
    record with no folder, is kept and said, never dropped; the record is never graded.
    ``only``: the one folder of ``p`` wanted (a notebook regraded alone)."""
    from . import lms

    meta = p / lms.GRADESCOPE_METADATA
    text = lms._read_text(meta)
    try:
        entries, problems = lms.read_gradescope_metadata(text if text is not None else "")
    except lms.GradescopeError as exc:
        raise SubmissionsError(
            f"{shown(meta)}: Gradescope's record of who handed in each submission folder "
            f"is {exc}: download the export again"
        ) from None
    notes += problems
    if only is not None:
        entries = {k: v for k, v in entries.items() if k == only}
    folders = {os.fsdecode(d.name): d for d in dirs}
    found: list[_Found] = []
    for name, entry in entries.items():
        d = folders.pop(name, None)
        for s in entry.submitters or [lms.Submitter(name, "", "")]:
            parsed = lms.Parsed(
                lms.GRADESCOPE,
                s.name or s.email or s.sid,
                s.email or s.sid,
                (entry.created_at or 0.0,),
                entry.created_at,
                time_source=f"Gradescope {lms.GRADESCOPE_METADATA}" if entry.created_at else "",
                email=s.email,
                sis_id=s.sid,
            )
            if d is None:
                why = (
                    f"{lms.GRADESCOPE_METADATA} lists {shown(name)} for them, but the export "
                    "has no such folder: nothing of theirs to grade"
                )
                found.append(_found_parsed(parsed, meta, why))
                continue
            f = _from_folder(d, expected, notes)
            found.append(_found_parsed(parsed, f.path, f.refused))
            found[-1].other, found[-1].handed = f.other, list(f.handed)
        if d is not None and len(entry.submitters) > 1:
            who = ", ".join(x.name or x.email for x in entry.submitters)
            notes.append(
                f"{shown(name)}: a group of {len(entry.submitters)} ({who}): each gets the "
                "grade of the one notebook"
            )
        if d is not None and entry.earlier:
            notes.append(
                f"{shown(name)}: submitted {len(entry.earlier) + 1} times on Gradescope; the "
                f"export holds the active one ({entry.created_text}), graded"
            )
    for name, d in sorted(folders.items()):
        notes.append(
            f"{shown(name)}: a folder of the export that {lms.GRADESCOPE_METADATA} does not "
            "list: graded under the folder's name, matched to nobody"
        )
        found.append(_from_folder(d, expected, notes))
    loose = [f for f in files if f.name != lms.GRADESCOPE_METADATA]
    return found + [_from_file(f) for f in loose]


def _mtime(p: Path) -> float:
    try:
        return os.lstat(p).st_mtime
    except OSError:
        return 0.0


def _given_notebook(
    p: Path, expected: str, notes: list[str], roster: list | None
) -> list[_Found]:
    """The student (or a Gradescope group's students) of one notebook given alone: read
    as in its class, from the LMS's name, the student's folder or the export around it,
    with the files handed in beside it."""
    if p.suffix.lower() != ".ipynb":
        raise SubmissionsError(f"{shown(p)}: not a notebook (.ipynb) file")
    if p.is_symlink() or _refusal(p):
        # A path the instructor typed may be a link; read what it points to as is.
        p = Path(os.path.realpath(p))
    f = _from_file(p, _beside(p, roster))
    if f.parsed is None:  # a notebook in a Moodle or Brightspace student folder
        inside = _in_student_folder(p)
        if inside is not None:
            f = inside
            f.handed = handedfiles.beside(p) if not f.refused else []
    elif not f.refused:  # a flat download: the same student's files beside it
        f.handed = _flat_siblings(p, f)
    alone = _in_gradescope_export(p, expected, notes) if f.parsed is None else []
    for g in alone or [f]:
        g.root, g.named = p.parent, True
    return alone or [f]


def discover(
    paths: list[Path | str],
    expected: str,
    files: StudentFiles | None = None,
    roster: list | None = None,
) -> tuple[list[Submission], list[str]]:
    """The submissions in the files and folders given, with one note per thing skipped.

    Each ``.ipynb`` argument is one student. A folder holds a class: a notebook per student
    (LMS download names and the LMS's records beside them are read, see
    :mod:`rikingrade.lms`; other names are the id), a folder per student (Moodle and
    Brightspace folder names are parsed; the notebook named ``expected`` is taken, or the
    only/most similar one), or an nbgrader ``submitted/`` tree. A folder holding only
    ``expected`` is one student's folder. Several attempts of one student: the newest
    counts, the others are returned in ``earlier``. Every other file and folder ends in
    one place: a student who handed in no notebook (a .zip, a script, a text entry, an
    empty folder) is a submission refused with the reason; another file of a student who
    has a notebook is named in a note. Symbolic links are never followed (each is
    reported), nor hard-linked files read. ``roster`` (:class:`rikingrade.roster.RosterEntry`
    rows) tells Blackboard usernames holding ``_`` and Brightspace namesakes apart. The
    submissions read their files through ``files`` (see :mod:`rikingrade.studentfiles`).

    Raises
    ------
    SubmissionsError
        A path does not exist, nothing was found, or a folder does not look like a class
        (the message says what was found and what to pass instead).
    """
    notes: list[str] = []
    found: list[_Found] = []
    for arg in paths:
        p = Path(arg)
        if not os.path.lexists(p):
            raise SubmissionsError(f"{shown(p)}: no such file or folder")
        if p.is_file():
            found += _given_notebook(p, expected, notes, roster)
        elif p.is_dir():
            for f in _class(p, expected, notes, roster):
                f.root = p
                found.append(f)
        else:
            raise SubmissionsError(f"{shown(p)}: neither a file nor a folder")
    if not found:
        raise SubmissionsError(
            "no submission found in "
            + ", ".join(shown(Path(a)) for a in paths)
            + (": " + "; ".join(notes[:5]) if notes else "")
        )
    _split_namesakes(found, roster, notes)
    groups: dict[str, list[_Found]] = {}
    for f in found:
        if f.submitted_at is None:
            f.submitted_at, f.time_source = _mtime(f.path), "file modification time"
        groups.setdefault(f.key, []).append(f)
    subs = [s for key, group in groups.items() for s in _one_student(key, group, notes)]
    _unique_ids(subs, notes)
    subs.sort(key=lambda s: s.student)
    for s in subs:
        for one in (s, *s.earlier):
            one.files = files
    return subs, notes


def _in_student_folder(p: Path) -> _Found | None:
    """The notebook ``p`` given alone, whose own name says nothing, as its student: the
    Moodle or Brightspace student folder holding it names them (as when the class is
    graded), so one student is regraded under their own id. None: not in such a folder."""
    from . import lms

    parsed = lms.parse_folder(os.fsdecode(p.parent.name))
    if parsed is None:
        return None
    why = not_a_notebook(shown(p.name), parsed.kind) if parsed.kind != "file" else ""
    return _found_parsed(parsed, p, why)


def _in_gradescope_export(p: Path, expected: str, notes: list[str]) -> list[_Found]:
    """The notebook ``p`` given alone, in a ``submission_<id>/`` folder of a Gradescope
    export: its submitters, as when the export is graded ([] if it is not in one)."""
    from . import lms

    export = p.parent.parent
    if not (export / lms.GRADESCOPE_METADATA).is_file():
        return []
    name = os.fsdecode(p.parent.name)
    found = _gradescope_export(export, expected, notes, [], [p.parent], only=name)
    for f in found:
        f.path = p
    return found


def _beside(p: Path, roster):
    """The LMS's records beside one file given alone (its Blackboard attempt's .txt,
    Brightspace's index.html), to read it as in its class."""
    from . import lms

    raw = os.fsdecode(p.name)
    names = [raw, lms.BRIGHTSPACE_INDEX, lms.blackboard_record(raw)]
    usernames = [e.username.lstrip("#") for e in roster or () if e.username]
    found = [n for n in names if n and os.path.lexists(p.parent / n)]
    return lms.Download.read(p.parent, found, usernames)


def _split_namesakes(found: list[_Found], roster, notes: list[str]) -> None:
    """Files an LMS names by the student's name only (Brightspace), where the roster has
    several students of that name: each file stays its own submission (never merged on a
    guess), and the note says so."""
    from . import lms

    if not roster:
        return
    count: dict[str, int] = {}
    for e in roster:
        count[lms.person_key(e.name or f"{e.first} {e.last}")] = (
            count.get(lms.person_key(e.name or f"{e.first} {e.last}"), 0) + 1
        )
    seen: dict[str, list[_Found]] = {}
    for f in found:
        if f.key.startswith("brightspace:name:"):
            k = f.key.removeprefix("brightspace:name:")
            if count.get(k, 0) > 1:
                seen.setdefault(k, []).append(f)
    for k, same in seen.items():
        for f in same:
            tag = _tag(_download_name(f.path))
            f.key, f.student = f"{f.key}:{tag}", f"{f.student}-{tag}"
        notes.append(
            f"ambiguous: {count[k]} students on the roster are named {same[0].name}, and the "
            f"download names students by name only: {len(same)} file(s) "
            f"({_examples([f.path for f in same])}) graded each on its own, matched to no "
            "roster row: give these grades by hand"
        )


def _download_name(p: Path) -> str:
    """The name the LMS gave the file ``p`` (with its submission folder's, when a folder
    names the student): the same however the path was typed, so a file regraded alone keeps
    its student's id."""
    from . import lms

    name = os.fsdecode(p.name)
    folder = os.fsdecode(p.parent.name)
    return f"{folder}/{name}" if lms.parse_folder(folder) is not None else name


def _one_student(key: str, group: list[_Found], notes: list[str]) -> list[Submission]:
    """The submission(s) of one key: the newest notebook counts, earlier ones are kept; a
    student with no notebook gets one refused submission; other files are noted."""
    nbs = [f for f in group if not f.other]
    others = [f for f in group if f.other]
    if not nbs:
        first = sorted(others, key=lambda f: (f.order, f.submitted_at or 0.0, os.fsencode(f.path)))
        best = next((f for f in first if ".zip" in f.refused), first[-1])
        for f in others:
            if f is not best:
                notes.append(f"{best.student}: also handed in {shown(f.path.name)}: {f.refused}")
        notes.append(f"{shown(best.path)}: not graded: {best.refused}")
        return [_submission(best, [])]
    given = _given_files(others)
    for f in others:
        if f.path in given:
            notes.append(
                f"{nbs[0].student}: also handed in {shown(f.path.name)}: given to the "
                f"notebook's cells as {shown(given[f.path])}"
            )
        else:
            notes.append(
                f"{nbs[0].student}: also handed in {shown(f.path.name)}, not graded: {f.refused}"
            )
    group = nbs
    for f in group:
        if key.startswith("unknown:"):
            notes.append(f"{shown(f.path)}: not graded: {f.refused}")
    group.sort(key=lambda f: (f.order, f.submitted_at or 0.0, os.fsencode(f.path)))
    if key.startswith(("file:", "folder:", "nbgrader:", "unknown:")) and len(group) > 1:
        # The same plain name twice (two folders given): two students, not attempts.
        notes.append(
            f"{len(group)} submissions named {group[0].student} "
            f"({', '.join(shown(f.path) for f in group)}): graded as separate students "
            "with the path's hash added to the id"
        )
        out = []
        for f in group:
            f.student = f"{f.student}-{_tag(shown(f.path))}"
            out.append(_submission(f, []))
        return out
    newest = group[-1]
    if given and not newest.handed:  # a flat download: the files the LMS gives this student
        newest.handed = [(name, path) for path, name in given.items()]
    if len(group) > 1:
        notes.append(
            f"{newest.student}: {len(group)} attempts; the newest ({shown(newest.path.name)}) "
            f"counts, earlier ones are kept in the gradebook: "
            + ", ".join(shown(f.path.name) for f in group[:-1])
            + (
                " (the download names students by name only; a roster given with --roster "
                "tells namesakes apart)"
                if key.startswith("brightspace:name:")
                else ""
            )
        )
    return [_submission(newest, [_submission(f, []) for f in group[:-1]])]


def _given_files(others: list[_Found]) -> dict[Path, str]:
    """The files of a flat LMS download that a student handed in beside their notebook:
    path -> the name the student gave it (the newest attempt of one name wins)."""
    by_name: dict[str, _Found] = {}
    for f in sorted(others, key=lambda f: (f.order, f.submitted_at or 0.0, os.fsencode(f.path))):
        orig = getattr(f.parsed, "orig", "")
        if getattr(f.parsed, "kind", None) == "file" and orig and "/" not in orig:
            by_name[orig] = f
    return {f.path: name for name, f in by_name.items()}


def _flat_siblings(p: Path, f: _Found) -> list[tuple[str, Path]]:
    """The files beside the notebook ``p`` of a flat LMS download (given alone) that the
    LMS's names give to the same student as ``f``: the files of the class's run."""
    others = []
    for o in _scan(p.parent, [])[2]:
        g = _from_file(o)
        if g.key == f.key and g.other:
            others.append(g)
    return [(name, path) for path, name in _given_files(others).items()]


def _unique_ids(subs: list[Submission], notes: list[str]) -> None:
    by_id: dict[str, list[Submission]] = {}
    for s in subs:
        by_id.setdefault(s.student, []).append(s)
    for sid, same in by_id.items():
        if len(same) > 1:
            notes.append(
                f"id collision: {len(same)} different students map to {sid} "
                f"({', '.join(s.shown_path for s in same)}); each id gets its file's hash"
            )
            for s in same:
                s.student = f"{sid}-{_tag(s.shown_path)}"


def _submission(f: _Found, earlier: list[Submission]) -> Submission:
    parsed = f.parsed
    return Submission(
        student=f.student,
        path=f.path,
        name=f.name,
        lms=getattr(parsed, "lms", "") or f.key.split(":", 1)[0],
        lms_id=getattr(parsed, "lms_id", ""),
        submitted_at=f.submitted_at,
        time_source=f.time_source,
        late=bool(getattr(parsed, "late", False)),
        earlier=earlier,
        refused=f.refused,
        root=f.root,
        named=f.named,
        file_id=getattr(parsed, "file_id", ""),
        download_name=f.name,
        email=getattr(parsed, "email", ""),
        sis_id=getattr(parsed, "sis_id", ""),
        handed=list(f.handed),
    )
