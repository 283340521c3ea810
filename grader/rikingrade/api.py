"""The grading API: :func:`grade` a folder of notebooks; :func:`check_sandbox` probes isolation.

The command line (``rikin-grade``) is a thin layer over these functions and takes its
defaults from their signatures, so the two cannot drift.

:func:`grade` is a pipeline of named steps, in this order: *discover* the notebooks handed in
(:func:`rikingrade.notebook.discover`) and *match* them to the roster (:func:`_match`); enter
the class, its rules and the files into the gradebook (:func:`_enter_class`,
:func:`_enter_submissions`); *plan* (:func:`_plan`: a refused file scores 0 with why, a file
graded before with the same settings keeps its result, the rest is to run); *run* the rest in
sandboxes (:func:`_run`, :mod:`rikingrade.pool`), each result *recorded* as it comes
(:class:`_GradebookRun`); then the summary and the *export* of the views (:func:`_finish`).
"""

from __future__ import annotations

import hashlib
import inspect
import json
import logging
import sys
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from . import handedfiles, repair
from ._version import __version__
from .assignment import Assignment, load_assignment
from .gradebook import Gradebook, GradebookDamaged
from .intake import ids_of_class, keep_folder_students, match_roster, stored_roster, time_notes
from .lmsfiles import MISSING_BLANK, MISSING_ZERO
from .notebook import OUTPUT_MARK, Submission, SubmissionsError, discover, shown
from .outputs import atomic_write
from .policy import PolicyError, Rules, parse_time, show_time
from .pool import Batch, failed_result, log_result
from .pool import run_pool as _run_pool
from .probe import check_sandbox
from .progress import Progress, summarize, summary_text
from .report import INVALID, SubmissionResult
from .roster import (
    COLUMN_NOTE,
    Roster,
    RosterEntry,
    RosterError,
    assignment_column,
    load_roster,
    read_table,
)
from .runner import RunOptions
from .safetext import SafeFormatter
from .sandbox import Limits, SandboxConfig
from .sandbox.cgroup import machine_memory_mb
from .sandbox.config import DESCRIBE, package_dir, resolve_mode
from .studentfiles import StudentFiles
from .views import export, student_view, write_student

__all__ = [
    "DEFAULT_SEED",
    "GradeReport",
    "GradeSettings",
    "check_sandbox",
    "grade",
    "grade_upload",
]

log = logging.getLogger("rikingrade")

DEFAULT_SEED = 20240901


@dataclass
class GradeReport:
    """What :func:`grade` returns: one result per submission and the batch summary."""

    out: Path
    results: list[SubmissionResult]
    summary: dict[str, Any]
    notes: list[str] = field(default_factory=list)

    def by_student(self) -> dict[str, SubmissionResult]:
        return {r.student: r for r in self.results}


@dataclass(frozen=True)
class GradeSettings:
    """How :func:`grade` grades a batch: its keyword arguments (their defaults are in its
    signature, the one place they live).

    Attributes
    ----------
    workers : int
        Submissions graded in parallel, one sandbox each.
    seed : int
        Seed of the hidden tests' random inputs; the same inputs for every student.
    reveal : bool
        Let feedback show hidden inputs and expected values.
    timeout : float or None
        Wall-clock seconds per test call; None uses each hidden test's own timeout (2 s in
        the four arm exercises).
    cell_timeout : float
        Wall-clock seconds per notebook cell; a slower cell is skipped (later cells run).
    time_budget : float
        Wall-clock seconds one submission may cost in all (cells, calls, restarts); the
        tests not reached in time score 0 and the submission's status is ``timeout``.
    memory_mb : int
        Memory (MiB, address space) a notebook may allocate on top of the preloaded
        libraries (numpy, sympy, matplotlib, rikin: about 250 MiB).
    cpu_seconds : int
        CPU seconds per notebook process (a backstop behind the wall-clock limits).
    max_processes : int
        Processes and threads per sandbox (stops fork bombs).
    max_file_mb : int
        Largest file a notebook may write (MiB).
    tmp_mb : int
        Size of the sandbox's private, wiped ``/scratch`` (MiB).
    output_limit : int
        Characters of printed output kept per cell (the rest is counted and dropped).
    regrade : bool
        Grade everything given again (a new result in the gradebook) instead of reusing the
        result of a file already graded with the same settings.
    gradebook : str or None
        The course's SQLite gradebook (default ``<out>/gradebook.sqlite``); share one across
        assignments by passing the same file.
    roster : str or None
        The class's roster as the LMS exports it (Canvas gradebook export, Moodle grading
        worksheet or gradebook export, Blackboard Grade Center download, Brightspace grades
        export; or a CSV with id, name, email, SIS id, section): submissions are matched to
        it by the LMS's id, else by name (an ambiguity is reported, never guessed); the LMS
        files use its ids, leave out students not on it and list those missing. Kept in the
        gradebook for later runs until another is given.
    lms_column : str or None
        The assignment's column in the LMS: the roster export's header (``HW3 (4455)``,
        ``HW3 [Total Pts: 10 Score] |12345``, ``HW3 Points Grade``) or a part of it found in
        one column only. Default: the one column holding the exercise's name. Kept in the
        gradebook.
    missing : {"blank", "zero"} or None
        What the LMS files give a student on the roster with no submission: nothing (the
        LMS keeps what it has) or 0. Kept in the gradebook (default blank).
    due : str or None
        Due time (``2026-11-20 23:59``, local time, or ISO 8601 with an offset); with
        ``late_per_day`` it sets the late penalty. Recorded in the gradebook: later runs
        keep it until another is given.
    late_per_day : float
        Late penalty, percent of the maximum per started day after ``due``.
    late_cap : float
        Largest late penalty, percent of the maximum.
    grace_minutes : float
        Minutes after ``due`` that are not late.
    extensions : str or None
        A CSV of per-student due times: columns student (id, as in grades.csv, or LMS id),
        due, reason.
    sandbox : {"auto", "bwrap", "uid"}
        How student code is isolated: ``bwrap`` (bubblewrap namespaces), ``uid`` (no
        namespaces; a root grader runs each worker as its own unprivileged uid and first
        proves the grader's files unreadable to it), or ``auto``: the strongest that works
        here. The log says which was used.
    unsafe_no_sandbox : bool
        Run student code without bubblewrap (development only: no isolation at all).
    progress : bool or None
        Progress bar; None shows it when stderr is a terminal.
    quiet : bool
        Print nothing (the log and the files are still written).
    """

    workers: int
    seed: int
    reveal: bool
    timeout: float | None
    cell_timeout: float
    time_budget: float
    memory_mb: int
    cpu_seconds: int
    max_processes: int
    max_file_mb: int
    tmp_mb: int
    output_limit: int
    regrade: bool
    gradebook: str | None
    roster: str | None
    lms_column: str | None
    missing: str | None
    due: str | None
    late_per_day: float
    late_cap: float
    grace_minutes: float
    extensions: str | None
    sandbox: str
    unsafe_no_sandbox: bool
    progress: bool | None
    quiet: bool


def grade(
    assignment: str | Path,
    submissions: Sequence[str | Path] | str | Path,
    out: str | Path,
    *,
    workers: int = 2,
    seed: int = DEFAULT_SEED,
    reveal: bool = False,
    timeout: float | None = None,
    cell_timeout: float = 30.0,
    time_budget: float = 180.0,
    memory_mb: int = 1024,
    cpu_seconds: int = 120,
    max_processes: int = 32,
    max_file_mb: int = 16,
    tmp_mb: int = 64,
    output_limit: int = 10_000,
    regrade: bool = False,
    gradebook: str | None = None,
    roster: str | None = None,
    lms_column: str | None = None,
    missing: str | None = None,
    due: str | None = None,
    late_per_day: float = 0.0,
    late_cap: float = 100.0,
    grace_minutes: float = 0.0,
    extensions: str | None = None,
    sandbox: str = "auto",
    unsafe_no_sandbox: bool = False,
    progress: bool | None = None,
    quiet: bool = False,
) -> GradeReport:
    """Grade notebooks against an assignment's hidden tests into the course gradebook.

    Parameters
    ----------
    assignment : str or Path
        An exercise name (``"scara"`` means ``rikingrade.hidden.scara``), a dotted module
        name, or the path of a ``.py`` hidden-test module following ``rikingrade.spec``.
    submissions : path or sequence of paths
        ``.ipynb`` files and class folders as LMS give them (Canvas, Moodle, Blackboard,
        Brightspace downloads, an nbgrader ``submitted/`` tree, a notebook or a folder per
        student; see :func:`rikingrade.notebook.discover`); a folder that does not look like
        a class is refused with what was found.
    out : path
        Output folder: the gradebook (``gradebook.sqlite`` unless ``gradebook`` is given)
        and its views (``grades.csv``, ``summary.json``, the LMS files, ``report/``,
        ``results/<student>.json``, ``feedback/``: see :mod:`rikingrade.views`), the log.
    workers, seed, reveal, ..., quiet
        The keyword arguments, each documented in :class:`GradeSettings`.

    Returns
    -------
    GradeReport
        This run's results (graded or reused), the summary, and the discovery notes.

    Raises
    ------
    AssignmentError, SubmissionsError, RosterError, PolicyError
        The assignment, a path of submissions, the roster or a setting is refused.
    SandboxUnavailable
        No sandbox mode can run here (and ``unsafe_no_sandbox`` is False): says what failed.
    GradebookBusy, GradebookDamaged
        Another grader writes the same gradebook; or it is damaged or lacks grades ``out``
        holds (nothing was written; the message gives the command that repairs it).
    """
    given = locals()
    settings = GradeSettings(**{f.name: given[f.name] for f in fields(GradeSettings)})
    return _grade(assignment, submissions, out, settings)


def grade_upload(
    assignment: str | Path, notebook: Path, upload: Path, out: str | Path, **options: Any
) -> GradeReport:
    """Grade one uploaded notebook as :func:`grade` does, with the files handed in beside it.

    ``notebook`` is the grader's own copy of the upload's notebook ``upload`` (Gradescope's
    ``/autograder/submission/...``); the files below ``upload``'s folder are given to the
    cells as a student folder's are (:mod:`rikingrade.handedfiles`: read from the upload
    by the safe reader, with the same limits; a file not given is a line of feedback).
    ``options`` are :func:`grade`'s keyword arguments (its defaults for the others).
    """
    sig = inspect.signature(grade).parameters
    given = {n: p.default for n, p in sig.items() if p.kind is p.KEYWORD_ONLY}
    unknown = set(options) - set(given)
    if unknown:
        raise TypeError(f"grade_upload() got unexpected options: {sorted(unknown)}")
    given.update(options)
    settings = GradeSettings(**{f.name: given[f.name] for f in fields(GradeSettings)})
    return _grade(assignment, [notebook], out, settings, beside=Path(upload))


def _hand_in_beside(subs: list[Submission], upload: Path) -> None:
    """Give the submission found (the copy of ``upload``) the files beside ``upload``, read
    relative to its folder; its identity is computed again with them."""
    for sub in subs:
        sub.handed = handedfiles.beside(upload)
        sub.root = upload.parent
        sub.sha256, sub._digests = "", None


def _grade(
    assignment: str | Path,
    submissions: Sequence[str | Path] | str | Path,
    out: str | Path,
    s: GradeSettings,
    beside: Path | None = None,
) -> GradeReport:
    """The pipeline of :func:`grade` (the module's docstring walks through it); ``beside``:
    see :func:`grade_upload`."""
    t0 = time.monotonic()
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    handler = _attach_log(out / "grading.log")
    gb: Gradebook | None = None
    reader = StudentFiles()
    try:
        a = load_assignment(assignment)
        paths = [submissions] if isinstance(submissions, (str, Path)) else list(submissions)
        gb_path = Path(s.gradebook).resolve() if s.gradebook else out / "gradebook.sqlite"
        _mark_output(out, paths)
        ros = load_roster(s.roster) if s.roster is not None else None
        entries = ros.entries if ros is not None else stored_roster(gb_path, a.exercise)
        subs, notes = discover(paths, a.notebook, reader, entries)
        if beside is not None:
            _hand_in_beside(subs, beside)
        notes += keep_folder_students(subs, gb_path, a.exercise)
        notes += _match(subs, ros, entries)
        rules = Rules(
            parse_time(s.due) if s.due else None, s.late_per_day, s.late_cap, s.grace_minutes
        )
        ext_rows = _read_extensions(s.extensions, subs, entries, notes) if s.extensions else []
        options = _run_options(s)
        key = _grader_key(a, s.seed, options, s.tmp_mb)
        gb = _open_gradebook(gb_path, a.exercise, out, s.gradebook)
        notes += _enter_class(gb, a, s, rules, ext_rows, ros)
        notes += time_notes(subs, gb.policy(a.exercise))
        _tell(notes, s.quiet)
        sub_ids, older = _enter_submissions(gb, subs, a.exercise, s.quiet)
        notes += older
        run = _GradebookRun.start(gb, a, s, key, out, sub_ids, paths, gb_path, len(subs))
        calls = a.calls(s.seed)
        results, todo, resumed = _plan(a, subs, key, run, s.regrade)
        bar = Progress(len(subs), enabled=s.progress, quiet=s.quiet)
        for r in results.values():
            bar.update(r, resumed=True)
        state = "interrupted"
        try:
            if todo:
                config = _sandbox_config(a, s, out, subs, gb_path)
                batch = Batch(a, calls, options, key, config)
                _run(batch, todo, s.workers, run, bar, results)
            state = "finished"
        finally:  # the views are written even after Ctrl-C: every committed grade is in them
            run.close()  # no worker records a result once they are being written
            ordered = [results[x.student] for x in subs if x.student in results]
            summary = _summary(run, ordered, time.monotonic() - t0, resumed, state, notes)
            files = _finish(run, summary)
        log.info("summary: %s", summary_text(summary))
        if not s.quiet:
            _print_outcome(a.exercise, summary, gb, gb_path, files, out)
        return GradeReport(out=out, results=ordered, summary=summary, notes=notes)
    finally:
        reader.close()
        if gb is not None:
            gb.close()
        logging.getLogger("rikingrade").removeHandler(handler)
        handler.close()


# ----------------------------------------------------------------- discover and match
def _match(subs: list[Submission], ros: Roster | None, entries: list[RosterEntry]) -> list[str]:
    """Match the submissions to the roster given (or kept from an earlier run: who is
    missing is then in the report, not in the notes); the notes."""
    if not entries:
        return []
    return (ros.notes if ros is not None else []) + match_roster(
        subs, entries, missing_note=ros is not None
    )


def _tell(notes: list[str], quiet: bool) -> None:
    """Notes into the log and, unless ``quiet``, onto stderr."""
    for n in notes:
        log.warning("%s", n)
        if not quiet:
            print(f"rikin-grade: note: {n}", file=sys.stderr)


# ----------------------------------------------------------------- the batch's settings
def _run_options(s: GradeSettings) -> RunOptions:
    """The limits and timeouts each submission runs under."""
    limits = Limits(
        memory_mb=int(s.memory_mb),
        cpu_seconds=int(s.cpu_seconds),
        max_processes=int(s.max_processes),
        max_file_mb=int(s.max_file_mb),
        # without a memory cgroup, both workers' sandboxes together fit in 90% of it
        share_mb=int(machine_memory_mb() * 0.9 / max(1, int(s.workers))),
    )
    return RunOptions(
        limits=limits,
        cell_timeout=float(s.cell_timeout),
        time_budget=float(s.time_budget),
        timeout=None if s.timeout is None else float(s.timeout),
        output_limit=int(s.output_limit),
        reveal=bool(s.reveal),
    )


# ----------------------------------------------------------------- into the gradebook
def _enter_class(
    gb: Gradebook,
    a: Assignment,
    s: GradeSettings,
    rules: Rules,
    ext_rows: list[tuple[str, float, str]],
    ros: Roster | None,
) -> list[str]:
    """The assignment, its late policy and extensions, the roster, the LMS column and the
    missing-work policy into the gradebook; the notes."""
    gb.add_assignment(a.exercise, a.max_score, [(t.name, float(t.weight)) for t in a.tests])
    if s.due or s.late_per_day:
        gb.set_policy(a.exercise, rules.due, rules.per_day, rules.cap, rules.grace_minutes)
    for sid, when, why in ext_rows:
        gb.add_extension(sid, a.exercise, when, why)
    return _class_settings(gb, a.exercise, ros, s.lms_column, s.missing)


def _enter_submissions(
    gb: Gradebook, subs: list[Submission], exercise: str, quiet: bool
) -> tuple[dict[str, int], list[str]]:
    """Students and files into the gradebook (this reads, so hashes, every file); the
    counted file's id per student and the notes on older files (told here, as are the
    files found unreadable while reading)."""
    linked = {s.student for s in subs if s.refused}
    sub_ids = _record_submissions(gb, subs, exercise)
    older = _older_than_counted(gb, exercise, subs)
    _tell(older, quiet)
    for s in subs:
        if s.refused and s.student not in linked:
            log.warning("%s: %s: not read: %s", s.student, s.shown_path, s.refused)
            if not quiet:
                print(f"rikin-grade: note: {s.shown_path}: not read: {s.refused}", file=sys.stderr)
    return sub_ids, older


class _GradebookRun:
    """This batch's run in the gradebook: each result recorded as it comes, with the
    student's files rewritten, until the run is closed for its summary (Ctrl-C: a result
    that comes after is not recorded; the next run grades that file again)."""

    def __init__(
        self,
        gb: Gradebook,
        exercise: str,
        out: Path,
        seed: int,
        key: str,
        sub_ids: dict[str, int],
        run_id: int,
    ) -> None:
        self.gb, self.exercise, self.out, self.seed, self.key = gb, exercise, out, seed, key
        self.sub_ids, self.run_id = sub_ids, run_id
        self.lock = threading.Lock()
        self.closing = False

    @classmethod
    def start(
        cls,
        gb: Gradebook,
        a: Assignment,
        s: GradeSettings,
        key: str,
        out: Path,
        sub_ids: dict[str, int],
        paths: list[str | Path],
        gb_path: Path,
        count: int,
    ) -> _GradebookRun:
        """Open a run of ``a`` in ``gb`` (and say so in the log): ``count`` submissions."""
        given = {
            "submissions": [shown(p) for p in paths],
            "regrade": s.regrade,
            "workers": s.workers,
            "reveal": s.reveal,
        }
        run_id = gb.start_run(a.exercise, __version__, s.seed, key, given)
        log.info(
            "rikin-grade %s: %s (%d tests, max %.4g), %d submissions, seed %d, key %s, "
            "run %d of %s",
            __version__,
            a.name,
            len(a.tests),
            a.max_score,
            count,
            int(s.seed),
            key,
            run_id,
            gb_path,
        )
        return cls(gb, a.exercise, out, s.seed, key, sub_ids, run_id)

    def cached(self, sub: Submission) -> SubmissionResult | None:
        """The result of this very file graded earlier with the same settings, if any."""
        return self.gb.cached(self.sub_ids[sub.student], self.key)

    def reuse(self, sub: Submission, prev: SubmissionResult) -> None:
        """Record ``prev`` (from :meth:`cached`) as this run's result of ``sub``."""
        prev.student = sub.student
        sub_id = self.sub_ids[sub.student]
        reused = prev.result_id  # type: ignore[attr-defined]
        self.gb.record(self.run_id, sub_id, prev, self.exercise, self.seed, reuse=reused)

    def commit(self, sub: Submission, res: SubmissionResult) -> bool:
        """Record ``res`` and rewrite the student's files; False once the run is closed."""
        with self.lock:
            if self.closing:
                return False
            self.gb.record(self.run_id, self.sub_ids[sub.student], res, self.exercise, self.seed)
            _write_views(self.gb, self.exercise, self.out, sub.student)
            return True

    def close(self) -> None:
        """No result is recorded after this (the views are being written)."""
        with self.lock:
            self.closing = True


# ----------------------------------------------------------------- plan and run
def _plan(
    a: Assignment, subs: list[Submission], key: str, run: _GradebookRun, regrade: bool
) -> tuple[dict[str, SubmissionResult], list[Submission], int]:
    """Who is graded how: a refused file scores 0 with why (recorded now, once per file:
    run again, even with ``regrade``, it keeps its result); a file graded before with the
    same ``key`` keeps its result (unless ``regrade``); the rest is to run.

    Returns
    -------
    results : dict
        Student to result, those settled now.
    todo : list of Submission
        The submissions to run.
    resumed : int
        How many results were reused.
    """
    results: dict[str, SubmissionResult] = {}
    todo: list[Submission] = []
    resumed = 0
    for s in subs:
        # A refusal (a file not read, or read and not a notebook) follows from the file
        # alone: one result per file, kept even by a regrade (a changed file is a new one).
        prev = run.cached(s)
        if prev is not None and (prev.refused or not (regrade or s.refused)):
            run.reuse(s, prev)
            results[s.student] = prev
            resumed += not s.refused
        elif s.refused:
            res = _refused(a, s, key)
            run.commit(s, res)
            log_result(res)
            results[s.student] = res
        else:
            todo.append(s)
    return results, todo, resumed


def _refused(a: Assignment, s: Submission, key: str) -> SubmissionResult:
    """The result of a file not read (a link, not a notebook, unreadable): 0, with why."""
    assert s.refused
    if s.refused.startswith(("a symbolic link", "a hard link")):
        why = (
            f"not graded: {s.shown_path} is {s.refused}; the grader reads only "
            "notebook files handed in as they are (upload the .ipynb file itself)"
        )
    else:
        why = f"not graded: {s.shown_path}: {s.refused}"
    res = failed_result(a, s, key, why, INVALID, "not run: the submission was not read")
    res.problems = [why]
    res.refused = s.refused
    return res


def _sandbox_config(
    a: Assignment, s: GradeSettings, out: Path, subs: list[Submission], gb_path: Path
) -> SandboxConfig:
    """The sandbox asked for, with everything a notebook must not read masked."""
    return SandboxConfig(
        sandbox=not s.unsafe_no_sandbox,
        mode=s.sandbox,
        tmp_mb=int(s.tmp_mb),
        hidden=_hidden_paths(a, out, subs) + [gb_path.parent],
    )


def _run(
    batch: Batch,
    todo: list[Submission],
    workers: int,
    run: _GradebookRun,
    bar: Progress,
    results: dict[str, SubmissionResult],
) -> None:
    """Grade ``todo`` in sandboxes of the strongest mode that works here (the log says
    which), each result recorded in ``run`` as it comes."""
    config = batch.config
    resolve_mode(config)
    for note in config.notes:
        log.warning("%s", note)
    log.info("sandbox: %s", DESCRIBE[config.mode])
    if not config.sandbox:
        log.warning(
            "UNSAFE: grading without a sandbox (--unsafe-no-sandbox); "
            "student code can read and change this machine's files"
        )
    _run_pool(batch, todo, max(1, int(workers)), run.commit, bar, results)


# ----------------------------------------------------------------- summary and export
def _summary(
    run: _GradebookRun,
    ordered: list[SubmissionResult],
    elapsed: float,
    resumed: int,
    state: str,
    notes: list[str],
) -> dict[str, Any]:
    """The batch's summary, for the gradebook and ``summary.json``."""
    summary: dict[str, Any] = summarize(ordered, elapsed, resumed)
    summary.update(
        {
            "assignment": run.exercise,
            "grader_version": __version__,
            "key": run.key,
            "seed": int(run.seed),
            "run": run.run_id,
            "state": state,
            # students the roster could not tell apart (reported by name, not matched)
            "ambiguous": sum(n.startswith("ambiguous:") for n in notes),
            # no one roster column for the assignment: the LMS files' header is a guess
            "lms_column": sum(n.startswith(COLUMN_NOTE) for n in notes),
        }
    )
    return summary


def _finish(run: _GradebookRun, summary: dict[str, Any]) -> dict[str, Any]:
    """End the run with its summary and export the views (every grade committed is in
    them, after Ctrl-C too); the files written."""
    run.gb.end_run(run.run_id, summary["state"], summary)
    return export(run.gb, run.exercise, run.exercise, run.out, run.run_id, summary)


def _print_outcome(
    exercise: str,
    summary: dict[str, Any],
    gb: Gradebook,
    gb_path: Path,
    files: dict[str, Any],
    out: Path,
) -> None:
    """The summary and where the gradebook, its views and the LMS files are."""
    print(f"{exercise}: {summary_text(summary)}")
    print(
        f"gradebook: {gb_path} ({len(gb.current(exercise))} students)  "
        f"grades: {files['grades']}  report: {files['report'][0]}  "
        f"log: {out / 'grading.log'}"
    )
    print_lms_files(files)


def _write_views(gb: Gradebook, exercise: str, out: Path, student: str) -> None:
    """One student's results and feedback, as the gradebook has their grade now."""
    for res, g, record, who in student_view(gb, exercise, student):
        write_student(out, res, exercise, g, record, who)


def _record_submissions(gb: Gradebook, subs: list[Submission], exercise: str) -> dict[str, int]:
    """Students and files into the gradebook (earlier attempts kept); the counted file's id."""
    ids = {}
    for s in subs:
        gb.add_student(
            s.student,
            name=s.name,
            email=s.email,
            sis_id=s.sis_id,
            login=s.login,
            section=s.section,
            canvas_id=s.lms_id if s.lms == "canvas" else "",
            moodle_id=s.lms_id if s.lms == "moodle" else "",
            lms=s.lms,
            lms_id=s.lms_id,
        )
        if s.roster_key:
            gb.set_roster_key(s.student, s.roster_key)
        for e in s.earlier:
            gb.add_submission(
                s.student,
                exercise,
                e.hash(),
                e.shown_path,
                e.submitted_at,
                e.time_source,
                e.late,
            )
        ids[s.student] = gb.add_submission(
            s.student, exercise, s.hash(), s.shown_path, s.submitted_at, s.time_source, s.late
        )
    return ids


def _older_than_counted(gb: Gradebook, exercise: str, subs: list[Submission]) -> list[str]:
    """Notes on files handed in before the one whose grade counts (an earlier attempt
    regraded alone): graded and kept, but the newer attempt's grade still counts."""
    notes = []
    for s in subs:
        now = gb.current(exercise, s.student)
        if not now or s.submitted_at is None or now[0]["submitted_at"] <= s.submitted_at:
            continue
        notes.append(
            f"{s.student}: {s.shown_path} (handed in {show_time(s.submitted_at)}) is an earlier "
            f"attempt than {now[0]['path']} (handed in {show_time(now[0]['submitted_at'])}), "
            "whose grade still counts; it is graded and kept. To count it instead, set the "
            f"grade by hand: rikin-grade override {exercise} {s.student} --score ..."
        )
    return notes


def _open_gradebook(path: Path, assignment: str, out: Path, given: str | None) -> Gradebook:
    """The gradebook, refused with the repair advice when it is damaged or lacks grades
    that ``out`` holds (before anything is written)."""
    gb = None
    try:
        gb = Gradebook.open(path)
        repair.check(gb, out, assignment)
        return gb
    except GradebookDamaged as exc:
        if gb is not None:
            gb.close()
        exc.advice = repair.advice(exc, assignment, out, given)
        raise


def _class_settings(
    gb: Gradebook,
    assignment: str,
    ros: Roster | None,
    lms_column: str | None,
    missing: str | None,
) -> list[str]:
    """Record the roster given, the LMS's column and the missing-work policy; notes."""
    notes = []
    if missing is not None:
        if missing not in (MISSING_BLANK, MISSING_ZERO):
            raise PolicyError(f"--missing is {MISSING_BLANK} or {MISSING_ZERO}, not {missing!r}")
        gb.set_setting(assignment, "missing", missing)
    if ros is not None:
        gb.set_roster(assignment, ros.kind, ros.path, [(e.key, e.as_dict()) for e in ros.entries])
        kept = {"path": ros.path, "kind": ros.kind, "columns": ros.columns}
        gb.set_setting(assignment, "roster_columns", json.dumps(kept))
    elif lms_column:  # the roster kept from an earlier run: its columns, as downloaded
        ros = _kept_columns(gb, assignment)
    if ros is not None or lms_column:
        column, note = (
            assignment_column(ros, lms_column or "", assignment)
            if ros is not None
            else (lms_column or "", "")
        )
        if note:
            notes.append(note)
        if column:
            gb.set_setting(assignment, "lms_column", column)
    return notes


def _kept_columns(gb: Gradebook, assignment: str) -> Roster | None:
    """The assignment columns of the roster an earlier run was given (no students), so
    that ``--lms-column`` alone finds the header as the LMS wrote it; None when the
    gradebook kept none (no roster yet, or one kept by a grader that did not record them).
    """
    try:
        kept = json.loads(gb.setting(assignment, "roster_columns", "") or "{}")
        columns = [str(c) for c in kept["columns"]]
        return Roster(str(kept["path"]), str(kept["kind"]), [], columns)
    except (ValueError, KeyError, TypeError):
        return None


_LMS_TITLES = {
    "canvas": "Canvas import",
    "moodle": "Moodle import",
    "blackboard": "Blackboard import",
    "brightspace": "Brightspace import",
    "gradescope": "Gradescope grades (its export's columns)",
    "canvas_feedback": "Canvas feedback import (Re-upload submissions)",
    "moodle_feedback": "Moodle feedback import (feedback files zip)",
}


def print_lms_files(files: dict[str, Any]) -> None:
    """What the LMS files are and whom they left out; the roster's lists."""
    for key, title in _LMS_TITLES.items():
        if key in files:
            left = files.get(f"{key}_skipped") or []
            print(
                f"{title}: {files[key]}"
                + (
                    f" (left out, no id for this LMS: {', '.join(left[:5])}"
                    f"{' ...' if len(left) > 5 else ''})"
                    if left
                    else ""
                )
            )
    for key, what in (
        ("not_on_roster", "graded but not on the roster (left out of the LMS files)"),
        ("missing", "on the roster, nothing handed in"),
        ("ambiguous", "on the roster, not told apart (enter their grades by hand)"),
    ):
        who = [w if isinstance(w, str) else w.get("name") or "?" for w in files.get(key) or []]
        if who:
            print(f"{what}: {len(who)}: {', '.join(who[:8])}{' ...' if len(who) > 8 else ''}")


def _read_extensions(
    path: str, subs: list[Submission], entries: list, notes: list[str]
) -> list[tuple[str, float, str]]:
    """(student id, due, reason) from an extensions CSV (student, due, reason), each student
    named by any of their ids (the roster's too); a note for one no submission has."""
    by_any = ids_of_class(subs, entries)
    try:
        rows = read_table(Path(path), "the extensions file")
    except RosterError as exc:
        raise PolicyError(str(exc)) from None
    out = []
    for i, r in enumerate(rows):
        if not r or not any(c.strip() for c in r):
            continue
        if i == 0 and r[0].strip().lower() in ("student", "id", "student id"):
            continue
        if len(r) < 2:
            raise PolicyError(f"{path} line {i + 1}: expected student, due, reason; got {r}")
        who = r[0].strip()
        sid = by_any.get(who) or by_any.get(who.casefold()) or who
        if sid == who and who not in by_any:
            notes.append(
                f"{path} line {i + 1}: the extension of {who} is for no student of this "
                f"download; it is kept for a submission whose student id is {who}"
            )
        out.append((sid, parse_time(r[1]), (r[2].strip() if len(r) > 2 else "") or "extension"))
    return out


def _grader_key(a: Assignment, seed: int, options: RunOptions, tmp_mb: int) -> str:
    """What must match for a previous result to be reused."""
    payload = json.dumps(
        {
            "version": __version__,
            "assignment": a.exercise,
            "fingerprint": a.fingerprint,
            "seed": int(seed),
            "reveal": options.reveal,
            "timeout": options.timeout,
            "cell_timeout": options.cell_timeout,
            "time_budget": options.time_budget,
            "limits": options.limits.as_dict(),
            "output_limit": options.output_limit,
            "tmp_mb": tmp_mb,
        },
        sort_keys=True,
    )
    return f"{__version__}-{hashlib.sha256(payload.encode()).hexdigest()[:12]}"


def _hidden_paths(a: Assignment, out: Path, subs: list[Submission]) -> list[Path]:
    hidden = [out]
    grader_pkg = package_dir("rikingrade")
    if grader_pkg is not None:
        hidden.append(grader_pkg)
        course = grader_pkg.parent.parent
        for name in ("solutions", "exercises", "grader", "tests"):
            if (course / name).is_dir():
                hidden.append(course / name)
    if a.source_path is not None:
        hidden.append(
            a.source_path.parent if a.source_path.name == "__init__.py" else a.source_path
        )
    hidden += [s.path.parent for s in subs]
    return hidden


def _mark_output(out: Path, submissions: Sequence[str | Path]) -> None:
    """Mark ``out`` as the grader's output folder (discovery skips a folder so marked, so
    ``--out`` may sit inside the class folder); ``out`` cannot be a class folder itself.

    Raises
    ------
    SubmissionsError
        A folder of submissions is the output folder.
    """
    for s in submissions:
        if Path(s).is_dir() and Path(s).resolve() == out:
            raise SubmissionsError(
                f"{shown(out)} is both the output folder and a folder of submissions: give "
                "--out a folder of its own (beside the class folder or inside it)"
            )
    mark = out / OUTPUT_MARK
    if not mark.is_file():
        atomic_write(mark, "rikin-grade's output folder: not read as submissions.\n")


def _attach_log(path: Path) -> logging.Handler:
    # a student's text in a message (a lone surrogate in a cell) is escaped, not a logging
    # error that drops the line and prints a traceback on the instructor's terminal
    handler = logging.FileHandler(path, encoding="utf-8", errors="backslashreplace")
    handler.setFormatter(SafeFormatter("%(asctime)s %(levelname)s %(message)s"))
    handler.setLevel(logging.INFO)
    lg = logging.getLogger("rikingrade")
    lg.addHandler(handler)
    if lg.level == logging.NOTSET or lg.level > logging.INFO:
        lg.setLevel(logging.INFO)
    lg.propagate = False
    return handler
