"""The grading API: :func:`grade` a folder of notebooks; :func:`check_sandbox` probes isolation.

The command line (``rikin-grade``) is a thin layer over these functions and takes its
defaults from their signatures, so the two cannot drift.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import queue
import shutil
import sys
import threading
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from . import __version__, repair
from .assignment import Assignment, load_assignment
from .gradebook import Gradebook, GradebookDamaged
from .intake import ids_of_class, match_roster, stored_roster, time_notes
from .lmsfiles import MISSING_BLANK, MISSING_ZERO
from .notebook import OUTPUT_MARK, Submission, SubmissionsError, discover, shown
from .outputs import atomic_write
from .policy import PolicyError, Rules, parse_time, show_time
from .progress import Progress, summarize, summary_text
from .report import GRADER_ERROR, INVALID, SubmissionResult, TestResult
from .roster import RosterError, load_roster, read_table
from .runner import RunOptions, SubmissionRunner
from .safetext import SafeFormatter
from .sandbox import (
    Limits,
    Sandbox,
    SandboxConfig,
    SandboxUnavailable,
    prepare_workdir,
)
from .sandbox.cgroup import machine_memory_mb
from .sandbox.config import (
    DESCRIBE,
    NONE,
    UID,
    package_dir,
    resolve_mode,
    sandbox_workdir,
)
from .sandbox.uidmode import SHARED_WRITABLE
from .studentfiles import StudentFiles
from .views import export, student_view, write_student

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
        student; see :func:`rikingrade.notebook.discover`). A folder that does not look
        like a class is refused with what was found.
    out : path
        Output folder: the gradebook (``gradebook.sqlite`` unless ``gradebook`` is given)
        and its views: ``grades.csv``, ``summary.json``, the class's LMS files
        (``<lms>-<exercise>.csv``, ``<lms>-feedback-<exercise>.zip``, see
        :mod:`rikingrade.views`), ``report/``, ``results/<student>.json`` (Gradescope format,
        with what rebuilds the gradebook), ``feedback/<student>.md`` and ``.html``;
        ``grading.log``.
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

    Returns
    -------
    GradeReport
        This run's results (graded or reused), the summary, and the discovery notes.

    Raises
    ------
    AssignmentError
        The assignment cannot be loaded.
    SubmissionsError
        A path does not exist, holds no notebook, or does not look like a class.
    SandboxUnavailable
        No sandbox mode can run here (and ``unsafe_no_sandbox`` is False); the message
        says what failed.
    GradebookBusy
        Another grader is writing the same gradebook.
    GradebookDamaged
        The gradebook is damaged, or lacks grades the output folder holds; the message
        says so and gives the command that repairs it (nothing was written).
    RosterError
        The roster cannot be read.
    """
    t0 = time.monotonic()
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    handler = _attach_log(out / "grading.log")
    gb: Gradebook | None = None
    reader = StudentFiles()
    try:
        a = load_assignment(assignment)
        if isinstance(submissions, (str, Path)):
            submissions = [submissions]
        gb_path = Path(gradebook).resolve() if gradebook else out / "gradebook.sqlite"
        _mark_output(out, submissions)
        ros = load_roster(roster) if roster is not None else None
        entries = ros.entries if ros is not None else stored_roster(gb_path, a.exercise)
        subs, notes = discover(list(submissions), a.notebook, reader, entries)
        if entries:  # (a roster kept from an earlier run: who is missing is in the report)
            notes += (ros.notes if ros is not None else []) + match_roster(
                subs, entries, missing_note=ros is not None
            )
        rules = Rules(parse_time(due) if due else None, late_per_day, late_cap, grace_minutes)
        ext_rows = _read_extensions(extensions, subs, entries, notes) if extensions else []
        limits = Limits(
            memory_mb=int(memory_mb),
            cpu_seconds=int(cpu_seconds),
            max_processes=int(max_processes),
            max_file_mb=int(max_file_mb),
            # without a memory cgroup, both workers' sandboxes together fit in 90% of it
            share_mb=int(machine_memory_mb() * 0.9 / max(1, int(workers))),
        )
        options = RunOptions(
            limits=limits,
            cell_timeout=float(cell_timeout),
            time_budget=float(time_budget),
            timeout=None if timeout is None else float(timeout),
            output_limit=int(output_limit),
            reveal=bool(reveal),
        )
        key = _grader_key(a, seed, options, tmp_mb)
        gb = _open_gradebook(gb_path, a.exercise, out, gradebook)
        gb.add_assignment(a.exercise, a.max_score, [(t.name, float(t.weight)) for t in a.tests])
        if due or late_per_day:
            gb.set_policy(a.exercise, rules.due, rules.per_day, rules.cap, rules.grace_minutes)
        for sid, when, why in ext_rows:
            gb.add_extension(sid, a.exercise, when, why)
        notes += _class_settings(gb, a.exercise, ros, lms_column, missing)
        notes += time_notes(subs, gb.policy(a.exercise))
        for n in notes:
            log.warning("%s", n)
            if not quiet:
                print(f"rikin-grade: note: {n}", file=sys.stderr)
        linked = {s.student for s in subs if s.refused}
        sub_ids = _record_submissions(gb, subs, a.exercise)  # reads (hashes) every file
        for n in _older_than_counted(gb, a.exercise, subs):
            notes.append(n)
            log.warning("%s", n)
            if not quiet:
                print(f"rikin-grade: note: {n}", file=sys.stderr)
        for s in subs:
            if s.refused and s.student not in linked:
                log.warning("%s: %s: not read: %s", s.student, s.shown_path, s.refused)
                if not quiet:
                    print(
                        f"rikin-grade: note: {s.shown_path}: not read: {s.refused}",
                        file=sys.stderr,
                    )
        run_id = gb.start_run(
            a.exercise,
            __version__,
            seed,
            key,
            {
                "submissions": [shown(p) for p in submissions],
                "regrade": regrade,
                "workers": workers,
                "reveal": reveal,
            },
        )
        log.info(
            "rikin-grade %s: %s (%d tests, max %.4g), %d submissions, seed %d, key %s, "
            "run %d of %s",
            __version__,
            a.name,
            len(a.tests),
            a.max_score,
            len(subs),
            int(seed),
            key,
            run_id,
            gb_path,
        )
        calls = a.calls(seed)
        results: dict[str, SubmissionResult] = {}
        todo: list[Submission] = []
        resumed = 0  # results reused from an earlier run (refused files are not)
        for s in subs:
            if s.refused:  # a link, not a notebook, not readable: graded 0, with why
                if s.refused.startswith(("a symbolic link", "a hard link")):
                    why = (
                        f"not graded: {s.shown_path} is {s.refused}; the grader reads only "
                        "notebook files handed in as they are (upload the .ipynb file itself)"
                    )
                else:
                    why = f"not graded: {s.shown_path}: {s.refused}"
                res = _failed(a, s, key, why, INVALID, "not run: the submission was not read")
                res.problems = [why]
                res.refused = s.refused
                gb.record(run_id, sub_ids[s.student], res, a.exercise, seed)
                _write_views(gb, a.exercise, out, s.student)
                _log_result(res)
                results[s.student] = res
                continue
            prev = None if regrade else gb.cached(sub_ids[s.student], key)
            if prev is not None:
                prev.student = s.student
                gb.record(run_id, sub_ids[s.student], prev, a.exercise, seed, reuse=prev.result_id)  # type: ignore[attr-defined]
                results[s.student] = prev
                resumed += 1
            else:
                todo.append(s)
        bar = Progress(len(subs), enabled=progress, quiet=quiet)
        for r in results.values():
            bar.update(r, resumed=True)
        state = "interrupted"
        commit = threading.Lock()
        closing = False
        try:
            if todo:
                config = SandboxConfig(
                    sandbox=not unsafe_no_sandbox,
                    mode=sandbox,
                    tmp_mb=int(tmp_mb),
                    hidden=_hidden_paths(a, out, subs) + [gb_path.parent],
                )
                resolve_mode(config)
                for note in config.notes:
                    log.warning("%s", note)
                log.info("sandbox: %s", DESCRIBE[config.mode])
                if not config.sandbox:
                    log.warning(
                        "UNSAFE: grading without a sandbox (--unsafe-no-sandbox); "
                        "student code can read and change this machine's files"
                    )

                def done(sub: Submission, res: SubmissionResult) -> bool:
                    with commit:
                        if closing:  # interrupted: graded again by the next run
                            return False
                        gb.record(run_id, sub_ids[sub.student], res, a.exercise, seed)
                        _write_views(gb, a.exercise, out, sub.student)
                        return True

                _run_pool(
                    a,
                    calls,
                    options,
                    key,
                    config,
                    todo,
                    max(1, int(workers)),
                    done,
                    bar,
                    results,
                )
            state = "finished"
        finally:
            with commit:  # no worker commits once the views are being written
                closing = True
            ordered = [results[s.student] for s in subs if s.student in results]
            summary = summarize(ordered, time.monotonic() - t0, resumed)
            summary.update(
                {
                    "assignment": a.exercise,
                    "grader_version": __version__,
                    "key": key,
                    "seed": int(seed),
                    "run": run_id,
                    "state": state,
                    # students the roster could not tell apart (reported by name, not matched)
                    "ambiguous": sum(n.startswith("ambiguous:") for n in notes),
                }
            )
            gb.end_run(run_id, state, summary)
            # The views are rewritten even after Ctrl-C: every committed grade is in them.
            files = export(gb, a.exercise, a.exercise, out, run_id, summary)
        log.info("summary: %s", summary_text(summary))
        if not quiet:
            print(f"{a.exercise}: {summary_text(summary)}")
            print(
                f"gradebook: {gb_path} ({len(gb.current(a.exercise))} students)  "
                f"grades: {files['grades']}  report: {files['report'][0]}  "
                f"log: {out / 'grading.log'}"
            )
            print_lms_files(files)
        return GradeReport(out=out, results=ordered, summary=summary, notes=notes)
    finally:
        reader.close()
        if gb is not None:
            gb.close()
        logging.getLogger("rikingrade").removeHandler(handler)
        handler.close()


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


def _class_settings(gb: Gradebook, assignment: str, ros, lms_column, missing) -> list[str]:
    """Record the roster given, the LMS's column and the missing-work policy; notes."""
    from .roster import assignment_column

    notes = []
    if missing is not None:
        if missing not in (MISSING_BLANK, MISSING_ZERO):
            raise PolicyError(f"--missing is {MISSING_BLANK} or {MISSING_ZERO}, not {missing!r}")
        gb.set_setting(assignment, "missing", missing)
    if ros is not None:
        gb.set_roster(assignment, ros.kind, ros.path, [(e.key, e.as_dict()) for e in ros.entries])
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


_LMS_TITLES = {
    "canvas": "Canvas import",
    "moodle": "Moodle import",
    "blackboard": "Blackboard import",
    "brightspace": "Brightspace import",
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


def _log_result(res: SubmissionResult) -> None:
    log.info(
        "%s: %.4g/%.4g %s %s (%.2f s) %s",
        res.student,
        res.score,
        res.max_score,
        res.status,
        res.reason,
        res.elapsed,
        res.path,
    )
    for t in res.tests:
        log.info(
            "  %s %s %.4g/%.4g: %s%s",
            res.student,
            t.name,
            t.points,
            t.weight,
            t.feedback,
            f" | {t.detail}" if t.detail else "",
        )
    for c in res.cells:
        if c.status != "ok":
            log.info(
                "  %s cell %d %s %s: %s\n%s",
                res.student,
                c.number,
                c.status,
                c.error_type,
                c.message,
                c.traceback,
            )


def _run_pool(
    a: Assignment,
    calls,
    options: RunOptions,
    key: str,
    config: SandboxConfig,
    todo: list[Submission],
    workers: int,
    done: Callable[[Submission, SubmissionResult], bool],
    bar: Progress,
    results: dict[str, SubmissionResult],
) -> None:
    """Grade ``todo`` with ``workers`` sandboxes; ``done`` commits each result as it comes
    (False: it was not committed, the batch is being interrupted)."""
    jobs: queue.Queue[Submission] = queue.Queue()
    for s in todo:
        jobs.put(s)
    workdir = sandbox_workdir()
    prepare_workdir(workdir, config.sandbox)
    start_errors: list[str] = []
    lock = threading.Lock()
    stop = threading.Event()

    def worker(n: int) -> None:
        sandbox = Sandbox(config, workdir)
        try:
            try:
                sandbox.start()
            except SandboxUnavailable as exc:
                with lock:
                    start_errors.append(str(exc))
                return
            runner = SubmissionRunner(sandbox, a, calls, options, key)
            while not stop.is_set():
                try:
                    sub = jobs.get_nowait()
                except queue.Empty:
                    return
                try:
                    res = runner.grade(sub)
                except Exception:  # a bug must cost one submission, not the batch
                    log.error("%s: internal error:\n%s", sub.student, traceback.format_exc())
                    res = _failed(a, sub, key)
                    sandbox.close()
                try:
                    if not done(sub, res):  # interrupted: the views are being written
                        return
                    _log_result(res)
                except Exception:  # e.g. a disk error: this submission only, never the batch
                    log.error(
                        "%s: writing the results failed:\n%s", sub.student, traceback.format_exc()
                    )
                    res = _failed(a, sub, key, "writing this submission's results failed")
                    try:
                        if not done(sub, res):
                            return
                    except Exception:
                        log.error("%s: its failure could not be recorded either", sub.student)
                with lock:
                    results[sub.student] = res
                bar.update(res)
        except Exception:  # the worker itself: what it had not graded is reported below
            log.error("grader worker %d stopped:\n%s", n, traceback.format_exc())
        finally:
            sandbox.close()

    threads = [
        threading.Thread(target=worker, args=(i,), name=f"grader-{i}", daemon=True)
        for i in range(min(workers, len(todo)))
    ]
    try:
        for t in threads:
            t.start()
        for t in threads:
            while t.is_alive():
                t.join(0.2)
    except KeyboardInterrupt:
        stop.set()
        raise
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    if start_errors and len(start_errors) == len(threads):
        raise SandboxUnavailable("\n".join([*config.notes, start_errors[0]]))
    for e in start_errors:
        log.warning("a worker's sandbox did not start: %s", e)
    for s in todo:  # every submission ends in the gradebook, graded or with the reason
        if s.student not in results and not stop.is_set():
            results[s.student] = _failed(a, s, key, "not graded: a grader worker stopped")
            try:
                done(s, results[s.student])
            except Exception:
                log.error("%s: not graded, and that could not be recorded", s.student)
            bar.update(results[s.student])


def _failed(
    a: Assignment,
    sub: Submission,
    key: str,
    why: str = "",
    status: str = GRADER_ERROR,
    test_note: str = "not run: internal grader error",
) -> SubmissionResult:
    """The result of a submission the grader failed on (status grader-error, score 0), or
    did not read (``status`` invalid: a link)."""
    try:
        sha = sub.hash()
    except OSError:
        sha = ""
    return SubmissionResult(
        student=sub.student,
        path=sub.shown_path,
        sha256=sha,
        status=status,
        reason=why or "internal grader error (see the log)",
        max_score=a.max_score,
        key=key,
        tests=[
            TestResult(t.name, float(t.weight), 0.0, test_note, grader_error=status == GRADER_ERROR)
            for t in a.tests
        ],
    )


# ----------------------------------------------------------------------------- probe
PROBE = r"""
import os, socket, subprocess
def probe(paths):
    r = {"uid": os.getuid(), "gid": os.getgid(), "cwd": os.getcwd()}
    r["root"] = sorted(os.listdir("/"))
    def readable(p):
        try:
            if os.path.isdir(p):
                return bool(os.listdir(p))
            with open(p, "rb") as f:
                return bool(f.read(1))
        except OSError:
            return False
    r["visible"] = [p for p in paths if readable(p)]
    try:
        socket.create_connection(("1.1.1.1", 53), timeout=2).close()
        r["network"] = True
    except OSError as e:
        r["network"] = False
    written = []
    stdlib = os.path.dirname(os.__file__)
    for d in ("/", "/tmp", "/usr", "/etc", stdlib, "/opt", "/dev", "/dev/shm"):
        try:
            with open(os.path.join(d, "rikingrade-probe"), "w") as f:
                f.write("x")
            written.append(d)
            os.unlink(os.path.join(d, "rikingrade-probe"))
        except OSError:
            pass
    r["writable"] = written
    with open("/proc/self/status") as f:
        r["status_uid"] = [l.split()[1:] for l in f if l.startswith("Uid:")][0]
    return r
"""


def _host_uid(pid: int) -> int | None:
    """The real uid of ``pid`` as the host sees it (what RLIMIT_NPROC counts against)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("Uid:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def check_sandbox(
    unsafe_no_sandbox: bool = False,
    paths: Sequence[str | Path] = (),
    hidden: Sequence[str | Path] = (),
    sandbox: str = "auto",
) -> dict[str, Any]:
    """Start a sandbox and report what a notebook inside it can see and do.

    ``paths`` must be unreadable from inside; ``hidden`` are masked like the grader package
    (use it for paths inside a bound directory) and must be unreadable too. ``sandbox`` is
    the mode to probe (``auto``: the one :func:`grade` would use here).

    Returns a dict with ``ok`` (True when none of those paths, the grader package or the
    course is readable, there is no network and nothing outside the places the mode wipes
    is writable), ``mode`` and its description, why stronger modes were not used
    (``notes``), the probe's raw findings and the command used.

    Raises
    ------
    SandboxUnavailable
        No sandbox of that mode can start here (the message says what failed).
    """
    config = SandboxConfig(sandbox=not unsafe_no_sandbox, mode=sandbox)
    grader_pkg = package_dir("rikingrade")
    secret = [str(p) for p in [*paths, *hidden]]
    config.hidden = [Path(h) for h in hidden]
    if grader_pkg is not None:
        course = grader_pkg.parent.parent
        config.hidden.append(grader_pkg)
        secret += [
            str(grader_pkg),
            str(grader_pkg / "hidden"),
            str(course / "solutions"),
            str(course / "grader"),
            str(course / ".git"),
        ]
    resolve_mode(config)
    workdir = sandbox_workdir()
    sandbox_ = Sandbox(config, workdir)
    try:
        prepare_workdir(workdir, config.sandbox)
        try:
            sandbox_.start()
        except SandboxUnavailable as exc:
            raise SandboxUnavailable("\n".join([*config.notes, str(exc)])) from None
        child = sandbox_.spawn(Limits())
        deadline = time.monotonic() + 30
        child.send({"op": "exec", "cells": [[1, PROBE]], "output_limit": 1000}, deadline)
        while child.recv(deadline).get("event") != "exec_done":
            pass
        child.send(
            {"op": "call", "id": 1, "function": "probe", "kwargs": {"paths": secret}}, deadline
        )
        reply = child.recv(deadline)
        child.close()
        found = reply.get("value") or {}
        host_uid = _host_uid(sandbox_.proc.pid) if sandbox_.proc is not None else None
        # the uid mode cannot stop writes to the world-writable folders: it wipes them after
        wiped = set(SHARED_WRITABLE) if config.mode == UID else set()
        writable = [d for d in found.get("writable") or [] if d not in wiped]
        ok = (
            config.mode != NONE
            and host_uid not in (0, None)
            and not found.get("visible")
            and found.get("network") is False
            and not writable
            and found.get("uid") != 0
        )
        return {
            "ok": bool(ok),
            "mode": config.mode,
            "mode_description": DESCRIBE[config.mode],
            "notes": list(config.notes),
            "sandboxed": config.sandbox,
            "probe": found,
            "error": reply.get("error_message"),
            "preload_errors": sandbox_.preload_errors,
            "launcher": sandbox_.launcher_notes,
            "command": getattr(sandbox_, "command", None),
            "grader_uid": os.geteuid(),
            "sandbox_host_uid": host_uid,
        }
    finally:
        sandbox_.close()
        shutil.rmtree(workdir, ignore_errors=True)
