"""``rikin-grade``: the command line over :mod:`rikingrade.api` (defaults come from the API).

Commands::

    rikin-grade ASSIGNMENT SUBMISSIONS... --out DIR [options]   grade a class
    rikin-grade override ASSIGNMENT STUDENT --out DIR (--score X | --excused | --clear)
                --reason TEXT                                 set a grade by hand
    rikin-grade export ASSIGNMENT --out DIR                       rewrite the views
    rikin-grade backup --out DIR [--to FILE]                      one consistent copy
    rikin-grade repair ASSIGNMENT --out DIR [--from-backup FILE]  rebuild a gradebook
    rikin-grade gradescope-bundle ASSIGNMENT --out bundle.zip     build a Gradescope autograder
    rikin-grade gradescope-run ASSIGNMENT [--submission DIR] [--results FILE]
    rikin-grade check-sandbox                                     show what student code can see
"""

from __future__ import annotations

import argparse
import inspect
import json
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ._version import __version__

EXIT_OK, EXIT_GRADER_ERRORS, EXIT_USAGE, EXIT_SANDBOX = 0, 1, 2, 3

DESCRIPTION = """\
Grade students' exercise notebooks safely, in parallel, with partial credit.

Each notebook runs in a bubblewrap sandbox (no network, no access to the course, the hidden
tests or other submissions, read-only filesystem, unprivileged user, memory/CPU/process/file
limits); the grader sends the hidden tests' inputs as JSON, reads the results back as JSON
and scores them in its own process. A cell that raises is recorded and later cells still
run; a call that hangs or crashes costs only its test.
"""

EPILOG = """\
other commands:
  rikin-grade override ASSIGNMENT STUDENT --out DIR --score 7 --reason "..."
                                                              set (or --excused, --clear) a grade
  rikin-grade export ASSIGNMENT --out DIR                     rewrite grades.csv, LMS files, report
  rikin-grade backup --out DIR                                copy the gradebook, consistently
  rikin-grade repair ASSIGNMENT --out DIR                     rebuild a damaged gradebook from
                                                              OUT/results (or --from-backup FILE)
  rikin-grade gradescope-bundle ASSIGNMENT --out bundle.zip   build a Gradescope autograder zip
  rikin-grade gradescope-run ASSIGNMENT                       grade one upload (inside Gradescope)
  rikin-grade check-sandbox                                   probe what a notebook can see and do
  (each takes --help)

examples:
  rikin-grade scara submissions/ --out graded/
  rikin-grade scara alice.ipynb bob.ipynb --out graded/ --workers 4 --reveal
  rikin-grade scara canvas_download/ --out graded/ --roster canvas_gradebook_export.csv \
      --due "2026-11-20 23:59" --late-per-day 10 --late-cap 50 --grace-minutes 15
  rikin-grade scara canvas_download/smithjohn_12345_67890_scara.ipynb --out graded/
                                             (regrade one student: the others keep their grade)
  rikin-grade path/to/my_hidden_tests.py class/ --out graded/ --timeout 10

Grades go into a gradebook (SQLite) in OUT that keeps every run; grades.csv, the import
files of the class's LMS (canvas-, moodle-, blackboard-, brightspace-ASSIGNMENT.csv, and
canvas-/moodle-feedback-ASSIGNMENT.zip for their bulk feedback upload), results/ (Gradescope
JSON, and what rebuilds the gradebook), feedback/ and report/ASSIGNMENT.html (the class
report) are rewritten from it after each run, even after Ctrl-C. The instructor's guide
(a part of the book) walks through each LMS.

exit status: 0 graded (whatever the scores), 1 some submissions hit a grader error, were
refused (a link, a file its folder's owner may not read, a .zip, a script or anything else
that is not a notebook: see the notes and the log) or could not be told apart on the roster
(see the notes), or the roster has no one column for the assignment (the note says which
to pass as --lms-column), 2 bad arguments, assignment, submissions folder or roster,
gradebook in use or damaged (the message gives the command that repairs it), 3 the sandbox
is unavailable.
"""

# (parameter of api.grade, help). Defaults are read from the function's signature.
GRADE_OPTIONS: list[tuple[str, str]] = [
    ("workers", "submissions graded in parallel, one sandbox each"),
    ("seed", "seed of the hidden tests' random inputs (the same inputs for every student)"),
    ("reveal", "let feedback show hidden inputs and expected values"),
    (
        "timeout",
        "wall-clock seconds per test call (default: each hidden test's own, 2 s in the "
        "four arm exercises)",
    ),
    (
        "cell_timeout",
        "wall-clock seconds per notebook cell; a slower cell is skipped and later cells still run",
    ),
    (
        "time_budget",
        "wall-clock seconds one submission may cost in all (cells, calls, restarts); tests "
        "not reached in time score 0",
    ),
    (
        "memory_mb",
        "memory (MiB of address space) a notebook may allocate on top of the preloaded "
        "numpy/sympy/matplotlib/rikin (about 250 MiB)",
    ),
    ("cpu_seconds", "CPU seconds per notebook process (a backstop behind the wall-clock limits)"),
    ("max_processes", "processes and threads per sandbox (stops fork bombs)"),
    ("max_file_mb", "largest file a notebook may write, MiB"),
    ("tmp_mb", "size of the sandbox's private /scratch, MiB (wiped between submissions)"),
    ("output_limit", "characters of printed output kept per cell (the rest is dropped)"),
    (
        "regrade",
        "grade every submission again (default: resume, skipping submissions already graded "
        "with the same file hash and grader settings)",
    ),
    (
        "gradebook",
        "the course's SQLite gradebook (default: OUT/gradebook.sqlite); pass the same file for "
        "every assignment of a course",
    ),
    (
        "roster",
        "the class's roster as the LMS exports it (Canvas gradebook export, Moodle grading "
        "worksheet or gradebook export, Blackboard Grade Center download, Brightspace grades "
        "export, Gradescope Download Grades) or a CSV with id, name, email, SIS id, "
        "section: submissions are matched on "
        "the LMS's id, else by name (ambiguities are reported, never guessed); the LMS files "
        "use its ids, leave out students not on it and list those missing; kept for later runs",
    ),
    (
        "lms_column",
        "the assignment's column in the LMS, as in the roster export (e.g. 'HW3 (4455)', "
        "'HW3 [Total Pts: 10 Score] |12345', 'HW3 Points Grade') or a part of it; default: "
        "the one column holding the exercise's name; kept for later runs",
    ),
    (
        "missing",
        "what the LMS files give a student on the roster with no submission: blank (the LMS "
        "keeps what it has) or zero; kept for later runs (default: blank)",
    ),
    (
        "due",
        "due time, e.g. '2026-11-20 23:59' (local) or ISO 8601 with an offset; kept in the "
        "gradebook for later runs",
    ),
    ("late_per_day", "late penalty, percent of the maximum per started day after --due"),
    ("late_cap", "largest late penalty, percent of the maximum"),
    ("grace_minutes", "minutes after --due that are not late"),
    ("extensions", "CSV of per-student due times: student, due, reason"),
    (
        "sandbox",
        "how student code is isolated: bwrap (bubblewrap namespaces), uid (no namespaces: "
        "a root grader runs each worker as its own uid, after proving the grader's files "
        "unreadable to it) or auto, the strongest that works here",
    ),
    (
        "unsafe_no_sandbox",
        "DEVELOPMENT ONLY: run student code without bubblewrap, with no isolation",
    ),
    ("progress", "show a progress bar (default: only when stderr is a terminal)"),
    ("quiet", "print nothing; the files and the log are still written"),
]


def _add_options(
    p: argparse.ArgumentParser, func: Callable[..., Any], table: list[tuple[str, str]]
) -> None:
    sig = inspect.signature(func).parameters
    for name, help_ in table:
        default = sig[name].default
        flag = "--" + name.replace("_", "-")
        if name == "progress":
            p.add_argument(
                flag, dest=name, action=argparse.BooleanOptionalAction, default=default, help=help_
            )
        elif isinstance(default, bool):
            p.add_argument(flag, dest=name, action="store_true", default=default, help=help_)
        else:
            ann = sig[name].annotation
            ann = str(ann)
            typ = float if "float" in ann else (int if "int" in ann else str)
            shown = "" if default is None else " (default: %(default)s)"
            p.add_argument(
                flag, dest=name, type=typ, default=default, metavar=name.upper(), help=help_ + shown
            )


def grade_parser() -> argparse.ArgumentParser:
    from .api import grade

    p = argparse.ArgumentParser(
        prog="rikin-grade",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "assignment",
        metavar="ASSIGNMENT",
        help="exercise name (e.g. scara = rikingrade.hidden.scara), dotted module, or path "
        "to a hidden-test .py module",
    )
    p.add_argument(
        "submissions",
        metavar="SUBMISSIONS",
        nargs="+",
        help=".ipynb files or class folders as LMS give them: Canvas, Moodle, Blackboard, "
        "Brightspace downloads (names parsed; the newest attempt counts), Gradescope's "
        "Export Submissions (its submission_metadata.yml read), an nbgrader "
        "submitted/ tree, a notebook or a folder per student",
    )
    p.add_argument(
        "--out",
        "-o",
        required=True,
        metavar="DIR",
        help="output folder: gradebook.sqlite, grades.csv, summary.json, LMS import files, "
        "report/, grading.log, results/<student>.json (Gradescope format), "
        "feedback/<student>.md and .html",
    )
    _add_options(p, grade, GRADE_OPTIONS)
    p.add_argument("--version", action="version", version=f"rikin-grade {__version__}")
    return p


def bundle_parser() -> argparse.ArgumentParser:
    from .gradescope import gradescope_bundle

    p = argparse.ArgumentParser(
        prog="rikin-grade gradescope-bundle",
        description="Build the zip Gradescope's 'Configure Autograder' page takes: setup.sh "
        "(installs "
        "bubblewrap, Python, rikin and rikingrade), run_autograder (grades "
        "/autograder/submission, writes /autograder/results/results.json) and the hidden "
        "tests with their reference.",
    )
    p.add_argument(
        "assignment", metavar="ASSIGNMENT", help="exercise name, dotted module or .py path"
    )
    p.add_argument("--out", "-o", required=True, metavar="ZIP", help="the zip file to write")
    _add_options(
        p,
        gradescope_bundle,
        [
            ("seed", "seed of the hidden tests' random inputs"),
            ("reveal", "let feedback show hidden inputs and expected values"),
            ("timeout", "wall-clock seconds per test call (default: each test's own)"),
            ("cell_timeout", "wall-clock seconds per notebook cell"),
            ("memory_mb", "memory (MiB) a notebook may allocate on top of the preloaded libraries"),
            (
                "late_per_day",
                "late penalty, percent of the maximum per started day after the student's due "
                "date, by Gradescope's own times (submission_metadata.json)",
            ),
            ("late_cap", "largest late penalty, percent of the maximum"),
            ("grace_minutes", "minutes after the due date that are not late"),
            (
                "unsafe_no_sandbox",
                "run student code with no isolation inside Gradescope (normally not needed: "
                "without user namespaces the bundle uses the uid sandbox; with this, "
                "student code can read the hidden tests)",
            ),
        ],
    )
    return p


def run_parser() -> argparse.ArgumentParser:
    from .gradescope import gradescope_run

    p = argparse.ArgumentParser(
        prog="rikin-grade gradescope-run",
        description="Grade the one submission Gradescope gives "
        "(the run_autograder script calls this).",
    )
    p.add_argument(
        "assignment", metavar="ASSIGNMENT", help="exercise name, dotted module or .py path"
    )
    _add_options(
        p,
        gradescope_run,
        [
            ("submission", "folder holding the student's upload"),
            ("results", "where to write Gradescope's results.json"),
            ("seed", "seed of the hidden tests' random inputs"),
            ("reveal", "let feedback show hidden inputs and expected values"),
            ("timeout", "wall-clock seconds per test call (default: each test's own)"),
            ("cell_timeout", "wall-clock seconds per notebook cell"),
            ("memory_mb", "memory (MiB) a notebook may allocate on top of the preloaded libraries"),
            (
                "late_per_day",
                "late penalty, percent of the maximum per started day late (by "
                "submission_metadata.json beside the submission folder)",
            ),
            ("late_cap", "largest late penalty, percent of the maximum"),
            ("grace_minutes", "minutes after the due date that are not late"),
            ("sandbox", "bwrap, uid or auto (the strongest that works here)"),
            ("unsafe_no_sandbox", "run without bubblewrap (no isolation)"),
        ],
    )
    return p


def check_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="rikin-grade check-sandbox",
        description="Start a sandbox and show what a notebook inside it can see and do "
        "(user id, visible paths, network, writable directories).",
    )
    p.add_argument("paths", nargs="*", metavar="PATH", help="more paths that must be invisible")
    p.add_argument(
        "--sandbox",
        default="auto",
        choices=("auto", "bwrap", "uid"),
        help="the mode to probe (default: auto, the one grading would use here)",
    )
    p.add_argument(
        "--unsafe-no-sandbox", action="store_true", help="probe the unsandboxed mode instead"
    )
    return p


def _gradebook_parser(prog: str, description: str) -> argparse.ArgumentParser:
    """A command on an existing gradebook: ASSIGNMENT, --out, --gradebook."""
    p = argparse.ArgumentParser(prog=f"rikin-grade {prog}", description=description)
    p.add_argument("assignment", metavar="ASSIGNMENT", help="exercise name, as graded")
    p.add_argument("--out", "-o", required=True, metavar="DIR", help="the grading output folder")
    p.add_argument("--gradebook", metavar="FILE", help="default: OUT/gradebook.sqlite")
    return p


def override_parser() -> argparse.ArgumentParser:
    p = _gradebook_parser(
        "override",
        "Set a student's grade by hand, excuse them, or clear an override; the "
        "reason is recorded in the gradebook and shown in their feedback. The views "
        "(grades.csv, LMS files, feedback, report) are rewritten.",
    )
    p.add_argument(
        "student",
        metavar="STUDENT",
        help="student id, as in grades.csv, or an id of theirs from the download or the "
        "roster (LMS id, SIS id or login, e-mail, username, name)",
    )
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--score", type=float, help="the grade to give")
    what.add_argument("--excused", action="store_true", help="excuse the student")
    what.add_argument("--clear", action="store_true", help="remove the override in force")
    p.add_argument("--reason", required=True, help="why (shown to the student)")
    return p


def export_parser() -> argparse.ArgumentParser:
    return _gradebook_parser(
        "export",
        "Rewrite grades.csv, summary.json, the LMS import files, feedback and the class "
        "report from the gradebook alone (after a kill, or to export another assignment of "
        "a shared gradebook).",
    )


def repair_parser() -> argparse.ArgumentParser:
    p = _gradebook_parser(
        "repair",
        "Make a gradebook usable again: one SQLite finds damaged, an empty one, or one that "
        "lacks grades OUT/results holds (copied without its -wal file after a kill) is "
        "rebuilt: the file is moved aside (never deleted), a backup is restored if given, and "
        "every grade in OUT/results that the gradebook lacks is recorded again; then the "
        "views are rewritten. Re-run with --roster to restore the roster.",
    )
    p.add_argument(
        "--from-backup",
        metavar="FILE",
        help="a backup made by 'rikin-grade backup' to start from (the gradebook there is "
        "moved aside)",
    )
    return p


def backup_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="rikin-grade backup",
        description="Copy the gradebook into one consistent file with SQLite's backup API "
        "(it holds what is still in the -wal file, and may run while grading goes on). Copy "
        "this file, never gradebook.sqlite alone.",
    )
    p.add_argument("--out", "-o", required=True, metavar="DIR", help="the grading output folder")
    p.add_argument("--gradebook", metavar="FILE", help="default: OUT/gradebook.sqlite")
    p.add_argument(
        "--to",
        metavar="FILE",
        help="the backup to write (default: OUT/backups/gradebook-<date>-<time>.sqlite)",
    )
    return p


def _paths(ns) -> tuple[Path, Path]:
    out = Path(ns.out).resolve()
    return out, Path(ns.gradebook).resolve() if ns.gradebook else out / "gradebook.sqlite"


_ROSTER_IDS = ("id", "name", "email", "sis_id", "login", "canvas_id", "moodle_id")


def _named_students(gb, assignment: str, given: str) -> list[str]:
    """The graded students ``given`` names: the id in grades.csv, else every student one
    of whose ids is ``given`` (case aside), as the download or the roster gave it: LMS id,
    SIS id or login, e-mail, Blackboard or Brightspace username, OrgDefinedId, name."""
    import unicodedata

    from .roster import bare

    known = {r["student"] for r in gb.current(assignment)}
    if given in known:
        return [given]
    want = unicodedata.normalize("NFC", given).strip().casefold()
    entries = dict(gb.roster(assignment)[1])
    found = []
    for sid, st in gb.students().items():
        if sid not in known:
            continue
        e = entries.get(st["roster_key"]) or {}
        ids = [st[k] for k in ("name", "email", "sis_id", "login", "canvas_id", "moodle_id")]
        ids += [st["lms_id"], *(e.get(k) for k in _ROSTER_IDS)]
        ids += [bare(str(e.get(k) or "")) for k in ("username", "org_id")]
        if any(str(x or "").strip().casefold() == want for x in ids):
            found.append(sid)
    return sorted(found)


def _override(gb, ns) -> int:
    named = _named_students(gb, ns.assignment, ns.student)
    if len(named) != 1:
        known = sorted({r["student"] for r in gb.current(ns.assignment)})
        print(
            f"rikin-grade: {ns.student!r} names {len(named)} students graded for "
            f"{ns.assignment} ({', '.join(named)}): pass the id in grades.csv"
            if named
            else f"rikin-grade: no student {ns.student!r} graded for {ns.assignment} "
            f"(known: {', '.join(known[:8])}{' ...' if len(known) > 8 else ''})",
            file=sys.stderr,
        )
        return EXIT_USAGE
    ns.student = named[0]
    kind = "excused" if ns.excused else "cleared" if ns.clear else "score"
    max_score = gb.max_score(ns.assignment)
    if kind == "score" and not 0 <= ns.score <= max_score:
        print(f"rikin-grade: --score must be in [0, {max_score:g}]", file=sys.stderr)
        return EXIT_USAGE
    gb.add_override(ns.student, ns.assignment, kind, ns.score, ns.reason)
    return EXIT_OK


def _gradebook_command(cmd: str, args_list: list[str]) -> int:
    from . import repair
    from .gradebook import Gradebook, GradebookDamaged
    from .views import export

    ns = (override_parser() if cmd == "override" else export_parser()).parse_args(args_list)
    out, path = _paths(ns)
    if not path.exists():
        print(f"rikin-grade: no gradebook at {path}: grade the class first", file=sys.stderr)
        return EXIT_USAGE
    try:
        gb = Gradebook.open(path)
        try:
            repair.check(gb, out, ns.assignment)
        except BaseException:
            gb.close()
            raise
    except GradebookDamaged as exc:
        exc.advice = repair.advice(exc, ns.assignment, out, ns.gradebook)
        raise
    with gb:
        if not gb.current(ns.assignment):
            print(f"rikin-grade: {path} has no grades for {ns.assignment}", file=sys.stderr)
            return EXIT_USAGE
        if cmd == "override" and _override(gb, ns) != EXIT_OK:
            return EXIT_USAGE
        info = export(gb, ns.assignment, ns.assignment, out)
    _wrote(info)
    return EXIT_OK


def _wrote(info: dict[str, Any]) -> None:
    from .views import LMS_NAMES

    files = [info["grades"]] + [info[k] for k in LMS_NAMES if k in info] + [info["report"][0]]
    print("wrote " + ", ".join(files))


def _repair_command(args_list: list[str]) -> int:
    from . import repair

    ns = repair_parser().parse_args(args_list)
    out, path = _paths(ns)
    done = repair.repair(ns.assignment, out, ns.gradebook, ns.from_backup)
    if done["aside"]:
        print(f"moved the unusable gradebook aside: {done['aside']}")
    if done.get("backup"):
        print(f"restored the backup {done['backup']}")
    print(
        f"restored {len(done['restored'])} grade(s) from {out / 'results'} into {path}"
        + (f": {', '.join(done['restored'][:8])}" if done["restored"] else "")
        + (" ..." if len(done["restored"]) > 8 else "")
    )
    if done["views"]:
        _wrote(done["views"])
    else:
        print(f"no grades for {ns.assignment} in {path}: grade the class again", file=sys.stderr)
    return EXIT_OK


def _backup_command(args_list: list[str]) -> int:
    import time

    from .gradebook import backup

    ns = backup_parser().parse_args(args_list)
    out, path = _paths(ns)
    if not path.exists():
        print(f"rikin-grade: no gradebook at {path}", file=sys.stderr)
        return EXIT_USAGE
    stamp = time.strftime("%Y%m%d-%H%M%S")
    dst = Path(ns.to).resolve() if ns.to else out / "backups" / f"gradebook-{stamp}.sqlite"
    dst.parent.mkdir(parents=True, exist_ok=True)
    try:
        backup(path, dst)
    except FileExistsError as exc:
        print(f"rikin-grade: {exc}", file=sys.stderr)
        return EXIT_USAGE
    print(
        f"wrote {dst}: a consistent copy of {path} (restore: rikin-grade repair ... "
        "--from-backup FILE)"
    )
    return EXIT_OK


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``rikin-grade``; returns the exit status."""
    from .assignment import AssignmentError
    from .gradebook import GradebookBusy, GradebookDamaged
    from .notebook import SubmissionsError
    from .policy import PolicyError
    from .roster import RosterError
    from .sandbox import SandboxUnavailable

    args_list = list(sys.argv[1:] if argv is None else argv)
    cmd = args_list[0] if args_list else ""
    try:
        if cmd == "gradescope-bundle":
            from .gradescope import gradescope_bundle

            ns = bundle_parser().parse_args(args_list[1:])
            kw = vars(ns)
            path = gradescope_bundle(kw.pop("assignment"), kw.pop("out"), **kw)
            print(f"wrote {path}: upload it on Gradescope's 'Configure Autograder' page")
            return EXIT_OK
        if cmd == "gradescope-run":
            from .gradescope import gradescope_run

            kw = vars(run_parser().parse_args(args_list[1:]))
            res = gradescope_run(kw.pop("assignment"), **kw)
            return EXIT_GRADER_ERRORS if res.status == "grader-error" else EXIT_OK
        if cmd == "check-sandbox":
            from .api import check_sandbox

            ns = check_parser().parse_args(args_list[1:])
            info = check_sandbox(
                unsafe_no_sandbox=ns.unsafe_no_sandbox, paths=ns.paths, sandbox=ns.sandbox
            )
            print(json.dumps(info, indent=2))
            for note in info["notes"]:
                print(note, file=sys.stderr)
            verdict = "OK" if info["ok"] else "NOT isolated"
            print(f"sandbox {verdict}: mode {info['mode_description']}", file=sys.stderr)
            return EXIT_OK if info["ok"] else EXIT_SANDBOX
        if cmd in ("override", "export"):
            return _gradebook_command(cmd, args_list[1:])
        if cmd == "repair":
            return _repair_command(args_list[1:])
        if cmd == "backup":
            return _backup_command(args_list[1:])
        if cmd == "grade":
            args_list = args_list[1:]
        from .api import grade

        kw = vars(grade_parser().parse_args(args_list))
        report = grade(kw.pop("assignment"), kw.pop("submissions"), kw.pop("out"), **kw)
        s = report.summary
        attention = (s.get("grader_errors") or s.get("refused") or s.get("ambiguous")
                     or s.get("lms_column"))
        return EXIT_GRADER_ERRORS if attention else EXIT_OK
    except (
        AssignmentError,
        SubmissionsError,
        GradebookBusy,
        GradebookDamaged,
        PolicyError,
        RosterError,
    ) as exc:
        print(f"rikin-grade: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except SandboxUnavailable as exc:
        print(f"rikin-grade: {exc}", file=sys.stderr)
        return EXIT_SANDBOX
    except KeyboardInterrupt:
        print("rikin-grade: interrupted; run the same command again to resume", file=sys.stderr)
        return 130


def entry() -> int:
    """The ``rikin-grade`` command: :func:`main` in a process that reaps what it orphans.

    As the subreaper of its descendants, the grader collects the processes a sandbox leaves
    when it is killed, instead of leaving them to a container's init (see
    :func:`rikingrade.sandbox.uidmode.adopt_orphans`).
    """
    from .sandbox.uidmode import adopt_orphans

    adopt_orphans()
    return main()


if __name__ == "__main__":
    sys.exit(entry())
