"""The class report: how a class did on one assignment, as HTML, a PNG histogram and JSON.

Written after each run (``report/<exercise>-run<N>.*``, and ``report/<exercise>.*`` for the
newest) from the gradebook's grades that count: the score histogram, each hidden test's
pass rate and mean, the most common failure messages with how many students hit each,
the students whose notebook failed to run, crashed or timed out, and the late, excused and
overridden ones.
"""

from __future__ import annotations

import html
import io
import json
import re
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


_NUMBERS = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e-?\d+)?(?![\w-])")


def _message(text: str) -> str:
    """The kind of a failure: the message with its numbers written ``#``, so that the same
    mistake made with different values (or on different hidden inputs) counts as one."""
    t = _NUMBERS.sub("#", " ".join(str(text).split()))
    return t if len(t) <= 240 else t[:239] + "…"


def _shown(text: str, limit: int = 300) -> str:
    t = " ".join(str(text).split())
    return t if len(t) <= limit else t[: limit - 1] + "…"


def statistics(rows: list[dict[str, Any]], tests: list[tuple[str, float]]) -> dict[str, Any]:
    """The report's numbers (also the JSON written beside the page)."""
    n = len(rows)
    graded = [r for r in rows if not r["excused"]]
    scores = [r["final"] for r in graded]
    max_score = max((r["max_score"] for r in rows), default=sum(w for _, w in tests))
    per_test = []
    failures: Counter[tuple[str, str]] = Counter()
    who: dict[tuple[str, str], list[str]] = defaultdict(list)
    example: dict[tuple[str, str], str] = {}
    ran = [r for r in graded if r["status"] not in (INVALID, GRADER_ERROR)]
    for name, weight in tests:
        pts, passed = [], 0
        for r in graded:
            res: SubmissionResult = r["result"]
            t = next((t for t in res.tests if t.name == name), None)
            if t is None:
                continue
            pts.append(t.points)
            passed += t.fraction >= 1.0
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
            }
        )
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
    trouble = [
        {
            "student": r["student"],
            "status": r["status"],
            "reason": r["result"].reason,
            "timed_out_tests": [t.name for t in r["result"].tests if t.timed_out],
        }
        for r in rows
        if r["status"] in (INVALID, GRADER_ERROR, TIMEOUT, CRASHED)
        or any(t.timed_out for t in r["result"].tests)
    ]
    sorted_scores = sorted(scores)
    mid = len(sorted_scores) // 2
    median = (
        0.0
        if not sorted_scores
        else sorted_scores[mid]
        if len(sorted_scores) % 2
        else (sorted_scores[mid - 1] + sorted_scores[mid]) / 2
    )
    return {
        "students": n,
        "excused": n - len(graded),
        "max_score": max_score,
        "mean": sum(scores) / len(scores) if scores else 0.0,
        "median": median,
        "full_marks": sum(s >= max_score for s in scores),
        "zero": sum(s == 0 for s in scores),
        "late": sum(r["grade"].late_days > 0 for r in rows),
        "penalised": sum(r["grade"].penalty > 0 for r in rows),
        "overridden": sum(bool(r["grade"].override) for r in rows),
        "histogram": histogram(scores, max_score),
        "tests": per_test,
        "failures": [
            {
                "test": t,
                "message": m,
                "students": c,
                "examples": who[(t, m)][:5],
                "example_message": example[(t, m)],
            }
            for (t, m), c in failures.most_common(TOP_FAILURES)
        ],
        "cell_errors": [
            {
                "error": k,
                "students": c,
                "examples": cell_who[k][:5],
                "example_message": example[("", k)],
            }
            for k, c in cell_errors.most_common(TOP_FAILURES)
        ],
        "failed_to_run_or_timed_out": trouble,
    }


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
    ax.yaxis.get_major_locator().set_params(integer=True)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    return buf.getvalue()


def report_html(stats: dict[str, Any], title: str, png_name: str, subtitle: str) -> str:
    e = html.escape
    s = stats

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
    fail_rows = (
        "\n".join(
            f"<tr><td>{f['students']}</td><td>{e(f['test'])}</td>"
            f"<td>{e(f['example_message'])}</td>"
            f"<td>{e(', '.join(f['examples']))}"
            f"{' …' if f['students'] > len(f['examples']) else ''}</td></tr>"
            for f in s["failures"]
        )
        or "<tr><td colspan=4>no failures</td></tr>"
    )
    cell_rows = (
        "\n".join(
            f"<tr><td>{c['students']}</td><td>{e(c['example_message'])}</td>"
            f"<td>{e(', '.join(c['examples']))}{' …' if c['students'] > 5 else ''}</td></tr>"
            for c in s["cell_errors"]
        )
        or "<tr><td colspan=3>no cell raised</td></tr>"
    )
    trouble_rows = (
        "\n".join(
            f"<tr><td>{e(t['student'])}</td><td>{e(t['status'])}</td><td>{e(t['reason'])}</td>"
            f"<td>{e(', '.join(t['timed_out_tests']))}</td></tr>"
            for t in s["failed_to_run_or_timed_out"]
        )
        or "<tr><td colspan=4>none</td></tr>"
    )
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>{e(title)}: class report</title>
<style>
body{{font-family:system-ui,sans-serif;max-width:64em;margin:1.5em auto;padding:0 1em;color:#222}}
table{{border-collapse:collapse;margin:.5em 0 1.5em}}
td,th{{border:1px solid #ccc;padding:.25em .6em;text-align:left;vertical-align:top}}
th{{background:#f3f3f3}}
.cards{{display:flex;gap:1em;flex-wrap:wrap}}
.card{{border:1px solid #ccc;border-radius:6px;padding:.5em 1em;min-width:7em}}
.card b{{display:block;font-size:1.5em}}
.bar{{display:inline-block;width:6em;height:.8em;background:#eee;margin-right:.4em}}
.bar span{{display:block;height:100%;background:#3b6ea8}}
</style></head><body>
<h1>{e(title)}: class report</h1>
<p>{e(subtitle)}</p>
<div class="cards">
<div class="card"><b>{s["students"]}</b>students</div>
<div class="card"><b>{s["mean"]:.3g}</b>mean of {s["max_score"]:g}</div>
<div class="card"><b>{s["median"]:.3g}</b>median</div>
<div class="card"><b>{s["full_marks"]}</b>full marks</div>
<div class="card"><b>{s["zero"]}</b>scored zero</div>
<div class="card"><b>{len(s["failed_to_run_or_timed_out"])}</b>failed to run or timed out</div>
<div class="card"><b>{s["late"]}</b>late ({s["penalised"]} penalised)</div>
<div class="card"><b>{s["overridden"]}</b>overridden, {s["excused"]} excused</div>
</div>
<h2>Scores</h2>
<img src="{e(png_name)}" alt="histogram of final scores" width="700">
<h2>Hidden tests</h2>
<table><tr><th>test</th><th>weight</th><th>pass rate</th><th>mean points</th><th>mean %</th>
<th>scored 0</th></tr>
{test_rows}
</table>
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
<h2>Failed to run, crashed or timed out</h2>
<table><tr><th>student</th><th>status</th><th>reason</th><th>tests that timed out</th></tr>
{trouble_rows}
</table>
</body></html>
"""


def write_report(
    gb, assignment: str, exercise: str, out: Path, rows: list[dict[str, Any]], run_id: int | None
) -> dict[str, Any]:
    """Write the report files; returns the statistics with the paths written."""
    stats = statistics(rows, gb.tests(assignment))
    folder = Path(out) / "report"
    names = [exercise] + ([f"{exercise}-run{run_id}"] if run_id is not None else [])
    subtitle = (
        f"Grades that count after run {run_id}" if run_id is not None else "Grades that count"
    ) + f" ({gb.path.name}); scores after late penalties and overrides."
    png = histogram_png(stats, f"{exercise}: {stats['students']} students")
    paths = []
    for name in names:
        atomic_write(folder / f"{name}.png", png)
        atomic_write(folder / f"{name}.html", report_html(stats, exercise, f"{name}.png", subtitle))
        atomic_write(folder / f"{name}.json", json.dumps(stats, indent=2))
        paths.append(str(folder / f"{name}.html"))
    stats["paths"] = paths
    return stats
