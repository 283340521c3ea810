"""Writing results: atomic files, Gradescope results.json, feedback (Markdown and HTML).

Every file is written atomically (a temporary file in the same folder, fsync, then
``os.replace``), so a grader killed at any moment leaves either the old file or the new
one, never half of one. The grades themselves live in the gradebook
(:mod:`rikingrade.gradebook`); the files of the output folder are its views
(:mod:`rikingrade.views`).
"""

from __future__ import annotations

import html
import os
import re
import tempfile
from pathlib import Path
from typing import Any

from .i18n import N_, t, use
from .report import SubmissionResult


def atomic_write(path: Path, data: str | bytes, fsync: bool = False) -> None:
    """Write ``data`` to ``path`` so that readers see the old or the new file, never a mix.

    ``os.replace`` makes the switch atomic for any reader and against the writer being
    killed; ``fsync=True`` also survives a power cut (slower: used for the class files).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    raw = data.encode("utf-8") if isinstance(data, str) else data
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
            f.flush()
            if fsync:
                os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _fmt(x: float) -> str:
    return f"{x:.4g}" if x != int(x) else str(int(x))


# ----------------------------------------------------------------------------- per student
def feedback_lines(res: SubmissionResult) -> list[tuple[str, str, str, str]]:
    """(verdict, test name, points text, feedback) for each test."""
    return [
        (t.verdict, t.name, f"{_fmt(t.points)}/{_fmt(t.weight)}", t.feedback) for t in res.tests
    ]


def _score_line(res: SubmissionResult) -> str:
    return t("Score: {score} / {max}", score=_fmt(round(res.score, 4)), max=_fmt(res.max_score))


#: The verdicts of a test, as the feedback shows them.
VERDICTS = {"pass": N_("pass"), "partial": N_("partial"), "fail": N_("fail")}


def _verdict(v: str) -> str:
    return t(VERDICTS[v])


def feedback_markdown(res: SubmissionResult, exercise: str, final: str = "", who: str = "") -> str:
    """The student's Markdown feedback: the final score (``final``, when a grading policy
    applies; else the autograder's score) first, the notebook's problems (the real cause,
    once), then one line per test. Every text is escaped as Markdown (never HTML); the
    headings are in the notebook's language (``res.language``)."""
    with use(res.language):
        out = [t("# {exercise}: feedback for {who}", exercise=exercise,
                 who=_md(who or res.student)), ""]
        out.append(f"**{_md(final or _score_line(res))}**")
        out.append("")
        if res.problems:
            out += [t("## Your notebook"), ""]
            out += [f"- {_md(p)}" for p in res.problems]
            out.append("")
        out.append(t("## Tests"))
        out.append("")
        for verdict, name, pts, fb in feedback_lines(res):
            out.append(f"- [{_verdict(verdict)}] **{name}** ({pts}): {_md(fb)}")
        out.append("")
    return "\n".join(out)


def feedback_html(res: SubmissionResult, exercise: str, final: str = "", who: str = "") -> str:
    """The student's HTML feedback (see :func:`feedback_markdown`)."""
    with use(res.language):
        return _feedback_html(res, exercise, final, who)


def _feedback_html(res: SubmissionResult, exercise: str, final: str, who: str) -> str:
    e = html.escape
    who = who or res.student
    colors = {"pass": "#1a7f37", "partial": "#9a6700", "fail": "#cf222e"}
    rows = "\n".join(
        f'<tr><td style="color:{colors[v]};font-weight:bold">{_verdict(v)}</td><td>{e(n)}</td>'
        f"<td>{e(p)}</td><td>{e(_one_line(fb))}</td></tr>"
        for v, n, p, fb in feedback_lines(res)
    )
    probs = ""
    if res.problems:
        items = "\n".join(f"<li>{e(_one_line(p))}</li>" for p in res.problems)
        probs = f"<h2>{e(t('Your notebook'))}</h2>\n<ul>\n{items}\n</ul>"
    title = e(t("{exercise}: feedback for {who}", exercise=exercise, who=who))
    head = [e(t(w)) for w in (N_("result"), N_("test"), N_("points"), N_("feedback"))]
    return f"""<!DOCTYPE html>
<html lang="{res.language}"><head><meta charset="utf-8">
<title>{title}</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto}}
table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:.3em .6em;text-align:left}}</style>
</head><body>
<h1>{title}</h1>
<p><strong>{e(final or _score_line(res))}</strong></p>
{probs}
<h2>{e(t("Tests"))}</h2>
<table><tr><th>{head[0]}</th><th>{head[1]}</th><th>{head[2]}</th><th>{head[3]}</th></tr>
{rows}
</table>
</body></html>
"""


#: What gives text a meaning inline (a feedback line never starts with student text, so
#: the line-start markers # + - 1. need no escape).
_MD_SPECIAL = re.compile(r"([\\`*\[\]<>~&]|(?<!\w)_|_(?!\w))")


def _md(text: str) -> str:
    """One line of Markdown that shows ``text`` as it is, and can carry no markup or HTML.

    Every character Markdown (CommonMark) or HTML gives a meaning inline is backslash-escaped
    (an underscore inside a word has none), so ``l2 + l3 < 5`` renders as written (not
    ``&lt;``), and a student's ``<img>`` or ``[link](...)`` is plain text."""
    return _MD_SPECIAL.sub(lambda m: "\\" + m.group(0), _one_line(text))


def _one_line(text: str, limit: int = 600) -> str:
    t = " ".join(str(text).split())
    return t if len(t) <= limit else t[: limit - 1] + "…"


def gradescope_json(res: SubmissionResult, exercise: str) -> dict[str, Any]:
    """The results.json Gradescope reads (https://gradescope-autograders.readthedocs.io)."""
    tests = [
        {
            "name": t.name,
            "score": round(t.points, 6),
            "max_score": t.weight,
            "status": "passed" if t.fraction >= 1.0 else "failed",
            "output": _md(t.feedback),
            "output_format": "md",
            "visibility": "visible",
        }
        for t in res.tests
    ]
    output = f"Status: {_md(res.status)}" + (f": {_md(res.reason)}" if res.reason else "")
    if res.problems:
        output += "\n\n" + "\n".join(f"- {_md(p)}" for p in res.problems)
    return {
        "score": round(res.score, 6),
        "execution_time": round(res.elapsed, 3),
        "output": output,
        "output_format": "md",
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "tests": tests,
        "extra_data": {"exercise": exercise, "status": res.status, "sha256": res.sha256},
    }
