"""A gradebook that explains and repairs itself.

Every grade that counts is also in the output folder: ``results/<student>.json`` carries,
under ``extra_data.rikin`` (encoded, see :func:`rikingrade.views.encode_record`), the
student, the file, the result, the seed and settings key,
and the late rules, extension and override that made the final grade (written after each
commit and by every export). So a gradebook that SQLite finds damaged, an empty one, or one
that lacks grades the folder holds (``gradebook.sqlite`` copied without its ``-wal`` after
a kill; a file replaced) is found at once, before anything is rewritten, and
:func:`repair` rebuilds it: the damaged file is moved aside (never deleted), a backup is
restored if one is given, and every grade of ``results/`` missing from the gradebook is
recorded again, with the time it was graded. :func:`rikingrade.gradebook.backup` makes the
one consistent file to keep (SQLite's backup API).
"""

from __future__ import annotations

import json
import os
import shlex
import time
from pathlib import Path
from typing import Any

from ._version import __version__
from .gradebook import Gradebook, GradebookDamaged, backup, lock
from .report import SubmissionResult
from .views import RECORD_VERSION, decode_record, export


def command(assignment: str, out: Path, gradebook: str | Path | None) -> str:
    """The repair command line for this gradebook."""
    cmd = ["rikin-grade", "repair", assignment, "--out", str(out)]
    if gradebook:
        cmd += ["--gradebook", str(gradebook)]
    return shlex.join(cmd)


def advice(exc: GradebookDamaged, assignment: str, out: Path, gradebook=None) -> str:
    """The paragraph an instructor reads: what is wrong, and the command that repairs it."""
    cmd = command(assignment, out, gradebook)
    return (
        f"the gradebook {exc.path} cannot be used: {exc.why}. Nothing was changed. Rebuild it "
        f"from the grades written beside it ({Path(out) / 'results'}, one file per student): "
        f"`{cmd}` (the file as it is now is kept as {exc.path.name}.damaged-<time>; every "
        "grade that counts is restored, and the next run grades anything not there), or "
        f"restore a backup made by `rikin-grade backup`: `{cmd} --from-backup FILE`."
    )


def records(out: Path) -> list[dict[str, Any]]:
    """The grade records of the output folder's ``results/``, decoded (files without one
    are skipped: written by an older grader, or damaged)."""
    found = []
    folder = Path(out) / "results"
    if not folder.is_dir():
        return []
    for p in sorted(folder.glob("*.json")):
        try:
            rec = decode_record(json.loads(p.read_text(encoding="utf-8"))["extra_data"]["rikin"])
        except (OSError, ValueError, KeyError, TypeError):
            continue
        if rec is not None and rec.get("version") == RECORD_VERSION:
            rec["_file"] = str(p)
            found.append(rec)
    return found


def lost(gb: Gradebook, out: Path, assignment: str) -> list[dict[str, Any]]:
    """The records of ``out`` for ``assignment`` whose grade the gradebook does not hold."""
    return [
        r
        for r in records(out)
        if r.get("assignment") == assignment
        and not gb.has_result(r["student"]["id"], assignment, r["submission"]["sha256"], r["key"])
    ]


def check(gb: Gradebook, out: Path, assignment: str) -> None:
    """Refuse a gradebook that lacks grades ``out`` holds (before anything is rewritten).

    Raises
    ------
    GradebookDamaged
        With what is missing (the caller adds the repair advice).
    """
    missing = lost(gb, out, assignment)
    if not missing:
        listed = _listed(out)
        if listed and not gb.conn.execute("SELECT 1 FROM results LIMIT 1").fetchone():
            raise GradebookDamaged(
                gb.path,
                f"it holds no grade at all, while {Path(out) / 'grades.csv'} lists "
                f"{len(listed)} student(s) ({', '.join(listed[:5])}"
                f"{' ...' if len(listed) > 5 else ''}): emptied, replaced, or not this "
                "folder's gradebook (grade into a new --out folder)?",
            )
        return
    ids = {r.get("gradebook_id") for r in missing} - {gb.gradebook_id()}
    names = ", ".join(r["student"]["id"] for r in missing[:5])
    more = " ..." if len(missing) > 5 else ""
    why = f"it lacks {len(missing)} grade(s) that {Path(out) / 'results'} holds ({names}{more})"
    if ids:
        why += (
            "; they were written from another gradebook (this one was replaced or started "
            "anew, or the folder belongs to another gradebook: grade into a new --out folder)"
        )
    else:
        why += "; was it copied without its -wal file, or restored from an older copy?"
    raise GradebookDamaged(gb.path, why)


def _listed(out: Path) -> list[str]:
    """The students grades.csv lists (its first column)."""
    try:
        lines = (Path(out) / "grades.csv").read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return []
    if not lines or not lines[0].startswith("student,"):
        return []
    return [ln.split(",", 1)[0] for ln in lines[1:] if ln.strip()]


def _move_aside(path: Path) -> Path | None:
    """Rename the gradebook file (and its -wal, -shm) to ``<name>.damaged-<time>``."""
    if not path.exists():
        return None
    stamp = time.strftime("%Y%m%d-%H%M%S")
    aside = path.with_name(f"{path.name}.damaged-{stamp}")
    n = 1
    while aside.exists():
        n += 1
        aside = path.with_name(f"{path.name}.damaged-{stamp}-{n}")
    os.replace(path, aside)
    for ext in ("-wal", "-shm"):
        side = Path(f"{path}{ext}")
        if side.exists():
            os.replace(side, Path(f"{aside}{ext}"))
    return aside


def _restore_rules(gb: Gradebook, assignment: str, recs: list[dict[str, Any]]) -> None:
    """The late rules, extensions and overrides of the records, where the gradebook lacks
    them (the newest record of each wins)."""
    pols = [r["policy"] for r in recs if r.get("policy")]
    if pols and gb.policy(assignment) is None:
        p = max(pols, key=lambda p: p.get("created_at") or 0)
        gb.set_policy(assignment, p["due"], p["per_day"], p["cap"], p["grace_minutes"])
    have_ext = gb.extensions(assignment)
    have_ovr = gb.overrides(assignment)
    for r in recs:
        sid = r["student"]["id"]
        e, o = r.get("extension"), r.get("override")
        if e and sid not in have_ext:
            gb.add_extension(sid, assignment, e["due"], e["reason"])
        if o and sid not in have_ovr:
            gb.add_override(sid, assignment, o["kind"], o["score"], o["reason"])


_STUDENT_FIELDS = (
    "name",
    "email",
    "sis_id",
    "login",
    "section",
    "canvas_id",
    "moodle_id",
    "lms",
    "lms_id",
)


def restore(gb: Gradebook, out: Path, assignment: str) -> list[str]:
    """Record again every grade of ``out``'s results that the gradebook lacks; the students
    restored."""
    missing = lost(gb, out, assignment)
    if not missing:
        return []
    first = missing[0]
    if not gb.tests(assignment):
        gb.add_assignment(assignment, first["max_score"], [tuple(t) for t in first["tests"]])
    run = gb.start_run(assignment, __version__, first["seed"], first["key"], {"repair": str(out)})
    done = []
    for rec in missing:
        st, sub = rec["student"], rec["submission"]
        sid = st["id"]
        gb.add_student(sid, **{k: st.get(k) or "" for k in _STUDENT_FIELDS})
        if st.get("roster_key"):
            gb.set_roster_key(sid, st["roster_key"])
        sub_id = gb.add_submission(
            sid,
            assignment,
            sub["sha256"],
            sub["path"],
            sub["submitted_at"],
            sub["time_source"],
            bool(sub["lms_late"]),
        )
        res = SubmissionResult.from_dict(rec["result"])
        res.student = sid
        gb.record(run, sub_id, res, assignment, rec["seed"], graded_at=rec.get("graded_at"))
        done.append(sid)
    _restore_rules(gb, assignment, [r for r in records(out) if r.get("assignment") == assignment])
    gb.end_run(run, "finished", {"restored": len(done), "from": str(Path(out) / "results")})
    return done


def repair(
    assignment: str,
    out: str | Path,
    gradebook: str | Path | None = None,
    from_backup: str | Path | None = None,
) -> dict[str, Any]:
    """Make the gradebook usable again and restore every grade ``out`` holds.

    A gradebook that cannot be used (damaged, empty, not one) is moved aside, never
    deleted; ``from_backup`` (a file made by ``rikin-grade backup``) replaces the gradebook
    (the one there is moved aside too); then the grades of ``out/results`` the gradebook
    lacks are recorded again, and the views are rewritten.

    Returns a dict: the gradebook's path, what was moved aside, the backup restored, the
    students restored from ``results/``, and the views written.
    """
    out = Path(out).resolve()
    path = Path(gradebook).resolve() if gradebook else out / "gradebook.sqlite"
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = lock(path)
    aside = None
    try:
        if from_backup is not None:
            Gradebook.open(from_backup, readonly=True).close()  # a usable gradebook?
            aside = _move_aside(path)
            backup(from_backup, path)
        elif path.exists():
            try:
                Gradebook.open(path, readonly=True).close()
            except GradebookDamaged:
                aside = _move_aside(path)
        gb = Gradebook.open(path, lock_fd=fd)
    except BaseException:
        os.close(fd)
        raise
    with gb:
        restored = restore(gb, out, assignment)
        if not gb.current(assignment):
            return {"gradebook": str(path), "aside": str(aside or ""), "restored": [], "views": {}}
        views = export(gb, assignment, assignment, out)
    return {
        "gradebook": str(path),
        "aside": str(aside or ""),
        "backup": str(from_backup or ""),
        "restored": restored,
        "views": views,
    }
