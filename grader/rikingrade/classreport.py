"""The class report: how a class did on one assignment, as HTML, PNG histograms and JSON.

Written after each run (``report/<exercise>-run<N>.*``, and ``report/<exercise>.*`` for the
newest) from the gradebook's grades that count: the score histogram and spread (mean,
median, standard deviation, minimum, maximum, percentiles), the same per section, each
hidden test's pass rate, mean and histogram of points, the most common failure messages
with how many students hit each, every student by name with a link to their feedback, and
the lists to act on: missing (on the roster, nothing handed in), late, failed to run or
timed out, not on the roster, and students the roster cannot tell apart.
"""

from __future__ import annotations

import html
import io
import json
import math
import re
import urllib.parse
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

from .outputs import atomic_write
from .report import CRASHED, GRADER_ERROR, INVALID, TIMEOUT, SubmissionResult

#: Failure messages listed in the report.
TOP_FAILURES = 12


def _bins(max_score: float) -> list[float]:
    n = 10 if max_score <= 0 else min(20, max(5, int(round(max_score))))
    return [max_score * i / n for i in range(n + 1)]


def histogram(scores: list[float], max_score: float) -> list[dict[str, float]]:
    """Counts per bin of ``[lo, hi)``; the last bin includes the maximum."""
    edges = _bins(max_score or 1.0)
    counts = [0] * (len(edges) - 1)
    for s in scores:
        for i in range(len(counts)):
            if s < edges[i + 1] or i == len(counts) - 1:
                counts[i] += 1
                break
    return [{"from": edges[i], "to": edges[i + 1], "count": counts[i]} for i in range(len(counts))]


#: Percentiles shown in the report.
PERCENTILES = (10, 25, 50, 75, 90)
#: Bins of a test's histogram: the fraction of its points a student got.
TEST_BINS = ("0", "< 25%", "25-50%", "50-75%", "75-100%", "100%")


def percentile(sorted_scores: list[float], q: float) -> float:
    """The ``q``-th percentile (0-100) by linear interpolation between closest ranks (as
    numpy's default)."""
    if not sorted_scores:
        return 0.0
    pos = (len(sorted_scores) - 1) * q / 100
    lo = math.floor(pos)
    hi = min(lo + 1, len(sorted_scores) - 1)
    return sorted_scores[lo] + (sorted_scores[hi] - sorted_scores[lo]) * (pos - lo)


def spread(scores: list[float]) -> dict[str, float]:
    """Mean, median, sample standard deviation, minimum, maximum and percentiles."""
    xs = sorted(scores)
    n = len(xs)
    mean = sum(xs) / n if n else 0.0
    sd = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1)) if n > 1 else 0.0
    out = {
        "n": n,
        "mean": mean,
        "median": percentile(xs, 50),
        "sd": sd,
        "min": xs[0] if xs else 0.0,
        "max": xs[-1] if xs else 0.0,
    }
    out.update({f"p{q}": percentile(xs, q) for q in PERCENTILES})
    return out


def _test_bin(fraction: float) -> int:
    if fraction <= 0:
        return 0
    if fraction >= 1:
        return 5
    return 1 + min(3, int(fraction * 4))


_NUMBERS = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e-?\d+)?(?![\w-])")


def _message(text: str) -> str:
    """The kind of a failure: the message with its numbers written ``#``, so that the same
    mistake made with different values (or on different hidden inputs) counts as one."""
    t = _NUMBERS.sub("#", " ".join(str(text).split()))
    return t if len(t) <= 240 else t[:239] + "…"


def _shown(text: str, limit: int = 300) -> str:
    t = " ".join(str(text).split())
    return t if len(t) <= limit else t[: limit - 1] + "…"


def _per_test(graded, ran, tests) -> tuple[list[dict[str, Any]], list[dict[str, Any]], dict]:
    """Each test's pass rate, mean and histogram; the most common failures."""
    per_test = []
    failures: Counter[tuple[str, str]] = Counter()
    who: dict[tuple[str, str], list[str]] = defaultdict(list)
    example: dict[tuple[str, str], str] = {}
    for name, weight in tests:
        pts, passed, bins = [], 0, [0] * len(TEST_BINS)
        for r in graded:
            res: SubmissionResult = r["result"]
            t = next((t for t in res.tests if t.name == name), None)
            if t is None:
                continue
            pts.append(t.points)
            passed += t.fraction >= 1.0
            bins[_test_bin(t.fraction)] += 1
            if t.fraction < 1.0 and r in ran:
                key = (name, _message(t.feedback))
                failures[key] += 1
                who[key].append(r["student"])
                example.setdefault(key, _shown(t.feedback))
        k = len(pts)
        per_test.append(
            {
                "test": name,
                "weight": weight,
                "pass_rate": passed / k if k else 0.0,
                "mean": sum(pts) / k if k else 0.0,
                "zero": sum(p == 0 for p in pts),
                "students": k,
                "histogram": dict(zip(TEST_BINS, bins, strict=True)),
            }
        )
    top = [
        {
            "test": t,
            "message": m,
            "students": c,
            "examples": who[(t, m)][:5],
            "example_message": example[(t, m)],
        }
        for (t, m), c in failures.most_common(TOP_FAILURES)
    ]
    return per_test, top, example


def _cell_errors(ran, example) -> list[dict[str, Any]]:
    cell_errors: Counter[str] = Counter()
    cell_who: dict[str, list[str]] = defaultdict(list)
    for r in ran:
        res = r["result"]
        kinds = {
            f"{c.error_type}: {_message(c.message)}": f"{c.error_type}: {_shown(c.message)}"
            for c in res.cells
            if c.status == "error"
        }
        for k, raw in kinds.items():
            cell_errors[k] += 1
            cell_who[k].append(r["student"])
            example.setdefault(("", k), raw)
    return [
        {
            "error": k,
            "students": c,
            "examples": cell_who[k][:5],
            "example_message": example[("", k)],
        }
        for k, c in cell_errors.most_common(TOP_FAILURES)
    ]


def _person(r: dict[str, Any]) -> dict[str, Any]:
    g = r["grade"]
    return {
        "student": r["student"],
        "name": r.get("name") or "",
        "section": r.get("section") or "",
        "final": None if r["excused"] else r["final"],
        "status": r["status"],
        "late_days": g.late_days,
        "penalty": g.penalty,
        "excused": r["excused"],
        "override": g.override,
    }


def _sections(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    by: dict[str, list[float]] = defaultdict(list)
    for r in rows:
        if not r["excused"]:
            by[r.get("section") or ""].append(r["final"])
    if len(by) < 2 and "" in by:
        return []
    return [{"section": k or "(no section)", **spread(v)} for k, v in sorted(by.items())]


def statistics(
    rows: list[dict[str, Any]],
    tests: list[tuple[str, float]],
    roster: dict[str, list] | None = None,
) -> dict[str, Any]:
    """The report's numbers and lists (also the JSON written beside the page).

    ``roster`` holds the roster's lists (``missing``, ``not_on_roster``, ``ambiguous``) when
    the class has one.
    """
    n = len(rows)
    graded = [r for r in rows if not r["excused"]]
    scores = [r["final"] for r in graded]
    max_score = max((r["max_score"] for r in rows), default=sum(w for _, w in tests))
    ran = [r for r in graded if r["status"] not in (INVALID, GRADER_ERROR)]
    per_test, top, example = _per_test(graded, ran, tests)
    trouble = [
        {
            "student": r["student"],
            "name": r.get("name") or "",
            "status": r["status"],
            "reason": r["result"].reason,
            "timed_out_tests": [t.name for t in r["result"].tests if t.timed_out],
        }
        for r in rows
        if r["status"] in (INVALID, GRADER_ERROR, TIMEOUT, CRASHED)
        or any(t.timed_out for t in r["result"].tests)
    ]
    sp = spread(scores)
    roster = roster or {}
    return {
        "students": n,
        "excused": n - len(graded),
        "max_score": max_score,
        "mean": sp["mean"],
        "median": sp["median"],
        "spread": sp,
        "full_marks": sum(s >= max_score for s in scores),
        "zero": sum(s == 0 for s in scores),
        "late": sum(r["grade"].late_days > 0 for r in rows),
        "penalised": sum(r["grade"].penalty > 0 for r in rows),
        "overridden": sum(bool(r["grade"].override) for r in rows),
        "histogram": histogram(scores, max_score),
        "sections": _sections(rows),
        "tests": per_test,
        "failures": top,
        "cell_errors": _cell_errors(ran, example),
        "failed_to_run_or_timed_out": trouble,
        "people": [_person(r) for r in rows],
        "late_students": [_person(r) for r in rows if r["grade"].late_days > 0],
        "missing": [_who(m) for m in roster.get("missing", [])],
        "not_on_roster": list(roster.get("not_on_roster", [])),
        "ambiguous": [_who(m) for m in roster.get("ambiguous", [])],
    }


def _who(m: dict[str, Any]) -> dict[str, str]:
    ids = [m.get(k) for k in ("canvas_id", "moodle_id", "bb_username", "d2l_org_id", "sis_id")]
    return {
        "name": m.get("name") or "",
        "id": next((i for i in ids if i), ""),
        "email": m.get("email") or "",
        "section": m.get("section") or "",
    }


def _integer_ticks(axis: Any) -> None:
    """Ticks at whole numbers only on ``axis`` (a matplotlib ``Axis``: counts of students),
    keeping its automatic locator's other choices."""
    from matplotlib.ticker import MaxNLocator

    locator = axis.get_major_locator()
    if isinstance(locator, MaxNLocator):  # the automatic locator is one
        locator.set_params(integer=True)


def histogram_png(stats: dict[str, Any], title: str) -> bytes:
    """The score histogram as a PNG (matplotlib, no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 3.2), dpi=100)
    ax = fig.add_subplot()
    bins = stats["histogram"]
    ax.bar(
        [b["from"] for b in bins],
        [b["count"] for b in bins],
        width=[b["to"] - b["from"] for b in bins],
        align="edge",
        color="#3b6ea8",
        edgecolor="white",
    )
    ax.set_xlim(0, stats["max_score"] or 1)
    ax.set_xlabel(f"final score (of {stats['max_score']:g})")
    ax.set_ylabel("students")
    ax.set_title(title)
    _integer_ticks(ax.yaxis)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    return buf.getvalue()


def tests_png(stats: dict[str, Any], title: str) -> bytes:
    """Each hidden test's histogram (students by the share of its points they got), one
    panel per test, as a PNG."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    tests = stats["tests"] or [{"test": "(no test)", "histogram": dict.fromkeys(TEST_BINS, 0)}]
    cols = min(3, len(tests))
    rows = math.ceil(len(tests) / cols)
    fig = Figure(figsize=(3.2 * cols, 2.3 * rows + 0.4), dpi=100)
    for i, t in enumerate(tests):
        ax = fig.add_subplot(rows, cols, i + 1)
        counts = [t["histogram"][b] for b in TEST_BINS]
        ax.bar(range(len(TEST_BINS)), counts, color="#3b6ea8", edgecolor="white")
        ax.set_xticks(range(len(TEST_BINS)), TEST_BINS, fontsize=7)
        ax.set_title(t["test"], fontsize=9)
        _integer_ticks(ax.yaxis)
        ax.tick_params(axis="y", labelsize=7)
    fig.suptitle(f"{title}: share of each test's points", fontsize=10)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    return buf.getvalue()


def _rows(items: list[str], cols: int, empty: str) -> str:
    return "\n".join(items) or f"<tr><td colspan={cols}>{empty}</td></tr>"


def _fmt(x: float | None) -> str:
    return "" if x is None else f"{x:.3g}"


def _feedback_link(student: str) -> str:
    return "../feedback/" + urllib.parse.quote(student) + ".html"


def _people_html(s: dict[str, Any]) -> str:
    e = html.escape
    rows = [
        f'<tr><td>{e(p["name"])}</td><td><a href="{e(_feedback_link(p["student"]))}">'
        f"{e(p['student'])}</a></td><td>{e(p['section'])}</td>"
        f"<td>{'excused' if p['excused'] else _fmt(p['final'])}</td><td>{e(p['status'])}</td>"
        f"<td>{p['late_days'] or ''}</td><td>{e(p['override'])}</td></tr>"
        for p in sorted(s["people"], key=lambda p: (p["name"].casefold(), p["student"]))
    ]
    return _rows(rows, 7, "nobody graded")


def _lists_html(s: dict[str, Any]) -> str:
    e = html.escape
    late = [
        f'<tr><td>{e(p["name"])}</td><td><a href="{e(_feedback_link(p["student"]))}">'
        f"{e(p['student'])}</a></td><td>{p['late_days']}</td><td>{_fmt(p['penalty'])}</td></tr>"
        for p in s["late_students"]
    ]
    trouble = [
        f'<tr><td>{e(t["name"])}</td><td><a href="{e(_feedback_link(t["student"]))}">'
        f"{e(t['student'])}</a></td><td>{e(t['status'])}</td><td>{e(t['reason'])}</td>"
        f"<td>{e(', '.join(t['timed_out_tests']))}</td></tr>"
        for t in s["failed_to_run_or_timed_out"]
    ]
    missing = [
        f"<tr><td>{e(m['name'])}</td><td>{e(m['id'])}</td><td>{e(m['email'])}</td>"
        f"<td>{e(m['section'])}</td></tr>"
        for m in s["missing"]
    ]
    unsure = [
        f"<tr><td>{e(m['name'])}</td><td>{e(m['id'])}</td><td>{e(m['email'])}</td>"
        f"<td>{e(m['section'])}</td></tr>"
        for m in s["ambiguous"]
    ]
    gone = [
        f'<tr><td><a href="{e(_feedback_link(w))}">{e(w)}</a></td></tr>' for w in s["not_on_roster"]
    ]
    return f"""<h2 id="missing">Missing: on the roster, nothing handed in ({len(missing)})</h2>
<table><tr><th>name</th><th>LMS id</th><th>e-mail</th><th>section</th></tr>
{_rows(missing, 4, "none (or no roster given)")}
</table>
<h2 id="late">Late ({len(late)})</h2>
<table><tr><th>name</th><th>student</th><th>days late</th><th>penalty</th></tr>
{_rows(late, 4, "none")}
</table>
<h2 id="failed">Failed to run, crashed or timed out ({len(trouble)})</h2>
<table><tr><th>name</th><th>student</th><th>status</th><th>reason</th>
<th>tests that timed out</th></tr>
{_rows(trouble, 5, "none")}
</table>
<h2 id="not-on-roster">Graded, but not on the roster ({len(gone)})</h2>
<p>Left out of the LMS files (withdrawn, or from another class).</p>
<table><tr><th>student</th></tr>
{_rows(gone, 1, "none")}
</table>
<h2 id="ambiguous">On the roster, but not told apart ({len(unsure)})</h2>
<p>Several roster rows share a name and the download names students by name only: their
grades are not matched; enter them by hand.</p>
<table><tr><th>name</th><th>LMS id</th><th>e-mail</th><th>section</th></tr>
{_rows(unsure, 4, "none")}
</table>"""


def _spread_html(s: dict[str, Any]) -> str:
    sp = s["spread"]
    head = "".join(f"<th>p{q}</th>" for q in PERCENTILES)
    cells = "".join(f"<td>{_fmt(sp[f'p{q}'])}</td>" for q in PERCENTILES)
    sections = [
        f"<tr><td>{html.escape(x['section'])}</td><td>{x['n']}</td><td>{_fmt(x['mean'])}</td>"
        f"<td>{_fmt(x['median'])}</td><td>{_fmt(x['sd'])}</td><td>{_fmt(x['min'])}</td>"
        f"<td>{_fmt(x['max'])}</td></tr>"
        for x in s["sections"]
    ]
    return f"""<table><tr><th>students</th><th>mean</th><th>sd</th><th>min</th>{head}
<th>max</th></tr>
<tr><td>{sp["n"]}</td><td>{_fmt(sp["mean"])}</td><td>{_fmt(sp["sd"])}</td><td>{_fmt(sp["min"])}</td>
{cells}<td>{_fmt(sp["max"])}</td></tr></table>
<h2 id="sections">Sections</h2>
<table><tr><th>section</th><th>students</th><th>mean</th><th>median</th><th>sd</th><th>min</th>
<th>max</th></tr>
{_rows(sections, 7, "one section (or none in the roster)")}
</table>"""


def _tests_html(s: dict[str, Any], e) -> tuple[str, str, str]:
    def pct(x: float) -> str:
        return f"{100 * x:.0f}%"

    test_rows = "\n".join(
        f"<tr><td>{e(t['test'])}</td><td>{t['weight']:g}</td>"
        f"<td><div class=bar><span style='width:{pct(t['pass_rate'])}'></span></div>"
        f"{pct(t['pass_rate'])}</td><td>{t['mean']:.3g}</td>"
        f"<td>{pct(t['mean'] / t['weight']) if t['weight'] else '-'}</td>"
        f"<td>{t['zero']}</td></tr>"
        for t in s["tests"]
    )
    fail_rows = _rows(
        [
            f"<tr><td>{f['students']}</td><td>{e(f['test'])}</td>"
            f"<td>{e(f['example_message'])}</td>"
            f"<td>{e(', '.join(f['examples']))}"
            f"{' …' if f['students'] > len(f['examples']) else ''}</td></tr>"
            for f in s["failures"]
        ],
        4,
        "no failures",
    )
    cell_rows = _rows(
        [
            f"<tr><td>{c['students']}</td><td>{e(c['example_message'])}</td>"
            f"<td>{e(', '.join(c['examples']))}{' …' if c['students'] > 5 else ''}</td></tr>"
            for c in s["cell_errors"]
        ],
        3,
        "no cell raised",
    )
    return test_rows, fail_rows, cell_rows


CSS = """body{font-family:system-ui,sans-serif;max-width:64em;margin:1.5em auto;padding:0 1em;
color:#222}
table{border-collapse:collapse;margin:.5em 0 1.5em}
td,th{border:1px solid #ccc;padding:.25em .6em;text-align:left;vertical-align:top}
th{background:#f3f3f3}
.cards{display:flex;gap:1em;flex-wrap:wrap}
.card{border:1px solid #ccc;border-radius:6px;padding:.5em 1em;min-width:7em}
.card b{display:block;font-size:1.5em}
.card a{color:inherit}
.bar{display:inline-block;width:6em;height:.8em;background:#eee;margin-right:.4em}
.bar span{display:block;height:100%;background:#3b6ea8}"""


def report_html(
    stats: dict[str, Any], title: str, png_name: str, subtitle: str, tests_png_name: str = ""
) -> str:
    e = html.escape
    s = stats
    test_rows, fail_rows, cell_rows = _tests_html(s, e)
    tests_img = (
        f'<img src="{e(tests_png_name)}" alt="histogram of each test\'s points" width="700">'
        if tests_png_name
        else ""
    )
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>{e(title)}: class report</title>
<style>
{CSS}
</style></head><body>
<h1>{e(title)}: class report</h1>
<p>{e(subtitle)}</p>
<div class="cards">
<div class="card"><b>{s["students"]}</b>students graded</div>
<div class="card"><b>{s["mean"]:.3g}</b>mean of {s["max_score"]:g}</div>
<div class="card"><b>{s["median"]:.3g}</b>median</div>
<div class="card"><b>{s["spread"]["sd"]:.3g}</b>standard deviation</div>
<div class="card"><b>{s["full_marks"]}</b>full marks</div>
<div class="card"><b>{s["zero"]}</b>scored zero</div>
<div class="card"><a href="#missing"><b>{len(s["missing"])}</b>missing</a></div>
<div class="card"><a href="#failed"><b>{len(s["failed_to_run_or_timed_out"])}</b>failed to run
or timed out</a></div>
<div class="card"><a href="#late"><b>{s["late"]}</b>late ({s["penalised"]} penalised)</a></div>
<div class="card"><b>{s["overridden"]}</b>overridden, {s["excused"]} excused</div>
</div>
<h2>Scores</h2>
<img src="{e(png_name)}" alt="histogram of final scores" width="700">
{_spread_html(s)}
<h2>Hidden tests</h2>
<table><tr><th>test</th><th>weight</th><th>pass rate</th><th>mean points</th><th>mean %</th>
<th>scored 0</th></tr>
{test_rows}
</table>
{tests_img}
<h2>Most common failures</h2>
<p>Feedback that differs only in its numbers counts as one failure; the first student's is
shown.</p>
<table><tr><th>students</th><th>test</th><th>feedback</th><th>students, for example</th></tr>
{fail_rows}
</table>
<h2>Errors in notebook cells</h2>
<table><tr><th>students</th><th>error</th><th>students, for example</th></tr>
{cell_rows}
</table>
{_lists_html(s)}
<h2 id="students">Every student</h2>
<table><tr><th>name</th><th>student (feedback)</th><th>section</th><th>final</th><th>status</th>
<th>days late</th><th>override</th></tr>
{_people_html(s)}
</table>
</body></html>
"""


def write_report(
    gb,
    assignment: str,
    exercise: str,
    out: Path,
    rows: list[dict[str, Any]],
    run_id: int | None,
    roster: dict[str, list] | None = None,
) -> dict[str, Any]:
    """Write the report files; returns the statistics with the paths written."""
    stats = statistics(rows, gb.tests(assignment), roster)
    folder = Path(out) / "report"
    names = [exercise] + ([f"{exercise}-run{run_id}"] if run_id is not None else [])
    subtitle = (
        f"Grades that count after run {run_id}" if run_id is not None else "Grades that count"
    ) + f" ({gb.path.name}); scores after late penalties and overrides."
    png = histogram_png(stats, f"{exercise}: {stats['students']} students")
    per_test = tests_png(stats, exercise)
    paths = []
    for name in names:
        atomic_write(folder / f"{name}.png", png)
        atomic_write(folder / f"{name}-tests.png", per_test)
        page = report_html(stats, exercise, f"{name}.png", subtitle, f"{name}-tests.png")
        atomic_write(folder / f"{name}.html", page)
        atomic_write(folder / f"{name}.json", json.dumps(stats, indent=2))
        paths.append(str(folder / f"{name}.html"))
    stats["paths"] = paths
    return stats
